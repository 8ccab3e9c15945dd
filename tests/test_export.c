/* cn_export read back in C: OBJ (with its MTL) and glTF 2.0 of assemblies built here, parsed by a
 * minimal OBJ reader and by jansson plus a base64 decoder, checked against closed forms (corners,
 * volumes, areas), against each other, under translation, and on bad formats and failing writes. */
#include <jansson.h>
#include <float.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

/* Capacities of the parsed form: far above what the assemblies here need; exceeding one is a
 * failure, not an overflow. */
#define MAXV 32
#define MAXF 64
#define MAXI 256
#define MAXPC 8
#define MAXPARTS 8

/* One piece as read back: its vertices and its faces (vertex loops, indices into its vertices). */
typedef struct {
    int nv, nf, ni;
    double v[MAXV][3];
    int fstart[MAXF + 1];
    int fidx[MAXI];
} Piece;

typedef struct {
    char name[64];
    char mtl[32]; /* OBJ: its usemtl; glTF: its material's name */
    int fixed;    /* glTF: extras.fixed; OBJ: -1 (not carried but by the material) */
    double t[3];  /* glTF: the node's translation (added to its pieces' vertices); OBJ: 0 */
    int npieces;
    Piece pieces[MAXPC];
} Part;

typedef struct {
    int nparts;
    Part parts[MAXPARTS];
    char mtllib[64];
} Mesh;

/* ---- reading back ---- */

static bool add_face(Piece *pc, const int *idx, int n) {
    if (pc->nf >= MAXF || pc->ni + n > MAXI) return false;
    pc->fstart[pc->nf] = pc->ni;
    for (int k = 0; k < n; k++)
        pc->fidx[pc->ni++] = idx[k];
    pc->fstart[++pc->nf] = pc->ni;
    return true;
}

/* OBJ: o starts a part, g a piece, v a vertex of the current piece, f a face of it (1-based,
 * counted over the file; a face may use only its own piece's vertices). Anything else fails. */
static bool parse_obj(const char *text, Mesh *m) {
    memset(m, 0, sizeof *m);
    Part *p = NULL;
    Piece *pc = NULL;
    int total = 0, first = 0; /* vertices so far; the current piece's first */
    bool ok = true;
    const char *s = text;
    while (ok && *s) {
        const char *e = strchr(s, '\n');
        size_t n = e ? (size_t)(e - s) : strlen(s);
        char line[512];
        if (n >= sizeof line) return false;
        memcpy(line, s, n);
        line[n] = '\0';
        s += n + (e ? 1 : 0);
        if (!line[0] || line[0] == '#') continue;
        if (!strncmp(line, "mtllib ", 7)) {
            snprintf(m->mtllib, sizeof m->mtllib, "%s", line + 7);
        } else if (!strncmp(line, "o ", 2)) {
            if (m->nparts >= MAXPARTS) return false;
            p = &m->parts[m->nparts++];
            p->fixed = -1;
            snprintf(p->name, sizeof p->name, "%s", line + 2);
            pc = NULL;
        } else if (!strncmp(line, "usemtl ", 7)) {
            if (!p) return false;
            snprintf(p->mtl, sizeof p->mtl, "%s", line + 7);
        } else if (!strncmp(line, "g ", 2)) {
            if (!p || p->npieces >= MAXPC) return false;
            char want[128];
            snprintf(want, sizeof want, "%s.piece%d", p->name, p->npieces);
            ok = !strcmp(line + 2, want);
            pc = &p->pieces[p->npieces++];
            first = total;
        } else if (!strncmp(line, "v ", 2)) {
            if (!pc || pc->nf || pc->nv >= MAXV) return false;
            char *q = line + 2, *end;
            for (int k = 0; k < 3; k++, q = end) {
                pc->v[pc->nv][k] = strtod(q, &end);
                ok = ok && end != q;
            }
            ok = ok && *q == '\0';
            pc->nv++, total++;
        } else if (!strncmp(line, "f ", 2)) {
            if (!pc) return false;
            int idx[MAXV], k = 0;
            char *q = line + 1, *end;
            for (;;) {
                long x = strtol(q, &end, 10);
                if (end == q) break;
                if (k >= MAXV || x - 1 < first || x - 1 >= first + pc->nv) return false;
                idx[k++] = (int)(x - 1 - first);
                q = end;
            }
            ok = ok && *q == '\0' && k >= 3 && add_face(pc, idx, k);
        } else {
            return false;
        }
    }
    return ok;
}

static int b64val(int c) {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    return c == '+' ? 62 : c == '/' ? 63 : -1;
}

/* Strict base64 (padded, no whitespace) into a new buffer; NULL if malformed. */
static unsigned char *b64decode(const char *s, size_t *n) {
    size_t len = strlen(s);
    if (len % 4) return NULL;
    unsigned char *out = malloc(len / 4 * 3 + 1);
    if (!out) return NULL;
    size_t o = 0;
    for (size_t i = 0; i < len; i += 4) {
        int pad = (s[i + 3] == '=') + (s[i + 2] == '=');
        if (pad && i + 4 != len) break;
        int c[4];
        for (int k = 0; k < 4; k++)
            c[k] = k >= 4 - pad ? 0 : b64val((unsigned char)s[i + k]);
        if (c[0] < 0 || c[1] < 0 || c[2] < 0 || c[3] < 0) break;
        uint32_t x =
            (uint32_t)c[0] << 18 | (uint32_t)c[1] << 12 | (uint32_t)c[2] << 6 | (uint32_t)c[3];
        out[o++] = (unsigned char)(x >> 16);
        if (pad < 2) out[o++] = (unsigned char)(x >> 8);
        if (pad < 1) out[o++] = (unsigned char)x;
        if (i + 4 == len) {
            *n = o;
            return out;
        }
    }
    free(out);
    return NULL;
}

static uint32_t le32(const unsigned char *b) {
    return (uint32_t)b[0] | (uint32_t)b[1] << 8 | (uint32_t)b[2] << 16 | (uint32_t)b[3] << 24;
}

/* A member's string, "" when absent or not a string. */
static const char *jstr(const json_t *o, const char *key) {
    const char *s = json_string_value(json_object_get(o, key));
    return s ? s : "";
}

static int jint(const json_t *o, const char *key) {
    const json_t *x = json_object_get(o, key);
    return json_is_integer(x) ? (int)json_integer_value(x) : -1;
}

/* A bufferView's bytes [off, off+len) that lie in the buffer, or false. */
static bool view_range(const json_t *doc, int view, size_t blen, size_t *off, size_t *len) {
    const json_t *bv = json_array_get(json_object_get(doc, "bufferViews"), (size_t)view);
    if (!bv || jint(bv, "buffer") != 0) return false;
    int o = jint(bv, "byteOffset"), l = jint(bv, "byteLength");
    if (o < 0 || l < 0 || (size_t)o + (size_t)l > blen || o % 4) return false;
    *off = (size_t)o, *len = (size_t)l;
    return true;
}

/* One primitive: float VEC3 positions (their accessor's min and max exactly theirs) and uint32
 * triangles (mode 4), each triangle a face. */
static bool read_prim(const json_t *doc, const json_t *prim, const unsigned char *buf, size_t blen,
                      Piece *pc, int *material) {
    const json_t *acc = json_object_get(doc, "accessors");
    const json_t *pa =
        json_array_get(acc, (size_t)jint(json_object_get(prim, "attributes"), "POSITION"));
    const json_t *ia = json_array_get(acc, (size_t)jint(prim, "indices"));
    *material = jint(prim, "material");
    if (!pa || !ia || jint(prim, "mode") != 4) return false;
    if (jint(pa, "componentType") != 5126 || strcmp(jstr(pa, "type"), "VEC3")) return false;
    if (jint(ia, "componentType") != 5125 || strcmp(jstr(ia, "type"), "SCALAR")) return false;
    int nv = jint(pa, "count"), ni = jint(ia, "count");
    size_t po, pl, io, il;
    if (nv < 3 || nv > MAXV || ni < 3 || ni % 3 || ni > MAXI) return false;
    if (!view_range(doc, jint(pa, "bufferView"), blen, &po, &pl) ||
        !view_range(doc, jint(ia, "bufferView"), blen, &io, &il) || pl != 12 * (size_t)nv ||
        il != 4 * (size_t)ni)
        return false;
    float lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int v = 0; v < nv; v++)
        for (int k = 0; k < 3; k++) {
            uint32_t u = le32(buf + po + 12 * (size_t)v + 4 * (size_t)k);
            float x;
            memcpy(&x, &u, 4);
            pc->v[v][k] = x;
            lo[k] = fminf(lo[k], x), hi[k] = fmaxf(hi[k], x);
        }
    pc->nv = nv;
    const json_t *mn = json_object_get(pa, "min"), *mx = json_object_get(pa, "max");
    for (int k = 0; k < 3; k++)
        if ((float)json_number_value(json_array_get(mn, (size_t)k)) != lo[k] ||
            (float)json_number_value(json_array_get(mx, (size_t)k)) != hi[k])
            return false;
    for (int t = 0; t < ni; t += 3) {
        int tri[3];
        for (int k = 0; k < 3; k++) {
            uint32_t x = le32(buf + io + 4 * (size_t)(t + k));
            if (x >= (uint32_t)nv) return false;
            tri[k] = (int)x;
        }
        if (!add_face(pc, tri, 3)) return false;
    }
    return true;
}

/* glTF: asset 2.0, one buffer as a base64 data URI of byteLength bytes, one node per part (its
 * name, mesh, extras.fixed), listed by scene 0 in order; a primitive per piece. */
static bool parse_gltf(const char *text, Mesh *m, bool *double_sided) {
    memset(m, 0, sizeof *m);
    json_error_t err;
    json_t *doc = json_loads(text, 0, &err);
    if (!doc) return false;
    bool ok = false;
    unsigned char *buf = NULL;
    size_t blen = 0;
    const char *prefix = "data:application/octet-stream;base64,";
    const json_t *b0 = json_array_get(json_object_get(doc, "buffers"), 0);
    const char *uri = json_string_value(json_object_get(b0, "uri"));
    const json_t *nodes = json_object_get(doc, "nodes"), *meshes = json_object_get(doc, "meshes");
    const json_t *mats = json_object_get(doc, "materials");
    const json_t *scene = json_array_get(json_object_get(doc, "scenes"), 0);
    const json_t *snodes = json_object_get(scene, "nodes");
    if (strcmp(jstr(json_object_get(doc, "asset"), "version"), "2.0") || jint(doc, "scene") != 0 ||
        !uri || strncmp(uri, prefix, strlen(prefix)) ||
        json_array_size(json_object_get(doc, "buffers")) != 1)
        goto done;
    buf = b64decode(uri + strlen(prefix), &blen);
    if (!buf || jint(b0, "byteLength") != (int)blen || json_array_size(nodes) > MAXPARTS ||
        json_array_size(snodes) != json_array_size(nodes))
        goto done;
    *double_sided = true;
    for (size_t i = 0; i < json_array_size(nodes); i++) {
        const json_t *node = json_array_get(nodes, i);
        const json_t *mesh = json_array_get(meshes, (size_t)jint(node, "mesh"));
        const json_t *prims = json_object_get(mesh, "primitives");
        const json_t *fx = json_object_get(json_object_get(node, "extras"), "fixed");
        const char *name = json_string_value(json_object_get(node, "name"));
        if (!mesh || !name || !json_is_boolean(fx) ||
            json_integer_value(json_array_get(snodes, i)) != (json_int_t)i ||
            strcmp(jstr(mesh, "name"), name) || json_array_size(prims) > MAXPC)
            goto done;
        Part *p = &m->parts[m->nparts++];
        snprintf(p->name, sizeof p->name, "%s", name);
        p->fixed = json_is_true(fx);
        for (size_t s = 0; s < json_array_size(prims); s++) {
            int mat;
            if (!read_prim(doc, json_array_get(prims, s), buf, blen, &p->pieces[p->npieces++],
                           &mat))
                goto done;
            const json_t *mo = json_array_get(mats, (size_t)mat);
            if (!mo) goto done;
            snprintf(p->mtl, sizeof p->mtl, "%s", jstr(mo, "name"));
            *double_sided = *double_sided && json_is_true(json_object_get(mo, "doubleSided"));
        }
        /* the node's translation: the pieces are stored about it */
        const json_t *tr = json_object_get(node, "translation");
        if (json_array_size(tr) != 3) goto done;
        for (int k = 0; k < 3; k++) {
            p->t[k] = json_number_value(json_array_get(tr, (size_t)k));
            if (!json_is_number(json_array_get(tr, (size_t)k)) || !isfinite(p->t[k])) goto done;
        }
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nv; v++)
                for (int k = 0; k < 3; k++) p->pieces[s].v[v][k] += p->t[k];
    }
    ok = true;
done:
    free(buf);
    json_decref(doc);
    return ok;
}

/* ---- writing ---- */

/* The export of a in `format` as a string (caller frees), its MTL into *mtl_out when asked. */
static char *export_str(const cnAssembly *a, const char *format, char **mtl_out,
                        const char *mtl_name) {
    char *buf = NULL, *mbuf = NULL;
    size_t len = 0, mlen = 0;
    FILE *f = open_memstream(&buf, &len), *mf = mtl_out ? open_memstream(&mbuf, &mlen) : NULL;
    cnDiag d;
    cn_diag_clear(&d);
    cnStatus s = cn_export(f, a, format, mf, mtl_name, &d);
    CHECK_MSG(s == CN_OK, "export %s: %s", format, d.message);
    fclose(f);
    if (mf) fclose(mf);
    if (mtl_out) *mtl_out = mbuf;
    return buf;
}

/* ---- geometry of what was read ---- */

/* Every directed edge once and its reverse once, no degenerate edge, every vertex on a face. */
static bool closed(const Piece *pc) {
    static int cnt[MAXV][MAXV];
    memset(cnt, 0, sizeof cnt);
    bool used[MAXV] = {false};
    for (int f = 0; f < pc->nf; f++) {
        int n = pc->fstart[f + 1] - pc->fstart[f];
        for (int k = 0; k < n; k++) {
            int a = pc->fidx[pc->fstart[f] + k], b = pc->fidx[pc->fstart[f] + (k + 1) % n];
            if (a == b) return false;
            cnt[a][b]++;
            used[a] = true;
        }
    }
    for (int a = 0; a < pc->nv; a++) {
        if (!used[a]) return false;
        for (int b = 0; b < pc->nv; b++)
            if (cnt[a][b] && (cnt[a][b] != 1 || cnt[b][a] != 1)) return false;
    }
    return true;
}

/* Signed volume by the divergence theorem (faces fanned, about the first vertex). */
static double volume(const Piece *pc) {
    const double *o = pc->v[0];
    double s = 0;
    for (int f = 0; f < pc->nf; f++) {
        const int *l = pc->fidx + pc->fstart[f];
        int n = pc->fstart[f + 1] - pc->fstart[f];
        for (int k = 1; k + 1 < n; k++) {
            double a[3], b[3], c[3];
            for (int j = 0; j < 3; j++)
                a[j] = pc->v[l[0]][j] - o[j], b[j] = pc->v[l[k]][j] - o[j],
                c[j] = pc->v[l[k + 1]][j] - o[j];
            s += a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                 a[2] * (b[0] * c[1] - b[1] * c[0]);
        }
    }
    return s / 6;
}

/* Signed area in the xy plane of face f (shoelace); *min_tri: the least fan triangle's. */
static double area(const Piece *pc, int f, double *min_tri) {
    const int *l = pc->fidx + pc->fstart[f];
    int n = pc->fstart[f + 1] - pc->fstart[f];
    double s = 0;
    *min_tri = INFINITY;
    for (int k = 1; k + 1 < n; k++) {
        const double *a = pc->v[l[0]], *b = pc->v[l[k]], *c = pc->v[l[k + 1]];
        double t = ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])) / 2;
        s += t;
        *min_tri = fmin(*min_tri, t);
    }
    return s;
}

/* Are the piece's vertices the points want[0..n-1], as sets (a bijection within tol)? */
static bool same_set(const Piece *pc, const double (*want)[3], int n, double tol) {
    if (pc->nv != n) return false;
    bool taken[MAXV] = {false};
    for (int i = 0; i < n; i++) {
        int hit = -1;
        for (int v = 0; v < pc->nv && hit < 0; v++)
            if (!taken[v] && fabs(pc->v[v][0] - want[i][0]) <= tol &&
                fabs(pc->v[v][1] - want[i][1]) <= tol && fabs(pc->v[v][2] - want[i][2]) <= tol)
                hit = v;
        if (hit < 0) return false;
        taken[hit] = true;
    }
    return true;
}

static int box_corners(const double lo[3], const double hi[3], double out[][3]) {
    for (int c = 0; c < 8; c++)
        for (int k = 0; k < 3; k++)
            out[c][k] = c >> k & 1 ? hi[k] : lo[k];
    return 8;
}

/* OBJ and glTF say the same: parts, names, pieces, each vertex the OBJ's within single precision
 * about its part's middle, each triangle the fan of the OBJ's faces in turn. */
static void check_agree(const Mesh *o, const Mesh *g, const char *what) {
    CHECK_MSG(o->nparts == g->nparts, "%s: %d parts in OBJ, %d in glTF", what, o->nparts,
              g->nparts);
    for (int i = 0; i < o->nparts && i < g->nparts; i++) {
        const Part *po = &o->parts[i], *pg = &g->parts[i];
        CHECK_MSG(!strcmp(po->name, pg->name), "%s: part %d: '%s' vs '%s'", what, i, po->name,
                  pg->name);
        CHECK_MSG(po->npieces == pg->npieces, "%s: %s: pieces differ", what, po->name);
        for (int s = 0; s < po->npieces && s < pg->npieces; s++) {
            const Piece *a = &po->pieces[s], *b = &pg->pieces[s];
            bool same = a->nv == b->nv;
            for (int v = 0; same && v < a->nv; v++)
                for (int k = 0; k < 3; k++)
                    same = same && fabs(b->v[v][k] - a->v[v][k]) <=
                                       FLT_EPSILON * fabs(a->v[v][k] - pg->t[k]) + 1e-9 * fabs(pg->t[k]);
            int t = 0;
            for (int f = 0; same && f < a->nf; f++) {
                const int *l = a->fidx + a->fstart[f];
                for (int k = 1; same && k + 1 < a->fstart[f + 1] - a->fstart[f]; k++, t++) {
                    const int *tri = b->fidx + b->fstart[t];
                    same = t < b->nf && tri[0] == l[0] && tri[1] == l[k] && tri[2] == l[k + 1];
                }
            }
            CHECK_MSG(same && t == b->nf, "%s: %s piece %d: OBJ and glTF geometry differ", what,
                      po->name, s);
        }
    }
}

/* ---- the assemblies, every coordinate moved by t (written into the JSON here) ---- */

/* What a part must export: its name, whether fixed, per piece the corners (the points of an
 * exact convex piece) and the volume or area. A part whose outline is split (split > 0) gives
 * its outline as piece 0's corners and its area as piece 0's. */
typedef struct {
    const char *name;
    bool fixed;
    int npieces, split;
    int nc[2];
    double c[2][8][3];
    double size[2];
} Want;

static const double TABLE_LO[3] = {-4, -4, -1}, TABLE_HI[3] = {6, 4, 0};
static const double BLOCK_LO[3] = {0.5, -1.25, 0}, BLOCK_HI[3] = {2.5, 0.25, 1.5};
static const double TET[4][3] = {{3, 0, 0}, {5, 0, 0}, {3, 2, 0}, {3, 0, 3}};
static const double ELL_LO[3] = {-3, -3, 0}, ELL_HI[3] = {-1, -2, 1};
static const double PRISM[6][3] = {{-3, -3, 1}, {-2, -3, 1}, {-3, -2, 1},
                                   {-3, -3, 3}, {-2, -3, 3}, {-3, -2, 3}};
static const double TURN_HI[3] = {1, 2, 0.5}, TURN_POS[3] = {5.5, 2, 0};
#define NPARTS3 5

static const double GROUND[4][3] = {{-5, -1, 0}, {5, -1, 0}, {5, 0, 0}, {-5, 0, 0}};
static const double PENTA_CW[5][3] = {{0, 0, 0}, {0, 1, 0}, {1, 2, 0}, {2, 1, 0}, {2, 0, 0}};
static const double ELL2[6][3] = {{3, 0, 0}, {6, 0, 0}, {6, 1, 0}, {4, 1, 0}, {4, 3, 0}, {3, 3, 0}};
#define NPARTS2 3

static void set_pts(Want *w, int s, const double (*p)[3], int n, const double t[3], double size) {
    w->nc[s] = n;
    w->size[s] = size;
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++)
            w->c[s][i][k] = p[i][k] + t[k];
}

static void set_box(Want *w, int s, const double lo[3], const double hi[3], const double t[3]) {
    double c[8][3];
    box_corners(lo, hi, c);
    set_pts(w, s, (const double(*)[3])c, 8, t, (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]));
}

/* "[[x,y,z],...]" of n points moved by t (dim coordinates each). */
static int put_pts(char *j, size_t cap, const double (*p)[3], int n, const double t[3], int dim) {
    int k = snprintf(j, cap, "[");
    for (int i = 0; i < n; i++) {
        k += snprintf(j + k, cap - (size_t)k, "%s[%.17g,%.17g", i ? "," : "", p[i][0] + t[0],
                      p[i][1] + t[1]);
        k += snprintf(j + k, cap - (size_t)k, dim == 3 ? ",%.17g]" : "]", p[i][2] + t[2]);
    }
    return k + snprintf(j + k, cap - (size_t)k, "]");
}

static int put_box(char *j, size_t cap, const double lo[3], const double hi[3], const double t[3]) {
    return snprintf(j, cap, "{\"min\":[%.17g,%.17g,%.17g],\"max\":[%.17g,%.17g,%.17g]}",
                    lo[0] + t[0], lo[1] + t[1], lo[2] + t[2], hi[0] + t[0], hi[1] + t[1],
                    hi[2] + t[2]);
}

/* 3-D: a table, a box, a tetrahedron, an L of a box and a triangular prism ("hulls"; its name
 * has a quote and spaces), and a box turned 90 degrees about z by its pose. */
static cnAssembly *load3(const double t[3], Want w[NPARTS3]) {
    char j[4096];
    size_t cap = sizeof j;
    const double zero[3] = {0, 0, 0};
    int k = snprintf(j, cap,
                     "{\"name\":\"export 3-D\",\"dimension\":3,\"parts\":["
                     "{\"name\":\"table top\",\"fixed\":true,\"box\":");
    k += put_box(j + k, cap - (size_t)k, TABLE_LO, TABLE_HI, t);
    k += snprintf(j + k, cap - (size_t)k, "},{\"name\":\"block\",\"box\":");
    k += put_box(j + k, cap - (size_t)k, BLOCK_LO, BLOCK_HI, t);
    k += snprintf(j + k, cap - (size_t)k, "},{\"name\":\"tet\",\"hull\":");
    k += put_pts(j + k, cap - (size_t)k, TET, 4, t, 3);
    k += snprintf(j + k, cap - (size_t)k, "},{\"name\":\"L \\\"two\\\" pieces\",\"hulls\":[");
    double c[8][3];
    box_corners(ELL_LO, ELL_HI, c);
    k += put_pts(j + k, cap - (size_t)k, (const double(*)[3])c, 8, t, 3);
    k += snprintf(j + k, cap - (size_t)k, ",");
    k += put_pts(j + k, cap - (size_t)k, PRISM, 6, t, 3);
    snprintf(j + k, cap - (size_t)k,
             "]},{\"name\":\"turned\",\"box\":{\"min\":[0,0,0],\"max\":[1,2,0.5]},"
             "\"rotation\":{\"axis\":[0,0,1],\"angle\":90},\"position\":[%.17g,%.17g,%.17g]}]}",
             TURN_POS[0] + t[0], TURN_POS[1] + t[1], TURN_POS[2] + t[2]);
    memset(w, 0, NPARTS3 * sizeof *w);
    w[0] = (Want){.name = "table top", .fixed = true, .npieces = 1};
    set_box(&w[0], 0, TABLE_LO, TABLE_HI, t);
    w[1] = (Want){.name = "block", .npieces = 1};
    set_box(&w[1], 0, BLOCK_LO, BLOCK_HI, t);
    w[2] = (Want){.name = "tet", .npieces = 1};
    set_pts(&w[2], 0, TET, 4, t, 2 * 2 * 3 / 6.0);
    w[3] = (Want){.name = "L \"two\" pieces", .npieces = 2};
    set_box(&w[3], 0, ELL_LO, ELL_HI, t);
    set_pts(&w[3], 1, PRISM, 6, t, 0.5 * 2);
    /* turned: (x, y, z) -> (-y, x, z), then moved */
    w[4] = (Want){.name = "turned", .npieces = 1};
    set_box(&w[4], 0, zero, TURN_HI, zero);
    for (int i = 0; i < 8; i++) {
        double x = w[4].c[0][i][0], y = w[4].c[0][i][1];
        w[4].c[0][i][0] = -y + TURN_POS[0] + t[0];
        w[4].c[0][i][1] = x + TURN_POS[1] + t[1];
        w[4].c[0][i][2] += TURN_POS[2] + t[2];
    }
    return load_ok(j);
}

/* 2-D: a fixed ground, a convex pentagon written clockwise, an L-shaped outline (split into
 * convex pieces by the loader). */
static cnAssembly *load2(const double t[3], Want w[NPARTS2]) {
    char j[2048];
    size_t cap = sizeof j;
    int k = snprintf(
        j, cap, "{\"dimension\":2,\"parts\":[{\"name\":\"ground\",\"fixed\":true,\"polygon\":");
    k += put_pts(j + k, cap - (size_t)k, GROUND, 4, t, 2);
    k += snprintf(j + k, cap - (size_t)k, "},{\"name\":\"penta\",\"polygon\":");
    k += put_pts(j + k, cap - (size_t)k, PENTA_CW, 5, t, 2);
    k += snprintf(j + k, cap - (size_t)k, "},{\"name\":\"ell\",\"polygon\":");
    k += put_pts(j + k, cap - (size_t)k, ELL2, 6, t, 2);
    snprintf(j + k, cap - (size_t)k, "}]}");
    const double t2[3] = {t[0], t[1], 0};
    memset(w, 0, NPARTS2 * sizeof *w);
    w[0] = (Want){.name = "ground", .fixed = true, .npieces = 1};
    set_pts(&w[0], 0, GROUND, 4, t2, 10);
    w[1] = (Want){.name = "penta", .npieces = 1};
    set_pts(&w[1], 0, PENTA_CW, 5, t2, 2 + 1);
    w[2] = (Want){.name = "ell", .split = 1};
    set_pts(&w[2], 0, ELL2, 6, t2, 3 + 2);
    return load_ok(j);
}

/* ---- the oracles ---- */

/* Is every vertex of pc within tol of one of p[0..n-1]? Marks those hit in `hit`. */
static bool within(const Piece *pc, const double (*p)[3], int n, double tol, bool *hit) {
    for (int v = 0; v < pc->nv; v++) {
        bool any = false;
        for (int i = 0; i < n; i++)
            if (fabs(pc->v[v][0] - p[i][0]) <= tol && fabs(pc->v[v][1] - p[i][1]) <= tol &&
                fabs(pc->v[v][2] - p[i][2]) <= tol)
                any = hit[i] = true;
        if (!any) return false;
    }
    return true;
}

/* One format read back against the closed forms: names, the fixed flag (glTF's extras, and the
 * support material in both), corners as sets, 3-D pieces closed and outward with their volume,
 * 2-D pieces flat, convex and counter-clockwise with their area. tol: a coordinate's, rel: a
 * volume's or area's (relative). */
static void check_mesh(const Mesh *m, const Want *w, int nw, int dim, bool gltf, double tol,
                       double rel, const char *what) {
    CHECK_MSG(m->nparts == nw, "%s: %d parts, expected %d", what, m->nparts, nw);
    for (int i = 0; i < nw && i < m->nparts; i++) {
        const Part *p = &m->parts[i];
        const Want *x = &w[i];
        CHECK_MSG(!strcmp(p->name, x->name), "%s: part %d is '%s', expected '%s'", what, i, p->name,
                  x->name);
        CHECK_MSG(p->fixed == (gltf ? (int)x->fixed : -1), "%s: %s: fixed %d", what, x->name,
                  p->fixed);
        CHECK_MSG(!strcmp(p->mtl, "support") == x->fixed, "%s: %s: material '%s'", what, x->name,
                  p->mtl);
        if (x->split) { /* an outline split: pieces of its corners, all of them, tiling its area */
            CHECK_MSG(p->npieces >= 2, "%s: %s: %d pieces", what, x->name, p->npieces);
            bool hit[8] = {false}, in = true;
            double sum = 0;
            for (int s = 0; s < p->npieces; s++) {
                const Piece *pc = &p->pieces[s];
                in = in && within(pc, (const double(*)[3])x->c[0], x->nc[0], tol, hit);
                for (int f = 0; f < pc->nf; f++) {
                    double mt;
                    sum += area(pc, f, &mt);
                    CHECK_MSG(mt > 0, "%s: %s piece %d: a clockwise or degenerate triangle", what,
                              x->name, s);
                }
                CHECK_MSG(pc->nf == (gltf ? pc->nv - 2 : 1), "%s: %s piece %d: %d faces", what,
                          x->name, s, pc->nf);
            }
            bool all = true;
            for (int c = 0; c < x->nc[0]; c++)
                all = all && hit[c];
            CHECK_MSG(in && all, "%s: %s: the pieces' corners are not the outline's", what,
                      x->name);
            CHECK_NEAR(sum, x->size[0], rel * x->size[0]);
            continue;
        }
        CHECK_MSG(p->npieces == x->npieces, "%s: %s: %d pieces, expected %d", what, x->name,
                  p->npieces, x->npieces);
        for (int s = 0; s < p->npieces && s < x->npieces; s++) {
            const Piece *pc = &p->pieces[s];
            CHECK_MSG(same_set(pc, (const double(*)[3])x->c[s], x->nc[s], tol),
                      "%s: %s piece %d: corners differ", what, x->name, s);
            if (dim == 3) {
                CHECK_MSG(closed(pc),
                          "%s: %s piece %d: not a closed, consistently oriented surface", what,
                          x->name, s);
                double vol = volume(pc);
                CHECK_MSG(fabs(vol - x->size[s]) <= rel * x->size[s],
                          "%s: %s piece %d: volume %.17g, expected %g", what, x->name, s, vol,
                          x->size[s]);
            } else {
                bool flat = true;
                for (int v = 0; v < pc->nv; v++)
                    flat = flat && pc->v[v][2] == 0;
                CHECK_MSG(flat, "%s: %s: a 2-D vertex off z = 0", what, x->name);
                /* OBJ: one face, its vertices in turn; glTF: its fan */
                bool loop = gltf ? pc->nf == pc->nv - 2 : pc->nf == 1 && pc->fstart[1] == pc->nv;
                for (int k = 0; !gltf && loop && k < pc->nv; k++)
                    loop = pc->fidx[k] == k;
                CHECK_MSG(loop, "%s: %s: not the polygon as one face", what, x->name);
                double a = 0, mt = INFINITY;
                for (int f = 0; f < pc->nf; f++) {
                    double m1;
                    a += area(pc, f, &m1);
                    mt = fmin(mt, m1);
                }
                /* convex and counter-clockwise: every turn left (each fan triangle positive) */
                bool left = true;
                for (int v = 0; !gltf && v < pc->nv; v++) {
                    const double *a0 = pc->v[v], *b0 = pc->v[(v + 1) % pc->nv],
                                 *c0 = pc->v[(v + 2) % pc->nv];
                    left =
                        left &&
                        (b0[0] - a0[0]) * (c0[1] - a0[1]) - (b0[1] - a0[1]) * (c0[0] - a0[0]) > 0;
                }
                CHECK_MSG(mt > 0 && left, "%s: %s: not convex counter-clockwise", what, x->name);
                CHECK_NEAR(a, x->size[s], rel * x->size[s]);
            }
        }
    }
}

/* Exports a as OBJ (with MTL) and glTF, reads both back, checks them against w and each other;
 * the meshes read go to *obj and *gltf. scale: the coordinates' magnitude; ratio: that over the
 * pieces' size (how many digits a volume or area loses). */
static void check_assembly(const cnAssembly *a, const Want *w, int nw, double scale, double ratio,
                           Mesh *obj, Mesh *gltf, const char *what) {
    char *mtl = NULL, *o = export_str(a, "obj", &mtl, "x.mtl"),
         *g = export_str(a, "gltf", NULL, NULL);
    char msg[128];
    snprintf(msg, sizeof msg, "%s (OBJ)", what);
    bool ok = o && parse_obj(o, obj);
    CHECK_MSG(ok, "%s: the OBJ does not parse", msg);
    if (ok) {
        check_mesh(obj, w, nw, a->dim, false, 1e-13 * scale, 1e-12 * ratio, msg);
        CHECK_MSG(!strcmp(obj->mtllib, "x.mtl"), "%s: mtllib '%s'", msg, obj->mtllib);
        /* every material the OBJ uses is defined in the MTL */
        for (int i = 0; i < obj->nparts; i++) {
            char def[64];
            snprintf(def, sizeof def, "newmtl %s\n", obj->parts[i].mtl);
            CHECK_MSG(mtl && obj->parts[i].mtl[0] && strstr(mtl, def),
                      "%s: material '%s' not in the MTL", msg, obj->parts[i].mtl);
        }
    }
    snprintf(msg, sizeof msg, "%s (glTF)", what);
    bool ds = false;
    bool okg = g && parse_gltf(g, gltf, &ds);
    CHECK_MSG(okg, "%s: the glTF does not parse or is inconsistent", msg);
    if (okg) {
        /* floats: a coordinate within its rounding, a size within the rounding over its faces */
        check_mesh(gltf, w, nw, a->dim, true, 0x1p-23 * scale, 1e-6 * ratio, msg);
        CHECK_MSG(ds == (a->dim == 2), "%s: doubleSided %d", msg, ds);
    }
    if (ok && okg) check_agree(obj, gltf, what);
    /* without an MTL the OBJ is the same, less its mtllib line */
    const char *lib = "mtllib x.mtl\n";
    char *plain = export_str(a, "obj", NULL, NULL);
    const char *ml = o ? strstr(o, lib) : NULL;
    size_t head = ml ? (size_t)(ml - o) : 0;
    CHECK_MSG(ml && plain && strlen(plain) + strlen(lib) == strlen(o) && !strncmp(plain, o, head) &&
                  !strcmp(plain + head, ml + strlen(lib)),
              "%s: the OBJ without an MTL is not the OBJ less its mtllib line", what);
    free(plain);
    free(o);
    free(g);
    free(mtl);
}

/* Each piece of b is its piece of a moved by t, as sets of vertices (within tol). */
static void check_moved(const Mesh *a, const Mesh *b, const double t[3], double tol,
                        const char *what) {
    bool ok = a->nparts == b->nparts;
    for (int i = 0; ok && i < a->nparts; i++) {
        ok = a->parts[i].npieces == b->parts[i].npieces;
        for (int s = 0; ok && s < a->parts[i].npieces; s++) {
            const Piece *pa = &a->parts[i].pieces[s];
            double mv[MAXV][3];
            for (int v = 0; v < pa->nv; v++)
                for (int k = 0; k < 3; k++)
                    mv[v][k] = pa->v[v][k] + t[k];
            ok = same_set(&b->parts[i].pieces[s], (const double(*)[3])mv, pa->nv, tol) &&
                 pa->nf == b->parts[i].pieces[s].nf;
        }
    }
    CHECK_MSG(ok, "%s: translating the assembly does not translate every exported vertex", what);
}

/* ---- the tests ---- */

/* The 3-D and 2-D assemblies at the origin and far from it: each against its closed forms, OBJ
 * against glTF, and the far one's vertices the near one's moved. */
static void test_oracles_and_translation(void) {
    const double t3[3] = {1000.1, -250.3, 0.7}, t2[3] = {-37.7, 12.9, 0}, zero[3] = {0, 0, 0};
    Mesh *m = calloc(4, sizeof *m);
    CHECK(m != NULL);
    if (!m) return;
    for (int dim = 2; dim <= 3; dim++) {
        const double *t = dim == 3 ? t3 : t2;
        Want w0[NPARTS3], w1[NPARTS3];
        cnAssembly *a0 = dim == 3 ? load3(zero, w0) : load2(zero, w0);
        cnAssembly *a1 = dim == 3 ? load3(t, w1) : load2(t, w1);
        int nw = dim == 3 ? NPARTS3 : NPARTS2;
        char what[64];
        if (a0) {
            snprintf(what, sizeof what, "%d-D at the origin", dim);
            check_assembly(a0, w0, nw, 8, 8, &m[0], &m[1], what);
        }
        if (a1) {
            snprintf(what, sizeof what, "%d-D moved", dim);
            double sc = 8 + fmax(fabs(t[0]), fmax(fabs(t[1]), fabs(t[2])));
            check_assembly(a1, w1, nw, sc, sc, &m[2], &m[3], what);
        }
        if (a0 && a1) {
            snprintf(what, sizeof what, "%d-D moved (OBJ)", dim);
            check_moved(&m[0], &m[2], t, 1e-12 * 1024, what);
            snprintf(what, sizeof what, "%d-D moved (glTF)", dim);
            check_moved(&m[1], &m[3], t, 0x1p-22 * (8 + fmax(fabs(t[0]), fabs(t[1]))), what);
        }
        cn_assembly_free(a0);
        cn_assembly_free(a1);
    }
    free(m);
}

/* A box and a tetrahedron scaled by 1e30 and by 1e-30 (inside float's normal range, which glTF
 * keeps): the same closed forms, scaled; OBJ to double precision, glTF the floats of them. */
static void test_scales(void) {
    const double scales[2] = {1e30, 1e-30};
    Mesh *m = calloc(2, sizeof *m);
    CHECK(m != NULL);
    if (!m) return;
    for (int k = 0; k < 2; k++) {
        double s = scales[k], lo[3], hi[3], tet[4][3];
        for (int i = 0; i < 3; i++)
            lo[i] = s * (BLOCK_LO[i] + 7), hi[i] = s * (BLOCK_HI[i] + 7);
        for (int v = 0; v < 4; v++)
            for (int i = 0; i < 3; i++)
                tet[v][i] = s * (TET[v][i] + 7);
        const double zero[3] = {0, 0, 0};
        char j[1024];
        int n = snprintf(j, sizeof j, "{\"dimension\":3,\"parts\":[{\"name\":\"block\",\"box\":");
        n += put_box(j + n, sizeof j - (size_t)n, lo, hi, zero);
        n += snprintf(j + n, sizeof j - (size_t)n, "},{\"name\":\"tet\",\"hull\":");
        n += put_pts(j + n, sizeof j - (size_t)n, (const double(*)[3])tet, 4, zero, 3);
        snprintf(j + n, sizeof j - (size_t)n, "}]}");
        Want w[2] = {{.name = "block", .npieces = 1}, {.name = "tet", .npieces = 1}};
        set_box(&w[0], 0, lo, hi, zero);
        set_pts(&w[1], 0, (const double(*)[3])tet, 4, zero, 2 * s * s * s);
        cnAssembly *a = load_ok(j);
        if (!a) continue;
        check_assembly(a, w, 2, 16 * s, 16, &m[0], &m[1], k ? "scaled by 1e-30" : "scaled by 1e30");
        cn_assembly_free(a);
    }
    free(m);
}

/* Far from the origin: a 0.6 x 1 x 1 box at x = 1e7 keeps its shape in glTF (its vertices are
 * stored about its middle; at 1e7 floats are 1 apart), its volume within single precision. A part
 * wider than a float holds is refused as an input error, and nothing claims success. */
static void test_far_and_huge(void) {
    cnAssembly *a = load_ok("{\"dimension\":3,\"parts\":[{\"name\":\"far\",\"box\":"
                            "{\"min\":[10000000,0,0],\"max\":[10000000.6,1,1]}}]}");
    if (a) {
        char *g = export_str(a, "gltf", NULL, NULL);
        Mesh *m = calloc(1, sizeof *m);
        bool ds;
        CHECK(g && m && parse_gltf(g, m, &ds));
        if (g && m && m->nparts == 1 && m->parts[0].npieces == 1) {
            CHECK_NEAR(volume(&m->parts[0].pieces[0]), 0.6, 1e-6);
            CHECK_NEAR(m->parts[0].t[0], 10000000.3, 1e-2);
        }
        free(g), free(m);
        cn_assembly_free(a);
    }
    a = load_ok("{\"dimension\":3,\"parts\":[{\"name\":\"huge\",\"box\":"
                "{\"min\":[-1e39,0,0],\"max\":[1e39,1e39,1e39]}}]}");
    if (a) {
        char *buf = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&buf, &len);
        cnDiag d;
        cn_diag_clear(&d);
        cnStatus st = cn_export(f, a, "gltf", NULL, NULL, &d);
        fclose(f);
        CHECK_MSG(st == CN_ERR_INPUT && d.code == CN_ERR_INPUT && strstr(d.message, "single precision") &&
                  strstr(d.message, "--to obj"), "huge part: status %d: %s", (int)st, d.message);
        CHECK_MSG(len == 0, "huge part: %zu bytes written", len);
        free(buf);
        char *o = export_str(a, "obj", NULL, NULL); /* OBJ writes doubles: no limit */
        CHECK(o && strstr(o, "e+38 "));
        free(o);
        cn_assembly_free(a);
    }
}

/* A format that is neither obj nor gltf: an input error naming it (a long name cut, the message
 * whole), nothing written. */
static void test_unknown_format(void) {
    Want w[NPARTS2];
    const double zero[3] = {0, 0, 0};
    cnAssembly *a = load2(zero, w);
    if (!a) return;
    char longname[300];
    memset(longname, 'x', sizeof longname - 1);
    longname[sizeof longname - 1] = '\0';
    const char *bad[] = {"stl", "OBJ", "", "gltf ", "glb", longname};
    for (int k = 0; k < 6; k++) {
        char *buf = NULL;
        size_t len = 0;
        FILE *f = open_memstream(&buf, &len);
        cnDiag d;
        cn_diag_clear(&d);
        cnStatus s = cn_export(f, a, bad[k], NULL, NULL, &d);
        fclose(f);
        char quoted[64];
        snprintf(quoted, sizeof quoted, k == 5 ? "'%.40s" : "'%s'", bad[k]);
        CHECK_MSG(s == CN_ERR_INPUT && d.code == CN_ERR_INPUT, "format '%.40s': status %d", bad[k],
                  (int)s);
        CHECK_MSG(strstr(d.message, quoted) != NULL && strlen(d.message) < 200,
                  "format '%.40s': message '%s'", bad[k], d.message);
        CHECK_MSG(len == 0, "format '%.40s': %zu bytes written", bad[k], len);
        free(buf);
    }
    cn_assembly_free(a);
}

/* Writes that fail: an I/O error with its message, whichever stream fails, never a crash. */
static void test_write_failures(void) {
    Want w[NPARTS3];
    const double zero[3] = {0, 0, 0};
    cnAssembly *a = load3(zero, w);
    if (!a) return;
    const char *fmt[2] = {"obj", "gltf"};
    for (int k = 0; k < 2; k++) {
        /* a stream opened for reading */
        FILE *ro = fopen("/dev/null", "r");
        CHECK(ro != NULL);
        if (ro) {
            cnDiag d;
            cn_diag_clear(&d);
            cnStatus s = cn_export(ro, a, fmt[k], NULL, NULL, &d);
            CHECK_MSG(s == CN_ERR_IO && d.code == CN_ERR_IO, "%s to a read-only stream: status %d",
                      fmt[k], (int)s);
            CHECK_MSG(strstr(d.message, "cannot write") != NULL, "%s: message '%s'", fmt[k],
                      d.message);
            fclose(ro);
        }
        /* a one-byte memory stream, unbuffered so that the failure shows at once */
        char small[1];
        FILE *mf = fmemopen(small, sizeof small, "w");
        CHECK(mf != NULL);
        if (mf) {
            setvbuf(mf, NULL, _IONBF, 0);
            cnDiag d;
            cnStatus s = cn_export(mf, a, fmt[k], NULL, NULL, &d);
            CHECK_MSG(s == CN_ERR_IO, "%s to a full memory stream: status %d", fmt[k], (int)s);
            fclose(mf);
        }
        /* buffered: what still sits in the buffer fails at fclose (cn_export does not flush);
           the failure must show in one of the two */
        mf = fmemopen(small, sizeof small, "w");
        if (mf) {
            cnDiag d;
            cnStatus s = cn_export(mf, a, fmt[k], NULL, NULL, &d);
            int rc = fclose(mf);
            CHECK_MSG(s == CN_ERR_IO || rc != 0,
                      "%s to a full buffered memory stream: no failure seen", fmt[k]);
        }
    }
    /* the OBJ written, its MTL not */
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len), *ro = fopen("/dev/null", "r");
    if (f && ro) {
        cnDiag d;
        cnStatus s = cn_export(f, a, "obj", ro, "x.mtl", &d);
        CHECK_MSG(s == CN_ERR_IO && d.code == CN_ERR_IO, "MTL to a read-only stream: status %d",
                  (int)s);
    }
    if (ro) fclose(ro);
    if (f) fclose(f);
    free(buf);
    cn_assembly_free(a);
}

void test_export(void) {
    test_oracles_and_translation();
    test_scales();
    test_far_and_huge();
    test_unknown_format();
    test_write_failures();
}
