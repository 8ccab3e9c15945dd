/* The stability verdict of an assembly at one instant: at rest (cairn check) or with parts
 * moving (a step of a motion path, paper sec. III-B, Algorithm 1).
 *
 * Frictionless (paper sec. III-A, eq. 1; Baraff 1994): a = A F + b with A = J M^-1 J^T,
 * b = J M^-1 f_ext, 0 <= F _|_ a >= 0. Held parts are kinematic (quasi-static motion: at the
 * acceleration level they act as fixed bodies); a pushed part's inverse mass loses its direction
 * of motion. The body accelerations M^-1 (f_ext + J^T F) are the same for every solution (Gauss'
 * principle), so the LCP decides: stable iff they vanish. An LP (equilibrium with F >= 0) must
 * agree; it is run as a cross-check.
 *
 * Friction (eq. 5, Stewart & Trinkle 1996): the impulse-velocity LCP over one step dt, with the
 * parts' nominal velocities (moving parts translate at the gripper's velocity) and a D-direction
 * friction pyramid. Stable means every dynamic part keeps its nominal velocity. The LCP can have
 * several solutions, so whether such a solution exists is decided exactly by an LP: equilibrium
 * of every dynamic part, p_n >= 0, kinetic friction mu p_n against the nominal sliding at sliding
 * contacts, the friction pyramid at sticking ones, no force at contacts that open by the nominal
 * motion. The LCP gives the motion when there is no such solution. Every LCP solution, and every
 * LP solution, is verified. */
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>

#include "mech.h"
#include "solve.h"
#include "proof_memo.h"
#include "strong.h"

/* Equilibrium residual accepted for an LP solution, relative to the reference weight. */
#define CN_LP_EQ_TOL 1e-7
/* The frictionless LP sought only for its field (before the friction LP) is taken to have none
 * when the duals of cairn's interior point show that a field would need normal forces summing
 * to more than this many weights a body (field_cost_bound). */
#define CN_LP_FIELD_ABSENT 1e4
/* b.y (scaled: weights) below which field_cost_bound bounds nothing */
#define CN_LP_FIELD_BY_MIN 1e-9
/* ... and when the forces it converged to are farther than this (relative residual) from a field */
#define CN_LP_FIELD_FAR 1e-4
/* Nominal relative velocities below this fraction of (|v| + |w| L + g dt) count as zero (a
 * contact neither slides nor opens by the nominal motion): v the moved parts' velocity at the
 * contact, w their turning rate, L the assembly's size. Nominal motions are exact, so this only
 * absorbs rounding, which near a turn's axis is that of the positions (|w| L) whatever the
 * velocity there. */
#define CN_NOMINAL_TOL 1e-9
/* Above this size the automatic choice skips principal pivoting, whose every step refactorises
 * the clamped block (O(|C|^3)), and goes to Lemke (O(n^2) per pivot). */
#define CN_PIVOT_MAX_AUTO 200
/* LCPs larger than this are not solved when the LP (run first) finds a static solution: with
 * friction, and frictionless. Frictionless the LP is a sparse simplex and the dense LCP costs
 * O(n^2) per pivot: measured on frictionless running-bond walls, each state a check and a
 * simulated lift, planning 64 bricks took 1.6 s with 600 and 0.40 s with 100, 100 bricks 6.0 to
 * 9.1 s with 600 and 1.3 s with 100 (0.9 to 1.4 s from 50 down to 0); below about 100 the
 * dense solvers keep their warm starts along paths. */
#define CN_LCP_LP_FIRST 600
#define CN_LCP_LP_FIRST_FRICTIONLESS 100
/* Memory for the dense LCP and Lemke's basis inverse (16 n^2 bytes) at most: beyond, cairn says
 * so rather than exhaust the machine. */
#define CN_DENSE_LCP_MAX_BYTES ((double)(1u << 30))
/* Frictionless LCPs of this many contacts or more go to the sparse QP first (motion_qp.c), the
 * dense pivoting after it when its answer does not verify. Measured on 2-D arches (unstable,
 * frictionless): 300 voussoirs (n = 602) 0.12 s against Lemke's 0.29 s, 1,000 voussoirs 0.28 s
 * against 20 s; a 10 x 10 barrel vault (n = 1,124) 0.42 s against 1.98 s; below, both take
 * hundredths of a second and the dense pivoting keeps its warm starts along paths. */
#define CN_QP_FIRST 500
/* A frictionless LCP solution whose largest contact force exceeds this many reference weights
 * squeezes a part between parts that cannot give way (a held part pressing it onto the table):
 * the forces are not unique there, and rounding in 1e11-weight forces tilts them into a false
 * motion. Such a motion is decided again by the equilibrium LP, an exact second formulation
 * (frictionless accelerations are unique, so a static solution means no motion). */
#define CN_SQUEEZE_WEIGHTS 1e4

cnCheckOptions cn_check_options_default(void) {
    cnCheckOptions o;
    memset(&o, 0, sizeof o);
    o.solver = CN_SOLVER_AUTO;
    o.lp_crosscheck = true;
    o.motion_tol = CN_DEFAULT_MOTION_TOL;
    o.lcp = cn_lcp_options_default();
    o.query = NULL;
    o.motion = NULL;
    return o;
}

void cn_check_result_free(cnCheckResult *r) {
    if (!r) return;
    cn_contacts_free(&r->contacts);
    cn_lcp_free(&r->lcp);
    cn_free(r->contact);
    cn_free(r->part);
    cn_free(r->moving);
    memset(r, 0, sizeof *r);
}

/* Friction directions at a contact: 2-D: +t, -t. 3-D: D directions evenly spaced, the first
 * along `prefer` (the sliding direction at a sliding contact, else gravity projected on the
 * tangent plane) when it has a tangential part, so that an incline, and kinetic friction
 * against a sliding motion, are resolved exactly by the pyramid. */
static void friction_dirs(const cnAssembly *a, const double n[3], const double prefer[3], int D,
                          double (*dirs)[3]) {
    if (a->dim == 2) {
        double t[3] = {-n[1], n[0], 0};
        cn_copy3(dirs[0], t);
        for (int k = 0; k < 3; k++) dirs[1][k] = -t[k];
        return;
    }
    double t1[3], t2[3], g[3];
    double gn = cn_dot3(prefer, n);
    for (int k = 0; k < 3; k++) g[k] = prefer[k] - gn * n[k];
    if (cn_norm3(g) > 1e-6 * cn_norm3(prefer)) {
        cn_copy3(t1, g);
        cn_normalize3(t1);
        cn_cross3(n, t1, t2);
    } else {
        cn_tangent_basis(n, t1, t2);
    }
    for (int d = 0; d < D; d++) {
        double th = 2 * CN_PI * d / D, c = cos(th), s = sin(th);
        for (int k = 0; k < 3; k++) dirs[d][k] = c * t1[k] + s * t2[k];
    }
}

/* How the nominal motion meets a contact. */
enum { NOM_STICK = 0, NOM_SLIDE = 1, NOM_OPEN = 2, NOM_CLOSE = 3 };

/* A reading of the corner contacts' normals: by index (meet_contacts), or with one corner (the
 * one-th, from 0) taking end `end` and every other its first end (one >= 0). */
typedef struct {
    unsigned long long index;
    int one, end;
} Reading;

typedef struct {
    const cnAssembly *a;
    cnMech m;
    double dt;
    int K;          /* contacts */
    int Kf;         /* contacts with friction */
    int D;          /* friction directions */
    int *fric_of;   /* contact -> friction index or -1 */
    int *contact_of_fric;
    double *mu;     /* per friction contact */
    int *nominal;   /* per contact: NOM_* */
    double (*slide)[3]; /* per contact: unit nominal sliding direction (body2 w.r.t. body1) */
    double (*dirs)[3];  /* Kf * D friction directions */
    cnJRow *rows;   /* K normal rows, then Kf*D friction rows */
    const cnContactSet *cs;
    double lp_residual; /* verified residual of the LP's solution (relative to W) */
    const char *lp_method; /* how the last verified LP answer was found (a static string) */
    double *cert;       /* nb * nd: when the LP has no solution, its verified Farkas certificate:
                           a virtual motion (velocity per dof) with f_ext . cert > 0 */
    bool has_cert;      /* cert holds the certificate of the last static_lp */
    bool defer_cert;    /* static_lp may leave its interior point until after the sparse QP */
    bool cert_deferred; /* ... and did: the descent found no static field, nothing else ran */
    bool cert_resumed;  /* static_lp after a deferral: the load descent is known to fail */
    bool field_only;    /* static_lp wants a field or nothing (the frictionless LP before the
                         * friction one): no certificate, no GLPK when the interior point shows
                         * that none exists ... */
    bool field_absent;  /* ... and it did */
    const double *cert_try; /* nb * nd, or NULL: a motion static_lp tries as the certificate first */
    double *qp_motion;  /* nb * nd: the sparse QP's own accelerations, when a certificate waits */
    /* cn_check's stages: the options, the result being filled, and the solvers' arrays */
    const cnCheckOptions *o;
    cnCheckResult *r;
    cnDiag *diag;
    int n, nrows;       /* LCP size; force rows (K normal + Kf * D friction) */
    cnLcp lcp;
    double *z, *wv, *dscale;     /* n: the LCP's solution and its scaling */
    double *force, *lpforce, *mforce; /* nrows: forces of the LCP, the LP, the motion search */
    double *acc;                 /* nb * nd: the motion */
    double *nominal_rows;        /* Kf * D: nominal sliding per friction row */
    double (*fric)[3], (*lpfric)[3]; /* K: friction force vectors (LCP, LP) */
    cnLcpStatus ls;
    cnLcpInfo info;
    const char *lcp_why;         /* why the LCP was not solved */
    bool qp_failed;              /* the sparse QP was tried and its answer did not verify */
    bool lp_done, lp_feasible;   /* the LP ran; it found a static solution */
    bool lp_trusted;             /* ran first, and its static solution decides (no LCP) */
    bool nf_done, nf_proved;     /* with friction: the frictionless field was sought first
                                    (frictionless_first); it proves that nothing moves */
    bool lcp_ok, lcp_static;     /* the LCP was solved; its solution is static */
    bool squeezed;               /* frictionless LCP motion carried by forces above CN_SQUEEZE_WEIGHTS */
    Reading reading;             /* the reading of the corner contacts' normals (meet_contacts) */
    bool drop_corners;           /* leave the corner contacts out altogether */
    bool held_unloaded;          /* leave out the contacts of held parts with free parts */
    int ncorners;                /* contacts that are a corner on a corner */
    double readings, readings_log2; /* their readings: the product of their cones' ends */
    bool corners_wide;           /* a corner contact's cone had more ends than were kept */
} Work;

static void work_free(Work *w) {
    cn_lcp_free(&w->lcp);
    cn_free(w->z);
    cn_free(w->wv);
    cn_free(w->dscale);
    cn_free(w->force);
    cn_free(w->lpforce);
    cn_free(w->mforce);
    cn_free(w->acc);
    cn_free(w->nominal_rows);
    cn_free(w->fric);
    cn_free(w->lpfric);
    cn_mech_free(&w->m);
    cn_free(w->fric_of);
    cn_free(w->contact_of_fric);
    cn_free(w->mu);
    cn_free(w->nominal);
    cn_free(w->slide);
    cn_free(w->dirs);
    cn_free(w->rows);
    cn_free(w->cert);
    cn_free(w->qp_motion);
}

/* Verify an LP solution (x: scaled, from GLPK; on return clipped to >= 0 and in absolute
 * units): the largest violation of a body's equilibrium (relative to its row scale) or of a
 * friction cone. res: scratch of nb * nd. */
static double lp_verify(const Work *w, const cnJRow *cols, int ncols, const int *col_contact,
                        const int *col_dir, const int *col_inq, const double *col_inq_val,
                        const double *colscale, const double *rowscale, double *x, double *res) {
    const cnMech *m = &w->m;
    int nd = m->nd, neq = m->nb * nd;
    for (int jj = 0; jj < ncols; jj++) {
        if (!isfinite(x[jj])) return INFINITY; /* fmax below would hide a NaN */
        x[jj] = fmax(x[jj], 0.0) * colscale[jj];
    }
    for (int i = 0; i < neq; i++) res[i] = m->fext[i];
    for (int jj = 0; jj < ncols; jj++)
        for (int side = 0; side < 2; side++) {
            int b = cols[jj].body[side];
            if (b < 0) continue;
            for (int d = 0; d < nd; d++) res[b * nd + d] += cols[jj].c[side][d] * x[jj];
        }
    double worst = 0;
    for (int i = 0; i < neq; i++) {
        double e = fabs(res[i]) / rowscale[i];
        if (!(e <= worst)) worst = isnan(e) ? INFINITY : e; /* a NaN (an overflowed weight) never passes */
    }
    for (int jj = 0; jj < ncols; jj++) {
        if (col_dir[jj] >= 0 || col_contact[jj] < 0 || col_inq[jj] < 0) continue;
        double sum = col_inq_val[jj] * x[jj];
        for (int t = jj + 1; t < ncols && col_dir[t] >= 0; t++) sum -= x[t];
        worst = fmax(worst, -sum / colscale[jj]);
    }
    return worst;
}

/* LPs with more columns than this skip the slow fallbacks (the dual simplex, measured over 200 s
 * on a 10,000-brick wall's LP): their answer, when the first ways fail to verify, is a
 * numerical failure. */
#define CN_LP_FALLBACK_MAX_COLS 4000

/* A Farkas certificate must show a static solution absurd: given the certificate's rounding,
 * every one would need some contact force of at least this many times the weights (scaled
 * columns are in units of weight). */
#define CN_LP_CERT_FORCE 1e6
/* ... and gravity's power on it, in absolute units, must exceed this fraction of the largest it
 * could have on a motion of that size (gravity acts on the linear rows only). */
#define CN_LP_CERT_POWER 1e-9
/* A body drives a certificate's motion when gravity does at least this share of its power on it. */
#define CN_LP_CERT_SHARE 1e-6

/* "; the masses ... span" when the free parts' masses span more than CN_MASS_SPAN_RESOLVED (a
 * light part's balance is then a small difference of forces many times its weight), else "". */
static const char *mass_span(const Work *w, char *buf, size_t cap) {
    double lo = INFINITY, hi = 0;
    for (int b = 0; b < w->m.nb; b++) lo = fmin(lo, w->m.mass[b]), hi = fmax(hi, w->m.mass[b]);
    buf[0] = '\0';
    if (hi > CN_MASS_SPAN_RESOLVED * lo)
        snprintf(buf, cap, "; the parts' masses span a factor of %.3g, and beyond about %.0e the "
                 "lighter parts' balance is lost to rounding", hi / lo, CN_MASS_SPAN_RESOLVED);
    return buf;
}

/* (A^T y)_j for the LP's column j, y's inequality entries taken at zero where negative (a cone
 * row's dual only counts as it resists). */
static double col_dual(const cnLpProblem *lp, int j, const double *y) {
    double g = 0;
    for (int t = lp->colptr[j]; t < lp->colptr[j + 1]; t++) {
        int i = lp->rows[t];
        g += lp->vals[t] * (i < lp->neq ? y[i] : fmax(y[i], 0.0));
    }
    return g;
}

/* Verify the elastic LP's duals y as a certificate that lp has no solution. Gravity's power
 * rhs^T y on the virtual motion must exceed CN_LP_EQ_TOL; a column j (force x_j >= 0) resists
 * the motion by g_j = (A^T y)_j, exactly 0 or less for a perfect certificate and a rounding
 * error above it otherwise. A static solution x would satisfy sum_j g_j x_j >= power (the cone
 * rows' duals are >= 0 and their right-hand sides 0), so some column with g_j > 0 would carry
 * max x >= power / sum_{g_j > 0} g_j; the certificate holds when that is CN_LP_CERT_FORCE
 * weights or more. (Bounding by the largest g_j times the number of columns instead rejected
 * a 16-block bridge's certificate at mu 0.05, power 0.36 against one column's 3.8e-10.)
 * On success w->cert receives the motion (absolute units). */
static bool lp_certificate(Work *w, const cnLpProblem *lp, const double *y,
                           const double *rowscale, const double *colscale) {
    int neq = lp->neq;
    double power = 0, resist = 0, resist_abs = 0, weight = 0;
    for (int i = 0; i < neq; i++) power += lp->rhs[i] * y[i]; /* = gravity's power, absolute */
    for (int j = 0; j < lp->nvars; j++) {
        double g = col_dual(lp, j, y);
        if (!isfinite(g)) return false;
        if (g <= 0) continue;
        resist += g;
        resist_abs += g / colscale[j]; /* resistance per unit of absolute force */
    }
    if (!(power > CN_LP_EQ_TOL) || !(resist * CN_LP_CERT_FORCE <= power)) return false;
    /* The same bound in absolute forces: a static solution would need a force of
     * power / resist_abs, which must be absurd next to the weights that drive the motion (the
     * bodies on which gravity does a share of the power; in each column's own units a light
     * part's contacts look absurd while they carry a heavy part's weight) */
    for (int b = 0; b < w->m.nb; b++) {
        double pb = 0;
        for (int d = 0; d < w->m.dim; d++) pb -= y[b * w->m.nd + d] / rowscale[b * w->m.nd + d] * w->m.fext[b * w->m.nd + d];
        if (pb > CN_LP_CERT_SHARE * power) weight += w->m.mass[b] * w->m.g;
    }
    if (!(resist_abs * CN_LP_CERT_FORCE * weight <= power)) return false;
    if (!w->cert) w->cert = cn_malloc(sizeof(double) * (size_t)(neq + 1));
    if (!w->cert) return false;
    for (int i = 0; i < neq; i++) w->cert[i] = -y[i] / rowscale[i];
    /* ... and, in the bodies' own units, gravity's power on the motion must be a real fraction of
     * what it could be: rows scaled by weights 1e12 apart let rounding pass for power (a light
     * block slid sideways under a heavy one "proved" that no static solution exists) */
    const cnMech *m = &w->m;
    double pw = 0, most = 0;
    for (int b = 0; b < m->nb; b++) {
        double fl = 0, ul = 0;
        for (int d = 0; d < m->dim; d++) {
            pw += m->fext[b * m->nd + d] * w->cert[b * m->nd + d];
            fl += m->fext[b * m->nd + d] * m->fext[b * m->nd + d];
            ul += w->cert[b * m->nd + d] * w->cert[b * m->nd + d];
        }
        most += sqrt(fl * ul);
    }
    if (!(pw > CN_LP_CERT_POWER * most)) return false;
    w->has_cert = true;
    return true;
}

/* LPs with friction cones and at least this many columns try GLPK's interior-point method
 * before the simplex, after cairn's (measured: 30x faster than the simplex with friction;
 * slower than the simplex without) */
#define CN_LP_INTERIOR_MIN_COLS 2000
/* LPs without cone rows (frictionless, or every friction contact sliding) of at least this many
 * columns are solved first by descent (load_descent: each body from the top down passes its
 * load to the contacts below it; linear time, measured: the 10,000-brick 2-D wall 0.6 s in all
 * instead of 5.2, the 10-layer stack of 1,000 boxes 0.3 s instead of 1.4), then by cairn's own
 * interior-point method (lp_ipm.c, on CHOLMOD), both verified
 * like GLPK's answers; GLPK follows when it does not verify. Measured against GLPK alone: the 10,000-brick 2-D wall's frictionless LP 5 s
 * against about 55 s (GLPK's primal simplex gives up, its elastic LP answers), the 1,000-brick
 * 3-D wall frictionless 0.93 s against 2.65 s. LPs with friction cones skip the descent and go
 * to cairn's interior point, then GLPK's: on them GLPK's interior point was once as fast or
 * faster (2-D wall of 1,000 bricks 0.77 s against 0.53 s; 10 layers of 10 x 10 boxes, 41 s
 * against 30 s), but walls and stacks now stop at the frictionless field, and on the arches and
 * vaults that reach the friction LP GLPK's interior point fails and its simplex is slow
 * (2026-11-28, whole checks with friction 0.6: 2-D arch of 1,000 voussoirs 3.35 s against
 * 0.55 s; 3-D vault of 10 x 10 0.67 s against 0.44 s; of 25 x 40 9.4 s, 335 MiB against 9.9 s,
 * 152 MiB).
 * The environment variable CAIRN_LP_GLPK_ONLY (any value) skips both: the benchmarks time both;
 * CAIRN_NO_LOAD_DESCENT skips the descent alone: the tests reach the interior point with it. */
#define CN_LP_IPM_MIN_COLS 2000

/* The equilibrium LP's arrays: one column per force variable (a contact's normal force, with
 * kinetic friction folded in when it slides; D pyramid forces per sticking friction contact; a
 * push along the nominal motion both ways per pushed body), rows of body equilibrium then one
 * cone row per sticking friction contact. */
typedef struct {
    int ncols, ninq, neq;
    cnJRow *cols;
    int *col_contact;    /* contact, or -1 */
    int *col_dir;        /* pyramid index or -1 */
    int *col_inq;        /* cone row or -1 */
    double *col_inq_val;
    int *colptr, *rowi;  /* the scaled matrix, compressed by column */
    double *vals, *rhs, *cost;
    double *x, *y, *res; /* primal, dual, equilibrium residual */
    double *rowscale, *colscale;
    bool any_field; /* any static field decides: the LP's cost only picks among them */
} LpArrays;

static void lp_arrays_free(LpArrays *L) {
    cn_free(L->cols);
    cn_free(L->col_contact);
    cn_free(L->col_dir);
    cn_free(L->col_inq);
    cn_free(L->col_inq_val);
    cn_free(L->colptr);
    cn_free(L->rowi);
    cn_free(L->vals);
    cn_free(L->rhs);
    cn_free(L->cost);
    cn_free(L->x);
    cn_free(L->res);
    cn_free(L->rowscale);
    cn_free(L->colscale);
    cn_free(L->y);
}

/* Count the columns and allocate. */
static cnStatus lp_arrays_alloc(const Work *w, bool nofric, LpArrays *L, cnDiag *diag) {
    const cnMech *m = &w->m;
    int npushed = 0, nd = m->nd;
    for (int b = 0; b < m->nb; b++) npushed += m->pushed[b];
    for (int c = 0; c < w->K; c++) {
        if (w->nominal[c] == NOM_OPEN) continue;
        L->ncols++;
        if (!nofric && w->fric_of[c] >= 0 && w->nominal[c] == NOM_STICK) L->ncols += w->D, L->ninq++;
    }
    L->ncols += 2 * npushed;
    L->neq = m->nb * nd;
    size_t nc = (size_t)L->ncols + 1, nr = (size_t)(L->neq + L->ninq + 1);
    size_t cap = (size_t)L->ncols * (2 * nd + 1) + 1;
    L->cols = cn_calloc(nc, sizeof(cnJRow));
    L->col_contact = cn_malloc(sizeof(int) * nc);
    L->col_dir = cn_malloc(sizeof(int) * nc);
    L->col_inq = cn_malloc(sizeof(int) * nc);
    L->col_inq_val = cn_malloc(sizeof(double) * nc);
    L->colptr = cn_malloc(sizeof(int) * nc);
    L->rowi = cn_malloc(sizeof(int) * cap);
    L->vals = cn_malloc(sizeof(double) * cap);
    L->rhs = cn_malloc(sizeof(double) * nr);
    L->cost = cn_malloc(sizeof(double) * nc);
    L->x = cn_calloc(nc, sizeof(double));
    L->res = cn_calloc((size_t)L->neq + 1, sizeof(double));
    L->rowscale = cn_malloc(sizeof(double) * (size_t)(L->neq + 1));
    L->y = cn_malloc(sizeof(double) * nr);
    L->colscale = cn_malloc(sizeof(double) * nc);
    if (!L->cols || !L->col_contact || !L->col_dir || !L->col_inq || !L->col_inq_val || !L->colptr ||
        !L->rowi || !L->vals || !L->rhs || !L->cost || !L->x || !L->res || !L->rowscale || !L->colscale || !L->y)
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the LP");
    return CN_OK;
}

/* The columns in body coordinates: contacts (kinetic friction folded into sliding ones, the
 * pyramid of sticking ones) and the pushes along the nominal motion. */
static void lp_columns(const Work *w, bool nofric, LpArrays *L) {
    const cnMech *m = &w->m;
    int nd = m->nd, K = w->K, D = w->D;
    int j = 0, q = 0;
    for (int c = 0; c < K; c++) {
        if (w->nominal[c] == NOM_OPEN) continue;
        const cnContact *ct = &w->cs->items[c];
        int f = nofric ? -1 : w->fric_of[c];
        L->cols[j] = w->rows[c];
        if (f >= 0 && w->nominal[c] == NOM_SLIDE) {
            /* kinetic friction mu p_n against the sliding of body2 (and for body1 the reverse,
             * which the row's sign convention gives) */
            cnJRow tr;
            cn_mech_row(m, ct->body1, ct->body2, ct->point, w->slide[c], &tr);
            for (int side = 0; side < 2; side++)
                for (int d = 0; d < nd; d++) L->cols[j].c[side][d] -= w->mu[f] * tr.c[side][d];
        }
        L->col_contact[j] = c, L->col_dir[j] = -1, L->col_inq[j] = -1;
        int normal_col = j;
        j++;
        if (f >= 0 && w->nominal[c] == NOM_STICK) {
            L->col_inq[normal_col] = L->neq + q;
            L->col_inq_val[normal_col] = w->mu[f];
            for (int d = 0; d < D; d++) {
                L->cols[j] = w->rows[K + f * D + d];
                L->col_contact[j] = c, L->col_dir[j] = d, L->col_inq[j] = L->neq + q, L->col_inq_val[j] = -1.0;
                j++;
            }
            q++;
        }
    }
    for (int b = 0; b < m->nb; b++)
        for (int s = -1; s <= 1; s += 2) {
            if (!m->pushed[b]) continue;
            memset(&L->cols[j], 0, sizeof L->cols[j]);
            L->cols[j].body[0] = b, L->cols[j].body[1] = -1;
            for (int k = 0; k < w->a->dim; k++) L->cols[j].c[0][k] = s * m->mdir[k];
            L->col_contact[j] = -1, L->col_dir[j] = -1, L->col_inq[j] = -1;
            j++;
        }
}

/* Scaling, per body and per contact, so that parts of 1e-4 and 1e4 in one assembly are each
 * judged at their own scale: a body's force rows are divided by its weight W_b and its torque
 * rows by W_b r_b (r_b: its radius about its centre of mass); a column's variable is in units
 * of the largest weight among the bodies it acts on. Then the scaled matrix, right-hand side
 * (gravity) and cost (the sum of normal forces). */
static void lp_scaled_matrix(const Work *w, LpArrays *L) {
    const cnMech *m = &w->m;
    const cnAssembly *a = w->a;
    int nd = m->nd, dim = a->dim, ncols = L->ncols;
    double W = m->wref;
    for (int b = 0; b < m->nb; b++) {
        double wb = a->parts[m->part_of_body[b]].mass * m->g;
        if (!(wb > 0)) wb = W;
        double rb = m->radius[b] > 0 ? m->radius[b] : a->length_scale;
        for (int d = 0; d < nd; d++) L->rowscale[b * nd + d] = d < dim ? wb : wb * rb;
    }
    for (int jj = 0; jj < ncols; jj++) {
        double sc = 0;
        for (int side = 0; side < 2; side++)
            if (L->cols[jj].body[side] >= 0) sc = fmax(sc, L->rowscale[L->cols[jj].body[side] * nd]);
        L->colscale[jj] = sc > 0 ? sc : W;
    }
    int k = 0;
    for (int jj = 0; jj < ncols; jj++) {
        L->colptr[jj] = k;
        for (int side = 0; side < 2; side++) {
            int b = L->cols[jj].body[side];
            if (b < 0) continue;
            for (int d = 0; d < nd; d++) {
                double v = L->cols[jj].c[side][d] * L->colscale[jj] / L->rowscale[b * nd + d];
                if (v == 0) continue;
                L->rowi[k] = b * nd + d, L->vals[k] = v, k++;
            }
        }
        if (L->col_inq[jj] >= 0) L->rowi[k] = L->col_inq[jj], L->vals[k] = L->col_inq_val[jj], k++;
        L->cost[jj] = (L->col_contact[jj] >= 0 && L->col_dir[jj] < 0) ? 1.0 : 0.0;
    }
    L->colptr[ncols] = k;
    for (int i = 0; i < L->neq; i++) L->rhs[i] = -m->fext[i] / L->rowscale[i];
    for (int i = 0; i < L->ninq; i++) L->rhs[L->neq + i] = 0;
}

/* Verify the solution in L->x (scaled; unscaled in place), found by `method`: true when it is a
 * static solution (then *worst is its residual); *worst keeps the best residual seen. */
static bool lp_accept(Work *w, LpArrays *L, const char *method, double *worst) {
    double wk = lp_verify(w, L->cols, L->ncols, L->col_contact, L->col_dir, L->col_inq, L->col_inq_val,
                          L->colscale, L->rowscale, L->x, L->res);
    *worst = fmin(*worst, wk);
    w->lp_method = method;
    if (!(wk <= CN_LP_EQ_TOL)) return false;
    *worst = wk;
    return true;
}

/* The bodies from the top of the assembly down (against gravity; ties by index). */
typedef struct {
    double h;
    int b;
} Height;
static int by_height(const void *x, const void *y) {
    const Height *p = x, *q = y;
    if (p->h != q->h) return p->h > q->h ? -1 : 1;
    return p->b - q->b;
}

/* The LP by descent (cn_lp_descent) when no body is pushed: each body, from the top down, takes
 * the loads of the bodies above it and passes its weight and theirs to the contacts below. A
 * nonzero status only when out of memory. */
static cnStatus load_descent(const Work *w, const cnLpProblem *lp, double *x, bool *met) {
    const cnMech *m = &w->m;
    *met = false;
    /* cn_lp_descent refuses cone rows too; saying so here saves the height sort */
    if (lp->nineq != 0 || getenv("CAIRN_NO_LOAD_DESCENT")) return CN_OK;
    for (int b = 0; b < m->nb; b++)
        if (m->pushed[b]) return CN_OK;
    Height *hs = cn_malloc(sizeof(Height) * (size_t)(m->nb + 1));
    int *order = cn_malloc(sizeof(int) * (size_t)(m->nb + 1));
    cnStatus st = CN_ERR_MEMORY;
    if (hs && order) {
        const double *g = w->a->gravity;
        for (int b = 0; b < m->nb; b++)
            hs[b] = (Height){-(g[0] * m->com[b][0] + g[1] * m->com[b][1] + g[2] * m->com[b][2]), b};
        qsort(hs, (size_t)m->nb, sizeof(Height), by_height);
        for (int b = 0; b < m->nb; b++) order[b] = hs[b].b;
        st = cn_lp_descent(lp, m->nd, order, x, met);
    }
    cn_free(hs);
    cn_free(order);
    return st;
}

/* A lower bound, from any y, on the cost c.x of every x >= 0 with A_eq x = b_eq, A_in x >= b_in
 * (y's inequality entries taken at zero where negative): b.y = sum_j x_j (A^T y)_j <= rho c.x
 * when (A^T y)_j <= rho c_j for every column, so c.x >= b.y / rho. Infinite when y is a Farkas
 * certificate (b.y > 0 with A^T y <= 0), zero when it bounds nothing. */
static double field_cost_bound(const cnLpProblem *lp, const double *y) {
    double by = 0, rho = 0;
    for (int i = 0; i < lp->neq + lp->nineq; i++) by += lp->rhs[i] * (i < lp->neq ? y[i] : fmax(y[i], 0));
    for (int j = 0; j < lp->nvars; j++) {
        double g = col_dual(lp, j, y);
        double c = lp->cost ? lp->cost[j] : 0;
        if (c > 0) rho = fmax(rho, g / c);
        else if (g > 0 || c < 0) return 0;
    }
    if (!(by > CN_LP_FIELD_BY_MIN)) return 0; /* rounding bounds nothing */
    return rho > 0 ? by / rho : INFINITY;
}

/* A motion found elsewhere (the sparse QP's accelerations) as the LP's Farkas certificate:
 * y = -u * rowscale inverts lp_certificate's cert = -y / rowscale, and lp_certificate verifies
 * it as it verifies the solvers' duals. A frictionless motion that opens or keeps every contact
 * (J a >= 0) and on which gravity does work (Gauss's principle: f_ext . a = a^T M a > 0) is
 * one. */
static bool motion_certificate(Work *w, LpArrays *L, const cnLpProblem *lp) {
    for (int i = 0; i < L->neq; i++) L->y[i] = -w->cert_try[i] * L->rowscale[i];
    for (int i = L->neq; i < L->neq + L->ninq; i++) L->y[i] = 0;
    if (!lp_certificate(w, lp, L->y, L->rowscale, L->colscale)) return false;
    w->lp_method = "QP motion";
    return true;
}

/* Every answer is verified, and GLPK is run in several ways until one verifies: the
 * interior-point method for large LPs with friction (its solution, once verified, is as good a
 * certificate as a vertex); the primal simplex; the elastic LP, whose primal is the force field
 * closest to equilibrium and whose dual is a Farkas certificate (a virtual motion on which
 * gravity does work and no contact force resists), so that GLPK's claim that there is no
 * solution is believed only with a certificate that verifies; then, for LPs up to
 * CN_LP_FALLBACK_MAX_COLS, the dual simplex and the elastic LP with the other scaling. (GLPK's
 * exact rational simplex, tried as a last step, took over 20 s on a fuzzing input: it is not
 * used.) Returns whether one verified; *worst: the best equilibrium residual found. */
static bool lp_solve_verified(Work *w, LpArrays *L, double *worst, cnDiag *diag) {
    cnLpProblem lp = {L->ncols, L->neq, L->ninq, L->colptr, L->rowi, L->vals, L->rhs, L->cost,
                      false, CN_LP_PRIMAL_AUTO, true, L->any_field};
    static const struct {
        bool interior, elastic, small_only;
        int method;
    } steps[] = {{true, false, false, CN_LP_PRIMAL_AUTO}, {false, false, false, CN_LP_PRIMAL_AUTO},
                 {false, true, false, CN_LP_DUAL_EQ},     {false, false, true, CN_LP_DUAL_EQ},
                 {false, true, true, CN_LP_PRIMAL_AUTO}};
    *worst = INFINITY;
    if (w->cert_try && motion_certificate(w, L, &lp)) return true;
    if (L->ncols >= CN_LP_IPM_MIN_COLS && !getenv("CAIRN_LP_GLPK_ONLY")) {
        /* first, without cone rows, the descent (linear time; it fails where a load must go up
         * or sideways) */
        bool met = false; /* out of memory: not met, and the interior point says so too */
        if (!w->cert_resumed && load_descent(w, &lp, L->x, &met) == CN_OK && met &&
            lp_accept(w, L, "load descent", worst))
            return true;
        /* frictionless and large, the sparse QP follows (solve_models): it gives the LCP's motion,
         * and a moving answer of it is the certificate, so the interior point waits for it */
        if (w->defer_cert) {
            w->cert_deferred = true;
            return false;
        }
        /* then the interior point: any failure of it (out of memory among them) leaves the
         * answer to GLPK */
        cnLpIpmInfo info;
        bool ran = !cn_lp_ipm(&lp, CN_IPM_WEIGHT_FORCES, L->x, L->y, &info, diag);
        if (ran && lp_accept(w, L, "interior point", worst)) return true;
        if (ran && info.field_stop) {
            /* stopped at a field that does not verify here: the method again, to its optimum */
            lp.any_field = false;
            ran = !cn_lp_ipm(&lp, CN_IPM_WEIGHT_FORCES, L->x, L->y, &info, diag);
            if (ran && lp_accept(w, L, "interior point", worst)) return true;
        }
        if (ran) {
            /* frictionless and wanted only for its field: none, when the interior point ended
             * far from one and its duals show that any field would need normal forces over
             * CN_LP_FIELD_ABSENT weights a body (the elastic penalty is exact, and the method
             * approaches a field, unless fields cost about that much); else the usual
             * fallbacks, which may still find one (an arch's thrust alone, carried by every
             * joint, sums to about the number of bodies squared times span / (8 rise)). At
             * worst a field is missed and a stable assembly is reported undecided. */
            if (w->field_only && *worst > CN_LP_FIELD_FAR &&
                field_cost_bound(&lp, L->y) >= CN_LP_FIELD_ABSENT * w->m.nb) {
                w->field_absent = true;
                return false;
            }
            /* no static solution: the duals of the same LP with (almost) no cost on the forces
             * are the certificate (with the forces' cost, every loaded column resists by the
             * cost's weight, far above what lp_certificate lets through) */
            lp.any_field = false;
            if (info.elastic > 0 && !cn_lp_ipm(&lp, CN_IPM_WEIGHT_CERTIFICATE, L->x, L->y, &info, diag) &&
                lp_certificate(w, &lp, L->y, L->rowscale, L->colscale))
                return true;
        }
    }
    for (int i = 0; i < (int)(sizeof steps / sizeof steps[0]); i++) {
        if (steps[i].interior && !(L->ncols >= CN_LP_INTERIOR_MIN_COLS && L->ninq > 0)) continue;
        if (steps[i].small_only && L->ncols > CN_LP_FALLBACK_MAX_COLS) continue;
        lp.interior = steps[i].interior;
        lp.method = steps[i].method;
        if (steps[i].elastic) {
            if (cn_lp_elastic(&lp, L->x, L->y, diag)) continue;
        } else {
            bool feas = false;
            if (cn_lp_solve(&lp, &feas, L->x, diag) || !feas) continue;
        }
        if (lp_accept(w, L,
                      steps[i].interior ? "GLPK interior point"
                      : steps[i].elastic ? "GLPK simplex, elastic" : "GLPK simplex",
                      worst))
            return true;
        if (steps[i].elastic && lp_certificate(w, &lp, L->y, L->rowscale, L->colscale)) return true;
    }
    return false;
}

/* The verified LP solution as contact forces (normal, pyramid) and friction vectors. */
static void lp_forces(const Work *w, const LpArrays *L, bool nofric, double *force, double (*fric)[3]) {
    int K = w->K, D = w->D;
    memset(force, 0, sizeof(double) * (size_t)(K + w->Kf * D));
    memset(fric, 0, sizeof(double[3]) * (size_t)K);
    for (int jj = 0; jj < L->ncols; jj++) {
        int c = L->col_contact[jj];
        double x = L->x[jj];
        if (c < 0) continue;
        if (L->col_dir[jj] < 0) {
            force[c] = x;
            if (w->nominal[c] == NOM_SLIDE && w->fric_of[c] >= 0 && !nofric)
                for (int kk = 0; kk < 3; kk++) fric[c][kk] = -w->mu[w->fric_of[c]] * x * w->slide[c][kk];
        } else {
            int f = w->fric_of[c];
            force[K + f * D + L->col_dir[jj]] = x;
            for (int kk = 0; kk < 3; kk++) fric[c][kk] += x * w->dirs[f * D + L->col_dir[jj]][kk];
        }
    }
}

/* The LP: is there a solution in which every dynamic part keeps its nominal motion? Columns are
 * generalized forces: per contact the normal force (minus kinetic friction when it slides), the
 * pyramid directions at sticking friction contacts, and +-m for pushed parts (the gripper).
 * On success, force (size K + Kf*D) and fric (per contact friction vector on body2) are
 * filled in absolute units. */
static cnStatus static_lp(Work *w, bool nofric, bool *feasible, double *force,
                          double (*fric)[3], cnDiag *diag) {
    *feasible = false;
    w->has_cert = false;
    w->cert_deferred = false;
    w->field_absent = false;
    for (int c = 0; c < w->K; c++)
        if (w->nominal[c] == NOM_CLOSE) return CN_OK; /* a part is driven into another */
    LpArrays L;
    memset(&L, 0, sizeof L);
    cnStatus st = lp_arrays_alloc(w, nofric, &L, diag);
    if (!st) {
        lp_columns(w, nofric, &L);
        L.any_field = !nofric && w->r->friction;
        lp_scaled_matrix(w, &L);
        double worst;
        long internal = cn_lp_internal_errors();
        if (!lp_solve_verified(w, &L, &worst, diag)) {
            char why[160];
            if (w->cert_deferred || w->field_absent) {
                /* decided after the sparse QP (solve_models), or by the friction LP */
            } else if (cn_lp_internal_errors() > internal) /* GLPK's own message says why */
                st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                                 "the LP solver (GLPK) stopped on an internal error (out of memory, "
                                 "or numbers it cannot scale) on the equilibrium LP (%d rows, %d "
                                 "columns); no verdict", L.neq + L.ninq, L.ncols);
            else
                st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                                 "the equilibrium LP (%d rows, %d columns) is too ill-conditioned "
                                 "to decide: neither a static force field (closest residual %.2g of "
                                 "the weights) nor a certificate that none exists verifies%s; no "
                                 "verdict", L.neq + L.ninq, L.ncols, worst, mass_span(w, why, sizeof why));
        } else {
            w->lp_residual = worst;
            if (worst <= CN_LP_EQ_TOL) { /* else infeasible, with w->cert */
                *feasible = true;
                lp_forces(w, &L, nofric, force, fric);
            }
        }
    }
    lp_arrays_free(&L);
    return st;
}

/* The motion of the LP's certificate u, sized as the acceleration along it when contacts do no
 * work: a = (fext.u / u^T M u) u. */
static void cert_motion(const Work *w, double *acc) {
    const cnMech *m = &w->m;
    int nv = m->nb * m->nd;
    double fu = 0;
    for (int i = 0; i < nv; i++) fu += m->fext[i] * w->cert[i];
    double e = cn_mech_kinetic(m, w->cert, NULL);
    double t = e > 0 ? fu / e : 0;
    for (int i = 0; i < nv; i++) acc[i] = t * w->cert[i];
}

static cnLcpStatus solve_lcp(const cnLcp *p, cnSolverChoice choice, bool symmetric_psd,
                             const cnLcpOptions *o, double *z, double *wv, cnLcpInfo *info,
                             const char **used) {
    cnLcpStatus s;
    if (choice == CN_SOLVER_PIVOT ||
        (choice == CN_SOLVER_AUTO && symmetric_psd && p->n <= CN_PIVOT_MAX_AUTO)) {
        s = cn_lcp_pivot(p, o, z, wv, info);
        *used = "pivot";
        if (s == CN_LCP_SOLVED || choice == CN_SOLVER_PIVOT) return s;
    }
    *used = "lemke";
    return cn_lcp_lemke(p, o, z, wv, info);
}

void cn_warm_start_free(cnWarmStart *ws) {
    if (!ws) return;
    for (int k = 0; k < CN_WARM_SLOTS; k++) {
        cn_free(ws->slot[k].basic);
        cn_free(ws->slot[k].row);
    }
    memset(ws->slot, 0, sizeof ws->slot);
    cn_free(ws->row_work);
    cn_free(ws->basic_work);
    cn_free(ws->used_work);
    ws->row_work = NULL;
    ws->basic_work = ws->used_work = NULL;
    ws->work_cap = 0;
    cn_proof_memo_free(ws->proofs);
    ws->proofs = NULL;
}

static unsigned long long mix(unsigned long long h, long long v) {
    return (h ^ (unsigned long long)v) * 0x100000001b3ULL; /* FNV-1a step */
}

/* The identity of each LCP row (its contact's bodies, pieces, fixel, kind and vertex, and which
 * row of the contact it is: normal, friction direction d, or the sliding speed), and the key of
 * the whole structure (all rows in order). */
static unsigned long long row_ids(const cnContactSet *cs, const int *fric_of, int Kf, int D,
                                  int n, unsigned long long *row) {
    int K = cs->count;
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &cs->items[c];
        unsigned long long h = 0xcbf29ce484222325ULL;
        long long v[7] = {ct->body1, ct->body2, ct->piece1, ct->piece2, ct->fixel, ct->kind,
                          ct->vertex};
        for (int k = 0; k < 7; k++) h = mix(h, v[k]);
        row[c] = h;
        int f = Kf > 0 ? fric_of[c] : -1;
        if (f < 0) continue;
        for (int d = 0; d < D; d++) row[K + f * D + d] = mix(h, 1 + d);
        row[K + Kf * D + f] = mix(h, -1);
    }
    unsigned long long key = mix(0xcbf29ce484222325ULL, n);
    for (int i = 0; i < n; i++) key = mix(key, (long long)row[i]);
    return key;
}

/* Remember basis `basic` (n flags, of rows `row`): refresh the slot that already holds it, else
 * overwrite the oldest. A failed allocation only means the next solve may be cold. */
static void warm_remember(cnWarmStart *ws, unsigned long long key, int n,
                          const unsigned long long *row, const unsigned char *basic, long stamp) {
    for (int k = 0; k < CN_WARM_SLOTS; k++)
        if (ws->slot[k].stamp && ws->slot[k].key == key && ws->slot[k].n == n &&
            !memcmp(ws->slot[k].basic, basic, (size_t)n)) {
            ws->slot[k].stamp = stamp;
            return;
        }
    int use = 0;
    for (int k = 0; k < CN_WARM_SLOTS; k++)
        if (ws->slot[k].stamp < ws->slot[use].stamp) use = k;
    if (n > ws->slot[use].cap) {
        unsigned char *nb = cn_realloc(ws->slot[use].basic, (size_t)n);
        if (nb) ws->slot[use].basic = nb;
        unsigned long long *nr = cn_realloc(ws->slot[use].row, sizeof(unsigned long long) * (size_t)n);
        if (nr) ws->slot[use].row = nr;
        if (!nb || !nr) {
            ws->slot[use].stamp = 0;
            return;
        }
        ws->slot[use].cap = n;
    }
    memcpy(ws->slot[use].basic, basic, (size_t)n);
    memcpy(ws->slot[use].row, row, sizeof(unsigned long long) * (size_t)n);
    ws->slot[use].key = key;
    ws->slot[use].n = n;
    ws->slot[use].stamp = stamp;
}

/* Carry slot k's basis over to rows `row` (n of them): each row takes the flag of the first
 * unused remembered row with its identity; rows without one start nonbasic. */
static void warm_carry(cnWarmStart *ws, int k, int n, const unsigned long long *row,
                       unsigned char *basic) {
    int m = ws->slot[k].n;
    unsigned char *used = ws->used_work; /* m <= work_cap: see warm_solve */
    memset(used, 0, (size_t)m);
    for (int i = 0; i < n; i++) {
        basic[i] = 0;
        for (int j = 0; j < m; j++)
            if (!used[j] && ws->slot[k].row[j] == row[i]) {
                used[j] = 1;
                basic[i] = ws->slot[k].basic[j];
                break;
            }
    }
}

/* Warm-start attempts per solve, at most: remembered bases of the same contacts, most recent
 * first (bisection alternates between the two sides of an onset). */
#define WARM_TRIES 2

/* solve_lcp with the warm start `ws` (may be NULL): remembered bases are tried first (see
 * cnWarmStart), and the solution's basis is remembered. Times and counts every solve. */
static cnLcpStatus warm_solve(cnWarmStart *ws, const cnContactSet *cs, const int *fric_of,
                              int Kf, int D, const cnLcp *p, cnSolverChoice choice,
                              bool symmetric_psd, const cnLcpOptions *o, double *z, double *wv,
                              cnLcpInfo *info, const char **used) {
    if (!ws) return solve_lcp(p, choice, symmetric_psd, o, z, wv, info, used);
    int n = p->n;
    struct timespec t0;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    /* scratch for the rows, sized for them and for every remembered basis */
    int need = n;
    for (int k = 0; k < CN_WARM_SLOTS; k++) need = ws->slot[k].n > need ? ws->slot[k].n : need;
    if (need > ws->work_cap) {
        unsigned long long *r = cn_realloc(ws->row_work, sizeof(unsigned long long) * (size_t)need);
        if (r) ws->row_work = r;
        unsigned char *b = cn_realloc(ws->basic_work, (size_t)need);
        if (b) ws->basic_work = b;
        unsigned char *u = cn_realloc(ws->used_work, (size_t)need);
        if (u) ws->used_work = u;
        if (r && b && u) ws->work_cap = need;
    }
    bool ready = need <= ws->work_cap;
    unsigned long long *row = ws->row_work;
    unsigned long long key = ready ? row_ids(cs, fric_of, Kf, D, n, row) : 0;
    cnLcpStatus s = CN_LCP_NUMERIC;
    bool tried[CN_WARM_SLOTS] = {false}, same = false;
    for (int t = 0; ready && !ws->record_only && t < WARM_TRIES && s != CN_LCP_SOLVED; t++) {
        int best = -1;
        for (int k = 0; k < CN_WARM_SLOTS; k++)
            if (!tried[k] && ws->slot[k].stamp && ws->slot[k].key == key && ws->slot[k].n == n &&
                (best < 0 || ws->slot[k].stamp > ws->slot[best].stamp))
                best = k;
        if (best >= 0) {
            same = tried[best] = true;
            s = cn_lcp_solve_basis(p, ws->slot[best].basic, o, z, wv, info);
            continue;
        }
        if (same) break;
        /* the contacts changed: the latest basis, carried over */
        for (int k = 0; k < CN_WARM_SLOTS; k++)
            if (ws->slot[k].stamp && (best < 0 || ws->slot[k].stamp > ws->slot[best].stamp)) best = k;
        if (best >= 0) {
            warm_carry(ws, best, n, row, ws->basic_work);
            s = cn_lcp_solve_basis(p, ws->basic_work, o, z, wv, info);
        }
        break;
    }
    if (s == CN_LCP_SOLVED) *used = symmetric_psd ? "pivot" : "lemke";
    else s = solve_lcp(p, choice, symmetric_psd, o, z, wv, info, used);
    double el = cn_seconds_since(&t0);
    ws->seconds += el;
    if (info->warm) ws->warm_seconds += el;
    ws->solves++;
    ws->warm_solves += info->warm;
    ws->pivots += info->pivots;
    if (s == CN_LCP_SOLVED && ready) {
        cn_lcp_basis_of(n, z, wv, ws->basic_work);
        warm_remember(ws, key, n, row, ws->basic_work, ws->solves);
    }
    return s;
}

/* Contacts of a moving body whose motion is at least this fraction of the largest are reported as
 * opening or sliding (see fill_result). */
#define CN_ONSET_FRACTION 1e-2

static void fill_result(Work *w, cnCheckResult *r, const double *force, const double (*fric)[3],
                        const double *acc, double tol) {
    const cnMech *m = &w->m;
    const cnAssembly *a = w->a;
    int nd = m->nd, K = w->K;
    double scale = m->g;
    r->nmoving = 0;
    for (int b = 0; b < m->nb; b++) {
        int p = m->part_of_body[b];
        bool mv = cn_mech_moves(m, b, acc, tol);
        r->part[p].moves = mv;
        if (!mv) continue;
        r->moving[r->nmoving++] = p;
        for (int k = 0; k < a->dim; k++) r->part[p].lin[k] = acc[(size_t)b * nd + k];
        if (a->dim == 2) r->part[p].ang[2] = acc[(size_t)b * nd + 2];
        else
            for (int k = 0; k < 3; k++) r->part[p].ang[k] = acc[(size_t)b * nd + 3 + k];
    }
    for (int i = 1; i < r->nmoving; i++) /* part order */
        for (int j = i; j > 0 && r->moving[j - 1] > r->moving[j]; j--) {
            int t = r->moving[j];
            r->moving[j] = r->moving[j - 1];
            r->moving[j - 1] = t;
        }
    for (int c = 0; c < K; c++) {
        cnContactResult *cr = &r->contact[c];
        const cnContact *ct = &r->contacts.items[c];
        cr->normal_force = force[c];
        cn_copy3(cr->friction, fric[c]);
        /* Relative motion at the contact beyond the nominal one. */
        double sep = cn_mech_relative(m, &w->rows[c], acc);
        cr->separation = sep;
        double t1[3], t2[3];
        if (a->dim == 2) {
            t1[0] = -ct->normal[1], t1[1] = ct->normal[0], t1[2] = 0;
        } else {
            cn_tangent_basis(ct->normal, t1, t2);
        }
        cnJRow tr;
        cn_mech_row(m, ct->body1, ct->body2, ct->point, t1, &tr);
        double s1 = cn_mech_relative(m, &tr, acc), s2 = 0;
        if (a->dim == 3) {
            cn_mech_row(m, ct->body1, ct->body2, ct->point, t2, &tr);
            s2 = cn_mech_relative(m, &tr, acc);
        }
        cr->slip = hypot(s1, s2);
        cr->separates = sep > tol * scale;
        cr->slides = !cr->separates && cr->slip > tol * scale;
    }
    /* At the very onset of an instability (a path located by bisection) a body may just pass
     * the threshold while each of its contacts' motions is still below it (a long body turning
     * about a short base): then its contacts that open or slide are those whose motion is a
     * sizeable fraction of the largest, so the report names them. */
    if (r->nmoving == 0) return;
    /* ... above the LCP verification's relative tolerance times g (its residual is relative to
     * data about g in size; the same floor for slipping): in the collapse of a frictionless
     * barrel vault every contact slides and none opens (the largest opening 1.2e-10 g, below
     * this floor by 8), and the rule named 1,282 or 1,415 of its 11,684 contacts opening by the
     * rounding of the solver's last steps. Contacts of a body just past the motion tolerance
     * opening by less than this floor are not named (at the default tolerances, only when the
     * largest opening is below 1e-7 g). */
    double noise = fmax(CN_TOL_NOISE, w->o->lcp.tol > 0 ? w->o->lcp.tol : CN_LCP_DEFAULT_TOL) * scale;
    double maxsep = 0, maxslip = 0;
    for (int c = 0; c < K; c++) maxsep = fmax(maxsep, r->contact[c].separation), maxslip = fmax(maxslip, r->contact[c].slip);
    for (int c = 0; c < K; c++) {
        cnContactResult *cr = &r->contact[c];
        const cnContact *ct = &r->contacts.items[c];
        bool moving = (ct->body1 >= 0 && r->part[ct->body1].moves) || (ct->body2 >= 0 && r->part[ct->body2].moves);
        if (!moving || cr->separates || cr->slides) continue;
        if (cr->separation > CN_ONSET_FRACTION * maxsep && cr->separation > noise) cr->separates = true;
        else if (cr->slip > CN_ONSET_FRACTION * maxslip && cr->slip > noise) cr->slides = true;
    }
}

/* The scaled contact LCP (dense): unknowns in units of W (average forces over dt), rows in units
 * of g (accelerations, or velocity changes over dt divided by dt). Friction adds the
 * Stewart-Trinkle blocks E, -E^T and mu (eq. 5), and the nominal relative velocities J v0 / dt
 * to q (b_n, b_f of eq. 5 with v^{t-1} the nominal motion).
 *
 * Then each contact is scaled to its own size: z_i = d_i z'_i and w'_i = d_i w_i with
 * d = 1 / sqrt(M_cc) for the normal and friction rows of contact c and 1 / d for its lambda
 * row, so that the diagonal of the normal block is 1 while E, -E^T and mu keep their entries
 * and M stays symmetric when frictionless. Without it, the forces between parts of 1e-4 units
 * beside parts of 1e4 units are 1e-15 of W and the solvers take them for zero. `d` (size n)
 * receives the scale; the solution of the LCP built here is d_i z'_i. */
static void scale_lcp(const Work *w, int n, bool friction, cnLcp *lcp, double *d) {
    int K = w->K, Kf = w->Kf, D = w->D;
    for (int i = 0; i < n; i++) d[i] = 1.0;
    for (int c = 0; c < K; c++) {
        double mcc = lcp->M[(size_t)c * n + c];
        d[c] = mcc > 0 && isfinite(mcc) ? 1.0 / sqrt(mcc) : 1.0;
    }
    if (friction)
        for (int f = 0; f < Kf; f++) {
            double dc = d[w->contact_of_fric[f]];
            for (int k = 0; k < D; k++) d[K + f * D + k] = dc;
            d[K + Kf * D + f] = 1.0 / dc;
        }
    for (int i = 0; i < n; i++) {
        for (int j = 0; j < n; j++) lcp->M[(size_t)i * n + j] *= d[i] * d[j];
        lcp->q[i] *= d[i];
    }
}

static cnStatus build_lcp(const Work *w, int n, bool friction, cnLcp *lcp, double *dscale) {
    if (cn_lcp_alloc(lcp, n) != CN_OK) return CN_ERR_MEMORY;
    int K = w->K, Kf = w->Kf, D = w->D, nrows = friction ? K + Kf * D : K;
    double g = w->m.g, W = w->m.wref;
    cn_mech_product(&w->m, w->rows, nrows, w->rows, nrows, W / g, lcp->M, n);
    for (int i = 0; i < nrows; i++) {
        lcp->q[i] = cn_mech_relative(&w->m, &w->rows[i], w->m.a0) / g;
        if (friction) {
            const cnContact *ct = &w->cs->items[i < K ? i : w->contact_of_fric[(i - K) / D]];
            double d[3];
            if (i < K) cn_copy3(d, ct->normal);
            else cn_copy3(d, w->dirs[i - K]);
            lcp->q[i] += cn_mech_nominal(&w->m, ct->body1, ct->body2, ct->point, d) / (g * w->dt);
        }
    }
    if (!friction) {
        scale_lcp(w, n, friction, lcp, dscale);
        return CN_OK;
    }
    for (int f = 0; f < Kf; f++) {
        int c = w->contact_of_fric[f];
        int lam = K + Kf * D + f;
        for (int d = 0; d < D; d++) {
            int row = K + f * D + d;
            lcp->M[(size_t)row * n + lam] = 1.0;  /* E */
            lcp->M[(size_t)lam * n + row] = -1.0; /* -E^T */
        }
        lcp->M[(size_t)lam * n + c] = w->mu[f]; /* mu */
    }
    scale_lcp(w, n, friction, lcp, dscale);
    return CN_OK;
}

/* Complementarity pairs beyond which the search for a motion from rest is not started (its LPs
 * would take seconds each): the verdict is then the weak one unless the frictionless certificate
 * holds. */
#define CN_MOTION_MAX_PAIRS 400

/* The contact LCP as the motion search reads it; nominal (Kf*D entries) receives the nominal
 * sliding along each friction row. Returns true when nothing slides nominally (the energy
 * argument holds). */
static bool motion_problem(const Work *w, const cnCheckOptions *o, double *nominal,
                           cnMotionProblem *p) {
    int Kf = w->Kf, D = w->D;
    bool energy = true;
    for (int f = 0; f < Kf; f++) {
        const cnContact *ct = &w->cs->items[w->contact_of_fric[f]];
        for (int d = 0; d < D; d++) {
            double v = cn_mech_nominal(&w->m, ct->body1, ct->body2, ct->point, w->dirs[f * D + d]) / w->dt;
            nominal[f * D + d] = v;
            if (v != 0) energy = false;
        }
    }
    *p = (cnMotionProblem){&w->m, w->K, Kf, D, w->rows, w->contact_of_fric, w->mu,
                           energy ? NULL : nominal, o->motion_tol, o->max_nodes, false};
    return energy;
}

/* Lemke's solution z moves: is it a solution that moves by the search's per-contact tolerances
 * too (so that rounding in a problem of very unequal parts is not taken for a motion)? acc
 * receives its motion. */
static bool lemke_motion_holds(const Work *w, const cnMotionProblem *p, const double *force,
                               const double *z, double *acc) {
    int K = w->K, Kf = w->Kf, D = w->D;
    double *lambda = cn_calloc((size_t)Kf + 1, sizeof(double));
    if (!lambda) return false;
    for (int f = 0; f < Kf; f++) lambda[f] = z[K + Kf * D + f] * w->m.g;
    bool holds = cn_motion_verify(p, force, lambda, acc) == 1;
    cn_free(lambda);
    return holds;
}

/* Corner contacts carrying at most this fraction of the reference weight (normal force and
 * friction) are idle in a static field: leaving them out changes its equilibrium by less than
 * a millionth of what the LP's verification accepts (CN_LP_EQ_TOL). */
#define CN_CORNER_IDLE 1e-13

/* Does a field of normal forces (absolute units, one per contact) leave every corner contact
 * idle? */
static bool field_leaves_corners(const Work *w, const double *force) {
    double cap = CN_CORNER_IDLE * w->m.wref;
    for (int i = 0; i < w->K; i++)
        if (w->r->contacts.items[i].corner && !(fabs(force[i]) <= cap)) return false;
    return true;
}

/* The frictionless certificate of prove_still from the frictionless contact LCP instead of the
 * equilibrium LP, for up to CN_PIVOT_MAX_AUTO contacts (principal pivoting, microseconds where
 * the LP takes a millisecond): a solution z >= 0 is a force field, and the bound of
 * cn_motion_frictionless_bound holds for any force field >= 0; where nothing moves without
 * friction its residual is rounding, and the bound proves that nothing moves with friction
 * either. False (the LP is tried) when the LCP is not solved or its solution moves. *idle: the
 * proving field leaves every corner contact idle. */
static bool frictionless_lcp_proves(Work *w, const cnMotionProblem *p, bool *idle) {
    int K = w->K;
    *idle = false;
    if (K == 0 || K > CN_PIVOT_MAX_AUTO) return false;
    cnLcp lcp;
    memset(&lcp, 0, sizeof lcp);
    double *d = cn_malloc(sizeof(double) * (size_t)K * 4);
    if (!d || build_lcp(w, K, false, &lcp, d) != CN_OK) {
        cn_free(d);
        cn_lcp_free(&lcp);
        return false;
    }
    double *z = d + K, *wv = d + 2 * K, *force = d + 3 * K;
    cnLcpInfo info;
    bool proved = false;
    if (cn_lcp_pivot(&lcp, &w->o->lcp, z, wv, &info) == CN_LCP_SOLVED) {
        for (int i = 0; i < K; i++) force[i] = fmax(z[i] * d[i], 0) * w->m.wref;
        cn_motion_frictionless_bound(p, force, &proved);
        *idle = proved && field_leaves_corners(w, force);
    }
    cn_lcp_free(&lcp);
    cn_free(d);
    return proved;
}

/* What an undecided search left open (r->open_speed, part[].unsettled): |a|_M^2 <= power bounds
 * every body's speed by sqrt(power / mass), so the bound is over all bodies; the parts flagged
 * are those the open nodes' LP motions move (all of them without a bound, or a search). */
static void open_motions(const Work *w, const cnMotionStats *stats, cnCheckResult *r) {
    const cnMech *m = &w->m;
    bool bounded = stats->open_bodies && isfinite(stats->open_power);
    r->open_speed = bounded ? 0 : INFINITY;
    for (int b = 0; b < m->nb; b++) {
        bool open = !bounded || stats->open_bodies[b];
        int part = m->part_of_body[b];
        if (open && part >= 0 && r->part) r->part[part].unsettled = true;
        if (bounded && m->mass[b] > 0) r->open_speed = fmax(r->open_speed, sqrt(stats->open_power / m->mass[b]));
    }
}

/* A static solution exists: is there also a motion from rest? First the frictionless certificate
 * (cn_motion_frictionless_bound: a frictionless force field that balances gravity proves that
 * nothing can move, whatever the friction; only without nominal sliding), then the exact search
 * (cn_motion_search). *ans: NONE (r->proof: how), FOUND (force, acc: the motion) or UNDECIDED
 * (r->proof = CN_PROOF_UNDECIDED, r->search_undecided: why). */
static cnStatus prove_still(Work *w, const cnMotionProblem *p, bool energy, cnCheckResult *r,
                            double *force, double *acc, cnMotionAnswer *ans, cnDiag *diag) {
    int K = w->K, Kf = w->Kf, D = w->D;
    cnStatus st = CN_OK;
    *ans = CN_MOTION_UNDECIDED;
    bool idle = false;
    if (energy && frictionless_lcp_proves(w, p, &idle)) {
        *ans = CN_MOTION_NONE;
        r->proof = CN_PROOF_FRICTIONLESS;
        r->proof_corners_idle = idle;
        return CN_OK;
    }
    if (energy && w->nf_done) {
        if (w->nf_proved) {
            *ans = CN_MOTION_NONE;
            r->proof = CN_PROOF_FRICTIONLESS;
            r->proof_corners_idle = field_leaves_corners(w, w->lpforce);
        }
    } else if (energy) {
        double(*nffric)[3] = cn_calloc((size_t)K + 1, sizeof(double[3]));
        if (!nffric) return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
        bool feas = false, proved = false;
        double keep = w->lp_residual;
        const char *keep_method = w->lp_method;
        st = static_lp(w, true, &feas, force, nffric, diag);
        w->lp_residual = keep;
        w->lp_method = keep_method;
        cn_free(nffric);
        /* only a shortcut to a proof: an LP that cannot be decided proves nothing */
        if (st == CN_ERR_NUMERIC) st = CN_OK, feas = false;
        if (!st && feas) cn_motion_frictionless_bound(p, force, &proved);
        if (!st && proved) {
            *ans = CN_MOTION_NONE;
            r->proof = CN_PROOF_FRICTIONLESS;
            r->proof_corners_idle = field_leaves_corners(w, force);
        }
    }
    int npairs = K + Kf * D + Kf;
    if (!st && *ans == CN_MOTION_UNDECIDED) {
        cnMotionStats stats;
        memset(&stats, 0, sizeof stats);
        if (npairs > CN_MOTION_MAX_PAIRS) {
            stats.why = "the LCP is too large for the search";
        } else {
            stats.open_bodies = cn_calloc((size_t)w->m.nb + 1, 1);
            if (!stats.open_bodies) return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
            /* along a path: the same problem as an earlier sample's is decided as it was */
            cnWarmStart *ws = w->o->warm && !w->o->warm->record_only ? w->o->warm : NULL;
            if (!(ws && cn_proof_memo_find(ws->proofs, p, ans, &stats))) {
                st = cn_motion_search(p, ans, force, acc, &stats, diag);
                if (!st && ws && !cn_proof_memo_keep(&ws->proofs, p, *ans, &stats)) {
                    cn_free(stats.open_bodies);
                    return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
                }
            }
            r->search_nodes = stats.nodes;
        }
        if (!st && *ans == CN_MOTION_NONE) r->proof = CN_PROOF_SEARCH;
        if (!st && *ans == CN_MOTION_UNDECIDED) {
            r->search_undecided = stats.why ? stats.why : "unknown";
            r->proof = CN_PROOF_UNDECIDED;
            open_motions(w, &stats, r);
        }
        cn_free(stats.open_bodies);
    }
    return st;
}

/* The friction vector of each contact (on body2) from the pyramid forces of force. */
static void friction_vectors(const Work *w, const double *force, double (*fric)[3]) {
    int K = w->K, D = w->D;
    for (int f = 0; f < w->Kf; f++)
        for (int d = 0; d < D; d++)
            for (int k = 0; k < 3; k++)
                fric[w->contact_of_fric[f]][k] += force[K + f * D + d] * w->dirs[f * D + d][k];
}

/* Memory of the dense contact LCP of n unknowns (M and its factors: 16 bytes an entry). */
static double dense_bytes(int n) {
    return 16.0 * (double)n * (double)n;
}

/* Unstable with the LP's certificate as the motion (the LCP was not solved: why). */
static void mechanism_result(Work *w, cnCheckResult *r, const char *why, double *force,
                             double (*fric)[3], double *acc, double motion_tol) {
    memset(force, 0, sizeof(double) * (size_t)(w->K + w->Kf * w->D));
    memset(fric, 0, sizeof(double[3]) * (size_t)w->K);
    cert_motion(w, acc);
    r->verdict = CN_VERDICT_UNSTABLE;
    r->stable = false;
    r->mechanism = why ? why : "not solved";
    r->solver = "none";
    fill_result(w, r, force, (const double(*)[3])fric, acc, motion_tol);
}

/* ---- cn_check, stage by stage ---- */

static cnStatus out_of_memory(Work *w) { return cn_diag_set(w->diag, CN_ERR_MEMORY, "", "out of memory"); }

/* Contacts from the geometry, and the mechanics over them. *finished: an overlap decided it. */
static cnStatus meet_contacts(Work *w, bool *finished) {
    const cnAssembly *a = w->a;
    cnCheckResult *r = w->r;
    *finished = false;
    cnOverlap ov;
    cnStatus st = cn_contacts_find(a, w->o->query, &r->contacts, &ov, w->diag);
    if (st) return st;
    int kept = 0;
    /* the reading: corner contact j takes end d_j of its cone, the digits of reading / 2 in the
     * mixed radix of the cones' ends (the first contact the lowest digit), each digit reversed
     * (n - 1 - d) in an odd reading; with two ends per cone, bit j of reading / 2, complemented
     * in an odd reading */
    unsigned long long digits = w->reading.index / 2;
    w->readings = 1;
    w->readings_log2 = 0;
    /* the index of the reading taken, as a plan of ends read as digits (even), or, when that
     * is past the last index, as their reverse (odd) */
    unsigned long long shown = 0, rshown = 0, place = 1;
    bool shown_ok = true;
    /* corners that the faces of their pair imply at their point: no reading of them changes
     * anything, and each would double the readings (compas_cra's bridge section: 6 of 10) */
    unsigned char *implied = cn_calloc((size_t)r->contacts.count + 1, 1);
    if (!implied) return out_of_memory(w);
    for (int c = 0; c < r->contacts.count; c++)
        implied[c] = cn_contact_corner_implied(a, &r->contacts, c);
    r->corners_implied = 0;
    for (int c = 0; c < r->contacts.count; c++) {
        cnContact *ct = &r->contacts.items[c];
        if (implied[c]) {
            r->corners_implied++;
            continue;
        }
        if (ct->corner) {
            int n = ct->corner_ends >= 2 ? ct->corner_ends : 2, e = (int)(digits % (unsigned)n);
            digits /= (unsigned)n;
            if (w->reading.index & 1) e = n - 1 - e;
            if (w->reading.one >= 0) e = w->ncorners == w->reading.one && w->reading.end < n ? w->reading.end : 0;
            if (e > 0) {
                double t[3], *end = cn_contact_end(ct, e);
                cn_copy3(t, ct->normal);
                cn_copy3(ct->normal, end);
                cn_copy3(end, t);
            }
            if (place > ULLONG_MAX / (unsigned)n) shown_ok = false;
            else {
                shown += place * (unsigned)e, rshown += place * (unsigned)(n - 1 - e);
                place *= (unsigned)n;
            }
            w->ncorners++;
            w->readings *= n;
            w->readings_log2 += log2(n);
            if (ct->corner_wide) w->corners_wide = true;
            if (w->drop_corners) continue;
        }
        r->contacts.items[kept++] = *ct;
    }
    cn_free(implied);
    r->corner_reading_moves = -1;
    r->corner_reading = w->ncorners == 0 || !shown_ok ? -1
                        : 2 * (double)shown < w->readings ? (long long)(2 * shown)
                                                          : (long long)(2 * rshown + 1);
    r->contacts.count = kept;
    if (w->o->one_reading && !(w->o->reading < w->readings)) {
        if (w->ncorners == 0)
            return cn_diag_set(w->diag, CN_ERR_INPUT, "",
                               "there is no reading %llu: no parts touch corner to corner, so the only reading is 0",
                               w->o->reading);
        return cn_diag_set(w->diag, CN_ERR_INPUT, "",
                           "there is no reading %llu of the corner contacts' normals: there are %.0f, numbered 0 "
                           "to %.0f",
                           w->o->reading, w->readings, w->readings - 1);
    }
    if (ov.found && w->o->overlap_is_result) {
        r->infeasible = true;
        r->overlap = ov;
        *finished = true;
        return CN_OK;
    }
    if (ov.found)
        return cn_diag_set(w->diag, CN_ERR_INPUT, "", "parts '%s' and '%s' overlap by %.6g (tolerance %.3g)",
                           a->parts[ov.part1].name, a->parts[ov.part2].name, ov.depth, ov.tol);
    st = cn_mech_build(a, w->o->query, w->o->motion, &w->m, w->diag);
    if (st) return st;
    r->ref_weight = w->m.wref;
    r->ref_part = w->m.ref_part;
    int K = w->K = r->contacts.count, nb = w->m.nb, nd = w->m.nd;
    w->D = a->friction_dirs;
    w->fric_of = cn_malloc(sizeof(int) * (size_t)(K + 1));
    w->contact_of_fric = cn_malloc(sizeof(int) * (size_t)(K + 1));
    w->mu = cn_malloc(sizeof(double) * (size_t)(K + 1));
    w->nominal = cn_calloc((size_t)K + 1, sizeof(int));
    w->slide = cn_calloc((size_t)K + 1, sizeof(double[3]));
    r->contact = cn_calloc((size_t)K + 1, sizeof(cnContactResult));
    r->part = cn_calloc((size_t)a->nparts, sizeof(cnPartMotion));
    r->moving = cn_calloc((size_t)a->nparts, sizeof(int));
    w->acc = cn_calloc((size_t)nb * nd + 1, sizeof(double));
    w->fric = cn_calloc((size_t)K + 1, sizeof(double[3]));
    w->lpfric = cn_calloc((size_t)K + 1, sizeof(double[3]));
    if (!w->fric_of || !w->contact_of_fric || !w->mu || !w->nominal || !w->slide || !r->contact ||
        !r->part || !r->moving || !w->acc || !w->fric || !w->lpfric)
        return out_of_memory(w);
    return CN_OK;
}

/* A contact closing under the nominal motion: a moving part driven into a part that does not
 * move makes the path collide (recorded in r->overlap when overlaps are results). */
static void closing_contact(Work *w, const cnContact *ct, double vn) {
    const cnCheckOptions *o = w->o;
    cnCheckResult *r = w->r;
    int still = -1, mover = -1;
    int ends[2] = {ct->body1, ct->body2};
    for (int s2 = 0; s2 < 2; s2++) {
        int p = ends[s2];
        if (p < 0) continue;
        int role = (o->motion && o->motion->role) ? o->motion->role[p] : CN_ROLE_FREE;
        if (role == CN_ROLE_FREE && !w->a->parts[p].fixed) still = p;
        else if (role == CN_ROLE_FREE || role == CN_ROLE_STILL) still = still < 0 ? p : still;
        else mover = p;
    }
    if (still >= 0 && mover >= 0 && o->overlap_is_result && !r->infeasible) {
        r->infeasible = true;
        r->overlap.found = 1;
        r->overlap.part1 = mover;
        r->overlap.part2 = still;
        /* negative depth: the distance still to travel along the motion before the surfaces
         * meet (the contact is within the tolerance, not yet closed) */
        double speed = o->motion ? o->motion->speed : 0;
        r->overlap.depth = speed > 0 ? -fmax(ct->gap, 0) * speed / fabs(vn) : 0;
    }
}

/* A contact between a held part and a free one (not fixed): the held part's weight is the
 * gripper's, so it need not press the free part (Proposition 2). */
static bool held_meets_free(const Work *w, const cnContact *ct) {
    const cnMotion *mo = w->o->motion;
    if (!mo || !mo->role || ct->body1 < 0 || ct->body2 < 0) return false;
    int r1 = mo->role[ct->body1], r2 = mo->role[ct->body2];
    bool free1 = r1 == CN_ROLE_FREE && !w->a->parts[ct->body1].fixed;
    bool free2 = r2 == CN_ROLE_FREE && !w->a->parts[ct->body2].fixed;
    return (r1 == CN_ROLE_HELD && free2) || (r2 == CN_ROLE_HELD && free1);
}

/* How the nominal motion meets each contact: opens, closes, slides or sticks. Contacts that
 * open are not contacts an instant later (Baraff: only contacts at zero relative normal
 * velocity enter the problem), so they leave the set. A part driven into a free part makes that
 * part move: an instability, decided here. A contact closing onto a fixed or kinematic part is
 * left to the overlap test of the next instant. */
static void classify_nominal(Work *w) {
    cnCheckResult *r = w->r;
    int nkept = 0;
    for (int c = 0; c < w->K; c++) {
        const cnContact *ct = &r->contacts.items[c];
        double vn = cn_mech_nominal(&w->m, ct->body1, ct->body2, ct->point, ct->normal);
        double vt[3];
        for (int k = 0; k < 3; k++) {
            double e[3] = {0, 0, 0};
            e[k] = 1;
            vt[k] = cn_mech_nominal(&w->m, ct->body1, ct->body2, ct->point, e) - vn * ct->normal[k];
        }
        double vx[3] = {0, 0, 0}; /* the moved parts' velocity here */
        double turn = 0;          /* ... and what a turn gives across the assembly */
        if (w->o->motion) {
            cn_twist_at(&w->o->motion->twist, ct->point, vx);
            turn = cn_norm3(w->o->motion->twist.w) * w->a->length_scale;
        }
        double tol = CN_NOMINAL_TOL * (cn_norm3(vx) + turn + w->m.g * w->dt);
        int nom = NOM_STICK;
        if (vn > tol) nom = NOM_OPEN;
        else if (vn < -tol) nom = NOM_CLOSE;
        else if (cn_norm3(vt) > tol) nom = NOM_SLIDE;
        if (nom == NOM_OPEN) continue;
        if (nom == NOM_CLOSE) {
            closing_contact(w, ct, vn);
            continue;
        }
        if (w->held_unloaded && held_meets_free(w, ct)) {
            r->held_unloaded++;
            continue;
        }
        w->nominal[nkept] = nom;
        if (nom == NOM_SLIDE) {
            cn_copy3(w->slide[nkept], vt);
            cn_normalize3(w->slide[nkept]);
        }
        r->contacts.items[nkept++] = *ct;
    }
    r->contacts.count = w->K = nkept;
}

/* The friction contacts, the friction directions and the Jacobian rows (K normal, then D per
 * friction contact). */
static cnStatus build_rows(Work *w) {
    const cnAssembly *a = w->a;
    cnCheckResult *r = w->r;
    int K = w->K;
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &r->contacts.items[c];
        double mu = cn_assembly_mu(a, ct->body1, ct->body2);
        w->fric_of[c] = -1;
        if (mu > 0) {
            w->fric_of[c] = w->Kf;
            w->contact_of_fric[w->Kf] = c;
            w->mu[w->Kf] = mu;
            w->Kf++;
        }
    }
    int Kf = w->Kf, D = w->D;
    int nrows = w->nrows = K + Kf * D;
    w->rows = cn_calloc((size_t)nrows + 1, sizeof(cnJRow));
    w->dirs = cn_calloc((size_t)Kf * D + 1, sizeof(double[3]));
    w->force = cn_calloc((size_t)nrows + 1, sizeof(double));
    w->lpforce = cn_calloc((size_t)nrows + 1, sizeof(double));
    w->mforce = cn_calloc((size_t)nrows + 1, sizeof(double));
    w->nominal_rows = cn_calloc((size_t)Kf * D + 1, sizeof(double));
    if (!w->rows || !w->dirs || !w->force || !w->lpforce || !w->mforce || !w->nominal_rows)
        return out_of_memory(w);
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &r->contacts.items[c];
        cn_mech_row(&w->m, ct->body1, ct->body2, ct->point, ct->normal, &w->rows[c]);
        int f = w->fric_of[c];
        if (f < 0) continue;
        const double *prefer = w->nominal[c] == NOM_SLIDE ? w->slide[c] : a->gravity;
        friction_dirs(a, ct->normal, prefer, D, w->dirs + (size_t)f * D);
        for (int d = 0; d < D; d++)
            cn_mech_row(&w->m, ct->body1, ct->body2, ct->point, w->dirs[f * D + d], &w->rows[K + f * D + d]);
    }
    r->friction = Kf > 0;
    w->n = r->lcp_size = r->friction ? K + Kf * D + Kf : K;
    w->z = cn_calloc((size_t)w->n + 1, sizeof(double));
    w->wv = cn_calloc((size_t)w->n + 1, sizeof(double));
    w->dscale = cn_calloc((size_t)w->n + 1, sizeof(double));
    if (!w->z || !w->wv || !w->dscale) return out_of_memory(w);
    if (r->friction && w->o->solver == CN_SOLVER_PIVOT)
        return cn_diag_set(w->diag, CN_ERR_INPUT, "",
                           "the pivot solver handles frictionless assemblies only; use --solver lemke or auto");
    return CN_OK;
}

/* Frictionless, when the dense LCP was not solved (too large to hold, or its pivoting failed):
 * the same LCP as a convex QP (Gauss's principle), solved sparse and verified (cn_motion_qp).
 * The environment variable CAIRN_NO_SPARSE_QP (any value) skips it: the tests and benchmarks
 * compare the LP certificate's motion with it. */
static bool sparse_qp_allowed(const Work *w) {
    return !w->r->friction && cn_motion_qp_usable(&w->m) && !getenv("CAIRN_NO_SPARSE_QP");
}

static cnStatus sparse_frictionless(Work *w) {
    cnCheckResult *r = w->r;
    if (!sparse_qp_allowed(w)) return CN_OK;
    bool solved = false;
    double residual;
    if (w->cert_deferred && !w->qp_motion &&
        !(w->qp_motion = cn_malloc(sizeof(double) * (size_t)(w->m.nb * w->m.nd + 1))))
        return out_of_memory(w);
    cnStatus st = cn_motion_qp(&w->m, w->rows, w->K, w->o->lcp.tol, w->force, w->acc,
                               w->cert_deferred ? w->qp_motion : NULL, &solved, &residual, NULL, w->diag);
    if (st) return st;
    if (!solved) {
        w->qp_failed = true;
        return CN_OK;
    }
    for (int i = 0; i < w->K; i++) w->z[i] = w->force[i] / w->m.wref;
    w->ls = CN_LCP_SOLVED;
    memset(&w->info, 0, sizeof w->info);
    w->info.residual = residual;
    r->solver = "interior point";
    return CN_OK;
}

static bool lp_still(Work *w);

/* With friction, large, and no nominal sliding: the frictionless equilibrium LP before the
 * friction one. Its force field, if any, is a static solution with friction too (friction zero)
 * and, through cn_motion_frictionless_bound, usually the proof that nothing moves, which
 * prove_still would seek with the same LP anyway. The friction LP (D + 1 columns a contact
 * instead of one, with cone rows) then runs only when no frictionless field exists. */
static cnStatus frictionless_first(Work *w) {
    cnMotionProblem mp;
    if (!motion_problem(w, w->o, w->nominal_rows, &mp)) return CN_OK;
    bool feas = false, proved = false;
    /* no field: the friction LP decides, so the frictionless one's certificate (a second
     * interior point) and GLPK's slow fallbacks (minutes on a vault of 10,000) are not wanted */
    w->field_only = true;
    cnStatus st = static_lp(w, true, &feas, w->lpforce, w->lpfric, w->diag);
    w->field_only = false;
    if (st == CN_ERR_NUMERIC) return CN_OK; /* proves nothing: the friction LP decides */
    if (st) return st;
    w->nf_done = true;
    if (!feas) return CN_OK;
    cn_motion_frictionless_bound(&mp, w->lpforce, &proved);
    w->nf_proved = proved;
    w->lp_done = w->lp_feasible = w->lp_trusted = true;
    return CN_OK;
}

/* The contact LCP (paper eq. 3 or 5), and the equilibrium LP where it is needed. For large LCPs
 * the LP runs first: a verified solution is a certificate of stability and an LCP solution
 * itself (see decide_*), so dense Lemke is skipped; the LCP is still solved whenever the
 * assembly is unstable, for the motion that starts (and, frictionless, as the cross-check of
 * the verdict). Frictionless and large, only the LP's load descent runs first: when it finds no
 * field, the sparse QP comes before the LP's interior point, whose work a moving QP answer
 * (the LP's certificate then) saves. */
static cnStatus solve_models(Work *w) {
    cnCheckResult *r = w->r;
    const cnCheckOptions *o = w->o;
    int n = w->n;
    cnStatus st;
    bool lp_first = n > (r->friction ? CN_LCP_LP_FIRST : CN_LCP_LP_FIRST_FRICTIONLESS);
    /* frictionless and large: the sparse QP before the dense LCP */
    bool sparse_first = !r->friction && n >= CN_QP_FIRST;
    if (lp_first && r->friction && (st = frictionless_first(w))) return st;
    if (lp_first && !w->lp_done) {
        /* when the sparse QP follows, the LP's interior point waits for it (after the descent): a
           moving answer of the QP is the LP's certificate too (below, need_lp), and a static
           one is cross-checked by the LP as the dense LCP's is */
        w->defer_cert = sparse_first && sparse_qp_allowed(w);
        st = static_lp(w, false, &w->lp_feasible, w->lpforce, w->lpfric, w->diag);
        w->defer_cert = false;
        if (st) return st;
        w->lp_done = !w->cert_deferred;
        /* frictionless, its static solution decides only when its forces keep every part still
           (lp_still): else the LCP decides, with the LP as its cross-check */
        w->lp_trusted = w->lp_feasible && (r->friction || lp_still(w));
    }
    memset(&w->info, 0, sizeof w->info);
    w->ls = CN_LCP_NUMERIC;
    if (n == 0) w->ls = CN_LCP_SOLVED, r->solver = "none";
    else if (!w->lp_trusted) {
        double bytes = dense_bytes(n);
        bool dense = bytes <= CN_DENSE_LCP_MAX_BYTES;
        if (sparse_first && (st = sparse_frictionless(w))) return st;
        if (w->cert_deferred && w->ls != CN_LCP_SOLVED) {
            /* the QP gave no verified answer: the LP in full now, before the dense LCP, so that
               its static field decides alone (as when it ran first) and its certificate cuts
               Lemke's retries short */
            w->cert_resumed = true;
            st = static_lp(w, false, &w->lp_feasible, w->lpforce, w->lpfric, w->diag);
            w->cert_resumed = false;
            if (st) return st;
            w->lp_done = true;
            w->lp_trusted = w->lp_feasible && lp_still(w);
        }
        if (dense && w->ls != CN_LCP_SOLVED && !w->lp_trusted) {
            if (build_lcp(w, n, r->friction, &w->lcp, w->dscale) != CN_OK) return out_of_memory(w);
            /* with the LP's certificate in hand the verdict is made: a long Lemke path that
               fails is not retried (its motion is only a better one than the certificate's) */
            cnLcpOptions lo = o->lcp;
            lo.short_retries = w->lp_done && w->has_cert;
            w->ls = warm_solve(o->warm, &r->contacts, w->fric_of, w->Kf, w->D, &w->lcp, o->solver,
                               !r->friction, &lo, w->z, w->wv, &w->info, &r->solver);
            for (int i = 0; i < n; i++) w->z[i] *= w->dscale[i], w->wv[i] /= w->dscale[i];
            w->lcp_why = cn_lcp_status_name(w->ls);
        }
        if (!sparse_first && w->ls != CN_LCP_SOLVED && (st = sparse_frictionless(w))) return st;
        if (w->ls == CN_LCP_SOLVED || dense || w->lp_trusted) {
            /* solved, or left to the verdict's stage (the certificate, or no verdict) */
        } else if (w->lp_done && w->has_cert) {
            /* the certificate gives the motion */
            w->lcp_why = w->qp_failed ? "too large for a dense LCP, and the sparse QP's answer did not verify"
                                      : "too large for a dense LCP";
        } else {
            return cn_diag_set(w->diag, CN_ERR_NUMERIC, "",
                               "%s; the contact LCP that would say how it moves has %d unknowns "
                               "and needs %.1f GiB as a dense problem, more than the %.0f GiB "
                               "limit%s, so no motion is computed; no verdict",
                               w->lp_done ? "the equilibrium LP finds no static solution" : "the assembly is large",
                               n, bytes / (1 << 30), CN_DENSE_LCP_MAX_BYTES / (1 << 30),
                               w->qp_failed ? ", and the sparse QP's answer did not verify" : "");
        }
    }
    r->pivots = w->info.pivots;
    r->residual = w->info.residual;
    w->lcp_ok = w->ls == CN_LCP_SOLVED;
    if (w->lcp_ok) {
        for (int i = 0; i < w->nrows; i++) w->force[i] = w->z[i] * w->m.wref;
        if (r->friction) friction_vectors(w, w->force, w->fric);
        cn_mech_response(&w->m, w->rows, r->friction ? w->nrows : w->K, w->force, w->acc);
        w->lcp_static = true;
        for (int b = 0; b < w->m.nb; b++)
            if (cn_mech_moves(&w->m, b, w->acc, o->motion_tol)) w->lcp_static = false;
    }
    /* With friction a static LCP solution already decides (stable), and the LP is needed only
     * when the LCP's solution moves (another solution may be static). Frictionless, the LP is
     * the cross-check of the LCP's verdict, and decides a motion that only a squeeze carries. */
    w->squeezed = false;
    if (w->lcp_ok && !r->friction && !w->lcp_static)
        for (int i = 0; i < w->K; i++)
            if (w->z[i] > CN_SQUEEZE_WEIGHTS) w->squeezed = true;
    bool need_lp = !w->lp_done &&
                   (!w->lcp_ok || (r->friction ? !w->lcp_static : o->lp_crosscheck || w->squeezed));
    if (need_lp) {
        /* still deferred here, the QP's answer verified (else the LP ran in full before the dense
           LCP): its motion, when it moves, is tried as the certificate first */
        w->cert_try = w->cert_deferred && !w->lcp_static ? w->qp_motion : NULL;
        w->cert_resumed = w->cert_deferred;
        st = static_lp(w, false, &w->lp_feasible, w->lpforce, w->lpfric, w->diag);
        w->cert_try = NULL;
        w->cert_resumed = false;
        if (st) return st;
    }
    r->lp_stable = (w->lp_done || need_lp) ? w->lp_feasible : w->lcp_static; /* skipped: implied */
    r->lp_method = (w->lp_done || need_lp) ? w->lp_method : NULL;
    return CN_OK;
}

/* Stable on the LP's solution: it keeps every part on its nominal motion; with v = v0 and
 * lambda at the sliding contacts' kinetic level it solves the same LCP, and static_lp()
 * verified the conditions (p >= 0, equilibrium, cones). */
static void stable_by_lp(Work *w) {
    cnCheckResult *r = w->r;
    r->residual = w->lp_residual;
    r->solver = "lp";
    memset(w->acc, 0, sizeof(double) * (size_t)w->m.nb * w->m.nd); /* no deviation anywhere */
    r->stable = true;
    r->verdict = CN_VERDICT_STABLE;
    fill_result(w, r, w->lpforce, (const double(*)[3])w->lpfric, w->acc, w->o->motion_tol);
}

/* The LP's static solution, read as the LCP's motion is read: do its forces leave every part
 * still at the motion tolerance? The LP accepts an equilibrium residual (CN_LP_EQ_TOL of the
 * weights) that, for a part whose mass sits near a far-reaching axis (a small inertia against its
 * size), is a turn above the tolerance: then the LP's "static" is not static. Frictionless. */
static bool lp_still(Work *w) {
    int nb = w->m.nb, nd = w->m.nd;
    double *acc = cn_malloc(sizeof(double) * (size_t)(nb * nd + 1));
    if (!acc) return false; /* cannot tell: not still */
    cn_mech_response(&w->m, w->rows, w->K, w->lpforce, acc);
    bool still = true;
    for (int b = 0; b < nb && still; b++)
        if (cn_mech_moves(&w->m, b, acc, w->o->motion_tol)) still = false;
    cn_free(acc);
    return still;
}

/* Frictionless: the LCP's solution is unique in its motion; the LP cross-checks it. */
static cnStatus decide_frictionless(Work *w) {
    cnCheckResult *r = w->r;
    const cnCheckOptions *o = w->o;
    /* a moving LCP solution against an LP solution whose own forces move the parts as well: the
     * two agree (unstable); a squeeze is decided by the LP only when its forces hold everything */
    bool lp_static = w->lp_feasible && (w->lcp_static || !w->lcp_ok || lp_still(w));
    /* without the LCP, the LP decides only with forces that keep every part still */
    bool lp_holds = w->lp_feasible && (w->lp_trusted || lp_still(w));
    if (w->lp_trusted || (!w->lcp_ok && lp_holds) || (w->squeezed && lp_static)) {
        stable_by_lp(w);
    } else if (!w->lcp_ok && w->has_cert) {
        mechanism_result(w, r, w->lcp_why, w->force, w->fric, w->acc, o->motion_tol);
    } else if (!w->lcp_ok) {
        return cn_diag_set(w->diag, CN_ERR_NUMERIC, "",
                           "the frictionless contact LCP (%d contacts) was not solved: %s after "
                           "%d pivots, and %s; no verdict",
                           w->n, cn_lcp_status_name(w->ls), w->info.pivots,
                           w->lp_feasible ? "the equilibrium LP's static solution leaves a part moving "
                                            "above the motion tolerance (its residual)"
                                          : "no static solution exists");
    } else if (o->lp_crosscheck && lp_static != w->lcp_static) {
        char why[160];
        return cn_diag_set(w->diag, CN_ERR_NUMERIC, "",
                           "the LCP says %s but the equilibrium LP says %s: %s; no verdict",
                           w->lcp_static ? "stable" : "unstable", lp_static ? "stable" : "unstable",
                           mass_span(w, why, sizeof why)[0] ? why + 2
                                                           : "the assembly is within numerical tolerance of a tipping threshold");
    } else {
        r->stable = w->lcp_static;
        r->verdict = w->lcp_static ? CN_VERDICT_STABLE : CN_VERDICT_UNSTABLE;
        fill_result(w, r, w->force, (const double(*)[3])w->fric, w->acc, o->motion_tol);
    }
    return CN_OK;
}

/* With friction and no static solution: unstable, with the LCP's motion or, without it, the
 * LP's certificate (a mechanism). (Measured: the search for a moving LCP solution, 500 LPs,
 * found none on the random stacks where Lemke ends on a secondary ray.) */
static cnStatus decide_friction_unstable(Work *w) {
    cnCheckResult *r = w->r;
    if (w->lcp_ok) {
        r->verdict = CN_VERDICT_UNSTABLE;
        fill_result(w, r, w->force, (const double(*)[3])w->fric, w->acc, w->o->motion_tol);
    } else if (w->has_cert) {
        mechanism_result(w, r, w->lcp_why, w->force, w->fric, w->acc, w->o->motion_tol);
    } else {
        return cn_diag_set(w->diag, CN_ERR_NUMERIC, "",
                           "no static solution exists (LP), but the friction LCP (n = %d) was "
                           "not solved (%s), so the motion is unknown; no verdict",
                           w->n, cn_lcp_status_name(w->ls));
    }
    return CN_OK;
}

/* With friction and a static solution: stable only if no solution from rest moves (strong
 * stability). Its forces are reported either way: they are the squeeze a not-guaranteed
 * assembly needs. */
static cnStatus decide_friction_static(Work *w) {
    cnCheckResult *r = w->r;
    const cnCheckOptions *o = w->o;
    size_t nacc = sizeof(double) * (size_t)w->m.nb * w->m.nd;
    const double *sforce = w->lcp_static ? w->force : w->lpforce;
    const double(*sfric)[3] = (const double(*)[3])(w->lcp_static ? w->fric : w->lpfric);
    if (!w->lcp_static) r->residual = w->lp_residual, r->solver = "lp";
    if (o->accept_prestress) {
        r->verdict = CN_VERDICT_STABLE;
        r->proof = CN_PROOF_ACCEPTED;
        memset(w->acc, 0, nacc);
    } else {
        cnMotionProblem mp;
        bool energy = motion_problem(w, o, w->nominal_rows, &mp);
        if (w->lcp_ok && !w->lcp_static && lemke_motion_holds(w, &mp, w->force, w->z, w->acc)) {
            r->verdict = CN_VERDICT_NOT_GUARANTEED; /* the LCP's own solution moves */
        } else {
            cnMotionAnswer ans;
            cnStatus st = prove_still(w, &mp, energy, r, w->mforce, w->acc, &ans, w->diag);
            if (st) return st;
            if (ans == CN_MOTION_FOUND) r->verdict = CN_VERDICT_NOT_GUARANTEED;
            else memset(w->acc, 0, nacc);
            if (ans == CN_MOTION_UNDECIDED) r->verdict = CN_VERDICT_UNDECIDED;
        }
    }
    r->stable = r->verdict == CN_VERDICT_STABLE;
    fill_result(w, r, sforce, sfric, w->acc, o->motion_tol);
    return CN_OK;
}

static cnStatus check_stages(Work *w) {
    bool finished;
    cnStatus st = meet_contacts(w, &finished);
    if (st || finished) return st;
    classify_nominal(w);
    if (w->r->infeasible) return CN_OK; /* a collision: nothing to solve */
    if ((st = build_rows(w)) || (st = solve_models(w))) return st;
    if (!w->r->friction) return decide_frictionless(w);
    if (!w->lcp_static && !w->lp_feasible) return decide_friction_unstable(w);
    return decide_friction_static(w);
}

/* One reading of the corner contacts' normals (reading, as meet_contacts reads it; drop:
 * without them), as cn_check documents for the whole check (its LCP kept on failure too, though
 * cn_check frees a later reading's); *ncorners: how many corner contacts the assembly has (their
 * readings in r->corner_readings_all and _log2, r->corners_wide). */
static cnStatus check_reading(const cnAssembly *a, const cnCheckOptions *opt, cnCheckResult *r,
                              cnDiag *diag, Reading reading, bool drop, bool unload, int *ncorners) {
    cnCheckOptions o = *opt;
    memset(r, 0, sizeof *r);
    r->ref_part = -1;
    Work w;
    memset(&w, 0, sizeof w);
    w.a = a;
    w.o = &o;
    w.r = r;
    w.diag = diag;
    w.reading = reading;
    w.drop_corners = drop;
    w.held_unloaded = unload;
    w.cs = &r->contacts;
    w.dt = (o.motion && o.motion->dt > 0) ? o.motion->dt : 1.0;
    cnStatus st = check_stages(&w);
    if (!st && o.keep_lcp && w.n > 0 && dense_bytes(w.n) <= CN_DENSE_LCP_MAX_BYTES &&
        w.lcp.n != w.n) {
        cn_lcp_free(&w.lcp);
        if (build_lcp(&w, w.n, r->friction, &w.lcp, w.dscale) != CN_OK) st = out_of_memory(&w);
    }
    /* keep the LCP when asked, on failure too: that is when it is most wanted */
    cnLcp kept = {0};
    if (o.keep_lcp && (st ? w.lcp.n > 0 : dense_bytes(w.n) <= CN_DENSE_LCP_MAX_BYTES)) {
        kept = w.lcp;
        memset(&w.lcp, 0, sizeof w.lcp);
    }
    if (st) cn_check_result_free(r);
    r->lcp = kept;
    *ncorners = w.ncorners;
    r->corner_readings_all = w.readings;
    r->corner_readings_log2 = w.readings_log2;
    r->corners_wide = w.corners_wide;
    work_free(&w);
    return st;
}

static bool has_static(cnVerdict v) { return v != CN_VERDICT_UNSTABLE; }
static bool has_motion(cnVerdict v) {
    return v == CN_VERDICT_UNSTABLE || v == CN_VERDICT_NOT_GUARANTEED;
}

/* A reading that stands (stat) and one that moves (mov): not guaranteed, with the static
 * solution's forces and the motion the other reading admits (contacts matched by id; a contact
 * the moving reading does not have opened). stat takes mov's motion; mov is left to be freed. */
static void merge_readings(const cnAssembly *a, cnCheckResult *stat, cnCheckResult *mov) {
    stat->verdict = CN_VERDICT_NOT_GUARANTEED;
    stat->stable = false;
    stat->corners_disagree = true;
    stat->corner_reading_moves = mov->corner_reading;
    stat->proof = CN_PROOF_NONE;
    stat->search_undecided = NULL;
    memcpy(stat->part, mov->part, sizeof(cnPartMotion) * (size_t)a->nparts);
    memcpy(stat->moving, mov->moving, sizeof(int) * (size_t)a->nparts);
    stat->nmoving = mov->nmoving;
    for (int c = 0; c < stat->contacts.count; c++) {
        cnContactResult *x = &stat->contact[c];
        x->separates = true, x->slides = false;
        for (int d = 0; d < mov->contacts.count; d++)
            if (mov->contacts.items[d].id == stat->contacts.items[c].id) {
                x->separates = mov->contact[d].separates;
                x->slides = mov->contact[d].slides;
                x->separation = mov->contact[d].separation;
                x->slip = mov->contact[d].slip;
            }
    }
}

/* Is the first reading's stable verdict one of every reading? Its static solution (the forces
 * reported) must put no force on a corner contact: it is then a static solution of every
 * reading. That decides it frictionless, and with --accept-prestress (weak stability); with
 * friction the proof that nothing moves must hold in every reading too: a frictionless field
 * that leaves the corner contacts idle (the check without them would look for one). */
static bool corners_idle(const cnCheckResult *r, const cnCheckOptions *o) {
    if (r->friction && !(r->proof == CN_PROOF_FRICTIONLESS && r->proof_corners_idle) &&
        !(o->accept_prestress && r->proof == CN_PROOF_ACCEPTED))
        return false;
    double cap = CN_CORNER_IDLE * r->ref_weight;
    if (!(cap > 0)) return false;
    for (int i = 0; i < r->contacts.count; i++) {
        if (!r->contacts.items[i].corner) continue;
        const cnContactResult *c = &r->contact[i];
        if (!(fabs(c->normal_force) <= cap) || !(cn_norm3(c->friction) <= cap)) return false;
    }
    return true;
}

/* With more readings than can be tried and a first reading that stands: the readings that
 * change one loaded corner contact (the first reading's force on it above CN_CORNER_IDLE times
 * the reference weight), the most loaded first, to each of its other ends in turn, up to
 * CN_CORNER_FLIPS of them. A corner that carries weight in the first reading is the likeliest
 * to let a part go when read another way, and one reading that moves makes the assembly not
 * guaranteed (a verdict) where the check would otherwise be undecided. Returns their number. */
typedef struct {
    double force;
    int corner, at; /* its number among the corner contacts, its index among the contacts */
} Loaded;

static int most_loaded_first(const void *pa, const void *pb) {
    const Loaded *a = pa, *b = pb;
    if (a->force != b->force) return (a->force < b->force) - (a->force > b->force);
    return (a->corner > b->corner) - (a->corner < b->corner);
}

static int loaded_flips(const cnCheckResult *r, Reading *out) {
    int nc = 0;
    for (int i = 0; i < r->contacts.count; i++) nc += r->contacts.items[i].corner;
    if (nc == 0 || !r->contact) return 0;
    Loaded *l = cn_malloc(sizeof(Loaded) * (size_t)nc);
    if (!l) return 0;
    int n = 0, j = 0, m = 0;
    double cap = CN_CORNER_IDLE * r->ref_weight;
    for (int i = 0; i < r->contacts.count; i++) {
        if (!r->contacts.items[i].corner) continue;
        double f = fabs(r->contact[i].normal_force);
        if (f > cap) l[n++] = (Loaded){f, j, i};
        j++;
    }
    qsort(l, (size_t)n, sizeof *l, most_loaded_first);
    for (int a = 0; a < n && m < CN_CORNER_FLIPS; a++) {
        int ends = r->contacts.items[l[a].at].corner_ends;
        for (int e = 1; e < (ends >= 2 ? ends : 2) && m < CN_CORNER_FLIPS; e++)
            out[m++] = (Reading){0, l[a].corner, e};
    }
    cn_free(l);
    return m;
}

/* The check with every reading of the corner contacts' normals (see cn_check); unload: without
 * the contacts of held parts with free ones. */
static cnStatus check_readings(const cnAssembly *a, const cnCheckOptions *opt, bool unload,
                               cnCheckResult *r, cnDiag *diag) {
    cnCheckOptions o = *opt;
    int k = 0;
    const Reading first = {o.one_reading ? o.reading : 0, -1, 0};
    cnStatus st = check_reading(a, &o, r, diag, first, false, unload, &k);
    if (!st && o.one_reading) {
        r->corners = k, r->corner_readings = k ? 1 : 0;
        return CN_OK;
    }
    if (st || k == 0 || r->infeasible || r->verdict == CN_VERDICT_NOT_GUARANTEED) {
        r->corners = k, r->corner_readings = k ? 1 : 0;
        return st;
    }
    /* the readings are tried in the order of their index i (meet_contacts): all ends as found,
     * all reversed, then each pattern and its reverse in turn, which covers every reading by
     * i < total (the reverse of pattern j is pattern total - 1 - j) */
    double total = r->corner_readings_all;
    /* every reading stands at once when a frictionless force field balances gravity without the
     * corner contacts: it is a static solution of each reading, and it bounds every motion from
     * rest of each (the contacts it uses are in all of them; see strong.c) */
    if (r->verdict == CN_VERDICT_STABLE && corners_idle(r, &o)) {
        /* the first reading's own field already leaves them idle: no second check (measured:
         * 10 layers of 10 x 10 boxes, whose diagonal neighbours touch edge on edge at 3,240
         * points, 0.9 s instead of 2.0) */
        r->corners = k, r->corner_readings = (long)fmin(total, 9.2e18);
        r->corners_by_field = true;
        return CN_OK;
    }
    if (r->verdict == CN_VERDICT_STABLE) {
        cnCheckResult dr;
        int kd;
        cnDiag quiet;
        if (check_reading(a, &o, &dr, &quiet, first, true, unload, &kd) == CN_OK) {
            /* with --accept-prestress (weak stability: a static solution is enough) any static
             * solution without the corner contacts is one of every reading, its corners idle */
            bool all = !dr.infeasible && dr.verdict == CN_VERDICT_STABLE &&
                       (!dr.friction || dr.proof == CN_PROOF_FRICTIONLESS ||
                        (o.accept_prestress && dr.proof == CN_PROOF_ACCEPTED));
            cn_check_result_free(&dr);
            if (all) {
                r->corners = k, r->corner_readings = (long)fmin(total, 9.2e18);
                r->corners_by_field = true;
                return CN_OK;
            }
        }
    }
    /* a corner on a corner: each reading of the cone ends is a possible contact; the assembly
     * stands only if every reading does (the first reading is r; stat and mov are the first
     * readings found standing and moving) */
    long nread = (long)fmin(total, (double)CN_CORNER_READINGS);
    /* Too many readings to decide them all: the verdict cannot be stable whatever they say (a
     * first reading that moves makes it unstable or not guaranteed, an undecided one leaves it
     * undecided unless another moves, a standing one leaves it undecided unless another moves).
     * Only the first reading and, when it stands, its complement are tried: each reading is a
     * whole check, and trying 64 made a 3-D barrel vault of 6 x 10 voussoirs (180 edges resting
     * on edges) take 20 s instead of 0.3 s, and compas_cra's Armadillo vault (8) 210 s instead
     * of 3 s. With at most log2(CN_CORNER_READINGS) corners every reading is decided. */
    if (total > CN_CORNER_READINGS) nread = r->verdict == CN_VERDICT_STABLE ? 2 : 1;
    Reading *plan = cn_malloc(sizeof(Reading) * (size_t)(nread + CN_CORNER_FLIPS));
    if (!plan) {
        cn_check_result_free(r);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
    }
    int nplan = 0;
    for (long i = 1; i < nread; i++) plan[nplan++] = (Reading){(unsigned long long)i, -1, 0};
    if (total > CN_CORNER_READINGS && r->verdict == CN_VERDICT_STABLE)
        nplan += loaded_flips(r, plan + nplan);
    cnCheckResult *stat = has_static(r->verdict) ? r : NULL, *mov = has_motion(r->verdict) ? r : NULL;
    cnCheckResult *undec = r->verdict == CN_VERDICT_UNDECIDED ? r : NULL;
    cnCheckResult more[3]; /* at most stat, mov and undec are kept */
    memset(more, 0, sizeof more);
    int used = 0;
    long i; /* readings tried, the first among them */
    for (i = 1; i <= nplan && !(stat && mov); i++) {
        cnCheckResult *x = &more[used];
        int k2;
        st = check_reading(a, &o, x, diag, plan[i - 1], false, unload, &k2);
        if (st) break;
        bool keep = false;
        if (x->infeasible) { /* a collision in one reading: the step fails */
            cn_check_result_free(r);
            *r = *x;
            memset(x, 0, sizeof *x);
            r->corners = k, r->corner_readings = i + 1;
            for (int u = 0; u < used; u++) cn_check_result_free(&more[u]);
            cn_free(plan);
            return CN_OK;
        }
        if (x->verdict == CN_VERDICT_NOT_GUARANTEED && !(stat && stat->verdict == CN_VERDICT_NOT_GUARANTEED)) {
            stat = mov = x, keep = true; /* both in one reading */
        } else {
            if (!stat && has_static(x->verdict)) stat = x, keep = true;
            if (!mov && has_motion(x->verdict)) mov = x, keep = true;
            if (!undec && x->verdict == CN_VERDICT_UNDECIDED) undec = x, keep = true;
        }
        if (keep) used++;
        else cn_check_result_free(x);
    }
    cn_free(plan);
    cnCheckResult *out = r;
    if (!st) {
        if (stat && mov && stat == mov) out = stat;
        else if (stat && mov) merge_readings(a, stat, mov), out = stat;
        else if (undec) out = undec;
        else if (!mov && i < total) { /* standing in every reading tried, not in all */
            r->verdict = CN_VERDICT_UNDECIDED;
            r->stable = false;
            r->proof = CN_PROOF_UNDECIDED;
            r->search_undecided = "too many corner-on-corner contacts to decide every reading of their normals";
            r->corners_undecided = true;
        } else if (!mov && r->corners_wide) { /* standing in every reading kept, not in all */
            r->verdict = CN_VERDICT_UNDECIDED;
            r->stable = false;
            r->proof = CN_PROOF_UNDECIDED;
            r->search_undecided = "a corner contact's cone of normals has more ends than cairn keeps";
            r->corners_undecided = true;
        }
        if (out != r) {
            cn_check_result_free(r);
            *r = *out;
            memset(out, 0, sizeof *out);
        }
        r->corners = k, r->corner_readings = i;
    }
    for (int u = 0; u < 3; u++) cn_check_result_free(&more[u]);
    if (st) cn_check_result_free(r);
    return st;
}

/* Does a part have the held role while another is free? Only then can a held part press one. */
static bool held_and_free(const cnAssembly *a, const cnCheckOptions *o) {
    if (!o->motion || !o->motion->role) return false;
    bool held = false, free_part = false;
    for (int p = 0; p < a->nparts; p++) {
        held |= o->motion->role[p] == CN_ROLE_HELD;
        free_part |= o->motion->role[p] == CN_ROLE_FREE && !a->parts[p].fixed;
    }
    return held && free_part;
}

cnStatus cn_check(const cnAssembly *a, const cnCheckOptions *opt, cnCheckResult *r, cnDiag *diag) {
    cnCheckOptions o = opt ? *opt : cn_check_options_default();
    if (o.motion_tol <= 0) o.motion_tol = CN_DEFAULT_MOTION_TOL;
    /* Proposition 2: a held part presses nothing. Without its contacts with free parts the rest
     * must stand by itself; when it does not (a free part leans or rests on the held one, or is
     * left undecided), the contacts are taken as any other. */
    if (held_and_free(a, &o)) {
        cnStatus st = check_readings(a, &o, true, r, diag);
        if (st || r->held_unloaded == 0 || r->infeasible || r->verdict == CN_VERDICT_STABLE) return st;
        cn_check_result_free(r);
    }
    cnStatus st = check_readings(a, &o, false, r, diag);
    if (!st) r->held_unloaded = 0;
    return st;
}
