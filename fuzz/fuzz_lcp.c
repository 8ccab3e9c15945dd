/* libFuzzer target: LCP text -> Lemke, warm starts from a basis, principal pivoting (make fuzz). */
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
            double z[12] = {0}, w[12] = {0};
            cnLcpInfo info;
            /* a solution, then its basis and its complement as warm starts: whatever
             * cn_lcp_solve_basis accepts must verify */
            cn_lcp_lemke(&p, NULL, z, w, &info);
            unsigned char basic[12];
            for (int flip = 0; flip < 2; flip++) {
                cn_lcp_basis_of(p.n, z, w, basic);
                for (int i = 0; flip && i < p.n; i++) basic[i] = !basic[i];
                double zb[12], wb[12];
                if (cn_lcp_solve_basis(&p, basic, NULL, zb, wb, &info) == CN_LCP_SOLVED &&
                    !cn_lcp_verify(&p, zb, CN_LCP_DEFAULT_TOL, NULL))
                    abort();
            }
            cn_lcp_pivot(&p, NULL, z, w, &info);
        }
        cn_lcp_free(&p);
    }
    free(s);
    return 0;
}
