/* The numerical libraries' run-time settings the program chooses for itself. Both libraries are
 * found by name at run time (the program links neither itself; either may be absent). A program
 * is the place for this: the library leaves its caller's thread and kernel settings alone. */
#include <dlfcn.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "numerics.h"

/* CHOLMOD's supernodal factorisation opens OpenMP regions of a fixed width (four threads, built
 * in) and the BLAS under it has its own pool; on two shared cores their hand-offs cost more than
 * they save: the 3-D vault of 10,000 voussoirs (bench/run.sh) took 46 s with 2.3 million context
 * switches, and 32 s with under 1,000 on one thread. One thread also keeps the sums in one order,
 * so a verdict's numbers repeat run to run. */
void cli_numerics_one_thread(void) {
    void (*levels)(int), (*blas)(int);
    *(void **)&levels = dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"); /* POSIX's idiom */
    *(void **)&blas = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    if (levels) levels(0); /* every OpenMP region inactive: one thread */
    if (blas) blas(1);
}

/* OpenBLAS picks its kernels by the processor's model number when it is loaded, before main, and
 * falls back to its oldest x86-64 kernel ("Prescott", SSE3) for a model newer than itself:
 * Debian 12's 0.3.21 on an Intel Xeon of model 207 (Emerald Rapids) does, and CHOLMOD's dense
 * updates then run at a fraction of the processor's speed (the 3-D vault of 10,000 voussoirs
 * without friction: 20.7 s, and 12.6 s with the AVX-512 kernel). Its only way to choose another
 * is the environment variable OPENBLAS_CORETYPE, read at load; so the program sets it from the
 * processor's own feature flags and starts itself again, once (the variable, set, stops a second
 * start; set by the user, it is left alone). Not under valgrind, whose child would run untraced
 * and whose processor has no AVX-512. The kernels' sums differ in the last bits only; every
 * answer is verified as before. */
static const char *kernel_for_cpu(void) {
    __builtin_cpu_init();
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512cd"))
        return "SkylakeX";
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
    return NULL;
}

void cli_blas_kernel(char **argv) {
#if defined(__linux__) && (defined(__x86_64__) || defined(__i386__))
    if (getenv("OPENBLAS_CORETYPE")) return;
    const char *preload = getenv("LD_PRELOAD");
    if (preload && strstr(preload, "vgpreload")) return;
    char *(*corename)(void);
    *(void **)&corename = dlsym(RTLD_DEFAULT, "openblas_get_corename");
    if (!corename) return;
    const char *now = corename();
    if (!now) return;
    /* the kernels with AVX2 or better: nothing to gain */
    static const char *const fast[] = {"haswell", "zen", "skylakex", "cooperlake", "sapphirerapids"};
    for (size_t i = 0; i < sizeof fast / sizeof fast[0]; i++)
        if (!strcasecmp(now, fast[i])) return;
    const char *want = kernel_for_cpu();
    if (!want || setenv("OPENBLAS_CORETYPE", want, 1) != 0) return;
    execv("/proc/self/exe", argv);
    unsetenv("OPENBLAS_CORETYPE"); /* not started again: go on with the kernel loaded */
#else
    (void)argv;
#endif
}
