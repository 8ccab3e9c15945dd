/* Unit tests of src/io/load_plan.c (and the paths and turns of load_read.c): what a plan, its
 * grippers and the candidate paths read into, field by field, against the file (test_load checks
 * the refusals). The plan of docs/cli.md's example: a pushed step of two moves; a subassembly
 * with one part gripped (the default grips all moved parts); a step with a gripper body (an
 * extra fixed part after the assembly's own, named after its step, with its own mass); a step
 * without a path (made at load: straight up, against gravity, until clear of the parts whose
 * shadow meets its own, a taller one beside it included, plus 1 % of its height); the sampling. A turn (degrees to radians, 2-D axis z) and
 * a 3-D turn's axis made unit. Candidates by part and name, their support given or the file's
 * default. And gravity turned 90 degrees: the made path goes against it. */
#include <math.h>

#include "helpers.h"

#define NEAR(x, y) (fabs((double)(x) - (double)(y)) <= 1e-12 * fmax(1, fabs((double)(y))))

static const char *PLAN_2D =
    "{\"dimension\":2,\"parts\":["
    "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-9,-1],[9,-1],[9,0],[-9,0]]},"
    "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
    "{\"name\":\"B\",\"polygon\":[[1,0],[2,0],[2,1],[1,1]]},"
    "{\"name\":\"C\",\"polygon\":[[3,0],[4,0],[4,1],[3,1]]},"
    "{\"name\":\"D\",\"polygon\":[[5,0],[6,0],[6,1],[5,1]]},"
    "{\"name\":\"E\",\"polygon\":[[5,1],[6,1],[6,2],[5,2]]},"
    "{\"name\":\"F\",\"polygon\":[[6,0],[7,0],[7,3],[6,3]]}],"
    "\"plan\":["
    "{\"move\":\"C\",\"path\":[[2,0],{\"rotate\":-90,\"about\":[0,3]},[0,2]],\"support\":\"push\"},"
    "{\"move\":[\"A\",\"B\"],\"grip\":\"A\",\"path\":[[-6,0]]},"
    "{\"move\":\"E\"},"
    "{\"move\":\"D\",\"path\":[[0,5]],\"gripper\":{\"polygon\":[[4,1],[5,1],[5,1.2],[4,1.2]]}}],"
    "\"simulation\":{\"dt\":0.25,\"speed\":2},"
    "\"candidates\":{\"C\":{\"I\":[[0,6]],\"II\":{\"path\":[[-8,0],[0,6]],\"support\":\"push\"}},"
    "\"A\":{\"up\":[[0,4]]}}}";

static bool seg_move(const cnSegment *s, double x, double y, double z) {
    return s->kind == CN_SEGMENT_MOVE && NEAR(s->move[0], x) && NEAR(s->move[1], y) && NEAR(s->move[2], z);
}

static void test_plan_2d(void) {
    cnAssembly *a = load_ok(PLAN_2D);
    if (!a) return;
    int A = cn_assembly_find_part(a, "A"), B = cn_assembly_find_part(a, "B"), C = cn_assembly_find_part(a, "C"),
        D = cn_assembly_find_part(a, "D"), E = cn_assembly_find_part(a, "E");
    CHECK(a->nsteps == 4 && a->nparts == 8);
    const cnPlanStep *s = a->plan;
    /* a pushed step: a move, a quarter turn clockwise about (0, 3), a move */
    CHECK(s[0].nmove == 1 && s[0].move[0] == C && s[0].ngrip == 1 && s[0].grip[0] == C);
    CHECK(s[0].support == CN_SUPPORT_PUSH && s[0].gripper == -1 && s[0].path_given && s[0].nseg == 3 && !s[0].still);
    CHECK(seg_move(&s[0].seg[0], 2, 0, 0) && seg_move(&s[0].seg[2], 0, 2, 0));
    const cnSegment *t = &s[0].seg[1];
    CHECK(t->kind == CN_SEGMENT_TURN && NEAR(t->angle, -acos(-1.0) / 2) && NEAR(t->axis[2], 1) && NEAR(t->axis[0], 0) &&
          NEAR(t->about[0], 0) && NEAR(t->about[1], 3));
    CHECK(cn_path_turns(s[0].seg, s[0].nseg) && !cn_path_turns(s[1].seg, s[1].nseg));
    /* a subassembly, one part gripped, held by default */
    CHECK(s[1].nmove == 2 && s[1].move[0] == A && s[1].move[1] == B && s[1].ngrip == 1 && s[1].grip[0] == A);
    CHECK(s[1].support == CN_SUPPORT_HOLD && s[1].nseg == 1 && seg_move(&s[1].seg[0], -6, 0, 0));
    /* no path: made at load, straight up until clear of every part whose shadow meets E's (F,
       touching its side, tops out at 3: 2 above E's bottom) plus 1 % of E's height */
    CHECK(s[2].nmove == 1 && s[2].move[0] == E && !s[2].path_given && s[2].nseg == 1 && s[2].seg[0].kind == CN_SEGMENT_MOVE);
    CHECK_MSG(NEAR(s[2].seg[0].move[0], 0) && NEAR(s[2].seg[0].move[1], 2.01), "made path (%g, %g)", s[2].seg[0].move[0],
              s[2].seg[0].move[1]);
    /* a gripper body: the last part, fixed, named after its step, with its area as size */
    int g = s[3].gripper;
    CHECK(s[3].move[0] == D && g == a->nparts - 1 && a->parts[g].fixed && a->parts[g].gripper_step == 3);
    CHECK(!strcmp(a->parts[g].name, "gripper4") && NEAR(a->parts[g].size, 0.2));
    for (int i = 0; i < a->nparts - 1; i++) CHECK(a->parts[i].gripper_step < 0);
    CHECK(a->sim_dt == 0.25 && a->sim_speed == 2);
    /* candidates, grouped by part in file order */
    CHECK(a->ncand == 3 && a->cand_support == CN_SUPPORT_HOLD);
    if (a->ncand == 3) {
        const cnCandidate *c = a->cand;
        CHECK(c[0].part == C && !strcmp(c[0].name, "I") && c[0].support == -1 && c[0].nseg == 1 &&
              seg_move(&c[0].seg[0], 0, 6, 0));
        CHECK(c[1].part == C && !strcmp(c[1].name, "II") && c[1].support == CN_SUPPORT_PUSH && c[1].nseg == 2 &&
              seg_move(&c[1].seg[0], -8, 0, 0) && seg_move(&c[1].seg[1], 0, 6, 0));
        CHECK(c[2].part == A && !strcmp(c[2].name, "up"));
    }
    cn_assembly_free(a);
}

static void test_plan_3d(void) {
    /* gravity along -x: the made path goes +x, clear of C beside B (reaching x = 4: 3 past B's
       low end) plus 1 % of B's extent; a turn about an axis given at length 2 */
    const char *json =
        "{\"dimension\":3,\"gravity\":[-9.81,0,0],\"candidate_support\":\"push\",\"parts\":["
        "{\"name\":\"W\",\"fixed\":true,\"box\":{\"min\":[-1,-5,-5],\"max\":[0,5,5]}},"
        "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}},"
        "{\"name\":\"B\",\"box\":{\"min\":[1,0,0],\"max\":[2,1,1]}},"
        "{\"name\":\"C\",\"box\":{\"min\":[0,1,0],\"max\":[4,2,1]}}],"
        "\"plan\":[{\"move\":\"B\"},{\"move\":\"A\",\"path\":[{\"rotate\":45,\"axis\":[0,2,0],\"about\":[0,0,0]}]}],"
        "\"candidates\":{\"A\":{\"out\":[[3,0,0]]}}}";
    cnAssembly *a = load_ok(json);
    if (!a) return;
    const cnPlanStep *s = a->plan;
    CHECK(a->nsteps == 2 && !s[0].path_given && s[0].nseg == 1);
    CHECK_MSG(NEAR(s[0].seg[0].move[0], 3.01) && NEAR(s[0].seg[0].move[1], 0) && NEAR(s[0].seg[0].move[2], 0),
              "made path (%g, %g, %g)", s[0].seg[0].move[0], s[0].seg[0].move[1], s[0].seg[0].move[2]);
    const cnSegment *t = &s[1].seg[0];
    CHECK(t->kind == CN_SEGMENT_TURN && NEAR(t->angle, acos(-1.0) / 4) && NEAR(t->axis[1], 1) && NEAR(t->axis[0], 0) &&
          NEAR(t->axis[2], 0));
    CHECK(a->ncand == 1 && a->cand_support == CN_SUPPORT_PUSH && a->cand[0].support == -1);
    cn_assembly_free(a);
}

void test_load_plan(void) {
    test_plan_2d();
    test_plan_3d();
}
