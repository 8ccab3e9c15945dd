/* cairn: figures (PNG, drawn with cairo). Built as a library of its own, libcairn_figure (link it
 * before libcairn, with cairo): libcairn itself does not need cairo. */
#ifndef CAIRN_FIGURE_H
#define CAIRN_FIGURE_H

#include <stdbool.h>

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

cnFigureOptions cn_figure_options_default(void);

/** Draw an assembly and a check result (NULL: geometry only) to a PNG file: parts (moving parts
 *  in red), vertex numbers, contact points with their ids, force arrows scaled by the reference
 *  weight, the motion that starts, and the verdict. 3-D assemblies are drawn in an axonometric
 *  view with gravity pointing down. Returns CN_ERR_IO when the file cannot be written. */
cnStatus cn_figure_check_png(const char *path, const cnAssembly *a, const cnCheckResult *r,
                             const cnFigureOptions *opt, cnDiag *diag);

/** Figures of a simulated plan into directory `dir` (created if missing): per step, the force-
 *  time plot and the assembly at the step's start, at the instability and at its end, each as
 *  PNG, SVG and PDF. File names: [assembly-]stepK-{forces,start,onset,end}.{png,svg,pdf}. */
cnStatus cn_figure_simulation(const char *dir, const cnAssembly *a, const cnSimResult *r,
                              cnDiag *diag);

#ifdef __cplusplus
}
#endif
#endif
