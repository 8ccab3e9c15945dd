/* Unit tests of src/figure/ (figure.c and the scenes of figure_scene.c): the legends' promises,
 * read back in the pixels of the PNGs drawn. A figure is read with cairo and its pixels sorted
 * by the colours the legend names. Checked, each against the verdict the scene has by
 * construction:
 *  - a 2-D block resting on a table: the verdict in green, blue force arrows (and far fewer blue
 *    pixels with forces off), no part drawn red;
 *  - a 2-D block over the table's end (its centre past it): drawn red, on the side the table
 *    ends, the verdict red, no part in the colour it has at rest;
 *  - blocks on an incline with friction: above the friction angle green friction arrows and no
 *    sliding dot; below it orange sliding dots and the block red;
 *  - a 3-D cube on a table and one over its edge: red only in the second;
 *  - the collapse mechanism of the incline's critical friction (cn_figure_margin): the block red,
 *    written as PNG, and refused (input error) for a margin with no collapse;
 *  - a force-time plot (figure_plot.c) of a falling series, the onset marked at half its range and
 *    a carried interval shaded from 0.2 to 0.4: the series falls left to right, the red dashed
 *    mark stands at the middle of its span and the shading over that interval (within 4 pixels),
 *    its legend entry beside the frame; the SVG and PDF written beside the PNG;
 *  - a failing step's figures (figure_sim.c): start, onset and force plot in three formats, no
 *    end; the part that tips red at the onset only; the onset marked in red on the plot;
 *  - a figure into a directory that does not exist: an I/O error naming the path, nothing else
 *    written. */
#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cairn/figure.h"
#include "figure_plot.h"
#include "helpers.h"
#include "sim_scenes.h"

static char dir[] = "/tmp/cairn_figureXXXXXX";

/* The colours a legend names, as drawn over the white page. */
enum { PX_RED_PART, PX_REST_PART, PX_FIXED, PX_BLUE, PX_GREEN_TEXT, PX_RED_TEXT, PX_ORANGE, PX_RED_SHADED, PX_N };

typedef struct {
    long count[PX_N];
    double sx[PX_N], sy[PX_N]; /* sums of pixel coordinates */
    int w, h;
} Pixels;

static bool near_rgb(int r, int g, int b, int R, int G, int B, int tol) {
    return abs(r - R) <= tol && abs(g - G) <= tol && abs(b - B) <= tol;
}

/* Fill over white at alpha 0.85 (2-D parts): 0.85 c + 0.15. */
static int over_white(double c) { return (int)lround(255 * (0.85 * c + 0.15)); }

/* rest: the colour of a free part at rest (its palette entry) */
static bool read_png(const char *path, const double rest[3], Pixels *px) {
    memset(px, 0, sizeof *px);
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    if (cairo_surface_status(s) != CAIRO_STATUS_SUCCESS) {
        cairo_surface_destroy(s);
        return false;
    }
    cairo_surface_flush(s);
    px->w = cairo_image_surface_get_width(s), px->h = cairo_image_surface_get_height(s);
    int stride = cairo_image_surface_get_stride(s);
    const unsigned char *d = cairo_image_surface_get_data(s);
    for (int y = 0; y < px->h; y++)
        for (int x = 0; x < px->w; x++) {
            unsigned v = *(const unsigned *)(d + (size_t)y * (size_t)stride + 4 * (size_t)x);
            int r = (v >> 16) & 255, g = (v >> 8) & 255, b = v & 255, k = -1;
            if (near_rgb(r, g, b, over_white(0.89), over_white(0.34), over_white(0.26), 4)) k = PX_RED_PART;
            else if (near_rgb(r, g, b, over_white(rest[0]), over_white(rest[1]), over_white(rest[2]), 4)) k = PX_REST_PART;
            else if (near_rgb(r, g, b, over_white(0.72), over_white(0.72), over_white(0.72), 4)) k = PX_FIXED;
            else if (b > 120 && b - r > 90 && b - g > 50 && r < 90) k = PX_BLUE;
            else if (g > 90 && g - r > 60 && g - b > 50 && r < 90 && b < 100) k = PX_GREEN_TEXT;
            else if (near_rgb(r, g, b, 242, 140, 0, 30)) k = PX_ORANGE;
            else if (r > 150 && g < 70 && b < 70) k = PX_RED_TEXT;
            else if (r > 60 && fabs((double)g / r - 0.34 / 0.89) < 0.03 && fabs((double)b / r - 0.26 / 0.89) < 0.03)
                k = PX_RED_SHADED; /* a 3-D face of a red part, shaded (opaque) */
            if (k < 0) continue;
            px->count[k]++, px->sx[k] += x, px->sy[k] += y;
        }
    cairo_surface_destroy(s);
    return true;
}

static double mean_x(const Pixels *p, int k) { return p->count[k] ? p->sx[k] / (double)p->count[k] : NAN; }

/* Check `json` and draw it to dir/name; its pixels in px. */
static bool draw_check(const char *json, const char *name, bool forces, cnVerdict want, const double rest[3],
                       Pixels *px) {
    cnAssembly *a = load_ok(json);
    if (!a) return false;
    cnCheckOptions co = cn_check_options_default();
    cnCheckResult r;
    cnDiag d;
    bool ok = cn_check(a, &co, &r, &d) == CN_OK;
    CHECK_MSG(ok && r.verdict == want, "%s: verdict %d, expected %d", name, (int)r.verdict, (int)want);
    char path[256];
    snprintf(path, sizeof path, "%s/%s.png", dir, name);
    cnFigureOptions fo = cn_figure_options_default();
    fo.forces = forces;
    ok = ok && cn_figure_check_png(path, a, &r, &fo, &d) == CN_OK;
    CHECK_MSG(ok, "%s: %s", name, d.message);
    ok = ok && read_png(path, rest, px);
    CHECK(ok);
    cn_check_result_free(&r);
    cn_assembly_free(a);
    return ok;
}

/* palette entries of parts 1 and 2 at rest (figure_scene.c's color_of) */
static const double PAL1[3] = {0.62, 0.82, 0.62};

static const char *TABLE_BLOCK =
    "{\"dimension\":2,\"parts\":[{\"name\":\"table\",\"fixed\":true,\"polygon\":[[0,-1],[4,-1],[4,0],[0,0]]},"
    "{\"name\":\"block\",\"polygon\":[[%g,0],[%g,0],[%g,1],[%g,1]]}]}";

static void test_resting_and_tipping(void) {
    char json[512];
    Pixels rest, tip, bare;
    snprintf(json, sizeof json, TABLE_BLOCK, 1.0, 3.0, 3.0, 1.0);
    if (draw_check(json, "rest", true, CN_VERDICT_STABLE, PAL1, &rest)) {
        CHECK(rest.count[PX_RED_PART] == 0);
        CHECK_MSG(rest.count[PX_REST_PART] > 500, "%ld", rest.count[PX_REST_PART]);
        CHECK_MSG(rest.count[PX_GREEN_TEXT] > 20, "%ld", rest.count[PX_GREEN_TEXT]);
        CHECK(rest.count[PX_RED_TEXT] == 0);
    }
    if (draw_check(json, "rest_bare", false, CN_VERDICT_STABLE, PAL1, &bare))
        CHECK_MSG(rest.count[PX_BLUE] > 4 * bare.count[PX_BLUE] + 40, "blue %ld with forces, %ld without",
                  rest.count[PX_BLUE], bare.count[PX_BLUE]);
    /* centre at 4.3, past the table's end at 4: it tips off to the right */
    snprintf(json, sizeof json, TABLE_BLOCK, 3.3, 5.3, 5.3, 3.3);
    if (draw_check(json, "tip", true, CN_VERDICT_UNSTABLE, PAL1, &tip)) {
        CHECK_MSG(tip.count[PX_RED_PART] > 500, "%ld", tip.count[PX_RED_PART]);
        CHECK(tip.count[PX_REST_PART] == 0);
        CHECK_MSG(tip.count[PX_RED_TEXT] > 20, "%ld", tip.count[PX_RED_TEXT]);
        CHECK(tip.count[PX_GREEN_TEXT] == 0);
        CHECK_MSG(mean_x(&tip, PX_RED_PART) > mean_x(&tip, PX_FIXED), "red at x %g, the table at %g",
                  mean_x(&tip, PX_RED_PART), mean_x(&tip, PX_FIXED));
    }
}

static void test_friction(void) {
    char json[512];
    Pixels holds, slides;
    scene_incline_2d(json, sizeof json, 0.5); /* tan 20 degrees = 0.364 */
    if (draw_check(json, "incline_holds", true, CN_VERDICT_STABLE, PAL1, &holds)) {
        CHECK(holds.count[PX_ORANGE] == 0);
        CHECK(holds.count[PX_RED_PART] == 0);
        CHECK_MSG(holds.count[PX_GREEN_TEXT] > 40, "friction arrows and verdict: %ld", holds.count[PX_GREEN_TEXT]);
    }
    scene_incline_2d(json, sizeof json, 0.3);
    if (draw_check(json, "incline_slides", true, CN_VERDICT_UNSTABLE, PAL1, &slides)) {
        CHECK_MSG(slides.count[PX_ORANGE] > 10, "sliding dots: %ld", slides.count[PX_ORANGE]);
        CHECK(slides.count[PX_RED_PART] > 500);
        CHECK(slides.count[PX_REST_PART] == 0);
    }
}

static const char *TABLE_CUBE_3D =
    "{\"dimension\":3,\"parts\":[{\"name\":\"table\",\"fixed\":true,\"box\":{\"min\":[0,0,-1],\"max\":[4,4,0]}},"
    "{\"name\":\"cube\",\"box\":{\"min\":[%g,1,0],\"max\":[%g,2,1]}}]}";

static void test_3d(void) {
    char json[512];
    Pixels rest, tip;
    snprintf(json, sizeof json, TABLE_CUBE_3D, 1.0, 2.0);
    if (draw_check(json, "cube_rest", true, CN_VERDICT_STABLE, PAL1, &rest)) {
        CHECK(rest.count[PX_RED_TEXT] == 0 && rest.count[PX_RED_SHADED] == 0);
        CHECK(rest.count[PX_GREEN_TEXT] > 20);
    }
    snprintf(json, sizeof json, TABLE_CUBE_3D, 3.7, 4.7);
    if (draw_check(json, "cube_tip", true, CN_VERDICT_UNSTABLE, PAL1, &tip)) {
        CHECK_MSG(tip.count[PX_RED_SHADED] > 500, "red faces %ld", tip.count[PX_RED_SHADED]);
        CHECK(tip.count[PX_RED_TEXT] > 20);
        CHECK(tip.count[PX_GREEN_TEXT] == 0);
    }
}

static void test_margin_figure(void) {
    char json[512], path[256];
    scene_incline_2d(json, sizeof json, 0.5);
    cnAssembly *a = load_ok(json);
    if (!a) return;
    cnMarginOptions o = cn_margin_options_default();
    cnMarginResult r;
    cnDiag d;
    CHECK(cn_margin(a, &o, &r, &d) == CN_OK);
    CHECK(r.friction.computed && r.friction.end == CN_MARGIN_FOUND);
    cnFigureOptions fo = cn_figure_options_default();
    snprintf(path, sizeof path, "%s/margin_friction.png", dir);
    CHECK_MSG(cn_figure_margin(path, a, &r.friction, CN_MARGIN_FRICTION, &fo, &d) == CN_OK, "%s", d.message);
    Pixels px;
    if (read_png(path, PAL1, &px)) CHECK_MSG(px.count[PX_RED_PART] > 200, "red %ld", px.count[PX_RED_PART]);
    else CHECK(!"margin figure readable");
    cn_margin_result_free(&r);
    /* the block alone on a level table is stable at any friction: no collapse to draw */
    snprintf(json, sizeof json, TABLE_BLOCK, 1.0, 3.0, 3.0, 1.0);
    cn_assembly_free(a);
    a = load_ok(json);
    if (!a) return;
    o.kinds = CN_MARGIN_FRICTION;
    CHECK(cn_margin(a, &o, &r, &d) == CN_OK && r.friction.end == CN_MARGIN_WHOLE);
    snprintf(path, sizeof path, "%s/margin_none.png", dir);
    CHECK(cn_figure_margin(path, a, &r.friction, CN_MARGIN_FRICTION, &fo, &d) == CN_ERR_INPUT);
    CHECK(access(path, F_OK) != 0);
    cn_margin_result_free(&r);
    cn_assembly_free(a);
}

/* The pixels of colour (R, G, B) within tol (R < 0: of a red hue, however light), x in [xa, xb]
 * and y in [ya, yb]: their count, x extent, mean y. */
typedef struct {
    long n;
    int xmin, xmax;
    double mean_y;
} Run;

static Run colour_run(const char *path, int R, int G, int B, int tol, double xa, double xb, double ya, double yb) {
    Run run = {0, 1 << 30, -1, NAN};
    double sy = 0;
    cairo_surface_t *s = cairo_image_surface_create_from_png(path);
    if (cairo_surface_status(s) == CAIRO_STATUS_SUCCESS) {
        int w = cairo_image_surface_get_width(s), h = cairo_image_surface_get_height(s);
        int stride = cairo_image_surface_get_stride(s);
        const unsigned char *d = cairo_image_surface_get_data(s);
        for (int y = 0; y < h; y++)
            for (int x = 0; x < w; x++) {
                unsigned v = *(const unsigned *)(d + (size_t)y * (size_t)stride + 4 * (size_t)x);
                int r = (v >> 16) & 255, g = (v >> 8) & 255, b = v & 255;
                if (x < xa || x > xb || y < ya || y > yb) continue;
                if (R < 0 ? !(r > g + 40 && r > b + 40) : !near_rgb(r, g, b, R, G, B, tol)) continue;
                run.n++, sy += y;
                if (x < run.xmin) run.xmin = x;
                if (x > run.xmax) run.xmax = x;
            }
    }
    cairo_surface_destroy(s);
    if (run.n) run.mean_y = sy / (double)run.n;
    return run;
}

static bool starts_with(const char *path, const char *magic) {
    char buf[16] = {0};
    FILE *f = fopen(path, "rb");
    if (!f) return false;
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    return n >= strlen(magic) && !memcmp(buf, magic, strlen(magic));
}

static void test_plot(void) {
    double t[11], y[11];
    for (int i = 0; i <= 10; i++) t[i] = 0.1 * i, y[i] = 1 - 0.1 * i;
    cnPlotSeries se = {"falling", 11, t, y, false};
    const double band[1][2] = {{0.2, 0.4}};
    cnPlot p = {.title = "plot", .xlabel = "t", .ylabel = "y", .x0 = 0, .x1 = 1, .mark = true, .mark_x = 0.5,
                .nseries = 1, .series = &se, .nbands = 1, .band = band, .band_label = "carried"};
    char base[256], path[300];
    snprintf(base, sizeof base, "%s/plot", dir);
    cnDiag d;
    CHECK_MSG(cn_plot_write(base, &p, &d) == CN_OK, "%s", d.message);
    snprintf(path, sizeof path, "%s.svg", base);
    CHECK(starts_with(path, "<?xml") || starts_with(path, "<svg"));
    snprintf(path, sizeof path, "%s.pdf", base);
    CHECK(starts_with(path, "%PDF"));
    snprintf(path, sizeof path, "%s.png", base);
    /* the series (the palette's first colour) spans the frame, t = 0 to 1 (less its dots' radius);
       it falls, so its right end is low, away from the legend's entries (top right) */
    const double big = 1e9;
    Run s = colour_run(path, 31, 120, 181, 12, 0, big, 0, big);
    Run low = colour_run(path, 31, 120, 181, 12, 0, big, s.mean_y, big);
    if (!(s.n > 100 && low.n > 50)) {
        CHECK_MSG(false, "series pixels: %ld", s.n);
        return;
    }
    double x0 = s.xmin + 2.5, x1 = low.xmax - 2.5, w = x1 - x0;
    Run left = colour_run(path, 31, 120, 181, 12, 0, x0 + 0.1 * w, 0, big);
    Run right = colour_run(path, 31, 120, 181, 12, x1 - 0.1 * w, x1 + 3, 0, big);
    CHECK_MSG(left.mean_y + 0.05 * w < right.mean_y, "falls: left y %g, right y %g", left.mean_y, right.mean_y);
    /* the onset's mark (red, dashed): one column at t = 0.5 */
    Run m = colour_run(path, -1, 0, 0, 0, 0, big, 0, big);
    CHECK_MSG(m.n > 200 && fabs(0.5 * (m.xmin + m.xmax) - (x0 + 0.5 * w)) <= 3 && m.xmax - m.xmin <= 4,
              "mark: %ld pixels at x %d..%d, the middle at %g", m.n, m.xmin, m.xmax, x0 + 0.5 * w);
    /* the shading over [0.2, 0.4] inside the frame, and its legend entry right of it */
    Run in = colour_run(path, 219, 230, 247, 3, 0, x1, 0, big);
    CHECK_MSG(in.n > 100 && fabs(in.xmin - (x0 + 0.2 * w)) <= 3 && fabs(in.xmax - (x0 + 0.4 * w)) <= 3,
              "band x %d..%d, want %g..%g", in.xmin, in.xmax, x0 + 0.2 * w, x0 + 0.4 * w);
    CHECK(colour_run(path, 219, 230, 247, 3, x1 + 10, big, 0, big).n > 20);
}

/* A simulation's figures (figure_sim.c): sim_scenes.h's A slid out from under B, B tipping from
 * s = 0.5. The step fails, so it has a start, an onset and a force plot, each as PNG, SVG and
 * PDF, and no end; B is red at the onset, not at the start; the plot marks the onset in red. */
static void test_simulation_figures(void) {
    cnAssembly *a = load_ok(SIM_SLIDE_OUT);
    if (!a) return;
    cnSimOptions o = cn_sim_options_default();
    cnSimResult R;
    cnDiag d;
    CHECK(cn_simulate(a, &o, &R, &d) == CN_OK && R.nsteps == 1 && R.steps[0].status == CN_STEP_UNSTABLE);
    char sub[300], path[400];
    snprintf(sub, sizeof sub, "%s/sim", dir);
    CHECK_MSG(cn_figure_simulation(sub, a, &R, &d) == CN_OK, "%s", d.message);
    static const char *const kinds[3] = {"start", "onset", "forces"}, *const ext[3] = {"png", "svg", "pdf"};
    for (int k = 0; k < 3; k++)
        for (int e = 0; e < 3; e++) {
            snprintf(path, sizeof path, "%s/step1-%s.%s", sub, kinds[k], ext[e]);
            CHECK_MSG(access(path, F_OK) == 0, "missing %s", path);
        }
    snprintf(path, sizeof path, "%s/step1-end.png", sub);
    CHECK(access(path, F_OK) != 0);
    Pixels start, onset;
    snprintf(path, sizeof path, "%s/step1-start.png", sub);
    if (read_png(path, PAL1, &start)) CHECK(start.count[PX_RED_PART] == 0);
    snprintf(path, sizeof path, "%s/step1-onset.png", sub);
    if (read_png(path, PAL1, &onset)) CHECK_MSG(onset.count[PX_RED_PART] > 200, "B at the onset: %ld red", onset.count[PX_RED_PART]);
    snprintf(path, sizeof path, "%s/step1-forces.png", sub);
    CHECK(colour_run(path, -1, 0, 0, 0, 0, 1e9, 0, 1e9).n > 50);
    cn_sim_result_free(&R);
    cn_assembly_free(a);
}

static void test_unwritable(void) {
    char json[512], path[256];
    snprintf(json, sizeof json, TABLE_BLOCK, 1.0, 3.0, 3.0, 1.0);
    cnAssembly *a = load_ok(json);
    if (!a) return;
    snprintf(path, sizeof path, "%s/no/such/dir/f.png", dir);
    cnFigureOptions fo = cn_figure_options_default();
    cnDiag d;
    CHECK(cn_figure_check_png(path, a, NULL, &fo, &d) == CN_ERR_IO);
    CHECK_MSG(strstr(d.message, "f.png") || strstr(d.where, "f.png"), "where '%s' message '%s'", d.where, d.message);
    cn_assembly_free(a);
}

void test_figure(void) {
    if (!mkdtemp(dir)) {
        CHECK(!"mkdtemp");
        return;
    }
    test_resting_and_tipping();
    test_friction();
    test_3d();
    test_margin_figure();
    test_plot();
    test_simulation_figures();
    test_unwritable();
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
}
