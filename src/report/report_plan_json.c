/* The planner's findings as JSON (plan --json), and the ranking of plan --margin. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "margin_hook.h"
#include "report_plan.h"

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

json_t *cn_report_best_plan_json(const cnAssembly *a, const cnPlanSequence *best) {
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
    json_t *plan = cn_report_best_plan_json(a, seq);
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

json_t *cn_report_fixels_json(const cnAssembly *a, const cnFixelSuggestion *fs) {
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
bool cn_report_grip_whole(const cnPlanMove *m) { return m->move.n > 1 && m->grip < 0 && m->nseg > 0; }

static json_t *tree_json(const cnAssembly *a, const cnPlanNode *n) {
    json_t *o = json_object();
    json_object_set_new(o, "parts", names_json(a, n->parts));
    json_object_set_new(o, "held_by", name_or_null(a, n->held_by));
    json_object_set_new(o, "held_whole", json_boolean(n->held_whole));
    if (!n->split) return o;
    json_object_set_new(o, "remove", names_json(a, n->take_out.move));
    json_object_set_new(o, "grip", name_or_null(a, n->take_out.grip));
    json_object_set_new(o, "grip_whole", json_boolean(cn_report_grip_whole(&n->take_out)));
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
    json_object_set_new(how, "grip_whole", json_boolean(cn_report_grip_whole(&sp->move)));
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

json_t *cn_report_plan_json(const cnAssembly *a, const cnPlanResult *r) {
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
    json_object_set_new(rep, "best_plan", cn_report_best_plan_json(a, r->best_plan));
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
        json_object_set_new(o, "fixels", cn_report_fixels_json(a, &r->fixels[k]));
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


const char *const CN_REPORT_MARGIN_KEYS[3] = {"friction", "tilt", "lateral"};
static const int MARGIN_KINDS[3] = {CN_MARGIN_FRICTION, CN_MARGIN_TILT, CN_MARGIN_LATERAL};

/* The ranking of plan --margin: per sequence, its weakest step of each kind. */
json_t *cn_report_plan_margins_json(const cnAssembly *a, const cnPlanMargin *m, int n, int nlisted, int rank) {
    json_t *o = json_object(), *list = json_array();
    json_object_set_new(o, "ranked_by", json_string(CN_REPORT_MARGIN_KEYS[cn_margin_kind_index(rank)]));
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
            json_object_set_new(e, CN_REPORT_MARGIN_KEYS[k], mj);
        }
        json_array_append_new(list, e);
    }
    json_object_set_new(o, "sequences", list);
    json_object_set_new(o, "ranked", json_integer(n));
    json_object_set_new(o, "of", json_integer(nlisted));
    return o;
}

/* One margin's value in a ranking line. */
