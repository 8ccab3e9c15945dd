/* Loading an assembly from JSON (jansson). Everything is validated here, once: unknown keys,
 * types, finite numbers, convexity, orientation, names, overlaps. Every message names its JSON
 * path (or line:column for syntax) and says what to do. */
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
#include "load_ctx.h"
#include "pieces.h"

/* The size of gravity cairn computes with (a verdict depends on its direction only). */
#define CN_GRAVITY_MIN 1e-100
#define CN_GRAVITY_MAX 1e100

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
        return cn_ld_fail(c, path, "expected a part object {\"name\": ..., shape}, found %s",
                          cn_ld_type_name(v));
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
            return cn_ld_fail(c, p, "'%s' is a %d-D shape but the assembly has dimension %d; use %s",
                              other[i], c->dim == 2 ? 3 : 2, c->dim,
                              c->dim == 2 ? "polygon or polygons" : "box, hull, hulls or mesh");
        }
    cnStatus s = cn_ld_check_keys(c, v, path, c->dim == 2 ? keys2 : keys3);
    if (s) return s;
    cnPart *part = &a->parts[index];
    part->gripper_step = -1;

    json_t *name = json_object_get(v, "name");
    snprintf(p, sizeof p, "%s.name", path);
    if (!name) return cn_ld_fail(c, p, "missing; every part needs a unique name");
    if (!json_is_string(name)) return cn_ld_fail(c, p, "expected a string, found %s", cn_ld_type_name(name));
    if (json_string_length(name) == 0) return cn_ld_fail(c, p, "the name is empty; give the part a name");
    if ((s = cn_ld_printable(c, json_string_value(name), p))) return s;
    /* (a NUL inside a name cannot get here: the JSON reader rejects \u0000) */
    json_t *seen = json_object_get(c->names, json_string_value(name));
    if (seen)
        return cn_ld_fail(c, p, "'%s' is already the name of parts[%d]; names must be unique",
                          json_string_value(name), (int)json_integer_value(seen));
    part->name = cn_strdup(json_string_value(name));
    if (!part->name || json_object_set_new(c->names, part->name, json_integer(index)) != 0)
        return cn_diag_set(c->diag, CN_ERR_MEMORY, p, "out of memory");

    json_t *fixed = json_object_get(v, "fixed");
    if (fixed) {
        snprintf(p, sizeof p, "%s.fixed", path);
        if (!json_is_boolean(fixed))
            return cn_ld_fail(c, p, "expected true or false, found %s", cn_ld_type_name(fixed));
        part->fixed = json_is_true(fixed);
    }

    s = cn_ld_load_shape(c, v, path, part);
    if (s) return s;
    cnPose pose;
    bool posed;
    if ((s = cn_ld_get_pose(c, v, path, &pose, &posed))) return s;
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
                return cn_ld_fail(c, path, "pieces %d and %d of the mesh '%s' (its objects, or the pieces "
                                  "of its split, in order) overlap by %.3g: the common region would count "
                                  "twice in the part's mass; make its objects only touch", pi, pj,
                                  part->mesh_file, depth);
            snprintf(p, sizeof p, "%s.%s[%d]", path, c->dim == 2 ? "polygons" : "hulls", pj);
            return cn_ld_fail(c, p, "overlaps piece %d of the same part by %.3g: the common region would "
                              "count twice in the part's mass; split the part into pieces that only touch",
                              pi, depth);
        }
    }

    double density = defdensity, mass = 0;
    json_t *d = json_object_get(v, "density"), *m = json_object_get(v, "mass");
    if (d && m)
        return cn_ld_fail(c, path, "give either \"density\" or \"mass\" for part '%s', not both",
                          part->name);
    if (d) {
        snprintf(p, sizeof p, "%s.density", path);
        s = cn_ld_get_positive(c, d, p, &density);
        if (s) return s;
    }
    if (m) {
        snprintf(p, sizeof p, "%s.mass", path);
        s = cn_ld_get_positive(c, m, p, &mass);
        if (s) return s;
    }
    cn_mass_part(part, c->dim, density, mass);
    if (!(part->size > 0) || !isfinite(part->mass) || !(part->mass > 0))
        return cn_ld_fail(c, path,
                          "part '%s' has no %s or its mass is not finite; check its density or mass "
                          "and the units of its coordinates",
                          part->name, c->dim == 2 ? "area" : "volume");
    double g = hypot(hypot(a->gravity[0], a->gravity[1]), a->gravity[2]);
    if (!isfinite(part->mass * g))
        return cn_ld_fail(c, path,
                          "part '%s' weighs more than a double holds (mass %g times gravity %g); scale "
                          "the masses or densities down (only their ratios change a verdict)",
                          part->name, part->mass, g);
    return CN_OK;
}

static cnStatus load_fixel(Ctx *c, const json_t *v, int index, cnAssembly *a) {
    char path[PATH_MAX_LEN], p[PATH_MAX_LEN];
    snprintf(path, sizeof path, "fixels[%d]", index);
    if (!json_is_object(v))
        return cn_ld_fail(c, path, "expected {\"part\": name, \"point\": [...], \"normal\": [...]}, "
                             "found %s",
                    cn_ld_type_name(v));
    static const char *const keys[] = {"part", "point", "normal", NULL};
    cnStatus s = cn_ld_check_keys(c, v, path, keys);
    if (s) return s;
    cnFixel *f = &a->fixels[index];
    json_t *part = json_object_get(v, "part");
    snprintf(p, sizeof p, "%s.part", path);
    if (!part) return cn_ld_fail(c, p, "missing; name the part the fixel holds");
    if (!json_is_string(part)) return cn_ld_fail(c, p, "expected a part name, found %s", cn_ld_type_name(part));
    f->part = cn_assembly_find_part(a, json_string_value(part));
    if (f->part < 0) return cn_ld_no_such_part(c, p, json_string_value(part), a);
    if (a->parts[f->part].fixed)
        return cn_ld_fail(c, p, "part '%s' is fixed; a fixel on a fixed part does nothing — remove it",
                          json_string_value(part));
    const char *names[2] = {"point", "normal"};
    double *dst[2] = {f->point, f->normal};
    for (int k = 0; k < 2; k++) {
        snprintf(p, sizeof p, "%s.%s", path, names[k]);
        json_t *e = json_object_get(v, names[k]);
        if (!e) return cn_ld_fail(c, p, "missing; a fixel needs a point and a normal");
        s = k == 0 ? cn_ld_get_place(c, e, p, a->dim, dst[k]) : cn_ld_get_point(c, e, p, a->dim, dst[k]);
        if (s) return s;
    }
    snprintf(p, sizeof p, "%s.normal", path);
    if (!(cn_normalize3(f->normal) > 0)) return cn_ld_fail(c, p, "the normal must not be zero");
    /* The point must be on the part's surface and the normal must push into the part. */
    const cnPart *pt = &a->parts[f->part];
    double dmin, din, dout, tol;
    cn_fixel_probe(a, f, &dmin, &din, &dout, &tol);
    snprintf(p, sizeof p, "%s.point", path);
    if (dmin > tol)
        return cn_ld_fail(c, p, "the point is %g away from part '%s'; a fixel must touch the part's "
                          "surface",
                    dmin, pt->name);
    if (dmin < -tol)
        return cn_ld_fail(c, p, "the point is %g inside part '%s'; a fixel must touch the part's "
                          "surface",
                    -dmin, pt->name);
    snprintf(p, sizeof p, "%s.normal", path);
    if (din > tol && dout > tol) /* both probes outside: the normal runs along the surface */
        return cn_ld_fail(c, p, "the normal must point into part '%s' (the direction the fixel pushes "
                          "it); it runs along the surface there",
                    pt->name);
    if (din <= tol && dout <= tol) { /* both probes in the part: between two of its pieces */
        snprintf(p, sizeof p, "%s.point", path);
        return cn_ld_fail(c, p, "the point is inside part '%s' (where two of its pieces meet), not on its "
                          "surface; a fixel must touch the part's surface",
                    pt->name);
    }
    if (din > tol || dout < -tol)
        return cn_ld_fail(c, p, "the normal must point into part '%s' (the direction the fixel pushes "
                          "it); flip its sign",
                    pt->name);
    return CN_OK;
}

static cnStatus load_pair(Ctx *c, const json_t *v, int index, cnAssembly *a) {
    char path[PATH_MAX_LEN], p[PATH_MAX_LEN];
    snprintf(path, sizeof path, "friction_pairs[%d]", index);
    if (!json_is_object(v))
        return cn_ld_fail(c, path, "expected {\"parts\": [name, name], \"mu\": number}, found %s",
                          cn_ld_type_name(v));
    static const char *const keys[] = {"parts", "mu", NULL};
    cnStatus s = cn_ld_check_keys(c, v, path, keys);
    if (s) return s;
    cnFrictionPair *fp = &a->pairs[index];
    json_t *parts = json_object_get(v, "parts");
    snprintf(p, sizeof p, "%s.parts", path);
    if (!parts) return cn_ld_fail(c, p, "missing; name the two parts");
    if (!json_is_array(parts) || json_array_size(parts) != 2)
        return cn_ld_fail(c, p, "expected an array of two part names");
    int idx[2];
    for (int k = 0; k < 2; k++) {
        json_t *e = json_array_get(parts, (size_t)k);
        snprintf(p, sizeof p, "%s.parts[%d]", path, k);
        if (!json_is_string(e)) return cn_ld_fail(c, p, "expected a part name, found %s", cn_ld_type_name(e));
        idx[k] = cn_assembly_find_part(a, json_string_value(e));
        if (idx[k] < 0) return cn_ld_no_such_part(c, p, json_string_value(e), a);
    }
    if (idx[0] == idx[1]) return cn_ld_fail(c, p, "the two parts must differ");
    fp->a = idx[0] < idx[1] ? idx[0] : idx[1];
    fp->b = idx[0] < idx[1] ? idx[1] : idx[0];
    for (int j = 0; j < index; j++)
        if (a->pairs[j].a == fp->a && a->pairs[j].b == fp->b) {
            snprintf(p, sizeof p, "%s.parts", path);
            return cn_ld_fail(c, p, "this pair already has a coefficient in friction_pairs[%d]", j);
        }
    json_t *mu = json_object_get(v, "mu");
    snprintf(p, sizeof p, "%s.mu", path);
    if (!mu) return cn_ld_fail(c, p, "missing; give the friction coefficient");
    s = cn_ld_get_number(c, mu, p, &fp->mu);
    if (s) return s;
    if (fp->mu < 0) return cn_ld_fail(c, p, "must be zero or positive, got %g", fp->mu);
    return CN_OK;
}


/* The file's settings: name, dimension, gravity, density, friction, friction directions,
 * tolerance. */
static cnStatus load_settings(Ctx *c, const json_t *root, cnAssembly *a) {
    cnStatus s;
    json_t *v = json_object_get(root, "name");
    if (v) {
        if (!json_is_string(v)) return cn_ld_fail(c, "name", "expected a string, found %s", cn_ld_type_name(v));
        if ((s = cn_ld_printable(c, json_string_value(v), "name"))) return s;
        a->name = cn_strdup(json_string_value(v));
    }
    v = json_object_get(root, "dimension");
    if (!v) return cn_ld_fail(c, "dimension", "missing; say \"dimension\": 2 or 3");
    if (!json_is_integer(v) || (json_integer_value(v) != 2 && json_integer_value(v) != 3))
        return cn_ld_fail(c, "dimension", "must be 2 or 3");
    a->dim = c->dim = (int)json_integer_value(v);

    a->gravity[0] = a->gravity[1] = a->gravity[2] = 0;
    a->gravity[a->dim - 1] = -9.81;
    v = json_object_get(root, "gravity");
    if (v) {
        s = cn_ld_get_point(c, v, "gravity", a->dim, a->gravity);
        if (s) return s;
        double gmax = fmax(fabs(a->gravity[0]), fmax(fabs(a->gravity[1]), fabs(a->gravity[2])));
        if (!(gmax > 0))
            return cn_ld_fail(c, "gravity", "must not be zero: stability under gravity needs gravity");
        /* squared in norms and multiplied by masses: outside this range the digits are lost to
         * underflow or overflow, while only gravity's direction changes a verdict */
        if (gmax < CN_GRAVITY_MIN || gmax > CN_GRAVITY_MAX)
            return cn_ld_fail(c, "gravity", "its size %g is outside the %g to %g cairn computes with; only "
                              "its direction changes a verdict (forces scale with it): scale it, e.g. to "
                              "9.81", gmax * hypot(hypot(a->gravity[0] / gmax, a->gravity[1] / gmax), a->gravity[2] / gmax),
                              CN_GRAVITY_MIN, CN_GRAVITY_MAX);
    }
    a->density = 1.0;
    v = json_object_get(root, "density");
    if (v && (s = cn_ld_get_positive(c, v, "density", &a->density))) return s;
    a->friction = 0.0;
    v = json_object_get(root, "friction");
    if (v) {
        if ((s = cn_ld_get_number(c, v, "friction", &a->friction))) return s;
        if (a->friction < 0) return cn_ld_fail(c, "friction", "must be zero or positive");
    }
    a->friction_dirs = a->dim == 2 ? 2 : CN_DEFAULT_FRICTION_DIRECTIONS;
    v = json_object_get(root, "friction_directions");
    if (v) {
        if (!json_is_integer(v))
            return cn_ld_fail(c, "friction_directions", "expected an integer, found %s", cn_ld_type_name(v));
        long long d = json_integer_value(v);
        if (a->dim == 2 && d != 2)
            return cn_ld_fail(c, "friction_directions", "2-D friction always uses 2 directions");
        if (a->dim == 3 && (d < 3 || d > CN_MAX_FRICTION_DIRECTIONS))
            return cn_ld_fail(c, "friction_directions", "must be from 3 to 64");
        a->friction_dirs = (int)d;
    }
    a->rel_tol = CN_DEFAULT_RELATIVE_TOLERANCE;
    v = json_object_get(root, "tolerance");
    if (v) {
        if ((s = cn_ld_get_number(c, v, "tolerance", &a->rel_tol))) return s;
        if (!(a->rel_tol >= 1e-12 && a->rel_tol <= 1e-1))
            return cn_ld_fail(c, "tolerance",
                              "the relative contact tolerance must be from 1e-12 to 0.1, got %g",
                              a->rel_tol);
    }

    return CN_OK;
}

/* The parts, numbered on from each other's vertices. */
static cnStatus load_parts(Ctx *c, const json_t *root, cnAssembly *a) {
    cnStatus s = CN_OK;
    json_t *v;
    c->rel_tol = a->rel_tol;
    v = json_object_get(root, "parts");
    if (!v) return cn_ld_fail(c, "parts", "missing; list the parts of the assembly");
    if (!json_is_array(v)) return cn_ld_fail(c, "parts", "expected an array, found %s", cn_ld_type_name(v));
    if (json_array_size(v) == 0) return cn_ld_fail(c, "parts", "the assembly has no parts");
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
    return CN_OK;
}

/* The assembly's size and contact tolerance; a part too small, too large or too far from the
 * origin for its digits is refused. */
static cnStatus load_scale(Ctx *c, cnAssembly *a) {
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
                return cn_ld_fail(c, p, "this part is %g across, outside the %g to %g cairn computes with (its "
                                  "volume and inertia would overflow or underflow): scale the file, e.g. to metres",
                                  size, CN_MIN_PART_SIZE, CN_MAX_PART_SIZE);
            }
            for (int k = 0; k < 3; k++) f = fmax(f, fmax(fabs(a->parts[i].lo[k]), fabs(a->parts[i].hi[k])));
            if (f > CN_MAX_FAR_RATIO * cn_norm3(e)) which = i, far = f, small = cn_norm3(e);
        }
        if (which >= 0) {
            char p[PATH_MAX_LEN];
            snprintf(p, sizeof p, "parts[%d]", which);
            return cn_ld_fail(c, p, "this part is %g across but reaches %g from the origin: "
                              "its coordinates keep fewer than 8 of its 16 digits; move the assembly "
                              "near the origin (a verdict does not depend on where it is)",
                              small, far);
        }
    }

    return CN_OK;
}

/* The friction pairs and the fixels. */
static cnStatus load_lists(Ctx *c, const json_t *root, cnAssembly *a) {
    cnStatus s;
    json_t *v;
    v = json_object_get(root, "friction_pairs");
    if (v) {
        if (!json_is_array(v))
            return cn_ld_fail(c, "friction_pairs", "expected an array, found %s", cn_ld_type_name(v));
        a->npairs = (int)json_array_size(v);
        a->pairs = cn_calloc((size_t)a->npairs + 1, sizeof(cnFrictionPair));
        if (!a->pairs) return cn_diag_oom(c->diag);
        for (int i = 0; i < a->npairs; i++)
            if ((s = load_pair(c, json_array_get(v, (size_t)i), i, a))) return s;
    }
    v = json_object_get(root, "fixels");
    if (v) {
        if (!json_is_array(v)) return cn_ld_fail(c, "fixels", "expected an array, found %s", cn_ld_type_name(v));
        a->nfixels = (int)json_array_size(v);
        a->fixels = cn_calloc((size_t)a->nfixels + 1, sizeof(cnFixel));
        if (!a->fixels) return cn_diag_oom(c->diag);
        for (int i = 0; i < a->nfixels; i++)
            if ((s = load_fixel(c, json_array_get(v, (size_t)i), i, a))) return s;
    }

    return CN_OK;
}

/* Overlapping parts are an input error: they cannot be at rest. */
static cnStatus check_overlaps(Ctx *c, cnAssembly *a) {
    cnStatus s;
    cnContactSet cs = {0};
    cnOverlap ov;
    s = cn_contacts_find(a, NULL, &cs, &ov, c->diag);
    cn_contacts_free(&cs);
    if (s) return s;
    if (ov.found) {
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "parts[%d]", ov.part2);
        return cn_ld_fail(c, p,
                          "part '%s' overlaps part '%s' (parts[%d]) by %.6g, more than the contact "
                          "tolerance %.3g (%g of the smaller part's size); parts at rest may touch but "
                          "not overlap: move them apart (or raise \"tolerance\" if this is modelling "
                          "noise)",
                          a->parts[ov.part2].name, a->parts[ov.part1].name, ov.part1, ov.depth,
                          ov.tol, a->rel_tol);
    }
    return CN_OK;
}

static cnStatus load_root(Ctx *c, const json_t *root, cnAssembly *a) {
    if (!json_is_object(root))
        return cn_ld_fail(c, "$", "the file must hold one JSON object, found %s", cn_ld_type_name(root));
    static const char *const keys[] = {"name",     "dimension",      "gravity",
                                       "density",  "friction",       "friction_pairs",
                                       "friction_directions", "tolerance", "parts",
                                       "fixels",   "plan", "simulation", "candidates",
                                       "candidate_support", NULL};
    cnStatus s = cn_ld_check_keys(c, root, "", keys);
    if (s) return s;

    if ((s = load_settings(c, root, a)) || (s = load_parts(c, root, a)) || (s = load_scale(c, a)) ||
        (s = load_lists(c, root, a)))
        return s;
    s = cn_ld_load_plan(c, root, a);
    if (s) return s;
    for (int i = a->nreal; i < a->nparts; i++) {
        const cnPart *q = &a->parts[i - 1];
        a->parts[i].vertex_base = q->vertex_base + numbers_of(q);
    }
    for (int i = 0; i < a->nparts; i++) a->parts[i].nnumbers = numbers_of(&a->parts[i]);
    if ((s = cn_ld_check_grippers(c, a))) return s;
    if ((s = cn_ld_load_candidates(c, root, a))) return s;

    return check_overlaps(c, a);
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
            return cn_diag_oom(diag);
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
        return cn_diag_oom(diag);
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
            return cn_diag_oom(diag);
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
