/* A simple polygon split into convex pieces: ear clipping, then Hertel-Mehlhorn (drop each
 * diagonal of the triangulation whose removal leaves both of its ends convex: at most four times
 * the fewest convex pieces). Vertices where the outline runs straight on are left out of the
 * triangulation (an ear cannot have its tip there) and put back afterwards on the piece edge
 * they lie on, so that every outline vertex is a vertex of some piece and keeps its number. */
#include <math.h>
#include <string.h>

#include "pieces.h"

/* Twice the signed area of triangle (a, b, c): positive counter-clockwise. Relative to a, so
 * that coordinates far from the origin keep their digits. */
static double orient(const double *a, const double *b, const double *c) {
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

/* Does segment p1-p2 come within tol of segment q1-q2 (cross or touch)? */
static bool segments_meet(const double *p1, const double *p2, const double *q1, const double *q2, double tol) {
    double lp = hypot(p2[0] - p1[0], p2[1] - p1[1]), lq = hypot(q2[0] - q1[0], q2[1] - q1[1]);
    double d1 = orient(p1, p2, q1) / lp, d2 = orient(p1, p2, q2) / lp;
    double d3 = orient(q1, q2, p1) / lq, d4 = orient(q1, q2, p2) / lq;
    if (((d1 > tol && d2 < -tol) || (d1 < -tol && d2 > tol)) && ((d3 > tol && d4 < -tol) || (d3 < -tol && d4 > tol)))
        return true; /* a proper crossing */
    /* an end within tol of the other segment */
    const double *ends[4][3] = {{q1, p1, p2}, {q2, p1, p2}, {p1, q1, q2}, {p2, q1, q2}};
    for (int k = 0; k < 4; k++) {
        const double *x = ends[k][0], *a = ends[k][1], *b = ends[k][2];
        double ab[2] = {b[0] - a[0], b[1] - a[1]}, ax[2] = {x[0] - a[0], x[1] - a[1]};
        double L2 = ab[0] * ab[0] + ab[1] * ab[1];
        double t = L2 > 0 ? (ax[0] * ab[0] + ax[1] * ab[1]) / L2 : 0;
        t = fmax(0, fmin(1, t));
        if (hypot(ax[0] - t * ab[0], ax[1] - t * ab[1]) <= tol) return true;
    }
    return false;
}

/* Is x inside triangle (a, b, c) (counter-clockwise), its boundary included within tol? */
static bool in_triangle(const double *x, const double *a, const double *b, const double *c, double tol) {
    double la = hypot(b[0] - a[0], b[1] - a[1]), lb = hypot(c[0] - b[0], c[1] - b[1]), lc = hypot(a[0] - c[0], a[1] - c[1]);
    return orient(a, b, x) >= -tol * la && orient(b, c, x) >= -tol * lb && orient(c, a, x) >= -tol * lc;
}

int cn_turn2(const double *a, const double *b, const double *c) {
    double cr = orient(a, b, c), l = hypot(b[0] - a[0], b[1] - a[1]) * hypot(c[0] - b[0], c[1] - b[1]);
    return cr > CN_TOL_CORNER * l ? 1 : cr < -CN_TOL_CORNER * l ? -1 : 0;
}

int cn_polygon_simple(const double (*p)[3], int n, double tol, int *e1, int *e2) {
    for (int i = 0; i < n; i++)
        for (int j = i + 2; j < n; j++) {
            if (i == 0 && j == n - 1) continue; /* neighbours across the wrap */
            if (segments_meet(p[i], p[(i + 1) % n], p[j], p[(j + 1) % n], tol)) {
                *e1 = i, *e2 = j;
                return 0;
            }
        }
    return 1;
}

/* A growing list of int lists (the pieces). */
typedef struct {
    int n, cap;
    int *len, *capv;
    int **v;
    bool *dead;
} Lists;

static int lists_add(Lists *L, const int *idx, int m) {
    if (L->n == L->cap) {
        int cap = L->cap ? 2 * L->cap : 16;
        int *len = cn_realloc(L->len, sizeof(int) * (size_t)cap), *capv;
        if (!len) return -1;
        L->len = len;
        if (!(capv = cn_realloc(L->capv, sizeof(int) * (size_t)cap))) return -1;
        L->capv = capv;
        int **v = cn_realloc(L->v, sizeof(int *) * (size_t)cap);
        if (!v) return -1;
        L->v = v;
        bool *dead = cn_realloc(L->dead, sizeof(bool) * (size_t)cap);
        if (!dead) return -1;
        L->dead = dead;
        L->cap = cap;
    }
    L->v[L->n] = cn_malloc(sizeof(int) * (size_t)(m + 1));
    if (!L->v[L->n]) return -1;
    memcpy(L->v[L->n], idx, sizeof(int) * (size_t)m);
    L->len[L->n] = m;
    L->capv[L->n] = m + 1;
    L->dead[L->n] = false;
    L->n++;
    return 0;
}

static void lists_free(Lists *L) {
    for (int i = 0; i < L->n; i++) cn_free(L->v[i]);
    cn_free(L->v), cn_free(L->len), cn_free(L->capv), cn_free(L->dead);
    memset(L, 0, sizeof *L);
}

/* The live piece holding directed edge a -> b, and where (position of a); -1 if none. */
static int edge_owner(const Lists *L, int a, int b, int *at) {
    for (int k = 0; k < L->n; k++) {
        if (L->dead[k]) continue;
        int m = L->len[k];
        for (int i = 0; i < m; i++)
            if (L->v[k][i] == a && L->v[k][(i + 1) % m] == b) {
                *at = i;
                return k;
            }
    }
    return -1;
}

/* The core of the outline: straight[i] set for the points left out, those on the line of their
 * two neighbours, so long as every run of them stays within tol of the chord between the kept
 * points at its ends (on a gently curved outline the neighbours' test alone lets a long run drift
 * off the chord): where one does not, its farthest point is kept, until every run does. Returns
 * the points kept. */
static int core_points(const double (*p)[3], int n, double tol, bool *straight) {
    int left = 0;
    for (int i = 0; i < n; i++) {
        const double *a = p[(i + n - 1) % n], *b = p[i], *c = p[(i + 1) % n];
        double dot = (b[0] - a[0]) * (c[0] - b[0]) + (b[1] - a[1]) * (c[1] - b[1]);
        straight[i] = cn_turn2(a, b, c) == 0 && dot > 0; /* on, not back */
        left += !straight[i];
    }
    if (left < 3) { /* (an outline with area has three corners; keep every point if not) */
        memset(straight, 0, (size_t)n * sizeof(bool));
        left = n;
    }
    for (bool changed = true; changed;) {
        changed = false;
        for (int a = 0; a < n; a++) {
            if (straight[a]) continue;
            int b = (a + 1) % n;
            while (straight[b]) b = (b + 1) % n;
            double chord = hypot(p[b][0] - p[a][0], p[b][1] - p[a][1]), far = tol;
            int keep = -1;
            for (int x = (a + 1) % n; x != b; x = (x + 1) % n) {
                double d = chord > 0 ? fabs(orient(p[a], p[b], p[x])) / chord : hypot(p[x][0] - p[a][0], p[x][1] - p[a][1]);
                if (d > far) far = d, keep = x;
            }
            if (keep >= 0) straight[keep] = false, left++, changed = true;
        }
    }
    return left;
}

/* Hertel-Mehlhorn: each diagonal of the triangulation (a triangle edge that is not on the core's
 * outline) removed where the two pieces it separates stay convex at its ends. -1 when out of
 * memory. */
static int merge_diagonals(const double (*p)[3], const int *tri, int ntri, Lists *Lp) {
    Lists L = *Lp;
    for (int t = 0; t < ntri; t++)
        for (int e = 0; e < 3; e++) {
            int a = tri[3 * t + e], b = tri[3 * t + (e + 1) % 3];
            if (a > b) continue; /* each diagonal once (both of its triangles list it) */
            int ia, ib;
            int P = edge_owner(&L, a, b, &ia), Q = edge_owner(&L, b, a, &ib);
            if (P < 0 || Q < 0 || P == Q) continue; /* an outline edge */
            int mp = L.len[P], mq = L.len[Q];
            /* the merged piece: P from b round to a, then Q from after a to before b */
            int m = mp + mq - 2;
            int *w = cn_malloc(sizeof(int) * (size_t)(m + 1));
            if (!w) {
                *Lp = L;
                return -1;
            }
            int k = 0;
            for (int s = 1; s <= mp; s++) w[k++] = L.v[P][(ia + s) % mp]; /* b ... a */
            for (int s = 2; s < mq; s++) w[k++] = L.v[Q][(ib + s) % mq];  /* after a ... before b */
            /* convex at a (w[mp - 1]) and at b (w[0])? */
            bool convex = true;
            int at[2] = {mp - 1, 0};
            for (int z = 0; z < 2; z++) { /* convex there as the loader judges a corner */
                int u = at[z];
                if (cn_turn2(p[w[(u + m - 1) % m]], p[w[u]], p[w[(u + 1) % m]]) < 0) convex = false;
            }
            if (convex) {
                cn_free(L.v[P]);
                L.v[P] = w, L.len[P] = m, L.capv[P] = m + 1;
                L.dead[Q] = true;
            } else {
                cn_free(w);
            }
        }
    *Lp = L;
    return 0;
}

/* The straight-on points back, each on the piece edge between its core neighbours. -1 when an
 * edge has no piece or memory runs out. */
static int restore_straight(int n, const bool *straight, Lists *L) {
    for (int s = 0; s < n; s++) {
        if (!straight[s]) continue;
        int a = s, b = s;
        do a = (a + n - 1) % n;
        while (straight[a]);
        do b = (b + 1) % n;
        while (straight[b]);
        /* the run a .. b of the outline: put every straight vertex of it in once, from a */
        if ((s + n - 1) % n != a) continue; /* only from the first of the run */
        int at;
        int k = edge_owner(L, a, b, &at);
        if (k < 0) return -1;
        int run = 0;
        for (int x = (a + 1) % n; x != b; x = (x + 1) % n) run++;
        int *w = cn_malloc(sizeof(int) * (size_t)(L->len[k] + run + 1));
        if (!w) return -1;
        int q = 0;
        for (int u = 0; u <= at; u++) w[q++] = L->v[k][u];
        for (int x = (a + 1) % n; x != b; x = (x + 1) % n) w[q++] = x;
        for (int u = at + 1; u < L->len[k]; u++) w[q++] = L->v[k][u];
        cn_free(L->v[k]);
        L->v[k] = w, L->len[k] = q, L->capv[k] = q + 1;
    }
    return 0;
}

int cn_polygon_split(const double (*p)[3], int n, double tol, int *npieces, int **lens, int ***pieces) {
    *npieces = 0, *lens = NULL, *pieces = NULL;
    int *next = cn_malloc(sizeof(int) * (size_t)n), *prev = cn_malloc(sizeof(int) * (size_t)n);
    bool *straight = cn_calloc((size_t)n, sizeof(bool)), *ear = cn_calloc((size_t)n, sizeof(bool));
    int *tri = cn_malloc(sizeof(int) * 3 * (size_t)n);
    Lists L = {0};
    int rc = -1;
    if (!next || !prev || !straight || !ear || !tri) goto done;
    int left = core_points(p, n, tol, straight);
    for (int i = 0; i < n; i++) { /* link the core */
        if (straight[i]) continue;
        int b = (i + 1) % n;
        while (straight[b]) b = (b + 1) % n;
        next[i] = b, prev[b] = i;
    }
    /* ear clipping on the core (counter-clockwise): an ear's tip turns left and no other
       vertex of the core lies in its triangle */
    int start = 0;
    while (straight[start]) start++;
    int ntri = 0;
#define IS_EAR(i)                                                                             \
    do {                                                                                      \
        int a_ = prev[i], c_ = next[i];                                                       \
        double l_ = fmax(hypot(p[i][0] - p[a_][0], p[i][1] - p[a_][1]),                       \
                         hypot(p[c_][0] - p[i][0], p[c_][1] - p[i][1]));                      \
        ear[i] = orient(p[a_], p[i], p[c_]) > tol * l_;                                       \
        for (int j = next[c_]; ear[i] && j != a_; j = next[j])                                \
            if (in_triangle(p[j], p[a_], p[i], p[c_], tol)) ear[i] = false;                   \
    } while (0)
    for (int i = start, k = 0; k < left; k++, i = next[i]) IS_EAR(i);
    int i = start, guard = 0;
    while (left > 3) {
        if (ear[i]) {
            tri[3 * ntri] = prev[i], tri[3 * ntri + 1] = i, tri[3 * ntri + 2] = next[i];
            ntri++;
            int a = prev[i], c = next[i];
            next[a] = c, prev[c] = a, left--;
            IS_EAR(a);
            IS_EAR(c);
            i = c, guard = 0;
            continue;
        }
        i = next[i];
        if (++guard > left) { /* no ear: the outline is not simple (numerically) */
            rc = 1;
            goto done;
        }
    }
#undef IS_EAR
    tri[3 * ntri] = prev[i], tri[3 * ntri + 1] = i, tri[3 * ntri + 2] = next[i];
    ntri++;
    for (int t = 0; t < ntri; t++)
        if (lists_add(&L, &tri[3 * t], 3) < 0) goto done;
    if (merge_diagonals(p, tri, ntri, &L) < 0) goto done;
    if (restore_straight(n, straight, &L) < 0) goto done;
    /* hand the live pieces over */
    int live = 0;
    for (int k = 0; k < L.n; k++) live += !L.dead[k];
    *lens = cn_malloc(sizeof(int) * (size_t)live);
    *pieces = cn_malloc(sizeof(int *) * (size_t)live);
    if (!*lens || !*pieces) {
        cn_free(*lens), cn_free(*pieces);
        *lens = NULL, *pieces = NULL;
        goto done;
    }
    int q = 0;
    for (int k = 0; k < L.n; k++) {
        if (L.dead[k]) continue;
        (*lens)[q] = L.len[k];
        (*pieces)[q++] = L.v[k];
        L.v[k] = NULL;
    }
    *npieces = live;
    rc = 0;
done:
    lists_free(&L);
    cn_free(next), cn_free(prev), cn_free(straight), cn_free(ear), cn_free(tri);
    return rc;
}
