/* The usage text, `cairn COMMAND --help`, "did you mean" suggestions, and the conventions every
 * command shares (--opt=value, --help, --quiet). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"

/* The usage text, in two literals (C99 guarantees 4,095 characters to one); usage() joins them. */
static const char *const USAGE_1 =
    "usage: cairn <command> FILE [options]\n"
    "\n"
    "commands:\n"
    "  check FILE [--json] [--figure FIG] [--solver auto|lemke|pivot] [--no-lp-check]\n"
    "             [--lcp-out LCP] [--accept-prestress] [--search-budget N] [--max-seconds S]\n"
    "             [--reading K] [--margin] [--assume-planar]\n"
    "      does the assembly stay put? exit 0 stable, 1 unstable or not guaranteed (with\n"
    "      friction: a static solution exists but so does a motion from rest), 3 undecided\n"
    "      (a static solution exists; the search for a motion from rest ran out of budget);\n"
    "      --accept-prestress takes a static solution as enough (parts known to be wedged in);\n"
    "      --assume-planar: a 3-D prism (every part extruded along one axis across gravity)\n"
    "      that is undecided takes its 2-D section's verdict when that is stable (motions out\n"
    "      of the section's plane assumed away);\n"
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
    "              [--accept-prestress] [--assume-planar] [--search-budget N]\n"
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

const char *cli_usage(void) {
    static char text[8192];
    if (!text[0]) snprintf(text, sizeof text, "%s%s", USAGE_1, USAGE_2);
    return text;
}

/* One line on stderr, as for every other input error. */
int cli_usage_error(const char *msg) {
    fprintf(stderr, "cairn: %s (run 'cairn --help' for usage)\n", msg);
    return EXIT_USAGE;
}

/* The options that take a value: "--name=value" is split into "--name" "value" for them; a
 * flag given "=value" is refused. */
static const char *const VALUE_OPTIONS[] = {"--solver", "--search-budget", "--figure", "--lcp-out",
                                            "--repeat", "--plan", "--csv", "--figures", "--html",
                                            "--max-states", "--max-seconds", "--support",
                                            "--max-sub", "--parts", "--to", "--friction", "--density",
                                            "--tolerance", "--supports", "--only", "--pair", "--axis",
                                            "--direction", "--margin-tol", NULL};

const char *const CLI_COMMANDS[] = {"check", "simulate", "plan", "margin", "directions", "contacts", "lcp", "export", NULL};

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
const char *cli_suggest(const char *cmd, const char *word, char *buf, size_t n) {
    const char *best = NULL;
    size_t best_len = 0;
    int best_d = 99;
    int limit = (int)strlen(word) / 3 > 2 ? (int)strlen(word) / 3 : 2;
    if (!cmd) {
        for (int k = 0; CLI_COMMANDS[k]; k++) {
            int dd = edit_distance(word, CLI_COMMANDS[k]);
            if (dd < best_d) best_d = dd, best = CLI_COMMANDS[k], best_len = strlen(CLI_COMMANDS[k]);
        }
    } else {
        char head[32];
        snprintf(head, sizeof head, "\n  %s ", cmd);
        const char *u = cli_usage(), *at = strstr(u, head), *end = at ? strstr(at + 1, "\n  ") : NULL;
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
int cli_command_help(const char *cmd) {
    char head[32];
    snprintf(head, sizeof head, "\n  %s ", cmd);
    const char *at = strstr(cli_usage(), head);
    if (!at) return cli_usage_error("no help for this command");
    at += 3; /* the newline and the indentation */
    const char *end = NULL;
    for (int k = 0; CLI_COMMANDS[k]; k++) {
        char other[32];
        snprintf(other, sizeof other, "\n  %s ", CLI_COMMANDS[k]);
        const char *o = strstr(at, other);
        if (o && o > at && (!end || o < end)) end = o;
    }
    const char *shared = strstr(cli_usage(), "\n\nFILE (and PLAN)");
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
int cli_normalize_args(int argc, char **argv, int *outc, char ***outv, bool *help) {
    char **v = malloc(sizeof(char *) * (size_t)(2 * argc + 1));
    if (!v) return cli_usage_error("out of memory");
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
                return cli_usage_error(msg);
            }
            s[len] = '\0'; /* argv's strings are ours to modify */
            v[n++] = s;
            v[n++] = s + len + 1;
        } else v[n++] = s;
    }
    v[n] = NULL;
    if (quiet && !freopen("/dev/null", "w", stdout)) {
        free(v);
        return cli_usage_error("--quiet: cannot redirect standard output");
    }
    *outc = n;
    *outv = v;
    return -1;
}
