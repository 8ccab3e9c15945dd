/* check --json: the verdict, motion, forces (streamed), solver report and corner readings of a
 * check as one JSON document. */
#include <jansson.h>
#include <math.h>

#include "json_out.h"
#include "report_check.h"

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
        json_object_set_new(m, "linear", cn_report_vec(r->part[p].lin, dim, g));
        if (dim == 2) json_object_set_new(m, "angular", json_real(cn_report_clean(r->part[p].ang[2], g / a->length_scale)));
        else json_object_set_new(m, "angular", cn_report_vec(r->part[p].ang, 3, g / a->length_scale));
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
        unsigned char *first = cn_report_unsettled_joints(r);
        for (int c = 0; c < r->contacts.count && r->contact; c++) {
            if (!r->contact[c].unsettled) continue;
            json_array_append_new(uc, json_integer(r->contacts.items[c].id));
            if (!first || !first[c]) continue;
            json_t *j = json_array();
            json_array_append_new(j, json_string(cn_report_contact_part(a, r->contacts.items[c].body1)));
            json_array_append_new(j, json_string(cn_report_contact_part(a, r->contacts.items[c].body2)));
            json_array_append_new(uj, j);
        }
        cn_free(first);
        json_object_set_new(u, "contacts", uc);
        json_object_set_new(u, "joints", uj);
        json_object_set_new(u, "max_speed", isfinite(r->open_speed) ? json_real(r->open_speed) : json_null());
        json_object_set_new(u, "lemke_static", json_boolean(cn_report_lemke_static(r)));
        json_object_set_new(o, "undecided", u);
    }
    if (r->section.checked) { /* a 3-D prism: its 2-D section's verdict */
        json_t *sc = json_object();
        const char *proof = cn_report_proof_name(r->section.proof);
        json_object_set_new(sc, "axis", json_string((const char *[]){"x", "y", "z"}[r->section.axis]));
        json_object_set_new(sc, "verdict", json_string(cn_verdict_word(r->section.verdict)));
        json_object_set_new(sc, "stability_proof", proof ? json_string(proof) : json_null());
        json_object_set_new(sc, "search_nodes", json_integer(r->section.search_nodes));
        json_object_set_new(sc, "lifted", json_boolean(r->section.lifted));
        json_object_set_new(o, "section", sc);
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

cnStatus cn_report_check_json(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    double W = r->ref_weight;
    const char *refname = r->ref_part >= 0 ? a->parts[r->ref_part].name : NULL;
    json_t *o = json_object();
    if (a->name) json_object_set_new(o, "name", json_string(a->name));
    json_object_set_new(o, "dimension", json_integer(a->dim));
    json_object_set_new(o, "stable", json_boolean(r->stable));
    json_object_set_new(o, "verdict", json_string(cn_verdict_word(r->verdict)));
    json_object_set_new(o, "friction", json_boolean(r->friction));
    const char *proof = cn_report_proof_name(r->proof);
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
    json_object_set_new(o, "meshes", cn_report_mesh_json(a));
    double rel;
    int k = cn_report_deepest_overlap(a, &r->contacts, &rel);
    json_t *dov = json_null();
    if (k >= 0) {
        dov = json_object();
        json_object_set_new(dov, "contact", json_integer(r->contacts.items[k].id));
        json_object_set_new(dov, "depth", json_real(-r->contacts.items[k].gap));
        json_object_set_new(dov, "relative", json_real(rel));
    }
    json_object_set_new(o, "deepest_overlap", dov);
    cnReportContacts cc_ctx = {a, r, NULL};
    return cn_json_write_streamed(f, o, 10, "contacts", cn_report_check_contacts, &cc_ctx);
}
