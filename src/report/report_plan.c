/* Reports of removal directions and plans. */
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
            cn_json_write(f, o, 10);
        } else json_decref(arr);
    }
    return st;
}

static void names_text(FILE *f, json_t *arr) {
    for (size_t i = 0; i < json_array_size(arr); i++)
        fprintf(f, "%s%s", i ? "+" : "", json_string_value(json_array_get(arr, i)));
}

static void tree_text(FILE *f, json_t *node, int depth) {
    fprintf(f, "%*s{", 2 * depth + 2, "");
    names_text(f, json_object_get(node, "parts"));
    fprintf(f, "}");
    json_t *held = json_object_get(node, "held_by");
    if (json_is_string(held)) fprintf(f, " in the gripper holding %s", json_string_value(held));
    else if (json_array_size(json_object_get(node, "parts")) > 0) fprintf(f, " on the supports");
    json_t *rm = json_object_get(node, "remove");
    if (!rm) {
        fprintf(f, "\n");
        return;
    }
    fprintf(f, ": take out ");
    names_text(f, rm);
    json_t *grip = json_object_get(node, "grip");
    if (json_is_string(grip)) fprintf(f, " gripping %s", json_string_value(grip));
    fprintf(f, " (%s), AND\n", json_string_value(json_object_get(node, "path")));
    json_t *ch = json_object_get(node, "and");
    for (size_t i = 0; i < json_array_size(ch); i++) tree_text(f, json_array_get(ch, i), depth + 1);
}

static void splits_text(FILE *f, json_t *splits) {
    for (size_t i = 0; i < json_array_size(splits); i++) {
        json_t *sp = json_array_get(splits, i), *parts = json_object_get(sp, "parts");
        bool ok = json_is_true(json_object_get(sp, "stable"));
        if (i == 0) fprintf(f, "two-handed splits of the assembly:\n");
        fprintf(f, "  {");
        names_text(f, json_array_get(parts, 0));
        fprintf(f, "} | {");
        names_text(f, json_array_get(parts, 1));
        json_t *w = json_object_get(sp, ok ? "how" : "why_not");
        fprintf(f, "}: %s: ", ok ? "stable" : "not stable");
        names_text(f, json_object_get(w, "move"));
        json_t *grip = json_object_get(w, "grip");
        if (json_is_string(grip)) fprintf(f, " gripping %s", json_string_value(grip));
        fprintf(f, " (%s) %s", json_string_value(json_object_get(w, "path")),
                json_string_value(json_object_get(w, "status")));
        json_t *mp = json_object_get(w, "moving_parts");
        if (mp) {
            json_t *tm = json_object_get(w, "time");
            if (json_is_null(tm)) fprintf(f, " by Proposition 1, ");
            else fprintf(f, " at t = %.6g, ", json_real_value(tm));
            names_text(f, mp);
            fprintf(f, " start%s to move", json_array_size(mp) == 1 ? "s" : "");
        }
        json_t *reason = json_object_get(w, "reason");
        if (reason) fprintf(f, ": %s", json_string_value(reason));
        fprintf(f, "\n");
    }
}

cnStatus cn_report_plan(FILE *f, const cnAssembly *a, const cnPlanResult *r, int json) {
    json_t *rep = (json_t *)r->report;
    if (!rep) return CN_ERR_INPUT;
    if (json) return cn_json_write(f, json_incref(rep), 10);
    json_t *search = json_object_get(rep, "search");
    const char *budget = json_string_value(json_object_get(search, "budget"));
    if (a->name) fprintf(f, "%s\n", a->name);
    fprintf(f, "search: %lld free parts, %lld states, %lld simulations, %.3g s, %s\n",
            (long long)json_integer_value(json_object_get(search, "free_parts")),
            (long long)json_integer_value(json_object_get(search, "states")),
            (long long)json_integer_value(json_object_get(search, "simulations")),
            r->seconds,
            json_is_true(json_object_get(search, "budget_reached"))
                ? (budget && !strcmp(budget, "time")
                       ? "STOPPED: the time budget was reached, the results are partial"
                       : "STOPPED: the state budget was reached, the results are partial")
                : json_is_true(json_object_get(search, "exhaustive")) ? "exhaustive"
                                                                      : "stopped at the first stable plan (more than 16 free parts)");
    double count = json_real_value(json_object_get(rep, "sequence_count"));
    json_t *seqs = json_object_get(rep, "sequences");
    json_t *orders = json_object_get(rep, "stable_orders");
    if (json_is_true(json_object_get(rep, "stable_single_part"))) {
        double norders = json_real_value(json_object_get(rep, "order_count"));
        fprintf(f, "a stable plan exists: %.0f stable order%s of the parts (%.0f with the choice of paths):",
                norders, norders == 1 ? "" : "s", count);
        for (size_t i = 0; i < json_array_size(orders) && i < 10; i++) {
            json_t *o = json_array_get(orders, i);
            fprintf(f, "%s", i ? "," : "");
            for (size_t k = 0; k < json_array_size(o); k++) {
                fprintf(f, "%s", k ? "-" : " ");
                names_text(f, json_array_get(o, k));
            }
        }
        fprintf(f, "%s\n", json_array_size(orders) > 10 ? ", ..." : "");
    }
    else if (json_is_true(json_object_get(rep, "stable")))
        fprintf(f, "no single part can go first stably, but subassemblies can: see the AND/OR tree\n");
    else if (json_is_true(json_object_get(search, "budget_reached")))
        fprintf(f, "no stable plan found within the search budget (one may still exist)\n");
    else fprintf(f, "NO stable plan exists\n");
    if (json_array_size(seqs) > 0) {
        fprintf(f, "stable sequences%s:\n", (double)json_array_size(seqs) < count ? " (the first ones; --all lists every one)" : "");
        for (size_t i = 0; i < json_array_size(seqs); i++) {
            json_t *sq = json_array_get(seqs, i);
            fprintf(f, "  %zu. ", i + 1);
            for (size_t k = 0; k < json_array_size(sq); k++) {
                json_t *st = json_array_get(sq, k);
                if (k) fprintf(f, ", ");
                names_text(f, json_object_get(st, "move"));
                fprintf(f, " (%s)", json_string_value(json_object_get(st, "path")));
            }
            fprintf(f, "\n");
        }
    }
    json_t *rows = json_object_get(rep, "table");
    fprintf(f, "sequence x paths:\n");
    for (size_t i = 0; i < json_array_size(rows); i++) {
        json_t *row = json_array_get(rows, i), *sq = json_object_get(row, "sequence"),
               *ps = json_object_get(row, "paths");
        char buf[512] = "";
        for (size_t k = 0; k < json_array_size(sq); k++) {
            json_t *m = json_array_get(sq, k);
            for (size_t q = 0; q < json_array_size(m); q++) {
                strncat(buf, q ? "+" : (k ? " - " : ""), sizeof buf - strlen(buf) - 1);
                strncat(buf, json_string_value(json_array_get(m, q)), sizeof buf - strlen(buf) - 1);
            }
            strncat(buf, " (", sizeof buf - strlen(buf) - 1);
            strncat(buf, json_string_value(json_array_get(ps, k)), sizeof buf - strlen(buf) - 1);
            strncat(buf, ")", sizeof buf - strlen(buf) - 1);
        }
        fprintf(f, "  %-52s %s", buf, json_string_value(json_object_get(row, "result")));
        json_t *tm = json_object_get(row, "time");
        if (json_is_null(tm))
            fprintf(f, " at step %lld (Proposition 1: the state without it is unstable)", (long long)json_integer_value(json_object_get(row, "failing_step")));
        else if (tm) fprintf(f, " at step %lld, t = %.6g", (long long)json_integer_value(json_object_get(row, "failing_step")), json_real_value(tm));
        json_t *mp = json_object_get(row, "moving_parts");
        if (mp) {
            fprintf(f, ": ");
            names_text(f, mp);
            fprintf(f, " move%s", json_array_size(mp) == 1 ? "s" : "");
        }
        json_t *bb = json_object_get(row, "blocked_by");
        if (bb) fprintf(f, ": blocked by %s", json_string_value(bb));
        fprintf(f, "\n");
    }
    json_t *steps = json_object_get(rep, "steps");
    int any = 0;
    for (size_t i = 0; i < json_array_size(steps); i++) {
        json_t *d = json_array_get(steps, i);
        if (!json_is_true(json_object_get(d, "path_dependent"))) continue;
        if (!any) fprintf(f, "path-dependent steps (some paths stable, others not):\n");
        any = 1;
        fprintf(f, "  from {");
        names_text(f, json_object_get(d, "remaining"));
        fprintf(f, "}, removing %s:", json_string_value(json_object_get(d, "move")));
        json_t *ps = json_object_get(d, "paths");
        for (size_t k = 0; k < json_array_size(ps); k++) {
            json_t *p = json_array_get(ps, k);
            fprintf(f, " %s %s%s", json_string_value(json_object_get(p, "path")),
                    json_string_value(json_object_get(p, "status")), k + 1 < json_array_size(ps) ? ";" : "");
        }
        fprintf(f, "\n");
    }
    if (!any) fprintf(f, "every step explored is path-independent\n");
    json_t *best = json_object_get(rep, "best_plan");
    if (json_is_array(best)) {
        char *s = json_dumps(best, JSON_COMPACT | JSON_REAL_PRECISION(10));
        fprintf(f, "best plan (replay it with cairn simulate):\n  \"plan\": %s\n", s ? s : "");
        free(s);
    }
    json_t *dead = json_object_get(rep, "dead_ends");
    for (size_t i = 0; i < json_array_size(dead); i++) {
        json_t *d = json_array_get(dead, i);
        if (i == 0) fprintf(f, "why every first step fails:\n");
        json_t *reason = json_object_get(d, "reason");
        if (!json_object_get(d, "move")) {
            fprintf(f, "  %s\n", json_string_value(reason));
            continue;
        }
        fprintf(f, "  ");
        names_text(f, json_object_get(d, "move"));
        fprintf(f, " (%s): %s", json_string_value(json_object_get(d, "path")), json_string_value(json_object_get(d, "status")));
        json_t *mp = json_object_get(d, "moving_parts");
        if (mp) {
            json_t *tm = json_object_get(d, "time");
            if (json_is_null(tm)) fprintf(f, " by Proposition 1 (the state without it is unstable), ");
            else fprintf(f, " at t = %.6g, ", json_real_value(tm));
            names_text(f, mp);
            fprintf(f, " start%s to move", json_array_size(mp) == 1 ? "s" : "");
        }
        json_t *bb = json_object_get(d, "blocked_by");
        if (bb && json_is_string(bb)) fprintf(f, ", blocked by %s", json_string_value(bb));
        if (reason) fprintf(f, ": %s", json_string_value(reason));
        fprintf(f, "\n");
    }
    json_t *fix = json_object_get(rep, "fixel_suggestions");
    for (size_t i = 0; i < json_array_size(fix); i++) {
        json_t *s = json_array_get(fix, i), *for_ = json_object_get(s, "for");
        if (i == 0) fprintf(f, "fixels that make a first step stable (each verified by simulating it again):\n");
        fprintf(f, "  for ");
        names_text(f, json_object_get(for_, "move"));
        fprintf(f, " (%s):", json_string_value(json_object_get(for_, "path")));
        char *fx = json_dumps(json_object_get(s, "fixels"), JSON_COMPACT | JSON_REAL_PRECISION(8));
        fprintf(f, " \"fixels\": %s\n", fx ? fx : "");
        free(fx);
    }
    splits_text(f, json_object_get(rep, "splits"));
    json_t *tree = json_object_get(rep, "and_or_tree");
    if (tree && json_is_object(tree)) {
        fprintf(f, "stable AND/OR tree (two-handed: a subassembly taken out stays in its gripper):\n");
        tree_text(f, tree, 0);
    } else if (tree) fprintf(f, "no stable two-handed decomposition either\n");
    return CN_OK;
}
