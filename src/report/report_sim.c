/* Reports of a simulated plan: text, JSON and the CSV history. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "json_out.h"
#include "cairn/report.h"

const char *cn_step_status_word(cnStepStatus s) {
    switch (s) {
    case CN_STEP_STABLE: return "stable";
    case CN_STEP_UNSTABLE: return "unstable";
    case CN_STEP_INFEASIBLE: return "geometrically infeasible";
    case CN_STEP_SKIPPED: return "not simulated";
    case CN_STEP_UNDECIDED: return "undecided";
    }
    return "?";
}

static void names(FILE *f, const cnAssembly *a, const int *idx, int n) {
    for (int i = 0; i < n; i++) fprintf(f, "%s%s", i ? ", " : "", a->parts[idx[i]].name);
}

static json_t *name_array(const cnAssembly *a, const int *idx, int n) {
    json_t *arr = json_array();
    for (int i = 0; i < n; i++) json_array_append_new(arr, json_string(a->parts[idx[i]].name));
    return arr;
}

static json_t *vec(const double *v, int dim) {
    json_t *arr = json_array();
    for (int k = 0; k < dim; k++) json_array_append_new(arr, json_real(fabs(v[k]) < CN_TOL_PRINT_ZERO ? 0.0 : v[k]));
    return arr;
}

static void contact_label(const cnAssembly *a, int b1, int b2, int vertex, char *buf, size_t n) {
    char v[32] = "";
    if (vertex) snprintf(v, sizeof v, "%d ", vertex);
    snprintf(buf, n, "%s%s/%s", v, b1 == CN_WORLD ? "fixel" : a->parts[b1].name,
             a->parts[b2].name);
}

/* A step whose path turns reports the moved parts' rotation too. */
static bool turns(const cnPlanStep *st) { return cn_path_turns(st->seg, st->nseg); }

static double degrees(double rad) {
    double d = rad * 180 / CN_PI;
    return fabs(d) < CN_TOL_PRINT_ZERO ? 0.0 : d;
}

/* Where along the path the onset is: "t = T (step time S, distance D along the path[, turned
 * A deg])". */
static void onset_where(FILE *f, const cnPlanStep *st, const cnStepResult *s) {
    fprintf(f, "t = %.6g (step time %.6g, distance %.6g along the path", s->onset_time,
            s->onset_step_time, s->onset_distance);
    if (turns(st)) fprintf(f, ", turned %.6g deg", degrees(s->onset_angle));
    fprintf(f, ")");
}

/* Where along the path an onset (instability or collision) is: time, distance, displacement,
 * and the rotation when the path turns. */
static json_t *onset_json(const cnAssembly *a, const cnPlanStep *st, const cnStepResult *s) {
    json_t *u = json_object();
    json_object_set_new(u, "time", json_real(s->onset_time));
    json_object_set_new(u, "step_time", json_real(s->onset_step_time));
    json_object_set_new(u, "distance", json_real(s->onset_distance));
    json_object_set_new(u, "displacement", vec(s->onset_disp, a->dim));
    if (turns(st)) json_object_set_new(u, "rotation", json_real(degrees(s->onset_angle)));
    return u;
}

/* The run's verdict: stable, unstable, geometrically infeasible (a path collides) or undecided
 * (the step that stopped it could not be decided). */
static const char *sim_verdict(const cnSimResult *R) {
    if (R->stable) return "stable";
    if (R->undecided) return "undecided";
    for (int k = 0; k < R->nsteps; k++)
        if (R->steps[k].status == CN_STEP_INFEASIBLE) return "infeasible";
    return "unstable";
}

static const int MARGIN_KINDS[3] = {CN_MARGIN_FRICTION, CN_MARGIN_TILT, CN_MARGIN_LATERAL};
static const char *const MARGIN_KEYS[3] = {"friction", "tilt", "lateral"};

/* A step's weakest margins (simulate --margin): null when none was found. */
static json_t *step_margin_json(const cnAssembly *a, const cnStepResult *s) {
    json_t *o = NULL;
    for (int k = 0; k < 3; k++) {
        const cnStepMargin *w = &s->margin[k];
        if (!w->computed) continue;
        if (!o) o = json_object();
        if (k == 0) json_object_set_new(o, "critical_friction", isfinite(w->at.value) ? json_real(w->at.value) : json_null());
        json_t *m = cn_margin_json(a, &w->at, MARGIN_KINDS[k]);
        json_object_set_new(m, "time", json_real(w->time));
        json_object_set_new(m, "step_time", json_real(w->step_time));
        json_object_set_new(m, "distance", json_real(w->distance));
        json_object_set_new(m, "samples", json_integer(w->samples));
        json_object_set_new(o, MARGIN_KEYS[k], m);
    }
    return o ? o : json_null();
}

/* A step's weakest margins as text, one line each with where on the path. */
static void step_margin_text(FILE *f, const cnAssembly *a, const cnStepResult *s) {
    for (int k = 0; k < 3; k++) {
        const cnStepMargin *w = &s->margin[k];
        if (!w->computed) continue;
        char at[96];
        snprintf(at, sizeof at, " (weakest of %d sample%s, at t = %.6g, distance %.6g)", w->samples,
                 w->samples == 1 ? "" : "s", w->time, w->distance);
        cn_margin_text(f, a, &w->at, MARGIN_KINDS[k], "  ", at);
    }
}

static json_t *sim_json(const cnAssembly *a, const cnSimResult *R) {
    json_t *o = json_object();
    json_object_set_new(o, "stable", json_boolean(R->stable));
    json_object_set_new(o, "verdict", json_string(sim_verdict(R)));
    json_object_set_new(o, "mode", json_string(R->assemble ? "assembly" : "disassembly"));
    json_t *steps = json_array();
    for (int kk = 0; kk < R->nsteps; kk++) {
        const cnStepResult *s = &R->steps[kk];
        const cnPlanStep *st = &a->plan[R->plan_index[kk]];
        json_t *j = json_object();
        json_object_set_new(j, "plan_step", json_integer(R->plan_index[kk]));
        json_object_set_new(j, "move", name_array(a, st->move, st->nmove));
        json_object_set_new(j, "grip", name_array(a, st->grip, st->ngrip));
        json_object_set_new(j, "support", json_string(st->support == CN_SUPPORT_PUSH ? "push" : "hold"));
        json_object_set_new(j, "status", json_string(cn_step_status_word(s->status)));
        json_object_set_new(j, "stable", json_boolean(s->status == CN_STEP_STABLE));
        json_object_set_new(j, "start_time", json_real(s->t0));
        json_object_set_new(j, "end_time", json_real(s->t1));
        json_object_set_new(j, "path_length", json_real(s->length));
        json_object_set_new(j, "samples", json_integer(s->nsamples));
        if (s->status == CN_STEP_UNSTABLE && s->has_onset) {
            json_t *u = onset_json(a, st, s);
            json_object_set_new(u, "after_removal", json_boolean(s->onset_after));
            json_object_set_new(u, "moving_parts", name_array(a, s->onset.moving, s->onset.nmoving));
            json_t *motion = json_array(), *sep = json_array(), *sl = json_array();
            for (int i = 0; i < s->onset.nmoving; i++) {
                int p = s->onset.moving[i];
                json_t *m = json_object();
                json_object_set_new(m, "part", json_string(a->parts[p].name));
                json_object_set_new(m, "linear", vec(s->onset.part[p].lin, a->dim));
                double wq = cn_norm3(a->gravity) / a->length_scale, wc[3];
                for (int k = 0; k < 3; k++) wc[k] = cn_report_clean(s->onset.part[p].ang[k], wq);
                if (a->dim == 2) json_object_set_new(m, "angular", json_real(wc[2]));
                else json_object_set_new(m, "angular", vec(wc, 3));
                json_array_append_new(motion, m);
            }
            for (int c = 0; c < s->onset.contacts.count; c++) {
                const cnContact *ct = &s->onset.contacts.items[c];
                char lab[300];
                contact_label(a, ct->body1, ct->body2, ct->vertex, lab, sizeof lab);
                json_t *cj = json_object();
                json_object_set_new(cj, "id", json_integer(ct->id));
                json_object_set_new(cj, "label", json_string(lab));
                json_object_set_new(cj, "vertex", ct->vertex ? json_integer(ct->vertex) : json_null());
                if (s->onset.contact[c].separates) json_array_append(sep, cj);
                if (s->onset.contact[c].slides) json_array_append(sl, cj);
                json_decref(cj);
            }
            json_object_set_new(u, "motion", motion);
            json_object_set_new(u, "separating_contacts", sep);
            json_object_set_new(u, "sliding_contacts", sl);
            json_object_set_new(j, "unstable_at", u);
        } else {
            json_object_set_new(j, "unstable_at", json_null());
        }
        if (s->status == CN_STEP_UNDECIDED && s->has_onset) {
            json_t *u = onset_json(a, st, s);
            json_object_set_new(u, "after_removal", json_boolean(s->onset_after));
            json_object_set_new(u, "why", json_string(s->onset.undecided ? cn_undecided_text(s->onset.undecided) : "undecided"));
            json_object_set_new(u, "search_lps", json_integer(s->onset.solver.search_nodes));
            json_object_set_new(u, "sampled_to", json_real(s->sampled_to));
            json_object_set_new(j, "undecided_at", u);
        } else {
            json_object_set_new(j, "undecided_at", json_null());
        }
        if (s->status == CN_STEP_INFEASIBLE && s->has_onset) {
            json_t *u = onset_json(a, st, s);
            json_object_set_new(u, "part", s->blocked_part >= 0 ? json_string(a->parts[s->blocked_part].name) : json_null());
            json_object_set_new(u, "blocked_by", s->blocking_part >= 0 ? json_string(a->parts[s->blocking_part].name) : json_null());
            json_object_set_new(j, "infeasible_at", u);
        } else {
            json_object_set_new(j, "infeasible_at", json_null());
        }
        if (s->took_weight) {
            json_t *u = json_object();
            json_object_set_new(u, "time", json_real(s->took_weight_time));
            json_object_set_new(u, "part", s->took_weight_part >= 0 ? json_string(a->parts[s->took_weight_part].name) : json_null());
            json_object_set_new(j, "gripper_took_weight", u);
        } else {
            json_object_set_new(j, "gripper_took_weight", json_null());
        }
        json_t *carried = json_array();
        for (int c = 0; c < s->ncarry; c++) {
            json_t *u = json_object();
            json_object_set_new(u, "from", json_real(s->carry[c].t0));
            json_object_set_new(u, "to", json_real(s->carry[c].t1));
            json_object_set_new(u, "part", s->carry[c].part >= 0 ? json_string(a->parts[s->carry[c].part].name) : json_null());
            json_object_set_new(u, "released", json_boolean(s->carry[c].released));
            json_array_append_new(carried, u);
        }
        json_object_set_new(j, "gripper_carried", carried);
        json_object_set_new(j, "margin", step_margin_json(a, s));
        json_object_set_new(j, "contact_events", json_integer(s->nevents));
        json_object_set_new(j, "contact_events_not_sampled", json_integer(s->events_dropped));
        json_array_append_new(steps, j);
    }
    json_object_set_new(o, "steps", steps);
    json_t *l = json_object();
    json_object_set_new(l, "solves", json_integer(R->lcp_solves));
    json_object_set_new(l, "warm_started", json_integer(R->lcp_warm));
    json_object_set_new(l, "pivots", json_integer(R->lcp_pivots));
    json_object_set_new(o, "lcp", l);
    return o;
}

static const char *step_word(cnStepStatus s) {
    switch (s) {
    case CN_STEP_STABLE: return "STABLE";
    case CN_STEP_UNSTABLE: return "UNSTABLE";
    case CN_STEP_INFEASIBLE: return "GEOMETRICALLY INFEASIBLE";
    case CN_STEP_SKIPPED: return "not simulated (an earlier step failed)";
    case CN_STEP_UNDECIDED: return "UNDECIDED";
    }
    return "?";
}

/* The verdict line's word for one run. */
static const char *run_word(const cnSimResult *R) {
    return R->stable ? "STABLE" : R->undecided ? "UNDECIDED" : "UNSTABLE";
}

static void sim_text(FILE *f, const cnAssembly *a, const cnSimResult *R) {
    for (int kk = 0; kk < R->nsteps; kk++) {
        const cnStepResult *s = &R->steps[kk];
        const cnPlanStep *st = &a->plan[R->plan_index[kk]];
        fprintf(f, "step %d (plan[%d]): %s ", kk + 1, R->plan_index[kk],
                R->assemble ? "insert" : "move");
        names(f, a, st->move, st->nmove);
        if (st->ngrip != st->nmove) {
            fprintf(f, " gripping ");
            names(f, a, st->grip, st->ngrip);
        }
        fprintf(f, ", %s, path length %.4g: %s\n", st->support == CN_SUPPORT_PUSH ? "pushed" : "held",
                s->length, step_word(s->status));
        if (s->events_dropped > 0)
            fprintf(f, "  warning: %d contact events past the first %d of a segment were not sampled; an "
                       "instability between samples may be missed (split the path)\n",
                    s->events_dropped, CN_SIM_MAX_EVENTS);
        for (int c = 0; c < s->ncarry; c++) {
            const cnCarryInterval *ci = &s->carry[c];
            fprintf(f, "  the gripper carries %s from t = %.6g to %.6g: pushed alone it would fall or tip",
                    ci->part >= 0 ? a->parts[ci->part].name : "the part", ci->t0, ci->t1);
            if (ci->released) fprintf(f, "; from then on it rests on its supports again");
            fprintf(f, "\n");
        }
        step_margin_text(f, a, s);
        if (s->status == CN_STEP_INFEASIBLE && s->has_onset) {
            fprintf(f, "  at t = %.6g (step time %.6g, displacement ", s->onset_time, s->onset_step_time);
            for (int k = 0; k < a->dim; k++) fprintf(f, "%s%.6g", k ? ", " : "(", s->onset_disp[k]);
            fprintf(f, ")");
            if (turns(st)) fprintf(f, ", turned %.6g deg", degrees(s->onset_angle));
            fprintf(f, ") %s would penetrate %s\n",
                    s->blocked_part >= 0 ? a->parts[s->blocked_part].name : "?",
                    s->blocking_part >= 0 ? a->parts[s->blocking_part].name : "?");
        }
        if (s->status == CN_STEP_UNDECIDED && s->has_onset) {
            const char *why = s->onset.undecided ? cn_undecided_text(s->onset.undecided) : "undecided";
            if (s->onset_after)
                fprintf(f, "  when the moved parts are taken away at t = %.6g", s->onset_time);
            else if (s->length > 0 && s->nsamples > 0)
                fprintf(f, "  at "), onset_where(f, st, s);
            else fprintf(f, "  in the state before the step");
            fprintf(f, ": a static solution exists, but the search for a motion from rest %s "
                       "(%s after %ld LP%s): not proved stable\n",
                    s->onset.solver.search_nodes > 0 ? "stopped" : "was not run whole", why, s->onset.solver.search_nodes,
                    s->onset.solver.search_nodes == 1 ? "" : "s");
            if (s->sampled_to < s->length)
                fprintf(f, "  sampling stopped at distance %.6g of %.6g along the path, after %d undecided "
                           "samples: the rest of the path was not checked\n",
                        s->sampled_to, s->length, CN_SIM_MAX_UNDECIDED);
        }
        if (s->status == CN_STEP_UNSTABLE && s->has_onset) {
            if (s->onset_after)
                fprintf(f, "  when the moved parts are taken away at t = %.6g, the rest starts to move\n", s->onset_time);
            else if (s->length > 0 && s->nsamples > 0) {
                fprintf(f, "  instability starts at ");
                onset_where(f, st, s);
                fprintf(f, "\n");
            }
            else fprintf(f, "  the state before the step is already unstable\n");
            for (int i = 0; i < s->onset.nmoving; i++) {
                int p = s->onset.moving[i];
                const cnPartMotion *m = &s->onset.part[p];
                fprintf(f, "  %s moves: linear", a->parts[p].name);
                for (int k = 0; k < a->dim; k++) fprintf(f, "%s%.4g", k ? ", " : " (", m->lin[k]);
                double wq = cn_norm3(a->gravity) / a->length_scale, w[3]; /* rounding: 0 */
                for (int k = 0; k < 3; k++) w[k] = cn_report_clean(m->ang[k], wq);
                if (a->dim == 2) fprintf(f, "), angular %.4g%s\n", w[2], w[2] > 0 ? " (counter-clockwise)" : w[2] < 0 ? " (clockwise)" : "");
                else fprintf(f, "), angular (%.4g, %.4g, %.4g)\n", w[0], w[1], w[2]);
            }
            for (int pass = 0; pass < 2; pass++) {
                int any = 0;
                for (int c = 0; c < s->onset.contacts.count; c++) {
                    const cnContactResult *cr = &s->onset.contact[c];
                    if (!(pass ? cr->slides : cr->separates)) continue;
                    const cnContact *ct = &s->onset.contacts.items[c];
                    char lab[300];
                    contact_label(a, ct->body1, ct->body2, ct->vertex, lab, sizeof lab);
                    fprintf(f, "%s%d [%s]", any ? ", " : pass ? "  contacts that slide: " : "  contacts that separate: ", ct->id, lab);
                    any = 1;
                }
                if (any) fprintf(f, "\n");
            }
        }
    }
}

cnStatus cn_report_sim(FILE *f, const cnAssembly *a, const cnSimResult *dis, const cnSimResult *as,
                       int json) {
    if (json) {
        json_t *o = sim_json(a, dis);
        if (a->name) json_object_set_new(o, "name", json_string(a->name));
        if (as) {
            json_t *asj = sim_json(a, as);
            json_object_set_new(o, "assembly", asj);
            /* undecided on either side: whether the plan is invertible is not known */
            json_object_set_new(o, "invertible", dis->undecided || as->undecided ? json_null()
                                                 : json_boolean(dis->stable == as->stable));
        }
        return cn_json_write(f, o, 10);
    }
    if (a->name) fprintf(f, "%s\n", a->name);
    fprintf(f, "plan of %d step%s, sampled every %.4g at speed %.4g\n", a->nsteps,
            a->nsteps == 1 ? "" : "s", a->sim_dt, a->sim_speed);
    if (!as) {
        sim_text(f, a, dis);
        bool infeasible = false;
        for (int k = 0; k < dis->nsteps; k++) infeasible |= dis->steps[k].status == CN_STEP_INFEASIBLE;
        fprintf(f, "verdict: %s\n", dis->stable ? "STABLE: every step keeps the rest in place"
                                   : dis->undecided ? "UNDECIDED: a step could not be proved stable "
                                                      "or unstable (no verdict)"
                                   : infeasible ? "GEOMETRICALLY INFEASIBLE: a path collides"
                                                : "UNSTABLE");
        return CN_OK;
    }
    fprintf(f, "\n== disassembly (the plan) ==\n");
    sim_text(f, a, dis);
    fprintf(f, "\n== assembly (the plan reversed, each path reversed) ==\n");
    sim_text(f, a, as);
    fprintf(f, "\n%-28s %-12s %-12s\n", "step", "disassembly", "assembly");
    for (int k = 0; k < a->nsteps; k++) {
        int ka = a->nsteps - 1 - k; /* the same plan step in the reversed run */
        char lab[128] = "";
        for (int i = 0; i < a->plan[k].nmove; i++) {
            strncat(lab, i ? "," : "", sizeof lab - strlen(lab) - 1);
            strncat(lab, a->parts[a->plan[k].move[i]].name, sizeof lab - strlen(lab) - 1);
        }
        fprintf(f, "plan[%d] %-20s %-12s %-12s\n", k, lab, cn_step_status_word(dis->steps[k].status),
                cn_step_status_word(as->steps[ka].status));
    }
    fprintf(f, "verdict: disassembly %s, assembly %s%s\n", run_word(dis), run_word(as),
            dis->undecided || as->undecided ? ": whether it is invertible is not known"
            : dis->stable != as->stable     ? ": NOT INVERTIBLE (paper sec. VIII)"
                                            : "");
    return CN_OK;
}

/* One CSV field per RFC 4180: quoted when it holds a comma, a double quote or a line break,
 * with its double quotes doubled (unquoted, a part named "C,1" would shift every column after
 * it). A name a spreadsheet would run as a formula (starting with =, +, -, @, a tab or a carriage
 * return) gets a leading apostrophe, as spreadsheets themselves write text that looks like a
 * formula. */
static void csv_text(FILE *f, const char *s) {
    bool formula = s[0] && strchr("=+-@\t\r", s[0]);
    if (!strpbrk(s, ",\"\r\n")) {
        if (formula) fputc('\'', f);
        fputs(s, f);
        return;
    }
    fputc('"', f);
    if (formula) fputc('\'', f);
    for (; *s; s++) {
        if (*s == '"') fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

cnStatus cn_report_sim_csv(FILE *f, const cnAssembly *a, const cnSimResult *R) {
    bool margins = false; /* the margin columns, when simulate --margin found any */
    for (int k = 0; k < R->nsteps; k++)
        for (int m = 0; m < 3; m++) margins |= R->steps[k].margin[m].computed;
    /* RFC 4180: records end in CRLF */
    fprintf(f, "mode,step,plan_step,move,time,step_time,distance,stable,held,contact_id,part1,part2,"
               "vertex,label,force,force_normalized,normal_motion,separates,slides,angle_deg%s\r\n",
            margins ? ",critical_friction,tilt_deg,lateral_g" : "");
    for (int i = 0; i < R->nsamples; i++) {
        const cnSimSample *sm = &R->samples[i];
        const cnStepResult *s = &R->steps[sm->step];
        const cnPlanStep *st = &a->plan[R->plan_index[sm->step]];
        char mv[256] = "";
        for (int k = 0; k < st->nmove; k++) {
            strncat(mv, k ? "+" : "", sizeof mv - strlen(mv) - 1);
            strncat(mv, a->parts[st->move[k]].name, sizeof mv - strlen(mv) - 1);
        }
        for (int c = sm->first; c < sm->first + sm->count; c++) {
            const cnSimContact *x = &R->contacts[c];
            char lab[300];
            contact_label(a, x->body1, x->body2, x->vertex, lab, sizeof lab);
            fprintf(f, "%s,%d,%d,", R->assemble ? "assembly" : "disassembly", sm->step + 1,
                    R->plan_index[sm->step]);
            csv_text(f, mv);
            fprintf(f, ",%.9g,%.9g,%.9g,%d,%d,%d,", sm->time, sm->step_time, sm->distance, sm->stable,
                    sm->held, x->id);
            csv_text(f, x->body1 == CN_WORLD ? "fixel" : a->parts[x->body1].name);
            fputc(',', f);
            csv_text(f, a->parts[x->body2].name);
            fprintf(f, ",%d,", x->vertex);
            csv_text(f, lab);
            fprintf(f, ",%.9g,%.9g,%.9g,%d,%d,%.9g", x->force, s->weight > 0 ? x->force / s->weight : 0.0,
                    x->motion, x->separates, x->slides, degrees(sm->angle));
            for (int m = 0; margins && m < 3; m++) /* empty where not found */
                if (isfinite(sm->margin[m])) fprintf(f, ",%.9g", m == 1 ? degrees(sm->margin[m]) : sm->margin[m]);
                else fputs(sm->margin[m] > 0 ? ",inf" : ",", f); /* inf: no friction suffices */
            fputs("\r\n", f);
        }
    }
    return ferror(f) ? CN_ERR_IO : CN_OK;
}
