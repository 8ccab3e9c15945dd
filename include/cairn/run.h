/* cairn: one call per command, its report as JSON text: what `cairn COMMAND FILE --json`
 * prints, for programs and language bindings that would rather read the versioned JSON report
 * (see CN_JSON_FORMAT_VERSION) than the C result structures. The Python package uses it. */
#ifndef CAIRN_RUN_H
#define CAIRN_RUN_H

#include "cairn/export.h"

#include "cairn/model.h"
#include "cairn/plan.h"
#include "cairn/simulate.h"
#include "cairn/stability.h"
#include "cairn/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** What a command found, as the CLI's exit status says it. */
typedef enum cnOutcome {
    CN_OUTCOME_GOOD = 0,      /**< stable (check, simulate), a stable plan exists (plan), done */
    CN_OUTCOME_NEGATIVE = 1,  /**< not stable (unstable or not guaranteed), or no stable plan */
    CN_OUTCOME_UNDECIDED = 3  /**< a static solution exists but the search for a motion from rest
                                   ran out of budget: no verdict (the report says what is known) */
} cnOutcome;

/** The outcome of a check: stable, not (unstable or not guaranteed), or undecided. */
CN_API cnOutcome cn_check_outcome(const cnCheckResult *r);
/** The outcome of a simulated plan, and of its assembly run when given (may be NULL): good when
 *  both are stable; undecided when no step failed but one could not be decided; else negative. */
CN_API cnOutcome cn_sim_outcome(const cnSimResult *dis, const cnSimResult *assembly);
/** The outcome of a plan search: a stable plan; none, with undecided states or moves (no
 *  verdict); or none. */
CN_API cnOutcome cn_plan_outcome(const cnPlanResult *r);

/** Why `path` cannot take an output, checked before the work: CN_OUTPUT_OK; CN_OUTPUT_INPUT (it
 *  is the file the assembly was read from, `file`, or one of its mesh files, found relative to
 *  `file`); CN_OUTPUT_DIRECTORY; CN_OUTPUT_DENIED (an existing file without write permission);
 *  CN_OUTPUT_NO_DIRECTORY (a new file whose directory is missing or not writable). `file` may be
 *  NULL or "-" (standard input). */
typedef enum cnOutputProblem {
    CN_OUTPUT_OK = 0,
    CN_OUTPUT_INPUT,
    CN_OUTPUT_DIRECTORY,
    CN_OUTPUT_DENIED,
    CN_OUTPUT_NO_DIRECTORY
} cnOutputProblem;
CN_API cnOutputProblem cn_output_problem(const char *path, const char *file, const cnAssembly *a);

/** Run `command` ("check", "simulate", "plan", "directions", "contacts" or "margin") on the assembly with
 *  the options in `options`, a JSON object (NULL or "" or "{}": the defaults) whose keys are the
 *  command's CLI options without the dashes, '-' written '_':
 *   - check:      solver ("auto", "lemke", "pivot"), lp_check (bool), accept_prestress (bool),
 *                 search_budget (integer LPs), reading (integer: one reading of the corner
 *                 contacts' normals)
 *   - simulate:   assemble, cold, accept_prestress (bool), search_budget
 *   - plan:       all, subassemblies, exhaustive, accept_prestress (bool), support ("hold",
 *                 "push", "both"), max_sub, max_states, search_budget (integers), max_seconds (number)
 *   - directions: parts (an array of part names: the subassembly's directions)
 *   - contacts:   none
 *   - margin:     only (an array of "friction", "tilt", "lateral"), pair (two part names), axis,
 *                 direction (arrays of 2 or 3 numbers), margin_tol, max_seconds (numbers),
 *                 accept_prestress, search_budget
 *  On success *json is the report (newly allocated; free with cn_string_free) and *outcome (may be
 *  NULL) what it found. A bad option is CN_ERR_INPUT with where = "options.NAME"; the assembly's
 *  own problems and numerical failures are reported as by the command's C call. */
CN_API cnStatus cn_run_json(const cnAssembly *a, const char *command, const char *options, char **json,
                     cnOutcome *outcome, cnDiag *diag);

#ifdef __cplusplus
}
#endif
#endif
