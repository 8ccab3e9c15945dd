/* Reports of contacts, as text or JSON (jansson), and what the check's JSON and text writers
 * share (report_check.h). */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "json_out.h"
#include "report_check.h"
#include "cairn/report.h"

/* Values closer to zero than this fraction of their scale print as 0, so round-off noise does
 * not show up as -1.2e-17 in reports (and output is stable across builds). */
#define REPORT_ZERO CN_TOL_PRINT_ZERO

double cn_report_clean(double v, double scale) { return fabs(v) <= REPORT_ZERO * scale ? 0.0 : v; }

static const char *kind_name(cnContactKind k, int dim) {
    switch (k) {
    case CN_CONTACT_VERTEX: return "vertex";
    case CN_CONTACT_EDGE: return dim == 2 ? "edge-edge" : "edge";
    case CN_CONTACT_FACE: return "face-face";
    case CN_CONTACT_FIXEL: return "fixel";
    }
    return "?";
}

void cn_report_body_name(const cnAssembly *a, const cnContact *c, int which, char *buf, size_t n) {
    int b = which ? c->body2 : c->body1;
    if (b == CN_WORLD) snprintf(buf, n, "fixel[%d]", c->fixel);
    else snprintf(buf, n, "%s", a->parts[b].name);
}

json_t *cn_report_vec(const double *v, int dim, double scale) {
    json_t *arr = json_array();
    for (int k = 0; k < dim; k++) json_array_append_new(arr, json_real(cn_report_clean(v[k], scale)));
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
        double x = cn_report_clean(v[k], scale);
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

/* A check's contacts, streamed (ctx: a cnReportContacts). */
void cn_report_check_contacts(cnJsonStream *s, void *ctx) {
    const cnReportContacts *x = ctx;
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
        stream_real_key(s, "force", cn_report_clean(cr->normal_force, W));
        stream_real_key(s, "force_normalized", cn_report_clean(cr->normal_force / W, 1));
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
    const cnReportContacts *x = ctx;
    const cnAssembly *a = x->a;
    const cnContactSet *cs = x->cs;
    unsigned k0 = cn_json_stream_open(s, false);
    for (int i = 0; i < cs->count; i++) {
        unsigned k1 = cn_json_stream_open(s, true);
        stream_contact_head(s, a, &cs->items[i]);
        stream_real_key(s, "gap", cn_report_clean(cs->items[i].gap, a->length_scale));
        cn_json_stream_close(s, k1);
    }
    cn_json_stream_close(s, k0);
}

void cn_report_fmt_vec(char *buf, size_t n, const double *v, int dim, double scale) {
    if (dim == 2) snprintf(buf, n, "(%.4g, %.4g)", cn_report_clean(v[0], scale), cn_report_clean(v[1], scale));
    else
        snprintf(buf, n, "(%.4g, %.4g, %.4g)", cn_report_clean(v[0], scale), cn_report_clean(v[1], scale),
                 cn_report_clean(v[2], scale));
}

/* The deepest overlap accepted as contact (a negative gap within the tolerance): its index in
 * the contacts, or -1 when no two parts overlap; *rel: its depth over the smaller part's size. */
int cn_report_deepest_overlap(const cnAssembly *a, const cnContactSet *cs, double *rel) {
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
void cn_report_mesh_text(FILE *f, const cnAssembly *a) {
    for (int i = 0; i < a->nparts; i++) {
        const cnPart *p = &a->parts[i];
        if (!p->mesh_file) continue;
        fprintf(f, "part '%s': mesh '%s', %d convex piece%s", p->name, p->mesh_file, p->npieces,
                p->npieces == 1 ? "" : "s");
        if (p->mesh_split) fprintf(f, " (%d made by the exact convex decomposition of a non-convex mesh)", p->mesh_split);
        fprintf(f, "\n");
    }
}

json_t *cn_report_mesh_json(const cnAssembly *a) {
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

cnStatus cn_report_contacts(FILE *f, const cnAssembly *a, const cnContactSet *cs, int json) {
    if (json) {
        json_t *o = json_object();
        json_object_set_new(o, "dimension", json_integer(a->dim));
        json_object_set_new(o, "relative_tolerance", json_real(a->rel_tol));
        json_object_set_new(o, "contacts", json_null()); /* its place: written by found_contacts */
        cnReportContacts ctx = {a, NULL, cs};
        return cn_json_write_streamed(f, o, 10, "contacts", found_contacts, &ctx);
    }
    fprintf(f, "%d contact%s (tolerance %.3g of the smaller part's size)\n", cs->count,
            cn_plural(cs->count), a->rel_tol);
    fprintf(f, "%4s  %-24s %-10s %-26s %-22s\n", "id", "parts", "kind", "point", "normal");
    for (int i = 0; i < cs->count; i++) {
        const cnContact *c = &cs->items[i];
        char n1[128], n2[128], pair[260], p[80], nv[80];
        cn_report_body_name(a, c, 0, n1, sizeof n1);
        cn_report_body_name(a, c, 1, n2, sizeof n2);
        snprintf(pair, sizeof pair, "%s / %s", n1, n2);
        cn_report_fmt_vec(p, sizeof p, c->point, a->dim, a->length_scale);
        cn_report_fmt_vec(nv, sizeof nv, c->normal, a->dim, 1.0);
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

const char *cn_report_proof_name(cnProof p) {
    switch (p) {
    case CN_PROOF_FRICTIONLESS: return "frictionless_field";
    case CN_PROOF_SEARCH: return "search";
    case CN_PROOF_ACCEPTED: return "accepted_prestress";
    case CN_PROOF_UNDECIDED: return "none_search_undecided";
    case CN_PROOF_SECTION: return "section_planar_assumed";
    default: return NULL;
    }
}

/* The paper's own test agrees with the static solution: the LCP's solution by Lemke's method does
 * not move (its forces are the ones reported). */
bool cn_report_lemke_static(const cnCheckResult *r) { return r->solver.forces_from == CN_FORCES_LEMKE; }

/* The name of a contact's part (a fixel's "world"). */
const char *cn_report_contact_part(const cnAssembly *a, int part) {
    return part >= 0 && part < a->nparts ? a->parts[part].name : "world";
}

/* Is contact c the first unsettled one between its two parts (either way round)? */
typedef struct {
    int lo, hi, c;
} JointKey;

static int cmp_joint(const void *x, const void *y) {
    const JointKey *a = x, *b = y;
    if (a->lo != b->lo) return (a->lo > b->lo) - (a->lo < b->lo);
    if (a->hi != b->hi) return (a->hi > b->hi) - (a->hi < b->hi);
    return (a->c > b->c) - (a->c < b->c);
}

unsigned char *cn_report_unsettled_joints(const cnCheckResult *r) {
    int K = r->contact ? r->contacts.count : 0, n = 0;
    unsigned char *first = cn_calloc((size_t)K + 1, 1);
    JointKey *key = cn_malloc(sizeof(JointKey) * (size_t)(K + 1));
    if (!first || !key) {
        cn_free(first), cn_free(key);
        return NULL;
    }
    for (int c = 0; c < K; c++) {
        if (!r->contact[c].unsettled) continue;
        int b1 = r->contacts.items[c].body1, b2 = r->contacts.items[c].body2;
        key[n++] = (JointKey){b1 < b2 ? b1 : b2, b1 < b2 ? b2 : b1, c};
    }
    qsort(key, (size_t)n, sizeof(JointKey), cmp_joint);
    for (int i = 0; i < n; i++)
        if (i == 0 || key[i].lo != key[i - 1].lo || key[i].hi != key[i - 1].hi) first[key[i].c] = 1;
    cn_free(key);
    return first;
}

cnStatus cn_report_check(FILE *f, const cnAssembly *a, const cnCheckResult *r, int json) {
    if (json) return cn_report_check_json(f, a, r);
    cn_report_check_text(f, a, r);
    return CN_OK;
}
