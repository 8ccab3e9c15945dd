/* Motions of one body, or of two in contact, held among the rest: bodies that can move while
 * every other body of their group is held still (their own search, cn_bb_search_group, with
 * their neighbours as fixed parts) move the whole when the others can in fact hold still: when
 * the reactions of their motion's forces on their neighbours are balanced by a static field of
 * the rest, found by an LP over the rows of the bodies about them (the given static field's
 * forces beyond). Each motion so made is checked as a solution of the whole problem
 * (cn_motion_verify) before it counts, so what this finds is proved; what it does not find
 * proves nothing. It serves the groups the whole search leaves undecided or cannot take (too
 * many pairs): the end brick of a wall that a sideways load tips, a block that slides by itself,
 * a brick that tips with the one it carries. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "search.h"
#include "solve.h"

/* The bodies about the moving ones whose forces the LP may change, each tried while the last
 * finds no field: those in contact with them; then those and, down to a fixed part, a shortest
 * chain of bodies from each moving one with the bodies in contact with the chain (a load that
 * changes must reach a fixed part); then every body. */
enum { RING_NEIGHBOURS, RING_CHAINS, RING_ALL, RINGS };
/* Bodies up to which the LP of every body at once is tried when the rings find no field. */
#define CN_LOCAL_WHOLE_MAX 2000

/* Add to in the bodies in contact with a body of `from` (not moving ones). One sweep of the
 * contacts. */
static void add_neighbours(const cnMotionProblem *p, const int *sub, const unsigned char *from,
                           unsigned char *in) {
    for (int r = 0; r < p->K; r++) {
        int b0 = p->rows[r].body[0], b1 = p->rows[r].body[1];
        if (b0 < 0 || b1 < 0) continue;
        if (from[b0] && sub[b1] < 0) in[b1] = 1;
        if (from[b1] && sub[b0] < 0) in[b0] = 1;
    }
}

/* Maps of a problem found once: each body's contacts (first, list: ascending), each contact's
 * friction contact (fof; -1 none) and each body's contacts from a fixed part (height; -1 none). */
typedef struct {
    const int *first, *list, *fof;
    int *height;
} Graph;

/* The other side of contact c from body b (-1: a fixed part). */
static int other(const cnMotionProblem *p, int c, int b) {
    return p->rows[c].body[0] == b ? p->rows[c].body[1] : p->rows[c].body[0];
}

/* Each body's height: a breadth-first search from the bodies that touch a fixed part. queue:
 * scratch (nb). */
static void heights(const cnMotionProblem *p, Graph *G, int *queue) {
    int nb = p->m->nb, head = 0, tail = 0;
    for (int b = 0; b < nb; b++) {
        G->height[b] = -1;
        for (int i = G->first[b]; i < G->first[b + 1] && G->height[b] < 0; i++)
            if (other(p, G->list[i], b) < 0) G->height[b] = 0, queue[tail++] = b;
    }
    while (head < tail) {
        int b = queue[head++];
        for (int i = G->first[b]; i < G->first[b + 1]; i++) {
            int o = other(p, G->list[i], b);
            if (o >= 0 && G->height[o] < 0) G->height[o] = G->height[b] + 1, queue[tail++] = o;
        }
    }
}

/* Each body's contacts, ascending: list[first[b] .. first[b + 1] - 1] (first: nb + 2 zeros,
 * list: 2 K). */
static void adjacency(const cnMotionProblem *p, int *first, int *list) {
    int nb = p->m->nb, K = p->K;
    for (int c = 0; c < K; c++)
        for (int x = 0; x < 2; x++) {
            int b = p->rows[c].body[x];
            if (b >= 0 && (x == 0 || b != p->rows[c].body[0])) first[b + 2]++;
        }
    for (int b = 0; b < nb; b++)
        first[b + 2] += first[b + 1];
    for (int c = 0; c < K; c++)
        for (int x = 0; x < 2; x++) {
            int b = p->rows[c].body[x];
            if (b >= 0 && (x == 0 || b != p->rows[c].body[0])) list[first[b + 1]++] = c;
        }
}

/* The bodies whose forces the LP of kind (RING_*) may change: in[c]. mark: scratch (nb). */
static void ring(const cnMotionProblem *p, const int *sub, int kind, const Graph *G,
                 unsigned char *mark, unsigned char *in) {
    int nb = p->m->nb;
    for (int c = 0; c < nb; c++)
        in[c] = kind == RING_ALL && sub[c] < 0, mark[c] = sub[c] >= 0;
    if (kind == RING_ALL) return;
    /* from each moving body down: to the neighbour nearest a fixed part, the first of those */
    for (int s = 0; kind == RING_CHAINS && s < nb; s++) {
        if (sub[s] < 0) continue;
        for (int cur = s; cur >= 0 && G->height[cur] > 0;) {
            int next = -1;
            for (int i = G->first[cur]; i < G->first[cur + 1]; i++) {
                int o = other(p, G->list[i], cur);
                if (o < 0 || G->height[o] < 0 || G->height[o] >= G->height[cur]) continue;
                if (next < 0 || G->height[o] < G->height[next] ||
                    (G->height[o] == G->height[next] && o < next))
                    next = o;
            }
            if (next >= 0 && sub[next] < 0) mark[next] = 1;
            cur = next;
        }
    }
    add_neighbours(p, sub, mark, in);
    for (int c = 0; c < nb; c++)
        if (mark[c] && sub[c] < 0) in[c] = 1;
}

/* Does a row touch a moving body? */
static bool touches(const cnJRow *row, const int *sub) {
    return (row->body[0] >= 0 && sub[row->body[0]] >= 0) ||
           (row->body[1] >= 0 && sub[row->body[1]] >= 0);
}

/* Is every body of a row in `in`, and one at least? */
static bool within(const cnJRow *row, const unsigned char *in) {
    int b0 = row->body[0], b1 = row->body[1];
    return (b0 >= 0 || b1 >= 0) && (b0 < 0 || in[b0]) && (b1 < 0 || in[b1]);
}

/* The forces of every row that touches no moving body (force: K + Kf*D, the moving bodies' rows
 * given) that hold every other body still: the rows between bodies of `in` by an LP (each one's
 * equilibrium, the friction cones), the others at the field's forces (field NULL: every other
 * body is in `in`). 1 found, 0 none (or the LP solver failed), -1 out of memory. */
static int hold_rest(const cnMotionProblem *p, const Graph *G, const int *sub,
                     const unsigned char *in, double *force) {
    const cnMech *m = p->m;
    int K = p->K, Kf = p->Kf, D = p->D, nd = m->nd, nb = m->nb;
    int nrows = K + Kf * D;
    double W = m->wref;
    int *col = cn_malloc(sizeof(int) * (size_t)(nrows + 1)); /* row -> LP column or -1 */
    int *eq = cn_malloc(sizeof(int) * (size_t)(nb + 1));     /* body -> its first equation */
    if (!col || !eq) {
        cn_free(col), cn_free(eq);
        return -1;
    }
    int nvars = 0, neq = 0, nineq = 0;
    /* the moving bodies' rows given; between bodies of in the LP's; the others the field's */
    for (int r = 0; r < nrows; r++) {
        const cnJRow *row = &p->rows[r];
        col[r] = !touches(row, sub) && within(row, in) ? nvars++ : -1;
        if (col[r] < 0 && !touches(row, sub)) force[r] = p->field ? p->field[r] : 0;
    }
    for (int c = 0; c < nb; c++)
        eq[c] = in[c] ? (neq += nd) - nd : -1;
    for (int f = 0; f < Kf; f++)
        nineq += col[p->contact_of_fric[f]] >= 0;
    size_t nnz = (size_t)nvars * 2 * (size_t)nd + (size_t)nineq * (size_t)(D + 1) + 1;
    int *colptr = cn_malloc(sizeof(int) * (size_t)(nvars + 2)),
        *rows = cn_malloc(sizeof(int) * nnz);
    double *vals = cn_malloc(sizeof(double) * nnz),
           *rhs = cn_calloc((size_t)(neq + nineq) + 1, sizeof(double));
    double *cost = cn_calloc((size_t)nvars + 1, sizeof(double)),
           *x = cn_calloc((size_t)nvars + 1, sizeof(double));
    double *scale = cn_malloc(sizeof(double) * (size_t)(nb * nd + 1));
    int *ineq_of = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    const int *fof = G->fof;
    int found = -1;
    if (!colptr || !rows || !vals || !rhs || !cost || !x || !scale || !ineq_of) goto done;
    /* equations in g (rotations times the body's radius), forces in W */
    for (int c = 0; c < nb; c++)
        for (int d = 0; d < nd; d++)
            scale[c * nd + d] = cn_motion_dof_unit(m, c, d);
    for (int c = 0; c < nb; c++)
        for (int d = 0; in[c] && d < nd; d++)
            rhs[eq[c] + d] = -m->a0[c * nd + d] * scale[c * nd + d];
    for (int r = 0; r < nrows; r++) { /* the fixed rows' forces on the bodies held */
        if (col[r] >= 0) continue;
        const cnJRow *row = &p->rows[r];
        for (int s = 0; s < 2; s++) {
            int c = row->body[s];
            for (int d = 0; c >= 0 && in[c] && d < nd; d++)
                rhs[eq[c] + d] -= row->u[s][d] * force[r] * scale[c * nd + d];
        }
    }
    int at = 0, ni = 0;
    for (int f = 0; f < Kf; f++)
        ineq_of[f] = col[p->contact_of_fric[f]] >= 0 ? neq + ni++ : -1;
    for (int r = 0; r < nrows; r++) {
        if (col[r] < 0) continue;
        colptr[col[r]] = at;
        const cnJRow *row = &p->rows[r];
        for (int s = 0; s < 2; s++) {
            int c = row->body[s];
            for (int d = 0; c >= 0 && in[c] && d < nd; d++) {
                double v = row->u[s][d] * W * scale[c * nd + d];
                if (v != 0) rows[at] = eq[c] + d, vals[at++] = v;
            }
        }
        /* friction cones: mu p_n - sum p_k >= 0 */
        if (r < K) {
            if (fof[r] >= 0 && ineq_of[fof[r]] >= 0)
                rows[at] = ineq_of[fof[r]], vals[at++] = p->mu[fof[r]];
        } else if (ineq_of[(r - K) / D] >= 0) {
            rows[at] = ineq_of[(r - K) / D], vals[at++] = -1.0;
        }
    }
    colptr[nvars] = at;
    cnLpProblem lp = {.nvars = nvars,
                      .neq = neq,
                      .nineq = nineq,
                      .colptr = colptr,
                      .rows = rows,
                      .vals = vals,
                      .rhs = rhs,
                      .cost = cost,
                      .method = CN_LP_DUAL_EQ,
                      .any_field = true};
    bool feasible = false;
    cnDiag quiet;
    cn_diag_clear(&quiet);
    cnStatus st = cn_lp_solve(&lp, &feasible, x, &quiet);
    if (st == CN_ERR_MEMORY) goto done;
    found = st == CN_OK && feasible; /* the LP solver failing: no field found */
    for (int r = 0; feasible && r < nrows; r++)
        if (col[r] >= 0) force[r] = fmax(x[col[r]], 0) * W;
done:
    cn_free(col), cn_free(eq), cn_free(colptr), cn_free(rows), cn_free(vals), cn_free(rhs);
    cn_free(cost), cn_free(x), cn_free(scale), cn_free(ineq_of);
    return found;
}

/* The motion of the moving bodies (sub[c] >= 0) found by themselves (forces in part's
 * numbering) made one of the whole: 1 a verified motion (force, acc: the whole's), 0 not one, -1
 * out of memory. */
static int extend(const cnMotionProblem *p, const int *sub, const cnSub *part, const Graph *G,
                  const double *sforce, double *force, double *acc) {
    const cnMech *m = p->m;
    int K = p->K, Kf = p->Kf, D = p->D, nb = m->nb;
    int sn = part->p.K + part->p.Kf * D;
    double *lambda = cn_calloc((size_t)Kf + 1, sizeof(double));
    unsigned char *in = cn_malloc((size_t)nb + 1), *mark = cn_malloc((size_t)nb + 1);
    if (!lambda || !in || !mark) {
        cn_free(lambda), cn_free(in), cn_free(mark);
        return -1;
    }
    int out = 0;
    size_t nrow_bytes = sizeof(double) * (size_t)(K + Kf * D);
    for (int kind = 0; kind < RINGS && out == 0; kind++) {
        if (kind != RING_ALL && !p->field) continue; /* without a field: every body at once */
        if (kind == RING_ALL && nb > CN_LOCAL_WHOLE_MAX) break; /* its LP too large to solve here */
        memset(force, 0, nrow_bytes);
        for (int i = 0; i < sn; i++)
            force[part->row[i]] = sforce[i];
        ring(p, sub, kind, G, mark, in);
        int h = hold_rest(p, G, sub, in, force);
        if (h < 0) out = -1;
        if (h != 1) continue;
        /* sliding speeds: zero where nothing slides; at the moving bodies' friction contacts
           their motion's along the most opposed direction (verified below) */
        cn_mech_response(m, p->rows, K + Kf * D, force, acc);
        for (int f = 0; f < Kf; f++) {
            lambda[f] = 0;
            if (!touches(&p->rows[p->contact_of_fric[f]], sub)) continue;
            for (int d = 0; d < D; d++) {
                int r = K + f * D + d;
                double v = cn_mech_relative(m, &p->rows[r], acc) +
                           (p->nominal ? p->nominal[f * D + d] : 0);
                lambda[f] = fmax(lambda[f], -v);
            }
        }
        out = cn_motion_verify(p, force, lambda, acc) == 1;
    }
    cn_free(lambda), cn_free(in), cn_free(mark);
    return out;
}

/* Candidates by how many contacts they have, fewest first (ties by their bodies): bodies that
 * can move by themselves mostly have few (the top of a wall, its ends), and each search is
 * smaller. */
typedef struct {
    int contacts, b0, b1; /* b1: -1 for one body */
} Candidate;
static int cmp_candidates(const void *x, const void *y) {
    const Candidate *a = x, *b = y;
    if (a->contacts != b->contacts)
        return (a->contacts > b->contacts) - (a->contacts < b->contacts);
    if (a->b0 != b->b0) return (a->b0 > b->b0) - (a->b0 < b->b0);
    return (a->b1 > b->b1) - (a->b1 < b->b1);
}

/* The contacts of one or two bodies, ascending, without repeats (out: room for both lists). */
static int merge(const int *a, int na, const int *b, int nb, int *out) {
    int i = 0, j = 0, n = 0;
    while (i < na || j < nb) {
        int v = j >= nb || (i < na && a[i] <= b[j]) ? a[i++] : b[j++];
        if (n == 0 || out[n - 1] != v) out[n++] = v;
    }
    return n;
}

/* One candidate's search by itself and, when it moves, its motion extended to the whole: 1
 * found (force, acc), 0 not, -1 out of memory; *lps grows by its LPs. */
static int try_candidate(const cnMotionProblem *p, const Candidate *cand, int *sub, const Graph *G,
                         int *contacts, long max_lps, double left, double *force, double *acc,
                         long *lps, cnDiag *diag, cnStatus *st) {
    int nd = p->m->nd, D = p->D, b0 = cand->b0, b1 = cand->b1;
    const int *first = G->first, *list = G->list;
    int nc = merge(list + first[b0], first[b0 + 1] - first[b0], b1 >= 0 ? list + first[b1] : NULL,
                   b1 >= 0 ? first[b1 + 1] - first[b1] : 0, contacts);
    if (nc * (D + 2) > CN_MOTION_MAX_PAIRS) return 0; /* too many contacts to search */
    sub[b0] = 0; /* b0 < b1: numbered in the whole's order */
    if (b1 >= 0) sub[b1] = 1;
    cnSub part;
    int found = 0;
    double *sf = NULL, *sa = NULL;
    int bodies[2] = {b0, b1};
    if (cn_sub_make(p, sub, bodies, b1 >= 0 ? 2 : 1, contacts, nc, G->fof, &part) != 0) {
        found = -1;
        goto done;
    }
    int sn = part.p.K + part.p.Kf * D;
    part.p.max_nodes = (long)fmin(CN_LOCAL_LPS, (double)(max_lps - *lps));
    part.p.max_seconds = left;
    part.p.progress = NULL;
    sf = cn_calloc((size_t)sn + 1, sizeof(double));
    sa = cn_calloc((size_t)(part.m.nb * nd) + 1, sizeof(double));
    if (!sf || !sa) {
        found = -1;
        goto done;
    }
    cnMotionStats ss;
    memset(&ss, 0, sizeof ss);
    cnMotionAnswer a = CN_MOTION_NONE;
    *st = cn_bb_search_group(&part.p, &a, sf, sa, &ss, diag);
    *lps += ss.nodes;
    if (*st == CN_ERR_NUMERIC) { /* GLPK stopped on this candidate: none found here */
        *st = CN_OK;
        cn_diag_clear(diag);
        a = CN_MOTION_NONE;
    }
    if (!*st && a == CN_MOTION_FOUND) found = extend(p, sub, &part, G, sf, force, acc);
done:
    sub[b0] = -1;
    if (b1 >= 0) sub[b1] = -1;
    cn_free(sf), cn_free(sa), cn_sub_free(&part);
    return found;
}

cnStatus cn_local_motion(const cnMotionProblem *p, long max_lps, double max_seconds,
                         cnMotionAnswer *answer, double *force, double *acc, long *lps,
                         cnDiag *diag) {
    const cnMech *m = p->m;
    int nb = m->nb, K = p->K, Kf = p->Kf;
    *answer = CN_MOTION_NONE;
    *lps = 0;
    if (nb < 2) return CN_OK; /* the whole search was the body's own */
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    /* each body's contacts (ascending), the friction contact of each contact; candidates: each
       body, then each two bodies in contact */
    int *first = cn_calloc((size_t)nb + 2, sizeof(int)),
        *list = cn_malloc(sizeof(int) * (size_t)(2 * K + 1));
    int *fof = cn_malloc(sizeof(int) * (size_t)(K + 1)),
        *sub = cn_malloc(sizeof(int) * (size_t)(nb + 1));
    int *contacts = cn_malloc(sizeof(int) * (size_t)(2 * K + 1));
    Candidate *cand = cn_malloc(sizeof(Candidate) * (size_t)(nb + K + 1));
    int *height = cn_malloc(sizeof(int) * (size_t)(nb + 1)),
        *queue = cn_malloc(sizeof(int) * (size_t)(nb + 1));
    if (!first || !list || !fof || !sub || !contacts || !cand || !height || !queue) {
        cn_free(first), cn_free(list), cn_free(fof), cn_free(sub), cn_free(contacts), cn_free(cand);
        cn_free(height), cn_free(queue);
        return cn_diag_oom(diag);
    }
    adjacency(p, first, list);
    for (int c = 0; c < K; c++)
        fof[c] = -1;
    for (int f = 0; f < Kf; f++)
        fof[p->contact_of_fric[f]] = f;
    int n1 = 0, n2 = 0;
    for (int b = 0; b < nb; b++)
        cand[n1++] = (Candidate){first[b + 1] - first[b], b, -1}, sub[b] = -1;
    for (int c = 0; c < K; c++) { /* two bodies in contact (once: sorted, repeats dropped) */
        int b0 = p->rows[c].body[0], b1 = p->rows[c].body[1];
        if (b0 < 0 || b1 < 0 || b0 == b1) continue;
        int lo = b0 < b1 ? b0 : b1, hi = b0 < b1 ? b1 : b0;
        cand[n1 + n2++] =
            (Candidate){first[lo + 1] - first[lo] + first[hi + 1] - first[hi], lo, hi};
    }
    qsort(cand, (size_t)n1, sizeof(Candidate), cmp_candidates);
    qsort(cand + n1, (size_t)n2, sizeof(Candidate), cmp_candidates);
    int kept = 0;
    for (int i = 0; i < n2; i++) {
        const Candidate *x = &cand[n1 + i];
        if (kept == 0 || x->b0 != cand[n1 + kept - 1].b0 || x->b1 != cand[n1 + kept - 1].b1)
            cand[n1 + kept++] = *x;
    }
    n2 = kept;
    Graph G = {first, list, fof, height};
    heights(p, &G, queue);
    cnStatus st = CN_OK;
    for (int i = 0; i < n1 + n2 && *answer != CN_MOTION_FOUND && !st; i++) {
        double left = max_seconds - cn_seconds_since(&t0);
        if (*lps >= max_lps || !(left > 0)) break;
        int f = try_candidate(p, &cand[i], sub, &G, contacts, max_lps, left, force, acc, lps, diag,
                              &st);
        if (f < 0 && !st) st = cn_diag_oom(diag);
        if (f == 1 && !st) *answer = CN_MOTION_FOUND;
    }
    cn_free(first), cn_free(list), cn_free(fof), cn_free(sub), cn_free(contacts), cn_free(cand);
    cn_free(height), cn_free(queue);
    return st;
}

int cn_local_chain_ring(const cnMotionProblem *p, const unsigned char *moving, unsigned char *in) {
    int nb = p->m->nb, K = p->K;
    int *first = cn_calloc((size_t)nb + 2, sizeof(int)), *list = cn_malloc(sizeof(int) * (size_t)(2 * K + 1));
    int *height = cn_malloc(sizeof(int) * (size_t)(nb + 1)), *queue = cn_malloc(sizeof(int) * (size_t)(nb + 1));
    int *sub = cn_malloc(sizeof(int) * (size_t)(nb + 1));
    unsigned char *mark = cn_malloc((size_t)nb + 1);
    int out = -1;
    if (first && list && height && queue && sub && mark) {
        adjacency(p, first, list);
        Graph G = {.first = first, .list = list, .fof = NULL, .height = height};
        heights(p, &G, queue);
        for (int b = 0; b < nb; b++) sub[b] = moving[b] ? 0 : -1;
        ring(p, sub, RING_CHAINS, &G, mark, in);
        for (int b = 0; b < nb; b++) in[b] = in[b] || moving[b];
        out = 0;
    }
    cn_free(first), cn_free(list), cn_free(height), cn_free(queue), cn_free(sub), cn_free(mark);
    return out;
}
