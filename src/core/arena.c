/* An arena: blocks handed out from larger chunks, all freed together. A result that owns many
 * small arrays (the planner's sequences, tables and trees) lives in one, so that building it
 * needs no per-field cleanup on every error path. */
#include <stdalign.h>
#include <string.h>

#include "core.h"

/* Bytes per chunk; a larger request gets a chunk of its own. */
#define CN_ARENA_CHUNK 16384

struct cnArena {
    cnArena *next; /* the previous chunk */
    size_t used, cap;
    alignas(max_align_t) unsigned char data[];
};

void *cn_arena_alloc(cnArena **arena, size_t count, size_t size) {
    if (size && count > ((size_t)-1 - CN_ARENA_CHUNK) / size) return NULL;
    size_t bytes = count * size, align = alignof(max_align_t);
    bytes = (bytes + align - 1) / align * align;
    if (bytes == 0) bytes = align;
    cnArena *a = *arena;
    if (!a || a->cap - a->used < bytes) {
        size_t cap = bytes > CN_ARENA_CHUNK ? bytes : CN_ARENA_CHUNK;
        cnArena *n = cn_malloc(sizeof(cnArena) + cap);
        if (!n) return NULL;
        n->next = a;
        n->used = 0;
        n->cap = cap;
        *arena = a = n;
    }
    void *p = a->data + a->used;
    a->used += bytes;
    memset(p, 0, bytes);
    return p;
}

char *cn_arena_strdup(cnArena **arena, const char *s) {
    size_t n = strlen(s) + 1;
    char *d = cn_arena_alloc(arena, n, 1);
    if (d) memcpy(d, s, n);
    return d;
}

void cn_arena_free(cnArena *arena) {
    while (arena) {
        cnArena *next = arena->next;
        cn_free(arena);
        arena = next;
    }
}
