/* Reports read back: the JSON parses and says what the typed result says; the text names the
 * verdict. A second reading of each result, independent of the writer's own code paths. */
#include <jansson.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "helpers.h"
#include "json_out.h"

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
            /* where the forces came from: frictionless and small, the pivoting solver (the
               default's choice for a symmetric LCP); the LP's method as its name, or null */
            json_t *sv = json_object_get(doc, "solver");
            const char *from = json_string_value(json_object_get(sv, "forces_from"));
            CHECK(r.solver.forces_from == CN_FORCES_PIVOT && from && !strcmp(from, "pivot"));
            const char *lpm = cn_lp_method_name(r.solver.lp_method);
            json_t *jm = json_object_get(sv, "lp_method");
            CHECK(lpm ? json_is_string(jm) && !strcmp(json_string_value(jm), lpm) : json_is_null(jm));
            CHECK(json_is_null(json_object_get(sv, "lcp_unsolved")) && r.unsolved == CN_UNSOLVED_NO);
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
    /* names a spreadsheet would run as formulas are written as text (a leading apostrophe) */
    a = load_ok("{\"dimension\":2,\"gravity\":[0,-1],\"parts\":[" GROUND ","
                "{\"name\":\"=HYPERLINK(1,2)\",\"polygon\":[[0,0],[2,0],[2,1],[0,1]]},"
                "{\"name\":\"@cmd\",\"polygon\":[[0,1],[1,1],[1,2],[0,2]]}],"
                "\"plan\":[{\"move\":\"@cmd\",\"path\":[[0,2]]}]}");
    if (!a) return;
    CHECK(cn_simulate(a, &o, &r, &d) == CN_OK);
    buf = NULL, len = 0;
    f = open_memstream(&buf, &len);
    CHECK(cn_report_sim_csv(f, a, &r) == CN_OK);
    fclose(f);
    n = csv_read(buf, nf, 256, "'=HYPERLINK(1,2)", "'@cmd", &seen);
    CHECK_MSG(n > 2 && seen == 3, "CSV with formula-like names: %d records, seen %d", n, seen);
    CHECK(buf && !strstr(buf, ",=") && !strstr(buf, ",@") && !strstr(buf, "\"="));
    free(buf);
    cn_sim_result_free(&r);
    cn_assembly_free(a);
}

/* The streamed array (json_stream.c) against jansson's own dump of the same values: reals of
 * every size and sign (xorshift, a fixed seed), integers, booleans, strings with quotes,
 * backslashes, control characters and UTF-8, empty and nested containers. The document must be
 * byte for byte what jansson writes for the whole tree. */
typedef struct {
    double *reals;
    int n;
} StreamCase;

static void stream_case(cnJsonStream *s, void *ctx) {
    const StreamCase *c = ctx;
    unsigned k0 = cn_json_stream_open(s, false);
    for (int i = 0; i < c->n; i++) {
        unsigned k1 = cn_json_stream_open(s, true);
        cn_json_stream_key(s, "id");
        cn_json_stream_int(s, (long long)i * 1000003LL - 7);
        cn_json_stream_key(s, "name \"q\"");
        cn_json_stream_string(s, i % 2 ? "a\\b\t\001\n\x1f/\xc3\xa9" : "");
        cn_json_stream_key(s, "v");
        unsigned k2 = cn_json_stream_open(s, false);
        for (int k = 0; k < i % 4; k++) cn_json_stream_real(s, c->reals[(i * 3 + k) % c->n]);
        cn_json_stream_close(s, k2);
        cn_json_stream_key(s, "o");
        unsigned k3 = cn_json_stream_open(s, true);
        if (i % 3) {
            cn_json_stream_key(s, "b");
            cn_json_stream_bool(s, i % 3 == 1);
            cn_json_stream_key(s, "x");
            cn_json_stream_real(s, c->reals[i]);
        }
        cn_json_stream_close(s, k3);
        cn_json_stream_close(s, k1);
    }
    cn_json_stream_close(s, k0);
}

static void test_json_stream(void) {
    enum { N = 400 };
    double reals[N];
    unsigned long long x = 88172645463325252ULL;
    for (int i = 0; i < N; i++) {
        x ^= x << 13, x ^= x >> 7, x ^= x << 17;
        double m = (double)(x >> 11) / 9007199254740992.0;             /* [0, 1) */
        int e = (int)((x >> 3) % 80) - 40;                              /* 1e-40 .. 1e39 */
        reals[i] = (i % 5 == 0) ? (double)(i - 200) : (i % 2 ? -1 : 1) * m * pow(10.0, e);
    }
    reals[1] = -0.0, reals[2] = 1e21, reals[3] = 123456789012.0, reals[4] = 1e-5;
    for (int prec = 6; prec <= 17; prec += 4) {
        StreamCase c = {reals, N};
        /* the tree jansson dumps */
        json_t *arr = json_array();
        for (int i = 0; i < N; i++) {
            json_t *o = json_object();
            json_object_set_new(o, "id", json_integer((json_int_t)i * 1000003LL - 7));
            json_object_set_new(o, "name \"q\"", json_string(i % 2 ? "a\\b\t\001\n\x1f/\xc3\xa9" : ""));
            json_t *v = json_array();
            for (int k = 0; k < i % 4; k++) json_array_append_new(v, json_real(reals[(i * 3 + k) % N]));
            json_object_set_new(o, "v", v);
            json_t *oo = json_object();
            if (i % 3) {
                json_object_set_new(oo, "b", json_boolean(i % 3 == 1));
                json_object_set_new(oo, "x", json_real(reals[i]));
            }
            json_object_set_new(o, "o", oo);
            json_array_append_new(arr, o);
        }
        json_t *tree = json_object();
        json_object_set_new(tree, "before", json_string("x"));
        json_object_set_new(tree, "big", arr);
        json_object_set_new(tree, "after", json_integer(3));
        char *want = NULL, *got = NULL;
        size_t wl = 0, gl = 0;
        FILE *f = open_memstream(&want, &wl);
        CHECK(cn_json_write(f, tree, prec) == CN_OK);
        fclose(f);
        json_t *doc = json_object();
        json_object_set_new(doc, "before", json_string("x"));
        json_object_set_new(doc, "big", json_null());
        json_object_set_new(doc, "after", json_integer(3));
        f = open_memstream(&got, &gl);
        CHECK(cn_json_write_streamed(f, doc, prec, "big", stream_case, &c) == CN_OK);
        fclose(f);
        size_t at = 0;
        while (at < wl && at < gl && want[at] == got[at]) at++;
        CHECK_MSG(wl == gl && at == wl, "precision %d: streamed JSON differs from jansson's at byte %zu of %zu: "
                  "\"%.40s\" against \"%.40s\"", prec, at, wl, got + (at < gl ? at : gl), want + (at < wl ? at : wl));
        free(want);
        free(got);
    }
}

void test_report(void) {
    test_json_stream();
    test_sim_csv();
    test_check_reports();
    test_plan_report();
}
