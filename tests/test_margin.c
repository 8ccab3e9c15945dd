/* Margins against hand calculations: a block on an incline (critical friction tan(theta), tilt
 * atan(mu) - theta, lateral factor tan of that), a block on a table (lateral min(mu, b/h), tilt
 * atan of it), a two-block stack (the top block tips first), a ladder against a frictionless
 * wall (critical friction by moments about its foot), their 3-D extrusions along given
 * axes; invariance under turning, scaling and moving the whole scene with its gravity, and
 * under reordering its parts; the ends of the ranges and bad options. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include <valgrind/valgrind.h>

#include "helpers.h"
#include "cairn/cairn.h"
#include "check_limit.h"

#define DEG (180 / 3.14159265358979323846)
/* Margins are bisected to 1e-7 relative; the verdicts' motion threshold (1e-9 g) blurs them
 * far less. */
#define REL 1e-6

/* A flat block (4 x 0.5) resting on an incline of theta degrees rising to the right, the whole
 * turned by `turn` degrees with its gravity, scaled by s and moved by (dx, dy); the block first
 * or second. */
static char *incline2(double theta, double mu, double turn, double s, double dx, double dy, bool block_first) {
    double t = theta / DEG, q = turn / DEG, c = cos(t), sn = sin(t);
    double tab[4][2] = {{-10 * c, -10 * sn}, {10 * c, 10 * sn}, {10 * c, -10}, {-10 * c, -10}};
    double blk[4][2] = {{-2, 0}, {2, 0}, {2, 0.5}, {-2, 0.5}};
    char parts[2][512];
    for (int w = 0; w < 2; w++) {
        double (*P)[2] = w ? blk : tab;
        int n = snprintf(parts[w], sizeof parts[w], "{\"name\":\"%s\",%s\"polygon\":[", w ? "block" : "incline",
                         w ? "" : "\"fixed\":true,");
        for (int k = 0; k < 4; k++) {
            double x = P[k][0], y = P[k][1];
            if (w) { /* the block on the slope */
                double xr = x * c - y * sn, yr = x * sn + y * c;
                x = xr, y = yr;
            }
            double X = s * (x * cos(q) - y * sin(q)) + dx, Y = s * (x * sin(q) + y * cos(q)) + dy;
            n += snprintf(parts[w] + n, sizeof parts[w] - (size_t)n, "%s[%.17g,%.17g]", k ? "," : "", X, Y);
        }
        snprintf(parts[w] + n, sizeof parts[w] - (size_t)n, "]}");
    }
    char *buf = malloc(2048);
    snprintf(buf, 2048, "{\"dimension\":2,\"gravity\":[%.17g,%.17g],\"friction\":%g,\"parts\":[%s,%s]}",
             9.81 * sin(q), -9.81 * cos(q), mu, parts[block_first ? 1 : 0], parts[block_first ? 0 : 1]);
    return buf;
}

static bool margins(const char *json, const cnMarginOptions *o, cnMarginResult *r) {
    cnAssembly *a = load_ok(json);
    memset(r, 0, sizeof *r);
    if (!a) return false;
    cnDiag d;
    cnStatus st = cn_margin(a, o, r, &d);
    cn_assembly_free(a);
    CHECK_MSG(st == CN_OK, "cn_margin: %s: %s", d.where, d.message);
    return st == CN_OK;
}

static void test_incline(void) {
    for (int v = 0; v < (RUNNING_ON_VALGRIND ? 2 : 4); v++) {
        /* as loaded, then turned 37 degrees with its gravity, scaled by 1e-3 and moved far,
           then with the block listed first, then scaled by 1e3 */
        double turn = v == 1 ? 37 : 0, s = v == 1 ? 1e-3 : v == 3 ? 1e3 : 1;
        char *json = incline2(20, 0.4, turn, s, v == 1 ? 1e3 : 0, v == 1 ? -5e2 : 0, v == 2);
        cnMarginOptions o = cn_margin_options_default();
        cnMarginResult r;
        if (margins(json, &o, &r)) {
            double crit = tan(20 / DEG), tilt = atan(0.4) * DEG - 20;
            CHECK(r.verdict == CN_VERDICT_STABLE);
            CHECK(r.friction.end == CN_MARGIN_FOUND && r.tilt.end == CN_MARGIN_FOUND && r.lateral.end == CN_MARGIN_FOUND);
            CHECK_NEAR(r.friction.value, crit, REL * crit);
            CHECK(r.friction.past < r.friction.value && r.friction.past_verdict != CN_VERDICT_STABLE);
            CHECK_NEAR(r.tilt.value * DEG, tilt, REL * tilt);
            CHECK_NEAR(r.lateral.value, tan(tilt / DEG), REL * tan(tilt / DEG));
            /* downhill: gravity turned clockwise, the lateral force pointing down the slope
               (to -x before the scene is turned) */
            CHECK(r.tilt.dir[2] == -1);
            double q = turn / DEG;
            CHECK_NEAR(r.lateral.dir[0], -cos(q), 1e-9);
            CHECK_NEAR(r.lateral.dir[1], -sin(q), 1e-9);
            /* the mechanism: the block slides on the incline */
            CHECK(r.lateral.collapse.nmoving == 1);
            CHECK(r.friction.verdicts + r.tilt.verdicts + r.lateral.verdicts < 200);
        }
        cn_margin_result_free(&r);
        free(json);
    }
    /* friction of the one pair: the same; as loaded below it, no tilt or lateral margin */
    char *json = incline2(20, 0.2, 0, 1, 0, 0, false);
    cnAssembly *a = load_ok(json);
    cnMarginOptions o = cn_margin_options_default();
    o.pair[0] = cn_assembly_find_part(a, "block"), o.pair[1] = cn_assembly_find_part(a, "incline");
    cn_assembly_free(a);
    cnMarginResult r;
    if (margins(json, &o, &r)) {
        CHECK(r.verdict == CN_VERDICT_UNSTABLE);
        CHECK_NEAR(r.friction.value, tan(20 / DEG), REL);
        CHECK_NEAR(r.friction.base, 0.2, 0);
        CHECK(r.tilt.end == CN_MARGIN_NONE && r.tilt.value == 0);
        CHECK(r.lateral.end == CN_MARGIN_NONE && r.lateral.value == 0);
    }
    cn_margin_result_free(&r);
    free(json);
    /* no default friction, the pair's 0.4: every coefficient scaled together is that one's */
    json = incline2(20, 0, 0, 1, 0, 0, false);
    char *with_pair = malloc(strlen(json) + 128);
    char *parts = strstr(json, "\"parts\"");
    snprintf(with_pair, strlen(json) + 128, "%.*s\"friction_pairs\":[{\"parts\":[\"block\",\"incline\"],\"mu\":0.4}],%s",
             (int)(parts - json), json, parts);
    o = cn_margin_options_default();
    o.kinds = CN_MARGIN_FRICTION;
    if (margins(with_pair, &o, &r)) {
        CHECK(r.friction.end == CN_MARGIN_FOUND);
        CHECK_NEAR(r.friction.value, tan(20 / DEG), REL);
        CHECK_NEAR(r.friction.base, 0.4, 0);
    }
    cn_margin_result_free(&r);
    /* a given axis however small its components: the counter-clockwise turn lifts the block's
       uphill end: it slides when gravity has turned atan(0.4) + 20 degrees */
    o = cn_margin_options_default();
    o.kinds = CN_MARGIN_TILT;
    o.axis[2] = 1e-200;
    if (margins(json, &o, &r)) CHECK(r.verdict == CN_VERDICT_UNSTABLE); /* mu 0 */
    cn_margin_result_free(&r);
    free(json);
    free(with_pair);
    json = incline2(20, 0.4, 0, 1, 0, 0, false);
    if (margins(json, &o, &r)) {
        CHECK(r.tilt.dir[2] == 1);
        CHECK_NEAR(r.tilt.value * DEG, atan(0.4) * DEG + 20, REL * 42);
    }
    cn_margin_result_free(&r);
    free(json);
}

/* A block b wide and h high on a table (2-D), or its extrusion 1.5 deep (3-D). */
static char *on_table(int dim, double b, double h, double mu) {
    char *buf = malloc(1024);
    if (dim == 2)
        snprintf(buf, 1024,
                 "{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":%g,\"parts\":["
                 "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                 "{\"name\":\"block\",\"polygon\":[[0,0],[%g,0],[%g,%g],[0,%g]]}]}",
                 mu, b, b, h, h);
    else
        snprintf(buf, 1024,
                 "{\"dimension\":3,\"gravity\":[0,0,-9.81],\"friction\":%g,\"parts\":["
                 "{\"name\":\"table\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}},"
                 "{\"name\":\"block\",\"box\":{\"min\":[0,0,0],\"max\":[%g,1.5,%g]}}]}",
                 mu, b, h);
    return buf;
}

static void test_table(void) {
    for (int dim = 2; dim <= 3; dim++)
        for (int k = 0; k < (RUNNING_ON_VALGRIND && dim == 3 ? 1 : 2); k++) {
            double mu = k ? 0.3 : 0.8, lat = fmin(mu, 0.5); /* b / h = 1 / 2 */
            char *json = on_table(dim, 1, 2, mu);
            cnMarginOptions o = cn_margin_options_default();
            if (dim == 3) { /* along x, a direction of the friction pyramid (exactly mu there) */
                o.axis[1] = 1;
                o.direction[0] = 1;
            }
            cnMarginResult r;
            if (margins(json, &o, &r)) {
                CHECK(r.friction.end == CN_MARGIN_WHOLE && r.friction.value == 0);
                CHECK_NEAR(r.lateral.value, lat, REL * lat);
                CHECK_NEAR(r.tilt.value, atan(lat), REL * atan(lat));
                /* tipping opens the block's contacts with the table; sliding keeps them */
                bool opens = false;
                for (int i = 0; i < r.lateral.collapse.contacts.count; i++) opens |= r.lateral.collapse.contact[i].separates;
                CHECK(opens == (k == 0));
            }
            cn_margin_result_free(&r);
            free(json);
        }
    /* 3-D, the weakest direction: tipping over the narrow side (lateral 0.5 along +-x); a scan
       of about 100 verdicts, left out under valgrind */
    char *json = on_table(3, 1, 2, 0.8);
    cnMarginOptions o = cn_margin_options_default();
    o.kinds = CN_MARGIN_LATERAL;
    cnMarginResult r;
    memset(&r, 0, sizeof r);
    if (!RUNNING_ON_VALGRIND && margins(json, &o, &r)) {
        CHECK_NEAR(r.lateral.value, 0.5, REL * 0.5);
        CHECK_NEAR(fabs(r.lateral.dir[0]), 1, 1e-6);
        CHECK(!r.friction.computed && !r.tilt.computed);
    }
    cn_margin_result_free(&r);
    free(json);
    /* the same block turned 10 degrees about the vertical: its weakest direction is its narrow
       side's normal, between the scan's azimuths (every 22.5 degrees), found by the searches
       about the weakest (left out under valgrind) */
    if (!RUNNING_ON_VALGRIND) {
        double c10 = cos(10 / DEG), s10 = sin(10 / DEG);
        char hull[512];
        int n = 0;
        for (int v = 0; v < 8; v++) {
            double x = v & 1 ? 1 : 0, y = v & 2 ? 1.5 : 0, z = v & 4 ? 2 : 0;
            n += snprintf(hull + n, sizeof hull - (size_t)n, "%s[%.17g,%.17g,%g]", v ? "," : "", x * c10 - y * s10,
                          x * s10 + y * c10, z);
        }
        char *turned = malloc(1024);
        snprintf(turned, 1024,
                 "{\"dimension\":3,\"gravity\":[0,0,-9.81],\"friction\":0.8,\"parts\":["
                 "{\"name\":\"table\",\"fixed\":true,\"box\":{\"min\":[-5,-5,-1],\"max\":[5,5,0]}},"
                 "{\"name\":\"block\",\"hull\":[%s]}]}",
                 hull);
        o = cn_margin_options_default();
        o.kinds = CN_MARGIN_LATERAL;
        if (margins(turned, &o, &r)) {
            CHECK_NEAR(r.lateral.value, 0.5, REL * 0.5);
            CHECK_NEAR(fabs(r.lateral.dir[0]), c10, 1e-3);
            CHECK_NEAR(fabs(r.lateral.dir[1]), s10, 1e-3);
            /* the pattern searches compare directions by their static limits (the statics give
               way here): the scan's verdicts and the bracket's, not one a direction tried */
            CHECK_MSG(r.lateral.verdicts <= 40, "%d verdicts", r.lateral.verdicts);
        }
        cn_margin_result_free(&r);
        free(turned);
    }
    /* a block whose weight falls outside its base: no friction makes it stand */
    json = strdup("{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":0.5,\"parts\":["
                  "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                  "{\"name\":\"leaner\",\"polygon\":[[0,0],[1,0],[4,3],[3,3]]}]}");
    o = cn_margin_options_default();
    o.kinds = CN_MARGIN_FRICTION;
    if (margins(json, &o, &r)) {
        CHECK(r.friction.end == CN_MARGIN_NONE && isinf(r.friction.value));
        CHECK(r.friction.collapse.nmoving == 1);
    }
    cn_margin_result_free(&r);
    free(json);
}

/* A block 2 wide and 1 high on the table, a block 1 wide and 2 high centred on it: the top one
 * tips at 0.5 g (b / h of its own), before the column (base half-width 1 over its centre of
 * mass at 1.25: 0.8 g) and before anything slides (mu 1). */
static void test_stack(void) {
    const char *json = "{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":1,\"parts\":["
                       "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                       "{\"name\":\"base\",\"polygon\":[[-1,0],[1,0],[1,1],[-1,1]]},"
                       "{\"name\":\"top\",\"polygon\":[[-0.5,1],[0.5,1],[0.5,3],[-0.5,3]]}]}";
    cnMarginOptions o = cn_margin_options_default();
    o.kinds = CN_MARGIN_LATERAL | CN_MARGIN_TILT;
    cnMarginResult r;
    if (margins(json, &o, &r)) {
        CHECK_NEAR(r.lateral.value, 0.5, REL * 0.5);
        CHECK_NEAR(r.tilt.value, atan(0.5), REL);
        cnAssembly *a = load_ok(json);
        const cnCheckResult *c = &r.lateral.collapse;
        CHECK(a && c->nmoving >= 1 && c->part[cn_assembly_find_part(a, "top")].moves);
        cn_assembly_free(a);
    }
    cn_margin_result_free(&r);
    /* friction between the two blocks only, 0.3: the top block slides off at 0.3 g */
    o.kinds = CN_MARGIN_LATERAL;
    const char *json2 = "{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":1,"
                        "\"friction_pairs\":[{\"parts\":[\"base\",\"top\"],\"mu\":0.3}],\"parts\":["
                        "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]},"
                        "{\"name\":\"base\",\"polygon\":[[-1,0],[1,0],[1,1],[-1,1]]},"
                        "{\"name\":\"top\",\"polygon\":[[-1,1],[1,1],[1,1.5],[-1,1.5]]}]}";
    if (margins(json2, &o, &r)) CHECK_NEAR(r.lateral.value, 0.3, REL * 0.3);
    cn_margin_result_free(&r);
}

/* A ladder (4 long, 0.05 thick) leaning 60 degrees on a frictionless wall: by moments about its
 * foot, the wall pushes H = W (x_c - x_foot) / (y_top - y_foot), which the floor's friction must
 * match: the critical friction of the floor pair is (x_c - x_foot) / (y_top - y_foot) (about
 * cot 60 / 2 = 0.2887 for a thin ladder). */
static void test_ladder(void) {
    double th = 60 / DEG, L = 4, t = 0.05, c = cos(th), sn = sin(th);
    /* the ladder's corners: foot (0, 0), along (c, sn), across (-sn, c) * t (towards the wall is +x) */
    double P[4][2] = {{0, 0}, {L * c, L * sn}, {L * c - t * sn, L * sn + t * c}, {-t * sn, t * c}};
    double xw = L * c; /* the wall's face through the top corner */
    double xc = 0.5 * (L * c - t * sn), yc = 0.5 * (L * sn + t * c);
    double crit = (xc - P[0][0]) / (P[1][1] - P[0][1]);
    char json[2048];
    snprintf(json, sizeof json,
             "{\"dimension\":2,\"gravity\":[0,-9.81],\"friction\":0.5,"
             "\"friction_pairs\":[{\"parts\":[\"ladder\",\"wall\"],\"mu\":0}],\"parts\":["
             "{\"name\":\"floor\",\"fixed\":true,\"polygon\":[[-3,-1],[%.17g,-1],[%.17g,0],[-3,0]]},"
             "{\"name\":\"wall\",\"fixed\":true,\"polygon\":[[%.17g,0],[%.17g,0],[%.17g,5],[%.17g,5]]},"
             "{\"name\":\"ladder\",\"polygon\":[[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g],[%.17g,%.17g]]}]}",
             xw, xw, xw, xw + 1, xw + 1, xw, P[0][0], P[0][1], P[1][0], P[1][1], P[2][0], P[2][1], P[3][0], P[3][1]);
    (void)yc;
    cnAssembly *a = load_ok(json);
    if (!a) return;
    cnMarginOptions o = cn_margin_options_default();
    o.kinds = CN_MARGIN_FRICTION;
    o.pair[0] = cn_assembly_find_part(a, "ladder"), o.pair[1] = cn_assembly_find_part(a, "floor");
    cn_assembly_free(a);
    cnMarginResult r;
    if (margins(json, &o, &r)) {
        CHECK(r.verdict == CN_VERDICT_STABLE);
        CHECK(r.friction.end == CN_MARGIN_FOUND);
        CHECK_NEAR(r.friction.value, crit, REL * crit);
        CHECK_NEAR(crit, 0.5 / tan(th), 0.01); /* the thin-ladder formula, roughly */
    }
    cn_margin_result_free(&r);
}

static void test_bad_options(void) {
    char *json = on_table(3, 1, 2, 0.8);
    cnAssembly *a = load_ok(json);
    free(json);
    if (!a) return;
    cnMarginOptions o = cn_margin_options_default();
    o.axis[2] = 1; /* along gravity */
    cnMarginResult r;
    cnDiag d;
    CHECK(cn_margin(a, &o, &r, &d) == CN_ERR_INPUT && !strcmp(d.where, "axis"));
    cn_margin_result_free(&r);
    o = cn_margin_options_default();
    o.pair[0] = 1, o.pair[1] = 1;
    CHECK(cn_margin(a, &o, &r, &d) == CN_ERR_INPUT && !strcmp(d.where, "pair"));
    cn_margin_result_free(&r);
    o = cn_margin_options_default();
    o.kinds = 8;
    CHECK(cn_margin(a, &o, &r, &d) == CN_ERR_INPUT);
    cn_margin_result_free(&r);
    cn_assembly_free(a);
}

/* The static limit (the equilibrium LP with a column for the load factor) of the incline's
 * block: a horizontal acceleration a g downhill slides it when a cos + sin > mu (cos - a sin),
 * so a = tan(atan mu - theta), and uphill tan(atan mu + theta) (the flat block does not tip);
 * the scene turned with its gravity and scaled gives the same; a load along gravity adds weight
 * and never limits (the cap), one against it lifts the block at exactly 1 g. */
static void test_static_limit(void) {
    for (int v = 0; v < 3; v++) {
        double turn = v == 1 ? 37 : 0, s = v == 2 ? 1e3 : 1;
        char *json = incline2(20, 0.4, turn, s, v == 1 ? 1e3 : 0, 0, v == 2);
        cnAssembly *a = load_ok(json);
        free(json);
        if (!a) continue;
        double q = turn / DEG, g = 9.81, th = 20 / DEG, mu = 0.4;
        double down[3] = {-g * cos(q), -g * sin(q), 0}, up[3] = {g * cos(q), g * sin(q), 0};
        double heavier[3] = {g * sin(q), -g * cos(q), 0}, lighter[3] = {-g * sin(q), g * cos(q), 0};
        double t[4];
        cnDiag d;
        CHECK(cn_check_load_limit(a, NULL, down, 1e3, &t[0], &d) == CN_OK);
        CHECK(cn_check_load_limit(a, NULL, up, 1e3, &t[1], &d) == CN_OK);
        CHECK(cn_check_load_limit(a, NULL, heavier, 1e3, &t[2], &d) == CN_OK);
        CHECK(cn_check_load_limit(a, NULL, lighter, 1e3, &t[3], &d) == CN_OK);
        double want_down = tan(atan(mu) - th), want_up = tan(atan(mu) + th);
        CHECK_MSG(fabs(t[0] - want_down) <= 1e-9 * want_down, "downhill %.12g, by hand %.12g", t[0], want_down);
        CHECK_MSG(fabs(t[1] - want_up) <= 1e-9 * want_up, "uphill %.12g, by hand %.12g", t[1], want_up);
        CHECK_MSG(t[2] == 1e3, "along gravity: up to the cap, %g", t[2]);
        CHECK_MSG(fabs(t[3] - 1) <= 1e-9, "against gravity: 1, %.12g", t[3]);
        cn_assembly_free(a);
        /* a static field exists from friction tan(theta) up (the LP's 1e-7 residual aside) */
        for (int k = 0; k < 2; k++) {
            char *js = incline2(20, tan(th) * (k ? 1 + 1e-5 : 1 - 1e-5), turn, s, 0, 0, v == 2);
            cnAssembly *b = load_ok(js);
            free(js);
            int has = -1;
            if (b) CHECK(cn_check_has_field(b, NULL, &has, &d) == CN_OK);
            CHECK_MSG(has == k, "friction tan 20 %s 1e-5: field %d", k ? "plus" : "minus", has);
            cn_assembly_free(b);
        }
    }
}

void test_margin(void) {
    test_static_limit();
    test_incline();
    test_table();
    test_stack();
    test_ladder();
    test_bad_options();
}
