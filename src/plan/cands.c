/* The candidate paths of a part or group leaving a state (sec. V): the file's named paths, or
 * straight lines along representative free directions of the non-directional blocking graph
 * ("up" first), each as long as it takes to clear the parts in its way, and routes through other
 * openings (a roadmap over the C-space obstacles, paths2.c and paths3.c). */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cands.h"
#include "paths2.h"

/* Piecewise-linear routes added to the straight-line candidates. */
#define PLAN_ROUTES 2
/* A direction opens a contact when its normal speed along it, per unit speed, exceeds this. */
#define CN_CAND_OPENS 1e-6

/* How far past the last part in their way the planner's straight paths take the moved parts, as
 * a fraction of their extent along the path: far enough that a replay shows them leaving. Nothing
 * is met there (every part in the shadow of the motion is behind). */
#define CN_PLAN_CLEARANCE 0.5

/* The distance to move the parts in `move` along unit d until they are clear of every part in
 * `rest` whose shadow along d meets theirs, plus CN_PLAN_CLEARANCE of their extent. */
static double clearance(const cnAssembly *a, const unsigned char *move, const unsigned char *rest,
                        const double d[3]) {
    double t1[3], t2[3];
    if (a->dim == 2) t1[0] = -d[1], t1[1] = d[0], t1[2] = 0, t2[0] = t2[1] = t2[2] = 0;
    else cn_tangent_basis(d, t1, t2);
    const double *ax[3] = {d, t1, t2};
    double mlo[3] = {INFINITY, INFINITY, INFINITY}, mhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (int i = 0; i < a->nparts; i++) {
        if (!move[i]) continue;
        for (int s = 0; s < a->parts[i].npieces; s++)
            for (int v = 0; v < a->parts[i].pieces[s].nverts; v++)
                for (int k = 0; k < 3; k++) {
                    double x = cn_dot3(ax[k], a->parts[i].pieces[s].verts[v]);
                    mlo[k] = fmin(mlo[k], x), mhi[k] = fmax(mhi[k], x);
                }
    }
    double need = 0, tol = a->contact_tol;
    for (int j = 0; j < a->nparts; j++) {
        if (!rest[j]) continue;
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int s = 0; s < a->parts[j].npieces; s++)
            for (int v = 0; v < a->parts[j].pieces[s].nverts; v++)
                for (int k = 0; k < 3; k++) {
                    double x = cn_dot3(ax[k], a->parts[j].pieces[s].verts[v]);
                    lo[k] = fmin(lo[k], x), hi[k] = fmax(hi[k], x);
                }
        /* touching counts: a part is clear once nothing it rests on or against is beside it */
        bool shadow = true;
        for (int k = 1; k < a->dim; k++)
            if (lo[k] > mhi[k] + tol || mlo[k] > hi[k] + tol) shadow = false;
        if (shadow) need = fmax(need, hi[0] - mlo[0]);
    }
    return need + CN_PLAN_CLEARANCE * (mhi[0] - mlo[0]) + 10 * tol;
}

/* Is every segment of the candidate a translation along or against gravity (held either way:
 * Corollary 1)? */
bool cn_cand_vertical(const cnAssembly *a, const cnCand *c) {
    const cnSegment *sg = cn_cand_seg(c);
    double g = cn_norm3(a->gravity);
    for (int i = 0; i < c->nseg; i++) {
        if (sg[i].kind != CN_SEGMENT_MOVE) return false;
        double x[3], len = cn_norm3(sg[i].move);
        cn_cross3(sg[i].move, a->gravity, x);
        if (!(cn_norm3(x) <= CN_TOL_SAME_DIRECTION * len * g)) return false;
    }
    return true;
}

/* The options' support applied to the n candidates of c (room for 2 n): overridden, or with
 * CN_PLAN_SUPPORT_BOTH each one that is not vertical only followed by its pushed twin (the first
 * held), both named by their support. */
static void apply_support(const cnCandGen *G, cnCand *c, int *n) {
    cnPlanSupport ps = G->o->support;
    if (ps == CN_PLAN_SUPPORT_HOLD || ps == CN_PLAN_SUPPORT_PUSH)
        for (int i = 0; i < *n; i++) c[i].support = ps == CN_PLAN_SUPPORT_HOLD ? CN_SUPPORT_HOLD : CN_SUPPORT_PUSH;
    if (ps != CN_PLAN_SUPPORT_BOTH) return;
    int m = *n;
    for (int i = m - 1; i >= 0; i--) {
        cnCand base = c[i];
        bool twin = !cn_cand_vertical(G->a, &base);
        /* shift the later ones to make room */
        int k = i + 1;
        if (twin) {
            memmove(&c[k + 1], &c[k], sizeof(cnCand) * (size_t)(m - k));
            m++;
        }
        char nm[64];
        snprintf(nm, sizeof nm, "%s", cn_cand_name(&base));
        c[i].support = CN_SUPPORT_HOLD;
        if (twin) {
            snprintf(c[i].name, sizeof c[i].name, "%.50s, held", nm);
            c[k] = base;
            c[k].support = CN_SUPPORT_PUSH;
            snprintf(c[k].name, sizeof c[k].name, "%.50s, pushed", nm);
        }
    }
    *n = m;
}

cnStatus cn_cands_cones(cnCandGen *G) {
    if (G->have_cones) return CN_OK;
    cnStatus s = cn_ndbg_cones(G->a, NULL, NULL, &G->cones, G->diag);
    G->have_cones = s == CN_OK;
    return s;
}

/* 3-D: the free directions of the parts flagged in `moving` from the state `absent` says, from
 * the blocking graph of that group (sec. V): up when it is free, then one direction of every free
 * cell (the cells holding an axis first, with that axis; then regions, arcs, single directions),
 * then the other free axes. A graph with too many circles falls back to the sampled directions of
 * cn_free_directions. */
static cnStatus graph_directions(cnCandGen *G, const unsigned char *absent, const unsigned char *moving,
                                 double (**dirs)[3], int *nd) {
    const cnAssembly *a = G->a;
    *dirs = NULL;
    *nd = 0;
    cnStatus s = cn_cands_cones(G);
    if (s) return s;
    cnNdbg g;
    if ((s = cn_ndbg_arrange(a, &G->cones, absent, moving, 0, &g, G->diag))) return s;
    if (g.too_large) {
        cn_ndbg_free(&g);
        return cn_free_directions(a, absent, moving, dirs, nd, G->diag);
    }
    s = cn_ndbg_free_dirs(a, &g, dirs, nd, G->diag);
    cn_ndbg_free(&g);
    return s;
}

/* Does translating the flagged parts along unit d open every contact they have with the other
 * parts present (no contact slides or stays closed)? The contact normal points from body1 into
 * body2, so body2 leaves along +normal. */
static bool opens_all(const cnContactSet *cs, const unsigned char *moving, const double d[3]) {
    for (int k = 0; k < cs->count; k++) {
        const cnContact *c = &cs->items[k];
        bool m1 = c->body1 >= 0 && moving[c->body1], m2 = c->body2 >= 0 && moving[c->body2];
        if (m1 == m2) continue;
        double v = cn_dot3(d, c->normal) * (m2 ? 1 : -1);
        if (!(v > CN_CAND_OPENS)) return false;
        for (int e = 1; c->corner && e < c->corner_ends; e++)
            if (!(cn_dot3(d, cn_contact_end((cnContact *)c, e)) * (m2 ? 1 : -1) > CN_CAND_OPENS)) return false;
    }
    return true;
}

/* Directions that open every contact of the moving parts first (stable partition), so that a
 * part is not dragged along its neighbours when another way out exists. */
static cnStatus opening_first(cnCandGen *G, const unsigned char *absent, const unsigned char *moving,
                              double (*dirs)[3], int nd) {
    cnContactSet cs;
    memset(&cs, 0, sizeof cs);
    cnContactQuery q = {NULL, absent, NULL};
    cnStatus s = cn_contacts_find(G->a, &q, &cs, NULL, G->diag);
    double(*tmp)[3] = s ? NULL : cn_malloc(sizeof(double[3]) * (size_t)(nd + 1));
    unsigned char *open = s ? NULL : cn_malloc((size_t)nd + 1);
    if (!s && (!tmp || !open)) s = cn_diag_oom(G->diag);
    if (!s) {
        int k = 0;
        for (int i = 0; i < nd; i++) open[i] = opens_all(&cs, moving, dirs[i]);
        for (int pass = 1; pass >= 0; pass--)
            for (int i = 0; i < nd; i++)
                if (open[i] == pass) cn_copy3(tmp[k++], dirs[i]);
        memcpy(dirs, tmp, sizeof(double[3]) * (size_t)nd);
    }
    cn_free(tmp);
    cn_free(open);
    cn_contacts_free(&cs);
    return s;
}

cnStatus cn_cands(cnCandGen *G, const unsigned char *absent, const unsigned char *moving, int single,
                  bool opening, cnCand **out, int *n) {
    const cnAssembly *a = G->a;
    *out = NULL;
    *n = 0;
    int nfile = 0;
    for (int k = 0; single >= 0 && k < a->ncand; k++) nfile += a->cand[k].part == single;
    cnCand *c = cn_calloc((size_t)(2 * (nfile + G->o->auto_dirs + PLAN_ROUTES) + 2), sizeof(cnCand));
    if (!c) return cn_diag_oom(G->diag);
    if (nfile > 0) {
        for (int k = 0; k < a->ncand; k++) {
            const cnCandidate *cd = &a->cand[k];
            if (cd->part != single) continue;
            cnCand *x = &c[(*n)++];
            x->file = cd;
            x->nseg = cd->nseg;
            x->support = cd->support >= 0 ? (cnSupport)cd->support : a->cand_support;
        }
        apply_support(G, c, n);
        *out = c;
        return CN_OK;
    }
    double(*dirs)[3];
    int nd;
    cnStatus s = a->dim == 3 ? graph_directions(G, absent, moving, &dirs, &nd)
                             : cn_free_directions(a, absent, moving, &dirs, &nd, G->diag);
    if (s) {
        cn_free(c);
        return s;
    }
    if (opening && nd > 1 && (s = opening_first(G, absent, moving, dirs, nd))) {
        cn_directions_free(dirs);
        cn_free(c);
        return s;
    }
    unsigned char *rest = cn_malloc((size_t)a->nparts);
    if (!rest) {
        cn_directions_free(dirs);
        cn_free(c);
        return cn_diag_oom(G->diag);
    }
    for (int i = 0; i < a->nparts; i++) rest[i] = !absent[i] && !moving[i];
    double up[3];
    cn_copy3(up, a->gravity);
    cn_scale3(up, -1.0 / cn_norm3(up));
    for (int i = 0; i < nd && *n < G->o->auto_dirs; i++) {
        cnCand *x = &c[(*n)++];
        double L = clearance(a, moving, rest, dirs[i]);
        if (cn_dot3(dirs[i], up) > 1 - CN_TOL_SAME_DIRECTION) snprintf(x->name, sizeof x->name, "up");
        else if (a->dim == 2)
            snprintf(x->name, sizeof x->name, "dir %.4g deg",
                     fmod(atan2(dirs[i][1], dirs[i][0]) * 180 / CN_PI + 360, 360));
        else
            snprintf(x->name, sizeof x->name, "dir (%.3g, %.3g, %.3g)", dirs[i][0], dirs[i][1],
                     dirs[i][2]);
        x->nseg = 1;
        x->own[0].kind = CN_SEGMENT_MOVE;
        for (int k = 0; k < 3; k++) x->own[0].move[k] = dirs[i][k] * L;
        x->support = a->cand_support;
    }
    /* routes through other openings (a roadmap over the C-space obstacles) */
    if (single >= 0) {
        double segs[PLAN_ROUTES][CN_ROUTE_MAX_SEGMENTS][3];
        int nseg[PLAN_ROUTES], nr = 0;
        s = a->dim == 2 ? cn_paths2(a, absent, moving, PLAN_ROUTES, segs, nseg, &nr, G->diag)
                        : cn_paths3(a, absent, moving, PLAN_ROUTES, segs, nseg, &nr, G->diag);
        for (int r = 0; !s && r < nr; r++) {
            cnCand *x = &c[(*n)++];
            snprintf(x->name, sizeof x->name, "route %d", r + 1);
            x->nseg = nseg[r];
            for (int i = 0; i < nseg[r]; i++) {
                x->own[i].kind = CN_SEGMENT_MOVE;
                cn_copy3(x->own[i].move, segs[r][i]);
            }
            x->support = a->cand_support;
        }
    }
    cn_free(rest);
    cn_directions_free(dirs);
    if (s) {
        cn_free(c);
        return s;
    }
    if (single >= 0) apply_support(G, c, n);
    *out = c;
    return CN_OK;
}

void cn_cands_free(cnCandGen *G) {
    cn_ndbg_cones_free(&G->cones);
    G->have_cones = false;
}
