/* Removal directions against hand-computed arcs, and the planner on small known cases. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "pieces.h"
#include "paths2.h"

static double deg(double r) { return r * 180 / CN_PI; }

/* The free arcs of part `name`, as degrees; returns the count. */
static int arcs_of(const char *json, const char *name, double out[][2]) {
    cnAssembly *a = load_ok(json);
    if (!a) return -1;
    unsigned char *mv = calloc((size_t)a->nparts, 1);
    mv[cn_assembly_find_part(a, name)] = 1;
    cnArc *arcs;
    int n;
    cnDiag d;
    CHECK(cn_directions2(a, NULL, mv, &arcs, &n, NULL, NULL, &d) == CN_OK);
    for (int i = 0; i < n; i++) out[i][0] = deg(arcs[i].from), out[i][1] = deg(arcs[i].to);
    cn_free_arcs(arcs);
    free(mv);
    cn_assembly_free(a);
    return n;
}

#define T2 "{\"name\":\"t\",\"fixed\":true,\"polygon\":[[-10,-1],[10,-1],[10,0],[-10,0]]}"
#define BOX "{\"name\":\"A\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]}"

static void test_arcs(void) {
    double a[8][2];
    /* on a table: the upper half-plane, ends included */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX "]}", "A", a) == 1);
    CHECK_NEAR(a[0][0], 0, 1e-9);
    CHECK_NEAR(a[0][1], 180, 1e-9);
    /* in a slot (walls touching both sides, taller than the block): straight up only */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                  "{\"name\":\"w1\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,3],[-1,3]]},"
                  "{\"name\":\"w2\",\"fixed\":true,\"polygon\":[[1,0],[2,0],[2,3],[1,3]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 90, 1e-9);
    CHECK_NEAR(a[0][1], 90, 1e-9);
    /* in a corner (wall on the left as tall as the block): [0, 90], plus up-left once above
     * the wall? The wall is 1 tall: leaving up-left hits it, so [0, 90] */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                  "{\"name\":\"w1\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,1],[-1,1]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 0, 1e-9);
    /* the wall's top-right corner (0,1) seen from the block's bottom-left corner (0,0) is
     * straight up, and from the block's bottom-right corner (1,0) at 135 degrees: directions
     * above 135 clear the wall (the block rises faster than it moves left)... the extent of
     * M = wall - block is [90, 180] open, so the free arc ends at 90 */
    CHECK_NEAR(a[0][1], 90, 1e-9);
    /* under a ceiling that touches its top (no table): the lower half-plane, wrapping past 0 */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" BOX ","
                  "{\"name\":\"c\",\"fixed\":true,\"polygon\":[[-5,1],[5,1],[5,2],[-5,2]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 180, 1e-9);
    CHECK_NEAR(a[0][1], 0, 1e-9);
    /* nothing around: every direction (one arc, the whole circle) */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" BOX "]}", "A", a) == 1);
    CHECK_NEAR(a[0][0], 0, 1e-9);
    CHECK_NEAR(a[0][1], 360, 1e-9);
    /* a post of height 1 at distance 2 to the right: directions below atan(1/1) = 45 deg
     * (bottom-right corner (1,0) to the post's top-left corner (2,1)... but the block's top
     * corner (1,1) reaches the post's bottom-left (2,0) going down-right, blocked by the table
     * anyway): free [45, 180] */
    CHECK(arcs_of("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                  "{\"name\":\"p\",\"fixed\":true,\"polygon\":[[2,0],[3,0],[3,1],[2,1]]}]}",
                  "A", a) == 1);
    CHECK_NEAR(a[0][0], 45, 1e-9);
    CHECK_NEAR(a[0][1], 180, 1e-9);
}

/* The per-direction sweep test agrees with the arcs on many random directions. */
static void test_sweep_agrees(void) {
    const char *json = "{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                       "{\"name\":\"p\",\"fixed\":true,\"polygon\":[[2,0],[3,0],[3,1],[2,1]]},"
                       "{\"name\":\"q\",\"fixed\":true,\"polygon\":[[-3,2],[-2,2],[-2,3],[-3,3]]}]}";
    cnAssembly *a = load_ok(json);
    if (!a) return;
    unsigned char mv[4] = {0, 1, 0, 0};
    cnArc *arcs;
    int n;
    cnDiag d;
    CHECK(cn_directions2(a, NULL, mv, &arcs, &n, NULL, NULL, &d) == CN_OK);
    cnRng r = {31};
    int agree = 0, total = 0;
    for (int i = 0; i < 200; i++) {
        double th = cn_rng_range(&r, 0, 2 * CN_PI);
        bool in = false;
        for (int k = 0; k < n; k++) {
            double len = fmod(arcs[k].to - arcs[k].from + 4 * CN_PI, 2 * CN_PI);
            if (arcs[k].to - arcs[k].from >= 2 * CN_PI) len = 2 * CN_PI;
            double x = fmod(th - arcs[k].from + 4 * CN_PI, 2 * CN_PI);
            if (x <= len + 1e-12) in = true;
        }
        double dir[3] = {cos(th), sin(th), 0};
        bool fr;
        CHECK(cn_direction_free(a, NULL, mv, dir, &fr, &d) == CN_OK);
        total++;
        agree += fr == in;
    }
    CHECK_MSG(agree == total, "arcs and sweeps agree on %d of %d directions", agree, total);
    cn_free_arcs(arcs);
    cn_assembly_free(a);
}

/* cn_free_directions through the public API only, freed with the public cn_directions_free (the
 * header once said cn_free, which callers cannot reach): a block in a slot leaves straight up. */
static void test_free_directions_public(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"parts\":[" T2 "," BOX ","
                            "{\"name\":\"w1\",\"fixed\":true,\"polygon\":[[-1,0],[0,0],[0,3],[-1,3]]},"
                            "{\"name\":\"w2\",\"fixed\":true,\"polygon\":[[1,0],[2,0],[2,3],[1,3]]}]}");
    if (!a) return;
    unsigned char *mv = calloc((size_t)a->nparts, 1);
    mv[cn_assembly_find_part(a, "A")] = 1;
    double(*dirs)[3] = NULL;
    int n = 0;
    cnDiag d;
    CHECK(cn_free_directions(a, NULL, mv, &dirs, &n, &d) == CN_OK);
    CHECK(n >= 1);
    if (n >= 1) {
        CHECK_NEAR(dirs[0][0], 0, 1e-12);
        CHECK_NEAR(dirs[0][1], 1, 1e-12);
    }
    for (int i = 0; i < n; i++) CHECK_MSG(dirs[i][1] > 1 - 1e-9, "direction %d is not up", i);
    cn_directions_free(dirs);
    free(mv);
    cn_assembly_free(a);
}

/* ---- the planner, through its typed result ---- */


static int part(const cnAssembly *a, const char *name) { return cn_assembly_find_part(a, name); }

/* The paper's Fig. 1 blocks: C is B's counterweight against D, so D goes first, then C, B, A: a
 * single stable order (hand-derived), and every listed sequence replays stably. */
static void test_plan_blocks(void) {
    cnAssembly *a = load_example("blocks");
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK(r.stable && r.stable_single_part);
    CHECK_NEAR(r.norders, 1, 0);
    CHECK(r.nlisted_orders == 1);
    if (r.nlisted_orders == 1 && r.orders[0].n == 4) {
        const char *want[4] = {"D", "C", "B", "A"};
        for (int k = 0; k < 4; k++) CHECK_MSG(r.orders[0].idx[k] == part(a, want[k]), "step %d is not %s", k + 1, want[k]);
    } else CHECK(false);
    CHECK(r.nlisted == o.list_limit && r.nsequences > r.nlisted);
    CHECK(r.best_plan == &r.sequences[0]);
    for (int i = 0; i < r.nlisted; i++) CHECK_MSG(cn_test_replay_stable(a, &r.sequences[i]), "sequence %d does not replay stably", i + 1);
    /* every row of the table ends as its last move says */
    int stable_rows = 0;
    for (int i = 0; i < r.nrows; i++) {
        const cnPlanRow *row = &r.table[i];
        CHECK(row->seq.n >= 1);
        if (row->end == CN_ROW_STABLE) {
            stable_rows++;
            CHECK(row->seq.n == 4);
        }
        if (row->end == CN_ROW_STEP_FAILS) CHECK(row->seq.steps[row->seq.n - 1].status != CN_STEP_STABLE);
    }
    CHECK(stable_rows > 0);
    CHECK(r.search.exhaustive && !r.search.budget_reached && r.search.free_parts == 4);
    CHECK(r.ndead == 0 && !r.tree && !r.subassemblies);
    cn_plan_result_free(&r);
    CHECK(r.mem_ == NULL && r.sequences == NULL);
    cn_plan_result_free(&r); /* twice is harmless */
    cn_assembly_free(a);
}

/* Fig. 17: no single part leaves stably; the paper's split {A-B, C-D} does (sec. VII). The
 * AND/OR tree's first move takes out two parts, and each split's sides cover the assembly. */
static void test_plan_subassemblies(void) {
    cnAssembly *a = load_example("fig17");
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    o.subassemblies = true;
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK(r.stable && !r.stable_single_part);
    CHECK(r.nlisted == 0 && r.best_plan == NULL);
    CHECK(r.tree && r.tree->split && r.tree->take_out.move.n == 2 && r.tree->take_out.status == CN_STEP_STABLE);
    bool ab_cd = false;
    for (int i = 0; i < r.nsplits; i++) {
        const cnPlanSplit *sp = &r.splits[i];
        CHECK(sp->side[0].n + sp->side[1].n == 4);
        unsigned mask[2] = {0, 0};
        for (int s = 0; s < 2; s++)
            for (int k = 0; k < sp->side[s].n; k++) mask[s] |= 1u << sp->side[s].idx[k];
        unsigned ab = 1u << part(a, "A") | 1u << part(a, "B"), cd = 1u << part(a, "C") | 1u << part(a, "D");
        if (sp->stable && ((mask[0] == ab && mask[1] == cd) || (mask[0] == cd && mask[1] == ab))) ab_cd = true;
    }
    CHECK_MSG(ab_cd, "the split {A-B, C-D} is not among the stable splits");
    /* by hand: A+B taken out gripping B (A rests on it; by A, B would fall) or held whole, C+D
     * likewise, and what stays then leaves the same way: 2 x 1 + 2 x 1 */
    CHECK(r.nplans == 4);
    /* no stable single-part sequence: every first move fails, by Proposition 1 here (the dead
     * ends are listed only when no plan at all is stable) */
    CHECK(r.nrows > 0 && r.ndead == 0);
    for (int i = 0; i < r.nrows; i++) {
        const cnPlanMove *m = &r.table[i].seq.steps[0];
        CHECK(r.table[i].end == CN_ROW_STEP_FAILS && r.table[i].seq.n == 1);
        CHECK(m->status == CN_STEP_UNSTABLE && m->proposition_1 && isnan(m->time) && m->moving.n >= 1);
    }
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* The two-handed plans of an assembly (subassemblies on, groups up to max_sub parts). */
static double two_handed(cnAssembly *a, int max_sub, cnPlanResult *r) {
    cnPlanOptions o = cn_plan_options_default();
    o.subassemblies = true;
    o.max_sub = max_sub;
    cnDiag d;
    if (cn_plan(a, &o, r, &d) != CN_OK) {
        CHECK_MSG(false, "plan failed: %s", d.message);
        memset(r, 0, sizeof *r);
        return -1;
    }
    CHECK(r->search.exhaustive && (r->nplans > 0) == (r->tree != NULL));
    return r->nplans;
}

/* Two cantilevers that hold each other up (examples/cantilevers.json): A on post P1, its right
 * end on B's left end; B on post P2, tipping alone. Counted by hand (parts A, B, P1, P2):
 *  - no part leaves alone (the others fall), and the group of all four has no grip to hang by;
 *  - {A, B} held whole: P1 and P2 stand; {P1, P2} comes apart in 2 orders, {A, B} in the air in
 *    1 way (either part taken from the other: one split), by A or by B it falls: 2 plans;
 *  - {A, B, P1} held whole, P2 stands: in the air B, P1 or B+P1 (held whole) is taken from the
 *    rest (by one part, a group falls off it): 3 plans; {A, B, P2} likewise: 3;
 *  - every other group leaves a cantilever without its post or post without its load bearer.
 * 8 in all; with groups of at most 2 parts, 2; of 1, none. The count does not depend on the
 * order of the parts in the file. */
static void test_plan_cantilevers(void) {
    cnAssembly *a = load_example("cantilevers");
    if (!a) return;
    cnPlanResult r;
    CHECK(two_handed(a, 0, &r) == 8);
    CHECK(r.stable && !r.stable_single_part && r.nsequences == 0);
    const cnPlanNode *t = r.tree;
    CHECK(t && t->split && !t->held_whole && t->held_by < 0);
    if (t && t->split) {
        /* the first tree takes A and B out held whole (no single grip carries the other) */
        CHECK(t->take_out.move.n == 2 && t->take_out.grip < 0 && t->take_out.status == CN_STEP_STABLE);
        CHECK(t->nchildren == 2 && t->children[0].held_whole && t->children[0].parts.n == 2);
        CHECK(t->children[1].parts.n == 2 && !t->children[1].held_whole && t->children[1].held_by < 0);
    }
    double total = 0;
    for (int i = 0; i < r.nsplits; i++) total += r.splits[i].nplans;
    CHECK(r.nsplits == 7 && total == 8);
    cn_plan_result_free(&r);
    CHECK(two_handed(a, 2, &r) == 2);
    cn_plan_result_free(&r);
    CHECK(two_handed(a, 1, &r) == 0 && !r.stable);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
    /* the same parts listed in reverse */
    cnAssembly *b = load_ok("{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
        "{\"name\":\"P2\",\"polygon\":[[5,0],[5.5,0],[5.5,3],[5,3]]},"
        "{\"name\":\"P1\",\"polygon\":[[0,0],[1,0],[1,4],[0,4]]},"
        "{\"name\":\"B\",\"polygon\":[[4,3],[8,3],[8,4],[4,4]]},"
        "{\"name\":\"A\",\"polygon\":[[0,4],[5,4],[5,5],[0,5]]},"
        "{\"name\":\"ground\",\"fixed\":true,\"polygon\":[[-2,-1],[10,-1],[10,0],[-2,0]]}]}");
    if (!b) return;
    CHECK(two_handed(b, 0, &r) == 8);
    cn_plan_result_free(&r);
    cn_assembly_free(b);
}

/* Held whole, a split {M | rest} is one split whichever side is taken out. A on B, C apart,
 * every part leaving straight up only (its file candidate): in the air {A, B} comes apart only by
 * taking A off. By hand: A out, then B and C in 2 orders (2); C out, then A-B by order, or A+B
 * lifted by B (2); A+B gripped by B (1), held whole (1); A+C held whole (1): 7, in either order
 * of the parts (the split once counted from the side that could not go: 6 and 7). And with 20
 * free parts the search is not exhaustive: its count is a lower bound and says so. */
static void test_plan_twin_splits(void) {
    const char *parts[4] = {
        "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-5,-1],[9,-1],[9,0],[-5,0]]}",
        "{\"name\":\"A\",\"polygon\":[[0,1],[2,1],[2,2],[0,2]]}",
        "{\"name\":\"B\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]}",
        "{\"name\":\"C\",\"polygon\":[[5,0],[6,0],[6,1],[5,1]]}"};
    for (int rev = 0; rev < 2; rev++) {
        char js[1024];
        snprintf(js, sizeof js, "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[%s,%s,%s,%s],"
                 "\"candidates\":{\"A\":{\"I\":[[0,5]]},\"B\":{\"I\":[[0,5]]},\"C\":{\"I\":[[0,5]]}}}",
                 parts[rev ? 3 : 0], parts[rev ? 2 : 1], parts[rev ? 1 : 2], parts[rev ? 0 : 3]);
        cnAssembly *a = load_ok(js);
        if (!a) return;
        cnPlanResult r;
        double n = two_handed(a, 0, &r);
        CHECK_MSG(n == 7, "twin splits, %s order: %g plans", rev ? "reversed" : "file", n);
        cn_plan_result_free(&r);
        cn_assembly_free(a);
    }
    /* five copies of the cantilevers side by side: 20 free parts */
    char big[8192];
    int len = snprintf(big, sizeof big, "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                       "{\"name\":\"g\",\"fixed\":true,\"polygon\":[[-2,-1],[60,-1],[60,0],[-2,0]]}");
    for (int k = 0; k < 5; k++) {
        double x = 11.0 * k;
        len += snprintf(big + len, sizeof big - (size_t)len,
                        ",{\"name\":\"A%d\",\"polygon\":[[%g,4],[%g,4],[%g,5],[%g,5]]}"
                        ",{\"name\":\"B%d\",\"polygon\":[[%g,3],[%g,3],[%g,4],[%g,4]]}"
                        ",{\"name\":\"P%d\",\"polygon\":[[%g,0],[%g,0],[%g,4],[%g,4]]}"
                        ",{\"name\":\"Q%d\",\"polygon\":[[%g,0],[%g,0],[%g,3],[%g,3]]}",
                        k, x, x + 5, x + 5, x, k, x + 4, x + 8, x + 8, x + 4, k, x, x + 1, x + 1, x,
                        k, x + 5, x + 5.5, x + 5.5, x + 5);
    }
    snprintf(big + len, sizeof big - (size_t)len, "]}");
    cnAssembly *a = load_ok(big);
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    o.subassemblies = true;
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK(r.stable && r.nplans >= 1 && !r.search.exhaustive);
    cn_plan_result_free(&r);
    /* a state budget binds inside a state's 2^20 groups too */
    o.max_states = 100;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK_MSG(r.search.budget_reached && r.search.states <= 200, "budget 100: %d states", r.search.states);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* Taking out one part at a time, the AND/OR count is the sequence search's count of stable
 * orders (two searches written apart); with groups allowed it can only grow. */
static void test_plan_count_orders(void) {
    const char *names[] = {"blocks", "books", "fig6", "fig14", "fig9", "exits", "slide_held", "fig17"};
    for (size_t i = 0; i < sizeof names / sizeof *names; i++) {
        cnAssembly *a = load_example(names[i]);
        if (!a) continue;
        cnPlanResult r;
        double one = two_handed(a, 1, &r);
        CHECK_MSG(one == r.norders, "%s: %g two-handed plans of single parts, %g stable orders",
                  names[i], one, r.norders);
        cn_plan_result_free(&r);
        double any = two_handed(a, 0, &r);
        CHECK_MSG(any >= one && r.stable == (any > 0), "%s: %g plans with groups, %g without", names[i], any, one);
        cn_plan_result_free(&r);
        cn_assembly_free(a);
    }
}

static bool same_move(const cnPlanMove *x, const cnPlanMove *y) {
    if (x->move.n != y->move.n || x->status != y->status || strcmp(x->path, y->path) || x->nseg != y->nseg) return false;
    for (int i = 0; i < x->move.n; i++)
        if (x->move.idx[i] != y->move.idx[i]) return false;
    return (x->time == y->time || (isnan(x->time) && isnan(y->time))) &&
           !memcmp(x->seg, y->seg, sizeof(cnSegment) * (size_t)x->nseg);
}

/* Two threads give the same result as one, move for move. */
static void test_plan_parallel_same(void) {
    cnAssembly *a = load_example("friction_drag"); /* friction: the worker thread uses GLPK */
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    o.all = true;
    cnPlanResult r1, r2;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r1, &d) == CN_OK);
    o.parallel = true;
    CHECK(cn_plan(a, &o, &r2, &d) == CN_OK);
    CHECK(r2.search.threads == 2 && r1.search.threads == 1);
    CHECK(r1.search.simulations == r2.search.simulations && r1.search.states == r2.search.states && r1.nrows == r2.nrows && r1.nlisted == r2.nlisted);
    int diff = 0;
    for (int i = 0; i < r1.nrows && i < r2.nrows; i++) {
        if (r1.table[i].end != r2.table[i].end || r1.table[i].seq.n != r2.table[i].seq.n) diff++;
        else
            for (int k = 0; k < r1.table[i].seq.n; k++) diff += !same_move(&r1.table[i].seq.steps[k], &r2.table[i].seq.steps[k]);
    }
    CHECK_MSG(diff == 0, "%d rows differ between one and two threads", diff);
    cn_plan_result_free(&r1);
    cn_plan_result_free(&r2);
    cn_assembly_free(a);
}

/* Undecided moves and states count as not stable: a block on a plank on a table (mu 0.3),
 * every candidate pushed, has stable orders by every path with the default search budget; with
 * a budget of one LP the sideways pushes of the block (its friction drags the plank) are
 * undecided, and the plans found are exactly those that avoid them
 * (a subset of the decided ones). A state that is undecided ends its rows as such, and the plan
 * is not called stable. */
static const char *PLANK =
    "{\"dimension\":2,\"friction\":0.3,\"parts\":["
    "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-4,-1],[12,-1],[12,0],[-4,0]]},"
    "{\"name\":\"plank\",\"polygon\":[[0,0],[10,0],[10,1],[0,1]]},"
    "{\"name\":\"block\",\"polygon\":[[4,1],[6,1],[6,2],[4,2]]}]}";

static void test_plan_undecided(void) {
    cnAssembly *a = load_ok(PLANK);
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    o.all = true;
    o.support = CN_PLAN_SUPPORT_PUSH; /* held, the block would press nothing (Proposition 2) */
    cnPlanResult full, low;
    cnDiag d;
    CHECK(cn_plan(a, &o, &full, &d) == CN_OK);
    o.sim.check.max_nodes = 1;
    CHECK(cn_plan(a, &o, &low, &d) == CN_OK);
    CHECK(full.stable && full.search.undecided_moves == 0 && full.search.undecided_states == 0);
    CHECK(low.stable && low.search.undecided_moves > 0 && low.search.undecided_states == 0);
    CHECK(low.nsequences < full.nsequences);
    int undecided_rows = 0;
    for (int i = 0; i < low.nrows; i++) {
        const cnPlanRow *row = &low.table[i];
        if (row->end != CN_ROW_STEP_FAILS) continue;
        undecided_rows += row->seq.steps[row->seq.n - 1].status == CN_STEP_UNDECIDED;
    }
    CHECK(undecided_rows == low.search.undecided_moves);
    /* every stable sequence found with the low budget is found with the full one */
    for (int i = 0; i < low.nlisted; i++) {
        bool found = false;
        for (int j = 0; j < full.nlisted && !found; j++) {
            const cnPlanSequence *x = &low.sequences[i], *y = &full.sequences[j];
            bool same = x->n == y->n;
            for (int k = 0; same && k < x->n; k++)
                same = !strcmp(x->steps[k].path, y->steps[k].path) &&
                       x->steps[k].move.idx[0] == y->steps[k].move.idx[0];
            found = same;
        }
        CHECK_MSG(found, "sequence %d of the low budget is not a decided one", i + 1);
    }
    cn_plan_result_free(&full);
    cn_plan_result_free(&low);
    cn_assembly_free(a);
}

/* Path dependence from the gripper's support (issue: Fig. 9 reported "path-independent" because
 * the planner held every candidate). With --support both, A taken off B along -Y (after C is
 * gone) is stable held and unstable pushed: pushed, its weight stays on B (mass 14, centre y =
 * 0, base y in [-0.5, 0.5]) and B tips about y = -0.5 when (8 y_A) / 22 = -0.5, y_A = -1.375:
 * after 0.375 of the path (A starts at y = -1). Without the option nothing is path-dependent. */
static void test_plan_support_both(void) {
    cnAssembly *a = load_example("fig9");
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    int dep = 0;
    for (int i = 0; i < r.nchoices; i++) dep += r.choices[i].path_dependent;
    CHECK_MSG(dep == 0, "%d path-dependent steps with the file's (held) candidates", dep);
    cn_plan_result_free(&r);
    o.support = CN_PLAN_SUPPORT_BOTH;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    int A = part(a, "A"), B = part(a, "B"), found = 0;
    for (int i = 0; i < r.nchoices; i++) {
        const cnPlanPathChoice *c = &r.choices[i];
        if (c->part != A || c->remaining.n != 2) continue;
        CHECK(c->path_dependent);
        for (int k = 0; k < c->paths.n; k++) {
            const cnPlanMove *m = &c->paths.steps[k];
            if (m->nseg != 1 || !(m->seg[0].move[1] < 0) || fabs(m->seg[0].move[0]) > 1e-9) continue;
            if (m->support == CN_SUPPORT_HOLD) {
                CHECK_MSG(m->status == CN_STEP_STABLE, "A held along -Y: status %d", (int)m->status);
                found |= 1;
            } else {
                CHECK_MSG(m->status == CN_STEP_UNSTABLE, "A pushed along -Y: status %d", (int)m->status);
                if (m->status == CN_STEP_UNSTABLE) CHECK_NEAR(m->time, 0.375, 1e-4);
                found |= 2;
                bool tips = false;
                for (int q = 0; q < m->moving.n; q++) tips |= m->moving.idx[q] == B;
                CHECK_MSG(tips, "A pushed along -Y: B does not tip");
            }
        }
    }
    CHECK_MSG(found == 3, "A along -Y held and pushed from {A, B}: found %d", found);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* The progress callback: called during the search (here at every budget check), with states
 * and simulations that only grow and never pass the result's totals. */
typedef struct {
    int calls;
    long states, sims;
    bool monotone;
} Progress;

static void count_progress(void *ctx, long states, long sims, double seconds) {
    Progress *p = ctx;
    if (states < p->states || sims < p->sims || !(seconds >= 0)) p->monotone = false;
    p->states = states, p->sims = sims, p->calls++;
}

static void test_plan_progress(void) {
    cnAssembly *a = load_example("fig6");
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    Progress pr = {0, 0, 0, true};
    o.progress = count_progress, o.progress_ctx = &pr, o.progress_every = 1e-12;
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK_MSG(pr.calls > 5 && pr.monotone && pr.states <= r.search.states && pr.sims <= r.search.simulations,
              "progress: %d calls, last %ld states %ld sims, of %d and %d", pr.calls, pr.states, pr.sims,
              r.search.states, r.search.simulations);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* ---- 3-D routes (paths3.c) ---- */

/* The housing of tests/cases/housing3d.json as boxes: floor, four walls, the lid around a hole
 * x in [2.5, 3.7], y in [0.3, 1.7] (or a whole lid), the block [0.5, 1.5]^2 x [0, 1] last. */
static const double HOUSING[][6] = {
    {-0.5, -0.5, -0.5, 4.5, 2.5, 0}, {-0.5, -0.5, 0, 0, 2.5, 1.5},  {4, -0.5, 0, 4.5, 2.5, 1.5},
    {0, -0.5, 0, 4, 0, 1.5},         {0, 2, 0, 4, 2.5, 1.5},        {-0.5, -0.5, 1.5, 2.5, 2.5, 1.8},
    {3.7, -0.5, 1.5, 4.5, 2.5, 1.8}, {2.5, -0.5, 1.5, 3.7, 0.3, 1.8}, {2.5, 1.7, 1.5, 3.7, 2.5, 1.8},
    {0.5, 0.5, 0, 1.5, 1.5, 1}};
#define HOUSING_N 10

/* Coordinates turned a quarter about x when `turn` (y -> z, z -> -y), with gravity. */
static void housing_map(const double p[3], int turn, double out[3]) {
    out[0] = p[0];
    out[1] = turn ? -p[2] : p[1];
    out[2] = turn ? p[1] : p[2];
}

/* The housing as JSON (boxes mapped by housing_map); `hole`: the lid has its hole. */
static char *housing_json(int hole, int turn) {
    size_t cap = 8192;
    char *s = malloc(cap);
    double g[3] = {0, 0, -1}, gm[3];
    housing_map(g, turn, gm);
    int n = snprintf(s, cap, "{\"dimension\":3,\"friction\":0.5,\"gravity\":[%g,%g,%g],\"parts\":[", gm[0],
                     gm[1], gm[2]);
    for (int b = 0; b < HOUSING_N; b++) {
        double lo[3], hi[3], box[6];
        memcpy(box, HOUSING[b], sizeof box);
        if (!hole && b == 5) box[3] = 4.5; /* the whole lid; the other lid boxes then overlap it */
        if (!hole && b > 5 && b < 9) continue;
        housing_map(box, turn, lo);
        housing_map(box + 3, turn, hi);
        for (int k = 0; k < 3; k++)
            if (lo[k] > hi[k]) {
                double t = lo[k];
                lo[k] = hi[k], hi[k] = t;
            }
        n += snprintf(s + n, cap - (size_t)n,
                      "%s{\"name\":\"%s\",%s\"box\":{\"min\":[%g,%g,%g],\"max\":[%g,%g,%g]}}",
                      b ? "," : "", b == HOUSING_N - 1 ? "block" : (const char *[]){"floor", "wall1", "wall2", "wall3", "wall4", "lid1", "lid2", "lid3", "lid4"}[b],
                      b == HOUSING_N - 1 ? "" : "\"fixed\":true,", lo[0], lo[1], lo[2], hi[0], hi[1],
                      hi[2]);
    }
    snprintf(s + n, cap - (size_t)n, "]}");
    return s;
}

/* An independent check of a route of the block: sampled finely, the block's box (moved) never
 * enters another box's interior by more than `tol`, and it ends above the lid (in the frame
 * before the turn). */
static bool route_clear(const double (*seg)[3], int nseg, int turn, double tol) {
    double at[3] = {0, 0, 0};
    const double *blk = HOUSING[HOUSING_N - 1];
    for (int l = 0; l < nseg; l++) {
        double d[3];
        /* back to the unturned frame: (x, y, z) -> (x, z, -y) */
        d[0] = seg[l][0], d[1] = turn ? seg[l][2] : seg[l][1], d[2] = turn ? -seg[l][1] : seg[l][2];
        for (int s = 0; s <= 400; s++) {
            double t = s / 400.0, o[3];
            for (int k = 0; k < 3; k++) o[k] = at[k] + t * d[k];
            for (int b = 0; b < HOUSING_N - 1; b++) {
                double depth = INFINITY;
                for (int k = 0; k < 3; k++)
                    depth = fmin(depth, fmin(blk[3 + k] + o[k] - HOUSING[b][k], HOUSING[b][3 + k] - (blk[k] + o[k])));
                if (depth > tol) return false;
            }
        }
        for (int k = 0; k < 3; k++) at[k] += d[k];
    }
    return blk[2] + at[2] > 1.8; /* out through the hole: above the lid */
}

static void test_routes3(void) {
    for (int turn = 0; turn <= 1; turn++) {
        char *js = housing_json(1, turn);
        cnAssembly *a = load_ok(js);
        free(js);
        if (!a) return;
        unsigned char *mv = calloc((size_t)a->nparts, 1);
        mv[part(a, "block")] = 1;
        double segs[4][CN_ROUTE_MAX_SEGMENTS][3];
        int nseg[4], nr = 0;
        cnDiag d;
        CHECK(cn_paths3(a, NULL, mv, 4, segs, nseg, &nr, &d) == CN_OK);
        /* no straight line leaves (the lid is over the block, the walls around it); a route
         * slides under the lid to the hole and rises: at least two legs */
        CHECK(nr >= 1);
        for (int r = 0; r < nr; r++) {
            CHECK(nseg[r] >= 2);
            CHECK(route_clear((const double(*)[3])segs[r], nseg[r], turn, a->contact_tol));
        }
        /* the planner takes it, and the simulator replays it stably */
        cnPlanOptions o = cn_plan_options_default();
        cnPlanResult res;
        CHECK(cn_plan(a, &o, &res, &d) == CN_OK);
        CHECK(res.stable && res.best_plan);
        if (res.best_plan) {
            CHECK(res.best_plan->n == 1 && res.best_plan->steps[0].nseg >= 2);
            CHECK(cn_test_replay_stable(a, res.best_plan));
        }
        cn_plan_result_free(&res);
        free(mv);
        cn_assembly_free(a);
    }
    /* a whole lid: nothing leaves, and no route is offered */
    char *js = housing_json(0, 0);
    cnAssembly *a = load_ok(js);
    free(js);
    if (!a) return;
    unsigned char *mv = calloc((size_t)a->nparts, 1);
    mv[part(a, "block")] = 1;
    double segs[4][CN_ROUTE_MAX_SEGMENTS][3];
    int nseg[4], nr = -1;
    cnDiag d;
    CHECK(cn_paths3(a, NULL, mv, 4, segs, nseg, &nr, &d) == CN_OK);
    CHECK(nr == 0);
    free(mv);
    cn_assembly_free(a);
}

/* ---- past the exhaustive search (more than 16 free parts) ---- */


/* Plans ranked by their margins: a column 1 x 3 beside a block 2 x 1 (mu 0.6). Taken first, the
 * block leaves the column alone (it tips at b/h = 1/3 g, a tilt of atan 1/3); taken first, the
 * column leaves the block (it slides at mu = 0.6 g, atan 0.6). Ranked by lateral and by tilt,
 * every column-first sequence comes before every block-first one, with those values; by the
 * critical friction (0 for all: both stand without friction) the planner's order is kept. */
static void test_plan_margins(void) {
    const char *json = "{\"dimension\":2,\"gravity\":[0,-1],\"friction\":0.6,\"parts\":["
                       "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                       "{\"name\":\"column\",\"polygon\":[[0,0],[1,0],[1,3],[0,3]]},"
                       "{\"name\":\"block\",\"polygon\":[[1,0],[3,0],[3,1],[1,1]]}]}";
    cnAssembly *a = load_ok(json);
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    cnMarginOptions mo = cn_margin_options_default();
    mo.rel_tol = 1e-6;
    cnSimOptions so = cn_sim_options_default();
    so.margin = &mo;
    const int ranks[3] = {CN_MARGIN_LATERAL, CN_MARGIN_TILT, CN_MARGIN_FRICTION};
    const double want_hi[3] = {0.6, atan(0.6), 0}, want_lo[3] = {1.0 / 3, atan(1.0 / 3), 0};
    for (int t = 0; t < 3 && r.nlisted > 1; t++) {
        cnPlanMargin *m = NULL;
        int n = 0;
        mo.kinds = (unsigned)ranks[t]; /* the kind ranked by only: a third of the work */
        CHECK(cn_plan_margins(a, &r, &so, ranks[t], &m, &n, &d) == CN_OK);
        CHECK(n == r.nlisted);
        int k = t == 0 ? 2 : t == 1 ? 1 : 0;
        bool block_seen = false;
        for (int i = 0; i < n; i++) {
            CHECK(m[i].status == CN_STEP_STABLE && m[i].weakest_step[k] >= 0);
            const char *first = a->parts[r.sequences[m[i].sequence].steps[0].move.idx[0]].name;
            bool column_first = !strcmp(first, "column");
            double v = m[i].weakest[k].at.value, want = column_first ? want_hi[t] : want_lo[t];
            CHECK_MSG(fabs(v - want) <= 2e-6 * fmax(want, 1e-9), "rank %d, %s first: %.9g, want %.9g", t, first, v, want);
            if (t < 2) CHECK_MSG(!(column_first && block_seen), "rank %d: a column-first sequence after a block-first one", t);
            else CHECK(i == 0 || m[i].sequence > m[i - 1].sequence);
            block_seen |= !column_first;
        }
        cn_plan_margins_free(m, n);
    }
    cnPlanMargin *m = NULL;
    int n = 0;
    so.margin = NULL;
    CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_LATERAL, &m, &n, &d) == CN_ERR_INPUT && !m);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* visibility.c: the lazily tested Dijkstra against Floyd-Warshall over every leg tested, on
 * random point sets in 2-D and 3-D whose legs are blocked by a fixed hash of the pair (each leg
 * blocked or not the same both ways). */
typedef struct {
    unsigned seed;
    const double *node;
    int dim, m;
} VisCtx;

static int vis_index(const VisCtx *c, const double *p) {
    return (int)((p - c->node) / c->dim);
}
static bool vis_blocked(void *ctx, const double *a, const double *b) {
    const VisCtx *c = ctx;
    unsigned i = (unsigned)vis_index(c, a), j = (unsigned)vis_index(c, b);
    if (i > j) {
        unsigned t = i;
        i = j, j = t;
    }
    unsigned h = (i * 2654435761u) ^ (j * 40503u) ^ c->seed;
    h ^= h >> 13, h *= 0x5bd1e995u, h ^= h >> 15;
    return h % 100 < 55; /* most legs blocked: paths of several legs */
}

static double vis_len(const double *a, const double *b, int dim) {
    double w = 0;
    for (int k = 0; k < dim; k++) w += (a[k] - b[k]) * (a[k] - b[k]);
    return sqrt(w);
}

static void test_vis_dijkstra(void) {
    unsigned long long s = 99;
    for (int t = 0; t < 40; t++) {
        int dim = 2 + t % 2, m = 5 + t % 20;
        double node[24 * 3];
        for (int i = 0; i < m * dim; i++) {
            s = s * 6364136223846793005ULL + 1442695040888963407ULL;
            node[i] = (double)(s >> 11) / 9007199254740992.0 * 10;
        }
        VisCtx c = {(unsigned)t * 7919u, node, dim, m};
        cnVisGraph g = {dim, node, m, m, m, false, vis_blocked, &c};
        double dist[24], fw[24][24];
        int prev[24];
        unsigned char done[24];
        cn_vis_dijkstra(&g, dist, prev, done);
        for (int i = 0; i < m; i++)
            for (int j = 0; j < m; j++) {
                const double *a = node + i * dim, *b = node + j * dim;
                fw[i][j] = i == j ? 0 : vis_blocked(&c, a, b) ? INFINITY : vis_len(a, b, dim);
            }
        for (int k = 0; k < m; k++)
            for (int i = 0; i < m; i++)
                for (int j = 0; j < m; j++)
                    if (fw[i][k] + fw[k][j] < fw[i][j]) fw[i][j] = fw[i][k] + fw[k][j];
        bool same = true, chain = true;
        for (int v = 0; v < m; v++) {
            same &= isinf(fw[0][v]) ? isinf(dist[v]) : fabs(dist[v] - fw[0][v]) <= 1e-12 * (1 + fw[0][v]);
            /* prev walks back to node 0 over unblocked legs, adding up to dist */
            if (v == 0 || isinf(dist[v])) continue;
            double len = 0;
            int u = v, steps = 0;
            while (u != 0 && prev[u] >= 0 && steps++ < m) {
                const double *a = node + prev[u] * dim, *b = node + u * dim;
                chain &= !vis_blocked(&c, a, b);
                len += vis_len(a, b, dim);
                u = prev[u];
            }
            chain &= u == 0 && fabs(len - dist[v]) <= 1e-12 * (1 + len);
        }
        CHECK_MSG(same, "Dijkstra against Floyd-Warshall, %d-D, %d nodes", dim, m);
        CHECK_MSG(chain, "paths back to the start, %d-D, %d nodes", dim, m);
    }
}

void test_plan(void) {
    test_vis_dijkstra();
    test_plan_margins();
    test_routes3();
    test_plan_progress();
    test_plan_support_both();
    test_plan_blocks();
    test_plan_undecided();
    test_plan_subassemblies();
    test_plan_cantilevers();
    test_plan_count_orders();
    test_plan_twin_splits();
    test_plan_parallel_same();
    test_arcs();
    test_free_directions_public();
    test_sweep_agrees();
}
