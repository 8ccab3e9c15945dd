/* The counted allocator: every library allocation goes through here, so the live and peak
 * byte counts are known (reported by benchmarks and large runs). A size header precedes each
 * block. The counters are atomic: the planner may simulate on two threads. */
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

#include "core.h"

typedef union {
    size_t size;
    max_align_t align;
} cnHeader;

static _Atomic size_t g_live, g_peak;

static void *account(cnHeader *h, size_t bytes) {
    h->size = bytes;
    size_t live = atomic_fetch_add_explicit(&g_live, bytes, memory_order_relaxed) + bytes;
    size_t peak = atomic_load_explicit(&g_peak, memory_order_relaxed);
    while (live > peak &&
           !atomic_compare_exchange_weak_explicit(&g_peak, &peak, live, memory_order_relaxed,
                                                  memory_order_relaxed)) {
    }
    return h + 1;
}

void *cn_malloc(size_t bytes) {
    cnHeader *h = malloc(sizeof(cnHeader) + (bytes ? bytes : 1));
    return h ? account(h, bytes) : NULL;
}

void *cn_calloc(size_t count, size_t size) {
    if (size && count > (((size_t)-1) - sizeof(cnHeader)) / size) return NULL;
    size_t bytes = count * size;
    cnHeader *h = calloc(1, sizeof(cnHeader) + (bytes ? bytes : 1));
    return h ? account(h, bytes) : NULL;
}

void *cn_realloc(void *p, size_t bytes) {
    if (!p) return cn_malloc(bytes);
    cnHeader *h = (cnHeader *)p - 1;
    size_t old = h->size;
    cnHeader *n = realloc(h, sizeof(cnHeader) + (bytes ? bytes : 1));
    if (!n) return NULL;
    atomic_fetch_sub_explicit(&g_live, old, memory_order_relaxed);
    return account(n, bytes);
}

void cn_free(void *p) {
    if (!p) return;
    cnHeader *h = (cnHeader *)p - 1;
    atomic_fetch_sub_explicit(&g_live, h->size, memory_order_relaxed);
    free(h);
}

char *cn_strdup(const char *s) {
    size_t n = strlen(s) + 1;
    char *d = cn_malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

size_t cn_alloc_live_bytes(void) { return atomic_load(&g_live); }
size_t cn_alloc_peak_bytes(void) { return atomic_load(&g_peak); }
