/* cairn: feasible removal directions (the non-directional blocking graph) and planning. */
#ifndef CAIRN_PLAN_H
#define CAIRN_PLAN_H

#include "cairn/export.h"

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
CN_API cnStatus cn_directions2(const cnAssembly *a, const unsigned char *absent,
                        const unsigned char *moving, cnArc **free_arcs, int *nfree,
                        cnArc **local, int *nlocal, cnDiag *diag);
CN_API void cn_free_arcs(cnArc *arcs);

/** 3-D (and 2-D): is the straight translation along unit d to infinity free? Exact: the moving
 *  pieces swept along d must not overlap any other present piece beyond the contact tolerance. */
CN_API cnStatus cn_direction_free(const cnAssembly *a, const unsigned char *absent,
                           const unsigned char *moving, const double d[3], bool *free_,
                           cnDiag *diag);

/** Representative free directions: in 2-D the middle of every free arc (a single direction for
 *  a degenerate one) and its ends; in 3-D one direction of every free cell of the group's
 *  blocking graph (cn_ndbg_build: the cells holding an axis with that axis, then the others),
 *  then the other free axes; when that graph is too large, the candidates of the arrangement
 *  that the swept test finds free: the axes, the face normals of the pieces involved, their
 *  pairwise cross products, all with both signs. "Up" (against gravity) comes first when it is
 *  free. Free *dirs with cn_directions_free. */
CN_API cnStatus cn_free_directions(const cnAssembly *a, const unsigned char *absent,
                            const unsigned char *moving, double (**dirs)[3], int *ndirs,
                            cnDiag *diag);
/** Free the directions of cn_free_directions (NULL is allowed). */
CN_API void cn_directions_free(double (*dirs)[3]);

/** The non-directional blocking graph (NDBG, Wilson and Latombe; paper sec. V) for translations
 *  to infinity. For a moving part i and another present part j, the directions d along which i,
 *  translated along d, would enter j's interior form an open cone: the union over their convex
 *  pieces p of i and q of j of the directions of rays from the origin through the interior of the
 *  Minkowski difference M = q - p (pieces that touch within the contact tolerance: the interior of
 *  M's tangent cone at the origin). Touching and sliding are allowed, as in cn_directions2 and
 *  cn_direction_free. The great circles (2-D: the lines through the origin) that bound these cones
 *  cut the directions into cells: open regions, open arcs of the circles and single directions
 *  (where circles meet), on each of which every pair either blocks or does not. */

/** One cell of the blocking graph. */
typedef struct cnNdbgCell {
    double dir[3];   /**< a unit direction inside the cell (up, or an axis, when one lies in it) */
    int dim;         /**< 3-D: 2 an open region, 1 an open arc of a great circle, 0 a single
                          direction; 2-D: 1 an open arc, 0 a single direction */
    double from, to; /**< 2-D: the angles the cell spans (radians in [0, 2 pi), counter-clockwise
                          from +x; from == to for a single direction; to - from is 2 pi for the
                          whole circle and to < from when the arc wraps past 0); 3-D: 0 */
    int first, nedges; /**< its blocking edges: edges[first .. first + nedges) */
} cnNdbgCell;

/** An edge of a cell's directional blocking graph: `part`, translated along the cell's
 *  directions, collides with `blocker` (indices into cnAssembly.parts). */
typedef struct cnNdbgEdge {
    int part, blocker;
} cnNdbgEdge;

/** Default limit on the bounding circles of one graph. The cells grow with its square and the
 *  work of arranging them with its cube, and the planner arranges one graph per state and group:
 *  the limit keeps each arrangement small. */
#define CN_NDBG_MAX_CIRCLES 120

/** A blocking graph. Free with cn_ndbg_free. */
typedef struct cnNdbg {
    int dim;           /**< 2 or 3 */
    bool too_large;    /**< more bounding circles than the limit: no cells were built */
    int ncircles;      /**< distinct bounding circles (2-D: lines through the origin) */
    int ncells;
    cnNdbgCell *cells; /**< 2-D counter-clockwise from +x; 3-D: the cell of "up" first, then those
                            holding an axis (-x, +x, -y, +y, -z, +z), then regions, arcs and single
                            directions */
    int nedges;
    cnNdbgEdge *edges;
    int nparts;        /**< the assembly's parts (cnAssembly.nparts) */
    void *priv_;       /**< private: the circles and the cells' sign vectors (cn_ndbg_locate) */
} cnNdbg;

/** Build the blocking graph of the present parts (`absent` may be NULL: every part of the
 *  assembly present). `group` NULL: every present free part may move, and each cell has an edge
 *  i -> j for every free i blocked by a present j; else the parts flagged move together: the
 *  arrangement is that of the cones between a flagged part and an unflagged present one only, and
 *  edges go from flagged parts to unflagged ones (a cell without edges is free for the group).
 *  max_circles (0: CN_NDBG_MAX_CIRCLES) bounds the circles: beyond it g->too_large is set, no
 *  cell is built and the status is still CN_OK. */
CN_API cnStatus cn_ndbg_build(const cnAssembly *a, const unsigned char *absent, const unsigned char *group,
                       int max_circles, cnNdbg *g, cnDiag *diag);

/** The cell that holds unit direction d (z ignored in 2-D), or -1 when none does (a graph too
 *  large, or d within rounding of a circle where the arrangement has no such cell). */
CN_API int cn_ndbg_locate(const cnNdbg *g, const double d[3]);

/** The minimal removable subassemblies of cell `cell`: a set S of free parts is removable along
 *  the cell's directions when no edge leaves S (no part of S blocked by a part outside it); the
 *  minimal ones are the closures of single free parts under the edges that contain no fixed part
 *  and no smaller such closure (a graph of a group: the group, when the cell has no edge). Written
 *  as *nsets lists: the parts of set k are
 *  (*parts)[(*start)[k] .. (*start)[k + 1]) (ascending). Free both with cn_free_ints. */
CN_API cnStatus cn_ndbg_removable(const cnAssembly *a, const cnNdbg *g, int cell, int **parts,
                           int **start, int *nsets, cnDiag *diag);
/** Free the arrays of cn_ndbg_removable (NULL is allowed). */
CN_API void cn_free_ints(int *p);

/** Free a blocking graph's arrays (g may be zeroed or NULL). */
CN_API void cn_ndbg_free(cnNdbg *g);

/** Options of the planner. Make with cn_plan_options_default(). */
/** How the planner's candidate paths are supported by the gripper. */
typedef enum cnPlanSupport {
    CN_PLAN_SUPPORT_FILE = 0, /**< as the file says (each candidate's `support`, else the file's
                                   `candidate_support`, else hold) */
    CN_PLAN_SUPPORT_HOLD,     /**< every candidate held */
    CN_PLAN_SUPPORT_PUSH,     /**< every candidate pushed */
    CN_PLAN_SUPPORT_BOTH      /**< every candidate of one part tried both ways (a path along or
                                   against gravity only is held either way: tried once) */
} cnPlanSupport;

typedef struct cnPlanOptions {
    cnSimOptions sim;
    cnPlanSupport support; /**< default CN_PLAN_SUPPORT_FILE */
    bool subassemblies;  /**< also split states into two subassemblies (AND/OR search) */
    bool all;            /**< list every stable sequence and every table row */
    int list_limit;      /**< stable sequences listed (default 20) */
    int table_limit;     /**< rows of the sequence x path table (default 60) */
    int auto_dirs;       /**< automatic straight-line candidates per part and state (default 4) */
    int max_sub;         /**< largest subassembly moved as one (0, the default: any size) */
    bool fixels;         /**< suggest fixels when no plan is stable (default true) */
    int max_states;      /**< search budget: states explored at most (default 50000); when it is
                            reached the search stops and the report says so */
    double max_seconds;  /**< time budget of the search in seconds (0: none); when it is reached
                            the search stops as for max_states (the result then depends on the
                            machine's speed) */
    bool exhaustive;     /**< expand every state whatever the number of free parts (at most
                            62), within max_states and max_seconds: exact counts past 16 free
                            parts, where the default is one plan found depth-first. The states
                            can number 2^n (docs/bench.md, section 3, for walls of 20 bricks) */
    bool parallel;       /**< simulate a state's transitions on two threads (the results are
                            the same as on one). Off by default */
    bool timing;         /**< put the wall time in the report's "search" ("seconds"); off by
                            default so that the same input gives byte-identical JSON */
    /** Called now and then while the search runs (by default at most 4 times a second, from the
     *  calling thread) with the states explored, the simulations run and the seconds spent, for
     *  a progress display; NULL (the default): never. It must not call into the planner. */
    void (*progress)(void *ctx, long states, long simulations, double seconds);
    void *progress_ctx;
    double progress_every; /**< seconds between two progress calls at least (0: 0.25) */
} cnPlanOptions;

CN_API cnPlanOptions cn_plan_options_default(void);

/** Parts, by index into cnAssembly.parts. */
typedef struct cnPartList {
    int n;
    const int *idx;
} cnPartList;

/** A move the planner tried: parts taken out of a state along one candidate path. */
typedef struct cnPlanMove {
    cnPartList move;       /**< the parts taken out (ascending index) */
    const char *path;      /**< the candidate path's name */
    int nseg;              /**< the path's segments (relative to where the parts are) */
    const cnSegment *seg;
    cnSupport support;     /**< hold or push */
    int grip;              /**< the part gripped, the others carried by contact; -1: each moved
                                part is gripped (a subassembly held as a rigid whole) */
    cnStepStatus status;
    bool proposition_1;    /**< unstable without a simulation: the state it leads to is not
                                stable (Proposition 1); `time` is then NAN */
    double time;           /**< unstable: the onset; infeasible: the first contact */
    cnPartList moving;     /**< unstable: the parts that start to move */
    int blocked_by;        /**< infeasible: the part in the way, -1 when none is named */
} cnPlanMove;

/** A sequence of moves (a stable disassembly sequence, or a row of the table). */
typedef struct cnPlanSequence {
    int n;
    const cnPlanMove *steps;
} cnPlanSequence;

/** How a row of the sequence x path table ends. */
typedef enum cnPlanRowEnd {
    CN_ROW_STABLE = 0,        /**< every part out, every step stable */
    CN_ROW_STATE_UNSTABLE,    /**< it reaches a state that is not stable (Proposition 1) */
    CN_ROW_UNEXPLORED,        /**< it reaches a state the search budget left unexplored */
    CN_ROW_NO_WAY_ON,         /**< it reaches a state from which no move was found */
    CN_ROW_STEP_FAILS,        /**< its last step is not stable (that step's status says how) */
    CN_ROW_STATE_UNDECIDED    /**< it reaches a state whose friction verdict is undecided (the
                                   search for a motion from rest ran out of budget): not stable */
} cnPlanRowEnd;

typedef struct cnPlanRow {
    cnPlanSequence seq;
    cnPlanRowEnd end;
} cnPlanRow;

/** The paths tried for one part from one state, when there were at least two. */
typedef struct cnPlanPathChoice {
    cnPartList remaining;  /**< the state: the free parts that remain */
    int part;              /**< the part taken out */
    bool path_dependent;   /**< some paths stable, others unstable */
    cnPlanSequence paths;  /**< each path tried (a sequence of alternatives, not of steps) */
} cnPlanPathChoice;

/** Fixels that make a failing first step stable (verified by simulating the step again). */
typedef struct cnFixelSuggestion {
    cnPlanMove step;
    int nfixels;           /**< 1 or 2 */
    cnFixel fixels[2];
} cnFixelSuggestion;

/** A node of the AND/OR tree: a (sub)assembly and how it comes apart. */
typedef struct cnPlanNode {
    cnPartList parts;
    int held_by;           /**< the part a gripper holds it by (the others rest on it); -1: on
                                the supports, or held whole */
    bool held_whole;       /**< a gripper holds every part of it (a rigid whole) */
    bool split;            /**< it is taken apart: `take_out`, then each child */
    cnPlanMove take_out;   /**< the parts taken out (status stable) */
    int nchildren;         /**< the taken-out subassembly (when more than one part) first */
    const struct cnPlanNode *children;
} cnPlanNode;

/** A two-handed split of the whole assembly into two groups. */
typedef struct cnPlanSplit {
    cnPartList side[2];
    bool stable;           /**< the groups come apart stably and each side comes apart */
    double nplans;         /**< stable two-handed plans that begin with this split (each way of
                                gripping the side taken out counts; paths aside) */
    int moves_tried;
    cnPlanMove move;       /**< stable: the move that works; else the first one tried */
    bool sides_fail;       /**< the move is stable, but a side cannot come apart afterwards */
} cnPlanSplit;

/** The search itself. */
typedef struct cnPlanSearch {
    int free_parts, states, simulations, max_states;
    bool exhaustive;       /**< every state was expanded (at most 16 free parts or
                                cnPlanOptions.exhaustive, no budget hit, no split capped; or,
                                past 16 without it, no plan exists and every state reachable
                                stably was expanded): the counts are exact */
    bool first_plan;       /**< the depth-first search for one plan past 16 free parts (single
                                parts): when it found one, the counts are lower bounds (1), path
                                choices are not gathered and no fixels are suggested */
    bool budget_reached;   /**< the state or time budget ended the search: results are partial */
    bool out_of_time;      /**< ... and it was the time budget */
    bool splits_capped;    /**< the two-handed search took a state's groups from 20 of its parts
                                at most (states of more than 20 parts outside the hand): not
                                exhaustive */
    bool timing;           /**< `seconds` is part of the report (cnPlanOptions.timing) */
    int threads;           /**< threads that simulated (2 with cnPlanOptions.parallel) */
    double seconds;        /**< wall time */
    int undecided_states;  /**< states whose friction verdict was undecided (counted as not
                                stable: plans through them are not offered) */
    int undecided_moves;   /**< moves whose status was CN_STEP_UNDECIDED (likewise): simulated, or
                                into an undecided state (Proposition 1) */
} cnPlanSearch;

/** The planner's findings, owned by the result (free with cn_plan_result_free). Lists are
 *  limited as cnPlanOptions says (list_limit, table_limit, all). */
typedef struct cnPlanResult {
    bool stable;               /**< a stable plan exists (single parts or subassemblies) */
    bool stable_single_part;   /**< ... taking out one part at a time */
    double nsequences;         /**< stable single-part sequences (parts and paths) */
    double norders;            /**< stable orders of the parts (paths aside) */
    int nlisted;               /**< stable sequences listed */
    const cnPlanSequence *sequences;
    int nlisted_orders;        /**< stable orders listed: the parts in removal order */
    const cnPartList *orders;
    const cnPlanSequence *best_plan; /**< the first stable sequence with its paths, or NULL */
    int nrows;                 /**< the sequence x path table */
    const cnPlanRow *table;
    int nchoices;              /**< path dependence of each explored step */
    const cnPlanPathChoice *choices;
    bool unstable_at_start;    /**< not stable before any part moves (no stable plan) */
    bool undecided_at_start;   /**< ... because its friction verdict is undecided (not proved) */
    int ndead;                 /**< no stable plan: every first move and why it fails */
    const cnPlanMove *dead_ends;
    int nfixels;
    const cnFixelSuggestion *fixels;
    bool subassemblies;        /**< the AND/OR search ran (cnPlanOptions.subassemblies) */
    const cnPlanNode *tree;    /**< its first stable AND/OR tree, or NULL */
    double nplans;             /**< stable two-handed plans: AND/OR trees, each split counted once
                                    per way of gripping the side taken out (by one of its parts,
                                    or whole), paths aside; exact when search.exhaustive */
    int nsplits;
    const cnPlanSplit *splits;
    cnPlanSearch search;       /**< states explored, simulations, wall time, budgets */
    void *mem_;                /**< private: the memory all of the above lives in */
} cnPlanResult;

/** Search stable disassembly sequences over the states "which parts remain" (memoised; each
 *  state checked once, Proposition 1), each transition simulated along each candidate path.
 *  Exhaustive for up to 16 free parts. Beyond, taking out single parts, the search looks for one
 *  stable plan depth-first over any number of free parts: the parts highest against gravity
 *  tried first, each move into a state that is not stable rejected by one check (Proposition 1),
 *  the others along their first candidate path that simulates stable, states with no plan from
 *  them remembered, independent components (free parts that share no contact, even through
 *  other free parts) taken out whole one after another before the whole assembly is searched; the result then holds that one plan (or, when none is found, every first
 *  move tried and why it fails) and says the search was not exhaustive. The two-handed search
 *  (subassemblies) beyond 16 free parts stops at its first stable plan, and takes at most 62.
 *  With cnPlanOptions.exhaustive the search expands every state up to 62 free parts (the
 *  two-handed one tries every split of a state with at most 20 parts outside the hand). */
CN_API cnStatus cn_plan(const cnAssembly *a, const cnPlanOptions *opt, cnPlanResult *out, cnDiag *diag);

CN_API void cn_plan_result_free(cnPlanResult *r);

/** One stable sequence's margins (cn_plan_margins): each step simulated with margins, and per
 *  kind (friction, tilt, lateral) the weakest step's. */
typedef struct cnPlanMargin {
    int sequence;          /**< index into cnPlanResult.sequences */
    cnStepStatus status;   /**< how its simulation ended: stable, or (sampled more finely than the
                                planner did) the first step that was not */
    int failed_step;       /**< that step (0-based), or -1 */
    int weakest_step[3];   /**< per kind, the step (0-based) whose margin is the weakest; -1: none
                                (not asked, or not stable) */
    cnStepMargin weakest[3]; /**< that step's weakest margin (its collapse owned here) */
} cnPlanMargin;

/** The margin plans are ranked by when none is named: lateral if asked for, else tilt, else
 *  friction (kinds: cnMarginOptions.kinds, 0 all). */
static inline int cn_plan_margin_rank(unsigned kinds) {
    if (!kinds) kinds = CN_MARGIN_ALL;
    return kinds & CN_MARGIN_LATERAL ? CN_MARGIN_LATERAL : kinds & CN_MARGIN_TILT ? CN_MARGIN_TILT : CN_MARGIN_FRICTION;
}

/** Stable sequences whose margins cn_plan_margins finds, at most (the first listed). */
#define CN_PLAN_MARGIN_MAX 200

/** Margins of the stable sequences listed in r (r->sequences, up to CN_PLAN_MARGIN_MAX): each simulated as a plan with
 *  so (so->margin must be set; so->assemble is ignored), then ranked strongest first by the
 *  kind `rank` (CN_MARGIN_FRICTION: the least critical friction; CN_MARGIN_TILT, _LATERAL: the
 *  largest), sequences whose simulation was not stable last. *out (n entries) is freed
 *  with cn_plan_margins_free. CN_ERR_INPUT when so->margin is NULL or rank is not asked for. */
CN_API cnStatus cn_plan_margins(const cnAssembly *a, const cnPlanResult *r, const cnSimOptions *so, int rank,
                         cnPlanMargin **out, int *n, cnDiag *diag);

CN_API void cn_plan_margins_free(cnPlanMargin *m, int n);

#ifdef __cplusplus
}
#endif
#endif
