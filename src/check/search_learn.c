/* Prunes learned from the duals of pruned nodes (nogoods).
 *
 * A node is pruned when its LP bound on gravity's power keeps every body still. The optimal
 * basis of that LP stays optimal when a fix whose reduced cost does not push against it is
 * released (a column fixed at zero whose reduced cost is not positive, a row fixed at its lower
 * bound whose dual is not positive: the variable would stay at the bound), so the fixes with a
 * positive reduced cost alone give the same bound. Every node that makes those fixes, whatever
 * else it fixes, lies inside that relaxed LP (the power row and the energy cuts are valid for
 * every solution of the LCP), so it is pruned without an LP. Depth-first search meets the same conflict among a
 * few joints again under every choice of the joints branched on between them. */
#include <math.h>
#include <string.h>

#include "search.h"

/* A reduced cost above this (scaled units) keeps its fix in a learned set; GLPK's own
 * optimality tolerance on reduced costs is 1e-7, so the learned bound is as sure as the node's. */
#define CN_BB_LEARN_DUAL 1e-9
/* Learned sets kept, at most, and fixes in one: a larger set rarely recurs */
#define CN_BB_LEARN_MAX 50000
#define CN_BB_LEARN_LONG 96
/* A simplex-table entry below this fraction of its row's largest is taken for a zero that
 * rounding left (GLPK's own pivot tolerance, 1e-9 relative, is coarser) */
#define CN_BB_LEARN_ALPHA 1e-12
/* An infeasibility certificate must miss the bound by this, relative to its terms */
#define CN_BB_LEARN_MARGIN 1e-9

void cn_bb_learn_reset(Bb *s) {
    s->ng_count = s->ng_len = 0;
}

/* Room for one more learned set of at most CN_BB_LEARN_LONG fixes. */
static bool learn_room(Bb *s) {
    if (s->ng_count >= CN_BB_LEARN_MAX || !s->fix0) return false;
    if (s->ng_len + CN_BB_LEARN_LONG > s->ng_cap) {
        int cap = 2 * s->ng_cap + 4 * CN_BB_LEARN_LONG;
        int *grown = cn_realloc(s->ng, sizeof(int) * (size_t)cap);
        if (!grown) return false;
        s->ng = grown, s->ng_cap = cap;
    }
    if (s->ng_count + 1 > s->ng_endcap) {
        int cap = 2 * s->ng_endcap + 64;
        int *grown = cn_realloc(s->ng_end, sizeof(int) * (size_t)cap);
        if (!grown) return false;
        s->ng_end = grown, s->ng_endcap = cap;
    }
    return true;
}

/* The pair whose z (a column) or w (a row) is GLPK's variable k (rows first, m of them), or -1
 * (a motion unknown, a dynamics row, the power row, a cut). */
static int pair_of(const Bb *s, int k, int m) {
    int i = (k <= m ? k : k - m) - s->nv - 1;
    return i >= 0 && i < s->n ? i : -1;
}

/* Learn from the node just pruned by its bound (its LP optimal and still loaded). */
void cn_bb_learn(Bb *s) {
    if (!learn_room(s)) return;
    int len = s->ng_len, start = len;
    for (int i = 0; i < s->n; i++) {
        if (!s->fix[i] || s->fix0[i] == s->fix[i]) continue;
        int k = s->nv + i + 1;
        double d = s->fix[i] == 1 ? glp_get_col_dual(s->P, k) : glp_get_row_dual(s->P, k);
        if (!(d <= CN_BB_LEARN_DUAL)) { /* NaN keeps the fix */
            if (len - start >= CN_BB_LEARN_LONG) return;
            s->ng[len++] = 2 * i + s->fix[i] - 1;
        }
    }
    s->ng_len = len;
    s->ng_end[s->ng_count++] = len;
}

/* Does the current node make every fix of some learned set? */
bool cn_bb_known(const Bb *s) {
    for (int c = s->ng_count - 1; c >= 0; c--) {
        int j = c > 0 ? s->ng_end[c - 1] : 0, e = s->ng_end[c];
        for (; j < e; j++) {
            int v = s->ng[j];
            if (s->fix[v >> 1] != (v & 1) + 1) break;
        }
        if (j == e) return true;
    }
    return false;
}

/* The bounds of GLPK's variable k (rows first, m of them): -inf/inf where it has none. */
static void var_bounds(glp_prob *P, int k, int m, double *lo, double *up) {
    bool row = k <= m;
    int type = row ? glp_get_row_type(P, k) : glp_get_col_type(P, k - m);
    *lo = type == GLP_LO || type == GLP_DB || type == GLP_FX
              ? (row ? glp_get_row_lb(P, k) : glp_get_col_lb(P, k - m)) : -INFINITY;
    *up = type == GLP_UP || type == GLP_DB || type == GLP_FX
              ? (row ? glp_get_row_ub(P, k) : glp_get_col_ub(P, k - m)) : INFINITY;
}

/* Is GLPK's variable j one of this node's fixes (an upper bound at its lower one, made by the
 * search and not before it)? Its pair, or -1. */
static int fix_of(const Bb *s, int j, int m) {
    int pj = pair_of(s, j, m);
    if (pj < 0 || !s->fix[pj] || s->fix0[pj] == s->fix[pj]) return -1;
    return s->fix[pj] == (j <= m ? 2 : 1) ? pj : -1;
}

/* The learned set of the infeasible row of basic variable k (rows first, m of them), which must
 * rise (dir 1) to its bound `bound` or fall (dir -1) to it; ind and val are scratch. */
static void learn_row(Bb *s, int k, int m, int dir, double bound, int *ind, double *val) {
    int len = glp_eval_tab_row(s->P, k, ind, val);
    double big = 0;
    for (int t = 1; t <= len; t++) big = fmax(big, fabs(val[t]));
    int start = s->ng_len, at = start;
    int pk = fix_of(s, k, m);
    if (dir < 0 && pk >= 0) s->ng[at++] = 2 * pk + s->fix[pk] - 1;
    double reach = 0, size = fabs(bound); /* the farthest x_k goes, its terms' scale */
    for (int t = 1; t <= len; t++) {
        int j = ind[t], pj = fix_of(s, j, m);
        double a = val[t], jlo, jup;
        if (fabs(a) <= CN_BB_LEARN_ALPHA * big) continue; /* rounding of a zero */
        var_bounds(s->P, j, m, &jlo, &jup);
        bool rise = dir * a > 0; /* x_j helps by rising */
        if (pj >= 0 && rise) {
            if (at - start >= CN_BB_LEARN_LONG) return;
            s->ng[at++] = 2 * pj + s->fix[pj] - 1;
        }
        double x = rise && pj < 0 ? jup : jlo; /* a fix relaxed keeps its lower bound */
        if (!isfinite(x)) return; /* free on the helpful side: no certificate */
        reach += a * x;
        size += fabs(a * x);
    }
    double margin = CN_BB_LEARN_MARGIN * (1 + size);
    if (!(dir > 0 ? reach < bound - margin : reach > bound + margin)) return;
    s->ng_len = at;
    s->ng_end[s->ng_count++] = at;
}

/* Learn from the node just found infeasible by the dual simplex. GLPK names the basic variable
 * x_k it could not bring within its bounds; its row of the simplex table, x_k = sum alpha_j x_j
 * over the nonbasic variables (the rows are homogeneous), is a certificate when the farthest x_k
 * can go, each x_j at its bound on the helpful side, still misses x_k's bound. A fix is an upper
 * bound at the lower one: it blocks only an x_j that would help by rising, so those fixes (and
 * x_k's, if a fix is what x_k exceeds) go into the learned set, and every other bound the sum
 * uses holds at every node. The certificate is checked here, not taken from GLPK's status. */
void cn_bb_learn_infeasible(Bb *s) {
    if (!learn_room(s) || !glp_bf_exists(s->P)) return;
    int k = glp_get_unbnd_ray(s->P);
    int m = glp_get_num_rows(s->P), nc = glp_get_num_cols(s->P);
    if (k <= 0 || k > m + nc) return;
    bool row = k <= m;
    if ((row ? glp_get_row_stat(s->P, k) : glp_get_col_stat(s->P, k - m)) != GLP_BS) return;
    double v = row ? glp_get_row_prim(s->P, k) : glp_get_col_prim(s->P, k - m), lo, up;
    var_bounds(s->P, k, m, &lo, &up);
    int dir; /* +1: x_k must rise, -1: fall */
    if (v < lo) dir = 1;
    else if (v > up) dir = -1;
    else return;
    int *ind = cn_bb_tmp(s, TMP_IND, sizeof(int) * (size_t)(m + nc + 1));
    double *val = cn_bb_tmp(s, TMP_VAL, sizeof(double) * (size_t)(m + nc + 1));
    if (ind && val) learn_row(s, k, m, dir, dir > 0 ? lo : up, ind, val);
    cn_bb_tmp_free(s, TMP_IND), cn_bb_tmp_free(s, TMP_VAL);
}
