/* Closed polyhedral meshes: welding, the checks a mesh must pass to be a part (closed, manifold,
 * consistently oriented, no degenerate faces, a volume), and the convexity test that decides
 * whether it is one piece or goes to the exact decomposition. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mesh3.h"

static double signed_volume(const cnMesh *m);

void cn_mesh_free(cnMesh *m) {
    if (!m) return;
    cn_free(m->verts);
    cn_free(m->start);
    cn_free(m->idx);
    cn_free(m->face_id);
    memset(m, 0, sizeof *m);
}

void cn_mesh_pieces_free(cnMeshPieces *p) {
    if (!p) return;
    for (int i = 0; p->pts && i < p->n; i++) free(p->pts[i]);
    free(p->pts);
    free(p->lens);
    memset(p, 0, sizeof *p);
}

static const double (*g_sort_verts)[3];
static int cmp_vert(const void *a, const void *b) {
    const double *x = g_sort_verts[*(const int *)a], *y = g_sort_verts[*(const int *)b];
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return (x[k] > y[k]) - (x[k] < y[k]);
    return *(const int *)a - *(const int *)b;
}

/* Map every vertex to the first of the vertices within tol of it (by x first: a sorted sweep). */
static int weld(cnMesh *m, double tol, int *map) {
    int n = m->nverts;
    int *order = cn_malloc(sizeof(int) * (size_t)(n + 1));
    if (!order) return -1;
    for (int i = 0; i < n; i++) order[i] = i, map[i] = i;
    g_sort_verts = (const double(*)[3])m->verts;
    qsort(order, (size_t)n, sizeof(int), cmp_vert);
    for (int s = 0; s < n; s++) {
        int i = order[s];
        if (map[i] != i) continue;
        for (int t = s + 1; t < n && m->verts[order[t]][0] - m->verts[i][0] <= tol; t++) {
            int j = order[t];
            double d[3];
            cn_sub3(m->verts[j], m->verts[i], d);
            if (map[j] == j && cn_norm3(d) <= tol) map[j] = i;
        }
    }
    cn_free(order);
    return 0;
}

typedef struct {
    int lo, hi, from, face;
} Edge;

static int cmp_edge(const void *a, const void *b) {
    const Edge *x = a, *y = b;
    if (x->lo != y->lo) return x->lo - y->lo;
    if (x->hi != y->hi) return x->hi - y->hi;
    return x->face - y->face;
}

/* Twice the area vector of face f (Newell). */
static void face_normal(const cnMesh *m, int f, double n[3]) {
    n[0] = n[1] = n[2] = 0;
    for (int k = m->start[f]; k < m->start[f + 1]; k++) {
        int kn = k + 1 < m->start[f + 1] ? k + 1 : m->start[f];
        const double *a = m->verts[m->idx[k]], *b = m->verts[m->idx[kn]];
        n[0] += (a[1] - b[1]) * (a[2] + b[2]);
        n[1] += (a[2] - b[2]) * (a[0] + b[0]);
        n[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
}

double cn_mesh_volume(const cnMesh *m) {
    return signed_volume(m);
}

static double signed_volume(const cnMesh *m) {
    double v = 0;
    for (int f = 0; f < m->nfaces; f++) {
        const double *a = m->verts[m->idx[m->start[f]]];
        for (int k = m->start[f] + 1; k + 1 < m->start[f + 1]; k++) {
            const double *b = m->verts[m->idx[k]], *c = m->verts[m->idx[k + 1]];
            double bc[3];
            cn_cross3(b, c, bc);
            v += cn_dot3(a, bc) / 6.0;
        }
    }
    return v;
}

cnStatus cn_mesh_check(cnMesh *m, double tol, cnDiag *diag) {
    if (m->nfaces < 4)
        return cn_diag_set(diag, CN_ERR_INPUT, "", "has %d face%s: a closed mesh needs at least 4",
                           m->nfaces, m->nfaces == 1 ? "" : "s");
    int *map = cn_malloc(sizeof(int) * (size_t)(m->nverts + 1));
    if (!map || weld(m, tol, map) < 0) {
        cn_free(map);
        return cn_diag_oom(diag);
    }
    /* faces on welded vertices, repeated corners dropped */
    int w = 0, nf = 0;
    for (int f = 0; f < m->nfaces; f++) {
        int s = w;
        for (int k = m->start[f]; k < m->start[f + 1]; k++) {
            int v = map[m->idx[k]];
            if (w > s && m->idx[w - 1] == v) continue;
            m->idx[w++] = v;
        }
        if (w - s > 1 && m->idx[w - 1] == m->idx[s]) w--;
        int id = m->face_id[f];
        m->start[nf] = s;
        m->face_id[nf] = id;
        nf++;
        if (w - s < 3) {
            cn_free(map);
            return cn_diag_set(diag, CN_ERR_INPUT, "", "face %d is degenerate: fewer than 3 of "
                               "its corners are apart by more than the tolerance (%.3g); remove it, "
                               "or, if the part is that thin, lower the tolerance", id, tol);
        }
    }
    m->start[nf] = w;
    m->nfaces = nf;
    cn_free(map);
    for (int f = 0; f < m->nfaces; f++) {
        double n[3];
        face_normal(m, f, n);
        if (cn_norm3(n) <= tol * tol)
            return cn_diag_set(diag, CN_ERR_INPUT, "", "face %d is degenerate (no area: its "
                               "corners are on a line); remove it", m->face_id[f]);
    }
    /* every edge in exactly two faces, once each way */
    int ne = w;
    Edge *e = cn_malloc(sizeof(Edge) * (size_t)(ne + 1));
    if (!e) return cn_diag_oom(diag);
    int k = 0;
    for (int f = 0; f < m->nfaces; f++)
        for (int j = m->start[f]; j < m->start[f + 1]; j++) {
            int jn = j + 1 < m->start[f + 1] ? j + 1 : m->start[f];
            int a = m->idx[j], b = m->idx[jn];
            e[k].lo = a < b ? a : b, e[k].hi = a < b ? b : a, e[k].from = a, e[k].face = f;
            k++;
        }
    qsort(e, (size_t)ne, sizeof(Edge), cmp_edge);
    cnStatus st = CN_OK;
    for (int i = 0; i < ne && !st;) {
        int j = i;
        while (j < ne && e[j].lo == e[i].lo && e[j].hi == e[i].hi) j++;
        int fi = m->face_id[e[i].face];
        if (j - i == 1)
            st = cn_diag_set(diag, CN_ERR_INPUT, "", "is open: an edge of face %d belongs to no "
                             "other face (a hole in the surface); close it", fi);
        else if (j - i > 2)
            st = cn_diag_set(diag, CN_ERR_INPUT, "", "is not a manifold: an edge of face %d "
                             "belongs to %d faces (at most 2); give each closed part as a mesh "
                             "of its own", fi, j - i);
        else if (e[i].from == e[i + 1].from)
            st = cn_diag_set(diag, CN_ERR_INPUT, "", "faces %d and %d are oriented "
                             "inconsistently (they run along their common edge the same way); "
                             "orient every face the same way round", fi, m->face_id[e[i + 1].face]);
        i = j;
    }
    cn_free(e);
    if (st) return st;
    double vol = signed_volume(m);
    if (fabs(vol) <= 0 || !isfinite(vol))
        return cn_diag_set(diag, CN_ERR_INPUT, "", "encloses no volume");
    if (vol < 0) /* every face points in: turn them out */
        for (int f = 0; f < m->nfaces; f++)
            for (int a = m->start[f], b = m->start[f + 1] - 1; a < b; a++, b--) {
                int t = m->idx[a];
                m->idx[a] = m->idx[b], m->idx[b] = t;
            }
    return CN_OK;
}

bool cn_mesh_is_convex(const cnMesh *m, const cnPiece *hull, double tol) {
    /* every face lies in a face plane of the hull and faces the same way (the inner faces of a
     * ring or a hollow box thinner than tol lie within tol of the hull's planes too, but face
     * the other way), and the mesh holds the hull's volume */
    for (int f = 0; f < m->nfaces; f++) {
        double nf[3];
        face_normal(m, f, nf);
        double lf = cn_norm3(nf);
        bool on = false;
        for (int h = 0; h < hull->nfaces && !on; h++) {
            on = lf > 0 && cn_dot3(hull->faces[h].normal, nf) > CN_MESH_SAME_SIDE_COS * lf;
            for (int k = m->start[f]; k < m->start[f + 1] && on; k++)
                on = fabs(cn_dot3(hull->faces[h].normal, m->verts[m->idx[k]]) - hull->faces[h].offset) <= tol;
        }
        if (!on) return false;
    }
    double vh = 0, first[3], second[3][3];
    cn_mass_piece(hull, 3, NULL, &vh, first, second);
    double area = 0;
    for (int f = 0; f < m->nfaces; f++) {
        double n[3];
        face_normal(m, f, n);
        area += 0.5 * cn_norm3(n);
    }
    return fabs(signed_volume(m) - vh) <= tol * area;
}

const char *cn_mesh_split_why(int code) {
    switch (code) {
    case 2: return "is not a valid closed polyhedron";
    case 3: return "intersects itself";
    case 5: return "is not a manifold at a vertex (two parts of the surface meet at one point); give each closed part as a mesh of its own";
    case 6: return "has more faces than cairn splits exactly (1,000); give it as convex pieces (OBJ objects or groups), or simplify it";
    case 9: return "has more concave (reflex) edges than cairn splits exactly (96: the split's time grows with their cube); give it as convex pieces (OBJ objects or groups), or simplify it";
    case 8: return "splits into pieces thinner than the tolerance that hold more than a sliver of its volume; raise --tolerance, or give it as convex pieces (OBJ objects or groups)";
    case 7: return "has a cavity or a nested shell (its convex pieces do not add up to the volume it encloses); give the solid without voids";
    default: return "could not be split into convex pieces; give it as convex pieces (OBJ objects or groups)";
    }
}

/* Drop the pieces of a decomposition thinner than tol (slivers the exact pieces leave at
 * warped or finely faceted surfaces: rounded to doubles they may not span a volume at all), as
 * long as what they held is within tol of the surface: their volume together at most tol times
 * the mesh's area. 0 done, 8 too much would go, -1 out of memory. */
static int drop_slivers(const cnMesh *m, double tol, cnMeshPieces *mp) {
    double area = 0, dropped = 0;
    for (int f = 0; f < m->nfaces; f++) {
        double n[3];
        face_normal(m, f, n);
        area += 0.5 * cn_norm3(n);
    }
    int kept = 0;
    for (int i = 0; i < mp->n; i++) {
        cnPiece h;
        cnDiag local;
        cn_diag_clear(&local);
        cnStatus st = cn_hull3_build((const double(*)[3])mp->pts[i], mp->lens[i], &h, &local);
        if (st == CN_ERR_MEMORY) return -1;
        double vol = 0, width = INFINITY;
        if (!st) {
            double first[3], second[3][3];
            cn_mass_piece(&h, 3, NULL, &vol, first, second);
            /* its width across each face (the least of them is at least its true width) */
            for (int f = 0; f < h.nfaces; f++) {
                double lo = INFINITY, hi = -INFINITY;
                for (int v = 0; v < h.nverts; v++) {
                    double d = cn_dot3(h.faces[f].normal, h.verts[v]);
                    lo = fmin(lo, d), hi = fmax(hi, d);
                }
                width = fmin(width, hi - lo);
            }
            cn_piece_free(&h);
        }
        if (st || width < tol) {
            dropped += fmax(vol, 0);
            free(mp->pts[i]);
            continue;
        }
        mp->pts[kept] = mp->pts[i];
        mp->lens[kept] = mp->lens[i];
        kept++;
    }
    mp->n = kept;
    return kept > 0 && dropped <= tol * area ? 0 : 8;
}

int cn_mesh_split(const cnMesh *m, double tol, cnMeshPieces *out, int *face1, int *face2) {
    memset(out, 0, sizeof *out);
    *face1 = *face2 = -1;
    if (m->nfaces > CN_MESH_SPLIT_MAX_FACES) return 6;
    int r = cn_mesh_decompose(m, out, face1, face2);
    if (!r) r = drop_slivers(m, tol, out);
    if (r) cn_mesh_pieces_free(out);
    return r;
}
