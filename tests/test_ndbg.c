/* The non-directional blocking graph against cells derived by hand, an interlock that only a pair
 * can leave, the rotated assembly's cells, and the exact swept test of cn_direction_free as the
 * reference for every region's direction. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "core.h"

static double deg(double r) { return r * 180 / CN_PI; }

/* Is there an edge part -> blocker (by name) in cell c? */
static bool has_edge(const cnAssembly *a, const cnNdbg *g, int c, const char *part, const char *blocker) {
    int p = cn_assembly_find_part(a, part), b = cn_assembly_find_part(a, blocker);
    for (int k = 0; k < g->cells[c].nedges; k++) {
        const cnNdbgEdge *e = &g->edges[g->cells[c].first + k];
        if (e->part == p && e->blocker == b) return true;
    }
    return false;
}

/* Is part `name` free (no edge from it) in cell c? */
static bool part_free(const cnAssembly *a, const cnNdbg *g, int c, const char *name) {
    int p = cn_assembly_find_part(a, name);
    for (int k = 0; k < g->cells[c].nedges; k++)
        if (g->edges[g->cells[c].first + k].part == p) return false;
    return true;
}

/* The removable sets of cell c as strings "A", "A+B", joined by spaces. */
static void removable_of(const cnAssembly *a, const cnNdbg *g, int c, char *out, size_t size) {
    int *parts, *start, ns;
    cnDiag d;
    out[0] = 0;
    CHECK(cn_ndbg_removable(a, g, c, &parts, &start, &ns, &d) == CN_OK);
    for (int s = 0; s < ns; s++) {
        if (s) strncat(out, " ", size - strlen(out) - 1);
        for (int k = start[s]; k < start[s + 1]; k++) {
            if (k > start[s]) strncat(out, "+", size - strlen(out) - 1);
            strncat(out, a->parts[parts[k]].name, size - strlen(out) - 1);
        }
    }
    cn_free_ints(parts);
    cn_free_ints(start);
}

#define FLOOR2 "{\"name\":\"t\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]}"

/* A 1 x 1 block on the floor of a U channel 3 wide with walls 2 high, the block 1 from each wall.
 * The blocked arcs (the cones of the Minkowski differences): the right wall [3,4]x[0,2] minus the
 * block [1,2]x[0,1] is [1,3]x[-1,2], seen from the origin between its corners (1,-1) and (1,2):
 * (-45, atan2(2,1) = 63.43) degrees; the left wall [-1,0]x[0,2] gives [-3,-1]x[-1,2], between
 * (-1,2) and (-1,-1): (116.57, 225); the floor, touching, the lower half-plane (180, 360). Free:
 * the closed arc [63.43, 116.57], ends included (the block grazes a wall's top corner). */
static void test_channel(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"parts\":[{\"name\":\"U\",\"fixed\":true,\"polygons\":["
                            "[[-1,-1],[4,-1],[4,0],[-1,0]],[[-1,0],[0,0],[0,2],[-1,2]],[[3,0],[4,0],[4,2],[3,2]]]},"
                            "{\"name\":\"A\",\"polygon\":[[1,0],[2,0],[2,1],[1,1]]}]}");
    if (!a) return;
    cnNdbg g;
    cnDiag d;
    CHECK(cn_ndbg_build(a, NULL, NULL, 0, &g, &d) == CN_OK);
    double lo = deg(atan2(2, 1)), hi = deg(atan2(2, -1));
    int nfree = 0, npoints = 0;
    for (int c = 0; c < g.ncells; c++) {
        const cnNdbgCell *C = &g.cells[c];
        if (!part_free(a, &g, c, "A")) {
            CHECK(has_edge(a, &g, c, "A", "U"));
            continue;
        }
        nfree++;
        if (C->dim == 0) {
            npoints++;
            CHECK(fabs(deg(C->from) - lo) < 1e-9 || fabs(deg(C->from) - hi) < 1e-9);
        } else {
            CHECK_NEAR(deg(C->from), lo, 1e-9);
            CHECK_NEAR(deg(C->to), hi, 1e-9);
            CHECK_NEAR(C->dir[1], 1, 1e-12); /* up lies in it: its direction */
        }
    }
    CHECK(nfree == 3 && npoints == 2);
    cn_ndbg_free(&g);
    cn_assembly_free(a);
}

/* Two hooked parts on a floor: A is a post [0,1]x[0,2] with an arm [0,3]x[2,3] over B and a foot
 * [1,2]x[0,0.5] under it; B [1,3]x[0.5,2] fills the gap. Straight up, A's foot runs into B and B
 * into A's arm: neither alone leaves, the pair does. Along +x B slides out between arm and foot
 * (touching both) while A's post runs into B: B alone leaves. */
static void test_interlock(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"parts\":[" FLOOR2 ","
                            "{\"name\":\"A\",\"polygons\":[[[0,0],[1,0],[1,2],[0,2]],[[0,2],[3,2],[3,3],[0,3]],"
                            "[[1,0],[2,0],[2,0.5],[1,0.5]]]},"
                            "{\"name\":\"B\",\"polygon\":[[1,0.5],[3,0.5],[3,2],[1,2]]}]}");
    if (!a) return;
    cnNdbg g;
    cnDiag d;
    char sets[256];
    CHECK(cn_ndbg_build(a, NULL, NULL, 0, &g, &d) == CN_OK);
    int up = cn_ndbg_locate(&g, (double[3]){0, 1, 0});
    CHECK(up >= 0);
    if (up >= 0) {
        CHECK(has_edge(a, &g, up, "A", "B") && has_edge(a, &g, up, "B", "A"));
        CHECK(g.cells[up].nedges == 2);
        removable_of(a, &g, up, sets, sizeof sets);
        CHECK_MSG(!strcmp(sets, "A+B"), "%s", sets);
    }
    int right = cn_ndbg_locate(&g, (double[3]){1, 0, 0});
    CHECK(right >= 0 && g.cells[right].dim == 0);
    if (right >= 0) {
        CHECK(has_edge(a, &g, right, "A", "B") && !has_edge(a, &g, right, "B", "A"));
        removable_of(a, &g, right, sets, sizeof sets);
        CHECK_MSG(!strcmp(sets, "B"), "%s", sets);
    }
    cn_ndbg_free(&g);
    cn_assembly_free(a);
}

#define TABLE3 "{\"name\":\"table\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}}"

/* A block on a table: one circle (the table's top, z = 0); the upper hemisphere and the circle
 * itself are free (lifting, sliding), the lower hemisphere blocked. */
static void test_table(void) {
    cnAssembly *a = load_ok("{\"dimension\":3,\"parts\":[" TABLE3 ",{\"name\":\"A\",\"box\":"
                            "{\"min\":[0,0,0],\"max\":[1,1,1]}}]}");
    if (!a) return;
    cnNdbg g;
    cnDiag d;
    CHECK(cn_ndbg_build(a, NULL, NULL, 0, &g, &d) == CN_OK);
    CHECK(g.ncircles == 1 && g.ncells == 3);
    if (g.ncells == 3) {
        /* up's cell first, then the axes' */
        CHECK(g.cells[0].dim == 2 && g.cells[0].nedges == 0 && g.cells[0].dir[2] == 1);
        CHECK(g.cells[1].dim == 1 && g.cells[1].nedges == 0 && g.cells[1].dir[0] == -1);
        CHECK(g.cells[2].dim == 2 && g.cells[2].nedges == 1 && has_edge(a, &g, 2, "A", "table"));
        CHECK(cn_ndbg_locate(&g, (double[3]){0.6, 0.8, 0}) == 1);
        CHECK(cn_ndbg_locate(&g, (double[3]){0.6, 0, -0.8}) == 2);
    }
    cn_ndbg_free(&g);
    cn_assembly_free(a);
}

/* A peg in a square hole that fits it exactly (the base's walls touch all four sides, its floor
 * the peg's bottom): the one free cell is the single direction straight up, where the circles
 * x = 0 and y = 0 meet; tilted however little, the peg runs into a wall. */
static void test_peg(void) {
    cnAssembly *a = load_ok(
        "{\"dimension\":3,\"parts\":[{\"name\":\"base\",\"fixed\":true,\"hulls\":["
        "[[-2,-2,-1],[2,-2,-1],[2,2,-1],[-2,2,-1],[-2,-2,0],[2,-2,0],[2,2,0],[-2,2,0]],"
        "[[-2,-2,0],[0,-2,0],[0,2,0],[-2,2,0],[-2,-2,2],[0,-2,2],[0,2,2],[-2,2,2]],"
        "[[1,-2,0],[2,-2,0],[2,2,0],[1,2,0],[1,-2,2],[2,-2,2],[2,2,2],[1,2,2]],"
        "[[0,-2,0],[1,-2,0],[1,0,0],[0,0,0],[0,-2,2],[1,-2,2],[1,0,2],[0,0,2]],"
        "[[0,1,0],[1,1,0],[1,2,0],[0,2,0],[0,1,2],[1,1,2],[1,2,2],[0,2,2]]]},"
        "{\"name\":\"peg\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,3]}}]}");
    if (!a) return;
    cnNdbg g;
    cnDiag d;
    CHECK(cn_ndbg_build(a, NULL, NULL, 0, &g, &d) == CN_OK);
    int nfree = 0, at = -1;
    for (int c = 0; c < g.ncells; c++)
        if (g.cells[c].nedges == 0) nfree++, at = c;
    CHECK_MSG(nfree == 1, "%d free cells of %d", nfree, g.ncells);
    if (at >= 0) {
        CHECK(g.cells[at].dim == 0);
        CHECK_NEAR(g.cells[at].dir[2], 1, 1e-12);
    }
    /* the planner's directions: straight up only */
    cn_ndbg_free(&g);
    cn_assembly_free(a);
}

/* The assembly turned about an oblique axis (its coordinates and gravity): as many cells of each
 * kind, and every cell's direction, turned, lies in a cell with the same edges. */
static void rot(double R[3][3], const double x[3], double y[3]) {
    for (int i = 0; i < 3; i++) y[i] = R[i][0] * x[0] + R[i][1] * x[1] + R[i][2] * x[2];
}

static void box_json(char *buf, size_t size, const char *name, bool fixed, const double lo[3],
                     const double hi[3], double R[3][3]) {
    char *p = buf + strlen(buf);
    size_t left = size - strlen(buf);
    int n = snprintf(p, left, "{\"name\":\"%s\",%s\"hull\":[", name, fixed ? "\"fixed\":true," : "");
    for (int v = 0; v < 8; v++) {
        double x[3] = {v & 1 ? hi[0] : lo[0], v & 2 ? hi[1] : lo[1], v & 4 ? hi[2] : lo[2]}, y[3];
        rot(R, x, y);
        n += snprintf(p + n, left - (size_t)n, "%s[%.17g,%.17g,%.17g]", v ? "," : "", y[0], y[1], y[2]);
    }
    snprintf(p + n, left - (size_t)n, "]}");
}

static cnAssembly *stack(double R[3][3]) {
    static char buf[8192];
    double g0[3] = {0, 0, -1}, g[3];
    rot(R, g0, g);
    snprintf(buf, sizeof buf, "{\"dimension\":3,\"gravity\":[%.17g,%.17g,%.17g],\"parts\":[", g[0], g[1], g[2]);
    box_json(buf, sizeof buf, "table", true, (double[3]){-3, -3, -0.5}, (double[3]){3, 3, 0}, R);
    strcat(buf, ",");
    box_json(buf, sizeof buf, "A", false, (double[3]){-1, -1, 0}, (double[3]){1, 1, 1}, R);
    strcat(buf, ",");
    box_json(buf, sizeof buf, "B", false, (double[3]){-0.5, -0.8, 1}, (double[3]){1.5, 0.8, 1.6}, R);
    strcat(buf, ",");
    box_json(buf, sizeof buf, "C", false, (double[3]){0.2, -0.4, 1.6}, (double[3]){1.2, 0.4, 2.2}, R);
    strcat(buf, "]}");
    return load_ok(buf);
}

static void test_rotated(void) {
    double I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, R[3][3];
    double ax[3] = {1, 2, 3}, th = 0.7;
    cn_normalize3(ax);
    double c = cos(th), s = sin(th);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            R[i][j] = (i == j ? c : 0) + (1 - c) * ax[i] * ax[j];
    R[0][1] -= s * ax[2], R[0][2] += s * ax[1], R[1][0] += s * ax[2];
    R[1][2] -= s * ax[0], R[2][0] -= s * ax[1], R[2][1] += s * ax[0];
    cnAssembly *a = stack(I), *b = stack(R);
    if (!a || !b) {
        cn_assembly_free(a);
        cn_assembly_free(b);
        return;
    }
    cnNdbg ga, gb;
    cnDiag d;
    CHECK(cn_ndbg_build(a, NULL, NULL, 0, &ga, &d) == CN_OK);
    CHECK(cn_ndbg_build(b, NULL, NULL, 0, &gb, &d) == CN_OK);
    CHECK(ga.ncircles == gb.ncircles && ga.ncells == gb.ncells && ga.ncells > 100);
    int kinds[2][3] = {{0}}, bad = 0;
    for (int k = 0; k < ga.ncells; k++) kinds[0][ga.cells[k].dim]++;
    for (int k = 0; k < gb.ncells; k++) kinds[1][gb.cells[k].dim]++;
    CHECK(!memcmp(kinds[0], kinds[1], sizeof kinds[0]));
    for (int k = 0; k < ga.ncells; k++) {
        double y[3];
        rot(R, ga.cells[k].dir, y);
        int m = cn_ndbg_locate(&gb, y);
        if (m < 0 || gb.cells[m].dim != ga.cells[k].dim || gb.cells[m].nedges != ga.cells[k].nedges) {
            bad++;
            continue;
        }
        for (int e = 0; e < ga.cells[k].nedges; e++) {
            const cnNdbgEdge *E = &ga.edges[ga.cells[k].first + e];
            if (!has_edge(b, &gb, m, a->parts[E->part].name, a->parts[E->blocker].name)) bad++;
        }
    }
    CHECK_MSG(bad == 0, "%d cells differ once turned", bad);
    cn_ndbg_free(&ga);
    cn_ndbg_free(&gb);
    cn_assembly_free(a);
    cn_assembly_free(b);
}

/* The reference: each part's own graph against the swept test of cn_direction_free, at every
 * region's direction (well inside the cell) and every free cell's direction. */
static void test_against_swept(const char *file) {
    char path[512];
    snprintf(path, sizeof path, "%s/examples/%s", CAIRN_SOURCE_DIR, file);
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_file(path, &a, &d) != CN_OK) {
        CHECK_MSG(false, "%s: %s", path, d.message);
        return;
    }
    unsigned char *mv = calloc((size_t)a->nparts, 1);
    int disagree = 0, tried = 0;
    for (int i = 0; i < a->nreal; i++) {
        if (a->parts[i].fixed) continue;
        memset(mv, 0, (size_t)a->nparts);
        mv[i] = 1;
        cnNdbg g;
        CHECK(cn_ndbg_build(a, NULL, mv, 0, &g, &d) == CN_OK);
        for (int c = 0; c < g.ncells; c++) {
            bool gfree = g.cells[c].nedges == 0, sfree;
            if (g.cells[c].dim != (a->dim == 3 ? 2 : 1) && !gfree) continue;
            CHECK(cn_direction_free(a, NULL, mv, g.cells[c].dir, &sfree, &d) == CN_OK);
            tried++;
            if (gfree != sfree) disagree++;
        }
        cn_ndbg_free(&g);
    }
    CHECK_MSG(disagree == 0 && tried > 0, "%s: %d of %d directions disagree", file, disagree, tried);
    free(mv);
    cn_assembly_free(a);
}

/* Is direction t (radians) in one of the closed arcs, at least margin from every end? -1 when
 * it is within margin of an end (not compared). */
static int in_arcs(const cnArc *arcs, int n, double t, double margin) {
    int in = 0;
    for (int k = 0; k < n; k++) {
        double from = arcs[k].from, len = fmod(arcs[k].to - arcs[k].from + 4 * CN_PI, 2 * CN_PI);
        if (arcs[k].to - arcs[k].from >= 2 * CN_PI - 1e-12) len = 2 * CN_PI;
        double d = fmod(t - from + 4 * CN_PI, 2 * CN_PI);
        if (fabs(d) < margin || fabs(d - len) < margin || fabs(d - 2 * CN_PI) < margin) return -1;
        if (d <= len) in = 1;
    }
    return in;
}

/* The 2-D free arcs (the union of the pieces' blocked arcs, complemented) against the swept test
 * at 720 directions each, on random scenes of turned rectangles around a moving one (up to 40
 * blockers, so hundreds of arcs whose ends cluster) and on two interlocking combs (arcs that
 * meet exactly: single free directions). */
static void test_arcs_against_swept(void) {
    cnRng rng = {4242};
    int disagree = 0, tried = 0;
    for (int trial = 0; trial < 31; trial++) {
        char *j = malloc(65536);
        int len = 0;
        if (trial < 30) {
            int nb = 2 + trial;
            len += sprintf(j + len, "{\"dimension\":2,\"parts\":[");
            for (int b = 0; b <= nb; b++) { /* part 0 moves; the others on a grid around it */
                double cx = b == 0 ? 0 : 3.0 * ((b - 1) % 7 - 3), cy = b == 0 ? 0 : 3.0 * ((b - 1) / 7 + 1) * (b % 2 ? 1 : -1);
                double w = cn_rng_range(&rng, 0.3, 1.2), h = cn_rng_range(&rng, 0.3, 1.2), th = cn_rng_range(&rng, 0, CN_PI);
                len += sprintf(j + len, "%s{\"name\":\"P%d\",%s\"polygon\":[", b ? "," : "", b, b ? "\"fixed\":true," : "");
                for (int v = 0; v < 4; v++) {
                    double x = (v == 1 || v == 2 ? w : -w), y = (v >= 2 ? h : -h);
                    len += sprintf(j + len, "%s[%.17g,%.17g]", v ? "," : "", cx + x * cos(th) - y * sin(th),
                                   cy + x * sin(th) + y * cos(th));
                }
                len += sprintf(j + len, "]}");
            }
            len += sprintf(j + len, "]}");
        } else { /* combs: 12 teeth each, B's between A's, touching their sides */
            len += sprintf(j + len, "{\"dimension\":2,\"parts\":[{\"name\":\"B\",\"polygon\":[[24,5.5],[0,5.5],[0,4.5]");
            for (int k = 0; k < 12; k++)
                len += sprintf(j + len, ",[%d,4.5],[%d,1.5],[%d,1.5],[%d,4.5]", 2 * k + 1, 2 * k + 1, 2 * k + 2, 2 * k + 2);
            len += sprintf(j + len, "]},{\"name\":\"A\",\"fixed\":true,\"polygon\":[[0,0],[24,0],[24,1]");
            for (int k = 11; k >= 0; k--)
                len += sprintf(j + len, ",[%d,1],[%d,4],[%d,4],[%d,1]", 2 * k + 1, 2 * k + 1, 2 * k, 2 * k);
            len += sprintf(j + len, "]}]}");
        }
        cnAssembly *a = load_ok(j);
        free(j);
        if (!a) continue;
        unsigned char *mv = calloc((size_t)a->nparts, 1);
        mv[0] = 1;
        cnArc *arcs = NULL;
        int narcs = 0;
        cnDiag d;
        CHECK(cn_directions2(a, NULL, mv, &arcs, &narcs, NULL, NULL, &d) == CN_OK);
        for (int k = 0; arcs && k < 720; k++) {
            double t = (k + 0.37) * CN_PI / 360, dir[3] = {cos(t), sin(t), 0};
            int in = in_arcs(arcs, narcs, t, 1e-6);
            if (in < 0) continue;
            bool sfree;
            CHECK(cn_direction_free(a, NULL, mv, dir, &sfree, &d) == CN_OK);
            tried++;
            if ((in == 1) != sfree) disagree++;
        }
        cn_free_arcs(arcs);
        free(mv);
        cn_assembly_free(a);
    }
    CHECK_MSG(disagree == 0 && tried > 10000, "free arcs: %d of %d directions disagree with the swept test", disagree,
              tried);
}

void test_ndbg(void) {
    test_channel();
    test_interlock();
    test_table();
    test_peg();
    test_rotated();
    test_against_swept("fig9.json");
    test_against_swept("stack3d.json");
    test_against_swept("blocks.json");
    test_against_swept("fig17.json");
    test_arcs_against_swept();
}
