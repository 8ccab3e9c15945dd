/* plan: 2-D translational escape paths. Private. */
#ifndef CAIRN_PATHS2_H
#define CAIRN_PATHS2_H

#include "pieces.h"

/* Most segments of a route the planner generates (cn_paths2). Paths given in files have no such
 * limit (CN_MAX_PATH_SEGMENTS). */
#define CN_ROUTE_MAX_SEGMENTS 8

/* ---- 2-D translational paths (paths2.c) ---- */
/* Up to max_paths piecewise-linear paths (at most CN_ROUTE_MAX_SEGMENTS segments each) leaving through distinct
 * openings, shortest first; straight-out paths are left to the straight-line candidates. */
cnStatus cn_paths2(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                   int max_paths, double (*segs)[CN_ROUTE_MAX_SEGMENTS][3], int *nseg, int *npaths, cnDiag *diag);

#endif
