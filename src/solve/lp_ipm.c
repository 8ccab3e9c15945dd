/* A primal-dual interior-point method for the large equilibrium LPs, on CHOLMOD's sparse
 * Cholesky factorisation of the normal equations.
 *
 * The problem is cnLpProblem's (A_eq x = b_eq, A_in x >= b_in, x >= 0), made elastic and put in
 * standard form: v = [x, t, s+, s-] >= 0 with
 *     A_eq x          + s+ - s- = b_eq
 *     A_in x  -  t    + s+ - s- = b_in
 * and cost weight c.x + sum(s+ + s-). The elastic slacks make every LP feasible and
 * bounded (c >= 0 on the normal forces keeps prestress from running off), so the method always
 * has an optimum to converge to: its x is a force field when the slacks vanish, and its duals
 * y (|y| <= 1, A^T y <= weight c) point along the motion that gravity drives when they do not.
 * The caller verifies either answer as it verifies GLPK's, and falls back to GLPK when neither
 * holds.
 *
 * Each iteration (Mehrotra's predictor-corrector) solves the normal equations
 *     (A D_x A^T + diag(d)) dy = r,  d_i = D_{s+,i} + D_{s-,i} (+ D_{t,i} on inequality rows),
 * which follow the contact graph (a body's rows meet the rows of the bodies it touches). They
 * are factorised as G G^T with G = [A D_x^(1/2), diag(d^(1/2))], whose pattern is fixed: the
 * ordering and symbolic analysis are done once, the numeric factorisation once per iteration.
 *
 * It starts from Mehrotra's point (mehrotra_start). Near the optimum of a badly scaled LP (the
 * thrust of an arch of 10,000 voussoirs with friction) the primal residual can grow again while
 * the gap closes: each solve is refined against A_hat D A_hat^T itself, the iterate whose forces
 * come nearest to a static field is kept, and an answer whose forces miss equilibrium by more
 * than the tolerance is projected onto it (field_polish) before the caller verifies it. When any
 * field will do (cnLpProblem.any_field) the projection is also tried during the run, and the
 * method stops at the first one that is a field. */
#include <math.h>
#include <pthread.h>
#include <string.h>

#include <suitesparse/cholmod.h>

#include "solve.h"

/* Converged when the primal and dual residuals are below this relative to the data, and the
 * complementarity gap below it relative to the objective. */
#define CN_IPM_TOL 1e-10
/* Iterations before giving up (typical: 15-40; the 2-D arch of 10,000 voussoirs with friction
 * needs 93, the 3-D vault of 10,000 80). */
#define CN_IPM_MAX_ITER 150
/* Fraction of the step to the boundary taken. */
#define CN_IPM_STEP 0.995
/* Refinement steps of each normal-equations solve (a step that makes the residual worse is
 * undone), and the residual (relative to the right-hand side) below which none is done. */
#define CN_IPM_REFINE 2
#define CN_IPM_REFINE_TOL 1e-12
/* Iterations after the gap and the dual residual have closed, with forces already within
 * CN_IPM_POLISH_FROM of a static field, without their coming nearer to one by CN_IPM_BETTER,
 * before the method stops (with the nearest iterate). With forces farther from any field (the
 * elastic optimum is positive: the LP has none), the same count without the primal residual
 * falling by CN_IPM_BETTER: the duals, the certificate, no longer change. */
#define CN_IPM_STALL 8
#define CN_IPM_BETTER 0.5
/* Projections of an answer that misses CN_IPM_TOL onto equilibrium (field_polish), and the weight of the
 * elastic slacks in them relative to the largest force squared (they are to stay zero). */
/* On a failed factorisation, the slacks' diagonal raised by this times the largest weight, and
 * 100 times more on each of a few tries. */
#define CN_IPM_REG 1e-15
#define CN_IPM_REG_TRIES 3
#define CN_IPM_POLISH 3
#define CN_IPM_POLISH_REG 1e-14
/* ... tried only on forces this near (relative residual) to a field: farther, the LP has none,
 * or not near this iterate */
#define CN_IPM_POLISH_FROM 1e-4
/* When any field will do (cnLpProblem.any_field), projections tried during the run: at most
 * this many, the first once the forces are within CN_IPM_POLISH_FROM of a field, each next one
 * once they have come nearer by this factor. Each costs three factorisations, and one that
 * finds a field ends the run early. */
#define CN_IPM_FIELD_TRIES 3
#define CN_IPM_FIELD_RETRY 1e-2

static pthread_mutex_t analyse_lock = PTHREAD_MUTEX_INITIALIZER;

/* The factorisation is simplicial (column by column, no BLAS) unless the symbolic analysis
 * finds at least this many flops per entry of the factor, which is where dense blocks
 * (supernodes) pay for the BLAS calls. Flat assemblies (2-D arches and walls: about 10 to 130
 * flops per entry) gain little in supernodes, or lose, and lose on a reference BLAS; solid ones
 * (3-D vaults and stacks: 250 and more) gain, even on a reference BLAS. So 200 keeps the flat
 * ones simplicial on any BLAS and gives the solid ones to the BLAS. */
#define CN_CHOLMOD_SUPERNODAL_SWITCH 200

void cn_cholmod_start(cholmod_common *c) {
    cholmod_start(c);
    c->print = 0; /* the library never prints: failures come back as statuses */
    c->error_handler = NULL;
    c->final_ll = 1; /* LL^T, as the normal equations are positive definite */
    c->supernodal = CHOLMOD_AUTO;
    c->supernodal_switch = CN_CHOLMOD_SUPERNODAL_SWITCH;
    /* CHOLMOD's default ordering: AMD, then METIS when AMD fills in much (AMD alone makes the
     * factorisation of a large wall several times slower). */
}

bool cn_cholmod_factor(cholmod_sparse *G, cholmod_factor **L, cholmod_common *c) {
    if (!*L) {
        pthread_mutex_lock(&analyse_lock);
        *L = cholmod_analyze(G, c);
        pthread_mutex_unlock(&analyse_lock);
        if (!*L) return false;
    }
    return cholmod_factorize(G, *L, c) && c->status == CHOLMOD_OK;
}

bool cn_cholmod_solve(cholmod_factor *L, const double *b, double *x, int n, cholmod_common *c) {
    cholmod_dense *bd = cholmod_allocate_dense((size_t)n, 1, (size_t)n, CHOLMOD_REAL, c);
    if (!bd) return false;
    memcpy(bd->x, b, sizeof(double) * (size_t)n);
    cholmod_dense *xd = cholmod_solve(CHOLMOD_A, L, bd, c);
    cholmod_free_dense(&bd, c);
    if (!xd) return false;
    memcpy(x, xd->x, sizeof(double) * (size_t)n);
    cholmod_free_dense(&xd, c);
    for (int i = 0; i < n; i++)
        if (!isfinite(x[i])) return false;
    return true;
}

void cn_cholmod_finish(cholmod_sparse **G, cholmod_factor **L, cholmod_common *c) {
    if (*L) cholmod_free_factor(L, c);
    if (*G) cholmod_free_sparse(G, c);
    cholmod_finish(c);
}

typedef struct {
    const cnLpProblem *lp;
    int n, nin, m, N; /* x, t, rows, all of v */
    double *v, *z, *y;
    double *dv, *dz, *dy;
    double *rp, *rd, *rc, *rhs, *D;
    double *scratch, *res, *corr; /* the refinement's: N, m, m entries */
    double *best;                 /* the forces of the iterate nearest to a static field */
    double *trial;                /* an iterate's forces projected onto a field (any_field) */
    double *cost;
    /* Inequality rows eliminated from the normal equations (schur), when each column has an entry
     * in at most one of them (a contact's cone row, over its own normal and friction columns):
     * their block of A D A^T is then diagonal and the factor is of its Schur complement, whose
     * pattern is the equations' alone. */
    bool schur;
    int *grp_p, *grp;    /* the columns of each inequality row (nin + 1, then its entries) */
    double *grp_c;       /* their coefficients in that row */
    int *urow_p, *urow;  /* the union of a row's columns' equation rows (nin + 1, then rows) */
    int *rowpos;         /* scratch: a row's place in its union (m entries, -1 otherwise) */
    unsigned char *ingrp; /* per column: it has an entry in an inequality row */
    double *delta;       /* per inequality row: its diagonal entry, c^T D c + its slacks' */
    double *sch;         /* scratch: m entries */
    double *ge;          /* scratch: a row's equation entries, dense (its union by its columns) */
    int gmax;            /* largest union times columns */
    double reg;          /* added to the slacks' diagonal when the factorisation fails */
    cholmod_common c;
    cholmod_sparse *G;
    cholmod_factor *L;
    bool started;
} Ipm;

/* Offsets of v's blocks. */
static int off_t_(const Ipm *s) { return s->n; }
static int off_sp(const Ipm *s) { return s->n + s->nin; }
static int off_sm(const Ipm *s) { return s->n + s->nin + s->m; }

/* out = A_hat v (m entries). */
static void mul_a(const Ipm *s, const double *v, double *out) {
    const cnLpProblem *lp = s->lp;
    memset(out, 0, sizeof(double) * (size_t)s->m);
    for (int j = 0; j < s->n; j++)
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) out[lp->rows[t]] += lp->vals[t] * v[j];
    for (int k = 0; k < s->nin; k++) out[lp->neq + k] -= v[off_t_(s) + k];
    for (int i = 0; i < s->m; i++) out[i] += v[off_sp(s) + i] - v[off_sm(s) + i];
}

/* out = A_hat^T y (N entries). */
static void mul_at(const Ipm *s, const double *y, double *out) {
    const cnLpProblem *lp = s->lp;
    for (int j = 0; j < s->n; j++) {
        double g = 0;
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) g += lp->vals[t] * y[lp->rows[t]];
        out[j] = g;
    }
    for (int k = 0; k < s->nin; k++) out[off_t_(s) + k] = -y[s->lp->neq + k];
    for (int i = 0; i < s->m; i++) out[off_sp(s) + i] = y[i], out[off_sm(s) + i] = -y[i];
}

static double inf_norm(const double *a, int n) {
    double r = 0;
    for (int i = 0; i < n; i++) r = fmax(r, fabs(a[i]));
    return r;
}

/* The inequality rows' columns, when every column has an entry in at most one of them (and
 * none holds a row twice): s->schur. False when out of memory. */
static bool schur_groups(Ipm *s) {
    const cnLpProblem *lp = s->lp;
    int nin = s->nin, neq = lp->neq;
    s->schur = false;
    if (nin == 0) return true;
    int *cnt = cn_calloc((size_t)nin + 1, sizeof(int));
    if (!cnt) return false;
    for (int j = 0; j < s->n; j++) {
        int k = 0;
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
            if (lp->rows[t] >= neq) k++, cnt[lp->rows[t] - neq]++;
        if (k > 1) {
            cn_free(cnt);
            return true; /* not separable: the full system */
        }
    }
    s->grp_p = cn_malloc(sizeof(int) * (size_t)(nin + 1));
    s->urow_p = cn_malloc(sizeof(int) * (size_t)(nin + 1));
    s->rowpos = cn_malloc(sizeof(int) * (size_t)s->m);
    s->delta = cn_calloc((size_t)nin, sizeof(double));
    s->sch = cn_calloc((size_t)s->m, sizeof(double));
    if (!s->grp_p || !s->urow_p || !s->rowpos || !s->delta || !s->sch) {
        cn_free(cnt);
        return false;
    }
    s->grp_p[0] = 0;
    for (int i = 0; i < nin; i++) s->grp_p[i + 1] = s->grp_p[i] + cnt[i];
    s->grp = cn_malloc(sizeof(int) * (size_t)(s->grp_p[nin] + 1));
    s->grp_c = cn_malloc(sizeof(double) * (size_t)(s->grp_p[nin] + 1));
    s->ingrp = cn_calloc((size_t)s->n + 1, 1);
    if (!s->grp || !s->grp_c || !s->ingrp) {
        cn_free(cnt);
        return false;
    }
    memset(cnt, 0, sizeof(int) * (size_t)nin);
    for (int j = 0; j < s->n; j++)
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
            if (lp->rows[t] >= neq) {
                int i = lp->rows[t] - neq, at = s->grp_p[i] + cnt[i]++;
                s->grp[at] = j, s->grp_c[at] = lp->vals[t], s->ingrp[j] = 1;
            }
    cn_free(cnt);
    /* each row's union of equation rows, in the order its columns meet them */
    size_t cap = 1;
    for (int a = 0; a < s->grp_p[nin]; a++) cap += (size_t)(lp->colptr[s->grp[a] + 1] - lp->colptr[s->grp[a]]);
    s->urow = cn_malloc(sizeof(int) * cap);
    if (!s->urow) return false;
    for (int i = 0; i < s->m; i++) s->rowpos[i] = -1;
    int k = 0;
    for (int i = 0; i < nin; i++) {
        int start = s->urow_p[i] = k;
        for (int a = s->grp_p[i]; a < s->grp_p[i + 1]; a++)
            for (int t = lp->colptr[s->grp[a]]; t < lp->colptr[s->grp[a] + 1]; t++) {
                int r = lp->rows[t];
                if (r < neq && s->rowpos[r] < 0) s->rowpos[r] = k - start, s->urow[k++] = r;
            }
        for (int a = start; a < k; a++) s->rowpos[s->urow[a]] = -1;
        int sz = (k - start) * (s->grp_p[i + 1] - s->grp_p[i]);
        if (sz > s->gmax) s->gmax = sz;
    }
    s->urow_p[nin] = k;
    s->ge = cn_malloc(sizeof(double) * (size_t)(s->gmax + 1));
    if (!s->ge) return false;
    s->schur = true;
    return true;
}

/* G = [A D_x^(1/2), diag(d^(1/2))]: the pattern once, the values from D every time. With the
 * inequality rows eliminated (schur), G has the equation rows only, and the columns of an
 * inequality row are replaced by as many over the union of their rows (fill_g). */
static bool build_g(Ipm *s) {
    const cnLpProblem *lp = s->lp;
    if (s->schur) {
        int neq = lp->neq;
        size_t nnz = (size_t)neq;
        for (int j = 0; j < s->n; j++)
            for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) nnz += lp->rows[t] < neq;
        for (int i = 0; i < s->nin; i++)
            nnz += (size_t)(s->urow_p[i + 1] - s->urow_p[i]) * (size_t)(s->grp_p[i + 1] - s->grp_p[i]);
        s->G = cholmod_allocate_sparse((size_t)neq, (size_t)(s->n + neq), nnz, 0, 1, 0, CHOLMOD_REAL, &s->c);
        if (!s->G) return false;
        int *p = s->G->p, *ri = s->G->i;
        int k = 0, col = 0;
        /* the grouped columns first, row by row, then the others, then the diagonal */
        for (int i = 0; i < s->nin; i++)
            for (int a = s->grp_p[i]; a < s->grp_p[i + 1]; a++) {
                p[col++] = k;
                for (int b = s->urow_p[i]; b < s->urow_p[i + 1]; b++) ri[k++] = s->urow[b];
            }
        for (int j = 0; j < s->n; j++) {
            if (s->ingrp[j]) continue;
            p[col++] = k;
            for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
                if (lp->rows[t] < neq) ri[k++] = lp->rows[t];
        }
        for (int i = 0; i < neq; i++) p[col++] = k, ri[k++] = i;
        p[col] = k;
        return true;
    }
    size_t nnz = (size_t)(s->n > 0 ? lp->colptr[s->n] : 0) + (size_t)s->m;
    /* unsorted: a column's rows come as the LP gives them */
    s->G = cholmod_allocate_sparse((size_t)s->m, (size_t)(s->n + s->m), nnz, 0, 1, 0, CHOLMOD_REAL, &s->c);
    if (!s->G) return false;
    int *p = s->G->p, *ri = s->G->i;
    int k = 0;
    for (int j = 0; j < s->n; j++) {
        p[j] = k;
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) ri[k++] = lp->rows[t];
    }
    for (int i = 0; i < s->m; i++) p[s->n + i] = k, ri[k++] = i;
    p[s->n + s->m] = k;
    return true;
}

/* G's values with the inequality rows eliminated. An inequality row c over its columns S, with
 * D_S their weights and d its slacks', contributes E_S (D_S - D_S c c^T D_S / (c^T D_S c + d))
 * E_S^T to the Schur complement; with u = D_S^(1/2) c and beta = |u|^2 / (|u|^2 + d) that is
 * E_S D_S^(1/2) (I - beta uu^T/|u|^2) D_S^(1/2) E_S^T, and I - gamma uu^T/|u|^2 with gamma =
 * 1 - sqrt(1 - beta) = beta / (1 + sqrt(1 - beta)) (written so, without cancellation) is the
 * square root of the middle factor: G's columns are E_S D_S^(1/2) (I - gamma uu^T/|u|^2). */
static void fill_g_schur(Ipm *s) {
    const cnLpProblem *lp = s->lp;
    int neq = lp->neq;
    double *gx = s->G->x;
    int k = 0;
    for (int i = 0; i < s->nin; i++) {
        int a0 = s->grp_p[i], nc = s->grp_p[i + 1] - a0, u0 = s->urow_p[i], nu = s->urow_p[i + 1] - u0;
        for (int b = 0; b < nu; b++) s->rowpos[s->urow[u0 + b]] = b;
        double *E = s->ge; /* nu x nc, by column */
        memset(E, 0, sizeof(double) * (size_t)(nu * nc));
        double uu = 0;
        for (int a = 0; a < nc; a++) {
            int j = s->grp[a0 + a];
            for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
                if (lp->rows[t] < neq) E[a * nu + s->rowpos[lp->rows[t]]] += lp->vals[t];
            double uj = sqrt(s->D[j]) * s->grp_c[a0 + a];
            uu += uj * uj;
        }
        for (int b = 0; b < nu; b++) s->rowpos[s->urow[u0 + b]] = -1;
        double d = s->D[off_t_(s) + i] + s->D[off_sp(s) + neq + i] + s->D[off_sm(s) + neq + i];
        s->delta[i] = uu + d;
        double beta = uu > 0 ? uu / (uu + d) : 0, gamma = beta / (1 + sqrt(1 - beta)), un = sqrt(uu);
        /* w = E_S D_S^(1/2) u / |u| over the union's rows */
        double *w = s->sch; /* nu entries at most */
        for (int b = 0; b < nu; b++) w[b] = 0;
        for (int a = 0; a < nc && un > 0; a++) {
            int j = s->grp[a0 + a];
            double f = s->D[j] * s->grp_c[a0 + a] / un; /* sqrt(D_j) * uhat_j */
            for (int b = 0; b < nu; b++) w[b] += E[a * nu + b] * f;
        }
        for (int a = 0; a < nc; a++) {
            int j = s->grp[a0 + a];
            double r = sqrt(s->D[j]), uh = un > 0 ? r * s->grp_c[a0 + a] / un : 0;
            for (int b = 0; b < nu; b++) gx[k++] = r * E[a * nu + b] - gamma * uh * w[b];
        }
    }
    /* the ungrouped columns, in build_g's order: every column not in a group, by index */
    for (int j = 0; j < s->n; j++) {
        if (s->ingrp[j]) continue;
        double r = sqrt(s->D[j]);
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
            if (lp->rows[t] < neq) gx[k++] = lp->vals[t] * r;
    }
    for (int i = 0; i < neq; i++) gx[k++] = sqrt(s->D[off_sp(s) + i] + s->D[off_sm(s) + i] + s->reg);
}

static void fill_g(Ipm *s) {
    const cnLpProblem *lp = s->lp;
    if (s->schur) {
        fill_g_schur(s);
        return;
    }
    double *gx = s->G->x;
    int k = 0;
    for (int j = 0; j < s->n; j++) {
        double r = sqrt(s->D[j]);
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) gx[k++] = lp->vals[t] * r;
    }
    for (int i = 0; i < s->m; i++) {
        double d = s->D[off_sp(s) + i] + s->D[off_sm(s) + i];
        if (i >= lp->neq) d += s->D[off_t_(s) + i - lp->neq];
        gx[k++] = sqrt(d + s->reg);
    }
}

/* dy = (A_hat D A_hat^T)^-1 rhs with the current factor: G G^T itself, or, with the inequality
 * rows eliminated, their part of rhs moved onto the equations, the Schur complement solved,
 * and their part of dy from it. */
static bool solve_factor(Ipm *s, const double *rhs, double *dy) {
    if (!s->schur) return cn_cholmod_solve(s->L, rhs, dy, s->m, &s->c);
    const cnLpProblem *lp = s->lp;
    int neq = lp->neq;
    double *r1 = s->sch;
    memcpy(r1, rhs, sizeof(double) * (size_t)neq);
    for (int i = 0; i < s->nin; i++) {
        double wi = s->delta[i] > 0 ? rhs[neq + i] / s->delta[i] : 0;
        if (wi == 0) continue;
        for (int a = s->grp_p[i]; a < s->grp_p[i + 1]; a++) {
            int j = s->grp[a];
            double f = s->D[j] * s->grp_c[a] * wi;
            for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
                if (lp->rows[t] < neq) r1[lp->rows[t]] -= lp->vals[t] * f;
        }
    }
    if (!cn_cholmod_solve(s->L, r1, dy, neq, &s->c)) return false;
    for (int i = 0; i < s->nin; i++) {
        double g = 0;
        for (int a = s->grp_p[i]; a < s->grp_p[i + 1]; a++) {
            int j = s->grp[a];
            double e = 0;
            for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
                if (lp->rows[t] < neq) e += lp->vals[t] * dy[lp->rows[t]];
            g += s->grp_c[a] * s->D[j] * e;
        }
        dy[neq + i] = s->delta[i] > 0 ? (rhs[neq + i] - g) / s->delta[i] : 0;
    }
    return true;
}

/* out = (A_hat D A_hat^T) y, from A_hat itself rather than the factor; t: N entries of scratch. */
static void mul_normal(Ipm *s, const double *y, double *t, double *out) {
    mul_at(s, y, t);
    for (int j = 0; j < s->N; j++) t[j] *= s->D[j];
    mul_a(s, t, out);
}

/* Solve (A_hat D A_hat^T) dy = rhs with the current factor, refined against the product itself:
 * the primal residual of the step is this system's residual, which a factor of a badly scaled D
 * leaves far above rounding near the optimum. */
static bool solve_normal(Ipm *s, const double *rhs, double *dy) {
    if (!solve_factor(s, rhs, dy)) return false;
    double rn = inf_norm(rhs, s->m), prev = INFINITY;
    for (int k = 0;; k++) {
        mul_normal(s, dy, s->scratch, s->res);
        for (int i = 0; i < s->m; i++) s->res[i] = rhs[i] - s->res[i];
        double e = inf_norm(s->res, s->m);
        if (!(e < prev)) { /* the last correction made it worse: undone */
            if (k > 0)
                for (int i = 0; i < s->m; i++) dy[i] -= s->corr[i];
            break;
        }
        if (!(e > CN_IPM_REFINE_TOL * rn) || k == CN_IPM_REFINE) break;
        prev = e;
        if (!solve_factor(s, s->res, s->corr)) break; /* dy stands unrefined */
        for (int i = 0; i < s->m; i++) dy[i] += s->corr[i];
    }
    return true;
}

/* The Newton direction for the complementarity target rc (per entry of v): dv, dz, dy. */
static bool direction(Ipm *s) {
    int N = s->N, m = s->m;
    /* rhs = rp + A_hat (D rd - Z^-1 rc) */
    for (int j = 0; j < N; j++) s->dv[j] = s->D[j] * s->rd[j] - s->rc[j] / s->z[j];
    mul_a(s, s->dv, s->rhs);
    for (int i = 0; i < m; i++) s->rhs[i] += s->rp[i];
    if (!solve_normal(s, s->rhs, s->dy)) return false;
    mul_at(s, s->dy, s->dz); /* scratch: A_hat^T dy */
    for (int j = 0; j < N; j++) {
        s->dv[j] = s->D[j] * (s->dz[j] - s->rd[j]) + s->rc[j] / s->z[j];
        s->dz[j] = (s->rc[j] - s->z[j] * s->dv[j]) / s->v[j];
    }
    return true;
}

static double max_step(const double *x, const double *dx, int n) {
    double a = 1.0;
    for (int j = 0; j < n; j++)
        if (dx[j] < 0) a = fmin(a, -x[j] / dx[j]);
    return a;
}

static void ipm_free(Ipm *s) {
    double **arrs[] = {&s->v, &s->z, &s->y, &s->dv, &s->dz, &s->dy, &s->rp, &s->rd, &s->rc, &s->rhs, &s->D, &s->cost,
                       &s->scratch, &s->res, &s->corr, &s->best, &s->trial, &s->grp_c, &s->delta, &s->sch, &s->ge};
    for (size_t i = 0; i < sizeof arrs / sizeof arrs[0]; i++) cn_free(*arrs[i]), *arrs[i] = NULL;
    int **iarrs[] = {&s->grp_p, &s->grp, &s->urow_p, &s->urow, &s->rowpos};
    for (size_t i = 0; i < sizeof iarrs / sizeof iarrs[0]; i++) cn_free(*iarrs[i]), *iarrs[i] = NULL;
    cn_free(s->ingrp), s->ingrp = NULL;
    if (s->started) cn_cholmod_finish(&s->G, &s->L, &s->c);
}

/* How far the forces v[0..n) alone are from a static field: the largest equilibrium residual
 * and cone violation, the elastic slacks left out. */
static double field_residual(Ipm *s, const double *v, const double *b) {
    const cnLpProblem *lp = s->lp;
    double *r = s->res;
    memset(r, 0, sizeof(double) * (size_t)s->m);
    for (int j = 0; j < s->n; j++)
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) r[lp->rows[t]] += lp->vals[t] * v[j];
    double e = 0;
    for (int i = 0; i < s->m; i++) e = fmax(e, i < lp->neq ? fabs(b[i] - r[i]) : b[i] - r[i]);
    return e;
}

/* The kept iterate's forces and cone slacks (v, the elastic slacks zero) moved onto A_hat v = b
 * by the least change weighted by v^2 (affine scaling: a force changes in proportion to
 * itself, so small ones stay positive): dv = V^2 A_hat^T w, (A_hat V^2 A_hat^T) w = b - A_hat
 * v, a few times, each step cut short where a variable would reach zero. The interior point
 * stops short of exact equilibrium by its elastic slacks and, near the optimum, by its own
 * rounding; this removes both when the forces it found can carry the loads. */
static void field_polish(Ipm *s, const double *b, double *v) {
    int nx = s->n + s->nin;
    s->reg = 0;
    for (int k = 0; k < CN_IPM_POLISH; k++) {
        mul_a(s, v, s->rhs);
        for (int i = 0; i < s->m; i++) s->rhs[i] = b[i] - s->rhs[i];
        double big = 0;
        for (int j = 0; j < nx; j++) big = fmax(big, v[j] * v[j]);
        for (int j = 0; j < nx; j++) s->D[j] = v[j] * v[j];
        for (int j = nx; j < s->N; j++) s->D[j] = CN_IPM_POLISH_REG * big;
        fill_g(s);
        if (!cn_cholmod_factor(s->G, &s->L, &s->c) || !solve_normal(s, s->rhs, s->dy)) return;
        mul_at(s, s->dy, s->dv);
        for (int j = 0; j < nx; j++) s->dv[j] *= s->D[j];
        double a = fmin(1.0, max_step(v, s->dv, nx));
        if (a < 1) a *= CN_IPM_STEP;
        for (int j = 0; j < nx; j++) v[j] = fmax(v[j] + a * s->dv[j], 0.0);
    }
}

/* Mehrotra's start: the least-norm v with A_hat v = b and the least-norm z with A_hat^T y + z =
 * cost, each shifted into the interior by enough to make them positive and then by their mean
 * complementarity, so that the first iterate has the data's shape (large forces where the loads
 * are large) rather than a uniform one. One factorisation of A_hat A_hat^T. */
static bool mehrotra_start(Ipm *s, const double *b) {
    int N = s->N;
    for (int j = 0; j < N; j++) s->D[j] = 1.0;
    fill_g(s);
    if (!cn_cholmod_factor(s->G, &s->L, &s->c)) return false;
    if (!solve_factor(s, b, s->dy)) return false;
    mul_at(s, s->dy, s->v);
    mul_a(s, s->cost, s->rhs);
    if (!solve_factor(s, s->rhs, s->y)) return false;
    mul_at(s, s->y, s->z);
    for (int j = 0; j < N; j++) s->z[j] = s->cost[j] - s->z[j];
    double vmin = INFINITY, zmin = INFINITY;
    for (int j = 0; j < N; j++) vmin = fmin(vmin, s->v[j]), zmin = fmin(zmin, s->z[j]);
    double dv = fmax(-1.5 * vmin, 0), dz = fmax(-1.5 * zmin, 0);
    double vz = 0, sv = 0, sz = 0;
    for (int j = 0; j < N; j++) {
        double a = s->v[j] + dv, c = s->z[j] + dz;
        vz += a * c, sv += a, sz += c;
    }
    double hv = sz > 0 ? 0.5 * vz / sz : 0, hz = sv > 0 ? 0.5 * vz / sv : 0;
    for (int j = 0; j < N; j++) {
        s->v[j] += dv + hv;
        s->z[j] += dz + hz;
        if (!(s->v[j] > 0) || !(s->z[j] > 0)) return false;
    }
    return true;
}

/* One step of Mehrotra's predictor-corrector from the iterate in s (mu, gap its centring and
 * gap): false when the system cannot be factored or solved (the iterate is left as it is). */
static bool ipm_step(Ipm *s, double mu, double gap) {
    int N = s->N, m = s->m;
    for (int j = 0; j < N; j++) s->D[j] = s->v[j] / s->z[j];
    /* not positive definite in floating point (near the optimum, D spans many orders): the
     * slacks' diagonal raised a little, the refinement against the system itself making up for
     * it; failing that, the iterate reached so far is returned, for the caller to verify */
    s->reg = 0;
    fill_g(s);
    bool ok = cn_cholmod_factor(s->G, &s->L, &s->c);
    if (!ok) {
        double big = 0;
        for (int j = 0; j < N; j++) big = fmax(big, s->D[j]);
        for (int tries = 0; tries < CN_IPM_REG_TRIES && !ok; tries++) {
            s->reg = big * CN_IPM_REG * pow(100.0, tries);
            fill_g(s);
            ok = cn_cholmod_factor(s->G, &s->L, &s->c);
        }
    }
    if (!ok) return false;
    /* predictor: the affine direction */
    for (int j = 0; j < N; j++) s->rc[j] = -s->v[j] * s->z[j];
    if (!direction(s)) return false;
    double ap = fmin(1.0, max_step(s->v, s->dv, N)), ad = fmin(1.0, max_step(s->z, s->dz, N));
    double gaff = 0;
    for (int j = 0; j < N; j++) gaff += (s->v[j] + ap * s->dv[j]) * (s->z[j] + ad * s->dz[j]);
    double sigma = pow(gaff / gap, 3);
    /* corrector: centring and the second-order term */
    for (int j = 0; j < N; j++) s->rc[j] = sigma * mu - s->v[j] * s->z[j] - s->dv[j] * s->dz[j];
    /* rd and rp are unchanged; aty (= rc) was consumed above */
    if (!direction(s)) return false;
    ap = fmin(1.0, CN_IPM_STEP * max_step(s->v, s->dv, N));
    ad = fmin(1.0, CN_IPM_STEP * max_step(s->z, s->dz, N));
    for (int j = 0; j < N; j++) {
        s->v[j] += ap * s->dv[j];
        s->z[j] += ad * s->dz[j];
        if (!(s->v[j] > 0)) s->v[j] = 1e-300;
        if (!(s->z[j] > 0)) s->z[j] = 1e-300;
    }
    for (int i = 0; i < m; i++) s->y[i] += ad * s->dy[i];
    return true;
}

/* The answer of a run that stopped: converged, the last iterate (the optimum); stopped at a field,
 * that field; else the iterate nearest to a field (best_res its residual), polished. x and y
 * receive it; returns the elastic slacks' sum. */
static double ipm_answer(Ipm *s, const double *b, double bnorm, double best_res, cnLpIpmInfo *info, double *x,
                         double *y) {
    int N = s->N, m = s->m;
    double el = 0;
    for (int i = 0; i < m; i++) el += s->v[off_sp(s) + i] + s->v[off_sm(s) + i];
    bool finite = isfinite(el);
    for (int j = 0; j < s->n && finite; j++) finite = isfinite(s->v[j]);
    for (int i = 0; i < m && finite; i++) finite = isfinite(s->y[i]);
    if (finite) { /* else nothing: an overflowed iterate is no answer */
        /* converged, the last iterate is the optimum; stopped at a field, that field; else the
         * iterate nearest to a field */
        double last = info->field_stop ? 0 : field_residual(s, s->v, b) / (1 + bnorm), near = last;
        if (info->field_stop) memcpy(s->best, s->trial, sizeof(double) * (size_t)(s->n + s->nin)), el = 0;
        else if (!info->converged && best_res < last) near = best_res;
        else memcpy(s->best, s->v, sizeof(double) * (size_t)(s->n + s->nin));
        memcpy(x, s->best, sizeof(double) * (size_t)s->n);
        if (near > CN_IPM_TOL && near < CN_IPM_POLISH_FROM) {
            for (int j = s->n + s->nin; j < N; j++) s->best[j] = 0;
            field_polish(s, b, s->best);
            if (field_residual(s, s->best, b) / (1 + bnorm) < near) memcpy(x, s->best, sizeof(double) * (size_t)s->n);
        }
        memcpy(y, s->y, sizeof(double) * (size_t)m);
    } else {
        info->converged = false;
    }
    return el;
}

cnStatus cn_lp_ipm(const cnLpProblem *lp, double weight, double *x, double *y, cnLpIpmInfo *info, cnDiag *diag) {
    memset(info, 0, sizeof *info);
    Ipm s;
    memset(&s, 0, sizeof s);
    memset(x, 0, sizeof(double) * (size_t)lp->nvars);
    memset(y, 0, sizeof(double) * (size_t)(lp->neq + lp->nineq));
    s.lp = lp;
    s.n = lp->nvars, s.nin = lp->nineq, s.m = lp->neq + lp->nineq;
    s.N = s.n + s.nin + 2 * s.m;
    int N = s.N, m = s.m;
    if (m == 0 || s.n == 0) return CN_OK; /* nothing to solve: not converged, the caller falls back */
    double **nvecs[] = {&s.v, &s.z, &s.dv, &s.dz, &s.rd, &s.rc, &s.D, &s.cost, &s.scratch, &s.best, &s.trial};
    double **mvecs[] = {&s.y, &s.dy, &s.rp, &s.rhs, &s.res, &s.corr};
    bool ok = true;
    for (size_t i = 0; i < sizeof nvecs / sizeof nvecs[0]; i++) ok = ok && (*nvecs[i] = cn_calloc((size_t)N, sizeof(double)));
    for (size_t i = 0; i < sizeof mvecs / sizeof mvecs[0]; i++) ok = ok && (*mvecs[i] = cn_calloc((size_t)m, sizeof(double)));
    if (!ok) {
        ipm_free(&s);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory in the interior-point LP");
    }
    cn_cholmod_start(&s.c);
    s.started = true;
    if (!schur_groups(&s)) {
        ipm_free(&s);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory in the interior-point LP");
    }
    info->eliminated = s.schur;
    if (!build_g(&s)) {
        ipm_free(&s);
        return CN_OK;
    }
    const double *b = lp->rhs;
    for (int j = 0; j < s.n; j++) s.cost[j] = weight * (lp->cost ? lp->cost[j] : 0.0);
    for (int i = 0; i < m; i++) s.cost[off_sp(&s) + i] = s.cost[off_sm(&s) + i] = 1.0;
    double bnorm = inf_norm(b, m), cnorm = inf_norm(s.cost, N);
    if (!mehrotra_start(&s, b)) {
        /* the start: every variable and slack at the scale of the data */
        double start = fmax(1.0, bnorm);
        for (int j = 0; j < N; j++) s.v[j] = start, s.z[j] = 1.0;
        memset(s.y, 0, sizeof(double) * (size_t)m);
    }
    double *aty = s.rc; /* scratch before rc is needed */
    double best_res = INFINITY, best_pres = INFINITY, try_below = CN_IPM_POLISH_FROM;
    int stalled = 0, pstalled = 0, tries = 0;
    for (int it = 0; it < CN_IPM_MAX_ITER; it++) {
        info->iterations = it;
        mul_a(&s, s.v, s.rp);
        for (int i = 0; i < m; i++) s.rp[i] = b[i] - s.rp[i];
        mul_at(&s, s.y, aty);
        for (int j = 0; j < N; j++) s.rd[j] = s.cost[j] - aty[j] - s.z[j];
        double gap = 0, pobj = 0, dobj = 0;
        for (int j = 0; j < N; j++) gap += s.v[j] * s.z[j], pobj += s.cost[j] * s.v[j];
        for (int i = 0; i < m; i++) dobj += b[i] * s.y[i];
        double mu = gap / N;
        double pres = inf_norm(s.rp, m) / (1 + bnorm), dres = inf_norm(s.rd, N) / (1 + cnorm);
        info->objective = pobj;
        /* the forces alone (slacks dropped) as a static field: the iterate nearest to one is kept */
        double xr = field_residual(&s, s.v, b) / (1 + bnorm);
        bool better = xr < best_res * CN_IPM_BETTER;
        if (better) {
            best_res = xr;
            memcpy(s.best, s.v, sizeof(double) * (size_t)(s.n + s.nin));
        }
        if (pres <= CN_IPM_TOL && dres <= CN_IPM_TOL && gap <= CN_IPM_TOL * (1 + fabs(pobj))) {
            info->converged = true;
            break;
        }
        /* any field will do: this iterate's forces, projected onto equilibrium, may be one
         * already (the rest of the run would only lower their cost) */
        if (lp->any_field && tries < CN_IPM_FIELD_TRIES && xr < try_below) {
            tries++;
            try_below = xr * CN_IPM_FIELD_RETRY;
            memcpy(s.trial, s.v, sizeof(double) * (size_t)(s.n + s.nin));
            for (int j = s.n + s.nin; j < N; j++) s.trial[j] = 0;
            if (xr > CN_IPM_TOL) field_polish(&s, b, s.trial);
            if (field_residual(&s, s.trial, b) / (1 + bnorm) <= CN_IPM_TOL) {
                info->field_stop = true;
                break;
            }
        }
        if (!isfinite(mu) || !isfinite(pres) || !isfinite(dres)) break;
        /* near the optimum a badly scaled D can make the primal residual grow again: once the gap
         * has closed, a long run without a better field ends the search */
        bool closed = gap <= CN_IPM_TOL * (1 + fabs(pobj)) && dres <= CN_IPM_TOL;
        stalled = better || !closed ? 0 : stalled + 1;
        if (stalled >= CN_IPM_STALL && best_res < CN_IPM_POLISH_FROM) break;
        bool pbetter = pres < best_pres * CN_IPM_BETTER;
        if (pbetter) best_pres = pres;
        pstalled = pbetter || !closed ? 0 : pstalled + 1;
        if (pstalled >= CN_IPM_STALL && best_res >= CN_IPM_POLISH_FROM) break;
        if (!ipm_step(&s, mu, gap)) break;
    }
    double el = ipm_answer(&s, b, bnorm, best_res, info, x, y);
    info->elastic = el; /* stopped at a field: its slacks are zero */
    ipm_free(&s);
    return CN_OK;
}
