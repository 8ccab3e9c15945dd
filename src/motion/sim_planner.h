/* What the planner asks of the simulator beyond the public API. */
#ifndef CAIRN_SIM_PLANNER_H
#define CAIRN_SIM_PLANNER_H

#include <stdbool.h>

#include "cairn/simulate.h"

/* cn_simulate_step, for a caller that proved the state after the step (the moved parts taken
 * away) stable with the same check options (after_known: the planner, by Proposition 1's check
 * of that state): the step's last check, of that state, is not repeated, and a sample where
 * every moved part is held and touches nothing is that state (stable without solving). */
cnStatus cn_sm_simulate_step(const cnAssembly *a, const unsigned char *absent, const cnPlanStep *st,
                             const cnSimOptions *opt, bool after_known, cnStepResult *out,
                             cnDiag *diag);

#endif
