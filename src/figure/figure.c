/* Figures of an assembly and its check (cairo, Debian libcairo2): parts, vertex numbers, contact
 * points with ids, force arrows, the motion that starts, and the verdict. 2-D is drawn with
 * gravity pointing down the page; 3-D in an axonometric view, faces by depth (painter's). */
#include <cairo.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sys/stat.h>

#include "figure_plot.h"
#include "core.h"

/* Longest force arrow (for the largest force) as a fraction of the view's size. */
#define FIG_FORCE_ARROW 0.12
/* Labels are drawn only where they stay readable: vertex numbers up to this many vertices,
 * contact ids up to this many contacts, part names for parts at least this many pixels tall. */
#define FIG_MAX_NUMBERED 240
#define FIG_MAX_CONTACT_IDS 60
#define FIG_MIN_NAMED_PX 30.0
/* Contacts projected closer than this (pixels) are at one spot: one label names them all. */
#define FIG_SAME_SPOT 4.0
/* A collapse figure turns a moving part by at most this (radians) */
#define FIG_COLLAPSE_TURN 0.2

cnFigureOptions cn_figure_options_default(void) {
    cnFigureOptions o = {900, 640, true, true};
    return o;
}

/* What to draw: parts posed (absent ones left out), contacts, the parts that move. */
typedef struct {
    int id;
    double point[3], normal[3], force, friction[3];
    bool separates, slides;
} FigContact;

typedef struct {
    const cnPose *pose;        /* per part; NULL: as loaded */
    const unsigned char *absent; /* NULL: every part but grippers */
    int ncontacts;
    const FigContact *contacts;
    const cnPartMotion *motion; /* per part, NULL: nothing moves */
    const unsigned char *red;   /* per part: drawn red (it starts to move) */
    bool friction;
    const cnPose *moved;        /* per part, NULL: the red parts also drawn dashed where their
                                   motion takes them (a collapse mechanism) */
    const unsigned char *gripped; /* per part, NULL: drawn steel blue (the gripper moves it) */
} Scene;

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


static bool shown(const cnAssembly *a, const Scene *sc, int i) {
    return cn_assembly_part_present(a, sc->absent, i);
}

/* a vertex of part i, posed */
static void posed(const Scene *sc, int i, const double v[3], double out[3]) {
    if (sc->pose) cn_pose_apply(&sc->pose[i], v, out);
    else cn_copy3(out, v);
}

/* a direction of part i (a face normal), posed */
static void posed_dir(const Scene *sc, int i, const double v[3], double out[3]) {
    if (sc->pose) cn_pose_rotate(&sc->pose[i], v, out);
    else cn_copy3(out, v);
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

/* Fit the view on the free parts (every pose in `fitp`, e.g. a whole path) and the contacts
 * (fixed parts such as a long table are clipped), or on everything when nothing is free. */
static void fit(View *v, const cnAssembly *a, const Scene *const *fitp, int nfit) {
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    int any_free = 0;
    for (int i = 0; i < a->nreal; i++) any_free |= !a->parts[i].fixed;
    for (int f = 0; f < nfit; f++) {
        const Scene *sc = fitp[f];
        for (int i = 0; i < a->nparts; i++) {
            const cnPart *p = &a->parts[i];
            if ((any_free && p->fixed) || !shown(a, sc, i)) continue;
            for (int s = 0; s < p->npieces; s++)
                for (int k = 0; k < p->pieces[s].nverts; k++) {
                    double q[3];
                    posed(sc, i, p->pieces[s].verts[k], q);
                    double x = cn_dot3(q, v->e1), y = cn_dot3(q, v->e2);
                    lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
                    lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
                }
        }
        for (int c = 0; c < sc->ncontacts; c++) {
            double x = cn_dot3(sc->contacts[c].point, v->e1);
            double y = cn_dot3(sc->contacts[c].point, v->e2);
            lo[0] = fmin(lo[0], x), hi[0] = fmax(hi[0], x);
            lo[1] = fmin(lo[1], y), hi[1] = fmax(hi[1], y);
        }
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

static void color_of(const cnAssembly *a, const Scene *sc, int i, double rgb[3]) {
    static const double pal[6][3] = {{0.55, 0.71, 0.86}, {0.62, 0.82, 0.62}, {0.96, 0.80, 0.50},
                                     {0.78, 0.68, 0.88}, {0.55, 0.82, 0.80}, {0.90, 0.70, 0.75}};
    if (a->parts[i].gripper_step >= 0) rgb[0] = 0.35, rgb[1] = 0.35, rgb[2] = 0.45;
    else if (sc->gripped && sc->gripped[i]) rgb[0] = 0.33, rgb[1] = 0.51, rgb[2] = 0.76;
    else if (sc->red && sc->red[i]) rgb[0] = 0.89, rgb[1] = 0.34, rgb[2] = 0.26;
    else if (a->parts[i].fixed) rgb[0] = rgb[1] = rgb[2] = 0.72;
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

/* A line of text from (x, y) within width w: its size lowered (to 70% at most) until it fits,
 * then, if it still does not, cut with an ellipsis, so that no title or legend runs off the
 * picture. */
#define FIG_TEXT_MIN_SHRINK 0.7
static void text_fit(cairo_t *cr, double x, double y, const char *s, double size, double w) {
    cairo_text_extents_t te;
    cairo_set_font_size(cr, size);
    cairo_text_extents(cr, s, &te);
    if (te.x_advance > w) size = fmax(size * w / te.x_advance, size * FIG_TEXT_MIN_SHRINK);
    cairo_set_font_size(cr, size);
    cairo_text_extents(cr, s, &te);
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", s);
    for (size_t n = strlen(buf); te.x_advance > w && n > 4;) {
        n--;
        while (n > 0 && ((unsigned char)buf[n] & 0xC0) == 0x80) n--; /* whole UTF-8 characters */
        memcpy(buf + n, "\xe2\x80\xa6", 4); /* an ellipsis */
        cairo_text_extents(cr, buf, &te);
    }
    cairo_move_to(cr, x, y);
    cairo_show_text(cr, buf);
}

typedef struct {
    int part, piece, face;
    int group;     /* 0: supports (fixed parts), drawn first; 1: the rest */
    double pdepth; /* depth of the piece's centre: pieces are drawn whole, far to near */
    double depth;
} FaceRef;

static int cmp_depth(const void *x, const void *y) {
    const FaceRef *a = x, *b = y;
    if (a->group != b->group) return a->group - b->group;
    if (a->pdepth != b->pdepth) return (a->pdepth > b->pdepth) - (a->pdepth < b->pdepth);
    if (a->part != b->part || a->piece != b->piece)
        return a->part != b->part ? a->part - b->part : a->piece - b->piece;
    return (a->depth > b->depth) - (a->depth < b->depth);
}

/* A closed 2-D loop of part i's points (posed) as the current path. */
static void loop_path(cairo_t *cr, const View *v, const Scene *sc, int i, const double (*pts)[3], int n) {
    for (int k = 0; k < n; k++) {
        double x, y, q[3];
        posed(sc, i, pts[k], q);
        project(v, q, &x, &y);
        if (k == 0) cairo_move_to(cr, x, y);
        else cairo_line_to(cr, x, y);
    }
    cairo_close_path(cr);
}

static void outline_stroke(cairo_t *cr) {
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_set_line_width(cr, 1.2);
    cairo_stroke(cr);
}

static void draw_parts(cairo_t *cr, const View *v, const cnAssembly *a, const Scene *sc) {
    double rgb[3];
    if (a->dim == 2) {
        for (int i = 0; i < a->nparts; i++) {
            const cnPart *p = &a->parts[i];
            if (!shown(a, sc, i)) continue;
            color_of(a, sc, i, rgb);
            for (int s = 0; s < p->npieces; s++) {
                loop_path(cr, v, sc, i, (const double(*)[3])p->pieces[s].verts, p->pieces[s].nverts);
                if (p->noutline > 0) { /* pieces split from an outline: filled, the outline drawn */
                    /* opaque (the colour the translucent fill has over white), and stroked in
                       it, so that the pieces' shared edges leave no seam */
                    cairo_set_source_rgb(cr, 0.85 * rgb[0] + 0.15, 0.85 * rgb[1] + 0.15, 0.85 * rgb[2] + 0.15);
                    cairo_set_line_width(cr, 0.6);
                    cairo_fill_preserve(cr);
                    cairo_stroke(cr);
                    continue;
                }
                cairo_set_source_rgba(cr, rgb[0], rgb[1], rgb[2], 0.85);
                cairo_fill_preserve(cr);
                outline_stroke(cr);
            }
            if (p->noutline > 0) {
                loop_path(cr, v, sc, i, (const double(*)[3])p->outline, p->noutline);
                outline_stroke(cr);
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
            if (!shown(a, sc, i)) continue;
            const cnPiece *pc = &a->parts[i].pieces[s];
            double pc_c[3] = {0, 0, 0};
            for (int k = 0; k < pc->nverts; k++) {
                double q[3];
                posed(sc, i, pc->verts[k], q);
                cn_add3(pc_c, q, pc_c);
            }
            double pdepth = cn_dot3(pc_c, v->c) / pc->nverts;
            for (int f = 0; f < pc->nfaces; f++) {
                double fn[3];
                posed_dir(sc, i, pc->faces[f].normal, fn);
                if (cn_dot3(fn, v->c) <= 1e-9) continue; /* faces away */
                double d = 0;
                for (int k = 0; k < pc->faces[f].nverts; k++) {
                    double q[3];
                    posed(sc, i, pc->verts[pc->faces[f].verts[k]], q);
                    d += cn_dot3(q, v->c);
                }
                faces[nf].part = i, faces[nf].piece = s, faces[nf].face = f;
                faces[nf].group = a->parts[i].fixed && a->parts[i].gripper_step < 0 ? 0 : 1;
                faces[nf].pdepth = pdepth;
                faces[nf].depth = d / pc->faces[f].nverts;
                nf++;
            }
        }
    qsort(faces, (size_t)nf, sizeof(FaceRef), cmp_depth);
    for (int t = 0; t < nf; t++) {
        const cnPiece *pc = &a->parts[faces[t].part].pieces[faces[t].piece];
        const cnFace *F = &pc->faces[faces[t].face];
        color_of(a, sc, faces[t].part, rgb);
        double fn[3];
        posed_dir(sc, faces[t].part, F->normal, fn);
        double shade = 0.75 + 0.25 * cn_dot3(fn, v->e2); /* lit from above */
        for (int k = 0; k < F->nverts; k++) {
            double x, y, q[3];
            posed(sc, faces[t].part, pc->verts[F->verts[k]], q);
            project(v, q, &x, &y);
            if (k == 0) cairo_move_to(cr, x, y);
            else cairo_line_to(cr, x, y);
        }
        cairo_close_path(cr);
        cairo_set_source_rgb(cr, rgb[0] * shade, rgb[1] * shade, rgb[2] * shade); /* opaque: hidden faces stay hidden */
        cairo_fill_preserve(cr);
        cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
        cairo_set_line_width(cr, 1.0);
        cairo_stroke(cr);
    }
    cn_free(faces);
}

static void draw_vertex_numbers(cairo_t *cr, const View *v, const cnAssembly *a, const Scene *sc) {
    int total = 0;
    for (int i = 0; i < a->nparts; i++)
        total += a->parts[i].nnumbers;
    if (total > FIG_MAX_NUMBERED) return;
    int k = 0;
    char buf[16];
    cairo_set_source_rgb(cr, 0.35, 0.35, 0.35);
    for (int i = 0; i < a->nparts; i++) {
        const cnPart *p = &a->parts[i];
        /* a part split from an outline: its outline's points, each once */
        int nsrc = p->noutline > 0 ? 1 : p->npieces;
        for (int s = 0; s < nsrc; s++)
            for (int j = 0; j < (p->noutline > 0 ? p->noutline : p->pieces[s].nverts); j++) {
                k++;
                if (p->fixed || !shown(a, sc, i)) continue;
                double x, y, cxp, cyp, q[3], c[3];
                posed(sc, i, p->noutline > 0 ? p->outline[j] : p->pieces[s].verts[j], q);
                posed(sc, i, p->com, c);
                project(v, q, &x, &y);
                project(v, c, &cxp, &cyp);
                double dx = x - cxp, dy = y - cyp, L = hypot(dx, dy);
                if (L > 0) dx /= L, dy /= L;
                snprintf(buf, sizeof buf, "%d", k);
                text_at(cr, x - 9 * dx, y - 9 * dy, buf, 9.5, 1);
            }
    }
}

/* Occlusion tests of contact points against faces, at most (contacts times faces): past it,
 * every contact is drawn as seen. */
#define FIG_OCCLUSION_WORK 4e6

/* Is p (3-D) behind a face of a shown part, seen along the view? A face it lies on does not
 * hide it (tol: world units). */
static bool occluded(const View *v, const cnAssembly *a, const Scene *sc, const double p[3],
                     double tol) {
    for (int i = 0; i < a->nparts; i++) {
        if (!shown(a, sc, i)) continue;
        for (int s = 0; s < a->parts[i].npieces; s++) {
            const cnPiece *pc = &a->parts[i].pieces[s];
            for (int f = 0; f < pc->nfaces; f++) {
                const cnFace *fc = &pc->faces[f];
                double fn[3], q0[3], d[3];
                posed_dir(sc, i, fc->normal, fn);
                double fc_ = cn_dot3(fn, v->c);
                if (fc_ <= 1e-9 || fc->nverts < 3) continue; /* faces away: the front face hides */
                posed(sc, i, pc->verts[fc->verts[0]], q0);
                cn_sub3(q0, p, d);
                double t = cn_dot3(fn, d) / fc_;
                if (!(t > tol)) continue;
                double x[3], inside = 1;
                for (int k = 0; k < 3; k++) x[k] = p[k] + t * v->c[k];
                for (int k = 0; k < fc->nverts && inside > 0; k++) {
                    double e0[3], e1[3], ed[3], xd[3], cr3[3];
                    posed(sc, i, pc->verts[fc->verts[k]], e0);
                    posed(sc, i, pc->verts[fc->verts[(k + 1) % fc->nverts]], e1);
                    cn_sub3(e1, e0, ed);
                    cn_sub3(x, e0, xd);
                    cn_cross3(ed, xd, cr3);
                    inside = cn_dot3(cr3, fn) >= -tol * cn_norm3(ed) ? 1 : -1;
                }
                if (inside > 0) return true;
            }
        }
    }
    return false;
}

static void draw_contacts(cairo_t *cr, const View *v, const cnAssembly *a, const Scene *sc,
                          const cnFigureOptions *o, double fscale) {
    double fmax_ = fscale;
    for (int c = 0; c < sc->ncontacts; c++) fmax_ = fmax(fmax_, sc->contacts[c].force);
    double span = (v->H - v->top - v->bottom) / v->scale; /* world units of the view height */
    double unit = fmax_ > 0 ? FIG_FORCE_ARROW * span / fmax_ : 0;
    char buf[64];
    double nfaces = 0;
    for (int i = 0; a->dim == 3 && i < a->nparts; i++)
        for (int s = 0; s < a->parts[i].npieces; s++) nfaces += a->parts[i].pieces[s].nfaces;
    bool test_hidden = a->dim == 3 && nfaces * sc->ncontacts <= FIG_OCCLUSION_WORK;
    for (int c = 0; c < sc->ncontacts; c++) {
        const FigContact *ct = &sc->contacts[c];
        double x, y;
        project(v, ct->point, &x, &y);
        const FigContact *res = ct;
        /* behind a part: drawn faint, its dot hollow */
        bool hidden = test_hidden && occluded(v, a, sc, ct->point, 1e-6 * span);
        double alpha = hidden ? 0.35 : 1;
        /* the force on the upper part of the pair (the legend's promise): the normal points into
         * the second part, so it is turned round where it points down */
        double up = -cn_dot3(ct->normal, a->gravity), sign = up < -1e-9 * cn_norm3(a->gravity) ? -1 : 1;
        double normal[3];
        for (int k = 0; k < 3; k++) normal[k] = sign * ct->normal[k];
        if (o->forces && res->force > 0) {
            double tip[3];
            for (int k = 0; k < 3; k++) tip[k] = ct->point[k] + normal[k] * res->force * unit;
            double tx, ty;
            project(v, tip, &tx, &ty);
            cairo_set_source_rgba(cr, 0.10, 0.25, 0.65, alpha);
            cairo_set_line_width(cr, 2.0);
            arrow(cr, x, y, tx, ty, 7);
            if (sc->friction && cn_norm3(res->friction) > 0) {
                for (int k = 0; k < 3; k++) tip[k] = ct->point[k] + sign * res->friction[k] * unit;
                project(v, tip, &tx, &ty);
                cairo_set_source_rgba(cr, 0.15, 0.55, 0.20, alpha);
                arrow(cr, x, y, tx, ty, 6);
            }
        }
        if (res->separates) cairo_set_source_rgb(cr, 0.85, 0.1, 0.1);
        else if (res->slides) cairo_set_source_rgb(cr, 0.95, 0.55, 0.0);
        else cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
        cairo_new_path(cr); /* no line from where the last label ended */
        cairo_arc(cr, x, y, (res->separates || res->slides) ? 4.5 : 3.0, 0, 2 * CN_PI);
        if (hidden) {
            cairo_set_line_width(cr, 1.2);
            cairo_stroke(cr);
        } else {
            cairo_fill(cr);
        }
        /* id label beside the point, away from the normal arrow */
        double nx, ny, o2[3];
        cn_add3(ct->point, normal, o2);
        project(v, o2, &nx, &ny);
        double dx = nx - x, dy = ny - y, L = hypot(dx, dy);
        if (L > 0) dx /= L, dy /= L;
        if (sc->ncontacts > FIG_MAX_CONTACT_IDS) continue;
        /* contacts drawn at one spot share one label, "4,5", given at the first of them */
        bool shown = false;
        for (int d = 0; d < c && !shown; d++) {
            double px, py;
            project(v, sc->contacts[d].point, &px, &py);
            shown = hypot(px - x, py - y) < FIG_SAME_SPOT;
        }
        if (shown) continue;
        int len = snprintf(buf, sizeof buf, "%d", ct->id);
        for (int d = c + 1; d < sc->ncontacts && len < (int)sizeof buf - 12; d++) {
            double px, py;
            project(v, sc->contacts[d].point, &px, &py);
            if (hypot(px - x, py - y) < FIG_SAME_SPOT)
                len += snprintf(buf + len, sizeof buf - (size_t)len, ",%d", sc->contacts[d].id);
        }
        cairo_set_source_rgb(cr, 0.10, 0.25, 0.65);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        text_at(cr, x - 11 * dx + 8 * dy, y - 11 * dy - 8 * dx, buf, 11, 1);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    }
}

static void draw_motion(cairo_t *cr, const View *v, const cnAssembly *a, const Scene *sc) {
    double span = (v->H - v->top - v->bottom) / v->scale;
    if (!sc->motion) return;
    for (int p = 0; p < a->nparts; p++) {
        const cnPartMotion *m = &sc->motion[p];
        if (!m->moves || !shown(a, sc, p)) continue;
        double x, y, c[3];
        posed(sc, p, a->parts[p].com, c);
        project(v, c, &x, &y);
        cairo_set_source_rgb(cr, 0.75, 0.0, 0.0);
        cairo_set_line_width(cr, 3.0);
        double L = cn_norm3(m->lin);
        if (L > 0) {
            double tip[3];
            for (int k = 0; k < 3; k++) tip[k] = c[k] + m->lin[k] / L * 0.12 * span;
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

static void draw_labels(cairo_t *cr, const View *v, const cnAssembly *a, const Scene *sc) {
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    for (int i = 0; i < a->nparts; i++) {
        if (a->parts[i].fixed || !shown(a, sc, i)) continue;
        double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
        for (int s = 0; s < a->parts[i].npieces; s++)
            for (int k = 0; k < a->parts[i].pieces[s].nverts; k++) {
                double px, py, q[3];
                posed(sc, i, a->parts[i].pieces[s].verts[k], q);
                project(v, q, &px, &py);
                lo[0] = fmin(lo[0], px), hi[0] = fmax(hi[0], px);
                lo[1] = fmin(lo[1], py), hi[1] = fmax(hi[1], py);
            }
        if (hi[1] - lo[1] < FIG_MIN_NAMED_PX) continue;
        double x, y, c[3];
        posed(sc, i, a->parts[i].com, c);
        project(v, c, &x, &y);
        text_at(cr, x + 10, y - 10, a->parts[i].name, 14, 1);
    }
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
}

/* The red parts' outlines where sc->moved puts them, dashed. */
static void draw_moved(cairo_t *cr, const View *v, const cnAssembly *a, const Scene *sc) {
    if (!sc->moved || !sc->red) return;
    Scene m = *sc;
    m.pose = sc->moved;
    double dash[2] = {6, 4};
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
    cairo_set_line_width(cr, 1.8);
    for (int i = 0; i < a->nparts; i++) {
        if (!sc->red[i] || !shown(a, sc, i)) continue;
        const cnPart *p = &a->parts[i];
        for (int s2 = 0; s2 < p->npieces; s2++) {
            const cnPiece *pc = &p->pieces[s2];
            if (a->dim == 2) {
                loop_path(cr, v, &m, i, (const double(*)[3])pc->verts, pc->nverts);
                cairo_stroke(cr);
                continue;
            }
            for (int f = 0; f < pc->nfaces; f++) {
                for (int k = 0; k < pc->faces[f].nverts; k++) {
                    double x, y, q[3];
                    posed(&m, i, pc->verts[pc->faces[f].verts[k]], q);
                    project(v, q, &x, &y);
                    if (k == 0) cairo_move_to(cr, x, y);
                    else cairo_line_to(cr, x, y);
                }
                cairo_close_path(cr);
                cairo_stroke(cr);
            }
        }
    }
    cairo_set_dash(cr, NULL, 0, 0);
}

/* An arrow for a gravity vector, top right, labelled. */
static void draw_gravity(cairo_t *cr, const View *v, const double g[3]) {
    double dx = cn_dot3(g, v->e1), dy = -cn_dot3(g, v->e2), L = hypot(dx, dy);
    if (!(L > 0)) return;
    double cx = v->W - 60, cy = v->top + 50, r = 36;
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    cairo_set_line_width(cr, 2.5);
    arrow(cr, cx - r * dx / L, cy - r * dy / L, cx + r * dx / L, cy + r * dy / L, 10);
    text_at(cr, cx + 12, cy - r - 4, "gravity", 11, 1);
}

/* Draw a scene on a cairo context; fit the view on the scenes `fitp` (the same view for the
 * pictures of one step). title: first line; verdict: second line (red when bad); legend: the
 * bottom line. */
typedef struct {
    const cnAssembly *a;
    const Scene *sc;
    const Scene *const *fitp;
    int nfit;
    const cnFigureOptions *o;
    const char *title, *verdict, *legend;
    bool bad;
    double fscale;
    const double *gravity; /* drawn as an arrow when not NULL */
} Render;

static void render(cairo_t *cr, const Render *R) {
    const cnAssembly *a = R->a;
    View v;
    memset(&v, 0, sizeof v);
    v.dim = a->dim, v.W = R->o->width, v.H = R->o->height, v.top = 56, v.bottom = 30;
    setup_axes(&v, a);
    fit(&v, a, R->fitp, R->nfit);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_save(cr);
    cairo_rectangle(cr, 0, v.top, v.W, v.H - v.top - v.bottom);
    cairo_clip(cr);
    draw_parts(cr, &v, a, R->sc);
    draw_moved(cr, &v, a, R->sc);
    if (R->o->vertex_numbers) draw_vertex_numbers(cr, &v, a, R->sc);
    draw_labels(cr, &v, a, R->sc);
    draw_contacts(cr, &v, a, R->sc, R->o, R->fscale);
    draw_motion(cr, &v, a, R->sc);
    if (R->gravity) draw_gravity(cr, &v, R->gravity);
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
    text_fit(cr, 10, 20, R->title, 13, v.W - 20);
    if (R->verdict) {
        if (R->bad) cairo_set_source_rgb(cr, 0.8, 0.1, 0.1);
        else cairo_set_source_rgb(cr, 0.1, 0.5, 0.15);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
        text_fit(cr, 10, 42, R->verdict, 15, v.W - 20);
        cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    }
    if (R->legend) {
        cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
        text_fit(cr, 10, v.H - 10, R->legend, 10.5, v.W - 20);
    }
}

static void render_cb(void *cr, const void *R) { render((cairo_t *)cr, (const Render *)R); }

/* Write the rendering to `path` (PNG), or with formats = 3 to base.png, base.svg and base.pdf
 * (path is then the base name without extension). */
static cnStatus render_files(const char *path, int formats, const Render *R, cnDiag *diag) {
    return cn_cairo_write(path, formats, R->o->width, R->o->height, render_cb, R, diag);
}

static const char *LEGEND =
    "blue: contact force on the upper part of each pair (longest = largest); dots: contacts "
    "(red opens, orange slides, hollow behind a part); red: parts that start to move, and how";
static const char *LEGEND_F =
    "on the upper part of each pair: blue contact force (longest = largest), green friction; "
    "dots: contacts (red opens, orange slides, hollow behind a part); red: parts that start to move";
/* ... in a step of a simulation, before them */
static const char *LEGEND_STEP = "steel blue: the part the gripper moves; ";

/* A check's contacts as drawn: points, normals, open and sliding, and (forces) their forces. */
static void fig_contacts(const cnCheckResult *r, int nc, bool forces, FigContact *fc) {
    for (int c = 0; c < nc; c++) {
        const cnContact *ct = &r->contacts.items[c];
        fc[c].id = ct->id;
        cn_copy3(fc[c].point, ct->point);
        cn_copy3(fc[c].normal, ct->normal);
        if (!r->contact) continue;
        if (forces) {
            fc[c].force = r->contact[c].normal_force;
            cn_copy3(fc[c].friction, r->contact[c].friction);
        }
        fc[c].separates = r->contact[c].separates;
        fc[c].slides = r->contact[c].slides;
    }
}

cnStatus cn_figure_check_png(const char *path, const cnAssembly *a, const cnCheckResult *r,
                             const cnFigureOptions *opt, cnDiag *diag) {
    cnFigureOptions o = opt ? *opt : cn_figure_options_default();
    int nc = r ? r->contacts.count : 0;
    FigContact *fc = cn_calloc((size_t)nc + 1, sizeof(FigContact));
    unsigned char *red = cn_calloc((size_t)a->nparts + 1, 1);
    if (!fc || !red) {
        cn_free(fc);
        cn_free(red);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
    fig_contacts(r, nc, true, fc);
    for (int i = 0; r && r->part && i < a->nparts; i++) red[i] = r->part[i].moves;
    Scene sc = {NULL, NULL, nc, fc, r ? r->part : NULL, red, r && r->friction, NULL, NULL};
    const Scene *fitp[1] = {&sc};
    char title[512], verdict[512] = "";
    snprintf(title, sizeof title, "%s", a->name ? a->name : (a->source ? a->source : "assembly"));
    if (r) {
        if (r->stable) snprintf(verdict, sizeof verdict, "STABLE: no part moves");
        else if (r->verdict == CN_VERDICT_UNDECIDED)
            snprintf(verdict, sizeof verdict, "UNDECIDED: a static solution (drawn) exists; a motion from rest was not ruled out");
        else {
            int len = snprintf(verdict, sizeof verdict, "%s",
                               r->verdict == CN_VERDICT_NOT_GUARANTEED
                                   ? "NOT GUARANTEED: held only by the squeeze drawn; can also move:"
                                   : "UNSTABLE: moving");
            for (int i = 0; i < r->nmoving && len < (int)sizeof verdict - 40; i++)
                len += snprintf(verdict + len, sizeof verdict - (size_t)len, " %s",
                                a->parts[r->moving[i]].name);
        }
    }
    Render R = {a, &sc, fitp, 1, &o, title, r ? verdict : NULL,
                r ? (r->friction ? LEGEND_F : LEGEND) : NULL, r && !r->stable, 0, NULL};
    cnStatus st = render_files(path, 1, &R, diag);
    cn_free(fc);
    cn_free(red);
    return st;
}

/* ---- figures of a simulation ---- */

typedef struct {
    int b1, b2, key; /* key: vertex number, or -id when the point is on no vertex */
    int n, cap;
    double *t, *y;
    int na, capa;
    double *ta, *ya; /* positive separation accelerations (in g) */
    double fmax;
    char label[96];
} Series;

static int series_of(Series **ss, int *ns, int *cap, const cnAssembly *a, int b1, int b2, int key) {
    for (int i = 0; i < *ns; i++)
        if ((*ss)[i].b1 == b1 && (*ss)[i].b2 == b2 && (*ss)[i].key == key) return i;
    if (*ns == *cap) {
        int nc = *cap ? 2 * *cap : 16;
        Series *n = cn_realloc(*ss, sizeof(Series) * (size_t)nc);
        if (!n) return -1;
        *ss = n;
        *cap = nc;
    }
    Series *s = &(*ss)[(*ns)++];
    memset(s, 0, sizeof *s);
    s->b1 = b1, s->b2 = b2, s->key = key;
    char v[24] = "";
    if (key > 0) snprintf(v, sizeof v, "%d ", key);
    snprintf(s->label, sizeof s->label, "%s%s/%s", v, b1 < 0 ? "fixel" : a->parts[b1].name,
             a->parts[b2].name);
    return *ns - 1;
}

static int push_pt(double **t, double **y, int *n, int *cap, double tv, double yv) {
    if (*n == *cap) {
        int nc = *cap ? 2 * *cap : 32;
        double *nt = cn_realloc(*t, sizeof(double) * (size_t)nc);
        if (!nt) return -1;
        *t = nt;
        double *ny = cn_realloc(*y, sizeof(double) * (size_t)nc);
        if (!ny) return -1;
        *y = ny;
        *cap = nc;
    }
    (*t)[*n] = tv, (*y)[*n] = yv, (*n)++;
    return 0;
}

static int cmp_series(const void *x, const void *y) {
    double a = ((const Series *)x)->fmax, b = ((const Series *)y)->fmax;
    return (a < b) - (a > b);
}

static cnStatus step_plot(const char *base, const cnAssembly *a, const cnSimResult *R, int kk,
                          const char *title, cnDiag *diag) {
    const cnStepResult *out = &R->steps[kk];
    double W = out->weight > 0 ? out->weight : 1, g = cn_norm3(a->gravity);
    Series *ss = NULL;
    int ns = 0, cap = 0;
    cnStatus st = CN_OK;
    for (int j = out->first_sample; j < out->first_sample + out->nsamples && !st; j++) {
        const cnSimSample *sm = &R->samples[j];
        for (int c = sm->first; c < sm->first + sm->count && !st; c++) {
            const cnSimContact *x = &R->contacts[c];
            int i = series_of(&ss, &ns, &cap, a, x->body1, x->body2, x->vertex ? x->vertex : -x->id);
            if (i < 0 || push_pt(&ss[i].t, &ss[i].y, &ss[i].n, &ss[i].cap, sm->time, x->force / W))
                st = CN_ERR_MEMORY;
            else if (x->separates &&
                     push_pt(&ss[i].ta, &ss[i].ya, &ss[i].na, &ss[i].capa, sm->time, x->motion / g))
                st = CN_ERR_MEMORY;
            if (i >= 0) ss[i].fmax = fmax(ss[i].fmax, x->force / W);
        }
    }
    /* the state at the onset */
    if (!st && out->has_onset && out->status == CN_STEP_UNSTABLE && out->onset.contact) {
        for (int c = 0; c < out->onset.contacts.count && !st; c++) {
            const cnContact *ct = &out->onset.contacts.items[c];
            const cnContactResult *cr = &out->onset.contact[c];
            int i = series_of(&ss, &ns, &cap, a, ct->body1, ct->body2, ct->vertex ? ct->vertex : -ct->id);
            if (i < 0 || push_pt(&ss[i].t, &ss[i].y, &ss[i].n, &ss[i].cap, out->onset_time, cr->normal_force / W))
                st = CN_ERR_MEMORY;
            else if (cr->separates && push_pt(&ss[i].ta, &ss[i].ya, &ss[i].na, &ss[i].capa,
                                              out->onset_time, cr->separation / g))
                st = CN_ERR_MEMORY;
        }
    }
    if (st) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    } else {
        qsort(ss, (size_t)ns, sizeof(Series), cmp_series);
        int keep = ns < 24 ? ns : 24;
        int nalarm = 0;
        for (int i = 0; i < keep; i++) nalarm += ss[i].na > 0;
        cnPlotSeries *ps = cn_calloc((size_t)(keep + nalarm + 1), sizeof(cnPlotSeries));
        char(*alabels)[128] = cn_calloc((size_t)nalarm + 1, sizeof(char[128]));
        if (!ps || !alabels) st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
        else {
            int m = 0, q = 0;
            for (int i = 0; i < keep; i++) {
                ps[m].label = ss[i].label, ps[m].n = ss[i].n, ps[m].t = ss[i].t, ps[m].y = ss[i].y;
                m++;
            }
            for (int i = 0; i < keep; i++) {
                if (!ss[i].na) continue;
                snprintf(alabels[q], sizeof alabels[q], "accel. at %s (g)", ss[i].label);
                ps[m].label = alabels[q++], ps[m].n = ss[i].na, ps[m].t = ss[i].ta, ps[m].y = ss[i].ya;
                ps[m].alarm = true;
                m++;
            }
            char sub[256];
            if (out->status == CN_STEP_UNSTABLE)
                snprintf(sub, sizeof sub, "unstable at t = %.6g (red: positive separation accelerations)",
                         out->onset_time);
            else if (out->status == CN_STEP_INFEASIBLE)
                snprintf(sub, sizeof sub, "geometrically infeasible at t = %.6g", out->onset_time);
            else if (out->status == CN_STEP_UNDECIDED)
                snprintf(sub, sizeof sub, "undecided at t = %.6g (not proved stable)", out->onset_time);
            else snprintf(sub, sizeof sub, "stable throughout");
            double x1 = out->t1 > out->t0 ? out->t1 : out->t0 + 1;
            double(*band)[2] = cn_calloc((size_t)out->ncarry + 1, sizeof(double[2]));
            char blabel[160];
            snprintf(blabel, sizeof blabel, "gripper carries %s",
                     out->ncarry > 0 && out->carry[0].part >= 0 ? a->parts[out->carry[0].part].name : "the part");
            for (int c = 0; band && c < out->ncarry; c++) band[c][0] = out->carry[c].t0, band[c][1] = out->carry[c].t1;
            cnPlot p = {title, sub, "time", "contact force / weight of the moved parts",
                        out->status != CN_STEP_STABLE, out->t0, x1,
                        out->has_onset && out->status != CN_STEP_STABLE, out->onset_time, m, ps,
                        band ? out->ncarry : 0, (const double(*)[2])band, blabel};
            st = cn_plot_write(base, &p, diag);
            cn_free(band);
        }
        cn_free(ps);
        cn_free(alabels);
    }
    for (int i = 0; i < ns; i++) {
        cn_free(ss[i].t);
        cn_free(ss[i].y);
        cn_free(ss[i].ta);
        cn_free(ss[i].ya);
    }
    cn_free(ss);
    return st;
}

/* simulate --margin: a stable step's margins at its samples against time (tilt in radians, so
 * that the three share an axis), the weakest of each marked by its value in the legend. No file
 * when the step has none. A lateral factor over the whole range searched is left out (it would
 * flatten the rest); so is a critical friction of none (+inf). */
static cnStatus margin_plot(const char *base, const cnSimResult *R, int kk, const char *title, cnDiag *diag) {
    const cnStepResult *out = &R->steps[kk];
    static const char *const names[3] = {"crit. friction", "tilt (rad)", "lateral (g)"};
    double *t = cn_calloc((size_t)out->nsamples * 3 + 1, sizeof(double));
    double *y = cn_calloc((size_t)out->nsamples * 3 + 1, sizeof(double));
    cnPlotSeries ps[3];
    char labels[3][96];
    int m = 0;
    if (!t || !y) {
        cn_free(t), cn_free(y);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
    for (int k = 0; k < 3; k++) {
        const cnStepMargin *w = &out->margin[k];
        if (!w->computed) continue;
        double *tk = t + (size_t)k * (size_t)out->nsamples, *yk = y + (size_t)k * (size_t)out->nsamples;
        int n = 0;
        for (int j = 0; j < out->nsamples; j++) {
            const cnSimSample *sm = &R->samples[out->first_sample + j];
            double v = sm->margin[k];
            if (!isfinite(v) || (k == 2 && v >= CN_MARGIN_MAX_LATERAL)) continue;
            tk[n] = sm->time, yk[n] = v, n++;
        }
        if (n == 0) continue;
        snprintf(labels[m], sizeof labels[m], "%s: weakest %.3g, t %.3g", names[k], w->at.value, w->time);
        ps[m] = (cnPlotSeries){labels[m], n, tk, yk, false};
        m++;
    }
    cnStatus st = CN_OK;
    if (m > 0) {
        char sub[160];
        snprintf(sub, sizeof sub, "margins at %d of its %d samples (simulate --margin)", out->margin[0].computed
                 ? out->margin[0].samples : out->margin[1].computed ? out->margin[1].samples : out->margin[2].samples,
                 out->nsamples);
        double x1 = out->t1 > out->t0 ? out->t1 : out->t0 + 1;
        cnPlot p = {title, sub, "time", "margin (critical friction; tilt in radians; lateral in g)", false, out->t0, x1,
                    false, 0, m, ps, 0, NULL, NULL};
        st = cn_plot_write(base, &p, diag);
    }
    cn_free(t);
    cn_free(y);
    return st;
}

/* Every part where it was loaded, the moved parts of step ps (and its gripper) at pose p. */
static void place_moved(cnPose *pose, int np, const cnPlanStep *ps, const cnPose *p) {
    for (int i = 0; i < np; i++) pose[i] = cn_pose_identity();
    for (int i = 0; i < ps->nmove; i++) pose[ps->move[i]] = *p;
    if (ps->gripper >= 0) pose[ps->gripper] = *p;
}

cnStatus cn_figure_simulation(const char *dir, const cnAssembly *a, const cnSimResult *R,
                              cnDiag *diag) {
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return cn_diag_set(diag, CN_ERR_IO, "", "cannot create the directory %s: %s", dir,
                           strerror(errno));
    cnFigureOptions o = cn_figure_options_default();
    int np = a->nparts;
    unsigned char *absent = cn_malloc((size_t)np), *red = cn_malloc((size_t)np),
                  *gripped = cn_malloc((size_t)np);
    cnPose *off = cn_calloc((size_t)np, sizeof(cnPose));
    int maxc = 1;
    for (int j = 0; j < R->nsamples; j++) maxc = R->samples[j].count > maxc ? R->samples[j].count : maxc;
    for (int kk = 0; kk < R->nsteps; kk++)
        if (R->steps[kk].onset.contacts.count > maxc) maxc = R->steps[kk].onset.contacts.count;
    FigContact *fc = cn_calloc((size_t)maxc + 1, sizeof(FigContact));
    cnStatus st = CN_OK;
    if (!absent || !red || !gripped || !off || !fc)
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    const char *prefix = R->assemble ? "assembly-" : "";
    for (int kk = 0; kk < R->nsteps && !st; kk++) {
        const cnStepResult *out = &R->steps[kk];
        const cnPlanStep *ps = &a->plan[R->plan_index[kk]];
        if (out->status == CN_STEP_SKIPPED || out->nsamples == 0) continue;
        /* the scene of this step: parts moved by other steps before it are gone (disassembly) or
         * not yet there (assembly) */
        for (int i = 0; i < np; i++) absent[i] = a->parts[i].gripper_step >= 0 && i != ps->gripper;
        for (int jj = 0; jj < R->nsteps; jj++) {
            bool gone = R->assemble ? jj > kk : jj < kk;
            if (!gone) continue;
            const cnPlanStep *o2 = &a->plan[R->plan_index[jj]];
            for (int i = 0; i < o2->nmove; i++) absent[o2->move[i]] = 1;
        }
        memset(red, 0, (size_t)np);
        memset(gripped, 0, (size_t)np);
        for (int i = 0; i < ps->nmove; i++) gripped[ps->move[i]] = 1;
        char names[256] = "";
        for (int i = 0; i < ps->nmove; i++) {
            strncat(names, i ? ", " : "", sizeof names - strlen(names) - 1);
            strncat(names, a->parts[ps->move[i]].name, sizeof names - strlen(names) - 1);
        }
        char title[512], path[1024], verdict[512];
        /* poses to fit the view on: start, onset or end */
        const cnSimSample *first = &R->samples[out->first_sample];
        const cnSimSample *last = &R->samples[out->first_sample + out->nsamples - 1];
        cnPose *off2 = cn_calloc((size_t)np, sizeof(cnPose));
        if (!off2) {
            st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
            break;
        }
        place_moved(off2, np, ps, out->has_onset ? &out->onset_pose : &last->pose);
        Scene fit2 = {off2, absent, 0, NULL, NULL, red, false, NULL, gripped};
        for (int pic = 0; pic < 3 && !st; pic++) {
            /* 0: start, 1: onset (when there is one), 2: end (when stable) */
            if (pic == 1 && !out->has_onset) continue;
            if (pic == 2 && out->status != CN_STEP_STABLE) continue;
            const cnSimSample *sm = pic == 0 ? first : last;
            place_moved(off, np, ps, pic == 1 ? &out->onset_pose : &sm->pose);
            int nc = 0;
            const cnPartMotion *motion = NULL;
            bool bad = false;
            double t = sm->time;
            if (pic == 1) {
                t = out->onset_time;
                bad = true;
                if (out->onset.contact) {
                    for (int c = 0; c < out->onset.contacts.count; c++) {
                        const cnContact *ct = &out->onset.contacts.items[c];
                        FigContact *f = &fc[nc++];
                        memset(f, 0, sizeof *f);
                        f->id = ct->id;
                        cn_copy3(f->point, ct->point);
                        cn_copy3(f->normal, ct->normal);
                        f->force = out->onset.contact[c].normal_force;
                        cn_copy3(f->friction, out->onset.contact[c].friction);
                        f->separates = out->onset.contact[c].separates;
                        f->slides = out->onset.contact[c].slides;
                    }
                    motion = out->onset.part;
                    for (int i = 0; i < np; i++) red[i] = out->onset.part[i].moves && !gripped[i];
                }
                if (out->status == CN_STEP_INFEASIBLE)
                    snprintf(verdict, sizeof verdict, "t = %.6g: %s would penetrate %s", t,
                             out->blocked_part >= 0 ? a->parts[out->blocked_part].name : "?",
                             out->blocking_part >= 0 ? a->parts[out->blocking_part].name : "?");
                else if (out->status == CN_STEP_UNDECIDED)
                    snprintf(verdict, sizeof verdict, "t = %.6g: UNDECIDED%s: a static solution, "
                             "no motion from rest found or ruled out", t,
                             out->onset_after ? " once the moved parts are away" : "");
                else {
                    int len = snprintf(verdict, sizeof verdict, "t = %.6g: UNSTABLE%s, moving", t,
                                       out->onset_after ? " once the moved parts are away" : "");
                    for (int i = 0; i < out->onset.nmoving && len < (int)sizeof verdict - 40; i++)
                        len += snprintf(verdict + len, sizeof verdict - (size_t)len, " %s",
                                        a->parts[out->onset.moving[i]].name);
                }
            } else {
                for (int c = sm->first; c < sm->first + sm->count; c++) {
                    const cnSimContact *x = &R->contacts[c];
                    FigContact *f = &fc[nc++];
                    memset(f, 0, sizeof *f);
                    f->id = x->id;
                    cn_copy3(f->point, x->point);
                    cn_copy3(f->normal, x->normal);
                    f->force = x->force;
                    f->separates = x->separates;
                    f->slides = x->slides;
                }
                snprintf(verdict, sizeof verdict, "t = %.6g: %s", t,
                         sm->stable ? "stable" : "not stable");
                bad = !sm->stable;
            }
            if (cn_path_turns(ps->seg, ps->nseg)) {
                size_t len = strlen(verdict);
                double ang = (pic == 1 ? out->onset_angle : sm->angle) * 180 / CN_PI;
                snprintf(verdict + len, sizeof verdict - len, " (turned %.4g deg)", fabs(ang) < 5e-5 ? 0.0 : ang);
            }
            Scene sc = {off, absent, nc, fc, motion, red, pic == 1 && out->onset.friction, NULL, gripped};
            Scene fit1 = {NULL, absent, 0, NULL, NULL, red, false, NULL, gripped};
            cnPose *off0 = cn_calloc((size_t)np, sizeof(cnPose));
            if (!off0) {
                st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
                break;
            }
            place_moved(off0, np, ps, &first->pose);
            fit1.pose = off0;
            const Scene *fitp[2] = {&fit1, &fit2};
            static const char *which[3] = {"start", "onset", "end"};
            snprintf(title, sizeof title, "%s step %d: %s %s (%s), %s", R->assemble ? "assembly" : "disassembly",
                     kk + 1, R->assemble ? "insert" : "move", names,
                     ps->support == CN_SUPPORT_PUSH ? "pushed" : "held", which[pic]);
            snprintf(path, sizeof path, "%s/%sstep%d-%s", dir, prefix, kk + 1, which[pic]);
            char legend[512];
            snprintf(legend, sizeof legend, "%s%s", LEGEND_STEP, sc.friction ? LEGEND_F : LEGEND);
            Render Rd = {a, &sc, fitp, 2, &o, title, verdict, legend, bad, out->weight, NULL};
            st = render_files(path, 3, &Rd, diag);
            cn_free(off0);
        }
        cn_free(off2);
        if (st) break;
        snprintf(title, sizeof title, "%s step %d: %s %s (%s)", R->assemble ? "assembly" : "disassembly",
                 kk + 1, R->assemble ? "insert" : "move", names,
                 ps->support == CN_SUPPORT_PUSH ? "pushed" : "held");
        snprintf(path, sizeof path, "%s/%sstep%d-forces", dir, prefix, kk + 1);
        st = step_plot(path, a, R, kk, title, diag);
        if (!st) {
            snprintf(path, sizeof path, "%s/%sstep%d-margin", dir, prefix, kk + 1);
            st = margin_plot(path, R, kk, title, diag);
        }
    }
    cn_free(absent);
    cn_free(red);
    cn_free(gripped);
    cn_free(off);
    cn_free(fc);
    return st;
}

/* ---- the collapse mechanism of a margin ---- */

cnStatus cn_figure_margin(const char *path, const cnAssembly *a, const cnMargin *m, int kind,
                          const cnFigureOptions *opt, cnDiag *diag) {
    const cnCheckResult *r = &m->collapse;
    if (!m->computed || !r->part || (r->verdict != CN_VERDICT_UNSTABLE && r->verdict != CN_VERDICT_NOT_GUARANTEED))
        return cn_diag_set(diag, CN_ERR_INPUT, "", "no collapse to draw: the margin has no not-stable verdict");
    cnFigureOptions o = opt ? *opt : cn_figure_options_default();
    int nc = r->contacts.count;
    FigContact *fc = cn_calloc((size_t)nc + 1, sizeof(FigContact));
    unsigned char *red = cn_calloc((size_t)a->nparts + 1, 1);
    cnPose *moved = cn_calloc((size_t)a->nparts + 1, sizeof(cnPose));
    if (!fc || !red || !moved) {
        cn_free(fc), cn_free(red), cn_free(moved);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
    fig_contacts(r, nc, false, fc);
    /* the moving parts carried along their motion (its scale is arbitrary: it only starts) until
       the farthest point has moved a fifth of the largest moving part's size, and no part has
       turned more than FIG_COLLAPSE_TURN */
    double big = 0, size = 0, wmax = 0;
    for (int i = 0; i < a->nparts; i++) {
        const cnPartMotion *pm = &r->part[i];
        red[i] = pm->moves;
        if (!pm->moves) continue;
        double d[3];
        cn_sub3(a->parts[i].hi, a->parts[i].lo, d);
        size = fmax(size, cn_norm3(d));
        wmax = fmax(wmax, cn_norm3(pm->ang));
        big = fmax(big, cn_norm3(pm->lin) + cn_norm3(pm->ang) * 0.5 * cn_norm3(d));
    }
    double s = big > 0 ? 0.2 * size / big : 0;
    if (wmax * s > FIG_COLLAPSE_TURN) s = FIG_COLLAPSE_TURN / wmax;
    for (int i = 0; i < a->nparts; i++) {
        moved[i] = cn_pose_identity();
        if (!red[i]) continue;
        const cnPartMotion *pm = &r->part[i];
        double t[3], w = cn_norm3(pm->ang);
        for (int k = 0; k < 3; k++) t[k] = pm->lin[k] * s;
        cnPose turn = w > 0 ? cn_pose_rotation(pm->ang, w * s, a->parts[i].com) : cn_pose_identity();
        cnPose shift = cn_pose_translation(t);
        moved[i] = cn_pose_then(&turn, &shift);
    }
    Scene sc = {NULL, NULL, nc, fc, r->part, red, false, moved, NULL};
    Scene there = {moved, NULL, 0, NULL, NULL, red, false, NULL, NULL};
    const Scene *fitp[2] = {&sc, &there};
    char title[512], verdict[512];
    snprintf(title, sizeof title, "%s", a->name ? a->name : (a->source ? a->source : "assembly"));
    double deg = 180 / CN_PI;
    int len;
    if (kind == CN_MARGIN_FRICTION)
        len = snprintf(verdict, sizeof verdict, "critical friction %.6g; at %.6g:", m->value, m->mechanism_at);
    else if (kind == CN_MARGIN_TILT)
        len = snprintf(verdict, sizeof verdict, "tilt %.5g deg; turned %.5g deg:", m->value * deg, m->mechanism_at * deg);
    else
        len = snprintf(verdict, sizeof verdict, "lateral %.5g g; at %.5g g:", m->value, m->mechanism_at);
    len += snprintf(verdict + len, sizeof verdict - (size_t)len, " %s",
                    r->verdict == CN_VERDICT_NOT_GUARANTEED ? "not guaranteed, can move" : "moving");
    for (int i = 0; i < r->nmoving && len < (int)sizeof verdict - 40; i++)
        len += snprintf(verdict + len, sizeof verdict - (size_t)len, " %s", a->parts[r->moving[i]].name);
    static const char *legend = "as loaded; dashed red: the moving parts carried along the motion at collapse "
                                "(exaggerated); dots: contacts (red opens, orange slides); arrow: gravity there";
    Render R = {a, &sc, fitp, 2, &o, title, verdict, legend, true, 0, m->gravity};
    cnStatus st = render_files(path, 1, &R, diag);
    cn_free(fc), cn_free(red), cn_free(moved);
    return st;
}
