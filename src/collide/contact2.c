/* 2-D contacts between convex polygons.
 *
 * Separating-axis test over the edge normals of both polygons gives the contact normal (the axis
 * of largest separation) and the gap. When the gap is within the tolerance, the touching
 * features are the vertices of each polygon within the tolerance of the separating line; their
 * extents along the tangent overlap in an interval whose end points are the contact points:
 * two for edge-edge (the overlap segment's ends), one for vertex-edge or vertex-vertex. */
#include <math.h>

#include "collide.h"

/* A touching interval up to this many tolerances long is tested for a corner on a corner: two
 * corners whose tips overlap by up to the tolerance meet along parallel edges over about the
 * tolerance over the sine of their angle. */
#define CN_CORNER_OVERLAP_SPAN 16

/* Ties between axes resolve to the first axis found (P's edges before Q's) deterministically,
 * unless the relative motion closes one and not the other (cn_axis_better). */

static void extent(const cnPiece *P, const double o[3], const double u[2], double *lo,
                   double *hi) {
    *lo = INFINITY;
    *hi = -INFINITY;
    for (int i = 0; i < P->nverts; i++) {
        double d = u[0] * (P->verts[i][0] + o[0]) + u[1] * (P->verts[i][1] + o[1]);
        *lo = fmin(*lo, d);
        *hi = fmax(*hi, d);
    }
}

/* The separation along the outward normal u of edge i of S (side 0: P's edge, axis from P to Q;
 * side 1: Q's edge, axis reversed) and the axis itself. */
static double edge_axis(const cnPiece *P, const double oP[3], const cnPiece *Q, const double oQ[3],
                        int side, int i, double u[2]) {
    const cnPiece *S = side ? Q : P;
    const double *a = S->verts[i], *b = S->verts[(i + 1) % S->nverts];
    double ex = b[0] - a[0], ey = b[1] - a[1], len = hypot(ex, ey);
    u[0] = ey / len, u[1] = -ex / len; /* outward normal of S's edge */
    if (side) u[0] = -u[0], u[1] = -u[1]; /* axis always points from P to Q */
    /* the polygon whose edge this is reaches furthest along its own outward normal at that edge
     * (convex): only the other one's vertices are scanned, O(n m) in all */
    const double *oS = side ? oQ : oP;
    double da = u[0] * (a[0] + oS[0]) + u[1] * (a[1] + oS[1]);
    double db = u[0] * (b[0] + oS[0]) + u[1] * (b[1] + oS[1]);
    double lo, hi;
    if (!side) {
        extent(Q, oQ, u, &lo, &hi);
        return lo - fmax(da, db);
    }
    extent(P, oP, u, &lo, &hi);
    return fmin(da, db) - hi;
}

/* A corner on a corner: every axis within the tolerance of the best separates the two pieces
 * equally well, and the contact has no normal of its own. The admissible normals form a cone
 * (the corners' normal cones meet in it); the pieces may move apart along any direction that
 * one of them does not close, so the contact is the union of the half-planes of the cone's two
 * end normals, not either one alone. When the pieces are at rest relative to each other and the
 * ends differ by more than CN_TOL_CORNER_CONE, the manifold carries both: the normal (the end
 * nearer the chosen axis) and m->alt, and the check decides both readings. */
static bool corner_cone(const cnPiece *P, const double oP[3], const cnPiece *Q, const double oQ[3],
                        const double vrel[3], double tol, double best, const double bu[2],
                        cnManifold *m) {
    double ccw = 0, cw = 0, eccw[3] = {bu[0], bu[1], 0}, ecw[3] = {bu[0], bu[1], 0};
    for (int side = 0; side < 2; side++) {
        const cnPiece *S = side ? Q : P;
        for (int i = 0; i < S->nverts; i++) {
            double u[2];
            double sep = edge_axis(P, oP, Q, oQ, side, i, u);
            if (fabs(sep - best) > tol) continue;
            double ang = atan2(bu[0] * u[1] - bu[1] * u[0], bu[0] * u[0] + bu[1] * u[1]);
            if (ang > ccw) ccw = ang, eccw[0] = u[0], eccw[1] = u[1];
            if (ang < cw) cw = ang, ecw[0] = u[0], ecw[1] = u[1];
        }
    }
    if (ccw - cw <= CN_TOL_CORNER_CONE) return false;
    cn_corner_ends(vrel, eccw, ecw, ccw <= -cw, m);
    return true;
}

int cn_contact2_pieces(const cnPiece *P, const double oP[3], const cnPiece *Q,
                       const double oQ[3], const double vrel[3], double tol, cnManifold *m) {
    double best = -INFINITY, bu[2] = {0, 0};
    for (int side = 0; side < 2; side++) {
        const cnPiece *S = side ? Q : P;
        for (int i = 0; i < S->nverts; i++) {
            double u[2];
            double sep = edge_axis(P, oP, Q, oQ, side, i, u);
            double u3[3] = {u[0], u[1], 0}, b3[3] = {bu[0], bu[1], 0};
            if (cn_axis_better(sep, u3, best, b3, vrel, tol)) best = sep, bu[0] = u[0], bu[1] = u[1];
        }
    }
    m->n = 0;
    m->corner = 0;
    m->gap = best;
    m->normal[0] = bu[0];
    m->normal[1] = bu[1];
    m->normal[2] = 0;
    if (best > tol) return CN_PAIR_APART;
    if (best < -tol) return CN_PAIR_OVERLAP;
    double plo, phi, qlo, qhi;
    extent(P, oP, bu, &plo, &phi);
    extent(Q, oQ, bu, &qlo, &qhi);
    double t[2] = {-bu[1], bu[0]};
    double a0 = INFINITY, a1 = -INFINITY, b0 = INFINITY, b1 = -INFINITY;
    for (int i = 0; i < P->nverts; i++) {
        double x = P->verts[i][0] + oP[0], y = P->verts[i][1] + oP[1];
        if (bu[0] * x + bu[1] * y >= phi - tol) {
            double s = t[0] * x + t[1] * y;
            a0 = fmin(a0, s), a1 = fmax(a1, s);
        }
    }
    for (int i = 0; i < Q->nverts; i++) {
        double x = Q->verts[i][0] + oQ[0], y = Q->verts[i][1] + oQ[1];
        if (bu[0] * x + bu[1] * y <= qlo + tol) {
            double s = t[0] * x + t[1] * y;
            b0 = fmin(b0, s), b1 = fmax(b1, s);
        }
    }
    double lo = fmax(a0, b0), hi = fmin(a1, b1);
    if (lo > hi + tol) return CN_PAIR_APART; /* corners that only nearly meet */
    /* corners whose tips overlap within the tolerance have parallel edges that overlap over a few
       tolerances: still a corner on a corner, one point (the edge pair the first tied axis
       names would depend on the order of the pieces) */
    bool corner = hi - lo <= CN_CORNER_OVERLAP_SPAN * tol && corner_cone(P, oP, Q, oQ, vrel, tol, best, bu, m);
    double h = 0.5 * (phi + qlo);
    double p[3] = {0, 0, 0};
    if (hi - lo <= tol || corner) {
        double s = 0.5 * (lo + hi);
        p[0] = h * bu[0] + s * t[0];
        p[1] = h * bu[1] + s * t[1];
        if (cn_manifold_push(m, p) < 0) return -1;
    } else {
        p[0] = h * bu[0] + lo * t[0];
        p[1] = h * bu[1] + lo * t[1];
        if (cn_manifold_push(m, p) < 0) return -1;
        p[0] = h * bu[0] + hi * t[0];
        p[1] = h * bu[1] + hi * t[1];
        if (cn_manifold_push(m, p) < 0) return -1;
    }
    return CN_PAIR_TOUCH;
}
