/* model: closed polyhedral meshes made into convex pieces (mesh3.c; the exact decomposition of a
 * non-convex one in decompose3.cpp, CGAL). Private; C and C++. */
#ifndef CAIRN_MESH3_H
#define CAIRN_MESH3_H

#include "pieces.h"

/* One closed surface: vertices and polygonal faces (face f: idx[start[f] .. start[f + 1] - 1],
 * counter-clockwise seen from outside once cn_mesh_check has run). Owned arrays (cn_malloc). */
typedef struct cnMesh {
    char name[64];  /* the object or group's name in its file, or "" */
    int nverts, nfaces;
    double (*verts)[3];
    int *start, *idx;
    int *face_id;   /* per face: its number in the file (from 1), for messages */
} cnMesh;

void cn_mesh_free(cnMesh *m);

/* Convex pieces as point lists (malloc'd: free with cn_mesh_pieces_free). */
typedef struct cnMeshPieces {
    int n;
    int *lens;
    double (**pts)[3];
} cnMeshPieces;

void cn_mesh_pieces_free(cnMeshPieces *p);

/* Weld vertices closer than tol, drop repeated corners, and check that the mesh is a closed,
 * consistently oriented 2-manifold without degenerate faces that encloses a volume; turn it
 * outward when every face points in. CN_ERR_INPUT with a message naming the face (no `where`). */
cnStatus cn_mesh_check(cnMesh *m, double tol, cnDiag *diag);

/* A face of a mesh lies on a face of its hull only if their normals are within this cosine
 * (warped faces lean a little; the inner faces of a thin ring or shell face the other way). */
#define CN_MESH_SAME_SIDE_COS 0.5

/* Is the checked mesh the boundary of its own convex hull (within tol)? hull: that hull. */
bool cn_mesh_is_convex(const cnMesh *m, const cnPiece *hull, double tol);

/* The volume a checked (outward) mesh encloses. */
double cn_mesh_volume(const cnMesh *m);

/* The most faces a non-convex mesh may have to be split (the exact decomposition's time grows
 * fast with them; docs/performance.md). */
#define CN_MESH_SPLIT_MAX_FACES 1000
/* ... and the most concave (reflex) edges, once its faces are triangulated: the decomposition's
 * time grows with their cube (docs/bench.md, section 10). */
#define CN_MESH_SPLIT_MAX_REFLEX 96

/* A checked non-convex mesh split into convex pieces (cn_mesh_decompose), refused beyond
 * CN_MESH_SPLIT_MAX_FACES; pieces thinner than tol are dropped when they hold no more than tol
 * times the surface's area. 0 done, else the code of cn_mesh_decompose, 6 (too many faces) or 8
 * (too much in pieces thinner than tol); the message for a code in cn_mesh_split_why. */
int cn_mesh_split(const cnMesh *m, double tol, cnMeshPieces *out, int *face1, int *face2);
const char *cn_mesh_split_why(int code);

/* Exact convex decomposition of a checked closed mesh: 0 done; 2 not a valid closed polyhedron;
 * 3 self-intersecting (faces *face1 and *face2 of m cross, -1 when not known); 4 the
 * decomposition failed; 5 two parts of the surface meet at a vertex (not a manifold there); 7
 * the pieces do not add up to the volume the surface encloses, exactly (a cavity, a nested
 * shell); 9 more than CN_MESH_SPLIT_MAX_REFLEX concave edges; -1 out of memory. */
#ifdef __cplusplus
extern "C"
#endif
int cn_mesh_decompose(const cnMesh *m, cnMeshPieces *out, int *face1, int *face2);

#endif
