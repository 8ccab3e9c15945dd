/* Options every command shares, loading the assembly, and the messages and checks the commands
 * share (output files, undecided verdicts, progress lines). */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "cli.h"

/* The length of the valid UTF-8 sequence at s (1..4), or 0 when s does not start one. */
static int utf8_len(const unsigned char *s) {
    int n = s[0] < 0x80 ? 1 : s[0] >= 0xC2 && s[0] <= 0xDF ? 2 : s[0] >= 0xE0 && s[0] <= 0xEF ? 3
          : s[0] >= 0xF0 && s[0] <= 0xF4 ? 4 : 0;
    for (int k = 1; k < n; k++)
        if ((s[k] & 0xC0) != 0x80) return 0;
    return n;
}

/* A name from the command line as it may be printed in one line: C0 control characters, DEL,
 * C1 controls (UTF-8 0xC2 0x80..0x9F) and bytes that are not UTF-8 as \xHH, at most 60 bytes. */
const char *cli_safe_name(const char *s, char out[256]) {
    size_t n = 0;
    const unsigned char *p = (const unsigned char *)s;
    while (*p && n < 60 * 4) {
        int len = utf8_len(p);
        bool c1 = len == 2 && p[0] == 0xC2 && p[1] <= 0x9F;
        if (len == 0 || c1 || p[0] < 32 || p[0] == 127) {
            for (int k = 0; k < (c1 ? 2 : 1); k++) n += (size_t)snprintf(out + n, 256 - n, "\\x%02x", p[k]);
            p += c1 ? 2 : 1;
        } else {
            memcpy(out + n, p, (size_t)len);
            n += (size_t)len, p += len;
        }
    }
    out[n] = '\0';
    return out;
}

/* One line on stderr: cairn: FILE: WHERE: message */
int cli_report_diag(const char *file, const cnDiag *d) {
    if (d->file[0]) file = d->file;
    if (!strcmp(file, "-")) file = "<stdin>";
    if (d->where[0]) fprintf(stderr, "cairn: %s: %s: %s\n", file, d->where, d->message);
    else fprintf(stderr, "cairn: %s: %s\n", file, d->message);
    switch (d->code) {
    case CN_ERR_NUMERIC: return EXIT_NUMERIC;
    case CN_ERR_MEMORY: return EXIT_NUMERIC;
    default: return EXIT_USAGE;
    }
}

/* Methods left out for cross-checks and benchmarks, named in the environment (any value):
 * CAIRN_NO_SPARSE_QP, CAIRN_NO_LOAD_DESCENT, CAIRN_LP_GLPK_ONLY, CAIRN_NO_WHOLE
 * (docs/performance.md). The
 * verdicts are the same; the library itself reads no environment. */
unsigned cli_env_route(void) {
    return (getenv("CAIRN_NO_SPARSE_QP") ? CN_ROUTE_NO_SPARSE_QP : 0u) |
           (getenv("CAIRN_NO_LOAD_DESCENT") ? CN_ROUTE_NO_LOAD_DESCENT : 0u) |
           (getenv("CAIRN_LP_GLPK_ONLY") ? CN_ROUTE_LP_GLPK_ONLY : 0u) |
           (getenv("CAIRN_NO_WHOLE") ? CN_ROUTE_NO_WHOLE : 0u);
}

/* An output file of option opt, checked before any work: not '-', not an input, and writable
 * (an existing file, or a new one in an existing directory). Returns an exit status, or -1. */
int cli_output_ok_plan(const char *opt, const char *out, const char *file, const char *plan,
                          const cnAssembly *as) {
    if (!out) return -1;
    if (!strcmp(out, "-")) {
        fprintf(stderr, "cairn: %s -: '-' is not an output file here (the report is on standard output); "
                        "name a file\n", opt);
        return EXIT_USAGE;
    }
    cnOutputProblem p = cn_output_problem(out, file, as);
    if (plan && p != CN_OUTPUT_INPUT && cn_output_problem(out, plan, NULL) == CN_OUTPUT_INPUT) {
        fprintf(stderr, "cairn: %s: is the plan file; %s would write over it: name another output file\n",
                out, opt);
        return EXIT_USAGE;
    }
    if (p == CN_OUTPUT_INPUT) {
        fprintf(stderr, "cairn: %s: is a file the assembly was read from; %s would write over it: name "
                        "another output file\n", out, opt);
        return EXIT_USAGE;
    }
    if (p != CN_OUTPUT_OK) {
        fprintf(stderr, "cairn: %s: cannot be written (%s); name a writable file for %s\n", out,
                p == CN_OUTPUT_DIRECTORY ? "a directory"
                : p == CN_OUTPUT_DENIED  ? "no permission"
                                         : "its directory does not exist or is not writable", opt);
        return EXIT_USAGE;
    }
    return -1;
}

int cli_output_ok(const char *opt, const char *out, const char *file, const cnAssembly *as) {
    return cli_output_ok_plan(opt, out, file, NULL, as);
}

/* The number after option argv[*i] (advancing *i), which must lie in [lo, hi] (whole when
 * `whole`). Returns -1 with *out set, else the exit status of the usage message `range_msg`. */
int cli_number_arg(int argc, char **argv, int *i, const char *missing_msg,
                      const char *range_msg, double lo, double hi, bool whole, double *out) {
    if (*i + 1 >= argc) return cli_usage_error(missing_msg);
    char *end;
    double v = strtod(argv[++*i], &end);
    if (end == argv[*i] || *end || !(v >= lo && v <= hi) || (whole && v != (double)(long)v))
        return cli_usage_error(range_msg);
    *out = v;
    return -1;
}

/* The one stderr line of an undecided friction verdict (exit 3): `where` names the step, or is
 * empty for the assembly itself. */
void cli_undecided_line(const char *file, const char *where, const cnCheckResult *r) {
    const char *why = cn_undecided_text(r->undecided);
    if (r->undecided == CN_UNDECIDED_CORNERS_WIDE) {
        fprintf(stderr, "cairn: %s: no verdict%s: %d contacts touch corner to corner and every one "
                        "of the %ld readings of their normals stands, but a cone of normals has more "
                        "than %d ends and the others were not tried\n",
                file, where, r->corners.count, r->corners.readings, CN_CORNER_ENDS);
        return;
    }
    if (r->undecided == CN_UNDECIDED_CORNERS) {
        fprintf(stderr, "cairn: %s: no verdict%s: %d contacts touch corner to corner and every one "
                        "of the %ld readings of their normals tried stands, but there are %.0f; "
                        "cairn decides at most %d\n",
                file, where, r->corners.count, r->corners.readings, r->corners.readings_all, CN_CORNER_READINGS);
        return;
    }
    char ran[320];
    if (r->undecided != CN_UNDECIDED_TOO_LARGE) /* else too large to search at all */
        snprintf(ran, sizeof ran, "stopped after %ld LP%s (%s); give it more with %s, or",
                 r->solver.search_nodes, r->solver.search_nodes == 1 ? "" : "s", why,
                 r->undecided == CN_UNDECIDED_TIME ? "--max-seconds S" : "--search-budget N");
    else
        snprintf(ran, sizeof ran, "was not run whole (%s);", why);
    bool planar = r->section.checked && r->section.verdict == CN_VERDICT_STABLE;
    fprintf(stderr, "cairn: %s: no verdict%s: a static solution exists, but the search for a "
                    "motion from rest %s take the weak reading with --accept-prestress%s\n",
            file, where, ran,
            planar ? ", or its 2-D section's verdict (proved stable) with --assume-planar" : "");
}

/* A simulation run that stopped at an undecided step: that step, for undecided_line. */
const cnStepResult *cli_undecided_step(const cnSimResult *R, int *kk) {
    for (int k = 0; R->undecided && k < R->nsteps; k++)
        if (R->steps[k].status == CN_STEP_UNDECIDED) {
            *kk = k;
            return &R->steps[k];
        }
    return NULL;
}

/* --search-budget N (check, simulate, plan): the LPs the search for a motion from rest may
 * spend. Returns -2 when argv[*i] is not that option, -1 when it was read, else an exit
 * status. */
int cli_budget_arg(int argc, char **argv, int *i, long *out) {
    if (strcmp(argv[*i], "--search-budget")) return -2;
    double v;
    int rc = cli_number_arg(argc, argv, i, "--search-budget needs a number of LPs",
                        "--search-budget must be a whole number of LPs from 1 to 1e9, e.g. 20000",
                        1, 1e9, true, &v);
    if (rc >= 0) return rc;
    *out = (long)v;
    return -1;
}

/* --figure FIG (check, margin): a name ending in .png, .svg or .pdf. Returns -1 when read. */
int cli_figure_arg(int argc, char **argv, int *i, const char **out) {
    if (*i + 1 >= argc) return cli_usage_error("--figure needs a file name ending in .png, .svg or .pdf");
    *out = argv[++*i];
    const char *dot = strrchr(*out, '.');
    if (!dot || strchr(dot, '/') || (strcasecmp(dot, ".png") && strcasecmp(dot, ".svg") && strcasecmp(dot, ".pdf")))
        return cli_usage_error("--figure takes its format from the file name: end it in .png, .svg or .pdf");
    return -1;
}

/* The end of every command's option loop: an unknown option, or the one FILE. Returns -1 to go
 * on, else an exit status. */
int cli_other_arg(const char *s, const char *cmd, const char **file) {
    if (s[0] == '-' && s[1]) {
        char msg[400], near[80];
        snprintf(msg, sizeof msg, "unknown option '%.100s' for '%s'%s", s, cmd, cli_suggest(cmd, s, near, sizeof near));
        return cli_usage_error(msg);
    }
    if (*file) return cli_usage_error("give exactly one FILE");
    *file = s;
    return -1;
}

/* The overrides every command that reads an assembly takes: --friction, --density,
 * --tolerance, --supports (taken out of the arguments by take_load_options). */
cnLoadOptions cli_load_opts;

/* ... with the plan read from another file (NULL: the assembly file's own). */
int cli_load_plan(const char *file, const char *plan, cnAssembly **as) {
    if (!file) return cli_usage_error("missing FILE");
    if (plan && !strcmp(file, "-") && !strcmp(plan, "-"))
        return cli_usage_error("FILE and --plan cannot both be '-' (standard input)");
    cnDiag d;
    cn_diag_clear(&d);
    *as = NULL;
    if (cn_assembly_load_with(file, plan, NULL, &cli_load_opts, as, &d) != CN_OK) return cli_report_diag(file, &d);
    return -1;
}

/* Take --friction MU, --density D, --tolerance T, --supports KEY,... and --mesh-anywhere out of argv (after
 * normalize_args: values are separate words) into load_opts. */
int cli_take_load_options(int *argc, char **argv) {
    int n = 2;
    for (int i = 2; i < *argc; i++) {
        const char *s = argv[i];
        double v;
        int rc = -1;
        if (!strcmp(s, "--friction"))
            rc = cli_number_arg(*argc, argv, &i, "--friction needs a coefficient, e.g. 0.6",
                            "--friction must be a number from 0 (frictionless) to 1e6, e.g. 0.6", 0, 1e6, false, &v),
            cli_load_opts.friction = v;
        else if (!strcmp(s, "--density"))
            rc = cli_number_arg(*argc, argv, &i, "--density needs a number", "--density must be a positive number up to 1e100",
                            1e-100, 1e100, false, &v),
            cli_load_opts.density = v;
        else if (!strcmp(s, "--tolerance"))
            rc = cli_number_arg(*argc, argv, &i, "--tolerance needs a number",
                            "--tolerance must be a relative tolerance from 1e-12 to 0.1, e.g. 1e-4", 1e-12, 1e-1, false, &v),
            cli_load_opts.tolerance = v;
        else if (!strcmp(s, "--mesh-anywhere"))
            cli_load_opts.mesh_anywhere = true;
        else if (!strcmp(s, "--supports")) {
            if (i + 1 >= *argc || !argv[i + 1][0]) return cli_usage_error("--supports needs node keys, e.g. 0 or 0,1");
            cli_load_opts.supports = argv[++i];
        } else {
            argv[n++] = argv[i];
            continue;
        }
        if (rc >= 0) return rc;
    }
    *argc = n;
    argv[n] = NULL;
    return -1;
}

/* Load the FILE every assembly command takes. Returns -1 with *as set, else an exit status
 * (the one-line message already written). */
int cli_load(const char *file, cnAssembly **as) { return cli_load_plan(file, NULL, as); }

int cli_parse_args(int argc, char **argv, Args *a, int allow_solver, int allow_lp_check) {
    memset(a, 0, sizeof *a);
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "--json")) a->json = 1;
        else if (allow_solver && !strcmp(s, "--solver")) {
            if (i + 1 >= argc) return cli_usage_error("--solver needs a value");
            a->solver = argv[++i];
        } else if (allow_solver && !strncmp(s, "--solver=", 9)) a->solver = s + 9;
        else if (allow_lp_check && !strcmp(s, "--no-lp-check")) a->no_lp_check = 1;
        else if (allow_lp_check && !strcmp(s, "--accept-prestress")) a->accept_prestress = 1;
        else if (allow_lp_check && !strcmp(s, "--assume-planar")) a->assume_planar = 1;
        else if (allow_lp_check && !strcmp(s, "--search-budget")) {
            int rc = cli_budget_arg(argc, argv, &i, &a->search_budget);
            if (rc >= 0) return rc;
        }
        else if (allow_lp_check && !strcmp(s, "--reading")) {
            double v;
            int rc = cli_number_arg(argc, argv, &i, "--reading needs the number of a reading of the corner contacts",
                                "--reading must be a whole number from 0 to 1e15, e.g. 5", 0, 1e15, true, &v);
            if (rc >= 0) return rc;
            a->one_reading = 1;
            a->reading = (unsigned long long)v;
        }
        else if (allow_lp_check && !strcmp(s, "--figure")) {
            int rc = cli_figure_arg(argc, argv, &i, &a->figure);
            if (rc >= 0) return rc;
        } else if (allow_lp_check && !strcmp(s, "--margin")) {
            a->margin = 1;
        } else if (allow_lp_check && !strcmp(s, "--max-seconds")) {
            int rc = cli_number_arg(argc, argv, &i, "--max-seconds needs a number of seconds",
                                "--max-seconds must be a number of seconds from 0.001 to 1e9", 1e-3, 1e9,
                                false, &a->max_seconds);
            if (rc >= 0) return rc;
        } else if (allow_lp_check && !strcmp(s, "--lcp-out")) {
            if (i + 1 >= argc) return cli_usage_error("--lcp-out needs a file name");
            a->lcp_out = argv[++i];
        } else if (allow_solver && !allow_lp_check && !strcmp(s, "--repeat")) {
            double v;
            int rc = cli_number_arg(argc, argv, &i, "--repeat needs a number of solves",
                                "--repeat must be a whole number from 1 to 1e6", 1, 1e6, true, &v);
            if (rc >= 0) return rc;
            a->repeat = (int)v;
        }
        else {
            int rc = cli_other_arg(s, argv[1], &a->file);
            if (rc >= 0) return rc;
        }
    }
    if (!a->file) return cli_usage_error("missing FILE");
    return -1;
}

/* A progress line on stderr, rewritten in place, once a run has taken a second; *shown is set
 * so that the caller clears it before the report. */
void cli_progress_line(bool *shown, double seconds, const char *fmt, ...) {
    if (seconds < 1) return; /* quick runs show nothing */
    *shown = true;
    va_list ap;
    va_start(ap, fmt);
    fputs("\rcairn: ", stderr);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, ", %.0f s\033[K", seconds);
    fflush(stderr);
}

/* The margin options of simulate --margin and plan --margin (margin's, but --max-seconds, which
 * is the command's own): -2 when argv[*i] is none of them, -1 when read (*first: the first one
 * read, for "add --margin"), else an exit status. */
int cli_path_margin_arg(int argc, char **argv, int *i, cnMarginOptions *mo, const char **pair_names,
                           const char **first) {
    if (!strcmp(argv[*i], "--max-seconds")) return -2;
    const char *s = argv[*i];
    int rc = cli_margin_arg(argc, argv, i, mo, pair_names);
    if (rc == -1 && !*first) *first = s;
    return rc;
}

/* "--only is an option of --margin: add --margin" when a margin option came without it; -1: fine. */
int cli_margin_alone(const char *first, int margin) {
    if (!first || margin) return -1;
    char msg[160];
    snprintf(msg, sizeof msg, "%s is an option of --margin: add --margin", first);
    return cli_usage_error(msg);
}

/* X,Y,Z (two numbers in 2-D are also taken): a vector option. Returns -1 when read. */
static int vec3_arg(int argc, char **argv, int *i, const char *opt, double out[3]) {
    char msg[200];
    snprintf(msg, sizeof msg, "%s needs a vector X,Y,Z (finite numbers, not all zero, separated by commas, e.g. 0,1,0)", opt);
    if (*i + 1 >= argc) return cli_usage_error(msg);
    const char *s = argv[++*i];
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k < 3; k++) {
        char *end;
        out[k] = strtod(s, &end);
        if (end == s || !isfinite(out[k])) return cli_usage_error(msg);
        if (*end == '\0' && k >= 1) {
            if (out[0] == 0 && out[1] == 0 && out[2] == 0) break;
            return -1;
        }
        if (*end != ',' || k == 2) return cli_usage_error(msg);
        s = end + 1;
    }
    return cli_usage_error(msg);
}

/* --only friction,tilt,lateral: the margins asked for. Returns -1 when read. */
static int kinds_arg(int argc, char **argv, int *i, unsigned *kinds) {
    const char *msg = "--only takes a list of friction, tilt and lateral separated by commas, e.g. tilt,lateral";
    if (*i + 1 >= argc) return cli_usage_error(msg);
    const char *s = argv[++*i];
    *kinds = 0;
    while (*s) {
        size_t n = strcspn(s, ",");
        if (n == 8 && !strncmp(s, "friction", n)) *kinds |= CN_MARGIN_FRICTION;
        else if (n == 4 && !strncmp(s, "tilt", n)) *kinds |= CN_MARGIN_TILT;
        else if (n == 7 && !strncmp(s, "lateral", n)) *kinds |= CN_MARGIN_LATERAL;
        else return cli_usage_error(msg);
        s += n;
        if (*s == ',') s++;
    }
    return *kinds ? -1 : cli_usage_error(msg);
}

/* The margin options of `cairn margin` and `check --margin`, options i..: -2 when argv[*i] is
 * none of them, -1 when read, else an exit status. pair_names receives --pair's value. */
int cli_margin_arg(int argc, char **argv, int *i, cnMarginOptions *mo, const char **pair_names) {
    const char *s = argv[*i];
    if (!strcmp(s, "--only")) return kinds_arg(argc, argv, i, &mo->kinds);
    if (!strcmp(s, "--axis")) return vec3_arg(argc, argv, i, "--axis", mo->axis);
    if (!strcmp(s, "--direction")) return vec3_arg(argc, argv, i, "--direction", mo->direction);
    if (!strcmp(s, "--pair")) {
        if (*i + 1 >= argc) return cli_usage_error("--pair needs two part names, e.g. block,table");
        *pair_names = argv[++*i];
        return -1;
    }
    if (!strcmp(s, "--max-seconds")) {
        double v;
        int rc = cli_number_arg(argc, argv, i, "--max-seconds needs a number of seconds",
                            "--max-seconds must be a number of seconds from 0.001 to 1e9", 1e-3, 1e9, false, &v);
        if (rc >= 0) return rc;
        mo->max_seconds = v;
        return -1;
    }
    if (!strcmp(s, "--margin-tol")) {
        double v;
        int rc = cli_number_arg(argc, argv, i, "--margin-tol needs a relative tolerance",
                            "--margin-tol must be a number from 1e-12 to 0.1, e.g. 1e-4", 1e-12, 0.1, false, &v);
        if (rc >= 0) return rc;
        mo->rel_tol = v;
        return -1;
    }
    return -2;
}

/* --pair A,B to part indices; -1 when done, else an exit status (message written). */
int cli_margin_pair(const char *file, const cnAssembly *as, const char *names, cnMarginOptions *mo) {
    if (!names) return -1;
    const char *comma = strchr(names, ',');
    char a[256], b[256], nm[256];
    if (!comma || comma == names || !comma[1] || strchr(comma + 1, ',') || (size_t)(comma - names) >= sizeof a) {
        fprintf(stderr, "cairn: %s: --pair takes two part names separated by a comma, e.g. block,table\n", file);
        return EXIT_USAGE;
    }
    snprintf(a, sizeof a, "%.*s", (int)(comma - names), names);
    snprintf(b, sizeof b, "%s", comma + 1);
    int ia = cn_assembly_find_part(as, a), ib = cn_assembly_find_part(as, b);
    if (ia < 0 || ib < 0 || ia >= as->nreal || ib >= as->nreal) {
        fprintf(stderr, "cairn: %s: --pair: no part named '%s'\n", file, cli_safe_name(ia < 0 || ia >= as->nreal ? a : b, nm));
        return EXIT_USAGE;
    }
    if (ia == ib) {
        fprintf(stderr, "cairn: %s: --pair names '%s' twice: give two different parts\n", file, cli_safe_name(a, nm));
        return EXIT_USAGE;
    }
    mo->pair[0] = ia, mo->pair[1] = ib;
    return -1;
}

/* FIG with "-KIND" before its extension: margin --figure's file for one margin. */
void cli_margin_figure_name(const char *fig, const char *kind, char *out, size_t n) {
    const char *dot = strrchr(fig, '.');
    snprintf(out, n, "%.*s-%s%s", (int)(dot - fig), fig, kind, dot);
}
