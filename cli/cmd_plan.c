/* The commands about motions: simulate (a plan along its paths), plan (find one), directions
 * (where each part can go). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cli.h"

/* The simulation's progress, on stderr when it is a terminal: step, samples, seconds. */
static void sim_progress(void *ctx, int step, int nsteps, long samples, double seconds) {
    cli_progress_line(ctx, seconds, "simulating: step %d of %d, %ld samples", step + 1, nsteps, samples);
}

int cli_cmd_simulate(int argc, char **argv) {
    const char *file = NULL, *csv = NULL, *figdir = NULL, *plan = NULL, *html = NULL;
    int json = 0, assemble = 0, cold = 0, prestress = 0, margin = 0;
    long budget = 0;
    cnMarginOptions mo = cn_margin_options_default();
    mo.rel_tol = 0; /* a path's: CN_SIM_MARGIN_REL_TOL */
    const char *pair_names = NULL, *margin_opt = NULL; /* the first margin option given */
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        int brc = cli_budget_arg(argc, argv, &i, &budget);
        if (brc >= 0) return brc;
        if (brc == -1) continue;
        int mrc = cli_path_margin_arg(argc, argv, &i, &mo, &pair_names, &margin_opt);
        if (mrc >= 0) return mrc;
        if (mrc == -1) continue;
        if (!strcmp(s, "--margin")) margin = 1;
        else if (!strcmp(s, "--json")) json = 1;
        else if (!strcmp(s, "--accept-prestress")) prestress = 1;
        else if (!strcmp(s, "--assemble")) assemble = 1;
        else if (!strcmp(s, "--cold")) cold = 1;
        else if (!strcmp(s, "--csv") || !strcmp(s, "--figures") || !strcmp(s, "--plan") || !strcmp(s, "--html")) {
            if (i + 1 >= argc) {
                char msg[100];
                snprintf(msg, sizeof msg, "%s needs a value", s);
                return cli_usage_error(msg);
            }
            if (!strcmp(s, "--csv")) csv = argv[++i];
            else if (!strcmp(s, "--plan")) plan = argv[++i];
            else if (!strcmp(s, "--html")) html = argv[++i];
            else figdir = argv[++i];
        } else {
            int rc = cli_other_arg(s, "simulate", &file);
            if (rc >= 0) return rc;
        }
    }
    int arc = cli_margin_alone(margin_opt, margin);
    if (arc >= 0) return arc;
    cnAssembly *as;
    int lrc = cli_load_plan(file, plan, &as);
    if (lrc >= 0) return lrc;
    int prc = margin ? cli_margin_pair(file, as, pair_names, &mo) : -1;
    if (prc >= 0) {
        cn_assembly_free(as);
        return prc;
    }
    int orc = cli_output_ok_plan("--csv", csv, file, plan, as);
    if (orc < 0) orc = cli_output_ok_plan("--html", html, file, plan, as);
    if (orc >= 0) {
        cn_assembly_free(as);
        return orc;
    }
    cnDiag d;
    cn_diag_clear(&d);
    cnSimOptions so = cn_sim_options_default();
    so.check.route = cli_env_route();
    so.cold = cold;
    so.check.accept_prestress = prestress;
    so.check.max_nodes = budget;
    if (margin) so.margin = &mo;
    cnSimResult dis, asm_r;
    memset(&asm_r, 0, sizeof asm_r);
    bool shown = false; /* progress on a terminal's stderr, one line rewritten in place */
    if (isatty(STDERR_FILENO)) so.progress = sim_progress, so.progress_ctx = &shown;
    cnStatus sst = cn_simulate(as, &so, &dis, &d);
    if (sst == CN_OK && assemble) {
        so.assemble = true;
        sst = cn_simulate(as, &so, &asm_r, &d);
        if (sst != CN_OK) cn_sim_result_free(&dis);
    }
    if (shown) fputs("\r\033[K", stderr); /* the progress line is gone before the report */
    if (sst != CN_OK) {
        cn_assembly_free(as);
        return cli_report_diag(file, &d);
    }
    int code = EXIT_GOOD;
    if (csv) {
        FILE *cf = fopen(csv, "w");
        if (!cf || cn_report_sim_csv(cf, as, &dis) != CN_OK ||
            (assemble && cn_report_sim_csv(cf, as, &asm_r) != CN_OK) || fclose(cf) != 0) {
            fprintf(stderr, "cairn: %s: cannot write the CSV file\n", csv);
            code = EXIT_USAGE;
        }
    }
    if (figdir && code == EXIT_GOOD) {
        if (cn_figure_simulation(figdir, as, &dis, &d) != CN_OK ||
            (assemble && cn_figure_simulation(figdir, as, &asm_r, &d) != CN_OK)) {
            code = cli_report_diag(figdir, &d);
        }
    }
    if (html && code == EXIT_GOOD &&
        cn_figure_simulation_html(html, as, &dis, assemble ? &asm_r : NULL, &d) != CN_OK)
        code = cli_report_diag(html, &d);
    if (code == EXIT_GOOD) {
        cn_report_sim(stdout, as, &dis, assemble ? &asm_r : NULL, json);
        cnOutcome out = cn_sim_outcome(&dis, assemble ? &asm_r : NULL);
        code = out == CN_OUTCOME_GOOD ? EXIT_GOOD : EXIT_NEGATIVE;
        /* no step failed, but one could not be decided: no verdict (a failure elsewhere is one) */
        int kk = 0;
        const cnSimResult *u = dis.undecided ? &dis : &asm_r;
        const cnStepResult *us = cli_undecided_step(u, &kk);
        if (out == CN_OUTCOME_UNDECIDED && us) {
            char where[96];
            snprintf(where, sizeof where, " at step %d (plan[%d])%s", kk + 1, u->plan_index[kk],
                     u->assemble ? " of the assembly" : "");
            cli_undecided_line(file, where, &us->onset);
            code = EXIT_NUMERIC;
        }
    }
    cn_sim_result_free(&dis);
    cn_sim_result_free(&asm_r);
    cn_assembly_free(as);
    return code;
}

/* The planner's progress, on stderr when it is a terminal: states, simulations, seconds. */
static void plan_progress(void *ctx, long states, long sims, double seconds) {
    cli_progress_line(ctx, seconds, "planning: %ld states, %ld simulations", states, sims);
}

/* plan's options. */
typedef struct {
    const char *file, *html;
    int json, margin;
    cnPlanOptions po;
    cnMarginOptions mo;
    const char *pair_names, *margin_opt;
} PlanArgs;

/* Read plan's options into pa: -1, else an exit status. */
static int plan_args(int argc, char **argv, PlanArgs *pa) {
    memset(pa, 0, sizeof *pa);
    pa->po = cn_plan_options_default();
    pa->po.sim.check.route = cli_env_route();
    pa->mo = cn_margin_options_default();
    pa->mo.rel_tol = 0; /* a path's: CN_SIM_MARGIN_REL_TOL */
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        int brc = cli_budget_arg(argc, argv, &i, &pa->po.sim.check.max_nodes);
        if (brc >= 0) return brc;
        if (brc == -1) continue;
        int mrc = cli_path_margin_arg(argc, argv, &i, &pa->mo, &pa->pair_names, &pa->margin_opt);
        if (mrc >= 0) return mrc;
        if (mrc == -1) continue;
        if (!strcmp(s, "--json")) pa->json = 1;
        else if (!strcmp(s, "--margin")) pa->margin = 1;
        else if (!strcmp(s, "--all")) pa->po.all = true;
        else if (!strcmp(s, "--accept-prestress")) pa->po.sim.check.accept_prestress = true;
        else if (!strcmp(s, "--subassemblies")) pa->po.subassemblies = true;
        else if (!strcmp(s, "--parallel")) pa->po.parallel = true;
        else if (!strcmp(s, "--exhaustive")) pa->po.exhaustive = true;
        else if (!strcmp(s, "--timing")) pa->po.timing = true;
        else if (!strcmp(s, "--html")) {
            if (i + 1 >= argc) return cli_usage_error("--html needs a file name, e.g. plan.html");
            pa->html = argv[++i];
        }
        else if (!strcmp(s, "--support")) {
            const char *v = i + 1 < argc ? argv[++i] : NULL;
            if (!v) return cli_usage_error("--support needs hold, push or both");
            if (!strcmp(v, "hold")) pa->po.support = CN_PLAN_SUPPORT_HOLD;
            else if (!strcmp(v, "push")) pa->po.support = CN_PLAN_SUPPORT_PUSH;
            else if (!strcmp(v, "both")) pa->po.support = CN_PLAN_SUPPORT_BOTH;
            else return cli_usage_error("--support must be hold, push or both (both: every candidate path tried held and pushed)");
        }
        else if (!strcmp(s, "--max-seconds")) {
            int rc = cli_number_arg(argc, argv, &i, "--max-seconds needs a number",
                                "--max-seconds must be a number of seconds from 0 to 1e7, e.g. 30",
                                1e-9, 1e7, false, &pa->po.max_seconds);
            if (rc >= 0) return rc;
        }
        else if (!strcmp(s, "--max-sub")) {
            pa->po.subassemblies = true;
            double v;
            int rc = cli_number_arg(argc, argv, &i, "--max-sub needs a number",
                                "--max-sub must be a whole number of parts from 1 to 62, e.g. 3", 1, 62, true, &v);
            if (rc >= 0) return rc;
            pa->po.max_sub = (int)v;
        }
        else if (!strcmp(s, "--max-states")) {
            double v;
            int rc = cli_number_arg(argc, argv, &i, "--max-states needs a number",
                                "--max-states must be a whole number from 1 to 1e8", 1, 1e8, true, &v);
            if (rc >= 0) return rc;
            pa->po.max_states = (int)v;
        }
        else {
            int rc = cli_other_arg(s, "plan", &pa->file);
            if (rc >= 0) return rc;
        }
    }
    return -1;
}

/* plan's report: the plan (or with --margin each stable sequence simulated with its margins,
 * ranked). -1, else an exit status. */
static int plan_report(const char *file, const cnAssembly *as, const cnPlanResult *r, const PlanArgs *pa) {
    cnDiag d;
    cn_diag_clear(&d);
    if (pa->margin) {
        /* each stable sequence listed, simulated as `simulate --plan` would, with its margins */
        cnSimOptions so = cn_sim_options_default();
        so.check = pa->po.sim.check;
        so.margin = &pa->mo;
        int rank = cn_plan_margin_rank(pa->mo.kinds);
        cnPlanMargin *pm = NULL;
        int npm = 0;
        if (cn_plan_margins(as, r, &so, rank, &pm, &npm, &d) != CN_OK) return cli_report_diag(file, &d);
        cn_report_plan_margins(stdout, as, r, pm, npm, rank, pa->json);
        cn_plan_margins_free(pm, npm);
    } else {
        cn_report_plan(stdout, as, r, pa->json);
    }
    return -1;
}

int cli_cmd_plan(int argc, char **argv) {
    PlanArgs pa;
    int rc = plan_args(argc, argv, &pa);
    if (rc >= 0) return rc;
    const char *file = pa.file, *html = pa.html;
    int margin = pa.margin;
    cnPlanOptions po = pa.po;
    if (html && file && !strcmp(file, "-"))
        return cli_usage_error("plan --html reads the assembly again for each sequence: give it as a file, not '-'");
    int arc = cli_margin_alone(pa.margin_opt, margin);
    if (arc >= 0) return arc;
    cnAssembly *as;
    int lrc = cli_load(file, &as);
    if (lrc >= 0) return lrc;
    int prc = margin ? cli_margin_pair(file, as, pa.pair_names, &pa.mo) : -1;
    if (prc >= 0) {
        cn_assembly_free(as);
        return prc;
    }
    int orc = cli_output_ok("--html", html, file, as);
    if (orc >= 0) {
        cn_assembly_free(as);
        return orc;
    }
    cnDiag d;
    cn_diag_clear(&d);
    cnPlanResult r;
    bool shown = false; /* progress on a terminal's stderr, one line rewritten in place */
    if (isatty(STDERR_FILENO)) po.progress = plan_progress, po.progress_ctx = &shown;
    cnStatus pst = cn_plan(as, &po, &r, &d);
    if (shown) fputs("\r\033[K", stderr); /* the progress line is gone before the report */
    if (pst != CN_OK) {
        cn_assembly_free(as);
        return cli_report_diag(file, &d);
    }
    if (html) {
        cnDiag hd;
        int hrc = cn_figure_plan_html(html, file, &cli_load_opts, as, &r, &po.sim, &hd) == CN_OK
                      ? EXIT_GOOD
                      : cli_report_diag(html, &hd);
        if (hrc != EXIT_GOOD) {
            cn_plan_result_free(&r);
            cn_assembly_free(as);
            return hrc;
        }
    }
    int rrc = plan_report(file, as, &r, &pa);
    if (rrc >= 0) {
        cn_plan_result_free(&r);
        cn_assembly_free(as);
        return rrc;
    }
    int code = r.stable ? EXIT_GOOD : EXIT_NEGATIVE;
    if (cn_plan_outcome(&r) == CN_OUTCOME_UNDECIDED) {
        /* none proved stable, but some were not decided: no verdict */
        fprintf(stderr, "cairn: %s: no verdict: no plan was proved stable, and %d state%s and %d "
                        "move%s were undecided (the search for a motion from rest ran out of "
                        "budget); give it more with --search-budget N, or take the weak reading "
                        "with --accept-prestress\n",
                file, r.search.undecided_states, r.search.undecided_states == 1 ? "" : "s",
                r.search.undecided_moves, r.search.undecided_moves == 1 ? "" : "s");
        code = EXIT_NUMERIC;
    }
    cn_plan_result_free(&r);
    cn_assembly_free(as);
    return code;
}

/* Free directions per free part (or for the subassembly named by --parts A,B). */
int cli_cmd_directions(int argc, char **argv) {
    const char *file = NULL, *parts = NULL;
    int json = 0, graph = 0;
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "--json")) json = 1;
        else if (!strcmp(s, "--graph")) graph = 1;
        else if (!strcmp(s, "--parts")) {
            if (i + 1 >= argc) return cli_usage_error("--parts needs a list of names, e.g. A,B");
            parts = argv[++i];
        } else {
            int rc = cli_other_arg(s, "directions", &file);
            if (rc >= 0) return rc;
        }
    }
    cnAssembly *as;
    int lrc = cli_load(file, &as);
    if (lrc >= 0) return lrc;
    cnDiag d;
    cn_diag_clear(&d);
    int *sel = NULL, nsel = 0;
    if (parts) {
        sel = calloc((size_t)as->nparts + 1, sizeof(int));
        char *copy = strdup(parts);
        const char *bad = NULL; /* why the list is refused, with %s the name */
        char *tok = copy, *next = NULL;
        for (; copy && sel && tok; tok = next) {
            next = strchr(tok, ',');
            if (next) *next++ = '\0';
            int k = tok[0] ? cn_assembly_find_part(as, tok) : -1;
            if (!tok[0]) bad = "--parts: an empty name%s; list part names separated by commas, e.g. A,B (no space, no comma at an end)";
            else if (k < 0 || k >= as->nreal || as->parts[k].fixed) bad = "--parts: '%s' is not a part that can move";
            for (int q = 0; q < nsel && !bad; q++)
                if (sel[q] == k) bad = "--parts: '%s' is listed twice";
            if (bad) break;
            sel[nsel++] = k;
        }
        if (bad) {
            char nm[256];
            fprintf(stderr, "cairn: %s: ", file);
            fprintf(stderr, bad, tok && tok[0] ? cli_safe_name(tok, nm) : "");
            fprintf(stderr, "\n");
        } else if (!copy || !sel)
            fprintf(stderr, "cairn: %s: out of memory\n", file);
        free(copy);
        if (bad || !copy || !sel) {
            free(sel);
            cn_assembly_free(as);
            return bad ? EXIT_USAGE : EXIT_NUMERIC;
        }
    }
    cnStatus s = graph ? cn_report_ndbg(stdout, as, sel, nsel, json, &d)
                       : cn_report_directions(stdout, as, sel, nsel, json, &d);
    free(sel);
    cn_assembly_free(as);
    if (s != CN_OK) return cli_report_diag(file, &d);
    return EXIT_GOOD;
}
