/* check's text report: the assembly, the verdict and motion, the forces, corner readings and how
 * the verdict was proved. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json_out.h"
#include "report_check.h"

/* Overlaps accepted as contacts are told in the text from this fraction of the smaller part's
 * size on (below it they are the rounding of coordinates that touch). */
#define CN_OVERLAP_SHOWN 1e-9

static const char *turn_name(double w) { return w > 0 ? "counter-clockwise" : "clockwise"; }

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
        cn_report_fmt_vec(n1, sizeof n1, c->normal, a->dim, 1.0);
        cn_report_fmt_vec(n2, sizeof n2, c->alt_normal, a->dim, 1.0);
        if (c->corner_ends <= 2) {
            fprintf(f, "  contact %d: normal anywhere from %s (shown) to %s\n", c->id, n1, n2);
            continue;
        }
        fprintf(f, "  contact %d: normal anywhere in the cone spanned by %s (shown), %s", c->id, n1, n2);
        for (int e = 0; e < c->corner_ends - 2; e++) {
            cn_report_fmt_vec(n2, sizeof n2, c->more_normals[e], a->dim, 1.0);
            fprintf(f, "%s %s", e == c->corner_ends - 3 ? " and" : ",", n2);
        }
        fprintf(f, "%s\n", c->corner_wide ? ", and more ends that were not kept" : "");
    }
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
    cn_report_mesh_text(f, a);
    double rel;
    int dk = cn_report_deepest_overlap(a, &r->contacts, &rel);
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
        cn_report_fmt_vec(lv, sizeof lv, m->lin, dim, g);
        fprintf(f, "  %s: linear %s %s, |%.4g| = %.3g g", a->parts[p].name, q, lv, lin,
                lin / g);
        if (dim == 2) {
            double w = cn_report_clean(m->ang[2], g / a->length_scale);
            if (w != 0) fprintf(f, "; turns %s (angular %.4g)", turn_name(w), w);
        } else {
            double wn = cn_norm3(m->ang);
            if (cn_report_clean(wn, g / a->length_scale) != 0) {
                double ax[3] = {m->ang[0] / wn, m->ang[1] / wn, m->ang[2] / wn};
                char av[96];
                cn_report_fmt_vec(av, sizeof av, ax, 3, 1.0);
                fprintf(f, "; turns about axis %s (angular %.4g)", av, wn);
            }
        }
        fprintf(f, "\n");
    }
}

/* A 3-D prism's 2-D section, checked when its verdict was undecided. */
static void section_text(FILE *f, const cnCheckResult *r) {
    if (!r->section.checked) return;
    char axis = "xyz"[r->section.axis];
    const char *v = cn_verdict_word(r->section.verdict);
    if (r->section.verdict == CN_VERDICT_STABLE)
        fprintf(f, "its 2-D section across %c (every part an extrusion along %c) is stable (%s, %ld LP%s): "
                   "a motion from rest in 3-D would have to leave that plane%s\n",
                axis, axis, cn_report_proof_name(r->section.proof), r->section.search_nodes,
                cn_plural(r->section.search_nodes),
                r->proof == CN_PROOF_SECTION ? " (--assume-planar rules such motions out)"
                                             : "; --assume-planar takes the section's verdict");
    else if (r->section.lifted)
        fprintf(f, "its 2-D section across %c (every part an extrusion along %c) is not guaranteed: the "
                   "motion above is its motion from rest, extruded and verified in 3-D\n", axis, axis);
    else
        fprintf(f, "its 2-D section across %c (every part an extrusion along %c) is %s\n", axis, axis,
                r->section.verdict == CN_VERDICT_NOT_GUARANTEED ? "not guaranteed (it admits a motion in its plane)" : v);
}

/* check's text: the verdict, and for a motion the parts and contacts it moves. */
static void check_text_verdict(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    if (r->stable) {
        fprintf(f, "verdict: STABLE: no part moves%s\n",
                r->proof == CN_PROOF_ACCEPTED ? " (a static solution exists; prestress accepted, "
                                                "a motion from rest was not ruled out)"
                : r->proof == CN_PROOF_SECTION ? " (planar motion assumed: its 2-D section is proved "
                                                 "stable; motions out of that plane were not ruled out)"
                                                 : "");
    } else if (r->verdict == CN_VERDICT_UNDECIDED && r->corners.undecided) {
        char all[32];
        readings_text(r, all, sizeof all);
        fprintf(f, "verdict: UNDECIDED: %d contacts touch corner to corner, and their normals have "
                   "%s readings; every one of the %ld tried stands, the others were not tried "
                   "(neither --search-budget nor --accept-prestress changes that)\n",
                r->corners.count, all, r->corners.readings);
    } else if (r->verdict == CN_VERDICT_UNDECIDED && r->undecided == CN_UNDECIDED_TOO_LARGE) {
        fprintf(f, "verdict: UNDECIDED: a static solution exists (forces below), but whether a "
                   "motion from rest exists too was not decided: its parts are too many for the "
                   "whole search, and no part, alone or with one it touches, was found to move "
                   "with the rest held still; --accept-prestress takes the static solution as "
                   "enough\n");
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
        cn_report_body_name(a, c, 0, n1, sizeof n1);
        cn_report_body_name(a, c, 1, n2, sizeof n2);
        snprintf(pair, sizeof pair, "%s / %s", n1, n2);
        cn_report_fmt_vec(p, sizeof p, c->point, dim, a->length_scale);
        cn_report_fmt_vec(nv, sizeof nv, c->normal, dim, 1.0);
        const char *state = cr->separates ? "separates" : cr->slides ? "slides" : "";
        fprintf(f, "%4d  %-22s %-24s %-18s %12.5g %9.4f  %s\n", c->id, pair, p, nv,
                cn_report_clean(cr->normal_force, W), cn_report_clean(cr->normal_force / W, 1), state);
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
    if (r->proof == CN_PROOF_SECTION || r->section.lifted) section_text(f, r);
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
        unsigned char *first = cn_report_unsettled_joints(r);
        for (int c = 0; c < r->contacts.count && first; c++)
            if (first[c])
                fprintf(f, "%s%s/%s", n++ ? ", " : "joints they leave unsettled: ",
                        cn_report_contact_part(a, r->contacts.items[c].body1), cn_report_contact_part(a, r->contacts.items[c].body2));
        cn_free(first);
        if (n) fprintf(f, "\n");
        if (isfinite(r->open_speed))
            fprintf(f, "in any motion left open no part starts faster than %.3g per time unit (%.3g times g)\n",
                    r->open_speed, r->open_speed / g);
        section_text(f, r);
        if (cn_report_lemke_static(r))
            fprintf(f, "the paper's test agrees with the static solution: the LCP's solution that "
                       "Lemke's method finds does not move (the forces above); cairn also asks that no "
                       "other solution moves\n");
        else
            fprintf(f, "Lemke's method gave no static solution of the LCP (the forces above are the "
                       "LP's)\n");
    }
}

void cn_report_check_text(FILE *f, const cnAssembly *a, const cnCheckResult *r) {
    check_text_head(f, a, r);
    check_text_verdict(f, a, r);
    check_text_forces(f, a, r);
    check_text_proof(f, a, r);
}
