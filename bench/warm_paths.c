/* Warm-started path samples against cold ones: each plan is simulated REPEATS times with every
 * sample's contact LCP solved from scratch (cnSimOptions.cold) and REPEATS times warm-started from
 * the previous samples' bases, in one process. Prints one Markdown row per plan: LCP solves, how
 * many the warm run solved on a remembered basis, pivots cold and warm, the median LCP time per
 * solve cold and warm and their ratio, the time of a warm-started solve alone (the others went
 * cold after the remembered bases failed) against a cold one, and the median whole-simulation
 * time per solve (contacts, LP and all) cold and warm. The verdicts of the two runs must agree (exit 1 if not).
 *   usage: warm_paths [--repeats R] ASSEMBLY.json[:PLAN.json] ...      (make bench) */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "bench.h"
#include "cairn/cairn.h"


typedef struct {
    long solves, warm, pivots, samples;
    double lcp_median, total_median, hit_median; /* seconds per run (hit: warm-started solves) */
    bool stable;
} Run;

static int run(const cnAssembly *a, bool cold, int repeats, Run *out) {
    double *lcp = malloc(sizeof(double) * (size_t)repeats);
    double *tot = malloc(sizeof(double) * (size_t)repeats);
    double *hit = malloc(sizeof(double) * (size_t)repeats);
    if (!lcp || !tot || !hit) return 1;
    for (int k = 0; k < repeats; k++) {
        cnSimOptions o = cn_sim_options_default();
        o.cold = cold;
        cnSimResult r;
        cnDiag d;
        cn_diag_clear(&d);
        double t0 = bench_now();
        if (cn_simulate(a, &o, &r, &d) != CN_OK) {
            fprintf(stderr, "warm_paths: %s\n", d.message);
            free(lcp);
            free(tot);
            free(hit);
            return 1;
        }
        tot[k] = bench_now() - t0;
        lcp[k] = r.lcp_seconds;
        hit[k] = r.lcp_warm_seconds;
        out->solves = r.lcp_solves;
        out->warm = r.lcp_warm;
        out->pivots = r.lcp_pivots;
        out->samples = r.nsamples;
        out->stable = r.stable;
        cn_sim_result_free(&r);
    }
    qsort(lcp, (size_t)repeats, sizeof(double), bench_cmp_double);
    qsort(tot, (size_t)repeats, sizeof(double), bench_cmp_double);
    qsort(hit, (size_t)repeats, sizeof(double), bench_cmp_double);
    out->lcp_median = lcp[repeats / 2];
    out->total_median = tot[repeats / 2];
    out->hit_median = hit[repeats / 2];
    free(lcp);
    free(tot);
    free(hit);
    return 0;
}

int main(int argc, char **argv) {
    int repeats = 200, bad = 0;
    double sum_cold = 0, sum_warm = 0, hit_sum = 0, hit_cold = 0;
    long hit_n = 0;
    printf("| plan | LCP solves | warm-started | pivots cold | pivots warm | LCP µs/solve cold | "
           "LCP µs/solve warm | warm / cold | µs per warm-started solve | that / cold | whole "
           "µs/solve cold | whole µs/solve warm |\n");
    printf("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--repeats") && i + 1 < argc) {
            repeats = atoi(argv[++i]);
            if (repeats < 1) repeats = 1;
            continue;
        }
        char path[4096];
        snprintf(path, sizeof path, "%s", argv[i]);
        char *plan = strchr(path, ':');
        if (plan) *plan++ = '\0';
        cnAssembly *a = NULL;
        cnDiag d;
        cn_diag_clear(&d);
        if (cn_assembly_load_with_plan(path, plan, &a, &d) != CN_OK) {
            fprintf(stderr, "warm_paths: %s: %s\n", argv[i], d.message);
            bad = 1;
            continue;
        }
        Run c = {0}, w = {0};
        if (run(a, true, repeats, &c) || run(a, false, repeats, &w)) {
            bad = 1;
            cn_assembly_free(a);
            continue;
        }
        cn_assembly_free(a);
        if (c.stable != w.stable || c.samples != w.samples) {
            fprintf(stderr, "warm_paths: %s: cold and warm runs disagree\n", argv[i]);
            bad = 1;
        }
        if (c.solves == 0) continue;
        const char *name = plan ? strrchr(plan, '/') : strrchr(path, '/');
        name = name ? name + 1 : (plan ? plan : path);
        double lc = 1e6 * c.lcp_median / (double)c.solves, lw = 1e6 * w.lcp_median / (double)w.solves;
        double lh = w.warm ? 1e6 * w.hit_median / (double)w.warm : 0;
        sum_cold += c.lcp_median;
        sum_warm += w.lcp_median;
        if (w.warm) hit_sum += w.hit_median, hit_n += w.warm, hit_cold += c.lcp_median / (double)c.solves * (double)w.warm;
        char hs[64] = "- | -";
        if (w.warm) snprintf(hs, sizeof hs, "%.2f | %.2f", lh, lh / lc);
        printf("| %s | %ld | %ld | %ld | %ld | %.2f | %.2f | %.2f | %s | %.1f | %.1f |\n", name,
               c.solves, w.warm, c.pivots, w.pivots, lc, lw, lw / lc, hs,
               1e6 * c.total_median / (double)c.solves, 1e6 * w.total_median / (double)w.solves);
    }
    if (sum_cold > 0)
        printf("\nAll plans (median of %d runs each): LCP time warm / cold = %.2f; a warm-started "
               "solve costs %.2f of a cold solve of the same plan\n",
               repeats, sum_warm / sum_cold, hit_cold > 0 ? hit_sum / hit_cold : 0);
    return bad;
}
