/* Unit tests of src/report/report_lcp.c: the report of an LCP solve, read back. A 2 x 2 problem
 * with a solution known by hand, z = (1, 0), w = (0, 1): status, solver, z and w in the JSON, and
 * the text's size, note and timing; a problem with none (M = 0, q < 0): its status, and z, w and
 * the residual null. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cairn/cairn.h"
#include "report_capture.h"

static void test_lcp_report(void) {
    /* M = [[1, 0], [0, 1]], q = (-1, 1): z = (1, 0), w = (0, 1) */
    cnLcp p;
    CHECK(cn_lcp_alloc(&p, 2) == CN_OK);
    p.M[0] = 1, p.M[1] = 0, p.M[2] = 0, p.M[3] = 1, p.q[0] = -1, p.q[1] = 1;
    double z[2], w[2];
    cnLcpOptions lo = cn_lcp_options_default();
    cnLcpInfo info;
    cnLcpStatus st = cn_lcp_lemke(&p, &lo, z, w, &info);
    CHECK(st == CN_LCP_SOLVED);
    char *buf = NULL;
    CAPTURE(buf, cn_report_lcp(f, &p, st, "lemke", z, w, &info, 1, NULL, -1, 0));
    json_error_t err;
    json_t *j = buf ? json_loads(buf, 0, &err) : NULL;
    CHECK(j);
    if (j) {
        json_t *jz = json_object_get(j, "z"), *jw = json_object_get(j, "w");
        CHECK(json_is_true(json_object_get(j, "solved")) && !strcmp(str(j, "solver"), "lemke") && num(j, "n") == 2);
        CHECK(fabs(json_number_value(json_array_get(jz, 0)) - 1) < 1e-12 &&
              fabs(json_number_value(json_array_get(jz, 1))) < 1e-12 &&
              fabs(json_number_value(json_array_get(jw, 0))) < 1e-12 &&
              fabs(json_number_value(json_array_get(jw, 1)) - 1) < 1e-12);
        CHECK(!json_object_get(j, "solve_seconds"));
        json_decref(j);
    }
    free(buf);
    buf = NULL;
    CAPTURE(buf, cn_report_lcp(f, &p, st, "lemke", z, w, &info, 0, "a note", 0.5, 3));
    CHECK(buf && strstr(buf, "n = 2") && strstr(buf, "note: a note") && strstr(buf, "median of 3 solves"));
    free(buf);
    /* no solution: M = 0, q < 0 */
    p.M[0] = p.M[3] = 0, p.q[1] = -1;
    st = cn_lcp_lemke(&p, &lo, z, w, &info);
    CHECK(st != CN_LCP_SOLVED);
    buf = NULL;
    CAPTURE(buf, cn_report_lcp(f, &p, st, "lemke", NULL, NULL, &info, 1, NULL, -1, 0));
    j = buf ? json_loads(buf, 0, &err) : NULL;
    CHECK(j && json_is_false(json_object_get(j, "solved")) && json_is_null(json_object_get(j, "z")) &&
          json_is_null(json_object_get(j, "residual")) && !strcmp(str(j, "status"), cn_lcp_status_name(st)));
    json_decref(j);
    free(buf);
    cn_lcp_free(&p);
}

void test_report_lcp(void) {
    test_lcp_report();
}
