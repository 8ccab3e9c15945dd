/* One test binary; the argument picks the module (ctest runs one test per module). */
#include <string.h>

#include "test.h"

int cn_test_failures = 0;
int cn_test_checks = 0;

int main(int argc, char **argv) {
    struct {
        const char *name;
        void (*fn)(void);
    } mods[] = {{"lcp", test_lcp},
                {"geom", test_geom},
                {"load", test_load},
                {"contact", test_contact},
                {"stability", test_stability},
                {"strong", test_strong},
                {"simulate", test_simulate},
                {"motion", test_motion},
                {"plan", test_plan},
                {"mech", test_mech},
                {"report", test_report},
                {"degenerate", test_degenerate},
                {"api", test_api},
                {"ndbg", test_ndbg},
                {"lp", test_lp},
                {"margin", test_margin}};
    int nm = (int)(sizeof mods / sizeof mods[0]), ran = 0;
    for (int i = 0; i < nm; i++) {
        if (argc > 1 && strcmp(argv[1], mods[i].name)) continue;
        mods[i].fn();
        ran++;
    }
    if (!ran) {
        fprintf(stderr, "unknown test module '%s'\n", argv[1]);
        return 2;
    }
    printf("%d checks, %d failures\n", cn_test_checks, cn_test_failures);
    return cn_test_failures ? 1 : 0;
}
