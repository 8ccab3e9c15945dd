/* The frictionless contact problem as the convex QP it is, by a primal-dual interior-point
 * method on CHOLMOD: for assemblies whose contact LCP is too large to hold dense.
 *
 * Gauss's principle of least constraint: the accelerations a of the frictionless LCP (Baraff;
 * paper eq. 1-2) are the unique minimiser of
 *     1/2 a^T M a - b^T a   subject to   J a >= 0,
 * with M the (block-diagonal, positive definite) mass matrix, b the external forces and J the
 * contacts' normal rows; the multipliers f >= 0 of J a >= 0 are the contact forces, and the
 * optimality conditions M a = b + J^T f, J a >= 0, f >= 0, f.(J a) = 0 are the LCP's. a = 0 is
 * always feasible and M is positive definite, so the optimum exists and is unique in a.
 *
 * With a slack s = J a >= 0, each iteration (Mehrotra's predictor-corrector) solves
 *     (M + J^T D J) da = r,   D = diag(f / s),
 * an nv x nv matrix (nv: the bodies' degrees of freedom) whose pattern is the contact graph's,
 * factorised as G G^T with G = [L_M, J^T D^(1/2)] (L_M: each body's Cholesky factor of its mass
 * block): ordering and symbolic analysis once, the numeric factorisation once per iteration.
 * The answer proves nothing by itself: the caller recomputes the accelerations from the forces
 * and verifies the LCP's conditions, as it verifies every LCP solution. */
#include <math.h>
#include <string.h>

#include <suitesparse/cholmod.h>

#include "solve.h"

/* Converged when the residuals are below this relative to the data (scaled: forces in weights,
 * accelerations in g) and the mean complementarity product below it. */
#define CN_QP_TOL 1e-12
/* ... and the largest min(slack, force) below this relative to the largest force (or 1). */
#define CN_QP_NAT_TOL 1e-11
/* The polish: its penalty (scaled units: M's blocks are about 1), its solves for the multipliers
 * (conjugate-gradient iterations) a round at most, and the closed contacts' relative
 * acceleration (in g) it stops at. */
#define CN_QP_POLISH_RHO 1e4 /* larger penalties leave larger residuals */
#define CN_QP_POLISH_ROUNDS 30
#define CN_QP_POLISH_TOL 1e-14
/* Corrections of the guessed active set at most, and how far (scaled: a force in weights, an
 * acceleration in g) a held contact must pull, or a free one close, to change the set: a tenth
 * of what the caller's verification (relative residual 1e-9) can see. With 0, the four points
 * of a 3-D face, whose forces are not unique, trade rounding-sized negative forces and the set
 * never settles. */
#define CN_QP_POLISH_SETS 8
#define CN_QP_POLISH_SET_TOL 1e-10
/* While the set may change, the multipliers are solved to this fraction of CN_QP_POLISH_SET_TOL
 * only (the full CN_QP_POLISH_TOL once it is settled): a round that changes the set needs only
 * the precision that shows the change. */
#define CN_QP_POLISH_SET_PRECISION 1e-2
/* The guess of the active set reads the last step's indicators (after El-Bakry, Tapia and Zhang,
 * SIAM Review 1994, on linear programs; the threshold below is cairn's): a contact that keeps a
 * force at the optimum keeps it from step to step (the ratio of its last two forces tends to 1),
 * one whose force vanishes loses it with the complementarity, by about the square root of its
 * reduction where the slack vanishes too (mu falling by 0.14 a step: forces falling by 0.38).
 * Such a contact, while its force is still above its slack, would be guessed held by that test
 * alone and then pulled in the polish, at the cost of rounds of corrections; the indicators leave
 * it out. A contact is guessed held when its force is above its slack and fell by less than the
 * geometric mean of 1 and that square root, (mu ratio)^(1/4); the indicator is read only when
 * the last step was not the first and cut mu to at most this fraction (else the force above the
 * slack decides). Early (a factorisation failing after a step or two) held contacts still lose
 * force and the guess can be too small to settle: then the polish starts again from the force
 * above the slack alone. */
#define CN_QP_INDICATOR_PROGRESS 0.5
/* Iterations before giving up (typical: 15-30). */
#define CN_QP_MAX_ITER 120
/* Fraction of the step to the boundary taken. */
#define CN_QP_STEP 0.995

typedef struct {
    const cnContactQp *qp;
    int nv, K;
    double *lm;                 /* nb blocks nd x nd: lower Cholesky factors of M's blocks */
    double *a, *s, *f;          /* iterate */
    double *da, *ds, *df;       /* direction */
    double *rd, *rp, *rc, *rhs; /* residuals, complementarity target, right-hand side */
    double *D, *tmp;
    double *fprev;  /* the forces before the last step */
    double mu_step; /* the mean complementarity before the last step (NaN: none) */
    int steps;      /* steps taken */
    int moves;      /* contacts the polish's corrections moved between held and free */
    char *guess;    /* polish_early's guess, whether the indicators gave it, whether it was tried */
    bool guessed, tried;
    double *sa, *sf; /* the iterate's a and f kept while polish_early tries */
    cholmod_common c;
    cholmod_sparse *G;
    cholmod_factor *L;
    bool started;
} Qp;

/* out = J x (K entries). */
static void mul_j(const cnContactQp *qp, const double *x, double *out) {
    for (int r = 0; r < qp->K; r++) {
        double v = 0;
        for (int t = qp->rowptr[r]; t < qp->rowptr[r + 1]; t++) v += qp->val[t] * x[qp->col[t]];
        out[r] = v;
    }
}

/* out = J^T y (nv entries). */
static void mul_jt(const cnContactQp *qp, int nv, const double *y, double *out) {
    memset(out, 0, sizeof(double) * (size_t)nv);
    for (int r = 0; r < qp->K; r++)
        for (int t = qp->rowptr[r]; t < qp->rowptr[r + 1]; t++) out[qp->col[t]] += qp->val[t] * y[r];
}

/* out = M x. */
static void mul_m(const cnContactQp *qp, const double *x, double *out) {
    int nd = qp->nd;
    for (int b = 0; b < qp->nb; b++) {
        const double *Mb = qp->mblk + (size_t)b * nd * nd;
        for (int i = 0; i < nd; i++) {
            double v = 0;
            for (int k = 0; k < nd; k++) v += Mb[i * nd + k] * x[(size_t)b * nd + k];
            out[(size_t)b * nd + i] = v;
        }
    }
}

static double inf_norm(const double *a, int n) {
    double r = 0;
    for (int i = 0; i < n; i++) r = fmax(r, fabs(a[i]));
    return r;
}

/* G's pattern: L_M's blocks (column j of body b: rows j..end of the block), then J's rows as
 * columns. Unsorted within a column is allowed; these come sorted only for the blocks. */
static bool build_g(Qp *s) {
    const cnContactQp *qp = s->qp;
    int nd = qp->nd, nv = s->nv, K = s->K;
    size_t nnz = (size_t)qp->nb * (size_t)(nd * (nd + 1) / 2) + (size_t)qp->rowptr[K];
    s->G = cholmod_allocate_sparse((size_t)nv, (size_t)(nv + K), nnz, 0, 1, 0, CHOLMOD_REAL, &s->c);
    if (!s->G) return false;
    int *p = s->G->p, *ri = s->G->i;
    double *gx = s->G->x;
    int k = 0;
    for (int j = 0; j < nv; j++) {
        int b = j / nd, jl = j % nd;
        p[j] = k;
        for (int i = jl; i < nd; i++) {
            ri[k] = b * nd + i;
            gx[k++] = s->lm[(size_t)b * nd * nd + i * nd + jl];
        }
    }
    for (int r = 0; r < K; r++) {
        p[nv + r] = k;
        for (int t = qp->rowptr[r]; t < qp->rowptr[r + 1]; t++) ri[k++] = qp->col[t];
    }
    p[nv + K] = k;
    return true;
}

/* J^T D^(1/2)'s values in G (the blocks stay). */
static void fill_g(Qp *s) {
    const cnContactQp *qp = s->qp;
    int *p = s->G->p;
    double *gx = s->G->x;
    for (int r = 0; r < s->K; r++) {
        double d = sqrt(s->D[r]);
        int k = p[s->nv + r];
        for (int t = qp->rowptr[r]; t < qp->rowptr[r + 1]; t++) gx[k++] = qp->val[t] * d;
    }
}

/* out = H^-1 rhs with the current factor of H = G G^T; false when that fails or overflows. */
static bool solve_h(Qp *s, double *out) {
    return cn_cholmod_solve(s->L, s->rhs, out, s->nv, &s->c);
}

/* The Newton direction for the complementarity target rc: da, ds, df. */
static bool direction(Qp *s) {
    int nv = s->nv, K = s->K;
    /* (M + J^T D J) da = -rd + J^T (rc / s - D rp) */
    for (int r = 0; r < K; r++) s->tmp[r] = s->rc[r] / s->s[r] - s->D[r] * s->rp[r];
    mul_jt(s->qp, nv, s->tmp, s->rhs);
    for (int j = 0; j < nv; j++) s->rhs[j] -= s->rd[j];
    if (!solve_h(s, s->da)) return false;
    /* ds = J da + rp; df = rc / s - D ds */
    mul_j(s->qp, s->da, s->ds);
    for (int r = 0; r < K; r++) {
        s->ds[r] += s->rp[r];
        s->df[r] = s->rc[r] / s->s[r] - s->D[r] * s->ds[r];
    }
    return true;
}

static double max_step(const double *x, const double *dx, int n, double a) {
    for (int j = 0; j < n; j++)
        if (dx[j] < 0) a = fmin(a, -x[j] / dx[j]);
    return a;
}

/* Polish (as OSQP does): a contact near the boundary of being active has its slack and force
 * both near sqrt(mu), which the iterations reduce slowly, and the factorisation fails before
 * they are small. So the active set is guessed from the last iterate (see
 * CN_QP_INDICATOR_PROGRESS), and
 * the problem with those contacts held closed and the others left out, min 1/2 a^T M a - b^T a
 * with J_A a = 0, is solved by the method of multipliers on one factorisation of
 * M + rho J_A^T J_A. The result is the QP's solution when the guess is right, which the caller's
 * verification decides. */
/* a = H^-1 (b + J_A^T f_A), H = M + rho J_A^T J_A (its current factor) */
static bool accel_from_forces(Qp *s) {
    mul_jt(s->qp, s->nv, s->f, s->rhs);
    for (int j = 0; j < s->nv; j++) s->rhs[j] += s->qp->b[j];
    return solve_h(s, s->a);
}

static bool polish_once(Qp *s, double tol, bool factorise) {
    const cnContactQp *qp = s->qp;
    int nv = s->nv, K = s->K;
    if (factorise) {
        fill_g(s);
        if (!cholmod_factorize(s->G, s->L, &s->c) || s->c.status != CHOLMOD_OK) return false;
    }
    if (!accel_from_forces(s)) return false;
    /* The multipliers solve S f_A = -J_A H^-1 b with S = J_A H^-1 J_A^T (then J_A a = 0), by
     * conjugate gradients on S (positive semidefinite, its right-hand side in its range): one
     * solve with H per iteration, as the plain multiplier update f_A -= rho J_A a, which
     * converged at 0.66 to 0.92 per iteration on a barrel vault and stopped at its round limit.
     * r = -J_A a (the residual), p the direction (ds), q = S p (df), H^-1 J_A^T p in da. */
    double *r = s->tmp, *p = s->ds, *q = s->df;
    mul_j(qp, s->a, r);
    double rr = 0, viol = 0;
    for (int k = 0; k < K; k++) {
        r[k] = s->D[k] > 0 ? -r[k] : 0;
        p[k] = r[k];
        rr += r[k] * r[k];
        viol = fmax(viol, fabs(r[k]));
    }
    for (int it = 0; it < CN_QP_POLISH_ROUNDS && viol > tol; it++) {
        mul_jt(qp, nv, p, s->rhs);
        if (!solve_h(s, s->da)) return false;
        mul_j(qp, s->da, q);
        double pq = 0;
        for (int k = 0; k < K; k++) {
            if (!(s->D[k] > 0)) q[k] = 0;
            pq += p[k] * q[k];
        }
        if (!(pq > 0)) break; /* S p = 0: nothing more to gain along p (or NaN) */
        double al = rr / pq, rr2 = 0;
        viol = 0;
        for (int j = 0; j < nv; j++) s->a[j] += al * s->da[j];
        for (int k = 0; k < K; k++) {
            s->f[k] += al * p[k];
            r[k] -= al * q[k];
            rr2 += r[k] * r[k];
            viol = fmax(viol, fabs(r[k]));
        }
        double be = rr2 / rr;
        rr = rr2;
        for (int k = 0; k < K; k++) p[k] = r[k] + be * p[k];
    }
    return accel_from_forces(s); /* again: the recurrences drift by rounding */
}

/* The indicators' threshold for the last step (0: the indicators are not read), from the mean
 * complementarity now (mu) and before the step (CN_QP_INDICATOR_PROGRESS). */
static double indicator_keep(const Qp *s, double mu) {
    double cut = mu / s->mu_step; /* NaN or 1 and more: no step, or no progress */
    return s->steps >= 2 && cut <= CN_QP_INDICATOR_PROGRESS ? pow(cut, 0.25) : 0;
}

/* Held in the guess: force above slack and, with keep > 0, not below keep times the force
 * before the last step. */
static bool guessed_held(const Qp *s, int r, double keep) {
    return s->f[r] > s->s[r] && s->f[r] >= keep * s->fprev[r];
}

/* The active set guessed from the last iterate, then corrected (a held contact that pulls leaves
 * it, a free one that the motion closes joins it) while that changes anything, rounds times at
 * most, each on its own factorisation. *settled: the last correction changed nothing (the set's
 * factorisation is then the current one). */
static bool settle_set(Qp *s, double keep, int rounds, bool *settled) {
    int K = s->K;
    for (int r = 0; r < K; r++) {
        bool active = guessed_held(s, r, keep);
        s->D[r] = active ? CN_QP_POLISH_RHO : 0;
        if (!active) s->f[r] = 0;
    }
    bool changed = true;
    for (int round = 0; round < rounds && changed; round++) {
        /* a set that changes needs only the precision that says so */
        if (!polish_once(s, CN_QP_POLISH_SET_TOL * CN_QP_POLISH_SET_PRECISION, true)) return false;
        mul_j(s->qp, s->a, s->tmp);
        changed = false;
        for (int r = 0; r < K; r++) {
            double pull = -s->f[r], close = -s->tmp[r];
            if (s->D[r] > 0 && pull > CN_QP_POLISH_SET_TOL) s->D[r] = 0, s->f[r] = 0, changed = true, s->moves++;
            else if (s->D[r] == 0 && close > CN_QP_POLISH_SET_TOL)
                s->D[r] = CN_QP_POLISH_RHO, changed = true, s->moves++;
        }
    }
    *settled = !changed;
    return true;
}

/* The last set to the full precision (on its factorisation when it settled). The forces returned
 * are the ones a satisfies: M a = b + J_A^T f - rho J_A^T J_A a, so each held contact's force is
 * f - rho (J a) (rho times J a, rounding-sized when the conjugate gradients converged: left out,
 * the LCP's residual reached 1.5e-11 on the small stacks of test_sparse_motion, against 4e-13). */
static bool finish_set(Qp *s, bool settled) {
    if (!polish_once(s, CN_QP_POLISH_TOL, !settled)) return false;
    mul_j(s->qp, s->a, s->tmp);
    for (int r = 0; r < s->K; r++) s->f[r] = s->D[r] > 0 ? s->f[r] - s->D[r] * s->tmp[r] : 0;
    return true;
}

/* After finish_set (J a in tmp): the held contacts closed and pushing, the free ones not
 * closing, each within CN_QP_POLISH_SET_TOL (the conjugate gradients may stop at their round
 * limit short of CN_QP_POLISH_TOL). */
static bool answer_holds(const Qp *s) {
    for (int r = 0; r < s->K; r++) {
        bool ok = s->D[r] > 0 ? s->f[r] >= -CN_QP_POLISH_SET_TOL && fabs(s->tmp[r]) <= CN_QP_POLISH_SET_TOL
                              : s->tmp[r] >= -CN_QP_POLISH_SET_TOL;
        if (!ok) return false;
    }
    return true;
}

static bool polish_from(Qp *s, double keep, bool *settled) {
    return settle_set(s, keep, CN_QP_POLISH_SETS, settled) && finish_set(s, *settled);
}

/* The polish from the indicators' guess (CN_QP_INDICATOR_PROGRESS) and, when that does not
 * settle, again from the force above the slack alone (the iterate's forces kept in sf, as
 * polish_early keeps them). */
static bool polish(Qp *s) {
    int K = s->K;
    double mu = 0;
    for (int r = 0; r < K; r++) mu += s->s[r] * s->f[r];
    double keep = K > 0 ? indicator_keep(s, mu / K) : 0;
    bool settled = false;
    if (keep > 0) {
        memcpy(s->sf, s->f, sizeof(double) * (size_t)K);
        if (!polish_from(s, keep, &settled)) return false;
        if (settled) return true;
        memcpy(s->f, s->sf, sizeof(double) * (size_t)K);
    }
    return polish_from(s, 0, &settled);
}

/* The polish tried during the run, on the indicators' guess once it is the same two steps
 * running (both read by the indicators: s->guess is the last step's, s->guessed says whether it
 * was; s->tried whether this guess was tried already). One round: when it changes nothing and
 * the answer at full precision holds (answer_holds), the answer is the polish's (true) and the
 * steps left are saved (they change neither the guess nor, but for rounding, the polish's
 * answer); else the iterate is restored (from sa, sf) and the run goes on, the guess not tried
 * again until it changes. A try takes one factorisation, as a step does. */
static bool polish_early(Qp *s, double mu) {
    double keep = indicator_keep(s, mu);
    if (keep == 0) {
        s->guessed = false;
        return false;
    }
    int changes = 0;
    for (int r = 0; r < s->K; r++) {
        char held = guessed_held(s, r, keep);
        changes += held != s->guess[r];
        s->guess[r] = held;
    }
    bool repeat = s->guessed && changes == 0;
    s->guessed = true;
    if (!repeat) s->tried = false;
    if (!repeat || s->tried || !s->L) return false;
    s->tried = true;
    memcpy(s->sa, s->a, sizeof(double) * (size_t)s->nv);
    memcpy(s->sf, s->f, sizeof(double) * (size_t)s->K);
    int moves = s->moves;
    bool settled = false;
    if (settle_set(s, keep, 1, &settled) && settled && finish_set(s, true) && answer_holds(s)) return true;
    memcpy(s->a, s->sa, sizeof(double) * (size_t)s->nv);
    memcpy(s->f, s->sf, sizeof(double) * (size_t)s->K);
    s->moves = moves;
    return false;
}

static void qp_free(Qp *s) {
    double **arrs[] = {&s->lm, &s->a, &s->s, &s->f, &s->da, &s->ds, &s->df, &s->rd,
                       &s->rp, &s->rc, &s->rhs, &s->D, &s->tmp, &s->fprev, &s->sa, &s->sf};
    for (size_t i = 0; i < sizeof arrs / sizeof arrs[0]; i++) cn_free(*arrs[i]), *arrs[i] = NULL;
    cn_free(s->guess), s->guess = NULL;
    if (s->started) cn_cholmod_finish(&s->G, &s->L, &s->c);
}

cnStatus cn_contact_qp_ipm(const cnContactQp *qp, double *a, double *f, cnQpIpmInfo *info, cnDiag *diag) {
    memset(info, 0, sizeof *info);
    Qp s;
    memset(&s, 0, sizeof s);
    s.mu_step = NAN;
    s.qp = qp;
    int nd = qp->nd, nv = s.nv = qp->nb * qp->nd, K = s.K = qp->K;
    memset(a, 0, sizeof(double) * (size_t)nv);
    memset(f, 0, sizeof(double) * (size_t)K);
    if (nv == 0) return CN_OK;
    double **vvecs[] = {&s.a, &s.da, &s.rd, &s.rhs, &s.sa};
    double **kvecs[] = {&s.s, &s.f, &s.ds, &s.df, &s.rp, &s.rc, &s.D, &s.tmp, &s.fprev, &s.sf};
    bool ok = (s.lm = cn_malloc(sizeof(double) * ((size_t)nv * nd + 1))) != NULL;
    ok = ok && (s.guess = cn_calloc((size_t)K + 1, 1));
    for (size_t i = 0; i < sizeof vvecs / sizeof vvecs[0]; i++) ok = ok && (*vvecs[i] = cn_calloc((size_t)nv + 1, sizeof(double)));
    for (size_t i = 0; i < sizeof kvecs / sizeof kvecs[0]; i++) ok = ok && (*kvecs[i] = cn_calloc((size_t)K + 1, sizeof(double)));
    if (!ok) {
        qp_free(&s);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory in the interior-point QP");
    }
    /* each body's mass block: positive definite, or nothing is solved */
    memcpy(s.lm, qp->mblk, sizeof(double) * (size_t)nv * nd);
    for (int b = 0; b < qp->nb; b++)
        if (cn_chol_factor(s.lm + (size_t)b * nd * nd, nd, 1e-12) != 0) {
            qp_free(&s);
            return CN_OK;
        }
    cn_cholmod_start(&s.c);
    s.started = true;
    if (!build_g(&s)) {
        qp_free(&s);
        return CN_OK;
    }
    double bnorm = inf_norm(qp->b, nv);
    /* the start: at rest, every contact's slack and force at the scale of the data */
    double start = fmax(1.0, bnorm);
    for (int r = 0; r < K; r++) s.s[r] = start, s.f[r] = start;
    for (int it = 0; it < CN_QP_MAX_ITER; it++) {
        info->iterations = it; /* completed */
        /* rd = M a - b - J^T f; rp = J a - s */
        mul_m(qp, s.a, s.rd);
        mul_jt(qp, nv, s.f, s.rhs);
        for (int j = 0; j < nv; j++) s.rd[j] -= qp->b[j] + s.rhs[j];
        mul_j(qp, s.a, s.rp);
        for (int r = 0; r < K; r++) s.rp[r] -= s.s[r];
        double gap = 0, nat = 0, fbig = 1;
        for (int r = 0; r < K; r++) {
            gap += s.s[r] * s.f[r];
            nat = fmax(nat, fmin(s.s[r], s.f[r]));
            fbig = fmax(fbig, s.f[r]);
        }
        double mu = K > 0 ? gap / K : 0;
        double dres = inf_norm(s.rd, nv) / (1 + bnorm), pres = inf_norm(s.rp, K) / (1 + inf_norm(s.s, K));
        info->residual = fmax(dres, fmax(pres, mu));
        /* the natural residual too: a contact at the boundary of being active (its slack and
         * force both tend to 0) has both near sqrt(mu) */
        if (dres <= CN_QP_TOL && pres <= CN_QP_TOL && mu <= CN_QP_TOL && nat <= CN_QP_NAT_TOL * fbig) {
            info->converged = true;
            break;
        }
        if (!isfinite(mu) || !isfinite(dres) || !isfinite(pres)) break;
        if (polish_early(&s, mu)) {
            info->polished = true;
            break;
        }
        for (int r = 0; r < K; r++) s.D[r] = s.f[r] / s.s[r];
        fill_g(&s);
        /* not positive definite in floating point (near the optimum, where D spans many orders):
         * the polish takes over from the last iterate */
        if (!cn_cholmod_factor(s.G, &s.L, &s.c)) break;
        /* predictor */
        for (int r = 0; r < K; r++) s.rc[r] = -s.s[r] * s.f[r];
        if (!direction(&s)) break;
        double al = fmin(max_step(s.s, s.ds, K, 1.0), max_step(s.f, s.df, K, 1.0));
        double gaff = 0;
        for (int r = 0; r < K; r++) gaff += (s.s[r] + al * s.ds[r]) * (s.f[r] + al * s.df[r]);
        double sigma = gap > 0 ? pow(gaff / gap, 3) : 0;
        /* corrector */
        for (int r = 0; r < K; r++) s.rc[r] = sigma * mu - s.s[r] * s.f[r] - s.ds[r] * s.df[r];
        if (!direction(&s)) break;
        /* one step length for both: a and f are tied by M a = b + J^T f */
        al = fmin(1.0, CN_QP_STEP * fmin(max_step(s.s, s.ds, K, INFINITY), max_step(s.f, s.df, K, INFINITY)));
        for (int j = 0; j < nv; j++) s.a[j] += al * s.da[j];
        memcpy(s.fprev, s.f, sizeof(double) * (size_t)K);
        s.mu_step = mu;
        s.steps++;
        for (int r = 0; r < K; r++) {
            s.s[r] += al * s.ds[r];
            s.f[r] += al * s.df[r];
            if (!(s.s[r] > 0)) s.s[r] = 1e-300;
            if (!(s.f[r] > 0)) s.f[r] = 1e-300;
        }
    }
    if (!info->converged && !info->polished && s.L) info->polished = polish(&s);
    info->moves = s.moves;
    bool finite = true;
    for (int j = 0; j < nv && finite; j++) finite = isfinite(s.a[j]);
    for (int r = 0; r < K && finite; r++) finite = isfinite(s.f[r]);
    if (finite) { /* an overflowed iterate is no answer */
        memcpy(a, s.a, sizeof(double) * (size_t)nv);
        memcpy(f, s.f, sizeof(double) * (size_t)K);
    } else {
        info->converged = false;
    }
    qp_free(&s);
    return CN_OK;
}
