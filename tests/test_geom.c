/* Mass properties and hulls against closed-form answers. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "pieces.h"

static void test_polygon_mass(void) {
    /* 2 x 1 rectangle, density 3: m = 6, com (1, 0.5), I = m (a^2 + b^2) / 12 = 6 * 5 / 12 */
    cnAssembly *a = load_ok("{\"dimension\":2,\"density\":3,\"parts\":[{\"name\":\"A\",\"polygon\":"
                            "[[0,0],[2,0],[2,1],[0,1]]}]}");
    if (!a) return;
    const cnPart *p = &a->parts[0];
    CHECK_NEAR(p->size, 2, 1e-12);
    CHECK_NEAR(p->mass, 6, 1e-12);
    CHECK_NEAR(p->com[0], 1, 1e-12);
    CHECK_NEAR(p->com[1], 0.5, 1e-12);
    CHECK_NEAR(p->inertia[2][2], 6.0 * 5 / 12, 1e-12);
    cn_assembly_free(a);
    /* clockwise input, far from the origin, right triangle legs 3 and 4: area 6, com at
     * (1, 4/3) from the right angle; polar moment about com = m (a^2 + b^2) / 18 */
    a = load_ok("{\"dimension\":2,\"parts\":[{\"name\":\"T\",\"polygon\":"
                "[[1000,1000],[1000,1004],[1003,1000]]}]}");
    if (!a) return;
    p = &a->parts[0];
    CHECK_NEAR(p->size, 6, 1e-9);
    CHECK_NEAR(p->com[0], 1001, 1e-9);
    CHECK_NEAR(p->com[1], 1000 + 4.0 / 3, 1e-9);
    CHECK_NEAR(p->inertia[2][2], 6.0 * 25 / 18, 1e-7);
    /* stored counter-clockwise */
    const cnPiece *pc = &p->pieces[0];
    double area2 = 0;
    for (int i = 0; i < 3; i++) {
        const double *u = pc->verts[i], *v = pc->verts[(i + 1) % 3];
        area2 += u[0] * v[1] - u[1] * v[0];
    }
    CHECK(area2 > 0);
    cn_assembly_free(a);
    /* a part of two pieces (an L: 2 x 1 and 1 x 1 on it) 1e6 from the origin keeps its inertia
     * to 1e-9 (moments about the origin kept only about 4 digits of it). About the com
     * (1.5 - 1/6... computed): pieces' own moments plus the parallel-axis terms */
    for (int far = 0; far < 2; far++) {
        double o = far ? 1e6 : 0;
        char js[512];
        snprintf(js, sizeof js, "{\"dimension\":2,\"parts\":[{\"name\":\"L\",\"polygons\":["
                 "[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]],"
                 "[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]]]}]}",
                 o, o, o + 2, o, o + 2, o + 1, o, o + 1, o, o + 1, o + 1, o + 1, o + 1, o + 2, o, o + 2);
        a = load_ok(js);
        if (!a) return;
        p = &a->parts[0];
        /* com: (2 * (1, 0.5) + 1 * (0.5, 1.5)) / 3 = (5/6, 5/6) */
        double cx = 5.0 / 6, cy = 5.0 / 6;
        double I = 2 * 5.0 / 12 + 2 * ((1 - cx) * (1 - cx) + (0.5 - cy) * (0.5 - cy)) +
                   1 * 2.0 / 12 + 1 * ((0.5 - cx) * (0.5 - cx) + (1.5 - cy) * (1.5 - cy));
        CHECK_NEAR(p->com[0] - o, cx, 1e-9);
        CHECK_NEAR(p->com[1] - o, cy, 1e-9);
        CHECK_MSG(fabs(p->inertia[2][2] - I) < 1e-9 * I, "L at %g: inertia %.17g, want %.17g", o, p->inertia[2][2], I);
        cn_assembly_free(a);
    }
    /* composite L: [0,1]x[0,3] and [1,4]x[0,1]: area 6, com ((0.5*3 + 2.5*3)/6, (1.5*3+0.5*3)/6) */
    a = load_ok("{\"dimension\":2,\"parts\":[{\"name\":\"L\",\"polygons\":"
                "[[[0,0],[1,0],[1,3],[0,3]],[[1,0],[4,0],[4,1],[1,1]]]}]}");
    if (!a) return;
    p = &a->parts[0];
    CHECK_NEAR(p->size, 6, 1e-12);
    CHECK_NEAR(p->com[0], 1.5, 1e-12);
    CHECK_NEAR(p->com[1], 1.0, 1e-12);
    /* parallel axis: each piece I_c = 3 * (1 + 9) / 12 = 2.5, offsets (1, 0.5) and (1, 0.5)
     * from the com: d^2 = 1.25 each -> I = 2 * (2.5 + 3 * 1.25) */
    CHECK_NEAR(p->inertia[2][2], 2 * (2.5 + 3 * 1.25), 1e-12);
    cn_assembly_free(a);
}

static void test_box_mass(void) {
    cnAssembly *a = load_ok("{\"dimension\":3,\"parts\":[{\"name\":\"B\",\"mass\":12,\"box\":"
                            "{\"min\":[1,2,3],\"max\":[3,5,7]}}]}");
    if (!a) return;
    const cnPart *p = &a->parts[0];
    CHECK_NEAR(p->size, 24, 1e-12);
    CHECK_NEAR(p->mass, 12, 1e-12);
    CHECK_NEAR(p->com[0], 2, 1e-12);
    CHECK_NEAR(p->com[1], 3.5, 1e-12);
    CHECK_NEAR(p->com[2], 5, 1e-12);
    /* I_xx = m (b^2 + c^2) / 12 with sides a = 2, b = 3, c = 4 */
    CHECK_NEAR(p->inertia[0][0], 12 * (9 + 16) / 12.0, 1e-10);
    CHECK_NEAR(p->inertia[1][1], 12 * (4 + 16) / 12.0, 1e-10);
    CHECK_NEAR(p->inertia[2][2], 12 * (4 + 9) / 12.0, 1e-10);
    CHECK_NEAR(p->inertia[0][1], 0, 1e-10);
    const cnPiece *pc = &p->pieces[0];
    CHECK(pc->nverts == 8);
    CHECK(pc->nfaces == 6);
    CHECK(pc->nedges == 12);
    for (int f = 0; f < pc->nfaces; f++) CHECK(pc->faces[f].nverts == 4);
    cn_assembly_free(a);
}

static void test_hull_tetra(void) {
    /* unit tetrahedron plus interior and coplanar points: volume 1/6, com (1/4,1/4,1/4);
     * I_xx about com = m/10 * ... use the known covariance: for the unit corner tetrahedron,
     * integral of x^2 = 1/60, of x y = 1/120 */
    cnAssembly *a = load_ok("{\"dimension\":3,\"parts\":[{\"name\":\"T\",\"hull\":"
                            "[[0,0,0],[1,0,0],[0,1,0],[0,0,1],[0.1,0.1,0.1],[0.5,0.5,0],"
                            "[0.25,0,0]]}]}");
    if (!a) return;
    const cnPart *p = &a->parts[0];
    CHECK_NEAR(p->size, 1.0 / 6, 1e-12);
    for (int k = 0; k < 3; k++) CHECK_NEAR(p->com[k], 0.25, 1e-12);
    double V = 1.0 / 6, cxx = 1.0 / 60 - V / 16, cxy = 1.0 / 120 - V / 16;
    CHECK_NEAR(p->inertia[0][0], 2 * cxx, 1e-12);
    CHECK_NEAR(p->inertia[0][1], -cxy, 1e-12);
    const cnPiece *pc = &p->pieces[0];
    CHECK(pc->nverts == 4);
    CHECK(pc->nfaces == 4);
    CHECK(pc->nedges == 6);
    /* every face normal points away from the centroid */
    for (int f = 0; f < pc->nfaces; f++)
        CHECK(cn_dot3(pc->faces[f].normal, p->com) < pc->faces[f].offset);
    cn_assembly_free(a);
}

/* Random point clouds: Euler V - E + F = 2, every vertex inside every face's half-space, and
 * the volume equals the sum over faces of (offset * area) / 3. */
static void test_hull_random(void) {
    cnRng r = {99};
    for (int t = 0; t < 50; t++) {
        double pts[40][3];
        int n = 4 + (int)(cn_rng_uniform(&r) * 36);
        for (int i = 0; i < n; i++)
            for (int k = 0; k < 3; k++) pts[i][k] = cn_rng_range(&r, -1, 1);
        cnPiece pc;
        cnDiag d;
        if (cn_hull3_build((const double(*)[3])pts, n, &pc, &d) != CN_OK) continue;
        CHECK_MSG(pc.nverts - pc.nedges + pc.nfaces == 2, "V %d E %d F %d", pc.nverts, pc.nedges,
                  pc.nfaces);
        double vol = 0;
        for (int f = 0; f < pc.nfaces; f++) {
            const cnFace *F = &pc.faces[f];
            for (int v = 0; v < pc.nverts; v++)
                CHECK(cn_dot3(F->normal, pc.verts[v]) <= F->offset + 1e-9);
            double area[3] = {0, 0, 0};
            for (int i = 0; i < F->nverts; i++) {
                double c[3];
                cn_cross3(pc.verts[F->verts[i]], pc.verts[F->verts[(i + 1) % F->nverts]], c);
                cn_add3(area, c, area);
            }
            vol += F->offset * cn_dot3(area, F->normal) / 2 / 3;
        }
        double s, first[3], second[3][3];
        cn_mass_piece(&pc, 3, NULL, &s, first, second);
        CHECK_NEAR(s, vol, 1e-10);
        cn_piece_free(&pc);
    }
}

/* A prism whose caps are regular 3,000-gons (6,000 points, past the joggled hull's threshold):
 * two caps and 3,000 rectangles, every point within 1e-9 of the hull's boundary or a vertex of
 * it, and the volume of the polygon times the height (computed here). */
static void test_hull_cocircular(void) {
    int m = 3000, n = 2 * m;
    double(*pts)[3] = malloc(sizeof(double[3]) * (size_t)n);
    if (!pts) return;
    for (int i = 0; i < m; i++)
        for (int z = 0; z < 2; z++) {
            double a = 2 * 3.141592653589793 * i / m;
            pts[2 * i + z][0] = cos(a), pts[2 * i + z][1] = sin(a), pts[2 * i + z][2] = 0.5 * z;
        }
    cnPiece pc;
    cnDiag d;
    CHECK(cn_hull3_build((const double(*)[3])pts, n, &pc, &d) == CN_OK);
    int caps = 0;
    for (int f = 0; f < pc.nfaces; f++) caps += fabs(pc.faces[f].normal[2]) > 0.5;
    CHECK_MSG(caps == 2 && pc.nfaces == m + 2 && pc.nverts - pc.nedges + pc.nfaces == 2,
              "caps %d faces %d V %d E %d", caps, pc.nfaces, pc.nverts, pc.nedges);
    CHECK_MSG(pc.nverts >= n - 10, "%d of %d points are vertices", pc.nverts, n);
    double s, first[3], second[3][3];
    cn_mass_piece(&pc, 3, NULL, &s, first, second);
    CHECK_NEAR(s, 0.5 * 0.5 * m * sin(2 * 3.141592653589793 / m), 1e-9);
    cn_piece_free(&pc);
    /* the same points twice: one vertex each (joggled apart, a duplicate was a vertex of its own) */
    double(*twice)[3] = malloc(sizeof(double[3]) * (size_t)(2 * n));
    if (twice) {
        memcpy(twice, pts, sizeof(double[3]) * (size_t)n);
        memcpy(twice + n, pts, sizeof(double[3]) * (size_t)n);
        CHECK(cn_hull3_build((const double(*)[3])twice, 2 * n, &pc, &d) == CN_OK);
        CHECK_MSG(pc.nverts <= n && pc.nfaces == m + 2, "V %d F %d", pc.nverts, pc.nfaces);
        cn_piece_free(&pc);
        free(twice);
    }
    /* a 6,000-gon (coplanar, no duplicates): no volume, as without the joggle */
    for (int i = 0; i < n; i++)
        pts[i][0] = cos(2 * 3.141592653589793 * i / n), pts[i][1] = sin(2 * 3.141592653589793 * i / n), pts[i][2] = 0;
    CHECK(cn_hull3_build((const double(*)[3])pts, n, &pc, &d) == CN_ERR_INPUT);
    free(pts);
}

/* A non-convex "polygon" split into convex pieces, judged on its own terms: every piece convex
 * and counter-clockwise, the pieces' areas adding up to the outline's (shoelace, computed here),
 * every outline point in some piece with its own number, at most 2 r + 1 pieces (r reflex
 * points: Hertel-Mehlhorn's bound), and the part's centre the outline's. Random star-shaped
 * outlines (sorted angles, random radii: simple), combs and outlines with points on straight
 * runs. */
static void check_split(double (*pt)[2], int n, const char *what) {
    size_t cap = 64 + (size_t)n * 60;
    char *j = malloc(cap);
    if (!j) return;
    int k = snprintf(j, cap, "{\"dimension\":2,\"parts\":[{\"name\":\"P\",\"polygon\":[");
    for (int i = 0; i < n; i++) k += snprintf(j + k, cap - (size_t)k, "%s[%.17g,%.17g]", i ? "," : "", pt[i][0], pt[i][1]);
    snprintf(j + k, cap - (size_t)k, "]}]}");
    cnAssembly *a = load_ok(j);
    free(j);
    if (!a) {
        fprintf(stderr, "  (%s)\n", what);
        return;
    }
    const cnPart *p = &a->parts[0];
    double area = 0, cx = 0, cy = 0; /* shoelace about point 0 */
    int reflex = 0;
    for (int i = 0; i < n; i++) {
        const double *u = pt[i], *v = pt[(i + 1) % n], *w = NULL;
        double cr = (u[0] - pt[0][0]) * (v[1] - pt[0][1]) - (v[0] - pt[0][0]) * (u[1] - pt[0][1]);
        area += cr / 2;
        cx += cr * (u[0] + v[0] - 2 * pt[0][0]) / 6, cy += cr * (u[1] + v[1] - 2 * pt[0][1]) / 6;
        (void)w;
    }
    for (int i = 0; i < n; i++) { /* reflex: turning against the outline's orientation */
        const double *u = pt[i], *v = pt[(i + 1) % n], *w = pt[(i + 2) % n];
        double turn = (v[0] - u[0]) * (w[1] - v[1]) - (v[1] - u[1]) * (w[0] - v[0]);
        double l = hypot(v[0] - u[0], v[1] - u[1]) * hypot(w[0] - v[0], w[1] - v[1]);
        if (turn * (area > 0 ? 1 : -1) < -1e-9 * l) reflex++; /* the loader's convexity test */
    }
    cx = cx / area + pt[0][0], cy = cy / area + pt[0][1];
    if (reflex == 0) { /* convex after all: one piece, numbered in turn */
        CHECK_MSG(p->npieces == 1 && p->noutline == 0 && p->nnumbers == n, "%s: convex, %d pieces", what, p->npieces);
        cn_assembly_free(a);
        return;
    }
    double sum = 0;
    bool *seen = calloc((size_t)n, 1), convex = true, numbered = true;
    for (int q = 0; q < p->npieces; q++) {
        const cnPiece *pc = &p->pieces[q];
        double a2 = 0;
        for (int v = 0; v < pc->nverts; v++) {
            const double *x0 = pc->verts[v], *x1 = pc->verts[(v + 1) % pc->nverts], *x2 = pc->verts[(v + 2) % pc->nverts];
            a2 += (x0[0] - pc->verts[0][0]) * (x1[1] - pc->verts[0][1]) - (x1[0] - pc->verts[0][0]) * (x0[1] - pc->verts[0][1]);
            double l = hypot(x1[0] - x0[0], x1[1] - x0[1]) * hypot(x2[0] - x1[0], x2[1] - x1[1]);
            if ((x1[0] - x0[0]) * (x2[1] - x1[1]) - (x1[1] - x0[1]) * (x2[0] - x1[0]) < -1e-9 * l) convex = false;
            int o = pc->vnum ? pc->vnum[v] : -1;
            int at = area < 0 ? n - 1 - o : o; /* a clockwise outline is numbered reversed */
            if (o < 0 || o >= n || pc->verts[v][0] != pt[at][0] || pc->verts[v][1] != pt[at][1]) numbered = false;
            else if (seen) seen[o] = true;
        }
        sum += a2 / 2;
    }
    int missing = 0;
    for (int i = 0; seen && i < n; i++) missing += !seen[i];
    free(seen);
    CHECK_MSG(convex && numbered && missing == 0, "%s: convex %d, numbered %d, %d points in no piece", what, convex, numbered, missing);
    CHECK_MSG(fabs(sum - fabs(area)) <= 1e-9 * fabs(area), "%s: pieces' area %.17g, outline's %.17g", what, sum, fabs(area));
    CHECK_MSG(p->npieces <= 2 * reflex + 1, "%s: %d pieces for %d reflex points", what, p->npieces, reflex);
    CHECK_MSG(hypot(p->com[0] - cx, p->com[1] - cy) <= 1e-9 * sqrt(fabs(area)), "%s: centre (%g, %g), outline's (%g, %g)", what,
              p->com[0], p->com[1], cx, cy);
    CHECK(p->noutline == n && p->nnumbers == n);
    cn_assembly_free(a);
}

static void test_polygon_split(void) {
    double pt[400][2];
    unsigned seed = 12345;
#define RND() ((seed = seed * 1103515245u + 12345u) / 4294967296.0)
    for (int t = 0; t < 60; t++) { /* star-shaped: simple, reflex points where the radius dips */
        int n = 5 + t * 5 % 200;
        double th[400];
        for (int i = 0; i < n; i++) th[i] = 2 * 3.14159265358979 * (i + 0.2 + 0.6 * RND()) / n;
        for (int i = 0; i < n; i++) {
            double r = 1 + 3 * RND();
            pt[i][0] = 100 * (t % 3) + r * cos(th[i]), pt[i][1] = -50 + r * sin(th[i]);
        }
        if (t % 2) /* clockwise as well */
            for (int i = 0, j2 = n - 1; i < j2; i++, j2--) {
                double x = pt[i][0], y = pt[i][1];
                pt[i][0] = pt[j2][0], pt[i][1] = pt[j2][1], pt[j2][0] = x, pt[j2][1] = y;
            }
        char what[64];
        snprintf(what, sizeof what, "star %d (%d points)", t, n);
        check_split(pt, n, what);
    }
    /* a comb: k + 1 teeth on a base (2 k reflex points) */
    for (int k = 1; k <= 40; k += 13) {
        int n = 0;
        pt[n][0] = 0, pt[n++][1] = 0;
        pt[n][0] = 2 * k + 1, pt[n++][1] = 0;
        for (int x = 2 * k + 1; x > 0; x -= 2) { /* the top, right to left: a tooth, then a gap */
            pt[n][0] = x, pt[n++][1] = 3;
            pt[n][0] = x - 1, pt[n++][1] = 3;
            if (x - 1 > 0) {
                pt[n][0] = x - 1, pt[n++][1] = 1;
                pt[n][0] = x - 2, pt[n++][1] = 1;
            }
        }
        char what[64];
        snprintf(what, sizeof what, "comb of %d teeth", k + 1);
        check_split(pt, n, what);
    }
    /* an L with points on its straight runs (each must stay in a piece, numbered) */
    double l[][2] = {{0, 0}, {0.5, 0}, {1, 0}, {1, 1}, {1, 2}, {1, 3}, {2, 3}, {2.5, 3}, {2.5, 4}, {1, 4}, {0, 4}, {0, 2}};
    check_split(l, 12, "L with points on its sides");
    /* a block whose top sags gently (1 %, 1e-4 and 1e-7 of its length) over many points:
       neighbours nearly in line, a long run must not drift off its chord */
    static double sag[1010][2];
    double sags[3] = {1e-2, 1e-4, 1e-7};
    for (int k = 0; k < 3; k++) {
        int m = 1000;
        sag[0][0] = 0, sag[0][1] = 0, sag[1][0] = 1, sag[1][1] = 0;
        for (int i = 0; i < m; i++) {
            double x = 1 - (double)i / (m - 1);
            sag[2 + i][0] = x, sag[2 + i][1] = 0.5 - sags[k] * sin(3.14159265358979 * x);
        }
        char what[64];
        snprintf(what, sizeof what, "a block sagging by %g", sags[k]);
        check_split(sag, m + 2, what);
    }
    /* a U */
    double u[][2] = {{0, 0}, {3, 0}, {3, 3}, {2, 3}, {2, 1}, {1, 1}, {1, 3}, {0, 3}};
    check_split(u, 8, "U");
#undef RND
}

void test_geom(void) {
    test_polygon_split();
    test_polygon_mass();
    test_box_mass();
    test_hull_tetra();
    test_hull_random();
    test_hull_cocircular();
}
