/* Feasible removal directions: the non-directional blocking graph's cells (paper sec. II-B, after
 * Wilson and Latombe).
 *
 * 2-D, exact: a convex piece p translated by t d overlaps a convex piece q iff t d lies in the
 * interior of the Minkowski difference M = q + (-p) = conv{q_i - p_j}. The ray {t d : t > 0}
 * meets int M iff d lies strictly inside the angular extent of M seen from the origin (M does not
 * contain the origin in its interior, parts at rest do not overlap): an open arc of at most pi
 * (exactly pi when the pieces touch along an edge). The free directions are the circle minus the
 * union of these open arcs: closed arcs, possibly single directions (a block in a slot can only
 * go up). Arc ends within ARC_SNAP of each other are one direction, so that two blocking arcs
 * that meet leave exactly that direction free.
 *
 * Any dimension, exact per direction: the piece swept along d (the hull of p and p + L d, L past
 * the assembly) must not overlap q beyond the contact tolerance. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "blocking.h"
#include "collide.h"
#include "ndbg.h"
#include "cairn/plan.h"

/* Arc ends closer than this (radians) are the same direction. */
#define ARC_SNAP 1e-9

void cn_free_arcs(cnArc *arcs) { cn_free(arcs); }
void cn_directions_free(double (*dirs)[3]) { cn_free(dirs); }

static double wrap(double t) {
    t = fmod(t, 2 * CN_PI);
    if (t < 0) t += 2 * CN_PI;
    if (t >= 2 * CN_PI) t -= 2 * CN_PI;
    return t;
}

static int cmp_double(const void *x, const void *y) {
    double a = *(const double *)x, b = *(const double *)y;
    return (a > b) - (a < b);
}

/* The open angular extent of the points (origin excluded) as [lo, hi] with lo <= hi possibly
 * above 2 pi. Returns 0 when there is no point away from the origin. */
static int extent(double *ang, int n, double *lo, double *hi) {
    if (n == 0) return 0;
    qsort(ang, (size_t)n, sizeof(double), cmp_double);
    double gap = -1;
    int at = 0;
    for (int i = 0; i < n; i++) {
        double next = i + 1 < n ? ang[i + 1] : ang[0] + 2 * CN_PI;
        if (next - ang[i] > gap) gap = next - ang[i], at = i;
    }
    /* the arc runs from the angle after the largest gap to the angle before it */
    *lo = at + 1 < n ? ang[at + 1] : ang[0];
    *hi = ang[at];
    if (*hi < *lo) *hi += 2 * CN_PI;
    return 1;
}

typedef struct {
    double lo, len; /* the open arc from lo (in [0, 2 pi)) counter-clockwise over len (0, pi] */
} Open;

/* The cluster end an arc end x snaps to: the last k whose e[k] is within ARC_SNAP of x, around
 * the circle (e sorted, m of them, at least ARC_SNAP apart); -1 when none is. */
static int snap_end(const double *e, int m, double x) {
    int best = -1;
    int lo = 0, hi = m; /* the first e[k] >= x - ARC_SNAP */
    while (lo < hi) {
        int mid = (lo + hi) / 2;
        if (e[mid] < x - ARC_SNAP) lo = mid + 1;
        else hi = mid;
    }
    for (int k = lo; k < m && e[k] <= x + ARC_SNAP; k++)
        if (fabs(e[k] - x) <= ARC_SNAP) best = k;
    /* across 0: the largest ends near 2 pi when x is near 0, the smallest near 0 when x is near 2 pi */
    if (m > 0 && fabs(e[m - 1] - x) >= 2 * CN_PI - ARC_SNAP) return m - 1;
    for (int k = 0; best < 0 && k < m && fabs(e[k] - x) >= 2 * CN_PI - ARC_SNAP; k++) best = k;
    return best;
}

/* Add 1 over the indices [a, b) around a circle of m (a == b: none), as a difference array. */
static void cover(int *diff, int m, int a, int b) {
    if (a == b) return;
    diff[a]++, diff[b]--;
    if (a > b) diff[0]++, diff[m]--;
}

/* Complement of a union of open arcs on the circle: closed arcs. Ends are snapped first (ends
 * within ARC_SNAP are one direction). Then every distinct end and the middle of every gap
 * between consecutive ends is tested, and runs of free ones are joined into closed arcs; an arc
 * from end kl to end kh covers the ends strictly between them and the gaps from kl to kh, which
 * difference arrays count in time linear in the arcs and ends. */
static cnStatus complement(Open *ar, int n, cnArc **out, int *nout) {
    *out = NULL;
    *nout = 0;
    double *e = cn_malloc(sizeof(double) * (size_t)(2 * n + 2));
    unsigned char *fe = cn_malloc((size_t)(2 * n + 2)), *fg = cn_malloc((size_t)(2 * n + 2));
    cnArc *res = cn_malloc(sizeof(cnArc) * (size_t)(2 * n + 2));
    int *de = cn_calloc((size_t)(2 * n + 3), sizeof(int)), *dg = cn_calloc((size_t)(2 * n + 3), sizeof(int));
    if (!e || !fe || !fg || !res || !de || !dg) {
        cn_free(e), cn_free(fe), cn_free(fg), cn_free(res), cn_free(de), cn_free(dg);
        return CN_ERR_MEMORY;
    }
    int ne = 0;
    for (int i = 0; i < n; i++) e[ne++] = wrap(ar[i].lo), e[ne++] = wrap(ar[i].lo + ar[i].len);
    qsort(e, (size_t)ne, sizeof(double), cmp_double);
    /* cluster the ends (also across 0) */
    int m = 0;
    for (int i = 0; i < ne; i++)
        if (m == 0 || e[i] - e[m - 1] > ARC_SNAP) e[m++] = e[i];
    if (m > 1 && e[0] + 2 * CN_PI - e[m - 1] <= ARC_SNAP) m--;
    if (m == 0) { /* nothing blocks: the whole circle */
        res[0].from = 0, res[0].to = 2 * CN_PI;
        *out = res, *nout = 1;
        cn_free(e), cn_free(fe), cn_free(fg), cn_free(de), cn_free(dg);
        return CN_OK;
    }
    for (int i = 0; i < n; i++) { /* snap each arc's ends to the cluster values, and count what it covers */
        double lo = wrap(ar[i].lo), hi = wrap(ar[i].lo + ar[i].len);
        int kl = snap_end(e, m, lo), kh = snap_end(e, m, hi);
        if (kl >= 0) lo = e[kl];
        if (kh >= 0) hi = e[kh];
        double len = wrap(hi - lo);
        if (len == 0) len = ar[i].len > CN_PI ? 2 * CN_PI : 0;
        ar[i].lo = lo, ar[i].len = len;
        if (len == 0 || kl < 0 || kh < 0) continue;
        if (len == 2 * CN_PI) { /* every end but its own, and every gap */
            cover(de, m, (kl + 1) % m, kl);
            cover(dg, m, kl, kl), dg[0]++, dg[m]--;
            continue;
        }
        cover(de, m, (kl + 1) % m, kh);
        cover(dg, m, kl, kh);
    }
    for (int k = 0, ce = 0, cg = 0; k < m; k++) {
        ce += de[k], cg += dg[k];
        fe[k] = ce == 0, fg[k] = cg == 0;
    }
    /* walk once around from a blocked element: end k, then gap k (to end k+1) */
    int start = -1;
    for (int k = 0; k < m && start < 0; k++) {
        if (!fe[k]) start = 2 * k;
        else if (!fg[k]) start = 2 * k + 1;
    }
    int nr = 0;
    if (start < 0) { /* only ends touch: everything free */
        res[0].from = 0, res[0].to = 2 * CN_PI;
        nr = 1;
    } else {
        bool in = false;
        double from = 0;
        for (int t = 1; t <= 2 * m; t++) {
            int el = (start + t) % (2 * m), k = el / 2;
            bool isfree = el % 2 == 0 ? fe[k] : fg[k];
            if (isfree && !in) {
                in = true;
                from = e[k]; /* a free gap starts at its (free) end k */
            }
            if (!isfree && in) {
                in = false;
                /* the run ended at the element before: an end k (closed) or the gap before it */
                res[nr].from = from;
                res[nr].to = el % 2 == 0 ? e[(k + m - 1) % m] : e[k];
                if (el % 2 == 0) res[nr].to = e[(k + m - 1) % m];
                nr++;
            }
        }
        if (in) res[nr].from = from, res[nr].to = e[start / 2], nr++;
    }
    cn_free(e), cn_free(fe), cn_free(fg), cn_free(de), cn_free(dg);
    *out = res;
    *nout = nr;
    return CN_OK;
}

int cn_blocked_arc2(const cnPiece *P, const cnPiece *Q, double tol, double **scratch, int *cap,
                    double *lo, double *len) {
    int need = P->nverts * Q->nverts;
    if (need > *cap) {
        double *na = cn_realloc(*scratch, sizeof(double) * (size_t)need);
        if (!na) return -1;
        *scratch = na, *cap = need;
    }
    double *ang = *scratch, hi;
    int k = 0;
    for (int u = 0; u < Q->nverts; u++)
        for (int v = 0; v < P->nverts; v++) {
            double dx = Q->verts[u][0] - P->verts[v][0];
            double dy = Q->verts[u][1] - P->verts[v][1];
            if (hypot(dx, dy) > tol) ang[k++] = wrap(atan2(dy, dx));
        }
    if (!extent(ang, k, lo, &hi)) return 0;
    *len = fmin(hi - *lo, CN_PI); /* touching along an edge: a half-plane */
    return *len > 0;
}

static bool is_blocker(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                       int j) {
    if (moving[j]) return false;
    return cn_assembly_part_present(a, absent, j);
}

cnStatus cn_directions2(const cnAssembly *a, const unsigned char *absent,
                        const unsigned char *moving, cnArc **free_arcs, int *nfree,
                        cnArc **local, int *nlocal, cnDiag *diag) {
    if (a->dim != 2)
        return cn_diag_set(diag, CN_ERR_INPUT, "dimension", "exact direction arcs are 2-D only");
    int cap = 64, n = 0, nl = 0;
    Open *ar = cn_malloc(sizeof(Open) * (size_t)cap), *al = cn_malloc(sizeof(Open) * (size_t)cap);
    double *ang = NULL;
    int capang = 0;
    cnManifold m = {.pts = NULL};
    cnStatus st = CN_OK;
    double tol = a->contact_tol, zero[3] = {0, 0, 0};
    if (!ar || !al) goto oom;
    for (int i = 0; i < a->nparts; i++) {
        if (!moving[i]) continue;
        for (int j = 0; j < a->nparts; j++) {
            if (!is_blocker(a, absent, moving, j)) continue;
            for (int pi = 0; pi < a->parts[i].npieces; pi++)
                for (int qi = 0; qi < a->parts[j].npieces; qi++) {
                    const cnPiece *P = &a->parts[i].pieces[pi], *Q = &a->parts[j].pieces[qi];
                    double lo, len;
                    int r0 = cn_blocked_arc2(P, Q, tol, &ang, &capang, &lo, &len);
                    if (r0 < 0) goto oom;
                    if (r0 == 0) continue;
                    if (n == cap || nl == cap) {
                        cap *= 2;
                        Open *n1 = cn_realloc(ar, sizeof(Open) * (size_t)cap);
                        if (!n1) goto oom;
                        ar = n1;
                        Open *n2 = cn_realloc(al, sizeof(Open) * (size_t)cap);
                        if (!n2) goto oom;
                        al = n2;
                    }
                    ar[n].lo = lo, ar[n].len = len, n++;
                    int r = cn_contact2_pieces(P, zero, Q, zero, zero, tol, &m);
                    if (r == CN_PAIR_TOUCH || r == CN_PAIR_OVERLAP) al[nl].lo = lo, al[nl].len = len, nl++;
                }
        }
    }
    if (complement(ar, n, free_arcs, nfree) != CN_OK) goto oom;
    if (local && complement(al, nl, local, nlocal) != CN_OK) goto oom;
    goto done;
oom:
    st = cn_diag_oom(diag);
done:
    cn_free(ar);
    cn_free(al);
    cn_free(ang);
    cn_free(m.pts);
    return st;
}

/* The piece swept along d over L: the hull of its vertices and their translates. */
static cnStatus swept_piece(const cnPiece *p, int dim, const double d[3], double L, cnPiece *out,
                            cnDiag *diag) {
    memset(out, 0, sizeof *out);
    int n = p->nverts;
    if (dim == 2) {
        double(*q)[2] = cn_malloc(sizeof(double[2]) * (size_t)(2 * n));
        if (!q) return cn_diag_oom(diag);
        for (int i = 0; i < n; i++) {
            q[i][0] = p->verts[i][0], q[i][1] = p->verts[i][1];
            q[n + i][0] = p->verts[i][0] + L * d[0], q[n + i][1] = p->verts[i][1] + L * d[1];
        }
        int h = cn_hull2(q, 2 * n, 0);
        out->verts = cn_calloc((size_t)(h > 0 ? h : 1), sizeof(double[3]));
        if (h < 3 || !out->verts) {
            cn_free(q);
            cn_free(out->verts);
            out->verts = NULL;
            return cn_diag_set(diag, CN_ERR_NUMERIC, "", "degenerate swept piece");
        }
        for (int i = 0; i < h; i++) out->verts[i][0] = q[i][0], out->verts[i][1] = q[i][1];
        out->nverts = h;
        cn_free(q);
        cn_piece_bounds(out, 2);
        return CN_OK;
    }
    double(*q)[3] = cn_malloc(sizeof(double[3]) * (size_t)(2 * n));
    if (!q) return cn_diag_oom(diag);
    for (int i = 0; i < n; i++) {
        cn_copy3(q[i], p->verts[i]);
        for (int k = 0; k < 3; k++) q[n + i][k] = p->verts[i][k] + L * d[k];
    }
    cnStatus st = cn_hull3_build((const double(*)[3])q, 2 * n, out, diag);
    cn_free(q);
    return st;
}

cnStatus cn_direction_free(const cnAssembly *a, const unsigned char *absent,
                           const unsigned char *moving, const double d[3], bool *free_,
                           cnDiag *diag) {
    *free_ = true;
    double L = 3 * a->length_scale, tol = a->contact_tol, zero[3] = {0, 0, 0};
    cnManifold m = {.pts = NULL};
    for (int i = 0; i < a->nparts && *free_; i++) {
        if (!moving[i]) continue;
        for (int pi = 0; pi < a->parts[i].npieces && *free_; pi++) {
            cnPiece sw;
            cnStatus st = swept_piece(&a->parts[i].pieces[pi], a->dim, d, L, &sw, diag);
            if (st) {
                cn_free(m.pts);
                return st;
            }
            for (int j = 0; j < a->nparts && *free_; j++) {
                if (!is_blocker(a, absent, moving, j)) continue;
                for (int qi = 0; qi < a->parts[j].npieces && *free_; qi++) {
                    const cnPiece *Q = &a->parts[j].pieces[qi];
                    bool apart = false;
                    for (int k = 0; k < a->dim; k++)
                        if (sw.lo[k] > Q->hi[k] + tol || Q->lo[k] > sw.hi[k] + tol) apart = true;
                    if (apart) continue;
                    int r = a->dim == 2 ? cn_contact2_pieces(&sw, zero, Q, zero, zero, tol, &m)
                                        : cn_contact3_pieces(&sw, zero, Q, zero, zero, tol, &m);
                    if (r == CN_PAIR_OVERLAP) *free_ = false;
                }
            }
            cn_piece_free(&sw);
        }
    }
    cn_free(m.pts);
    return CN_OK;
}

static int push_dir(double (**dirs)[3], int *n, int *cap, const double d[3]) {
    for (int i = 0; i < *n; i++)
        if (cn_dot3((*dirs)[i], d) > 1 - CN_TOL_SAME_DIRECTION) return 0;
    if (*n == *cap) {
        int nc = *cap ? 2 * *cap : 32;
        double(*nd)[3] = cn_realloc(*dirs, sizeof(double[3]) * (size_t)nc);
        if (!nd) return -1;
        *dirs = nd;
        *cap = nc;
    }
    cn_copy3((*dirs)[(*n)++], d);
    return 0;
}

cnStatus cn_free_directions(const cnAssembly *a, const unsigned char *absent,
                            const unsigned char *moving, double (**dirs)[3], int *ndirs,
                            cnDiag *diag) {
    *dirs = NULL;
    *ndirs = 0;
    double up[3];
    cn_copy3(up, a->gravity);
    cn_scale3(up, -1.0 / cn_norm3(up));
    double(*cand)[3] = NULL;
    int nc = 0, capc = 0, cap = 0;
    cnStatus st = CN_OK;
    if (push_dir(&cand, &nc, &capc, up) < 0) goto oom;
    if (a->dim == 2) {
        cnArc *arcs;
        int na;
        st = cn_directions2(a, absent, moving, &arcs, &na, NULL, NULL, diag);
        if (st) goto done;
        for (int i = 0; i < na; i++) {
            double len = wrap(arcs[i].to - arcs[i].from);
            if (arcs[i].to - arcs[i].from >= 2 * CN_PI) len = 2 * CN_PI;
            double mids[3] = {arcs[i].from + 0.5 * len, arcs[i].from, arcs[i].from + len};
            for (int k = 0; k < 3; k++) {
                double d[3] = {cos(mids[k]), sin(mids[k]), 0};
                if (push_dir(&cand, &nc, &capc, d) < 0) {
                    cn_free_arcs(arcs);
                    goto oom;
                }
            }
        }
        cn_free_arcs(arcs);
    } else {
        /* exact: the free cells of the group's blocking graph (ndbg.c) */
        cnNdbg g;
        st = cn_ndbg_build(a, absent, moving, 0, &g, diag);
        if (st) goto done;
        if (!g.too_large) {
            cn_free(cand);
            st = cn_ndbg_free_dirs(a, &g, dirs, ndirs, diag);
            cn_ndbg_free(&g);
            return st;
        }
        cn_ndbg_free(&g);
        /* too many circles: the arrangement's likely directions, each tested: the axes, the face
         * normals, their cross products, both signs */
        double (*nrm)[3] = NULL;
        int nn = 0, capn = 0;
        for (int k = 0; k < 3; k++) {
            double e[3] = {0, 0, 0};
            e[k] = 1;
            if (push_dir(&nrm, &nn, &capn, e) < 0) goto oom;
        }
        for (int i = 0; i < a->nparts; i++) {
            if (!(moving[i] || is_blocker(a, absent, moving, i))) continue;
            for (int s = 0; s < a->parts[i].npieces; s++)
                for (int f = 0; f < a->parts[i].pieces[s].nfaces; f++) {
                    double n1[3];
                    cn_copy3(n1, a->parts[i].pieces[s].faces[f].normal);
                    if (n1[0] < 0 || (n1[0] == 0 && (n1[1] < 0 || (n1[1] == 0 && n1[2] < 0))))
                        cn_scale3(n1, -1);
                    if (push_dir(&nrm, &nn, &capn, n1) < 0) goto oom;
                }
        }
        for (int i = 0; i < nn; i++)
            for (int sgn = -1; sgn <= 1; sgn += 2) {
                double d[3];
                cn_copy3(d, nrm[i]);
                cn_scale3(d, sgn);
                if (push_dir(&cand, &nc, &capc, d) < 0) goto oom;
            }
        for (int i = 0; i < nn && nn < 40; i++)
            for (int j = i + 1; j < nn; j++) {
                double d[3];
                cn_cross3(nrm[i], nrm[j], d);
                if (cn_normalize3(d) < 1e-9) continue;
                if (push_dir(&cand, &nc, &capc, d) < 0) goto oom;
                cn_scale3(d, -1);
                if (push_dir(&cand, &nc, &capc, d) < 0) goto oom;
            }
        cn_free(nrm);
    }
    for (int i = 0; i < nc; i++) {
        bool ok;
        st = cn_direction_free(a, absent, moving, cand[i], &ok, diag);
        if (st) goto done;
        if (ok && push_dir(dirs, ndirs, &cap, cand[i]) < 0) goto oom;
    }
    goto done;
oom:
    st = cn_diag_oom(diag);
done:
    cn_free(cand);
    return st;
}
