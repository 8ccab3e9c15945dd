/* plan: the candidate paths of a part or group leaving a state (cands.c): the file's named paths,
 * or straight lines along the free directions of the blocking graph ("up" first) and routes
 * through the openings around. Shared by the exhaustive planner (plan.c) and the search for large
 * assemblies (plan_large.c). Private. */
#ifndef CAIRN_CANDS_H
#define CAIRN_CANDS_H

#include "ndbg.h"
#include "paths2.h"
#include "cairn/plan.h"

/* A candidate path of one part (or subassembly) from one state. */
typedef struct {
    char name[64];            /* a generated candidate's name */
    const cnCandidate *file;  /* a candidate of the file (its name and segments), or NULL */
    int nseg;
    cnSegment own[CN_ROUTE_MAX_SEGMENTS]; /* a generated candidate's segments */
    cnSupport support;
} cnCand;

/* A candidate's segments and name, wherever they are kept (a cnCand is copied by value). */
static inline const cnSegment *cn_cand_seg(const cnCand *c) { return c->file ? c->file->seg : c->own; }
static inline const char *cn_cand_name(const cnCand *c) {
    return c->file && !c->name[0] ? c->file->name : c->name;
}

/* What candidate generation keeps between calls: the blocking graph's cones of every pair of
 * parts (parts never move between states: computed once, when first needed). */
typedef struct {
    const cnAssembly *a;
    const cnPlanOptions *o;
    cnDiag *diag;
    cnNdbgCones cones;
    bool have_cones;
} cnCandGen;

/* Is every segment of the candidate a translation along or against gravity? */
bool cn_cand_vertical(const cnAssembly *a, const cnCand *c);

/* The candidates of the parts flagged in `moving` leaving the state whose absent parts `absent`
 * flags (single: the part's index when one part moves, else -1): the file's candidates of a
 * single part when it has any, else at most o->auto_dirs straight lines and, for a single part,
 * routes. A single part's carry the options' support (a twin pushed one with
 * CN_PLAN_SUPPORT_BOTH); a group's keep the file's default support (the planner holds groups). With
 * `opening`, the straight lines that open every contact of the moving parts come first (then the
 * others, each group in the graph's order). *out: cn_free. */
cnStatus cn_cands(cnCandGen *G, const unsigned char *absent, const unsigned char *moving, int single,
                  bool opening, cnCand **out, int *n);

/* The cones of G, computed when first needed. */
cnStatus cn_cands_cones(cnCandGen *G);
void cn_cands_free(cnCandGen *G);

#endif
