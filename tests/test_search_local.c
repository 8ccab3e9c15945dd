/* search_local.c: motions of one body, or two, held among the rest, on rows of blocks too many
 * for the whole search (over CN_MOTION_MAX_PAIRS pairs). The end block A of a row stands with its
 * centre over the ground's edge, alone or with a block B on it; a sideways load outward tips it
 * (by moments about the edge, at any load: the weight's arm is zero), inward presses it on. The
 * verdicts are checked against that statics, against the whole search on a short row (a second
 * way to the same verdict), and under mirroring, turning and scaling the whole scene. */
#include <math.h>
#include <string.h>

#include "helpers.h"

#define ROW_LONG 60 /* blocks in the row: about 1,000 pairs, beyond the whole search */

/* The row scene: blocks 1 x 1 on the ground (x <= 0) side by side up to A (2 x 1, on x in
 * [-1, 1]: its centre over the ground's edge x = 0), B (1 x 1) on A's middle when `withb`;
 * gravity g down plus a sideways load lat g (outward: +x); the whole mirrored in x when mirror,
 * then turned by th about the origin and scaled by s. */
static void row_scene(char *json, size_t cap, int n, bool withb, double lat, bool mirror, double th,
                      double s) {
    double c = cos(th), sn = sin(th), mx = mirror ? -1 : 1;
    size_t at = 0;
#define PT(x, y)                                                                                   \
    at += (size_t)snprintf(json + at, cap - at, "[%.17g,%.17g]", s * (c * mx * (x) - sn * (y)),     \
                           s * (sn * mx * (x) + c * (y)))
#define POLY(name, x0, y0, x1, y1, fixed)                                                          \
    do {                                                                                           \
        at += (size_t)snprintf(json + at, cap - at, "%s{\"name\":\"%s\",%s\"polygon\":[",         \
                               fixed ? "" : ",", name, fixed ? "\"fixed\":true," : "");             \
        if (mirror) { /* counter-clockwise once mirrored */                                        \
            PT(x0, y0), json[at++] = ',', PT(x0, y1), json[at++] = ',', PT(x1, y1), json[at++] = ','; \
            PT(x1, y0);                                                                            \
        } else {                                                                                   \
            PT(x0, y0), json[at++] = ',', PT(x1, y0), json[at++] = ',', PT(x1, y1), json[at++] = ','; \
            PT(x0, y1);                                                                            \
        }                                                                                          \
        at += (size_t)snprintf(json + at, cap - at, "]}");                                         \
    } while (0)
    double gx = mx * lat * 9.81, gy = -9.81;
    at += (size_t)snprintf(json + at, cap - at,
                           "{\"dimension\":2,\"friction\":0.6,\"gravity\":[%.17g,%.17g],\"parts\":[",
                           c * gx - sn * gy, sn * gx + c * gy);
    POLY("ground", -(n + 3.0), -1.0, 0.0, 0.0, true);
    POLY("A", -1.0, 0.0, 1.0, 1.0, false);
    if (withb) POLY("B", -0.5, 1.0, 0.5, 2.0, false);
    for (int k = 0; k < n; k++) {
        char name[16];
        snprintf(name, sizeof name, "k%d", k);
        POLY(name, -2.0 - k, 0.0, -1.0 - k, 1.0, false);
    }
    snprintf(json + at, cap - at, "]}");
#undef POLY
#undef PT
}

/* The check of the row scene: its verdict, the names of the parts that move (comma-separated),
 * and A's angular acceleration (2-D). */
static cnVerdict row_check(int n, bool withb, double lat, bool mirror, double th, double s, char *moving,
                           size_t mcap, double *a_ang) {
    static char json[40000];
    row_scene(json, sizeof json, n, withb, lat, mirror, th, s);
    cnAssembly *a = load_ok(json);
    if (!a) return CN_VERDICT_UNDECIDED;
    cnCheckOptions o = cn_check_options_default();
    cnCheckResult r;
    cnDiag d;
    cnVerdict v = CN_VERDICT_UNDECIDED;
    moving[0] = 0;
    *a_ang = 0;
    if (cn_check(a, &o, &r, &d) == CN_OK) {
        v = r.verdict;
        size_t at = 0;
        for (int i = 0; i < r.nmoving; i++)
            at += (size_t)snprintf(moving + at, mcap - at, "%s%s", i ? "," : "", a->parts[r.moving[i]].name);
        int A = cn_assembly_find_part(a, "A");
        if (A >= 0) *a_ang = r.part[A].ang[2];
    } else {
        cn_test_failures++;
        fprintf(stderr, "check failed: %s\n", d.message);
    }
    cn_check_result_free(&r);
    cn_assembly_free(a);
    return v;
}

static void test_end_block(void) {
    char moving[256];
    double ang;
    /* A alone tips outward: only A moves, turning clockwise (outward about the edge) */
    cnVerdict v = row_check(ROW_LONG, false, 0.05, false, 0, 1, moving, sizeof moving, &ang);
    CHECK_MSG(v == CN_VERDICT_NOT_GUARANTEED, "end block, outward: verdict %d", (int)v);
    CHECK_MSG(!strcmp(moving, "A"), "end block, outward: moving '%s'", moving);
    CHECK_MSG(ang < 0, "end block, outward: A turns %g (clockwise expected)", ang);
    /* with B on it, A cannot turn alone (it would lift B, held still): A and B tip together */
    v = row_check(ROW_LONG, true, 0.05, false, 0, 1, moving, sizeof moving, &ang);
    CHECK_MSG(v == CN_VERDICT_NOT_GUARANTEED, "A under B, outward: verdict %d", (int)v);
    CHECK_MSG(strstr(moving, "A") && strstr(moving, "B"), "A under B, outward: moving '%s'", moving);
    CHECK_MSG(ang < 0, "A under B, outward: A turns %g", ang);
    /* inward the load presses A onto the ground: no motion may be reported */
    for (int withb = 0; withb < 2; withb++) {
        v = row_check(ROW_LONG, withb, -0.05, false, 0, 1, moving, sizeof moving, &ang);
        CHECK_MSG(v != CN_VERDICT_NOT_GUARANTEED && v != CN_VERDICT_UNSTABLE,
                  "inward (B %d): verdict %d, moving '%s'", withb, (int)v, moving);
    }
}

/* The whole search on a short row gives the same verdict as the motions held among the rest on
 * a long one. */
static void test_short_row_agrees(void) {
    char moving[256];
    double ang;
    for (int withb = 0; withb < 2; withb++) {
        cnVerdict v = row_check(2, withb, 0.05, false, 0, 1, moving, sizeof moving, &ang);
        CHECK_MSG(v == CN_VERDICT_NOT_GUARANTEED, "short row (B %d): verdict %d", withb, (int)v);
        CHECK_MSG(strstr(moving, "A") != NULL, "short row (B %d): moving '%s'", withb, moving);
    }
}

/* The same verdict and moving parts mirrored, turned and scaled (A's turn mirrored with it). */
static void test_invariance(void) {
    char base[256], moving[256];
    double ang0, ang;
    for (int withb = 0; withb < 2; withb++) {
        cnVerdict v0 = row_check(ROW_LONG, withb, 0.05, false, 0, 1, base, sizeof base, &ang0);
        const struct {
            bool mirror;
            double th, s;
        } t[] = {{true, 0, 1}, {false, 0.7, 1}, {false, -2.1, 3.5}, {true, 1.3, 0.2}};
        for (size_t i = 0; i < sizeof t / sizeof t[0]; i++) {
            cnVerdict v = row_check(ROW_LONG, withb, 0.05, t[i].mirror, t[i].th, t[i].s, moving, sizeof moving, &ang);
            CHECK_MSG(v == v0 && !strcmp(moving, base), "B %d, case %zu: verdict %d moving '%s' (was %d '%s')",
                      withb, i, (int)v, moving, (int)v0, base);
            CHECK_MSG((t[i].mirror ? -ang : ang) < 0, "B %d, case %zu: A turns %g", withb, i, ang);
        }
    }
}

void test_search_local(void) {
    test_end_block();
    test_short_row_agrees();
    test_invariance();
}
