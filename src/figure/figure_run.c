/* cn_figure_run_json: cn_run_json with the figures this library draws (libcairn has no cairo). */
#include "cairn/figure.h"
#include "run_figures.h"

static cnStatus check_figure(const char *path, const cnAssembly *a, const cnCheckResult *r, cnDiag *diag) {
    cnFigureOptions fo = cn_figure_options_default();
    return cn_figure_check_png(path, a, r, &fo, diag);
}

cnStatus cn_figure_run_json(const cnAssembly *a, const char *command, const char *options, char **json,
                            cnOutcome *outcome, cnDiag *diag) {
    static const cnRunFigures figures = {check_figure};
    return cn_run_json_figures(a, command, options, json, outcome, &figures, diag);
}
