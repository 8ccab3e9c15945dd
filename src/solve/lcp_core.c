/* LCP problems: allocation, the text format, residuals and verification, feasibility. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "solve.h"

cnLcpOptions cn_lcp_options_default(void) {
    cnLcpOptions o = {0, CN_LCP_DEFAULT_TOL, false};
    return o;
}

cnLcpOptions cn_lcp_begin(const cnLcpOptions *opt, int default_budget, cnLcpInfo **info,
                          cnLcpInfo *scratch) {
    cnLcpOptions o = opt ? *opt : cn_lcp_options_default();
    if (o.tol <= 0) o.tol = CN_LCP_DEFAULT_TOL;
    if (o.max_pivots <= 0) o.max_pivots = default_budget;
    if (!*info) *info = scratch;
    memset(*info, 0, sizeof **info);
    (*info)->ray_variable = -1;
    return o;
}

cnStatus cn_lcp_alloc(cnLcp *p, int n) {
    p->n = n;
    p->M = cn_calloc((size_t)n * (size_t)n + 1, sizeof(double));
    p->q = cn_calloc((size_t)n + 1, sizeof(double));
    if (!p->M || !p->q) {
        cn_lcp_free(p);
        return CN_ERR_MEMORY;
    }
    return CN_OK;
}

void cn_lcp_free(cnLcp *p) {
    if (!p) return;
    cn_free(p->M);
    cn_free(p->q);
    p->M = p->q = NULL;
    p->n = 0;
}

const char *cn_lcp_status_name(cnLcpStatus s) {
    switch (s) {
    case CN_LCP_SOLVED: return "solved";
    case CN_LCP_RAY: return "secondary ray";
    case CN_LCP_INFEASIBLE: return "infeasible";
    case CN_LCP_MAX_PIVOTS: return "pivot limit";
    case CN_LCP_NUMERIC: return "numerical failure";
    }
    return "unknown";
}

/* A tokenizer that remembers line and column for diagnostics. */
typedef struct {
    const char *s;
    int line, col;
} cnTok;

static void tok_skip(cnTok *t) {
    while (*t->s == ' ' || *t->s == '\t' || *t->s == '\n' || *t->s == '\r') {
        if (*t->s == '\n') t->line++, t->col = 1;
        else t->col++;
        t->s++;
    }
}

/* Read one finite number; returns 0 on success, 1 at end of text, -1 on a bad token. */
static int tok_number(cnTok *t, double *v, int *line, int *col) {
    tok_skip(t);
    *line = t->line;
    *col = t->col;
    if (!*t->s) return 1;
    char *end;
    errno = 0;
    *v = strtod(t->s, &end);
    if (end == t->s || (*end && !strchr(" \t\r\n", *end)) || !isfinite(*v) || errno == ERANGE)
        return -1;
    t->col += (int)(end - t->s);
    t->s = end;
    return 0;
}

cnStatus cn_lcp_read_string(const char *text, cnLcp *p, cnDiag *diag) {
    cnTok t = {text, 1, 1};
    double v;
    int line, col;
    char where[64];
    int r = tok_number(&t, &v, &line, &col);
    snprintf(where, sizeof where, "%d:%d", line, col);
    if (r != 0)
        return cn_diag_set(diag, CN_ERR_INPUT, where,
                           "expected the problem size n (a positive integer) first");
    if (v != floor(v) || v < 1 || v > 20000)
        return cn_diag_set(diag, CN_ERR_INPUT, where,
                           "the problem size n must be an integer from 1 to 20000, got %g", v);
    int n = (int)v;
    size_t total = (size_t)n * (size_t)n + (size_t)n;
    /* k numbers take at least 2k - 1 characters: a text too short for n is reported without
     * allocating n*n doubles first (a 10-byte file saying n = 20000 asked for 3.2 GB) */
    bool too_short = total > (strlen(t.s) + 1) / 2;
    if (!too_short && cn_lcp_alloc(p, n) != CN_OK)
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory for an LCP of size %d", n);
    for (size_t k = 0; k < total; k++) {
        r = tok_number(&t, &v, &line, &col);
        snprintf(where, sizeof where, "%d:%d", line, col);
        if (r == 0 && too_short) continue;
        if (r != 0) {
            if (!too_short) cn_lcp_free(p);
            if (r > 0)
                return cn_diag_set(diag, CN_ERR_INPUT, where,
                                   "the file ends after %zu numbers; n = %d needs n*n + n = %zu "
                                   "(M row by row, then q)",
                                   k, n, total);
            return cn_diag_set(diag, CN_ERR_INPUT, where,
                               "not a finite number; the format is n, M row by row, then q");
        }
        if (k < (size_t)n * (size_t)n) p->M[k] = v;
        else p->q[k - (size_t)n * (size_t)n] = v;
    }
    r = tok_number(&t, &v, &line, &col);
    if (r != 1) {
        snprintf(where, sizeof where, "%d:%d", line, col);
        cn_lcp_free(p);
        return cn_diag_set(diag, CN_ERR_INPUT, where,
                           "unexpected text after the %zu numbers of M and q", total);
    }
    return CN_OK;
}

/* An LCP file is read whole: at most this many bytes (n = 8,000 written out in full). */
#define CN_LCP_MAX_FILE_BYTES (1 << 30)

cnStatus cn_lcp_read_file(const char *path, cnLcp *p, cnDiag *diag) {
    bool in = !strcmp(path, "-"); /* standard input */
    FILE *f = in ? stdin : fopen(path, "rb");
    if (!f) return cn_diag_set(diag, CN_ERR_IO, "", "cannot open: %s", strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        if (!in) fclose(f);
        return cn_diag_set(diag, CN_ERR_IO, "", "is a directory; give an LCP file");
    }
    size_t cap = 1 << 16, len = 0;
    char *buf = cn_malloc(cap);
    for (;;) {
        if (!buf) {
            if (!in) fclose(f);
            return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading the file");
        }
        size_t got = fread(buf + len, 1, cap - len - 1, f);
        /* not text: refused at the first NUL, before reading on (a device such as /dev/zero
         * would never end) */
        if (memchr(buf + len, '\0', got)) {
            if (!in) fclose(f);
            cn_free(buf);
            return cn_diag_set(diag, CN_ERR_INPUT, "", "the file contains a NUL byte; it is not text");
        }
        len += got;
        if (got == 0) break;
        if (len > CN_LCP_MAX_FILE_BYTES) {
            if (!in) fclose(f);
            cn_free(buf);
            return cn_diag_set(diag, CN_ERR_INPUT, "", "the file is larger than %d MiB: cairn reads LCPs "
                               "of at most that size", CN_LCP_MAX_FILE_BYTES >> 20);
        }
        if (len + 1 >= cap) {
            cap *= 2;
            char *nb = cn_realloc(buf, cap);
            if (!nb) cn_free(buf);
            buf = nb;
        }
    }
    if (!in) fclose(f);
    buf[len] = '\0';
    if (strlen(buf) != len) {
        cn_free(buf);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "the file contains a NUL byte; it is not text");
    }
    cnStatus s = cn_lcp_read_string(buf, p, diag);
    cn_free(buf);
    return s;
}

double cn_lcp_row_norm(const cnLcp *p) {
    int n = p->n;
    double mmax = 0;
    for (int i = 0; i < n; i++) {
        const double *Mi = p->M + (size_t)i * n;
        double a[4] = {0, 0, 0, 0};
        int j = 0;
        for (; j + 4 <= n; j += 4)
            for (int k = 0; k < 4; k++) a[k] += fabs(Mi[j + k]);
        for (; j < n; j++) a[0] += fabs(Mi[j]);
        double rowabs = (a[0] + a[1]) + (a[2] + a[3]);
        if (!isfinite(rowabs)) return INFINITY; /* a NaN or an infinity */
        mmax = fmax(mmax, rowabs);
    }
    return mmax;
}

double cn_lcp_residual_at(const cnLcp *p, const double *z, double *w, double mnorm) {
    int n = p->n;
    double qmax = 0, zmax = 0, worst = 0;
    bool bad = !isfinite(mnorm); /* a NaN or an infinity met anywhere fails the whole */
    /* the products of z's nonzero entries only (the same sums: the others add zeros) */
    int *nz = cn_malloc(sizeof(int) * (size_t)(n + 1)), nnz = 0;
    for (int j = 0; j < n && nz; j++)
        if (z[j] != 0) nz[nnz++] = j;
    for (int i = 0; i < n; i++) {
        double s = p->q[i];
        const double *Mi = p->M + (size_t)i * n;
        if (nz)
            for (int k = 0; k < nnz; k++) s += Mi[nz[k]] * z[nz[k]];
        else
            for (int j = 0; j < n; j++) s += Mi[j] * z[j];
        if (w) w[i] = s;
        qmax = cn_max_nan(qmax, fabs(p->q[i]));
        zmax = cn_max_nan(zmax, fabs(z[i]));
        /* violation: z < 0, w < 0, or both positive (complementarity: min(z, w) != 0) */
        double e = cn_max_nan(cn_max_nan(-z[i], -s), fabs(z[i] < s ? z[i] : s));
        if (z[i] != z[i] || s != s || e != e) bad = true;
        else if (e > worst) worst = e;
    }
    cn_free(nz);
    double scale = cn_max_nan(cn_max_nan(qmax, mnorm * zmax), 1e-300);
    return bad || !isfinite(scale) ? NAN : worst / scale;
}

double cn_lcp_residual(const cnLcp *p, const double *z, double *w) {
    return cn_lcp_residual_at(p, z, w, cn_lcp_row_norm(p));
}

bool cn_lcp_finish_at(const cnLcp *p, double *z, double *w, double tol, double *residual, double mnorm) {
    for (int i = 0; i < p->n; i++)
        if (z[i] < 0) z[i] = 0; /* round-off: verification below decides whether that is fine */
    double r = cn_lcp_residual_at(p, z, w, mnorm);
    if (residual) *residual = r;
    return r <= tol;
}

bool cn_lcp_finish(const cnLcp *p, double *z, double *w, double tol, double *residual) {
    return cn_lcp_finish_at(p, z, w, tol, residual, cn_lcp_row_norm(p));
}

bool cn_lcp_verify(const cnLcp *p, const double *z, double tol, double *residual) {
    double r = cn_lcp_residual(p, z, NULL);
    if (residual) *residual = r;
    return r <= tol; /* false for NaN */
}

cnStatus cn_lcp_feasible(const cnLcp *p, bool *feasible, cnDiag *diag) {
    int n = p->n;
    int *colptr = cn_malloc(sizeof(int) * (size_t)(n + 1));
    int *rows = cn_malloc(sizeof(int) * ((size_t)n * n + 1));
    double *vals = cn_malloc(sizeof(double) * ((size_t)n * n + 1));
    double *rhs = cn_malloc(sizeof(double) * (size_t)(n + 1));
    double *x = cn_malloc(sizeof(double) * (size_t)(n + 1));
    cnStatus s = CN_ERR_MEMORY;
    if (colptr && rows && vals && rhs && x) {
        int k = 0;
        for (int j = 0; j < n; j++) {
            colptr[j] = k;
            for (int i = 0; i < n; i++) {
                double v = p->M[(size_t)i * n + j];
                if (v != 0) rows[k] = i, vals[k] = v, k++;
            }
        }
        colptr[n] = k;
        for (int i = 0; i < n; i++) rhs[i] = -p->q[i];
        cnLpProblem lp = {n, 0, n, colptr, rows, vals, rhs, NULL, false, CN_LP_PRIMAL_AUTO, false, false};
        s = cn_lp_solve(&lp, feasible, x, diag);
    } else {
        cn_diag_oom(diag);
    }
    cn_free(colptr);
    cn_free(rows);
    cn_free(vals);
    cn_free(rhs);
    cn_free(x);
    return s;
}

cnStatus cn_lcp_write(FILE *f, const cnLcp *p) {
    int n = p->n;
    fprintf(f, "%d\n", n);
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++)
            fprintf(f, "%.17g%c", p->M[(size_t)i * n + j], j + 1 < n ? ' ' : '\n');
    for (int i = 0; i < n; i++) fprintf(f, "%.17g%c", p->q[i], i + 1 < n ? ' ' : '\n');
    return ferror(f) ? CN_ERR_IO : CN_OK;
}
