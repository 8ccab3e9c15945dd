/* core: the stage every other stage stands on. The counted allocator, diagnostics, small vector
 * helpers and dense linear algebra. Private (not installed); includes no other stage. */
#ifndef CAIRN_CORE_H
#define CAIRN_CORE_H

#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <time.h>

#include "cairn/status.h"
#include "tol.h"

/* Exported from libcairn for libcairn_figure only (which allocates with libcairn's counted
 * allocator and draws cn_run_json's figures), as CN_API is; not part of the public interface. */
#define CN_SIBLING CN_API

/* ---- counted allocator (alloc.c): every library allocation goes through these ---- */
CN_SIBLING void *cn_malloc(size_t bytes);
CN_SIBLING void *cn_calloc(size_t count, size_t size);
CN_SIBLING void *cn_realloc(void *p, size_t bytes);
CN_SIBLING void cn_free(void *p);
/* The one out-of-memory diagnostic: CN_ERR_MEMORY, "out of memory", at no input place. */
CN_SIBLING cnStatus cn_diag_oom(cnDiag *d);
char *cn_strdup(const char *s);
size_t cn_alloc_live_bytes(void);
size_t cn_alloc_peak_bytes(void);

/* ---- arena (arena.c): many small blocks freed at once, for results that own a tree of arrays.
 * An empty arena is a NULL pointer; allocations are zeroed and aligned for any type. ---- */
typedef struct cnArena cnArena;
void *cn_arena_alloc(cnArena **arena, size_t count, size_t size);
char *cn_arena_strdup(cnArena **arena, const char *s);
void cn_arena_free(cnArena *arena);

/* ---- index table (hash.c): open addressing over items numbered 0..n-1 that the caller stores
 * (slot holds item + 1, 0 empty; the mask is the size - 1, a power of two). The caller finds an
 * item by walking slots from its hash until an empty one; before adding item n it grows the
 * table to keep it at most half full. ---- */
typedef size_t (*cnHashOf)(const void *ctx, int item);
/* The first empty slot from hash h. */
static inline size_t cn_hash_free_slot(const int *slot, size_t mask, size_t h) {
    size_t i = h & mask;
    while (slot[i]) i = (i + 1) & mask;
    return i;
}
/* Make room for item n (double the table when n + 1 would fill half of it, placing items 0..n-1
 * again by hash_of); 0, or -1 out of memory (the table unchanged). */
int cn_hash_room(int **slot, size_t *mask, int n, cnHashOf hash_of, const void *ctx);

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
    if (!(n > 1e-150 && n < 1e150)) { /* the squares over- or underflow: divide by the largest first */
        double m = fmax(fabs(a[0]), fmax(fabs(a[1]), fabs(a[2])));
        if (!(m > 0) || !isfinite(m)) return n;
        for (int k = 0; k < 3; k++) a[k] /= m;
        double r = cn_norm3(a);
        cn_scale3(a, 1.0 / r);
        return m * r;
    }
    cn_scale3(a, 1.0 / n);
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

#endif
