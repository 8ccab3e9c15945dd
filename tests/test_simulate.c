/* Motion paths against hand calculations: the tipping onset of Proposition 3 for several masses,
 * sampling intervals and speeds; Proposition 2 (held: stable); a counterweight lifted off a
 * cantilever; friction drag and noninvertibility (sec. VIII); a blocked path; a subassembly
 * carried by contact (Fig. 18b). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "sim_planner.h"
#include "pieces.h"

static cnSimResult sim_with(const char *json, bool assemble, const cnMarginOptions *margin, int *ok) {
    cnSimResult r;
    memset(&r, 0, sizeof r);
    *ok = 0;
    cnAssembly *a = load_ok(json);
    if (!a) return r;
    cnSimOptions o = cn_sim_options_default();
    o.assemble = assemble;
    o.margin = margin;
    cnDiag d;
    if (cn_simulate(a, &o, &r, &d) != CN_OK) {
        fprintf(stderr, "simulate failed: %s\n", d.message);
        cn_test_failures++;
    } else {
        *ok = 1;
    }
    cn_assembly_free(a);
    return r;
}

static cnSimResult sim(const char *json, bool assemble, int *ok) { return sim_with(json, assemble, NULL, ok); }

/* A T of weight 5 (centre x = 0) on a base with its right corner at x = 0.5; a block of mass m
 * pushed from x = 0 along the top tips the T when m (x - 0.5) = 5 * 0.5. */
static char *t_scene(double m, double dt, double speed, const char *support) {
    char *buf = malloc(2048);
    snprintf(buf, 2048,
             "{\"dimension\":2,\"gravity\":[0,-1],\"simulation\":{\"dt\":%g,\"speed\":%g},"
             "\"parts\":[{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-6,-1],[6,-1],[6,0],[-6,0]]},"
             "{\"name\":\"E\",\"polygons\":[[[-0.5,0],[0.5,0],[0.5,2],[-0.5,2]],"
             "[[-3,2],[3,2],[3,2.5],[-3,2.5]]]},"
             "{\"name\":\"C\",\"mass\":%g,\"polygon\":[[-0.5,2.5],[0.5,2.5],[0.5,3],[-0.5,3]]}],"
             "\"plan\":[{\"move\":\"C\",\"path\":[[2.4,0],[0,2]],\"support\":\"%s\"}]}",
             dt, speed, m, support);
    return buf;
}

static void test_prop3_onset(void) {
    double masses[] = {4, 5, 10};
    double dts[] = {1, 0.3, 2.5};
    double speeds[] = {1, 0.5};
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            for (int k = 0; k < 2; k++) {
                double m = masses[i], xs = 0.5 + 2.5 / m;
                char *json = t_scene(m, dts[j], speeds[k], "push");
                int ok;
                cnSimResult r = sim(json, false, &ok);
                free(json);
                if (!ok) continue;
                CHECK(!r.stable && r.steps[0].status == CN_STEP_UNSTABLE);
                /* located to 1e-6 of the path length (4.4), plus the tolerance band */
                CHECK_MSG(fabs(r.steps[0].onset_distance - xs) < 2e-5,
                          "m %g dt %g speed %g: onset at %.9f, expected %.9f", m, dts[j],
                          speeds[k], r.steps[0].onset_distance, xs);
                CHECK_NEAR(r.steps[0].onset_time, xs / speeds[k], 2e-5 / speeds[k]);
                CHECK(r.steps[0].onset.nmoving >= 1 &&
                      !strcmp("E", "E")); /* E tips (C rides along) */
                int e_moves = 0;
                for (int q = 0; q < r.steps[0].onset.nmoving; q++) e_moves |= r.steps[0].onset.moving[q] == 1;
                CHECK(e_moves);
                CHECK(!r.steps[0].took_weight); /* C does not fall by itself */
                cn_sim_result_free(&r);
            }
    /* Proposition 2: carried by the gripper, the same path is stable */
    char *json = t_scene(5, 1, 1, "hold");
    int ok;
    cnSimResult r = sim(json, false, &ok);
    free(json);
    if (ok) CHECK(r.stable);
    cn_sim_result_free(&r);
}

/* The T scene (C of density 10: weight 5 like the T) in units scaled by s, with no "simulation" key: the default sampling follows the
 * parts' size, so the onset (in units of s) and the number of samples do not depend on s. */
static void test_default_sampling_scale_free(void) {
    double scales[] = {1e-4, 1, 1e4};
    int nsamples[3] = {0, 0, 0};
    for (int i = 0; i < 3; i++) {
        double s = scales[i];
        char buf[2048];
        snprintf(buf, sizeof buf,
                 "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                 "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[%.17g,%.17g],[%.17g,%.17g],[%.17g,0],[%.17g,0]]},"
                 "{\"name\":\"E\",\"polygons\":[[[%.17g,0],[%.17g,0],[%.17g,%.17g],[%.17g,%.17g]],"
                 "[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]]]},"
                 "{\"name\":\"C\",\"density\":10,\"polygon\":[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]]}],"
                 "\"plan\":[{\"move\":\"C\",\"path\":[[%.17g,0],[0,%.17g]],\"support\":\"push\"}]}",
                 -6 * s, -1 * s, 6 * s, -1 * s, 6 * s, -6 * s,                    /* table */
                 -0.5 * s, 0.5 * s, 0.5 * s, 2 * s, -0.5 * s, 2 * s,              /* stem */
                 -3 * s, 2 * s, 3 * s, 2 * s, 3 * s, 2.5 * s, -3 * s, 2.5 * s,    /* top */
                 -0.5 * s, 2.5 * s, 0.5 * s, 2.5 * s, 0.5 * s, 3 * s, -0.5 * s, 3 * s, /* C */
                 2.4 * s, 2 * s);
        int ok;
        cnSimResult r = sim(buf, false, &ok);
        if (!ok) continue;
        CHECK(!r.stable && r.steps[0].status == CN_STEP_UNSTABLE);
        CHECK_MSG(fabs(r.steps[0].onset_distance / s - 1.0) < 2e-5, "scale %g: onset at %.9g", s,
                  r.steps[0].onset_distance / s);
        nsamples[i] = r.nsamples;
        cn_sim_result_free(&r);
    }
    CHECK_MSG(nsamples[0] == nsamples[1] && nsamples[1] == nsamples[2] && nsamples[1] >= 3,
              "samples at scales 1e-4, 1, 1e4: %d %d %d", nsamples[0], nsamples[1], nsamples[2]);
}

/* Pushed past the end of the top, the block itself tips: the gripper takes its weight (and the
 * T stays, the block's weight no longer on it). */
static void test_push_takes_weight(void) {
    const char *json =
        "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-6,-1],[6,-1],[6,0],[-6,0]]},"
        "{\"name\":\"C\",\"polygon\":[[-0.5,0],[0.5,0],[0.5,0.5],[-0.5,0.5]]}],"
        "\"plan\":[{\"move\":\"C\",\"path\":[[7,0]],\"support\":\"push\"}]}";
    int ok;
    cnSimResult r = sim(json, false, &ok);
    if (!ok) return;
    CHECK(r.stable);
    CHECK(r.steps[0].took_weight);
    /* C tips when its centre passes the table's edge at x = 6 */
    CHECK_NEAR(r.steps[0].took_weight_time, 6.0, 2e-5);
    cn_sim_result_free(&r);
}

/* The gripper carries a pushed part only while it could not rest (paper sec. IV: "not supported
 * by the gripper unless the part itself becomes unstable"). A block C of mass 10 pushed right
 * across a gap onto a free plank balanced on a narrow post. Pushed at its centre (0.5 above its
 * base) and sliding at mu 0.4, C tips forward over the table's edge once it overhangs by 0.5 mu
 * = 0.2 (the push and the friction make a couple 0.5 mu W): from x = -0.2, s = 1.3. Its weight
 * goes back on a support where it can rest: on the plank's end (x = 2), with its centre 0.2
 * short of it, at s = 3.3; there it tips the plank. Under the old rule (carried to the end once
 * taken) this step was "stable". */
static void test_gripper_lets_go(void) {
    const char *json =
        "{\"dimension\":2,\"friction\":0.4,\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-4,-1],[0,-1],[0,0],[-4,0]]},"
        "{\"name\":\"post\",\"fixed\":true,\"polygon\":[[3.9,-2],[4.1,-2],[4.1,-0.2],[3.9,-0.2]]},"
        "{\"name\":\"plank\",\"mass\":1,\"polygon\":[[2,-0.2],[6,-0.2],[6,0],[2,0]]},"
        "{\"name\":\"C\",\"mass\":10,\"polygon\":[[-2,0],[-1,0],[-1,1],[-2,1]]}],"
        "\"plan\":[{\"move\":\"C\",\"path\":[[5,0]],\"support\":\"push\"}]}";
    int ok;
    cnSimResult r = sim(json, false, &ok);
    if (!ok) return;
    const cnStepResult *s = &r.steps[0];
    CHECK(!r.stable && s->status == CN_STEP_UNSTABLE);
    CHECK_MSG(s->ncarry == 1, "C carried in %d intervals", s->ncarry);
    if (s->ncarry == 1) {
        CHECK_NEAR(s->carry[0].t0, 1.3, 2e-5);
        CHECK_NEAR(s->carry[0].t1, 3.3, 2e-5);
        CHECK(s->took_weight && s->took_weight_time == s->carry[0].t0 && s->carry[0].released);
    }
    CHECK_NEAR(s->onset_time, 3.3, 2e-5);
    bool plank = false;
    for (int i = 0; i < s->onset.nmoving; i++) plank |= s->onset.moving[i] == 2;
    CHECK_MSG(plank, "the plank does not tip at the onset");
    cn_sim_result_free(&r);
    /* carried over the gap into a wall: the interval ends at the collision (t = 3), not a
     * release (a colliding sample says nothing about whether the part could rest) */
    const char *wall =
        "{\"dimension\":2,\"friction\":0.4,\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-4,-1],[0,-1],[0,0],[-4,0]]},"
        "{\"name\":\"wall\",\"fixed\":true,\"polygon\":[[2,-1],[3,-1],[3,3],[2,3]]},"
        "{\"name\":\"C\",\"mass\":10,\"polygon\":[[-2,0],[-1,0],[-1,1],[-2,1]]}],"
        "\"plan\":[{\"move\":\"C\",\"path\":[[5,0]],\"support\":\"push\"}]}";
    r = sim(wall, false, &ok);
    if (!ok) return;
    s = &r.steps[0];
    CHECK(s->status == CN_STEP_INFEASIBLE);
    CHECK_MSG(s->ncarry == 1 && !s->carry[0].released && fabs(s->carry[0].t1 - 3) < 2e-5 &&
                  fabs(s->carry[0].t0 - 1.3) < 2e-5,
              "into the wall: %d intervals", s->ncarry);
    cn_sim_result_free(&r);
}

/* No instability between samples: the same block pushed across the seesaw plank and on onto a
 * table beyond it. Sampled every dt alone, dt = 9 saw only the start, s = 9 (on the far table)
 * and the end, all stable; with the contact events sampled (where a contact can begin or end,
 * and just after) the verdict and the onset do not depend on dt: unstable at s = 3.3, carried
 * from 1.3 (the hand values of test_gripper_lets_go) for every dt from 0.05 to 20. */
static void test_events_between_samples(void) {
    double dts[] = {0.05, 0.3, 1, 2.5, 9, 20};
    for (int i = 0; i < 6; i++) {
        char json[1400];
        snprintf(json, sizeof json,
                 "{\"dimension\":2,\"friction\":0.4,\"simulation\":{\"dt\":%g},\"parts\":["
                 "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-4,-1],[0,-1],[0,0],[-4,0]]},"
                 "{\"name\":\"post\",\"fixed\":true,\"polygon\":[[3.9,-2],[4.1,-2],[4.1,-0.2],[3.9,-0.2]]},"
                 "{\"name\":\"plank\",\"mass\":1,\"polygon\":[[2,-0.2],[6,-0.2],[6,0],[2,0]]},"
                 "{\"name\":\"far\",\"fixed\":true,\"polygon\":[[6,-1],[12,-1],[12,0],[6,0]]},"
                 "{\"name\":\"C\",\"mass\":10,\"polygon\":[[-2,0],[-1,0],[-1,1],[-2,1]]}],"
                 "\"plan\":[{\"move\":\"C\",\"path\":[[10,0]],\"support\":\"push\"}]}",
                 dts[i]);
        int ok;
        cnSimResult r = sim(json, false, &ok);
        if (!ok) continue;
        const cnStepResult *s = &r.steps[0];
        CHECK_MSG(!r.stable && s->status == CN_STEP_UNSTABLE, "dt %g: status %d", dts[i], (int)s->status);
        CHECK_MSG(fabs(s->onset_time - 3.3) < 2e-5, "dt %g: onset %g, not 3.3", dts[i], s->onset_time);
        CHECK_MSG(s->ncarry == 1 && fabs(s->carry[0].t0 - 1.3) < 2e-5, "dt %g: carried in %d intervals",
                  dts[i], s->ncarry);
        CHECK(s->nevents > 0 && s->events_dropped == 0);
        cn_sim_result_free(&r);
    }
}

/* No instability between samples of a turn. 2-D: a bar hanging from (0, 2.5) (after a lift of
 * 0.5) turned 90 degrees counter-clockwise; its end (radius sqrt 12.26, the farthest point)
 * clips the bottom-left corner region of a free block B (x in [3, 4], y in [0, 1]) for about 9
 * degrees. Its leading corner, at angle -(pi/2 - atan(0.1/3.5)) from the pivot, reaches B's left
 * side x = 3 (at y = 0.695) at the turn t = pi/2 - atan(0.1/3.5) - acos(3/sqrt 12.26) = 57.32 deg,
 * distance 0.5 + t sqrt 12.26 = 4.0030: the bar is driven into B, and the path collides there.
 * 3-D: the same scene extruded along y, turned about -y: the same distance. Sampled every dt
 * alone, dt = 1, 2, 3 and 10 stepped over the clip and called the path stable; with the turn's
 * contact events sampled, every dt from 0.05 to 10 stops at 4.0030.
 * A turntable (3-D): two arms 40 degrees apart turned 40 degrees about the vertical, a plank
 * resting on a post and on the first arm (frictionless: the arm slides under it). The first
 * arm's trailing edge y' = -0.5 leaves the plank's corner (3, 0.25) at t = atan(0.25/3) +
 * asin(0.5/sqrt 9.0625) = 14.32 deg, and the plank falls until the second arm comes under it at
 * 25.7 deg: unstable at distance t sqrt 16.25 = 1.0078 for every dt. On the grid alone, dt = 1 to
 * 10 saw an arm under the plank at every sample and found it falling only once the arms were
 * taken away, at the end of the step (2.81). (A turn is always held, so it cannot load a part;
 * a part that needs a turning part's support falls when the moved parts are taken away anyway:
 * what a turn can do between samples is collide, or move the onset.) */
static void test_turn_events_between_samples(void) {
    double dts[] = {0.05, 0.3, 1, 2, 3, 10};
    double r2 = sqrt(12.26), t2 = CN_PI / 2 - atan(0.1 / 3.5) - acos(3 / r2), s2 = 0.5 + t2 * r2;
    double t3 = atan(0.25 / 3) + asin(0.5 / sqrt(9.0625)), s3 = t3 * sqrt(16.25);
    for (int i = 0; i < 6; i++)
        for (int scene = 0; scene < 3; scene++) {
            char json[2000];
            if (scene == 0)
                snprintf(json, sizeof json,
                         "{\"dimension\":2,\"friction\":0.4,\"simulation\":{\"dt\":%g},\"parts\":["
                         "{\"name\":\"floor\",\"fixed\":true,\"polygon\":[[-1,-2.5],[1,-2.5],[1,-1.5],[-1,-1.5]]},"
                         "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[2.9,-1],[6,-1],[6,0],[2.9,0]]},"
                         "{\"name\":\"B\",\"polygon\":[[3,0],[4,0],[4,1],[3,1]]},"
                         "{\"name\":\"bar\",\"polygon\":[[-0.1,-1.5],[0.1,-1.5],[0.1,2],[-0.1,2]]}],"
                         "\"plan\":[{\"move\":\"bar\",\"path\":[[0,0.5],{\"rotate\":90,\"about\":[0,2.5]}]}]}",
                         dts[i]);
            else if (scene == 1)
                snprintf(json, sizeof json,
                         "{\"dimension\":3,\"friction\":0.4,\"simulation\":{\"dt\":%g},\"parts\":["
                         "{\"name\":\"floor\",\"fixed\":true,\"box\":{\"min\":[-1,-1,-2.5],\"max\":[1,1,-1.5]}},"
                         "{\"name\":\"table\",\"fixed\":true,\"box\":{\"min\":[2.9,-1,-1],\"max\":[6,1,0]}},"
                         "{\"name\":\"B\",\"box\":{\"min\":[3,-0.5,0],\"max\":[4,0.5,1]}},"
                         "{\"name\":\"bar\",\"box\":{\"min\":[-0.1,-0.2,-1.5],\"max\":[0.1,0.2,2]}}],"
                         "\"plan\":[{\"move\":\"bar\",\"path\":[[0,0,0.5],{\"rotate\":90,\"axis\":[0,-1,0],\"about\":[0,0,2.5]}]}]}",
                         dts[i]);
            else
                snprintf(json, sizeof json,
                         "{\"dimension\":3,\"friction\":0,\"simulation\":{\"dt\":%g},\"parts\":["
                         "{\"name\":\"floor\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[8,5,0]}},"
                         "{\"name\":\"post\",\"fixed\":true,\"box\":{\"min\":[6,-1,0],\"max\":[7,1,1]}},"
                         "{\"name\":\"arm1\",\"box\":{\"min\":[2,-0.5,0],\"max\":[4,0.5,1]}},"
                         "{\"name\":\"arm2\",\"hull\":[[1.210695081395,-1.668597440933,0],[1.210695081395,-1.668597440933,1],"
                         "[1.853482691081,-0.902552997814,0],[1.853482691081,-0.902552997814,1],"
                         "[2.742783967633,-2.954172660306,0],[2.742783967633,-2.954172660306,1],"
                         "[3.385571577319,-2.188128217187,0],[3.385571577319,-2.188128217187,1]]},"
                         "{\"name\":\"plank\",\"box\":{\"min\":[3,-0.25,1],\"max\":[7,0.25,1.2]}}],"
                         "\"plan\":[{\"move\":[\"arm1\",\"arm2\"],\"path\":[{\"rotate\":40,\"axis\":[0,0,1],\"about\":[0,0,0]}]}]}",
                         dts[i]);
            int ok;
            cnSimResult r = sim(json, false, &ok);
            if (!ok) continue;
            const cnStepResult *s = &r.steps[0];
            if (scene < 2) {
                CHECK_MSG(!r.stable && s->status == CN_STEP_INFEASIBLE, "clip %dd, dt %g: status %d",
                          scene + 2, dts[i], (int)s->status);
                CHECK_MSG(fabs(s->onset_distance - s2) < 1e-5, "clip %dd, dt %g: onset at %.9g, not %.9g",
                          scene + 2, dts[i], s->onset_distance, s2);
                CHECK_MSG(s->blocked_part == 3 && s->blocking_part == 2, "clip %dd, dt %g: the bar does not hit B",
                          scene + 2, dts[i]);
            } else {
                CHECK_MSG(!r.stable && s->status == CN_STEP_UNSTABLE && !s->onset_after,
                          "turntable, dt %g: status %d", dts[i], (int)s->status);
                CHECK_MSG(fabs(s->onset_distance - s3) < 1e-5, "turntable, dt %g: onset at %.9g, not %.9g",
                          dts[i], s->onset_distance, s3);
                CHECK_MSG(s->onset.nmoving == 1 && s->onset.moving[0] == 4,
                          "turntable, dt %g: the plank does not fall", dts[i]);
            }
            CHECK(s->nevents > 0 && s->events_dropped == 0);
            cn_sim_result_free(&r);
        }
}

static void test_counterweight(void) {
    char path[512];
    snprintf(path, sizeof path, "%s/examples/cantilever.json", CAIRN_SOURCE_DIR);
    cnAssembly *a = NULL;
    cnDiag d;
    CHECK(cn_assembly_load_file(path, &a, &d) == CN_OK);
    if (!a) return;
    cn_assembly_free(a);
    const char *json =
        "{\"dimension\":2,\"parts\":["
        "{\"name\":\"post\",\"fixed\":true,\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
        "{\"name\":\"plank\",\"polygon\":[[-0.5,1],[3.5,1],[3.5,1.2],[-0.5,1.2]]},"
        "{\"name\":\"weight\",\"polygon\":[[-0.5,1.2],[0,1.2],[0,2.7],[-0.5,2.7]]}],"
        "\"plan\":[{\"move\":\"weight\"}]}";
    int ok;
    cnSimResult r = sim(json, false, &ok);
    if (!ok) return;
    /* the plank topples at the moment the weight separates: t = 0 of the lift */
    CHECK(!r.stable && r.steps[0].status == CN_STEP_UNSTABLE);
    CHECK_NEAR(r.steps[0].onset_time, 0, 1e-9);
    CHECK(r.steps[0].onset.nmoving == 1 && r.steps[0].onset.moving[0] == 1);
    cn_sim_result_free(&r);
}

static void test_friction_noninvertible(void) {
    const char *json =
        "{\"dimension\":2,\"gravity\":[0,-1],"
        "\"friction_pairs\":[{\"parts\":[\"A\",\"B\"],\"mu\":0.2},{\"parts\":[\"B\",\"table\"],\"mu\":0.05}],"
        "\"parts\":[{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-2,-1],[10,-1],[10,0],[-2,0]]},"
        "{\"name\":\"wall\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,3],[-1,3]]},"
        "{\"name\":\"B\",\"mass\":1,\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
        "{\"name\":\"A\",\"mass\":1,\"polygon\":[[0,1],[2,1],[2,2],[0,2]]}],"
        "\"plan\":[{\"move\":\"A\",\"path\":[[4,0]],\"support\":\"push\"},{\"move\":\"B\"}]}";
    int ok;
    cnSimResult r = sim(json, false, &ok);
    if (ok) {
        CHECK(!r.stable && r.steps[0].status == CN_STEP_UNSTABLE);
        CHECK(r.steps[0].onset.nmoving == 1 && r.steps[0].onset.moving[0] == 2);
        /* B is dragged right: net force 0.2 - 0.05 * 2 = 0.1 on a unit mass */
        if (r.steps[0].onset.part) CHECK_NEAR(r.steps[0].onset.part[2].lin[0], 0.1, 1e-9);
    }
    cn_sim_result_free(&r);
    r = sim(json, true, &ok);
    if (ok) CHECK(r.stable); /* inserted from the right, B is held by the wall */
    /* ... with A's weight on B from where A can rest on it, pushed left and sliding at mu 0.2:
     * pivoting on B's corner (2, 1) with its centre 0.5 above it, A rests when W (x - 2) <=
     * 0.5 mu W, x <= 2.1: carried from the start of the insertion (t = 3.01, after B's) to
     * t = 3.01 + (5 - 2.1) = 5.91, and resting on B (the wall holding B) after that */
    if (ok && r.nsteps == 2) {
        const cnStepResult *s = &r.steps[1];
        CHECK_MSG(s->ncarry == 1, "A carried in %d intervals", s->ncarry);
        if (s->ncarry == 1) {
            CHECK_NEAR(s->carry[0].t0, 3.01, 1e-9);
            CHECK_NEAR(s->carry[0].t1, 5.91, 2e-5);
        }
    }
    cn_sim_result_free(&r);
    /* A held instead of pushed: its weight is the gripper's and it presses nothing on B
     * (Proposition 2), so B stays put along the whole path */
    char *held = strdup(json);
    char *q = strstr(held, "\"push\"");
    memcpy(q, "\"hold\"", 6);
    r = sim(held, false, &ok);
    if (ok) CHECK_MSG(r.stable && r.steps[0].status == CN_STEP_STABLE, "held A drags B");
    cn_sim_result_free(&r);
    free(held);
    /* lifting A vertically: invertible */
    char *up = strdup(json);
    char *p = strstr(up, "[[4,0]]");
    memcpy(p, "[[0,4]]", 7);
    r = sim(up, false, &ok);
    if (ok) CHECK(r.stable);
    cn_sim_result_free(&r);
    r = sim(up, true, &ok);
    if (ok) CHECK(r.stable);
    cn_sim_result_free(&r);
    free(up);
}

static void test_blocked_and_carried(void) {
    const char *json =
        "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[10,-1],[10,0],[-5,0]]},"
        "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
        "{\"name\":\"B\",\"polygon\":[[3,0],[4,0],[4,2],[3,2]]}],"
        "\"plan\":[{\"move\":\"A\",\"path\":[[4,0]],\"support\":\"push\"}]}";
    int ok;
    cnSimResult r = sim(json, false, &ok);
    if (ok) {
        CHECK(r.steps[0].status == CN_STEP_INFEASIBLE);
        CHECK_NEAR(r.steps[0].onset_distance, 2.0, 1e-6);
        CHECK(r.steps[0].blocked_part == 1 && r.steps[0].blocking_part == 2);
    }
    cn_sim_result_free(&r);
    /* Fig. 18b: the gripper moves A, which pushes B along: stable */
    const char *carried =
        "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-8,-1],[5,-1],[5,0],[-8,0]]},"
        "{\"name\":\"B\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
        "{\"name\":\"A\",\"polygon\":[[1,0],[2,0],[2,1.5],[1,1.5]]}],"
        "\"plan\":[{\"move\":[\"A\",\"B\"],\"grip\":\"A\",\"path\":[[-5,0]],\"support\":\"push\"}]}";
    r = sim(carried, false, &ok);
    if (ok) CHECK(r.stable);
    cn_sim_result_free(&r);
    /* moving A alone into B (not in the move set) is a collision */
    const char *alone =
        "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-8,-1],[5,-1],[5,0],[-8,0]]},"
        "{\"name\":\"B\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
        "{\"name\":\"A\",\"polygon\":[[1,0],[2,0],[2,1.5],[1,1.5]]}],"
        "\"plan\":[{\"move\":\"A\",\"path\":[[-5,0]],\"support\":\"push\"}]}";
    r = sim(alone, false, &ok);
    if (ok) {
        CHECK(r.steps[0].status == CN_STEP_INFEASIBLE);
        CHECK_NEAR(r.steps[0].onset_distance, 0, 1e-9);
    }
    cn_sim_result_free(&r);
}

/* Warm starts change how each sample's LCP is solved, never the outcome: on the paper's plans
 * the warm and cold runs give the same verdicts, onsets and samples, and the warm run solves
 * most samples on a remembered basis with far fewer pivots. */
static void test_warm_equals_cold(void) {
    static const char *plans[][2] = {
        {"fig4", "fig4_lift_A"},          {"fig6", "fig6_C_exit_II"},
        {"fig6", "fig6_C_exit_III"},      {"fig6", "fig6_A_then_C_exit_II"},
        {"fig9", "fig9_C_minus_y"},       {"fig9", "fig9_C_plus_x"},
        {"fig14", "fig14_P_out"},         {"fig17", "fig17_B_left"},
        {"slide_tips", NULL},             {"fig15", NULL}};
    long solves = 0, warm = 0, pc = 0, pw = 0;
    for (size_t k = 0; k < sizeof plans / sizeof plans[0]; k++) {
        char path[512], plan[512];
        snprintf(path, sizeof path, "%s/examples/%s.json", CAIRN_SOURCE_DIR, plans[k][0]);
        snprintf(plan, sizeof plan, "%s/examples/plans/%s.json", CAIRN_SOURCE_DIR,
                 plans[k][1] ? plans[k][1] : "");
        cnAssembly *a = NULL;
        cnDiag d;
        CHECK(cn_assembly_load_with_plan(path, plans[k][1] ? plan : NULL, &a, &d) == CN_OK);
        if (!a) continue;
        cnSimResult rc, rw;
        cnSimOptions o = cn_sim_options_default();
        o.cold = true;
        CHECK(cn_simulate(a, &o, &rc, &d) == CN_OK);
        o.cold = false;
        CHECK(cn_simulate(a, &o, &rw, &d) == CN_OK);
        CHECK_MSG(rc.stable == rw.stable && rc.nsteps == rw.nsteps && rc.nsamples == rw.nsamples,
                  "%s", path);
        for (int i = 0; i < rc.nsteps && i < rw.nsteps; i++) {
            CHECK(rc.steps[i].status == rw.steps[i].status);
            CHECK_NEAR(rc.steps[i].onset_distance, rw.steps[i].onset_distance, 1e-9);
            CHECK(rc.steps[i].onset.nmoving == rw.steps[i].onset.nmoving);
        }
        for (int i = 0; i < rc.nsamples && i < rw.nsamples; i++)
            CHECK(rc.samples[i].stable == rw.samples[i].stable);
        CHECK(rc.lcp_warm == 0 && rc.lcp_solves == rw.lcp_solves);
        solves += rw.lcp_solves, warm += rw.lcp_warm, pc += rc.lcp_pivots, pw += rw.lcp_pivots;
        cn_sim_result_free(&rc);
        cn_sim_result_free(&rw);
        cn_assembly_free(a);
    }
    printf("warm starts on the paper's plans: %ld of %ld solves, pivots %ld cold, %ld warm\n",
           warm, solves, pc, pw);
    CHECK(warm * 4 > solves * 3);
    CHECK(pw * 4 < pc);
}

/* Proposition 2 does not unload a held part that another part's weight rests on: a block on a
 * held tray that slides right at mu 0.5 is dragged along (it may not stay put), and a block
 * leaning on a held post falls when the post moves away, but stands while the post pauses
 * (its weight needs the post there: the contact is kept). */
static void test_held_supports(void) {
    const char *tray =
        "{\"dimension\":2,\"friction\":0.5,\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-4,-1],[12,-1],[12,0],[-4,0]]},"
        "{\"name\":\"tray\",\"polygon\":[[0,0],[4,0],[4,0.5],[0,0.5]]},"
        "{\"name\":\"block\",\"polygon\":[[1,0.5],[2,0.5],[2,1.5],[1,1.5]]}],"
        "\"plan\":[{\"move\":\"tray\",\"path\":[[3,0]],\"support\":\"hold\"}]}";
    int ok;
    cnSimResult r = sim(tray, false, &ok);
    if (ok) {
        CHECK(!r.stable && r.steps[0].status == CN_STEP_UNSTABLE);
        CHECK(r.steps[0].onset.nmoving == 1 && r.steps[0].onset.moving[0] == 2);
        CHECK_NEAR(r.steps[0].onset_time, 0, 1e-9);
    }
    cn_sim_result_free(&r);
    /* a plank leaning on a post (frictionless there, mu 0.5 elsewhere), its foot against a
     * fixed stop: the post is held and lifted, sliding along the plank's top face. Without the
     * post the plank falls, so its contact is kept; frictionless, it does no work on the plank,
     * which stays put until the post's foot passes the plank's top corner, 3.1 up */
    const char *lean =
        "{\"dimension\":2,\"friction\":0.5,\"friction_pairs\":[{\"parts\":[\"post\",\"plank\"],\"mu\":0}],"
        "\"parts\":["
        "{\"name\":\"floor\",\"fixed\":true,\"polygon\":[[-4,-1],[12,-1],[12,0],[-4,0]]},"
        "{\"name\":\"stop\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,0.5],[-1,0.5]]},"
        "{\"name\":\"post\",\"polygon\":[[3,0],[4,0],[4,5],[3,5]]},"
        "{\"name\":\"plank\",\"polygon\":[[0,0],[0.3,0],[3,2.7],[3,3.1]]}],"
        "\"plan\":[{\"move\":\"post\",\"path\":[[0,4]],\"support\":\"hold\"}]}";
    r = sim(lean, false, &ok);
    if (ok) {
        CHECK(!r.stable && r.steps[0].status == CN_STEP_UNSTABLE);
        CHECK_NEAR(r.steps[0].onset_time, 3.1, 1e-3);
        CHECK(r.steps[0].onset.nmoving == 1 && r.steps[0].onset.moving[0] == 3);
    }
    cn_sim_result_free(&r);
}

/* A block pushed along a plank that lies on a table, mu 0.3 everywhere: friction drags the plank
 * with at most 0.3 Wb, the table holds it with up to 0.3 (Wb + Wp), so nothing else moves (by
 * hand). Decided with the default search budget; with a budget of one LP the sample is undecided,
 * and undecided is never read as stable: the step and the run say so, and the run stops there.
 * The weak reading (accept_prestress) calls it stable. */
static const char *PUSH_PLANK =
    "{\"dimension\":2,\"friction\":0.3,\"parts\":["
    "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-4,-1],[12,-1],[12,0],[-4,0]]},"
    "{\"name\":\"plank\",\"polygon\":[[0,0],[10,0],[10,1],[0,1]]},"
    "{\"name\":\"block\",\"polygon\":[[4,1],[6,1],[6,2],[4,2]]}],"
    "\"plan\":[{\"move\":\"block\",\"path\":[[-3,0]],\"support\":\"push\"},{\"move\":\"plank\"}]}";

/* The arch of 4 voussoirs at mu 0.6 (proved stable by the search in 661 LPs) and a toy block
 * beside it, lifted away: undecided before the step with a budget of 50. */
static const char *ARCH_TOY =
    "{\"dimension\":2,\"friction\":0.6,\"parts\":["
    "{\"name\":\"ground\",\"fixed\":true,\"polygon\":[[-13,-1],[20,-1],[20,0],[-13,0]]},"
    "{\"name\":\"v0\",\"polygon\":[[10,0],[11.5,0],[8.1317279836452965,8.1317279836452965],[7.0710678118654755,7.0710678118654746]]},"
    "{\"name\":\"v1\",\"polygon\":[[7.0710678118654755,7.0710678118654746],[8.1317279836452965,8.1317279836452965],[7.0417190950972809e-16,11.5],[6.1232339957367663e-16,10]]},"
    "{\"name\":\"v2\",\"polygon\":[[6.1232339957367663e-16,10],[7.0417190950972809e-16,11.5],[-8.1317279836452965,8.1317279836452965],[-7.0710678118654746,7.0710678118654755]]},"
    "{\"name\":\"v3\",\"polygon\":[[-7.0710678118654746,7.0710678118654755],[-8.1317279836452965,8.1317279836452965],[-11.5,0],[-10,0]]},"
    "{\"name\":\"toy\",\"polygon\":[[15,0],[16,0],[16,1],[15,1]]}],"
    "\"plan\":[{\"move\":\"toy\",\"path\":[[0,3]]}]}";

static cnSimResult sim_budget(const char *json, long budget, bool prestress, int *ok) {
    cnSimResult r;
    memset(&r, 0, sizeof r);
    *ok = 0;
    cnAssembly *a = load_ok(json);
    if (!a) return r;
    cnSimOptions o = cn_sim_options_default();
    o.check.max_nodes = budget;
    o.check.accept_prestress = prestress;
    cnDiag d;
    if (cn_simulate(a, &o, &r, &d) == CN_OK) *ok = 1;
    else fprintf(stderr, "simulate failed: %s\n", d.message), cn_test_failures++;
    cn_assembly_free(a);
    return r;
}

static void test_undecided_is_not_stable(void) {
    int ok;
    cnSimResult r = sim_budget(PUSH_PLANK, 0, false, &ok); /* 0: the default budget */
    CHECK(ok && r.stable && !r.undecided && r.steps[0].status == CN_STEP_STABLE);
    cn_sim_result_free(&r);

    r = sim_budget(PUSH_PLANK, 1, false, &ok);
    CHECK(ok && !r.stable && r.undecided);
    if (ok && r.nsteps == 2) {
        const cnStepResult *s = &r.steps[0];
        CHECK(s->status == CN_STEP_UNDECIDED && s->has_onset && !s->onset_after);
        CHECK(s->onset.verdict == CN_VERDICT_UNDECIDED && s->onset.undecided != CN_UNDECIDED_NO);
        CHECK(s->onset.nmoving == 0);
        CHECK(r.steps[1].status == CN_STEP_SKIPPED);
        /* the path is sampled on to its end (no sample is proved unstable), and the step is
         * undecided from the first sample */
        CHECK(r.nsamples == 4 && s->onset_distance == 0 && !r.samples[0].stable);
    }
    cn_sim_result_free(&r);
    /* ... or stops at the first undecided sample when asked to (as the planner does) */
    {
        cnAssembly *a = load_ok(PUSH_PLANK);
        cnSimOptions o = cn_sim_options_default();
        o.check.max_nodes = 1;
        o.stop_at_undecided = true;
        cnDiag d;
        CHECK(a && cn_simulate(a, &o, &r, &d) == CN_OK);
        CHECK(a && r.undecided && r.nsamples == 1 && r.steps[0].status == CN_STEP_UNDECIDED);
        if (a) cn_sim_result_free(&r);
        cn_assembly_free(a);
    }

    r = sim_budget(PUSH_PLANK, 1, true, &ok);
    CHECK(ok && r.stable && !r.undecided);
    cn_sim_result_free(&r);

    /* the state before the step undecided: no sample simulated */
    r = sim_budget(ARCH_TOY, 5, false, &ok);
    CHECK(ok && !r.stable && r.undecided && r.steps[0].status == CN_STEP_UNDECIDED);
    CHECK(ok && r.steps[0].onset.solver.search_nodes == 5 && r.nsamples == 0);
    cn_sim_result_free(&r);
    r = sim_budget(ARCH_TOY, 0, false, &ok);
    CHECK(ok && r.stable);
    cn_sim_result_free(&r);
}

/* Proposition 2's held slide (C carried over the T's crossbar, frictionless) turned, moved far
 * from the origin and with its parts listed in either order: stable every time. The T is
 * squeezed between the held C and the table, where the contact forces are not unique; Lemke's
 * choice of 1e11-weight forces turned into a false sideways motion at (1e4, 1e4). */
static void test_held_slide_invariant(void) {
    static const double P[3][5][2] = {
        {{-6, -1}, {6, -1}, {6, 0}, {-6, 0}},
        {{-0.5, 0}, {0.5, 0}, {0.5, 2}, {-0.5, 2}},
        {{-3, 2}, {3, 2}, {3, 2.5}, {-3, 2.5}}};
    static const double C[4][2] = {{-0.5, 2.5}, {0.5, 2.5}, {0.5, 3}, {-0.5, 3}};
    int unstable = 0, runs = 0;
    for (int deg = 3; deg < 360; deg += 23)
        for (int k = 0; k < 3; k++)
            for (int rev = 0; rev < 2; rev++) {
                double off = k == 0 ? 0 : k == 1 ? 1e4 : 1e6, t = deg * 3.141592653589793 / 180;
                double c = cos(t), s = sin(t);
                char pts[4][4][128], part[3][700], buf[4096];
                for (int q = 0; q < 4; q++) {
                    size_t len = 0;
                    for (int v = 0; v < 4; v++) {
                        double x = q < 3 ? P[q][v][0] : C[v][0], y = q < 3 ? P[q][v][1] : C[v][1];
                        len += (size_t)snprintf(pts[q][0] + len, sizeof pts[q] - len, "%s[%.17g,%.17g]",
                                                v ? "," : "", c * x - s * y + off, s * x + c * y + off);
                    }
                }
                snprintf(part[0], sizeof part[0], "{\"name\":\"table\",\"fixed\":true,\"polygon\":[%s]}", pts[0][0]);
                snprintf(part[1], sizeof part[1], "{\"name\":\"E\",\"polygons\":[[%s],[%s]]}", pts[1][0], pts[2][0]);
                snprintf(part[2], sizeof part[2], "{\"name\":\"C\",\"mass\":5,\"polygon\":[%s]}", pts[3][0]);
                snprintf(buf, sizeof buf,
                         "{\"dimension\":2,\"gravity\":[%.17g,%.17g],\"parts\":[%s,%s,%s],"
                         "\"plan\":[{\"move\":\"C\",\"path\":[[%.17g,%.17g],[%.17g,%.17g]],\"support\":\"hold\"}]}",
                         s, -c, part[rev ? 2 : 0], part[1], part[rev ? 0 : 2], 2 * c, 2 * s, -2 * s, 2 * c);
                int ok;
                cnSimResult r = sim(buf, false, &ok);
                runs++;
                if (!ok || !r.stable) unstable++;
                if (ok) cn_sim_result_free(&r);
            }
    CHECK(runs == 96 && unstable == 0);
    if (unstable) fprintf(stderr, "  held slide: %d of %d poses not stable\n", unstable, runs);
}

/* The planner's shortcut (cn_sm_simulate_step's after_known: a sample where the held part
 * touches nothing is the state after the step, known stable). A block A lifted off the table and carried over block B:
 * along a path high enough it touches nothing after leaving the table (stable either way, with
 * fewer checks solved); along a path that runs into B mid-way, the step is infeasible with the
 * shortcut as without it (the samples near B are checked); and a path that passes 0.02 above
 * B's top is stable either way. */
static void test_apart_shortcut(void) {
    const char *paths[3] = {"[[0,3],[6,0]]", "[[0,0.5],[6,0]]", "[[0,1.02],[6,0]]"};
    const cnStepStatus want[3] = {CN_STEP_STABLE, CN_STEP_INFEASIBLE, CN_STEP_STABLE};
    for (int k = 0; k < 3; k++) {
        char js[1024];
        snprintf(js, sizeof js,
                 "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                 "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-3,-1],[10,-1],[10,0],[-3,0]]},"
                 "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
                 "{\"name\":\"B\",\"polygon\":[[4,0],[5,0],[5,1],[4,1]]}],"
                 "\"plan\":[{\"move\":\"A\",\"path\":%s,\"support\":\"hold\"}]}",
                 paths[k]);
        cnAssembly *a = load_ok(js);
        if (!a) return;
        unsigned char absent[3] = {0, 0, 0};
        cnStepStatus got[2];
        for (int fast = 0; fast < 2; fast++) {
            cnSimOptions o = cn_sim_options_default();
            cnStepResult r;
            cnDiag d;
            CHECK(cn_sm_simulate_step(a, absent, &a->plan[0], &o, fast, &r, &d) == CN_OK);
            got[fast] = r.status;
            cn_step_result_free(&r);
        }
        CHECK_MSG(got[0] == want[k] && got[1] == want[k], "path %d: %d without the shortcut, %d with it, want %d",
                  k, got[0], got[1], want[k]);
        cn_assembly_free(a);
    }
}


/* Margins along a path: sec. VIII's A held over B (B against the wall, mu_B,table 0.05): A
 * presses nothing, so B slides away from the wall at a lateral 0.05 g, a tilt of atan 0.05, and
 * stands without friction; a block lifted off a column (1 wide, 4 tall, mu 0.3) leaves the column
 * alone, which tips at b/h = 0.25 g before it slides, as cn_margin finds for the column alone;
 * an unstable step has none. */
static void test_path_margins(void) {
    const char *drag = "{\"dimension\":2,\"gravity\":[0,-1],\"friction_pairs\":[{\"parts\":[\"A\",\"B\"],\"mu\":0.2},"
                       "{\"parts\":[\"B\",\"table\"],\"mu\":0.05}],\"parts\":["
                       "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-2,-1],[10,-1],[10,0],[-2,0]]},"
                       "{\"name\":\"wall\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,3],[-1,3]]},"
                       "{\"name\":\"B\",\"mass\":1,\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
                       "{\"name\":\"A\",\"mass\":1,\"polygon\":[[0,1],[2,1],[2,2],[0,2]]}],"
                       "\"plan\":[{\"move\":\"A\",\"path\":[[4,0]],\"support\":\"%s\"}]}";
    char json[1024];
    snprintf(json, sizeof json, drag, "hold");
    cnMarginOptions mo = cn_margin_options_default();
    mo.rel_tol = 1e-6;
    int ok;
    cnSimResult r = sim_with(json, false, &mo, &ok);
    if (ok) {
        const cnStepResult *s = &r.steps[0];
        CHECK(r.stable && s->margin[0].computed && s->margin[1].computed && s->margin[2].computed);
        CHECK(s->margin[0].at.end == CN_MARGIN_WHOLE && s->margin[0].at.value == 0);
        CHECK_MSG(fabs(s->margin[2].at.value - 0.05) < 1e-6 * 0.05 + 1e-9, "lateral %.9g, want 0.05", s->margin[2].at.value);
        CHECK(s->margin[2].at.dir[0] > 0.999);
        CHECK_MSG(fabs(s->margin[1].at.value - atan(0.05)) < 2e-6 * atan(0.05), "tilt %.9g, want %.9g",
                  s->margin[1].at.value, atan(0.05));
        int found = 0;
        for (int i = 0; i < s->nsamples; i++) {
            double v = r.samples[s->first_sample + i].margin[2];
            if (isnan(v)) continue;
            found++;
            CHECK_MSG(fabs(v - 0.05) < 1e-6, "sample %d: lateral %.9g", i, v);
        }
        CHECK(found == s->margin[2].samples && found >= 2);
    }
    cn_sim_result_free(&r);
    snprintf(json, sizeof json, drag, "push"); /* unstable (the paper): no margin */
    r = sim_with(json, false, &mo, &ok);
    if (ok) {
        CHECK(!r.stable && !r.steps[0].margin[0].computed && !r.steps[0].margin[2].computed);
        for (int i = 0; i < r.nsamples; i++) CHECK(isnan(r.samples[i].margin[1]));
    }
    cn_sim_result_free(&r);

    const char *column = "{\"dimension\":2,\"gravity\":[0,-1],\"friction\":0.3,\"parts\":["
                         "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                         "{\"name\":\"D\",\"polygon\":[[0,0],[1,0],[1,4],[0,4]]}%s]%s}";
    snprintf(json, sizeof json, column,
             ",{\"name\":\"C\",\"polygon\":[[0,4],[1,4],[1,5],[0,5]]}",
             ",\"plan\":[{\"move\":\"C\",\"path\":[[0,3]]}]");
    r = sim_with(json, false, &mo, &ok);
    char alone[1024];
    snprintf(alone, sizeof alone, column, "", "");
    cnAssembly *a = load_ok(alone);
    cnMarginResult m;
    memset(&m, 0, sizeof m);
    cnDiag d;
    if (a && cn_margin(a, &mo, &m, &d) == CN_OK && ok) {
        const cnStepResult *s = &r.steps[0];
        CHECK(r.stable);
        const cnMargin *want[3] = {&m.friction, &m.tilt, &m.lateral};
        for (int k = 0; k < 3; k++)
            CHECK_MSG(s->margin[k].computed && fabs(s->margin[k].at.value - want[k]->value) <= 2e-6 * want[k]->value,
                      "margin %d: %.9g along the path, %.9g for the column alone", k, s->margin[k].at.value,
                      want[k]->value);
        CHECK_MSG(fabs(m.lateral.value - 0.25) < 1e-6, "column alone: lateral %.9g, want b/h = 0.25", m.lateral.value);
        CHECK_MSG(fabs(m.tilt.value - atan(0.25)) < 1e-6, "column alone: tilt %.9g, want atan 0.25", m.tilt.value);
    }
    cn_margin_result_free(&m);
    cn_assembly_free(a);
    cn_sim_result_free(&r);
}

/* Margins along a 3-D path, their verdicts guided by the sample's own static limits: a box B
 * held and lifted off a box A (mu 0.6) presses nothing, so at every sample the tilt about y and
 * the lateral factor along x are those of A alone (cn_margin), each found in a few verdicts
 * about the limit (17 each when no limit guided them). */
static void test_path_margins_3d(void) {
    const char *lift = "{\"dimension\":3,\"friction\":0.6,\"parts\":["
                       "{\"name\":\"table\",\"fixed\":true,\"box\":{\"min\":[-3,-3,-1],\"max\":[3,3,0]}},"
                       "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}}%s]%s}";
    char json[1024], alone[1024];
    snprintf(json, sizeof json, lift, ",{\"name\":\"B\",\"box\":{\"min\":[0.1,0.1,1],\"max\":[0.9,0.9,1.8]}}",
             ",\"plan\":[{\"move\":\"B\",\"path\":[[0,0,2]],\"support\":\"hold\"}]");
    snprintf(alone, sizeof alone, lift, "", "");
    cnMarginOptions mo = cn_margin_options_default();
    mo.kinds = CN_MARGIN_TILT | CN_MARGIN_LATERAL;
    mo.rel_tol = 1e-4;
    mo.axis[1] = 1;
    mo.direction[0] = 1;
    cnAssembly *a = load_ok(json), *b = load_ok(alone);
    cnMarginResult m;
    memset(&m, 0, sizeof m);
    cnDiag d;
    cnSimOptions o = cn_sim_options_default();
    o.margin = &mo;
    o.margin_samples = 3;
    cnSimResult r;
    memset(&r, 0, sizeof r);
    if (a && b && cn_margin(b, &mo, &m, &d) == CN_OK && cn_simulate(a, &o, &r, &d) == CN_OK) {
        const cnStepResult *s = &r.steps[0];
        CHECK(r.stable && !s->margin[0].computed);
        const cnMargin *want[3] = {NULL, &m.tilt, &m.lateral};
        for (int k = 1; k < 3; k++) {
            CHECK_MSG(s->margin[k].computed && s->margin[k].samples == 3 &&
                          fabs(s->margin[k].at.value - want[k]->value) <= 2e-4 * want[k]->value,
                      "3-D margin %d: %.9g along the path (%d samples), %.9g for A alone", k,
                      s->margin[k].at.value, s->margin[k].samples, want[k]->value);
            CHECK_MSG(s->margin[k].at.verdicts <= 5, "3-D margin %d: %d verdicts", k, s->margin[k].at.verdicts);
        }
        /* A alone: sliding comes first (mu 0.6 < b/h 1) */
        CHECK_MSG(fabs(m.lateral.value - 0.6) <= 1e-3, "A alone: lateral %.9g, want mu 0.6", m.lateral.value);
        CHECK_MSG(fabs(m.tilt.value - atan(0.6)) <= 1e-3, "A alone: tilt %.9g, want atan 0.6", m.tilt.value);
    } else
        CHECK_MSG(false, "3-D path margins: %s", d.message);
    cn_sim_result_free(&r);
    cn_margin_result_free(&m);
    cn_assembly_free(a);
    cn_assembly_free(b);
}

/* The weakest sample is the weakest: a block pushed along a plank towards its overhang
 * (examples/plank_push.json, mu 0.5): the step's weakest tilt is the least of its samples', its
 * time is that sample's, and up to t = 2.5 every sample's is the plank's sliding on the post at
 * atan 0.5 (past it the pusher, stopped, holds the block and the plank gains margin). */
static void test_path_margin_weakest(void) {
    cnAssembly *a = load_example("plank_push");
    if (!a) return;
    cnDiag d;
    cnMarginOptions mo = cn_margin_options_default();
    mo.kinds = CN_MARGIN_TILT;
    mo.rel_tol = 1e-4;
    cnSimOptions o = cn_sim_options_default();
    o.margin = &mo;
    cnSimResult r;
    if (cn_simulate(a, &o, &r, &d) == CN_OK) {
        const cnStepResult *s = &r.steps[0];
        CHECK(r.stable && s->margin[1].computed && !s->margin[0].computed && !s->margin[2].computed);
        double least = INFINITY, first = NAN, at = NAN;
        for (int i = 0; i < s->nsamples; i++) {
            const cnSimSample *sm = &r.samples[s->first_sample + i];
            if (isnan(sm->margin[1])) continue;
            if (isnan(first)) first = sm->margin[1];
            if (sm->margin[1] < least) least = sm->margin[1], at = sm->time;
        }
        CHECK_MSG(s->margin[1].at.value == least && s->margin[1].time == at,
                  "weakest tilt %.9g at t = %g, least of the samples %.9g at t = %g", s->margin[1].at.value,
                  s->margin[1].time, least, at);
        for (int i = 0; i < s->nsamples; i++) {
            const cnSimSample *sm = &r.samples[s->first_sample + i];
            if (isnan(sm->margin[1]) || sm->time > 2.5 + 1e-9) continue;
            CHECK_MSG(fabs(sm->margin[1] - atan(0.5)) <= 2e-4 * atan(0.5), "t = %g: tilt %.9g, want atan 0.5",
                      sm->time, sm->margin[1]);
        }
        CHECK_MSG(least <= first && at <= 2.5 + 1e-9, "least %.9g at t = %g, first %.9g", least, at, first);
    } else {
        cn_test_failures++;
        fprintf(stderr, "simulate failed: %s\n", d.message);
    }
    cn_sim_result_free(&r);
    cn_assembly_free(a);
}

void test_simulate(void) {
    test_path_margins();
    test_path_margins_3d();
    test_path_margin_weakest();
    test_apart_shortcut();
    test_held_slide_invariant();
    test_events_between_samples();
    test_turn_events_between_samples();
    test_gripper_lets_go();
    test_prop3_onset();
    test_push_takes_weight();
    test_default_sampling_scale_free();
    test_counterweight();
    test_friction_noninvertible();
    test_held_supports();
    test_blocked_and_carried();
    test_warm_equals_cold();
    test_undecided_is_not_stable();
}
