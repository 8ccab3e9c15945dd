/* Mesh files (OBJ, STL ascii and binary, PLY, OFF and whatever else Assimp reads) as closed
 * surfaces: one cnMesh per mesh of the file (an OBJ object or group), its vertices posed by the
 * file's node transforms, its faces as written (no triangulation: faces are checked as given). */
#include <assimp/cimport.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <stdio.h>
#include <string.h>

#include "io.h"

/* The node transform of mesh `mi` (the first node that holds it, with its parents'). */
static bool find_transform(const struct aiNode *nd, unsigned mi, struct aiMatrix4x4 acc,
                           struct aiMatrix4x4 *out) {
    struct aiMatrix4x4 here = acc;
    aiMultiplyMatrix4(&here, &nd->mTransformation);
    for (unsigned k = 0; k < nd->mNumMeshes; k++)
        if (nd->mMeshes[k] == mi) {
            *out = here;
            return true;
        }
    for (unsigned c = 0; c < nd->mNumChildren; c++)
        if (find_transform(nd->mChildren[c], mi, here, out)) return true;
    return false;
}

static cnStatus copy_mesh(const struct aiScene *sc, unsigned mi, double scale, cnMesh *m,
                          cnDiag *diag) {
    const struct aiMesh *am = sc->mMeshes[mi];
    memset(m, 0, sizeof *m);
    snprintf(m->name, sizeof m->name, "%.*s", (int)am->mName.length, am->mName.data);
    struct aiMatrix4x4 id, T;
    aiIdentityMatrix4(&id);
    if (!sc->mRootNode || !find_transform(sc->mRootNode, mi, id, &T)) T = id;
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
        aiTransformVecByMatrix4(&v, &T);
        m->verts[i][0] = scale * (double)v.x;
        m->verts[i][1] = scale * (double)v.y;
        m->verts[i][2] = scale * (double)v.z;
    }
    int k = 0, nf = 0;
    for (unsigned f = 0; f < am->mNumFaces; f++) {
        const struct aiFace *af = &am->mFaces[f];
        if (af->mNumIndices < 3) continue; /* a point or a line */
        m->start[nf] = k;
        m->face_id[nf] = (int)f + 1; /* counted from 1, as in the file */
        nf++;
        for (unsigned j = 0; j < af->mNumIndices; j++) m->idx[k++] = (int)af->mIndices[j];
    }
    m->start[nf] = k;
    return CN_OK;
}

cnStatus cn_mesh_read(const char *file, double scale, cnMesh **out, int *nout, cnDiag *diag) {
    *out = NULL;
    *nout = 0;
    FILE *f = fopen(file, "rb");
    if (!f) return cn_diag_set(diag, CN_ERR_INPUT, "", "cannot open the mesh file '%s'", file);
    fclose(f);
    /* the faces as the file gives them: no triangulation, no welding (cn_mesh_check welds by
     * position, whatever the normals or texture coordinates say), no sorting by kind (that
     * would split a mesh of triangles and quads in two); points and lines are skipped */
    const struct aiScene *sc = aiImportFile(file, 0);
    if (!sc) {
        const char *why = aiGetErrorString();
        return cn_diag_set(diag, CN_ERR_INPUT, "", "cannot read the mesh file '%s': %s", file,
                           why && why[0] ? why : "not a mesh format Assimp knows");
    }
    int n = 0;
    for (unsigned i = 0; i < sc->mNumMeshes; i++)
        if (sc->mMeshes[i]->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON)) n++;
    if (n == 0) {
        aiReleaseImport(sc);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "the mesh file '%s' has no faces", file);
    }
    cnMesh *ms = cn_calloc((size_t)n, sizeof(cnMesh));
    if (!ms) {
        aiReleaseImport(sc);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory reading a mesh");
    }
    int k = 0;
    for (unsigned i = 0; i < sc->mNumMeshes; i++) {
        if (!(sc->mMeshes[i]->mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON)))
            continue;
        cnStatus s = copy_mesh(sc, i, scale, &ms[k], diag);
        if (s) {
            for (int j = 0; j < k; j++) cn_mesh_free(&ms[j]);
            cn_free(ms);
            aiReleaseImport(sc);
            return s;
        }
        k++;
    }
    aiReleaseImport(sc);
    *out = ms;
    *nout = n;
    return CN_OK;
}
