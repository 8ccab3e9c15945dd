/* 3-D convex hulls: qhull (Debian libqhull-r) finds the hull; the face loops are then rebuilt
 * exactly: every distinct supporting plane gets the hull vertices lying on it, ordered
 * counter-clockwise seen from outside. Coplanar triangles therefore come out as one face, which
 * is what contact detection needs (a box face is one quadrilateral, not two triangles). */
#include <libqhull_r/qhull_ra.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "pieces.h"

/* Vertices within this fraction of the hull's size from a plane lie on it. */
#define HULL_PLANE_TOL 1e-9
/* Hulls of more points than this are built from joggled input (cn_hull3_build). */
#define HULL_JOGGLE_POINTS 4096
/* ... when qhull's joggle stays within this fraction of the points' size (it starts near 1e-11
 * and grows tenfold on each retry: 1.4e-9 on a prism with 10,000-gon caps). A point the joggle
 * leaves inside the hull is no vertex of it: the hull is then that far from the exact one. */
#define HULL_JOGGLE_MAX 1e-8

typedef struct {
    double ang;
    int idx;
} AngIdx;

static int cmp_edge(const void *a, const void *b) {
    const int *x = a, *y = b;
    return x[0] != y[0] ? (x[0] > y[0]) - (x[0] < y[0]) : (x[1] > y[1]) - (x[1] < y[1]);
}

static int cmp_ang(const void *a, const void *b) {
    double x = ((const AngIdx *)a)->ang, y = ((const AngIdx *)b)->ang;
    return (x > y) - (x < y);
}

/* A facet's unit normal: qhull's; or, joggled, the normal of its first three vertices' own
 * points (an exact plane where qhull's is off by the joggle over the facet's width: 1e-8 on a
 * sliver of a cap), qhull's when they are nearly collinear. */
static void facet_normal(qhT *qh, const facetT *f, const double (*pts)[3], bool joggled, double nrm[3]) {
    cn_copy3(nrm, f->normal);
    cn_normalize3(nrm);
    if (!joggled || qh_setsize(qh, f->vertices) < 3) return;
    const double *p[3];
    for (int i = 0; i < 3; i++) p[i] = pts[qh_pointid(qh, ((vertexT *)f->vertices->e[i].p)->point)];
    double a[3], b[3], c[3];
    cn_sub3(p[1], p[0], a), cn_sub3(p[2], p[0], b), cn_cross3(a, b, c);
    if (!(cn_norm3(c) > 1e-6 * cn_norm3(a) * cn_norm3(b))) return;
    cn_normalize3(c);
    if (cn_dot3(c, nrm) < 0) cn_scale3(c, -1);
    cn_copy3(nrm, c);
}

static int cmp_point(const void *a, const void *b) {
    const double *x = a, *y = b;
    for (int k = 0; k < 3; k++)
        if (x[k] != y[k]) return (x[k] > y[k]) - (x[k] < y[k]);
    return 0;
}

/* Are two of the points the same? (joggled apart, both would be vertices of the hull) */
static bool has_duplicates(const double (*p)[3], int n) {
    double(*q)[3] = cn_malloc(sizeof(double[3]) * (size_t)n);
    if (!q) return true; /* the merging run then */
    memcpy(q, p, sizeof(double[3]) * (size_t)n);
    qsort(q, (size_t)n, sizeof q[0], cmp_point);
    bool dup = false;
    for (int i = 1; i < n && !dup; i++) dup = !cmp_point(q[i - 1], q[i]);
    cn_free(q);
    return dup;
}

/* The hull's thickness: twice its volume over its area (a plate's thickness). */
static double hull_thickness(const cnPiece *h) {
    double vol = 0, area = 0;
    for (int f = 0; f < h->nfaces; f++) {
        const cnFace *F = &h->faces[f];
        double a[3] = {0, 0, 0};
        for (int i = 0; i < F->nverts; i++) {
            double c[3];
            cn_cross3(h->verts[F->verts[i]], h->verts[F->verts[(i + 1) % F->nverts]], c);
            cn_add3(a, c, a);
        }
        double fa = 0.5 * cn_dot3(a, F->normal);
        area += fa;
        vol += F->offset * fa / 3;
    }
    return area > 0 ? 2 * vol / area : 0;
}

/* The hull's vertices, faces (coplanar facets merged, loops counter-clockwise from outside)
 * and unique edges from qhull's result, into out, every allocation checked. pts are the points
 * about the middle ctr, where qhull saw them; the result is moved back by ctr. Joggled: facet planes from
 * the points themselves. */
/* The unique edges of a closed hull's face loops: every side of every face, sorted, duplicates
 * dropped (each edge is a side of two faces). NULL when out of memory. */
static int (*unique_edges(const cnFace *faces, int nf, int *nep))[2] {
    size_t cape = 0;
    int ne = 0;
    for (int f = 0; f < nf; f++) cape += (size_t)faces[f].nverts;
    int(*edges)[2] = cn_malloc(sizeof(int[2]) * (cape + 1));
    if (!edges) return NULL;
    for (int f = 0; f < nf; f++)
        for (int i = 0; i < faces[f].nverts; i++) {
            int a = faces[f].verts[i], b = faces[f].verts[(i + 1) % faces[f].nverts];
            edges[ne][0] = a < b ? a : b;
            edges[ne][1] = a < b ? b : a;
            ne++;
        }
    qsort(edges, (size_t)ne, sizeof(int[2]), cmp_edge);
    int nu = 0;
    for (int e = 0; e < ne; e++)
        if (nu == 0 || edges[e][0] != edges[nu - 1][0] || edges[e][1] != edges[nu - 1][1]) {
            edges[nu][0] = edges[e][0];
            edges[nu][1] = edges[e][1];
            nu++;
        }
    ne = nu;
    *nep = ne;
    return edges;
}

/* A face's m vertices (onplane) ordered counter-clockwise about the outward normal nrm into ai,
 * and their centre c. */
static void face_order(const double (*verts)[3], const int *onplane, int m, const double nrm[3], AngIdx *ai,
                       double c[3]) {
    double t1[3], t2[3];
    c[0] = c[1] = c[2] = 0;
    for (int i = 0; i < m; i++) cn_add3(c, verts[onplane[i]], c);
    cn_scale3(c, 1.0 / m);
    cn_tangent_basis(nrm, t1, t2);
    for (int i = 0; i < m; i++) {
        double r[3];
        cn_sub3(verts[onplane[i]], c, r);
        ai[i].ang = atan2(cn_dot3(r, t2), cn_dot3(r, t1));
        ai[i].idx = onplane[i];
    }
    qsort(ai, (size_t)m, sizeof(AngIdx), cmp_ang);
}

/* Face F's normal by Newell's method for accuracy (the facet's nrm where it disagrees), its
 * offset from the centre c. */
static void face_plane(const double (*verts)[3], const double nrm[3], const double c[3], cnFace *F) {
    int m = F->nverts;
    double nn[3] = {0, 0, 0};
    for (int i = 0; i < m; i++) {
        const double *p0 = verts[F->verts[i]], *p1 = verts[F->verts[(i + 1) % m]];
        nn[0] += (p0[1] - p1[1]) * (p0[2] + p1[2]);
        nn[1] += (p0[2] - p1[2]) * (p0[0] + p1[0]);
        nn[2] += (p0[0] - p1[0]) * (p0[1] + p1[1]);
    }
    if (cn_normalize3(nn) > 0 && cn_dot3(nn, nrm) > 0.9) cn_copy3(F->normal, nn);
    else cn_copy3(F->normal, nrm);
    F->offset = cn_dot3(F->normal, c);
}

static cnStatus collect(qhT *qh, const double (*pts)[3], int n, double size, const double ctr[3],
                        bool joggled, cnPiece *out, cnDiag *diag) {
    int nv = qh->num_vertices, nfacets = qh->num_facets, nf = 0, capf = 16, ne = 0;
    double(*verts)[3] = cn_calloc((size_t)nv + 1, sizeof *verts);
    int *map = cn_malloc(sizeof(int) * (size_t)n); /* point id -> hull vertex index */
    cnFace *faces = cn_calloc((size_t)capf, sizeof(cnFace));
    int *onplane = cn_malloc(sizeof(int) * ((size_t)nv + 1));
    AngIdx *ai = cn_malloc(sizeof(AngIdx) * ((size_t)nv + 1));
    facetT **queue = cn_malloc(sizeof(facetT *) * (size_t)(nfacets + 1));
    unsigned char *visited = cn_calloc((size_t)qh->facet_id + 1, 1);
    int *stamp = cn_calloc((size_t)nv + 1, sizeof(int));
    int(*edges)[2] = NULL;
    if (!verts || !map || !faces || !onplane || !ai || !queue || !visited || !stamp) goto oom;
    /* Collect hull vertices. */
    for (int i = 0; i < n; i++) map[i] = -1;
    int k = 0;
    vertexT *vertex;
    FORALLvertices {
        int id = qh_pointid(qh, vertex->point);
        if (id >= 0 && id < n && map[id] < 0 && k < nv) {
            map[id] = k;
            cn_copy3(verts[k], pts[id]);
            k++;
        }
    }
    nv = k;
    /* Faces: each connected set of coplanar triangles, found by flooding from a facet over
     * its neighbours whose vertices lie on its plane (linear in the facets, where comparing
     * every facet with every face is quadratic). */
    double tol = HULL_PLANE_TOL * size;
    facetT *facet;
    FORALLfacets {
        if (visited[facet->id]) continue;
        double nrm[3];
        facet_normal(qh, facet, pts, joggled, nrm);
        double off = joggled ? cn_dot3(nrm, pts[qh_pointid(qh, ((vertexT *)facet->vertices->e[0].p)->point)])
                             : -facet->offset;
        int head = 0, tail = 0, m = 0;
        queue[tail++] = facet;
        visited[facet->id] = 1;
        while (head < tail) {
            facetT *f = queue[head++], *neighbor, **neighborp;
            vertexT *fv, **fvp;
            FOREACHsetelement_(vertexT, f->vertices, fv) {
                int vi = map[qh_pointid(qh, fv->point)];
                if (vi >= 0 && stamp[vi] != nf + 1) stamp[vi] = nf + 1, onplane[m++] = vi;
            }
            FOREACHneighbor_(f) {
                if (visited[neighbor->id] || tail > nfacets) continue;
                double nn[3];
                facet_normal(qh, neighbor, pts, joggled, nn);
                bool same = cn_dot3(nn, nrm) >= 1 - 1e-9;
                FOREACHsetelement_(vertexT, neighbor->vertices, fv)
                    if (same && fabs(cn_dot3(nrm, pts[qh_pointid(qh, fv->point)]) - off) > tol) same = false;
                if (!same) continue;
                visited[neighbor->id] = 1;
                queue[tail++] = neighbor;
            }
        }
        if (m < 3) continue;
        double c[3];
        face_order((const double(*)[3])verts, onplane, m, nrm, ai, c);
        if (nf == capf) {
            cnFace *grown = cn_realloc(faces, sizeof(cnFace) * (size_t)capf * 2);
            if (!grown) goto oom;
            faces = grown;
            memset(faces + capf, 0, sizeof(cnFace) * (size_t)capf);
            capf *= 2;
        }
        cnFace *F = &faces[nf];
        if (!(F->verts = cn_malloc(sizeof(int) * (size_t)m))) goto oom;
        nf++;
        F->nverts = m;
        for (int i = 0; i < m; i++) F->verts[i] = ai[i].idx;
        face_plane((const double(*)[3])verts, nrm, c, F);
    }
    if (!(edges = unique_edges(faces, nf, &ne))) goto oom;
    /* back where the points were */
    for (int i = 0; i < nv; i++) cn_add3(verts[i], ctr, verts[i]);
    for (int f = 0; f < nf; f++) faces[f].offset += cn_dot3(faces[f].normal, ctr);
    out->shape = CN_SHAPE_POLYHEDRON;
    out->nverts = nv;
    out->verts = verts;
    out->nfaces = nf;
    out->faces = faces;
    out->nedges = ne;
    out->edges = edges;
    cn_piece_bounds(out, 3);
    cn_free(map), cn_free(onplane), cn_free(ai), cn_free(queue), cn_free(visited), cn_free(stamp);
    if (nf < 4) {
        cn_piece_free(out);
        return cn_diag_set(diag, CN_ERR_INPUT, "", "the hull is degenerate (fewer than 4 faces)");
    }
    return CN_OK;
oom:
    for (int f = 0; faces && f < nf; f++) cn_free(faces[f].verts);
    cn_free(faces), cn_free(verts), cn_free(edges);
    cn_free(map), cn_free(onplane), cn_free(ai), cn_free(queue), cn_free(visited), cn_free(stamp);
    memset(out, 0, sizeof *out);
    return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the hull of %d points", n);
}

cnStatus cn_hull3_build(const double (*pts)[3], int n, cnPiece *out, cnDiag *diag) {
    memset(out, 0, sizeof *out);
    if (n < 4) return cn_diag_set(diag, CN_ERR_INPUT, "", "a hull needs at least 4 points");
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], pts[i][k]), hi[k] = fmax(hi[k], pts[i][k]);
    double d[3];
    cn_sub3(hi, lo, d);
    double size = cn_norm3(d);
    if (!(size > 0)) return cn_diag_set(diag, CN_ERR_INPUT, "", "all the points coincide");

    /* Everything below works about the middle of the points' box, and moves the result back at
     * the end: far from the origin, planes through the origin's frame lose the hull's digits. */
    double ctr[3];
    for (int k = 0; k < 3; k++) ctr[k] = 0.5 * (lo[k] + hi[k]);
    coordT *coords = cn_malloc(sizeof(coordT) * 3 * (size_t)n);
    double(*local)[3] = cn_malloc(sizeof(double[3]) * (size_t)n);
    if (!coords || !local) {
        cn_free(coords);
        cn_free(local);
        return cn_diag_oom(diag);
    }
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) coords[3 * i + k] = local[i][k] = pts[i][k] - ctr[k];
    pts = (const double(*)[3])local;

    char *errbuf = NULL;
    size_t errlen = 0;
    FILE *errf = open_memstream(&errbuf, &errlen);
    qhT qh_qh;
    qhT *qh = &qh_qh;
    qh_zero(qh, errf);
    /* Many points: joggled input (QJ) and no merging. Qhull's merging of coplanar facets is
     * slow where thousands of points lie on one circle (a prism's many-sided caps; docs/bench.md,
     * section 10); the faces are merged here anyway (collect). The joggle can leave a point of
     * such a cap inside the hull (HULL_JOGGLE_MAX). Where the joggle fails, grew past that, or
     * leaves a film, and for points with duplicates, the merging run. */
    char flags[] = "qhull Qt", jflags[] = "qhull QJ";
    int exitcode = qh_ERRinput;
    cnStatus st = CN_OK;
    bool joggled = n > HULL_JOGGLE_POINTS && !has_duplicates((const double(*)[3])local, n);
    if (joggled) {
        /* kept only when qhull's joggle stayed small and the hull is thicker than a thousand
           joggles (coplanar points joggled into a film are the merging run's to refuse) */
        exitcode = qh_new_qhull(qh, 3, n, coords, False, jflags, NULL, errf);
        bool kept = !exitcode && qh->JOGGLEmax <= HULL_JOGGLE_MAX * size &&
                    collect(qh, pts, n, size, ctr, true, out, diag) == CN_OK;
        if (kept && !(hull_thickness(out) >= 1e3 * qh->JOGGLEmax)) {
            cn_piece_free(out);
            kept = false;
        }
        if (!kept && exitcode != qh_ERRmem) {
            int curlong, totlong;
            qh_freeqhull(qh, !qh_ALL);
            qh_memfreeshort(qh, &curlong, &totlong);
            qh_zero(qh, errf);
            joggled = false;
        }
    }
    if (!joggled) exitcode = qh_new_qhull(qh, 3, n, coords, False, flags, NULL, errf);
    if (exitcode == qh_ERRmem) {
        st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory in qhull building the hull of %d points", n);
    } else if (exitcode) {
        st = cn_diag_set(diag, CN_ERR_INPUT, "",
                         "the points do not span a volume (they are coplanar or collinear); a "
                         "hull needs points that are not all in one plane");
    } else if (!joggled) {
        st = collect(qh, pts, n, size, ctr, false, out, diag);
    }
    int curlong, totlong;
    qh_freeqhull(qh, !qh_ALL);
    qh_memfreeshort(qh, &curlong, &totlong);
    fclose(errf);
    free(errbuf);
    cn_free(coords);
    cn_free(local);
    return st;
}
