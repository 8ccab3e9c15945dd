/* Exact mass properties of convex pieces and composite parts.
 *
 * 2-D: triangle fan from a reference point; 3-D: tetrahedra from a reference point to a fan of
 * each face. For a tetrahedron (0, a, b, c) of volume V the second moment is
 * integral x x^T dV = V/20 (a a^T + b b^T + c c^T + s s^T), s = a + b + c
 * (Tonon, "Explicit exact formulas for the 3-D tetrahedron inertia tensor", J. Math. Stat. 2004);
 * the 2-D triangle analogue is A/12 (a a^T + b b^T + s s^T)... written out below per entry. */
#include <math.h>
#include <string.h>

#include "pieces.h"

static void add_outer(double C[3][3], const double a[3], const double b[3], double s) {
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) C[i][j] += s * a[i] * b[j];
}

void cn_mass_piece(const cnPiece *p, int dim, const double ref[3], double *size, double first[3],
                   double second[3][3]) {
    /* Work relative to r (mean of vertices) for accuracy, then shift to the origin. */
    double r[3] = {0, 0, 0};
    for (int i = 0; i < p->nverts; i++) cn_add3(r, p->verts[i], r);
    cn_scale3(r, 1.0 / p->nverts);
    double S = 0, F[3] = {0, 0, 0}, C[3][3];
    memset(C, 0, sizeof C);
    if (dim == 2) {
        for (int i = 0; i < p->nverts; i++) {
            double a[3], b[3];
            cn_sub3(p->verts[i], r, a);
            cn_sub3(p->verts[(i + 1) % p->nverts], r, b);
            double cr = a[0] * b[1] - a[1] * b[0];
            double A = cr / 2;
            S += A;
            for (int k = 0; k < 2; k++) F[k] += A * (a[k] + b[k]) / 3;
            /* integral of x_i x_j over triangle (0, a, b) = A/6 (a_i a_j + b_i b_j) + A/12 (a_i b_j
             * + b_i a_j) */
            add_outer(C, a, a, A / 6);
            add_outer(C, b, b, A / 6);
            add_outer(C, a, b, A / 12);
            add_outer(C, b, a, A / 12);
        }
    } else {
        for (int f = 0; f < p->nfaces; f++) {
            const cnFace *fc = &p->faces[f];
            double a[3];
            cn_sub3(p->verts[fc->verts[0]], r, a);
            for (int i = 1; i + 1 < fc->nverts; i++) {
                double b[3], c[3], bc[3];
                cn_sub3(p->verts[fc->verts[i]], r, b);
                cn_sub3(p->verts[fc->verts[i + 1]], r, c);
                cn_cross3(b, c, bc);
                double V = cn_dot3(a, bc) / 6;
                S += V;
                double s[3] = {a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
                for (int k = 0; k < 3; k++) F[k] += V * s[k] / 4;
                add_outer(C, a, a, V / 20);
                add_outer(C, b, b, V / 20);
                add_outer(C, c, c, V / 20);
                add_outer(C, s, s, V / 20);
            }
        }
    }
    /* Shift to ref: x - ref = (x - r) + d, d = r - ref (small when ref is near the piece) */
    double d[3] = {0, 0, 0};
    for (int k = 0; k < 3; k++) d[k] = r[k] - (ref ? ref[k] : 0);
    *size = S;
    for (int k = 0; k < 3; k++) first[k] = F[k] + S * d[k];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            second[i][j] = C[i][j] + d[i] * F[j] + F[i] * d[j] + S * d[i] * d[j];
}

void cn_mass_part(cnPart *part, int dim, double density, double given_mass) {
    double S = 0, F[3] = {0, 0, 0}, C[3][3];
    memset(C, 0, sizeof C);
    for (int k = 0; k < 3; k++) part->lo[k] = INFINITY, part->hi[k] = -INFINITY;
    for (int i = 0; i < part->npieces; i++)
        for (int k = 0; k < 3; k++) {
            part->lo[k] = fmin(part->lo[k], part->pieces[i].lo[k]);
            part->hi[k] = fmax(part->hi[k], part->pieces[i].hi[k]);
        }
    /* Moments about the middle of the part's box, not the origin: far from the origin, moments
     * about it would lose the part's own digits (its inertia is a small difference of huge
     * terms) */
    double ref[3];
    for (int k = 0; k < 3; k++)
        ref[k] = part->npieces > 0 ? 0.5 * (part->lo[k] + part->hi[k]) : 0;
    for (int i = 0; i < part->npieces; i++) {
        double s, f[3], c[3][3];
        cn_mass_piece(&part->pieces[i], dim, ref, &s, f, c);
        S += s;
        for (int k = 0; k < 3; k++) F[k] += f[k];
        for (int a = 0; a < 3; a++)
            for (int b = 0; b < 3; b++) C[a][b] += c[a][b];
    }
    part->size = S;
    part->density = given_mass > 0 ? given_mass / S : density;
    part->mass = part->density * S;
    double g[3]; /* the centre of mass relative to ref */
    for (int k = 0; k < 3; k++) g[k] = S > 0 ? F[k] / S : 0;
    for (int k = 0; k < 3; k++) part->com[k] = ref[k] + g[k];
    /* Second moment about the centre of mass, then the inertia tensor tr(C) I - C. */
    double Cc[3][3];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++)
            Cc[a][b] = part->density * (C[a][b] - S * g[a] * g[b]);
    double tr = Cc[0][0] + Cc[1][1] + Cc[2][2];
    for (int a = 0; a < 3; a++)
        for (int b = 0; b < 3; b++) part->inertia[a][b] = (a == b ? tr : 0) - Cc[a][b];
}
