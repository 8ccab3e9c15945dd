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
#include <pthread.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

#include "plan_state.h"
#include "sim_planner.h"
#include "solve.h"
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

/* The search's budgets: states explored (max_states) and wall time (max_seconds). When one is
 * spent the search is marked partial (and which budget it was). */
/* Seconds between two calls of the progress callback, at least (cnPlanOptions.progress_every). */
#define PLAN_PROGRESS_SECONDS 0.25

bool cn_pl_out_of_budget(Planner *P) {
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
bool cn_pl_first_only(const Planner *P) {
    return P->nfree > PLAN_MAX_EXHAUSTIVE && !P->o->exhaustive;
}

static size_t hash_mask(Mask m, int held) {
    m ^= (Mask)(held + 1) * 0x9e3779b97f4a7c15ULL;
    m ^= m >> 33;
    m *= 0xff51afd7ed558ccdULL;
    m ^= m >> 33;
    return (size_t)m;
}

static size_t state_hash(const void *ctx, int k) {
    const Planner *P = ctx;
    return hash_mask(P->st[k].mask, P->st[k].held);
}

/* The state of the parts `m`, on the supports (held = -1) or in a gripper holding bit `held`. */
int cn_pl_state_at(Planner *P, Mask m, int held) {
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
    size_t before = P->hmask;
    if (cn_hash_room(&P->hash, &P->hmask, P->nst, state_hash, P)) return -1;
    if (P->hmask != before) i = cn_hash_free_slot(P->hash, P->hmask, hash_mask(m, held));
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

int cn_pl_state_of(Planner *P, Mask m) { return cn_pl_state_at(P, m, -1); }

/* Flags the parts absent from a state (and, held in a gripper, the supports), and the parts held
 * still (the gripped one, or every one held whole). */
void cn_pl_set_absent_held(Planner *P, Mask present, int held) {
    const cnAssembly *a = P->a;
    for (int i = 0; i < a->nparts; i++)
        P->absent[i] = a->parts[i].gripper_step >= 0 || (held != -1 && a->parts[i].fixed);
    for (int b = 0; b < P->nfree; b++) P->absent[P->part_of[b]] = !(present >> b & 1);
    memset(P->still, 0, (size_t)a->nparts);
    if (held >= 0) P->still[P->part_of[held]] = 1;
    for (int b = 0; held == HELD_WHOLE && b < P->nfree; b++)
        if (present >> b & 1) P->still[P->part_of[b]] = 1;
}

void cn_pl_set_absent(Planner *P, Mask present) { cn_pl_set_absent_held(P, present, -1); }

cnStatus cn_pl_state_stable(Planner *P, int si, bool *stable) {
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
    cn_pl_set_absent_held(P, P->st[si].mask, held);
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
    co.lp_crosscheck = true; /* as the simulator's check of a state at rest (cn_sm_simulate_step) */
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
cnStatus cn_pl_candidates(Planner *P, Mask present, int held, Mask move, cnCand **out, int *n) {
    const cnAssembly *a = P->a;
    int single = -1, count = 0;
    for (int b = 0; b < P->nfree; b++)
        if (move >> b & 1) single = P->part_of[b], count++;
    if (count != 1) single = -1;
    cn_pl_set_absent_held(P, present, held);
    memset(P->moving, 0, (size_t)a->nparts);
    for (int b = 0; b < P->nfree; b++)
        if (move >> b & 1) P->moving[P->part_of[b]] = 1;
    return cn_cands(&P->gen, P->absent, P->moving, single, false, out, n);
}

/* A transition of `move` along `cand` (NULL: unnamed), not simulated yet. */
Trans cn_pl_trans_init(Mask move, const cnCand *cand, int grip, int from) {
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
cnStatus cn_pl_transition(Planner *P, Mask present, int held, Mask move, int grip,
                          const cnCand *cand, bool after_known, Trans *t) {
    const cnAssembly *a = P->a;
    *t = cn_pl_trans_init(move, cand, grip, -1);
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
    cn_pl_set_absent_held(P, present, held);
    for (int i = 0; i < nm; i++) P->still[mv[i]] = 0; /* held whole: the group taken out moves */
    st.still = held != -1 ? P->still : NULL;
    cnStepResult r;
    cnStatus s = cn_sm_simulate_step(a, P->absent, &st, &P->o->sim, after_known, &r, P->diag);
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

int cn_pl_push_trans(Planner *P, const Trans *t) {
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
        if (cn_pl_transition(&w->W, w->present, -1, w->jobs[i].move, -1, &w->jobs[i].cand, true, &w->res[i]) != CN_OK)
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
    for (int i = split; i < nj && !s; i++) s = cn_pl_transition(P, present, -1, jobs[i].move, -1, &jobs[i].cand, true, &res[i]);
    if (started) {
        pthread_join(th, NULL);
        cn_free(w.W.absent);
        cn_free(w.W.still);
        if (w.ok) P->nsims += w.W.nsims;
        else /* the worker failed: do its half here (errors are then reported here) */
            for (int i = 0; i < split && !s; i++)
                s = cn_pl_transition(P, present, -1, jobs[i].move, -1, &jobs[i].cand, true, &res[i]);
    }
    return s;
}

/* Single-part transitions of state si (computed once). */
cnStatus cn_pl_expand(Planner *P, int si) {
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
        s = cn_pl_candidates(P, m, -1, 1ULL << b, &c, &nc);
        if (s) break;
        /* Proposition 1: if the state without the part is not stable, every path is unstable */
        int nx = cn_pl_state_of(P, m & ~(1ULL << b));
        bool after = true;
        if (nx < 0) s = cn_diag_oom(P->diag);
        else s = cn_pl_state_stable(P, nx, &after);
        if (!s && !after && nc > 0) {
            Trans *np = cn_realloc(prop, sizeof(Trans) * (size_t)(nprop + nc));
            if (!np) s = cn_diag_oom(P->diag);
            for (int k = 0; !s && k < nc; k++) {
                prop = np;
                Trans *t = &prop[nprop++];
                *t = cn_pl_trans_init(1ULL << b, &c[k], -1, -1);
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
                    s = cn_diag_oom(P->diag);
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
    if (!s && !res) s = cn_diag_oom(P->diag);
    if (!s) s = run_jobs(P, m, jobs, nj, res);
    int first = P->ntr;
    for (int i = 0; i < nj && !s; i++)
        if (cn_pl_push_trans(P, &res[i]) < 0) s = cn_diag_oom(P->diag);
    for (int i = 0; i < nprop && !s; i++)
        if (cn_pl_push_trans(P, &prop[i]) < 0) s = cn_diag_oom(P->diag);
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
    cnStatus s = cn_pl_state_stable(P, si, &stable);
    if (s) return s;
    if (!stable) {
        P->st[si].solved = 0;
        P->st[si].ways = 0;
        return CN_OK;
    }
    if (cn_pl_out_of_budget(P)) { /* this state stays unexplored (not solved) */
        P->st[si].unexplored = true;
        P->st[si].solved = 0;
        P->st[si].ways = 0;
        return CN_OK;
    }
    if ((s = cn_pl_expand(P, si))) return s;
    double ways = 0;
    int first = P->st[si].first, n = P->st[si].ntrans;
    for (int k = 0; k < n; k++) {
        /* copy out: the recursion may move the transition array */
        cnStepStatus status = P->tr[first + k].status;
        Mask mv = P->tr[first + k].move;
        if (status != CN_STEP_STABLE) continue;
        int nx = cn_pl_state_of(P, m & ~mv);
        if (nx < 0) return cn_diag_oom(P->diag);
        if ((s = solve(P, nx, depth + 1))) return s;
        ways += P->st[nx].ways;
        if (cn_pl_first_only(P) && ways > 0) {
            P->truncated = true;
            break;
        }
    }
    P->st[si].ways = ways;
    P->st[si].solved = ways > 0;
    return CN_OK;
}

/* ---- subassemblies: the AND/OR search ---- */

/* The planner of assembly a with options o (kept by pointer: they must outlive it): its free
 * parts numbered and its work arrays made; -1 out of memory (cn_pl_free frees what was made). */
int cn_pl_init(Planner *P, const cnAssembly *a, const cnPlanOptions *o, cnDiag *diag) {
    memset(P, 0, sizeof *P);
    P->a = a;
    P->o = o;
    P->diag = diag;
    P->gen.a = a;
    P->gen.o = o;
    P->gen.diag = diag;
    for (int i = 0; i < a->nreal && P->nfree < PLAN_MAX_PARTS; i++)
        if (!a->parts[i].fixed) P->part_of[P->nfree++] = i;
    P->hmask = 1023;
    P->hash = cn_calloc(P->hmask + 1, sizeof(int));
    P->absent = cn_malloc((size_t)a->nparts + 1);
    P->moving = cn_malloc((size_t)a->nparts + 1);
    P->still = cn_calloc((size_t)a->nparts + 1, 1);
    P->role = cn_calloc((size_t)a->nparts + 1, 1);
    return P->hash && P->absent && P->moving && P->still && P->role ? 0 : -1;
}

/* Which free parts touch as loaded (P->touch), for the two-handed search: states never move a
 * part, so the contacts are found once. */
cnStatus cn_pl_find_touching(Planner *P) {
    const cnAssembly *a = P->a;
    int np = a->nparts, *bit_of = cn_malloc(sizeof(int) * (size_t)(np + 1));
    if (!bit_of) return cn_diag_oom(P->diag);
    for (int i = 0; i < np; i++) bit_of[i] = -1;
    for (int b = 0; b < P->nfree; b++) bit_of[P->part_of[b]] = b;
    cnContactSet cs;
    memset(&cs, 0, sizeof cs);
    cnStatus s = cn_contacts_find(a, NULL, &cs, NULL, P->diag);
    for (int k = 0; !s && k < cs.count; k++) {
        int p1 = cs.items[k].body1, p2 = cs.items[k].body2;
        if (p1 < 0 || p2 < 0 || p1 >= np || p2 >= np || bit_of[p1] < 0 || bit_of[p2] < 0) continue;
        P->touch[bit_of[p1]] |= 1ULL << bit_of[p2];
        P->touch[bit_of[p2]] |= 1ULL << bit_of[p1];
    }
    cn_contacts_free(&cs);
    cn_free(bit_of);
    return s;
}

/* Free what cn_pl_init and the search made. */
void cn_pl_free(Planner *P) {
    cn_free(P->st);
    cn_free(P->hash);
    cn_free(P->tr);
    cn_free(P->absent);
    cn_free(P->moving);
    cn_free(P->still);
    cn_free(P->role);
    cn_cands_free(&P->gen);
}

cnStatus cn_plan(const cnAssembly *a, const cnPlanOptions *opt, cnPlanResult *out, cnDiag *diag) {
    cnPlanOptions o = opt ? *opt : cn_plan_options_default();
    memset(out, 0, sizeof *out);
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    Planner P; /* made by cn_pl_init below, past the early returns */
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
    int ok = cn_pl_init(&P, a, &o, diag);
    P.t0 = t0;
    cnStatus s = CN_OK;
    Out O = {&P, NULL, NULL, false};
    Trans **stack = cn_calloc((size_t)P.nfree + 2, sizeof(Trans *));
    if (ok != 0 || !stack) {
        s = cn_diag_oom(diag);
        goto done;
    }
    if (o.subassemblies && (s = cn_pl_find_touching(&P))) goto done;
    Mask full = P.nfree == 64 ? ~0ULL : (1ULL << P.nfree) - 1;
    int root = cn_pl_state_of(&P, full);
    if (root < 0 || (s = solve(&P, root, 0))) goto done;
    if (o.subassemblies && (s = cn_pl_solve_sub(&P, root))) goto done;

    if ((s = cn_pl_harvest(&O, root, stack, out))) goto done;
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
        s = cn_diag_oom(diag);
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
    cn_pl_free(&P);
    return s;
}
