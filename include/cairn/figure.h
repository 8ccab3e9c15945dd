/* cairn: figures (PNG, drawn with cairo). Built as a library of its own, libcairn_figure (link it
 * before libcairn, with cairo): libcairn itself does not need cairo. */
#ifndef CAIRN_FIGURE_H
#define CAIRN_FIGURE_H

#include "cairn/export.h"

#include <stdbool.h>

#include "cairn/margin.h"
#include "cairn/model.h"
#include "cairn/plan.h"
#include "cairn/run.h"
#include "cairn/simulate.h"
#include "cairn/stability.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct cnFigureOptions {
    int width, height;    /**< pixels */
    bool vertex_numbers;  /**< number every vertex (1.., in part order), as the paper does */
    bool forces;          /**< draw contact force arrows */
} cnFigureOptions;

CN_API cnFigureOptions cn_figure_options_default(void);

/** Draw an assembly and a check result (NULL: geometry only) to a PNG file: parts (moving parts
 *  in red), vertex numbers, contact points with their ids, force arrows scaled by the reference
 *  weight, the motion that starts, and the verdict. 3-D assemblies are drawn in an axonometric
 *  view with gravity pointing down. Returns CN_ERR_IO when the file cannot be written. */
CN_API cnStatus cn_figure_check_png(const char *path, const cnAssembly *a, const cnCheckResult *r,
                             const cnFigureOptions *opt, cnDiag *diag);

/** The collapse mechanism of margin m (kind: CN_MARGIN_FRICTION, _TILT or _LATERAL) to a PNG,
 *  SVG or PDF file (as the name ends): the parts as loaded, the moving parts also dashed where
 *  their motion at `past` carries them (exaggerated to a tenth of the assembly's size), the
 *  contacts that open and slide, and the gravity of that verdict. CN_ERR_INPUT when the margin
 *  has no collapse verdict (stable over the whole range). */
CN_API cnStatus cn_figure_margin(const char *path, const cnAssembly *a, const cnMargin *m, int kind,
                          const cnFigureOptions *opt, cnDiag *diag);

/** Figures of a simulated plan into directory `dir` (created if missing): per step, the force-
 *  time plot and the assembly at the step's start, at the instability and at its end, each as
 *  PNG, SVG and PDF. File names: [assembly-]stepK-{forces,start,onset,end}.{png,svg,pdf}. */
CN_API cnStatus cn_figure_simulation(const char *dir, const cnAssembly *a, const cnSimResult *r,
                              cnDiag *diag);

/** The interactive report of a simulated plan: one self-contained HTML page (nothing is fetched
 *  when it is viewed) with the assembly (2-D as SVG, 3-D with WebGL, three.js inlined), the plan
 *  played along its paths with play/pause and a time slider, contacts coloured by force, the
 *  parts that start to move highlighted from the onset on, and the force-time plot linked to the
 *  slider. `assembly` (may be NULL): the same plan run as an assembly, a second run in the page. */
CN_API cnStatus cn_figure_simulation_html(const char *path, const cnAssembly *a, const cnSimResult *dis,
                                   const cnSimResult *assembly, cnDiag *diag);

/** The same page for any simulated runs of one assembly's parts (e.g. a planner's sequences):
 *  nruns runs, run r a simulation of asms[r]'s plan (the same parts in each; the parts are drawn
 *  from asms[0]), each with a label and a detail (details may be NULL), listed in a table whose
 *  rows play them. */
CN_API cnStatus cn_figure_html(const char *path, const cnAssembly *const *asms, const cnSimResult *const *runs,
                        const char *const *labels, const char *const *details, int nruns,
                        const char *subtitle, cnDiag *diag);

/** Rows of a plan's table that cn_figure_plan_html plays, at most: each is simulated and kept
 *  for the page, and a plan listing all may have hundreds of thousands. */
#define CN_FIGURE_PLAN_ROWS 200

/** `cairn plan --html`: every row of r's sequence x path table with steps to play (the first
 *  CN_FIGURE_PLAN_ROWS) simulated along its paths as `simulate --plan` would (the assembly read
 *  again from `file` with `load` and the row's plan; so options), then one page (cn_figure_html)
 *  with a run per row; with no row to play, the assembly `a` at rest and why. A load or
 *  simulation that fails names `file` in diag->file. */
CN_API cnStatus cn_figure_plan_html(const char *path, const char *file, const cnLoadOptions *load,
                                    const cnAssembly *a, const cnPlanResult *r, const cnSimOptions *so,
                                    cnDiag *diag);

/** cn_run_json (run.h) that also draws: the option "figure" of check names a PNG file that
 *  receives the check's figure (as `cairn check --figure`), checked before the work (not the
 *  assembly's own file, writable). What the Python package calls for check(figure=...). */
CN_API cnStatus cn_figure_run_json(const cnAssembly *a, const char *command, const char *options, char **json,
                            cnOutcome *outcome, cnDiag *diag);

#ifdef __cplusplus
}
#endif
#endif
