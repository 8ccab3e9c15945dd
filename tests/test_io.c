/* COMPAS blocks to cairn (compas.c), closed meshes (mesh3.c) and 2-D polygon splits (split2.c),
 * against closed-form volumes, centroids and inertias, brute-force references written here
 * (segment crossings, point membership sampled at random), and rigid-motion invariance. */
#include <stdlib.h>
#include <string.h>

#include "test.h"
#include "cairn/cairn.h"
#include "io.h"

#define SHAPE_MAXV 64
#define SHAPE_MAXF 64
#define SHAPE_MAXI 256

/* A closed surface given as vertices and face loops (face f: idx[first .. first + len[f] - 1]). */
typedef struct {
    int nv, nf, ni;
    double v[SHAPE_MAXV][3];
    int len[SHAPE_MAXF];
    int idx[SHAPE_MAXI];
} Shape;

static void shape_face(Shape *s, int n, const int *loop) {
    s->len[s->nf++] = n;
    for (int k = 0; k < n; k++) s->idx[s->ni++] = loop[k];
}

/* The first index of face f in idx. */
static int shape_first(const Shape *s, int f) {
    int k = 0;
    for (int g = 0; g < f; g++) k += s->len[g];
    return k;
}

/* An a x b x c box with its low corner at o; vertex i is at (i & 1, i & 2, i & 4) scaled; faces
 * counter-clockwise seen from outside. */
static void shape_box(Shape *s, double a, double b, double c, const double o[3]) {
    memset(s, 0, sizeof *s);
    for (int i = 0; i < 8; i++) {
        s->v[i][0] = o[0] + ((i & 1) ? a : 0);
        s->v[i][1] = o[1] + ((i & 2) ? b : 0);
        s->v[i][2] = o[2] + ((i & 4) ? c : 0);
    }
    static const int f[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                                {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    s->nv = 8;
    for (int k = 0; k < 6; k++) shape_face(s, 4, f[k]);
}

/* The prism over a counter-clockwise polygon (n points) from z = 0 to z = h. */
static void shape_prism(Shape *s, const double (*p)[2], int n, double h) {
    memset(s, 0, sizeof *s);
    int loop[SHAPE_MAXV] = {0};
    for (int i = 0; i < n; i++) {
        s->v[i][0] = s->v[n + i][0] = p[i][0];
        s->v[i][1] = s->v[n + i][1] = p[i][1];
        s->v[i][2] = 0, s->v[n + i][2] = h;
    }
    s->nv = 2 * n;
    for (int i = 0; i < n; i++) loop[i] = n - 1 - i; /* bottom, seen from below */
    shape_face(s, n, loop);
    for (int i = 0; i < n; i++) loop[i] = n + i;
    shape_face(s, n, loop);
    for (int i = 0; i < n; i++) {
        int q[4] = {i, (i + 1) % n, n + (i + 1) % n, n + i};
        shape_face(s, 4, q);
    }
}

/* The L: a x t along x and t x b along y, corner at the origin (area a t + t (b - t)). */
static void l_polygon(double a, double b, double t, double p[6][2]) {
    double q[6][2] = {{0, 0}, {a, 0}, {a, t}, {t, t}, {t, b}, {0, b}};
    memcpy(p, q, sizeof q);
}

/* The tetrahedron (0, 0, 0), (a, 0, 0), (0, b, 0), (0, 0, c): volume a b c / 6. */
static void shape_tetra(Shape *s, double a, double b, double c) {
    memset(s, 0, sizeof *s);
    double v[4][3] = {{0, 0, 0}, {a, 0, 0}, {0, b, 0}, {0, 0, c}};
    memcpy(s->v, v, sizeof v);
    s->nv = 4;
    static const int f[4][3] = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
    for (int k = 0; k < 4; k++) shape_face(s, 3, f[k]);
}

/* The icosahedron of edge 2 about the origin, vertex i then scaled by r[i] (NULL: 1): faces are
 * the triples of mutual distance 2, turned to face away from the origin (scaling along the rays
 * keeps that). */
static void shape_icosa(Shape *s, const double *r) {
    memset(s, 0, sizeof *s);
    const double g = (1 + sqrt(5.0)) / 2;
    int n = 0;
    for (int a = -1; a <= 1; a += 2)
        for (int b = -1; b <= 1; b += 2) {
            double v[3][3] = {{0, a, b * g}, {a, b * g, 0}, {b * g, 0, a}};
            for (int k = 0; k < 3; k++) memcpy(s->v[n++], v[k], sizeof v[k]);
        }
    s->nv = n;
    for (int i = 0; i < n; i++)
        for (int j = i + 1; j < n; j++)
            for (int k = j + 1; k < n; k++) {
                double d[3][3];
                cn_sub3(s->v[i], s->v[j], d[0]), cn_sub3(s->v[j], s->v[k], d[1]), cn_sub3(s->v[k], s->v[i], d[2]);
                if (fabs(cn_norm3(d[0]) - 2) > 1e-9 || fabs(cn_norm3(d[1]) - 2) > 1e-9 || fabs(cn_norm3(d[2]) - 2) > 1e-9)
                    continue;
                double e1[3], e2[3], nrm[3];
                cn_sub3(s->v[j], s->v[i], e1), cn_sub3(s->v[k], s->v[i], e2), cn_cross3(e1, e2, nrm);
                int loop[3] = {i, j, k};
                if (cn_dot3(nrm, s->v[i]) < 0) loop[1] = k, loop[2] = j;
                shape_face(s, 3, loop);
            }
    if (r)
        for (int i = 0; i < n; i++) cn_scale3(s->v[i], r[i]);
}

static void shape_reverse_face(Shape *s, int f) {
    int *q = &s->idx[shape_first(s, f)];
    for (int a = 0, b = s->len[f] - 1; a < b; a++, b--) {
        int t = q[a];
        q[a] = q[b], q[b] = t;
    }
}

/* A uniformly random rotation (unit quaternion from a ball sample) as a matrix. */
static void random_rotation(cnRng *rng, double R[3][3]) {
    double q[4], n2;
    do {
        n2 = 0;
        for (int k = 0; k < 4; k++) q[k] = cn_rng_range(rng, -1, 1), n2 += q[k] * q[k];
    } while (n2 > 1 || n2 < 0.01);
    double w = q[0] / sqrt(n2), x = q[1] / sqrt(n2), y = q[2] / sqrt(n2), z = q[3] / sqrt(n2);
    double M[3][3] = {{1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)},
                      {2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)},
                      {2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)}};
    memcpy(R, M, sizeof M);
}

static void rigid_apply(const double R[3][3], const double t[3], const double x[3], double out[3]) {
    double y[3];
    for (int i = 0; i < 3; i++) y[i] = R[i][0] * x[0] + R[i][1] * x[1] + R[i][2] * x[2] + t[i];
    cn_copy3(out, y);
}

/* The inverse: R^T (x - t). */
static void rigid_unapply(const double R[3][3], const double t[3], const double x[3], double out[3]) {
    double d[3];
    cn_sub3(x, t, d);
    for (int i = 0; i < 3; i++) out[i] = R[0][i] * d[0] + R[1][i] * d[1] + R[2][i] * d[2];
}

static void shape_move(Shape *s, const double R[3][3], const double t[3]) {
    for (int i = 0; i < s->nv; i++) rigid_apply(R, t, s->v[i], s->v[i]);
}

/* The shape as a cnMesh (arrays from cn_malloc, as cn_mesh_free frees them; faces numbered from 1). */
static cnMesh mesh_of(const Shape *s) {
    cnMesh m;
    memset(&m, 0, sizeof m);
    m.nverts = s->nv, m.nfaces = s->nf;
    m.verts = cn_malloc(sizeof(double[3]) * (size_t)(s->nv + 1));
    m.start = cn_malloc(sizeof(int) * (size_t)(s->nf + 1));
    m.idx = cn_malloc(sizeof(int) * (size_t)(s->ni + 1));
    m.face_id = cn_malloc(sizeof(int) * (size_t)(s->nf + 1));
    memcpy(m.verts, s->v, sizeof(double[3]) * (size_t)s->nv);
    memcpy(m.idx, s->idx, sizeof(int) * (size_t)s->ni);
    for (int f = 0, k = 0; f <= s->nf; k += f < s->nf ? s->len[f] : 0, f++) {
        m.start[f] = k;
        if (f < s->nf) m.face_id[f] = f + 1;
    }
    return m;
}

/* The length of the diagonal of the shape's bounding box. */
static double shape_size(const Shape *s) {
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY}, d[3];
    for (int i = 0; i < s->nv; i++)
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], s->v[i][k]), hi[k] = fmax(hi[k], s->v[i][k]);
    cn_sub3(hi, lo, d);
    return cn_norm3(d);
}

/* ---- membership references ---- */

/* Crossing-number test for a polygon of n points; *edge gets the distance to its boundary. */
static bool in_polygon2(const double (*p)[2], int n, double x, double y, double *edge) {
    bool in = false;
    *edge = INFINITY;
    for (int i = 0, j = n - 1; i < n; j = i++) {
        if ((p[i][1] > y) != (p[j][1] > y) &&
            x < p[j][0] + (y - p[j][1]) * (p[i][0] - p[j][0]) / (p[i][1] - p[j][1]))
            in = !in;
        double ex = p[i][0] - p[j][0], ey = p[i][1] - p[j][1], L2 = ex * ex + ey * ey;
        double t = fmax(0, fmin(1, ((x - p[j][0]) * ex + (y - p[j][1]) * ey) / L2));
        *edge = fmin(*edge, hypot(x - p[j][0] - t * ex, y - p[j][1] - t * ey));
    }
    return in;
}

/* Is x inside the convex piece (by its face planes)? *margin: the distance to the nearest plane
 * of those that decide. */
static bool in_piece(const cnPiece *pc, const double x[3], double *margin) {
    double worst = -INFINITY;
    for (int f = 0; f < pc->nfaces; f++)
        worst = fmax(worst, cn_dot3(pc->faces[f].normal, x) - pc->faces[f].offset);
    *margin = fabs(worst);
    return worst < 0;
}

/* Is x inside the star-shaped (about the origin) triangulated shape: does the ray from the origin
 * through x leave the surface beyond x? Moller-Trumbore on every face; *margin: the relative
 * distance of x from the surface along the ray, or 0 when the ray grazes an edge. */
static bool in_star(const Shape *s, const double x[3], double *margin) {
    *margin = 0;
    for (int f = 0; f < s->nf; f++) {
        const int *q = &s->idx[3 * f];
        const double *a = s->v[q[0]], *b = s->v[q[1]], *c = s->v[q[2]];
        double e1[3], e2[3], pv[3], tv[3], qv[3];
        cn_sub3(b, a, e1), cn_sub3(c, a, e2), cn_cross3(x, e2, pv);
        double det = cn_dot3(e1, pv);
        if (fabs(det) < 1e-300) continue;
        double o[3] = {0, 0, 0};
        cn_sub3(o, a, tv);
        double u = cn_dot3(tv, pv) / det;
        cn_cross3(tv, e1, qv);
        double w = cn_dot3(x, qv) / det, t = cn_dot3(e2, qv) / det;
        if (u < -1e-9 || w < -1e-9 || u + w > 1 + 1e-9 || t <= 0) continue;
        if (u < 1e-6 || w < 1e-6 || u + w > 1 - 1e-6) return false; /* an edge: undecided */
        *margin = fabs(t - 1) / t;
        return t > 1;
    }
    return false;
}

/* ---- 1. COMPAS blocks ---- */

/* A COMPAS block mesh; coordinates equal to 0 left to default_vertex_attributes when `sparse`. */
static json_t *compas_block(const Shape *s, bool sparse) {
    json_t *vert = json_object(), *face = json_object();
    char k[32];
    for (int i = 0; i < s->nv; i++) {
        json_t *v = json_object();
        for (int c = 0; c < 3; c++)
            if (!sparse || s->v[i][c] != 0) json_object_set_new(v, c == 0 ? "x" : c == 1 ? "y" : "z", json_real(s->v[i][c]));
        snprintf(k, sizeof k, "%d", i);
        json_object_set_new(vert, k, v);
    }
    for (int f = 0, at = 0; f < s->nf; at += s->len[f], f++) {
        json_t *loop = json_array();
        for (int j = 0; j < s->len[f]; j++) json_array_append_new(loop, json_integer(s->idx[at + j]));
        snprintf(k, sizeof k, "%d", f);
        json_object_set_new(face, k, loop);
    }
    return json_pack("{s:s,s:{s:o,s:o,s:{s:f,s:f,s:f}}}", "dtype", "compas_assembly.datastructures/Block",
                     "data", "vertex", vert, "face", face, "default_vertex_attributes", "x", 0.0, "y", 0.0, "z", 0.0);
}

static json_t *compas_new(void) {
    return json_pack("{s:s,s:{s:{s:s},s:{s:s,s:{s:{s:n,s:b},s:{}}}}}", "dtype",
                     "compas_assembly.datastructures/Assembly", "data", "attributes", "name", "test", "graph",
                     "dtype", "compas.datastructures/Graph", "data", "default_node_attributes", "block",
                     "is_support", 0, "node");
}

static json_t *compas_nodes(json_t *root) {
    return json_object_get(json_object_get(json_object_get(json_object_get(root, "data"), "graph"), "data"), "node");
}

/* Add node `key` with the block (reference stolen; NULL: none) and is_support (NULL: absent). */
static void compas_add(json_t *root, const char *key, json_t *block, json_t *is_support) {
    json_t *node = json_object();
    if (block) json_object_set_new(node, "block", block);
    if (is_support) json_object_set_new(node, "is_support", is_support);
    json_object_set_new(compas_nodes(root), key, node);
}

/* The converted document's part named key, or NULL. */
static const json_t *doc_part(const json_t *doc, const char *key) {
    const json_t *parts = json_object_get(doc, "parts");
    for (size_t i = 0; i < json_array_size(parts); i++) {
        const char *n = json_string_value(json_object_get(json_array_get(parts, i), "name"));
        if (n && !strcmp(n, key)) return json_array_get(parts, i);
    }
    return NULL;
}

/* Convert and load; NULL (a failure counted) when either fails. */
static cnAssembly *compas_load(const json_t *root, const char *supports, json_t **doc_out) {
    cnDiag d;
    cn_diag_clear(&d);
    json_t *doc = cn_compas_to_cairn(root, supports, 1e-6, &d);
    CHECK_MSG(doc != NULL, "conversion failed: %s: %s", d.where, d.message);
    if (!doc) return NULL;
    char *text = json_dumps(doc, JSON_COMPACT);
    cnAssembly *a = NULL;
    cnStatus st = cn_assembly_load_string(text, "compas", &a, &d);
    CHECK_MSG(st == CN_OK, "load of the converted document failed: %s: %s", d.where, d.message);
    free(text);
    if (doc_out) *doc_out = doc;
    else json_decref(doc);
    return a;
}

/* The analytic mass properties of a union of disjoint axis-aligned boxes (dims[k], centres
 * ctr[k]) moved by (R, t): volume, centroid and second moment about the centroid. */
static void boxes_moments(int n, const double (*dims)[3], const double (*ctr)[3], const double R[3][3],
                          const double t[3], double *vol, double com[3], double S[3][3]) {
    double V = 0, c[3] = {0, 0, 0}, L[3][3] = {{0}};
    for (int k = 0; k < n; k++) {
        double v = dims[k][0] * dims[k][1] * dims[k][2];
        V += v;
        for (int i = 0; i < 3; i++) c[i] += v * ctr[k][i];
    }
    for (int i = 0; i < 3; i++) c[i] /= V;
    for (int k = 0; k < n; k++) { /* own moment plus the parallel-axis term */
        double v = dims[k][0] * dims[k][1] * dims[k][2], d[3];
        cn_sub3(ctr[k], c, d);
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 3; j++) L[i][j] += v * d[i] * d[j] + (i == j ? v * dims[k][i] * dims[k][i] / 12 : 0);
    }
    /* rotated: R L R^T */
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            S[i][j] = 0;
            for (int p = 0; p < 3; p++)
                for (int q = 0; q < 3; q++) S[i][j] += R[i][p] * L[p][q] * R[j][q];
        }
    rigid_apply(R, t, c, com);
    *vol = V;
}

/* The part's size, com and inertia against a body of volume V, centroid c, second moment S. */
static void check_part_mass(const cnPart *p, double V, const double c[3], const double S[3][3], double scale,
                            const char *what) {
    CHECK_MSG(fabs(p->size - V) <= 1e-9 * V, "%s: volume %.17g, want %.17g", what, p->size, V);
    for (int k = 0; k < 3; k++)
        CHECK_MSG(fabs(p->com[k] - c[k]) <= 1e-9 * scale, "%s: com[%d] %.17g, want %.17g", what, k, p->com[k], c[k]);
    if (p->fixed) return; /* a support has no mass */
    double rho = p->mass / p->size, tr = S[0][0] + S[1][1] + S[2][2], worst = 0, norm = 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            double want = rho * ((i == j ? tr : 0) - S[i][j]);
            worst = fmax(worst, fabs(p->inertia[i][j] - want));
            norm = fmax(norm, fabs(want));
        }
    CHECK_MSG(worst <= 1e-8 * norm, "%s: inertia off by %.3g of %.3g", what, worst, norm);
}

/* Sample points in the part's box: exactly one piece holds each point inside the body, none one
 * outside (inside: body(x, &margin)), points within 1e-6 of a boundary skipped. */
static void check_tiling(const cnPiece *pcs, int np, bool (*body)(const void *, const double *, double *),
                         const void *ctx, const double lo[3], const double hi[3], cnRng *rng, int samples,
                         const char *what) {
    int bad = 0, tested = 0;
    double scale = 0;
    for (int k = 0; k < 3; k++) scale = fmax(scale, hi[k] - lo[k]);
    for (int s = 0; s < samples; s++) {
        double x[3], m;
        for (int k = 0; k < 3; k++) x[k] = cn_rng_range(rng, lo[k], hi[k]);
        bool in = body(ctx, x, &m);
        if (m < 1e-6 * scale) continue;
        int holders = 0;
        bool near = false;
        for (int i = 0; i < np; i++) {
            double pm;
            holders += in_piece(&pcs[i], x, &pm);
            near |= pm < 1e-6 * scale;
        }
        if (near) continue;
        tested++;
        if (holders != (in ? 1 : 0)) {
            if (!bad) fprintf(stderr, "%s: (%g, %g, %g) is %s, in %d pieces\n", what, x[0], x[1], x[2], in ? "inside" : "outside", holders);
            bad++;
        }
    }
    CHECK_MSG(bad == 0, "%s: %d of %d sample points misplaced", what, bad, tested);
    CHECK_MSG(tested > samples / 2, "%s: only %d of %d points decided", what, tested, samples);
}

/* A prism over a polygon, moved by (R, t), as a membership reference. */
typedef struct {
    const double (*p)[2];
    int n;
    double h;
    const double (*R)[3];
    const double *t;
} PrismBody;

static bool in_prism(const void *ctx, const double *x, double *margin) {
    const PrismBody *b = ctx;
    double y[3], edge;
    rigid_unapply(b->R, b->t, x, y);
    bool in = in_polygon2(b->p, b->n, y[0], y[1], &edge) && y[2] > 0 && y[2] < b->h;
    *margin = fmin(edge, fmin(fabs(y[2]), fabs(y[2] - b->h)));
    return in;
}

static bool in_star_body(const void *ctx, const double *x, double *margin) {
    bool in = in_star(ctx, x, margin);
    *margin *= cn_norm3(x);
    return in;
}

/* Is x (within tol) a vertex of one of the pieces? */
static bool piece_vertex(const cnPiece *pcs, int np, const double x[3], double tol) {
    for (int i = 0; i < np; i++)
        for (int v = 0; v < pcs[i].nverts; v++) {
            double d[3];
            cn_sub3(pcs[i].verts[v], x, d);
            if (cn_norm3(d) <= tol) return true;
        }
    return false;
}

/* A box block (convex: one "hull" of its 8 vertices) and an L block (not convex: "hulls"), each
 * under a random rigid motion: volume, com and inertia against the closed forms, the L's pieces
 * tile it (sampled), every corner of the L is a corner of a piece, supports from is_support. */
static void test_compas_blocks(void) {
    cnRng rng = {0x9e3779b97f4a7c15ULL};
    const double I3[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    for (int trial = 0; trial < 3; trial++) {
        double R[3][3], t[3];
        if (trial == 0) memcpy(R, I3, sizeof R), memset(t, 0, sizeof t);
        else {
            random_rotation(&rng, R);
            for (int k = 0; k < 3; k++) t[k] = cn_rng_range(&rng, -50, 50);
        }
        /* the support: a slab well below; the box 3 x 2 x 1.5; the L off to the side */
        double a = 3, b = 2, c = 1.5, o[3] = {0, 0, 0}, so[3] = {-20, -20, -20};
        Shape sup, box, L;
        shape_box(&sup, 10, 10, 1, so);
        shape_box(&box, a, b, c, o);
        double lp[6][2], la = 4, lb = 3, lt = 1, lh = 2;
        l_polygon(la, lb, lt, lp);
        shape_prism(&L, (const double(*)[2])lp, 6, lh);
        double lt3[3] = {10, 0, 0};
        shape_move(&L, I3, lt3);
        shape_move(&sup, (const double(*)[3])R, t), shape_move(&box, (const double(*)[3])R, t);
        shape_move(&L, (const double(*)[3])R, t);

        json_t *root = compas_new();
        compas_add(root, "base", compas_block(&sup, false), json_true());
        compas_add(root, "box", compas_block(&box, trial == 0), NULL); /* sparse: defaults used */
        compas_add(root, "L", compas_block(&L, false), json_false());
        json_t *doc = NULL;
        cnAssembly *as = compas_load(root, NULL, &doc);
        if (!as) {
            json_decref(doc);
            json_decref(root);
            continue;
        }
        /* the document: a hull for the convex blocks, hulls for the L, supports from is_support */
        const json_t *pb = doc_part(doc, "box"), *pl = doc_part(doc, "L"), *ps = doc_part(doc, "base");
        CHECK(pb && pl && ps);
        CHECK(json_array_size(json_object_get(doc, "parts")) == 3);
        if (pb && pl && ps) {
            CHECK(json_is_true(json_object_get(ps, "fixed")));
            CHECK(json_is_false(json_object_get(pb, "fixed")));
            CHECK(json_is_false(json_object_get(pl, "fixed")));
            const json_t *hull = json_object_get(pb, "hull");
            CHECK(json_array_size(hull) == 8 && !json_object_get(pb, "hulls"));
            /* the hull's points are the box's corners, as a set */
            int matched = 0;
            for (int i = 0; i < 8; i++)
                for (size_t j = 0; j < json_array_size(hull); j++) {
                    const json_t *q = json_array_get(hull, j);
                    double d = 0;
                    for (int k = 0; k < 3; k++) d = fmax(d, fabs(json_number_value(json_array_get(q, (size_t)k)) - box.v[i][k]));
                    if (d <= 1e-12 * 100) {
                        matched++;
                        break;
                    }
                }
            CHECK_MSG(matched == 8, "trial %d: %d of the box's corners in its hull", trial, matched);
            CHECK(json_array_size(json_object_get(pl, "hulls")) >= 2 && !json_object_get(pl, "hull"));
        }
        int ib = cn_assembly_find_part(as, "box"), il = cn_assembly_find_part(as, "L"), is = cn_assembly_find_part(as, "base");
        CHECK(ib >= 0 && il >= 0 && is >= 0);
        if (ib >= 0 && il >= 0 && is >= 0) {
            CHECK(as->parts[is].fixed && !as->parts[ib].fixed && !as->parts[il].fixed);
            double V, com[3], S[3][3];
            double bdim[1][3] = {{a, b, c}}, bctr[1][3] = {{a / 2, b / 2, c / 2}};
            boxes_moments(1, (const double(*)[3])bdim, (const double(*)[3])bctr, (const double(*)[3])R, t, &V, com, S);
            check_part_mass(&as->parts[ib], V, com, (const double(*)[3])S, 60, "box");
            /* the L: the 4 x 1 bar plus the 1 x 2 bar on it, 2 high, moved by 10 along x first */
            double ldim[2][3] = {{la, lt, lh}, {lt, lb - lt, lh}};
            double lctr[2][3] = {{10 + la / 2, lt / 2, lh / 2}, {10 + lt / 2, lt + (lb - lt) / 2, lh / 2}};
            boxes_moments(2, (const double(*)[3])ldim, (const double(*)[3])lctr, (const double(*)[3])R, t, &V, com, S);
            CHECK_NEAR(V, (la * lt + lt * (lb - lt)) * lh, 1e-12); /* (4 + 2) * 2 = 12 */
            check_part_mass(&as->parts[il], V, com, (const double(*)[3])S, 60, "L");
            const cnPart *p = &as->parts[il];
            CHECK(p->npieces >= 2);
            for (int i = 0; i < L.nv; i++)
                CHECK_MSG(piece_vertex(p->pieces, p->npieces, L.v[i], 1e-9 * 60), "trial %d: L corner %d is no piece's vertex", trial, i);
            double lt_full[3]; /* the L's frame: (R, R (10, 0, 0) + t) */
            rigid_apply((const double(*)[3])R, t, lt3, lt_full);
            PrismBody body = {(const double(*)[2])lp, 6, lh, (const double(*)[3])R, lt_full};
            check_tiling(p->pieces, p->npieces, in_prism, &body, p->lo, p->hi, &rng, 3000, "compas L");
            /* the support: 10 x 10 x 1 */
            CHECK_NEAR(as->parts[is].size, 100, 1e-9 * 100);
        }
        cn_assembly_free(as);
        json_decref(doc);
        json_decref(root);
    }
}

/* The same block given as a COMPAS mesh and as cairn's own box, and an L with its faces all
 * turned inward (consistently): the same volume, com and inertia. */
static void test_compas_second_formulation(void) {
    double o[3] = {1, 2, 3}, so[3] = {0, 0, -1};
    Shape box, sup, L;
    shape_box(&box, 2, 1, 0.5, o);
    shape_box(&sup, 6, 6, 1, so);
    double lp[6][2];
    l_polygon(2, 2, 0.5, lp);
    shape_prism(&L, (const double(*)[2])lp, 6, 1);
    for (int f = 0; f < L.nf; f++) shape_reverse_face(&L, f);
    json_t *root = compas_new();
    compas_add(root, "0", compas_block(&sup, false), NULL);
    compas_add(root, "1", compas_block(&box, false), NULL);
    compas_add(root, "2", compas_block(&L, false), NULL);
    cnAssembly *a = compas_load(root, "0", NULL);
    cnAssembly *b = NULL;
    cnDiag d;
    CHECK_MSG(cn_assembly_load_string("{\"dimension\":3,\"parts\":[{\"name\":\"0\",\"fixed\":true,\"box\":"
                                      "{\"min\":[0,0,-1],\"max\":[6,6,0]}},{\"name\":\"1\",\"box\":{\"min\":[1,2,3],"
                                      "\"max\":[3,3,3.5]}},{\"name\":\"2\",\"hulls\":[[[0,0,0],[2,0,0],[2,0.5,0],"
                                      "[0,0.5,0],[0,0,1],[2,0,1],[2,0.5,1],[0,0.5,1]],[[0,0.5,0],[0.5,0.5,0],"
                                      "[0.5,2,0],[0,2,0],[0,0.5,1],[0.5,0.5,1],[0.5,2,1],[0,2,1]]]}]}",
                                      "cairn", &b, &d) == CN_OK,
              "%s: %s", d.where, d.message);
    if (a && b) {
        for (int i = 0; i < 3; i++) {
            int ia = cn_assembly_find_part(a, b->parts[i].name);
            CHECK_MSG(ia >= 0, "no part %s", b->parts[i].name);
            if (ia < 0) continue;
            const cnPart *p = &a->parts[ia], *q = &b->parts[i];
            CHECK_MSG(p->fixed == q->fixed, "part %s", q->name);
            CHECK_MSG(fabs(p->size - q->size) <= 1e-12 * q->size, "part %s: %.17g vs %.17g", q->name, p->size, q->size);
            CHECK_MSG(fabs(p->mass - q->mass) <= 1e-12 * fmax(q->mass, 1), "part %s", q->name);
            for (int k = 0; k < 3; k++) {
                CHECK_NEAR(p->com[k], q->com[k], 1e-12);
                for (int j = 0; j < 3; j++) CHECK_NEAR(p->inertia[k][j], q->inertia[k][j], 1e-12);
            }
        }
        CHECK_NEAR(b->parts[2].size, 2 * 0.5 + 0.5 * 1.5, 1e-12); /* the reference itself */
    }
    cn_assembly_free(a);
    cn_assembly_free(b);
    json_decref(root);
}

/* Supports: the caller's list wins over is_support; default_node_attributes apply; a listed key
 * that is no node, no support at all, and a non-boolean is_support are refused. */
static void test_compas_supports(void) {
    Shape s[3];
    for (int i = 0; i < 3; i++) {
        double o[3] = {3.0 * i, 0, 0};
        shape_box(&s[i], 1, 1, 1, o);
    }
    const char *keys[3] = {"a", "b", "c"};
    struct {
        const char *supports;
        int is_sup[3]; /* -1 absent, 0 false, 1 true */
        int dflt;      /* default_node_attributes.is_support */
        int want[3];   /* -1: refused */
        const char *where;
    } cases[] = {
        {NULL, {1, 0, -1}, 0, {1, 0, 0}, NULL},
        {NULL, {-1, 0, -1}, 1, {1, 0, 1}, NULL},
        {"b", {1, 0, -1}, 0, {0, 1, 0}, NULL},
        {"c,a", {-1, -1, -1}, 0, {1, 0, 1}, NULL},
        {"a,b,c", {-1, -1, -1}, 0, {1, 1, 1}, NULL},
        {"a,z", {-1, -1, -1}, 0, {-1}, "--supports"},
        {"", {1, 1, 1}, 0, {-1}, "--supports"},
        {NULL, {0, 0, -1}, 0, {-1}, "--supports"},
        {NULL, {2, 0, 0}, 0, {-1}, "data.graph.data.node.a.is_support"},
        {"b", {2, 0, 0}, 0, {0, 1, 0}, NULL}, /* is_support not read when the caller lists them */
    };
    for (size_t c = 0; c < sizeof cases / sizeof cases[0]; c++) {
        json_t *root = compas_new();
        json_object_set_new(json_object_get(json_object_get(json_object_get(json_object_get(root, "data"), "graph"), "data"),
                                            "default_node_attributes"), "is_support", json_boolean(cases[c].dflt));
        for (int i = 0; i < 3; i++) {
            int v = cases[c].is_sup[i];
            compas_add(root, keys[i], compas_block(&s[i], false),
                       v < 0 ? NULL : v == 2 ? json_string("yes") : json_boolean(v));
        }
        cnDiag d;
        cn_diag_clear(&d);
        json_t *doc = cn_compas_to_cairn(root, cases[c].supports, 1e-6, &d);
        if (cases[c].want[0] < 0) {
            CHECK_MSG(!doc && d.code == CN_ERR_INPUT && !strcmp(d.where, cases[c].where),
                      "case %zu: where '%s', want '%s' (%s)", c, d.where, cases[c].where, d.message);
        } else {
            CHECK_MSG(doc != NULL, "case %zu: %s: %s", c, d.where, d.message);
            for (int i = 0; doc && i < 3; i++) {
                const json_t *p = doc_part(doc, keys[i]);
                CHECK_MSG(p && json_is_true(json_object_get(p, "fixed")) == (cases[c].want[i] == 1),
                          "case %zu: part %s fixed?", c, keys[i]);
            }
        }
        if (c == 5) CHECK_MSG(strstr(d.message, "'z'") != NULL, "names the missing key: %s", d.message);
        json_decref(doc);
        json_decref(root);
    }
    /* keys longer than any buffer: named whole in --supports, and one such key unknown */
    char lng[301], other[301];
    memset(lng, 'k', 300), lng[300] = 0;
    memcpy(other, lng, sizeof other), other[299] = 'j';
    for (int t = 0; t < 2; t++) {
        json_t *root = compas_new();
        compas_add(root, lng, compas_block(&s[0], false), NULL);
        compas_add(root, "b", compas_block(&s[1], false), NULL);
        char list[400];
        snprintf(list, sizeof list, "b,%s", t ? other : lng);
        cnDiag d;
        cn_diag_clear(&d);
        json_t *doc = cn_compas_to_cairn(root, list, 1e-6, &d);
        if (t == 0)
            CHECK_MSG(doc && json_is_true(json_object_get(doc_part(doc, lng), "fixed")), "long key: %s", d.message);
        else
            CHECK_MSG(!doc && d.code == CN_ERR_INPUT && !strcmp(d.where, "--supports"), "unknown long key: %s", d.message);
        json_decref(doc);
        json_decref(root);
    }
}

/* Malformed documents: no crash, CN_ERR_INPUT, the JSON path of the problem and what it is. */
static void test_compas_malformed(void) {
    double o[3] = {0, 0, 0};
    Shape box, L;
    shape_box(&box, 1, 1, 1, o);
    double lp[6][2];
    l_polygon(2, 2, 1, lp);
    shape_prism(&L, (const double(*)[2])lp, 6, 1);
    for (int c = 0; c < 17; c++) {
        json_t *root = compas_new();
        json_t *blk = compas_block(c >= 10 && c <= 12 ? &L : &box, false);
        json_t *mesh = json_object_get(blk, "data");
        const char *key = "k7", *where = "data.graph.data.node.k7.block", *says = NULL;
        char keybuf[8];
        switch (c) {
        case 0: /* no graph at all (removed below) */
            where = "data.graph.data.node", says = "nodes";
            break;
        case 1: /* a node without a block (the default is null) */
            json_decref(blk), blk = NULL, says = "no block";
            break;
        case 2: /* a vertex without y, and no default */
            json_object_del(json_object_get(json_object_get(mesh, "vertex"), "5"), "y");
            json_object_del(mesh, "default_vertex_attributes");
            says = "vertex '5' has no finite y";
            break;
        case 3: /* a coordinate that is not a number */
            json_object_set_new(json_object_get(json_object_get(mesh, "vertex"), "2"), "z", json_string("1"));
            says = "vertex '2' has no finite z";
            break;
        case 4: /* a face naming a vertex the mesh lacks */
            json_array_set_new(json_object_get(json_object_get(mesh, "face"), "3"), 1, json_integer(8));
            says = "face '3' is not a loop";
            break;
        case 5: /* a face of two vertices */
            json_object_set_new(json_object_get(mesh, "face"), "2", json_pack("[i,i]", 0, 1));
            says = "face '2' is not a loop";
            break;
        case 6: /* vertex keys as strings in a face */
            json_object_set_new(json_object_get(mesh, "face"), "0", json_pack("[s,s,s]", "0", "2", "3"));
            says = "face '0' is not a loop";
            break;
        case 7: /* three vertices only */
            json_object_del(json_object_get(mesh, "vertex"), "7"), json_object_del(json_object_get(mesh, "vertex"), "6");
            json_object_del(json_object_get(mesh, "vertex"), "5"), json_object_del(json_object_get(mesh, "vertex"), "4");
            json_object_del(json_object_get(mesh, "vertex"), "3");
            says = "expected a COMPAS mesh";
            break;
        case 8: /* the block's data not an object */
            json_object_set_new(blk, "data", json_integer(5));
            says = "expected a COMPAS mesh";
            break;
        case 9: /* a coordinate beyond what cairn computes with */
            json_object_set_new(json_object_get(json_object_get(mesh, "vertex"), "1"), "x", json_real(1e300));
            says = "beyond";
            break;
        case 10: /* a non-convex block with a face missing: open */
            json_object_del(json_object_get(mesh, "face"), "4");
            says = "is open";
            break;
        case 11: /* a non-convex block with one face turned: inconsistent */
            json_object_set_new(json_object_get(mesh, "face"), "5", json_pack("[i,i,i,i]", 9, 10, 4, 3));
            says = "oriented inconsistently";
            break;
        case 12: /* a non-convex block with a face dict of one face */
            json_object_set_new(mesh, "face", json_pack("{s:[i,i,i]}", "0", 0, 1, 2));
            says = "at least 4";
            break;
        case 13: /* a control character in a node key */
            snprintf(keybuf, sizeof keybuf, "k\x01");
            key = keybuf, where = "data.graph.data.node", says = "control character";
            break;
        case 14: /* a flat block: its faces on the top and bottom planes, the sides degenerate */
            for (int v = 4; v < 8; v++)
                json_object_set_new(json_object_get(json_object_get(mesh, "vertex"), (char[2]){(char)('0' + v), 0}), "z", json_real(0));
            says = "degenerate";
            break;
        case 15: /* a convex block with a face missing: open (its hull would hide it) */
            json_object_del(json_object_get(mesh, "face"), "2");
            says = "is open";
            break;
        case 16: { /* a convex block with one face turned */
            json_t *fl = json_object_get(json_object_get(mesh, "face"), "1"), *rev = json_array();
            for (size_t a = json_array_size(fl); a-- > 0;) json_array_append(rev, json_array_get(fl, a));
            json_object_set_new(json_object_get(mesh, "face"), "1", rev);
            says = "oriented inconsistently";
            break;
        }
        }
        compas_add(root, key, blk, json_true());
        if (c == 0) json_object_del(json_object_get(root, "data"), "graph");
        cnDiag d;
        cn_diag_clear(&d);
        json_t *doc = cn_compas_to_cairn(root, NULL, 1e-6, &d);
        CHECK_MSG(!doc && d.code == CN_ERR_INPUT, "case %d: refused", c);
        CHECK_MSG(!strcmp(d.where, where), "case %d: where '%s', want '%s' (%s)", c, d.where, where, d.message);
        CHECK_MSG(strstr(d.message, says) != NULL, "case %d: message '%s' lacks '%s'", c, d.message, says);
        json_decref(doc);
        json_decref(root);
    }
    /* overlapping blocks: found at load, named as COMPAS nodes; boxes overlap by 0.25 along z */
    json_t *root = compas_new();
    double o2[3] = {0, 0, 0.75};
    Shape b2;
    shape_box(&b2, 1, 1, 1, o2);
    compas_add(root, "P", compas_block(&box, false), json_true());
    compas_add(root, "Q", compas_block(&b2, false), json_false());
    char *text = json_dumps(root, JSON_COMPACT);
    cnAssembly *a = NULL;
    cnDiag d;
    cnStatus st = cn_assembly_load_string(text, "compas", &a, &d);
    CHECK(st == CN_ERR_INPUT && a == NULL);
    CHECK_MSG(!strcmp(d.where, "data.graph.data.node.P") || !strcmp(d.where, "data.graph.data.node.Q"), "where '%s'", d.where);
    CHECK_MSG(strstr(d.message, "by 0.25") && !strstr(d.message, "parts["), "message '%s'", d.message);
    cn_assembly_free(a);
    free(text);
    json_decref(root);
}

/* ---- 2. closed meshes ---- */

/* Check the shape as a mesh with tolerance rel of its size: the status, its message in *msg. */
static cnStatus mesh_check_shape(const Shape *s, double rel, double *vol, char *msg, size_t n) {
    cnMesh m = mesh_of(s);
    cnDiag d;
    cn_diag_clear(&d);
    cnStatus st = cn_mesh_check(&m, rel * shape_size(s), &d);
    if (msg) snprintf(msg, n, "%s", st ? d.message : "");
    if (vol) *vol = st ? NAN : cn_mesh_volume(&m);
    cn_mesh_free(&m);
    return st;
}

/* Volumes against closed forms, unchanged under random rigid motions and under welding of
 * duplicated corners; a mesh all turned inward is turned out. */
static void test_mesh_volume(void) {
    cnRng rng = {0x1234567887654321ULL};
    for (int trial = 0; trial < 20; trial++) {
        double R[3][3], t[3];
        random_rotation(&rng, R);
        for (int k = 0; k < 3; k++) t[k] = cn_rng_range(&rng, -100, 100);
        double a = cn_rng_range(&rng, 0.5, 3), b = cn_rng_range(&rng, 0.5, 3), c = cn_rng_range(&rng, 0.5, 3);
        double o[3] = {cn_rng_range(&rng, -1, 1), cn_rng_range(&rng, -1, 1), cn_rng_range(&rng, -1, 1)};
        Shape s[5];
        double want[5];
        shape_box(&s[0], a, b, c, o), want[0] = a * b * c;
        shape_tetra(&s[1], a, b, c), want[1] = a * b * c / 6;
        double lp[6][2], lt = fmin(a, b) / 3;
        l_polygon(a, b, lt, lp);
        shape_prism(&s[2], (const double(*)[2])lp, 6, c), want[2] = (a * lt + lt * (b - lt)) * c;
        shape_icosa(&s[3], NULL), want[3] = 5.0 / 12 * (3 + sqrt(5.0)) * 8; /* edge 2 */
        /* a pentagonal prism: the regular pentagon of circumradius a, area (5/2) a^2 sin 72 */
        double pent[5][2];
        for (int i = 0; i < 5; i++) pent[i][0] = a * cos(2 * CN_PI * i / 5), pent[i][1] = a * sin(2 * CN_PI * i / 5);
        shape_prism(&s[4], (const double(*)[2])pent, 5, c), want[4] = 2.5 * a * a * sin(2 * CN_PI / 5) * c;
        for (int k = 0; k < 5; k++) {
            double v0, v1;
            char msg[1024];
            CHECK_MSG(mesh_check_shape(&s[k], 1e-9, &v0, msg, sizeof msg) == CN_OK, "shape %d: %s", k, msg);
            CHECK_MSG(fabs(v0 - want[k]) <= 1e-12 * want[k] * 10, "shape %d: volume %.17g, want %.17g", k, v0, want[k]);
            Shape moved = s[k];
            shape_move(&moved, (const double(*)[3])R, t);
            CHECK_MSG(mesh_check_shape(&moved, 1e-9, &v1, msg, sizeof msg) == CN_OK, "shape %d moved: %s", k, msg);
            CHECK_MSG(fabs(v1 - want[k]) <= 1e-9 * want[k], "shape %d moved: volume %.17g, want %.17g", k, v1, want[k]);
            /* all faces inward: turned out, the same volume, and the faces then point away */
            Shape in = moved;
            for (int f = 0; f < in.nf; f++) shape_reverse_face(&in, f);
            cnMesh m = mesh_of(&in);
            cnDiag d;
            CHECK_MSG(cn_mesh_check(&m, 1e-9 * shape_size(&in), &d) == CN_OK, "shape %d inward: %s", k, d.message);
            CHECK_MSG(fabs(cn_mesh_volume(&m) - want[k]) <= 1e-9 * want[k], "shape %d inward: volume %.17g", k, cn_mesh_volume(&m));
            double ctr[3] = {0, 0, 0};
            for (int i = 0; i < in.nv; i++)
                for (int j = 0; j < 3; j++) ctr[j] += in.v[i][j] / in.nv;
            int outward = 0;
            for (int f = 0; f < m.nfaces; f++) { /* every face of these is seen from the vertex mean */
                const double *p0 = m.verts[m.idx[m.start[f]]], *p1 = m.verts[m.idx[m.start[f] + 1]], *p2 = m.verts[m.idx[m.start[f] + 2]];
                double e1[3], e2[3], nrm[3], dc[3];
                cn_sub3(p1, p0, e1), cn_sub3(p2, p0, e2), cn_cross3(e1, e2, nrm), cn_sub3(p0, ctr, dc);
                outward += cn_dot3(nrm, dc) > 0;
            }
            if (k != 2) CHECK_MSG(outward == m.nfaces, "shape %d inward: %d of %d faces turned out", k, outward, m.nfaces);
            cn_mesh_free(&m);
        }
    }
    /* a box whose faces each have corners of their own (24 vertices), face f's moved by
     * (f + 1) (1, 2, 3) 1e-12: welded; by (f + 1) (1, 2, 3) 1e-6, beyond the tolerance: open */
    for (int pass = 0; pass < 2; pass++) {
        double o[3] = {5, -3, 2};
        Shape box, loose;
        shape_box(&box, 2, 3, 4, o);
        memset(&loose, 0, sizeof loose);
        for (int f = 0, at = 0; f < box.nf; at += box.len[f], f++) {
            int loop[4];
            for (int j = 0; j < 4; j++) {
                loop[j] = loose.nv;
                for (int k = 0; k < 3; k++) loose.v[loose.nv][k] = box.v[box.idx[at + j]][k] + (pass ? 1e-6 : 1e-12) * (f + 1) * (k + 1);
                loose.nv++;
            }
            shape_face(&loose, 4, loop);
        }
        double v;
        char msg[1024];
        cnStatus st = mesh_check_shape(&loose, 1e-9, &v, msg, sizeof msg);
        if (pass == 0) {
            CHECK_MSG(st == CN_OK, "welded box: %s", msg);
            CHECK_NEAR(v, 24, 1e-9);
        } else { /* apart by more than the tolerance: not welded, so open */
            CHECK_MSG(st == CN_ERR_INPUT && strstr(msg, "open"), "unwelded box: %s", msg);
        }
    }
}

/* Surfaces that are not a part's: each refused with the right reason and the face it names. */
static void test_mesh_check_errors(void) {
    double o[3] = {0, 0, 0};
    Shape s;
    char msg[1024];
    /* one face flipped: inconsistent, the message names it */
    for (int f = 0; f < 6; f++) {
        shape_box(&s, 1, 2, 3, o);
        shape_reverse_face(&s, f);
        CHECK(mesh_check_shape(&s, 1e-9, NULL, msg, sizeof msg) == CN_ERR_INPUT);
        int f1 = -1, f2 = -1;
        const char *at = strstr(msg, "faces ");
        CHECK_MSG(at && sscanf(at, "faces %d and %d", &f1, &f2) == 2 && strstr(msg, "oriented inconsistently"),
                  "flipped face %d: %s", f + 1, msg);
        CHECK_MSG(f1 == f + 1 || f2 == f + 1, "flipped face %d, named %d and %d", f + 1, f1, f2);
    }
    /* an open box (a face missing) */
    shape_box(&s, 1, 2, 3, o);
    s.nf = 5, s.ni = 20;
    CHECK(mesh_check_shape(&s, 1e-9, NULL, msg, sizeof msg) == CN_ERR_INPUT);
    CHECK_MSG(strstr(msg, "is open"), "open box: %s", msg);
    /* too few faces */
    s.nf = 3, s.ni = 12;
    CHECK(mesh_check_shape(&s, 1e-9, NULL, msg, sizeof msg) == CN_ERR_INPUT);
    CHECK_MSG(strstr(msg, "at least 4"), "3 faces: %s", msg);
    /* a face whose corners are on a line (face 2: corners 0, 1, 3) */
    shape_tetra(&s, 1, 1, 1);
    s.v[3][0] = 0.5, s.v[3][2] = 0;
    CHECK(mesh_check_shape(&s, 1e-9, NULL, msg, sizeof msg) == CN_ERR_INPUT);
    CHECK_MSG(strstr(msg, "face 2 is degenerate"), "collinear face: %s", msg);
    /* a face with two corners welded into one: fewer than 3 left */
    shape_tetra(&s, 1, 1, 1);
    s.v[3][0] = 1, s.v[3][2] = 1e-13; /* 3 onto 1 */
    CHECK(mesh_check_shape(&s, 1e-9, NULL, msg, sizeof msg) == CN_ERR_INPUT);
    CHECK_MSG(strstr(msg, "degenerate"), "welded corners: %s", msg);
    /* two tetrahedra sharing an edge: that edge in four faces */
    memset(&s, 0, sizeof s);
    double v[6][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0, -1, 0}, {0, 0, -1}};
    memcpy(s.v, v, sizeof v);
    s.nv = 6;
    static const int tet[2][4] = {{0, 1, 2, 3}, {0, 1, 4, 5}};
    for (int k = 0; k < 2; k++) {
        const int *q = tet[k];
        int fs[4][3] = {{q[0], q[1], q[2]}, {q[0], q[1], q[3]}, {q[0], q[2], q[3]}, {q[1], q[2], q[3]}};
        double c[3] = {0, 0, 0};
        for (int j = 0; j < 4; j++)
            for (int i = 0; i < 3; i++) c[i] += s.v[q[j]][i] / 4;
        for (int f = 0; f < 4; f++) { /* outward from the tetrahedron's centroid */
            double e1[3], e2[3], nrm[3], dc[3];
            cn_sub3(s.v[fs[f][1]], s.v[fs[f][0]], e1), cn_sub3(s.v[fs[f][2]], s.v[fs[f][0]], e2);
            cn_cross3(e1, e2, nrm), cn_sub3(s.v[fs[f][0]], c, dc);
            if (cn_dot3(nrm, dc) < 0) {
                int t = fs[f][1];
                fs[f][1] = fs[f][2], fs[f][2] = t;
            }
            shape_face(&s, 3, fs[f]);
        }
    }
    CHECK(mesh_check_shape(&s, 1e-9, NULL, msg, sizeof msg) == CN_ERR_INPUT);
    CHECK_MSG(strstr(msg, "not a manifold") && strstr(msg, "belongs to 4 faces"), "bowtie: %s", msg);
}

/* Convexity against the closed forms (box, tetrahedron, prisms: convex; the L, a box with a
 * dent: not) and against a brute-force reference on icosahedra with random radii (convex when
 * every vertex is behind every face's plane). */
static void test_mesh_convex(void) {
    cnRng rng = {0xdeadbeefcafef00dULL};
    Shape s[6];
    bool want[6];
    double o[3] = {0, 0, 0}, lp[6][2];
    shape_box(&s[0], 1, 2, 3, o), want[0] = true;
    shape_tetra(&s[1], 1, 2, 3), want[1] = true;
    l_polygon(2, 2, 1, lp);
    shape_prism(&s[2], (const double(*)[2])lp, 6, 1), want[2] = false;
    /* a box whose top face is four triangles about its centre: flat (convex), or dented by 0.1 */
    for (int k = 3; k <= 4; k++) {
        shape_box(&s[k], 2, 2, 2, o);
        Shape *b = &s[k];
        int top[4] = {4, 5, 7, 6};
        /* drop the top quad (face 1) and fan the centre vertex 8 */
        Shape t = *b;
        memset(&t.len, 0, sizeof t.len);
        t.nf = 0, t.ni = 0;
        for (int f = 0, at = 0; f < b->nf; at += b->len[f], f++)
            if (f != 1) shape_face(&t, b->len[f], &b->idx[at]);
        t.v[8][0] = 1, t.v[8][1] = 1, t.v[8][2] = k == 3 ? 2 : 1.9;
        t.nv = 9;
        for (int j = 0; j < 4; j++) {
            int tri[3] = {top[j], top[(j + 1) % 4], 8};
            shape_face(&t, 3, tri);
        }
        *b = t;
        want[k] = k == 3;
    }
    double pent[5][2];
    for (int i = 0; i < 5; i++) pent[i][0] = cos(2 * CN_PI * i / 5), pent[i][1] = sin(2 * CN_PI * i / 5);
    shape_prism(&s[5], (const double(*)[2])pent, 5, 0.5), want[5] = true;
    for (int rep = 0; rep < 3; rep++)
        for (int k = 0; k < 6; k++) {
            Shape x = s[k];
            if (rep) { /* the same under a rigid motion */
                double R[3][3], t[3];
                random_rotation(&rng, R);
                for (int j = 0; j < 3; j++) t[j] = cn_rng_range(&rng, -10, 10);
                shape_move(&x, (const double(*)[3])R, t);
            }
            cnMesh m = mesh_of(&x);
            cnDiag d;
            double tol = 1e-9 * shape_size(&x);
            CHECK_MSG(cn_mesh_check(&m, tol, &d) == CN_OK, "shape %d: %s", k, d.message);
            cnPiece hull;
            CHECK(cn_hull3_build((const double(*)[3])m.verts, m.nverts, &hull, &d) == CN_OK);
            CHECK_MSG(cn_mesh_is_convex(&m, &hull, tol) == want[k], "shape %d (motion %d): convex %d, want %d", k, rep,
                      !want[k], want[k]);
            cn_piece_free(&hull);
            cn_mesh_free(&m);
        }
    /* random radii: the reference decides where it is clear by 1e-3 */
    int seen[2] = {0, 0};
    for (int trial = 0; trial < 60; trial++) {
        double r[12];
        for (int i = 0; i < 12; i++) r[i] = cn_rng_range(&rng, trial % 2 ? 0.97 : 0.25, trial % 2 ? 1.03 : 1.75);
        Shape x;
        shape_icosa(&x, r);
        double worst = -INFINITY, nearest = INFINITY;
        for (int f = 0; f < x.nf; f++) {
            const int *q = &x.idx[3 * f];
            double e1[3], e2[3], nrm[3];
            cn_sub3(x.v[q[1]], x.v[q[0]], e1), cn_sub3(x.v[q[2]], x.v[q[0]], e2), cn_cross3(e1, e2, nrm);
            cn_normalize3(nrm);
            for (int v = 0; v < x.nv; v++) {
                if (v == q[0] || v == q[1] || v == q[2]) continue;
                double dv[3];
                cn_sub3(x.v[v], x.v[q[0]], dv);
                double h = cn_dot3(nrm, dv);
                worst = fmax(worst, h), nearest = fmin(nearest, fabs(h));
            }
        }
        if (nearest < 1e-3) continue; /* a vertex near a face's plane: undecided */
        bool convex = worst < 0;
        seen[convex]++;
        cnMesh m = mesh_of(&x);
        cnDiag d;
        double tol = 1e-9 * shape_size(&x);
        CHECK_MSG(cn_mesh_check(&m, tol, &d) == CN_OK, "icosahedron %d: %s", trial, d.message);
        cnPiece hull;
        CHECK(cn_hull3_build((const double(*)[3])m.verts, m.nverts, &hull, &d) == CN_OK);
        CHECK_MSG(cn_mesh_is_convex(&m, &hull, tol) == convex, "icosahedron %d: convex is %d", trial, convex);
        cn_piece_free(&hull);
        cn_mesh_free(&m);
    }
    CHECK_MSG(seen[0] >= 5 && seen[1] >= 5, "both kinds drawn: %d non-convex, %d convex", seen[0], seen[1]);
}

/* Split a checked shape; the pieces as hulls (*np of them, free with pieces_free). */
static cnPiece *split_shape(const Shape *s, int *np, int *code) {
    cnMesh m = mesh_of(s);
    cnDiag d;
    *np = 0;
    cnPiece *pcs = NULL;
    CHECK_MSG(cn_mesh_check(&m, 1e-9 * shape_size(s), &d) == CN_OK, "%s", d.message);
    cnMeshPieces mp;
    int f1, f2;
    *code = cn_mesh_split(&m, 1e-9 * shape_size(s), &mp, &f1, &f2);
    if (!*code) {
        pcs = calloc((size_t)mp.n, sizeof(cnPiece));
        for (int i = 0; i < mp.n; i++)
            CHECK_MSG(cn_hull3_build((const double(*)[3])mp.pts[i], mp.lens[i], &pcs[i], &d) == CN_OK, "piece %d: %s", i, d.message);
        *np = mp.n;
        cn_mesh_pieces_free(&mp);
    }
    cn_mesh_free(&m);
    return pcs;
}

static void pieces_free(cnPiece *pcs, int np) {
    for (int i = 0; i < np; i++) cn_piece_free(&pcs[i]);
    free(pcs);
}

static double pieces_volume(const cnPiece *pcs, int np, double lo[3], double hi[3]) {
    double total = 0;
    for (int k = 0; k < 3; k++) lo[k] = INFINITY, hi[k] = -INFINITY;
    for (int i = 0; i < np; i++) {
        double v, first[3], second[3][3];
        cn_mass_piece(&pcs[i], 3, NULL, &v, first, second);
        total += v;
        for (int k = 0; k < 3; k++) lo[k] = fmin(lo[k], pcs[i].lo[k]), hi[k] = fmax(hi[k], pcs[i].hi[k]);
    }
    return total;
}

/* Non-convex meshes split: the pieces' volumes add up to the closed form (the L, a U, both under
 * a rigid motion) or to the mesh's own volume (dented icosahedra), and they tile the body. */
static void test_mesh_split(void) {
    cnRng rng = {0x0badc0ffee0ddf00ULL};
    const double I3[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    double lp[6][2], up[8][2] = {{0, 0}, {3, 0}, {3, 2}, {2, 2}, {2, 1}, {1, 1}, {1, 2}, {0, 2}};
    l_polygon(3, 2, 0.5, lp);
    struct {
        const double (*p)[2];
        int n;
        double area;
    } polys[2] = {{(const double(*)[2])lp, 6, 3 * 0.5 + 0.5 * 1.5}, {(const double(*)[2])up, 8, 6 - 1}};
    for (int k = 0; k < 2; k++)
        for (int rep = 0; rep < 2; rep++) {
            double R[3][3], t[3];
            memcpy(R, I3, sizeof R), memset(t, 0, sizeof t);
            if (rep) {
                random_rotation(&rng, R);
                for (int j = 0; j < 3; j++) t[j] = cn_rng_range(&rng, -20, 20);
            }
            Shape s;
            shape_prism(&s, polys[k].p, polys[k].n, 1.5);
            shape_move(&s, (const double(*)[3])R, t);
            int np, code;
            cnPiece *pcs = split_shape(&s, &np, &code);
            CHECK_MSG(code == 0 && np >= 2, "prism %d: code %d, %d pieces", k, code, np);
            double lo[3], hi[3], want = polys[k].area * 1.5;
            double v = pieces_volume(pcs, np, lo, hi);
            CHECK_MSG(fabs(v - want) <= 1e-9 * want, "prism %d (motion %d): pieces hold %.17g, want %.17g", k, rep, v, want);
            PrismBody body = {polys[k].p, polys[k].n, 1.5, (const double(*)[3])R, t};
            check_tiling(pcs, np, in_prism, &body, lo, hi, &rng, 3000, "split prism");
            pieces_free(pcs, np);
        }
    /* dented icosahedra: radii drawn until the reference finds it not convex */
    int done = 0;
    for (int trial = 0; trial < 50 && done < 3; trial++) {
        double r[12];
        for (int i = 0; i < 12; i++) r[i] = cn_rng_range(&rng, 0.6, 1.4);
        Shape x;
        shape_icosa(&x, r);
        bool convex = true;
        for (int f = 0; f < x.nf && convex; f++) {
            const int *q = &x.idx[3 * f];
            double e1[3], e2[3], nrm[3];
            cn_sub3(x.v[q[1]], x.v[q[0]], e1), cn_sub3(x.v[q[2]], x.v[q[0]], e2), cn_cross3(e1, e2, nrm);
            cn_normalize3(nrm);
            for (int v = 0; v < x.nv; v++) {
                double dv[3];
                cn_sub3(x.v[v], x.v[q[0]], dv);
                if (cn_dot3(nrm, dv) > 1e-3) convex = false;
            }
        }
        if (convex) continue;
        done++;
        cnMesh m = mesh_of(&x);
        cnDiag d;
        CHECK(cn_mesh_check(&m, 1e-9 * shape_size(&x), &d) == CN_OK);
        double vm = cn_mesh_volume(&m);
        cn_mesh_free(&m);
        int np, code;
        cnPiece *pcs = split_shape(&x, &np, &code);
        CHECK_MSG(code == 0 && np >= 2, "icosahedron %d: code %d, %d pieces", trial, code, np);
        double lo[3], hi[3];
        double v = pieces_volume(pcs, np, lo, hi);
        CHECK_MSG(fabs(v - vm) <= 1e-9 * vm, "icosahedron %d: pieces hold %.17g, the mesh %.17g", trial, v, vm);
        check_tiling(pcs, np, in_star_body, &x, lo, hi, &rng, 3000, "split icosahedron");
        pieces_free(pcs, np);
    }
    CHECK_MSG(done == 3, "dented icosahedra drawn: %d", done);
    /* more faces than are split: refused before any work (a 1000-gon prism, 1002 faces) */
    int n = CN_MESH_SPLIT_MAX_FACES;
    cnMesh m;
    memset(&m, 0, sizeof m);
    m.nverts = 2 * n, m.nfaces = n + 2;
    m.verts = cn_malloc(sizeof(double[3]) * (size_t)(2 * n));
    m.start = cn_malloc(sizeof(int) * (size_t)(n + 3));
    m.idx = cn_malloc(sizeof(int) * (size_t)(6 * n));
    m.face_id = cn_malloc(sizeof(int) * (size_t)(n + 2));
    for (int i = 0; i < n; i++) {
        double a = 2 * CN_PI * i / n, rr = i % 2 ? 1 : 0.8; /* a star: not convex */
        double p[3] = {rr * cos(a), rr * sin(a), 0};
        cn_copy3(m.verts[i], p);
        p[2] = 1;
        cn_copy3(m.verts[n + i], p);
    }
    int k = 0, f = 0;
    m.start[f] = k;
    for (int i = n - 1; i >= 0; i--) m.idx[k++] = i;
    m.start[++f] = k;
    for (int i = 0; i < n; i++) m.idx[k++] = n + i;
    for (int i = 0; i < n; i++) {
        m.start[++f] = k;
        m.idx[k++] = i, m.idx[k++] = (i + 1) % n, m.idx[k++] = n + (i + 1) % n, m.idx[k++] = n + i;
    }
    m.start[++f] = k;
    for (int i = 0; i < n + 2; i++) m.face_id[i] = i + 1;
    cnDiag d;
    CHECK_MSG(cn_mesh_check(&m, 1e-9, &d) == CN_OK, "star prism: %s", d.message);
    cnMeshPieces mp;
    int f1, f2;
    CHECK(cn_mesh_split(&m, 1e-9, &mp, &f1, &f2) == 6 && mp.n == 0);
    cn_mesh_pieces_free(&mp);
    cn_mesh_free(&m);
}

/* ---- 3. 2-D polygons ---- */

typedef double P3[3];

static double cross2(const double *o, const double *a, const double *b) {
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0]);
}

/* Twice the shoelace area of the points idx[0 .. n-1] of p (idx NULL: 0 .. n-1), taken about
 * p[0] so that far from the origin the terms keep their digits. */
static double shoelace(const P3 *p, const int *idx, int n) {
    double s = 0;
    for (int i = 0; i < n; i++) {
        const double *a = p[idx ? idx[i] : i], *b = p[idx ? idx[(i + 1) % n] : (i + 1) % n];
        s += (a[0] - p[0][0]) * (b[1] - p[0][1]) - (a[1] - p[0][1]) * (b[0] - p[0][0]);
    }
    return s;
}

/* The distance between closed segments ab and cd, by solving a + s (b - a) = c + u (d - c) for a
 * crossing, else the nearest end-to-segment distance. */
static double seg_dist(const double *a, const double *b, const double *c, const double *d) {
    double r[2] = {b[0] - a[0], b[1] - a[1]}, q[2] = {d[0] - c[0], d[1] - c[1]};
    double den = r[0] * q[1] - r[1] * q[0], w[2] = {c[0] - a[0], c[1] - a[1]};
    if (den != 0) {
        double s = (w[0] * q[1] - w[1] * q[0]) / den, u = (w[0] * r[1] - w[1] * r[0]) / den;
        if (s >= 0 && s <= 1 && u >= 0 && u <= 1) return 0;
    }
    const double *x[4] = {a, b, c, d}, *sa[4] = {c, c, a, a}, *sb[4] = {d, d, b, b};
    double best = INFINITY;
    for (int k = 0; k < 4; k++) {
        double e[2] = {sb[k][0] - sa[k][0], sb[k][1] - sa[k][1]}, L2 = e[0] * e[0] + e[1] * e[1];
        double t = fmax(0, fmin(1, ((x[k][0] - sa[k][0]) * e[0] + (x[k][1] - sa[k][1]) * e[1]) / L2));
        best = fmin(best, hypot(x[k][0] - sa[k][0] - t * e[0], x[k][1] - sa[k][1] - t * e[1]));
    }
    return best;
}

/* Brute force: the first pair (i < j, not neighbours) of edges that meet, or 1 when none; 0 with
 * the pair; -1 when some pair is too near to tell (within 1e-6 without meeting). */
static int simple_ref(const P3 *p, int n, int *e1, int *e2) {
    int first = 1;
    for (int i = 0; i < n; i++)
        for (int j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1) continue;
            double dd = seg_dist(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n]);
            if (dd > 0 && dd < 1e-6) return -1;
            if (dd == 0 && first) first = 0, *e1 = i, *e2 = j;
        }
    return first;
}

/* A random star-shaped polygon about the origin (counter-clockwise, n >= 4: every angular gap
 * under pi). */
static void star_polygon(cnRng *rng, int n, double rmin, P3 *p) {
    double phase = cn_rng_range(rng, 0, 2 * CN_PI);
    for (int i = 0; i < n; i++) {
        double a = phase + 2 * CN_PI * (i + 0.8 * cn_rng_uniform(rng)) / n, r = cn_rng_range(rng, rmin, 1);
        p[i][0] = r * cos(a), p[i][1] = r * sin(a), p[i][2] = 0;
    }
}

static void test_turn2(void) {
    double o[3] = {0, 0, 0}, x[3] = {1, 0, 0}, up[3] = {1, 1, 0}, dn[3] = {1, -1, 0}, on[3] = {2, 0, 0}, back[3] = {0.5, 0, 0};
    CHECK(cn_turn2(o, x, up) == 1);
    CHECK(cn_turn2(o, x, dn) == -1);
    CHECK(cn_turn2(o, x, on) == 0);
    CHECK(cn_turn2(o, x, back) == 0);
    /* a bend of 1e-12 radians is straight, one of 1e-6 is not */
    double tiny[3] = {2, 1e-12, 0}, small[3] = {2, 1e-6, 0}, smalldn[3] = {2, -1e-6, 0};
    CHECK(cn_turn2(o, x, tiny) == 0);
    CHECK(cn_turn2(o, x, small) == 1 && cn_turn2(o, x, smalldn) == -1);
    /* random turns against the sign of the heading change (atan2), and its invariance */
    cnRng rng = {0x5555aaaa3333ccccULL};
    int ok = 0, inv = 0, n = 0;
    for (int t = 0; t < 2000; t++) {
        double p[3][3];
        for (int i = 0; i < 3; i++) p[i][0] = cn_rng_range(&rng, -1, 1), p[i][1] = cn_rng_range(&rng, -1, 1), p[i][2] = 0;
        double h1 = atan2(p[1][1] - p[0][1], p[1][0] - p[0][0]), h2 = atan2(p[2][1] - p[1][1], p[2][0] - p[1][0]);
        double sn = sin(h2 - h1);
        if (fabs(sn) < 1e-6) continue;
        n++;
        int want = sn > 0 ? 1 : -1, got = cn_turn2(p[0], p[1], p[2]);
        ok += got == want;
        /* rotated, moved, scaled by s > 0: the same; mirrored: the opposite */
        double ang = cn_rng_range(&rng, 0, 2 * CN_PI), s = exp(cn_rng_range(&rng, -10, 10));
        double tx = cn_rng_range(&rng, -1e3, 1e3), ty = cn_rng_range(&rng, -1e3, 1e3), q[3][3], m[3][3];
        for (int i = 0; i < 3; i++) {
            q[i][0] = s * (cos(ang) * p[i][0] - sin(ang) * p[i][1]) + tx;
            q[i][1] = s * (sin(ang) * p[i][0] + cos(ang) * p[i][1]) + ty;
            m[i][0] = -p[i][0], m[i][1] = p[i][1], q[i][2] = m[i][2] = 0;
        }
        inv += cn_turn2(q[0], q[1], q[2]) == want && cn_turn2(m[0], m[1], m[2]) == -want;
    }
    CHECK_MSG(ok == n, "turn2: %d of %d right", ok, n);
    CHECK_MSG(inv == n, "turn2: %d of %d invariant", inv, n);
}

static void test_polygon_simple(void) {
    cnRng rng = {0x2468ace013579bdfULL};
    int seen[2] = {0, 0}, agree = 0, tried = 0;
    P3 p[40];
    for (int t = 0; t < 600; t++) {
        int n = 4 + (int)(cn_rng_uniform(&rng) * 20);
        if (t % 3 == 0) star_polygon(&rng, n, 0.2, p); /* simple by construction */
        else { /* random points in random order: mostly crossing */
            for (int i = 0; i < n; i++) p[i][0] = cn_rng_range(&rng, -1, 1), p[i][1] = cn_rng_range(&rng, -1, 1), p[i][2] = 0;
        }
        int r1 = -1, r2 = -1, e1 = -1, e2 = -1;
        int want = simple_ref((const P3 *)p, n, &r1, &r2);
        if (want < 0) continue;
        if (t % 3 == 0) CHECK_MSG(want == 1, "star polygon %d not simple by the reference", t);
        tried++;
        seen[want]++;
        int got = cn_polygon_simple((const double(*)[3])p, n, 1e-12, &e1, &e2);
        bool same = got == want && (want || (e1 == r1 && e2 == r2));
        if (!same) fprintf(stderr, "polygon %d (n %d): simple %d, want %d; edges %d %d, want %d %d\n", t, n, got, want, e1, e2, r1, r2);
        agree += same;
    }
    CHECK_MSG(agree == tried, "cn_polygon_simple: %d of %d agree", agree, tried);
    CHECK_MSG(seen[0] > 50 && seen[1] > 50, "both kinds: %d crossing, %d simple", seen[0], seen[1]);
    /* touching without crossing: a corner on a non-adjacent edge; and a bowtie */
    P3 pinch[5] = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {2, 0, 0}, {0, 4, 0}};
    int e1, e2;
    CHECK(cn_polygon_simple((const double(*)[3])pinch, 5, 1e-9, &e1, &e2) == 0 && ((e1 == 0 && e2 == 2) || (e1 == 0 && e2 == 3)));
    P3 bow[4] = {{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}};
    CHECK(cn_polygon_simple((const double(*)[3])bow, 4, 1e-9, &e1, &e2) == 0 && e1 == 0 && e2 == 2);
    /* within tol counts as meeting: a corner 1e-7 from an edge, tol 1e-6 vs 1e-8 */
    P3 near[5] = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {2, 1e-7, 0}, {0, 4, 0}};
    CHECK(cn_polygon_simple((const double(*)[3])near, 5, 1e-6, &e1, &e2) == 0);
    CHECK(cn_polygon_simple((const double(*)[3])near, 5, 1e-8, &e1, &e2) == 1);
}

/* Split pieces: valid indices, counter-clockwise and convex, every point used, areas adding to
 * the polygon's, each piece's vertex mean inside the polygon, at most 2 r + 1 pieces (r reflex
 * corners: Hertel-Mehlhorn's bound); returns the number of pieces, -1 if refused. */
static int check_split(const P3 *p, int n, const char *what) {
    int np = 0, *lens = NULL, **pcs = NULL;
    double scale = 0;
    for (int i = 0; i < n; i++) scale = fmax(scale, fmax(fabs(p[i][0]), fabs(p[i][1])));
    int rc = cn_polygon_split((const double(*)[3])p, n, 1e-9 * scale, &np, &lens, &pcs);
    CHECK_MSG(rc == 0, "%s: split refused (%d)", what, rc);
    if (rc) return -1;
    double total = shoelace(p, NULL, n), sum = 0;
    int reflex = 0;
    for (int i = 0; i < n; i++) reflex += cross2(p[(i + n - 1) % n], p[i], p[(i + 1) % n]) < -1e-12 * scale * scale;
    char *used = calloc((size_t)n, 1);
    int bad_index = 0, not_convex = 0, outside = 0;
    for (int k = 0; k < np; k++) {
        int m = lens[k];
        bool idx_ok = m >= 3;
        for (int j = 0; j < m; j++) idx_ok &= pcs[k][j] >= 0 && pcs[k][j] < n;
        if (!idx_ok) {
            bad_index++;
            continue;
        }
        for (int j = 0; j < m; j++) {
            used[pcs[k][j]] = 1;
            const double *a = p[pcs[k][j]], *b = p[pcs[k][(j + 1) % m]], *c = p[pcs[k][(j + 2) % m]];
            double la = hypot(b[0] - a[0], b[1] - a[1]), lb = hypot(c[0] - b[0], c[1] - b[1]);
            if (cross2(a, b, c) < -1e-9 * la * lb) not_convex++;
        }
        double area = shoelace(p, pcs[k], m);
        if (!(area > 0)) not_convex++;
        sum += area;
        double cx = 0, cy = 0, edge, poly[64][2];
        for (int j = 0; j < m; j++) cx += p[pcs[k][j]][0] / m, cy += p[pcs[k][j]][1] / m;
        for (int i = 0; i < n && i < 64; i++) poly[i][0] = p[i][0], poly[i][1] = p[i][1];
        if (!in_polygon2((const double(*)[2])poly, n, cx, cy, &edge)) outside++;
    }
    int unused = 0;
    for (int i = 0; i < n; i++) unused += !used[i];
    CHECK_MSG(bad_index == 0, "%s: %d pieces with bad indices", what, bad_index);
    CHECK_MSG(not_convex == 0, "%s: %d reflex corners in pieces", what, not_convex);
    CHECK_MSG(unused == 0, "%s: %d points in no piece", what, unused);
    CHECK_MSG(outside == 0, "%s: %d pieces outside", what, outside);
    CHECK_MSG(fabs(sum - total) <= 1e-12 * fabs(total) * n, "%s: pieces' area %.17g, polygon's %.17g", what, sum / 2, total / 2);
    CHECK_MSG(np <= 2 * reflex + 1, "%s: %d pieces for %d reflex corners", what, np, reflex);
    free(used);
    for (int k = 0; k < np; k++) cn_free(pcs[k]);
    cn_free(pcs), cn_free(lens);
    return np;
}

static void test_polygon_split(void) {
    cnRng rng = {0x13579bdf2468aceULL};
    P3 p[64];
    char what[64];
    for (int t = 0; t < 300; t++) {
        int n = 4 + (int)(cn_rng_uniform(&rng) * 36);
        star_polygon(&rng, n, t % 4 == 0 ? 0.999 : 0.2, p);
        /* far from the origin every 5th time */
        double off = t % 5 == 0 ? 1e4 : 0;
        for (int i = 0; i < n; i++) p[i][0] += off, p[i][1] -= off;
        bool convex = true;
        for (int i = 0; i < n; i++) convex &= cross2(p[(i + n - 1) % n], p[i], p[(i + 1) % n]) > 0;
        snprintf(what, sizeof what, "star %d (n %d)", t, n);
        int np = check_split((const P3 *)p, n, what);
        if (convex) CHECK_MSG(np == 1, "%s: convex, in %d pieces", what, np);
    }
    /* points where the outline runs straight on: put back on piece edges, every one used */
    P3 sq[8] = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}, {0, 2, 0}, {0, 1, 0}};
    CHECK(check_split((const P3 *)sq, 8, "square with midpoints") == 1);
    P3 ell[10] = {{0, 0, 0}, {2, 0, 0}, {4, 0, 0}, {4, 1, 0}, {1, 1, 0}, {1, 2, 0}, {1, 3, 0}, {0, 3, 0}, {0, 2, 0}, {0, 1, 0}};
    int np = check_split((const P3 *)ell, 10, "L with straight points");
    CHECK(np >= 2 && np <= 3); /* one reflex corner: 2 r + 1 at most */
    /* a comb: teeth 1 wide, gaps 1 wide; at least as many pieces as teeth */
    P3 comb[20];
    int m = 0, teeth = 4;
    comb[m][0] = 0, comb[m][1] = 0, comb[m++][2] = 0;
    comb[m][0] = 2 * teeth - 1, comb[m][1] = 0, comb[m++][2] = 0;
    for (int k = teeth - 1; k >= 0; k--) {
        double x0 = 2 * k, x1 = 2 * k + 1;
        comb[m][0] = x1, comb[m][1] = 3, comb[m++][2] = 0;
        comb[m][0] = x0, comb[m][1] = 3, comb[m++][2] = 0;
        if (k) comb[m][0] = x0, comb[m][1] = 1, comb[m++][2] = 0, comb[m][0] = x0 - 1, comb[m][1] = 1, comb[m++][2] = 0;
    }
    np = check_split((const P3 *)comb, m, "comb");
    CHECK_MSG(np >= teeth, "comb: %d pieces", np);
    /* clockwise: no ear, refused (not a crash) */
    P3 cw[4] = {{0, 0, 0}, {0, 1, 0}, {1, 1, 0}, {1, 0, 0}};
    int npc, *lens, **pcs;
    CHECK(cn_polygon_split((const double(*)[3])cw, 4, 1e-9, &npc, &lens, &pcs) == 1 && npc == 0 && !lens && !pcs);
}

void test_io(void) {
    test_compas_blocks();
    test_compas_second_formulation();
    test_compas_supports();
    test_compas_malformed();
    test_mesh_volume();
    test_mesh_check_errors();
    test_mesh_convex();
    test_mesh_split();
    test_turn2();
    test_polygon_simple();
    test_polygon_split();
}
