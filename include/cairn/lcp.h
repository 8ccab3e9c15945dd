/* cairn: linear complementarity problems and their solvers.
 *
 * LCP(M, q): find z >= 0 with w = M z + q >= 0 and z^T w = 0. */
#ifndef CAIRN_LCP_H
#define CAIRN_LCP_H

#include "cairn/export.h"

#include <stdbool.h>
#include <stdio.h>

#include "cairn/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A dense LCP. M is row-major n x n. The struct owns M and q when made by cn_lcp_alloc(). */
typedef struct cnLcp {
    int n;
    double *M;
    double *q;
} cnLcp;

/** How a solver ended. Only CN_LCP_SOLVED carries a verified solution. */
typedef enum cnLcpStatus {
    CN_LCP_SOLVED = 0,      /**< z verified: z >= 0, w >= 0, z.w = 0 within tolerance */
    CN_LCP_RAY = 1,         /**< Lemke ended on a secondary ray: no solution found */
    CN_LCP_INFEASIBLE = 2,  /**< proved infeasible: no z >= 0 with M z + q >= 0 */
    CN_LCP_MAX_PIVOTS = 3,  /**< pivot budget exhausted */
    CN_LCP_NUMERIC = 4      /**< singular pivot or a result that failed verification */
} cnLcpStatus;

/** Default relative residual tolerance for verification (see cn_lcp_residual()). */
#define CN_LCP_DEFAULT_TOL 1e-9

typedef struct cnLcpOptions {
    int max_pivots;   /**< 0: automatic (generous, grows with n) */
    double tol;       /**< relative residual accepted by verification */
    bool short_retries; /**< Lemke: start no retry (other pivot tolerances, perturbations) once
                           the attempts so far have done 4e9 units of work (n^2 a pivot); for
                           callers with another answer to fall back on (cn_check, when the
                           equilibrium LP's certificate has already proved the assembly
                           unstable) */
} cnLcpOptions;

typedef struct cnLcpInfo {
    int pivots;        /**< pivots (Lemke) or principal pivots (pivot solver) */
    double residual;   /**< relative residual of the returned z (see cn_lcp_residual) */
    bool refined;      /**< the final basis was refactorised to recover accuracy */
    int ray_variable;  /**< Lemke: the variable that could not be blocked, or -1 */
    bool warm;         /**< solved on a guessed basis (cn_lcp_solve_basis), without pivoting */
} cnLcpInfo;

CN_API cnLcpOptions cn_lcp_options_default(void);

/** Allocate an n x n problem with zero M and q. */
CN_API cnStatus cn_lcp_alloc(cnLcp *p, int n);
CN_API void cn_lcp_free(cnLcp *p);

/** Read the plain text format of shared/lcp/README.md: n, then M row-major, then q (path "-":
 *  standard input). Diagnostics name "line:column". */
CN_API cnStatus cn_lcp_read_file(const char *path, cnLcp *p, cnDiag *diag);
CN_API cnStatus cn_lcp_read_string(const char *text, cnLcp *p, cnDiag *diag);

/** Write a problem in the text format read by cn_lcp_read_file (full precision). */
CN_API cnStatus cn_lcp_write(FILE *f, const cnLcp *p);

/** Lemke's complementary pivoting (a covering vector of 1 on the rows with q_i < 0, distinct
 *  values in [1, 2) on the others) and a lexicographic ratio test
 *  (so degenerate problems cannot cycle). z and w must hold n doubles each. */
CN_API cnLcpStatus cn_lcp_lemke(const cnLcp *p, const cnLcpOptions *opt, double *z, double *w,
                         cnLcpInfo *info);

/** Principal pivoting (Baraff's incremental "drive to zero", a Dantzig-style method) for
 *  symmetric positive semidefinite M, as in frictionless contact. */
CN_API cnLcpStatus cn_lcp_pivot(const cnLcp *p, const cnLcpOptions *opt, double *z, double *w,
                         cnLcpInfo *info);

/** Solve on a guessed complementary basis (a warm start: along a motion path the previous
 *  sample's basis, see cn_lcp_basis_of, is usually still right): z_i = 0 where !basic[i], and M_BB z_B = -q_B on the
 *  rest (one LU factorisation of M_BB). CN_LCP_SOLVED only when the result verifies (tolerance
 *  of opt); CN_LCP_NUMERIC when M_BB is singular or the guess was wrong (some z_B < 0 or
 *  w_N < 0). info->pivots is 0. */
CN_API cnLcpStatus cn_lcp_solve_basis(const cnLcp *p, const unsigned char *basic,
                               const cnLcpOptions *opt, double *z, double *w, cnLcpInfo *info);

/** The basis of a solution, to warm-start the next solve: basic[i] = z_i > max(w_i, 0). */
CN_API void cn_lcp_basis_of(int n, const double *z, const double *w, unsigned char *basic);

/** Relative residual of z: max over i of max(-z_i, -w_i, |min(z_i, w_i)|), divided by
 *  max(|q|_inf, |M|_inf |z|_inf, tiny); NaN (which fails every verification) when M, q or z
 *  holds a NaN or an infinity. Fills w = M z + q when w is not NULL. */
CN_API double cn_lcp_residual(const cnLcp *p, const double *z, double *w);

/** True when z passes verification with relative tolerance tol. */
CN_API bool cn_lcp_verify(const cnLcp *p, const double *z, double tol, double *residual);

/** Whether {z >= 0 : M z + q >= 0} is nonempty, decided by a linear program. Returns CN_OK and
 *  sets *feasible, or CN_ERR_NUMERIC when the LP solver fails. */
CN_API cnStatus cn_lcp_feasible(const cnLcp *p, bool *feasible, cnDiag *diag);

CN_API const char *cn_lcp_status_name(cnLcpStatus s);

#ifdef __cplusplus
}
#endif
#endif
