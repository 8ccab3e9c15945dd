/* Unit tests of src/plan/plan_large.c (cn_plan past 16 free parts: one stable plan depth-first,
 * the highest parts first): running-bond walls of 25 bricks frictionless and 18 with friction,
 * whose plans the simulator replays stably, and a balanced plank whose every first move fails by
 * Proposition 1. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cairn/cairn.h"
#include "helpers.h"

/* A running-bond wall of rows x cols bricks (2 x 1) on a fixed ground, frictionless, its bricks
 * written to the file in the order perm gives (NULL: row by row). */
static char *wall_json(int rows, int cols, const int *perm) {
    size_t cap = 256 + (size_t)rows * cols * 128;
    char *js = malloc(cap);
    int len = snprintf(js, cap, "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                       "{\"name\":\"ground\",\"fixed\":true,\"polygon\":[[-2,-1],[%d,-1],[%d,0],[-2,0]]}",
                       2 * cols + 3, 2 * cols + 3);
    for (int k = 0; k < rows * cols; k++) {
        int i = perm ? perm[k] : k, r = i / cols, c = i % cols, x = 2 * c + r % 2;
        len += snprintf(js + len, cap - (size_t)len,
                        ",{\"name\":\"r%dc%d\",\"polygon\":[[%d,%d],[%d,%d],[%d,%d],[%d,%d]]}", r, c, x, r,
                        x + 2, r, x + 2, r + 1, x, r + 1);
    }
    snprintf(js + len, cap - (size_t)len, "]}");
    return js;
}

/* 25 bricks: one plan, every brick once, that the simulator replays stably step by step; the
 * same with the bricks listed in reverse file order (the search's order is by height, not by
 * file). The search says it is not exhaustive, and it checked one state per step. */
static void test_plan_large_wall(void) {
    int perm[25];
    for (int rev = 0; rev < 2; rev++) {
        for (int k = 0; k < 25; k++) perm[k] = rev ? 24 - k : k;
        char *js = wall_json(5, 5, perm);
        cnAssembly *a = load_ok(js);
        free(js);
        if (!a) return;
        cnPlanOptions o = cn_plan_options_default();
        cnPlanResult r;
        cnDiag d;
        CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
        CHECK_MSG(r.stable && r.best_plan && r.best_plan->n == 25, "wall 5 x 5 (%s): no plan of 25 steps",
                  rev ? "reversed" : "file order");
        if (r.best_plan && r.best_plan->n == 25) {
            int seen[26] = {0};
            for (int k = 0; k < 25; k++) {
                const cnPlanMove *m = &r.best_plan->steps[k];
                CHECK(m->move.n == 1 && m->status == CN_STEP_STABLE && !m->proposition_1);
                if (m->move.n == 1 && m->move.idx[0] >= 0 && m->move.idx[0] < 26) seen[m->move.idx[0]]++;
            }
            for (int i = 1; i < 26; i++) CHECK_MSG(seen[i] == 1, "brick %d is taken out %d times", i, seen[i]);
            CHECK(cn_test_replay_stable(a, r.best_plan));
            /* the top row comes out first */
            CHECK(a->parts[r.best_plan->steps[0].move.idx[0]].com[1] > 4);
        }
        CHECK(!r.search.exhaustive && !r.search.budget_reached && r.search.free_parts == 25);
        CHECK_MSG(r.search.states == 26, "%d states", r.search.states);
        CHECK(r.nrows == 1 && r.table[0].end == CN_ROW_STABLE && r.ndead == 0);
        cn_plan_result_free(&r);
        /* a budget of 5 states ends the search without a plan, and says so */
        o.max_states = 5;
        CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
        CHECK(!r.stable && r.search.budget_reached && !r.search.out_of_time);
        cn_plan_result_free(&r);
        cn_assembly_free(a);
    }
}

/* With friction (a running-bond wall of 3 x 6 bricks, mu = 0.6): lifting a brick straight up
 * slides it along its neighbours (the search for a motion from rest cannot decide that drag), so
 * each brick goes first along a direction that opens every contact it has, up and away: one
 * simulation per step, none undecided. The plan replays stably with the simulator's full budget
 * (which checks every sample, the planner's shortcut for samples where the brick touches
 * nothing aside). */
static void test_plan_large_friction(void) {
    char *js = wall_json(3, 6, NULL);
    char *at = strstr(js, "\"parts\"");
    size_t len = strlen(js);
    char *fj = malloc(len + 32);
    memcpy(fj, js, (size_t)(at - js));
    int k = sprintf(fj + (at - js), "\"friction\":0.6,");
    memcpy(fj + (at - js) + k, at, len - (size_t)(at - js) + 1);
    free(js);
    cnAssembly *a = load_ok(fj);
    free(fj);
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK_MSG(r.stable && r.best_plan && r.best_plan->n == 18, "friction wall 3 x 6: no plan");
    if (r.best_plan) CHECK(cn_test_replay_stable(a, r.best_plan));
    CHECK_MSG(r.search.undecided_moves == 0 && r.search.states == 19 && r.search.simulations == 18,
              "%d undecided moves, %d states, %d simulations", r.search.undecided_moves, r.search.states,
              r.search.simulations);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* A plank on a narrow fulcrum (top 0.1 wide) carries two columns of 8 unit blocks, 4 either side
 * of it: balanced. Taking any block out shifts the centre of mass by at least 4 / 20 of a unit,
 * past the fulcrum's edge (the plank tips), or leaves blocks in the air; the plank is under them.
 * So no first move is stable, each by Proposition 1 (hand-derived): 17 dead ends, no simulation,
 * 18 states checked. */
static void test_plan_large_none(void) {
    char js[8192];
    int len = snprintf(js, sizeof js, "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                       "{\"name\":\"F\",\"fixed\":true,\"polygon\":[[-1,-2],[1,-2],[0.05,0],[-0.05,0]]},"
                       "{\"name\":\"plank\",\"polygon\":[[-5,0],[5,0],[5,0.5],[-5,0.5]]}");
    for (int side = 0; side < 2; side++)
        for (int k = 0; k < 8; k++) {
            double x = side ? 3.5 : -4.5, y = 0.5 + k;
            len += snprintf(js + len, sizeof js - (size_t)len,
                            ",{\"name\":\"%c%d\",\"polygon\":[[%g,%g],[%g,%g],[%g,%g],[%g,%g]]}", side ? 'R' : 'L', k,
                            x, y, x + 1, y, x + 1, y + 1, x, y + 1);
        }
    snprintf(js + len, sizeof js - (size_t)len, "]}");
    cnAssembly *a = load_ok(js);
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK(!r.stable && !r.unstable_at_start && !r.search.budget_reached);
    CHECK_MSG(r.ndead == 17 && r.search.states == 18 && r.search.simulations == 0,
              "%d dead ends, %d states, %d simulations", r.ndead, r.search.states, r.search.simulations);
    for (int k = 0; k < r.ndead; k++) CHECK(r.dead_ends[k].proposition_1 && r.dead_ends[k].status == CN_STEP_UNSTABLE);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

void test_plan_large(void) {
    test_plan_large_wall();
    test_plan_large_none();
    test_plan_large_friction();
}
