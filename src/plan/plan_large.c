/* Planning past the exhaustive search (more than 16 free parts, any number of them): one stable
 * single-part plan, found depth-first.
 *
 * The exhaustive planner (plan.c) simulates every candidate path of every part of a state before
 * it goes deeper: from a wall of 100 bricks, hundreds of simulations per state. Here a state's
 * moves are tried lazily, best first, and the first that works is followed:
 *  - the parts are ordered by how high their top is against gravity (ties: file order), the way
 *    a wall or a stack comes apart from the top; a part whose removal leaves a state that is not
 *    stable costs one check and no simulation (Proposition 1: every path of it is unstable);
 *  - otherwise its candidate paths (cands.c: "up" first) are simulated (Algorithm 1) one after
 *    another until one is stable, and the search goes on from the state it leads to; the other
 *    paths lead to the same state and are not tried;
 *  - a state from which no plan leads is remembered (a hash set of the states' bit sets), so that
 *    no other order reaching it explores it again.
 * The search is bounded by cnPlanOptions.max_states (states checked) and max_seconds, and says
 * what it explored. Each state's verdict is cn_check's, as in the exhaustive planner: an
 * undecided friction verdict is not stable. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cands.h"
#include "plan_large.h"
#include "sim_planner.h"

/* The first pass over a part's paths gives the search for a motion from rest this many LPs (a
 * path it leaves undecided is tried again with the options' budget, when no other path is
 * stable). An undecided path is often followed by a stable one (in a running-bond wall with
 * friction a brick lifted straight up slides along its neighbours, undecided, and one lifted up
 * and away at an angle is stable): so the first pass spends little on each path, and the full
 * budget only where no path is stable. */
#define LARGE_QUICK_NODES 25
/* Seconds between two calls of the progress callback, at least (as plan.c). */
#define LARGE_PROGRESS_SECONDS 0.25

typedef uint64_t Word;

/* A move tried from the root, kept for the report when no plan is found. */
typedef struct {
    int bit;
    cnCand cand;
    cnStepStatus status;
    bool prop1;
    double time;
    int *moving, nmoving; /* cn_malloc'd */
    int blocking;
} Tried;

typedef struct {
    int bit;
    cnCand cand;
} Step;

typedef struct {
    const cnAssembly *a;
    const cnPlanOptions *o;
    cnDiag *diag;
    cnCandGen gen;
    int nfree, nw;          /* free parts; words per state */
    int *part_of;           /* bit -> part index */
    int *order;             /* bits, the highest part first */
    /* states: their bit sets (nw words each), verdicts and whether a plan leads from them */
    Word *keys;
    signed char *stable;    /* -1 unknown */
    unsigned char *dead;    /* bit 1: no plan from here (fully explored); bit 2: the parts of
                               `allowed` cannot all be taken out from here (the current run) */
    const Word *allowed;    /* the parts a run of descend() takes out (a component), or NULL */
    unsigned char *undecided;
    int **falls;            /* not stable: the parts that start to move (count first) */
    int nst, capst;
    int *hash;              /* open addressing: state index + 1, 0 empty */
    size_t hmask;
    unsigned char *absent, *moving;
    Step *path;             /* the plan being built, one step per depth */
    Tried *tried;           /* the root's moves */
    int ntried, captried;
    int nsims, undecided_moves;
    bool friction;          /* some contact may have friction: paths that open every contact first */
    bool budget, out_of_time;
    struct timespec t0;
    double progress_at;
} Large;

static bool has(const Word *s, int b) { return s[b >> 6] >> (b & 63) & 1; }
static void clear_bit(Word *s, int b) { s[b >> 6] &= ~((Word)1 << (b & 63)); }
static void set_bit(Word *s, int b) { s[b >> 6] |= (Word)1 << (b & 63); }

static size_t hash_words(const Word *s, int nw) {
    uint64_t h = 0x9e3779b97f4a7c15ULL;
    for (int i = 0; i < nw; i++) {
        h ^= s[i] + 0x9e3779b97f4a7c15ULL + (h << 6) + (h >> 2);
        h ^= h >> 33;
        h *= 0xff51afd7ed558ccdULL;
    }
    h ^= h >> 33;
    return (size_t)h;
}

static cnStatus nomem(Large *L) { return cn_diag_oom(L->diag); }

static size_t key_hash(const void *ctx, int k) {
    const Large *L = ctx;
    return hash_words(&L->keys[(size_t)k * L->nw], L->nw);
}

/* The index of state s, added when new; -1 out of memory. */
static int state_index(Large *L, const Word *s) {
    int nw = L->nw;
    size_t i = hash_words(s, nw) & L->hmask;
    while (L->hash[i]) {
        int k = L->hash[i] - 1;
        if (!memcmp(&L->keys[(size_t)k * nw], s, sizeof(Word) * (size_t)nw)) return k;
        i = (i + 1) & L->hmask;
    }
    if (L->nst == L->capst) {
        int nc = L->capst ? 2 * L->capst : 256;
        Word *nk = cn_realloc(L->keys, sizeof(Word) * (size_t)nc * (size_t)nw);
        if (nk) L->keys = nk;
        signed char *ns = cn_realloc(L->stable, (size_t)nc);
        if (ns) L->stable = ns;
        unsigned char *nd = cn_realloc(L->dead, (size_t)nc);
        if (nd) L->dead = nd;
        unsigned char *nu = cn_realloc(L->undecided, (size_t)nc);
        if (nu) L->undecided = nu;
        int **nf = cn_realloc(L->falls, sizeof(int *) * (size_t)nc);
        if (nf) L->falls = nf;
        if (!nk || !ns || !nd || !nu || !nf) return -1;
        L->capst = nc;
    }
    size_t before = L->hmask;
    if (cn_hash_room(&L->hash, &L->hmask, L->nst, key_hash, L)) return -1;
    if (L->hmask != before) i = cn_hash_free_slot(L->hash, L->hmask, hash_words(s, nw));
    int k = L->nst++;
    memcpy(&L->keys[(size_t)k * nw], s, sizeof(Word) * (size_t)nw);
    L->stable[k] = -1;
    L->dead[k] = 0;
    L->undecided[k] = 0;
    L->falls[k] = NULL;
    L->hash[i] = k + 1;
    return k;
}

static void set_absent(Large *L, const Word *present) {
    const cnAssembly *a = L->a;
    for (int i = 0; i < a->nparts; i++) L->absent[i] = a->parts[i].gripper_step >= 0;
    for (int b = 0; b < L->nfree; b++) L->absent[L->part_of[b]] = !has(present, b);
}

static bool out_of_budget(Large *L) {
    double t = cn_seconds_since(&L->t0);
    if (L->o->progress &&
        t - L->progress_at >= (L->o->progress_every > 0 ? L->o->progress_every : LARGE_PROGRESS_SECONDS)) {
        L->progress_at = t;
        L->o->progress(L->o->progress_ctx, (long)L->nst, (long)L->nsims, t);
    }
    bool out = L->o->max_states > 0 && L->nst > L->o->max_states;
    if (!out && L->o->max_seconds > 0) out = L->out_of_time = t > L->o->max_seconds;
    if (out) L->budget = true;
    return out;
}

/* Is state si stable (cn_check on its parts)? */
static cnStatus state_stable(Large *L, int si, bool *stable) {
    if (L->stable[si] >= 0) {
        *stable = L->stable[si];
        return CN_OK;
    }
    set_absent(L, &L->keys[(size_t)si * L->nw]);
    cnContactQuery q = {NULL, L->absent, NULL};
    cnCheckOptions co = L->o->sim.check;
    co.query = &q;
    co.motion = NULL;
    co.overlap_is_result = true;
    co.lp_crosscheck = true; /* as the simulator's check of a state at rest */
    cnCheckResult r;
    cnStatus s = cn_check(L->a, &co, &r, L->diag);
    if (s) return s;
    bool settled = !r.infeasible && r.nmoving == 0;
    L->undecided[si] = settled && r.verdict == CN_VERDICT_UNDECIDED;
    *stable = settled && !L->undecided[si];
    if (!*stable && r.nmoving > 0) {
        int *f = cn_malloc(sizeof(int) * (size_t)(r.nmoving + 1));
        if (!f) {
            cn_check_result_free(&r);
            return nomem(L);
        }
        f[0] = r.nmoving;
        memcpy(f + 1, r.moving, sizeof(int) * (size_t)r.nmoving);
        L->falls[si] = f;
    }
    cn_check_result_free(&r);
    L->stable[si] = *stable;
    return CN_OK;
}

/* Simulate part bit b leaving state `present` along cand. */
static cnStatus simulate(Large *L, const Word *present, int b, const cnCand *cand, long nodes,
                         cnStepResult *r) {
    int part = L->part_of[b];
    cnPlanStep st;
    memset(&st, 0, sizeof st);
    st.nmove = st.ngrip = 1;
    st.move = st.grip = &part;
    st.nseg = cand->nseg;
    st.seg = (cnSegment *)cn_cand_seg(cand); /* read only: cn_simulate_step takes the step const */
    st.path_given = true;
    st.support = cand->support;
    st.gripper = -1;
    set_absent(L, present);
    cnSimOptions so = L->o->sim;
    if (nodes > 0) so.check.max_nodes = nodes;
    /* descend() checked the state it leads to */
    cnStatus s = cn_sm_simulate_step(L->a, L->absent, &st, &so, true, r, L->diag);
    L->nsims++;
    return s;
}

/* Record a move from the root (at entry k, replacing it: the move simulated again; k < 0: a new
 * entry). */
static cnStatus remember(Large *L, int k, int b, const cnCand *cand, cnStepStatus status, bool prop1,
                         double time, const int *moving, int nmoving, int blocking) {
    if (k >= 0) {
        cn_free(L->tried[k].moving);
        L->tried[k].moving = NULL;
    } else if (L->ntried == L->captried) {
        int nc = L->captried ? 2 * L->captried : 32;
        Tried *n = cn_realloc(L->tried, sizeof(Tried) * (size_t)nc);
        if (!n) return nomem(L);
        L->tried = n;
        L->captried = nc;
    }
    Tried *t = &L->tried[k >= 0 ? k : L->ntried++];
    memset(t, 0, sizeof *t);
    t->bit = b;
    if (cand) t->cand = *cand;
    else snprintf(t->cand.name, sizeof t->cand.name, "any path");
    t->status = status;
    t->prop1 = prop1;
    t->time = time;
    t->blocking = blocking;
    if (nmoving > 0) {
        t->moving = cn_malloc(sizeof(int) * (size_t)nmoving);
        if (!t->moving) return nomem(L);
        memcpy(t->moving, moving, sizeof(int) * (size_t)nmoving);
        t->nmoving = nmoving;
    }
    return CN_OK;
}

/* Depth-first from state `present` (si its index, known stable): *found when a plan leads from
 * it (L->path[depth ..] then holds it). */
static cnStatus descend(Large *L, Word *present, int si, int depth, bool *found) {
    *found = false;
    int left = 0;
    unsigned char mark = L->allowed ? 2 : 1;
    for (int b = 0; b < L->nfree; b++) left += has(present, b) && (!L->allowed || has(L->allowed, b));
    if (left == 0) {
        *found = true;
        return CN_OK;
    }
    if (out_of_budget(L)) return CN_OK;
    for (int k = 0; k < L->nfree && !L->budget; k++) {
        int b = L->order[k];
        if (!has(present, b) || (L->allowed && !has(L->allowed, b))) continue;
        clear_bit(present, b);
        int nx = state_index(L, present);
        bool after = false;
        cnStatus s = nx < 0 ? nomem(L) : state_stable(L, nx, &after);
        set_bit(present, b);
        if (s) return s;
        if (!after) { /* Proposition 1 */
            if (L->undecided[nx]) L->undecided_moves++; /* a move into an undecided state */
            if (depth == 0) {
                const int *f = L->falls[nx];
                s = remember(L, -1, b, NULL, L->undecided[nx] ? CN_STEP_UNDECIDED : CN_STEP_UNSTABLE, true, NAN,
                             f ? f + 1 : NULL, f ? f[0] : 0, -1);
                if (s) return s;
            }
            continue;
        }
        if (L->dead[nx] & mark) continue;
        set_absent(L, present);
        memset(L->moving, 0, (size_t)L->a->nparts);
        L->moving[L->part_of[b]] = 1;
        cnCand *c;
        int nc;
        if ((s = cn_cands(&L->gen, L->absent, L->moving, L->part_of[b], L->friction, &c, &nc))) return s;
        /* two passes: first each path with a small budget for the search for a motion from
           rest (a gripped part sliding along its neighbours is the costly case, and another
           path often opens every contact instead), then the paths left undecided with the
           options' budget */
        unsigned char *undecided = cn_calloc((size_t)nc + 1, 1);
        int *rec = cn_malloc(sizeof(int) * (size_t)(nc + 1)); /* each path's entry in L->tried */
        if (!undecided || !rec) s = nomem(L);
        long user = L->o->sim.check.max_nodes, quick = user > 0 && user < LARGE_QUICK_NODES ? user : LARGE_QUICK_NODES;
        bool moved = false, again = false;
        for (int pass = 0; pass < 2 && !s && !moved && !L->budget; pass++) {
            if (pass == 1 && (!again || (user > 0 && user <= quick))) break;
            for (int j = 0; j < nc && !L->budget; j++) {
                if (pass == 1 && !undecided[j]) continue;
                cnStepResult r;
                if ((s = simulate(L, present, b, &c[j], pass == 0 ? quick : 0, &r))) break;
                cnStepStatus status = r.status;
                undecided[j] = status == CN_STEP_UNDECIDED;
                again |= undecided[j];
                if (pass == 1 && status != CN_STEP_UNDECIDED) L->undecided_moves--; /* decided now */
                if (pass == 0 && status == CN_STEP_UNDECIDED) L->undecided_moves++;
                if (depth == 0) {
                    if (pass == 0) rec[j] = L->ntried;
                    s = remember(L, pass == 1 ? rec[j] : -1, b, &c[j], status, false, r.onset_time,
                                 status == CN_STEP_UNSTABLE ? r.onset.moving : NULL,
                                 status == CN_STEP_UNSTABLE ? r.onset.nmoving : 0,
                                 status == CN_STEP_INFEASIBLE ? r.blocking_part : -1);
                }
                cn_step_result_free(&r);
                if (s) break;
                if (status != CN_STEP_STABLE) continue;
                moved = true;
                L->path[depth].bit = b;
                L->path[depth].cand = c[j];
                clear_bit(present, b);
                s = descend(L, present, nx, depth + 1, found);
                set_bit(present, b);
                break; /* the other paths lead to the same state */
            }
        }
        cn_free(undecided);
        cn_free(rec);
        cn_free(c);
        if (s || *found) return s;
    }
    if (!L->budget) L->dead[si] |= mark;
    return CN_OK;
}

/* Independent groups first. The free parts that touch one another, directly or through other
 * free parts, form components; two components share no contact, so neither's stability depends
 * on the other (only their paths may meet). When the assembly has two or more, each is taken out
 * whole in turn (the highest first, the others staying where they are), a component that cannot
 * be taken out now tried again after the others have gone: a trap in one component no longer
 * makes the depth-first search go through every subset of the others. *found: every component
 * came out (L->path[0 .. nfree) holds the plan); else the caller searches the whole assembly. */
static cnStatus by_components(Large *L, Word *full, int root, bool *found) {
    *found = false;
    const cnAssembly *a = L->a;
    int nf = L->nfree, nw = L->nw;
    int *comp = cn_malloc(sizeof(int) * (size_t)(nf + 1)), *bit_of = cn_malloc(sizeof(int) * (size_t)(a->nparts + 1));
    Word *cur = cn_malloc(sizeof(Word) * (size_t)nw), *allowed = cn_calloc((size_t)nw, sizeof(Word));
    unsigned char *done = cn_calloc((size_t)nf + 1, 1);
    cnContactSet cs;
    memset(&cs, 0, sizeof cs);
    cnStatus s = CN_OK;
    if (!comp || !bit_of || !cur || !allowed || !done) {
        s = nomem(L);
        goto out;
    }
    for (int i = 0; i < a->nparts; i++) bit_of[i] = -1;
    for (int b = 0; b < nf; b++) bit_of[L->part_of[b]] = b, comp[b] = b;
    set_absent(L, full);
    cnContactQuery q = {NULL, L->absent, NULL};
    if ((s = cn_contacts_find(a, &q, &cs, NULL, L->diag))) goto out;
    for (int k = 0; k < cs.count; k++) { /* union-find, by the smaller root */
        int p1 = cs.items[k].body1, p2 = cs.items[k].body2;
        if (p1 < 0 || p2 < 0 || p1 >= a->nparts || p2 >= a->nparts || bit_of[p1] < 0 || bit_of[p2] < 0) continue;
        int r1 = bit_of[p1], r2 = bit_of[p2];
        while (comp[r1] != r1) r1 = comp[r1] = comp[comp[r1]];
        while (comp[r2] != r2) r2 = comp[r2] = comp[comp[r2]];
        if (r1 != r2) comp[r1 > r2 ? r1 : r2] = r1 < r2 ? r1 : r2;
    }
    int ncomp = 0;
    for (int b = 0; b < nf; b++) {
        int r = b;
        while (comp[r] != r) r = comp[r];
        comp[b] = r;
        ncomp += r == b;
    }
    if (ncomp < 2) goto out;
    /* the components in the order of their highest parts (done[] marks them seen, then is
       cleared) */
    int nc = 0, *corder = bit_of; /* bit_of is no longer needed */
    for (int k = 0; k < nf; k++) {
        int c = comp[L->order[k]];
        if (!done[c]) done[c] = 1, corder[nc++] = c;
    }
    memset(done, 0, (size_t)nf + 1);
    memcpy(cur, full, sizeof(Word) * (size_t)nw);
    int depth = 0, si = root, left = ncomp;
    for (bool progress = true; progress && left > 0 && !L->budget;) {
        progress = false;
        for (int k = 0; k < ncomp && !progress && !L->budget; k++) {
            int c = corder[k];
            if (done[c]) continue;
            int size = 0;
            memset(allowed, 0, sizeof(Word) * (size_t)nw);
            for (int b = 0; b < nf; b++)
                if (comp[b] == c) set_bit(allowed, b), size++;
            for (int i = 0; i < L->nst; i++) L->dead[i] &= (unsigned char)~2;
            L->allowed = allowed;
            bool out_all = false;
            s = descend(L, cur, si, depth, &out_all);
            L->allowed = NULL;
            if (s) goto out;
            if (!out_all) continue;
            for (int b = 0; b < nf; b++)
                if (comp[b] == c) clear_bit(cur, b);
            depth += size;
            if ((si = state_index(L, cur)) < 0) {
                s = nomem(L);
                goto out;
            }
            done[c] = 1;
            left--;
            progress = true;
        }
    }
    *found = left == 0;
out:
    cn_contacts_free(&cs);
    cn_free(comp);
    cn_free(bit_of);
    cn_free(cur);
    cn_free(allowed);
    cn_free(done);
    return s;
}

/* ---- the result ---- */

typedef struct {
    Large *L;
    cnArena *mem;
    bool nomem;
} Out;

static void *out_alloc(Out *O, size_t count, size_t size) {
    void *p = cn_arena_alloc(&O->mem, count ? count : 1, size);
    if (!p) O->nomem = true;
    return p;
}

static cnPartList part_list(Out *O, const int *idx, int n) {
    cnPartList l = {0, NULL};
    int *x = out_alloc(O, (size_t)n, sizeof(int));
    if (!x) return l;
    if (n > 0) memcpy(x, idx, sizeof(int) * (size_t)n);
    for (int i = 1; i < n; i++) /* ascending */
        for (int j = i; j > 0 && x[j - 1] > x[j]; j--) {
            int t = x[j];
            x[j] = x[j - 1], x[j - 1] = t;
        }
    l.n = n;
    l.idx = x;
    return l;
}

static cnPlanMove move_of(Out *O, int bit, const cnCand *cand, cnStepStatus status, bool prop1,
                          double time, const int *moving, int nmoving, int blocking) {
    cnPlanMove mv;
    memset(&mv, 0, sizeof mv);
    int part = O->L->part_of[bit];
    mv.move = part_list(O, &part, 1);
    mv.path = cn_arena_strdup(&O->mem, cn_cand_name(cand));
    if (!mv.path) O->nomem = true;
    mv.nseg = prop1 ? 0 : cand->nseg;
    cnSegment *seg = out_alloc(O, (size_t)mv.nseg, sizeof(cnSegment));
    if (seg && mv.nseg > 0) memcpy(seg, cn_cand_seg(cand), sizeof(cnSegment) * (size_t)mv.nseg);
    mv.seg = seg;
    mv.support = cand->support;
    mv.grip = -1;
    mv.status = status;
    mv.proposition_1 = prop1;
    mv.time = prop1 ? NAN : time;
    if (status == CN_STEP_UNSTABLE) mv.moving = part_list(O, moving, nmoving);
    mv.blocked_by = status == CN_STEP_INFEASIBLE ? blocking : -1;
    return mv;
}

static void harvest(Out *O, bool found, bool root_stable, bool root_undecided, cnPlanResult *out) {
    Large *L = O->L;
    int n = L->nfree;
    out->stable = out->stable_single_part = found;
    out_alloc(O, 1, 1); /* a result always has its memory */
    if (found) {
        cnPlanMove *steps = out_alloc(O, (size_t)n, sizeof(cnPlanMove));
        cnPlanSequence *seq = out_alloc(O, 1, sizeof(cnPlanSequence));
        cnPartList *order = out_alloc(O, 1, sizeof(cnPartList));
        int *idx = out_alloc(O, (size_t)n, sizeof(int));
        cnPlanRow *row = out_alloc(O, 1, sizeof(cnPlanRow));
        if (!steps || !seq || !order || !idx || !row) return;
        for (int d = 0; d < n; d++) {
            steps[d] = move_of(O, L->path[d].bit, &L->path[d].cand, CN_STEP_STABLE, false, NAN, NULL, 0, -1);
            idx[d] = L->part_of[L->path[d].bit];
        }
        seq->n = n;
        seq->steps = steps;
        order->n = n;
        order->idx = idx;
        row->seq = *seq;
        row->end = CN_ROW_STABLE;
        out->nsequences = out->norders = 1; /* found, at least */
        out->nlisted = out->nlisted_orders = 1;
        out->sequences = seq;
        out->orders = order;
        out->best_plan = seq;
        out->nrows = 1;
        out->table = row;
        return;
    }
    out->unstable_at_start = !root_stable;
    out->undecided_at_start = !root_stable && root_undecided;
    cnPlanMove *dead = out_alloc(O, (size_t)L->ntried, sizeof(cnPlanMove));
    cnPlanRow *rows = out_alloc(O, (size_t)L->ntried, sizeof(cnPlanRow));
    if (!dead || !rows) return;
    int nrows = 0, limit = L->o->all ? 100000 : L->o->table_limit;
    for (int k = 0; k < L->ntried; k++) {
        const Tried *t = &L->tried[k];
        dead[k] = move_of(O, t->bit, &t->cand, t->status, t->prop1, t->time, t->moving, t->nmoving, t->blocking);
        if (nrows < limit) {
            rows[nrows].seq.n = 1;
            rows[nrows].seq.steps = &dead[k];
            rows[nrows].end = t->status == CN_STEP_STABLE ? CN_ROW_NO_WAY_ON : CN_ROW_STEP_FAILS;
            if (t->status == CN_STEP_STABLE && L->budget) rows[nrows].end = CN_ROW_UNEXPLORED;
            nrows++;
        }
    }
    out->ndead = L->ntried;
    out->dead_ends = dead;
    out->nrows = nrows;
    out->table = rows;
}

/* The order to try the parts in: the highest top against gravity first (file order on ties,
 * heights within the contact tolerance being one height). */
typedef struct {
    double top;
    int bit;
} Key;

static int by_top(const void *x, const void *y) {
    const Key *a = x, *b = y;
    if (a->top != b->top) return a->top > b->top ? -1 : 1;
    return a->bit - b->bit;
}

static cnStatus order_parts(Large *L) {
    const cnAssembly *a = L->a;
    double up[3];
    cn_copy3(up, a->gravity);
    cn_scale3(up, -1.0 / cn_norm3(up));
    Key *key = cn_malloc(sizeof(Key) * (size_t)(L->nfree + 1));
    if (!key) return nomem(L);
    for (int b = 0; b < L->nfree; b++) {
        const cnPart *p = &a->parts[L->part_of[b]];
        double t = -INFINITY;
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nverts; v++) t = fmax(t, cn_dot3(up, p->pieces[s].verts[v]));
        key[b].top = a->contact_tol > 0 ? round(t / a->contact_tol) * a->contact_tol : t;
        key[b].bit = b;
    }
    qsort(key, (size_t)L->nfree, sizeof(Key), by_top);
    for (int b = 0; b < L->nfree; b++) L->order[b] = key[b].bit;
    cn_free(key);
    return CN_OK;
}

cnStatus cn_plan_large(const cnAssembly *a, const cnPlanOptions *o, cnPlanResult *out, cnDiag *diag) {
    memset(out, 0, sizeof *out);
    Large L;
    memset(&L, 0, sizeof L);
    clock_gettime(CLOCK_MONOTONIC, &L.t0);
    L.a = a;
    L.o = o;
    L.diag = diag;
    L.gen.a = a;
    L.gen.o = o;
    L.gen.diag = diag;
    cnStatus s = CN_OK;
    Out O = {&L, NULL, false};
    L.part_of = cn_malloc(sizeof(int) * (size_t)(a->nreal + 1));
    L.order = cn_malloc(sizeof(int) * (size_t)(a->nreal + 1));
    L.path = cn_calloc((size_t)a->nreal + 1, sizeof(Step));
    L.absent = cn_malloc((size_t)a->nparts + 1);
    L.moving = cn_malloc((size_t)a->nparts + 1);
    L.hmask = 1023;
    L.hash = cn_calloc(L.hmask + 1, sizeof(int));
    if (!L.part_of || !L.order || !L.path || !L.absent || !L.moving || !L.hash) {
        s = nomem(&L);
        goto done;
    }
    for (int i = 0; i < a->nreal; i++)
        if (!a->parts[i].fixed) L.part_of[L.nfree++] = i;
    L.friction = a->friction > 0;
    for (int i = 0; i < a->npairs; i++) L.friction |= a->pairs[i].mu > 0;
    L.nw = (L.nfree + 63) / 64;
    if (L.nw == 0) L.nw = 1;
    if ((s = order_parts(&L))) goto done;
    Word *full = cn_calloc((size_t)L.nw, sizeof(Word));
    if (!full) {
        s = nomem(&L);
        goto done;
    }
    for (int b = 0; b < L.nfree; b++) set_bit(full, b);
    int root = state_index(&L, full);
    bool stable = false, found = false;
    s = root < 0 ? nomem(&L) : state_stable(&L, root, &stable);
    if (!s && stable) s = by_components(&L, full, root, &found);
    if (!s && stable && !found && !L.budget) {
        /* the whole assembly, its moves from the start recorded afresh */
        for (int i = 0; i < L.ntried; i++) cn_free(L.tried[i].moving);
        L.ntried = 0;
        s = descend(&L, full, root, 0, &found);
    }
    cn_free(full);
    if (s) goto done;
    harvest(&O, found, stable, root >= 0 && L.undecided[root], out);
    cnPlanSearch *se = &out->search;
    se->free_parts = L.nfree;
    se->states = L.nst;
    se->simulations = L.nsims;
    se->exhaustive = !found && !L.budget; /* no plan: every state reached stably was expanded */
    se->first_plan = true;
    se->budget_reached = L.budget;
    se->out_of_time = L.budget && L.out_of_time;
    se->max_states = o->max_states;
    se->timing = o->timing;
    se->seconds = cn_seconds_since(&L.t0);
    se->threads = 1;
    for (int i = 0; i < L.nst; i++) se->undecided_states += L.undecided[i];
    se->undecided_moves = L.undecided_moves;
    if (O.nomem) {
        s = nomem(&L);
        goto done;
    }
    out->mem_ = O.mem;
    O.mem = NULL;
done:
    if (s) memset(out, 0, sizeof *out);
    cn_arena_free(O.mem);
    for (int i = 0; i < L.nst; i++) cn_free(L.falls[i]);
    for (int i = 0; i < L.ntried; i++) cn_free(L.tried[i].moving);
    cn_free(L.tried);
    cn_free(L.falls);
    cn_free(L.keys);
    cn_free(L.stable);
    cn_free(L.dead);
    cn_free(L.undecided);
    cn_free(L.hash);
    cn_free(L.part_of);
    cn_free(L.order);
    cn_free(L.path);
    cn_free(L.absent);
    cn_free(L.moving);
    cn_cands_free(&L.gen);
    return s;
}
