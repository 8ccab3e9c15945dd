/* A part's shape from JSON: polygons (split when not convex), hulls, boxes, meshes from files,
 * and poses. */
/* realpath (XSI) */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "collide.h"
#include "io.h"
#include "load_ctx.h"
#include "pieces.h"

/* How far from 1 the length of a rotation quaternion may be (it is then normalised). */
#define CN_QUATERNION_UNIT_TOL 1e-3

/* A convex polygon, either orientation; stored counter-clockwise. Coincident points, zero area,
 * reflex vertices and self-crossing are errors, each judged relative to the polygon's size.
 * nonconvex (may be NULL): a polygon with a reflex vertex is not an error but handed over, its
 * points counter-clockwise, in *nonconvex (*nn of them) for splitting; `out` is then untouched. */
static cnStatus make_polygon_or_outline(Ctx *c, const json_t *v, const char *path, cnPiece *out,
                                        double (**nonconvex)[3], int *nn);
static cnStatus make_polygon(Ctx *c, const json_t *v, const char *path, cnPiece *out) {
    return make_polygon_or_outline(c, v, path, out, NULL, NULL);
}

/* Reverse points in place. */
static void reverse_points(double (*pts)[3], int n) {
    for (int i = 0, j = n - 1; i < j; i++, j--) {
        double t[3];
        cn_copy3(t, pts[i]);
        cn_copy3(pts[i], pts[j]);
        cn_copy3(pts[j], t);
    }
}

static cnStatus make_polygon_or_outline(Ctx *c, const json_t *v, const char *path, cnPiece *out,
                                        double (**nonconvex)[3], int *nn) {
    double(*pts)[3];
    int n;
    cnStatus s = cn_ld_get_points(c, v, path, 2, 3, "a polygon", &pts, &n);
    if (s) return s;
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) lo[k] = fmin(lo[k], pts[i][k]), hi[k] = fmax(hi[k], pts[i][k]);
    double size = hypot(hi[0] - lo[0], hi[1] - lo[1]);
    double area2 = 0; /* about the first point: far from the origin the digits stay */
    for (int i = 0; i < n; i++) {
        const double *a = pts[i], *b = pts[(i + 1) % n];
        area2 += (a[0] - pts[0][0]) * (b[1] - pts[0][1]) - (a[1] - pts[0][1]) * (b[0] - pts[0][0]);
        if (hypot(b[0] - a[0], b[1] - a[1]) <= CN_TOL_LENGTH_ZERO * size) {
            cn_free(pts);
            return cn_ld_fail(c, path,
                              "points %d and %d coincide; remove the repeated point", i, (i + 1) % n);
        }
    }
    if (!(fabs(area2) > CN_TOL_LENGTH_ZERO * size * size)) {
        cn_free(pts);
        return cn_ld_fail(c, path, "the polygon has no area: its points are collinear or it crosses itself");
    }
    double sign = area2 > 0 ? 1 : -1;
    double turning = 0;
    for (int i = 0; i < n; i++) {
        const double *a = pts[(i + n - 1) % n], *b = pts[i], *d = pts[(i + 1) % n];
        double e1x = b[0] - a[0], e1y = b[1] - a[1], e2x = d[0] - b[0], e2y = d[1] - b[1];
        double cr = e1x * e2y - e1y * e2x;
        if (sign * cn_turn2(a, b, d) < 0) {
            if (nonconvex) { /* split by the caller */
                if (sign < 0) reverse_points(pts, n);
                *nonconvex = pts, *nn = n;
                return CN_OK;
            }
            cn_free(pts);
            return cn_ld_fail(c, path,
                              "not convex at vertex %d (the boundary turns the other way there); a piece "
                              "of \"polygons\" must be convex: split it further, or give the whole part as "
                              "one \"polygon\" (a simple outline is split into convex pieces for you)",
                              i);
        }
        turning += atan2(sign * cr, e1x * e2x + e1y * e2y);
    }
    if (turning > 2 * CN_PI * 1.5) {
        cn_free(pts);
        return cn_ld_fail(c, path, "the polygon winds around more than once (it crosses itself)");
    }
    out->shape = CN_SHAPE_POLYGON;
    out->nverts = n;
    out->verts = pts;
    if (sign < 0) reverse_points(pts, n); /* store counter-clockwise */
    return CN_OK;
}

/* Most points of a non-convex polygon split automatically (the simplicity test is quadratic). */
#define SPLIT_MAX_POINTS 4096

/* A non-convex simple polygon (counter-clockwise, n points, taken) split into convex pieces:
 * the part's pieces, numbered on the outline, which the part keeps. */
static cnStatus split_polygon(Ctx *c, double (*pts)[3], int n, const char *path, cnPart *part) {
    if (n > SPLIT_MAX_POINTS) {
        cn_free(pts);
        return cn_ld_fail(c, path, "a non-convex polygon of %d points; at most %d are split into convex "
                          "pieces automatically: give it as \"polygons\" (convex pieces)", n, SPLIT_MAX_POINTS);
    }
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) lo[k] = fmin(lo[k], pts[i][k]), hi[k] = fmax(hi[k], pts[i][k]);
    double tol = 1e-9 * hypot(hi[0] - lo[0], hi[1] - lo[1]);
    int e1, e2;
    if (!cn_polygon_simple((const double(*)[3])pts, n, tol, &e1, &e2)) {
        cn_free(pts);
        return cn_ld_fail(c, path, "not convex, and its edges %d-%d and %d-%d meet: a non-convex part must be a "
                          "simple polygon (its edges meet only at their shared ends; no holes); fix the points, or "
                          "give convex pieces with \"polygons\"", e1, (e1 + 1) % n, e2, (e2 + 1) % n);
    }
    int np = 0, *lens = NULL, **idx = NULL;
    int rc = cn_polygon_split((const double(*)[3])pts, n, tol, &np, &lens, &idx);
    if (rc < 0) {
        cn_free(pts);
        return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    }
    cnStatus s = CN_OK;
    if (rc > 0) s = cn_ld_fail(c, path, "not convex, and it could not be split into convex pieces (it nearly touches "
                               "itself); give convex pieces with \"polygons\"");
    if (!s && !(part->pieces = cn_calloc((size_t)np, sizeof(cnPiece))))
        s = cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    if (!s) part->npieces = np;
    for (int k = 0; !s && k < np; k++) {
        cnPiece *pc = &part->pieces[k];
        pc->shape = CN_SHAPE_POLYGON;
        pc->verts = cn_calloc((size_t)lens[k], sizeof(double[3]));
        pc->vnum = cn_malloc(sizeof(int) * (size_t)lens[k]);
        if (!pc->verts || !pc->vnum) {
            s = cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
            break;
        }
        pc->nverts = lens[k];
        double area2 = 0;
        for (int j = 0; j < lens[k]; j++) {
            cn_copy3(pc->verts[j], pts[idx[k][j]]);
            pc->vnum[j] = idx[k][j];
        }
        for (int j = 0; j < lens[k]; j++) { /* each piece convex, counter-clockwise, with area */
            const double *a = pc->verts[j], *b = pc->verts[(j + 1) % lens[k]], *d = pc->verts[(j + 2) % lens[k]];
            area2 += (a[0] - pc->verts[0][0]) * (b[1] - pc->verts[0][1]) - (a[1] - pc->verts[0][1]) * (b[0] - pc->verts[0][0]);
            if (cn_turn2(a, b, d) < 0)
                s = cn_ld_fail(c, path, "not convex, and its split into convex pieces failed (piece %d); give convex "
                               "pieces with \"polygons\"", k);
        }
        if (!s && !(area2 > tol * tol))
            s = cn_ld_fail(c, path, "not convex, and its split into convex pieces failed (piece %d has no area); give "
                           "convex pieces with \"polygons\"", k);
    }
    for (int k = 0; k < np; k++) cn_free(idx[k]);
    cn_free(idx), cn_free(lens);
    if (s) {
        cn_free(pts);
        return s;
    }
    part->outline = pts, part->noutline = n;
    return CN_OK;
}


static cnStatus make_hull(Ctx *c, const json_t *v, const char *path, cnPiece *out) {
    double(*pts)[3];
    int n;
    cnStatus s = cn_ld_get_points(c, v, path, 3, 4, "a hull", &pts, &n);
    if (s) return s;
    s = cn_hull3_build((const double(*)[3])pts, n, out, c->diag);
    cn_free(pts);
    if (s) {
        snprintf(c->diag->where, sizeof c->diag->where, "%s", path);
        return s;
    }
    return CN_OK;
}

static cnStatus make_box(Ctx *c, const json_t *v, const char *path, cnPiece *out) {
    if (!json_is_object(v))
        return cn_ld_fail(c, path, "expected a box: {\"min\": [x, y, z], \"max\": [x, y, z]}, found %s",
                          cn_ld_type_name(v));
    static const char *const keys[] = {"min", "max", NULL};
    cnStatus s = cn_ld_check_keys(c, v, path, keys);
    if (s) return s;
    double lo[3], hi[3];
    char p[PATH_MAX_LEN];
    for (int w = 0; w < 2; w++) {
        const char *k = w ? "max" : "min";
        snprintf(p, sizeof p, "%s.%s", path, k);
        json_t *e = json_object_get(v, k);
        if (!e) return cn_ld_fail(c, p, "missing; a box needs \"min\" and \"max\" corners");
        s = cn_ld_get_place(c, e, p, 3, w ? hi : lo);
        if (s) return s;
    }
    for (int k = 0; k < 3; k++)
        if (!(hi[k] > lo[k])) {
            snprintf(p, sizeof p, "%s.max[%d]", path, k);
            return cn_ld_fail(c, p, "must be greater than min[%d] (%g); a box needs volume", k, lo[k]);
        }
    double pts[8][3];
    for (int i = 0; i < 8; i++) {
        pts[i][0] = (i & 1) ? hi[0] : lo[0];
        pts[i][1] = (i & 2) ? hi[1] : lo[1];
        pts[i][2] = (i & 4) ? hi[2] : lo[2];
    }
    s = cn_hull3_build((const double(*)[3])pts, 8, out, c->diag);
    if (s) snprintf(c->diag->where, sizeof c->diag->where, "%s", path);
    return s;
}

static cnStatus make_pieces(Ctx *c, const json_t *v, const char *path, int multi, int kind,
                            cnPart *part) {
    /* kind: 0 polygon, 1 hull, 2 box */
    if (!multi && kind == 0) { /* a polygon: convex, or a simple outline split into pieces */
        cnPiece one;
        memset(&one, 0, sizeof one);
        double(*outline)[3] = NULL;
        int n = 0;
        cnStatus s = make_polygon_or_outline(c, v, path, &one, &outline, &n);
        if (s) return s;
        if (outline) return split_polygon(c, outline, n, path, part);
        part->pieces = cn_calloc(1, sizeof(cnPiece));
        if (!part->pieces) {
            cn_piece_free(&one);
            return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
        }
        part->npieces = 1;
        part->pieces[0] = one;
        return CN_OK;
    }
    if (!multi) {
        part->pieces = cn_calloc(1, sizeof(cnPiece));
        if (!part->pieces) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
        part->npieces = 1;
        return kind == 0 ? make_polygon(c, v, path, part->pieces)
               : kind == 1 ? make_hull(c, v, path, part->pieces)
                           : make_box(c, v, path, part->pieces);
    }
    if (!json_is_array(v) || json_array_size(v) == 0)
        return cn_ld_fail(c, path, "expected a non-empty array of convex pieces, found %s",
                          json_is_array(v) ? "an empty array" : cn_ld_type_name(v));
    int m = (int)json_array_size(v);
    part->pieces = cn_calloc((size_t)m, sizeof(cnPiece));
    if (!part->pieces) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    part->npieces = m;
    for (int i = 0; i < m; i++) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "%s[%d]", path, i);
        json_t *e = json_array_get(v, (size_t)i);
        cnStatus s = kind == 0 ? make_polygon(c, e, p, &part->pieces[i])
                               : make_hull(c, e, p, &part->pieces[i]);
        if (s) return s;
    }
    return CN_OK;
}

/* The file a part's "mesh" names: relative to the mesh directory (the assembly file's), and
 * inside it unless mesh_anywhere. */
static cnStatus mesh_file(Ctx *c, const json_t *v, const char *path, char *out, size_t n) {
    if (!json_is_string(v))
        return cn_ld_fail(c, path, "expected the path of a mesh file (OBJ, STL, PLY, OFF), found %s",
                          cn_ld_type_name(v));
    const char *rel = json_string_value(v);
    if (!rel[0]) return cn_ld_fail(c, path, "the path is empty; give the mesh file's path");
    const char *dir = c->mesh_dir ? c->mesh_dir : ".";
    if (rel[0] == '/') snprintf(out, n, "%s", rel);
    else if ((size_t)snprintf(out, n, "%s/%s", dir, rel) >= n)
        return cn_ld_fail(c, path, "the path is too long");
    char *real = realpath(out, NULL);
    if (!real)
        return cn_ld_fail(c, path, "cannot open the mesh file '%s'%s: %s", rel,
                          rel[0] == '/' ? "" : " (relative to the assembly file's directory)", strerror(errno));
    struct stat st;
    if (stat(real, &st) != 0 || !S_ISREG(st.st_mode)) {
        free(real);
        return cn_ld_fail(c, path, "'%s' is not a file; give a mesh file", rel);
    }
    if (!c->mesh_anywhere) {
        char *base = realpath(dir, NULL);
        size_t bl = base ? strlen(base) : 0;
        bool inside = base && !strncmp(real, base, bl) && (real[bl] == '/' || !strcmp(base, "/"));
        free(base);
        if (!inside) {
            free(real);
            return cn_ld_fail(c, path, "'%s' is outside the assembly file's directory; move it "
                              "there, or allow paths outside it with --mesh-anywhere", rel);
        }
    }
    free(real);
    return CN_OK;
}

/* A mesh's tolerance: rel of its bounding box's diagonal. */
static double mesh_tol(const cnMesh *m, double rel) {
    double lo[3], hi[3], d[3];
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int i = 0; i < m->nverts; i++)
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], m->verts[i][k]), hi[k] = fmax(hi[k], m->verts[i][k]);
    cn_sub3(hi, lo, d);
    return rel * cn_norm3(d);
}

/* Convex pieces of one checked closed mesh: itself when convex, else its exact decomposition.
 * Appended to *pieces (grown); *split counts the pieces a decomposition made. */
static cnStatus mesh_pieces(Ctx *c, cnMesh *m, const char *path, const char *what,
                            cnPiece **pieces, int *np, int *split) {
    double tol = mesh_tol(m, c->rel_tol);
    cnStatus s = cn_mesh_check(m, tol, c->diag);
    if (s) {
        if (s == CN_ERR_INPUT || s == CN_ERR_IO) { /* named at the part's mesh, its own status kept */
            char msg[sizeof c->diag->message];
            snprintf(msg, sizeof msg, "%s", c->diag->message);
            return cn_ld_fail(c, path, "%s %s", what, msg);
        }
        return s;
    }
    /* only the vertices the faces use */
    int nv = 0;
    double(*pts)[3] = cn_malloc(sizeof(double[3]) * (size_t)(m->start[m->nfaces] + 1));
    char *used = cn_calloc((size_t)m->nverts + 1, 1);
    if (!pts || !used) {
        cn_free(pts), cn_free(used);
        return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    }
    for (int k = 0; k < m->start[m->nfaces]; k++)
        if (!used[m->idx[k]]) used[m->idx[k]] = 1, cn_copy3(pts[nv++], m->verts[m->idx[k]]);
    cn_free(used);
    cnPiece hull;
    memset(&hull, 0, sizeof hull);
    s = cn_hull3_build((const double(*)[3])pts, nv, &hull, c->diag);
    cn_free(pts);
    if (s) {
        if (s == CN_ERR_INPUT) return cn_ld_fail(c, path, "%s is flat: its points are coplanar", what);
        return s;
    }
    cnMeshPieces mp = {0, NULL, NULL};
    int add = 1;
    if (!cn_mesh_is_convex(m, &hull, tol)) {
        int f1, f2;
        int r = cn_mesh_split(m, tol, &mp, &f1, &f2);
        if (r) {
            cn_piece_free(&hull);
            if (r < 0) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
            if (r == 3 && f1 >= 0 && f2 >= 0)
                return cn_ld_fail(c, path, "%s intersects itself: faces %d and %d cross; fix the mesh",
                                  what, m->face_id[f1], m->face_id[f2]);
            return cn_ld_fail(c, path, "%s is not convex, and %s", what, cn_mesh_split_why(r));
        }
        add = mp.n;
        *split += mp.n;
    }
    cnPiece *grown = cn_realloc(*pieces, sizeof(cnPiece) * (size_t)(*np + add));
    if (!grown) {
        cn_piece_free(&hull);
        cn_mesh_pieces_free(&mp);
        return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    }
    *pieces = grown;
    if (mp.n == 0) {
        (*pieces)[(*np)++] = hull;
        return CN_OK;
    }
    cn_piece_free(&hull);
    for (int i = 0; i < mp.n; i++) {
        memset(&(*pieces)[*np], 0, sizeof(cnPiece));
        s = cn_hull3_build((const double(*)[3])mp.pts[i], mp.lens[i], &(*pieces)[*np], c->diag);
        if (s) {
            cn_mesh_pieces_free(&mp);
            if (s == CN_ERR_INPUT)
                return cn_ld_fail(c, path, "%s: convex piece %d of its decomposition is flat", what, i);
            return s;
        }
        (*np)++;
    }
    cn_mesh_pieces_free(&mp);
    return CN_OK;
}

/* A part from a mesh file: each closed mesh of the file (an OBJ object or group) a convex piece
 * or, when not convex, its exact convex decomposition; when the file's meshes are not each
 * closed, all of them together as one surface. */
static cnStatus make_mesh(Ctx *c, const json_t *v, const char *path, double scale, cnPart *part) {
    char file[PATH_MAX + 1];
    cnStatus s = mesh_file(c, v, path, file, sizeof file);
    if (s) return s;
    cnMesh *ms;
    int n;
    if ((s = cn_mesh_read(file, json_string_value(v), scale, &ms, &n, c->diag))) {
        if (s == CN_ERR_INPUT || s == CN_ERR_IO) { /* named at the part's mesh, its own status kept */
            char msg[sizeof c->diag->message];
            snprintf(msg, sizeof msg, "%s", c->diag->message);
            cn_ld_fail(c, path, "%s", msg);
            if (c->diag) c->diag->code = s;
            return s;
        }
        return s;
    }
    /* separate closed meshes? (a probe of each: an open one sends them all together) */
    bool each = n > 1;
    for (int i = 0; i < n && each; i++) {
        int ne = ms[i].start[ms[i].nfaces];
        cnMesh probe = ms[i];
        probe.verts = cn_malloc(sizeof(double[3]) * (size_t)(probe.nverts + 1));
        probe.start = cn_malloc(sizeof(int) * (size_t)(probe.nfaces + 1));
        probe.idx = cn_malloc(sizeof(int) * (size_t)(ne + 1));
        probe.face_id = cn_malloc(sizeof(int) * (size_t)(probe.nfaces + 1));
        if (probe.verts && probe.start && probe.idx && probe.face_id) {
            memcpy(probe.verts, ms[i].verts, sizeof(double[3]) * (size_t)probe.nverts);
            memcpy(probe.start, ms[i].start, sizeof(int) * (size_t)(probe.nfaces + 1));
            memcpy(probe.idx, ms[i].idx, sizeof(int) * (size_t)ne);
            memcpy(probe.face_id, ms[i].face_id, sizeof(int) * (size_t)probe.nfaces);
            cnDiag quiet;
            each = cn_mesh_check(&probe, mesh_tol(&probe, c->rel_tol), &quiet) == CN_OK;
        } else {
            each = false;
        }
        cn_mesh_free(&probe);
    }
    if (!each && n > 1) { /* one surface of all the file's faces */
        cnMesh all;
        memset(&all, 0, sizeof all);
        int nv = 0, nf = 0, ni = 0;
        for (int i = 0; i < n; i++) nv += ms[i].nverts, nf += ms[i].nfaces, ni += ms[i].start[ms[i].nfaces];
        all.verts = cn_malloc(sizeof(double[3]) * (size_t)(nv + 1));
        all.start = cn_malloc(sizeof(int) * (size_t)(nf + 1));
        all.idx = cn_malloc(sizeof(int) * (size_t)(ni + 1));
        all.face_id = cn_malloc(sizeof(int) * (size_t)(nf + 1));
        if (all.verts && all.start && all.idx && all.face_id) {
            int vb = 0, fb = 0, ib = 0;
            for (int i = 0; i < n; i++) {
                memcpy(all.verts + vb, ms[i].verts, sizeof(double[3]) * (size_t)ms[i].nverts);
                for (int f = 0; f < ms[i].nfaces; f++) {
                    all.start[fb + f] = ib + ms[i].start[f];
                    all.face_id[fb + f] = fb + f + 1;
                }
                for (int k = 0; k < ms[i].start[ms[i].nfaces]; k++) all.idx[ib + k] = vb + ms[i].idx[k];
                vb += ms[i].nverts, fb += ms[i].nfaces, ib += ms[i].start[ms[i].nfaces];
            }
            all.start[fb] = ib;
            all.nverts = nv, all.nfaces = nf;
        }
        for (int i = 0; i < n; i++) cn_mesh_free(&ms[i]);
        if (!all.verts || !all.start || !all.idx || !all.face_id) {
            cn_mesh_free(&all);
            cn_free(ms);
            return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
        }
        ms[0] = all;
        n = 1;
    }
    cnPiece *pieces = NULL;
    int np = 0, split = 0;
    for (int i = 0; i < n && !s; i++) {
        char what[160];
        if (n > 1) snprintf(what, sizeof what, "object '%s' of the mesh", ms[i].name);
        else snprintf(what, sizeof what, "the mesh");
        s = mesh_pieces(c, &ms[i], path, what, &pieces, &np, &split);
    }
    for (int i = 0; i < n; i++) cn_mesh_free(&ms[i]);
    cn_free(ms);
    if (s) {
        for (int i = 0; i < np; i++) cn_piece_free(&pieces[i]);
        cn_free(pieces);
        return s;
    }
    part->pieces = pieces;
    part->npieces = np;
    part->mesh_split = split;
    part->mesh_file = cn_strdup(json_string_value(v));
    if (!part->mesh_file) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    return CN_OK;
}

/* The one shape key of a part (or gripper) object: polygon / polygons in 2-D; box / hull /
 * hulls in 3-D. */
cnStatus cn_ld_load_shape(Ctx *c, const json_t *v, const char *path, cnPart *part) {
    char p[PATH_MAX_LEN];
    const char *shapes2[] = {"polygon", "polygons"};
    const char *shapes3[] = {"box", "hull", "hulls", "mesh"};
    int nshapes = c->dim == 2 ? 2 : 4;
    const char **shapes = c->dim == 2 ? shapes2 : shapes3;
    int found = -1;
    for (int i = 0; i < nshapes; i++) {
        if (json_object_get(v, shapes[i])) {
            if (found >= 0) {
                snprintf(p, sizeof p, "%s.%s", path, shapes[i]);
                return cn_ld_fail(c, p, "there is already a shape ('%s'); give exactly one",
                                  shapes[found]);
            }
            found = i;
        }
    }
    if (found < 0)
        return cn_ld_fail(c, path, "'%s' has no shape; give one of %s", part->name,
                          c->dim == 2 ? "polygon, polygons" : "box, hull, hulls, mesh");
    snprintf(p, sizeof p, "%s.%s", path, shapes[found]);
    json_t *shape = json_object_get(v, shapes[found]);
    json_t *scale = json_object_get(v, "scale");
    if (scale && !(c->dim == 3 && found == 3)) {
        snprintf(p, sizeof p, "%s.scale", path);
        return cn_ld_fail(c, p, "'scale' applies to a mesh only; scale the coordinates themselves");
    }
    cnStatus s;
    if (c->dim == 3 && found == 3) {
        double sc = 1;
        if (scale) {
            char ps[PATH_MAX_LEN];
            snprintf(ps, sizeof ps, "%s.scale", path);
            if ((s = cn_ld_get_positive(c, scale, ps, &sc))) return s;
            if (!(sc >= CN_MIN_PART_SIZE && sc <= CN_MAX_PART_SIZE))
                return cn_ld_fail(c, ps, "%g is outside the %g to %g cairn takes for a mesh's scale (beyond, its "
                                  "coordinates would overflow or underflow)", sc, CN_MIN_PART_SIZE, CN_MAX_PART_SIZE);
        }
        if ((s = make_mesh(c, shape, p, sc, part))) return s;
        for (int i = 0; i < part->npieces; i++) cn_piece_bounds(&part->pieces[i], c->dim);
        return CN_OK;
    }
    if (c->dim == 2) s = make_pieces(c, shape, p, found == 1, 0, part);
    else s = make_pieces(c, shape, p, found == 2, found == 0 ? 2 : 1, part);
    if (s) return s;
    for (int i = 0; i < part->npieces; i++) cn_piece_bounds(&part->pieces[i], c->dim);
    return CN_OK;
}

/* A pose's angle in radians: whole turns taken off in degrees first (exactly: fmod), so that an
 * angle of 1e19 turns is no turn rather than the rounding of its product with pi / 180. */
static double pose_radians(double deg) { return fmod(deg, 360.0) * CN_PI / 180.0; }

/* A part's pose: "rotation" (2-D: degrees, counter-clockwise; 3-D: {"axis": [x, y, z],
 * "angle": degrees} or {"quaternion": [w, x, y, z]}) about the origin of the coordinates its
 * shape is given in, then "position" (added). *posed: either was given. */
cnStatus cn_ld_get_pose(Ctx *c, const json_t *v, const char *path, cnPose *out, bool *posed) {
    char p[PATH_MAX_LEN];
    *out = cn_pose_identity();
    json_t *rot = json_object_get(v, "rotation"), *pos = json_object_get(v, "position");
    *posed = rot || pos;
    cnStatus s;
    if (rot) {
        snprintf(p, sizeof p, "%s.rotation", path);
        const double origin[3] = {0, 0, 0};
        if (c->dim == 2) {
            double deg;
            if (!json_is_number(rot))
                return cn_ld_fail(c, p, "expected an angle in degrees (counter-clockwise), found %s", cn_ld_type_name(rot));
            if ((s = cn_ld_get_number(c, rot, p, &deg))) return s;
            *out = cn_pose_rotation((const double[3]){0, 0, 1}, pose_radians(deg), origin);
        } else {
            static const char *const keys[] = {"axis", "angle", "quaternion", NULL};
            if (!json_is_object(rot))
                return cn_ld_fail(c, p, "expected {\"axis\": [x, y, z], \"angle\": degrees} or "
                                  "{\"quaternion\": [w, x, y, z]}, found %s", cn_ld_type_name(rot));
            if ((s = cn_ld_check_keys(c, rot, p, keys))) return s;
            json_t *axis = json_object_get(rot, "axis"), *ang = json_object_get(rot, "angle"),
                   *quat = json_object_get(rot, "quaternion");
            if (quat && (axis || ang))
                return cn_ld_fail(c, p, "give either axis and angle or a quaternion, not both");
            if (quat) {
                snprintf(p, sizeof p, "%s.rotation.quaternion", path);
                double q[4], n = 0;
                if (!json_is_array(quat) || json_array_size(quat) != 4)
                    return cn_ld_fail(c, p, "expected [w, x, y, z]: 4 numbers, found %s%s", cn_ld_type_name(quat),
                                      json_is_array(quat) ? " of another length" : "");
                for (int k = 0; k < 4; k++) {
                    char pk[PATH_MAX_LEN];
                    snprintf(pk, sizeof pk, "%s[%d]", p, k);
                    if ((s = cn_ld_get_number(c, json_array_get(quat, (size_t)k), pk, &q[k]))) return s;
                }
                for (int k = 0; k < 4; k++) n = hypot(n, q[k]);
                if (!isfinite(n))
                    return cn_ld_fail(c, p, "not a unit quaternion (its length overflows); normalize it");
                if (!(n > 1e-6))
                    return cn_ld_fail(c, p, "a rotation quaternion must not be zero; the identity is [1, 0, 0, 0]");
                /* a quaternion written to four or five digits ([0.7071, 0, 0, 0.7071]) is off by
                 * about 1e-5: taken, normalised; one further off is a mistake, not rounding */
                if (fabs(n - 1) > CN_QUATERNION_UNIT_TOL)
                    return cn_ld_fail(c, p, "not a unit quaternion (its length is %.9g); normalize it", n);
                for (int k = 0; k < 4; k++) out->q[k] = q[k] / n;
            } else {
                double ax[3], deg;
                snprintf(p, sizeof p, "%s.rotation.axis", path);
                if (!axis) return cn_ld_fail(c, p, "missing; give the axis of the rotation, e.g. [0, 0, 1]");
                if ((s = cn_ld_get_point(c, axis, p, 3, ax))) return s;
                /* a direction: scaled by its largest component first, so that [1e-300, 0, 0]
                   is the x axis, not a length that underflows to zero */
                double big = fmax(fabs(ax[0]), fmax(fabs(ax[1]), fabs(ax[2])));
                if (!(big > 0)) return cn_ld_fail(c, p, "the axis is zero; give its direction, e.g. [0, 0, 1]");
                for (int k = 0; k < 3; k++) ax[k] /= big;
                snprintf(p, sizeof p, "%s.rotation.angle", path);
                if (!ang) return cn_ld_fail(c, p, "missing; give the angle in degrees (right-hand rule about the axis)");
                if ((s = cn_ld_get_number(c, ang, p, &deg))) return s;
                *out = cn_pose_rotation(ax, pose_radians(deg), origin);
            }
        }
    }
    if (pos) {
        double t[3] = {0, 0, 0};
        snprintf(p, sizeof p, "%s.position", path);
        if ((s = cn_ld_get_place(c, pos, p, c->dim, t))) return s;
        for (int k = 0; k < 3; k++) out->t[k] += t[k];
    }
    return CN_OK;
}
