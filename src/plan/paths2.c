/* Translational motion planning in 2-D: paths that leave through distinct openings (for the
 * planner's automatic candidates, like the paper's exits).
 *
 * The configuration-space obstacle of a moving convex piece p against a convex piece q is the
 * convex polygon M = conv{q_i - p_j} (translations that make them overlap lie in its interior).
 * A path of the reference point from the origin must not pass through any interior (touching,
 * sliding along a boundary, is allowed). Shortest paths run along the visibility graph of the
 * obstacles' vertices (Lozano-Perez and Wesley 1979) to goal points on a circle around
 * everything; paths whose last corner (the opening they leave by) differs are kept. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "paths2.h"
#include "cairn/plan.h"

/* Goal directions on the far circle. */
#define PATHS_GOALS 24
/* Visibility graphs larger than this are not built (the planner keeps straight lines). */
#define PATHS_MAX_NODES 400

typedef struct {
    int n;
    double (*v)[2]; /* CCW */
    double lo[2], hi[2];
} Poly;

/* Does segment a-b pass through the interior of the convex polygon deeper than tol? */
static bool seg_blocked(const Poly *P, const double a[2], const double b[2], double tol) {
    if (fmax(a[0], b[0]) < P->lo[0] + tol || fmin(a[0], b[0]) > P->hi[0] - tol ||
        fmax(a[1], b[1]) < P->lo[1] + tol || fmin(a[1], b[1]) > P->hi[1] - tol)
        return false;
    double t0 = 0, t1 = 1, d[2] = {b[0] - a[0], b[1] - a[1]};
    for (int i = 0; i < P->n; i++) {
        const double *p = P->v[i], *q = P->v[(i + 1) % P->n];
        double ex = q[0] - p[0], ey = q[1] - p[1], L = hypot(ex, ey);
        if (L == 0) continue;
        /* inside distance (positive inside), shrunk by tol */
        double f0 = (ex * (a[1] - p[1]) - ey * (a[0] - p[0])) / L - tol;
        double fd = (ex * d[1] - ey * d[0]) / L;
        if (fabs(fd) < 1e-300) {
            if (f0 <= 0) return false;
            continue;
        }
        double t = -f0 / fd;
        if (fd > 0) t0 = fmax(t0, t);
        else t1 = fmin(t1, t);
        if (t0 >= t1) return false;
    }
    return t1 - t0 > CN_TOL_LENGTH_ZERO; /* fractions of the segment */
}

/* The obstacles of a visibility graph in 2-D. */
typedef struct {
    const Poly *polys;
    int np;
    double tol;
} Obstacles2;

static bool blocked2(void *ctx, const double *a, const double *b) {
    const Obstacles2 *o = ctx;
    for (int k = 0; k < o->np; k++)
        if (seg_blocked(&o->polys[k], a, b, o->tol)) return true;
    return false;
}

/* The configuration-space obstacles of the moving parts against the parts present that stay
 * (*polys, *np of them, *cap allocated), their extent *ext and the moving parts' size *own; pts
 * is scratch. -1 when out of memory (what was built is left to free). */
static int obstacles2(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                      Poly **polysp, int *npp, int *capp, double (**ptsp)[2], int *cappts_p, double *extp,
                      double *ownp) {
    Poly *polys = *polysp;
    int np = *npp, cap = *capp, cappts = *cappts_p;
    double(*pts)[2] = *ptsp;
    int rc = 0;
    double ext = 0, own = 0; /* obstacles' extent; the moving parts' own size */
    for (int i = 0; i < a->nparts; i++) {
        if (!moving[i]) continue;
        double d[3];
        cn_sub3(a->parts[i].hi, a->parts[i].lo, d);
        own = fmax(own, cn_norm3(d));
        for (int j = 0; j < a->nparts; j++) {
            bool blocker = !moving[j] && cn_assembly_part_present(a, absent, j);
            if (!blocker) continue;
            for (int pi = 0; pi < a->parts[i].npieces; pi++)
                for (int qi = 0; qi < a->parts[j].npieces; qi++) {
                    const cnPiece *P = &a->parts[i].pieces[pi], *Q = &a->parts[j].pieces[qi];
                    int need = P->nverts * Q->nverts;
                    if (need > cappts) {
                        double(*n2)[2] = cn_realloc(pts, sizeof(double[2]) * (size_t)need);
                        if (!n2) { rc = -1; goto out; }
                        pts = n2, cappts = need;
                    }
                    int k = 0;
                    for (int u = 0; u < Q->nverts; u++)
                        for (int v = 0; v < P->nverts; v++) {
                            pts[k][0] = Q->verts[u][0] - P->verts[v][0];
                            pts[k][1] = Q->verts[u][1] - P->verts[v][1];
                            k++;
                        }
                    int h = cn_hull2(pts, k, 0);
                    if (h < 3) continue;
                    if (np == cap) {
                        cap *= 2;
                        Poly *n2 = cn_realloc(polys, sizeof(Poly) * (size_t)cap);
                        if (!n2) { rc = -1; goto out; }
                        polys = n2;
                    }
                    Poly *M = &polys[np++];
                    M->n = h;
                    M->v = cn_malloc(sizeof(double[2]) * (size_t)h);
                    if (!M->v) { rc = -1; goto out; }
                    memcpy(M->v, pts, sizeof(double[2]) * (size_t)h);
                    M->lo[0] = M->lo[1] = INFINITY, M->hi[0] = M->hi[1] = -INFINITY;
                    for (int q = 0; q < h; q++)
                        for (int c = 0; c < 2; c++) {
                            M->lo[c] = fmin(M->lo[c], M->v[q][c]), M->hi[c] = fmax(M->hi[c], M->v[q][c]);
                            ext = fmax(ext, fabs(M->v[q][c]));
                        }
                }
        }
    }
out:
    *polysp = polys, *npp = np, *capp = cap, *ptsp = pts, *cappts_p = cappts, *extp = ext, *ownp = own;
    return rc;
}

cnStatus cn_paths2(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                   int max_paths, double (*segs)[CN_ROUTE_MAX_SEGMENTS][3], int *nseg, int *npaths, cnDiag *diag) {
    *npaths = 0;
    if (a->dim != 2) return CN_OK;
    double tol = a->contact_tol;
    int cap = 32, np = 0;
    Poly *polys = cn_calloc((size_t)cap, sizeof(Poly));
    double(*pts)[2] = NULL;
    int cappts = 0;
    cnStatus st = CN_OK;
    if (!polys) return cn_diag_oom(diag);
    double ext = 0, own = 0; /* obstacles' extent; the moving parts' own size */
    if (obstacles2(a, absent, moving, &polys, &np, &cap, &pts, &cappts, &ext, &own) != 0) goto oom;
    {
        /* nodes: the origin, the obstacles' vertices (exact: a leg along an obstacle's edge is
         * then exactly parallel to the touching surfaces), goals on the far circle */
        int nn = 1;
        for (int k = 0; k < np; k++) nn += polys[k].n;
        nn += PATHS_GOALS;
        if (nn > PATHS_MAX_NODES) goto done;
        double(*node)[2] = cn_calloc((size_t)nn, sizeof(double[2]));
        double *dist = cn_malloc(sizeof(double) * (size_t)nn);
        int *prev = cn_malloc(sizeof(int) * (size_t)nn);
        unsigned char *done_ = cn_calloc((size_t)nn, 1);
        if (!node || !dist || !prev || !done_) {
            cn_free(node), cn_free(dist), cn_free(prev), cn_free(done_);
            goto oom;
        }
        int m = 1;
        for (int k = 0; k < np; k++)
            for (int q = 0; q < polys[k].n; q++) {
                node[m][0] = polys[k].v[q][0];
                node[m][1] = polys[k].v[q][1];
                m++;
            }
        double R = 2 * ext + 10 * a->length_scale * 1e-3 + 1;
        /* goals up or sideways only: parts leave an assembly against gravity or across it */
        double up[2] = {-a->gravity[0], -a->gravity[1]}, gl = hypot(up[0], up[1]);
        up[0] /= gl, up[1] /= gl;
        int g0 = m;
        for (int g = 0; g < PATHS_GOALS; g++) {
            double th = 2 * CN_PI * g / PATHS_GOALS;
            if (cos(th) * up[0] + sin(th) * up[1] < -1e-9) continue;
            node[m][0] = R * cos(th), node[m][1] = R * sin(th);
            m++;
        }
        /* Dijkstra with visibility tested lazily, O(m^2 * obstacles); goals are ends */
        Obstacles2 obs = {polys, np, tol};
        cnVisGraph vg = {2, &node[0][0], m, g0, 0, false, blocked2, &obs};
        cn_vis_dijkstra(&vg, dist, prev, done_);
        /* one path per distinct opening (the last corner before the goal), shortest first */
        int order[PATHS_GOALS + 1];
        int no = 0;
        for (int g = g0; g < m; g++)
            if (dist[g] < INFINITY) order[no++] = g;
        for (int i = 1; i < no; i++)
            for (int j = i; j > 0 && dist[order[j - 1]] > dist[order[j]]; j--) {
                int t = order[j];
                order[j] = order[j - 1];
                order[j - 1] = t;
            }
        int used_last[PATHS_GOALS];
        int nused = 0;
        for (int i = 0; i < no && *npaths < max_paths; i++) {
            int g = order[i], last = prev[g];
            if (last == 0) continue; /* straight out: the straight-line candidates cover it */
            bool dup = false;
            for (int k = 0; k < nused; k++) dup |= used_last[k] == last;
            if (dup) continue;
            /* the chain of nodes, origin first */
            int chain[PATHS_MAX_NODES], nc = 0;
            for (int x = g; x >= 0 && nc < PATHS_MAX_NODES; x = prev[x]) chain[nc++] = x;
            if (nc - 1 > CN_ROUTE_MAX_SEGMENTS) continue;
            used_last[nused++] = last;
            int p = (*npaths)++;
            nseg[p] = 0;
            for (int k = nc - 1; k > 0; k--) {
                double dx = node[chain[k - 1]][0] - node[chain[k]][0];
                double dy = node[chain[k - 1]][1] - node[chain[k]][1];
                if (k == 1) {
                    /* the last leg only as far as it takes to be past every obstacle */
                    double L = hypot(dx, dy), ux = dx / L, uy = dy / L, t = 0;
                    const double *c = node[chain[1]];
                    for (int q = 0; q < np; q++)
                        for (int w = 0; w < polys[q].n; w++) {
                            double along = (polys[q].v[w][0] - c[0]) * ux + (polys[q].v[w][1] - c[1]) * uy;
                            t = fmax(t, along);
                        }
                    t += 0.05 * own + 10 * tol; /* a margin the part's own size sets */
                    if (t < L) dx = ux * t, dy = uy * t;
                }
                segs[p][nseg[p]][0] = dx, segs[p][nseg[p]][1] = dy, segs[p][nseg[p]][2] = 0;
                nseg[p]++;
            }
        }
        cn_free(node), cn_free(dist), cn_free(prev), cn_free(done_);
    }
    goto done;
oom:
    st = cn_diag_oom(diag);
done:
    for (int k = 0; k < np; k++) cn_free(polys[k].v);
    cn_free(polys);
    cn_free(pts);
    return st;
}
