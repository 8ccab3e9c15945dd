/* The interactive report: one self-contained HTML page. The data (parts, runs, samples, contact
 * forces) is a JSON object in the page; the viewer (html/viewer.js, and three.js for 3-D, from
 * Debian's libjs-three) is inlined at build time (tools/embed.c), so the page fetches nothing. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cairn/cairn.h"
#include "core.h"

extern const unsigned char cn_html_viewer_js[], cn_html_viewer_css[], cn_html_three_js[], cn_html_orbit_js[];
extern const unsigned long cn_html_viewer_js_len, cn_html_viewer_css_len, cn_html_three_js_len, cn_html_orbit_js_len;

/* jansson's setters take the new value's reference; a NULL value (out of memory) is caught by
 * the final dump, which then fails */
static json_t *vec(const double *v, int n) {
    json_t *a = json_array();
    for (int i = 0; i < n; i++) json_array_append_new(a, json_real(isfinite(v[i]) ? v[i] : 0.0));
    return a;
}

static json_t *part_json(const cnAssembly *a, int i) {
    const cnPart *p = &a->parts[i];
    json_t *o = json_object(), *pieces = json_array();
    json_object_set_new(o, "name", json_string(p->name));
    json_object_set_new(o, "fixed", json_boolean(p->fixed));
    for (int k = 0; k < p->npieces; k++) {
        const cnPiece *pc = &p->pieces[k];
        json_t *po = json_object(), *verts = json_array();
        for (int v = 0; v < pc->nverts; v++) json_array_append_new(verts, vec(pc->verts[v], a->dim));
        json_object_set_new(po, "verts", verts);
        if (a->dim == 3) {
            json_t *faces = json_array();
            for (int f = 0; f < pc->nfaces; f++) {
                json_t *loop = json_array();
                for (int v = 0; v < pc->faces[f].nverts; v++) json_array_append_new(loop, json_integer(pc->faces[f].verts[v]));
                json_array_append_new(faces, loop);
            }
            json_object_set_new(po, "faces", faces);
        }
        json_array_append_new(pieces, po);
    }
    json_object_set_new(o, "pieces", pieces);
    if (p->noutline > 0) { /* split from a non-convex outline: the outline is drawn */
        json_t *ol = json_array();
        for (int v = 0; v < p->noutline; v++) json_array_append_new(ol, vec(p->outline[v], a->dim));
        json_object_set_new(o, "outline", ol);
    }
    json_object_set_new(o, "label", vec(p->com, a->dim));
    return o;
}

/* Grow the box lo..hi by the corners of part i's box under pose q. */
static void grow(const cnAssembly *a, int i, const cnPose *q, double lo[3], double hi[3]) {
    const cnPart *p = &a->parts[i];
    for (int c = 0; c < 8; c++) {
        double x[3] = {c & 1 ? p->hi[0] : p->lo[0], c & 2 ? p->hi[1] : p->lo[1], c & 4 ? p->hi[2] : p->lo[2]};
        cn_pose_apply(q, x, x);
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], x[k]), hi[k] = fmax(hi[k], x[k]);
    }
}

/* One run (a simulation) as the viewer reads it; the box lo..hi grows by where its parts go. */
static json_t *run_json(const cnAssembly *a, const cnSimResult *R, const char *label, const char *detail,
                        double lo[3], double hi[3]) {
    json_t *o = json_object(), *steps = json_array(), *samples = json_array();
    json_object_set_new(o, "label", json_string(label));
    if (detail) json_object_set_new(o, "detail", json_string(detail));
    json_object_set_new(o, "assemble", json_boolean(R->assemble));
    json_object_set_new(o, "stable", json_boolean(R->stable));
    json_object_set_new(o, "verdict", json_string(R->stable ? "stable" : R->undecided ? "undecided" : "not stable"));
    double t_end = 0, fmx = 0;
    for (int k = 0; k < R->nsteps; k++) {
        const cnStepResult *s = &R->steps[k];
        const cnPlanStep *ps = &a->plan[R->plan_index[k]];
        json_t *so = json_object(), *move = json_array(), *carry = json_array();
        for (int i = 0; i < ps->nmove; i++) json_array_append_new(move, json_integer(ps->move[i]));
        json_object_set_new(so, "move", move);
        json_object_set_new(so, "status", json_string(cn_step_status_word(s->status)));
        json_object_set_new(so, "t0", json_real(s->t0));
        json_object_set_new(so, "t1", json_real(s->t1));
        if (s->has_onset && s->status != CN_STEP_STABLE) {
            json_t *on = json_object(), *mv = json_array();
            for (int i = 0; i < s->onset.nmoving; i++) json_array_append_new(mv, json_integer(s->onset.moving[i]));
            if (s->status == CN_STEP_INFEASIBLE && s->blocking_part >= 0) json_array_append_new(mv, json_integer(s->blocking_part));
            json_object_set_new(on, "time", json_real(s->onset_time));
            json_object_set_new(on, "moving", mv);
            json_object_set_new(on, "after", json_boolean(s->onset_after));
            json_object_set_new(so, "onset", on);
        } else {
            json_object_set_new(so, "onset", json_null());
        }
        for (int c = 0; c < s->ncarry; c++) {
            double iv[2] = {s->carry[c].t0, s->carry[c].t1};
            json_array_append_new(carry, vec(iv, 2));
        }
        json_object_set_new(so, "carry", carry);
        json_array_append_new(steps, so);
        t_end = fmax(t_end, s->t1);
        if (s->has_onset) t_end = fmax(t_end, s->onset_time);
    }
    for (int k = 0; k < R->nsamples; k++) {
        const cnSimSample *sm = &R->samples[k];
        json_t *so = json_object(), *cs = json_array();
        json_object_set_new(so, "t", json_real(sm->time));
        json_object_set_new(so, "step", json_integer(sm->step));
        json_object_set_new(so, "q", vec(sm->pose.q, 4));
        json_object_set_new(so, "p", vec(sm->pose.t, 3));
        json_object_set_new(so, "stable", json_boolean(sm->stable));
        json_object_set_new(so, "held", json_boolean(sm->held));
        if (isfinite(sm->margin[0]) || isfinite(sm->margin[1]) || isfinite(sm->margin[2])) {
            /* simulate --margin: critical friction, tilt (degrees), lateral factor (g); null: not found */
            json_t *m = json_array();
            for (int i = 0; i < 3; i++)
                json_array_append_new(m, isfinite(sm->margin[i]) ? json_real(i == 1 ? sm->margin[i] * 180 / CN_PI : sm->margin[i])
                                                                 : json_null());
            json_object_set_new(so, "m", m);
        }
        for (int c = sm->first; c < sm->first + sm->count; c++) {
            const cnSimContact *ct = &R->contacts[c];
            double row[9] = {ct->body1, ct->body2, ct->point[0], ct->point[1], ct->point[2],
                             ct->normal[0], ct->normal[1], ct->normal[2], ct->force};
            json_t *r = vec(row, 9);
            json_array_set_new(r, 0, json_integer(ct->body1));
            json_array_set_new(r, 1, json_integer(ct->body2));
            json_array_append_new(cs, r);
            if (isfinite(ct->force)) fmx = fmax(fmx, ct->force);
        }
        json_object_set_new(so, "c", cs);
        json_array_append_new(samples, so);
        t_end = fmax(t_end, sm->time);
        const cnPlanStep *ps = &a->plan[R->plan_index[sm->step]];
        for (int i = 0; i < ps->nmove; i++) grow(a, ps->move[i], &sm->pose, lo, hi);
    }
    json_object_set_new(o, "steps", steps);
    json_object_set_new(o, "samples", samples);
    json_object_set_new(o, "t_end", json_real(t_end));
    json_object_set_new(o, "max_force", json_real(fmx));
    return o;
}

/* The page: style, the skeleton, three.js (3-D), the data, the viewer. */
static bool write_page(FILE *f, const cnAssembly *a, const char *data) {
    const char *title = a->name ? a->name : "cairn";
    fputs("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>", f);
    for (const char *c = title; *c; c++) { /* the name as text */
        if (*c == '<') fputs("&lt;", f);
        else if (*c == '&') fputs("&amp;", f);
        else fputc(*c, f);
    }
    fputs(" \xe2\x80\x94 cairn</title>\n"
          /* any script error is kept on the page, for its tests and its readers */
          "<script>window.addEventListener(\"error\", function (e) { document.documentElement.dataset.errors = "
          "(document.documentElement.dataset.errors || \"\") + e.message + \"; \"; });</script>\n<style>\n", f);
    fwrite(cn_html_viewer_css, 1, cn_html_viewer_css_len, f);
    fputs("</style></head>\n<body>\n"
          "<header><h1 id=\"title\"></h1><div id=\"subtitle\"></div><div id=\"verdict\"></div></header>\n"
          "<main>\n<div id=\"scene\"></div>\n"
          "<div id=\"controls\"><button id=\"play\">\xe2\x96\xb6 play</button>"
          "<input type=\"range\" id=\"slider\" min=\"0\" max=\"1\" step=\"any\" value=\"0\" aria-label=\"time\">"
          "<span>t = <b id=\"time\">0</b></span><button id=\"to-onset\">go to onset</button></div>\n"
          "<div id=\"status\"></div>\n"
          "<div class=\"legend\">contacts coloured by force (light blue low, dark blue high), arrows along the normal "
          "scaled by force; parts that start to move in red from the onset on. The plot: the force each pair "
          "of parts carries over the weight W of the heaviest part (shaded: the gripper carries the pushed "
          "part; dashed: onsets). Click the plot to move the time.</div>\n"
          "<div id=\"plot\"></div>\n"
          "<table><thead><tr><th>run</th><th>verdict (simulated again)</th><th id=\"detail-head\">in the "
          "plan's table</th></tr></thead><tbody id=\"runs\"></tbody></table>\n"
          "</main>\n<footer>cairn ",
          f);
    fputs(cn_version(), f);
    fputs(" \xe2\x80\x94 drag to orbit (3-D), click a row to play it</footer>\n", f);
    if (a->dim == 3) {
        fputs("<script>\n", f);
        fwrite(cn_html_three_js, 1, cn_html_three_js_len, f);
        fputs("\n</script>\n<script>\n", f);
        fwrite(cn_html_orbit_js, 1, cn_html_orbit_js_len, f);
        fputs("\n</script>\n", f);
    }
    fputs("<script>\nconst CAIRN = ", f);
    /* '<' only occurs inside JSON strings: as \u003c no name can open or close a tag, or a
       comment, in the script */
    for (const char *c = data; *c; c++) {
        if (*c == '<') fputs("\\u003c", f);
        else fputc(*c, f);
    }
    fputs(";\n</script>\n<script>\n", f);
    fwrite(cn_html_viewer_js, 1, cn_html_viewer_js_len, f);
    fputs("</script>\n</body></html>\n", f);
    return !ferror(f);
}

/* The heaviest free part's weight: the plot's unit. */
static double ref_weight(const cnAssembly *a) {
    double w = 0;
    for (int i = 0; i < a->nreal; i++)
        if (!a->parts[i].fixed) w = fmax(w, cn_part_weight(a, i));
    return w > 0 ? w : 1.0;
}

cnStatus cn_figure_html(const char *path, const cnAssembly *const *asms, const cnSimResult *const *runs,
                        const char *const *labels, const char *const *details, int nruns, const char *subtitle,
                        cnDiag *diag) {
    const cnAssembly *a = asms[0];
    json_t *d = json_object(), *parts = json_array(), *rs = json_array();
    double lo[3], hi[3];
    for (int k = 0; k < 3; k++) lo[k] = a->lo[k], hi[k] = a->hi[k];
    json_object_set_new(d, "format_version", json_integer(CN_JSON_FORMAT_VERSION));
    json_object_set_new(d, "name", json_string(a->name ? a->name : ""));
    if (subtitle) json_object_set_new(d, "subtitle", json_string(subtitle));
    json_object_set_new(d, "dimension", json_integer(a->dim));
    json_object_set_new(d, "gravity", vec(a->gravity, 3));
    json_object_set_new(d, "ref_weight", json_real(ref_weight(a)));
    for (int i = 0; i < a->nreal; i++) json_array_append_new(parts, part_json(a, i));
    json_object_set_new(d, "parts", parts);
    for (int r = 0; r < nruns; r++) {
        /* each run's own box (the view while it plays), and the box of them all */
        double rlo[3], rhi[3];
        for (int k = 0; k < 3; k++) rlo[k] = a->lo[k], rhi[k] = a->hi[k];
        json_t *run = run_json(asms[r], runs[r], labels[r], details ? details[r] : NULL, rlo, rhi);
        json_t *rbox = json_array();
        json_array_append_new(rbox, vec(rlo, 3));
        json_array_append_new(rbox, vec(rhi, 3));
        json_object_set_new(run, "bounds", rbox);
        json_array_append_new(rs, run);
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], rlo[k]), hi[k] = fmax(hi[k], rhi[k]);
    }
    json_object_set_new(d, "runs", rs);
    json_t *box = json_array();
    json_array_append_new(box, vec(lo, 3));
    json_array_append_new(box, vec(hi, 3));
    json_object_set_new(d, "bounds", box);
    /* "</script>" cannot appear: every '/' is escaped */
    char *data = json_dumps(d, JSON_COMPACT | JSON_ESCAPE_SLASH | JSON_REAL_PRECISION(8));
    json_decref(d);
    if (!data) return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory writing the interactive report");
    FILE *f = fopen(path, "w");
    if (!f) {
        free(data);
        return cn_diag_set(diag, CN_ERR_IO, "", "cannot write the interactive report");
    }
    bool ok = write_page(f, a, data);
    free(data);
    if (fclose(f) != 0 || !ok) return cn_diag_set(diag, CN_ERR_IO, "", "cannot write the interactive report");
    return CN_OK;
}

cnStatus cn_figure_simulation_html(const char *path, const cnAssembly *a, const cnSimResult *dis,
                                   const cnSimResult *assembly, cnDiag *diag) {
    const cnSimResult *runs[2] = {dis, assembly};
    const cnAssembly *asms[2] = {a, a};
    const char *labels[2] = {"disassembly", "assembly (the plan reversed)"};
    return cn_figure_html(path, asms, runs, labels, NULL, assembly ? 2 : 1, "the plan simulated along its paths", diag);
}
