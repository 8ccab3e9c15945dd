/* collide: the narrow phase shared by contact.c (broad phase, manifolds), contact2.c (polygons),
 * contact3.c (polyhedra) and gauss_map.c (contact3's filter of edge pairs). Private; includes only model and core. */
#ifndef CAIRN_COLLIDE_H
#define CAIRN_COLLIDE_H

#include "pieces.h"

/* The touching region of two convex pieces: points and one normal from P into Q. */
typedef struct cnManifold {
    double normal[3];
    double gap;          /* signed separation along normal (negative = overlap) */
    int corner;          /* a corner on a corner: the cone of normals has corner + 1 ends, the
                            normal and alt[0 .. corner - 1] */
    double alt[CN_CORNER_ENDS - 1][3];
    bool wide;           /* with corner: the cone had more than CN_CORNER_ENDS ends (the rest
                            were not kept) */
    int n, cap;
    double (*pts)[3];
} cnManifold;

int cn_manifold_push(cnManifold *m, const double p[3]);

/* Edge pairs closer to parallel than this (sine of their angle) give no axis of their own. */
#define EDGE_PARALLEL_SIN 1e-6

/* Pieces with more edges than this skip the search for parallel edges (quadratic in the edges):
 * an axis found twice is tried twice, with the same separation. Past it on both pieces, the
 * Gauss-map filter (gauss_map.c) chooses the edge pairs tried. */
#define EDGE_DIRS_MAX 256

/* The filter of a pair of pieces: the edge pairs (as the separating-axis test numbers them,
 * i * nq + j, in increasing order) that may meet on a face of the Minkowski difference; off
 * (pairs NULL) for small pieces or when out of memory, and every pair is tried. */
typedef struct {
    long long *pairs;
    long long n;
} cnGaussFilter;

void cn_gauss_filter(const cnPiece *P, const cnPiece *Q, cnGaussFilter *g);
void cn_gauss_filter_free(cnGaussFilter *g);

/* Result of a narrow-phase test. */
enum { CN_PAIR_APART = 0, CN_PAIR_TOUCH = 1, CN_PAIR_OVERLAP = 2 };

/* P and Q translated by oP and oQ; vrel: velocity of Q relative to P (breaks ties between
 * axes that touch equally: one that the motion does not close wins). tol: absolute contact
 * tolerance. On CN_PAIR_OVERLAP, m->gap holds minus the penetration depth. Returns -1 on
 * allocation failure. */
int cn_contact2_pieces(const cnPiece *P, const double oP[3], const cnPiece *Q,
                       const double oQ[3], const double vrel[3], double tol, cnManifold *m);
int cn_contact3_pieces(const cnPiece *P, const double oP[3], const cnPiece *Q,
                       const double oQ[3], const double vrel[3], double tol, cnManifold *m);

/* The contact tolerance of parts i and j at their loaded places: the assembly's relative
 * tolerance times the smaller part's size (as the narrow phase judges them), never below what
 * their coordinates resolve. */
double cn_pair_tolerance(const cnAssembly *a, int i, int j);

/* The deepest overlap between two convex pieces of one part beyond tol (relative to the pair's
 * size): its depth, with the pieces in *pi < *pj; 0 when the pieces only touch or are apart.
 * (Overlapping pieces would count their common volume twice in the part's mass.) Returns -1 on
 * allocation failure. */
double cn_part_self_overlap(const cnPart *part, int dim, double rel_tol, int *pi, int *pj);

/* A corner on a corner's cone of normals with ends a and b (a the nearer the chosen axis when
 * a_near): cn_corner_cone with the two ends. Shared by 2-D (contact2.c) and 3-D edges on
 * parallel edges (contact3.c). */
void cn_corner_ends(const double vrel[3], const double a[3], const double b[3], bool a_near,
                    cnManifold *m);

/* A cone of normals with n >= 2 ends (its extreme rays, unit; ends[0] the one shown first; more
 * than CN_CORNER_ENDS: the first CN_CORNER_ENDS kept and m->wide set). The pieces may move apart
 * along any motion that one end does not close (the union of the ends' half-spaces is the union
 * over the whole cone). When the pieces move relative to each other (vrel), the end the motion
 * opens most is the normal (the contact opens); when the motion closes some ends, the others
 * are the cone; when it closes every end, nothing changes (a collision, as the chosen axis
 * says). At rest, the manifold carries every end: ends[0] as its normal, the others as m->alt
 * (m->corner of them). */
void cn_corner_cone(const double vrel[3], const double (*ends)[3], int n, cnManifold *m);

/* Tie-breaking between separating axes: replace the best axis by `u` (separation `sep`)?
 * An axis must beat the best by a small fraction of the tolerance; among axes within the
 * tolerance of each other, one along which the relative motion vrel does not close beats one
 * along which it does. */
static inline int cn_axis_better(double sep, const double u[3], double best, const double bu[3],
                                 const double vrel[3], double tol) {
    double vu = cn_dot3(vrel, u), vb = cn_dot3(vrel, bu);
    double vtol = CN_TOL_NOISE * (cn_norm3(vrel) + 1e-300);
    if (best > -INFINITY && fabs(sep - best) <= tol) {
        int closes_u = vu < -vtol, closes_b = vb < -vtol;
        if (closes_u != closes_b) return closes_b;
    }
    return sep > best + 1e-3 * tol;
}

/* Intersection of two convex planar point sets (each: a point, a segment or a CCW polygon, as
 * produced by cn_hull2), result appended to out as 2-D points (x, y, 0). */
int cn_hull2(double (*pts)[2], int n, double tol);
int cn_convex_intersect2(const double (*A)[2], int na, const double (*B)[2], int nb, double tol,
                         double (*out)[2], int cap);

/* Contact events (events.c): the distances s in [0, L] at which the moving parts (moving[i]),
 * posed by `pose` and translated by s u (u unit), can change how they touch the parts that stay
 * (still[i]): a vertex meets an edge or a face, an edge crosses an edge, a vertex passes a
 * vertex along its line. Sorted, distinct; at most cap (the rest counted in *dropped).
 * Returns the count, -1 out of memory. */
int cn_contact_events(const cnAssembly *a, const unsigned char *moving, const unsigned char *still,
                      const cnPose *pose, const double u[3], double L, double *ev, int cap,
                      int *dropped);

/* Contact events along a turn (events_turn.c): the angles phi in [0, |angle|] at which the moving
 * parts, posed by `pose` and then turned by phi (in the sense of `angle`, radians) about the axis
 * `axis` (nonzero) through `about`, can change how they touch the parts that stay: a vertex meets
 * an edge (2-D and 3-D) or a face (3-D), an edge crosses an edge (3-D). Sorted, distinct; at most
 * cap (the rest counted in *dropped). radius (cap entries, or NULL): the touching point's distance
 * from the axis at each event (the nearest of those at one angle). Returns the count, -1 out of
 * memory. */
int cn_contact_events_turn(const cnAssembly *a, const unsigned char *moving,
                           const unsigned char *still, const cnPose *pose, const double axis[3],
                           const double about[3], double angle, double *ev, double *radius,
                           int cap, int *dropped);

#endif
