/* Contact detection: known contact sets in 2-D and 3-D, tolerances, overlaps. */
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "collide.h"
#include "pieces.h"

static int count_contacts(const char *json, cnContactSet *cs, cnOverlap *ov) {
    cnAssembly *a = load_ok(json);
    if (!a) return -1;
    cnDiag d;
    cs->count = 0;
    CHECK(cn_contacts_find(a, NULL, cs, ov, &d) == CN_OK);
    cn_assembly_free(a);
    return cs->count;
}

static int has_point(const cnContactSet *cs, double x, double y, double z, double tol) {
    for (int i = 0; i < cs->count; i++) {
        const double *p = cs->items[i].point;
        if (fabs(p[0] - x) <= tol && fabs(p[1] - y) <= tol && fabs(p[2] - z) <= tol) return 1;
    }
    return 0;
}

#define TABLE2 "{\"name\":\"t\",\"fixed\":true,\"polygon\":[[-10,-1],[10,-1],[10,0],[-10,0]]}"
#define TABLE3 "{\"name\":\"t\",\"fixed\":true,\"box\":{\"min\":[-10,-10,-1],\"max\":[10,10,0]}}"

static void test_2d(void) {
    cnContactSet cs = {0};
    cnOverlap ov;
    /* edge-edge: two points at the block's corners, normal up from the table */
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2 ",{\"name\":\"A\",\"polygon\":"
                         "[[1,0],[3,0],[3,1],[1,1]]}]}",
                         &cs, &ov) == 2);
    CHECK(has_point(&cs, 1, 0, 0, 1e-12) && has_point(&cs, 3, 0, 0, 1e-12));
    CHECK(cs.items[0].normal[1] == 1.0 && cs.items[0].body1 == 0 && cs.items[0].body2 == 1);
    CHECK(cs.items[0].kind == CN_CONTACT_EDGE);
    /* vertex-edge: a triangle standing on its apex */
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2 ",{\"name\":\"A\",\"polygon\":"
                         "[[0,0],[1,2],[-1,2]]}]}",
                         &cs, &ov) == 1);
    CHECK(has_point(&cs, 0, 0, 0, 1e-12) && cs.items[0].kind == CN_CONTACT_VERTEX);
    /* overlap of two edges only partly: block A on block B offset -> overlap segment ends */
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2
                         ",{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
                         "{\"name\":\"B\",\"polygon\":[[1.5,1],[4,1],[4,2],[1.5,2]]}]}",
                         &cs, &ov) == 4);
    CHECK(has_point(&cs, 1.5, 1, 0, 1e-12) && has_point(&cs, 2, 1, 0, 1e-12));
    /* side by side blocks touching on a vertical face: contact between them too */
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2
                         ",{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
                         "{\"name\":\"B\",\"polygon\":[[1,0],[2,0],[2,2],[1,2]]}]}",
                         &cs, &ov) == 6);
    CHECK(has_point(&cs, 1, 1, 0, 1e-12));
    /* gap just within / just beyond the tolerance (1e-6 of the smaller part's bounding-box
     * diagonal: the block's, about 2.236, so 2.236e-6) */
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2 ",{\"name\":\"A\",\"polygon\":"
                         "[[1,0.000002],[3,0.000002],[3,1],[1,1]]}]}",
                         &cs, &ov) == 2);
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2 ",{\"name\":\"A\",\"polygon\":"
                         "[[1,0.0000025],[3,0.0000025],[3,1],[1,1]]}]}",
                         &cs, &ov) == 0);
    /* non-convex U on two supports: contacts from both pieces */
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2
                         ",{\"name\":\"U\",\"polygons\":[[[0,0],[1,0],[1,2],[0,2]],"
                         "[[3,0],[4,0],[4,2],[3,2]],[[1,1],[3,1],[3,2],[1,2]]]}]}",
                         &cs, &ov) == 4);
    /* two fixed parts never contact */
    CHECK(count_contacts("{\"dimension\":2,\"parts\":[" TABLE2
                         ",{\"name\":\"w\",\"fixed\":true,\"polygon\":[[0,0],[1,0],[1,3],[0,3]]}]}",
                         &cs, &ov) == 0);
    cn_contacts_free(&cs);
}

static void test_overlap(void) {
    cnAssembly *a = NULL;
    cnDiag d;
    CHECK(cn_assembly_load_string("{\"dimension\":2,\"parts\":[" TABLE2
                                  ",{\"name\":\"A\",\"polygon\":[[0,-0.25],[1,-0.25],[1,1],[0,1]]}]}",
                                  NULL, &a, &d) == CN_ERR_INPUT);
    CHECK(!strcmp(d.where, "parts[1]"));
    CHECK(strstr(d.message, "'A' overlaps part 't'") != NULL);
    CHECK(strstr(d.message, "by 0.25") != NULL);
}

static void test_3d(void) {
    cnContactSet cs = {0};
    cnOverlap ov;
    /* face-face: box on table: 4 corners */
    CHECK(count_contacts("{\"dimension\":3,\"parts\":[" TABLE3 ",{\"name\":\"A\",\"box\":"
                         "{\"min\":[0,0,0],\"max\":[1,2,3]}}]}",
                         &cs, &ov) == 4);
    CHECK(has_point(&cs, 1, 2, 0, 1e-12) && cs.items[0].kind == CN_CONTACT_FACE);
    /* partial face overlap: B shifted on A -> overlap rectangle's corners */
    CHECK(count_contacts("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"fixed\":true,\"box\":"
                         "{\"min\":[0,0,0],\"max\":[2,2,1]}},{\"name\":\"B\",\"box\":"
                         "{\"min\":[1,1.5,1],\"max\":[3,3,2]}}]}",
                         &cs, &ov) == 4);
    CHECK(has_point(&cs, 1, 1.5, 1, 1e-12) && has_point(&cs, 2, 2, 1, 1e-12));
    /* square rotated 45 degrees on a smaller square: octagon, 8 points */
    CHECK(count_contacts("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"fixed\":true,\"box\":"
                         "{\"min\":[-1,-1,-1],\"max\":[1,1,0]}},{\"name\":\"B\",\"hull\":"
                         "[[1.3,0,0],[0,1.3,0],[-1.3,0,0],[0,-1.3,0],"
                         "[1.3,0,1],[0,1.3,1],[-1.3,0,1],[0,-1.3,1]]}]}",
                         &cs, &ov) == 8);
    /* edge-face: a triangular prism lying on an edge: 2 points */
    CHECK(count_contacts("{\"dimension\":3,\"parts\":[" TABLE3 ",{\"name\":\"P\",\"hull\":"
                         "[[0,0,0],[0,3,0],[-1,0,1],[1,0,1],[-1,3,1],[1,3,1]]}]}",
                         &cs, &ov) == 2);
    CHECK(has_point(&cs, 0, 0, 0, 1e-12) && has_point(&cs, 0, 3, 0, 1e-12));
    CHECK(cs.items[0].kind == CN_CONTACT_EDGE);
    /* vertex-face: a tetrahedron on its apex */
    CHECK(count_contacts("{\"dimension\":3,\"parts\":[" TABLE3 ",{\"name\":\"T\",\"hull\":"
                         "[[0,0,0],[1,0,1],[-1,1,1],[-1,-1,1]]}]}",
                         &cs, &ov) == 1);
    /* edge-edge: two prisms crossing at right angles, ridge on ridge: 1 point */
    CHECK(count_contacts("{\"dimension\":3,\"parts\":[{\"name\":\"L\",\"fixed\":true,\"hull\":"
                         "[[0,-2,0],[0,2,0],[-1,-2,-1],[1,-2,-1],[-1,2,-1],[1,2,-1]]},"
                         "{\"name\":\"U\",\"hull\":"
                         "[[-2,0,0],[2,0,0],[-2,-1,1],[-2,1,1],[2,-1,1],[2,1,1]]}]}",
                         &cs, &ov) == 1);
    CHECK(has_point(&cs, 0, 0, 0, 1e-12));
    CHECK(fabs(fabs(cs.items[0].normal[2]) - 1) < 1e-12);
    cn_contacts_free(&cs);
}

/* Contacts move with a part's offset and disappear for absent parts. */
static void test_query(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"parts\":[" TABLE2
                            ",{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
                            "{\"name\":\"B\",\"polygon\":[[0,1],[1,1],[1,2],[0,2]]}]}");
    if (!a) return;
    cnPose pose[3] = {cn_pose_identity(), cn_pose_identity(), cn_pose_translation((double[3]){0.5, 0, 0})};
    unsigned char absent[3] = {0, 0, 0};
    cnContactQuery q = {pose, absent, NULL};
    cnContactSet cs = {0};
    cnOverlap ov;
    CHECK(cn_contacts_find(a, &q, &cs, &ov, NULL) == CN_OK);
    CHECK(cs.count == 4 && has_point(&cs, 1.5, 1, 0, 1e-12));
    absent[1] = 1;
    CHECK(cn_contacts_find(a, &q, &cs, &ov, NULL) == CN_OK);
    CHECK(cs.count == 0);
    cn_contacts_free(&cs);
    cn_assembly_free(a);
}

/* Events of M (moving along u by up to L) against S, as a sorted list. */
static int events_of(const char *json, const double u[3], double L, double *ev, int cap) {
    cnAssembly *a = load_ok(json);
    if (!a) return -1;
    unsigned char mov[8] = {0}, still[8] = {0};
    for (int i = 0; i < a->nparts && i < 8; i++) {
        mov[i] = !strcmp(a->parts[i].name, "M");
        still[i] = !mov[i];
    }
    cnPose id = cn_pose_identity();
    int dropped = 0;
    int n = cn_contact_events(a, mov, still, &id, u, L, ev, cap, &dropped);
    CHECK(dropped == 0);
    cn_assembly_free(a);
    return n;
}

static bool has_event(const double *ev, int n, double s) {
    for (int i = 0; i < n; i++)
        if (fabs(ev[i] - s) < 1e-9) return true;
    return false;
}

/* Contact events along a translation, by hand. 2-D: a unit square M at [0,1]^2 slid right along
 * a table (y < 0) towards a block S at x in [3, 4] (y in [0, 2]) and over a step: its right side
 * meets S's left side at s = 2 (vertex on edge, both ways); along the table, M's corners pass the
 * table's corner (10, 0) at s = 9 and 10. 3-D: a unit cube moved along (1, 0, 0) meets a box
 * whose face is at x = 2.5 at s = 1.5; moved along (1, 1, 0)/sqrt 2 past a box at x, y in [2, 3]
 * it first meets it edge on edge at s = sqrt 2 (corner edges at x = y = 1 and x = y = 2). */
static void test_events(void) {
    double ev[256];
    double ux[3] = {1, 0, 0};
    int n = events_of("{\"dimension\":2,\"parts\":["
                      "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-5,-1],[10,-1],[10,0],[-5,0]]},"
                      "{\"name\":\"S\",\"fixed\":true,\"polygon\":[[3,0],[4,0],[4,2],[3,2]]},"
                      "{\"name\":\"M\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]}]}",
                      ux, 12, ev, 256);
    CHECK(n > 0);
    CHECK_MSG(has_event(ev, n, 2), "2-D: no event where M meets S");
    CHECK_MSG(has_event(ev, n, 9) && has_event(ev, n, 10), "2-D: no event where M's corners pass the table's");
    for (int i = 0; i < n; i++) CHECK_MSG(ev[i] >= 0 && ev[i] <= 12 && (i == 0 || ev[i] > ev[i - 1]),
                                          "2-D: events not sorted in [0, L]");
    n = events_of("{\"dimension\":3,\"parts\":["
                  "{\"name\":\"S\",\"fixed\":true,\"box\":{\"min\":[2.5,-1,-1],\"max\":[3.5,2,2]}},"
                  "{\"name\":\"M\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}}]}",
                  ux, 4, ev, 256);
    CHECK_MSG(n > 0 && ev[0] > 1.5 - 1e-9 && has_event(ev, n, 1.5), "3-D: first event %g, not 1.5", n > 0 ? ev[0] : -1);
    double ud[3] = {sqrt(0.5), sqrt(0.5), 0};
    n = events_of("{\"dimension\":3,\"parts\":["
                  "{\"name\":\"S\",\"fixed\":true,\"box\":{\"min\":[2,2,-1],\"max\":[3,3,2]}},"
                  "{\"name\":\"M\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}}]}",
                  ud, 4, ev, 256);
    CHECK_MSG(n > 0 && fabs(ev[0] - sqrt(2.0)) < 1e-9, "3-D diagonal: first event %g, not sqrt 2", n > 0 ? ev[0] : -1);
    /* edge across edge only: a prism whose ridge (x = 3, z = 0.5) runs along y and points at the
     * cube; the cube's vertical front edges (x = 1) cross it at s = 2, before any vertex meets a
     * face (the corners reach the prism's slopes at s = 2.5 at the earliest) */
    n = events_of("{\"dimension\":3,\"parts\":["
                  "{\"name\":\"S\",\"fixed\":true,\"hull\":[[3,-1,0.5],[3,2,0.5],[4,-1,0],[4,-1,1],[4,2,0],[4,2,1]]},"
                  "{\"name\":\"M\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}}]}",
                  ux, 4, ev, 256);
    CHECK_MSG(n > 0 && fabs(ev[0] - 2) < 1e-9, "3-D ridge: first event %g, not 2", n > 0 ? ev[0] : -1);
}

void test_contact(void) {
    test_events();
    test_2d();
    test_overlap();
    test_3d();
    test_query();
}
