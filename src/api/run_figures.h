/* api: the figures cn_run_json can draw when the figure library supplies the drawing (libcairn
 * itself has no cairo). Private to libcairn and libcairn_figure. */
#ifndef CAIRN_RUN_FIGURES_H
#define CAIRN_RUN_FIGURES_H

#include "cairn/run.h"
#include "core.h"

typedef struct cnRunFigures {
    /* draw a check's figure to path (PNG) */
    cnStatus (*check)(const char *path, const cnAssembly *a, const cnCheckResult *r, cnDiag *diag);
} cnRunFigures;

/* cn_run_json with figures: the option "figure" (check) names the file to draw, drawn by fig
 * (NULL: the option is refused, naming the figure library's cn_figure_run_json). */
CN_SIBLING cnStatus cn_run_json_figures(const cnAssembly *a, const char *command, const char *options, char **json,
                             cnOutcome *outcome, const cnRunFigures *fig, cnDiag *diag);

#endif
