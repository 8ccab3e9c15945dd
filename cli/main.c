/* cairn command line: argument parsing and exit codes only; the work is in libcairn.
 *
 * Exit status: 0 stable / solved, 1 unstable / no solution, 2 bad input or usage,
 * 3 no verdict (a numerical failure, or with friction "undecided"). */
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli.h"
#include "numerics.h"

static int dispatch(int argc, char **argv);

static int run(int argc, char **argv) {
    if (argc >= 2) {
        for (int k = 0; CLI_COMMANDS[k]; k++)
            if (!strcmp(argv[1], CLI_COMMANDS[k])) {
                int c2;
                char **v2;
                bool help;
                int rc = cli_normalize_args(argc, argv, &c2, &v2, &help);
                if (rc >= 0) return rc;
                cli_load_opts = cn_load_options_default();
                /* lcp reads no assembly: these options are its own errors there */
                if (!help && strcmp(argv[1], "lcp") && (rc = cli_take_load_options(&c2, v2)) >= 0) {
                    free(v2);
                    return rc;
                }
                rc = help ? cli_command_help(argv[1]) : dispatch(c2, v2);
                free(v2);
                return rc;
            }
    }
    return dispatch(argc, argv);
}

static int dispatch(int argc, char **argv) {
    if (argc < 2) return cli_usage_error("missing command");
    const char *c = argv[1];
    if (!strcmp(c, "--help") || !strcmp(c, "-h") || !strcmp(c, "help")) {
        fputs(cli_usage(), stdout);
        return EXIT_GOOD;
    }
    if (!strcmp(c, "--version")) {
        printf("cairn %s\n", CAIRN_VERSION);
        return EXIT_GOOD;
    }
    if (!strcmp(c, "lcp")) return cli_cmd_lcp(argc, argv);
    if (!strcmp(c, "check")) return cli_cmd_check(argc, argv);
    if (!strcmp(c, "contacts")) return cli_cmd_contacts(argc, argv);
    if (!strcmp(c, "simulate")) return cli_cmd_simulate(argc, argv);
    if (!strcmp(c, "directions")) return cli_cmd_directions(argc, argv);
    if (!strcmp(c, "plan")) return cli_cmd_plan(argc, argv);
    if (!strcmp(c, "export")) return cli_cmd_export(argc, argv);
    if (!strcmp(c, "margin")) return cli_cmd_margin(argc, argv);
    char msg[300];
    char near[80];
    snprintf(msg, sizeof msg, "unknown command '%.100s'%s", c, cli_suggest(NULL, c, near, sizeof near));
    return cli_usage_error(msg);
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
