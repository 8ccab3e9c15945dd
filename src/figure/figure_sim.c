/* Figures of a simulation: each failing step drawn at its start, its onset and its end, the forces
 * at its contacts and its margins against time. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <sys/stat.h>

#include "figure_scene.h"
#include "core.h"

typedef struct {
    int b1, b2, key; /* key: vertex number, or -id when the point is on no vertex */
    int n, cap;
    double *t, *y;
    int na, capa;
    double *ta, *ya; /* positive separation accelerations (in g) */
    double fmax;
    char label[96];
} Series;

static int series_of(Series **ss, int *ns, int *cap, const cnAssembly *a, int b1, int b2, int key) {
    for (int i = 0; i < *ns; i++)
        if ((*ss)[i].b1 == b1 && (*ss)[i].b2 == b2 && (*ss)[i].key == key) return i;
    if (*ns == *cap) {
        int nc = *cap ? 2 * *cap : 16;
        Series *n = cn_realloc(*ss, sizeof(Series) * (size_t)nc);
        if (!n) return -1;
        *ss = n;
        *cap = nc;
    }
    Series *s = &(*ss)[(*ns)++];
    memset(s, 0, sizeof *s);
    s->b1 = b1, s->b2 = b2, s->key = key;
    char v[24] = "";
    if (key > 0) snprintf(v, sizeof v, "%d ", key);
    snprintf(s->label, sizeof s->label, "%s%s/%s", v, b1 < 0 ? "fixel" : a->parts[b1].name,
             a->parts[b2].name);
    return *ns - 1;
}

static int push_pt(double **t, double **y, int *n, int *cap, double tv, double yv) {
    if (*n == *cap) {
        int nc = *cap ? 2 * *cap : 32;
        double *nt = cn_realloc(*t, sizeof(double) * (size_t)nc);
        if (!nt) return -1;
        *t = nt;
        double *ny = cn_realloc(*y, sizeof(double) * (size_t)nc);
        if (!ny) return -1;
        *y = ny;
        *cap = nc;
    }
    (*t)[*n] = tv, (*y)[*n] = yv, (*n)++;
    return 0;
}

static int cmp_series(const void *x, const void *y) {
    double a = ((const Series *)x)->fmax, b = ((const Series *)y)->fmax;
    return (a < b) - (a > b);
}

static cnStatus step_plot(const char *base, const cnAssembly *a, const cnSimResult *R, int kk,
                          const char *title, cnDiag *diag) {
    const cnStepResult *out = &R->steps[kk];
    double W = out->weight > 0 ? out->weight : 1, g = cn_norm3(a->gravity);
    Series *ss = NULL;
    int ns = 0, cap = 0;
    cnStatus st = CN_OK;
    for (int j = out->first_sample; j < out->first_sample + out->nsamples && !st; j++) {
        const cnSimSample *sm = &R->samples[j];
        for (int c = sm->first; c < sm->first + sm->count && !st; c++) {
            const cnSimContact *x = &R->contacts[c];
            int i = series_of(&ss, &ns, &cap, a, x->body1, x->body2, x->vertex ? x->vertex : -x->id);
            if (i < 0 || push_pt(&ss[i].t, &ss[i].y, &ss[i].n, &ss[i].cap, sm->time, x->force / W))
                st = CN_ERR_MEMORY;
            else if (x->separates &&
                     push_pt(&ss[i].ta, &ss[i].ya, &ss[i].na, &ss[i].capa, sm->time, x->motion / g))
                st = CN_ERR_MEMORY;
            if (i >= 0) ss[i].fmax = fmax(ss[i].fmax, x->force / W);
        }
    }
    /* the state at the onset */
    if (!st && out->has_onset && out->status == CN_STEP_UNSTABLE && out->onset.contact) {
        for (int c = 0; c < out->onset.contacts.count && !st; c++) {
            const cnContact *ct = &out->onset.contacts.items[c];
            const cnContactResult *cr = &out->onset.contact[c];
            int i = series_of(&ss, &ns, &cap, a, ct->body1, ct->body2, ct->vertex ? ct->vertex : -ct->id);
            if (i < 0 || push_pt(&ss[i].t, &ss[i].y, &ss[i].n, &ss[i].cap, out->onset_time, cr->normal_force / W))
                st = CN_ERR_MEMORY;
            else if (cr->separates && push_pt(&ss[i].ta, &ss[i].ya, &ss[i].na, &ss[i].capa,
                                              out->onset_time, cr->separation / g))
                st = CN_ERR_MEMORY;
        }
    }
    if (st) {
        st = cn_diag_oom(diag);
    } else {
        qsort(ss, (size_t)ns, sizeof(Series), cmp_series);
        int keep = ns < 24 ? ns : 24;
        int nalarm = 0;
        for (int i = 0; i < keep; i++) nalarm += ss[i].na > 0;
        cnPlotSeries *ps = cn_calloc((size_t)(keep + nalarm + 1), sizeof(cnPlotSeries));
        char(*alabels)[128] = cn_calloc((size_t)nalarm + 1, sizeof(char[128]));
        if (!ps || !alabels) st = cn_diag_oom(diag);
        else {
            int m = 0, q = 0;
            for (int i = 0; i < keep; i++) {
                ps[m].label = ss[i].label, ps[m].n = ss[i].n, ps[m].t = ss[i].t, ps[m].y = ss[i].y;
                m++;
            }
            for (int i = 0; i < keep; i++) {
                if (!ss[i].na) continue;
                snprintf(alabels[q], sizeof alabels[q], "accel. at %s (g)", ss[i].label);
                ps[m].label = alabels[q++], ps[m].n = ss[i].na, ps[m].t = ss[i].ta, ps[m].y = ss[i].ya;
                ps[m].alarm = true;
                m++;
            }
            char sub[256];
            if (out->status == CN_STEP_UNSTABLE)
                snprintf(sub, sizeof sub, "unstable at t = %.6g (red: positive separation accelerations)",
                         out->onset_time);
            else if (out->status == CN_STEP_INFEASIBLE)
                snprintf(sub, sizeof sub, "geometrically infeasible at t = %.6g", out->onset_time);
            else if (out->status == CN_STEP_UNDECIDED)
                snprintf(sub, sizeof sub, "undecided at t = %.6g (not proved stable)", out->onset_time);
            else snprintf(sub, sizeof sub, "stable throughout");
            double x1 = out->t1 > out->t0 ? out->t1 : out->t0 + 1;
            double(*band)[2] = cn_calloc((size_t)out->ncarry + 1, sizeof(double[2]));
            char blabel[160];
            snprintf(blabel, sizeof blabel, "gripper carries %s",
                     out->ncarry > 0 && out->carry[0].part >= 0 ? a->parts[out->carry[0].part].name : "the part");
            for (int c = 0; band && c < out->ncarry; c++) band[c][0] = out->carry[c].t0, band[c][1] = out->carry[c].t1;
            cnPlot p = {title, sub, "time", "contact force / weight of the moved parts",
                        out->status != CN_STEP_STABLE, out->t0, x1,
                        out->has_onset && out->status != CN_STEP_STABLE, out->onset_time, m, ps,
                        band ? out->ncarry : 0, (const double(*)[2])band, blabel};
            st = cn_plot_write(base, &p, diag);
            cn_free(band);
        }
        cn_free(ps);
        cn_free(alabels);
    }
    for (int i = 0; i < ns; i++) {
        cn_free(ss[i].t);
        cn_free(ss[i].y);
        cn_free(ss[i].ta);
        cn_free(ss[i].ya);
    }
    cn_free(ss);
    return st;
}

/* simulate --margin: a stable step's margins at its samples against time (tilt in radians, so
 * that the three share an axis), the weakest of each marked by its value in the legend. No file
 * when the step has none. A lateral factor over the whole range searched is left out (it would
 * flatten the rest); so is a critical friction of none (+inf). */
static cnStatus margin_plot(const char *base, const cnSimResult *R, int kk, const char *title, cnDiag *diag) {
    const cnStepResult *out = &R->steps[kk];
    static const char *const names[3] = {"crit. friction", "tilt (rad)", "lateral (g)"};
    double *t = cn_calloc((size_t)out->nsamples * 3 + 1, sizeof(double));
    double *y = cn_calloc((size_t)out->nsamples * 3 + 1, sizeof(double));
    cnPlotSeries ps[3];
    char labels[3][96];
    int m = 0;
    if (!t || !y) {
        cn_free(t), cn_free(y);
        return cn_diag_oom(diag);
    }
    for (int k = 0; k < 3; k++) {
        const cnStepMargin *w = &out->margin[k];
        if (!w->computed) continue;
        double *tk = t + (size_t)k * (size_t)out->nsamples, *yk = y + (size_t)k * (size_t)out->nsamples;
        int n = 0;
        for (int j = 0; j < out->nsamples; j++) {
            const cnSimSample *sm = &R->samples[out->first_sample + j];
            double v = sm->margin[k];
            if (!isfinite(v) || (k == 2 && v >= CN_MARGIN_MAX_LATERAL)) continue;
            tk[n] = sm->time, yk[n] = v, n++;
        }
        if (n == 0) continue;
        snprintf(labels[m], sizeof labels[m], "%s: weakest %.3g, t %.3g", names[k], w->at.value, w->time);
        ps[m] = (cnPlotSeries){labels[m], n, tk, yk, false};
        m++;
    }
    cnStatus st = CN_OK;
    if (m > 0) {
        char sub[160];
        snprintf(sub, sizeof sub, "margins at %d of its %d samples (simulate --margin)", out->margin[0].computed
                 ? out->margin[0].samples : out->margin[1].computed ? out->margin[1].samples : out->margin[2].samples,
                 out->nsamples);
        double x1 = out->t1 > out->t0 ? out->t1 : out->t0 + 1;
        cnPlot p = {title, sub, "time", "margin (critical friction; tilt in radians; lateral in g)", false, out->t0, x1,
                    false, 0, m, ps, 0, NULL, NULL};
        st = cn_plot_write(base, &p, diag);
    }
    cn_free(t);
    cn_free(y);
    return st;
}

/* Every part where it was loaded, the moved parts of step ps (and its gripper) at pose p. */
static void place_moved(cnPose *pose, int np, const cnPlanStep *ps, const cnPose *p) {
    for (int i = 0; i < np; i++) pose[i] = cn_pose_identity();
    for (int i = 0; i < ps->nmove; i++) pose[ps->move[i]] = *p;
    if (ps->gripper >= 0) pose[ps->gripper] = *p;
}

/* The onset picture of a step: its contacts into fc (how many), the parts that start to move
 * into red (and *motion), its verdict line. */
static int onset_picture(const cnAssembly *a, const cnStepResult *out, FigContact *fc,
                         unsigned char *red, const unsigned char *gripped,
                         const cnPartMotion **motion, char *verdict, size_t cap) {
    int nc = 0, np = a->nparts;
    double t = out->onset_time;
    if (out->onset.contact) {
        for (int c = 0; c < out->onset.contacts.count; c++) {
            const cnContact *ct = &out->onset.contacts.items[c];
            FigContact *f = &fc[nc++];
            memset(f, 0, sizeof *f);
            f->id = ct->id;
            cn_copy3(f->point, ct->point);
            cn_copy3(f->normal, ct->normal);
            f->force = out->onset.contact[c].normal_force;
            cn_copy3(f->friction, out->onset.contact[c].friction);
            f->separates = out->onset.contact[c].separates;
            f->slides = out->onset.contact[c].slides;
        }
        *motion = out->onset.part;
        for (int i = 0; i < np; i++) red[i] = out->onset.part[i].moves && !gripped[i];
    }
    if (out->status == CN_STEP_INFEASIBLE)
        snprintf(verdict, cap, "t = %.6g: %s would penetrate %s", t,
                 out->blocked_part >= 0 ? a->parts[out->blocked_part].name : "?",
                 out->blocking_part >= 0 ? a->parts[out->blocking_part].name : "?");
    else if (out->status == CN_STEP_UNDECIDED)
        snprintf(verdict, cap, "t = %.6g: UNDECIDED%s: a static solution, "
                 "no motion from rest found or ruled out", t,
                 out->onset_after ? " once the moved parts are away" : "");
    else {
        int len = snprintf(verdict, cap, "t = %.6g: UNSTABLE%s, moving", t,
                           out->onset_after ? " once the moved parts are away" : "");
        for (int i = 0; i < out->onset.nmoving && len < (int)cap - 40; i++)
            len += snprintf(verdict + len, cap - (size_t)len, " %s", a->parts[out->onset.moving[i]].name);
    }
    return nc;
}

/* The picture of a recorded sample (a step's start or end): its contacts into fc (how many), its
 * verdict line. */
static int sample_picture(const cnSimResult *R, const cnSimSample *sm, FigContact *fc, char *verdict,
                          size_t cap) {
    int nc = 0;
    for (int c = sm->first; c < sm->first + sm->count; c++) {
        const cnSimContact *x = &R->contacts[c];
        FigContact *f = &fc[nc++];
        memset(f, 0, sizeof *f);
        f->id = x->id;
        cn_copy3(f->point, x->point);
        cn_copy3(f->normal, x->normal);
        f->force = x->force;
        f->separates = x->separates;
        f->slides = x->slides;
    }
    snprintf(verdict, cap, "t = %.6g: %s", sm->time, sm->stable ? "stable" : "not stable");
    return nc;
}

cnStatus cn_figure_simulation(const char *dir, const cnAssembly *a, const cnSimResult *R,
                              cnDiag *diag) {
    if (mkdir(dir, 0777) != 0 && errno != EEXIST)
        return cn_diag_set(diag, CN_ERR_IO, "", "cannot create the directory %s: %s", dir,
                           strerror(errno));
    cnFigureOptions o = cn_figure_options_default();
    int np = a->nparts;
    unsigned char *absent = cn_malloc((size_t)np), *red = cn_malloc((size_t)np),
                  *gripped = cn_malloc((size_t)np);
    cnPose *off = cn_calloc((size_t)np, sizeof(cnPose));
    int maxc = 1;
    for (int j = 0; j < R->nsamples; j++) maxc = R->samples[j].count > maxc ? R->samples[j].count : maxc;
    for (int kk = 0; kk < R->nsteps; kk++)
        if (R->steps[kk].onset.contacts.count > maxc) maxc = R->steps[kk].onset.contacts.count;
    FigContact *fc = cn_calloc((size_t)maxc + 1, sizeof(FigContact));
    cnStatus st = CN_OK;
    if (!absent || !red || !gripped || !off || !fc)
        st = cn_diag_oom(diag);
    const char *prefix = R->assemble ? "assembly-" : "";
    for (int kk = 0; kk < R->nsteps && !st; kk++) {
        const cnStepResult *out = &R->steps[kk];
        const cnPlanStep *ps = &a->plan[R->plan_index[kk]];
        if (out->status == CN_STEP_SKIPPED || out->nsamples == 0) continue;
        /* the scene of this step: parts moved by other steps before it are gone (disassembly) or
         * not yet there (assembly) */
        for (int i = 0; i < np; i++) absent[i] = a->parts[i].gripper_step >= 0 && i != ps->gripper;
        for (int jj = 0; jj < R->nsteps; jj++) {
            bool gone = R->assemble ? jj > kk : jj < kk;
            if (!gone) continue;
            const cnPlanStep *o2 = &a->plan[R->plan_index[jj]];
            for (int i = 0; i < o2->nmove; i++) absent[o2->move[i]] = 1;
        }
        memset(red, 0, (size_t)np);
        memset(gripped, 0, (size_t)np);
        for (int i = 0; i < ps->nmove; i++) gripped[ps->move[i]] = 1;
        char names[256] = "";
        for (int i = 0; i < ps->nmove; i++) {
            strncat(names, i ? ", " : "", sizeof names - strlen(names) - 1);
            strncat(names, a->parts[ps->move[i]].name, sizeof names - strlen(names) - 1);
        }
        char title[512], path[1024], verdict[512];
        /* poses to fit the view on: start, onset or end */
        const cnSimSample *first = &R->samples[out->first_sample];
        const cnSimSample *last = &R->samples[out->first_sample + out->nsamples - 1];
        cnPose *off2 = cn_calloc((size_t)np, sizeof(cnPose));
        if (!off2) {
            st = cn_diag_oom(diag);
            break;
        }
        place_moved(off2, np, ps, out->has_onset ? &out->onset_pose : &last->pose);
        Scene fit2 = {off2, absent, 0, NULL, NULL, red, false, NULL, gripped};
        for (int pic = 0; pic < 3 && !st; pic++) {
            /* 0: start, 1: onset (when there is one), 2: end (when stable) */
            if (pic == 1 && !out->has_onset) continue;
            if (pic == 2 && out->status != CN_STEP_STABLE) continue;
            const cnSimSample *sm = pic == 0 ? first : last;
            place_moved(off, np, ps, pic == 1 ? &out->onset_pose : &sm->pose);
            int nc = 0;
            const cnPartMotion *motion = NULL;
            bool bad = false;
            if (pic == 1) {
                bad = true;
                nc = onset_picture(a, out, fc, red, gripped, &motion, verdict, sizeof verdict);
            } else {
                nc = sample_picture(R, sm, fc, verdict, sizeof verdict);
                bad = !sm->stable;
            }
            if (cn_path_turns(ps->seg, ps->nseg)) {
                size_t len = strlen(verdict);
                double ang = (pic == 1 ? out->onset_angle : sm->angle) * 180 / CN_PI;
                snprintf(verdict + len, sizeof verdict - len, " (turned %.4g deg)", fabs(ang) < 5e-5 ? 0.0 : ang);
            }
            Scene sc = {off, absent, nc, fc, motion, red, pic == 1 && out->onset.friction, NULL, gripped};
            Scene fit1 = {NULL, absent, 0, NULL, NULL, red, false, NULL, gripped};
            cnPose *off0 = cn_calloc((size_t)np, sizeof(cnPose));
            if (!off0) {
                st = cn_diag_oom(diag);
                break;
            }
            place_moved(off0, np, ps, &first->pose);
            fit1.pose = off0;
            const Scene *fitp[2] = {&fit1, &fit2};
            static const char *which[3] = {"start", "onset", "end"};
            snprintf(title, sizeof title, "%s step %d: %s %s (%s), %s", R->assemble ? "assembly" : "disassembly",
                     kk + 1, R->assemble ? "insert" : "move", names,
                     ps->support == CN_SUPPORT_PUSH ? "pushed" : "held", which[pic]);
            snprintf(path, sizeof path, "%s/%sstep%d-%s", dir, prefix, kk + 1, which[pic]);
            char legend[512];
            snprintf(legend, sizeof legend, "%s%s", CN_FG_LEGEND_STEP, sc.friction ? CN_FG_LEGEND_F : CN_FG_LEGEND);
            Render Rd = {a, &sc, fitp, 2, &o, title, verdict, legend, bad, out->weight, NULL};
            st = cn_fg_render_files(path, 3, &Rd, diag);
            cn_free(off0);
        }
        cn_free(off2);
        if (st) break;
        snprintf(title, sizeof title, "%s step %d: %s %s (%s)", R->assemble ? "assembly" : "disassembly",
                 kk + 1, R->assemble ? "insert" : "move", names,
                 ps->support == CN_SUPPORT_PUSH ? "pushed" : "held");
        snprintf(path, sizeof path, "%s/%sstep%d-forces", dir, prefix, kk + 1);
        st = step_plot(path, a, R, kk, title, diag);
        if (!st) {
            snprintf(path, sizeof path, "%s/%sstep%d-margin", dir, prefix, kk + 1);
            st = margin_plot(path, R, kk, title, diag);
        }
    }
    cn_free(absent);
    cn_free(red);
    cn_free(gripped);
    cn_free(off);
    cn_free(fc);
    return st;
}
