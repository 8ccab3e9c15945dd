/* The numerical libraries' run-time settings the program chooses for itself. Both libraries are
 * found by name at run time (the program links neither itself; either may be absent). A program
 * is the place for this: the library leaves its caller's thread and kernel settings alone. */
#include <dlfcn.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/auxv.h>
#include <unistd.h>

#include "numerics.h"

/* CHOLMOD's supernodal factorisation opens OpenMP regions of a fixed width (four threads, built
 * in) and the BLAS under it has its own pool; on a few shared cores their hand-offs cost more
 * than they save (docs/bench.md). One thread also keeps the sums in one order, so a verdict's
 * numbers repeat run to run. */
void cli_numerics_one_thread(void) {
    void (*levels)(int), (*blas)(int);
    *(void **)&levels = dlsym(RTLD_DEFAULT, "omp_set_max_active_levels"); /* POSIX's idiom */
    *(void **)&blas = dlsym(RTLD_DEFAULT, "openblas_set_num_threads");
    if (levels) levels(0); /* every OpenMP region inactive: one thread */
    if (blas) blas(1);
}

/* OpenBLAS (built with DYNAMIC_ARCH, as Debian's) picks its kernels by the processor's model
 * number when it is loaded, before main, and for some models newer than itself takes its SSE3
 * kernel, "Prescott": Debian 12's 0.3.21 does for Intel family 6 models 192 to 207 (this
 * machine's Xeon is 207, Emerald Rapids). CHOLMOD's dense updates then run at a fraction of the
 * processor's speed (docs/bench.md). OpenBLAS's only way to choose another is the
 * environment variable OPENBLAS_CORETYPE, read at load; so when it chose Prescott on a processor
 * whose flags say it runs more, the program sets the variable and starts itself again, once
 * (set, the variable stops a second start; set by the user, it is left alone). The same start
 * sets the size of OpenBLAS's thread pool (below). The new start
 * runs the program's own file (by its path, so that the process keeps its name), and not when
 * the loader was run by hand ("ld.so ./cairn ...": the loader is then the program's file), nor
 * under valgrind, whose child would run untraced. The kernels' sums differ in the last bits;
 * every answer is verified as before. */
static const char *kernel_for_cpu(void) {
    __builtin_cpu_init(); /* its flags count only what the OS saves (XCR0) */
    if (__builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512cd"))
        return "SkylakeX";
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) return "Haswell";
    return NULL;
}

void cli_blas_kernel(char **argv) {
#if defined(__linux__) && (defined(__x86_64__) || defined(__i386__))
    if (getauxval(AT_BASE) == 0) return;
    const char *preload = getenv("LD_PRELOAD");
    if (preload && strstr(preload, "vgpreload")) return;
    char *(*corename)(void), *(*config)(void);
    int (*threads)(void);
    *(void **)&corename = dlsym(RTLD_DEFAULT, "openblas_get_corename");
    *(void **)&config = dlsym(RTLD_DEFAULT, "openblas_get_config");
    *(void **)&threads = dlsym(RTLD_DEFAULT, "openblas_get_num_threads");
    if (!corename || !config) return;
    const char *want = NULL;
    if (!getenv("OPENBLAS_CORETYPE")) {
        const char *now = corename(), *built = config();
        if (now && strcasecmp(now, "Prescott") == 0 && built && strstr(built, "DYNAMIC_ARCH"))
            want = kernel_for_cpu();
    }
    /* OpenBLAS starts its thread pool at load, each thread with its own buffers: under a
     * memory limit (ulimit -v) a thread that cannot get them loops and the process never
     * exits. The program runs the BLAS on one thread anyway (cli_numerics_one_thread), so it
     * starts again with the pool of one unless the user chose its size. */
    bool pool = !getenv("OPENBLAS_NUM_THREADS") && threads && threads() > 1;
    if (!want && !pool) return;
    char self[4096];
    ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
    if (len <= 0 || (size_t)len >= sizeof self - 1) return;
    self[len] = '\0';
    const char *path = strstr(self, " (deleted)") ? "/proc/self/exe" : self; /* replaced meanwhile */
    if (want && setenv("OPENBLAS_CORETYPE", want, 1) != 0) return;
    if (pool && setenv("OPENBLAS_NUM_THREADS", "1", 1) != 0) return;
    execv(path, argv);
    /* not started again: go on with the library as loaded */
    if (want) unsetenv("OPENBLAS_CORETYPE");
    if (pool) unsetenv("OPENBLAS_NUM_THREADS");
#else
    (void)argv;
#endif
}
