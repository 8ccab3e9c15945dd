/* Unit tests of src/motion/sim_sample.c: one sample of a step (sim_scenes.h's scenes). Checked:
 *  - how a sample is posed (cn_sm_pose_check): the held part placed along the path and moving at
 *    the step's speed (still at the path's end), its role held, the others free, the check asked
 *    about the sample's poses and reporting a collision instead of refusing it;
 *  - a pushed part keeps its role while it can rest by itself, and the gripper takes its weight
 *    (S.held) once its centre is past A's end, the sample stable either way;
 *  - the state after a step (cn_sm_eval_static): B resting on A stands; with A gone, B falls;
 *  - a sample's record (cn_sm_record): distance, times, displacement, the contacts of its check
 *    (B's two corners on A carrying B's weight between them, 9.81 per unit of area, by hand); an
 *    infeasible sample records none; and every outcome's step status;
 *  - cn_sm_remember keeps 1,000 places in order. */
#include <math.h>

#include "sim_scenes.h"

static void test_pose(void) {
    cnSimOptions o;
    Step S;
    cnAssembly *a = sim_begin(SIM_SLIDE_OUT, &S, &o);
    if (!a) return;
    int A = sim_part(a, "A"), B = sim_part(a, "B"), T = sim_part(a, "table");
    cnSamplePose sp;
    cn_sm_pose_check(&S, 0.75, false, &o.check, &sp);
    const cnMotion *m = sp.check.motion;
    CHECK(m && m->role == S.role && S.role[A] == CN_ROLE_HELD && S.role[B] == CN_ROLE_FREE &&
          S.role[T] == CN_ROLE_FREE);
    CHECK(fabs(S.pose[A].t[0] - 0.75) < 1e-12 && fabs(S.pose[A].t[1]) < 1e-12 && fabs(S.pose[B].t[0]) < 1e-12);
    CHECK(fabs(m->speed - a->sim_speed) < 1e-12 && fabs(m->twist.v[0] - a->sim_speed) < 1e-12 &&
          fabs(m->twist.v[1]) < 1e-12 && fabs(m->direction[0] - 1) < 1e-12);
    CHECK(sp.check.query == &sp.query && sp.query.pose == S.pose && sp.query.absent == S.absent);
    CHECK(sp.check.overlap_is_result && !sp.check.keep_lcp);
    /* at the path's end the parts pause: no speed */
    cn_sm_pose_check(&S, S.length, false, &o.check, &sp);
    CHECK(sp.check.motion->speed == 0 && sp.check.motion->twist.v[0] == 0 && fabs(S.pose[A].t[0] - 2) < 1e-12);
    sim_end(a, &S);
}

static void test_pushed(void) {
    cnSimOptions o;
    Step S;
    cnAssembly *a = sim_begin(SIM_PUSH_OVER, &S, &o);
    if (!a) return;
    int B = sim_part(a, "B");
    cnCheckResult r;
    EvStatus ev;
    cnDiag d;
    CHECK(cn_sm_eval(&S, 1, false, true, &r, &ev, &d) == CN_OK && ev == EV_STABLE && !S.held &&
          S.role[B] == CN_ROLE_PUSHED);
    cn_check_result_free(&r);
    CHECK(cn_sm_eval(&S, 2, false, true, &r, &ev, &d) == CN_OK && ev == EV_STABLE && S.held &&
          S.role[B] == CN_ROLE_HELD);
    cn_check_result_free(&r);
    sim_end(a, &S);
}

static void test_static_and_record(void) {
    cnSimOptions o;
    Step S;
    cnAssembly *a = sim_begin(SIM_SLIDE_OUT, &S, &o);
    if (!a) return;
    int A = sim_part(a, "A"), B = sim_part(a, "B");
    cnCheckResult r;
    EvStatus ev;
    cnDiag d;
    CHECK(cn_sm_eval_static(&S, &r, &ev, &d) == CN_OK && ev == EV_STABLE);
    cn_check_result_free(&r);
    S.absent[A] = 1;
    CHECK(cn_sm_eval_static(&S, &r, &ev, &d) == CN_OK && ev == EV_UNSTABLE && sim_moves(&r, B));
    cn_check_result_free(&r);
    S.absent[A] = 0;
    /* a sample's record */
    cnSimResult R;
    memset(&R, 0, sizeof R);
    CHECK(cn_sm_eval(&S, 0.25, false, true, &r, &ev, &d) == CN_OK && ev == EV_STABLE);
    CHECK(cn_sm_record(&R, 0, 10, 0.25, &S, &r, ev, false) == CN_OK && R.nsamples == 1);
    const cnSimSample *sm = &R.samples[0];
    CHECK(sm->distance == 0.25 && fabs(sm->step_time - 0.25 / a->sim_speed) < 1e-12 &&
          fabs(sm->time - (10 + 0.25 / a->sim_speed)) < 1e-12 && sm->stable && !sm->held);
    CHECK(fabs(sm->disp[0] - 0.25) < 1e-12 && fabs(sm->disp[1]) < 1e-12 && isnan(sm->margin[0]));
    CHECK(sm->first == 0 && sm->count == r.contacts.count && R.ncontacts == sm->count);
    double onB = 0;
    int nB = 0;
    for (int c = 0; c < sm->count; c++) {
        const cnSimContact *x = &R.contacts[sm->first + c];
        if (x->body1 != B && x->body2 != B) continue;
        onB += x->force * fabs(x->normal[1]), nB++;
    }
    CHECK_MSG(nB == 2 && fabs(onB - 9.81) < 1e-6, "B's contacts: %d carrying %.12g", nB, onB);
    /* an infeasible sample records its place, no contacts */
    CHECK(cn_sm_record(&R, 0, 10, 0.5, &S, &r, EV_INFEASIBLE, true) == CN_OK && R.nsamples == 2);
    CHECK(R.samples[1].count == 0 && !R.samples[1].stable && R.samples[1].held && R.samples[1].first == R.ncontacts);
    cn_check_result_free(&r);
    cn_free(R.samples);
    cn_free(R.contacts);
    CHECK(cn_sm_step_status(EV_STABLE) == CN_STEP_STABLE && cn_sm_step_status(EV_UNSTABLE) == CN_STEP_UNSTABLE &&
          cn_sm_step_status(EV_INFEASIBLE) == CN_STEP_INFEASIBLE &&
          cn_sm_step_status(EV_UNDECIDED) == CN_STEP_UNDECIDED);
    /* the places margins are taken at */
    bool ok = true;
    for (int i = 0; i < 1000 && ok; i++) ok = cn_sm_remember(&S, 0.001 * i, i % 3 == 0) == CN_OK;
    CHECK(ok && S.nrec == 1000);
    for (int i = 0; i < S.nrec && ok; i++) ok = S.rec_s[i] == 0.001 * i && S.rec_leave[i] == (i % 3 == 0);
    CHECK(ok);
    sim_end(a, &S);
}

void test_sim_sample(void) {
    test_pose();
    test_pushed();
    test_static_and_record();
}
