/* Unit tests of src/motion/sim_onset.c: where a step starts to fail, and where the gripper starts
 * to carry a pushed part, both found by bisection between two samples, against the distances by
 * hand (sim_scenes.h): A slid out from under B, B tips from s = 0.5; B pushed along A and back, its
 * weight taken from s = 1.5 to 4.5. Checked: each found within the bisection's tolerance and on the proved side
 * (the onset reported is a distance where B moves, the carrying one where it is carried), at the
 * default tolerance and at 1e-3 of the path; the check returned with the onset is the one that
 * moves B; and the carrying intervals cn_sm_push_carry keeps (an interval ending before it begins,
 * from an onset bisected into the same sample gap, is dropped). */
#include <math.h>

#include "sim_scenes.h"

static void test_tipping_onset(void) {
    cnAssembly *a = load_ok(SIM_SLIDE_OUT);
    if (!a) return;
    int B = sim_part(a, "B");
    for (int v = 0; v < 2; v++) {
        cnSimOptions o = cn_sim_options_default();
        o.bisect_tol = v ? 1e-3 : 0;
        Step S;
        if (!sim_step_begin(&S, a, 0, &o)) {
            CHECK(!"out of memory");
            break;
        }
        double tol = (v ? 1e-3 : SIM_BISECT_TOL) * S.length;
        CHECK(fabs(S.length - 2) < 1e-12);
        cnCheckResult r;
        EvStatus ev;
        cnDiag d;
        /* the two samples it starts from: still before, B tipping after */
        CHECK(cn_sm_eval(&S, 0.25, false, true, &r, &ev, &d) == CN_OK && ev == EV_STABLE);
        cn_check_result_free(&r);
        CHECK(cn_sm_eval(&S, 1, false, true, &r, &ev, &d) == CN_OK && ev == EV_UNSTABLE && sim_moves(&r, B));
        double s_on = NAN;
        CHECK(cn_sm_bisect(&S, 0.25, 1, &r, &ev, &s_on, &d) == CN_OK);
        CHECK_MSG(s_on > 0.5 && s_on - 0.5 <= tol, "onset at %.12g, by hand 0.5 (tol %g)", s_on, tol);
        CHECK(ev == EV_UNSTABLE && sim_moves(&r, B));
        cn_check_result_free(&r);
        cn_sm_step_free(&S);
    }
    cn_assembly_free(a);
}

static void test_carry_onset(void) {
    cnSimOptions o;
    Step S;
    cnAssembly *a = sim_begin(SIM_PUSH_OVER, &S, &o);
    if (!a) return;
    cnCheckResult r;
    EvStatus ev;
    cnDiag d;
    double at = NAN;
    CHECK(cn_sm_bisect_carry(&S, 1, 2, false, &at, &d) == CN_OK);
    CHECK_MSG(at > 1.5 && at - 1.5 <= SIM_BISECT_TOL * S.length, "carried from %.12g, by hand 1.5", at);
    /* on the proved side: carried there, resting on A just before the bisection's last interval */
    S.held = false;
    CHECK(cn_sm_eval(&S, at, false, true, &r, &ev, &d) == CN_OK && S.held && ev == EV_STABLE);
    cn_check_result_free(&r);
    S.held = false;
    CHECK(cn_sm_eval(&S, 1.5 - 1e-3, false, true, &r, &ev, &d) == CN_OK && !S.held && ev == EV_STABLE);
    cn_check_result_free(&r);
    /* and back: released where B's centre is over A again */
    double back = NAN;
    CHECK(cn_sm_bisect_carry(&S, 4, 5, true, &back, &d) == CN_OK);
    CHECK_MSG(fabs(back - 4.5) <= SIM_BISECT_TOL * S.length, "released at %.12g, by hand 4.5", back);
    S.held = false;
    CHECK(cn_sm_eval(&S, back, false, true, &r, &ev, &d) == CN_OK && !S.held && ev == EV_STABLE);
    cn_check_result_free(&r);
    sim_end(a, &S);
}

static void test_push_carry(void) {
    cnAssembly *a = load_ok(SIM_PUSH_OVER);
    if (!a) return;
    cnStepResult out;
    memset(&out, 0, sizeof out);
    CHECK(cn_sm_push_carry(&out, 2, 1, false, &a->plan[0]) == CN_OK && out.ncarry == 0 && !out.took_weight);
    CHECK(cn_sm_push_carry(&out, 1, 2, false, &a->plan[0]) == CN_OK);
    CHECK(cn_sm_push_carry(&out, 3, 4, true, &a->plan[0]) == CN_OK);
    CHECK(out.ncarry == 2 && out.took_weight && out.took_weight_time == 1);
    CHECK(out.took_weight_part == sim_part(a, "B") && out.carry[1].part == sim_part(a, "B"));
    CHECK(out.carry[0].t0 == 1 && out.carry[0].t1 == 2 && !out.carry[0].released);
    CHECK(out.carry[1].t0 == 3 && out.carry[1].t1 == 4 && out.carry[1].released);
    cn_free(out.carry);
    cn_assembly_free(a);
}

void test_sim_onset(void) {
    test_tipping_onset();
    test_carry_onset();
    test_push_carry();
}
