/* Test helpers: load an assembly from inline JSON or an example, and fail loudly if it does not
 * load. */
#ifndef CAIRN_TEST_HELPERS_H
#define CAIRN_TEST_HELPERS_H

#include <stdio.h>

#include "cairn/cairn.h"
#include "test.h"

static inline cnAssembly *load_ok(const char *json) {
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(json, "inline", &a, &d) != CN_OK) {
        cn_test_failures++;
        fprintf(stderr, "load failed: %s: %s\n  in %s\n", d.where, d.message, json);
        return NULL;
    }
    return a;
}

#ifdef CAIRN_SOURCE_DIR
/* examples/NAME.json of the source tree, or NULL (a failure counted). */
static inline cnAssembly *load_example(const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/examples/%s.json", CAIRN_SOURCE_DIR, name);
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_file(path, &a, &d) != CN_OK) {
        cn_test_failures++;
        fprintf(stderr, "load failed: %s: %s\n", path, d.message);
        return NULL;
    }
    return a;
}
#endif

#endif
