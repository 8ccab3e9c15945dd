/* LCP solvers against brute-force enumeration of complementary bases, against each other, and on
 * known hard cases (Murty's exponential example, degenerate and redundant contact sets). */
#include <stdlib.h>
#include <string.h>

#include "cairn/cairn.h"
#include "pieces.h"
#include "solve.h"
#include "test.h"

/* Brute force: try every support S (z_S from M_SS z_S = -q_S, z elsewhere 0). Returns 1 and
 * fills z when some S gives a solution verified at tolerance tol. Independent of the solvers:
 * plain Gaussian elimination per subset. */
static int brute_force(const cnLcp *p, double *z, double tol) {
    int n = p->n;
    double *K = malloc(sizeof(double) * (size_t)(n * n + 1));
    double *b = malloc(sizeof(double) * (size_t)(n + 1));
    int *idx = malloc(sizeof(int) * (size_t)(n + 1));
    int found = 0;
    for (unsigned long S = 0; S < (1UL << n) && !found; S++) {
        int m = 0;
        for (int i = 0; i < n; i++)
            if (S & (1UL << i)) idx[m++] = i;
        for (int a = 0; a < m; a++) {
            for (int c = 0; c < m; c++) K[a * m + c] = p->M[idx[a] * n + idx[c]];
            b[a] = -p->q[idx[a]];
        }
        /* Gaussian elimination with partial pivoting */
        int ok = 1;
        for (int k = 0; k < m && ok; k++) {
            int piv = k;
            for (int i = k + 1; i < m; i++)
                if (fabs(K[i * m + k]) > fabs(K[piv * m + k])) piv = i;
            if (fabs(K[piv * m + k]) < 1e-12) {
                ok = 0;
                break;
            }
            for (int c = 0; c < m; c++) {
                double t = K[k * m + c];
                K[k * m + c] = K[piv * m + c];
                K[piv * m + c] = t;
            }
            double t = b[k];
            b[k] = b[piv];
            b[piv] = t;
            for (int i = k + 1; i < m; i++) {
                double f = K[i * m + k] / K[k * m + k];
                for (int c = k; c < m; c++) K[i * m + c] -= f * K[k * m + c];
                b[i] -= f * b[k];
            }
        }
        if (!ok) continue;
        for (int i = m - 1; i >= 0; i--) {
            double s = b[i];
            for (int c = i + 1; c < m; c++) s -= K[i * m + c] * b[c];
            b[i] = s / K[i * m + i];
        }
        for (int i = 0; i < n; i++) z[i] = 0;
        for (int a = 0; a < m; a++) z[idx[a]] = b[a];
        if (cn_lcp_verify(p, z, tol, NULL)) found = 1;
    }
    free(K);
    free(b);
    free(idx);
    return found;
}

static void random_psd(cnRng *r, cnLcp *p, int n, int rank) {
    /* M = B^T B with B rank x n: singular when rank < n (redundant contacts) */
    double *B = malloc(sizeof(double) * (size_t)(rank * n + 1));
    for (int i = 0; i < rank * n; i++) B[i] = cn_rng_range(r, -1, 1);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double s = 0;
            for (int k = 0; k < rank; k++) s += B[k * n + i] * B[k * n + j];
            p->M[i * n + j] = s;
        }
    /* q in range of M plus a nonnegative part, as contact problems have (q = J a0) */
    double y[16];
    for (int k = 0; k < rank; k++) y[k] = cn_rng_range(r, -1, 1);
    for (int i = 0; i < n; i++) {
        double s = 0;
        for (int k = 0; k < rank; k++) s += B[k * n + i] * y[k];
        p->q[i] = s;
    }
    free(B);
}

static void test_small_known(void) {
    cnLcp p;
    cn_lcp_alloc(&p, 2);
    /* M = [[2,1],[1,2]], q = [-5,-6]: z = (4/3, 7/3), w = 0 */
    double M[4] = {2, 1, 1, 2}, q[2] = {-5, -6};
    memcpy(p.M, M, sizeof M);
    memcpy(p.q, q, sizeof q);
    double z[2], w[2];
    cnLcpInfo info;
    CHECK(cn_lcp_lemke(&p, NULL, z, w, &info) == CN_LCP_SOLVED);
    CHECK_NEAR(z[0], 4.0 / 3, 1e-12);
    CHECK_NEAR(z[1], 7.0 / 3, 1e-12);
    CHECK(cn_lcp_pivot(&p, NULL, z, w, &info) == CN_LCP_SOLVED);
    CHECK_NEAR(z[0], 4.0 / 3, 1e-12);
    CHECK_NEAR(z[1], 7.0 / 3, 1e-12);
    /* q >= 0: z = 0 */
    p.q[0] = 1, p.q[1] = 0;
    CHECK(cn_lcp_lemke(&p, NULL, z, w, &info) == CN_LCP_SOLVED);
    CHECK(z[0] == 0 && z[1] == 0);
    /* infeasible: w1 = -z2 - 1 < 0 always -> M = [[0,-1],[0,0]] */
    double M2[4] = {0, -1, 0, 0}, q2[2] = {-1, 0};
    memcpy(p.M, M2, sizeof M2);
    memcpy(p.q, q2, sizeof q2);
    CHECK(cn_lcp_lemke(&p, NULL, z, w, &info) == CN_LCP_RAY);
    bool feas = true;
    CHECK(cn_lcp_feasible(&p, &feas, NULL) == CN_OK);
    CHECK(!feas);
    cn_lcp_free(&p);

    /* M = I, q = (-1e-12, 1, 1, 1.5e-9): z = (1e-12, 0, 0, 0) exactly. Only a row with q_i < 0
     * may leave at the first pivot; a q_i within the tie tolerance of the minimum (1.5e-9 over
     * a spread d_i near 2) once did, starting z0 below zero and ending on z = 0, w_0 = -1e-12 */
    cn_lcp_alloc(&p, 4);
    for (int i = 0; i < 4; i++) p.M[i * 4 + i] = 1;
    p.q[0] = -1e-12, p.q[1] = 1, p.q[2] = 1, p.q[3] = 1.5e-9;
    double z4[4], w4[4];
    CHECK(cn_lcp_lemke(&p, NULL, z4, w4, &info) == CN_LCP_SOLVED);
    CHECK(z4[0] == 1e-12 && z4[1] == 0 && z4[2] == 0 && z4[3] == 0 && w4[0] == 0);
    cn_lcp_free(&p);

    /* a general (not copositive-plus) M where the spread covering vector ends on a secondary
     * ray and d = 1 finds the solution z = (4/3, 13/3, 7/3, 0, 0): both are tried */
    const double Mg[25] = {-4, 2, -1, 3, 5, -5, 1, 1, -1, -4, -2, -1, 3, -4, 5,
                           1, 0, 2, -2, 5, 3, -3, 4, 3, -4};
    cn_lcp_alloc(&p, 5);
    memcpy(p.M, Mg, sizeof Mg);
    p.q[0] = -1;
    double z5[5], w5[5];
    CHECK(cn_lcp_lemke(&p, NULL, z5, w5, &info) == CN_LCP_SOLVED);
    CHECK_NEAR(z5[0], 4.0 / 3, 1e-12);
    CHECK_NEAR(z5[1], 13.0 / 3, 1e-12);
    CHECK_NEAR(z5[2], 7.0 / 3, 1e-12);
    CHECK(z5[3] == 0 && z5[4] == 0);
    cn_lcp_free(&p);
}

/* Murty's example: M upper triangular with 1 on the diagonal and 2 above, q = -(2^n, ...)
 * style; Lemke needs 2^n pivots (counting the first one), a check that it follows the
 * textbook path exactly, and that the default budget lets it (it stopped from n = 11, at a
 * fixed 50 n + 1000 pivots). */
static void test_murty(void) {
    for (int n = 3; n <= 16; n++) {
        cnLcp p;
        cn_lcp_alloc(&p, n);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) p.M[i * n + j] = i == j ? 1 : (j > i ? 2 : 0);
        /* q_i = -(2^{n} - 2^{n-1-i}) ... as in Siconos' lcp_exp_murty2 for n = 6 */
        for (int i = 0; i < n; i++) p.q[i] = -(ldexp(1, n + 1) - ldexp(1, i + 1));
        double *z = calloc((size_t)n, sizeof(double)), *w = calloc((size_t)n, sizeof(double));
        cnLcpInfo info;
        CHECK(cn_lcp_lemke(&p, NULL, z, w, &info) == CN_LCP_SOLVED);
        CHECK_MSG(info.pivots == (1 << n), "n = %d: %d pivots, expected 2^n = %d", n, info.pivots,
                  1 << n);
        CHECK(info.residual < 1e-12);
        free(z);
        free(w);
        cn_lcp_free(&p);
    }
}

static void test_random_psd(void) {
    cnRng r = {0x5eedULL};
    int solved_l = 0, solved_p = 0, total = 0, pivot_fail = 0;
    for (int t = 0; t < 400; t++) {
        int n = 1 + (int)(cn_rng_uniform(&r) * 9);
        int rank = 1 + (int)(cn_rng_uniform(&r) * n);
        cnLcp p;
        cn_lcp_alloc(&p, n);
        random_psd(&r, &p, n, rank);
        double z[16], w[16], zb[16], wb[16], zp[16], wp[16];
        int exists = brute_force(&p, zb, 1e-9);
        cn_lcp_residual(&p, zb, wb);
        cnLcpInfo info;
        cnLcpStatus sl = cn_lcp_lemke(&p, NULL, z, w, &info);
        cnLcpStatus sp = cn_lcp_pivot(&p, NULL, zp, wp, &info);
        total++;
        /* q in range(M) with M PSD: feasible, so a solution exists and both must find it */
        CHECK_MSG(exists, "trial %d: brute force found no solution", t);
        CHECK_MSG(sl == CN_LCP_SOLVED, "trial %d (n=%d rank=%d): lemke %s", t, n, rank,
                  cn_lcp_status_name(sl));
        solved_l += sl == CN_LCP_SOLVED;
        solved_p += sp == CN_LCP_SOLVED;
        if (sp != CN_LCP_SOLVED) pivot_fail++;
        /* symmetric PSD: w = M z + q is the same for every solution */
        if (exists && sl == CN_LCP_SOLVED)
            for (int i = 0; i < n; i++) CHECK_NEAR(w[i], wb[i], 1e-7 * (1 + fabs(wb[i])));
        if (exists && sp == CN_LCP_SOLVED)
            for (int i = 0; i < n; i++) CHECK_NEAR(wp[i], wb[i], 1e-7 * (1 + fabs(wb[i])));
        cn_lcp_free(&p);
    }
    CHECK_MSG(pivot_fail <= total / 100, "principal pivoting failed on %d of %d", pivot_fail, total);
    printf("random PSD: %d problems, lemke solved %d, pivot solved %d\n", total, solved_l, solved_p);
}

/* P-matrices (positive definite, non-symmetric): the solution is unique. */
static void test_random_pmatrix(void) {
    cnRng r = {0xabcdefULL};
    for (int t = 0; t < 300; t++) {
        int n = 1 + (int)(cn_rng_uniform(&r) * 8);
        cnLcp p;
        cn_lcp_alloc(&p, n);
        random_psd(&r, &p, n, n);
        for (int i = 0; i < n; i++) {
            p.M[i * n + i] += 0.1;
            for (int j = 0; j < i; j++) {
                double s = cn_rng_range(&r, -1, 1);
                p.M[i * n + j] += s;
                p.M[j * n + i] -= s;
            }
            p.q[i] = cn_rng_range(&r, -1, 1);
        }
        double z[16], w[16], zb[16];
        CHECK(brute_force(&p, zb, 1e-9));
        cnLcpInfo info;
        CHECK(cn_lcp_lemke(&p, NULL, z, w, &info) == CN_LCP_SOLVED);
        for (int i = 0; i < n; i++) CHECK_NEAR(z[i], zb[i], 1e-7 * (1 + fabs(zb[i])));
        cn_lcp_free(&p);
    }
}

/* General random matrices: when Lemke says solved, the solution verifies; when brute force
 * finds nothing, Lemke must not claim a solution; Lemke on copositive-plus M (here: M with
 * nonnegative entries plus identity) must solve. */
static void test_random_general(void) {
    cnRng r = {0x1234ULL};
    int agree = 0;
    for (int t = 0; t < 300; t++) {
        int n = 1 + (int)(cn_rng_uniform(&r) * 6);
        cnLcp p;
        cn_lcp_alloc(&p, n);
        int copos = t % 2;
        for (int i = 0; i < n * n; i++)
            p.M[i] = copos ? cn_rng_range(&r, 0, 1) : cn_rng_range(&r, -1, 1);
        for (int i = 0; i < n; i++) p.q[i] = cn_rng_range(&r, -1, 1);
        double z[8], w[8], zb[8];
        int exists = brute_force(&p, zb, 1e-9);
        cnLcpInfo info;
        cnLcpStatus s = cn_lcp_lemke(&p, NULL, z, w, &info);
        if (s == CN_LCP_SOLVED) {
            CHECK(cn_lcp_verify(&p, z, 1e-9, NULL));
            CHECK_MSG(exists, "trial %d: lemke solved what brute force could not", t);
        }
        if (copos) CHECK_MSG(s == CN_LCP_SOLVED, "trial %d: copositive-plus not solved", t);
        agree += (s == CN_LCP_SOLVED) == exists;
        cn_lcp_free(&p);
    }
    printf("random general: lemke and brute force agree on existence in %d of 300\n", agree);
}

/* Redundant contacts: J has duplicated and dependent rows, q = J a with zeros (resting). */
static void test_redundant(void) {
    cnRng r = {0x77ULL};
    for (int t = 0; t < 200; t++) {
        int dofs = 3, n = 4 + (int)(cn_rng_uniform(&r) * 8);
        double J[16][3];
        for (int i = 0; i < n; i++) {
            if (i >= 3 && cn_rng_uniform(&r) < 0.5) { /* copy or combine earlier rows */
                int a = (int)(cn_rng_uniform(&r) * i), b = (int)(cn_rng_uniform(&r) * i);
                double s = cn_rng_uniform(&r);
                for (int k = 0; k < dofs; k++) J[i][k] = s * J[a][k] + (1 - s) * J[b][k];
            } else {
                for (int k = 0; k < dofs; k++) J[i][k] = cn_rng_range(&r, -1, 1);
            }
        }
        double g[3] = {0, -1, cn_rng_range(&r, -0.3, 0.3)};
        cnLcp p;
        cn_lcp_alloc(&p, n);
        for (int i = 0; i < n; i++) {
            for (int j = 0; j < n; j++) {
                double s = 0;
                for (int k = 0; k < dofs; k++) s += J[i][k] * J[j][k];
                p.M[i * n + j] = s;
            }
            double s = 0;
            for (int k = 0; k < dofs; k++) s += J[i][k] * g[k];
            p.q[i] = s;
        }
        double z[16], w[16], zb[16], wb[16];
        CHECK(brute_force(&p, zb, 1e-9));
        cn_lcp_residual(&p, zb, wb);
        cnLcpInfo info;
        CHECK(cn_lcp_lemke(&p, NULL, z, w, &info) == CN_LCP_SOLVED);
        for (int i = 0; i < n; i++) CHECK_NEAR(w[i], wb[i], 1e-7);
        cnLcpStatus sp = cn_lcp_pivot(&p, NULL, z, w, &info);
        CHECK_MSG(sp == CN_LCP_SOLVED || sp == CN_LCP_NUMERIC, "trial %d n=%d: pivot %s", t, n, cn_lcp_status_name(sp));
        if (sp == CN_LCP_SOLVED)
            for (int i = 0; i < n; i++) CHECK_NEAR(w[i], wb[i], 1e-7);
        cn_lcp_free(&p);
    }
}

/* The residual of hand-made LCPs: w = M z + q filled in; a NaN or an infinity in M, q or z, in
 * any row (not only the last), fails verification, even where the rest of the row is met. */
static void test_residual_nonfinite(void) {
    double M[4] = {2, 1, 1, 3}, q[2] = {-2, -1}, z[2] = {1, 0}, w[2];
    cnLcp p = {2, M, q};
    CHECK(cn_lcp_residual(&p, z, w) == 0 && w[0] == 0 && w[1] == 0); /* z = (1, 0) solves it */
    CHECK(cn_lcp_verify(&p, z, 1e-12, NULL));
    double Mi[4] = {INFINITY, 0, 0, 1}, qi[2] = {-1, -1}, zi[2] = {1, 1};
    cnLcp pi = {2, Mi, qi};
    CHECK(isnan(cn_lcp_residual(&pi, zi, NULL)) && !cn_lcp_verify(&pi, zi, 1, NULL));
    double Mj[4] = {1, INFINITY, 0, 1}, qj[2] = {-5, 0}, zj[2] = {1, 0};
    cnLcp pj = {2, Mj, qj};
    CHECK(!cn_lcp_verify(&pj, zj, 1, NULL)); /* row 0 is 4 short, whatever the scale */
    double Mn[4] = {1, 0, 0, 1}, qn[2] = {NAN, 0}, zn[2] = {0, 0};
    cnLcp pn = {2, Mn, qn};
    CHECK(!cn_lcp_verify(&pn, zn, 1, NULL));
    double zz[2] = {1, NAN};
    CHECK(!cn_lcp_verify(&p, zz, 1, NULL));
}

static void test_read(void) {
    cnLcp p;
    cnDiag d;
    CHECK(cn_lcp_read_string("2\n1 0\n0 1\n-1 -1\n", &p, &d) == CN_OK);
    CHECK(p.n == 2 && p.M[3] == 1 && p.q[1] == -1);
    cn_lcp_free(&p);
    CHECK(cn_lcp_read_string("2\n1 0\n0 1\n-1\n", &p, &d) == CN_ERR_INPUT);
    CHECK(strstr(d.message, "ends after 5 numbers") != NULL);
    CHECK(cn_lcp_read_string("2\n1 x\n", &p, &d) == CN_ERR_INPUT);
    CHECK(!strcmp(d.where, "2:3"));
    CHECK(cn_lcp_read_string("0\n", &p, &d) == CN_ERR_INPUT);
    CHECK(cn_lcp_read_string("1 1 1 5\n", &p, &d) == CN_ERR_INPUT);
    CHECK(strstr(d.message, "unexpected text") != NULL);
}

/* Warm starts: the basis of a solution, given back to cn_lcp_solve_basis, reproduces it
 * without pivoting (w unique for PSD M: compared with brute force); on the same problem with q
 * moved a little (the next sample of a path) it usually still solves it; a wrong basis is
 * refused, never returned unverified; and redundant (singular) bases are handled by keeping an
 * independent principal block. */
static void test_solve_basis(void) {
    cnRng r = {0x3141ULL};
    int reused = 0, moved = 0, wrong_refused = 0, trials = 200;
    for (int t = 0; t < trials; t++) {
        int n = 2 + (int)(cn_rng_uniform(&r) * 9), rank = t % 2 ? n : 1 + (int)(cn_rng_uniform(&r) * n);
        cnLcp p;
        cn_lcp_alloc(&p, n);
        random_psd(&r, &p, n, rank);
        double z[16], w[16], zb[16], wb[16], zw[16], ww[16];
        unsigned char basic[16];
        cnLcpInfo info;
        CHECK(cn_lcp_lemke(&p, NULL, z, w, &info) == CN_LCP_SOLVED);
        CHECK(brute_force(&p, zb, 1e-9));
        cn_lcp_residual(&p, zb, wb);
        cn_lcp_basis_of(n, z, w, basic);
        cnLcpStatus s = cn_lcp_solve_basis(&p, basic, NULL, zw, ww, &info);
        CHECK_MSG(s == CN_LCP_SOLVED, "trial %d n=%d rank=%d: %s", t, n, rank, cn_lcp_status_name(s));
        if (s == CN_LCP_SOLVED) {
            reused++;
            CHECK(info.warm && info.pivots == 0);
            CHECK(cn_lcp_verify(&p, zw, 1e-9, NULL));
            for (int i = 0; i < n; i++) CHECK_NEAR(ww[i], wb[i], 1e-7);
        }
        /* the next sample: q moved by 1e-4 of its size */
        double qmax = 0;
        for (int i = 0; i < n; i++) qmax = fmax(qmax, fabs(p.q[i]));
        for (int i = 0; i < n; i++) p.q[i] += 1e-4 * qmax * cn_rng_range(&r, -1, 1);
        s = cn_lcp_solve_basis(&p, basic, NULL, zw, ww, &info);
        if (s == CN_LCP_SOLVED) {
            moved++;
            CHECK(cn_lcp_verify(&p, zw, 1e-9, NULL));
        }
        /* a basis with every flag flipped: whatever it returns must verify */
        for (int i = 0; i < n; i++) basic[i] = !basic[i];
        s = cn_lcp_solve_basis(&p, basic, NULL, zw, ww, &info);
        if (s == CN_LCP_SOLVED) CHECK(cn_lcp_verify(&p, zw, 1e-9, NULL));
        else wrong_refused++;
        cn_lcp_free(&p);
    }
    printf("solve_basis: own basis reused in %d of %d, after q moved %d, flipped basis refused %d\n",
           reused, trials, moved, wrong_refused);
    CHECK(moved > trials / 2);
    CHECK(wrong_refused > trials / 2);
}

/* Lemke stores the columns of B^-1 of the k equations whose w is nonbasic and grows that
 * block past 16, 32, 64 (k is the number of basic z): problems of n = 20 to 150 whose solution
 * is built first. M is positive definite (a P-matrix: the solution is unique) or symmetric
 * positive semidefinite of low rank (w is unique); z*, w* >= 0 are complementary with a random
 * support, a quarter of the indices degenerate (z*_i = w*_i = 0, as resting contacts are), and
 * q = w* - M z*. */
static void test_lemke_constructed(void) {
    cnRng r = {0xC0FFEEULL};
    int kinds[2] = {0, 0};
    for (int t = 0; t < 24; t++) {
        int n = 20 + (int)(cn_rng_uniform(&r) * 131);
        bool pd = t % 2 == 0;
        int rank = pd ? n : n / 3 + 1;
        cnLcp p;
        cn_lcp_alloc(&p, n);
        double *B = malloc(sizeof(double) * (size_t)rank * n);
        double *zs = malloc(sizeof(double) * (size_t)n), *ws = malloc(sizeof(double) * (size_t)n);
        double *z = malloc(sizeof(double) * (size_t)n), *w = malloc(sizeof(double) * (size_t)n);
        for (int i = 0; i < rank * n; i++) B[i] = cn_rng_range(&r, -1, 1);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double v = 0;
                for (int k = 0; k < rank; k++) v += B[k * n + i] * B[k * n + j];
                p.M[i * n + j] = v / rank;
            }
        if (pd)
            for (int i = 0; i < n; i++) {
                p.M[i * n + i] += 0.05;
                for (int j = 0; j < i; j++) { /* a skew part: not symmetric, still a P-matrix */
                    double v = cn_rng_range(&r, -0.5, 0.5);
                    p.M[i * n + j] += v;
                    p.M[j * n + i] -= v;
                }
            }
        for (int i = 0; i < n; i++) {
            double u = cn_rng_uniform(&r);
            zs[i] = u < 0.45 ? cn_rng_range(&r, 0.1, 2) : 0;
            ws[i] = u >= 0.45 && u < 0.75 ? cn_rng_range(&r, 0.1, 2) : 0;
        }
        for (int i = 0; i < n; i++) {
            double v = ws[i];
            for (int j = 0; j < n; j++) v -= p.M[i * n + j] * zs[j];
            p.q[i] = v;
        }
        cnLcpInfo info;
        cnLcpStatus st = cn_lcp_lemke(&p, NULL, z, w, &info);
        CHECK_MSG(st == CN_LCP_SOLVED, "trial %d (n=%d, %s): %s", t, n, pd ? "P" : "PSD",
                  cn_lcp_status_name(st));
        if (st == CN_LCP_SOLVED) {
            CHECK(cn_lcp_verify(&p, z, 1e-9, NULL));
            for (int i = 0; i < n; i++) {
                if (pd) CHECK_NEAR(z[i], zs[i], 1e-7 * (1 + fabs(zs[i])));
                CHECK_NEAR(w[i], ws[i], 1e-7 * (1 + fabs(ws[i])));
            }
            kinds[pd]++;
        }
        free(B), free(zs), free(ws), free(z), free(w);
        cn_lcp_free(&p);
    }
    printf("lemke on built solutions: %d P-matrix and %d PSD problems of n = 20 to 150 solved\n",
           kinds[1], kinds[0]);
}

/* x = B^-1 y for a small dense n x n matrix B (row-major, copied), by Gaussian elimination with
 * partial pivoting. */
static void dense_solve(const double *B, int n, const double *y, double *x) {
    double a[6][7];
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) a[i][j] = B[i * n + j];
        a[i][n] = y[i];
    }
    for (int c = 0; c < n; c++) {
        int piv = c;
        for (int r = c + 1; r < n; r++)
            if (fabs(a[r][c]) > fabs(a[piv][c])) piv = r;
        for (int j = 0; j <= n; j++) {
            double t = a[c][j];
            a[c][j] = a[piv][j], a[piv][j] = t;
        }
        for (int r = c + 1; r < n; r++) {
            double f = a[r][c] / a[c][c];
            for (int j = c; j <= n; j++) a[r][j] -= f * a[c][j];
        }
    }
    for (int i = n - 1; i >= 0; i--) {
        double v = a[i][n];
        for (int j = i + 1; j < n; j++) v -= a[i][j] * x[j];
        x[i] = v / a[i][i];
    }
}

/* The sparse interior-point QP of the frictionless contact problem (cn_contact_qp_ipm) against
 * Lemke on its dual LCP, on random problems: min 1/2 a^T M a - b^T a subject to J a >= 0 with M
 * block diagonal and positive definite; a = M^-1 (b + J^T f) with f solving the LCP
 * (J M^-1 J^T, J M^-1 b). The accelerations are unique (strictly convex), so they must agree. */
static void test_contact_qp(void) {
    cnRng r = {0x9b1dULL};
    int agree = 0, total = 0, active = 0;
    for (int t = 0; t < 200; t++) {
        int nb = 1 + (int)(cn_rng_uniform(&r) * 3), nd = 3, nv = nb * nd;
        int K = 1 + (int)(cn_rng_uniform(&r) * 8);
        double mblk[3 * 9], b[9], Minv[9][9] = {{0}};
        for (int k = 0; k < nb; k++) { /* L L^T + I/2 */
            double L[9];
            for (int i = 0; i < 9; i++) L[i] = cn_rng_range(&r, -1, 1);
            for (int i = 0; i < 3; i++)
                for (int j = 0; j < 3; j++) {
                    double v = i == j ? 0.5 : 0;
                    for (int q = 0; q < 3; q++) v += L[i * 3 + q] * L[j * 3 + q];
                    mblk[k * 9 + i * 3 + j] = v;
                }
            for (int j = 0; j < 3; j++) { /* the block's inverse, column by column */
                double e[3] = {0, 0, 0}, x[3];
                e[j] = 1;
                dense_solve(mblk + k * 9, 3, e, x);
                for (int i = 0; i < 3; i++) Minv[k * 3 + i][k * 3 + j] = x[i];
            }
        }
        for (int i = 0; i < nv; i++) b[i] = cn_rng_range(&r, -1, 1);
        /* each row touches one or two blocks, two or three entries each */
        int rowptr[9], col[8 * 6];
        double val[8 * 6], J[8][9] = {{0}};
        int nz = 0;
        for (int c = 0; c < K; c++) {
            rowptr[c] = nz;
            int b0 = (int)(cn_rng_uniform(&r) * nb), b1 = (int)(cn_rng_uniform(&r) * nb);
            for (int j = 0; j < nv; j++) {
                int blk = j / 3;
                if ((blk == b0 || blk == b1) && cn_rng_uniform(&r) < 0.8) {
                    col[nz] = j, val[nz] = J[c][j] = cn_rng_range(&r, -1, 1);
                    nz++;
                }
            }
        }
        rowptr[K] = nz;
        cnContactQp qp = {nb, nd, K, mblk, b, rowptr, col, val};
        double a[9], f[8];
        cnQpIpmInfo info;
        cnDiag d;
        if (cn_contact_qp_ipm(&qp, a, f, &info, &d) != CN_OK) {
            CHECK_MSG(0, "trial %d: %s", t, d.message);
            continue;
        }
        /* the reference: Lemke on the dual LCP */
        double mb[9];
        for (int i = 0; i < nv; i++) {
            mb[i] = 0;
            for (int j = 0; j < nv; j++) mb[i] += Minv[i][j] * b[j];
        }
        cnLcp p;
        cn_lcp_alloc(&p, K);
        for (int c = 0; c < K; c++) {
            p.q[c] = 0;
            for (int j = 0; j < nv; j++) p.q[c] += J[c][j] * mb[j];
            for (int e = 0; e < K; e++) {
                double v = 0;
                for (int i = 0; i < nv; i++)
                    for (int j = 0; j < nv; j++) v += J[c][i] * Minv[i][j] * J[e][j];
                p.M[c * K + e] = v;
            }
        }
        double z[8], w[8];
        cnLcpInfo li;
        cnLcpStatus ls = cn_lcp_lemke(&p, NULL, z, w, &li);
        cn_lcp_free(&p);
        total++;
        if (ls != CN_LCP_SOLVED) {
            CHECK_MSG(0, "trial %d: Lemke %s on a feasible PSD LCP", t, cn_lcp_status_name(ls));
            continue;
        }
        double aref[9], scale = 1;
        for (int i = 0; i < nv; i++) {
            double v = b[i];
            for (int c = 0; c < K; c++) v += J[c][i] * z[c];
            aref[i] = v;
        }
        for (int i = 0; i < nv; i++) {
            double v = 0;
            for (int j = 0; j < nv; j++) v += Minv[i][j] * aref[j];
            mb[i] = v, scale = fmax(scale, fabs(v));
        }
        double err = 0;
        for (int i = 0; i < nv; i++) err = fmax(err, fabs(a[i] - mb[i]));
        for (int c = 0; c < K; c++) active += z[c] > 1e-9;
        CHECK_MSG(info.converged || info.polished, "trial %d: the QP neither converged nor polished", t);
        CHECK_MSG(err <= 1e-6 * scale, "trial %d (%d bodies, %d contacts): QP and Lemke differ by %g",
                  t, nb, K, err);
        agree += err <= 1e-6 * scale;
    }
    printf("lcp: the contact QP and Lemke's dual agree on %d of %d random problems (%d contacts "
           "pressed)\n", agree, total, active);
    CHECK(total == 200 && active > 100);
}

void test_lcp(void) {
    test_contact_qp();
    test_residual_nonfinite();
    test_read();
    test_small_known();
    test_murty();
    test_random_psd();
    test_random_pmatrix();
    test_lemke_constructed();
    test_random_general();
    test_redundant();
    test_solve_basis();
}
