/* Report of an LCP solve (cairn lcp): text or JSON. */
#include <jansson.h>
#include <math.h>

#include "json_out.h"
#include "cairn/report.h"

static json_t *array_of(const double *v, int n) {
    json_t *a = json_array();
    for (int i = 0; i < n; i++) json_array_append_new(a, json_real(v[i]));
    return a;
}

cnStatus cn_report_lcp(FILE *f, const cnLcp *p, cnLcpStatus st, const char *solver,
                       const double *z, const double *w, const cnLcpInfo *info, int json,
                       const char *note, double solve_seconds, int repeats) {
    if (json) {
        json_t *o = json_object();
        json_object_set_new(o, "status", json_string(cn_lcp_status_name(st)));
        json_object_set_new(o, "solved", json_boolean(st == CN_LCP_SOLVED));
        json_object_set_new(o, "solver", json_string(solver));
        json_object_set_new(o, "n", json_integer(p->n));
        json_object_set_new(o, "pivots", json_integer(info->pivots));
        if (st == CN_LCP_SOLVED) {
            json_object_set_new(o, "residual", json_real(info->residual));
            json_object_set_new(o, "z", array_of(z, p->n));
            json_object_set_new(o, "w", array_of(w, p->n));
        } else {
            json_object_set_new(o, "residual", json_null());
            json_object_set_new(o, "z", json_null());
            json_object_set_new(o, "w", json_null());
        }
        if (note) json_object_set_new(o, "note", json_string(note));
        if (solve_seconds >= 0) {
            json_object_set_new(o, "solve_seconds", json_real(solve_seconds));
            json_object_set_new(o, "repeats", json_integer(repeats));
        }
        return cn_json_write(f, o, 17);
    }
    fprintf(f, "status: %s (solver %s, n = %d, %d pivot%s)\n", cn_lcp_status_name(st), solver,
            p->n, info->pivots, cn_plural(info->pivots));
    if (note) fprintf(f, "note: %s\n", note);
    if (solve_seconds >= 0)
        fprintf(f, "solve time: %.3g s (median of %d solve%s, reading excluded)\n", solve_seconds,
                repeats, cn_plural(repeats));
    if (st != CN_LCP_SOLVED) return CN_OK;
    fprintf(f, "residual: %.3g (relative; z >= 0, w >= 0, min(z, w) = 0)\n", info->residual);
    int shown = p->n <= 40 ? p->n : 20;
    fprintf(f, "%6s %24s %24s\n", "i", "z", "w");
    for (int i = 0; i < shown; i++) fprintf(f, "%6d %24.17g %24.17g\n", i + 1, z[i], w[i]);
    if (shown < p->n)
        fprintf(f, "... %d more (use --json for all)\n", p->n - shown);
    return CN_OK;
}
