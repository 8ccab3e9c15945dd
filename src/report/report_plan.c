/* The planner's findings as text, and the plan reports' entry points (JSON: report_plan_json.c). */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "margin_hook.h"
#include "report_plan.h"

static void names_text(FILE *f, const cnAssembly *a, cnPartList l) {
    for (int i = 0; i < l.n; i++) fprintf(f, "%s%s", i ? "+" : "", a->parts[l.idx[i]].name);
}

/* " gripping X" (the others carried by contact) or " held whole" for a group taken out. */
static void grip_text(FILE *f, const cnAssembly *a, const cnPlanMove *m) {
    if (m->grip >= 0) fprintf(f, " gripping %s", a->parts[m->grip].name);
    else if (cn_report_grip_whole(m)) fprintf(f, " held whole");
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
        json_t *fj = cn_report_fixels_json(a, s);
        char *fx = json_dumps(fj, JSON_COMPACT | JSON_REAL_PRECISION(8));
        json_decref(fj);
        fprintf(f, " \"fixels\": %s\n", fx ? fx : "");
        free(fx);
    }
}


static void margin_value_text(FILE *f, int k, const cnStepMargin *w) {
    if (k == 0) fprintf(f, "critical friction %.4g", w->at.value);
    else if (k == 1) fprintf(f, "tilt %.4g deg%s", w->at.value * 180 / CN_PI, w->at.end == CN_MARGIN_WHOLE ? " (or more)" : "");
    else fprintf(f, "lateral %.4g g%s", w->at.value, w->at.end == CN_MARGIN_WHOLE ? " (or more)" : "");
}

static void margins_text(FILE *f, const cnAssembly *a, const cnPlanResult *r, const cnPlanMargin *m, int n, int rank) {
    int rk = cn_margin_kind_index(rank);
    fprintf(f, "margins of the stable sequences listed, strongest first (ranked by %s; each the weakest step's, "
               "over its samples, to 4 digits)", rk == 0 ? "the critical friction" : CN_REPORT_MARGIN_KEYS[rk]);
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
        json_t *o = cn_report_plan_json(a, r);
        json_object_set_new(o, "margins", cn_report_plan_margins_json(a, m, n, r->nlisted, rank));
        return cn_json_write(f, o, 10);
    }
    cnStatus st = cn_report_plan(f, a, r, 0);
    if (st == CN_OK) margins_text(f, a, r, m, n, rank);
    return st;
}

cnStatus cn_report_plan(FILE *f, const cnAssembly *a, const cnPlanResult *r, int json) {
    if (!r->mem_) return CN_ERR_INPUT;
    if (json) return cn_json_write(f, cn_report_plan_json(a, r), 10);
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
        json_t *bp = cn_report_best_plan_json(a, r->best_plan);
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
