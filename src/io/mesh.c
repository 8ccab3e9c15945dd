/* Mesh files (OBJ, STL ascii and binary, PLY, OFF; read with Assimp) as closed surfaces: one
 * cnMesh per placement of a mesh of the file (an OBJ object or group), its vertices posed by the
 * file's node transforms, its faces as written (no triangulation: faces are checked as given).
 * Other formats Assimp reads are refused: glTF and others may name further files (buffers),
 * which could lead outside the assembly's directory. Assimp keeps coordinates in single
 * precision. */
#include <assimp/cfileio.h>
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <math.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <limits.h>
#include <string.h>
#include <strings.h>

#include "io.h"

static cnStatus copy_mesh(const struct aiMesh *am, const struct aiMatrix4x4 *T, double scale,
                          cnMesh *m, cnDiag *diag) {
    memset(m, 0, sizeof *m);
    snprintf(m->name, sizeof m->name, "%.*s", (int)am->mName.length, am->mName.data);
    size_t nidx = 0;
    unsigned npoly = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++)
        if (am->mFaces[f].mNumIndices >= 3) nidx += am->mFaces[f].mNumIndices, npoly++;
    m->nverts = (int)am->mNumVertices;
    m->nfaces = (int)npoly;
    m->verts = cn_malloc(sizeof(double[3]) * (size_t)(m->nverts + 1));
    m->start = cn_malloc(sizeof(int) * (size_t)(m->nfaces + 1));
    m->idx = cn_malloc(sizeof(int) * (nidx + 1));
    m->face_id = cn_malloc(sizeof(int) * (size_t)(m->nfaces + 1));
    if (!m->verts || !m->start || !m->idx || !m->face_id) {
        cn_mesh_free(m);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading a mesh");
    }
    for (int i = 0; i < m->nverts; i++) {
        struct aiVector3D v = am->mVertices[i];
        aiTransformVecByMatrix4(&v, T);
        m->verts[i][0] = scale * (double)v.x;
        m->verts[i][1] = scale * (double)v.y;
        m->verts[i][2] = scale * (double)v.z;
        if (!isfinite(m->verts[i][0]) || !isfinite(m->verts[i][1]) || !isfinite(m->verts[i][2])) {
            cn_mesh_free(m);
            return cn_diag_set(diag, CN_ERR_INPUT, "", "vertex %d of the mesh is not finite (a "
                               "coordinate is NaN or infinite, or too large once scaled); give "
                               "finite numbers", i + 1);
        }
    }
    int k = 0, nf = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *af = &am->mFaces[f];
        if (af->mNumIndices < 3) continue; /* a point or a line */
        m->start[nf] = k;
        m->face_id[nf] = (int)f + 1; /* counted from 1, as in the file */
        nf++;
        for (unsigned j = 0; j < af->mNumIndices; j++) {
            if (af->mIndices[j] >= am->mNumVertices) {
                int nv = (int)am->mNumVertices;
                cn_mesh_free(m);
                return cn_diag_set(diag, CN_ERR_INPUT, "", "face %u of the mesh refers to vertex "
                                   "%u, but the mesh has %d vertices (counted from 0 in the file's "
                                   "numbering); fix the face", f + 1, af->mIndices[j], nv);
            }
            m->idx[k++] = (int)af->mIndices[j];
        }
    }
    m->start[nf] = k;
    return CN_OK;
}

typedef struct {
    cnMesh *ms;
    int n, cap;
} Placements;

/* Every placement of every polygon mesh under node nd (its transform after acc). */
static cnStatus walk(const struct aiScene *sc, const struct aiNode *nd, struct aiMatrix4x4 acc,
                     double scale, Placements *out, cnDiag *diag) {
    struct aiMatrix4x4 here = acc;
    aiMultiplyMatrix4(&here, &nd->mTransformation);
    for (unsigned k = 0; k < nd->mNumMeshes; k++) {
        if (nd->mMeshes[k] >= sc->mNumMeshes) continue;
        const struct aiMesh *am = sc->mMeshes[nd->mMeshes[k]];
        if (!(am->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON))) continue;
        if (out->n == out->cap) {
            int nc = out->cap ? 2 * out->cap : 8;
            cnMesh *g = cn_realloc(out->ms, sizeof(cnMesh) * (size_t)nc);
            if (!g) return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading a mesh");
            out->ms = g, out->cap = nc;
        }
        cnStatus s = copy_mesh(am, &here, scale, &out->ms[out->n], diag);
        if (s) return s;
        out->n++;
    }
    for (unsigned c = 0; c < nd->mNumChildren; c++) {
        cnStatus s = walk(sc, nd->mChildren[c], here, scale, out, diag);
        if (s) return s;
    }
    return CN_OK;
}

/* Assimp reads through these: the mesh file's bytes, already read, and no other file. An OBJ's
 * "mtllib" may name any path (../../etc/passwd); its materials are not needed, and a file
 * outside the assembly's directory must not be opened (Assimp's own memory reader falls back
 * to the disk for other names). */
typedef struct {
    const char *buf;
    size_t len, pos;
    const char *base; /* the mesh file's name, without its directory */
} MemFile;

static size_t mem_read(struct aiFile *f, char *out, size_t size, size_t count) {
    MemFile *m = (MemFile *)f->UserData;
    if (size == 0) return 0;
    size_t n = (m->len - m->pos) / size;
    if (n > count) n = count;
    memcpy(out, m->buf + m->pos, n * size);
    m->pos += n * size;
    return n;
}
static size_t mem_write(struct aiFile *f, const char *in, size_t size, size_t count) {
    (void)f, (void)in, (void)size, (void)count;
    return 0;
}
static size_t mem_tell(struct aiFile *f) { return ((MemFile *)f->UserData)->pos; }
static size_t mem_size(struct aiFile *f) { return ((MemFile *)f->UserData)->len; }
static void mem_flush(struct aiFile *f) { (void)f; }
static enum aiReturn mem_seek(struct aiFile *f, size_t off, enum aiOrigin how) {
    MemFile *m = (MemFile *)f->UserData;
    size_t at = how == aiOrigin_SET ? off : how == aiOrigin_CUR ? m->pos + off : m->len + off;
    if (at > m->len) return aiReturn_FAILURE;
    m->pos = at;
    return aiReturn_SUCCESS;
}
static struct aiFile *mem_open(struct aiFileIO *io, const char *name, const char *mode) {
    const MemFile *src = (const MemFile *)io->UserData;
    const char *b = strrchr(name, '/');
    b = b ? b + 1 : name;
    if (strchr(mode, 'w') || strcmp(b, src->base)) return NULL; /* only the mesh file itself */
    struct aiFile *f = calloc(1, sizeof *f);
    MemFile *m = malloc(sizeof *m);
    if (!f || !m) {
        free(f), free(m);
        return NULL;
    }
    *m = *src;
    m->pos = 0;
    f->ReadProc = mem_read, f->WriteProc = mem_write, f->TellProc = mem_tell;
    f->FileSizeProc = mem_size, f->SeekProc = mem_seek, f->FlushProc = mem_flush;
    f->UserData = (aiUserData)m;
    return f;
}
static void mem_close(struct aiFileIO *io, struct aiFile *f) {
    (void)io;
    if (!f) return;
    free(f->UserData);
    free(f);
}

static bool known_format(const char *file) {
    const char *dot = strrchr(file, '.');
    static const char *const ext[] = {".obj", ".stl", ".ply", ".off", NULL};
    for (int i = 0; dot && ext[i]; i++)
        if (!strcasecmp(dot, ext[i])) return true;
    return false;
}

/* The next whitespace-separated token of buf[*at..len) (comments from '#' to the line's end
 * skipped when hash): its start, *n its length; NULL at the end. */
static const char *token(const char *buf, size_t len, size_t *at, size_t *n, bool hash) {
    size_t i = *at;
    for (;;) {
        while (i < len && (buf[i] == ' ' || buf[i] == '\t' || buf[i] == '\r' || buf[i] == '\n')) i++;
        if (hash && i < len && buf[i] == '#') {
            while (i < len && buf[i] != '\n') i++;
            continue;
        }
        break;
    }
    if (i >= len) return NULL;
    size_t j = i;
    while (j < len && buf[j] != ' ' && buf[j] != '\t' && buf[j] != '\r' && buf[j] != '\n') j++;
    *at = j, *n = j - i;
    return buf + i;
}

/* A count in a header: a decimal integer (as a double, so that 1e30 stays large); -1 if not. */
static double count_of(const char *t, size_t n) {
    if (!t || n == 0 || n > 30) return -1;
    double v = 0;
    for (size_t i = 0; i < n; i++) {
        if (t[i] < '0' || t[i] > '9') return -1;
        v = 10 * v + (t[i] - '0');
    }
    return v;
}

/* Bytes a PLY property of this type takes in binary (0: not a type). */
static int ply_size(const char *t, size_t n) {
    static const struct { const char *name; int size; } types[] = {
        {"char", 1}, {"uchar", 1}, {"int8", 1}, {"uint8", 1}, {"short", 2}, {"ushort", 2},
        {"int16", 2}, {"uint16", 2}, {"int", 4}, {"uint", 4}, {"int32", 4}, {"uint32", 4},
        {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (strlen(types[i].name) == n && !strncasecmp(t, types[i].name, n)) return types[i].size;
    return 0;
}

/* Header keywords are matched whatever their case, as Assimp reads them (a PLY's
 * "binary_little_Endian" is binary to it). */

/* The least size of the data an OFF or PLY header declares (counts of vertices, faces and other
 * elements, each at its smallest: a digit and a separator per number in text, its type's bytes
 * in binary), so that a header that lies about its counts is refused before anything is
 * allocated for them. Returns the bytes needed after the header (0 when nothing is declared,
 * or the header is not understood: Assimp then judges the file), *what names the counts. */
static double declared_bytes(const char *buf, size_t len, const char *ext, size_t *header, char *what,
                             size_t wn) {
    size_t at = 0, n;
    const char *t = token(buf, len, &at, &n, !strcasecmp(ext, ".off"));
    *header = 0;
    if (!t) return 0;
    if (!strcasecmp(ext, ".off")) {
        /* [C][N][4]OFF, then vertices, faces, edges */
        if (n < 3 || strncasecmp(t + n - 3, "OFF", 3)) return 0;
        double c[3];
        for (int k = 0; k < 3; k++) {
            const char *ck = token(buf, len, &at, &n, true);
            c[k] = count_of(ck, n);
        }
        if (c[0] < 0 || c[1] < 0) return 0;
        *header = at;
        snprintf(what, wn, "%.17g vert%s and %.17g face%s", c[0], c[0] == 1 ? "ex" : "ices", c[1],
                 c[1] == 1 ? "" : "s");
        return c[0] * 6 + c[1] * 8; /* "x y z\n", "3 a b c\n" at the least */
    }
    if (n != 3 || strncasecmp(t, "ply", 3)) return 0;
    bool binary = false;
    double need = 0, elem = 0, per = 0, vertices = 0, faces = 0;
    while ((t = token(buf, len, &at, &n, false))) {
        if (n == 10 && !strncasecmp(t, "end_header", 10)) {
            need += elem * per;
            /* the header ends with its line */
            while (at < len && buf[at] != '\n') at++;
            *header = at < len ? at + 1 : at;
            snprintf(what, wn, "%.17g vert%s and %.17g face%s", vertices, vertices == 1 ? "ex" : "ices", faces,
                     faces == 1 ? "" : "s");
            return need;
        }
        if (n == 6 && !strncasecmp(t, "format", 6)) {
            const char *f = token(buf, len, &at, &n, false);
            binary = f && n > 6 && !strncasecmp(f, "binary", 6);
        } else if (n == 7 && !strncasecmp(t, "element", 7)) {
            need += elem * per;
            const char *name = token(buf, len, &at, &n, false);
            size_t nn = n;
            const char *ct = token(buf, len, &at, &n, false);
            elem = count_of(ct, n);
            if (!name || elem < 0) return 0;
            if (nn == 6 && !strncasecmp(name, "vertex", 6)) vertices = elem;
            if (nn == 4 && !strncasecmp(name, "face", 4)) faces = elem;
            per = 0;
        } else if (n == 8 && !strncasecmp(t, "property", 8)) {
            const char *ty = token(buf, len, &at, &n, false);
            if (!ty) return 0;
            if (n == 4 && !strncasecmp(ty, "list", 4)) {
                const char *ct = token(buf, len, &at, &n, false); /* the count's type */
                int cs = ct ? ply_size(ct, n) : 0;
                token(buf, len, &at, &n, false); /* the items' type: a list may be empty */
                per += binary ? cs : 2;
            } else {
                int sz = ply_size(ty, n);
                per += binary ? sz : 2;
            }
        }
    }
    return 0;
}

/* false for a file that starts as a PLY header ("ply" on its first line) and has no line
 * "end_header" (leading and trailing blanks aside) */
static bool ply_header_ends(const char *buf, size_t len) {
    size_t at = 0, n;
    const char *t = token(buf, len, &at, &n, false);
    if (!t || n != 3 || strncasecmp(t, "ply", 3)) return true;
    for (size_t i = 0; i < len;) {
        size_t e = i;
        while (e < len && buf[e] != '\n') e++;
        size_t a = i, b = e;
        while (a < b && (buf[a] == ' ' || buf[a] == '\t')) a++;
        while (b > a && (buf[b - 1] == ' ' || buf[b - 1] == '\t' || buf[b - 1] == '\r')) b--;
        if (b - a == 10 && !strncasecmp(buf + a, "end_header", 10)) return true;
        i = e + 1;
    }
    return false;
}

/* For a file that starts as a PLY header: its format token (*f, *n) when that is not ascii,
 * binary_little_endian or binary_big_endian (Assimp reads other words as binary, whose counts
 * the checks here could not tell), else NULL */
static const char *ply_format_unknown(const char *buf, size_t len, size_t *n) {
    size_t at = 0;
    const char *t = token(buf, len, &at, n, false);
    if (!t || *n != 3 || strncasecmp(t, "ply", 3)) return NULL;
    while ((t = token(buf, len, &at, n, false))) {
        if (*n == 10 && !strncasecmp(t, "end_header", 10)) return NULL;
        if (*n != 6 || strncasecmp(t, "format", 6)) continue;
        const char *f = token(buf, len, &at, n, false);
        if (!f) return NULL;
        if ((*n == 5 && !strncasecmp(f, "ascii", 5)) || (*n == 20 && !strncasecmp(f, "binary_little_endian", 20)) ||
            (*n == 17 && !strncasecmp(f, "binary_big_endian", 17)))
            return NULL;
        return f;
    }
    return NULL;
}

/* A PLY file's element layout, as its header declares it (at most PLY_MAX elements and
 * properties each: a file past that is left to Assimp). */
#define PLY_MAX 64
typedef struct {
    double count;
    int nprop;
    int size[PLY_MAX];  /* a scalar's bytes, or a list's items' bytes */
    int csize[PLY_MAX]; /* a list's count's bytes; 0 for a scalar */
} PlyElement;

/* Read an unsigned count of cs bytes at p (endianness big when be). */
static double ply_count(const unsigned char *p, int cs, bool be) {
    double v = 0;
    for (int i = 0; i < cs; i++) v = 256 * v + p[be ? i : cs - 1 - i];
    return v;
}

/* Walk a PLY file's data element by element, checking each list's count against the bytes left
 * before Assimp allocates for it (a face claiming 4e9 indices). Returns 0 when the data fits or
 * the header is not understood (Assimp then judges the file), else the offset of the first
 * list that does not fit (+1), with *claimed its count and *line its line (text files). */
static size_t ply_lists_misfit(const char *buf, size_t len, double *claimed, size_t *line) {
    PlyElement el[PLY_MAX];
    int ne = -1, format = 0; /* 1 text, 2 binary little endian, 3 big */
    size_t at = 0, n;
    const char *t = token(buf, len, &at, &n, false);
    if (!t || n != 3 || strncasecmp(t, "ply", 3)) return 0;
    for (;;) {
        if (!(t = token(buf, len, &at, &n, false))) return 0;
        if (n == 10 && !strncasecmp(t, "end_header", 10)) break;
        if (n == 6 && !strncasecmp(t, "format", 6)) {
            const char *f = token(buf, len, &at, &n, false);
            if (!f) return 0;
            format = n == 5 && !strncasecmp(f, "ascii", 5) ? 1 : n == 20 && !strncasecmp(f, "binary_little_endian", 20) ? 2
                   : n == 17 && !strncasecmp(f, "binary_big_endian", 17) ? 3 : 0;
        } else if (n == 7 && !strncasecmp(t, "element", 7)) {
            if (++ne >= PLY_MAX || !token(buf, len, &at, &n, false)) return 0;
            const char *ct = token(buf, len, &at, &n, false);
            el[ne].count = count_of(ct, n);
            el[ne].nprop = 0;
            if (el[ne].count < 0) return 0;
        } else if (n == 8 && !strncasecmp(t, "property", 8)) {
            if (ne < 0 || el[ne].nprop >= PLY_MAX) return 0;
            const char *ty = token(buf, len, &at, &n, false);
            if (!ty) return 0;
            int k = el[ne].nprop++, cs = 0, sz;
            if (n == 4 && !strncasecmp(ty, "list", 4)) {
                const char *c = token(buf, len, &at, &n, false);
                cs = c ? ply_size(c, n) : 0;
                const char *it = token(buf, len, &at, &n, false);
                sz = it ? ply_size(it, n) : 0;
                if (cs == 0 || cs > 4) return 0;
            } else {
                sz = ply_size(ty, n);
            }
            if (sz == 0) return 0;
            el[ne].size[k] = sz, el[ne].csize[k] = cs;
        }
    }
    if (format == 0) return 0;
    while (at < len && buf[at] != '\n') at++;
    at++;
    size_t ln = 1;
    for (size_t i = 0; i < at && i < len; i++) ln += buf[i] == '\n';
    for (int e = 0; e <= ne; e++) {
        if (el[e].nprop == 0) continue;
        /* the declared counts fit the file (declared_bytes), so this loop is bounded by its size */
        for (double item = 0; item < el[e].count; item++) {
            for (int k = 0; k < el[e].nprop; k++) {
                if (at >= len) return 0; /* short: Assimp says so */
                if (format == 1) {
                    size_t from = at;
                    const char *v = token(buf, len, &at, &n, false);
                    if (!v) return 0;
                    for (size_t i = from; i < at; i++) ln += buf[i] == '\n';
                    if (el[e].csize[k] == 0) continue;
                    double c = count_of(v, n);
                    if (c < 0) return 0;
                    size_t start = v - buf;
                    if (c * 2 > (double)(len - at) + 1) return *claimed = c, *line = ln, start + 1;
                    for (double i = 0; i < c; i++) {
                        from = at;
                        if (!token(buf, len, &at, &n, false)) return 0;
                        for (size_t j = from; j < at; j++) ln += buf[j] == '\n';
                    }
                } else if (el[e].csize[k] == 0) {
                    at += (size_t)el[e].size[k];
                } else {
                    int cs = el[e].csize[k];
                    if (len - at < (size_t)cs) return 0;
                    double c = ply_count((const unsigned char *)buf + at, cs, format == 3);
                    if (c * el[e].size[k] > (double)(len - at - (size_t)cs))
                        return *claimed = c, *line = 0, at + 1;
                    at += (size_t)cs + (size_t)c * (size_t)el[e].size[k];
                }
            }
        }
    }
    return 0;
}

cnStatus cn_mesh_read(const char *file, const char *shown, double scale, cnMesh **out, int *nout,
                      cnDiag *diag) {
    *out = NULL;
    *nout = 0;
    if (!known_format(file))
        return cn_diag_set(diag, CN_ERR_INPUT, "", "'%s' is not a mesh format cairn reads; give "
                           "an .obj, .stl, .ply or .off file", shown);
    /* read here and served to Assimp from memory (mem_open), so that it opens no other file */
    FILE *f = fopen(file, "rb");
    if (!f) return cn_diag_set(diag, CN_ERR_INPUT, "", "cannot open the mesh file '%s'", shown);
    char *buf = NULL;
    size_t len = 0, cap = 0;
    for (;;) {
        if (len == cap) {
            size_t nc = cap ? 2 * cap : 65536;
            char *nb = nc > cap ? cn_realloc(buf, nc) : NULL;
            if (!nb) {
                fclose(f);
                cn_free(buf);
                return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading the mesh file '%s'", shown);
            }
            buf = nb, cap = nc;
        }
        size_t got = fread(buf + len, 1, cap - len, f);
        len += got;
        if (got == 0) break;
    }
    bool bad = ferror(f);
    fclose(f);
    if (bad || len == 0 || len > UINT_MAX) {
        cn_free(buf);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "cannot read the mesh file '%s'%s", shown,
                           len == 0 && !bad ? ": it is empty" : "");
    }
    /* a PLY header must end: Assimp's reader looks for end_header past the end of the file */
    if (strrchr(file, '.') && !strcasecmp(strrchr(file, '.'), ".ply") && !ply_header_ends(buf, len)) {
        cn_free(buf);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "the mesh file '%s' starts a PLY header but has no "
                           "end_header line; end the header with it", shown);
    }
    if (strrchr(file, '.') && !strcasecmp(strrchr(file, '.'), ".ply")) {
        size_t fn = 0;
        const char *fw = ply_format_unknown(buf, len, &fn);
        if (fw) {
            char word[40];
            size_t k = 0;
            for (; k < fn && k < 32; k++) word[k] = fw[k] >= 0x20 && fw[k] < 0x7f ? fw[k] : '?';
            word[k] = 0;
            cn_free(buf);
            return cn_diag_set(diag, CN_ERR_INPUT, "", "the mesh file '%s' has the PLY format '%s%s'; "
                               "write ascii, binary_little_endian or binary_big_endian", shown, word,
                               fn > 32 ? "..." : "");
        }
    }
    /* counts a header declares must fit in the file before Assimp allocates for them */
    {
        size_t header = 0;
        char what[160] = "";
        double need = declared_bytes(buf, len, strrchr(file, '.'), &header, what, sizeof what);
        if (need > (double)(len - header)) {
            cn_free(buf);
            return cn_diag_set(diag, CN_ERR_INPUT, "", "the mesh file '%s' declares %s, more than its "
                               "%zu bytes can hold (%.3g at the least); fix the counts in its header",
                               shown, what, len, need);
        }
    }
    if (strrchr(file, '.') && !strcasecmp(strrchr(file, '.'), ".ply")) {
        double claimed = 0;
        size_t line = 0, where = ply_lists_misfit(buf, len, &claimed, &line);
        if (where) {
            cn_free(buf);
            if (line)
                return cn_diag_set(diag, CN_ERR_INPUT, "", "the mesh file '%s' declares a list of %.17g "
                                   "items on line %zu, more than the rest of the file can hold; fix "
                                   "that count", shown, claimed, line);
            return cn_diag_set(diag, CN_ERR_INPUT, "", "the mesh file '%s' declares a list of %.17g "
                               "items at byte %zu, more than the rest of its %zu bytes can hold; fix "
                               "that count", shown, claimed, where - 1, len);
        }
    }
    /* the faces as the file gives them: no triangulation, no welding (cn_mesh_check welds by
     * position, whatever the normals or texture coordinates say), no sorting by kind (that
     * would split a mesh of triangles and quads in two); points and lines are skipped */
    MemFile src = {buf, len, 0, strrchr(file, '/') ? strrchr(file, '/') + 1 : file};
    struct aiFileIO io = {mem_open, mem_close, (aiUserData)&src};
    const struct aiScene *sc = aiImportFileEx(file, 0, &io);
    cn_free(buf);
    if (!sc) {
        const char *why = aiGetErrorString();
        if (why && strstr(why, "bad_alloc"))
            return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading the mesh file '%s'", shown);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "cannot read the mesh file '%s': %s", shown,
                           why && why[0] ? why : "not a mesh format Assimp knows");
    }
    Placements pl = {NULL, 0, 0};
    struct aiMatrix4x4 id;
    aiIdentityMatrix4(&id);
    cnStatus s = CN_OK;
    if (sc->mRootNode) s = walk(sc, sc->mRootNode, id, scale, &pl, diag);
    else /* no node tree: each mesh once, as stored */
        for (unsigned i = 0; i < sc->mNumMeshes && !s; i++) {
            struct aiNode root;
            memset(&root, 0, sizeof root);
            aiIdentityMatrix4(&root.mTransformation);
            unsigned one = i;
            root.mNumMeshes = 1, root.mMeshes = &one;
            s = walk(sc, &root, id, scale, &pl, diag);
        }
    aiReleaseImport(sc);
    if (!s && pl.n == 0)
        s = cn_diag_set(diag, CN_ERR_INPUT, "", "the mesh file '%s' has no faces", shown);
    if (s) {
        for (int j = 0; j < pl.n; j++) cn_mesh_free(&pl.ms[j]);
        cn_free(pl.ms);
        return s;
    }
    *out = pl.ms;
    *nout = pl.n;
    return CN_OK;
}
