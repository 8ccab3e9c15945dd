/* The growth of an open-addressing index table (core.h): the planners' state sets. */
#include "core.h"

int cn_hash_room(int **slot, size_t *mask, int n, cnHashOf hash_of, const void *ctx) {
    if ((size_t)(n + 1) * 2 <= *mask) return 0;
    size_t size = (*mask + 1) * 2;
    int *grown = cn_calloc(size, sizeof(int));
    if (!grown) return -1;
    for (int k = 0; k < n; k++) grown[cn_hash_free_slot(grown, size - 1, hash_of(ctx, k))] = k + 1;
    cn_free(*slot);
    *slot = grown;
    *mask = size - 1;
    return 0;
}
