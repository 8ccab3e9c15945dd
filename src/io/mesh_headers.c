/* PLY and OFF files checked before Assimp reads them, as Assimp reads them: a header not
 * understood is refused; the counts it declares are checked against the file's size, each list's
 * count against what is left of its line (PLY text) or of the file (PLY binary), and each face of
 * an OFF file, since Assimp allocates before it reads and trusts what it reads. */
#include <stdbool.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>

#include "io.h"

/* Elements a header may declare, and properties an element may have. */
#define PLY_MAX 64

typedef struct {
    double count;
    int nprop;
    int size[PLY_MAX];    /* a scalar's bytes, or a list's items' bytes */
    int csize[PLY_MAX];   /* a list's count's bytes; 0 for a scalar */
    bool csign[PLY_MAX];  /* the list's count has a signed type */
} PlyElement;

typedef struct {
    int format;           /* 1 text, 2 binary little endian, 3 binary big endian */
    int ne;
    PlyElement el[PLY_MAX];
    size_t data;          /* offset of the data, past end_header's line */
    size_t data_line;     /* the data's first line */
    double vertices, faces; /* the counts of elements vertex and face */
} PlyHeader;

/* A line of buf from *at: [*a, *b) without its end ("\n", "\r\n" or "\r"), *at moved past it.
 * false at the end of buf. */
static bool next_line(const char *buf, size_t len, size_t *at, size_t *a, size_t *b) {
    if (*at >= len) return false;
    size_t i = *at;
    while (i < len && buf[i] != '\n' && buf[i] != '\r') i++;
    *a = *at, *b = i;
    if (i < len && buf[i] == '\r') i++;
    if (i < len && buf[i] == '\n' && (i == *b || buf[i - 1] == '\r')) i++;
    *at = i;
    return true;
}

/* The next blank-separated token of [*i, b): its start and length (0 at the line's end). */
static size_t next_token(const char *buf, size_t *i, size_t b, const char **t) {
    while (*i < b && (buf[*i] == ' ' || buf[*i] == '\t')) (*i)++;
    size_t j = *i;
    while (j < b && buf[j] != ' ' && buf[j] != '\t') j++;
    *t = buf + *i;
    size_t n = j - *i;
    *i = j;
    return n;
}

/* Split [a, b) into at most max tokens at blanks: their starts and lengths; the count, or max+1
 * when there are more. */
static int tokens(const char *buf, size_t a, size_t b, const char **t, size_t *n, int max) {
    int k = 0;
    const char *tk;
    for (size_t i = a, m; (m = next_token(buf, &i, b, &tk)) > 0; k++) {
        if (k == max) return max + 1;
        t[k] = tk, n[k] = m;
    }
    return k;
}

static bool word(const char *t, size_t n, const char *w) {
    return n == strlen(w) && !strncasecmp(t, w, n);
}

/* The header's last line, in the spec's case only: Assimp looks for it so, and runs on forever
 * through a file whose header ends otherwise. */
static bool end_header(const char *t, size_t n) { return n == 10 && !strncmp(t, "end_header", n); }

/* Bytes a property of this type takes in binary (0: not a type); *integer, *sign its kind. */
static int type_size(const char *t, size_t n, bool *integer, bool *sign) {
    static const struct { const char *name; int size; bool integer, sign; } types[] = {
        {"char", 1, 1, 1}, {"uchar", 1, 1, 0}, {"int8", 1, 1, 1}, {"uint8", 1, 1, 0},
        {"short", 2, 1, 1}, {"ushort", 2, 1, 0}, {"int16", 2, 1, 1}, {"uint16", 2, 1, 0},
        {"int", 4, 1, 1}, {"uint", 4, 1, 0}, {"int32", 4, 1, 1}, {"uint32", 4, 1, 0},
        {"float", 4, 0, 1}, {"float32", 4, 0, 1}, {"double", 8, 0, 1}, {"float64", 8, 0, 1}};
    for (size_t i = 0; i < sizeof types / sizeof types[0]; i++)
        if (word(t, n, types[i].name)) {
            if (integer) *integer = types[i].integer;
            if (sign) *sign = types[i].sign;
            return types[i].size;
        }
    return 0;
}

/* A token for a message: at most 24 characters, others than printable ASCII as '?'. */
static const char *shown_token(const char *t, size_t n, char out[32]) {
    size_t k = 0;
    for (; k < n && k < 24; k++) out[k] = t[k] >= 0x20 && t[k] < 0x7f ? t[k] : '?';
    if (n > 24) out[k++] = '.', out[k++] = '.', out[k++] = '.';
    out[k] = 0;
    return out;
}

/* A count in a mesh file's header: a decimal integer (as a double, so that 1e30 stays large);
 * -1 if not. */
static double count_of(const char *t, size_t n) {
    if (!t || n == 0 || n > 30) return -1;
    double v = 0;
    for (size_t i = 0; i < n; i++) {
        if (t[i] < '0' || t[i] > '9') return -1;
        v = 10 * v + (t[i] - '0');
    }
    return v;
}

#define FAIL(...) return cn_diag_set(diag, CN_ERR_INPUT, "", __VA_ARGS__)

/* Read the header into *h. CN_OK, or CN_ERR_INPUT naming the file and the line. */
static cnStatus read_header(const char *buf, size_t len, const char *shown, PlyHeader *h, cnDiag *diag) {
    size_t at = 0, a = 0, b = 0, line = 0;
    bool bad = false, ctrl = false;
    const char *t[6];
    size_t n[6];
    char s1[32], s2[32];
    h->format = 0, h->ne = -1, h->vertices = h->faces = 0, h->data = 0, h->data_line = 0;
    while (next_line(buf, len, &at, &a, &b)) {
        line++;
        for (size_t i = a; i < b && !ctrl; i++) ctrl = (unsigned char)buf[i] < 0x20 && buf[i] != '\t';
        if (ctrl) {
            bad = true;
            break;
        }
        int k = tokens(buf, a, b, t, n, 5);
        if (line == 1) {
            if (k != 1 || !word(t[0], n[0], "ply"))
                FAIL("the mesh file '%s' does not start with a line 'ply'; give a PLY file", shown);
            continue;
        }
        if (k == 0) continue;
        if (word(t[0], n[0], "comment") || word(t[0], n[0], "obj_info")) continue;
        if (end_header(t[0], n[0])) {
            if (k != 1) { bad = true; break; }
            if (h->format == 0)
                FAIL("the mesh file '%s' has no format line in its PLY header; add 'format ascii 1.0' "
                     "or a binary one", shown);
            h->data = at, h->data_line = line + 1;
            return CN_OK;
        }
        if (word(t[0], n[0], "format")) {
            if (k != 3) { bad = true; break; }
            h->format = word(t[1], n[1], "ascii") ? 1 : word(t[1], n[1], "binary_little_endian") ? 2
                      : word(t[1], n[1], "binary_big_endian") ? 3 : 0;
            if (h->format == 0)
                FAIL("the mesh file '%s' has the PLY format '%s' on line %zu; write ascii, "
                     "binary_little_endian or binary_big_endian", shown, shown_token(t[1], n[1], s1), line);
            continue;
        }
        if (word(t[0], n[0], "element")) {
            if (k != 3) { bad = true; break; }
            double c = count_of(t[2], n[2]);
            if (c < 0)
                FAIL("the mesh file '%s': the count '%s' of element '%s' on line %zu is not a whole "
                     "number; write how many there are", shown, shown_token(t[2], n[2], s1),
                     shown_token(t[1], n[1], s2), line);
            if (++h->ne >= PLY_MAX)
                FAIL("the mesh file '%s' declares more than %d elements in its PLY header (line %zu); "
                     "cairn reads at most %d", shown, PLY_MAX, line, PLY_MAX);
            h->el[h->ne].count = c, h->el[h->ne].nprop = 0;
            if (word(t[1], n[1], "vertex")) h->vertices = c;
            if (word(t[1], n[1], "face")) h->faces = c;
            continue;
        }
        if (word(t[0], n[0], "property")) {
            if (h->ne < 0)
                FAIL("the mesh file '%s': the property on line %zu of its PLY header comes before any "
                     "element; declare its element first", shown, line);
            PlyElement *e = &h->el[h->ne];
            if (e->nprop >= PLY_MAX)
                FAIL("the mesh file '%s': an element has more than %d properties (line %zu); cairn "
                     "reads at most %d", shown, PLY_MAX, line, PLY_MAX);
            bool integer = false, sign = false;
            int p = e->nprop, sz, cs = 0;
            if (k == 5 && word(t[1], n[1], "list")) {
                cs = type_size(t[2], n[2], &integer, &sign);
                if (!cs || !integer)
                    FAIL("the mesh file '%s': the list count type '%s' on line %zu is not an integer "
                         "type; write uchar, ushort or uint", shown, shown_token(t[2], n[2], s1), line);
                sz = type_size(t[3], n[3], NULL, NULL);
                if (!sz) FAIL("the mesh file '%s': '%s' on line %zu is not a PLY type; write one of "
                              "char, uchar, short, ushort, int, uint, float, double", shown,
                              shown_token(t[3], n[3], s1), line);
            } else if (k == 3) {
                sz = type_size(t[1], n[1], NULL, NULL);
                if (!sz) FAIL("the mesh file '%s': '%s' on line %zu is not a PLY type; write one of "
                              "char, uchar, short, ushort, int, uint, float, double", shown,
                              shown_token(t[1], n[1], s1), line);
            } else {
                bad = true;
                break;
            }
            e->size[p] = sz, e->csize[p] = cs, e->csign[p] = sign, e->nprop++;
            continue;
        }
        bad = true;
        break;
    }
    /* a header without end_header runs into the data: say what is missing */
    bool ends = false;
    for (size_t i = 0, p, q; !ends && next_line(buf, len, &i, &p, &q);) {
        while (p < q && (buf[p] == ' ' || buf[p] == '\t')) p++;
        while (q > p && (buf[q - 1] == ' ' || buf[q - 1] == '\t')) q--;
        ends = end_header(buf + p, q - p);
    }
    if (!bad || !ends)
        FAIL("the mesh file '%s' starts a PLY header but has no end_header line; end the header "
             "with it (in lower case)", shown);
    if (ctrl)
        FAIL("the mesh file '%s': line %zu of its PLY header holds a control character; write the "
             "header as plain text", shown, line);
    FAIL("the mesh file '%s': line %zu of its PLY header ('%s') is not a PLY header line; write "
         "format, element, property, comment or end_header lines", shown, line,
         shown_token(buf + a, b - a, s1));
}

/* A list's count of cs bytes at p, as Assimp takes it: an unsigned 32-bit integer, a signed
 * type's negative value wrapped. */
static double binary_count(const unsigned char *p, int cs, bool sign, bool be) {
    double v = 0;
    for (int i = 0; i < cs; i++) v = 256 * v + p[be ? i : cs - 1 - i];
    double top = (double)(1ull << (8 * cs - 1));
    if (sign && v >= top) v += 4294967296.0 - 2 * top; /* sign-extended to 32 bits */
    return v;
}

/* The least bytes the declared data takes: a digit and a separator per text value, its type's
 * bytes per binary value (lists at their counts' bytes). */
static double least_bytes(const PlyHeader *h) {
    double need = 0;
    for (int e = 0; e <= h->ne; e++) {
        double per = 0;
        for (int p = 0; p < h->el[e].nprop; p++)
            per += h->format == 1 ? 2 : h->el[e].csize[p] ? h->el[e].csize[p] : h->el[e].size[p];
        need += h->el[e].count * per;
    }
    return need;
}

/* Check one text element (a line, [a, b), line number line): each list's count must be a whole
 * number of at most the tokens left on the line. */
static cnStatus text_element(const char *buf, size_t a, size_t b, size_t line, const PlyElement *el,
                             const char *shown, cnDiag *diag) {
    size_t i = a;
    for (int p = 0; p < el->nprop; p++) {
        const char *t;
        size_t n = next_token(buf, &i, b, &t);
        if (n == 0) return CN_OK; /* the line ends: Assimp takes defaults */
        if (!el->csize[p]) continue;
        char s1[32];
        double c = count_of(t, n);
        if (c < 0)
            FAIL("the mesh file '%s': the list count '%s' on line %zu is not a whole number; write "
                 "how many items follow", shown, shown_token(t, n, s1), line);
        double left = 0; /* the list's items, skipped */
        while (left < c && next_token(buf, &i, b, &t) > 0) left++;
        if (left < c)
            FAIL("the mesh file '%s' declares a list of %.17g items on line %zu, more than the line "
                 "holds after it (%.17g); fix that count", shown, c, line, left);
    }
    return CN_OK;
}

cnStatus cn_ply_check(const char *buf, size_t len, const char *shown, cnDiag *diag) {
    PlyHeader h;
    cnStatus s = read_header(buf, len, shown, &h, diag);
    if (s) return s;
    double need = least_bytes(&h);
    if (need > (double)(len - h.data))
        FAIL("the mesh file '%s' declares %.17g vert%s and %.17g face%s, more than the %zu bytes after "
             "its header can hold (%.3g at the least); fix the counts in its header", shown, h.vertices,
             h.vertices == 1 ? "ex" : "ices", h.faces, h.faces == 1 ? "" : "s", len - h.data, need);
    size_t at = h.data, line = h.data_line - 1;
    for (int e = 0; e <= h.ne; e++) {
        const PlyElement *el = &h.el[e];
        /* the declared counts fit the file, so this loop is bounded by its size */
        for (double item = 0; item < el->count; item++) {
            if (h.format == 1) { /* text: an element per line, as Assimp reads it */
                size_t a, b;
                if (!next_line(buf, len, &at, &a, &b)) return CN_OK; /* short: Assimp says so */
                if ((s = text_element(buf, a, b, ++line, el, shown, diag))) return s;
                continue;
            }
            for (int p = 0; p < el->nprop; p++) {
                int cs = el->csize[p];
                if (at >= len || len - at < (size_t)(cs ? cs : el->size[p])) return CN_OK; /* short */
                if (!cs) {
                    at += (size_t)el->size[p];
                    continue;
                }
                double c = binary_count((const unsigned char *)buf + at, cs, el->csign[p], h.format == 3);
                if (c * el->size[p] > (double)(len - at - (size_t)cs))
                    FAIL("the mesh file '%s' declares a list of %.17g items at byte %zu, more than the "
                         "rest of its %zu bytes can hold; fix that count", shown, c, at, len);
                at += (size_t)cs + (size_t)c * (size_t)el->size[p];
            }
        }
    }
    return CN_OK;
}

/* OFF, as Assimp reads it: a first token [ST][C][N][4][n]OFF, or none (the counts first); the
 * counts of vertices, faces and edges (blanks, line ends and '#' lines between tokens); then a
 * line per vertex and per face, blank lines skipped, the file ending at its first NUL. */

/* Assimp copies each data line into a buffer of this many bytes. */
#define OFF_LINE_MAX 4096
/* Assimp skips faces of more vertices than this. */
#define OFF_FACE_MAX 9

/* The next header token from *at: blanks, line ends and lines starting with '#' skipped. */
static size_t off_token(const char *buf, size_t len, size_t *at, const char **t) {
    size_t i = *at;
    for (;;) {
        while (i < len && (buf[i] == ' ' || buf[i] == '\t' || buf[i] == '\n' || buf[i] == '\r')) i++;
        if (i < len && buf[i] == '#') {
            while (i < len && buf[i] != '\n' && buf[i] != '\r') i++;
            continue;
        }
        break;
    }
    size_t j = i;
    while (j < len && buf[j] != ' ' && buf[j] != '\t' && buf[j] != '\n' && buf[j] != '\r') j++;
    *t = buf + i, *at = j;
    return j - i;
}

/* The 1-based line of offset at. */
static size_t line_of(const char *buf, size_t at) {
    size_t line = 1;
    for (size_t i = 0; i < at; i++) line += buf[i] == '\n' || (buf[i] == '\r' && (i + 1 == at || buf[i + 1] != '\n'));
    return line;
}

/* The next data line from *at ([*a, *b)), the line ends after it skipped; false at the end. */
static bool off_line(const char *buf, size_t len, size_t *at, size_t *a, size_t *b) {
    if (*at >= len) return false;
    size_t i = *at;
    while (i < len && buf[i] != '\n' && buf[i] != '\r' && buf[i] != '\f') i++;
    *a = *at, *b = i;
    while (i < len && (buf[i] == '\n' || buf[i] == '\r' || buf[i] == '\f')) i++;
    *at = i;
    return true;
}

cnStatus cn_off_check(const char *buf, size_t len, const char *shown, cnDiag *diag) {
    const void *nul = memchr(buf, 0, len);
    if (nul) len = (size_t)((const char *)nul - buf);
    size_t at = 0;
    const char *t;
    size_t n = off_token(buf, len, &at, &t);
    char s1[32];
    double dims = 3;
    if (n > 0 && t[0] >= '0' && t[0] <= '9') {
        at = (size_t)(t - buf); /* no keyword: the counts come first */
    } else {
        size_t k = 0;
        bool dim = false;
        if (k + 1 < n && t[k] == 'S' && t[k + 1] == 'T') k += 2;
        if (k < n && t[k] == 'C') k++;
        if (k < n && t[k] == 'N') k++;
        if (k < n && t[k] == '4') k++;
        if (k < n && t[k] == 'n') k++, dim = true;
        if (n != k + 3 || strncmp(t + k, "OFF", 3))
            FAIL("the mesh file '%s' does not start with OFF (or a variant such as COFF) or with its "
                 "counts; give an OFF file", shown);
        if (dim) {
            n = off_token(buf, len, &at, &t);
            dims = count_of(t, n);
            if (dims < 0 || dims > 3)
                FAIL("the mesh file '%s': the dimension '%s' on line %zu is not 1, 2 or 3", shown,
                     shown_token(t, n, s1), line_of(buf, (size_t)(t - buf)));
        }
    }
    static const char *const what[3] = {"vertices", "faces", "edges"};
    double c[3];
    for (int k = 0; k < 3; k++) {
        n = off_token(buf, len, &at, &t);
        c[k] = count_of(t, n);
        if (c[k] < 0)
            FAIL("the mesh file '%s': the count of %s '%s' on line %zu is not a whole number; write "
                 "the counts of vertices, faces and edges", shown, what[k], shown_token(t, n, s1),
                 line_of(buf, (size_t)(t - buf)));
    }
    off_token(buf, len, &at, &t);
    at = (size_t)(t - buf); /* the data: Assimp moves to the next token */
    /* "x y z\n", "3 a b c\n" at the least */
    if (c[0] * 6 + c[1] * 8 > (double)(len - at))
        FAIL("the mesh file '%s' declares %.17g vert%s and %.17g face%s, more than the %zu bytes after "
             "its header can hold (%.3g at the least); fix the counts in its header", shown, c[0],
             c[0] == 1 ? "ex" : "ices", c[1], c[1] == 1 ? "" : "s", len - at, c[0] * 6 + c[1] * 8);
    size_t a, b;
    for (double i = 0; i < c[0] + c[1]; i++) {
        if (!off_line(buf, len, &at, &a, &b)) return CN_OK; /* short: Assimp says so */
        if (b - a >= OFF_LINE_MAX)
            FAIL("the mesh file '%s': line %zu is longer than %d characters; Assimp reads no more",
                 shown, line_of(buf, a), OFF_LINE_MAX - 1);
        if (i < c[0]) continue;
        size_t q = a;
        n = next_token(buf, &q, b, &t);
        double k = count_of(t, n);
        if (k < 3 || k > OFF_FACE_MAX)
            FAIL("the mesh file '%s': the face on line %zu starts with '%s', not a count of 3 to %d "
                 "vertices; write the count, then the vertices' indices", shown, line_of(buf, a),
                 shown_token(t, n, s1), OFF_FACE_MAX);
        for (double v = 0; v < k; v++) {
            n = next_token(buf, &q, b, &t);
            double x = count_of(t, n);
            if (n == 0)
                FAIL("the mesh file '%s': the face on line %zu has %.17g of its %.17g indices; write "
                     "them all", shown, line_of(buf, a), v, k);
            if (x < 0 || x >= c[0])
                FAIL("the mesh file '%s': the face on line %zu names the vertex '%s', but the file has "
                     "vertices 0 to %.17g", shown, line_of(buf, a), shown_token(t, n, s1), c[0] - 1);
        }
    }
    return CN_OK;
}
