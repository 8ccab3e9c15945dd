/* Unit tests of src/motion/sim_path.c: where a step's parts are along its path. A 2 x 1 block is
 * lifted by 3, turned 90 degrees clockwise about (0, 3), then moved 4 along x; by hand: the
 * path's length is 3 + (pi/2) sqrt 5 + 4 (the turn measured along the arc of the block's
 * farthest corner), the corner (2, 1) passes (3/sqrt 2, 3 - 1/sqrt 2) half-way round the turn and
 * ends at (5, 1). Checked: the length; poses, directions and velocities on each segment; pausing
 * at a segment's end and leaving it; the assembly's traversal, which must be the disassembly's
 * run backwards (the pose at s is the disassembly's at length - s); which samples the gripper
 * always holds (along gravity, and turns); the reported displacement (a move's translation, a
 * turn's centre of mass). */
#include <math.h>
#include <string.h>

#include "helpers.h"
#include "sim_step.h"

#define PI 3.14159265358979323846
#define NEAR(x, y) (fabs((double)(x) - (double)(y)) <= 1e-9 * fmax(1, fabs((double)(y))))

static const char *LIFT_TURN =
    "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
    "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-9,-1],[9,-1],[9,0],[-9,0]]},"
    "{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]}],"
    "\"plan\":[{\"move\":\"A\",\"path\":[[0,3],{\"rotate\":-90,\"about\":[0,3]},[4,0]]}]}";

/* Where the block's corner (2, 1) is at distance s. */
static void corner_at(const Step *S, double s, bool leave, double out[3]) {
    PathPoint pp;
    cn_sm_path_at(S, s, leave, &pp);
    double c[3] = {2, 1, 0};
    cn_pose_apply(&pp.pose, c, out);
}

void test_sim_path(void) {
    cnAssembly *a = load_ok(LIFT_TURN);
    if (!a) return;
    Step S, R;
    memset(&S, 0, sizeof S);
    memset(&R, 0, sizeof R);
    S.a = R.a = a;
    if (cn_sm_step_alloc(&S, 3) != 0 || cn_sm_step_alloc(&R, 3) != 0) {
        CHECK_MSG(false, "out of memory");
        goto done;
    }
    cn_sm_step_setup(&S, &a->plan[0], false);
    cn_sm_step_setup(&R, &a->plan[0], true);
    double L2 = PI / 2 * sqrt(5), L = 3 + L2 + 4;
    CHECK_MSG(NEAR(S.length, L) && NEAR(R.length, L), "length %.15g (assembly %.15g), want %.15g", S.length,
              R.length, L);
    CHECK(NEAR(S.seglen[0], 3) && NEAR(S.seglen[1], L2) && NEAR(S.seglen[2], 4));
    CHECK(NEAR(R.seglen[0], 4) && NEAR(R.seglen[2], 3));
    PathPoint pp;
    double x[3];
    /* the lift: up along +y, held (along gravity), reported as its translation */
    cn_sm_path_at(&S, 1.5, false, &pp);
    CHECK(!pp.turn && !pp.paused && NEAR(pp.pose.t[1], 1.5) && NEAR(pp.pose.t[0], 0) && NEAR(pp.dir[1], 1) &&
          NEAR(pp.unit.v[1], 1));
    CHECK(cn_sm_always_held(a, &pp));
    cn_sm_reported_disp(&S, &pp.pose, x);
    CHECK(NEAR(x[0], 0) && NEAR(x[1], 1.5));
    /* the lift's end: arriving, it pauses; leaving, the turn begins */
    cn_sm_path_at(&S, 3, false, &pp);
    CHECK(!pp.turn && pp.paused && NEAR(pp.pose.t[1], 3));
    cn_sm_path_at(&S, 3, true, &pp);
    CHECK(pp.turn && !pp.paused && NEAR(pp.unit.w[2], -(PI / 2) / L2) && NEAR(pp.unit.about[1], 3));
    /* half-way round the turn: held (a turn always is); the corner by hand */
    cn_sm_path_at(&S, 3 + L2 / 2, false, &pp);
    CHECK(pp.turn && cn_sm_always_held(a, &pp));
    corner_at(&S, 3 + L2 / 2, false, x);
    CHECK_MSG(NEAR(x[0], 3 / sqrt(2)) && NEAR(x[1], 3 - 1 / sqrt(2)), "mid-turn corner (%.12g, %.12g)", x[0], x[1]);
    /* its reported displacement: the centre of mass (1, 0.5) lifted to (1, 3.5), then turned by
       -45 degrees about (0, 3) */
    cn_sm_reported_disp(&S, &pp.pose, x);
    double cx = (1 * cos(PI / 4) + 0.5 * sin(PI / 4)), cy = 3 + (-1 * sin(PI / 4) + 0.5 * cos(PI / 4));
    CHECK_MSG(NEAR(x[0], cx - 1) && NEAR(x[1], cy - 0.5), "mid-turn displacement (%.12g, %.12g)", x[0], x[1]);
    /* the last move, sideways: not always held; the end */
    cn_sm_path_at(&S, 3 + L2 + 1, false, &pp);
    CHECK(!pp.turn && NEAR(pp.dir[0], 1) && !cn_sm_always_held(a, &pp));
    corner_at(&S, L, false, x);
    CHECK_MSG(NEAR(x[0], 5) && NEAR(x[1], 1), "end corner (%.12g, %.12g)", x[0], x[1]);
    cn_sm_path_at(&S, L, false, &pp);
    CHECK(pp.paused);
    /* the assembly: the disassembly run backwards, at every distance */
    int bad = 0;
    for (int i = 0; i <= 200; i++) {
        double s = L * i / 200, y[3];
        corner_at(&R, s, false, x);
        corner_at(&S, L - s, false, y);
        if (!NEAR(x[0], y[0]) || !NEAR(x[1], y[1])) bad++;
    }
    CHECK_MSG(bad == 0, "assembly: %d of 201 distances off the disassembly run backwards", bad);
    corner_at(&R, 0, false, x);
    CHECK(NEAR(x[0], 5) && NEAR(x[1], 1));
done:
    cn_sm_step_free(&S);
    cn_sm_step_free(&R);
    cn_assembly_free(a);
}
