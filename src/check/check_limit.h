/* Static limits (the equilibrium LP alone): for the margins (margin/), which bracket them with
 * verdicts. */
#ifndef CAIRN_CHECK_LIMIT_H
#define CAIRN_CHECK_LIMIT_H

#include "cairn/stability.h"

/* The largest t in [0, cap] for which the equilibrium LP of the check that opt describes (the
 * first reading of its corner contacts) has a static field under gravity plus the acceleration
 * t * load of every body; -1 when there is none at any t or the LP is too large or fails. The
 * t with a field are an interval: the caller makes sure it holds 0 (a margin's tilt and lateral
 * factor are sought only on an assembly stable as loaded); otherwise a positive t may come back
 * from an interval that starts above 0. Not verified, and not a verdict: a static field is
 * necessary for a stable verdict, so a margin's verdicts look near it first. */
cnStatus cn_check_load_limit(const cnAssembly *a, const cnCheckOptions *opt, const double load[3],
                             double cap, double *t, cnDiag *diag);

/* Has the equilibrium LP of the check that opt describes (its first reading) a static field? *has
 * 1 yes, 0 no (a verified certificate), -1 not known (neither verified, more than
 * CN_LIMIT_LP_MAX_COLS columns, a part driven into another, an overlap). The margins' critical
 * friction bisects on it before its verdicts. */
cnStatus cn_check_has_field(const cnAssembly *a, const cnCheckOptions *opt, int *has, cnDiag *diag);

#endif
