/* 3-D contacts between convex polyhedra, and planar convex-set intersection.
 *
 * Separating-axis test over face normals of both pieces and cross products of their edges gives
 * the normal and the gap (face axes win ties, so resting faces get their face normal). Within the
 * tolerance, each piece's touching feature is its set of vertices within the tolerance of the
 * separating plane: a vertex, an edge or a face. Projected on the plane, the two features are
 * intersected as convex sets (point, segment or polygon): the vertices of the intersection are
 * the contact points. This yields face-face (the overlap polygon's vertices), edge-face (the
 * clipped segment's ends), vertex-face and edge-edge (the crossing point) contacts. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"

/* Edges of one piece this close to parallel (sine) count as one direction of separating axes. */
#define EDGE_SAME_SIN 1e-12
/* Once an axis separates the pieces by more than this many tolerances they are apart whatever
 * the other axes give (a later axis can only take over the best within one tolerance of it). */
#define APART_EARLY 3

static double cross2(const double o[2], const double a[2], const double b[2]) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

static int cmp_xy(const void *pa, const void *pb) {
    const double *a = pa, *b = pb;
    if (a[0] != b[0]) return (a[0] > b[0]) - (a[0] < b[0]);
    return (a[1] > b[1]) - (a[1] < b[1]);
}

/* Distance from x to the segment [q, r]. */
static double seg_dist2(const double *q, const double *r, const double *x) {
    double d[2] = {r[0] - q[0], r[1] - q[1]}, L2 = d[0] * d[0] + d[1] * d[1];
    double t = L2 > 0 ? ((x[0] - q[0]) * d[0] + (x[1] - q[1]) * d[1]) / L2 : 0;
    t = t < 0 ? 0 : t > 1 ? 1 : t;
    return hypot(x[0] - q[0] - t * d[0], x[1] - q[1] - t * d[1]);
}

/* Convex hull in place, simplified within tol: returns 1 (a point), 2 (a segment) or >= 3 (a CCW
 * polygon), -1 out of memory. Every input point lies within tol of the result, and every point
 * of the result is an input point: no touching area is lost, none is invented.
 *   - Andrew's monotone chain runs without a tolerance (after exact duplicates are removed), so
 *     every extreme point is kept. A tolerance inside the chain would drop a point near the
 *     line through its neighbours in sorted order though it is not between them: on a nearly
 *     vertical segment, sorted by rounding in x, an end of a contact would be lost.
 *   - Then one walk around drops a vertex when it, and every vertex dropped since the last kept
 *     one, lie within tol of the segment from that kept vertex to the next vertex. Near-duplicate
 *     corners go this way too; merging points within tol before the chain could keep the inner
 *     one of two and lose the corner (a corner 1.8 tol outside; a finely divided circle 1.01 tol).
 *   - The walk starts at the lowest point, which is dropped last by the same test if it can be.
 *   - A set within tol of its lowest point is that point (a vertex contact stays one point).
 * Two kept vertices may still lie within tol of each other where dropping either would leave an
 * input point farther than tol. */
int cn_hull2(double (*p)[2], int n, double tol) {
    if (n <= 0) return 0;
    qsort(p, (size_t)n, sizeof p[0], cmp_xy);
    int m = 0;
    for (int i = 0; i < n; i++)
        if (m == 0 || p[i][0] != p[m - 1][0] || p[i][1] != p[m - 1][1]) p[m][0] = p[i][0], p[m][1] = p[i][1], m++;
    bool one = true;
    for (int i = 1; i < m && one; i++) one = hypot(p[i][0] - p[0][0], p[i][1] - p[0][1]) <= tol;
    if (one) return 1;
    if (m == 2) return 2;
    double(*h)[2] = cn_malloc(sizeof(double[2]) * (size_t)(2 * m + 1));
    int *kept = cn_malloc(sizeof(int) * (size_t)(2 * m + 1));
    if (!h || !kept) {
        cn_free(h), cn_free(kept);
        return -1;
    }
    int k = 0;
    for (int i = 0; i < m; i++) {
        while (k >= 2 && cross2(h[k - 2], h[k - 1], p[i]) <= 0) k--;
        h[k][0] = p[i][0], h[k][1] = p[i][1], k++;
    }
    for (int i = m - 2, t = k + 1; i >= 0; i--) {
        while (k >= t && cross2(h[k - 2], h[k - 1], p[i]) <= 0) k--;
        h[k][0] = p[i][0], h[k][1] = p[i][1], k++;
    }
    k--; /* last equals first */
    if (k < 3) { /* exactly collinear: the two ends */
        h[0][0] = p[0][0], h[0][1] = p[0][1];
        h[1][0] = p[m - 1][0], h[1][1] = p[m - 1][1];
        k = 2;
    }
    /* the walk starts at h[0], the lowest point (a vertex of the exact hull; it is kept) */
    int nk = 0;
    kept[nk++] = 0;
    for (int j = 1; j < k; j++) {
        int next = (j + 1) % k, last = kept[nk - 1];
        bool drop = true;
        for (int jj = j; jj > last && drop; jj--) /* this vertex and those dropped after last */
            drop = seg_dist2(h[last], h[next], h[jj]) <= tol;
        if (!drop) kept[nk++] = j;
    }
    /* the start itself, when it and the vertices dropped around it lie within tol of the
     * segment between its kept neighbours (a sliver whose lowest point is in its middle) */
    if (nk >= 3) {
        int a = kept[nk - 1], b = kept[1];
        bool drop = true;
        for (int jj = a + 1; jj <= k && drop; jj++) drop = seg_dist2(h[a], h[b], h[jj % k]) <= tol;
        for (int jj = 1; jj < b && drop; jj++) drop = seg_dist2(h[a], h[b], h[jj]) <= tol;
        if (drop) memmove(kept, kept + 1, sizeof(int) * (size_t)--nk);
    }
    /* from the lowest kept point, counter-clockwise */
    int lo = 0;
    for (int j = 1; j < nk; j++)
        if (cmp_xy(h[kept[j]], h[kept[lo]]) < 0) lo = j;
    for (int j = 0; j < nk; j++) p[j][0] = h[kept[(lo + j) % nk]][0], p[j][1] = h[kept[(lo + j) % nk]][1];
    cn_free(kept), cn_free(h);
    return nk;
}

static int push2(double (*out)[2], int *n, int cap, double x, double y, double tol) {
    for (int i = 0; i < *n; i++)
        if (hypot(out[i][0] - x, out[i][1] - y) <= tol) return 0;
    if (*n >= cap) return -1;
    out[*n][0] = x;
    out[*n][1] = y;
    (*n)++;
    return 0;
}

/* Signed distance of x to the left of directed edge a->b (positive inside a CCW polygon). */
static double inside_dist(const double a[2], const double b[2], const double x[2]) {
    double len = hypot(b[0] - a[0], b[1] - a[1]);
    return cross2(a, b, x) / len;
}

static int point_in(const double (*B)[2], int nb, const double x[2], double tol) {
    if (nb == 1) return hypot(B[0][0] - x[0], B[0][1] - x[1]) <= tol;
    if (nb == 2) {
        double d[2] = {B[1][0] - B[0][0], B[1][1] - B[0][1]};
        double L2 = d[0] * d[0] + d[1] * d[1];
        double t = ((x[0] - B[0][0]) * d[0] + (x[1] - B[0][1]) * d[1]) / L2;
        t = fmin(1, fmax(0, t));
        return hypot(B[0][0] + t * d[0] - x[0], B[0][1] + t * d[1] - x[1]) <= tol;
    }
    for (int i = 0; i < nb; i++)
        if (inside_dist(B[i], B[(i + 1) % nb], x) < -tol) return 0;
    return 1;
}

int cn_convex_intersect2(const double (*A)[2], int na, const double (*B)[2], int nb, double tol,
                         double (*out)[2], int cap) {
    int n = 0;
    if (na > nb) { /* make A the lower-dimensional one */
        const double(*T)[2] = A;
        A = B, B = T;
        int t = na;
        na = nb, nb = t;
    }
    if (na == 1) {
        if (point_in(B, nb, A[0], tol) && push2(out, &n, cap, A[0][0], A[0][1], tol) < 0) return -1;
        return n;
    }
    if (na == 2 && nb == 2) {
        double d1[2] = {A[1][0] - A[0][0], A[1][1] - A[0][1]};
        double d2[2] = {B[1][0] - B[0][0], B[1][1] - B[0][1]};
        double l1 = hypot(d1[0], d1[1]), l2 = hypot(d2[0], d2[1]);
        double cr = d1[0] * d2[1] - d1[1] * d2[0];
        if (fabs(cr) <= EDGE_PARALLEL_SIN * l1 * l2 || fabs(cr) / l1 <= tol) {
            /* parallel: collinear overlap, if any */
            double u[2] = {d1[0] / l1, d1[1] / l1};
            double off0 = fabs(cross2(A[0], A[1], B[0])) / l1;
            double off1 = fabs(cross2(A[0], A[1], B[1])) / l1;
            if (off0 > tol || off1 > tol) return 0;
            double b0 = (B[0][0] - A[0][0]) * u[0] + (B[0][1] - A[0][1]) * u[1];
            double b1 = (B[1][0] - A[0][0]) * u[0] + (B[1][1] - A[0][1]) * u[1];
            double lo = fmax(0, fmin(b0, b1)), hi = fmin(l1, fmax(b0, b1));
            if (lo > hi + tol) return 0;
            if (hi < lo) lo = hi = 0.5 * (lo + hi);
            if (push2(out, &n, cap, A[0][0] + lo * u[0], A[0][1] + lo * u[1], tol) < 0) return -1;
            if (push2(out, &n, cap, A[0][0] + hi * u[0], A[0][1] + hi * u[1], tol) < 0) return -1;
            return n;
        }
        /* crossing: A0 + s d1 = B0 + t d2 */
        double w[2] = {B[0][0] - A[0][0], B[0][1] - A[0][1]};
        double s = (w[0] * d2[1] - w[1] * d2[0]) / cr;
        double t = (w[0] * d1[1] - w[1] * d1[0]) / cr;
        if (s < -tol / l1 || s > 1 + tol / l1 || t < -tol / l2 || t > 1 + tol / l2) return 0;
        s = fmin(1, fmax(0, s));
        if (push2(out, &n, cap, A[0][0] + s * d1[0], A[0][1] + s * d1[1], tol) < 0) return -1;
        return n;
    }
    if (na == 2) { /* segment clipped by a polygon (Cyrus-Beck) */
        /* Crossings are placed on the true edge lines; the tolerance only keeps end points
         * that lie on (within tol of) an edge line. */
        double t0 = 0, t1 = 1;
        double d[2] = {A[1][0] - A[0][0], A[1][1] - A[0][1]};
        for (int i = 0; i < nb; i++) {
            const double *a = B[i], *b = B[(i + 1) % nb];
            double f0 = inside_dist(a, b, A[0]), f1 = inside_dist(a, b, A[1]);
            if (f0 < -tol && f1 < -tol) return 0;
            /* an end clearly outside is clipped to the crossing, or to the other end when that
             * one lies on the edge line (within tol): unclipped, its outside end would be a
             * contact point too (a box's edge standing above the face it touches would give a
             * point in the air) */
            if (f0 < -tol && f1 >= -tol) t0 = fmax(t0, f1 > 0 ? f0 / (f0 - f1) : 1);
            else if (f1 < -tol && f0 >= -tol) t1 = fmin(t1, f0 > 0 ? f0 / (f0 - f1) : 0);
        }
        if (t0 > t1) return 0;
        if (push2(out, &n, cap, A[0][0] + t0 * d[0], A[0][1] + t0 * d[1], tol) < 0) return -1;
        if (push2(out, &n, cap, A[0][0] + t1 * d[0], A[0][1] + t1 * d[1], tol) < 0) return -1;
        return n;
    }
    /* polygon-polygon: Sutherland-Hodgman, clipping A by each edge of B */
    int cur = na, capw = na + nb + 4;
    double(*P)[2] = cn_malloc(sizeof(double[2]) * (size_t)capw * 2);
    if (!P) return -1;
    double(*Qb)[2] = P + capw;
    memcpy(P, A, sizeof(double[2]) * (size_t)na);
    for (int i = 0; i < nb && cur > 0; i++) {
        const double *a = B[i], *b = B[(i + 1) % nb];
        int m = 0;
        for (int j = 0; j < cur; j++) {
            const double *x = P[j], *y = P[(j + 1) % cur];
            /* keep vertices within tol of the inside; cross only where the true edge line is
             * crossed from clearly inside to clearly outside or back */
            double fx = inside_dist(a, b, x), fy = inside_dist(a, b, y);
            if (fx >= -tol && m < capw) Qb[m][0] = x[0], Qb[m][1] = x[1], m++;
            if (((fx > tol && fy < -tol) || (fx < -tol && fy > tol)) && m < capw) {
                double t = fx / (fx - fy);
                Qb[m][0] = x[0] + t * (y[0] - x[0]);
                Qb[m][1] = x[1] + t * (y[1] - x[1]);
                m++;
            }
        }
        memcpy(P, Qb, sizeof(double[2]) * (size_t)m);
        cur = m;
    }
    int rc = 0;
    for (int j = 0; j < cur && rc == 0; j++) rc = push2(out, &n, cap, P[j][0], P[j][1], tol);
    cn_free(P);
    if (rc < 0) return -1;
    /* drop points made collinear by the tolerance-widened clipping */
    if (n >= 3) n = cn_hull2(out, n, tol);
    return n;
}

static void extent3(const cnPiece *P, const double o[3], const double u[3], double *lo,
                    double *hi) {
    double l = INFINITY, h = -INFINITY; /* compared inline: fmin/fmax are calls here */
    double base = cn_dot3(u, o);
    for (int i = 0; i < P->nverts; i++) {
        double d = cn_dot3(u, P->verts[i]) + base;
        if (d < l) l = d;
        if (d > h) h = d;
    }
    *lo = l;
    *hi = h;
}

/* Extreme vertices along 26 fixed directions, kept to bound a piece's extent along any axis
 * cheaply: along u, the piece reaches at least as far as the farthest of them (computed as
 * extent3 computes, so that the bound holds in floating point too). An axis whose separation
 * bound cannot win is skipped without scanning every vertex: for large pieces scanning them all
 * is (faces + edge pairs) x vertices, 1.8e10 operations for a ball of 30,000 hull points. */
#define SAMPLE_DIRS 26
typedef struct {
    int n;
    int idx[SAMPLE_DIRS];
} Samples;

static void samples_of(const cnPiece *P, Samples *S) {
    S->n = 0;
    for (int a = -1; a <= 1; a++)
        for (int b = -1; b <= 1; b++)
            for (int c = -1; c <= 1; c++) {
                if (!a && !b && !c) continue;
                double d[3] = {a, b, c}, h = -INFINITY;
                int best = 0;
                for (int i = 0; i < P->nverts; i++) {
                    double x = cn_dot3(d, P->verts[i]);
                    if (x > h) h = x, best = i;
                }
                S->idx[S->n++] = best;
            }
}

/* the piece reaches along u at least this far (a lower bound of extent3's hi)... */
static double reach_lo(const cnPiece *P, const Samples *S, const double o[3], const double u[3]) {
    double base = cn_dot3(u, o), h = -INFINITY;
    for (int k = 0; k < S->n; k++) {
        double d = cn_dot3(u, P->verts[S->idx[k]]) + base;
        if (d > h) h = d;
    }
    return h;
}

/* ... and starts along u at most here (an upper bound of extent3's lo) */
static double start_hi(const cnPiece *P, const Samples *S, const double o[3], const double u[3]) {
    double base = cn_dot3(u, o), l = INFINITY;
    for (int k = 0; k < S->n; k++) {
        double d = cn_dot3(u, P->verts[S->idx[k]]) + base;
        if (d < l) l = d;
    }
    return l;
}

/* The distinct directions of a piece's edges (exactly parallel edges, to rounding, give the same
 * separating axes): indices of one edge per direction into dir, returns their number. */
static int edge_dirs(const cnPiece *P, int *dir) {
    int nd = 0;
    if (P->nedges > EDGE_DIRS_MAX) {
        for (int i = 0; i < P->nedges; i++) dir[i] = i;
        return P->nedges;
    }
    for (int i = 0; i < P->nedges; i++) {
        double e[3];
        cn_sub3(P->verts[P->edges[i][1]], P->verts[P->edges[i][0]], e);
        int same = 0;
        for (int k = 0; k < nd && !same; k++) {
            double f[3], c[3];
            cn_sub3(P->verts[P->edges[dir[k]][1]], P->verts[P->edges[dir[k]][0]], f);
            cn_cross3(e, f, c);
            same = cn_norm3(c) <= EDGE_SAME_SIN * cn_norm3(e) * cn_norm3(f);
        }
        if (!same) dir[nd++] = i;
    }
    return nd;
}


/* The next edge axis to try (k as sat_axis numbers it, from nf): every one in turn, or with the
 * filter on, both signs of its pairs'. *c counts from 0; false past the last. */
static bool next_edge_axis(const cnGaussFilter *g, int nf, int np, int nq, long long *c, long long *k) {
    if (!g || !g->pairs) {
        if (*c >= 2LL * np * nq) return false;
        *k = nf + *c;
    } else {
        if (*c >= 2 * g->n) return false;
        *k = nf + 2 * g->pairs[*c / 2] + (*c & 1);
    }
    ++*c;
    return true;
}

/* With the filter on, an upper bound of edge axis k's separation along u in O(1): P reaches along
 * u at least as far as its edge's first vertex, Q starts no later than its edge's (computed as
 * extent3 computes, so that the bound holds in floating point too); INFINITY when off. */
static double gauss_bound(const cnGaussFilter *g, const cnPiece *P, const double oP[3], const cnPiece *Q,
                          const double oQ[3], const int *dp, const int *dq, int nq, int nf, long long k,
                          const double u[3]) {
    if (!g || !g->pairs) return INFINITY;
    long long pair = (k - nf) / 2;
    const double *p = P->verts[P->edges[dp[pair / nq]][0]], *q = Q->verts[Q->edges[dq[pair % nq]][0]];
    return (cn_dot3(u, q) + cn_dot3(u, oQ)) - (cn_dot3(u, p) + cn_dot3(u, oP));
}



/* An edge axis within this sine of the best face axis is that axis (both exact to rounding). */
#define SAME_AXIS_SIN 1e-15

static int apart(cnManifold *m, double sep, const double u[3]) {
    m->n = 0;
    m->gap = sep; /* a lower bound of the gap: enough to say the pieces are apart */
    cn_copy3(m->normal, u);
    return CN_PAIR_APART;
}

/* Face normals within this sine of perpendicular to a segment contact's direction can be ends of
 * its cone of normals. */
#define CORNER_PERP_SIN 1e-9

/* An edge resting on a parallel edge (the 3-D form of 2-D's corner on a corner: two extruded
 * corners touching along a line): the face axes perpendicular to the segment that separate the
 * pieces as well as the best one (within the tolerance) span a cone of normals about the
 * segment, and the contact has no normal of its own. As in 2-D (contact2.c, corner_cone), the
 * pieces may move apart along any motion that one end of the cone allows: when the pieces are
 * at rest relative to each other and the ends differ by more than CN_TOL_CORNER_CONE, the
 * manifold carries both ends (the normal nearer the chosen axis, and m->alt), and the check
 * decides every reading. Were the first tied axis the normal, the verdict would depend on the
 * order of the parts (a plank on a block's edge: unstable in one order, stable in the other).
 * Edges crossing at a point (a cone in three dimensions) keep the chosen axis. */
static void corner_cone3(const cnPiece *P, const double oP[3], const cnPiece *Q, const double oQ[3],
                         const double vrel[3], double tol, double best, const double bu[3],
                         cnManifold *m) {
    double e[3];
    cn_sub3(m->pts[1], m->pts[0], e);
    double ne = cn_norm3(e);
    if (!(ne > 0)) return;
    cn_scale3(e, 1.0 / ne);
    double ccw = 0, cw = 0, eccw[3], ecw[3];
    cn_copy3(eccw, bu), cn_copy3(ecw, bu);
    for (int side = 0; side < 2; side++) {
        const cnPiece *S = side ? Q : P;
        for (int f = 0; f < S->nfaces; f++) {
            double u[3], plo, phi, qlo, qhi, x[3];
            cn_copy3(u, S->faces[f].normal);
            if (side) cn_scale3(u, -1);
            if (fabs(cn_dot3(u, e)) > CORNER_PERP_SIN) continue;
            extent3(P, oP, u, &plo, &phi);
            extent3(Q, oQ, u, &qlo, &qhi);
            if (fabs((qlo - phi) - best) > tol) continue;
            cn_cross3(bu, u, x);
            double ang = atan2(cn_dot3(x, e), cn_dot3(bu, u));
            if (ang > ccw) ccw = ang, cn_copy3(eccw, u);
            if (ang < cw) cw = ang, cn_copy3(ecw, u);
        }
    }
    if (ccw - cw <= CN_TOL_CORNER_CONE) return;
    cn_corner_ends(vrel, eccw, ecw, ccw <= -cw, m);
}

/* Candidate separating axis k of P and Q, unit, from P into Q: P's face normals (k < nfaces of
 * P), then Q's negated, then the cross products of P's and Q's distinct edge directions (dp, dq:
 * edge_dirs), each pair both ways. false when the pair's edges are parallel (no axis). */
static bool sat_axis(const cnPiece *P, const cnPiece *Q, const int *dp, const int *dq, int nq,
                     long long k, double u[3]) {
    if (k < P->nfaces) {
        cn_copy3(u, P->faces[k].normal);
        return true;
    }
    k -= P->nfaces;
    if (k < Q->nfaces) {
        cn_copy3(u, Q->faces[k].normal);
        cn_scale3(u, -1);
        return true;
    }
    k -= Q->nfaces;
    long long pair = k / 2;
    int i = dp[pair / nq], j = dq[pair % nq];
    double e1[3], e2[3];
    cn_sub3(P->verts[P->edges[i][1]], P->verts[P->edges[i][0]], e1);
    cn_sub3(Q->verts[Q->edges[j][1]], Q->verts[Q->edges[j][0]], e2);
    cn_cross3(e1, e2, u);
    double nu = cn_norm3(u);
    if (nu <= EDGE_PARALLEL_SIN * cn_norm3(e1) * cn_norm3(e2)) return false;
    cn_scale3(u, (k & 1) ? -1.0 / nu : 1.0 / nu);
    return true;
}

/* The most tied axes a vertex contact's cone is built from (more: the cone is marked wide). */
#define VERTEX_AXES_MAX 256
/* A direction inside a vertex contact's cone must be at least this close (cosine) to every
 * tied axis to project them (the perceptron below looks for one). */
#define VERTEX_CENTRE_COS 1e-3
/* The perceptron's steps at most (a cone of margin m needs about 1 / m^2). */
#define VERTEX_CENTRE_STEPS 10000

typedef struct {
    int n;
    bool full;
    double u[VERTEX_AXES_MAX][3];
} Axes;

static void axes_add(Axes *A, const double u[3]) {
    for (int i = 0; i < A->n; i++) {
        double x[3];
        cn_cross3(A->u[i], u, x);
        if (cn_dot3(A->u[i], u) > 0 && cn_norm3(x) <= CN_TOL_CORNER_CONE) return; /* the same */
    }
    if (A->n == VERTEX_AXES_MAX) {
        A->full = true;
        return;
    }
    cn_copy3(A->u[A->n++], u);
}

/* A point is kept as a vertex of the hull when the directions to the other points leave a gap
 * of at least pi less this (radians): a vertex leaves more than pi, an end of collinear points
 * 2 pi, a point inside less than pi. The margin keeps every vertex whatever the rounding of the
 * angles; a point on an edge between two vertices (a gap of pi) is kept too, and dropped after. */
#define HULL_KEEP_ANGLE 1e-9
/* A kept point this close to the segment between two other kept points (relative to the
 * points' size), and strictly inside it, is not a vertex. */
#define HULL_ON_SEGMENT 1e-12

static int cmp_double(const void *pa, const void *pb) {
    double a = *(const double *)pa, b = *(const double *)pb;
    return (a > b) - (a < b);
}

/* The indices of the points (distinct) that are vertices of their convex hull, in keep; returns
 * their number. Errs towards keeping: a point is dropped only when the others surround it, or
 * when it lies inside the segment between two points kept. A cone's ends come from it, and an
 * end lost would hide the motions only that end allows (a false "stable"); an end too many is a
 * reading too many. cn_hull2 is not used: its tolerance drops a point near the line through its
 * neighbours in sorted order even when the point is not between them (a fan whose projection
 * is a nearly vertical line, sorted by rounding, lost its end). work: n doubles. */
static int hull_vertices(const double (*x)[2], int n, int *keep, double *work) {
    int nk = 0;
    for (int i = 0; i < n; i++) {
        int m = 0;
        for (int j = 0; j < n; j++)
            if (j != i && (x[j][0] != x[i][0] || x[j][1] != x[i][1]))
                work[m++] = atan2(x[j][1] - x[i][1], x[j][0] - x[i][0]);
        if (m == 0) {
            keep[nk++] = i;
            continue;
        }
        qsort(work, (size_t)m, sizeof(double), cmp_double);
        double gap = work[0] + 2 * CN_PI - work[m - 1];
        for (int k = 1; k < m; k++)
            if (work[k] - work[k - 1] > gap) gap = work[k] - work[k - 1];
        if (gap >= CN_PI - HULL_KEEP_ANGLE) keep[nk++] = i;
    }
    /* drop the kept points inside a segment between two others kept (in turn, so that of
     * several collinear points the two outermost stay) */
    for (int a = 0; a < nk; a++) {
        const double *p = x[keep[a]];
        bool inside = false;
        for (int b = 0; b < nk && !inside; b++)
            for (int c = b + 1; c < nk && !inside; c++) {
                if (b == a || c == a) continue;
                const double *q = x[keep[b]], *r = x[keep[c]];
                double d[2] = {r[0] - q[0], r[1] - q[1]}, L2 = d[0] * d[0] + d[1] * d[1];
                double scale = 1 + fabs(p[0]) + fabs(p[1]) + fabs(q[0]) + fabs(q[1]) + fabs(r[0]) + fabs(r[1]);
                if (!(L2 > 0)) continue;
                double t = ((p[0] - q[0]) * d[0] + (p[1] - q[1]) * d[1]) / L2;
                double off = fabs(cross2(q, r, p)) / sqrt(L2);
                inside = t > HULL_ON_SEGMENT && t < 1 - HULL_ON_SEGMENT && off <= HULL_ON_SEGMENT * scale;
            }
        if (inside) {
            for (int k = a; k + 1 < nk; k++) keep[k] = keep[k + 1];
            nk--, a--;
        }
    }
    return nk;
}

/* A single contact point where a vertex meets a vertex or an edge's end (or edges cross at their
 * ends): every axis that separates the pieces as well as the best one (within the tolerance)
 * is a normal of the contact, and together they span a cone (where the two features' normal
 * cones meet; its extreme rays are face normals or cross products of edges, all among the
 * axes tried). The pieces may part along any motion that one of its extreme rays does not close,
 * so the manifold carries them all (cn_corner_cone) and the check decides each reading. A box's
 * corner on a box's corner: x, y and z. Were the first tied axis the normal, the verdict would
 * depend on the order of the parts (a plank's corner on a block's corner: unstable in one
 * order, stable in another). A vertex on a face, or edges crossing inside both, have one
 * normal and are left as they are. */
static int vertex_cone3(const cnPiece *P, const double oP[3], const cnPiece *Q, const double oQ[3],
                        const Samples *sp, const Samples *sq, const int *dp, int np, const int *dq,
                        int nq, const cnGaussFilter *gf, const double vrel[3], double tol, double best,
                        const double bu[3], cnManifold *m) {
    Axes *A = cn_malloc(sizeof *A);
    if (!A) return -1;
    A->n = 0;
    A->full = false;
    double plo, phi, qlo, qhi;
#define TIED(u)                                                                                    \
    (!(best - (start_hi(Q, sq, oQ, u) - reach_lo(P, sp, oP, u)) > tol) &&                          \
     (extent3(P, oP, u, &plo, &phi), extent3(Q, oQ, u, &qlo, &qhi), fabs((qlo - phi) - best) <= tol))
    int nf = P->nfaces + Q->nfaces;
    for (int k = 0; k < nf; k++) {
        double u[3];
        if (sat_axis(P, Q, dp, dq, nq, k, u) && TIED(u)) axes_add(A, u);
    }
    long long ek;
    for (long long c = 0; next_edge_axis(gf, nf, np, nq, &c, &ek);) {
        double u[3];
        if (!sat_axis(P, Q, dp, dq, nq, ek, u)) continue;
        if (best - gauss_bound(gf, P, oP, Q, oQ, dp, dq, nq, nf, ek, u) > tol) continue;
        if (TIED(u)) axes_add(A, u);
    }
#undef TIED
    if (A->n < 2) {
        cn_free(A);
        return 0;
    }
    /* a direction c inside the cone (every axis within 90 degrees of it): the perceptron, from
     * the chosen axis, adding the worst axis to an unnormalised sum (it ends within about
     * 1 / margin^2 steps; renormalising after each step kept c on the bisector of the worst two,
     * and it went back and forth between them on cones of margin 0.3) */
    double c[3], w[3];
    cn_copy3(w, bu);
    bool centred = false;
    for (int it = 0; it < VERTEX_CENTRE_STEPS && !centred; it++) {
        double nw = cn_norm3(w);
        if (!(nw > 0)) break;
        cn_copy3(c, w);
        cn_scale3(c, 1.0 / nw);
        int worst = 0;
        for (int i = 1; i < A->n; i++)
            if (cn_dot3(A->u[i], c) < cn_dot3(A->u[worst], c)) worst = i;
        if (cn_dot3(A->u[worst], c) >= VERTEX_CENTRE_COS) centred = true;
        else cn_add3(w, A->u[worst], w);
    }
    double ends[VERTEX_AXES_MAX][3];
    int ne = 0;
    /* not centred: every axis is an end (the true ends are among them; the others are one
     * reading too many each) */
    bool wide = A->full;
    if (centred) {
        /* the cone's extreme rays: the vertices of the hull of the axes' central projection on
         * the plane through c + their directions (two ends for a fan about an edge) */
        double t1[3], t2[3], (*x)[2] = cn_malloc(sizeof(double[2]) * (size_t)A->n);
        int *keep = cn_malloc(sizeof(int) * (size_t)A->n);
        double *work = cn_malloc(sizeof(double) * (size_t)A->n);
        if (!x || !keep || !work) {
            cn_free(x), cn_free(keep), cn_free(work), cn_free(A);
            return -1;
        }
        cn_tangent_basis(c, t1, t2);
        for (int i = 0; i < A->n; i++) {
            double d = cn_dot3(A->u[i], c);
            x[i][0] = cn_dot3(A->u[i], t1) / d, x[i][1] = cn_dot3(A->u[i], t2) / d;
        }
        int h = hull_vertices((const double(*)[2])x, A->n, keep, work);
        for (int k = 0; k < h; k++) cn_copy3(ends[ne++], A->u[keep[k]]);
        cn_free(x), cn_free(keep), cn_free(work);
    } else {
        for (int i = 0; i < A->n; i++) cn_copy3(ends[ne++], A->u[i]);
    }
    cn_free(A);
    if (ne < 2) return 0;
    /* the end nearest the chosen axis first, the others in the order found */
    int near = 0;
    for (int i = 1; i < ne; i++)
        if (cn_dot3(ends[i], bu) > cn_dot3(ends[near], bu)) near = i;
    double ord[VERTEX_AXES_MAX][3];
    for (int i = 0; i < ne; i++) cn_copy3(ord[i], ends[(near + i) % ne]);
    cn_corner_cone(vrel, (const double(*)[3])ord, ne, m);
    if (m->corner && wide) m->wide = true;
    return 0;
}

/* The contact points of two pieces that touch along axis bu: the faces' features within tol of
 * the axis's extremes, projected on the tangent plane, intersected; pushed into m. CN_PAIR_TOUCH,
 * CN_PAIR_APART (the features do not meet) or -1 (out of memory). */
static int touch_manifold(const cnPiece *P, const double oP[3], const cnPiece *Q, const double oQ[3],
                          const double bu[3], double tol, cnManifold *m) {
    double plo, phi, qlo, qhi;
    extent3(P, oP, bu, &plo, &phi);
    extent3(Q, oQ, bu, &qlo, &qhi);
    double t1[3], t2[3];
    cn_tangent_basis(bu, t1, t2);
    int cap = P->nverts + Q->nverts + 4;
    double(*A)[2] = cn_malloc(sizeof(double[2]) * (size_t)cap * 3);
    if (!A) return -1;
    double(*B)[2] = A + cap, (*R)[2] = A + 2 * cap;
    /* project relative to a common origin (the centre of P's feature) */
    double c[3] = {0, 0, 0};
    int na = 0, nb = 0, cnt = 0;
    for (int i = 0; i < P->nverts; i++) {
        double x[3];
        cn_add3(P->verts[i], oP, x);
        if (cn_dot3(bu, x) >= phi - tol) cn_add3(c, x, c), cnt++;
    }
    cn_scale3(c, 1.0 / cnt);
    for (int i = 0; i < P->nverts; i++) {
        double x[3];
        cn_add3(P->verts[i], oP, x);
        if (cn_dot3(bu, x) >= phi - tol) {
            cn_sub3(x, c, x);
            A[na][0] = cn_dot3(x, t1), A[na][1] = cn_dot3(x, t2), na++;
        }
    }
    for (int i = 0; i < Q->nverts; i++) {
        double x[3];
        cn_add3(Q->verts[i], oQ, x);
        if (cn_dot3(bu, x) <= qlo + tol) {
            cn_sub3(x, c, x);
            B[nb][0] = cn_dot3(x, t1), B[nb][1] = cn_dot3(x, t2), nb++;
        }
    }
    na = cn_hull2(A, na, tol);
    nb = cn_hull2(B, nb, tol);
    int nr = (na > 0 && nb > 0) ? cn_convex_intersect2((const double(*)[2])A, na,
                                                       (const double(*)[2])B, nb, tol, R, cap)
                                : 0;
    int rc = nr > 0 ? CN_PAIR_TOUCH : CN_PAIR_APART;
    if (nr < 0 || na < 0 || nb < 0) rc = -1;
    double h = 0.5 * (phi + qlo) - cn_dot3(bu, c);
    for (int i = 0; i < nr && rc == CN_PAIR_TOUCH; i++) {
        double x[3];
        for (int k = 0; k < 3; k++) x[k] = c[k] + R[i][0] * t1[k] + R[i][1] * t2[k] + h * bu[k];
        if (cn_manifold_push(m, x) < 0) rc = -1;
    }
    cn_free(A);
    return rc;
}

int cn_contact3_pieces(const cnPiece *P, const double oP[3], const cnPiece *Q,
                       const double oQ[3], const double vrel[3], double tol, cnManifold *m) {
    double best = -INFINITY, bu[3] = {0, 0, 1};
    double plo, phi, qlo, qhi;
    /* an axis can win only if best - sep <= tol (cn_axis_better's tie, computed as it computes
     * it: best - bound > tol implies best - sep > tol in floating point too, since sep <= bound and
     * rounded subtraction is monotone), and can end the search early only if it beats every axis
     * before it: such an axis is skipped */
    Samples sp, sq;
    samples_of(P, &sp);
    samples_of(Q, &sq);
#define CANNOT_WIN(u) (best - (start_hi(Q, &sq, oQ, u) - reach_lo(P, &sp, oP, u)) > tol)
    int nf = P->nfaces + Q->nfaces;
    for (int k = 0; k < nf; k++) {
        double u[3];
        sat_axis(P, Q, NULL, NULL, 0, k, u);
        if (CANNOT_WIN(u)) continue;
        extent3(P, oP, u, &plo, &phi);
        extent3(Q, oQ, u, &qlo, &qhi);
        double sep = qlo - phi;
        if (sep > APART_EARLY * tol) return apart(m, sep, u);
        if (cn_axis_better(sep, u, best, bu, vrel, tol)) best = sep, cn_copy3(bu, u);
    }
    double best_face = best, bface[3];
    cn_copy3(bface, bu);
    int *dp = cn_malloc(sizeof(int) * (size_t)(P->nedges + Q->nedges + 1));
    if (!dp) return -1;
    int *dq = dp + P->nedges;
    int np = edge_dirs(P, dp), nq = edge_dirs(Q, dq);
    cnGaussFilter gf;
    cn_gauss_filter(P, Q, &gf);
    long long ek;
    for (long long c = 0; next_edge_axis(&gf, nf, np, nq, &c, &ek);) {
        double u[3];
        if (!sat_axis(P, Q, dp, dq, nq, ek, u)) continue;
        if (best - gauss_bound(&gf, P, oP, Q, oQ, dp, dq, nq, nf, ek, u) > tol || CANNOT_WIN(u)) continue;
        /* the best face's own axis again, to rounding (edges in the plane of a resting face and
           of the face under it): its separation, which cannot beat the face's */
        double cr[3];
        cn_cross3(u, bface, cr);
        if (cn_dot3(u, bface) > 0 && cn_norm3(cr) <= SAME_AXIS_SIN) continue;
        extent3(P, oP, u, &plo, &phi);
        extent3(Q, oQ, u, &qlo, &qhi);
        double sep = qlo - phi;
        if (sep > APART_EARLY * tol) {
            cn_free(dp);
            cn_gauss_filter_free(&gf);
            return apart(m, sep, u);
        }
        /* edge axes must beat the faces clearly: resting faces keep their normal */
        if (sep > best_face + 1e-3 * tol && cn_axis_better(sep, u, best, bu, vrel, tol))
            best = sep, cn_copy3(bu, u);
    }
#undef CANNOT_WIN
    m->n = 0;
    m->gap = best;
    cn_copy3(m->normal, bu);
    if (best > tol || best < -tol) {
        cn_free(dp);
        cn_gauss_filter_free(&gf);
        return best > tol ? CN_PAIR_APART : CN_PAIR_OVERLAP;
    }

    int rc = touch_manifold(P, oP, Q, oQ, bu, tol, m);
    if (rc == CN_PAIR_TOUCH && m->n == 2) corner_cone3(P, oP, Q, oQ, vrel, tol, best, bu, m);
    if (rc == CN_PAIR_TOUCH && m->n == 1 &&
        vertex_cone3(P, oP, Q, oQ, &sp, &sq, dp, np, dq, nq, &gf, vrel, tol, best, bu, m) < 0)
        rc = -1;
    cn_free(dp);
    cn_gauss_filter_free(&gf);
    return rc;
}
