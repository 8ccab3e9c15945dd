/* The inner points of a 2-D joint: three or more contacts on one line between the same two
 * bodies, with one normal, one set of friction rows and one coefficient (a non-convex part's
 * pieces meeting a face, each piece its own contact points along it). Only the two outermost are
 * needed, exactly, by the search for a motion from rest:
 * - along the line the bodies' relative normal velocity is linear and the sliding velocity one,
 *   so an inner point is in contact only when both ends are, and slides as they do;
 * - a force at an inner point is a convex combination of the same force at the two ends (the
 *   same wrench on each body), which keeps each end's force within its cone.
 * So a solution of the whole gives one of the ends alone (each inner force moved to the ends),
 * and one of the ends alone is one of the whole (the inner forces zero, their sliding speeds the
 * ends'). */
#include <math.h>
#include <string.h>

#include "search.h"

/* Normal rows of contacts a and b: the same bodies and linear parts (the same normal). */
static bool same_normal(const cnMotionProblem *p, int a, int b) {
    const cnJRow *ra = &p->rows[a], *rb = &p->rows[b];
    for (int x = 0; x < 2; x++) {
        if (ra->body[x] != rb->body[x]) return false;
        if (ra->body[x] < 0) continue;
        for (int k = 0; k < p->m->dim; k++)
            if (fabs(ra->c[x][k] - rb->c[x][k]) > CN_BB_SAME_ROW) return false;
    }
    return true;
}

/* Contact c's place along its line: its normal row's turning part on a body it touches (linear
 * in the position along the line, with slope +-1, for a fixed normal). */
static double along(const cnMotionProblem *p, int c) {
    const cnJRow *r = &p->rows[c];
    int x = r->body[0] >= 0 ? 0 : 1;
    return r->c[x][p->m->dim];
}

int cn_line_inner(const cnMotionProblem *p, int *end0, int *end1) {
    int K = p->K, Kf = p->Kf, D = p->D, dropped = 0;
    for (int c = 0; c < K; c++) end0[c] = end1[c] = -1;
    if (p->m->dim != 2 || p->nominal || Kf < 3 || K + Kf * D + Kf > CN_SEARCH_PAIRS_GROUPED_UPTO)
        return 0;
    int *grp = cn_malloc(sizeof(int) * (size_t)(Kf + 1)), *rep = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    if (!grp || !rep) {
        cn_free(grp), cn_free(rep);
        return -1;
    }
    /* the friction groups (the search's own), each split by normal */
    int *fg = cn_malloc(sizeof(int) * (size_t)(2 * Kf + 1));
    if (!fg) {
        cn_free(grp), cn_free(rep);
        return -1;
    }
    cn_bb_friction_groups(p, fg, fg + Kf);
    int G = 0;
    for (int f = 0; f < Kf; f++) {
        int g = 0;
        while (g < G && !(fg[rep[g]] == fg[f] && same_normal(p, p->contact_of_fric[rep[g]], p->contact_of_fric[f])))
            g++;
        if (g == G) rep[G++] = f;
        grp[f] = g;
    }
    cn_free(fg);
    for (int g = 0; g < G; g++) {
        int lo = -1, hi = -1, n = 0;
        for (int f = 0; f < Kf; f++) {
            if (grp[f] != g) continue;
            int c = p->contact_of_fric[f];
            n++;
            if (lo < 0 || along(p, c) < along(p, lo)) lo = c;
            if (hi < 0 || along(p, c) > along(p, hi)) hi = c;
        }
        if (n < 3 || !(along(p, hi) > along(p, lo))) continue;
        for (int f = 0; f < Kf; f++) {
            int c = p->contact_of_fric[f];
            if (grp[f] != g || c == lo || c == hi) continue;
            end0[c] = lo, end1[c] = hi;
            dropped++;
        }
    }
    cn_free(grp), cn_free(rep);
    return dropped;
}

void cn_line_field(const cnMotionProblem *p, const int *end0, const int *end1, const cnSub *g) {
    int K = p->K, D = p->D, n = g->p.K + g->p.Kf * D;
    if (!g->field) return;
    int *fof = cn_malloc(sizeof(int) * (size_t)(K + 1)), *at = cn_malloc(sizeof(int) * (size_t)(K + p->Kf * D + 1));
    if (!fof || !at) { /* the field is only a start for extending a motion: left as it is */
        cn_free(fof), cn_free(at);
        return;
    }
    for (int c = 0; c < K; c++) fof[c] = -1;
    for (int f = 0; f < p->Kf; f++) fof[p->contact_of_fric[f]] = f;
    for (int r = 0; r < K + p->Kf * D; r++) at[r] = -1;
    for (int i = 0; i < n; i++) at[g->row[i]] = i;
    for (int c = 0; c < K; c++) {
        if (end0[c] < 0 || at[end0[c]] < 0 || at[end1[c]] < 0) continue;
        double s0 = along(p, end0[c]), s1 = along(p, end1[c]), t = (along(p, c) - s0) / (s1 - s0);
        int e[2] = {end0[c], end1[c]};
        double share[2] = {1 - t, t};
        for (int k = 0; k < 2; k++) {
            g->field[at[e[k]]] += share[k] * p->field[c];
            int fc = fof[c], fe = fof[e[k]];
            for (int d = 0; fc >= 0 && fe >= 0 && d < D; d++)
                if (at[K + fe * D + d] >= 0) g->field[at[K + fe * D + d]] += share[k] * p->field[K + fc * D + d];
        }
    }
    cn_free(fof), cn_free(at);
}
