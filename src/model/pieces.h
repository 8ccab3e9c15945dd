/* model: the loaded assembly's parts and pieces (presence, geometry, convex hulls, mass
 * properties). Private; includes only core. */
#ifndef CAIRN_PIECES_H
#define CAIRN_PIECES_H

#include "core.h"
#include "cairn/contact.h"
#include "cairn/model.h"

/* ---- the assembly (assembly.c) ---- */
/* Is part i in the scene? With an absent mask, as it says; without, every part but the plan's
 * gripper bodies. */
int cn_part_present(const cnAssembly *a, const cnContactQuery *q, int i);
/* Does plan step `step` move `part`? */
int cn_plan_moves(const cnAssembly *a, int step, int part);
/* Where fixel f (its normal unit) sits on its part: the signed distance from the part (its
 * nearest piece) of its point (*at), and of the point moved a thousandth of the part's size along
 * its normal (*in) and against it (*out); *tol is the distance within which a point is on the
 * surface. A fixel touches the part where |at| <= tol and pushes into it where in <= tol < out. */
void cn_fixel_probe(const cnAssembly *a, const cnFixel *f, double *at, double *in, double *out, double *tol);

/* ---- geometry of pieces (geom.c) ---- */
/* Bounding boxes, 2-D polygon orientation helpers. */
void cn_piece_bounds(cnPiece *p, int dim);
void cn_piece_free(cnPiece *p);
/* Move a piece by pose q (its vertices, face planes and bounds); in 2-D q turns about z. */
void cn_piece_transform(cnPiece *p, int dim, const cnPose *q);
/* Signed distance of point x from the convex piece (positive outside, negative inside,
 * by the max over supporting planes / edge lines). */
double cn_piece_plane_distance(const cnPiece *p, int dim, const double x[3]);

/* ---- simple polygons split into convex pieces (split2.c) ---- */
/* The turn at b on the way a -> b -> c: 1 left, -1 right, 0 none (straight on, or straight back)
 * within CN_TOL_CORNER. */
int cn_turn2(const double *a, const double *b, const double *c);
/* Is the closed polygon p (n points) simple: do no two non-adjacent edges come within tol? 1
 * yes; 0 no, with the first two edges that meet in *e1, *e2 (edge i runs from point i to i+1). */
int cn_polygon_simple(const double (*p)[3], int n, double tol, int *e1, int *e2);
/* Split a simple polygon (counter-clockwise, no coincident neighbours) into convex pieces, each
 * a counter-clockwise list of indices into p; every point of p is in some piece. tol: a length
 * (points this near a line are on it). 0 done (*npieces lists, free each and both arrays with
 * cn_free), 1 it could not be split (not simple, numerically), -1 out of memory. */
int cn_polygon_split(const double (*p)[3], int n, double tol, int *npieces, int **lens, int ***pieces);

/* ---- 3-D convex hull (hull3.c): qhull, then exact face loops ---- */
/* Build a convex piece from a point cloud. Returns CN_ERR_INPUT with a message (no `where`)
 * when the points are degenerate (coplanar, too few). */
cnStatus cn_hull3_build(const double (*pts)[3], int n, cnPiece *out, cnDiag *diag);

/* ---- mass properties (mass.c) ---- */
/* Size (area/volume), first moment and second moment (integral of y y^T, y = x - ref) about
 * ref (NULL: the origin). */
void cn_mass_piece(const cnPiece *p, int dim, const double ref[3], double *size, double first[3],
                   double second[3][3]);
/* Fill part->size, mass, com, inertia from pieces and density (or mass when given > 0). */
void cn_mass_part(cnPart *part, int dim, double density, double given_mass);

#endif
