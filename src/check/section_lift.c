/* A motion of a prism's 2-D section lifted to the prism: the section's motion extruded (each
 * body moving in the section's plane as its section does), the contact forces that give the 3-D
 * problem that motion found by an LP (the least complementarity violation with the motion's
 * velocities), and the whole verified as a solution of the 3-D LCP (cn_motion_verify) before it
 * counts. */
#include <math.h>
#include <string.h>

#include "check_work.h"
#include "section.h"

/* A pair whose velocity is above this (in g) takes no force, a cone whose contact slides faster
 * is tight: just under cn_motion_verify's tolerance (CN_BB_VERIFY_TOL), so that what the LP finds
 * passes it. */
#define CN_LIFT_TOL 0.999e-7
/* A column's entries below this fraction of its largest are rounding (left out of the LP; the
 * verification recomputes the motion from the forces found, with every entry) */
#define CN_LIFT_ROUNDING 1e-12

int cn_section_lift(const cnMotionProblem *p, const double *target, double *force, double *acc) {
    const cnMech *m = p->m;
    int K = p->K, Kf = p->Kf, D = p->D, nd = m->nd, dim = m->dim, nb = m->nb;
    int nrows = K + Kf * D;
    double W = m->wref, g = m->g;
    if (p->nominal || nb == 0) return 0;
    double *rel = cn_malloc(sizeof(double) * (size_t)(nrows + 1));
    double *gam = cn_calloc((size_t)Kf + 1, sizeof(double)); /* each friction contact's slip */
    int *fof = cn_malloc(sizeof(int) * (size_t)(K + 1));
    double *scale = cn_malloc(sizeof(double) * (size_t)(nb * nd + 1));
    int *colptr = cn_malloc(sizeof(int) * (size_t)(nrows + 2));
    int *col = cn_malloc(sizeof(int) * (size_t)(nrows + 1));  /* row -> LP column, or -1 */
    int *cone = cn_malloc(sizeof(int) * (size_t)(Kf + 1));    /* friction contact -> its cone row */
    size_t nnz = (size_t)nrows * (2 * (size_t)nd + 1) + 1;
    int *rows = cn_malloc(sizeof(int) * nnz);
    double *vals = cn_malloc(sizeof(double) * nnz);
    double *rhs = cn_calloc((size_t)(nb * nd + Kf) + 1, sizeof(double));
    double *cost = cn_calloc((size_t)nrows + 1, sizeof(double)), *x = cn_calloc((size_t)nrows + 1, sizeof(double));
    double *lambda = cn_calloc((size_t)Kf + 1, sizeof(double));
    int out = -1;
    if (!rel || !gam || !fof || !scale || !colptr || !col || !cone || !rows || !vals || !rhs || !cost || !x || !lambda) goto done;
    out = 0;
    double vmax = 0;
    for (int r = 0; r < nrows; r++) {
        rel[r] = cn_mech_relative(m, &p->rows[r], target);
        vmax = fmax(vmax, fabs(rel[r]));
    }
    if (!(vmax > 0) || !isfinite(vmax)) goto done;
    for (int c = 0; c < K; c++) fof[c] = -1;
    for (int f = 0; f < Kf; f++) {
        fof[p->contact_of_fric[f]] = f;
        for (int d = 0; d < D; d++) gam[f] = fmax(gam[f], -rel[K + f * D + d]);
    }
    /* equations in g (rotations times the body's radius): each body's motion is the target;
       then the friction cones. The motion fixes every complementarity pair's velocity w, so
       z.w (z: the forces and the cones' slack) is linear in the forces: the LP minimises it */
    for (int c = 0; c < nb; c++)
        for (int d = 0; d < nd; d++)
            scale[c * nd + d] = (d < dim ? 1.0 : (m->radius[c] > 0 ? m->radius[c] : 1.0)) / g;
    /* a force where its pair's velocity w is above the verification's tolerance must be zero,
       and a cone whose contact slides that much tight: the rest chosen by the LP */
    double thr = CN_LIFT_TOL * g;
    int nvars = 0, neq = nb * nd, nineq = 0;
    for (int r = 0; r < nrows; r++)
        col[r] = (r < K ? rel[r] : rel[r] + gam[(r - K) / D]) <= thr ? nvars++ : -1;
    for (int f = 0; f < Kf; f++)
        if (gam[f] > thr) cone[f] = neq++;
    for (int f = 0; f < Kf; f++)
        if (!(gam[f] > thr)) cone[f] = nb * nd + (neq - nb * nd) + nineq++;
    for (int i = 0; i < nb * nd; i++) rhs[i] = (target[i] - m->a0[i]) * scale[i];
    int at = 0;
    for (int r = 0; r < nrows; r++) {
        if (col[r] < 0) continue;
        colptr[col[r]] = at;
        const cnJRow *row = &p->rows[r];
        /* entries at rounding of the column's largest left out: a friction direction at pi
           has sin(pi) = 1.2e-16 across the section, which the LP's scaling would blow up */
        double big = 0;
        for (int s2 = 0; s2 < 2; s2++)
            for (int d = 0; row->body[s2] >= 0 && d < nd; d++)
                big = fmax(big, fabs(row->u[s2][d] * scale[row->body[s2] * nd + d]));
        for (int s2 = 0; s2 < 2; s2++) {
            int c = row->body[s2];
            for (int d = 0; c >= 0 && d < nd; d++) {
                double v = row->u[s2][d] * scale[c * nd + d];
                if (fabs(v) > CN_LIFT_ROUNDING * big) rows[at] = c * nd + d, vals[at++] = v * W;
            }
        }
        if (r < K) { /* its normal velocity, and mu times its sliding speed (the cone's slack) */
            cost[col[r]] = rel[r] / g;
            if (fof[r] >= 0) {
                rows[at] = cone[fof[r]], vals[at++] = p->mu[fof[r]];
                cost[col[r]] += p->mu[fof[r]] * gam[fof[r]] / g;
            }
        } else { /* its row's velocity (rel + gamma), less the slack's -gamma */
            rows[at] = cone[(r - K) / D], vals[at++] = -1.0;
            cost[col[r]] = rel[r] / g;
        }
    }
    colptr[nvars] = at;
    cnLpProblem lp = {.nvars = nvars, .neq = neq, .nineq = nineq, .colptr = colptr, .rows = rows, .vals = vals,
                      .rhs = rhs, .cost = cost, .method = CN_LP_DUAL_EQ};
    bool feasible = false;
    cnDiag quiet;
    cn_diag_clear(&quiet);
    cnStatus st = cn_lp_solve(&lp, &feasible, x, &quiet);
    if (st == CN_ERR_MEMORY) {
        out = -1;
        goto done;
    }
    if (st != CN_OK || !feasible) goto done; /* no forces give it that motion: not a lift */
    for (int r = 0; r < nrows; r++) force[r] = col[r] >= 0 ? fmax(x[col[r]], 0) * W : 0;
    /* the sliding speeds of the motion the forces give, along the most opposed direction */
    cn_mech_response(m, p->rows, nrows, force, acc);
    for (int f = 0; f < Kf; f++) {
        lambda[f] = 0;
        for (int d = 0; d < D; d++)
            lambda[f] = fmax(lambda[f], -cn_mech_relative(m, &p->rows[K + f * D + d], acc));
    }
    out = cn_motion_verify(p, force, lambda, acc) == 1;
done:
    cn_free(rel), cn_free(gam), cn_free(fof), cn_free(scale), cn_free(colptr), cn_free(rows);
    cn_free(vals), cn_free(rhs), cn_free(cost), cn_free(x), cn_free(lambda), cn_free(col), cn_free(cone);
    return out;
}
