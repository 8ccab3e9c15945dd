/* Threads sharing assemblies (make test-tsan, built with ThreadSanitizer): eight threads check,
 * simulate and plan the same loaded assemblies at once, and every result must be the one a
 * single thread gets. The library keeps no state between calls and reads an assembly without
 * writing it; a data race on either fails the run under the sanitizer. */
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cairn/cairn.h"

#define NTHREADS 8
#define ROUNDS 3

static const char *const kFiles[] = {"examples/blocks.json", "examples/friction_drag.json",
                                     "examples/stack3d.json", "examples/fig15.json"};
#define NFILES (int)(sizeof kFiles / sizeof kFiles[0])

static cnAssembly *asm_[NFILES];
static cnVerdict want[NFILES];
static int want_steps[NFILES];
static int failures;
static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;

static void fail(const char *what, int f) {
    pthread_mutex_lock(&lock);
    failures++;
    fprintf(stderr, "thread_check: %s differs on %s\n", what, kFiles[f]);
    pthread_mutex_unlock(&lock);
}

/* A check and, with a plan, its simulation: the verdict and the steps' statuses. */
static void run(int f, cnVerdict *v, int *steps) {
    cnCheckOptions o = cn_check_options_default();
    cnCheckResult r;
    cnDiag d;
    *v = (cnVerdict)-1, *steps = -1;
    if (cn_check(asm_[f], &o, &r, &d) == CN_OK) {
        *v = r.verdict;
        cn_check_result_free(&r);
    }
    if (asm_[f]->nsteps > 0) {
        cnSimOptions so = cn_sim_options_default();
        cnSimResult sr;
        if (cn_simulate(asm_[f], &so, &sr, &d) == CN_OK) {
            *steps = 0;
            for (int k = 0; k < sr.nsteps; k++) *steps = 4 * *steps + (int)sr.steps[k].status;
            cn_sim_result_free(&sr);
        }
    }
}

static void *worker(void *arg) {
    int id = (int)(long)arg;
    for (int round = 0; round < ROUNDS; round++)
        for (int k = 0; k < NFILES; k++) {
            int f = (k + id) % NFILES; /* threads start on different files */
            cnVerdict v;
            int steps;
            run(f, &v, &steps);
            if (v != want[f]) fail("the verdict", f);
            if (steps != want_steps[f]) fail("the simulation", f);
        }
    return NULL;
}

int main(void) {
    cnDiag d;
    for (int f = 0; f < NFILES; f++) {
        if (cn_assembly_load_file(kFiles[f], &asm_[f], &d) != CN_OK) {
            fprintf(stderr, "thread_check: %s: %s\n", kFiles[f], d.message);
            return 2;
        }
        run(f, &want[f], &want_steps[f]);
    }
    pthread_t t[NTHREADS];
    for (long i = 0; i < NTHREADS; i++)
        if (pthread_create(&t[i], NULL, worker, (void *)i)) return 2;
    for (int i = 0; i < NTHREADS; i++) pthread_join(t[i], NULL);
    for (int f = 0; f < NFILES; f++) cn_assembly_free(asm_[f]);
    printf("thread_check: %d threads x %d rounds x %d assemblies, %d results differ\n", NTHREADS, ROUNDS,
           NFILES, failures);
    return failures ? 1 : 0;
}
