/* Loader: every malformed input gives CN_ERR_INPUT with the right place and a useful message. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "io.h"

#define CN_PI 3.14159265358979323846

static void expect_error(const char *json, const char *where, const char *msg_part) {
    cnAssembly *a = NULL;
    cnDiag d;
    cnStatus s = cn_assembly_load_string(json, "inline", &a, &d);
    CHECK_MSG(s == CN_ERR_INPUT, "expected an input error for %s", json);
    CHECK_MSG(a == NULL, "no assembly on error");
    CHECK_MSG(!strcmp(d.where, where), "where '%s', expected '%s' (message: %s)", d.where, where,
              d.message);
    CHECK_MSG(strstr(d.message, msg_part) != NULL, "message '%s' lacks '%s'", d.message, msg_part);
    cn_assembly_free(a);
}

#define P2 "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]}"

/* A path of n segments [0, 1e-3] for part A, as a plan step's path (candidate false) or as a
 * candidate: one more than CN_MAX_PATH_SEGMENTS is refused naming the path, the limit loads. */
static void path_limit(bool candidate) {
    int n = CN_MAX_PATH_SEGMENTS + 1;
    size_t cap = (size_t)n * 16 + 512;
    char *j = malloc(cap);
    CHECK(j != NULL);
    if (!j) return;
    for (int pass = 0; pass < 2; pass++, n--) {
        int k = snprintf(j, cap, "{\"dimension\":2,\"parts\":[%s],%s[", P2,
                         candidate ? "\"candidates\":{\"A\":{\"long\":" : "\"plan\":[{\"move\":\"A\",\"path\":");
        for (int i = 0; i < n; i++) k += snprintf(j + k, cap - (size_t)k, "%s[0,1e-3]", i ? "," : "");
        snprintf(j + k, cap - (size_t)k, "]%s}", candidate ? "}}" : "}]");
        if (pass == 0) {
            expect_error(j, candidate ? "candidates.A.long" : "plan[0].path", "at most 10000 segments");
        } else {
            cnAssembly *a = NULL;
            cnDiag d;
            CHECK_MSG(cn_assembly_load_string(j, "inline", &a, &d) == CN_OK, "%s", d.message);
            if (a) CHECK(candidate ? a->cand[0].nseg == CN_MAX_PATH_SEGMENTS : a->plan[0].nseg == CN_MAX_PATH_SEGMENTS);
            cn_assembly_free(a);
        }
    }
    free(j);
}

/* The check of a one-part-on-a-table assembly: stable?, the moving parts, the total normal force. */
static bool check_one(const char *json, double *total, int *nmoving) {
    cnAssembly *a = load_ok(json);
    if (!a) return false;
    cnCheckResult r;
    cnDiag d;
    bool ok = cn_check(a, NULL, &r, &d) == CN_OK;
    CHECK_MSG(ok, "check: %s", d.message);
    bool stable = ok && r.stable;
    *total = 0;
    for (int c = 0; ok && c < r.contacts.count; c++) *total += r.contact[c].normal_force;
    *nmoving = ok ? r.nmoving : -1;
    if (ok) cn_check_result_free(&r);
    cn_assembly_free(a);
    return stable;
}

#define TABLE2 "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]}"
#define TABLE3 "{\"name\":\"T\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}}"

/* Poses (rotation, then position) against hand-derived placements and verdicts. */
static void test_poses(void) {
    double total;
    int nm;
    /* a 2 x 1 rectangle turned 90 degrees and moved by (1, 0) stands on its short side, x in
       [0, 1], y in [0, 2]: stable, its centre at (0.5, 1) */
    const char *stand = "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ",{\"name\":\"R\","
                        "\"polygon\":[[0,0],[2,0],[2,1],[0,1]],\"rotation\":90,\"position\":[1,0]}]}";
    cnAssembly *a = load_ok(stand);
    if (a) {
        const cnPart *p = &a->parts[1];
        CHECK(fabs(p->com[0] - 0.5) < 1e-12 && fabs(p->com[1] - 1) < 1e-12 && fabs(p->mass - 2) < 1e-12);
        CHECK(fabs(p->lo[0]) < 1e-12 && fabs(p->hi[0] - 1) < 1e-12 && fabs(p->lo[1]) < 1e-12 && fabs(p->hi[1] - 2) < 1e-12);
        cn_assembly_free(a);
    }
    CHECK(check_one(stand, &total, &nm) && fabs(total - 2) < 1e-9);
    /* turned 30 degrees about its corner at the origin: it stands on that corner, its centre
       R (1, 0.5) = (0.616, 0.933) to the right of it: it tips */
    CHECK(!check_one("{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ",{\"name\":\"R\","
                     "\"polygon\":[[0,0],[2,0],[2,1],[0,1]],\"rotation\":30}]}", &total, &nm) && nm == 1);
    /* a unit cube turned 30 degrees about the vertical stands on its face: stable, the table
       carries its weight (9.81) */
    const char *turned = "{\"dimension\":3,\"parts\":[" TABLE3 ",{\"name\":\"C\",\"box\":{\"min\":[0,0,0],"
                         "\"max\":[1,1,1]},\"rotation\":{\"axis\":[0,0,1],\"angle\":30}}]}";
    CHECK(check_one(turned, &total, &nm) && fabs(total - 9.81) < 1e-9);
    a = load_ok(turned);
    if (a) { /* its centre: R_z(30) (0.5, 0.5, 0.5) */
        double c = cos(CN_PI / 6), sn = sin(CN_PI / 6), x = 0.5 * c - 0.5 * sn, y = 0.5 * sn + 0.5 * c;
        CHECK(fabs(a->parts[1].com[0] - x) < 1e-12 && fabs(a->parts[1].com[1] - y) < 1e-12);
        CHECK(fabs(a->parts[1].com[2] - 0.5) < 1e-12);
        cn_assembly_free(a);
    }
    /* the same turn as a quaternion (cos 15, 0, 0, sin 15) and as a hull of the turned corners:
       the same part */
    char buf[2048];
    snprintf(buf, sizeof buf, "{\"dimension\":3,\"parts\":[" TABLE3 ",{\"name\":\"C\",\"box\":{\"min\":[0,0,0],"
             "\"max\":[1,1,1]},\"rotation\":{\"quaternion\":[%.17g,0,0,%.17g]}}]}", cos(CN_PI / 12), sin(CN_PI / 12));
    cnAssembly *q = load_ok(buf), *t = load_ok(turned);
    if (q && t) {
        for (int k = 0; k < 3; k++) CHECK(fabs(q->parts[1].com[k] - t->parts[1].com[k]) < 1e-12);
        CHECK(fabs(q->parts[1].mass - 1) < 1e-12);
    }
    cn_assembly_free(q);
    cn_assembly_free(t);
    /* a cube on an edge: turned 40 degrees about y (a 45-degree turn would put its centre over
       the edge), lifted so that its lowest edge is on the table: its centre is beside that edge,
       it tips */
    double lowest = 0;
    for (int i = 0; i < 8; i++) {
        double x = (i & 1) ? 0.5 : -0.5, z = (i & 4) ? 0.5 : -0.5, th = 40 * CN_PI / 180;
        lowest = fmin(lowest, -x * sin(th) + z * cos(th));
    }
    snprintf(buf, sizeof buf, "{\"dimension\":3,\"parts\":[" TABLE3 ",{\"name\":\"C\",\"box\":{\"min\":[-0.5,-0.5,-0.5],"
             "\"max\":[0.5,0.5,0.5]},\"rotation\":{\"axis\":[0,1,0],\"angle\":40},\"position\":[0,0,%.17g]}]}", -lowest);
    CHECK(!check_one(buf, &total, &nm) && nm == 1);
    /* bad poses, each at its place */
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1]],\"rotation\":{\"angle\":3}}]}",
                 "parts[0].rotation", "expected an angle in degrees");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]},\"rotation\":30}]}",
                 "parts[0].rotation", "expected {\"axis\"");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]},\"rotation\":{\"quaternion\":[1,1,0,0]}}]}",
                 "parts[0].rotation.quaternion", "not a unit quaternion");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]},\"rotation\":{\"axis\":[0,0,0],\"angle\":5}}]}",
                 "parts[0].rotation.axis", "the axis is zero");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]},\"rotation\":{\"axis\":[0,0,1]}}]}",
                 "parts[0].rotation.angle", "missing");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]},\"rotation\":{\"axis\":[0,0,1],\"angle\":5,\"quaternion\":[1,0,0,0]}}]}",
                 "parts[0].rotation", "not both");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1]],\"position\":[1,2,3]}]}",
                 "parts[0].position", "an array of 2 numbers");
}

/* cn_ply_check on buffers: ok is whether the file passes, msg a part of the message if not. */
static void ply(const char *buf, size_t len, bool ok, const char *msg) {
    cnDiag d;
    memset(&d, 0, sizeof d);
    cnStatus s = cn_ply_check(buf, len, "t.ply", &d);
    CHECK_MSG(ok ? s == CN_OK : s == CN_ERR_INPUT, "status %d for %.60s (message: %s)", (int)s, buf, d.message);
    if (!ok && msg) CHECK_MSG(strstr(d.message, msg) != NULL, "message '%s' lacks '%s'", d.message, msg);
}

#define PLY_TET_HEAD "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n" \
                     "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
#define PLY_TET_DATA "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n"

/* The PLY checks: line ends of every kind, lists within their lines, counts of every type. */
static void test_ply_check(void) {
    const char *tet = PLY_TET_HEAD PLY_TET_DATA;
    ply(tet, strlen(tet), true, NULL);
    /* CR line ends, and CRLF, read as LF */
    char cr[512], crlf[1024];
    size_t k = 0, j = 0;
    for (const char *c = tet; *c; c++) {
        cr[k++] = *c == '\n' ? '\r' : *c;
        if (*c == '\n') crlf[j++] = '\r';
        crlf[j++] = *c;
    }
    ply(cr, k, true, NULL);
    ply(crlf, j, true, NULL);
    /* a list one item longer than its line: refused with the line */
    const char *longer = PLY_TET_HEAD "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n4 0 1 3\n3 1 2 3\n3 2 0 3\n";
    ply(longer, strlen(longer), false, "list of 4 items on line 15, more than the line holds after it (3)");
    /* items of the next line do not count for a list */
    const char *split = PLY_TET_HEAD "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2\n1\n3 1 2 3\n3 2 0 3\n3 0 1 2\n";
    ply(split, strlen(split), false, "on line 14");
    /* a header line not understood, a keyword glued to a byte, a count with a sign */
    const char *glued = "ply\nformat ascii 1.0\nelement vertex 1\nproperty\x93 float x\nend_header\n0\n";
    ply(glued, strlen(glued), false, "line 4 of its PLY header");
    const char *sign = "ply\nformat ascii 1.0\nelement vertex +1\nproperty float x\nend_header\n0\n";
    ply(sign, strlen(sign), false, "is not a whole number");
    static const char nul[] = "ply\nformat ascii 1.0\nelement vertex 1\0\nproperty float x\nend_header\n0\n";
    ply(nul, sizeof nul - 1, false, "control character");
    /* binary data where the header should end: the missing end_header is what is named */
    const char *noend = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n\x01\x02\x03\x04";
    ply(noend, strlen(noend), false, "no end_header line");
    const char *nofmt = "ply\nelement vertex 1\nproperty float x\nend_header\n0\n";
    ply(nofmt, strlen(nofmt), false, "no format line");
    /* binary: a signed char count of -1 is 4294967295 to Assimp; 3 fits the file */
    char bin[256];
    const char *bh = "ply\nformat binary_little_endian 1.0\nelement face 1\nproperty list char int v\nend_header\n";
    size_t n = strlen(bh);
    memcpy(bin, bh, n);
    memset(bin + n, 0, 13);
    bin[n] = (char)0xff;
    ply(bin, n + 13, false, "list of 4294967295 items");
    bin[n] = 3;
    ply(bin, n + 13, true, NULL);
    bin[n] = 4; /* 16 bytes of items in 12 */
    ply(bin, n + 13, false, "list of 4 items");
    /* big endian ushort count 0x0003 */
    const char *bb = "ply\nformat binary_big_endian 1.0\nelement face 1\nproperty list ushort int v\nend_header\n";
    n = strlen(bb);
    memcpy(bin, bb, n);
    memset(bin + n, 0, 14);
    bin[n + 1] = 3;
    ply(bin, n + 14, true, NULL);
    bin[n] = 1; /* 259 */
    ply(bin, n + 14, false, "list of 259 items");
}

/* cn_off_check on buffers, as ply() */
static void off(const char *buf, bool ok, const char *msg) {
    cnDiag d;
    memset(&d, 0, sizeof d);
    cnStatus s = cn_off_check(buf, strlen(buf), "t.off", &d);
    CHECK_MSG(ok ? s == CN_OK : s == CN_ERR_INPUT, "status %d for %.60s (message: %s)", (int)s, buf, d.message);
    if (!ok && msg) CHECK_MSG(strstr(d.message, msg) != NULL, "message '%s' lacks '%s'", d.message, msg);
}

/* The OFF checks: keyword variants, comments in the header, faces that Assimp would skip or
 * change. */
static void test_off_check(void) {
    const char *v = "0 0 0\n1 0 0\n0 1 0\n0 0 1\n";
    char b[4096];
    snprintf(b, sizeof b, "OFF\n4 4 6\n%s3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n", v);
    off(b, true, NULL);
    snprintf(b, sizeof b, "# c\nCOFF\n# c\n4 4 6\n%s\n\n3 0 2 1\r\n3 0 1 3\r3 1 2 3\n3 2 0 3\n", v);
    off(b, true, NULL);
    snprintf(b, sizeof b, "nOFF 3\n4 4 6\n%s3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n", v);
    off(b, true, NULL);
    snprintf(b, sizeof b, "4 4 6\n%s3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n", v);
    off(b, true, NULL);
    off("OFFX\n4 4 6\n", false, "does not start with OFF");
    off("OFF\n4 x 6\n", false, "the count of faces 'x' on line 2");
    snprintf(b, sizeof b, "OFF\n4 4 6\n%s3 0 2 1\n3 0 1 3\n3 1 2 3\n0          \n", v);
    off(b, false, "the face on line 10 starts with '0'");
    snprintf(b, sizeof b, "OFF\n4 4 6\n%s3 0 2 1\n3 0 1 3\n3 1 2 3\n10 0 1 2 3 0 1 2 3 0 1\n", v);
    off(b, false, "not a count of 3 to 9");
    snprintf(b, sizeof b, "OFF\n4 4 6\n%s3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0      \n", v);
    off(b, false, "has 2 of its 3 indices");
    snprintf(b, sizeof b, "OFF\n4 4 6\n%s3 0 2 1\n3 0 1 3\n3 1 2 4\n3 2 0 3\n", v);
    off(b, false, "names the vertex '4', but the file has vertices 0 to 3");
    /* a line past Assimp's buffer */
    char *big = malloc(8192);
    CHECK(big != NULL);
    if (!big) return;
    int k = snprintf(big, 8192, "OFF\n4 4 6\n0 0 0");
    memset(big + k, ' ', 4100);
    snprintf(big + k + 4100, 8192 - 4100 - (size_t)k, "\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 2 0 3\n");
    off(big, false, "line 3 is longer than 4095 characters");
    free(big);
}

void test_load(void) {
    test_ply_check();
    test_off_check();
    test_poses();
    path_limit(false);
    path_limit(true);
    expect_error("{\"dimension\": 2,\n \"parts\": [}", "2:12", "JSON syntax error");
    expect_error("[1]", "$", "one JSON object");
    expect_error("{\"dimension\":2,\"colour\":1,\"parts\":[" P2 "]}", "colour",
                 "unknown key 'colour'; the keys allowed here are: name, dimension");
    expect_error("{\"parts\":[" P2 "]}", "dimension", "missing");
    expect_error("{\"dimension\":\"2\",\"parts\":[" P2 "]}", "dimension", "must be 2 or 3");
    expect_error("{\"dimension\":4,\"parts\":[" P2 "]}", "dimension", "must be 2 or 3");
    expect_error("{\"dimension\":2,\"parts\":[]}", "parts", "no parts");
    expect_error("{\"dimension\":2}", "parts", "missing");
    expect_error("{\"dimension\":2,\"parts\":[{\"polygon\":[[0,0],[1,0],[1,1]]}]}",
                 "parts[0].name", "missing; every part needs a unique name");
    expect_error("{\"dimension\":2,\"parts\":[" P2 "," P2 "]}", "parts[1].name",
                 "'A' is already the name of parts[0]");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"colour\":\"red\","
                 "\"polygon\":[[0,0],[1,0],[1,1]]}]}",
                 "parts[0].colour", "unknown key 'colour'");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\","
                 "\"polygons\":[[[0,0],[2,0],[2,2],[1,0.5],[0,2]]]}]}",
                 "parts[0].polygons[0]", "not convex at vertex 3");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\","
                 "\"polygon\":[[0,0],[1,1],[1,0],[0,1]]}]}",
                 "parts[0].polygon", "crosses itself");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[1,0]]}]}",
                 "parts[0].polygon", "at least 3 points");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[2,0]]}]}",
                 "parts[0].polygon", "no area");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[1,\"x\"],[1,1]]}]}",
                 "parts[0].polygon[1][1]", "expected a number");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[1,0,5],[1,1]]}]}",
                 "parts[0].polygon[1]", "array of 2 numbers");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[1e999,0],[1,1]]}]}",
                 "1:59", "real number overflow");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"polygon\":[[0,0],[NaN,0],[1,1]]}]}",
                 "1:57", "invalid token");
    expect_error("{\"dimension\":2,\"dimension\":2,\"parts\":[" P2 "]}", "1:26", "duplicate object key");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,1,1]}}]}",
                 "parts[0].box", "'box' is a 3-D shape but the assembly has dimension 2");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[1,0,1]}}]}",
                 "parts[0].box.max[1]", "must be greater than min[1]");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"hull\":[[0,0,0],[1,0,0],[0,1,0],[1,1,0]]}]}",
                 "parts[0].hull", "do not span a volume");
    expect_error("{\"dimension\":3,\"parts\":[{\"name\":\"A\"}]}", "parts[0]", "has no shape");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"density\":1,\"mass\":2,"
                 "\"polygon\":[[0,0],[1,0],[1,1]]}]}",
                 "parts[0]", "either \"density\" or \"mass\"");
    expect_error("{\"dimension\":2,\"parts\":[{\"name\":\"A\",\"mass\":-2,"
                 "\"polygon\":[[0,0],[1,0],[1,1]]}]}",
                 "parts[0].mass", "greater than zero");
    expect_error("{\"dimension\":2,\"gravity\":[0,0],\"parts\":[" P2 "]}", "gravity", "must not be zero");
    expect_error("{\"dimension\":2,\"friction\":-1,\"parts\":[" P2 "]}", "friction", "zero or positive");
    expect_error("{\"dimension\":2,\"friction_pairs\":[{\"parts\":[\"A\",\"Z\"],\"mu\":0.2}],"
                 "\"parts\":[" P2 "]}",
                 "friction_pairs[0].parts[1]", "no part is named 'Z'");
    expect_error("{\"dimension\":2,\"fixels\":[{\"part\":\"Q\",\"point\":[1,0.5],\"normal\":[-1,0]}],"
                 "\"parts\":[" P2 "]}",
                 "fixels[0].part", "no part is named 'Q'");
    expect_error("{\"dimension\":2,\"fixels\":[{\"part\":\"A\",\"point\":[3,0.5],\"normal\":[-1,0]}],"
                 "\"parts\":[" P2 "]}",
                 "fixels[0].point", "away from part 'A'");
    expect_error("{\"dimension\":2,\"fixels\":[{\"part\":\"A\",\"point\":[1,0.5],\"normal\":[1,0]}],"
                 "\"parts\":[" P2 "]}",
                 "fixels[0].normal", "must point into part 'A'");
    expect_error("{\"dimension\":2,\"parts\":[" P2 ",{\"name\":\"B\",\"polygon\":"
                 "[[0.5,0.5],[2,0.5],[2,2],[0.5,2]]}]}",
                 "parts[1]", "'B' overlaps part 'A' (parts[0]) by 0.5");
    expect_error("{\"dimension\":2,\"tolerance\":0.5,\"parts\":[" P2 "]}", "tolerance", "from 1e-12 to 0.1");

    /* good files load: defaults */
    cnAssembly *a = load_ok("{\"dimension\":3,\"parts\":[{\"name\":\"A\",\"box\":"
                            "{\"min\":[0,0,0],\"max\":[1,1,1]}}]}");
    if (a) {
        CHECK(a->gravity[2] == -9.81 && a->gravity[0] == 0);
        CHECK(a->density == 1 && a->friction == 0 && a->friction_dirs == 8);
        CHECK_NEAR(a->contact_tol, 1e-6 * sqrt(3.0), 1e-15);
        cn_assembly_free(a);
    }
    a = load_ok("{\"dimension\":2,\"friction\":0.1,\"friction_pairs\":[{\"parts\":[\"B\",\"A\"],"
                "\"mu\":0.3}],\"parts\":[" P2 ",{\"name\":\"B\",\"polygon\":[[1,0],[2,0],[2,1]]},"
                "{\"name\":\"C\",\"polygon\":[[2,0],[3,0],[3,1]]}]}");
    if (a) {
        CHECK(cn_assembly_mu(a, 0, 1) == 0.3 && cn_assembly_mu(a, 1, 0) == 0.3);
        CHECK(cn_assembly_mu(a, 1, 2) == 0.1);
        CHECK(cn_assembly_mu(a, -1, 2) == 0);
        cn_assembly_free(a);
    }
}
