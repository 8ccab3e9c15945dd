/* The assembly as cairn understood it, for any 3-D viewer: every convex piece of every part where
 * its pose put it (2-D pieces flat in z = 0), supports in a material of their own. Wavefront OBJ
 * (with its .mtl) or glTF 2.0 (one self-contained .gltf: the geometry a base64 data URI). */
#include <jansson.h>
#include <math.h>
#include <stdint.h>
#include <string.h>

#include "cairn/cairn.h"
#include "core.h"

/* Part colours: supports grey, the others in turn (the figures' palette). */
static const double PALETTE[][3] = {{0.56, 0.71, 0.85}, {0.90, 0.78, 0.54}, {0.66, 0.83, 0.62}, {0.85, 0.64, 0.78},
                                    {0.62, 0.83, 0.82}, {0.83, 0.71, 0.62}, {0.72, 0.69, 0.88}, {0.79, 0.85, 0.56}};
#define NPAL ((int)(sizeof PALETTE / sizeof PALETTE[0]))
static const double SUPPORT[3] = {0.6, 0.6, 0.6};

static const double *colour(const cnAssembly *a, int i) {
    return a->parts[i].fixed ? SUPPORT : PALETTE[i % NPAL];
}

/* The faces of a piece as vertex loops: a 3-D piece's faces, or a 2-D polygon as one face. */
static int nfaces(const cnPiece *pc, int dim) { return dim == 2 ? 1 : pc->nfaces; }
static int face_len(const cnPiece *pc, int dim, int f) { return dim == 2 ? pc->nverts : pc->faces[f].nverts; }
static int face_vert(const cnPiece *pc, int dim, int f, int k) { return dim == 2 ? k : pc->faces[f].verts[k]; }

static cnStatus export_obj(FILE *f, FILE *mtl, const char *mtl_name, const cnAssembly *a) {
    fprintf(f, "# %s\n# written by cairn %s: every convex piece of every part as loaded (poses applied)%s\n",
            a->name ? a->name : "assembly", cn_version(), a->dim == 2 ? "; 2-D pieces flat in z = 0" : "");
    if (mtl_name) fprintf(f, "mtllib %s\n", mtl_name);
    if (mtl) {
        fprintf(mtl, "# materials of %s (cairn)\nnewmtl support\nKd %.3f %.3f %.3f\n", a->name ? a->name : "assembly",
                SUPPORT[0], SUPPORT[1], SUPPORT[2]);
        for (int c = 0; c < NPAL; c++)
            fprintf(mtl, "newmtl part%d\nKd %.3f %.3f %.3f\n", c, PALETTE[c][0], PALETTE[c][1], PALETTE[c][2]);
    }
    long base = 1;
    for (int i = 0; i < a->nreal; i++) {
        const cnPart *p = &a->parts[i];
        fprintf(f, "o %s\n", p->name);
        if (p->fixed) fprintf(f, "usemtl support\n");
        else fprintf(f, "usemtl part%d\n", i % NPAL);
        for (int s = 0; s < p->npieces; s++) {
            const cnPiece *pc = &p->pieces[s];
            fprintf(f, "g %s.piece%d\n", p->name, s);
            for (int v = 0; v < pc->nverts; v++)
                fprintf(f, "v %.17g %.17g %.17g\n", pc->verts[v][0], pc->verts[v][1], a->dim == 2 ? 0.0 : pc->verts[v][2]);
            for (int fc = 0; fc < nfaces(pc, a->dim); fc++) {
                fputc('f', f);
                for (int k = 0; k < face_len(pc, a->dim, fc); k++) fprintf(f, " %ld", base + face_vert(pc, a->dim, fc, k));
                fputc('\n', f);
            }
            base += pc->nverts;
        }
    }
    bool bad = fflush(f) != 0 || ferror(f);
    if (mtl) bad |= fflush(mtl) != 0 || ferror(mtl);
    return bad ? CN_ERR_IO : CN_OK;
}

static char *base64(const unsigned char *in, size_t n) {
    static const char T[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    char *out = cn_malloc(4 * ((n + 2) / 3) + 1);
    if (!out) return NULL;
    size_t o = 0;
    for (size_t i = 0; i < n; i += 3) {
        uint32_t x = (uint32_t)in[i] << 16 | (i + 1 < n ? (uint32_t)in[i + 1] << 8 : 0) | (i + 2 < n ? in[i + 2] : 0);
        out[o++] = T[x >> 18 & 63];
        out[o++] = T[x >> 12 & 63];
        out[o++] = i + 1 < n ? T[x >> 6 & 63] : '=';
        out[o++] = i + 2 < n ? T[x & 63] : '=';
    }
    out[o] = '\0';
    return out;
}

/* glTF 2.0: per piece a mesh primitive (float positions, uint32 triangle fans of its convex
 * faces, no normals: viewers then shade flat, as the spec says), per part a node and a mesh. */
/* A write that failed: out of memory, or the stream's error. */
static cnStatus write_failed(cnDiag *diag, cnStatus s) {
    if (s == CN_ERR_MEMORY) return cn_diag_set(diag, s, "", "out of memory writing the export");
    return cn_diag_set(diag, s, "", "cannot write the export");
}

static cnStatus export_gltf(FILE *f, const cnAssembly *a, cnDiag *diag) {
    size_t nv = 0, ni = 0;
    int npieces = 0;
    for (int i = 0; i < a->nreal; i++)
        for (int s = 0; s < a->parts[i].npieces; s++) {
            const cnPiece *pc = &a->parts[i].pieces[s];
            nv += (size_t)pc->nverts;
            for (int fc = 0; fc < nfaces(pc, a->dim); fc++) ni += 3 * (size_t)(face_len(pc, a->dim, fc) - 2);
            npieces++;
        }
    size_t bytes = nv * 12 + ni * 4;
    unsigned char *buf = cn_malloc(bytes + 1);
    if (!buf) return write_failed(diag, CN_ERR_MEMORY);
    json_t *doc = json_object(), *accessors = json_array(), *views = json_array(), *meshes = json_array(),
           *nodes = json_array(), *materials = json_array(), *scene_nodes = json_array();
    json_object_set_new(doc, "asset", json_pack("{s:s, s:s}", "version", "2.0", "generator", "cairn"));
    for (int i = 0; i < a->nreal; i++) {
        const double *c = colour(a, i);
        json_array_append_new(materials, json_pack("{s:s, s:{s:[f,f,f,f], s:f, s:f}, s:b}", "name",
                                                   a->parts[i].fixed ? "support" : "part", "pbrMetallicRoughness",
                                                   "baseColorFactor", c[0], c[1], c[2], 1.0, "metallicFactor", 0.0,
                                                   "roughnessFactor", 0.9, "doubleSided", a->dim == 2));
    }
    size_t off = 0;
    bool fits = true;
    for (int i = 0; i < a->nreal; i++) {
        const cnPart *p = &a->parts[i];
        /* the vertices relative to the middle of the part's box, which is its node's translation:
         * single precision keeps each part's shape however far it is from the origin */
        double mid[3] = {0, 0, 0}, blo[3] = {INFINITY, INFINITY, INFINITY}, bhi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nverts; v++)
                for (int k = 0; k < a->dim; k++)
                    blo[k] = fmin(blo[k], p->pieces[s].verts[v][k]), bhi[k] = fmax(bhi[k], p->pieces[s].verts[v][k]);
        for (int k = 0; k < a->dim; k++)
            if (blo[k] <= bhi[k]) mid[k] = 0.5 * blo[k] + 0.5 * bhi[k];
        json_t *prims = json_array();
        for (int s = 0; s < p->npieces; s++) {
            const cnPiece *pc = &p->pieces[s];
            float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
            size_t pos_off = off;
            for (int v = 0; v < pc->nverts; v++)
                for (int k = 0; k < 3; k++) {
                    float x = (float)(a->dim == 2 && k == 2 ? 0.0 : pc->verts[v][k] - mid[k]);
                    fits &= isfinite(x);
                    memcpy(buf + off, &x, 4);
                    off += 4;
                    lo[k] = fminf(lo[k], x), hi[k] = fmaxf(hi[k], x);
                }
            size_t idx_off = off, nidx = 0;
            for (int fc = 0; fc < nfaces(pc, a->dim); fc++)
                for (int k = 1; k + 1 < face_len(pc, a->dim, fc); k++) {
                    uint32_t t[3] = {(uint32_t)face_vert(pc, a->dim, fc, 0), (uint32_t)face_vert(pc, a->dim, fc, k),
                                     (uint32_t)face_vert(pc, a->dim, fc, k + 1)};
                    memcpy(buf + off, t, 12);
                    off += 12, nidx += 3;
                }
            int vp = (int)json_array_size(views);
            json_array_append_new(views, json_pack("{s:i, s:I, s:I, s:i}", "buffer", 0, "byteOffset", (json_int_t)pos_off,
                                                   "byteLength", (json_int_t)(idx_off - pos_off), "target", 34962));
            json_array_append_new(views, json_pack("{s:i, s:I, s:I, s:i}", "buffer", 0, "byteOffset", (json_int_t)idx_off,
                                                   "byteLength", (json_int_t)(off - idx_off), "target", 34963));
            int ap = (int)json_array_size(accessors);
            json_array_append_new(accessors, json_pack("{s:i, s:i, s:i, s:s, s:[f,f,f], s:[f,f,f]}", "bufferView", vp,
                                                       "componentType", 5126, "count", pc->nverts, "type", "VEC3",
                                                       "min", (double)lo[0], (double)lo[1], (double)lo[2], "max",
                                                       (double)hi[0], (double)hi[1], (double)hi[2]));
            json_array_append_new(accessors, json_pack("{s:i, s:i, s:I, s:s}", "bufferView", vp + 1, "componentType",
                                                       5125, "count", (json_int_t)nidx, "type", "SCALAR"));
            json_array_append_new(prims, json_pack("{s:{s:i}, s:i, s:i, s:i}", "attributes", "POSITION", ap, "indices",
                                                   ap + 1, "material", i, "mode", 4));
        }
        json_array_append_new(meshes, json_pack("{s:s, s:o}", "name", p->name, "primitives", prims));
        json_array_append_new(nodes, json_pack("{s:s, s:i, s:[f,f,f], s:{s:b}}", "name", p->name, "mesh", i, "translation",
                                               mid[0], mid[1], mid[2], "extras", "fixed", p->fixed));
        json_array_append_new(scene_nodes, json_integer(i));
    }
    /* every object built (json_pack fails only on memory, or on a number that is not finite) */
    bool built = json_array_size(accessors) == 2 * (size_t)npieces && json_array_size(views) == 2 * (size_t)npieces &&
                 json_array_size(meshes) == (size_t)a->nreal && json_array_size(nodes) == (size_t)a->nreal &&
                 json_array_size(materials) == (size_t)a->nreal;
    for (size_t m = 0; built && m < json_array_size(meshes); m++)
        built = json_array_size(json_object_get(json_array_get(meshes, m), "primitives")) ==
                (size_t)a->parts[m].npieces;
    if (!fits || !built) {
        cn_free(buf);
        json_decref(doc), json_decref(accessors), json_decref(views), json_decref(meshes), json_decref(nodes),
            json_decref(materials), json_decref(scene_nodes);
        if (fits) return write_failed(diag, CN_ERR_MEMORY);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "a part spans more than single precision holds (about 3e38), "
                           "which glTF stores: export it as OBJ (--to obj)");
    }
    char *b64 = base64(buf, off);
    cn_free(buf);
    if (!b64) {
        json_decref(doc), json_decref(accessors), json_decref(views), json_decref(meshes), json_decref(nodes),
            json_decref(materials), json_decref(scene_nodes);
        return write_failed(diag, CN_ERR_MEMORY);
    }
    json_t *uri = json_sprintf("data:application/octet-stream;base64,%s", b64);
    cn_free(b64);
    json_object_set_new(doc, "buffers", json_pack("[{s:I, s:o}]", "byteLength", (json_int_t)off, "uri", uri));
    json_object_set_new(doc, "bufferViews", views);
    json_object_set_new(doc, "accessors", accessors);
    json_object_set_new(doc, "materials", materials);
    json_object_set_new(doc, "meshes", meshes);
    json_object_set_new(doc, "nodes", nodes);
    json_object_set_new(doc, "scenes", json_pack("[{s:s, s:o}]", "name", a->name ? a->name : "assembly", "nodes", scene_nodes));
    json_object_set_new(doc, "scene", json_integer(0));
    int rc = json_dumpf(doc, f, JSON_INDENT(1) | JSON_REAL_PRECISION(9));
    json_decref(doc);
    return rc != 0 || fflush(f) != 0 || ferror(f) ? write_failed(diag, CN_ERR_IO) : CN_OK;
}

cnStatus cn_export(FILE *f, const cnAssembly *a, const char *format, FILE *mtl, const char *mtl_name, cnDiag *diag) {
    if (!strcmp(format, "gltf")) return export_gltf(f, a, diag);
    if (strcmp(format, "obj")) return cn_diag_set(diag, CN_ERR_INPUT, "", "no export format '%.40s': obj or gltf", format);
    cnStatus s = export_obj(f, mtl, mtl_name, a);
    return s ? write_failed(diag, s) : CN_OK;
}
