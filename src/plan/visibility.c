/* Shortest paths over a visibility graph whose edges are tested lazily (the route planners of
 * paths2.c and paths3.c): Dijkstra over every node pair, a leg tested for obstacles only when it
 * would shorten a path. */
#include <math.h>

#include "core.h"
#include "paths2.h"

void cn_vis_dijkstra(const cnVisGraph *g, double *dist, int *prev, unsigned char *done) {
    int m = g->m, dim = g->dim;
    const double *node = g->node;
    for (int i = 0; i < m; i++) dist[i] = INFINITY, prev[i] = -1, done[i] = 0;
    dist[0] = 0;
    for (int it = 0; it < m; it++) {
        int u = -1;
        for (int i = 0; i < m; i++)
            if (!done[i] && dist[i] < INFINITY && (u < 0 || dist[i] < dist[u])) u = i;
        if (u < 0) break;
        done[u] = 1;
        if (u >= g->ends) continue; /* an end is reached, never left */
        const double *nu = node + (size_t)u * (size_t)dim;
        if (u >= g->inside_from && g->blocked(g->ctx, nu, nu)) { /* inside an obstacle */
            if (g->inside_drops) dist[u] = INFINITY;
            continue;
        }
        for (int v = 0; v < m; v++) {
            if (done[v]) continue;
            const double *nv = node + (size_t)v * (size_t)dim;
            double w;
            if (dim == 2) {
                w = hypot(nv[0] - nu[0], nv[1] - nu[1]);
            } else {
                double d[3];
                cn_sub3(nv, nu, d);
                w = cn_norm3(d);
            }
            if (dist[u] + w >= dist[v]) continue;
            if (!g->blocked(g->ctx, nu, nv)) dist[v] = dist[u] + w, prev[v] = u;
        }
    }
}
