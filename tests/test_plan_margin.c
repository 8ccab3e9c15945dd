/* Unit tests of src/plan/plan_margin.c (cn_plan_margins): each stable sequence the planner lists,
 * simulated with margins, ranked strongest first by its weakest step. The scenes are tiny 2-D
 * assemblies whose stable orders and margins follow by hand: a column (1 x 4) on a table beside a
 * flat block on a 20-degree incline, apart (mu 1); a block on a block (mu 0.5); two lone columns
 * whose lateral margins differ by 1e-3. Each sequence's weakest margins are checked against those
 * formulas and against cn_simulate run on the sequence written as a plan of the test's own (the
 * weakest being the extreme over its steps); the rankings against the order the formulas give,
 * ties in the planner's order; sequences made by hand that fail (unstable, infeasible) ranked last
 * without margins; the rank argument and the options, the limit of CN_PLAN_MARGIN_MAX sequences,
 * an empty result; and the ranking by part names unchanged when the parts are listed in another
 * order or the scene is moved. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "cairn/cairn.h"
#include "helpers.h"

#define DEG (180 / 3.14159265358979323846)
/* The margins are asked to 1e-6 (relative); the values are the stable ends of their brackets. */
#define MARGIN_TOL 1e-6
#define NEAR(v, want) (fabs((v) - (want)) <= 3 * MARGIN_TOL * fmax(fabs(want), 1e-6))
#define MAXSTEPS 4

static int part(const cnAssembly *a, const char *name) {
    return cn_assembly_find_part(a, name);
}

/* A column X (1 wide, 4 high) on a table, and a flat block Y (4 x 0.5) on a fixed wedge whose
 * slope rises 20 degrees to the right, out of each other's reach (mu 1, gravity -y); every part
 * moved by (dx, dy), listed in reverse when `reorder`. Candidates: X straight up; Y straight up
 * and, when `two_paths`, along the slope's normal. By hand (Y alone: the block slides down the
 * slope when the load turns past atan(mu) = 45 degrees from the slope's normal; X alone: the
 * column tips over its edge at b/h = 1/4 before it slides at mu = 1):
 *   Y alone: critical friction tan 20, tilt 45 - 20 = 25 degrees, lateral tan 25 g;
 *   X alone: critical friction 0 (it stands frictionless), tilt atan 1/4, lateral 1/4 g.
 * Both orders are stable; the first step leaves the other part alone, the second nothing. */
static char *scene_incline(double dx, double dy, bool reorder, bool two_paths) {
    double c = cos(20 / DEG), s = sin(20 / DEG);
    char parts[4][320];
    snprintf(parts[0], sizeof parts[0],
             "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],"
             "[%.17g,%.17g]]}",
             -5 + dx, -1 + dy, 9 + dx, -1 + dy, 9 + dx, dy, -5 + dx, dy);
    snprintf(parts[1], sizeof parts[1],
             "{\"name\":\"wedge\",\"fixed\":true,\"polygon\":[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]]}",
             dx, dy, 8 * c + dx, dy, 8 * c + dx, 8 * s + dy);
    snprintf(parts[2], sizeof parts[2],
             "{\"name\":\"X\",\"polygon\":[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]]}",
             -4 + dx, dy, -3 + dx, dy, -3 + dx, 4 + dy, -4 + dx, 4 + dy);
    double U[4] = {2, 6, 6, 2}, V[4] = {0, 0, 0.5, 0.5}; /* along the slope, off it */
    int n = snprintf(parts[3], sizeof parts[3], "{\"name\":\"Y\",\"polygon\":[");
    for (int k = 0; k < 4; k++)
        n += snprintf(parts[3] + n, sizeof parts[3] - (size_t)n, "%s[%.17g,%.17g]", k ? "," : "",
                      U[k] * c - V[k] * s + dx, U[k] * s + V[k] * c + dy);
    snprintf(parts[3] + n, sizeof parts[3] - (size_t)n, "]}");
    char ycand[128];
    if (two_paths)
        snprintf(ycand, sizeof ycand, "\"up\":[[0,6]],\"normal\":[[%.17g,%.17g]]", -3 * s, 3 * c);
    else
        snprintf(ycand, sizeof ycand, "\"up\":[[0,6]]");
    char *buf = malloc(4096);
    int p = reorder ? 3 : 0, q = reorder ? -1 : 1;
    snprintf(buf, 4096,
             "{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":1,\"parts\":[%s,%s,%s,%s],"
             "\"candidates\":{\"X\":{\"up\":[[0,6]]},\"Y\":{%s}}}",
             parts[p], parts[p + q], parts[p + 2 * q], parts[p + 3 * q], ycand);
    return buf;
}

/* A block 2 wide and 1 high on the table, a column 1 x 2 standing on it (mu 0.5). By hand the
 * only stable order is top, then base (the base cannot leave from under the top); the top
 * lifted leaves the base alone: it slides at mu = 0.5 g (it tips at b/h = 2), tilt atan 0.5,
 * critical friction 0. */
static const char *STACK = "{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":0.5,\"parts\":["
                           "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                           "{\"name\":\"base\",\"polygon\":[[-1,0],[1,0],[1,1],[-1,1]]},"
                           "{\"name\":\"top\",\"polygon\":[[-0.5,1],[0.5,1],[0.5,3],[-0.5,3]]}],"
                           "\"candidates\":{\"top\":{\"up\":[[0,5]]},"
                           "\"base\":{\"up\":[[0,5]],\"left\":[[-3,0]]}}}";

static cnSimOptions sim_options(cnMarginOptions *mo, unsigned kinds, int samples) {
    *mo = cn_margin_options_default();
    mo->kinds = kinds;
    mo->rel_tol = MARGIN_TOL;
    cnSimOptions so = cn_sim_options_default();
    so.margin = mo;
    so.margin_samples = samples;
    return so;
}

static bool plan_ok(const cnAssembly *a, cnPlanResult *r) {
    cnPlanOptions o = cn_plan_options_default();
    cnDiag d;
    if (cn_plan(a, &o, r, &d) != CN_OK) {
        CHECK_MSG(false, "cn_plan: %s: %s", d.where, d.message);
        memset(r, 0, sizeof *r);
        return false;
    }
    return true;
}

static const char *first_part(const cnAssembly *a, const cnPlanSequence *s) {
    return a->parts[s->steps[0].move.idx[0]].name;
}

/* A sequence by part and path names, e.g. "X/up Y/normal". */
static void seq_name(const cnAssembly *a, const cnPlanSequence *s, char *buf, size_t cap) {
    size_t n = 0;
    buf[0] = 0;
    for (int i = 0; i < s->n && n < cap; i++)
        for (int j = 0; j < s->steps[i].move.n && n < cap; j++)
            n += (size_t)snprintf(buf + n, cap - n, "%s%s/%s", n ? " " : "",
                                  a->parts[s->steps[i].move.idx[j]].name, s->steps[i].path);
}

/* The oracle of a sequence: `json` with the sequence appended as its "plan" (each step's parts,
 * gripped, along its path's displacements, held or pushed), loaded and simulated with margins by
 * cn_simulate, as `cairn simulate --plan --margin` would. Per step its status and each kind's
 * margin (NAN where none). Returns the steps simulated, -1 on failure. */
static int simulate_plan(const char *json, const cnAssembly *a, const cnPlanSequence *seq,
                         const cnSimOptions *so, cnStepStatus status[MAXSTEPS], double v[MAXSTEPS][3]) {
    size_t cap = strlen(json) + 4096, n = strlen(json) - 1; /* json ends with its closing brace */
    char *buf = malloc(cap);
    memcpy(buf, json, n);
    n += (size_t)snprintf(buf + n, cap - n, ",\"plan\":[");
    for (int i = 0; i < seq->n; i++) {
        const cnPlanMove *m = &seq->steps[i];
        n += (size_t)snprintf(buf + n, cap - n, "%s{\"move\":[", i ? "," : "");
        for (int j = 0; j < m->move.n; j++)
            n += (size_t)snprintf(buf + n, cap - n, "%s\"%s\"", j ? "," : "", a->parts[m->move.idx[j]].name);
        n += (size_t)snprintf(buf + n, cap - n, "],\"path\":[");
        for (int k = 0; k < m->nseg; k++) {
            CHECK(m->seg[k].kind == CN_SEGMENT_MOVE);
            n += (size_t)snprintf(buf + n, cap - n, "%s[%.17g,%.17g]", k ? "," : "", m->seg[k].move[0],
                                  m->seg[k].move[1]);
        }
        n += (size_t)snprintf(buf + n, cap - n, "],\"support\":\"%s\"}",
                              m->support == CN_SUPPORT_PUSH ? "push" : "hold");
    }
    snprintf(buf + n, cap - n, "]}");
    cnAssembly *b = load_ok(buf);
    free(buf);
    if (!b) return -1;
    cnSimResult R;
    cnDiag d;
    int steps = -1;
    if (cn_simulate(b, so, &R, &d) == CN_OK) {
        steps = R.nsteps < MAXSTEPS ? R.nsteps : MAXSTEPS;
        for (int s = 0; s < steps; s++) {
            status[s] = R.steps[s].status;
            for (int k = 0; k < 3; k++)
                v[s][k] = R.steps[s].margin[k].computed ? R.steps[s].margin[k].at.value : NAN;
        }
        cn_sim_result_free(&R);
    } else
        CHECK_MSG(false, "cn_simulate: %s: %s", d.where, d.message);
    cn_assembly_free(b);
    return steps;
}

/* Is x weaker than y for kind index k (a larger critical friction, a smaller tilt or lateral)? */
static bool weaker(int k, double x, double y) {
    return k == 0 ? x > y : x < y;
}

/* Each entry of m against the oracle: a stable sequence's weakest value of each asked kind is the
 * extreme over its steps' values from cn_simulate, its weakest step one that has that value and
 * none of its steps weaker; kinds not asked have none. */
static void check_against_simulate(const char *json, const cnAssembly *a, const cnPlanResult *r,
                                   const cnSimOptions *so, unsigned kinds, const cnPlanMargin *m, int n) {
    for (int i = 0; i < n; i++) {
        const cnPlanSequence *seq = &r->sequences[m[i].sequence];
        cnStepStatus st[MAXSTEPS];
        double v[MAXSTEPS][3];
        int steps = simulate_plan(json, a, seq, so, st, v);
        CHECK(steps == seq->n);
        if (steps != seq->n) continue;
        for (int k = 0; k < 3; k++) {
            int w = m[i].weakest_step[k];
            if (!(kinds & (1u << k)) || m[i].status != CN_STEP_STABLE) {
                CHECK_MSG(w == -1 && !m[i].weakest[k].computed, "sequence %d kind %d: a margin not asked for",
                          m[i].sequence, k);
                continue;
            }
            CHECK_MSG(w >= 0 && w < steps && m[i].weakest[k].computed, "sequence %d kind %d: step %d",
                      m[i].sequence, k, w);
            if (w < 0 || w >= steps) continue;
            double got = m[i].weakest[k].at.value, ext = v[0][k];
            for (int s = 1; s < steps; s++)
                if (weaker(k, v[s][k], ext)) ext = v[s][k];
            CHECK_MSG(got == ext, "sequence %d kind %d: weakest %.17g, the extreme of its steps %.17g",
                      m[i].sequence, k, got, ext);
            CHECK_MSG(v[w][k] == got, "sequence %d kind %d: step %d has %.17g, not the weakest %.17g",
                      m[i].sequence, k, w, v[w][k], got);
        }
    }
}

/* The planner's sequences ranked by hand: those whose first part is `stronger` first, then the
 * others, each group in the planner's order (ties). */
static void ranked_by_hand(const cnAssembly *a, const cnPlanResult *r, const char *stronger, int *want) {
    int n = 0;
    for (int g = 0; g < 2; g++)
        for (int i = 0; i < r->nlisted; i++)
            if ((strcmp(first_part(a, &r->sequences[i]), stronger) == 0) == (g == 0)) want[n++] = i;
}

/* The column and the inclined block, both Y paths: 4 sequences (X first: 1 path for X, 2 for Y
 * after; Y first: 2 for Y, then X). Every weakest margin is its first step's (the second leaves
 * nothing: no friction needed, tilt 90 degrees, lateral 1,000 g), with the values by hand above;
 * ranked by lateral and by tilt the X-first sequences come first, by the critical friction (the
 * least first) the Y-first ones; equal sequences in the planner's order. */
static void test_ranked_by_hand(void) {
    char *json = scene_incline(0, 0, false, true);
    cnAssembly *a = load_ok(json);
    cnPlanResult r;
    if (!a || !plan_ok(a, &r)) {
        cn_assembly_free(a);
        free(json);
        return;
    }
    CHECK(r.stable && r.norders == 2);
    CHECK_MSG(r.nlisted == 4, "%d sequences listed", r.nlisted);
    const double th = 20 / DEG;
    const double y_alone[3] = {tan(th), 45 / DEG - th, tan(45 / DEG - th)}; /* after X */
    const double x_alone[3] = {0, atan(0.25), 0.25};                        /* after Y */
    const int ranks[3] = {CN_MARGIN_LATERAL, CN_MARGIN_TILT, CN_MARGIN_FRICTION};
    for (int t = 0; t < 3 && r.nlisted == 4; t++) {
        cnMarginOptions mo;
        unsigned kinds = t == 0 ? CN_MARGIN_ALL : (unsigned)ranks[t];
        cnSimOptions so = sim_options(&mo, kinds, 3);
        cnPlanMargin *m = NULL;
        int n = 0;
        cnDiag d;
        CHECK(cn_plan_margins(a, &r, &so, ranks[t], &m, &n, &d) == CN_OK);
        CHECK(n == 4);
        int want[4];
        ranked_by_hand(a, &r, ranks[t] == CN_MARGIN_FRICTION ? "Y" : "X", want);
        for (int i = 0; i < n && n == 4; i++) {
            CHECK_MSG(m[i].sequence == want[i], "rank %d, place %d: sequence %d, by hand %d", ranks[t], i,
                      m[i].sequence, want[i]);
            CHECK(m[i].status == CN_STEP_STABLE && m[i].failed_step == -1);
            bool x_first = !strcmp(first_part(a, &r.sequences[m[i].sequence]), "X");
            for (int k = 0; k < 3; k++) {
                if (!(kinds & (1u << k))) continue;
                double v = m[i].weakest[k].at.value, h = x_first ? y_alone[k] : x_alone[k];
                CHECK_MSG(NEAR(v, h), "sequence %d kind %d: %.12g, by hand %.12g", m[i].sequence, k, v, h);
                /* the first step is the weakest, strictly (X first: critical friction tan 20 > 0) */
                if (k > 0 || x_first)
                    CHECK_MSG(m[i].weakest_step[k] == 0, "kind %d: step %d", k, m[i].weakest_step[k]);
                CHECK(m[i].weakest[k].samples >= 1 && m[i].weakest[k].samples <= 3);
            }
        }
        check_against_simulate(json, a, &r, &so, kinds, m, n);
        cn_plan_margins_free(m, n);
    }
    cn_plan_result_free(&r);
    cn_assembly_free(a);
    free(json);
}

static cnPlanMove hand_move(const int *idx, const char *path, const cnSegment *seg) {
    cnPlanMove m;
    memset(&m, 0, sizeof m);
    m.move.n = 1;
    m.move.idx = idx;
    m.path = path;
    m.nseg = 1;
    m.seg = seg;
    m.support = CN_SUPPORT_HOLD;
    m.grip = -1;
    m.status = CN_STEP_STABLE;
    m.blocked_by = -1;
    return m;
}

/* The stack: the planner's 2 sequences (top, then base up or left) are equally strong, lateral
 * mu = 0.5 g and tilt atan 0.5 at their first step: the planner's order. Then sequences written
 * by hand: base slid left first (the top, dragged, moves: unstable at step 1), top up then base
 * down into the table (infeasible at step 2: its first step's margins are dropped), and the two
 * stable ones. The stable ones come first, in their order; the failed ones last, in theirs, with
 * their status and step as cn_simulate finds them and no margin. */
static void test_stack_and_failures(void) {
    cnAssembly *a = load_ok(STACK);
    cnPlanResult r;
    if (!a || !plan_ok(a, &r)) {
        cn_assembly_free(a);
        return;
    }
    CHECK(r.norders == 1 && r.nlisted == 2);
    for (int i = 0; i < r.nlisted; i++)
        CHECK(!strcmp(first_part(a, &r.sequences[i]), "top"));
    cnMarginOptions mo;
    const unsigned kinds = CN_MARGIN_LATERAL | CN_MARGIN_TILT;
    cnSimOptions so = sim_options(&mo, kinds, 2);
    cnPlanMargin *m = NULL;
    int n = 0;
    cnDiag d;
    CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_TILT, &m, &n, &d) == CN_OK);
    CHECK(n == 2);
    for (int i = 0; i < n; i++) {
        CHECK(m[i].sequence == i);
        CHECK(m[i].status == CN_STEP_STABLE && m[i].weakest_step[1] == 0 && m[i].weakest_step[2] == 0);
        CHECK_MSG(NEAR(m[i].weakest[2].at.value, 0.5), "lateral %.12g", m[i].weakest[2].at.value);
        CHECK_MSG(NEAR(m[i].weakest[1].at.value, atan(0.5)), "tilt %.12g", m[i].weakest[1].at.value);
    }
    check_against_simulate(STACK, a, &r, &so, kinds, m, n);
    cn_plan_margins_free(m, n);

    int ib = part(a, "base"), it = part(a, "top");
    cnSegment up = {CN_SEGMENT_MOVE, {0, 5, 0}, 0, {0, 0, 1}, {0, 0, 0}};
    cnSegment left = {CN_SEGMENT_MOVE, {-3, 0, 0}, 0, {0, 0, 1}, {0, 0, 0}};
    cnSegment down = {CN_SEGMENT_MOVE, {0, -3, 0}, 0, {0, 0, 1}, {0, 0, 0}};
    cnPlanMove mv[4][2] = {{hand_move(&ib, "left", &left), hand_move(&it, "up", &up)},
                           {hand_move(&it, "up", &up), hand_move(&ib, "down", &down)},
                           {hand_move(&it, "up", &up), hand_move(&ib, "up", &up)},
                           {hand_move(&it, "up", &up), hand_move(&ib, "left", &left)}};
    cnPlanSequence seqs[4];
    for (int i = 0; i < 4; i++)
        seqs[i].n = 2, seqs[i].steps = mv[i];
    cnPlanResult hand;
    memset(&hand, 0, sizeof hand);
    hand.nlisted = 4;
    hand.sequences = seqs;
    CHECK(cn_plan_margins(a, &hand, &so, CN_MARGIN_LATERAL, &m, &n, &d) == CN_OK);
    CHECK(n == 4);
    const int want[4] = {2, 3, 0, 1};
    const cnStepStatus want_status[4] = {CN_STEP_STABLE, CN_STEP_STABLE, CN_STEP_UNSTABLE,
                                         CN_STEP_INFEASIBLE};
    const int want_failed[4] = {-1, -1, 0, 1};
    for (int i = 0; i < n && n == 4; i++) {
        CHECK_MSG(m[i].sequence == want[i], "place %d: sequence %d, by hand %d", i, m[i].sequence, want[i]);
        CHECK_MSG(m[i].status == want_status[i] && m[i].failed_step == want_failed[i],
                  "place %d: status %d at %d", i, m[i].status, m[i].failed_step);
        for (int k = 1; k < 3; k++)
            if (i < 2)
                CHECK(m[i].weakest_step[k] == 0 && NEAR(m[i].weakest[k].at.value, k == 1 ? atan(0.5) : 0.5));
            else
                CHECK(m[i].weakest_step[k] == -1 && !m[i].weakest[k].computed &&
                      m[i].weakest[k].at.value == 0);
    }
    check_against_simulate(STACK, a, &hand, &so, kinds, m, n);
    /* the oracle's statuses of the failing ones */
    for (int i = 0; i < 2; i++) {
        cnStepStatus st[MAXSTEPS];
        double v[MAXSTEPS][3];
        int steps = simulate_plan(STACK, a, &seqs[i], &so, st, v);
        CHECK(steps >= want_failed[i + 2] + 1 && st[want_failed[i + 2]] == want_status[i + 2]);
        if (i == 1) CHECK(st[0] == CN_STEP_STABLE && NEAR(v[0][2], 0.5)); /* dropped, not missing */
    }
    cn_plan_margins_free(m, n);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* Two lone columns 1 wide on a table, P 4 high and Q 4 / (1 + 1e-3) high: the lateral margin of
 * the one left standing is b/h, 1/4 for P and 1/4 (1 + 1e-3) for Q. Found to 1e-7 the sequence
 * that leaves Q (P first) is stronger and comes first; found to 1e-3 each value is within 1e-3
 * below its own, so the two are within twice that of each other: equal, in the planner's order. */
static void test_near_tie(void) {
    char json[1024];
    snprintf(json, sizeof json,
             "{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":1,\"parts\":["
             "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
             "{\"name\":\"Q\",\"polygon\":[[2,0],[3,0],[3,%.17g],[2,%.17g]]},"
             "{\"name\":\"P\",\"polygon\":[[-4,0],[-3,0],[-3,4],[-4,4]]}],"
             "\"candidates\":{\"P\":{\"up\":[[0,6]]},\"Q\":{\"up\":[[0,6]]}}}",
             4 / (1 + 1e-3), 4 / (1 + 1e-3));
    cnAssembly *a = load_ok(json);
    cnPlanResult r;
    if (!a || !plan_ok(a, &r)) {
        cn_assembly_free(a);
        return;
    }
    CHECK(r.nlisted == 2);
    for (int t = 0; t < 2 && r.nlisted == 2; t++) {
        cnMarginOptions mo;
        cnSimOptions so = sim_options(&mo, CN_MARGIN_LATERAL, 2);
        mo.rel_tol = t ? 1e-3 : 1e-7;
        cnPlanMargin *m = NULL;
        int n = 0;
        cnDiag d;
        CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_LATERAL, &m, &n, &d) == CN_OK);
        CHECK(n == 2);
        if (n == 2) {
            bool p0 = !strcmp(first_part(a, &r.sequences[m[0].sequence]), "P");
            if (t == 0) {
                CHECK_MSG(p0, "found to 1e-7, the sequence leaving Q is not first");
                CHECK_NEAR(m[0].weakest[2].at.value, 0.25 * (1 + 1e-3), 3e-7 * 0.25);
                CHECK_NEAR(m[1].weakest[2].at.value, 0.25, 3e-7 * 0.25);
            } else {
                CHECK_MSG(m[0].sequence == 0 && m[1].sequence == 1, "found to 1e-3: not the planner's order");
                /* the values found differ (so the tolerance is what makes them equal) */
                double x = m[0].weakest[2].at.value, y = m[1].weakest[2].at.value;
                CHECK_MSG(x != y && fabs(x - y) <= 2e-3 * fmax(x, y), "found to 1e-3: %.17g and %.17g", x, y);
            }
        }
        cn_plan_margins_free(m, n);
    }
    /* the test means something only when the planner lists the weaker first */
    CHECK(r.nlisted == 2 && !strcmp(first_part(a, &r.sequences[0]), "Q"));
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

/* The column and the inclined block with one path each, as loaded, with its parts listed in
 * reverse, and moved by (37.5, -12.25): ranked by lateral and by critical friction, the same
 * sequences by part and path names in the same places, with the same weakest margins. */
static void test_invariance(void) {
    char names[2][3][2][64];
    double vals[2][3][2];
    int count[2][3] = {{0}};
    for (int v = 0; v < 3; v++) {
        char *json = scene_incline(v == 2 ? 37.5 : 0, v == 2 ? -12.25 : 0, v == 1, false);
        cnAssembly *a = load_ok(json);
        cnPlanResult r;
        if (a && plan_ok(a, &r)) {
            CHECK(r.nlisted == 2);
            for (int t = 0; t < 2; t++) {
                int rank = t ? CN_MARGIN_FRICTION : CN_MARGIN_LATERAL, k = t ? 0 : 2;
                cnMarginOptions mo;
                cnSimOptions so = sim_options(&mo, (unsigned)rank, 2);
                cnPlanMargin *m = NULL;
                int n = 0;
                cnDiag d;
                CHECK(cn_plan_margins(a, &r, &so, rank, &m, &n, &d) == CN_OK);
                count[t][v] = n;
                for (int i = 0; i < n && i < 2; i++) {
                    seq_name(a, &r.sequences[m[i].sequence], names[t][v][i], sizeof names[t][v][i]);
                    vals[t][v][i] = m[i].weakest[k].at.value;
                }
                cn_plan_margins_free(m, n);
            }
            cn_plan_result_free(&r);
        }
        cn_assembly_free(a);
        free(json);
    }
    for (int t = 0; t < 2; t++) {
        /* as loaded, by hand: lateral X first (tan 25 over 1/4), friction Y first (0 under tan 20) */
        CHECK(count[t][0] == 2);
        if (count[t][0] == 2)
            CHECK_MSG(!strcmp(names[t][0][0], t ? "Y/up X/up" : "X/up Y/up"), "%s", names[t][0][0]);
        for (int v = 1; v < 3; v++) {
            CHECK(count[t][v] == count[t][0]);
            for (int i = 0; i < count[t][0] && i < count[t][v]; i++) {
                CHECK_MSG(!strcmp(names[t][v][i], names[t][0][i]),
                          "variant %d, rank %d, place %d: %s, as loaded %s", v, t, i, names[t][v][i],
                          names[t][0][i]);
                CHECK_MSG(NEAR(vals[t][v][i], vals[t][0][i]),
                          "variant %d, rank %d, place %d: %.12g, as loaded %.12g", v, t, i, vals[t][v][i],
                          vals[t][0][i]);
            }
        }
    }
}

/* The rank argument and the options: no margin options, a rank that is not a kind or not asked
 * for are input errors (nothing returned); kinds 0 asks for all three; `assemble` is ignored. The
 * default rank of the header: lateral when asked, else tilt, else friction. No stable plan (a part
 * whose weight falls outside its base): nothing to rank, and no error. */
static void test_arguments(void) {
    cnAssembly *a = load_ok(STACK);
    cnPlanResult r;
    if (!a || !plan_ok(a, &r)) {
        cn_assembly_free(a);
        return;
    }
    cnMarginOptions mo;
    cnSimOptions so = sim_options(&mo, CN_MARGIN_TILT, 1);
    cnPlanMargin *m = (cnPlanMargin *)&r; /* anything: it must be reset */
    int n = 7;
    cnDiag d;
    CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_LATERAL, &m, &n, &d) == CN_ERR_INPUT &&
          !strcmp(d.where, "rank"));
    CHECK(m == NULL && n == 0);
    const int bad[3] = {0, 3, 8};
    for (int i = 0; i < 3; i++) {
        mo.kinds = CN_MARGIN_ALL;
        CHECK(cn_plan_margins(a, &r, &so, bad[i], &m, &n, &d) == CN_ERR_INPUT && !strcmp(d.where, "rank"));
        CHECK(m == NULL && n == 0);
    }
    so.margin = NULL;
    CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_TILT, &m, &n, &d) == CN_ERR_INPUT &&
          !strcmp(d.where, "margin"));
    CHECK(m == NULL && n == 0);
    CHECK(cn_plan_margins(a, &r, NULL, CN_MARGIN_TILT, &m, &n, &d) == CN_ERR_INPUT && m == NULL && n == 0);
    so.margin = &mo;
    mo.kinds = 0;       /* all: friction, tilt and lateral found, ranked by friction (ties: 0 for both) */
    so.assemble = true; /* ignored: the sequences are disassembled */
    CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_FRICTION, &m, &n, &d) == CN_OK && n == 2);
    for (int i = 0; i < n; i++) {
        CHECK(m[i].sequence == i);
        for (int k = 0; k < 3; k++)
            CHECK(m[i].weakest_step[k] == 0 && m[i].weakest[k].computed);
        CHECK(m[i].weakest[0].at.value == 0 && NEAR(m[i].weakest[2].at.value, 0.5));
    }
    cn_plan_margins_free(m, n);
    cn_plan_margins_free(NULL, 0);
    CHECK(cn_plan_margin_rank(0) == CN_MARGIN_LATERAL &&
          cn_plan_margin_rank(CN_MARGIN_ALL) == CN_MARGIN_LATERAL);
    CHECK(cn_plan_margin_rank(CN_MARGIN_TILT | CN_MARGIN_FRICTION) == CN_MARGIN_TILT);
    CHECK(cn_plan_margin_rank(CN_MARGIN_FRICTION) == CN_MARGIN_FRICTION);
    cn_plan_result_free(&r);
    cn_assembly_free(a);

    a = load_ok("{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":0.5,\"parts\":["
                "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                "{\"name\":\"block\",\"polygon\":[[-4,0],[-3,0],[-3,1],[-4,1]]},"
                "{\"name\":\"leaner\",\"polygon\":[[0,0],[1,0],[4,3],[3,3]]}]}");
    if (a && plan_ok(a, &r)) {
        CHECK(!r.stable && r.nlisted == 0);
        mo.kinds = CN_MARGIN_LATERAL;
        m = (cnPlanMargin *)&r;
        n = 7;
        CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_LATERAL, &m, &n, &d) == CN_OK && m == NULL && n == 0);
        /* the rank is still checked */
        CHECK(cn_plan_margins(a, &r, &so, CN_MARGIN_TILT, &m, &n, &d) == CN_ERR_INPUT);
        cn_plan_result_free(&r);
    }
    cn_assembly_free(a);
}

/* More sequences than CN_PLAN_MARGIN_MAX (201 copies of a block's one-step sequence): the first
 * CN_PLAN_MARGIN_MAX are ranked, all equal (the block's step leaves nothing: critical friction
 * 0), so in the order listed. */
static void test_limit(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":0.5,\"parts\":["
                            "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                            "{\"name\":\"block\",\"polygon\":[[0,0],[1,0],[1,1],[0,1]]}],"
                            "\"candidates\":{\"block\":{\"up\":[[0,2]]}}}");
    cnPlanResult r;
    if (!a || !plan_ok(a, &r)) {
        cn_assembly_free(a);
        return;
    }
    CHECK(r.nlisted == 1);
    if (r.nlisted == 1) {
        enum { N = CN_PLAN_MARGIN_MAX + 1 };
        cnPlanSequence *seqs = malloc(N * sizeof *seqs);
        for (int i = 0; i < N; i++)
            seqs[i] = r.sequences[0];
        cnPlanResult many;
        memset(&many, 0, sizeof many);
        many.nlisted = N;
        many.sequences = seqs;
        cnMarginOptions mo;
        cnSimOptions so = sim_options(&mo, CN_MARGIN_FRICTION, 1);
        cnPlanMargin *m = NULL;
        int n = 0;
        cnDiag d;
        CHECK(cn_plan_margins(a, &many, &so, CN_MARGIN_FRICTION, &m, &n, &d) == CN_OK);
        CHECK(n == CN_PLAN_MARGIN_MAX);
        int in_order = 0;
        for (int i = 0; i < n; i++)
            in_order += m[i].sequence == i && m[i].status == CN_STEP_STABLE && m[i].weakest_step[0] == 0 &&
                        m[i].weakest[0].at.value == 0;
        CHECK_MSG(in_order == CN_PLAN_MARGIN_MAX, "%d of %d in order, stable, critical friction 0", in_order,
                  n);
        cn_plan_margins_free(m, n);
        free(seqs);
    }
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

void test_plan_margin(void) {
    test_ranked_by_hand();
    test_stack_and_failures();
    test_near_tie();
    test_invariance();
    test_arguments();
    test_limit();
}
