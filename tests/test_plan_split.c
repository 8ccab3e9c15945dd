/* The two-handed splits (plan/plan_split.c) on a planner built here as cn_plan builds it:
 * cn_pl_popcount against a loop over the 64 bits; cn_pl_split_states against the states its
 * definition names, for every group and grip of every state of a stack; cn_pl_solve_sub on tiny
 * frictionless assemblies (stacks, a row of blocks, a lintel on two posts), its count of
 * every memoised state against a brute force that applies the documented split rules
 * (docs/cli.md, --subassemblies) to stability written by hand, its root counts against counts
 * derived by hand, the groups it tries and the moves it finds stable from the whole assembly
 * against an enumeration of the subsets, the same counts in 3-D (where a state's blocking graph
 * prunes its groups), and invariance under reordering the parts in the file and translating the
 * assembly. */
#include <stdlib.h>
#include <string.h>

#include "core.h"
#include "helpers.h"
#include "plan_state.h"

/* ---- cn_pl_popcount ---- */

static int naive_popcount(Mask m) {
    int c = 0;
    for (int b = 0; b < 64; b++) c += (int)(m >> b & 1);
    return c;
}

static Mask rng_mask(cnRng *r) {
    cn_rng_uniform(r);
    return r->s;
}

/* cn_pl_popcount against a loop over the 64 bits: the ends (empty, one bit, the top bit, all 64)
 * and random masks, sparse, even and dense. */
static void test_popcount(void) {
    const Mask edge[] = {0, 1, 2, 3, 1ULL << 63, (1ULL << 63) | 1, ~0ULL, ~0ULL >> 1, 0xAAAAAAAAAAAAAAAAULL};
    const int want[] = {0, 1, 1, 2, 1, 2, 64, 63, 32};
    for (size_t i = 0; i < sizeof edge / sizeof *edge; i++)
        CHECK_MSG(cn_pl_popcount(edge[i]) == want[i], "popcount(%#llx) = %d, expected %d", edge[i],
                  cn_pl_popcount(edge[i]), want[i]);
    cnRng r = {0x5eed5eedULL};
    int bad = 0;
    for (int i = 0; i < 3000; i++) {
        Mask a = rng_mask(&r), b = rng_mask(&r), c = rng_mask(&r);
        Mask m = i % 3 == 0 ? a & b & c : i % 3 == 1 ? a : a | b | c;
        if (cn_pl_popcount(m) != naive_popcount(m)) bad++;
    }
    CHECK_MSG(bad == 0, "popcount differs from the bit loop on %d of 3000 masks", bad);
}

/* ---- scenes: boxes on a fixed table, frictionless ---- */

typedef struct {
    const char *name;
    double x0, y0, x1, y1;
} Blk;

/* One box as a part (after a comma unless `first`): in 2-D the rectangle [x0, x1] x [y0, y1]; in
 * 3-D the block [x0, x1] x [d0, d1] x [y0, y1] (the plane's y is height, along z). */
static int box_json(char *js, size_t cap, int dim, const char *name, bool fixed, bool first, double x0,
                    double y0, double x1, double y1, double d0, double d1) {
    int len = snprintf(js, cap, "%s{\"name\":\"%s\",%s\"%s\":[", first ? "" : ",", name,
                       fixed ? "\"fixed\":true," : "", dim == 2 ? "polygon" : "hull");
    for (int c = 0; c < (dim == 2 ? 4 : 8); c++) {
        /* 2-D counter-clockwise: (x0, y0), (x1, y0), (x1, y1), (x0, y1) */
        bool hx = dim == 2 ? c == 1 || c == 2 : c & 1, hy = dim == 2 ? c >= 2 : c >> 1 & 1;
        double x = hx ? x1 : x0, y = hy ? y1 : y0, d = c >> 2 & 1 ? d1 : d0;
        len += dim == 2 ? snprintf(js + len, cap - (size_t)len, "%s[%.17g,%.17g]", c ? "," : "", x, y)
                        : snprintf(js + len, cap - (size_t)len, "%s[%.17g,%.17g,%.17g]", c ? "," : "", x,
                                   d, y);
    }
    return len + snprintf(js + len, cap - (size_t)len, "]}");
}

/* The blocks (1 deep in 3-D) listed in the file in order[] (NULL: as given) after a fixed table,
 * everything shifted by (dx, dy), in 2-D (gravity -y) or 3-D (gravity -z); `well` (3-D): fixed
 * walls 3 tall touching the four sides of the column [0, 1] x [0, 1]; `extra` (NULL: none) ends
 * the file's object (",\"candidates\":..."). */
static cnAssembly *scene_x(int dim, const Blk *b, int n, const int *order, double dx, double dy, bool well,
                           const char *extra) {
    char js[8192];
    int len = snprintf(js, sizeof js, "{\"dimension\":%d,\"gravity\":%s,\"parts\":[", dim,
                       dim == 2 ? "[0,-1]" : "[0,0,-1]");
    len += box_json(js + len, sizeof js - (size_t)len, dim, "T", true, true, -10 + dx, -1 + dy, 10 + dx, dy,
                    -3, 4);
    if (well) {
        /* x0, d0, x1, d1 of the left, right, front and back walls */
        static const double w[4][4] = {{-1, -1, 0, 2}, {1, -1, 2, 2}, {0, -1, 1, 0}, {0, 1, 1, 2}};
        static const char *names[4] = {"wl", "wr", "wf", "wb"};
        for (int k = 0; k < 4; k++)
            len += box_json(js + len, sizeof js - (size_t)len, dim, names[k], true, false, w[k][0] + dx, dy,
                            w[k][2] + dx, 3 + dy, w[k][1], w[k][3]);
    }
    for (int k = 0; k < n; k++) {
        const Blk *q = &b[order ? order[k] : k];
        len += box_json(js + len, sizeof js - (size_t)len, dim, q->name, false, false, q->x0 + dx,
                        q->y0 + dy, q->x1 + dx, q->y1 + dy, 0, 1);
    }
    snprintf(js + len, sizeof js - (size_t)len, "]%s}", extra ? extra : "");
    return load_ok(js);
}

static cnAssembly *scene(const Blk *b, int n, const int *order, double dx, double dy) {
    return scene_x(2, b, n, order, dx, dy, false, NULL);
}

/* ---- the model: stability of tiny frictionless assemblies, by hand ----
 * Parts are numbered by position (not by their place in the file):
 *  - STACK: n blocks one on another, 0 at the bottom;
 *  - ROW: n blocks side by side on the table, touching, 0 on the left;
 *  - LINTEL: posts 0 = [0, 1] x [0, 2] and 1 = [3, 4] x [0, 2], lintel 2 = [0, 4] x [2, 3] on
 *    both (its centre over the gap: it tips off one post alone). */
typedef enum { STACK, ROW, LINTEL } Kind;

typedef struct {
    Kind kind;
    int n;
    Blk b[4];
} Model;

static Model model(Kind kind, int n) {
    static const char *names[4] = {"A", "B", "C", "D"};
    Model md;
    memset(&md, 0, sizeof md);
    md.kind = kind;
    md.n = kind == LINTEL ? 3 : n;
    for (int i = 0; i < md.n; i++) {
        Blk s = {names[i], 0, i, 1, i + 1}, r = {names[i], i, 0, i + 1, 1};
        md.b[i] = kind == STACK ? s : r;
    }
    if (kind == LINTEL) {
        Blk p1 = {"P1", 0, 0, 1, 2}, p2 = {"P2", 3, 0, 4, 2}, l = {"L", 0, 2, 4, 3};
        md.b[0] = p1, md.b[1] = p2, md.b[2] = l;
    }
    return md;
}

static int popc(unsigned s) { return naive_popcount(s); }

/* Does the state of the parts S stand: on the table (h = -1), gripped by part h (no table), or
 * held whole (HELD_WHOLE: nothing can fall)? Frictionless: a block stands only on a face below
 * it, and one gripped part holds up only what rests on it. */
static bool m_stable(const Model *md, unsigned S, int h) {
    if (h == HELD_WHOLE || S == 0) return true;
    unsigned run = (1u << popc(S)) - 1;
    switch (md->kind) {
    case STACK: /* a run from the bottom, or from the gripped block up */
        return h < 0 ? S == run : S == run << h;
    case ROW: /* on the table every block stands; a gripped one holds none of its neighbours */
        return h < 0 ? true : S == 1u << h;
    case LINTEL: /* the lintel needs both posts; a gripped part holds nothing up */
        return h < 0 ? !(S & 4) || (S & 3) == 3 : S == 1u << h;
    }
    return false;
}

/* The parts of M that part g of M holds up through contacts among them (the model's touching
 * pairs: neighbours in a stack or a row; the lintel and each post). */
static unsigned m_reach(const Model *md, unsigned M, int g) {
    unsigned seen = 1u << g, grown = 1;
    while (grown) {
        grown = 0;
        for (int i = 0; i < md->n; i++)
            for (int j = 0; j < md->n; j++) {
                bool touch = md->kind == LINTEL ? (i == 2) != (j == 2) : abs(i - j) == 1;
                if (touch && (seen >> i & 1) && (M >> j & 1) && !(seen >> j & 1)) seen |= 1u << j, grown = 1;
            }
    }
    return seen;
}

static int lowest(unsigned S) {
    int i = 0;
    while (!(S >> i & 1)) i++;
    return i;
}

/* Stable two-handed plans from the state (S, h) of the model, by the rules of docs/cli.md: on the
 * table, each part that can leave alone, and each group of 2 or more parts gripped by one of its
 * parts (the group must stand on it) or whole (not every part at once); gripped by part h, each
 * group of the other parts (a single one gripped alone); held whole, each way of cutting it in two
 * once, the side taken out gripped whole (or, 2 or more parts, by one of them). The rest must
 * stand; both sides then come apart (the product). Groups of at most max_sub parts (0: any). In
 * these scenes a move between two standing states always has a stable path (up, or, in the air,
 * sideways along the faces). */
static double m_count(const Model *md, unsigned S, int h, int max_sub) {
    unsigned hm = h >= 0 ? 1u << h : 0;
    if ((S & ~hm) == 0 || (h == HELD_WHOLE && popc(S) == 1)) return 1;
    if (!m_stable(md, S, h)) return 0;
    double total = 0;
    if (h == -1)
        for (int p = 0; p < md->n; p++)
            if ((S >> p & 1) && m_stable(md, S & ~(1u << p), -1))
                total += m_count(md, S & ~(1u << p), -1, max_sub);
    unsigned free_ = S & ~hm;
    int nb = popc(free_), kmin = h == -1 ? 2 : 1, kmax = max_sub > 0 && max_sub < nb ? max_sub : nb;
    if (h == HELD_WHOLE && kmax == nb) kmax = nb - 1;
    for (unsigned M = 1; M < 1u << md->n; M++) {
        int k = popc(M);
        if ((M & ~free_) || k < kmin || k > kmax || !m_stable(md, S & ~M, h)) continue;
        double rest = m_count(md, S & ~M, h, max_sub);
        /* held whole, {M | rest} counts once: from the side without the lowest position */
        bool twin = h == HELD_WHOLE && (M >> lowest(S) & 1);
        if (k == 1) {
            if (!twin) total += rest;
            continue;
        }
        for (int g = 0; g < md->n; g++)
            if ((M >> g & 1) && m_stable(md, M, g)) total += rest * m_count(md, M, g, max_sub);
        if (!twin && !(h == -1 && M == S)) total += rest * m_count(md, M, HELD_WHOLE, max_sub);
    }
    return total;
}

/* ---- a planner built as cn_plan builds it (without the single-part search) ---- */

typedef struct {
    Planner P;
    cnPlanOptions o;
    cnDiag d;
    int pos_of_bit[PLAN_MAX_PARTS]; /* the model's position of each free part */
} Rig;

static bool rig_init(Rig *R, const cnAssembly *a, const Model *md, int max_sub) {
    memset(R, 0, sizeof *R);
    R->o = cn_plan_options_default();
    R->o.subassemblies = true;
    R->o.max_sub = max_sub;
    Planner *P = &R->P;
    if (cn_pl_init(P, a, &R->o, &R->d) != 0) return false;
    for (int b = 0; b < P->nfree; b++) {
        R->pos_of_bit[b] = -1;
        for (int k = 0; k < md->n; k++)
            if (cn_assembly_find_part(a, md->b[k].name) == P->part_of[b]) R->pos_of_bit[b] = k;
        if (R->pos_of_bit[b] < 0) return false;
    }
    return cn_pl_find_touching(P) == CN_OK;
}

static void rig_free(Rig *R) { cn_pl_free(&R->P); }

static Mask rig_full(const Rig *R) { return (1ULL << R->P.nfree) - 1; }

/* A planner mask as model positions, and a planner grip (bit, -1 or HELD_WHOLE) as a position. */
static unsigned to_pos(const Rig *R, Mask m) {
    unsigned s = 0;
    for (int b = 0; b < R->P.nfree; b++)
        if (m >> b & 1) s |= 1u << R->pos_of_bit[b];
    return s;
}
static int held_pos(const Rig *R, int held) { return held >= 0 ? R->pos_of_bit[held] : held; }
static Mask to_bits(const Rig *R, unsigned s) {
    Mask m = 0;
    for (int b = 0; b < R->P.nfree; b++)
        if (s >> R->pos_of_bit[b] & 1) m |= 1ULL << b;
    return m;
}

/* Solve the two-handed plans of the whole assembly of md (file order `order`, shifted by dx, dy)
 * on a rig; returns the root's state, -1 on failure. */
static int rig_solve_x(Rig *R, cnAssembly **a, int dim, bool well, const Model *md, const int *order,
                       double dx, double dy, int max_sub, const char *extra) {
    memset(R, 0, sizeof *R); /* rig_free-able whatever fails */
    *a = scene_x(dim, md->b, md->n, order, dx, dy, well, extra);
    if (!*a) return -1;
    if (!rig_init(R, *a, md, max_sub)) {
        CHECK_MSG(false, "planner set-up failed");
        return -1;
    }
    int root = cn_pl_state_of(&R->P, rig_full(R));
    cnStatus s = root < 0 ? CN_ERR_MEMORY : cn_pl_solve_sub(&R->P, root);
    CHECK_MSG(s == CN_OK, "cn_pl_solve_sub: %s", R->d.message);
    return s == CN_OK ? root : -1;
}

static int rig_solve(Rig *R, cnAssembly **a, const Model *md, const int *order, double dx, double dy,
                     int max_sub) {
    return rig_solve_x(R, a, 2, false, md, order, dx, dy, max_sub, NULL);
}

/* Every memoised count of the rig against the model's brute force; returns how many matched. */
static int rig_vs_model(const Rig *R, const Model *md, int max_sub, const char *what) {
    int ok = 0;
    for (int i = 0; i < R->P.nst; i++) {
        const State *S = &R->P.st[i];
        if (S->sub_plans < 0) continue;
        unsigned s = to_pos(R, S->mask);
        int h = held_pos(R, S->held);
        double want = m_count(md, s, h, max_sub);
        CHECK_MSG(S->sub_plans == want, "%s: state %#x held %d: %g plans, the brute force %g", what, s, h,
                  S->sub_plans, want);
        ok += S->sub_plans == want;
    }
    return ok;
}

/* ---- cn_pl_split_states ---- */

/* For every state (m, held) of a stack of three (on the table, gripped by each of its parts, held
 * whole), every group M of its parts outside the hand and every grip of M (by each of its parts,
 * or whole): the rest is the state (m without M, held), and the part taken out is gone (a single
 * part) or is the state (M, its grip; whole when grip is -1). The states are made once each. */
static void test_split_states(void) {
    Model md = model(STACK, 3);
    cnAssembly *a = scene(md.b, md.n, NULL, 0, 0);
    if (!a) return;
    Rig R;
    if (!rig_init(&R, a, &md, 0)) {
        CHECK(false);
        rig_free(&R);
        cn_assembly_free(a);
        return;
    }
    Planner *P = &R.P;
    int n = P->nfree, bad = 0, cases = 0, distinct = 0;
    bool seen[8][6]; /* [mask][held + 2], held in -2 .. 2 */
    memset(seen, 0, sizeof seen);
#define SEE(m, h) (seen[m][(h) + 2] ? 0 : (seen[m][(h) + 2] = true, 1))
    for (Mask m = 1; m < 1ULL << n; m++)
        for (int held = HELD_WHOLE; held < n; held++) {
            if (held >= 0 && !(m >> held & 1)) continue;
            Mask hm = held >= 0 ? 1ULL << held : 0;
            distinct += SEE(m, held);
            int si = cn_pl_state_at(P, m, held);
            for (Mask M = 1; M < 1ULL << n; M++) {
                if (M & ~(m & ~hm)) continue;
                for (int g = -1; g < n; g++) {
                    if (g >= 0 && !(M >> g & 1)) continue;
                    Trans t = cn_pl_trans_init(M, NULL, g, si);
                    int rest = -9, out = -9, rest2 = -9, out2 = -9;
                    cnStatus s = cn_pl_split_states(P, si, &t, &rest, &out);
                    cnStatus s2 = cn_pl_split_states(P, si, &t, &rest2, &out2);
                    bool single = naive_popcount(M) == 1;
                    int want_held = g >= 0 ? g : HELD_WHOLE;
                    distinct += SEE(m & ~M, held);
                    if (!single) distinct += SEE(M, want_held);
                    bool ok = s == CN_OK && s2 == CN_OK && rest >= 0 && rest == rest2 && out == out2 &&
                              P->st[rest].mask == (m & ~M) && P->st[rest].held == held &&
                              (single ? out == -1
                                      : out >= 0 && P->st[out].mask == M && P->st[out].held == want_held);
                    cases++;
                    if (!ok) {
                        bad++;
                        fprintf(stderr, "split of %#llx held %d taking %#llx grip %d: rest %d, out %d\n", m,
                                held, M, g, rest, out);
                    }
                }
            }
        }
#undef SEE
    CHECK_MSG(bad == 0, "%d of %d splits lead to the wrong states", bad, cases);
    /* (group, grip) pairs: 4 in each one-part state, 18 in each two-part one, 59 in the whole */
    CHECK(cases == 125);
    CHECK_MSG(P->nst == distinct, "%d states made for %d distinct (parts, hold) pairs", P->nst, distinct);
    for (int i = 0; i < P->nst; i++) CHECK(P->st[i].sub_plans == -1 && P->st[i].sub_choice == -1);
    rig_free(&R);
    cn_assembly_free(a);
}

/* ---- cn_pl_solve_sub ---- */

/* The states where nothing is left to take apart count one plan, found without a move; a state
 * that does not stand counts none; a solved state is not solved again. Stack of three (A, B, C
 * from the bottom, bits in that order): (nothing), (A gripped by A), (B held whole), (B + C on the
 * table: B floats). */
static void test_solve_sub_ends(void) {
    Model md = model(STACK, 3);
    cnAssembly *a = scene(md.b, md.n, NULL, 0, 0);
    if (!a) return;
    Rig R;
    if (!rig_init(&R, a, &md, 0)) {
        CHECK(false);
        rig_free(&R);
        cn_assembly_free(a);
        return;
    }
    Planner *P = &R.P;
    struct {
        Mask m;
        int held;
        double want;
    } ends[] = {{0, -1, 1}, {1, 0, 1}, {2, HELD_WHOLE, 1}, {6, -1, 0}};
    for (size_t i = 0; i < sizeof ends / sizeof *ends; i++) {
        int si = cn_pl_state_at(P, ends[i].m, ends[i].held);
        int ntr = P->ntr, nsims = P->nsims;
        CHECK(si >= 0 && cn_pl_solve_sub(P, si) == CN_OK);
        CHECK_MSG(P->st[si].sub_plans == ends[i].want, "state %#llx held %d: %g plans, expected %g",
                  ends[i].m, ends[i].held, P->st[si].sub_plans, ends[i].want);
        CHECK(P->st[si].sub_choice == -1 && P->ntr == ntr && P->nsims == nsims);
    }
    /* the whole stack, then again: memoised, nothing more made or simulated */
    int root = cn_pl_state_of(P, rig_full(&R));
    CHECK(cn_pl_solve_sub(P, root) == CN_OK && P->st[root].sub_plans == 7);
    int nst = P->nst, ntr = P->ntr, nsims = P->nsims;
    CHECK(nsims > 0 && cn_pl_solve_sub(P, root) == CN_OK);
    CHECK(P->nst == nst && P->ntr == ntr && P->nsims == nsims && P->st[root].sub_plans == 7);
    /* the first split with plans: a stable move out of the root whose sides both come apart */
    int c = P->st[root].sub_choice;
    CHECK(c >= 0 && c < P->ntr);
    if (c >= 0 && c < P->ntr) {
        const Trans *t = &P->tr[c];
        int r1, r2;
        CHECK(t->status == CN_STEP_STABLE && cn_pl_split_states(P, root, t, &r1, &r2) == CN_OK);
        CHECK(P->st[r1].sub_plans > 0 && (r2 < 0 || P->st[r2].sub_plans > 0));
    }
    rig_free(&R);
    cn_assembly_free(a);
}

/* Counts on tiny assemblies, derived by hand (A, B, C, D from the bottom or the left):
 *  - stack of 2: B off, then A (1); A + B gripped by A, B resting on it, then B off it (1); by B,
 *    A falls; whole is not allowed for every part at once: 2.
 *  - stack of 3: C off, then the stack of 2 (2); B + C gripped by B (C rests on it: then C off B,
 *    1) or held whole (then C from B in the air, 1), A standing (1): 2; A + B + C gripped by A,
 *    then in that hand C alone (1), B + C by B (1) or whole (1): 3; B off leaves C floating, and
 *    A + B, A + C leave a floating block: 7. Groups of at most 2: 2 + 2 = 4; single parts: 1.
 *  - row of 3 (side by side, touching): any block first, then either of the other two first: 6;
 *    any two held whole (by one, the other slides off its face), the third standing, then the two
 *    apart in the air once: 3; the three by one part: the others slide off: 9. Single parts: 6.
 *  - row of 4: a block first, then a row of 3 (4 x 9); two held whole, then the other two (6 x 2
 *    x 1); three held whole, the fourth standing (1), then the three cut in two in the air once,
 *    the single block first or the pair whole (3 ways, each 1 x 1): 4 x 3; all four: 0: 60.
 *  - lintel: the lintel first, then the posts in 2 orders (2); a post with the lintel held whole
 *    (by the post the lintel tips off, by the lintel the post falls), the other post standing,
 *    then the two apart in the air: 1 + 1; both posts leave the lintel floating; all three by one
 *    part: the others fall: 4.
 * Every state the search solved is also checked against the brute force m_count. */
static void test_solve_sub_counts(void) {
    struct {
        Kind kind;
        int n, max_sub;
        double want;
    } cases[] = {{STACK, 2, 0, 2}, {STACK, 3, 0, 7}, {STACK, 3, 2, 4}, {STACK, 3, 1, 1},
                 {ROW, 3, 0, 9},   {ROW, 3, 1, 6},   {ROW, 4, 0, 60},  {LINTEL, 3, 0, 4}};
    static const char *kinds[] = {"stack", "row", "lintel"};
    for (size_t i = 0; i < sizeof cases / sizeof *cases; i++) {
        Model md = model(cases[i].kind, cases[i].n);
        char what[64];
        snprintf(what, sizeof what, "%s of %d, groups of at most %d", kinds[cases[i].kind], md.n,
                 cases[i].max_sub);
        /* the hand count and the brute force agree before the planner is asked */
        double brute = m_count(&md, (1u << md.n) - 1, -1, cases[i].max_sub);
        CHECK_MSG(brute == cases[i].want, "%s: brute force %g, by hand %g", what, brute, cases[i].want);
        Rig R;
        cnAssembly *a = NULL;
        int root = rig_solve(&R, &a, &md, NULL, 0, 0, cases[i].max_sub);
        if (root >= 0) {
            CHECK_MSG(R.P.st[root].sub_plans == cases[i].want, "%s: %g plans, expected %g", what,
                      R.P.st[root].sub_plans, cases[i].want);
            CHECK_MSG(rig_vs_model(&R, &md, cases[i].max_sub, what) >= 3, "%s: too few states solved", what);
            CHECK(!R.P.truncated && !R.P.splits_capped && !R.P.budget);
        }
        rig_free(&R);
        cn_assembly_free(a);
    }
}

/* The groups tried from the whole assembly and the moves found stable, against an enumeration of
 * the subsets: every group of 2 or more parts is tried (single parts are the sequence search's
 * moves); a group whose rest does not stand is failed by Proposition 1 once, without a
 * simulation, gripped whole; and the stable moves are exactly the (group, grip) pairs where the
 * rest stands and the group stands in its grip (whole: any but every part), each once. Row of 3
 * and lintel. */
static void test_root_splits(void) {
    Kind kinds[2] = {ROW, LINTEL};
    for (int kk = 0; kk < 2; kk++) {
        Model md = model(kinds[kk], 3);
        Rig R;
        cnAssembly *a = NULL;
        int root = rig_solve(&R, &a, &md, NULL, 0, 0, 0);
        if (root < 0) {
            rig_free(&R);
            cn_assembly_free(a);
            continue;
        }
        const Planner *P = &R.P;
        unsigned all = (1u << md.n) - 1;
        for (unsigned M = 1; M <= all; M++) {
            Mask bits = to_bits(&R, M);
            int tried = 0, prop1 = 0, stable[PLAN_MAX_PARTS + 1] = {0}, whole_stable = 0;
            for (int k = 0; k < P->ntr; k++) {
                const Trans *t = &P->tr[k];
                if (t->from != root || t->move != bits) continue;
                tried++;
                prop1 += t->prop1;
                if (t->prop1) CHECK(t->status == CN_STEP_UNSTABLE && isnan(t->time) && t->moving);
                if (t->status == CN_STEP_STABLE) {
                    if (t->grip >= 0) stable[held_pos(&R, t->grip)]++;
                    else whole_stable++;
                }
            }
            if (popc(M) < 2) {
                CHECK_MSG(tried == 0, "kind %d: single part %#x tried as a group from the root", kk, M);
                continue;
            }
            CHECK_MSG(tried > 0, "kind %d: group %#x never tried from the root", kk, M);
            bool rest_ok = m_stable(&md, all & ~M, -1);
            if (!rest_ok) {
                CHECK_MSG(tried == 1 && prop1 == 1, "kind %d: group %#x (the rest falls): %d moves, %d by "
                          "Proposition 1", kk, M, tried, prop1);
                continue;
            }
            for (int g = 0; g < md.n; g++) {
                if (!(M >> g & 1)) continue;
                int want = m_stable(&md, M, g) ? 1 : 0;
                CHECK_MSG(stable[g] == want, "kind %d: group %#x gripped by %d: %d stable moves, expected %d",
                          kk, M, g, stable[g], want);
            }
            int want_whole = M != all;
            CHECK_MSG(whole_stable == want_whole,
                      "kind %d: group %#x held whole: %d stable moves, expected %d", kk, M, whole_stable,
                      want_whole);
        }
        rig_free(&R);
        cn_assembly_free(a);
    }
}

/* A group gripped by one part whose other parts do not all touch it through each other fails at
 * once (Proposition 1), and the parts recorded as moving are exactly those that touch nothing
 * connected to the gripped part, by the model's contacts. Row of 4, where a group gripped by one
 * part can also shed a neighbour that touches it (A + B + D gripped by A: D is lost, B would
 * slide off later). */
static void test_grip_carries(void) {
    Model md = model(ROW, 4);
    Rig R;
    cnAssembly *a = NULL;
    int root = rig_solve(&R, &a, &md, NULL, 0, 0, 0), lost_root = 0;
    for (int k = 0; root >= 0 && k < R.P.ntr; k++) {
        const Trans *t = &R.P.tr[k];
        if (t->grip < 0 || t->from < 0) continue;
        unsigned M = to_pos(&R, t->move);
        int g = held_pos(&R, t->grip);
        unsigned lost = M & ~m_reach(&md, M, g);
        if (!lost) continue;
        lost_root += t->from == root;
        CHECK_MSG(t->prop1 && t->status == CN_STEP_UNSTABLE && to_pos(&R, t->moving) == lost,
                  "group %#x gripped by %d: moving %#x, expected %#x lost", M, g, to_pos(&R, t->moving),
                  lost);
    }
    /* from the root: {A, C}, {B, D}, {A, D} by either part, {A, B, D} and {A, C, D} by any: 12 */
    CHECK_MSG(lost_root == 12, "%d moves from the root of a group that falls apart in the hand", lost_root);
    rig_free(&R);
    cn_assembly_free(a);
}

/* Held whole, {M | rest} is one split whichever side moves: it is tried from the side without the
 * lowest part in the file and, when that side has no stable path, from the other. Each block of
 * a stack of 3 may only rise (its file candidate): in the air, B under C cannot rise out of {B,
 * C}, C can. Listed with C before B, the split is tried from B's side first and found from C's:
 * every order counts 7, each state as the brute force says. */
static void test_twin_fallback(void) {
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    const char *up = ",\"candidates\":{\"A\":{\"up\":[[0,5]]},\"B\":{\"up\":[[0,5]]},"
                     "\"C\":{\"up\":[[0,5]]}}";
    Model md = model(STACK, 3);
    for (int p = 0; p < 6; p++) {
        Rig R;
        cnAssembly *a = NULL;
        char what[48];
        snprintf(what, sizeof what, "rising only, listed %d%d%d", perms[p][0], perms[p][1],
                 perms[p][2]);
        int root = rig_solve_x(&R, &a, 2, false, &md, perms[p], 0, 0, 0, up);
        if (root >= 0) {
            CHECK_MSG(R.P.st[root].sub_plans == 7, "%s: %g plans", what, R.P.st[root].sub_plans);
            rig_vs_model(&R, &md, 0, what);
        }
        rig_free(&R);
        cn_assembly_free(a);
    }
}

/* The stack of three listed in each of the six orders in the file: the bits (and so the side of a
 * held-whole split it is counted from) change, the counts do not; every state's count is the
 * brute force's for the same parts. Translated (table included), the same states count the same
 * plans. */
static void test_invariance(void) {
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    Model md = model(STACK, 3);
    for (int p = 0; p < 6; p++) {
        Rig R;
        cnAssembly *a = NULL;
        char what[48];
        snprintf(what, sizeof what, "stack listed %d%d%d", perms[p][0], perms[p][1], perms[p][2]);
        int root = rig_solve(&R, &a, &md, perms[p], 0, 0, 0);
        if (root >= 0) {
            CHECK_MSG(R.P.st[root].sub_plans == 7, "%s: %g plans", what, R.P.st[root].sub_plans);
            rig_vs_model(&R, &md, 0, what);
        }
        rig_free(&R);
        cn_assembly_free(a);
    }
    /* the lintel, where it stands and moved by (12.5, -3.25) */
    md = model(LINTEL, 3);
    Rig R0, R1;
    cnAssembly *a0 = NULL, *a1 = NULL;
    int r0 = rig_solve(&R0, &a0, &md, NULL, 0, 0, 0), r1 = rig_solve(&R1, &a1, &md, NULL, 12.5, -3.25, 0);
    if (r0 >= 0 && r1 >= 0) {
        CHECK(R1.P.st[r1].sub_plans == 4);
        int n0 = 0, n1 = 0, same = 0;
        for (int i = 0; i < R0.P.nst; i++) n0 += R0.P.st[i].sub_plans >= 0;
        for (int j = 0; j < R1.P.nst; j++) n1 += R1.P.st[j].sub_plans >= 0;
        for (int i = 0; i < R0.P.nst; i++) {
            const State *x = &R0.P.st[i];
            for (int j = 0; j < R1.P.nst && x->sub_plans >= 0; j++) {
                const State *y = &R1.P.st[j];
                same += y->mask == x->mask && y->held == x->held && y->sub_plans == x->sub_plans;
            }
        }
        CHECK_MSG(n0 == n1 && same == n0 && n0 > 0, "translated: %d and %d states solved, %d alike", n0, n1,
                  same);
    }
    rig_free(&R0);
    rig_free(&R1);
    cn_assembly_free(a0);
    cn_assembly_free(a1);
}

/* In 3-D a group is tried only when a cell of the state's blocking graph lets it out (no part of
 * it blocked by a part outside it, none by a fixed part). The stack of 3 and the row of 3 as
 * blocks 1 deep count as in 2-D (7 and 9), and the stack of 3 in a well (fixed walls touching its
 * four sides, 3 tall: every group leaves only straight up, where the parts below are blocked by
 * those above in the group) too: each state as the brute force says, and every group of 2 or
 * more parts tried from the root. */
static void test_3d(void) {
    Kind kinds[3] = {STACK, ROW, STACK};
    const char *what[3] = {"3-D stack", "3-D row", "3-D stack in a well"};
    const double want[3] = {7, 9, 7};
    for (int kk = 0; kk < 3; kk++) {
        Model md = model(kinds[kk], 3);
        Rig R;
        cnAssembly *a = NULL;
        int root = rig_solve_x(&R, &a, 3, kk == 2, &md, NULL, 0, 0, 0, NULL);
        if (root >= 0) {
            CHECK_MSG(R.P.st[root].sub_plans == want[kk], "%s: %g plans", what[kk], R.P.st[root].sub_plans);
            rig_vs_model(&R, &md, 0, what[kk]);
            Mask tried = 0; /* the groups, as bit M of a mask of the 2^3 subsets */
            for (int k = 0; k < R.P.ntr; k++)
                if (R.P.tr[k].from == root) tried |= 1ULL << R.P.tr[k].move;
            CHECK_MSG(tried == ((1ULL << 3) | (1ULL << 5) | (1ULL << 6) | (1ULL << 7)),
                      "%s: groups tried from the root %#llx", what[kk], tried);
        }
        rig_free(&R);
        cn_assembly_free(a);
    }
}

/* The public planner counts what the planner's split code counts on the same assembly (the rig
 * is set up as cn_plan sets it up): the lintel, 4. */
static void test_public_agrees(void) {
    Model md = model(LINTEL, 3);
    cnAssembly *a = scene(md.b, md.n, NULL, 0, 0);
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    o.subassemblies = true;
    cnPlanResult r;
    cnDiag d;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    CHECK(r.subassemblies && r.stable && r.search.exhaustive && r.nplans == 4);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

void test_plan_split(void) {
    test_popcount();
    test_split_states();
    test_solve_sub_ends();
    test_solve_sub_counts();
    test_root_splits();
    test_grip_carries();
    test_twin_fallback();
    test_invariance();
    test_3d();
    test_public_agrees();
}
