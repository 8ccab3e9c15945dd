/* Translational motion planning in 3-D: routes that leave through distinct openings (the
 * planner's automatic candidates beside straight lines; the 3-D counterpart of paths2.c).
 *
 * The configuration-space obstacle of a moving convex piece p against a still convex piece q
 * is the convex polytope M = conv{q_i - p_j} (qhull): a translation t makes them overlap
 * exactly when t is inside M. A route of the reference point from the origin must not pass
 * through any interior (touching, sliding along a face, is allowed: interiors are shrunk by the
 * contact tolerance of the two parts, the one the simulation judges them by). Routes run
 * through a roadmap whose nodes are the origin, the obstacles'
 * vertices and the midpoints of their edges (a passage between two edges has no vertex of its
 * own); edges are straight legs between nodes that see each other, found lazily by Dijkstra.
 * A route ends with a leg out to infinity from its last node: up, across gravity, or between,
 * long enough to clear every obstacle. Shortest polyhedral paths in 3-D bend over edges, so
 * these are short routes, not shortest ones; one is kept per distinct last node (the opening
 * it leaves by), shortest first, legs along one line joined, and a route that another already
 * is (through a node on its line) kept once. Each is then verified by the exact swept test:
 * every moving piece swept along each leg (the hull of its two ends) must not overlap a still
 * piece. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "paths2.h"
#include "cairn/plan.h"

/* Roadmaps larger than this are not built (the planner keeps its straight lines); edge
 * midpoints are added only while the count stays below it. */
#define PATHS3_MAX_NODES 600
/* Directions of the last leg: up, PATHS3_RING across gravity, PATHS3_RING halfway up. */
#define PATHS3_RING 8
#define PATHS3_GOALS (1 + 2 * PATHS3_RING)

typedef struct {
    int nf;
    double (*n)[3];   /* outward unit normals */
    double *off;      /* n . x = off on each face */
    int nv, nm;       /* corners, then edge midpoints, in v */
    double tol;       /* the contact tolerance of the two parts (cn_pair_tolerance) */
    double (*v)[3];
    double lo[3], hi[3];
} Obs;

/* Does the segment a-b pass through the interior of the polytope deeper than tol? (a == b:
 * is the point inside.) */
static bool seg_blocked3(const Obs *P, const double a[3], const double b[3]) {
    double tol = P->tol;
    for (int k = 0; k < 3; k++)
        if (fmax(a[k], b[k]) < P->lo[k] + tol || fmin(a[k], b[k]) > P->hi[k] - tol) return false;
    double t0 = 0, t1 = 1, d[3];
    cn_sub3(b, a, d);
    for (int f = 0; f < P->nf; f++) {
        /* inside distance (positive inside), shrunk by tol */
        double f0 = P->off[f] - tol - cn_dot3(P->n[f], a);
        double fd = -cn_dot3(P->n[f], d);
        if (fabs(fd) < 1e-300) {
            if (f0 <= 0) return false;
            continue;
        }
        double t = -f0 / fd;
        if (fd > 0) t0 = fmax(t0, t);
        else t1 = fmin(t1, t);
        if (t0 >= t1) return false;
    }
    return t1 - t0 > CN_TOL_LENGTH_ZERO;
}

static bool leg_blocked(const Obs *ob, int no, const double a[3], const double b[3]) {
    for (int k = 0; k < no; k++)
        if (seg_blocked3(&ob[k], a, b)) return true;
    return false;
}

/* The obstacles of a visibility graph in 3-D. */
typedef struct {
    const Obs *ob;
    int no;
} Obstacles3;

static bool blocked3(void *ctx, const double *a, const double *b) {
    const Obstacles3 *o = ctx;
    return leg_blocked(o->ob, o->no, a, b);
}

static void obs_free(Obs *o) {
    cn_free(o->n);
    cn_free(o->off);
    cn_free(o->v);
    memset(o, 0, sizeof *o);
}

/* The C-space obstacle of moving piece P against still piece Q: 0 built, 1 degenerate (flat:
 * no interior to enter), -1 out of memory. */
static int obstacle(const cnPiece *P, const cnPiece *Q, Obs *out) {
    memset(out, 0, sizeof *out);
    int n = P->nverts * Q->nverts;
    double(*pts)[3] = cn_malloc(sizeof(double[3]) * (size_t)n);
    if (!pts) return -1;
    int k = 0;
    for (int u = 0; u < Q->nverts; u++)
        for (int v = 0; v < P->nverts; v++) cn_sub3(Q->verts[u], P->verts[v], pts[k++]);
    cnPiece h;
    cnDiag local;
    cn_diag_clear(&local);
    cnStatus st = cn_hull3_build((const double(*)[3])pts, n, &h, &local);
    cn_free(pts);
    if (st == CN_ERR_MEMORY) return -1;
    if (st) return 1;
    out->nf = h.nfaces, out->nv = h.nverts, out->nm = h.nedges;
    out->n = cn_malloc(sizeof(double[3]) * (size_t)h.nfaces);
    out->off = cn_malloc(sizeof(double) * (size_t)h.nfaces);
    out->v = cn_malloc(sizeof(double[3]) * (size_t)(h.nverts + h.nedges));
    if (!out->n || !out->off || !out->v) {
        cn_piece_free(&h);
        obs_free(out);
        return -1;
    }
    for (int f = 0; f < h.nfaces; f++) {
        cn_copy3(out->n[f], h.faces[f].normal);
        out->off[f] = h.faces[f].offset;
    }
    memcpy(out->v, h.verts, sizeof(double[3]) * (size_t)h.nverts);
    for (int e = 0; e < h.nedges; e++)
        for (int c = 0; c < 3; c++)
            out->v[h.nverts + e][c] = 0.5 * (h.verts[h.edges[e][0]][c] + h.verts[h.edges[e][1]][c]);
    cn_copy3(out->lo, h.lo);
    cn_copy3(out->hi, h.hi);
    cn_piece_free(&h);
    return 0;
}

/* The exact swept test of one leg: every moving piece, translated by `at`, swept by `d` (the
 * hull of its two ends), against every still piece. true: no overlap deeper than tol. */
static cnStatus leg_free(const cnAssembly *a, const unsigned char *absent,
                         const unsigned char *moving, const double at[3], const double d[3],
                         bool *free_, cnDiag *diag) {
    *free_ = true;
    double zero[3] = {0, 0, 0};
    cnManifold m = {.pts = NULL};
    cnStatus st = CN_OK;
    for (int i = 0; i < a->nparts && *free_ && !st; i++) {
        if (!moving[i]) continue;
        for (int pi = 0; pi < a->parts[i].npieces && *free_ && !st; pi++) {
            const cnPiece *p = &a->parts[i].pieces[pi];
            int n = p->nverts;
            double(*q)[3] = cn_malloc(sizeof(double[3]) * (size_t)(2 * n));
            if (!q) {
                st = cn_diag_oom(diag);
                break;
            }
            for (int v = 0; v < n; v++)
                for (int k = 0; k < 3; k++) {
                    q[v][k] = p->verts[v][k] + at[k];
                    q[n + v][k] = q[v][k] + d[k];
                }
            cnPiece sw;
            cnDiag local;
            cn_diag_clear(&local);
            cnStatus hs = cn_hull3_build((const double(*)[3])q, 2 * n, &sw, &local);
            cn_free(q);
            if (hs == CN_ERR_MEMORY) {
                st = cn_diag_oom(diag);
                break;
            }
            if (hs) { /* a flat sweep cannot happen for a solid piece: refuse the leg */
                *free_ = false;
                break;
            }
            for (int j = 0; j < a->nparts && *free_; j++) {
                if (moving[j] || !cn_assembly_part_present(a, absent, j)) continue;
                /* judged at the pair's own tolerance, as the simulation will judge it */
                double tol = cn_pair_tolerance(a, i, j);
                for (int qi = 0; qi < a->parts[j].npieces && *free_; qi++) {
                    const cnPiece *Q = &a->parts[j].pieces[qi];
                    bool apart = false;
                    for (int k = 0; k < 3; k++)
                        if (sw.lo[k] > Q->hi[k] + tol || Q->lo[k] > sw.hi[k] + tol) apart = true;
                    if (apart) continue;
                    int r = cn_contact3_pieces(&sw, zero, Q, zero, zero, tol, &m);
                    if (r < 0) st = cn_diag_oom(diag);
                    else if (r == CN_PAIR_OVERLAP) *free_ = false;
                }
            }
            cn_piece_free(&sw);
        }
    }
    cn_free(m.pts);
    return st;
}

/* Do legs a and b point the same way (parallel, same sense)? */
static bool same_way(const double a[3], const double b[3]) {
    double c3[3];
    cn_cross3(a, b, c3);
    return cn_norm3(c3) <= CN_TOL_SAME_DIRECTION * cn_norm3(a) * cn_norm3(b) && cn_dot3(a, b) > 0;
}

/* Is the route legs[0..nl) one of the n kept (the same legs within tol)? */
static bool known_route(double (*segs)[CN_ROUTE_MAX_SEGMENTS][3], const int *nseg, int n,
                        double (*legs)[3], int nl, double tol) {
    for (int p = 0; p < n; p++) {
        bool same = nseg[p] == nl;
        for (int l = 0; same && l < nl; l++) {
            double d[3];
            cn_sub3(segs[p][l], legs[l], d);
            same = cn_norm3(d) <= tol;
        }
        if (same) return true;
    }
    return false;
}

/* The last leg's directions: up, a ring across gravity and a ring halfway up. */
static int goal_dirs(const cnAssembly *a, double (*g)[3]) {
    double up[3], e1[3], e2[3];
    cn_copy3(up, a->gravity);
    cn_scale3(up, -1.0 / cn_norm3(up));
    /* a frame about up: e1 from the axis least along it */
    int k = 0;
    for (int c = 1; c < 3; c++)
        if (fabs(up[c]) < fabs(up[k])) k = c;
    double ax[3] = {0, 0, 0};
    ax[k] = 1;
    cn_cross3(up, ax, e1);
    cn_normalize3(e1);
    cn_cross3(up, e1, e2);
    int n = 0;
    cn_copy3(g[n++], up);
    for (int ring = 0; ring < 2; ring++)
        for (int i = 0; i < PATHS3_RING; i++) {
            double th = 2 * CN_PI * i / PATHS3_RING, el = ring ? CN_PI / 4 : 0;
            for (int c = 0; c < 3; c++)
                g[n][c] = cos(el) * (cos(th) * e1[c] + sin(th) * e2[c]) + sin(el) * up[c];
            cn_normalize3(g[n]);
            n++;
        }
    return n;
}

/* The configuration-space obstacles of the moving parts against the parts present that stay
 * (*obp, *nop of them, *capp allocated), and the moving parts' size *own. -1 when out of memory
 * (what was built is left to free). */
static int obstacles3(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving, Obs **obp,
                      int *nop, int *capp, double *ownp) {
    Obs *ob = *obp;
    int no = *nop, cap = *capp, rc = 0;
    double own = 0;
    for (int i = 0; i < a->nparts; i++) {
        if (!moving[i]) continue;
        double d[3];
        cn_sub3(a->parts[i].hi, a->parts[i].lo, d);
        own = fmax(own, cn_norm3(d));
        for (int j = 0; j < a->nparts; j++) {
            if (moving[j] || !cn_assembly_part_present(a, absent, j)) continue;
            for (int pi = 0; pi < a->parts[i].npieces; pi++)
                for (int qi = 0; qi < a->parts[j].npieces; qi++) {
                    if (no == cap) {
                        Obs *n2 = cn_realloc(ob, sizeof(Obs) * (size_t)(2 * cap));
                        if (!n2) { rc = -1; goto out; }
                        memset(n2 + cap, 0, sizeof(Obs) * (size_t)cap);
                        ob = n2, cap *= 2;
                    }
                    int r = obstacle(&a->parts[i].pieces[pi], &a->parts[j].pieces[qi], &ob[no]);
                    if (r < 0) { rc = -1; goto out; }
                    ob[no].tol = cn_pair_tolerance(a, i, j);
                    if (r == 0) no++;
                }
        }
    }
out:
    *obp = ob, *nop = no, *capp = cap, *ownp = own;
    return rc;
}

cnStatus cn_paths3(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                   int max_paths, double (*segs)[CN_ROUTE_MAX_SEGMENTS][3], int *nseg, int *npaths, cnDiag *diag) {
    *npaths = 0;
    if (a->dim != 3 || max_paths <= 0) return CN_OK;
    double tol = a->contact_tol, own = 0;
    int cap = 32, no = 0;
    Obs *ob = cn_calloc((size_t)cap, sizeof(Obs));
    double(*node)[3] = NULL;
    double *dist = NULL, *reach = NULL;
    int *prev = NULL, *reach_g = NULL;
    unsigned char *done_ = NULL;
    cnStatus st = CN_OK;
    if (!ob) return cn_diag_oom(diag);
    if (obstacles3(a, absent, moving, &ob, &no, &cap, &own) != 0) goto oom;
    {
        /* nodes: the origin, the corners, then the edge midpoints while they fit */
        int nn = 1, nmid = 0;
        for (int k = 0; k < no; k++) nn += ob[k].nv, nmid += ob[k].nm;
        if (nn > PATHS3_MAX_NODES) goto done;
        bool mids = nn + nmid <= PATHS3_MAX_NODES;
        if (mids) nn += nmid;
        node = cn_calloc((size_t)nn, sizeof(double[3]));
        dist = cn_malloc(sizeof(double) * (size_t)nn);
        reach = cn_malloc(sizeof(double) * (size_t)nn);
        prev = cn_malloc(sizeof(int) * (size_t)nn);
        reach_g = cn_malloc(sizeof(int) * (size_t)nn);
        done_ = cn_calloc((size_t)nn, 1);
        if (!node || !dist || !reach || !prev || !reach_g || !done_) goto oom;
        int m = 1;
        for (int k = 0; k < no; k++)
            for (int q = 0; q < ob[k].nv + (mids ? ob[k].nm : 0); q++) cn_copy3(node[m++], ob[k].v[q]);
        /* Dijkstra with visibility tested lazily; a node inside an obstacle is not reached */
        Obstacles3 obs = {ob, no};
        cnVisGraph vg = {3, &node[0][0], m, m, 1, true, blocked3, &obs};
        cn_vis_dijkstra(&vg, dist, prev, done_);
        /* the way out from each node: the shortest clear last leg among the goal directions */
        double g[PATHS3_GOALS][3];
        int ng = goal_dirs(a, g);
        double margin = 0.05 * own + 10 * tol;
        for (int u = 0; u < m; u++) {
            reach[u] = INFINITY, reach_g[u] = -1;
            if (!(dist[u] < INFINITY)) continue;
            for (int k = 0; k < ng; k++) {
                double t = 0;
                for (int q = 0; q < no; q++)
                    for (int w = 0; w < ob[q].nv; w++) {
                        double r[3];
                        cn_sub3(ob[q].v[w], node[u], r);
                        t = fmax(t, cn_dot3(r, g[k]));
                    }
                t += margin;
                if (t >= reach[u]) continue;
                double end[3];
                for (int c = 0; c < 3; c++) end[c] = node[u][c] + t * g[k][c];
                if (!leg_blocked(ob, no, node[u], end)) reach[u] = t, reach_g[u] = k;
            }
        }
        /* one route per last node, shortest first; the origin's own way out is a straight line,
         * which the straight-line candidates cover */
        for (;;) {
            if (*npaths >= max_paths) break;
            int best = -1;
            for (int u = 1; u < m; u++)
                if (reach_g[u] >= 0 && (best < 0 || dist[u] + reach[u] < dist[best] + reach[best]))
                    best = u;
            if (best < 0) break;
            int u = best, k = reach_g[u];
            reach_g[u] = -1; /* taken */
            int chain[CN_ROUTE_MAX_SEGMENTS + 1], nc = 0;
            bool fits = true;
            for (int x = u; x >= 0; x = prev[x]) {
                if (nc == CN_ROUTE_MAX_SEGMENTS) {
                    fits = false;
                    break;
                }
                chain[nc++] = x;
            }
            if (!fits) continue;
            /* legs: the chain (origin last in it), then out */
            double legs[CN_ROUTE_MAX_SEGMENTS][3], at[3] = {0, 0, 0};
            int nl = 0;
            for (int c = nc - 1; c > 0; c--) cn_sub3(node[chain[c - 1]], node[chain[c]], legs[nl++]);
            for (int c = 0; c < 3; c++) legs[nl][c] = reach[u] * g[k][c];
            nl++;
            /* drop zero legs (coincident nodes) and join legs that go on along one line (a node
             * passed straight through); one leg left is a straight line */
            int nz = 0;
            for (int l = 0; l < nl; l++) {
                if (cn_norm3(legs[l]) <= tol) continue;
                if (nz > 0 && same_way(legs[nz - 1], legs[l]))
                    cn_add3(legs[nz - 1], legs[l], legs[nz - 1]);
                else cn_copy3(legs[nz++], legs[l]);
            }
            nl = nz;
            if (nl <= 1 || known_route(segs, nseg, *npaths, legs, nl, tol)) continue;
            /* verified leg by leg by the exact swept test */
            bool ok = true;
            for (int l = 0; l < nl && ok; l++) {
                st = leg_free(a, absent, moving, at, legs[l], &ok, diag);
                if (st) goto done;
                cn_add3(at, legs[l], at);
            }
            if (!ok) continue;
            int p = (*npaths)++;
            nseg[p] = nl;
            for (int l = 0; l < nl; l++) cn_copy3(segs[p][l], legs[l]);
        }
    }
    goto done;
oom:
    st = cn_diag_oom(diag);
done:
    for (int k = 0; k < cap; k++) obs_free(&ob[k]);
    cn_free(ob);
    cn_free(node), cn_free(dist), cn_free(reach), cn_free(prev), cn_free(reach_g), cn_free(done_);
    return st;
}
