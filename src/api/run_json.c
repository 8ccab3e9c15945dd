/* cn_run_json: a command's options from a JSON object, the command's C call, its JSON report
 * written to a string (open_memstream), and the outcome the CLI would exit with. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cairn/builder.h"
#include "cairn/contact.h"
#include "cairn/margin.h"
#include "cairn/plan.h"
#include "cairn/report.h"
#include "cairn/run.h"
#include "cairn/simulate.h"
#include "cairn/stability.h"
#include "run_figures.h"

typedef struct {
    json_t *opts;
    cnDiag *diag;
    cnStatus st; /* the first bad option */
    const cnRunFigures *fig;
    const char *prefix; /* NULL, or an object's key and a dot: its options are that object's */
} Opts;

static cnStatus bad(Opts *o, const char *key, const char *what) {
    char where[96];
    snprintf(where, sizeof where, "options.%s%s", o->prefix ? o->prefix : "", key);
    if (o->st == CN_OK) o->st = cn_diag_set(o->diag, CN_ERR_INPUT, where, "%s", what);
    return o->st;
}

/* Refuse keys the command does not take, naming the ones it does. */
static void only(Opts *o, const char *const *keys, const char *command) {
    const char *key;
    json_t *v;
    json_object_foreach(o->opts, key, v) {
        bool ok = false;
        for (int i = 0; keys[i] && !ok; i++) ok = !strcmp(keys[i], key);
        if (ok) continue;
        char what[512];
        int n = snprintf(what, sizeof what, "'%s' takes no option of that name; its options are:", command);
        for (int i = 0; keys[i] && n > 0 && (size_t)n < sizeof what; i++)
            n += snprintf(what + n, sizeof what - (size_t)n, "%s %s", i ? "," : "", keys[i]);
        if (!keys[0]) snprintf(what, sizeof what, "'%s' takes no options", command);
        bad(o, key, what);
        return;
    }
}

static void get_bool(Opts *o, const char *key, bool *out) {
    json_t *v = json_object_get(o->opts, key);
    if (!v) return;
    if (!json_is_boolean(v)) bad(o, key, "expected true or false");
    else *out = json_is_true(v);
}

/* A whole number from lo to hi. */
static void get_count(Opts *o, const char *key, double lo, double hi, long *out) {
    json_t *v = json_object_get(o->opts, key);
    if (!v) return;
    char what[128];
    snprintf(what, sizeof what, "expected a whole number from %g to %g", lo, hi);
    /* a real that is a whole number (1e3) is taken, as the CLI takes --search-budget 1e3 */
    double x = json_is_number(v) ? json_number_value(v) : NAN;
    if (!(x >= lo && x <= hi) || x != floor(x)) bad(o, key, what);
    else *out = (long)x;
}

/* A number from lo to hi. */
static void get_real(Opts *o, const char *key, double lo, double hi, double *out) {
    json_t *v = json_object_get(o->opts, key);
    if (!v) return;
    char what[128];
    snprintf(what, sizeof what, "expected a number from %g to %g", lo, hi);
    double x = json_is_number(v) ? json_number_value(v) : NAN;
    if (!(x >= lo && x <= hi)) bad(o, key, what);
    else *out = x;
}

static void get_choice(Opts *o, const char *key, const char *const *names, int *out) {
    json_t *v = json_object_get(o->opts, key);
    if (!v) return;
    for (int i = 0; names[i] && json_is_string(v); i++)
        if (!strcmp(names[i], json_string_value(v))) {
            *out = i;
            return;
        }
    char what[160];
    int n = snprintf(what, sizeof what, "expected one of");
    for (int i = 0; names[i]; i++) n += snprintf(what + n, sizeof what - (size_t)n, "%s \"%s\"", i ? "," : "", names[i]);
    bad(o, key, what);
}

/* Which parts `options.parts` names (by index), checked as --parts is. */
static int *get_parts(Opts *o, const cnAssembly *a, int *n) {
    json_t *v = json_object_get(o->opts, "parts");
    *n = 0;
    if (!v) return NULL;
    if (!json_is_array(v) || json_array_size(v) == 0) {
        bad(o, "parts", "expected a non-empty array of part names, e.g. [\"A\", \"B\"]");
        return NULL;
    }
    int *sel = malloc(sizeof(int) * (json_array_size(v) + 1));
    if (!sel) {
        o->st = cn_diag_set(o->diag, CN_ERR_MEMORY, "options.parts", "out of memory");
        return NULL;
    }
    size_t i;
    json_t *e;
    json_array_foreach(v, i, e) {
        char key[48];
        snprintf(key, sizeof key, "parts[%zu]", i);
        int k = json_is_string(e) ? cn_assembly_find_part(a, json_string_value(e)) : -1;
        if (!json_is_string(e)) bad(o, key, "expected a part name");
        else if (k < 0 || k >= a->nreal || a->parts[k].fixed) bad(o, key, "not a part that can move");
        for (int q = 0; q < *n && o->st == CN_OK; q++)
            if (sel[q] == k) bad(o, key, "listed twice");
        if (o->st != CN_OK) {
            free(sel);
            *n = 0;
            return NULL;
        }
        sel[(*n)++] = k;
    }
    return sel;
}

cnOutcome cn_check_outcome(const cnCheckResult *r) {
    return r->verdict == CN_VERDICT_UNDECIDED ? CN_OUTCOME_UNDECIDED : r->stable ? CN_OUTCOME_GOOD : CN_OUTCOME_NEGATIVE;
}

cnOutcome cn_sim_outcome(const cnSimResult *dis, const cnSimResult *assembly) {
    if (dis->stable && (!assembly || assembly->stable)) return CN_OUTCOME_GOOD;
    bool failed = (!dis->stable && !dis->undecided) || (assembly && !assembly->stable && !assembly->undecided);
    return failed ? CN_OUTCOME_NEGATIVE : CN_OUTCOME_UNDECIDED;
}

cnOutcome cn_plan_outcome(const cnPlanResult *r) {
    if (r->stable) return CN_OUTCOME_GOOD;
    return r->search.undecided_states || r->search.undecided_moves ? CN_OUTCOME_UNDECIDED : CN_OUTCOME_NEGATIVE;
}

/* Is the file whose stat is so the assembly's file or one of its mesh files? */
static bool is_input(const struct stat *so, const char *file, const cnAssembly *a) {
    struct stat si;
    if (file && strcmp(file, "-") && stat(file, &si) == 0 && si.st_dev == so->st_dev && si.st_ino == so->st_ino)
        return true;
    /* read from standard input, which is that file (cairn check - < FILE) */
    if (file && !strcmp(file, "-") && fstat(STDIN_FILENO, &si) == 0 && S_ISREG(si.st_mode) &&
        si.st_dev == so->st_dev && si.st_ino == so->st_ino)
        return true;
    for (int i = 0; a && i < a->nreal; i++) {
        const char *mf = a->parts[i].mesh_file;
        if (!mf) continue;
        char mp[8192];
        const char *sl = file && strcmp(file, "-") ? strrchr(file, '/') : NULL;
        if (mf[0] == '/' || !sl) snprintf(mp, sizeof mp, "%s", mf);
        else snprintf(mp, sizeof mp, "%.*s/%s", (int)(sl - file), file, mf);
        if (stat(mp, &si) == 0 && si.st_dev == so->st_dev && si.st_ino == so->st_ino) return true;
    }
    return false;
}

cnOutputProblem cn_output_problem(const char *path, const char *file, const cnAssembly *a) {
    struct stat so;
    if (stat(path, &so) == 0) {
        if (is_input(&so, file, a)) return CN_OUTPUT_INPUT;
        if (S_ISDIR(so.st_mode)) return CN_OUTPUT_DIRECTORY;
        return access(path, W_OK) == 0 ? CN_OUTPUT_OK : CN_OUTPUT_DENIED;
    }
    char dir[4096];
    const char *sl = strrchr(path, '/');
    if (sl) snprintf(dir, sizeof dir, "%.*s", sl == path ? 1 : (int)(sl - path), path);
    else snprintf(dir, sizeof dir, ".");
    return stat(dir, &so) == 0 && S_ISDIR(so.st_mode) && access(dir, W_OK | X_OK) == 0 ? CN_OUTPUT_OK
                                                                                        : CN_OUTPUT_NO_DIRECTORY;
}

static const char *const SOLVERS[] = {"auto", "lemke", "pivot", NULL};
static const char *const SUPPORTS[] = {"hold", "push", "both", NULL};

static cnStatus run_check(const cnAssembly *a, Opts *o, FILE *f, cnOutcome *outcome) {
    static const char *const keys[] = {"solver",  "lp_check",    "accept_prestress", "assume_planar",
                                       "search_budget", "reading", "max_seconds", "figure", NULL};
    cnCheckOptions opt = cn_check_options_default();
    int solver = 0;
    long reading = -1;
    only(o, keys, "check");
    get_choice(o, "solver", SOLVERS, &solver);
    get_bool(o, "lp_check", &opt.lp_crosscheck);
    get_bool(o, "accept_prestress", &opt.accept_prestress);
    get_bool(o, "assume_planar", &opt.assume_planar);
    get_count(o, "search_budget", 1, 1e9, &opt.max_nodes);
    get_count(o, "reading", 0, 1e15, &reading);
    get_real(o, "max_seconds", 1e-3, 1e9, &opt.max_seconds);
    opt.one_reading = reading >= 0;
    opt.reading = reading >= 0 ? (unsigned long long)reading : 0;
    json_t *fv = json_object_get(o->opts, "figure");
    const char *figure = json_is_string(fv) ? json_string_value(fv) : NULL;
    if (fv && (!figure || !figure[0] || !strcmp(figure, "-")))
        bad(o, "figure", "expected the name of a PNG file to draw, e.g. \"check.png\"");
    else if (fv && !(o->fig && o->fig->check))
        bad(o, "figure", "figures are drawn by libcairn_figure: call its cn_figure_run_json (the Python package "
                         "loads it for figure=)");
    else if (fv) {
        cnOutputProblem p = cn_output_problem(figure, a->source, a);
        if (p != CN_OUTPUT_OK)
            bad(o, "figure", p == CN_OUTPUT_INPUT ? "is a file the assembly was read from: name another file"
                             : p == CN_OUTPUT_DIRECTORY ? "is a directory: name a file"
                             : p == CN_OUTPUT_DENIED ? "cannot be written (no permission): name a writable file"
                                                     : "cannot be written (its directory does not exist or is not "
                                                       "writable): name a writable file");
    }
    if (o->st != CN_OK) return o->st;
    opt.solver = solver == 1 ? CN_SOLVER_LEMKE : solver == 2 ? CN_SOLVER_PIVOT : CN_SOLVER_AUTO;
    cnCheckResult r;
    cnStatus s = cn_check(a, &opt, &r, o->diag);
    if (s == CN_OK && figure) s = o->fig->check(figure, a, &r, o->diag);
    if (s == CN_OK) {
        s = cn_report_check(f, a, &r, 1);
        *outcome = cn_check_outcome(&r);
    }
    cn_check_result_free(&r);
    return s;
}

static void margin_opts(const cnAssembly *a, Opts *o, cnMarginOptions *mo);
static void margin_where(Opts *o, cnStatus s, const char *prefix);

/* "margin" of simulate and plan: true, or an object of margin options (a path's tolerance by
 * default). Returns mo filled, or NULL when there is none (or it is bad: o->st says). */
static const cnMarginOptions *path_margin_opts(const cnAssembly *a, Opts *o, const char *command,
                                               cnMarginOptions *mo) {
    static const char *const margin_keys[] = {"only", "pair", "axis", "direction", "margin_tol", NULL};
    *mo = cn_margin_options_default();
    mo->rel_tol = 0;
    json_t *mv = json_object_get(o->opts, "margin");
    if (json_is_true(mv)) return mo;
    if (json_is_object(mv)) {
        Opts mopts = *o;
        mopts.opts = mv, mopts.prefix = "margin.";
        char what[64];
        snprintf(what, sizeof what, "%s's margin", command);
        only(&mopts, margin_keys, what);
        margin_opts(a, &mopts, mo);
        o->st = mopts.st;
        return mo;
    }
    if (mv && !json_is_false(mv) && !json_is_null(mv))
        bad(o, "margin", "expected true, or an object of margin options, e.g. {\"only\": [\"lateral\"]}");
    return NULL;
}

static cnStatus run_simulate(const cnAssembly *a, Opts *o, FILE *f, cnOutcome *outcome) {
    static const char *const keys[] = {"assemble", "cold", "accept_prestress", "search_budget", "margin", NULL};
    cnSimOptions so = cn_sim_options_default();
    bool assemble = false;
    only(o, keys, "simulate");
    get_bool(o, "assemble", &assemble);
    get_bool(o, "cold", &so.cold);
    get_bool(o, "accept_prestress", &so.check.accept_prestress);
    get_count(o, "search_budget", 1, 1e9, &so.check.max_nodes);
    cnMarginOptions mo;
    so.margin = path_margin_opts(a, o, "simulate", &mo);
    if (o->st != CN_OK) return o->st;
    cnSimResult dis, asm_r;
    memset(&asm_r, 0, sizeof asm_r);
    cnStatus s = cn_simulate(a, &so, &dis, o->diag);
    margin_where(o, s, "margin.");
    if (s != CN_OK) return s;
    if (assemble) {
        so.assemble = true;
        s = cn_simulate(a, &so, &asm_r, o->diag);
        margin_where(o, s, "margin.");
    }
    if (s == CN_OK) {
        s = cn_report_sim(f, a, &dis, assemble ? &asm_r : NULL, 1);
        *outcome = cn_sim_outcome(&dis, assemble ? &asm_r : NULL);
    }
    cn_sim_result_free(&dis);
    cn_sim_result_free(&asm_r);
    return s;
}

static cnStatus run_plan(const cnAssembly *a, Opts *o, FILE *f, cnOutcome *outcome) {
    static const char *const keys[] = {"all", "subassemblies", "exhaustive", "accept_prestress", "support",
                                       "max_sub", "max_states", "max_seconds", "search_budget", "margin", NULL};
    cnPlanOptions po = cn_plan_options_default();
    int support = -1;
    long max_sub = 0, max_states = 0;
    only(o, keys, "plan");
    get_bool(o, "all", &po.all);
    get_bool(o, "subassemblies", &po.subassemblies);
    get_bool(o, "exhaustive", &po.exhaustive);
    get_bool(o, "accept_prestress", &po.sim.check.accept_prestress);
    get_choice(o, "support", SUPPORTS, &support);
    get_count(o, "max_sub", 1, 62, &max_sub);
    get_count(o, "max_states", 1, 1e8, &max_states);
    get_count(o, "search_budget", 1, 1e9, &po.sim.check.max_nodes);
    json_t *v = json_object_get(o->opts, "max_seconds");
    if (v && (!json_is_number(v) || !(json_number_value(v) > 0) || json_number_value(v) > 1e7))
        bad(o, "max_seconds", "expected a number of seconds above 0, at most 1e7, e.g. 30");
    if (o->st != CN_OK) return o->st;
    cnMarginOptions mo;
    cnSimOptions so = cn_sim_options_default();
    so.margin = path_margin_opts(a, o, "plan", &mo);
    if (o->st != CN_OK) return o->st;
    if (v) po.max_seconds = json_number_value(v);
    if (support >= 0)
        po.support = support == 0 ? CN_PLAN_SUPPORT_HOLD : support == 1 ? CN_PLAN_SUPPORT_PUSH : CN_PLAN_SUPPORT_BOTH;
    if (max_sub > 0) po.subassemblies = true, po.max_sub = (int)max_sub;
    if (max_states > 0) po.max_states = (int)max_states;
    cnPlanResult r;
    cnStatus s = cn_plan(a, &po, &r, o->diag);
    if (s != CN_OK) return s;
    if (so.margin) { /* each stable sequence listed, simulated with its margins (plan --margin) */
        so.check = po.sim.check;
        int rank = cn_plan_margin_rank(mo.kinds);
        cnPlanMargin *pm = NULL;
        int npm = 0;
        s = cn_plan_margins(a, &r, &so, rank, &pm, &npm, o->diag);
        margin_where(o, s, "margin.");
        if (s == CN_OK) s = cn_report_plan_margins(f, a, &r, pm, npm, rank, 1);
        cn_plan_margins_free(pm, npm);
    } else {
        s = cn_report_plan(f, a, &r, 1);
    }
    *outcome = cn_plan_outcome(&r);
    cn_plan_result_free(&r);
    return s;
}

static cnStatus run_directions(const cnAssembly *a, Opts *o, FILE *f, cnOutcome *outcome) {
    static const char *const keys[] = {"parts", NULL};
    only(o, keys, "directions");
    int n = 0;
    int *sel = o->st == CN_OK ? get_parts(o, a, &n) : NULL;
    if (o->st != CN_OK) return o->st;
    cnStatus s = cn_report_directions(f, a, sel, n, 1, o->diag);
    free(sel);
    *outcome = CN_OUTCOME_GOOD;
    return s;
}

static cnStatus run_contacts(const cnAssembly *a, Opts *o, FILE *f, cnOutcome *outcome) {
    static const char *const keys[] = {NULL};
    only(o, keys, "contacts");
    if (o->st != CN_OK) return o->st;
    cnContactSet cs = {0};
    cnOverlap ov;
    cnStatus s = cn_contacts_find(a, NULL, &cs, &ov, o->diag);
    if (s == CN_OK) s = cn_report_contacts(f, a, &cs, 1);
    cn_contacts_free(&cs);
    *outcome = CN_OUTCOME_GOOD;
    return s;
}

/* A vector of 2 or 3 finite numbers (2-D: z = 0). */
static void get_vec3(Opts *o, const char *key, double out[3]) {
    json_t *v = json_object_get(o->opts, key);
    if (!v) return;
    size_t n = json_is_array(v) ? json_array_size(v) : 0;
    bool ok = n == 2 || n == 3;
    double x[3] = {0, 0, 0};
    for (size_t i = 0; ok && i < n; i++) {
        json_t *e = json_array_get(v, i);
        x[i] = json_is_number(e) ? json_number_value(e) : NAN;
        ok = isfinite(x[i]);
    }
    if (ok && x[0] == 0 && x[1] == 0 && x[2] == 0) ok = false;
    if (!ok) bad(o, key, "expected an array of 2 or 3 finite numbers, not all zero, e.g. [0, 1, 0]");
    else memcpy(out, x, sizeof x);
}

/* The margins asked for, their directions, pair and tolerance (margin's options, or those of
 * simulate's "margin" object). */
static void margin_opts(const cnAssembly *a, Opts *o, cnMarginOptions *mo) {
    json_t *v = json_object_get(o->opts, "only");
    if (v) {
        static const char *const kinds[] = {"friction", "tilt", "lateral"};
        mo->kinds = 0;
        size_t i;
        json_t *e;
        bool ok = json_is_array(v) && json_array_size(v) > 0;
        json_array_foreach(v, i, e) {
            bool known = false;
            for (int k = 0; k < 3 && json_is_string(e); k++)
                if (!strcmp(kinds[k], json_string_value(e))) mo->kinds |= 1u << k, known = true;
            ok = ok && known;
        }
        if (!ok) bad(o, "only", "expected an array of \"friction\", \"tilt\" and \"lateral\"");
    }
    v = json_object_get(o->opts, "pair");
    if (v) {
        bool ok = json_is_array(v) && json_array_size(v) == 2;
        for (int k = 0; k < 2 && ok; k++) {
            json_t *e = json_array_get(v, (size_t)k);
            mo->pair[k] = json_is_string(e) ? cn_assembly_find_part(a, json_string_value(e)) : -1;
            ok = mo->pair[k] >= 0 && mo->pair[k] < a->nreal;
        }
        if (!ok || mo->pair[0] == mo->pair[1]) bad(o, "pair", "expected two different part names, e.g. [\"block\", \"table\"]");
    }
    get_vec3(o, "axis", mo->axis);
    get_vec3(o, "direction", mo->direction);
    get_real(o, "margin_tol", 1e-12, 0.1, &mo->rel_tol);
}

/* A margin's own complaint about its axis, direction or pair, placed under options (prefix: the
 * object holding them). */
static void margin_where(Opts *o, cnStatus s, const char *prefix) {
    if (s == CN_ERR_INPUT && (!strcmp(o->diag->where, "axis") || !strcmp(o->diag->where, "direction") ||
                              !strcmp(o->diag->where, "pair"))) {
        char where[96];
        snprintf(where, sizeof where, "options.%s%s", prefix, o->diag->where);
        snprintf(o->diag->where, sizeof o->diag->where, "%s", where);
    }
}

static cnStatus run_margin(const cnAssembly *a, Opts *o, FILE *f, cnOutcome *outcome) {
    static const char *const keys[] = {"only", "pair", "axis", "direction", "margin_tol", "max_seconds",
                                       "accept_prestress", "assume_planar", "search_budget", NULL};
    cnMarginOptions mo = cn_margin_options_default();
    only(o, keys, "margin");
    margin_opts(a, o, &mo);
    get_real(o, "max_seconds", 1e-3, 1e9, &mo.max_seconds);
    get_bool(o, "accept_prestress", &mo.check.accept_prestress);
    get_bool(o, "assume_planar", &mo.check.assume_planar);
    get_count(o, "search_budget", 1, 1e9, &mo.check.max_nodes);
    if (o->st != CN_OK) return o->st;
    cnMarginResult r;
    cnStatus s = cn_margin(a, &mo, &r, o->diag);
    margin_where(o, s, "");
    if (s == CN_OK) s = cn_report_margin(f, a, &r, 1);
    *outcome = r.verdict == CN_VERDICT_STABLE ? CN_OUTCOME_GOOD
               : r.verdict == CN_VERDICT_UNDECIDED ? CN_OUTCOME_UNDECIDED : CN_OUTCOME_NEGATIVE;
    cn_margin_result_free(&r);
    return s;
}

cnStatus cn_run_json(const cnAssembly *a, const char *command, const char *options, char **json,
                     cnOutcome *outcome, cnDiag *diag) {
    return cn_run_json_figures(a, command, options, json, outcome, NULL, diag);
}

cnStatus cn_run_json_figures(const cnAssembly *a, const char *command, const char *options, char **json,
                             cnOutcome *outcome, const cnRunFigures *fig, cnDiag *diag) {
    cnDiag local;
    if (!diag) diag = &local;
    cn_diag_clear(diag);
    *json = NULL;
    if (!a || !command) return cn_diag_set(diag, CN_ERR_INPUT, "", "no assembly or no command given");
    static const char *const names[] = {"check", "simulate", "plan", "directions", "contacts", "margin", NULL};
    static cnStatus (*const runs[])(const cnAssembly *, Opts *, FILE *, cnOutcome *) = {
        run_check, run_simulate, run_plan, run_directions, run_contacts, run_margin};
    int cmd = -1;
    for (int i = 0; names[i] && cmd < 0; i++)
        if (!strcmp(names[i], command)) cmd = i;
    if (cmd < 0)
        return cn_diag_set(diag, CN_ERR_INPUT, "command",
                           "no command '%.100s'; the commands are check, simulate, plan, directions, contacts and margin",
                           command);
    json_error_t err;
    json_t *opts = options && options[0] ? json_loads(options, JSON_REJECT_DUPLICATES, &err) : json_object();
    if (!opts)
        return cn_diag_set(diag, CN_ERR_INPUT, "options", "not a JSON object: %s (at %d:%d)", err.text,
                           err.line, err.column);
    if (!json_is_object(opts)) {
        json_decref(opts);
        return cn_diag_set(diag, CN_ERR_INPUT, "options", "expected a JSON object of options, e.g. {\"accept_prestress\": true}");
    }
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    if (!f) {
        json_decref(opts);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory for the report");
    }
    Opts o = {opts, diag, CN_OK, fig, NULL};
    cnOutcome out = CN_OUTCOME_GOOD;
    cnStatus s = runs[cmd](a, &o, f, &out);
    if (fclose(f) != 0 && s == CN_OK) s = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory for the report");
    json_decref(opts);
    if (s != CN_OK) {
        free(buf);
        return s;
    }
    *json = buf;
    if (outcome) *outcome = out;
    return CN_OK;
}
