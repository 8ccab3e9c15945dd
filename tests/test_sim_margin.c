/* Unit tests of src/motion/sim_margin.c: the margins along a stable step. The gripper lifts B
 * (1 x 1) off A (1 wide, 2 tall, on a table, mu 0.8). A held part presses nothing, so at every
 * sample the margins are A's alone, by hand: it stands frictionless (critical friction 0, the
 * whole range), tips under a horizontal load of b/h = 0.5 g (below mu) and under gravity turned
 * by atan(b/h) = 26.57 degrees (friction holds to atan 0.8 = 38.7). Were B's weight on A, the
 * column (3 tall) would give 1/3 g and 18.4 degrees. Checked: each at every sample taken, within
 * the path's margin tolerance and on the proved side; the weakest sample's place on the path;
 * margin_samples 2 takes the first and the last of the three samples; cn_sm_drop_margins clears
 * them all. */
#include <math.h>

#include "sim_scenes.h"

static const char *LIFT_OFF =
    "{\"dimension\":2,\"friction\":0.8,\"gravity\":[0,-9.81],\"parts\":["
    "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-9,-1],[9,-1],[9,0],[-9,0]]},"
    "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,2],[0,2]]},"
    "{\"name\":\"B\",\"polygon\":[[0,2],[1,2],[1,3],[0,3]]}],"
    "\"plan\":[{\"move\":\"B\",\"path\":[[0,3]],\"support\":\"hold\"}]}";

/* value within the path's tolerance below `hand` (the proved side) */
static bool proved_below(double value, double hand) {
    return value <= hand * (1 + 1e-12) && value >= hand * (1 - 2 * CN_SIM_MARGIN_REL_TOL);
}

static void margins_at(const cnAssembly *a, int nsamples_cap, int want) {
    cnMarginOptions mo = cn_margin_options_default();
    cnSimOptions o = cn_sim_options_default();
    o.margin = &mo;
    o.margin_samples = nsamples_cap;
    Step S;
    if (!sim_step_begin(&S, a, 0, &o)) {
        CHECK(!"out of memory");
        return;
    }
    const double at[3] = {0, 1.5, 3};
    cnSimResult R;
    memset(&R, 0, sizeof R);
    R.samples = cn_calloc(3, sizeof *R.samples);
    R.nsamples = 3;
    for (int i = 0; R.samples && i < 3; i++) {
        CHECK(cn_sm_remember(&S, at[i], false) == CN_OK);
        R.samples[i].distance = at[i];
        for (int k = 0; k < 3; k++) R.samples[i].margin[k] = NAN;
    }
    cnStepResult out;
    memset(&out, 0, sizeof out);
    out.nsamples = 3;
    cnDiag d;
    CHECK_MSG(R.samples && cn_sm_step_margins(&S, &R, &out, &d) == CN_OK, "%s", d.message);
    const double hand[3] = {0, atan(0.5), 0.5};
    for (int k = 0; k < 3 && R.samples; k++) {
        const cnStepMargin *w = &out.margin[k];
        CHECK_MSG(w->computed && w->samples == want, "margin %d: %d samples, want %d", k, w->samples, want);
        int taken = 0;
        for (int i = 0; i < 3; i++) {
            double v = R.samples[i].margin[k];
            if (isnan(v)) continue;
            taken++;
            CHECK_MSG(k == 0 ? v == 0 : proved_below(v, hand[k]), "margin %d at s = %g: %.12g, by hand %.12g", k,
                      at[i], v, hand[k]);
        }
        CHECK(taken == want);
        if (want == 2) CHECK(isnan(R.samples[1].margin[k]));
        CHECK(k != 0 || w->at.end == CN_MARGIN_WHOLE);
        CHECK(k == 0 || (w->at.end == CN_MARGIN_FOUND && proved_below(w->at.value, hand[k])));
        CHECK(w->sample >= 0 && w->sample < 3 && w->distance == at[w->sample]);
    }
    cn_sm_drop_margins(&R, &out);
    bool clear = true;
    for (int i = 0; R.samples && i < 3; i++)
        for (int k = 0; k < 3; k++) clear &= isnan(R.samples[i].margin[k]) && !out.margin[k].computed;
    CHECK(clear);
    cn_free(R.samples);
    cn_sm_step_free(&S);
}

void test_sim_margin(void) {
    cnAssembly *a = load_ok(LIFT_OFF);
    if (!a) return;
    margins_at(a, 0, 3);
    margins_at(a, 2, 2);
    cn_assembly_free(a);
}
