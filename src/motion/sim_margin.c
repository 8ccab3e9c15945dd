/* The margins along a stable step (simulate --margin): cn_margin_with at some of its samples, each
 * verdict taken by the step's own rules. */
#include <math.h>
#include <string.h>

#include "margin_hook.h"
#include "sim_step.h"

/* One sample of a path, with the assembly's gravity or friction changed: a margin's verdict. */
typedef struct {
    Step *S;
    double s;
    bool leave;
    cnSamplePose posed;   /* the sample's check options for the static limits (margin_pose) */
} MarginAt;

/* The verdict of the sample at m->s on v (the assembly changed) by the step's own rules: eval,
 * the gripper's carrying decided afresh, the margin's check options and warm start. */
static cnStatus margin_verdict(void *ctx, const cnAssembly *v, const cnCheckOptions *co, cnCheckResult *r,
                               cnDiag *diag) {
    MarginAt *m = ctx;
    Step *S = m->S;
    memset(r, 0, sizeof *r);
    const cnAssembly *a0 = S->a;
    const cnSimOptions *o0 = S->o;
    cnWarmStart *w0 = S->warm;
    bool h0 = S->held, k0 = S->after_known;
    long b0 = S->later_budget;
    cnSimOptions o = *o0;
    o.check = *co;
    /* after_known off: the state after the step was proved as loaded, not as changed */
    S->a = v, S->o = &o, S->warm = co->warm, S->held = false, S->later_budget = 0, S->after_known = false;
    EvStatus ev = EV_STABLE;
    cnStatus st = cn_sm_eval(S, m->s, m->leave, true, r, &ev, diag);
    S->a = a0, S->o = o0, S->warm = w0, S->held = h0, S->later_budget = b0, S->after_known = k0;
    if (st != CN_OK) return st;
    /* the sample's outcome is the verdict: a part moving, a collision or an undecided search */
    if (ev == EV_UNDECIDED) r->verdict = CN_VERDICT_UNDECIDED, r->stable = false;
    else if (ev != EV_STABLE && r->verdict == CN_VERDICT_STABLE) r->verdict = CN_VERDICT_UNSTABLE, r->stable = false;
    return CN_OK;
}

/* The sample at m->s posed as its verdicts pose it (moving, held parts pressing nothing aside),
 * for the static limits that guide where a margin's verdicts look. */
static const cnCheckOptions *margin_pose(void *ctx, const cnCheckOptions *co) {
    MarginAt *m = ctx;
    bool h0 = m->S->held;
    m->S->held = false; /* as margin_verdict: the gripper's carrying decided afresh */
    cn_sm_pose_check(m->S, m->s, m->leave, co, &m->posed);
    m->S->held = h0;
    return &m->posed.check;
}

/* The margins of a stable step at up to margin_samples of its samples (evenly spread over them),
 * each sample's into R->samples, the weakest into out->margin. */
cnStatus cn_sm_step_margins(Step *S, cnSimResult *R, cnStepResult *out, cnDiag *diag) {
    int n = S->nrec, cap = S->o->margin_samples > 0 ? S->o->margin_samples : CN_SIM_MARGIN_SAMPLES;
    if (n == 0) return CN_OK;
    cnDiag own; /* where a margin's complaint is read */
    if (!diag) diag = &own;
    cnMarginOptions mo = *S->o->margin;
    if (!(mo.rel_tol > 0)) mo.rel_tol = CN_SIM_MARGIN_REL_TOL;
    mo.check = S->o->check;
    mo.check.motion_tol = 0; /* the margin's own threshold, as cn_margin */
    mo.check.warm = NULL;
    unsigned kinds = mo.kinds ? mo.kinds : CN_MARGIN_ALL;
    int taken = n < cap ? n : cap, last = -1;
    for (int i = 0; i < taken; i++) {
        int j = taken == 1 ? n - 1 : (int)lround((double)i * (n - 1) / (taken - 1));
        if (j == last) continue;
        last = j;
        MarginAt at = {.S = S, .s = S->rec_s[j], .leave = S->rec_leave[j]};
        cnMarginResult mr;
        cnStatus st = cn_margin_with(S->a, &mo, margin_verdict, margin_pose, &at, &mr, diag);
        if (st == CN_ERR_INPUT && !strcmp(diag->where, "pair") && (mo.pair[0] >= 0 || mo.pair[1] >= 0)) {
            /* the pair whose friction varies does not touch here (it came apart along the path, or
               a part of it is gone): no friction margin at this sample, the others as asked */
            cn_diag_clear(diag);
            cnMarginOptions rest = mo;
            rest.kinds = kinds & ~(unsigned)CN_MARGIN_FRICTION;
            if (!rest.kinds) continue;
            st = cn_margin_with(S->a, &rest, margin_verdict, margin_pose, &at, &mr, diag);
        }
        if (st != CN_OK) return st;
        int si = out->first_sample + j;
        cnMargin *ms[3] = {&mr.friction, &mr.tilt, &mr.lateral};
        for (int k = 0; k < 3; k++) {
            if (!(kinds & (1u << k)) || !ms[k]->computed) continue;
            cnStepMargin *w = &out->margin[k];
            R->samples[si].margin[k] = ms[k]->value;
            w->samples++;
            if (w->computed && !cn_margin_weaker(k, ms[k]->value, w->at.value)) continue;
            cn_check_result_free(&w->at.collapse);
            w->computed = true;
            w->at = *ms[k];
            memset(&ms[k]->collapse, 0, sizeof ms[k]->collapse); /* moved into w */
            w->sample = si;
            w->distance = R->samples[si].distance;
            w->step_time = R->samples[si].step_time;
            w->time = R->samples[si].time;
        }
        cn_margin_result_free(&mr);
    }
    return CN_OK;
}

/* Drop a step's margins (it did not stay stable after all). */
void cn_sm_drop_margins(cnSimResult *R, cnStepResult *out) {
    for (int k = 0; k < 3; k++) {
        cn_check_result_free(&out->margin[k].at.collapse);
        memset(&out->margin[k], 0, sizeof out->margin[k]);
    }
    for (int i = 0; i < out->nsamples; i++)
        for (int k = 0; k < 3; k++) R->samples[out->first_sample + i].margin[k] = NAN;
}
