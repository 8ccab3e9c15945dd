/* One sample of a step: its check with the parts placed and their roles (held, pushed, carried,
 * still), the gripper taking a pushed part's weight where it could not rest by itself, and the
 * sample recorded into the result. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "sim_step.h"

/* Seconds between two progress calls, at least (cnSimOptions.progress_every). */
#define SIM_PROGRESS_SECONDS 0.25

static void progress(Step *S, const cnSimResult *R, int step) {
    if (!S->o->progress) return;
    double t = cn_seconds_since(&S->t0);
    if (t - S->progress_at < (S->o->progress_every > 0 ? S->o->progress_every : SIM_PROGRESS_SECONDS)) return;
    S->progress_at = t;
    S->o->progress(S->o->progress_ctx, step, S->nsteps, (long)R->nsamples, t);
}

static bool is_gripped(const cnPlanStep *st, int p) {
    for (int i = 0; i < st->ngrip; i++)
        if (st->grip[i] == p) return true;
    return false;
}

/* Moved parts farther than this many contact tolerances from every other part touch nothing. */
#define SIM_APART_TOLS 10

/* A sample's outcome from its check. Undecided (friction: a static solution, but the search for
 * a motion from rest ran out of budget) is not stable: the run stops there, never reads it as
 * stable. */
static EvStatus check_ev(const cnCheckResult *r) {
    if (r->infeasible) return EV_INFEASIBLE;
    if (r->nmoving > 0) return EV_UNSTABLE;
    return r->verdict == CN_VERDICT_UNDECIDED ? EV_UNDECIDED : EV_STABLE;
}

cnStepStatus cn_sm_step_status(EvStatus ev) {
    switch (ev) {
    case EV_STABLE: return CN_STEP_STABLE;
    case EV_INFEASIBLE: return CN_STEP_INFEASIBLE;
    case EV_UNDECIDED: return CN_STEP_UNDECIDED;
    case EV_UNSTABLE: break;
    }
    return CN_STEP_UNSTABLE;
}

/* Are the moved parts, at their poses in S->pose, farther than a few contact tolerances from
 * every other part present (bounding boxes apart)? Then no contact touches them. */
static bool apart_from_rest(const Step *S) {
    const cnAssembly *a = S->a;
    const cnPlanStep *st = S->st;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < st->nmove; i++) {
        const cnPart *p = &a->parts[st->move[i]];
        for (int k = 0; k < p->npieces; k++)
            for (int v = 0; v < p->pieces[k].nverts; v++) {
                double x[3];
                cn_pose_apply(&S->pose[st->move[i]], p->pieces[k].verts[v], x);
                for (int d = 0; d < 3; d++) lo[d] = fmin(lo[d], x[d]), hi[d] = fmax(hi[d], x[d]);
            }
    }
    double m = SIM_APART_TOLS * a->contact_tol;
    for (int j = 0; j < a->nparts; j++) {
        if (S->absent[j] || S->role[j] != CN_ROLE_FREE) continue;
        if (a->parts[j].gripper_step >= 0) continue;
        const cnPart *p = &a->parts[j];
        double plo[3] = {INFINITY, INFINITY, INFINITY}, phi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int k = 0; k < p->npieces; k++)
            for (int v = 0; v < p->pieces[k].nverts; v++)
                for (int d = 0; d < 3; d++)
                    plo[d] = fmin(plo[d], p->pieces[k].verts[v][d]), phi[d] = fmax(phi[d], p->pieces[k].verts[v][d]);
        bool sep = false;
        for (int d = 0; d < a->dim && !sep; d++) sep = plo[d] > hi[d] + m || lo[d] > phi[d] + m;
        if (!sep) return false;
    }
    return true;
}

/* Pose the sample at distance s (moving: the moved parts in motion) in S's pose, role and
 * velocity arrays, and its check options in sp: base with the sample's query and motion (which
 * point into sp and S). Returns whether the moved parts are held. */
static bool pose_sample(Step *S, double s, bool leave, bool moving, const cnCheckOptions *base,
                        cnSamplePose *sp) {
    const cnAssembly *a = S->a;
    const cnPlanStep *st = S->st;
    PathPoint pp;
    cn_sm_path_at(S, s, leave, &pp);
    for (int i = 0; i < a->nparts; i++) S->pose[i] = cn_pose_identity();
    for (int i = 0; i < st->nmove; i++) S->pose[st->move[i]] = pp.pose;
    if (st->gripper >= 0) S->pose[st->gripper] = pp.pose;
    bool hold = st->support == CN_SUPPORT_HOLD || cn_sm_always_held(a, &pp) || S->held;
    memset(S->role, CN_ROLE_FREE, (size_t)a->nparts);
    for (int i = 0; st->still && i < a->nparts; i++)
        if (st->still[i]) S->role[i] = CN_ROLE_STILL;
    if (moving) {
        for (int i = 0; i < st->nmove; i++) {
            int p = st->move[i];
            S->role[p] = is_gripped(st, p) ? (hold ? CN_ROLE_HELD : CN_ROLE_PUSHED) : CN_ROLE_CARRIED;
        }
        if (st->gripper >= 0) S->role[st->gripper] = CN_ROLE_HELD;
    }
    cnMotion *motion = &sp->motion;
    memset(motion, 0, sizeof *motion);
    motion->role = S->role;
    bool goes = moving && !pp.paused;
    for (int k = 0; k < 3; k++) {
        motion->twist.v[k] = goes ? pp.unit.v[k] * a->sim_speed : 0;
        motion->twist.w[k] = goes ? pp.unit.w[k] * a->sim_speed : 0;
        motion->twist.about[k] = pp.unit.about[k];
        motion->direction[k] = pp.dir[k];
    }
    motion->speed = goes ? a->sim_speed : 0;
    motion->dt = a->sim_dt;
    static const cnTwist rest = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int i = 0; i < a->nparts; i++)
        S->vel[i] = (S->role[i] != CN_ROLE_FREE && S->role[i] != CN_ROLE_STILL) ? motion->twist : rest;
    sp->query = (cnContactQuery){S->pose, S->absent, S->vel};
    sp->check = *base;
    sp->check.query = &sp->query;
    sp->check.motion = motion;
    sp->check.overlap_is_result = true;
    sp->check.keep_lcp = false;
    return hold;
}

void cn_sm_pose_check(Step *S, double s, bool leave, const cnCheckOptions *base, cnSamplePose *sp) {
    pose_sample(S, s, leave, true, base, sp);
}

/* Evaluate the state at distance s. `moving`: the moved parts are in motion (false: at rest in
 * the state after the step, for the final check). Fills r (caller frees). */
cnStatus cn_sm_eval(Step *S, double s, bool leave, bool moving, cnCheckResult *r, EvStatus *ev,
                     cnDiag *diag) {
    const cnAssembly *a = S->a;
    const cnPlanStep *st = S->st;
    cnSamplePose sp;
    bool hold = pose_sample(S, s, leave, moving, &S->o->check, &sp);
    /* The planner has proved the state after the step stable (S->after_known): at a sample
     * where every moved part is held (gripped and held, no gripper body, nothing held still
     * besides) and touches nothing, the check is that state's check, so the sample is stable
     * without solving (its result then has no contacts). */
    if (S->after_known && moving && hold && st->gripper < 0 && !st->still) {
        bool all = true;
        for (int i = 0; i < st->nmove && all; i++) all = is_gripped(st, st->move[i]);
        if (all && apart_from_rest(S)) {
            memset(r, 0, sizeof *r);
            r->stable = true;
            r->verdict = CN_VERDICT_STABLE;
            *ev = EV_STABLE;
            return CN_OK;
        }
    }
    cnCheckOptions co = sp.check;
    if (S->later_budget > 0 && (co.max_nodes <= 0 || co.max_nodes > S->later_budget))
        co.max_nodes = S->later_budget;
    co.warm = S->warm;
    cnStatus stt = cn_check(a, &co, r, diag);
    if (stt) return stt;
    if (r->infeasible) {
        *ev = EV_INFEASIBLE;
        return CN_OK;
    }
    /* A pushed part that would fall or tip by itself (with every other part held still): the
     * gripper takes its weight from now on. A pushed part that only rides along with parts
     * that tip under it is part of that instability. */
    bool pushed_moves = false;
    for (int i = 0; i < r->nmoving; i++) pushed_moves |= S->role[r->moving[i]] == CN_ROLE_PUSHED;
    if (moving && !hold && pushed_moves) {
        unsigned char *saved = cn_malloc((size_t)a->nparts);
        if (!saved) return cn_diag_oom(diag);
        memcpy(saved, S->role, (size_t)a->nparts);
        for (int i = 0; i < a->nparts; i++)
            if (S->role[i] == CN_ROLE_FREE && !a->parts[i].fixed) S->role[i] = CN_ROLE_STILL;
        cnCheckResult alone;
        co.warm = NULL; /* another problem: keep the path's basis */
        stt = cn_check(a, &co, &alone, diag);
        memcpy(S->role, saved, (size_t)a->nparts);
        cn_free(saved);
        if (stt) return stt;
        bool falls = false;
        for (int i = 0; i < alone.nmoving; i++)
            falls |= S->role[alone.moving[i]] == CN_ROLE_PUSHED;
        if (falls) {
            cn_check_result_free(&alone);
            S->held = true;
            cn_check_result_free(r);
            return cn_sm_eval(S, s, leave, moving, r, ev, diag);
        }
        if (alone.verdict == CN_VERDICT_UNDECIDED) {
            /* whether the gripper takes the weight is not known: unstable only if it is
             * unstable either way (the part held too), else undecided (the alone check) */
            cnCheckResult held;
            EvStatus eh;
            S->held = true;
            stt = cn_sm_eval(S, s, leave, moving, &held, &eh, diag);
            S->held = false;
            if (!stt) cn_check_result_free(&held);
            if (stt || eh == EV_UNSTABLE || eh == EV_INFEASIBLE) {
                cn_check_result_free(&alone);
                if (stt) return stt;
                *ev = EV_UNSTABLE;
                return CN_OK;
            }
            cn_check_result_free(r);
            *r = alone;
            *ev = EV_UNDECIDED;
            return CN_OK;
        }
        cn_check_result_free(&alone);
    }
    *ev = check_ev(r);
    return CN_OK;
}

/* The static check of the state after a step (or before the first): nothing moves. */
cnStatus cn_sm_eval_static(Step *S, cnCheckResult *r, EvStatus *ev, cnDiag *diag) {
    const cnAssembly *a = S->a;
    for (int i = 0; i < a->nparts; i++) S->pose[i] = cn_pose_identity();
    memset(S->role, CN_ROLE_FREE, (size_t)a->nparts);
    /* parts held in place by the other hand stay so */
    cnMotion still;
    memset(&still, 0, sizeof still);
    still.role = S->role;
    still.dt = a->sim_dt;
    bool any_still = false;
    for (int i = 0; S->st->still && i < a->nparts; i++)
        if (S->st->still[i]) S->role[i] = CN_ROLE_STILL, any_still = true;
    cnContactQuery q = {S->pose, S->absent, NULL};
    cnCheckOptions co = S->o->check;
    co.query = &q;
    co.motion = any_still ? &still : NULL;
    co.overlap_is_result = true;
    co.warm = NULL; /* at rest, not a sample of the path */
    /* a state at rest is check's question, not a probe of a threshold: decided as check decides
     * it (frictionless, the LP cross-checks the LCP), so that the two never disagree on it */
    co.lp_crosscheck = true;
    cnStatus st = cn_check(a, &co, r, diag);
    if (st) return st;
    *ev = check_ev(r);
    return CN_OK;
}

cnStatus cn_sm_record(cnSimResult *R, int step, double t0, double s, Step *S,
                       const cnCheckResult *r, EvStatus ev, bool held) {
    const cnAssembly *a = S->a;
    progress(S, R, step);
    if (R->nsamples % 64 == 0) {
        cnSimSample *ns = cn_realloc(R->samples, sizeof(cnSimSample) * (size_t)(R->nsamples + 64));
        if (!ns) return CN_ERR_MEMORY;
        R->samples = ns;
    }
    cnSimSample *sm = &R->samples[R->nsamples++];
    memset(sm, 0, sizeof *sm);
    sm->step = step;
    sm->step_time = s / a->sim_speed;
    sm->time = t0 + sm->step_time;
    sm->distance = s;
    PathPoint pp;
    cn_sm_path_at(S, s, false, &pp);
    sm->pose = pp.pose;
    sm->angle = cn_pose_angle(&pp.pose, a->dim);
    cn_sm_reported_disp(S, &pp.pose, sm->disp);
    sm->stable = ev == EV_STABLE;
    sm->held = held || cn_sm_always_held(a, &pp);
    for (int k = 0; k < 3; k++) sm->margin[k] = NAN;
    sm->first = R->ncontacts;
    if (ev == EV_INFEASIBLE || !r->contact) return CN_OK;
    for (int c = 0; c < r->contacts.count; c++) {
        if (R->ncontacts == R->capcontacts) {
            int nc = R->capcontacts ? 2 * R->capcontacts : 256;
            cnSimContact *n = cn_realloc(R->contacts, sizeof(cnSimContact) * (size_t)nc);
            if (!n) return CN_ERR_MEMORY;
            R->contacts = n;
            R->capcontacts = nc;
        }
        const cnContact *ct = &r->contacts.items[c];
        cnSimContact *x = &R->contacts[R->ncontacts++];
        x->id = ct->id;
        x->body1 = ct->body1;
        x->body2 = ct->body2;
        x->vertex = ct->vertex;
        cn_copy3(x->point, ct->point);
        cn_copy3(x->normal, ct->normal);
        x->force = r->contact[c].normal_force;
        x->motion = r->contact[c].separation;
        x->separates = r->contact[c].separates;
        x->slides = r->contact[c].slides;
        sm->count++;
    }
    return CN_OK;
}

/* Keep a recorded sample's place on the path (the margins are taken at some of them). */
cnStatus cn_sm_remember(Step *S, double s, bool leave) {
    if (S->nrec == S->caprec) {
        int n = S->caprec ? 2 * S->caprec : 64;
        double *ns = cn_realloc(S->rec_s, sizeof(double) * (size_t)n);
        if (ns) S->rec_s = ns;
        unsigned char *nl = cn_realloc(S->rec_leave, (size_t)n);
        if (nl) S->rec_leave = nl;
        if (!ns || !nl) return CN_ERR_MEMORY;
        S->caprec = n;
    }
    S->rec_s[S->nrec] = s;
    S->rec_leave[S->nrec++] = leave;
    return CN_OK;
}
