/* libFuzzer target: JSON text -> assembly -> static check (make fuzz). */
#include <stdint.h>
#include <stdlib.h>
#include "cairn/cairn.h"
#include "fuzz.h"
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *s = fuzz_text(data, size);
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(s, "fuzz", &a, &d) == CN_OK) {
        cnCheckResult r;
        cnCheckOptions o = cn_check_options_default();
        o.max_nodes = 20;
        if (a->nparts <= 12 && cn_check(a, &o, &r, &d) == CN_OK) cn_check_result_free(&r);
        cn_assembly_free(a);
    }
    free(s);
    return 0;
}
