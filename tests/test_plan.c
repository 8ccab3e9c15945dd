/* Removal directions against hand-computed arcs, and the planner on small known cases. */
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "pieces.h"

static double deg(double r) { return r * 180 / CN_PI; }

/* The free arcs of part `name`, as degrees; returns the count. */
static int arcs_of(const char *json, const char *name, double out[][2]) {
    cnAssembly *a = load_ok(json);
    if (!a) return -1;
    unsigned char *mv = calloc((size_t)a->nparts, 1);
    mv[cn_assembly_find_part(a, name)] = 1;
    cnArc *arcs;
    int n;
    cnDiag d;
    CHECK(cn_directions2(a, NULL, mv, &arcs, &n, NULL, NULL, &d) == CN_OK);
    for (int i = 0; i < n; i++) out[i][0] = deg(arcs[i].from), out[i][1] = deg(arcs[i].to);
    cn_free_arcs(arcs);
    free(mv);
    cn_assembly_free(a);
    return n;
}

#define T2 "{\"name\":\"t\",\"fixed\":true,\"polygon\":[[-10,-1],[10,-1],[10,0],[-10,0]]}"
#define BOX "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]}"

static void test_arcs(void) {
    double a[8][2];
    /* on a table: the upper half-plane, ends included */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX "]}", "A", a) == 1);
    CHECK_NEAR(a[0][0], 0, 1e-9);
    CHECK_NEAR(a[0][1], 180, 1e-9);
    /* in a slot (walls touching both sides, taller than the block): straight up only */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                  "{\"name\":\"w1\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,3],[-1,3]]},"
                  "{\"name\":\"w2\",\"fixed\":true,\"polygon\":[[1,0],[2,0],[2,3],[1,3]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 90, 1e-9);
    CHECK_NEAR(a[0][1], 90, 1e-9);
    /* in a corner (wall on the left as tall as the block): [0, 90], plus up-left once above
     * the wall? The wall is 1 tall: leaving up-left hits it, so [0, 90] */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                  "{\"name\":\"w1\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,1],[-1,1]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 0, 1e-9);
    /* the wall's top-right corner (0,1) seen from the block's bottom-left corner (0,0) is
     * straight up, and from the block's bottom-right corner (1,0) at 135 degrees: directions
     * above 135 clear the wall (the block rises faster than it moves left)... the extent of
     * M = wall - block is [90, 180] open, so the free arc ends at 90 */
    CHECK_NEAR(a[0][1], 90, 1e-9);
    /* under a ceiling that touches its top (no table): the lower half-plane, wrapping past 0 */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" BOX ","
                  "{\"name\":\"c\",\"fixed\":true,\"polygon\":[[-5,1],[5,1],[5,2],[-5,2]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 180, 1e-9);
    CHECK_NEAR(a[0][1], 0, 1e-9);
    /* nothing around: every direction (one arc, the whole circle) */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" BOX "]}", "A", a) == 1);
    CHECK_NEAR(a[0][0], 0, 1e-9);
    CHECK_NEAR(a[0][1], 360, 1e-9);
    /* a post of height 1 at distance 2 to the right: directions below atan(1/1) = 45 deg
     * (bottom-right corner (1,0) to the post's top-left corner (2,1)... but the block's top
     * corner (1,1) reaches the post's bottom-left (2,0) going down-right, blocked by the table
     * anyway): free [45, 180] */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                  "{\"name\":\"p\",\"fixed\":true,\"polygon\":[[2,0],[3,0],[3,1],[2,1]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 45, 1e-9);
    CHECK_NEAR(a[0][1], 180, 1e-9);
}

/* The per-direction sweep test agrees with the arcs on many random directions. */
static void test_sweep_agrees(void) {
    const char *json = "{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                       "{\"name\":\"p\",\"fixed\":true,\"polygon\":[[2,0],[3,0],[3,1],[2,1]]},"
                       "{\"name\":\"q\",\"fixed\":true,\"polygon\":[[-3,2],[-2,2],[-2,3],[-3,3]]}]}";
    cnAssembly *a = load_ok(json);
    if (!a) return;
    unsigned char mv[4] = {0, 1, 0, 0};
    cnArc *arcs;
    int n;
    cnDiag d;
    CHECK(cn_directions2(a, NULL, mv, &arcs, &n, NULL, NULL, &d) == CN_OK);
    cnRng r = {31};
    int agree = 0, total = 0;
    for (int i = 0; i < 200; i++) {
        double th = cn_rng_range(&r, 0, 2 * CN_PI);
        bool in = false;
        for (int k = 0; k < n; k++) {
            double len = fmod(arcs[k].to - arcs[k].from + 4 * CN_PI, 2 * CN_PI);
            if (arcs[k].to - arcs[k].from >= 2 * CN_PI) len = 2 * CN_PI;
            double x = fmod(th - arcs[k].from + 4 * CN_PI, 2 * CN_PI);
            if (x <= len + 1e-12) in = true;
        }
        double dir[3] = {cos(th), sin(th), 0};
        bool fr;
        CHECK(cn_direction_free(a, NULL, mv, dir, &fr, &d) == CN_OK);
        total++;
        agree += fr == in;
    }
    CHECK_MSG(agree == total, "arcs and sweeps agree on %d of %d directions", agree, total);
    cn_free_arcs(arcs);
    cn_assembly_free(a);
}

/* cn_free_directions through the public API only, freed with the public cn_directions_free (the
 * header once said cn_free, which callers cannot reach): a block in a slot leaves straight up. */
static void test_free_directions_public(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                            "{\"name\":\"w1\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,3],[-1,3]]},"
                            "{\"name\":\"w2\",\"fixed\":true,\"polygon\":[[1,0],[2,0],[2,3],[1,3]]}]}");
    if (!a) return;
    unsigned char *mv = calloc((size_t)a->nparts, 1);
    mv[cn_assembly_find_part(a, "A")] = 1;
    double(*dirs)[3] = NULL;
    int n = 0;
    cnDiag d;
    CHECK(cn_free_directions(a, NULL, mv, &dirs, &n, &d) == CN_OK);
    CHECK(n >= 1);
    if (n >= 1) {
        CHECK_NEAR(dirs[0][0], 0, 1e-12);
        CHECK_NEAR(dirs[0][1], 1, 1e-12);
    }
    for (int i = 0; i < n; i++) CHECK_MSG(dirs[i][1] > 1 - 1e-9, "direction %d is not up", i);
    cn_directions_free(dirs);
    free(mv);
    cn_assembly_free(a);
}

void test_plan(void) {
    test_arcs();
    test_free_directions_public();
    test_sweep_agrees();
}
