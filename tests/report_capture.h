/* The report tests' helpers (test_report_sim.c, test_report_margin.c, test_report_lcp.c): a
 * report written into memory, and the members of its parsed JSON. */
#ifndef CAIRN_TEST_REPORT_CAPTURE_H
#define CAIRN_TEST_REPORT_CAPTURE_H

#include <jansson.h>
#include <stdio.h>

#include "test.h"

/* What `call` writes to f, into buf (caller frees). */
#define CAPTURE(buf, call)                                                                         \
    do {                                                                                           \
        size_t len_ = 0;                                                                           \
        FILE *f = open_memstream(&(buf), &len_);                                                   \
        CHECK(f && (call) == CN_OK);                                                               \
        if (f) fclose(f);                                                                          \
    } while (0)

static inline double num(const json_t *o, const char *key) { return json_number_value(json_object_get(o, key)); }
static inline const char *str(const json_t *o, const char *key) {
    const char *s = json_string_value(json_object_get(o, key));
    return s ? s : "";
}

#endif
