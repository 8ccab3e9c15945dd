/* Loading an assembly from JSON (jansson). Everything is validated here, once: unknown keys,
 * types, finite numbers, convexity, orientation, names, overlaps. Every message names its JSON
 * path (or line:column for syntax) and says what to do. */
/* realpath (XSI) */
#define _XOPEN_SOURCE 700
#include <errno.h>
#include <jansson.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <limits.h>
#include <stdlib.h>
#include <sys/stat.h>

#include "collide.h"
#include "io.h"
#include "pieces.h"

/* How far from 1 the length of a rotation quaternion may be (it is then normalised). */
#define CN_QUATERNION_UNIT_TOL 1e-3

typedef struct {
    cnDiag *diag;
    int dim;
    double rel_tol;        /* the assembly's relative tolerance (meshes are welded within it) */
    const char *mesh_dir;  /* mesh paths are relative to this directory */
    bool mesh_anywhere;    /* and may lead outside it */
    json_t *names;         /* while the parts load: each name so far, with its part's index */
} Ctx;

#define PATH_MAX_LEN 256

static cnStatus fail(Ctx *c, const char *path, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static cnStatus fail(Ctx *c, const char *path, const char *fmt, ...) {
    char msg[900];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return cn_diag_set(c->diag, CN_ERR_INPUT, path, "%s", msg);
}

/* "no part is named 'Q'; the parts are: T, A" (the first 12 names, then how many more). */
/* Names are printed in one-line messages, tables and figures: no control characters, C0
 * (bytes 0..31, 127) nor C1 (U+0080..U+009F, UTF-8 0xC2 0x80..0x9F: some terminals act on them). */
int cn_control_char(const char *text, int *at) {
    for (const unsigned char *q = (const unsigned char *)text; *q; q++) {
        int code = *q < 32 || *q == 127 ? *q : (*q == 0xC2 && q[1] >= 0x80 && q[1] <= 0x9F) ? q[1] : -1;
        if (code >= 0) {
            *at = (int)(q - (const unsigned char *)text);
            return code;
        }
    }
    return -1;
}

static cnStatus printable(Ctx *c, const char *text, const char *path) {
    int at, code = cn_control_char(text, &at);
    if (code >= 0)
        return fail(c, path, "the name contains a control character (code %d at byte %d); use "
                    "printable characters", code, at);
    return CN_OK;
}

/* A reference to a part that does not exist: said with the names there are (every defined name
 * is printable, so a reference with a control character is refused as such first). */
static cnStatus no_such_part(Ctx *c, const char *path, const char *name, const cnAssembly *a) {
    cnStatus st = printable(c, name, path);
    if (st) return st;
    char list[400];
    size_t len = 0;
    int n = a->nreal > 0 ? a->nreal : a->nparts, shown = n < 12 ? n : 12;
    list[0] = 0;
    for (int i = 0; i < shown && len < sizeof list; i++)
        len += (size_t)snprintf(list + len, sizeof list - len, "%s%s", i ? ", " : "",
                                a->parts[i].name);
    if (n > shown && len < sizeof list)
        snprintf(list + len, sizeof list - len, " and %d more", n - shown);
    return fail(c, path, "no part is named '%s'; the parts are: %s", name, list);
}

static const char *type_name(const json_t *v) {
    switch (json_typeof(v)) {
    case JSON_OBJECT: return "an object";
    case JSON_ARRAY: return "an array";
    case JSON_STRING: return "a string";
    case JSON_INTEGER:
    case JSON_REAL: return "a number";
    case JSON_TRUE:
    case JSON_FALSE: return "a boolean";
    case JSON_NULL: return "null";
    }
    return "a value";
}

/* Reject keys not in `allowed` (NULL-terminated), listing the allowed ones. */
static cnStatus check_keys(Ctx *c, const json_t *obj, const char *path,
                           const char *const *allowed) {
    const char *key;
    json_t *val;
    json_object_foreach((json_t *)obj, key, val) {
        int ok = 0;
        for (int i = 0; allowed[i]; i++)
            if (!strcmp(key, allowed[i])) ok = 1;
        if (!ok) {
            char list[400] = "";
            for (int i = 0; allowed[i]; i++) {
                strncat(list, i ? ", " : "", sizeof list - strlen(list) - 1);
                strncat(list, allowed[i], sizeof list - strlen(list) - 1);
            }
            char p[PATH_MAX_LEN];
            if (path[0]) snprintf(p, sizeof p, "%s.%s", path, key);
            else snprintf(p, sizeof p, "%s", key);
            return fail(c, p, "unknown key '%s'; the keys allowed here are: %s", key, list);
        }
    }
    return CN_OK;
}

static cnStatus get_number(Ctx *c, const json_t *v, const char *path, double *out) {
    if (!json_is_number(v))
        return fail(c, path, "expected a number, found %s", type_name(v));
    double x = json_number_value(v);
    if (!isfinite(x)) return fail(c, path, "the number is not finite");
    *out = x;
    return CN_OK;
}

static cnStatus get_positive(Ctx *c, const json_t *v, const char *path, double *out) {
    cnStatus s = get_number(c, v, path, out);
    if (s) return s;
    if (!(*out > 0)) return fail(c, path, "must be greater than zero, got %g", *out);
    return CN_OK;
}

/* A point of `dim` numbers. */

/* The size of gravity cairn computes with (a verdict depends on its direction only). */
#define CN_GRAVITY_MIN 1e-100
#define CN_GRAVITY_MAX 1e100

static cnStatus get_point(Ctx *c, const json_t *v, const char *path, int dim, double out[3]) {
    if (!json_is_array(v) || (int)json_array_size(v) != dim)
        return fail(c, path, "expected a point: an array of %d numbers, found %s%s", dim,
                    type_name(v), json_is_array(v) ? " of another length" : "");
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k < dim; k++) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "%s[%d]", path, k);
        cnStatus s = get_number(c, json_array_get(v, (size_t)k), p, &out[k]);
        if (s) return s;
    }
    return CN_OK;
}

/* A place's coordinates (at most CN_MAX_COORD in magnitude); directions and displacements are
 * read by get_point. */
static cnStatus get_place(Ctx *c, const json_t *v, const char *path, int dim, double out[3]) {
    cnStatus s = get_point(c, v, path, dim, out);
    for (int k = 0; !s && k < dim; k++)
        if (fabs(out[k]) > CN_MAX_COORD) {
            char p[PATH_MAX_LEN];
            snprintf(p, sizeof p, "%s[%d]", path, k);
            return fail(c, p, "%g is beyond the coordinates cairn computes with (magnitude up to %g: a part "
                        "up to %g across, up to %g times that from the origin); scale the file, e.g. to metres",
                        out[k], CN_MAX_COORD, CN_MAX_PART_SIZE, CN_MAX_FAR_RATIO);
        }
    return s;
}

/* Points array with at least `min` entries. Caller frees *pts. */
static cnStatus get_points(Ctx *c, const json_t *v, const char *path, int dim, int min,
                           const char *what, double (**pts)[3], int *n);

/* A turn: {"rotate": degrees, "about": point, "axis": direction (3-D only)}. */
static cnStatus get_turn(Ctx *c, const json_t *v, const char *path, int dim, cnSegment *out) {
    static const char *const keys2[] = {"rotate", "about", NULL};
    static const char *const keys3[] = {"rotate", "axis", "about", NULL};
    char p[PATH_MAX_LEN];
    if (dim == 2 && json_object_get(v, "axis")) {
        snprintf(p, sizeof p, "%s.axis", path);
        return fail(c, p, "a 2-D turn is about z (counter-clockwise positive); remove axis");
    }
    cnStatus s = check_keys(c, v, path, dim == 2 ? keys2 : keys3);
    if (s) return s;
    out->kind = CN_SEGMENT_TURN;
    snprintf(p, sizeof p, "%s.rotate", path);
    json_t *e = json_object_get(v, "rotate");
    double deg;
    if (!e) return fail(c, p, "missing; give the angle in degrees (counter-clockwise positive%s)",
                        dim == 3 ? ", right-hand rule about axis" : "");
    if ((s = get_number(c, e, p, &deg))) return s;
    if (deg == 0) return fail(c, p, "a rotation of zero degrees; remove it");
    if (fabs(deg) > 360)
        return fail(c, p, "at most one full turn (360 degrees) per segment, got %g; split it", deg);
    out->angle = deg * CN_PI / 180.0;
    snprintf(p, sizeof p, "%s.about", path);
    e = json_object_get(v, "about");
    if (!e) return fail(c, p, "missing; give the point the parts turn about, e.g. [0, 0%s]",
                        dim == 3 ? ", 0" : "");
    if ((s = get_point(c, e, p, dim, out->about))) return s;
    out->axis[0] = out->axis[1] = 0, out->axis[2] = 1;
    if (dim == 3) {
        snprintf(p, sizeof p, "%s.axis", path);
        e = json_object_get(v, "axis");
        if (!e) return fail(c, p, "missing; give the direction of the axis of the turn, e.g. [0, 0, 1]");
        if ((s = get_point(c, e, p, 3, out->axis))) return s;
        double n = cn_norm3(out->axis);
        if (!(n > 0) || !isfinite(n)) {
            /* rescale first: a valid direction written with huge components */
            double big = fmax(fabs(out->axis[0]), fmax(fabs(out->axis[1]), fabs(out->axis[2])));
            if (big > 0 && isfinite(big)) {
                cn_scale3(out->axis, 1.0 / big);
                n = cn_norm3(out->axis);
            }
        }
        if (!(n > 0)) return fail(c, p, "the axis has zero length; give its direction, e.g. [0, 0, 1]");
        cn_scale3(out->axis, 1.0 / n);
    }
    return CN_OK;
}

/* A path: 1 .. CN_MAX_PATH_SEGMENTS segments, each a displacement (an array of dim numbers) or
 * a turn (an object). */
static cnStatus get_path(Ctx *c, const json_t *v, const char *path, int dim, cnSegment **segs,
                         int *n) {
    *segs = NULL;
    if (json_is_array(v) && json_array_size(v) > CN_MAX_PATH_SEGMENTS)
        return fail(c, path, "a path has at most %d segments, found %zu; merge collinear ones",
                    CN_MAX_PATH_SEGMENTS, json_array_size(v));
    if (!json_is_array(v))
        return fail(c, path, "expected a path: an array of points, found %s", type_name(v));
    int m = (int)json_array_size(v);
    if (m < 1) return fail(c, path, "a path needs at least 1 points, found 0");
    cnSegment *out = cn_calloc((size_t)m, sizeof(cnSegment));
    if (!out) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    for (int i = 0; i < m; i++) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "%s[%d]", path, i);
        const json_t *e = json_array_get(v, (size_t)i);
        cnStatus s = json_is_object(e) ? get_turn(c, e, p, dim, &out[i])
                                       : get_point(c, e, p, dim, out[i].move);
        if (s) {
            cn_free(out);
            return s;
        }
    }
    *segs = out;
    *n = m;
    return CN_OK;
}

/* Turns of a path that moves `parts`: each must move them (a turn by a few ulps of an angle, or
 * about a point on which every vertex sits, would be a segment of zero length: samples would
 * divide by it) and turn about a point near the assembly (beyond a million times its size a turn
 * is a translation to within rounding; give a move instead). `path` names the path. */
#define CN_TURN_MAX_REACH 1e6
static cnStatus check_turns(Ctx *c, const cnAssembly *a, const char *path, const int *parts,
                            int n, const cnSegment *seg, int nseg) {
    double *len = cn_malloc(sizeof(double) * (size_t)(nseg + 1));
    if (!len) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    double centre[3], d[3];
    for (int k = 0; k < 3; k++) centre[k] = 0.5 * (a->lo[k] + a->hi[k]);
    cnStatus s = CN_OK;
    char p[PATH_MAX_LEN];
    for (int i = 0; i < nseg && !s; i++) {
        if (seg[i].kind != CN_SEGMENT_TURN) continue;
        cn_sub3(seg[i].about, centre, d);
        double far = fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2]))) / a->length_scale;
        if (!(far <= CN_TURN_MAX_REACH)) {
            snprintf(p, sizeof p, "%s[%d].about", path, i);
            s = fail(c, p, "%.3g times the assembly's size away from it; a turn about so far a point "
                           "is a move to within rounding: give a displacement instead", far);
        }
    }
    if (!s) cn_path_length(a, parts, n, seg, nseg, len);
    for (int i = 0; i < nseg && !s; i++)
        if (seg[i].kind == CN_SEGMENT_TURN && !(len[i] > CN_TOL_LENGTH_ZERO * a->length_scale)) {
            snprintf(p, sizeof p, "%s[%d].rotate", path, i);
            s = fail(c, p, "the turn moves no point of the parts (%.3g degrees); remove it or turn further",
                     seg[i].angle * 180 / CN_PI);
        }
    cn_free(len);
    return s;
}

static cnStatus get_points(Ctx *c, const json_t *v, const char *path, int dim, int min,
                           const char *what, double (**pts)[3], int *n) {
    *pts = NULL;
    if (!json_is_array(v))
        return fail(c, path, "expected %s: an array of points, found %s", what, type_name(v));
    int m = (int)json_array_size(v);
    if (m < min)
        return fail(c, path, "%s needs at least %d points, found %d", what, min, m);
    *pts = cn_calloc((size_t)m, sizeof **pts);
    if (!*pts) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    for (int i = 0; i < m; i++) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "%s[%d]", path, i);
        cnStatus s = get_place(c, json_array_get(v, (size_t)i), p, dim, (*pts)[i]);
        if (s) {
            cn_free(*pts);
            *pts = NULL;
            return s;
        }
    }
    *n = m;
    return CN_OK;
}

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
    cnStatus s = get_points(c, v, path, 2, 3, "a polygon", &pts, &n);
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
            return fail(c, path,
                        "points %d and %d coincide; remove the repeated point", i, (i + 1) % n);
        }
    }
    if (!(fabs(area2) > CN_TOL_LENGTH_ZERO * size * size)) {
        cn_free(pts);
        return fail(c, path, "the polygon has no area: its points are collinear or it crosses itself");
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
            return fail(c, path,
                        "not convex at vertex %d (the boundary turns the other way there); a piece "
                        "of \"polygons\" must be convex: split it further, or give the whole part as "
                        "one \"polygon\" (a simple outline is split into convex pieces for you)",
                        i);
        }
        turning += atan2(sign * cr, e1x * e2x + e1y * e2y);
    }
    if (turning > 2 * CN_PI * 1.5) {
        cn_free(pts);
        return fail(c, path, "the polygon winds around more than once (it crosses itself)");
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
        return fail(c, path, "a non-convex polygon of %d points; at most %d are split into convex "
                    "pieces automatically: give it as \"polygons\" (convex pieces)", n, SPLIT_MAX_POINTS);
    }
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 2; k++) lo[k] = fmin(lo[k], pts[i][k]), hi[k] = fmax(hi[k], pts[i][k]);
    double tol = 1e-9 * hypot(hi[0] - lo[0], hi[1] - lo[1]);
    int e1, e2;
    if (!cn_polygon_simple((const double(*)[3])pts, n, tol, &e1, &e2)) {
        cn_free(pts);
        return fail(c, path, "not convex, and its edges %d-%d and %d-%d meet: a non-convex part must be a "
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
    if (rc > 0) s = fail(c, path, "not convex, and it could not be split into convex pieces (it nearly touches "
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
                s = fail(c, path, "not convex, and its split into convex pieces failed (piece %d); give convex "
                         "pieces with \"polygons\"", k);
        }
        if (!s && !(area2 > tol * tol))
            s = fail(c, path, "not convex, and its split into convex pieces failed (piece %d has no area); give "
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

static cnStatus get_support(Ctx *c, const json_t *e, const char *p, int *out);

static cnStatus make_hull(Ctx *c, const json_t *v, const char *path, cnPiece *out) {
    double(*pts)[3];
    int n;
    cnStatus s = get_points(c, v, path, 3, 4, "a hull", &pts, &n);
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
        return fail(c, path, "expected a box: {\"min\": [x, y, z], \"max\": [x, y, z]}, found %s",
                    type_name(v));
    static const char *const keys[] = {"min", "max", NULL};
    cnStatus s = check_keys(c, v, path, keys);
    if (s) return s;
    double lo[3], hi[3];
    char p[PATH_MAX_LEN];
    for (int w = 0; w < 2; w++) {
        const char *k = w ? "max" : "min";
        snprintf(p, sizeof p, "%s.%s", path, k);
        json_t *e = json_object_get(v, k);
        if (!e) return fail(c, p, "missing; a box needs \"min\" and \"max\" corners");
        s = get_place(c, e, p, 3, w ? hi : lo);
        if (s) return s;
    }
    for (int k = 0; k < 3; k++)
        if (!(hi[k] > lo[k])) {
            snprintf(p, sizeof p, "%s.max[%d]", path, k);
            return fail(c, p, "must be greater than min[%d] (%g); a box needs volume", k, lo[k]);
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
        return fail(c, path, "expected a non-empty array of convex pieces, found %s",
                    json_is_array(v) ? "an empty array" : type_name(v));
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
        return fail(c, path, "expected the path of a mesh file (OBJ, STL, PLY, OFF), found %s",
                    type_name(v));
    const char *rel = json_string_value(v);
    if (!rel[0]) return fail(c, path, "the path is empty; give the mesh file's path");
    const char *dir = c->mesh_dir ? c->mesh_dir : ".";
    if (rel[0] == '/') snprintf(out, n, "%s", rel);
    else if ((size_t)snprintf(out, n, "%s/%s", dir, rel) >= n)
        return fail(c, path, "the path is too long");
    char *real = realpath(out, NULL);
    if (!real)
        return fail(c, path, "cannot open the mesh file '%s'%s: %s", rel,
                    rel[0] == '/' ? "" : " (relative to the assembly file's directory)", strerror(errno));
    struct stat st;
    if (stat(real, &st) != 0 || !S_ISREG(st.st_mode)) {
        free(real);
        return fail(c, path, "'%s' is not a file; give a mesh file", rel);
    }
    if (!c->mesh_anywhere) {
        char *base = realpath(dir, NULL);
        size_t bl = base ? strlen(base) : 0;
        bool inside = base && !strncmp(real, base, bl) && (real[bl] == '/' || !strcmp(base, "/"));
        free(base);
        if (!inside) {
            free(real);
            return fail(c, path, "'%s' is outside the assembly file's directory; move it "
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
        if (s == CN_ERR_INPUT) {
            char msg[sizeof c->diag->message];
            snprintf(msg, sizeof msg, "%s", c->diag->message);
            return fail(c, path, "%s %s", what, msg);
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
        if (s == CN_ERR_INPUT) return fail(c, path, "%s is flat: its points are coplanar", what);
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
                return fail(c, path, "%s intersects itself: faces %d and %d cross; fix the mesh",
                            what, m->face_id[f1], m->face_id[f2]);
            return fail(c, path, "%s is not convex, and %s", what, cn_mesh_split_why(r));
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
                return fail(c, path, "%s: convex piece %d of its decomposition is flat", what, i);
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
        if (s == CN_ERR_INPUT) {
            char msg[sizeof c->diag->message];
            snprintf(msg, sizeof msg, "%s", c->diag->message);
            return fail(c, path, "%s", msg);
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
static cnStatus load_shape(Ctx *c, const json_t *v, const char *path, cnPart *part) {
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
                return fail(c, p, "there is already a shape ('%s'); give exactly one",
                            shapes[found]);
            }
            found = i;
        }
    }
    if (found < 0)
        return fail(c, path, "'%s' has no shape; give one of %s", part->name,
                    c->dim == 2 ? "polygon, polygons" : "box, hull, hulls, mesh");
    snprintf(p, sizeof p, "%s.%s", path, shapes[found]);
    json_t *shape = json_object_get(v, shapes[found]);
    json_t *scale = json_object_get(v, "scale");
    if (scale && !(c->dim == 3 && found == 3)) {
        snprintf(p, sizeof p, "%s.scale", path);
        return fail(c, p, "'scale' applies to a mesh only; scale the coordinates themselves");
    }
    cnStatus s;
    if (c->dim == 3 && found == 3) {
        double sc = 1;
        if (scale) {
            char ps[PATH_MAX_LEN];
            snprintf(ps, sizeof ps, "%s.scale", path);
            if ((s = get_positive(c, scale, ps, &sc))) return s;
            if (!(sc >= CN_MIN_PART_SIZE && sc <= CN_MAX_PART_SIZE))
                return fail(c, ps, "%g is outside the %g to %g cairn takes for a mesh's scale (beyond, its "
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
static cnStatus get_pose(Ctx *c, const json_t *v, const char *path, cnPose *out, bool *posed) {
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
                return fail(c, p, "expected an angle in degrees (counter-clockwise), found %s", type_name(rot));
            if ((s = get_number(c, rot, p, &deg))) return s;
            *out = cn_pose_rotation((const double[3]){0, 0, 1}, pose_radians(deg), origin);
        } else {
            static const char *const keys[] = {"axis", "angle", "quaternion", NULL};
            if (!json_is_object(rot))
                return fail(c, p, "expected {\"axis\": [x, y, z], \"angle\": degrees} or "
                            "{\"quaternion\": [w, x, y, z]}, found %s", type_name(rot));
            if ((s = check_keys(c, rot, p, keys))) return s;
            json_t *axis = json_object_get(rot, "axis"), *ang = json_object_get(rot, "angle"),
                   *quat = json_object_get(rot, "quaternion");
            if (quat && (axis || ang))
                return fail(c, p, "give either axis and angle or a quaternion, not both");
            if (quat) {
                snprintf(p, sizeof p, "%s.rotation.quaternion", path);
                double q[4], n = 0;
                if (!json_is_array(quat) || json_array_size(quat) != 4)
                    return fail(c, p, "expected [w, x, y, z]: 4 numbers, found %s%s", type_name(quat),
                                json_is_array(quat) ? " of another length" : "");
                for (int k = 0; k < 4; k++) {
                    char pk[PATH_MAX_LEN];
                    snprintf(pk, sizeof pk, "%s[%d]", p, k);
                    if ((s = get_number(c, json_array_get(quat, (size_t)k), pk, &q[k]))) return s;
                }
                for (int k = 0; k < 4; k++) n = hypot(n, q[k]);
                if (!isfinite(n))
                    return fail(c, p, "not a unit quaternion (its length overflows); normalize it");
                if (!(n > 1e-6))
                    return fail(c, p, "a rotation quaternion must not be zero; the identity is [1, 0, 0, 0]");
                /* a quaternion written to four or five digits ([0.7071, 0, 0, 0.7071]) is off by
                 * about 1e-5: taken, normalised; one further off is a mistake, not rounding */
                if (fabs(n - 1) > CN_QUATERNION_UNIT_TOL)
                    return fail(c, p, "not a unit quaternion (its length is %.9g); normalize it", n);
                for (int k = 0; k < 4; k++) out->q[k] = q[k] / n;
            } else {
                double ax[3], deg;
                snprintf(p, sizeof p, "%s.rotation.axis", path);
                if (!axis) return fail(c, p, "missing; give the axis of the rotation, e.g. [0, 0, 1]");
                if ((s = get_point(c, axis, p, 3, ax))) return s;
                /* a direction: scaled by its largest component first, so that [1e-300, 0, 0]
                   is the x axis, not a length that underflows to zero */
                double big = fmax(fabs(ax[0]), fmax(fabs(ax[1]), fabs(ax[2])));
                if (!(big > 0)) return fail(c, p, "the axis is zero; give its direction, e.g. [0, 0, 1]");
                for (int k = 0; k < 3; k++) ax[k] /= big;
                snprintf(p, sizeof p, "%s.rotation.angle", path);
                if (!ang) return fail(c, p, "missing; give the angle in degrees (right-hand rule about the axis)");
                if ((s = get_number(c, ang, p, &deg))) return s;
                *out = cn_pose_rotation(ax, pose_radians(deg), origin);
            }
        }
    }
    if (pos) {
        double t[3] = {0, 0, 0};
        snprintf(p, sizeof p, "%s.position", path);
        if ((s = get_place(c, pos, p, c->dim, t))) return s;
        for (int k = 0; k < 3; k++) out->t[k] += t[k];
    }
    return CN_OK;
}

/* How many vertex numbers a part uses: its outline's points when it was split from one, else
 * its pieces' vertices. */
static int numbers_of(const cnPart *p) {
    if (p->noutline > 0) return p->noutline;
    int n = 0;
    for (int k = 0; k < p->npieces; k++) n += p->pieces[k].nverts;
    return n;
}

static cnStatus load_part(Ctx *c, const json_t *v, int index, cnAssembly *a, double defdensity) {
    char path[PATH_MAX_LEN], p[PATH_MAX_LEN];
    snprintf(path, sizeof path, "parts[%d]", index);
    if (!json_is_object(v))
        return fail(c, path, "expected a part object {\"name\": ..., shape}, found %s",
                    type_name(v));
    static const char *const keys2[] = {"name", "fixed", "polygon", "polygons", "density",
                                        "mass", "position", "rotation", NULL};
    static const char *const keys3[] = {"name", "fixed", "box", "hull", "hulls", "mesh", "scale",
                                        "density", "mass", "position", "rotation", NULL};
    /* A shape key of the other dimension gets a specific message. */
    static const char *const other2[] = {"box", "hull", "hulls", "mesh", NULL};
    static const char *const other3[] = {"polygon", "polygons", NULL};
    const char *const *other = c->dim == 2 ? other2 : other3;
    for (int i = 0; other[i]; i++)
        if (json_object_get(v, other[i])) {
            snprintf(p, sizeof p, "%s.%s", path, other[i]);
            return fail(c, p, "'%s' is a %d-D shape but the assembly has dimension %d; use %s",
                        other[i], c->dim == 2 ? 3 : 2, c->dim,
                        c->dim == 2 ? "polygon or polygons" : "box, hull, hulls or mesh");
        }
    cnStatus s = check_keys(c, v, path, c->dim == 2 ? keys2 : keys3);
    if (s) return s;
    cnPart *part = &a->parts[index];
    part->gripper_step = -1;

    json_t *name = json_object_get(v, "name");
    snprintf(p, sizeof p, "%s.name", path);
    if (!name) return fail(c, p, "missing; every part needs a unique name");
    if (!json_is_string(name)) return fail(c, p, "expected a string, found %s", type_name(name));
    if (json_string_length(name) == 0) return fail(c, p, "the name is empty; give the part a name");
    if ((s = printable(c, json_string_value(name), p))) return s;
    /* (a NUL inside a name cannot get here: the JSON reader rejects \u0000) */
    json_t *seen = json_object_get(c->names, json_string_value(name));
    if (seen)
        return fail(c, p, "'%s' is already the name of parts[%d]; names must be unique",
                    json_string_value(name), (int)json_integer_value(seen));
    part->name = cn_strdup(json_string_value(name));
    if (!part->name || json_object_set_new(c->names, part->name, json_integer(index)) != 0)
        return cn_diag_set(c->diag, CN_ERR_MEMORY, p, "out of memory");

    json_t *fixed = json_object_get(v, "fixed");
    if (fixed) {
        snprintf(p, sizeof p, "%s.fixed", path);
        if (!json_is_boolean(fixed))
            return fail(c, p, "expected true or false, found %s", type_name(fixed));
        part->fixed = json_is_true(fixed);
    }

    s = load_shape(c, v, path, part);
    if (s) return s;
    cnPose pose;
    bool posed;
    if ((s = get_pose(c, v, path, &pose, &posed))) return s;
    for (int i = 0; i < part->npieces; i++) {
        if (posed) cn_piece_transform(&part->pieces[i], c->dim, &pose);
        cn_piece_bounds(&part->pieces[i], c->dim);
    }
    for (int i = 0; posed && i < part->noutline; i++) {
        cn_pose_apply(&pose, part->outline[i], part->outline[i]);
        part->outline[i][2] = 0;
    }
    if (part->npieces > 1) { /* pieces may touch, not overlap: the overlap would weigh twice */
        int pi, pj;
        double depth = cn_part_self_overlap(part, c->dim, a->rel_tol, &pi, &pj);
        if (depth < 0) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
        if (depth > 0) {
            if (part->mesh_file)
                return fail(c, path, "pieces %d and %d of the mesh '%s' (its objects, or the pieces "
                            "of its split, in order) overlap by %.3g: the common region would count "
                            "twice in the part's mass; make its objects only touch", pi, pj,
                            part->mesh_file, depth);
            snprintf(p, sizeof p, "%s.%s[%d]", path, c->dim == 2 ? "polygons" : "hulls", pj);
            return fail(c, p, "overlaps piece %d of the same part by %.3g: the common region would "
                        "count twice in the part's mass; split the part into pieces that only touch",
                        pi, depth);
        }
    }

    double density = defdensity, mass = 0;
    json_t *d = json_object_get(v, "density"), *m = json_object_get(v, "mass");
    if (d && m)
        return fail(c, path, "give either \"density\" or \"mass\" for part '%s', not both",
                    part->name);
    if (d) {
        snprintf(p, sizeof p, "%s.density", path);
        s = get_positive(c, d, p, &density);
        if (s) return s;
    }
    if (m) {
        snprintf(p, sizeof p, "%s.mass", path);
        s = get_positive(c, m, p, &mass);
        if (s) return s;
    }
    cn_mass_part(part, c->dim, density, mass);
    if (!(part->size > 0) || !isfinite(part->mass) || !(part->mass > 0))
        return fail(c, path,
                    "part '%s' has no %s or its mass is not finite; check its density or mass "
                    "and the units of its coordinates",
                    part->name, c->dim == 2 ? "area" : "volume");
    double g = hypot(hypot(a->gravity[0], a->gravity[1]), a->gravity[2]);
    if (!isfinite(part->mass * g))
        return fail(c, path,
                    "part '%s' weighs more than a double holds (mass %g times gravity %g); scale "
                    "the masses or densities down (only their ratios change a verdict)",
                    part->name, part->mass, g);
    return CN_OK;
}

static cnStatus load_fixel(Ctx *c, const json_t *v, int index, cnAssembly *a) {
    char path[PATH_MAX_LEN], p[PATH_MAX_LEN];
    snprintf(path, sizeof path, "fixels[%d]", index);
    if (!json_is_object(v))
        return fail(c, path, "expected {\"part\": name, \"point\": [...], \"normal\": [...]}, "
                             "found %s",
                    type_name(v));
    static const char *const keys[] = {"part", "point", "normal", NULL};
    cnStatus s = check_keys(c, v, path, keys);
    if (s) return s;
    cnFixel *f = &a->fixels[index];
    json_t *part = json_object_get(v, "part");
    snprintf(p, sizeof p, "%s.part", path);
    if (!part) return fail(c, p, "missing; name the part the fixel holds");
    if (!json_is_string(part)) return fail(c, p, "expected a part name, found %s", type_name(part));
    f->part = cn_assembly_find_part(a, json_string_value(part));
    if (f->part < 0) return no_such_part(c, p, json_string_value(part), a);
    if (a->parts[f->part].fixed)
        return fail(c, p, "part '%s' is fixed; a fixel on a fixed part does nothing — remove it",
                    json_string_value(part));
    const char *names[2] = {"point", "normal"};
    double *dst[2] = {f->point, f->normal};
    for (int k = 0; k < 2; k++) {
        snprintf(p, sizeof p, "%s.%s", path, names[k]);
        json_t *e = json_object_get(v, names[k]);
        if (!e) return fail(c, p, "missing; a fixel needs a point and a normal");
        s = k == 0 ? get_place(c, e, p, a->dim, dst[k]) : get_point(c, e, p, a->dim, dst[k]);
        if (s) return s;
    }
    snprintf(p, sizeof p, "%s.normal", path);
    if (!(cn_normalize3(f->normal) > 0)) return fail(c, p, "the normal must not be zero");
    /* The point must be on the part's surface and the normal must push into the part. */
    const cnPart *pt = &a->parts[f->part];
    double psize = hypot(hypot(pt->hi[0] - pt->lo[0], pt->hi[1] - pt->lo[1]), pt->hi[2] - pt->lo[2]);
    double tol = fmax(a->contact_tol, 1e-9 * psize);
    double dmin = INFINITY, din = INFINITY, dout = INFINITY;
    double eps = 1e-3 * psize;
    double pin[3], pout[3];
    for (int k = 0; k < 3; k++) pin[k] = f->point[k] + eps * f->normal[k];
    for (int k = 0; k < 3; k++) pout[k] = f->point[k] - eps * f->normal[k];
    for (int i = 0; i < pt->npieces; i++) {
        dmin = fmin(dmin, cn_piece_plane_distance(&pt->pieces[i], a->dim, f->point));
        din = fmin(din, cn_piece_plane_distance(&pt->pieces[i], a->dim, pin));
        dout = fmin(dout, cn_piece_plane_distance(&pt->pieces[i], a->dim, pout));
    }
    snprintf(p, sizeof p, "%s.point", path);
    if (dmin > tol)
        return fail(c, p, "the point is %g away from part '%s'; a fixel must touch the part's "
                          "surface",
                    dmin, pt->name);
    if (dmin < -tol)
        return fail(c, p, "the point is %g inside part '%s'; a fixel must touch the part's "
                          "surface",
                    -dmin, pt->name);
    snprintf(p, sizeof p, "%s.normal", path);
    if (din > tol && dout > tol) /* both probes outside: the normal runs along the surface */
        return fail(c, p, "the normal must point into part '%s' (the direction the fixel pushes "
                          "it); it runs along the surface there",
                    pt->name);
    if (din <= tol && dout <= tol) { /* both probes in the part: between two of its pieces */
        snprintf(p, sizeof p, "%s.point", path);
        return fail(c, p, "the point is inside part '%s' (where two of its pieces meet), not on its "
                          "surface; a fixel must touch the part's surface",
                    pt->name);
    }
    if (din > tol || dout < -tol)
        return fail(c, p, "the normal must point into part '%s' (the direction the fixel pushes "
                          "it); flip its sign",
                    pt->name);
    return CN_OK;
}

static cnStatus load_pair(Ctx *c, const json_t *v, int index, cnAssembly *a) {
    char path[PATH_MAX_LEN], p[PATH_MAX_LEN];
    snprintf(path, sizeof path, "friction_pairs[%d]", index);
    if (!json_is_object(v))
        return fail(c, path, "expected {\"parts\": [name, name], \"mu\": number}, found %s",
                    type_name(v));
    static const char *const keys[] = {"parts", "mu", NULL};
    cnStatus s = check_keys(c, v, path, keys);
    if (s) return s;
    cnFrictionPair *fp = &a->pairs[index];
    json_t *parts = json_object_get(v, "parts");
    snprintf(p, sizeof p, "%s.parts", path);
    if (!parts) return fail(c, p, "missing; name the two parts");
    if (!json_is_array(parts) || json_array_size(parts) != 2)
        return fail(c, p, "expected an array of two part names");
    int idx[2];
    for (int k = 0; k < 2; k++) {
        json_t *e = json_array_get(parts, (size_t)k);
        snprintf(p, sizeof p, "%s.parts[%d]", path, k);
        if (!json_is_string(e)) return fail(c, p, "expected a part name, found %s", type_name(e));
        idx[k] = cn_assembly_find_part(a, json_string_value(e));
        if (idx[k] < 0) return no_such_part(c, p, json_string_value(e), a);
    }
    if (idx[0] == idx[1]) return fail(c, p, "the two parts must differ");
    fp->a = idx[0] < idx[1] ? idx[0] : idx[1];
    fp->b = idx[0] < idx[1] ? idx[1] : idx[0];
    for (int j = 0; j < index; j++)
        if (a->pairs[j].a == fp->a && a->pairs[j].b == fp->b) {
            snprintf(p, sizeof p, "%s.parts", path);
            return fail(c, p, "this pair already has a coefficient in friction_pairs[%d]", j);
        }
    json_t *mu = json_object_get(v, "mu");
    snprintf(p, sizeof p, "%s.mu", path);
    if (!mu) return fail(c, p, "missing; give the friction coefficient");
    s = get_number(c, mu, p, &fp->mu);
    if (s) return s;
    if (fp->mu < 0) return fail(c, p, "must be zero or positive, got %g", fp->mu);
    return CN_OK;
}


/* A part name or an array of names of parts that can move (not fixed, not already removed by an
 * earlier step), without repeats. `allowed` (may be NULL) restricts the names further. */
static cnStatus get_part_list(Ctx *c, const json_t *v, const char *path, const cnAssembly *a,
                              const int *removed_by, int step, const int *allowed, int nallowed,
                              int **out, int *n) {
    char p[PATH_MAX_LEN];
    *out = NULL;
    *n = 0;
    int m = json_is_string(v) ? 1 : json_is_array(v) ? (int)json_array_size(v) : -1;
    if (m < 0) return fail(c, path, "expected a part name or an array of names, found %s", type_name(v));
    if (m == 0) return fail(c, path, "the list is empty; name at least one part");
    *out = cn_malloc(sizeof(int) * (size_t)m);
    if (!*out) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    for (int i = 0; i < m; i++) {
        const json_t *e = json_is_string(v) ? v : json_array_get(v, (size_t)i);
        if (json_is_array(v)) snprintf(p, sizeof p, "%s[%d]", path, i);
        else snprintf(p, sizeof p, "%s", path);
        if (!json_is_string(e)) return fail(c, p, "expected a part name, found %s", type_name(e));
        const char *name = json_string_value(e);
        int k = cn_assembly_find_part(a, name);
        if (k < 0 || k >= a->nreal) return no_such_part(c, p, name, a);
        if (a->parts[k].fixed) return fail(c, p, "part '%s' is fixed; fixed parts never move", name);
        if (removed_by[k] >= 0 && removed_by[k] < step)
            return fail(c, p, "part '%s' was already removed by plan[%d]", name, removed_by[k]);
        for (int j = 0; j < *n; j++)
            if ((*out)[j] == k) return fail(c, p, "part '%s' is named twice", name);
        if (allowed) {
            int ok = 0;
            for (int j = 0; j < nallowed; j++) ok |= allowed[j] == k;
            if (!ok) return fail(c, p, "part '%s' is not one of the parts this step moves", name);
        }
        (*out)[(*n)++] = k;
    }
    return CN_OK;
}

/* Straight up, against gravity, until the moved parts are clear of every remaining part whose
 * shadow along gravity meets theirs, plus 1% of their own height. */
static void default_lift(cnAssembly *a, cnPlanStep *st, const int *removed_by, int step) {
    double u[3], t1[3], t2[3];
    cn_copy3(u, a->gravity);
    cn_scale3(u, -1.0 / cn_norm3(u));
    if (a->dim == 2) t1[0] = u[1], t1[1] = -u[0], t1[2] = 0, t2[0] = t2[1] = t2[2] = 0;
    else cn_tangent_basis(u, t1, t2);
    double mlo[3] = {INFINITY, INFINITY, INFINITY}, mhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const double *axes[3] = {u, t1, t2};
    for (int i = 0; i < st->nmove; i++) {
        const cnPart *p = &a->parts[st->move[i]];
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nverts; v++)
                for (int k = 0; k < 3; k++) {
                    double d = cn_dot3(axes[k], p->pieces[s].verts[v]);
                    mlo[k] = fmin(mlo[k], d), mhi[k] = fmax(mhi[k], d);
                }
    }
    double need = 0, tol = a->contact_tol;
    for (int r = 0; r < a->nreal; r++) {
        if (removed_by[r] >= 0 && removed_by[r] <= step) continue;
        const cnPart *p = &a->parts[r];
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nverts; v++)
                for (int k = 0; k < 3; k++) {
                    double d = cn_dot3(axes[k], p->pieces[s].verts[v]);
                    lo[k] = fmin(lo[k], d), hi[k] = fmax(hi[k], d);
                }
        int shadow = 1; /* touching side by side counts: clear means clear of it too */
        for (int k = 1; k < a->dim; k++)
            if (lo[k] > mhi[k] + tol || mlo[k] > hi[k] + tol) shadow = 0;
        if (shadow) need = fmax(need, hi[0] - mlo[0]);
    }
    double lift = need + 0.01 * (mhi[0] - mlo[0]);
    st->nseg = 1;
    st->seg = cn_calloc(1, sizeof(cnSegment));
    if (st->seg) for (int k = 0; k < 3; k++) st->seg[0].move[k] = lift * u[k];
}

/* The default distance between samples of a motion: half the size (largest extent) of the
 * smallest free part, so that sampling is the same whatever the unit of length. A part that
 * moves this far can neither pass over nor leave a support of any free part unseen between
 * two samples, and bisection then locates an onset to the solver's tolerance. */
static double default_sample_length(const cnAssembly *a) {
    double h = INFINITY;
    for (int i = 0; i < a->nreal; i++) {
        const cnPart *p = &a->parts[i];
        if (p->fixed) continue;
        double ext = 0;
        for (int k = 0; k < a->dim; k++) ext = fmax(ext, p->hi[k] - p->lo[k]);
        h = fmin(h, 0.5 * ext);
    }
    return isfinite(h) && h > 0 ? h : a->length_scale;
}

static cnStatus load_plan(Ctx *c, const json_t *root, cnAssembly *a) {
    json_t *sim = json_object_get(root, "simulation");
    bool dt_given = false;
    a->sim_dt = 1.0;
    a->sim_speed = 1.0;
    if (sim) {
        if (!json_is_object(sim))
            return fail(c, "simulation", "expected {\"dt\": number, \"speed\": number}, found %s", type_name(sim));
        static const char *const keys[] = {"dt", "speed", NULL};
        cnStatus s = check_keys(c, sim, "simulation", keys);
        if (s) return s;
        json_t *e = json_object_get(sim, "dt");
        if (e && (s = get_positive(c, e, "simulation.dt", &a->sim_dt))) return s;
        dt_given = e != NULL;
        e = json_object_get(sim, "speed");
        if (e && (s = get_positive(c, e, "simulation.speed", &a->sim_speed))) return s;
    }
    if (!dt_given) a->sim_dt = default_sample_length(a) / a->sim_speed;
    json_t *plan = json_object_get(root, "plan");
    if (!plan) return CN_OK;
    if (!json_is_array(plan)) return fail(c, "plan", "expected an array of steps, found %s", type_name(plan));
    int ns = (int)json_array_size(plan);
    a->plan = cn_calloc((size_t)ns + 1, sizeof(cnPlanStep));
    int *removed_by = cn_malloc(sizeof(int) * (size_t)(a->nreal + 1));
    if (!a->plan || !removed_by) {
        cn_free(removed_by);
        return cn_diag_set(c->diag, CN_ERR_MEMORY, "plan", "out of memory");
    }
    for (int i = 0; i < a->nreal; i++) removed_by[i] = -1;
    cnStatus s = CN_OK;
    char path[PATH_MAX_LEN], p[PATH_MAX_LEN];
    int ngrippers = 0;
    for (int k = 0; k < ns && !s; k++) {
        const json_t *v = json_array_get(plan, (size_t)k);
        cnPlanStep *st = &a->plan[k];
        st->gripper = -1;
        a->nsteps = k + 1;
        snprintf(path, sizeof path, "plan[%d]", k);
        if (!json_is_object(v)) {
            s = fail(c, path, "expected a step {\"move\": ..., \"path\": ...}, found %s", type_name(v));
            break;
        }
        static const char *const keys[] = {"move", "grip", "path", "support", "gripper", NULL};
        if ((s = check_keys(c, v, path, keys))) break;
        json_t *e = json_object_get(v, "move");
        snprintf(p, sizeof p, "%s.move", path);
        if (!e) {
            s = fail(c, p, "missing; name the part or parts that leave");
            break;
        }
        if ((s = get_part_list(c, e, p, a, removed_by, k, NULL, 0, &st->move, &st->nmove))) break;
        e = json_object_get(v, "grip");
        snprintf(p, sizeof p, "%s.grip", path);
        if (e) {
            if ((s = get_part_list(c, e, p, a, removed_by, k, st->move, st->nmove, &st->grip, &st->ngrip))) break;
        } else {
            st->grip = cn_malloc(sizeof(int) * (size_t)st->nmove);
            if (!st->grip) {
                s = cn_diag_set(c->diag, CN_ERR_MEMORY, p, "out of memory");
                break;
            }
            memcpy(st->grip, st->move, sizeof(int) * (size_t)st->nmove);
            st->ngrip = st->nmove;
        }
        for (int i = 0; i < st->nmove; i++) removed_by[st->move[i]] = k;
        e = json_object_get(v, "support");
        snprintf(p, sizeof p, "%s.support", path);
        if (e) {
            int sup;
            if ((s = get_support(c, e, p, &sup))) break;
            st->support = (cnSupport)sup;
        }
        e = json_object_get(v, "path");
        snprintf(p, sizeof p, "%s.path", path);
        if (e) {
            cnSegment *pts;
            int np;
            if (!json_is_array(e) || json_array_size(e) == 0) {
                s = fail(c, p, "expected a non-empty array of displacements, e.g. [[-12, 0], [0, 6]]");
                break;
            }
            if ((s = get_path(c, e, p, a->dim, &pts, &np))) break;
            st->seg = pts;
            st->nseg = np;
            st->path_given = true;
            for (int i = 0; i < np && !s; i++) {
                const double *mv = pts[i].move; /* hypot: 1e200 is not inf */
                double len = pts[i].kind == CN_SEGMENT_MOVE ? hypot(hypot(mv[0], mv[1]), mv[2]) : 1;
                snprintf(p, sizeof p, "%s.path[%d]", path, i);
                if (!(len > CN_TOL_LENGTH_ZERO * a->length_scale))
                    s = fail(c, p, "a displacement of zero length; remove it");
                /* where the parts would end, double coordinates keep too few digits for contacts
                   of their size (as for a part far from the origin) */
                else if (!(len <= CN_MAX_FAR_RATIO * a->length_scale))
                    s = fail(c, p, "a displacement of %.3g, more than %g times the parts' size (%.3g): "
                             "shorten it", len, CN_MAX_FAR_RATIO, a->length_scale);
            }
            if (s) break;
            snprintf(p, sizeof p, "%s.path", path);
            if ((s = check_turns(c, a, p, st->move, st->nmove, st->seg, st->nseg))) break;
        }
        if (json_object_get(v, "gripper")) ngrippers++;
    }
    if (!s)
        for (int k = 0; k < a->nsteps; k++)
            if (!a->plan[k].path_given) default_lift(a, &a->plan[k], removed_by, k);
    /* a bound on the samples of a step, so that a tiny dt cannot make a run that never ends */
    for (int k = 0; !s && dt_given && k < a->nsteps; k++) {
        const cnPlanStep *st = &a->plan[k];
        double L = cn_path_length(a, st->move, st->nmove, st->seg, st->nseg, NULL);
        double n = L / (a->sim_speed * a->sim_dt);
        if (n > CN_MAX_SAMPLES)
            s = fail(c, "simulation.dt",
                     "plan[%d] would take %.3g samples (path length %.6g, speed %g, dt %g); at "
                     "most %d are allowed: raise dt or speed",
                     k, n, L, a->sim_speed, a->sim_dt, CN_MAX_SAMPLES);
    }
    cn_free(removed_by);
    if (s || ngrippers == 0) return s;

    /* Gripper bodies: extra parts, after the assembly's own. */
    cnPart *np = cn_realloc(a->parts, sizeof(cnPart) * (size_t)(a->nparts + ngrippers));
    if (!np) return cn_diag_set(c->diag, CN_ERR_MEMORY, "plan", "out of memory");
    a->parts = np;
    for (int k = 0; k < a->nsteps; k++) {
        const json_t *g = json_object_get(json_array_get(plan, (size_t)k), "gripper");
        if (!g) continue;
        snprintf(p, sizeof p, "plan[%d].gripper", k);
        if (!json_is_object(g)) return fail(c, p, "expected a shape object, e.g. {\"polygon\": [...]}, found %s", type_name(g));
        static const char *const keys2[] = {"polygon", "polygons", NULL};
        static const char *const keys3[] = {"box", "hull", "hulls", NULL};
        if ((s = check_keys(c, g, p, c->dim == 2 ? keys2 : keys3))) return s;
        int gi = a->nparts++;
        cnPart *part = &a->parts[gi];
        memset(part, 0, sizeof *part);
        char name[32];
        snprintf(name, sizeof name, "gripper%d", k + 1);
        if (cn_assembly_find_part(a, name) >= 0 && cn_assembly_find_part(a, name) != gi)
            return fail(c, p, "a part is already named '%s', the name of this step's gripper; rename the part", name);
        part->name = cn_strdup(name);
        part->fixed = true;
        part->gripper_step = k;
        if ((s = load_shape(c, g, p, part))) return s;
        cn_mass_part(part, c->dim, 1.0, 0);
        a->plan[k].gripper = gi;
    }
    return CN_OK;
}

static cnStatus get_support(Ctx *c, const json_t *e, const char *p, int *out) {
    if (!json_is_string(e) || (strcmp(json_string_value(e), "hold") && strcmp(json_string_value(e), "push")))
        return fail(c, p, "must be \"hold\" (the gripper carries the weight) or \"push\" (it drives the part along the path only)");
    *out = strcmp(json_string_value(e), "push") ? CN_SUPPORT_HOLD : CN_SUPPORT_PUSH;
    return CN_OK;
}

/* "candidates": {"C": {"I": [[0, 6]], "II": {"path": [[-8, 0], [0, 6]], "support": "push"}}} */
static cnStatus load_candidates(Ctx *c, const json_t *root, cnAssembly *a) {
    a->cand_support = CN_SUPPORT_HOLD;
    json_t *cs = json_object_get(root, "candidate_support");
    cnStatus s;
    if (cs) {
        int v;
        if ((s = get_support(c, cs, "candidate_support", &v))) return s;
        a->cand_support = (cnSupport)v;
    }
    json_t *cands = json_object_get(root, "candidates");
    if (!cands) return CN_OK;
    if (!json_is_object(cands))
        return fail(c, "candidates", "expected {\"part\": {\"name\": path, ...}, ...}, found %s", type_name(cands));
    int total = 0;
    const char *pname;
    json_t *pv;
    json_object_foreach(cands, pname, pv) total += json_is_object(pv) ? (int)json_object_size(pv) : 0;
    a->cand = cn_calloc((size_t)total + 1, sizeof(cnCandidate));
    if (!a->cand) return cn_diag_set(c->diag, CN_ERR_MEMORY, "candidates", "out of memory");
    char p[PATH_MAX_LEN];
    json_object_foreach(cands, pname, pv) {
        snprintf(p, sizeof p, "candidates.%s", pname);
        int k = cn_assembly_find_part(a, pname);
        if (k < 0 || k >= a->nreal) return no_such_part(c, p, pname, a);
        if (a->parts[k].fixed) return fail(c, p, "part '%s' is fixed; fixed parts never move", pname);
        if (!json_is_object(pv))
            return fail(c, p, "expected named paths, e.g. {\"I\": [[0, 6]]}, found %s", type_name(pv));
        const char *cname;
        json_t *cv;
        json_object_foreach(pv, cname, cv) {
            char q[PATH_MAX_LEN];
            snprintf(q, sizeof q, "candidates.%s.%s", pname, cname);
            cnStatus ps = printable(c, cname, q);
            if (ps) return ps;
            cnCandidate *cd = &a->cand[a->ncand];
            cd->part = k;
            cd->support = -1;
            cd->name = cn_strdup(cname);
            if (!cd->name) return cn_diag_set(c->diag, CN_ERR_MEMORY, q, "out of memory");
            a->ncand++;
            const json_t *path = cv;
            if (json_is_object(cv)) {
                static const char *const keys[] = {"path", "support", NULL};
                if ((s = check_keys(c, cv, q, keys))) return s;
                path = json_object_get(cv, "path");
                json_t *sup = json_object_get(cv, "support");
                char q2[PATH_MAX_LEN];
                snprintf(q2, sizeof q2, "%s.support", q);
                if (sup && (s = get_support(c, sup, q2, &cd->support))) return s;
                snprintf(q2, sizeof q2, "%s.path", q);
                if (!path) return fail(c, q2, "missing; give the path's displacements");
                if (!json_is_array(path) || json_array_size(path) == 0)
                    return fail(c, q2, "expected a non-empty array of displacements");
                if ((s = get_path(c, path, q2, a->dim, &cd->seg, &cd->nseg))) return s;
                if ((s = check_turns(c, a, q2, &cd->part, 1, cd->seg, cd->nseg))) return s;
            } else {
                if (!json_is_array(cv) || json_array_size(cv) == 0)
                    return fail(c, q, "expected a path: a non-empty array of displacements, e.g. [[0, 6]]");
                if ((s = get_path(c, cv, q, a->dim, &cd->seg, &cd->nseg))) return s;
                if ((s = check_turns(c, a, q, &cd->part, 1, cd->seg, cd->nseg))) return s;
            }
            for (int i = 0; i < cd->nseg; i++)
                if (cd->seg[i].kind == CN_SEGMENT_MOVE &&
                    !(cn_norm3(cd->seg[i].move) > CN_TOL_LENGTH_ZERO * a->length_scale))
                    return fail(c, q, "displacement %d has zero length; remove it", i);
            double L = cn_path_length(a, &cd->part, 1, cd->seg, cd->nseg, NULL);
            if (L / (a->sim_speed * a->sim_dt) > CN_MAX_SAMPLES)
                return fail(c, q, "the path would take %.3g samples (length %.6g, speed %g, dt %g); "
                                  "at most %d are allowed: raise simulation.dt or speed",
                            L / (a->sim_speed * a->sim_dt), L, a->sim_speed, a->sim_dt, CN_MAX_SAMPLES);
        }
    }
    return CN_OK;
}

/* A gripper must touch the parts it supports and not overlap them. */
static cnStatus check_grippers(Ctx *c, cnAssembly *a) {
    unsigned char *absent = cn_malloc((size_t)a->nparts);
    if (!absent) return cn_diag_set(c->diag, CN_ERR_MEMORY, "plan", "out of memory");
    cnStatus s = CN_OK;
    for (int k = 0; k < a->nsteps && !s; k++) {
        const cnPlanStep *st = &a->plan[k];
        if (st->gripper < 0) continue;
        memset(absent, 1, (size_t)a->nparts);
        absent[st->gripper] = 0;
        for (int i = 0; i < st->nmove; i++) absent[st->move[i]] = 0;
        cnContactQuery q = {NULL, absent, NULL};
        cnContactSet cs = {0};
        cnOverlap ov;
        s = cn_contacts_find(a, &q, &cs, &ov, c->diag);
        int touches = 0;
        for (int i = 0; i < cs.count; i++)
            touches |= cs.items[i].body1 == st->gripper || cs.items[i].body2 == st->gripper;
        cn_contacts_free(&cs);
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "plan[%d].gripper", k);
        if (!s && ov.found)
            s = fail(c, p, "the gripper overlaps part '%s' by %.6g; it must touch the moved parts, not overlap them",
                     a->parts[ov.part1 == st->gripper ? ov.part2 : ov.part1].name, ov.depth);
        else if (!s && !touches)
            s = fail(c, p, "the gripper does not touch the parts this step moves; place it against them");
    }
    cn_free(absent);
    return s;
}

static cnStatus load_root(Ctx *c, const json_t *root, cnAssembly *a) {
    if (!json_is_object(root))
        return fail(c, "$", "the file must hold one JSON object, found %s", type_name(root));
    static const char *const keys[] = {"name",     "dimension",      "gravity",
                                       "density",  "friction",       "friction_pairs",
                                       "friction_directions", "tolerance", "parts",
                                       "fixels",   "plan", "simulation", "candidates",
                                       "candidate_support", NULL};
    cnStatus s = check_keys(c, root, "", keys);
    if (s) return s;

    json_t *v = json_object_get(root, "name");
    if (v) {
        if (!json_is_string(v)) return fail(c, "name", "expected a string, found %s", type_name(v));
        if ((s = printable(c, json_string_value(v), "name"))) return s;
        a->name = cn_strdup(json_string_value(v));
    }
    v = json_object_get(root, "dimension");
    if (!v) return fail(c, "dimension", "missing; say \"dimension\": 2 or 3");
    if (!json_is_integer(v) || (json_integer_value(v) != 2 && json_integer_value(v) != 3))
        return fail(c, "dimension", "must be 2 or 3");
    a->dim = c->dim = (int)json_integer_value(v);

    a->gravity[0] = a->gravity[1] = a->gravity[2] = 0;
    a->gravity[a->dim - 1] = -9.81;
    v = json_object_get(root, "gravity");
    if (v) {
        s = get_point(c, v, "gravity", a->dim, a->gravity);
        if (s) return s;
        double gmax = fmax(fabs(a->gravity[0]), fmax(fabs(a->gravity[1]), fabs(a->gravity[2])));
        if (!(gmax > 0))
            return fail(c, "gravity", "must not be zero: stability under gravity needs gravity");
        /* squared in norms and multiplied by masses: outside this range the digits are lost to
         * underflow or overflow, while only gravity's direction changes a verdict */
        if (gmax < CN_GRAVITY_MIN || gmax > CN_GRAVITY_MAX)
            return fail(c, "gravity", "its size %g is outside the %g to %g cairn computes with; only "
                        "its direction changes a verdict (forces scale with it): scale it, e.g. to "
                        "9.81", gmax * hypot(hypot(a->gravity[0] / gmax, a->gravity[1] / gmax), a->gravity[2] / gmax),
                        CN_GRAVITY_MIN, CN_GRAVITY_MAX);
    }
    a->density = 1.0;
    v = json_object_get(root, "density");
    if (v && (s = get_positive(c, v, "density", &a->density))) return s;
    a->friction = 0.0;
    v = json_object_get(root, "friction");
    if (v) {
        if ((s = get_number(c, v, "friction", &a->friction))) return s;
        if (a->friction < 0) return fail(c, "friction", "must be zero or positive");
    }
    a->friction_dirs = a->dim == 2 ? 2 : CN_DEFAULT_FRICTION_DIRECTIONS;
    v = json_object_get(root, "friction_directions");
    if (v) {
        if (!json_is_integer(v))
            return fail(c, "friction_directions", "expected an integer, found %s", type_name(v));
        long long d = json_integer_value(v);
        if (a->dim == 2 && d != 2)
            return fail(c, "friction_directions", "2-D friction always uses 2 directions");
        if (a->dim == 3 && (d < 3 || d > 64))
            return fail(c, "friction_directions", "must be from 3 to 64");
        a->friction_dirs = (int)d;
    }
    a->rel_tol = CN_DEFAULT_RELATIVE_TOLERANCE;
    v = json_object_get(root, "tolerance");
    if (v) {
        if ((s = get_number(c, v, "tolerance", &a->rel_tol))) return s;
        if (!(a->rel_tol >= 1e-12 && a->rel_tol <= 1e-1))
            return fail(c, "tolerance",
                        "the relative contact tolerance must be from 1e-12 to 0.1, got %g",
                        a->rel_tol);
    }

    c->rel_tol = a->rel_tol;
    v = json_object_get(root, "parts");
    if (!v) return fail(c, "parts", "missing; list the parts of the assembly");
    if (!json_is_array(v)) return fail(c, "parts", "expected an array, found %s", type_name(v));
    if (json_array_size(v) == 0) return fail(c, "parts", "the assembly has no parts");
    a->nparts = (int)json_array_size(v);
    a->parts = cn_calloc((size_t)a->nparts, sizeof(cnPart));
    if (!a->parts) return cn_diag_set(c->diag, CN_ERR_MEMORY, "parts", "out of memory");
    /* names seen so far in a hash table (a list searched for each part is quadratic) */
    if (!(c->names = json_object())) return cn_diag_set(c->diag, CN_ERR_MEMORY, "parts", "out of memory");
    for (int i = 0; i < a->nparts && !s; i++) s = load_part(c, json_array_get(v, (size_t)i), i, a, a->density);
    json_decref(c->names);
    c->names = NULL;
    if (s) return s;
    a->nreal = a->nparts;
    for (int i = 1; i < a->nparts; i++) {
        const cnPart *q = &a->parts[i - 1];
        a->parts[i].vertex_base = q->vertex_base + numbers_of(q);
    }
    /* Scale: bounding box of everything. */
    for (int k = 0; k < 3; k++) a->lo[k] = INFINITY, a->hi[k] = -INFINITY;
    for (int i = 0; i < a->nparts; i++)
        for (int k = 0; k < 3; k++) {
            a->lo[k] = fmin(a->lo[k], a->parts[i].lo[k]);
            a->hi[k] = fmax(a->hi[k], a->parts[i].hi[k]);
        }
    double d[3];
    cn_sub3(a->hi, a->lo, d);
    a->length_scale = cn_norm3(d);
    a->contact_tol = a->rel_tol * a->length_scale;
    /* How many digits of its smallest part the coordinates keep: cairn works in the file's
     * frame, so a part far from the origin relative to its size is refused rather than judged on
     * rounding (its contacts would be decided within a few ulps of the contact tolerance). */
    {
        double far = 0, small = INFINITY;
        int which = -1;
        for (int i = 0; i < a->nparts && which < 0; i++) {
            double e[3], f = 0;
            cn_sub3(a->parts[i].hi, a->parts[i].lo, e);
            double size = cn_norm3(e);
            if (!(size >= CN_MIN_PART_SIZE && size <= CN_MAX_PART_SIZE)) {
                char p[PATH_MAX_LEN];
                snprintf(p, sizeof p, "parts[%d]", i);
                return fail(c, p, "this part is %g across, outside the %g to %g cairn computes with (its "
                            "volume and inertia would overflow or underflow): scale the file, e.g. to metres",
                            size, CN_MIN_PART_SIZE, CN_MAX_PART_SIZE);
            }
            for (int k = 0; k < 3; k++) f = fmax(f, fmax(fabs(a->parts[i].lo[k]), fabs(a->parts[i].hi[k])));
            if (f > CN_MAX_FAR_RATIO * cn_norm3(e)) which = i, far = f, small = cn_norm3(e);
        }
        if (which >= 0) {
            char p[PATH_MAX_LEN];
            snprintf(p, sizeof p, "parts[%d]", which);
            return fail(c, p, "this part is %g across but reaches %g from the origin: "
                        "its coordinates keep fewer than 8 of its 16 digits; move the assembly "
                        "near the origin (a verdict does not depend on where it is)",
                        small, far);
        }
    }

    v = json_object_get(root, "friction_pairs");
    if (v) {
        if (!json_is_array(v))
            return fail(c, "friction_pairs", "expected an array, found %s", type_name(v));
        a->npairs = (int)json_array_size(v);
        a->pairs = cn_calloc((size_t)a->npairs + 1, sizeof(cnFrictionPair));
        if (!a->pairs) return cn_diag_set(c->diag, CN_ERR_MEMORY, "", "out of memory");
        for (int i = 0; i < a->npairs; i++)
            if ((s = load_pair(c, json_array_get(v, (size_t)i), i, a))) return s;
    }
    v = json_object_get(root, "fixels");
    if (v) {
        if (!json_is_array(v)) return fail(c, "fixels", "expected an array, found %s", type_name(v));
        a->nfixels = (int)json_array_size(v);
        a->fixels = cn_calloc((size_t)a->nfixels + 1, sizeof(cnFixel));
        if (!a->fixels) return cn_diag_set(c->diag, CN_ERR_MEMORY, "", "out of memory");
        for (int i = 0; i < a->nfixels; i++)
            if ((s = load_fixel(c, json_array_get(v, (size_t)i), i, a))) return s;
    }

    s = load_plan(c, root, a);
    if (s) return s;
    for (int i = a->nreal; i < a->nparts; i++) {
        const cnPart *q = &a->parts[i - 1];
        a->parts[i].vertex_base = q->vertex_base + numbers_of(q);
    }
    for (int i = 0; i < a->nparts; i++) a->parts[i].nnumbers = numbers_of(&a->parts[i]);
    if ((s = check_grippers(c, a))) return s;
    if ((s = load_candidates(c, root, a))) return s;

    /* Overlapping parts are an input error: they cannot be at rest. */
    cnContactSet cs = {0};
    cnOverlap ov;
    s = cn_contacts_find(a, NULL, &cs, &ov, c->diag);
    cn_contacts_free(&cs);
    if (s) return s;
    if (ov.found) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "parts[%d]", ov.part2);
        return fail(c, p,
                    "part '%s' overlaps part '%s' (parts[%d]) by %.6g, more than the contact "
                    "tolerance %.3g (%g of the smaller part's size); parts at rest may touch but "
                    "not overlap: move them apart (or raise \"tolerance\" if this is modelling "
                    "noise)",
                    a->parts[ov.part2].name, a->parts[ov.part1].name, ov.part1, ov.depth,
                    ov.tol, a->rel_tol);
    }
    return CN_OK;
}

cnLoadOptions cn_load_options_default(void) {
    cnLoadOptions o;
    memset(&o, 0, sizeof o);
    o.friction = o.density = o.tolerance = NAN;
    return o;
}

/* A COMPAS assembly turned into cairn's document, and the caller's overrides set in it. */
static cnStatus prepare_root(json_t **root, const cnLoadOptions *o, cnDiag *diag) {
    if (cn_compas_is(*root)) {
        double tol = o && o->tolerance > 0 ? o->tolerance : CN_DEFAULT_RELATIVE_TOLERANCE;
        json_t *doc = cn_compas_to_cairn(*root, o ? o->supports : NULL, tol, diag);
        if (!doc) return diag->code;
        json_decref(*root);
        *root = doc;
    } else if (o && o->supports) {
        return cn_diag_set(diag, CN_ERR_INPUT, "--supports",
                           "names the supports of a COMPAS assembly; in a cairn file mark them with \"fixed\": true");
    }
    if (!o || !json_is_object(*root)) return CN_OK;
    const char *keys[3] = {"friction", "density", "tolerance"};
    double vals[3] = {o->friction, o->density, o->tolerance};
    for (int k = 0; k < 3; k++)
        if (!isnan(vals[k]) && json_object_set_new(*root, keys[k], json_real(vals[k])))
            return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    return CN_OK;
}

/* A problem found in the document made from a COMPAS assembly is named where the COMPAS file
 * has it: parts[i] is the node whose key is part i's name (its shape, the node's block; its
 * "fixed", the node's is_support); "parts[j]" in the message is that node too. */
/* The index in "parts[N]" at text (its length in *len), or -1 when text does not start so or N is
 * not a part of the document. */
static long part_ref(const char *text, const json_t *parts, int *len) {
    if (strncmp(text, "parts[", 6) != 0) return -1;
    char *end;
    long j = strtol(text + 6, &end, 10);
    if (end == text + 6 || *end != ']' || j < 0 || (size_t)j >= json_array_size(parts)) return -1;
    *len = (int)(end + 1 - text);
    return j;
}

/* Is text (n bytes) the name of a part of the document? */
static bool quoted_name(const json_t *parts, const char *text, size_t n) {
    for (size_t i = 0; i < json_array_size(parts); i++) {
        const char *name = json_string_value(json_object_get(json_array_get(parts, i), "name"));
        if (name && strlen(name) == n && !strncmp(name, text, n)) return true;
    }
    return false;
}

static void compas_where(const json_t *doc, cnDiag *diag) {
    const json_t *parts = json_object_get(doc, "parts");
    int len = 0;
    long i = part_ref(diag->where, parts, &len);
    if (i < 0) return;
    const char *key = json_string_value(json_object_get(json_array_get(parts, (size_t)i), "name"));
    if (!key) return;
    const char *rest = diag->where + len;
    const char *field = !strncmp(rest, ".fixed", 6) ? ".is_support" : !strncmp(rest, ".name", 5) || !*rest ? "" : ".block";
    char where[sizeof diag->where];
    snprintf(where, sizeof where, "data.graph.data.node.%.60s%s", key, field);
    snprintf(diag->where, sizeof diag->where, "%s", where);
    /* the message, outside its quoted part names (a key may read "parts[2]"): "parts[j]" becomes
     * the node, " (parts[j])" after a name goes (the name is the key), "tolerance" the option */
    char msg[sizeof diag->message];
    size_t m = 0;
    for (const char *q = diag->message; *q && m + 1 < sizeof msg;) {
        long j;
        int n = 0;
        const char *k2, *close = *q == '\'' ? strchr(q + 1, '\'') : NULL;
        if (close && quoted_name(parts, q + 1, (size_t)(close - q - 1))) { /* 'name': as it is */
            while (q <= close && m + 1 < sizeof msg) msg[m++] = *q++;
            continue;
        }
        if (q[0] == ' ' && q[1] == '(' && (j = part_ref(q + 2, parts, &n)) >= 0 && q[2 + n] == ')') {
            q += 2 + n + 1;
        } else if ((j = part_ref(q, parts, &n)) >= 0 &&
                   (k2 = json_string_value(json_object_get(json_array_get(parts, (size_t)j), "name")))) {
            int w = snprintf(msg + m, sizeof msg - m, "node '%.60s'", k2);
            m = w > 0 && (size_t)w < sizeof msg - m ? m + (size_t)w : sizeof msg - 1;
            q += n;
        } else if (!strncmp(q, "\"tolerance\"", 11)) {
            int w = snprintf(msg + m, sizeof msg - m, "--tolerance");
            m = w > 0 && (size_t)w < sizeof msg - m ? m + (size_t)w : sizeof msg - 1;
            q += 11;
        } else {
            msg[m++] = *q++;
        }
    }
    msg[m] = '\0';
    snprintf(diag->message, sizeof diag->message, "%s", msg);
}

static cnStatus load_from_root(json_t *root, const char *source, cnAssembly **out,
                               cnDiag *diag, const cnLoadOptions *opts, const char *file) {
    cnDiag mine;
    if (!diag) diag = &mine;
    bool compas = cn_compas_is(root);
    cnStatus ps = prepare_root(&root, opts, diag);
    if (ps) {
        json_decref(root);
        return ps;
    }
    cnAssembly *a = cn_calloc(1, sizeof(cnAssembly));
    if (!a) {
        json_decref(root);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
    if (source) a->source = cn_strdup(source);
    cnDiag local;
    Ctx c = {diag ? diag : &local, 0, CN_DEFAULT_RELATIVE_TOLERANCE, ".", false, NULL};
    /* mesh paths: relative to the caller's directory, else the file's, else the current one */
    char *dir = NULL;
    if (opts && opts->mesh_dir) c.mesh_dir = opts->mesh_dir;
    else if (file && strcmp(file, "-")) {
        dir = cn_strdup(file);
        if (!dir) {
            cn_assembly_free(a);
            json_decref(root);
            return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
        }
        char *slash = strrchr(dir, '/');
        if (!slash) strcpy(dir, ".");
        else if (slash == dir) dir[1] = '\0';
        else *slash = '\0';
        c.mesh_dir = dir;
    }
    c.mesh_anywhere = opts && opts->mesh_anywhere;
    cnStatus s = load_root(&c, root, a);
    cn_free(dir);
    if (s && compas) compas_where(root, c.diag);
    json_decref(root);
    if (s) {
        cn_assembly_free(a);
        return s;
    }
    *out = a;
    return CN_OK;
}

static cnStatus syntax_error(cnDiag *diag, const json_error_t *err) {
    /* jansson out of memory: not the file's fault (it said "JSON syntax error" at line -1);
     * where an allocation fails it may leave the error's text empty rather than say so */
    if (json_error_code(err) == json_error_out_of_memory || !err->text[0])
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading the JSON text");
    char where[64];
    /* jansson says column 0 at the end of the text; columns are 1-based for people */
    snprintf(where, sizeof where, "%d:%d", err->line, err->column > 0 ? err->column : 1);
    /* jansson's own words for these name its flags; say what is wrong instead */
    if (strstr(err->text, "JSON_ALLOW_NUL"))
        return cn_diag_set(diag, CN_ERR_INPUT, where,
                           "a string contains \\u0000 (a NUL character), which names and "
                           "values cannot hold; remove it");
    if (strstr(err->text, "duplicate object key"))
        return cn_diag_set(diag, CN_ERR_INPUT, where,
                           "JSON syntax error: %s; each key may appear once in an object",
                           err->text);
    return cn_diag_set(diag, CN_ERR_INPUT, where, "JSON syntax error: %s", err->text);
}

cnStatus cn_assembly_load_string(const char *text, const char *source, cnAssembly **out,
                                 cnDiag *diag) {
    return cn_assembly_load_string_with(text, source, NULL, out, diag);
}

cnStatus cn_assembly_load_string_with(const char *text, const char *source, const cnLoadOptions *o,
                                      cnAssembly **out, cnDiag *diag) {
    cn_diag_clear(diag);
    *out = NULL;
    json_error_t err;
    json_t *root = json_loads(text, JSON_REJECT_DUPLICATES, &err);
    if (!root) return syntax_error(diag, &err);
    return load_from_root(root, source, out, diag, o, NULL);
}

static cnStatus read_json_file(const char *path, json_t **root, cnDiag *diag) {
    bool in = !strcmp(path, "-"); /* standard input */
    FILE *f = in ? stdin : fopen(path, "rb");
    if (!f) return cn_diag_set(diag, CN_ERR_IO, "", "cannot open the file: %s", strerror(errno));
    struct stat st;
    if (fstat(fileno(f), &st) == 0 && S_ISDIR(st.st_mode)) {
        if (!in) fclose(f);
        return cn_diag_set(diag, CN_ERR_IO, "", "is a directory; give a JSON file");
    }
    json_error_t err;
    *root = json_loadf(f, JSON_REJECT_DUPLICATES, &err);
    if (!in) fclose(f);
    if (!*root) return syntax_error(diag, &err);
    return CN_OK;
}

cnStatus cn_assembly_load_file(const char *path, cnAssembly **out, cnDiag *diag) {
    return cn_assembly_load_with_plan(path, NULL, out, diag);
}

/* Is a diagnostic's place inside what the plan file supplied? */
static bool in_plan_file(const char *where) {
    return !strncmp(where, "plan", 4) || !strncmp(where, "simulation", 10) ||
           !strncmp(where, "name", 4) || !strncmp(where, "fixels", 6);
}

static cnStatus with_plan(const char *path, const char *plan_path, const char *plan_text,
                          cnAssembly **out, cnDiag *diag, const cnLoadOptions *o);

cnStatus cn_assembly_load_with_plan(const char *path, const char *plan_path, cnAssembly **out,
                                    cnDiag *diag) {
    return with_plan(path, plan_path, NULL, out, diag, NULL);
}

cnStatus cn_assembly_load_with(const char *path, const char *plan_path, const char *plan_text,
                               const cnLoadOptions *o, cnAssembly **out, cnDiag *diag) {
    return with_plan(path, plan_text ? "<plan>" : plan_path, plan_text, out, diag, o);
}

cnStatus cn_assembly_load_with_plan_text(const char *path, const char *plan_text, cnAssembly **out,
                                         cnDiag *diag) {
    return with_plan(path, plan_text ? "<plan>" : NULL, plan_text, out, diag, NULL);
}

/* The plan from the file plan_path, or from plan_text (named plan_path in messages). */
static cnStatus with_plan(const char *path, const char *plan_path, const char *plan_text,
                          cnAssembly **out, cnDiag *diag, const cnLoadOptions *o) {
    cn_diag_clear(diag);
    *out = NULL;
    json_t *root, *plan = NULL;
    cnStatus s = read_json_file(path, &root, diag);
    if (s) return s;
    if (!plan_path) return load_from_root(root, path, out, diag, o, path);
    if (plan_text) {
        json_error_t err;
        plan = json_loads(plan_text, JSON_REJECT_DUPLICATES, &err);
        if (!plan) {
            s = syntax_error(diag, &err);
            goto plan_fail;
        }
    } else if ((s = read_json_file(plan_path, &plan, diag))) {
        goto plan_fail;
    }
    if (!json_is_object(plan)) {
        s = cn_diag_set(diag, CN_ERR_INPUT, "", "a plan file is a JSON object with \"plan\" "
                        "(and optionally \"simulation\" and \"name\")");
        goto plan_fail;
    }
    const char *key;
    json_t *v;
    json_object_foreach(plan, key, v) {
        if (strcmp(key, "plan") && strcmp(key, "simulation") && strcmp(key, "name") &&
            strcmp(key, "fixels")) {
            s = cn_diag_set(diag, CN_ERR_INPUT, key, "unknown key in a plan file; allowed: plan, "
                            "simulation, fixels, name");
            goto plan_fail;
        }
    }
    if (!json_object_get(plan, "plan")) {
        s = cn_diag_set(diag, CN_ERR_INPUT, "", "a plan file needs \"plan\": a list of steps");
        goto plan_fail;
    }
    if (!json_is_object(root)) { /* the loader says what is wrong with the assembly */
        json_decref(plan);
        return load_from_root(root, path, out, diag, o, path);
    }
    json_object_set(root, "plan", json_object_get(plan, "plan"));
    if (json_object_get(plan, "simulation"))
        json_object_set(root, "simulation", json_object_get(plan, "simulation"));
    if (json_object_get(plan, "fixels")) /* fixtures for this run, added to the file's */
        json_object_set(root, "fixels", json_object_get(plan, "fixels"));
    json_t *pname = json_object_get(plan, "name"), *aname = json_object_get(root, "name");
    if (pname && !json_is_string(pname)) {
        s = cn_diag_set(diag, CN_ERR_INPUT, "name", "must be a string");
        goto plan_fail;
    }
    if (pname && json_is_string(aname)) {
        json_object_set_new(root, "name", json_sprintf("%s; %s", json_string_value(aname),
                                                       json_string_value(pname)));
    } else if (pname) {
        json_object_set(root, "name", pname);
    }
    json_decref(plan);
    plan = NULL;
    s = load_from_root(root, path, out, diag, o, path);
    if (s && diag && in_plan_file(diag->where)) snprintf(diag->file, sizeof diag->file, "%s", plan_path);
    return s;
plan_fail:
    json_decref(root);
    if (plan) json_decref(plan);
    if (diag) snprintf(diag->file, sizeof diag->file, "%s", plan_path);
    return s;
}
