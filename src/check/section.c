/* The 2-D section of a 3-D prism assembly, and its check: where a static 3-D friction check
 * would start its search for a motion from rest (cn_ck_prove_still) and every part is an
 * extrusion along one coordinate axis perpendicular to gravity (the free parts over one common
 * depth, the fixed ones over at least that depth), the section across that axis is checked as a
 * 2-D assembly. Its motion, if it has one, is lifted to the prism (section_lift.c); its verdict is
 * reported; with assume_planar a stable section settles a 3-D search left undecided. */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cairn/stability.h"
#include "core.h"
#include "pieces.h"
#include "section.h"

/* Coordinates that must agree for a part to be an extrusion, relative to the assembly's size:
 * a prism written by a program agrees to rounding. */
#define CN_SECTION_REL_TOL 1e-9
/* A piece with more vertices than this is not tested (the test is quadratic in them). */
#define CN_SECTION_MAX_VERTS 4096

/* Is the piece an extrusion along axis k over [lo, hi]: every vertex at one end, and the two
 * ends the same polygon? */
static bool piece_extruded(const cnPiece *pc, int k, double tol) {
    double lo = pc->lo[k], hi = pc->hi[k];
    if (pc->nverts < 6 || pc->nverts > CN_SECTION_MAX_VERTS || !(hi - lo > tol)) return false;
    int u = (k + 1) % 3, w = (k + 2) % 3;
    for (int i = 0; i < pc->nverts; i++) {
        const double *v = pc->verts[i];
        bool at_lo = fabs(v[k] - lo) <= tol;
        if (!at_lo && fabs(v[k] - hi) > tol) return false;
        bool twin = false; /* the same point at the other end */
        for (int j = 0; j < pc->nverts && !twin; j++) {
            const double *x = pc->verts[j];
            twin = fabs(x[k] - (at_lo ? hi : lo)) <= tol && fabs(x[u] - v[u]) <= tol &&
                   fabs(x[w] - v[w]) <= tol;
        }
        if (!twin) return false;
    }
    return true;
}

int cn_section_axis(const cnAssembly *a, const cnContactQuery *q) {
    /* the friction pyramid must hold the section's tangent and be symmetric about its plane
       (cn_tangent_basis puts one of its axes along the extrusion): D a multiple of 4 */
    if (a->dim != 3 || a->nfixels > 0 || (q && (q->pose || q->twist)) || a->friction_dirs % 4 != 0) return -1;
    for (int p = a->nreal; p < a->nparts; p++) /* a gripper present: not a prism */
        if (cn_part_present(a, q, p)) return -1;
    double tol = CN_SECTION_REL_TOL * a->length_scale;
    double g = cn_norm3(a->gravity);
    for (int k = 0; k < 3; k++) {
        if (fabs(a->gravity[k]) > CN_SECTION_REL_TOL * g) continue;
        double y0 = NAN, y1 = NAN;
        bool ok = true, any_free = false;
        for (int p = 0; p < a->nreal && ok; p++) { /* the free parts' common depth */
            if (!cn_part_present(a, q, p) || a->parts[p].fixed) continue;
            for (int i = 0; i < a->parts[p].npieces && ok; i++) {
                const cnPiece *pc = &a->parts[p].pieces[i];
                if (!any_free) y0 = pc->lo[k], y1 = pc->hi[k], any_free = true;
                ok = piece_extruded(pc, k, tol) && fabs(pc->lo[k] - y0) <= tol && fabs(pc->hi[k] - y1) <= tol;
            }
        }
        for (int p = 0; p < a->nreal && ok && any_free; p++) { /* the supports span it */
            if (!cn_part_present(a, q, p) || !a->parts[p].fixed) continue;
            for (int i = 0; i < a->parts[p].npieces && ok; i++) {
                const cnPiece *pc = &a->parts[p].pieces[i];
                ok = piece_extruded(pc, k, tol) && pc->lo[k] <= y0 + tol && pc->hi[k] >= y1 - tol;
            }
        }
        if (ok && any_free) return k;
    }
    return -1;
}

/* The piece's end polygon in the section's coordinates (counter-clockwise, at most nverts / 2
 * vertices) as a JSON array of points; NULL when out of memory. */
static json_t *piece_polygon(const cnPiece *pc, int k, double tol) {
    int u = (k + 1) % 3, w = (k + 2) % 3, n = 0;
    double(*xy)[2] = malloc(sizeof(double[2]) * (size_t)pc->nverts);
    double *ang = malloc(sizeof(double) * (size_t)pc->nverts);
    json_t *poly = json_array();
    if (!xy || !ang || !poly) goto fail;
    double cx = 0, cy = 0;
    for (int i = 0; i < pc->nverts; i++) {
        const double *v = pc->verts[i];
        if (fabs(v[k] - pc->lo[k]) > tol) continue;
        bool dup = false;
        for (int j = 0; j < n && !dup; j++) dup = fabs(xy[j][0] - v[u]) <= tol && fabs(xy[j][1] - v[w]) <= tol;
        if (dup) continue;
        xy[n][0] = v[u], xy[n][1] = v[w];
        cx += v[u], cy += v[w], n++;
    }
    cx /= n, cy /= n;
    for (int i = 0; i < n; i++) ang[i] = atan2(xy[i][1] - cy, xy[i][0] - cx);
    for (int i = 1; i < n; i++) /* by angle about the centroid: the convex end in order */
        for (int j = i; j > 0 && ang[j] < ang[j - 1]; j--) {
            double t = ang[j];
            ang[j] = ang[j - 1], ang[j - 1] = t;
            double p0 = xy[j][0], p1 = xy[j][1];
            xy[j][0] = xy[j - 1][0], xy[j][1] = xy[j - 1][1];
            xy[j - 1][0] = p0, xy[j - 1][1] = p1;
        }
    for (int i = 0; i < n; i++) {
        json_t *pt = json_pack("[ff]", xy[i][0], xy[i][1]);
        if (!pt || json_array_append_new(poly, pt)) goto fail;
    }
    free(xy), free(ang);
    return poly;
fail:
    free(xy), free(ang);
    json_decref(poly);
    return NULL;
}

/* jansson's setters, false when out of memory (the value is released either way) */
static bool put(json_t *o, const char *key, json_t *v) { return v && json_object_set_new(o, key, v) == 0; }
static bool add(json_t *arr, json_t *v) { return v && json_array_append_new(arr, v) == 0; }

/* The section as an assembly file's JSON text (free with free()); NULL when out of memory. */
static char *section_json(const cnAssembly *a, const cnContactQuery *q, int k) {
    int u = (k + 1) % 3, w = (k + 2) % 3;
    double tol = CN_SECTION_REL_TOL * a->length_scale;
    json_t *root = json_object(), *parts = json_array(), *pairs = json_array();
    char *text = NULL;
    bool ok = root && parts && pairs;
    /* the same absolute contact tolerance: the section's size is its own */
    double lo[2] = {INFINITY, INFINITY}, hi[2] = {-INFINITY, -INFINITY};
    for (int p = 0; p < a->nreal; p++) {
        if (!cn_part_present(a, q, p)) continue;
        const cnPart *pt = &a->parts[p];
        lo[0] = fmin(lo[0], pt->lo[u]), hi[0] = fmax(hi[0], pt->hi[u]);
        lo[1] = fmin(lo[1], pt->lo[w]), hi[1] = fmax(hi[1], pt->hi[w]);
    }
    double diag = hypot(hi[0] - lo[0], hi[1] - lo[1]);
    double rel = diag > 0 ? a->contact_tol / diag : a->rel_tol;
    ok = ok && put(root, "dimension", json_integer(2)) &&
         put(root, "gravity", json_pack("[ff]", a->gravity[u], a->gravity[w])) &&
         put(root, "friction", json_real(a->friction)) && put(root, "density", json_real(a->density)) &&
         put(root, "tolerance", json_real(fmin(fmax(rel, 1e-12), 0.1)));
    for (int p = 0; p < a->nreal && ok; p++) {
        if (!cn_part_present(a, q, p)) continue;
        const cnPart *pt = &a->parts[p];
        json_t *o = json_object(), *polys = json_array();
        ok = o && polys && put(o, "name", json_string(pt->name)) &&
             (pt->fixed ? put(o, "fixed", json_true())
                        : put(o, "mass", json_real(pt->mass))); /* every free part is as deep */
        for (int i = 0; i < pt->npieces && ok; i++) ok = add(polys, piece_polygon(&pt->pieces[i], k, tol));
        if (ok) ok = put(o, "polygons", json_incref(polys)) && add(parts, json_incref(o));
        json_decref(o), json_decref(polys);
    }
    for (int i = 0; i < a->npairs && ok; i++) {
        const cnFrictionPair *fp = &a->pairs[i];
        if (fp->a >= a->nreal || fp->b >= a->nreal || !cn_part_present(a, q, fp->a) || !cn_part_present(a, q, fp->b))
            continue;
        ok = add(pairs, json_pack("{s:[ss],s:f}", "parts", a->parts[fp->a].name, a->parts[fp->b].name, "mu",
                                  fp->mu));
    }
    ok = ok && put(root, "parts", json_incref(parts)) &&
         (!json_array_size(pairs) || put(root, "friction_pairs", json_incref(pairs)));
    if (ok) text = json_dumps(root, JSON_COMPACT | JSON_REAL_PRECISION(17));
    json_decref(parts), json_decref(pairs), json_decref(root);
    return text;
}

cnStatus cn_section_run(const cnAssembly *a, const cnCheckOptions *o, cnSectionCache *c, cnDiag *diag) {
    c->tried = true;
    memset(&c->rep, 0, sizeof c->rep);
    if (o->motion) return CN_OK;
    int k = cn_section_axis(a, o->query);
    if (k < 0) return CN_OK;
    char *text = section_json(a, o->query, k);
    if (!text) return cn_diag_oom(diag);
    cnAssembly *s = NULL;
    cnDiag d2;
    cnStatus st = cn_assembly_load_string(text, "section", &s, &d2);
    free(text);
    if (st == CN_ERR_MEMORY) return cn_diag_oom(diag);
    if (st) return CN_OK; /* the section is not an assembly cairn reads (parts too thin): none */
    cnCheckOptions o2 = *o;
    o2.query = NULL, o2.keep_lcp = false, o2.warm = NULL, o2.one_reading = false;
    o2.assume_planar = false, o2.progress = NULL;
    /* its search has the budget of any (a given one, or by default its own size's); without
       assume_planar a stable section decides nothing, only a motion does, which a search finds
       early: as for a group after an undecided one (search_split.c), at most
       CN_MOTION_AFTER_UNDECIDED LPs by default */
    if (!o->assume_planar && o->max_nodes <= 0) o2.max_nodes = CN_MOTION_AFTER_UNDECIDED;
    cnCheckResult r2;
    st = cn_check(s, &o2, &r2, &d2);
    if (st == CN_ERR_MEMORY) {
        cn_check_result_free(&r2), cn_assembly_free(s);
        return cn_diag_oom(diag);
    }
    c->rep.checked = true;
    c->rep.axis = k;
    /* a section cairn cannot decide (numerical trouble) is reported undecided */
    c->rep.verdict = st == CN_OK ? r2.verdict : CN_VERDICT_UNDECIDED;
    c->rep.proof = st == CN_OK ? r2.proof : CN_PROOF_NONE;
    c->rep.search_nodes = st == CN_OK ? r2.solver.search_nodes : 0;
    if (st == CN_OK && r2.verdict == CN_VERDICT_NOT_GUARANTEED && r2.part && !c->motion) {
        /* the section's parts are the present ones in order: the motion back in 3-D axes */
        c->motion = cn_calloc((size_t)a->nreal * 6 + 1, sizeof(double));
        if (!c->motion) {
            cn_check_result_free(&r2), cn_assembly_free(s);
            return cn_diag_oom(diag);
        }
        int u = (k + 1) % 3, w = (k + 2) % 3;
        for (int p = 0, i = 0; p < a->nreal; p++) {
            if (!cn_part_present(a, o->query, p)) continue;
            const cnPartMotion *pm = &r2.part[i++];
            double *x = c->motion + (size_t)p * 6;
            x[u] = pm->lin[0], x[w] = pm->lin[1], x[3 + k] = pm->ang[2];
        }
    }
    cn_check_result_free(&r2), cn_assembly_free(s);
    return CN_OK;
}
