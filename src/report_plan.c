/* Reports of removal directions and plans. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "internal.h"

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
    bool up_free = nd > 0 && cn_dot3(dirs[0], up) > 1 - 1e-12;
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
            cn_free(dirs);
            return st;
        }
        json_t *ja = json ? json_array() : NULL, *jl = json ? json_array() : NULL;
        if (!json) fprintf(f, "; free directions (degrees, counter-clockwise from +x):");
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
            fprintf(f, " (%.3g, %.3g, %.3g)", fabs(dirs[i][0]) < 1e-12 ? 0 : dirs[i][0],
                    fabs(dirs[i][1]) < 1e-12 ? 0 : dirs[i][1], fabs(dirs[i][2]) < 1e-12 ? 0 : dirs[i][2]);
        if (nd > 12) fprintf(f, " ... (%d in all)", nd);
        fprintf(f, "\n");
    }
    if (json) {
        json_t *jd = json_array();
        for (int i = 0; i < nd; i++) {
            json_t *p = json_array();
            for (int k = 0; k < a->dim; k++)
                json_array_append_new(p, json_real(fabs(dirs[i][k]) < 1e-12 ? 0.0 : dirs[i][k]));
            json_array_append_new(jd, p);
        }
        json_object_set_new(o, "free_directions", jd);
        json_array_append_new(arr, o);
    }
    cn_free(dirs);
    return CN_OK;
}

cnStatus cn_report_directions(FILE *f, const cnAssembly *a, const int *sel, int nsel, int json,
                              cnDiag *diag) {
    unsigned char *moving = cn_calloc((size_t)a->nparts, 1);
    if (!moving) return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
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
            char *s = json_dumps(o, JSON_INDENT(2) | JSON_REAL_PRECISION(10));
            json_decref(o);
            if (s) fprintf(f, "%s\n", s);
            free(s);
        } else json_decref(arr);
    }
    return st;
}
