/* plan: the search for one stable plan in assemblies past the exhaustive planner's size
 * (plan_large.c). Private. */
#ifndef CAIRN_PLAN_LARGE_H
#define CAIRN_PLAN_LARGE_H

#include "cairn/plan.h"

/* One stable single-part plan, depth-first with the parts highest against gravity tried first,
 * each step taken only into a stable state (Proposition 1, one check) and along the first of its
 * candidate paths that simulates stable; states from which no plan leads are remembered. Any
 * number of free parts; not exhaustive (out->search.exhaustive is false). */
cnStatus cn_plan_large(const cnAssembly *a, const cnPlanOptions *o, cnPlanResult *out, cnDiag *diag);

#endif
