/* LCP solvers side by side: cairn's Lemke (lexicographic ratio test) and principal pivoting
 * against Siconos Numerics' lexicographic Lemke, pivot method and PGS, on the same problems in
 * one process. For each problem: the median time of repeated solves (reading excluded), whether
 * each solution verifies (cn_lcp_verify: z >= 0, w = Mz + q >= 0, z.w = 0 to 1e-9 relative),
 * and the ratio Siconos Lemke / cairn Lemke.
 *   usage: lcp_vs_siconos [--budget SECONDS] FILE.lcp ...      (make bench) */
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <LCP_Solvers.h>
#include <LinearComplementarityProblem.h>
#include <NumericsMatrix.h>
#include <SolverOptions.h>
#include <lcp_cst.h>

#include "bench.h"
#include "cairn/cairn.h"


enum { CAIRN_LEMKE, CAIRN_PIVOT, SIC_LEMKE, SIC_PIVOT, SIC_PGS, NSOLVERS };
static const int kSiconosId[NSOLVERS] = {0, 0, SICONOS_LCP_LEMKE, SICONOS_LCP_PIVOT, SICONOS_LCP_PGS};

/* Siconos prints its diagnostics on standard output: the table goes to `out` (the original
 * standard output) and file descriptor 1 to /dev/null, once, outside the timings */
static FILE *out;

/* one solve; returns whether the solution verifies (its relative residual in *res) */
static bool solve(int which, const cnLcp *p, LinearComplementarityProblem *sp, double *z,
                  double *w, double *res) {
    if (which == CAIRN_LEMKE || which == CAIRN_PIVOT) {
        cnLcpOptions o = cn_lcp_options_default();
        cnLcpInfo info;
        cnLcpStatus st = which == CAIRN_LEMKE ? cn_lcp_lemke(p, &o, z, w, &info)
                                              : cn_lcp_pivot(p, &o, z, w, &info);
        *res = cn_lcp_residual(p, z, w);
        return st == CN_LCP_SOLVED && cn_lcp_verify(p, z, 1e-9, res);
    }
    SolverOptions *opt = solver_options_create(kSiconosId[which]);
    if (which == SIC_PGS) {
        opt->iparam[SICONOS_IPARAM_MAX_ITER] = 100000;
        opt->dparam[SICONOS_DPARAM_TOL] = 1e-12;
    } else {
        opt->iparam[SICONOS_IPARAM_MAX_ITER] = 100 * p->n + 1000;
    }
    memset(z, 0, sizeof(double) * (size_t)p->n);
    memset(w, 0, sizeof(double) * (size_t)p->n);
    int info = 0;
    if (which == SIC_LEMKE) lcp_lexicolemke(sp, z, w, &info, opt);
    else if (which == SIC_PIVOT) lcp_pivot(sp, z, w, &info, opt);
    else lcp_pgs(sp, z, w, &info, opt);
    solver_options_delete(opt);
    bool ok = cn_lcp_verify(p, z, 1e-9, res);
    return info == 0 && ok;
}

int main(int argc, char **argv) {
    double budget = 0.5; /* seconds of repeated solves per solver and problem */
    double give_up = 20;  /* a solver that took longer than this is not run on larger problems */
    int gave_up_at[NSOLVERS] = {0};
    int first = 1;
    if (argc > 2 && !strcmp(argv[1], "--budget")) budget = atof(argv[2]), first = 3;
    if (argc > first + 1 && !strcmp(argv[first], "--give-up")) give_up = atof(argv[first + 1]), first += 2;
    fflush(stdout);
    out = fdopen(dup(1), "w");
    int dn = open("/dev/null", O_WRONLY);
    if (!out || dn < 0) return 1;
    dup2(dn, 1);
    close(dn);
    fprintf(out, "| problem | n | cairn Lemke | cairn pivot | Siconos lexicolemke | Siconos pivot | "
           "Siconos PGS | Siconos Lemke / cairn Lemke |\n|---|---|---|---|---|---|---|---|\n");
    for (int f = first; f < argc; f++) {
        cnLcp p = {0};
        cnDiag d;
        if (cn_lcp_read_file(argv[f], &p, &d) != CN_OK) {
            fprintf(stderr, "%s: %s: %s\n", argv[f], d.where, d.message);
            continue;
        }
        int n = p.n;
        double *colmajor = malloc(sizeof(double) * (size_t)n * (size_t)n);
        double *q = malloc(sizeof(double) * (size_t)n);
        double *z = calloc((size_t)n, sizeof(double)), *w = calloc((size_t)n, sizeof(double));
        for (int i = 0; i < n; i++) {
            q[i] = p.q[i];
            for (int j = 0; j < n; j++) colmajor[(size_t)j * n + i] = p.M[(size_t)i * n + j];
        }
        LinearComplementarityProblem sp;
        sp.size = n;
        sp.M = NM_create_from_data(NM_DENSE, n, n, colmajor);
        sp.q = q;
        const char *base = strrchr(argv[f], '/');
        fprintf(out, "| %s | %d |", base ? base + 1 : argv[f], n);
        double med[NSOLVERS];
        bool ok[NSOLVERS];
        for (int s = 0; s < NSOLVERS; s++) {
            med[s] = -1;
            ok[s] = false;
            if (s == CAIRN_PIVOT || s == SIC_PIVOT || s == SIC_PGS) {
                /* these need M symmetric positive semidefinite (or a P-matrix): try only then */
                bool sym = true;
                for (int i = 0; i < n && sym; i++)
                    for (int j = 0; j < i && sym; j++)
                        sym = p.M[(size_t)i * n + j] == p.M[(size_t)j * n + i];
                if (!sym) {
                    fprintf(out, " n/a |");
                    continue;
                }
            }
            if (gave_up_at[s] && n >= gave_up_at[s]) {
                fprintf(out, " skipped (> %.0f s at n = %d) |", give_up, gave_up_at[s]);
                continue;
            }
            double t[2001], res = 0;
            int k = 0;
            double start = bench_now();
            do {
                double t0 = bench_now();
                ok[s] = solve(s, &p, &sp, z, w, &res);
                t[k++] = bench_now() - t0;
            } while (k < 2001 && bench_now() - start < budget && (k < 3 || ok[s]));
            if (t[0] > give_up) gave_up_at[s] = n;
            qsort(t, (size_t)k, sizeof(double), bench_cmp_double);
            med[s] = t[k / 2];
            if (ok[s]) fprintf(out, " %.3g ms |", 1e3 * med[s]);
            else fprintf(out, " %.3g ms, not solved (residual %.1e) |", 1e3 * med[s], res);
        }
        if (ok[CAIRN_LEMKE] && ok[SIC_LEMKE]) fprintf(out, " %.1f |\n", med[SIC_LEMKE] / med[CAIRN_LEMKE]);
        else fprintf(out, " - |\n");
        fflush(out);
        NM_free(sp.M); /* frees colmajor (matrix0) and the struct */
        free(q);
        free(z);
        free(w);
        cn_lcp_free(&p);
    }
    return 0;
}
