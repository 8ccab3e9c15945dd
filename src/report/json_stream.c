/* A JSON document whose one large array is written as it goes, without a tree for it: a large
 * check's contacts as a jansson tree (an object, two arrays and a dozen values each) cost more
 * time and memory than the check itself. The document is still dumped by jansson, with a placeholder where the large array goes; the array is
 * written here in exactly the bytes jansson would write (2-space indentation, its number and
 * string formats), so the output does not change. */
/* flockfile and putc_unlocked are POSIX: every build defines _POSIX_C_SOURCE (CMakeLists.txt) */
#include <jansson.h>
#include <locale.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "json_out.h"
#include "cairn/report.h"

/* The placeholder's value: control characters, which jansson writes as \u0001 escapes. */
static const char PLACEHOLDER[] = "\001cairn streamed array\001";
static const char PLACEHOLDER_DUMPED[] = "\"\\u0001cairn streamed array\\u0001\"";

struct cnJsonStream {
    FILE *f;
    int precision;
    int depth;    /* of the value being written, in jansson's indentation units */
    bool first;   /* no element written yet in the innermost container */
    bool in_obj;  /* the innermost container is an object */
};

/* The stream's FILE is locked once for the whole array (cn_json_write_streamed), so single
 * characters go out unlocked and runs as one fwrite: a character at a time through the locking
 * fputc was a sixth of the 10,000-brick wall's `check --json`. */
static void indent(cnJsonStream *s) {
    static const char SPACES[] = "\n                                                                ";
    int n = 2 * s->depth;
    if (n < (int)sizeof SPACES - 1) {
        fwrite(SPACES, 1, (size_t)n + 1, s->f);
        return;
    }
    putc_unlocked('\n', s->f);
    for (int i = 0; i < n; i++) putc_unlocked(' ', s->f);
}

/* Before a value or key: the separator from the previous element and the indentation. */
static void element(cnJsonStream *s) {
    if (!s->first) putc_unlocked(',', s->f);
    s->first = false;
    indent(s);
}

/* A string as jansson writes it without JSON_ENSURE_ASCII or JSON_ESCAPE_SLASH: quotes,
 * backslashes and control characters escaped, everything else (UTF-8) as it is. */
static void put_string(cnJsonStream *s, const char *str) {
    FILE *f = s->f;
    putc_unlocked('"', f);
    for (const unsigned char *p = (const unsigned char *)str; *p; p++) {
        const unsigned char *run = p; /* characters written as they are, in one go */
        while (*p >= 0x20 && *p != '"' && *p != '\\') p++;
        if (p > run) fwrite(run, 1, (size_t)(p - run), f);
        if (!*p) break;
        switch (*p) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\b': fputs("\\b", f); break;
        case '\f': fputs("\\f", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        default:
            fprintf(f, "\\u%04X", (unsigned)*p); /* the rest of the control characters */
        }
    }
    putc_unlocked('"', f);
}

void cn_json_stream_real_text(double v, int precision, char *buf, size_t n) {
    /* jansson's: %.*g, then ".0" when neither a point nor an exponent shows, and the exponent
     * without its '+' or leading zeros */
    if (precision <= 0 || precision > 31) precision = 17; /* as JSON_REAL_PRECISION reads it */
    /* the precision written into the format, not passed as "*": glibc formats a '*' argument
     * by its slower positional path (a sixth of the wall's report) */
    char fmt[8] = {'%', '.', (char)('0' + precision / 10), (char)('0' + precision % 10), 'g', 0};
    if (precision < 10) memmove(fmt + 2, fmt + 3, 3);
    int len = snprintf(buf, n, fmt, v);
    if (len < 0 || (size_t)len >= n) return;
    /* the decimal point as JSON writes it whatever the caller's locale (jansson's from_locale):
     * a program embedding the library may have set LC_NUMERIC to a comma */
    char point = localeconv()->decimal_point[0];
    if (point != '.' && point != '\0') {
        char *p = strchr(buf, point);
        if (p) *p = '.';
    }
    if (!strchr(buf, '.') && !strchr(buf, 'e')) {
        if ((size_t)len + 3 > n) return;
        memcpy(buf + len, ".0", 3);
        return;
    }
    char *e = strchr(buf, 'e');
    if (e) {
        char *start = e + 1, *end = e + 2;
        if (*start == '-') start++;
        while (*end == '0') end++;
        if (end != start) memmove(start, end, strlen(end) + 1);
    }
}

void cn_json_stream_key(cnJsonStream *s, const char *key) {
    element(s);
    put_string(s, key);
    fputs(": ", s->f);
    s->first = true; /* the value follows on this line: no separator, no indentation */
}

/* A value: in an object after its key, in an array on a line of its own. */
static void value_start(cnJsonStream *s) {
    if (s->in_obj) s->first = false;
    else element(s);
}

void cn_json_stream_int(cnJsonStream *s, long long v) {
    value_start(s);
    fprintf(s->f, "%lld", v);
}

void cn_json_stream_bool(cnJsonStream *s, bool v) {
    value_start(s);
    fputs(v ? "true" : "false", s->f);
}

void cn_json_stream_string(cnJsonStream *s, const char *v) {
    value_start(s);
    put_string(s, v);
}

bool cn_json_stream_real_ok(double v) { return isfinite(v); }

void cn_json_stream_real(cnJsonStream *s, double v) {
    char buf[64];
    value_start(s);
    cn_json_stream_real_text(v, s->precision, buf, sizeof buf);
    fputs(buf, s->f);
}

/* Containers: the state of the enclosing one is kept by the caller's nesting (open returns it,
 * close takes it back), as jansson writes "[]" and "{}" when empty. */
unsigned cn_json_stream_open(cnJsonStream *s, bool object) {
    value_start(s);
    putc_unlocked(object ? '{' : '[', s->f);
    unsigned saved = (s->in_obj ? 1u : 0u);
    s->in_obj = object;
    s->first = true;
    s->depth++;
    return saved;
}

void cn_json_stream_close(cnJsonStream *s, unsigned saved) {
    bool object = s->in_obj, empty = s->first;
    s->depth--;
    if (!empty) indent(s);
    putc_unlocked(object ? '}' : ']', s->f);
    s->in_obj = saved & 1u;
    s->first = false;
}

cnStatus cn_json_write_streamed(FILE *f, void *json, int precision, const char *key,
                                cnJsonStreamFn write, void *ctx) {
    json_t *o = json;
    if (!json_is_object(o) || json_object_set_new(o, key, json_string(PLACEHOLDER))) {
        json_decref(o);
        return CN_ERR_MEMORY;
    }
    json_t *doc = json_object();
    bool ok = doc && !json_object_set_new(doc, "format_version", json_integer(CN_JSON_FORMAT_VERSION)) &&
              !json_object_update(doc, o);
    json_decref(o);
    char *text = ok ? json_dumps(doc, JSON_INDENT(2) | JSON_REAL_PRECISION(precision)) : NULL;
    json_decref(doc);
    if (!text) return CN_ERR_MEMORY;
    /* the key at the top level: a new line, two spaces, the key, the placeholder */
    size_t klen = strlen(key), plen = strlen(PLACEHOLDER_DUMPED);
    char *at = NULL;
    for (char *p = strstr(text, "\n  \""); p; p = strstr(p + 1, "\n  \"")) {
        if (!strncmp(p + 4, key, klen) && !strncmp(p + 4 + klen, "\": ", 3) &&
            !strncmp(p + 7 + klen, PLACEHOLDER_DUMPED, plen)) {
            at = p + 7 + klen;
            break;
        }
    }
    if (!at) { /* cannot happen (the key was set above): a failed dump, as jansson's are */
        free(text);
        return CN_ERR_MEMORY;
    }
    fwrite(text, 1, (size_t)(at - text), f);
    cnJsonStream s = {f, precision, 1, true, true};
    flockfile(f);
    write(&s, ctx);
    funlockfile(f);
    fprintf(f, "%s\n", at + plen);
    free(text);
    return CN_OK;
}
