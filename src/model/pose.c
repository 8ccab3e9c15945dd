/* Poses: where a rigid part is (a unit quaternion and a translation). Rotations are kept as
 * quaternions so that composing many small turns along a path stays a rotation; a pose that is
 * exactly a translation maps points by addition alone, so translated parts are placed to the
 * last bit as they were before poses existed. */
#include <math.h>

#include "pieces.h"

cnPose cn_pose_identity(void) {
    cnPose p = {{1, 0, 0, 0}, {0, 0, 0}};
    return p;
}

cnPose cn_pose_translation(const double t[3]) {
    cnPose p = cn_pose_identity();
    cn_copy3(p.t, t);
    return p;
}

bool cn_pose_is_translation(const cnPose *p) {
    return p->q[1] == 0 && p->q[2] == 0 && p->q[3] == 0;
}

void cn_pose_matrix(const cnPose *p, double R[3][3]) {
    double w = p->q[0], x = p->q[1], y = p->q[2], z = p->q[3];
    R[0][0] = 1 - 2 * (y * y + z * z);
    R[0][1] = 2 * (x * y - w * z);
    R[0][2] = 2 * (x * z + w * y);
    R[1][0] = 2 * (x * y + w * z);
    R[1][1] = 1 - 2 * (x * x + z * z);
    R[1][2] = 2 * (y * z - w * x);
    R[2][0] = 2 * (x * z - w * y);
    R[2][1] = 2 * (y * z + w * x);
    R[2][2] = 1 - 2 * (x * x + y * y);
}

void cn_pose_rotate(const cnPose *p, const double v[3], double out[3]) {
    if (cn_pose_is_translation(p)) {
        cn_copy3(out, v);
        return;
    }
    double R[3][3], r[3];
    cn_pose_matrix(p, R);
    for (int i = 0; i < 3; i++) r[i] = R[i][0] * v[0] + R[i][1] * v[1] + R[i][2] * v[2];
    cn_copy3(out, r);
}

void cn_pose_apply(const cnPose *p, const double x[3], double out[3]) {
    double r[3];
    cn_pose_rotate(p, x, r);
    cn_add3(r, p->t, out);
}

cnPose cn_pose_rotation(const double axis[3], double angle, const double about[3]) {
    cnPose p = cn_pose_identity();
    double u[3];
    cn_copy3(u, axis);
    if (!(cn_normalize3(u) > 0) || angle == 0) return p;
    double s = sin(0.5 * angle);
    p.q[0] = cos(0.5 * angle);
    for (int k = 0; k < 3; k++) p.q[k + 1] = s * u[k];
    /* x -> R (x - c) + c = R x + (c - R c) */
    double rc[3];
    cn_pose_rotate(&p, about, rc);
    cn_sub3(about, rc, p.t);
    return p;
}

cnPose cn_pose_then(const cnPose *first, const cnPose *then) {
    /* then(first(x)) = R2 (R1 x + t1) + t2: q = q2 q1, t = R2 t1 + t2 */
    const double *a = then->q, *b = first->q;
    cnPose p;
    p.q[0] = a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3];
    p.q[1] = a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2];
    p.q[2] = a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1];
    p.q[3] = a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0];
    if (cn_pose_is_translation(first) && cn_pose_is_translation(then)) {
        p.q[0] = 1; /* exactly: no drift from 1 * 1 */
    } else {
        double n = sqrt(p.q[0] * p.q[0] + p.q[1] * p.q[1] + p.q[2] * p.q[2] + p.q[3] * p.q[3]);
        for (int k = 0; k < 4; k++) p.q[k] /= n;
        if (p.q[0] < 0) /* the same rotation, w >= 0 */
            for (int k = 0; k < 4; k++) p.q[k] = -p.q[k];
    }
    cn_pose_apply(then, first->t, p.t);
    return p;
}

double cn_pose_angle(const cnPose *p, int dim) {
    double v = sqrt(p->q[1] * p->q[1] + p->q[2] * p->q[2] + p->q[3] * p->q[3]);
    double ang = 2 * atan2(v, fabs(p->q[0]));
    if (dim == 2) {
        /* about +z or -z: counter-clockwise positive, in (-pi, pi] */
        double s = p->q[3] * (p->q[0] < 0 ? -1 : 1);
        return s < 0 ? -ang : ang;
    }
    return ang;
}

void cn_twist_at(const cnTwist *t, const double x[3], double out[3]) {
    double r[3], wr[3];
    cn_sub3(x, t->about, r);
    cn_cross3(t->w, r, wr);
    cn_add3(t->v, wr, out);
}

bool cn_path_turns(const cnSegment *seg, int nseg) {
    for (int i = 0; i < nseg; i++)
        if (seg[i].kind == CN_SEGMENT_TURN) return true;
    return false;
}

cnPose cn_segment_pose(const cnSegment *s, double f) {
    if (s->kind == CN_SEGMENT_TURN) return cn_pose_rotation(s->axis, s->angle * f, s->about);
    double t[3];
    for (int k = 0; k < 3; k++) t[k] = s->move[k] * f;
    return cn_pose_translation(t);
}

double cn_path_length(const cnAssembly *a, const int *parts, int n, const cnSegment *seg, int nseg,
                      double *lengths) {
    double total = 0;
    cnPose at = cn_pose_identity(); /* where the parts are when the segment starts */
    for (int i = 0; i < nseg; i++) {
        const cnSegment *s = &seg[i];
        double L = 0;
        if (s->kind == CN_SEGMENT_MOVE) {
            L = cn_norm3(s->move);
        } else {
            double r = 0;
            for (int j = 0; j < n; j++) {
                const cnPart *p = &a->parts[parts[j]];
                for (int q = 0; q < p->npieces; q++)
                    for (int v = 0; v < p->pieces[q].nverts; v++) {
                        double x[3], d[3], c[3];
                        cn_pose_apply(&at, p->pieces[q].verts[v], x);
                        cn_sub3(x, s->about, d);
                        cn_cross3(s->axis, d, c);
                        r = fmax(r, cn_norm3(c));
                    }
            }
            L = fabs(s->angle) * r;
        }
        if (lengths) lengths[i] = L;
        total += L;
        cnPose step = cn_segment_pose(s, 1.0);
        at = cn_pose_then(&at, &step);
    }
    return total;
}
