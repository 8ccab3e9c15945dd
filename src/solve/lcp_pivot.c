/* Principal pivoting for symmetric positive semidefinite LCPs (frictionless contact).
 *
 * Reference: D. Baraff, "Fast contact force computation for nonpenetrating rigid bodies",
 * SIGGRAPH 1994, sec. 4-6 (the incremental "drive to zero" algorithm, a variant of Dantzig's
 * principal pivoting method, Cottle-Pang-Stone sec. 4.2).
 *
 * Indices are processed one at a time. For an index d with w_d < 0, z_d is increased while the
 * clamped set C (z > 0, w = 0) keeps w_C = 0 and the free set NC (z = 0, w > 0) keeps z = 0;
 * the step stops at the first index that changes set (ratio test). Every solve factorises M_CC
 * (LU: real contact data are symmetric only to rounding), which stays nonsingular for PSD M in
 * exact arithmetic; near-redundant contacts can make it numerically singular, which is reported
 * as a numerical failure (callers then fall back to Lemke). The final z_C is re-solved from the
 * clamped set to remove the drift of the incremental updates. */
#include <math.h>
#include <string.h>

#include "solve.h"

/* |w_d| below this fraction of the problem's scale counts as zero (d needs no driving). */
#define PIVOT_ZERO_TOL 1e-13
/* Step direction entries below this (relative) are treated as zero in the ratio test. */
#define PIVOT_DIR_TOL 1e-12
/* M_CC counts as singular when an LU pivot falls below this fraction of its largest entry. */
#define PIVOT_SINGULAR_TOL 1e-15

enum { SET_NONE = 0, SET_C = 1, SET_NC = 2 };

/* The solver's state: the clamped set (SET_C: w_i = 0, z_i free; SET_NC: z_i = 0), the step
 * direction and the dense factor of M_CC. */
typedef struct {
    const cnLcp *p;
    int n, nc;
    int *set, *cidx, *piv;
    double *dz, *dw, *K, *rhs;
    double *z, *w;
    double mdiag;
} Pv;

/* The clamped indices, and the LU factor of M_CC with rhs the given column (col >= 0: -M_{C,col})
 * or -q_C (col < 0), solved in place. Returns -1 when M_CC is singular. */
static int pivot_solve_clamped(Pv *P, int col) {
    const double *M = P->p->M;
    int n = P->n;
    P->nc = 0;
    for (int i = 0; i < n; i++)
        if (P->set[i] == SET_C) P->cidx[P->nc++] = i;
    int nc = P->nc;
    if (nc == 0) return 0;
    for (int a = 0; a < nc; a++) {
        for (int b = 0; b < nc; b++) P->K[(size_t)a * nc + b] = M[(size_t)P->cidx[a] * n + P->cidx[b]];
        P->rhs[a] = col >= 0 ? -M[(size_t)P->cidx[a] * n + col] : -P->p->q[P->cidx[a]];
    }
    if (cn_lu_factor(P->K, nc, P->piv, PIVOT_SINGULAR_TOL) != 0) return -1;
    cn_lu_solve(P->K, nc, P->piv, P->rhs);
    return 0;
}

/* The direction that raises z_d keeping the clamped w at zero: dz, dw = M dz. Returns the
 * tolerance below which a dw entry counts as zero, or -1 when M_CC is singular. */
static double pivot_direction(Pv *P, int d) {
    const double *M = P->p->M;
    int n = P->n;
    if (pivot_solve_clamped(P, d) != 0) return -1;
    memset(P->dz, 0, sizeof(double) * (size_t)n);
    P->dz[d] = 1.0;
    for (int a = 0; a < P->nc; a++) P->dz[P->cidx[a]] = P->rhs[a];
    double dmax = 0;
    for (int i = 0; i < n; i++) {
        double s = M[(size_t)i * n + d];
        for (int a = 0; a < P->nc; a++) s += M[(size_t)i * n + P->cidx[a]] * P->dz[P->cidx[a]];
        P->dw[i] = s;
        dmax = fmax(dmax, fabs(s));
    }
    return PIVOT_DIR_TOL * fmax(dmax, P->mdiag);
}

/* The longest step along the direction before w_d reaches zero, a clamped z hits zero or a free
 * w does; *j: the index that blocks (-1: none). */
static double pivot_step(const Pv *P, int d, double dtol, int *j) {
    double step = INFINITY;
    *j = -1;
    if (P->dw[d] > dtol) step = -P->w[d] / P->dw[d], *j = d;
    for (int a = 0; a < P->nc; a++) {
        int i = P->cidx[a];
        if (P->dz[i] < -PIVOT_DIR_TOL) {
            double s = -P->z[i] / P->dz[i];
            if (s < step) step = s, *j = i;
        }
    }
    for (int i = 0; i < P->n; i++) {
        if (P->set[i] == SET_NC && P->dw[i] < -dtol) {
            double s = fmax(P->w[i], 0.0) / -P->dw[i];
            if (s < step) step = s, *j = i;
        }
    }
    return step;
}

/* Drive w_d to zero (Cottle-Dantzig principal pivoting for one index). */
static cnLcpStatus pivot_index(Pv *P, int d, int max_pivots, cnLcpInfo *info) {
    int n = P->n;
    for (;;) {
        if (info->pivots >= max_pivots) return CN_LCP_MAX_PIVOTS;
        info->pivots++;
        double dtol = pivot_direction(P, d);
        if (dtol < 0) return CN_LCP_NUMERIC;
        int j;
        double step = pivot_step(P, d, dtol, &j);
        if (j < 0) {
            if (fabs(P->dw[d]) <= dtol) {
                /* Row d depends on the clamped rows, so for PSD M its w is a combination of
                 * their zeros: the negative w_d is rounding. Leave z_d = 0; the final
                 * verification judges the result. */
                P->set[d] = SET_NC;
                return CN_LCP_SOLVED;
            }
            /* unbounded direction: M is not PSD */
            info->ray_variable = d;
            return CN_LCP_RAY;
        }
        step = fmax(step, 0.0);
        for (int i = 0; i < n; i++) {
            P->z[i] += step * P->dz[i];
            P->w[i] += step * P->dw[i];
        }
        if (j == d) {
            P->w[d] = 0;
            P->set[d] = SET_C;
            return CN_LCP_SOLVED;
        }
        if (P->set[j] == SET_C) {
            P->z[j] = 0;
            P->set[j] = SET_NC;
        } else {
            P->w[j] = 0;
            P->set[j] = SET_C;
        }
    }
}

/* Polish: solve M_CC z_C = -q_C afresh; keep it only if it verifies better. */
static void pivot_polish(Pv *P, double mnorm) {
    double before = cn_lcp_residual_at(P->p, P->z, NULL, mnorm);
    if (pivot_solve_clamped(P, -1) != 0 || P->nc == 0) return;
    memcpy(P->dz, P->z, sizeof(double) * (size_t)P->n);
    for (int a = 0; a < P->nc; a++) P->z[P->cidx[a]] = P->rhs[a];
    if (!(cn_lcp_residual_at(P->p, P->z, NULL, mnorm) < before))
        memcpy(P->z, P->dz, sizeof(double) * (size_t)P->n);
}

cnLcpStatus cn_lcp_pivot(const cnLcp *p, const cnLcpOptions *opt, double *z, double *w,
                         cnLcpInfo *info) {
    int n = p->n;
    cnLcpInfo scratch;
    cnLcpOptions o = cn_lcp_begin(opt, 20 * n + 100, &info, &scratch);
    const double *M = p->M;
    double scale = 0, mdiag = 0;
    for (int i = 0; i < n; i++) {
        scale = fmax(scale, fabs(p->q[i]));
        mdiag = fmax(mdiag, fabs(M[(size_t)i * n + i]));
    }
    if (!isfinite(scale) || !isfinite(mdiag)) return CN_LCP_NUMERIC;
    double wtol = PIVOT_ZERO_TOL * fmax(scale, 1e-300);
    Pv P = {p, n, 0, NULL, NULL, NULL, NULL, NULL, NULL, NULL, z, w, mdiag};
    P.set = cn_calloc((size_t)n + 1, sizeof(int));
    P.cidx = cn_malloc(sizeof(int) * (size_t)(n + 1));
    P.dz = cn_calloc((size_t)n + 1, sizeof(double));
    P.dw = cn_malloc(sizeof(double) * (size_t)(n + 1));
    P.K = cn_malloc(sizeof(double) * ((size_t)n * n + 1));
    P.rhs = cn_malloc(sizeof(double) * (size_t)(n + 1));
    P.piv = cn_malloc(sizeof(int) * (size_t)(n + 1));
    int *nzi = cn_malloc(sizeof(int) * (size_t)(n + 1));
    cnLcpStatus status = CN_LCP_NUMERIC;
    if (!P.set || !P.cidx || !P.dz || !P.dw || !P.K || !P.rhs || !P.piv || !nzi) goto done;
    for (int i = 0; i < n; i++) z[i] = 0, w[i] = p->q[i];
    for (int d = 0; d < n; d++) {
        /* w afresh from z (the incremental updates drift), over z's nonzero entries (the same
           sums: the others add zeros) */
        int nnz = 0;
        for (int k = 0; k < n; k++)
            if (z[k] != 0) nzi[nnz++] = k;
        for (int i = 0; i < n; i++) {
            double s = p->q[i];
            const double *Mi = M + (size_t)i * n;
            for (int a = 0; a < nnz; a++) s += Mi[nzi[a]] * z[nzi[a]];
            w[i] = s;
        }
        if (w[d] >= -wtol) {
            P.set[d] = SET_NC;
            continue;
        }
        if ((status = pivot_index(&P, d, o.max_pivots, info)) != CN_LCP_SOLVED) goto done;
    }
    double mnorm = cn_lcp_row_norm(p);
    pivot_polish(&P, mnorm);
    status = cn_lcp_finish_at(p, z, w, o.tol, &info->residual, mnorm) ? CN_LCP_SOLVED : CN_LCP_NUMERIC;
done:
    cn_free(P.set);
    cn_free(P.cidx);
    cn_free(P.dz);
    cn_free(P.dw);
    cn_free(P.K);
    cn_free(P.rhs);
    cn_free(P.piv);
    cn_free(nzi);
    return status;
}
