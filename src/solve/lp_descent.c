/* A static force field by descent: the equilibrium LP's rows come in blocks (a body's nd rows),
 * and the blocks are met one at a time in the order the caller gives (the bodies from the top of
 * the assembly down). A block's columns that no earlier block has set are its unknowns; the
 * columns set earlier (the loads of the bodies above) are known. Each block is then a small
 * nonnegative least-squares problem (nd rows, a few contact columns), solved exactly by Lawson
 * and Hanson's active-set method. When every block is met, the columns are a solution of the
 * whole LP; when one is not, the descent proves nothing (a load may need to go up or sideways,
 * as in an arch) and the caller solves the LP whole.
 *
 * For an assembly whose parts rest on the parts below, this takes time linear in the contacts
 * where an interior point factorises the contact graph twenty times. */
#include <math.h>
#include <string.h>

#include "solve.h"

/* A block is met when its residual's largest entry is below this, in the LP's scaled units (the
 * caller verifies the whole field against its own tolerance, 1e-7, after). */
#define CN_DESCENT_TOL 1e-10
/* The active-set method adds a column only when its gradient exceeds this (scaled units). */
#define CN_NNLS_GRAD_TOL 1e-14
/* Rows of a block, at most (6: a 3-D body). */
#define CN_DESCENT_MAX_BLOCK 6

/* Least squares on the passive columns (P[j] = 1) of A (m x n, column-major): z. False when
 * their normal matrix is singular (a column dependent on the others). */
static bool passive_ls(const double *A, int m, int n, const double *b, const unsigned char *P, double *z,
                       int *idx, double *G) {
    int p = 0;
    for (int j = 0; j < n; j++)
        if (P[j]) idx[p++] = j;
    double rhs[CN_DESCENT_MAX_BLOCK];
    if (p > m) return false; /* more columns than rows: dependent */
    for (int a = 0; a < p; a++) {
        const double *ca = A + (size_t)idx[a] * m;
        double s = 0;
        for (int i = 0; i < m; i++) s += ca[i] * b[i];
        rhs[a] = s;
        for (int c = 0; c <= a; c++) {
            const double *cc = A + (size_t)idx[c] * m;
            double g = 0;
            for (int i = 0; i < m; i++) g += ca[i] * cc[i];
            G[a * p + c] = G[c * p + a] = g;
        }
    }
    if (cn_chol_factor(G, p, 1e-12)) return false;
    cn_chol_solve(G, p, rhs);
    for (int j = 0; j < n; j++) z[j] = 0;
    for (int a = 0; a < p; a++) z[idx[a]] = rhs[a];
    return true;
}

/* min |A x - b| over x >= 0 (Lawson and Hanson, "Solving Least Squares Problems", ch. 23), for
 * m <= CN_DESCENT_MAX_BLOCK rows. Scratch: P, out (n flags: passive; left out as dependent), z
 * (n), idx (n), G (m * m). Returns the residual's largest entry, infinite when the data hold a NaN or an infinity. */
static double nnls(const double *A, int m, int n, const double *b, double *x, unsigned char *P,
                   unsigned char *out, double *z, int *idx, double *G) {
    double r[CN_DESCENT_MAX_BLOCK];
    memset(P, 0, (size_t)n);
    memset(out, 0, (size_t)n);
    for (int j = 0; j < n; j++) x[j] = 0;
    for (int outer = 0; outer < 3 * n + 10; outer++) {
        for (int i = 0; i < m; i++) r[i] = b[i];
        for (int j = 0; j < n; j++)
            if (P[j])
                for (int i = 0; i < m; i++) r[i] -= A[(size_t)j * m + i] * x[j];
        int t = -1;
        double best = CN_NNLS_GRAD_TOL;
        for (int j = 0; j < n; j++) {
            if (P[j] || out[j]) continue;
            double g = 0;
            for (int i = 0; i < m; i++) g += A[(size_t)j * m + i] * r[i];
            if (g > best) best = g, t = j;
        }
        if (t < 0) break;
        P[t] = 1;
        for (int inner = 0; inner < 3 * n + 10; inner++) {
            if (!passive_ls(A, m, n, b, P, z, idx, G)) {
                P[t] = 0, out[t] = 1; /* dependent on the passive ones: never again */
                break;
            }
            double alpha = 2;
            for (int j = 0; j < n; j++)
                if (P[j] && z[j] <= 0) alpha = fmin(alpha, x[j] / (x[j] - z[j]));
            if (alpha > 1) { /* every passive one positive */
                for (int j = 0; j < n; j++) x[j] = P[j] ? z[j] : 0;
                break;
            }
            for (int j = 0; j < n; j++)
                if (P[j]) {
                    x[j] += alpha * (z[j] - x[j]);
                    if (x[j] <= 0 || (z[j] <= 0 && x[j] <= 1e-15)) P[j] = 0, x[j] = 0;
                }
        }
    }
    for (int i = 0; i < m; i++) r[i] = b[i];
    for (int j = 0; j < n; j++)
        for (int i = 0; i < m; i++) r[i] -= A[(size_t)j * m + i] * x[j];
    double worst = 0;
    for (int i = 0; i < m; i++) {
        double e = fabs(r[i]);
        if (!isfinite(e)) return INFINITY; /* NaN or infinite data: never "met" */
        worst = fmax(worst, e);
    }
    return worst;
}

cnStatus cn_lp_descent(const cnLpProblem *lp, int block, const int *order, double *x, bool *met) {
    *met = false;
    int n = lp->nvars, nblk = block > 0 ? lp->neq / block : 0;
    if (lp->nineq != 0 || block < 1 || block > CN_DESCENT_MAX_BLOCK || nblk * block != lp->neq || n == 0)
        return CN_OK;
    /* the columns of each block (a column touches a block once however many of its rows) */
    int *start = cn_calloc((size_t)nblk + 2, sizeof(int));
    unsigned char *set = cn_calloc((size_t)n + 1, 1);
    int *cols = NULL;
    double *A = NULL, *xs = NULL, *z = NULL, *G = NULL;
    int *idx = NULL, *freej = NULL;
    unsigned char *P = NULL, *out = NULL;
    cnStatus st = CN_OK;
    if (!start || !set) goto oom;
    /* order must be a permutation of the blocks, and a column's rows of one block must come
     * together (as the check's matrix has them): else nothing is claimed */
    int *mark = start; /* start[] is still zero: borrowed as marks (j + 1 = seen by column j) */
    for (int o = 0; o < nblk; o++) {
        if (order[o] < 0 || order[o] >= nblk || mark[order[o]]) goto done;
        mark[order[o]] = 1;
    }
    memset(mark, 0, sizeof(int) * (size_t)nblk);
    for (int j = 0; j < n; j++) {
        int prev = -1;
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) {
            int k = lp->rows[t] / block;
            if (k == prev) continue;
            if (mark[k] == j + 1) goto done; /* this column left block k and came back */
            mark[k] = j + 1, prev = k;
        }
    }
    memset(mark, 0, sizeof(int) * (size_t)nblk);
    for (int pass = 0; pass < 2; pass++) {
        for (int j = 0; j < n; j++)
            for (int t = lp->colptr[j], last = -1; t < lp->colptr[j + 1]; t++) {
                int k = lp->rows[t] / block;
                if (k == last) continue; /* a column's rows of one block come together (checked) */
                last = k;
                if (pass == 0) start[k + 2]++;
                else cols[start[k + 1]++] = j;
            }
        if (pass == 0) {
            for (int k = 0; k < nblk; k++) start[k + 2] += start[k + 1];
            if (!(cols = cn_malloc(sizeof(int) * ((size_t)start[nblk + 1] + 1)))) goto oom;
        }
    }
    /* now start[k] .. start[k + 1] are block k's columns */
    int most = 0;
    for (int k = 0; k < nblk; k++) most = start[k + 1] - start[k] > most ? start[k + 1] - start[k] : most;
    size_t cap = (size_t)most + 1;
    A = cn_malloc(sizeof(double) * cap * (size_t)block);
    xs = cn_malloc(sizeof(double) * cap);
    z = cn_malloc(sizeof(double) * cap);
    idx = cn_malloc(sizeof(int) * cap);
    freej = cn_malloc(sizeof(int) * cap);
    G = cn_malloc(sizeof(double) * (size_t)block * (size_t)block);
    P = cn_malloc(cap);
    out = cn_malloc(cap);
    if (!A || !xs || !z || !idx || !freej || !G || !P || !out) goto oom;
    memset(x, 0, sizeof(double) * (size_t)n);
    bool ok = true;
    for (int o = 0; o < nblk && ok; o++) {
        int k = order[o], r0 = k * block;
        double b[CN_DESCENT_MAX_BLOCK];
        for (int i = 0; i < block; i++) b[i] = lp->rhs[r0 + i];
        int nf = 0; /* free columns packed into A (a set column's slot is reused) */
        for (int q = start[k]; q < start[k + 1]; q++) {
            int j = cols[q];
            double *col = A + (size_t)nf * block;
            for (int i = 0; i < block; i++) col[i] = 0;
            for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
                if (lp->rows[t] / block == k) col[lp->rows[t] - r0] += lp->vals[t];
            if (set[j])
                for (int i = 0; i < block; i++) b[i] -= col[i] * x[j];
            else
                freej[nf++] = j;
        }
        double worst = nnls(A, block, nf, b, xs, P, out, z, idx, G);
        if (!(worst <= CN_DESCENT_TOL)) ok = false;
        for (int a = 0; a < nf; a++) x[freej[a]] = xs[a], set[freej[a]] = 1;
    }
    *met = ok;
    goto done;
oom:
    st = CN_ERR_MEMORY;
done:
    cn_free(start), cn_free(set), cn_free(cols);
    cn_free(A), cn_free(xs), cn_free(z), cn_free(idx), cn_free(freej), cn_free(G), cn_free(P), cn_free(out);
    return st;
}
