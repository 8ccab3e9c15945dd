/* The smallest program on libcairn: load an assembly file, check it, print the verdict and the
 * parts that start to move. Exit 0 stable, 1 not stable, 2 bad input, 3 no verdict, as the CLI.
 *   cc check.c $(pkg-config --cflags --libs cairn) -o check && ./check wall.json   */
#include <stdio.h>

#include <cairn/cairn.h>

int main(int argc, char **argv) {
    if (argc != 2) {
        fprintf(stderr, "usage: %s ASSEMBLY.json\n", argv[0]);
        return 2;
    }
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_file(argv[1], &a, &d) != CN_OK) {
        fprintf(stderr, "%s: %s: %s\n", argv[1], d.where, d.message);
        return 2;
    }
    cnCheckResult r;
    if (cn_check(a, NULL, &r, &d) != CN_OK) { /* no verdict: numerical trouble */
        fprintf(stderr, "%s: %s\n", argv[1], d.message);
        cn_assembly_free(a);
        return 3;
    }
    printf("cairn %s: %s: %s\n", cn_version(), a->name ? a->name : argv[1], r.stable ? "stable" : "not stable");
    int code = r.stable ? 0 : 1;
    cn_check_result_free(&r);
    cn_assembly_free(a);
    return code;
}
