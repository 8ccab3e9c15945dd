/* Test helpers: load an assembly from inline JSON and fail loudly if it does not load. */
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

#endif
