/* libFuzzer target: LCP text -> Lemke and principal pivoting (make fuzz). */
#include <stdint.h>
#include <stdlib.h>
#include "cairn/cairn.h"
#include "fuzz.h"
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *s = fuzz_text(data, size);
    cnLcp p = {0};
    cnDiag d;
    if (cn_lcp_read_string(s, &p, &d) == CN_OK) {
        if (p.n <= 12) {
            double z[12], w[12];
            cnLcpInfo info;
            cn_lcp_lemke(&p, NULL, z, w, &info);
            cn_lcp_pivot(&p, NULL, z, w, &info);
        }
        cn_lcp_free(&p);
    }
    free(s);
    return 0;
}
