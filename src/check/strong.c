/* Is there a motion from rest? (strong stability: Pang and Trinkle, "Stability characterizations
 * of fixtured rigid bodies with Coulomb friction", ICRA 2000.)
 *
 * With friction the Stewart-Trinkle LCP (paper eq. 5) may have a static solution and a moving
 * one at once: a crossbar between legs that spread downward is held by a squeeze that the
 * static LP happily supplies, yet it also falls freely. cairn calls an assembly stable only
 * when no solution moves. Two facts make that decidable here:
 *
 * 1. Gauss / energy. For any solution from rest (no gripped part sliding on another), with a
 *    the motion (velocity change over dt, divided by dt), a^T M a = fext.a - sum lambda mu p_n
 *    <= fext.a: gravity must do positive work on every motion. So if a frictionless force field
 *    f >= 0 nearly balances gravity, r = fext + J_n^T f small, then fext.a = r.a - f.J_n a <= r.a
 *    and |a|_M <= |r|_{M^-1}: nothing moves (cn_motion_frictionless_bound).
 * 2. Otherwise the largest gravity power over all solutions of the LCP is a linear program with
 *    complementarity constraints. Branch and bound over the complementarity pairs (z_i = 0 or
 *    w_i = 0), an LP relaxation at each node (GLPK, dual simplex warm-started from the parent),
 *    decides it exactly: a node whose power bound keeps every body still (by 1.'s inequality,
 *    |a|_M^2 <= power) is pruned; a node whose LP solution is complementary is a solution of the
 *    LCP, verified here and reported if it moves. With a gripped part sliding on another the
 *    drag also does work, so the search maximises each component of each body's motion instead.
 *    In 3-D the points of one face or edge between two bodies (a joint) are branched on
 *    together: their slips come from one relative motion, so only some combinations of their
 *    sliding modes exist (joint patterns, search_joint.c).
 *
 * The LP works in scaled units: motions in g (rotations times the body's radius), forces in the
 * weight of the heaviest body a contact touches, sliding speeds in g. */
#include <math.h>
#include <string.h>

#include "search.h"
#include "solve.h"

/* A found solution is accepted when it meets the LCP's conditions to this, scaled. */
#define CN_BB_VERIFY_TOL 1e-7
/* No wall-time limit: the node budget alone bounds the search, so that a verdict does not
 * depend on the machine's speed (the same JSON from every build and run). */
#define CN_BB_SECONDS INFINITY
/* A node whose power bound (in units of the reference weight times g) is positive but below
 * this is solved again in rational arithmetic (cn_bb_exact) before it is branched on. The
 * still-test's threshold scales with the square of the motion tolerance and with the lightest
 * body, so on an assembly of heavy and light blocks it falls to about 1e-13, where the double
 * simplex leaves bounds of 1e-14 to 1e-12 that are rounding. What glp_exact solves exactly is
 * not the double data itself: it first turns each coefficient and bound into a nearby simple
 * fraction (relative error at most 1e-10, so 1/3 stays 1/3). That is finer than what every
 * other node's bound rests on, the double simplex's tolerances (1e-7 on bounds and reduced
 * costs), so the search's decisions are as trustworthy as the double solve's, at a level that
 * solve cannot reach. Each exact solve counts as one LP of the budget. */
#define CN_BB_EXACT_BELOW 1e-9
/* Exact solves per search, at most (past them the noise nodes are branched on as in double):
 * the rare expensive exact solve (masses far apart) does not dominate a search. */
#define CN_BB_EXACT_MAX 64
/* With the floors' cuts (dense rows) the double simplex leaves bounds of up to about 1e-7 at
 * nodes whose exact bound is zero: those are solved again exactly, up to this many. */
#define CN_BB_EXACT_BELOW_FLOORS 1e-6
#define CN_BB_EXACT_MAX_FLOORS 16
static int silent(void *info, const char *s) {
    (void)info;
    (void)s;
    return 1;
}

/* Every body still when |a|_M <= beta: |a_lin| <= beta / sqrt(m_b) and |omega| <= beta *
 * sqrt(trace(I^-1)) (lambda_min(I) >= 1 / trace(I^-1)), against the thresholds of
 * cn_mech_moves. */
static bool still_within(const cnMech *m, double beta, double tol) {
    int nd = m->nd, dim = m->dim;
    for (int b = 0; b < m->nb; b++) {
        double mass = m->mass[b];
        if (!(mass > 0)) return false;
        const double *Mi = m->minv + (size_t)b * nd * nd;
        double tr = 0;
        for (int k = dim; k < nd; k++) tr += Mi[k * nd + k];
        if (beta / sqrt(mass) > tol * m->g) return false;
        if (beta * sqrt(tr) * m->radius[b] > tol * m->g) return false;
    }
    return true;
}

double cn_motion_frictionless_bound(const cnMotionProblem *p, const double *force, bool *proved) {
    const cnMech *m = p->m;
    int nd = m->nd, nb = m->nb;
    /* r = fext + J_n^T f, body by body */
    double *r = cn_malloc(sizeof(double) * (size_t)(nb * nd + 1));
    if (!r) {
        *proved = false; /* cannot tell */
        return INFINITY;
    }
    memcpy(r, m->fext, sizeof(double) * (size_t)(nb * nd));
    for (int c = 0; c < p->K; c++)
        for (int x = 0; x < 2; x++) {
            int b = p->rows[c].body[x];
            if (b >= 0)
                for (int k = 0; k < nd; k++) r[(size_t)b * nd + k] += p->rows[c].c[x][k] * force[c];
        }
    double beta2 = 0;
    for (int b = 0; b < nb; b++) {
        const double *Mi = m->minv + (size_t)b * nd * nd, *rb = r + (size_t)b * nd;
        for (int i = 0; i < nd; i++)
            for (int j = 0; j < nd; j++) beta2 += rb[i] * Mi[i * nd + j] * rb[j];
    }
    cn_free(r);
    if (!isfinite(beta2)) { /* an overflowed weight: nothing proved */
        *proved = false;
        return INFINITY;
    }
    double beta = sqrt(fmax(beta2, 0));
    *proved = isfinite(beta) && still_within(m, beta, p->motion_tol);
    return beta;
}

int cn_motion_verify(const cnMotionProblem *p, const double *force, const double *lambda,
                     double *acc) {
    const cnMech *m = p->m;
    int K = p->K, D = p->D, nrows = K + p->Kf * D;
    double g = m->g, viol = 0; /* the largest violation, scaled */
    cn_mech_response(m, p->rows, nrows, force, acc);
    for (int r = 0; r < nrows; r++) {
        double wr = cn_bb_row_weight(m, &p->rows[r]);
        double w = cn_mech_relative(m, &p->rows[r], acc) / g;
        if (r >= K) {
            int f = (r - K) / D;
            w += lambda[f] / g;
            if (p->nominal) w += p->nominal[r - K] / g;
        }
        double z = force[r] / wr;
        viol = fmax(viol, fmax(fmax(-z, -w), fmin(z, w)));
    }
    for (int f = 0; f < p->Kf; f++) {
        int c = p->contact_of_fric[f];
        double wr = cn_bb_row_weight(m, &p->rows[c]);
        double zeta = p->mu[f] * force[c];
        for (int d = 0; d < D; d++) zeta -= force[K + f * D + d];
        zeta /= wr;
        double lam = lambda[f] / g;
        viol = fmax(viol, fmax(fmax(-lam, -zeta), fmin(lam, zeta)));
    }
    if (!(viol <= CN_BB_VERIFY_TOL)) return -1;
    double size = 0; /* the largest motion, as cn_mech_moves measures it */
    for (int b = 0; b < m->nb; b++) size = fmax(size, cn_mech_motion_size(m, b, acc));
    if (!(size > p->motion_tol * g)) return 0;
    /* a motion within rounding of the violations may belong to no solution */
    return viol * CN_VERIFY_MOTION_OVER <= size / g ? 1 : -1;
}

/* Is the node's LP solution a solution of the LCP that moves? Its forces and sliding speeds,
 * in absolute units, go through cn_motion_verify (the motion recomputed from the forces). */
static int bb_candidate(Bb *s) {
    const cnMotionProblem *p = s->p;
    int nrows = s->nrows, nv = s->nv, K = p->K, D = p->D;
    for (int r = 0; r < K; r++) s->force[r] = fmax(glp_get_col_prim(s->P, nv + r + 1), 0) * s->wcol[r];
    /* each group's friction shared by its members in proportion to their normal forces (equally
       when they carry none: the friction is then zero) */
    for (int gr = 0; gr < s->G; gr++) {
        int j0 = s->gfirst[gr], j1 = s->gfirst[gr + 1];
        double sum = 0;
        for (int j = j0; j < j1; j++) sum += s->force[p->contact_of_fric[s->gmem[j]]];
        double lam = fmax(glp_get_col_prim(s->P, nv + nrows + gr + 1), 0) * p->m->g;
        for (int j = j0; j < j1; j++) {
            int f = s->gmem[j];
            double share = sum > 0 ? s->force[p->contact_of_fric[f]] / sum : 1.0 / (j1 - j0);
            for (int d = 0; d < D; d++) {
                int r = K + gr * D + d;
                s->force[K + f * D + d] = fmax(glp_get_col_prim(s->P, nv + r + 1), 0) * s->wcol[r] * share;
            }
            s->lambda[f] = lam;
        }
    }
    return cn_motion_verify(p, s->force, s->lambda, s->acc);
}

/* A full leaf (every pair fixed): maximise each motion component both ways over it, each
 * optimum a solution of the LCP. 1 one moves, 0 none does (every component within the
 * threshold), -1 undecided. The objective is restored. */
static int bb_leaf(Bb *s) {
    int nv = s->nv;
    double *obj = s->a;
    for (int i = 0; i < nv; i++) obj[i] = glp_get_obj_coef(s->P, i + 1);
    int out = 0;
    for (int i = 0; i < 2 * nv && out == 0; i++) {
        for (int j = 0; j < nv; j++) glp_set_obj_coef(s->P, j + 1, j == i / 2 ? (i % 2 ? -1.0 : 1.0) : 0.0);
        int lp = cn_bb_lp(s);
        if (lp < 0) out = -1;
        else if (lp == 1 && glp_get_obj_val(s->P) > s->p->motion_tol / sqrt(3.0)) {
            int c = bb_candidate(s);
            out = c == 1 ? 1 : -1;
        }
    }
    for (int i = 0; i < nv; i++) glp_set_obj_coef(s->P, i + 1, obj[i]);
    return out;
}

/* Room on the search's stack for more entries (its top entries kept); false when out of
 * memory. */
bool cn_bb_stack_room(Bb *s, int top, int more) {
    if (top + more <= s->stack_cap) return true;
    int cap = 2 * (top + more) + 16;
    BbEntry *grown = cn_realloc(s->tmp[TMP_STACK], sizeof(BbEntry) * (size_t)cap);
    if (!grown) return false;
    s->tmp[TMP_STACK] = grown;
    s->stack_cap = cap;
    return true;
}

/* A pair that moves no body: a contact between two parts neither of which is a body of the
 * problem (fixed, or moved by the gripper), or its friction; its forces act on nothing, so they
 * are set to zero rather than branched on. Its sliding speed lambda is left free (the other
 * side of its pair, zeta = mu p_n - sum p_k, is then identically zero): with nominal sliding
 * the contact's friction rows need lambda >= -nominal > 0 in some direction, and lambda = 0
 * would make every node infeasible, a false proof that nothing moves. */
static bool bb_dead(const Bb *s, int i) {
    const cnMotionProblem *p = s->p;
    const cnJRow *row = i < s->nrows ? cn_bb_row(s, i) : &p->rows[p->contact_of_fric[s->grep[i - s->nrows]]];
    return row->body[0] < 0 && row->body[1] < 0;
}

/* The nodes left open when the budget ran out (entry e, unsolved, and the stack's): the largest
 * of their parents' bounds on gravity's power (a bound on |a|_M^2 of every motion they hold;
 * energy search only), and the bodies their parents' LP motions move (indicative: a motion in
 * an open node may move others too). */
static void bb_frontier(Bb *s, const BbEntry *e, const BbEntry *stack, int top) {
    int nb = s->p->m->nb, K = s->p->K;
    if (s->open_contacts) {
        memset(s->open_contacts, 0, (size_t)K);
        for (int i = -1; i < top; i++) {
            const BbEntry *x = i < 0 ? e : &stack[i];
            if (x->depth == 0 || !s->loose) { /* the root: every contact */
                memset(s->open_contacts, 1, (size_t)K);
                break;
            }
            const unsigned char *lc = s->loose + (size_t)(x->depth - 1) * (size_t)K;
            for (int c = 0; c < K; c++) s->open_contacts[c] |= lc[c];
        }
    }
    s->open_bound = 0;
    if (!s->energy || s->gray) { /* bounds of motion components, or leaves left open: no power
                                    bound on the whole */
        s->open_bound = INFINITY;
        return;
    }
    if (s->open_bodies) memset(s->open_bodies, 0, (size_t)nb);
    for (int i = -1; i < top; i++) {
        const BbEntry *x = i < 0 ? e : &stack[i];
        s->open_bound = fmax(s->open_bound, x->bound);
        if (!s->open_bodies) continue;
        if (x->depth == 0 || !s->moving) {
            memset(s->open_bodies, 1, (size_t)nb); /* the root: every body */
            continue;
        }
        const unsigned char *mv = s->moving + (size_t)(x->depth - 1) * (size_t)nb;
        for (int b = 0; b < nb; b++) s->open_bodies[b] |= mv[b];
    }
}

/* order[0..n) sorted by far[] descending (ties by index), so that the nearest is pushed last. */
void cn_bb_sort_by_far(int *order, int n, const double *far) {
    for (int a = 1; a < n; a++) {
        int v = order[a], b = a;
        while (b > 0 && far[order[b - 1]] < far[v]) order[b] = order[b - 1], b--;
        order[b] = v;
    }
}

/* Enter node e: undo the fixes of the nodes the path leaves (deeper than e's parent) and make
 * e's own (a joint member's mode, a friction group's mode, or one pair). */
static void bb_enter(Bb *s, const BbEntry *e, int *fixed, int *mark, int *tdepth, int *nfixed) {
    while (*tdepth > (e->depth > 0 ? e->depth - 1 : 0))
        for ((*tdepth)--; *nfixed > mark[*tdepth];) cn_bb_pair_set(s, fixed[--*nfixed], 0);
    if (e->depth == 0) return;
    mark[(*tdepth)++] = *nfixed;
    if (e->group == -3) {
        int J = e->pair, nm = s->jfirst[J + 1] - s->jfirst[J], k = 0, q = 0, i = 0;
        unsigned mask = (unsigned)e->choice;
        for (int t = 0; t < nm; t++) k += mask >> t & 1;
        const unsigned char *pat =
            s->jpat[((size_t)J << CN_BB_JOINT_MAX) + mask] + (size_t)e->mode * (size_t)k;
        for (;; q++)
            if (mask >> q & 1 && i++ == e->level) break;
        cn_bb_mode(s, s->jmem[s->jfirst[J] + q], pat[e->level], fixed, nfixed);
    } else if (e->group >= 0) {
        cn_bb_mode(s, e->group, e->mode, fixed, nfixed);
    } else {
        cn_bb_pair_set(s, e->pair, e->choice);
        fixed[(*nfixed)++] = e->pair;
    }
}

typedef enum { BB_PRUNED, BB_OPEN, BB_FAILED } BbBound;

/* Solve the node's LP (cn_bb_node_lp) and decide whether its bound prunes it; *obj receives
 * the bound of an open node. A bound within rounding of zero is solved again exactly
 * (cn_bb_exact), counted as one more node. */
static BbBound bb_bound(Bb *s, double *obj) {
    const cnMotionProblem *p = s->p;
    const cnMech *m = p->m;
    double W = m->wref, g = m->g;
    bool energy = s->energy;
    int lp = cn_bb_node_lp(s);
    if (lp < 0) return BB_FAILED;
    if (lp == 0) {
        cn_bb_learn_infeasible(s);
        return BB_PRUNED;
    }
    *obj = glp_get_obj_val(s->P);
    bool still = energy ? still_within(m, sqrt(fmax(*obj * W * g, 0)), p->motion_tol)
                        : *obj <= p->motion_tol / sqrt(3.0);
    if (still) cn_bb_learn(s);
    if (still) return BB_PRUNED;
    if (energy && *obj < (s->nfloor ? CN_BB_EXACT_BELOW_FLOORS : CN_BB_EXACT_BELOW) &&
        s->exact < (s->nfloor ? CN_BB_EXACT_MAX_FLOORS : CN_BB_EXACT_MAX) && s->nodes < s->budget) {
        s->exact++;
        s->nodes++;
        int ex = cn_bb_exact(s);
        if (ex == -2) return BB_FAILED;
        if (ex == 0) return BB_PRUNED;
        *obj = glp_get_obj_val(s->P);
        if (ex == 1 && still_within(m, sqrt(fmax(*obj * W * g, 0)), p->motion_tol))
            return BB_PRUNED;
    }
    return BB_OPEN;
}

/* The most violated free pair of the node's LP solution (-1: none beyond CN_BB_COMPL_TOL), and
 * in *roomy the free pair with the most room; s->x and s->wv receive the free pairs' z and w. */
static int bb_worst(Bb *s, int *roomy) {
    int worst = -1;
    double wv = CN_BB_COMPL_TOL, room = -1;
    *roomy = -1;
    for (int i = 0; i < s->n; i++) {
        if (s->fix[i]) continue;
        double z = glp_get_col_prim(s->P, s->nv + i + 1);
        double w = glp_get_row_prim(s->P, s->nv + i + 1) - s->rowlo[i];
        s->x[i] = z, s->wv[i] = w;
        double v = fmin(z, w);
        if (v > wv) wv = v, worst = i;
        if (fmax(z, w) > room) room = fmax(z, w), *roomy = i;
    }
    return worst;
}

/* The contacts of pair i: its contact (a normal pair), or every member of its friction group
 * (a friction row or a sliding speed), flagged in out (K). */
static void pair_contacts(const Bb *s, int i, unsigned char *out) {
    const cnMotionProblem *p = s->p;
    if (i < p->K) {
        out[i] = 1;
        return;
    }
    int g = i < s->nrows ? (i - p->K) / p->D : i - s->nrows;
    for (int j = s->gfirst[g]; j < s->gfirst[g + 1]; j++) out[p->contact_of_fric[s->gmem[j]]] = 1;
}

/* The bodies the node's LP motion moves and the contacts its pairs leave unresolved (s->x, s->wv
 * from bb_worst), kept by depth for an undecided report. */
static void bb_note_moving(Bb *s, int depth) {
    const cnMech *m = s->p->m;
    if (s->loose) {
        unsigned char *lc = s->loose + (size_t)depth * (size_t)s->p->K;
        memset(lc, 0, (size_t)s->p->K);
        for (int i = 0; i < s->n; i++)
            if (!s->fix[i] && fmin(s->x[i], s->wv[i]) > CN_BB_COMPL_TOL) pair_contacts(s, i, lc);
    }
    for (int b = 0; b < m->nb; b++) {
        double lin = 0, ang = 0;
        for (int k = 0; k < m->nd; k++) {
            double v = glp_get_col_prim(s->P, b * m->nd + k + 1);
            if (k < m->dim) lin = fmax(lin, fabs(v));
            else ang = fmax(ang, fabs(v));
        }
        s->moving[(size_t)depth * (size_t)m->nb + (size_t)b] = lin + ang > s->p->motion_tol;
    }
}

/* Push the children of node e, branched on pair `worst`: the next member of a joint being
 * fixed member by member; else the joint of worst's friction group, within its patterns; else
 * the group's sliding modes; else the pair's two sides. False when out of memory. */
static bool bb_branch(Bb *s, int *top, const BbEntry *e, int worst, double obj) {
    const cnMotionProblem *p = s->p;
    if (e->group == -3) {
        int J = e->pair, nm = s->jfirst[J + 1] - s->jfirst[J], k = 0;
        for (int t = 0; t < nm; t++) k += (unsigned)e->choice >> t & 1;
        if (e->level + 1 < k)
            return cn_bb_prefix_children(s, top, e, J, (unsigned)e->choice, e->mode, e->level + 1,
                                         obj);
    }
    int grp = cn_bb_mode_group(s, worst);
    int J = grp >= 0 && s->joint ? s->joint[grp] : -1;
    /* a joint: its members whose friction is free and whose normal force is not fixed at zero
       (an unloaded point's friction is zero whatever it slides) */
    unsigned mask = 0;
    int np = 0;
    if (J >= 0) {
        int nm = s->jfirst[J + 1] - s->jfirst[J];
        for (int q = 0; q < nm; q++) {
            int h = s->jmem[s->jfirst[J] + q], c = p->contact_of_fric[s->grep[h]];
            if (cn_bb_group_free(s, h) && s->fix[c] != 1) mask |= 1u << q;
        }
        if (mask & (mask - 1)) np = cn_bb_joint_patterns(s, J, mask); /* two members or more */
    }
    if (np > 0) return cn_bb_prefix_children(s, top, e, J, mask, -1, 0, obj);
    if (!cn_bb_stack_room(s, *top, p->D + 2)) return false;
    BbEntry *stack = s->tmp[TMP_STACK];
    if (grp >= 0) {
        /* children: the modes, the one nearest the LP's solution (least to set to zero) explored
           first */
        int nm = p->D + 1, order[CN_BB_MAX_D + 1];
        double far[CN_BB_MAX_D + 1];
        for (int k = 0; k < nm; k++) order[k] = k, far[k] = cn_bb_mode_far(s, grp, k);
        for (int a = 0; a < nm; a++)
            for (int b = a + 1; b < nm; b++)
                if (far[order[b]] > far[order[a]]) {
                    int t = order[a];
                    order[a] = order[b], order[b] = t;
                }
        for (int k = 0; k < nm; k++) stack[(*top)++] = (BbEntry){e->depth + 1, -1, 0, grp, order[k], obj, 0};
    } else {
        /* children: the one that keeps the larger of z and w is explored first */
        bool keep_z = s->x[worst] >= s->wv[worst];
        stack[(*top)++] = (BbEntry){e->depth + 1, worst, keep_z ? 1 : 2, -1, 0, obj, 0};
        stack[(*top)++] = (BbEntry){e->depth + 1, worst, keep_z ? 2 : 1, -1, 0, obj, 0};
    }
    return true;
}

/* Depth-first branch and bound with the objective set on s->P. Returns FOUND, NONE or
 * UNDECIDED; energy: the objective is gravity's power (pruned by still_within), else one
 * scaled motion component (pruned below the motion threshold). */
static cnMotionAnswer bb_search(Bb *s, bool energy) {
    s->energy = energy;
    const cnMotionProblem *p = s->p;
    int n = s->n;
    for (int i = 0; i < n; i++)
        if (s->fix[i]) cn_bb_pair_set(s, i, 0);
    for (int i = 0; i < n; i++)
        if (bb_dead(s, i)) cn_bb_pair_set(s, i, i < s->nrows ? 1 : 2);
    s->stack_cap = (p->D + 2) * (n + 2);
    BbEntry *stack = cn_bb_tmp(s, TMP_STACK, sizeof(BbEntry) * (size_t)s->stack_cap);
    s->moving = cn_bb_tmp(s, TMP_MOVING, (size_t)(n + 2) * (size_t)(p->m->nb + 1));
    s->loose = s->open_contacts && s->moving ? cn_bb_tmp(s, TMP_LOOSE, (size_t)(n + 2) * (size_t)(p->K + 1))
                                             : NULL; /* both filled by bb_note_moving */
    int *fixed = cn_bb_tmp(s, TMP_FIXED, sizeof(int) * (size_t)(n + 2)); /* pairs fixed by branching */
    int *mark = cn_bb_tmp(s, TMP_MARK, sizeof(int) * (size_t)(n + 2));  /* nfixed before each depth */
    /* the basis of the open node at each depth of the current path, its children's start */
    size_t bw = (size_t)glp_get_num_rows(s->P) + (size_t)glp_get_num_cols(s->P) + CN_BB_CUT_MAX;
    int *basis_rows = cn_bb_tmp(s, TMP_BASIS_ROWS, sizeof(int) * (size_t)(n + 2)); /* rows then */
    unsigned char *basis = cn_bb_tmp(s, TMP_BASIS, bw * (size_t)(n + 2));
    if (!stack || !fixed || !mark || !basis || !basis_rows) {
        cn_bb_tmp_free(s, TMP_STACK), cn_bb_tmp_free(s, TMP_FIXED), cn_bb_tmp_free(s, TMP_MARK);
        cn_bb_tmp_free(s, TMP_BASIS), cn_bb_tmp_free(s, TMP_BASIS_ROWS);
        cn_bb_tmp_free(s, TMP_MOVING), cn_bb_tmp_free(s, TMP_LOOSE);
        s->moving = NULL, s->loose = NULL;
        s->why = CN_UNDECIDED_MEMORY;
        return CN_MOTION_UNDECIDED;
    }
    cn_bb_learn_reset(s);
    cn_free(s->fix0);
    if ((s->fix0 = cn_malloc((size_t)n + 1))) memcpy(s->fix0, s->fix, (size_t)n);
    int top = 0, tdepth = 0, nfixed = 0, held = -1; /* held: the depth whose basis the LP holds */
    stack[top++] = (BbEntry){0, -1, 0, -1, 0, INFINITY, 0};
    cnMotionAnswer ans = CN_MOTION_NONE;
    while (top > 0) {
        BbEntry e = ((BbEntry *)s->tmp[TMP_STACK])[--top];
        bb_enter(s, &e, fixed, mark, &tdepth, &nfixed);
        double now = cn_seconds_since(&s->t0);
        if (s->nodes >= s->budget || now > s->seconds) {
            s->why = s->nodes >= s->budget ? CN_UNDECIDED_BUDGET : CN_UNDECIDED_TIME;
            ans = CN_MOTION_UNDECIDED;
            bb_frontier(s, &e, s->tmp[TMP_STACK], top);
            break;
        }
        if (e.depth > 0 && !p->no_learning && cn_bb_known(s)) {
            s->ng_hits++;
            continue;
        }
        s->nodes++;
        if (e.depth > s->depth) s->depth = e.depth;
        if (p->progress && now >= s->progress_at)
            p->progress(p->progress_ctx, s->nodes, now), s->progress_at = now + CN_PROGRESS_SECONDS;
        double obj = 0;
        /* the parent's basis, unless the LP still holds it (its first child) */
        if (e.depth > 0 && e.depth <= n + 1 && held != e.depth - 1)
            cn_bb_basis_put(s, basis + bw * (size_t)(e.depth - 1), basis_rows[e.depth - 1]);
        held = -1;
        BbBound bound = bb_bound(s, &obj);
        if (bound == BB_FAILED) {
            s->why = CN_UNDECIDED_SOLVER;
            ans = CN_MOTION_UNDECIDED;
            break;
        }
        if (bound == BB_PRUNED) continue;
        int roomy, worst = bb_worst(s, &roomy);
        if (worst < 0) {
            if (bb_candidate(s) == 1) {
                ans = CN_MOTION_FOUND;
                break;
            }
            worst = roomy;
            if (worst < 0) { /* every pair fixed: a face of the solution set, whose power bound
                                is within rounding of the threshold: every point of it is a
                                solution, so its extreme motions decide */
                int c2 = bb_leaf(s);
                if (c2 == 1) {
                    ans = CN_MOTION_FOUND;
                    break;
                }
                if (c2 < 0) s->gray++;
                continue;
            }
        }
        if (s->moving) bb_note_moving(s, e.depth);
        if (e.depth <= n + 1) {
            cn_bb_basis_get(s, basis + bw * (size_t)e.depth);
            basis_rows[e.depth] = glp_get_num_rows(s->P), held = e.depth;
        }
        if (!bb_branch(s, &top, &e, worst, obj)) {
            s->why = CN_UNDECIDED_MEMORY;
            ans = CN_MOTION_UNDECIDED;
            break;
        }
    }
    while (nfixed > 0) cn_bb_pair_set(s, fixed[--nfixed], 0);
    cn_bb_tmp_free(s, TMP_STACK);
    cn_bb_tmp_free(s, TMP_MOVING);
    s->moving = NULL;
    cn_bb_tmp_free(s, TMP_LOOSE);
    s->loose = NULL;
    cn_bb_tmp_free(s, TMP_FIXED);
    cn_bb_tmp_free(s, TMP_MARK);
    cn_bb_tmp_free(s, TMP_BASIS), cn_bb_tmp_free(s, TMP_BASIS_ROWS);
    if (ans == CN_MOTION_NONE && s->gray) {
        s->why = CN_UNDECIDED_THRESHOLD;
        ans = CN_MOTION_UNDECIDED;
    }
    return ans;
}

/* The part of the search that calls GLPK, run under its error hook (cn_lp_guarded_call). */
typedef struct {
    Bb *s;
    bool energy;
    cnMotionAnswer answer;
    int built; /* cn_bb_build's status: nonzero when out of memory */
} BbRun;

static void bb_run(void *ctx) {
    BbRun *r = ctx;
    Bb *s = r->s;
    bool energy = r->energy;
    if ((r->built = cn_bb_build(s, energy)) != 0) return;
    if (energy && s->p->D > 2 && s->p->m->dim == 3 && !s->p->pointwise && cn_bb_joints(s) != 0) {
        /* no joints: every point is branched on by itself */
        cn_free(s->joint);
        s->joint = NULL;
    }
    if (energy) {
        /* the search as it is; in 2-D, when it ends undecided by its budget, once more with the
           normal-force floors in its energy cuts (cn_bb_normal_floors) and a share of its budget:
           they cut the bounds of sliding joints (large arches, walls under a sideways load) but
           lead the depth-first search elsewhere, sometimes to a longer search, so the first pass
           keeps every verdict the search gave without them */
        long full = s->budget;
        int mode = s->p->floors; /* cn_bb_normal_floors finds none in 3-D */
        if (mode == 0 && full < CN_BB_FLOOR_MIN_BUDGET) mode = -1;
        if (mode <= 0) r->answer = bb_search(s, true);
        if (mode > 0 || (mode == 0 && r->answer == CN_MOTION_UNDECIDED && s->why == CN_UNDECIDED_BUDGET)) {
            long lps = cn_bb_normal_floors(s);
            if (lps < 0) {
                r->answer = CN_MOTION_UNDECIDED;
                s->why = CN_UNDECIDED_SOLVER;
                return;
            }
            if (s->floored > 0 || mode > 0) { /* else the same search again */
                s->budget = s->nodes + (mode > 0 ? full : full / CN_BB_FLOOR_SHARE);
                s->nodes += lps;
                s->gray = 0, s->exact = 0;
                s->why = CN_UNDECIDED_NO;
                r->answer = bb_search(s, true);
            }
        }
    } else {
        /* each component of each body's motion, both ways, until one moves */
        bool undecided = false;
        for (int i = 0; i < s->nv * 2 && r->answer != CN_MOTION_FOUND; i++) {
            for (int j = 0; j < s->nv; j++) glp_set_obj_coef(s->P, j + 1, 0.0);
            glp_set_obj_coef(s->P, i / 2 + 1, i % 2 ? -1.0 : 1.0);
            cnMotionAnswer a = bb_search(s, false);
            if (a == CN_MOTION_FOUND) r->answer = a;
            else if (a == CN_MOTION_UNDECIDED) {
                undecided = true;
                if (s->nodes >= s->budget) break;
            }
        }
        if (r->answer != CN_MOTION_FOUND && undecided) r->answer = CN_MOTION_UNDECIDED;
    }
}

cnStatus cn_bb_search_group(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                            double *acc, cnMotionStats *stats, cnDiag *diag) {
    unsigned char *open_bodies = stats->open_bodies, *open_contacts = stats->open_contacts;
    memset(stats, 0, sizeof *stats);
    stats->open_bodies = open_bodies;
    stats->open_contacts = open_contacts;
    if (open_contacts) memset(open_contacts, 1, (size_t)p->K); /* narrowed by bb_frontier */
    *answer = CN_MOTION_NONE;
    const cnMech *m = p->m;
    if (m->nb == 0 || !(m->g > 0)) return CN_OK;
    glp_term_hook(silent, NULL);
    bool energy = !cn_motion_drags(p->rows, p->K, p->Kf, p->D, p->nominal);
    Bb s;
    memset(&s, 0, sizeof s);
    cnStatus st = CN_OK;
    s.p = p;
    s.nv = m->nb * m->nd;
    s.open_bodies = open_bodies;
    s.open_contacts = open_contacts;
    s.open_bound = INFINITY;
    if (cn_bb_group(&s) != 0) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
        goto done;
    }
    s.nrows = p->K + s.G * p->D;
    s.n = s.nrows + s.G;
    stats->default_budget = energy ? cn_motion_energy_budget(s.n) : cn_motion_drag_budget(s.n);
    s.budget = stats->budget = p->max_nodes > 0 ? p->max_nodes : stats->default_budget;
    s.seconds = p->max_seconds > 0 ? p->max_seconds : CN_BB_SECONDS;
    s.progress_at = CN_PROGRESS_SECONDS; /* a quick search makes no call */
    clock_gettime(CLOCK_MONOTONIC, &s.t0);
    s.force = force;
    s.acc = acc;
    s.sv = cn_malloc(sizeof(double) * (size_t)(s.nv + 1));
    s.wcol = cn_malloc(sizeof(double) * (size_t)(s.nrows + 1));
    s.rowlo = cn_malloc(sizeof(double) * (size_t)(s.n + 1));
    s.fix = cn_calloc((size_t)s.n + 1, 1);
    s.x = cn_malloc(sizeof(double) * (size_t)(s.n + 1));
    s.wv = cn_malloc(sizeof(double) * (size_t)(s.n + 1));
    s.lambda = cn_malloc(sizeof(double) * (size_t)(p->Kf + 1));
    s.a = cn_malloc(sizeof(double) * (size_t)(s.nv + 1));
    s.ma = cn_malloc(sizeof(double) * (size_t)(s.nv + 1));
    if (!s.lambda || !s.a || !s.ma) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
        goto done;
    }
    if (!s.sv || !s.wcol || !s.rowlo || !s.fix || !s.x || !s.wv) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
        goto done;
    }
    BbRun run = {&s, energy, CN_MOTION_NONE, 0};
    if (!cn_lp_guarded_call(bb_run, &run)) {
        s.P = NULL; /* freed with GLPK's environment */
        st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                         "the LP solver (GLPK) stopped on an internal error (out of memory, or numbers "
                         "it cannot scale) in the search for a motion from rest; no verdict");
        goto done;
    }
    if (run.built != 0) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
        goto done;
    }
    *answer = run.answer;
    stats->nodes = s.nodes;
    stats->learned = s.ng_hits;
    stats->depth = s.depth;
    for (int J = 0; s.joint && s.jnpat && J < s.NJ; J++) {
        bool used = false;
        for (unsigned mask = 0; mask < 1u << CN_BB_JOINT_MAX; mask++)
            used |= s.jnpat[((size_t)J << CN_BB_JOINT_MAX) + mask] > 0;
        stats->joints += used;
    }
    stats->floors += s.floored;
    stats->why = *answer == CN_MOTION_UNDECIDED ? s.why : CN_UNDECIDED_NO;
    stats->open_power = *answer == CN_MOTION_UNDECIDED ? s.open_bound * m->wref * m->g : 0;
    if (*answer == CN_MOTION_UNDECIDED && open_bodies && !isfinite(s.open_bound))
        memset(open_bodies, 1, (size_t)m->nb); /* nothing bounded: every body */
done:
    if (s.P) glp_delete_prob(s.P);
    cn_free(s.sv);
    cn_free(s.wcol);
    cn_free(s.rowlo);
    cn_free(s.fix);
    cn_free(s.fix0);
    cn_free(s.nfloor);
    cn_free(s.ng);
    cn_free(s.ng_end);
    cn_free(s.x);
    cn_free(s.wv);
    cn_free(s.lambda);
    cn_free(s.a);
    cn_free(s.ma);
    cn_free(s.grep);
    cn_free(s.gfirst);
    cn_free(s.gmem);
    cn_free(s.joint);
    cn_free(s.jfirst);
    cn_free(s.jmem);
    for (size_t i = 0; s.jpat && i < (size_t)s.NJ << CN_BB_JOINT_MAX; i++) cn_free(s.jpat[i]);
    cn_free(s.jpat);
    cn_free(s.jnpat);
    for (int i = 0; i < TMP_SLOTS; i++) cn_free(s.tmp[i]);
    return st;
}
