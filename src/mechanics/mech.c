/* Rigid-body mechanics: bodies, wrench rows and J M^-1 J^T (the paper's eq. 1 and 5: A_nn =
 * W_n^T M^-1 W_n and friends). Generalized coordinates per body: linear velocity of the centre of
 * mass, then angular velocity (one component in 2-D, three in 3-D). */
#include <math.h>
#include <string.h>

#include "mech.h"

/* The inverse of A, computed on A scaled by its largest entry (the determinant of an inertia
 * tensor is its scale cubed: it would overflow or underflow for parts of size 1e20 or 1e-20). */
static int inv3_unit(const double A[3][3], double out[3][3]);
static int inv3(const double A[3][3], double out[3][3]) {
    double s = 0, B[3][3];
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) s = fmax(s, fabs(A[r][c]));
    if (!(s > 0) || !isfinite(s)) return -1;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) B[r][c] = A[r][c] / s;
    if (inv3_unit((const double(*)[3])B, out) != 0) return -1;
    for (int r = 0; r < 3; r++)
        for (int c = 0; c < 3; c++) {
            out[r][c] /= s;
            if (!isfinite(out[r][c])) return -1;
        }
    return 0;
}

static int inv3_unit(const double A[3][3], double out[3][3]) {
    double c00 = A[1][1] * A[2][2] - A[1][2] * A[2][1];
    double c01 = A[1][2] * A[2][0] - A[1][0] * A[2][2];
    double c02 = A[1][0] * A[2][1] - A[1][1] * A[2][0];
    double det = A[0][0] * c00 + A[0][1] * c01 + A[0][2] * c02;
    if (!(fabs(det) > 0) || !isfinite(det)) return -1;
    double id = 1.0 / det;
    out[0][0] = c00 * id;
    out[0][1] = (A[0][2] * A[2][1] - A[0][1] * A[2][2]) * id;
    out[0][2] = (A[0][1] * A[1][2] - A[0][2] * A[1][1]) * id;
    out[1][0] = c01 * id;
    out[1][1] = (A[0][0] * A[2][2] - A[0][2] * A[2][0]) * id;
    out[1][2] = (A[0][2] * A[1][0] - A[0][0] * A[1][2]) * id;
    out[2][0] = c02 * id;
    out[2][1] = (A[0][1] * A[2][0] - A[0][0] * A[2][1]) * id;
    out[2][2] = (A[0][0] * A[1][1] - A[0][1] * A[1][0]) * id;
    return 0;
}

void cn_mech_free(cnMech *m) {
    cn_free(m->body_of_part);
    cn_free(m->part_of_body);
    cn_free(m->com);
    cn_free(m->minv);
    cn_free(m->mass);
    cn_free(m->inertia);
    cn_free(m->fext);
    cn_free(m->a0);
    cn_free(m->radius);
    cn_free(m->ptw);
    cn_free(m->pushed);
    memset(m, 0, sizeof *m);
}

cnStatus cn_mech_build(const cnAssembly *a, const cnContactQuery *q, const cnMotion *motion,
                       cnMech *m, cnDiag *diag) {
    memset(m, 0, sizeof *m);
    m->dim = a->dim;
    m->nd = a->dim == 2 ? 3 : 6;
    int n = a->nparts, nd = m->nd;
    m->body_of_part = cn_malloc(sizeof(int) * (size_t)n);
    m->part_of_body = cn_malloc(sizeof(int) * (size_t)n);
    m->com = cn_calloc((size_t)n, sizeof(double[3]));
    m->minv = cn_calloc((size_t)n * nd * nd, sizeof(double));
    m->mass = cn_calloc((size_t)n + 1, sizeof(double));
    m->inertia = cn_calloc((size_t)n * 9 + 1, sizeof(double));
    m->fext = cn_calloc((size_t)n * nd, sizeof(double));
    m->a0 = cn_calloc((size_t)n * nd, sizeof(double));
    m->radius = cn_calloc((size_t)n, sizeof(double));
    m->ptw = cn_calloc((size_t)n + 1, sizeof(cnTwist));
    m->pushed = cn_calloc((size_t)n + 1, 1);
    if (!m->body_of_part || !m->part_of_body || !m->com || !m->minv || !m->mass || !m->inertia ||
        !m->fext || !m->a0 ||
        !m->radius || !m->ptw || !m->pushed) {
        cn_mech_free(m);
        return cn_diag_oom(diag);
    }
    m->g = cn_norm3(a->gravity);
    m->ref_part = -1;
    double mdir[3] = {0, 0, 0};
    if (motion) {
        cn_copy3(mdir, cn_norm3(motion->direction) > 0 ? motion->direction : motion->twist.v);
        cn_normalize3(mdir);
    }
    cn_copy3(m->mdir, mdir);
    for (int i = 0; i < n; i++) {
        m->body_of_part[i] = -1;
        const cnPart *p = &a->parts[i];
        int role = (motion && motion->role) ? motion->role[i] : CN_ROLE_FREE;
        if (p->fixed && role != CN_ROLE_HELD) role = CN_ROLE_FREE; /* a gripper body may move */
        if (role == CN_ROLE_STILL) continue; /* kinematic, at rest */
        if (role != CN_ROLE_FREE && motion) m->ptw[i] = motion->twist;
        if (role == CN_ROLE_PUSHED && cn_norm3(mdir) == 0) role = CN_ROLE_HELD;
        if (p->fixed || role == CN_ROLE_HELD || !cn_part_present(a, q, i)) continue;
        int b = m->nb++;
        m->body_of_part[i] = b;
        m->part_of_body[b] = i;
        /* mass properties where the part is: com moved, inertia turned (R I R^T) */
        const cnPose *ps = (q && q->pose) ? &q->pose[i] : NULL;
        double I[3][3];
        memcpy(I, p->inertia, sizeof I);
        if (ps) {
            cn_pose_apply(ps, p->com, m->com[b]);
            if (!cn_pose_is_translation(ps)) {
                double R[3][3], RI[3][3];
                cn_pose_matrix(ps, R);
                for (int r = 0; r < 3; r++)
                    for (int c = 0; c < 3; c++) {
                        RI[r][c] = 0;
                        for (int k = 0; k < 3; k++) RI[r][c] += R[r][k] * p->inertia[k][c];
                    }
                for (int r = 0; r < 3; r++)
                    for (int c = 0; c < 3; c++) {
                        I[r][c] = 0;
                        for (int k = 0; k < 3; k++) I[r][c] += RI[r][k] * R[c][k];
                    }
                if (a->dim == 2) I[2][2] = p->inertia[2][2]; /* a turn about z keeps the polar moment */
            }
        } else {
            cn_copy3(m->com[b], p->com);
        }
        double *Mi = m->minv + (size_t)b * nd * nd;
        m->mass[b] = p->mass;
        for (int r = 0; r < 3; r++)
            for (int c = 0; c < 3; c++) m->inertia[(size_t)b * 9 + r * 3 + c] = I[r][c];
        for (int k = 0; k < a->dim; k++) Mi[k * nd + k] = 1.0 / p->mass;
        if (a->dim == 2) {
            Mi[2 * nd + 2] = 1.0 / I[2][2];
        } else {
            double inv[3][3];
            if (inv3((const double(*)[3])I, inv) != 0) {
                cn_mech_free(m);
                return cn_diag_set(diag, CN_ERR_NUMERIC, "", "part '%s' has a singular inertia",
                                   p->name);
            }
            for (int r = 0; r < 3; r++)
                for (int c = 0; c < 3; c++) Mi[(3 + r) * nd + 3 + c] = inv[r][c];
        }
        for (int k = 0; k < a->dim; k++) {
            m->fext[(size_t)b * nd + k] = p->mass * a->gravity[k];
            m->a0[(size_t)b * nd + k] = a->gravity[k];
        }
        if (role == CN_ROLE_PUSHED) {
            /* the gripper takes every force along the motion: project it out */
            m->pushed[b] = 1;
            double gm = cn_dot3(a->gravity, mdir);
            for (int r = 0; r < a->dim; r++) {
                m->a0[(size_t)b * nd + r] -= gm * mdir[r];
                for (int c = 0; c < a->dim; c++)
                    Mi[r * nd + c] = ((r == c) - mdir[r] * mdir[c]) / p->mass;
            }
        }
        double rad = 0;
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nverts; v++) {
                double d[3];
                cn_sub3(p->pieces[s].verts[v], p->com, d);
                rad = fmax(rad, cn_norm3(d));
            }
        m->radius[b] = rad;
        double w = p->mass * m->g;
        if (w > m->wref) m->wref = w, m->ref_part = i;
    }
    if (m->wref <= 0) m->wref = 1.0;
    return CN_OK;
}

static void fill(const cnMech *m, int b, int sign, const double p[3], const double d[3],
                 double c[6], double u[6]) {
    int nd = m->nd;
    double r[3], t[3];
    cn_sub3(p, m->com[b], r);
    memset(c, 0, sizeof(double) * 6);
    if (m->dim == 2) {
        c[0] = sign * d[0];
        c[1] = sign * d[1];
        c[2] = sign * (r[0] * d[1] - r[1] * d[0]);
    } else {
        cn_cross3(r, d, t);
        for (int k = 0; k < 3; k++) c[k] = sign * d[k], c[3 + k] = sign * t[k];
    }
    const double *Mi = m->minv + (size_t)b * nd * nd;
    for (int i = 0; i < nd; i++) {
        double s = 0;
        for (int k = 0; k < nd; k++) s += Mi[i * nd + k] * c[k];
        u[i] = s;
    }
}

void cn_mech_row(const cnMech *m, int part1, int part2, const double p[3], const double d[3],
                 cnJRow *row) {
    memset(row, 0, sizeof *row);
    int b1 = part1 >= 0 ? m->body_of_part[part1] : -1;
    int b2 = part2 >= 0 ? m->body_of_part[part2] : -1;
    row->body[0] = b2;
    row->body[1] = b1;
    if (b2 >= 0) fill(m, b2, +1, p, d, row->c[0], row->u[0]);
    if (b1 >= 0) fill(m, b1, -1, p, d, row->c[1], row->u[1]);
}

void cn_mech_gram(const cnMech *m, const cnJRow *rows, int nr, const cnJRow *cols, int nc,
                  double scale, const double *d, double *A, int ld) {
    int nd = m->nd;
    /* J M^-1 J^T is symmetric: with the same rows on both sides, the upper triangle is mirrored */
    bool same = rows == cols && nr == nc;
    for (int r = 0; r < nr; r++) {
        for (int c = same ? r : 0; c < nc; c++) {
            double s = 0;
            for (int x = 0; x < 2; x++) {
                int b = rows[r].body[x];
                if (b < 0) continue;
                for (int y = 0; y < 2; y++) {
                    if (cols[c].body[y] != b) continue;
                    for (int k = 0; k < nd; k++) s += rows[r].c[x][k] * cols[c].u[y][k];
                }
            }
            s *= scale;
            if (d) s *= d[r] * d[c];
            A[(size_t)r * ld + c] = s;
            if (same) A[(size_t)c * ld + r] = s;
        }
    }
}

void cn_mech_response(const cnMech *m, const cnJRow *rows, int nr, const double *f, double *acc) {
    int nd = m->nd;
    memcpy(acc, m->a0, sizeof(double) * (size_t)m->nb * nd);
    for (int r = 0; r < nr; r++) {
        if (f[r] == 0) continue;
        for (int x = 0; x < 2; x++) {
            int b = rows[r].body[x];
            if (b < 0) continue;
            for (int k = 0; k < nd; k++) acc[(size_t)b * nd + k] += rows[r].u[x][k] * f[r];
        }
    }
}

double cn_mech_relative(const cnMech *m, const cnJRow *row, const double *acc) {
    double s = 0;
    for (int x = 0; x < 2; x++) {
        int b = row->body[x];
        if (b < 0) continue;
        for (int k = 0; k < m->nd; k++) s += row->c[x][k] * acc[(size_t)b * m->nd + k];
    }
    return s;
}

bool cn_mech_moves(const cnMech *m, int b, const double *acc, double tol) {
    return cn_mech_motion_size(m, b, acc) > tol * m->g;
}

double cn_mech_motion_size(const cnMech *m, int b, const double *acc) {
    int nd = m->nd, dim = m->dim;
    const double *v = acc + (size_t)b * nd;
    double lin = 0, ang = 0;
    for (int k = 0; k < dim; k++) lin += v[k] * v[k];
    for (int k = dim; k < nd; k++) ang += v[k] * v[k];
    return fmax(sqrt(lin), sqrt(ang) * m->radius[b]);
}

double cn_mech_nominal(const cnMech *m, int part1, int part2, const double x[3], const double d[3]) {
    double v[3] = {0, 0, 0}, vp[3];
    if (part2 >= 0) cn_twist_at(&m->ptw[part2], x, vp), cn_add3(v, vp, v);
    if (part1 >= 0) cn_twist_at(&m->ptw[part1], x, vp), cn_sub3(v, vp, v);
    return cn_dot3(v, d);
}

double cn_mech_kinetic(const cnMech *m, const double *a, double *ma) {
    int nd = m->nd, dim = m->dim;
    double e = 0;
    for (int b = 0; b < m->nb; b++) {
        const double *ab = a + (size_t)b * nd;
        double mb[6];
        for (int k = 0; k < dim; k++) mb[k] = m->mass[b] * ab[k];
        const double *I = m->inertia + (size_t)b * 9;
        if (dim == 2) mb[2] = I[8] * ab[2];
        else
            for (int i = 0; i < 3; i++) {
                mb[3 + i] = 0;
                for (int j = 0; j < 3; j++) mb[3 + i] += I[i * 3 + j] * ab[3 + j];
            }
        for (int k = 0; k < nd; k++) {
            e += ab[k] * mb[k];
            if (ma) ma[(size_t)b * nd + k] = mb[k];
        }
    }
    return e;
}
