/* The margins report (cairn margin): text and JSON. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json_out.h"
#include "cairn/margin.h"
#include "cairn/report.h"

/* Names listed in a text line at most (JSON lists every one). */
#define CN_MARGIN_TEXT_NAMES 12

static const char *end_word(cnMarginEnd e) {
    return e == CN_MARGIN_FOUND ? "found" : e == CN_MARGIN_NONE ? "none" : "whole_range";
}

static const char *side_name(const cnAssembly *a, int b) {
    return b == CN_WORLD ? "a fixel" : a->parts[b].name;
}

/* A real for JSON: +-inf and NaN have no JSON value, null stands for them. */
static json_t *real_or_null(double v) { return isfinite(v) ? json_real(v) : json_null(); }

static json_t *dir_json(const double d[3], int dim) {
    json_t *arr = json_array();
    for (int k = 0; k < dim; k++) json_array_append_new(arr, json_real(fabs(d[k]) < 1e-15 ? 0.0 : d[k]));
    return arr;
}

/* Is contact i opening (pass 0) or sliding without opening (pass 1), and the first such of its
 * pair of parts? (A mechanism lists each pair once.) */
static bool pair_first(const cnCheckResult *r, int i, int pass) {
    const cnContactResult *cr = r->contact;
    bool on = pass ? cr[i].slides && !cr[i].separates : cr[i].separates;
    if (!on) return false;
    const cnContact *c = &r->contacts.items[i];
    for (int j = 0; j < i; j++) {
        const cnContact *e = &r->contacts.items[j];
        bool onj = pass ? cr[j].slides && !cr[j].separates : cr[j].separates;
        if (onj && e->body1 == c->body1 && e->body2 == c->body2) return false;
    }
    return true;
}

/* The mechanism of a collapse verdict: the parts that move and how, and the pairs of parts
 * whose contacts open or slide (each pair once). */
static json_t *mechanism_json(const cnAssembly *a, const cnCheckResult *r) {
    json_t *o = json_object(), *mv = json_array(), *op = json_array(), *sl = json_array();
    for (int i = 0; i < r->nmoving; i++) {
        int p = r->moving[i];
        json_t *m = json_object();
        json_object_set_new(m, "part", json_string(a->parts[p].name));
        json_object_set_new(m, "linear", dir_json(r->part[p].lin, a->dim));
        if (a->dim == 2) json_object_set_new(m, "angular", json_real(r->part[p].ang[2]));
        else json_object_set_new(m, "angular", dir_json(r->part[p].ang, 3));
        json_array_append_new(mv, m);
    }
    for (int pass = 0; pass < 2; pass++) {
        json_t *list = pass ? sl : op;
        for (int i = 0; i < r->contacts.count; i++) {
            if (!pair_first(r, i, pass)) continue;
            const cnContact *c = &r->contacts.items[i];
            json_t *pair = json_array();
            json_array_append_new(pair, json_string(side_name(a, c->body1)));
            json_array_append_new(pair, json_string(side_name(a, c->body2)));
            json_array_append_new(list, pair);
        }
    }
    json_object_set_new(o, "moving_parts", mv);
    json_object_set_new(o, "opening", op);
    json_object_set_new(o, "sliding", sl);
    return o;
}

void *cn_margin_json(const cnAssembly *a, const cnMargin *m, int kind) {
    json_t *o = json_object();
    bool angle = kind == CN_MARGIN_TILT;
    double unit = angle ? 180 / CN_PI : 1;
    const char *key = kind == CN_MARGIN_FRICTION ? "critical" : angle ? "angle" : "factor";
    json_object_set_new(o, key, real_or_null(m->value * unit));
    if (kind == CN_MARGIN_TILT) json_object_set_new(o, "axis", dir_json(m->dir, 3));
    if (kind == CN_MARGIN_LATERAL) json_object_set_new(o, "direction", dir_json(m->dir, a->dim));
    if (kind == CN_MARGIN_FRICTION) json_object_set_new(o, "as_loaded", json_real(m->base));
    json_object_set_new(o, "end", json_string(end_word(m->end)));
    json_object_set_new(o, "not_stable_at", real_or_null(m->past * unit));
    json_object_set_new(o, "verdict_there",
                        m->past_failed ? json_string("numerical_failure")
                        : isnan(m->past) ? json_null()
                                         : json_string(cn_verdict_word(m->past_verdict)));
    json_object_set_new(o, "stopped", json_boolean(m->stopped));
    bool shown = m->collapse.part && (m->collapse.verdict == CN_VERDICT_UNSTABLE ||
                                      m->collapse.verdict == CN_VERDICT_NOT_GUARANTEED);
    json_object_set_new(o, "mechanism_at", shown ? real_or_null(m->mechanism_at * unit) : json_null());
    json_object_set_new(o, "verdicts", json_integer(m->verdicts));
    json_object_set_new(o, "mechanism", shown ? mechanism_json(a, &m->collapse) : json_null());
    return o;
}

/* One line per pair of parts whose contacts open, then slide, in a collapse. */
static void mechanism_text(FILE *f, const cnAssembly *a, const cnCheckResult *r, const char *lead) {
    if (!r->part) return;
    fprintf(f, "%s      moving:", lead);
    if (r->nmoving == 0) fprintf(f, " none above the threshold");
    for (int i = 0; i < r->nmoving && i < CN_MARGIN_TEXT_NAMES; i++)
        fprintf(f, "%s %s", i ? "," : "", a->parts[r->moving[i]].name);
    if (r->nmoving > CN_MARGIN_TEXT_NAMES) fprintf(f, " and %d more (--json lists them)", r->nmoving - CN_MARGIN_TEXT_NAMES);
    fprintf(f, "\n");
    for (int pass = 0; pass < 2; pass++) {
        int n = 0;
        for (int i = 0; i < r->contacts.count; i++) {
            if (!pair_first(r, i, pass)) continue;
            const cnContact *c = &r->contacts.items[i];
            if (n++ < CN_MARGIN_TEXT_NAMES)
                fprintf(f, "%s%s %s/%s", n > 1 ? "" : lead, n > 1 ? "," : pass ? "      sliding:" : "      opening:",
                        side_name(a, c->body1), side_name(a, c->body2));
        }
        if (n > CN_MARGIN_TEXT_NAMES) fprintf(f, " and %d more pairs", n - CN_MARGIN_TEXT_NAMES);
        if (n) fprintf(f, "\n");
    }
}

static void verdict_upper(char *buf, size_t n, cnVerdict v) {
    snprintf(buf, n, "%s", cn_verdict_word(v));
    for (char *p = buf; *p; p++) *p = *p == '_' ? ' ' : (char)(*p >= 'a' && *p <= 'z' ? *p - 32 : *p);
}

void cn_margin_text(FILE *f, const cnAssembly *a, const cnMargin *m, int kind, const char *lead, const char *at) {
    char vw[48];
    verdict_upper(vw, sizeof vw, m->past_verdict);
    if (m->past_failed) snprintf(vw, sizeof vw, "NO VERDICT (numerical failure)");
    if (kind == CN_MARGIN_FRICTION) {
        fprintf(f, "%scritical friction%s: ", lead, at);
        if (m->end == CN_MARGIN_WHOLE) fprintf(f, "0: stable without friction\n");
        else if (m->end == CN_MARGIN_NONE)
            fprintf(f, "none: not stable even at friction %g (%s)\n", m->past, vw);
        else
            fprintf(f, "%.7g (as loaded %g): stable at %.7g, %s at %.7g\n", m->value, m->base, m->value, vw,
                    m->past);
    } else if (kind == CN_MARGIN_TILT) {
        double d = 180 / CN_PI;
        fprintf(f, "%stilt%s: ", lead, at);
        if (m->end == CN_MARGIN_NONE) fprintf(f, "0: not stable as loaded\n");
        else if (m->end == CN_MARGIN_WHOLE)
            fprintf(f, "stable up to 90 degrees about (%.4g, %.4g, %.4g), the whole range searched\n", m->dir[0],
                    m->dir[1], m->dir[2]);
        else
            fprintf(f, "%.7g degrees about (%.4g, %.4g, %.4g): stable at %.7g, %s at %.7g\n", m->value * d,
                    m->dir[0], m->dir[1], m->dir[2], m->value * d, vw, m->past * d);
    } else {
        fprintf(f, "%slateral%s: ", lead, at);
        if (m->end == CN_MARGIN_NONE) fprintf(f, "0: not stable as loaded\n");
        else if (m->end == CN_MARGIN_WHOLE)
            fprintf(f, "stable up to %g g along (%.4g, %.4g%s), the whole range searched\n", m->value, m->dir[0],
                    m->dir[1], a->dim == 3 ? ", ..." : "");
        else if (a->dim == 2)
            fprintf(f, "%.7g g along (%.4g, %.4g): stable at %.7g, %s at %.7g\n", m->value, m->dir[0], m->dir[1],
                    m->value, vw, m->past);
        else
            fprintf(f, "%.7g g along (%.4g, %.4g, %.4g): stable at %.7g, %s at %.7g\n", m->value, m->dir[0],
                    m->dir[1], m->dir[2], m->value, vw, m->past);
    }
    if (m->stopped)
        fprintf(f, "%s      stopped by the time limit: the bracket is proved but wider than asked%s\n", lead,
                kind != CN_MARGIN_FRICTION ? ", and the weakest direction is that of those tried" : "");
    if (m->end == CN_MARGIN_FOUND && (m->past_failed || m->past_verdict == CN_VERDICT_UNDECIDED)) {
        fprintf(f, "%s      no mechanism: the verdict past the margin is %s, so that side of the bracket is not "
                   "proved\n", lead, m->past_failed ? "a numerical failure" : "undecided");
    } else if (m->collapse.part && m->end != CN_MARGIN_WHOLE) {
        double unit = kind == CN_MARGIN_TILT ? 180 / CN_PI : 1;
        fprintf(f, "%s      the mechanism, at %.7g%s:\n", lead, m->mechanism_at * unit,
                kind == CN_MARGIN_TILT ? " degrees" : kind == CN_MARGIN_LATERAL ? " g" : "");
        mechanism_text(f, a, &m->collapse, lead);
    }
}

cnStatus cn_report_margin(FILE *f, const cnAssembly *a, const cnMarginResult *r, int json) {
    const cnMargin *ms[3] = {&r->friction, &r->tilt, &r->lateral};
    const int kinds[3] = {CN_MARGIN_FRICTION, CN_MARGIN_TILT, CN_MARGIN_LATERAL};
    if (json) {
        json_t *o = json_object();
        if (a->name) json_object_set_new(o, "name", json_string(a->name));
        json_object_set_new(o, "dimension", json_integer(a->dim));
        json_object_set_new(o, "verdict", json_string(cn_verdict_word(r->verdict)));
        if (r->friction.computed) json_object_set_new(o, "critical_friction", real_or_null(r->friction.value));
        const char *keys[3] = {"friction", "tilt", "lateral"};
        for (int k = 0; k < 3; k++)
            if (ms[k]->computed) json_object_set_new(o, keys[k], cn_margin_json(a, ms[k], kinds[k]));
        return cn_json_write(f, o, 10);
    }
    char vw[32];
    verdict_upper(vw, sizeof vw, r->verdict);
    fprintf(f, "as loaded: %s\n", vw);
    int total = 0;
    for (int k = 0; k < 3; k++)
        if (ms[k]->computed) {
            cn_margin_text(f, a, ms[k], kinds[k], "", "");
            total += ms[k]->verdicts;
        }
    fprintf(f, "verdicts run: %d\n", total);
    return CN_OK;
}
