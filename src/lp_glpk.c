/* Linear programs through GLPK (Debian libglpk): used for the static-equilibrium decision and for
 * LCP feasibility. The rows are expected to be scaled by the caller to unit size. */
#include <glpk.h>
#include <math.h>

#include "internal.h"

static int silent(void *info, const char *s) {
    (void)info;
    (void)s;
    return 1; /* GLPK prints nothing */
}

cnStatus cn_lp_solve(const cnLpProblem *lp, bool *feasible, double *x, cnDiag *diag) {
    glp_term_hook(silent, NULL);
    glp_prob *P = glp_create_prob();
    int m = lp->neq + lp->nineq;
    int n = lp->nvars;
    glp_set_obj_dir(P, GLP_MIN);
    if (m > 0) glp_add_rows(P, m);
    if (n > 0) glp_add_cols(P, n);
    for (int i = 0; i < m; i++)
        glp_set_row_bnds(P, i + 1, i < lp->neq ? GLP_FX : GLP_LO, lp->rhs[i], lp->rhs[i]);
    int nnz = n > 0 ? lp->colptr[n] : 0;
    int *ia = cn_malloc(sizeof(int) * (size_t)(nnz + 1));
    int *ja = cn_malloc(sizeof(int) * (size_t)(nnz + 1));
    double *ar = cn_malloc(sizeof(double) * (size_t)(nnz + 1));
    if (!ia || !ja || !ar) {
        cn_free(ia);
        cn_free(ja);
        cn_free(ar);
        glp_delete_prob(P);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the LP");
    }
    int k = 1;
    for (int j = 0; j < n; j++) {
        glp_set_col_bnds(P, j + 1, GLP_LO, 0.0, 0.0);
        glp_set_obj_coef(P, j + 1, lp->cost ? lp->cost[j] : 0.0);
        for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) {
            ia[k] = lp->rows[t] + 1;
            ja[k] = j + 1;
            ar[k] = lp->vals[t];
            k++;
        }
    }
    if (nnz > 0) glp_load_matrix(P, nnz, ia, ja, ar);
    cn_free(ia);
    cn_free(ja);
    cn_free(ar);

    if (lp->interior) {
        /* large sparse problems: 30x faster than the simplex on a 1,000-brick wall with
         * friction; the caller verifies the solution (and falls back when there is none) */
        glp_iptcp ip;
        glp_init_iptcp(&ip);
        ip.msg_lev = GLP_MSG_OFF;
        int rc = glp_interior(P, &ip);
        *feasible = rc == 0 && glp_ipt_status(P) == GLP_OPT;
        for (int j = 0; *feasible && j < n; j++) x[j] = glp_ipt_col_prim(P, j + 1);
        glp_delete_prob(P);
        return CN_OK;
    }
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.presolve = GLP_OFF;
    parm.it_lim = 100000 + 50 * (m + n);
    glp_scale_prob(P, GLP_SF_AUTO);
    glp_adv_basis(P, 0);
    int rc = glp_simplex(P, &parm);
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
