/* The frictionless motion of a large assembly without the dense LCP: the contact problem handed
 * to the sparse interior-point QP (cn_contact_qp_ipm, Gauss's principle), in scaled units, and
 * its answer verified as an LCP solution before it is used. */
#include <math.h>
#include <string.h>

#include "solve.h"
#include "strong.h"


bool cn_motion_qp_usable(const cnMech *m) {
    double lo = INFINITY, hi = 0;
    for (int b = 0; b < m->nb; b++) {
        if (m->pushed && m->pushed[b]) return false; /* a singular inverse mass: no mass matrix */
        lo = fmin(lo, m->mass[b]), hi = fmax(hi, m->mass[b]);
    }
    return m->nb > 0 && m->g > 0 && m->wref > 0 && lo > 0 && hi <= CN_MASS_SPAN_RESOLVED * lo;
}

/* M's block of body b, from its inverse: false when that is not positive definite. */
static bool mass_block(const cnMech *m, int b, double *Mb) {
    int nd = m->nd;
    double L[36], e[6];
    memcpy(L, m->minv + (size_t)b * nd * nd, sizeof(double) * (size_t)nd * nd);
    if (cn_chol_factor(L, nd, 1e-12) != 0) return false;
    for (int j = 0; j < nd; j++) {
        for (int i = 0; i < nd; i++) e[i] = i == j;
        cn_chol_solve(L, nd, e);
        for (int i = 0; i < nd; i++) Mb[i * nd + j] = e[i];
    }
    for (int i = 0; i < nd; i++) /* exactly symmetric */
        for (int j = 0; j < i; j++) Mb[i * nd + j] = Mb[j * nd + i] = 0.5 * (Mb[i * nd + j] + Mb[j * nd + i]);
    return true;
}

/* The dense LCP's scaling (build_lcp's scale_lcp): row r of M = J M^-1 J^T (in W / g) times
 * sc[r] = 1 / sqrt(M_rr), and the largest row sum of |M| after it (*mmax), without forming M:
 * row r meets only the rows of the bodies it touches. */
static bool lcp_scale(const cnMech *m, const cnJRow *rows, int K, double *sc, double *mmax) {
    int nb = m->nb, nd = m->nd;
    double W = m->wref, g = m->g;
    int *start = cn_calloc((size_t)nb + 2, sizeof(int)), *list = cn_malloc(sizeof(int) * (2 * (size_t)K + 1));
    int *seen = cn_malloc(sizeof(int) * ((size_t)K + 1)), *stamp = cn_malloc(sizeof(int) * ((size_t)K + 1));
    double *val = cn_malloc(sizeof(double) * ((size_t)K + 1));
    if (!start || !list || !seen || !stamp || !val) {
        cn_free(start), cn_free(list), cn_free(seen), cn_free(stamp), cn_free(val);
        return false;
    }
    for (int r = 0; r < K; r++)
        for (int x = 0; x < 2; x++)
            if (rows[r].body[x] >= 0) start[rows[r].body[x] + 2]++;
    for (int b = 0; b < nb; b++) start[b + 2] += start[b + 1];
    for (int r = 0; r < K; r++)
        for (int x = 0; x < 2; x++)
            if (rows[r].body[x] >= 0) list[start[rows[r].body[x] + 1]++] = r;
    /* start[b] .. start[b + 1]: the rows of body b */
    for (int r = 0; r < K; r++) {
        double d = 0;
        for (int x = 0; x < 2; x++)
            if (rows[r].body[x] >= 0)
                for (int k = 0; k < nd; k++) d += rows[r].c[x][k] * rows[r].u[x][k];
        d *= W / g;
        sc[r] = d > 0 && isfinite(d) ? 1.0 / sqrt(d) : 1.0;
        val[r] = 0;
        stamp[r] = -1;
    }
    *mmax = 0;
    for (int r = 0; r < K; r++) {
        int ns = 0;
        for (int x = 0; x < 2; x++) {
            int b = rows[r].body[x];
            if (b < 0) continue;
            for (int t = start[b]; t < start[b + 1]; t++) {
                int j = list[t];
                const cnJRow *rj = &rows[j];
                int y = rj->body[0] == b ? 0 : 1;
                double v = 0;
                for (int k = 0; k < nd; k++) v += rows[r].c[x][k] * rj->u[y][k];
                if (stamp[j] != r) stamp[j] = r, seen[ns++] = j; /* each row once (at most K) */
                val[j] += v * W / g;
            }
        }
        double sum = 0;
        for (int t = 0; t < ns; t++) sum += fabs(val[seen[t]]) * sc[r] * sc[seen[t]], val[seen[t]] = 0;
        if (!(sum <= *mmax)) *mmax = sum;
    }
    cn_free(start), cn_free(list), cn_free(seen), cn_free(stamp), cn_free(val);
    return true;
}

cnStatus cn_motion_qp(const cnMech *m, const cnJRow *rows, int K, double tol, double *force, double *acc,
                      double *motion, bool *solved, double *residual, int *polish_moves, cnDiag *diag) {
    *solved = false;
    if (polish_moves) *polish_moves = -1;
    *residual = INFINITY;
    if (!cn_motion_qp_usable(m)) return CN_OK;
    int nb = m->nb, nd = m->nd, nv = nb * nd, dim = m->dim;
    double g = m->g, W = m->wref;
    int nnz = 0;
    for (int r = 0; r < K; r++)
        for (int x = 0; x < 2; x++) nnz += rows[r].body[x] >= 0 ? nd : 0;
    double *t = cn_malloc(sizeof(double) * (size_t)(nv + 1));
    double *mblk = cn_malloc(sizeof(double) * ((size_t)nv * nd + 1));
    double *b = cn_malloc(sizeof(double) * (size_t)(nv + 1));
    double *ah = cn_malloc(sizeof(double) * (size_t)(nv + 1));
    double *fh = cn_malloc(sizeof(double) * (size_t)(K + 1));
    int *rowptr = cn_malloc(sizeof(int) * (size_t)(K + 1));
    int *col = cn_malloc(sizeof(int) * (size_t)(nnz + 1));
    double *val = cn_malloc(sizeof(double) * (size_t)(nnz + 1));
    cnStatus st = CN_OK;
    if (!t || !mblk || !b || !ah || !fh || !rowptr || !col || !val) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the frictionless QP");
        goto done;
    }
    /* unknowns: accelerations in g, rotations times the body's radius */
    for (int bo = 0; bo < nb; bo++)
        for (int k = 0; k < nd; k++) {
            double rad = m->radius[bo] > 0 ? m->radius[bo] : 1.0;
            t[bo * nd + k] = k < dim ? g : g / rad;
        }
    for (int bo = 0; bo < nb; bo++) {
        double *Mb = mblk + (size_t)bo * nd * nd;
        if (!mass_block(m, bo, Mb)) goto done;
        for (int i = 0; i < nd; i++)
            for (int j = 0; j < nd; j++) Mb[i * nd + j] *= t[bo * nd + i] * t[bo * nd + j] / (W * g);
    }
    for (int j = 0; j < nv; j++) b[j] = m->fext[j] * t[j] / (W * g);
    int k = 0;
    for (int r = 0; r < K; r++) {
        rowptr[r] = k;
        for (int x = 0; x < 2; x++) {
            int bo = rows[r].body[x];
            if (bo < 0) continue;
            for (int d = 0; d < nd; d++) {
                col[k] = bo * nd + d;
                val[k++] = rows[r].c[x][d] * t[bo * nd + d] / g;
            }
        }
    }
    rowptr[K] = k;
    cnContactQp qp = {nb, nd, K, mblk, b, rowptr, col, val};
    cnQpIpmInfo info;
    if ((st = cn_contact_qp_ipm(&qp, ah, fh, &info, diag))) goto done;
    if (polish_moves) *polish_moves = info.polished ? info.moves : -1;
    /* the forces are the answer, converged or not (the last iterates of an ill-conditioned
     * problem stall in the residuals but not in the forces): the motion is recomputed from them
     * and the LCP's conditions checked */
    for (int r = 0; r < K; r++) force[r] = fmax(fh[r], 0) * W;
    if (motion)
        for (int j = 0; j < nv; j++) motion[j] = ah[j] * t[j];
    cn_mech_response(m, rows, K, force, acc);
    /* the natural residual of the scaled LCP relative to its data, as the dense LCP's
     * verification (cn_lcp_residual) reads it */
    double mmax;
    if (!lcp_scale(m, rows, K, fh, &mmax)) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory verifying the frictionless QP");
        goto done;
    }
    double worst = 0, qmax = 0, zmax = 0;
    for (int r = 0; r < K; r++) {
        double sc = fh[r]; /* scratch reused: the row scales */
        double q = sc * cn_mech_relative(m, &rows[r], m->a0) / g;
        double w = sc * cn_mech_relative(m, &rows[r], acc) / g, f = force[r] / W / sc;
        qmax = fmax(qmax, fabs(q));
        zmax = fmax(zmax, f);
        double e = fmax(-w, fabs(fmin(f, w)));
        if (isnan(w) || isnan(f) || isnan(q)) e = NAN; /* fmax and fmin drop a NaN */
        if (!(e <= worst)) worst = e;                  /* NaN: failure */
    }
    *residual = worst / fmax(fmax(qmax, mmax * zmax), 1e-300);
    if (isnan(mmax)) *residual = NAN;
    *solved = *residual <= (tol > 0 ? tol : CN_LCP_DEFAULT_TOL);
done:
    cn_free(t);
    cn_free(mblk);
    cn_free(b);
    cn_free(ah);
    cn_free(fh);
    cn_free(rowptr);
    cn_free(col);
    cn_free(val);
    return st;
}
