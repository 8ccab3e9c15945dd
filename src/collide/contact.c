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

static const double ZERO3[3] = {0, 0, 0};

static const double *offset_of(const cnContactQuery *q, int i) {
    return (q && q->offset) ? q->offset[i] : ZERO3;
}


/* The number of a vertex of piece `piece` of part `part` (posed by o) at x, or 0. */
static int vertex_at(const cnAssembly *a, int part, int piece, const double o[3], const double x[3],
                     double tol) {
    const cnPart *p = &a->parts[part];
    int base = p->vertex_base;
    for (int s = 0; s < piece; s++) base += p->pieces[s].nverts;
    const cnPiece *pc = &p->pieces[piece];
    for (int v = 0; v < pc->nverts; v++) {
        double d[3];
        for (int k = 0; k < 3; k++) d[k] = pc->verts[v][k] + o[k] - x[k];
        if (cn_norm3(d) <= tol) return base + v + 1;
    }
    return 0;
}

/* The contact tolerance of a pair of parts: rel_tol of the smaller part's size (its bounding
 * box diagonal), so that a part 1e-4 across beside one 1e4 across is judged at its own scale
 * (the assembly's tolerance would be larger than the small part). Never below what the
 * coordinates can resolve: 64 ulps of the largest coordinate involved. Rigid motions and scaling
 * of the whole assembly leave it unchanged relative to the parts. */
double cn_pair_tol(const cnAssembly *a, int i, int j, const double *oi, const double *oj) {
    const cnPart *P = &a->parts[i], *Q = &a->parts[j];
    double dp[3], dq[3], mag = 0;
    cn_sub3(P->hi, P->lo, dp);
    cn_sub3(Q->hi, Q->lo, dq);
    for (int k = 0; k < 3; k++) {
        mag = fmax(mag, fmax(fabs(P->lo[k] + oi[k]), fabs(P->hi[k] + oi[k])));
        mag = fmax(mag, fmax(fabs(Q->lo[k] + oj[k]), fabs(Q->hi[k] + oj[k])));
    }
    double t = a->rel_tol * fmin(cn_norm3(dp), cn_norm3(dq));
    return fmin(a->contact_tol, fmax(t, 64 * DBL_EPSILON * mag));
}

/* Contacts between parts i < j: every pair of pieces, duplicates merged. */
static int pair_contacts(const cnAssembly *a, const cnContactQuery *q, int i, int j,
                         cnContactSet *out, cnOverlap *ov, cnManifold *m) {
    const cnPart *P = &a->parts[i], *Q = &a->parts[j];
    const double *oP = offset_of(q, i), *oQ = offset_of(q, j);
    double tol = cn_pair_tol(a, i, j, oP, oQ);
    double vrel[3] = {0, 0, 0}; /* velocity of Q relative to P */
    if (q && q->velocity) cn_sub3(q->velocity[j], q->velocity[i], vrel);
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
            int r = a->dim == 2 ? cn_contact2_pieces(pp, oP, qp, oQ, vrel, tol, m)
                                : cn_contact3_pieces(pp, oP, qp, oQ, vrel, tol, m);
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
                /* merge with an existing point of this pair: same place, same normal */
                int dup = 0;
                for (int c = first; c < out->count && !dup; c++) {
                    double d[3];
                    cn_sub3(out->items[c].point, m->pts[k], d);
                    if (cn_norm3(d) <= tol && cn_dot3(out->items[c].normal, m->normal) > 1 - 1e-9)
                        dup = 1;
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
                c.gap = m->gap;
                c.vertex = vertex_at(a, j, qi, oQ, m->pts[k], tol);
                if (!c.vertex) c.vertex = vertex_at(a, i, pi, oP, m->pts[k], tol);
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
    cnManifold m = {{0, 0, 0}, 0, 0, 0, NULL};
    cnStatus st = CN_OK;
    if (!items || !pairs) goto oom;

    int ni = 0;
    for (int i = 0; i < n; i++)
        if (cn_part_present(a, q, i)) {
            items[ni].part = i;
            items[ni].lo = a->parts[i].lo[0] + offset_of(q, i)[0];
            ni++;
        }
    qsort(items, (size_t)ni, sizeof(SweepItem), cmp_sweep);
    for (int s = 0; s < ni; s++) {
        int i = items[s].part;
        const double *oi = offset_of(q, i);
        double hi_x = a->parts[i].hi[0] + oi[0] + tol;
        for (int t = s + 1; t < ni && items[t].lo <= hi_x; t++) {
            int j = items[t].part;
            if (a->parts[i].fixed && a->parts[j].fixed) continue;
            /* a gripper touches only the parts its step moves (the paper ignores collisions of
             * the gripper with the rest of the assembly) */
            if (a->parts[i].gripper_step >= 0 && !cn_plan_moves(a, a->parts[i].gripper_step, j))
                continue;
            if (a->parts[j].gripper_step >= 0 && !cn_plan_moves(a, a->parts[j].gripper_step, i))
                continue;
            const double *oj = offset_of(q, j);
            int apart = 0;
            for (int k = 1; k < a->dim; k++)
                if (a->parts[i].lo[k] + oi[k] > a->parts[j].hi[k] + oj[k] + tol ||
                    a->parts[j].lo[k] + oj[k] > a->parts[i].hi[k] + oi[k] + tol)
                    apart = 1;
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
        if (pair_contacts(a, q, pairs[p].i, pairs[p].j, out, ov, &m) < 0) goto oom;
    for (int f = 0; f < a->nfixels; f++) {
        const cnFixel *fx = &a->fixels[f];
        if (!cn_part_present(a, q, fx->part)) continue;
        cnContact c = {0};
        c.body1 = CN_WORLD;
        c.body2 = fx->part;
        c.piece1 = c.piece2 = -1;
        c.fixel = f;
        c.kind = CN_CONTACT_FIXEL;
        cn_add3(fx->point, offset_of(q, fx->part), c.point);
        cn_copy3(c.normal, fx->normal);
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
    return st;
}
