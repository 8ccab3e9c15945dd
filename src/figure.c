/* Figures of an assembly and its check (cairo, Debian libcairo2): parts, vertex numbers, contact
 * points with ids, force arrows, the motion that starts, and the verdict. 2-D is drawn with
 * gravity pointing down the page; 3-D in an axonometric view, faces by depth (painter's). */
#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "internal.h"

/* Longest force arrow (for the largest force) as a fraction of the view's size. */
#define FIG_FORCE_ARROW 0.12
/* Labels are drawn only where they stay readable: vertex numbers up to this many vertices,
 * contact ids up to this many contacts, part names for parts at least this many pixels tall. */
#define FIG_MAX_NUMBERED 240
#define FIG_MAX_CONTACT_IDS 60
#define FIG_MIN_NAMED_PX 30.0

cnFigureOptions cn_figure_options_default(void) {
    cnFigureOptions o = {900, 640, true, true};
    return o;
}

typedef struct {
    int dim, W, H;
    double e1[3], e2[3], c[3]; /* screen right, screen up, towards the viewer */
    double cx, cy, scale;
    double top, bottom;        /* pixels reserved for title and legend */
} View;

static void project(const View *v, const double p[3], double *x, double *y) {
    *x = v->W / 2.0 + (cn_dot3(p, v->e1) - v->cx) * v->scale;
    *y = v->top + (v->H - v->top - v->bottom) / 2.0 - (cn_dot3(p, v->e2) - v->cy) * v->scale;
}

static void setup_axes(View *v, const cnAssembly *a) {
    double u[3];
    cn_copy3(u, a->gravity);
    cn_scale3(u, -1.0 / cn_norm3(u));
    if (a->dim == 2) {
        cn_copy3(v->e2, u);
        v->e1[0] = u[1], v->e1[1] = -u[0], v->e1[2] = 0;
        v->c[0] = v->c[1] = 0, v->c[2] = 1;
        return;
    }
    /* horizontal basis h1, h2; camera from azimuth -55 deg, elevation 25 deg */
    double ax[3] = {0, 0, 0};
    int k = 0;
    if (fabs(u[1]) < fabs(u[k])) k = 1;
    if (fabs(u[2]) < fabs(u[k])) k = 2;
    ax[k] = 1;
    double h1[3], h2[3], d = cn_dot3(ax, u);
    for (int i = 0; i < 3; i++) h1[i] = ax[i] - d * u[i];
    cn_normalize3(h1);
    cn_cross3(u, h1, h2);
    double az = -55 * CN_PI / 180, el = 25 * CN_PI / 180;
    for (int i = 0; i < 3; i++)
        v->c[i] = cos(el) * (cos(az) * h1[i] + sin(az) * h2[i]) + sin(el) * u[i];
    double uc = cn_dot3(u, v->c);
    for (int i = 0; i < 3; i++) v->e2[i] = u[i] - uc * v->c[i];
    cn_normalize3(v->e2);
    cn_cross3(v->e2, v->c, v->e1);
}

/* Fit the view on the free parts and the contacts (fixed parts such as a long table are
 * clipped), or on everything when nothing is free. */
static void fit(View *v, const cnAssembly *a, const cnCheckResult *r) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    int any_free = 0;
    for (int i = 0; i < a->nparts; i++) any_free |= !a->parts[i].fixed;
    for (int i = 0; i < a->nparts; i++) {
        const cnPart *p = &a->parts[i];
        if (any_free && p->fixed) continue;
        for (int s = 0; s < p->npieces; s++)
            for (int k = 0; k < p->pieces[s].nverts; k++) {
                double x = cn_dot3(p->pieces[s].verts[k], v->e1);
                double y = cn_dot3(p->pieces[s].verts[k], v->e2);
                lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
                lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
            }
    }
    if (r)
        for (int c = 0; c < r->contacts.count; c++) {
            double x = cn_dot3(r->contacts.items[c].point, v->e1);
            double y = cn_dot3(r->contacts.items[c].point, v->e2);
            lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
            lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
        }
    double w = hi[0] - lo[0], h = hi[1] - lo[1], m = 0.18 * fmax(w, h);
    /* show a band of the supports below */
    lo[0] -= m, hi[0] += m, lo[1] -= m, hi[1] += m;
    w = hi[0] - lo[0], h = hi[1] - lo[1];
    v->cx = 0.5 * (lo[0] + hi[0]);
    v->cy = 0.5 * (lo[1] + hi[1]);
    double aw = v->W - 20, ah = v->H - v->top - v->bottom;
    v->scale = fmin(aw / fmax(w, 1e-300), ah / fmax(h, 1e-300));
}

static void color_of(const cnAssembly *a, const cnCheckResult *r, int i, double rgb[3]) {
    static const double pal[6][3] = {{0.55, 0.71, 0.86}, {0.62, 0.82, 0.62}, {0.96, 0.80, 0.50},
                                     {0.78, 0.68, 0.88}, {0.55, 0.82, 0.80}, {0.90, 0.70, 0.75}};
    if (a->parts[i].fixed) rgb[0] = rgb[1] = rgb[2] = 0.72;
    else if (r && r->part && r->part[i].moves) rgb[0] = 0.89, rgb[1] = 0.34, rgb[2] = 0.26;
    else memcpy(rgb, pal[i % 6], sizeof(double) * 3);
}

static void arrow(cairo_t *cr, double x0, double y0, double x1, double y1, double head) {
    double dx = x1 - x0, dy = y1 - y0, L = hypot(dx, dy);
    if (L < 1e-9) return;
    dx /= L, dy /= L;
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
    cairo_stroke(cr);
    cairo_move_to(cr, x1, y1);
    cairo_line_to(cr, x1 - head * (dx + 0.45 * dy), y1 - head * (dy - 0.45 * dx));
    cairo_line_to(cr, x1 - head * (dx - 0.45 * dy), y1 - head * (dy + 0.45 * dx));
    cairo_close_path(cr);
    cairo_fill(cr);
}

static void text_at(cairo_t *cr, double x, double y, const char *s, double size, int centre) {
    cairo_set_font_size(cr, size);
    cairo_text_extents_t te;
    cairo_text_extents(cr, s, &te);
    if (centre) x -= te.width / 2 + te.x_bearing, y -= te.height / 2 + te.y_bearing;
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, s);
}

typedef struct {
    int part, piece, face;
    double depth;
} FaceRef;

static int cmp_depth(const void *x, const void *y) {
    double a = ((const FaceRef *)x)->depth, b = ((const FaceRef *)y)->depth;
    return (a > b) - (a < b);
}

static void draw_parts(cairo_t *cr, const View *v, const cnAssembly *a, const cnCheckResult *r) {
    double rgb[3];
    if (a->dim == 2) {
        for (int i = 0; i < a->nparts; i++) {
            const cnPart *p = &a->parts[i];
            color_of(a, r, i, rgb);
            for (int s = 0; s < p->npieces; s++) {
                const cnPiece *pc = &p->pieces[s];
                for (int k = 0; k < pc->nverts; k++) {
                    double x, y;
                    project(v, pc->verts[k], &x, &y);
                    if (k == 0) cairo_move_to(cr, x, y);
                    else cairo_line_to(cr, x, y);
                }
                cairo_close_path(cr);
                cairo_set_source_rgba(cr, rgb[0], rgb[1], rgb[2], 0.85);
                cairo_fill_preserve(cr);
                cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
                cairo_set_line_width(cr, 1.2);
                cairo_stroke(cr);
            }
        }
        return;
    }
    int nf = 0;
    for (int i = 0; i < a->nparts; i++)
        for (int s = 0; s < a->parts[i].npieces; s++) nf += a->parts[i].pieces[s].nfaces;
    FaceRef *faces = cn_malloc(sizeof(FaceRef) * (size_t)(nf + 1));
    if (!faces) return;
    nf = 0;
    for (int i = 0; i < a->nparts; i++)
        for (int s = 0; s < a->parts[i].npieces; s++) {
            const cnPiece *pc = &a->parts[i].pieces[s];
            for (int f = 0; f < pc->nfaces; f++) {
                if (cn_dot3(pc->faces[f].normal, v->c) <= 1e-9) continue; /* faces away */
                double d = 0;
                for (int k = 0; k < pc->faces[f].nverts; k++)
                    d += cn_dot3(pc->verts[pc->faces[f].verts[k]], v->c);
                faces[nf].part = i, faces[nf].piece = s, faces[nf].face = f;
                faces[nf].depth = d / pc->faces[f].nverts;
                nf++;
            }
        }
    qsort(faces, (size_t)nf, sizeof(FaceRef), cmp_depth);
    for (int t = 0; t < nf; t++) {
        const cnPiece *pc = &a->parts[faces[t].part].pieces[faces[t].piece];
        const cnFace *F = &pc->faces[faces[t].face];
        color_of(a, r, faces[t].part, rgb);
        double shade = 0.75 + 0.25 * cn_dot3(F->normal, v->e2); /* lit from above */
        for (int k = 0; k < F->nverts; k++) {
            double x, y;
            project(v, pc->verts[F->verts[k]], &x, &y);
            if (k == 0) cairo_move_to(cr, x, y);
            else cairo_line_to(cr, x, y);
        }
        cairo_close_path(cr);
        cairo_set_source_rgba(cr, rgb[0] * shade, rgb[1] * shade, rgb[2] * shade, 0.82);
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        cairo_set_line_width(cr, 1.0);
        cairo_stroke(cr);
    }
    cn_free(faces);
}

static void draw_vertex_numbers(cairo_t *cr, const View *v, const cnAssembly *a) {
    int total = 0;
    for (int i = 0; i < a->nparts; i++)
        for (int s = 0; s < a->parts[i].npieces; s++) total += a->parts[i].pieces[s].nverts;
    if (total > FIG_MAX_NUMBERED) return;
    int k = 0;
    char buf[16];
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    for (int i = 0; i < a->nparts; i++) {
        const cnPart *p = &a->parts[i];
        for (int s = 0; s < p->npieces; s++)
            for (int j = 0; j < p->pieces[s].nverts; j++) {
                k++;
                if (p->fixed) continue;
                double x, y, cxp, cyp;
                project(v, p->pieces[s].verts[j], &x, &y);
                project(v, p->com, &cxp, &cyp);
                double dx = x - cxp, dy = y - cyp, L = hypot(dx, dy);
                if (L > 0) dx /= L, dy /= L;
                snprintf(buf, sizeof buf, "%d", k);
                text_at(cr, x - 9 * dx, y - 9 * dy, buf, 9.5, 1);
            }
    }
}

static void draw_contacts(cairo_t *cr, const View *v, const cnAssembly *a, const cnCheckResult *r,
                          const cnFigureOptions *o) {
    double fmax_ = 0;
    for (int c = 0; c < r->contacts.count && r->contact; c++)
        fmax_ = fmax(fmax_, r->contact[c].normal_force);
    double span = (v->H - v->top - v->bottom) / v->scale; /* world units of the view height */
    double unit = fmax_ > 0 ? FIG_FORCE_ARROW * span / fmax_ : 0;
    char buf[32];
    for (int c = 0; c < r->contacts.count; c++) {
        const cnContact *ct = &r->contacts.items[c];
        double x, y;
        project(v, ct->point, &x, &y);
        const cnContactResult *res = r->contact ? &r->contact[c] : NULL;
        if (o->forces && res && res->normal_force > 0) {
            double tip[3];
            for (int k = 0; k < 3; k++) tip[k] = ct->point[k] + ct->normal[k] * res->normal_force * unit;
            double tx, ty;
            project(v, tip, &tx, &ty);
            cairo_set_source_rgb(cr, 0.10, 0.25, 0.65);
            cairo_set_line_width(cr, 2.0);
            arrow(cr, x, y, tx, ty, 7);
            if (r->friction && cn_norm3(res->friction) > 0) {
                for (int k = 0; k < 3; k++) tip[k] = ct->point[k] + res->friction[k] * unit;
                project(v, tip, &tx, &ty);
                cairo_set_source_rgb(cr, 0.15, 0.55, 0.20);
                arrow(cr, x, y, tx, ty, 6);
            }
        }
        if (res && res->separates) cairo_set_source_rgb(cr, 0.85, 0.1, 0.1);
        else if (res && res->slides) cairo_set_source_rgb(cr, 0.95, 0.55, 0.0);
        else cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
        cairo_arc(cr, x, y, res && (res->separates || res->slides) ? 4.5 : 3.0, 0, 2 * CN_PI);
        cairo_fill(cr);
        /* id label beside the point, away from the normal arrow */
        double nx, ny, o2[3];
        cn_add3(ct->point, ct->normal, o2);
        project(v, o2, &nx, &ny);
        double dx = nx - x, dy = ny - y, L = hypot(dx, dy);
        if (L > 0) dx /= L, dy /= L;
        if (r->contacts.count > FIG_MAX_CONTACT_IDS) continue;
        snprintf(buf, sizeof buf, "%d", ct->id);
        cairo_set_source_rgb(cr, 0.10, 0.25, 0.65);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        text_at(cr, x - 11 * dx + 8 * dy, y - 11 * dy - 8 * dx, buf, 11, 1);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    }
}

static void draw_motion(cairo_t *cr, const View *v, const cnAssembly *a, const cnCheckResult *r) {
    double span = (v->H - v->top - v->bottom) / v->scale;
    for (int i = 0; i < r->nmoving; i++) {
        int p = r->moving[i];
        const cnPartMotion *m = &r->part[p];
        double x, y;
        project(v, a->parts[p].com, &x, &y);
        cairo_set_source_rgb(cr, 0.75, 0.0, 0.0);
        cairo_set_line_width(cr, 3.0);
        double L = cn_norm3(m->lin);
        if (L > 0) {
            double tip[3];
            for (int k = 0; k < 3; k++) tip[k] = a->parts[p].com[k] + m->lin[k] / L * 0.12 * span;
            double tx, ty;
            project(v, tip, &tx, &ty);
            arrow(cr, x, y, tx, ty, 10);
        }
        double d[3];
        cn_sub3(a->parts[p].hi, a->parts[p].lo, d);
        double edge_acc = fabs(m->ang[2]) * 0.5 * cn_norm3(d); /* at the part's edge */
        if (a->dim == 2 && edge_acc > 1e-6 * cn_norm3(a->gravity)) { /* a curved turn arrow */
            double rad = 18, s = m->ang[2] > 0 ? -1 : 1; /* screen y is down */
            cairo_set_line_width(cr, 2.0);
            double a0 = -CN_PI / 2, a1 = a0 + s * 1.4 * CN_PI;
            if (s > 0) cairo_arc(cr, x, y, rad, a0, a1);
            else cairo_arc_negative(cr, x, y, rad, a0, a1);
            cairo_stroke(cr);
            double ex = x + rad * cos(a1), ey = y + rad * sin(a1);
            double tx = -sin(a1) * s, ty = cos(a1) * s;
            arrow(cr, ex - 6 * tx, ey - 6 * ty, ex + 2 * tx, ey + 2 * ty, 8);
        }
    }
}

static void draw_labels(cairo_t *cr, const View *v, const cnAssembly *a) {
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    for (int i = 0; i < a->nparts; i++) {
        if (a->parts[i].fixed) continue;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int s = 0; s < a->parts[i].npieces; s++)
            for (int k = 0; k < a->parts[i].pieces[s].nverts; k++) {
                double px, py;
                project(v, a->parts[i].pieces[s].verts[k], &px, &py);
                lo[0] = fmin(lo[0], px), hi[0] = fmax(hi[0], px);
                lo[1] = fmin(lo[1], py), hi[1] = fmax(hi[1], py);
            }
        if (hi[1] - lo[1] < FIG_MIN_NAMED_PX) continue;
        double x, y;
        project(v, a->parts[i].com, &x, &y);
        text_at(cr, x + 10, y - 10, a->parts[i].name, 14, 1);
    }
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
}

cnStatus cn_figure_check_png(const char *path, const cnAssembly *a, const cnCheckResult *r,
                             const cnFigureOptions *opt, cnDiag *diag) {
    cnFigureOptions o = opt ? *opt : cn_figure_options_default();
    View v;
    memset(&v, 0, sizeof v);
    v.dim = a->dim, v.W = o.width, v.H = o.height, v.top = 56, v.bottom = 30;
    setup_axes(&v, a);
    fit(&v, a, r);
    cairo_surface_t *surf = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, v.W, v.H);
    cairo_t *cr = cairo_create(surf);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_save(cr);
    cairo_rectangle(cr, 0, v.top, v.W, v.H - v.top - v.bottom);
    cairo_clip(cr);
    draw_parts(cr, &v, a, r);
    if (o.vertex_numbers) draw_vertex_numbers(cr, &v, a);
    draw_labels(cr, &v, a);
    if (r) {
        draw_contacts(cr, &v, a, r, &o);
        draw_motion(cr, &v, a, r);
    }
    cairo_restore(cr);

    /* title and verdict */
    char buf[512];
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    snprintf(buf, sizeof buf, "%s", a->name ? a->name : (a->source ? a->source : "assembly"));
    text_at(cr, 10, 20, buf, 13, 0);
    if (r) {
        if (r->stable) {
            cairo_set_source_rgb(cr, 0.1, 0.5, 0.15);
            snprintf(buf, sizeof buf, "STABLE: no part moves");
        } else {
            cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
            int len = snprintf(buf, sizeof buf, "UNSTABLE: moving");
            for (int i = 0; i < r->nmoving && len < (int)sizeof buf - 40; i++)
                len += snprintf(buf + len, sizeof buf - (size_t)len, " %s",
                                a->parts[r->moving[i]].name);
        }
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        text_at(cr, 10, 42, buf, 15, 0);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
        cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
        snprintf(buf, sizeof buf,
                 "blue: contact force on the upper part of each pair (longest = largest)%s;  "
                 "dots: contacts (red opens, orange slides);  red arrows: motion that starts",
                 r->friction ? ", green: friction" : "");
        text_at(cr, 10, v.H - 10, buf, 10.5, 0);
    }
    cairo_destroy(cr);
    cairo_status_t cs = cairo_surface_write_to_png(surf, path);
    cairo_surface_destroy(surf);
    if (cs != CAIRO_STATUS_SUCCESS)
        return cn_diag_set(diag, CN_ERR_IO, "", "cannot write the figure %s: %s", path,
                           cairo_status_to_string(cs));
    return CN_OK;
}

cnStatus cn_figure_simulation(const char *dir, const cnAssembly *a, const cnSimResult *r,
                              cnDiag *diag) {
    (void)dir;
    (void)a;
    (void)r;
    return cn_diag_set(diag, CN_ERR_IO, "", "figures of simulations are not written yet");
}
