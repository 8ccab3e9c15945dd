/* Convex pieces: bounds, distances, freeing. 2-D pieces are CCW polygons with z = 0. */
#include <math.h>

#include "pieces.h"

void cn_piece_bounds(cnPiece *p, int dim) {
    for (int k = 0; k < 3; k++) p->lo[k] = INFINITY, p->hi[k] = -INFINITY;
    for (int i = 0; i < p->nverts; i++)
        for (int k = 0; k < 3; k++) {
            p->lo[k] = fmin(p->lo[k], p->verts[i][k]);
            p->hi[k] = fmax(p->hi[k], p->verts[i][k]);
        }
    if (dim == 2) p->lo[2] = p->hi[2] = 0;
}

void cn_piece_transform(cnPiece *p, int dim, const cnPose *q) {
    for (int i = 0; i < p->nverts; i++) {
        cn_pose_apply(q, p->verts[i], p->verts[i]);
        if (dim == 2) p->verts[i][2] = 0;
    }
    for (int f = 0; f < p->nfaces; f++) { /* n'.(R x + t) = n.x + n'.t */
        cnFace *fc = &p->faces[f];
        cn_pose_rotate(q, fc->normal, fc->normal);
        fc->offset += fc->normal[0] * q->t[0] + fc->normal[1] * q->t[1] + fc->normal[2] * q->t[2];
    }
    cn_piece_bounds(p, dim);
}

void cn_piece_free(cnPiece *p) {
    if (!p) return;
    for (int f = 0; f < p->nfaces; f++) cn_free(p->faces[f].verts);
    cn_free(p->faces);
    cn_free(p->edges);
    cn_free(p->verts);
    cn_free(p->vnum);
    p->vnum = NULL;
    p->faces = NULL;
    p->edges = NULL;
    p->verts = NULL;
    p->nverts = p->nfaces = p->nedges = 0;
}

/* Max over the supporting lines (2-D) or planes (3-D) of the signed distance: positive outside,
 * negative inside (then it is minus the distance to the nearest face). */
double cn_piece_plane_distance(const cnPiece *p, int dim, const double x[3]) {
    double best = -INFINITY;
    if (dim == 2) {
        for (int i = 0; i < p->nverts; i++) {
            const double *a = p->verts[i], *b = p->verts[(i + 1) % p->nverts];
            double ex = b[0] - a[0], ey = b[1] - a[1];
            double len = hypot(ex, ey);
            double nx = ey / len, ny = -ex / len; /* outward for CCW */
            best = fmax(best, nx * (x[0] - a[0]) + ny * (x[1] - a[1]));
        }
        return best;
    }
    for (int f = 0; f < p->nfaces; f++)
        best = fmax(best, cn_dot3(p->faces[f].normal, x) - p->faces[f].offset);
    return best;
}
