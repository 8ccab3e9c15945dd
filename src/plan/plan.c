/* Planning: stable disassembly sequences, their paths, and subassemblies (paper sec. III-A, V,
 * VI, VII; the AND/OR graph of de Mello and Sanderson).
 *
 * States are the sets of free parts that remain (a bit mask; fixed parts always remain). Each
 * state's stability is checked once: a state that is not stable ends every sequence through it
 * (Proposition 1). From a stable state, each remaining part is removed along each of its
 * candidate paths (the file's named paths, or straight lines along representative free
 * directions of the non-directional blocking graph, "up" first), each such transition simulated
 * along its path (Algorithm 1). The number of stable sequences from a state is the sum over its
 * stable transitions of that of the state they lead to, memoised.
 *
 * With subassemblies (two-handed disassembly), a state may also split into a subassembly that a
 * gripper takes out and the rest; both must then come apart (an AND node), each state an OR over
 * its splits (the AND/OR graph, every split of every state tried, memoised). The subassembly is
 * taken out in one of two grips:
 *  - by one of its parts, the others carried along by contact (Fig. 18b). It stays in that
 *    gripper, where it is (no supports, gravity acting), and is taken apart there: its gripped
 *    part held still, the others resting on it, removed one by one or in groups;
 *  - as a rigid whole, every part gripped (sec. VII: "have to be held together and lifted
 *    simultaneously"). It is taken apart in the air: the other hand takes a group out of it
 *    (again by one part, or whole), the rest staying held. Nothing held can fall, so only the
 *    parts carried by contact and what stays on the supports are checked.
 * The rest stays where it was (on the supports, or in its gripper). From the supports a rigid
 * grip takes out a proper part of the free parts (taking all of them at once, the question would
 * be geometry alone); a grip by one part may take out all of them (then it hangs from that part).
 * The number of stable two-handed plans counts AND/OR trees: a split counts once per way of
 * gripping the side taken out, whatever the path. */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <pthread.h>

#include "cands.h"
#include "plan_large.h"
#include "solve.h"
#include "cairn/plan.h"

/* Exhaustive search up to this many free parts; beyond, depth-first to the first stable plan. */
#define PLAN_MAX_EXHAUSTIVE 16
#define PLAN_MAX_PARTS 62
/* Samples per transition at most: candidate paths are sampled more coarsely beyond (bisection
 * still locates an onset to 1e-6 of the path). */
#define PLAN_MAX_SAMPLES 2000

cnPlanOptions cn_plan_options_default(void) {
    cnPlanOptions o;
    memset(&o, 0, sizeof o);
    o.sim = cn_sim_options_default();
    o.list_limit = 20;
    o.table_limit = 60;
    o.auto_dirs = 4;
    o.max_sub = 0;
    o.fixels = true;
    o.parallel = false; /* slower than one thread: see cnPlanOptions.parallel */
    o.max_states = 50000;
    o.sim.max_samples = PLAN_MAX_SAMPLES;
    o.sim.stop_at_undecided = true; /* a move only needs to be known not stable */
    return o;
}

void cn_plan_result_free(cnPlanResult *r) {
    if (!r) return;
    cn_arena_free(r->mem_);
    memset(r, 0, sizeof *r);
}

typedef unsigned long long Mask;

/* State.held of a subassembly held as a rigid whole (every part gripped). */
#define HELD_WHOLE (-2)

/* A simulated transition: `move` leaves state S along `cand`. */
typedef struct {
    Mask move;
    cnCand cand;
    cnStepStatus status;
    double time;          /* onset (when not stable) */
    Mask moving;          /* parts that start to move (unstable) */
    int blocking;         /* infeasible: the part in the way */
    int grip;             /* the bit of the gripped part; -1: every moved part is gripped */
    int from;             /* the state it leaves (subassembly transitions), else -1 */
    bool prop1;           /* unstable without simulation: the state it leads to is (Prop. 1) */
} Trans;

typedef struct {
    Mask mask;
    int held;             /* bit of the part a gripper holds still (no supports); -1: on the
                             supports, where the assembly stood; HELD_WHOLE: every part held */
    int stable;           /* -1 unknown */
    int solved;           /* -1 unknown: ways computed */
    double ways;          /* stable single-part sequences from here */
    int first, ntrans;    /* single-part transitions */
    double sub_plans;     /* -1 unknown: stable two-handed plans from here (0: none) */
    int sub_choice;       /* the first split that works (index into trans), -1 */
    double orders;        /* stable orders of the parts from here (paths aside), -1 unknown */
    Mask falls;           /* not stable: the parts that start to move */
    bool undecided;       /* not stable because its friction verdict is undecided */
    bool unexplored;      /* left unexpanded when the search budget ran out */
} State;

typedef struct {
    const cnAssembly *a;
    const cnPlanOptions *o;
    int nfree;
    int part_of[PLAN_MAX_PARTS]; /* bit -> part index */
    State *st;
    int nst, capst;
    int *hash;             /* open addressing: state index + 1, 0 empty */
    size_t hmask;
    Trans *tr;
    int ntr, captr;
    int nsims;
    bool truncated;        /* not exhaustive */
    bool splits_capped;    /* ... because a state's groups were taken from 20 of its parts */
    bool budget;           /* the state or time budget was reached */
    bool out_of_time;      /* ... and it was the time budget */
    struct timespec t0;    /* when the search started */
    double progress_at;    /* seconds into the search of the last progress call */
    cnDiag *diag;
    unsigned char *absent;
    unsigned char *moving;
    unsigned char *still;  /* per part: held still by the other hand */
    unsigned char *role;   /* per part: roles for the check of a held state */
    Mask touch[PLAN_MAX_PARTS]; /* per free part (bit): the free parts it touches (bits) */
    cnCandGen gen;         /* candidate paths, and the blocking graph's cones they come from */
} Planner;

/* The search's budgets: states explored (max_states) and wall time (max_seconds). When one is
 * spent the search is marked partial (and which budget it was). */
/* Seconds between two calls of the progress callback, at least (cnPlanOptions.progress_every). */
#define PLAN_PROGRESS_SECONDS 0.25

static bool out_of_budget(Planner *P) {
    if (P->o->progress) {
        double t = cn_seconds_since(&P->t0);
        if (t - P->progress_at >= (P->o->progress_every > 0 ? P->o->progress_every : PLAN_PROGRESS_SECONDS)) {
            P->progress_at = t;
            P->o->progress(P->o->progress_ctx, (long)P->nst, (long)P->nsims, t);
        }
    }
    bool out = P->o->max_states > 0 && P->nst > P->o->max_states;
    if (!out && P->o->max_seconds > 0) {
        out = P->out_of_time = cn_seconds_since(&P->t0) > P->o->max_seconds;
    }
    if (out) P->budget = P->truncated = true;
    return out;
}

/* Past PLAN_MAX_EXHAUSTIVE free parts (unless the options ask for every state) a state stops at
 * its first way on, and the counts are lower bounds. */
static bool first_only(const Planner *P) {
    return P->nfree > PLAN_MAX_EXHAUSTIVE && !P->o->exhaustive;
}

static size_t hash_mask(Mask m, int held) {
    m ^= (Mask)(held + 1) * 0x9e3779b97f4a7c15ULL;
    m ^= m >> 33;
    m *= 0xff51afd7ed558ccdULL;
    m ^= m >> 33;
    return (size_t)m;
}

/* The state of the parts `m`, on the supports (held = -1) or in a gripper holding bit `held`. */
static int state_at(Planner *P, Mask m, int held) {
    size_t i = hash_mask(m, held) & P->hmask;
    while (P->hash[i]) {
        const State *x = &P->st[P->hash[i] - 1];
        if (x->mask == m && x->held == held) return P->hash[i] - 1;
        i = (i + 1) & P->hmask;
    }
    if (P->nst == P->capst) {
        int nc = P->capst ? 2 * P->capst : 256;
        State *ns = cn_realloc(P->st, sizeof(State) * (size_t)nc);
        if (!ns) return -1;
        P->st = ns;
        P->capst = nc;
    }
    if ((size_t)(P->nst + 1) * 2 > P->hmask) { /* grow the table */
        size_t nsz = (P->hmask + 1) * 2;
        int *nh = cn_calloc(nsz, sizeof(int));
        if (!nh) return -1;
        for (int k = 0; k < P->nst; k++) {
            size_t j = hash_mask(P->st[k].mask, P->st[k].held) & (nsz - 1);
            while (nh[j]) j = (j + 1) & (nsz - 1);
            nh[j] = k + 1;
        }
        cn_free(P->hash);
        P->hash = nh;
        P->hmask = nsz - 1;
        i = hash_mask(m, held) & P->hmask;
        while (P->hash[i]) i = (i + 1) & P->hmask;
    }
    State *s = &P->st[P->nst];
    memset(s, 0, sizeof *s);
    s->mask = m;
    s->held = held;
    s->stable = s->solved = -1;
    s->sub_plans = -1;
    s->sub_choice = -1;
    s->orders = -1;
    P->hash[i] = P->nst + 1;
    return P->nst++;
}

static int state_of(Planner *P, Mask m) { return state_at(P, m, -1); }

/* Flags the parts absent from a state (and, held in a gripper, the supports), and the parts held
 * still (the gripped one, or every one held whole). */
static void set_absent_held(Planner *P, Mask present, int held) {
    const cnAssembly *a = P->a;
    for (int i = 0; i < a->nparts; i++)
        P->absent[i] = a->parts[i].gripper_step >= 0 || (held != -1 && a->parts[i].fixed);
    for (int b = 0; b < P->nfree; b++) P->absent[P->part_of[b]] = !(present >> b & 1);
    memset(P->still, 0, (size_t)a->nparts);
    if (held >= 0) P->still[P->part_of[held]] = 1;
    for (int b = 0; held == HELD_WHOLE && b < P->nfree; b++)
        if (present >> b & 1) P->still[P->part_of[b]] = 1;
}

static void set_absent(Planner *P, Mask present) { set_absent_held(P, present, -1); }

static cnStatus state_stable(Planner *P, int si, bool *stable) {
    if (P->st[si].stable >= 0) {
        *stable = P->st[si].stable;
        return CN_OK;
    }
    int held = P->st[si].held;
    if (held == HELD_WHOLE) { /* every part gripped: nothing can fall */
        P->st[si].stable = 1;
        *stable = true;
        return CN_OK;
    }
    set_absent_held(P, P->st[si].mask, held);
    cnContactQuery q = {NULL, P->absent, NULL};
    cnCheckOptions co = P->o->sim.check;
    co.query = &q;
    co.motion = NULL;
    cnMotion still; /* a held state: its gripped part at rest, kinematic */
    memset(&still, 0, sizeof still);
    if (held >= 0) {
        for (int i = 0; i < P->a->nparts; i++) P->role[i] = P->still[i] ? CN_ROLE_STILL : CN_ROLE_FREE;
        still.role = P->role;
        still.dt = P->a->sim_dt;
        co.motion = &still;
    }
    co.overlap_is_result = true;
    co.lp_crosscheck = true; /* as the simulator's check of a state at rest (after_known_stable) */
    cnCheckResult r;
    cnStatus s = cn_check(P->a, &co, &r, P->diag);
    if (s) return s;
    /* undecided (friction: the search for a motion from rest ran out of budget) is not stable */
    bool settled = !r.infeasible && r.nmoving == 0;
    P->st[si].undecided = settled && r.verdict == CN_VERDICT_UNDECIDED;
    *stable = settled && !P->st[si].undecided;
    for (int i = 0; i < r.nmoving; i++)
        for (int b = 0; b < P->nfree; b++)
            if (P->part_of[b] == r.moving[i]) P->st[si].falls |= 1ULL << b;
    cn_check_result_free(&r);
    P->st[si].stable = *stable;
    return CN_OK;
}

/* Candidate paths of the parts in `move` (bits) from state `present` (cn_cands). */
static cnStatus candidates(Planner *P, Mask present, int held, Mask move, cnCand **out, int *n) {
    const cnAssembly *a = P->a;
    int single = -1, count = 0;
    for (int b = 0; b < P->nfree; b++)
        if (move >> b & 1) single = P->part_of[b], count++;
    if (count != 1) single = -1;
    set_absent_held(P, present, held);
    memset(P->moving, 0, (size_t)a->nparts);
    for (int b = 0; b < P->nfree; b++)
        if (move >> b & 1) P->moving[P->part_of[b]] = 1;
    return cn_cands(&P->gen, P->absent, P->moving, single, false, out, n);
}

/* A transition of `move` along `cand` (NULL: unnamed), not simulated yet. */
static Trans trans_init(Mask move, const cnCand *cand, int grip, int from) {
    Trans t;
    memset(&t, 0, sizeof t);
    t.move = move;
    if (cand) t.cand = *cand;
    t.blocking = -1;
    t.grip = grip;
    t.from = from;
    return t;
}

/* Simulate `move` leaving `present` (held: see State) along `cand`, gripped by bit `grip` (the
 * others carried) or, grip = -1, by all of them. */
static cnStatus transition(Planner *P, Mask present, int held, Mask move, int grip,
                           const cnCand *cand, bool after_known, Trans *t) {
    const cnAssembly *a = P->a;
    *t = trans_init(move, cand, grip, -1);
    int mv[PLAN_MAX_PARTS], nm = 0, gp = grip >= 0 ? P->part_of[grip] : -1;
    for (int b = 0; b < P->nfree; b++)
        if (move >> b & 1) mv[nm++] = P->part_of[b];
    cnPlanStep st;
    memset(&st, 0, sizeof st);
    st.nmove = st.ngrip = nm;
    st.move = st.grip = mv;
    if (gp >= 0) st.ngrip = 1, st.grip = &gp;
    st.nseg = cand->nseg;
    st.seg = (cnSegment *)cn_cand_seg(cand); /* read only: cn_simulate_step takes the step const */
    st.path_given = true;
    st.support = cand->support;
    st.gripper = -1;
    set_absent_held(P, present, held);
    for (int i = 0; i < nm; i++) P->still[mv[i]] = 0; /* held whole: the group taken out moves */
    st.still = held != -1 ? P->still : NULL;
    cnStepResult r;
    cnSimOptions so = P->o->sim;
    so.after_known_stable = after_known;
    cnStatus s = cn_simulate_step(a, P->absent, &st, &so, &r, P->diag);
    P->nsims++;
    if (s) return s;
    t->status = r.status;
    t->time = r.onset_time;
    if (r.status == CN_STEP_UNSTABLE)
        for (int i = 0; i < r.onset.nmoving; i++)
            for (int b = 0; b < P->nfree; b++)
                if (P->part_of[b] == r.onset.moving[i]) t->moving |= 1ULL << b;
    if (r.status == CN_STEP_INFEASIBLE) t->blocking = r.blocking_part;
    cn_step_result_free(&r);
    return CN_OK;
}

static int push_trans(Planner *P, const Trans *t) {
    if (P->ntr == P->captr) {
        int nc = P->captr ? 2 * P->captr : 256;
        Trans *n = cn_realloc(P->tr, sizeof(Trans) * (size_t)nc);
        if (!n) return -1;
        P->tr = n;
        P->captr = nc;
    }
    P->tr[P->ntr++] = *t;
    return P->ntr - 1;
}

/* Simulate jobs[i] (leaving `present`) into res[i]. With `parallel` and enough jobs, a second
 * thread takes the first half, with scratch buffers, diagnostics and options of its own (no
 * warm start: that is state a caller may share); a simulation reads the assembly and writes
 * only its own result, and GLPK keeps its state per thread (Debian's GLPK is built with
 * thread-local storage; the worker frees its GLPK environment when it ends). If the worker fails
 * in any way, its half is done again here, so that errors are reported as on one thread. The
 * results do not depend on the threads: each job's result has its own slot. */
typedef struct {
    Mask move;
    cnCand cand;
} Job;

typedef struct {
    Planner W;          /* the worker's copy: its own absent/still buffers and diagnostics */
    cnPlanOptions o;    /* its options: the planner's, without a warm start */
    cnDiag diag;
    Mask present;
    const Job *jobs;
    Trans *res;
    int n;
    bool ok;
} Worker;

static void *worker_run(void *arg) {
    Worker *w = arg;
    w->ok = true;
    for (int i = 0; i < w->n && w->ok; i++)
        if (transition(&w->W, w->present, -1, w->jobs[i].move, -1, &w->jobs[i].cand, true, &w->res[i]) != CN_OK)
            w->ok = false;
    cn_lp_thread_end();
    return NULL;
}

static cnStatus run_jobs(Planner *P, Mask present, const Job *jobs, int nj, Trans *res) {
    int split = (P->o->parallel && nj >= 4) ? nj / 2 : 0;
    Worker w;
    pthread_t th;
    bool started = false;
    if (split > 0) {
        memset(&w, 0, sizeof w);
        w.W = *P;
        w.o = *P->o;
        w.o.sim.check.warm = NULL;
        w.W.o = &w.o;
        w.W.diag = &w.diag;
        w.W.gen.o = &w.o;
        w.W.gen.diag = &w.diag;
        w.W.nsims = 0;
        w.W.absent = cn_malloc((size_t)P->a->nparts + 1);
        w.W.still = cn_calloc((size_t)P->a->nparts + 1, 1);
        w.present = present;
        w.jobs = jobs;
        w.res = res;
        w.n = split;
        started = w.W.absent && w.W.still && pthread_create(&th, NULL, worker_run, &w) == 0;
        if (!started) {
            cn_free(w.W.absent);
            cn_free(w.W.still);
            split = 0;
        }
    }
    cnStatus s = CN_OK;
    for (int i = split; i < nj && !s; i++) s = transition(P, present, -1, jobs[i].move, -1, &jobs[i].cand, true, &res[i]);
    if (started) {
        pthread_join(th, NULL);
        cn_free(w.W.absent);
        cn_free(w.W.still);
        if (w.ok) P->nsims += w.W.nsims;
        else /* the worker failed: do its half here (errors are then reported here) */
            for (int i = 0; i < split && !s; i++)
                s = transition(P, present, -1, jobs[i].move, -1, &jobs[i].cand, true, &res[i]);
    }
    return s;
}

/* Single-part transitions of state si (computed once). */
static cnStatus expand(Planner *P, int si) {
    State *S = &P->st[si];
    if (S->ntrans || S->first < 0) return CN_OK;
    Mask m = S->mask;
    int nj = 0, capj = 0;
    Job *jobs = NULL;
    cnStatus s = CN_OK;
    int nprop = 0;
    Trans *prop = NULL;
    for (int b = 0; b < P->nfree && !s; b++) {
        if (!(m >> b & 1)) continue;
        cnCand *c;
        int nc;
        s = candidates(P, m, -1, 1ULL << b, &c, &nc);
        if (s) break;
        /* Proposition 1: if the state without the part is not stable, every path is unstable */
        int nx = state_of(P, m & ~(1ULL << b));
        bool after = true;
        if (nx < 0) s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
        else s = state_stable(P, nx, &after);
        if (!s && !after && nc > 0) {
            Trans *np = cn_realloc(prop, sizeof(Trans) * (size_t)(nprop + nc));
            if (!np) s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
            for (int k = 0; !s && k < nc; k++) {
                prop = np;
                Trans *t = &prop[nprop++];
                *t = trans_init(1ULL << b, &c[k], -1, -1);
                t->status = P->st[nx].undecided ? CN_STEP_UNDECIDED : CN_STEP_UNSTABLE;
                t->time = NAN;
                t->moving = P->st[nx].falls;
                t->prop1 = true;
            }
            cn_free(c);
            continue;
        }
        for (int k = 0; !s && k < nc; k++) {
            if (nj == capj) {
                capj = capj ? 2 * capj : 16;
                Job *nw = cn_realloc(jobs, sizeof(Job) * (size_t)capj);
                if (!nw) {
                    s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
                    break;
                }
                jobs = nw;
            }
            jobs[nj].move = 1ULL << b;
            jobs[nj].cand = c[k];
            nj++;
        }
        cn_free(c);
    }
    Trans *res = s ? NULL : cn_calloc((size_t)nj + 1, sizeof(Trans));
    if (!s && !res) s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    if (!s) s = run_jobs(P, m, jobs, nj, res);
    int first = P->ntr;
    for (int i = 0; i < nj && !s; i++)
        if (push_trans(P, &res[i]) < 0) s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    for (int i = 0; i < nprop && !s; i++)
        if (push_trans(P, &prop[i]) < 0) s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    cn_free(prop);
    cn_free(jobs);
    cn_free(res);
    if (s) return s;
    S = &P->st[si];
    S->first = first;
    S->ntrans = P->ntr - first;
    if (S->ntrans == 0) S->first = -1;
    return CN_OK;
}

/* Stable single-part sequences from state si. */
static cnStatus solve(Planner *P, int si, int depth) {
    if (P->st[si].solved >= 0) return CN_OK;
    Mask m = P->st[si].mask;
    if (m == 0) {
        P->st[si].solved = 1;
        P->st[si].ways = 1;
        return CN_OK;
    }
    bool stable;
    cnStatus s = state_stable(P, si, &stable);
    if (s) return s;
    if (!stable) {
        P->st[si].solved = 0;
        P->st[si].ways = 0;
        return CN_OK;
    }
    if (out_of_budget(P)) { /* this state stays unexplored (not solved) */
        P->st[si].unexplored = true;
        P->st[si].solved = 0;
        P->st[si].ways = 0;
        return CN_OK;
    }
    if ((s = expand(P, si))) return s;
    double ways = 0;
    int first = P->st[si].first, n = P->st[si].ntrans;
    for (int k = 0; k < n; k++) {
        /* copy out: the recursion may move the transition array */
        cnStepStatus status = P->tr[first + k].status;
        Mask mv = P->tr[first + k].move;
        if (status != CN_STEP_STABLE) continue;
        int nx = state_of(P, m & ~mv);
        if (nx < 0) return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
        if ((s = solve(P, nx, depth + 1))) return s;
        ways += P->st[nx].ways;
        if (first_only(P) && ways > 0) {
            P->truncated = true;
            break;
        }
    }
    P->st[si].ways = ways;
    P->st[si].solved = ways > 0;
    return CN_OK;
}

/* ---- subassemblies: the AND/OR search ---- */

static cnStatus solve_sub(Planner *P, int si);

static int popcount(Mask m) {
    int c = 0;
    for (; m; m &= m - 1) c++;
    return c;
}

/* Where a split transition t of state si leads: *rest, the state of the parts that stay where
 * they were, and *out, the subassembly taken out in its gripper (held by its gripped part, or
 * whole); -1 for a single part, which is gone. */
static cnStatus split_states(Planner *P, int si, const Trans *t, int *rest, int *out) {
    Mask m = P->st[si].mask;
    int held = P->st[si].held;
    bool group = popcount(t->move) > 1;
    *out = -1;
    *rest = state_at(P, m & ~t->move, held);
    if (*rest >= 0 && group) *out = state_at(P, t->move, t->grip >= 0 ? t->grip : HELD_WHOLE);
    if (*rest < 0 || (group && *out < 0)) return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    return CN_OK;
}

/* The stable two-handed plans that begin with the stable split transition t of state si: the
 * product of those of its two sides (each solved here). */
static cnStatus split_plans(Planner *P, int si, const Trans *t, double *plans) {
    int r1, r2;
    *plans = 0;
    cnStatus s = split_states(P, si, t, &r1, &r2);
    if (s || (s = solve_sub(P, r1))) return s;
    double n = P->st[r1].sub_plans;
    if (n > 0 && r2 >= 0) {
        if ((s = solve_sub(P, r2))) return s;
        n *= P->st[r2].sub_plans;
    }
    *plans = n;
    return CN_OK;
}

/* The grips a group M taken out of state si may be held by, into grips[]: by each of its parts
 * (bits; the others carried by contact) and whole (-1), or a single part gripped (-1). Taken out
 * of a subassembly held whole, the group and the rest are one split when the group is held whole
 * too: it is tried from the side without the state's lowest part (and, when that side cannot go,
 * by taking out the other side), and counted once. */
static int grips_of(const Planner *P, int si, Mask M, int *grips) {
    Mask m = P->st[si].mask;
    int held = P->st[si].held, n = 0;
    bool twin = held == HELD_WHOLE && (M & m & (~m + 1)); /* M holds the lowest part */
    if (popcount(M) == 1) {
        if (!twin) grips[n++] = -1;
        return n;
    }
    for (int g = 0; g < P->nfree; g++)
        if (M >> g & 1) grips[n++] = g;
    if (!twin && !(held == -1 && M == m)) grips[n++] = -1;
    return n;
}

/* The parts of M that a gripper holding bit g carries by contact: those connected to g through
 * contacts among the parts of M (the others touch nothing held in the gripper: they fall). */
static Mask reach(const Planner *P, Mask M, int g) {
    Mask seen = 1ULL << g, front = seen;
    while (front) {
        Mask next = 0;
        for (int b = 0; b < P->nfree; b++)
            if (front >> b & 1) next |= P->touch[b] & M & ~seen;
        seen |= next;
        front = next;
    }
    return seen;
}

/* Proposition 1 for a split of state si taking out group M gripped by `grip`: is the state
 * (mask, held) the move leaves stable (*ok)? When it is not, the move is recorded as unstable
 * without a simulation, for the report of splits. */
static cnStatus after_move(Planner *P, int si, Mask mask, int held, Mask M, int grip, bool *ok) {
    *ok = true;
    if (mask == 0 || held == HELD_WHOLE) return CN_OK;
    int nx = state_at(P, mask, held);
    if (nx < 0) return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    cnStatus s = state_stable(P, nx, ok);
    if (s || *ok) return s;
    Trans t = trans_init(M, NULL, grip, si);
    snprintf(t.cand.name, sizeof t.cand.name, "any path");
    t.status = P->st[nx].undecided ? CN_STEP_UNDECIDED : CN_STEP_UNSTABLE;
    t.time = NAN;
    t.moving = P->st[nx].falls;
    t.prop1 = true;
    if (push_trans(P, &t) < 0) return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    return CN_OK;
}

/* Group M leaves state si gripped by `grip` along each candidate path in turn until one is
 * stable (each simulated, and recorded for the report); that one's plans are added to *plans
 * (*choice: the first transition with plans). *found: a path was stable. */
static cnStatus try_paths(Planner *P, int si, Mask M, int grip, const cnCand *c, int nc, bool *found,
                          double *plans, int *choice) {
    Mask m = P->st[si].mask;
    int held = P->st[si].held;
    *found = false;
    for (int j = 0; j < nc; j++) {
        Trans t;
        cnCand cj = c[j];
        if (popcount(M) > 1) cj.support = CN_SUPPORT_HOLD; /* the gripper carries them */
        if (held == HELD_WHOLE && grip < 0 && !cj.file && cj.nseg == 1) {
            /* everything held: a straight line along a free direction is free */
            t = trans_init(M, &cj, -1, si);
            t.status = CN_STEP_STABLE;
        } else {
            cnStatus s = transition(P, m, held, M, grip, &cj, false, &t);
            if (s) return s;
        }
        t.from = si;
        int idx = push_trans(P, &t);
        if (idx < 0) return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
        if (t.status != CN_STEP_STABLE) continue;
        double n;
        cnStatus s = split_plans(P, si, &t, &n);
        if (s) return s;
        *found = true;
        *plans += n;
        if (n > 0 && *choice < 0) *choice = idx;
        return CN_OK;
    }
    return CN_OK;
}

/* The groups of state si that some cell of its blocking graph lets out (sec. V): per cell, for
 * each free part (bit) the free parts that block it, and the parts blocked by a part that is not
 * free (a support). A group M can leave along the cell's directions iff no part of M is blocked by
 * a part outside M. *ncell = -1: no graph (too many circles), every group is tried. */
typedef struct {
    int ncell;
    Mask *blk;      /* ncell x nfree */
    Mask *stuck;    /* per cell */
} Removable;

static cnStatus removable_of_state(Planner *P, Mask m, int held, Removable *R) {
    const cnAssembly *a = P->a;
    memset(R, 0, sizeof *R);
    if (a->dim == 2) { /* the 2-D arcs of a group cost less than the state's graph */
        R->ncell = -1;
        return CN_OK;
    }
    cnStatus s = cn_cands_cones(&P->gen);
    if (s) return s;
    set_absent_held(P, m, held);
    cnNdbg g;
    if ((s = cn_ndbg_arrange(a, &P->gen.cones, P->absent, NULL, 0, &g, P->diag))) return s;
    if (g.too_large) {
        R->ncell = -1;
        cn_ndbg_free(&g);
        return CN_OK;
    }
    R->blk = cn_calloc((size_t)g.ncells * (size_t)P->nfree + 1, sizeof(Mask));
    R->stuck = cn_calloc((size_t)g.ncells + 1, sizeof(Mask));
    if (!R->blk || !R->stuck) {
        cn_free(R->blk), cn_free(R->stuck);
        cn_ndbg_free(&g);
        return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    }
    R->ncell = g.ncells;
    for (int c = 0; c < g.ncells; c++)
        for (int k = 0; k < g.cells[c].nedges; k++) {
            const cnNdbgEdge *e = &g.edges[g.cells[c].first + k];
            int bp = -1, bb = -1;
            for (int b = 0; b < P->nfree; b++) {
                if (P->part_of[b] == e->part) bp = b;
                if (P->part_of[b] == e->blocker) bb = b;
            }
            if (bp < 0) continue;
            if (bb < 0) R->stuck[c] |= 1ULL << bp;
            else R->blk[(size_t)c * (size_t)P->nfree + (size_t)bp] |= 1ULL << bb;
        }
    cn_ndbg_free(&g);
    return CN_OK;
}

static bool group_removable(const Planner *P, const Removable *R, Mask M) {
    /* a single part may leave by a route or by a path of the file, which the graph's straight
     * lines do not see: its candidates decide */
    if (R->ncell < 0 || !(M & (M - 1))) return true;
    for (int c = 0; c < R->ncell; c++) {
        if (R->stuck[c] & M) continue;
        bool ok = true;
        for (int b = 0; b < P->nfree && ok; b++)
            if ((M >> b & 1) && (R->blk[(size_t)c * (size_t)P->nfree + (size_t)b] & ~M)) ok = false;
        if (ok) return true;
    }
    return false;
}

/* Stable two-handed plans from state si (memoised in sub_plans): an OR over its splits, each an
 * AND of its two sides. Every split of every state is tried (exact counts) up to
 * PLAN_MAX_EXHAUSTIVE free parts (any number with cnPlanOptions.exhaustive); beyond, a state stops
 * at its first stable split. */
static cnStatus solve_sub(Planner *P, int si) {
    if (P->st[si].sub_plans >= 0) return CN_OK;
    Mask m = P->st[si].mask;
    int held = P->st[si].held;
    Mask hm = held >= 0 ? 1ULL << held : 0;
    /* nothing left, only the part in the hand, or one part held */
    if ((m & ~hm) == 0 || (held == HELD_WHOLE && popcount(m) == 1)) {
        P->st[si].sub_plans = 1;
        return CN_OK;
    }
    bool stable;
    cnStatus s = state_stable(P, si, &stable);
    if (s) return s;
    if (!stable) {
        P->st[si].sub_plans = 0;
        return CN_OK;
    }
    P->st[si].sub_plans = 0; /* provisional (states only shrink: no cycles) */
    if (out_of_budget(P)) return CN_OK;
    bool first = first_only(P);
    if (first) P->truncated = true; /* counts are then lower bounds */
    double plans = 0;
    int choice = -1;
    /* single parts from the supports: the transitions the sequence search simulated; a part
     * counts once, whichever of its stable paths (they all lead to the same state) */
    if (held == -1) {
        if ((s = expand(P, si))) return s;
        Mask done = 0;
        for (int k = 0; k < P->st[si].ntrans && !(first && plans > 0); k++) {
            int idx = P->st[si].first + k;
            Trans t = P->tr[idx];
            if (t.status != CN_STEP_STABLE || (done & t.move)) continue;
            done |= t.move;
            double n;
            if ((s = split_plans(P, si, &t, &n))) return s;
            plans += n;
            if (n > 0 && choice < 0) choice = idx;
        }
    }
    /* every group M of the parts not in the hand, smallest first, up to max_sub parts (from the
     * supports, single parts are done above) */
    int bits[PLAN_MAX_PARTS], nb = 0;
    for (int b = 0; b < P->nfree; b++)
        if ((m & ~hm) >> b & 1) bits[nb++] = b;
    bool capped = nb > 20; /* 2^20 groups at most */
    if (capped) nb = 20;
    int kmin = held == -1 ? 2 : 1; /* from the supports, single parts are done above */
    int kmax = P->o->max_sub > 0 && P->o->max_sub < nb ? P->o->max_sub : nb;
    if (held == HELD_WHOLE && kmax == nb) kmax = nb - 1; /* something stays in the hand */
    if (capped && kmax >= kmin) { /* groups were left out */
        P->truncated = true;
        if (!first) P->splits_capped = true; /* (else the report says it stopped at a first plan) */
    }
    /* the state's blocking graph says which groups have a free direction at all */
    Removable rem;
    if ((s = removable_of_state(P, m, held, &rem))) return s;
    for (int k = kmin; k <= kmax && !s; k++) {
        for (Mask sub = 1; sub < (1ULL << nb) && !s && !(first && plans > 0); sub++) {
            if (popcount(sub) != k) continue;
            if (out_of_budget(P)) break; /* checked per group: a state may have 2^n of them */
            Mask M = 0;
            for (int i = 0; i < nb; i++)
                if (sub >> i & 1) M |= 1ULL << bits[i];
            int grips[PLAN_MAX_PARTS + 1];
            int ng = grips_of(P, si, M, grips);
            if (ng == 0) continue;
            /* Proposition 1: the rest must stand where it stays (cheaper than any simulation) */
            bool ok;
            if ((s = after_move(P, si, m & ~M, held, M, -1, &ok)) || !ok) continue;
            cnCand *c = NULL;
            int nc = 0;
            if (group_removable(P, &rem, M) && (s = candidates(P, m, held, M, &c, &nc))) break;
            if (nc == 0) { /* no free direction: recorded for the report of splits */
                Trans t = trans_init(M, NULL, -1, si);
                t.status = CN_STEP_INFEASIBLE;
                snprintf(t.cand.name, sizeof t.cand.name, "no free direction");
                if (push_trans(P, &t) < 0) s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
            }
            /* each grip in turn; its first path that is stable counts */
            for (int gi = 0; gi < ng && !s && !(first && plans > 0); gi++) {
                /* ... and the group must stay on the part that holds it (Proposition 1): parts
                 * that touch nothing connected to it fall at once */
                Mask lost = grips[gi] >= 0 ? M & ~reach(P, M, grips[gi]) : 0;
                if (nc > 0 && lost) {
                    Trans t = trans_init(M, NULL, grips[gi], si);
                    snprintf(t.cand.name, sizeof t.cand.name, "any path");
                    t.status = CN_STEP_UNSTABLE;
                    t.time = NAN;
                    t.moving = lost;
                    t.prop1 = true;
                    if (push_trans(P, &t) < 0) s = cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
                    continue;
                }
                if (nc > 0 && grips[gi] >= 0 &&
                    ((s = after_move(P, si, M, grips[gi], M, grips[gi], &ok)) || !ok))
                    continue;
                bool found;
                if ((s = try_paths(P, si, M, grips[gi], c, nc, &found, &plans, &choice))) break;
                if (found || grips[gi] >= 0 || held != HELD_WHOLE) continue;
                /* held whole, {M | rest} is one split whichever side the other hand takes: when
                 * M cannot go, the rest may (it is not tried from its own side) */
                cnCand *c2;
                int nc2;
                Mask R = m & ~M;
                if ((s = candidates(P, m, held, R, &c2, &nc2))) break;
                s = try_paths(P, si, R, -1, c2, nc2, &found, &plans, &choice);
                cn_free(c2);
            }
            cn_free(c);
        }
    }
    cn_free(rem.blk);
    cn_free(rem.stuck);
    if (s) return s;
    P->st[si].sub_plans = plans;
    P->st[si].sub_choice = choice;
    return CN_OK;
}

/* ---- the result: typed, in one arena (cnPlanResult.mem_) ---- */

typedef struct {
    Planner *P;
    cnArena *mem;
    cnPlanMove *memo; /* per transition: its move, built once (path == NULL: not yet); the
                         result's lists share its name, segments and part lists */
    bool nomem;  /* an allocation failed: the result is incomplete and is not returned */
} Out;

static void *out_alloc(Out *O, size_t count, size_t size) {
    void *p = cn_arena_alloc(&O->mem, count, size);
    if (!p) O->nomem = true;
    return p;
}

static cnPartList mask_list(Out *O, Mask m) {
    cnPartList l = {0, NULL};
    int n = popcount(m);
    int *idx = out_alloc(O, (size_t)n, sizeof(int));
    if (!idx) return l;
    for (int b = 0; b < O->P->nfree; b++)
        if (m >> b & 1) idx[l.n++] = O->P->part_of[b];
    l.idx = idx;
    return l;
}

static int part_or_none(const Planner *P, int bit) { return bit >= 0 ? P->part_of[bit] : -1; }

/* A transition (an element of P->tr) as the result reports it: its path's name and segments
 * copied into the result once, however many sequences and rows it appears in. */
static cnPlanMove move_of(Out *O, const Trans *t) {
    cnPlanMove *memo = O->memo ? &O->memo[t - O->P->tr] : NULL;
    if (memo && memo->path) return *memo;
    cnPlanMove mv;
    memset(&mv, 0, sizeof mv);
    mv.move = mask_list(O, t->move);
    const char *name = cn_cand_name(&t->cand);
    mv.path = cn_arena_strdup(&O->mem, name);
    if (!mv.path) O->nomem = true;
    mv.nseg = t->cand.nseg;
    cnSegment *seg = out_alloc(O, (size_t)mv.nseg, sizeof(cnSegment));
    if (seg && mv.nseg > 0) memcpy(seg, cn_cand_seg(&t->cand), sizeof(cnSegment) * (size_t)mv.nseg);
    mv.seg = seg;
    mv.support = t->cand.support;
    mv.grip = part_or_none(O->P, t->grip);
    mv.status = t->status;
    mv.proposition_1 = t->prop1;
    mv.time = t->prop1 ? NAN : t->time;
    if (t->status == CN_STEP_UNSTABLE) mv.moving = mask_list(O, t->moving);
    mv.blocked_by = t->status == CN_STEP_INFEASIBLE ? t->blocking : -1;
    if (memo) *memo = mv;
    return mv;
}

/* A growing list of moves or sequences in the arena (doubling; the old blocks stay in the
 * arena until the result is freed). */
static void *grow(Out *O, void *arr, int n, int *cap, size_t size) {
    if (n < *cap) return arr;
    int nc = *cap ? 2 * *cap : 8;
    void *na = out_alloc(O, (size_t)nc, size);
    if (!na) return NULL;
    if (n > 0) memcpy(na, arr, size * (size_t)n);
    *cap = nc;
    return na;
}

typedef struct {
    cnPlanSequence *items;
    int n, cap, limit;
} SeqList;

static void seq_add(Out *O, SeqList *L, Trans **stack, int depth, const Trans *last) {
    cnPlanSequence *ni = grow(O, L->items, L->n, &L->cap, sizeof(cnPlanSequence));
    if (!ni) return;
    L->items = ni;
    int n = depth + (last ? 1 : 0);
    cnPlanMove *steps = out_alloc(O, (size_t)n, sizeof(cnPlanMove));
    if (!steps) return;
    for (int i = 0; i < depth; i++) steps[i] = move_of(O, stack[i]);
    if (last) steps[depth] = move_of(O, last);
    L->items[L->n].n = n;
    L->items[L->n].steps = steps;
    L->n++;
}

static cnPlanNode tree_of(Out *O, int si) {
    Planner *P = O->P;
    State *S = &P->st[si];
    cnPlanNode o;
    memset(&o, 0, sizeof o);
    o.parts = mask_list(O, S->mask);
    o.held_by = part_or_none(P, S->held);
    o.held_whole = S->held == HELD_WHOLE;
    Mask hm = S->held >= 0 ? 1ULL << S->held : 0;
    if ((S->mask & ~hm) == 0 || S->sub_choice < 0) return o; /* nothing to take out */
    Trans t = P->tr[S->sub_choice];
    o.split = true;
    o.take_out = move_of(O, &P->tr[S->sub_choice]);
    int r1, r2;
    if (split_states(P, si, &t, &r1, &r2)) {
        O->nomem = true;
        return o;
    }
    cnPlanNode *ch = out_alloc(O, 2, sizeof(cnPlanNode));
    if (!ch) return o;
    if (r2 >= 0) ch[o.nchildren++] = tree_of(O, r2);
    if (P->st[r1].mask != 0) ch[o.nchildren++] = tree_of(O, r1); /* something stays */
    o.children = ch;
    return o;
}

/* Does part bit b leave state si stably along some path, into a solved state? */
static int leaves(Planner *P, int si, int b) {
    for (int k = 0; k < P->st[si].ntrans; k++) {
        const State *S = &P->st[si]; /* afresh: state_of may move the states */
        Trans *t = &P->tr[S->first + k];
        if (t->move != 1ULL << b || t->status != CN_STEP_STABLE) continue;
        int nx = state_of(P, S->mask & ~t->move);
        if (nx >= 0 && P->st[nx].solved == 1) return nx;
    }
    return -1;
}

/* Stable orders of the parts from state si, paths aside (memoised). */
static double count_orders(Planner *P, int si) {
    if (P->st[si].orders >= 0) return P->st[si].orders;
    double n = 0;
    if (P->st[si].mask == 0) n = 1;
    else if (P->st[si].solved == 1)
        for (int b = 0; b < P->nfree; b++) {
            if (!(P->st[si].mask >> b & 1)) continue;
            int nx = leaves(P, si, b);
            if (nx >= 0) n += count_orders(P, nx);
        }
    P->st[si].orders = n;
    return n;
}

typedef struct {
    cnPartList *items;
    int n, cap, limit;
} OrderList;

static void list_orders(Out *O, int si, int *stack, int depth, OrderList *L) {
    Planner *P = O->P;
    if (L->n >= L->limit || O->nomem) return;
    if (P->st[si].mask == 0) {
        cnPartList *ni = grow(O, L->items, L->n, &L->cap, sizeof(cnPartList));
        int *idx = out_alloc(O, (size_t)depth, sizeof(int));
        if (!ni || !idx) return;
        L->items = ni;
        for (int i = 0; i < depth; i++) idx[i] = P->part_of[stack[i]];
        L->items[L->n].n = depth;
        L->items[L->n].idx = idx;
        L->n++;
        return;
    }
    for (int b = 0; b < P->nfree; b++) {
        if (!(P->st[si].mask >> b & 1)) continue;
        int nx = leaves(P, si, b);
        if (nx < 0) continue;
        stack[depth] = b;
        list_orders(O, nx, stack, depth + 1, L);
    }
}

/* Stable sequences (depth-first, up to the list's limit). */
static void list_sequences(Out *O, int si, Trans **stack, int depth, SeqList *L) {
    Planner *P = O->P;
    if (L->n >= L->limit || O->nomem) return;
    State *S = &P->st[si];
    if (S->mask == 0) {
        seq_add(O, L, stack, depth, NULL);
        return;
    }
    if (S->solved != 1) return;
    for (int k = 0; k < P->st[si].ntrans; k++) {
        S = &P->st[si]; /* afresh: state_of and the recursion may move the states */
        Trans *t = &P->tr[S->first + k];
        if (t->status != CN_STEP_STABLE) continue;
        int nx = state_of(P, S->mask & ~t->move);
        if (nx < 0 || P->st[nx].solved != 1) continue;
        stack[depth] = t;
        list_sequences(O, nx, stack, depth + 1, L);
    }
}

typedef struct {
    cnPlanRow *items;
    int n, cap, limit;
} RowList;

static void row_add(Out *O, RowList *L, Trans **stack, int n, cnPlanRowEnd end) {
    cnPlanRow *ni = grow(O, L->items, L->n, &L->cap, sizeof(cnPlanRow));
    cnPlanMove *steps = out_alloc(O, (size_t)n, sizeof(cnPlanMove));
    if (!ni || !steps) return;
    L->items = ni;
    for (int i = 0; i < n; i++) steps[i] = move_of(O, stack[i]);
    L->items[L->n].seq.n = n;
    L->items[L->n].seq.steps = steps;
    L->items[L->n].end = end;
    L->n++;
}

/* The sequence x path table: every explored branch, to its end or its first failure. */
static void table_rows(Out *O, int si, Trans **stack, int depth, RowList *L) {
    Planner *P = O->P;
    if (L->n >= L->limit || O->nomem) return;
    State *S = &P->st[si];
    bool leaf = S->mask == 0 || S->stable == 0 || S->ntrans == 0 || S->solved < 0;
    if (leaf) {
        row_add(O, L, stack, depth,
                S->mask == 0       ? CN_ROW_STABLE
                : S->stable == 0   ? (S->undecided ? CN_ROW_STATE_UNDECIDED : CN_ROW_STATE_UNSTABLE)
                : S->unexplored    ? CN_ROW_UNEXPLORED
                                   : CN_ROW_NO_WAY_ON);
        return;
    }
    for (int k = 0; k < S->ntrans && L->n < L->limit && !O->nomem; k++) {
        Trans *t = &P->tr[S->first + k];
        stack[depth] = t;
        if (t->status != CN_STEP_STABLE) {
            row_add(O, L, stack, depth + 1, CN_ROW_STEP_FAILS);
            continue;
        }
        int nx = state_of(P, S->mask & ~t->move);
        if (nx < 0) return;
        table_rows(O, nx, stack, depth + 1, L);
        S = &P->st[si];
    }
}

/* Does transition k leave state si (its single-part ones, or its subassembly ones)? */
static bool leaves_state(const Planner *P, int si, int k) {
    const State *S = &P->st[si];
    return P->tr[k].from == si || (k >= S->first && k < S->first + S->ntrans);
}

/* The two-handed splits of the whole assembly into two groups, each stable or not, and how. */
static void splits_of(Out *O, int si, cnPlanSplit **out, int *nout) {
    Planner *P = O->P;
    Mask m = P->st[si].mask;
    Mask done[512];
    int nd = 0, cap = 0;
    *out = NULL;
    *nout = 0;
    for (int pass = 0; pass < 2; pass++) /* stable splits first */
        for (int k = 0; k < P->ntr; k++) {
            Trans t = P->tr[k];
            if (!leaves_state(P, si, k) || t.move == m) continue;
            Mask key = t.move < (m & ~t.move) ? t.move : m & ~t.move;
            bool seen = false;
            for (int i = 0; i < nd; i++) seen |= done[i] == key;
            if (seen || nd == 512) continue;
            /* the first transition of this split that works, else the first that was tried; the
             * plans through it (a stable move counts once per grip, whatever its path) */
            int ok = -1, tried = -1, ntried = 0;
            double plans = 0;
            for (int j = 0; j < P->ntr; j++) {
                Trans u = P->tr[j];
                if (!leaves_state(P, si, j) || (u.move != key && u.move != (m & ~key))) continue;
                ntried++;
                if (tried < 0) tried = j;
                if (u.status != CN_STEP_STABLE) continue;
                bool again = false;
                for (int i = 0; i < j && !again; i++)
                    again = leaves_state(P, si, i) && P->tr[i].status == CN_STEP_STABLE &&
                            P->tr[i].move == u.move && P->tr[i].grip == u.grip;
                int r1, r2;
                if (again || split_states(P, si, &u, &r1, &r2)) continue;
                double n = P->st[r1].sub_plans > 0 ? P->st[r1].sub_plans : 0;
                if (r2 >= 0) n *= P->st[r2].sub_plans > 0 ? P->st[r2].sub_plans : 0;
                plans += n;
                if (n > 0 && ok < 0) ok = j;
                else if (ok < 0 && P->tr[tried].status != CN_STEP_STABLE) tried = j;
            }
            if ((pass == 0) != (ok >= 0)) continue;
            done[nd++] = key;
            cnPlanSplit *na = grow(O, *out, *nout, &cap, sizeof(cnPlanSplit));
            if (!na) return;
            *out = na;
            cnPlanSplit *sp = &na[(*nout)++];
            sp->side[0] = mask_list(O, key);
            sp->side[1] = mask_list(O, m & ~key);
            sp->stable = ok >= 0;
            sp->nplans = plans;
            sp->moves_tried = ntried;
            const Trans *w = &P->tr[ok >= 0 ? ok : tried];
            sp->move = move_of(O, w);
            sp->sides_fail = ok < 0 && w->status == CN_STEP_STABLE;
        }
}

/* ---- fixels ---- */

/* Try fixels on the parts that start to move in a failing transition: at their vertices, pushing
 * against faces the motion opens; keep the fewest (one, else two) that make the step stable,
 * verified by simulating it again. */
typedef struct {
    cnFixelSuggestion *items;
    int n, cap;
} FixList;

static cnStatus suggest_fixels(Out *O, Mask present, const Trans *t, FixList *out) {
    Planner *P = O->P;
    const cnAssembly *a = P->a;
    int dim = a->dim;
    /* the motion at the onset: simulate once more to get it */
    int mv[PLAN_MAX_PARTS], nm = 0;
    for (int b = 0; b < P->nfree; b++)
        if (t->move >> b & 1) mv[nm++] = P->part_of[b];
    cnPlanStep st;
    memset(&st, 0, sizeof st);
    st.nmove = st.ngrip = nm;
    st.move = st.grip = mv;
    st.nseg = t->cand.nseg;
    st.seg = (cnSegment *)cn_cand_seg(&t->cand); /* read only */
    st.path_given = true;
    st.support = t->cand.support;
    st.gripper = -1;
    set_absent(P, present);
    cnStepResult r;
    cnStatus s = cn_simulate_step(a, P->absent, &st, &P->o->sim, &r, P->diag);
    if (s) return s;
    if (r.status != CN_STEP_UNSTABLE || !r.onset.part) {
        cn_step_result_free(&r);
        return CN_OK;
    }
    /* candidate fixels, scored by how directly the motion opens the face */
    typedef struct {
        cnFixel f;
        double score;
    } FC;
    int cap = 64, nf = 0;
    FC *fc = cn_malloc(sizeof(FC) * (size_t)cap);
    for (int i = 0; fc && i < r.onset.nmoving; i++) {
        int p = r.onset.moving[i];
        const cnPart *pt = &a->parts[p];
        const cnPartMotion *m = &r.onset.part[p];
        for (int sI = 0; sI < pt->npieces; sI++) {
            const cnPiece *pc = &pt->pieces[sI];
            for (int v = 0; v < pc->nverts; v++) {
                double rr[3], vel[3];
                cn_sub3(pc->verts[v], pt->com, rr);
                if (dim == 2) {
                    vel[0] = m->lin[0] - m->ang[2] * rr[1];
                    vel[1] = m->lin[1] + m->ang[2] * rr[0];
                    vel[2] = 0;
                } else {
                    cn_cross3(m->ang, rr, vel);
                    cn_add3(vel, m->lin, vel);
                }
                /* faces through v: 2-D the two edges at v; 3-D the faces listing v */
                double normals[16][3];
                int nn = 0;
                if (dim == 2) {
                    for (int e = 0; e < 2; e++) {
                        const double *A = pc->verts[e ? v : (v + pc->nverts - 1) % pc->nverts];
                        const double *B = pc->verts[e ? (v + 1) % pc->nverts : v];
                        double ex = B[0] - A[0], ey = B[1] - A[1], L = hypot(ex, ey);
                        normals[nn][0] = ey / L, normals[nn][1] = -ex / L, normals[nn][2] = 0, nn++;
                    }
                } else {
                    for (int f = 0; f < pc->nfaces && nn < 16; f++)
                        for (int k = 0; k < pc->faces[f].nverts; k++)
                            if (pc->faces[f].verts[k] == v) cn_copy3(normals[nn++], pc->faces[f].normal);
                }
                for (int k = 0; k < nn; k++) {
                    double sc = cn_dot3(vel, normals[k]);
                    if (sc <= 0) continue;
                    if (nf == cap) {
                        cap *= 2;
                        FC *n2 = cn_realloc(fc, sizeof(FC) * (size_t)cap);
                        if (!n2) break;
                        fc = n2;
                    }
                    fc[nf].f.part = p;
                    cn_copy3(fc[nf].f.point, pc->verts[v]);
                    for (int q = 0; q < 3; q++) fc[nf].f.normal[q] = -normals[k][q];
                    fc[nf].score = sc;
                    nf++;
                }
            }
        }
    }
    cn_step_result_free(&r);
    if (!fc) return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    for (int i = 1; i < nf; i++) /* best first */
        for (int j = i; j > 0 && fc[j - 1].score < fc[j].score; j--) {
            FC x = fc[j];
            fc[j] = fc[j - 1];
            fc[j - 1] = x;
        }
    if (nf > 10) nf = 10;
    cnAssembly copy = *a;
    cnFixel *fx = cn_malloc(sizeof(cnFixel) * (size_t)(a->nfixels + 2));
    if (!fx) {
        cn_free(fc);
        return cn_diag_set(P->diag, CN_ERR_MEMORY, "", "out of memory");
    }
    if (a->nfixels > 0) memcpy(fx, a->fixels, sizeof(cnFixel) * (size_t)a->nfixels);
    copy.fixels = fx;
    bool found = false;
    for (int size = 1; size <= 2 && !found; size++)
        for (int i = 0; i < nf && !found; i++)
            for (int j = size == 1 ? i : i + 1; j < (size == 1 ? i + 1 : nf) && !found; j++) {
                fx[a->nfixels] = fc[i].f;
                if (size == 2) fx[a->nfixels + 1] = fc[j].f;
                copy.nfixels = a->nfixels + size;
                set_absent(P, present);
                s = cn_simulate_step(&copy, P->absent, &st, &P->o->sim, &r, P->diag);
                P->nsims++;
                if (s) {
                    cn_free(fx);
                    cn_free(fc);
                    return s;
                }
                if (r.status == CN_STEP_STABLE) {
                    found = true;
                    cnFixelSuggestion *na = grow(O, out->items, out->n, &out->cap, sizeof *na);
                    if (na) {
                        out->items = na;
                        cnFixelSuggestion *fs = &na[out->n++];
                        fs->step = move_of(O, t);
                        fs->nfixels = size;
                        for (int q = 0; q < size; q++) fs->fixels[q] = fx[a->nfixels + q];
                    }
                }
                cn_step_result_free(&r);
            }
    cn_free(fx);
    cn_free(fc);
    return CN_OK;
}

/* Path dependence: for each explored state and part with two or more paths tried, which were
 * stable. */
static void harvest_choices(Out *O, cnPlanResult *out) {
    Planner *P = O->P;
    cnPlanPathChoice *ch = NULL;
    int nch = 0, cap = 0;
    for (int si = 0; si < P->nst && !O->nomem; si++) {
        State *S = &P->st[si];
        for (int b = 0; b < P->nfree; b++) {
            int nst = 0, nun = 0, nall = 0;
            for (int k = 0; k < S->ntrans; k++) {
                Trans *t = &P->tr[S->first + k];
                if (t->move != 1ULL << b) continue;
                nall++;
                if (t->status == CN_STEP_STABLE) nst++;
                else if (t->status == CN_STEP_UNSTABLE) nun++;
            }
            if (nst + nun < 2) continue;
            cnPlanPathChoice *na = grow(O, ch, nch, &cap, sizeof *na);
            cnPlanMove *mv = out_alloc(O, (size_t)nall, sizeof(cnPlanMove));
            if (!na || !mv) break;
            ch = na;
            cnPlanPathChoice *d = &ch[nch++];
            d->remaining = mask_list(O, S->mask);
            d->part = P->part_of[b];
            d->path_dependent = nst > 0 && nun > 0;
            d->paths.steps = mv;
            for (int k = 0; k < S->ntrans; k++) {
                Trans *t = &P->tr[S->first + k];
                if (t->move == 1ULL << b) mv[d->paths.n++] = move_of(O, t);
            }
        }
    }
    out->nchoices = nch;
    out->choices = ch;
}

/* No stable plan: every first move and why it fails, and fixels that would make one stable. */
static cnStatus harvest_dead_ends(Out *O, int root, cnPlanResult *out) {
    Planner *P = O->P;
    State *S = &P->st[root];
    out->unstable_at_start = S->stable == 0;
    out->undecided_at_start = S->stable == 0 && S->undecided;
    cnPlanMove *dead = out_alloc(O, (size_t)S->ntrans, sizeof(cnPlanMove));
    for (int k = 0; dead && k < S->ntrans; k++) dead[k] = move_of(O, &P->tr[S->first + k]);
    out->ndead = dead ? S->ntrans : 0;
    out->dead_ends = dead;
    FixList fix = {NULL, 0, 0};
    for (int k = 0; P->o->fixels && !P->budget && k < S->ntrans && fix.n < 5; k++) {
        const Trans *t = &P->tr[S->first + k];
        if (t->status != CN_STEP_UNSTABLE) continue;
        cnStatus s = suggest_fixels(O, S->mask, t, &fix);
        if (s) return s;
    }
    out->nfixels = fix.n;
    out->fixels = fix.items;
    return CN_OK;
}

/* The AND/OR tree and the splits of the two-handed search. */
static void harvest_subassemblies(Out *O, int root, cnPlanResult *out) {
    Planner *P = O->P;
    out->subassemblies = P->o->subassemblies;
    if (P->o->subassemblies) {
        out->nplans = P->st[root].sub_plans > 0 ? P->st[root].sub_plans : 0;
        if (P->st[root].sub_plans > 0) {
            cnPlanNode *tree = out_alloc(O, 1, sizeof(cnPlanNode));
            if (tree) *tree = tree_of(O, root);
            out->tree = tree;
        }
        cnPlanSplit *sp;
        int nsp;
        splits_of(O, root, &sp, &nsp);
        out->splits = sp;
        out->nsplits = nsp;
    }
}

/* The typed result, read off the solved states (the order of the steps matters: listing may
 * add states, which the search counts). */
static cnStatus harvest(Out *O, int root, Trans **stack, cnPlanResult *out) {
    Planner *P = O->P;
    O->memo = cn_calloc((size_t)P->ntr + 1, sizeof(cnPlanMove));
    if (!O->memo) O->nomem = true;
    out_alloc(O, 1, 1); /* a result always has its memory (mem_ set): the report checks it */
    bool stable = P->st[root].solved == 1 || (P->o->subassemblies && P->st[root].sub_plans > 0);
    out->stable = stable;
    out->stable_single_part = P->st[root].solved == 1;
    int limit = P->o->all ? 100000 : P->o->list_limit;
    SeqList seqs = {NULL, 0, 0, limit};
    list_sequences(O, root, stack, 0, &seqs);
    out->nlisted = seqs.n;
    out->sequences = seqs.items;
    /* stable orders of the parts (paths aside), as the paper counts them */
    {
        int *ostack = cn_calloc((size_t)P->nfree + 2, sizeof(int));
        OrderList orders = {NULL, 0, 0, limit};
        if (ostack) list_orders(O, root, ostack, 0, &orders);
        else O->nomem = true;
        cn_free(ostack);
        out->nlisted_orders = orders.n;
        out->orders = orders.items;
        out->norders = count_orders(P, root);
    }
    /* the best plan, replayable: the first stable sequence (each step the first stable move
     * into a state that comes apart) */
    out->best_plan = seqs.n > 0 ? &seqs.items[0] : NULL;
    RowList rows = {NULL, 0, 0, P->o->all ? 100000 : P->o->table_limit};
    table_rows(O, root, stack, 0, &rows);
    out->nrows = rows.n;
    out->table = rows.items;
    harvest_choices(O, out);
    if (!stable) {
        cnStatus s = harvest_dead_ends(O, root, out);
        if (s) return s;
    }
    harvest_subassemblies(O, root, out);
    return CN_OK;
}

cnStatus cn_plan(const cnAssembly *a, const cnPlanOptions *opt, cnPlanResult *out, cnDiag *diag) {
    cnPlanOptions o = opt ? *opt : cn_plan_options_default();
    memset(out, 0, sizeof *out);
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    Planner P;
    memset(&P, 0, sizeof P);
    P.t0 = t0;
    P.a = a;
    P.o = &o;
    P.diag = diag;
    P.gen.a = a;
    P.gen.o = &o;
    P.gen.diag = diag;
    int nfree = 0;
    for (int i = 0; i < a->nreal; i++) nfree += !a->parts[i].fixed;
    if (nfree > PLAN_MAX_EXHAUSTIVE && !o.subassemblies && !o.exhaustive)
        return cn_plan_large(a, &o, out, diag);
    if (nfree > PLAN_MAX_PARTS) { /* one bit per free part in a state's set */
        const char *who = o.subassemblies ? "the two-handed planner (subassemblies)" : "the exhaustive search";
        const char *drop = !o.subassemblies ? "--exhaustive"
                           : o.exhaustive   ? "subassemblies and without --exhaustive"
                                            : "subassemblies";
        return cn_diag_set(diag, CN_ERR_INPUT, "parts",
                           "%s handles at most %d free parts (this assembly has %d); plan without %s, "
                           "or mark the parts that stay in place \"fixed\": true and plan the rest",
                           who, PLAN_MAX_PARTS, nfree, drop);
    }
    for (int i = 0; i < a->nreal; i++)
        if (!a->parts[i].fixed) P.part_of[P.nfree++] = i;
    P.hmask = 1023;
    P.hash = cn_calloc(P.hmask + 1, sizeof(int));
    P.absent = cn_malloc((size_t)a->nparts + 1);
    P.moving = cn_malloc((size_t)a->nparts + 1);
    P.still = cn_calloc((size_t)a->nparts + 1, 1);
    P.role = cn_calloc((size_t)a->nparts + 1, 1);
    cnStatus s = CN_OK;
    Out O = {&P, NULL, NULL, false};
    Trans **stack = cn_calloc((size_t)P.nfree + 2, sizeof(Trans *));
    if (!P.hash || !P.absent || !P.moving || !P.still || !P.role || !stack) {
        s = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
        goto done;
    }
    if (o.subassemblies) { /* which free parts touch (states never move a part) */
        cnContactSet cs;
        memset(&cs, 0, sizeof cs);
        int np = a->nparts, *bit_of = cn_malloc(sizeof(int) * (size_t)(np + 1));
        if (!bit_of) {
            s = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
            goto done;
        }
        for (int i = 0; i < np; i++) bit_of[i] = -1;
        for (int b = 0; b < P.nfree; b++) bit_of[P.part_of[b]] = b;
        s = cn_contacts_find(a, NULL, &cs, NULL, diag);
        for (int k = 0; !s && k < cs.count; k++) {
            int p1 = cs.items[k].body1, p2 = cs.items[k].body2;
            if (p1 < 0 || p2 < 0 || p1 >= np || p2 >= np || bit_of[p1] < 0 || bit_of[p2] < 0) continue;
            P.touch[bit_of[p1]] |= 1ULL << bit_of[p2];
            P.touch[bit_of[p2]] |= 1ULL << bit_of[p1];
        }
        cn_contacts_free(&cs);
        cn_free(bit_of);
        if (s) goto done;
    }
    Mask full = P.nfree == 64 ? ~0ULL : (1ULL << P.nfree) - 1;
    int root = state_of(&P, full);
    if (root < 0 || (s = solve(&P, root, 0))) goto done;
    if (o.subassemblies && (s = solve_sub(&P, root))) goto done;

    if ((s = harvest(&O, root, stack, out))) goto done;
    double wall = cn_seconds_since(&t0);
    cnPlanSearch *se = &out->search;
    se->free_parts = P.nfree;
    se->states = P.nst;
    se->simulations = P.nsims;
    se->exhaustive = !P.truncated;
    se->splits_capped = P.splits_capped;
    se->budget_reached = P.budget;
    se->out_of_time = P.budget && P.out_of_time;
    se->max_states = o.max_states;
    se->timing = o.timing;
    se->seconds = wall;
    se->threads = o.parallel ? 2 : 1;
    for (int i = 0; i < P.nst; i++) se->undecided_states += P.st[i].undecided;
    for (int i = 0; i < P.ntr; i++) se->undecided_moves += P.tr[i].status == CN_STEP_UNDECIDED;
    if (O.nomem) {
        s = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
        goto done;
    }
    out->nsequences = P.st[root].ways;
    out->mem_ = O.mem;
    O.mem = NULL;
done:
    if (s) memset(out, 0, sizeof *out);
    cn_arena_free(O.mem);
    cn_free(O.memo);
    cn_free(stack);
    cn_free(P.st);
    cn_free(P.hash);
    cn_free(P.tr);
    cn_free(P.absent);
    cn_free(P.moving);
    cn_free(P.still);
    cn_free(P.role);
    cn_cands_free(&P.gen);
    return s;
}
