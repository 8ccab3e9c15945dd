/* Warm starts: solving an LCP on a guessed complementary basis.
 *
 * Along a motion path consecutive samples differ by a small displacement, so the contacts that
 * push (z > 0) and those that open (w > 0) are usually the same as at the previous sample. The
 * solution on that basis is one linear solve, M_BB z_B = -q_B with z_N = 0; it is a solution of
 * the LCP exactly when z_B >= 0 and w_N = M_NB z_B + q_N >= 0, which the verification checks.
 * A wrong guess is detected there and the caller pivots from scratch. */
#include <math.h>
#include <string.h>

#include "solve.h"

/* M_BB counts as singular when an LU pivot falls below this fraction of its largest entry (a
 * redundant contact in the guess: the cold solve then decides). */
#define WARM_SINGULAR_TOL 1e-13
/* A z_B below -WARM_REJECT max(|q|, |z|) rejects the guess before the O(n^2) verification: a
 * wrong guess shows such a negative entry, a right one only rounding. Rejecting costs a cold
 * solve, never a wrong answer. */
#define WARM_REJECT 1e-6

/* A = M_BB for the b indices idx (row-major b x b). */
static void gather(const cnLcp *p, const int *idx, int b, double *A) {
    int n = p->n;
    for (int r = 0; r < b; r++) {
        const double *Mi = p->M + (size_t)idx[r] * n;
        for (int c = 0; c < b; c++) A[(size_t)r * b + c] = Mi[idx[c]];
    }
}

void cn_lcp_basis_of(int n, const double *z, const double *w, unsigned char *basic) {
    for (int i = 0; i < n; i++) basic[i] = z[i] > fmax(w[i], 0.0);
}

cnLcpStatus cn_lcp_solve_basis(const cnLcp *p, const unsigned char *basic,
                               const cnLcpOptions *opt, double *z, double *w, cnLcpInfo *info) {
    int n = p->n;
    cnLcpInfo scratch;
    cnLcpOptions o = cn_lcp_begin(opt, 1, &info, &scratch);
    int b = 0;
    for (int i = 0; i < n; i++) b += basic[i] != 0;
    /* one block: A (b x b), x (b), then idx and piv (b ints each) */
    size_t nd = (size_t)b * (size_t)b + (size_t)b + 1;
    double *A = cn_malloc(sizeof(double) * nd + sizeof(int) * 2 * ((size_t)b + 1));
    if (!A) return CN_LCP_NUMERIC;
    double *x = A + (size_t)b * (size_t)b;
    int *idx = (int *)(A + nd), *piv = idx + b + 1;
    cnLcpStatus status = CN_LCP_NUMERIC;
    b = 0;
    for (int i = 0; i < n; i++)
        if (basic[i]) idx[b++] = i;
    gather(p, idx, b, A);
    for (int r = 0; r < b; r++) x[r] = -p->q[idx[r]];
    memset(z, 0, sizeof(double) * (size_t)n);
    if (b > 0 && cn_lu_factor(A, b, piv, WARM_SINGULAR_TOL) == 0) {
        cn_lu_solve(A, b, piv, x);
        for (int r = 0; r < b; r++) z[idx[r]] = x[r];
    } else if (b > 0) {
        /* Redundant contacts make M_BB singular (positive semidefinite M): keep a maximal
         * independent principal block and leave the dependent variables at zero (the LU
         * above overwrote A). */
        gather(p, idx, b, A);
        int rank = cn_lu_principal(A, b, piv, WARM_SINGULAR_TOL);
        for (int r = 0; r < rank; r++) x[r] = -p->q[idx[piv[r]]];
        cn_lu_principal_solve(A, b, rank, x);
        for (int r = 0; r < rank; r++) z[idx[piv[r]]] = x[r];
    }
    /* a clearly negative z_B: the guess is wrong (the residual would say so, at O(n^2)) */
    double big = 0, zmin = 0;
    for (int i = 0; i < n; i++) big = fmax(big, fmax(fabs(p->q[i]), fabs(z[i]))), zmin = fmin(zmin, z[i]);
    if (zmin < -WARM_REJECT * big) goto done;
    if (cn_lcp_finish(p, z, w, o.tol, &info->residual)) {
        status = CN_LCP_SOLVED;
        info->warm = true;
    }
done:
    cn_free(A);
    return status;
}
