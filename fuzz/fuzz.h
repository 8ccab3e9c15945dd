/* The entry point every fuzz target defines: libFuzzer calls it (make fuzz), and so does
 * replay_main.c, which replays the seed corpus and every past finding under `make test`. */
#ifndef CAIRN_FUZZ_H
#define CAIRN_FUZZ_H
#include <stdarg.h>
#include <stddef.h>
#include <stdio.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* The input as a NUL-terminated string (the readers take text); free() it. */
static inline char *fuzz_text(const uint8_t *data, size_t size) {
    char *s = malloc(size + 1);
    if (!s) abort();
    memcpy(s, data, size);
    s[size] = 0;
    return s;
}
/* A growing text buffer for the generators that write an assembly as JSON. */
typedef struct {
    char *s;
    size_t len, cap;
} Buf;

static inline void put(Buf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static inline void put(Buf *b, const char *fmt, ...) {
    for (;;) {
        va_list ap;
        va_start(ap, fmt);
        int k = vsnprintf(b->s + b->len, b->cap - b->len, fmt, ap);
        va_end(ap);
        if (k >= 0 && (size_t)k < b->cap - b->len) {
            b->len += (size_t)k;
            return;
        }
        b->cap = 2 * b->cap + (size_t)(k > 0 ? k : 64);
        b->s = realloc(b->s, b->cap);
        if (!b->s) abort();
    }
}
#endif
