/* The Gauss-map filter of the separating-axis test between two large convex pieces: which of
 * their edge pairs can give an axis at all. */
#include <math.h>
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"

/* Both pieces with more edges than EDGE_DIRS_MAX (each edge its own direction), the edge pairs
 * number in the hundreds of millions for two meshes of 10,000 faces. Only a pair whose two
 * edges meet on a face of the Minkowski difference can give the best axis or an end of a contact's
 * cone: the arcs of their faces' normals cross on the unit sphere (P's edge between normals a, b;
 * Q's between -c, -d; Gregorius, "The separating axis test between convex polyhedra", GDC
 * 2013). Other pairs are skipped before their axis is formed. The test keeps a pair whenever
 * the normals' own error could decide it (products of two sines within GAUSS_ARC_SLACK: arcs
 * 1e-4 rad apart, beyond the rounding of a face merged within 1e-9 of its size), so no
 * Minkowski face is lost; neighbouring arcs of a finely faceted surface are 1e-2 apart. */
#define GAUSS_ARC_SLACK 1e-8

/* The two faces of each edge of a piece (faces[2 * e], faces[2 * e + 1]; -1 when not found). */
typedef struct {
    int *faces;
} EdgeFaces;

static unsigned long edge_key(int a, int b) {
    unsigned long lo = (unsigned)(a < b ? a : b), hi = (unsigned)(a < b ? b : a);
    return lo * 2654435761ul ^ hi * 40503ul;
}

/* -1 out of memory */
static int edge_faces(const cnPiece *P, EdgeFaces *E) {
    size_t cap = 1;
    while (cap < 2 * (size_t)P->nedges + 2) cap *= 2;
    int *slot = cn_malloc(sizeof(int) * cap);
    E->faces = cn_malloc(sizeof(int) * (2 * (size_t)P->nedges + 1));
    if (!slot || !E->faces) {
        cn_free(slot), cn_free(E->faces);
        E->faces = NULL;
        return -1;
    }
    for (size_t i = 0; i < cap; i++) slot[i] = -1;
    for (int e = 0; e < P->nedges; e++) {
        size_t h = edge_key(P->edges[e][0], P->edges[e][1]) & (cap - 1);
        while (slot[h] >= 0) h = (h + 1) & (cap - 1);
        slot[h] = e;
        E->faces[2 * e] = E->faces[2 * e + 1] = -1;
    }
    for (int f = 0; f < P->nfaces; f++) {
        const cnFace *F = &P->faces[f];
        for (int k = 0; k < F->nverts; k++) {
            int a = F->verts[k], b = F->verts[(k + 1) % F->nverts];
            for (size_t h = edge_key(a, b) & (cap - 1); slot[h] >= 0; h = (h + 1) & (cap - 1)) {
                int e = slot[h];
                if ((P->edges[e][0] == a && P->edges[e][1] == b) || (P->edges[e][0] == b && P->edges[e][1] == a)) {
                    int *x = &E->faces[2 * e];
                    if (x[0] < 0) x[0] = f;
                    else if (x[1] < 0 && x[0] != f) x[1] = f;
                    break;
                }
            }
        }
    }
    cn_free(slot);
    return 0;
}

/* Two unit face normals within this distance are one point of the sphere (rounding of the same
 * plane's normal computed from two faces' vertices). */
#define GAUSS_SAME_NORMAL 1e-12

static bool same_normal(const double *u, const double *v) {
    return fabs(u[0] - v[0]) <= GAUSS_SAME_NORMAL && fabs(u[1] - v[1]) <= GAUSS_SAME_NORMAL &&
           fabs(u[2] - v[2]) <= GAUSS_SAME_NORMAL;
}

/* Can P's edge i and Q's edge j meet on a face of the Minkowski difference? true when unsure.
 * Arcs with an end in common (a face of P parallel to one of Q, facing it) cross only there,
 * where the difference has that face: their edges' axis is the face's normal, tried as a face
 * axis. Arcs with antipodal ends (a face of P facing the same way as one of Q) lie on great
 * circles that meet only at those two points, one on each arc's end alone: they do not cross.
 * Arcs on one great circle are parallel edges (no axis). Such pairs are skipped: the crossing
 * test below cannot tell them apart (two stacked prisms with n-gon caps: n^2 of each). */
static bool minkowski_pair(const cnPiece *P, const EdgeFaces *EP, int i, const cnPiece *Q,
                           const EdgeFaces *EQ, int j) {
    int fa = EP->faces[2 * i], fb = EP->faces[2 * i + 1], fc = EQ->faces[2 * j], fd = EQ->faces[2 * j + 1];
    if (fa < 0 || fb < 0 || fc < 0 || fd < 0) return true;
    const double *a = P->faces[fa].normal, *b = P->faces[fb].normal;
    double c[3], d[3], bxa[3], dxc[3];
    cn_copy3(c, Q->faces[fc].normal), cn_scale3(c, -1);
    cn_copy3(d, Q->faces[fd].normal), cn_scale3(d, -1);
    if (same_normal(a, c) || same_normal(a, d) || same_normal(b, c) || same_normal(b, d)) return false;
    const double *Qc = Q->faces[fc].normal, *Qd = Q->faces[fd].normal; /* -c, -d */
    if (same_normal(a, Qc) || same_normal(a, Qd) || same_normal(b, Qc) || same_normal(b, Qd)) return false;
    cn_cross3(b, a, bxa);
    cn_cross3(d, c, dxc);
    double par[3];
    cn_cross3(bxa, dxc, par); /* both arcs on one great circle: parallel edges, no axis */
    if (cn_norm3(par) <= EDGE_PARALLEL_SIN * cn_norm3(bxa) * cn_norm3(dxc)) return false;
    double cba = cn_dot3(c, bxa), dba = cn_dot3(d, bxa), adc = cn_dot3(a, dxc), bdc = cn_dot3(b, dxc);
    return cba * dba <= GAUSS_ARC_SLACK && adc * bdc <= GAUSS_ARC_SLACK && cba * bdc >= -GAUSS_ARC_SLACK;
}

/* Bucketing of the arcs on the unit sphere, so that the pairs are not all tested: each arc goes
 * to the cells of a G x G grid on each face of the cube about the sphere (central projection:
 * an arc is a straight segment there, within the bounding box of its ends). An arc whose ends
 * lie on one cube face by a margin of GAUSS_FACE_MARGIN stays on it (a face's region of the
 * sphere is convex); another is halved until each piece does, or until a piece is shorter than
 * GAUSS_PIECE_SHORT, which goes to every face it comes within the margin (plus its length) of:
 * two arcs that cross, or nearly, then share a cell of the face where they do. An arc of more
 * than GAUSS_ARC_PIECES pieces, or a piece over GAUSS_ARC_CELLS cells, is tested against every
 * arc. */
#define GAUSS_FACE_MARGIN 1e-3
#define GAUSS_ARC_CELLS 256
#define GAUSS_ARC_PIECES 64
#define GAUSS_PIECE_SHORT 0.05
/* A short piece is projected onto a face only where every point of it is at least this far
 * into the face's hemisphere (the projection is then finite and straight) */
#define GAUSS_HEMISPHERE 0.3

/* One piece of an arc on one cube face: the face and its cells' box (c0..c1 in s, r0..r1 in t) */
typedef struct {
    int arc, face, box[4];
} ArcPiece;

typedef struct {
    ArcPiece *p;
    int n, cap;
} Pieces;

/* The cube face of u (0..5) and its projection (s, t) in [-1, 1]; -1 within the margin of an
 * edge of the cube. */
static int cube_face(const double u[3], double *s, double *t) {
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(u[i]) > fabs(u[k])) k = i;
    int a = (k + 1) % 3, b = (k + 2) % 3;
    double m = fabs(u[k]);
    if (!(m > 0) || fabs(u[a]) > m - GAUSS_FACE_MARGIN || fabs(u[b]) > m - GAUSS_FACE_MARGIN) return -1;
    *s = u[a] / m, *t = u[b] / m;
    return 2 * k + (u[k] < 0);
}

/* Cell index of projected coordinate x in [-1, 1] (clamped) */
static int cell_of(double x, int G) {
    int c = (int)floor((x + 1) * 0.5 * G);
    return c < 0 ? 0 : c >= G ? G - 1 : c;
}

/* Appends the piece on face f between projections (s1, t1) and (s2, t2), its box expanded by one
 * cell; false when it spans too many cells or out of room. */
static bool piece_add(Pieces *out, int arc, int f, double s1, double t1, double s2, double t2, int G) {
    int c0 = cell_of(fmin(s1, s2), G) - 1, c1 = cell_of(fmax(s1, s2), G) + 1;
    int r0 = cell_of(fmin(t1, t2), G) - 1, r1 = cell_of(fmax(t1, t2), G) + 1;
    c0 = c0 < 0 ? 0 : c0, r0 = r0 < 0 ? 0 : r0, c1 = c1 >= G ? G - 1 : c1, r1 = r1 >= G ? G - 1 : r1;
    if ((long)(c1 - c0 + 1) * (r1 - r0 + 1) > GAUSS_ARC_CELLS) return false;
    if (out->n == out->cap) {
        int cap = 2 * out->cap + 64;
        ArcPiece *grown = cn_realloc(out->p, sizeof(ArcPiece) * (size_t)cap);
        if (!grown) return false;
        out->p = grown, out->cap = cap;
    }
    out->p[out->n++] = (ArcPiece){arc, f, {c0, c1, r0, r1}};
    return true;
}

/* The pieces of the arc from unit x to unit y (halved depth times so far); false when the arc is
 * to be tested against every arc. */
static bool arc_split(Pieces *out, int arc, const double *x, const double *y, int G, int depth, int first) {
    if (out->n - first > GAUSS_ARC_PIECES) return false;
    double s1, t1, s2, t2, d[3];
    int f1 = cube_face(x, &s1, &t1), f2 = cube_face(y, &s2, &t2);
    if (f1 >= 0 && f1 == f2 && piece_add(out, arc, f1, s1, t1, s2, t2, G)) return true;
    cn_sub3(y, x, d);
    double len = cn_norm3(d);
    if (len <= GAUSS_PIECE_SHORT || depth >= 12) { /* every face it comes near */
        double mid[3];
        cn_add3(x, y, mid);
        if (!(cn_normalize3(mid) > 0)) return false;
        const double *pt[3] = {x, y, mid};
        int faces = 0;
        for (int f = 0; f < 6; f++) {
            int k = f / 2, a = (k + 1) % 3, b = (k + 2) % 3;
            double sg = f % 2 ? -1 : 1;
            bool in = true, near = false;
            for (int q = 0; q < 3; q++) {
                double uk = sg * pt[q][k];
                in = in && uk >= GAUSS_HEMISPHERE;
                near = near || uk >= fmax(fabs(pt[q][a]), fabs(pt[q][b])) - GAUSS_FACE_MARGIN - len;
            }
            if (!in || !near) continue;
            double m1 = sg * x[k], m2 = sg * y[k];
            if (!piece_add(out, arc, f, x[a] / m1, x[b] / m1, y[a] / m2, y[b] / m2, G)) return false;
            faces++;
        }
        return faces > 0;
    }
    double mid[3];
    cn_add3(x, y, mid);
    if (!(cn_normalize3(mid) > 0)) return false;
    return arc_split(out, arc, x, mid, G, depth + 1, first) && arc_split(out, arc, mid, y, G, depth + 1, first);
}

/* The pieces of an arc appended to out; false (out unchanged) when it is tested against every
 * arc. */
static bool arc_pieces(Pieces *out, int arc, const double *x, const double *y, int G) {
    int first = out->n;
    if (arc_split(out, arc, x, y, G, 0, first)) return true;
    out->n = first;
    return false;
}


static int cmp_pair(const void *a, const void *b) {
    long long x = *(const long long *)a, y = *(const long long *)b;
    return (x > y) - (x < y);
}

/* Appends the pair (i, j) to *out when its arcs may cross; -1 out of memory. */
static int keep_pair(const cnPiece *P, const EdgeFaces *EP, int i, const cnPiece *Q, const EdgeFaces *EQ,
                     int j, long long **out, long long *n, long long *cap) {
    if (!minkowski_pair(P, EP, i, Q, EQ, j)) return 0;
    if (*n == *cap) {
        long long *bigger = cn_realloc(*out, sizeof(long long) * (size_t)(*cap * 2));
        if (!bigger) return -1;
        *out = bigger, *cap *= 2;
    }
    (*out)[(*n)++] = (long long)i * Q->nedges + j;
    return 0;
}

/* The arc of edge e of piece S (its faces' normals, negated for Q); false when a face is
 * missing. */
static bool edge_arc(const cnPiece *S, const EdgeFaces *E, int e, double sign, double x[3], double y[3]) {
    int fa = E->faces[2 * e], fb = E->faces[2 * e + 1];
    if (fa < 0 || fb < 0) return false;
    cn_copy3(x, S->faces[fa].normal), cn_scale3(x, sign);
    cn_copy3(y, S->faces[fb].normal), cn_scale3(y, sign);
    return true;
}

/* A face with at least this many edges is a hub of the Gauss map: all its edges' arcs start at
 * its normal, so they fill that point's cell (a prism's n-gon cap: n arcs). In a cell, Q's arcs
 * from one hub are kept together, and a P arc whose own end is that hub's point, or its
 * antipode, passes over them at once: minkowski_pair skips every such pair. */
#define GAUSS_HUB_EDGES 32

/* Q's hub of each arc (-1 none), and for each face f of P the hub of Q whose normal is f's
 * (pmatch[2 f]) and the one whose normal is opposite (pmatch[2 f + 1]), -1 none; false out of
 * memory. */
static bool gauss_hubs(const cnPiece *P, const cnPiece *Q, const EdgeFaces *EQ, int *qhub, int *pmatch) {
    int nh = 0, *hub = cn_malloc(sizeof(int) * ((size_t)Q->nfaces + 1));
    if (!hub) return false;
    for (int f = 0; f < Q->nfaces; f++)
        if (Q->faces[f].nverts >= GAUSS_HUB_EDGES) hub[nh++] = f;
    for (int j = 0; j < Q->nedges; j++) {
        int fc = EQ->faces[2 * j], fd = EQ->faces[2 * j + 1], h = -1;
        if (fc >= 0 && Q->faces[fc].nverts >= GAUSS_HUB_EDGES) h = fc;
        if (fd >= 0 && Q->faces[fd].nverts >= GAUSS_HUB_EDGES && (h < 0 || Q->faces[fd].nverts > Q->faces[h].nverts))
            h = fd;
        qhub[j] = h;
    }
    for (int f = 0; f < P->nfaces; f++) {
        const double *u = P->faces[f].normal;
        double v[3] = {-u[0], -u[1], -u[2]};
        pmatch[2 * f] = pmatch[2 * f + 1] = -1;
        for (int k = 0; k < nh; k++) {
            if (same_normal(u, Q->faces[hub[k]].normal) && pmatch[2 * f] < 0) pmatch[2 * f] = hub[k];
            if (same_normal(v, Q->faces[hub[k]].normal) && pmatch[2 * f + 1] < 0) pmatch[2 * f + 1] = hub[k];
        }
    }
    cn_free(hub);
    return true;
}

/* An arc of Q in a cell: its hub (-1 none), its number, and the end of its cell's run of arcs
 * from the same hub */
typedef struct {
    int hub, arc, run;
} CellArc;

static int cmp_hub(const void *a, const void *b) {
    int x = ((const CellArc *)a)->hub, y = ((const CellArc *)b)->hub;
    return (x > y) - (x < y);
}

/* Q's arcs (the negated normals of each edge's faces) by cell; arcs of P looked up there. */
static int gauss_pairs(const cnPiece *P, const EdgeFaces *EP, const cnPiece *Q, const EdgeFaces *EQ,
                       cnGaussFilter *g) {
    int nq = Q->nedges, np = P->nedges;
    int G = (int)ceil(sqrt(nq / 6.0));
    if (G < 1) G = 1;
    long ncell = 6L * G * G;
    int *start = cn_calloc((size_t)ncell + 1, sizeof(int));
    int *global = cn_malloc(sizeof(int) * (size_t)nq), *stamp = cn_malloc(sizeof(int) * (size_t)nq);
    int *qhub = cn_malloc(sizeof(int) * (size_t)nq), *pmatch = cn_malloc(sizeof(int) * (2 * (size_t)P->nfaces + 1));
    CellArc *cell = NULL;
    Pieces qp = {NULL, 0, 0}, pp = {NULL, 0, 0};
    long long cap = 1024, n = 0;
    long long *out = cn_malloc(sizeof(long long) * (size_t)cap);
    int ng = 0, rc = -1;
    if (!start || !global || !stamp || !out || !qhub || !pmatch || !gauss_hubs(P, Q, EQ, qhub, pmatch)) goto done;
    for (int j = 0; j < nq; j++) {
        stamp[j] = -1;
        double x[3], y[3];
        if (!edge_arc(Q, EQ, j, -1, x, y) || !arc_pieces(&qp, j, x, y, G)) global[ng++] = j;
    }
    for (int e = 0; e < qp.n; e++) {
        const ArcPiece *a = &qp.p[e];
        for (int c = a->box[0]; c <= a->box[1]; c++)
            for (int r = a->box[2]; r <= a->box[3]; r++) start[((long)a->face * G + c) * G + r + 1]++;
    }
    for (long k = 0; k < ncell; k++) start[k + 1] += start[k];
    cell = cn_malloc(sizeof(CellArc) * ((size_t)start[ncell] + 1));
    if (!cell) goto done;
    for (int e = 0; e < qp.n; e++) {
        const ArcPiece *a = &qp.p[e];
        for (int c = a->box[0]; c <= a->box[1]; c++)
            for (int r = a->box[2]; r <= a->box[3]; r++)
                cell[start[((long)a->face * G + c) * G + r]++] = (CellArc){qhub[a->arc], a->arc, 0};
    }
    for (long k = ncell; k > 0; k--) start[k] = start[k - 1]; /* back to the cells' starts */
    start[0] = 0;
    for (long c = 0; c < ncell; c++) { /* each cell's arcs by hub, and where each run ends */
        int lo = start[c], hi = start[c + 1];
        if (hi - lo > 1) qsort(cell + lo, (size_t)(hi - lo), sizeof(CellArc), cmp_hub);
        for (int t = hi - 1; t >= lo; t--)
            cell[t].run = t + 1 < hi && cell[t + 1].hub == cell[t].hub ? cell[t + 1].run : t + 1;
    }
    for (int i = 0; i < np; i++) {
        double x[3], y[3];
        pp.n = 0;
        if (!edge_arc(P, EP, i, 1, x, y) || !arc_pieces(&pp, i, x, y, G)) {
            for (int j = 0; j < nq; j++)
                if (keep_pair(P, EP, i, Q, EQ, j, &out, &n, &cap) < 0) goto done;
            continue;
        }
        for (int k = 0; k < ng; k++)
            if (keep_pair(P, EP, i, Q, EQ, global[k], &out, &n, &cap) < 0) goto done;
        const int *ma = &pmatch[2 * EP->faces[2 * i]], *mb = &pmatch[2 * EP->faces[2 * i + 1]];
        for (int e = 0; e < pp.n; e++) {
            const ArcPiece *a = &pp.p[e];
            for (int c0 = a->box[0]; c0 <= a->box[1]; c0++)
                for (int r0 = a->box[2]; r0 <= a->box[3]; r0++) {
                    long c = ((long)a->face * G + c0) * G + r0;
                    for (int t = start[c]; t < start[c + 1]; t++) {
                        int j = cell[t].arc, h = cell[t].hub;
                        if (h >= 0 && (h == ma[0] || h == ma[1] || h == mb[0] || h == mb[1])) {
                            /* an end shared or opposed */
                            t = cell[t].run - 1;
                            continue;
                        }
                        if (stamp[j] == i) continue;
                        stamp[j] = i;
                        if (keep_pair(P, EP, i, Q, EQ, j, &out, &n, &cap) < 0) goto done;
                    }
                }
        }
    }
    qsort(out, (size_t)n, sizeof(long long), cmp_pair);
    g->pairs = out, g->n = n, out = NULL;
    rc = 0;
done:
    cn_free(start), cn_free(global), cn_free(stamp), cn_free(cell), cn_free(out);
    cn_free(qhub), cn_free(pmatch);
    cn_free(qp.p), cn_free(pp.p);
    return rc;
}

void cn_gauss_filter(const cnPiece *P, const cnPiece *Q, cnGaussFilter *g) {
    g->pairs = NULL, g->n = 0;
    if (P->nedges <= EDGE_DIRS_MAX || Q->nedges <= EDGE_DIRS_MAX) return;
    EdgeFaces ep = {NULL}, eq = {NULL};
    if (edge_faces(P, &ep) == 0 && edge_faces(Q, &eq) == 0) gauss_pairs(P, &ep, Q, &eq, g);
    cn_free(ep.faces), cn_free(eq.faces);
}

void cn_gauss_filter_free(cnGaussFilter *g) { cn_free(g->pairs); }
