/* The builder: an assembly file's JSON document built call by call (jansson), loaded by the file
 * loader itself, so that what it accepts and how it says what is wrong are the file format's.
 * The only checks made here are those the document cannot carry: a non-finite number (JSON has
 * none), a missing name or point list, a piece with no part to join. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cairn/builder.h"
#include "core.h"

struct cnBuilder {
    json_t *root;
    json_t *last;     /* the part added last, or NULL */
    int dim;
    cnDiag err;       /* the first failure, replayed by cn_builder_finish */
};

cnBuilder *cn_builder_new(int dim) {
    cnBuilder *b = cn_calloc(1, sizeof *b);
    if (!b) return NULL;
    b->dim = dim;
    b->root = json_object();
    if (!b->root || json_object_set_new(b->root, "dimension", json_integer(dim)) ||
        json_object_set_new(b->root, "parts", json_array())) {
        json_decref(b->root);
        cn_free(b);
        return NULL;
    }
    cn_diag_clear(&b->err);
    /* every point is read as dim numbers: a bad dim is an error before anything is read */
    if (dim != 2 && dim != 3) cn_diag_set(&b->err, CN_ERR_INPUT, "dimension", "must be 2 or 3, got %d", dim);
    return b;
}

void cn_builder_free(cnBuilder *b) {
    if (!b) return;
    json_decref(b->root);
    cn_free(b);
}

void cn_string_free(char *s) { free(s); }

/* The first failure sticks: later calls return it and change nothing. */
#define GUARD(b)                                                  \
    do {                                                          \
        if (!(b)) return CN_ERR_INPUT;                            \
        if ((b)->err.code != CN_OK) return (b)->err.code;         \
    } while (0)

static cnStatus failed(cnBuilder *b, cnStatus code, const char *where, const char *what) {
    return cn_diag_set(&b->err, code, where, "%s", what);
}

static cnStatus nomem(cnBuilder *b, const char *where) {
    return failed(b, CN_ERR_MEMORY, where, "out of memory building the assembly");
}

/* The JSON path of the part added last, and of the next one. */
static void part_path(const cnBuilder *b, int offset, const char *key, char *out, size_t n) {
    size_t k = json_array_size(json_object_get(b->root, "parts"));
    snprintf(out, n, "parts[%zu]%s%s", k + (size_t)offset - 1, key ? "." : "", key ? key : "");
}

/* A number as JSON; NULL (with the failure set) when it is not finite. */
static json_t *number(cnBuilder *b, double v, const char *where) {
    if (!isfinite(v)) {
        failed(b, CN_ERR_INPUT, where, "not a finite number (JSON has no NaN or infinity); give a finite value");
        return NULL;
    }
    json_t *j = json_real(v);
    if (!j) nomem(b, where);
    return j;
}

/* n numbers as a JSON array; a bad one is named where[i], as the file's path would. */
static json_t *point(cnBuilder *b, const double *x, int n, const char *where) {
    json_t *a = json_array();
    if (!a) {
        nomem(b, where);
        return NULL;
    }
    for (int i = 0; i < n; i++) {
        char wi[160];
        snprintf(wi, sizeof wi, "%s[%d]", where, i);
        json_t *v = number(b, x[i], wi);
        if (!v || json_array_append_new(a, v)) {
            if (v && b->err.code == CN_OK) nomem(b, where);
            json_decref(a);
            return NULL;
        }
    }
    return a;
}

/* n points of `dim` coordinates each as a JSON array of arrays. */
static json_t *points(cnBuilder *b, int n, const double *x, const char *where) {
    if (n < 0 || (n > 0 && !x)) {
        failed(b, CN_ERR_INPUT, where, "no points given; pass the number of points and their coordinates");
        return NULL;
    }
    json_t *a = json_array();
    if (!a) {
        nomem(b, where);
        return NULL;
    }
    for (int i = 0; i < n; i++) {
        char wi[160];
        snprintf(wi, sizeof wi, "%s[%d]", where, i);
        json_t *p = point(b, x + (size_t)i * (size_t)b->dim, b->dim, wi);
        if (!p || json_array_append_new(a, p)) {
            if (p && b->err.code == CN_OK) nomem(b, where);
            json_decref(a);
            return NULL;
        }
    }
    return a;
}

/* A string as JSON; NULL (with the failure set) when it is missing or not UTF-8. */
static json_t *text(cnBuilder *b, const char *s, const char *where, const char *what) {
    if (!s) {
        failed(b, CN_ERR_INPUT, where, what);
        return NULL;
    }
    json_t *j = json_string(s);
    if (j) return j;
    j = json_string_nocheck(s); /* it failed: invalid UTF-8, or out of memory */
    if (j) {
        json_decref(j);
        failed(b, CN_ERR_INPUT, where, "not valid UTF-8 text; give names and titles in UTF-8");
    } else {
        nomem(b, where);
    }
    return NULL;
}

/* Set key on obj to v (taking v), or record why not. */
static cnStatus put(cnBuilder *b, json_t *obj, const char *key, json_t *v, const char *where) {
    if (!v) return b->err.code != CN_OK ? b->err.code : nomem(b, where);
    if (json_object_set_new(obj, key, v)) return nomem(b, where);
    return CN_OK;
}

static cnStatus put_number(cnBuilder *b, const char *key, double v) {
    GUARD(b);
    return put(b, b->root, key, number(b, v, key), key);
}

cnStatus cn_builder_set_name(cnBuilder *b, const char *name) {
    GUARD(b);
    return put(b, b->root, "name", text(b, name, "name", "no name given"), "name");
}

cnStatus cn_builder_set_gravity(cnBuilder *b, const double *g) {
    GUARD(b);
    if (!g) return failed(b, CN_ERR_INPUT, "gravity", "no vector given");
    return put(b, b->root, "gravity", point(b, g, b->dim, "gravity"), "gravity");
}

cnStatus cn_builder_set_friction(cnBuilder *b, double mu) { return put_number(b, "friction", mu); }
cnStatus cn_builder_set_density(cnBuilder *b, double density) { return put_number(b, "density", density); }
cnStatus cn_builder_set_tolerance(cnBuilder *b, double rel_tol) { return put_number(b, "tolerance", rel_tol); }

cnStatus cn_builder_set_friction_directions(cnBuilder *b, int n) {
    GUARD(b);
    return put(b, b->root, "friction_directions", json_integer(n), "friction_directions");
}

/* Append v (taken) to the root's array `key`, made when missing. */
static cnStatus append(cnBuilder *b, const char *key, json_t *v) {
    if (!v) return b->err.code != CN_OK ? b->err.code : nomem(b, key);
    json_t *arr = json_object_get(b->root, key);
    if (!arr) {
        arr = json_array();
        if (!arr || json_object_set_new(b->root, key, arr)) {
            json_decref(v);
            return nomem(b, key);
        }
    }
    if (json_array_append_new(arr, v)) return nomem(b, key);
    return CN_OK;
}

cnStatus cn_builder_set_pair_friction(cnBuilder *b, const char *a, const char *bname, double mu) {
    GUARD(b);
    char where[64];
    snprintf(where, sizeof where, "friction_pairs[%zu]", json_array_size(json_object_get(b->root, "friction_pairs")));
    char wn[96], wm[96];
    snprintf(wn, sizeof wn, "%s.parts", where);
    snprintf(wm, sizeof wm, "%s.mu", where);
    json_t *n1 = text(b, a, wn, "two part names are needed");
    json_t *n2 = n1 ? text(b, bname, wn, "two part names are needed") : NULL;
    json_t *m = n2 ? number(b, mu, wm) : NULL;
    if (!m) {
        json_decref(n1), json_decref(n2);
        return b->err.code;
    }
    return append(b, "friction_pairs", json_pack("{s:[o,o], s:o}", "parts", n1, n2, "mu", m));
}

/* A new part object with its name and fixed flag, appended; it becomes b->last. */
static cnStatus new_part(cnBuilder *b, const char *name, bool fixed, const char *key, json_t *shape) {
    char where[64];
    part_path(b, 1, NULL, where, sizeof where);
    if (!shape) return b->err.code != CN_OK ? b->err.code : nomem(b, where);
    char wn[96];
    snprintf(wn, sizeof wn, "%s.name", where);
    json_t *nm = text(b, name, wn, "no name given; every part needs a unique name");
    if (!nm) {
        json_decref(shape);
        return b->err.code;
    }
    json_t *p = json_pack("{s:o, s:b, s:o}", "name", nm, "fixed", fixed, key, shape);
    if (!p) return nomem(b, where);
    cnStatus s = append(b, "parts", json_incref(p));
    b->last = s == CN_OK ? p : NULL;
    json_decref(p);
    return s;
}

/* A shape of the other dimension: refused as the file loader would (before any point is read). */
static cnStatus wrong_dim(cnBuilder *b, const char *shape, int want) {
    if (b->dim == want) return CN_OK;
    char where[64];
    part_path(b, 1, shape, where, sizeof where);
    char what[160];
    snprintf(what, sizeof what, "'%s' is a %d-D shape but the assembly has dimension %d; use %s", shape, want,
             b->dim, b->dim == 2 ? "cn_builder_add_polygon" : "cn_builder_add_box or cn_builder_add_hull");
    return failed(b, CN_ERR_INPUT, where, what);
}

cnStatus cn_builder_add_polygon(cnBuilder *b, const char *name, int n, const double *xy, bool fixed) {
    GUARD(b);
    if (wrong_dim(b, "polygon", 2)) return b->err.code;
    char where[64];
    part_path(b, 1, "polygon", where, sizeof where);
    return new_part(b, name, fixed, "polygon", points(b, n, xy, where));
}

cnStatus cn_builder_add_hull(cnBuilder *b, const char *name, int n, const double *xyz, bool fixed) {
    GUARD(b);
    if (wrong_dim(b, "hull", 3)) return b->err.code;
    char where[64];
    part_path(b, 1, "hull", where, sizeof where);
    return new_part(b, name, fixed, "hull", points(b, n, xyz, where));
}

cnStatus cn_builder_add_box(cnBuilder *b, const char *name, const double lo[3], const double hi[3], bool fixed) {
    GUARD(b);
    if (wrong_dim(b, "box", 3)) return b->err.code;
    char where[64], wmin[80], wmax[80];
    part_path(b, 1, "box", where, sizeof where);
    snprintf(wmin, sizeof wmin, "%s.min", where);
    snprintf(wmax, sizeof wmax, "%s.max", where);
    if (!lo || !hi) return failed(b, CN_ERR_INPUT, where, "give both corners, min and max");
    json_t *mn = point(b, lo, 3, wmin), *mx = mn ? point(b, hi, 3, wmax) : NULL;
    if (!mn || !mx) {
        json_decref(mn);
        return b->err.code != CN_OK ? b->err.code : nomem(b, where);
    }
    return new_part(b, name, fixed, "box", json_pack("{s:o, s:o}", "min", mn, "max", mx));
}

cnStatus cn_builder_add_piece(cnBuilder *b, int n, const double *pts) {
    GUARD(b);
    const char *one = b->dim == 2 ? "polygon" : "hull", *many = b->dim == 2 ? "polygons" : "hulls";
    char where[64];
    part_path(b, 0, many, where, sizeof where);
    if (!b->last) return failed(b, CN_ERR_INPUT, "parts", "a piece needs a part to join: add a part first");
    json_t *list = json_object_get(b->last, many);
    if (!list) {
        json_t *first = json_object_get(b->last, one);
        if (!first) return failed(b, CN_ERR_INPUT, where, "this part is a box; a box cannot take more pieces (give it as a hull instead)");
        list = json_array();
        if (!list) return nomem(b, where);
        if (json_array_append(list, first)) {
            json_decref(list);
            return nomem(b, where);
        }
        if (json_object_set_new(b->last, many, list)) return nomem(b, where); /* list freed by it */
        json_object_del(b->last, one);
    }
    char wp[96];
    snprintf(wp, sizeof wp, "%s[%zu]", where, json_array_size(list));
    json_t *p = points(b, n, pts, wp);
    if (!p) return b->err.code;
    if (json_array_append_new(list, p)) return nomem(b, where);
    return CN_OK;
}

static cnStatus part_number(cnBuilder *b, const char *key, double v) {
    GUARD(b);
    char where[64];
    part_path(b, 0, key, where, sizeof where);
    if (!b->last) return failed(b, CN_ERR_INPUT, "parts", "no part yet: add a part first");
    return put(b, b->last, key, number(b, v, where), where);
}

cnStatus cn_builder_set_part_density(cnBuilder *b, double density) { return part_number(b, "density", density); }
cnStatus cn_builder_set_part_mass(cnBuilder *b, double mass) { return part_number(b, "mass", mass); }

cnStatus cn_builder_set_part_pose(cnBuilder *b, const cnPose *pose) {
    GUARD(b);
    char where[64];
    part_path(b, 0, "rotation", where, sizeof where);
    if (!b->last) return failed(b, CN_ERR_INPUT, "parts", "no part yet: add a part first");
    if (!pose) return failed(b, CN_ERR_INPUT, where, "no pose given");
    json_t *rot;
    if (b->dim == 2) {
        if (pose->q[1] != 0 || pose->q[2] != 0)
            return failed(b, CN_ERR_INPUT, where, "a 2-D part turns about z only: q = (cos a/2, 0, 0, sin a/2)");
        rot = number(b, 2 * atan2(pose->q[3], pose->q[0]) * 180.0 / CN_PI, where);
    } else {
        char wq[96];
        snprintf(wq, sizeof wq, "%s.quaternion", where);
        json_t *q = point(b, pose->q, 4, wq);
        rot = q ? json_pack("{s:o}", "quaternion", q) : NULL;
    }
    cnStatus s = put(b, b->last, "rotation", rot, where);
    if (s) return s;
    part_path(b, 0, "position", where, sizeof where);
    return put(b, b->last, "position", point(b, pose->t, b->dim, where), where);
}

cnStatus cn_builder_add_fixel(cnBuilder *b, const char *part, const double *pt, const double *normal) {
    GUARD(b);
    char where[64];
    snprintf(where, sizeof where, "fixels[%zu]", json_array_size(json_object_get(b->root, "fixels")));
    if (!part || !pt || !normal) return failed(b, CN_ERR_INPUT, where, "give the part's name, a point and a normal");
    char wpart[96], wpt[96], wn[96];
    snprintf(wpart, sizeof wpart, "%s.part", where);
    snprintf(wpt, sizeof wpt, "%s.point", where);
    snprintf(wn, sizeof wn, "%s.normal", where);
    json_t *nm = text(b, part, wpart, "no part named");
    json_t *p = nm ? point(b, pt, b->dim, wpt) : NULL, *n = p ? point(b, normal, b->dim, wn) : NULL;
    if (!nm || !p || !n) {
        json_decref(nm), json_decref(p);
        return b->err.code != CN_OK ? b->err.code : nomem(b, where);
    }
    return append(b, "fixels", json_pack("{s:o, s:o, s:o}", "part", nm, "point", p, "normal", n));
}

/* One path segment as the file writes it: a displacement, or {"rotate": deg, "about", "axis"}. */
static json_t *segment(cnBuilder *b, const cnSegment *s, const char *where) {
    if (s->kind == CN_SEGMENT_MOVE) return point(b, s->move, b->dim, where);
    if (s->kind != CN_SEGMENT_TURN) {
        failed(b, CN_ERR_INPUT, where, "a segment is CN_SEGMENT_MOVE or CN_SEGMENT_TURN");
        return NULL;
    }
    json_t *deg = number(b, s->angle * 180.0 / CN_PI, where);
    json_t *about = deg ? point(b, s->about, b->dim, where) : NULL;
    json_t *axis = about && b->dim == 3 ? point(b, s->axis, 3, where) : NULL;
    if (!deg || !about || (b->dim == 3 && !axis)) {
        json_decref(deg), json_decref(about);
        return NULL;
    }
    json_t *t = json_pack("{s:o, s:o}", "rotate", deg, "about", about);
    if (t && axis && json_object_set_new(t, "axis", axis)) {
        json_decref(t);
        return NULL;
    }
    if (!t) json_decref(axis);
    return t;
}

cnStatus cn_builder_add_step(cnBuilder *b, int nmove, const char *const *move, int nseg,
                             const cnSegment *seg, cnSupport support) {
    GUARD(b);
    char where[64], sw[96];
    snprintf(where, sizeof where, "plan[%zu]", json_array_size(json_object_get(b->root, "plan")));
    if (nmove < 1 || !move) return failed(b, CN_ERR_INPUT, where, "a step moves at least one part: name it");
    if (nseg < 0 || (nseg > 0 && !seg)) return failed(b, CN_ERR_INPUT, where, "no segments given for the path");
    if (support != CN_SUPPORT_HOLD && support != CN_SUPPORT_PUSH) {
        snprintf(sw, sizeof sw, "%s.support", where);
        return failed(b, CN_ERR_INPUT, sw, "must be CN_SUPPORT_HOLD or CN_SUPPORT_PUSH");
    }
    json_t *step = json_object(), *names = json_array();
    if (!step || !names || json_object_set_new(step, "move", names)) {
        json_decref(step);
        if (step) return nomem(b, where);
        json_decref(names);
        return nomem(b, where);
    }
    for (int i = 0; i < nmove; i++) {
        snprintf(sw, sizeof sw, "%s.move[%d]", where, i);
        json_t *nm = text(b, move[i], sw, "no name given");
        if (!nm || json_array_append_new(names, nm)) {
            json_decref(step);
            return b->err.code != CN_OK ? b->err.code : nomem(b, sw);
        }
    }
    if (nseg > 0) {
        json_t *path = json_array();
        if (!path || json_object_set_new(step, "path", path)) {
            json_decref(step);
            return nomem(b, where);
        }
        for (int i = 0; i < nseg; i++) {
            snprintf(sw, sizeof sw, "%s.path[%d]", where, i);
            json_t *j = segment(b, &seg[i], sw);
            if (!j || json_array_append_new(path, j)) {
                json_decref(step);
                return b->err.code != CN_OK ? b->err.code : nomem(b, sw);
            }
        }
    }
    if (support == CN_SUPPORT_PUSH && json_object_set_new(step, "support", json_string("push"))) {
        json_decref(step);
        return nomem(b, where);
    }
    return append(b, "plan", step);
}

cnStatus cn_builder_set_simulation(cnBuilder *b, double dt, double speed) {
    GUARD(b);
    json_t *sim = json_object();
    if (!sim) return nomem(b, "simulation");
    if ((dt != 0 && put(b, sim, "dt", number(b, dt, "simulation.dt"), "simulation.dt")) ||
        (speed != 0 && put(b, sim, "speed", number(b, speed, "simulation.speed"), "simulation.speed"))) {
        json_decref(sim);
        return b->err.code;
    }
    return put(b, b->root, "simulation", sim, "simulation");
}

char *cn_builder_json(const cnBuilder *b) {
    if (!b) return NULL;
    return json_dumps(b->root, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(17));
}

cnStatus cn_builder_finish(const cnBuilder *b, cnAssembly **out, cnDiag *diag) {
    cn_diag_clear(diag);
    *out = NULL;
    if (!b) return cn_diag_set(diag, CN_ERR_INPUT, "", "no builder given");
    if (b->err.code != CN_OK) {
        if (diag) *diag = b->err;
        return b->err.code;
    }
    char *text = json_dumps(b->root, JSON_COMPACT | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(17));
    if (!text) return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the assembly");
    cnStatus s = cn_assembly_load_string(text, "<builder>", out, diag);
    free(text);
    return s;
}
