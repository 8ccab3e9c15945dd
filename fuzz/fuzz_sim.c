/* libFuzzer target: JSON text -> assembly -> simulate its plan and plan it (make fuzz). */
#include <stdint.h>
#include <stdlib.h>
#include "cairn/cairn.h"
#include "fuzz.h"
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    char *s = fuzz_text(data, size);
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(s, "fuzz", &a, &d) == CN_OK) {
        if (a->nparts <= 8 && a->nsteps > 0 && a->nsteps <= 3) {
            cnSimOptions o = cn_sim_options_default();
            o.check.max_nodes = 20;
            o.max_samples = 200; /* a step's cost bounded: the planner's budget is checked only
                                    between states, and the fuzz build's instrumentation slows
                                    the geometry most */
            cnSimResult r;
            if (cn_simulate(a, &o, &r, &d) == CN_OK) cn_sim_result_free(&r);
        }
        if (a->nparts <= 5) {
            cnPlanOptions po = cn_plan_options_default();
            po.max_states = 8;
            po.sim.check.max_nodes = 20;
            po.sim.max_samples = 200;
            po.max_seconds = 2; /* the planner's own time budget bounds a slow input */
            cnPlanResult pr;
            if (cn_plan(a, &po, &pr, &d) == CN_OK) cn_plan_result_free(&pr);
        }
        cn_assembly_free(a);
    }
    free(s);
    return 0;
}
