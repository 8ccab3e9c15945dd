/* Reports of removal directions and plans. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "margin_hook.h"
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

/* ---- plans: JSON and text from the typed result ---- */

static json_t *names_json(const cnAssembly *a, cnPartList l) {
    json_t *arr = json_array();
    for (int i = 0; i < l.n; i++) json_array_append_new(arr, json_string(a->parts[l.idx[i]].name));
    return arr;
}

static json_t *name_or_null(const cnAssembly *a, int part) {
    return part >= 0 ? json_string(a->parts[part].name) : json_null();
}

/* A segment as the file writes it: a displacement, or {"rotate": degrees, "about", "axis"}. */
static json_t *seg_json(const cnSegment *sg, int dim) {
    if (sg->kind == CN_SEGMENT_TURN) {
        json_t *o = json_object(), *ab = json_array();
        json_object_set_new(o, "rotate", json_real(sg->angle * 180 / CN_PI));
        for (int k = 0; k < dim; k++) json_array_append_new(ab, json_real(sg->about[k]));
        json_object_set_new(o, "about", ab);
        if (dim == 3) {
            json_t *ax = json_array();
            for (int k = 0; k < 3; k++) json_array_append_new(ax, json_real(sg->axis[k]));
            json_object_set_new(o, "axis", ax);
        }
        return o;
    }
    json_t *v = json_array();
    for (int k = 0; k < dim; k++)
        json_array_append_new(v, json_real(fabs(sg->move[k]) < CN_TOL_PRINT_ZERO ? 0.0 : sg->move[k]));
    return v;
}

static json_t *path_json(const cnAssembly *a, const cnPlanMove *m) {
    json_t *arr = json_array();
    for (int i = 0; i < m->nseg; i++) json_array_append_new(arr, seg_json(&m->seg[i], a->dim));
    return arr;
}


static const char *support_word(cnSupport s) { return s == CN_SUPPORT_PUSH ? "push" : "hold"; }

/* The onset time of a failing move; null when not simulated (Proposition 1). */
static json_t *time_json(const cnPlanMove *m) { return m->proposition_1 ? json_null() : json_real(m->time); }

static json_t *move_json(const cnAssembly *a, const cnPlanMove *m) {
    json_t *o = json_object();
    if (m->proposition_1) json_object_set_new(o, "proposition_1", json_true());
    json_object_set_new(o, "move", names_json(a, m->move));
    json_object_set_new(o, "path", json_string(m->path));
    json_object_set_new(o, "support", json_string(support_word(m->support)));
    json_object_set_new(o, "status", json_string(cn_step_status_word(m->status)));
    if (m->status == CN_STEP_UNSTABLE) {
        json_object_set_new(o, "time", time_json(m));
        json_object_set_new(o, "moving_parts", names_json(a, m->moving));
    } else if (m->status == CN_STEP_INFEASIBLE) {
        json_object_set_new(o, "time", time_json(m));
        json_object_set_new(o, "blocked_by", name_or_null(a, m->blocked_by));
    }
    return o;
}

static json_t *best_plan_json(const cnAssembly *a, const cnPlanSequence *best) {
    if (!best) return json_null();
    json_t *plan = json_array();
    for (int i = 0; i < best->n; i++) {
        const cnPlanMove *m = &best->steps[i];
        json_t *step = json_object();
        json_object_set_new(step, "move", m->move.n == 1 ? json_string(a->parts[m->move.idx[0]].name) : names_json(a, m->move));
        json_object_set_new(step, "path", path_json(a, m));
        json_object_set_new(step, "support", json_string(support_word(m->support)));
        json_array_append_new(plan, step);
    }
    return plan;
}

char *cn_plan_sequence_json(const cnAssembly *a, const cnPlanSequence *seq) {
    json_t *plan = best_plan_json(a, seq);
    /* a subassembly gripped by one of its parts: the grip as planned (the default grips all) */
    for (int i = 0; plan && i < seq->n; i++) {
        const cnPlanMove *m = &seq->steps[i];
        if (m->move.n > 1 && m->grip >= 0)
            json_object_set_new(json_array_get(plan, (size_t)i), "grip", json_string(a->parts[m->grip].name));
    }
    json_t *doc = json_object();
    json_object_set_new(doc, "plan", plan);
    char *text = json_dumps(doc, JSON_COMPACT | JSON_REAL_PRECISION(17));
    json_decref(doc);
    return text;
}

const char *cn_plan_row_word(const cnPlanRow *r) {
    switch (r->end) {
    case CN_ROW_STABLE: return "stable";
    case CN_ROW_STATE_UNSTABLE: return "unstable state (Proposition 1)";
    case CN_ROW_STATE_UNDECIDED: return "undecided state (not proved stable)";
    case CN_ROW_UNEXPLORED: return "not explored (search budget)";
    case CN_ROW_NO_WAY_ON: return "no way on";
    default: return cn_step_status_word(r->seq.steps[r->seq.n - 1].status);
    }
}

static json_t *row_json(const cnAssembly *a, const cnPlanRow *r) {
    json_t *row = json_object(), *seq = json_array(), *paths = json_array();
    for (int i = 0; i < r->seq.n; i++) {
        json_array_append_new(seq, names_json(a, r->seq.steps[i].move));
        json_array_append_new(paths, json_string(r->seq.steps[i].path));
    }
    json_object_set_new(row, "sequence", seq);
    json_object_set_new(row, "paths", paths);
    json_object_set_new(row, "result", json_string(cn_plan_row_word(r)));
    if (r->end == CN_ROW_STEP_FAILS) {
        const cnPlanMove *t = &r->seq.steps[r->seq.n - 1];
        json_object_set_new(row, "failing_step", json_integer(r->seq.n));
        json_object_set_new(row, "time", time_json(t));
        if (t->proposition_1) json_object_set_new(row, "proposition_1", json_true());
        if (t->status == CN_STEP_UNSTABLE) json_object_set_new(row, "moving_parts", names_json(a, t->moving));
        if (t->status == CN_STEP_INFEASIBLE && t->blocked_by >= 0)
            json_object_set_new(row, "blocked_by", json_string(a->parts[t->blocked_by].name));
    }
    return row;
}

static json_t *fixels_json(const cnAssembly *a, const cnFixelSuggestion *fs) {
    json_t *arr = json_array();
    for (int q = 0; q < fs->nfixels; q++) {
        const cnFixel *f = &fs->fixels[q];
        json_t *fj = json_object(), *pp = json_array(), *nn = json_array();
        json_object_set_new(fj, "part", json_string(a->parts[f->part].name));
        for (int k = 0; k < a->dim; k++) {
            json_array_append_new(pp, json_real(f->point[k]));
            json_array_append_new(nn, json_real(fabs(f->normal[k]) < CN_TOL_PRINT_ZERO ? 0.0 : f->normal[k]));
        }
        json_object_set_new(fj, "point", pp);
        json_object_set_new(fj, "normal", nn);
        json_array_append_new(arr, fj);
    }
    return arr;
}

/* A count: a JSON integer while it is one exactly (below 2^53), else a number. */
static json_t *count_json(double n) {
    return n >= 0 && n <= 9007199254740992.0 && n == floor(n) ? json_integer((json_int_t)n) : json_real(n);
}

/* A group taken out with every part gripped (a rigid whole). */
static bool grip_whole(const cnPlanMove *m) { return m->move.n > 1 && m->grip < 0 && m->nseg > 0; }

static json_t *tree_json(const cnAssembly *a, const cnPlanNode *n) {
    json_t *o = json_object();
    json_object_set_new(o, "parts", names_json(a, n->parts));
    json_object_set_new(o, "held_by", name_or_null(a, n->held_by));
    json_object_set_new(o, "held_whole", json_boolean(n->held_whole));
    if (!n->split) return o;
    json_object_set_new(o, "remove", names_json(a, n->take_out.move));
    json_object_set_new(o, "grip", name_or_null(a, n->take_out.grip));
    json_object_set_new(o, "grip_whole", json_boolean(grip_whole(&n->take_out)));
    json_object_set_new(o, "path", json_string(n->take_out.path));
    json_object_set_new(o, "path_displacements", path_json(a, &n->take_out));
    json_t *ch = json_array();
    for (int i = 0; i < n->nchildren; i++) json_array_append_new(ch, tree_json(a, &n->children[i]));
    json_object_set_new(o, "and", ch);
    return o;
}

static json_t *split_json(const cnAssembly *a, const cnPlanSplit *sp) {
    json_t *o = json_object(), *parts = json_array();
    json_array_append_new(parts, names_json(a, sp->side[0]));
    json_array_append_new(parts, names_json(a, sp->side[1]));
    json_object_set_new(o, "parts", parts);
    json_object_set_new(o, "stable", json_boolean(sp->stable));
    json_object_set_new(o, "plans", count_json(sp->nplans));
    json_object_set_new(o, "moves_tried", json_integer(sp->moves_tried));
    json_t *how = move_json(a, &sp->move);
    json_object_set_new(how, "grip", name_or_null(a, sp->move.grip));
    json_object_set_new(how, "grip_whole", json_boolean(grip_whole(&sp->move)));
    if (sp->sides_fail)
        json_object_set_new(how, "reason", json_string("the move is stable, but a side cannot come apart afterwards"));
    json_object_set_new(o, sp->stable ? "how" : "why_not", how);
    return o;
}

static json_t *search_json(const cnPlanSearch *se) {
    json_t *search = json_object();
    json_object_set_new(search, "free_parts", json_integer(se->free_parts));
    json_object_set_new(search, "states", json_integer(se->states));
    json_object_set_new(search, "simulations", json_integer(se->simulations));
    json_object_set_new(search, "exhaustive", json_boolean(se->exhaustive));
    json_object_set_new(search, "first_plan", json_boolean(se->first_plan));
    json_object_set_new(search, "budget_reached", json_boolean(se->budget_reached));
    json_object_set_new(search, "max_states", json_integer(se->max_states));
    if (se->budget_reached) json_object_set_new(search, "budget", json_string(se->out_of_time ? "time" : "states"));
    if (se->splits_capped) json_object_set_new(search, "splits_capped", json_true());
    if (se->timing) json_object_set_new(search, "seconds", json_real(se->seconds));
    json_object_set_new(search, "processes", json_integer(se->threads));
    json_object_set_new(search, "undecided_states", json_integer(se->undecided_states));
    json_object_set_new(search, "undecided_moves", json_integer(se->undecided_moves));
    return search;
}

static json_t *plan_json(const cnAssembly *a, const cnPlanResult *r) {
    json_t *rep = json_object();
    json_object_set_new(rep, "stable", json_boolean(r->stable));
    json_object_set_new(rep, "stable_single_part", json_boolean(r->stable_single_part));
    json_object_set_new(rep, "sequence_count", count_json(r->nsequences));
    json_t *seqs = json_array();
    for (int i = 0; i < r->nlisted; i++) {
        json_t *seq = json_array();
        for (int k = 0; k < r->sequences[i].n; k++) {
            json_t *st = json_object();
            json_object_set_new(st, "move", names_json(a, r->sequences[i].steps[k].move));
            json_object_set_new(st, "path", json_string(r->sequences[i].steps[k].path));
            json_array_append_new(seq, st);
        }
        json_array_append_new(seqs, seq);
    }
    json_object_set_new(rep, "sequences", seqs);
    json_t *orders = json_array();
    for (int i = 0; i < r->nlisted_orders; i++) {
        json_t *ord = json_array();
        for (int k = 0; k < r->orders[i].n; k++) {
            json_t *one = json_array();
            json_array_append_new(one, json_string(a->parts[r->orders[i].idx[k]].name));
            json_array_append_new(ord, one);
        }
        json_array_append_new(orders, ord);
    }
    json_object_set_new(rep, "stable_orders", orders);
    json_object_set_new(rep, "order_count", count_json(r->norders));
    json_object_set_new(rep, "best_plan", best_plan_json(a, r->best_plan));
    json_t *rows = json_array();
    for (int i = 0; i < r->nrows; i++) json_array_append_new(rows, row_json(a, &r->table[i]));
    json_object_set_new(rep, "table", rows);
    json_t *dep = json_array();
    for (int i = 0; i < r->nchoices; i++) {
        const cnPlanPathChoice *c = &r->choices[i];
        json_t *d = json_object(), *which = json_array();
        json_object_set_new(d, "remaining", names_json(a, c->remaining));
        json_object_set_new(d, "move", json_string(a->parts[c->part].name));
        json_object_set_new(d, "path_dependent", json_boolean(c->path_dependent));
        for (int k = 0; k < c->paths.n; k++) json_array_append_new(which, move_json(a, &c->paths.steps[k]));
        json_object_set_new(d, "paths", which);
        json_array_append_new(dep, d);
    }
    json_object_set_new(rep, "steps", dep);
    json_t *dead = json_array(), *fix = json_array();
    if (r->unstable_at_start) {
        json_t *d = json_object();
        json_object_set_new(d, "reason", json_string(r->undecided_at_start ? "the assembly is not proved stable before any part moves (undecided)"
                                                                         : "the assembly is not stable before any part moves"));
        json_array_append_new(dead, d);
    }
    for (int k = 0; k < r->ndead; k++) {
        json_t *d = move_json(a, &r->dead_ends[k]);
        if (r->dead_ends[k].status == CN_STEP_STABLE)
            json_object_set_new(d, "reason", json_string(r->search.budget_reached
                                                             ? "stable; the search budget ran out beyond it"
                                                             : "stable, but no stable way on from the state it leaves"));
        json_array_append_new(dead, d);
    }
    for (int k = 0; k < r->nfixels; k++) {
        json_t *o = json_object();
        json_object_set_new(o, "for", move_json(a, &r->fixels[k].step));
        json_object_set_new(o, "fixels", fixels_json(a, &r->fixels[k]));
        json_object_set_new(o, "verified", json_true());
        json_array_append_new(fix, o);
    }
    json_object_set_new(rep, "dead_ends", dead);
    json_object_set_new(rep, "fixel_suggestions", fix);
    if (r->subassemblies) {
        json_object_set_new(rep, "two_handed_plans", count_json(r->nplans));
        json_object_set_new(rep, "two_handed_plans_exact", json_boolean(r->search.exhaustive));
        json_object_set_new(rep, "and_or_tree", r->tree ? tree_json(a, r->tree) : json_null());
        json_t *sp = json_array();
        for (int i = 0; i < r->nsplits; i++) json_array_append_new(sp, split_json(a, &r->splits[i]));
        json_object_set_new(rep, "splits", sp);
    }
    json_object_set_new(rep, "search", search_json(&r->search));
    return rep;
}

static void names_text(FILE *f, const cnAssembly *a, cnPartList l) {
    for (int i = 0; i < l.n; i++) fprintf(f, "%s%s", i ? "+" : "", a->parts[l.idx[i]].name);
}

/* " gripping X" (the others carried by contact) or " held whole" for a group taken out. */
static void grip_text(FILE *f, const cnAssembly *a, const cnPlanMove *m) {
    if (m->grip >= 0) fprintf(f, " gripping %s", a->parts[m->grip].name);
    else if (grip_whole(m)) fprintf(f, " held whole");
}

static void tree_text(FILE *f, const cnAssembly *a, const cnPlanNode *n, int depth) {
    fprintf(f, "%*s{", 2 * depth + 2, "");
    names_text(f, a, n->parts);
    fprintf(f, "}");
    if (n->held_by >= 0) fprintf(f, " in the gripper holding %s", a->parts[n->held_by].name);
    else if (n->held_whole) fprintf(f, " held whole");
    else if (n->parts.n > 0) fprintf(f, " on the supports");
    if (!n->split) {
        fprintf(f, "\n");
        return;
    }
    fprintf(f, ": take out ");
    names_text(f, a, n->take_out.move);
    grip_text(f, a, &n->take_out);
    fprintf(f, " (%s)%s\n", n->take_out.path, n->nchildren ? ", AND" : "");
    for (int i = 0; i < n->nchildren; i++) tree_text(f, a, &n->children[i], depth + 1);
}

/* " at t = ..., X starts to move" (or by Proposition 1) for an unstable move. */
static void onset_text(FILE *f, const cnAssembly *a, const cnPlanMove *m, const char *prop1) {
    if (m->proposition_1) fprintf(f, "%s", prop1);
    else fprintf(f, " at t = %.6g, ", m->time);
    names_text(f, a, m->moving);
    fprintf(f, " start%s to move", m->moving.n == 1 ? "s" : "");
}

static void splits_text(FILE *f, const cnAssembly *a, const cnPlanResult *r) {
    for (int i = 0; i < r->nsplits; i++) {
        const cnPlanSplit *sp = &r->splits[i];
        const cnPlanMove *w = &sp->move;
        if (i == 0) fprintf(f, "two-handed splits of the assembly:\n");
        fprintf(f, "  {");
        names_text(f, a, sp->side[0]);
        fprintf(f, "} | {");
        names_text(f, a, sp->side[1]);
        if (sp->stable) fprintf(f, "}: stable (%.0f plan%s): ", sp->nplans, sp->nplans == 1 ? "" : "s");
        else fprintf(f, "}: not stable: ");
        names_text(f, a, w->move);
        grip_text(f, a, w);
        fprintf(f, " (%s) %s", w->path, cn_step_status_word(w->status));
        if (w->status == CN_STEP_UNSTABLE) onset_text(f, a, w, " by Proposition 1, ");
        if (sp->sides_fail) fprintf(f, ": %s", "the move is stable, but a side cannot come apart afterwards");
        fprintf(f, "\n");
    }
}

static const char *search_word(const cnPlanSearch *se) {
    if (se->budget_reached)
        return se->out_of_time ? "STOPPED: the time budget was reached, the results are partial"
                               : "STOPPED: the state budget was reached, the results are partial";
    if (se->exhaustive)
        return se->first_plan ? "exhaustive (more than 16 free parts, and no plan: every state reached stably was expanded)"
                              : "exhaustive";
    if (se->splits_capped)
        return "not exhaustive: the two-handed search took a state's groups from 20 of its parts at most";
    return "stopped at the first stable plan (more than 16 free parts)";
}

static void verdict_text(FILE *f, const cnAssembly *a, const cnPlanResult *r) {
    if (r->stable_single_part) {
        const char *least = r->search.exhaustive ? "" : "at least ";
        fprintf(f, "a stable plan exists: %s%.0f stable order%s of the parts (%s%.0f with the choice of paths):",
                least, r->norders, r->norders == 1 ? "" : "s", least, r->nsequences);
        for (int i = 0; i < r->nlisted_orders && i < 10; i++) {
            fprintf(f, "%s", i ? "," : "");
            for (int k = 0; k < r->orders[i].n; k++)
                fprintf(f, "%s%s", k ? "-" : " ", a->parts[r->orders[i].idx[k]].name);
        }
        fprintf(f, "%s\n", r->nlisted_orders > 10 ? ", ..." : "");
    } else if (r->stable)
        fprintf(f, "no single part can go first stably, but subassemblies can: see the AND/OR tree\n");
    else if (r->search.budget_reached)
        fprintf(f, "no stable plan found within the search budget (one may still exist)\n");
    else if (r->search.undecided_states || r->search.undecided_moves)
        fprintf(f, "no plan was proved stable (one may still exist through the undecided states "
                   "or moves)\n");
    else fprintf(f, "NO stable plan exists\n");
    if (r->nlisted > 0) {
        fprintf(f, "stable sequences%s:\n", (double)r->nlisted < r->nsequences ? " (the first ones; --all lists every one)" : "");
        for (int i = 0; i < r->nlisted; i++) {
            fprintf(f, "  %d. ", i + 1);
            for (int k = 0; k < r->sequences[i].n; k++) {
                if (k) fprintf(f, ", ");
                names_text(f, a, r->sequences[i].steps[k].move);
                fprintf(f, " (%s)", r->sequences[i].steps[k].path);
            }
            fprintf(f, "\n");
        }
    }
}

static void table_text(FILE *f, const cnAssembly *a, const cnPlanResult *r) {
    fprintf(f, "sequence x paths:\n");
    for (int i = 0; i < r->nrows; i++) {
        const cnPlanRow *row = &r->table[i];
        char buf[512] = "";
        for (int k = 0; k < row->seq.n; k++) {
            const cnPlanMove *m = &row->seq.steps[k];
            for (int q = 0; q < m->move.n; q++) {
                strncat(buf, q ? "+" : (k ? " - " : ""), sizeof buf - strlen(buf) - 1);
                strncat(buf, a->parts[m->move.idx[q]].name, sizeof buf - strlen(buf) - 1);
            }
            strncat(buf, " (", sizeof buf - strlen(buf) - 1);
            strncat(buf, m->path, sizeof buf - strlen(buf) - 1);
            strncat(buf, ")", sizeof buf - strlen(buf) - 1);
        }
        fprintf(f, "  %-52s %s", buf, cn_plan_row_word(row));
        if (row->end == CN_ROW_STEP_FAILS) {
            const cnPlanMove *t = &row->seq.steps[row->seq.n - 1];
            if (t->proposition_1)
                fprintf(f, " at step %d (Proposition 1: the state without it is %s)", row->seq.n,
                        t->status == CN_STEP_UNDECIDED ? "undecided" : "unstable");
            else fprintf(f, " at step %d, t = %.6g", row->seq.n, t->time);
            if (t->status == CN_STEP_UNSTABLE) {
                fprintf(f, ": ");
                names_text(f, a, t->moving);
                fprintf(f, " move%s", t->moving.n == 1 ? "s" : "");
            }
            if (t->status == CN_STEP_INFEASIBLE && t->blocked_by >= 0) fprintf(f, ": blocked by %s", a->parts[t->blocked_by].name);
        }
        fprintf(f, "\n");
    }
    int any = 0;
    for (int i = 0; i < r->nchoices; i++) {
        const cnPlanPathChoice *d = &r->choices[i];
        if (!d->path_dependent) continue;
        if (!any) fprintf(f, "path-dependent steps (some paths stable, others not):\n");
        any = 1;
        fprintf(f, "  from {");
        names_text(f, a, d->remaining);
        fprintf(f, "}, removing %s:", a->parts[d->part].name);
        for (int k = 0; k < d->paths.n; k++)
            fprintf(f, " %s %s%s", d->paths.steps[k].path, cn_step_status_word(d->paths.steps[k].status), k + 1 < d->paths.n ? ";" : "");
        fprintf(f, "\n");
    }
    if (!any && !r->search.first_plan) fprintf(f, "every step explored is path-independent\n");
}

static void failures_text(FILE *f, const cnAssembly *a, const cnPlanResult *r) {
    if (r->unstable_at_start || r->ndead > 0)
        fprintf(f, "%s\n", r->search.budget_reached && !r->unstable_at_start
                                ? "the first steps tried before the search budget ran out, and how they ended:"
                                : "why every first step fails:");
    if (r->unstable_at_start)
        fprintf(f, "  the assembly is %s before any part moves\n",
                r->undecided_at_start ? "not proved stable (undecided)" : "not stable");
    for (int i = 0; i < r->ndead; i++) {
        const cnPlanMove *d = &r->dead_ends[i];
        fprintf(f, "  ");
        names_text(f, a, d->move);
        fprintf(f, " (%s): %s", d->path, cn_step_status_word(d->status));
        if (d->status == CN_STEP_UNSTABLE) onset_text(f, a, d, " by Proposition 1 (the state without it is unstable), ");
        if (d->status == CN_STEP_INFEASIBLE && d->blocked_by >= 0) fprintf(f, ", blocked by %s", a->parts[d->blocked_by].name);
        if (d->status == CN_STEP_STABLE)
            fprintf(f, "%s", r->search.budget_reached ? ": stable; the search budget ran out beyond it"
                                                      : ": stable, but no stable way on from the state it leaves");
        fprintf(f, "\n");
    }
    for (int i = 0; i < r->nfixels; i++) {
        const cnFixelSuggestion *s = &r->fixels[i];
        if (i == 0) fprintf(f, "fixels that make a first step stable (each verified by simulating it again):\n");
        fprintf(f, "  for ");
        names_text(f, a, s->step.move);
        fprintf(f, " (%s):", s->step.path);
        json_t *fj = fixels_json(a, s);
        char *fx = json_dumps(fj, JSON_COMPACT | JSON_REAL_PRECISION(8));
        json_decref(fj);
        fprintf(f, " \"fixels\": %s\n", fx ? fx : "");
        free(fx);
    }
}

static const char *const MARGIN_KEYS[3] = {"friction", "tilt", "lateral"};
static const int MARGIN_KINDS[3] = {CN_MARGIN_FRICTION, CN_MARGIN_TILT, CN_MARGIN_LATERAL};

/* The ranking of plan --margin: per sequence, its weakest step of each kind. */
static json_t *margins_json(const cnAssembly *a, const cnPlanMargin *m, int n, int nlisted, int rank) {
    json_t *o = json_object(), *list = json_array();
    json_object_set_new(o, "ranked_by", json_string(MARGIN_KEYS[cn_margin_kind_index(rank)]));
    for (int i = 0; i < n; i++) {
        json_t *e = json_object();
        json_object_set_new(e, "sequence", json_integer(m[i].sequence));
        json_object_set_new(e, "status", json_string(cn_step_status_word(m[i].status)));
        json_object_set_new(e, "failed_step", m[i].failed_step >= 0 ? json_integer(m[i].failed_step) : json_null());
        for (int k = 0; k < 3; k++) {
            if (m[i].weakest_step[k] < 0) continue;
            const cnStepMargin *w = &m[i].weakest[k];
            if (k == 0) json_object_set_new(e, "critical_friction", isfinite(w->at.value) ? json_real(w->at.value) : json_null());
            json_t *mj = cn_margin_json(a, &w->at, MARGIN_KINDS[k]);
            json_object_set_new(mj, "step", json_integer(m[i].weakest_step[k]));
            json_object_set_new(mj, "time", json_real(w->time));
            json_object_set_new(mj, "distance", json_real(w->distance));
            json_object_set_new(e, MARGIN_KEYS[k], mj);
        }
        json_array_append_new(list, e);
    }
    json_object_set_new(o, "sequences", list);
    json_object_set_new(o, "ranked", json_integer(n));
    json_object_set_new(o, "of", json_integer(nlisted));
    return o;
}

/* One margin's value in a ranking line. */
static void margin_value_text(FILE *f, int k, const cnStepMargin *w) {
    if (k == 0) fprintf(f, "critical friction %.4g", w->at.value);
    else if (k == 1) fprintf(f, "tilt %.4g deg%s", w->at.value * 180 / CN_PI, w->at.end == CN_MARGIN_WHOLE ? " (or more)" : "");
    else fprintf(f, "lateral %.4g g%s", w->at.value, w->at.end == CN_MARGIN_WHOLE ? " (or more)" : "");
}

static void margins_text(FILE *f, const cnAssembly *a, const cnPlanResult *r, const cnPlanMargin *m, int n, int rank) {
    int rk = cn_margin_kind_index(rank);
    fprintf(f, "margins of the stable sequences listed, strongest first (ranked by %s; each the weakest step's, "
               "over its samples, to 4 digits)", rk == 0 ? "the critical friction" : MARGIN_KEYS[rk]);
    if (n < r->nlisted) fprintf(f, "; the first %d of the %d listed", n, r->nlisted);
    fprintf(f, ":\n");
    for (int i = 0; i < n; i++) {
        const cnPlanMargin *p = &m[i];
        fprintf(f, "  %d. sequence %d: ", i + 1, p->sequence + 1);
        if (p->failed_step >= 0) {
            fprintf(f, "step %d %s when sampled as simulate does (no margin)\n", p->failed_step + 1,
                    cn_step_status_word(p->status));
            continue;
        }
        bool any = false;
        for (int k = 0; k < 3; k++) {
            int kk = k == 0 ? rk : k == rk ? 0 : k; /* the ranking's kind first */
            if (p->weakest_step[kk] < 0) continue;
            const cnStepMargin *w = &p->weakest[kk];
            fprintf(f, "%s", any ? "; " : "");
            margin_value_text(f, kk, w);
            fprintf(f, " at step %d (", p->weakest_step[kk] + 1);
            names_text(f, a, r->sequences[p->sequence].steps[p->weakest_step[kk]].move);
            fprintf(f, ", distance %.4g)", w->distance);
            any = true;
        }
        if (!any) fprintf(f, "no margin found (with --pair: the pair's friction plays no part at any sample)");
        fprintf(f, "\n");
    }
}

cnStatus cn_report_plan_margins(FILE *f, const cnAssembly *a, const cnPlanResult *r, const cnPlanMargin *m,
                                int n, int rank, int json) {
    if (!r->mem_) return CN_ERR_INPUT;
    if (json) {
        json_t *o = plan_json(a, r);
        json_object_set_new(o, "margins", margins_json(a, m, n, r->nlisted, rank));
        return cn_json_write(f, o, 10);
    }
    cnStatus st = cn_report_plan(f, a, r, 0);
    if (st == CN_OK) margins_text(f, a, r, m, n, rank);
    return st;
}

cnStatus cn_report_plan(FILE *f, const cnAssembly *a, const cnPlanResult *r, int json) {
    if (!r->mem_) return CN_ERR_INPUT;
    if (json) return cn_json_write(f, plan_json(a, r), 10);
    if (a->name) fprintf(f, "%s\n", a->name);
    fprintf(f, "search: %d free part%s, %d state%s, %d simulation%s, %.3g s, %s\n",
            r->search.free_parts, cn_plural(r->search.free_parts), r->search.states,
            cn_plural(r->search.states), r->search.simulations, cn_plural(r->search.simulations),
            r->search.seconds, search_word(&r->search));
    if (r->search.undecided_states || r->search.undecided_moves)
        fprintf(f, "undecided: %d state%s and %d move%s could not be proved stable or unstable (with "
                   "friction, the search for a motion from rest ran out of budget); they count as not "
                   "stable. More with --search-budget N; the weak reading with --accept-prestress\n",
                r->search.undecided_states, r->search.undecided_states == 1 ? "" : "s",
                r->search.undecided_moves, r->search.undecided_moves == 1 ? "" : "s");
    verdict_text(f, a, r);
    table_text(f, a, r);
    if (r->best_plan) {
        json_t *bp = best_plan_json(a, r->best_plan);
        char *s = json_dumps(bp, JSON_COMPACT | JSON_REAL_PRECISION(10));
        json_decref(bp);
        fprintf(f, "best plan (replay it with cairn simulate):\n  \"plan\": %s\n", s ? s : "");
        free(s);
    }
    failures_text(f, a, r);
    splits_text(f, a, r);
    if (r->subassemblies && r->tree) {
        fprintf(f, "%s%.0f stable two-handed plan%s (AND/OR trees; a split counts once per grip of the "
                   "side taken out, paths aside); the first:\n",
                r->search.exhaustive ? "" : "at least ", r->nplans, r->nplans == 1 ? "" : "s");
        tree_text(f, a, r->tree, 0);
    } else if (r->subassemblies) fprintf(f, "no stable two-handed decomposition either\n");
    return CN_OK;
}
