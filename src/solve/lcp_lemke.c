/* Lemke's complementary pivoting algorithm with a lexicographic ratio test.
 *
 * Reference: Cottle, Pang & Stone, "The Linear Complementarity Problem" (1992), sec. 4.4
 * (Lemke's method, scheme I) and sec. 4.9 (lexicographic degeneracy resolution).
 *
 * System: I w - M z - d z0 = q with a covering vector d > 0 (below). Revised form: the basis
 * inverse is kept (without its unit columns, below), so the lexicographic test can compare rows of
 * [x_B, B^-1] / col_i, which is exactly the textbook rule applied to the tableau [q | I]. With it,
 * no basis repeats, so degenerate problems (resting contacts: many zeros in q) cannot cycle.
 *
 * The covering vector: d_i = 1 where q_i < 0, and 1 + r_i, r_i in [0, 1) fixed pseudo-random per
 * row, where q_i >= 0. Any d > 0 is a valid start (z0 = max(-q_i / d_i) makes every w_i >= 0).
 * For copositive-plus M (positive semidefinite: every contact LCP here) Lemke ends on a
 * solution whenever the LCP is feasible, whatever d (sec. 4.4); for other M, d can decide
 * between a solution and a secondary ray, so cn_lcp_lemke tries d = 1 next when this d fails.
 * The path's length depends on d: with d = 1, the rows with q_i >= 0 (contacts the load does
 * not press: q_i = 0 for many) stay tied along it, and distinct d_i there break the ties and
 * shorten it. The first pivot is the same as with d = 1: only rows with q_i < 0 are its
 * candidates (d_i = 1 there).
 *
 * Variables: w_i = i, z_i = n + i, z0 = 2n. */
#include <math.h>
#include <string.h>

#include "solve.h"

/* Relative pivot tolerances tried in turn: entries of the entering column below this fraction of
 * its largest entry are treated as zero (they cannot block). Real contact data have nearly
 * redundant contacts whose pivots are noise-sized; 1e-8 rejects them. If an attempt fails
 * (secondary ray or failed verification), the next tolerance is tried, so a tolerance never turns
 * into a false "no solution" when another succeeds. */
static const double LEMKE_PIVOT_TOLS[] = {1e-8, 1e-11, 1e-6};
/* Relative tolerance for ties in ratios and in the lexicographic comparison. */
#define LEMKE_TIE_TOL 1e-9
/* Relative tolerance of the lexicographic comparison (fraction of the candidate rows' size). */
#define LEMKE_LEX_TOL 1e-10
/* Columns of the stored part of B^-1 to start with, and the size of each later allocation of
 * more (see lemke_reserve). */
#define LEMKE_BR_INITIAL 16
#define LEMKE_CHUNK_BYTES 65536
/* Entries of the visited-basis table to start with (doubled when half full). */
#define LEMKE_SEEN_INITIAL 64
/* The default pivot budget: Lemke may need exponentially many pivots (Murty's example, 2^n),
 * each at most O(n^2) (O(n k) with k basic z's); the budget counts n^2 per pivot: the
 * first attempt may do about this much work and at least
 * 50 n + 1000 pivots, so that n = 20 in Murty's example (1,048,576 pivots) is solved while an
 * LCP that needs more stops in bounded time; the retries (other pivot tolerances,
 * perturbations) get 50 n + 1000 pivots. */
#define LEMKE_WORK 5e8
/* With cnLcpOptions.short_retries, once the attempts so far have done this much work, counted
 * as above, no retry follows: the retries are for rounding trouble on paths of ordinary length,
 * and a retry of a long path that ends on a secondary ray is as long and tends to end the same
 * way (the caller asks for short retries when the LP has already decided). */
#define LEMKE_RETRY_WORK 4e9

/* Inline max and min (libm's fmax and fmin are calls, a large part of a small solve). Like
 * them, these ignore a NaN in b (cn_max_nan returns it, so that a NaN is caught). */
static inline double max_of(double a, double b) { return b > a ? b : a; }
static inline double min_of(double a, double b) { return b < a ? b : a; }

/* The basis inverse, without its unit columns. Column e of B^-1 is the unit vector of w_e's slot
 * whenever w_e is basic (B's column for it is e_e), so only the columns of the k equations R
 * whose w is nonbasic are kept: k columns of n entries, updated by the pivots' row operations like
 * the whole inverse, with a column added or dropped when R changes. A pivot costs O(n k) instead
 * of O(n^2), and k, the number of basic z (z0 among them), ends well below n on contact LCPs (an
 * 8-row 2-D pyramid's friction LCP: 65 of its 736 z positive at the solution). The
 * lexicographic test still reads whole rows of B^-1: the stored part, and the implicit 1 of a
 * basic w.
 *
 * Each stored column is its own buffer of n doubles, reached through `BR[q]`: a column joins or
 * leaves by moving a pointer, and room for more columns comes in new chunks, never by copying
 * the stored ones (copying a doubling block, and faulting in its pages, would take a large part
 * of a solve). */
typedef struct {
    int n;
    const cnLcp *p;
    double *xB;  /* value of the basic variable of each slot */
    double *col; /* the entering column B^-1 a, per slot */
    double *a;   /* the entering variable's column of the system */
    double *aR;  /* a's entries in the equations R, by position */
    double *acc; /* three more partial sums of B^-1 a, per slot (lemke_column) */
    double *d;   /* the covering vector */
    int *basis;  /* variable in each slot */
    int *rowof;  /* slot of each variable, -1 when nonbasic */
    int *cand;
    unsigned char *incand; /* per slot: among the lexicographic test's candidates (else 0) */
    int k, kcap; /* equations in R, and column buffers for them (BR[0 .. kcap)) */
    int *R;      /* the equations whose w is nonbasic, by position */
    int *rpos;   /* position in R of each equation, -1 when w_i is basic */
    double **BR; /* column q of the stored part of B^-1 (equation R[q]), n entries by slot;
                    BR[k .. kcap) are spare buffers */
    double **chunks; /* the buffers' allocations beyond the work block's first ones */
    int nchunks;
    unsigned long long hash;     /* Zobrist hash of the current basis */
    unsigned long long *seen;    /* open-addressing set of visited basis hashes */
    unsigned long long *seen_initial; /* its first table, inside the work block */
    size_t seen_mask, seen_count; /* grown (doubled) when half full */
    double qscale;
    double ptol;
} cnLemke;

/* A fixed pseudo-random key per variable (splitmix64), XORed into the basis hash. */
static unsigned long long var_key(int v) {
    unsigned long long x = (unsigned long long)v * 0x9E3779B97F4A7C15ULL + 0x632BE59BD9B4E019ULL;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
}

/* Record the current basis; returns 1 if it was visited before. Exact lexicographic Lemke never
 * revisits a basis, so a repeat means rounding broke the rule and the path is cycling. (A hash
 * collision would only end the attempt early; the next attempt or the caller's fallback
 * handles it.) */
static int lemke_seen(cnLemke *L) {
    unsigned long long h = L->hash ? L->hash : 1;
    size_t i = (size_t)(h ^ (h >> 29)) & L->seen_mask;
    while (L->seen[i]) {
        if (L->seen[i] == h) return 1;
        i = (i + 1) & L->seen_mask;
    }
    L->seen[i] = h;
    if (++L->seen_count * 2 > L->seen_mask) { /* grow: the table starts small (most runs take
                                                 a few pivots) */
        size_t cap = 2 * (L->seen_mask + 1);
        unsigned long long *t = cn_calloc(cap, sizeof(unsigned long long));
        if (!t) return 1; /* out of memory: end this attempt, as for cycling */
        for (size_t k = 0; k <= L->seen_mask; k++) {
            unsigned long long v = L->seen[k];
            if (!v) continue;
            size_t j = (size_t)(v ^ (v >> 29)) & (cap - 1);
            while (t[j]) j = (j + 1) & (cap - 1);
            t[j] = v;
        }
        if (L->seen != L->seen_initial) cn_free(L->seen);
        L->seen = t;
        L->seen_mask = cap - 1;
    }
    return 0;
}

/* The two loops that take a pivot's time, built twice (AVX2 and the baseline) and picked at
 * load time. Element by element, without reassociation or contraction, so both give the same
 * bits. */
#if defined(__x86_64__) && defined(__linux__) && defined(__has_attribute) && !defined(__SANITIZE_THREAD__)
#if __has_attribute(target_clones)
#define LEMKE_HOT __attribute__((target_clones("avx2", "default")))
#endif
#endif
#ifndef LEMKE_HOT /* elsewhere (no x86-64, no ifunc to pick a clone, or ThreadSanitizer, which is
                     not started when the loader runs the resolver): the baseline only */
#define LEMKE_HOT
#endif

/* y += f x over m entries */
LEMKE_HOT static void axpy_plus(double *restrict y, double f, const double *restrict x, int m) {
    for (int i = 0; i < m; i++) y[i] += f * x[i];
}

/* y -= f x over m entries */
LEMKE_HOT static void axpy_minus(double *restrict y, double f, const double *restrict x, int m) {
    for (int i = 0; i < m; i++) y[i] -= f * x[i];
}

/* The system's column of z variable `var` (z_j, or z0: -d) into out. */
static void z_column(const cnLemke *L, int var, double *out) {
    int n = L->n;
    if (var == 2 * n) {
        for (int i = 0; i < n; i++) out[i] = -L->d[i];
        return;
    }
    const double *M = L->p->M + (var - n);
    for (int i = 0; i < n; i++) out[i] = -M[(size_t)i * n];
}

/* B^-1 times the column of `var` into L->col (per slot): a basic w_e's slot gets a_e from its
 * unit column, and every slot the stored columns times a_R. The sum over the stored columns runs
 * in four partial sums (columns q = 0, 1, 2, 3 mod 4, the last k mod 4 into the first), added as
 * (s0 + s1) + (s2 + s3): independent chains the CPU overlaps, in a fixed order, so the result
 * is the same on every run and build. */
static void lemke_column(cnLemke *L, int var) {
    int n = L->n, k = L->k;
    if (var < n) { /* w_var: a = e_var, and var is in R */
        memcpy(L->col, L->BR[L->rpos[var]], sizeof(double) * (size_t)n);
        return;
    }
    z_column(L, var, L->a);
    for (int q = 0; q < k; q++) L->aR[q] = L->a[L->R[q]];
    double *s0 = L->col, *s1 = L->acc, *s2 = s1 + n, *s3 = s2 + n;
    memset(s0, 0, sizeof(double) * (size_t)n);
    memset(s1, 0, sizeof(double) * 3 * (size_t)n);
    /* a contact LCP's column of M is sparse (the contacts that share a body): a zero of a_R adds
     * nothing and is skipped */
    double *sum[4] = {s0, s1, s2, s3};
    int k4 = k & ~3;
    for (int q = 0; q < k; q++)
        if (L->aR[q] != 0) axpy_plus(sum[q < k4 ? (q & 3) : 0], L->aR[q], L->BR[q], n);
    for (int s = 0; s < n; s++) {
        int b = L->basis[s];
        L->col[s] = (b < n ? L->a[b] : 0.0) + ((s0[s] + s1[s]) + (s2[s] + s3[s]));
    }
}

/* Room for k + 1 columns in BR: a new chunk of spare buffers when all are in use, of about
 * LEMKE_CHUNK_BYTES (at least one column; below the allocator's threshold for a mapping of its
 * own, so that repeated solves reuse the memory). Returns -1 when out of memory. */
static int lemke_reserve(cnLemke *L) {
    if (L->k < L->kcap) return 0;
    int n = L->n;
    size_t per = LEMKE_CHUNK_BYTES / (sizeof(double) * (size_t)n);
    int add = per < 1 ? 1 : (int)per;
    if (add > n - L->kcap) add = n - L->kcap;
    if (add < 1) return -1; /* n columns at most: cannot happen */
    double *c = cn_malloc(sizeof(double) * (size_t)add * n);
    if (!c) return -1;
    L->chunks[L->nchunks++] = c;
    for (int j = 0; j < add; j++) L->BR[L->kcap++] = c + (size_t)j * n;
    return 0;
}

/* Column q of BR := the unit vector of slot r (the column of the equation of a basic w in slot
 * r, about to be stored). */
static void br_unit(cnLemke *L, int q, int r) {
    memset(L->BR[q], 0, sizeof(double) * (size_t)L->n);
    L->BR[q][r] = 1.0;
}

/* The pivot on slot r's element of the entering column (in L->col). R changes first where the
 * leaving or entering variable is a w (its equation's column joins BR as the unit column it
 * was, or leaves it, being unit after the pivot), then the row operations. Returns -1 when out of
 * memory. */
static int lemke_pivot(cnLemke *L, int r, int entering) {
    int n = L->n;
    int leaving = L->basis[r];
    if (leaving < n) { /* w_i leaves: equation i joins R (at m's place if w_m enters) */
        int q;
        if (entering < n) {
            q = L->rpos[entering];
            L->rpos[entering] = -1;
        } else {
            if (lemke_reserve(L)) return -1;
            q = L->k++;
        }
        br_unit(L, q, r);
        L->R[q] = leaving, L->rpos[leaving] = q;
    } else if (entering < n) { /* z out, w_m in: equation m leaves R (its buffer is spare) */
        int q = L->rpos[entering], last = L->k - 1;
        if (q != last) {
            double *t = L->BR[q];
            L->BR[q] = L->BR[last], L->BR[last] = t;
            L->R[q] = L->R[last], L->rpos[L->R[q]] = q;
        }
        L->rpos[entering] = -1;
        L->k = last;
    }
    int k = L->k;
    double *col = L->col;
    double inv = 1.0 / col[r];
    /* each stored column: its slot-r entry scaled, then the other slots less col times it (the
     * slot-r entry of col is zeroed for the sweep, so that slot keeps its scaled value) */
    double cr = col[r];
    col[r] = 0;
    for (int q = 0; q < k; q++) {
        double *c = L->BR[q];
        double br = c[r] * inv;
        if (br != 0) axpy_minus(c, br, col, n); /* a zero changes nothing */
        c[r] = br;
    }
    col[r] = cr;
    L->xB[r] *= inv;
    for (int s = 0; s < n; s++) {
        if (s == r) continue;
        double f = col[s];
        if (f == 0) continue;
        L->xB[s] -= f * L->xB[r];
    }
    L->hash ^= var_key(leaving) ^ var_key(entering);
    L->rowof[leaving] = -1;
    L->basis[r] = entering;
    L->rowof[entering] = r;
    return 0;
}

/* Among candidate slots (already tied on the ratio x_B,i / div_i), pick the lexicographic
 * minimum of the rows of B^-1 divided by div_i. Entries are compared with a tolerance relative
 * to the size of the whole candidate rows, not of one column: product-form updates leave noise
 * (~1e-15 of the row) where exact arithmetic has zeros, and comparing noise against noise
 * breaks lexicographic positivity and lets the method cycle. */
static int lemke_lexmin(cnLemke *L, int m, const double *div) {
    if (m <= 1) return L->cand[0];
    int n = L->n, k = L->k;
    double rowscale = 0;
    for (int c = 0; c < m; c++) {
        int s = L->cand[c];
        L->incand[s] = 1;
        /* four partial maxima: independent chains (a maximum is exact in any order) */
        double m0 = L->basis[s] < n ? 1.0 : 0.0, m1 = 0, m2 = 0, m3 = 0;
        int q = 0;
        for (; q + 4 <= k; q += 4) {
            m0 = max_of(m0, fabs(L->BR[q][s]));
            m1 = max_of(m1, fabs(L->BR[q + 1][s]));
            m2 = max_of(m2, fabs(L->BR[q + 2][s]));
            m3 = max_of(m3, fabs(L->BR[q + 3][s]));
        }
        for (; q < k; q++) m0 = max_of(m0, fabs(L->BR[q][s]));
        double mx = max_of(max_of(m0, m1), max_of(m2, m3));
        rowscale = max_of(rowscale, mx / fabs(div[s]));
    }
    double tol = LEMKE_LEX_TOL * rowscale;
    double *v = L->acc + n; /* the candidates' entries of column e over div (the ratio test
                               keeps its ratios in acc[0, n)) */
    for (int e = 0; e < n && m > 1; e++) {
        int q = L->rpos[e];
        if (q < 0) {
            /* a unit column: 1 in w_e's slot (if basic), 0 in every other. With another
             * candidate at 0, the minimum is 0 and only w_e's slot can drop out. */
            int se = L->rowof[e];
            if (se < 0 || !L->incand[se] || 1.0 / div[se] <= tol) continue;
            int kept = 0;
            for (int c = 0; c < m; c++)
                if (L->cand[c] != se) L->cand[kept++] = L->cand[c];
            m = kept;
            L->incand[se] = 0;
            continue;
        }
        const double *Be = L->BR[q];
        double best = INFINITY;
        for (int c = 0; c < m; c++) {
            int s = L->cand[c];
            double x = Be[s];
            v[c] = x != 0 ? x / div[s] : 0.0;
            best = min_of(best, v[c]);
        }
        int kept = 0;
        for (int c = 0; c < m; c++) {
            if (v[c] <= best + tol) L->cand[kept++] = L->cand[c];
            else L->incand[L->cand[c]] = 0;
        }
        m = kept;
    }
    for (int c = 0; c < m; c++) L->incand[L->cand[c]] = 0;
    return L->cand[0];
}

/* Re-solve B x = q for the final basis from scratch, removing drift from the product-form
 * updates: with J the basic z's, C_RJ x_J = q_R (LU), then x_i = q_i - C_iJ x_J for each basic
 * w_i. Returns 0 on success. */
static int lemke_refine(cnLemke *L) {
    int n = L->n, k = L->k;
    double *C = cn_malloc(sizeof(double) * ((size_t)k * k + 1));
    double *x = cn_malloc(sizeof(double) * ((size_t)k + 1));
    int *piv = cn_malloc(sizeof(int) * ((size_t)k + 1));
    int *J = cn_malloc(sizeof(int) * ((size_t)k + 1));
    int rc = -1, nj = 0;
    for (int s = 0; J && s < n; s++)
        if (L->basis[s] >= n && nj < k) J[nj++] = L->basis[s];
    if (C && x && piv && J && nj == k) {
        for (int p = 0; p < k; p++) { /* column p of C_RJ: the system's column of z J[p] */
            z_column(L, J[p], L->a);
            for (int q = 0; q < k; q++) C[(size_t)q * k + p] = L->a[L->R[q]];
        }
        if (k == 0 || cn_lu_factor(C, k, piv, 1e-14) == 0) {
            for (int q = 0; q < k; q++) x[q] = L->p->q[L->R[q]];
            if (k) cn_lu_solve(C, k, piv, x);
            for (int s = 0; s < n; s++)
                if (L->basis[s] < n) L->xB[s] = L->p->q[L->basis[s]];
            for (int p = 0; p < k; p++) {
                L->xB[L->rowof[J[p]]] = x[p];
                z_column(L, J[p], L->a);
                for (int s = 0; s < n; s++)
                    if (L->basis[s] < n) L->xB[s] -= L->a[L->basis[s]] * x[p];
            }
            rc = 0;
        }
    }
    cn_free(C);
    cn_free(x);
    cn_free(piv);
    cn_free(J);
    return rc;
}

static void lemke_extract(const cnLemke *L, double *z) {
    int n = L->n;
    for (int j = 0; j < n; j++) {
        int r = L->rowof[n + j];
        z[j] = (r >= 0) ? L->xB[r] : 0.0;
        if (z[j] <= 0 && z[j] > -1e-300) z[j] = 0; /* no negative zeros (-0.0 among them) */
    }
}

/* The work arrays in one block (small problems are dominated by allocation otherwise): the
 * doubles (the first LEMKE_BR_INITIAL column buffers among them), the initial visited-basis
 * table, the column and chunk pointers, then the ints; more buffers come in chunks as k grows.
 * The basis starts as w = q. */
static int lemke_init(cnLemke *L, const cnLcp *p, double qscale, double ptol, bool unit_d) {
    int n = p->n;
    memset(L, 0, sizeof *L);
    L->n = n;
    L->p = p;
    L->qscale = qscale;
    L->ptol = ptol;
    size_t tbl = LEMKE_SEEN_INITIAL;
    L->kcap = n < LEMKE_BR_INITIAL ? n : LEMKE_BR_INITIAL;
    size_t bytes = sizeof(double) * (8 + (size_t)L->kcap) * (size_t)n +
                   sizeof(unsigned long long) * tbl + sizeof(double *) * 2 * ((size_t)n + 1) +
                   sizeof(int) * (6 * (size_t)n + 1) + (size_t)n;
    L->xB = cn_malloc(bytes);
    if (!L->xB) return -1;
    L->col = L->xB + n;
    L->a = L->col + n;
    L->aR = L->a + n;
    L->acc = L->aR + n;
    L->d = L->acc + 3 * (size_t)n;
    double *first = L->d + n;
    L->seen = L->seen_initial = (unsigned long long *)(first + (size_t)L->kcap * n);
    memset(L->seen, 0, sizeof(unsigned long long) * tbl);
    L->seen_mask = tbl - 1;
    L->BR = (double **)(L->seen + tbl);
    L->chunks = L->BR + n + 1;
    for (int q = 0; q < L->kcap; q++) L->BR[q] = first + (size_t)q * n;
    L->basis = (int *)(L->chunks + n + 1);
    L->rowof = L->basis + n;
    L->cand = L->rowof + 2 * n + 1;
    L->R = L->cand + n;
    L->rpos = L->R + n;
    L->incand = (unsigned char *)(L->rpos + n);
    memset(L->incand, 0, (size_t)n);
    for (int i = 0; i < n; i++) {
        double r = (double)(var_key(i) >> 11) * (1.0 / 9007199254740992.0); /* [0, 1) */
        L->d[i] = p->q[i] < 0 || unit_d ? 1.0 : 1.0 + r;
        L->xB[i] = p->q[i];
        L->basis[i] = i;
        L->rowof[i] = i;
        L->rowof[n + i] = -1;
        L->rpos[i] = -1;
        L->hash ^= var_key(i);
    }
    L->rowof[2 * n] = -1;
    return 0;
}

static void lemke_release(cnLemke *L) {
    if (L->seen != L->seen_initial) cn_free(L->seen);
    for (int c = 0; c < L->nchunks; c++) cn_free(L->chunks[c]);
    cn_free(L->xB);
}

/* First pivot: z0 enters at the level that makes every w_i >= 0; the leaving row is the
 * lexicographic minimum of (q_i, e_i) / d_i. Returns the variable that left, -1 when out of
 * memory. */
static int lemke_first_pivot(cnLemke *L) {
    int n = L->n, m = 0;
    const double *q = L->p->q, *d = L->d;
    double qmin = INFINITY;
    for (int i = 0; i < n; i++) qmin = fmin(qmin, q[i] / d[i]);
    double tol = LEMKE_TIE_TOL * L->qscale;
    for (int i = 0; i < n; i++) /* ties within tol, among the rows that need z0 (q_i < 0) */
        if (q[i] < 0 && q[i] / d[i] <= qmin + tol) L->cand[m++] = i;
    int r = lemke_lexmin(L, m, d);
    lemke_column(L, 2 * n);
    int leaving = L->basis[r];
    if (lemke_pivot(L, r, 2 * n)) return -1;
    return leaving;
}

/* The ratio test on the entering column (in L->col): the leaving row, z0's when it ties (a
 * solution), else the lexicographic minimum among the ties; -1: no row limits it (a ray);
 * -2: the column is not finite. */
static int lemke_ratio_test(cnLemke *L) {
    int n = L->n, m = 0, z0row = -1;
    /* the column's largest entry, in four partial maxima (independent chains; a maximum is
     * exact in any order), and whether any entry is not a number (x - x is 0 for the others) */
    double c0 = 0, c1 = 0, c2 = 0, c3 = 0, nan = 0;
    const double *col = L->col;
    int i4 = 0;
    for (; i4 + 4 <= n; i4 += 4) {
        c0 = max_of(c0, fabs(col[i4]));
        c1 = max_of(c1, fabs(col[i4 + 1]));
        c2 = max_of(c2, fabs(col[i4 + 2]));
        c3 = max_of(c3, fabs(col[i4 + 3]));
        nan += (col[i4] - col[i4]) + (col[i4 + 1] - col[i4 + 1]) + (col[i4 + 2] - col[i4 + 2]) +
               (col[i4 + 3] - col[i4 + 3]);
    }
    for (; i4 < n; i4++) c0 = max_of(c0, fabs(col[i4])), nan += col[i4] - col[i4];
    double cmax = max_of(max_of(c0, c1), max_of(c2, c3));
    if (nan != 0 || !isfinite(cmax)) return -2;
    double pivtol = L->ptol * cmax;
    /* the ratios (infinite where the entry cannot block; no division for the zeros of a
     * degenerate basis), kept for the ties below, and their minimum in two partial chains */
    double *ratio = L->acc, t0 = INFINITY, t1 = INFINITY;
    for (int i = 0; i < n; i++) {
        double x = L->xB[i];
        double t = col[i] > pivtol ? (x > 0 ? x / col[i] : 0.0) : INFINITY;
        ratio[i] = t;
        if (i & 1) t1 = min_of(t1, t);
        else t0 = min_of(t0, t);
    }
    double tmin = min_of(t0, t1);
    if (tmin == INFINITY) return -1;
    /* Ties: ratios equal within a tolerance relative to the scale of q. A ratio above the
     * tolerance's bound with both terms doubled (no division: times col_i > 0) cannot tie. */
    double far = 2.0 * LEMKE_TIE_TOL * 1e-3 * L->qscale;
    for (int i = 0; i < n; i++) {
        double t = ratio[i];
        if (t == INFINITY || (t - tmin - 2.0 * LEMKE_TIE_TOL * tmin) * col[i] > far) continue;
        double ttol = LEMKE_TIE_TOL * (tmin + L->qscale / col[i] * 1e-3);
        if (t <= tmin + ttol) {
            L->cand[m++] = i;
            if (L->basis[i] == 2 * n) z0row = i;
        }
    }
    return z0row >= 0 ? z0row : lemke_lexmin(L, m, L->col);
}

static cnLcpStatus lemke_run(const cnLcp *p, const cnLcpOptions *opt, double ptol, bool unit_d,
                             double *z, double *w, cnLcpInfo *info) {
    int n = p->n;
    cnLcpInfo scratch;
    double by_work = LEMKE_WORK / ((double)n * n + 1);
    int budget = by_work > 50.0 * n + 1000 ? (int)fmin(by_work, 1e9) : 50 * n + 1000;
    cnLcpOptions o = cn_lcp_begin(opt, budget, &info, &scratch);
    int qneg = 0;
    double qscale = 0;
    for (int i = 0; i < n; i++) {
        if (p->q[i] < 0) qneg = 1;
        qscale = fmax(qscale, fabs(p->q[i]));
        if (!isfinite(p->q[i])) return CN_LCP_NUMERIC;
    }
    if (!qneg) { /* z = 0 solves it */
        for (int i = 0; i < n; i++) z[i] = 0, w[i] = p->q[i];
        info->residual = 0;
        return CN_LCP_SOLVED;
    }
    cnLemke L;
    if (lemke_init(&L, p, qscale, ptol, unit_d)) return CN_LCP_NUMERIC;
    cnLcpStatus status = CN_LCP_NUMERIC;
    int first = lemke_first_pivot(&L);
    if (first < 0) goto done;
    int entering = first + n; /* complement of w_r is z_r */
    info->pivots = 1;
    for (;;) {
        if (info->pivots >= o.max_pivots) {
            status = CN_LCP_MAX_PIVOTS;
            goto done;
        }
        lemke_column(&L, entering);
        int r = lemke_ratio_test(&L);
        if (r == -2) goto done;
        if (r == -1) {
            info->ray_variable = entering;
            status = CN_LCP_RAY;
            goto done;
        }
        int leaving = L.basis[r];
        if (lemke_pivot(&L, r, entering)) goto done;
        info->pivots++;
        if (leaving == 2 * n) break; /* z0 left: a solution */
        if (lemke_seen(&L)) {        /* cycling: give up this attempt */
            status = CN_LCP_NUMERIC;
            goto done;
        }
        entering = leaving < n ? leaving + n : leaving - n;
    }
    lemke_extract(&L, z);
    cn_lcp_finish(p, z, w, o.tol, &info->residual);
    if (!(info->residual <= o.tol * 1e-3) && lemke_refine(&L) == 0) {
        /* Product-form drift: recompute the basic solution from the final basis. */
        info->refined = true;
        lemke_extract(&L, z);
        cn_lcp_finish(p, z, w, o.tol, &info->residual);
    }
    status = info->residual <= o.tol ? CN_LCP_SOLVED : CN_LCP_NUMERIC;
done:
    lemke_release(&L);
    return status;
}

/* Relative size of the diagonal shift of the regularised attempt (M + eps I is a P-matrix when
 * M is positive semidefinite), and of the perturbation of q of the perturbed attempt (distinct
 * positive amounts per row, a numerical stand-in for the lexicographic perturbation that removes
 * the ties of degenerate problems). Their results must still verify on the original problem. */
#define LEMKE_REGULARIZATION 1e-10
#define LEMKE_PERTURBATION 1e-10

/* Solve a modified copy of p (diagonal shift `eps`, q perturbed by up to `delta` per row) and
 * accept the result only if it verifies on p itself and the modification moved w by less than
 * the tolerance (a huge z could otherwise solve the modified problem but not p). */
static cnLcpStatus lemke_modified(const cnLcp *p, const cnLcpOptions *o, double eps,
                                  double delta, double *z, double *w, cnLcpInfo *cur) {
    int n = p->n;
    cnLcp mod = {0};
    if (n == 0 || cn_lcp_alloc(&mod, n) != CN_OK) return CN_LCP_NUMERIC;
    memcpy(mod.M, p->M, sizeof(double) * (size_t)n * n);
    for (int i = 0; i < n; i++) {
        mod.M[(size_t)i * n + i] += eps;
        double rnd = (double)(var_key(i) >> 11) * (1.0 / 9007199254740992.0); /* [0, 1) */
        mod.q[i] = p->q[i] + delta * (0.5 + rnd);
    }
    cnLcpStatus s = lemke_run(&mod, o, LEMKE_PIVOT_TOLS[0], true, z, w, cur);
    cn_lcp_free(&mod);
    double zmax = 0, qmax = 0;
    for (int i = 0; i < n && s == CN_LCP_SOLVED; i++) /* z is written only when solved */
        zmax = fmax(zmax, fabs(z[i])), qmax = fmax(qmax, fabs(p->q[i]));
    if (s == CN_LCP_SOLVED && eps * zmax + 1.5 * delta <= o->tol * qmax &&
        cn_lcp_finish(p, z, w, o->tol, &cur->residual)) {
        cur->refined = true;
        return CN_LCP_SOLVED;
    }
    return s == CN_LCP_SOLVED ? CN_LCP_NUMERIC : s;
}

cnLcpStatus cn_lcp_lemke(const cnLcp *p, const cnLcpOptions *opt, double *z, double *w,
                         cnLcpInfo *info) {
    cnLcpOptions o = opt ? *opt : cn_lcp_options_default();
    if (o.tol <= 0) o.tol = CN_LCP_DEFAULT_TOL;
    int n = p->n;
    double dmax = 0, qmax = 0;
    for (int i = 0; i < n; i++) {
        dmax = fmax(dmax, fabs(p->M[(size_t)i * n + i]));
        qmax = fmax(qmax, fabs(p->q[i]));
    }
    if (dmax == 0)
        for (size_t k = 0; k < (size_t)n * n; k++) dmax = fmax(dmax, fabs(p->M[k]));
    cnLcpInfo first, cur;
    memset(&first, 0, sizeof first);
    cnLcpStatus first_status = CN_LCP_NUMERIC;
    int total = 0;
    /* Attempts: the exact problem with the spread covering vector; then, with d = 1 (for M
     * that is not copositive-plus, the covering vector changes whether Lemke finds a solution:
     * each d is tried), the exact problem, q perturbed (degenerate problems), the exact problem
     * with the other pivot tolerances, and M + eps I. */
    int ntols = (int)(sizeof LEMKE_PIVOT_TOLS / sizeof LEMKE_PIVOT_TOLS[0]);
    for (int t = 0; t < ntols + 3; t++) {
        cnLcpStatus s;
        if (t <= 1) s = lemke_run(p, &o, LEMKE_PIVOT_TOLS[0], t == 1, z, w, &cur);
        else if (t == 2) s = lemke_modified(p, &o, 0, LEMKE_PERTURBATION * qmax, z, w, &cur);
        else if (t <= ntols + 1) s = lemke_run(p, &o, LEMKE_PIVOT_TOLS[t - 2], true, z, w, &cur);
        else s = lemke_modified(p, &o, LEMKE_REGULARIZATION * dmax, 0, z, w, &cur);
        total += cur.pivots;
        if (s == CN_LCP_SOLVED) {
            cur.pivots = total;
            if (info) *info = cur;
            return s;
        }
        if (t == 0) first = cur, first_status = s;
        if (o.short_retries && (double)total * ((double)n * n) > LEMKE_RETRY_WORK) break;
        /* the default budget is spent once: a path that long is not shortened by another pivot
         * tolerance or a perturbation, which are for rounding trouble (they get 50 n + 1000) */
        if (t == 0 && s == CN_LCP_MAX_PIVOTS && o.max_pivots <= 0) o.max_pivots = 50 * n + 1000;
    }
    first.pivots = total;
    if (info) *info = first;
    return first_status;
}
