/* The scenes of the unit tests of src/motion/'s samples, onsets and margins (test_sim_sample.c,
 * test_sim_onset.c, test_sim_margin.c), and a step's work state set up as simulate.c sets it. */
#ifndef CAIRN_TEST_SIM_SCENES_H
#define CAIRN_TEST_SIM_SCENES_H

#include <string.h>

#include "helpers.h"
#include "sim_step.h"

/* Frictionless: A (2 x 1) on a table, B (1 x 1) on A's left half. The gripper holds A and slides
 * it 2 to the right, out from under B: B's centre (x = 0.5) leaves A's top face, which starts at
 * x = s, at s = 0.5; beyond it, B tips off A's left edge. */
#define SIM_SLIDE_OUT                                                                              \
    "{\"dimension\":2,\"gravity\":[0,-9.81],\"parts\":["                                           \
    "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-9,-1],[9,-1],[9,0],[-9,0]]},"               \
    "{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"                                      \
    "{\"name\":\"B\",\"polygon\":[[0,1],[1,1],[1,2],[0,2]]}],"                                     \
    "\"plan\":[{\"move\":\"A\",\"path\":[[2,0]],\"support\":\"hold\"}]}"

/* Frictionless: the gripper pushes B 3 to the right along A's top and back: B rests on A until its
 * centre (x = 0.5 + s) passes A's right end (x = 2) at s = 1.5; beyond, alone, it would tip, so
 * the gripper takes its weight, until the centre is back over A at s = 4.5. */
#define SIM_PUSH_OVER                                                                              \
    "{\"dimension\":2,\"gravity\":[0,-9.81],\"parts\":["                                           \
    "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-9,-1],[9,-1],[9,0],[-9,0]]},"               \
    "{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"                                      \
    "{\"name\":\"B\",\"polygon\":[[0,1],[1,1],[1,2],[0,2]]}],"                                     \
    "\"plan\":[{\"move\":\"B\",\"path\":[[3,0],[-3,0]],\"support\":\"push\"}]}"

/* Set S up for step k of a's plan, as simulate.c does (the moved parts present, every later
 * step's gone only if it is a gripper body). o: the simulation's options, kept by S. */
static inline bool sim_step_begin(Step *S, const cnAssembly *a, int k, const cnSimOptions *o) {
    memset(S, 0, sizeof *S);
    S->a = a;
    S->o = o;
    const cnPlanStep *st = &a->plan[k];
    if (cn_sm_step_alloc(S, st->nseg) != 0) return false;
    for (int i = 0; i < a->nparts; i++) S->absent[i] = a->parts[i].gripper_step >= 0;
    cn_sm_step_setup(S, st, false);
    for (int i = 0; i < st->nmove; i++) S->absent[st->move[i]] = 0;
    return true;
}

/* Load json and set S up for its first step with o defaulted: the assembly, or NULL (a failure
 * counted). sim_end frees both. */
static inline cnAssembly *sim_begin(const char *json, Step *S, cnSimOptions *o) {
    cnAssembly *a = load_ok(json);
    if (!a) return NULL;
    *o = cn_sim_options_default();
    if (sim_step_begin(S, a, 0, o)) return a;
    CHECK(!"out of memory");
    cn_sm_step_free(S);
    cn_assembly_free(a);
    return NULL;
}

static inline void sim_end(cnAssembly *a, Step *S) {
    cn_sm_step_free(S);
    cn_assembly_free(a);
}

/* A part's index by name, or -1. */
static inline int sim_part(const cnAssembly *a, const char *name) {
    for (int i = 0; i < a->nparts; i++)
        if (!strcmp(a->parts[i].name, name)) return i;
    return -1;
}

/* Does part p move in r? */
static inline bool sim_moves(const cnCheckResult *r, int p) {
    for (int i = 0; i < r->nmoving; i++)
        if (r->moving[i] == p) return true;
    return false;
}

#endif
