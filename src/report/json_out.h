/* report: what every report shares (the JSON writer, the words for a step's status). Private. */
#ifndef CAIRN_JSON_OUT_H
#define CAIRN_JSON_OUT_H

#include <stdio.h>
#include "core.h"
#include "cairn/simulate.h"

/* ---- reports (report.c) ---- */
/* Write a JSON document (jansson json_t *, taken: it is released) with 2-space indentation and
 * `precision` significant digits, then a newline. */
cnStatus cn_json_write(FILE *f, void *json, int precision);

/* v, or 0 when it is rounding: within 1e-12 (CN_TOL_PRINT_ZERO) of its scale. */
double cn_report_clean(double v, double scale);

/* A verdict as JSON says it: "stable", "unstable", "not_guaranteed", "undecided". */
const char *cn_verdict_word(cnVerdict v);

/* ---- margins (report_margin.c), also in a simulation's report ---- */
/* One margin (kind: CN_MARGIN_FRICTION, _TILT, _LATERAL) as a JSON object (a json_t *). */
void *cn_margin_json(const cnAssembly *a, const cnMargin *m, int kind);
/* One margin as text: its line, starting with `lead` then the margin's name and `at` (e.g. " at
 * t = 2"), then the mechanism's lines indented by lead and six spaces. */
void cn_margin_text(FILE *f, const cnAssembly *a, const cnMargin *m, int kind, const char *lead, const char *at);

/* ---- one large array written as it goes (json_stream.c) ---- */
/* cn_json_write for a document whose top-level `key` (a key of json, or appended) holds a large
 * array: write(stream, ctx) writes that value with the functions below, in the bytes jansson
 * would write for it (so the output is as if the whole document were a tree). */
typedef struct cnJsonStream cnJsonStream;
typedef void (*cnJsonStreamFn)(cnJsonStream *s, void *ctx);
cnStatus cn_json_write_streamed(FILE *f, void *json, int precision, const char *key,
                                cnJsonStreamFn write, void *ctx);
/* A container (object or array) as a value; close takes open's result. */
unsigned cn_json_stream_open(cnJsonStream *s, bool object);
void cn_json_stream_close(cnJsonStream *s, unsigned saved);
/* In an object, each value follows its key. A non-finite real is not written (jansson has no
 * value for it): check cn_json_stream_real_ok first and leave the key out, as jansson does. */
void cn_json_stream_key(cnJsonStream *s, const char *key);
void cn_json_stream_int(cnJsonStream *s, long long v);
void cn_json_stream_bool(cnJsonStream *s, bool v);
void cn_json_stream_string(cnJsonStream *s, const char *v);
bool cn_json_stream_real_ok(double v);
void cn_json_stream_real(cnJsonStream *s, double v);
/* jansson's text of a real at `precision` significant digits (exposed for the unit tests). */
void cn_json_stream_real_text(double v, int precision, char *buf, size_t n);

/* ---- reports of simulations and plans (report_sim.c) ---- */

/* "s" after a count other than 1: "1 part", "2 parts" */
static inline const char *cn_plural(long n) { return n == 1 ? "" : "s"; }

#endif
