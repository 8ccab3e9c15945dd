/* plan: translational escape routes, 2-D (paths2.c) and 3-D (paths3.c). Private. */
#ifndef CAIRN_PATHS2_H
#define CAIRN_PATHS2_H

#include "pieces.h"

/* Most segments of a route the planner generates (cn_paths2). Paths given in files have no such
 * limit (CN_MAX_PATH_SEGMENTS). */
#define CN_ROUTE_MAX_SEGMENTS 8

/* ---- shortest paths over a lazily tested visibility graph (visibility.c) ---- */
typedef struct {
    int dim;            /* 2 or 3: coordinates per node */
    const double *node; /* m x dim; node 0 the start */
    int m;
    int ends;           /* nodes from this one on are ends: reached, never left (m: none) */
    int inside_from;    /* nodes from this one on are tested for lying inside an obstacle: such a
                           node is not left ... */
    bool inside_drops;  /* ... and with this, not reached either */
    bool (*blocked)(void *ctx, const double *a, const double *b); /* does leg a-b cross an obstacle? */
    void *ctx;
} cnVisGraph;

/* Dijkstra from node 0: dist (m) the lengths, prev (m) the previous node (-1: none); done (m) is
 * scratch. */
void cn_vis_dijkstra(const cnVisGraph *g, double *dist, int *prev, unsigned char *done);

/* ---- 2-D translational paths (paths2.c) ---- */
/* Up to max_paths piecewise-linear paths (at most CN_ROUTE_MAX_SEGMENTS segments each) leaving through distinct
 * openings, shortest first; straight-out paths are left to the straight-line candidates. */
cnStatus cn_paths2(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                   int max_paths, double (*segs)[CN_ROUTE_MAX_SEGMENTS][3], int *nseg, int *npaths, cnDiag *diag);

/* ---- 3-D translational routes (paths3.c) ---- */
/* Up to max_paths piecewise-linear routes through the C-space obstacles' roadmap, one per
 * distinct last node, shortest first, each verified by the exact swept test; straight-out
 * routes are left to the straight-line candidates. */
cnStatus cn_paths3(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                   int max_paths, double (*segs)[CN_ROUTE_MAX_SEGMENTS][3], int *nseg, int *npaths, cnDiag *diag);

#endif
