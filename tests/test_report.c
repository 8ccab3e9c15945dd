/* Reports read back: the JSON parses and says what the typed result says; the text names the
 * verdict. A second reading of each result, independent of the writer's own code paths. */
#include <jansson.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"

/* The report of a check (cr) or of a plan (pr), written into memory (caller frees). */
static char *capture(const cnAssembly *a, const cnCheckResult *cr, const cnPlanResult *pr, int json) {
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    CHECK((cr ? cn_report_check(f, a, cr, json) : cn_report_plan(f, a, pr, json)) == CN_OK);
    fclose(f);
    return buf;
}

#define GROUND "{\"name\":\"g\",\"fixed\":true,\"polygon\":[[-5,-1],[5,-1],[5,0],[-5,0]]}"

/* A block resting on the ground (stable, two contacts carrying half its weight each) and one
 * hanging over the edge of a post (unstable: it tips). */
static void test_check_reports(void) {
    const char *files[2] = {
        "{\"dimension\":2,\"gravity\":[0,-10],\"parts\":[" GROUND ",{\"name\":\"B\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]}]}",
        "{\"dimension\":2,\"gravity\":[0,-10],\"parts\":[{\"name\":\"post\",\"fixed\":true,\"polygon\":[[-1,-1],[0,-1],[0,0],[-1,0]]},"
        "{\"name\":\"B\",\"polygon\":[[-0.5,0],[1.5,0],[1.5,1],[-0.5,1]]}]}"};
    for (int k = 0; k < 2; k++) {
        cnAssembly *a = load_ok(files[k]);
        if (!a) continue;
        cnCheckResult r;
        cnDiag d;
        CHECK(cn_check(a, NULL, &r, &d) == CN_OK);
        CHECK(r.stable == (k == 0));
        char *js = capture(a, &r, NULL, 1), *tx = capture(a, &r, NULL, 0);
        json_error_t err;
        json_t *doc = js ? json_loads(js, 0, &err) : NULL;
        CHECK_MSG(doc != NULL, "check JSON does not parse: %s", doc ? "" : err.text);
        if (doc) {
            CHECK(json_integer_value(json_object_get(doc, "format_version")) == CN_JSON_FORMAT_VERSION);
            CHECK(!strncmp(js, "{\n  \"format_version\": 1,", strlen("{\n  \"format_version\": 1,"))); /* first */
            CHECK(json_is_true(json_object_get(doc, "stable")) == r.stable);
            json_t *cs = json_object_get(doc, "contacts");
            CHECK(json_is_array(cs) && (int)json_array_size(cs) == r.contacts.count);
            if (k == 0 && json_array_size(cs) == 2) {
                double total = 0;
                for (size_t i = 0; i < 2; i++)
                    total += json_number_value(json_object_get(json_array_get(cs, i), "force"));
                CHECK_NEAR(total, 20, 1e-6); /* the block's weight, 2 * 10 */
            }
            json_t *mv = json_object_get(doc, "moving_parts");
            CHECK(json_is_array(mv) && (int)json_array_size(mv) == (k == 0 ? 0 : 1));
            json_decref(doc);
        }
        CHECK(tx && strstr(tx, k == 0 ? "verdict: STABLE" : "verdict: UNSTABLE"));
        free(js);
        free(tx);
        cn_check_result_free(&r);
        cn_assembly_free(a);
    }
}

/* The plan report says what the typed result holds: the same counts, sequences and rows. */
static void test_plan_report(void) {
    char path[1024];
    snprintf(path, sizeof path, "%s/examples/blocks.json", CAIRN_SOURCE_DIR);
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_file(path, &a, &d) != CN_OK) {
        CHECK(false);
        return;
    }
    cnPlanOptions o = cn_plan_options_default();
    cnPlanResult r;
    CHECK(cn_plan(a, &o, &r, &d) == CN_OK);
    char *js = capture(a, NULL, &r, 1), *tx = capture(a, NULL, &r, 0);
    json_error_t err;
    json_t *doc = js ? json_loads(js, 0, &err) : NULL;
    CHECK(doc != NULL);
    if (doc) {
        CHECK(json_is_true(json_object_get(doc, "stable")) == r.stable);
        CHECK_NEAR(json_number_value(json_object_get(doc, "sequence_count")), r.nsequences, 0);
        CHECK((int)json_array_size(json_object_get(doc, "sequences")) == r.nlisted);
        CHECK((int)json_array_size(json_object_get(doc, "table")) == r.nrows);
        json_t *best = json_object_get(doc, "best_plan");
        CHECK(r.best_plan && json_is_array(best) && (int)json_array_size(best) == r.best_plan->n);
        /* each best-plan step names the part of the typed step and its path's displacements */
        for (int i = 0; r.best_plan && i < r.best_plan->n && i < (int)json_array_size(best); i++) {
            json_t *st = json_array_get(best, i);
            const cnPlanMove *m = &r.best_plan->steps[i];
            CHECK(!strcmp(json_string_value(json_object_get(st, "move")), a->parts[m->move.idx[0]].name));
            CHECK((int)json_array_size(json_object_get(st, "path")) == m->nseg);
        }
        json_t *search = json_object_get(doc, "search");
        CHECK(json_integer_value(json_object_get(search, "states")) == r.search.states);
        CHECK(json_integer_value(json_object_get(search, "simulations")) == r.search.simulations);
        json_decref(doc);
    }
    CHECK(tx && strstr(tx, "a stable plan exists: 1 stable order of the parts") && strstr(tx, "D-C-B-A"));
    free(js);
    free(tx);
    cn_plan_result_free(&r);
    /* an empty result (never filled, or freed) is refused, not read */
    CHECK(cn_report_plan(stdout, a, &r, 1) == CN_ERR_INPUT);
    cn_assembly_free(a);
}

/* An RFC 4180 reader: records of fields, quoted fields with doubled quotes, CRLF between
 * records. Returns the number of records, each field count in nf[], and whether the fields
 * `want` were seen; -1 when the text is not valid RFC 4180. */
static int csv_read(const char *t, int *nf, int cap, const char *want1, const char *want2, int *seen) {
    int nrec = 0, fields = 0;
    char field[512];
    size_t len = 0;
    *seen = 0;
    while (*t) {
        len = 0;
        if (*t == '"') {
            for (t++;; t++) {
                if (!*t) return -1;
                if (*t == '"' && t[1] == '"') field[len++] = '"', t++;
                else if (*t == '"') {
                    t++;
                    break;
                } else field[len++] = *t;
                if (len >= sizeof field - 1) return -1;
            }
        } else {
            while (*t && *t != ',' && *t != '\r' && *t != '\n' && *t != '"' && len < sizeof field - 1) field[len++] = *t++;
            if (*t == '"' || *t == '\n') return -1; /* a bare quote, or LF without CR */
        }
        field[len] = 0;
        if (!strcmp(field, want1)) *seen |= 1;
        if (!strcmp(field, want2)) *seen |= 2;
        fields++;
        if (*t == ',') t++;
        else if (t[0] == '\r' && t[1] == '\n') {
            if (nrec < cap) nf[nrec] = fields;
            nrec++, fields = 0, t += 2;
        } else return -1;
    }
    return fields == 0 ? nrec : -1;
}

/* The CSV history of a simulation read back by that reader: parts named with a comma and with
 * quotes stay in their columns (a part named "C,1" shifted every column after it). */
static void test_sim_csv(void) {
    cnAssembly *a = load_ok("{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" GROUND ","
                            "{\"name\":\"C,1\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
                            "{\"name\":\"say \\\"hi\\\"\",\"polygon\":[[0,1],[1,1],[1,2],[0,2]]}],"
                            "\"plan\":[{\"move\":\"say \\\"hi\\\"\",\"path\":[[0,2]]}]}");
    if (!a) return;
    cnSimOptions o = cn_sim_options_default();
    cnSimResult r;
    cnDiag d;
    CHECK(cn_simulate(a, &o, &r, &d) == CN_OK);
    char *buf = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&buf, &len);
    CHECK(cn_report_sim_csv(f, a, &r) == CN_OK);
    fclose(f);
    int nf[256], seen = 0;
    int n = csv_read(buf, nf, 256, "C,1", "say \"hi\"", &seen);
    CHECK_MSG(n > 2 && seen == 3, "CSV: %d records, seen %d", n, seen);
    for (int i = 0; i < n && i < 256; i++) CHECK_MSG(nf[i] == 20, "CSV record %d has %d fields", i, nf[i]);
    free(buf);
    cn_sim_result_free(&r);
    cn_assembly_free(a);
}

void test_report(void) {
    test_sim_csv();
    test_check_reports();
    test_plan_report();
}
