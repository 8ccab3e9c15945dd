/* solve: the LCP solvers' shared start and finish, and the LP backend (GLPK) behind one
 * interface. Private; includes only core. */
#ifndef CAIRN_SOLVE_H
#define CAIRN_SOLVE_H

#include <stdbool.h>
#include "core.h"
#include "cairn/lcp.h"

/* ---- LCP helpers (lcp_core.c) ---- */
/* Common start of a solve: the options with defaults filled in (tolerance, and the pivot budget
 * `default_budget` when none is set), and a cleared info (`*info` may be NULL on entry: it is
 * then pointed at `scratch`). */
cnLcpOptions cn_lcp_begin(const cnLcpOptions *opt, int default_budget, cnLcpInfo **info,
                          cnLcpInfo *scratch);
/* Clamp round-off negatives of z to zero, fill w = M z + q, and verify (relative tol). */
bool cn_lcp_finish(const cnLcp *p, double *z, double *w, double tol, double *residual);
/* The same with M's norm given: mnorm = cn_lcp_row_norm(p), the largest sum of a row's absolute
 * values (infinite when M holds a NaN or an infinity), for a solver that verifies one LCP more
 * than once. cn_lcp_residual_at likewise. */
double cn_lcp_row_norm(const cnLcp *p);
double cn_lcp_residual_at(const cnLcp *p, const double *z, double *w, double mnorm);
bool cn_lcp_finish_at(const cnLcp *p, double *z, double *w, double tol, double *residual, double mnorm);

/* ---- LP (lp_glpk.c; lp_ipm.c for the interior-point method) ---- */
/* Equilibrium LP: does a static contact-force solution exist? Sparse columns in the
 * CSC-like layout: for variable j, entries rows[colptr[j]..colptr[j+1]) with values vals.
 * Constraint rows 0..neq-1 are equalities (= rhs), rows neq..neq+nineq-1 are >= rhs.
 * All variables are >= 0. Minimises sum(cost_j x_j). Returns CN_OK and *feasible; x filled
 * when feasible. CN_ERR_NUMERIC when the LP solver fails. */
typedef struct cnLpProblem {
    int nvars, neq, nineq;
    const int *colptr, *rows;
    const double *vals;
    const double *rhs;
    const double *cost;
    bool interior;  /* solve by GLPK's interior-point method: *feasible = true when it finds an
                       optimum, false when it does not (which proves nothing: the caller falls
                       back to the simplex) */
    int method;     /* cnLpSimplex, for the simplex */
    bool short_budget; /* CN_LP_PRIMAL_AUTO stops after 2,000 + 20 (rows + columns) pivots (it
                          cycles on some small contact LPs): for callers with a fallback */
    bool any_field;    /* any static field will do, not only the cheapest: cn_lp_ipm may stop at
                          the first iterate whose forces are one (GLPK ignores it) */
} cnLpProblem;

/* How GLPK's simplex is run. Each gets some contact LPs wrong: the primal simplex
 * with GLPK's automatic (geometric-mean) scaling cycles, or reports a wrong optimum, when lever
 * arms carry 1e-17 rounding noise, but is the fastest on large LPs and handles 1e6 mass ratios;
 * with equilibration scaling only (CN_LP_DUAL_EQ) it is robust to the noise, and the dual
 * simplex used then for a non-elastic LP is too slow on large ones. Callers verify every answer
 * and go down a list. */
typedef enum cnLpSimplex { CN_LP_DUAL_EQ = 0, CN_LP_PRIMAL_AUTO = 1 } cnLpSimplex;
cnStatus cn_lp_solve(const cnLpProblem *lp, bool *feasible, double *x, cnDiag *diag);

/* The elastic LP of lp (its cost ignored): min sum |s| over x >= 0, A x + s = rhs (equations),
 * C x >= rhs (inequalities): always feasible, and by duality its optimum is the largest
 * rhs^T y over duals y (neq + nineq entries, |y_eq| <= 1, y_ineq >= 0) with A^T y + C^T y <= 0:
 * a Farkas certificate of infeasibility when positive. x receives its primal (nvars), y its
 * duals. lp->method says how (CN_LP_DUAL_EQ: the primal simplex, equilibrated). The caller
 * verifies both answers. */
cnStatus cn_lp_elastic(const cnLpProblem *lp, double *x, double *y, cnDiag *diag);

/* The interior-point method (lp_ipm.c, on CHOLMOD) for large LPs: the elastic LP of lp with lp's
 * cost kept at a small weight, min weight c.x + sum |s| over x >= 0, A x + s = rhs (equations),
 * C x + s >= rhs (inequalities). x receives its primal (nvars), y its duals (neq + nineq): a
 * force field when the slacks vanish; a Farkas certificate up to weight (A^T y <= weight c) when
 * they do not. Both are zero when it found nothing. It proves nothing by itself: the caller
 * verifies x as a force field or y as a certificate, and falls back to GLPK when neither
 * verifies. Returns an error only when out of memory. */
typedef struct cnLpIpmInfo {
    int iterations;
    bool converged;   /* residuals and gap within CN_IPM_TOL */
    double objective; /* weighted cost plus the elastic slacks */
    double elastic;   /* the slacks' sum: about 0 when the LP is feasible */
    bool field_stop;  /* stopped at a field before the optimum (lp->any_field): x is that field,
                         elastic 0, and y the duals of that iteration (no certificate) */
    bool eliminated;  /* the inequality rows were eliminated from the normal equations: each
                         column has an entry in at most one of them (cone rows) */
} cnLpIpmInfo;
/* The weights: for the forces (an exact penalty while the LP's optimal duals are below 1e6; the
 * cost is then met to about the method's tolerance / weight), and for a certificate (every
 * column may then resist by 1e-13 of its cost, below lp_certificate's 1e-6 / columns) */
#define CN_IPM_WEIGHT_FORCES 1e-6
#define CN_IPM_WEIGHT_CERTIFICATE 1e-13
cnStatus cn_lp_ipm(const cnLpProblem *lp, double weight, double *x, double *y, cnLpIpmInfo *info, cnDiag *diag);

/* A solution of an LP without inequality rows (A x = rhs, x >= 0) by descent: its rows in blocks
 * of `block` (at most 6: a body's equilibrium), met one block at a time in `order` (a
 * permutation of the neq / block blocks; a column's rows within one block must come together),
 * each for the columns no earlier block set, by
 * nonnegative least squares. *met: every block met to 1e-10 (scaled units); x then solves the
 * LP (the caller verifies it). False proves nothing (also when order or the columns are not as
 * required). Time and memory linear in the nonzeros.
 * CN_ERR_MEMORY when out of memory. */
cnStatus cn_lp_descent(const cnLpProblem *lp, int block, const int *order, double *x, bool *met);

/* The frictionless contact problem as a convex QP (Gauss's principle; qp_ipm.c, on CHOLMOD):
 * min 1/2 a^T M a - b^T a subject to J a >= 0, M block-diagonal (nb blocks of nd x nd, positive
 * definite), J sparse in compressed rows (K rows over nb * nd columns). Its solution is the
 * frictionless LCP's: accelerations a, contact forces f (the multipliers). a and f receive the
 * last iterate (zero when nothing was solved: a block not positive definite, the factorisation
 * failed); info->converged says whether the residuals met the method's tolerance. It proves
 * nothing by itself: the caller verifies the LCP's conditions. Returns an error only when out of
 * memory. */
typedef struct cnContactQp {
    int nb, nd, K;
    const double *mblk; /* nb blocks of nd x nd, row-major */
    const double *b;    /* nb * nd */
    const int *rowptr;  /* K + 1 */
    const int *col;
    const double *val;
} cnContactQp;
typedef struct cnQpIpmInfo {
    int iterations;
    bool converged;
    double residual; /* the largest of the relative residuals and the mean complementarity */
    bool polished;   /* not converged: the answer is the polish on the active set guessed */
    int moves;       /* the polish's corrections of that guess: contacts moved between held and
                      * free (a contact moved twice counts twice) */
} cnQpIpmInfo;
cnStatus cn_contact_qp_ipm(const cnContactQp *qp, double *a, double *f, cnQpIpmInfo *info, cnDiag *diag);

/* The numeric factorisation of G G^T into *L, after CHOLMOD's ordering and symbolic analysis when
 * *L is still NULL. The analysis is serialised: METIS, which CHOLMOD's default ordering calls,
 * seeds and draws from the C library's rand() and installs process-wide signal handlers for the
 * call. False when either fails (out of memory, or not positive definite in floating point). */
struct cholmod_sparse_struct;
struct cholmod_factor_struct;
struct cholmod_common_struct;
/* cholmod_start with cairn's settings: silent (statuses, no prints), LL^T, simplicial or
 * supernodal (BLAS) as the analysis finds the factor sparse or dense. With a multithreaded BLAS
 * the supernodal factor's last bits depend on its thread count, not on the run. */
void cn_cholmod_start(struct cholmod_common_struct *c);
bool cn_cholmod_factor(struct cholmod_sparse_struct *G, struct cholmod_factor_struct **L,
                       struct cholmod_common_struct *c);
/* x = (G G^T)^-1 b (n entries) with the factor L; false when CHOLMOD fails or x is not finite. */
bool cn_cholmod_solve(struct cholmod_factor_struct *L, const double *b, double *x, int n,
                      struct cholmod_common_struct *c);
/* Free the matrix and the factor (either may be NULL) and finish c. */
void cn_cholmod_finish(struct cholmod_sparse_struct **G, struct cholmod_factor_struct **L,
                       struct cholmod_common_struct *c);

/* A thread that used the LP backend is done with it: GLPK keeps an environment per thread
 * (Debian's GLPK is built with thread-local storage), which this frees. Call it at the end of a
 * worker thread only, when no GLPK problem of the thread is alive. */
void cn_lp_thread_end(void);
/* Run fn(ctx), which calls GLPK directly (the motion search keeps its own problem), under the
 * error hook: returns false when GLPK stopped on an internal error, after which every GLPK
 * problem of this thread is gone (fn's problem must not be deleted again) and what fn allocated
 * itself since its last store into ctx is lost. */
bool cn_lp_guarded_call(void (*fn)(void *ctx), void *ctx);
/* GLPK's internal errors (out of memory among them) caught on this thread so far: each ended its
 * call with CN_ERR_NUMERIC instead of GLPK's abort. */
long cn_lp_internal_errors(void);

#endif
