/* A random symmetric positive definite LCP for the solver table: M = A^T A / n + 0.01 I with
 * A's entries uniform in [-1, 1], q uniform in [-1, 1] (about half of z positive at the
 * solution). Written in cairn's LCP text format (n, then M row by row, then q). The generator is
 * xorshift64*, so a seed gives the same problem on every machine.
 *   usage: gen_psd N SEED > FILE.lcp      (make bench) */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

static uint64_t state;

static double uniform(void) { /* in [-1, 1) */
    state ^= state >> 12;
    state ^= state << 25;
    state ^= state >> 27;
    uint64_t r = state * 0x2545F4914F6CDD1DULL;
    return (double)(r >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

int main(int argc, char **argv) {
    int n = argc == 3 ? atoi(argv[1]) : 0;
    if (n < 1 || n > 5000) {
        fprintf(stderr, "usage: gen_psd N SEED   (1 <= N <= 5000)\n");
        return 2;
    }
    state = 0x9E3779B97F4A7C15ULL ^ (uint64_t)strtoull(argv[2], NULL, 10);
    double *A = malloc(sizeof(double) * (size_t)n * n);
    double *row = malloc(sizeof(double) * (size_t)n);
    if (!A || !row) return 3;
    for (size_t i = 0; i < (size_t)n * n; i++) A[i] = uniform();
    printf("%d\n", n);
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) row[j] = 0;
        for (int k = 0; k < n; k++) {
            double a = A[(size_t)k * n + i];
            const double *Ak = A + (size_t)k * n;
            for (int j = 0; j < n; j++) row[j] += a * Ak[j];
        }
        for (int j = 0; j < n; j++) printf("%.17g ", row[j] / n + (i == j ? 0.01 : 0.0));
        printf("\n");
    }
    for (int i = 0; i < n; i++) printf("%.17g ", uniform());
    printf("\n");
    free(A);
    free(row);
    return 0;
}
