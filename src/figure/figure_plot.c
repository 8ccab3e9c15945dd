/* Line plots (cairo): the force-time plots of simulations, like the paper's Figs. 2, 3, 5, 7, 8.
 * One plot is written as PNG, SVG and PDF. */
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "figure_plot.h"

static const double PAL[10][3] = {{0.12, 0.47, 0.71}, {0.17, 0.63, 0.17}, {1.00, 0.50, 0.05},
                                  {0.58, 0.40, 0.74}, {0.55, 0.34, 0.29}, {0.89, 0.47, 0.76},
                                  {0.50, 0.50, 0.50}, {0.74, 0.74, 0.13}, {0.09, 0.75, 0.81},
                                  {0.12, 0.20, 0.45}};

/* The colour and line of series k: past the palette, series are told apart by their line
 * (solid, dashed, dotted, dash-dot); k < 0: an alarm series (red, dashed). */
static void series_style(cairo_t *cr, int k) {
    static const double dash[4][4] = {{0}, {8, 4}, {2, 3}, {8, 3, 2, 3}};
    static const int ndash[4] = {0, 2, 2, 4};
    if (k < 0) {
        static const double alarm[2] = {4, 3};
        cairo_set_source_rgb(cr, 0.85, 0.05, 0.05);
        cairo_set_dash(cr, alarm, 2, 0);
        return;
    }
    int st = (k / 10) % 4;
    cairo_set_source_rgb(cr, PAL[k % 10][0], PAL[k % 10][1], PAL[k % 10][2]);
    cairo_set_dash(cr, dash[st], ndash[st], 0);
}

/* A "nice" tick step for a range. */
static double nice_step(double range, int target) {
    double raw = range / target, mag = pow(10, floor(log10(raw))), f = raw / mag;
    double n = f < 1.5 ? 1 : f < 3.5 ? 2 : f < 7.5 ? 5 : 10;
    return n * mag;
}

static void draw_plot(cairo_t *cr, double W, double H, const cnPlot *p) {
    double L = 70, R = 230, T = 56, B = 50;
    double pw = W - L - R, ph = H - T - B;
    double x0 = p->x0, x1 = p->x1, y0 = 0, y1 = 0, a0 = 0, a1 = 0;
    bool accel = false; /* alarm series (accelerations) get their own axis, on the right */
    for (int s = 0; s < p->nseries; s++)
        for (int i = 0; i < p->series[s].n; i++) {
            double v = p->series[s].y[i];
            if (p->series[s].alarm) a0 = fmin(a0, v), a1 = fmax(a1, v), accel = true;
            else y0 = fmin(y0, v), y1 = fmax(y1, v);
        }
    if (y1 <= y0) y1 = y0 + 1;
    if (a1 <= a0) a1 = a0 + 1;
    double pad = 0.06 * (y1 - y0), apad = 0.06 * (a1 - a0);
    y1 += pad, a1 += apad;
    if (y0 < 0) y0 -= pad;
    if (a0 < 0) a0 -= apad;
    /* every value at one instant (an onset at the start): the instant in the middle, each
       series drawn across it */
    double tlo = INFINITY, thi = -INFINITY;
    for (int s = 0; s < p->nseries; s++)
        for (int i = 0; i < p->series[s].n; i++)
            tlo = fmin(tlo, p->series[s].t[i]), thi = fmax(thi, p->series[s].t[i]);
    bool instant = !(x1 > x0) || tlo == thi;
    double at = tlo == thi ? tlo : x0;
    if (instant) x0 = at - 1, x1 = at + 1;
    if (accel) R += 50;
    pw = W - L - R;
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
#define PX(x) (L + ((x) - x0) / (x1 - x0) * pw)
#define PY(y) (T + ph - ((y) - y0) / (y1 - y0) * ph)
#define PA(y) (T + ph - ((y) - a0) / (a1 - a0) * ph)
    /* shaded intervals, under everything else */
    cairo_set_source_rgb(cr, 0.86, 0.90, 0.97);
    for (int b = 0; b < p->nbands; b++) {
        double bx0 = fmax(p->band[b][0], x0), bx1 = fmin(p->band[b][1], x1);
        if (bx1 <= bx0) continue;
        cairo_rectangle(cr, PX(bx0), T, PX(bx1) - PX(bx0), ph);
        cairo_fill(cr);
    }
    /* grid and ticks */
    char buf[64];
    cairo_set_font_size(cr, 11);
    double xs = nice_step(x1 - x0, 8), ys = nice_step(y1 - y0, 6);
    cairo_set_line_width(cr, 1);
    double xt0 = ceil(x0 / xs) * xs, xt1 = x1 + 1e-9 * xs;
    if (instant) xt0 = at, xt1 = at, xs = 1; /* one tick: the instant */
    for (double x = xt0; x <= xt1; x += xs) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, PX(x), T);
        cairo_line_to(cr, PX(x), T + ph);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(buf, sizeof buf, "%g", fabs(x) < CN_TOL_PRINT_ZERO * xs ? 0.0 : x);
        cairo_text_extents_t te;
        cairo_text_extents(cr, buf, &te);
        cairo_move_to(cr, PX(x) - te.width / 2, T + ph + 16);
        cairo_show_text(cr, buf);
    }
    for (double y = ceil(y0 / ys) * ys; y <= y1 + 1e-9 * ys; y += ys) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, L, PY(y));
        cairo_line_to(cr, L + pw, PY(y));
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(buf, sizeof buf, "%g", fabs(y) < CN_TOL_PRINT_ZERO * ys ? 0.0 : y);
        cairo_text_extents_t te;
        cairo_text_extents(cr, buf, &te);
        cairo_move_to(cr, L - 6 - te.width, PY(y) + 4);
        cairo_show_text(cr, buf);
    }
    if (accel) { /* the accelerations' axis, on the right, in their colour */
        double as = nice_step(a1 - a0, 6);
        cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
        for (double y = ceil(a0 / as) * as; y <= a1 + 1e-9 * as; y += as) {
            snprintf(buf, sizeof buf, "%g", fabs(y) < CN_TOL_PRINT_ZERO * as ? 0.0 : y);
            cairo_move_to(cr, L + pw, PA(y));
            cairo_line_to(cr, L + pw + 5, PA(y));
            cairo_stroke(cr);
            cairo_move_to(cr, L + pw + 8, PA(y) + 4);
            cairo_show_text(cr, buf);
        }
    }
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_rectangle(cr, L, T, pw, ph);
    cairo_stroke(cr);
    /* labels */
    cairo_set_font_size(cr, 12);
    cairo_text_extents_t te;
    cairo_text_extents(cr, p->xlabel, &te);
    cairo_move_to(cr, L + pw / 2 - te.width / 2, H - 12);
    cairo_show_text(cr, p->xlabel);
    cairo_save(cr);
    cairo_text_extents(cr, p->ylabel, &te);
    cairo_move_to(cr, 18, T + ph / 2 + te.width / 2);
    cairo_rotate(cr, -CN_PLOT_PI / 2);
    cairo_show_text(cr, p->ylabel);
    cairo_restore(cr);
    cairo_set_font_size(cr, 13);
    cairo_move_to(cr, L, 20);
    cairo_show_text(cr, p->title);
    if (p->subtitle) {
        cairo_set_font_size(cr, 12);
        if (p->subtitle_bad) cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
        else cairo_set_source_rgb(cr, 0.1, 0.5, 0.15);
        cairo_move_to(cr, L, 40);
        cairo_show_text(cr, p->subtitle);
    }
    /* the onset */
    if (p->mark) {
        cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
        double dash[2] = {6, 4};
        cairo_set_dash(cr, dash, 2, 0);
        cairo_set_line_width(cr, 1.5);
        cairo_move_to(cr, PX(p->mark_x), T);
        cairo_line_to(cr, PX(p->mark_x), T + ph);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
    }
    /* series */
    cairo_save(cr);
    cairo_rectangle(cr, L, T, pw, ph);
    cairo_clip(cr);
    int colour = 0;
    for (int s = 0; s < p->nseries; s++) {
        const cnPlotSeries *se = &p->series[s];
        series_style(cr, se->alarm ? -1 : colour++);
        cairo_set_line_width(cr, se->alarm ? 2.5 : 2.0);
        for (int i = 0; i < se->n; i++) {
            double py = se->alarm ? PA(se->y[i]) : PY(se->y[i]);
            if (instant) { /* across the middle: the value at the instant */
                cairo_move_to(cr, PX(at) - 0.3 * pw, py);
                cairo_line_to(cr, PX(at) + 0.3 * pw, py);
            } else if (i == 0) {
                cairo_move_to(cr, PX(se->t[i]), py);
            } else {
                cairo_line_to(cr, PX(se->t[i]), py);
            }
        }
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
        for (int i = 0; i < se->n; i++) {
            double py = se->alarm ? PA(se->y[i]) : PY(se->y[i]);
            cairo_arc(cr, PX(instant ? at : se->t[i]), py, se->alarm ? 3.5 : 2.5, 0, 2 * CN_PLOT_PI);
            cairo_fill(cr);
        }
    }
    cairo_restore(cr);
    /* legend */
    cairo_set_font_size(cr, 11);
    colour = 0;
    double ly = T + 8, lx = L + pw + (accel ? 52 : 0); /* past the right axis's numbers */
    int shown = 0;
    for (int s = 0; s < p->nseries; s++) {
        const cnPlotSeries *se = &p->series[s];
        int k = se->alarm ? -1 : colour++;
        if (ly > T + ph - 10) {
            if (!shown) {
                cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
                cairo_move_to(cr, lx + 14, ly + 4);
                cairo_show_text(cr, "(more in the CSV)");
                shown = 1;
            }
            continue;
        }
        series_style(cr, k);
        cairo_set_line_width(cr, 2.5);
        cairo_move_to(cr, lx + 12, ly);
        cairo_line_to(cr, lx + 34, ly);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
        cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
        cairo_move_to(cr, lx + 40, ly + 4);
        cairo_show_text(cr, se->label);
        ly += 17;
    }
    if (p->nbands > 0 && p->band_label && ly <= T + ph - 10) {
        cairo_set_source_rgb(cr, 0.86, 0.90, 0.97);
        cairo_rectangle(cr, lx + 12, ly - 6, 22, 12);
        cairo_fill(cr);
        cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
        cairo_move_to(cr, lx + 40, ly + 4);
        cairo_show_text(cr, p->band_label);
    }
#undef PX
#undef PY
#undef PA
}

cnStatus cn_cairo_write(const char *path, int formats, double W, double H,
                        void (*draw)(void *cr, const void *ctx), const void *ctx, cnDiag *diag) {
    const char *ext[3] = {"png", "svg", "pdf"};
    /* one file: its format from its extension (.svg, .pdf; PNG otherwise) */
    int only = -1;
    if (formats == 1) {
        const char *dot = strrchr(path, '.');
        only = dot && !strcasecmp(dot, ".svg") ? 1 : dot && !strcasecmp(dot, ".pdf") ? 2 : 0;
    }
    for (int k = 0; k < formats; k++) {
        int f = only >= 0 ? only : k;
        char file[1100];
        if (formats == 1) snprintf(file, sizeof file, "%s", path);
        else snprintf(file, sizeof file, "%s.%s", path, ext[f]);
        cairo_surface_t *surf = f == 0   ? cairo_image_surface_create(CAIRO_FORMAT_ARGB32, (int)W, (int)H)
                                : f == 1 ? cairo_svg_surface_create(file, W, H)
                                         : cairo_pdf_surface_create(file, W, H);
        cairo_t *cr = cairo_create(surf);
        draw(cr, ctx);
        cairo_destroy(cr);
        cairo_status_t cs;
        if (f == 0) cs = cairo_surface_write_to_png(surf, file);
        else {
            cairo_surface_finish(surf);
            cs = cairo_surface_status(surf);
        }
        cairo_surface_destroy(surf);
        if (cs != CAIRO_STATUS_SUCCESS)
            return cn_diag_set(diag, CN_ERR_IO, "", "cannot write the figure %s: %s", file,
                               cairo_status_to_string(cs));
    }
    return CN_OK;
}

static void draw_plot_cb(void *cr, const void *p) { draw_plot((cairo_t *)cr, 900, 540, (const cnPlot *)p); }

cnStatus cn_plot_write(const char *base, const cnPlot *p, cnDiag *diag) {
    return cn_cairo_write(base, 3, 900, 540, draw_plot_cb, p, diag);
}
