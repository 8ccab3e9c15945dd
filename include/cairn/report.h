/* cairn: human-readable and JSON reports. The library writes only to streams it is given. */
#ifndef CAIRN_REPORT_H
#define CAIRN_REPORT_H

#include "cairn/export.h"

#include <stdio.h>

#include "cairn/contact.h"
#include "cairn/lcp.h"
#include "cairn/margin.h"
#include "cairn/plan.h"
#include "cairn/simulate.h"
#include "cairn/stability.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Every JSON report starts with "format_version": this number. It goes up when a key is
 *  removed or changes meaning; keys are only added without a change of version. */
#define CN_JSON_FORMAT_VERSION 1

/** Write the contact list as text or JSON (JSON ends with a newline). */
CN_API cnStatus cn_report_contacts(FILE *f, const cnAssembly *a, const cnContactSet *c, int json);

/** Write a check result as text or JSON. */
CN_API cnStatus cn_report_check(FILE *f, const cnAssembly *a, const cnCheckResult *r, int json);

/** Write an LCP solve as text or JSON. `z` and `w` may be NULL when there is no solution. */
CN_API cnStatus cn_report_lcp(FILE *f, const cnLcp *p, cnLcpStatus st, const char *solver,
                       const double *z, const double *w, const cnLcpInfo *info, int json,
                       const char *note, double solve_seconds, int repeats);

/** Write a simulated plan as text or JSON. `assembly` (may be NULL) is the same plan run as an
 *  assembly; when given, the two verdicts are shown side by side. */
CN_API cnStatus cn_report_sim(FILE *f, const cnAssembly *a, const cnSimResult *disassembly,
                       const cnSimResult *assembly, int json);

/** Write the free removal directions of every free part, or (sel, nsel > 0) of the subassembly
 *  of those parts, as text or JSON. */
CN_API cnStatus cn_report_directions(FILE *f, const cnAssembly *a, const int *sel, int nsel, int json,
                              cnDiag *diag);

/** Write the non-directional blocking graph (cn_ndbg_build) of the assembly's free parts, or
 *  (sel, nsel > 0) of the subassembly of those parts moving as one, as text or JSON: per cell its
 *  direction (2-D also its angles), its blocking edges and its minimal removable subassemblies.
 *  Text lists at most CN_REPORT_NDBG_TEXT_CELLS cells and JSON CN_REPORT_NDBG_JSON_CELLS (the
 *  report says how many it left out). */
CN_API cnStatus cn_report_ndbg(FILE *f, const cnAssembly *a, const int *sel, int nsel, int json,
                        cnDiag *diag);
#define CN_REPORT_NDBG_TEXT_CELLS 200
#define CN_REPORT_NDBG_JSON_CELLS 5000

/** Write the margins (cn_margin) as text or JSON. */
CN_API cnStatus cn_report_margin(FILE *f, const cnAssembly *a, const cnMarginResult *r, int json);

/** Write the planner's findings as text or JSON. */
CN_API cnStatus cn_report_plan(FILE *f, const cnAssembly *a, const cnPlanResult *r, int json);

/** The same, with its stable sequences' margins (cn_plan_margins: n entries, ranked by `rank`):
 *  text, a ranking after the report; JSON, under "margins". */
CN_API cnStatus cn_report_plan_margins(FILE *f, const cnAssembly *a, const cnPlanResult *r, const cnPlanMargin *m,
                                int n, int rank, int json);

/** A planner's sequence (a stable sequence, or a row of its table) as a plan file's JSON text,
 *  {"plan": [...]}, for cn_assembly_load_with_plan_text (newly allocated, free with cn_string_free). */
CN_API char *cn_plan_sequence_json(const cnAssembly *a, const cnPlanSequence *seq);

/** A step's status as JSON and tables say it: "stable", "unstable", "geometrically infeasible",
 *  "not simulated" or "undecided" (a static string). */
CN_API const char *cn_step_status_word(cnStepStatus s);

/** How a row of the planner's table ends, in words ("stable", "unstable state (Proposition 1)",
 *  a failing step's status, ...): a static string. */
CN_API const char *cn_plan_row_word(const cnPlanRow *r);

/** Write the assembly as it was understood, for a 3-D viewer: every convex piece of every part
 *  where its pose put it (2-D pieces flat in z = 0), supports in a material of their own.
 *  format "obj" (Wavefront OBJ, one object per part, one group per piece; its materials go to
 *  `mtl`, may be NULL, which the OBJ names as `mtl_name`, may be NULL) or "gltf" (glTF 2.0, one
 *  self-contained JSON file: a node and a mesh per part, a primitive per piece, the geometry a
 *  base64 data URI; a node's extras say whether the part is fixed). */
CN_API cnStatus cn_export(FILE *f, const cnAssembly *a, const char *format, FILE *mtl, const char *mtl_name,
                   cnDiag *diag);

/** Write the history of a simulation as CSV: one row per sample and contact. */
CN_API cnStatus cn_report_sim_csv(FILE *f, const cnAssembly *a, const cnSimResult *r);

#ifdef __cplusplus
}
#endif
#endif
