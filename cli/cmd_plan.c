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

/* Rows of the plan's table that plan --html plays, at most: each is simulated and kept for the
 * page, and --all may list hundreds of thousands. */
#define PLAN_HTML_MAX_ROWS 200

/* plan --html: every row of the sequence x path table simulated along its paths (its plan
 * loaded with the assembly, as `simulate --plan` would), then one page with a run per row (the
 * first PLAN_HTML_MAX_ROWS of them). */
static int plan_html(const char *file, const char *html, const cnAssembly *as, const cnPlanResult *r,
                     const cnSimOptions *so) {
    int n = 0, done = 0, code = EXIT_GOOD;
    int playable = 0; /* rows with steps to play, and those past the page's limit */
    size_t cap_rows = (size_t)(r->nrows < PLAN_HTML_MAX_ROWS ? r->nrows : PLAN_HTML_MAX_ROWS) + 1;
    cnAssembly **asms = calloc(cap_rows, sizeof *asms);
    cnSimResult *sims = calloc(cap_rows, sizeof *sims);
    const cnSimResult **runs = calloc(cap_rows, sizeof *runs);
    char **labels = calloc(cap_rows, sizeof *labels);
    const char **details = calloc(cap_rows, sizeof *details);
    cnDiag d;
    cn_diag_clear(&d);
    if (!asms || !sims || !runs || !labels || !details) {
        fprintf(stderr, "cairn: %s: out of memory\n", html);
        code = EXIT_NUMERIC;
    }
    /* the rows with steps to play (a row of no step: the assembly is not stable as it stands) */
    for (int row = 0; row < r->nrows && code == EXIT_GOOD; row++) {
        const cnPlanSequence *seq = &r->table[row].seq;
        if (seq->n == 0) continue;
        /* a move rejected by Proposition 1 on no particular path (the search past 16 free parts
           rejects a part that way before generating its paths): nothing to play */
        bool pathless = false;
        for (int k = 0; k < seq->n; k++) pathless |= seq->steps[k].nseg == 0;
        if (pathless) continue;
        if (++playable > PLAN_HTML_MAX_ROWS) continue;
        int i = n++;
        char *plan = cn_plan_sequence_json(as, seq);
        cnStatus s = plan ? cn_assembly_load_with(file, NULL, plan, &cli_load_opts, &asms[i], &d) : CN_ERR_MEMORY;
        cn_string_free(plan);
        if (s == CN_OK) s = cn_simulate(asms[i], so, &sims[i], &d);
        if (s != CN_OK) {
            code = cli_report_diag(file, &d);
            break;
        }
        runs[i] = &sims[i];
        done++; /* sims[0 .. done - 1] are freed at the end */
        details[i] = cn_plan_row_word(&r->table[row]);
        size_t cap = 64;
        for (int k = 0; k < seq->n; k++) cap += 8 + strlen(seq->steps[k].path) + 64 * (size_t)seq->steps[k].move.n;
        labels[i] = malloc(cap);
        if (!labels[i]) {
            code = EXIT_NUMERIC;
            break;
        }
        int len = snprintf(labels[i], cap, "%d.", row + 1);
        for (int k = 0; k < seq->n; k++) {
            const cnPlanMove *m = &seq->steps[k];
            len += snprintf(labels[i] + len, cap - (size_t)len, " ");
            for (int j = 0; j < m->move.n; j++)
                len += snprintf(labels[i] + len, cap - (size_t)len, "%s%.60s", j ? "+" : "", as->parts[m->move.idx[j]].name);
            len += snprintf(labels[i] + len, cap - (size_t)len, " (%s)", m->path);
        }
    }
    if (code == EXIT_GOOD) {
        /* no row to play: the page shows the assembly at rest and why */
        if (n == 0) asms[0] = (cnAssembly *)as;
        char more[160];
        snprintf(more, sizeof more, "disassembly sequences: click a row to play it (the first %d of the table's %d "
                 "rows with steps; the text report lists the table)", PLAN_HTML_MAX_ROWS, playable);
        const char *sub = playable > n ? more
                          : n > 0 ? "disassembly sequences: click a row to play it"
                          : r->unstable_at_start ? "no sequence to play: the assembly is not stable as it stands"
                                                 : "no sequence to play";
        if (cn_figure_html(html, (const cnAssembly *const *)asms, runs, (const char *const *)labels, details, n, sub,
                           &d) != CN_OK)
            code = cli_report_diag(html, &d);
        if (n == 0) asms[0] = NULL;
    }
    for (int i = 0; i < done; i++) {
        cn_sim_result_free(&sims[i]);
        free(labels[i]);
    }
    for (int i = 0; asms && i < (int)cap_rows - 1; i++) cn_assembly_free(asms[i]);
    free(asms), free(sims), free(runs), free(labels), free(details);
    return code;
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
        int hrc = plan_html(file, html, as, &r, &po.sim);
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
