/* Plans ranked by how far they are from failing: each stable sequence the planner listed is
 * simulated as a plan with margins (cnSimOptions.margin), and the weakest step of each kind is
 * kept; the sequences are then sorted strongest first. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "core.h"
#include "margin_hook.h"
#include "cairn/plan.h"


/* The plan steps of a sequence (its moves along their paths, as cn_plan_sequence_json writes
 * them: a subassembly gripped by its planned part, else every moved part gripped). */
static cnPlanStep *sequence_steps(const cnPlanSequence *seq, int *grips) {
    cnPlanStep *steps = cn_calloc((size_t)seq->n + 1, sizeof(cnPlanStep));
    if (!steps) return NULL;
    for (int i = 0; i < seq->n; i++) {
        const cnPlanMove *m = &seq->steps[i];
        cnPlanStep *st = &steps[i];
        st->nmove = m->move.n;
        st->move = (int *)m->move.idx;
        grips[i] = m->grip;
        st->ngrip = m->move.n > 1 && m->grip >= 0 ? 1 : m->move.n;
        st->grip = m->move.n > 1 && m->grip >= 0 ? &grips[i] : (int *)m->move.idx;
        st->nseg = m->nseg;
        st->seg = (cnSegment *)m->seg;
        st->path_given = true;
        st->support = m->support;
        st->gripper = -1;
    }
    return steps;
}

static cnStatus one_sequence(const cnAssembly *a, const cnPlanSequence *seq, const cnSimOptions *so,
                             cnPlanMargin *pm, cnDiag *diag) {
    int *grips = cn_calloc((size_t)seq->n + 1, sizeof(int));
    cnPlanStep *steps = grips ? sequence_steps(seq, grips) : NULL;
    if (!steps) {
        cn_free(grips);
        return cn_diag_oom(diag);
    }
    cnAssembly v = *a; /* the assembly with this sequence as its plan */
    v.plan = steps;
    v.nsteps = seq->n;
    cnSimOptions o = *so;
    o.assemble = false;
    cnSimResult R;
    cnStatus st = cn_simulate(&v, &o, &R, diag);
    if (st == CN_OK) {
        pm->status = CN_STEP_STABLE;
        pm->failed_step = -1;
        for (int k = 0; k < 3; k++) pm->weakest_step[k] = -1;
        for (int s = 0; s < R.nsteps; s++) {
            cnStepResult *sr = &R.steps[s];
            if (sr->status != CN_STEP_STABLE) {
                if (pm->failed_step < 0) pm->status = sr->status, pm->failed_step = s;
                continue;
            }
            for (int k = 0; k < 3; k++) {
                cnStepMargin *w = &sr->margin[k];
                if (!w->computed) continue;
                if (pm->weakest_step[k] >= 0 && !cn_margin_weaker(k, w->at.value, pm->weakest[k].at.value)) continue;
                cn_check_result_free(&pm->weakest[k].at.collapse);
                pm->weakest[k] = *w;
                memset(&w->at.collapse, 0, sizeof w->at.collapse); /* moved */
                pm->weakest_step[k] = s;
            }
        }
        if (pm->failed_step >= 0) /* not stable after all: no margin */
            for (int k = 0; k < 3; k++) {
                cn_check_result_free(&pm->weakest[k].at.collapse);
                memset(&pm->weakest[k], 0, sizeof pm->weakest[k]);
                pm->weakest_step[k] = -1;
            }
        cn_sim_result_free(&R);
    }
    cn_free(steps);
    cn_free(grips);
    return st;
}

/* Is p to be ranked before q (kind index k)? Found before not found, then stronger (values
 * within tol of each other, relative, are a tie: the margins are found to that), then in the
 * planner's order. */
static bool before(int k, double tol, const cnPlanMargin *p, const cnPlanMargin *q) {
    bool ps = p->weakest_step[k] >= 0, qs = q->weakest_step[k] >= 0;
    if (ps != qs) return ps;
    if (ps) {
        double a = p->weakest[k].at.value, b = q->weakest[k].at.value;
        bool tie = a == b || (isfinite(a) && isfinite(b) && fabs(a - b) <= tol * fmax(fabs(a), fabs(b)));
        if (!tie) return cn_margin_weaker(k, b, a);
    }
    return p->sequence < q->sequence;
}

cnStatus cn_plan_margins(const cnAssembly *a, const cnPlanResult *r, const cnSimOptions *so, int rank,
                         cnPlanMargin **out, int *n, cnDiag *diag) {
    *out = NULL;
    *n = 0;
    if (!so || !so->margin)
        return cn_diag_set(diag, CN_ERR_INPUT, "margin", "plan margins need margin options (cnSimOptions.margin)");
    unsigned kinds = so->margin->kinds ? so->margin->kinds : CN_MARGIN_ALL;
    if ((rank != CN_MARGIN_FRICTION && rank != CN_MARGIN_TILT && rank != CN_MARGIN_LATERAL) || !(kinds & (unsigned)rank))
        return cn_diag_set(diag, CN_ERR_INPUT, "rank", "plans are ranked by a margin that is asked for");
    int count = r->nlisted < CN_PLAN_MARGIN_MAX ? r->nlisted : CN_PLAN_MARGIN_MAX;
    if (count <= 0) return CN_OK;
    cnPlanMargin *m = cn_calloc((size_t)count, sizeof(cnPlanMargin));
    if (!m) return cn_diag_oom(diag);
    cnStatus st = CN_OK;
    int done = 0;
    for (; done < count && st == CN_OK; done++) {
        m[done].sequence = done;
        st = one_sequence(a, &r->sequences[done], so, &m[done], diag);
    }
    if (st != CN_OK) {
        cn_plan_margins_free(m, done);
        return st;
    }
    int k = cn_margin_kind_index(rank);
    double tol = 2 * (so->margin->rel_tol > 0 ? so->margin->rel_tol : CN_SIM_MARGIN_REL_TOL);
    for (int i = 1; i < count; i++) { /* insertion sort: stable, and count is small */
        cnPlanMargin x = m[i];
        int j = i;
        for (; j > 0 && before(k, tol, &x, &m[j - 1]); j--) m[j] = m[j - 1];
        m[j] = x;
    }
    *out = m;
    *n = count;
    return CN_OK;
}

void cn_plan_margins_free(cnPlanMargin *m, int n) {
    for (int i = 0; m && i < n; i++)
        for (int k = 0; k < 3; k++) cn_check_result_free(&m[i].weakest[k].at.collapse);
    cn_free(m);
}
