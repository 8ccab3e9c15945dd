/* Test helpers: load an assembly from inline JSON or an example, and fail loudly if it does not
 * load; replay a planned sequence with the simulator. */
#ifndef CAIRN_TEST_HELPERS_H
#define CAIRN_TEST_HELPERS_H

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cairn/cairn.h"
#include "test.h"

static inline cnAssembly *load_ok(const char *json) {
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(json, "inline", &a, &d) != CN_OK) {
        cn_test_failures++;
        fprintf(stderr, "load failed: %s: %s\n  in %s\n", d.where, d.message, json);
        return NULL;
    }
    return a;
}

/* The 2-D scene of the search tests: a box A (2 x 1) with, when `two`, a box B (1 x 0.6) on it,
 * and a fixed triangle F far away (A and B are bodies; their contacts are the test's own), under
 * gravity turned by `ang` radians from -y. */
static inline void scene_two_boxes_2d(char *json, size_t cap, double ang, int two) {
    snprintf(json, cap,
             "{\"dimension\":2,\"gravity\":[%.17g,%.17g],\"parts\":["
             "{\"name\":\"F\",\"fixed\":true,\"polygon\":[[-9,-9],[-8,-9],[-8,-8]]},"
             "{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]}%s]}",
             9.81 * sin(ang), -9.81 * cos(ang),
             two ? ",{\"name\":\"B\",\"polygon\":[[0.5,1],[1.5,1],[1.5,1.6],[0.5,1.6]]}" : "");
}

/* A 2 x 1 block on a level slope under gravity turned 20 degrees (a 20 degree incline), friction
 * mu: it holds for mu >= tan 20 = 0.364 (test_figure, test_report_margin). */
static inline void scene_incline_2d(char *json, size_t cap, double mu) {
    double t = 20 * acos(-1.0) / 180;
    snprintf(json, cap,
             "{\"dimension\":2,\"friction\":%g,\"gravity\":[%.17g,%.17g],\"parts\":["
             "{\"name\":\"slope\",\"fixed\":true,\"polygon\":[[-3,-1],[3,-1],[3,0],[-3,0]]},"
             "{\"name\":\"block\",\"polygon\":[[-1,0],[1,0],[1,1],[-1,1]]}]}",
             mu, 9.81 * sin(t), -9.81 * cos(t));
}

#ifdef CAIRN_SOURCE_DIR
/* examples/NAME.json of the source tree, or NULL (a failure counted). */
static inline cnAssembly *load_example(const char *name) {
    char path[1024];
    snprintf(path, sizeof path, "%s/examples/%s.json", CAIRN_SOURCE_DIR, name);
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_file(path, &a, &d) != CN_OK) {
        cn_test_failures++;
        fprintf(stderr, "load failed: %s: %s\n", path, d.message);
        return NULL;
    }
    return a;
}
#endif

/* Replay a sequence with the simulator, one step after another (the parts taken out so far
 * absent): every step must be stable. A second path to the planner's claim. */
static inline bool cn_test_replay_stable(const cnAssembly *a, const cnPlanSequence *seq) {
    unsigned char *absent = calloc((size_t)a->nparts, 1);
    cnSimOptions so = cn_sim_options_default();
    bool ok = true;
    for (int i = 0; i < a->nparts; i++) absent[i] = a->parts[i].gripper_step >= 0;
    for (int k = 0; k < seq->n && ok; k++) {
        const cnPlanMove *m = &seq->steps[k];
        cnPlanStep st;
        memset(&st, 0, sizeof st);
        st.nmove = st.ngrip = m->move.n;
        st.move = st.grip = (int *)m->move.idx;
        st.nseg = m->nseg;
        st.seg = (cnSegment *)m->seg;
        st.path_given = true;
        st.support = m->support;
        st.gripper = -1;
        cnStepResult r;
        cnDiag d;
        if (cn_simulate_step(a, absent, &st, &so, &r, &d) != CN_OK) return free(absent), false;
        ok = r.status == CN_STEP_STABLE;
        cn_step_result_free(&r);
        for (int i = 0; i < m->move.n; i++) absent[m->move.idx[i]] = 1;
    }
    free(absent);
    return ok;
}

#endif
