/* The command line's pieces (private to cli/): exit codes, the usage text and shared
 * conventions (usage.c), options and loading (options.c), and the commands (cmd_check.c,
 * cmd_plan.c), dispatched by main.c. */
#ifndef CAIRN_CLI_H
#define CAIRN_CLI_H

#include <stdbool.h>
#include <stddef.h>

#include "cairn/cairn.h"

enum { EXIT_GOOD = 0, EXIT_NEGATIVE = 1, EXIT_USAGE = 2, EXIT_NUMERIC = 3 };

typedef struct {
    const char *file;
    int json;
    const char *solver;
    int no_lp_check;
    int accept_prestress;
    int assume_planar;
    long search_budget; /* --search-budget (0: the default) */
    int one_reading;    /* --reading K given */
    unsigned long long reading;
    const char *lcp_out;
    const char *figure;
    int repeat; /* lcp --repeat K (0: not given) */
    int margin; /* check --margin */
    double max_seconds; /* check --max-seconds (0: none) */
} Args;

/* The overrides every command that reads an assembly takes (options.c) */
extern cnLoadOptions cli_load_opts;
/* The commands, in the order of the usage text, NULL-terminated (usage.c) */
extern const char *const CLI_COMMANDS[];

/* usage.c: the usage text, help, suggestions, conventions every command shares */
int cli_command_help(const char *cmd);
int cli_normalize_args(int argc, char **argv, int *outc, char ***outv, bool *help);
const char *cli_suggest(const char *cmd, const char *word, char *buf, size_t n);
const char *cli_usage(void);
int cli_usage_error(const char *msg);

/* options.c: options, loading, messages */
int cli_budget_arg(int argc, char **argv, int *i, long *out);
unsigned cli_env_route(void);
int cli_figure_arg(int argc, char **argv, int *i, const char **out);
int cli_load(const char *file, cnAssembly **as);
int cli_load_plan(const char *file, const char *plan, cnAssembly **as);
int cli_margin_alone(const char *first, int margin);
int cli_margin_arg(int argc, char **argv, int *i, cnMarginOptions *mo, const char **pair_names);
void cli_margin_figure_name(const char *fig, const char *kind, char *out, size_t n);
int cli_margin_pair(const char *file, const cnAssembly *as, const char *names, cnMarginOptions *mo);
int cli_number_arg(int argc, char **argv, int *i, const char *missing_msg, const char *range_msg,
                   double lo, double hi, bool whole, double *out);
int cli_other_arg(const char *s, const char *cmd, const char **file);
int cli_output_ok(const char *opt, const char *out, const char *file, const cnAssembly *as);
int cli_output_ok_plan(const char *opt, const char *out, const char *file, const char *plan,
                       const cnAssembly *as);
int cli_parse_args(int argc, char **argv, Args *a, int allow_solver, int allow_lp_check);
int cli_path_margin_arg(int argc, char **argv, int *i, cnMarginOptions *mo,
                        const char **pair_names, const char **first);
void cli_progress_line(bool *shown, double seconds, const char *fmt, ...);
int cli_report_diag(const char *file, const cnDiag *d);
const char *cli_safe_name(const char *s, char out[256]);
int cli_take_load_options(int *argc, char **argv);
void cli_undecided_line(const char *file, const char *where, const cnCheckResult *r);
const cnStepResult *cli_undecided_step(const cnSimResult *R, int *kk);

/* cmd_check.c: check, margin, contacts, lcp, export */
int cli_cmd_check(int argc, char **argv);
int cli_cmd_contacts(int argc, char **argv);
int cli_cmd_export(int argc, char **argv);
int cli_cmd_lcp(int argc, char **argv);
int cli_cmd_margin(int argc, char **argv);

/* cmd_plan.c: simulate, plan, directions */
int cli_cmd_directions(int argc, char **argv);
int cli_cmd_plan(int argc, char **argv);
int cli_cmd_simulate(int argc, char **argv);

#endif
