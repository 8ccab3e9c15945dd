/* plan: what the removal directions (blocking.c) share with the blocking graph (ndbg.c). Private. */
#ifndef CAIRN_BLOCKING_H
#define CAIRN_BLOCKING_H

#include "core.h"
#include "cairn/model.h"

/* 2-D: the open arc of directions d along which convex piece P, translated along d to infinity,
 * enters the interior of convex piece Q: from *lo (radians, [0, 2 pi)) counter-clockwise over
 * *len (0, pi]. The angular extent of the Minkowski difference Q - P seen from the origin, its
 * points within tol of the origin left out (touching pieces: capped at a half-plane). *scratch
 * (of *cap doubles) is grown as needed; the caller frees it. Returns 1 with an arc, 0 when nothing
 * blocks, -1 when out of memory. */
int cn_blocked_arc2(const cnPiece *P, const cnPiece *Q, double tol, double **scratch, int *cap,
                    double *lo, double *len);

#endif
