/* Linear programs through GLPK (Debian libglpk): used for the static-equilibrium decision and for
 * LCP feasibility. The rows are expected to be scaled by the caller to unit size. */
#include <glpk.h>
#include <math.h>
#include <setjmp.h>

#include "solve.h"

void cn_lp_thread_end(void) { glp_free_env(); }

static int silent(void *info, const char *s) {
    (void)info;
    (void)s;
    return 1; /* GLPK prints nothing */
}

/* Every coefficient, right-hand side and cost finite: GLPK aborts the process on an infinite
 * one (in its scaling: masses 1e-160 and 1e160 stacked give rows that overflow). */
static bool all_finite(const cnLpProblem *lp) {
    int m = lp->neq + lp->nineq, n = lp->nvars;
    for (int i = 0; i < m; i++)
        if (!isfinite(lp->rhs[i])) return false;
    for (int j = 0; j < n; j++) {
        if (lp->cost && !isfinite(lp->cost[j])) return false;
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
            if (!isfinite(lp->vals[t])) return false;
    }
    return true;
}

/* GLPK's copy of lp: its rows, its columns x >= 0 with lp's cost, and when elastic (cost
 * ignored) the slacks s+ and s- of every equation at cost 1. NULL when out of memory. */
/* The matrix's index arrays while build() hands them to GLPK, kept where the error hook's jump
 * (guarded) can free them. */
static _Thread_local void *build_arrays[3];

static void build_arrays_free(void) {
    for (int i = 0; i < 3; i++) cn_free(build_arrays[i]), build_arrays[i] = NULL;
}

static glp_prob *build(const cnLpProblem *lp, bool elastic) {
    glp_term_hook(silent, NULL);
    int m = lp->neq + lp->nineq, n = lp->nvars, ns = elastic ? 2 * lp->neq : 0;
    int nnz = (n > 0 ? lp->colptr[n] : 0) + ns;
    int *ia = build_arrays[0] = cn_malloc(sizeof(int) * (size_t)(nnz + 1));
    int *ja = build_arrays[1] = cn_malloc(sizeof(int) * (size_t)(nnz + 1));
    double *ar = build_arrays[2] = cn_malloc(sizeof(double) * (size_t)(nnz + 1));
    glp_prob *P = NULL;
    if (ia && ja && ar) {
        P = glp_create_prob();
        glp_set_obj_dir(P, GLP_MIN);
        if (m > 0) glp_add_rows(P, m);
        if (n + ns > 0) glp_add_cols(P, n + ns);
        for (int i = 0; i < m; i++)
            glp_set_row_bnds(P, i + 1, i < lp->neq ? GLP_FX : GLP_LO, lp->rhs[i], lp->rhs[i]);
        int k = 1;
        for (int j = 0; j < n; j++) {
            glp_set_col_bnds(P, j + 1, GLP_LO, 0.0, 0.0);
            glp_set_obj_coef(P, j + 1, !elastic && lp->cost ? lp->cost[j] : 0.0);
            for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++)
                ia[k] = lp->rows[t] + 1, ja[k] = j + 1, ar[k] = lp->vals[t], k++;
        }
        for (int c = 0; c < ns; c++) {
            int col = n + c + 1;
            glp_set_col_bnds(P, col, GLP_LO, 0.0, 0.0);
            glp_set_obj_coef(P, col, 1.0);
            ia[k] = c / 2 + 1, ja[k] = col, ar[k] = c % 2 ? -1.0 : 1.0, k++;
        }
        if (nnz > 0) glp_load_matrix(P, nnz, ia, ja, ar);
    }
    build_arrays_free();
    return P;
}

/* The simplex as lp->method says (see cnLpSimplex); GLPK's return code. */
static int simplex(glp_prob *P, const cnLpProblem *lp, bool elastic) {
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.presolve = GLP_OFF;
    int size = glp_get_num_rows(P) + glp_get_num_cols(P);
    parm.it_lim = 100000 + 50 * size;
    /* the primal simplex with automatic scaling cycles on some small contact LPs (to the limit
     * of 1e5 pivots, on 30 rows); the others (contact LPs take a few pivots per row) stop far
     * below this, and a cycling one gives way to the next method quickly */
    if (lp->method == CN_LP_PRIMAL_AUTO && !elastic && lp->short_budget)
        parm.it_lim = 2000 + 20 * size;
    /* CN_LP_DUAL_EQ: the dual simplex (with costs >= 0 the starting basis is dual feasible;
     * the primal simplex can cycle to the iteration limit, 1e5 pivots on 30 rows, on contact
     * LPs whose lever arms carry 1e-17 rounding noise), except for the elastic LP, whose slacks
     * are a feasible start for the primal; and equilibration only (the geometric-mean scaling is
     * thrown by such entries, and the simplex then reports a wrong optimum) */
    if (lp->method == CN_LP_DUAL_EQ && !elastic) parm.meth = GLP_DUALP;
    glp_scale_prob(P, lp->method == CN_LP_DUAL_EQ ? GLP_SF_EQ : GLP_SF_AUTO);
    glp_adv_basis(P, 0);
    return glp_simplex(P, &parm);
}

static cnStatus no_memory(cnDiag *diag) {
    return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the LP");
}

static cnStatus not_finite(cnDiag *diag) {
    return cn_diag_set(diag, CN_ERR_NUMERIC, "",
                       "a coefficient of the equilibrium LP overflows double precision (masses, "
                       "sizes or gravity about 1e300 apart): no verdict at this scale");
}

static cnStatus lp_solve(const cnLpProblem *lp, bool *feasible, double *x, cnDiag *diag) {
    int m = lp->neq + lp->nineq, n = lp->nvars;
    if (!all_finite(lp)) return not_finite(diag);
    glp_prob *P = build(lp, false);
    if (!P) return no_memory(diag);
    if (lp->interior) {
        /* large sparse problems, where it is much faster than the simplex; the caller verifies
         * the solution (and falls back when there is none) */
        glp_iptcp ip;
        glp_init_iptcp(&ip);
        ip.msg_lev = GLP_MSG_OFF;
        int rc = glp_interior(P, &ip);
        *feasible = rc == 0 && glp_ipt_status(P) == GLP_OPT;
        for (int j = 0; *feasible && j < n; j++) x[j] = glp_ipt_col_prim(P, j + 1);
        glp_delete_prob(P);
        return CN_OK;
    }
    int rc = simplex(P, lp, false);
    cnStatus st = CN_OK;
    if (rc != 0) {
        st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                         "the LP solver (GLPK) failed with code %d on an LP of %d rows and %d "
                         "columns",
                         rc, m, n);
    } else {
        int ps = glp_get_prim_stat(P);
        int status = glp_get_status(P);
        if (status == GLP_OPT || status == GLP_FEAS) {
            *feasible = true;
            for (int j = 0; j < n; j++) x[j] = glp_get_col_prim(P, j + 1);
        } else if (ps == GLP_NOFEAS || status == GLP_NOFEAS || status == GLP_INFEAS) {
            *feasible = false;
        } else if (status == GLP_UNBND) {
            *feasible = true; /* only with a cost; feasibility holds */
            for (int j = 0; j < n; j++) x[j] = glp_get_col_prim(P, j + 1);
        } else {
            st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                             "the LP solver (GLPK) ended undecided (status %d)", status);
        }
    }
    glp_delete_prob(P);
    return st;
}

static cnStatus lp_elastic(const cnLpProblem *lp, double *x, double *y, cnDiag *diag) {
    int m = lp->neq + lp->nineq, n = lp->nvars;
    if (!all_finite(lp)) return not_finite(diag);
    glp_prob *P = build(lp, true);
    if (!P) return no_memory(diag);
    int rc = simplex(P, lp, true);
    cnStatus st = CN_OK;
    if (rc != 0 || glp_get_status(P) != GLP_OPT) {
        st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                         "the elastic LP (GLPK) ended with code %d, status %d, on %d rows and %d "
                         "columns",
                         rc, glp_get_status(P), m, n + 2 * lp->neq);
    } else {
        for (int j = 0; j < n; j++) x[j] = glp_get_col_prim(P, j + 1);
        for (int i = 0; i < m; i++) y[i] = glp_get_row_dual(P, i + 1);
    }
    glp_delete_prob(P);
    return st;
}

/* GLPK ends the process (abort) on an internal error, running out of memory among them, unless
 * its error hook jumps out; then every GLPK object of this thread is freed with its environment
 * (glp_free_env), with the matrix's index arrays if build() was handing them over, and the next
 * call starts afresh. */
static _Thread_local jmp_buf *glpk_escape;
static _Thread_local long glpk_errors;

long cn_lp_internal_errors(void) { return glpk_errors; }

static void glpk_error(void *info) {
    (void)info;
    if (glpk_escape) longjmp(*glpk_escape, 1);
}

static cnStatus guarded(const cnLpProblem *lp, bool elastic, bool *feasible, double *x, double *y,
                        cnDiag *diag) {
    jmp_buf jb;
    if (setjmp(jb)) {
        glpk_escape = NULL;
        glpk_errors++;
        glp_free_env();
        build_arrays_free();
        return cn_diag_set(diag, CN_ERR_NUMERIC, "",
                           "the LP solver (GLPK) stopped on an internal error (out of memory, or "
                           "numbers it cannot scale) on an LP of %d rows and %d columns; no verdict",
                           lp->neq + lp->nineq, lp->nvars);
    }
    glpk_escape = &jb;
    glp_error_hook(glpk_error, NULL);
    cnStatus s = elastic ? lp_elastic(lp, x, y, diag) : lp_solve(lp, feasible, x, diag);
    glp_error_hook(NULL, NULL);
    glpk_escape = NULL;
    return s;
}

bool cn_lp_guarded_call(void (*fn)(void *ctx), void *ctx) {
    jmp_buf jb;
    if (setjmp(jb)) {
        glpk_escape = NULL;
        glpk_errors++;
        glp_free_env();
        return false;
    }
    glpk_escape = &jb;
    glp_error_hook(glpk_error, NULL);
    fn(ctx);
    glp_error_hook(NULL, NULL);
    glpk_escape = NULL;
    return true;
}

cnStatus cn_lp_solve(const cnLpProblem *lp, bool *feasible, double *x, cnDiag *diag) {
    return guarded(lp, false, feasible, x, NULL, diag);
}

cnStatus cn_lp_elastic(const cnLpProblem *lp, double *x, double *y, cnDiag *diag) {
    return guarded(lp, true, NULL, x, y, diag);
}
