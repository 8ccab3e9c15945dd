/* Two-handed disassembly: a state split into a subassembly a gripper takes out and the rest
 * (an AND node), each side taken apart in turn. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "plan_state.h"
#include "solve.h"

int cn_pl_popcount(Mask m) {
    int c = 0;
    for (; m; m &= m - 1) c++;
    return c;
}

/* Where a split transition t of state si leads: *rest, the state of the parts that stay where
 * they were, and *out, the subassembly taken out in its gripper (held by its gripped part, or
 * whole); -1 for a single part, which is gone. */
cnStatus cn_pl_split_states(Planner *P, int si, const Trans *t, int *rest, int *out) {
    Mask m = P->st[si].mask;
    int held = P->st[si].held;
    bool group = cn_pl_popcount(t->move) > 1;
    *out = -1;
    *rest = cn_pl_state_at(P, m & ~t->move, held);
    if (*rest >= 0 && group) *out = cn_pl_state_at(P, t->move, t->grip >= 0 ? t->grip : HELD_WHOLE);
    if (*rest < 0 || (group && *out < 0)) return cn_diag_oom(P->diag);
    return CN_OK;
}

/* The stable two-handed plans that begin with the stable split transition t of state si: the
 * product of those of its two sides (each solved here). */
static cnStatus split_plans(Planner *P, int si, const Trans *t, double *plans) {
    int r1, r2;
    *plans = 0;
    cnStatus s = cn_pl_split_states(P, si, t, &r1, &r2);
    if (s || (s = cn_pl_solve_sub(P, r1))) return s;
    double n = P->st[r1].sub_plans;
    if (n > 0 && r2 >= 0) {
        if ((s = cn_pl_solve_sub(P, r2))) return s;
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
    if (cn_pl_popcount(M) == 1) {
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
    int nx = cn_pl_state_at(P, mask, held);
    if (nx < 0) return cn_diag_oom(P->diag);
    cnStatus s = cn_pl_state_stable(P, nx, ok);
    if (s || *ok) return s;
    Trans t = cn_pl_trans_init(M, NULL, grip, si);
    snprintf(t.cand.name, sizeof t.cand.name, "any path");
    t.status = P->st[nx].undecided ? CN_STEP_UNDECIDED : CN_STEP_UNSTABLE;
    t.time = NAN;
    t.moving = P->st[nx].falls;
    t.prop1 = true;
    if (cn_pl_push_trans(P, &t) < 0) return cn_diag_oom(P->diag);
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
        if (cn_pl_popcount(M) > 1) cj.support = CN_SUPPORT_HOLD; /* the gripper carries them */
        if (held == HELD_WHOLE && grip < 0 && !cj.file && cj.nseg == 1) {
            /* everything held: a straight line along a free direction is free */
            t = cn_pl_trans_init(M, &cj, -1, si);
            t.status = CN_STEP_STABLE;
        } else {
            cnStatus s = cn_pl_transition(P, m, held, M, grip, &cj, false, &t);
            if (s) return s;
        }
        t.from = si;
        int idx = cn_pl_push_trans(P, &t);
        if (idx < 0) return cn_diag_oom(P->diag);
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
    cn_pl_set_absent_held(P, m, held);
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
        return cn_diag_oom(P->diag);
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
cnStatus cn_pl_solve_sub(Planner *P, int si) {
    if (P->st[si].sub_plans >= 0) return CN_OK;
    Mask m = P->st[si].mask;
    int held = P->st[si].held;
    Mask hm = held >= 0 ? 1ULL << held : 0;
    /* nothing left, only the part in the hand, or one part held */
    if ((m & ~hm) == 0 || (held == HELD_WHOLE && cn_pl_popcount(m) == 1)) {
        P->st[si].sub_plans = 1;
        return CN_OK;
    }
    bool stable;
    cnStatus s = cn_pl_state_stable(P, si, &stable);
    if (s) return s;
    if (!stable) {
        P->st[si].sub_plans = 0;
        return CN_OK;
    }
    P->st[si].sub_plans = 0; /* provisional (states only shrink: no cycles) */
    if (cn_pl_out_of_budget(P)) return CN_OK;
    bool first = cn_pl_first_only(P);
    if (first) P->truncated = true; /* counts are then lower bounds */
    double plans = 0;
    int choice = -1;
    /* single parts from the supports: the transitions the sequence search simulated; a part
     * counts once, whichever of its stable paths (they all lead to the same state) */
    if (held == -1) {
        if ((s = cn_pl_expand(P, si))) return s;
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
            if (cn_pl_popcount(sub) != k) continue;
            if (cn_pl_out_of_budget(P)) break; /* checked per group: a state may have 2^n of them */
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
            if (group_removable(P, &rem, M) && (s = cn_pl_candidates(P, m, held, M, &c, &nc))) break;
            if (nc == 0) { /* no free direction: recorded for the report of splits */
                Trans t = cn_pl_trans_init(M, NULL, -1, si);
                t.status = CN_STEP_INFEASIBLE;
                snprintf(t.cand.name, sizeof t.cand.name, "no free direction");
                if (cn_pl_push_trans(P, &t) < 0) s = cn_diag_oom(P->diag);
            }
            /* each grip in turn; its first path that is stable counts */
            for (int gi = 0; gi < ng && !s && !(first && plans > 0); gi++) {
                /* ... and the group must stay on the part that holds it (Proposition 1): parts
                 * that touch nothing connected to it fall at once */
                Mask lost = grips[gi] >= 0 ? M & ~reach(P, M, grips[gi]) : 0;
                if (nc > 0 && lost) {
                    Trans t = cn_pl_trans_init(M, NULL, grips[gi], si);
                    snprintf(t.cand.name, sizeof t.cand.name, "any path");
                    t.status = CN_STEP_UNSTABLE;
                    t.time = NAN;
                    t.moving = lost;
                    t.prop1 = true;
                    if (cn_pl_push_trans(P, &t) < 0) s = cn_diag_oom(P->diag);
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
                if ((s = cn_pl_candidates(P, m, held, R, &c2, &nc2))) break;
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
