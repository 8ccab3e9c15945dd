/* Dense linear algebra for small systems: LU with partial pivoting, Cholesky. Row-major. */
#include <math.h>

#include "core.h"

/* The pivot threshold: rel_tol of A's largest entry (of 1 for a zero matrix). */
static double lu_tiny(const double *A, int n, double rel_tol) {
    double amax = 0;
    for (int i = 0; i < n * n; i++) amax = fmax(amax, fabs(A[i]));
    return rel_tol * (amax > 0 ? amax : 1.0);
}

static void swap_rows(double *A, int n, int k, int p) {
    for (int j = 0; j < n; j++) {
        double t = A[k * n + j];
        A[k * n + j] = A[p * n + j];
        A[p * n + j] = t;
    }
}

/* Eliminate below pivot k: the multipliers go in column k (unit lower factor). */
static void lu_eliminate(double *A, int n, int k) {
    double inv = 1.0 / A[k * n + k];
    for (int i = k + 1; i < n; i++) {
        double f = A[i * n + k] * inv;
        A[i * n + k] = f;
        if (f == 0) continue;
        for (int j = k + 1; j < n; j++) A[i * n + j] -= f * A[k * n + j];
    }
}

int cn_lu_factor(double *A, int n, int *piv, double rel_tol) {
    double tiny = lu_tiny(A, n, rel_tol);
    for (int k = 0; k < n; k++) {
        int p = k;
        double best = fabs(A[k * n + k]);
        for (int i = k + 1; i < n; i++) {
            double v = fabs(A[i * n + k]);
            if (v > best) best = v, p = i;
        }
        piv[k] = p;
        if (best <= tiny) return -1;
        if (p != k) swap_rows(A, n, k, p);
        lu_eliminate(A, n, k);
    }
    return 0;
}

void cn_lu_solve(const double *LU, int n, const int *piv, double *b) {
    for (int k = 0; k < n; k++) {
        if (piv[k] != k) {
            double t = b[k];
            b[k] = b[piv[k]];
            b[piv[k]] = t;
        }
    }
    cn_lu_principal_solve(LU, n, n, b);
}

int cn_chol_factor(double *A, int n, double rel_tol) {
    double dmax = 0;
    for (int i = 0; i < n; i++) dmax = fmax(dmax, fabs(A[i * n + i]));
    double tiny = rel_tol * (dmax > 0 ? dmax : 1.0);
    for (int j = 0; j < n; j++) {
        double s = A[j * n + j];
        for (int k = 0; k < j; k++) s -= A[j * n + k] * A[j * n + k];
        if (!(s > tiny)) return -1;
        double d = sqrt(s);
        A[j * n + j] = d;
        for (int i = j + 1; i < n; i++) {
            double t = A[i * n + j];
            for (int k = 0; k < j; k++) t -= A[i * n + k] * A[j * n + k];
            A[i * n + j] = t / d;
        }
    }
    return 0;
}

void cn_chol_solve(const double *L, int n, double *b) {
    for (int i = 0; i < n; i++) {
        double s = b[i];
        for (int k = 0; k < i; k++) s -= L[i * n + k] * b[k];
        b[i] = s / L[i * n + i];
    }
    for (int i = n - 1; i >= 0; i--) {
        double s = b[i];
        for (int k = i + 1; k < n; k++) s -= L[k * n + i] * b[k];
        b[i] = s / L[i * n + i];
    }
}

void cn_tangent_basis(const double n[3], double t1[3], double t2[3]) {
    /* Pick the axis least aligned with n, project it out. */
    double ax[3] = {0, 0, 0};
    int k = 0;
    if (fabs(n[1]) < fabs(n[k])) k = 1;
    if (fabs(n[2]) < fabs(n[k])) k = 2;
    ax[k] = 1;
    double d = cn_dot3(ax, n);
    for (int i = 0; i < 3; i++) t1[i] = ax[i] - d * n[i];
    cn_normalize3(t1);
    cn_cross3(n, t1, t2);
}

int cn_lu_principal(double *A, int n, int *perm, double rel_tol) {
    double tiny = lu_tiny(A, n, rel_tol);
    for (int i = 0; i < n; i++) perm[i] = i;
    for (int k = 0; k < n; k++) {
        int p = k;
        double best = fabs(A[k * n + k]);
        for (int i = k + 1; i < n; i++) {
            double v = fabs(A[i * n + i]);
            if (v > best) best = v, p = i;
        }
        if (best <= tiny) return k;
        if (p != k) { /* swap rows and columns k and p */
            swap_rows(A, n, k, p);
            for (int i = 0; i < n; i++) {
                double t = A[i * n + k];
                A[i * n + k] = A[i * n + p];
                A[i * n + p] = t;
            }
            int t = perm[k];
            perm[k] = perm[p];
            perm[p] = t;
        }
        lu_eliminate(A, n, k);
    }
    return n;
}

void cn_lu_principal_solve(const double *LU, int n, int r, double *b) {
    for (int i = 0; i < r; i++) {
        double s = b[i];
        for (int j = 0; j < i; j++) s -= LU[i * n + j] * b[j];
        b[i] = s;
    }
    for (int i = r - 1; i >= 0; i--) {
        double s = b[i];
        for (int j = i + 1; j < r; j++) s -= LU[i * n + j] * b[j];
        b[i] = s / LU[i * n + i];
    }
}
