/* Mechanics against hand-derived rigid-body quantities: mass, inertia, gravity, Jacobian rows,
 * the response to forces, the nominal relative velocity of moved parts. */
#include <math.h>
#include <string.h>

#include "helpers.h"
#include "mech.h"

#define GROUND "{\"name\":\"g\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]}"

/* A 2 x 1 block of density 1 (mass 2) with its centre at (1, 0.5): I = m (w^2 + h^2) / 12. */
static void test_mass_and_gravity_2d(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"gravity\":[0,-10],\"parts\":[" GROUND ","
                            "{\"name\":\"B\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]}]}");
    if (!a) return;
    cnMech m;
    cnDiag d;
    CHECK(cn_mech_build(a, NULL, NULL, &m, &d) == CN_OK);
    CHECK(m.nb == 1 && m.nd == 3 && m.dim == 2);
    CHECK(m.body_of_part[cn_assembly_find_part(a, "g")] == -1);
    CHECK_NEAR(m.mass[0], 2, 1e-12);
    CHECK_NEAR(m.com[0][0], 1, 1e-12);
    CHECK_NEAR(m.com[0][1], 0.5, 1e-12);
    double I = 2 * (4 + 1) / 12.0;
    CHECK_NEAR(m.inertia[8], I, 1e-12);
    CHECK_NEAR(m.minv[0], 0.5, 1e-12);
    CHECK_NEAR(m.minv[4], 0.5, 1e-12);
    CHECK_NEAR(m.minv[8], 1 / I, 1e-12);
    CHECK_NEAR(m.fext[0], 0, 1e-12);
    CHECK_NEAR(m.fext[1], -20, 1e-12);
    CHECK_NEAR(m.fext[2], 0, 1e-12);
    CHECK_NEAR(m.g, 10, 1e-12);
    CHECK_NEAR(m.radius[0], sqrt(1 + 0.25), 1e-12);
    /* a unit upward force at the corner (2, 0) on B (body2; body1 the ground): the force
     * (0, 1) and the torque r x f = (2 - 1) * 1 = 1 */
    cnJRow row;
    double p[3] = {2, 0, 0}, up[3] = {0, 1, 0};
    int g = cn_assembly_find_part(a, "g"), b = cn_assembly_find_part(a, "B");
    cn_mech_row(&m, g, b, p, up, &row);
    CHECK(row.body[0] == 0 && row.body[1] == -1); /* slot 0: the body pushed along +d */
    CHECK_NEAR(row.c[0][0], 0, 1e-12);
    CHECK_NEAR(row.c[0][1], 1, 1e-12);
    CHECK_NEAR(row.c[0][2], 1, 1e-12);
    CHECK_NEAR(row.u[0][2], 1 / I, 1e-12);
    /* the weight shared by the two bottom corners: no motion; all of it at one corner: B turns */
    cnJRow rows[2];
    double p0[3] = {0, 0, 0};
    cn_mech_row(&m, g, b, p0, up, &rows[0]);
    rows[1] = row;
    double f[2] = {10, 10}, acc[3];
    cn_mech_response(&m, rows, 2, f, acc);
    for (int k = 0; k < 3; k++) CHECK_NEAR(acc[k], 0, 1e-12);
    CHECK(!cn_mech_moves(&m, 0, acc, 1e-6));
    double f1[2] = {0, 20};
    cn_mech_response(&m, rows, 2, f1, acc);
    CHECK_NEAR(acc[1], 0, 1e-12);
    CHECK_NEAR(acc[2], 20 / I, 1e-12); /* torque 20 * 1 */
    CHECK(cn_mech_moves(&m, 0, acc, 1e-6));
    /* kinetic energy form: a^T M a */
    double ma[3];
    double ke = cn_mech_kinetic(&m, acc, ma);
    CHECK_NEAR(ke, I * (20 / I) * (20 / I), 1e-9);
    CHECK_NEAR(ma[2], 20, 1e-12);
    /* relative acceleration at the corner along the normal: omega x r with r = (1, -0.5) */
    CHECK_NEAR(cn_mech_relative(&m, &row, acc), 20 / I * 1, 1e-12);
    cn_mech_free(&m);
    cn_assembly_free(a);
}

/* 3-D: a unit cube of density 2: mass 2, I = m / 6 about each axis; gravity along -z. */
static void test_mass_3d(void) {
    cnAssembly *a = load_ok("{\"dimension\":3,\"gravity\":[0,0,-9.81],\"parts\":["
                            "{\"name\":\"g\",\"fixed\":true,\"box\":{\"min\":[-3,-3,-1],\"max\":[3,3,0]}},"
                            "{\"name\":\"C\",\"density\":2,\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}}]}");
    if (!a) return;
    cnMech m;
    cnDiag d;
    CHECK(cn_mech_build(a, NULL, NULL, &m, &d) == CN_OK);
    CHECK(m.nb == 1 && m.nd == 6);
    CHECK_NEAR(m.mass[0], 2, 1e-12);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) CHECK_NEAR(m.inertia[i * 3 + j], i == j ? 2.0 / 6 : 0, 1e-12);
    CHECK_NEAR(m.fext[2], -2 * 9.81, 1e-12);
    for (int k = 3; k < 6; k++) CHECK_NEAR(m.fext[k], 0, 1e-12);
    /* a unit force along +x at (1, 0.5, 1) (top edge): torque r x f with r = (0.5, 0, 0.5) */
    cnJRow row;
    double p[3] = {1, 0.5, 1}, x[3] = {1, 0, 0};
    cn_mech_row(&m, cn_assembly_find_part(a, "g"), cn_assembly_find_part(a, "C"), p, x, &row);
    double want[6] = {1, 0, 0, 0, 0.5, 0}; /* (0.5,0,0.5) x (1,0,0) = (0, 0.5, 0) */
    for (int k = 0; k < 6; k++) CHECK_NEAR(row.c[0][k], want[k], 1e-12);
    cn_mech_free(&m);
    cn_assembly_free(a);
}

/* A held part turning about a point: the nominal velocity at a contact is v + w x (x - about);
 * against a still part the relative velocity is that, its sign by who is part 2. */
static void test_nominal_twist(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"parts\":[" GROUND ","
                            "{\"name\":\"H\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
                            "{\"name\":\"S\",\"polygon\":[[1,0],[2,0],[2,1],[1,1]]}]}");
    if (!a) return;
    int h = cn_assembly_find_part(a, "H"), s = cn_assembly_find_part(a, "S");
    unsigned char role[3] = {0, 0, 0};
    role[h] = CN_ROLE_HELD;
    cnMotion mo;
    memset(&mo, 0, sizeof mo);
    mo.role = role;
    mo.twist.v[0] = 0.5;
    mo.twist.w[2] = 2;             /* counter-clockwise, 2 rad per unit time */
    mo.twist.about[0] = 0;         /* about the origin */
    mo.speed = 1;
    mo.dt = 1;
    cnMech m;
    cnDiag d;
    CHECK(cn_mech_build(a, NULL, &mo, &m, &d) == CN_OK);
    CHECK(m.body_of_part[h] == -1); /* held: kinematic, not a body */
    double x[3] = {1, 0.5, 0}, ex[3] = {1, 0, 0}, ey[3] = {0, 1, 0};
    /* velocity of H at (1, 0.5): (0.5, 0) + 2 z x (1, 0.5) = (0.5 - 1, 2) */
    CHECK_NEAR(cn_mech_nominal(&m, s, h, x, ex), -0.5, 1e-12);
    CHECK_NEAR(cn_mech_nominal(&m, s, h, x, ey), 2, 1e-12);
    CHECK_NEAR(cn_mech_nominal(&m, h, s, x, ex), 0.5, 1e-12);
    cn_mech_free(&m);
    cn_assembly_free(a);
}

void test_mech(void) {
    test_mass_and_gravity_2d();
    test_mass_3d();
    test_nominal_twist();
}
