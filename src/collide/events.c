/* Contact events along a translation: the distances at which the contact topology between
 * translating convex pieces and static ones can change (a vertex meets a face or an edge, an
 * edge crosses an edge, a vertex passes a vertex on the line it slides along). Between two
 * events every touching pair touches by the same features, so a simulation that samples the
 * events (and just before and after them) sees every contact begin and end, whatever its
 * sampling interval (issue: an instability that starts and ends between two samples). Exact for
 * translations of convex pieces up to rounding; turns are events_turn.c's. */
#include <math.h>
#include <stdlib.h>

#include "collide.h"

typedef struct {
    double *ev;
    int n, cap;
    int dropped;
    double L, slack;
} Events;

static void add(Events *E, double s) {
    if (!(s > -E->slack && s < E->L + E->slack)) return;
    if (E->n == E->cap) {
        E->dropped++;
        return;
    }
    E->ev[E->n++] = fmin(fmax(s, 0.0), E->L);
}

/* Vertex x moving along u (x + s u) meets the segment [b1, b2]: 2-D and 3-D (the nearest point
 * of the two lines, accepted when they meet within tol). */
static void vertex_segment(Events *E, const double x[3], const double u[3], const double b1[3],
                           const double b2[3], double tol) {
    double e[3], w[3];
    cn_sub3(b2, b1, e);
    cn_sub3(x, b1, w);
    /* x + s u = b1 + t e: least squares in (s, t) */
    double uu = cn_dot3(u, u), ee = cn_dot3(e, e), ue = cn_dot3(u, e);
    double det = uu * ee - ue * ue;
    if (!(det > 1e-12 * uu * ee)) return; /* parallel: vertex passes handle it */
    double uw = cn_dot3(u, w), ew = cn_dot3(e, w);
    /* minimise |w + s u - t e|^2 */
    double s = (ue * ew - ee * uw) / det, t = (uu * ew - ue * uw) / det;
    if (t < -1e-9 || t > 1 + 1e-9) return;
    double r[3];
    for (int k = 0; k < 3; k++) r[k] = w[k] + s * u[k] - t * e[k];
    if (cn_norm3(r) <= tol) add(E, s);
}

/* Vertex x moving along u meets the face f of piece Q (3-D). */
static void vertex_face(Events *E, const double x[3], const double u[3], const cnPiece *Q,
                        const cnFace *f, double tol) {
    double nu = cn_dot3(f->normal, u);
    if (fabs(nu) < 1e-12) return;
    double s = (f->offset - cn_dot3(f->normal, x)) / nu, p[3];
    for (int k = 0; k < 3; k++) p[k] = x[k] + s * u[k];
    /* inside the face loop: on the inner side of every edge (in the face's plane) */
    for (int i = 0; i < f->nverts; i++) {
        const double *a = Q->verts[f->verts[i]], *b = Q->verts[f->verts[(i + 1) % f->nverts]];
        double e[3], w[3], c[3];
        cn_sub3(b, a, e);
        cn_sub3(p, a, w);
        cn_cross3(e, w, c);
        double el = cn_norm3(e);
        if (el > 0 && cn_dot3(c, f->normal) < -tol * el) return;
    }
    add(E, s);
}

/* Vertex x moving along u passes vertex y on its line (within tol of it). */
static void vertex_vertex(Events *E, const double x[3], const double u[3], const double y[3],
                          double tol) {
    double w[3];
    cn_sub3(y, x, w);
    double uu = cn_dot3(u, u), s = cn_dot3(w, u) / uu, r[3];
    for (int k = 0; k < 3; k++) r[k] = w[k] - s * u[k];
    if (cn_norm3(r) <= tol) add(E, s);
}

/* Edges of a piece: 2-D polygons' consecutive vertices, 3-D the unique edge list. */
static int nedges(const cnPiece *P, int dim) { return dim == 2 ? P->nverts : P->nedges; }
static void edge(const cnPiece *P, int dim, int i, int *a, int *b) {
    if (dim == 2) *a = i, *b = (i + 1) % P->nverts;
    else *a = P->edges[i][0], *b = P->edges[i][1];
}

/* Events of moving piece P (vertices moved by pose) against static piece Q, for the motion s u
 * (unit u) over [0, L]. */
static void pair_events(Events *E, const cnPiece *P, const cnPose *pose, const cnPiece *Q, int dim,
                        const double u[3], double tol, double *pv) {
    double mu[3] = {-u[0], -u[1], -u[2]};
    for (int i = 0; i < P->nverts; i++) cn_pose_apply(pose, P->verts[i], pv + 3 * i);
    int np = nedges(P, dim), nq = nedges(Q, dim);
    for (int i = 0; i < P->nverts; i++) {
        const double *x = pv + 3 * i;
        for (int j = 0; j < Q->nverts; j++) vertex_vertex(E, x, u, Q->verts[j], tol);
        for (int j = 0; j < nq; j++) {
            int a, b;
            edge(Q, dim, j, &a, &b);
            vertex_segment(E, x, u, Q->verts[a], Q->verts[b], tol);
        }
        if (dim == 3)
            for (int f = 0; f < Q->nfaces; f++) vertex_face(E, x, u, Q, &Q->faces[f], tol);
    }
    /* Q's vertices against P's edges and faces: Q moves by -s u relative to P */
    for (int j = 0; j < Q->nverts; j++) {
        const double *y = Q->verts[j];
        for (int i = 0; i < np; i++) {
            int a, b;
            edge(P, dim, i, &a, &b);
            vertex_segment(E, y, mu, pv + 3 * a, pv + 3 * b, tol);
        }
        if (dim == 3) {
            /* P's faces, posed: normals turned, loops through the posed vertices */
            cnPiece posed = *P;
            posed.verts = (double(*)[3])pv;
            for (int f = 0; f < P->nfaces; f++) {
                cnFace g = P->faces[f];
                cn_pose_rotate(pose, P->faces[f].normal, g.normal);
                g.offset = cn_dot3(g.normal, pv + 3 * g.verts[0]);
                vertex_face(E, y, mu, &posed, &g, tol);
            }
        }
    }
    /* 3-D: an edge of P crossing an edge of Q (general position: a 3 x 3 solve) */
    if (dim == 3)
        for (int i = 0; i < np; i++) {
            int a1, a2;
            edge(P, dim, i, &a1, &a2);
            const double *p1 = pv + 3 * a1, *p2 = pv + 3 * a2;
            double e1[3];
            cn_sub3(p2, p1, e1);
            for (int j = 0; j < nq; j++) {
                int b1, b2;
                edge(Q, dim, j, &b1, &b2);
                double e2[3], w[3], c[3];
                cn_sub3(Q->verts[b2], Q->verts[b1], e2);
                cn_sub3(Q->verts[b1], p1, w);
                /* p1 + s u + t1 e1 = b1 + t2 e2: s u + t1 e1 - t2 e2 = w */
                cn_cross3(e1, e2, c);
                double det = cn_dot3(u, c); /* det [u, e1, -e2] = -u.(e1 x e2) */
                double scale = cn_norm3(e1) * cn_norm3(e2);
                if (!(fabs(det) > 1e-9 * scale)) continue; /* coplanar: vertex events cover it */
                /* Cramer on the columns [u, e1, -e2]: det = -u.c; s = w.c / u.c, t1 =
                   u.(w x e2) / u.c, t2 = e1.(u x w) / u.c */
                double c1[3], c2[3];
                cn_cross3(w, e2, c1);
                cn_cross3(u, w, c2);
                double s = cn_dot3(w, c) / det;
                double t1 = cn_dot3(u, c1) / det, t2 = cn_dot3(e1, c2) / det;
                if (t1 < -1e-9 || t1 > 1 + 1e-9 || t2 < -1e-9 || t2 > 1 + 1e-9) continue;
                add(E, s);
            }
        }
}

static int cmp_double(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

int cn_contact_events(const cnAssembly *a, const unsigned char *moving, const unsigned char *still,
                      const cnPose *pose, const double u[3], double L, double *ev, int cap,
                      int *dropped) {
    int dim = a->dim;
    double tol = a->contact_tol;
    Events E = {ev, 0, cap, 0, L, tol};
    *dropped = 0;
    if (!(L > 0)) return 0;
    int maxv = 0;
    for (int i = 0; i < a->nparts; i++)
        if (moving[i])
            for (int k = 0; k < a->parts[i].npieces; k++) maxv = a->parts[i].pieces[k].nverts > maxv ? a->parts[i].pieces[k].nverts : maxv;
    double *pv = cn_malloc(sizeof(double) * 3 * (size_t)(maxv + 1));
    if (!pv) return -1;
    for (int i = 0; i < a->nparts; i++) {
        if (!moving[i]) continue;
        const cnPart *P = &a->parts[i];
        /* the swept box of the moving part, for the broad phase */
        double lo[3], hi[3], plo[3] = {INFINITY, INFINITY, INFINITY}, phi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int c = 0; c < 8; c++) { /* the corners of its box, posed */
            double x[3] = {c & 1 ? P->hi[0] : P->lo[0], c & 2 ? P->hi[1] : P->lo[1], c & 4 ? P->hi[2] : P->lo[2]}, y[3];
            cn_pose_apply(pose, x, y);
            for (int k = 0; k < 3; k++) plo[k] = fmin(plo[k], y[k]), phi[k] = fmax(phi[k], y[k]);
        }
        for (int k = 0; k < 3; k++) {
            lo[k] = fmin(plo[k], plo[k] + L * u[k]) - 2 * tol;
            hi[k] = fmax(phi[k], phi[k] + L * u[k]) + 2 * tol;
        }
        for (int j = 0; j < a->nparts; j++) {
            if (!still[j]) continue;
            const cnPart *Q = &a->parts[j];
            bool near = true;
            for (int k = 0; k < dim; k++) near = near && Q->lo[k] <= hi[k] && Q->hi[k] >= lo[k];
            if (!near) continue;
            for (int p = 0; p < P->npieces; p++)
                for (int q = 0; q < Q->npieces; q++)
                    pair_events(&E, &P->pieces[p], pose, &Q->pieces[q], dim, u, tol, pv);
        }
    }
    cn_free(pv);
    qsort(ev, (size_t)E.n, sizeof(double), cmp_double);
    /* distinct within rounding of the path */
    int m = 0;
    for (int i = 0; i < E.n; i++)
        if (m == 0 || ev[i] - ev[m - 1] > 1e-12 * L) ev[m++] = ev[i];
    *dropped = E.dropped;
    return m;
}
