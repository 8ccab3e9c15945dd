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
 *    sliding modes exist (joint patterns, below).
 *
 * The LP works in scaled units: motions in g (rotations times the body's radius), forces in the
 * weight of the heaviest body a contact touches, sliding speeds in g. */
#include <glpk.h>
#include <math.h>
#include <string.h>
#include <time.h>

#include "solve.h"
#include "strong.h"

/* Complementarity is met when min(z, w) of a pair, in scaled units, is below this. */
#define CN_BB_COMPL_TOL 1e-9
/* A found solution is accepted when it meets the LCP's conditions to this, scaled. */
#define CN_BB_VERIFY_TOL 1e-7
/* Motions are boxed to this many g in the component search (nominal sliding): no solution of a
 * contact problem under gravity and a gripper's drag comes near it. */
#define CN_BB_BOX 1e4
/* Rounds of energy cuts (bb_cut) per node, at most, and the cuts kept in the LP: past the cap,
 * the cuts the current basis does not use are deleted (the cuts more than halve the nodes of
 * 2-D arches; keeping every one makes each LP too large to pay for it). */
#define CN_BB_CUT_ROUNDS 2
#define CN_BB_CUT_CAP 30
/* No wall-time limit: the node budget alone bounds the search, so that a verdict does not
 * depend on the machine's speed (the same JSON from every build and run). */
#define CN_BB_SECONDS INFINITY
/* Two friction rows are the same row when their coefficients differ by less than this (linear
 * parts, unit; rotational parts relative to the body's radius): contacts along one line of a
 * 2-D joint. */
#define CN_BB_SAME_ROW 1e-9
/* Friction directions up to which a contact's sliding modes are branched on together. */
#define CN_BB_MAX_D 64
/* A node whose power bound (in units of the reference weight times g) is positive but below
 * this is solved again in rational arithmetic (glp_exact) before it is branched on. The
 * still-test's threshold scales with the square of the motion tolerance and with the lightest
 * body, so on an assembly of heavy and light blocks it falls to about 1e-13, where the double
 * simplex leaves bounds of 1e-14 to 1e-12 that are rounding (on compas_cra's bridge section,
 * half of the branched nodes, with an exact optimum of 0). What glp_exact solves exactly is not the double data itself: it first turns each
 * coefficient and bound into a nearby simple fraction (relative error at most 1e-10, so 1/3
 * stays 1/3). That is finer than what every other node's bound rests on, the double simplex's
 * tolerances (1e-7 on bounds and reduced costs), so the search's decisions are as trustworthy
 * as the double solve's, at a level that solve cannot reach. Each exact solve counts as
 * one LP of the budget. */
#define CN_BB_EXACT_BELOW 1e-9
/* Exact solves per search, at most (past them the noise nodes are branched on as in double),
 * and the pivots each may take (past them the double bound stands). An exact solve starts from
 * the double simplex's optimal basis, which is nearly always optimal exactly too, within a few
 * pivots; the limits keep the rare expensive exact solve (masses far apart) from dominating a
 * search. */
#define CN_BB_EXACT_MAX 64
#define CN_BB_EXACT_ITERS 10
/* The exact solve is declined when a coefficient or bound of the LP is outside this range of
 * magnitudes (a friction coefficient of 5e-324, densities 1e150 apart): GLPK's exact simplex
 * turns its fractions into doubles to choose pivots and stops on an internal error when one
 * underflows to 0, and then cannot free its GMP numbers. The node keeps its double bound. */
#define CN_BB_EXACT_RANGE 1e100
/* A joint's sliding patterns kept at most, and the small LPs spent finding them (past either,
 * its points are branched on one by one, as single contacts). */
#define CN_BB_JOINT_MAX_PATTERNS 1024
/* Points of a joint at most (more: its points are branched on one by one) */
#define CN_BB_JOINT_MAX 8
#define CN_BB_JOINT_MAX_LPS 20000
/* Simplex pivots per LP of a joint's enumeration, at most. */
#define CN_BB_JOINT_PIVOTS 2000
/* A joint's pattern exists when the LP's margin on its strict inequalities exceeds this (the
 * conditions are cones, so a pattern that exists reaches the cap of 1; this only absorbs
 * rounding). */
#define CN_BB_JOINT_STRICT 1e-9

static int silent(void *info, const char *s) {
    (void)info;
    (void)s;
    return 1;
}

/* The force scale of a row: the weight of the heaviest body it touches (the reference weight
 * when it touches none). */
static double row_weight(const cnMech *m, const cnJRow *row) {
    double wr = 0;
    for (int x = 0; x < 2; x++)
        if (row->body[x] >= 0) wr = fmax(wr, m->mass[row->body[x]] * m->g);
    return wr > 0 ? wr : m->wref;
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

/* Scratch arrays alive across GLPK calls, kept in the search's state so that they are freed
 * even when GLPK's error hook jumps out of the search (cn_lp_guarded_call). */
enum { TMP_IA, TMP_JA, TMP_AR, TMP_IND, TMP_VAL, TMP_DEL, TMP_STACK, TMP_FIXED, TMP_MARK,
       TMP_JOUT, TMP_MOVING, TMP_SLOTS };

typedef struct {
    const cnMotionProblem *p;
    glp_prob *P;
    void *tmp[TMP_SLOTS];
    int nv, nrows, n;     /* motion unknowns, force rows, complementarity pairs */
    double *sv;           /* nv: a = sv x */
    double *wcol;         /* nrows: force scale of each row's column */
    double *rowlo;        /* n: lower bound of each pair's row (w_i >= rowlo_i) */
    unsigned char *fix;   /* n: 0 free, 1 z = 0, 2 w = 0 */
    double *x;            /* scratch: column values */
    double *wv;           /* scratch: row slacks of the pairs */
    double *force, *acc;  /* out: the solution found */
    long nodes, budget;
    double seconds;       /* wall-time budget */
    struct timespec t0;
    double *lambda;       /* scratch: Kf sliding speeds */
    /* Friction groups: friction contacts whose friction rows are the same rows and whose mu is
     * the same (the points of a 2-D joint along its line). Only the sum of their friction acts,
     * and that sum can be anything with |sum| <= mu sum p_n, so the search carries one set of
     * friction rows and one sliding speed per group (exact: a solution of either LCP gives one
     * of the other, the friction shared in proportion to the normal forces). */
    int G;                /* groups */
    int *grep;            /* G: a member (friction contact) whose rows stand for the group */
    int *gfirst;          /* G + 1: offsets into gmem */
    int *gmem;            /* Kf: friction contacts, by group */
    double *a, *ma;       /* scratch: nv */
    /* Joints: friction groups between the same two bodies with the same normal (the points of a
     * face or edge contact). Their tangential slips are those of one relative motion, so only
     * some combinations of the points' sliding modes can occur together: those are listed once
     * (joint_patterns) and branched on member by member within them (bb_prefix_children): a
     * member's children are its modes in the patterns that agree with the members fixed before
     * it, so a mode no pattern of the prefix allows is never tried, and an infeasible prefix
     * cuts every pattern that extends it with one LP. */
    int *joint;           /* G: the joint of each group, -1 when it has no joint of its own */
    int NJ;
    int *jfirst, *jmem;   /* NJ + 1 offsets into jmem; the groups of each joint */
    int *jnpat;           /* NJ x 2^CN_BB_JOINT_MAX: patterns of each joint's subset of members
                             (a mask), found when first branched on (-1 not yet; 0 none kept:
                             its points are branched on one by one) */
    unsigned char **jpat; /* the same: the patterns, jnpat x (members in the mask) modes */
    int stack_cap;        /* entries of the search's stack */
    unsigned char *moving; /* (depth + 1) x nb: the bodies the LP's motion moves at the node
                              branched on at each depth of the current path */
    double open_bound;    /* undecided by the budget: the largest bound (scaled power) of the
                             nodes left open */
    unsigned char *open_bodies; /* ... and the bodies their parents' motions move (nb) */
    int cuts;
    int depth;
    bool energy;          /* the search maximises gravity's power (no nominal sliding) */
    int gray;             /* complementary points near the threshold that did not resolve */
    int exact;            /* nodes solved again in exact arithmetic */
    double progress_at;   /* seconds into the search of the next progress call */
    bool exact_ok;        /* the LP's numbers are within CN_BB_EXACT_RANGE for glp_exact */
    const char *why;
} Bb;

static void *bb_tmp(Bb *s, int slot, size_t bytes) { return s->tmp[slot] = cn_malloc(bytes); }

/* A number of the LP: exact arithmetic is declined when one is outside the range it handles. */
static void exact_range(Bb *s, double v) {
    double a = fabs(v);
    if (a != 0 && !(a >= 1 / CN_BB_EXACT_RANGE && a <= CN_BB_EXACT_RANGE)) s->exact_ok = false;
}
static void bb_tmp_free(Bb *s, int slot) {
    cn_free(s->tmp[slot]);
    s->tmp[slot] = NULL;
}

/* The force row of the search's column r: a normal row, or the representative's friction row. */
static const cnJRow *bb_row(const Bb *s, int r) {
    const cnMotionProblem *p = s->p;
    if (r < p->K) return &p->rows[r];
    int g = (r - p->K) / p->D, d = (r - p->K) % p->D;
    return &p->rows[p->K + s->grep[g] * p->D + d];
}

/* Are friction contacts f1 and f2 the same rows with the same mu and nominal sliding? */
static bool same_friction(const cnMotionProblem *p, int f1, int f2) {
    const cnMech *m = p->m;
    int D = p->D, nd = m->nd, dim = m->dim;
    if (p->mu[f1] != p->mu[f2]) return false;
    for (int d = 0; d < D; d++) {
        const cnJRow *a = &p->rows[p->K + f1 * D + d], *b = &p->rows[p->K + f2 * D + d];
        for (int x = 0; x < 2; x++) {
            if (a->body[x] != b->body[x]) return false;
            if (a->body[x] < 0) continue;
            double rad = m->radius[a->body[x]] > 0 ? m->radius[a->body[x]] : 1.0;
            for (int k = 0; k < nd; k++)
                if (fabs(a->c[x][k] - b->c[x][k]) > CN_BB_SAME_ROW * (k < dim ? 1.0 : rad)) return false;
        }
        if (p->nominal) {
            double u = p->nominal[f1 * D + d], v = p->nominal[f2 * D + d];
            if (fabs(u - v) > CN_BB_SAME_ROW * fmax(fabs(u), fabs(v))) return false;
        }
    }
    return true;
}

/* Group the friction contacts (s->G, grep, gfirst, gmem); -1 out of memory. */
static int bb_group(Bb *s) {
    const cnMotionProblem *p = s->p;
    int Kf = p->Kf;
    int *of = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    s->grep = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    s->gfirst = cn_malloc(sizeof(int) * (size_t)(Kf + 2));
    s->gmem = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    if (!of || !s->grep || !s->gfirst || !s->gmem) {
        cn_free(of);
        return -1;
    }
    int G = 0;
    for (int f = 0; f < Kf; f++) {
        int g = 0;
        while (g < G && !same_friction(p, s->grep[g], f)) g++;
        if (g == G) s->grep[G++] = f;
        of[f] = g;
    }
    int k = 0;
    for (int g = 0; g < G; g++) {
        s->gfirst[g] = k;
        for (int f = 0; f < Kf; f++)
            if (of[f] == g) s->gmem[k++] = f;
    }
    s->gfirst[G] = k;
    s->G = G;
    cn_free(of);
    return 0;
}

static void pair_set(Bb *s, int i, int choice) {
    int col = s->nv + i + 1, row = s->nv + i + 1;
    s->fix[i] = (unsigned char)choice;
    if (choice == 0) {
        glp_set_col_bnds(s->P, col, GLP_LO, 0.0, 0.0);
        glp_set_row_bnds(s->P, row, GLP_LO, s->rowlo[i], 0.0);
    } else if (choice == 1) {
        glp_set_col_bnds(s->P, col, GLP_FX, 0.0, 0.0);
    } else {
        glp_set_row_bnds(s->P, row, GLP_FX, s->rowlo[i], s->rowlo[i]);
    }
}

/* The LP of the relaxation: dynamics (equalities), the pairs' rows (>= lower bounds), and in
 * the energy search the power row fext.a <= fext.a0 (valid: |a|_M^2 <= fext.a and Cauchy-Schwarz
 * give fext.a <= |fext|_{M^-1}^2). */
static int bb_build(Bb *s, bool energy) {
    const cnMotionProblem *p = s->p;
    const cnMech *m = p->m;
    int nd = m->nd, nb = m->nb, K = p->K, Kf = p->Kf, D = p->D, dim = m->dim;
    int nv = s->nv, nrows = s->nrows, n = s->n;
    double W = m->wref, g = m->g;
    glp_prob *P = s->P = glp_create_prob();
    glp_set_obj_dir(P, GLP_MAX);
    int nrow_all = nv + n + (energy ? 1 : 0), ncol = nv + n;
    glp_add_rows(P, nrow_all);
    glp_add_cols(P, ncol);
    for (int b = 0; b < nb; b++)
        for (int k = 0; k < nd; k++) {
            double rad = m->radius[b] > 0 ? m->radius[b] : 1.0;
            s->sv[b * nd + k] = k < dim ? g : g / rad;
        }
    for (int r = 0; r < nrows; r++) s->wcol[r] = row_weight(m, bb_row(s, r));
    /* nonzeros: dynamics 2 nd per force column + nv identity; pair rows 2 nd + 1 each; zeta
     * rows D + 1; power row nv */
    size_t cap = (size_t)nv * 2 + (size_t)nrows * (4 * nd + 1) + (size_t)Kf * (D + 2) + 8;
    int *ia = bb_tmp(s, TMP_IA, sizeof(int) * (cap + 1));
    int *ja = bb_tmp(s, TMP_JA, sizeof(int) * (cap + 1));
    double *ar = bb_tmp(s, TMP_AR, sizeof(double) * (cap + 1));
    if (!ia || !ja || !ar) {
        bb_tmp_free(s, TMP_IA), bb_tmp_free(s, TMP_JA), bb_tmp_free(s, TMP_AR);
        return -1;
    }
    int k = 0;
#define PUT(row, col, val) (ia[++k] = (row), ja[k] = (col), ar[k] = (val))
    s->exact_ok = true;
    for (int i = 0; i < nv; i++) {
        exact_range(s, m->a0[i] / s->sv[i]);
        glp_set_row_bnds(P, i + 1, GLP_FX, m->a0[i] / s->sv[i], 0.0);
        glp_set_col_bnds(P, i + 1, energy ? GLP_FR : GLP_DB, -CN_BB_BOX, CN_BB_BOX);
        PUT(i + 1, i + 1, 1.0);
    }
    for (int r = 0; r < nrows; r++) {
        int col = nv + r + 1, row = nv + r + 1;
        glp_set_col_bnds(P, col, GLP_LO, 0.0, 0.0);
        const cnJRow *jr = bb_row(s, r);
        for (int x = 0; x < 2; x++) {
            int b = jr->body[x];
            if (b < 0) continue;
            for (int d = 0; d < nd; d++) {
                /* dynamics: x - sum (u W_r / sv) p = a0 / sv */
                double u = jr->u[x][d] * s->wcol[r] / s->sv[b * nd + d];
                if (u != 0) PUT(b * nd + d + 1, col, -u);
                /* the pair's row: relative motion along the row, in g */
                double c = jr->c[x][d] * s->sv[b * nd + d] / g;
                if (c != 0) PUT(row, b * nd + d + 1, c);
            }
        }
        double lo = 0;
        if (r >= K) {
            int gr = (r - K) / D;
            PUT(row, nv + nrows + gr + 1, 1.0); /* lambda */
            lo = p->nominal ? -p->nominal[s->grep[gr] * D + (r - K) % D] / g : 0.0;
        }
        s->rowlo[r] = lo;
        exact_range(s, lo);
        glp_set_row_bnds(P, row, GLP_LO, lo, 0.0);
    }
    for (int gr = 0; gr < s->G; gr++) {
        int col = nv + nrows + gr + 1, row = nv + nrows + gr + 1;
        glp_set_col_bnds(P, col, GLP_LO, 0.0, 0.0);
        s->rowlo[nrows + gr] = 0;
        glp_set_row_bnds(P, row, GLP_LO, 0.0, 0.0);
        /* mu sum p_n - sum p_k: every member's normal row has the representative's force scale
           (the same two bodies) */
        for (int j = s->gfirst[gr]; j < s->gfirst[gr + 1]; j++) {
            int f = s->gmem[j];
            PUT(row, nv + p->contact_of_fric[f] + 1, p->mu[f]);
        }
        for (int d = 0; d < D; d++) PUT(row, nv + K + gr * D + d + 1, -1.0);
    }
    if (energy) {
        int row = nv + n + 1;
        double e0 = 0;
        for (int b = 0; b < nb; b++) {
            double mass = m->mass[b];
            for (int d = 0; d < dim; d++) {
                double fa = mass * m->a0[b * nd + d]; /* gravity as the body feels it */
                e0 += fa * m->a0[b * nd + d];
                double coef = fa * s->sv[b * nd + d] / (W * g);
                if (coef != 0) PUT(row, b * nd + d + 1, coef);
                glp_set_obj_coef(P, b * nd + d + 1, coef);
            }
        }
        exact_range(s, e0 / (W * g));
        glp_set_row_bnds(P, row, GLP_UP, 0.0, e0 / (W * g) * (1 + 1e-9) + CN_TOL_NOISE);
    }
#undef PUT
    for (int i = 1; i <= k; i++) exact_range(s, ar[i]);
    glp_load_matrix(P, k, ia, ja, ar);
    bb_tmp_free(s, TMP_IA), bb_tmp_free(s, TMP_JA), bb_tmp_free(s, TMP_AR);
    return 0;
}

/* Every solution of the LCP from rest has z.w = a^T M a - fext.a + sum lambda mu p_n = 0, so
 * a^T M a <= fext.a: the contacts do no net work on the motion. The LP relaxation does not know
 * it (a friction force may push along the sliding it opposes, if another brakes); this adds the
 * tangent plane of the convex constraint at the current LP solution when that violates it
 * (outer approximation, Kelley): 2 (M a*).a - fext.a <= a*^T M a*. Returns true when a cut was
 * added. Valid without nominal sliding only. */
static bool bb_cut(Bb *s) {
    const cnMech *m = s->p->m;
    int nv = s->nv, nd = m->nd, dim = m->dim;
    double W = m->wref, g = m->g;
    double fa = 0;
    for (int i = 0; i < nv; i++) s->a[i] = glp_get_col_prim(s->P, i + 1) * s->sv[i];
    double e = cn_mech_kinetic(s->p->m, s->a, s->ma);
    for (int b = 0; b < m->nb; b++)
        for (int k = 0; k < dim; k++) fa += m->mass[b] * m->a0[b * nd + k] * s->a[b * nd + k];
    if (!(e > fa + 1e-9 * (fabs(fa) + e) + CN_TOL_NOISE * W * g)) return false;
    int row = glp_add_rows(s->P, 1);
    int *ind = bb_tmp(s, TMP_IND, sizeof(int) * (size_t)(nv + 1));
    double *val = bb_tmp(s, TMP_VAL, sizeof(double) * (size_t)(nv + 1));
    if (!ind || !val) {
        bb_tmp_free(s, TMP_IND), bb_tmp_free(s, TMP_VAL);
        glp_del_rows(s->P, 1, (const int[]){0, row});
        return false;
    }
    int k = 0;
    for (int i = 0; i < nv; i++) {
        int b = i / nd, d = i % nd;
        double f = d < dim ? m->mass[b] * m->a0[i] : 0;
        double c = (2 * s->ma[i] - f) * s->sv[i] / (W * g);
        if (c != 0) ind[++k] = i + 1, val[k] = c, exact_range(s, c);
    }
    exact_range(s, e / (W * g));
    glp_set_mat_row(s->P, row, k, ind, val);
    glp_set_row_bnds(s->P, row, GLP_UP, 0.0, e / (W * g));
    bb_tmp_free(s, TMP_IND), bb_tmp_free(s, TMP_VAL);
    s->cuts++;
    return true;
}

/* Keep at most cap energy cuts: past it, the cuts the current basis does not use (their row
 * basic, i.e. slack) are deleted, which keeps the basis valid for the next warm start. */
static void bb_trim_cuts(Bb *s, int cap) {
    int first = s->nv + s->n + 2, nrow = glp_get_num_rows(s->P);
    if (nrow - first + 1 <= cap) return;
    int *del = bb_tmp(s, TMP_DEL, sizeof(int) * (size_t)(nrow - first + 2));
    if (!del) return;
    int k = 0;
    for (int r = first; r <= nrow; r++)
        if (glp_get_row_stat(s->P, r) == GLP_BS) del[++k] = r;
    if (k > 0) glp_del_rows(s->P, k, del);
    bb_tmp_free(s, TMP_DEL);
}

/* Solve the current node's LP: 1 optimal, 0 infeasible, -1 the solver failed. */
static int bb_lp(Bb *s) {
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.meth = GLP_DUALP;
    parm.presolve = GLP_OFF;
    parm.it_lim = 20000 + 50 * (glp_get_num_rows(s->P) + glp_get_num_cols(s->P));
    for (int attempt = 0; attempt < 2; attempt++) {
        if (attempt == 1) glp_adv_basis(s->P, 0);
        int rc = glp_simplex(s->P, &parm);
        if (rc != 0) continue;
        int st = glp_get_status(s->P);
        if (st == GLP_OPT) return 1;
        if (st == GLP_NOFEAS) return 0;
    }
    return -1;
}

/* The current node's LP again in exact rational arithmetic, from the basis the double simplex
 * left: 1 optimal (its solution now the LP's), 0 infeasible, -1 not solved (an iteration limit
 * or a failure; the LP is then solved again in double so that its solution is the node's), -2
 * that double solve failed too. */
static int bb_exact(Bb *s) {
    if (!s->exact_ok) return -1; /* the double solve just made stands */
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.it_lim = CN_BB_EXACT_ITERS;
    if (glp_exact(s->P, &parm) == 0) {
        int st = glp_get_status(s->P);
        if (st == GLP_OPT) return 1;
        if (st == GLP_NOFEAS) return 0;
    }
    int lp = bb_lp(s);
    return lp == 1 ? -1 : lp == 0 ? 0 : -2;
}

int cn_motion_verify(const cnMotionProblem *p, const double *force, const double *lambda,
                     double *acc) {
    const cnMech *m = p->m;
    int K = p->K, D = p->D, nrows = K + p->Kf * D;
    double g = m->g;
    cn_mech_response(m, p->rows, nrows, force, acc);
    for (int r = 0; r < nrows; r++) {
        double wr = row_weight(m, &p->rows[r]);
        double w = cn_mech_relative(m, &p->rows[r], acc) / g;
        if (r >= K) {
            int f = (r - K) / D;
            w += lambda[f] / g;
            if (p->nominal) w += p->nominal[r - K] / g;
        }
        double z = force[r] / wr;
        if (z < -CN_BB_VERIFY_TOL || w < -CN_BB_VERIFY_TOL || fmin(z, w) > CN_BB_VERIFY_TOL)
            return -1;
    }
    for (int f = 0; f < p->Kf; f++) {
        int c = p->contact_of_fric[f];
        double wr = row_weight(m, &p->rows[c]);
        double zeta = p->mu[f] * force[c];
        for (int d = 0; d < D; d++) zeta -= force[K + f * D + d];
        zeta /= wr;
        double lam = lambda[f] / g;
        if (lam < -CN_BB_VERIFY_TOL || zeta < -CN_BB_VERIFY_TOL || fmin(lam, zeta) > CN_BB_VERIFY_TOL)
            return -1;
    }
    for (int b = 0; b < m->nb; b++)
        if (cn_mech_moves(m, b, acc, p->motion_tol)) return 1;
    return 0;
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
        int lp = bb_lp(s);
        if (lp < 0) out = -1;
        else if (lp == 1 && glp_get_obj_val(s->P) > s->p->motion_tol / sqrt(3.0)) {
            int c = bb_candidate(s);
            out = c == 1 ? 1 : -1;
        }
    }
    for (int i = 0; i < nv; i++) glp_set_obj_coef(s->P, i + 1, obj[i]);
    return out;
}

/* A node to explore: at depth, one pair fixed (pair >= 0, choice 1: z = 0, 2: w = 0), or one
 * friction group's sliding mode (group >= 0). */
typedef struct {
    int depth, pair, choice, group, mode; /* group -3: joint `pair`'s member `level` (in the
                                             order of mask `choice`) takes its mode in the
                                             joint's pattern `mode` */
    double bound;                         /* the parent's bound (scaled power; root: inf) */
    int level;
} BbEntry;

/* With two friction directions (2-D) a group's friction pairs have three modes, which between
 * them hold every solution (up to its sliding speed lambda, which no motion depends on: where
 * the group carries no normal force, lambda = |a_t| is as good as any larger one):
 *   0 stick     lambda = 0 (both rows w = +-a_t >= 0, so a_t = 0)
 *   1 slide +   zeta = 0, p_+ = 0, w_- = 0 (friction mu sum p_n along -, a_t = lambda >= 0)
 *   2 slide -   zeta = 0, p_- = 0, w_+ = 0
 * With D >= 3 directions evenly spaced about the normal (3-D), D + 1 modes:
 *   0     stick   lambda = 0 (w_d = d.a_t >= 0 in every direction, so a_t = 0)
 *   1 + j slide   zeta = 0, w_j = 0, p_d = 0 for every d other than j and j + 1 (mod D)
 * Every solution with lambda > 0 and a_t != 0 has lambda = max_d (-d.a_t) (were it larger, every
 * w_d > 0, no friction, zeta = mu p_n = 0 and lambda can be lowered to that max), attained by one
 * direction or two adjacent ones, and friction only there: mode 1 + j for the first of them.
 * With a_t = 0 and lambda > 0 the contact carries nothing and lambda = 0 is as good: mode 0.
 * (With nominal sliding v, w_d = d.(a_t + v) + lambda and the same holds of a_t + v; the modes
 * are used only without it, see below.)
 * One branch per mode instead of one per pair: the pairs' patterns, most of them empty, are
 * never visited one by one (about half the LPs on a 3-D block on an incline). In 3-D, only in
 * the energy search: in the component search (nominal sliding) the LPs after fixing D + 1
 * pairs at once take longer than the branches they save. bb_mode_pairs lists the pairs a mode
 * fixes (choice 1: z = 0, 2: w = 0); bb_mode fixes them (fixed/nfixed receive them). */
static int bb_mode_pairs(const Bb *s, int g, int mode, int *pairs, int *choice) {
    int K = s->p->K, D = s->p->D, lam = s->nrows + g, base = K + g * D, k = 0;
    if (mode == 0) {
        pairs[k] = lam, choice[k++] = 1;
    } else if (D == 2) {
        int plus = base, minus = base + 1;
        pairs[k] = lam, choice[k++] = 2;
        pairs[k] = mode == 1 ? plus : minus, choice[k++] = 1;
        pairs[k] = mode == 1 ? minus : plus, choice[k++] = 2;
    } else {
        int j = mode - 1, j1 = (j + 1) % D;
        pairs[k] = lam, choice[k++] = 2;
        pairs[k] = base + j, choice[k++] = 2;
        for (int d = 0; d < D; d++)
            if (d != j && d != j1) pairs[k] = base + d, choice[k++] = 1;
    }
    return k;
}

static void bb_mode(Bb *s, int g, int mode, int *fixed, int *nfixed) {
    int pairs[CN_BB_MAX_D + 2], choice[CN_BB_MAX_D + 2];
    int k = bb_mode_pairs(s, g, mode, pairs, choice);
    for (int j = 0; j < k; j++) {
        pair_set(s, pairs[j], choice[j]);
        fixed[(*nfixed)++] = pairs[j];
    }
}

/* The distance of the node's LP solution from a friction group's mode: the sum of what the mode
 * sets to zero (z of the pairs it fixes at z = 0, w of those at w = 0). */
static double bb_mode_far(const Bb *s, int g, int mode) {
    int pairs[CN_BB_MAX_D + 2], choice[CN_BB_MAX_D + 2];
    int k = bb_mode_pairs(s, g, mode, pairs, choice);
    double far = 0;
    for (int j = 0; j < k; j++) far += choice[j] == 1 ? s->x[pairs[j]] : s->wv[pairs[j]];
    return far;
}

/* The group whose friction modes to branch on for pair i: -1 when i is a normal pair, one of
 * the group's pairs is already fixed, or the pyramid has more than two directions outside the
 * energy search. */
static int bb_mode_group(const Bb *s, int i) {
    int K = s->p->K, D = s->p->D;
    if (i < K || D < 2 || D > CN_BB_MAX_D || (D > 2 && !s->energy)) return -1;
    int g = i < s->nrows ? (i - K) / D : i - s->nrows;
    if (s->fix[s->nrows + g]) return -1;
    for (int d = 0; d < D; d++)
        if (s->fix[K + g * D + d]) return -1;
    return g;
}

/* Are none of group g's pairs (its friction rows and sliding speed) fixed? */
static bool bb_group_free(const Bb *s, int g) {
    int K = s->p->K, D = s->p->D;
    if (s->fix[s->nrows + g]) return false;
    for (int d = 0; d < D; d++)
        if (s->fix[K + g * D + d]) return false;
    return true;
}

/* Joint patterns. A friction group's sliding modes (bb_mode_pairs: 0 stick, 1 + j sliding with
 * d_j a direction of largest -d.u, friction on d_j and d_{j+1}) depend only on its slip u, and
 * the slips of a joint's points are those of one relative motion of its two bodies: a face that
 * slides without turning slides the same way at every point, one that turns about its normal
 * slides each point about the same pole. A pattern (one mode per member) is kept when some
 * motion of the two bodies gives it: stick, u = 0; mode 1 + j, d_j.u <= d.u for every direction
 * d, strictly for d_{j-1} (a slip whose largest -d.u is at d_{j-1} and d_j is mode j's); and,
 * unless every member sticks, the sliding members' slips summing to a positive amount (the
 * conditions are cones). Every solution of the LCP has one of the patterns, each member's mode
 * being the one bb_mode_pairs assigns it, so branching on a joint's patterns leaves no solution
 * out, with far fewer children than the members' modes combined (a rectangle's 4 points at 8
 * directions: about 200 of 9^4 = 6,561). */
typedef struct {
    Bb *s;
    glp_prob *P;
    int J, k, D, nb2, body[2];
    const int *mem;           /* the joint's groups */
    int idx[CN_BB_JOINT_MAX];  /* k: the members enumerated (indices into mem) */
    unsigned char *pat;       /* k: the pattern being built */
    unsigned char *out;       /* cap patterns of k modes: those found */
    int cap, npat;
    long lps;
    bool over;                /* more than cap patterns, or CN_BB_JOINT_MAX_LPS */
} JointEnum;

/* Member i's slip along direction d as a row over the two bodies' velocities (out[1..nv],
 * dense; a rotational dof in units of g / radius, as the search's LP, so that every coefficient
 * is of order 1). */
static void je_row(const JointEnum *e, int i, int d, double *out) {
    const cnMotionProblem *p = e->s->p;
    const cnMech *m = p->m;
    const cnJRow *r = &p->rows[p->K + e->s->grep[e->mem[e->idx[i]]] * p->D + d];
    for (int c = 0; c <= e->nb2 * m->nd; c++) out[c] = 0;
    for (int x = 0; x < 2; x++) {
        int b = r->body[x];
        if (b < 0) continue;
        int slot = b == e->body[0] ? 0 : 1;
        double rad = m->radius[b] > 0 ? m->radius[b] : 1.0;
        for (int q = 0; q < m->nd; q++) out[slot * m->nd + q + 1] += r->c[x][q] / (q < m->dim ? 1.0 : rad);
    }
}

/* Adds the row sum_c coef[c] y_c (+ t when strict; bounds type, lo, hi) to the enumeration's
 * LP. */
static void je_add(JointEnum *e, const double *coef, bool strict, int type, double lo, double hi) {
    int nv = e->nb2 * e->s->p->m->nd, nz = 0, ind[14];
    double val[14];
    for (int c = 1; c <= nv; c++)
        if (coef[c] != 0) ind[++nz] = c, val[nz] = coef[c];
    if (strict) ind[++nz] = nv + 1, val[nz] = 1.0;
    int r = glp_add_rows(e->P, 1);
    glp_set_mat_row(e->P, r, nz, ind, val);
    glp_set_row_bnds(e->P, r, type, lo, hi);
}

/* Is the set the rows added so far describe nonempty? Column nv + 1 (t) is the margin of the
 * strict inequalities; the set is nonempty when the LP's largest t is positive (past rounding).
 * 1 yes, 0 no, -1 the solver failed. */
static int je_feasible(JointEnum *e) {
    if (++e->lps > CN_BB_JOINT_MAX_LPS) {
        e->over = true;
        return 0;
    }
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.presolve = GLP_OFF;
    /* a few dozen rows and columns: past this the simplex cycles (a degenerate vertex of badly
       scaled rows), the joint's patterns are given up and its points branched on one by one */
    parm.it_lim = CN_BB_JOINT_PIVOTS;
    for (int attempt = 0; attempt < 2; attempt++) {
        if (attempt == 1) glp_adv_basis(e->P, 0);
        if (glp_simplex(e->P, &parm) != 0) continue;
        int st = glp_get_status(e->P);
        if (st == GLP_OPT) return glp_get_obj_val(e->P) > CN_BB_JOINT_STRICT;
        if (st == GLP_NOFEAS) return 0;
    }
    return -1;
}

/* Depth-first over the members: member i's mode, its rows added, pruned when infeasible;
 * complete patterns are recorded. Returns -1 when the solver failed. */
static int je_dfs(JointEnum *e, int i, int nsliding) {
    int D = e->D, nv = e->nb2 * e->s->p->m->nd;
    double rj[13], rd[13], coef[13];
    for (int mode = 0; mode <= D && !e->over; mode++) {
        int first = glp_get_num_rows(e->P) + 1;
        if (mode == 0) {
            for (int d = 0; d < D; d++) je_row(e, i, d, rd), je_add(e, rd, false, GLP_FX, 0.0, 0.0);
        } else {
            je_row(e, i, mode - 1, rj);
            for (int d = 0; d < D; d++) {
                if (d == mode - 1) continue;
                je_row(e, i, d, rd);
                for (int c = 1; c <= nv; c++) coef[c] = rj[c] - rd[c];
                /* d_j.u <= d.u, and < for the direction before j: a slip whose friction may lie
                   on d_{j-1} and d_j is mode j's (bb_mode_pairs) */
                je_add(e, coef, d == (mode - 2 + D) % D, GLP_UP, 0.0, 0.0);
            }
        }
        /* row 1: minus the sliding members' slips along their own direction, >= 1 once one
           slides */
        e->pat[i] = (unsigned char)mode;
        int ns = nsliding + (mode > 0);
        for (int c = 0; c <= nv; c++) coef[c] = 0;
        for (int q = 0; q <= i; q++) {
            if (e->pat[q] == 0) continue;
            je_row(e, q, e->pat[q] - 1, rd);
            for (int c = 1; c <= nv; c++) coef[c] -= rd[c];
        }
        int nz = 0, ind[13];
        double val[13];
        for (int c = 1; c <= nv; c++)
            if (coef[c] != 0) ind[++nz] = c, val[nz] = coef[c];
        glp_set_mat_row(e->P, 1, nz, ind, val);
        if (ns > 0) glp_set_row_bnds(e->P, 1, GLP_LO, 1.0, 0.0);
        else glp_set_row_bnds(e->P, 1, GLP_FR, 0.0, 0.0);
        int f = je_feasible(e), rc = 0;
        if (f < 0) rc = -1;
        else if (f == 1 && i + 1 < e->k) rc = je_dfs(e, i + 1, ns);
        else if (f == 1 && e->npat >= e->cap) e->over = true;
        else if (f == 1) memcpy(e->out + (size_t)e->npat++ * (size_t)e->k, e->pat, (size_t)e->k);
        int nrow = glp_get_num_rows(e->P), del[65], nd = 0;
        for (int r = first; r <= nrow && nd < 64; r++) del[++nd] = r;
        if (nd > 0) glp_del_rows(e->P, nd, del);
        if (rc < 0) return -1;
    }
    return 0;
}

/* The joints (s->joint, jfirst, jmem, NJ): friction groups between the same two bodies whose
 * normal rows have the same direction, 2 to CN_BB_JOINT_MAX of them. Their patterns are found later
 * (joint_patterns). Only in 3-D, in the energy search. Returns -1 when out of memory. */
static int bb_joints(Bb *s) {
    const cnMotionProblem *p = s->p;
    const cnMech *m = p->m;
    int G = s->G;
    s->joint = cn_malloc(sizeof(int) * (size_t)(G + 1));
    s->jfirst = cn_malloc(sizeof(int) * (size_t)(G + 2));
    s->jmem = cn_malloc(sizeof(int) * (size_t)(G + 1));
    if (!s->joint || !s->jfirst || !s->jmem) return -1;
    int *root = s->jmem; /* scratch first: the first group of each group's joint */
    for (int g = 0; g < G; g++) {
        const cnJRow *rg = &p->rows[p->contact_of_fric[s->grep[g]]];
        root[g] = g;
        if ((rg->body[0] < 0 && rg->body[1] < 0) || s->gfirst[g + 1] - s->gfirst[g] != 1) continue;
        for (int h = 0; h < g && root[g] == g; h++) {
            if (root[h] != h) continue;
            const cnJRow *rh = &p->rows[p->contact_of_fric[s->grep[h]]];
            bool same = rg->body[0] == rh->body[0] && rg->body[1] == rh->body[1] &&
                        s->gfirst[h + 1] - s->gfirst[h] == 1;
            for (int x = 0; x < 2 && same; x++)
                for (int k = 0; k < m->dim && same; k++)
                    if (fabs(rg->c[x][k] - rh->c[x][k]) > CN_BB_SAME_ROW) same = false;
            if (same) root[g] = h;
        }
    }
    int NJ = 0;
    for (int g = 0; g < G; g++) s->joint[g] = -1;
    for (int g = 0; g < G; g++) {
        if (root[g] != g) continue;
        int k = 0;
        for (int h = g; h < G; h++) k += root[h] == g;
        if (k < 2 || k > CN_BB_JOINT_MAX) continue;
        for (int h = g; h < G; h++)
            if (root[h] == g) s->joint[h] = NJ;
        NJ++;
    }
    int at = 0;
    for (int J = 0; J < NJ; J++) {
        s->jfirst[J] = at;
        for (int g = 0; g < G; g++)
            if (s->joint[g] == J) s->jmem[at++] = g;
    }
    s->jfirst[NJ] = at;
    s->NJ = NJ;
    size_t slots = (size_t)NJ << CN_BB_JOINT_MAX;
    s->jnpat = cn_malloc(sizeof(int) * (slots + 1));
    s->jpat = cn_calloc(slots + 1, sizeof(unsigned char *));
    if (!s->jnpat || !s->jpat) return -1;
    for (size_t i = 0; i < slots; i++) s->jnpat[i] = -1;
    return 0;
}

/* The patterns of joint J's members in mask, found on first use: how many (0 when there are
 * too many, or the LP solver failed, or memory ran out: those points are then branched on one
 * by one). */
static int joint_patterns(Bb *s, int J, unsigned mask) {
    size_t slot = ((size_t)J << CN_BB_JOINT_MAX) + mask;
    if (s->jnpat[slot] >= 0) return s->jnpat[slot];
    const cnMotionProblem *p = s->p;
    int cap = CN_BB_JOINT_MAX_PATTERNS, n = s->jfirst[J + 1] - s->jfirst[J];
    const int *mem = s->jmem + s->jfirst[J];
    const cnJRow *r0 = &p->rows[p->contact_of_fric[s->grep[mem[0]]]];
    unsigned char pat[CN_BB_JOINT_MAX];
    s->jnpat[slot] = 0;
    JointEnum e = {s, NULL, J, 0, p->D, 0, {-1, -1}, mem, {0}, pat, NULL, cap, 0, 0, false};
    for (int q = 0; q < n; q++)
        if (mask >> q & 1) e.idx[e.k++] = q;
    if (e.k == 0) return 0;
    unsigned char *out = bb_tmp(s, TMP_JOUT, (size_t)cap * (size_t)e.k);
    if (!out) return 0;
    e.out = out;
    e.P = glp_create_prob();
    for (int x = 0; x < 2; x++)
        if (r0->body[x] >= 0) e.body[e.nb2++] = r0->body[x];
    int nv = e.nb2 * p->m->nd;
    glp_add_cols(e.P, nv + 1);
    for (int c = 1; c <= nv; c++) glp_set_col_bnds(e.P, c, GLP_FR, 0.0, 0.0);
    glp_set_col_bnds(e.P, nv + 1, GLP_UP, 0.0, 1.0); /* t <= 1 */
    glp_set_obj_coef(e.P, nv + 1, 1.0);
    glp_set_obj_dir(e.P, GLP_MAX);
    glp_add_rows(e.P, 1);
    glp_set_row_bnds(e.P, 1, GLP_FR, 0.0, 0.0);
    int rc = je_dfs(&e, 0, 0);
    glp_delete_prob(e.P);
    if (rc < 0 || e.over || e.npat == 0) {
        bb_tmp_free(s, TMP_JOUT);
        return 0;
    }
    s->tmp[TMP_JOUT] = NULL; /* the joint's now */
    unsigned char *kept = cn_realloc(out, (size_t)e.npat * (size_t)e.k);
    s->jpat[slot] = kept ? kept : out;
    s->jnpat[slot] = e.npat;
    return e.npat;
}

/* Room on the search's stack for more entries (its top entries kept); false when out of
 * memory. */
static bool bb_stack_room(Bb *s, int top, int more) {
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
    const cnJRow *row = i < s->nrows ? bb_row(s, i) : &p->rows[p->contact_of_fric[s->grep[i - s->nrows]]];
    return row->body[0] < 0 && row->body[1] < 0;
}

/* The nodes left open when the budget ran out (entry e, unsolved, and the stack's): the largest
 * of their parents' bounds on gravity's power (a bound on |a|_M^2 of every motion they hold;
 * energy search only), and the bodies their parents' LP motions move (indicative: a motion in
 * an open node may move others too). */
static void bb_frontier(Bb *s, const BbEntry *e, const BbEntry *stack, int top) {
    int nb = s->p->m->nb;
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
static void sort_by_far(int *order, int n, const double *far) {
    for (int a = 1; a < n; a++) {
        int v = order[a], b = a;
        while (b > 0 && far[order[b - 1]] < far[v]) order[b] = order[b - 1], b--;
        order[b] = v;
    }
}

/* Children of a node that branches on joint J's member `level` (in the mask's order): one per
 * mode that member has in the patterns agreeing with pattern rep on the members before it (rep
 * -1: every pattern), each child carrying such a pattern; the mode nearest the LP's solution is
 * pushed last (explored first). False when out of memory. */
static bool bb_prefix_children(Bb *s, int *top, const BbEntry *e, int J, unsigned mask, int rep, int level,
                               double obj) {
    int nm = s->jfirst[J + 1] - s->jfirst[J], k = 0, member = -1;
    for (int q = 0; q < nm; q++)
        if (mask >> q & 1 && k++ == level) member = s->jmem[s->jfirst[J] + q];
    size_t slot = ((size_t)J << CN_BB_JOINT_MAX) + mask;
    const unsigned char *pats = s->jpat[slot];
    int np = s->jnpat[slot], nmode = s->p->D + 1;
    int rep_of[CN_BB_MAX_D + 1], order[CN_BB_MAX_D + 1], n = 0;
    double far[CN_BB_MAX_D + 1] = {0};
    for (int m = 0; m < nmode; m++) rep_of[m] = -1;
    for (int q = 0; q < np; q++) {
        const unsigned char *pat = pats + (size_t)q * (size_t)k;
        if (rep >= 0 && memcmp(pat, pats + (size_t)rep * (size_t)k, (size_t)level) != 0) continue;
        if (rep_of[pat[level]] < 0) rep_of[pat[level]] = q;
    }
    for (int m = 0; m < nmode; m++)
        if (rep_of[m] >= 0) order[n] = m, far[m] = bb_mode_far(s, member, m), n++;
    if (!bb_stack_room(s, *top, n)) return false;
    BbEntry *stack = s->tmp[TMP_STACK];
    sort_by_far(order, n, far);
    for (int c = 0; c < n; c++)
        stack[(*top)++] = (BbEntry){e->depth + 1, J, (int)mask, -3, rep_of[order[c]], obj, level};
    return true;
}

/* Depth-first branch and bound with the objective set on s->P. Returns FOUND, NONE or
 * UNDECIDED; energy: the objective is gravity's power (pruned by still_within), else one
 * scaled motion component (pruned below the motion threshold). */
static cnMotionAnswer bb_search(Bb *s, bool energy) {
    s->energy = energy;
    const cnMotionProblem *p = s->p;
    const cnMech *m = p->m;
    int n = s->n;
    double W = m->wref, g = m->g;
    for (int i = 0; i < n; i++)
        if (s->fix[i]) pair_set(s, i, 0);
    for (int i = 0; i < n; i++)
        if (bb_dead(s, i)) pair_set(s, i, i < s->nrows ? 1 : 2);
    s->stack_cap = (p->D + 2) * (n + 2);
    BbEntry *stack = bb_tmp(s, TMP_STACK, sizeof(BbEntry) * (size_t)s->stack_cap);
    s->moving = bb_tmp(s, TMP_MOVING, (size_t)(n + 2) * (size_t)(p->m->nb + 1));
    int *fixed = bb_tmp(s, TMP_FIXED, sizeof(int) * (size_t)(n + 2)); /* pairs fixed by branching */
    int *mark = bb_tmp(s, TMP_MARK, sizeof(int) * (size_t)(n + 2));  /* nfixed before each depth */
    if (!stack || !fixed || !mark) {
        bb_tmp_free(s, TMP_STACK), bb_tmp_free(s, TMP_FIXED), bb_tmp_free(s, TMP_MARK);
        bb_tmp_free(s, TMP_MOVING);
        s->moving = NULL;
        s->why = "out of memory";
        return CN_MOTION_UNDECIDED;
    }
    int top = 0, tdepth = 0, nfixed = 0;
    stack[top++] = (BbEntry){0, -1, 0, -1, 0, INFINITY, 0};
    cnMotionAnswer ans = CN_MOTION_NONE;
    while (top > 0) {
        BbEntry e = stack[--top];
        while (tdepth > (e.depth > 0 ? e.depth - 1 : 0))
            for (tdepth--; nfixed > mark[tdepth];) pair_set(s, fixed[--nfixed], 0);
        if (e.depth > 0) {
            mark[tdepth++] = nfixed;
            if (e.group == -3) {
                int J = e.pair, nm = s->jfirst[J + 1] - s->jfirst[J], k = 0, q = 0, i = 0;
                unsigned mask = (unsigned)e.choice;
                for (int t = 0; t < nm; t++) k += mask >> t & 1;
                const unsigned char *pat = s->jpat[((size_t)J << CN_BB_JOINT_MAX) + mask] + (size_t)e.mode * (size_t)k;
                for (;; q++)
                    if (mask >> q & 1 && i++ == e.level) break;
                bb_mode(s, s->jmem[s->jfirst[J] + q], pat[e.level], fixed, &nfixed);
            } else if (e.group >= 0) {
                bb_mode(s, e.group, e.mode, fixed, &nfixed);
            } else {
                pair_set(s, e.pair, e.choice);
                fixed[nfixed++] = e.pair;
            }
        }
        double now = cn_seconds_since(&s->t0);
        if (s->nodes >= s->budget || now > s->seconds) {
            s->why = s->nodes >= s->budget ? "the branch-and-bound budget of nodes ran out"
                                           : "the search's time budget ran out";
            ans = CN_MOTION_UNDECIDED;
            bb_frontier(s, &e, stack, top);
            break;
        }
        s->nodes++;
        if (e.depth > s->depth) s->depth = e.depth;
        if (p->progress && now >= s->progress_at)
            p->progress(p->progress_ctx, s->nodes, now), s->progress_at = now + CN_PROGRESS_SECONDS;
        int lp = bb_lp(s);
        for (int round = 0; energy && lp == 1 && round < CN_BB_CUT_ROUNDS && bb_cut(s); round++)
            lp = bb_lp(s);
        if (energy && lp == 1) bb_trim_cuts(s, CN_BB_CUT_CAP);
        if (lp < 0) {
            s->why = "the LP solver (GLPK) failed on a node";
            ans = CN_MOTION_UNDECIDED;
            break;
        }
        if (lp == 0) continue;
        double obj = glp_get_obj_val(s->P);
        if (energy ? still_within(m, sqrt(fmax(obj * W * g, 0)), p->motion_tol)
                   : obj <= p->motion_tol / sqrt(3.0))
            continue;
        if (energy && obj < CN_BB_EXACT_BELOW && s->exact < CN_BB_EXACT_MAX && s->nodes < s->budget) {
            s->exact++;
            s->nodes++;
            int ex = bb_exact(s);
            if (ex == -2) {
                s->why = "the LP solver (GLPK) failed on a node";
                ans = CN_MOTION_UNDECIDED;
                break;
            }
            if (ex == 0) continue;
            obj = glp_get_obj_val(s->P);
            if (ex == 1 && still_within(m, sqrt(fmax(obj * W * g, 0)), p->motion_tol)) continue;
        }
        /* the most violated pair, and the free pair with the most room, in case none is */
        int worst = -1, roomy = -1;
        double wv = CN_BB_COMPL_TOL, room = -1;
        for (int i = 0; i < n; i++) {
            if (s->fix[i]) continue;
            double z = glp_get_col_prim(s->P, s->nv + i + 1);
            double w = glp_get_row_prim(s->P, s->nv + i + 1) - s->rowlo[i];
            s->x[i] = z, s->wv[i] = w;
            double v = fmin(z, w);
            if (v > wv) wv = v, worst = i;
            if (fmax(z, w) > room) room = fmax(z, w), roomy = i;
        }
        if (worst < 0) {
            int c = bb_candidate(s);
            if (c == 1) {
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
        if (s->moving) { /* the bodies this node's motion moves, for an undecided report */
            const cnMech *mm = p->m;
            for (int b = 0; b < mm->nb; b++) {
                double lin = 0, ang = 0;
                for (int k = 0; k < mm->nd; k++) {
                    double v = glp_get_col_prim(s->P, b * mm->nd + k + 1);
                    if (k < mm->dim) lin = fmax(lin, fabs(v));
                    else ang = fmax(ang, fabs(v));
                }
                s->moving[(size_t)e.depth * (size_t)mm->nb + (size_t)b] = lin + ang > p->motion_tol;
            }
        }
        if (e.group == -3) {
            int J = e.pair, nm = s->jfirst[J + 1] - s->jfirst[J], k = 0;
            for (int t = 0; t < nm; t++) k += (unsigned)e.choice >> t & 1;
            if (e.level + 1 < k) {
                if (!bb_prefix_children(s, &top, &e, J, (unsigned)e.choice, e.mode, e.level + 1, obj)) {
                    s->why = "out of memory";
                    ans = CN_MOTION_UNDECIDED;
                    break;
                }
                stack = s->tmp[TMP_STACK];
                continue;
            }
        }
        int grp = bb_mode_group(s, worst);
        int J = grp >= 0 && s->joint ? s->joint[grp] : -1;
        /* a joint: its members whose friction is free and whose normal force is not fixed at
           zero (an unloaded point's friction is zero whatever it slides) */
        unsigned mask = 0;
        int np = 0;
        if (J >= 0) {
            int nm = s->jfirst[J + 1] - s->jfirst[J];
            for (int q = 0; q < nm; q++) {
                int h = s->jmem[s->jfirst[J] + q], c = p->contact_of_fric[s->grep[h]];
                if (bb_group_free(s, h) && s->fix[c] != 1) mask |= 1u << q;
            }
            if (mask & (mask - 1)) np = joint_patterns(s, J, mask); /* two members or more */
        }
        if (np > 0) {
            if (!bb_prefix_children(s, &top, &e, J, mask, -1, 0, obj)) {
                s->why = "out of memory";
                ans = CN_MOTION_UNDECIDED;
                break;
            }
            stack = s->tmp[TMP_STACK];
        } else if (!bb_stack_room(s, top, p->D + 2)) {
            s->why = "out of memory";
            ans = CN_MOTION_UNDECIDED;
            break;
        } else if (grp >= 0) {
            stack = s->tmp[TMP_STACK];
            /* children: the modes, the one nearest the LP's solution (least to set to zero)
               explored first */
            int nm = p->D + 1, order[CN_BB_MAX_D + 1];
            double far[CN_BB_MAX_D + 1];
            for (int k = 0; k < nm; k++) order[k] = k, far[k] = bb_mode_far(s, grp, k);
            for (int a = 0; a < nm; a++)
                for (int b = a + 1; b < nm; b++)
                    if (far[order[b]] > far[order[a]]) {
                        int t = order[a];
                        order[a] = order[b], order[b] = t;
                    }
            for (int k = 0; k < nm; k++) stack[top++] = (BbEntry){e.depth + 1, -1, 0, grp, order[k], obj, 0};
        } else {
            stack = s->tmp[TMP_STACK];
            /* children: the one that keeps the larger of z and w is explored first */
            bool keep_z = s->x[worst] >= s->wv[worst];
            stack[top++] = (BbEntry){e.depth + 1, worst, keep_z ? 1 : 2, -1, 0, obj, 0};
            stack[top++] = (BbEntry){e.depth + 1, worst, keep_z ? 2 : 1, -1, 0, obj, 0};
        }
    }
    while (nfixed > 0) pair_set(s, fixed[--nfixed], 0);
    bb_tmp_free(s, TMP_STACK);
    bb_tmp_free(s, TMP_MOVING);
    s->moving = NULL;
    bb_tmp_free(s, TMP_FIXED);
    bb_tmp_free(s, TMP_MARK);
    if (ans == CN_MOTION_NONE && s->gray) {
        s->why = "solutions moving at the motion threshold could not be told from still ones";
        ans = CN_MOTION_UNDECIDED;
    }
    return ans;
}

/* The part of the search that calls GLPK, run under its error hook (cn_lp_guarded_call). */
typedef struct {
    Bb *s;
    bool energy;
    cnMotionAnswer answer;
    int built; /* bb_build's status: nonzero when out of memory */
} BbRun;

static void bb_run(void *ctx) {
    BbRun *r = ctx;
    Bb *s = r->s;
    bool energy = r->energy;
    if ((r->built = bb_build(s, energy)) != 0) return;
    if (energy && s->p->D > 2 && s->p->m->dim == 3 && !s->p->pointwise && bb_joints(s) != 0) {
        /* no joints: every point is branched on by itself */
        cn_free(s->joint);
        s->joint = NULL;
    }
    if (energy) {
        r->answer = bb_search(s, true);
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

cnStatus cn_motion_search(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                          double *acc, cnMotionStats *stats, cnDiag *diag) {
    unsigned char *open_bodies = stats->open_bodies;
    memset(stats, 0, sizeof *stats);
    stats->open_bodies = open_bodies;
    *answer = CN_MOTION_NONE;
    const cnMech *m = p->m;
    if (m->nb == 0 || !(m->g > 0)) return CN_OK;
    glp_term_hook(silent, NULL);
    bool energy = true;
    for (int i = 0; p->nominal && i < p->Kf * p->D; i++)
        if (p->nominal[i] != 0) energy = false;
    Bb s;
    memset(&s, 0, sizeof s);
    cnStatus st = CN_OK;
    s.p = p;
    s.nv = m->nb * m->nd;
    s.open_bodies = open_bodies;
    s.open_bound = INFINITY;
    if (bb_group(&s) != 0) {
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
    stats->depth = s.depth;
    for (int J = 0; s.joint && s.jnpat && J < s.NJ; J++) {
        bool used = false;
        for (unsigned mask = 0; mask < 1u << CN_BB_JOINT_MAX; mask++)
            used |= s.jnpat[((size_t)J << CN_BB_JOINT_MAX) + mask] > 0;
        stats->joints += used;
    }
    stats->why = *answer == CN_MOTION_UNDECIDED ? s.why : NULL;
    stats->open_power = *answer == CN_MOTION_UNDECIDED ? s.open_bound * m->wref * m->g : 0;
    if (*answer == CN_MOTION_UNDECIDED && open_bodies && !isfinite(s.open_bound))
        memset(open_bodies, 1, (size_t)m->nb); /* nothing bounded: every body */
done:
    if (s.P) glp_delete_prob(s.P);
    cn_free(s.sv);
    cn_free(s.wcol);
    cn_free(s.rowlo);
    cn_free(s.fix);
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
