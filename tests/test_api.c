/* The builder and cn_run_json: an assembly built call by call is the assembly its file would
 * load (the same parts, masses, contacts, verdict and forces), the builder's problems are named
 * by the file's JSON paths, and the JSON a command returns says what the C call says. */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "cairn/figure.h"
#include "helpers.h"

#define PI 3.14159265358979323846

#define TABLE_FILE "{\"name\":\"table\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]}"

static const double TABLE[] = {-5, -1, 5, -1, 5, 0, -5, 0};

/* Two blocks on a table, B on A and over A's edge with its centre over A, with friction 0.3, a
 * lighter B and a plan that lifts B. */
static cnBuilder *two_blocks(void) {
    cnBuilder *b = cn_builder_new(2);
    CHECK(b != NULL);
    if (!b) return NULL;
    CHECK(cn_builder_set_name(b, "two blocks") == CN_OK);
    CHECK(cn_builder_set_gravity(b, (double[]){0, -10}) == CN_OK);
    CHECK(cn_builder_set_friction(b, 0.3) == CN_OK);
    CHECK(cn_builder_add_polygon(b, "table", 4, TABLE, true) == CN_OK);
    CHECK(cn_builder_add_polygon(b, "A", 4, (double[]){0, 0, 2, 0, 2, 1, 0, 1}, false) == CN_OK);
    CHECK(cn_builder_add_polygon(b, "B", 4, (double[]){1, 1, 2.5, 1, 2.5, 2, 1, 2}, false) == CN_OK);
    CHECK(cn_builder_set_part_density(b, 0.5) == CN_OK);
    cnSegment up = {.kind = CN_SEGMENT_MOVE, .move = {0, 3, 0}};
    CHECK(cn_builder_add_step(b, 1, (const char *const[]){"B"}, 1, &up, CN_SUPPORT_HOLD) == CN_OK);
    return b;
}

static const char *TWO_BLOCKS_FILE =
    "{\"name\":\"two blocks\",\"dimension\":2,\"gravity\":[0,-10],\"friction\":0.3,\"parts\":[" TABLE_FILE ","
    "{\"name\":\"A\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
    "{\"name\":\"B\",\"density\":0.5,\"polygon\":[[1,1],[2.5,1],[2.5,2],[1,2]]}],"
    "\"plan\":[{\"move\":\"B\",\"path\":[[0,3]]}]}";

/* The same assembly: parts, masses, centres, plan; then the same check, contact by contact. */
static void same_assembly(const cnAssembly *x, const cnAssembly *y) {
    CHECK(x->dim == y->dim && x->nparts == y->nparts && x->nsteps == y->nsteps);
    CHECK(x->friction == y->friction && x->gravity[1] == y->gravity[1]);
    CHECK(x->name && y->name && !strcmp(x->name, y->name));
    for (int i = 0; i < x->nparts && i < y->nparts; i++) {
        CHECK(!strcmp(x->parts[i].name, y->parts[i].name));
        CHECK(x->parts[i].fixed == y->parts[i].fixed);
        CHECK_MSG(x->parts[i].mass == y->parts[i].mass, "part %d mass %g vs %g", i, x->parts[i].mass, y->parts[i].mass);
        for (int k = 0; k < 3; k++) CHECK(x->parts[i].com[k] == y->parts[i].com[k]);
    }
    cnCheckResult rx, ry;
    cnDiag d;
    CHECK(cn_check(x, NULL, &rx, &d) == CN_OK);
    CHECK(cn_check(y, NULL, &ry, &d) == CN_OK);
    CHECK(rx.stable == ry.stable && rx.verdict == ry.verdict);
    CHECK(rx.contacts.count == ry.contacts.count);
    for (int c = 0; c < rx.contacts.count && c < ry.contacts.count; c++)
        CHECK(rx.contact[c].normal_force == ry.contact[c].normal_force);
    cn_check_result_free(&rx);
    cn_check_result_free(&ry);
}

static void test_builder_equals_file(void) {
    cnBuilder *b = two_blocks();
    cnAssembly *built = NULL, *loaded = load_ok(TWO_BLOCKS_FILE), *again = NULL;
    cnDiag d;
    CHECK_MSG(b && cn_builder_finish(b, &built, &d) == CN_OK, "finish: %s: %s", d.where, d.message);
    if (built && loaded) {
        same_assembly(built, loaded);
        CHECK(built->parts[2].mass == 0.75); /* 1.5 x 1 at density 0.5 */
        CHECK(built->nsteps == 1 && built->plan[0].nseg == 1 && built->plan[0].seg[0].move[1] == 3);
    }
    /* the builder's own JSON text loads to the same assembly */
    char *text = b ? cn_builder_json(b) : NULL;
    CHECK(text != NULL);
    if (text && loaded) {
        again = load_ok(text);
        if (again) same_assembly(again, loaded);
    }
    cn_string_free(text);
    cn_assembly_free(again);
    cn_assembly_free(built);
    cn_assembly_free(loaded);
    cn_builder_free(b);
}

/* A 3-D part of two hull pieces (an L of two boxes), a box table, a turn in the plan: the
 * builder's "hulls" and {"rotate", "axis", "about"} are the file's. */
static void test_builder_3d(void) {
    cnBuilder *b = cn_builder_new(3);
    if (!b) return;
    CHECK(cn_builder_add_box(b, "floor", (double[]){-5, -5, -1}, (double[]){5, 5, 0}, true) == CN_OK);
    double p1[] = {0, 0, 0, 2, 0, 0, 2, 1, 0, 0, 1, 0, 0, 0, 1, 2, 0, 1, 2, 1, 1, 0, 1, 1};
    double p2[] = {0, 0, 1, 1, 0, 1, 1, 1, 1, 0, 1, 1, 0, 0, 3, 1, 0, 3, 1, 1, 3, 0, 1, 3};
    CHECK(cn_builder_add_hull(b, "L", 8, p1, false) == CN_OK);
    CHECK(cn_builder_add_piece(b, 8, p2) == CN_OK);
    /* a posed box: a small box turned 30 degrees about z, set on the L's short leg */
    cnPose pose = cn_pose_rotation((double[]){0, 0, 1}, PI / 6, (double[]){0, 0, 0});
    pose.t[0] = 1.5, pose.t[1] = 0.5, pose.t[2] = 1;
    CHECK(cn_builder_add_box(b, "cap", (double[]){-0.25, -0.25, 0}, (double[]){0.25, 0.25, 0.5}, false) == CN_OK);
    CHECK(cn_builder_set_part_pose(b, &pose) == CN_OK);
    cnSegment turn = {.kind = CN_SEGMENT_TURN, .angle = PI / 6, .axis = {0, 0, 1}, .about = {0, 0, 0}};
    cnSegment lift = {.kind = CN_SEGMENT_MOVE, .move = {0, 0, 4}};
    cnSegment path[2] = {lift, turn};
    CHECK(cn_builder_add_step(b, 1, (const char *const[]){"L"}, 2, path, CN_SUPPORT_HOLD) == CN_OK);
    cnAssembly *a = NULL;
    cnDiag d;
    CHECK_MSG(cn_builder_finish(b, &a, &d) == CN_OK, "3-D finish: %s: %s", d.where, d.message);
    if (a) {
        CHECK(a->parts[1].npieces == 2);
        CHECK(fabs(a->parts[2].com[0] - 1.5) < 1e-12 && fabs(a->parts[2].com[2] - 1.25) < 1e-12);
        CHECK(fabs(a->parts[2].hi[0] - 1.5 - 0.25 * (cos(PI / 6) + sin(PI / 6))) < 1e-12);
        CHECK(fabs(a->parts[1].mass - 4.0) < 1e-12); /* 2 + 2 */
        CHECK(a->plan[0].nseg == 2 && a->plan[0].seg[1].kind == CN_SEGMENT_TURN);
        CHECK(fabs(a->plan[0].seg[1].angle - PI / 6) < 1e-12);
        cnCheckResult r;
        CHECK(cn_check(a, NULL, &r, &d) == CN_OK && r.stable);
        cn_check_result_free(&r);
    }
    cn_assembly_free(a);
    cn_builder_free(b);
}

/* Each problem named where the file would have it; the first failure sticks. */
static void test_builder_errors(void) {
    cnDiag d;
    cnAssembly *a = NULL;
    /* a non-convex piece of "polygons": the loader's message, at the piece's JSON path (a
       non-convex "polygon" alone is split for the user) */
    cnBuilder *b = cn_builder_new(2);
    if (!b) return;
    cn_builder_add_polygon(b, "table", 4, TABLE, true);
    cn_builder_add_polygon(b, "L", 6, (double[]){0, 0, 2, 0, 2, 1, 1, 1, 1, 2, 0, 2}, false);
    cn_builder_add_piece(b, 4, (double[]){2, 0, 3, 0, 3, 1, 2, 1});
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && a == NULL);
    CHECK_MSG(!strcmp(d.where, "parts[1].polygons[0]") && strstr(d.message, "convex"), "%s: %s", d.where, d.message);
    cn_builder_free(b);
    /* a duplicate name */
    b = cn_builder_new(2);
    cn_builder_add_polygon(b, "A", 4, TABLE, true);
    cn_builder_add_polygon(b, "A", 4, (double[]){0, 0, 1, 0, 1, 1, 0, 1}, false);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT);
    CHECK_MSG(strstr(d.where, "parts[1]") != NULL, "duplicate at %s: %s", d.where, d.message);
    cn_builder_free(b);
    /* a NaN: refused at the call, and every later call returns the same failure */
    b = cn_builder_new(2);
    CHECK(cn_builder_set_gravity(b, (double[]){0, NAN}) == CN_ERR_INPUT);
    CHECK(cn_builder_add_polygon(b, "table", 4, TABLE, true) == CN_ERR_INPUT);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && a == NULL);
    CHECK_MSG(!strcmp(d.where, "gravity[1]") && strstr(d.message, "finite"), "%s: %s", d.where, d.message);
    cn_builder_free(b);
    /* an infinite coordinate of the third point of part 0 */
    b = cn_builder_new(2);
    CHECK(cn_builder_add_polygon(b, "table", 3, (double[]){0, 0, 1, 0, INFINITY, 1}, true) == CN_ERR_INPUT);
    CHECK_MSG(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "parts[0].polygon[2][0]"), "%s", d.where);
    cn_builder_free(b);
    /* a piece with no part, a piece on a box, a part without a name, a step without parts */
    b = cn_builder_new(3);
    CHECK(cn_builder_add_piece(b, 3, (double[]){0, 0, 0, 1, 0, 0, 0, 1, 0}) == CN_ERR_INPUT);
    cn_builder_free(b);
    b = cn_builder_new(3);
    cn_builder_add_box(b, "box", (double[]){0, 0, 0}, (double[]){1, 1, 1}, false);
    CHECK(cn_builder_add_piece(b, 4, (double[]){0, 0, 1, 1, 0, 1, 0, 1, 1, 0, 0, 2}) == CN_ERR_INPUT);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "parts[0].hulls"));
    cn_builder_free(b);
    b = cn_builder_new(2);
    CHECK(cn_builder_add_polygon(b, NULL, 4, TABLE, true) == CN_ERR_INPUT);
    cn_builder_free(b);
    b = cn_builder_new(2);
    CHECK(cn_builder_add_step(b, 0, NULL, 0, NULL, CN_SUPPORT_HOLD) == CN_ERR_INPUT);
    cn_builder_free(b);
    /* a dimension of 4: refused before any point is read (each point is dim numbers) */
    b = cn_builder_new(4);
    CHECK(cn_builder_set_gravity(b, (double[]){0, -1}) == CN_ERR_INPUT);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "dimension"));
    cn_builder_free(b);
    /* a shape of the other dimension: refused before its points are read (a 2-D polygon's
       array has 2 numbers a point, a 3-D builder would read 3) */
    b = cn_builder_new(3);
    CHECK(cn_builder_add_polygon(b, "P", 3, (double[]){0, 0, 1, 0, 0, 1}, false) == CN_ERR_INPUT);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "parts[0].polygon"));
    cn_builder_free(b);
    b = cn_builder_new(2);
    CHECK(cn_builder_add_box(b, "B", (double[]){0, 0, 0}, (double[]){1, 1, 1}, false) == CN_ERR_INPUT);
    cn_builder_free(b);
    b = cn_builder_new(2);
    CHECK(cn_builder_add_hull(b, "H", 4, (double[]){0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1}, false) == CN_ERR_INPUT);
    cn_builder_free(b);
    /* names that are not UTF-8 are bad input (not out of memory); a support that is neither */
    b = cn_builder_new(2);
    CHECK(cn_builder_add_polygon(b, "caf\xe9", 4, TABLE, true) == CN_ERR_INPUT);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "parts[0].name") && strstr(d.message, "UTF-8"));
    cn_builder_free(b);
    b = cn_builder_new(2);
    CHECK(cn_builder_set_name(b, "\xff") == CN_ERR_INPUT);
    cn_builder_free(b);
    b = cn_builder_new(2);
    CHECK(cn_builder_add_step(b, 1, (const char *const[]){"A"}, 0, NULL, (cnSupport)42) == CN_ERR_INPUT);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "plan[0].support"));
    cn_builder_free(b);
    /* a bad number in the second piece, a fixel's normal: named to the number */
    b = cn_builder_new(2);
    cn_builder_add_polygon(b, "P", 4, (double[]){0, 0, 1, 0, 1, 1, 0, 1}, false);
    CHECK(cn_builder_add_piece(b, 3, (double[]){1, 0, 2, NAN, 1, 1}) == CN_ERR_INPUT);
    CHECK_MSG(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "parts[0].polygons[1][1][1]"), "%s", d.where);
    cn_builder_free(b);
    b = cn_builder_new(2);
    CHECK(cn_builder_add_fixel(b, "P", (double[]){0, 0}, (double[]){INFINITY, 0}) == CN_ERR_INPUT);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT && !strcmp(d.where, "fixels[0].normal[0]"));
    cn_builder_free(b);
    /* a plan naming a part that is not there: the loader's words */
    b = cn_builder_new(2);
    cn_builder_add_polygon(b, "table", 4, TABLE, true);
    cn_builder_add_polygon(b, "A", 4, (double[]){0, 0, 1, 0, 1, 1, 0, 1}, false);
    cn_builder_add_step(b, 1, (const char *const[]){"Q"}, 0, NULL, CN_SUPPORT_PUSH);
    CHECK(cn_builder_finish(b, &a, &d) == CN_ERR_INPUT);
    CHECK_MSG(!strncmp(d.where, "plan[0].move", 12) && strstr(d.message, "Q"), "%s: %s", d.where, d.message);
    cn_builder_free(b);
    CHECK(cn_builder_finish(NULL, &a, &d) == CN_ERR_INPUT);
}

static json_t *run(const cnAssembly *a, const char *cmd, const char *opts, cnStatus want, cnOutcome *out,
                   cnDiag *d) {
    char *text = NULL;
    cnStatus s = cn_run_json(a, cmd, opts, &text, out, d);
    CHECK_MSG(s == want, "%s %s: status %d (%s: %s)", cmd, opts ? opts : "", s, d->where, d->message);
    json_t *doc = NULL;
    if (text) {
        json_error_t err;
        doc = json_loads(text, 0, &err);
        CHECK_MSG(doc != NULL, "%s: the report does not parse: %s", cmd, err.text);
        CHECK(json_integer_value(json_object_get(doc, "format_version")) == CN_JSON_FORMAT_VERSION);
    }
    CHECK((text != NULL) == (s == CN_OK));
    cn_string_free(text);
    return doc;
}

/* A 3-D arch of two quarter-ring voussoirs (built), whose proof of no motion needs more than a
 * few LPs: undecided on a budget of 5. */
static cnAssembly *vault(void) {
    cnBuilder *b = cn_builder_new(3);
    if (!b) return NULL;
    cn_builder_set_friction(b, 0.6);
    cn_builder_add_box(b, "ground", (double[]){-13, -1, -1}, (double[]){13, 2, 0}, true);
    for (int v = 0; v < 2; v++) {
        /* voussoir v spans the angles pi v / 2 .. pi (v + 1) / 2 of a ring of radii 10, 11.5 in
           the xz plane, 1 deep in y: the hull of its 8 corners */
        double pts[8 * 3];
        int k = 0;
        for (int y = 0; y < 2; y++)
            for (int e = 0; e < 2; e++)
                for (int r = 0; r < 2; r++) {
                    double ang = PI * (v + e) / 2, rad = r ? 11.5 : 10;
                    pts[k++] = rad * cos(ang), pts[k++] = y, pts[k++] = v + e == 1 ? rad : 0;
                }
        cn_builder_add_hull(b, v ? "right" : "left", 8, pts, false);
    }
    cnAssembly *a = NULL;
    cnDiag d;
    CHECK_MSG(cn_builder_finish(b, &a, &d) == CN_OK, "vault: %s: %s", d.where, d.message);
    cn_builder_free(b);
    return a;
}

/* TWO_BLOCKS_FILE written to dir/in.json (its path in input) and loaded from there; NULL (a check
 * failed) when it cannot be. */
static cnAssembly *two_blocks_in(const char *dir, char *input, size_t n) {
    snprintf(input, n, "%s/in.json", dir);
    FILE *f = fopen(input, "w");
    if (f) fputs(TWO_BLOCKS_FILE, f), fclose(f);
    cnAssembly *a = NULL;
    cnDiag d;
    CHECK_MSG(cn_assembly_load_file(input, &a, &d) == CN_OK, "%s: %s", input, d.message);
    return a;
}

/* cn_figure_run_json draws check's figure, after checking the path; cn_output_problem says why
 * a path cannot take an output */
static void test_run_json_figure(void) {
    char dir[] = "/tmp/cairn_figXXXXXX";
    if (!mkdtemp(dir)) return;
    char png[256], input[256], missing[256];
    snprintf(png, sizeof png, "%s/check.png", dir);
    snprintf(missing, sizeof missing, "%s/none/check.png", dir);
    cnAssembly *a = two_blocks_in(dir, input, sizeof input);
    if (!a) return;
    cnDiag d;
    CHECK(cn_output_problem(png, input, a) == CN_OUTPUT_OK);
    CHECK(cn_output_problem(input, input, a) == CN_OUTPUT_INPUT);
    CHECK(cn_output_problem(dir, input, a) == CN_OUTPUT_DIRECTORY);
    CHECK(cn_output_problem(missing, input, a) == CN_OUTPUT_NO_DIRECTORY);
    char opts[320], *text = NULL;
    cnOutcome out = -1;
    snprintf(opts, sizeof opts, "{\"figure\": \"%s\"}", png);
    CHECK(cn_figure_run_json(a, "check", opts, &text, &out, &d) == CN_OK && out == CN_OUTCOME_GOOD);
    cn_string_free(text);
    FILE *f = fopen(png, "rb");
    unsigned char sig[8] = {0};
    CHECK(f && fread(sig, 1, 8, f) == 8 && sig[0] == 0x89 && sig[1] == 'P');
    if (f) fclose(f);
    snprintf(opts, sizeof opts, "{\"figure\": \"%s\"}", input); /* never over the input */
    text = NULL;
    CHECK(cn_figure_run_json(a, "check", opts, &text, &out, &d) == CN_ERR_INPUT && !text);
    CHECK(!strcmp(d.where, "options.figure"));
    cn_assembly_free(a);
    remove(png), remove(input), rmdir(dir);
}

/* cn_figure_plan_html: every row of the table of two stacked blocks (each a sequence along the
 * planner's paths) played on the page under its label, as plan --html writes it; an input that
 * cannot be read again is named in diag.file. */
static void test_plan_html(void) {
    char dir[] = "/tmp/cairn_planhtmlXXXXXX";
    if (!mkdtemp(dir)) return;
    char html[256], input[256], gone[256];
    snprintf(html, sizeof html, "%s/plan.html", dir);
    snprintf(gone, sizeof gone, "%s/gone.json", dir);
    cnAssembly *a = two_blocks_in(dir, input, sizeof input);
    cnDiag d;
    cn_diag_clear(&d);
    cnPlanResult r;
    memset(&r, 0, sizeof r);
    cnLoadOptions lo = cn_load_options_default();
    cnPlanOptions po = cn_plan_options_default();
    if (a && cn_plan(a, &po, &r, &d) == CN_OK) {
        CHECK(r.stable && r.nrows >= 1);
        CHECK_MSG(cn_figure_plan_html(html, input, &lo, a, &r, &po.sim, &d) == CN_OK, "plan html: %s", d.message);
        long size = 0;
        char *page = NULL;
        FILE *f = fopen(html, "rb");
        if (f && !fseek(f, 0, SEEK_END) && (size = ftell(f)) > 0 && !fseek(f, 0, SEEK_SET) &&
            (page = malloc((size_t)size + 1)) && fread(page, 1, (size_t)size, f) == (size_t)size) {
            page[size] = 0;
            CHECK(strstr(page, "<html") != NULL);
            for (int row = 0; row < r.nrows; row++) {
                char label[64];
                snprintf(label, sizeof label, "\"%d. ", row + 1);
                CHECK_MSG(strstr(page, label) != NULL, "row %d's label not on the page", row + 1);
            }
        } else
            CHECK_MSG(false, "plan html: %s not written", html);
        if (f) fclose(f);
        free(page);
        /* the input gone: its load fails, named */
        CHECK(cn_figure_plan_html(html, gone, &lo, a, &r, &po.sim, &d) != CN_OK && !strcmp(d.file, gone));
    } else
        CHECK_MSG(false, "plan html set-up: %s", d.message);
    cn_plan_result_free(&r);
    cn_assembly_free(a);
    remove(html), remove(input), rmdir(dir);
}

static void test_run_json(void) {
    cnAssembly *a = load_ok(TWO_BLOCKS_FILE);
    cnAssembly *tip = load_ok("{\"dimension\":2,\"parts\":[" TABLE_FILE ","
                              "{\"name\":\"post\",\"fixed\":true,\"polygon\":[[6,-1],[7,-1],[7,0],[6,0]]},"
                              "{\"name\":\"B\",\"polygon\":[[6.5,0],[8.5,0],[8.5,1],[6.5,1]]}]}");
    if (!a || !tip) return;
    cnDiag d;
    cnOutcome out = -1;
    json_t *doc = run(a, "check", NULL, CN_OK, &out, &d);
    CHECK(out == CN_OUTCOME_GOOD && json_is_true(json_object_get(doc, "stable")));
    CHECK(!strcmp(json_string_value(json_object_get(doc, "verdict")), "stable"));
    json_decref(doc);
    doc = run(tip, "check", "{\"solver\": \"lemke\", \"lp_check\": false}", CN_OK, &out, &d);
    CHECK(out == CN_OUTCOME_NEGATIVE && json_is_false(json_object_get(doc, "stable")));
    json_t *moving = json_object_get(doc, "moving_parts");
    CHECK(json_array_size(moving) == 1 && !strcmp(json_string_value(json_array_get(moving, 0)), "B"));
    json_decref(doc);
    doc = run(a, "simulate", "{\"assemble\": true}", CN_OK, &out, &d);
    CHECK(out == CN_OUTCOME_GOOD && doc && json_object_get(doc, "assembly"));
    json_decref(doc);
    doc = run(a, "plan", "{\"max_states\": 100, \"support\": \"both\"}", CN_OK, &out, &d);
    CHECK(out == CN_OUTCOME_GOOD && json_is_true(json_object_get(doc, "stable")));
    json_decref(doc);
    doc = run(a, "plan", "{\"exhaustive\": true}", CN_OK, &out, &d);
    CHECK(out == CN_OUTCOME_GOOD && json_is_true(json_object_get(json_object_get(doc, "search"), "exhaustive")));
    json_decref(doc);
    doc = run(a, "directions", "{\"parts\": [\"B\"]}", CN_OK, &out, &d);
    json_decref(doc);
    doc = run(a, "contacts", "{}", CN_OK, &out, &d);
    CHECK(json_array_size(json_object_get(doc, "contacts")) == 4);
    json_decref(doc);
    /* a plan is needed to simulate: the simulation's own message */
    run(tip, "simulate", NULL, CN_ERR_INPUT, &out, &d);
    CHECK(strstr(d.message, "plan") != NULL);
    /* bad options, each at its place */
    struct { const char *cmd, *opts, *where; } bad[] = {
        {"check", "{\"solverr\": \"lemke\"}", "options.solverr"},
        {"check", "{\"solver\": \"simplex\"}", "options.solver"},
        {"check", "{\"search_budget\": 0}", "options.search_budget"},
        {"check", "{\"search_budget\": 2.5}", "options.search_budget"},
        {"check", "{\"search_budget\": 1e10}", "options.search_budget"},
        {"check", "[1]", "options"},
        {"check", "{\"a\": ", "options"},
        {"plan", "{\"max_seconds\": -1}", "options.max_seconds"},
        {"plan", "{\"support\": 3}", "options.support"},
        {"plan", "{\"exhaustive\": 1}", "options.exhaustive"},
        {"directions", "{\"parts\": [\"table\"]}", "options.parts[0]"},
        {"directions", "{\"parts\": [\"B\", \"B\"]}", "options.parts[1]"},
        {"directions", "{\"parts\": []}", "options.parts"},
        {"contacts", "{\"all\": true}", "options.all"},
        {"check", "{\"figure\": \"check.png\"}", "options.figure"}, /* figures: cn_figure_run_json */
        {"check", "{\"figure\": 3}", "options.figure"},
        {"chekc", NULL, "command"},
    };
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        run(a, bad[i].cmd, bad[i].opts, CN_ERR_INPUT, &out, &d);
        CHECK_MSG(!strcmp(d.where, bad[i].where), "%s %s: where '%s', wanted '%s' (%s)", bad[i].cmd, bad[i].opts,
                  d.where, bad[i].where, d.message);
    }
    /* a whole number written as a real (1e3) is taken, as the CLI takes --search-budget 1e3 */
    doc = run(a, "check", "{\"search_budget\": 1e3}", CN_OK, &out, &d);
    json_decref(doc);
    /* undecided: a static solution, and a search cut short */
    cnAssembly *v = vault();
    if (v) {
        doc = run(v, "check", "{\"search_budget\": 5}", CN_OK, &out, &d);
        CHECK(out == CN_OUTCOME_UNDECIDED);
        CHECK(doc && !strcmp(json_string_value(json_object_get(doc, "verdict")), "undecided"));
        json_decref(doc);
        doc = run(v, "check", "{\"accept_prestress\": true}", CN_OK, &out, &d);
        CHECK(out == CN_OUTCOME_GOOD);
        json_decref(doc);
    }
    cn_assembly_free(v);
    cn_assembly_free(a);
    cn_assembly_free(tip);
}

/* Every reason for no verdict has a sentence of its own; a verdict has none. */
static void test_undecided_text(void) {
    CHECK(strcmp(cn_undecided_text(CN_UNDECIDED_NO), "") == 0);
    for (int a = CN_UNDECIDED_BUDGET; a <= CN_UNDECIDED_CORNERS_WIDE; a++) {
        const char *ta = cn_undecided_text((cnUndecided)a);
        CHECK_MSG(ta && *ta && strcmp(ta, "undecided") != 0, "reason %d has no sentence", a);
        for (int b = CN_UNDECIDED_BUDGET; b < a; b++)
            CHECK_MSG(strcmp(ta, cn_undecided_text((cnUndecided)b)) != 0, "reasons %d and %d read alike", a, b);
    }
}

/* The names of where the forces came from, of the LP's methods and of why the LCP gave no
 * motion are the reports' words, one each (none for "none" where the reports write null). */
static void test_result_names(void) {
    const char *from[] = {"none", "pivot", "lemke", "lp", "interior point"};
    for (int f = CN_FORCES_NONE; f <= CN_FORCES_SPARSE_QP; f++)
        CHECK_MSG(!strcmp(cn_forces_from_name((cnForcesFrom)f), from[f]), "forces from %d", f);
    CHECK(cn_lp_method_name(CN_LP_METHOD_NONE) == NULL);
    for (int a = CN_LP_METHOD_LOAD_DESCENT; a <= CN_LP_METHOD_GLPK_ELASTIC; a++) {
        const char *ta = cn_lp_method_name((cnLpMethod)a);
        CHECK_MSG(ta && *ta, "LP method %d has no name", a);
        for (int b = CN_LP_METHOD_LOAD_DESCENT; ta && b < a; b++)
            CHECK_MSG(strcmp(ta, cn_lp_method_name((cnLpMethod)b)) != 0, "LP methods %d and %d read alike", a, b);
    }
    CHECK(strcmp(cn_unsolved_text(CN_UNSOLVED_NO), "") == 0);
    CHECK(strcmp(cn_unsolved_text(CN_UNSOLVED_RAY), cn_lcp_status_name(CN_LCP_RAY)) == 0);
    for (int a = CN_UNSOLVED_RAY; a <= CN_UNSOLVED_NOT_SOLVED; a++) {
        const char *ta = cn_unsolved_text((cnUnsolved)a);
        CHECK_MSG(*ta, "reason %d has no sentence", a);
        for (int b = CN_UNSOLVED_RAY; b < a; b++)
            CHECK_MSG(strcmp(ta, cn_unsolved_text((cnUnsolved)b)) != 0, "reasons %d and %d read alike", a, b);
    }
}

void test_api(void) {
    test_undecided_text();
    test_result_names();
    test_builder_equals_file();
    test_builder_3d();
    test_builder_errors();
    test_run_json();
    test_run_json_figure();
    test_plan_html();
}
