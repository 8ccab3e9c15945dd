/* section.c: a 3-D prism's 2-D section. Which assemblies are prisms (cn_section_axis on small
 * scenes written by hand); the section checked after an undecided 3-D arch against the same arch
 * written in 2-D directly (a second construction: the same verdict and search), extruded along
 * each axis, mirrored and scaled; and --assume-planar makes stable only what the 2-D arch is. */
#include <math.h>
#include <string.h>

#include "helpers.h"
#include "section.h"

#define PI 3.14159265358979323846
/* LPs a search may take: the 3-D arches' searches stop undecided, the 2-D ones' end in fewer */
#define BUDGET 100

static int axis_of(const char *json, const unsigned char *absent) {
    cnAssembly *a = load_ok(json);
    if (!a) return -2;
    cnContactQuery q = {.absent = absent};
    int k = cn_section_axis(a, absent ? &q : NULL);
    cn_assembly_free(a);
    return k;
}

static void test_axis(void) {
    /* a block on a table, gravity down z: a prism along x (the first axis tried) */
    const char *block = "{\"dimension\":3,\"parts\":["
                        "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}},"
                        "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,2,1]}}]}";
    CHECK_MSG(axis_of(block, NULL) == 0, "block: axis %d", axis_of(block, NULL));
    /* gravity along x: x is not an axis, y is */
    const char *gx = "{\"dimension\":3,\"gravity\":[9.81,0,0],\"parts\":["
                     "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[1,-5,-5],\"max\":[2,5,5]}},"
                     "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,2,1]}}]}";
    CHECK_MSG(axis_of(gx, NULL) == 1, "gravity along x: axis %d", axis_of(gx, NULL));
    /* gravity with a small part along every axis: none */
    const char *gall = "{\"dimension\":3,\"gravity\":[0.01,0.01,-9.81],\"parts\":["
                       "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}},"
                       "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,2,1]}}]}";
    CHECK_MSG(axis_of(gall, NULL) == -1, "gravity off every axis: axis %d", axis_of(gall, NULL));
    /* two free blocks over different depths in x and in y: none */
    const char *stag = "{\"dimension\":3,\"parts\":["
                       "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}},"
                       "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}},"
                       "{\"name\":\"B\",\"box\":{\"min\":[0.5,0.5,1],\"max\":[1.5,1.5,2]}}]}";
    CHECK_MSG(axis_of(stag, NULL) == -1, "staggered: axis %d", axis_of(stag, NULL));
    /* ... but with B absent, A alone is a prism */
    unsigned char absent[3] = {0, 0, 1};
    CHECK_MSG(axis_of(stag, absent) == 0, "B absent: axis %d", axis_of(stag, absent));
    /* a support shorter than the free parts' depth along x and y: none */
    const char *shortsup = "{\"dimension\":3,\"parts\":["
                           "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[0.2,0.2,-1],\"max\":[0.8,0.8,0]}},"
                           "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}}]}";
    CHECK_MSG(axis_of(shortsup, NULL) == -1, "short support: axis %d", axis_of(shortsup, NULL));
    /* a wedge whose two ends differ (a pyramid's frustum along y): along y none; along x the
       ends differ too */
    const char *frustum = "{\"dimension\":3,\"parts\":["
                          "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}},"
                          "{\"name\":\"A\",\"hull\":[[0,0,0],[2,0,0],[2,0,1],[0,0,1],"
                          "[0.5,1,0],[1.5,1,0],[1.5,1,1],[0.5,1,1]]}]}";
    CHECK_MSG(axis_of(frustum, NULL) == -1, "frustum: axis %d", axis_of(frustum, NULL));
    /* a fixel: none (the section has no fixels) */
    const char *fixel = "{\"dimension\":3,\"parts\":["
                        "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}},"
                        "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,2,1]}}],"
                        "\"fixels\":[{\"part\":\"A\",\"point\":[0,1,0.5],\"normal\":[1,0,0]}]}";
    CHECK_MSG(axis_of(fixel, NULL) == -1, "fixel: axis %d", axis_of(fixel, NULL));
    /* 2-D: none */
    const char *flat = "{\"dimension\":2,\"parts\":[{\"name\":\"T\",\"fixed\":true,"
                       "\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                       "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]}]}";
    CHECK_MSG(axis_of(flat, NULL) == -1, "2-D: axis %d", axis_of(flat, NULL));
}

/* A semicircular arch of n voussoirs, radius 10, thickness t, on a ground block, friction mu. In
 * 2-D (k < 0) as polygons; else extruded along axis k over depth [0, 2], its section's horizontal
 * along axis h and up along the third axis (gravity down it), mirrored across the vertical plane
 * when mirror, every length scaled by s. */
static void arch_lat(char *json, size_t cap, int n, double t, double mu, int k, int h, bool mirror, double s,
                     double lat) {
    int up = 3 - (k < 0 ? 1 : k) - (k < 0 ? 0 : h);
    size_t at = 0;
    double R = 10, mx = mirror ? -1 : 1;
    double gv[3] = {0, 0, 0};
    if (k >= 0) gv[up] = -9.81, gv[h] = mx * lat * 9.81;
    else gv[0] = mx * lat * 9.81, gv[1] = -9.81;
    at += (size_t)snprintf(json + at, cap - at, "{\"dimension\":%d,\"friction\":%g,\"gravity\":[%.17g,%.17g%s",
                           k < 0 ? 2 : 3, mu, gv[0], gv[1], k < 0 ? "]" : "");
    if (k >= 0) at += (size_t)snprintf(json + at, cap - at, ",%.17g]", gv[2]);
    at += (size_t)snprintf(json + at, cap - at, ",\"parts\":[");
    for (int i = -1; i < n; i++) {
        double pts[4][2];
        if (i < 0) { /* the ground */
            double g[4][2] = {{-13, -1}, {13, -1}, {13, 0}, {-13, 0}};
            memcpy(pts, g, sizeof g);
        } else {
            double a0 = PI * i / n, a1 = PI * (i + 1) / n;
            double c0 = cos(a0), s0 = i == 0 ? 0 : sin(a0), c1 = cos(a1), s1 = i + 1 == n ? 0 : sin(a1);
            double v[4][2] = {{R * c0, R * s0}, {(R + t) * c0, (R + t) * s0}, {(R + t) * c1, (R + t) * s1},
                              {R * c1, R * s1}};
            memcpy(pts, v, sizeof v);
        }
        at += (size_t)snprintf(json + at, cap - at, "%s{\"name\":\"%s%d\",%s\"%s\":[", i < 0 ? "" : ",",
                               i < 0 ? "ground" : "v", i < 0 ? 0 : i, i < 0 ? "\"fixed\":true," : "",
                               k < 0 ? "polygon" : "hull");
        for (int y = 0; y < (k < 0 ? 1 : 2); y++)
            for (int j = 0; j < 4; j++) {
                double x = s * mx * pts[j][0], z = s * pts[j][1];
                if (k < 0) at += (size_t)snprintf(json + at, cap - at, "%s[%.17g,%.17g]", j ? "," : "", x, z);
                else {
                    double p[3];
                    p[k] = s * (i < 0 ? 3.0 * y - 0.5 : 2.0 * y), p[h] = x, p[up] = z;
                    at += (size_t)snprintf(json + at, cap - at, "%s[%.17g,%.17g,%.17g]", y || j ? "," : "",
                                           p[0], p[1], p[2]);
                }
            }
        at += (size_t)snprintf(json + at, cap - at, "]}");
    }
    snprintf(json + at, cap - at, "]}");
}

static void arch(char *json, size_t cap, int n, double t, double mu, int k, int h, bool mirror, double s) {
    arch_lat(json, cap, n, t, mu, k, h, mirror, s, 0);
}

static cnStatus check_with(const char *json, const cnCheckOptions *o, cnCheckResult *r) {
    memset(r, 0, sizeof *r);
    cnAssembly *a = load_ok(json);
    if (!a) return CN_ERR_INPUT;
    cnDiag d;
    cnStatus st = cn_check(a, o, r, &d);
    if (st) fprintf(stderr, "check failed: %s\n", d.message);
    cn_assembly_free(a);
    return st;
}

static cnStatus check(const char *json, long budget, bool planar, cnCheckResult *r) {
    cnCheckOptions o = cn_check_options_default();
    o.max_nodes = budget;
    o.assume_planar = planar;
    return check_with(json, &o, r);
}

static void test_arches(void) {
    static char json[20000];
    const double thick[] = {1.5, 0.5}, mus[] = {0.8, 0.35};
    /* extrusion axis, horizontal axis, mirror, scale */
    const struct {
        int k, h;
        bool mirror;
        double s;
    } frame[] = {{1, 0, false, 1}, {0, 1, false, 3.7}, {2, 0, true, 1}, {0, 2, true, 0.25}};
    int checked = 0, stable = 0;
    for (int n = 3; n <= 5; n += 2)
        for (size_t ti = 0; ti < 2; ti++)
            for (size_t mi = 0; mi < 2; mi++) {
                cnCheckResult r2;
                arch(json, sizeof json, n, thick[ti], mus[mi], -1, 0, false, 1);
                if (check(json, BUDGET, false, &r2)) {
                    cn_test_failures++;
                    cn_check_result_free(&r2);
                    continue;
                }
                for (size_t f = 0; f < sizeof frame / sizeof frame[0]; f++) {
                    cnCheckResult r3, rp;
                    arch(json, sizeof json, n, thick[ti], mus[mi], frame[f].k, frame[f].h, frame[f].mirror,
                         frame[f].s);
                    if (check(json, BUDGET, false, &r3) || check(json, BUDGET, true, &rp)) {
                        cn_test_failures++;
                    } else {
                        if (r3.section.checked) {
                            checked++;
                            stable += r2.verdict == CN_VERDICT_STABLE;
                            CHECK_MSG(r3.verdict == CN_VERDICT_UNDECIDED, "n %d t %g mu %g frame %zu: verdict %d",
                                      n, thick[ti], mus[mi], f, (int)r3.verdict);
                            CHECK_MSG(r3.section.axis == frame[f].k, "n %d frame %zu: axis %d", n, f, r3.section.axis);
                            CHECK_MSG(r3.section.verdict == r2.verdict && r3.section.proof == r2.proof,
                                      "n %d t %g mu %g frame %zu: section %d (proof %d), the 2-D arch %d (%d)", n,
                                      thick[ti], mus[mi], f, (int)r3.section.verdict, (int)r3.section.proof,
                                      (int)r2.verdict, (int)r2.proof);
                        }
                        /* --assume-planar: a decided verdict unchanged; an undecided one stable
                           exactly where the 2-D arch is */
                        CHECK_MSG(r3.verdict == CN_VERDICT_UNDECIDED || rp.verdict == r3.verdict,
                                  "n %d t %g mu %g frame %zu: planar %d, 3-D %d", n, thick[ti], mus[mi], f,
                                  (int)rp.verdict, (int)r3.verdict);
                        CHECK_MSG(!rp.stable || r3.stable || r2.verdict == CN_VERDICT_STABLE,
                                  "n %d t %g mu %g frame %zu: planar %d, 3-D %d, 2-D %d", n, thick[ti], mus[mi], f,
                                  (int)rp.verdict, (int)r3.verdict, (int)r2.verdict);
                        if (r3.verdict == CN_VERDICT_UNDECIDED && r3.section.checked)
                            CHECK_MSG(rp.stable == (r2.verdict == CN_VERDICT_STABLE),
                                      "n %d t %g mu %g frame %zu: planar %d, 2-D %d", n, thick[ti], mus[mi], f,
                                      (int)rp.verdict, (int)r2.verdict);
                        if (r3.verdict == CN_VERDICT_UNSTABLE) CHECK(rp.verdict == CN_VERDICT_UNSTABLE);
                        if (rp.proof == CN_PROOF_SECTION) {
                            CHECK(rp.stable && rp.undecided == CN_UNDECIDED_NO && rp.nmoving == 0);
                            CHECK(rp.section.checked && rp.section.verdict == CN_VERDICT_STABLE &&
                                  rp.section.axis == frame[f].k && rp.solver.search_nodes == BUDGET);
                        }
                    }
                    cn_check_result_free(&r3), cn_check_result_free(&rp);
                }
                cn_check_result_free(&r2);
            }
    /* the comparison must have happened, on stable sections and others */
    fprintf(stderr, "sections checked %d, stable %d\n", checked, stable);
    CHECK_MSG(checked >= 16 && stable >= 8 && checked > stable, "sections checked %d, stable %d", checked, stable);
}

/* The tilt and lateral margins of a 3-D arch with --assume-planar about its extrusion axis are
 * the 2-D arch's (cn_margin of each: a second formulation), and their far sides are proved too:
 * there the section's motion, lifted to 3-D and verified, makes the 3-D arch not guaranteed
 * where its own search would be undecided. */
static void test_margins_lifted(void) {
    static char json[20000];
    const struct {
        int k, h;
        bool mirror;
    } frame[] = {{1, 0, false}, {0, 1, true}};
    cnMarginResult m2;
    cnDiag d;
    int lifted = 0;
    arch(json, sizeof json, 3, 1.5, 0.8, -1, 0, false, 1);
    cnAssembly *a2 = load_ok(json);
    if (!a2) return;
    cnMarginOptions mo = cn_margin_options_default();
    mo.direction[0] = 1; /* lateral towards +x (the 2-D arch's horizontal) */
    CHECK(cn_margin(a2, &mo, &m2, &d) == CN_OK);
    /* the weakest sense: the arch is symmetric, so the other sense's margin differs by rounding,
       and both take few verdicts (20 when the other sense galloped down 1e-3 first and its
       static limit's upper end, stable, sent the search 4 times farther) */
    cnMarginOptions mw = cn_margin_options_default();
    mw.kinds = CN_MARGIN_LATERAL;
    cnMarginResult w2;
    CHECK(cn_margin(a2, &mw, &w2, &d) == CN_OK);
    CHECK_MSG(w2.lateral.end == CN_MARGIN_FOUND && fabs(w2.lateral.value - m2.lateral.value) <= 1e-5 * m2.lateral.value,
              "weakest %.9g, towards +x %.9g", w2.lateral.value, m2.lateral.value);
    CHECK_MSG(w2.lateral.verdicts <= 12, "the weakest lateral factor took %d verdicts", w2.lateral.verdicts);
    cn_margin_result_free(&w2);
    cn_assembly_free(a2);
    for (size_t f = 0; f < sizeof frame / sizeof frame[0]; f++) {
        arch(json, sizeof json, 3, 1.5, 0.8, frame[f].k, frame[f].h, frame[f].mirror, 1);
        cnAssembly *a3 = load_ok(json);
        if (!a3) continue;
        cnMarginOptions m3o = cn_margin_options_default();
        m3o.check.assume_planar = true; /* the section decides; the 3-D search would not */
        m3o.check.max_nodes = BUDGET;
        m3o.kinds = CN_MARGIN_TILT | CN_MARGIN_LATERAL; /* the friction margin's sections need more */
        m3o.axis[frame[f].k] = frame[f].mirror ? -1 : 1; /* the same turn of gravity, mirrored */
        m3o.direction[frame[f].h] = frame[f].mirror ? -1 : 1;
        cnMarginResult m3;
        CHECK(cn_margin(a3, &m3o, &m3, &d) == CN_OK);
        const cnMargin *p2[] = {&m2.friction, &m2.tilt, &m2.lateral}, *p3[] = {&m3.friction, &m3.tilt, &m3.lateral};
        for (int i = 1; i < 3; i++) {
            CHECK_MSG(p3[i]->end == CN_MARGIN_FOUND && fabs(p3[i]->value - p2[i]->value) <= 1e-5 * fabs(p2[i]->value),
                      "frame %zu margin %d: 3-D %.9g, 2-D %.9g", f, i, p3[i]->value, p2[i]->value);
            CHECK_MSG(p3[i]->past_verdict == CN_VERDICT_NOT_GUARANTEED || p3[i]->past_verdict == CN_VERDICT_UNSTABLE,
                      "frame %zu margin %d: past verdict %d", f, i, (int)p3[i]->past_verdict);
        }
        /* past the 2-D arch's lateral margin, where it is not guaranteed, the 3-D arch is not
           guaranteed too, with or without the assumption: the section's motion lifted (Lemke's
           motion left out, the 3-D search at 100 LPs would be undecided) */
        for (int planar = 0; planar < 2; planar++) {
            cnCheckResult r;
            cnCheckOptions o = cn_check_options_default();
            o.max_nodes = BUDGET, o.motion_tol = CN_MARGIN_MOTION_TOL, o.assume_planar = planar;
            o.route = CN_ROUTE_NO_LEMKE_MOTION; /* not the LCP's own motion: the section's */
            arch_lat(json, sizeof json, 3, 1.5, 0.8, -1, 0, frame[f].mirror, 1, m2.lateral.past);
            cnCheckOptions o2 = o;
            o2.route = 0;
            if (check_with(json, &o2, &r) || r.verdict != CN_VERDICT_NOT_GUARANTEED) {
                fprintf(stderr, "frame %zu: the 2-D arch at %.9g g is %d, not 'not guaranteed'\n", f,
                        m2.lateral.past, (int)r.verdict);
                cn_check_result_free(&r);
                continue;
            }
            cn_check_result_free(&r);
            arch_lat(json, sizeof json, 3, 1.5, 0.8, frame[f].k, frame[f].h, frame[f].mirror, 1, m2.lateral.past);
            if (check_with(json, &o, &r)) cn_test_failures++;
            else {
                lifted++;
                CHECK_MSG(r.verdict == CN_VERDICT_NOT_GUARANTEED && r.section.lifted && r.nmoving == 3 &&
                              r.solver.search_nodes == 0,
                          "frame %zu planar %d at %.9g g: verdict %d lifted %d moving %d LPs %ld", f, planar,
                          m2.lateral.past, (int)r.verdict, r.section.lifted, r.nmoving, r.solver.search_nodes);
            }
            cn_check_result_free(&r);
        }
        cn_margin_result_free(&m3);
        cn_assembly_free(a3);
    }
    cn_margin_result_free(&m2);
    CHECK_MSG(lifted >= 2, "lifted checks %d", lifted);
}

void test_section(void) {
    test_axis();
    test_arches();
    test_margins_lifted();
}
