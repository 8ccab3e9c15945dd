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
 *  signs, and "up" (against gravity). "Up" comes first when it is free. Free *dirs with
 *  cn_directions_free. */
cnStatus cn_free_directions(const cnAssembly *a, const unsigned char *absent,
                            const unsigned char *moving, double (**dirs)[3], int *ndirs,
                            cnDiag *diag);
/** Free the directions of cn_free_directions (NULL is allowed). */
void cn_directions_free(double (*dirs)[3]);

/** Options of the planner. Make with cn_plan_options_default(). */
typedef struct cnPlanOptions {
    cnSimOptions sim;
    bool subassemblies;  /**< also split states into two subassemblies (AND/OR search) */
    bool all;            /**< list every stable sequence and every table row */
    int list_limit;      /**< stable sequences listed (default 20) */
    int table_limit;     /**< rows of the sequence x path table (default 60) */
    int auto_dirs;       /**< automatic straight-line candidates per part and state (default 4) */
    int max_sub;         /**< largest subassembly moved as one (default 3) */
    bool fixels;         /**< suggest fixels when no plan is stable (default true) */
    int max_states;      /**< search budget: states explored at most (default 50000); when it is
                            reached the search stops and the report says so */
    double max_seconds;  /**< time budget of the search in seconds (0: none); when it is reached
                            the search stops as for max_states (the result then depends on the
                            machine's speed) */
    bool parallel;       /**< simulate a state's transitions in two processes (fork per state).
                            Off by default: measured slower than one process on the examples
                            (12-brick wall 3.4 s against 2.0 s) because a simulation costs well
                            under a millisecond; a persistent worker pool is the way to gain */
    bool timing;         /**< put the wall time in the report's "search" ("seconds"); off by
                            default so that the same input gives byte-identical JSON */
} cnPlanOptions;

cnPlanOptions cn_plan_options_default(void);

/** The planner's findings. `report` is an opaque JSON document (jansson) that
 *  cn_report_plan() writes. */
typedef struct cnPlanResult {
    bool stable;           /**< a stable plan exists */
    double nsequences;     /**< stable single-part sequences (parts and paths) */
    int nstates;           /**< states explored */
    int nsims;             /**< transitions simulated */
    double seconds;
    void *report;
} cnPlanResult;

/** Search stable disassembly sequences over the states "which parts remain" (memoised; each
 *  state checked once, Proposition 1), each transition simulated along each candidate path.
 *  Exhaustive for up to 16 free parts; beyond, the search stops at the first stable plan found
 *  depth-first, and the report says so. */
cnStatus cn_plan(const cnAssembly *a, const cnPlanOptions *opt, cnPlanResult *out, cnDiag *diag);

void cn_plan_result_free(cnPlanResult *r);

#ifdef __cplusplus
}
#endif
#endif
