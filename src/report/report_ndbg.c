/* Reports of removal directions (cairn directions) and the non-directional blocking graph. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json_out.h"
#include "cairn/report.h"

static double deg(double r) {
    double d = r * 180.0 / CN_PI;
    if (fabs(d - round(d)) < 1e-7) d = round(d);
    if (d >= 360) d -= 360;
    return d;
}

/* One moving set: its arcs (2-D) or directions (3-D). */
static cnStatus one(FILE *f, json_t *arr, const cnAssembly *a, const unsigned char *moving,
                    const char *label, int json, cnDiag *diag) {
    double(*dirs)[3];
    int nd;
    cnStatus st = cn_free_directions(a, NULL, moving, &dirs, &nd, diag);
    if (st) return st;
    double up[3];
    cn_copy3(up, a->gravity);
    cn_scale3(up, -1.0 / cn_norm3(up));
    bool up_free = nd > 0 && cn_dot3(dirs[0], up) > 1 - CN_TOL_SAME_DIRECTION;
    json_t *o = json ? json_object() : NULL;
    if (json) {
        json_object_set_new(o, "parts", json_string(label));
        json_object_set_new(o, "up_free", json_boolean(up_free));
    } else {
        fprintf(f, "%s: %s", label, nd == 0 ? "blocked in every direction" : up_free ? "can go up" : "cannot go straight up");
    }
    if (a->dim == 2) {
        cnArc *arcs, *loc;
        int na, nl;
        st = cn_directions2(a, NULL, moving, &arcs, &na, &loc, &nl, diag);
        if (st) {
            cn_directions_free(dirs);
            return st;
        }
        json_t *ja = json ? json_array() : NULL, *jl = json ? json_array() : NULL;
        if (!json) fprintf(f, "; free directions (degrees, counter-clockwise from +x):%s", na ? "" : " none");
        for (int i = 0; i < na; i++) {
            bool full = arcs[i].to - arcs[i].from >= 2 * CN_PI;
            if (json) {
                json_t *p = json_array();
                json_array_append_new(p, json_real(deg(arcs[i].from)));
                json_array_append_new(p, json_real(full ? 360.0 : deg(arcs[i].to)));
                json_array_append_new(ja, p);
            } else if (full) fprintf(f, " all");
            else if (arcs[i].from == arcs[i].to) fprintf(f, " %g only", deg(arcs[i].from));
            else fprintf(f, " [%g, %g]", deg(arcs[i].from), deg(arcs[i].to));
        }
        for (int i = 0; json && i < nl; i++) {
            json_t *p = json_array();
            bool full = loc[i].to - loc[i].from >= 2 * CN_PI;
            json_array_append_new(p, json_real(deg(loc[i].from)));
            json_array_append_new(p, json_real(full ? 360.0 : deg(loc[i].to)));
            json_array_append_new(jl, p);
        }
        if (!json) {
            fprintf(f, "; locally (contacts only):");
            for (int i = 0; i < nl; i++) {
                bool full = loc[i].to - loc[i].from >= 2 * CN_PI;
                if (full) fprintf(f, " all");
                else if (loc[i].from == loc[i].to) fprintf(f, " %g only", deg(loc[i].from));
                else fprintf(f, " [%g, %g]", deg(loc[i].from), deg(loc[i].to));
            }
            if (nl == 0) fprintf(f, " none");
            fprintf(f, "\n");
        } else {
            json_object_set_new(o, "free_arcs_degrees", ja);
            json_object_set_new(o, "local_arcs_degrees", jl);
        }
        cn_free_arcs(arcs);
        cn_free_arcs(loc);
    } else if (!json) {
        fprintf(f, "; free among the arrangement's directions:");
        for (int i = 0; i < nd && i < 12; i++)
            fprintf(f, " (%.3g, %.3g, %.3g)", fabs(dirs[i][0]) < CN_TOL_PRINT_ZERO ? 0 : dirs[i][0],
                    fabs(dirs[i][1]) < CN_TOL_PRINT_ZERO ? 0 : dirs[i][1], fabs(dirs[i][2]) < CN_TOL_PRINT_ZERO ? 0 : dirs[i][2]);
        if (nd > 12) fprintf(f, " ... (%d in all)", nd);
        fprintf(f, "\n");
    }
    if (json) {
        json_t *jd = json_array();
        for (int i = 0; i < nd; i++) {
            json_t *p = json_array();
            for (int k = 0; k < a->dim; k++)
                json_array_append_new(p, json_real(fabs(dirs[i][k]) < CN_TOL_PRINT_ZERO ? 0.0 : dirs[i][k]));
            json_array_append_new(jd, p);
        }
        json_object_set_new(o, "free_directions", jd);
        json_array_append_new(arr, o);
    }
    cn_directions_free(dirs);
    return CN_OK;
}

cnStatus cn_report_directions(FILE *f, const cnAssembly *a, const int *sel, int nsel, int json,
                              cnDiag *diag) {
    unsigned char *moving = cn_calloc((size_t)a->nparts, 1);
    if (!moving) return cn_diag_oom(diag);
    json_t *arr = json ? json_array() : NULL;
    cnStatus st = CN_OK;
    if (nsel > 0) {
        char label[512] = "";
        for (int i = 0; i < nsel; i++) {
            moving[sel[i]] = 1;
            strncat(label, i ? "+" : "", sizeof label - strlen(label) - 1);
            strncat(label, a->parts[sel[i]].name, sizeof label - strlen(label) - 1);
        }
        st = one(f, arr, a, moving, label, json, diag);
    } else {
        for (int i = 0; i < a->nreal && !st; i++) {
            if (a->parts[i].fixed) continue;
            memset(moving, 0, (size_t)a->nparts);
            moving[i] = 1;
            st = one(f, arr, a, moving, a->parts[i].name, json, diag);
        }
    }
    cn_free(moving);
    if (json) {
        if (!st) {
            json_t *o = json_object();
            json_object_set_new(o, "dimension", json_integer(a->dim));
            json_object_set_new(o, "directions", arr);
            cn_json_write(f, o, 10);
        } else json_decref(arr);
    }
    return st;
}

/* ---- the blocking graph ---- */

static double pz(double x) { return fabs(x) < CN_TOL_PRINT_ZERO ? 0.0 : x; }

static const char *cell_kind(int dim, int cdim) {
    if (cdim == 0) return "direction";
    return dim == 3 && cdim == 2 ? "region" : "arc";
}

/* One cell as text or as a JSON object (returned). */
static cnStatus ndbg_cell(FILE *f, const cnAssembly *a, const cnNdbg *g, int c, int json,
                          json_t **out, cnDiag *diag) {
    const cnNdbgCell *C = &g->cells[c];
    int *parts, *start, ns;
    cnStatus st = cn_ndbg_removable(a, g, c, &parts, &start, &ns, diag);
    if (st) return st;
    if (json) {
        json_t *o = json_object(), *d = json_array(), *e = json_array(), *r = json_array();
        json_object_set_new(o, "kind", json_string(cell_kind(g->dim, C->dim)));
        for (int k = 0; k < g->dim; k++) json_array_append_new(d, json_real(pz(C->dir[k])));
        json_object_set_new(o, "direction", d);
        if (g->dim == 2) {
            json_t *deg2 = json_array();
            bool full = C->to - C->from >= 2 * CN_PI;
            json_array_append_new(deg2, json_real(deg(C->from)));
            json_array_append_new(deg2, json_real(full ? 360.0 : deg(C->to)));
            json_object_set_new(o, "degrees", deg2);
        }
        for (int k = 0; k < C->nedges; k++) {
            const cnNdbgEdge *E = &g->edges[C->first + k];
            json_t *p = json_array();
            json_array_append_new(p, json_string(a->parts[E->part].name));
            json_array_append_new(p, json_string(a->parts[E->blocker].name));
            json_array_append_new(e, p);
        }
        json_object_set_new(o, "blocked", e);
        for (int s = 0; s < ns; s++) {
            json_t *p = json_array();
            for (int k = start[s]; k < start[s + 1]; k++)
                json_array_append_new(p, json_string(a->parts[parts[k]].name));
            json_array_append_new(r, p);
        }
        json_object_set_new(o, "removable", r);
        *out = o;
    } else {
        fprintf(f, "  %s ", cell_kind(g->dim, C->dim));
        if (g->dim == 2) {
            if (C->to - C->from >= 2 * CN_PI) fprintf(f, "all directions");
            else if (C->dim == 0) fprintf(f, "%g deg", deg(C->from));
            else fprintf(f, "(%g, %g) deg, e.g. %g", deg(C->from), deg(C->to),
                         deg(fmod(atan2(C->dir[1], C->dir[0]) + 2 * CN_PI, 2 * CN_PI)));
        } else
            fprintf(f, "(%.4g, %.4g, %.4g)", pz(C->dir[0]), pz(C->dir[1]), pz(C->dir[2]));
        fprintf(f, ": ");
        if (C->nedges == 0) fprintf(f, "nothing blocked");
        else fprintf(f, "blocked");
        for (int k = 0; k < C->nedges; k++) {
            const cnNdbgEdge *E = &g->edges[C->first + k];
            fprintf(f, "%s %s by %s", k ? "," : "", a->parts[E->part].name, a->parts[E->blocker].name);
        }
        fprintf(f, "; removable:");
        for (int s = 0; s < ns; s++) {
            fprintf(f, " {");
            for (int k = start[s]; k < start[s + 1]; k++)
                fprintf(f, "%s%s", k > start[s] ? "+" : "", a->parts[parts[k]].name);
            fprintf(f, "}");
        }
        if (ns == 0) fprintf(f, " none");
        fprintf(f, "\n");
    }
    cn_free_ints(parts);
    cn_free_ints(start);
    return CN_OK;
}

cnStatus cn_report_ndbg(FILE *f, const cnAssembly *a, const int *sel, int nsel, int json,
                        cnDiag *diag) {
    unsigned char *group = NULL;
    if (nsel > 0) {
        if (!(group = cn_calloc((size_t)a->nparts, 1))) return cn_diag_oom(diag);
        for (int i = 0; i < nsel; i++) group[sel[i]] = 1;
    }
    cnNdbg g;
    cnStatus st = cn_ndbg_build(a, NULL, group, 0, &g, diag);
    cn_free(group);
    if (st) return st;
    int nfree = 0, bydim[3] = {0, 0, 0};
    for (int c = 0; c < g.ncells; c++) {
        nfree += g.cells[c].nedges == 0;
        bydim[g.cells[c].dim]++;
    }
    int cap = json ? CN_REPORT_NDBG_JSON_CELLS : CN_REPORT_NDBG_TEXT_CELLS;
    int listed = g.ncells < cap ? g.ncells : cap;
    json_t *o = json ? json_object() : NULL, *cells = json ? json_array() : NULL;
    if (json) {
        json_object_set_new(o, "dimension", json_integer(a->dim));
        if (nsel > 0) {
            json_t *p = json_array();
            for (int i = 0; i < nsel; i++) json_array_append_new(p, json_string(a->parts[sel[i]].name));
            json_object_set_new(o, "parts", p);
        }
        json_t *gr = json_object();
        json_object_set_new(gr, "too_large", json_boolean(g.too_large));
        json_object_set_new(gr, "max_circles", json_integer(CN_NDBG_MAX_CIRCLES));
        json_object_set_new(gr, "circles", json_integer(g.ncircles));
        json_object_set_new(gr, "cells", json_integer(g.ncells));
        json_object_set_new(gr, "free_cells", json_integer(nfree));
        json_object_set_new(gr, "cells_listed", json_integer(listed));
        json_object_set_new(o, "graph", gr);
    } else if (g.too_large) {
        fprintf(f, "blocking graph: more than %d bounding %s: not built (directions and plans use "
                   "the sampled directions)\n", CN_NDBG_MAX_CIRCLES, a->dim == 3 ? "great circles" : "lines");
    } else {
        fprintf(f, "blocking graph (%s): %d bounding %s, %d cells (", nsel > 0 ? "the parts listed moving together" : "every free part",
                g.ncircles, a->dim == 3 ? "great circles" : "lines", g.ncells);
        if (a->dim == 3) fprintf(f, "%d regions, %d arcs, %d single directions", bydim[2], bydim[1], bydim[0]);
        else fprintf(f, "%d arcs, %d single directions", bydim[1], bydim[0]);
        fprintf(f, "), %d with nothing blocked\n", nfree);
        if (nsel > 0) {
            fprintf(f, "moving together:");
            for (int i = 0; i < nsel; i++) fprintf(f, "%s%s", i ? "+" : " ", a->parts[sel[i]].name);
            fprintf(f, "\n");
        }
    }
    for (int c = 0; c < listed && !st; c++) {
        json_t *x = NULL;
        st = ndbg_cell(f, a, &g, c, json, &x, diag);
        if (x) json_array_append_new(cells, x);
    }
    if (!json && !st && listed < g.ncells)
        fprintf(f, "  ... %d more cells not listed (at most %d are; --json lists up to %d)\n", g.ncells - listed,
                CN_REPORT_NDBG_TEXT_CELLS, CN_REPORT_NDBG_JSON_CELLS);
    cn_ndbg_free(&g);
    if (json) {
        if (st) {
            json_decref(o);
            json_decref(cells);
            return st;
        }
        json_object_set_new(o, "cells", cells);
        if (cn_json_write(f, o, 10)) return cn_diag_oom(diag);
    }
    return st;
}
