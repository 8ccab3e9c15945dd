/* core/: dense linear algebra against products computed here (LU with partial pivoting,
 * Cholesky, the principal LU of a PSD matrix and its rank), the tangent basis's orthonormality,
 * the arena's alignment, contents and chunking, and the index table against a linear scan. */
#include <math.h>
#include <stdalign.h>
#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "core.h"
#include "test.h"

#define N 7

/* A deterministic generator in [-1, 1). */
static double rnd(unsigned long long *s) {
    *s = *s * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(*s >> 11) / 9007199254740992.0 * 2 - 1;
}

/* b = A x (n x n, row-major) */
static void mul(const double *A, int n, const double *x, double *b) {
    for (int i = 0; i < n; i++) {
        b[i] = 0;
        for (int j = 0; j < n; j++) b[i] += A[i * n + j] * x[j];
    }
}

static double max_diff(const double *a, const double *b, int n) {
    double d = 0;
    for (int i = 0; i < n; i++) d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

static void test_lu_chol(void) {
    unsigned long long s = 12345;
    for (int t = 0; t < 50; t++) {
        int n = 1 + t % N;
        double A[N * N], F[N * N], x[N], b[N], y[N];
        /* general, made nonsingular by its diagonal; rows scaled apart so pivoting matters */
        for (int i = 0; i < n * n; i++) A[i] = rnd(&s);
        for (int i = 0; i < n; i++) A[i * n + i] += 4 * (i % 2 ? 1 : -1);
        for (int i = 0; i < n; i++) x[i] = rnd(&s);
        mul(A, n, x, b);
        memcpy(F, A, sizeof(double) * (size_t)(n * n));
        int piv[N];
        CHECK(cn_lu_factor(F, n, piv, 1e-14) == 0);
        memcpy(y, b, sizeof(double) * (size_t)n);
        cn_lu_solve(F, n, piv, y);
        CHECK_MSG(max_diff(x, y, n) < 1e-12, "LU, n = %d: %g", n, max_diff(x, y, n));
        /* symmetric positive definite: B B^T + I */
        double B[N * N];
        for (int i = 0; i < n * n; i++) B[i] = rnd(&s);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double v = i == j;
                for (int k = 0; k < n; k++) v += B[i * n + k] * B[j * n + k];
                A[i * n + j] = v;
            }
        mul(A, n, x, b);
        memcpy(F, A, sizeof(double) * (size_t)(n * n));
        CHECK(cn_chol_factor(F, n, 1e-14) == 0);
        memcpy(y, b, sizeof(double) * (size_t)n);
        cn_chol_solve(F, n, y);
        CHECK_MSG(max_diff(x, y, n) < 1e-12, "Cholesky, n = %d: %g", n, max_diff(x, y, n));
        /* the principal LU of the same matrix: full rank, and A x = b after its permutation */
        memcpy(F, A, sizeof(double) * (size_t)(n * n));
        int perm[N];
        CHECK(cn_lu_principal(F, n, perm, 1e-14) == n);
        double bp[N];
        for (int i = 0; i < n; i++) bp[i] = b[perm[i]];
        cn_lu_principal_solve(F, n, n, bp);
        for (int i = 0; i < n; i++) y[perm[i]] = bp[i];
        CHECK_MSG(max_diff(x, y, n) < 1e-12, "principal LU, n = %d: %g", n, max_diff(x, y, n));
    }
    /* rank r < n: a PSD matrix V V^T of r columns has principal rank r, LU and Cholesky refuse */
    for (int r = 1; r < N; r++) {
        int n = N;
        double V[N * N], A[N * N], F[N * N];
        for (int i = 0; i < n * r; i++) V[i] = rnd(&s);
        for (int i = 0; i < n; i++)
            for (int j = 0; j < n; j++) {
                double v = 0;
                for (int k = 0; k < r; k++) v += V[i * r + k] * V[j * r + k];
                A[i * n + j] = v;
            }
        int perm[N], piv[N];
        memcpy(F, A, sizeof F);
        CHECK_MSG(cn_lu_principal(F, n, perm, 1e-10) == r, "rank %d", r);
        memcpy(F, A, sizeof F);
        CHECK(cn_lu_factor(F, n, piv, 1e-10) == -1);
        memcpy(F, A, sizeof F);
        CHECK(cn_chol_factor(F, n, 1e-10) == -1);
    }
}

static void test_tangent_basis(void) {
    unsigned long long s = 777;
    for (int t = 0; t < 200; t++) {
        double n[3] = {rnd(&s), rnd(&s), rnd(&s)};
        if (t < 6) n[0] = n[1] = n[2] = 0, n[t % 3] = t < 3 ? 1 : -1; /* the axes too */
        cn_normalize3(n);
        double t1[3], t2[3], c[3];
        cn_tangent_basis(n, t1, t2);
        CHECK(fabs(cn_norm3(t1) - 1) < 1e-14 && fabs(cn_norm3(t2) - 1) < 1e-14);
        CHECK(fabs(cn_dot3(t1, n)) < 1e-14 && fabs(cn_dot3(t2, n)) < 1e-14 && fabs(cn_dot3(t1, t2)) < 1e-14);
        cn_cross3(t1, t2, c); /* right-handed: t1 x t2 = n */
        CHECK(fabs(cn_dot3(c, n) - 1) < 1e-14);
    }
}

static void test_arena(void) {
    cnArena *a = NULL;
    char *names[50];
    int nn = 0;
    bool aligned = true, zeroed = true, got = true;
    for (int i = 0; i < 5000; i++) { /* many chunks' worth, odd sizes, one larger than a chunk */
        size_t bytes = i == 2500 ? 100000 : (size_t)(1 + i % 37);
        unsigned char *p = cn_arena_alloc(&a, bytes, 1);
        if (!p) {
            got = false;
            break;
        }
        aligned &= (uintptr_t)p % alignof(max_align_t) == 0;
        for (size_t k = 0; k < bytes; k++) zeroed &= p[k] == 0;
        memset(p, 0xA5, bytes); /* a block overlapping another would show in the names below */
        if (i % 100 == 0) {
            char name[32];
            snprintf(name, sizeof name, "part %d", i);
            names[nn++] = cn_arena_strdup(&a, name);
        }
    }
    CHECK(got && aligned && zeroed);
    bool intact = true;
    for (int k = 0; k < nn; k++) {
        char name[32];
        snprintf(name, sizeof name, "part %d", 100 * k);
        intact &= names[k] && !strcmp(names[k], name);
    }
    CHECK_MSG(intact, "the arena's strings kept their text");
    CHECK(cn_arena_alloc(&a, SIZE_MAX / 2, 4) == NULL); /* a size that overflows */
    cn_arena_free(a);
}

/* The index table: keys with many colliding hashes, each found again (its item) after every
 * growth, absent keys not found, and the table never more than half full; against a linear scan
 * of the keys added. */
typedef struct {
    const unsigned *keys;
} HashCtx;
static size_t key_hash(const void *ctx, int item) { return ((const HashCtx *)ctx)->keys[item] % 61; }
static int find(const int *slot, size_t mask, const unsigned *keys, unsigned key) {
    for (size_t i = (key % 61) & mask; slot[i]; i = (i + 1) & mask)
        if (keys[slot[i] - 1] == key) return slot[i] - 1;
    return -1;
}
static void test_hash(void) {
    enum { M = 3000 };
    static unsigned keys[M];
    HashCtx ctx = {keys};
    size_t mask = 7;
    int *slot = cn_calloc(mask + 1, sizeof(int)), n = 0;
    unsigned long long s = 99;
    bool found = true, absent = true, half = true;
    while (slot && n < M) {
        unsigned key = (unsigned)((rnd(&s) + 1) * 1e6);
        int scan = -1;
        for (int k = 0; k < n; k++)
            if (keys[k] == key) scan = k;
        if (find(slot, mask, keys, key) != scan) absent = false;
        if (scan >= 0) continue;
        if (cn_hash_room(&slot, &mask, n, key_hash, &ctx)) break;
        keys[n] = key;
        slot[cn_hash_free_slot(slot, mask, key % 61)] = n + 1;
        n++;
        half &= (size_t)n * 2 <= mask + 1;
    }
    for (int k = 0; k < n; k++) found &= find(slot, mask, keys, keys[k]) == k;
    CHECK(n == M);
    CHECK(found);
    CHECK(absent);
    CHECK(half);
    cn_free(slot);
}

void test_core(void) {
    test_lu_chol();
    test_tangent_basis();
    test_arena();
    test_hash();
}
