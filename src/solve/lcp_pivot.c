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

cnLcpStatus cn_lcp_pivot(const cnLcp *p, const cnLcpOptions *opt, double *z, double *w,
                         cnLcpInfo *info) {
    int n = p->n;
    cnLcpInfo scratch;
    cnLcpOptions o = cn_lcp_begin(opt, 20 * n + 100, &info, &scratch);
    int max_pivots = o.max_pivots;
    const double *M = p->M;

    double scale = 0, mdiag = 0;
    for (int i = 0; i < n; i++) {
        scale = fmax(scale, fabs(p->q[i]));
        mdiag = fmax(mdiag, fabs(M[(size_t)i * n + i]));
    }
    if (!isfinite(scale) || !isfinite(mdiag)) return CN_LCP_NUMERIC;
    double wtol = PIVOT_ZERO_TOL * fmax(scale, 1e-300);

    int *set = cn_calloc((size_t)n + 1, sizeof(int));
    int *cidx = cn_malloc(sizeof(int) * (size_t)(n + 1));
    double *dz = cn_calloc((size_t)n + 1, sizeof(double));
    double *dw = cn_malloc(sizeof(double) * (size_t)(n + 1));
    double *K = cn_malloc(sizeof(double) * ((size_t)n * n + 1));
    double *rhs = cn_malloc(sizeof(double) * (size_t)(n + 1));
    int *piv = cn_malloc(sizeof(int) * (size_t)(n + 1));
    cnLcpStatus status = CN_LCP_NUMERIC;
    if (!set || !cidx || !dz || !dw || !K || !rhs || !piv) goto done;

    for (int i = 0; i < n; i++) z[i] = 0, w[i] = p->q[i];

    for (int d = 0; d < n; d++) {
        /* w afresh from z: the incremental updates drift */
        for (int i = 0; i < n; i++) {
            double s = p->q[i];
            for (int k = 0; k < n; k++) s += M[(size_t)i * n + k] * z[k];
            w[i] = s;
        }
        if (w[d] >= -wtol) {
            set[d] = SET_NC;
            continue;
        }
        /* drive w_d to zero */
        for (;;) {
            if (info->pivots >= max_pivots) {
                status = CN_LCP_MAX_PIVOTS;
                goto done;
            }
            info->pivots++;
            int nc = 0;
            for (int i = 0; i < n; i++)
                if (set[i] == SET_C) cidx[nc++] = i;
            memset(dz, 0, sizeof(double) * (size_t)n);
            dz[d] = 1.0;
            if (nc > 0) {
                for (int a = 0; a < nc; a++) {
                    for (int b = 0; b < nc; b++)
                        K[(size_t)a * nc + b] = M[(size_t)cidx[a] * n + cidx[b]];
                    rhs[a] = -M[(size_t)cidx[a] * n + d];
                }
                if (cn_lu_factor(K, nc, piv, PIVOT_SINGULAR_TOL) != 0) goto done;
                cn_lu_solve(K, nc, piv, rhs);
                for (int a = 0; a < nc; a++) dz[cidx[a]] = rhs[a];
            }
            double dmax = 0;
            for (int i = 0; i < n; i++) {
                double s = M[(size_t)i * n + d];
                for (int a = 0; a < nc; a++) s += M[(size_t)i * n + cidx[a]] * dz[cidx[a]];
                dw[i] = s;
                dmax = fmax(dmax, fabs(s));
            }
            double dtol = PIVOT_DIR_TOL * fmax(dmax, mdiag);
            double step = INFINITY;
            int j = -1;
            if (dw[d] > dtol) step = -w[d] / dw[d], j = d;
            for (int a = 0; a < nc; a++) {
                int i = cidx[a];
                if (dz[i] < -PIVOT_DIR_TOL) {
                    double s = -z[i] / dz[i];
                    if (s < step) step = s, j = i;
                }
            }
            for (int i = 0; i < n; i++) {
                if (set[i] == SET_NC && dw[i] < -dtol) {
                    double s = fmax(w[i], 0.0) / -dw[i];
                    if (s < step) step = s, j = i;
                }
            }
            if (j < 0) {
                if (fabs(dw[d]) <= dtol) {
                    /* Row d depends on the clamped rows, so for PSD M its w is a combination of
                     * their zeros: the negative w_d is rounding. Leave z_d = 0; the final
                     * verification judges the result. */
                    set[d] = SET_NC;
                    break;
                }
                /* unbounded direction: M is not PSD */
                info->ray_variable = d;
                status = CN_LCP_RAY;
                goto done;
            }
            step = fmax(step, 0.0);
            for (int i = 0; i < n; i++) {
                z[i] += step * dz[i];
                w[i] += step * dw[i];
            }
            if (j == d) {
                w[d] = 0;
                set[d] = SET_C;
                break;
            }
            if (set[j] == SET_C) {
                z[j] = 0;
                set[j] = SET_NC;
            } else {
                w[j] = 0;
                set[j] = SET_C;
            }
        }
    }
    {
        /* Polish: solve M_CC z_C = -q_C afresh; keep it only if it verifies better. */
        int nc = 0;
        for (int i = 0; i < n; i++)
            if (set[i] == SET_C) cidx[nc++] = i;
        double before = cn_lcp_residual(p, z, NULL);
        if (nc > 0) {
            for (int a = 0; a < nc; a++) {
                for (int b = 0; b < nc; b++) K[(size_t)a * nc + b] = M[(size_t)cidx[a] * n + cidx[b]];
                rhs[a] = -p->q[cidx[a]];
            }
            if (cn_lu_factor(K, nc, piv, PIVOT_SINGULAR_TOL) == 0) {
                cn_lu_solve(K, nc, piv, rhs);
                memcpy(dz, z, sizeof(double) * (size_t)n);
                for (int a = 0; a < nc; a++) z[cidx[a]] = rhs[a];
                if (!(cn_lcp_residual(p, z, NULL) < before)) memcpy(z, dz, sizeof(double) * (size_t)n);
            }
        }
    }
    status = cn_lcp_finish(p, z, w, o.tol, &info->residual) ? CN_LCP_SOLVED : CN_LCP_NUMERIC;

done:
    cn_free(set);
    cn_free(cidx);
    cn_free(dz);
    cn_free(dw);
    cn_free(K);
    cn_free(rhs);
    cn_free(piv);
    return status;
}
