/* Figures of an assembly and its check, and of a margin's collapse mechanism (scenes drawn by
 * figure_scene.c; a simulation's figures are figure_sim.c's). */
#include <stdio.h>
#include <string.h>

#include "figure_scene.h"
#include "core.h"

/* A collapse figure turns a moving part by at most this (radians) */
#define FIG_COLLAPSE_TURN 0.2

cnFigureOptions cn_figure_options_default(void) {
    cnFigureOptions o = {900, 640, true, true};
    return o;
}

/* A check's contacts as drawn: points, normals, open and sliding, and (forces) their forces. */
void cn_fg_contacts(const cnCheckResult *r, int nc, bool forces, FigContact *fc) {
    for (int c = 0; c < nc; c++) {
        const cnContact *ct = &r->contacts.items[c];
        fc[c].id = ct->id;
        cn_copy3(fc[c].point, ct->point);
        cn_copy3(fc[c].normal, ct->normal);
        if (!r->contact) continue;
        if (forces) {
            fc[c].force = r->contact[c].normal_force;
            cn_copy3(fc[c].friction, r->contact[c].friction);
        }
        fc[c].separates = r->contact[c].separates;
        fc[c].slides = r->contact[c].slides;
    }
}

cnStatus cn_figure_check_png(const char *path, const cnAssembly *a, const cnCheckResult *r,
                             const cnFigureOptions *opt, cnDiag *diag) {
    cnFigureOptions o = opt ? *opt : cn_figure_options_default();
    int nc = r ? r->contacts.count : 0;
    FigContact *fc = cn_calloc((size_t)nc + 1, sizeof(FigContact));
    unsigned char *red = cn_calloc((size_t)a->nparts + 1, 1);
    if (!fc || !red) {
        cn_free(fc);
        cn_free(red);
        return cn_diag_oom(diag);
    }
    cn_fg_contacts(r, nc, true, fc);
    for (int i = 0; r && r->part && i < a->nparts; i++) red[i] = r->part[i].moves;
    Scene sc = {NULL, NULL, nc, fc, r ? r->part : NULL, red, r && r->friction, NULL, NULL};
    const Scene *fitp[1] = {&sc};
    char title[512], verdict[512] = "";
    snprintf(title, sizeof title, "%s", a->name ? a->name : (a->source ? a->source : "assembly"));
    if (r) {
        if (r->stable)
            snprintf(verdict, sizeof verdict, "STABLE: no part moves%s",
                     r->proof == CN_PROOF_ACCEPTED  ? " (prestress accepted: a motion from rest was not ruled out)"
                     : r->proof == CN_PROOF_SECTION ? " (planar motion assumed: its 2-D section is proved stable)"
                                                    : "");
        else if (r->verdict == CN_VERDICT_UNDECIDED)
            snprintf(verdict, sizeof verdict, "UNDECIDED: a static solution (drawn) exists; a motion from rest was not ruled out");
        else {
            int len = snprintf(verdict, sizeof verdict, "%s",
                               r->verdict == CN_VERDICT_NOT_GUARANTEED
                                   ? "NOT GUARANTEED: held only by the squeeze drawn; can also move:"
                                   : "UNSTABLE: moving");
            for (int i = 0; i < r->nmoving && len < (int)sizeof verdict - 40; i++)
                len += snprintf(verdict + len, sizeof verdict - (size_t)len, " %s",
                                a->parts[r->moving[i]].name);
        }
    }
    Render R = {a, &sc, fitp, 1, &o, title, r ? verdict : NULL,
                r ? (r->friction ? CN_FG_LEGEND_F : CN_FG_LEGEND) : NULL, r && !r->stable, 0, NULL};
    cnStatus st = cn_fg_render_files(path, 1, &R, diag);
    cn_free(fc);
    cn_free(red);
    return st;
}

/* ---- the collapse mechanism of a margin ---- */

cnStatus cn_figure_margin(const char *path, const cnAssembly *a, const cnMargin *m, int kind,
                          const cnFigureOptions *opt, cnDiag *diag) {
    const cnCheckResult *r = &m->collapse;
    if (!m->computed || !r->part || (r->verdict != CN_VERDICT_UNSTABLE && r->verdict != CN_VERDICT_NOT_GUARANTEED))
        return cn_diag_set(diag, CN_ERR_INPUT, "", "no collapse to draw: the margin has no not-stable verdict");
    cnFigureOptions o = opt ? *opt : cn_figure_options_default();
    int nc = r->contacts.count;
    FigContact *fc = cn_calloc((size_t)nc + 1, sizeof(FigContact));
    unsigned char *red = cn_calloc((size_t)a->nparts + 1, 1);
    cnPose *moved = cn_calloc((size_t)a->nparts + 1, sizeof(cnPose));
    if (!fc || !red || !moved) {
        cn_free(fc), cn_free(red), cn_free(moved);
        return cn_diag_oom(diag);
    }
    cn_fg_contacts(r, nc, false, fc);
    /* the moving parts carried along their motion (its scale is arbitrary: it only starts) until
       the farthest point has moved a fifth of the largest moving part's size, and no part has
       turned more than FIG_COLLAPSE_TURN */
    double big = 0, size = 0, wmax = 0;
    for (int i = 0; i < a->nparts; i++) {
        const cnPartMotion *pm = &r->part[i];
        red[i] = pm->moves;
        if (!pm->moves) continue;
        double d[3];
        cn_sub3(a->parts[i].hi, a->parts[i].lo, d);
        size = fmax(size, cn_norm3(d));
        wmax = fmax(wmax, cn_norm3(pm->ang));
        big = fmax(big, cn_norm3(pm->lin) + cn_norm3(pm->ang) * 0.5 * cn_norm3(d));
    }
    double s = big > 0 ? 0.2 * size / big : 0;
    if (wmax * s > FIG_COLLAPSE_TURN) s = FIG_COLLAPSE_TURN / wmax;
    for (int i = 0; i < a->nparts; i++) {
        moved[i] = cn_pose_identity();
        if (!red[i]) continue;
        const cnPartMotion *pm = &r->part[i];
        double t[3], w = cn_norm3(pm->ang);
        for (int k = 0; k < 3; k++) t[k] = pm->lin[k] * s;
        cnPose turn = w > 0 ? cn_pose_rotation(pm->ang, w * s, a->parts[i].com) : cn_pose_identity();
        cnPose shift = cn_pose_translation(t);
        moved[i] = cn_pose_then(&turn, &shift);
    }
    Scene sc = {NULL, NULL, nc, fc, r->part, red, false, moved, NULL};
    Scene there = {moved, NULL, 0, NULL, NULL, red, false, NULL, NULL};
    const Scene *fitp[2] = {&sc, &there};
    char title[512], verdict[512];
    snprintf(title, sizeof title, "%s", a->name ? a->name : (a->source ? a->source : "assembly"));
    double deg = 180 / CN_PI;
    int len;
    if (kind == CN_MARGIN_FRICTION)
        len = snprintf(verdict, sizeof verdict, "critical friction %.6g; at %.6g:", m->value, m->mechanism_at);
    else if (kind == CN_MARGIN_TILT)
        len = snprintf(verdict, sizeof verdict, "tilt %.5g deg; turned %.5g deg:", m->value * deg, m->mechanism_at * deg);
    else
        len = snprintf(verdict, sizeof verdict, "lateral %.5g g; at %.5g g:", m->value, m->mechanism_at);
    len += snprintf(verdict + len, sizeof verdict - (size_t)len, " %s",
                    r->verdict == CN_VERDICT_NOT_GUARANTEED ? "not guaranteed, can move" : "moving");
    for (int i = 0; i < r->nmoving && len < (int)sizeof verdict - 40; i++)
        len += snprintf(verdict + len, sizeof verdict - (size_t)len, " %s", a->parts[r->moving[i]].name);
    static const char *legend = "as loaded; dashed red: the moving parts carried along the motion at collapse "
                                "(exaggerated); dots: contacts (red opens, orange slides); arrow: gravity there";
    Render R = {a, &sc, fitp, 2, &o, title, verdict, legend, true, 0, m->gravity};
    cnStatus st = cn_fg_render_files(path, 1, &R, diag);
    cn_free(fc), cn_free(red), cn_free(moved);
    return st;
}
