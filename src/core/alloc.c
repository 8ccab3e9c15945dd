/* The counted allocator: every library allocation goes through here, so the live and peak
 * byte counts are known (reported by benchmarks and large runs). A size header precedes each
 * block. Not thread-safe counters: cairn is single-threaded. */
#include <stdlib.h>
#include <string.h>

#include "core.h"

typedef union {
    size_t size;
    max_align_t align;
} cnHeader;

static size_t g_live, g_peak;

static void *account(cnHeader *h, size_t bytes) {
    h->size = bytes;
    g_live += bytes;
    if (g_live > g_peak) g_peak = g_live;
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
    g_live -= old;
    return account(n, bytes);
}

void cn_free(void *p) {
    if (!p) return;
    cnHeader *h = (cnHeader *)p - 1;
    g_live -= h->size;
    free(h);
}

char *cn_strdup(const char *s) {
    size_t n = strlen(s) + 1;
    char *d = cn_malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

size_t cn_alloc_live_bytes(void) { return g_live; }
size_t cn_alloc_peak_bytes(void) { return g_peak; }
