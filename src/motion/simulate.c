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

#include "collide.h"
#include "margin_hook.h"
#include "pieces.h"
#include "cairn/simulate.h"

/* Bisection stops when the interval is below this fraction of the path length. */
#define SIM_BISECT_TOL 1e-6
/* A path segment within this angle (sine) of gravity counts as vertical: always held. */
#define SIM_VERTICAL_SIN 1e-9
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

/* The work state of one step. */
typedef struct {
    const cnAssembly *a;
    const cnSimOptions *o;
    const cnPlanStep *st;
    int nseg;
    cnSegment *seg;       /* traversal segments (assembly: reversed and inverted) */
    double *seglen;       /* their lengths: the distance the moved parts' farthest point travels */
    cnPose start;         /* pose of the moved parts at distance 0 */
    double length;
    double com[3];        /* the moved parts' centre of mass as loaded (reported displacements) */
    unsigned char *absent;
    cnPose *pose;         /* per part */
    unsigned char *role;
    cnTwist *vel;         /* per part velocity (contact tie-breaking) */
    bool held;            /* push switched to hold */
    long later_budget;    /* after an undecided sample: the search budget of the later ones (0: the
                             options'), which are only looked at for a motion that is found */
    cnWarmStart *warm;    /* the previous sample's LCP basis, and the solve counters */
    struct timespec t0;   /* when the simulation started (progress) */
    double progress_at;   /* seconds into it of the last progress call */
    int nsteps;           /* steps of the plan (progress) */
    double *rec_s;        /* the step's recorded samples: distance, and leaving a junction */
    unsigned char *rec_leave;
    int nrec, caprec;
} Step;

/* Seconds between two progress calls, at least (cnSimOptions.progress_every). */
#define SIM_PROGRESS_SECONDS 0.25

static void progress(Step *S, const cnSimResult *R, int step) {
    if (!S->o->progress) return;
    double t = cn_seconds_since(&S->t0);
    if (t - S->progress_at < (S->o->progress_every > 0 ? S->o->progress_every : SIM_PROGRESS_SECONDS)) return;
    S->progress_at = t;
    S->o->progress(S->o->progress_ctx, step, S->nsteps, (long)R->nsamples, t);
}

/* Where the path is at one distance. */
typedef struct {
    cnPose pose;          /* of the moved parts */
    cnTwist unit;         /* their velocity at unit path speed (zero at the very start of a
                             zero-length path) */
    double dir[3];        /* a move: its unit direction; a turn: zero */
    bool turn;            /* the segment being travelled is a turn */
    bool paused;          /* at a segment's end (see path_at) */
} PathPoint;

/* The path at distance s: the pose, the velocity of the segment being travelled (at a junction:
 * the one that ends there, the part arriving, or with `leave` the one that starts there), and
 * whether the part pauses there: at a segment's end (within twice the contact tolerance) the
 * motion along it stops before the next begins, so a part placed at the end of a segment
 * arrives at its contacts instead of being driven into them. */
static void path_at(const Step *S, double s, bool leave, PathPoint *pp) {
    memset(pp, 0, sizeof *pp);
    pp->pose = S->start;
    double left = s, near = 2 * S->a->contact_tol;
    for (int i = 0; i < S->nseg; i++) {
        const cnSegment *sg = &S->seg[i];
        double L = S->seglen[i];
        /* leaving a junction: the next segment, from its start */
        bool here = leave ? left < L - near || i == S->nseg - 1 : left <= L || i == S->nseg - 1;
        double f = here ? fmin(left, L) : L;
        if (sg->kind == CN_SEGMENT_MOVE) {
            if (here) {
                cn_copy3(pp->dir, sg->move);
                cn_scale3(pp->dir, 1.0 / L);
                cn_copy3(pp->unit.v, pp->dir);
                for (int k = 0; k < 3; k++) pp->pose.t[k] += pp->dir[k] * f;
            } else {
                cn_add3(pp->pose.t, sg->move, pp->pose.t);
            }
        } else {
            cnPose turn = cn_segment_pose(sg, f / L);
            pp->pose = cn_pose_then(&pp->pose, &turn);
            if (here) {
                pp->turn = true;
                for (int k = 0; k < 3; k++) pp->unit.w[k] = sg->axis[k] * sg->angle / L;
                cn_copy3(pp->unit.about, sg->about);
            }
        }
        if (here) {
            pp->paused = L - f <= near;
            return;
        }
        left -= L;
    }
}

/* Corollary 1: along or against gravity the gripper always carries the weight. A turn is
 * always held: a gripper that only drives a part cannot turn it about a given axis. */
static bool always_held(const cnAssembly *a, const PathPoint *pp) {
    if (pp->turn) return true;
    double gd[3];
    cn_cross3(pp->dir, a->gravity, gd);
    return cn_norm3(gd) <= SIM_VERTICAL_SIN * cn_norm3(a->gravity);
}

/* The displacement reported for a pose of the moved parts: the translation itself for a move
 * (exact), else how far their centre of mass went. */
static void reported_disp(const Step *S, const cnPose *ps, double disp[3]) {
    if (cn_pose_is_translation(ps)) {
        cn_copy3(disp, ps->t);
        return;
    }
    double x[3];
    cn_pose_apply(ps, S->com, x);
    cn_sub3(x, S->com, disp);
}

static int step_alloc(Step *S, int maxseg) {
    int n = S->a->nparts;
    S->absent = cn_calloc((size_t)n + 1, 1);
    S->pose = cn_calloc((size_t)n + 1, sizeof(cnPose));
    S->role = cn_calloc((size_t)n + 1, 1);
    S->vel = cn_calloc((size_t)n + 1, sizeof(cnTwist));
    S->seg = cn_calloc((size_t)maxseg + 1, sizeof(cnSegment));
    S->seglen = cn_calloc((size_t)maxseg + 1, sizeof(double));
    return S->absent && S->pose && S->role && S->vel && S->seg && S->seglen ? 0 : -1;
}

static void step_free(Step *S) {
    cn_free(S->absent);
    cn_free(S->pose);
    cn_free(S->role);
    cn_free(S->vel);
    cn_free(S->seg);
    cn_free(S->seglen);
    cn_free(S->rec_s);
    cn_free(S->rec_leave);
}

/* The traversal of step st: its segments as given, or for an assembly reversed and inverted
 * from where disassembly leaves the parts; their lengths; the moved parts' centre of mass. */
static void step_setup(Step *S, const cnPlanStep *st, bool assemble) {
    const cnAssembly *a = S->a;
    S->st = st;
    S->held = false;
    S->nseg = st->nseg;
    S->start = cn_pose_identity();
    double *len = S->seglen;
    S->length = cn_path_length(a, st->move, st->nmove, st->seg, st->nseg, len);
    if (!assemble) {
        memcpy(S->seg, st->seg, sizeof(cnSegment) * (size_t)st->nseg);
    } else {
        /* inserted from where disassembly leaves it, along the path reversed */
        for (int i = 0; i < st->nseg; i++) {
            cnSegment sg = st->seg[i];
            if (sg.kind == CN_SEGMENT_MOVE) {
                cn_add3(S->start.t, sg.move, S->start.t);
            } else {
                cnPose turn = cn_segment_pose(&sg, 1.0);
                S->start = cn_pose_then(&S->start, &turn);
            }
        }
        for (int i = 0, j = st->nseg - 1; i < j; i++, j--) {
            double t = len[i];
            len[i] = len[j], len[j] = t;
        }
        for (int i = 0; i < st->nseg; i++) {
            cnSegment sg = st->seg[st->nseg - 1 - i];
            for (int d = 0; d < 3; d++) sg.move[d] = -sg.move[d];
            sg.angle = -sg.angle;
            S->seg[i] = sg;
        }
    }
    double m = 0;
    S->com[0] = S->com[1] = S->com[2] = 0;
    for (int i = 0; i < st->nmove; i++) {
        const cnPart *p = &a->parts[st->move[i]];
        for (int k = 0; k < 3; k++) S->com[k] += p->mass * p->com[k];
        m += p->mass;
    }
    if (m > 0) cn_scale3(S->com, 1.0 / m);
}

/* The warm start of a simulation: the caller's (o->check.warm), else `local`, zeroed (record
 * only with o->cold); free `local` with cn_warm_start_free. */
static cnWarmStart *step_warm(const cnSimOptions *o, cnWarmStart *local) {
    memset(local, 0, sizeof *local);
    local->record_only = o->cold;
    return o->check.warm ? o->check.warm : local;
}

static bool is_gripped(const cnPlanStep *st, int p) {
    for (int i = 0; i < st->ngrip; i++)
        if (st->grip[i] == p) return true;
    return false;
}

/* Moved parts farther than this many contact tolerances from every other part touch nothing. */
#define SIM_APART_TOLS 10

typedef enum { EV_STABLE = 0, EV_UNSTABLE = 1, EV_INFEASIBLE = 2, EV_UNDECIDED = 3 } EvStatus;

/* A sample's outcome from its check. Undecided (friction: a static solution, but the search for
 * a motion from rest ran out of budget) is not stable: the run stops there, never reads it as
 * stable. */
static EvStatus check_ev(const cnCheckResult *r) {
    if (r->infeasible) return EV_INFEASIBLE;
    if (r->nmoving > 0) return EV_UNSTABLE;
    return r->verdict == CN_VERDICT_UNDECIDED ? EV_UNDECIDED : EV_STABLE;
}

static cnStepStatus step_status(EvStatus ev) {
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

/* Evaluate the state at distance s. `moving`: the moved parts are in motion (false: at rest in
 * the state after the step, for the final check). Fills r (caller frees). */
static cnStatus eval(Step *S, double s, bool leave, bool moving, cnCheckResult *r, EvStatus *ev,
                     cnDiag *diag) {
    const cnAssembly *a = S->a;
    const cnPlanStep *st = S->st;
    PathPoint pp;
    path_at(S, s, leave, &pp);
    for (int i = 0; i < a->nparts; i++) S->pose[i] = cn_pose_identity();
    for (int i = 0; i < st->nmove; i++) S->pose[st->move[i]] = pp.pose;
    if (st->gripper >= 0) S->pose[st->gripper] = pp.pose;
    bool hold = st->support == CN_SUPPORT_HOLD || always_held(a, &pp) || S->held;
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
    /* The planner has proved the state after the step stable (after_known_stable): at a sample
     * where every moved part is held (gripped and held, no gripper body, nothing held still
     * besides) and touches nothing, the check is that state's check, so the sample is stable
     * without solving (its result then has no contacts). */
    if (S->o->after_known_stable && moving && hold && st->gripper < 0 && !st->still) {
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
    cnMotion motion;
    memset(&motion, 0, sizeof motion);
    motion.role = S->role;
    bool goes = moving && !pp.paused;
    for (int k = 0; k < 3; k++) {
        motion.twist.v[k] = goes ? pp.unit.v[k] * a->sim_speed : 0;
        motion.twist.w[k] = goes ? pp.unit.w[k] * a->sim_speed : 0;
        motion.twist.about[k] = pp.unit.about[k];
        motion.direction[k] = pp.dir[k];
    }
    motion.speed = goes ? a->sim_speed : 0;
    motion.dt = a->sim_dt;
    static const cnTwist rest = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    for (int i = 0; i < a->nparts; i++)
        S->vel[i] = (S->role[i] != CN_ROLE_FREE && S->role[i] != CN_ROLE_STILL) ? motion.twist : rest;
    cnContactQuery q = {S->pose, S->absent, S->vel};
    cnCheckOptions co = S->o->check;
    if (S->later_budget > 0 && (co.max_nodes <= 0 || co.max_nodes > S->later_budget))
        co.max_nodes = S->later_budget;
    co.query = &q;
    co.motion = &motion;
    co.overlap_is_result = true;
    co.keep_lcp = false;
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
        if (!saved) return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
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
            return eval(S, s, leave, moving, r, ev, diag);
        }
        if (alone.verdict == CN_VERDICT_UNDECIDED) {
            /* whether the gripper takes the weight is not known: unstable only if it is
             * unstable either way (the part held too), else undecided (the alone check) */
            cnCheckResult held;
            EvStatus eh;
            S->held = true;
            stt = eval(S, s, leave, moving, &held, &eh, diag);
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

static cnStatus record(cnSimResult *R, int step, double t0, double s, Step *S,
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
    path_at(S, s, false, &pp);
    sm->pose = pp.pose;
    sm->angle = cn_pose_angle(&pp.pose, a->dim);
    reported_disp(S, &pp.pose, sm->disp);
    sm->stable = ev == EV_STABLE;
    sm->held = held || always_held(a, &pp);
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

/* Locate the onset between s_lo (stable) and s_hi (unstable or infeasible) by bisection. On
 * return *r holds the check at the onset (the first bad point found). An undecided point inside
 * counts with the good side: the onset reported is one proved bad. */
static double bisect_length(const Step *S) {
    return (S->o->bisect_tol > 0 ? S->o->bisect_tol : SIM_BISECT_TOL) * fmax(S->length, 1e-300);
}

static cnStatus bisect(Step *S, double s_lo, double s_hi, cnCheckResult *r, EvStatus *ev,
                       double *s_on, cnDiag *diag) {
    double tol = bisect_length(S);
    for (int it = 0; it < 200 && s_hi - s_lo > tol; it++) {
        double mid = 0.5 * (s_lo + s_hi);
        cnCheckResult m;
        EvStatus e;
        S->held = false; /* carried or not: decided at every point */
        cnStatus st = eval(S, mid, false, true, &m, &e, diag);
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

/* The static check of the state after a step (or before the first): nothing moves. */
static cnStatus eval_static(Step *S, cnCheckResult *r, EvStatus *ev, cnDiag *diag) {
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

static void set_onset_pose(const Step *S, double s, cnStepResult *out) {
    PathPoint pp;
    path_at(S, s, false, &pp);
    out->onset_pose = pp.pose;
    out->onset_angle = cn_pose_angle(&pp.pose, S->a->dim);
    reported_disp(S, &pp.pose, out->onset_disp);
}

/* One more interval in which the gripper carried the pushed part (t0 < t1, absolute times). */
static cnStatus push_carry(cnStepResult *out, double t0, double t1, bool released,
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

/* Merge the contact events of every segment of the step (moves: cn_contact_events, turns:
 * cn_contact_events_turn) into the samples sv/lv (sorted): each event at it and just after it
 * (the touching point moved twice the contact tolerance, past the band in which a pair counts as
 * touching), which samples every stretch between two events with the contacts
 * it has (not just before: a vertex that grazes a corner would be caught closing on the face
 * it passes, within the band). *sv and *lv are reallocated; out counts the events. */
static cnStatus event_samples(Step *S, double **sv, unsigned char **lv, int *nsamp,
                              cnStepResult *out) {
    const cnAssembly *a = S->a;
    const cnPlanStep *st = S->st;
    int n = a->nparts;
    unsigned char *mov = cn_calloc((size_t)n + 1, 1), *still = cn_calloc((size_t)n + 1, 1);
    double *ev = cn_malloc(sizeof(double) * CN_SIM_MAX_EVENTS);
    double *extra = NULL;
    int nx = 0, capx = 0;
    cnStatus rc = CN_OK;
    if (!mov || !still || !ev) rc = CN_ERR_MEMORY;
    for (int i = 0; !rc && i < st->nmove; i++) mov[st->move[i]] = 1;
    for (int i = 0; !rc && i < n; i++)
        still[i] = !S->absent[i] && !mov[i] && a->parts[i].gripper_step < 0;
    double *rad = cn_malloc(sizeof(double) * CN_SIM_MAX_EVENTS);
    if (!rad) rc = CN_ERR_MEMORY;
    double acc = 0, delta = 2 * a->contact_tol;
    for (int i = 0; !rc && i < S->nseg; i++) {
        const cnSegment *sg = &S->seg[i];
        double L = S->seglen[i];
        if (L > 0 && (sg->kind == CN_SEGMENT_MOVE || sg->kind == CN_SEGMENT_TURN)) {
            PathPoint pp;
            path_at(S, acc, false, &pp);
            int dropped = 0, ne;
            /* a turn's events are angles: at distance f into it the turn is angle f / L (path_at),
               and a point at distance r from the axis has gone r / (L / |angle|) as far as the
               farthest one, so the sample just after an event moves its touching point 2 tol */
            double per_angle = 1;
            if (sg->kind == CN_SEGMENT_MOVE) {
                double u[3];
                cn_copy3(u, sg->move);
                cn_scale3(u, 1.0 / cn_norm3(u));
                ne = cn_contact_events(a, mov, still, &pp.pose, u, L, ev, CN_SIM_MAX_EVENTS, &dropped);
            } else {
                per_angle = L / fabs(sg->angle);
                ne = cn_contact_events_turn(a, mov, still, &pp.pose, sg->axis, sg->about, sg->angle,
                                            ev, rad, CN_SIM_MAX_EVENTS, &dropped);
            }
            if (ne < 0) {
                rc = CN_ERR_MEMORY;
                break;
            }
            out->nevents += ne;
            out->events_dropped += dropped;
            if (nx + 2 * ne > capx) {
                capx = 2 * (nx + 2 * ne) + 16;
                double *x = cn_realloc(extra, sizeof(double) * (size_t)capx);
                if (!x) {
                    rc = CN_ERR_MEMORY;
                    break;
                }
                extra = x;
            }
            for (int e = 0; e < ne; e++) {
                double at = ev[e] * per_angle, after = delta;
                if (sg->kind == CN_SEGMENT_TURN) /* a point on the axis: past it at the end */
                    after = rad[e] > 0 ? delta * per_angle / rad[e] : L;
                extra[nx++] = acc + fmin(at, L);
                extra[nx++] = acc + fmin(at + after, L);
            }
        }
        acc += L;
    }
    if (!rc && nx > 0) {
        /* sort the extra samples, then merge (the existing ones first at equal distances) */
        for (int i = 1; i < nx; i++) /* insertion sort: nearly sorted by construction */
            for (int j = i; j > 0 && extra[j] < extra[j - 1]; j--) {
                double t = extra[j];
                extra[j] = extra[j - 1], extra[j - 1] = t;
            }
        int m = *nsamp;
        double *ns = cn_malloc(sizeof(double) * (size_t)(m + nx));
        unsigned char *nl = cn_calloc((size_t)(m + nx), 1);
        if (!ns || !nl) {
            cn_free(ns);
            cn_free(nl);
            rc = CN_ERR_MEMORY;
        } else {
            double same = 1e-12 * fmax(S->length, 1e-300);
            int i = 0, j = 0, k = 0;
            while (i < m || j < nx) {
                if (j >= nx || (i < m && (*sv)[i] <= extra[j] + same)) {
                    ns[k] = (*sv)[i], nl[k] = (*lv)[i], k++;
                    /* an extra sample at the same distance as this one adds nothing */
                    while (j < nx && fabs(extra[j] - (*sv)[i]) <= same) j++;
                    i++;
                } else {
                    if (k == 0 || extra[j] - ns[k - 1] > same) ns[k] = extra[j], nl[k] = 0, k++;
                    j++;
                }
            }
            cn_free(*sv);
            cn_free(*lv);
            *sv = ns, *lv = nl, *nsamp = k;
        }
    }
    cn_free(mov);
    cn_free(still);
    cn_free(ev);
    cn_free(rad);
    cn_free(extra);
    return rc;
}

/* Where the pushed part starts or stops needing the gripper, between s_lo (carried as was_held)
 * and s_hi (not): *at. A point that collides or is undecided counts with s_lo (it says nothing
 * about whether the part could rest). */
static cnStatus bisect_carry(Step *S, double s_lo, double s_hi, bool was_held, double *at,
                             cnDiag *diag) {
    double tol = bisect_length(S);
    for (int it = 0; it < 200 && s_hi - s_lo > tol; it++) {
        double mid = 0.5 * (s_lo + s_hi);
        cnCheckResult m;
        EvStatus e;
        S->held = false;
        cnStatus rc = eval(S, mid, false, true, &m, &e, diag);
        if (rc) return rc;
        cn_check_result_free(&m);
        if (S->held == was_held || e == EV_INFEASIBLE || e == EV_UNDECIDED) s_lo = mid;
        else s_hi = mid;
    }
    *at = s_hi;
    return CN_OK;
}

/* Keep a recorded sample's place on the path (the margins are taken at some of them). */
static cnStatus remember(Step *S, double s, bool leave) {
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

/* One sample of a path, with the assembly's gravity or friction changed: a margin's verdict. */
typedef struct {
    Step *S;
    double s;
    bool leave;
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
    bool h0 = S->held;
    long b0 = S->later_budget;
    cnSimOptions o = *o0;
    o.check = *co;
    o.after_known_stable = false; /* that state's verdict is as loaded, not as changed */
    S->a = v, S->o = &o, S->warm = co->warm, S->held = false, S->later_budget = 0;
    EvStatus ev = EV_STABLE;
    cnStatus st = eval(S, m->s, m->leave, true, r, &ev, diag);
    S->a = a0, S->o = o0, S->warm = w0, S->held = h0, S->later_budget = b0;
    if (st != CN_OK) return st;
    /* the sample's outcome is the verdict: a part moving, a collision or an undecided search */
    if (ev == EV_UNDECIDED) r->verdict = CN_VERDICT_UNDECIDED, r->stable = false;
    else if (ev != EV_STABLE && r->verdict == CN_VERDICT_STABLE) r->verdict = CN_VERDICT_UNSTABLE, r->stable = false;
    return CN_OK;
}

/* The margins of a stable step at up to margin_samples of its samples (evenly spread over them),
 * each sample's into R->samples, the weakest into out->margin. */
static cnStatus step_margins(Step *S, cnSimResult *R, cnStepResult *out, cnDiag *diag) {
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
        MarginAt at = {S, S->rec_s[j], S->rec_leave[j]};
        cnMarginResult mr;
        cnStatus st = cn_margin_with(S->a, &mo, margin_verdict, &at, &mr, diag);
        if (st == CN_ERR_INPUT && !strcmp(diag->where, "pair") && (mo.pair[0] >= 0 || mo.pair[1] >= 0)) {
            /* the pair whose friction varies does not touch here (it came apart along the path, or
               a part of it is gone): no friction margin at this sample, the others as asked */
            cn_diag_clear(diag);
            cnMarginOptions rest = mo;
            rest.kinds = kinds & ~(unsigned)CN_MARGIN_FRICTION;
            if (!rest.kinds) continue;
            st = cn_margin_with(S->a, &rest, margin_verdict, &at, &mr, diag);
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
static void drop_margins(cnSimResult *R, cnStepResult *out) {
    for (int k = 0; k < 3; k++) {
        cn_check_result_free(&out->margin[k].at.collapse);
        memset(&out->margin[k], 0, sizeof out->margin[k]);
    }
    for (int i = 0; i < out->nsamples; i++)
        for (int k = 0; k < 3; k++) R->samples[out->first_sample + i].margin[k] = NAN;
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
    double speed = a->sim_speed, dt = a->sim_dt;
    double step_len = speed * dt;
    /* never more than CN_MAX_SAMPLES samples (the loader refuses plans that would need more;
     * the planner's own candidate paths are sampled more coarsely instead: bisection still
     * locates an onset to bisect_tol of the path) */
    int cap = S->o->max_samples > 0 ? S->o->max_samples : CN_MAX_SAMPLES;
    if (S->length / step_len > cap) step_len = S->length / cap;
    /* samples every dt, plus every segment's end (where the part pauses) */
    int ngrid = (int)ceil(S->length / step_len - 1e-9);
    int nsv = ngrid + 2 * S->nseg + 2, nsamp = 0;
    double *sv = cn_malloc(sizeof(double) * (size_t)nsv);
    unsigned char *lv = cn_calloc((size_t)nsv, 1);
    if (!sv || !lv) {
        cn_free(sv);
        cn_free(lv);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
    {
        double acc = 0;
        int g = 0;
        for (int i = 0; i <= S->nseg; i++) {
            double end = i < S->nseg ? acc + S->seglen[i] : INFINITY;
            for (; g <= ngrid && fmin(g * step_len, S->length) < end - CN_TOL_LENGTH_ZERO * S->length; g++)
                sv[nsamp++] = fmin(g * step_len, S->length);
            if (i < S->nseg) {
                if (!(nsamp > 0 && fabs(sv[nsamp - 1] - end) <= CN_TOL_LENGTH_ZERO * S->length)) sv[nsamp++] = fmin(end, S->length);
                if (i + 1 < S->nseg) lv[nsamp] = 1, sv[nsamp++] = end; /* and leaving it */
                acc = end;
                while (g <= ngrid && fabs(fmin(g * step_len, S->length) - end) <= CN_TOL_LENGTH_ZERO * S->length) g++;
            }
        }
    }
    if (event_samples(S, &sv, &lv, &nsamp, out) != CN_OK) {
        cn_free(sv);
        cn_free(lv);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
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
        bool was_held = carrying;
        S->held = false; /* carried or not: decided at every sample */
        if ((rc = eval(S, s, leave, true, &r, &ev, diag))) goto fail;
        /* a sample that collides, or whose friction verdict is undecided, says nothing about
           whether the part could rest: the carrying state stays as it was (an interval that
           ends at a collision is not a release) */
        bool known = ev != EV_INFEASIBLE && ev != EV_UNDECIDED;
        bool now = known ? S->held : was_held;
        if (now != was_held) {
            double at = 0;
            if (j > 0 && (rc = bisect_carry(S, s_prev, s, was_held, &at, diag))) {
                cn_check_result_free(&r);
                goto fail;
            }
            if (now) carry_from = at;
            else if (push_carry(out, t0 + carry_from / speed, t0 + at / speed, true, st) != CN_OK) {
                cn_check_result_free(&r);
                rc = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
                goto fail;
            }
            carrying = now;
            S->held = now;
        }
        if (record(R, k, t0, s, S, &r, ev, S->held || st->support == CN_SUPPORT_HOLD) != CN_OK ||
            remember(S, s, leave) != CN_OK) {
            cn_check_result_free(&r);
            rc = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
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
                (rc = bisect(S, s_prev, s, &r, &ev, &s_on, diag))) {
                cn_check_result_free(&r);
                goto fail;
            }
            if (ev == EV_INFEASIBLE && r.overlap.depth < 0) /* the surfaces meet a bit further */
                s_on = fmin(s_on - r.overlap.depth, S->length);
            out->status = step_status(ev);
            out->has_onset = true;
            out->onset_distance = s_on;
            out->onset_step_time = s_on / speed;
            out->onset_time = t0 + out->onset_step_time;
            set_onset_pose(S, s_on, out);
            if (ev == EV_INFEASIBLE) {
                int p1 = r.overlap.part1, p2 = r.overlap.part2;
                bool m1 = false;
                for (int i = 0; i < st->nmove; i++) m1 |= st->move[i] == p1;
                m1 |= p1 == st->gripper;
                out->blocked_part = m1 ? p1 : p2;
                out->blocking_part = m1 ? p2 : p1;
                out->depth = fmax(r.overlap.depth, 0);
                cn_check_result_free(&r);
            } else {
                out->onset = r;
            }
            out->t1 = out->onset_time;
            out->nsamples = R->nsamples - out->first_sample;
            cn_free(sv);
            cn_free(lv);
            if (carrying && push_carry(out, t0 + carry_from / speed, out->t1, false, st) != CN_OK)
                return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
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
    if (carrying && push_carry(out, t0 + carry_from / speed, out->t1, false, st) != CN_OK) {
        if (has_und) cn_check_result_free(&und);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
    if (!has_und && S->o->margin && (rc = step_margins(S, R, out, diag)) != CN_OK) return rc;
    if (has_und) { /* nothing proved unstable, but not everything proved stable */
        out->status = CN_STEP_UNDECIDED;
        out->has_onset = true;
        out->onset_distance = s_und;
        out->onset_step_time = s_und / speed;
        out->onset_time = t0 + out->onset_step_time;
        set_onset_pose(S, s_und, out);
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
    cnStatus rc = eval_static(S, &r, &ev, diag);
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
        set_onset_pose(S, S->length, out);
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
    if (!R->steps || !R->plan_index || step_alloc(&S, maxseg) != 0) {
        rc = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
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
        step_setup(&S, st, o.assemble);
        /* the state before the first step must be stable (Proposition 1) */
        if (kk == 0) {
            cnCheckResult r;
            EvStatus ev;
            rc = eval_static(&S, &r, &ev, diag);
            if (rc) goto done;
            if (ev != EV_STABLE) {
                out->status = step_status(ev);
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
            if (out->status != CN_STEP_STABLE) drop_margins(R, out);
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
    R->lcp_solves = S.warm->solves;
    R->lcp_warm = S.warm->warm_solves;
    R->lcp_pivots = S.warm->pivots;
    R->lcp_seconds = S.warm->seconds;
    R->lcp_warm_seconds = S.warm->warm_seconds;
    cn_warm_start_free(&warm);
    step_free(&S);
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
    S.nseg = st->nseg;
    cnWarmStart warm;
    S.warm = step_warm(&o, &warm);
    cnStatus rc = CN_OK;
    if (step_alloc(&S, st->nseg) != 0) {
        rc = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
        goto done;
    }
    memcpy(S.absent, absent, (size_t)a->nparts);
    step_setup(&S, st, false);
    for (int i = 0; i < st->nmove; i++) S.absent[st->move[i]] = 0;
    if (st->gripper >= 0) S.absent[st->gripper] = 0;
    rc = run_step(&S, &R, 0, 0, out, diag);
    if (!rc && (out->status == CN_STEP_STABLE || out->status == CN_STEP_UNDECIDED) &&
        !(o.after_known_stable && st->gripper < 0))
        rc = after_step(&S, false, out, diag);
    if (rc) cn_step_result_free(out); /* nothing for the caller to free on failure */
done:
    cn_warm_start_free(&warm);
    cn_free(R.samples);
    cn_free(R.contacts);
    step_free(&S);
    return rc;
}
