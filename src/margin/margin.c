/* How far from falling: each margin is a bracket between a stable verdict and a not-stable one
 * of cn_check, on the assembly with one thing changed, narrowed by bisection.
 *
 * - Friction: the default coefficient (every pair's scaled with it), or one pair's, set to t.
 * - Tilt: gravity turned by t about a horizontal axis (the tilting-table test).
 * - Lateral: a horizontal acceleration t g added to gravity (the equivalent static load of
 *   limit analysis, in g).
 * Without a given axis or direction, the weakest one: both senses in 2-D; in 3-D the azimuths
 * about gravity, CN_MARGIN_AZIMUTHS first, then a pattern search about the weakest. Each
 * direction after the first costs an LP and one verdict unless it is weaker (a direction whose
 * static limit is below the incumbent is bracketed about it; else the incumbent's value is tried
 * first). The tilt, lateral and friction brackets start at the static limit, the equilibrium LP's
 * (check_limit.h): a stable verdict needs a static field. */
#include <math.h>
#include <string.h>

#include "cairn/margin.h"
#include "core.h"
#include "margin_hook.h"
#include "check_limit.h"
#include "warm_start.h"

/* Bisections stop after this many halvings whatever the tolerance (2^-64 of the range). */
#define CN_MARGIN_MAX_HALVINGS 64
/* Turns of gravity searched: up to a quarter turn. */
#define CN_MARGIN_MAX_TILT (CN_PI / 2)
/* The azimuth scan's relative tolerance (the weakest direction's bracket is then narrowed to the
 * asked one), and the most moves its pattern search makes. */
#define CN_MARGIN_SCAN_TOL 1e-3
/* The fine search about the weakest azimuth goes down to this step (radians). */
#define CN_MARGIN_AZIMUTH_FINE 3e-5
#define CN_MARGIN_MAX_MOVES 16
/* How much farther than the bracket's end the mechanism is taken (relative). */
#define CN_MARGIN_PAST 1e-3
/* Components of a reported axis or direction below this are rounding (unit vectors). */
#define CN_MARGIN_DIR_ZERO 1e-12
/* A weaker direction's margin is sought first this fraction below the incumbent's, then 4, 16,
 * ... times farther. */
#define CN_MARGIN_GALLOP 1e-3
/* A verdict that is not stable on the stable side of the static limit is sought farther from it:
 * this fraction of it, then 4, 16, ... times farther (the LP accepts a field whose residual is
 * within 1e-7 of the weights, so its limit can be off by a few times that). */
#define CN_MARGIN_SEED_STEP 1e-6
/* Verdicts spent just above a static limit that a stable verdict passed, before the search
 * upward (4 times farther each time) takes over. */
#define CN_MARGIN_UP_STEPS 1
/* Verdicts spent farther out for a proved far side when the bracket's is undecided */
#define CN_MARGIN_PROOF_STEPS 6
/* From a margin of zero, each of those verdicts this many times farther out (from 0.1
 * CN_MARGIN_ZERO: up to 0.17 of the unit) */
#define CN_MARGIN_ZERO_GROWTH 16.0
/* An incumbent's margin this close to its static limit (relative) is the static limit's: the LP
 * accepts a field whose residual is within 1e-7 of the weights, which moves its limit by a few
 * times that. */
#define CN_MARGIN_STATIC_BAND 1e-5
/* A given axis or direction is refused when its part perpendicular to gravity is shorter than
 * this fraction of it (it is then nearly parallel to gravity). */
#define CN_MARGIN_PERP_MIN 1e-6

typedef struct {
    const cnAssembly *a;
    cnAssembly v;            /* the assembly changed: a shallow copy sharing a's parts */
    cnFrictionPair *pairs;   /* v's pairs when friction changes (own copy, one spare) */
    cnCheckOptions check;
    cnWarmStart warm;
    double g[3];             /* gravity as loaded */
    double tol;
    int pair_index;          /* friction of one pair: its index in pairs (may be the spare) */
    bool one_pair;
    double max_seconds;      /* 0: no limit */
    struct timespec t0;
    cnMarginVerdictFn verdict; /* every verdict */
    cnMarginPoseFn pose;     /* the static limits' check options (NULL: c->check, when the
                                verdicts are cn_check's; else none) */
    void *verdict_ctx;
} Ctx;

static cnStatus plain_check(void *ctx, const cnAssembly *v, const cnCheckOptions *o, cnCheckResult *r,
                            cnDiag *diag) {
    (void)ctx;
    return cn_check(v, o, r, diag);
}

/* The check options of the static limits: the margin's own when its verdicts are cn_check's, a
 * path sample's as its hook poses them, or NULL (a verdict of its own with no hook: no limit). */
static const cnCheckOptions *limit_options(Ctx *c) {
    if (c->verdict == plain_check) return &c->check;
    return c->pose ? c->pose(c->verdict_ctx, &c->check) : NULL;
}

static bool out_of_time(const Ctx *c) { return c->max_seconds > 0 && cn_seconds_since(&c->t0) > c->max_seconds; }

cnMarginOptions cn_margin_options_default(void) {
    cnMarginOptions o;
    memset(&o, 0, sizeof o);
    o.kinds = CN_MARGIN_ALL;
    o.pair[0] = o.pair[1] = -1;
    o.rel_tol = CN_MARGIN_DEFAULT_REL_TOL;
    o.check = cn_check_options_default();
    o.check.motion_tol = 0; /* the margin's own (CN_MARGIN_MOTION_TOL); check's as loaded */
    return o;
}

void cn_margin_result_free(cnMarginResult *r) {
    if (!r) return;
    cn_check_result_free(&r->friction.collapse);
    cn_check_result_free(&r->tilt.collapse);
    cn_check_result_free(&r->lateral.collapse);
    memset(&r->friction.collapse, 0, sizeof r->friction.collapse);
    memset(&r->tilt.collapse, 0, sizeof r->tilt.collapse);
    memset(&r->lateral.collapse, 0, sizeof r->lateral.collapse);
}

/* v rotated about the unit axis u by t (Rodrigues). */
static void turn(const double v[3], const double u[3], double t, double out[3]) {
    double c = cos(t), s = sin(t), uxv[3];
    cn_cross3(u, v, uxv);
    double ud = cn_dot3(u, v) * (1 - c);
    for (int k = 0; k < 3; k++) out[k] = v[k] * c + uxv[k] * s + u[k] * ud;
}

/* The gravity of kind at parameter t along dir (friction: as loaded). */
static void gravity_at(const Ctx *c, int kind, const double dir[3], double t, double out[3]) {
    cn_copy3(out, c->g);
    if (kind == CN_MARGIN_TILT) turn(c->g, dir, t, out);
    else if (kind == CN_MARGIN_LATERAL)
        for (int k = 0; k < 3; k++) out[k] = c->g[k] + t * cn_norm3(c->g) * dir[k];
    if (c->a->dim == 2) out[2] = 0;
}

/* The coefficient that varies when all do: the default, or (default 0) the largest pair's. */
static double friction_ref(const cnAssembly *a) {
    double ref = a->friction;
    for (int i = 0; i < a->npairs && !(a->friction > 0); i++) ref = fmax(ref, a->pairs[i].mu);
    return ref;
}

/* Friction at parameter t: the pair's coefficient, or the reference coefficient (friction_ref)
 * set to t with every other scaled in proportion (all 0: the default set to t). */
static void friction_at(Ctx *c, double t) {
    const cnAssembly *a = c->a;
    if (c->one_pair) {
        c->pairs[c->pair_index].mu = t;
        return;
    }
    double ref = friction_ref(a);
    c->v.friction = ref > 0 ? a->friction * (t / ref) : t;
    for (int i = 0; i < a->npairs; i++) c->pairs[i].mu = ref > 0 ? a->pairs[i].mu * (t / ref) : a->pairs[i].mu;
}

/* One verdict at parameter t. *stable receives it; when not stable the result is kept in m (the
 * last one kept is the nearest to the bracket's end). */
static cnStatus probe(Ctx *c, int kind, const double dir[3], double t, cnMargin *m, bool *stable,
                      cnDiag *diag) {
    gravity_at(c, kind, dir, t, c->v.gravity);
    if (kind == CN_MARGIN_FRICTION) friction_at(c, t);
    cnCheckResult r;
    cnStatus st = c->verdict(c->verdict_ctx, &c->v, &c->check, &r, diag);
    m->verdicts++;
    if (st == CN_ERR_NUMERIC) { /* no verdict there: not proved stable, and said so */
        cn_check_result_free(&r);
        cn_check_result_free(&m->collapse);
        memset(&m->collapse, 0, sizeof m->collapse);
        *stable = false;
        m->past = t, m->past_verdict = CN_VERDICT_UNDECIDED, m->past_failed = true;
        cn_copy3(m->gravity, c->v.gravity);
        return CN_OK;
    }
    if (st != CN_OK) {
        cn_check_result_free(&r);
        return st;
    }
    *stable = r.verdict == CN_VERDICT_STABLE;
    if (*stable) {
        cn_check_result_free(&r);
        return CN_OK;
    }
    cn_check_result_free(&m->collapse);
    m->collapse = r;
    m->past = t;
    m->past_verdict = r.verdict;
    m->past_failed = false;
    cn_copy3(m->gravity, c->v.gravity);
    return CN_OK;
}

/* The end of a tilt's or lateral factor's range (friction: none). */
static double range_top(int kind) {
    return kind == CN_MARGIN_TILT ? CN_MARGIN_MAX_TILT : kind == CN_MARGIN_LATERAL ? CN_MARGIN_MAX_LATERAL : INFINITY;
}

/* probe, except that an undecided verdict nearer the bracket does not replace a proved one (not
 * guaranteed or unstable) as its far side: close to the collapse the motion shrinks to the size
 * of the verdicts' rounding, where no motion is proved (cn_motion_verify), and the bracket's far
 * side stays where one was. */
static cnStatus probe_keeping_proof(Ctx *c, int kind, const double dir[3], double t, cnMargin *m,
                                    bool *stable, cnDiag *diag) {
    bool proved = !m->past_failed && (m->past_verdict == CN_VERDICT_NOT_GUARANTEED ||
                                      m->past_verdict == CN_VERDICT_UNSTABLE);
    if (!proved) return probe(c, kind, dir, t, m, stable, diag);
    cnCheckResult held = m->collapse;
    double past = m->past, g[3];
    cnVerdict verdict = m->past_verdict;
    cn_copy3(g, m->gravity);
    memset(&m->collapse, 0, sizeof m->collapse);
    cnStatus st = probe(c, kind, dir, t, m, stable, diag);
    bool replaced = st == CN_OK && !*stable && !m->past_failed &&
                    (m->past_verdict == CN_VERDICT_NOT_GUARANTEED || m->past_verdict == CN_VERDICT_UNSTABLE);
    if (replaced) {
        cn_check_result_free(&held);
        return st;
    }
    cn_check_result_free(&m->collapse);
    m->collapse = held;
    m->past = past, m->past_verdict = verdict, m->past_failed = false;
    cn_copy3(m->gravity, g);
    return st;
}

/* Narrow [s, f] (s stable, f not: either order) until it is within tolerance of its ends. */
static cnStatus bisect(Ctx *c, int kind, const double dir[3], double s, double f, cnMargin *m,
                       cnDiag *diag) {
    m->end = CN_MARGIN_FOUND;
    /* stable only at zero so far: one verdict at the absolute tolerance first, which settles a
       margin of zero (halving down to it would take a verdict a halving) */
    double z = 0.1 * CN_MARGIN_ZERO;
    if (s == 0 && f > z && !out_of_time(c)) {
        bool ok;
        cnStatus st = probe(c, kind, dir, z, m, &ok, diag);
        if (st != CN_OK) return st;
        if (ok) s = z;
        else f = z;
    }
    /* an undecided far side: a proved one farther out, CN_MARGIN_SEED_STEP of it and 4 times
       farther each time, kept while the bracket narrows (probe_keeping_proof); a margin of zero
       whose far side grows from zero, CN_MARGIN_ZERO_GROWTH times farther each time (a tiny
       load's motion is as small as the verdicts' rounding, and undecided) */
    bool from_zero = s == 0 && f > s && f < CN_MARGIN_ZERO;
    for (int k = 0, up = f > s ? 1 : -1; k < CN_MARGIN_PROOF_STEPS && f != s && !out_of_time(c) &&
                                         (m->past_failed || m->past_verdict == CN_VERDICT_UNDECIDED);
         k++) {
        double t = from_zero ? f * pow(CN_MARGIN_ZERO_GROWTH, k + 1)
                             : f + up * CN_MARGIN_SEED_STEP * fmax(fabs(f), CN_MARGIN_ZERO) * (double)(1 << 2 * k);
        if (!(t >= 0 && t <= range_top(kind))) break;
        double past = m->past;
        bool ok;
        cnStatus st = probe(c, kind, dir, t, m, &ok, diag);
        if (st != CN_OK) return st;
        if (ok) break; /* stable beyond it: the verdict changes more than once; as it stands */
        if (m->past_failed || m->past_verdict == CN_VERDICT_UNDECIDED) m->past = past;
    }
    for (int it = 0; it < CN_MARGIN_MAX_HALVINGS; it++) {
        if (fabs(s - f) <= fmax(c->tol * fmax(fabs(s), fabs(f)), 0.1 * CN_MARGIN_ZERO)) break;
        if (out_of_time(c)) {
            m->stopped = true;
            break;
        }
        double mid = 0.5 * (s + f);
        bool ok;
        cnStatus st = probe_keeping_proof(c, kind, dir, mid, m, &ok, diag);
        if (st != CN_OK) return st;
        if (ok) s = mid;
        else f = mid;
    }
    m->value = s;
    return CN_OK;
}

/* The static limit along dir in kind's parameter, or -1: the largest lateral factor at which the
 * equilibrium LP has a field (cn_check_load_limit); a tilt by theta about an axis u is gravity
 * plus tan(theta) |g| along u x g, scaled by cos(theta), which no verdict sees. A stable verdict
 * needs a static field, so the margin is about at most this (the LP is the first reading's, and
 * in 3-D its friction pyramids are turned to gravity as loaded, not as changed), and where
 * nothing but the static field limits the assembly, about equal to it. */
static double static_limit(Ctx *c, int kind, const double dir[3]) {
    const cnCheckOptions *co = limit_options(c);
    if (!co) return -1;
    double load[3];
    if (kind == CN_MARGIN_TILT) cn_cross3(dir, c->g, load);
    else
        for (int k = 0; k < 3; k++) load[k] = cn_norm3(c->g) * dir[k];
    if (c->a->dim == 2) load[2] = 0;
    cn_copy3(c->v.gravity, c->g);
    double t = -1;
    cnDiag quiet;
    if (cn_check_load_limit(&c->v, co, load, CN_MARGIN_MAX_LATERAL, &t, &quiet) != CN_OK) return -1;
    if (!(t > 0) || !(t < CN_MARGIN_MAX_LATERAL)) return -1;
    return kind == CN_MARGIN_TILT ? atan(t) : t;
}

/* Down from *f (not stable) towards floor (stable, or 0), CN_MARGIN_SEED_STEP of lim and 4 times
 * farther each time, to a stable verdict: *s the stable end found (floor when none), *f the
 * not-stable verdict nearest it. */
static cnStatus step_down(Ctx *c, int kind, const double dir[3], double lim, double floor, double *s,
                          double *f, cnMargin *m, cnDiag *diag) {
    *s = floor;
    for (double h = CN_MARGIN_SEED_STEP * lim; *f - h > floor; h *= 4) {
        bool ok;
        cnStatus st = probe(c, kind, dir, *f - h, m, &ok, diag);
        if (st != CN_OK) return st;
        if (ok) {
            *s = *f - h;
            return CN_OK;
        }
        *f -= h;
    }
    return CN_OK;
}

/* Up from s (stable, just above the static limit lim: the LP's limit can be off by a few times
 * its residual), CN_MARGIN_SEED_STEP of lim and 4 times farther each time, CN_MARGIN_UP_STEPS
 * times at most: a verdict not stable is bracketed with the last stable one (*done). Else *s is
 * the last stable one, for the search upward. */
static cnStatus step_up(Ctx *c, int kind, const double dir[3], double lim, double *s, cnMargin *m,
                        bool *done, cnDiag *diag) {
    *done = false;
    double top = range_top(kind), h = fmax(CN_MARGIN_SEED_STEP, c->tol) * lim;
    for (int k = 0; k < CN_MARGIN_UP_STEPS && *s + h < top; k++, h *= 4) {
        bool ok;
        cnStatus st = probe(c, kind, dir, *s + h, m, &ok, diag);
        if (st != CN_OK) return st;
        if (!ok) {
            *done = true;
            return bisect(c, kind, dir, *s, *s + h, m, diag);
        }
        *s += h;
    }
    return CN_OK;
}

/* The margin bracketed about the static limit lim: verdicts just below and just above it (two
 * verdicts when the static field is what gives way); else down from it, CN_MARGIN_SEED_STEP of
 * it and 4 times farther each time, to a stable verdict, then bisection. *done false: stable above it too (the caller
 * searches upward from *from). */
static cnStatus about_limit(Ctx *c, int kind, const double dir[3], double lim, cnMargin *m,
                            bool *done, double *from, cnDiag *diag) {
    bool ok;
    *done = true;
    double top = range_top(kind);
    double lo = lim * (1 - 0.5 * c->tol), hi = fmin(lim * (1 + 0.5 * c->tol), top);
    if (!(hi > lo)) return *done = false, *from = 0, CN_OK; /* at the search's end: as before */
    cnStatus st = probe(c, kind, dir, lo, m, &ok, diag);
    if (st != CN_OK) return st;
    if (ok) {
        if ((st = probe(c, kind, dir, hi, m, &ok, diag)) != CN_OK) return st;
        if (!ok) return bisect(c, kind, dir, lo, hi, m, diag);
        *from = hi;
        return step_up(c, kind, dir, lim, from, m, done, diag);
    }
    double s, f = lo;
    if ((st = step_down(c, kind, dir, lim, 0, &s, &f, m, diag)) != CN_OK) return st;
    return bisect(c, kind, dir, s, f, m, diag);
}


/* Narrow [s, f] (s stable, f not, s < f) as bisect does, looking first just below and just above
 * the static limit when it lies between them. */
static cnStatus narrow(Ctx *c, int kind, const double dir[3], double s, double f, cnMargin *m,
                       cnDiag *diag) {
    double lim = s < f ? static_limit(c, kind, dir) : -1;
    if (lim > s && lim < f) {
        bool ok;
        double lo = fmax(lim * (1 - 0.5 * c->tol), s), hi = fmin(lim * (1 + 0.5 * c->tol), f);
        cnStatus st = probe(c, kind, dir, lo, m, &ok, diag);
        if (st != CN_OK) return st;
        if (!ok) {
            /* the LP's limit can be off by a few times its residual: down from it as about_limit
               does, rather than bisecting all of [s, lo] */
            f = lo;
            if ((st = step_down(c, kind, dir, lim, s, &s, &f, m, diag)) != CN_OK) return st;
        } else {
            s = lo;
            if ((st = probe(c, kind, dir, hi, m, &ok, diag)) != CN_OK) return st;
            if (ok) s = hi;
            else f = hi;
        }
    }
    return bisect(c, kind, dir, s, f, m, diag);
}

/* The tilt or lateral margin along dir, the assembly standing as given. */
static cnStatus along(Ctx *c, int kind, const double dir[3], cnMargin *m, cnDiag *diag) {
    cn_copy3(m->dir, dir);
    bool ok;
    cnStatus st;
    double s = 0, lim = static_limit(c, kind, dir);
    if (lim > 0) {
        bool done;
        if ((st = about_limit(c, kind, dir, lim, m, &done, &s, diag)) != CN_OK || done) return st;
    }
    if (kind == CN_MARGIN_TILT) {
        if ((st = probe(c, kind, dir, CN_MARGIN_MAX_TILT, m, &ok, diag)) != CN_OK) return st;
        if (ok) {
            m->end = CN_MARGIN_WHOLE, m->value = CN_MARGIN_MAX_TILT;
            return CN_OK;
        }
        return bisect(c, kind, dir, s, CN_MARGIN_MAX_TILT, m, diag);
    }
    double t = s > 0 ? fmin(4 * s, CN_MARGIN_MAX_LATERAL) : 1;
    for (;;) {
        if ((st = probe(c, kind, dir, t, m, &ok, diag)) != CN_OK) return st;
        if (!ok) return bisect(c, kind, dir, s, t, m, diag);
        if (t >= CN_MARGIN_MAX_LATERAL) {
            m->end = CN_MARGIN_WHOLE, m->value = t;
            return CN_OK;
        }
        s = t;
        t = fmin(4 * t, CN_MARGIN_MAX_LATERAL);
    }
}

/* Direction dir's margin about its static limit lim (about_limit), its verdicts counted in best's;
 * it replaces best (*better) when bracketed there and below `below`. */
static cnStatus replace_about(Ctx *c, int kind, const double dir[3], double lim, double below,
                              cnMargin *best, bool *better, cnDiag *diag) {
    cnMargin m;
    memset(&m, 0, sizeof m);
    m.computed = true;
    m.past = NAN;
    cn_copy3(m.dir, dir);
    bool done;
    double from;
    cnStatus st = about_limit(c, kind, dir, lim, &m, &done, &from, diag);
    best->verdicts += m.verdicts;
    *better = st == CN_OK && done && m.value < below;
    if (*better) {
        m.verdicts = best->verdicts;
        cn_check_result_free(&best->collapse);
        *best = m;
        return CN_OK;
    }
    cn_check_result_free(&m.collapse);
    return st;
}

/* Direction dir against the incumbent by its static limit alone: when that is below best's
 * margin, its own margin about it (proved by verdicts), which replaces best when lower; else no
 * verdict. */
static cnStatus challenge_static(Ctx *c, int kind, const double dir[3], cnMargin *best, bool *better,
                                 cnDiag *diag) {
    *better = false;
    double lim = static_limit(c, kind, dir);
    if (!(lim > 0 && lim < best->value * (1 - c->tol))) return CN_OK;
    return replace_about(c, kind, dir, lim, best->value, best, better, diag);
}

/* Direction dir against the incumbent best: when its static limit is below best's margin, its
 * own margin about that limit (challenge_static); else one verdict at best's value, and when
 * that is not stable, dir's own margin (below best's). A weaker margin replaces best. */
static cnStatus challenge(Ctx *c, int kind, const double dir[3], double gallop, cnMargin *best, bool *better,
                          cnDiag *diag) {
    cnStatus st = challenge_static(c, kind, dir, best, better, diag); /* weaker by its statics */
    if (st != CN_OK || *better) return st;
    cnMargin m;
    memset(&m, 0, sizeof m);
    m.computed = true;
    m.past = NAN;
    cn_copy3(m.dir, dir);
    bool ok;
    st = probe(c, kind, dir, best->value, &m, &ok, diag);
    /* weaker: gallop down from best, `gallop` of it first (neighbouring directions differ
       little, the opposite sense of a symmetric 2-D assembly by rounding alone), then bisect */
    double f = best->value, h = gallop * best->value;
    bool found = false;
    while (st == CN_OK && !ok && f - h > 0) {
        bool below;
        st = probe(c, kind, dir, f - h, &m, &below, diag);
        if (st != CN_OK) break;
        if (below) {
            st = bisect(c, kind, dir, f - h, f, &m, diag);
            found = true;
            break;
        }
        f -= h, h *= 4;
    }
    if (st == CN_OK && !ok && !found) st = bisect(c, kind, dir, 0, f, &m, diag);
    best->verdicts += m.verdicts;
    if (st != CN_OK || ok) {
        cn_check_result_free(&m.collapse);
        return st;
    }
    m.verdicts = best->verdicts;
    cn_check_result_free(&best->collapse);
    *best = m;
    *better = true;
    return CN_OK;
}

/* The incumbent's static limit when its margin is that limit (within twice the tolerance, or
 * within CN_MARGIN_STATIC_BAND), else -1: then the pattern searches follow the static limits
 * (pattern_static). */
static double static_bound(Ctx *c, int kind, const cnMargin *best) {
    if (best->end != CN_MARGIN_FOUND) return -1;
    double lim = static_limit(c, kind, best->dir);
    double band = fmax(2 * c->tol, CN_MARGIN_STATIC_BAND);
    return lim > 0 && best->value >= lim * (1 - band) && best->value <= lim * (1 + band) ? lim : -1;
}

/* Two unit vectors perpendicular to gravity and to each other (3-D), from the world axis least
 * along gravity. */
static void horizontal_basis(const double g[3], double e1[3], double e2[3]) {
    double up[3] = {-g[0], -g[1], -g[2]};
    cn_normalize3(up);
    int k = 0;
    for (int i = 1; i < 3; i++)
        if (fabs(up[i]) < fabs(up[k])) k = i;
    double w[3] = {0, 0, 0};
    w[k] = 1;
    for (int i = 0; i < 3; i++) e1[i] = w[i] - cn_dot3(w, up) * up[i];
    cn_normalize3(e1);
    cn_cross3(up, e1, e2);
}

/* dir at azimuth phi: a tilt axis, or a lateral direction. */
static void azimuth(const double e1[3], const double e2[3], double phi, double dir[3]) {
    for (int k = 0; k < 3; k++) dir[k] = cos(phi) * e1[k] + sin(phi) * e2[k];
}

/* The pattern search of an incumbent whose margin is its static limit lim, on the static limits
 * alone (an LP a direction, no verdict): it moves to a neighbour whose limit is lower (at most
 * CN_MARGIN_MAX_MOVES times), else halves the step, down to min_step; the direction reached then
 * gets its margin about its limit (verdicts), which replaces best unless higher by more than the
 * tolerance (the LP's rounding). */
static cnStatus pattern_static(Ctx *c, int kind, const double e1[3], const double e2[3], double *phi,
                               double step, double min_step, double lim, cnMargin *best, cnDiag *diag) {
    double dir[3], at = *phi;
    for (int moves = 0; step >= min_step && moves < CN_MARGIN_MAX_MOVES;) {
        if (out_of_time(c)) {
            best->stopped = true;
            return CN_OK;
        }
        bool moved = false;
        for (int sgn = -1; sgn <= 1 && !moved; sgn += 2) {
            azimuth(e1, e2, at + sgn * step, dir);
            double l = static_limit(c, kind, dir);
            if (l > 0 && l < lim) at += sgn * step, lim = l, moved = true, moves++;
        }
        if (!moved) step /= 2;
    }
    if (at == *phi) return CN_OK;
    bool better;
    azimuth(e1, e2, at, dir);
    cnStatus st = replace_about(c, kind, dir, lim, best->value * (1 + c->tol), best, &better, diag);
    if (better) *phi = at;
    return st;
}

/* A pattern search over the azimuth about *phi: by the static limits when the incumbent's margin
 * is its own (pattern_static); else its neighbours at +-step challenge the incumbent, a weaker
 * one is moved to (at most CN_MARGIN_MAX_MOVES times), else the step halves, down to min_step. */
static cnStatus pattern(Ctx *c, int kind, const double e1[3], const double e2[3], double *phi, double step,
                        double min_step, cnMargin *best, cnDiag *diag) {
    double lim = static_bound(c, kind, best);
    if (lim > 0) return pattern_static(c, kind, e1, e2, phi, step, min_step, lim, best, diag);
    cnStatus st = CN_OK;
    double dir[3];
    bool better;
    for (int moves = 0; st == CN_OK && step >= min_step && moves < CN_MARGIN_MAX_MOVES && !best->stopped;) {
        if (out_of_time(c)) {
            best->stopped = true;
            break;
        }
        bool moved = false;
        for (int sgn = -1; sgn <= 1 && !moved && st == CN_OK; sgn += 2) {
            azimuth(e1, e2, *phi + sgn * step, dir);
            if ((st = challenge(c, kind, dir, CN_MARGIN_GALLOP, best, &better, diag)) != CN_OK) break;
            if (better) *phi += sgn * step, moved = true, moves++;
        }
        if (!moved) step /= 2;
    }
    return st;
}

/* The weakest direction's margin: 2-D both senses; 3-D the azimuths, then a pattern search. */
static cnStatus weakest(Ctx *c, int kind, cnMargin *best, cnDiag *diag) {
    bool better;
    cnStatus st;
    if (c->a->dim == 2) {
        double d[2][3] = {{0, 0, 1}, {0, 0, -1}};
        if (kind == CN_MARGIN_LATERAL) {
            double gl = hypot(c->g[0], c->g[1]);
            double h[3] = {-c->g[1] / gl, c->g[0] / gl, 0};
            for (int k = 0; k < 3; k++) d[0][k] = h[k], d[1][k] = -h[k];
        }
        if ((st = along(c, kind, d[0], best, diag)) != CN_OK) return st;
        return challenge(c, kind, d[1], fmin(c->tol, CN_MARGIN_GALLOP), best, &better, diag);
    }
    double e1[3], e2[3], dir[3], phi = 0, fine = c->tol;
    horizontal_basis(c->g, e1, e2);
    c->tol = fmax(fine, CN_MARGIN_SCAN_TOL); /* the scan coarse, the weakest refined below */
    for (int i = 0; i < CN_MARGIN_AZIMUTHS; i++) {
        if (i > 0 && out_of_time(c)) {
            best->stopped = true;
            break;
        }
        double at = 2 * CN_PI * i / CN_MARGIN_AZIMUTHS;
        azimuth(e1, e2, at, dir);
        if (i == 0) st = along(c, kind, dir, best, diag);
        else st = challenge(c, kind, dir, CN_MARGIN_GALLOP, best, &better, diag);
        if (st != CN_OK) break;
        if (i == 0 || better) phi = at;
    }
    if (st == CN_OK) st = pattern(c, kind, e1, e2, &phi, CN_PI / CN_MARGIN_AZIMUTHS, CN_MARGIN_AZIMUTH_STEP, best, diag);
    c->tol = fine;
    if (st == CN_OK && best->end == CN_MARGIN_FOUND && !isnan(best->past)) {
        cnMargin m = *best; /* the weakest direction's bracket, narrowed to the tolerance */
        st = narrow(c, kind, best->dir, best->value, best->past, &m, diag);
        *best = m;
    }
    /* again about the weakest at the fine tolerance: a direction weaker by less than the scan's
       tolerance was not seen (the margin is smooth in the azimuth near its minimum, or has a
       corner there: an azimuth within CN_MARGIN_AZIMUTH_FINE of it is within about its square,
       relative, of the least) */
    if (st == CN_OK && best->end == CN_MARGIN_FOUND)
        st = pattern(c, kind, e1, e2, &phi, CN_PI / CN_MARGIN_AZIMUTHS / 8, CN_MARGIN_AZIMUTH_FINE, best, diag);
    return st;
}

/* A given axis or direction: its part perpendicular to gravity, unit (2-D: a tilt axis is +-z,
 * a direction lies in the plane). */
static cnStatus given_dir(const Ctx *c, const char *what, const double in[3], double out[3],
                          cnDiag *diag) {
    double up[3];
    cn_copy3(up, c->g);
    cn_normalize3(up);
    if (c->a->dim == 2 && !strcmp(what, "axis")) {
        if (!(in[2] != 0) || !isfinite(in[2]))
            return cn_diag_set(diag, CN_ERR_INPUT, "axis",
                               "in 2-D gravity turns in the plane: give the axis as 0,0,1 (counter-clockwise) "
                               "or 0,0,-1 (clockwise)");
        out[0] = out[1] = 0, out[2] = in[2] > 0 ? 1 : -1;
        return CN_OK;
    }
    double big = fmax(fabs(in[0]), fmax(fabs(in[1]), fabs(in[2]))); /* scaled first: no under- or
                                                                         overflow in the norm */
    if (!(big > 0) || !isfinite(big) || !isfinite(in[0]) || !isfinite(in[1]) || !isfinite(in[2]))
        return cn_diag_set(diag, CN_ERR_INPUT, what, "the %s must be a finite, nonzero vector", what);
    for (int k = 0; k < 3; k++) out[k] = in[k] / big;
    cn_normalize3(out);
    if (c->a->dim == 2) out[2] = 0;
    double along_g = cn_dot3(out, up);
    for (int k = 0; k < 3; k++) out[k] -= along_g * up[k];
    if (cn_norm3(out) < CN_MARGIN_PERP_MIN)
        return cn_diag_set(diag, CN_ERR_INPUT, what,
                           "the %s is (nearly) parallel to gravity: give a horizontal one", what);
    cn_normalize3(out);
    return CN_OK;
}

/* The mechanism a little past the bracket: at `past` the motion is at the verdicts' threshold
 * (and may point anywhere); CN_MARGIN_PAST farther on it is the collapse's. */
static cnStatus sharpen(Ctx *c, int kind, cnMargin *m, cnDiag *diag) {
    m->mechanism_at = m->past;
    if (m->end != CN_MARGIN_FOUND || m->past_failed || !isfinite(m->past)) return CN_OK;
    double step = CN_MARGIN_PAST * fmax(fabs(m->past), CN_MARGIN_ZERO);
    /* a far side already that far from the margin (a margin of zero bracketed by growing
       steps, a coarse tolerance, a bracket left wide by the time limit): its mechanism is as
       clear of the threshold as the one farther on would be */
    if (isfinite(m->value) && fabs(m->past - m->value) >= step) return CN_OK;
    double t = kind == CN_MARGIN_FRICTION ? fmax(m->past - step, 0)
               : kind == CN_MARGIN_TILT  ? fmin(m->past + step, CN_MARGIN_MAX_TILT)
                                         : m->past + step;
    cnMargin probe_m = *m;
    memset(&probe_m.collapse, 0, sizeof probe_m.collapse);
    bool ok;
    cnStatus st = probe(c, kind, m->dir, t, &probe_m, &ok, diag);
    m->verdicts++;
    if (st != CN_OK || ok || probe_m.past_failed) {
        cn_check_result_free(&probe_m.collapse);
        return st;
    }
    cn_check_result_free(&m->collapse);
    m->collapse = probe_m.collapse;
    cn_copy3(m->gravity, probe_m.gravity);
    m->mechanism_at = t;
    return CN_OK;
}

/* Does the equilibrium LP have a static field at friction t? 1, 0, or -1 (not known). */
static int field_at(Ctx *c, double t) {
    cn_copy3(c->v.gravity, c->g);
    friction_at(c, t);
    int has = -1;
    cnDiag quiet;
    const cnCheckOptions *co = limit_options(c);
    if (!co || cn_check_has_field(&c->v, co, &has, &quiet) != CN_OK) return -1;
    return has;
}

/* The least friction at which the equilibrium LP has a static field, by bisection on the LP
 * alone between f (none) and s (one) to CN_MARGIN_STATIC_TOL times the margin's tolerance, or
 * -1 (an LP not known either way, the time up, or the plain check not the verdict). A static field exists at every larger coefficient
 * (each cone holds the smaller one), so the bisection is exact to its tolerance. */
#define CN_MARGIN_STATIC_TOL 0.1
static double friction_limit(Ctx *c, double f, double s) {
    if (!limit_options(c)) return -1;
    for (int it = 0; it < CN_MARGIN_MAX_HALVINGS; it++) {
        if (s - f <= fmax(CN_MARGIN_STATIC_TOL * c->tol * s, 0.1 * CN_MARGIN_ZERO)) break;
        if (out_of_time(c)) return -1;
        double mid = 0.5 * (f + s);
        int has = field_at(c, mid);
        if (has < 0) return -1;
        if (has) s = mid;
        else f = mid;
    }
    return s;
}

/* The critical friction from the static one, lim: verdicts just above and below it (two where
 * no motion from rest sets in above the statics); else up from it, CN_MARGIN_SEED_STEP of it
 * and 4 times farther each time, to a stable verdict, then bisection. *done false: no stable verdict found
 * up to CN_MARGIN_MAX_FRICTION (searched as before from *from). */
static cnStatus friction_about(Ctx *c, double lim, cnMargin *m, bool *done, double *from,
                               cnDiag *diag) {
    bool ok;
    *done = true;
    double lo = lim * (1 - 0.5 * c->tol), hi = lim * (1 + 0.5 * c->tol);
    if (!(hi < CN_MARGIN_MAX_FRICTION)) return *done = false, *from = 0, CN_OK; /* as before */
    cnStatus st = probe(c, CN_MARGIN_FRICTION, NULL, hi, m, &ok, diag);
    if (st != CN_OK) return st;
    if (ok) {
        if ((st = probe(c, CN_MARGIN_FRICTION, NULL, lo, m, &ok, diag)) != CN_OK) return st;
        return ok ? bisect(c, CN_MARGIN_FRICTION, NULL, lo, 0, m, diag)
                  : bisect(c, CN_MARGIN_FRICTION, NULL, hi, lo, m, diag);
    }
    double f = hi, h = CN_MARGIN_SEED_STEP * lim;
    while (f + h < CN_MARGIN_MAX_FRICTION) {
        if ((st = probe(c, CN_MARGIN_FRICTION, NULL, f + h, m, &ok, diag)) != CN_OK) return st;
        if (ok) return bisect(c, CN_MARGIN_FRICTION, NULL, f + h, f, m, diag);
        f += h, h *= 4;
    }
    *done = false, *from = f;
    return CN_OK;
}

static cnStatus margin_friction(Ctx *c, cnMargin *m, cnDiag *diag) {
    double base = c->one_pair ? c->pairs[c->pair_index].mu : friction_ref(c->a);
    m->base = base;
    bool ok;
    cnStatus st = probe(c, CN_MARGIN_FRICTION, NULL, 0, m, &ok, diag);
    if (st != CN_OK) return st;
    if (ok) {
        m->end = CN_MARGIN_WHOLE, m->value = 0;
        return CN_OK;
    }
    double f = 0, t = base > 0 ? fmin(base, CN_MARGIN_MAX_FRICTION) : 0.5;
    /* the static limit first, between none (frictionless: the verdict above was not stable) and
     * a coefficient where the LP has a field */
    double up = t;
    int has = field_at(c, up);
    while (has == 0 && up < CN_MARGIN_MAX_FRICTION) {
        up = fmin(4 * up, CN_MARGIN_MAX_FRICTION);
        has = field_at(c, up);
    }
    double lim = has == 1 && field_at(c, 0) == 0 ? friction_limit(c, 0, up) : -1;
    if (lim > 0) {
        bool done;
        double from;
        if ((st = friction_about(c, lim, m, &done, &from, diag)) != CN_OK || done) return st;
        if (from > 0) f = from, t = fmin(4 * from, CN_MARGIN_MAX_FRICTION);
    }
    for (;;) {
        if ((st = probe(c, CN_MARGIN_FRICTION, NULL, t, m, &ok, diag)) != CN_OK) return st;
        if (ok) return bisect(c, CN_MARGIN_FRICTION, NULL, t, f, m, diag);
        if (t >= CN_MARGIN_MAX_FRICTION) {
            m->end = CN_MARGIN_NONE, m->value = INFINITY;
            return CN_OK;
        }
        f = t;
        t = fmin(4 * t, CN_MARGIN_MAX_FRICTION);
    }
}

/* The pairs' own copy (one spare for a pair the file does not list), and the pair varied. */
static cnStatus setup_friction(Ctx *c, const cnMarginOptions *o, cnDiag *diag) {
    const cnAssembly *a = c->a;
    c->pairs = cn_calloc((size_t)a->npairs + 1, sizeof(cnFrictionPair));
    if (!c->pairs) return cn_diag_oom(diag);
    if (a->npairs) memcpy(c->pairs, a->pairs, sizeof(cnFrictionPair) * (size_t)a->npairs);
    c->v.pairs = c->pairs;
    c->one_pair = o->pair[0] >= 0 || o->pair[1] >= 0;
    if (!c->one_pair) return CN_OK;
    int i = o->pair[0], j = o->pair[1];
    if (i < 0 || j < 0 || i >= a->nreal || j >= a->nreal || i == j)
        return cn_diag_set(diag, CN_ERR_INPUT, "pair", "the pair must name two different parts of the assembly");
    c->pair_index = a->npairs;
    for (int k = 0; k < a->npairs; k++)
        if ((a->pairs[k].a == i && a->pairs[k].b == j) || (a->pairs[k].a == j && a->pairs[k].b == i))
            c->pair_index = k;
    if (c->pair_index == a->npairs) {
        c->pairs[a->npairs] = (cnFrictionPair){i < j ? i : j, i < j ? j : i, cn_assembly_mu(a, i, j)};
        c->v.npairs = a->npairs + 1;
    }
    return CN_OK;
}

cnStatus cn_margin(const cnAssembly *a, const cnMarginOptions *opt, cnMarginResult *out,
                   cnDiag *diag) {
    return cn_margin_with(a, opt, NULL, NULL, NULL, out, diag);
}

cnStatus cn_margin_with(const cnAssembly *a, const cnMarginOptions *opt, cnMarginVerdictFn fn,
                        cnMarginPoseFn pose, void *ctx, cnMarginResult *out, cnDiag *diag) {
    memset(out, 0, sizeof *out);
    cnMarginOptions o = opt ? *opt : cn_margin_options_default();
    unsigned kinds = o.kinds ? o.kinds : CN_MARGIN_ALL;
    if (kinds & ~(unsigned)CN_MARGIN_ALL)
        return cn_diag_set(diag, CN_ERR_INPUT, "kinds", "unknown margin kind: use friction, tilt, lateral");
    if (!(o.max_seconds >= 0))
        return cn_diag_set(diag, CN_ERR_INPUT, "max_seconds", "the time limit must be a number of seconds, 0 for none");
    if (!(o.rel_tol >= 0) || o.rel_tol >= 0.5)
        return cn_diag_set(diag, CN_ERR_INPUT, "rel_tol", "the tolerance must be a number from 0 to 0.5");
    Ctx c;
    memset(&c, 0, sizeof c);
    c.a = a;
    c.v = *a;
    c.verdict = fn ? fn : plain_check;
    c.pose = pose;
    c.verdict_ctx = ctx;
    c.check = o.check;
    cnCheckOptions loaded = o.check; /* the verdict as loaded: what cn_check says */
    if (!(c.check.motion_tol > 0)) c.check.motion_tol = CN_MARGIN_MOTION_TOL;
    c.max_seconds = o.max_seconds > 0 ? o.max_seconds : 0;
    clock_gettime(CLOCK_MONOTONIC, &c.t0);
    c.check.motion = NULL;
    c.check.keep_lcp = false;
    c.check.warm = &c.warm;
    c.tol = o.rel_tol > 0 ? o.rel_tol : CN_MARGIN_DEFAULT_REL_TOL;
    cn_copy3(c.g, a->gravity);
    if (!(cn_norm3(c.g) > 0))
        return cn_diag_set(diag, CN_ERR_INPUT, "gravity", "margins need gravity: the assembly's is zero");
    cnMargin *ms[3] = {&out->friction, &out->tilt, &out->lateral};
    for (int k = 0; k < 3; k++) ms[k]->past = NAN;
    double axis[3], direction[3];
    bool has_axis = o.axis[0] != 0 || o.axis[1] != 0 || o.axis[2] != 0;
    bool has_dir = o.direction[0] != 0 || o.direction[1] != 0 || o.direction[2] != 0;
    cnStatus st = CN_OK;
    if (has_axis) st = given_dir(&c, "axis", o.axis, axis, diag);
    if (st == CN_OK && has_dir) st = given_dir(&c, "direction", o.direction, direction, diag);
    if (st == CN_OK) st = setup_friction(&c, &o, diag);
    /* the verdict as given */
    cnCheckResult r0;
    if (st == CN_OK) {
        loaded.motion = NULL;
        loaded.keep_lcp = false;
        st = c.verdict(c.verdict_ctx, &c.v, &loaded, &r0, diag);
        if (st == CN_OK) out->verdict = r0.verdict;
        bool touch = false; /* the pair varied must touch, or its friction plays no part */
        for (int i = 0; st == CN_OK && c.one_pair && i < r0.contacts.count; i++) {
            const cnContact *ct = &r0.contacts.items[i];
            touch |= (ct->body1 == o.pair[0] && ct->body2 == o.pair[1]) ||
                     (ct->body1 == o.pair[1] && ct->body2 == o.pair[0]);
        }
        if (st == CN_OK && c.one_pair && !touch && (kinds & CN_MARGIN_FRICTION))
            st = cn_diag_set(diag, CN_ERR_INPUT, "pair",
                             "parts '%s' and '%s' do not touch: their friction plays no part; name two parts "
                             "in contact",
                             a->parts[o.pair[0]].name, a->parts[o.pair[1]].name);
        cn_check_result_free(&r0);
    }
    if (st == CN_OK && (kinds & CN_MARGIN_FRICTION)) {
        out->friction.computed = true;
        st = margin_friction(&c, &out->friction, diag);
        if (st == CN_OK) st = sharpen(&c, CN_MARGIN_FRICTION, &out->friction, diag);
        c.v.friction = a->friction, c.v.pairs = a->pairs, c.v.npairs = a->npairs;
    }
    for (int k = 1; k < 3 && st == CN_OK; k++) {
        int kind = k == 1 ? CN_MARGIN_TILT : CN_MARGIN_LATERAL;
        if (!(kinds & (unsigned)kind)) continue;
        cnMargin *m = ms[k];
        m->computed = true;
        if (out->verdict != CN_VERDICT_STABLE) { /* no margin: not stable as given */
            m->end = CN_MARGIN_NONE, m->value = 0;
            continue;
        }
        bool given = kind == CN_MARGIN_TILT ? has_axis : has_dir;
        if (given) st = along(&c, kind, kind == CN_MARGIN_TILT ? axis : direction, m, diag);
        else st = weakest(&c, kind, m, diag);
        if (st == CN_OK) st = sharpen(&c, kind, m, diag);
        if (st == CN_OK && m->end != CN_MARGIN_FOUND) m->past = NAN;
    }
    if (out->friction.computed && out->friction.end == CN_MARGIN_WHOLE) out->friction.past = NAN;
    for (int k = 0; k < 3; k++) /* below the verdicts' resolution: 0 */
        if (ms[k]->computed && ms[k]->end == CN_MARGIN_FOUND && ms[k]->value < CN_MARGIN_ZERO) ms[k]->value = 0;
    for (int k = 0; k < 3; k++) /* rounding out of the reported directions */
        for (int i = 0; i < 3; i++)
            if (!(fabs(ms[k]->dir[i]) > CN_MARGIN_DIR_ZERO)) ms[k]->dir[i] = 0;
    cn_warm_start_release(&c.warm);
    cn_free(c.pairs);
    if (st != CN_OK) cn_margin_result_free(out);
    return st;
}
