/* Minimal test macros: a failed check prints file:line and the expression, counts, and the test
 * binary exits non-zero at the end. */
#ifndef CAIRN_TEST_H
#define CAIRN_TEST_H

#include <math.h>
#include <stdio.h>

extern int cn_test_failures;
extern int cn_test_checks;

#define CHECK(cond)                                                                          \
    do {                                                                                     \
        cn_test_checks++;                                                                    \
        if (!(cond)) {                                                                       \
            cn_test_failures++;                                                              \
            fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond);         \
        }                                                                                    \
    } while (0)

#define CHECK_MSG(cond, ...)                                                                 \
    do {                                                                                     \
        cn_test_checks++;                                                                    \
        if (!(cond)) {                                                                       \
            cn_test_failures++;                                                              \
            fprintf(stderr, "%s:%d: check failed: %s: ", __FILE__, __LINE__, #cond);         \
            fprintf(stderr, __VA_ARGS__);                                                    \
            fprintf(stderr, "\n");                                                           \
        }                                                                                    \
    } while (0)

#define CHECK_NEAR(a, b, tol)                                                                \
    do {                                                                                     \
        double cn_a_ = (a), cn_b_ = (b);                                                     \
        cn_test_checks++;                                                                    \
        if (!(fabs(cn_a_ - cn_b_) <= (tol))) {                                               \
            cn_test_failures++;                                                              \
            fprintf(stderr, "%s:%d: %s = %.17g, expected %s = %.17g (tol %g)\n", __FILE__,   \
                    __LINE__, #a, cn_a_, #b, cn_b_, (double)(tol));                          \
        }                                                                                    \
    } while (0)

/* Deterministic pseudo-random numbers (xorshift64*), so failures reproduce. */
typedef struct {
    unsigned long long s;
} cnRng;
static inline double cn_rng_uniform(cnRng *r) {
    r->s ^= r->s >> 12;
    r->s ^= r->s << 25;
    r->s ^= r->s >> 27;
    return (double)((r->s * 2685821657736338717ULL) >> 11) * (1.0 / 9007199254740992.0);
}
static inline double cn_rng_range(cnRng *r, double lo, double hi) {
    return lo + (hi - lo) * cn_rng_uniform(r);
}

#define CN_TEST_MODULE(name, memcheck) void test_##name(void);
#include "modules.def"
#undef CN_TEST_MODULE

#endif
