/* Candidate removal paths (plan/cands.c) and routes through openings (plan/paths2.c, paths3.c)
 * against geometry computed here: separating-axis overlap tests sampled along each path,
 * hand-derived free directions, lengths and shortest routes, and invariance under moving the
 * whole assembly. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cands.h"
#include "helpers.h"
#include "paths2.h"

/* ---- scenes: axis-aligned boxes, the whole assembly placed by one rigid motion ---- */

typedef struct {
    const char *name;
    int fixed;
    double lo[3], hi[3];
} Box;

typedef struct {
    double R[3][3];
    double t[3];
} Xf;

static Xf xf_id(void) {
    Xf x = {{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {0, 0, 0}};
    return x;
}

/* A turn by `deg` about z (exact for quarter turns), then a shift by t. */
static Xf xf_turn_z(double deg, double tx, double ty, double tz) {
    Xf x = xf_id();
    double c = cos(deg * CN_PI / 180), s = sin(deg * CN_PI / 180);
    if (fmod(deg, 90) == 0) c = round(c), s = round(s);
    x.R[0][0] = c, x.R[0][1] = -s, x.R[1][0] = s, x.R[1][1] = c;
    x.t[0] = tx, x.t[1] = ty, x.t[2] = tz;
    return x;
}

/* A quarter turn about x: y -> z, z -> -y. */
static Xf xf_quarter_x(void) {
    Xf x = {{{1, 0, 0}, {0, 0, -1}, {0, 1, 0}}, {0, 0, 0}};
    return x;
}

static void xf_dir(const Xf *x, const double v[3], double out[3]) {
    double r[3];
    for (int i = 0; i < 3; i++)
        r[i] = x->R[i][0] * v[0] + x->R[i][1] * v[1] + x->R[i][2] * v[2];
    memcpy(out, r, sizeof r);
}

static void xf_point(const Xf *x, const double p[3], double out[3]) {
    xf_dir(x, p, out);
    for (int i = 0; i < 3; i++)
        out[i] += x->t[i];
}

/* The boxes as JSON, every corner and gravity (-y in 2-D, -z in 3-D) moved by x: polygons in
 * 2-D, hulls of the eight corners in 3-D. */
static char *scene_json(int dim, const Box *b, int n, const Xf *x) {
    size_t cap = 512 + (size_t)n * 1200;
    char *s = malloc(cap);
    double g[3] = {0, dim == 2 ? -1 : 0, dim == 3 ? -1 : 0}, gx[3];
    xf_dir(x, g, gx);
    int len = dim == 2
                  ? snprintf(s, cap, "{\"dimension\":2,\"gravity\":[%.17g,%.17g],\"parts\":[",
                             gx[0], gx[1])
                  : snprintf(s, cap, "{\"dimension\":3,\"gravity\":[%.17g,%.17g,%.17g],\"parts\":[",
                             gx[0], gx[1], gx[2]);
    for (int k = 0; k < n; k++) {
        len +=
            snprintf(s + len, cap - (size_t)len, "%s{\"name\":\"%s\",%s\"%s\":[", k ? "," : "",
                     b[k].name, b[k].fixed ? "\"fixed\":true," : "", dim == 2 ? "polygon" : "hull");
        int nc = dim == 2 ? 4 : 8;
        for (int c = 0; c < nc; c++) {
            /* 2-D counter-clockwise: (lo, lo), (hi, lo), (hi, hi), (lo, hi) */
            int bx = dim == 2 ? (c == 1 || c == 2) : c & 1, by = dim == 2 ? c >= 2 : (c >> 1) & 1;
            double p[3] = {bx ? b[k].hi[0] : b[k].lo[0], by ? b[k].hi[1] : b[k].lo[1],
                           dim == 3 && (c >> 2) ? b[k].hi[2] : b[k].lo[2]},
                   q[3];
            if (dim == 2) p[2] = 0;
            xf_point(x, p, q);
            len += dim == 2 ? snprintf(s + len, cap - (size_t)len, "%s[%.17g,%.17g]", c ? "," : "",
                                       q[0], q[1])
                            : snprintf(s + len, cap - (size_t)len, "%s[%.17g,%.17g,%.17g]",
                                       c ? "," : "", q[0], q[1], q[2]);
        }
        len += snprintf(s + len, cap - (size_t)len, "]}");
    }
    snprintf(s + len, cap - (size_t)len, "]}");
    return s;
}

/* clang-format off */
/* 2-D scenes (gravity -y): a table under a unit block A at [0, 1]^2. */
#define TABLE2 {"table", 1, {-10, -1, 0}, {10, 0, 0}}
#define BLOCK2 {"A", 0, {0, 0, 0}, {1, 1, 0}}
static const Box TABLE_ONLY[] = {TABLE2, BLOCK2};
/* walls touching both sides, 3 tall: open only upward */
static const Box SLOT[] = {TABLE2, BLOCK2, {"w1", 1, {-1, 0, 0}, {0, 3, 0}},
                           {"w2", 1, {1, 0, 0}, {2, 3, 0}}};
/* a wall as tall as the block touching its left side */
static const Box CORNER[] = {TABLE2, BLOCK2, {"w1", 1, {-1, 0, 0}, {0, 1, 0}}};
/* B on A */
static const Box STACK2[] = {TABLE2, BLOCK2, {"B", 0, {0, 1, 0}, {1, 2, 0}}};
/* A sandwiched between the table and a lintel over [0, 1.5], a wall on its left, a wall at
 * x = 3: it leaves only by sliding right 1.5, then rising past the walls (3 tall) */
static const Box LINTEL2[] = {TABLE2, BLOCK2, {"left", 1, {-1, 0, 0}, {0, 3, 0}},
                              {"lintel", 1, {0, 1, 0}, {1.5, 1.3, 0}},
                              {"right", 1, {3, 0, 0}, {4, 3, 0}}};
/* closed all round */
static const Box BOXED2[] = {TABLE2, BLOCK2, {"w1", 1, {-1, 0, 0}, {0, 3, 0}},
                             {"w2", 1, {1, 0, 0}, {2, 3, 0}}, {"lid", 1, {-1, 3, 0}, {2, 4, 0}}};

/* 3-D scenes (gravity -z): a floor under a unit cube A at [0, 1]^3. */
#define FLOOR3 {"floor", 1, {-3, -3, -1}, {4, 4, 0}}
#define CUBE3 {"A", 0, {0, 0, 0}, {1, 1, 1}}
/* walls 2 tall touching all four sides: open only upward */
static const Box POCKET3[] = {FLOOR3, CUBE3,
                              {"xm", 1, {-1, -1, 0}, {0, 2, 2}}, {"xp", 1, {1, -1, 0}, {2, 2, 2}},
                              {"ym", 1, {0, -1, 0}, {1, 0, 2}}, {"yp", 1, {0, 1, 0}, {1, 2, 2}}};
/* a U-shaped channel along y: walls 2 tall touching the cube's x sides */
static const Box CHANNEL3[] = {FLOOR3, CUBE3, {"xm", 1, {-1, -2, 0}, {0, 3, 2}},
                               {"xp", 1, {1, -2, 0}, {2, 3, 2}}};
/* B on A */
static const Box STACK3[] = {FLOOR3, CUBE3, {"B", 0, {0, 0, 1}, {1, 1, 2}}};
/* the lintel in 3-D: a chamber x in [0, 3], y in [0, 1] walled 3 tall, a slab over the cube's
 * x in [0, 1.5]: the cube slides +x 1.5, then rises 3 */
static const Box LINTEL3[] = {{"floor", 1, {-2, -2, -1}, {5, 3, 0}}, CUBE3,
                              {"xm", 1, {-1, -1, 0}, {0, 2, 3}}, {"xp", 1, {3, -1, 0}, {4, 2, 3}},
                              {"ym", 1, {0, -1, 0}, {3, 0, 3}}, {"yp", 1, {0, 1, 0}, {3, 2, 3}},
                              {"slab", 1, {0, 0, 1}, {1.5, 1, 1.3}}};
/* clang-format on */
#define NB(s) ((int)(sizeof(s) / sizeof(s[0])))

/* ---- brute-force geometry on the loaded pieces ---- */

/* The shadow [lo, hi] of piece P moved by off on unit axis u. */
static void shadow(const cnPiece *P, const double off[3], const double u[3], double *lo,
                   double *hi) {
    *lo = INFINITY, *hi = -INFINITY;
    for (int v = 0; v < P->nverts; v++) {
        double x = (P->verts[v][0] + off[0]) * u[0] + (P->verts[v][1] + off[1]) * u[1] +
                   (P->verts[v][2] + off[2]) * u[2];
        *lo = fmin(*lo, x), *hi = fmax(*hi, x);
    }
}

static double axis_overlap(const cnPiece *P, const double off[3], const cnPiece *Q,
                           const double u[3]) {
    static const double zero[3] = {0, 0, 0};
    double a0, a1, b0, b1;
    shadow(P, off, u, &a0, &a1);
    shadow(Q, zero, u, &b0, &b1);
    return fmin(a1, b1) - fmax(a0, b0);
}

/* The distinct directions of a 3-D piece's edges (a box has 3); returns how many. */
static int edge_dirs(const cnPiece *P, double (*out)[3], int cap) {
    int n = 0;
    for (int e = 0; e < P->nedges; e++) {
        double d[3], c[3];
        cn_sub3(P->verts[P->edges[e][1]], P->verts[P->edges[e][0]], d);
        if (cn_normalize3(d) == 0) continue;
        bool dup = false;
        for (int k = 0; k < n && !dup; k++) {
            cn_cross3(d, out[k], c);
            dup = cn_norm3(c) < 1e-12;
        }
        if (!dup && n < cap) cn_copy3(out[n++], d);
    }
    return n;
}

/* Overlap depth of convex pieces P (moved by off) and Q by the separating-axis theorem: the
 * least overlap of their shadows over the coordinate axes and the edge normals (2-D), or the
 * face normals and the cross products of edge directions (3-D). Negative: apart, by at least
 * its size. Pieces apart by more than 1e-3 along a coordinate axis are not looked at further
 * (every scene here is of unit size: far more than the contact tolerance). */
static double piece_depth(int dim, const cnPiece *P, const double off[3], const cnPiece *Q) {
    double depth = INFINITY;
    for (int k = 0; k < dim; k++) {
        double u[3] = {0, 0, 0};
        u[k] = 1;
        depth = fmin(depth, axis_overlap(P, off, Q, u));
    }
    if (depth < -1e-3) return depth;
    const cnPiece *X[2] = {P, Q};
    if (dim == 2) {
        for (int w = 0; w < 2; w++)
            for (int e = 0; e < X[w]->nverts; e++) {
                const double *p = X[w]->verts[e], *q = X[w]->verts[(e + 1) % X[w]->nverts];
                double u[3] = {q[1] - p[1], p[0] - q[0], 0}, L = hypot(u[0], u[1]);
                if (L == 0) continue;
                u[0] /= L, u[1] /= L;
                depth = fmin(depth, axis_overlap(P, off, Q, u));
            }
        return depth;
    }
    for (int w = 0; w < 2; w++)
        for (int f = 0; f < X[w]->nfaces; f++)
            depth = fmin(depth, axis_overlap(P, off, Q, X[w]->faces[f].normal));
    double ep[32][3], eq[32][3];
    int np = edge_dirs(P, ep, 32), nq = edge_dirs(Q, eq, 32);
    for (int e = 0; e < np; e++)
        for (int g = 0; g < nq; g++) {
            double u[3];
            cn_cross3(ep[e], eq[g], u);
            if (cn_normalize3(u) < 1e-9) continue;
            depth = fmin(depth, axis_overlap(P, off, Q, u));
        }
    return depth;
}

/* The deepest overlap of the parts flagged in mv, moved by off, with the present parts that
 * stay (negative: the narrowest gap). */
static double worst_depth(const cnAssembly *a, const unsigned char *absent, const unsigned char *mv,
                          const double off[3]) {
    double worst = -INFINITY;
    for (int i = 0; i < a->nparts; i++) {
        if (!mv[i]) continue;
        for (int j = 0; j < a->nparts; j++) {
            if (mv[j] || !cn_assembly_part_present(a, absent, j)) continue;
            for (int p = 0; p < a->parts[i].npieces; p++)
                for (int q = 0; q < a->parts[j].npieces; q++)
                    worst = fmax(worst, piece_depth(a->dim, &a->parts[i].pieces[p], off,
                                                    &a->parts[j].pieces[q]));
        }
    }
    return worst;
}

/* The deepest overlap along a path of translations (legs), each leg sampled at per_leg + 1
 * points; end: where it ends. */
static double path_depth(const cnAssembly *a, const unsigned char *absent, const unsigned char *mv,
                         const double (*legs)[3], int nleg, int per_leg, double end[3]) {
    double at[3] = {0, 0, 0}, worst = -INFINITY;
    for (int l = 0; l < nleg; l++) {
        for (int s = 0; s <= per_leg; s++) {
            double t = (double)s / per_leg, off[3];
            for (int k = 0; k < 3; k++)
                off[k] = at[k] + t * legs[l][k];
            worst = fmax(worst, worst_depth(a, absent, mv, off));
        }
        cn_add3(at, legs[l], at);
    }
    cn_copy3(end, at);
    return worst;
}

/* The flagged parts' extent along unit u. */
static double extent(const cnAssembly *a, const unsigned char *mv, const double u[3]) {
    static const double zero[3] = {0, 0, 0};
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < a->nparts; i++)
        for (int p = 0; mv[i] && p < a->parts[i].npieces; p++) {
            double l, h;
            shadow(&a->parts[i].pieces[p], zero, u, &l, &h);
            lo = fmin(lo, l), hi = fmax(hi, h);
        }
    return hi - lo;
}

/* How far the flagged parts, moved by off, are ahead of every present part that stays along
 * unit u (> 0: nothing lies ahead of them that way). */
static double ahead(const cnAssembly *a, const unsigned char *absent, const unsigned char *mv,
                    const double off[3], const double u[3]) {
    static const double zero[3] = {0, 0, 0};
    double mine = INFINITY, theirs = -INFINITY;
    for (int i = 0; i < a->nparts; i++) {
        if (!mv[i] && !cn_assembly_part_present(a, absent, i)) continue;
        for (int p = 0; p < a->parts[i].npieces; p++) {
            double l, h;
            shadow(&a->parts[i].pieces[p], mv[i] ? off : zero, u, &l, &h);
            if (mv[i])
                mine = fmin(mine, l);
            else
                theirs = fmax(theirs, h);
        }
    }
    return mine - theirs;
}

/* The least normal speed along unit d of the contacts (the library's contact finder) between
 * the flagged parts and the others: positive opens, zero slides, negative presses in (a corner
 * contact by its most opening end); *n: how many contacts. */
static double least_normal_speed(const cnAssembly *a, const unsigned char *absent,
                                 const unsigned char *mv, const double d[3], int *n) {
    cnContactSet cs;
    memset(&cs, 0, sizeof cs);
    cnContactQuery q = cn_contact_query_default();
    q.absent = absent;
    cnDiag dg;
    double least = INFINITY;
    *n = 0;
    CHECK(cn_contacts_find(a, &q, &cs, NULL, &dg) == CN_OK);
    for (int k = 0; k < cs.count; k++) {
        cnContact *c = &cs.items[k];
        bool m1 = c->body1 >= 0 && mv[c->body1], m2 = c->body2 >= 0 && mv[c->body2];
        if (m1 == m2) continue;
        double sgn = m2 ? 1 : -1, v = sgn * cn_dot3(d, c->normal);
        for (int e = 1; c->corner && e < c->corner_ends; e++)
            v = fmax(v, sgn * cn_dot3(d, cn_contact_end(c, e)));
        least = fmin(least, v);
        (*n)++;
    }
    cn_contacts_free(&cs);
    return least;
}

static double up_dot(const cnAssembly *a, const double d[3]) {
    return -cn_dot3(d, a->gravity) / cn_norm3(a->gravity);
}

/* ---- candidates (cands.c) ---- */

typedef struct {
    cnAssembly *a;
    unsigned char *absent, *mv;
    cnCand *c;
    int n;
} Cands;

/* The candidates of the parts named in movers (NULL-terminated) leaving the assembly with every
 * part present. */
static bool cands_of(const char *json, const char *const *movers, bool opening, int auto_dirs,
                     cnPlanSupport sup, Cands *r) {
    memset(r, 0, sizeof *r);
    r->a = load_ok(json);
    if (!r->a) return false;
    r->absent = calloc((size_t)r->a->nparts, 1);
    r->mv = calloc((size_t)r->a->nparts, 1);
    int single = -1, k = 0;
    for (; movers[k]; k++) {
        int i = cn_assembly_find_part(r->a, movers[k]);
        CHECK(i >= 0);
        if (i >= 0) r->mv[i] = 1, single = i;
    }
    if (k != 1) single = -1;
    cnPlanOptions o = cn_plan_options_default();
    o.auto_dirs = auto_dirs;
    o.support = sup;
    cnDiag d;
    cnCandGen G;
    memset(&G, 0, sizeof G);
    G.a = r->a, G.o = &o, G.diag = &d;
    cnStatus s = cn_cands(&G, r->absent, r->mv, single, opening, &r->c, &r->n);
    cn_cands_free(&G);
    CHECK_MSG(s == CN_OK, "cn_cands: %s", d.message);
    return s == CN_OK;
}

static void cands_free(Cands *r) {
    cn_free(r->c);
    free(r->absent);
    free(r->mv);
    cn_assembly_free(r->a);
}

static bool is_route(const cnCand *c) {
    return !strncmp(cn_cand_name(c), "route", 5);
}

/* The unit direction and length of a straight candidate. */
static double straight_dir(const cnCand *c, double d[3]) {
    const cnSegment *s = cn_cand_seg(c);
    double L = cn_norm3(s[0].move);
    for (int k = 0; k < 3; k++)
        d[k] = s[0].move[k] / L;
    return L;
}

/* A straight candidate: one move along a direction that presses into no contact, free of
 * overlap all along (sampled), and clear of every part for the last 0.49 of the moved parts'
 * extent (it clears the parts in its way, then goes on half its extent); named "up" exactly when
 * it points up. */
static void check_straight(const cnAssembly *a, const unsigned char *absent,
                           const unsigned char *mv, const cnCand *c, const char *tag) {
    const cnSegment *s = cn_cand_seg(c);
    const char *nm = cn_cand_name(c);
    CHECK_MSG(c->nseg == 1 && s[0].kind == CN_SEGMENT_MOVE, "%s: %s is not one move", tag, nm);
    if (c->nseg != 1 || s[0].kind != CN_SEGMENT_MOVE) return;
    double d[3], L = straight_dir(c, d), tol = a->contact_tol, end[3];
    int nc;
    double v = least_normal_speed(a, absent, mv, d, &nc);
    CHECK_MSG(nc > 0 && v >= -1e-9,
              "%s: %s presses into a contact (normal speed %g of %d contacts)", tag, nm, v, nc);
    double dep = path_depth(a, absent, mv, (const double(*)[3])s[0].move, 1, 1000, end);
    CHECK_MSG(dep <= 1.01 * tol, "%s: %s runs into a part (depth %g, tolerance %g)", tag, nm, dep,
              tol);
    double ext = extent(a, mv, d), gap = INFINITY;
    for (int k = 0; k <= 20; k++) {
        double t = L - 0.49 * ext * (1 - k / 20.0), off[3] = {t * d[0], t * d[1], t * d[2]};
        gap = fmin(gap, -worst_depth(a, absent, mv, off));
    }
    CHECK_MSG(gap > tol, "%s: %s is not clear over its last half extent (gap %g)", tag, nm, gap);
    bool up = up_dot(a, d) > 1 - 1e-9;
    CHECK_MSG(up == !strcmp(nm, "up"), "%s: %s (direction %g %g %g) is%s up", tag, nm, d[0], d[1],
              d[2], up ? "" : " not");
}

/* A route of translations: free of overlap (sampled; touching allowed), ending clear of every
 * part and ahead of all of them along its last leg (nothing left to meet). Returns its length. */
static double check_route(const cnAssembly *a, const unsigned char *absent, const unsigned char *mv,
                          const double (*legs)[3], int nleg, const char *tag) {
    double tol = a->contact_tol, end[3], len = 0;
    CHECK_MSG(nleg >= 1, "%s: no legs", tag);
    if (nleg < 1) return 0;
    double dep = path_depth(a, absent, mv, legs, nleg, 1000, end);
    CHECK_MSG(dep <= 1.01 * tol, "%s: runs into a part (depth %g, tolerance %g)", tag, dep, tol);
    double gap = -worst_depth(a, absent, mv, end);
    CHECK_MSG(gap > tol, "%s: does not end clear (gap %g)", tag, gap);
    double u[3];
    cn_copy3(u, legs[nleg - 1]);
    cn_normalize3(u);
    double ah = ahead(a, absent, mv, end, u);
    CHECK_MSG(ah > tol, "%s: a part lies ahead of its last leg (%g)", tag, ah);
    for (int l = 0; l < nleg; l++)
        len += cn_norm3(legs[l]);
    return len;
}

/* Every candidate checked as above. */
static void check_all(const Cands *r, const char *tag) {
    for (int i = 0; i < r->n; i++) {
        char t[160];
        snprintf(t, sizeof t, "%s, %s", tag, cn_cand_name(&r->c[i]));
        if (!is_route(&r->c[i])) {
            check_straight(r->a, r->absent, r->mv, &r->c[i], tag);
            continue;
        }
        double legs[CN_ROUTE_MAX_SEGMENTS][3];
        const cnSegment *s = cn_cand_seg(&r->c[i]);
        int ok = r->c[i].nseg <= CN_ROUTE_MAX_SEGMENTS;
        for (int l = 0; ok && l < r->c[i].nseg; l++) {
            ok &= s[l].kind == CN_SEGMENT_MOVE;
            cn_copy3(legs[l], s[l].move);
        }
        CHECK_MSG(ok, "%s: not a route of moves", t);
        if (ok) check_route(r->a, r->absent, r->mv, (const double(*)[3])legs, r->c[i].nseg, t);
    }
}

/* A straight candidate expected: its direction (2-D: degrees; 3-D: a unit vector) and the
 * length that clears the parts in its way plus half the moved parts' extent along it. */
typedef struct {
    double dir[3];
    double len;
} Want;

static Want want2(double deg, double len) {
    Want w = {{cos(deg * CN_PI / 180), sin(deg * CN_PI / 180), 0}, len};
    return w;
}

/* The straight candidates of r are exactly the wanted ones (each once, in any order; with
 * `all`, no others), of the wanted lengths: no shorter, and longer by a few contact tolerances
 * at most. Up comes first when it is wanted. */
static void check_wants(const Cands *r, const Want *w, int nw, bool all, const char *tag) {
    int nstraight = 0, seen[16] = {0};
    for (int i = 0; i < r->n; i++) {
        if (is_route(&r->c[i])) continue;
        nstraight++;
        double d[3], L = straight_dir(&r->c[i], d);
        int hit = -1;
        for (int k = 0; k < nw; k++)
            if (cn_dot3(d, w[k].dir) > 1 - 1e-12) hit = k;
        CHECK_MSG(hit >= 0 || !all, "%s: unexpected direction %g %g %g", tag, d[0], d[1], d[2]);
        if (hit < 0) continue;
        seen[hit]++;
        CHECK_MSG(L >= w[hit].len - 1e-9 && L <= w[hit].len + 20 * r->a->contact_tol,
                  "%s: %s has length %.12g, want %.12g", tag, cn_cand_name(&r->c[i]), L,
                  w[hit].len);
    }
    for (int k = 0; k < nw; k++)
        CHECK_MSG(seen[k] == 1, "%s: direction %g %g %g offered %d times", tag, w[k].dir[0],
                  w[k].dir[1], w[k].dir[2], seen[k]);
    if (all) CHECK_MSG(nstraight == nw, "%s: %d straight candidates, want %d", tag, nstraight, nw);
    for (int k = 0; k < nw; k++)
        if (up_dot(r->a, w[k].dir) > 1 - 1e-12)
            CHECK_MSG(r->n > 0 && !strcmp(cn_cand_name(&r->c[0]), "up"), "%s: up is not first",
                      tag);
}

static int count_routes(const Cands *r) {
    int n = 0;
    for (int i = 0; i < r->n; i++)
        n += is_route(&r->c[i]);
    return n;
}

/* 2-D: the free directions are the middle and ends of the free arcs (hand-derived), each as
 * long as the touching rule says: a part beside the path's start counts until passed. */
static void test_cands_2d(void) {
    static const char *const A[] = {"A", NULL}, *const B[] = {"B", NULL},
                             *const AB[] = {"A", "B", NULL};
    Xf id = xf_id();
    const double r2 = sqrt(2.0);
    struct {
        const char *tag;
        const Box *box;
        int nbox;
        const char *const *mv;
        Want w[3];
        int nw, routes; /* routes: -1 any */
    } sc[] = {
        /* clang-format off */
        /* on the table: up clears it at once; sideways past its end (10 right, 11 left) */
        {"table", TABLE_ONLY, NB(TABLE_ONLY), A,
         {want2(90, 0.5), want2(0, 10.5), want2(180, 11.5)}, 3, 0},
        /* in the slot: up only, past the walls (3) */
        {"slot", SLOT, NB(SLOT), A, {want2(90, 3.5)}, 1, -1},
        /* in the corner [0, 90]: up past the wall it touches (1); 45 deg past the table's far
         * corner along it (10 / sqrt 2) plus half its diagonal; right past the table */
        {"corner", CORNER, NB(CORNER), A,
         {want2(90, 1.5), want2(45, 5.5 * r2), want2(0, 10.5)}, 3, -1},
        /* A under B: sideways only, past the table */
        {"stack A", STACK2, NB(STACK2), A, {want2(0, 10.5), want2(180, 11.5)}, 2, -1},
        /* B on A: up at once, sideways past A (1) */
        {"stack B", STACK2, NB(STACK2), B,
         {want2(90, 0.5), want2(0, 1.5), want2(180, 1.5)}, 3, -1},
        /* A and B as one: half their height 2 up; no routes for a group */
        {"stack AB", STACK2, NB(STACK2), AB,
         {want2(90, 1.0), want2(0, 10.5), want2(180, 11.5)}, 3, 0},
        /* clang-format on */
    };
    for (size_t s = 0; s < sizeof sc / sizeof sc[0]; s++) {
        char *js = scene_json(2, sc[s].box, sc[s].nbox, &id);
        Cands r;
        if (cands_of(js, sc[s].mv, false, 8, CN_PLAN_SUPPORT_FILE, &r)) {
            check_wants(&r, sc[s].w, sc[s].nw, true, sc[s].tag);
            check_all(&r, sc[s].tag);
            if (sc[s].routes >= 0)
                CHECK_MSG(count_routes(&r) == sc[s].routes, "%s: %d routes, want %d", sc[s].tag,
                          count_routes(&r), sc[s].routes);
        }
        cands_free(&r);
        free(js);
    }
}

/* With `opening`, the directions that open every contact of the part (normal speed > 0 against
 * the contact finder's normals) come before those that slide along one: in the corner, only
 * 45 deg opens both the table's and the wall's (hand-derived); without it, up comes first. */
static void test_cands_opening(void) {
    static const char *const A[] = {"A", NULL};
    Xf id = xf_id();
    char *js = scene_json(2, CORNER, NB(CORNER), &id);
    for (int opening = 0; opening <= 1; opening++) {
        Cands r;
        if (cands_of(js, A, opening, 8, CN_PLAN_SUPPORT_FILE, &r)) {
            int nopen = 0, last_open = -1, first_closed = r.n;
            for (int i = 0; i < r.n; i++) {
                if (is_route(&r.c[i])) continue;
                double d[3];
                int nc;
                straight_dir(&r.c[i], d);
                bool opens = least_normal_speed(r.a, r.absent, r.mv, d, &nc) > 1e-6;
                CHECK(nc >= 2); /* the table's and the wall's */
                if (opens)
                    nopen++, last_open = i;
                else if (first_closed == r.n)
                    first_closed = i;
            }
            CHECK_MSG(nopen == 1, "%d opening directions, want 1", nopen);
            if (opening) {
                CHECK_MSG(last_open < first_closed, "an opening direction after a sliding one");
                double d[3] = {0, 0, 0};
                if (r.n > 0) straight_dir(&r.c[0], d);
                CHECK_MSG(r.n > 0 && fabs(d[0] - d[1]) < 1e-12 && d[0] > 0, "45 deg is not first");
            } else {
                CHECK(r.n > 0 && !strcmp(cn_cand_name(&r.c[0]), "up"));
            }
        }
        cands_free(&r);
    }
    free(js);
}

/* Is every move of c along y (gravity in the 2-D scenes)? */
static bool vertical_path(const cnCand *c) {
    const cnSegment *s = cn_cand_seg(c);
    bool vertical = true;
    for (int l = 0; l < c->nseg; l++)
        vertical &= fabs(s[l].move[0]) <= 1e-12 * cn_norm3(s[l].move);
    return vertical;
}

/* Do c and e move the same way (segment by segment)? */
static bool same_path(const cnCand *c, const cnCand *e) {
    if (c->nseg != e->nseg) return false;
    for (int l = 0; l < c->nseg; l++) {
        const cnSegment *x = &cn_cand_seg(c)[l], *y = &cn_cand_seg(e)[l];
        if (x->kind != y->kind || memcmp(x->move, y->move, sizeof x->move)) return false;
    }
    return true;
}

/* With CN_PLAN_SUPPORT_BOTH every candidate that is not along gravity is followed by its pushed
 * twin (verticality judged here); a file's candidates replace the generated ones. */
static void test_cands_support(void) {
    static const char *const A[] = {"A", NULL};
    Xf id = xf_id();
    char *js = scene_json(2, CORNER, NB(CORNER), &id);
    Cands r1, r2;
    bool ok1 = cands_of(js, A, false, 8, CN_PLAN_SUPPORT_FILE, &r1);
    bool ok2 = cands_of(js, A, false, 8, CN_PLAN_SUPPORT_BOTH, &r2);
    if (ok1 && ok2) {
        int want = 0;
        for (int i = 0; i < r1.n; i++)
            want += vertical_path(&r1.c[i]) ? 1 : 2;
        CHECK_MSG(r2.n == want, "%d candidates held and pushed, want %d", r2.n, want);
        for (int i = 0, k = 0; i < r1.n && k < r2.n; i++) {
            const cnCand *c = &r1.c[i];
            bool twin = !vertical_path(c);
            CHECK(r2.c[k].support == CN_SUPPORT_HOLD && same_path(&r2.c[k], c));
            if (twin) {
                CHECK(k + 1 < r2.n && r2.c[k + 1].support == CN_SUPPORT_PUSH &&
                      same_path(&r2.c[k + 1], c));
                /* named by their support */
                CHECK(strstr(cn_cand_name(&r2.c[k]), ", held") != NULL);
                CHECK(k + 1 < r2.n && strstr(cn_cand_name(&r2.c[k + 1]), ", pushed") != NULL);
            }
            k += twin ? 2 : 1;
        }
    }
    cands_free(&r2);
    cands_free(&r1);
    free(js);
    /* the file's candidates of A, and only them */
    const char *fj =
        "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-10,-1],[10,-1],[10,0],[-10,0]]},"
        "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]}],"
        "\"candidates\":{\"A\":{\"I\":[[0,6]],\"II\":{\"path\":[[-8,0],[0,6]],\"support\":\"push\"}"
        "}}}";
    Cands r;
    if (cands_of(fj, A, false, 8, CN_PLAN_SUPPORT_FILE, &r)) {
        CHECK(r.n == 2);
        if (r.n == 2) {
            CHECK(!strcmp(cn_cand_name(&r.c[0]), "I") && r.c[0].nseg == 1 &&
                  r.c[0].support == CN_SUPPORT_HOLD);
            CHECK(!strcmp(cn_cand_name(&r.c[1]), "II") && r.c[1].nseg == 2 &&
                  r.c[1].support == CN_SUPPORT_PUSH);
            CHECK_NEAR(cn_cand_seg(&r.c[1])[0].move[0], -8, 0);
            CHECK_NEAR(cn_cand_seg(&r.c[1])[1].move[1], 6, 0);
        }
    }
    cands_free(&r);
    /* both ways: I (straight up) once, II (sideways, then up) held and pushed */
    if (cands_of(fj, A, false, 8, CN_PLAN_SUPPORT_BOTH, &r)) {
        CHECK(r.n == 3);
        if (r.n == 3)
            CHECK(!strcmp(cn_cand_name(&r.c[0]), "I") && r.c[1].support == CN_SUPPORT_HOLD &&
                  r.c[2].support == CN_SUPPORT_PUSH &&
                  !strcmp(cn_cand_name(&r.c[2]), "II, pushed"));
    }
    cands_free(&r);
}

/* 3-D: free directions hand-derived from the contacts (pocket: up only; channel: the half circle
 * x = 0, z >= 0; B on A: the upper half-sphere; A under B: the horizontal circle), lengths
 * where every part around is in the way whatever the frame across the motion. */
static void test_cands_3d(void) {
    static const char *const A[] = {"A", NULL}, *const B[] = {"B", NULL};
    Xf id = xf_id();
    char *js = scene_json(3, POCKET3, NB(POCKET3), &id);
    Cands r;
    if (cands_of(js, A, false, 8, CN_PLAN_SUPPORT_FILE, &r)) {
        Want w[1] = {{{0, 0, 1}, 2.5}};
        check_wants(&r, w, 1, true, "pocket");
        check_all(&r, "pocket");
    }
    cands_free(&r);
    free(js);
    /* the channel: up past the walls (2); along y past the floor (4 either way) */
    js = scene_json(3, CHANNEL3, NB(CHANNEL3), &id);
    if (cands_of(js, A, false, 8, CN_PLAN_SUPPORT_FILE, &r)) {
        Want w[3] = {{{0, 0, 1}, 2.5}, {{0, 1, 0}, 4.5}, {{0, -1, 0}, 4.5}};
        check_wants(&r, w, 3, false, "channel");
        check_all(&r, "channel");
        for (int i = 0; i < r.n; i++) {
            double d[3];
            if (is_route(&r.c[i])) continue;
            straight_dir(&r.c[i], d);
            CHECK_MSG(fabs(d[0]) < 1e-9 && d[2] > -1e-9, "channel: %s leaves the free half circle",
                      cn_cand_name(&r.c[i]));
        }
    }
    cands_free(&r);
    free(js);
    js = scene_json(3, STACK3, NB(STACK3), &id);
    for (int which = 0; which < 2; which++) {
        if (cands_of(js, which ? B : A, false, 8, CN_PLAN_SUPPORT_FILE, &r)) {
            const char *tag = which ? "stack3 B" : "stack3 A";
            int nstraight = 0;
            for (int i = 0; i < r.n; i++) {
                double d[3];
                if (is_route(&r.c[i])) continue;
                nstraight++;
                straight_dir(&r.c[i], d);
                if (which)
                    CHECK_MSG(d[2] > -1e-9, "%s: %s goes down", tag, cn_cand_name(&r.c[i]));
                else
                    CHECK_MSG(fabs(d[2]) < 1e-9, "%s: %s is not level", tag, cn_cand_name(&r.c[i]));
            }
            CHECK_MSG(nstraight >= (which ? 3 : 2), "%s: %d straight candidates", tag, nstraight);
            if (which) {
                Want w[1] = {{{0, 0, 1}, 0.5}};
                check_wants(&r, w, 1, false, tag);
            }
            check_all(&r, tag);
        }
        cands_free(&r);
    }
    free(js);
}

/* The legs of a path of moves with consecutive legs along one line merged (a route may pass a
 * roadmap node on its way straight on); returns how many. */
static int merged_legs(const cnSegment *s, int nseg, double (*out)[3]) {
    int n = 0;
    for (int l = 0; l < nseg; l++) {
        double c[3];
        if (n > 0) cn_cross3(out[n - 1], s[l].move, c);
        if (n > 0 && cn_norm3(c) <= 1e-9 * cn_norm3(out[n - 1]) * cn_norm3(s[l].move) &&
            cn_dot3(out[n - 1], s[l].move) > 0)
            cn_add3(out[n - 1], s[l].move, out[n - 1]);
        else
            cn_copy3(out[n++], s[l].move);
    }
    return n;
}

/* Does candidate c, moved by x, appear in r: the same kind, its legs (merged) turned along,
 * each of the same direction and of the same length within len_tol? */
static bool has_image(const Cands *r, const cnCand *c, const Xf *x, double len_tol) {
    double lc[CN_ROUTE_MAX_SEGMENTS][3], li[CN_ROUTE_MAX_SEGMENTS][3];
    if (c->nseg > CN_ROUTE_MAX_SEGMENTS) return false;
    int nc = merged_legs(cn_cand_seg(c), c->nseg, lc);
    for (int i = 0; i < r->n; i++) {
        if (is_route(&r->c[i]) != is_route(c) || r->c[i].nseg > CN_ROUTE_MAX_SEGMENTS) continue;
        if (merged_legs(cn_cand_seg(&r->c[i]), r->c[i].nseg, li) != nc) continue;
        bool same = true;
        for (int l = 0; l < nc && same; l++) {
            double m[3];
            xf_dir(x, lc[l], m);
            double a = cn_norm3(m), b = cn_norm3(li[l]);
            same = cn_dot3(m, li[l]) > (1 - 1e-9) * a * b && fabs(a - b) <= len_tol;
        }
        if (same) return true;
    }
    return false;
}

/* Is c a straight candidate along an axis? */
static bool along_axis(const cnCand *c) {
    double d[3];
    if (is_route(c)) return false;
    straight_dir(c, d);
    return fmax(fabs(d[0]), fmax(fabs(d[1]), fabs(d[2]))) > 1 - 1e-12;
}

/* Moving the whole assembly (gravity with it) moves the candidates the same way: a shift (by
 * powers of two: exact) leaves them as they were, a quarter turn turns them. A turn by 30 deg in
 * 2-D turns the straight lines (their lengths change with the contact tolerance, which follows
 * the assembly's bounding box); the routes aim at points on a circle whose radius follows the
 * obstacles' extent along the axes, so only their number is kept. In 3-D a free region's
 * representative direction depends on the frame, so only the lines along axes and the routes
 * are compared. Every moved scene is checked as above too. */
static void test_cands_invariance(void) {
    static const char *const A[] = {"A", NULL}, *const B[] = {"B", NULL};
    struct {
        int dim;
        const Box *box;
        int nbox;
        const char *const *mv;
        const char *tag;
    } sc[] = {{2, CORNER, NB(CORNER), A, "corner"},
              {2, LINTEL2, NB(LINTEL2), A, "lintel"},
              {2, STACK2, NB(STACK2), B, "stack B"},
              {3, CHANNEL3, NB(CHANNEL3), A, "channel"},
              {3, STACK3, NB(STACK3), B, "stack3 B"}};
    Xf id = xf_id();
    for (size_t s = 0; s < sizeof sc / sizeof sc[0]; s++) {
        char *js = scene_json(sc[s].dim, sc[s].box, sc[s].nbox, &id);
        Cands r0;
        if (!cands_of(js, sc[s].mv, false, 8, CN_PLAN_SUPPORT_FILE, &r0)) {
            cands_free(&r0);
            free(js);
            continue;
        }
        free(js);
        Xf xs[3];
        xs[0] = xf_turn_z(0, 4, -2, sc[s].dim == 3 ? 8 : 0);
        xs[1] = sc[s].dim == 2 ? xf_turn_z(90, -2.5, 0.75, 0) : xf_turn_z(90, 0.5, -4, 2);
        xs[2] = sc[s].dim == 2 ? xf_turn_z(30, 3.7, -1.3, 0) : xf_quarter_x();
        for (int k = 0; k < 3; k++) {
            char tag[96];
            snprintf(tag, sizeof tag, "%s, moved %d", sc[s].tag, k);
            js = scene_json(sc[s].dim, sc[s].box, sc[s].nbox, &xs[k]);
            Cands r;
            if (cands_of(js, sc[s].mv, false, 8, CN_PLAN_SUPPORT_FILE, &r)) {
                CHECK_MSG(r.n == r0.n, "%s: %d candidates, %d unmoved", tag, r.n, r0.n);
                CHECK_MSG(count_routes(&r) == count_routes(&r0), "%s: %d routes, %d unmoved", tag,
                          count_routes(&r), count_routes(&r0));
                bool tilted = sc[s].dim == 2 && k == 2;
                double len_tol = tilted ? 20 * fmax(r.a->contact_tol, r0.a->contact_tol) : 1e-9;
                int want = 0, found = 0;
                for (int i = 0; i < r0.n; i++) {
                    const cnCand *c = &r0.c[i];
                    if (tilted ? is_route(c) : sc[s].dim == 3 && !is_route(c) && !along_axis(c))
                        continue;
                    want++;
                    bool hit = has_image(&r, c, &xs[k], len_tol);
                    found += hit;
                    CHECK_MSG(hit, "%s: %s is not moved along", tag, cn_cand_name(c));
                }
                if (!tilted || count_routes(&r0) < r0.n)
                    CHECK_MSG(want >= 2, "%s: %d candidates compared", tag, want);
                check_all(&r, tag);
            }
            cands_free(&r);
            free(js);
        }
        cands_free(&r0);
    }
}

/* ---- routes (paths2.c, paths3.c) ---- */

typedef struct {
    cnAssembly *a;
    unsigned char *absent, *mv;
    double segs[4][CN_ROUTE_MAX_SEGMENTS][3];
    int nseg[4], n;
} Routes;

static bool routes_of(int dim, const Box *b, int nb, const Xf *x, Routes *r) {
    memset(r, 0, sizeof *r);
    char *js = scene_json(dim, b, nb, x);
    r->a = load_ok(js);
    free(js);
    if (!r->a) return false;
    r->absent = calloc((size_t)r->a->nparts, 1);
    r->mv = calloc((size_t)r->a->nparts, 1);
    r->mv[cn_assembly_find_part(r->a, "A")] = 1;
    cnDiag d;
    cnStatus s = dim == 2 ? cn_paths2(r->a, r->absent, r->mv, 4, r->segs, r->nseg, &r->n, &d)
                          : cn_paths3(r->a, r->absent, r->mv, 4, r->segs, r->nseg, &r->n, &d);
    CHECK(s == CN_OK);
    return s == CN_OK;
}

static void routes_free(Routes *r) {
    free(r->absent);
    free(r->mv);
    cn_assembly_free(r->a);
}

static double route_len(const Routes *r, int k) {
    double len = 0;
    for (int l = 0; l < r->nseg[k]; l++)
        len += cn_norm3(r->segs[k][l]);
    return len;
}

/* The lintel (2-D and 3-D): the block is held between the table (floor) and the lintel (slab)
 * until it has slid 1.5 along +x, and must then rise 3 to pass the walls, so every way out is at
 * least 4.5 long, and 4.5 is reached (right 1.5, up 3): hand-derived. Every route: first leg
 * exactly (1.5, 0, 0) (no other leg from the start stays out of the parts), overlap-free when
 * sampled, ending clear and ahead of every part along its last leg, and no shorter than 4.5.
 * The first route (the planner's first choice) is at most 1.5 times 4.5 and the shortest one
 * within 10% of it: a route runs towards a goal direction on a fixed grid and on past every
 * part that way, so it may overshoot, but not by much when "up" or a near goal is among them.
 * Distinct routes leave by distinct last corners; no route twice, no node passed straight
 * through. */
static void check_lintel(const Routes *r, const char *tag) {
    const double shortest = 4.5;
    double best = INFINITY;
    CHECK_MSG(r->n >= 1, "%s: no route", tag);
    for (int k = 0; k < r->n; k++) {
        char t[96];
        snprintf(t, sizeof t, "%s, route %d", tag, k + 1);
        CHECK_MSG(r->nseg[k] >= 2, "%s: %d legs", t, r->nseg[k]);
        const double *l0 = r->segs[k][0];
        CHECK_MSG(fabs(l0[0] - 1.5) < 1e-9 && fabs(l0[1]) < 1e-9 && fabs(l0[2]) < 1e-9,
                  "%s: first leg %g %g %g, want 1.5 0 0", t, l0[0], l0[1], l0[2]);
        double len =
            check_route(r->a, r->absent, r->mv, (const double(*)[3])r->segs[k], r->nseg[k], t);
        CHECK_MSG(len >= shortest - 1e-9, "%s: length %g, shorter than the way out %g", t, len,
                  shortest);
        if (k == 0)
            CHECK_MSG(len <= 1.5 * shortest, "%s: length %g, shortest way out %g", t, len,
                      shortest);
        best = fmin(best, len);
        /* no node passed straight through (two legs one way), and no route twice */
        for (int l = 0; l + 1 < r->nseg[k]; l++) {
            double c3[3];
            cn_cross3(r->segs[k][l], r->segs[k][l + 1], c3);
            CHECK_MSG(cn_norm3(c3) > 1e-9 * cn_norm3(r->segs[k][l]) * cn_norm3(r->segs[k][l + 1]) ||
                          cn_dot3(r->segs[k][l], r->segs[k][l + 1]) < 0,
                      "%s: legs %d and %d go one way", t, l + 1, l + 2);
        }
        for (int j = 0; j < k; j++) {
            bool same = r->nseg[j] == r->nseg[k];
            for (int l = 0; same && l < r->nseg[k]; l++) {
                double d[3];
                cn_sub3(r->segs[j][l], r->segs[k][l], d);
                same = cn_norm3(d) <= 1e-9;
            }
            CHECK_MSG(!same, "%s: the same as route %d", t, j + 1);
        }
        /* the corner it leaves by */
        double c[3] = {0, 0, 0};
        for (int l = 0; l + 1 < r->nseg[k]; l++)
            cn_add3(c, r->segs[k][l], c);
        for (int j = 0; j < k; j++) {
            double cj[3] = {0, 0, 0}, diff[3];
            for (int l = 0; l + 1 < r->nseg[j]; l++)
                cn_add3(cj, r->segs[j][l], cj);
            cn_sub3(c, cj, diff);
            CHECK_MSG(cn_norm3(diff) > 1e-9, "%s: leaves by the corner of route %d", t, j + 1);
        }
    }
    CHECK_MSG(best <= 1.1 * shortest, "%s: shortest route %g, shortest way out %g", tag, best,
              shortest);
}

static void test_paths2(void) {
    Xf id = xf_id();
    Routes r;
    if (routes_of(2, LINTEL2, NB(LINTEL2), &id, &r)) check_lintel(&r, "lintel");
    /* a shift (exact) leaves the routes as they were; a quarter turn turns them */
    Xf xs[2] = {xf_turn_z(0, 4, -2, 0), xf_turn_z(90, 0.5, 1, 0)};
    for (int k = 0; k < 2; k++) {
        Routes m;
        char tag[64];
        snprintf(tag, sizeof tag, "lintel moved %d", k);
        if (routes_of(2, LINTEL2, NB(LINTEL2), &xs[k], &m)) {
            CHECK_MSG(m.n == r.n, "%s: %d routes, %d unmoved", tag, m.n, r.n);
            for (int p = 0; p < m.n && p < r.n; p++) {
                bool same = m.nseg[p] == r.nseg[p];
                for (int l = 0; same && l < r.nseg[p]; l++) {
                    double img[3], diff[3];
                    xf_dir(&xs[k], r.segs[p][l], img);
                    cn_sub3(img, m.segs[p][l], diff);
                    same = cn_norm3(diff) < 1e-9;
                }
                CHECK_MSG(same, "%s: route %d is not the unmoved one moved", tag, p + 1);
            }
        }
        routes_free(&m);
    }
    routes_free(&r);
    /* on the open table every goal is in sight of the start: straight lines, no route; closed
     * all round: nothing */
    if (routes_of(2, TABLE_ONLY, NB(TABLE_ONLY), &id, &r))
        CHECK_MSG(r.n == 0, "table: %d routes", r.n);
    routes_free(&r);
    if (routes_of(2, BOXED2, NB(BOXED2), &id, &r)) CHECK_MSG(r.n == 0, "boxed: %d routes", r.n);
    routes_free(&r);
}

static void test_paths3(void) {
    Xf id = xf_id();
    Routes r;
    if (routes_of(3, LINTEL3, NB(LINTEL3), &id, &r)) check_lintel(&r, "lintel3");
    /* moved: the same lengths, shortest first (a quarter turn about up keeps the goal
     * directions' ring) */
    Xf xs[2] = {xf_turn_z(0, 4, -2, 8), xf_turn_z(90, 0, 0, 0)};
    for (int k = 0; k < 2; k++) {
        Routes m;
        if (routes_of(3, LINTEL3, NB(LINTEL3), &xs[k], &m)) {
            CHECK_MSG(m.n == r.n, "lintel3 moved %d: %d routes, %d unmoved", k, m.n, r.n);
            for (int p = 0; p < m.n && p < r.n; p++)
                CHECK_MSG(fabs(route_len(&m, p) - route_len(&r, p)) < 1e-9,
                          "lintel3 moved %d: route %d %g, unmoved %g", k, p + 1, route_len(&m, p),
                          route_len(&r, p));
            if (m.n >= 1) {
                double img[3], diff[3];
                xf_dir(&xs[k], r.segs[0][0], img);
                cn_sub3(img, m.segs[0][0], diff);
                CHECK_MSG(cn_norm3(diff) < 1e-9,
                          "lintel3 moved %d: the first leg is not turned along", k);
            }
        }
        routes_free(&m);
    }
    routes_free(&r);
    /* through the candidates: no straight line leaves, the routes do */
    static const char *const A[] = {"A", NULL};
    char *js = scene_json(3, LINTEL3, NB(LINTEL3), &id);
    Cands c;
    if (cands_of(js, A, false, 4, CN_PLAN_SUPPORT_FILE, &c)) {
        CHECK_MSG(c.n >= 1 && count_routes(&c) == c.n, "lintel3: %d candidates, %d routes", c.n,
                  count_routes(&c));
        check_all(&c, "lintel3 candidates");
    }
    cands_free(&c);
    free(js);
    js = scene_json(2, LINTEL2, NB(LINTEL2), &id);
    if (cands_of(js, A, false, 4, CN_PLAN_SUPPORT_FILE, &c)) {
        CHECK_MSG(c.n >= 1 && count_routes(&c) == c.n, "lintel: %d candidates, %d routes", c.n,
                  count_routes(&c));
        check_all(&c, "lintel candidates");
    }
    cands_free(&c);
    free(js);
}

void test_plan_paths(void) {
    test_cands_2d();
    test_cands_opening();
    test_cands_support();
    test_cands_3d();
    test_cands_invariance();
    test_paths2();
    test_paths3();
}
