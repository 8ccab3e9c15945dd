/* One test binary; the argument picks the module (ctest runs one test per module). */
#include <string.h>

#include "test.h"

int cn_test_failures = 0;
int cn_test_checks = 0;

int main(int argc, char **argv) {
    struct {
        const char *name;
        void (*fn)(void);
    } mods[] = {
#define CN_TEST_MODULE(name, memcheck) {#name, test_##name},
#include "modules.def"
#undef CN_TEST_MODULE
    };
    int nm = (int)(sizeof mods / sizeof mods[0]), ran = 0;
    for (int i = 0; i < nm; i++) {
        if (argc > 1 && strcmp(argv[1], mods[i].name)) continue;
        mods[i].fn();
        ran++;
    }
    if (argc > 1 && !strcmp(argv[1], "--list")) { /* the modules, one a line */
        for (int i = 0; i < nm; i++) printf("%s\n", mods[i].name);
        return 0;
    }
    if (!ran) {
        fprintf(stderr, "unknown test module '%s'\n", argv[1]);
        return 2;
    }
    printf("%d checks, %d failures\n", cn_test_checks, cn_test_failures);
    return cn_test_failures ? 1 : 0;
}
