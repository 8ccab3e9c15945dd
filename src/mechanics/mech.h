/* Rigid-body mechanics of an assembly at rest: bodies, contact Jacobian rows, and the products
 * J M^-1 J^T that the complementarity problems are made of. Private to the library. */
#ifndef CAIRN_MECH_H
#define CAIRN_MECH_H

#include "pieces.h"
#include "cairn/stability.h"

/* One row of the contact Jacobian: a unit force direction d at a point, acting +d on body2 and
 * -d on body1. Each row touches at most two free bodies. */
typedef struct cnJRow {
    int body[2];     /* free-body indices, -1 when fixed / world */
    double c[2][6];  /* generalized force per unit magnitude on each body */
    double u[2][6];  /* M^-1 c: generalized acceleration per unit magnitude */
} cnJRow;

typedef struct cnMech {
    int dim, nd;        /* nd: 3 (2-D) or 6 (3-D) dofs per body */
    int nb;             /* free bodies present */
    int *body_of_part;  /* -1 for fixed or absent parts */
    int *part_of_body;
    double (*com)[3];   /* per body, posed */
    double *minv;       /* per body nd x nd inverse mass matrix */
    double *mass;       /* per body: its mass */
    double *inertia;    /* per body 9: its inertia about the centre of mass, row-major 3 x 3
                           (2-D: only [8], about z, is used) */
    double *fext;       /* per body nd generalized gravity force */
    double *a0;         /* per body nd: M^-1 fext (free-fall acceleration) */
    double *radius;     /* per body: max distance of its vertices from its centre of mass */
    unsigned char *pushed; /* per body: 1 when pushed (driven along mdir only) */
    double mdir[3];     /* unit direction of the motion (zero when nothing moves) */
    cnTwist *ptw;       /* per part: nominal velocity (held, pushed and carried parts move; zero
                           for the others) */
    double g;           /* |gravity| */
    double wref;        /* reference weight */
    int ref_part;
} cnMech;

/* Bodies of the parts present. Fixed and held parts are not bodies. A pushed part's inverse
 * mass loses the direction of its motion (the gripper supplies any force along it), so its
 * free-fall acceleration a0 is gravity projected off that direction. */
cnStatus cn_mech_build(const cnAssembly *a, const cnContactQuery *q, const cnMotion *motion,
                       cnMech *m, cnDiag *diag);

/* Nominal relative velocity of part2 with respect to part1 at point x along d. */
double cn_mech_nominal(const cnMech *m, int part1, int part2, const double x[3], const double d[3]);
void cn_mech_free(cnMech *m);

/* Does body b leave its nominal motion? acc: its generalized acceleration (friction: the average
 * over the step, (v1 - v0) / dt); tol: fraction of g (rotations times the body's radius). */
bool cn_mech_moves(const cnMech *m, int b, const double *acc, double tol);
/* The size of body b's motion that cn_mech_moves measures: the larger of its linear acceleration
 * and its angular one times its radius. */
double cn_mech_motion_size(const cnMech *m, int b, const double *acc);

/* Fill a Jacobian row for direction d at point p between parts (part1, part2). */
void cn_mech_row(const cnMech *m, int part1, int part2, const double p[3], const double d[3],
                 cnJRow *row);

/* Dense A = J_rows M^-1 J_cols^T (row-major nr x nc) times `scale`, each entry (r, c) also times
 * d[r] d[c] unless d is NULL, into A (leading dimension ld). With the same rows on both sides
 * (rows == cols, nr == nc: the only case d may be given, nr entries), each pair's entry is
 * computed once and mirrored. */
void cn_mech_gram(const cnMech *m, const cnJRow *rows, int nr, const cnJRow *cols, int nc,
                  double scale, const double *d, double *A, int ld);

/* Generalized acceleration of every body: a = M^-1 (fext + sum_r c_r f_r), nb*nd entries. */
void cn_mech_response(const cnMech *m, const cnJRow *rows, int nr, const double *f, double *acc);

/* Relative motion along direction d at point p of body2 w.r.t. body1, given per-body generalized
 * accelerations (or velocities). */
double cn_mech_relative(const cnMech *m, const cnJRow *row, const double *acc);

/* a^T M a for generalized accelerations (or velocities) a of every body (nb*nd entries); ma
 * (NULL: not wanted) receives M a. */
double cn_mech_kinetic(const cnMech *m, const double *a, double *ma);
#endif
