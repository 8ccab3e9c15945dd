/* Degenerate geometry: vertex on vertex, vertex on edge, crossing edges (3-D), slivers of 1e-9
 * of the part size, parts of 1e-4 and 1e4 units in one file, nearly coplanar faces, mass ratios
 * of 1e6, parts that only just touch, just miss or just overlap. Each case has a verdict known
 * by hand (or an input error), and the verdict and the set of parts that move must not change
 * when the whole assembly and its gravity are rotated, translated, scaled or its parts listed in
 * reverse order. */
#include <jansson.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <valgrind/valgrind.h>

#include "helpers.h"

enum { V_STABLE, V_UNSTABLE, V_ERROR };
static const char *const kVerdict[] = {"stable", "unstable", "an input error"};

typedef struct {
    double R[3][3]; /* rotation */
    double s;       /* scale */
    double t[3];    /* translation, applied after rotation and scale */
    bool reverse;   /* list the parts in reverse order */
    const char *name;
} Xform;

static void xpoint(const Xform *x, int dim, json_t *p, bool is_vector) {
    double v[3] = {0, 0, 0}, w[3];
    for (int k = 0; k < dim; k++) v[k] = json_number_value(json_array_get(p, (size_t)k));
    for (int i = 0; i < 3; i++) {
        w[i] = 0;
        for (int k = 0; k < 3; k++) w[i] += x->R[i][k] * v[k];
        if (!is_vector) w[i] = x->s * w[i] + x->t[i];
    }
    for (int k = 0; k < dim; k++) json_array_set_new(p, (size_t)k, json_real(w[k]));
}

static void xpoints(const Xform *x, int dim, json_t *arr) {
    for (size_t i = 0; i < json_array_size(arr); i++) xpoint(x, dim, json_array_get(arr, i), false);
}

/* The assembly JSON moved by x (boxes are not allowed in these cases: they cannot rotate). */
static char *transform(const char *text, const Xform *x) {
    json_error_t err;
    json_t *root = json_loads(text, 0, &err);
    if (!root) return NULL;
    int dim = (int)json_integer_value(json_object_get(root, "dimension"));
    json_t *g = json_object_get(root, "gravity");
    if (g) xpoint(x, dim, g, true);
    json_t *parts = json_object_get(root, "parts");
    for (size_t i = 0; i < json_array_size(parts); i++) {
        json_t *p = json_array_get(parts, i), *v;
        if ((v = json_object_get(p, "polygon"))) xpoints(x, dim, v);
        if ((v = json_object_get(p, "hull"))) xpoints(x, dim, v);
        json_t *many = json_object_get(p, "polygons");
        if (!many) many = json_object_get(p, "hulls");
        for (size_t j = 0; j < json_array_size(many); j++) xpoints(x, dim, json_array_get(many, j));
    }
    if (x->reverse) {
        json_t *rev = json_array();
        for (size_t i = json_array_size(parts); i-- > 0;) json_array_append(rev, json_array_get(parts, i));
        json_object_set_new(root, "parts", rev);
    }
    char *out = json_dumps(root, JSON_REAL_PRECISION(17));
    json_decref(root);
    return out;
}

/* The search budget of verdict()'s checks (0: the default). */
static long search_budget;

/* Verdict and the names of the parts that move, joined by spaces in name order. */
static int verdict(const char *json, char *moving, size_t cap, char *why, size_t whycap) {
    moving[0] = 0, why[0] = 0;
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(json, "case", &a, &d) != CN_OK) {
        snprintf(why, whycap, "%s: %s", d.where, d.message);
        return V_ERROR;
    }
    cnCheckOptions o = cn_check_options_default();
    o.max_nodes = search_budget;
    cnCheckResult r;
    cnStatus st = cn_check(a, &o, &r, &d);
    if (st != CN_OK) {
        snprintf(why, whycap, "%s: %s", d.where, d.message);
        cn_assembly_free(a);
        return st == CN_ERR_INPUT ? V_ERROR : -1;
    }
    /* names of moving parts, sorted */
    const char *names[64];
    int n = 0;
    for (int i = 0; i < r.nmoving && n < 64; i++) names[n++] = a->parts[r.moving[i]].name;
    for (int i = 1; i < n; i++)
        for (int j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; j--) {
            const char *t = names[j];
            names[j] = names[j - 1], names[j - 1] = t;
        }
    size_t len = 0;
    for (int i = 0; i < n; i++) len += (size_t)snprintf(moving + len, cap - len, "%s%s", i ? " " : "", names[i]);
    int v = r.stable ? V_STABLE : V_UNSTABLE;
    if (r.verdict == CN_VERDICT_UNDECIDED) { /* no verdict, honestly: the search ran out */
        snprintf(why, whycap, "undecided after %ld LPs", r.solver.search_nodes);
        v = -1;
    }
    cn_check_result_free(&r);
    cn_assembly_free(a);
    return v;
}

static void rot_axis(double R[3][3], const double axis[3], double ang) {
    double n = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    double u[3] = {axis[0] / n, axis[1] / n, axis[2] / n}, c = cos(ang), s = sin(ang);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) R[i][j] = (i == j ? c : 0) + (1 - c) * u[i] * u[j];
    R[0][1] -= s * u[2], R[0][2] += s * u[1];
    R[1][0] += s * u[2], R[1][2] -= s * u[0];
    R[2][0] -= s * u[1], R[2][1] += s * u[0];
}

/* Checks the verdict (and, if not NULL, the moving parts) of `json` under every transform.
 * With allow_numeric, a numerical failure (exit 3: "no verdict") is accepted in place of the
 * verdict, never the opposite verdict; the count of those is returned. */
static int expect_or_numeric(const char *name, const char *json, int want, const char *want_moving,
                             bool allow_numeric) {
    int numeric = 0;
    int dim = strstr(json, "\"dimension\":3") ? 3 : 2;
    Xform xs[8];
    int nx = 0;
    double z[3] = {0, 0, 1}, gen[3] = {0.3, -0.5, 0.8};
    for (int k = 0; k < 8; k++) {
        memset(&xs[k], 0, sizeof xs[k]);
        rot_axis(xs[k].R, z, 0);
        xs[k].s = 1;
    }
    xs[nx++].name = "as given";
    rot_axis(xs[nx].R, dim == 2 ? z : gen, 0.7), xs[nx++].name = "rotated by 0.7 rad";
    rot_axis(xs[nx].R, z, 1.5707963267948966), xs[nx++].name = "rotated by 90 degrees";
    rot_axis(xs[nx].R, dim == 2 ? z : gen, 2.9), xs[nx++].name = "rotated by 2.9 rad";
    xs[nx].t[0] = 1234.5, xs[nx].t[1] = -678.25, xs[nx].t[2] = dim == 3 ? 91.125 : 0;
    xs[nx++].name = "translated by (1234.5, -678.25, 91.125)";
    xs[nx].s = 1e-3, xs[nx++].name = "scaled by 1e-3";
    xs[nx].s = 1e3, xs[nx++].name = "scaled by 1e3";
    xs[nx].reverse = true, xs[nx++].name = "parts in reverse order";
    /* under valgrind's memcheck two poses: the others run the same code on other numbers */
    if (RUNNING_ON_VALGRIND) nx = 2;
    for (int k = 0; k < nx; k++) {
        char *text = transform(json, &xs[k]);
        CHECK_MSG(text != NULL, "%s: the case's JSON does not parse", name);
        if (!text) return numeric;
        char moving[512], why[1024];
        int v = verdict(text, moving, sizeof moving, why, sizeof why);
        if (v < 0 && allow_numeric) {
            numeric++;
            free(text);
            continue;
        }
        CHECK_MSG(v == want, "%s, %s: %s, expected %s (%s)", name, xs[k].name,
                  v < 0 ? "a numerical failure" : kVerdict[v], kVerdict[want], why);
        if (v == want && want_moving)
            CHECK_MSG(!strcmp(moving, want_moving), "%s, %s: moving '%s', expected '%s'", name,
                      xs[k].name, moving, want_moving);
        free(text);
    }
    return numeric;
}

static void expect(const char *name, const char *json, int want, const char *want_moving) {
    expect_or_numeric(name, json, want, want_moving, false);
}

#define TABLE2 "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]}"
#define TABLE3 "{\"name\":\"T\",\"fixed\":true,\"hull\":[[-5,-5,-1],[5,-5,-1],[5,5,-1],[-5,5,-1]," \
               "[-5,-5,0],[5,-5,0],[5,5,0],[-5,5,0]]}"

static char *fmt(const char *f, ...) __attribute__((format(printf, 1, 2)));
static char *fmt(const char *f, ...) {
    char *buf = malloc(8192);
    va_list ap;
    va_start(ap, f);
    vsnprintf(buf, 8192, f, ap);
    va_end(ap);
    return buf;
}

static void test_vertex_contacts(void) {
    /* B's bottom-left corner on A's top-right corner only: B falls */
    expect("vertex on vertex",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
           "{\"name\":\"A\",\"polygon\":[[-1,0],[1,0],[1,1],[-1,1]]},"
           "{\"name\":\"B\",\"polygon\":[[1,1],[2,1],[2,2],[1,2]]}]}",
           V_UNSTABLE, "B");
    /* a plank on two fixed spikes (vertex on edge) either side of its centre: stable */
    expect("vertex on edge, two spikes",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
           "{\"name\":\"S1\",\"fixed\":true,\"polygon\":[[-2,0],[-1,0],[-1.5,1]]},"
           "{\"name\":\"S2\",\"fixed\":true,\"polygon\":[[1,0],[2,0],[1.5,1]]},"
           "{\"name\":\"P\",\"polygon\":[[-3,1],[3,1],[3,1.2],[-3,1.2]]}]}",
           V_STABLE, "");
    /* the same plank on one spike off its centre: it tips */
    expect("vertex on edge, one spike",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
           "{\"name\":\"S1\",\"fixed\":true,\"polygon\":[[-2,0],[-1,0],[-1.5,1]]},"
           "{\"name\":\"P\",\"polygon\":[[-3,1],[3,1],[3,1.2],[-3,1.2]]}]}",
           V_UNSTABLE, "P");
    /* a triangle standing on its apex, its centroid off the apex: it falls */
    expect("apex on a table",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
           "{\"name\":\"W\",\"polygon\":[[0,0],[2,1.5],[-0.5,1.5]]}]}",
           V_UNSTABLE, "W");
}

static void test_crossing_edges(void) {
    /* two fixed ridges along x (y = -1 and y = 1); a prism lies across them ridge down (its ridge
     * along y): two edge-on-edge crossings. Its cross-section is lopsided, so its centre is off
     * the line through the two crossings: it rolls off. */
    expect("crossing edges, lopsided prism",
           "{\"dimension\":3,\"gravity\":[0,0,-1],\"parts\":[" TABLE3 ","
           "{\"name\":\"R1\",\"fixed\":true,\"hull\":[[-3,-1.5,0],[3,-1.5,0],[-3,-0.5,0],[3,-0.5,0],[-3,-1,1],[3,-1,1]]},"
           "{\"name\":\"R2\",\"fixed\":true,\"hull\":[[-3,0.5,0],[3,0.5,0],[-3,1.5,0],[3,1.5,0],[-3,1,1],[3,1,1]]},"
           "{\"name\":\"X\",\"hull\":[[0,-3,1],[0,3,1],[-0.5,-3,2],[-0.5,3,2],[2,-3,2],[2,3,2]]}]}",
           V_UNSTABLE, "X");
    /* a flat plate across the same ridges: two line contacts, stable */
    expect("plate across two ridges",
           "{\"dimension\":3,\"gravity\":[0,0,-1],\"parts\":[" TABLE3 ","
           "{\"name\":\"R1\",\"fixed\":true,\"hull\":[[-3,-1.5,0],[3,-1.5,0],[-3,-0.5,0],[3,-0.5,0],[-3,-1,1],[3,-1,1]]},"
           "{\"name\":\"R2\",\"fixed\":true,\"hull\":[[-3,0.5,0],[3,0.5,0],[-3,1.5,0],[3,1.5,0],[-3,1,1],[3,1,1]]},"
           "{\"name\":\"X\",\"hull\":[[-1,-3,1],[1,-3,1],[1,3,1],[-1,3,1],[-1,-3,1.2],[1,-3,1.2],[1,3,1.2],[-1,3,1.2]]}]}",
           V_STABLE, "");
    /* a tetrahedron resting on one of its edges across a fixed ridge: one crossing, falls */
    expect("edge across a ridge",
           "{\"dimension\":3,\"gravity\":[0,0,-1],\"parts\":[" TABLE3 ","
           "{\"name\":\"R1\",\"fixed\":true,\"hull\":[[-3,-0.5,0],[3,-0.5,0],[-3,0.5,0],[3,0.5,0],[-3,0,1],[3,0,1]]},"
           "{\"name\":\"X\",\"hull\":[[0,-1,1],[0,1,1],[1,0.3,2],[-0.2,-0.4,2.5]]}]}",
           V_UNSTABLE, "X");
}

static void test_slivers_and_sizes(void) {
    /* a sliver 1e-9 thick (of its length 2) lies on the table under a block: both stay */
    expect("sliver under a block",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
           "{\"name\":\"S\",\"polygon\":[[-1,0],[1,0],[1,2e-9],[-1,2e-9]]},"
           "{\"name\":\"B\",\"polygon\":[[-0.5,2e-9],[0.5,2e-9],[0.5,1.000000002],[-0.5,1.000000002]]}]}",
           V_STABLE, "");
    /* a wedge with a 1e-9 sliver of a top: its centre over the table, stable */
    expect("sliver top",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
           "{\"name\":\"W\",\"polygon\":[[-1,0],[1,0],[1,1e-9],[-1,1]]}]}",
           V_STABLE, "");
    /* parts of 1e4 and 1e-4 in one file: a block of 1e-4 on a slab 2e4 wide is stable; a second
     * one of 1e-4 more than half over the edge of the first (a trapezoid, its top corner over its base) falls */
    expect("1e4 and 1e-4 units, stable",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
           "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-1e4,-1e4],[1e4,-1e4],[1e4,0],[-1e4,0]]},"
           "{\"name\":\"a\",\"polygon\":[[0,0],[1e-4,0],[1e-4,1e-4],[0,1e-4]]},"
           "{\"name\":\"b\",\"polygon\":[[0,1e-4],[1e-4,1e-4],[1e-4,2e-4],[0,2e-4]]},"
           "{\"name\":\"H\",\"polygon\":[[1000,0],[3000,0],[3000,2000],[1000,2000]]}]}",
           V_STABLE, "");
    expect("1e4 and 1e-4 units, overhang",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
           "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-1e4,-1e4],[1e4,-1e4],[1e4,0],[-1e4,0]]},"
           "{\"name\":\"a\",\"polygon\":[[0,0],[3e-4,0],[2e-4,1e-4],[0,1e-4]]},"
           "{\"name\":\"b\",\"polygon\":[[1.6e-4,1e-4],[2.6e-4,1e-4],[2.6e-4,2e-4],[1.6e-4,2e-4]]},"
           "{\"name\":\"H\",\"polygon\":[[1000,0],[3000,0],[3000,2000],[1000,2000]]}]}",
           V_UNSTABLE, "b");
}

static void test_tolerance_boundary(void) {
    /* the contact tolerance is 1e-6 of the smaller part (the block, 1.414 across): a block 1e-8 above
     * or 1e-8 into the table rests on it; 1e-4 above, it falls; 1e-4 into it is an overlap */
    const char *tpl = "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
                      "{\"name\":\"B\",\"polygon\":[[-0.5,%.17g],[0.5,%.17g],[0.5,%.17g],[-0.5,%.17g]]}]}";
    struct {
        double gap;
        int want;
        const char *name;
    } cases[] = {{1e-8, V_STABLE, "just above (1e-9 of the size)"},
                 {-1e-8, V_STABLE, "just into (1e-9 of the size)"},
                 {1e-4, V_UNSTABLE, "above (1e-5 of the size)"},
                 {-1e-4, V_ERROR, "overlapping (1e-5 of the size)"}};
    for (int i = 0; i < 4; i++) {
        double y = cases[i].gap;
        char *j = fmt(tpl, y, y, y + 1, y + 1);
        expect(cases[i].name, j, cases[i].want, cases[i].want == V_UNSTABLE ? "B" : cases[i].want == V_STABLE ? "" : NULL);
        free(j);
    }
    /* nearly coplanar: the block's base tilted by 1e-8 (within the tolerance) rests flat; by
     * 1e-3 it stands on one corner... which is still over the table: stable either way, and the
     * near-flat one must find both corners */
    expect("base tilted by 1e-8",
           "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" TABLE2 ","
           "{\"name\":\"B\",\"polygon\":[[-0.5,0],[0.5,1e-8],[0.5,1],[-0.5,1]]}]}",
           V_STABLE, "");
    /* 3-D: a box whose base is 1e-8 off flat on two corners */
    expect("3-D base nearly coplanar",
           "{\"dimension\":3,\"gravity\":[0,0,-1],\"parts\":[" TABLE3 ","
           "{\"name\":\"B\",\"hull\":[[-1,-1,0],[1,-1,1e-8],[1,1,1e-8],[-1,1,0],"
           "[-1,-1,1],[1,-1,1],[1,1,1],[-1,1,1]]}]}",
           V_STABLE, "");
}

static void test_mass_ratios(void) {
    /* Fig. 1's counterweight with a 1e6 density ratio: C heavy holds the plank B against D;
     * D heavy and C light, the plank tips towards D */
    const char *tpl = "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                      "{\"name\":\"E\",\"fixed\":true,\"polygon\":[[-4,-1],[6,-1],[6,0],[-4,0]]},"
                      "{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
                      "{\"name\":\"B\",\"polygon\":[[-0.5,1],[3.5,1],[3.5,1.5],[-0.5,1.5]]},"
                      "{\"name\":\"C\",\"density\":%g,\"polygon\":[[-0.5,1.5],[0.5,1.5],[0.5,3],[-0.5,3]]},"
                      "{\"name\":\"D\",\"density\":%g,\"polygon\":[[2.5,1.5],[3.5,1.5],[3.5,3],[2.5,3]]}]}";
    char *j = fmt(tpl, 1e6, 1.0);
    expect("mass ratio 1e6, heavy counterweight", j, V_STABLE, "");
    free(j);
    j = fmt(tpl, 1.0, 1e6);
    expect("mass ratio 1e6, heavy overhang", j, V_UNSTABLE, "B C D");
    free(j);
    /* Two squares stacked on a table stand whatever their masses. Light under heavy, the lower
     * one carries forces up to 1e16 times its weight: a verdict, when cairn gives one, must be
     * "stable" (beyond about 1e8 it may say it cannot decide: exit 3). A Farkas certificate
     * judged in each column's own units once "proved" at 1e12 that the light square slides out. */
    const char *stack = "{\"dimension\":2,\"gravity\":[0,-1],%s\"parts\":["
                        "{\"name\":\"t\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                        "{\"name\":\"L\",\"mass\":1e-10,\"polygon\":[[0,0],[1,0],[1,1],[0,1]]},"
                        "{\"name\":\"U\",\"mass\":%g,\"polygon\":[[0,1],[1,1],[1,2],[0,2]]}]}";
    int decided = 0, runs = 0;
    for (double ratio = 1e4; ratio <= 1e16; ratio *= 100)
        for (int fr = 0; fr < 2; fr++) {
            j = fmt(stack, fr ? "\"friction\":0.5," : "", 1e-10 * ratio);
            char moving[256], why[512];
            int v = verdict(j, moving, sizeof moving, why, sizeof why);
            runs++;
            decided += v >= 0;
            CHECK_MSG(v < 0 || v == V_STABLE, "stack, mass ratio %g%s: %s (%s)", ratio,
                      fr ? ", friction 0.5" : "", v < 0 ? "?" : kVerdict[v], moving);
            free(j);
        }
    CHECK_MSG(decided >= 6, "stack: only %d of %d mass ratios decided", decided, runs);
}

/* a 3-D block on a 30-degree incline: it stays when mu > tan 30 = 0.5774 and slides when below,
 * alone and with a block 1e3 or 1e6 times denser on it. At 1e6 the friction LCP (whose matrix
 * has eigenvalues 1e6 apart) is not always solved by Lemke: cairn then says so (exit 3) and
 * gives no verdict; that is accepted here, a wrong verdict is not. With the heavy block on top
 * and mu 0.6 a static solution exists, but the search for a motion from rest does not end
 * within its budget (50,000 LPs did not either): "undecided" (exit 3) is accepted there, and
 * "stable" only when proved. */
static void test_incline_friction(void) {
    const char *tpl =
        "{\"dimension\":3,\"gravity\":[0,0,-1],\"friction\":%g,\"parts\":["
        "{\"name\":\"R\",\"fixed\":true,\"hull\":[[-4,-2,-1],[4,-2,-1],[4,2,-1],[-4,2,-1],"
        "[-4,-2,-0.5],[4,-2,-0.5],[4,2,-0.5],[-4,2,4.118802153517006],[-4,-2,4.118802153517006]]},"
        "{\"name\":\"B\",\"hull\":[%s]}%s]}";
    /* the block: 1 x 1 x 0.5 on the slope z = -0.5 + (4 - x) tan 30 / ... built in the slope's
     * frame: u along the slope (down +x), n its normal */
    double t = 0.5235987755982988, c = cos(t), sn = sin(t);
    double u[3] = {c, 0, -sn}, nn[3] = {sn, 0, c};
    double o[3] = {0, 0, -0.5 + 4 * tan(t)}; /* the slope's point above x = 0 */
    char blk[2048] = "", top[2048] = "";
    size_t len = 0, lt = 0;
    for (int k = 0; k < 8; k++) {
        double a1 = (k & 1) ? 0.5 : -0.5, a2 = (k & 2) ? 0.5 : -0.5, a3 = (k & 4) ? 0.5 : 0;
        double p[3], q[3];
        for (int d = 0; d < 3; d++) {
            p[d] = o[d] + a1 * u[d] + a3 * nn[d] + (d == 1 ? a2 : 0);
            q[d] = o[d] + a1 * 0.5 * u[d] + (0.5 + a3) * nn[d] + (d == 1 ? a2 * 0.5 : 0);
        }
        len += (size_t)snprintf(blk + len, sizeof blk - len, "%s[%.17g,%.17g,%.17g]", k ? "," : "", p[0], p[1], p[2]);
        lt += (size_t)snprintf(top + lt, sizeof top - lt, "%s[%.17g,%.17g,%.17g]", k ? "," : "", q[0], q[1], q[2]);
    }
    char heavy[2][2600];
    snprintf(heavy[0], sizeof heavy[0], ",{\"name\":\"H\",\"density\":1e3,\"hull\":[%s]}", top);
    snprintf(heavy[1], sizeof heavy[1], ",{\"name\":\"H\",\"density\":1e6,\"hull\":[%s]}", top);
    double mus[2] = {0.6, 0.55};
    /* 500 LPs: where the heavy block makes the search undecided, more (50,000 tried) do not
       decide it (accepted below); the cases that must be decided are decided within them */
    search_budget = 500;
    /* under memcheck the 1e6 block is left out: the 1e3 one runs the same code */
    for (int h = 0; h < (RUNNING_ON_VALGRIND ? 2 : 3); h++)
        for (int i = 0; i < 2; i++) {
            char *j = fmt(tpl, mus[i], blk, h ? heavy[h - 1] : "");
            char name[96];
            snprintf(name, sizeof name, "incline 30 deg, mu %g%s", mus[i],
                     h == 0 ? "" : h == 1 ? ", 1e3 denser block on top" : ", 1e6 denser block on top");
            int nnum = expect_or_numeric(name, j, i == 0 ? V_STABLE : V_UNSTABLE,
                                         i == 0 ? "" : h ? "B H" : "B", h == 2 || (h && i == 0));
            if (nnum) printf("degenerate: %s: no verdict (numerical, or the search undecided) in %d of 8 poses\n", name, nnum);
            free(j);
        }
    search_budget = 0;
}

void test_degenerate(void) {
    test_incline_friction();
    test_vertex_contacts();
    test_crossing_edges();
    test_slivers_and_sizes();
    test_tolerance_boundary();
    test_mass_ratios();
}
