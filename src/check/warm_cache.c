/* The contact LCP solved on a basis remembered from earlier checks of the same contact
 * structure (consecutive samples of a path): the cache of bases in cnWarmStart. */
#include "check_work.h"
#include "warm_start.h"

static cnLcpStatus solve_lcp(const cnLcp *p, cnSolverChoice choice, bool symmetric_psd,
                             const cnLcpOptions *o, double *z, double *wv, cnLcpInfo *info,
                             cnForcesFrom *used) {
    cnLcpStatus s;
    if (choice == CN_SOLVER_PIVOT ||
        (choice == CN_SOLVER_AUTO && symmetric_psd && p->n <= CN_PIVOT_MAX_AUTO)) {
        s = cn_lcp_pivot(p, o, z, wv, info);
        *used = CN_FORCES_PIVOT;
        if (s == CN_LCP_SOLVED || choice == CN_SOLVER_PIVOT) return s;
    }
    *used = CN_FORCES_LEMKE;
    return cn_lcp_lemke(p, o, z, wv, info);
}

cnWarmStart *cn_warm_start_new(bool record_only) {
    cnWarmStart *w = cn_calloc(1, sizeof *w);
    if (w) w->record_only = record_only;
    return w;
}

cnWarmStats cn_warm_start_stats(const cnWarmStart *w) {
    cnWarmStats none = {0};
    return w ? w->stats : none;
}

void cn_warm_start_free(cnWarmStart *w) {
    cn_warm_start_release(w);
    cn_free(w);
}

void cn_warm_start_release(cnWarmStart *ws) {
    if (!ws) return;
    for (int k = 0; k < CN_WARM_SLOTS; k++) {
        cn_free(ws->slot[k].basic);
        cn_free(ws->slot[k].row);
    }
    memset(ws->slot, 0, sizeof ws->slot);
    cn_free(ws->row_work);
    cn_free(ws->basic_work);
    cn_free(ws->used_work);
    ws->row_work = NULL;
    ws->basic_work = ws->used_work = NULL;
    ws->work_cap = 0;
    cn_proof_memo_free(ws->proofs);
    ws->proofs = NULL;
}

static unsigned long long mix(unsigned long long h, long long v) {
    return (h ^ (unsigned long long)v) * 0x100000001b3ULL; /* FNV-1a step */
}

/* The identity of each LCP row (its contact's bodies, pieces, fixel, kind and vertex, and which
 * row of the contact it is: normal, friction direction d, or the sliding speed), and the key of
 * the whole structure (all rows in order). */
static unsigned long long row_ids(const cnContactSet *cs, const int *fric_of, int Kf, int D,
                                  int n, unsigned long long *row) {
    int K = cs->count;
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &cs->items[c];
        unsigned long long h = 0xcbf29ce484222325ULL;
        long long v[7] = {ct->body1, ct->body2, ct->piece1, ct->piece2, ct->fixel, ct->kind,
                          ct->vertex};
        for (int k = 0; k < 7; k++) h = mix(h, v[k]);
        row[c] = h;
        int f = Kf > 0 ? fric_of[c] : -1;
        if (f < 0) continue;
        for (int d = 0; d < D; d++) row[K + f * D + d] = mix(h, 1 + d);
        row[K + Kf * D + f] = mix(h, -1);
    }
    unsigned long long key = mix(0xcbf29ce484222325ULL, n);
    for (int i = 0; i < n; i++) key = mix(key, (long long)row[i]);
    return key;
}

/* Remember basis `basic` (n flags, of rows `row`): refresh the slot that already holds it, else
 * overwrite the oldest. A failed allocation only means the next solve may be cold. */
static void warm_remember(cnWarmStart *ws, unsigned long long key, int n,
                          const unsigned long long *row, const unsigned char *basic, long stamp) {
    for (int k = 0; k < CN_WARM_SLOTS; k++)
        if (ws->slot[k].stamp && ws->slot[k].key == key && ws->slot[k].n == n &&
            !memcmp(ws->slot[k].basic, basic, (size_t)n)) {
            ws->slot[k].stamp = stamp;
            return;
        }
    int use = 0;
    for (int k = 0; k < CN_WARM_SLOTS; k++)
        if (ws->slot[k].stamp < ws->slot[use].stamp) use = k;
    if (n > ws->slot[use].cap) {
        unsigned char *nb = cn_realloc(ws->slot[use].basic, (size_t)n);
        if (nb) ws->slot[use].basic = nb;
        unsigned long long *nr = cn_realloc(ws->slot[use].row, sizeof(unsigned long long) * (size_t)n);
        if (nr) ws->slot[use].row = nr;
        if (!nb || !nr) {
            ws->slot[use].stamp = 0;
            return;
        }
        ws->slot[use].cap = n;
    }
    memcpy(ws->slot[use].basic, basic, (size_t)n);
    memcpy(ws->slot[use].row, row, sizeof(unsigned long long) * (size_t)n);
    ws->slot[use].key = key;
    ws->slot[use].n = n;
    ws->slot[use].stamp = stamp;
}

/* Carry slot k's basis over to rows `row` (n of them): each row takes the flag of the first
 * unused remembered row with its identity; rows without one start nonbasic. */
static void warm_carry(cnWarmStart *ws, int k, int n, const unsigned long long *row,
                       unsigned char *basic) {
    int m = ws->slot[k].n;
    unsigned char *used = ws->used_work; /* m <= work_cap: see cn_ck_warm_solve */
    memset(used, 0, (size_t)m);
    for (int i = 0; i < n; i++) {
        basic[i] = 0;
        for (int j = 0; j < m; j++)
            if (!used[j] && ws->slot[k].row[j] == row[i]) {
                used[j] = 1;
                basic[i] = ws->slot[k].basic[j];
                break;
            }
    }
}

/* Warm-start attempts per solve, at most: remembered bases of the same contacts, most recent
 * first (bisection alternates between the two sides of an onset). */
#define WARM_TRIES 2

/* solve_lcp with the warm start `ws` (may be NULL): remembered bases are tried first (see
 * cnWarmStart), and the solution's basis is remembered. Times and counts every solve. */
cnLcpStatus cn_ck_warm_solve(cnWarmStart *ws, const cnContactSet *cs, const int *fric_of,
                              int Kf, int D, const cnLcp *p, cnSolverChoice choice,
                              bool symmetric_psd, const cnLcpOptions *o, double *z, double *wv,
                              cnLcpInfo *info, cnForcesFrom *used) {
    if (!ws) return solve_lcp(p, choice, symmetric_psd, o, z, wv, info, used);
    int n = p->n;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    /* scratch for the rows, sized for them and for every remembered basis */
    int need = n;
    for (int k = 0; k < CN_WARM_SLOTS; k++) need = ws->slot[k].n > need ? ws->slot[k].n : need;
    if (need > ws->work_cap) {
        unsigned long long *r = cn_realloc(ws->row_work, sizeof(unsigned long long) * (size_t)need);
        if (r) ws->row_work = r;
        unsigned char *b = cn_realloc(ws->basic_work, (size_t)need);
        if (b) ws->basic_work = b;
        unsigned char *u = cn_realloc(ws->used_work, (size_t)need);
        if (u) ws->used_work = u;
        if (r && b && u) ws->work_cap = need;
    }
    bool ready = need <= ws->work_cap;
    unsigned long long *row = ws->row_work;
    unsigned long long key = ready ? row_ids(cs, fric_of, Kf, D, n, row) : 0;
    cnLcpStatus s = CN_LCP_NUMERIC;
    bool tried[CN_WARM_SLOTS] = {false}, same = false;
    for (int t = 0; ready && !ws->record_only && t < WARM_TRIES && s != CN_LCP_SOLVED; t++) {
        int best = -1;
        for (int k = 0; k < CN_WARM_SLOTS; k++)
            if (!tried[k] && ws->slot[k].stamp && ws->slot[k].key == key && ws->slot[k].n == n &&
                (best < 0 || ws->slot[k].stamp > ws->slot[best].stamp))
                best = k;
        if (best >= 0) {
            same = tried[best] = true;
            s = cn_lcp_solve_basis(p, ws->slot[best].basic, o, z, wv, info);
            continue;
        }
        if (same) break;
        /* the contacts changed: the latest basis, carried over */
        for (int k = 0; k < CN_WARM_SLOTS; k++)
            if (ws->slot[k].stamp && (best < 0 || ws->slot[k].stamp > ws->slot[best].stamp)) best = k;
        if (best >= 0) {
            warm_carry(ws, best, n, row, ws->basic_work);
            s = cn_lcp_solve_basis(p, ws->basic_work, o, z, wv, info);
        }
        break;
    }
    if (s == CN_LCP_SOLVED) *used = symmetric_psd ? CN_FORCES_PIVOT : CN_FORCES_LEMKE;
    else s = solve_lcp(p, choice, symmetric_psd, o, z, wv, info, used);
    double el = cn_seconds_since(&t0);
    ws->stats.seconds += el;
    if (info->warm) ws->stats.warm_seconds += el;
    ws->stats.solves++;
    ws->stats.warm_solves += info->warm;
    ws->stats.pivots += info->pivots;
    if (s == CN_LCP_SOLVED && ready) {
        cn_lcp_basis_of(n, z, wv, ws->basic_work);
        warm_remember(ws, key, n, row, ws->basic_work, ws->stats.solves);
    }
    return s;
}
