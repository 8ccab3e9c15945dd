/* cairn: feasible removal directions (the non-directional blocking graph) and planning. */
#ifndef CAIRN_PLAN_H
#define CAIRN_PLAN_H

#include <stdbool.h>

#include "cairn/simulate.h"

#ifdef __cplusplus
extern "C" {
#endif

/** A closed arc of directions in 2-D: counter-clockwise from `from` to `to` (radians, both in
 *  [0, 2 pi); to < from when it wraps past 0). from == to is a single direction. */
typedef struct cnArc {
    double from, to;
} cnArc;

/** Directions along which the parts flagged in `moving` can translate to infinity without
 *  penetrating any other present part (touching allowed). 2-D only: exact, as closed arcs, from
 *  the Minkowski differences of the convex pieces. `local` (may be NULL) gets the arcs allowed by
 *  the contacts alone (infinitesimal motion). Caller frees *free and *local with cn_free_arcs. */
cnStatus cn_directions2(const cnAssembly *a, const unsigned char *absent,
                        const unsigned char *moving, cnArc **free_arcs, int *nfree,
                        cnArc **local, int *nlocal, cnDiag *diag);
void cn_free_arcs(cnArc *arcs);

/** 3-D (and 2-D): is the straight translation along unit d to infinity free? Exact: the moving
 *  pieces swept along d must not overlap any other present piece beyond the contact tolerance. */
cnStatus cn_direction_free(const cnAssembly *a, const unsigned char *absent,
                           const unsigned char *moving, const double d[3], bool *free_,
                           cnDiag *diag);

/** Representative free directions: in 2-D the middle of every free arc (a single direction for
 *  a degenerate one) and its ends; in 3-D every candidate of the arrangement that is free: the
 *  axes, the face normals of the pieces involved, their pairwise cross products, all with both
 *  signs, and "up" (against gravity). "Up" comes first when it is free. *dirs must be freed
 *  with cn_free. */
cnStatus cn_free_directions(const cnAssembly *a, const unsigned char *absent,
                            const unsigned char *moving, double (**dirs)[3], int *ndirs,
                            cnDiag *diag);

#ifdef __cplusplus
}
#endif
#endif
