/* The interior-point LP (lp_ipm.c) against GLPK's simplex, on random sparse LPs that are feasible
 * or infeasible by construction (with inequality rows too, which the checks do not give it today),
 * and the verdicts of whole walls decided with it and with GLPK alone. */
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "solve.h"

typedef struct {
    cnLpProblem lp;
    int *colptr, *rows;
    double *vals, *rhs, *cost;
} RandLp;

static void rand_lp_free(RandLp *R) {
    free(R->colptr), free(R->rows), free(R->vals), free(R->rhs), free(R->cost);
}

/* A sparse LP of neq equations and nin inequalities over n columns. Feasible: rhs from a random
 * x0 >= 0 (a third of it zero), inequalities slack by a random amount. Infeasible: a random y0
 * with A^T y0 <= -0.05 |a_j| on every column and rhs.y0 > 0 (Farkas), equations only. */
static void rand_lp(RandLp *R, cnRng *r, int neq, int nin, int n, bool feasible) {
    int m = neq + nin;
    R->colptr = calloc((size_t)n + 1, sizeof(int));
    R->rows = calloc((size_t)n * (size_t)m, sizeof(int));
    R->vals = calloc((size_t)n * (size_t)m, sizeof(double));
    R->rhs = calloc((size_t)m, sizeof(double));
    R->cost = calloc((size_t)n, sizeof(double));
    double *x0 = calloc((size_t)n, sizeof(double)), *y0 = calloc((size_t)m, sizeof(double));
    for (int i = 0; i < m; i++) y0[i] = cn_rng_range(r, -1, 1);
    int k = 0;
    for (int j = 0; j < n; j++) {
        R->colptr[j] = k;
        int start = k;
        double g = 0, norm = 0;
        for (int i = 0; i < m; i++) {
            if (i >= neq && !feasible) break;
            if (cn_rng_uniform(r) > 0.25 && !(i == j % m)) continue;
            R->rows[k] = i, R->vals[k] = cn_rng_range(r, -1, 1);
            g += R->vals[k] * y0[i], norm += R->vals[k] * R->vals[k];
            k++;
        }
        if (!feasible) {
            /* turn the column against y0, by at least 5 % of its length */
            double s = g > 0 ? -1 : 1;
            for (int t = start; t < k; t++) R->vals[t] *= s;
            g *= s;
            double want = -0.05 * sqrt(norm);
            if (g > want) {
                double yy = 0;
                for (int t = start; t < k; t++) yy += y0[R->rows[t]] * y0[R->rows[t]];
                for (int t = start; t < k && yy > 0; t++) R->vals[t] += (want - g) * y0[R->rows[t]] / yy;
            }
        }
        R->cost[j] = cn_rng_range(r, 0.5, 1.5);
        x0[j] = cn_rng_uniform(r) < 0.33 ? 0 : cn_rng_range(r, 0, 2);
    }
    R->colptr[n] = k;
    if (feasible) {
        for (int j = 0; j < n; j++)
            for (int t = R->colptr[j]; t < R->colptr[j + 1]; t++) R->rhs[R->rows[t]] += R->vals[t] * x0[j];
        for (int i = neq; i < m; i++) R->rhs[i] -= cn_rng_range(r, 0, 0.5);
    } else {
        for (int i = 0; i < neq; i++) R->rhs[i] = y0[i];
    }
    R->lp = (cnLpProblem){n, neq, feasible ? nin : 0, R->colptr, R->rows, R->vals, R->rhs, R->cost,
                          false, CN_LP_PRIMAL_AUTO, false, false};
    free(x0), free(y0);
}

/* Largest violation of lp's rows by x (equations both ways, inequalities from below) and of x >= 0. */
static double violation(const cnLpProblem *lp, const double *x) {
    int m = lp->neq + lp->nineq;
    double *ax = calloc((size_t)m, sizeof(double)), worst = 0;
    for (int j = 0; j < lp->nvars; j++) {
        worst = fmax(worst, -x[j]);
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) ax[lp->rows[t]] += lp->vals[t] * x[j];
    }
    for (int i = 0; i < m; i++) worst = fmax(worst, i < lp->neq ? fabs(ax[i] - lp->rhs[i]) : lp->rhs[i] - ax[i]);
    free(ax);
    return worst;
}

static void test_ipm_feasible(void) {
    cnRng r = {0x5eed1};
    int trials = 60, agree = 0, early = 0, saved = 0;
    double worst_gap = 0, worst_viol = 0, worst_any = 0;
    for (int t = 0; t < trials; t++) {
        int neq = 5 + (int)(cn_rng_uniform(&r) * 40), nin = (int)(cn_rng_uniform(&r) * 20);
        int n = (neq + nin) * (2 + (int)(cn_rng_uniform(&r) * 3));
        RandLp R;
        rand_lp(&R, &r, neq, nin, n, true);
        double *x = calloc((size_t)n, sizeof(double)), *xg = calloc((size_t)n, sizeof(double));
        double *y = calloc((size_t)(neq + nin), sizeof(double));
        cnLpIpmInfo info;
        cnDiag d;
        CHECK(cn_lp_ipm(&R.lp, CN_IPM_WEIGHT_FORCES, x, y, &info, &d) == CN_OK);
        CHECK_MSG(info.converged, "trial %d: %d iterations", t, info.iterations);
        double v = violation(&R.lp, x);
        worst_viol = fmax(worst_viol, v);
        CHECK_MSG(v <= 1e-8, "trial %d: violation %g", t, v);
        bool feas = false;
        CHECK(cn_lp_solve(&R.lp, &feas, xg, &d) == CN_OK);
        CHECK(feas);
        double cx = 0, cg = 0;
        for (int j = 0; j < n; j++) cx += R.cost[j] * x[j], cg += R.cost[j] * xg[j];
        /* the same optimum: the elastic penalty is exact here, and the cost (weighted 1e-6 against
         * the slacks) is met to the method's tolerance divided by that weight */
        double gap = fabs(cx - cg) / (1 + fabs(cg));
        worst_gap = fmax(worst_gap, gap);
        CHECK_MSG(gap <= 1e-4, "trial %d: cost %.12g, GLPK %.12g", t, cx, cg);
        if (gap <= 1e-4 && v <= 1e-8) agree++;
        /* any field will do: the method may stop before the optimum, on a field that holds to
         * the same precision, and never later */
        R.lp.any_field = true;
        int full = info.iterations;
        CHECK(cn_lp_ipm(&R.lp, CN_IPM_WEIGHT_FORCES, x, y, &info, &d) == CN_OK);
        R.lp.any_field = false;
        CHECK_MSG(info.converged || info.field_stop, "trial %d: any field, %d iterations", t, info.iterations);
        CHECK_MSG(!info.field_stop || info.elastic == 0, "trial %d: a field with elastic %g", t, info.elastic);
        double va = violation(&R.lp, x);
        worst_any = fmax(worst_any, va);
        CHECK_MSG(va <= 1e-8, "trial %d: any field, violation %g", t, va);
        CHECK_MSG(info.iterations <= full, "trial %d: any field after %d iterations, optimum after %d", t,
                  info.iterations, full);
        if (info.field_stop) early++, saved += full - info.iterations;
        free(x), free(xg), free(y);
        rand_lp_free(&R);
    }
    printf("lp ipm: %d of %d feasible LPs agree with GLPK (worst cost gap %.2g, worst violation %.2g)\n",
           agree, trials, worst_gap, worst_viol);
    /* and it is of use: most of these stop early */
    CHECK_MSG(early >= trials / 2, "any field stopped early on %d of %d", early, trials);
    printf("lp ipm: any field stopped early on %d of %d (%d iterations saved, worst violation %.2g)\n",
           early, trials, saved, worst_any);
}

static void test_ipm_infeasible(void) {
    cnRng r = {0x5eed2};
    int trials = 40, certified = 0;
    for (int t = 0; t < trials; t++) {
        int neq = 5 + (int)(cn_rng_uniform(&r) * 40);
        int n = neq * (2 + (int)(cn_rng_uniform(&r) * 3));
        RandLp R;
        rand_lp(&R, &r, neq, 0, n, false);
        double *x = calloc((size_t)n, sizeof(double)), *y = calloc((size_t)neq, sizeof(double));
        cnLpIpmInfo info;
        cnDiag d;
        CHECK(cn_lp_ipm(&R.lp, CN_IPM_WEIGHT_FORCES, x, y, &info, &d) == CN_OK);
        CHECK_MSG(info.elastic > 1e-6, "trial %d: elastic %g on an infeasible LP", t, info.elastic);
        /* no field to stop at */
        R.lp.any_field = true;
        CHECK(cn_lp_ipm(&R.lp, CN_IPM_WEIGHT_FORCES, x, y, &info, &d) == CN_OK);
        R.lp.any_field = false;
        CHECK_MSG(!info.field_stop && info.elastic > 1e-6, "trial %d: any field on an infeasible LP", t);
        /* then, as the check does, the certificate from the LP with almost no cost: gravity's
         * power b.y positive, every column's resistance A^T y below power / (1e6 columns), what
         * the check's lp_certificate demands */
        CHECK(cn_lp_ipm(&R.lp, CN_IPM_WEIGHT_CERTIFICATE, x, y, &info, &d) == CN_OK);
        double by = 0, worst = -INFINITY;
        for (int i = 0; i < neq; i++) by += R.rhs[i] * y[i];
        for (int j = 0; j < n; j++) {
            double g = 0;
            for (int k = R.colptr[j]; k < R.colptr[j + 1]; k++) g += R.vals[k] * y[R.rows[k]];
            worst = fmax(worst, g);
        }
        bool cert = by > 1e-7 && worst * 1e6 * n <= by;
        CHECK_MSG(cert, "trial %d: b.y %g, worst column %g", t, by, worst);
        if (cert) certified++;
        bool feas = true;
        double *xg = calloc((size_t)n, sizeof(double));
        CHECK(cn_lp_solve(&R.lp, &feas, xg, &d) == CN_OK);
        CHECK(!feas);
        free(x), free(y), free(xg);
        rand_lp_free(&R);
    }
    printf("lp ipm: %d of %d infeasible LPs answered with a certificate\n", certified, trials);
}

/* An LP shaped like the friction LP: "contacts" of one normal and nf friction columns over the
 * equation rows of one or two random "bodies" (3 rows each), each contact with a cone row
 * mu x_n - sum x_f >= 0 over its own columns, and some columns in no cone row. Feasible: rhs =
 * A x0 for an x0 inside the cones. Infeasible: every column turned against a random y0 on the
 * equations (the cone rows then cannot help). */
static void cone_lp(RandLp *R, cnRng *r, int nbody, int ncontact, int nf, bool feasible) {
    int neq = 3 * nbody, nin = ncontact, nfree = ncontact / 3, n = ncontact * (1 + nf) + nfree;
    int m = neq + nin;
    R->colptr = calloc((size_t)n + 1, sizeof(int));
    R->rows = calloc((size_t)n * 8, sizeof(int));
    R->vals = calloc((size_t)n * 8, sizeof(double));
    R->rhs = calloc((size_t)m, sizeof(double));
    R->cost = calloc((size_t)n, sizeof(double));
    double *x0 = calloc((size_t)n, sizeof(double)), *y0 = calloc((size_t)m, sizeof(double));
    for (int i = 0; i < neq; i++) y0[i] = cn_rng_range(r, -1, 1);
    int k = 0, j = 0;
    for (int c = 0; c <= ncontact; c++) {
        int b1 = (int)(cn_rng_uniform(r) * nbody), b2 = cn_rng_uniform(r) < 0.3 ? -1 : (int)(cn_rng_uniform(r) * nbody);
        if (b2 == b1) b2 = -1;
        int ncols = c < ncontact ? 1 + nf : nfree;
        double mu = cn_rng_range(r, 0.2, 1.0), fsum = 0;
        for (int q = 0; q < ncols; q++, j++) {
            R->colptr[j] = k;
            int start = k;
            double g = 0, norm = 0;
            for (int side = 0; side < 2; side++) {
                int b = side ? b2 : b1;
                if (b < 0) continue;
                for (int d = 0; d < 3; d++) {
                    R->rows[k] = 3 * b + d, R->vals[k] = cn_rng_range(r, -1, 1);
                    g += R->vals[k] * y0[3 * b + d], norm += R->vals[k] * R->vals[k];
                    k++;
                }
            }
            if (!feasible) {
                double sg = g > 0 ? -1 : 1;
                for (int t = start; t < k; t++) R->vals[t] *= sg;
                g *= sg;
                double want = -0.05 * sqrt(norm);
                if (g > want) {
                    double yy = 0;
                    for (int t = start; t < k; t++) yy += y0[R->rows[t]] * y0[R->rows[t]];
                    for (int t = start; t < k && yy > 0; t++) R->vals[t] += (want - g) * y0[R->rows[t]] / yy;
                }
            }
            if (c < ncontact) { /* the cone row */
                R->rows[k] = neq + c, R->vals[k] = q == 0 ? mu : -1, k++;
                x0[j] = q == 0 ? cn_rng_range(r, 0.5, 2) : 0;
                if (q > 0 && cn_rng_uniform(r) < 0.5) {
                    x0[j] = cn_rng_range(r, 0, mu * x0[j - q] / nf);
                    fsum += x0[j];
                }
            } else {
                x0[j] = cn_rng_uniform(r) < 0.5 ? 0 : cn_rng_range(r, 0, 1);
            }
            R->cost[j] = q == 0 && c < ncontact ? 1.0 : 0.0;
        }
        (void)fsum;
    }
    R->colptr[n] = k;
    if (feasible) {
        for (int jj = 0; jj < n; jj++)
            for (int t = R->colptr[jj]; t < R->colptr[jj + 1]; t++)
                if (R->rows[t] < neq) R->rhs[R->rows[t]] += R->vals[t] * x0[jj];
    } else {
        for (int i = 0; i < neq; i++) R->rhs[i] = y0[i];
    }
    R->lp = (cnLpProblem){n, neq, nin, R->colptr, R->rows, R->vals, R->rhs, R->cost,
                          false, CN_LP_PRIMAL_AUTO, false, false};
    free(x0), free(y0);
}

/* Cone rows over disjoint columns are eliminated from the interior point's normal equations
 * (cnLpIpmInfo.eliminated): the same optimum as GLPK's simplex on feasible LPs, and a Farkas
 * certificate (inequality duals nonnegative) on infeasible ones. */
static void test_ipm_cone_rows(void) {
    cnRng r = {0x5eed3};
    int trials = 60, agree = 0, certified = 0;
    for (int t = 0; t < trials; t++) {
        bool feasible = t % 3 != 2;
        int nbody = 2 + (int)(cn_rng_uniform(&r) * 12), ncontact = nbody + (int)(cn_rng_uniform(&r) * 3 * nbody);
        int nf = t % 2 ? 2 : 4;
        RandLp R;
        cone_lp(&R, &r, nbody, ncontact, nf, feasible);
        int n = R.lp.nvars, m = R.lp.neq + R.lp.nineq;
        double *x = calloc((size_t)n, sizeof(double)), *xg = calloc((size_t)n, sizeof(double));
        double *y = calloc((size_t)m, sizeof(double));
        cnLpIpmInfo info;
        cnDiag d;
        CHECK(cn_lp_ipm(&R.lp, CN_IPM_WEIGHT_FORCES, x, y, &info, &d) == CN_OK);
        CHECK_MSG(info.eliminated, "trial %d: cone rows not eliminated", t);
        bool feas = false;
        CHECK(cn_lp_solve(&R.lp, &feas, xg, &d) == CN_OK);
        CHECK_MSG(feas == feasible, "trial %d: GLPK says %s", t, feas ? "feasible" : "infeasible");
        if (feasible) {
            double v = violation(&R.lp, x), cx = 0, cg = 0;
            for (int j = 0; j < n; j++) cx += R.cost[j] * x[j], cg += R.cost[j] * xg[j];
            double gap = fabs(cx - cg) / (1 + fabs(cg));
            CHECK_MSG(v <= 1e-8, "trial %d: violation %g (%d iterations)", t, v, info.iterations);
            CHECK_MSG(gap <= 1e-4, "trial %d: cost %.12g, GLPK %.12g, conv %d it %d el %g", t, cx, cg, info.converged, info.iterations, info.elastic);
            if (v <= 1e-8 && gap <= 1e-4) agree++;
        } else {
            CHECK_MSG(info.elastic > 1e-6, "trial %d: elastic %g on an infeasible LP", t, info.elastic);
            CHECK(cn_lp_ipm(&R.lp, CN_IPM_WEIGHT_CERTIFICATE, x, y, &info, &d) == CN_OK);
            double by = 0, worst = -INFINITY, yin = 0;
            for (int i = 0; i < R.lp.neq; i++) by += R.rhs[i] * y[i];
            for (int i = R.lp.neq; i < m; i++) yin = fmin(yin, y[i]);
            for (int j = 0; j < n; j++) {
                double g = 0;
                for (int k = R.colptr[j]; k < R.colptr[j + 1]; k++) g += R.vals[k] * y[R.rows[k]];
                worst = fmax(worst, g);
            }
            bool cert = by > 1e-7 && worst * 1e6 * n <= by && yin >= -1e-12;
            CHECK_MSG(cert, "trial %d: b.y %g, worst column %g, least inequality dual %g", t, by, worst, yin);
            if (cert) certified++;
        }
        free(x), free(xg), free(y);
        rand_lp_free(&R);
    }
    printf("lp ipm: cone rows eliminated, %d feasible LPs agree with GLPK, %d infeasible certified (of %d)\n",
           agree, certified, trials);
}

/* The descent (lp_descent.c): a beam on two supports by the lever rule; then random LPs, feasible
 * and infeasible by construction, in blocks of 3 and 6 rows: whenever it says "met", its x must
 * solve the LP (checked here row by row), and it must never say so on an infeasible one. */
static void test_descent(void) {
    /* a 2-D body (rows: force x, force y, moment) of weight 3 held by upward forces at x = -1
     * and x = 2, and a third column pushing sideways that must stay unused: 2 and 1 */
    int colptr[] = {0, 2, 4, 5};
    int rows[] = {1, 2, 1, 2, 0};
    double vals[] = {1, -1, 1, 2, 1};
    double rhs[] = {0, 3, 0}, x[3];
    cnLpProblem lp = {3, 3, 0, colptr, rows, vals, rhs, NULL, false, CN_LP_PRIMAL_AUTO, false, false};
    int order1[] = {0};
    bool met = false;
    CHECK(cn_lp_descent(&lp, 3, order1, x, &met) == CN_OK);
    CHECK_MSG(met && fabs(x[0] - 2) < 1e-14 && fabs(x[1] - 1) < 1e-14 && x[2] == 0,
              "lever rule: met %d, %g %g %g", met, x[0], x[1], x[2]);
    /* and not when the weight is pulled sideways (nothing holds it that way) */
    rhs[0] = -0.5;
    CHECK(cn_lp_descent(&lp, 3, order1, x, &met) == CN_OK);
    CHECK(!met);

    /* a NaN or an infinity in the data is never "met" (an overflowed weight: its residual
     * is NaN, which a max() would drop) */
    rhs[0] = 0, rhs[1] = NAN;
    CHECK(cn_lp_descent(&lp, 3, order1, x, &met) == CN_OK);
    CHECK_MSG(!met, "NaN weight: met");
    rhs[1] = INFINITY;
    CHECK(cn_lp_descent(&lp, 3, order1, x, &met) == CN_OK);
    CHECK_MSG(!met, "infinite weight: met");

    /* what it does not take, it does not claim: an order that is not a permutation, and a column
     * whose rows leave a block and come back (two blocks of 3 rows; the first column touches
     * rows 0, 3, 1) */
    {
        int cp[] = {0, 3, 5, 7};
        int rw[] = {0, 3, 1, 4, 5, 1, 2};
        double vl[] = {0.5, 1, 0.5, 1, 1, 1, 1}, rh[] = {0, 1, 1, 1, 1, 1}, x2[3];
        cnLpProblem lp2 = {3, 6, 0, cp, rw, vl, rh, NULL, false, CN_LP_PRIMAL_AUTO, false, false};
        int twice[] = {0, 0}, fine[] = {1, 0};
        CHECK(cn_lp_descent(&lp2, 3, twice, x2, &met) == CN_OK);
        CHECK_MSG(!met, "an order with a block twice: met");
        CHECK(cn_lp_descent(&lp2, 3, fine, x2, &met) == CN_OK);
        CHECK_MSG(!met, "a column back in a block it left: met");
    }

    cnRng r = {0x5eed3};
    int trials = 400, feasible_met = 0, feasible_n = 0, infeasible_n = 0;
    double worst = 0;
    for (int t = 0; t < trials; t++) {
        int block = cn_rng_uniform(&r) < 0.5 ? 3 : 6, nblk = 1 + (int)(cn_rng_uniform(&r) * 8);
        int neq = block * nblk, n = neq * (1 + (int)(cn_rng_uniform(&r) * 4));
        bool feasible = cn_rng_uniform(&r) < 0.6;
        RandLp R;
        rand_lp(&R, &r, neq, 0, n, feasible);
        int *order = malloc(sizeof(int) * (size_t)nblk);
        for (int k = 0; k < nblk; k++) order[k] = k;
        for (int k = nblk - 1; k > 0; k--) { /* a random order */
            int q = (int)(cn_rng_uniform(&r) * (k + 1));
            int tmp = order[k];
            order[k] = order[q], order[q] = tmp;
        }
        double *xs = calloc((size_t)n, sizeof(double));
        CHECK(cn_lp_descent(&R.lp, block, order, xs, &met) == CN_OK);
        if (met) {
            double v = violation(&R.lp, xs);
            worst = fmax(worst, v);
            CHECK_MSG(v <= 1e-8, "trial %d: met, but violates a row by %g", t, v);
        }
        CHECK_MSG(feasible || !met, "trial %d: met on an infeasible LP", t);
        if (feasible) feasible_n++, feasible_met += met;
        else infeasible_n++;
        free(order), free(xs);
        rand_lp_free(&R);
    }
    printf("lp descent: met %d of %d feasible random LPs (worst violation %.2g), none of %d infeasible\n",
           feasible_met, feasible_n, worst, infeasible_n);
}

/* A running-bond wall (make_wall.sh's) of rows x cols bricks with friction mu and gravity tilted
 * by tilt radians: large enough (with friction) for the interior-point method. */
static char *wall_json(int rows, int cols, double mu, double tilt) {
    size_t cap = 256 + (size_t)rows * (size_t)cols * 128, len = 0;
    char *s = malloc(cap);
    len += (size_t)snprintf(s + len, cap - len,
                            "{\"dimension\": 2, \"friction\": %g, \"gravity\": [%.17g, %.17g], \"parts\": ["
                            "{\"name\": \"ground\", \"fixed\": true, \"polygon\": [[-2,-1],[%d,-1],[%d,0],[-2,0]]}",
                            mu, 9.81 * sin(tilt), -9.81 * cos(tilt), 2 * cols + 3, 2 * cols + 3);
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++) {
            int x = 2 * c + (r % 2);
            len += (size_t)snprintf(s + len, cap - len,
                                    ", {\"name\": \"r%dc%d\", \"polygon\": [[%d,%d],[%d,%d],[%d,%d],[%d,%d]]}", r,
                                    c, x, r, x + 2, r, x + 2, r + 1, x, r + 1);
        }
    snprintf(s + len, cap - len, "]}");
    return s;
}

/* n levers side by side, frictionless: a plank B on a fixed apex with its weight off it, held down
 * at its short end by a block A whose other end rests on a fixed pillar. A can share its weight
 * between the pillar and B in many ways, and B stands only if A presses it with one particular
 * moment (0.8 of A's 5 weights' units about the apex: possible, e.g. 1.6 at B's tip): the descent,
 * which settles A before B, picks a share for A alone and fails, and the LP is solved whole. */
static char *levers_json(int n) {
    size_t cap = 256 + (size_t)n * 600, len = 0;
    char *s = malloc(cap);
    len += (size_t)snprintf(s + len, cap - len, "{\"dimension\": 2, \"parts\": [");
    for (int i = 0; i < n; i++) {
        double d = 8.0 * i;
        len += (size_t)snprintf(
            s + len, cap - len,
            "%s{\"name\": \"pillar%d\", \"fixed\": true, \"polygon\": [[%g,0],[%g,0],[%g,1.2],[%g,1.2]]},"
            "{\"name\": \"apex%d\", \"fixed\": true, \"polygon\": [[%g,0],[%g,0],[%g,1]]},"
            "{\"name\": \"B%d\", \"polygon\": [[%g,1],[%g,1],[%g,1.2],[%g,1.2]]},"
            "{\"name\": \"A%d\", \"polygon\": [[%g,1.2],[%g,1.2],[%g,3.2],[%g,3.2]]}",
            i ? "," : "", i, d - 3, d - 2, d - 2, d - 3, i, d - 0.5, d + 0.5, d, i, d - 1, d + 3, d + 3,
            d - 1, i, d - 3, d - 0.5, d - 0.5, d - 3);
    }
    snprintf(s + len, cap - len, "]}");
    return s;
}

/* method: what answers the LP without CN_ROUTE_LP_GLPK_ONLY. LPs of 2,000 columns and more go to
 * the load descent (without friction cones) and then to cairn's interior point; with friction
 * the frictionless LP runs first (its field is a static solution too) */
static void check_both_ways(const char *json, const char *label, cnVerdict want, const char *method) {
    cnAssembly *a = load_ok(json);
    if (!a) return;
    cnCheckOptions o = cn_check_options_default();
    cnCheckResult ri, rg;
    cnDiag d;
    memset(&ri, 0, sizeof ri), memset(&rg, 0, sizeof rg);
    CHECK_MSG(cn_check(a, &o, &ri, &d) == CN_OK, "%s: %s", label, d.message);
    o.route = CN_ROUTE_LP_GLPK_ONLY;
    CHECK_MSG(cn_check(a, &o, &rg, &d) == CN_OK, "%s: %s", label, d.message);
    CHECK_MSG(ri.verdict == want && rg.verdict == want, "%s: verdict %d with the interior point, %d with GLPK, want %d",
              label, ri.verdict, rg.verdict, want);
    const char *mi = cn_lp_method_name(ri.solver.lp_method), *mg = cn_lp_method_name(rg.solver.lp_method);
    CHECK_MSG(mi && !strcmp(mi, method), "%s: LP by %s", label, mi ? mi : "nothing");
    CHECK(rg.solver.lp_method == CN_LP_METHOD_GLPK_SIMPLEX || rg.solver.lp_method == CN_LP_METHOD_GLPK_INTERIOR ||
          rg.solver.lp_method == CN_LP_METHOD_GLPK_ELASTIC);
    static const char *names[] = {"stable", "unstable", "not guaranteed", "undecided"};
    printf("lp ipm: %s: %s both ways (LP by %s; by %s)\n", label, names[want], mi ? mi : "-", mg ? mg : "-");
    cn_check_result_free(&ri);
    cn_check_result_free(&rg);
    cn_assembly_free(a);
}

static void test_ipm_walls(void) {
    /* 240 bricks, about 1,400 contacts: over 4,000 LP columns with friction */
    char *s = wall_json(12, 20, 0.6, 0);
    check_both_ways(s, "wall, friction 0.6", CN_VERDICT_STABLE, "GLPK simplex"); /* frictionless first */
    free(s);
    /* gravity tilted 0.1 rad along the wall: no frictionless field (the ground must hold the rows
     * sideways), so the friction LP decides; a static field exists, its 1,400 contacts are too
     * many for the whole search for a motion from rest, and an end brick of the top row, centred
     * over the edge of the brick below, tips by itself (search_local.c): not guaranteed */
    s = wall_json(12, 20, 0.6, 0.1);
    check_both_ways(s, "wall, friction 0.6, tilted", CN_VERDICT_NOT_GUARANTEED, "interior point");
    free(s);
    /* 600 bricks, about 3,500 contacts: one LP column each */
    s = wall_json(20, 30, 0, 0);
    check_both_ways(s, "wall, frictionless", CN_VERDICT_STABLE, "load descent");
    free(s);
    s = wall_json(20, 30, 0.6, 0);
    check_both_ways(s, "wall, friction 0.6, 600 bricks", CN_VERDICT_STABLE, "load descent");
    free(s);
    /* gravity turned 0.7 rad (tan 0.84, past mu 0.6): the whole wall slides, shown by the whole
     * assembly on its supports (GLPK's elastic simplex alone, the other way); with the
     * certificate in hand the dense LCP (5,416 unknowns) gets 2e10 / n^2 pivots, and the motion
     * reported is the certificate's (26,137 pivots to a secondary ray, 80 s, before) */
    s = wall_json(12, 20, 0.6, 0.7);
    {
        cnAssembly *a = load_ok(s);
        cnCheckOptions o = cn_check_options_default();
        cnCheckResult r;
        cnDiag d;
        memset(&r, 0, sizeof r);
        if (a && cn_check(a, &o, &r, &d) == CN_OK) {
            CHECK(r.verdict == CN_VERDICT_UNSTABLE && r.solver.lp_method == CN_LP_METHOD_WHOLE);
            CHECK_MSG(r.solver.pivots <= 2e10 / ((double)r.solver.lcp_size * r.solver.lcp_size) + 1,
                      "%d pivots on %d unknowns", r.solver.pivots, r.solver.lcp_size);
        } else {
            CHECK_MSG(0, "sliding wall: %s", d.message);
        }
        cn_check_result_free(&r);
        cn_assembly_free(a);
    }
    check_both_ways(s, "wall, friction 0.6, turned past it", CN_VERDICT_UNSTABLE, "whole assembly");
    free(s);
    s = levers_json(420); /* 2,100 contacts */
    check_both_ways(s, "levers held down, frictionless", CN_VERDICT_STABLE, "interior point");
    free(s);
}

void test_lp(void) {
    test_descent();
    test_ipm_feasible();
    test_ipm_infeasible();
    test_ipm_cone_rows();
    test_ipm_walls();
}
