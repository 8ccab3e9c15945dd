/* The non-directional blocking graph for translations to infinity (paper sec. V, after Wilson and
 * Latombe, "Geometric reasoning about mechanical assembly", Artif. Intell. 71, 1994, sec. 4).
 *
 * Cones. Convex piece p translated by t d overlaps convex piece q iff t d lies in the interior of
 * the Minkowski difference M = q - p = conv{q_v - p_u}. The ray {t d : t > 0} meets int M iff d
 * lies in the interior of the cone M generates from the origin (pieces apart), or, when the
 * origin lies on M's boundary within the contact tolerance (pieces touching), in the interior of
 * M's tangent cone there: once a ray enters int M it stays inside up to M's far side, so a ray
 * along the boundary of these cones only touches (slides, grazes). Both are intersections of open
 * half-spaces n . d < 0: in 3-D the faces through the origin of the hull of M and the origin
 * (apart) or of M's faces within the tolerance of the origin (touching), from qhull; in 2-D the
 * two ends of the open arc of blocking.c (one line when the arc is a half-plane).
 *
 * Arrangement. The planes n . d = 0 cut the sphere of directions in great circles (2-D: the
 * circle in points). A cell is a maximal set of directions with the same sign vector over the
 * circles: open regions, open arcs of circles and single directions (vertices, where two or more
 * circles meet: the directions +-(n_a x n_b)). Whether a cone holds a direction depends only on
 * the signs, so each cell has one directional blocking graph. In 3-D every region and every arc
 * meets a vertex (any two great circles cross), so walking around each vertex finds every cell:
 * around vertex v the circles through it leave in 2 m tangent directions (the arcs) with m... 2 m
 * sectors between them (the regions). A vertex where several circles meet is found once, from its
 * two lowest circles; cells are deduplicated by sign vector. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "blocking.h"
#include "collide.h"
#include "ndbg.h"

/* The apex of the hull of M and the origin: faces within this fraction of the hull's size from the
 * origin pass through it (the origin is one of the hull's points, moved by qhull's centring). */
#define NDBG_APEX_TOL 1e-9

void cn_free_ints(int *p) { cn_free(p); }

/* ---- cones ---- */

typedef struct {
    double *ang;
    int capang;
    double (*pts)[3];
    int cappts;
    cnManifold m;
} Scratch;

static int push_nrm(cnNdbgCones *C, double x, double y, double z) {
    if (C->nnrm == C->capnrm) {
        int nc = C->capnrm ? 2 * C->capnrm : 64;
        double(*nn)[3] = cn_realloc(C->nrm, sizeof(double[3]) * (size_t)nc);
        if (!nn) return -1;
        C->nrm = nn, C->capnrm = nc;
    }
    double *n = C->nrm[C->nnrm];
    n[0] = x, n[1] = y, n[2] = z;
    if (cn_normalize3(n) <= 0) return 0;
    C->nnrm++;
    return 0;
}

static int push_cone(cnNdbgCones *C, int i, int j) {
    if (C->ncone == C->capcone) {
        int nc = C->capcone ? 2 * C->capcone : 32;
        cnNdbgCone *nn = cn_realloc(C->cone, sizeof(cnNdbgCone) * (size_t)nc);
        if (!nn) return -1;
        C->cone = nn, C->capcone = nc;
    }
    C->cone[C->ncone++] = (cnNdbgCone){.part = i, .other = j, .first = C->nnrm, .n = 0};
    return 0;
}

/* The blocked cone of piece P (moving) against piece Q, appended to C. */
static cnStatus cone_pieces(const cnAssembly *a, const cnPiece *P, const cnPiece *Q, int i, int j,
                            cnNdbgCones *C, Scratch *sc, cnDiag *diag) {
    double tol = a->contact_tol, zero[3] = {0, 0, 0};
    if (a->dim == 2) {
        double lo, len;
        int r = cn_blocked_arc2(P, Q, tol, &sc->ang, &sc->capang, &lo, &len);
        if (r < 0) goto oom;
        if (r == 0) return CN_OK;
        double hi = lo + len;
        /* strictly counter-clockwise of lo and clockwise of hi */
        if (push_cone(C, i, j) < 0 || push_nrm(C, sin(lo), -cos(lo), 0) < 0 ||
            push_nrm(C, -sin(hi), cos(hi), 0) < 0)
            goto oom;
        C->cone[C->ncone - 1].n = C->nnrm - C->cone[C->ncone - 1].first;
        return CN_OK;
    }
    int np = P->nverts * Q->nverts;
    if (np + 1 > sc->cappts) {
        double(*nw)[3] = cn_realloc(sc->pts, sizeof(double[3]) * (size_t)(np + 1));
        if (!nw) goto oom;
        sc->pts = nw, sc->cappts = np + 1;
    }
    int k = 0;
    for (int u = 0; u < Q->nverts; u++)
        for (int v = 0; v < P->nverts; v++) cn_sub3(Q->verts[u], P->verts[v], sc->pts[k++]);
    int r = cn_contact3_pieces(P, zero, Q, zero, zero, tol, &sc->m);
    if (r < 0) goto oom;
    bool touching = r != CN_PAIR_APART;
    if (!touching) cn_copy3(sc->pts[k++], zero);
    cnPiece H;
    cnStatus st = cn_hull3_build((const double(*)[3])sc->pts, k, &H, diag);
    if (st) return st;
    double ext[3];
    cn_sub3(H.hi, H.lo, ext);
    double thr = touching ? tol : NDBG_APEX_TOL * cn_norm3(ext);
    if (push_cone(C, i, j) < 0) {
        cn_piece_free(&H);
        goto oom;
    }
    for (int f = 0; f < H.nfaces; f++) {
        const cnFace *F = &H.faces[f];
        if (fabs(F->offset) > thr) continue;
        if (push_nrm(C, F->normal[0], F->normal[1], F->normal[2]) < 0) {
            cn_piece_free(&H);
            goto oom;
        }
    }
    C->cone[C->ncone - 1].n = C->nnrm - C->cone[C->ncone - 1].first;
    cn_piece_free(&H);
    return CN_OK;
oom:
    return cn_diag_oom(diag);
}

static bool present(const cnAssembly *a, const unsigned char *absent, int i) {
    return i < a->nreal && cn_assembly_part_present(a, absent, i);
}

static bool movable(const cnAssembly *a, int i) { return i < a->nreal && !a->parts[i].fixed; }

cnStatus cn_ndbg_cones(const cnAssembly *a, const unsigned char *absent, const unsigned char *group,
                       cnNdbgCones *C, cnDiag *diag) {
    memset(C, 0, sizeof *C);
    Scratch sc;
    memset(&sc, 0, sizeof sc);
    cnStatus st = CN_OK;
    for (int i = 0; i < a->nreal && !st; i++) {
        if (!present(a, absent, i)) continue;
        for (int j = i + 1; j < a->nreal && !st; j++) {
            if (!present(a, absent, j) || (!movable(a, i) && !movable(a, j))) continue;
            if (group && !group[i] == !group[j]) continue;
            for (int p = 0; p < a->parts[i].npieces && !st; p++)
                for (int q = 0; q < a->parts[j].npieces && !st; q++)
                    st = cone_pieces(a, &a->parts[i].pieces[p], &a->parts[j].pieces[q], i, j, C,
                                     &sc, diag);
        }
    }
    cn_free(sc.ang);
    cn_free(sc.pts);
    cn_free(sc.m.pts);
    if (st) cn_ndbg_cones_free(C);
    return st;
}

void cn_ndbg_cones_free(cnNdbgCones *C) {
    if (!C) return;
    cn_free(C->cone);
    cn_free(C->nrm);
    memset(C, 0, sizeof *C);
}

/* ---- the arrangement ---- */

typedef struct {
    int nc;
    double (*c)[3];     /* the circles' unit normals */
    signed char *sv;    /* the cells' sign vectors, nc per cell, in the cells' final order */
    unsigned char *mover; /* per part: it may move in this graph */
    bool group;         /* the movers move as one group */
    int *hash;          /* cell index + 1 by sign vector, 0 empty */
    size_t hmask;
} Priv;

/* A cell while the arrangement is walked. */
typedef struct {
    int dim;
    double rep[3];      /* its direction (regions: once every corner is seen) */
    double sum[3], sumu[3]; /* regions: the sum of the corners and of the directions into it */
    double fb[3];       /* regions: a direction just inside it from its first corner */
    int pref;           /* 1 + the index of the preferred direction that lies in it, else 0 */
    double from, to;    /* 2-D */
    int order;          /* generation order */
} Work;

typedef struct {
    const cnAssembly *a;
    Priv *pv;
    int ncell, capcell;
    signed char *sv;
    Work *w;
    signed char *tmp;
    bool nomem;
} Arr;

static size_t hash_sv(const signed char *s, int n) {
    size_t h = 1469598103934665603u;
    for (int k = 0; k < n; k++) h = (h ^ (unsigned char)(s[k] + 1)) * 1099511628211u;
    return h;
}

static int find_sv(const Priv *pv, const signed char *sv, const signed char *s) {
    if (!pv->hash) return -1;
    for (size_t h = hash_sv(s, pv->nc) & pv->hmask;; h = (h + 1) & pv->hmask) {
        int c = pv->hash[h] - 1;
        if (c < 0) return -1;
        if (!memcmp(sv + (size_t)c * (size_t)pv->nc, s, (size_t)pv->nc)) return c;
    }
}

static int rehash(Priv *pv, const signed char *sv, int ncell, size_t size) {
    int *h = cn_calloc(size, sizeof(int));
    if (!h) return -1;
    cn_free(pv->hash);
    pv->hash = h;
    pv->hmask = size - 1;
    for (int c = 0; c < ncell; c++) {
        size_t k = hash_sv(sv + (size_t)c * (size_t)pv->nc, pv->nc) & pv->hmask;
        while (h[k]) k = (k + 1) & pv->hmask;
        h[k] = c + 1;
    }
    return 0;
}

/* The cell of sign vector s (added with dimension dim when new: *isnew); -1 out of memory. In 2-D
 * every call adds a cell: the two ends of a lone line have the same signs but are two cells. */
static int add_cell(Arr *A, const signed char *s, int dim, bool *isnew) {
    Priv *pv = A->pv;
    *isnew = false;
    int c = A->a->dim == 2 ? -1 : find_sv(pv, A->sv, s);
    if (c >= 0) return c;
    if (A->ncell == A->capcell) {
        int nc = A->capcell ? 2 * A->capcell : 64;
        signed char *ns = cn_realloc(A->sv, (size_t)nc * (size_t)(pv->nc ? pv->nc : 1));
        if (!ns) return -1;
        A->sv = ns;
        Work *nw = cn_realloc(A->w, sizeof(Work) * (size_t)nc);
        if (!nw) return -1;
        A->w = nw;
        A->capcell = nc;
    }
    if ((size_t)(A->ncell + 1) * 2 > pv->hmask + 1 || !pv->hash) {
        size_t size = 256;
        while (size < (size_t)(A->ncell + 1) * 4) size *= 2;
        if (rehash(pv, A->sv, A->ncell, size) < 0) return -1;
    }
    c = A->ncell++;
    memcpy(A->sv + (size_t)c * (size_t)pv->nc, s, (size_t)pv->nc);
    size_t k = hash_sv(s, pv->nc) & pv->hmask;
    while (pv->hash[k]) k = (k + 1) & pv->hmask;
    pv->hash[k] = c + 1;
    memset(&A->w[c], 0, sizeof(Work));
    A->w[c].dim = dim;
    A->w[c].order = c;
    *isnew = true;
    return c;
}

static signed char sgn(double x) { return x > CN_TOL_ANGLE ? 1 : x < -CN_TOL_ANGLE ? -1 : 0; }

static void signs_of(const Priv *pv, const double d[3], signed char *s) {
    for (int k = 0; k < pv->nc; k++) s[k] = sgn(cn_dot3(pv->c[k], d));
}

typedef struct {
    double ang;
    int circle;
    double t[3];
} Spoke;

static int cmp_spoke(const void *x, const void *y) {
    double a = ((const Spoke *)x)->ang, b = ((const Spoke *)y)->ang;
    return (a > b) - (a < b);
}

/* 3-D: every cell, found around every vertex. */
/* The cells at vertex v of the arrangement, where circles ia < ib cross (v is taken from its two
 * lowest circles only): the vertex, the arcs leaving it and the sectors between them, in order
 * around it. T (nc) and sp (2 nc) are scratch. 0, or -1 when out of memory. */
static int walk3_vertex(Arr *A, const double v[3], int ia, int ib, int *T, Spoke *sp) {
    Priv *pv = A->pv;
    int nc = pv->nc;
    signed char *s = A->tmp;
    bool isnew;
    /* the circles through v; found from its two lowest ones only */
    int m = 0;
    double near = 1; /* the smallest |c . v| of the circles not through it */
    bool lowest = true;
    for (int k = 0; k < nc; k++) {
        double x = cn_dot3(pv->c[k], v);
        if (k == ia || k == ib || fabs(x) <= CN_TOL_ANGLE) {
            if (k < ib && k != ia) lowest = false;
            T[m++] = k;
            s[k] = 0;
        } else {
            s[k] = x > 0 ? 1 : -1;
            near = fmin(near, fabs(x));
        }
    }
    if (!lowest) return 0;
    int cv = add_cell(A, s, 0, &isnew);
    if (cv < 0) return -1;
    if (isnew) cn_copy3(A->w[cv].rep, v);
    /* the arcs leaving v, in order around it */
    double e1[3], e2[3];
    cn_tangent_basis(v, e1, e2);
    for (int q = 0; q < m; q++) {
        double t[3];
        cn_cross3(pv->c[T[q]], v, t);
        cn_normalize3(t);
        for (int h = 0; h < 2; h++) {
            Spoke *x = &sp[2 * q + h];
            cn_copy3(x->t, t);
            if (h) cn_scale3(x->t, -1);
            x->circle = T[q];
            x->ang = atan2(cn_dot3(x->t, e2), cn_dot3(x->t, e1));
        }
    }
    int ns = 2 * m;
    qsort(sp, (size_t)ns, sizeof(Spoke), cmp_spoke);
    for (int q = 0; q < ns; q++) {
        /* the arc along spoke q */
        for (int r = 0; r < m; r++)
            s[T[r]] = T[r] == sp[q].circle ? 0 : sgn(cn_dot3(pv->c[T[r]], sp[q].t));
        int ce = add_cell(A, s, 1, &isnew);
        if (ce < 0) return -1;
        if (isnew) { /* its middle: half way to the next circle it crosses */
            double th = CN_PI;
            for (int k = 0; k < nc; k++) {
                if (k == sp[q].circle) continue;
                double A0 = cn_dot3(pv->c[k], v), B0 = cn_dot3(pv->c[k], sp[q].t);
                if (fabs(A0) <= CN_TOL_ANGLE) continue; /* meets it at -v */
                double r0 = atan2(-A0, B0);
                if (r0 <= 0) r0 += CN_PI;
                th = fmin(th, r0);
            }
            for (int k = 0; k < 3; k++)
                A->w[ce].rep[k] = cos(th / 2) * v[k] + sin(th / 2) * sp[q].t[k];
            cn_normalize3(A->w[ce].rep);
        }
        /* the sector between spoke q and the next */
        double a0 = sp[q].ang, a1 = q + 1 < ns ? sp[q + 1].ang : sp[0].ang + 2 * CN_PI;
        double mid = 0.5 * (a0 + a1), u[3];
        for (int k = 0; k < 3; k++) u[k] = cos(mid) * e1[k] + sin(mid) * e2[k];
        for (int r = 0; r < m; r++) s[T[r]] = sgn(cn_dot3(pv->c[T[r]], u));
        int cr = add_cell(A, s, 2, &isnew);
        if (cr < 0) return -1;
        Work *W = &A->w[cr];
        if (isnew) {
            double dl = fmin(0.5 * near, 0.25);
            for (int k = 0; k < 3; k++) W->fb[k] = v[k] + dl * u[k];
            cn_normalize3(W->fb);
        }
        cn_add3(W->sum, v, W->sum);
        cn_add3(W->sumu, u, W->sumu);
    }
    return 0;
}

static int walk3(Arr *A) {
    Priv *pv = A->pv;
    int nc = pv->nc;
    signed char *s = A->tmp;
    bool isnew;
    if (nc == 0) {
        int c = add_cell(A, s, 2, &isnew);
        if (c < 0) return -1;
        A->w[c].rep[2] = A->w[c].fb[2] = 1;
        return 0;
    }
    if (nc == 1) { /* two hemispheres and their circle, which has no vertex */
        for (int side = -1; side <= 1; side++) {
            s[0] = (signed char)side;
            int c = add_cell(A, s, side ? 2 : 1, &isnew);
            if (c < 0) return -1;
            if (side) {
                cn_copy3(A->w[c].rep, pv->c[0]);
                cn_scale3(A->w[c].rep, side);
            } else {
                double t2[3];
                cn_tangent_basis(pv->c[0], A->w[c].rep, t2);
            }
            cn_copy3(A->w[c].fb, A->w[c].rep);
        }
        return 0;
    }
    int *T = cn_malloc(sizeof(int) * (size_t)nc);
    Spoke *sp = cn_malloc(sizeof(Spoke) * (size_t)(2 * nc));
    if (!T || !sp) {
        cn_free(T), cn_free(sp);
        return -1;
    }
    int rc = 0;
    for (int ia = 0; ia < nc && !rc; ia++)
        for (int ib = ia + 1; ib < nc && !rc; ib++) {
            double v0[3];
            cn_cross3(pv->c[ia], pv->c[ib], v0);
            if (cn_normalize3(v0) <= 0) continue;
            for (int side = -1; side <= 1 && !rc; side += 2) {
                double v[3];
                cn_copy3(v, v0);
                cn_scale3(v, side);
                rc = walk3_vertex(A, v, ia, ib, T, sp);
            }
        }
    cn_free(T);
    cn_free(sp);
    if (rc) return rc;
    /* a region's direction: the mean of its corners, nudged inside (a lune's corners cancel) */
    for (int c = 0; c < A->ncell; c++) {
        Work *W = &A->w[c];
        if (W->dim != 2) continue;
        for (int k = 0; k < 3; k++) W->rep[k] = W->sum[k] + 1e-3 * W->sumu[k];
        signs_of(pv, W->rep, s);
        if (cn_normalize3(W->rep) <= 0 || memcmp(s, A->sv + (size_t)c * (size_t)nc, (size_t)nc))
            cn_copy3(W->rep, W->fb);
    }
    return 0;
}

static int cmp_double(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* 2-D: the points where the lines meet the circle, and the open arcs between them. */
static int walk2(Arr *A) {
    Priv *pv = A->pv;
    int nc = pv->nc;
    signed char *s = A->tmp;
    bool isnew;
    if (nc == 0) {
        int c = add_cell(A, s, 1, &isnew);
        if (c < 0) return -1;
        A->w[c].rep[1] = 1;
        A->w[c].from = 0, A->w[c].to = 2 * CN_PI;
        return 0;
    }
    double *ang = cn_malloc(sizeof(double) * (size_t)(2 * nc));
    if (!ang) return -1;
    for (int k = 0; k < nc; k++) {
        double t = atan2(pv->c[k][0], -pv->c[k][1]); /* the direction (-c_y, c_x) */
        if (t < 0) t += 2 * CN_PI;
        ang[2 * k] = t;
        ang[2 * k + 1] = t < CN_PI ? t + CN_PI : t - CN_PI;
    }
    int n = 2 * nc;
    qsort(ang, (size_t)n, sizeof(double), cmp_double);
    for (int i = 0; i < n; i++) {
        double a0 = ang[i], a1 = i + 1 < n ? ang[i + 1] : ang[0] + 2 * CN_PI;
        double pt[3] = {cos(a0), sin(a0), 0};
        signs_of(pv, pt, s);
        int c = add_cell(A, s, 0, &isnew);
        if (c < 0) break;
        if (isnew) cn_copy3(A->w[c].rep, pt), A->w[c].from = A->w[c].to = a0;
        double mid = 0.5 * (a0 + a1), pm[3] = {cos(mid), sin(mid), 0};
        signs_of(pv, pm, s);
        c = add_cell(A, s, 1, &isnew);
        if (c < 0) break;
        if (isnew) {
            cn_copy3(A->w[c].rep, pm);
            A->w[c].from = a0;
            A->w[c].to = a1 >= 2 * CN_PI ? a1 - 2 * CN_PI : a1;
        }
        if (i + 1 == n) {
            cn_free(ang);
            return 0;
        }
    }
    cn_free(ang);
    return -1;
}

/* A cell's place in the graph's order. */
typedef struct {
    double k1;
    int k2, k3, idx;
} Key;

static int cmp_key(const void *x, const void *y) {
    const Key *a = x, *b = y;
    if (a->k1 != b->k1) return (a->k1 > b->k1) - (a->k1 < b->k1);
    if (a->k2 != b->k2) return a->k2 - b->k2;
    return a->k3 - b->k3;
}

/* 3-D: up's cell, the axes' cells, then regions, arcs, single directions (as found); 2-D:
 * counter-clockwise from +x, a single direction before the arc that starts there. */
static Key key_of(const Work *w, int dim, int idx) {
    if (dim == 2) return (Key){.k1 = w->from, .k2 = w->dim, .k3 = w->order, .idx = idx};
    return (Key){.k1 = w->pref ? w->pref : 100, .k2 = -w->dim, .k3 = w->order, .idx = idx};
}

/* 2-D: the cell whose angles hold direction d. */
static int locate2(const Work *w, int n, const double d[3]) {
    double t = atan2(d[1], d[0]);
    if (t < 0) t += 2 * CN_PI;
    for (int c = 0; c < n; c++) {
        double len = w[c].to - w[c].from, x = t - w[c].from;
        if (len < 0) len += 2 * CN_PI;
        if (x < 0) x += 2 * CN_PI;
        if (w[c].dim == 0 ? fmin(x, 2 * CN_PI - x) <= CN_TOL_ANGLE
                          : (len >= 2 * CN_PI || (x > CN_TOL_ANGLE && x < len - CN_TOL_ANGLE)))
            return c;
    }
    return -1;
}

/* Does the cone hold the direction of sign vector s (mirror: the mirrored cone)? */
static bool cone_holds(const cnNdbgCone *K, const int *circ, const signed char *sg,
                       const signed char *s, bool mirror) {
    for (int k = 0; k < K->n; k++) {
        int idx = K->first + k;
        int x = sg[idx] * s[circ[idx]];
        if (x != (mirror ? 1 : -1)) return false;
    }
    return true;
}

/* The cones this graph needs (use), their normals' circles (pv->c, canonically oriented so that
 * the order of the parts does not matter), each normal's circle and side (circ, sg); past
 * max_circles the graph is too large (g->too_large). -1 when out of memory. */
static int graph_circles(const cnAssembly *a, const cnNdbgCones *C, const unsigned char *absent,
                         const unsigned char *group, int max_circles, Priv *pv, unsigned char *use, int *circ,
                         signed char *sg, cnNdbg *g) {
    int capc = 0;
    for (int i = 0; i < C->ncone; i++) {
        const cnNdbgCone *K = &C->cone[i];
        if (!present(a, absent, K->part) || !present(a, absent, K->other)) continue;
        if (group ? !group[K->part] == !group[K->other]
                  : !movable(a, K->part) && !movable(a, K->other))
            continue;
        use[i] = 1;
        for (int k = K->first; k < K->first + K->n && !g->too_large; k++) {
            const double *n = C->nrm[k];
            int found = -1;
            for (int c = 0; c < pv->nc && found < 0; c++) {
                double x[3];
                cn_cross3(n, pv->c[c], x);
                if (cn_norm3(x) <= CN_TOL_ANGLE) found = c;
            }
            if (found < 0) {
                if (pv->nc == max_circles) {
                    g->too_large = true;
                    break;
                }
                if (pv->nc == capc) {
                    capc = capc ? 2 * capc : 32;
                    double(*nw)[3] = cn_realloc(pv->c, sizeof(double[3]) * (size_t)capc);
                    if (!nw) return -1;
                    pv->c = nw;
                }
                /* a canonical orientation, so that the order of the parts does not matter */
                double *c = pv->c[pv->nc];
                cn_copy3(c, n);
                int big = 0;
                for (int q = 1; q < 3; q++)
                    if (fabs(c[q]) > fabs(c[big]) + CN_TOL_ANGLE) big = q;
                if (c[big] < 0) cn_scale3(c, -1);
                found = pv->nc++;
            }
            circ[k] = found;
            sg[k] = cn_dot3(n, pv->c[found]) > 0 ? 1 : -1;
        }
    }
    return 0;
}

/* The edges of the cell with sign vector s: a pair blocks when one of its pieces' cones holds
 * the cell (each way: mover and blocker). Appended to g->edges (*cape allocated); -1 when out of
 * memory. */
static int cell_edges(const cnAssembly *a, const cnNdbgCones *C, const unsigned char *group,
                      const int *pairs, int npairs, const int *circ, const signed char *sg, const signed char *s,
                      cnNdbg *g, int *capep) {
    int cape = *capep;
    for (int q = 0; q < npairs; q++) {
        int i = pairs[2 * q], j = pairs[2 * q + 1];
        int p = C->cone[i].part, o = C->cone[i].other;
        for (int mir = 0; mir < 2; mir++) {
            int mover = mir ? o : p, blocker = mir ? p : o;
            if (group ? !group[mover] : !movable(a, mover)) continue;
            bool held = false;
            for (int k = i; k < j && !held; k++) held = cone_holds(&C->cone[k], circ, sg, s, mir);
            if (!held) continue;
            if (g->nedges == cape) {
                cape = cape ? 2 * cape : 64;
                *capep = cape;
                cnNdbgEdge *ne = cn_realloc(g->edges, sizeof(cnNdbgEdge) * (size_t)cape);
                if (!ne) return -1;
                g->edges = ne;
            }
            g->edges[g->nedges++] = (cnNdbgEdge){.part = mover, .blocker = blocker};
        }
    }
    return 0;
}

cnStatus cn_ndbg_arrange(const cnAssembly *a, const cnNdbgCones *C, const unsigned char *absent,
                         const unsigned char *group, int max_circles, cnNdbg *g, cnDiag *diag) {
    memset(g, 0, sizeof *g);
    g->dim = a->dim;
    g->nparts = a->nparts;
    if (max_circles <= 0) max_circles = CN_NDBG_MAX_CIRCLES;
    Priv *pv = cn_calloc(1, sizeof(Priv));
    unsigned char *use = cn_calloc((size_t)C->ncone + 1, 1);
    int *circ = cn_malloc(sizeof(int) * (size_t)(C->nnrm + 1));
    signed char *sg = cn_malloc((size_t)C->nnrm + 1);
    Arr A;
    memset(&A, 0, sizeof A);
    A.a = a;
    A.pv = pv;
    int *perm = NULL, *pairs = NULL, npairs = 0;
    Key *keys = NULL;
    cnStatus st = CN_OK;
    g->priv_ = pv;
    if (!pv || !use || !circ || !sg || !(pv->mover = cn_calloc((size_t)a->nparts + 1, 1))) goto oom;
    for (int i = 0; i < a->nparts; i++)
        pv->mover[i] = present(a, absent, i) && (group ? group[i] != 0 : movable(a, i));
    pv->group = group != NULL;
    if (graph_circles(a, C, absent, group, max_circles, pv, use, circ, sg, g) < 0) goto oom;
    g->ncircles = pv->nc;
    if (g->too_large) goto done;
    A.tmp = cn_malloc((size_t)pv->nc + 1);
    if (!A.tmp) goto oom;
    if ((a->dim == 2 ? walk2(&A) : walk3(&A)) < 0) goto oom;
    /* up and the axes, where they lie in a cell, are its direction */
    {
        double pref[7][3] = {{0}};
        cn_copy3(pref[0], a->gravity);
        cn_scale3(pref[0], -1.0 / cn_norm3(a->gravity));
        int np = 1;
        for (int k = 0; k < a->dim; k++)
            for (int sd = -1; sd <= 1; sd += 2) pref[np][k] = sd, np++;
        for (int p = 0; p < np; p++) {
            signs_of(pv, pref[p], A.tmp);
            int c = a->dim == 2 ? locate2(A.w, A.ncell, pref[p]) : find_sv(pv, A.sv, A.tmp);
            if (c < 0 || A.w[c].pref) continue;
            A.w[c].pref = p + 1;
            cn_copy3(A.w[c].rep, pref[p]);
        }
    }
    /* the cells' order, then the sign vectors in that order */
    perm = cn_malloc(sizeof(int) * (size_t)(A.ncell + 1));
    keys = cn_malloc(sizeof(Key) * (size_t)(A.ncell + 1));
    g->cells = cn_calloc((size_t)A.ncell + 1, sizeof(cnNdbgCell));
    pv->sv = cn_malloc((size_t)(A.ncell + 1) * (size_t)(pv->nc + 1));
    if (!perm || !keys || !g->cells || !pv->sv) goto oom;
    for (int c = 0; c < A.ncell; c++) keys[c] = key_of(&A.w[c], a->dim, c);
    qsort(keys, (size_t)A.ncell, sizeof(Key), cmp_key);
    for (int c = 0; c < A.ncell; c++) perm[c] = keys[c].idx;
    for (int c = 0; c < A.ncell; c++)
        memcpy(pv->sv + (size_t)c * (size_t)pv->nc, A.sv + (size_t)perm[c] * (size_t)pv->nc, (size_t)pv->nc);
    cn_free(pv->hash);
    pv->hash = NULL;
    {
        size_t size = 256;
        while (size < (size_t)A.ncell * 4) size *= 2;
        if (rehash(pv, pv->sv, A.ncell, size) < 0) goto oom;
    }
    g->ncells = A.ncell;
    /* the pairs used: each its first cone and one past its last */
    pairs = cn_malloc(sizeof(int) * (size_t)(2 * C->ncone + 2));
    if (!pairs) goto oom;
    for (int i = 0; i < C->ncone;) {
        int j = i;
        while (j < C->ncone && C->cone[j].part == C->cone[i].part && C->cone[j].other == C->cone[i].other) j++;
        if (use[i]) pairs[2 * npairs] = i, pairs[2 * npairs + 1] = j, npairs++;
        i = j;
    }
    /* each cell's edges: a pair blocks when one of its pieces' cones holds the cell */
    int cape = 0;
    for (int c = 0; c < g->ncells; c++) {
        const Work *W = &A.w[perm[c]];
        cnNdbgCell *cell = &g->cells[c];
        cn_copy3(cell->dir, W->rep);
        cell->dim = W->dim;
        cell->from = W->from, cell->to = W->to;
        cell->first = g->nedges;
        const signed char *s = pv->sv + (size_t)c * (size_t)pv->nc;
        if (cell_edges(a, C, group, pairs, npairs, circ, sg, s, g, &cape) < 0) goto oom;
        cell->nedges = g->nedges - cell->first;
    }
    goto done;
oom:
    st = cn_diag_oom(diag);
done:
    cn_free(use);
    cn_free(circ);
    cn_free(sg);
    cn_free(A.sv);
    cn_free(A.w);
    cn_free(A.tmp);
    cn_free(perm);
    cn_free(pairs);
    cn_free(keys);
    if (st) cn_ndbg_free(g);
    return st;
}

cnStatus cn_ndbg_build(const cnAssembly *a, const unsigned char *absent, const unsigned char *group,
                       int max_circles, cnNdbg *g, cnDiag *diag) {
    memset(g, 0, sizeof *g);
    cnNdbgCones C;
    cnStatus st = cn_ndbg_cones(a, absent, group, &C, diag);
    if (st) return st;
    st = cn_ndbg_arrange(a, &C, absent, group, max_circles, g, diag);
    cn_ndbg_cones_free(&C);
    return st;
}

int cn_ndbg_locate(const cnNdbg *g, const double d[3]) {
    const Priv *pv = g ? g->priv_ : NULL;
    if (!pv || g->too_large || g->ncells == 0) return -1;
    signed char *s = cn_malloc((size_t)pv->nc + 1);
    if (!s) return -1;
    double u[3] = {d[0], d[1], g->dim == 2 ? 0 : d[2]};
    cn_normalize3(u);
    int c;
    if (g->dim == 2) {
        c = -1;
        for (int k = 0; k < g->ncells && c < 0; k++) {
            const cnNdbgCell *x = &g->cells[k];
            Work w = {.dim = x->dim, .from = x->from, .to = x->to};
            if (locate2(&w, 1, u) == 0) c = k;
        }
    } else {
        signs_of(pv, u, s);
        c = find_sv(pv, pv->sv, s);
    }
    cn_free(s);
    return c;
}

void cn_ndbg_free(cnNdbg *g) {
    if (!g) return;
    Priv *pv = g->priv_;
    if (pv) {
        cn_free(pv->c);
        cn_free(pv->sv);
        cn_free(pv->hash);
        cn_free(pv->mover);
        cn_free(pv);
    }
    cn_free(g->cells);
    cn_free(g->edges);
    memset(g, 0, sizeof *g);
}

/* ---- removable subassemblies of one cell ---- */

cnStatus cn_ndbg_removable(const cnAssembly *a, const cnNdbg *g, int cell, int **parts,
                           int **start, int *nsets, cnDiag *diag) {
    *parts = NULL, *start = NULL, *nsets = 0;
    int n = a->nparts;
    const cnNdbgCell *C = &g->cells[cell];
    /* closure[i * n + j]: j must come along when i is taken out */
    unsigned char *cl = cn_calloc((size_t)n * (size_t)n + 1, 1);
    int *queue = cn_malloc(sizeof(int) * (size_t)(n + 1));
    unsigned char *ok = cn_calloc((size_t)n + 1, 1), *keep = cn_calloc((size_t)n + 1, 1);
    if (!cl || !queue || !ok || !keep) goto oom;
    const Priv *pv = g->priv_;
    const unsigned char *mover = pv->mover;
    for (int i = 0; i < a->nreal; i++) {
        if (!mover[i]) continue;
        if (pv->group) { /* the group leaves as one or not at all */
            memset(cl + (size_t)i * (size_t)n, 0, (size_t)n);
            for (int j = 0; j < n; j++) cl[(size_t)i * (size_t)n + j] = mover[j];
            ok[i] = C->nedges == 0;
            continue;
        }
        unsigned char *row = cl + (size_t)i * (size_t)n;
        int h = 0, t = 0;
        row[i] = 1;
        queue[t++] = i;
        ok[i] = 1;
        while (h < t) {
            int x = queue[h++];
            if (!mover[x]) ok[i] = 0;
            for (int e = 0; e < C->nedges; e++) {
                const cnNdbgEdge *E = &g->edges[C->first + e];
                if (E->part != x || row[E->blocker]) continue;
                row[E->blocker] = 1;
                queue[t++] = E->blocker;
            }
        }
    }
    /* minimal: every part of it has the same closure (a smaller closure inside would be valid) */
    int total = 0, ns = 0;
    for (int i = 0; i < a->nreal; i++) {
        if (!mover[i] || !ok[i]) continue;
        const unsigned char *row = cl + (size_t)i * (size_t)n;
        bool minimal = true, first = true;
        for (int j = 0; j < n && minimal; j++) {
            if (!row[j] || j == i) continue;
            if (memcmp(cl + (size_t)j * (size_t)n, row, (size_t)n)) minimal = false;
            else if (j < i) first = false; /* the same set, listed from its lowest part */
        }
        if (!minimal || !first) continue;
        keep[i] = 1;
        ns++;
        for (int j = 0; j < n; j++) total += row[j];
    }
    *parts = cn_malloc(sizeof(int) * (size_t)(total + 1));
    *start = cn_malloc(sizeof(int) * (size_t)(ns + 1));
    if (!*parts || !*start) goto oom;
    int k = 0, s = 0;
    for (int i = 0; i < a->nreal; i++) {
        if (!keep[i]) continue;
        (*start)[s++] = k;
        for (int j = 0; j < n; j++)
            if (cl[(size_t)i * (size_t)n + j]) (*parts)[k++] = j;
    }
    (*start)[s] = k;
    *nsets = ns;
    cn_free(cl), cn_free(queue), cn_free(ok), cn_free(keep);
    return CN_OK;
oom:
    cn_free(cl), cn_free(queue), cn_free(ok), cn_free(keep);
    cn_free(*parts), cn_free(*start);
    *parts = NULL, *start = NULL;
    return cn_diag_oom(diag);
}

/* ---- the free directions of a group ---- */

static void add_dir(double (*dirs)[3], int *n, const double d[3]) {
    for (int i = 0; i < *n; i++)
        if (cn_dot3(dirs[i], d) > 1 - CN_TOL_SAME_DIRECTION) return;
    cn_copy3(dirs[(*n)++], d);
}

cnStatus cn_ndbg_free_dirs(const cnAssembly *a, const cnNdbg *g, double (**dirs)[3], int *nd,
                           cnDiag *diag) {
    *dirs = NULL;
    *nd = 0;
    double(*d)[3] = cn_malloc(sizeof(double[3]) * (size_t)(g->ncells + 8));
    if (!d) return cn_diag_oom(diag);
    int n = 0;
    double up[3];
    cn_copy3(up, a->gravity);
    cn_scale3(up, -1.0 / cn_norm3(up));
    if (cn_ndbg_cell_free(g, cn_ndbg_locate(g, up))) add_dir(d, &n, up);
    for (int c = 0; c < g->ncells; c++)
        if (cn_ndbg_cell_free(g, c)) add_dir(d, &n, g->cells[c].dir);
    for (int k = 0; k < a->dim; k++)
        for (int sd = -1; sd <= 1; sd += 2) {
            double e[3] = {0, 0, 0};
            e[k] = sd;
            if (cn_ndbg_cell_free(g, cn_ndbg_locate(g, e))) add_dir(d, &n, e);
        }
    *dirs = d;
    *nd = n;
    return CN_OK;
}
