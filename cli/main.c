/* cairn command line: argument parsing and exit codes only; the work is in libcairn.
 *
 * Exit status: 0 stable / solved, 1 unstable / no solution, 2 bad input or usage,
 * 3 no verdict (a numerical failure, or with friction "undecided"). */
#include <errno.h>
#include <stdbool.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <strings.h>
#include <time.h>
#include <unistd.h>

#include <jansson.h>

#include "cairn/cairn.h"
#include "numerics.h"

enum { EXIT_GOOD = 0, EXIT_NEGATIVE = 1, EXIT_USAGE = 2, EXIT_NUMERIC = 3 };

/* The usage text, in two literals (C99 guarantees 4,095 characters to one); usage() joins them. */
static const char *const USAGE_1 =
    "usage: cairn <command> FILE [options]\n"
    "\n"
    "commands:\n"
    "  check FILE [--json] [--figure FIG] [--solver auto|lemke|pivot] [--no-lp-check]\n"
    "             [--lcp-out LCP] [--accept-prestress] [--search-budget N] [--max-seconds S]\n"
    "             [--reading K] [--margin]\n"
    "      does the assembly stay put? exit 0 stable, 1 unstable or not guaranteed (with\n"
    "      friction: a static solution exists but so does a motion from rest), 3 undecided\n"
    "      (a static solution exists; the search for a motion from rest ran out of budget);\n"
    "      --accept-prestress takes a static solution as enough (parts known to be wedged in);\n"
    "      --search-budget bounds the LPs spent proving that nothing moves (default 5e7 over\n"
    "      the square of its complementarity pairs, from 2000 to 20000);\n"
    "      --max-seconds, the seconds each such search may take (the verdict then depends on\n"
    "      the machine: off by default);\n"
    "      --reading K decides one reading of corner contacts' normals (as shown);\n"
    "      --figure draws the parts, contacts, forces and motion (FIG.png, .svg or .pdf: the\n"
    "      format from the name); --lcp-out writes the contact LCP (scaled) in the format\n"
    "      that 'cairn lcp' reads; --margin adds the margins of 'cairn margin' (weakest directions)\n"
    "  simulate FILE [--plan PLAN] [--json] [--assemble] [--csv FILE] [--figures DIR] [--cold]\n"
    "           [--html OUT.html] [--accept-prestress] [--search-budget N]\n"
    "           [--margin [--only KINDS] [--axis X,Y,Z] [--direction X,Y,Z] [--pair A,B] [--margin-tol R]]\n"
    "      run the file's plan (or the one in PLAN) along its paths (Algorithm 1); exit 0\n"
    "      when every step is stable, 3 when a step is undecided (none failed before it);\n"
    "      --assemble also runs it reversed, as an assembly; --html writes an interactive\n"
    "      report (one self-contained page: the plan played with a time slider, forces, onset);\n"
    "      --cold solves every sample's LCP from scratch instead of from the previous basis\n"    "      --margin: each stable step's weakest margins (those of 'cairn margin') over up to 24 of\n"
    "      its samples, each decided by the simulation's rules, and where on the path\n"
    "  plan FILE [--json] [--all] [--subassemblies] [--exhaustive] [--parallel]\n"
    "            [--max-states N] [--max-seconds S] [--timing] [--accept-prestress]\n"
    "            [--search-budget N] [--support hold|push|both] [--max-sub N]\n"
    "            [--html OUT.html] [--margin [--only KINDS] [--axis X,Y,Z] [--direction X,Y,Z]\n"
    "            [--pair A,B] [--margin-tol R]]\n"
    "      find stable disassembly sequences, paths and subassemblies; exit 0 when one exists,\n"
    "      3 when none is proved but some states or moves were undecided (not counted stable);\n"
    "      --max-states and --max-seconds bound the search (the report then says it is partial);\n"
    "      past 16 free parts it seeks one plan depth-first, unless --exhaustive (up to 62);\n"
    "      --timing puts the search's wall time in the JSON (which then differs run to run);\n"
    "      --support overrides how the gripper supports paths (both: each path held and pushed,\n"
    "      the path-dependence table shows where they differ); --subassemblies also splits\n"
    "      two-handed (a group taken out by one of its parts or held whole) and counts every\n"
    "      stable AND/OR tree; --max-sub N (implies --subassemblies) caps groups at N parts;\n"
    "      --html writes an interactive report whose table rows play each sequence; --margin\n"
    "      simulates each stable sequence listed with simulate --margin and ranks them by their\n"
    "      weakest step (lateral if asked, else tilt, else friction)\n";
static const char *const USAGE_2 =
    "  margin FILE [--json] [--only friction,tilt,lateral] [--pair A,B] [--axis X,Y,Z]\n"
    "              [--direction X,Y,Z] [--margin-tol R] [--max-seconds S] [--figure FIG]\n"
    "              [--accept-prestress] [--search-budget N]\n"
    "      how far from falling: the least friction at which it stands (every coefficient\n"
    "      scaled together, or the pair A,B's), the largest tilt of gravity (degrees) and the\n"
    "      largest horizontal acceleration (in g) it resists, each bracketed by two verdicts\n"
    "      and with the mechanism at collapse; the weakest axis or direction unless given;\n"
    "      --max-seconds leaves the brackets as they stand (proved, wider); --figure draws\n"
    "      each collapse mechanism to FIG with -friction, -tilt, -lateral before its ending;\n"
    "      exit 0 when it\n"
    "      stands as loaded, 1 when not, 3 when that verdict is undecided\n"
    "  directions FILE [--json] [--parts A,B] [--graph]\n"
    "      the directions each free part (or the named subassembly) can leave along;\n"
    "      --graph prints the non-directional blocking graph instead: its cells of directions,\n"
    "      in each which part is blocked by which, and the subassemblies that can leave\n"
    "  contacts FILE [--json]\n"
    "      list every contact found from the geometry\n"
    "  export FILE --to obj|gltf OUT\n"
    "      write the assembly as understood (every convex piece where its pose put it, supports\n"
    "      in a material of their own) for a 3-D viewer: OBJ (with OUT's .mtl) or glTF 2.0\n"
    "  lcp FILE [--solver lemke|pivot] [--json] [--repeat K]\n"
    "      solve an LCP in the text format (n, M row by row, q); exit 0 solved, 1 none found;\n"
    "      --repeat solves it K times and reports the median solve time (\"solve_seconds\")\n"
    "\n"
    "FILE (and PLAN) may be '-': standard input. Every option also takes the form --opt=value;\n"
    "--quiet (-q) prints nothing on standard output (the exit status says the verdict);\n"
    "cairn COMMAND --help shows one command. Every command that reads an assembly also takes\n"
    "--friction MU, --density D and --tolerance T (override the file's values) and, for a\n"
    "COMPAS assembly file (read directly: a part per block), --supports KEY,... (node keys);\n"
    "--mesh-anywhere lets a part's \"mesh\" path lead outside the assembly file's directory.\n"
    "\n"
    "exit status: 0 stable/solved, 1 unstable/no solution, 2 bad input or usage, 3 no verdict "
    "(numerical failure, or undecided)\n";

static const char *usage(void) {
    static char text[8192];
    if (!text[0]) snprintf(text, sizeof text, "%s%s", USAGE_1, USAGE_2);
    return text;
}

/* One line on stderr, as for every other input error. */
static int usage_error(const char *msg) {
    fprintf(stderr, "cairn: %s (run 'cairn --help' for usage)\n", msg);
    return EXIT_USAGE;
}

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
static const char *safe_name(const char *s, char out[256]) {
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
static int report_diag(const char *file, const cnDiag *d) {
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

/* The number after option argv[*i] (advancing *i), which must lie in [lo, hi] (whole when
 * `whole`). Returns -1 with *out set, else the exit status of the usage message `range_msg`. */
/* Is path the assembly file, or a mesh file the assembly was read from (relative to the
 * assembly file's directory, as the loader takes it)? */
/* Methods left out for cross-checks and benchmarks, named in the environment (any value):
 * CAIRN_NO_SPARSE_QP, CAIRN_NO_LOAD_DESCENT, CAIRN_LP_GLPK_ONLY (docs/performance.md). The
 * verdicts are the same; the library itself reads no environment. */
static unsigned env_route(void) {
    return (getenv("CAIRN_NO_SPARSE_QP") ? CN_ROUTE_NO_SPARSE_QP : 0u) |
           (getenv("CAIRN_NO_LOAD_DESCENT") ? CN_ROUTE_NO_LOAD_DESCENT : 0u) |
           (getenv("CAIRN_LP_GLPK_ONLY") ? CN_ROUTE_LP_GLPK_ONLY : 0u);
}

/* An output file of option opt, checked before any work: not '-', not an input, and writable
 * (an existing file, or a new one in an existing directory). Returns an exit status, or -1. */
static int output_ok_plan(const char *opt, const char *out, const char *file, const char *plan,
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

static int output_ok(const char *opt, const char *out, const char *file, const cnAssembly *as) {
    return output_ok_plan(opt, out, file, NULL, as);
}

static int number_arg(int argc, char **argv, int *i, const char *missing_msg,
                      const char *range_msg, double lo, double hi, bool whole, double *out) {
    if (*i + 1 >= argc) return usage_error(missing_msg);
    char *end;
    double v = strtod(argv[++*i], &end);
    if (end == argv[*i] || *end || !(v >= lo && v <= hi) || (whole && v != (double)(long)v))
        return usage_error(range_msg);
    *out = v;
    return -1;
}

/* The one stderr line of an undecided friction verdict (exit 3): `where` names the step, or is
 * empty for the assembly itself. */
static void undecided_line(const char *file, const char *where, const cnCheckResult *r) {
    const char *why = r->search_undecided ? r->search_undecided : "undecided";
    if (r->corners_undecided && r->corners_wide && r->corner_readings >= r->corner_readings_all) {
        fprintf(stderr, "cairn: %s: no verdict%s: %d contacts touch corner to corner and every one "
                        "of the %ld readings of their normals stands, but a cone of normals has more "
                        "than %d ends and the others were not tried\n",
                file, where, r->corners, r->corner_readings, CN_CORNER_ENDS);
        return;
    }
    if (r->corners_undecided) {
        fprintf(stderr, "cairn: %s: no verdict%s: %d contacts touch corner to corner and every one "
                        "of the %ld readings of their normals tried stands, but there are %.0f; "
                        "cairn decides at most %d\n",
                file, where, r->corners, r->corner_readings, r->corner_readings_all, CN_CORNER_READINGS);
        return;
    }
    char ran[160];
    if (!strstr(why, "too large")) /* else the LCP was too large to search at all */
        snprintf(ran, sizeof ran, "stopped after %ld LP%s (%s); give it more with %s, or",
                 r->search_nodes, r->search_nodes == 1 ? "" : "s", why,
                 strstr(why, "time") ? "--max-seconds S" : "--search-budget N");
    else
        snprintf(ran, sizeof ran, "was not run (%s);", why);
    fprintf(stderr, "cairn: %s: no verdict%s: a static solution exists, but the search for a "
                    "motion from rest %s take the weak reading with --accept-prestress\n",
            file, where, ran);
}

/* A simulation run that stopped at an undecided step: that step, for undecided_line. */
static const cnStepResult *undecided_step(const cnSimResult *R, int *kk) {
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
static int budget_arg(int argc, char **argv, int *i, long *out) {
    if (strcmp(argv[*i], "--search-budget")) return -2;
    double v;
    int rc = number_arg(argc, argv, i, "--search-budget needs a number of LPs",
                        "--search-budget must be a whole number of LPs from 1 to 1e9, e.g. 20000",
                        1, 1e9, true, &v);
    if (rc >= 0) return rc;
    *out = (long)v;
    return -1;
}

/* --figure FIG (check, margin): a name ending in .png, .svg or .pdf. Returns -1 when read. */
static int figure_arg(int argc, char **argv, int *i, const char **out) {
    if (*i + 1 >= argc) return usage_error("--figure needs a file name ending in .png, .svg or .pdf");
    *out = argv[++*i];
    const char *dot = strrchr(*out, '.');
    if (!dot || strchr(dot, '/') || (strcasecmp(dot, ".png") && strcasecmp(dot, ".svg") && strcasecmp(dot, ".pdf")))
        return usage_error("--figure takes its format from the file name: end it in .png, .svg or .pdf");
    return -1;
}

/* The end of every command's option loop: an unknown option, or the one FILE. Returns -1 to go
 * on, else an exit status. */
static const char *suggest(const char *cmd, const char *word, char *buf, size_t n);

static int other_arg(const char *s, const char *cmd, const char **file) {
    if (s[0] == '-' && s[1]) {
        char msg[400], near[80];
        snprintf(msg, sizeof msg, "unknown option '%.100s' for '%s'%s", s, cmd, suggest(cmd, s, near, sizeof near));
        return usage_error(msg);
    }
    if (*file) return usage_error("give exactly one FILE");
    *file = s;
    return -1;
}

/* Load the FILE every assembly command takes. Returns -1 with *as set, else an exit status
 * (the one-line message already written). */
/* The overrides every command that reads an assembly takes: --friction, --density,
 * --tolerance, --supports (taken out of the arguments by take_load_options). */
static cnLoadOptions load_opts;

static int load_plan(const char *file, const char *plan, cnAssembly **as) {
    if (!file) return usage_error("missing FILE");
    if (plan && !strcmp(file, "-") && !strcmp(plan, "-"))
        return usage_error("FILE and --plan cannot both be '-' (standard input)");
    cnDiag d;
    cn_diag_clear(&d);
    *as = NULL;
    if (cn_assembly_load_with(file, plan, NULL, &load_opts, as, &d) != CN_OK) return report_diag(file, &d);
    return -1;
}

/* Take --friction MU, --density D, --tolerance T, --supports KEY,... and --mesh-anywhere out of argv (after
 * normalize_args: values are separate words) into load_opts. */
static int take_load_options(int *argc, char **argv) {
    int n = 2;
    for (int i = 2; i < *argc; i++) {
        const char *s = argv[i];
        double v;
        int rc = -1;
        if (!strcmp(s, "--friction"))
            rc = number_arg(*argc, argv, &i, "--friction needs a coefficient, e.g. 0.6",
                            "--friction must be a number from 0 (frictionless) to 1e6, e.g. 0.6", 0, 1e6, false, &v),
            load_opts.friction = v;
        else if (!strcmp(s, "--density"))
            rc = number_arg(*argc, argv, &i, "--density needs a number", "--density must be a positive number up to 1e100",
                            1e-100, 1e100, false, &v),
            load_opts.density = v;
        else if (!strcmp(s, "--tolerance"))
            rc = number_arg(*argc, argv, &i, "--tolerance needs a number",
                            "--tolerance must be a relative tolerance from 1e-12 to 0.1, e.g. 1e-4", 1e-12, 1e-1, false, &v),
            load_opts.tolerance = v;
        else if (!strcmp(s, "--mesh-anywhere"))
            load_opts.mesh_anywhere = true;
        else if (!strcmp(s, "--supports")) {
            if (i + 1 >= *argc || !argv[i + 1][0]) return usage_error("--supports needs node keys, e.g. 0 or 0,1");
            load_opts.supports = argv[++i];
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

static int load(const char *file, cnAssembly **as) { return load_plan(file, NULL, as); }

typedef struct {
    const char *file;
    int json;
    const char *solver;
    int no_lp_check;
    int accept_prestress;
    long search_budget; /* --search-budget (0: the default) */
    int one_reading;    /* --reading K given */
    unsigned long long reading;
    const char *lcp_out;
    const char *figure;
    int repeat; /* lcp --repeat K (0: not given) */
    int margin; /* check --margin */
    double max_seconds; /* check --max-seconds (0: none) */
} Args;

static int parse_args(int argc, char **argv, Args *a, int allow_solver, int allow_lp_check) {
    memset(a, 0, sizeof *a);
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "--json")) a->json = 1;
        else if (allow_solver && !strcmp(s, "--solver")) {
            if (i + 1 >= argc) return usage_error("--solver needs a value");
            a->solver = argv[++i];
        } else if (allow_solver && !strncmp(s, "--solver=", 9)) a->solver = s + 9;
        else if (allow_lp_check && !strcmp(s, "--no-lp-check")) a->no_lp_check = 1;
        else if (allow_lp_check && !strcmp(s, "--accept-prestress")) a->accept_prestress = 1;
        else if (allow_lp_check && !strcmp(s, "--search-budget")) {
            int rc = budget_arg(argc, argv, &i, &a->search_budget);
            if (rc >= 0) return rc;
        }
        else if (allow_lp_check && !strcmp(s, "--reading")) {
            double v;
            int rc = number_arg(argc, argv, &i, "--reading needs the number of a reading of the corner contacts",
                                "--reading must be a whole number from 0 to 1e15, e.g. 5", 0, 1e15, true, &v);
            if (rc >= 0) return rc;
            a->one_reading = 1;
            a->reading = (unsigned long long)v;
        }
        else if (allow_lp_check && !strcmp(s, "--figure")) {
            int rc = figure_arg(argc, argv, &i, &a->figure);
            if (rc >= 0) return rc;
        } else if (allow_lp_check && !strcmp(s, "--margin")) {
            a->margin = 1;
        } else if (allow_lp_check && !strcmp(s, "--max-seconds")) {
            int rc = number_arg(argc, argv, &i, "--max-seconds needs a number of seconds",
                                "--max-seconds must be a number of seconds from 0.001 to 1e9", 1e-3, 1e9,
                                false, &a->max_seconds);
            if (rc >= 0) return rc;
        } else if (allow_lp_check && !strcmp(s, "--lcp-out")) {
            if (i + 1 >= argc) return usage_error("--lcp-out needs a file name");
            a->lcp_out = argv[++i];
        } else if (allow_solver && !allow_lp_check && !strcmp(s, "--repeat")) {
            double v;
            int rc = number_arg(argc, argv, &i, "--repeat needs a number of solves",
                                "--repeat must be a whole number from 1 to 1e6", 1, 1e6, true, &v);
            if (rc >= 0) return rc;
            a->repeat = (int)v;
        }
        else {
            int rc = other_arg(s, argv[1], &a->file);
            if (rc >= 0) return rc;
        }
    }
    if (!a->file) return usage_error("missing FILE");
    return -1;
}

static int cmp_double(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

static int cmd_lcp(int argc, char **argv) {
    Args a;
    int rc = parse_args(argc, argv, &a, 1, 0);
    if (rc >= 0) return rc;
    const char *solver = a.solver ? a.solver : "lemke";
    if (strcmp(solver, "lemke") && strcmp(solver, "pivot"))
        return usage_error("--solver must be lemke or pivot");
    cnLcp p = {0};
    cnDiag d;
    cn_diag_clear(&d);
    if (cn_lcp_read_file(a.file, &p, &d) != CN_OK) return report_diag(a.file, &d);
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

static int cmd_contacts(int argc, char **argv) {
    Args a;
    int rc = parse_args(argc, argv, &a, 0, 0);
    if (rc >= 0) return rc;
    cnAssembly *as;
    int lrc = load(a.file, &as);
    if (lrc >= 0) return lrc;
    cnDiag d;
    cn_diag_clear(&d);
    cnContactSet cs = {0};
    cnOverlap ov;
    cnStatus s = cn_contacts_find(as, NULL, &cs, &ov, &d);
    if (s != CN_OK) {
        cn_assembly_free(as);
        return report_diag(a.file, &d);
    }
    cn_report_contacts(stdout, as, &cs, a.json);
    cn_contacts_free(&cs);
    cn_assembly_free(as);
    return EXIT_GOOD;
}

/* The simulation's progress, on stderr when it is a terminal: step, samples, seconds. */
/* A progress line on stderr, rewritten in place, once a run has taken a second; *shown is set
 * so that the caller clears it before the report. */
static void progress_line(bool *shown, double seconds, const char *fmt, ...) {
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

static void sim_progress(void *ctx, int step, int nsteps, long samples, double seconds) {
    progress_line(ctx, seconds, "simulating: step %d of %d, %ld samples", step + 1, nsteps, samples);
}

static int margin_arg(int argc, char **argv, int *i, cnMarginOptions *mo, const char **pair_names);
static int margin_pair(const char *file, const cnAssembly *as, const char *names, cnMarginOptions *mo);

/* The margin options of simulate --margin and plan --margin (margin's, but --max-seconds, which
 * is the command's own): -2 when argv[*i] is none of them, -1 when read (*first: the first one
 * read, for "add --margin"), else an exit status. */
static int path_margin_arg(int argc, char **argv, int *i, cnMarginOptions *mo, const char **pair_names,
                           const char **first) {
    if (!strcmp(argv[*i], "--max-seconds")) return -2;
    const char *s = argv[*i];
    int rc = margin_arg(argc, argv, i, mo, pair_names);
    if (rc == -1 && !*first) *first = s;
    return rc;
}

/* "--only is an option of --margin: add --margin" when a margin option came without it; -1: fine. */
static int margin_alone(const char *first, int margin) {
    if (!first || margin) return -1;
    char msg[160];
    snprintf(msg, sizeof msg, "%s is an option of --margin: add --margin", first);
    return usage_error(msg);
}

static int cmd_simulate(int argc, char **argv) {
    const char *file = NULL, *csv = NULL, *figdir = NULL, *plan = NULL, *html = NULL;
    int json = 0, assemble = 0, cold = 0, prestress = 0, margin = 0;
    long budget = 0;
    cnMarginOptions mo = cn_margin_options_default();
    mo.rel_tol = 0; /* a path's: CN_SIM_MARGIN_REL_TOL */
    const char *pair_names = NULL, *margin_opt = NULL; /* the first margin option given */
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        int brc = budget_arg(argc, argv, &i, &budget);
        if (brc >= 0) return brc;
        if (brc == -1) continue;
        int mrc = path_margin_arg(argc, argv, &i, &mo, &pair_names, &margin_opt);
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
                return usage_error(msg);
            }
            if (!strcmp(s, "--csv")) csv = argv[++i];
            else if (!strcmp(s, "--plan")) plan = argv[++i];
            else if (!strcmp(s, "--html")) html = argv[++i];
            else figdir = argv[++i];
        } else {
            int rc = other_arg(s, "simulate", &file);
            if (rc >= 0) return rc;
        }
    }
    int arc = margin_alone(margin_opt, margin);
    if (arc >= 0) return arc;
    cnAssembly *as;
    int lrc = load_plan(file, plan, &as);
    if (lrc >= 0) return lrc;
    int prc = margin ? margin_pair(file, as, pair_names, &mo) : -1;
    if (prc >= 0) {
        cn_assembly_free(as);
        return prc;
    }
    int orc = output_ok_plan("--csv", csv, file, plan, as);
    if (orc < 0) orc = output_ok_plan("--html", html, file, plan, as);
    if (orc >= 0) {
        cn_assembly_free(as);
        return orc;
    }
    cnDiag d;
    cn_diag_clear(&d);
    cnSimOptions so = cn_sim_options_default();
    so.check.route = env_route();
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
        return report_diag(file, &d);
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
            code = report_diag(figdir, &d);
        }
    }
    if (html && code == EXIT_GOOD &&
        cn_figure_simulation_html(html, as, &dis, assemble ? &asm_r : NULL, &d) != CN_OK)
        code = report_diag(html, &d);
    if (code == EXIT_GOOD) {
        cn_report_sim(stdout, as, &dis, assemble ? &asm_r : NULL, json);
        cnOutcome out = cn_sim_outcome(&dis, assemble ? &asm_r : NULL);
        code = out == CN_OUTCOME_GOOD ? EXIT_GOOD : EXIT_NEGATIVE;
        /* no step failed, but one could not be decided: no verdict (a failure elsewhere is one) */
        int kk = 0;
        const cnSimResult *u = dis.undecided ? &dis : &asm_r;
        const cnStepResult *us = undecided_step(u, &kk);
        if (out == CN_OUTCOME_UNDECIDED && us) {
            char where[96];
            snprintf(where, sizeof where, " at step %d (plan[%d])%s", kk + 1, u->plan_index[kk],
                     u->assemble ? " of the assembly" : "");
            undecided_line(file, where, &us->onset);
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
    progress_line(ctx, seconds, "planning: %ld states, %ld simulations", states, sims);
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
        cnStatus s = plan ? cn_assembly_load_with(file, NULL, plan, &load_opts, &asms[i], &d) : CN_ERR_MEMORY;
        cn_string_free(plan);
        if (s == CN_OK) s = cn_simulate(asms[i], so, &sims[i], &d);
        if (s != CN_OK) {
            code = report_diag(file, &d);
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
            code = report_diag(html, &d);
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

static int cmd_plan(int argc, char **argv) {
    const char *file = NULL, *html = NULL;
    int json = 0, margin = 0;
    cnPlanOptions po = cn_plan_options_default();
    po.sim.check.route = env_route();
    cnMarginOptions mo = cn_margin_options_default();
    mo.rel_tol = 0; /* a path's: CN_SIM_MARGIN_REL_TOL */
    const char *pair_names = NULL, *margin_opt = NULL;
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        int brc = budget_arg(argc, argv, &i, &po.sim.check.max_nodes);
        if (brc >= 0) return brc;
        if (brc == -1) continue;
        int mrc = path_margin_arg(argc, argv, &i, &mo, &pair_names, &margin_opt);
        if (mrc >= 0) return mrc;
        if (mrc == -1) continue;
        if (!strcmp(s, "--json")) json = 1;
        else if (!strcmp(s, "--margin")) margin = 1;
        else if (!strcmp(s, "--all")) po.all = true;
        else if (!strcmp(s, "--accept-prestress")) po.sim.check.accept_prestress = true;
        else if (!strcmp(s, "--subassemblies")) po.subassemblies = true;
        else if (!strcmp(s, "--parallel")) po.parallel = true;
        else if (!strcmp(s, "--exhaustive")) po.exhaustive = true;
        else if (!strcmp(s, "--timing")) po.timing = true;
        else if (!strcmp(s, "--html")) {
            if (i + 1 >= argc) return usage_error("--html needs a file name, e.g. plan.html");
            html = argv[++i];
        }
        else if (!strcmp(s, "--support")) {
            const char *v = i + 1 < argc ? argv[++i] : NULL;
            if (!v) return usage_error("--support needs hold, push or both");
            if (!strcmp(v, "hold")) po.support = CN_PLAN_SUPPORT_HOLD;
            else if (!strcmp(v, "push")) po.support = CN_PLAN_SUPPORT_PUSH;
            else if (!strcmp(v, "both")) po.support = CN_PLAN_SUPPORT_BOTH;
            else return usage_error("--support must be hold, push or both (both: every candidate path tried held and pushed)");
        }
        else if (!strcmp(s, "--max-seconds")) {
            int rc = number_arg(argc, argv, &i, "--max-seconds needs a number",
                                "--max-seconds must be a number of seconds from 0 to 1e7, e.g. 30",
                                1e-9, 1e7, false, &po.max_seconds);
            if (rc >= 0) return rc;
        }
        else if (!strcmp(s, "--max-sub")) {
            po.subassemblies = true;
            double v;
            int rc = number_arg(argc, argv, &i, "--max-sub needs a number",
                                "--max-sub must be a whole number of parts from 1 to 62, e.g. 3", 1, 62, true, &v);
            if (rc >= 0) return rc;
            po.max_sub = (int)v;
        }
        else if (!strcmp(s, "--max-states")) {
            double v;
            int rc = number_arg(argc, argv, &i, "--max-states needs a number",
                                "--max-states must be a whole number from 1 to 1e8", 1, 1e8, true, &v);
            if (rc >= 0) return rc;
            po.max_states = (int)v;
        }
        else {
            int rc = other_arg(s, "plan", &file);
            if (rc >= 0) return rc;
        }
    }
    if (html && file && !strcmp(file, "-"))
        return usage_error("plan --html reads the assembly again for each sequence: give it as a file, not '-'");
    int arc = margin_alone(margin_opt, margin);
    if (arc >= 0) return arc;
    cnAssembly *as;
    int lrc = load(file, &as);
    if (lrc >= 0) return lrc;
    int prc = margin ? margin_pair(file, as, pair_names, &mo) : -1;
    if (prc >= 0) {
        cn_assembly_free(as);
        return prc;
    }
    int orc = output_ok("--html", html, file, as);
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
        return report_diag(file, &d);
    }
    if (html) {
        int hrc = plan_html(file, html, as, &r, &po.sim);
        if (hrc != EXIT_GOOD) {
            cn_plan_result_free(&r);
            cn_assembly_free(as);
            return hrc;
        }
    }
    if (margin) {
        /* each stable sequence listed, simulated as `simulate --plan` would, with its margins */
        cnSimOptions so = cn_sim_options_default();
        so.check = po.sim.check;
        so.margin = &mo;
        int rank = cn_plan_margin_rank(mo.kinds);
        cnPlanMargin *pm = NULL;
        int npm = 0;
        if (cn_plan_margins(as, &r, &so, rank, &pm, &npm, &d) != CN_OK) {
            cn_plan_result_free(&r);
            cn_assembly_free(as);
            return report_diag(file, &d);
        }
        cn_report_plan_margins(stdout, as, &r, pm, npm, rank, json);
        cn_plan_margins_free(pm, npm);
    } else {
        cn_report_plan(stdout, as, &r, json);
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

/* export FILE --to obj|gltf OUT: the assembly as understood, for a 3-D viewer (OBJ: its
 * materials in OUT with .mtl for its extension). */
static int cmd_export(int argc, char **argv) {
    const char *file = NULL, *to = NULL, *out = NULL;
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "--to")) {
            if (i + 1 >= argc) return usage_error("--to needs a format: obj or gltf");
            to = argv[++i];
            if (strcmp(to, "obj") && strcmp(to, "gltf")) return usage_error("--to must be obj or gltf");
        } else if (!file) {
            int rc = other_arg(s, "export", &file);
            if (rc >= 0) return rc;
        } else if (!out && (s[0] != '-' || !s[1])) {
            out = s;
        } else {
            int rc = other_arg(s, "export", &file);
            if (rc >= 0) return rc;
            return usage_error("export takes FILE --to FORMAT OUT");
        }
    }
    if (!to) return usage_error("export needs --to obj or --to gltf");
    if (!out) return usage_error("export needs an output file name (OUT.obj or OUT.gltf)");
    {
        const char *dot = strrchr(out, '.'), *slash = strrchr(out, '/');
        if (!dot || (slash && dot < slash) || strcasecmp(dot + 1, to)) {
            char msg[300];
            snprintf(msg, sizeof msg, "the output file of --to %s must end in .%s (so that it is not taken for "
                     "another kind of file, the assembly among them)", to, to);
            return usage_error(msg);
        }
    }
    cnAssembly *as;
    int lrc = load(file, &as);
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
        code = report_diag(out, &d);
    }
    if (f && fclose(f) != 0 && code == EXIT_GOOD) {
        fprintf(stderr, "cairn: %s: cannot write the export\n", out);
        code = EXIT_USAGE;
    }
    if (mtl && fclose(mtl) != 0 && code == EXIT_GOOD) {
        fprintf(stderr, "cairn: %s: cannot write the export\n", mtl_path);
        code = EXIT_USAGE;
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

/* Free directions per free part (or for the subassembly named by --parts A,B). */
static int cmd_directions(int argc, char **argv) {
    const char *file = NULL, *parts = NULL;
    int json = 0, graph = 0;
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        if (!strcmp(s, "--json")) json = 1;
        else if (!strcmp(s, "--graph")) graph = 1;
        else if (!strcmp(s, "--parts")) {
            if (i + 1 >= argc) return usage_error("--parts needs a list of names, e.g. A,B");
            parts = argv[++i];
        } else {
            int rc = other_arg(s, "directions", &file);
            if (rc >= 0) return rc;
        }
    }
    cnAssembly *as;
    int lrc = load(file, &as);
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
            fprintf(stderr, bad, tok && tok[0] ? safe_name(tok, nm) : "");
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
    if (s != CN_OK) return report_diag(file, &d);
    return EXIT_GOOD;
}

/* X,Y,Z (two numbers in 2-D are also taken): a vector option. Returns -1 when read. */
static int vec3_arg(int argc, char **argv, int *i, const char *opt, double out[3]) {
    char msg[200];
    snprintf(msg, sizeof msg, "%s needs a vector X,Y,Z (finite numbers, not all zero, separated by commas, e.g. 0,1,0)", opt);
    if (*i + 1 >= argc) return usage_error(msg);
    const char *s = argv[++*i];
    out[0] = out[1] = out[2] = 0;
    for (int k = 0; k < 3; k++) {
        char *end;
        out[k] = strtod(s, &end);
        if (end == s || !isfinite(out[k])) return usage_error(msg);
        if (*end == '\0' && k >= 1) {
            if (out[0] == 0 && out[1] == 0 && out[2] == 0) break;
            return -1;
        }
        if (*end != ',' || k == 2) return usage_error(msg);
        s = end + 1;
    }
    return usage_error(msg);
}

/* --only friction,tilt,lateral: the margins asked for. Returns -1 when read. */
static int kinds_arg(int argc, char **argv, int *i, unsigned *kinds) {
    const char *msg = "--only takes a list of friction, tilt and lateral separated by commas, e.g. tilt,lateral";
    if (*i + 1 >= argc) return usage_error(msg);
    const char *s = argv[++*i];
    *kinds = 0;
    while (*s) {
        size_t n = strcspn(s, ",");
        if (n == 8 && !strncmp(s, "friction", n)) *kinds |= CN_MARGIN_FRICTION;
        else if (n == 4 && !strncmp(s, "tilt", n)) *kinds |= CN_MARGIN_TILT;
        else if (n == 7 && !strncmp(s, "lateral", n)) *kinds |= CN_MARGIN_LATERAL;
        else return usage_error(msg);
        s += n;
        if (*s == ',') s++;
    }
    return *kinds ? -1 : usage_error(msg);
}

/* The margin options of `cairn margin` and `check --margin`, options i..: -2 when argv[*i] is
 * none of them, -1 when read, else an exit status. pair_names receives --pair's value. */
static int margin_arg(int argc, char **argv, int *i, cnMarginOptions *mo, const char **pair_names) {
    const char *s = argv[*i];
    if (!strcmp(s, "--only")) return kinds_arg(argc, argv, i, &mo->kinds);
    if (!strcmp(s, "--axis")) return vec3_arg(argc, argv, i, "--axis", mo->axis);
    if (!strcmp(s, "--direction")) return vec3_arg(argc, argv, i, "--direction", mo->direction);
    if (!strcmp(s, "--pair")) {
        if (*i + 1 >= argc) return usage_error("--pair needs two part names, e.g. block,table");
        *pair_names = argv[++*i];
        return -1;
    }
    if (!strcmp(s, "--max-seconds")) {
        double v;
        int rc = number_arg(argc, argv, i, "--max-seconds needs a number of seconds",
                            "--max-seconds must be a number of seconds from 0.001 to 1e9", 1e-3, 1e9, false, &v);
        if (rc >= 0) return rc;
        mo->max_seconds = v;
        return -1;
    }
    if (!strcmp(s, "--margin-tol")) {
        double v;
        int rc = number_arg(argc, argv, i, "--margin-tol needs a relative tolerance",
                            "--margin-tol must be a number from 1e-12 to 0.1, e.g. 1e-4", 1e-12, 0.1, false, &v);
        if (rc >= 0) return rc;
        mo->rel_tol = v;
        return -1;
    }
    return -2;
}

/* --pair A,B to part indices; -1 when done, else an exit status (message written). */
static int margin_pair(const char *file, const cnAssembly *as, const char *names, cnMarginOptions *mo) {
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
        fprintf(stderr, "cairn: %s: --pair: no part named '%s'\n", file, safe_name(ia < 0 || ia >= as->nreal ? a : b, nm));
        return EXIT_USAGE;
    }
    if (ia == ib) {
        fprintf(stderr, "cairn: %s: --pair names '%s' twice: give two different parts\n", file, safe_name(a, nm));
        return EXIT_USAGE;
    }
    mo->pair[0] = ia, mo->pair[1] = ib;
    return -1;
}

/* FIG with "-KIND" before its extension: margin --figure's file for one margin. */
static void margin_figure_name(const char *fig, const char *kind, char *out, size_t n) {
    const char *dot = strrchr(fig, '.');
    snprintf(out, n, "%.*s-%s%s", (int)(dot - fig), fig, kind, dot);
}

static int cmd_margin(int argc, char **argv) {
    const char *file = NULL, *pair_names = NULL, *figure = NULL;
    int json = 0;
    cnMarginOptions mo = cn_margin_options_default();
    mo.check.route = env_route();
    for (int i = 2; i < argc; i++) {
        const char *s = argv[i];
        int rc;
        if (!strcmp(s, "--json")) json = 1;
        else if (!strcmp(s, "--accept-prestress")) mo.check.accept_prestress = true;
        else if (!strcmp(s, "--figure")) {
            if ((rc = figure_arg(argc, argv, &i, &figure)) >= 0) return rc;
        } else if ((rc = budget_arg(argc, argv, &i, &mo.check.max_nodes)) != -2) {
            if (rc >= 0) return rc;
        } else if ((rc = margin_arg(argc, argv, &i, &mo, &pair_names)) != -2) {
            if (rc >= 0) return rc;
        } else if ((rc = other_arg(s, "margin", &file)) >= 0) return rc;
    }
    if (!file) return usage_error("missing FILE");
    cnAssembly *as;
    int lrc = load(file, &as);
    if (lrc >= 0) return lrc;
    int prc = margin_pair(file, as, pair_names, &mo);
    static const char *const kind_names[3] = {"friction", "tilt", "lateral"};
    char fig_names[3][4096];
    for (int k = 0; k < 3 && figure && prc < 0; k++) {
        margin_figure_name(figure, kind_names[k], fig_names[k], sizeof fig_names[k]);
        if ((mo.kinds ? mo.kinds : CN_MARGIN_ALL) & (1u << k)) prc = output_ok("--figure", fig_names[k], file, as);
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
        return report_diag(file, &d);
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
            return report_diag(fig_names[k], &d);
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
    mo.check.route = env_route();
    mo.check.accept_prestress = opt->accept_prestress;
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
    progress_line(ctx, seconds, "checking: searching for a motion from rest, %ld LPs", lps);
}

static int cmd_check(int argc, char **argv) {
    Args a;
    int rc = parse_args(argc, argv, &a, 1, 1);
    if (rc >= 0) return rc;
    cnCheckOptions opt = cn_check_options_default();
    opt.route = env_route();
    if (a.solver) {
        if (!strcmp(a.solver, "auto")) opt.solver = CN_SOLVER_AUTO;
        else if (!strcmp(a.solver, "lemke")) opt.solver = CN_SOLVER_LEMKE;
        else if (!strcmp(a.solver, "pivot")) opt.solver = CN_SOLVER_PIVOT;
        else return usage_error("--solver must be auto, lemke or pivot");
    }
    if (a.no_lp_check) opt.lp_crosscheck = false;
    opt.accept_prestress = a.accept_prestress;
    opt.max_nodes = a.search_budget;
    opt.one_reading = a.one_reading;
    opt.reading = a.reading;
    opt.keep_lcp = a.lcp_out != NULL;
    opt.max_seconds = a.max_seconds;
    bool shown = false; /* progress on a terminal's stderr, one line rewritten in place */
    if (isatty(STDERR_FILENO)) opt.progress = check_progress, opt.progress_ctx = &shown;
    cnAssembly *as;
    int lrc = load(a.file, &as);
    if (lrc >= 0) return lrc;
    int orc = output_ok("--lcp-out", a.lcp_out, a.file, as);
    if (orc < 0) orc = output_ok("--figure", a.figure, a.file, as);
    if (orc >= 0) {
        cn_assembly_free(as);
        return orc;
    }
    cnDiag d;
    cn_diag_clear(&d);
    cnCheckResult r;
    cnStatus s = cn_check(as, &opt, &r, &d);
    if (shown) fputs("\r\033[K", stderr); /* the progress line is gone before the report */
    if (a.lcp_out && r.lcp.n > 0) {
        FILE *lf = fopen(a.lcp_out, "w");
        if (!lf || cn_lcp_write(lf, &r.lcp) != CN_OK || fclose(lf) != 0) {
            fprintf(stderr, "cairn: %s: cannot write the LCP\n", a.lcp_out);
            cn_check_result_free(&r);
            cn_assembly_free(as);
            return EXIT_USAGE;
        }
    }
    if (s != CN_OK) {
        cn_check_result_free(&r);
        cn_assembly_free(as);
        return report_diag(a.file, &d);
    }
    if (a.figure) {
        cnFigureOptions fo = cn_figure_options_default();
        if (cn_figure_check_png(a.figure, as, &r, &fo, &d) != CN_OK) {
            cn_check_result_free(&r);
            cn_assembly_free(as);
            return report_diag(a.figure, &d);
        }
    }
    if (a.margin) {
        cnStatus ms = report_check_margin(as, &r, &opt, a.json, &d);
        if (ms != CN_OK) {
            cn_check_result_free(&r);
            cn_assembly_free(as);
            return report_diag(a.file, &d);
        }
    } else
        cn_report_check(stdout, as, &r, a.json);
    int code = r.stable ? EXIT_GOOD : EXIT_NEGATIVE;
    if (cn_check_outcome(&r) == CN_OUTCOME_UNDECIDED) { /* no verdict: the report says what is known */
        undecided_line(a.file, "", &r);
        code = EXIT_NUMERIC;
    }
    cn_check_result_free(&r);
    cn_assembly_free(as);
    return code;
}

/* The options that take a value: "--name=value" is split into "--name" "value" for them; a
 * flag given "=value" is refused. */
static const char *const VALUE_OPTIONS[] = {"--solver", "--search-budget", "--figure", "--lcp-out",
                                            "--repeat", "--plan", "--csv", "--figures", "--html",
                                            "--max-states", "--max-seconds", "--support",
                                            "--max-sub", "--parts", "--to", "--friction", "--density",
                                            "--tolerance", "--supports", "--only", "--pair", "--axis",
                                            "--direction", "--margin-tol", NULL};

static const char *const COMMANDS[] = {"check", "simulate", "plan", "margin", "directions", "contacts", "lcp", "export", NULL};

/* Edit distance (Levenshtein) of two short words; past 63 characters, large. */
static int edit_distance(const char *a, const char *b) {
    size_t la = strlen(a), lb = strlen(b);
    if (la > 63 || lb > 63) return 99;
    int d[64][64];
    for (size_t i = 0; i <= la; i++) d[i][0] = (int)i;
    for (size_t j = 0; j <= lb; j++) d[0][j] = (int)j;
    for (size_t i = 1; i <= la; i++)
        for (size_t j = 1; j <= lb; j++) {
            int sub = d[i - 1][j - 1] + (a[i - 1] != b[j - 1]);
            int del = d[i - 1][j] + 1, ins = d[i][j - 1] + 1;
            d[i][j] = sub < del ? (sub < ins ? sub : ins) : (del < ins ? del : ins);
        }
    return d[la][lb];
}

/* "; did you mean 'X'?" for the command name or option of cmd (cmd NULL: a command) nearest to
 * word, when one is within a third of its length (at least 2 edits); else "". Options are read
 * from the command's block of the usage text and the lines every command shares. */
static const char *suggest(const char *cmd, const char *word, char *buf, size_t n) {
    const char *best = NULL;
    size_t best_len = 0;
    int best_d = 99;
    int limit = (int)strlen(word) / 3 > 2 ? (int)strlen(word) / 3 : 2;
    if (!cmd) {
        for (int k = 0; COMMANDS[k]; k++) {
            int dd = edit_distance(word, COMMANDS[k]);
            if (dd < best_d) best_d = dd, best = COMMANDS[k], best_len = strlen(COMMANDS[k]);
        }
    } else {
        char head[32];
        snprintf(head, sizeof head, "\n  %s ", cmd);
        const char *u = usage(), *at = strstr(u, head), *end = at ? strstr(at + 1, "\n  ") : NULL;
        while (end && end[3] == ' ') end = strstr(end + 1, "\n  "); /* continuation lines */
        const char *shared = strstr(u, "\n\nFILE (and PLAN)");
        for (int part = 0; part < 2; part++) {
            const char *p = part ? shared : at, *q = part ? u + strlen(u) : end;
            if (!p) continue;
            if (!q) q = u + strlen(u);
            for (; p && p < q; p++) {
                if (!(p[0] == '-' && p[1] == '-' && (p == u || p[-1] == ' ' || p[-1] == '[' || p[-1] == '(' || p[-1] == '\n')))
                    continue;
                size_t len = 2;
                while (p[len] == '-' || (p[len] >= 'a' && p[len] <= 'z')) len++;
                char opt[64];
                if (len >= sizeof opt) continue;
                memcpy(opt, p, len), opt[len] = '\0';
                int dd = edit_distance(word, opt);
                if (dd < best_d) best_d = dd, best = p, best_len = len;
            }
        }
    }
    if (!best || best_d == 0 || best_d > limit) return "";
    snprintf(buf, n, "; did you mean '%.*s'?", (int)best_len, best);
    return buf;
}

/* `cairn COMMAND --help`: the command's block of the usage text (from its line to the next
 * command's), then the lines every command shares. */
static int command_help(const char *cmd) {
    char head[32];
    snprintf(head, sizeof head, "\n  %s ", cmd);
    const char *at = strstr(usage(), head);
    if (!at) return usage_error("no help for this command");
    at += 3; /* the newline and the indentation */
    const char *end = NULL;
    for (int k = 0; COMMANDS[k]; k++) {
        char other[32];
        snprintf(other, sizeof other, "\n  %s ", COMMANDS[k]);
        const char *o = strstr(at, other);
        if (o && o > at && (!end || o < end)) end = o;
    }
    const char *shared = strstr(usage(), "\n\nFILE (and PLAN)");
    if (!end || (shared && shared < end)) end = shared;
    /* the shared lines, as far as they concern this command */
    bool assembly = strcmp(cmd, "lcp") != 0, plan = !strcmp(cmd, "simulate");
    printf("usage: cairn %.*s\n\n", (int)(end - at), at);
    printf("%s may be '-': standard input. Every option also takes the form --opt=value;\n"
           "--quiet (-q) prints nothing on standard output (the exit status says the verdict).\n",
           plan ? "FILE or PLAN" : "FILE");
    if (assembly)
        printf("It also takes --friction MU, --density D and --tolerance T (override the file's\n"
               "values) and, for a COMPAS assembly file (read directly: a part per block),\n"
               "--supports KEY,... (node keys); --mesh-anywhere lets a part's \"mesh\" path lead\n"
               "outside the assembly file's directory.\n");
    printf("\nexit status: 0 stable/solved, 1 unstable/no solution, 2 bad input or usage, 3 no "
           "verdict (numerical failure, or undecided)\n");
    return EXIT_GOOD;
}

/* Conventions every command shares, applied before its own parsing: COMMAND --help (or -h),
 * --opt=value, --quiet (or -q: nothing on standard output; the exit status and stderr say what
 * happened, files asked for are still written). argv is rewritten in place into out (argc grows
 * by at most the options split). Returns -1 to go on, else an exit status. */
static int normalize_args(int argc, char **argv, int *outc, char ***outv, bool *help) {
    char **v = malloc(sizeof(char *) * (size_t)(2 * argc + 1));
    if (!v) return usage_error("out of memory");
    int n = 0;
    *help = false;
    bool quiet = false;
    for (int i = 0; i < argc; i++) {
        char *s = argv[i];
        if (i >= 2 && (!strcmp(s, "--help") || !strcmp(s, "-h"))) *help = true;
        else if (i >= 2 && (!strcmp(s, "--quiet") || !strcmp(s, "-q"))) quiet = true;
        else if (i >= 2 && !strncmp(s, "--", 2) && strchr(s, '=')) {
            size_t len = (size_t)(strchr(s, '=') - s);
            bool takes = false;
            for (int k = 0; VALUE_OPTIONS[k]; k++)
                if (strlen(VALUE_OPTIONS[k]) == len && !strncmp(s, VALUE_OPTIONS[k], len)) takes = true;
            if (!takes) {
                char msg[160];
                snprintf(msg, sizeof msg, "'%.*s' takes no value (only options such as --max-states=N do)",
                         (int)(len < 60 ? len : 60), s);
                free(v);
                return usage_error(msg);
            }
            s[len] = '\0'; /* argv's strings are ours to modify */
            v[n++] = s;
            v[n++] = s + len + 1;
        } else v[n++] = s;
    }
    v[n] = NULL;
    if (quiet && !freopen("/dev/null", "w", stdout)) {
        free(v);
        return usage_error("--quiet: cannot redirect standard output");
    }
    *outc = n;
    *outv = v;
    return -1;
}

static int dispatch(int argc, char **argv);

static int run(int argc, char **argv) {
    if (argc >= 2) {
        for (int k = 0; COMMANDS[k]; k++)
            if (!strcmp(argv[1], COMMANDS[k])) {
                int c2;
                char **v2;
                bool help;
                int rc = normalize_args(argc, argv, &c2, &v2, &help);
                if (rc >= 0) return rc;
                load_opts = cn_load_options_default();
                /* lcp reads no assembly: these options are its own errors there */
                if (!help && strcmp(argv[1], "lcp") && (rc = take_load_options(&c2, v2)) >= 0) {
                    free(v2);
                    return rc;
                }
                rc = help ? command_help(argv[1]) : dispatch(c2, v2);
                free(v2);
                return rc;
            }
    }
    return dispatch(argc, argv);
}

static int dispatch(int argc, char **argv) {
    if (argc < 2) return usage_error("missing command");
    const char *c = argv[1];
    if (!strcmp(c, "--help") || !strcmp(c, "-h") || !strcmp(c, "help")) {
        fputs(usage(), stdout);
        return EXIT_GOOD;
    }
    if (!strcmp(c, "--version")) {
        printf("cairn %s\n", CAIRN_VERSION);
        return EXIT_GOOD;
    }
    if (!strcmp(c, "lcp")) return cmd_lcp(argc, argv);
    if (!strcmp(c, "check")) return cmd_check(argc, argv);
    if (!strcmp(c, "contacts")) return cmd_contacts(argc, argv);
    if (!strcmp(c, "simulate")) return cmd_simulate(argc, argv);
    if (!strcmp(c, "directions")) return cmd_directions(argc, argv);
    if (!strcmp(c, "plan")) return cmd_plan(argc, argv);
    if (!strcmp(c, "export")) return cmd_export(argc, argv);
    if (!strcmp(c, "margin")) return cmd_margin(argc, argv);
    char msg[300];
    char near[80];
    snprintf(msg, sizeof msg, "unknown command '%.100s'%s", c, suggest(NULL, c, near, sizeof near));
    return usage_error(msg);
}

/* The command, then a check that its output reached stdout: a full disk or a closed pipe loses
 * the report, which is no verdict (exit 2 with one line, never exit 0 with nothing). */
int main(int argc, char **argv) {
    cli_blas_kernel(argv);
    cli_numerics_one_thread();
    int code = run(argc, argv);
    errno = 0;
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "cairn: cannot write the output to standard output (%s); check the disk "
                        "space or where stdout goes\n",
                errno ? strerror(errno) : "write error");
        return EXIT_USAGE;
    }
    return code;
}
