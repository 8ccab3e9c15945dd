/* The commands about one state of an assembly: check, margin, contacts, export; and lcp. */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include <jansson.h>

#include "cli.h"

static int cmp_double(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

int cli_cmd_lcp(int argc, char **argv) {
    Args a;
    int rc = cli_parse_args(argc, argv, &a, 1, 0);
    if (rc >= 0) return rc;
    const char *solver = a.solver ? a.solver : "lemke";
    if (strcmp(solver, "lemke") && strcmp(solver, "pivot"))
        return cli_usage_error("--solver must be lemke or pivot");
    cnLcp p = {0};
    cnDiag d;
    cn_diag_clear(&d);
    if (cn_lcp_read_file(a.file, &p, &d) != CN_OK) return cli_report_diag(a.file, &d);
    double *z = calloc((size_t)p.n + 1, sizeof(double));
    double *w = calloc((size_t)p.n + 1, sizeof(double));
    if (!z || !w) {
        fprintf(stderr, "cairn: %s: out of memory\n", a.file);
        return EXIT_NUMERIC;
    }
    cnLcpOptions opt = cn_lcp_options_default();
    cnLcpInfo info;
    int reps = a.repeat > 0 ? a.repeat : 1;
    double *secs = calloc((size_t)reps, sizeof(double));
    if (!secs) {
        fprintf(stderr, "cairn: %s: out of memory\n", a.file);
        return EXIT_NUMERIC;
    }
    cnLcpStatus st = CN_LCP_NUMERIC;
    for (int k = 0; k < reps; k++) {
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        st = !strcmp(solver, "lemke") ? cn_lcp_lemke(&p, &opt, z, w, &info)
                                      : cn_lcp_pivot(&p, &opt, z, w, &info);
        clock_gettime(CLOCK_MONOTONIC, &t1);
        secs[k] = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    }
    qsort(secs, (size_t)reps, sizeof(double), cmp_double);
    double median = reps % 2 ? secs[reps / 2] : 0.5 * (secs[reps / 2 - 1] + secs[reps / 2]);
    free(secs);
    const char *note = NULL;
    if (st == CN_LCP_RAY) {
        bool feasible = true;
        if (cn_lcp_feasible(&p, &feasible, &d) == CN_OK && !feasible) {
            st = CN_LCP_INFEASIBLE;
            note = "no z >= 0 has M z + q >= 0 (decided by a linear program): the problem has "
                   "no solution";
        } else if (!strcmp(solver, "lemke")) {
            note = "Lemke's method ended on a secondary ray: no solution found (the problem is "
                   "feasible, so a solution may still exist if M is not copositive-plus)";
        } else {
            note = "principal pivoting found an unbounded direction: M is not positive "
                   "semidefinite; try --solver lemke";
        }
    } else if (st == CN_LCP_MAX_PIVOTS) {
        note = "the pivot budget was exhausted before a solution was found";
    } else if (st == CN_LCP_NUMERIC) {
        note = "no verified solution: a pivot was singular or the result failed verification";
    }
    cn_report_lcp(stdout, &p, st, solver, z, w, &info, a.json, note, a.repeat > 0 ? median : -1.0,
                  reps);
    int code = st == CN_LCP_SOLVED ? EXIT_GOOD
               : (st == CN_LCP_RAY || st == CN_LCP_INFEASIBLE) ? EXIT_NEGATIVE
                                                                : EXIT_NUMERIC;
    if (code == EXIT_NUMERIC) fprintf(stderr, "cairn: %s: %s\n", a.file, note);
    free(z);
    free(w);
    cn_lcp_free(&p);
    return code;
}

int cli_cmd_contacts(int argc, char **argv) {
    Args a;
    int rc = cli_parse_args(argc, argv, &a, 0, 0);
    if (rc >= 0) return rc;
    cnAssembly *as;
    int lrc = cli_load(a.file, &as);
    if (lrc >= 0) return lrc;
    cnDiag d;
    cn_diag_clear(&d);
    cnContactSet cs = {0};
    cnOverlap ov;
    cnStatus s = cn_contacts_find(as, NULL, &cs, &ov, &d);
    if (s != CN_OK) {
        cn_assembly_free(as);
        return cli_report_diag(a.file, &d);
    }
    cn_report_contacts(stdout, as, &cs, a.json);
    cn_contacts_free(&cs);
    cn_assembly_free(as);
    return EXIT_GOOD;
}

/* export FILE --to obj|gltf OUT: the assembly as understood, for a 3-D viewer (OBJ: its
 * materials in OUT with .mtl for its extension). */
int cli_cmd_export(int argc, char **argv) {
    const char *file = NULL, *to = NULL, *out = NULL;
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "--to")) {
            if (i + 1 >= argc) return cli_usage_error("--to needs a format: obj or gltf");
            to = argv[++i];
            if (strcmp(to, "obj") && strcmp(to, "gltf")) return cli_usage_error("--to must be obj or gltf");
        } else if (!file) {
            int rc = cli_other_arg(s, "export", &file);
            if (rc >= 0) return rc;
        } else if (!out && (s[0] != '-' || !s[1])) {
            out = s;
        } else {
            int rc = cli_other_arg(s, "export", &file);
            if (rc >= 0) return rc;
            return cli_usage_error("export takes FILE --to FORMAT OUT");
        }
    }
    if (!to) return cli_usage_error("export needs --to obj or --to gltf");
    if (!out) return cli_usage_error("export needs an output file name (OUT.obj or OUT.gltf)");
    {
        const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
        if (!dot || (slash && dot < slash) || strcasecmp(dot + 1, to)) {
            char msg[300];
            snprintf(msg, sizeof msg, "the output file of --to %s must end in .%s (so that it is not taken for "
                     "another kind of file, the assembly among them)", to, to);
            return cli_usage_error(msg);
        }
    }
    cnAssembly *as;
    int lrc = cli_load(file, &as);
    if (lrc >= 0) return lrc;
    /* never write over what was read: the assembly, or a mesh file of it (OUT, or OUT.mtl) */
    {
        char mtl_probe[4096];
        snprintf(mtl_probe, sizeof mtl_probe, "%.*s.mtl", (int)(strrchr(out, '.') - out), out);
        const char *outs[2] = {out, !strcmp(to, "obj") ? mtl_probe : NULL};
        for (int k = 0; k < 2; k++) {
            struct stat so;
            if (!outs[k] || stat(outs[k], &so) != 0) continue;
            if (cn_output_problem(outs[k], file, as) == CN_OUTPUT_INPUT) {
                fprintf(stderr, "cairn: %s: is a file the assembly was read from; export to another name\n", outs[k]);
                cn_assembly_free(as);
                return EXIT_USAGE;
            }
        }
    }
    FILE *f = fopen(out, "w"), *mtl = NULL;
    char mtl_path[4096], *mtl_name = NULL;
    if (f && !strcmp(to, "obj")) { /* the materials beside it: OUT with .mtl for its extension */
        snprintf(mtl_path, sizeof mtl_path, "%s", out);
        char *dot = strrchr(mtl_path, '.'), *slash = strrchr(mtl_path, '/');
        if (dot && (!slash || dot > slash)) *dot = '\0';
        strncat(mtl_path, ".mtl", sizeof mtl_path - strlen(mtl_path) - 1);
        mtl = fopen(mtl_path, "w");
        mtl_name = strrchr(mtl_path, '/') ? strrchr(mtl_path, '/') + 1 : mtl_path;
    }
    cnDiag d;
    cn_diag_clear(&d);
    int code = EXIT_GOOD;
    if (!f || (!strcmp(to, "obj") && !mtl)) {
        fprintf(stderr, "cairn: %s: cannot write the export: %s\n", !f ? out : mtl_path, strerror(errno));
        code = EXIT_USAGE;
    } else if (cn_export(f, as, to, mtl, mtl_name, &d) != CN_OK) {
        code = cli_report_diag(out, &d);
    }
    if (f && fclose(f) != 0 && code == EXIT_GOOD) {
        fprintf(stderr, "cairn: %s: cannot write the export\n", out);
        code = EXIT_USAGE;
    }
    if (mtl && fclose(mtl) != 0 && code == EXIT_GOOD) {
        fprintf(stderr, "cairn: %s: cannot write the export\n", mtl_path);
        code = EXIT_USAGE;
    }
    if (code != EXIT_GOOD) { /* no partial export left behind */
        if (f) remove(out);
        if (mtl) remove(mtl_path);
    }
    if (code == EXIT_GOOD) {
        int np = 0;
        for (int i = 0; i < as->nreal; i++) np += as->parts[i].npieces;
        printf("wrote %s (%s: %d part%s, %d convex piece%s)%s%s\n", out, to, as->nreal,
               as->nreal == 1 ? "" : "s", np, np == 1 ? "" : "s", mtl ? " and " : "", mtl ? mtl_path : "");
    }
    cn_assembly_free(as);
    return code;
}

int cli_cmd_margin(int argc, char **argv) {
    const char *file = NULL, *pair_names = NULL, *figure = NULL;
    int json = 0;
    cnMarginOptions mo = cn_margin_options_default();
    mo.check.route = cli_env_route();
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        int rc;
        if (!strcmp(s, "--json")) json = 1;
        else if (!strcmp(s, "--accept-prestress")) mo.check.accept_prestress = true;
        else if (!strcmp(s, "--assume-planar")) mo.check.assume_planar = true;
        else if (!strcmp(s, "--figure")) {
            if ((rc = cli_figure_arg(argc, argv, &i, &figure)) >= 0) return rc;
        } else if ((rc = cli_budget_arg(argc, argv, &i, &mo.check.max_nodes)) != -2) {
            if (rc >= 0) return rc;
        } else if ((rc = cli_margin_arg(argc, argv, &i, &mo, &pair_names)) != -2) {
            if (rc >= 0) return rc;
        } else if ((rc = cli_other_arg(s, "margin", &file)) >= 0) return rc;
    }
    if (!file) return cli_usage_error("missing FILE");
    cnAssembly *as;
    int lrc = cli_load(file, &as);
    if (lrc >= 0) return lrc;
    int prc = cli_margin_pair(file, as, pair_names, &mo);
    static const char *const kind_names[3] = {"friction", "tilt", "lateral"};
    char fig_names[3][4096];
    for (int k = 0; k < 3 && figure && prc < 0; k++) {
        cli_margin_figure_name(figure, kind_names[k], fig_names[k], sizeof fig_names[k]);
        if ((mo.kinds ? mo.kinds : CN_MARGIN_ALL) & (1u << k)) prc = cli_output_ok("--figure", fig_names[k], file, as);
    }
    if (prc >= 0) {
        cn_assembly_free(as);
        return prc;
    }
    cnDiag d;
    cn_diag_clear(&d);
    cnMarginResult r;
    cnStatus st = cn_margin(as, &mo, &r, &d);
    if (st != CN_OK) {
        cn_margin_result_free(&r);
        cn_assembly_free(as);
        if (st == CN_ERR_INPUT && (!strcmp(d.where, "axis") || !strcmp(d.where, "direction") || !strcmp(d.where, "pair"))) {
            fprintf(stderr, "cairn: %s: --%s: %s\n", file, d.where, d.message);
            return EXIT_USAGE;
        }
        return cli_report_diag(file, &d);
    }
    const cnMargin *ms[3] = {&r.friction, &r.tilt, &r.lateral};
    for (int k = 0; k < 3 && figure; k++) {
        const cnCheckResult *cr = &ms[k]->collapse;
        if (!ms[k]->computed || !cr->part ||
            (cr->verdict != CN_VERDICT_UNSTABLE && cr->verdict != CN_VERDICT_NOT_GUARANTEED))
            continue; /* no collapse verdict to draw */
        cnFigureOptions fo = cn_figure_options_default();
        if (cn_figure_margin(fig_names[k], as, ms[k], 1 << k, &fo, &d) != CN_OK) {
            cn_margin_result_free(&r);
            cn_assembly_free(as);
            return cli_report_diag(fig_names[k], &d);
        }
    }
    cn_report_margin(stdout, as, &r, json);
    int code = r.verdict == CN_VERDICT_STABLE ? EXIT_GOOD : r.verdict == CN_VERDICT_UNDECIDED ? EXIT_NUMERIC : EXIT_NEGATIVE;
    if (code == EXIT_NUMERIC)
        fprintf(stderr, "cairn: %s: no verdict as loaded (undecided): the margins are those of proved verdicts only\n", file);
    cn_margin_result_free(&r);
    cn_assembly_free(as);
    return code;
}

/* check --margin: the check's report with the margins after it (text), or under "margin" (JSON).
 * Returns CN_OK, or the margin's failure (diag set). */
static cnStatus report_check_margin(const cnAssembly *as, const cnCheckResult *r, const cnCheckOptions *opt,
                                    int json, cnDiag *d) {
    cnMarginOptions mo = cn_margin_options_default();
    mo.check.route = cli_env_route();
    mo.check.accept_prestress = opt->accept_prestress;
    mo.check.assume_planar = opt->assume_planar;
    mo.check.max_nodes = opt->max_nodes;
    mo.check.solver = opt->solver;
    mo.check.lp_crosscheck = opt->lp_crosscheck;
    cnMarginResult m;
    cnStatus st = cn_margin(as, &mo, &m, d);
    if (st != CN_OK) {
        cn_margin_result_free(&m);
        return st;
    }
    if (!json) {
        cn_report_check(stdout, as, r, 0);
        printf("margins (cairn margin says more):\n");
        cn_report_margin(stdout, as, &m, 0);
        cn_margin_result_free(&m);
        return CN_OK;
    }
    char *cb = NULL, *mb = NULL;
    size_t cl = 0, ml = 0;
    FILE *cf = open_memstream(&cb, &cl), *mf = open_memstream(&mb, &ml);
    if (cf) cn_report_check(cf, as, r, 1);
    if (mf) cn_report_margin(mf, as, &m, 1);
    if (cf) fclose(cf);
    if (mf) fclose(mf);
    cn_margin_result_free(&m);
    json_t *co = cb ? json_loads(cb, 0, NULL) : NULL, *mo_json = mb ? json_loads(mb, 0, NULL) : NULL;
    free(cb);
    free(mb);
    if (!co || !mo_json) {
        json_decref(co);
        json_decref(mo_json);
        return cn_diag_set(d, CN_ERR_MEMORY, "", "out of memory for the report");
    }
    json_object_del(mo_json, "format_version");
    json_object_del(mo_json, "name");
    json_object_del(mo_json, "dimension");
    json_object_set_new(co, "margin", mo_json);
    char *text = json_dumps(co, JSON_INDENT(2) | JSON_REAL_PRECISION(10));
    json_decref(co);
    if (!text) return cn_diag_set(d, CN_ERR_MEMORY, "", "out of memory for the report");
    printf("%s\n", text);
    free(text);
    return CN_OK;
}

/* The check's progress, on stderr when it is a terminal: the search for a motion from rest. */
static void check_progress(void *ctx, long lps, double seconds) {
    cli_progress_line(ctx, seconds, "checking: searching for a motion from rest, %ld LPs", lps);
}

int cli_cmd_check(int argc, char **argv) {
    Args a;
    int rc = cli_parse_args(argc, argv, &a, 1, 1);
    if (rc >= 0) return rc;
    cnCheckOptions opt = cn_check_options_default();
    opt.route = cli_env_route();
    if (a.solver) {
        if (!strcmp(a.solver, "auto")) opt.solver = CN_SOLVER_AUTO;
        else if (!strcmp(a.solver, "lemke")) opt.solver = CN_SOLVER_LEMKE;
        else if (!strcmp(a.solver, "pivot")) opt.solver = CN_SOLVER_PIVOT;
        else return cli_usage_error("--solver must be auto, lemke or pivot");
    }
    if (a.no_lp_check) opt.lp_crosscheck = false;
    opt.accept_prestress = a.accept_prestress;
    opt.assume_planar = a.assume_planar;
    opt.max_nodes = a.search_budget;
    opt.one_reading = a.one_reading;
    opt.reading = a.reading;
    opt.keep_lcp = a.lcp_out != NULL;
    opt.max_seconds = a.max_seconds;
    bool shown = false; /* progress on a terminal's stderr, one line rewritten in place */
    if (isatty(STDERR_FILENO)) opt.progress = check_progress, opt.progress_ctx = &shown;
    cnAssembly *as;
    int lrc = cli_load(a.file, &as);
    if (lrc >= 0) return lrc;
    int orc = cli_output_ok("--lcp-out", a.lcp_out, a.file, as);
    if (orc < 0) orc = cli_output_ok("--figure", a.figure, a.file, as);
    if (orc >= 0) {
        cn_assembly_free(as);
        return orc;
    }
    cnDiag d;
    cn_diag_clear(&d);
    cnCheckResult r;
    cnStatus s = cn_check(as, &opt, &r, &d);
    if (shown) fputs("\r\033[K", stderr); /* the progress line is gone before the report */
    if (a.lcp_out && r.solver.lcp.n > 0) {
        FILE *lf = fopen(a.lcp_out, "w");
        if (!lf || cn_lcp_write(lf, &r.solver.lcp) != CN_OK || fclose(lf) != 0) {
            fprintf(stderr, "cairn: %s: cannot write the LCP\n", a.lcp_out);
            cn_check_result_free(&r);
            cn_assembly_free(as);
            return EXIT_USAGE;
        }
    }
    if (s != CN_OK) {
        cn_check_result_free(&r);
        cn_assembly_free(as);
        return cli_report_diag(a.file, &d);
    }
    if (a.figure) {
        cnFigureOptions fo = cn_figure_options_default();
        if (cn_figure_check_png(a.figure, as, &r, &fo, &d) != CN_OK) {
            cn_check_result_free(&r);
            cn_assembly_free(as);
            return cli_report_diag(a.figure, &d);
        }
    }
    if (a.margin) {
        cnStatus ms = report_check_margin(as, &r, &opt, a.json, &d);
        if (ms != CN_OK) {
            cn_check_result_free(&r);
            cn_assembly_free(as);
            return cli_report_diag(a.file, &d);
        }
    } else
        cn_report_check(stdout, as, &r, a.json);
    int code = r.stable ? EXIT_GOOD : EXIT_NEGATIVE;
    if (cn_check_outcome(&r) == CN_OUTCOME_UNDECIDED) { /* no verdict: the report says what is known */
        cli_undecided_line(a.file, "", &r);
        code = EXIT_NUMERIC;
    }
    cn_check_result_free(&r);
    cn_assembly_free(as);
    return code;
}
