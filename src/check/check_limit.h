/* The static limit of a load: for the margins (margin/), which bracket it with verdicts. */
#ifndef CAIRN_CHECK_LIMIT_H
#define CAIRN_CHECK_LIMIT_H

#include "cairn/stability.h"

/* The largest t in [0, cap] for which the equilibrium LP of the check that opt describes (the
 * first reading of its corner contacts) has a static field under gravity plus the acceleration
 * t * load of every body; -1 when there is none at t = 0 or the LP is too large or fails. Not
 * verified, and not a verdict: a static field is necessary for a stable verdict, so a margin's
 * verdicts look near it first. */
cnStatus cn_check_load_limit(const cnAssembly *a, const cnCheckOptions *opt, const double load[3],
                             double cap, double *t, cnDiag *diag);

#endif
