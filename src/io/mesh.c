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
#include <dlfcn.h>
#include <math.h>
#include <pthread.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <limits.h>
#include <string.h>
#include <strings.h>

#include "io.h"

#ifndef CN_ASSIMP_SONAME
#define CN_ASSIMP_SONAME "libassimp.so.5"
#endif

/* Assimp is loaded on the first mesh file read, not with libcairn: it and the libraries it
 * loads are most of the start of a process, and most processes read no mesh. */
_Static_assert(sizeof(struct aiMatrix4x4) == 16 * sizeof(ai_real), "aiMatrix4x4 is 16 numbers, row by row");
static struct {
    const struct aiScene *(*import)(const char *, unsigned int, struct aiFileIO *);
    void (*release)(const struct aiScene *);
    const char *(*error)(void);
    char why[200];
} assimp;
static pthread_once_t assimp_once = PTHREAD_ONCE_INIT;

static void assimp_open(void) {
    void *lib = dlopen(CN_ASSIMP_SONAME, RTLD_NOW | RTLD_LOCAL);
    if (!lib) {
        snprintf(assimp.why, sizeof assimp.why, "%s", dlerror());
        return;
    }
    void *f[3] = {dlsym(lib, "aiImportFileEx"), dlsym(lib, "aiReleaseImport"), dlsym(lib, "aiGetErrorString")};
    if (!f[0] || !f[1] || !f[2]) {
        snprintf(assimp.why, sizeof assimp.why, "%s lacks the functions cairn calls", CN_ASSIMP_SONAME);
        return;
    }
    memcpy(&assimp.release, &f[1], sizeof f[1]);
    memcpy(&assimp.error, &f[2], sizeof f[2]);
    memcpy(&assimp.import, &f[0], sizeof f[0]); /* last: set only when all are */
}

/* Assimp's matrix products in its own single precision and order of terms: dst = dst * src,
 * and v = T v (the point v, translation included). */
static void mat_mul(struct aiMatrix4x4 *dst, const struct aiMatrix4x4 *src) {
    ai_real a[16], b[16], r[16];
    memcpy(a, dst, sizeof a);
    memcpy(b, src, sizeof b);
    for (int i = 0; i < 4; i++)
        for (int j = 0; j < 4; j++)
            r[4 * i + j] = b[j] * a[4 * i] + b[4 + j] * a[4 * i + 1] + b[8 + j] * a[4 * i + 2] + b[12 + j] * a[4 * i + 3];
    memcpy(dst, r, sizeof r);
}
static void mat_point(struct aiVector3D *v, const struct aiMatrix4x4 *T) {
    ai_real t[16];
    memcpy(t, T, sizeof t);
    ai_real x = v->x, y = v->y, z = v->z;
    v->x = t[0] * x + t[1] * y + t[2] * z + t[3];
    v->y = t[4] * x + t[5] * y + t[6] * z + t[7];
    v->z = t[8] * x + t[9] * y + t[10] * z + t[11];
}
static void mat_identity(struct aiMatrix4x4 *m) {
    memset(m, 0, sizeof *m);
    m->a1 = m->b2 = m->c3 = m->d4 = 1;
}

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
        mat_point(&v, T);
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
    mat_mul(&here, &nd->mTransformation);
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
    const char *ext = strrchr(file, '.');
    cnStatus checked = CN_OK;
    if (!strcasecmp(ext, ".ply")) {
        checked = cn_ply_check(buf, len, shown, diag);
    } else if (!strcasecmp(ext, ".off")) {
        checked = cn_off_check(buf, len, shown, diag);
    }
    if (checked) {
        cn_free(buf);
        return checked;
    }
    /* the faces as the file gives them: no triangulation, no welding (cn_mesh_check welds by
     * position, whatever the normals or texture coordinates say), no sorting by kind (that
     * would split a mesh of triangles and quads in two); points and lines are skipped */
    MemFile src = {buf, len, 0, strrchr(file, '/') ? strrchr(file, '/') + 1 : file};
    struct aiFileIO io = {mem_open, mem_close, (aiUserData)&src};
    pthread_once(&assimp_once, assimp_open);
    if (!assimp.import) {
        cn_free(buf);
        return cn_diag_set(diag, CN_ERR_IO, "", "cannot read the mesh file '%s': the mesh reader (Assimp) did not load "
                           "(%s); install Debian's libassimp5 (make deps does)", shown, assimp.why);
    }
    const struct aiScene *sc = assimp.import(file, 0, &io);
    cn_free(buf);
    if (!sc) {
        const char *why = assimp.error();
        if (why && strstr(why, "bad_alloc"))
            return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading the mesh file '%s'", shown);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "cannot read the mesh file '%s': %s", shown,
                           why && why[0] ? why : "not a mesh format Assimp knows");
    }
    Placements pl = {NULL, 0, 0};
    struct aiMatrix4x4 id;
    mat_identity(&id);
    cnStatus s = CN_OK;
    if (sc->mRootNode) s = walk(sc, sc->mRootNode, id, scale, &pl, diag);
    else /* no node tree: each mesh once, as stored */
        for (unsigned i = 0; i < sc->mNumMeshes && !s; i++) {
            struct aiNode root;
            memset(&root, 0, sizeof root);
            mat_identity(&root.mTransformation);
            unsigned one = i;
            root.mNumMeshes = 1, root.mMeshes = &one;
            s = walk(sc, &root, id, scale, &pl, diag);
        }
    assimp.release(sc);
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
