/* Unit tests of src/report/report_sim.c: the report of a simulation, read back. The simulation is sim_scenes.h's A slid out from under B (B tips from
 * s = 0.5), run as a disassembly and as an assembly: its JSON (parsed with jansson) says what the
 * typed results say (verdict, mode, each step's status, path length, samples, the onset's time,
 * distance and moving part, the contacts that open and slide), and its text names the verdict, the
 * step and the part that moves. */
#include "report_capture.h"
#include "sim_scenes.h"

static void test_sim_report(void) {
    cnAssembly *a = load_ok(SIM_SLIDE_OUT);
    if (!a) return;
    cnSimOptions o = cn_sim_options_default();
    cnSimResult dis, as;
    cnDiag d;
    CHECK(cn_simulate(a, &o, &dis, &d) == CN_OK);
    o.assemble = true;
    CHECK(cn_simulate(a, &o, &as, &d) == CN_OK);
    const cnStepResult *st = &dis.steps[0];
    CHECK(!dis.stable && st->status == CN_STEP_UNSTABLE && st->has_onset);
    char *buf = NULL;
    CAPTURE(buf, cn_report_sim(f, a, &dis, NULL, 1));
    json_error_t err;
    json_t *j = buf ? json_loads(buf, 0, &err) : NULL;
    CHECK_MSG(j, "simulation JSON does not parse: %s", buf ? err.text : "no output");
    if (j) {
        CHECK(json_is_false(json_object_get(j, "stable")) && !strcmp(str(j, "verdict"), "unstable") &&
              !strcmp(str(j, "mode"), "disassembly") && num(j, "format_version") == CN_JSON_FORMAT_VERSION);
        json_t *s0 = json_array_get(json_object_get(j, "steps"), 0);
        CHECK(json_array_size(json_object_get(j, "steps")) == 1 && s0);
        CHECK(!strcmp(str(s0, "status"), "unstable") && !strcmp(str(s0, "support"), "hold") &&
              num(s0, "path_length") == 2 && num(s0, "samples") == st->nsamples);
        CHECK(!strcmp(json_string_value(json_array_get(json_object_get(s0, "move"), 0)), "A"));
        json_t *u = json_object_get(s0, "unstable_at");
        CHECK(u && fabs(num(u, "time") - st->onset_time) <= 1e-9 && fabs(num(u, "distance") - 0.5) <= 1e-5);
        json_t *mp = json_object_get(u, "moving_parts");
        CHECK(json_array_size(mp) == 1 && !strcmp(json_string_value(json_array_get(mp, 0)), "B"));
        CHECK(json_array_size(json_object_get(u, "separating_contacts")) >= 1);
        json_decref(j);
    }
    free(buf);
    buf = NULL;
    CAPTURE(buf, cn_report_sim(f, a, &dis, &as, 0));
    CHECK_MSG(buf && strstr(buf, "UNSTABLE") && strstr(buf, "B moves") && strstr(buf, "move A"), "text: %s",
              buf ? buf : "");
    free(buf);
    buf = NULL;
    CAPTURE(buf, cn_report_sim(f, a, &dis, &as, 1));
    j = buf ? json_loads(buf, 0, &err) : NULL;
    CHECK(j && json_object_get(j, "steps"));
    json_decref(j);
    free(buf);
    cn_sim_result_free(&dis);
    cn_sim_result_free(&as);
    cn_assembly_free(a);
}

void test_report_sim(void) {
    test_sim_report();
}
