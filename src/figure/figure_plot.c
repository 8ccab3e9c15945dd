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

/* Where a plot goes on the page: margins, ranges (values y, alarm series' accelerations a on
 * their own axis) and whether every value is at one instant. */
typedef struct {
    double L, R, T, B, pw, ph;
    double x0, x1, y0, y1, a0, a1;
    bool accel;   /* alarm series (accelerations) get their own axis, on the right */
    bool instant; /* every value at one instant (an onset at the start): drawn across the middle */
    double at;    /* ... that instant */
} Frame;

static double PX(const Frame *f, double x) { return f->L + (x - f->x0) / (f->x1 - f->x0) * f->pw; }
static double PY(const Frame *f, double y) { return f->T + f->ph - (y - f->y0) / (f->y1 - f->y0) * f->ph; }
static double PA(const Frame *f, double y) { return f->T + f->ph - (y - f->a0) / (f->a1 - f->a0) * f->ph; }

static Frame plot_frame(const cnPlot *p, double W, double H) {
    Frame f = {70, 230, 56, 50, 0, 0, p->x0, p->x1, 0, 0, 0, 0, false, false, 0};
    f.ph = H - f.T - f.B;
    for (int s = 0; s < p->nseries; s++)
        for (int i = 0; i < p->series[s].n; i++) {
            double v = p->series[s].y[i];
            if (p->series[s].alarm) f.a0 = fmin(f.a0, v), f.a1 = fmax(f.a1, v), f.accel = true;
            else f.y0 = fmin(f.y0, v), f.y1 = fmax(f.y1, v);
        }
    if (f.y1 <= f.y0) f.y1 = f.y0 + 1;
    if (f.a1 <= f.a0) f.a1 = f.a0 + 1;
    double pad = 0.06 * (f.y1 - f.y0), apad = 0.06 * (f.a1 - f.a0);
    f.y1 += pad, f.a1 += apad;
    if (f.y0 < 0) f.y0 -= pad;
    if (f.a0 < 0) f.a0 -= apad;
    /* every value at one instant (an onset at the start): the instant in the middle, each
       series drawn across it */
    double tlo = INFINITY, thi = -INFINITY;
    for (int s = 0; s < p->nseries; s++)
        for (int i = 0; i < p->series[s].n; i++)
            tlo = fmin(tlo, p->series[s].t[i]), thi = fmax(thi, p->series[s].t[i]);
    f.instant = !(f.x1 > f.x0) || tlo == thi;
    f.at = tlo == thi ? tlo : f.x0;
    if (f.instant) f.x0 = f.at - 1, f.x1 = f.at + 1;
    if (f.accel) f.R += 50;
    f.pw = W - f.L - f.R;
    return f;
}

/* The shaded intervals, the grid, both axes' ticks, the frame, the labels, the title and the
 * onset's line. */
static void draw_axes(cairo_t *cr, const Frame *f, double H, const cnPlot *p) {
    double L = f->L, T = f->T, pw = f->pw, ph = f->ph, x0 = f->x0, x1 = f->x1, y0 = f->y0, y1 = f->y1;
    /* shaded intervals, under everything else */
    cairo_set_source_rgb(cr, 0.86, 0.90, 0.97);
    for (int b = 0; b < p->nbands; b++) {
        double bx0 = fmax(p->band[b][0], x0), bx1 = fmin(p->band[b][1], x1);
        if (bx1 <= bx0) continue;
        cairo_rectangle(cr, PX(f, bx0), T, PX(f, bx1) - PX(f, bx0), ph);
        cairo_fill(cr);
    }
    /* grid and ticks */
    char buf[64];
    cairo_set_font_size(cr, 11);
    double xs = nice_step(x1 - x0, 8), ys = nice_step(y1 - y0, 6);
    cairo_set_line_width(cr, 1);
    double xt0 = ceil(x0 / xs) * xs, xt1 = x1 + 1e-9 * xs;
    if (f->instant) xt0 = f->at, xt1 = f->at, xs = 1; /* one tick: the instant */
    for (double x = xt0; x <= xt1; x += xs) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, PX(f, x), T);
        cairo_line_to(cr, PX(f, x), T + ph);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(buf, sizeof buf, "%g", fabs(x) < CN_TOL_PRINT_ZERO * xs ? 0.0 : x);
        cairo_text_extents_t te;
        cairo_text_extents(cr, buf, &te);
        cairo_move_to(cr, PX(f, x) - te.width / 2, T + ph + 16);
        cairo_show_text(cr, buf);
    }
    for (double y = ceil(y0 / ys) * ys; y <= y1 + 1e-9 * ys; y += ys) {
        cairo_set_source_rgb(cr, 0.9, 0.9, 0.9);
        cairo_move_to(cr, L, PY(f, y));
        cairo_line_to(cr, L + pw, PY(f, y));
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        snprintf(buf, sizeof buf, "%g", fabs(y) < CN_TOL_PRINT_ZERO * ys ? 0.0 : y);
        cairo_text_extents_t te;
        cairo_text_extents(cr, buf, &te);
        cairo_move_to(cr, L - 6 - te.width, PY(f, y) + 4);
        cairo_show_text(cr, buf);
    }
    if (f->accel) { /* the accelerations' axis, on the right, in their colour */
        double as = nice_step(f->a1 - f->a0, 6);
        cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
        for (double y = ceil(f->a0 / as) * as; y <= f->a1 + 1e-9 * as; y += as) {
            snprintf(buf, sizeof buf, "%g", fabs(y) < CN_TOL_PRINT_ZERO * as ? 0.0 : y);
            cairo_move_to(cr, L + pw, PA(f, y));
            cairo_line_to(cr, L + pw + 5, PA(f, y));
            cairo_stroke(cr);
            cairo_move_to(cr, L + pw + 8, PA(f, y) + 4);
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
        cairo_move_to(cr, PX(f, p->mark_x), T);
        cairo_line_to(cr, PX(f, p->mark_x), T + ph);
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
    }
}

/* Each series as a line with dots, clipped to the frame. */
static void draw_series(cairo_t *cr, const Frame *f, const cnPlot *p) {
    double pw = f->pw, at = f->at;
    cairo_save(cr);
    cairo_rectangle(cr, f->L, f->T, pw, f->ph);
    cairo_clip(cr);
    int colour = 0;
    for (int s = 0; s < p->nseries; s++) {
        const cnPlotSeries *se = &p->series[s];
        series_style(cr, se->alarm ? -1 : colour++);
        cairo_set_line_width(cr, se->alarm ? 2.5 : 2.0);
        for (int i = 0; i < se->n; i++) {
            double py = se->alarm ? PA(f, se->y[i]) : PY(f, se->y[i]);
            if (f->instant) { /* across the middle: the value at the instant */
                cairo_move_to(cr, PX(f, at) - 0.3 * pw, py);
                cairo_line_to(cr, PX(f, at) + 0.3 * pw, py);
            } else if (i == 0) {
                cairo_move_to(cr, PX(f, se->t[i]), py);
            } else {
                cairo_line_to(cr, PX(f, se->t[i]), py);
            }
        }
        cairo_stroke(cr);
        cairo_set_dash(cr, NULL, 0, 0);
        for (int i = 0; i < se->n; i++) {
            double py = se->alarm ? PA(f, se->y[i]) : PY(f, se->y[i]);
            cairo_arc(cr, PX(f, f->instant ? at : se->t[i]), py, se->alarm ? 3.5 : 2.5, 0, 2 * CN_PLOT_PI);
            cairo_fill(cr);
        }
    }
    cairo_restore(cr);
}

/* The legend, right of the frame (past the right axis's numbers): a line per series while they
 * fit, then the shaded intervals' entry. */
static void draw_legend(cairo_t *cr, const Frame *f, const cnPlot *p) {
    double T = f->T, ph = f->ph;
    cairo_set_font_size(cr, 11);
    int colour = 0;
    double ly = T + 8, lx = f->L + f->pw + (f->accel ? 52 : 0);
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
}

static void draw_plot(cairo_t *cr, double W, double H, const cnPlot *p) {
    Frame f = plot_frame(p, W, H);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    draw_axes(cr, &f, H, p);
    draw_series(cr, &f, p);
    draw_legend(cr, &f, p);
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
