/* Searches for a motion from rest already decided, kept by the problem they decided. */
#include <math.h>
#include <string.h>

#include "proof_memo.h"

/* Two problems are the same when each number is within this fraction of the largest magnitude
 * of its block: one quantity in one unit (a row's linear part on one body, its angular part, one
 * body's inverse mass, one friction coefficient, ...), so that a large entry never hides a change
 * in a small one. That leaves what moving a whole scene along a path does to the moment arms
 * (rounding), far below the search's own tolerances (1e-9). */
#define CN_MEMO_SAME 1e-12
/* Problems kept at most (the oldest is replaced) */
#define CN_MEMO_ENTRIES 8

/* A problem written out: integers compared exactly, numbers by arrays (seg: where each ends). */
typedef struct {
    long *ints;
    double *nums;
    int *seg;
    int nints, nnums, nseg, cap_ints, cap_nums, cap_seg;
    bool failed; /* out of memory */
} Sig;

typedef struct {
    Sig sig;
    cnMotionAnswer answer;
    cnMotionStats stats;
    unsigned char *open_bodies, *open_contacts;
    int nb, K;
} Entry;

struct cnProofMemo {
    Entry e[CN_MEMO_ENTRIES];
    int n, next;
};

static bool grow(void **buf, int *cap, int need, size_t size) {
    if (need <= *cap) return true;
    int c = *cap > 0 ? *cap : 64;
    while (c < need) c *= 2;
    void *b = cn_realloc(*buf, size * (size_t)c);
    if (!b) return false;
    *buf = b, *cap = c;
    return true;
}

static void put_int(Sig *s, long v) {
    if (s->failed || !grow((void **)&s->ints, &s->cap_ints, s->nints + 1, sizeof(long))) {
        s->failed = true;
        return;
    }
    s->ints[s->nints++] = v;
}

static void put_num(Sig *s, double v) {
    if (s->failed || !grow((void **)&s->nums, &s->cap_nums, s->nnums + 1, sizeof(double))) {
        s->failed = true;
        return;
    }
    s->nums[s->nnums++] = v;
}

/* the numbers put since the last end form one array */
static void end_array(Sig *s) {
    if (s->failed || !grow((void **)&s->seg, &s->cap_seg, s->nseg + 1, sizeof(int))) {
        s->failed = true;
        return;
    }
    s->seg[s->nseg++] = s->nnums;
}

static void put_nums(Sig *s, const double *v, int n) {
    for (int i = 0; v && i < n; i++) put_num(s, v[i]);
    end_array(s);
}

static void sig_free(Sig *s) {
    cn_free(s->ints);
    cn_free(s->nums);
    cn_free(s->seg);
    memset(s, 0, sizeof *s);
}

/* Everything the search reads of p. */
static void sig_of(const cnMotionProblem *p, Sig *s) {
    const cnMech *m = p->m;
    int nb = m->nb, nd = m->nd, nrows = p->K + p->Kf * p->D;
    put_int(s, m->dim), put_int(s, nd), put_int(s, nb);
    put_int(s, p->K), put_int(s, p->Kf), put_int(s, p->D), put_int(s, p->pointwise);
    put_int(s, p->nominal != NULL);
    for (int r = 0; r < nrows; r++) put_int(s, p->rows[r].body[0]), put_int(s, p->rows[r].body[1]);
    for (int f = 0; f < p->Kf; f++) put_int(s, p->contact_of_fric[f]);
    for (int b = 0; b < nb; b++) put_int(s, m->pushed ? m->pushed[b] : 0);
    put_num(s, p->motion_tol);
    end_array(s); /* compared exactly: its scale is itself */
    int dim = m->dim;
    /* blocks of one quantity each: linear (dim) and angular (nd - dim) parts apart */
    for (int r = 0; r < nrows; r++)
        for (int x = 0; x < 2; x++) {
            put_nums(s, p->rows[r].c[x], dim), put_nums(s, p->rows[r].c[x] + dim, nd - dim);
            put_nums(s, p->rows[r].u[x], dim), put_nums(s, p->rows[r].u[x] + dim, nd - dim);
        }
    for (int f = 0; f < p->Kf; f++) {
        put_nums(s, p->mu + f, 1);
        if (p->nominal) put_nums(s, p->nominal + (size_t)f * p->D, p->D);
    }
    for (int b = 0; b < nb; b++) {
        for (int i = 0; i < nd; i++) {
            const double *row = m->minv + ((size_t)b * nd + i) * nd;
            put_nums(s, row, dim), put_nums(s, row + dim, nd - dim);
        }
        put_nums(s, m->mass + b, 1);
        put_nums(s, m->inertia + (size_t)b * 9, 9);
        put_nums(s, m->fext + (size_t)b * nd, dim), put_nums(s, m->fext + (size_t)b * nd + dim, nd - dim);
        put_nums(s, m->a0 + (size_t)b * nd, dim), put_nums(s, m->a0 + (size_t)b * nd + dim, nd - dim);
        put_nums(s, m->radius + b, 1);
    }
    put_nums(s, &m->g, 1);
    put_nums(s, &m->wref, 1);
}

static bool same(const Sig *a, const Sig *b) {
    if (a->nints != b->nints || a->nnums != b->nnums || a->nseg != b->nseg) return false;
    if (memcmp(a->ints, b->ints, sizeof(long) * (size_t)a->nints) != 0) return false;
    if (memcmp(a->seg, b->seg, sizeof(int) * (size_t)a->nseg) != 0) return false;
    int from = 0;
    for (int k = 0; k < a->nseg; k++) {
        int to = a->seg[k];
        double scale = 0;
        for (int i = from; i < to; i++) scale = fmax(scale, fmax(fabs(a->nums[i]), fabs(b->nums[i])));
        double tol = k == 0 || !isfinite(scale) ? 0 : CN_MEMO_SAME * scale;
        for (int i = from; i < to; i++)
            if (!(fabs(a->nums[i] - b->nums[i]) <= tol)) return false;
        from = to;
    }
    return true;
}

bool cn_proof_memo_find(const cnProofMemo *memo, const cnMotionProblem *p, cnMotionAnswer *answer,
                        cnMotionStats *stats) {
    if (!memo || memo->n == 0) return false;
    Sig s;
    memset(&s, 0, sizeof s);
    sig_of(p, &s);
    const Entry *hit = NULL; /* a proof before an undecided answer */
    for (int k = 0; !s.failed && k < memo->n && !(hit && hit->answer == CN_MOTION_NONE); k++) {
        const Entry *e = &memo->e[k];
        /* the same problem has the same default budget */
        long budget = p->max_nodes > 0 ? p->max_nodes : e->stats.default_budget;
        if (e->answer == CN_MOTION_UNDECIDED && budget > e->stats.budget) continue;
        if (same(&s, &e->sig)) hit = e;
    }
    sig_free(&s);
    if (!hit) return false;
    *answer = hit->answer;
    unsigned char *ob = stats->open_bodies, *oc = stats->open_contacts;
    *stats = hit->stats;
    stats->open_bodies = ob;
    stats->open_contacts = oc;
    if (ob && hit->open_bodies) memcpy(ob, hit->open_bodies, (size_t)hit->nb);
    if (oc && hit->open_contacts) memcpy(oc, hit->open_contacts, (size_t)hit->K);
    else if (oc) memset(oc, 1, (size_t)p->K);
    return true;
}

static void entry_free(Entry *e) {
    sig_free(&e->sig);
    cn_free(e->open_bodies);
    cn_free(e->open_contacts);
    memset(e, 0, sizeof *e);
}

bool cn_proof_memo_keep(cnProofMemo **memo, const cnMotionProblem *p, cnMotionAnswer answer,
                        const cnMotionStats *stats) {
    if (answer != CN_MOTION_NONE && answer != CN_MOTION_UNDECIDED) return true;
    /* undecided is kept only when the budget or the threshold stopped the search (the same search
       stops the same way), not the clock or a failure */
    if (answer == CN_MOTION_UNDECIDED &&
        (p->max_seconds > 0 || (stats->why != CN_UNDECIDED_BUDGET && stats->why != CN_UNDECIDED_THRESHOLD)))
        return true;
    if (!*memo && !(*memo = cn_calloc(1, sizeof **memo))) return false;
    cnProofMemo *M = *memo;
    Entry e;
    memset(&e, 0, sizeof e);
    sig_of(p, &e.sig);
    int nb = p->m->nb;
    if (stats->open_bodies && !(e.open_bodies = cn_malloc((size_t)nb + 1))) e.sig.failed = true;
    if (stats->open_contacts && !(e.open_contacts = cn_malloc((size_t)p->K + 1))) e.sig.failed = true;
    if (e.sig.failed) {
        entry_free(&e);
        return false;
    }
    if (e.open_bodies) memcpy(e.open_bodies, stats->open_bodies, (size_t)nb);
    if (e.open_contacts) memcpy(e.open_contacts, stats->open_contacts, (size_t)p->K);
    e.nb = nb, e.K = p->K;
    e.answer = answer;
    e.stats = *stats;
    e.stats.open_bodies = e.stats.open_contacts = NULL;
    int k = -1; /* the entry of the same problem, else the next free one, else the oldest */
    for (int j = 0; j < M->n && k < 0; j++)
        if (same(&e.sig, &M->e[j].sig)) k = j;
    if (k < 0) {
        k = M->next;
        M->next = (k + 1) % CN_MEMO_ENTRIES;
        if (M->n < CN_MEMO_ENTRIES) M->n++;
    }
    entry_free(&M->e[k]);
    M->e[k] = e;
    return true;
}

void cn_proof_memo_free(cnProofMemo *memo) {
    if (!memo) return;
    for (int k = 0; k < memo->n; k++) entry_free(&memo->e[k]);
    cn_free(memo);
}
