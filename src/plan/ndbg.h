/* plan: the blocking graph's cones, kept apart from its arrangement so that the planner computes
 * the cones of an assembly once and arranges them per state and group (ndbg.c). Private. */
#ifndef CAIRN_NDBG_H
#define CAIRN_NDBG_H

#include "cairn/plan.h"

/* The blocked cone of one pair of convex pieces: part `part` (the lower index) translated along d
 * enters piece of part `other` iff nrm[k] . d < 0 for every k in first .. first + n - 1 (n == 0:
 * in every direction, pieces that overlap beyond the tolerance). `other` moving along d enters
 * `part` iff d is in the mirrored cone, every nrm[k] . d > 0. The cones of one pair of parts are
 * consecutive. */
typedef struct {
    int part, other, first, n;
} cnNdbgCone;

typedef struct {
    int ncone, capcone;
    cnNdbgCone *cone;
    int nnrm, capnrm;
    double (*nrm)[3];
} cnNdbgCones;

/* The cones of every pair of parts i < j, both present (absent NULL: all of the assembly's own
 * parts) and at least one free; with `group`, only the pairs with exactly one part in it. */
cnStatus cn_ndbg_cones(const cnAssembly *a, const unsigned char *absent, const unsigned char *group,
                       cnNdbgCones *C, cnDiag *diag);
void cn_ndbg_cones_free(cnNdbgCones *C);

/* The graph (as cn_ndbg_build) from cones computed beforehand for at least the pairs it needs. */
cnStatus cn_ndbg_arrange(const cnAssembly *a, const cnNdbgCones *C, const unsigned char *absent,
                         const unsigned char *group, int max_circles, cnNdbg *g, cnDiag *diag);

/* The free directions of a graph of a group (cn_free_directions in 3-D): up when it is free, one
 * direction of every free cell in the graph's order (the cells holding an axis first, with that
 * axis; then regions, arcs, single directions), then the other free axes. *dirs: cn_free. */
cnStatus cn_ndbg_free_dirs(const cnAssembly *a, const cnNdbg *g, double (**dirs)[3], int *nd,
                           cnDiag *diag);

/* Is the cell free: no edge in it? */
static inline bool cn_ndbg_cell_free(const cnNdbg *g, int cell) {
    return cell >= 0 && cell < g->ncells && g->cells[cell].nedges == 0;
}

#endif
