/* Line plots for simulations (figure_plot.c). Private. */
#ifndef CAIRN_FIGURE_PLOT_H
#define CAIRN_FIGURE_PLOT_H

#include <stdbool.h>

#include "core.h"
#include "cairn/figure.h"

#define CN_PLOT_PI 3.14159265358979323846

typedef struct {
    const char *label;
    int n;
    const double *t, *y;
    bool alarm; /* drawn red and dashed: a positive separation acceleration */
} cnPlotSeries;

typedef struct {
    const char *title, *subtitle, *xlabel, *ylabel;
    bool subtitle_bad;
    double x0, x1;
    bool mark;      /* a vertical dashed line at mark_x (the onset) */
    double mark_x;
    int nseries;
    const cnPlotSeries *series;
    int nbands;                /* shaded x-intervals (e.g. where the gripper carried a part) */
    const double (*band)[2];
    const char *band_label;    /* their legend entry */
} cnPlot;

/* Write base.png, base.svg and base.pdf. */
cnStatus cn_plot_write(const char *base, const cnPlot *p, cnDiag *diag);

/* Draw with `draw(cr, ctx)` on a W x H page and write it: formats = 1 writes `path` as PNG;
 * formats = 3 writes path.png, path.svg and path.pdf. */
cnStatus cn_cairo_write(const char *path, int formats, double W, double H,
                        void (*draw)(void *cr, const void *ctx), const void *ctx, cnDiag *diag);

#endif
