/* Poses and turning motion paths against hand calculations: the pose algebra; a plank held and
 * tilted about its end carries a block that slides once tan(theta) > mu, or tips once the block's
 * centre passes its lower corner (2-D and 3-D); a block turned into a wall meets it at the angle
 * where its corner reaches the wall; the same onsets after rotating, translating and scaling the
 * whole file (gravity too) and reversing its parts; a collision just after a junction is located
 * by bisection, for moves and turns alike. */
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "pieces.h"

#define DEG (CN_PI / 180)

static void test_pose_algebra(void) {
    /* a quarter turn about (1, 0, 0) along z takes (2, 0, 0) to (1, 1, 0) */
    cnPose p = cn_pose_rotation((double[3]){0, 0, 5}, CN_PI / 2, (double[3]){1, 0, 0});
    double x[3];
    cn_pose_apply(&p, (double[3]){2, 0, 0}, x);
    CHECK_NEAR(x[0], 1, 1e-15);
    CHECK_NEAR(x[1], 1, 1e-15);
    CHECK_NEAR(cn_pose_angle(&p, 2), CN_PI / 2, 1e-15);
    cnPose back = cn_pose_rotation((double[3]){0, 0, 1}, -CN_PI / 2, (double[3]){1, 0, 0});
    CHECK_NEAR(cn_pose_angle(&back, 2), -CN_PI / 2, 1e-15);
    /* composing: the turn and its inverse give the identity; three turns of 120 deg too */
    cnPose id = cn_pose_then(&p, &back);
    cn_pose_apply(&id, (double[3]){3, -2, 7}, x);
    CHECK_NEAR(x[0], 3, 1e-14);
    CHECK_NEAR(x[1], -2, 1e-14);
    CHECK_NEAR(x[2], 7, 1e-14);
    double axis[3] = {1, 2, 3}, c[3] = {0.5, -1, 2};
    cnPose t = cn_pose_rotation(axis, 2 * CN_PI / 3, c), acc = cn_pose_identity();
    for (int i = 0; i < 3; i++) acc = cn_pose_then(&acc, &t);
    cn_pose_apply(&acc, (double[3]){4, 5, 6}, x);
    CHECK_NEAR(x[0], 4, 1e-13);
    CHECK_NEAR(x[1], 5, 1e-13);
    CHECK_NEAR(x[2], 6, 1e-13);
    CHECK(cn_pose_angle(&acc, 3) < 1e-7);
    /* points on the axis stay; the matrix is a rotation (R R^T = I) */
    cn_pose_apply(&t, (double[3]){0.5 + 2, -1 + 4, 2 + 6}, x);
    CHECK_NEAR(x[0], 2.5, 1e-14);
    CHECK_NEAR(x[2], 8, 1e-14);
    double R[3][3];
    cn_pose_matrix(&t, R);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            CHECK_NEAR(R[i][0] * R[j][0] + R[i][1] * R[j][1] + R[i][2] * R[j][2], i == j, 1e-15);
    /* a translation stays exact */
    cnPose tr = cn_pose_translation((double[3]){0.1, 0.2, 0.3});
    cnPose tt = cn_pose_then(&tr, &tr);
    CHECK(cn_pose_is_translation(&tt) && tt.t[0] == 0.1 + 0.1 && tt.t[2] == 0.3 + 0.3);
}

/* A transform of the whole file: rotate by R (about the origin), scale by s, then translate by
 * T. Gravity is rotated with it. */
typedef struct {
    double R[3][3], s, T[3];
    bool reverse;
} Xf;

static Xf xf_identity(void) {
    Xf x;
    memset(&x, 0, sizeof x);
    for (int i = 0; i < 3; i++) x.R[i][i] = 1;
    x.s = 1;
    return x;
}

static void xf_point(const Xf *x, const double p[3], double out[3]) {
    for (int i = 0; i < 3; i++)
        out[i] = x->s * (x->R[i][0] * p[0] + x->R[i][1] * p[1] + x->R[i][2] * p[2]) + x->T[i];
}

static void xf_dir(const Xf *x, const double p[3], double out[3]) {
    for (int i = 0; i < 3; i++) out[i] = x->R[i][0] * p[0] + x->R[i][1] * p[1] + x->R[i][2] * p[2];
}

static int put(char *b, int n, int cap, const char *fmt, ...) __attribute__((format(printf, 4, 5)));
static int put(char *b, int n, int cap, const char *fmt, ...) {
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(b + n, n < cap ? (size_t)(cap - n) : 0, fmt, ap);
    va_end(ap);
    return n + k;
}

/* A box [lo, hi] (2-D: a rectangle) as a polygon or a hull, transformed. */
static int put_box(char *b, int n, int cap, int dim, const Xf *x, const char *name, bool fixed,
                   const double lo[3], const double hi[3]) {
    n = put(b, n, cap, "{\"name\":\"%s\",%s\"%s\":[", name, fixed ? "\"fixed\":true," : "",
            dim == 2 ? "polygon" : "hull");
    int nc = dim == 2 ? 4 : 8;
    static const int ccw[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    for (int i = 0; i < nc; i++) {
        double p[3], q[3];
        if (dim == 2) {
            p[0] = ccw[i][0] ? hi[0] : lo[0], p[1] = ccw[i][1] ? hi[1] : lo[1], p[2] = 0;
        } else {
            p[0] = (i & 1) ? hi[0] : lo[0], p[1] = (i & 2) ? hi[1] : lo[1], p[2] = (i & 4) ? hi[2] : lo[2];
        }
        xf_point(x, p, q);
        n = put(b, n, cap, "%s[%.17g,%.17g", i ? "," : "", q[0], q[1]);
        n = dim == 3 ? put(b, n, cap, ",%.17g]", q[2]) : put(b, n, cap, "]");
    }
    return put(b, n, cap, "]}");
}

/* A plank (10 x 1, y in [0, 1] in 2-D; z in 3-D) on a table, a block w x h on it at x = 4; the
 * plank gripped and turned by `deg` about its lower left edge (through the origin, 3-D: along
 * -y so that positive degrees lift its far end). */
static char *tilt_scene(int dim, double mu, double w, double h, double deg, const Xf *x) {
    int cap = 8192, n = 0;
    char *b = malloc((size_t)cap);
    int up = dim == 2 ? 1 : 2;
    double g[3] = {0, 0, 0}, gx[3];
    g[up] = -9.81;
    xf_dir(x, g, gx);
    n = put(b, n, cap, "{\"dimension\":%d,\"friction\":%.17g,\"gravity\":[%.17g,%.17g", dim, mu, gx[0], gx[1]);
    n = dim == 3 ? put(b, n, cap, ",%.17g],\"parts\":[", gx[2]) : put(b, n, cap, "],\"parts\":[");
    double tlo[3] = {-4, -2, -2}, thi[3] = {12, 2, 2}, plo[3] = {0, -1, -1}, phi[3] = {10, 1, 1};
    double blo[3] = {4, -0.5, -0.5}, bhi[3] = {4 + w, 0.5, 0.5};
    tlo[up] = -1, thi[up] = 0, plo[up] = 0, phi[up] = 1, blo[up] = 1, bhi[up] = 1 + h;
    const char *names[3] = {"table", "plank", "block"};
    const double *los[3] = {tlo, plo, blo}, *his[3] = {thi, phi, bhi};
    for (int k = 0; k < 3; k++) {
        int i = x->reverse ? 2 - k : k;
        if (k) n = put(b, n, cap, ",");
        n = put_box(b, n, cap, dim, x, names[i], i == 0, los[i], his[i]);
    }
    double about[3], ax[3] = {0, 0, 1}, axx[3];
    xf_point(x, (double[3]){0, 0, 0}, about);
    if (dim == 3) ax[1] = -1, ax[2] = 0;
    xf_dir(x, ax, axx);
    n = put(b, n, cap, "],\"plan\":[{\"move\":[\"plank\",\"block\"],\"grip\":\"plank\",\"path\":[{\"rotate\":%.17g,",
            deg * (dim == 2 && x->R[0][0] * x->R[1][1] - x->R[0][1] * x->R[1][0] < 0 ? -1 : 1));
    if (dim == 2) n = put(b, n, cap, "\"about\":[%.17g,%.17g]}]}]}", about[0], about[1]);
    else
        n = put(b, n, cap, "\"axis\":[%.17g,%.17g,%.17g],\"about\":[%.17g,%.17g,%.17g]}]}]}", axx[0],
                axx[1], axx[2], about[0], about[1], about[2]);
    if (n >= cap) {
        free(b);
        return NULL;
    }
    return b;
}

/* The turn (degrees, unsigned) at which the step becomes unstable, or -1; *slides / *tips say
 * how the block leaves the plank (all its contacts slide / one separates). */
static double onset_deg(const char *json, bool *slides, bool *tips) {
    cnAssembly *a = json ? load_ok(json) : NULL;
    if (!a) return -1;
    cnSimOptions o = cn_sim_options_default();
    cnSimResult r;
    cnDiag d;
    double out = -1;
    *slides = *tips = false;
    if (cn_simulate(a, &o, &r, &d) != CN_OK) {
        fprintf(stderr, "simulate failed: %s\n", d.message);
        cn_test_failures++;
        cn_assembly_free(a);
        return -1;
    }
    const cnStepResult *s = &r.steps[0];
    if (s->status == CN_STEP_UNSTABLE && s->has_onset && !s->onset_after) {
        out = fabs(s->onset_angle) / DEG;
        int block = cn_assembly_find_part(a, "block");
        bool moves = false;
        for (int i = 0; i < s->onset.nmoving; i++) moves |= s->onset.moving[i] == block;
        if (moves && s->onset.contact) {
            *slides = true;
            for (int c = 0; c < s->onset.contacts.count; c++) {
                const cnContact *ct = &s->onset.contacts.items[c];
                if (ct->body1 != block && ct->body2 != block) continue;
                *slides &= s->onset.contact[c].slides || s->onset.contact[c].separates;
                *tips |= s->onset.contact[c].separates;
            }
            if (*tips) *slides = false;
        }
    }
    cn_sim_result_free(&r);
    cn_assembly_free(a);
    return out;
}

static void test_tilted_plank(void) {
    for (int dim = 2; dim <= 3; dim++) {
        double mus[3] = {0.2, 0.5, 0.8};
        for (int i = 0; i < 3; i++) {
            Xf x = xf_identity();
            char *j = tilt_scene(dim, mus[i], 2, 1, 60, &x);
            bool sl, tp;
            double th = onset_deg(j, &sl, &tp);
            free(j);
            CHECK_MSG(fabs(th - atan(mus[i]) / DEG) < 1e-3 && sl,
                      "%d-D mu %g: slides at %.6f deg, expected atan(mu) = %.6f", dim, mus[i], th,
                      atan(mus[i]) / DEG);
        }
        /* a tall block with much friction tips instead: its centre passes the lower corner at
         * tan(theta) = w / h */
        Xf x = xf_identity();
        char *j = tilt_scene(dim, 2.0, 1, 3, 60, &x);
        bool sl, tp;
        double th = onset_deg(j, &sl, &tp);
        free(j);
        CHECK_MSG(fabs(th - atan(1.0 / 3) / DEG) < 1e-3 && tp,
                  "%d-D tall block: tips at %.6f deg, expected atan(1/3) = %.6f", dim, th, atan(1.0 / 3) / DEG);
        /* turned less than that: stable */
        x = xf_identity();
        j = tilt_scene(dim, 0.5, 2, 1, 20, &x);
        th = onset_deg(j, &sl, &tp);
        free(j);
        CHECK_MSG(th < 0, "%d-D: a 20 deg tilt at mu 0.5 should keep the block, got onset %.6f", dim, th);
    }
}

/* The same onsets after rotating, translating and scaling the whole file and reversing its
 * parts (2-D: also mirrored, which turns the other way). */
static void test_turn_invariance(void) {
    unsigned seed = 7;
    for (int t = 0; t < 12; t++) {
        int dim = t % 2 ? 3 : 2;
        Xf x = xf_identity();
        double ang = (double)(rand_r(&seed) % 3600) / 10 * DEG;
        if (dim == 2) {
            double sgn = t % 4 == 2 ? -1 : 1; /* a mirror image */
            x.R[0][0] = cos(ang), x.R[0][1] = -sin(ang) * sgn;
            x.R[1][0] = sin(ang), x.R[1][1] = cos(ang) * sgn;
        } else {
            double u[3] = {rand_r(&seed) % 100 - 50.0, rand_r(&seed) % 100 - 50.0, rand_r(&seed) % 100 + 1.0};
            cnPose p = cn_pose_rotation(u, ang, (double[3]){0, 0, 0});
            cn_pose_matrix(&p, x.R);
        }
        x.s = t % 3 == 0 ? 1e-3 : t % 3 == 1 ? 7.5 : 1;
        x.T[0] = (rand_r(&seed) % 2000 - 1000.0) * x.s;
        x.T[1] = (rand_r(&seed) % 2000 - 1000.0) * x.s;
        x.T[2] = dim == 3 ? (rand_r(&seed) % 2000 - 1000.0) * x.s : 0;
        x.reverse = t % 3 != 2;
        double mu = 0.3 + 0.1 * (t % 4);
        char *j = tilt_scene(dim, mu, 2, 1, 60, &x);
        bool sl, tp;
        double th = onset_deg(j, &sl, &tp);
        free(j);
        CHECK_MSG(fabs(th - atan(mu) / DEG) < 1e-3 && sl,
                  "case %d (%d-D, turned %.1f deg, scale %g, moved (%g, %g, %g)%s): slides at %.6f, expected %.6f",
                  t, dim, ang / DEG, x.s, x.T[0], x.T[1], x.T[2], x.reverse ? ", parts reversed" : "",
                  th, atan(mu) / DEG);
    }
}

/* A block [0, 2] x [0, 1] lifted by 3, then turned clockwise about its lower left corner: its
 * upper right corner (relative (2, 1)) reaches x = 2 cos(t) + sin(t); a wall at x = wx is met at
 * t = atan(1/2) - acos(wx / sqrt(5)). A move along x instead meets it after wx - 2. */
static void test_turn_into_wall(void) {
    double wx = 2.1;
    const char *paths[2] = {"[[0,3],{\"rotate\":-90,\"about\":[0,3]}]", "[[0,3],[1,0]]"};
    for (int k = 0; k < 2; k++) {
        char j[1024];
        snprintf(j, sizeof j,
                 "{\"dimension\":2,\"parts\":[{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-4,-1],[12,-1],[12,0],[-4,0]]},"
                 "{\"name\":\"wall\",\"fixed\":true,\"polygon\":[[%g,0],[3,0],[3,6],[%g,6]]},"
                 "{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]}],"
                 "\"plan\":[{\"move\":\"A\",\"path\":%s}]}",
                 wx, wx, paths[k]);
        cnAssembly *a = load_ok(j);
        if (!a) continue;
        cnSimOptions o = cn_sim_options_default();
        cnSimResult r;
        cnDiag d;
        CHECK(cn_simulate(a, &o, &r, &d) == CN_OK);
        const cnStepResult *s = &r.steps[0];
        CHECK(s->status == CN_STEP_INFEASIBLE && s->blocking_part == cn_assembly_find_part(a, "wall"));
        if (k == 0) {
            double want = (atan(0.5) - acos(wx / sqrt(5.0))) / DEG;
            CHECK_MSG(fabs(-s->onset_angle / DEG - want) < 1e-3, "turned into the wall at %.6f deg, expected %.6f",
                      -s->onset_angle / DEG, want);
            /* the reported displacement is that of the centre of mass (1, 0.5) */
            double t = s->onset_angle, cx = cos(t) - 0.5 * sin(t), cy = sin(t) + 0.5 * cos(t) + 3;
            CHECK_NEAR(s->onset_disp[0], cx - 1, 1e-6);
            CHECK_NEAR(s->onset_disp[1], cy - 0.5, 1e-6);
        } else {
            CHECK_NEAR(s->onset_distance, 3 + wx - 2, 1e-5);
        }
        cn_sim_result_free(&r);
        cn_assembly_free(a);
    }
}

void test_motion(void) {
    test_pose_algebra();
    test_tilted_plank();
    test_turn_invariance();
    test_turn_into_wall();
}
