/* Unit tests of src/plan/plan_harvest.c (cn_pl_harvest, through cn_plan): what the result says
 * of the search's states. The scenes are k towers of h unit blocks on a frictionless table, far
 * enough apart that no move disturbs another tower: a block can go only when it is the top of its
 * tower, so the stable orders are the interleavings of k top-first chains, (kh)! / (h!)^k of
 * them, a count made here independently of the planner. Checked: the count; the orders listed
 * (each a permutation of the free parts, each tower top first, no two alike, as many as the
 * limit allows, and all of them with `all` on the smaller scenes); the sequences listed, each a
 * stable order with its paths, and the best plan the first of them, which the simulator replays
 * stably; the table's rows; the same count with the towers listed in another order or the scene
 * moved far away; and a scene that is not stable as it stands: no order, no sequence, no best
 * plan. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cairn/cairn.h"
#include "helpers.h"

#define MAXK 3
#define MAXH 3

/* k towers of h unit blocks, tower t at x = 10 t + dx (block "Tt.j", j = 0 at the bottom),
 * listed tower by tower, or from the last tower to the first when `reversed`. */
static cnAssembly *towers(int k, int h, double dx, bool reversed) {
    char json[4096];
    int len = snprintf(json, sizeof json,
                       "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[{\"name\":\"table\",\"fixed\":true,"
                       "\"polygon\":[[%g,-1],[%g,-1],[%g,0],[%g,0]]}",
                       dx - 10, dx + 10 * k + 10, dx + 10 * k + 10, dx - 10);
    for (int tt = 0; tt < k; tt++) {
        int t = reversed ? k - 1 - tt : tt;
        for (int j = 0; j < h; j++) {
            double x = 10 * t + dx;
            len += snprintf(json + len, sizeof json - (size_t)len,
                            ",{\"name\":\"T%d.%d\",\"polygon\":[[%g,%d],[%g,%d],[%g,%d],[%g,%d]]}", t, j, x, j,
                            x + 1, j, x + 1, j + 1, x, j + 1);
        }
    }
    snprintf(json + len, sizeof json - (size_t)len, "]}");
    return load_ok(json);
}

/* (kh)! / (h!)^k, the interleavings of k chains of h. */
static double interleavings(int k, int h) {
    double n = 1;
    int placed = 0;
    for (int t = 0; t < k; t++)
        for (int j = 1; j <= h; j++) n = n * ++placed / j;
    return n;
}

/* The tower and level of part p from its name "Tt.j"; false for another part. */
static bool block_of(const cnAssembly *a, int p, int *t, int *j) {
    return p >= 0 && p < a->nparts && sscanf(a->parts[p].name, "T%d.%d", t, j) == 2;
}

/* Is the list of parts a stable order of the towers: every block once, each tower top first? */
static bool valid_order(const cnAssembly *a, const int *parts, int n, int k, int h) {
    if (n != k * h) return false;
    int next[MAXK]; /* the level each tower gives next */
    for (int t = 0; t < k; t++) next[t] = h - 1;
    for (int i = 0; i < n; i++) {
        int t, j;
        if (!block_of(a, parts[i], &t, &j) || t < 0 || t >= k || j != next[t]) return false;
        next[t]--;
    }
    return true;
}

/* A sequence's parts in removal order (each step one block). */
static bool sequence_parts(const cnPlanSequence *s, int *parts) {
    for (int i = 0; i < s->n; i++) {
        if (s->steps[i].move.n != 1) return false;
        parts[i] = s->steps[i].move.idx[0];
    }
    return true;
}

static cnPlanResult plan_of(const cnAssembly *a, bool all, bool *ok) {
    cnPlanOptions o = cn_plan_options_default();
    o.all = all;
    o.fixels = false;
    cnPlanResult r;
    memset(&r, 0, sizeof r);
    cnDiag d;
    *ok = cn_plan(a, &o, &r, &d) == CN_OK;
    CHECK_MSG(*ok, "plan: %s", d.message);
    return r;
}

static void check_towers(int k, int h) {
    cnAssembly *a = towers(k, h, 0, false);
    if (!a) return;
    double want = interleavings(k, h);
    cnPlanOptions dflt = cn_plan_options_default();
    /* with `all` only where the sequences (orders times paths) are few: under memcheck too */
    for (int all = 0; all < (k * h <= 4 ? 2 : 1); all++) {
        bool ok;
        cnPlanResult r = plan_of(a, all, &ok);
        if (!ok) continue;
        CHECK_MSG(r.stable && r.stable_single_part && !r.unstable_at_start, "%d x %d: not stable", k, h);
        CHECK_MSG(r.norders == want, "%d x %d towers: %g stable orders, want %g", k, h, r.norders, want);
        CHECK(r.nsequences >= r.norders);
        int limit = all ? 100000 : dflt.list_limit;
        CHECK_MSG(r.nlisted_orders == (int)fmin(want, limit), "%d x %d (all %d): %d orders listed of %g", k, h, all,
                  r.nlisted_orders, want);
        for (int i = 0; i < r.nlisted_orders; i++) {
            const cnPartList *o = &r.orders[i];
            CHECK_MSG(valid_order(a, o->idx, o->n, k, h), "%d x %d: listed order %d is not a stable order", k, h, i);
            for (int m = 0; m < i; m++)
                CHECK_MSG(o->n != r.orders[m].n || memcmp(o->idx, r.orders[m].idx, sizeof(int) * (size_t)o->n),
                          "%d x %d: orders %d and %d alike", k, h, m, i);
        }
        int parts[MAXK * MAXH];
        CHECK(r.nlisted >= 1 && r.nlisted <= (all ? 100000 : dflt.list_limit));
        for (int i = 0; i < r.nlisted; i++) {
            const cnPlanSequence *s = &r.sequences[i];
            CHECK_MSG(s->n == k * h && sequence_parts(s, parts) && valid_order(a, parts, s->n, k, h),
                      "%d x %d: sequence %d is not a stable order", k, h, i);
            for (int st = 0; st < s->n; st++)
                CHECK_MSG(s->steps[st].status == CN_STEP_STABLE && s->steps[st].nseg >= 1,
                          "%d x %d: sequence %d step %d: status %d, %d segments", k, h, i, st,
                          (int)s->steps[st].status, s->steps[st].nseg);
        }
        CHECK(r.best_plan == &r.sequences[0] && cn_test_replay_stable(a, r.best_plan));
        CHECK(r.nrows >= 1 && r.nrows <= (all ? 100000 : dflt.table_limit));
        for (int i = 0; i < r.nrows; i++) {
            const cnPlanSequence *s = &r.table[i].seq;
            CHECK_MSG(s->n <= k * h && sequence_parts(s, parts), "%d x %d: row %d", k, h, i);
        }
        CHECK(r.ndead == 0 && r.dead_ends == NULL);
        cn_plan_result_free(&r);
    }
    /* the towers listed the other way round, or the scene 1e4 away: the same count */
    for (int v = 0; v < 2; v++) {
        cnAssembly *b = v ? towers(k, h, 1e4, false) : towers(k, h, 0, true);
        bool ok;
        cnPlanResult r = b ? plan_of(b, false, &ok) : (cnPlanResult){0};
        if (b && ok)
            CHECK_MSG(r.norders == want, "%d x %d (%s): %g orders, want %g", k, h, v ? "moved" : "reordered",
                      r.norders, want);
        if (b) cn_plan_result_free(&r);
        cn_assembly_free(b);
    }
    cn_assembly_free(a);
}

/* A block overhanging its table by more than half (frictionless): not stable as it stands. */
static void check_unstable_start(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                            "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[0,-1],[0,0],[-5,0]]},"
                            "{\"name\":\"A\",\"polygon\":[[-0.2,0],[0.8,0],[0.8,1],[-0.2,1]]},"
                            "{\"name\":\"B\",\"polygon\":[[-3,0],[-2,0],[-2,1],[-3,1]]}]}");
    if (!a) return;
    bool ok;
    cnPlanResult r = plan_of(a, false, &ok);
    if (ok) {
        CHECK(!r.stable && r.unstable_at_start && !r.undecided_at_start);
        CHECK(r.norders == 0 && r.nsequences == 0 && r.nlisted == 0 && r.nlisted_orders == 0 && r.best_plan == NULL);
    }
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

void test_plan_harvest(void) {
    CHECK(interleavings(2, 2) == 6 && interleavings(3, 2) == 90 && interleavings(2, 3) == 20);
    check_towers(1, 3);
    check_towers(2, 2);
    check_towers(2, 3);
    check_towers(3, 2);
    check_unstable_start();
}
