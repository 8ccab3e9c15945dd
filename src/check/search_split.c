/* The search for a motion from rest, group by group: bodies that no contact joins move
 * independently (the LCP's matrix is block diagonal over the groups of bodies that contacts
 * join), so a motion exists if and only if one group has one, and each group is searched by
 * itself (cn_bb_search_group), with its own default budget (a budget given is shared: each
 * group gets what the groups before it left, and so is a time limit; after an undecided group the others get at most
 * CN_MOTION_AFTER_UNDECIDED, since they can only find a motion) and its own kind of search: the energy search
 * unless sliding that a gripper drives drags one of its bodies. A group of more than
 * CN_MOTION_MAX_PAIRS complementarity pairs is not searched (undecided). A contact that
 * touches no body acts on nothing and is left out. */
#include <math.h>
#include <string.h>

#include "search.h"

/* Union-find over the bodies, joined by the rows' two bodies. */
static int root_of(int *up, int b) {
    while (up[b] != b) b = up[b] = up[up[b]];
    return b;
}

/* An answer without a search: undecided for `why`, every body and contact left open. */
static void unsearched(const cnMotionProblem *p, cnUndecided why, cnMotionAnswer *answer,
                       cnMotionStats *stats) {
    unsigned char *open = stats->open_bodies, *loose = stats->open_contacts;
    memset(stats, 0, sizeof *stats);
    stats->open_bodies = open;
    stats->open_contacts = loose;
    if (open) memset(open, 1, (size_t)p->m->nb);
    if (loose) memset(loose, 1, (size_t)p->K);
    stats->why = why;
    stats->open_power = INFINITY;
    *answer = CN_MOTION_UNDECIDED;
}

/* One group's search, unless its LCP is too large for one (then undecided, every body open);
 * when undecided, the motions of its bodies held among the rest (cn_local_motion), within a
 * share of the group's default budget (or what a budget given leaves) and the search's time. */
static cnStatus search_group(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                             double *acc, cnMotionStats *stats, cnDiag *diag) {
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    cnStatus st = CN_OK;
    if (cn_motion_search_pairs(p) <= CN_MOTION_MAX_PAIRS)
        st = cn_bb_search_group(p, answer, force, acc, stats, diag);
    else
        unsearched(p, CN_UNDECIDED_TOO_LARGE, answer, stats);
    if (st || *answer != CN_MOTION_UNDECIDED || p->m->nb < 2) return st;
    long budget = p->max_nodes > 0 ? p->max_nodes - stats->nodes
                                   : cn_motion_energy_budget(p->K + p->Kf * p->D + p->Kf) / CN_LOCAL_SHARE;
    double seconds = (p->max_seconds > 0 ? p->max_seconds : INFINITY) - cn_seconds_since(&t0);
    cnMotionAnswer a = CN_MOTION_NONE;
    long lps = 0;
    if (budget > 0 && seconds > 0) st = cn_local_motion(p, budget, seconds, &a, force, acc, &lps, diag);
    stats->local_lps = lps;
    if (!st && a == CN_MOTION_FOUND) *answer = CN_MOTION_FOUND, stats->why = CN_UNDECIDED_NO;
    return st;
}

/* Which of two reasons for no verdict the whole reports: a failure before a limit, and a limit
 * that more budget cannot lift (a group too large) before one it can (time, then LPs). */
static int reason_rank(cnUndecided why) {
    switch (why) {
    case CN_UNDECIDED_MEMORY: return 6;
    case CN_UNDECIDED_SOLVER: return 5;
    case CN_UNDECIDED_TOO_LARGE: return 4;
    case CN_UNDECIDED_TIME: return 3;
    case CN_UNDECIDED_THRESHOLD: return 2;
    case CN_UNDECIDED_BUDGET: return 1;
    default: return 0;
    }
}

/* Fold one group's stats into the whole's (open_bodies mapped back by the caller). */
static void stats_add(cnMotionStats *all, const cnMotionStats *s, cnMotionAnswer a, bool first) {
    all->nodes += s->nodes;
    all->local_lps += s->local_lps;
    all->budget += s->budget;
    all->default_budget += s->default_budget;
    all->learned += s->learned;
    all->joints += s->joints;
    all->floors += s->floors;
    if (s->depth > all->depth) all->depth = s->depth;
    if (first) all->certificate = s->certificate;
    else all->certificate &= s->certificate;
    all->bound = sqrt(all->bound * all->bound + s->bound * s->bound); /* |a|_M^2 adds up */
    if (a == CN_MOTION_UNDECIDED) {
        if (reason_rank(s->why) > reason_rank(all->why)) all->why = s->why;
        if (s->open_power > all->open_power) all->open_power = s->open_power;
    }
}

static cnStatus search_groups(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                              double *acc, cnMotionStats *stats, cnDiag *diag);

/* The search of p without the inner points of its 2-D joints (end0 >= 0; search_line.c), its
 * answer mapped back: their forces zero, their contacts open where an end's is. */
static cnStatus search_ends(const cnMotionProblem *p, const int *end0, const int *end1,
                            cnMotionAnswer *answer, double *force, double *acc, cnMotionStats *stats,
                            cnDiag *diag) {
    int K = p->K, D = p->D, nb = p->m->nb, nk = 0;
    int *keep = cn_malloc(sizeof(int) * (size_t)(K + 1)), *sub = cn_malloc(sizeof(int) * (size_t)(nb + 1));
    cnSub g;
    memset(&g, 0, sizeof g);
    if (!keep || !sub) {
        cn_free(keep), cn_free(sub);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
    }
    for (int b = 0; b < nb; b++) sub[b] = b;
    for (int c = 0; c < K; c++)
        if (end0[c] < 0) keep[nk++] = c;
    int made = cn_sub_make(p, sub, NULL, 0, keep, nk, NULL, &g);
    cn_free(keep), cn_free(sub);
    int n = g.p.K + g.p.Kf * D;
    double *gf = made ? NULL : cn_calloc((size_t)n + 1, sizeof(double));
    unsigned char *gloose = made || !stats->open_contacts ? NULL : cn_calloc((size_t)g.p.K + 1, 1);
    if (made || !gf || (stats->open_contacts && !gloose)) {
        cn_free(gf), cn_sub_free(&g);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
    }
    cn_line_field(p, end0, end1, &g);
    unsigned char *loose = stats->open_contacts;
    stats->open_contacts = gloose; /* the bodies are the same, numbered alike */
    cnStatus st = search_groups(&g.p, answer, gf, acc, stats, diag); /* no inner points left */
    stats->open_contacts = loose;
    if (!st) {
        memset(force, 0, sizeof(double) * (size_t)(K + p->Kf * D));
        for (int i = 0; i < n; i++) force[g.row[i]] = gf[i];
        if (loose && *answer == CN_MOTION_UNDECIDED) {
            memset(loose, 0, (size_t)K);
            for (int c = 0; c < g.p.K; c++) loose[g.row[c]] = gloose[c];
            for (int c = 0; c < K; c++)
                if (end0[c] >= 0) loose[c] = loose[end0[c]] | loose[end1[c]];
        }
    }
    cn_free(gf), cn_free(gloose);
    cn_sub_free(&g);
    return st;
}

cnStatus cn_motion_search(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                          double *acc, cnMotionStats *stats, cnDiag *diag) {
    int K = p->K;
    int *end = cn_malloc(sizeof(int) * (size_t)(2 * K + 1));
    int inner = end ? cn_line_inner(p, end, end + K) : -1;
    cnStatus st = inner > 0 ? search_ends(p, end, end + K, answer, force, acc, stats, diag)
                  : inner == 0 ? search_groups(p, answer, force, acc, stats, diag)
                               : cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
    cn_free(end);
    return st;
}

/* cn_motion_search of a problem without inner points: group by group. */
static cnStatus search_groups(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                              double *acc, cnMotionStats *stats, cnDiag *diag) {
    const cnMech *M = p->m;
    int nb = M->nb, nd = M->nd, K = p->K, D = p->D;
    *answer = CN_MOTION_NONE;
    if (nb <= 1) return search_group(p, answer, force, acc, stats, diag);
    int *root = cn_malloc(sizeof(int) * (size_t)nb), *sub = cn_malloc(sizeof(int) * (size_t)nb);
    if (!root || !sub) {
        cn_free(root), cn_free(sub);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
    }
    for (int b = 0; b < nb; b++) root[b] = b;
    for (int c = 0; c < K; c++) {
        int b0 = p->rows[c].body[0], b1 = p->rows[c].body[1];
        if (b0 >= 0 && b1 >= 0) root[root_of(root, b0)] = root_of(root, b1);
    }
    int groups = 0;
    for (int b = 0; b < nb; b++) root[b] = root_of(root, b);
    for (int b = 0; b < nb; b++) groups += root[b] == b;
    if (groups == 1) { /* one group: the whole problem as it is */
        cn_free(root), cn_free(sub);
        return search_group(p, answer, force, acc, stats, diag);
    }
    unsigned char *open_out = stats->open_bodies, *loose_out = stats->open_contacts; /* written
                                                                        only when undecided */
    memset(stats, 0, sizeof *stats);
    stats->open_bodies = open_out;
    stats->open_contacts = loose_out;
    unsigned char *open_all = open_out ? cn_calloc((size_t)nb + 1, 1) : NULL;
    unsigned char *loose_all = loose_out ? cn_calloc((size_t)K + 1, 1) : NULL;
    if ((open_out && !open_all) || (loose_out && !loose_all)) {
        cn_free(root), cn_free(sub), cn_free(open_all), cn_free(loose_all);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
    }
    memset(force, 0, sizeof(double) * (size_t)(K + p->Kf * D));
    memset(acc, 0, sizeof(double) * (size_t)(nb * nd));
    bool undecided = false, first = true;
    cnStatus st = CN_OK;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    /* groups in the order of their first body; a motion found ends the search */
    for (int r = 0; r < nb && !st && *answer != CN_MOTION_FOUND; r++) {
        if (root[r] != r) continue;
        cnSub g;
        for (int b = 0, nsub = 0; b < nb; b++) sub[b] = root[b] == r ? nsub++ : -1;
        if (cn_sub_make(p, sub, NULL, 0, NULL, 0, NULL, &g) != 0) {
            cn_sub_free(&g);
            st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
            break;
        }
        int n = g.p.K + g.p.Kf * D;
        double *gf = cn_calloc((size_t)n + 1, sizeof(double));
        double *ga = cn_calloc((size_t)(g.m.nb * nd) + 1, sizeof(double));
        unsigned char *gopen = open_all ? cn_calloc((size_t)g.m.nb + 1, 1) : NULL;
        unsigned char *gloose = loose_all ? cn_calloc((size_t)g.p.K + 1, 1) : NULL;
        if (!gf || !ga || (open_all && !gopen) || (loose_all && !gloose)) {
            st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the motion search");
        } else {
            cnMotionStats gs;
            memset(&gs, 0, sizeof gs);
            gs.open_bodies = gopen;
            gs.open_contacts = gloose;
            cnMotionAnswer a = CN_MOTION_NONE;
            /* a budget given is the whole search's: each group gets what the earlier left */
            if (p->max_nodes > 0) g.p.max_nodes = p->max_nodes - stats->nodes - stats->local_lps;
            else if (undecided) g.p.max_nodes = CN_MOTION_AFTER_UNDECIDED;
            /* a time limit given is the whole search's too */
            if (p->max_seconds > 0) g.p.max_seconds = p->max_seconds - cn_seconds_since(&t0);
            bool out_of_lps = p->max_nodes > 0 && g.p.max_nodes <= 0;
            if (out_of_lps || (p->max_seconds > 0 && !(g.p.max_seconds > 0))) {
                unsearched(&g.p, out_of_lps ? CN_UNDECIDED_BUDGET : CN_UNDECIDED_TIME, &a, &gs);
            } else {
                st = search_group(&g.p, &a, gf, ga, &gs, diag);
            }
            if (!st) {
                stats_add(stats, &gs, a, first);
                first = false;
                undecided |= a == CN_MOTION_UNDECIDED;
                if (a == CN_MOTION_FOUND) {
                    *answer = CN_MOTION_FOUND;
                    for (int i = 0; i < n; i++) force[g.row[i]] = gf[i];
                    for (int s = 0; s < g.m.nb; s++)
                        memcpy(acc + (size_t)g.body[s] * nd, ga + (size_t)s * nd, sizeof(double) * (size_t)nd);
                }
                for (int s = 0; gopen && a == CN_MOTION_UNDECIDED && s < g.m.nb; s++)
                    open_all[g.body[s]] |= gopen[s];
                for (int c = 0; gloose && a == CN_MOTION_UNDECIDED && c < g.p.K; c++)
                    loose_all[g.row[c]] |= gloose[c];
            }
        }
        cn_free(gf), cn_free(ga), cn_free(gopen), cn_free(gloose);
        cn_sub_free(&g);
    }
    cn_free(root), cn_free(sub);
    if (!st && *answer != CN_MOTION_FOUND && undecided && open_out) memcpy(open_out, open_all, (size_t)nb);
    if (!st && *answer != CN_MOTION_FOUND && undecided && loose_out) memcpy(loose_out, loose_all, (size_t)K);
    cn_free(open_all), cn_free(loose_all);
    if (st) return st;
    if (*answer != CN_MOTION_FOUND) {
        *answer = undecided ? CN_MOTION_UNDECIDED : CN_MOTION_NONE;
        memset(acc, 0, sizeof(double) * (size_t)(nb * nd));
    }
    if (p->max_nodes > 0) stats->budget = p->max_nodes;
    if (*answer != CN_MOTION_UNDECIDED) stats->why = CN_UNDECIDED_NO, stats->open_power = 0;
    return CN_OK;
}
