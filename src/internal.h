/* cairn private helpers shared by the library's files. Not installed. */
#ifndef CAIRN_INTERNAL_H
#define CAIRN_INTERNAL_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <time.h>

#include "cairn/cairn.h"

/* ---- counted allocator (alloc.c): every library allocation goes through these ---- */
void *cn_malloc(size_t bytes);
void *cn_calloc(size_t count, size_t size);
void *cn_realloc(void *p, size_t bytes);
void cn_free(void *p);
char *cn_strdup(const char *s);
size_t cn_alloc_live_bytes(void);
size_t cn_alloc_peak_bytes(void);

#define CN_PI 3.14159265358979323846

/* ---- small vector helpers ---- */
static inline double cn_dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static inline void cn_cross3(const double a[3], const double b[3], double out[3]) {
    double x = a[1] * b[2] - a[2] * b[1];
    double y = a[2] * b[0] - a[0] * b[2];
    double z = a[0] * b[1] - a[1] * b[0];
    out[0] = x;
    out[1] = y;
    out[2] = z;
}
static inline void cn_sub3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[0] - b[0];
    out[1] = a[1] - b[1];
    out[2] = a[2] - b[2];
}
static inline void cn_add3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[0] + b[0];
    out[1] = a[1] + b[1];
    out[2] = a[2] + b[2];
}
static inline void cn_scale3(double a[3], double s) {
    a[0] *= s;
    a[1] *= s;
    a[2] *= s;
}
static inline double cn_norm3(const double a[3]) { return sqrt(cn_dot3(a, a)); }
static inline void cn_copy3(double dst[3], const double src[3]) {
    dst[0] = src[0];
    dst[1] = src[1];
    dst[2] = src[2];
}
/* Normalise in place; returns the old length (0 leaves a unchanged). */
/* max(a, b) inline (libm's fmax is a call on hot paths); a NaN b wins, so a NaN is caught. */
static inline double cn_max_nan(double a, double b) { return b > a || b != b ? b : a; }

/* Wall-clock seconds since t0 (CLOCK_MONOTONIC). */
static inline double cn_seconds_since(const struct timespec *t0) {
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)(t.tv_sec - t0->tv_sec) + 1e-9 * (double)(t.tv_nsec - t0->tv_nsec);
}

static inline double cn_normalize3(double a[3]) {
    double n = cn_norm3(a);
    if (n > 0) cn_scale3(a, 1.0 / n);
    return n;
}
/* An orthonormal tangent basis (t1, t2) for unit normal n, right-handed: t1 x t2 = n. */
void cn_tangent_basis(const double n[3], double t1[3], double t2[3]);

/* ---- dense linear algebra (linalg.c), row-major ---- */
/* LU with partial pivoting in place; returns 0 on success, -1 if a pivot is below
 * rel_tol * max|A|. piv receives n row indices. */
int cn_lu_factor(double *A, int n, int *piv, double rel_tol);
void cn_lu_solve(const double *LU, int n, const int *piv, double *b);
/* LU with symmetric (principal) pivoting and rank detection: at each step the largest diagonal
 * of the remaining Schur complement is the pivot; elimination stops when it falls to rel_tol of
 * the largest entry of A. Returns the rank r; perm[0..n) is the order of the indices, and the
 * leading r x r block (in that order) holds its LU factors (unit lower). The trailing indices
 * are those dependent on the leading ones: for a principal submatrix of an LCP, the variables
 * that can be left at zero. */
int cn_lu_principal(double *A, int n, int *perm, double rel_tol);
/* Solve the leading r x r system of cn_lu_principal: b is in perm order, overwritten. */
void cn_lu_principal_solve(const double *LU, int n, int r, double *b);
/* Cholesky (lower) in place of a symmetric positive definite matrix; -1 if not PD
 * (pivot below rel_tol * max diagonal). */
int cn_chol_factor(double *A, int n, double rel_tol);
void cn_chol_solve(const double *L, int n, double *b);

/* ---- the assembly (assembly.c) ---- */
/* Is part i in the scene? With an absent mask, as it says; without, every part but the plan's
 * gripper bodies. */
int cn_part_present(const cnAssembly *a, const cnContactQuery *q, int i);
/** The contact tolerance of parts i and j displaced by oi and oj (contact.c). */
double cn_pair_tol(const cnAssembly *a, int i, int j, const double *oi, const double *oj);
/* Does plan step `step` move `part`? */
int cn_plan_moves(const cnAssembly *a, int step, int part);

/* ---- geometry of pieces (geom.c) ---- */
/* Bounding boxes, 2-D polygon orientation helpers. */
void cn_piece_bounds(cnPiece *p, int dim);
void cn_piece_free(cnPiece *p);
/* Signed distance of point x from the convex piece (positive outside, negative inside,
 * by the max over supporting planes / edge lines). */
double cn_piece_plane_distance(const cnPiece *p, int dim, const double x[3]);

/* ---- 3-D convex hull (hull3.c): qhull, then exact face loops ---- */
/* Build a convex piece from a point cloud. Returns CN_ERR_INPUT with a message (no `where`)
 * when the points are degenerate (coplanar, too few). */
cnStatus cn_hull3_build(const double (*pts)[3], int n, cnPiece *out, cnDiag *diag);

/* ---- mass properties (mass.c) ---- */
/* Size (area/volume), first moment and second moment (integral of x x^T) about the origin. */
void cn_mass_piece(const cnPiece *p, int dim, double *size, double first[3],
                   double second[3][3]);
/* Fill part->size, mass, com, inertia from pieces and density (or mass when given > 0). */
void cn_mass_part(cnPart *part, int dim, double density, double given_mass);

/* ---- LCP helpers (lcp_core.c) ---- */
/* Common start of a solve: the options with defaults filled in (tolerance, and the pivot budget
 * `default_budget` when none is set), and a cleared info (`*info` may be NULL on entry: it is
 * then pointed at `scratch`). */
cnLcpOptions cn_lcp_begin(const cnLcpOptions *opt, int default_budget, cnLcpInfo **info,
                          cnLcpInfo *scratch);
/* Clamp round-off negatives of z to zero, fill w = M z + q, and verify (relative tol). */
bool cn_lcp_finish(const cnLcp *p, double *z, double *w, double tol, double *residual);

/* ---- reports (report.c) ---- */
/* Write a JSON document (jansson json_t *, taken: it is released) with 2-space indentation and
 * `precision` significant digits, then a newline. */
cnStatus cn_json_write(FILE *f, void *json, int precision);

/* ---- 2-D translational paths (paths2.c) ---- */
/* Up to max_paths piecewise-linear paths (at most 8 segments each) leaving through distinct
 * openings, shortest first; straight-out paths are left to the straight-line candidates. */
cnStatus cn_paths2(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                   int max_paths, double (*segs)[8][3], int *nseg, int *npaths, cnDiag *diag);

/* ---- LP (lp_glpk.c) ---- */
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
    int method;     /* cnLpMethod, for the simplex */
    bool short_budget; /* CN_LP_PRIMAL_AUTO stops after 2,000 + 20 (rows + columns) pivots (it
                          cycles on some small contact LPs): for callers with a fallback */
} cnLpProblem;

/* How GLPK's simplex is run. Each gets some contact LPs wrong (measured): the primal simplex
 * with GLPK's automatic (geometric-mean) scaling cycles, or reports a wrong optimum, when lever
 * arms carry 1e-17 rounding noise, but is the fastest on large LPs and handles 1e6 mass ratios;
 * with equilibration scaling only (CN_LP_DUAL_EQ) it is robust to the noise, and the dual
 * simplex used then for a non-elastic LP is too slow on large ones. Callers verify every answer
 * and go down a list. */
typedef enum cnLpMethod { CN_LP_DUAL_EQ = 0, CN_LP_PRIMAL_AUTO = 1 } cnLpMethod;
cnStatus cn_lp_solve(const cnLpProblem *lp, bool *feasible, double *x, cnDiag *diag);

/* The elastic LP of lp (its cost ignored): min sum |s| over x >= 0, A x + s = rhs (equations),
 * C x >= rhs (inequalities): always feasible, and by duality its optimum is the largest
 * rhs^T y over duals y (neq + nineq entries, |y_eq| <= 1, y_ineq >= 0) with A^T y + C^T y <= 0:
 * a Farkas certificate of infeasibility when positive. x receives its primal (nvars), y its
 * duals. lp->method says how (CN_LP_DUAL_EQ: the primal simplex, equilibrated). The caller
 * verifies both answers. */
cnStatus cn_lp_elastic(const cnLpProblem *lp, double *x, double *y, cnDiag *diag);

#endif
