/* Drawing a scene (cairo, Debian libcairo2): parts, vertex numbers, contact points with ids,
 * force arrows, the motion that starts, and the verdict. 2-D is drawn with gravity pointing down
 * the page; 3-D in an axonometric view, faces by depth (painter's). */
#include <cairo.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "figure_scene.h"
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

cnStatus cn_fg_render_files(const char *path, int formats, const Render *R, cnDiag *diag) {
    return cn_cairo_write(path, formats, R->o->width, R->o->height, render_cb, R, diag);
}
