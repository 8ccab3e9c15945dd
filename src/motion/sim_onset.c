/* Where a step starts to fail, and where the gripper starts or stops carrying a pushed part:
 * bisection between two samples. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "sim_step.h"

/* The length below which bisection stops: bisect_tol of the path. */
static double bisect_length(const Step *S) {
    return (S->o->bisect_tol > 0 ? S->o->bisect_tol : SIM_BISECT_TOL) * fmax(S->length, 1e-300);
}

/* Locate the onset between s_lo (stable) and s_hi (unstable or infeasible) by bisection. On
 * return *r holds the check at the onset (the first bad point found). An undecided point inside
 * counts with the good side: the onset reported is one proved bad. */
cnStatus cn_sm_bisect(Step *S, double s_lo, double s_hi, cnCheckResult *r, EvStatus *ev,
                       double *s_on, cnDiag *diag) {
    double tol = bisect_length(S);
    for (int it = 0; it < 200 && s_hi - s_lo > tol; it++) {
        double mid = 0.5 * (s_lo + s_hi);
        cnCheckResult m;
        EvStatus e;
        S->held = false; /* carried or not: decided at every point */
        cnStatus st = cn_sm_eval(S, mid, false, true, &m, &e, diag);
        if (st) return st;
        if (e == EV_STABLE || e == EV_UNDECIDED) {
            s_lo = mid;
            cn_check_result_free(&m);
        } else {
            s_hi = mid;
            cn_check_result_free(r);
            *r = m;
            *ev = e;
        }
    }
    *s_on = s_hi;
    return CN_OK;
}

/* Where the pushed part starts or stops needing the gripper, between s_lo (carried as was_held)
 * and s_hi (not): *at. A point that collides or is undecided counts with s_lo (it says nothing
 * about whether the part could rest). */
cnStatus cn_sm_bisect_carry(Step *S, double s_lo, double s_hi, bool was_held, double *at,
                             cnDiag *diag) {
    double tol = bisect_length(S);
    for (int it = 0; it < 200 && s_hi - s_lo > tol; it++) {
        double mid = 0.5 * (s_lo + s_hi);
        cnCheckResult m;
        EvStatus e;
        S->held = false;
        cnStatus rc = cn_sm_eval(S, mid, false, true, &m, &e, diag);
        if (rc) return rc;
        cn_check_result_free(&m);
        if (S->held == was_held || e == EV_INFEASIBLE || e == EV_UNDECIDED) s_lo = mid;
        else s_hi = mid;
    }
    *at = s_hi;
    return CN_OK;
}

/* One more interval in which the gripper carried the pushed part (t0 < t1, absolute times). */
cnStatus cn_sm_push_carry(cnStepResult *out, double t0, double t1, bool released,
                           const cnPlanStep *st) {
    /* an onset bisected to before the carrying began (both within one sample gap): the part
       was not carried before the step failed */
    if (t1 < t0) return CN_OK;
    cnCarryInterval *c = cn_realloc(out->carry, sizeof(cnCarryInterval) * (size_t)(out->ncarry + 1));
    if (!c) return CN_ERR_MEMORY;
    out->carry = c;
    int part = st->ngrip > 0 ? st->grip[st->ngrip - 1] : -1;
    c[out->ncarry++] = (cnCarryInterval){t0, t1, part, released};
    out->took_weight = true;
    out->took_weight_time = c[0].t0;
    out->took_weight_part = c[0].part;
    return CN_OK;
}
