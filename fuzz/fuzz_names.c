/* libFuzzer target: part names -> a stack of two blocks on a table whose top block is lifted ->
 * the CSV history and the JSON reports (make fuzz). Bytes up to each NUL are a name (made valid
 * UTF-8 when they are not). What is written must read back: every CSV record has the header's
 * columns, a part's name comes back as written (an apostrophe before one a spreadsheet would run
 * as a formula), no text field starts as a formula, the JSON reports parse and hold the names
 * they report (the check's contacts both blocks, the simulation the moved one), and the HTML
 * report has as many '<' as with plain names (every '<' of a name escaped). */
#include <jansson.h>
#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <unistd.h>

#include "cairn/cairn.h"
#include "cairn/figure.h"
#include "fuzz.h"

#define NNAMES 3

static bool formula_start(const char *s) { return s[0] && strchr("=+-@\t\r", s[0]); }

/* One CSV field per RFC 4180 from *p (quoted or not) into out; *p moves past it and its
 * separator; *end set at a record's end. false on a malformed field. */
static bool csv_field(const char **p, char *out, size_t cap, bool *quoted, bool *end) {
    const char *s = *p;
    size_t k = 0;
    *quoted = *s == '"';
    if (*quoted) {
        for (s++;; s++) {
            if (!*s) return false;
            if (*s == '"') {
                if (s[1] != '"') break;
                s++;
            }
            if (k + 1 < cap) out[k++] = *s;
        }
        s++;
    } else {
        for (; *s && *s != ',' && *s != '\r' && *s != '\n' && *s != '"'; s++)
            if (k + 1 < cap) out[k++] = *s;
        if (*s == '"') return false;
    }
    out[k] = 0;
    if (*s == ',') *end = false, s++;
    else if (s[0] == '\r' && s[1] == '\n') *end = true, s += 2;
    else return false;
    *p = s;
    return true;
}

/* A name as the CSV must give it back. */
static void csv_expect(const char *name, char *out, size_t cap) {
    snprintf(out, cap, "%s%s", formula_start(name) ? "'" : "", name);
}

static void check_csv(const char *csv, char names[NNAMES][4100]) {
    const char *p = csv;
    int header = 0, col = 0;
    bool end = false, quoted;
    char *field = malloc(1 << 16);
    if (!field) abort();
    while (*p) {
        if (!csv_field(&p, field, 1 << 16, &quoted, &end)) abort(); /* not RFC 4180 */
        /* columns: 3 move, 10 part1, 11 part2, 13 label */
        if (header > 0 && (col == 3 || col == 10 || col == 11 || col == 13)) {
            if (formula_start(field)) abort(); /* a spreadsheet would run it */
            if (col == 10 || col == 11) {
                bool known = !strcmp(field, "fixel");
                char want[4200];
                for (int i = 0; i < NNAMES && !known; i++) {
                    csv_expect(names[i], want, sizeof want);
                    known = !strcmp(field, want);
                }
                if (!known) abort(); /* a name that does not read back */
            }
        }
        col++;
        if (end) {
            if (header == 0) header = col;
            else if (col != header) abort(); /* a record with other columns than the header */
            col = 0;
        }
    }
    if (col != 0) abort(); /* the last record did not end */
    free(field);
}

/* Does the JSON value hold the string s (anywhere)? */
static bool json_holds(const json_t *v, const char *s) {
    if (json_is_string(v)) return !strcmp(json_string_value(v), s);
    if (json_is_array(v)) {
        size_t i;
        json_t *x;
        json_array_foreach(v, i, x) if (json_holds(x, s)) return true;
    }
    if (json_is_object(v)) {
        const char *k;
        json_t *x;
        json_object_foreach((json_t *)v, k, x) if (json_holds(x, s)) return true;
    }
    return false;
}

static void check_json(const char *text, const char *a, const char *b) {
    json_error_t e;
    json_t *v = json_loads(text, 0, &e);
    if (!v) abort(); /* not JSON */
    if (!json_holds(v, a) || (b && !json_holds(v, b))) abort(); /* a name lost or changed */
    json_decref(v);
}

static char dir[64];

static void remove_dir(void) {
    char path[128];
    snprintf(path, sizeof path, "%s/p.html", dir);
    unlink(path);
    rmdir(dir);
}

/* The '<' of the simulation's HTML report; -1 when it was not written. */
static long html_tags(const cnAssembly *a, const cnSimResult *r) {
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/cairn_fuzz_names.XXXXXX");
        if (!mkdtemp(dir)) abort();
        atexit(remove_dir);
    }
    char path[128];
    snprintf(path, sizeof path, "%s/p.html", dir);
    cnDiag d;
    if (cn_figure_simulation_html(path, a, r, NULL, &d) != CN_OK) return -1;
    FILE *f = fopen(path, "rb");
    if (!f) abort();
    long n = 0;
    for (int c; (c = fgetc(f)) != EOF;) n += c == '<';
    fclose(f);
    return n;
}

/* The assembly with these names (NULL: not loaded). */
static cnAssembly *stack(json_t *const js[NNAMES]) {
    json_t *doc = json_pack("{s:i, s:[{s:O, s:b, s:[[i,i],[i,i],[i,i],[i,i]]}, {s:O, s:[[i,i],[i,i],[i,i],[i,i]]},"
                            " {s:O, s:[[i,i],[i,i],[i,i],[i,i]]}], s:[{s:O, s:[[i,i]]}]}",
                            "dimension", 2, "parts",
                            "name", js[0], "fixed", 1, "polygon", -5, -1, 5, -1, 5, 0, -5, 0,
                            "name", js[1], "polygon", 0, 0, 1, 0, 1, 1, 0, 1,
                            "name", js[2], "polygon", 0, 1, 1, 1, 1, 2, 0, 2,
                            "plan", "move", js[2], "path", 0, 1);
    if (!doc) abort();
    char *text = json_dumps(doc, 0);
    json_decref(doc);
    if (!text) abort();
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_string(text, "fuzz", &a, &d) != CN_OK) a = NULL;
    free(text);
    return a;
}

/* The '<' of the report with plain names: what every report must have. */
static long plain_tags(void) {
    static long n = -2;
    if (n != -2) return n;
    json_t *js[NNAMES] = {json_string("T"), json_string("A"), json_string("B")};
    cnAssembly *a = stack(js);
    for (int i = 0; i < NNAMES; i++) json_decref(js[i]);
    if (!a) abort();
    cnSimOptions so = cn_sim_options_default();
    so.check.max_nodes = 20;
    cnSimResult sr;
    cnDiag d;
    if (cn_simulate(a, &so, &sr, &d) != CN_OK) abort();
    n = html_tags(a, &sr);
    cn_sim_result_free(&sr);
    cn_assembly_free(a);
    return n;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
    static char names[NNAMES][4100];
    static const char *const kDefault[NNAMES] = {"table", "A", "B"};
    size_t at = 0;
    for (int i = 0; i < NNAMES; i++) {
        size_t k = 0;
        while (at < size && data[at] != 0 && k + 1 < sizeof names[i]) names[i][k++] = (char)data[at++];
        at++;
        names[i][k] = 0;
        if (k == 0) snprintf(names[i], sizeof names[i], "%s", kDefault[i]);
    }
    json_t *js[NNAMES];
    for (int i = 0; i < NNAMES; i++) {
        js[i] = json_string(names[i]);
        if (!js[i]) { /* not UTF-8: ASCII of it */
            for (char *c = names[i]; *c; c++) *c = (char)((*c & 0x7f) ? (*c & 0x7f) : '?');
            js[i] = json_string(names[i]);
            if (!js[i]) abort();
        }
    }
    cnAssembly *a = stack(js);
    for (int i = 0; i < NNAMES; i++) json_decref(js[i]);
    cnDiag d;
    if (a) {
        cnCheckOptions co = cn_check_options_default();
        co.max_nodes = 20;
        cnCheckResult cr;
        char *out = NULL;
        size_t len = 0;
        if (cn_check(a, &co, &cr, &d) == CN_OK) {
            FILE *f = open_memstream(&out, &len);
            if (!f) abort();
            cn_report_check(f, a, &cr, 1);
            fclose(f);
            check_json(out, a->parts[1].name, a->parts[2].name);
            free(out);
            cn_check_result_free(&cr);
        }
        cnSimOptions so = cn_sim_options_default();
        so.check.max_nodes = 20;
        cnSimResult sr;
        if (cn_simulate(a, &so, &sr, &d) == CN_OK) {
            FILE *f = open_memstream(&out, &len);
            if (!f) abort();
            cn_report_sim_csv(f, a, &sr);
            fclose(f);
            check_csv(out, names);
            free(out);
            f = open_memstream(&out, &len);
            if (!f) abort();
            cn_report_sim(f, a, &sr, NULL, 1);
            fclose(f);
            check_json(out, a->parts[2].name, NULL); /* the moved part */
            free(out);
            long tags = html_tags(a, &sr);
            if (tags >= 0 && tags != plain_tags()) abort(); /* a name's '<' not escaped */
            cn_sim_result_free(&sr);
        }
        cn_assembly_free(a);
    }
    return 0;
}
