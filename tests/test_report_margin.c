/* Unit tests of src/report/report_margin.c: the report of the margins, read back. A 2 x 1 block
 * on a 20 degree incline at mu 0.5 (gravity turned), by hand: critical friction tan 20 = 0.36397,
 * tilt atan 0.5 - 20 degrees = 6.5651, lateral factor tan(atan 0.5 - 20 degrees) = 0.115086 g
 * downhill. The JSON (parsed with jansson) carries the typed result's values (to its printed
 * digits), brackets, verdict counts and mechanisms (the block sliding on the slope); the text
 * names each margin with its value; margins not asked for are null. */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "report_capture.h"

static bool near_rel(double x, double y, double tol) { return fabs(x - y) <= tol * fmax(1e-300, fabs(y)); }

/* The mechanism of a margin's JSON: the block moves, sliding on the slope. */
static bool block_slides(const json_t *m) {
    json_t *mech = json_object_get(m, "mechanism"), *mp = json_object_get(mech, "moving_parts");
    json_t *sl = json_array_get(json_object_get(mech, "sliding"), 0);
    return json_array_size(mp) == 1 && !strcmp(str(json_array_get(mp, 0), "part"), "block") &&
           !strcmp(json_string_value(json_array_get(sl, 0)), "slope") &&
           !strcmp(json_string_value(json_array_get(sl, 1)), "block");
}

void test_report_margin(void) {
    double th = 20 * acos(-1.0) / 180, hand[3] = {tan(th), atan(0.5) - th, tan(atan(0.5) - th)};
    char json[512];
    scene_incline_2d(json, sizeof json, 0.5);
    cnAssembly *a = load_ok(json);
    if (!a) return;
    cnMarginOptions o = cn_margin_options_default();
    cnMarginResult r;
    cnDiag d;
    CHECK(cn_margin(a, &o, &r, &d) == CN_OK);
    CHECK(near_rel(r.friction.value, hand[0], 1e-6) && near_rel(r.tilt.value, hand[1], 1e-6) &&
          near_rel(r.lateral.value, hand[2], 1e-6));
    char *buf = NULL;
    CAPTURE(buf, cn_report_margin(f, a, &r, 1));
    json_error_t err;
    json_t *j = buf ? json_loads(buf, 0, &err) : NULL;
    CHECK_MSG(j, "margin JSON does not parse: %s", buf ? err.text : "no output");
    if (j) {
        json_t *fr = json_object_get(j, "friction"), *ti = json_object_get(j, "tilt"), *la = json_object_get(j, "lateral");
        CHECK(!strcmp(str(j, "verdict"), "stable") && num(j, "dimension") == 2);
        CHECK(near_rel(num(j, "critical_friction"), r.friction.value, 1e-9) &&
              near_rel(num(fr, "critical"), r.friction.value, 1e-9) && num(fr, "as_loaded") == 0.5);
        CHECK(!strcmp(str(fr, "end"), "found") && near_rel(num(fr, "not_stable_at"), r.friction.past, 1e-9) &&
              num(fr, "verdicts") == r.friction.verdicts && json_is_false(json_object_get(fr, "stopped")));
        CHECK_MSG(near_rel(num(ti, "angle"), r.tilt.value * 180 / acos(-1.0), 1e-9), "tilt %g degrees",
                  num(ti, "angle"));
        CHECK(near_rel(num(la, "factor"), r.lateral.value, 1e-9));
        json_t *dir = json_object_get(la, "direction");
        CHECK(near_rel(json_number_value(json_array_get(dir, 0)), r.lateral.dir[0], 1e-9) &&
              near_rel(json_number_value(json_array_get(dir, 1)), r.lateral.dir[1], 1e-9));
        CHECK(block_slides(fr) && block_slides(ti) && block_slides(la));
        json_decref(j);
    }
    free(buf);
    buf = NULL;
    CAPTURE(buf, cn_report_margin(f, a, &r, 0));
    CHECK_MSG(buf && strstr(buf, "as loaded: STABLE") && strstr(buf, "critical friction: 0.36397") &&
                  strstr(buf, "tilt: 6.565") && strstr(buf, "lateral: 0.11508"),
              "text: %s", buf ? buf : "");
    free(buf);
    cn_margin_result_free(&r);
    /* the lateral factor alone: the others null */
    o.kinds = CN_MARGIN_LATERAL;
    CHECK(cn_margin(a, &o, &r, &d) == CN_OK);
    buf = NULL;
    CAPTURE(buf, cn_report_margin(f, a, &r, 1));
    json_t *k = buf ? json_loads(buf, 0, &err) : NULL;
    CHECK_MSG(k && !json_is_object(json_object_get(k, "friction")) && !json_is_object(json_object_get(k, "tilt")) &&
                  json_is_object(json_object_get(k, "lateral")),
              "%s", buf ? buf : "");
    json_decref(k);
    free(buf);
    cn_margin_result_free(&r);
    cn_assembly_free(a);
}
