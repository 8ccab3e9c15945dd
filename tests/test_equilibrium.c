/* The equilibrium LP of a check (src/check/equilibrium.c) on assemblies whose answers are known
 * without it. Its static fields are checked against each part's equilibrium and the
 * friction cones, recomputed here from the masses, centres and contact points of the assembly as
 * written, and against closed forms (the lever rule, a block on an incline: static iff
 * tan theta <= mu); its Farkas certificates by the same arithmetic (gravity does work on the
 * virtual motion, which opens every contact by at least mu times its slip) and their motion by
 * its hand-computed kinetic energy; the load limit against sliding (mu g) and tipping (g w / h);
 * the friction LCP's matrix against J M^-1 J^T written out from the Jacobian rows; and the answers
 * do not change when the assembly and its gravity are turned, moved or scaled, or its parts
 * reordered. */
#include <stdbool.h>
#include <stdlib.h>
#include <string.h>

#include "check_work.h"
#include "helpers.h"

/* ---- assemblies written here, with their masses, centres and inertias derived by hand ---- */

#define MAXV 8

typedef struct {
    const char *name;
    bool fixed;
    double mass;
    int nv;
    double v[MAXV][3];
    double com[3];     /* the centroid */
    double inertia[3]; /* principal, about the centre, along the axes as built (2-D: [2]) */
} Part;

typedef struct {
    int dim;
    double g[3];
    double mu;
    int np;
    Part *p; /* np parts, in the file's order */
} Scene;

static double dot3(const double a[3], const double b[3]) {
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
static double norm3(const double a[3]) { return sqrt(dot3(a, a)); }
static void cross3(const double a[3], const double b[3], double out[3]) {
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static Scene *scene_new(int dim, int cap, double gx, double gy, double gz, double mu) {
    Scene *s = calloc(1, sizeof *s);
    s->p = calloc((size_t)cap, sizeof(Part));
    s->dim = dim;
    s->g[0] = gx, s->g[1] = gy, s->g[2] = gz;
    s->mu = mu;
    return s;
}

static void scene_free(Scene *s) {
    if (!s) return;
    free(s->p);
    free(s);
}

/* A 2-D rectangle [x0, x1] x [y0, y1]: centre in the middle, I = m (w^2 + h^2) / 12. */
static Part *rect(Scene *s, const char *name, bool fixed, double mass, double x0, double y0, double x1,
                  double y1) {
    Part *p = &s->p[s->np++];
    p->name = name, p->fixed = fixed, p->mass = mass, p->nv = 4;
    double c[4][2] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    for (int i = 0; i < 4; i++) p->v[i][0] = c[i][0], p->v[i][1] = c[i][1];
    p->com[0] = (x0 + x1) / 2, p->com[1] = (y0 + y1) / 2;
    p->inertia[2] = mass * ((x1 - x0) * (x1 - x0) + (y1 - y0) * (y1 - y0)) / 12;
    return p;
}

/* A fixed 2-D triangle (a knife edge when its apex is up). */
static void tri(Scene *s, const char *name, double x0, double y0, double x1, double y1, double x2,
                double y2) {
    Part *p = &s->p[s->np++];
    p->name = name, p->fixed = true, p->nv = 3;
    double c[3][2] = {{x0, y0}, {x1, y1}, {x2, y2}};
    for (int i = 0; i < 3; i++) p->v[i][0] = c[i][0], p->v[i][1] = c[i][1];
}

/* A 3-D box lo..hi: centre in the middle, I_x = m (b^2 + c^2) / 12 and so on. */
static Part *box(Scene *s, const char *name, bool fixed, double mass, const double lo[3],
                 const double hi[3]) {
    Part *p = &s->p[s->np++];
    p->name = name, p->fixed = fixed, p->mass = mass, p->nv = 8;
    double e[3];
    for (int k = 0; k < 3; k++) e[k] = hi[k] - lo[k], p->com[k] = (lo[k] + hi[k]) / 2;
    for (int i = 0; i < 8; i++)
        for (int k = 0; k < 3; k++) p->v[i][k] = (i >> k) & 1 ? hi[k] : lo[k];
    for (int k = 0; k < 3; k++) {
        double a = e[(k + 1) % 3], b = e[(k + 2) % 3];
        p->inertia[k] = mass * (a * a + b * b) / 12;
    }
    return p;
}

/* The scene turned by R, scaled by sc and moved by T (gravity turned with it), its parts in the
 * order perm (NULL: as they are). Inertias scale by sc^2 (meaningful where R keeps the axes). */
static Scene *scene_posed(const Scene *s, double R[3][3], double sc, const double T[3], const int *perm) {
    Scene *o = scene_new(s->dim, s->np, 0, 0, 0, s->mu);
    o->np = s->np;
    for (int k = 0; k < 3; k++) o->g[k] = dot3(R[k], s->g);
    for (int i = 0; i < s->np; i++) {
        Part *q = &o->p[i];
        *q = s->p[perm ? perm[i] : i];
        for (int j = 0; j < q->nv; j++) {
            double v[3] = {q->v[j][0], q->v[j][1], q->v[j][2]};
            for (int k = 0; k < 3; k++) q->v[j][k] = sc * dot3(R[k], v) + T[k];
        }
        double c[3] = {q->com[0], q->com[1], q->com[2]};
        for (int k = 0; k < 3; k++) q->com[k] = sc * dot3(R[k], c) + T[k], q->inertia[k] *= sc * sc;
    }
    return o;
}

static void rot_z(double R[3][3], double deg) {
    double t = deg * CN_PI / 180, c = cos(t), s = sin(t);
    double M[3][3] = {{c, -s, 0}, {s, c, 0}, {0, 0, 1}};
    memcpy(R, M, sizeof M);
}

/* Rodrigues: a turn by deg about the unit axis n. */
static void rot_axis(double R[3][3], const double n[3], double deg) {
    double t = deg * CN_PI / 180, c = cos(t), s = sin(t);
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) R[i][j] = (i == j ? c : 0) + (1 - c) * n[i] * n[j];
    R[0][1] -= s * n[2], R[0][2] += s * n[1];
    R[1][0] += s * n[2], R[1][2] -= s * n[0];
    R[2][0] -= s * n[1], R[2][1] += s * n[0];
}

static char *scene_json(const Scene *s) {
    size_t cap = 4096 + (size_t)s->np * 640, len = 0;
    char *b = malloc(cap);
#define OUT(...) len += (size_t)snprintf(b + len, cap - len, __VA_ARGS__)
    OUT("{\"dimension\":%d,\"friction\":%.17g,\"gravity\":[", s->dim, s->mu);
    for (int k = 0; k < s->dim; k++) OUT("%s%.17g", k ? "," : "", s->g[k]);
    OUT("],\"parts\":[");
    for (int i = 0; i < s->np; i++) {
        const Part *p = &s->p[i];
        OUT("%s{\"name\":\"%s\",", i ? "," : "", p->name);
        if (p->fixed) OUT("\"fixed\":true,");
        else OUT("\"mass\":%.17g,", p->mass);
        OUT("\"%s\":[", s->dim == 2 ? "polygon" : "hull");
        for (int j = 0; j < p->nv; j++) {
            OUT("%s[", j ? "," : "");
            for (int k = 0; k < s->dim; k++) OUT("%s%.17g", k ? "," : "", p->v[j][k]);
            OUT("]");
        }
        OUT("]}");
    }
    OUT("]}");
#undef OUT
    return b;
}

/* ---- the check's work up to its rows, as src/check/limits.c sets it up ---- */

typedef struct {
    const Scene *s;
    cnAssembly *a;
    cnCheckOptions o;
    Found f;
    cnCheckResult r;
    Work w;
    cnDiag d;
    bool found;
} Rig;

/* The check's work for an assembly in JSON (route: cnCheckOptions.route; dirs: friction
 * directions, 0 the file's); rig_open for a scene written here. */
static bool rig_open_json(Rig *g, const char *json, unsigned route, int dirs) {
    memset(g, 0, sizeof *g);
    g->a = load_ok(json);
    if (!g->a) return false;
    if (dirs > 0) g->a->friction_dirs = dirs;
    g->o = cn_check_options_default();
    g->o.route = route;
    cn_ck_work_init(&g->w, &g->f, g->a, &g->o, &g->r, &g->d, (Reading){0, -1, 0}, false, false);
    if (cn_ck_find_contacts(g->a, &g->o, &g->f, &g->d)) {
        CHECK_MSG(0, "contacts: %s", g->d.message);
        return false;
    }
    g->found = true;
    bool finished = false;
    if (cn_ck_meet_contacts(&g->w, &finished) || finished) {
        CHECK_MSG(0, "meet: %s", g->d.message);
        return false;
    }
    cn_ck_classify_nominal(&g->w);
    if (g->r.infeasible || cn_ck_build_rows(&g->w)) {
        CHECK_MSG(0, "rows: %s", g->d.message);
        return false;
    }
    return true;
}

static bool rig_open(Rig *g, const Scene *s, unsigned route) {
    char *json = scene_json(s);
    bool ok = rig_open_json(g, json, route, 0);
    free(json);
    g->s = s;
    return ok;
}

static void rig_close(Rig *g) {
    cn_ck_work_free(&g->w);
    cn_check_result_free(&g->r);
    if (g->found) cn_ck_found_free(&g->f);
    cn_assembly_free(g->a);
}

static LpAnswer rig_lp(Rig *g, LpAsk ask) {
    LpAnswer ans;
    cnStatus st = cn_ck_static_lp(&g->w, &ask, &ans, g->w.lpforce, g->w.lpfric, &g->d);
    CHECK_MSG(st == CN_OK, "%s", g->d.message);
    return ans;
}

static double part_radius(const Part *p) {
    double r = 0;
    for (int j = 0; j < p->nv; j++) {
        double d[3] = {p->v[j][0] - p->com[0], p->v[j][1] - p->com[1], p->v[j][2] - p->com[2]};
        r = fmax(r, norm3(d));
    }
    return r;
}

static double min_weight(const Scene *s) {
    double w = INFINITY;
    for (int i = 0; i < s->np; i++)
        if (!s->p[i].fixed) w = fmin(w, s->p[i].mass * norm3(s->g));
    return w;
}

/* The largest residual of the free parts' equilibrium under the LP's contact forces, from the
 * scene: a contact pushes body2 by force[c] along its normal plus fric[c], body1 by the
 * opposite, and gravity pulls each part at its centre; the force residual over the part's
 * weight, the torque residual (about its centre) over its weight times its radius. */
static double field_residual(const Rig *g) {
    const Scene *s = g->s;
    double gm = norm3(s->g), worst = 0;
    for (int p = 0; p < s->np; p++) {
        const Part *P = &s->p[p];
        if (P->fixed) continue;
        double F[3], T[3] = {0, 0, 0};
        for (int k = 0; k < 3; k++) F[k] = P->mass * s->g[k];
        for (int c = 0; c < g->w.K; c++) {
            const cnContact *ct = &g->w.cs->items[c];
            int sign = ct->body2 == p ? 1 : ct->body1 == p ? -1 : 0;
            if (!sign) continue;
            double f[3], r[3], t[3];
            for (int k = 0; k < 3; k++) {
                f[k] = sign * (g->w.lpforce[c] * ct->normal[k] + g->w.lpfric[c][k]);
                r[k] = ct->point[k] - P->com[k];
                F[k] += f[k];
            }
            cross3(r, f, t);
            for (int k = 0; k < 3; k++) T[k] += t[k];
        }
        worst = fmax(worst, norm3(F) / (P->mass * gm));
        worst = fmax(worst, norm3(T) / (P->mass * gm * part_radius(P)));
    }
    return worst;
}

/* The largest violation of the Coulomb cones by the LP's forces, over the lightest weight: a
 * normal force below 0, friction off the contact plane, friction above mu times the normal
 * force (mu 0: any friction). */
static double cone_violation(const Rig *g) {
    double worst = 0, w = min_weight(g->s);
    for (int c = 0; c < g->w.K; c++) {
        const cnContact *ct = &g->w.cs->items[c];
        const double *fr = g->w.lpfric[c];
        double fn = g->w.lpforce[c], along = dot3(fr, ct->normal), t[3];
        for (int k = 0; k < 3; k++) t[k] = fr[k] - along * ct->normal[k];
        worst = fmax(worst, fmax(-fn, fabs(along)) / w);
        worst = fmax(worst, (norm3(t) - g->s->mu * fn) / w);
    }
    return worst;
}

/* The LP's normal forces summed over the contacts between parts named n1 and n2 (either way). */
static double pair_force(const Rig *g, const char *n1, const char *n2) {
    double sum = 0;
    for (int c = 0; c < g->w.K; c++) {
        const cnContact *ct = &g->w.cs->items[c];
        const char *a = ct->body1 >= 0 ? g->s->p[ct->body1].name : "";
        const char *b = ct->body2 >= 0 ? g->s->p[ct->body2].name : "";
        if ((!strcmp(a, n1) && !strcmp(b, n2)) || (!strcmp(a, n2) && !strcmp(b, n1))) sum += g->w.lpforce[c];
    }
    return sum;
}

/* The LP's normal force at the contact nearest x (-1 when none is within 1e-9 of the scale). */
static double force_at(const Rig *g, double x, double y, double z) {
    double p[3] = {x, y, z}, best = INFINITY, f = -1;
    for (int c = 0; c < g->w.K; c++) {
        double d[3];
        for (int k = 0; k < 3; k++) d[k] = g->w.cs->items[c].point[k] - p[k];
        if (norm3(d) < best) best = norm3(d), f = g->w.lpforce[c];
    }
    return best <= 1e-9 * (1 + norm3(p)) ? f : -1;
}

/* Velocity of part p at point x on the motion u (per body: the velocity of its centre, then its
 * angular velocity; a fixed part stands still). */
static void part_velocity(const Rig *g, const double *u, int p, const double x[3], double v[3]) {
    v[0] = v[1] = v[2] = 0;
    if (p < 0 || g->s->p[p].fixed) return;
    const double *ub = u + (size_t)g->w.m.body_of_part[p] * g->w.m.nd;
    double r[3], om[3] = {0, 0, 0}, t[3];
    for (int k = 0; k < 3; k++) r[k] = x[k] - g->s->p[p].com[k];
    if (g->s->dim == 2) om[2] = ub[2], v[0] = ub[0], v[1] = ub[1];
    else
        for (int k = 0; k < 3; k++) v[k] = ub[k], om[k] = ub[3 + k];
    cross3(om, r, t);
    for (int k = 0; k < 3; k++) v[k] += t[k];
}

/* A certificate's motion u checked from the scene. Returns gravity's power on u over the largest
 * it could be for those speeds (sum of weight times speed of centre); *gap: the least, over the
 * contacts, of the opening speed less mu cos(pi / D) times the slip (the pyramid of D edges is
 * inscribed in the cone; 2-D: the slip itself), in units of the rounding the certificate may
 * keep (a column may resist by 1e-6 of gravity's power a weight: -1 is that allowance). */
static double cert_check(const Rig *g, const double *u, double *gap) {
    const Scene *s = g->s;
    double P = 0, most = 0;
    for (int p = 0; p < s->np; p++) {
        if (s->p[p].fixed) continue;
        double v[3];
        part_velocity(g, u, p, s->p[p].com, v);
        P += s->p[p].mass * dot3(s->g, v);
        most += s->p[p].mass * norm3(s->g) * norm3(v);
    }
    double cosd = s->dim == 2 ? 1 : cos(CN_PI / g->w.D), unit = 1e-6 * P / min_weight(s);
    *gap = INFINITY;
    for (int c = 0; c < g->w.K; c++) {
        const cnContact *ct = &g->w.cs->items[c];
        double v1[3], v2[3], vr[3], t[3];
        part_velocity(g, u, ct->body1, ct->point, v1);
        part_velocity(g, u, ct->body2, ct->point, v2);
        for (int k = 0; k < 3; k++) vr[k] = v2[k] - v1[k];
        double vn = dot3(vr, ct->normal);
        for (int k = 0; k < 3; k++) t[k] = vr[k] - vn * ct->normal[k];
        *gap = fmin(*gap, (vn - s->mu * cosd * norm3(t)) / unit);
    }
    return most > 0 ? P / most : 0;
}

/* A certificate outcome whose motion (w->cert) passes cert_check. */
static void check_certificate(Rig *g, const LpAnswer *ans, const char *what) {
    CHECK_MSG(ans->outcome == LP_CERTIFICATE, "%s: outcome %d", what, (int)ans->outcome);
    CHECK_MSG(ans->outcome != LP_CERTIFICATE || g->w.cert, "%s: no motion", what);
    if (ans->outcome != LP_CERTIFICATE || !g->w.cert) return;
    double gap, pw = cert_check(g, g->w.cert, &gap);
    CHECK_MSG(pw > 1e-6, "%s: gravity's power %g", what, pw);
    CHECK_MSG(gap >= -1, "%s: a contact closes or slips by %g allowances", what, gap);
}

/* A field outcome whose forces pass field_residual and cone_violation. */
static void check_field(Rig *g, const LpAnswer *ans, const char *what) {
    CHECK_MSG(ans->outcome == LP_FIELD, "%s: outcome %d", what, (int)ans->outcome);
    if (ans->outcome != LP_FIELD) return;
    double res = field_residual(g), cone = cone_violation(g);
    CHECK_MSG(res <= 1e-7, "%s: equilibrium residual %g", what, res);
    CHECK_MSG(cone <= 1e-9, "%s: cone violated by %g", what, cone);
    CHECK_MSG(ans->residual <= 1e-7, "%s: reported residual %g", what, ans->residual);
}

/* ---- scenes ---- */

/* A lintel (mass 3, x 0..6) on knife edges at x = 1 and 4, a block (mass 2, x 3.5..5) on it.
 * Lever rule, g = 9.81: the block's corners carry g each; the lintel's edges carry R1 + R4 = 5 g
 * with, about x = 1, 3 R4 = 3 g * 2 + g * 2.5 + g * 4, so R4 = 12.5 g / 3 and R1 = 2.5 g / 3. */
static Scene *lintel(double mu) {
    Scene *s = scene_new(2, 4, 0, -9.81, 0, mu);
    tri(s, "edge1", 0.5, 0, 1.5, 0, 1, 1);
    tri(s, "edge4", 3.5, 0, 4.5, 0, 4, 1);
    rect(s, "lintel", false, 3, 0, 1, 6, 1.5);
    rect(s, "block", false, 2, 3.5, 1.5, 5, 2.5);
    return s;
}

/* A 2 x 1 block (mass m) on a table whose edge is at x = e, gravity g. */
static Scene *overhang(double e, double m, double gx, double gy, double mu) {
    Scene *s = scene_new(2, 2, gx, gy, 0, mu);
    rect(s, "table", true, 0, -4, -1, e, 0);
    rect(s, "block", false, m, 0, 0, 2, 1);
    return s;
}

/* A 3-D box 2 x 2 x 1 (mass 1) on a table whose edge is at x = e. */
static Scene *overhang3(double e, double gx, double gy, double gz, double mu) {
    Scene *s = scene_new(3, 2, gx, gy, gz, mu);
    box(s, "table", true, 0, (double[3]){-3, -3, -1}, (double[3]){e, 3, 0});
    box(s, "box", false, 1, (double[3]){0, -1, 0}, (double[3]){2, 1, 1});
    return s;
}

/* ---- the tests ---- */

/* Frictionless and with friction, the lintel's LP finds the lever rule's forces (unique: with
 * friction the horizontal forces cancel in each part's torque too) on a field that the part
 * equilibrium recomputed here accepts; the LP's size is one column a contact (plus two of
 * friction and a cone row each with friction) and three rows a part. */
static void test_lintel_field(void) {
    for (int f = 0; f < 2; f++) {
        double mu = f ? 0.5 : 0, g = 9.81;
        Scene *s = lintel(mu);
        Rig R;
        if (rig_open(&R, s, 0)) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = !f});
            check_field(&R, &ans, f ? "lintel, mu 0.5" : "lintel");
            CHECK(R.w.K == 4);
            CHECK(ans.rows == 6 + (f ? 4 : 0) && ans.cols == (f ? 12 : 4));
            CHECK_NEAR(force_at(&R, 1, 1, 0), 2.5 * g / 3, 1e-9 * g);
            CHECK_NEAR(force_at(&R, 4, 1, 0), 12.5 * g / 3, 1e-9 * g);
            CHECK_NEAR(force_at(&R, 3.5, 1.5, 0), g, 1e-9 * g);
            CHECK_NEAR(force_at(&R, 5, 1.5, 0), g, 1e-9 * g);
        }
        rig_close(&R);
        scene_free(s);
    }
}

/* The 2 x 1 block over a table's edge at x = e, frictionless: with its centre (x = 1) over the
 * table a field with the lever rule's R(0) = W (e - 1) / e, R(e) = W / e; at e = 1 exactly all of
 * the weight on the edge; past it (e = 0.8) a certificate whose motion is checked here. Also
 * within rounding of the threshold (the centre an ulp past the edge: the torque left is 1e-16 of
 * the weight's, far inside the 1e-7 a field may leave) a field, and clearly past it (1e-5) a
 * certificate. */
static void test_overhang_2d(void) {
    const double W = 9.81;
    double es[] = {1.2, 1.0, nextafter(1.0, 2.0), nextafter(1.0, 0.0)};
    for (int i = 0; i < 4; i++) {
        double e = es[i];
        Scene *s = overhang(e, 1, 0, -9.81, 0);
        Rig R;
        if (rig_open(&R, s, 0)) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = true});
            check_field(&R, &ans, "block over the edge, stands");
            CHECK_NEAR(force_at(&R, 0, 0, 0), W * (e - 1) / e, 1e-9 * W);
            CHECK_NEAR(force_at(&R, e, 0, 0), W / e, 1e-9 * W);
        }
        rig_close(&R);
        scene_free(s);
    }
    double tips[] = {0.8, 1 - 1e-5};
    for (int i = 0; i < 2; i++) {
        Scene *s = overhang(tips[i], 1, 0, -9.81, 0);
        Rig R;
        if (rig_open(&R, s, 0)) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = true});
            check_certificate(&R, &ans, "block over the edge, tips");
        }
        rig_close(&R);
        scene_free(s);
    }
}

/* A block on a table under gravity (1, -2): an incline of tan theta = 1/2 exactly. Static iff
 * mu >= 1/2: at 0.6 and at the threshold 0.5 a field whose normal forces sum to 2 m and whose
 * friction sums to m up the slope (at 0.5 each contact's friction at its cone's edge); at 0.4 a
 * certificate (the motion slides the block down and, associated, lifts it by mu times the slip);
 * frictionless, a certificate too. */
static void test_incline_2d(void) {
    double mus[] = {0.6, 0.5, 0.4, 0};
    for (int i = 0; i < 4; i++) {
        double mu = mus[i], m = 1.5;
        Scene *s = overhang(4, m, 1, -2, mu);
        Rig R;
        if (rig_open(&R, s, 0)) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = mu == 0});
            if (mu >= 0.5) {
                check_field(&R, &ans, "incline, static");
                double fx = 0;
                for (int c = 0; c < R.w.K; c++) fx += R.w.lpfric[c][0];
                CHECK_NEAR(pair_force(&R, "table", "block"), 2 * m, 1e-9);
                CHECK_NEAR(fx, -m, 1e-9);
                if (mu == 0.5)
                    for (int c = 0; c < R.w.K; c++)
                        CHECK_NEAR(fabs(R.w.lpfric[c][0]), 0.5 * R.w.lpforce[c], 1e-9);
            } else {
                check_certificate(&R, &ans, "incline, slides");
            }
        }
        rig_close(&R);
        scene_free(s);
    }
}

/* 3-D: a 2 x 2 x 1 box on a table, frictionless: a field whose normal forces sum to the weight;
 * over the table's edge at x = 0.8 (its centre at x = 1) a certificate. With gravity
 * (1, 0.5, -2), an incline of tan theta = sqrt(1.25) / 2 = 0.559: at mu 0.6 a field with friction
 * summing to m (1, 0.5) against the slope; at mu 0.5 a certificate (8 pyramid edges, the first
 * downhill: the slide is caught exactly). */
static void test_box_3d(void) {
    struct {
        double e, gx, gy, gz, mu;
        bool stands;
    } cases[] = {{3, 0, 0, -9.81, 0, true},  {0.8, 0, 0, -9.81, 0, false}, {3, 1, 0.5, -2, 0.6, true},
                 {3, 1, 0.5, -2, 0.5, false}, {1.5, 0, 0, -9.81, 0.3, true}, {0.8, 0, 0, -9.81, 0.3, false}};
    for (int i = 0; i < (int)(sizeof cases / sizeof cases[0]); i++) {
        Scene *s = overhang3(cases[i].e, cases[i].gx, cases[i].gy, cases[i].gz, cases[i].mu);
        Rig R;
        char what[64];
        snprintf(what, sizeof what, "3-D box %d", i);
        if (rig_open(&R, s, 0)) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = cases[i].mu == 0});
            if (cases[i].stands) {
                check_field(&R, &ans, what);
                CHECK_NEAR(pair_force(&R, "table", "box"), -cases[i].gz, 1e-9);
                double fr[3] = {0, 0, 0};
                for (int c = 0; c < R.w.K; c++)
                    for (int k = 0; k < 3; k++) fr[k] += R.w.lpfric[c][k];
                CHECK_NEAR(fr[0], -cases[i].gx, 1e-9);
                CHECK_NEAR(fr[1], -cases[i].gy, 1e-9);
            } else {
                check_certificate(&R, &ans, what);
            }
        }
        rig_close(&R);
        scene_free(s);
    }
}


/* The lintel, the tipping block and 3-D boxes on a table, turned (with their gravity), moved,
 * scaled (masses kept: the forces do not change) and with their parts reversed: the same
 * outcome; the lintel's normal force at each contact's image is the one at the contact; the
 * fields and certificates pass the checks here in the posed frame. */
static void test_invariance(void) {
    double R[3][3], I[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, T0[3] = {0, 0, 0};
    double Tm[3] = {1e3, -250, 0}, n[3] = {1 / sqrt(14.0), 2 / sqrt(14.0), 3 / sqrt(14.0)};
    int rev2[] = {1, 0}, rev4[] = {3, 2, 1, 0};
    rot_z(R, 37);
    for (int f = 0; f < 2; f++) {
        Scene *base = lintel(f ? 0.5 : 0);
        Rig B;
        if (!rig_open(&B, base, 0)) {
            rig_close(&B);
            scene_free(base);
            continue;
        }
        LpAnswer b = rig_lp(&B, (LpAsk){.nofric = !f});
        CHECK(b.outcome == LP_FIELD);
        for (int v = 0; v < 4; v++) {
            double(*Rv)[3] = v == 0 || v == 3 ? R : I, sc = v == 2 ? 10 : 1;
            const double *T = v == 1 || v == 3 ? Tm : T0;
            Scene *s = scene_posed(base, Rv, sc, T, v == 3 ? rev4 : NULL);
            Rig P;
            if (rig_open(&P, s, 0)) {
                LpAnswer ans = rig_lp(&P, (LpAsk){.nofric = !f});
                check_field(&P, &ans, "lintel, posed");
                CHECK(P.w.K == B.w.K);
                for (int c = 0; c < B.w.K; c++) {
                    double q[3];
                    for (int k = 0; k < 3; k++) q[k] = sc * dot3(Rv[k], B.w.cs->items[c].point) + T[k];
                    CHECK_NEAR(force_at(&P, q[0], q[1], q[2]), B.w.lpforce[c], 1e-9 * 9.81);
                }
            }
            rig_close(&P);
            scene_free(s);
        }
        rig_close(&B);
        scene_free(base);
    }
    for (int v = 0; v < 4; v++) {
        Scene *base = overhang(0.8, 1, 0, -9.81, v & 1 ? 0.4 : 0);
        double(*Rv)[3] = v < 2 ? R : I;
        Scene *s = scene_posed(base, Rv, v == 2 ? 1e-3 : 1, v == 3 ? Tm : T0, v == 3 ? rev2 : NULL);
        Rig P;
        if (rig_open(&P, s, 0)) {
            LpAnswer ans = rig_lp(&P, (LpAsk){.nofric = !(v & 1)});
            check_certificate(&P, &ans, "tipping block, posed");
        }
        rig_close(&P);
        scene_free(s);
        scene_free(base);
    }
    rot_axis(R, n, 40);
    for (int v = 0; v < 4; v++) {
        /* stands (its centre over the table) for v < 2, tips for v >= 2 */
        Scene *base = overhang3(v < 2 ? 1.5 : 0.8, 0, 0, -9.81, v & 1 ? 0.3 : 0);
        Scene *s = scene_posed(base, R, v == 1 ? 7 : 1, Tm, v == 3 ? rev2 : NULL);
        Rig P;
        if (rig_open(&P, s, 0)) {
            LpAnswer ans = rig_lp(&P, (LpAsk){.nofric = !(v & 1)});
            if (v < 2) {
                check_field(&P, &ans, "3-D box, posed");
                CHECK_NEAR(pair_force(&P, "table", "box"), 9.81, 1e-9);
            } else {
                check_certificate(&P, &ans, "3-D box, posed");
            }
        }
        rig_close(&P);
        scene_free(s);
        scene_free(base);
    }
}

/* Parts of masses 1e6 apart, 2-D: a light block A (x 0..2, y 0..1) on the table and a heavy one
 * B (x 0.5..1.5, y 1..2) on it, and the same with the masses swapped. Frictionless: lever rule,
 * B's corners carry W_B / 2 each, the table's contacts (W_A + W_B) / 2 each, and each part's
 * equilibrium is met to rounding of its own weight. Under gravity (1, -4) (tan theta = 1/4):
 * with mu 0.5 a field whose friction holds each part (the table's contacts (m_A + m_B) in all,
 * A's with B m_B), with mu 0.2 a certificate. */
static void test_mass_ratio(void) {
    for (int v = 0; v < 6; v++) {
        double mA = v & 1 ? 1e3 : 1e-3, mB = v & 1 ? 1e-3 : 1e3, gx = v < 2 ? 0 : 1, gy = v < 2 ? -9.81 : -4;
        double mu = v < 2 ? 0 : v < 4 ? 0.5 : 0.2;
        Scene *s = scene_new(2, 3, gx, gy, 0, mu);
        rect(s, "table", true, 0, -4, -1, 4, 0);
        rect(s, "A", false, mA, 0, 0, 2, 1);
        rect(s, "B", false, mB, 0.5, 1, 1.5, 2);
        Rig R;
        char what[64];
        snprintf(what, sizeof what, "masses %g and %g, mu %g", mA, mB, mu);
        if (rig_open(&R, s, 0)) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = mu == 0});
            if (v < 4) {
                check_field(&R, &ans, what);
                double WA = -mA * gy, WB = -mB * gy;
                double tol = 1e-12 * (WA + WB);
                CHECK_NEAR(pair_force(&R, "A", "B"), WB, tol);
                CHECK_NEAR(pair_force(&R, "table", "A"), WA + WB, tol);
                if (v < 2) {
                    CHECK_NEAR(force_at(&R, 0.5, 1, 0), WB / 2, tol);
                    CHECK_NEAR(force_at(&R, 1.5, 1, 0), WB / 2, tol);
                    CHECK_NEAR(force_at(&R, 0, 0, 0), (WA + WB) / 2, tol);
                    CHECK_NEAR(force_at(&R, 2, 0, 0), (WA + WB) / 2, tol);
                } else {
                    double ftab = 0, fab = 0;
                    for (int c = 0; c < R.w.K; c++) {
                        const cnContact *ct = &R.w.cs->items[c];
                        if (ct->body1 == 0 || ct->body2 == 0) ftab += fabs(R.w.lpfric[c][0]);
                        else fab += fabs(R.w.lpfric[c][0]);
                    }
                    CHECK_NEAR(ftab, mA + mB, 1e-12 * (mA + mB));
                    CHECK_NEAR(fab, mB, 1e-12 * (mA + mB));
                }
            } else {
                check_certificate(&R, &ans, what);
            }
            char buf[256];
            CHECK(!strcmp(cn_ck_mass_span(&R.w, buf, sizeof buf), "")); /* 1e6 < 1e8 */
        }
        rig_close(&R);
        scene_free(s);
    }
}

/* The kinetic energy u^T M u of a motion of the scene's parts (axis-aligned inertias). */
static double scene_kinetic(const Rig *g, const double *u) {
    double e = 0;
    for (int p = 0; p < g->s->np; p++) {
        const Part *P = &g->s->p[p];
        if (P->fixed) continue;
        const double *ub = u + (size_t)g->w.m.body_of_part[p] * g->w.m.nd;
        if (g->s->dim == 2) e += P->mass * (ub[0] * ub[0] + ub[1] * ub[1]) + P->inertia[2] * ub[2] * ub[2];
        else
            for (int k = 0; k < 3; k++) e += P->mass * ub[k] * ub[k] + P->inertia[k] * ub[3 + k] * ub[3 + k];
    }
    return e;
}

/* cn_ck_cert_motion on a verified certificate: acc = t u with t = (f . u) / (u^T M u), the
 * acceleration along u with workless contacts, f . u and u^T M u computed from the scene. */
static void check_cert_motion(Rig *g, const char *what) {
    int nv = g->w.m.nb * g->w.m.nd;
    double *acc = calloc((size_t)nv, sizeof(double)), P = 0;
    cn_ck_cert_motion(&g->w, acc);
    for (int p = 0; p < g->s->np; p++) {
        if (g->s->p[p].fixed) continue;
        double v[3];
        part_velocity(g, g->w.cert, p, g->s->p[p].com, v);
        P += g->s->p[p].mass * dot3(g->s->g, v);
    }
    double t = P / scene_kinetic(g, g->w.cert), worst = 0, size = 0;
    for (int i = 0; i < nv; i++) {
        worst = fmax(worst, fabs(acc[i] - t * g->w.cert[i]));
        size = fmax(size, fabs(t * g->w.cert[i]));
    }
    CHECK_MSG(worst <= 1e-12 * size && size > 0, "%s: motion off by %g of %g", what, worst, size);
    free(acc);
}

/* A motion tried as the certificate (LpAsk.cert_try). On the 2 x 1 block (mass 1) over a table
 * edge at x = 0.8: the turn about the edge, omega = -1, moves the centre (1, 0.5) at
 * omega z x (0.2, 0.5) = (0.5, -0.2), so u = (0.5, -0.2, -1); gravity's power m g 0.2 = 1.962,
 * the corner at x = 0 rises at 0.8 and the edge stays: accepted as it is ("QP motion"), and
 * cn_ck_cert_motion sizes it by t = 1.962 / (m 0.29 + I 1), I = m (4 + 1) / 12. A fall through
 * the table (0, -1, 0) or a lift (0, 1, 0) is refused and GLPK's certificate, checked here,
 * decides; on the lintel, which stands, a tried fall is refused and the field found. */
static void test_cert_try(void) {
    Scene *s = overhang(0.8, 1, 0, -9.81, 0);
    Rig R;
    if (rig_open(&R, s, 0)) {
        double u[3] = {0.5, -0.2, -1};
        LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = true, .cert_try = u});
        check_certificate(&R, &ans, "turn about the edge");
        CHECK(ans.method == CN_LP_METHOD_QP_MOTION);
        if (ans.outcome == LP_CERTIFICATE && R.w.cert) {
            for (int i = 0; i < 3; i++) CHECK_NEAR(R.w.cert[i], u[i], 1e-12);
            double acc[3], t = 1.962 / (0.29 + 5.0 / 12);
            cn_ck_cert_motion(&R.w, acc);
            for (int i = 0; i < 3; i++) CHECK_NEAR(acc[i], t * u[i], 1e-12);
        }
        double bad[2][3] = {{0, -1, 0}, {0, 1, 0}};
        for (int b = 0; b < 2; b++) {
            ans = rig_lp(&R, (LpAsk){.nofric = true, .cert_try = bad[b]});
            check_certificate(&R, &ans, "tried motion refused");
            CHECK(ans.method != CN_LP_METHOD_NONE && ans.method != CN_LP_METHOD_QP_MOTION);
            if (ans.outcome == LP_CERTIFICATE && R.w.cert) check_cert_motion(&R, "GLPK's certificate");
        }
    }
    rig_close(&R);
    scene_free(s);
    s = lintel(0);
    if (rig_open(&R, s, 0)) {
        double fall[6] = {0, -1, 0, 0, -1, 0};
        LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = true, .cert_try = fall});
        check_field(&R, &ans, "lintel, a fall tried");
    }
    rig_close(&R);
    scene_free(s);
}

/* The motion of every certificate of the scenes that fall: 2-D and 3-D, with and without
 * friction (check_cert_motion). */
static void test_cert_motion(void) {
    for (int v = 0; v < 4; v++) {
        double mu = v & 1 ? 0.3 : 0;
        Scene *s = v < 2 ? overhang(0.8, 2.5, 0, -9.81, mu) : overhang3(0.8, 0, 0, -9.81, mu);
        Rig R;
        if (rig_open(&R, s, 0)) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = !(v & 1)});
            check_certificate(&R, &ans, "tips");
            if (ans.outcome == LP_CERTIFICATE && R.w.cert) check_cert_motion(&R, "tips");
        }
        rig_close(&R);
        scene_free(s);
    }
}

/* cn_ck_load_limit_lp against closed forms for a block (mass 1, g = 9.81) on a table under an
 * extra acceleration t of every part along `load`: a 2 x 1 block pulled sideways slides at
 * t = mu g (it would tip at g w / h = 19.62); a 1 x 4 block tips first, at m t h / 2 = m g w / 2,
 * t = g / 4; under a cap of 1, 1; frictionless, sideways t = 0 and upwards t = g (the block
 * lifts beyond); a block tipping unloaded and pulled further over the edge -1; 3-D (8 pyramid
 * edges) sideways between mu g cos(pi / 8) and mu g. */
static void test_load_limit(void) {
    const double g = 9.81;
    struct {
        int dim;
        double w, h, mu, load[3], cap, lo, hi;
    } cases[] = {
        {2, 2, 1, 0.3, {1, 0, 0}, 100, 0.3 * g, 0.3 * g},
        {2, 2, 1, 0.3, {-1, 0, 0}, 100, 0.3 * g, 0.3 * g},
        {2, 1, 4, 0.5, {1, 0, 0}, 100, g / 4, g / 4},
        {2, 1, 4, 0.5, {2, 0, 0}, 100, g / 8, g / 8},
        {2, 2, 1, 0.3, {1, 0, 0}, 1, 1, 1},
        {2, 2, 1, 0, {1, 0, 0}, 100, 0, 0},
        {2, 2, 1, 0, {0, 1, 0}, 100, g, g},
        {2, 2, 1, 0, {0, -1, 0}, 100, 100, 100},
        {3, 2, 1, 0.3, {0, 1, 0}, 100, 0.3 * g * cos(CN_PI / 8), 0.3 * g},
        {3, 2, 1, 0.3, {0.6, 0.8, 0}, 100, 0.3 * g * cos(CN_PI / 8), 0.3 * g},
    };
    for (int i = 0; i < (int)(sizeof cases / sizeof cases[0]); i++) {
        int dim = cases[i].dim;
        Scene *s = scene_new(dim, 2, 0, dim == 2 ? -g : 0, dim == 3 ? -g : 0, cases[i].mu);
        double w = cases[i].w, h = cases[i].h;
        if (cases[i].dim == 2) {
            rect(s, "table", true, 0, -4, -1, 4, 0);
            rect(s, "block", false, 1, 0, 0, w, h);
        } else {
            box(s, "table", true, 0, (double[3]){-4, -4, -1}, (double[3]){4, 4, 0});
            box(s, "block", false, 1, (double[3]){0, 0, 0}, (double[3]){w, w, h});
        }
        Rig R;
        if (rig_open(&R, s, 0)) {
            double t = -2;
            CHECK(cn_ck_load_limit_lp(&R.w, cases[i].load, cases[i].cap, &t, &R.d) == CN_OK);
            CHECK_MSG(t >= cases[i].lo * (1 - 1e-9) && t <= cases[i].hi * (1 + 1e-9),
                      "load limit case %d: %.17g, expected %g .. %g", i, t, cases[i].lo, cases[i].hi);
        }
        rig_close(&R);
        scene_free(s);
    }
    Scene *s = overhang(0.8, 1, 0, -g, 0.5);
    Rig R;
    if (rig_open(&R, s, 0)) {
        double t = -2;
        /* pulled further over the edge: no field at any t */
        CHECK(cn_ck_load_limit_lp(&R.w, (double[3]){1, 0, 0}, 100, &t, &R.d) == CN_OK);
        CHECK(t == -1);
        CHECK(cn_ck_load_limit_lp(&R.w, (double[3]){0, 0, 0}, 100, &t, &R.d) == CN_OK);
        CHECK(t == -1); /* no load: nothing to size */
        /* pulled back over the table: a field from t = 0.4 g (0.5 t about the edge balances
           0.2 g) until it slides at t = mu g, none at 0; the limit is that interval's upper
           end, as check_limit.h says (its callers make sure a field exists at 0) */
        CHECK(cn_ck_load_limit_lp(&R.w, (double[3]){-1, 0, 0}, 100, &t, &R.d) == CN_OK);
        CHECK_MSG(fabs(t - 0.5 * g) <= 1e-9 * g, "pulled back: %.17g, expected mu g", t);
    }
    rig_close(&R);
    scene_free(s);
}

/* A contact that the nominal motion closes (a part driven into another): the LP is not run
 * (LP_NONE) and the load limit is -1. */
static void test_closing(void) {
    Scene *s = lintel(0.5);
    Rig R;
    if (rig_open(&R, s, 0)) {
        R.w.nominal[2] = NOM_CLOSE;
        LpAnswer ans = rig_lp(&R, (LpAsk){0});
        CHECK(ans.outcome == LP_NONE);
        double t = -2;
        CHECK(cn_ck_load_limit_lp(&R.w, (double[3]){1, 0, 0}, 10, &t, &R.d) == CN_OK);
        CHECK(t == -1);
    }
    rig_close(&R);
    scene_free(s);
}

/* The friction LCP's matrix (cn_ck_build_lcp, through each contact's basis rows) against J M^-1 J^T
 * written out entry by entry from the check's own Jacobian rows (a second formulation: each row's
 * generalized force against every other row's response, on the bodies they share), scaled by d;
 * E, -E^T and mu where Stewart and Trinkle put them; q as gravity's relative acceleration. On a
 * 3-D stack of three boxes turned 30 degrees about a slanted axis (normals off the axes) with 3,
 * 8, 13 and 64 friction directions, the same stack upright with one pair's friction zero (contacts
 * without friction rows among those with), the 3-D box over an edge, and the 2-D lintel. */
static void check_lcp_product(Rig *R, const char *what, bool some_frictionless) {
    Work *w = &R->w;
    int K = w->K, Kf = w->Kf, D = w->D, nrows = K + Kf * D, n = nrows + Kf;
    double g = w->m.g, W = w->m.wref;
    cnLcp lcp = {0};
    double *d = calloc((size_t)n, sizeof(double));
    if (!d || cn_ck_build_lcp(w, n, true, &lcp, d) != CN_OK) {
        CHECK_MSG(0, "%s: LCP not built", what);
        free(d);
        return;
    }
    double big = 0, worst = 0, qworst = 0, other = 0;
    for (int i = 0; i < n * n; i++) big = fmax(big, fabs(lcp.M[i]));
    for (int i = 0; i < nrows; i++) {
        for (int j = 0; j < nrows; j++) {
            const cnJRow *a = &w->rows[i], *b = &w->rows[j];
            double e = 0;
            for (int x = 0; x < 2; x++)
                for (int y = 0; y < 2; y++)
                    if (a->body[x] >= 0 && a->body[x] == b->body[y])
                        for (int k = 0; k < w->m.nd; k++) e += a->c[x][k] * b->u[y][k];
            worst = fmax(worst, fabs(lcp.M[(size_t)i * n + j] - e * W / g * d[i] * d[j]));
        }
        double qi = cn_mech_relative(&w->m, &w->rows[i], w->m.a0) / g * d[i];
        qworst = fmax(qworst, fabs(lcp.q[i] - qi));
    }
    for (int f = 0; f < Kf; f++) {
        int lam = nrows + f, c = w->contact_of_fric[f];
        for (int j = 0; j < n; j++) {
            double want = j == c ? w->mu[f] : j >= K + f * D && j < K + (f + 1) * D ? -1 : 0;
            other = fmax(other, fabs(lcp.M[(size_t)lam * n + j] - want));
            double col = j >= K + f * D && j < K + (f + 1) * D ? 1 : 0;
            if (j < nrows) other = fmax(other, fabs(lcp.M[(size_t)j * n + lam] - col));
        }
    }
    CHECK_MSG(worst <= 1e-13 * big, "%s: J M^-1 J^T off by %g (largest entry %g)", what, worst, big);
    CHECK_MSG(qworst <= 1e-13, "%s: q off by %g", what, qworst);
    CHECK_MSG(other == 0, "%s: E, -E^T or mu off by %g", what, other);
    CHECK_MSG(K > 0 && (some_frictionless ? Kf < K : Kf == K), "%s: %d contacts, %d with friction", what, K, Kf);
    cn_lcp_free(&lcp);
    free(d);
}

static void test_lcp_product(void) {
    Scene *stack = scene_new(3, 4, 0, 0, -9.81, 0.6);
    box(stack, "table", true, 0, (double[3]){-3, -3, -1}, (double[3]){3, 3, 0});
    box(stack, "A", false, 1, (double[3]){-1, -1, 0}, (double[3]){1, 1, 1});
    box(stack, "B", false, 2, (double[3]){-0.5, -0.7, 1}, (double[3]){1.5, 0.9, 1.5});
    box(stack, "C", false, 0.5, (double[3]){0, -0.2, 1.5}, (double[3]){0.8, 0.4, 2.5});
    double R[3][3], axis[3] = {0.48, 0.6, 0.64}; /* unit */
    rot_axis(R, axis, 30);
    Scene *turned = scene_posed(stack, R, 1.7, (double[3]){0.3, -2, 5}, NULL);
    char *json = scene_json(turned);
    int dirs[] = {3, 8, 13, 64};
    for (int k = 0; k < 4; k++) {
        Rig G;
        char what[64];
        snprintf(what, sizeof what, "turned stack, %d directions", dirs[k]);
        if (rig_open_json(&G, json, 0, dirs[k])) {
            check_lcp_product(&G, what, false);
            CHECK(G.w.D == dirs[k] && G.w.K >= 12);
        } else CHECK_MSG(0, "%s: not set up", what);
        rig_close(&G);
    }
    free(json);
    /* the same stack upright, A and B without friction between them: 4 contacts of 12 without
       friction rows */
    const char *mixed = "{\"dimension\": 3, \"friction\": 0.6, \"gravity\": [1.5, 0.4, -9.81], \"parts\": ["
                        "{\"name\": \"T\", \"fixed\": true, \"box\": {\"min\": [-3, -3, -1], \"max\": [3, 3, 0]}},"
                        "{\"name\": \"A\", \"box\": {\"min\": [-1, -1, 0], \"max\": [1, 1, 1]}},"
                        "{\"name\": \"B\", \"box\": {\"min\": [-0.5, -0.7, 1], \"max\": [1.5, 0.9, 1.5]}},"
                        "{\"name\": \"C\", \"box\": {\"min\": [0, -0.2, 1.5], \"max\": [0.8, 0.4, 2.5]}}],"
                        "\"friction_pairs\": [{\"parts\": [\"A\", \"B\"], \"mu\": 0}]}";
    Rig G;
    if (rig_open_json(&G, mixed, 0, 0)) {
        check_lcp_product(&G, "stack, one pair without friction", true);
        CHECK_MSG(G.w.K == 12 && G.w.Kf == 8, "%d contacts, %d with friction", G.w.K, G.w.Kf);
    } else CHECK_MSG(0, "mixed stack: not set up");
    rig_close(&G);
    Scene *s3 = overhang3(1.2, 0, 0, -9.81, 0.5), *s2 = lintel(0.5);
    if (rig_open(&G, s3, 0)) check_lcp_product(&G, "3-D box over an edge", false);
    rig_close(&G);
    if (rig_open(&G, s2, 0)) check_lcp_product(&G, "2-D lintel", false);
    rig_close(&G);
    scene_free(s3), scene_free(s2), scene_free(turned), scene_free(stack);
}

/* cn_ck_lp_failure and cn_ck_mass_span: an undecided LP is a numerical failure whose message
 * gives the LP's size and closest residual, or says GLPK stopped on an internal error; parts
 * of masses 1 and 1e9 (a span past 1e8) add the span to it, equal masses nothing. */
static void test_failure_message(void) {
    for (int v = 0; v < 2; v++) {
        Scene *s = scene_new(2, 3, 0, -9.81, 0, 0);
        rect(s, "table", true, 0, -4, -1, 4, 0);
        rect(s, "A", false, 1, -3, 0, -1, 1);
        rect(s, "B", false, v ? 1e9 : 1, 1, 0, 3, 1);
        Rig R;
        if (rig_open(&R, s, 0)) {
            char buf[256];
            const char *span = cn_ck_mass_span(&R.w, buf, sizeof buf);
            CHECK(v ? strstr(span, "a factor of 1e+09") != NULL : span[0] == '\0');
            LpAnswer ans = {.outcome = LP_UNDECIDED, .residual = 0.25, .rows = 6, .cols = 4};
            cnStatus st = cn_ck_lp_failure(&R.w, &ans, &R.d);
            CHECK(st == CN_ERR_NUMERIC && R.d.code == CN_ERR_NUMERIC);
            CHECK(strstr(R.d.message, "(6 rows, 4 columns)") != NULL);
            CHECK(strstr(R.d.message, "residual 0.25") != NULL);
            CHECK((strstr(R.d.message, "a factor of 1e+09") != NULL) == (v == 1));
            ans.glpk_error = true;
            st = cn_ck_lp_failure(&R.w, &ans, &R.d);
            CHECK(st == CN_ERR_NUMERIC && strstr(R.d.message, "internal error") != NULL);
            CHECK(strstr(R.d.message, "(6 rows, 4 columns)") != NULL);
        }
        rig_close(&R);
        scene_free(s);
    }
}

/* A tower of n unit-high blocks (mass 1) on a table, alternately 1 and 0.8 wide (every corner on
 * a face, none on a corner), the top one moved right by shift. */
#define TOWER_MAX 1000
static char tower_names[TOWER_MAX][12];
static Scene *tower(int n, double mu, double shift) {
    Scene *s = scene_new(2, n + 1, 0, -9.81, 0, mu);
    rect(s, "table", true, 0, -2, -1, 3, 0);
    for (int i = 0; i < n; i++) {
        snprintf(tower_names[i], sizeof tower_names[i], "b%d", i);
        double x0 = i % 2 ? 0.1 : 0, x1 = i % 2 ? 0.9 : 1, dx = i == n - 1 ? shift : 0;
        rect(s, tower_names[i], false, 1, x0 + dx, i, x1 + dx, i + 1);
    }
    return s;
}

/* LPs of 2,000 columns and more, which take the load descent and cairn's interior point first.
 * A frictionless tower of 1,000 stands: the joint under block i carries the n - i blocks above,
 * half on each of its two contacts (lever rule), found by the descent, by the interior point
 * without it, and by GLPK alone. Its top block moved 0.6 to the right (centre 0.2 past the
 * corner below) falls: the descent fails, and asked to defer the LP stops there; resumed (or
 * not deferred), the interior point's certificate is checked here, and wanted for its field only
 * the LP finds none. With friction (mu 0.5, 340 blocks: cone rows) the interior point's field
 * passes the checks here, the table carrying the whole weight. */
static void test_large(void) {
    const int n = 1000;
    const double g = 9.81;
    Scene *s = tower(n, 0, 0);
    unsigned routes[] = {0, CN_ROUTE_NO_LOAD_DESCENT, CN_ROUTE_LP_GLPK_ONLY};
    const char *methods[] = {"load descent", "interior point", "GLPK simplex"};
    for (int r = 0; r < 3; r++) {
        Rig R;
        if (rig_open(&R, s, routes[r])) {
            LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = true});
            check_field(&R, &ans, methods[r]);
            CHECK(ans.cols == 2 * n);
            const char *name = cn_lp_method_name(ans.method);
            CHECK_MSG(name && !strcmp(name, methods[r]), "method %s", name ? name : "none");
            double worst = 0;
            for (int c = 0; c < R.w.K; c++) {
                const cnContact *ct = &R.w.cs->items[c];
                int i = (int)lround(ct->point[1]); /* the joint under block i */
                worst = fmax(worst, fabs(R.w.lpforce[c] - (n - i) * g / 2));
            }
            CHECK_MSG(worst <= 1e-9 * n * g, "%s: lever rule off by %g", methods[r], worst);
        }
        rig_close(&R);
    }
    scene_free(s);
    s = tower(n, 0, 0.6);
    Rig R;
    if (rig_open(&R, s, 0)) {
        LpAnswer ans = rig_lp(&R, (LpAsk){.nofric = true, .defer_cert = true});
        CHECK(ans.outcome == LP_DEFERRED);
        ans = rig_lp(&R, (LpAsk){.nofric = true, .resumed = true});
        check_certificate(&R, &ans, "tower, resumed");
        if (ans.outcome == LP_CERTIFICATE && R.w.cert) check_cert_motion(&R, "tower, resumed");
        ans = rig_lp(&R, (LpAsk){.nofric = true});
        check_certificate(&R, &ans, "tower");
        ans = rig_lp(&R, (LpAsk){.nofric = true, .field_only = true});
        CHECK_MSG(ans.outcome == LP_ABSENT || ans.outcome == LP_CERTIFICATE, "field only: %d",
                  (int)ans.outcome);
    }
    rig_close(&R);
    scene_free(s);
    s = tower(340, 0.5, 0);
    if (rig_open(&R, s, 0)) {
        LpAnswer ans = rig_lp(&R, (LpAsk){0});
        check_field(&R, &ans, "tower with friction");
        CHECK(ans.cols >= 2000 && ans.rows == 3 * 340 + 2 * 340);
        CHECK_NEAR(pair_force(&R, "table", "b0"), 340 * g, 1e-9 * 340 * g);
    }
    rig_close(&R);
    scene_free(s);
}

/* A staircase of n blocks (mass 1, 1 x 1), block i shifted right by i * step over the one
 * below: frictionless, it stands while every partial stack's centre of mass is over the block
 * under it; its centres of mass spread sideways, so the whole's moment rows count. */
static Scene *stair(int n, double step) {
    Scene *s = scene_new(2, n + 1, 0, -9.81, 0, 0);
    rect(s, "table", true, 0, -2, -1, n * step + 3, 0);
    for (int i = 0; i < n; i++) {
        snprintf(tower_names[i], sizeof tower_names[i], "b%d", i);
        rect(s, tower_names[i], false, 1, i * step, i, i * step + 1, i + 1);
    }
    return s;
}

/* A 3-D running-bond wall of rows x cols bricks 2 x 1 x 1 (mass 2) on a slab, gravity [gx, 0, -9.81]. */
static Scene *wall3(int rows, int cols, double mu, double gx) {
    Scene *s = scene_new(3, rows * cols + 1, gx, 0, -9.81, mu);
    box(s, "slab", true, 0, (double[3]){-2, -2, -1}, (double[3]){2 * cols + 3, 3, 0});
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++) {
            int i = r * cols + c, x = 2 * c + (r % 2);
            snprintf(tower_names[i], sizeof tower_names[i], "r%dc%d", r, c);
            box(s, tower_names[i], false, 2, (double[3]){x, 0, r}, (double[3]){x + 2, 1, r + 1});
        }
    return s;
}

/* The whole assembly on its supports (equilibrium.c, whole_screen), before the interior point
 * of a large LP. A tower of 340 blocks (mu 0.5) under gravity turned 35 degrees (tan 0.70): the
 * whole slides on the table, and its rigid motion is the certificate, checked here as any other;
 * without the screen (CN_ROUTE_NO_WHOLE) the interior point's certificate says the same. Then,
 * frictionless, gravity turned by eps: the screen may say "no field" only where the interior
 * point finds none either (a field is verified to 1e-7 of each block's weight). */
/* Scene s (which sliding takes away) certified by the whole assembly, and by the interior point
 * without the screen. */
static void whole_certified(Scene *s, const char *what) {
    unsigned routes[] = {0, CN_ROUTE_NO_WHOLE};
    for (int r = 0; r < 2; r++) {
        Rig R;
        if (rig_open(&R, s, routes[r])) {
            LpAnswer ans = rig_lp(&R, (LpAsk){0});
            check_certificate(&R, &ans, what);
            CHECK_MSG(ans.method == (r ? CN_LP_METHOD_INTERIOR_POINT : CN_LP_METHOD_WHOLE), "%s, route %u: %s", what,
                      routes[r], cn_lp_method_name(ans.method) ? cn_lp_method_name(ans.method) : "none");
        }
        rig_close(&R);
    }
    scene_free(s);
}

/* Scene s's frictionless field-only answer, the same with and without the screen (s freed);
 * returns whether no field was found. */
static bool whole_same_field(Scene *s, const char *what, double turn) {
    LpOutcome out[2];
    for (int r = 0; r < 2; r++) {
        Rig R;
        out[r] = LP_UNDECIDED;
        if (rig_open(&R, s, (r ? CN_ROUTE_NO_WHOLE : 0) | CN_ROUTE_NO_LOAD_DESCENT))
            out[r] = rig_lp(&R, (LpAsk){.nofric = true, .field_only = true}).outcome;
        rig_close(&R);
    }
    CHECK_MSG(out[0] == out[1], "%s turned %g: %d with the screen, %d without", what, turn, (int)out[0], (int)out[1]);
    scene_free(s);
    return out[0] == LP_ABSENT;
}

static void test_whole(void) {
    const double g = 9.81, th = atan(0.7);
    Scene *s = tower(340, 0.5, 0);
    s->g[0] = g * sin(th), s->g[1] = -g * cos(th);
    whole_certified(s, "tower sliding");
    const double eps[] = {1e-9, 1e-8, 9e-8, 1e-7, 1.1e-7, 1.5e-7, 2e-7, 5e-7, 1e-6, 1e-5, 1e-3};
    int absent = 0;
    for (size_t k = 0; k < sizeof eps / sizeof eps[0]; k++) {
        s = tower(1000, 0, 0);
        s->g[0] = g * sin(eps[k]), s->g[1] = -g * cos(eps[k]);
        absent += whole_same_field(s, "tower", eps[k]);
    }
    CHECK_MSG(absent >= 4, "no field at %d of the turns", absent);
    /* the same on a staircase of 1,000 blocks leaning 0.4 to the right, turned either way */
    int sabsent = 0;
    for (size_t k = 0; k < 2 * (sizeof eps / sizeof eps[0]); k++) {
        double e = (k % 2 ? -1 : 1) * eps[k / 2];
        s = stair(1000, 4e-4);
        s->g[0] = g * sin(e), s->g[1] = -g * cos(e);
        sabsent += whole_same_field(s, "staircase", e);
    }
    CHECK_MSG(sabsent >= 8, "staircase: no field at %d of the turns", sabsent);
    /* 3-D: a wall of 8 x 15 bricks (mu 0.3) under gravity [5, 0, -9.81] slides on its slab, shown
     * by the whole (its summed rows carry the lever arms' rounding, which GLPK's automatic
     * scaling took for data: the certificate failed its check) */
    whole_certified(wall3(8, 15, 0.3, 5), "3-D wall sliding");
    printf("equilibrium: whole assembly: sliding tower and 3-D wall certified; no field at %d of 11 turns of a "
           "tower, %d of 22 of a staircase, as without it\n", absent, sabsent);
}

void test_equilibrium(void) {
    test_lintel_field();
    test_overhang_2d();
    test_incline_2d();
    test_box_3d();
    test_invariance();
    test_mass_ratio();
    test_cert_try();
    test_cert_motion();
    test_load_limit();
    test_closing();
    test_failure_message();
    test_lcp_product();
    test_large();
    test_whole();
}
