/* Searches for a motion from rest already decided, kept by the problem they decided. */
#include <math.h>
#include <string.h>

#include "proof_memo.h"

/* Two problems are the same when each number is within this fraction of the largest magnitude
 * of its array (contact rows, masses, gravity, ...): what moving a whole scene along a path
 * leaves of rounding in the moment arms, far below the search's own tolerances (1e-9). */
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
    unsigned char *open_bodies;
    int nb;
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
    for (int r = 0; r < nrows; r++)
        for (int x = 0; x < 2; x++)
            for (int d = 0; d < nd; d++) put_num(s, p->rows[r].c[x][d]);
    end_array(s);
    for (int r = 0; r < nrows; r++)
        for (int x = 0; x < 2; x++)
            for (int d = 0; d < nd; d++) put_num(s, p->rows[r].u[x][d]);
    end_array(s);
    put_nums(s, p->mu, p->Kf);
    put_nums(s, p->nominal, p->nominal ? p->Kf * p->D : 0);
    put_nums(s, m->minv, nb * nd * nd);
    put_nums(s, m->mass, nb);
    put_nums(s, m->inertia, nb * 9);
    put_nums(s, m->fext, nb * nd);
    put_nums(s, m->a0, nb * nd);
    put_nums(s, m->radius, nb);
    put_num(s, m->g), put_num(s, m->wref);
    end_array(s);
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
        double tol = k == 0 ? 0 : CN_MEMO_SAME * scale;
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
    bool found = false;
    for (int k = 0; !s.failed && k < memo->n && !found; k++) {
        const Entry *e = &memo->e[k];
        /* the same problem has the same default budget */
        long budget = p->max_nodes > 0 ? p->max_nodes : e->stats.default_budget;
        if (e->answer == CN_MOTION_UNDECIDED && budget > e->stats.budget) continue;
        if (!same(&s, &e->sig)) continue;
        found = true;
        *answer = e->answer;
        unsigned char *ob = stats->open_bodies;
        *stats = e->stats;
        stats->open_bodies = ob;
        if (ob && e->open_bodies) memcpy(ob, e->open_bodies, (size_t)e->nb);
    }
    sig_free(&s);
    return found;
}

static void entry_free(Entry *e) {
    sig_free(&e->sig);
    cn_free(e->open_bodies);
    memset(e, 0, sizeof *e);
}

bool cn_proof_memo_keep(cnProofMemo **memo, const cnMotionProblem *p, cnMotionAnswer answer,
                        const cnMotionStats *stats) {
    if (answer != CN_MOTION_NONE && answer != CN_MOTION_UNDECIDED) return true;
    if (answer == CN_MOTION_UNDECIDED && p->max_seconds > 0) return true; /* the clock's, not kept */
    if (!*memo && !(*memo = cn_calloc(1, sizeof **memo))) return false;
    cnProofMemo *M = *memo;
    Entry e;
    memset(&e, 0, sizeof e);
    sig_of(p, &e.sig);
    int nb = p->m->nb;
    if (stats->open_bodies && !(e.open_bodies = cn_malloc((size_t)nb + 1))) e.sig.failed = true;
    if (e.sig.failed) {
        entry_free(&e);
        return false;
    }
    if (e.open_bodies) memcpy(e.open_bodies, stats->open_bodies, (size_t)nb);
    e.nb = nb;
    e.answer = answer;
    e.stats = *stats;
    e.stats.open_bodies = NULL;
    int k = M->next; /* the next free entry, or the oldest */
    M->next = (k + 1) % CN_MEMO_ENTRIES;
    if (M->n < CN_MEMO_ENTRIES) M->n++;
    entry_free(&M->e[k]);
    M->e[k] = e;
    return true;
}

void cn_proof_memo_free(cnProofMemo *memo) {
    if (!memo) return;
    for (int k = 0; k < memo->n; k++) entry_free(&memo->e[k]);
    cn_free(memo);
}
