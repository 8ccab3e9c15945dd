/* Unit tests of src/io/mesh.c and mesh_headers.c (cn_mesh_read, cn_ply_check, cn_off_check):
 * small mesh files written here in each format cairn reads, whose faces and extent are known by
 * construction. Checked: a cube as OBJ (two objects, the second moved), PLY and OFF with its six
 * quadrilaterals kept as written, a tetrahedron as ASCII STL; each scaled as asked, each face's
 * number in the file, each closed and oriented by cn_mesh_check; a cube with a face missing read
 * but refused by cn_mesh_check; and the refusals, each an input error naming the file: a format
 * cairn does not read, a missing or empty file, an OFF face naming a vertex it does not have, a
 * PLY header ended in another case (which Assimp would read forever), a file with no faces. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core.h"
#include "helpers.h"
#include "io.h"

static char dir[] = "/tmp/cairn_meshXXXXXX";

/* Write text to dir/name; its path in path. */
static bool put(const char *name, const char *text, char *path, size_t n) {
    snprintf(path, n, "%s/%s", dir, name);
    FILE *f = fopen(path, "wb");
    if (!f) return false;
    bool ok = fputs(text, f) >= 0;
    return fclose(f) == 0 && ok;
}

/* The extent of a mesh's vertices. */
static void extent(const cnMesh *m, double lo[3], double hi[3]) {
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int v = 0; v < m->nverts; v++)
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], m->verts[v][k]), hi[k] = fmax(hi[k], m->verts[v][k]);
}

static bool box_is(const cnMesh *m, const double lo[3], const double hi[3]) {
    double a[3], b[3];
    extent(m, a, b);
    for (int k = 0; k < 3; k++)
        if (fabs(a[k] - lo[k]) > 1e-6 * fabs(hi[k] - lo[k]) || fabs(b[k] - hi[k]) > 1e-6 * fabs(hi[k] - lo[k]))
            return false;
    return true;
}

/* Every face has `corners` corners, faces are numbered 1.. in file order, and the mesh is a
 * closed oriented surface (cn_mesh_check). */
static bool faces_are(cnMesh *m, int nfaces, int corners) {
    if (m->nfaces != nfaces) return false;
    for (int f = 0; f < m->nfaces; f++)
        if (m->start[f + 1] - m->start[f] != corners || m->face_id[f] != f + 1) return false;
    cnDiag d;
    return cn_mesh_check(m, 1e-9, &d) == CN_OK;
}

static void free_meshes(cnMesh *ms, int n) {
    for (int i = 0; i < n; i++) cn_mesh_free(&ms[i]);
    cn_free(ms);
}

#define CUBE_V "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n"

static const char *OBJ_TWO =
    "# two unit cubes, the second moved by 3 along x\n"
    "o A\n" CUBE_V
    "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n"
    "o B\nv 3 0 0\nv 4 0 0\nv 4 1 0\nv 3 1 0\nv 3 0 1\nv 4 0 1\nv 4 1 1\nv 3 1 1\n"
    "f 9 12 11 10\nf 13 14 15 16\nf 9 10 14 13\nf 10 11 15 14\nf 11 12 16 15\nf 12 9 13 16\n";

static const char *OBJ_OPEN = "o open\n" CUBE_V "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\n";

static const char *PLY_CUBE =
    "ply\nformat ascii 1.0\nelement vertex 8\nproperty float x\nproperty float y\nproperty float z\n"
    "element face 6\nproperty list uchar int vertex_indices\nend_header\n"
    "0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

static const char *OFF_CUBE =
    "OFF\n8 6 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "4 0 3 2 1\n4 4 5 6 7\n4 0 1 5 4\n4 1 2 6 5\n4 2 3 7 6\n4 3 0 4 7\n";

static const char *STL_TET =
    "solid tet\n"
    "facet normal 0 0 -1\nouter loop\nvertex 0 0 0\nvertex 0 1 0\nvertex 1 0 0\nendloop\nendfacet\n"
    "facet normal 0 -1 0\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 0 1\nendloop\nendfacet\n"
    "facet normal -1 0 0\nouter loop\nvertex 0 0 0\nvertex 0 0 1\nvertex 0 1 0\nendloop\nendfacet\n"
    "facet normal 1 1 1\nouter loop\nvertex 1 0 0\nvertex 0 1 0\nvertex 0 0 1\nendloop\nendfacet\n"
    "endsolid tet\n";

static void read_formats(void) {
    char path[512];
    cnMesh *ms = NULL;
    int n = 0;
    cnDiag d;
    /* OBJ: two objects, scaled by 2 */
    if (put("two.obj", OBJ_TWO, path, sizeof path) && cn_mesh_read(path, "two.obj", 2, &ms, &n, &d) == CN_OK) {
        CHECK_MSG(n == 2, "two.obj: %d meshes", n);
        if (n == 2) {
            CHECK(!strcmp(ms[0].name, "A") && !strcmp(ms[1].name, "B"));
            CHECK(faces_are(&ms[0], 6, 4) && faces_are(&ms[1], 6, 4));
            CHECK(box_is(&ms[0], (double[]){0, 0, 0}, (double[]){2, 2, 2}));
            CHECK(box_is(&ms[1], (double[]){6, 0, 0}, (double[]){8, 2, 2}));
        }
        free_meshes(ms, n);
    } else
        CHECK_MSG(false, "two.obj: %s", d.message);
    /* PLY and OFF: the same cube, at 1e-3 */
    const char *names[2] = {"cube.ply", "cube.off"}, *texts[2] = {PLY_CUBE, OFF_CUBE};
    for (int i = 0; i < 2; i++) {
        if (put(names[i], texts[i], path, sizeof path) && cn_mesh_read(path, names[i], 1e-3, &ms, &n, &d) == CN_OK) {
            CHECK_MSG(n == 1 && faces_are(&ms[0], 6, 4) && box_is(&ms[0], (double[]){0, 0, 0}, (double[]){1e-3, 1e-3, 1e-3}),
                      "%s: %d meshes, %d faces", names[i], n, n ? ms[0].nfaces : 0);
            free_meshes(ms, n);
        } else
            CHECK_MSG(false, "%s: %s", names[i], d.message);
    }
    /* STL: a tetrahedron of four triangles */
    if (put("tet.stl", STL_TET, path, sizeof path) && cn_mesh_read(path, "tet.stl", 1, &ms, &n, &d) == CN_OK) {
        CHECK_MSG(n == 1 && faces_are(&ms[0], 4, 3) && box_is(&ms[0], (double[]){0, 0, 0}, (double[]){1, 1, 1}),
                  "tet.stl: %d meshes", n);
        free_meshes(ms, n);
    } else
        CHECK_MSG(false, "tet.stl: %s", d.message);
    /* a face missing: read as written, refused as a solid */
    if (put("open.obj", OBJ_OPEN, path, sizeof path) && cn_mesh_read(path, "open.obj", 1, &ms, &n, &d) == CN_OK) {
        CHECK(n == 1 && ms[0].nfaces == 5);
        if (n == 1) CHECK(cn_mesh_check(&ms[0], 1e-9, &d) == CN_ERR_INPUT && d.message[0]);
        free_meshes(ms, n);
    } else
        CHECK_MSG(false, "open.obj: %s", d.message);
}

/* An input error whose message names the file as shown and says `what`. */
static void refused(const char *name, const char *text, const char *what) {
    char path[512];
    cnMesh *ms = NULL;
    int n = -1;
    cnDiag d;
    cn_diag_clear(&d);
    if (text && !put(name, text, path, sizeof path)) {
        CHECK_MSG(false, "cannot write %s", name);
        return;
    }
    if (!text) snprintf(path, sizeof path, "%s/%s", dir, name);
    cnStatus s = cn_mesh_read(path, name, 1, &ms, &n, &d);
    CHECK_MSG(s == CN_ERR_INPUT && !ms && n == 0 && strstr(d.message, name) && strstr(d.message, what),
              "%s: status %d, message '%s' (want '%s')", name, (int)s, d.message, what);
    free_meshes(ms, n > 0 ? n : 0);
}

static void refusals(void) {
    refused("cube.gltf", "{}", "give an .obj, .stl, .ply or .off file");
    refused("missing.obj", NULL, "cannot open");
    refused("empty.obj", "", "it is empty");
    refused("points.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\n", "no faces");
    refused("far.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 9\n", "far.off");
    refused("case.ply",
            "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
            "element face 1\nproperty list uchar int vertex_indices\nend_hEader\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
            "end_header");
}

void test_mesh(void) {
    if (!mkdtemp(dir)) {
        CHECK_MSG(false, "mkdtemp");
        return;
    }
    read_formats();
    refusals();
    const char *files[] = {"two.obj", "cube.ply", "cube.off", "tet.stl", "open.obj", "cube.gltf",
                           "empty.obj", "points.obj", "far.off", "case.ply"};
    char path[512];
    for (size_t i = 0; i < sizeof files / sizeof *files; i++) {
        snprintf(path, sizeof path, "%s/%s", dir, files[i]);
        remove(path);
    }
    rmdir(dir);
}
