/* Contact events along a turn: the angles at which the contact topology between turning convex
 * pieces and static ones can change, the counterpart of events.c for a rotation by an angle A
 * about an axis k through a point c.
 *
 * Turned by phi, a point x goes round a circle: x(phi) = x0 + cos(phi) x1 + sin(phi) x2, with
 * x0 = c + ((x - c).k) k, x1 the part of x - c across k and x2 = k x x1. Relative to the turning
 * piece, a static point goes round the same axis the other way (-k). So:
 *  - a vertex meets a plane (a face's, 3-D; an edge's line through k, both dimensions) where
 *    n.x(phi) - d = a cos(phi) + b sin(phi) + c0 vanishes: solved in closed form, then kept when
 *    the point lies within the face or on the segment (within tol), as events.c does;
 *  - an edge crosses an edge (3-D) where the triple product g(phi) = (e1(phi) x e2).(p1(phi) - b1)
 *    of the turning edge p1 + t e1 and the static edge b1 + t e2 vanishes: a trigonometric
 *    polynomial of degree 2, whose roots are bracketed on a grid fine enough for the farthest
 *    point's arc (a quarter of the shorter edge per cell, at most pi/32), with the extremes of g
 *    found between sign changes of g' (two roots in one cell, or a graze within tol), each root
 *    then bisected to a thousandth of the tolerance in arc length.
 * A vertex passing a vertex is a vertex meeting the edges at that vertex. Exact up to rounding for
 * the closed forms. The edge-edge roots are as good as the grid: two roots of g in one cell have
 * an extreme between them (Rolle), found where g' changes sign across the cell; they are missed
 * only if g' vanishes twice in that cell too (two extremes of g within one cell). Edges that stay
 * in one plane all along have no crossing of their own: an end of one crosses the other. */
#include <math.h>
#include <stdlib.h>

#include "collide.h"

/* The edge-edge grid: at most this angle per cell (radians), and at most this many cells. */
#define TURN_GRID_MAX_STEP (CN_PI / 32)
#define TURN_GRID_MAX_CELLS 2048
/* The farthest point travels at most this fraction of the shorter edge per cell. */
#define TURN_GRID_EDGE_FRACTION 0.25
/* Roots are bisected until the farthest point's arc is below this fraction of the tolerance. */
#define TURN_ROOT_TOL 1e-3

typedef struct {
    double *ev, *rad;
    int n, cap;
    int dropped;
    double A, slack;
} Events;

/* An event at angle phi, touching at distance r from the axis. */
static void add(Events *E, double phi, double r) {
    if (!(phi > -E->slack && phi < E->A + E->slack)) return;
    if (E->n == E->cap) {
        E->dropped++;
        return;
    }
    E->ev[E->n] = fmin(fmax(phi, 0.0), E->A);
    E->rad[E->n++] = r;
}

/* The turn: unit axis k through c, by angles in [0, A] (A <= 2 pi, as the loader allows). */
typedef struct {
    double k[3], c[3];
    double A;
    double tol;   /* contact tolerance (length) */
} Turn;

/* x(phi) = x0 + cos(phi) x1 + sin(phi) x2 */
typedef struct {
    double x0[3], x1[3], x2[3];
    double r; /* |x1|: the distance from the axis */
} Circle;

static void circle_of(const double k[3], const double c[3], const double x[3], Circle *C) {
    double w[3];
    cn_sub3(x, c, w);
    double z = cn_dot3(k, w);
    for (int i = 0; i < 3; i++) {
        C->x0[i] = c[i] + z * k[i];
        C->x1[i] = w[i] - z * k[i];
    }
    cn_cross3(k, C->x1, C->x2);
    C->r = cn_norm3(C->x1);
}

static void circle_at(const Circle *C, double phi, double out[3]) {
    double co = cos(phi), si = sin(phi);
    for (int i = 0; i < 3; i++) out[i] = C->x0[i] + co * C->x1[i] + si * C->x2[i];
}

/* The angles in [-slack, A + slack] where a cos(phi) + b sin(phi) + c0 = 0 (a tangent within
 * tolc: where it comes closest), for a point at distance r from the axis; up to 6 in out. */
static int trig_roots(double a, double b, double c0, double tolc, double A, double slack,
                      double r, double out[6]) {
    double R = hypot(a, b);
    /* a point going round in a plane parallel to the plane (r: its distance from the axis) */
    if (!(R > CN_TOL_NOISE * r) || fabs(c0) > R + tolc) return 0;
    /* a cos + b sin = R cos(phi - al) */
    double al = atan2(b, a), d = acos(fmax(-1.0, fmin(1.0, -c0 / R)));
    double base[2] = {al + d, al - d};
    int n = 0;
    for (int i = 0; i < (d > 0 ? 2 : 1); i++) {
        double p = fmod(base[i], 2 * CN_PI);
        if (p < 0) p += 2 * CN_PI;
        for (int m = -1; m <= 1; m++) {
            double q = p + 2 * CN_PI * m;
            if (q >= -slack && q <= A + slack) out[n++] = q;
        }
    }
    return n;
}

/* The distance from p to the segment [b1, b2]. */
static double seg_dist(const double p[3], const double b1[3], const double b2[3]) {
    double e[3], w[3], r[3];
    cn_sub3(b2, b1, e);
    cn_sub3(p, b1, w);
    double ee = cn_dot3(e, e), t = ee > 0 ? cn_dot3(w, e) / ee : 0;
    t = fmin(fmax(t, 0.0), 1.0);
    for (int k = 0; k < 3; k++) r[k] = w[k] - t * e[k];
    return cn_norm3(r);
}

/* A vertex going round C (about k) meets the segment [b1, b2]: 2-D (vertex on edge) and 3-D.
 * Every point of the segment's line lies in the plane through it along k (or, for a line along
 * k, any plane through it along k): the circle crosses that plane at most twice; a crossing is an
 * event when the point is on the segment within tol. */
static void vertex_segment(Events *E, const Turn *T, const Circle *C, const double b1[3],
                           const double b2[3]) {
    if (!(C->r > 0)) return; /* on the axis: does not move */
    double e[3], n[3];
    cn_sub3(b2, b1, e);
    double el = cn_norm3(e);
    if (!(el > 0)) return;
    cn_cross3(T->k, e, n);
    if (!(cn_norm3(n) > CN_TOL_CORNER * el)) { /* along the axis: any plane through it along k */
        double o[3] = {1, 0, 0};
        if (fabs(T->k[0]) > 0.5) o[0] = 0, o[1] = 1;
        cn_cross3(T->k, o, n);
    }
    cn_normalize3(n);
    double w[3];
    cn_sub3(C->x0, b1, w);
    double roots[6];
    int nr = trig_roots(cn_dot3(n, C->x1), cn_dot3(n, C->x2), cn_dot3(n, w), T->tol, T->A,
                        T->tol / C->r, C->r, roots);
    for (int i = 0; i < nr; i++) {
        double p[3];
        circle_at(C, roots[i], p);
        if (seg_dist(p, b1, b2) <= T->tol) add(E, roots[i], C->r);
    }
}

/* A vertex going round C meets the face f of piece Q (3-D), whose vertices are verts. */
static void vertex_face(Events *E, const Turn *T, const Circle *C, const double (*verts)[3],
                        const cnFace *f, const double normal[3], double offset) {
    if (!(C->r > 0)) return;
    double roots[6];
    int nr = trig_roots(cn_dot3(normal, C->x1), cn_dot3(normal, C->x2),
                        cn_dot3(normal, C->x0) - offset, T->tol, T->A, T->tol / C->r, C->r, roots);
    for (int r = 0; r < nr; r++) {
        double p[3];
        circle_at(C, roots[r], p);
        /* inside the face loop: on the inner side of every edge (in the face's plane) */
        bool inside = true;
        for (int i = 0; inside && i < f->nverts; i++) {
            const double *a = verts[f->verts[i]], *b = verts[f->verts[(i + 1) % f->nverts]];
            double e[3], w[3], c[3];
            cn_sub3(b, a, e);
            cn_sub3(p, a, w);
            cn_cross3(e, w, c);
            double el = cn_norm3(e);
            if (el > 0 && cn_dot3(c, normal) < -T->tol * el) inside = false;
        }
        if (inside) add(E, roots[r], C->r);
    }
}

/* The edge p1 p2 turning (circles C1, C2 about T->k) against the static edge b1 b2 (3-D). */
typedef struct {
    const Turn *T;
    const Circle *C1, *C2;
    const double *b1, *b2;
    double e2[3];
    double scale; /* |e1| |e2| */
} EdgePair;

/* g(phi) = (e1 x e2).(p1 - b1) / (|e1| |e2|) and its derivative (the velocity of a point p going
 * round is k x (p - x0)). */
static void edge_g(const EdgePair *P, double phi, double *g, double *dg) {
    double p1[3], p2[3], e1[3], v1[3], v2[3], dv[3], w[3], c[3], r[3];
    circle_at(P->C1, phi, p1);
    circle_at(P->C2, phi, p2);
    cn_sub3(p2, p1, e1);
    cn_sub3(p1, P->b1, w);
    cn_cross3(e1, P->e2, c);
    *g = cn_dot3(c, w) / P->scale;
    if (!dg) return;
    cn_sub3(p1, P->C1->x0, r);
    cn_cross3(P->T->k, r, v1);
    cn_sub3(p2, P->C2->x0, r);
    cn_cross3(P->T->k, r, v2);
    cn_sub3(v2, v1, dv);
    cn_cross3(dv, P->e2, r);
    *dg = (cn_dot3(r, w) + cn_dot3(c, v1)) / P->scale;
}

/* At phi: do the two segments meet within tol? Then the event (touching at the turning edge's
 * point, its distance from the axis). */
static void edge_check(Events *E, const EdgePair *P, double phi) {
    double p1[3], p2[3], e1[3], w[3];
    circle_at(P->C1, phi, p1);
    circle_at(P->C2, phi, p2);
    cn_sub3(p2, p1, e1);
    cn_sub3(P->b1, p1, w);
    /* nearest points of the lines p1 + t1 e1, b1 + t2 e2 */
    double aa = cn_dot3(e1, e1), bb = cn_dot3(P->e2, P->e2), ab = cn_dot3(e1, P->e2);
    double det = aa * bb - ab * ab;
    if (!(det > 1e-12 * aa * bb)) return; /* parallel: the vertex events cover it */
    double aw = cn_dot3(e1, w), bw = cn_dot3(P->e2, w);
    double t1 = (bb * aw - ab * bw) / det, t2 = (ab * aw - aa * bw) / det;
    double s1 = P->T->tol / sqrt(aa), s2 = P->T->tol / sqrt(bb);
    if (t1 < -s1 || t1 > 1 + s1 || t2 < -s2 || t2 > 1 + s2) return;
    double x[3], y[3], d[3];
    for (int k = 0; k < 3; k++) x[k] = p1[k] + t1 * e1[k], y[k] = P->b1[k] + t2 * P->e2[k];
    cn_sub3(x, y, d);
    if (cn_norm3(d) > P->T->tol) return;
    double rr[3];
    cn_sub3(x, P->T->c, rr);
    double z = cn_dot3(rr, P->T->k);
    for (int k = 0; k < 3; k++) rr[k] -= z * P->T->k[k];
    add(E, phi, cn_norm3(rr));
}

/* A root of g (or of g' with deriv) in [lo, hi], whose ends have opposite signs (flo at lo). */
static double bisect_root(const EdgePair *P, bool deriv, double lo, double hi, double flo,
                          double htol) {
    for (int it = 0; it < 200 && hi - lo > htol; it++) {
        double mid = 0.5 * (lo + hi), g, dg;
        edge_g(P, mid, &g, &dg);
        double f = deriv ? dg : g;
        if (f == 0) return mid;
        if ((f < 0) == (flo < 0)) lo = mid, flo = f;
        else hi = mid;
    }
    return 0.5 * (lo + hi);
}

static void edge_edge(Events *E, const Turn *T, const Circle *C1, const Circle *C2,
                      const double b1[3], const double b2[3]) {
    EdgePair P = {T, C1, C2, b1, b2, {0, 0, 0}, 0};
    cn_sub3(b2, b1, P.e2);
    double e1[3];
    cn_sub3(C2->x0, C1->x0, e1); /* |e1| is that of the edge at any angle */
    double d1[3];
    cn_sub3(C2->x1, C1->x1, d1);
    double l1 = sqrt(cn_dot3(e1, e1) + cn_dot3(d1, d1)), l2 = cn_norm3(P.e2);
    double rmax = fmax(C1->r, C2->r);
    if (!(l1 > 0 && l2 > 0 && rmax > 0)) return;
    P.scale = l1 * l2;
    double h = fmin(TURN_GRID_MAX_STEP, TURN_GRID_EDGE_FRACTION * fmin(l1, l2) / rmax);
    int N = (int)fmin(ceil(T->A / h), TURN_GRID_MAX_CELLS);
    if (N < 1) N = 1;
    h = T->A / N;
    double htol = TURN_ROOT_TOL * T->tol / rmax;
    /* edges that stay in one plane (within a thousandth of the tolerance) all along: where they
       cross, an end of one crosses the other (the vertex events) */
    bool flat = true;
    int M = N > 8 ? N : 8; /* at least 9 points: g vanishes at no more than 4 of a full turn */
    for (int i = 0; flat && i <= M; i++) {
        double g;
        edge_g(&P, T->A * i / M, &g, NULL);
        flat = fabs(g) <= TURN_ROOT_TOL * T->tol;
    }
    if (flat) return;
    /* a graze: |g| (a distance times the sine between the edges) within tol */
    double g0, d0;
    edge_g(&P, 0, &g0, &d0);
    if (g0 == 0) edge_check(E, &P, 0);
    for (int i = 0; i < N; i++) {
        double lo = i * h, hi = i + 1 == N ? T->A : (i + 1) * h, g1, d1e;
        edge_g(&P, hi, &g1, &d1e);
        /* the cell split at an extreme of g, if g' changes sign in it */
        double pts[3] = {lo, hi, hi}, val[3] = {g0, g1, g1};
        int np = 2;
        if ((d0 < 0 && d1e > 0) || (d0 > 0 && d1e < 0)) {
            double m = bisect_root(&P, true, lo, hi, d0, htol), gm;
            edge_g(&P, m, &gm, NULL);
            pts[1] = m, val[1] = gm, np = 3;
            if (fabs(gm) <= T->tol) edge_check(E, &P, m);
        }
        for (int j = 0; j + 1 < np; j++) {
            if (val[j + 1] == 0) edge_check(E, &P, pts[j + 1]);
            else if ((val[j] < 0 && val[j + 1] > 0) || (val[j] > 0 && val[j + 1] < 0))
                edge_check(E, &P, bisect_root(&P, false, pts[j], pts[j + 1], val[j], htol));
        }
        g0 = g1, d0 = d1e;
    }
}

/* Edges of a piece: 2-D polygons' consecutive vertices, 3-D the unique edge list. */
static int nedges(const cnPiece *P, int dim) { return dim == 2 ? P->nverts : P->nedges; }
static void edge(const cnPiece *P, int dim, int i, int *a, int *b) {
    if (dim == 2) *a = i, *b = (i + 1) % P->nverts;
    else *a = P->edges[i][0], *b = P->edges[i][1];
}

/* Where a set of points lies relative to the turn's axis: along it [zlo, zhi], and from it
 * [rlo, rhi] (rlo a lower bound: the centroid's distance less the spread about it). */
typedef struct {
    double zlo, zhi, rlo, rhi;
} Band;

static Band band_of(const Turn *T, const double (*x)[3], int n) {
    Band b = {INFINITY, -INFINITY, 0, 0};
    double m[3] = {0, 0, 0};
    for (int i = 0; i < n; i++) {
        Circle C;
        circle_of(T->k, T->c, x[i], &C);
        double z = cn_dot3(T->k, x[i]);
        b.zlo = fmin(b.zlo, z), b.zhi = fmax(b.zhi, z), b.rhi = fmax(b.rhi, C.r);
        for (int k = 0; k < 3; k++) m[k] += C.x1[k] / n;
    }
    double spread = 0;
    for (int i = 0; i < n; i++) {
        Circle C;
        circle_of(T->k, T->c, x[i], &C);
        double d[3];
        cn_sub3(C.x1, m, d);
        spread = fmax(spread, cn_norm3(d));
    }
    b.rlo = fmax(0.0, cn_norm3(m) - spread);
    return b;
}

static bool bands_meet(const Band *p, const Band *q, double tol) {
    return p->zlo <= q->zhi + tol && q->zlo <= p->zhi + tol && p->rlo <= q->rhi + tol &&
           q->rlo <= p->rhi + tol;
}

/* Events of turning piece P (vertices pv: posed at the turn's start) against static piece Q. */
static void pair_events(Events *E, const Turn *T, const cnPiece *P, const cnPose *pose,
                        const double (*pv)[3], const cnPiece *Q, int dim) {
    Band bp = band_of(T, pv, P->nverts), bq = band_of(T, (const double(*)[3])Q->verts, Q->nverts);
    if (!bands_meet(&bp, &bq, 2 * T->tol)) return;
    Turn back = *T; /* Q's vertices relative to P: the other way round */
    for (int k = 0; k < 3; k++) back.k[k] = -T->k[k];
    int np = nedges(P, dim), nq = nedges(Q, dim);
    for (int i = 0; i < P->nverts; i++) {
        Circle C;
        circle_of(T->k, T->c, pv[i], &C);
        for (int j = 0; j < nq; j++) {
            int a, b;
            edge(Q, dim, j, &a, &b);
            vertex_segment(E, T, &C, Q->verts[a], Q->verts[b]);
        }
        if (dim == 3)
            for (int f = 0; f < Q->nfaces; f++)
                vertex_face(E, T, &C, (const double(*)[3])Q->verts, &Q->faces[f],
                            Q->faces[f].normal, Q->faces[f].offset);
    }
    for (int j = 0; j < Q->nverts; j++) {
        Circle C;
        circle_of(back.k, back.c, Q->verts[j], &C);
        for (int i = 0; i < np; i++) {
            int a, b;
            edge(P, dim, i, &a, &b);
            vertex_segment(E, &back, &C, pv[a], pv[b]);
        }
        if (dim == 3)
            for (int f = 0; f < P->nfaces; f++) { /* P's faces, posed */
                double n[3];
                cn_pose_rotate(pose, P->faces[f].normal, n);
                const cnFace *g = &P->faces[f];
                vertex_face(E, &back, &C, pv, g, n, cn_dot3(n, pv[g->verts[0]]));
            }
    }
    if (dim != 3) return;
    for (int i = 0; i < np; i++) {
        int a1, a2;
        edge(P, dim, i, &a1, &a2);
        const double ep[2][3] = {{pv[a1][0], pv[a1][1], pv[a1][2]},
                                 {pv[a2][0], pv[a2][1], pv[a2][2]}};
        Band be = band_of(T, ep, 2);
        Circle C1, C2;
        circle_of(T->k, T->c, pv[a1], &C1);
        circle_of(T->k, T->c, pv[a2], &C2);
        if (!bands_meet(&be, &bq, 2 * T->tol)) continue;
        for (int j = 0; j < nq; j++) {
            int b1, b2;
            edge(Q, dim, j, &b1, &b2);
            const double eq[2][3] = {{Q->verts[b1][0], Q->verts[b1][1], Q->verts[b1][2]},
                                     {Q->verts[b2][0], Q->verts[b2][1], Q->verts[b2][2]}};
            Band bf = band_of(T, eq, 2);
            if (!bands_meet(&be, &bf, 2 * T->tol)) continue;
            edge_edge(E, T, &C1, &C2, Q->verts[b1], Q->verts[b2]);
        }
    }
}

typedef struct {
    double phi, r;
} EvR;

static int cmp_ev(const void *x, const void *y) {
    double a = ((const EvR *)x)->phi, b = ((const EvR *)y)->phi;
    return (a > b) - (a < b);
}

int cn_contact_events_turn(const cnAssembly *a, const unsigned char *moving,
                           const unsigned char *still, const cnPose *pose, const double axis[3],
                           const double about[3], double angle, double *ev, double *radius,
                           int cap, int *dropped) {
    int dim = a->dim;
    *dropped = 0;
    Turn T;
    cn_copy3(T.k, axis);
    cn_copy3(T.c, about);
    if (!(cn_normalize3(T.k) > 0) || !(angle != 0) || !isfinite(angle)) return 0;
    if (angle < 0) cn_scale3(T.k, -1.0);
    T.A = fabs(angle);
    T.tol = a->contact_tol;
    int maxv = 0;
    double rmax = 0;
    for (int i = 0; i < a->nparts; i++)
        if (moving[i])
            for (int k = 0; k < a->parts[i].npieces; k++) {
                const cnPiece *P = &a->parts[i].pieces[k];
                maxv = P->nverts > maxv ? P->nverts : maxv;
                for (int v = 0; v < P->nverts; v++) {
                    double x[3];
                    Circle C;
                    cn_pose_apply(pose, P->verts[v], x);
                    circle_of(T.k, T.c, x, &C);
                    rmax = fmax(rmax, C.r);
                }
            }
    if (!(rmax > 0)) return 0;
    double (*pv)[3] = cn_malloc(sizeof(double) * 3 * (size_t)(maxv + 1));
    double *rad = radius ? radius : cn_malloc(sizeof(double) * (size_t)(cap + 1));
    if (!pv || !rad) {
        cn_free(pv);
        if (!radius) cn_free(rad);
        return -1;
    }
    Events E = {ev, rad, 0, cap, 0, T.A, T.tol / rmax};
    for (int i = 0; i < a->nparts; i++) {
        if (!moving[i]) continue;
        const cnPart *P = &a->parts[i];
        /* the broad phase: the band the part's box sweeps against each static part's */
        double corners[8][3];
        for (int c = 0; c < 8; c++) {
            double x[3] = {c & 1 ? P->hi[0] : P->lo[0], c & 2 ? P->hi[1] : P->lo[1],
                           c & 4 ? P->hi[2] : P->lo[2]};
            cn_pose_apply(pose, x, corners[c]);
        }
        Band bp = band_of(&T, (const double(*)[3])corners, 8);
        for (int j = 0; j < a->nparts; j++) {
            if (!still[j]) continue;
            const cnPart *Q = &a->parts[j];
            double qc[8][3];
            for (int c = 0; c < 8; c++) {
                qc[c][0] = c & 1 ? Q->hi[0] : Q->lo[0];
                qc[c][1] = c & 2 ? Q->hi[1] : Q->lo[1];
                qc[c][2] = c & 4 ? Q->hi[2] : Q->lo[2];
            }
            Band bq = band_of(&T, (const double(*)[3])qc, 8);
            if (!bands_meet(&bp, &bq, 2 * T.tol)) continue;
            for (int p = 0; p < P->npieces; p++) {
                const cnPiece *pc = &P->pieces[p];
                for (int v = 0; v < pc->nverts; v++) cn_pose_apply(pose, pc->verts[v], pv[v]);
                for (int q = 0; q < Q->npieces; q++)
                    pair_events(&E, &T, pc, pose, (const double(*)[3])pv, &Q->pieces[q], dim);
            }
        }
    }
    cn_free(pv);
    /* sorted by angle, distinct where the farthest point moves more than the roots' precision
       between them (the nearest touching point kept) */
    int m = 0;
    EvR *s = cn_malloc(sizeof(EvR) * (size_t)(E.n + 1));
    if (!s) {
        if (!radius) cn_free(rad);
        return -1;
    }
    for (int i = 0; i < E.n; i++) s[i] = (EvR){ev[i], rad[i]};
    qsort(s, (size_t)E.n, sizeof(EvR), cmp_ev);
    for (int i = 0; i < E.n; i++) {
        if (m > 0 && s[i].phi - ev[m - 1] <= TURN_ROOT_TOL * T.tol / rmax) {
            rad[m - 1] = fmin(rad[m - 1], s[i].r);
            continue;
        }
        ev[m] = s[i].phi, rad[m] = s[i].r, m++;
    }
    cn_free(s);
    if (!radius) cn_free(rad);
    *dropped = E.dropped;
    return m;
}
