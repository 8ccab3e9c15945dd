/* search_joint.c's sliding modes and joint patterns against brute force (contact solutions built
 * by hand, sampled relative twists of a face, an LP of its own in the face's plane); search_learn.c's
 * learned prunes against LP re-solves and the search without them; warm_cache.c against Lemke. */
#include <glpk.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <valgrind/valgrind.h>

#include "check_work.h"
#include "helpers.h"
#include "search.h"

#define MAXK 12 /* contacts of a problem made here */
#define MAXD 8  /* friction directions */
/* Under valgrind's memcheck a quarter of the problems: memory, not coverage */
#define SHARE(n) (RUNNING_ON_VALGRIND ? ((n) + 3) / 4 : (n))

static int quiet(void *info, const char *s) {
    (void)info, (void)s;
    return 1;
}

static int rng_int(cnRng *r, int n) { return (int)(cn_rng_uniform(r) * n) % n; }

/* ---- problems ---------------------------------------------------------------------------- */

/* A contact problem made here: a fixed frame F far off, box A and maybe box B (2-D: A
 * [0,2]x[0,1], B [0.5,1.5]x[1,1.6]; 3-D: A [0,2]x[0,1]x[0,1], B [0.5,1.5]x[0.2,0.8]x[1,1.5])
 * under gravity turned ang from straight down (towards azimuth az), its contacts added one by
 * one (prob_contact) before prob_finish makes the rows: K normal rows, then D friction rows a
 * contact (2-D: +t then -t; 3-D: dir in its tangent basis). */
typedef struct {
    cnAssembly *a;
    cnMech m;
    bool built;
    int dim, F, A, B, K, D;
    int p1[MAXK], p2[MAXK];
    double pt[MAXK][3], nr[MAXK][3];
    double dir[MAXK][MAXD][2]; /* 3-D: each friction direction in the tangent basis */
    cnJRow rows[MAXK * (1 + MAXD)];
    int cof[MAXK];
    double mu[MAXK], nom[MAXK * MAXD];
    cnMotionProblem p;
} Prob;

static bool prob_new(Prob *q, int dim, bool two, double ang, double az, int D) {
    memset(q, 0, sizeof *q);
    char json[1024];
    if (dim == 2)
        scene_two_boxes_2d(json, sizeof json, ang, two);
    else
        snprintf(json, sizeof json,
                 "{\"dimension\":3,\"gravity\":[%.17g,%.17g,%.17g],\"parts\":["
                 "{\"name\":\"F\",\"fixed\":true,\"box\":{\"min\":[-9,-9,-9],\"max\":[-8,-8,-8]}},"
                 "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[2,1,1]}}%s]}",
                 9.81 * sin(ang) * cos(az), 9.81 * sin(ang) * sin(az), -9.81 * cos(ang),
                 two ? ",{\"name\":\"B\",\"box\":{\"min\":[0.5,0.2,1],\"max\":[1.5,0.8,1.5]}}" : "");
    q->a = load_ok(json);
    if (!q->a) return false;
    cnDiag d;
    if (cn_mech_build(q->a, NULL, NULL, &q->m, &d) != CN_OK) {
        CHECK_MSG(0, "mech: %s", d.message);
        return false;
    }
    q->built = true;
    q->dim = dim;
    q->D = dim == 2 ? 2 : D;
    q->F = cn_assembly_find_part(q->a, "F");
    q->A = cn_assembly_find_part(q->a, "A");
    q->B = two ? cn_assembly_find_part(q->a, "B") : -1;
    return true;
}

static void prob_free(Prob *q) {
    if (q->built) cn_mech_free(&q->m);
    if (q->a) cn_assembly_free(q->a);
    q->a = NULL, q->built = false;
}

/* Contact part1 on part2 at pt, normal nr (into part2); in 3-D its directions at off + sgn (2 pi
 * j / D + jitter_j), the jitter (when asked) up to 0.15 of the even spacing, so that
 * consecutive directions stay less than pi apart. */
static void prob_contact(Prob *q, int part1, int part2, const double pt[3], const double nr[3],
                         double mu, double off, double sgn, cnRng *jitter) {
    if (q->K >= MAXK) return;
    int c = q->K++, D = q->D;
    q->p1[c] = part1, q->p2[c] = part2;
    cn_copy3(q->pt[c], pt);
    cn_copy3(q->nr[c], nr);
    q->mu[c] = mu;
    for (int j = 0; j < D; j++) {
        double jit = jitter ? cn_rng_range(jitter, -0.15, 0.15) * 2 * CN_PI / D : 0;
        double th = off + sgn * (2 * CN_PI * j / D + jit);
        q->dir[c][j][0] = cos(th), q->dir[c][j][1] = sin(th);
    }
}

/* The tangent basis of a normal along an axis: t1 the next axis, t2 = n x t1 (n = +z: x, y). */
static void tangents(const double nr[3], double t1[3], double t2[3]) {
    int k = 0;
    for (int x = 1; x < 3; x++)
        if (fabs(nr[x]) > fabs(nr[k])) k = x;
    t1[0] = t1[1] = t1[2] = 0;
    t1[(k + 1) % 3] = 1;
    cn_cross3(nr, t1, t2);
}

/* The rows and the problem; vf (when not NULL): the frame slides under the boxes at vf (nominal
 * sliding along the frame's contacts' friction rows). */
static void prob_finish(Prob *q, const double vf[3]) {
    int K = q->K, D = q->D;
    for (int c = 0; c < K; c++) {
        cn_mech_row(&q->m, q->p1[c], q->p2[c], q->pt[c], q->nr[c], &q->rows[c]);
        q->cof[c] = c;
        double t1[3], t2[3];
        if (q->dim == 2) t1[0] = -q->nr[c][1], t1[1] = q->nr[c][0], t1[2] = 0;
        else tangents(q->nr[c], t1, t2);
        for (int j = 0; j < D; j++) {
            double dir[3];
            for (int x = 0; x < 3; x++)
                dir[x] = q->dim == 2 ? (j ? -t1[x] : t1[x])
                                     : q->dir[c][j][0] * t1[x] + q->dir[c][j][1] * t2[x];
            cn_mech_row(&q->m, q->p1[c], q->p2[c], q->pt[c], dir, &q->rows[K + c * D + j]);
            q->nom[c * D + j] = vf && q->p1[c] == q->F ? -cn_dot3(vf, dir) : 0;
        }
    }
    q->p = (cnMotionProblem){&q->m, K, K, D, q->rows, q->cof, q->mu, vf ? q->nom : NULL,
                             CN_DEFAULT_MOTION_TOL, 200000, false, 0, NULL, NULL, false, NULL, 0};
}

/* The search's state for problem p as cn_bb_search_group sets it up: friction groups, the node
 * LP (energy search unless nominal sliding drags a body), nothing fixed. False when it fails. */
static bool bb_open(Bb *s, const cnMotionProblem *p) {
    const cnMech *m = p->m;
    memset(s, 0, sizeof *s);
    s->p = p;
    s->nv = m->nb * m->nd;
    if (cn_bb_group(s) != 0) return false;
    s->nrows = p->K + s->G * p->D;
    s->n = s->nrows + s->G;
    s->budget = 1000000;
    s->seconds = INFINITY;
    size_t n1 = (size_t)s->n + 1, v1 = (size_t)s->nv + 1;
    s->sv = cn_malloc(sizeof(double) * v1);
    s->wcol = cn_malloc(sizeof(double) * ((size_t)s->nrows + 1));
    s->rowlo = cn_malloc(sizeof(double) * n1);
    s->fix = cn_calloc(n1, 1);
    s->fix0 = cn_calloc(n1, 1);
    s->x = cn_malloc(sizeof(double) * n1);
    s->wv = cn_malloc(sizeof(double) * n1);
    s->lambda = cn_malloc(sizeof(double) * ((size_t)p->Kf + 1));
    s->a = cn_malloc(sizeof(double) * v1);
    s->ma = cn_malloc(sizeof(double) * v1);
    if (!s->sv || !s->wcol || !s->rowlo || !s->fix || !s->fix0 || !s->x || !s->wv || !s->lambda ||
        !s->a || !s->ma)
        return false;
    s->energy = !cn_motion_drags(p->rows, p->K, p->Kf, p->D, p->nominal);
    return cn_bb_build(s, s->energy) == 0;
}

static void bb_close(Bb *s) {
    if (s->P) glp_delete_prob(s->P);
    cn_free(s->sv), cn_free(s->wcol), cn_free(s->rowlo), cn_free(s->fix), cn_free(s->fix0);
    cn_free(s->ng), cn_free(s->ng_end), cn_free(s->x), cn_free(s->wv), cn_free(s->lambda);
    cn_free(s->a), cn_free(s->ma), cn_free(s->grep), cn_free(s->gfirst), cn_free(s->gmem);
    cn_free(s->joint), cn_free(s->jfirst), cn_free(s->jmem);
    for (size_t i = 0; s->jpat && i < (size_t)s->NJ << CN_BB_JOINT_MAX; i++) cn_free(s->jpat[i]);
    cn_free(s->jpat), cn_free(s->jnpat);
    for (int i = 0; i < TMP_SLOTS; i++) cn_free(s->tmp[i]);
    memset(s, 0, sizeof *s);
}

/* ---- sliding modes ----------------------------------------------------------------------- */

/* A contact's friction directions in its tangent basis (D = 2: +t and -t). */
static void contact_dirs(const Prob *q, int c, double *dx, double *dy) {
    for (int j = 0; j < q->D; j++) {
        if (q->dim == 2) dx[j] = j ? -1 : 1, dy[j] = 0;
        else dx[j] = q->dir[c][j][0], dy[j] = q->dir[c][j][1];
    }
}

/* A friction contact's complementary solution with unit normal force, built by hand from its
 * slip u: stuck (u = 0, lambda = 0) with friction r mu inside the cone, or sliding with lambda
 * = max_d (-d.u) and the friction mu against the direction attaining it, shared with weight
 * `share` with the next one when `tie` (the two attain it together). z, w (D + 1): the friction
 * rows' forces and w_d = d.u + lambda, then lambda and zeta = mu - sum p. */
static void contact_solution(int D, const double *dx, const double *dy, double mu, double ux,
                             double uy, int tie, double share, double r, cnRng *rng, double *z,
                             double *w) {
    if (ux == 0 && uy == 0) {
        double sum = 0;
        for (int d = 0; d < D; d++) z[d] = cn_rng_uniform(rng), sum += z[d];
        for (int d = 0; d < D; d++) z[d] *= r * mu / sum, w[d] = 0;
        z[D] = 0, w[D] = mu - r * mu;
        return;
    }
    double vmin = INFINITY;
    int j = 0;
    for (int d = 0; d < D; d++) {
        double v = dx[d] * ux + dy[d] * uy;
        if (v < vmin) vmin = v, j = d;
    }
    if (tie >= 0) j = tie;
    for (int d = 0; d < D; d++) z[d] = 0, w[d] = dx[d] * ux + dy[d] * uy - vmin;
    if (tie >= 0) {
        z[j] = share * mu, z[(j + 1) % D] = (1 - share) * mu;
        w[j] = w[(j + 1) % D] = 0; /* equal up to rounding: exactly zero in the solution */
    } else {
        z[j] = mu, w[j] = 0;
    }
    z[D] = -vmin, w[D] = 0;
}

/* Each friction group's modes (cn_bb_mode, cn_bb_mode_far) against complementary solutions of
 * the contact built by hand: each solution (stuck; sliding in general; sliding against two
 * adjacent directions at once, in 3-D) makes zero what exactly one mode fixes at zero, the one
 * the modes' numbering gives it (2-D: 1 sliding along +t, 2 along -t; 3-D: 1 + j, d_j the
 * direction of least d.u, the first of two), and cn_bb_mode's fixes are what cn_bb_mode_far
 * sums. With the contract of cn_bb_mode_group and cn_bb_group_free (from search_joint.c's
 * comments). 2-D and 3-D single boxes, 3 to 7 friction directions unevenly spaced, in either
 * angular order. */
static void test_sliding_modes(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x51ed2701a3c5f9e7ULL};
    int samples = 0, ties = 0, sticks = 0, grouped = 0;
    for (int t = 0; t < SHARE(20); t++) {
        int dim = t % 4 == 0 ? 2 : 3, D = 3 + t % 5;
        Prob q;
        if (!prob_new(&q, dim, false, cn_rng_range(&rng, -0.5, 0.5), cn_rng_range(&rng, 0, 2 * CN_PI), D)) {
            prob_free(&q);
            return;
        }
        D = q.D;
        double mu0 = cn_rng_range(&rng, 0.1, 1.2);
        int K = dim == 2 ? 3 : 2 + t % 3;
        for (int c = 0; c < K; c++) {
            double pt[3] = {0, 0, 0}, nr[3] = {0, dim == 2, dim == 3};
            if (dim == 2 && c == 2) pt[1] = 0.5, nr[0] = 1, nr[1] = 0; /* on A's left side */
            else if (dim == 2) pt[0] = 2.0 * c;                   /* the bottom corners: one group */
            else pt[0] = cn_rng_range(&rng, 0, 2), pt[1] = cn_rng_range(&rng, 0, 1);
            double sgn = cn_rng_uniform(&rng) < 0.5 ? 1 : -1;
            prob_contact(&q, q.F, q.A, pt, nr, c == 2 ? 0.5 * mu0 : mu0, cn_rng_range(&rng, 0, 2 * CN_PI),
                         sgn, t % 2 ? &rng : NULL);
        }
        prob_finish(&q, NULL);
        Bb s;
        if (!bb_open(&s, &q.p)) {
            CHECK_MSG(0, "modes trial %d: the search's state not built", t);
            bb_close(&s), prob_free(&q);
            return;
        }
        int nrw = s.nrows, n = s.n;
        grouped += s.G < K;
        /* the group of each pair: none for a normal pair */
        for (int i = 0; i < n; i++) {
            int want = i < K ? -1 : i < nrw ? (i - K) / D : i - nrw;
            CHECK_MSG(cn_bb_mode_group(&s, i) == want, "modes trial %d: pair %d", t, i);
        }
        for (int g = 0; g < s.G; g++) CHECK(cn_bb_group_free(&s, g));
        /* one pair of group g0 fixed: none of g0's pairs is branched on by modes, others are */
        int g0 = rng_int(&rng, s.G), d0 = rng_int(&rng, D + 1);
        int pair0 = d0 == D ? nrw + g0 : K + g0 * D + d0;
        cn_bb_pair_set(&s, pair0, 1 + rng_int(&rng, 2));
        for (int i = K; i < n; i++) {
            int g = i < nrw ? (i - K) / D : i - nrw;
            CHECK(cn_bb_mode_group(&s, i) == (g == g0 ? -1 : g));
            CHECK(cn_bb_group_free(&s, g) == (g != g0));
        }
        /* switched from one side to the other: only the new side is fixed in the LP */
        int col0 = s.nv + pair0 + 1;
        cn_bb_pair_set(&s, pair0, 1);
        cn_bb_pair_set(&s, pair0, 2);
        CHECK(glp_get_col_type(s.P, col0) == GLP_LO && glp_get_row_type(s.P, col0) == GLP_FX);
        cn_bb_pair_set(&s, pair0, 1);
        CHECK(glp_get_col_type(s.P, col0) == GLP_FX && glp_get_row_type(s.P, col0) == GLP_LO);
        cn_bb_pair_set(&s, pair0, 0);
        CHECK(glp_get_col_type(s.P, col0) == GLP_LO && glp_get_row_type(s.P, col0) == GLP_LO);
        /* outside the energy search a pyramid's modes are not branched on */
        s.energy = false;
        for (int i = K; i < n; i++) {
            int g = i < nrw ? (i - K) / D : i - nrw;
            CHECK(cn_bb_mode_group(&s, i) == (D > 2 ? -1 : g));
        }
        s.energy = true;
        for (int g = 0; g < s.G; g++) {
            int c = q.cof[s.grep[g]];
            double dx[MAXD], dy[MAXD];
            contact_dirs(&q, c, dx, dy);
            for (int smp = 0; smp < 40; smp++) {
                int kind = smp % 5; /* 0 stuck, 1 two directions at once (3-D), else sliding */
                double ux = 0, uy = 0, len = cn_rng_range(&rng, 0.05, 2);
                int tie = -1, want;
                if (kind == 1 && D > 2) {
                    tie = rng_int(&rng, D);
                    int j1 = (tie + 1) % D;
                    double sx = dx[tie] + dx[j1], sy = dy[tie] + dy[j1], l = sqrt(sx * sx + sy * sy);
                    ux = -len * sx / l, uy = -len * sy / l;
                } else if (kind != 0) {
                    double phi = cn_rng_range(&rng, 0, 2 * CN_PI);
                    ux = len * cos(phi), uy = dim == 2 ? 0 : len * sin(phi);
                    if (dim == 2 && ux == 0) ux = len;
                }
                double z[MAXD + 1], w[MAXD + 1];
                contact_solution(D, dx, dy, q.mu[c], ux, uy, tie, cn_rng_range(&rng, 0.2, 0.8),
                                 cn_rng_range(&rng, 0.1, 0.9), &rng, z, w);
                if (kind == 0) want = 0;
                else if (D == 2) want = ux > 0 ? 1 : 2;
                else if (tie >= 0) want = 1 + tie;
                else {
                    want = 0;
                    for (int d = 0; d < D; d++)
                        if (w[d] == 0 && z[d] > 0) want = 1 + d;
                }
                samples++, ties += tie >= 0, sticks += kind == 0;
                for (int i = 0; i < n; i++) s.x[i] = s.wv[i] = NAN; /* only g's pairs are read */
                for (int d = 0; d <= D; d++) {
                    int i = d < D ? K + g * D + d : nrw + g;
                    s.x[i] = z[d], s.wv[i] = w[d];
                }
                for (int mode = 0; mode <= D; mode++) {
                    double far = cn_bb_mode_far(&s, g, mode);
                    if (mode == want)
                        CHECK_MSG(fabs(far) <= 1e-12, "modes trial %d, group %d, sample %d: mode %d "
                                  "leaves %g of the solution it holds", t, g, smp, mode, far);
                    else
                        CHECK_MSG(far > 1e-9, "modes trial %d, group %d, sample %d (mode %d): mode %d "
                                  "holds it too (%g)", t, g, smp, want, mode, far);
                    int fixed[MAXD + 2], nf = 0;
                    cn_bb_mode(&s, g, mode, fixed, &nf);
                    double sum = 0;
                    bool ok = nf > 0 && nf <= D + 1;
                    for (int a = 0; a < nf; a++) {
                        int i = fixed[a], ch = s.fix[i], col = s.nv + i + 1;
                        ok &= (i >= K + g * D && i < K + (g + 1) * D) || i == nrw + g;
                        for (int b = 0; b < a; b++) ok &= fixed[b] != i;
                        if (ch == 1)
                            ok &= glp_get_col_type(s.P, col) == GLP_FX && glp_get_col_ub(s.P, col) == 0;
                        else ok &= ch == 2 && glp_get_row_type(s.P, col) == GLP_FX &&
                                   glp_get_row_lb(s.P, col) == s.rowlo[i];
                        sum += ch == 1 ? s.x[i] : s.wv[i];
                    }
                    CHECK_MSG(ok, "modes trial %d, group %d: mode %d fixes other pairs, or wrongly", t, g,
                              mode);
                    CHECK_NEAR(sum, far, 1e-12);
                    for (int a = 0; a < nf; a++) cn_bb_pair_set(&s, fixed[a], 0);
                }
            }
        }
        for (int i = 0; i < n; i++) CHECK(s.fix[i] == 0);
        bb_close(&s);
        prob_free(&q);
    }
    printf("search modes: %d contact solutions (%d stuck, %d against two directions) each in "
           "exactly its mode; %d problems with a friction group of two points\n",
           samples, sticks, ties, grouped);
    if (!RUNNING_ON_VALGRIND) CHECK(ties > 50 && sticks > 100 && grouped > 0);
}

/* ---- joint patterns ---------------------------------------------------------------------- */

/* A joint's points in the plane of its face (+z normal) in member order, and each one's
 * friction directions: under the relative twist of the two bodies, the in-plane slip of point i
 * is (vx - w (y_i - cy), vy + w (x_i - cx)) for a translation (vx, vy) and a turn w about
 * (cx, cy) (any motion of the two bodies slides a face so: its out-of-plane turns only add the
 * same translation at every point of the plane). */
typedef struct {
    int k, D;
    double x[MAXK], y[MAXK];
    double dx[MAXK][MAXD], dy[MAXK][MAXD];
} Face;

/* The mode of point i slipping by (ux, uy): 0 stuck; else 1 + j, d_j a direction of least d.u,
 * the first of two adjacent such (exact ties: a slip between d_j and d_{j+1} is mode j's). */
static int slip_mode(const Face *f, int i, double ux, double uy) {
    if (ux == 0 && uy == 0) return 0;
    int D = f->D, j = 0;
    double best = INFINITY;
    for (int d = 0; d < D; d++) {
        double v = f->dx[i][d] * ux + f->dy[i][d] * uy;
        if (v < best) best = v, j = d;
    }
    int jp = (j + D - 1) % D;
    if (f->dx[i][jp] * ux + f->dy[i][jp] * uy == best) j = jp;
    return 1 + j;
}

/* Code of a pattern of k modes (base D + 1). */
static int pat_code(const unsigned char *pat, int k, int D) {
    int code = 0;
    for (int q = k - 1; q >= 0; q--) code = code * (D + 1) + pat[q];
    return code;
}

/* The oracle's LP in the face's plane: columns vx, vy, w (turn about the origin) in [-1, 1] and
 * the margin t in [0, 1], maximised. */
static glp_prob *plane_new(void) {
    glp_prob *P = glp_create_prob();
    glp_set_obj_dir(P, GLP_MAX);
    glp_add_cols(P, 4);
    for (int c = 1; c <= 3; c++) glp_set_col_bnds(P, c, GLP_DB, -1.0, 1.0);
    glp_set_col_bnds(P, 4, GLP_DB, 0.0, 1.0);
    glp_set_obj_coef(P, 4, 1.0);
    return P;
}

static void plane_row(glp_prob *P, double a, double b, double c, double t, int type) {
    int ind[5], n = 0;
    double val[5], co[4] = {a, b, c, t};
    for (int j = 0; j < 4; j++)
        if (co[j] != 0) ind[++n] = j + 1, val[n] = co[j];
    int r = glp_add_rows(P, 1);
    glp_set_mat_row(P, r, n, ind, val);
    glp_set_row_bnds(P, r, type, 0.0, 0.0);
}

/* Point i in mode `mode`: stuck, u_i = 0; sliding (1 + j), (d_j - d).u_i <= 0 for every other
 * d, with the margin t on the one against d_{j-1} (the tie rule), or on all of them (`all`:
 * the inside of the mode's cone). */
static void plane_rows(glp_prob *P, const Face *f, int i, int mode, bool all) {
    double X = f->x[i], Y = f->y[i];
    if (mode == 0) {
        plane_row(P, 1, 0, -Y, 0, GLP_FX);
        plane_row(P, 0, 1, X, 0, GLP_FX);
        return;
    }
    int D = f->D, j = mode - 1, jp = (j + D - 1) % D;
    for (int d = 0; d < D; d++) {
        if (d == j) continue;
        double cx = f->dx[i][j] - f->dx[i][d], cy = f->dy[i][j] - f->dy[i][d];
        plane_row(P, cx, cy, cy * X - cx * Y, all || d == jp ? 1.0 : 0.0, GLP_UP);
    }
}

/* The largest margin (always feasible: the zero twist with t = 0); sol (3, or NULL) receives
 * the twist. -1 when the solver fails. */
static double plane_max(glp_prob *P, double *sol) {
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    glp_std_basis(P);
    if (glp_simplex(P, &parm) != 0 || glp_get_status(P) != GLP_OPT) return -1;
    for (int c = 0; sol && c < 3; c++) sol[c] = glp_get_col_prim(P, c + 1);
    return glp_get_obj_val(P);
}

static void plane_clear(glp_prob *P, int first) {
    int last = glp_get_num_rows(P), del[4 * MAXK * MAXD + 1], nd = 0;
    for (int r = first; r <= last; r++) del[++nd] = r;
    if (nd > 0) glp_del_rows(P, nd, del);
}

/* A pattern exists (some twist gives it) when the margin of the tie rule's strict inequalities
 * exceeds this (the conditions are cones: one that exists has a margin of order 1e-2 here). */
#define PLANE_EXISTS 1e-9

/* Every pattern of members mem[0..k) by depth-first search over their modes, the prefixes with
 * no twist pruned; found[code] set for each. */
static void plane_enum(glp_prob *P, const Face *f, const int *mem, int k, int q, int code, int mult,
                       unsigned char *found, long *lps) {
    for (int mode = 0; mode <= f->D; mode++) {
        int first = glp_get_num_rows(P) + 1;
        plane_rows(P, f, mem[q], mode, false);
        ++*lps;
        if (plane_max(P, NULL) > PLANE_EXISTS) {
            if (q + 1 < k) plane_enum(P, f, mem, k, q + 1, code + mode * mult, mult * (f->D + 1), found, lps);
            else found[code + mode * mult] = 1;
        }
        plane_clear(P, first);
    }
}

/* Slips of twist (vx, vy, w about (cx, cy)) at members mem[0..k), and their modes into pat. */
static void twist_modes(const Face *f, const int *mem, int k, const double tw[5], unsigned char *pat) {
    for (int q = 0; q < k; q++) {
        int i = mem[q];
        double ux = tw[0] - tw[2] * (f->y[i] - tw[4]), uy = tw[1] + tw[2] * (f->x[i] - tw[3]);
        pat[q] = (unsigned char)slip_mode(f, i, ux, uy);
    }
}

/* Sample smp of the relative twists: the zero twist, translations, turns about a member point
 * (it sticks), about points on the line of two members (at multiples of 1/8 of their distance,
 * so that a tie stays exact), and about poles near the face (within 1 or 3 of its centre) and
 * far from it (within 40). */
static void twist_sample(cnRng *rng, const Face *f, int smp, double tw[5]) {
    int kind = smp % 8, k = f->k;
    double w = cn_rng_uniform(rng) < 0.5 ? 1 : -1, cx = 0, cy = 0;
    for (int i = 0; i < k; i++) cx += f->x[i] / k, cy += f->y[i] / k;
    tw[0] = tw[1] = tw[2] = tw[3] = tw[4] = 0;
    if (smp == 0) return;
    if (kind == 0 && smp / 8 % 2) { /* along an axis or a diagonal: ties in the aligned faces */
        int a = rng_int(rng, 8);
        tw[0] = a % 4 == 2 ? 0 : a < 2 || a == 7 ? 1 : -1, tw[1] = a % 4 == 0 ? 0 : a < 4 ? 1 : -1;
    } else if (kind == 0) {
        double a = cn_rng_range(rng, 0, 2 * CN_PI);
        tw[0] = cos(a), tw[1] = sin(a);
    } else if (kind == 1) {
        int i = (smp / 8) % k;
        tw[2] = w, tw[3] = f->x[i], tw[4] = f->y[i];
    } else if (kind == 2) {
        int a = rng_int(rng, k), b = (a + 1 + rng_int(rng, k - 1)) % k;
        double s = rng_int(rng, 41) / 8.0 - 2; /* dyadic points: slips of a and b exactly parallel */
        tw[2] = w, tw[3] = f->x[a] + s * (f->x[b] - f->x[a]), tw[4] = f->y[a] + s * (f->y[b] - f->y[a]);
        if (s == 1) tw[3] = f->x[b], tw[4] = f->y[b];
    } else {
        double span = kind == 3 ? 40 : kind < 6 ? 3 : 1;
        tw[2] = w, tw[3] = cx + cn_rng_range(rng, -span, span), tw[4] = cy + cn_rng_range(rng, -span, span);
    }
}

#define NSAMPLES 6000

/* Joint patterns (cn_bb_joint_patterns) of one face between two bodies, box A on the frame or box
 * B on box A, 2 to 5 points (corners, anywhere, on one line, or corners and one anywhere), 3 to
 * 6 friction directions a point (the same set at every point, or each its own, unevenly
 * spaced, either angular order), against:
 *   completeness: the modes of 6,000 sampled relative twists (slip_mode, by brute force), each
 *     one a listed pattern; and every pattern an LP of the oracle's own in the face's plane
 *     finds (plane_enum) is listed;
 *   soundness: every listed pattern is one that LP finds, and where its cone has an inside,
 *     the twist at its centre has exactly that pattern by brute force;
 *   subsets: the patterns of a subset of the members (mask) are the full patterns cut to it;
 *   prefixes: cn_bb_prefix_children pushes one child per mode the member has among the patterns
 *     agreeing with the one given on the members before it, the nearest popped first.
 * Four more faces are aligned with their directions, so that patterns of a tie alone (a slip
 * exactly between two directions, given to the first by the tie rule) exist: each must be one a
 * sampled twist gives exactly. */
static void test_joint_patterns(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x2545f4914f6cdd1dULL};
    int nrand = SHARE(24), ntr = nrand + 4, thin = 0, thin_hit = 0, masks = 0, prefixes = 0, unhit = 0;
    long sampled = 0, listed = 0, lps = 0;
    /* the last four faces have slips exactly between two directions (D = 4, exact directions;
       the points' differences along the ties, their coordinates dyadic): patterns of a tie alone
       exist, the tie rule decides them */
    double h = sqrt(0.5);
    const double diag[4][2] = {{h, h}, {-h, h}, {-h, -h}, {h, -h}},
                 axes[4][2] = {{1, 0}, {0, 1}, {-1, 0}, {0, -1}},
                 back[4][2] = {{h, h}, {h, -h}, {-h, -h}, {-h, h}};
    const double sq[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}},
                 tri[3][2] = {{0.5, 0.25}, {1.5, 0.25}, {1.5, 0.75}},
                 line[3][2] = {{0, 0.5}, {1, 0.5}, {2, 0.5}};
    for (int t = 0; t < ntr; t++) {
        int al = t - nrand; /* the aligned faces: 0 to 3 */
        bool top = al < 0 ? t % 2 == 1 : al == 2;
        int k = 2 + (t / 2) % 3, D = 3 + (t / 6) % 4, style = rng_int(&rng, 4);
        if (t == nrand - 1) k = 5, D = 3, style = 1;
        if (al >= 0) k = al < 2 ? 4 : 3, D = 4;
        Prob q;
        if (!prob_new(&q, 3, top, cn_rng_range(&rng, -0.3, 0.3), cn_rng_range(&rng, 0, 2 * CN_PI), D)) {
            prob_free(&q);
            return;
        }
        double lo[2] = {top ? 0.5 : 0, top ? 0.2 : 0}, hi[2] = {top ? 1.5 : 2, top ? 0.8 : 1};
        double z = top ? 1 : 0, nz[3] = {0, 0, 1};
        int corner[4] = {0, 1, 2, 3};
        for (int a = 3; a > 0; a--) {
            int b = rng_int(&rng, a + 1), tmp = corner[a];
            corner[a] = corner[b], corner[b] = tmp;
        }
        double l0[2], l1[2]; /* the line of the collinear style */
        for (int x = 0; x < 2; x++)
            l0[x] = cn_rng_range(&rng, lo[x], hi[x]), l1[x] = cn_rng_range(&rng, lo[x], hi[x]);
        bool same_dirs = cn_rng_uniform(&rng) < 0.5, jitter = cn_rng_uniform(&rng) < 0.5;
        double off = cn_rng_range(&rng, 0, 2 * CN_PI), sgn = cn_rng_uniform(&rng) < 0.5 ? 1 : -1;
        cnRng jrng = rng; /* the same jitter at every point when the sets are the same */
        for (int c = 0; c < k; c++) {
            double pt[3] = {0, 0, z};
            bool at_corner = (style == 0 || style == 3) && c < 4 && !(style == 3 && c == k - 1);
            if (al >= 0) {
                const double(*at)[2] = al < 2 ? sq : al == 2 ? tri : line;
                pt[0] = at[c][0], pt[1] = at[c][1];
            } else if (at_corner) {
                int cc = corner[c];
                pt[0] = cc == 1 || cc == 2 ? hi[0] : lo[0], pt[1] = cc >= 2 ? hi[1] : lo[1];
            } else if (style == 2) {
                double s = cn_rng_uniform(&rng);
                for (int x = 0; x < 2; x++) pt[x] = l0[x] + s * (l1[x] - l0[x]);
            } else {
                for (int x = 0; x < 2; x++) pt[x] = cn_rng_range(&rng, lo[x], hi[x]);
            }
            if (!same_dirs) off = cn_rng_range(&rng, 0, 2 * CN_PI), sgn = cn_rng_uniform(&rng) < 0.5 ? 1 : -1;
            cnRng jr = same_dirs ? jrng : rng;
            prob_contact(&q, top ? q.A : q.F, top ? q.B : q.A, pt, nz, cn_rng_range(&rng, 0.1, 1.2), off,
                         sgn, jitter ? &jr : NULL);
            if (!same_dirs) rng = jr;
            for (int j = 0; al >= 0 && j < D; j++) {
                const double(*dd)[2] = al == 1 ? axes : al == 2 ? back : diag;
                q.dir[c][j][0] = dd[j][0], q.dir[c][j][1] = dd[j][1];
            }
        }
        prob_finish(&q, NULL);
        Bb s;
        if (!bb_open(&s, &q.p) || cn_bb_joints(&s) != 0) {
            CHECK_MSG(0, "joint trial %d: the search's state not built", t);
            bb_close(&s), prob_free(&q);
            return;
        }
        CHECK_MSG(s.NJ == 1 && s.jfirst[1] - s.jfirst[0] == k, "joint trial %d: %d joints", t, s.NJ);
        if (s.NJ != 1 || s.jfirst[1] - s.jfirst[0] != k) {
            bb_close(&s), prob_free(&q);
            continue;
        }
        Face f = {k, D, {0}, {0}, {{0}}, {{0}}};
        int mem[MAXK];
        for (int m = 0; m < k; m++) {
            int c = q.cof[s.grep[s.jmem[m]]];
            f.x[m] = q.pt[c][0], f.y[m] = q.pt[c][1];
            for (int j = 0; j < D; j++) f.dx[m][j] = q.dir[c][j][0], f.dy[m][j] = q.dir[c][j][1];
            mem[m] = m;
        }
        unsigned full = (1u << k) - 1;
        int np = cn_bb_joint_patterns(&s, 0, full), size = 1;
        for (int m = 0; m < k; m++) size *= D + 1;
        CHECK_MSG(np > 0, "joint trial %d: no patterns", t);
        const unsigned char *pats = s.jpat[full];
        unsigned char *in_code = calloc((size_t)size, 1), *in_mine = calloc((size_t)size, 1),
                      *hit = calloc((size_t)size, 1);
        if (!in_code || !in_mine || !hit) goto next;
        listed += np;
        int dup = 0, bad = 0;
        for (int p = 0; p < np; p++) {
            for (int m = 0; m < k; m++) bad += pats[p * k + m] > D;
            int code = pat_code(pats + p * k, k, D);
            dup += in_code[code];
            in_code[code] = 1;
        }
        CHECK_MSG(dup == 0 && bad == 0, "joint trial %d: %d patterns listed twice, %d bad modes", t,
                  dup, bad);
        /* completeness: the sampled twists */
        int missing = 0;
        for (int smp = 0; smp < SHARE(NSAMPLES); smp++) {
            double tw[5];
            unsigned char pat[MAXK];
            twist_sample(&rng, &f, smp, tw);
            twist_modes(&f, mem, k, tw, pat);
            int code = pat_code(pat, k, D);
            if (!in_code[code] && missing++ == 0) {
                fprintf(stderr, "joint trial %d (%d points, D %d, style %d): twist (%g, %g, %g about %g, %g) "
                        "gives a pattern not listed:", t, k, D, style, tw[0], tw[1], tw[2], tw[3], tw[4]);
                for (int m = 0; m < k; m++) fprintf(stderr, " %d", pat[m]);
                fprintf(stderr, "\n");
            }
            hit[code] = 1;
            sampled++;
        }
        CHECK_MSG(missing == 0, "joint trial %d: %d sampled twists give patterns not listed", t, missing);
        /* completeness and soundness: the oracle's own enumeration */
        glp_prob *P = plane_new();
        plane_enum(P, &f, mem, k, 0, 0, 1, in_mine, &lps);
        int extra = 0, absent = 0;
        for (int code = 0; code < size; code++) {
            extra += in_code[code] && !in_mine[code];
            absent += in_mine[code] && !in_code[code];
        }
        CHECK_MSG(extra == 0 && absent == 0, "joint trial %d (%d points, D %d): %d patterns listed that no "
                  "twist gives, %d that one gives not listed", t, k, D, extra, absent);
        /* soundness: the centre of each listed pattern's cone has that pattern */
        int wrong = 0;
        for (int p = 0; p < np; p++) {
            const unsigned char *pat = pats + p * k;
            for (int m = 0; m < k; m++) plane_rows(P, &f, m, pat[m], true);
            double sol[3], margin = plane_max(P, sol);
            plane_clear(P, 1);
            if (!(margin > 1e-7)) { /* a pattern of the tie's boundary alone */
                thin++, thin_hit += hit[pat_code(pat, k, D)];
                continue;
            }
            double tw[5] = {sol[0], sol[1], sol[2], 0, 0};
            unsigned char got[MAXK];
            twist_modes(&f, mem, k, tw, got);
            for (int m = 0; m < k; m++) {
                double ux = sol[0] - sol[2] * f.y[m], uy = sol[1] + sol[2] * f.x[m];
                bool ok = pat[m] == 0 ? fabs(ux) + fabs(uy) <= 1e-9 : got[m] == pat[m];
                wrong += !ok;
            }
            unhit += !hit[pat_code(pat, k, D)];
        }
        CHECK_MSG(wrong == 0, "joint trial %d: %d members of listed patterns slip otherwise", t, wrong);
        glp_delete_prob(P);
        /* subsets of the members: the full patterns cut to them */
        for (unsigned mask = 1; mask < full; mask++) {
            int mm[MAXK], km = 0;
            for (int m = 0; m < k; m++)
                if (mask >> m & 1) mm[km++] = m;
            if (km < 2 || (k >= 4 && cn_rng_uniform(&rng) < 0.6)) continue;
            int nm = cn_bb_joint_patterns(&s, 0, mask), sz = 1;
            for (int m = 0; m < km; m++) sz *= D + 1;
            unsigned char *cut = calloc((size_t)sz, 1), *got = calloc((size_t)sz, 1);
            if (!cut || !got) {
                free(cut), free(got);
                continue;
            }
            for (int p = 0; p < np; p++) {
                unsigned char pat[MAXK];
                for (int m = 0; m < km; m++) pat[m] = pats[p * k + mm[m]];
                cut[pat_code(pat, km, D)] = 1;
            }
            for (int p = 0; p < nm; p++) got[pat_code(s.jpat[mask] + p * km, km, D)] = 1;
            CHECK_MSG(nm > 0 && memcmp(cut, got, (size_t)sz) == 0,
                      "joint trial %d: the patterns of mask %u are not the full ones cut to it", t, mask);
            masks++;
            free(cut), free(got);
        }
        /* prefixes: the children of a node branching on member `level` */
        for (int r = 0; r < 4 && np > 0; r++) {
            int level = rng_int(&rng, k), rep = r == 0 ? -1 : rng_int(&rng, np);
            for (int i = 0; i < s.n; i++) s.x[i] = cn_rng_uniform(&rng), s.wv[i] = cn_rng_uniform(&rng);
            BbEntry e = {4, -1, 0, -1, 0, 0.25, 0};
            int ntop = 0;
            CHECK(cn_bb_prefix_children(&s, &ntop, &e, 0, full, rep, level, 0.75));
            const BbEntry *st = s.tmp[TMP_STACK];
            bool want[MAXD + 1] = {false}, seen[MAXD + 1] = {false};
            int nwant = 0, member = s.jmem[level];
            for (int p = 0; p < np; p++)
                if (rep < 0 || memcmp(pats + p * k, pats + rep * k, (size_t)level) == 0)
                    nwant += !want[pats[p * k + level]], want[pats[p * k + level]] = true;
            bool ok = ntop == nwant && st;
            for (int c = 0; ok && c < ntop; c++) {
                const BbEntry *x = &st[c];
                ok &= x->depth == 5 && x->pair == 0 && x->choice == (int)full && x->group == -3 &&
                      x->level == level && x->bound == 0.75 && x->mode >= 0 && x->mode < np;
                if (!ok) break;
                const unsigned char *pat = pats + x->mode * k;
                ok &= rep < 0 || memcmp(pat, pats + rep * k, (size_t)level) == 0;
                ok &= want[pat[level]] && !seen[pat[level]];
                seen[pat[level]] = true;
                if (c > 0)
                    ok &= cn_bb_mode_far(&s, member, pat[level]) <=
                          cn_bb_mode_far(&s, member, pats[st[c - 1].mode * k + level]);
            }
            CHECK_MSG(ok, "joint trial %d: children of member %d after pattern %d: %d pushed, %d modes",
                      t, level, rep, ntop, nwant);
            cn_bb_tmp_free(&s, TMP_STACK);
            s.stack_cap = 0;
            prefixes++;
        }
    next:
        free(in_code), free(in_mine), free(hit);
        bb_close(&s);
        prob_free(&q);
    }
    printf("search joints: %ld patterns of %d faces against %ld sampled twists and %ld LPs in the "
           "plane (%d on a tie's boundary alone, %d of them sampled; %d with an inside not sampled); "
           "%d subsets, %d prefixes\n", listed, ntr, sampled, lps, thin, thin_hit, unhit, masks, prefixes);
    CHECK(prefixes == 4 * ntr);
    /* every pattern of a tie alone is one a sampled twist gives exactly (soundness by brute
       force where the LP's centre cannot tell) */
    if (!RUNNING_ON_VALGRIND) CHECK(masks > 30 && thin > 20 && thin_hit == thin);
}

/* Which contacts make joints (cn_bb_joints): friction groups of one point each between the same
 * two bodies with the same normal, 2 to 8 of them. Box A on the frame (2 points under it), box B
 * on A (3 points), a point on A's side and one on B's side (each alone on its face), two
 * contacts at one point under B (one friction group of two: not a joint member). Then a face of
 * 9 points: too many for a joint. */
static void test_joint_members(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x7a3c1e5b9d2f4861ULL};
    for (int t = 0; t < 2; t++) {
        Prob q;
        if (!prob_new(&q, 3, true, 0.1, 0.3, 4)) {
            prob_free(&q);
            return;
        }
        double up[3] = {0, 0, 1}, side[3] = {1, 0, 0};
        int want[MAXK], nwant = 0; /* the joint each contact's group should be in (-1 none) */
        if (t == 0) {
            prob_contact(&q, q.F, q.A, (double[3]){0.2, 0.1, 0}, up, 0.5, 0.1, 1, NULL), want[nwant++] = 0;
            prob_contact(&q, q.F, q.A, (double[3]){0, 0.4, 0.5}, side, 0.5, 0.1, 1, NULL), want[nwant++] = -1;
            prob_contact(&q, q.A, q.B, (double[3]){0.5, 0.2, 1}, up, 0.7, 0.2, 1, NULL), want[nwant++] = 1;
            prob_contact(&q, q.F, q.A, (double[3]){1.8, 0.9, 0}, up, 0.5, 0.3, -1, NULL), want[nwant++] = 0;
            prob_contact(&q, q.A, q.B, (double[3]){1.5, 0.2, 1}, up, 0.3, 0.4, 1, NULL), want[nwant++] = 1;
            prob_contact(&q, q.F, q.B, (double[3]){0.5, 0.5, 1.2}, side, 0.5, 0.5, 1, NULL);
            want[nwant++] = -1;
            prob_contact(&q, q.A, q.B, (double[3]){1, 0.8, 1}, up, 0.7, 0.6, 1, NULL), want[nwant++] = 1;
            /* two contacts at one point, the same rows and mu: one group of two members */
            prob_contact(&q, q.A, q.B, (double[3]){1.2, 0.5, 1}, up, 0.7, 0.7, 1, NULL), want[nwant++] = -1;
            prob_contact(&q, q.A, q.B, (double[3]){1.2, 0.5, 1}, up, 0.7, 0.7, 1, NULL), want[nwant++] = -1;
        } else {
            for (int c = 0; c < 9; c++) {
                double pt[3] = {cn_rng_range(&rng, 0, 2), cn_rng_range(&rng, 0, 1), 0};
                prob_contact(&q, q.F, q.A, pt, up, 0.5, cn_rng_range(&rng, 0, 6), 1, NULL);
                want[nwant++] = -1;
            }
        }
        prob_finish(&q, NULL);
        Bb s;
        if (!bb_open(&s, &q.p) || cn_bb_joints(&s) != 0) {
            CHECK_MSG(0, "joint members %d: the search's state not built", t);
            bb_close(&s), prob_free(&q);
            return;
        }
        CHECK_MSG(s.G == (t == 0 ? 8 : 9), "joint members %d: %d friction groups", t, s.G);
        CHECK_MSG(s.NJ == (t == 0 ? 2 : 0), "joint members %d: %d joints", t, s.NJ);
        int members = 0;
        for (int g = 0; g < s.G; g++) {
            int c = q.cof[s.grep[g]];
            CHECK_MSG(s.joint[g] == want[c], "joint members %d: contact %d in joint %d, not %d", t, c,
                      s.joint[g], want[c]);
            members += s.joint[g] >= 0;
        }
        CHECK(s.jfirst[s.NJ] == members);
        for (int J = 0; J < s.NJ; J++)
            for (int a = s.jfirst[J]; a < s.jfirst[J + 1]; a++) CHECK(s.joint[s.jmem[a]] == J);
        bb_close(&s);
        prob_free(&q);
    }
}

/* ---- learned prunes ---------------------------------------------------------------------- */

/* The search's prune test (strong.c, still_within): every body still when |a|_M <= beta, beta^2
 * the power bound obj (in W g). */
static bool prunes(const cnMech *m, double obj, double tol) {
    double beta = sqrt(fmax(obj * m->wref * m->g, 0));
    int nd = m->nd;
    for (int b = 0; b < m->nb; b++) {
        const double *Mi = m->minv + (size_t)b * nd * nd;
        double tr = 0;
        for (int k = m->dim; k < nd; k++) tr += Mi[k * nd + k];
        if (beta / sqrt(m->mass[b]) > tol * m->g || beta * sqrt(tr) * m->radius[b] > tol * m->g) return false;
    }
    return true;
}

/* A random stack: box A on the frame (2-D: 2 or 3 points on its faces; 3-D: 3 or 4 points under
 * it, sometimes one on a side), maybe box B on A (2 or 3 points), mu from 0.05 to 1.2 (mostly
 * one value), gravity within ang_max of straight down; the frame slides under A at vf when
 * asked. */
static bool random_stack(Prob *q, cnRng *rng, int dim, bool two, int D, double ang_max, bool slide) {
    if (!prob_new(q, dim, two, cn_rng_range(rng, -ang_max, ang_max), cn_rng_range(rng, 0, 2 * CN_PI), D))
        return false;
    double mu0 = cn_rng_range(rng, 0.05, 1.2);
    int na = dim == 2 ? 2 + rng_int(rng, 2) : 3 + rng_int(rng, 2);
    for (int c = 0; c < na; c++) {
        double pt[3] = {0, 0, 0}, nr[3] = {0, dim == 2, dim == 3};
        double mu = cn_rng_uniform(rng) < 0.15 ? cn_rng_range(rng, 0.05, 1.2) : mu0;
        if (c == na - 1 && cn_rng_uniform(rng) < 0.3) { /* on A's left side */
            nr[0] = 1, nr[1] = nr[2] = 0;
            pt[1] = cn_rng_range(rng, 0, 1), pt[2] = dim == 3 ? cn_rng_uniform(rng) : 0;
        } else if (dim == 2) {
            pt[0] = cn_rng_uniform(rng) < 0.6 ? 2.0 * (c % 2) : cn_rng_range(rng, 0, 2);
        } else {
            static const double cx[4] = {0, 2, 2, 0}, cy[4] = {0, 0, 1, 1};
            bool corner = cn_rng_uniform(rng) < 0.5;
            pt[0] = corner ? cx[c % 4] : cn_rng_range(rng, 0, 2);
            pt[1] = corner ? cy[c % 4] : cn_rng_range(rng, 0, 1);
        }
        prob_contact(q, q->F, q->A, pt, nr, mu, cn_rng_range(rng, 0, 2 * CN_PI), 1, NULL);
    }
    for (int c = 0; two && c < 2 + rng_int(rng, 2); c++) {
        double pt[3] = {0, 1, 1}, nr[3] = {0, dim == 2, dim == 3};
        if (dim == 2) pt[0] = c == 0 ? 0.5 : c == 1 ? 1.5 : cn_rng_range(rng, 0.5, 1.5), pt[2] = 0;
        else pt[0] = cn_rng_range(rng, 0.5, 1.5), pt[1] = cn_rng_range(rng, 0.2, 0.8);
        double mu = cn_rng_uniform(rng) < 0.5 ? mu0 : cn_rng_range(rng, 0.05, 1.2);
        prob_contact(q, q->A, q->B, pt, nr, mu, cn_rng_range(rng, 0, 2 * CN_PI), 1, NULL);
    }
    double vf[3] = {cn_rng_range(rng, -5, 5), dim == 3 ? cn_rng_range(rng, -5, 5) : 0, 0};
    prob_finish(q, slide ? vf : NULL);
    return true;
}

/* Bounds of two LPs of one problem compared: GLPK's double simplex leaves this much (its
 * feasibility tolerance 1e-7 on scaled rows), which is why the search solves bounds below 1e-9
 * again exactly. */
#define LP_NOISE 1e-8

/* The current LP's optimum in exact arithmetic (glp_exact from its basis); NAN when unsolved. */
static double exact_bound(glp_prob *P) {
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    if (glp_exact(P, &parm) != 0 || glp_get_status(P) != GLP_OPT) return NAN;
    return glp_get_obj_val(P);
}

/* The node with fixes `want`: a pair fixed the other way is freed first (cn_bb_pair_set sets one
 * side's bounds and frees both only with choice 0, as the search's path does). */
static void set_fixes(Bb *s, const unsigned char *want) {
    for (int i = 0; i < s->n; i++) {
        if (s->fix[i] == want[i]) continue;
        if (s->fix[i]) cn_bb_pair_set(s, i, 0);
        if (want[i]) cn_bb_pair_set(s, i, want[i]);
    }
}

/* The learned sets (cn_bb_learn, cn_bb_learn_infeasible, cn_bb_known) on the node LPs of random
 * stacks, at random nodes (random fixes; the contacts closed and stuck, as a static field's
 * node; or an earlier node with more fixes): a set learned at an optimal node, its fixes alone,
 * gives the node's bound again (an LP re-solved: the same optimum up to GLPK's noise; where the
 * search prunes the node, the set's exact bound prunes as the node's does); one learned at an
 * infeasible node, its fixes alone, leave the LP infeasible; and cn_bb_known holds at exactly the nodes that make every fix of some set (by
 * inclusion, here), whose LPs are then infeasible or within that set's bound. The component
 * search's LP (the frame sliding: another objective, motions boxed) in a quarter. */
static void test_learned_sets(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x3b9aca07d1e5f00dULL};
    long nodes = 0, from_bound = 0, from_infeasible = 0, known = 0, pruned = 0, failed = 0;
    double worst = 0, worst_exact = 0;
    for (int t = 0; t < SHARE(16); t++) {
        int dim = t % 3 == 0 ? 2 : 3;
        bool slide = t % 4 == 3;
        Prob q;
        if (!random_stack(&q, &rng, dim, t % 2 == 1, 3 + t % 2, 0.6, slide)) {
            prob_free(&q);
            return;
        }
        Bb s;
        unsigned char *want = NULL, *saved = NULL, *kind = NULL;
        double *bound = NULL;
        if (!bb_open(&s, &q.p)) {
            CHECK_MSG(0, "learn trial %d: the search's state not built", t);
            goto next;
        }
        if (!s.energy) glp_set_obj_coef(s.P, 1 + rng_int(&rng, s.nv), cn_rng_uniform(&rng) < 0.5 ? 1 : -1);
        int n = s.n, K = q.K, nsaved = 0, nodes_here = 140;
        want = malloc((size_t)n), saved = malloc((size_t)n * 16);
        kind = malloc((size_t)nodes_here + 1), bound = malloc(sizeof(double) * (size_t)(nodes_here + 1));
        if (!want || !saved || !kind || !bound) goto next;
        for (int node = 0; node < nodes_here; node++) {
            if (node % 10 == 0) cn_bb_learn_reset(&s); /* a search's sets: fewer nodes known */
            double r = cn_rng_uniform(&rng), density = cn_rng_range(&rng, 0.05, 0.5);
            if (r < 0.25 && nsaved > 0) { /* an earlier node, more fixed */
                memcpy(want, saved + (size_t)rng_int(&rng, nsaved) * n, (size_t)n);
                for (int extra = 1 + rng_int(&rng, 3); extra > 0; extra--) {
                    int i = rng_int(&rng, n);
                    if (!want[i]) want[i] = (unsigned char)(1 + rng_int(&rng, 2));
                }
            } else if (r < 0.7) { /* contacts closed and stuck, a few pairs otherwise */
                for (int i = 0; i < n; i++) {
                    want[i] = i < K ? 2 : i >= s.nrows ? 1 : 0;
                    if (cn_rng_uniform(&rng) < 0.2) want[i] = (unsigned char)rng_int(&rng, 3);
                }
            } else {
                for (int i = 0; i < n; i++) {
                    double u = cn_rng_uniform(&rng);
                    want[i] = u < density / 2 ? 1 : u < density ? 2 : 0;
                }
            }
            set_fixes(&s, want);
            int lp = cn_bb_node_lp(&s);
            if (lp < 0) {
                failed++;
                continue;
            }
            double obj = lp == 1 ? glp_get_obj_val(s.P) : -INFINITY;
            nodes++;
            /* the sets this node makes, found here by inclusion */
            bool incl = false;
            for (int c = 0; c < s.ng_count; c++) {
                int j = c > 0 ? s.ng_end[c - 1] : 0, e = s.ng_end[c];
                bool sub = true;
                for (; j < e && sub; j++) sub = s.fix[s.ng[j] >> 1] == (s.ng[j] & 1) + 1;
                if (!sub) continue;
                incl = true;
                if (kind[c]) {
                    CHECK_MSG(lp == 0, "learn trial %d, node %d: a set learned infeasible, yet the LP "
                              "is feasible (bound %g)", t, node, obj);
                } else {
                    CHECK_MSG(lp == 0 || obj <= bound[c] + LP_NOISE * (1 + fabs(bound[c])),
                              "learn trial %d, node %d: bound %.17g beyond the %.17g of a set it makes",
                              t, node, obj, bound[c]);
                }
            }
            CHECK_MSG(cn_bb_known(&s) == incl, "learn trial %d, node %d: known %d, by inclusion %d", t,
                      node, (int)cn_bb_known(&s), (int)incl);
            known += incl;
            if (incl) continue; /* the search never solves it */
            int c0 = s.ng_count;
            if (lp == 0) cn_bb_learn_infeasible(&s);
            else cn_bb_learn(&s);
            if (s.ng_count == c0) continue;
            CHECK(s.ng_count == c0 + 1);
            int j0 = c0 > 0 ? s.ng_end[c0 - 1] : 0, j1 = s.ng_end[c0];
            bool sub = true;
            memset(want, 0, (size_t)n); /* fix0: nothing fixed before the search */
            for (int j = j0; j < j1; j++) {
                int i = s.ng[j] >> 1, ch = (s.ng[j] & 1) + 1;
                sub &= s.fix[i] == ch;
                want[i] = (unsigned char)ch;
            }
            CHECK_MSG(sub && cn_bb_known(&s), "learn trial %d, node %d: a set learned of fixes the node "
                      "does not make", t, node);
            kind[c0] = lp == 0, bound[c0] = obj;
            /* a node the search prunes: its bound again in exact arithmetic */
            bool prune = lp == 1 && s.energy && prunes(&q.m, obj, q.p.motion_tol);
            double exact_node = prune ? exact_bound(s.P) : NAN;
            if (nsaved < 16) memcpy(saved + (size_t)nsaved++ * n, s.fix, (size_t)n);
            else memcpy(saved + (size_t)rng_int(&rng, 16) * n, s.fix, (size_t)n);
            /* the set's fixes alone */
            set_fixes(&s, want);
            int lp2 = cn_bb_lp(&s);
            if (lp == 0) {
                from_infeasible++;
                CHECK_MSG(lp2 == 0, "learn trial %d, node %d: the %d fixes learned from an infeasible node "
                          "leave a feasible LP (%d)", t, node, j1 - j0, lp2);
            } else {
                from_bound++;
                double obj2 = lp2 == 1 ? glp_get_obj_val(s.P) : INFINITY;
                worst = fmax(worst, obj2 - obj);
                CHECK_MSG(lp2 == 1 && obj2 <= obj + LP_NOISE * (1 + fabs(obj)), "learn trial %d, node %d: "
                          "the %d fixes learned give the bound %.17g, the node %.17g", t, node, j1 - j0,
                          obj2, obj);
                if (!isnan(exact_node) && prunes(&q.m, exact_node, q.p.motion_tol)) {
                    /* pruned in exact arithmetic: so must every node that makes the set be */
                    double exact_set = exact_bound(s.P);
                    pruned++;
                    worst_exact = fmax(worst_exact, exact_set - exact_node);
                    CHECK_MSG(prunes(&q.m, exact_set, q.p.motion_tol), "learn trial %d, node %d: pruned with "
                              "the exact bound %g, its learned set's %g does not prune", t, node,
                              exact_node, exact_set);
                }
            }
        }
    next:
        free(want), free(saved), free(kind), free(bound);
        bb_close(&s);
        prob_free(&q);
    }
    printf("search learned sets: %ld node LPs, %ld sets from bounds (%ld pruning exactly), %ld from "
           "infeasible LPs, %ld nodes known; the bound of a set above its node's by %.3g at most (%.3g "
           "exactly); %ld LPs failed\n",
           nodes, from_bound, pruned, from_infeasible, known, worst, worst_exact, failed);
    CHECK(failed < nodes / 20);
    if (!RUNNING_ON_VALGRIND) CHECK(from_bound > 200 && pruned > 15 && from_infeasible > 100 && known > 100);
}

/* A motion the search found, checked by cn_motion_verify with sliding speeds worked out here
 * (lambda = max(0, max_d -(d.a + nominal)): the least any solution with this motion needs), and
 * without nominal sliding Gauss's inequality a^T M a <= fext.a. */
static bool found_holds(const cnMotionProblem *p, const double *force, const double *acc) {
    const cnMech *m = p->m;
    int K = p->K, D = p->D;
    double lambda[MAXK], a2[12];
    for (int f = 0; f < p->Kf; f++) {
        lambda[f] = 0;
        for (int d = 0; d < D; d++) {
            double v = cn_mech_relative(m, &p->rows[K + f * D + d], acc);
            if (p->nominal) v += p->nominal[f * D + d];
            lambda[f] = fmax(lambda[f], -v);
        }
    }
    bool ok = cn_motion_verify(p, force, lambda, a2) == 1;
    if (!p->nominal) {
        double power = 0, kin = cn_mech_kinetic(m, acc, NULL);
        for (int i = 0; i < m->nb * m->nd; i++) power += m->fext[i] * acc[i];
        ok &= kin <= power * (1 + 1e-6) + 1e-9 * m->wref * m->g;
    }
    return ok;
}

/* The whole search with its learned prunes and without them (no_learning), on random stacks of
 * one or two boxes in 2-D and 3-D, a fifth with the frame sliding under A: the same verdict, and
 * every motion found holds (found_holds). */
static void test_learning_same_verdict(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x6c8e9cf570932bd5ULL};
    int ntr = SHARE(40), agree = 0, found = 0, none = 0, learned = 0, undecided = 0;
    long lps_with = 0, lps_without = 0;
    for (int t = 0; t < ntr; t++) {
        int dim = t % 3 == 0 ? 2 : 3;
        Prob q;
        if (!random_stack(&q, &rng, dim, t % 2 == 0, 3 + t % 2, 0.8, t % 5 == 4)) {
            prob_free(&q);
            return;
        }
        cnMotionAnswer ans[2];
        cnStatus st[2];
        cnMotionStats stats[2];
        double force[2][MAXK * (1 + MAXD)], acc[2][12];
        cnDiag d;
        for (int run = 0; run < 2; run++) {
            q.p.no_learning = run == 1;
            memset(&stats[run], 0, sizeof stats[run]);
            st[run] = cn_motion_search(&q.p, &ans[run], force[run], acc[run], &stats[run], &d);
            CHECK_MSG(st[run] == CN_OK, "same verdict trial %d: status %d: %s", t, (int)st[run], d.message);
            if (st[run] == CN_OK && ans[run] == CN_MOTION_FOUND)
                CHECK_MSG(found_holds(&q.p, force[run], acc[run]), "same verdict trial %d (learning %s): "
                          "the motion found does not hold", t, run ? "off" : "on");
        }
        q.p.no_learning = false;
        lps_with += stats[0].nodes, lps_without += stats[1].nodes;
        learned += stats[0].learned > 0;
        if (ans[0] == CN_MOTION_UNDECIDED || ans[1] == CN_MOTION_UNDECIDED) {
            undecided++;
        } else {
            CHECK_MSG(ans[0] == ans[1], "same verdict trial %d (%d-D, %d contacts): with learned prunes %d, "
                      "without %d", t, dim, q.K, (int)ans[0], (int)ans[1]);
            agree += ans[0] == ans[1];
            found += ans[0] == CN_MOTION_FOUND, none += ans[0] == CN_MOTION_NONE;
        }
        CHECK_MSG(stats[1].learned == 0, "same verdict trial %d: learned prunes without learning", t);
        prob_free(&q);
    }
    printf("search learning: the same verdict in %d of %d stacks (%d move, %d still, %d undecided); "
           "learned prunes in %d; %ld LPs with them, %ld without\n",
           agree, ntr, found, none, undecided, learned, lps_with, lps_without);
    CHECK(undecided <= ntr / 10);
    if (!RUNNING_ON_VALGRIND) CHECK(found > ntr / 8 && none > ntr / 8 && learned > ntr / 8);
}

/* Normal-force floors (search_lp.c) against the search without them: on random 2-D stacks of
 * one or two boxes (gravity within 52 degrees of straight down, so that some slide) the same
 * verdict with the floors from the start (floors 1) as without (floors -1), every motion found
 * a solution of the LCP (found_holds), and the floors in use (a positive floor) in some; a
 * floor too large would prune a sliding motion that the search without them finds. */
static void test_floors_same_verdict(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x2f4b9d3c1e8a7765ULL};
    int ntr = SHARE(80), agree = 0, found = 0, none = 0, undecided = 0, floored = 0;
    long lps[2] = {0, 0};
    for (int t = 0; t < ntr; t++) {
        Prob q;
        if (!random_stack(&q, &rng, 2, t % 2 == 0, 2, 0.9, false)) {
            prob_free(&q);
            return;
        }
        cnMotionAnswer ans[2];
        double force[2][MAXK * (1 + MAXD)], acc[2][12];
        for (int run = 0; run < 2; run++) {
            cnMotionStats stats;
            cnDiag d;
            memset(&stats, 0, sizeof stats);
            q.p.floors = run == 0 ? -1 : 1;
            cnStatus st = cn_motion_search(&q.p, &ans[run], force[run], acc[run], &stats, &d);
            CHECK_MSG(st == CN_OK, "floors trial %d: status %d: %s", t, (int)st, d.message);
            lps[run] += stats.nodes;
            floored += run == 1 && stats.floors > 0;
            CHECK_MSG(run == 1 || stats.floors == 0, "floors trial %d: floors without floors", t);
            if (st == CN_OK && ans[run] == CN_MOTION_FOUND)
                CHECK_MSG(found_holds(&q.p, force[run], acc[run]), "floors trial %d (floors %s): the "
                          "motion found does not hold", t, run ? "on" : "off");
        }
        q.p.floors = 0;
        if (ans[0] == CN_MOTION_UNDECIDED || ans[1] == CN_MOTION_UNDECIDED) {
            undecided++;
        } else {
            CHECK_MSG(ans[0] == ans[1], "floors trial %d (%d contacts): without floors %d, with %d", t,
                      q.K, (int)ans[0], (int)ans[1]);
            agree += ans[0] == ans[1];
            found += ans[0] == CN_MOTION_FOUND, none += ans[0] == CN_MOTION_NONE;
        }
        prob_free(&q);
    }
    printf("search floors: the same verdict in %d of %d 2-D stacks (%d move, %d still, %d undecided), "
           "a positive floor in %d; %ld LPs without floors, %ld with\n", agree, ntr, found, none,
           undecided, floored, lps[0], lps[1]);
    CHECK(undecided == 0);
    CHECK(floored > ntr / 8);
    CHECK(found > ntr / 8 && none > ntr / 8);
}

/* ---- warm-started LCP solves ------------------------------------------------------------- */

/* The made-up LCPs: WK contacts, each with WD friction rows and a sliding speed (n = WK (2 +
 * WD)), M = I + 0.2 B B^T / n (positive definite, diagonally dominant: a unique solution whose
 * basis follows the signs of q). */
#define WK 3
#define WD 2
#define WN (WK * (2 + WD))

static void warm_contacts(cnContact *items, int base) {
    memset(items, 0, sizeof(cnContact) * WK);
    for (int c = 0; c < WK; c++) {
        items[c].id = c + 1;
        items[c].body1 = base + c, items[c].body2 = base + 50 + c;
        items[c].fixel = -1, items[c].vertex = c + 1;
    }
}

static bool warm_lcp(cnLcp *L, cnRng *rng) {
    if (cn_lcp_alloc(L, WN) != CN_OK) return false;
    double B[WN * WN];
    for (int i = 0; i < WN * WN; i++) B[i] = cn_rng_range(rng, -1, 1);
    for (int i = 0; i < WN; i++)
        for (int j = 0; j < WN; j++) {
            double v = i == j;
            for (int k = 0; k < WN; k++) v += 0.2 * B[i * WN + k] * B[j * WN + k] / WN;
            L->M[i * WN + j] = v;
        }
    for (int i = 0; i < WN; i++) L->q[i] = cn_rng_range(rng, -1, 1);
    return true;
}

/* Rows of contact c (its normal, friction rows and sliding speed), with fric_of[c] = c. */
static void contact_rows(int c, int *rows) {
    rows[0] = c;
    for (int d = 0; d < WD; d++) rows[1 + d] = WK + c * WD + d;
    rows[1 + WD] = WK + WK * WD + c;
}

/* The largest violation of z's complementarity with w = M z + q. */
static double lcp_violation(const cnLcp *L, const double *z) {
    double worst = 0;
    for (int i = 0; i < L->n; i++) {
        double w = L->q[i];
        for (int j = 0; j < L->n; j++) w += L->M[i * L->n + j] * z[j];
        worst = fmax(worst, fmax(fmax(-z[i], -w), fabs(fmin(z[i], w))));
    }
    return worst;
}

typedef struct {
    cnWarmStart *ws;
    long calls, warm, pivots;
} Warm;

/* One solve through the cache; true when it was warm. The solution must be Lemke's (the unique
 * one) and complementary. */
static bool warm_solve(Warm *W, const cnContact *items, const cnLcp *L, const char *what) {
    int fric_of[WK] = {0, 1, 2};
    cnContactSet cs = {WK, WK, (cnContact *)items};
    cnLcpOptions o = cn_lcp_options_default();
    double z[WN], w[WN], zc[WN], wc[WN];
    cnLcpInfo info, ic;
    cnForcesFrom used = CN_FORCES_NONE;
    cnLcpStatus st = cn_ck_warm_solve(W->ws, &cs, fric_of, WK, WD, L, CN_SOLVER_AUTO, true, &o, z,
                                      w, &info, &used);
    W->calls++, W->warm += info.warm, W->pivots += info.pivots;
    bool cold = cn_lcp_lemke(L, &o, zc, wc, &ic) == CN_LCP_SOLVED;
    double diff = 0;
    for (int i = 0; i < WN; i++) diff = fmax(diff, fabs(z[i] - zc[i]));
    CHECK_MSG(st == CN_LCP_SOLVED && cold && diff <= 1e-9 && lcp_violation(L, z) <= 1e-9,
              "warm solve (%s): status %d, %g from Lemke's solution", what, (int)st, diff);
    CHECK_MSG(!info.warm || info.pivots == 0, "warm solve (%s): warm after %d pivots", what, info.pivots);
    return info.warm;
}

static void basis_of(const cnLcp *L, unsigned char *basic) {
    double z[WN], w[WN];
    cnLcpInfo info;
    cnLcpOptions o = cn_lcp_options_default();
    cn_lcp_lemke(L, &o, z, w, &info);
    cn_lcp_basis_of(WN, z, w, basic);
}

/* The cache of bases (cn_ck_warm_solve) on made-up LCPs of 3 contacts: every solve gives the
 * cold solution (Lemke's), and is warm exactly when the cache's documented behaviour says so:
 * the first solve cold; the same LCP again, or with q moved slightly, warm; a changed basis
 * cold, the earlier basis of the same contacts found again (two tries); the contacts permuted
 * (the LCP with them), or one replaced by a contact that does not push, warm through the
 * basis carried over by the rows' identities; after four other contact sets the first one's
 * bases forgotten (CN_WARM_SLOTS); with record_only never warm; the counters add up. */
static void test_warm_solves(void) {
    cnRng rng = {0x0ddba11cafef00dULL};
    Warm W;
    memset(&W, 0, sizeof W);
    W.ws = cn_warm_start_new(false);
    cnContact s1[WK], s2[WK], s3[WK];
    cnLcp L1 = {0}, L4 = {0}, L5 = {0}, L6 = {0}, U = {0};
    warm_contacts(s1, 10);
    if (!W.ws || !warm_lcp(&L1, &rng) || cn_lcp_alloc(&L4, WN) != CN_OK || cn_lcp_alloc(&L5, WN) != CN_OK ||
        cn_lcp_alloc(&L6, WN) != CN_OK) {
        CHECK_MSG(0, "warm: out of memory");
        goto done;
    }
    /* contact 2 does not push: its rows' q large */
    int r2[2 + WD];
    contact_rows(2, r2);
    for (int a = 0; a < 2 + WD; a++) L1.q[r2[a]] = 5;
    CHECK(!warm_solve(&W, s1, &L1, "first"));
    CHECK(warm_solve(&W, s1, &L1, "the same again"));
    for (int i = 0; i < WN; i++) L1.q[i] += 1e-6 * cn_rng_range(&rng, -1, 1);
    CHECK(warm_solve(&W, s1, &L1, "q moved slightly"));
    /* L4: a pushing row of contact 0 or 1 lets go: another basis */
    memcpy(L4.M, L1.M, sizeof(double) * WN * WN), memcpy(L4.q, L1.q, sizeof(double) * WN);
    unsigned char b1[WN], b4[WN];
    basis_of(&L1, b1);
    int flip = -1;
    for (int i = 0; i < WN && flip < 0; i++)
        if (b1[i]) flip = i;
    CHECK(flip >= 0 && flip != r2[0]);
    if (flip >= 0) L4.q[flip] = 5;
    basis_of(&L4, b4);
    CHECK(memcmp(b1, b4, WN) != 0);
    CHECK(!warm_solve(&W, s1, &L4, "another basis"));
    CHECK(warm_solve(&W, s1, &L1, "back to the first basis"));
    CHECK(warm_solve(&W, s1, &L4, "and to the second"));
    /* L5: L4 with its contacts in the order 1, 2, 0 (items and rows): carried over by identity */
    int perm[WK] = {1, 2, 0}, map[WN];
    for (int c = 0; c < WK; c++) {
        int from[2 + WD], to[2 + WD];
        contact_rows(perm[c], from), contact_rows(c, to);
        for (int a = 0; a < 2 + WD; a++) map[to[a]] = from[a];
        s2[c] = s1[perm[c]];
    }
    for (int i = 0; i < WN; i++) {
        L5.q[i] = L4.q[map[i]];
        for (int j = 0; j < WN; j++) L5.M[i * WN + j] = L4.M[map[i] * WN + map[j]];
    }
    bool moves = false; /* by position the basis would be wrong */
    for (int i = 0; i < WN; i++) moves |= b4[i] != b4[map[i]];
    CHECK(moves);
    CHECK(warm_solve(&W, s2, &L5, "contacts permuted"));
    /* L6: L5 with s1's contact 2 (now 1) replaced by a new contact that does not push */
    memcpy(s3, s2, sizeof s3);
    s3[1].vertex = 99;
    memcpy(L6.M, L5.M, sizeof(double) * WN * WN), memcpy(L6.q, L5.q, sizeof(double) * WN);
    int rn[2 + WD];
    contact_rows(1, rn);
    unsigned char b5[WN];
    basis_of(&L5, b5);
    for (int a = 0; a < 2 + WD; a++) {
        int r = rn[a];
        CHECK(!b5[r]); /* s1's contact 2 (its q large): it pushed nowhere before either */
        for (int j = 0; j < WN; j++) L6.M[r * WN + j] = L6.M[j * WN + r] = j == r;
        L6.q[r] = 1;
    }
    CHECK(warm_solve(&W, s3, &L6, "a contact replaced"));
    /* four other contact sets: the first one's bases forgotten */
    for (int u = 0; u < CN_WARM_SLOTS; u++) {
        cnContact su[WK];
        warm_contacts(su, 1000 + 10 * u);
        if (!warm_lcp(&U, &rng)) break;
        CHECK(!warm_solve(&W, su, &U, "another contact set"));
        cn_lcp_free(&U);
    }
    CHECK(!warm_solve(&W, s1, &L1, "forgotten"));
    CHECK(warm_solve(&W, s1, &L1, "remembered again"));
    cnWarmStats ws = cn_warm_start_stats(W.ws);
    CHECK(ws.solves == W.calls && ws.warm_solves == W.warm && ws.pivots == W.pivots);
    CHECK(ws.warm_seconds <= ws.seconds && ws.seconds >= 0);
    /* record_only: counted, never warm */
    Warm R;
    memset(&R, 0, sizeof R);
    R.ws = cn_warm_start_new(true);
    CHECK(R.ws != NULL);
    if (!R.ws) goto done;
    CHECK(!warm_solve(&R, s1, &L1, "record only"));
    CHECK(!warm_solve(&R, s1, &L1, "record only, again"));
    ws = cn_warm_start_stats(R.ws);
    CHECK(ws.solves == 2 && ws.warm_solves == 0);
    cn_warm_start_free(R.ws);
done:
    cn_warm_start_free(W.ws);
    cn_lcp_free(&L1), cn_lcp_free(&L4), cn_lcp_free(&L5), cn_lcp_free(&L6), cn_lcp_free(&U);
}

/* A node's basis put back (cn_bb_basis_put after cn_bb_basis_get) is optimal again at once,
 * after the LP went elsewhere: on random stacks, a node with random fixes solved, its basis
 * kept, two other nodes solved, the first node's fixes and basis restored: the same optimum in
 * no simplex pivot (an infeasible node: infeasible again). */
static void test_basis_round_trip(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x5eed0fba515ULL};
    int tried = 0, optimal = 0, zero = 0;
    for (int t = 0; t < SHARE(12); t++) {
        Prob q;
        if (!random_stack(&q, &rng, t % 3 == 0 ? 2 : 3, t % 2 == 1, 3 + t % 2, 0.6, false)) {
            prob_free(&q);
            return;
        }
        Bb s;
        unsigned char *want = NULL, *basis = NULL;
        if (!bb_open(&s, &q.p)) {
            CHECK_MSG(0, "basis trial %d: the search's state not built", t);
            goto next;
        }
        int n = s.n;
        want = malloc((size_t)n * 3);
        basis = malloc((size_t)(glp_get_num_rows(s.P) + glp_get_num_cols(s.P)));
        if (!want || !basis) goto next;
        for (int k = 0; k < 3 * n; k++) {
            double u = cn_rng_uniform(&rng);
            want[k] = u < 0.15 ? 1 : u < 0.3 ? 2 : 0;
        }
        set_fixes(&s, want);
        int lp0 = cn_bb_lp(&s);
        if (lp0 < 0) goto next;
        double obj0 = lp0 == 1 ? glp_get_obj_val(s.P) : 0;
        cn_bb_basis_get(&s, basis);
        for (int other = 1; other <= 2; other++) {
            set_fixes(&s, want + (size_t)other * n);
            (void)cn_bb_lp(&s);
        }
        set_fixes(&s, want);
        cn_bb_basis_put(&s, basis, glp_get_num_rows(s.P));
        int it = glp_get_it_cnt(s.P), lp1 = cn_bb_lp(&s);
        tried++;
        CHECK_MSG(lp1 == lp0, "basis trial %d: LP status %d, then %d", t, lp0, lp1);
        if (lp0 == 1 && lp1 == 1)
            CHECK_MSG(fabs(glp_get_obj_val(s.P) - obj0) <= 1e-9 * (1 + fabs(obj0)),
                      "basis trial %d: optimum %.17g, then %.17g", t, obj0, glp_get_obj_val(s.P));
        if (lp0 == 1) optimal++, zero += glp_get_it_cnt(s.P) == it;
    next:
        free(want), free(basis);
        bb_close(&s);
        prob_free(&q);
    }
    CHECK_MSG(tried >= SHARE(12) / 2 && optimal >= tried / 2 && zero == optimal,
              "basis: %d of %d restored optimal nodes took pivots (%d tried)", optimal - zero, optimal, tried);
    printf("search basis: %d nodes restored, %d optimal again in no pivot\n", tried, zero);
}

/* search_line.c: the inner points of a 2-D joint are left out exactly. Random 2-D stacks (gravity
 * turned up to 0.8 rad, two coefficients): A on the frame along y = 0 at x = 0 and 2, B on A along
 * y = 1 at x = 0.5 and 1.5; and the same with one more point inside each line. cn_line_inner finds
 * those two and only those, their lines' ends as their ends; the two searches give the same answer
 * in the same LPs (what is left of the second is the first); and a motion found with the inner
 * points holds for the whole problem, inner points included (found_holds). */
static void test_line_inner(void) {
    glp_term_hook(quiet, NULL);
    cnRng rng = {0x2b7e151628aed2a6ULL};
    int ntr = SHARE(60), agree = 0, found = 0, none = 0;
    for (int t = 0; t < ntr; t++) {
        double ang = cn_rng_range(&rng, -0.8, 0.8), mu1 = cn_rng_range(&rng, 0.05, 1.2);
        double mu2 = cn_rng_range(&rng, 0.05, 1.2), x1 = cn_rng_range(&rng, 0.1, 1.9);
        double x2 = cn_rng_range(&rng, 0.6, 1.4);
        Prob q[2];
        bool ok = true;
        for (int k = 0; k < 2; k++) {
            ok = ok && prob_new(&q[k], 2, true, ang, 0, 2);
            if (!ok) break;
            double nr[3] = {0, 1, 0}, pts[3][3] = {{0, 0, 0}, {2, 0, 0}, {x1, 0, 0}};
            double ptb[3][3] = {{0.5, 1, 0}, {1.5, 1, 0}, {x2, 1, 0}};
            for (int i = 0; i < 2; i++) prob_contact(&q[k], q[k].F, q[k].A, pts[i], nr, mu1, 0, 1, NULL);
            for (int i = 0; i < 2; i++) prob_contact(&q[k], q[k].A, q[k].B, ptb[i], nr, mu2, 0, 1, NULL);
            if (k == 1) {
                prob_contact(&q[k], q[k].F, q[k].A, pts[2], nr, mu1, 0, 1, NULL);
                prob_contact(&q[k], q[k].A, q[k].B, ptb[2], nr, mu2, 0, 1, NULL);
            }
            prob_finish(&q[k], NULL);
        }
        if (!ok) {
            prob_free(&q[0]), prob_free(&q[1]);
            return;
        }
        int end[2][MAXK];
        CHECK_MSG(cn_line_inner(&q[0].p, end[0], end[1]) == 0, "line trial %d: inner points among the ends", t);
        CHECK_MSG(cn_line_inner(&q[1].p, end[0], end[1]) == 2, "line trial %d: not two inner points", t);
        for (int c = 0; c < 6; c++) {
            int lo = c < 4 ? -1 : c == 4 ? 0 : 2, hi = c < 4 ? -1 : lo + 1;
            CHECK_MSG(fmin(end[0][c], end[1][c]) == lo && fmax(end[0][c], end[1][c]) == hi,
                      "line trial %d: contact %d's ends %d and %d", t, c, end[0][c], end[1][c]);
        }
        /* a field moved from the inner points to the ends gives each body the same wrench */
        double field[MAXK * (1 + MAXD)], wr[2][12];
        int nr = q[1].K * (1 + q[1].D);
        for (int r = 0; r < nr; r++) field[r] = cn_rng_range(&rng, 0, 10);
        q[1].p.field = field;
        int keep[4] = {0, 1, 2, 3}, sub[3] = {0, 1, 2};
        cnSub g;
        if (cn_sub_make(&q[1].p, sub, NULL, 0, keep, 4, NULL, &g) == 0) {
            cn_line_field(&q[1].p, end[0], end[1], &g);
            for (int k = 0; k < 2; k++) {
                const cnJRow *rows = k ? g.rows : q[1].rows;
                const double *fv = k ? g.field : field;
                int n = k ? g.p.K * (1 + g.p.D) : nr;
                memset(wr[k], 0, sizeof wr[k]);
                for (int r = 0; r < n; r++)
                    for (int x = 0; x < 2; x++)
                        for (int j = 0; rows[r].body[x] >= 0 && j < 3; j++)
                            wr[k][rows[r].body[x] * 3 + j] += fv[r] * rows[r].c[x][j];
            }
            for (int j = 0; j < q[1].m.nb * 3; j++)
                CHECK_MSG(fabs(wr[0][j] - wr[1][j]) <= 1e-9 * (1 + fabs(wr[0][j])),
                          "line trial %d: the field's wrench %d: %g whole, %g at the ends", t, j, wr[0][j], wr[1][j]);
        } else {
            CHECK_MSG(0, "line trial %d: out of memory", t);
        }
        cn_sub_free(&g);
        q[1].p.field = NULL;
        cnMotionAnswer ans[2];
        cnMotionStats stats[2];
        double force[2][MAXK * (1 + MAXD)], acc[2][12];
        cnDiag d;
        for (int k = 0; k < 2; k++) {
            memset(&stats[k], 0, sizeof stats[k]);
            CHECK_MSG(cn_motion_search(&q[k].p, &ans[k], force[k], acc[k], &stats[k], &d) == CN_OK,
                      "line trial %d: %s", t, d.message);
        }
        CHECK_MSG(ans[0] == ans[1] && stats[0].nodes == stats[1].nodes,
                  "line trial %d: answer %d in %ld LPs, with inner points %d in %ld", t, (int)ans[0],
                  stats[0].nodes, (int)ans[1], stats[1].nodes);
        if (ans[1] == CN_MOTION_FOUND)
            CHECK_MSG(found_holds(&q[1].p, force[1], acc[1]), "line trial %d: the motion does not hold", t);
        agree += ans[0] == ans[1] && stats[0].nodes == stats[1].nodes;
        found += ans[1] == CN_MOTION_FOUND, none += ans[1] == CN_MOTION_NONE;
        prob_free(&q[0]), prob_free(&q[1]);
    }
    CHECK(found > 0 && none > 0);
    printf("search line: with inner points and without, the same answer and LPs in %d of %d stacks "
           "(%d move, %d do not)\n", agree, ntr, found, none);
}

void test_search(void) {
    test_line_inner();
    test_sliding_modes();
    test_joint_members();
    test_joint_patterns();
    test_learned_sets();
    test_basis_round_trip();
    test_learning_same_verdict();
    test_floors_same_verdict();
    test_warm_solves();
}
