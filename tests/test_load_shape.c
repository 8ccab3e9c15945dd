/* Unit tests of src/io/load_shape.c: what each shape a part may have reads into, against its
 * geometry by hand (test_load checks the refusals, test_io the splitting itself). Checked: an
 * L-shaped polygon, not convex, split into convex pieces that keep its area (3) and its outline
 * (6 corners, counter-clockwise, numbered as written), a clockwise square turned counter-clockwise;
 * "polygons" as written, one piece each; a box (8 corners, 6 faces, volume 6, its bounding box);
 * a hull of a cube's corners with interior points, which add nothing (volume 1); "hulls" as
 * pieces (volume 2); a box turned 90 degrees about z and moved, its bounding box and centre by
 * hand; the density a part gives and the mass it makes. */
#include <math.h>

#include "helpers.h"

#define NEAR(x, y) (fabs((double)(x) - (double)(y)) <= 1e-9 * fmax(1, fabs((double)(y))))

static const cnPart *part(const cnAssembly *a, const char *name) {
    int i = cn_assembly_find_part(a, name);
    CHECK_MSG(i >= 0, "no part %s", name);
    return i >= 0 ? &a->parts[i] : NULL;
}

/* Twice the signed area of a loop. */
static double loop_area2(const double (*v)[3], int n) {
    double s = 0;
    for (int i = 0; i < n; i++) s += v[i][0] * v[(i + 1) % n][1] - v[(i + 1) % n][0] * v[i][1];
    return s;
}

static void test_2d(void) {
    const char *json =
        "{\"dimension\":2,\"parts\":["
        "{\"name\":\"L\",\"polygon\":[[0,0],[2,0],[2,1],[1,1],[1,2],[0,2]]},"
        "{\"name\":\"cw\",\"polygon\":[[5,0],[5,1],[6,1],[6,0]]},"
        "{\"name\":\"two\",\"density\":2,\"polygons\":[[[8,0],[9,0],[9,1],[8,1]],[[9,0],[11,0],[11,1],[9,1]]]}]}";
    cnAssembly *a = load_ok(json);
    if (!a) return;
    const cnPart *L = part(a, "L"), *cw = part(a, "cw"), *two = part(a, "two");
    if (L) {
        double area = 0;
        for (int s = 0; s < L->npieces; s++) {
            double a2 = loop_area2((const double(*)[3])L->pieces[s].verts, L->pieces[s].nverts);
            CHECK(a2 > 0);
            area += a2 / 2;
        }
        CHECK_MSG(L->npieces >= 2 && NEAR(area, 3) && NEAR(L->size, 3), "%d pieces, area %g", L->npieces, area);
        CHECK(L->noutline == 6 && NEAR(loop_area2((const double(*)[3])L->outline, 6), 6) && L->nnumbers == 6);
        CHECK(NEAR(L->outline[3][0], 1) && NEAR(L->outline[3][1], 1));
        /* the centre of the L: (5/6, 5/6) */
        CHECK(NEAR(L->com[0], 5.0 / 6) && NEAR(L->com[1], 5.0 / 6));
    }
    if (cw) CHECK(cw->npieces == 1 && cw->noutline == 0 && loop_area2((const double(*)[3])cw->pieces[0].verts, 4) > 0);
    if (two) CHECK(two->npieces == 2 && NEAR(two->size, 3) && NEAR(two->mass, 6) && NEAR(two->com[0], (8.5 + 2 * 10) / 3));
    cn_assembly_free(a);
}

static void test_3d(void) {
    const char *json =
        "{\"dimension\":3,\"parts\":["
        "{\"name\":\"box\",\"box\":{\"min\":[0,0,0],\"max\":[1,2,3]}},"
        "{\"name\":\"hull\",\"hull\":[[5,0,0],[6,0,0],[6,1,0],[5,1,0],[5,0,1],[6,0,1],[6,1,1],[5,1,1],"
        "[5.5,0.5,0.5],[5.2,0.3,0.9]]},"
        "{\"name\":\"hulls\",\"hulls\":[[[8,0,0],[9,0,0],[9,1,0],[8,1,0],[8,0,1],[9,0,1],[9,1,1],[8,1,1]],"
        "[[9,0,0],[10,0,0],[10,1,0],[9,1,0],[9,0,1],[10,0,1],[10,1,1],[9,1,1]]]},"
        "{\"name\":\"turned\",\"box\":{\"min\":[0,0,0],\"max\":[2,1,1]},"
        "\"rotation\":{\"axis\":[0,0,1],\"angle\":90},\"position\":[20,0,0]}]}";
    cnAssembly *a = load_ok(json);
    if (!a) return;
    const cnPart *b = part(a, "box"), *h = part(a, "hull"), *hs = part(a, "hulls"), *t = part(a, "turned");
    if (b) {
        CHECK(b->npieces == 1 && b->pieces[0].nverts == 8 && b->pieces[0].nfaces == 6 && NEAR(b->size, 6));
        CHECK(NEAR(b->hi[0], 1) && NEAR(b->hi[1], 2) && NEAR(b->hi[2], 3) && NEAR(b->lo[2], 0));
        CHECK(NEAR(b->com[0], 0.5) && NEAR(b->com[1], 1) && NEAR(b->com[2], 1.5));
        /* a box's inertia about its centre: m (b^2 + c^2) / 12 */
        CHECK(NEAR(b->inertia[0][0], 6 * (4 + 9) / 12.0) && NEAR(b->inertia[0][1], 0));
    }
    if (h) CHECK(h->npieces == 1 && h->pieces[0].nverts == 8 && NEAR(h->size, 1));
    if (hs) CHECK(hs->npieces == 2 && NEAR(hs->size, 2) && NEAR(hs->com[0], 9));
    if (t) {
        /* (x, y) -> (-y, x), then + (20, 0, 0): x in [19, 20], y in [0, 2] */
        CHECK_MSG(NEAR(t->lo[0], 19) && NEAR(t->hi[0], 20) && NEAR(t->lo[1], 0) && NEAR(t->hi[1], 2),
                  "turned box [%g, %g] x [%g, %g]", t->lo[0], t->hi[0], t->lo[1], t->hi[1]);
        CHECK(NEAR(t->com[0], 19.5) && NEAR(t->com[1], 1) && NEAR(t->com[2], 0.5) && NEAR(t->size, 2));
    }
    cn_assembly_free(a);
}

void test_load_shape(void) {
    test_2d();
    test_3d();
}
