/* An assembly built in code (no JSON file), then checked, simulated along a plan and planned:
 * a plank B overhangs block A and is held down by a heavy counterweight C on its other end.
 * Taking C away first tips B, and so does taking B (C would fall off): no part can go first
 * alone. The planner, allowed to take subassemblies, lifts B and C together.
 *   cc build.c $(pkg-config --cflags --libs cairn) -o build && ./build   */
#include <stdio.h>

#include <cairn/cairn.h>

static int fail(const char *what, const cnDiag *d) {
    fprintf(stderr, "%s: %s%s%s\n", what, d->where, d->where[0] ? ": " : "", d->message);
    return d->code == CN_ERR_INPUT ? 2 : 3;
}

int main(void) {
    cnBuilder *b = cn_builder_new(2);
    if (!b) return 3;
    cn_builder_set_name(b, "counterweight");
    cn_builder_set_gravity(b, (double[]){0, -9.81});
    cn_builder_add_polygon(b, "table", 4, (double[]){-2, -1, 10, -1, 10, 0, -2, 0}, true);
    cn_builder_add_polygon(b, "A", 4, (double[]){0, 0, 4, 0, 4, 1, 0, 1}, false);
    cn_builder_add_polygon(b, "B", 4, (double[]){3, 1, 6, 1, 6, 2, 3, 2}, false);
    cn_builder_add_polygon(b, "C", 4, (double[]){3, 2, 4, 2, 4, 3, 3, 3}, false);
    cn_builder_set_part_density(b, 4); /* C: heavy enough to hold B down over A's edge */
    /* the plan to simulate: C lifted first, straight up */
    cn_builder_add_step(b, 1, (const char *const[]){"C"}, 1,
                        &(cnSegment){.kind = CN_SEGMENT_MOVE, .move = {0, 2, 0}}, CN_SUPPORT_HOLD);
    cnAssembly *a = NULL;
    cnDiag d;
    cnStatus s = cn_builder_finish(b, &a, &d);
    cn_builder_free(b);
    if (s != CN_OK) return fail("build", &d);

    cnCheckResult r;
    if (cn_check(a, NULL, &r, &d) != CN_OK) return fail("check", &d);
    printf("check: %s\n", r.stable ? "stable" : "not stable");
    cn_check_result_free(&r);

    cnSimOptions so = cn_sim_options_default();
    cnSimResult sim;
    if (cn_simulate(a, &so, &sim, &d) != CN_OK) return fail("simulate", &d);
    printf("simulate (C first): %s\n", sim.stable ? "stable" : "not stable");
    cn_sim_result_free(&sim);

    cnPlanOptions po = cn_plan_options_default();
    po.subassemblies = true;
    cnPlanResult pr;
    if (cn_plan(a, &po, &pr, &d) != CN_OK) return fail("plan", &d);
    printf("plan: %s, %.0f two-handed plan%s; first out:", pr.stable ? "stable" : "none stable", pr.nplans,
           pr.nplans == 1 ? "" : "s");
    const cnPlanMove *first = pr.tree ? &pr.tree->take_out : NULL;
    for (int i = 0; first && i < first->move.n; i++) printf(" %s", a->parts[first->move.idx[i]].name);
    printf("\n");
    int code = pr.stable ? 0 : 1;
    cn_plan_result_free(&pr);
    cn_assembly_free(a);
    return code;
}
