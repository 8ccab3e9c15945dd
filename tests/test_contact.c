/* Contact detection: known contact sets in 2-D and 3-D, tolerances, overlaps. */
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
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

void test_contact(void) {
    test_2d();
    test_overlap();
    test_3d();
    test_query();
}
