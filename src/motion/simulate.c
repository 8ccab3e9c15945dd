/* Simulating a plan along its motion paths: the paper's Algorithm 1 (sec. III-B), with the
 * supports of sec. III-A (hold, push), subassemblies carried by contact (sec. VII), gripper
 * support bodies (Fig. 12) and the reversed plan as an assembly (sec. VIII).
 *
 * A step moves its parts along the path, sampled every dt at the given speed. At each sample
 * the moved parts are placed, contacts are found afresh, and the check decides whether every
 * other part stays put and every carried part keeps moving with the gripper. Between a stable
 * and an unstable sample the onset is located by bisection. A pushed part is carried by the
 * gripper only at samples where it could not rest by itself (the paper, sec. IV). Moving along or
 * against gravity is always held (Corollary 1). After the path the moved parts are taken away
 * (assembly: released in place), and that state must be stable too (Proposition 1). */
#include <math.h>
#include <string.h>
#include <time.h>

#include "sim_step.h"
#include "sim_planner.h"
#include "warm_start.h"

/* The search budget (LPs) of a step's samples after its first undecided one, when the options
 * give none or a larger one: the step is undecided already, and these samples can only prove it
 * unstable; so a long path of undecided samples costs a few times one search, not 64. */
#define CN_SIM_LATER_BUDGET 500

cnSimOptions cn_sim_options_default(void) {
    cnSimOptions o;
    memset(&o, 0, sizeof o);
    o.check = cn_check_options_default();
    /* Bisection probes tipping thresholds on purpose, where the LCP and the LP may disagree
     * within rounding: along a path the LCP decides (the paper's method); the LP still stands
     * in when the LCP fails. */
    o.check.lp_crosscheck = false;
    o.assemble = false;
    o.bisect_tol = SIM_BISECT_TOL;
    return o;
}

void cn_sim_result_free(cnSimResult *r) {
    if (!r) return;
    for (int i = 0; i < r->nsteps; i++) cn_step_result_free(&r->steps[i]);
    cn_free(r->steps);
    cn_free(r->plan_index);
    cn_free(r->samples);
    cn_free(r->contacts);
    memset(r, 0, sizeof *r);
}

/* The warm start of a simulation: the caller's (o->check.warm), else `local`, zeroed (record
 * only with o->cold); free `local` with cn_warm_start_release. */
static cnWarmStart *step_warm(const cnSimOptions *o, cnWarmStart *local) {
    memset(local, 0, sizeof *local);
    local->record_only = o->cold;
    return o->check.warm ? o->check.warm : local;
}

/* The distances at which step S is sampled (sorted), and which of them leave a junction: every
 * dt, every segment's end (where the part pauses) and the start of the next, and around each
 * contact event (cn_sm_event_samples, counted in out). */
static cnStatus step_samples(Step *S, cnStepResult *out, double **svp, unsigned char **lvp, int *nsampp) {
    const cnAssembly *a = S->a;
    double step_len = a->sim_speed * a->sim_dt;
    /* never more than CN_MAX_SAMPLES samples (the loader refuses plans that would need more;
     * the planner's own candidate paths are sampled more coarsely instead: bisection still
     * locates an onset to bisect_tol of the path) */
    int cap = S->o->max_samples > 0 ? S->o->max_samples : CN_MAX_SAMPLES;
    if (S->length / step_len > cap) step_len = S->length / cap;
    int ngrid = (int)ceil(S->length / step_len - 1e-9);
    int nsv = ngrid + 2 * S->nseg + 2, nsamp = 0;
    double *sv = cn_malloc(sizeof(double) * (size_t)nsv);
    unsigned char *lv = cn_calloc((size_t)nsv, 1);
    if (!sv || !lv) {
        cn_free(sv);
        cn_free(lv);
        return CN_ERR_MEMORY;
    }
    double acc = 0, same = CN_TOL_LENGTH_ZERO * S->length;
    int g = 0;
    for (int i = 0; i <= S->nseg; i++) {
        double end = i < S->nseg ? acc + S->seglen[i] : INFINITY;
        for (; g <= ngrid && fmin(g * step_len, S->length) < end - same; g++)
            sv[nsamp++] = fmin(g * step_len, S->length);
        if (i < S->nseg) {
            if (!(nsamp > 0 && fabs(sv[nsamp - 1] - end) <= same)) sv[nsamp++] = fmin(end, S->length);
            if (i + 1 < S->nseg) lv[nsamp] = 1, sv[nsamp++] = end; /* and leaving it */
            acc = end;
            while (g <= ngrid && fabs(fmin(g * step_len, S->length) - end) <= same) g++;
        }
    }
    if (cn_sm_event_samples(S, &sv, &lv, &nsamp, out) != CN_OK) {
        cn_free(sv);
        cn_free(lv);
        return CN_ERR_MEMORY;
    }
    *svp = sv, *lvp = lv, *nsampp = nsamp;
    return CN_OK;
}

/* Step S fails at distance s_on with the sample's check r (ev: unstable, infeasible or
 * undecided): its onset into out, r moved into it (or freed for a collision). */
static void step_fails(const Step *S, double s_on, cnCheckResult *r, EvStatus ev, cnStepResult *out) {
    const cnPlanStep *st = S->st;
    out->status = cn_sm_step_status(ev);
    out->has_onset = true;
    out->onset_distance = s_on;
    out->onset_step_time = s_on / S->a->sim_speed;
    out->onset_time = out->t0 + out->onset_step_time;
    cn_sm_set_onset_pose(S, s_on, out);
    if (ev == EV_INFEASIBLE) {
        int p1 = r->overlap.part1, p2 = r->overlap.part2;
        bool m1 = false;
        for (int i = 0; i < st->nmove; i++) m1 |= st->move[i] == p1;
        m1 |= p1 == st->gripper;
        out->blocked_part = m1 ? p1 : p2;
        out->blocking_part = m1 ? p2 : p1;
        out->depth = fmax(r->overlap.depth, 0);
        cn_check_result_free(r);
    } else {
        out->onset = *r;
    }
}

/* Whether the gripper carries the pushed part changed at the sample at s (the previous one at
 * s_prev, `bisect` when there is one): where it did, bisected; a carrying interval that ends is
 * recorded in out. A sample that collides, or whose friction verdict is undecided, says nothing
 * about whether the part could rest: the carrying state stays as it was (an interval that ends
 * at a collision is not a release). */
static cnStatus carry_changes(Step *S, cnStepResult *out, bool bisect, double s_prev, double s, EvStatus ev,
                              bool *carrying, double *carry_from, cnDiag *diag) {
    bool was_held = *carrying;
    bool known = ev != EV_INFEASIBLE && ev != EV_UNDECIDED;
    bool now = known ? S->held : was_held;
    if (now == was_held) return CN_OK;
    double at = 0, speed = S->a->sim_speed, t0 = out->t0;
    cnStatus rc;
    if (bisect && (rc = cn_sm_bisect_carry(S, s_prev, s, was_held, &at, diag))) return rc;
    if (now) *carry_from = at;
    else if (cn_sm_push_carry(out, t0 + *carry_from / speed, t0 + at / speed, true, S->st) != CN_OK)
        return cn_diag_oom(diag);
    *carrying = now;
    S->held = now;
    return CN_OK;
}

static cnStatus run_step(Step *S, cnSimResult *R, int k, double t0, cnStepResult *out,
                         cnDiag *diag) {
    const cnAssembly *a = S->a;
    const cnPlanStep *st = S->st;
    out->t0 = t0;
    out->length = S->length;
    out->sampled_to = S->length;
    out->blocking_part = out->blocked_part = -1;
    out->took_weight_part = -1;
    out->first_sample = R->nsamples;
    S->nrec = 0;
    for (int i = 0; i < st->nmove; i++) out->weight += cn_part_weight(a, st->move[i]);
    double speed = a->sim_speed;
    double *sv = NULL;
    unsigned char *lv = NULL;
    int nsamp = 0;
    if (step_samples(S, out, &sv, &lv, &nsamp) != CN_OK) return cn_diag_oom(diag);
    double s_prev = 0;
    cnStatus rc = CN_OK;
    /* the first undecided sample: the step is not stable, but a later sample may still be proved
     * unstable or infeasible, which is the more useful answer (unless stop_at_undecided) */
    cnCheckResult und;
    double s_und = 0, sampled_to = S->length;
    bool has_und = false;
    int n_und = 0;
    /* the gripper carries the pushed part from carry_from while carrying */
    bool carrying = false;
    double carry_from = 0;
    for (int j = 0; j < nsamp; j++) {
        double s = sv[j];
        bool leave = lv[j];
        cnCheckResult r;
        EvStatus ev;
        S->held = false; /* carried or not: decided at every sample */
        if ((rc = cn_sm_eval(S, s, leave, true, &r, &ev, diag))) goto fail;
        if ((rc = carry_changes(S, out, j > 0, s_prev, s, ev, &carrying, &carry_from, diag))) {
            cn_check_result_free(&r);
            goto fail;
        }
        if (cn_sm_record(R, k, t0, s, S, &r, ev, S->held || st->support == CN_SUPPORT_HOLD) != CN_OK ||
            cn_sm_remember(S, s, leave) != CN_OK) {
            cn_check_result_free(&r);
            rc = cn_diag_oom(diag);
            goto fail;
        }
        if (ev == EV_UNDECIDED && !S->o->stop_at_undecided) {
            if (!has_und) und = r, s_und = s, has_und = true, S->later_budget = CN_SIM_LATER_BUDGET;
            else cn_check_result_free(&r);
            s_prev = s;
            if (++n_und >= CN_SIM_MAX_UNDECIDED) { /* enough: the rest is not sampled */
                sampled_to = s;
                break;
            }
            continue;
        }
        if (ev != EV_STABLE) {
            if (has_und) cn_check_result_free(&und), has_und = false;
            double s_on = s;
            /* between the last good sample (which may be the start of this segment, left from a
             * junction) and this one: every point inside lies on this segment */
            if (j > 0 && s > s_prev && !leave && ev != EV_UNDECIDED &&
                (rc = cn_sm_bisect(S, s_prev, s, &r, &ev, &s_on, diag))) {
                cn_check_result_free(&r);
                goto fail;
            }
            if (ev == EV_INFEASIBLE && r.overlap.depth < 0) /* the surfaces meet a bit further */
                s_on = fmin(s_on - r.overlap.depth, S->length);
            step_fails(S, s_on, &r, ev, out);
            out->t1 = out->onset_time;
            out->nsamples = R->nsamples - out->first_sample;
            cn_free(sv);
            cn_free(lv);
            if (carrying && cn_sm_push_carry(out, t0 + carry_from / speed, out->t1, false, st) != CN_OK)
                return cn_diag_oom(diag);
            return CN_OK;
        }
        cn_check_result_free(&r);
        s_prev = s;
    }
    cn_free(sv);
    cn_free(lv);
    out->t1 = t0 + S->length / speed;
    out->nsamples = R->nsamples - out->first_sample;
    out->sampled_to = sampled_to;
    if (carrying && cn_sm_push_carry(out, t0 + carry_from / speed, out->t1, false, st) != CN_OK) {
        if (has_und) cn_check_result_free(&und);
        return cn_diag_oom(diag);
    }
    if (!has_und && S->o->margin && (rc = cn_sm_step_margins(S, R, out, diag)) != CN_OK) return rc;
    if (has_und) { /* nothing proved unstable, but not everything proved stable */
        out->status = CN_STEP_UNDECIDED;
        out->has_onset = true;
        out->onset_distance = s_und;
        out->onset_step_time = s_und / speed;
        out->onset_time = t0 + out->onset_step_time;
        cn_sm_set_onset_pose(S, s_und, out);
        out->onset = und;
    }
    return CN_OK;
fail:
    if (has_und) cn_check_result_free(&und);
    cn_free(sv);
    cn_free(lv);
    return rc;
}

/* The state after step k (disassembly: its parts taken away; assembly: released in place). */
static cnStatus after_step(Step *S, bool assemble, cnStepResult *out, cnDiag *diag) {
    const cnPlanStep *st = S->st;
    if (!assemble)
        for (int i = 0; i < st->nmove; i++) S->absent[st->move[i]] = 1;
    if (st->gripper >= 0) S->absent[st->gripper] = 1;
    cnCheckResult r;
    EvStatus ev;
    cnStatus rc = cn_sm_eval_static(S, &r, &ev, diag);
    if (rc) return rc;
    /* after a path that was stable, or undecided (a proved failure after it decides the step) */
    bool decides = out->status == CN_STEP_STABLE ||
                   (out->status == CN_STEP_UNDECIDED && ev != EV_STABLE && ev != EV_UNDECIDED);
    if (ev != EV_STABLE && decides) {
        if (out->status == CN_STEP_UNDECIDED) cn_check_result_free(&out->onset);
        out->status = ev == EV_UNDECIDED ? CN_STEP_UNDECIDED : CN_STEP_UNSTABLE;
        out->has_onset = true;
        out->onset_after = true;
        out->onset_time = out->t1;
        out->onset_step_time = out->t1 - out->t0;
        out->onset_distance = S->length;
        cn_sm_set_onset_pose(S, S->length, out);
        out->onset = r;
        return CN_OK;
    }
    cn_check_result_free(&r);
    return CN_OK;
}

cnStatus cn_simulate(const cnAssembly *a, const cnSimOptions *opt, cnSimResult *R, cnDiag *diag) {
    cnSimOptions o = opt ? *opt : cn_sim_options_default();
    memset(R, 0, sizeof *R);
    if (a->nsteps == 0)
        return cn_diag_set(diag, CN_ERR_INPUT, "plan",
                           "the file has no plan; add \"plan\": [{\"move\": \"A\", \"path\": "
                           "[[0, 5]]}, ...]");
    int n = a->nsteps;
    R->assemble = o.assemble;
    R->steps = cn_calloc((size_t)n, sizeof(cnStepResult));
    R->plan_index = cn_malloc(sizeof(int) * (size_t)n);
    Step S;
    memset(&S, 0, sizeof S);
    S.a = a;
    S.o = &o;
    S.nsteps = n;
    clock_gettime(CLOCK_MONOTONIC, &S.t0);
    cnWarmStart warm;
    S.warm = step_warm(&o, &warm);
    int maxseg = 1;
    for (int k = 0; k < n; k++) maxseg = a->plan[k].nseg > maxseg ? a->plan[k].nseg : maxseg;
    cnStatus rc = CN_OK;
    if (!R->steps || !R->plan_index || cn_sm_step_alloc(&S, maxseg) != 0) {
        rc = cn_diag_oom(diag);
        goto done;
    }
    R->nsteps = n;
    for (int i = 0; i < a->nparts; i++) S.absent[i] = a->parts[i].gripper_step >= 0;
    if (o.assemble) /* start from the disassembled state */
        for (int k = 0; k < n; k++)
            for (int i = 0; i < a->plan[k].nmove; i++) S.absent[a->plan[k].move[i]] = 1;
    R->stable = true;
    double t = 0;
    bool failed = false;
    for (int kk = 0; kk < n; kk++) {
        int k = o.assemble ? n - 1 - kk : kk;
        R->plan_index[kk] = k;
        cnStepResult *out = &R->steps[kk];
        const cnPlanStep *st = &a->plan[k];
        if (failed) {
            out->status = CN_STEP_SKIPPED;
            out->blocking_part = out->blocked_part = out->took_weight_part = -1;
            continue;
        }
        cn_sm_step_setup(&S, st, o.assemble);
        /* the state before the first step must be stable (Proposition 1) */
        if (kk == 0) {
            cnCheckResult r;
            EvStatus ev;
            rc = cn_sm_eval_static(&S, &r, &ev, diag);
            if (rc) goto done;
            if (ev != EV_STABLE) {
                out->status = cn_sm_step_status(ev);
                out->has_onset = true;
                out->onset = r;
                out->blocking_part = out->blocked_part = out->took_weight_part = -1;
                out->weight = 0;
                for (int i = 0; i < st->nmove; i++) out->weight += cn_part_weight(a, st->move[i]);
                R->stable = false;
                R->undecided = ev == EV_UNDECIDED;
                failed = true;
                continue;
            }
            cn_check_result_free(&r);
        }
        for (int i = 0; i < st->nmove; i++) S.absent[st->move[i]] = 0;
        if (st->gripper >= 0) S.absent[st->gripper] = 0;
        rc = run_step(&S, R, kk, t, out, diag);
        if (rc) goto done;
        if (out->status == CN_STEP_STABLE || out->status == CN_STEP_UNDECIDED) {
            rc = after_step(&S, o.assemble, out, diag);
            if (rc) goto done;
            if (out->status != CN_STEP_STABLE) cn_sm_drop_margins(R, out);
        } else if (st->gripper >= 0) {
            S.absent[st->gripper] = 1;
        }
        t = out->t1;
        if (out->status != CN_STEP_STABLE) {
            R->stable = false;
            R->undecided = out->status == CN_STEP_UNDECIDED;
            failed = true;
        }
    }
done:
    R->lcp_solves = S.warm->stats.solves;
    R->lcp_warm = S.warm->stats.warm_solves;
    R->lcp_pivots = S.warm->stats.pivots;
    R->lcp_seconds = S.warm->stats.seconds;
    R->lcp_warm_seconds = S.warm->stats.warm_seconds;
    cn_warm_start_release(&warm);
    cn_sm_step_free(&S);
    if (rc) cn_sim_result_free(R);
    return rc;
}

void cn_step_result_free(cnStepResult *r) {
    if (!r) return;
    cn_check_result_free(&r->onset);
    for (int k = 0; k < 3; k++) cn_check_result_free(&r->margin[k].at.collapse);
    cn_free(r->carry);
    memset(r, 0, sizeof *r);
}

cnStatus cn_simulate_step(const cnAssembly *a, const unsigned char *absent, const cnPlanStep *st,
                          const cnSimOptions *opt, cnStepResult *out, cnDiag *diag) {
    return cn_sm_simulate_step(a, absent, st, opt, false, out, diag);
}

cnStatus cn_sm_simulate_step(const cnAssembly *a, const unsigned char *absent, const cnPlanStep *st,
                             const cnSimOptions *opt, bool after_known, cnStepResult *out,
                             cnDiag *diag) {
    cnSimOptions o = opt ? *opt : cn_sim_options_default();
    o.margin = NULL; /* margins point into a plan's samples: cn_simulate's */
    memset(out, 0, sizeof *out);
    cnSimResult R;
    memset(&R, 0, sizeof R);
    Step S;
    memset(&S, 0, sizeof S);
    S.a = a;
    S.o = &o;
    S.st = st;
    S.after_known = after_known;
    S.nseg = st->nseg;
    cnWarmStart warm;
    S.warm = step_warm(&o, &warm);
    cnStatus rc = CN_OK;
    if (cn_sm_step_alloc(&S, st->nseg) != 0) {
        rc = cn_diag_oom(diag);
        goto done;
    }
    memcpy(S.absent, absent, (size_t)a->nparts);
    cn_sm_step_setup(&S, st, false);
    for (int i = 0; i < st->nmove; i++) S.absent[st->move[i]] = 0;
    if (st->gripper >= 0) S.absent[st->gripper] = 0;
    rc = run_step(&S, &R, 0, 0, out, diag);
    if (!rc && (out->status == CN_STEP_STABLE || out->status == CN_STEP_UNDECIDED) &&
        !(S.after_known && st->gripper < 0))
        rc = after_step(&S, false, out, diag);
    if (rc) cn_step_result_free(out); /* nothing for the caller to free on failure */
done:
    cn_warm_start_release(&warm);
    cn_free(R.samples);
    cn_free(R.contacts);
    cn_sm_step_free(&S);
    return rc;
}
