/* The plan's result, built from the search's states and transitions in one arena: sequences,
 * orders, trees, table rows, splits, path choices, dead ends and subassemblies. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "plan_state.h"
#include "solve.h"

static void *out_alloc(Out *O, size_t count, size_t size) {
    void *p = cn_arena_alloc(&O->mem, count, size);
    if (!p) O->nomem = true;
    return p;
}

static cnPartList mask_list(Out *O, Mask m) {
    cnPartList l = {0, NULL};
    int n = cn_pl_popcount(m);
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
cnPlanMove cn_pl_move_of(Out *O, const Trans *t) {
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
void *cn_pl_grow(Out *O, void *arr, int n, int *cap, size_t size) {
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
    cnPlanSequence *ni = cn_pl_grow(O, L->items, L->n, &L->cap, sizeof(cnPlanSequence));
    if (!ni) return;
    L->items = ni;
    int n = depth + (last ? 1 : 0);
    cnPlanMove *steps = out_alloc(O, (size_t)n, sizeof(cnPlanMove));
    if (!steps) return;
    for (int i = 0; i < depth; i++) steps[i] = cn_pl_move_of(O, stack[i]);
    if (last) steps[depth] = cn_pl_move_of(O, last);
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
    o.take_out = cn_pl_move_of(O, &P->tr[S->sub_choice]);
    int r1, r2;
    if (cn_pl_split_states(P, si, &t, &r1, &r2)) {
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
        int nx = cn_pl_state_of(P, S->mask & ~t->move);
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
        cnPartList *ni = cn_pl_grow(O, L->items, L->n, &L->cap, sizeof(cnPartList));
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
        int nx = cn_pl_state_of(P, S->mask & ~t->move);
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
    cnPlanRow *ni = cn_pl_grow(O, L->items, L->n, &L->cap, sizeof(cnPlanRow));
    cnPlanMove *steps = out_alloc(O, (size_t)n, sizeof(cnPlanMove));
    if (!ni || !steps) return;
    L->items = ni;
    for (int i = 0; i < n; i++) steps[i] = cn_pl_move_of(O, stack[i]);
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
        int nx = cn_pl_state_of(P, S->mask & ~t->move);
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
                if (again || cn_pl_split_states(P, si, &u, &r1, &r2)) continue;
                double n = P->st[r1].sub_plans > 0 ? P->st[r1].sub_plans : 0;
                if (r2 >= 0) n *= P->st[r2].sub_plans > 0 ? P->st[r2].sub_plans : 0;
                plans += n;
                if (n > 0 && ok < 0) ok = j;
                else if (ok < 0 && P->tr[tried].status != CN_STEP_STABLE) tried = j;
            }
            if ((pass == 0) != (ok >= 0)) continue;
            done[nd++] = key;
            cnPlanSplit *na = cn_pl_grow(O, *out, *nout, &cap, sizeof(cnPlanSplit));
            if (!na) return;
            *out = na;
            cnPlanSplit *sp = &na[(*nout)++];
            sp->side[0] = mask_list(O, key);
            sp->side[1] = mask_list(O, m & ~key);
            sp->stable = ok >= 0;
            sp->nplans = plans;
            sp->moves_tried = ntried;
            const Trans *w = &P->tr[ok >= 0 ? ok : tried];
            sp->move = cn_pl_move_of(O, w);
            sp->sides_fail = ok < 0 && w->status == CN_STEP_STABLE;
        }
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
            cnPlanPathChoice *na = cn_pl_grow(O, ch, nch, &cap, sizeof *na);
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
                if (t->move == 1ULL << b) mv[d->paths.n++] = cn_pl_move_of(O, t);
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
    for (int k = 0; dead && k < S->ntrans; k++) dead[k] = cn_pl_move_of(O, &P->tr[S->first + k]);
    out->ndead = dead ? S->ntrans : 0;
    out->dead_ends = dead;
    FixList fix = {NULL, 0, 0};
    for (int k = 0; P->o->fixels && !P->budget && k < S->ntrans && fix.n < 5; k++) {
        const Trans *t = &P->tr[S->first + k];
        if (t->status != CN_STEP_UNSTABLE) continue;
        cnStatus s = cn_pl_suggest_fixels(O, S->mask, t, &fix);
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
cnStatus cn_pl_harvest(Out *O, int root, Trans **stack, cnPlanResult *out) {
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
