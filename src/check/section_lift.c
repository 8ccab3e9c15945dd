/* A motion of a prism's 2-D section lifted to the prism: the section's motion extruded (each
 * body moving in the section's plane as its section does), the contact forces that give the 3-D
 * problem that motion found by an LP (the least complementarity violation with the motion's
 * velocities), and the whole verified as a solution of the 3-D LCP (cn_motion_verify) before it
 * counts. A moving body may depart from the target by a slack that keeps every contact's mode (a
 * section from a file's float32 coordinates is over-determined in 3-D to rounding: a block
 * wedged on two faces slides in 2-D with two forces for three equations). The LP holds the moving
 * bodies, their chains down to a fixed part and the bodies touching those (cn_local_chain_ring),
 * the rest at the static field (a static solution of every other body, so complementary to its
 * rest); all bodies when that fails and there are few. */
#include <math.h>
#include <string.h>

#include "check_work.h"
#include "section.h"
#include "search.h"

/* A pair whose velocity is above this (in g) takes no force, a cone whose contact slides faster
 * is tight: just under cn_motion_verify's tolerance (CN_BB_VERIFY_TOL), so that what the LP finds
 * passes it; and, for a small motion, just under its size over CN_VERIFY_MOTION_OVER. */
#define CN_LIFT_TOL 0.999e-7
/* A column's entries below this fraction of its largest are rounding (left out of the LP; the
 * verification recomputes the motion from the forces found, with every entry) */
#define CN_LIFT_ROUNDING 1e-12
/* The LP over every body is tried up to this many bodies (its dual simplex grows fast: 400
 * bodies, 14 s) */
#define CN_LIFT_WHOLE_MAX 120

typedef struct {
    const cnMotionProblem *p;
    const double *target;
    const unsigned char *moving; /* the bodies the target moves */
    double *rel, *gam, *scale, *rhs, *cost, *x, *vals;
    int *fof, *colptr, *col, *cone, *rows, *eq, *band, *banded;
} Lift;

/* Does row r join bodies of `in` (or a body of it and a fixed part; in NULL: every body)? */
static bool inside(const cnMotionProblem *p, const unsigned char *in, int r) {
    const cnJRow *row = &p->rows[r];
    return !in || ((row->body[0] < 0 || in[row->body[0]]) && (row->body[1] < 0 || in[row->body[1]]));
}

/* One LP: the rows between bodies of `in` (NULL: every body) chosen, the others at the static
 * field; force receives them all. 1 found (not yet verified), 0 none, -1 out of memory. */
static int lift_lp(Lift *L, const unsigned char *in, bool slack, double *force) {
    const cnMotionProblem *p = L->p;
    const cnMech *m = p->m;
    int K = p->K, Kf = p->Kf, D = p->D, nd = m->nd, nb = m->nb, nrows = K + Kf * D;
    double W = m->wref, g = m->g, size = 0;
    for (int c = 0; c < nb; c++) size = fmax(size, cn_mech_motion_size(m, c, L->target));
    double thr = fmin(CN_LIFT_TOL * g, 0.999 * size / CN_VERIFY_MOTION_OVER);
    /* a force where its pair's velocity w is above the verification's tolerance must be zero,
       and a cone whose contact slides that much tight: the rest chosen by the LP */
    int nvars = 0, neq = 0, nineq = 0;
    for (int c = 0; c < nb; c++) L->eq[c] = !in || in[c] ? (neq += nd) - nd : -1;
    for (int r = 0; r < nrows; r++) {
        bool chosen = inside(p, in, r);
        double w = r < K ? L->rel[r] : L->rel[r] + L->gam[(r - K) / D];
        L->col[r] = chosen && w <= thr ? nvars++ : -1;
        force[r] = chosen ? 0 : p->field[r];
    }
    /* the cones of the contacts chosen: tight ones among the equations, the others after */
    int ncones = 0;
    for (int f = 0; f < Kf; f++) L->cone[f] = inside(p, in, p->contact_of_fric[f]) ? -1 : -2;
    for (int f = 0; f < Kf; f++)
        if (L->cone[f] == -1 && L->gam[f] > thr) L->cone[f] = neq + ncones++;
    for (int f = 0; f < Kf; f++)
        if (L->cone[f] == -1) L->cone[f] = neq + ncones + nineq++;
    for (int f = 0; f < Kf; f++)
        if (L->cone[f] == -2) L->cone[f] = -1;
    int neqs = neq + ncones;
    /* equations in g (rotations times the body's radius): each body's motion is the target, less
       what the fixed rows (the field's) give it */
    for (int c = 0; c < nb; c++)
        for (int d = 0; L->eq[c] >= 0 && d < nd; d++)
            L->rhs[L->eq[c] + d] = (L->target[c * nd + d] - m->a0[c * nd + d]) * L->scale[c * nd + d];
    for (int i = neq; i < neqs + nineq; i++) L->rhs[i] = 0;
    for (int r = 0; r < nrows; r++) {
        if (L->col[r] >= 0 || force[r] == 0) continue;
        const cnJRow *row = &p->rows[r];
        for (int s = 0; s < 2; s++) {
            int c = row->body[s];
            for (int d = 0; c >= 0 && L->eq[c] >= 0 && d < nd; d++)
                L->rhs[L->eq[c] + d] -= row->u[s][d] * force[r] * L->scale[c * nd + d];
        }
    }
    int at = 0;
    for (int r = 0; r < nrows; r++) {
        if (L->col[r] < 0) continue;
        int j = L->col[r];
        L->colptr[j] = at;
        const cnJRow *row = &p->rows[r];
        /* entries at rounding of the column's largest left out: a friction direction at pi
           has sin(pi) = 1.2e-16 across the section, which the LP's scaling would blow up */
        double big = 0;
        for (int s = 0; s < 2; s++)
            for (int d = 0; row->body[s] >= 0 && d < nd; d++)
                big = fmax(big, fabs(row->u[s][d] * L->scale[row->body[s] * nd + d]));
        for (int s = 0; s < 2; s++) {
            int c = row->body[s];
            for (int d = 0; c >= 0 && L->eq[c] >= 0 && d < nd; d++) {
                double v = row->u[s][d] * L->scale[c * nd + d];
                if (fabs(v) > CN_LIFT_ROUNDING * big) L->rows[at] = L->eq[c] + d, L->vals[at++] = v * W;
            }
        }
        /* z.w: its normal velocity and mu times its sliding speed (the cone's slack), or its
           row's velocity (rel + gamma) less the slack's -gamma */
        if (r < K) {
            L->cost[j] = L->rel[r] / g;
            int f = L->fof[r];
            if (f >= 0 && L->cone[f] >= 0) {
                L->rows[at] = L->cone[f], L->vals[at++] = p->mu[f];
                L->cost[j] += p->mu[f] * L->gam[f] / g;
            }
        } else {
            int f = (r - K) / D;
            if (L->cone[f] >= 0) L->rows[at] = L->cone[f], L->vals[at++] = -1.0;
            L->cost[j] = L->rel[r] / g;
        }
    }
    /* the moving bodies' slack: target + delta, each row's velocity under delta kept by a band
       (a row that may push: within the threshold of zero; one that may not: separating) */
    int nband = neqs + nineq, ncols = nvars, nbanded = 0;
    for (int r = 0; slack && r < nrows; r++) {
        const cnJRow *row = &p->rows[r];
        bool touch = false;
        for (int s = 0; s < 2; s++) touch |= row->body[s] >= 0 && L->moving[row->body[s]];
        L->band[r] = -1;
        /* a sliding contact's rows are left free: its speed may change along its slip */
        if (!touch || !inside(p, in, r) || (r >= K && (L->col[r] < 0 || L->gam[(r - K) / D] > thr))) continue;
        double w = r < K ? L->rel[r] : L->rel[r] + L->gam[(r - K) / D];
        L->band[r] = nband, L->banded[nbanded++] = r;
        if (L->col[r] >= 0) { /* |w + v| <= thr / 2 (a friction row: |v|), well within the verification */
            L->rhs[nband++] = (-0.5 * thr - (r < K ? w : 0)) / g;
            L->rhs[nband++] = ((r < K ? w : 0) - 0.5 * thr) / g;
        } else {
            L->rhs[nband++] = -w / g; /* w + v >= 0 */
        }
    }
    for (int c = 0; slack && c < nb; c++) {
        if (!L->moving[c] || L->eq[c] < 0) continue;
        for (int d = 0; d < nd; d++)
            for (int sg = 0; sg < 2; sg++) { /* delta+ then delta- (scaled, in g) */
                double sign = sg ? -1.0 : 1.0;
                L->colptr[ncols] = at;
                L->rows[at] = L->eq[c] + d, L->vals[at++] = -sign;
                for (int i = 0; i < nbanded; i++) {
                    int r = L->banded[i];
                    const cnJRow *row = &p->rows[r];
                    double v = 0; /* the row's velocity per unit of delta, in g */
                    for (int s = 0; s < 2; s++)
                        if (row->body[s] == c) v += row->c[s][d] / L->scale[c * nd + d];
                    v *= sign;
                    if (v == 0) continue;
                    L->rows[at] = L->band[r], L->vals[at++] = v;
                    if (L->col[r] >= 0) L->rows[at] = L->band[r] + 1, L->vals[at++] = -v;
                }
                L->cost[ncols++] = 1.0;
            }
    }
    L->colptr[ncols] = at;
    cnLpProblem lp = {.nvars = ncols, .neq = neqs, .nineq = nband - neqs, .colptr = L->colptr, .rows = L->rows,
                      .vals = L->vals, .rhs = L->rhs, .cost = L->cost, .method = CN_LP_DUAL_EQ};
    bool feasible = false;
    cnDiag quiet;
    cn_diag_clear(&quiet);
    cnStatus st = cn_lp_solve(&lp, &feasible, L->x, &quiet);
    if (st == CN_ERR_MEMORY) return -1;
    if (st != CN_OK || !feasible) return 0; /* no forces give it that motion there */
    for (int r = 0; r < nrows; r++)
        if (L->col[r] >= 0) force[r] = fmax(L->x[L->col[r]], 0) * W;
    return 1;
}

int cn_section_lift(const cnMotionProblem *p, const double *target, double *force, double *acc) {
    const cnMech *m = p->m;
    int K = p->K, Kf = p->Kf, D = p->D, nd = m->nd, nb = m->nb;
    int nrows = K + Kf * D;
    if (p->nominal || nb == 0) return 0;
    unsigned char *moving = cn_calloc((size_t)nb + 1, 1);
    Lift L = {.p = p, .target = target, .moving = moving};
    size_t nslack = 2 * (size_t)nb * (size_t)nd; /* the moving bodies' delta+ and delta- */
    size_t nnz = (size_t)nrows * (2 * (size_t)nd + 1) + (size_t)nd * 2 * ((size_t)nb + 4 * (size_t)nrows) + 1;
    L.rel = cn_malloc(sizeof(double) * (size_t)(nrows + 1));
    L.gam = cn_calloc((size_t)Kf + 1, sizeof(double)); /* each friction contact's slip */
    L.scale = cn_malloc(sizeof(double) * (size_t)(nb * nd + 1));
    L.rhs = cn_calloc((size_t)(nb * nd + 2 * Kf) + 2 * (size_t)nrows + 1, sizeof(double));
    L.cost = cn_calloc((size_t)nrows + nslack + 1, sizeof(double));
    L.x = cn_calloc((size_t)nrows + nslack + 1, sizeof(double));
    L.vals = cn_malloc(sizeof(double) * nnz);
    L.fof = cn_malloc(sizeof(int) * (size_t)(K + 1));
    L.colptr = cn_malloc(sizeof(int) * ((size_t)nrows + nslack + 2));
    L.band = cn_malloc(sizeof(int) * (size_t)(nrows + 1)); /* row -> its first band row, or -1 */
    L.banded = cn_malloc(sizeof(int) * (size_t)(nrows + 1)); /* the rows with a band */
    L.col = cn_malloc(sizeof(int) * (size_t)(nrows + 1)); /* row -> LP column, or -1 */
    L.cone = cn_malloc(sizeof(int) * (size_t)(Kf + 1));   /* friction contact -> its cone row */
    L.rows = cn_malloc(sizeof(int) * nnz);
    L.eq = cn_malloc(sizeof(int) * (size_t)(nb + 1)); /* body -> its first equation, or -1 */
    double *lambda = cn_calloc((size_t)Kf + 1, sizeof(double));
    unsigned char *in = cn_calloc((size_t)nb + 1, 1);
    int out = -1;
    if (!L.rel || !L.gam || !L.scale || !L.rhs || !L.cost || !L.x || !L.vals || !L.fof || !L.colptr || !L.col ||
        !L.cone || !L.rows || !L.eq || !L.band || !L.banded || !lambda || !in || !moving)
        goto done;
    out = 0;
    double vmax = 0;
    for (int r = 0; r < nrows; r++) {
        L.rel[r] = cn_mech_relative(m, &p->rows[r], target);
        vmax = fmax(vmax, fabs(L.rel[r]));
    }
    if (!(vmax > 0) || !isfinite(vmax)) goto done;
    for (int c = 0; c < K; c++) L.fof[c] = -1;
    for (int f = 0; f < Kf; f++) {
        L.fof[p->contact_of_fric[f]] = f;
        for (int d = 0; d < D; d++) L.gam[f] = fmax(L.gam[f], -L.rel[K + f * D + d]);
    }
    for (int c = 0; c < nb; c++)
        for (int d = 0; d < nd; d++)
            L.scale[c * nd + d] = cn_motion_dof_unit(m, c, d);
    /* the moving bodies, their chains down to a fixed part, and the bodies touching those */
    for (int c = 0; c < nb; c++)
        for (int d = 0; d < nd && !moving[c]; d++) moving[c] = target[c * nd + d] != 0;
    if (p->field && cn_local_chain_ring(p, moving, in) < 0) {
        out = -1;
        goto done;
    }
    /* the bodies held (then all), each first without the slack, then with it (its band rows,
       within the LP's own tolerances of zero, slow the simplex down) */
    for (int attempt = 0; attempt < 4 && out == 0; attempt++) {
        int pass = attempt / 2;
        if (pass == 0 && !p->field) continue;        /* without a field: every body at once */
        if (pass == 1 && nb > CN_LIFT_WHOLE_MAX) break; /* its LP too large to solve here */
        int h = lift_lp(&L, pass == 0 ? in : NULL, attempt % 2 == 1, force);
        if (h < 0) out = -1;
        if (h != 1) continue;
        /* the sliding speeds of the motion the forces give, along the most opposed direction */
        cn_mech_response(m, p->rows, nrows, force, acc);
        for (int f = 0; f < Kf; f++) {
            lambda[f] = 0;
            for (int d = 0; d < D; d++)
                lambda[f] = fmax(lambda[f], -cn_mech_relative(m, &p->rows[K + f * D + d], acc));
        }
        out = cn_motion_verify(p, force, lambda, acc) == 1;
    }
done:
    cn_free(L.rel), cn_free(L.gam), cn_free(L.scale), cn_free(L.rhs), cn_free(L.cost), cn_free(L.x);
    cn_free(L.vals), cn_free(L.fof), cn_free(L.colptr), cn_free(L.col), cn_free(L.cone), cn_free(L.rows);
    cn_free(L.eq), cn_free(L.band), cn_free(L.banded), cn_free(lambda), cn_free(in), cn_free(moving);
    return out;
}
