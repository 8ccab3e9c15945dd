/* Reading JSON values for the loader: messages that name their path, unknown keys, numbers,
 * points, paths and their turns, part lists. */
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

cnStatus cn_ld_fail(Ctx *c, const char *path, const char *fmt, ...) {
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

cnStatus cn_ld_printable(Ctx *c, const char *text, const char *path) {
    int at, code = cn_control_char(text, &at);
    if (code >= 0)
        return cn_ld_fail(c, path, "the name contains a control character (code %d at byte %d); use "
                          "printable characters", code, at);
    return CN_OK;
}

/* A reference to a part that does not exist: said with the names there are (every defined name
 * is printable, so a reference with a control character is refused as such first). */
cnStatus cn_ld_no_such_part(Ctx *c, const char *path, const char *name, const cnAssembly *a) {
    cnStatus st = cn_ld_printable(c, name, path);
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
    return cn_ld_fail(c, path, "no part is named '%s'; the parts are: %s", name, list);
}

const char *cn_ld_type_name(const json_t *v) {
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
cnStatus cn_ld_check_keys(Ctx *c, const json_t *obj, const char *path,
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
            return cn_ld_fail(c, p, "unknown key '%s'; the keys allowed here are: %s", key, list);
        }
    }
    return CN_OK;
}

cnStatus cn_ld_get_number(Ctx *c, const json_t *v, const char *path, double *out) {
    if (!json_is_number(v))
        return cn_ld_fail(c, path, "expected a number, found %s", cn_ld_type_name(v));
    double x = json_number_value(v);
    if (!isfinite(x)) return cn_ld_fail(c, path, "the number is not finite");
    *out = x;
    return CN_OK;
}

cnStatus cn_ld_get_positive(Ctx *c, const json_t *v, const char *path, double *out) {
    cnStatus s = cn_ld_get_number(c, v, path, out);
    if (s) return s;
    if (!(*out > 0)) return cn_ld_fail(c, path, "must be greater than zero, got %g", *out);
    return CN_OK;
}

/* A point of `dim` numbers. */
cnStatus cn_ld_get_point(Ctx *c, const json_t *v, const char *path, int dim, double out[3]) {
    if (!json_is_array(v) || (int)json_array_size(v) != dim)
        return cn_ld_fail(c, path, "expected a point: an array of %d numbers, found %s%s", dim,
                          cn_ld_type_name(v), json_is_array(v) ? " of another length" : "");
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k < dim; k++) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "%s[%d]", path, k);
        cnStatus s = cn_ld_get_number(c, json_array_get(v, (size_t)k), p, &out[k]);
        if (s) return s;
    }
    return CN_OK;
}

/* A place's coordinates (at most CN_MAX_COORD in magnitude); directions and displacements are
 * read by get_point. */
cnStatus cn_ld_get_place(Ctx *c, const json_t *v, const char *path, int dim, double out[3]) {
    cnStatus s = cn_ld_get_point(c, v, path, dim, out);
    for (int k = 0; !s && k < dim; k++)
        if (fabs(out[k]) > CN_MAX_COORD) {
            char p[PATH_MAX_LEN];
            snprintf(p, sizeof p, "%s[%d]", path, k);
            return cn_ld_fail(c, p, "%g is beyond the coordinates cairn computes with (magnitude up to %g: a part "
                              "up to %g across, up to %g times that from the origin); scale the file, e.g. to metres",
                              out[k], CN_MAX_COORD, CN_MAX_PART_SIZE, CN_MAX_FAR_RATIO);
        }
    return s;
}

/* Points array with at least `min` entries. Caller frees *pts. */

/* A turn: {"rotate": degrees, "about": point, "axis": direction (3-D only)}. */
static cnStatus get_turn(Ctx *c, const json_t *v, const char *path, int dim, cnSegment *out) {
    static const char *const keys2[] = {"rotate", "about", NULL};
    static const char *const keys3[] = {"rotate", "axis", "about", NULL};
    char p[PATH_MAX_LEN];
    if (dim == 2 && json_object_get(v, "axis")) {
        snprintf(p, sizeof p, "%s.axis", path);
        return cn_ld_fail(c, p, "a 2-D turn is about z (counter-clockwise positive); remove axis");
    }
    cnStatus s = cn_ld_check_keys(c, v, path, dim == 2 ? keys2 : keys3);
    if (s) return s;
    out->kind = CN_SEGMENT_TURN;
    snprintf(p, sizeof p, "%s.rotate", path);
    json_t *e = json_object_get(v, "rotate");
    double deg;
    if (!e) return cn_ld_fail(c, p, "missing; give the angle in degrees (counter-clockwise positive%s)",
                              dim == 3 ? ", right-hand rule about axis" : "");
    if ((s = cn_ld_get_number(c, e, p, &deg))) return s;
    if (deg == 0) return cn_ld_fail(c, p, "a rotation of zero degrees; remove it");
    if (fabs(deg) > 360)
        return cn_ld_fail(c, p, "at most one full turn (360 degrees) per segment, got %g; split it", deg);
    out->angle = deg * CN_PI / 180.0;
    snprintf(p, sizeof p, "%s.about", path);
    e = json_object_get(v, "about");
    if (!e) return cn_ld_fail(c, p, "missing; give the point the parts turn about, e.g. [0, 0%s]",
                              dim == 3 ? ", 0" : "");
    if ((s = cn_ld_get_point(c, e, p, dim, out->about))) return s;
    out->axis[0] = out->axis[1] = 0, out->axis[2] = 1;
    if (dim == 3) {
        snprintf(p, sizeof p, "%s.axis", path);
        e = json_object_get(v, "axis");
        if (!e) return cn_ld_fail(c, p, "missing; give the direction of the axis of the turn, e.g. [0, 0, 1]");
        if ((s = cn_ld_get_point(c, e, p, 3, out->axis))) return s;
        double n = cn_norm3(out->axis);
        if (!(n > 0) || !isfinite(n)) {
            /* rescale first: a valid direction written with huge components */
            double big = fmax(fabs(out->axis[0]), fmax(fabs(out->axis[1]), fabs(out->axis[2])));
            if (big > 0 && isfinite(big)) {
                cn_scale3(out->axis, 1.0 / big);
                n = cn_norm3(out->axis);
            }
        }
        if (!(n > 0)) return cn_ld_fail(c, p, "the axis has zero length; give its direction, e.g. [0, 0, 1]");
        cn_scale3(out->axis, 1.0 / n);
    }
    return CN_OK;
}

/* A path: 1 .. CN_MAX_PATH_SEGMENTS segments, each a displacement (an array of dim numbers) or
 * a turn (an object). */
cnStatus cn_ld_get_path(Ctx *c, const json_t *v, const char *path, int dim, cnSegment **segs,
                        int *n) {
    *segs = NULL;
    if (json_is_array(v) && json_array_size(v) > CN_MAX_PATH_SEGMENTS)
        return cn_ld_fail(c, path, "a path has at most %d segments, found %zu; merge collinear ones",
                          CN_MAX_PATH_SEGMENTS, json_array_size(v));
    if (!json_is_array(v))
        return cn_ld_fail(c, path, "expected a path: an array of points, found %s", cn_ld_type_name(v));
    int m = (int)json_array_size(v);
    if (m < 1) return cn_ld_fail(c, path, "a path needs at least 1 points, found 0");
    cnSegment *out = cn_calloc((size_t)m, sizeof(cnSegment));
    if (!out) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    for (int i = 0; i < m; i++) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "%s[%d]", path, i);
        const json_t *e = json_array_get(v, (size_t)i);
        cnStatus s = json_is_object(e) ? get_turn(c, e, p, dim, &out[i])
                                       : cn_ld_get_point(c, e, p, dim, out[i].move);
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
cnStatus cn_ld_check_turns(Ctx *c, const cnAssembly *a, const char *path, const int *parts,
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
            s = cn_ld_fail(c, p, "%.3g times the assembly's size away from it; a turn about so far a point "
                           "is a move to within rounding: give a displacement instead", far);
        }
    }
    if (!s) cn_path_length(a, parts, n, seg, nseg, len);
    for (int i = 0; i < nseg && !s; i++)
        if (seg[i].kind == CN_SEGMENT_TURN && !(len[i] > CN_TOL_LENGTH_ZERO * a->length_scale)) {
            snprintf(p, sizeof p, "%s[%d].rotate", path, i);
            s = cn_ld_fail(c, p, "the turn moves no point of the parts (%.3g degrees); remove it or turn further",
                           seg[i].angle * 180 / CN_PI);
        }
    cn_free(len);
    return s;
}

cnStatus cn_ld_get_points(Ctx *c, const json_t *v, const char *path, int dim, int min,
                          const char *what, double (**pts)[3], int *n) {
    *pts = NULL;
    if (!json_is_array(v))
        return cn_ld_fail(c, path, "expected %s: an array of points, found %s", what, cn_ld_type_name(v));
    int m = (int)json_array_size(v);
    if (m < min)
        return cn_ld_fail(c, path, "%s needs at least %d points, found %d", what, min, m);
    *pts = cn_calloc((size_t)m, sizeof **pts);
    if (!*pts) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    for (int i = 0; i < m; i++) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "%s[%d]", path, i);
        cnStatus s = cn_ld_get_place(c, json_array_get(v, (size_t)i), p, dim, (*pts)[i]);
        if (s) {
            cn_free(*pts);
            *pts = NULL;
            return s;
        }
    }
    *n = m;
    return CN_OK;
}

/* A part name or an array of names of parts that can move (not fixed, not already removed by an
 * earlier step), without repeats. `allowed` (may be NULL) restricts the names further. */
cnStatus cn_ld_get_part_list(Ctx *c, const json_t *v, const char *path, const cnAssembly *a,
                             const int *removed_by, int step, const int *allowed, int nallowed,
                             int **out, int *n) {
    char p[PATH_MAX_LEN];
    *out = NULL;
    *n = 0;
    int m = json_is_string(v) ? 1 : json_is_array(v) ? (int)json_array_size(v) : -1;
    if (m < 0) return cn_ld_fail(c, path, "expected a part name or an array of names, found %s", cn_ld_type_name(v));
    if (m == 0) return cn_ld_fail(c, path, "the list is empty; name at least one part");
    *out = cn_malloc(sizeof(int) * (size_t)m);
    if (!*out) return cn_diag_set(c->diag, CN_ERR_MEMORY, path, "out of memory");
    for (int i = 0; i < m; i++) {
        const json_t *e = json_is_string(v) ? v : json_array_get(v, (size_t)i);
        if (json_is_array(v)) snprintf(p, sizeof p, "%s[%d]", path, i);
        else snprintf(p, sizeof p, "%s", path);
        if (!json_is_string(e)) return cn_ld_fail(c, p, "expected a part name, found %s", cn_ld_type_name(e));
        const char *name = json_string_value(e);
        int k = cn_assembly_find_part(a, name);
        if (k < 0 || k >= a->nreal) return cn_ld_no_such_part(c, p, name, a);
        if (a->parts[k].fixed) return cn_ld_fail(c, p, "part '%s' is fixed; fixed parts never move", name);
        if (removed_by[k] >= 0 && removed_by[k] < step)
            return cn_ld_fail(c, p, "part '%s' was already removed by plan[%d]", name, removed_by[k]);
        for (int j = 0; j < *n; j++)
            if ((*out)[j] == k) return cn_ld_fail(c, p, "part '%s' is named twice", name);
        if (allowed) {
            int ok = 0;
            for (int j = 0; j < nallowed; j++) ok |= allowed[j] == k;
            if (!ok) return cn_ld_fail(c, p, "part '%s' is not one of the parts this step moves", name);
        }
        (*out)[(*n)++] = k;
    }
    return CN_OK;
}

cnStatus cn_ld_get_support(Ctx *c, const json_t *e, const char *p, int *out) {
    if (!json_is_string(e) || (strcmp(json_string_value(e), "hold") && strcmp(json_string_value(e), "push")))
        return cn_ld_fail(c, p, "must be \"hold\" (the gripper carries the weight) or \"push\" (it drives the part along the path only)");
    *out = strcmp(json_string_value(e), "push") ? CN_SUPPORT_HOLD : CN_SUPPORT_PUSH;
    return CN_OK;
}
