/* Contact detection: broad phase (sort and sweep on x over part bounding boxes), narrow phase per
 * pair of convex pieces (contact2.c, contact3.c), merging of duplicate points where pieces of a
 * non-convex part meet, fixels, and deterministic numbering. */
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "collide.h"

cnContactQuery cn_contact_query_default(void) {
    cnContactQuery q = {NULL, NULL, NULL};
    return q;
}

void cn_contacts_free(cnContactSet *s) {
    if (!s) return;
    cn_free(s->items);
    s->items = NULL;
    s->count = s->capacity = 0;
}

static int push_contact(cnContactSet *s, const cnContact *c) {
    if (s->count == s->capacity) {
        int nc = s->capacity ? 2 * s->capacity : 64;
        cnContact *ni = cn_realloc(s->items, sizeof(cnContact) * (size_t)nc);
        if (!ni) return -1;
        s->items = ni;
        s->capacity = nc;
    }
    s->items[s->count++] = *c;
    return 0;
}

int cn_manifold_push(cnManifold *m, const double p[3]) {
    if (m->n == m->cap) {
        int nc = m->cap ? 2 * m->cap : 16;
        double(*np)[3] = cn_realloc(m->pts, sizeof(double[3]) * (size_t)nc);
        if (!np) return -1;
        m->pts = np;
        m->cap = nc;
    }
    cn_copy3(m->pts[m->n++], p);
    return 0;
}

typedef struct {
    int part;
    double lo;
} SweepItem;

static int cmp_sweep(const void *a, const void *b) {
    const SweepItem *x = a, *y = b;
    if (x->lo != y->lo) return (x->lo > y->lo) - (x->lo < y->lo);
    return x->part - y->part;
}

typedef struct {
    int i, j;
} Pair;

static int cmp_pair(const void *a, const void *b) {
    const Pair *x = a, *y = b;
    if (x->i != y->i) return x->i - y->i;
    return x->j - y->j;
}

/* Where one part is for this query: its pieces as loaded with a translation the narrow phase
 * adds (`o`), or, for a part that is turned, copies of its pieces posed in world coordinates
 * (then `o` is zero). A translated part is thus placed exactly as before poses existed. */
typedef struct {
    const cnPiece *pieces;
    cnPiece *own;      /* posed copies (NULL: the part's own pieces, translated by o) */
    int npieces;
    double o[3];
    double lo[3], hi[3]; /* the placed part's bounding box */
} Placed;

/* Posed copy of a piece: vertices and face planes moved; face loops and edges shared with the
 * original (read only). */
static int pose_piece(const cnPiece *src, const cnPose *ps, int dim, cnPiece *out) {
    *out = *src;
    out->verts = cn_malloc(sizeof(double[3]) * (size_t)(src->nverts + 1));
    out->faces = src->nfaces ? cn_malloc(sizeof(cnFace) * (size_t)src->nfaces) : NULL;
    if (!out->verts || (src->nfaces && !out->faces)) {
        cn_free(out->verts);
        cn_free(out->faces);
        out->verts = NULL, out->faces = NULL;
        return -1;
    }
    for (int v = 0; v < src->nverts; v++) {
        cn_pose_apply(ps, src->verts[v], out->verts[v]);
        if (dim == 2) out->verts[v][2] = 0;
    }
    for (int f = 0; f < src->nfaces; f++) {
        out->faces[f] = src->faces[f];
        cn_pose_rotate(ps, src->faces[f].normal, out->faces[f].normal);
        out->faces[f].offset = src->faces[f].offset + cn_dot3(out->faces[f].normal, ps->t);
    }
    cn_piece_bounds(out, dim);
    return 0;
}

static void placed_free(Placed *pl, int n) {
    if (!pl) return;
    for (int i = 0; i < n; i++)
        if (pl[i].own) {
            for (int k = 0; k < pl[i].npieces; k++) cn_free(pl[i].own[k].verts), cn_free(pl[i].own[k].faces);
            cn_free(pl[i].own);
        }
    cn_free(pl);
}

/* Place every part present. NULL on allocation failure. */
static Placed *place_parts(const cnAssembly *a, const cnContactQuery *q) {
    int n = a->nparts;
    Placed *pl = cn_calloc((size_t)n + 1, sizeof(Placed));
    if (!pl) return NULL;
    for (int i = 0; i < n; i++) {
        const cnPart *P = &a->parts[i];
        Placed *x = &pl[i];
        x->pieces = P->pieces;
        x->npieces = P->npieces;
        const cnPose *ps = (q && q->pose) ? &q->pose[i] : NULL;
        if (!ps || cn_pose_is_translation(ps) || !cn_part_present(a, q, i)) {
            if (ps) cn_copy3(x->o, ps->t);
            for (int k = 0; k < 3; k++) x->lo[k] = P->lo[k] + x->o[k], x->hi[k] = P->hi[k] + x->o[k];
            continue;
        }
        x->own = cn_calloc((size_t)P->npieces + 1, sizeof(cnPiece));
        if (!x->own) goto oom;
        for (int k = 0; k < 3; k++) x->lo[k] = INFINITY, x->hi[k] = -INFINITY;
        for (int k = 0; k < P->npieces; k++) {
            if (pose_piece(&P->pieces[k], ps, a->dim, &x->own[k]) < 0) goto oom;
            for (int d = 0; d < 3; d++)
                x->lo[d] = fmin(x->lo[d], x->own[k].lo[d]), x->hi[d] = fmax(x->hi[d], x->own[k].hi[d]);
        }
        x->pieces = x->own;
    }
    return pl;
oom:
    placed_free(pl, n);
    return NULL;
}

/* The number of a vertex of piece `piece` of part `part` (placed as pl) at x, or 0. */
static int vertex_at(const cnAssembly *a, int part, int piece, const Placed *pl, const double x[3],
                     double tol) {
    const cnPart *p = &a->parts[part];
    int base = p->vertex_base;
    const cnPiece *pc = &pl->pieces[piece];
    if (!pc->vnum) /* numbered in turn over the pieces; else on the part's outline */
        for (int s = 0; s < piece; s++) base += p->pieces[s].nverts;
    for (int v = 0; v < pc->nverts; v++) {
        double d[3];
        for (int k = 0; k < 3; k++) d[k] = pc->verts[v][k] + pl->o[k] - x[k];
        if (cn_norm3(d) <= tol) return base + (pc->vnum ? pc->vnum[v] : v) + 1;
    }
    return 0;
}

/* The contact tolerance of a pair of parts: rel_tol of the smaller part's size (its bounding
 * box diagonal as loaded), so that a part 1e-4 across beside one 1e4 across is judged at its own
 * scale (the assembly's tolerance would be larger than the small part). Never below what the
 * coordinates can resolve: 64 ulps of the largest coordinate of the two placed boxes. Rigid
 * motions and scaling of the whole assembly leave it unchanged relative to the parts. */
static double pair_tol(const cnAssembly *a, int i, int j, const Placed *P, const Placed *Q) {
    double dp[3], dq[3], mag = 0;
    cn_sub3(a->parts[i].hi, a->parts[i].lo, dp);
    cn_sub3(a->parts[j].hi, a->parts[j].lo, dq);
    for (int k = 0; k < 3; k++)
        mag = fmax(mag, fmax(fmax(fabs(P->lo[k]), fabs(P->hi[k])), fmax(fabs(Q->lo[k]), fabs(Q->hi[k]))));
    double t = a->rel_tol * fmin(cn_norm3(dp), cn_norm3(dq));
    return fmin(a->contact_tol, fmax(t, 64 * DBL_EPSILON * mag));
}

double cn_pair_tolerance(const cnAssembly *a, int i, int j) {
    Placed P, Q;
    memset(&P, 0, sizeof P);
    memset(&Q, 0, sizeof Q);
    cn_copy3(P.lo, a->parts[i].lo), cn_copy3(P.hi, a->parts[i].hi);
    cn_copy3(Q.lo, a->parts[j].lo), cn_copy3(Q.hi, a->parts[j].hi);
    return pair_tol(a, i, j, &P, &Q);
}

/* The narrow phase of each pair of shape kinds (P's kind, Q's kind). A new kind of piece adds a
 * row and a column here; a pair without a routine cannot meet (an assembly is 2-D or 3-D). */
typedef int (*NarrowFn)(const cnPiece *P, const double oP[3], const cnPiece *Q, const double oQ[3],
                        const double vrel[3], double tol, cnManifold *m);
static const NarrowFn NARROW[CN_SHAPE_COUNT][CN_SHAPE_COUNT] = {
    [CN_SHAPE_POLYGON][CN_SHAPE_POLYGON] = cn_contact2_pieces,
    [CN_SHAPE_POLYHEDRON][CN_SHAPE_POLYHEDRON] = cn_contact3_pieces,
};

static int narrow_phase(const cnPiece *P, const double oP[3], const cnPiece *Q, const double oQ[3],
                        const double vrel[3], double tol, cnManifold *m) {
    NarrowFn fn = ((unsigned)P->shape < CN_SHAPE_COUNT && (unsigned)Q->shape < CN_SHAPE_COUNT)
                      ? NARROW[P->shape][Q->shape] : NULL;
    return fn ? fn(P, oP, Q, oQ, vrel, tol, m) : CN_PAIR_APART;
}

/* Velocity of Q relative to P, for tie-breaking between separating axes: at the middle of the
 * region where their boxes meet. */
static void relative_velocity(const cnContactQuery *q, int i, int j, const Placed *pi,
                              const Placed *pj, double vrel[3]) {
    vrel[0] = vrel[1] = vrel[2] = 0;
    if (!q || !q->twist) return;
    double x[3], vi[3], vj[3];
    for (int k = 0; k < 3; k++) x[k] = 0.5 * (fmax(pi->lo[k], pj->lo[k]) + fmin(pi->hi[k], pj->hi[k]));
    cn_twist_at(&q->twist[i], x, vi);
    cn_twist_at(&q->twist[j], x, vj);
    cn_sub3(vj, vi, vrel);
}

void cn_corner_cone(const double vrel[3], const double (*ends)[3], int n, cnManifold *m) {
    /* the gap grows at the largest of the ends' normal speeds: when the motion opens an end the
     * contact opens (that end is its normal, and it leaves the problem); the ends it closes are
     * no contact; when it closes every end the pieces collide */
    double vtol = CN_TOL_NOISE * (cn_norm3(vrel) + 1e-300);
    int open = -1, keep[CN_CORNER_ENDS], nk = 0;
    double vmax = vtol;
    for (int i = 0; i < n; i++) {
        double d = cn_dot3(vrel, ends[i]);
        if (d > vmax) vmax = d, open = i;
    }
    if (open >= 0) {
        cn_copy3(m->normal, ends[open]);
        return;
    }
    for (int i = 0; i < n; i++)
        if (!(cn_dot3(vrel, ends[i]) < -vtol)) {
            if (nk < CN_CORNER_ENDS) keep[nk++] = i;
            else m->wide = true;
        }
    if (nk == 0) return; /* closing every way: a collision */
    cn_copy3(m->normal, ends[keep[0]]);
    for (int i = 1; i < nk; i++) cn_copy3(m->alt[i - 1], ends[keep[i]]);
    m->corner = nk - 1;
}

void cn_corner_ends(const double vrel[3], const double a[3], const double b[3], bool a_near,
                    cnManifold *m) {
    /* the end the motion opens more (a on a tie) is the normal */
    double vtol = CN_TOL_NOISE * (cn_norm3(vrel) + 1e-300);
    double da = cn_dot3(vrel, a), db = cn_dot3(vrel, b);
    if (fmax(da, db) > vtol) {
        cn_copy3(m->normal, da >= db ? a : b);
        return;
    }
    double ends[2][3];
    cn_copy3(ends[0], a_near ? a : b);
    cn_copy3(ends[1], a_near ? b : a);
    cn_corner_cone(vrel, (const double(*)[3])ends, 2, m);
}

/* Normals within this angle (radians) are one (a cosine of 1 - 1e-9). */
#define SAME_NORMAL_ANGLE 4.47e-5

/* A 2-D cone of normals as an arc of angles [lo, hi] (hi - lo < pi): one normal, or a corner's
 * two ends. */
static void arc_of(const double n[3], const double *alt, double *lo, double *hi) {
    double a = atan2(n[1], n[0]);
    double d = alt ? atan2(alt[1], alt[0]) - a : 0;
    while (d > CN_PI) d -= 2 * CN_PI;
    while (d <= -CN_PI) d += 2 * CN_PI;
    *lo = d >= 0 ? a : a + d;
    *hi = d >= 0 ? a + d : a;
}

/* Merge a new point with normal cone (n, alt) into contact e at the same place, between the same
 * parts but other pieces: the parts are the unions of their pieces, so both constraints hold,
 * and at a point their cones of normals meet in the part's own: the intersection (a corner where
 * two pieces of a part meet touches as the part does there: a flat face split into pieces is
 * one normal; a corner split into pieces is the part's corner, without the seams' normals).
 * 0 when the cones do not meet (both are kept: each piece's constraint on its own). */
static bool merge2(cnContact *e, const double n[3], const double *alt) {
    double l1, h1, l2, h2;
    arc_of(e->normal, e->corner ? e->alt_normal : NULL, &l1, &h1);
    arc_of(n, alt, &l2, &h2);
    double c1 = 0.5 * (l1 + h1), c2 = 0.5 * (l2 + h2);
    while (c2 - c1 > CN_PI) l2 -= 2 * CN_PI, h2 -= 2 * CN_PI, c2 -= 2 * CN_PI;
    while (c1 - c2 > CN_PI) l2 += 2 * CN_PI, h2 += 2 * CN_PI, c2 += 2 * CN_PI;
    double lo = fmax(l1, l2), hi = fmin(h1, h2);
    if (lo > hi + SAME_NORMAL_ANGLE) return false;
    if (hi - lo <= CN_TOL_CORNER_CONE) {
        double mid = 0.5 * (lo + fmax(lo, hi));
        if (!e->corner && fabs(mid - c1) <= SAME_NORMAL_ANGLE) return true; /* as it was */
        e->normal[0] = cos(mid), e->normal[1] = sin(mid), e->normal[2] = 0;
        e->corner = false;
        e->corner_ends = 0;
        return true;
    }
    /* still a corner: the end nearer its first normal shown */
    double a = atan2(e->normal[1], e->normal[0]), da = remainder(lo - a, 2 * CN_PI), db = remainder(hi - a, 2 * CN_PI);
    double first = fabs(da) <= fabs(db) ? lo : hi, second = first == lo ? hi : lo;
    e->normal[0] = cos(first), e->normal[1] = sin(first), e->normal[2] = 0;
    e->alt_normal[0] = cos(second), e->alt_normal[1] = sin(second), e->alt_normal[2] = 0;
    e->corner = true;
    e->corner_ends = 2;
    return true;
}

static int pair_contacts(const cnAssembly *a, const cnContactQuery *q, const Placed *pl, int i,
                         int j, cnContactSet *out, cnOverlap *ov, cnManifold *m) {
    const Placed *P = &pl[i], *Q = &pl[j];
    const double *oP = P->o, *oQ = Q->o;
    double tol = pair_tol(a, i, j, P, Q);
    double vrel[3]; /* velocity of Q relative to P */
    relative_velocity(q, i, j, P, Q, vrel);
    int first = out->count;
    for (int pi = 0; pi < P->npieces; pi++) {
        const cnPiece *pp = &P->pieces[pi];
        for (int qi = 0; qi < Q->npieces; qi++) {
            const cnPiece *qp = &Q->pieces[qi];
            int apart = 0;
            for (int k = 0; k < a->dim; k++)
                if (pp->lo[k] + oP[k] > qp->hi[k] + oQ[k] + tol ||
                    qp->lo[k] + oQ[k] > pp->hi[k] + oP[k] + tol)
                    apart = 1;
            if (apart) continue;
            m->corner = 0;
            m->wide = false;
            int r = narrow_phase(pp, oP, qp, oQ, vrel, tol, m);
            if (r < 0) return -1;
            if (r == CN_PAIR_OVERLAP) {
                double depth = -m->gap;
                if (!ov->found || depth > ov->depth) {
                    ov->found = 1;
                    ov->part1 = i;
                    ov->part2 = j;
                    ov->depth = depth;
                    ov->tol = tol;
                }
                continue;
            }
            if (r != CN_PAIR_TOUCH) continue;
            cnContactKind kind = m->n >= 3 ? CN_CONTACT_FACE
                                 : m->n == 2 ? CN_CONTACT_EDGE
                                             : CN_CONTACT_VERTEX;
            for (int k = 0; k < m->n; k++) {
                /* merge with an existing point of this pair at the same place: in 3-D when the
                 * normal is the same, in 2-D when the cones of normals meet (merge2) */
                int dup = 0;
                for (int c = first; c < out->count && !dup; c++) {
                    cnContact *e = &out->items[c];
                    double d[3];
                    cn_sub3(e->point, m->pts[k], d);
                    if (cn_norm3(d) > tol) continue;
                    if (a->dim == 2) dup = merge2(e, m->normal, m->corner ? m->alt[0] : NULL);
                    else dup = cn_dot3(e->normal, m->normal) > 1 - 1e-9;
                }
                if (dup) continue;
                cnContact c = {0};
                c.body1 = i;
                c.body2 = j;
                c.piece1 = pi;
                c.piece2 = qi;
                c.fixel = -1;
                c.kind = kind;
                cn_copy3(c.point, m->pts[k]);
                cn_copy3(c.normal, m->normal);
                if (m->corner) {
                    c.corner = true;
                    c.corner_wide = m->wide;
                    c.corner_ends = m->corner + 1;
                    cn_copy3(c.alt_normal, m->alt[0]);
                    for (int e = 1; e < m->corner; e++) cn_copy3(c.more_normals[e - 1], m->alt[e]);
                }
                c.gap = m->gap;
                c.vertex = vertex_at(a, j, qi, Q, m->pts[k], tol);
                if (!c.vertex) c.vertex = vertex_at(a, i, pi, P, m->pts[k], tol);
                if (push_contact(out, &c) < 0) return -1;
            }
        }
    }
    return 0;
}

cnStatus cn_contacts_find(const cnAssembly *a, const cnContactQuery *q, cnContactSet *out,
                          cnOverlap *overlap, cnDiag *diag) {
    out->count = 0;
    cnOverlap local;
    cnOverlap *ov = overlap ? overlap : &local;
    memset(ov, 0, sizeof *ov);
    int n = a->nparts;
    double tol = a->contact_tol;
    SweepItem *items = cn_malloc(sizeof(SweepItem) * (size_t)(n + 1));
    int npairs = 0, cappairs = 4 * n + 16;
    Pair *pairs = cn_malloc(sizeof(Pair) * (size_t)cappairs);
    cnManifold m;
    memset(&m, 0, sizeof m);
    cnStatus st = CN_OK;
    Placed *pl = place_parts(a, q);
    if (!items || !pairs || !pl) goto oom;

    int ni = 0;
    for (int i = 0; i < n; i++)
        if (cn_part_present(a, q, i)) {
            items[ni].part = i;
            items[ni].lo = pl[i].lo[0];
            ni++;
        }
    qsort(items, (size_t)ni, sizeof(SweepItem), cmp_sweep);
    for (int s = 0; s < ni; s++) {
        int i = items[s].part;
        double hi_x = pl[i].hi[0] + tol;
        for (int t = s + 1; t < ni && items[t].lo <= hi_x; t++) {
            int j = items[t].part;
            if (a->parts[i].fixed && a->parts[j].fixed) continue;
            /* a gripper touches only the parts its step moves (the paper ignores collisions of
             * the gripper with the rest of the assembly) */
            if (a->parts[i].gripper_step >= 0 && !cn_plan_moves(a, a->parts[i].gripper_step, j))
                continue;
            if (a->parts[j].gripper_step >= 0 && !cn_plan_moves(a, a->parts[j].gripper_step, i))
                continue;
            int apart = 0;
            for (int k = 1; k < a->dim; k++)
                if (pl[i].lo[k] > pl[j].hi[k] + tol || pl[j].lo[k] > pl[i].hi[k] + tol) apart = 1;
            if (apart) continue;
            if (npairs == cappairs) {
                cappairs *= 2;
                Pair *np = cn_realloc(pairs, sizeof(Pair) * (size_t)cappairs);
                if (!np) goto oom;
                pairs = np;
            }
            pairs[npairs].i = i < j ? i : j;
            pairs[npairs].j = i < j ? j : i;
            npairs++;
        }
    }
    qsort(pairs, (size_t)npairs, sizeof(Pair), cmp_pair);
    for (int p = 0; p < npairs; p++)
        if (pair_contacts(a, q, pl, pairs[p].i, pairs[p].j, out, ov, &m) < 0) goto oom;
    for (int f = 0; f < a->nfixels; f++) {
        const cnFixel *fx = &a->fixels[f];
        if (!cn_part_present(a, q, fx->part)) continue;
        cnContact c = {0};
        c.body1 = CN_WORLD;
        c.body2 = fx->part;
        c.piece1 = c.piece2 = -1;
        c.fixel = f;
        c.kind = CN_CONTACT_FIXEL;
        if (q && q->pose) {
            cn_pose_apply(&q->pose[fx->part], fx->point, c.point);
            cn_pose_rotate(&q->pose[fx->part], fx->normal, c.normal);
        } else {
            cn_copy3(c.point, fx->point);
            cn_copy3(c.normal, fx->normal);
        }
        if (push_contact(out, &c) < 0) goto oom;
    }
    for (int c = 0; c < out->count; c++) out->items[c].id = c + 1;
    goto done;
oom:
    st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory finding contacts");
done:
    cn_free(items);
    cn_free(pairs);
    cn_free(m.pts);
    placed_free(pl, n);
    return st;
}

/* The gap between two convex pieces along unit axis u (either way round; <= 0: u does not
 * separate them). */
static double axis_gap(const cnPiece *P, const cnPiece *Q, const double u[3]) {
    double pl = INFINITY, ph = -INFINITY, ql = INFINITY, qh = -INFINITY;
    for (int v = 0; v < P->nverts; v++) {
        double d = cn_dot3(u, P->verts[v]);
        pl = fmin(pl, d), ph = fmax(ph, d);
    }
    for (int v = 0; v < Q->nverts; v++) {
        double d = cn_dot3(u, Q->verts[v]);
        ql = fmin(ql, d), qh = fmax(qh, d);
    }
    return fmax(ql - ph, pl - qh);
}

/* A lower bound of the distance between two convex pieces: the widest gap along their face (in
 * 2-D edge) normals, exact when the nearest features are parallel faces. */
static double piece_gap(const cnPiece *P, const cnPiece *Q, int dim) {
    double best = -INFINITY;
    for (int side = 0; side < 2; side++) {
        const cnPiece *S = side ? Q : P;
        int n = dim == 2 ? S->nverts : S->nfaces;
        for (int k = 0; k < n; k++) {
            double u[3] = {0, 0, 0};
            if (dim == 2) {
                const double *a = S->verts[k], *b = S->verts[(k + 1) % S->nverts];
                double len = hypot(b[0] - a[0], b[1] - a[1]);
                if (!(len > 0)) continue;
                u[0] = (b[1] - a[1]) / len, u[1] = (a[0] - b[0]) / len;
            } else {
                cn_copy3(u, S->faces[k].normal);
            }
            best = fmax(best, axis_gap(P, Q, u));
        }
    }
    return best;
}

int cn_part_nearest(const cnAssembly *a, int i, double *gap) {
    int near = -1;
    double best = INFINITY;
    const cnPart *P = &a->parts[i];
    for (int j = 0; j < a->nparts; j++) {
        if (j == i || !cn_part_present(a, NULL, j)) continue;
        const cnPart *Q = &a->parts[j];
        double box = 0; /* the boxes' distance: no piece pair is nearer */
        for (int k = 0; k < 3; k++) {
            double d = fmax(Q->lo[k] - P->hi[k], P->lo[k] - Q->hi[k]);
            if (d > 0) box += d * d;
        }
        if (near >= 0 && sqrt(box) >= best) continue;
        double g = INFINITY; /* the nearest pair of pieces */
        for (int p = 0; p < P->npieces; p++)
            for (int q = 0; q < Q->npieces; q++) g = fmin(g, piece_gap(&P->pieces[p], &Q->pieces[q], a->dim));
        g = fmax(g, sqrt(box));
        if (near < 0 || g < best) best = g, near = j;
    }
    if (gap) *gap = near >= 0 ? best : INFINITY;
    return near;
}

static int cmp_piece_lo(const void *a, const void *b) {
    const cnPiece *const *x = a, *const *y = b;
    double u = (*x)->lo[0], v = (*y)->lo[0];
    return (u > v) - (u < v);
}

double cn_part_self_overlap(const cnPart *part, int dim, double rel_tol, int *pi, int *pj) {
    double worst = 0, zero[3] = {0, 0, 0};
    *pi = *pj = -1;
    int n = part->npieces;
    if (n < 2) return 0;
    /* pieces by the low end of their boxes along x: a piece meets only those that start before
     * it ends, and two pieces whose boxes do not overlap in every axis cannot overlap (a sweep:
     * near-linear for a row of pieces, where comparing every pair is quadratic) */
    const cnPiece **by = cn_malloc(sizeof *by * (size_t)n);
    if (!by) return -1;
    for (int i = 0; i < n; i++) by[i] = &part->pieces[i];
    qsort(by, (size_t)n, sizeof *by, cmp_piece_lo);
    for (int a = 0; a < n; a++)
        for (int b = a + 1; b < n && by[b]->lo[0] < by[a]->hi[0]; b++) {
            const cnPiece *P = by[a], *Q = by[b];
            bool boxes = true;
            for (int k = 0; k < dim; k++) boxes = boxes && P->hi[k] > Q->lo[k] && Q->hi[k] > P->lo[k];
            if (!boxes) continue;
            int i = (int)(P - part->pieces), j = (int)(Q - part->pieces);
            if (i > j) {
                const cnPiece *t = P;
                P = Q, Q = t;
                int ti = i;
                i = j, j = ti;
            }
            double lo[3], hi[3], e[3];
            for (int k = 0; k < 3; k++) lo[k] = fmin(P->lo[k], Q->lo[k]), hi[k] = fmax(P->hi[k], Q->hi[k]);
            cn_sub3(hi, lo, e);
            double tol = rel_tol * cn_norm3(e);
            cnManifold m;
            memset(&m, 0, sizeof m);
            int r = dim == 2 ? cn_contact2_pieces(P, zero, Q, zero, zero, tol, &m)
                             : cn_contact3_pieces(P, zero, Q, zero, zero, tol, &m);
            cn_free(m.pts);
            if (r < 0) {
                cn_free(by);
                return -1;
            }
            /* the deepest; of equal depths the first pair in (i, j) order, as a double loop finds */
            bool deeper = -m.gap > worst || (-m.gap == worst && worst > 0 && (i < *pi || (i == *pi && j < *pj)));
            if (r == CN_PAIR_OVERLAP && deeper) worst = -m.gap, *pi = i, *pj = j;
        }
    cn_free(by);
    return worst;
}

/* Is unit vector e in the cone of the n directions d (2-D: along one, or between two)? The
 * coefficients are allowed a rounding slack of 1e-12. */
static bool in_cone2(const double e[2], const double (*d)[2], int n) {
    const double eps = 1e-12;
    for (int i = 0; i < n; i++) {
        if (fabs(e[0] * d[i][1] - e[1] * d[i][0]) <= eps && e[0] * d[i][0] + e[1] * d[i][1] > 0) return true;
        for (int j = i + 1; j < n; j++) {
            double det = d[i][0] * d[j][1] - d[i][1] * d[j][0];
            if (!(fabs(det) > eps)) continue;
            double al = (e[0] * d[j][1] - e[1] * d[j][0]) / det, be = (d[i][0] * e[1] - d[i][1] * e[0]) / det;
            if (al >= -eps && be >= -eps) return true;
        }
    }
    return false;
}

/* The face contacts' points must lie within this fraction of the smaller part's size of the
 * corner's point (and within the pair's contact tolerance) for them to imply it: the rounding of
 * coordinates stored as float32 (6e-8) passes, a lever arm that could matter does not, whatever
 * --tolerance says (the default contact tolerance is this fraction). */
#define CN_CORNER_SAME_POINT 1e-6

bool cn_contact_corner_implied(const cnAssembly *a, const cnContactSet *set, int c) {
    const cnContact *k = &set->items[c];
    if (a->dim != 2 || !k->corner || k->corner_ends > 2 || k->body1 < 0 || k->body2 < 0) return false;
    double dp[3], dq[3];
    cn_sub3(a->parts[k->body1].hi, a->parts[k->body1].lo, dp);
    cn_sub3(a->parts[k->body2].hi, a->parts[k->body2].lo, dq);
    double tol = fmin(cn_pair_tolerance(a, k->body1, k->body2), CN_CORNER_SAME_POINT * fmin(cn_norm3(dp), cn_norm3(dq)));
    double d[CN_CORNER_ENDS][2];
    int n = 0;
    /* the contacts of a pair are numbered together: look either way from c while the pair holds */
    for (int dir = -1; dir <= 1; dir += 2)
        for (int i = c + dir; i >= 0 && i < set->count && n < CN_CORNER_ENDS; i += dir) {
            const cnContact *f = &set->items[i];
            bool same = f->body1 == k->body1 && f->body2 == k->body2;
            if (!same && !(f->body1 == k->body2 && f->body2 == k->body1)) break;
            if (f->corner || hypot(f->point[0] - k->point[0], f->point[1] - k->point[1]) > tol) continue;
            d[n][0] = same ? f->normal[0] : -f->normal[0];
            d[n][1] = same ? f->normal[1] : -f->normal[1];
            n++;
        }
    return in_cone2(k->normal, (const double(*)[2])d, n) && in_cone2(k->alt_normal, (const double(*)[2])d, n);
}

