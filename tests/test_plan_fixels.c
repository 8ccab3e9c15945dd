/* The fixel suggestions of a failing step (plan/plan_fixels.c), on a planner built here as cn_plan
 * builds it, for single steps of tiny scenes whose answers are derived by hand in the comments: a
 * block over a table's edge held back by a counterweight that is lifted off (2-D and 3-D, squat
 * and tall, frictionless and with friction), a plank and a dome on a post pulled away from under
 * them, a block on a seesaw plank turned away from under it (free fall), with and without a fixel
 * of the file, and the boxed block on an incline of the examples through the public cn_plan.
 * Every suggestion is checked against the fixels derived by hand; against the faces the failing
 * motion opens, recomputed from the onset the public cn_simulate reports; by simulating the step
 * again with the public cn_simulate, the fixels written into the file as docs/format.md describes
 * (the file loads and the step is stable); and by the number of trial simulations that the rule
 * implies (docs/cli.md: one fixel if one suffices, else two; the candidates best first, at most
 * 10, alone and then in pairs). Also: no suggestion where no one or two fixels can help, none for
 * a step that does not fail, and the same fixels after translating the scene or reordering its
 * parts. */
#include <stdlib.h>
#include <string.h>

#include "core.h"
#include "helpers.h"
#include "plan_state.h"

/* ---- scenes: axis-aligned boxes ---- */

typedef struct {
    const char *name;
    bool fixed;
    double lo[3], hi[3]; /* 2-D: x, y */
} Box;

/* A fixel, its part by name. */
typedef struct {
    char part[16];
    double point[3], normal[3];
} Fx;

typedef struct {
    int dim;
    int n;
    Box b[4];
    const char *mover; /* the part the step takes out */
    bool turn;         /* its path: a turn by `angle` degrees about the point `seg` (2-D), else a
                          move by `seg` */
    double seg[3], angle;
    int nfile;         /* fixels of the file */
    Fx file[1];
    double mu;         /* friction (0: none) */
} Scene;

enum { WITH_CANDIDATE, WITH_PLAN };

static int put_fixels(char *js, size_t cap, int dim, const Fx *f, int n, const double sh[3], bool first) {
    int len = 0;
    for (int i = 0; i < n; i++) {
        len += snprintf(js + len, cap - (size_t)len, "%s{\"part\":\"%s\",\"point\":[", first && !i ? "" : ",",
                        f[i].part);
        for (int k = 0; k < dim; k++)
            len += snprintf(js + len, cap - (size_t)len, "%s%.17g", k ? "," : "", f[i].point[k] + sh[k]);
        len += snprintf(js + len, cap - (size_t)len, "],\"normal\":[");
        for (int k = 0; k < dim; k++)
            len += snprintf(js + len, cap - (size_t)len, "%s%.17g", k ? "," : "", f[i].normal[k]);
        len += snprintf(js + len, cap - (size_t)len, "]}");
    }
    return len;
}

/* The scene as a file: its boxes listed in order[] (NULL: as given), everything moved by sh; the
 * file's fixels and `extra` ones; the step as the mover's one candidate path or as the file's
 * plan. */
static cnAssembly *scene_load(const Scene *sc, const int *order, const double sh[3], const Fx *extra,
                              int nextra, int mode) {
    char js[8192];
    size_t cap = sizeof js;
    int dim = sc->dim;
    int len = snprintf(js, cap, "{\"dimension\":%d,\"gravity\":%s,\"friction\":%.17g,\"parts\":[", dim,
                       dim == 2 ? "[0,-1]" : "[0,0,-1]", sc->mu);
    for (int i = 0; i < sc->n; i++) {
        const Box *b = &sc->b[order ? order[i] : i];
        double x0 = b->lo[0] + sh[0], y0 = b->lo[1] + sh[1], x1 = b->hi[0] + sh[0], y1 = b->hi[1] + sh[1];
        len += snprintf(js + len, cap - (size_t)len, "%s{\"name\":\"%s\",%s", i ? "," : "", b->name,
                        b->fixed ? "\"fixed\":true," : "");
        if (dim == 2) /* counter-clockwise */
            len += snprintf(js + len, cap - (size_t)len,
                            "\"polygon\":[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]]}", x0, y0,
                            x1, y0, x1, y1, x0, y1);
        else
            len += snprintf(js + len, cap - (size_t)len,
                            "\"box\":{\"min\":[%.17g,%.17g,%.17g],\"max\":[%.17g,%.17g,%.17g]}}", x0, y0,
                            b->lo[2] + sh[2], x1, y1, b->hi[2] + sh[2]);
    }
    len += snprintf(js + len, cap - (size_t)len, "]");
    if (sc->nfile + nextra > 0) {
        len += snprintf(js + len, cap - (size_t)len, ",\"fixels\":[");
        len += put_fixels(js + len, cap - (size_t)len, dim, sc->file, sc->nfile, sh, true);
        len += put_fixels(js + len, cap - (size_t)len, dim, extra, nextra, sh, sc->nfile == 0);
        len += snprintf(js + len, cap - (size_t)len, "]");
    }
    char path[256];
    if (sc->turn)
        snprintf(path, sizeof path, "[{\"rotate\":%.17g,\"about\":[%.17g,%.17g]}]", sc->angle,
                 sc->seg[0] + sh[0], sc->seg[1] + sh[1]);
    else if (dim == 2)
        snprintf(path, sizeof path, "[[%.17g,%.17g]]", sc->seg[0], sc->seg[1]);
    else
        snprintf(path, sizeof path, "[[%.17g,%.17g,%.17g]]", sc->seg[0], sc->seg[1], sc->seg[2]);
    if (mode == WITH_CANDIDATE)
        snprintf(js + len, cap - (size_t)len, ",\"candidates\":{\"%s\":{\"c\":%s}}}", sc->mover, path);
    else
        snprintf(js + len, cap - (size_t)len, ",\"plan\":[{\"move\":\"%s\",\"path\":%s}]}", sc->mover, path);
    return load_ok(js);
}

static int box_of(const Scene *sc, const char *name) {
    for (int k = 0; k < sc->n; k++)
        if (!strcmp(sc->b[k].name, name)) return k;
    return -1;
}

/* ---- a planner built as cn_plan builds it (no search) ---- */

typedef struct {
    Planner P;
    cnPlanOptions o;
    cnDiag d;
} Rig;

static bool rig_init(Rig *R, const cnAssembly *a) {
    memset(R, 0, sizeof *R);
    R->o = cn_plan_options_default();
    return cn_pl_init(&R->P, a, &R->o, &R->d) == 0;
}

static void rig_free(Rig *R) { cn_pl_free(&R->P); }

/* What cn_pl_suggest_fixels made of one step. */
typedef struct {
    cnStepStatus status; /* the step, as the planner simulated it */
    int n;               /* suggestions */
    int nfix;            /* fixels of the first */
    Fx fix[2];
    int trials;          /* simulations the planner counted while suggesting, less the onset's */
    bool step_ok;        /* the suggestion names the step: its part, path and status */
} Sug;

/* The step of the assembly (its mover's one candidate path, from the whole assembly) simulated as
 * the planner does, then its fixels suggested. */
static bool suggest_in(const cnAssembly *a, const char *mover, Sug *out) {
    memset(out, 0, sizeof *out);
    Rig R;
    bool ok = rig_init(&R, a);
    Planner *P = &R.P;
    int part = cn_assembly_find_part(a, mover), bit = -1;
    for (int b = 0; b < P->nfree; b++)
        if (P->part_of[b] == part) bit = b;
    Mask full = (1ULL << P->nfree) - 1, move = 1ULL << (bit >= 0 ? bit : 0);
    cnCand *c = NULL;
    int nc = 0;
    Trans t;
    ok = ok && bit >= 0 && cn_pl_candidates(P, full, -1, move, &c, &nc) == CN_OK && nc == 1;
    ok = ok && cn_pl_transition(P, full, -1, move, -1, &c[0], false, &t) == CN_OK;
    if (ok) {
        out->status = t.status;
        int before = P->nsims;
        Out O = {P, NULL, NULL, false};
        FixList fl = {NULL, 0, 0};
        ok = cn_pl_suggest_fixels(&O, full, &t, &fl) == CN_OK && !O.nomem;
        /* a failing step is simulated once more for its onset's motion, then the trials */
        out->trials = P->nsims - before - (t.status == CN_STEP_UNSTABLE);
        out->n = fl.n;
        if (ok && fl.n > 0) {
            const cnFixelSuggestion *s = &fl.items[0];
            out->nfix = s->nfixels;
            out->step_ok = s->step.move.n == 1 && s->step.move.idx[0] == part && s->step.status == t.status &&
                           s->step.path && !strcmp(s->step.path, "c") && s->step.nseg == 1;
            for (int f = 0; f < s->nfixels && f < 2; f++) {
                snprintf(out->fix[f].part, sizeof out->fix[f].part, "%s", a->parts[s->fixels[f].part].name);
                memcpy(out->fix[f].point, s->fixels[f].point, sizeof out->fix[f].point);
                memcpy(out->fix[f].normal, s->fixels[f].normal, sizeof out->fix[f].normal);
            }
        }
        cn_arena_free(O.mem);
    }
    cn_free(c);
    rig_free(&R);
    CHECK_MSG(ok, "the planner could not suggest fixels for moving %s: %s", mover, R.d.message);
    return ok;
}

static bool suggest(const Scene *sc, const int *order, const double sh[3], Sug *out) {
    memset(out, 0, sizeof *out);
    cnAssembly *a = scene_load(sc, order, sh, NULL, 0, WITH_CANDIDATE);
    if (!a) return false;
    bool ok = suggest_in(a, sc->mover, out);
    cn_assembly_free(a);
    return ok;
}

/* ---- the oracle: the step simulated again by the public cn_simulate ---- */

typedef struct {
    cnStepStatus status;
    bool moving[4]; /* per box: starts to move at the onset */
    double lin[4][3], ang[4][3];
} Onset;

/* The scene's step with the extra fixels in the file, simulated; the onset's motion per box. */
static bool replay(const Scene *sc, const double sh[3], const Fx *fx, int nfx, Onset *on) {
    memset(on, 0, sizeof *on);
    cnAssembly *a = scene_load(sc, NULL, sh, fx, nfx, WITH_PLAN);
    if (!a) return false;
    cnSimOptions o = cn_sim_options_default();
    cnSimResult r;
    memset(&r, 0, sizeof r);
    cnDiag d;
    bool ok = cn_simulate(a, &o, &r, &d) == CN_OK && r.nsteps == 1;
    CHECK_MSG(ok, "cn_simulate: %s", d.message);
    if (ok) {
        const cnStepResult *st = &r.steps[0];
        on->status = st->status;
        for (int i = 0; st->status == CN_STEP_UNSTABLE && st->onset.part && i < st->onset.nmoving; i++) {
            int p = st->onset.moving[i], k = box_of(sc, a->parts[p].name);
            if (k < 0) continue;
            on->moving[k] = true;
            memcpy(on->lin[k], st->onset.part[p].lin, sizeof on->lin[k]);
            memcpy(on->ang[k], st->onset.part[p].ang, sizeof on->ang[k]);
        }
    }
    cn_sim_result_free(&r);
    cn_assembly_free(a);
    return ok;
}

static cnStepStatus replay_status(const Scene *sc, const double sh[3], const Fx *fx, int nfx) {
    Onset on;
    return replay(sc, sh, fx, nfx, &on) ? on.status : (cnStepStatus)-1;
}

/* The velocity at point p (unshifted) of box k at the onset: lin + ang x (p - its centre). */
static void onset_velocity(const Scene *sc, const Onset *on, int k, const double p[3], double v[3]) {
    double r[3];
    for (int i = 0; i < 3; i++) r[i] = p[i] - (i < sc->dim ? 0.5 * (sc->b[k].lo[i] + sc->b[k].hi[i]) : 0);
    const double *w = on->ang[k];
    v[0] = on->lin[k][0] + w[1] * r[2] - w[2] * r[1];
    v[1] = on->lin[k][1] + w[2] * r[0] - w[0] * r[2];
    v[2] = on->lin[k][2] + w[0] * r[1] - w[1] * r[0];
}

static bool near(double a, double b) { return fabs(a - b) <= 1e-9 * (1 + fabs(b)); }

/* Is fixel f (shifted by sh) at a corner of a box that starts to move at the onset, pushing along
 * minus the outward normal of a face through that corner that the onset's motion opens (the
 * corner's velocity has a positive component along the outward normal)? */
static bool on_opened_face(const Scene *sc, const double sh[3], const Onset *on, const Fx *f) {
    int k = box_of(sc, f->part);
    if (k < 0 || !on->moving[k]) return false;
    const Box *b = &sc->b[k];
    double p[3] = {0, 0, 0};
    for (int i = 0; i < sc->dim; i++) {
        p[i] = f->point[i] - sh[i];
        if (!near(p[i], b->lo[i]) && !near(p[i], b->hi[i])) return false; /* not a corner */
    }
    int j = -1;
    for (int i = 0; i < 3; i++) {
        if (fabs(fabs(f->normal[i]) - 1) < 1e-12) j = i;
        else if (fabs(f->normal[i]) > 1e-12) return false; /* not a face's normal */
    }
    if (j < 0 || j >= sc->dim) return false;
    double out = f->normal[j] < 0 ? 1 : -1; /* the face's outward normal is out * e_j */
    if (!near(p[j], out > 0 ? b->hi[j] : b->lo[j])) return false; /* the face is not through the corner */
    double v[3];
    onset_velocity(sc, on, k, p, v);
    return v[j] * out > 0;
}

/* The (corner, face) pairs of the moving boxes whose face the onset's motion opens; speeds below
 * 1e-12 of the largest are rounding (the face does not move); *unclear is set when another is
 * within 1e-6 of the largest (its sign then rests on rounding). */
static int count_opened(const Scene *sc, const Onset *on, bool *unclear) {
    /* each moving body's corners: the speed at which each face through the corner opens (s > 0) */
    double sp[4 * 8 * 3]; /* bodies (Scene.b) x corners x axes */
    int m = 0;
    for (int k = 0; k < sc->n; k++) {
        if (!on->moving[k]) continue;
        for (int c = 0; c < 1 << sc->dim; c++) {
            double p[3] = {0, 0, 0}, v[3];
            for (int i = 0; i < sc->dim; i++) p[i] = c >> i & 1 ? sc->b[k].hi[i] : sc->b[k].lo[i];
            onset_velocity(sc, on, k, p, v);
            for (int j = 0; j < sc->dim; j++) sp[m++] = (c >> j & 1 ? 1 : -1) * v[j];
        }
    }
    double vmax = 0, vmin = INFINITY;
    for (int i = 0; i < m; i++) vmax = fmax(vmax, fabs(sp[i]));
    int n = 0;
    for (int i = 0; i < m; i++) {
        if (!(fabs(sp[i]) > 1e-12 * vmax)) continue; /* rounding: the face does not move */
        n += sp[i] > 0;
        vmin = fmin(vmin, fabs(sp[i]));
    }
    *unclear = vmin < 1e-6 * vmax;
    return n;
}

/* Every check of one suggestion: the step fails without fixels; the suggestion names it; its
 * fixels are at corners of the moving parts on faces the failing motion opens; the file with them
 * loads and the step is then stable. */
static void check_suggestion(const char *what, const Scene *sc, const double sh[3], const Sug *s) {
    Onset on;
    if (!replay(sc, sh, NULL, 0, &on)) return;
    CHECK_MSG(on.status == CN_STEP_UNSTABLE && s->status == CN_STEP_UNSTABLE,
              "%s: the step is %d (planner %d)", what, on.status, s->status);
    CHECK_MSG(s->n == 1 && s->step_ok, "%s: %d suggestions, the step named %s", what, s->n,
              s->step_ok ? "right" : "wrong");
    for (int f = 0; f < s->nfix; f++)
        CHECK_MSG(on_opened_face(sc, sh, &on, &s->fix[f]),
                  "%s: fixel %d on %s at (%g, %g, %g) pushing (%g, %g, %g) is not on a face the motion opens",
                  what, f, s->fix[f].part, s->fix[f].point[0], s->fix[f].point[1], s->fix[f].point[2],
                  s->fix[f].normal[0], s->fix[f].normal[1], s->fix[f].normal[2]);
    Fx back[2]; /* where they are in the scene before it was moved */
    for (int f = 0; f < s->nfix && f < 2; f++) {
        back[f] = s->fix[f];
        for (int i = 0; i < 3; i++) back[f].point[i] -= sh[i];
    }
    CHECK_MSG(replay_status(sc, sh, back, s->nfix) == CN_STEP_STABLE,
              "%s: the step with the fixels is not stable", what);
}

/* Is fixel f (shifted by sh) the fixel on `part` at `pt` pushing along `nm`? */
static bool is_fixel(const Fx *f, const char *part, const double pt[3], const double nm[3],
                     const double sh[3]) {
    bool ok = !strcmp(f->part, part);
    for (int i = 0; i < 3; i++) ok = ok && near(f->point[i], pt[i] + sh[i]) && near(f->normal[i], nm[i]);
    return ok;
}

static const double ZERO[3] = {0, 0, 0};

/* ---- a block over a table's edge, its counterweight lifted off ---- */

/* 2-D, the table [-10, 0] x [-1, 0] (its corner, the edge, at the origin); A = [-1, 1.5] x
 * [0, 0.5] reaches 1.5 past it, its centre (0.25, 0.25) beyond the edge, held back by B = [-1, 0]
 * x [0.5, 1.5] on its back end (moments about the edge, per unit density: A 1.25 x 0.25 = 0.3125
 * forward, B 1 x 0.5 = 0.5 back). B lifted straight up: A tips forward about the edge at once.
 * Frictionless, nothing pushes A sideways, so its centre starts straight down: with angular
 * acceleration -w (clockwise) and the edge point staying on the table, a(p) = w (p_y - 0.25, -p_x).
 * Corners and the faces they open (outward normal . a > 0): (1.5, 0) bottom 1.5 w; (-1, 0.5) top
 * w; (1.5, 0.5) right 0.25 w; (-1, 0) left 0.25 w; the others close. The best, a fixel pushing up
 * at (1.5, 0), holds A: the edge and the fixel carry it from either side of its centre. One trial.
 * The second best, pushing down at (-1, 0.5), holds too (0.25 W at lever 1 against W at 0.25), and
 * the horizontal pushes do not (nothing takes a horizontal force in a frictionless scene). */
static const Scene OVER_EDGE = {.dim = 2,
                                .n = 3,
                                .b = {{"T", true, {-10, -1, 0}, {0, 0, 0}},
                                      {"A", false, {-1, 0, 0}, {1.5, 0.5, 0}},
                                      {"B", false, {-1, 0.5, 0}, {0, 1.5, 0}}},
                                .mover = "B",
                                .seg = {0, 3, 0}};

static void test_over_edge(void) {
    Sug s;
    if (!suggest(&OVER_EDGE, NULL, ZERO, &s)) return;
    check_suggestion("over the edge", &OVER_EDGE, ZERO, &s);
    CHECK_MSG(s.nfix == 1 && is_fixel(&s.fix[0], "A", (double[3]){1.5, 0, 0}, (double[3]){0, 1, 0}, ZERO),
              "over the edge: %d fixels, the first on %s at (%g, %g)", s.nfix, s.fix[0].part,
              s.fix[0].point[0], s.fix[0].point[1]);
    CHECK_MSG(s.trials == 1, "over the edge: %d trials", s.trials);
    /* the other candidates, by the public simulation: the back push holds, the side pushes not */
    Fx back = {"A", {-1, 0.5, 0}, {0, -1, 0}}, right = {"A", {1.5, 0.5, 0}, {-1, 0, 0}},
       left = {"A", {-1, 0, 0}, {1, 0, 0}};
    CHECK(replay_status(&OVER_EDGE, ZERO, &back, 1) == CN_STEP_STABLE);
    CHECK(replay_status(&OVER_EDGE, ZERO, &right, 1) == CN_STEP_UNSTABLE);
    CHECK(replay_status(&OVER_EDGE, ZERO, &left, 1) == CN_STEP_UNSTABLE);
    /* the onset the public simulation reports is the one derived: centre straight down, a_y = 0.25 w */
    Onset on;
    if (replay(&OVER_EDGE, ZERO, NULL, 0, &on)) {
        bool unclear;
        CHECK(on.moving[1] && !on.moving[2] && on.ang[1][2] < 0);
        CHECK_NEAR(on.lin[1][0], 0, 1e-9);
        CHECK_NEAR(on.lin[1][1], 0.25 * on.ang[1][2], 1e-9);
        CHECK(count_opened(&OVER_EDGE, &on, &unclear) == 4 && !unclear);
    }
}

/* The same, tall: A = [-1, 1.5] x [0, 4] (centre (0.25, 2)), B = [-1, 0] x [4, 10] (moments 2.5
 * forward, 3 back). a(p) = w (p_y - 2, -p_x): (-1, 0) opens the left face 2 w, (1.5, 4) the right
 * face 2 w, (1.5, 0) the bottom 1.5 w, (-1, 4) the top w. The two horizontal pushes come first and
 * fail alone; the third, up at (1.5, 0), holds: three trials. (The pair of horizontal pushes would
 * hold A by their couple, and the push down at (-1, 4) would hold it too, but neither comes
 * first.) */
static const Scene TALL = {.dim = 2,
                           .n = 3,
                           .b = {{"T", true, {-10, -1, 0}, {0, 0, 0}},
                                 {"A", false, {-1, 0, 0}, {1.5, 4, 0}},
                                 {"B", false, {-1, 4, 0}, {0, 10, 0}}},
                           .mover = "B",
                           .seg = {0, 3, 0}};

static void test_tall(void) {
    Sug s;
    if (!suggest(&TALL, NULL, ZERO, &s)) return;
    check_suggestion("tall", &TALL, ZERO, &s);
    CHECK_MSG(s.nfix == 1 && is_fixel(&s.fix[0], "A", (double[3]){1.5, 0, 0}, (double[3]){0, 1, 0}, ZERO),
              "tall: %d fixels, the first on %s at (%g, %g) pushing (%g, %g)", s.nfix, s.fix[0].part,
              s.fix[0].point[0], s.fix[0].point[1], s.fix[0].normal[0], s.fix[0].normal[1]);
    CHECK_MSG(s.trials == 3, "tall: %d trials", s.trials);
    Fx side[2] = {{"A", {-1, 0, 0}, {1, 0, 0}}, {"A", {1.5, 4, 0}, {-1, 0, 0}}},
       top = {"A", {-1, 4, 0}, {0, -1, 0}};
    CHECK(replay_status(&TALL, ZERO, &side[0], 1) == CN_STEP_UNSTABLE);
    CHECK(replay_status(&TALL, ZERO, &side[1], 1) == CN_STEP_UNSTABLE);
    CHECK(replay_status(&TALL, ZERO, side, 2) == CN_STEP_STABLE);
    CHECK(replay_status(&TALL, ZERO, &top, 1) == CN_STEP_STABLE);
}

/* The tall block with friction 0.5: the table's edge holds A's foot, and A turns about it, a(p) =
 * w (p_y, -p_x) (the friction this needs at the edge is 0.085 of the normal force). Now the right
 * face at (1.5, 4) opens fastest (4 w; the bottom at (1.5, 0) 1.5 w, the top at (-1, 4) w), and a
 * push to the left there holds A: W / 16 at lever 4 against W at 0.25, the table's friction
 * taking W / 16 sideways. One trial. A push to the right at (-1, 4), which turns A forward, does
 * not hold it. */
static void test_tall_friction(void) {
    Scene sc = TALL;
    sc.mu = 0.5;
    Sug s;
    if (!suggest(&sc, NULL, ZERO, &s)) return;
    check_suggestion("tall with friction", &sc, ZERO, &s);
    CHECK_MSG(s.nfix == 1 && is_fixel(&s.fix[0], "A", (double[3]){1.5, 4, 0}, (double[3]){-1, 0, 0}, ZERO),
              "tall with friction: %d fixels, the first at (%g, %g) pushing (%g, %g)", s.nfix,
              s.fix[0].point[0], s.fix[0].point[1], s.fix[0].normal[0], s.fix[0].normal[1]);
    CHECK_MSG(s.trials == 1, "tall with friction: %d trials", s.trials);
    Onset on; /* the public onset: A turns clockwise about the edge, which stays put */
    if (replay(&sc, ZERO, NULL, 0, &on)) {
        double v[3];
        onset_velocity(&sc, &on, 1, ZERO, v);
        CHECK(on.moving[1] && on.ang[1][2] < 0 && hypot(v[0], v[1]) <= 1e-9 * fabs(on.ang[1][2]));
    }
    Fx wrong = {"A", {-1, 4, 0}, {1, 0, 0}};
    CHECK(replay_status(&sc, ZERO, &wrong, 1) == CN_STEP_UNSTABLE);
}

/* 3-D, the tall block 1 deep (y in [0, 1]) over the edge x = 0 of the table: A tips about the y
 * axis, a(p) = w (p_z - 2, 0, -p_x). Opened, two corners each (y = 0 and 1): the left face at z = 0
 * and the right face at z = 4 (2 w), the bottom at x = 1.5 (1.5 w), the top at x = -1 (w); the y
 * faces do not move. The four horizontal pushes fail alone; the fifth trial, up at a corner (1.5,
 * y, 0), holds A (the table's contact [-1, 0] x [0, 1] and that corner surround its centre (0.25,
 * 0.5) in plan view, whichever y). */
static const Scene TALL3 = {.dim = 3,
                            .n = 3,
                            .b = {{"T", true, {-10, -10, -1}, {0, 10, 0}},
                                  {"A", false, {-1, 0, 0}, {1.5, 1, 4}},
                                  {"B", false, {-1, 0, 4}, {0, 1, 10}}},
                            .mover = "B",
                            .seg = {0, 0, 3}};

static void test_tall_3d(void) {
    Sug s;
    if (!suggest(&TALL3, NULL, ZERO, &s)) return;
    check_suggestion("tall 3-D", &TALL3, ZERO, &s);
    bool at = s.nfix == 1 && (is_fixel(&s.fix[0], "A", (double[3]){1.5, 0, 0}, (double[3]){0, 0, 1}, ZERO) ||
                              is_fixel(&s.fix[0], "A", (double[3]){1.5, 1, 0}, (double[3]){0, 0, 1}, ZERO));
    CHECK_MSG(at, "tall 3-D: %d fixels, the first on %s at (%g, %g, %g) pushing (%g, %g, %g)", s.nfix,
              s.fix[0].part, s.fix[0].point[0], s.fix[0].point[1], s.fix[0].point[2], s.fix[0].normal[0],
              s.fix[0].normal[1], s.fix[0].normal[2]);
    CHECK_MSG(s.trials == 5, "tall 3-D: %d trials", s.trials);
    Onset on;
    if (replay(&TALL3, ZERO, NULL, 0, &on)) {
        bool unclear;
        int n = count_opened(&TALL3, &on, &unclear);
        CHECK_MSG(n == 8, "tall 3-D: %d faces opened at corners", n);
    }
}

/* ---- a plank on a post, the post pulled away ---- */

/* The plank B = [-1, 1] x [1, 1.2] (centre (0, 1.1)) on the post A = [-0.1, 0.1] x [0, 1], A pulled
 * 3 to the left. B stays until A's right side passes under its centre, then tips clockwise about
 * A's corner (0, 1), right under its centre, which does not start to move (frictionless: no
 * sideways force; over the corner: no fall): a(p) = w (p_y - 1.1, -p_x). Opened: the bottom
 * at (1, 1) and the top at (-1, 1.2) (w), the right face at (1, 1.2) and the left at (-1, 1) (0.1
 * w). No one or two of these hold B once A has gone: the only fixel that pushes up is at x = 1, to
 * the right of B's centre, and no other force can turn B back (the others push down or sideways,
 * with nothing to balance them). So no suggestion, after every candidate alone and every pair: 4 +
 * 6 trials. */
static const Scene POST = {.dim = 2,
                           .n = 3,
                           .b = {{"T", true, {-10, -1, 0}, {10, 0, 0}},
                                 {"A", false, {-0.1, 0, 0}, {0.1, 1, 0}},
                                 {"B", false, {-1, 1, 0}, {1, 1.2, 0}}},
                           .mover = "A",
                           .seg = {-3, 0, 0}};

static void test_post(void) {
    Sug s;
    if (!suggest(&POST, NULL, ZERO, &s)) return;
    CHECK(s.status == CN_STEP_UNSTABLE);
    CHECK_MSG(s.n == 0, "post: %d suggestions", s.n);
    CHECK_MSG(s.trials == 10, "post: %d trials", s.trials);
    Onset on;
    if (replay(&POST, ZERO, NULL, 0, &on)) {
        bool unclear;
        CHECK(on.status == CN_STEP_UNSTABLE && on.moving[2] && !on.moving[1] && on.ang[2][2] < 0);
        CHECK(count_opened(&POST, &on, &unclear) == 4 && !unclear);
    }
    /* by the public simulation: the push up at (1, 1) alone, and with the push down at (-1, 1.2) */
    Fx up = {"B", {1, 1, 0}, {0, 1, 0}};
    Fx both[2] = {{"B", {1, 1, 0}, {0, 1, 0}}, {"B", {-1, 1.2, 0}, {0, -1, 0}}};
    CHECK(replay_status(&POST, ZERO, &up, 1) == CN_STEP_UNSTABLE);
    CHECK(replay_status(&POST, ZERO, both, 2) == CN_STEP_UNSTABLE);
}

/* The plank as a dome: the flat bottom [-1, 1] at y = 1 and an arc of 11 faces over it, (cos t,
 * 1 + 0.5 sin t) for t = k pi / 11, on the post pulled away as above. It tips as the plank did;
 * every face of the arc faces up (its outward normal at angle (t_k + t_k+1) / 2 in (0, pi)), so
 * the only fixel that pushes up is again at the bottom's right end, and neither one fixel nor two
 * can help: no suggestion. The motion opens more than 10 (corner, face) pairs (counted from the
 * public onset): the best 10 are tried, alone and in pairs, 10 + 45 trials. */
static void test_dome(void) {
    enum { NARC = 11 };
    double vx[NARC + 1], vy[NARC + 1]; /* counter-clockwise, from (1, 1) over the top to (-1, 1) */
    for (int k = 0; k <= NARC; k++) {
        double t = k * CN_PI / NARC;
        vx[k] = k == NARC ? -1 : k == 0 ? 1 : cos(t);
        vy[k] = k == NARC || k == 0 ? 1 : 1 + 0.5 * sin(t);
    }
    char js[4096];
    int len = snprintf(js, sizeof js,
                       "{\"dimension\":2,\"gravity\":[0,-1],\"parts\":["
                       "{\"name\":\"T\",\"fixed\":true,\"polygon\":[[-10,-1],[10,-1],[10,0],[-10,0]]},"
                       "{\"name\":\"A\",\"polygon\":[[-0.1,0],[0.1,0],[0.1,1],[-0.1,1]]},"
                       "{\"name\":\"B\",\"polygon\":[");
    for (int k = 0; k <= NARC; k++)
        len += snprintf(js + len, sizeof js - (size_t)len, "%s[%.17g,%.17g]", k ? "," : "", vx[k], vy[k]);
    char *tail = js + len;
    size_t room = sizeof js - (size_t)len;
    snprintf(tail, room, "]}],\"candidates\":{\"A\":{\"c\":[[-3,0]]}}}");
    cnAssembly *a = load_ok(js);
    Sug s;
    if (a && suggest_in(a, "A", &s)) {
        CHECK(s.status == CN_STEP_UNSTABLE);
        CHECK_MSG(s.n == 0, "dome: %d suggestions", s.n);
        CHECK_MSG(s.trials == 10 + 45, "dome: %d trials", s.trials);
    }
    cn_assembly_free(a);
    /* the public onset, and the pairs it opens: the dome's centre by the shoelace formula */
    snprintf(tail, room, "]}],\"plan\":[{\"move\":\"A\",\"path\":[[-3,0]]}]}");
    a = load_ok(js);
    if (!a) return;
    double area = 0, cx = 0, cy = 0;
    for (int k = 0; k <= NARC; k++) {
        int l = (k + 1) % (NARC + 1);
        double cr = vx[k] * vy[l] - vx[l] * vy[k];
        area += cr / 2, cx += (vx[k] + vx[l]) * cr / 6, cy += (vy[k] + vy[l]) * cr / 6;
    }
    cx /= area, cy /= area;
    cnSimOptions o = cn_sim_options_default();
    cnSimResult r;
    memset(&r, 0, sizeof r);
    cnDiag d;
    int b = cn_assembly_find_part(a, "B");
    if (cn_simulate(a, &o, &r, &d) == CN_OK && r.nsteps == 1 && r.steps[0].status == CN_STEP_UNSTABLE &&
        r.steps[0].onset.part && r.steps[0].onset.nmoving == 1 && r.steps[0].onset.moving[0] == b) {
        const cnPartMotion *m = &r.steps[0].onset.part[b];
        int opened = 0;
        double smax = 0, smin = INFINITY;
        for (int k = 0; k <= NARC; k++) {
            double ux = m->lin[0] - m->ang[2] * (vy[k] - cy), uy = m->lin[1] + m->ang[2] * (vx[k] - cx);
            for (int e = 0; e < 2; e++) { /* the faces into and out of corner k */
                int p = e ? k : (k + NARC) % (NARC + 1), q = e ? (k + 1) % (NARC + 1) : k;
                double ex = vx[q] - vx[p], ey = vy[q] - vy[p], L = hypot(ex, ey);
                double sc = (ux * ey - uy * ex) / L;
                opened += sc > 0;
                smax = fmax(smax, fabs(sc)), smin = fmin(smin, fabs(sc));
            }
        }
        CHECK_MSG(opened > 10 && smin > 1e-6 * smax, "dome: %d pairs opened (smallest speed %g of %g)",
                  opened, smin, smax);
    } else
        CHECK_MSG(false, "dome: the step does not fail as derived");
    cn_sim_result_free(&r);
    cn_assembly_free(a);
}

/* ---- a block on a seesaw plank, the plank turned away: free fall ---- */

/* The plank A = [0, 4] x [1, 1.2] on the fixed block F = [1.5, 2.5] x [0, 1]; the block B = [0.4,
 * 1.4] x [1.2, 1.4] on A (their centre x = (0.8 x 2 + 0.2 x 0.9) / 1 = 1.78, over F). A is turned
 * 10 degrees counter-clockwise about (1.45, 1): its top under B (x < 1.45) drops, its bottom on F
 * (x > 1.45) rises; both contacts open at once, and B falls freely: every point of B moves straight
 * down. Opened: the bottom face at both bottom corners (the same speed); the side faces do not
 * move along their normals. One push up at a corner cannot hold B (its weight acts 0.5 from it),
 * the two together can: two trials alone, then the pair. */
static const Scene SEESAW = {.dim = 2,
                             .n = 3,
                             .b = {{"F", true, {1.5, 0, 0}, {2.5, 1, 0}},
                                   {"A", false, {0, 1, 0}, {4, 1.2, 0}},
                                   {"B", false, {0.4, 1.2, 0}, {1.4, 1.4, 0}}},
                             .mover = "A",
                             .turn = true,
                             .seg = {1.45, 1, 0},
                             .angle = 10};

/* Does s suggest exactly the two pushes up at B's bottom corners (either order), shifted by sh? */
static bool seesaw_pair(const Sug *s, const double sh[3]) {
    static const double up[3] = {0, 1, 0};
    double l[3] = {0.4, 1.2, 0}, r[3] = {1.4, 1.2, 0};
    return s->n == 1 && s->nfix == 2 &&
           ((is_fixel(&s->fix[0], "B", l, up, sh) && is_fixel(&s->fix[1], "B", r, up, sh)) ||
            (is_fixel(&s->fix[0], "B", r, up, sh) && is_fixel(&s->fix[1], "B", l, up, sh)));
}

static void test_seesaw(void) {
    Sug s;
    if (!suggest(&SEESAW, NULL, ZERO, &s)) return;
    check_suggestion("seesaw", &SEESAW, ZERO, &s);
    CHECK_MSG(seesaw_pair(&s, ZERO), "seesaw: %d fixels", s.nfix);
    CHECK_MSG(s.trials == 3, "seesaw: %d trials", s.trials);
    Onset on;
    if (replay(&SEESAW, ZERO, NULL, 0, &on)) {
        bool unclear;
        CHECK(on.moving[2] && !on.moving[1]);
        CHECK(on.lin[2][1] < 0 && fabs(on.lin[2][0]) <= 1e-9 * fabs(on.lin[2][1]));
        CHECK(fabs(on.ang[2][2]) <= 1e-9 * fabs(on.lin[2][1]));
        CHECK(count_opened(&SEESAW, &on, &unclear) == 2);
    }
    Fx one[2] = {{"B", {0.4, 1.2, 0}, {0, 1, 0}}, {"B", {1.4, 1.2, 0}, {0, 1, 0}}};
    CHECK(replay_status(&SEESAW, ZERO, &one[0], 1) == CN_STEP_UNSTABLE);
    CHECK(replay_status(&SEESAW, ZERO, &one[1], 1) == CN_STEP_UNSTABLE);
}

/* The seesaw with a fixel of the file pushing up at B's bottom left corner (0.4, 1.2). B now tips
 * clockwise about it, its centre (0.9, 1.3) straight down: a(p) = w (p_y - 1.3, 0.4 - p_x). The best
 * face opened is the bottom at (1.4, 1.2) (w; the left face at (0.4, 1.2) and the right face at
 * (1.4, 1.4) open at 0.1 w), and a push up there holds B together with the file's fixel: one fixel,
 * one trial. The trial keeps the file's fixels (without it, one more would not do). */
static void test_file_fixel(void) {
    Scene sc = SEESAW;
    Fx held = {"B", {0.4, 1.2, 0}, {0, 1, 0}};
    sc.nfile = 1;
    sc.file[0] = held;
    Sug s;
    if (!suggest(&sc, NULL, ZERO, &s)) return;
    check_suggestion("seesaw with a fixel", &sc, ZERO, &s);
    CHECK_MSG(s.nfix == 1 && is_fixel(&s.fix[0], "B", (double[3]){1.4, 1.2, 0}, (double[3]){0, 1, 0}, ZERO),
              "seesaw with a fixel: %d fixels, the first at (%g, %g)", s.nfix, s.fix[0].point[0],
              s.fix[0].point[1]);
    CHECK_MSG(s.trials == 1, "seesaw with a fixel: %d trials", s.trials);
}

/* ---- steps that do not fail ---- */

/* Nothing is suggested, and nothing simulated, for a step that is stable (B lifted off the seesaw
 * plank: A stays on F) or geometrically infeasible (the plank B pushed down into its post). */
static void test_not_failing(void) {
    Scene lift = SEESAW, down = POST;
    lift.mover = "B", lift.turn = false, lift.seg[0] = 0, lift.seg[1] = 2;
    down.mover = "B", down.seg[0] = 0, down.seg[1] = -0.5;
    Sug s;
    if (suggest(&lift, NULL, ZERO, &s))
        CHECK_MSG(s.status == CN_STEP_STABLE && s.n == 0 && s.trials == 0,
                  "lift: step %d, %d suggestions, %d trials", s.status, s.n, s.trials);
    if (suggest(&down, NULL, ZERO, &s))
        CHECK_MSG(s.status == CN_STEP_INFEASIBLE && s.n == 0 && s.trials == 0,
                  "down: step %d, %d suggestions, %d trials", s.status, s.n, s.trials);
}

/* ---- invariance ---- */

/* The tall block listed in each of the six orders, where it stands and moved by (12.5, -3.25):
 * the same fixel, moved with it, after the same trials; the seesaw moved by (-7.25, 4.5) and listed
 * backwards: the same pair, moved with it. */
static void test_invariance(void) {
    static const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    const double shifts[2][3] = {{0, 0, 0}, {12.5, -3.25, 0}};
    for (int p = 0; p < 6; p++)
        for (int k = 0; k < 2; k++) {
            Sug s;
            if (!suggest(&TALL, perms[p], shifts[k], &s)) continue;
            CHECK_MSG(s.n == 1 && s.nfix == 1 && s.trials == 3 &&
                          is_fixel(&s.fix[0], "A", (double[3]){1.5, 0, 0}, (double[3]){0, 1, 0}, shifts[k]),
                      "tall listed %d%d%d, moved by (%g, %g): %d fixels, the first at (%g, %g), %d trials",
                      perms[p][0], perms[p][1], perms[p][2], shifts[k][0], shifts[k][1], s.nfix,
                      s.fix[0].point[0], s.fix[0].point[1], s.trials);
            if (p == 5 && k == 1) check_suggestion("tall, moved", &TALL, shifts[k], &s);
        }
    const double sh[3] = {-7.25, 4.5, 0};
    Sug s;
    if (suggest(&SEESAW, perms[5], sh, &s)) {
        CHECK_MSG(seesaw_pair(&s, sh) && s.trials == 3,
                  "seesaw moved and listed backwards: %d fixels, %d trials", s.nfix, s.trials);
        check_suggestion("seesaw, moved", &SEESAW, sh, &s);
    }
}

/* ---- the public planner ---- */

/* examples/boxed_incline.json: B is boxed on a 30-degree incline (gravity (-0.5, -0.866)) between
 * the table, the bar above it and the wall on its right, held by A on its left, which can only
 * leave upwards; then B slides left (frictionless, gravity's component along the table), the motion
 * opening only its left face x = 2. A push to the right at either of its corners (2, 0), (2, 1)
 * takes the 0.5 W along the table; the table and the bar take the rest and the moment. So there is
 * no plan, and each way of taking A out gets one fixel there; replayed (the step's path, the fixel
 * in the plan file) the step is stable, and without it it is not. Without fixel suggestions
 * (cnPlanOptions.fixels off) there are none. */
static void test_public_incline(void) {
    cnAssembly *a = load_example("boxed_incline");
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    cnDiag d;
    if (cn_plan(a, &o, &r, &d) != CN_OK) {
        CHECK_MSG(false, "cn_plan: %s", d.message);
        cn_assembly_free(a);
        return;
    }
    int A = cn_assembly_find_part(a, "A"), B = cn_assembly_find_part(a, "B");
    CHECK(!r.stable && r.nfixels >= 1 && r.nfixels <= r.ndead);
    char path[1024];
    snprintf(path, sizeof path, "%s/examples/boxed_incline.json", CAIRN_SOURCE_DIR);
    for (int i = 0; i < r.nfixels; i++) {
        const cnFixelSuggestion *fs = &r.fixels[i];
        const cnFixel *f = &fs->fixels[0];
        bool at = fs->nfixels == 1 && f->part == B && near(f->point[0], 2) &&
                  (near(f->point[1], 0) || near(f->point[1], 1)) && near(f->normal[0], 1) &&
                  near(f->normal[1], 0);
        CHECK_MSG(at, "incline, suggestion %d: %d fixels, at (%g, %g) pushing (%g, %g)", i, fs->nfixels,
                  f->point[0], f->point[1], f->normal[0], f->normal[1]);
        CHECK(fs->step.move.n == 1 && fs->step.move.idx[0] == A && fs->step.status == CN_STEP_UNSTABLE);
        /* the step replayed from a plan file, with the fixel and without */
        for (int with = 0; with < 2; with++) {
            char plan[2048];
            int len = snprintf(plan, sizeof plan, "{\"plan\":[{\"move\":\"A\",\"support\":\"%s\",\"path\":[",
                               fs->step.support == CN_SUPPORT_PUSH ? "push" : "hold");
            for (int k = 0; k < fs->step.nseg; k++) {
                const cnSegment *sg = &fs->step.seg[k];
                CHECK(sg->kind == CN_SEGMENT_MOVE);
                len += snprintf(plan + len, sizeof plan - (size_t)len, "%s[%.17g,%.17g]", k ? "," : "",
                                sg->move[0], sg->move[1]);
            }
            len += snprintf(plan + len, sizeof plan - (size_t)len, "]}]");
            if (with)
                len += snprintf(plan + len, sizeof plan - (size_t)len,
                                ",\"fixels\":[{\"part\":\"B\",\"point\":[%.17g,%.17g],"
                                "\"normal\":[%.17g,%.17g]}]",
                                f->point[0], f->point[1], f->normal[0], f->normal[1]);
            snprintf(plan + len, sizeof plan - (size_t)len, "}");
            cnAssembly *b = NULL;
            cnSimResult sr;
            memset(&sr, 0, sizeof sr);
            cnSimOptions so = cn_sim_options_default();
            bool ok = cn_assembly_load_with_plan_text(path, plan, &b, &d) == CN_OK &&
                      cn_simulate(b, &so, &sr, &d) == CN_OK && sr.nsteps == 1;
            CHECK_MSG(ok && sr.steps[0].status == (with ? CN_STEP_STABLE : CN_STEP_UNSTABLE),
                      "incline, suggestion %d replayed %s the fixel: %s", i, with ? "with" : "without",
                      ok ? "wrong verdict" : d.message);
            cn_sim_result_free(&sr);
            cn_assembly_free(b);
        }
    }
    cn_plan_result_free(&r);
    o.fixels = false;
    if (cn_plan(a, &o, &r, &d) == CN_OK) {
        CHECK(!r.stable && r.nfixels == 0 && r.ndead > 0);
        cn_plan_result_free(&r);
    } else
        CHECK_MSG(false, "cn_plan: %s", d.message);
    cn_assembly_free(a);
}

/* A block whose right end is a corner sharper than a right angle (its top slopes down to a tip at
 * (1.5, 0)) over the table's edge, the counterweight lifted off: the inward normal of its bottom
 * at the tip runs out past its top, so no fixel may push there (the loader refuses one: "it runs
 * along the surface there"). Every fixel cn_plan suggests loads in a file with the assembly, and
 * the step is stable with them. */
static void test_sharp_corner(void) {
    const char *parts = "{\"dimension\":2,\"parts\":["
                        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-10,-1],[0,-1],[0,0],[-10,0]]},"
                        "{\"name\":\"A\",\"polygon\":[[-1,0],[1.5,0],[1,0.5],[-1,0.5]]},"
                        "{\"name\":\"B\",\"polygon\":[[-1,0.5],[0,0.5],[0,1.5],[-1,1.5]]}]";
    char js[2048];
    snprintf(js, sizeof js, "%s}", parts);
    cnAssembly *a = load_ok(js);
    if (!a) return;
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    cnDiag d;
    if (cn_plan(a, &o, &r, &d) != CN_OK) {
        CHECK_MSG(false, "cn_plan: %s", d.message);
        cn_assembly_free(a);
        return;
    }
    CHECK(r.nfixels >= 1);
    for (int i = 0; i < r.nfixels; i++) {
        const cnFixelSuggestion *fs = &r.fixels[i];
        int len = snprintf(js, sizeof js, "%s,\"fixels\":[", parts);
        for (int k = 0; k < fs->nfixels; k++) {
            const cnFixel *f = &fs->fixels[k];
            len += snprintf(js + len, sizeof js - (size_t)len,
                            "%s{\"part\":\"%s\",\"point\":[%.17g,%.17g],\"normal\":[%.17g,%.17g]}", k ? "," : "",
                            a->parts[f->part].name, f->point[0], f->point[1], f->normal[0], f->normal[1]);
            CHECK_MSG(!(near(f->point[0], 1.5) && near(f->point[1], 0) && near(f->normal[1], 1)),
                      "sharp corner, suggestion %d: a push up at the tip", i);
        }
        snprintf(js + len, sizeof js - (size_t)len, "],\"plan\":[{\"move\":\"B\",\"path\":[[0,5]]}]}");
        cnAssembly *b = NULL;
        cnSimResult sr;
        memset(&sr, 0, sizeof sr);
        cnSimOptions so = cn_sim_options_default();
        bool loads = cn_assembly_load_string(js, "inline", &b, &d) == CN_OK;
        CHECK_MSG(loads, "sharp corner, suggestion %d does not load: %s", i, d.message);
        if (loads && cn_simulate(b, &so, &sr, &d) == CN_OK && sr.nsteps == 1 && fs->step.seg &&
            fs->step.seg[0].kind == CN_SEGMENT_MOVE && near(fs->step.seg[0].move[0], 0) &&
            fs->step.seg[0].move[1] > 0)
            CHECK_MSG(sr.steps[0].status == CN_STEP_STABLE, "sharp corner, suggestion %d: B lifted is %d", i,
                      sr.steps[0].status);
        cn_sim_result_free(&sr);
        cn_assembly_free(b);
    }
    cn_plan_result_free(&r);
    cn_assembly_free(a);
}

void test_plan_fixels(void) {
    test_sharp_corner();
    test_over_edge();
    test_tall();
    test_tall_friction();
    test_tall_3d();
    test_post();
    test_dome();
    test_seesaw();
    test_file_fixel();
    test_not_failing();
    test_invariance();
    test_public_incline();
}
