/* Reports of contacts and of a check, as text or JSON (jansson). */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json_out.h"
#include "cairn/report.h"

/* Values closer to zero than this fraction of their scale print as 0, so round-off noise does
 * not show up as -1.2e-17 in reports (and output is stable across builds). */
#define REPORT_ZERO CN_TOL_PRINT_ZERO

double cn_report_clean(double v, double scale) { return fabs(v) <= REPORT_ZERO * scale ? 0.0 : v; }
static double clean(double v, double scale) { return cn_report_clean(v, scale); }

static const char *kind_name(cnContactKind k, int dim) {
    switch (k) {
    case CN_CONTACT_VERTEX: return "vertex";
    case CN_CONTACT_EDGE: return dim == 2 ? "edge-edge" : "edge";
    case CN_CONTACT_FACE: return "face-face";
    case CN_CONTACT_FIXEL: return "fixel";
    }
    return "?";
}

static void body_name(const cnAssembly *a, const cnContact *c, int which, char *buf, size_t n) {
    int b = which ? c->body2 : c->body1;
    if (b == CN_WORLD) snprintf(buf, n, "fixel[%d]", c->fixel);
    else snprintf(buf, n, "%s", a->parts[b].name);
}

static json_t *vec(const double *v, int dim, double scale) {
    json_t *arr = json_array();
    for (int k = 0; k < dim; k++) json_array_append_new(arr, json_real(clean(v[k], scale)));
    return arr;
}

cnStatus cn_json_write(FILE *f, void *json, int precision) {
    json_t *o = json;
    /* "format_version" first, then the report's keys in their order */
    json_t *doc = o;
    if (json_is_object(o)) {
        doc = json_object();
        bool ok = doc && !json_object_set_new(doc, "format_version", json_integer(CN_JSON_FORMAT_VERSION)) &&
                  !json_object_update(doc, o);
        json_decref(o);
        if (!ok) {
            json_decref(doc);
            return CN_ERR_MEMORY;
        }
    }
    char *s = json_dumps(doc, JSON_INDENT(2) | JSON_REAL_PRECISION(precision));
    json_decref(doc);
    if (!s) return CN_ERR_MEMORY;
    fprintf(f, "%s\n", s);
    free(s);
    return CN_OK;
}

/* A vector as an array of cleaned reals (the non-finite ones left out, as jansson does). */
static void stream_vec(cnJsonStream *s, const double *v, int dim, double scale) {
    unsigned k0 = cn_json_stream_open(s, false);
    for (int k = 0; k < dim; k++) {
        double x = clean(v[k], scale);
        if (cn_json_stream_real_ok(x)) cn_json_stream_real(s, x);
    }
    cn_json_stream_close(s, k0);
}

static void stream_real_key(cnJsonStream *s, const char *key, double v) {
    if (!cn_json_stream_real_ok(v)) return;
    cn_json_stream_key(s, key);
    cn_json_stream_real(s, v);
}

/* The keys every contact record starts with (id, parts, kind, point, normal and, at a corner on
 * a corner, its other normal), into an open object. */
static void stream_contact_head(cnJsonStream *s, const cnAssembly *a, const cnContact *c) {
    int dim = a->dim;
    char fixel[32];
    cn_json_stream_key(s, "id");
    cn_json_stream_int(s, c->id);
    cn_json_stream_key(s, "parts");
    unsigned k2 = cn_json_stream_open(s, false);
    for (int which = 0; which < 2; which++) {
        int b = which ? c->body2 : c->body1;
        if (b == CN_WORLD) snprintf(fixel, sizeof fixel, "fixel[%d]", c->fixel);
        cn_json_stream_string(s, b == CN_WORLD ? fixel : a->parts[b].name);
    }
    cn_json_stream_close(s, k2);
    cn_json_stream_key(s, "kind");
    cn_json_stream_string(s, kind_name(c->kind, dim));
    cn_json_stream_key(s, "point");
    stream_vec(s, c->point, dim, a->length_scale);
    cn_json_stream_key(s, "normal");
    stream_vec(s, c->normal, dim, 1.0);
    if (c->corner) {
        cn_json_stream_key(s, "corner_alt_normal");
        stream_vec(s, c->alt_normal, dim, 1.0);
        if (c->corner_ends > 2) { /* a 3-D vertex's cone: its other ends */
            cn_json_stream_key(s, "corner_more_normals");
            unsigned k3 = cn_json_stream_open(s, false);
            for (int e = 0; e < c->corner_ends - 2; e++) stream_vec(s, c->more_normals[e], dim, 1.0);
            cn_json_stream_close(s, k3);
        }
        if (c->corner_wide) { /* more ends than were kept: a check cannot call it stable */
            cn_json_stream_key(s, "corner_cone_cut");
            cn_json_stream_bool(s, true);
        }
    }
}

/* A check's contacts, streamed: each record's head, then its forces and state. */
typedef struct {
    const cnAssembly *a;
    const cnCheckResult *r;  /* a check's contacts and forces, or */
    const cnContactSet *cs;  /* the contacts alone */
} CheckContacts;

static void check_contacts(cnJsonStream *s, void *ctx) {
    const CheckContacts *x = ctx;
    const cnAssembly *a = x->a;
    const cnCheckResult *r = x->r;
    double W = r->ref_weight;
    int dim = a->dim;
    unsigned k0 = cn_json_stream_open(s, false);
    for (int i = 0; i < r->contacts.count; i++) {
        const cnContact *c = &r->contacts.items[i];
        const cnContactResult *cr = &r->contact[i];
        unsigned k1 = cn_json_stream_open(s, true);
        stream_contact_head(s, a, c);
        stream_real_key(s, "force", clean(cr->normal_force, W));
        stream_real_key(s, "force_normalized", clean(cr->normal_force / W, 1));
        if (r->friction) {
            cn_json_stream_key(s, "friction");
            stream_vec(s, cr->friction, dim, W);
        }
        cn_json_stream_key(s, "separates");
        cn_json_stream_bool(s, cr->separates);
        cn_json_stream_key(s, "slides");
        cn_json_stream_bool(s, cr->slides);
        cn_json_stream_close(s, k1);
    }
    cn_json_stream_close(s, k0);
}

/* The contacts of `cairn contacts`, streamed: each record's head, then its gap. */
static void found_contacts(cnJsonStream *s, void *ctx) {
    const CheckContacts *x = ctx;
    const cnAssembly *a = x->a;
    const cnContactSet *cs = x->cs;
    unsigned k0 = cn_json_stream_open(s, false);
    for (int i = 0; i < cs->count; i++) {
        unsigned k1 = cn_json_stream_open(s, true);
        stream_contact_head(s, a, &cs->items[i]);
        stream_real_key(s, "gap", clean(cs->items[i].gap, a->length_scale));
        cn_json_stream_close(s, k1);
    }
    cn_json_stream_close(s, k0);
}

static void fmt_vec(char *buf, size_t n, const double *v, int dim, double scale) {
    if (dim == 2) snprintf(buf, n, "(%.4g, %.4g)", clean(v[0], scale), clean(v[1], scale));
    else
        snprintf(buf, n, "(%.4g, %.4g, %.4g)", clean(v[0], scale), clean(v[1], scale),
                 clean(v[2], scale));
}

/* Overlaps accepted as contacts are told in the text from this fraction of the smaller part's
 * size on (below it they are the rounding of coordinates that touch). */
#define CN_OVERLAP_SHOWN 1e-9

/* The deepest overlap accepted as contact (a negative gap within the tolerance): its index in
 * the contacts, or -1 when no two parts overlap; *rel: its depth over the smaller part's size. */
static int deepest_overlap(const cnAssembly *a, const cnContactSet *cs, double *rel) {
    int best = -1;
    *rel = 0;
    for (int i = 0; i < cs->count; i++) {
        const cnContact *c = &cs->items[i];
        if (c->body1 < 0 || !(c->gap < 0)) continue;
        double d1[3], d2[3];
        cn_sub3(a->parts[c->body1].hi, a->parts[c->body1].lo, d1);
        cn_sub3(a->parts[c->body2].hi, a->parts[c->body2].lo, d2);
        double r = -c->gap / fmin(cn_norm3(d1), cn_norm3(d2));
        if (r > *rel) *rel = r, best = i;
    }
    return best;
}

/* A line per part read from a mesh file: its pieces, and how many the decomposition made. */
static void mesh_text(FILE *f, const cnAssembly *a) {
    for (int i = 0; i < a->nparts; i++) {
        const cnPart *p = &a->parts[i];
        if (!p->mesh_file) continue;
        fprintf(f, "part '%s': mesh '%s', %d convex piece%s", p->name, p->mesh_file, p->npieces,
                p->npieces == 1 ? "" : "s");
        if (p->mesh_split) fprintf(f, " (%d made by the exact convex decomposition of a non-convex mesh)", p->mesh_split);
        fprintf(f, "\n");
    }
}

static json_t *mesh_json(const cnAssembly *a) {
    json_t *arr = json_array();
    for (int i = 0; i < a->nparts; i++) {
        const cnPart *p = &a->parts[i];
        if (!p->mesh_file) continue;
        json_t *o = json_object();
        json_object_set_new(o, "part", json_string(p->name));
        json_object_set_new(o, "file", json_string(p->mesh_file));
        json_object_set_new(o, "pieces", json_integer(p->npieces));
        json_object_set_new(o, "pieces_from_decomposition", json_integer(p->mesh_split));
        json_array_append_new(arr, o);
    }
    return arr;
}

/* The count of a check's readings of its corner contacts: exact up to 2^49, else as a power of
 * two (2^k when every cone has two ends, else to one decimal of the exponent). */
static void readings_text(const cnCheckResult *r, char *buf, size_t n) {
    double l = r->corners.readings_log2;
    if (l < 49.5) snprintf(buf, n, "%.0f", r->corners.readings_all);
    else if (l == floor(l)) snprintf(buf, n, "2^%.0f", l);
    else snprintf(buf, n, "about 2^%.1f", l);
}

/* The lines on corner-on-corner contacts of a check (none when there are none). */
static void corner_text(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    if (r->corners.implied > 0)
        fprintf(f, "corner on corner: %d contact%s left out, implied by contacts of the same parts at the same "
                   "point (a corner seated against two faces)\n",
                r->corners.implied, r->corners.implied == 1 ? "" : "s");
    if (r->corners.count <= 0) return;
    double total = r->corners.readings_all;
    char all[32], done[64];
    readings_text(r, all, sizeof all);
    if (r->corners.by_field) snprintf(done, sizeof done, "all %s", all);
    else snprintf(done, sizeof done, "%ld of %s", r->corners.readings, all);
    fprintf(f, "corner on corner: %d contact%s without a normal of %s own (the parts may part along "
               "any motion that one end of the cone of normals allows); %s reading%s "
               "decided%s\n",
            r->corners.count, r->corners.count == 1 ? "" : "s", r->corners.count == 1 ? "its" : "their",
            done, total == 1 ? "" : "s",
            r->corners.disagree ? ": one stands and another moves (a knife edge)"
            : r->verdict == CN_VERDICT_UNSTABLE && r->corners.readings < total
                ? ": a motion starts in the first, so the assembly is not stable in any case; whether "
                  "another reading stands (which would make it not guaranteed) was not tried"
            : r->verdict == CN_VERDICT_UNDECIDED && !r->corners.undecided && r->corners.readings < total
                ? " (the first undecided, so the others were not tried: the assembly cannot be proved "
                  "stable in all of them)"
            : r->corners.by_field && r->proof == CN_PROOF_ACCEPTED
                ? ": all stand weakly, a static solution not using those contacts (prestress accepted)"
            : r->corners.by_field ? ": all stand, a frictionless force field balancing gravity without "
                                    "those contacts"
                                  : "");
    if (r->corners.reading >= 0 && r->corners.reading_moves >= 0)
        fprintf(f, "  shown: the forces of reading %lld, which stands, and the motion of reading %lld (cairn "
                   "check --reading K decides one alone)\n",
                r->corners.reading, r->corners.reading_moves);
    else if (r->corners.reading >= 0)
        fprintf(f, "  shown: reading %lld (cairn check --reading %lld decides it alone)\n", r->corners.reading,
                r->corners.reading);
    for (int i = 0; i < r->contacts.count; i++) {
        const cnContact *c = &r->contacts.items[i];
        if (!c->corner) continue;
        char n1[80], n2[80];
        fmt_vec(n1, sizeof n1, c->normal, a->dim, 1.0);
        fmt_vec(n2, sizeof n2, c->alt_normal, a->dim, 1.0);
        if (c->corner_ends <= 2) {
            fprintf(f, "  contact %d: normal anywhere from %s (shown) to %s\n", c->id, n1, n2);
            continue;
        }
        fprintf(f, "  contact %d: normal anywhere in the cone spanned by %s (shown), %s", c->id, n1, n2);
        for (int e = 0; e < c->corner_ends - 2; e++) {
            fmt_vec(n2, sizeof n2, c->more_normals[e], a->dim, 1.0);
            fprintf(f, "%s %s", e == c->corner_ends - 3 ? " and" : ",", n2);
        }
        fprintf(f, "%s\n", c->corner_wide ? ", and more ends that were not kept" : "");
    }
}

cnStatus cn_report_contacts(FILE *f, const cnAssembly *a, const cnContactSet *cs, int json) {
    if (json) {
        json_t *o = json_object();
        json_object_set_new(o, "dimension", json_integer(a->dim));
        json_object_set_new(o, "relative_tolerance", json_real(a->rel_tol));
        json_object_set_new(o, "contacts", json_null()); /* its place: written by found_contacts */
        CheckContacts ctx = {a, NULL, cs};
        return cn_json_write_streamed(f, o, 10, "contacts", found_contacts, &ctx);
    }
    fprintf(f, "%d contact%s (tolerance %.3g of the smaller part's size)\n", cs->count,
            cn_plural(cs->count), a->rel_tol);
    fprintf(f, "%4s  %-24s %-10s %-26s %-22s\n", "id", "parts", "kind", "point", "normal");
    for (int i = 0; i < cs->count; i++) {
        const cnContact *c = &cs->items[i];
        char n1[128], n2[128], pair[260], p[80], nv[80];
        body_name(a, c, 0, n1, sizeof n1);
        body_name(a, c, 1, n2, sizeof n2);
        snprintf(pair, sizeof pair, "%s / %s", n1, n2);
        fmt_vec(p, sizeof p, c->point, a->dim, a->length_scale);
        fmt_vec(nv, sizeof nv, c->normal, a->dim, 1.0);
        if (c->corner) /* no normal of its own: the one shown is an end of its cone */
            fprintf(f, "%4d  %-24s %-10s %-26s %s, or another end of its cone (%d ends%s)\n", c->id,
                    pair, kind_name(c->kind, a->dim), p, nv, c->corner_ends,
                    c->corner_wide ? ", more not kept" : "");
        else
            fprintf(f, "%4d  %-24s %-10s %-26s %-22s\n", c->id, pair, kind_name(c->kind, a->dim), p,
                    nv);
    }
    return CN_OK;
}

const char *cn_verdict_word(cnVerdict v) {
    switch (v) {
    case CN_VERDICT_STABLE: return "stable";
    case CN_VERDICT_UNSTABLE: return "unstable";
    case CN_VERDICT_NOT_GUARANTEED: return "not_guaranteed";
    default: return "undecided";
    }
}

static const char *proof_name(cnProof p) {
    switch (p) {
    case CN_PROOF_FRICTIONLESS: return "frictionless_field";
    case CN_PROOF_SEARCH: return "search";
    case CN_PROOF_ACCEPTED: return "accepted_prestress";
    case CN_PROOF_UNDECIDED: return "none_search_undecided";
    default: return NULL;
    }
}

static const char *turn_name(double w) { return w > 0 ? "counter-clockwise" : "clockwise"; }

/* The paper's own test agrees with the static solution: the LCP's solution by Lemke's method does
 * not move (its forces are the ones reported). */
static bool lemke_static(const cnCheckResult *r) { return r->solver.forces_from == CN_FORCES_LEMKE; }

/* The JSON name of why a check gave no verdict. */
static const char *undecided_name(cnUndecided why) {
    switch (why) {
    case CN_UNDECIDED_NO: return "none";
    case CN_UNDECIDED_BUDGET: return "budget";
    case CN_UNDECIDED_TIME: return "time";
    case CN_UNDECIDED_TOO_LARGE: return "too_large";
    case CN_UNDECIDED_THRESHOLD: return "threshold";
    case CN_UNDECIDED_SOLVER: return "solver";
    case CN_UNDECIDED_MEMORY: return "memory";
    case CN_UNDECIDED_CORNERS: return "corners";
    case CN_UNDECIDED_CORNERS_WIDE: return "corners_wide";
    }
    return "none";
}

/* The name of a contact's part (a fixel's "world"). */
static const char *contact_part(const cnAssembly *a, int part) {
    return part >= 0 && part < a->nparts ? a->parts[part].name : "world";
}

/* Is contact c the first unsettled one between its two parts (either way round)? */
static bool first_unsettled_joint(const cnCheckResult *r, int c) {
    const cnContact *x = &r->contacts.items[c];
    for (int d = 0; d < c; d++) {
        const cnContact *y = &r->contacts.items[d];
        if (r->contact[d].unsettled && ((y->body1 == x->body1 && y->body2 == x->body2) ||
                                        (y->body1 == x->body2 && y->body2 == x->body1)))
            return false;
    }
    return true;
}

/* check --json: the parts that move and how, and what an undecided search left open. */
static void check_json_motion(json_t *o, const cnAssembly *a, const cnCheckResult *r) {
    double g = cn_norm3(a->gravity);
    int dim = a->dim;
    json_t *mv = json_array(), *motion = json_array();
    for (int i = 0; i < r->nmoving; i++) {
        int p = r->moving[i];
        json_array_append_new(mv, json_string(a->parts[p].name));
        json_t *m = json_object();
        json_object_set_new(m, "part", json_string(a->parts[p].name));
        json_object_set_new(m, "linear", vec(r->part[p].lin, dim, g));
        if (dim == 2) json_object_set_new(m, "angular", json_real(clean(r->part[p].ang[2], g / a->length_scale)));
        else json_object_set_new(m, "angular", vec(r->part[p].ang, 3, g / a->length_scale));
        json_array_append_new(motion, m);
    }
    json_object_set_new(o, "moving_parts", mv);
    json_object_set_new(o, "motion", motion);
    if (r->verdict == CN_VERDICT_UNDECIDED) {
        /* what the search left open: the parts its open motions move, and their speed bound */
        json_t *u = json_object(), *up = json_array();
        json_object_set_new(u, "reason", json_string(undecided_name(r->undecided)));
        json_object_set_new(u, "why", json_string(cn_undecided_text(r->undecided)));
        for (int p = 0; p < a->nparts && r->part; p++)
            if (r->part[p].unsettled) json_array_append_new(up, json_string(a->parts[p].name));
        json_object_set_new(u, "parts", up);
        /* the contacts whose complementarity the open nodes leave unresolved, and their joints
           (the pairs of parts they join) */
        json_t *uc = json_array(), *uj = json_array();
        for (int c = 0; c < r->contacts.count && r->contact; c++) {
            if (!r->contact[c].unsettled) continue;
            json_array_append_new(uc, json_integer(r->contacts.items[c].id));
            if (!first_unsettled_joint(r, c)) continue;
            json_t *j = json_array();
            json_array_append_new(j, json_string(contact_part(a, r->contacts.items[c].body1)));
            json_array_append_new(j, json_string(contact_part(a, r->contacts.items[c].body2)));
            json_array_append_new(uj, j);
        }
        json_object_set_new(u, "contacts", uc);
        json_object_set_new(u, "joints", uj);
        json_object_set_new(u, "max_speed", isfinite(r->open_speed) ? json_real(r->open_speed) : json_null());
        json_object_set_new(u, "lemke_static", json_boolean(lemke_static(r)));
        json_object_set_new(o, "undecided", u);
    }
}

/* check --json: the solver's report and the corner contacts' readings. */
static void check_json_solver(json_t *o, const cnCheckResult *r) {
    json_t *s = json_object();
    json_object_set_new(s, "forces_from", json_string(cn_forces_from_name(r->solver.forces_from)));
    json_object_set_new(s, "lcp_size", json_integer(r->solver.lcp_size));
    json_object_set_new(s, "pivots", json_integer(r->solver.pivots));
    json_object_set_new(s, "residual", json_real(r->solver.residual));
    json_object_set_new(s, "lp_stable", json_boolean(r->solver.lp_stable));
    const char *lp_method = cn_lp_method_name(r->solver.lp_method);
    json_object_set_new(s, "lp_method", lp_method ? json_string(lp_method) : json_null());
    json_object_set_new(s, "search_nodes", json_integer(r->solver.search_nodes));
    json_object_set_new(s, "motion_from", r->unsolved ? json_string("lp_certificate")
                                          : r->nmoving == 0 ? json_null()
                                                       : json_string("lcp"));
    json_object_set_new(s, "lcp_unsolved", r->unsolved ? json_string(cn_unsolved_text(r->unsolved)) : json_null());
    json_object_set_new(o, "solver", s);
    json_t *cc = json_object(), *ids = json_array();
    for (int i = 0; i < r->contacts.count; i++)
        if (r->contacts.items[i].corner) json_array_append_new(ids, json_integer(r->contacts.items[i].id));
    json_object_set_new(cc, "contacts", ids);
    json_object_set_new(cc, "implied", json_integer(r->corners.implied));
    json_object_set_new(cc, "reading", r->corners.reading >= 0 ? json_integer((json_int_t)r->corners.reading) : json_null());
    json_object_set_new(cc, "reading_moves",
                        r->corners.reading_moves >= 0 ? json_integer((json_int_t)r->corners.reading_moves) : json_null());
    json_object_set_new(cc, "readings_decided", json_integer(r->corners.readings));
    /* the product of the cones' ends: an integer, a real past 2^61, null past a double's
     * range (2^1024) */
    json_object_set_new(cc, "readings", r->corners.readings_log2 < 61 ? json_integer((json_int_t)r->corners.readings_all)
                                        : isfinite(r->corners.readings_all) ? json_real(r->corners.readings_all)
                                                                          : json_null());
    json_object_set_new(cc, "cone_too_wide", json_boolean(r->corners.wide));
    json_object_set_new(cc, "disagree", json_boolean(r->corners.disagree));
    json_object_set_new(cc, "all_by_force_field", json_boolean(r->corners.by_field));
    json_object_set_new(cc, "too_many", json_boolean(r->corners.undecided));
    json_object_set_new(o, "corner_contacts", cc);
}

static cnStatus check_json(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    double W = r->ref_weight;
    const char *refname = r->ref_part >= 0 ? a->parts[r->ref_part].name : NULL;
    json_t *o = json_object();
    if (a->name) json_object_set_new(o, "name", json_string(a->name));
    json_object_set_new(o, "dimension", json_integer(a->dim));
    json_object_set_new(o, "stable", json_boolean(r->stable));
    json_object_set_new(o, "verdict", json_string(cn_verdict_word(r->verdict)));
    json_object_set_new(o, "friction", json_boolean(r->friction));
    const char *proof = proof_name(r->proof);
    json_object_set_new(o, "stability_proof", proof ? json_string(proof) : json_null());
    check_json_motion(o, a, r);
    json_object_set_new(o, "motion_quantity",
                        json_string(r->friction ? "velocity after 1 time unit from rest"
                                                : "acceleration"));
    json_t *ref = json_object();
    json_object_set_new(ref, "part", refname ? json_string(refname) : json_null());
    json_object_set_new(ref, "weight", json_real(W));
    json_object_set_new(o, "reference_weight", ref);
    json_t *sep = json_array(), *sl = json_array();
    for (int i = 0; i < r->contacts.count; i++) {
        const cnContact *c = &r->contacts.items[i];
        if (r->contact[i].separates) json_array_append_new(sep, json_integer(c->id));
        if (r->contact[i].slides) json_array_append_new(sl, json_integer(c->id));
    }
    json_object_set_new(o, "contacts", json_null()); /* its place: written by check_contacts */
    json_object_set_new(o, "separating_contacts", sep);
    json_object_set_new(o, "sliding_contacts", sl);
    check_json_solver(o, r);
    json_object_set_new(o, "meshes", mesh_json(a));
    double rel;
    int k = deepest_overlap(a, &r->contacts, &rel);
    json_t *dov = json_null();
    if (k >= 0) {
        dov = json_object();
        json_object_set_new(dov, "contact", json_integer(r->contacts.items[k].id));
        json_object_set_new(dov, "depth", json_real(-r->contacts.items[k].gap));
        json_object_set_new(dov, "relative", json_real(rel));
    }
    json_object_set_new(o, "deepest_overlap", dov);
    CheckContacts cc_ctx = {a, r, NULL};
    return cn_json_write_streamed(f, o, 10, "contacts", check_contacts, &cc_ctx);
}

/* check's text: the assembly in one line, parts that touch nothing, meshes, the deepest
 * overlap taken as contact. */
static void check_text_head(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    int dim = a->dim;
    int nfixed = 0;
    for (int i = 0; i < a->nparts; i++) nfixed += a->parts[i].fixed;
    /* the file's friction, even where no contact uses it */
    bool file_friction = a->friction > 0;
    for (int i = 0; i < a->npairs; i++) file_friction |= a->pairs[i].mu > 0;
    fprintf(f, "%s%s%d-D assembly: %d part%s (%d fixed), %d contact%s, %s\n", a->name ? a->name : "",
            a->name ? "\n" : "", dim, a->nparts, a->nparts == 1 ? "" : "s", nfixed, r->contacts.count,
            r->contacts.count == 1 ? "" : "s",
            r->friction ? "with friction (Stewart-Trinkle LCP, static LP)"
            : file_friction ? "no contact with friction (Baraff LCP, frictionless)"
                            : "frictionless (Baraff LCP)");
    /* a free part that touches nothing falls freely: say so, rather than leave it to the verdict
     * (the parts touched marked in one pass over the contacts) */
    unsigned char *touched = cn_calloc((size_t)a->nparts + 1, 1);
    for (int c = 0; touched && c < r->contacts.count; c++)
        for (int x = 0; x < 2; x++) {
            int p = x ? r->contacts.items[c].body2 : r->contacts.items[c].body1;
            if (p >= 0 && p < a->nparts) touched[p] = 1;
        }
    for (int i = 0; touched && i < a->nreal; i++) {
        if (a->parts[i].fixed || touched[i]) continue;
        double gap;
        int near = cn_part_nearest(a, i, &gap);
        fprintf(f, "note: '%s' touches nothing (no part within the contact tolerance): it falls freely", a->parts[i].name);
        if (near >= 0 && gap > 0)
            fprintf(f, "; nearest part '%s', at least %.3g away\n", a->parts[near].name, gap);
        else if (near >= 0)
            fprintf(f, "; nearest part '%s'\n", a->parts[near].name);
        else
            fputc('\n', f);
    }
    cn_free(touched);
    mesh_text(f, a);
    double rel;
    int dk = deepest_overlap(a, &r->contacts, &rel);
    if (dk >= 0 && rel > CN_OVERLAP_SHOWN) {
        const cnContact *c = &r->contacts.items[dk];
        fprintf(f, "deepest overlap accepted as contact: %.3g (%.3g of the smaller part's size), "
                   "contact %d between '%s' and '%s' (tolerance %g)\n",
                -c->gap, rel, c->id, a->parts[c->body1].name, a->parts[c->body2].name, a->rel_tol);
    }
}

/* check's text: how each moving part starts to move. */
static void check_text_motion(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    double g = cn_norm3(a->gravity);
    int dim = a->dim;
    const char *q = r->friction ? "velocity after 1 time unit" : "acceleration";
    for (int i = 0; i < r->nmoving; i++) {
        int p = r->moving[i];
        const cnPartMotion *m = &r->part[p];
        double lin = cn_norm3(m->lin);
        char lv[96];
        fmt_vec(lv, sizeof lv, m->lin, dim, g);
        fprintf(f, "  %s: linear %s %s, |%.4g| = %.3g g", a->parts[p].name, q, lv, lin,
                lin / g);
        if (dim == 2) {
            double w = clean(m->ang[2], g / a->length_scale);
            if (w != 0) fprintf(f, "; turns %s (angular %.4g)", turn_name(w), w);
        } else {
            double wn = cn_norm3(m->ang);
            if (clean(wn, g / a->length_scale) != 0) {
                double ax[3] = {m->ang[0] / wn, m->ang[1] / wn, m->ang[2] / wn};
                char av[96];
                fmt_vec(av, sizeof av, ax, 3, 1.0);
                fprintf(f, "; turns about axis %s (angular %.4g)", av, wn);
            }
        }
        fprintf(f, "\n");
    }
}

/* check's text: the verdict, and for a motion the parts and contacts it moves. */
static void check_text_verdict(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    if (r->stable) {
        fprintf(f, "verdict: STABLE: no part moves%s\n",
                r->proof == CN_PROOF_ACCEPTED ? " (a static solution exists; prestress accepted, "
                                                "a motion from rest was not ruled out)"
                                                 : "");
    } else if (r->verdict == CN_VERDICT_UNDECIDED && r->corners.undecided) {
        char all[32];
        readings_text(r, all, sizeof all);
        fprintf(f, "verdict: UNDECIDED: %d contacts touch corner to corner, and their normals have "
                   "%s readings; every one of the %ld tried stands, the others were not tried "
                   "(neither --search-budget nor --accept-prestress changes that)\n",
                r->corners.count, all, r->corners.readings);
    } else if (r->verdict == CN_VERDICT_UNDECIDED) {
        fprintf(f, "verdict: UNDECIDED: a static solution exists (forces below), but whether a "
                   "motion from rest exists too was not decided in %ld LP%s; --search-budget N "
                   "searches longer, --accept-prestress takes the static solution as enough\n",
                r->solver.search_nodes, cn_plural(r->solver.search_nodes));
    } else {
        if (r->verdict == CN_VERDICT_NOT_GUARANTEED && r->corners.disagree)
            fprintf(f, "verdict: NOT GUARANTEED: parts touch corner to corner; in one reading of "
                       "the contact normals there a static solution exists, in another a motion "
                       "starts (--accept-prestress does not change that)\n"
                       "  the motion it admits: %d part%s can start to move:",
                    r->nmoving, r->nmoving == 1 ? "" : "s");
        else if (r->verdict == CN_VERDICT_NOT_GUARANTEED && r->corners.count > 0)
            fprintf(f, "verdict: NOT GUARANTEED: a static solution exists, but so does a motion "
                       "from rest, in a reading of the normals where parts touch corner to corner "
                       "(below)\n"
                       "  the motion it admits: %d part%s can start to move:",
                    r->nmoving, r->nmoving == 1 ? "" : "s");
        else if (r->verdict == CN_VERDICT_NOT_GUARANTEED)
            fprintf(f, "verdict: NOT GUARANTEED: a static solution exists, but so does a motion "
                       "from rest; it stands only if a prestress or a favourable sharing of the "
                       "load holds it (--accept-prestress takes that as stable)\n"
                       "  the motion it admits: %d part%s can start to move:",
                    r->nmoving, r->nmoving == 1 ? "" : "s");
        else
            fprintf(f, "verdict: UNSTABLE: %d part%s start%s to move:", r->nmoving,
                    r->nmoving == 1 ? "" : "s", r->nmoving == 1 ? "s" : "");
        for (int i = 0; i < r->nmoving; i++) fprintf(f, " %s", a->parts[r->moving[i]].name);
        fprintf(f, "\n");
        check_text_motion(f, a, r);
        int any = 0;
        for (int i = 0; i < r->contacts.count; i++)
            if (r->contact[i].separates) {
                fprintf(f, "%s%d", any ? ", " : "  contacts that separate: ", r->contacts.items[i].id);
                any = 1;
            }
        if (any) fprintf(f, "\n");
        any = 0;
        for (int i = 0; i < r->contacts.count; i++)
            if (r->contact[i].slides) {
                fprintf(f, "%s%d", any ? ", " : "  contacts that slide: ", r->contacts.items[i].id);
                any = 1;
            }
        if (any) fprintf(f, "\n");
        if (r->unsolved)
            fprintf(f, "  (the contact LCP was not solved: %s; this motion is the collapse "
                       "mechanism that proves no static solution exists: gravity does work on it "
                       "and no contact resists it. It is the mechanism of associated friction, so "
                       "contacts that would slide are shown opening; the forces are not known)\n",
                    cn_unsolved_text(r->unsolved));
    }
}

/* check's text: the contact forces, then the solver and the proof (or what was left open). */
static void check_text_forces(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    double W = r->ref_weight;
    int dim = a->dim;
    const char *refname = r->ref_part >= 0 ? a->parts[r->ref_part].name : NULL;
    corner_text(f, a, r);
    fprintf(f, "contact forces%s (reference weight W = %.6g, the weight of '%s'):\n",
            r->corners.disagree ? " of the reading that stands"
            : r->verdict == CN_VERDICT_NOT_GUARANTEED ? " of the static solution, the squeeze it needs"
                                                    : "",
            W, refname ? refname : "-");
    fprintf(f, "%4s  %-22s %-24s %-18s %12s %9s  %s\n", "id", "parts", "point", "normal", "force",
            "force/W", "state");
    for (int i = 0; i < r->contacts.count; i++) {
        const cnContact *c = &r->contacts.items[i];
        const cnContactResult *cr = &r->contact[i];
        char n1[128], n2[128], pair[260], p[80], nv[80];
        body_name(a, c, 0, n1, sizeof n1);
        body_name(a, c, 1, n2, sizeof n2);
        snprintf(pair, sizeof pair, "%s / %s", n1, n2);
        fmt_vec(p, sizeof p, c->point, dim, a->length_scale);
        fmt_vec(nv, sizeof nv, c->normal, dim, 1.0);
        const char *state = cr->separates ? "separates" : cr->slides ? "slides" : "";
        fprintf(f, "%4d  %-22s %-24s %-18s %12.5g %9.4f  %s\n", c->id, pair, p, nv,
                clean(cr->normal_force, W), clean(cr->normal_force / W, 1), state);
    }
}

static void check_text_proof(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    double g = cn_norm3(a->gravity);
    const char *lp_says = r->solver.lp_stable ? "a static solution exists" : "no static solution exists";
    if (r->solver.forces_from == CN_FORCES_SPARSE_QP) /* no pivots: the sparse QP */
        fprintf(f, "solver: forces from the LCP of size %d as a sparse QP (interior point), "
                   "residual %.2g; LP says %s\n", r->solver.lcp_size, r->solver.residual, lp_says);
    else
        fprintf(f, "solver: forces from %s, LCP of size %d, %d pivot%s, residual %.2g; LP says %s\n",
                cn_forces_from_name(r->solver.forces_from), r->solver.lcp_size, r->solver.pivots, cn_plural(r->solver.pivots), r->solver.residual,
                lp_says);
    if (r->proof == CN_PROOF_FRICTIONLESS)
        fprintf(f, "no motion from rest: a frictionless force field balances gravity, so every "
                   "motion would raise the parts\n");
    else if (r->proof == CN_PROOF_SEARCH)
        fprintf(f, "no motion from rest: a search of the LCP's solutions (%ld LP%s) found none "
                   "that moves\n",
                r->solver.search_nodes, cn_plural(r->solver.search_nodes));
    else if (r->proof == CN_PROOF_UNDECIDED) {
        fprintf(f, "motion from rest not ruled out: %s after %ld LP%s\n", cn_undecided_text(r->undecided),
                r->solver.search_nodes, cn_plural(r->solver.search_nodes));
        int n = 0;
        for (int p = 0; p < a->nparts && r->part; p++)
            if (r->part[p].unsettled) fprintf(f, "%s%s", n++ ? ", " : "parts its open nodes move: ", a->parts[p].name);
        if (n) fprintf(f, "\n");
        n = 0;
        for (int c = 0; c < r->contacts.count && r->contact; c++)
            if (r->contact[c].unsettled && first_unsettled_joint(r, c))
                fprintf(f, "%s%s/%s", n++ ? ", " : "joints they leave unsettled: ",
                        contact_part(a, r->contacts.items[c].body1), contact_part(a, r->contacts.items[c].body2));
        if (n) fprintf(f, "\n");
        if (isfinite(r->open_speed))
            fprintf(f, "in any motion left open no part starts faster than %.3g per time unit (%.3g times g)\n",
                    r->open_speed, r->open_speed / g);
        if (lemke_static(r))
            fprintf(f, "the paper's test agrees with the static solution: the LCP's solution that "
                       "Lemke's method finds does not move (the forces above); cairn also asks that no "
                       "other solution moves\n");
        else
            fprintf(f, "Lemke's method gave no static solution of the LCP (the forces above are the "
                       "LP's)\n");
    }
}

cnStatus cn_report_check(FILE *f, const cnAssembly *a, const cnCheckResult *r, int json) {
    if (json) return check_json(f, a, r);
    check_text_head(f, a, r);
    check_text_verdict(f, a, r);
    check_text_forces(f, a, r);
    check_text_proof(f, a, r);
    return CN_OK;
}
