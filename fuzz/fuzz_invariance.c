/* libFuzzer target: the same verdict after a rigid motion, a scaling and a reordering.
 *
 * Bytes -> a small stack of boxes (2-D polygons or 3-D hulls, on a grid of quarter units, so
 * that parts touch exactly), a friction coefficient and a one-step plan that moves the top part
 * (two straight segments, or a straight one and a turn about a bottom corner or edge of the part).
 * The scene is checked and simulated as written and again after a random rotation (gravity and
 * path turn with it), a translation up to 1e6 times its size, a scaling by 1e-9..1e9 (gravity's
 * magnitude and the densities scaled too) and a reordering of its parts. When both runs give a
 * verdict (no error, nothing undecided), the check's verdict and every step's outcome must agree;
 * a difference aborts, which libFuzzer reports as a finding.
 *
 * A scene within rounding of a threshold may honestly differ: a centre of mass exactly over an
 * edge, a path that ends exactly where a part tips (recognised by turning gravity by 1e-6 rad each
 * way; frictionless by 1e-10, below the motion tolerance, else a flat table would already let a
 * part slide), or a held part whose corner passes exactly over the corner it tips about (a
 * measure-zero jam, found or not within the motion search's tolerance: a step that fails on a
 * "not guaranteed" state is not compared with a stable one; and turning the whole scene by 1e-9
 * rad each way, a rigid motion too, must not change the verdict). When any of these changes the
 * verdict, the scene is not compared. */
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "cairn/cairn.h"
#include "fuzz.h"

#define MAXP 5

typedef struct {
    const uint8_t *p;
    size_t n, i;
} Bytes;
static unsigned take(Bytes *b) { return b->i < b->n ? b->p[b->i++] : 0u; }

/* The scene in its own frame: boxes [lo, hi]; part 0 is the fixed ground. Up is the last axis. */
typedef struct {
    int dim, n;
    double mu, lo[MAXP][3], hi[MAXP][3], density[MAXP];
    double path[2][3]; /* the top part's path: two segments */
    bool turn;         /* the second segment turns the part about `about` (in 3-D about a line
                          along the second axis) by `deg` degrees, instead of path[1] */
    double deg, about[3];
    int support_push;
} Scene;

/* How it is written: x' = s R x + t; gravity R g0 * gscale; parts listed in order[]. */
typedef struct {
    double R[3][3], s, t[3], gscale;
    int order[MAXP];
} Frame;

static void mat_vec(const double R[3][3], const double x[3], double y[3]) {
    for (int i = 0; i < 3; i++) y[i] = R[i][0] * x[0] + R[i][1] * x[1] + R[i][2] * x[2];
}

static void rotation(int dim, double angle, const double axis[3], double R[3][3]) {
    double c = cos(angle), s = sin(angle);
    if (dim == 2) {
        double M[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
        memcpy(R, M, sizeof M);
        return;
    }
    double n = sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
    double x = axis[0] / n, y = axis[1] / n, z = axis[2] / n, C = 1 - c;
    double M[3][3] = {{c + x * x * C, x * y * C - z * s, x * z * C + y * s},
                      {y * x * C + z * s, c + y * y * C, y * z * C - x * s},
                      {z * x * C - y * s, z * y * C + x * s, c + z * z * C}};
    memcpy(R, M, sizeof M);
}

static void point(Buf *b, const Scene *sc, const Frame *f, double x, double y, double z) {
    double p[3] = {x, y, z}, q[3];
    mat_vec(f->R, p, q);
    for (int i = 0; i < sc->dim; i++) q[i] = f->s * q[i] + f->t[i];
    if (sc->dim == 2) put(b, "[%.17g,%.17g]", q[0], q[1]);
    else put(b, "[%.17g,%.17g,%.17g]", q[0], q[1], q[2]);
}

/* gravity: down in the scene's frame, turned by `tilt` radians about the first horizontal axis
 * (and, in 3-D with tilt2, about the second) before the frame's rotation */
static char *write_scene(const Scene *sc, const Frame *f, double tilt, double tilt2) {
    Buf b = {malloc(1024), 0, 1024};
    if (!b.s) abort();
    double g0[3], g[3];
    if (sc->dim == 2) g0[0] = sin(tilt), g0[1] = -cos(tilt), g0[2] = 0;
    else g0[0] = sin(tilt), g0[1] = sin(tilt2), g0[2] = -cos(tilt) * cos(tilt2);
    mat_vec(f->R, g0, g);
    put(&b, "{\"dimension\":%d,\"friction\":%.17g,\"gravity\":", sc->dim, sc->mu);
    if (sc->dim == 2) put(&b, "[%.17g,%.17g]", 9.81 * f->gscale * g[0], 9.81 * f->gscale * g[1]);
    else put(&b, "[%.17g,%.17g,%.17g]", 9.81 * f->gscale * g[0], 9.81 * f->gscale * g[1], 9.81 * f->gscale * g[2]);
    put(&b, ",\"parts\":[");
    for (int k = 0; k < sc->n; k++) {
        int i = f->order[k];
        put(&b, "%s{\"name\":\"P%d\",", k ? "," : "", i);
        if (i == 0) put(&b, "\"fixed\":true,");
        /* density per unit area or volume: scaled so that the masses scale with gravity's frame */
        else put(&b, "\"density\":%.17g,", sc->density[i] / pow(f->s, sc->dim));
        const double *lo = sc->lo[i], *hi = sc->hi[i];
        if (sc->dim == 2) {
            put(&b, "\"polygon\":[");
            point(&b, sc, f, lo[0], lo[1], 0), put(&b, ",");
            point(&b, sc, f, hi[0], lo[1], 0), put(&b, ",");
            point(&b, sc, f, hi[0], hi[1], 0), put(&b, ",");
            point(&b, sc, f, lo[0], hi[1], 0);
        } else {
            put(&b, "\"hull\":[");
            for (int v = 0; v < 8; v++) {
                if (v) put(&b, ",");
                point(&b, sc, f, (v & 1) ? hi[0] : lo[0], (v & 2) ? hi[1] : lo[1], (v & 4) ? hi[2] : lo[2]);
            }
        }
        put(&b, "]}");
    }
    put(&b, "],\"plan\":[{\"move\":\"P%d\",\"support\":\"%s\",\"path\":[", sc->n - 1,
        sc->support_push ? "push" : "hold");
    for (int k = 0; k < 2; k++) {
        double q[3];
        if (k == 1 && sc->turn) { /* the turn's centre moves as a point, its axis turns with R */
            put(&b, ",{\"rotate\":%.17g,\"about\":", sc->deg);
            point(&b, sc, f, sc->about[0], sc->about[1], sc->about[2]);
            if (sc->dim == 3) {
                const double y[3] = {0, 1, 0};
                mat_vec(f->R, y, q);
                put(&b, ",\"axis\":[%.17g,%.17g,%.17g]", q[0], q[1], q[2]);
            }
            put(&b, "}");
            continue;
        }
        mat_vec(f->R, sc->path[k], q);
        if (sc->dim == 2) put(&b, "%s[%.17g,%.17g]", k ? "," : "", f->s * q[0], f->s * q[1]);
        else put(&b, "%s[%.17g,%.17g,%.17g]", k ? "," : "", f->s * q[0], f->s * q[1], f->s * q[2]);
    }
    put(&b, "]}]}");
    return b.s;
}

/* The outcome compared: -1 when there is none to compare (an error or something undecided). */
typedef struct {
    int check; /* cnVerdict */
    int steps; /* the step's status */
    bool jam;  /* the step failed where a static solution exists but so does a motion from rest */
} Outcome;

static Outcome run(const char *json) {
    Outcome o = {-1, -1, false};
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(json, "fuzz", &a, &d) != CN_OK) return o;
    cnCheckOptions co = cn_check_options_default();
    co.max_nodes = 100;
    cnCheckResult r;
    if (cn_check(a, &co, &r, &d) == CN_OK) {
        if (r.verdict != CN_VERDICT_UNDECIDED) o.check = (int)r.verdict;
        /* with more corner contacts than every reading can be tried for, a check decides the
         * first reading (and its complement when it stands), which one the frame picks: only
         * "not stable" is compared then, not unstable against not guaranteed */
        if (r.corners.readings_all > CN_CORNER_READINGS && !r.corners.by_field && r.verdict == CN_VERDICT_NOT_GUARANTEED)
            o.check = (int)CN_VERDICT_UNSTABLE;
        cn_check_result_free(&r);
    }
    cnSimOptions so = cn_sim_options_default();
    so.check.max_nodes = 50;
    so.max_samples = 60;
    cnSimResult sr;
    if (cn_simulate(a, &so, &sr, &d) == CN_OK) {
        if (!sr.undecided && sr.nsteps == 1 && sr.steps[0].status != CN_STEP_UNDECIDED)
            o.steps = (int)sr.steps[0].status;
        if (o.steps == CN_STEP_UNSTABLE) o.jam = sr.steps[0].onset.verdict == CN_VERDICT_NOT_GUARANTEED;
        cn_sim_result_free(&sr);
    }
    cn_assembly_free(a);
    return o;
}

/* A motion from rest that only a jam allows (a held part's corner passing exactly over the
 * corner a part would tip about, forces without bound) is found within the search's tolerance,
 * so at such an instant "not guaranteed" against "stable" is a threshold, not a finding. */
static bool fails(int st) { return st == CN_STEP_UNSTABLE || st == CN_STEP_INFEASIBLE; }

/* A step that fails fails in every frame; which comes first, an instability or a collision, may
 * tie (a pushed part reaching a surface as the part it left starts to move) and is not compared. */
static bool same(Outcome a, Outcome b) {
    bool steps = a.steps < 0 || b.steps < 0 || a.steps == b.steps || (fails(a.steps) && fails(b.steps)) ||
                 (a.jam && b.steps == CN_STEP_STABLE) || (b.jam && a.steps == CN_STEP_STABLE);
    return (a.check < 0 || b.check < 0 || a.check == b.check) && steps;
}

static const double kMu[4] = {0, 0.2, 0.5, 0.9};
static const double kScale[5] = {1e-9, 1e-3, 1, 1e3, 1e9};
static const double kOffset[4] = {0, 1e2, 1e4, 1e6};

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    Bytes in = {data, size, 0};
    Scene sc;
    memset(&sc, 0, sizeof sc);
    unsigned h = take(&in);
    sc.dim = (h & 1) ? 3 : 2;
    sc.n = 2 + (int)((h >> 1) % (MAXP - 1));
    sc.mu = kMu[(h >> 3) % 4];
    sc.support_push = (h >> 5) & 1;
    int up = sc.dim - 1;
    /* the ground: [-8, 8]^(d-1) x [-1, 0] */
    for (int k = 0; k < 3; k++) sc.lo[0][k] = -8, sc.hi[0][k] = 8;
    sc.lo[0][up] = -1, sc.hi[0][up] = 0;
    if (sc.dim == 2) sc.lo[0][2] = sc.hi[0][2] = 0;
    for (int i = 1; i < sc.n; i++) {
        int on = (int)(take(&in) % (unsigned)i);
        unsigned g = take(&in), w = take(&in);
        double ext[3] = {0.5 + 0.5 * (w % 4), 0.5 + 0.5 * ((w >> 2) % 3), 0.5 + 0.5 * ((w >> 4) % 4)};
        if (sc.dim == 2) ext[1] = ext[2], ext[2] = 0;
        for (int k = 0; k < up; k++) {
            double base = on ? sc.lo[on][k] : -2;
            sc.lo[i][k] = base - 0.5 + 0.25 * (double)((g >> (4 * k)) % 12);
            sc.hi[i][k] = sc.lo[i][k] + ext[k];
        }
        sc.lo[i][up] = sc.hi[on][up];
        sc.hi[i][up] = sc.lo[i][up] + ext[up];
        sc.density[i] = 1 + (double)((w >> 6) % 3);
    }
    unsigned p = take(&in);
    static const double kDir[6][3] = {{0, 0, 1}, {1, 0, 0}, {-1, 0, 0}, {1, 0, 1}, {0, 1, 0}, {-1, 0, -0.5}};
    for (int k = 0; k < 2; k++) {
        const double *dv = kDir[(p >> (3 * k)) % 6];
        double len = 0.5 * (1 + (p >> 6) % 4);
        /* the scene's up axis is the last one: in 2-D the third direction component is up */
        sc.path[k][0] = len * dv[0];
        if (sc.dim == 2) sc.path[k][1] = len * dv[2], sc.path[k][2] = 0;
        else sc.path[k][1] = len * dv[1], sc.path[k][2] = len * dv[2];
    }
    /* or, for the second segment, a turn about a bottom corner (2-D) or edge (3-D) of the moved
     * part where the first segment left it: lifting the far side, or pressing into what is below */
    unsigned tb = take(&in);
    if (tb & 1) {
        int top = sc.n - 1;
        sc.turn = true;
        sc.deg = ((tb >> 1) & 1 ? -1 : 1) * (10.0 + 10.0 * (double)((tb >> 2) % 6));
        sc.about[0] = ((tb >> 5) & 1 ? sc.hi[top][0] : sc.lo[top][0]) + sc.path[0][0];
        if (sc.dim == 2) {
            sc.about[1] = sc.lo[top][1] + sc.path[0][1], sc.about[2] = 0;
        } else {
            sc.about[1] = 0.5 * (sc.lo[top][1] + sc.hi[top][1]) + sc.path[0][1];
            sc.about[2] = sc.lo[top][2] + sc.path[0][2];
        }
    }

    Frame id, fr;
    memset(&id, 0, sizeof id);
    id.s = 1, id.gscale = 1;
    for (int k = 0; k < 3; k++) id.R[k][k] = 1;
    for (int i = 0; i < sc.n; i++) id.order[i] = i;
    unsigned t1 = take(&in), t2 = take(&in), t3 = take(&in);
    double axis[3] = {(double)(t2 & 7) - 3.5, (double)((t2 >> 3) & 7) - 3.5, (double)(t3 & 7) - 3.5};
    fr = id;
    rotation(sc.dim, (double)t1 * (6.283185307179586 / 256.0), axis, fr.R);
    unsigned t4 = take(&in);
    fr.s = kScale[(t3 >> 3) % 5];
    fr.gscale = fr.s;
    double off = kOffset[t4 % 4] * fr.s;
    for (int k = 0; k < sc.dim; k++) fr.t[k] = off * (k == 0 ? 0.6 : k == 1 ? -0.8 : 0.3);
    unsigned sh = take(&in);
    for (int i = 0; i < sc.n; i++) fr.order[i] = (int)(((unsigned)i + sh) % (unsigned)sc.n);
    if (sh & 0x80)
        for (int i = 0; i < sc.n / 2; i++) {
            int tmp = fr.order[i];
            fr.order[i] = fr.order[sc.n - 1 - i], fr.order[sc.n - 1 - i] = tmp;
        }

    char *base = write_scene(&sc, &id, 0, 0);
    Outcome ob = run(base);
    if (ob.check < 0 && ob.steps < 0) {
        free(base);
        return 0;
    }
    /* near a threshold? turn gravity a little each way */
    double eps = sc.mu > 0 ? 1e-6 : 1e-10;
    int ntilt = sc.dim == 2 ? 2 : 4;
    for (int k = 0; k < ntilt; k++) {
        double a1 = k < 2 ? (k ? -eps : eps) : 0, a2 = k < 2 ? 0 : (k == 2 ? eps : -eps);
        char *t = write_scene(&sc, &id, a1, a2);
        Outcome ot = run(t);
        free(t);
        if (!same(ob, ot) || (ob.check >= 0) != (ot.check >= 0) || (ob.steps >= 0) != (ot.steps >= 0)) {
            free(base);
            return 0;
        }
    }
    for (int k = 0; k < 2; k++) {
        Frame tiny = id;
        double skew[3] = {0.3, -0.5, 0.8};
        rotation(sc.dim, k ? 1e-9 : -1e-9, skew, tiny.R);
        char *t = write_scene(&sc, &tiny, 0, 0);
        Outcome ot = run(t);
        free(t);
        if (!same(ob, ot) || (ob.check >= 0) != (ot.check >= 0) || (ob.steps >= 0) != (ot.steps >= 0)) {
            free(base);
            return 0;
        }
    }
    char *moved = write_scene(&sc, &fr, 0, 0);
    Outcome om = run(moved);
    if (!same(ob, om)) {
        fprintf(stderr, "invariance: check %d vs %d, step %d vs %d\nas written: %s\nmoved: %s\n", ob.check,
                om.check, ob.steps, om.steps, base, moved);
        abort();
    }
    if (getenv("CAIRN_FUZZ_PRINT")) printf("%s\n%s\n", base, moved);
    free(base);
    free(moved);
    return 0;
}
