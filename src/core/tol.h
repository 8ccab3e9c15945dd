/* The library's scale-free tolerances, named by what they mean. Each is relative: multiply by the
 * scale named in its comment (the assembly's length scale, a path's length, a weight). Solver
 * tolerances with their own reasoning stay beside their solver (e.g. CN_LP_EQ_TOL). */
#ifndef CAIRN_TOL_H
#define CAIRN_TOL_H

/* A length below this fraction of its scale (the assembly's length scale, a path's length, a
 * polygon's size) is zero: a zero-length displacement, coincident points, two samples at the
 * same place along a path. Squared for areas. */
#define CN_TOL_LENGTH_ZERO 1e-12

/* Two unit vectors whose dot product exceeds 1 - this are the same direction ("up" among the
 * free directions, a direction already listed). */
#define CN_TOL_SAME_DIRECTION 1e-12

/* Two great circles of directions (3-D; lines through the origin in 2-D) whose unit normals are
 * closer than this angle (radians) are one circle, and a direction closer than this to a circle
 * lies on it: the blocking graph's arrangement (plan/ndbg.c). Far above the rounding of a normal
 * computed from coordinates (about 1e-15), far below any angle a part's shape makes. */
#define CN_TOL_ANGLE 1e-9

/* A component of a unit vector or of a displacement (relative to its scale) below this is
 * written as 0 in reports and figures: rounding noise, not a value a reader should see. */
#define CN_TOL_PRINT_ZERO 1e-12

/* A quantity below this fraction of its scale (a contact's separation or slip against the
 * motion's, a power against a weight times g) is rounding noise, never a motion. */
#define CN_TOL_NOISE 1e-12

/* A 2-D corner turns when the sine of its turn exceeds this (cross product of its two edges
 * against the product of their lengths): below it the outline runs straight on there. Every
 * convexity test of a polygon, and its split into convex pieces, judge corners by it. */
#define CN_TOL_CORNER 1e-9

/* Two pieces touching corner to corner have a cone of admissible contact normals; when the
 * cone is wider than this angle (radians) the contact's normal is undetermined and the check
 * decides each end of the cone (below it, one normal stands for all). */
#define CN_TOL_CORNER_CONE 1e-6

#endif
