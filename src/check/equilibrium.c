/* The equilibrium LP of a check: is there a static force field (frictionless, or within the
 * friction pyramids), verified; and when there is none, its verified Farkas certificate (a
 * virtual motion on which gravity does positive work against every contact force). */
#include "check_work.h"

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

/* LPs with more columns than this skip the slow fallbacks (the dual simplex, whose time grows
 * fastest with the size of the walls' LPs): their answer, when the first ways fail to verify,
 * is a numerical failure. */
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
const char *cn_ck_mass_span(const Work *w, char *buf, size_t cap) {
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
    return pw > CN_LP_CERT_POWER * most;
}

/* LPs with friction cones and at least this many columns try GLPK's interior-point method
 * before the simplex, after cairn's (with cone rows the simplex is the slower of the two on
 * large LPs; without them, the faster) */
#define CN_LP_INTERIOR_MIN_COLS 2000
/* LPs without cone rows (frictionless, or every friction contact sliding) of at least this many
 * columns are solved first by descent (load_descent: each body from the top down passes its
 * load to the contacts below it, in linear time), then by cairn's own interior-point method
 * (lp_ipm.c, on CHOLMOD), both verified like GLPK's answers; GLPK follows when they do not
 * verify (on the largest walls GLPK's primal simplex gives up and only its elastic LP answers).
 * LPs with friction cones skip the descent and go to cairn's interior point, then GLPK's: the
 * arches and vaults that reach the friction LP (walls and stacks stop at the frictionless
 * field) are where GLPK's interior point fails and its simplex is slow.
 * CN_ROUTE_LP_GLPK_ONLY in the options' route skips both: the benchmarks time both;
 * CN_ROUTE_NO_LOAD_DESCENT skips the descent alone: the tests reach the interior point with it. */
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
    cnLpMethod method;  /* the last method whose answer was verified or tried */
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
static bool lp_accept(Work *w, LpArrays *L, cnLpMethod method, double *worst) {
    double wk = lp_verify(w, L->cols, L->ncols, L->col_contact, L->col_dir, L->col_inq, L->col_inq_val,
                          L->colscale, L->rowscale, L->x, L->res);
    *worst = fmin(*worst, wk);
    L->method = method;
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
    if (lp->nineq != 0 || (w->o->route & CN_ROUTE_NO_LOAD_DESCENT)) return CN_OK;
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

/* A motion found elsewhere (the sparse QP's accelerations) as the LP's Farkas certificate:
 * y = -u * rowscale inverts lp_certificate's cert = -y / rowscale, and lp_certificate verifies
 * it as it verifies the solvers' duals. A frictionless motion that opens or keeps every contact
 * (J a >= 0) and on which gravity does work (Gauss's principle: f_ext . a = a^T M a > 0) is
 * one. */
static bool motion_certificate(Work *w, LpArrays *L, const cnLpProblem *lp, const double *u) {
    for (int i = 0; i < L->neq; i++) L->y[i] = -u[i] * L->rowscale[i];
    for (int i = L->neq; i < L->neq + L->ninq; i++) L->y[i] = 0;
    if (!lp_certificate(w, lp, L->y, L->rowscale, L->colscale)) return false;
    L->method = CN_LP_METHOD_QP_MOTION;
    return true;
}

/* The band about the whole assembly's balance, in units of the tolerance a field's rows are
 * verified to, within which a field of the LP could put it (whole_screen): a field's force rows
 * each within CN_LP_EQ_TOL of their body's weight put the whole's total force within that of
 * the total weight; its moments (the cross product counted twice) within twice that. A little
 * more, for the rounding of the sums. */
#define CN_LP_WHOLE_BAND 1.01
/* An entry of the whole's LP below this fraction of its column's largest is the sums' rounding. */
#define CN_LP_WHOLE_NOISE 1e-13

/* Whether the whole's LP t (nd equations, then cone rows) has no solution within each row's
 * band: CN_LP_WHOLE_BAND times CN_LP_EQ_TOL on the force rows (the first dim) and the cone rows,
 * twice that on the moment rows. Each equation becomes two inequalities scaled by its band, so
 * that GLPK's own feasibility tolerance (relative to a bound, about 1e-7) only widens the band:
 * its "infeasible" is the band's. Out of memory or undecided: nothing known (*absent false). */
static void whole_absent(const cnLpProblem *t, int dim, bool *absent) {
    int nd = t->neq, nin = t->nineq, n = t->nvars, nnz = t->colptr[n];
    *absent = false;
    int *cp = cn_malloc(sizeof(int) * (size_t)(n + 1)), *ri = cn_malloc(sizeof(int) * (size_t)(2 * nnz + 1));
    double *va = cn_malloc(sizeof(double) * (size_t)(2 * nnz + 1));
    double *rhs = cn_malloc(sizeof(double) * (size_t)(2 * nd + nin + 1)), *x = cn_malloc(sizeof(double) * (size_t)(n + 1));
    if (!cp || !ri || !va || !rhs || !x) {
        cn_free(cp), cn_free(ri), cn_free(va), cn_free(rhs), cn_free(x);
        return; /* nothing known */
    }
    int k = 0;
    for (int j = 0; j < n; j++) {
        cp[j] = k;
        for (int q = t->colptr[j]; q < t->colptr[j + 1]; q++) {
            int r = t->rows[q];
            if (r >= nd) {
                ri[k] = nd + r, va[k++] = t->vals[q]; /* a cone row, after the 2 nd */
                continue;
            }
            double band = CN_LP_WHOLE_BAND * CN_LP_EQ_TOL * (r < dim ? 1 : 2);
            ri[k] = 2 * r, va[k++] = t->vals[q] / band;
            ri[k] = 2 * r + 1, va[k++] = -t->vals[q] / band;
        }
    }
    cp[n] = k;
    for (int r = 0; r < nd; r++) {
        double band = CN_LP_WHOLE_BAND * CN_LP_EQ_TOL * (r < dim ? 1 : 2);
        rhs[2 * r] = t->rhs[r] / band - 1, rhs[2 * r + 1] = -t->rhs[r] / band - 1;
    }
    /* a field's cone rows are verified to CN_LP_EQ_TOL too (scaled units, as here) */
    for (int i = 0; i < nin; i++) rhs[2 * nd + i] = t->rhs[nd + i] - CN_LP_WHOLE_BAND * CN_LP_EQ_TOL;
    cnLpProblem b = {n, 0, 2 * nd + nin, cp, ri, va, rhs, NULL, false, CN_LP_DUAL_EQ, false, false};
    bool feas = true;
    cnDiag quiet;
    if (cn_lp_solve(&b, &feas, x, &quiet) == CN_OK) *absent = !feas;
    cn_free(cp), cn_free(ri), cn_free(va), cn_free(rhs), cn_free(x);
}

/* The equilibrium LP's rows summed into the whole assembly's (its total force, and its total
 * moment about the free bodies' centre of mass o), scaled by the total weight and by sum W_b
 * (r_b + |c_b - o|): R, with the columns that act on the whole (those of contacts with fixed
 * parts; a contact between two free bodies puts nothing on it) and their cone rows. A field
 * within CN_LP_EQ_TOL of every body would put the whole within CN_LP_EQ_TOL of balance in its
 * force rows and 2 CN_LP_EQ_TOL in its moment rows, so when no solution of this small LP (a
 * few rows and the supports' columns) comes that near (whole_absent), no field exists
 * (*absent). The duals of its elastic LP are then a rigid
 * motion of the whole that gravity drives and no support resists; R^T y is that motion as the
 * full LP's certificate, verified here as any other (*cert, w->cert). Bodies pushed by a
 * gripper: not tried. */
static void whole_screen(Work *w, LpArrays *L, const cnLpProblem *lp, bool want_cert, bool *absent, bool *cert) {
    const cnMech *m = &w->m;
    int nd = m->nd, dim = m->dim, nb = m->nb, neq = lp->neq;
    *absent = *cert = false;
    for (int b = 0; b < nb; b++)
        if (m->pushed[b]) return;
    double o[3] = {0, 0, 0}, mass = 0, fs = 0, ms = 0;
    for (int b = 0; b < nb; b++) {
        for (int k = 0; k < 3; k++) o[k] += m->mass[b] * m->com[b][k];
        mass += m->mass[b];
    }
    if (!(mass > 0)) return;
    for (int k = 0; k < 3; k++) o[k] /= mass;
    for (int b = 0; b < nb; b++) {
        double p[3] = {m->com[b][0] - o[0], m->com[b][1] - o[1], m->com[b][2] - o[2]};
        fs += L->rowscale[b * nd];
        ms += L->rowscale[b * nd + dim] + L->rowscale[b * nd] * cn_norm3(p);
    }
    /* out of memory anywhere below: nothing known, and the LP decides as without the screen */
    int nrow = nd, ncol = 0, k = 0;
    double *R = cn_calloc((size_t)nb * (size_t)nd * (size_t)nd, sizeof(double)); /* big row -> whole rows */
    int *inq = cn_malloc(sizeof(int) * (size_t)(lp->nineq + 1));
    int *cp = cn_malloc(sizeof(int) * (size_t)(L->ncols + 2));
    int *ri = cn_malloc(sizeof(int) * ((size_t)L->ncols * (size_t)(nd + 1) + 1));
    double *va = cn_malloc(sizeof(double) * ((size_t)L->ncols * (size_t)(nd + 1) + 1));
    double *rhs = cn_calloc((size_t)(nd + lp->nineq + 1), sizeof(double));
    double *x = cn_calloc((size_t)L->ncols + 1, sizeof(double)), *yt = NULL, *yb = NULL;
    if (!R || !inq || !cp || !ri || !va || !rhs || !x) goto done;
    for (int b = 0; b < nb; b++) {
        double p[3] = {m->com[b][0] - o[0], m->com[b][1] - o[1], m->com[b][2] - o[2]}, wb = L->rowscale[b * nd];
        for (int d = 0; d < dim; d++) {
            double *r = R + ((size_t)b * nd + d) * nd;
            r[d] = wb / fs;
            double e[3] = {0, 0, 0}, t[3];
            e[d] = 1;
            cn_cross3(p, e, t);
            if (dim == 2) r[2] = t[2] * wb / ms;
            else
                for (int h = 0; h < 3; h++) r[3 + h] = t[h] * wb / ms;
        }
        for (int h = dim; h < nd; h++) R[((size_t)b * nd + h) * nd + h] = L->rowscale[b * nd + h] / ms;
    }
    for (int i = 0; i <= lp->nineq; i++) inq[i] = -1;
    /* the columns on the whole: one side fixed (a contact between free bodies cancels exactly) */
    for (int j = 0; j < L->ncols; j++) {
        if ((L->cols[j].body[0] >= 0) == (L->cols[j].body[1] >= 0)) continue;
        cp[ncol++] = k;
        double t[6] = {0, 0, 0, 0, 0, 0}, big = 0;
        int ci = -1;
        double cv = 0;
        for (int q = lp->colptr[j]; q < lp->colptr[j + 1]; q++) {
            int r = lp->rows[q];
            if (r >= neq) {
                ci = r - neq, cv = lp->vals[q];
                continue;
            }
            for (int h = 0; h < nd; h++) t[h] += R[(size_t)r * nd + h] * lp->vals[q];
        }
        for (int h = 0; h < nd; h++) big = fmax(big, fabs(t[h]));
        /* the sums' rounding (a lever arm's 1e-17 where the moment is 0) left out */
        for (int h = 0; h < nd; h++)
            if (fabs(t[h]) > CN_LP_WHOLE_NOISE * big) ri[k] = h, va[k++] = t[h];
        if (ci >= 0) {
            if (inq[ci] < 0) inq[ci] = nrow++;
            ri[k] = inq[ci], va[k++] = cv;
        }
    }
    cp[ncol] = k;
    for (int r = 0; r < neq; r++)
        for (int h = 0; h < nd; h++) rhs[h] += R[(size_t)r * nd + h] * lp->rhs[r];
    if (ncol == 0) goto done;
    /* equilibration scaling: GLPK's automatic one is led astray by such noise (solve.h) */
    cnLpProblem t = {ncol, nd, nrow - nd, cp, ri, va, rhs, NULL, false, CN_LP_DUAL_EQ, false, false};
    whole_absent(&t, dim, absent);
    if (!*absent || !want_cert) goto done;
    yt = cn_calloc((size_t)nrow + 1, sizeof(double));
    yb = cn_calloc((size_t)(neq + lp->nineq) + 1, sizeof(double));
    cnDiag quiet;
    if (!yt || !yb || cn_lp_elastic(&t, x, yt, &quiet) != CN_OK) goto done; /* no duals: no certificate */
    for (int r = 0; r < neq; r++)
        for (int h = 0; h < nd; h++) yb[r] += R[(size_t)r * nd + h] * yt[h];
    for (int i = 0; i < lp->nineq; i++)
        if (inq[i] >= 0) yb[neq + i] = yt[inq[i]];
    if (lp_certificate(w, lp, yb, L->rowscale, L->colscale)) {
        *cert = true;
        L->method = CN_LP_METHOD_WHOLE;
    }
done:
    cn_free(R), cn_free(inq), cn_free(cp), cn_free(ri), cn_free(va), cn_free(rhs);
    cn_free(x), cn_free(yt), cn_free(yb);
}

/* Every answer is verified, and GLPK is run in several ways until one verifies: the
 * interior-point method for large LPs with friction (its solution, once verified, is as good a
 * certificate as a vertex); the primal simplex; the elastic LP, whose primal is the force field
 * closest to equilibrium and whose dual is a Farkas certificate (a virtual motion on which
 * gravity does work and no contact force resists), so that GLPK's claim that there is no
 * solution is believed only with a certificate that verifies; then, for LPs up to
 * CN_LP_FALLBACK_MAX_COLS, the dual simplex and the elastic LP with the other scaling. (GLPK's
 * exact rational simplex is not used here: its time has no useful bound on LPs of this size.)
 * Returns whether one verified; *worst: the best equilibrium residual found; *stop: the ask's
 * deferral or a field shown absent ended it; *internal (GLPK's count of internal errors when the
 * LP began) is moved past the whole assembly's screen's own. */
static bool lp_solve_verified(Work *w, const LpAsk *ask, LpArrays *L, double *worst,
                              LpOutcome *stop, long *internal, cnDiag *diag) {
    cnLpProblem lp = {L->ncols, L->neq, L->ninq, L->colptr, L->rowi, L->vals, L->rhs, L->cost,
                      false, CN_LP_PRIMAL_AUTO, true, L->any_field};
    static const struct {
        bool interior, elastic, small_only;
        int method;
    } steps[] = {{true, false, false, CN_LP_PRIMAL_AUTO}, {false, false, false, CN_LP_PRIMAL_AUTO},
                 {false, true, false, CN_LP_DUAL_EQ},     {false, false, true, CN_LP_DUAL_EQ},
                 {false, true, true, CN_LP_PRIMAL_AUTO}};
    *worst = INFINITY;
    if (ask->cert_try && motion_certificate(w, L, &lp, ask->cert_try)) return true;
    if (L->ncols >= CN_LP_IPM_MIN_COLS && !(w->o->route & CN_ROUTE_LP_GLPK_ONLY)) {
        /* first, without cone rows, the descent (linear time; it fails where a load must go up
         * or sideways) */
        bool met = false; /* out of memory: not met, and the interior point says so too */
        if (!ask->resumed && load_descent(w, &lp, L->x, &met) == CN_OK && met &&
            lp_accept(w, L, CN_LP_METHOD_LOAD_DESCENT, worst))
            return true;
        /* the whole assembly on its supports: when it cannot balance, no field is sought, and
         * its motion is the certificate */
        bool absent = false, whole_cert = false;
        long before = cn_lp_internal_errors();
        if (!(w->o->route & CN_ROUTE_NO_WHOLE)) whole_screen(w, L, &lp, !ask->field_only, &absent, &whole_cert);
        *internal += cn_lp_internal_errors() - before; /* the screen's own GLPK errors: not the LP's */
        if (absent) {
            if (whole_cert) return true;
            if (ask->field_only) {
                *stop = LP_ABSENT;
                return false;
            }
        }
        /* frictionless and large, the sparse QP follows (cn_ck_solve_models): it gives the LCP's
         * motion, and a moving answer of it is the certificate, so the interior point waits for it
         */
        if (ask->defer_cert) {
            *stop = LP_DEFERRED;
            return false;
        }
        /* then the interior point: any failure of it (out of memory among them) leaves the
         * answer to GLPK */
        cnLpIpmInfo info;
        bool ran = !cn_lp_ipm(&lp, CN_IPM_WEIGHT_FORCES, L->x, L->y, &info, diag);
        if (ran && lp_accept(w, L, CN_LP_METHOD_INTERIOR_POINT, worst)) return true;
        if (ran && info.field_stop) {
            /* stopped at a field that does not verify here: the method again, to its optimum */
            lp.any_field = false;
            ran = !cn_lp_ipm(&lp, CN_IPM_WEIGHT_FORCES, L->x, L->y, &info, diag);
            if (ran && lp_accept(w, L, CN_LP_METHOD_INTERIOR_POINT, worst)) return true;
        }
        if (ran) {
            /* frictionless and wanted only for its field: none found. The friction LP, whose
             * static solutions include every frictionless one, decides without it; the
             * certificate and GLPK's fallbacks would cost far more (the primal simplex ran for
             * minutes on a 2-D wall of 10,000 bricks under a sideways load). At worst a field
             * is missed and its proof that nothing moves with it. */
            if (ask->field_only) {
                *stop = LP_ABSENT;
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
                      steps[i].interior ? CN_LP_METHOD_GLPK_INTERIOR
                      : steps[i].elastic ? CN_LP_METHOD_GLPK_ELASTIC : CN_LP_METHOD_GLPK_SIMPLEX,
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
cnStatus cn_ck_static_lp(Work *w, const LpAsk *ask, LpAnswer *ans, double *force,
                         double (*fric)[3], cnDiag *diag) {
    bool nofric = ask->nofric;
    *ans = (LpAnswer){.outcome = LP_NONE, .residual = INFINITY};
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
        LpOutcome stop = LP_CERTIFICATE;
        ans->rows = L.neq + L.ninq, ans->cols = L.ncols;
        if (!lp_solve_verified(w, ask, &L, &worst, &stop, &internal, diag)) {
            ans->residual = worst;
            if (stop == LP_DEFERRED || stop == LP_ABSENT) {
                ans->outcome = stop; /* decided after the sparse QP, or by the friction LP */
            } else {
                ans->outcome = LP_UNDECIDED;
                ans->glpk_error = cn_lp_internal_errors() > internal;
            }
        } else {
            ans->residual = worst;
            ans->method = L.method;
            ans->outcome = LP_CERTIFICATE; /* in w->cert */
            if (worst <= CN_LP_EQ_TOL) {
                ans->outcome = LP_FIELD;
                lp_forces(w, &L, nofric, force, fric);
            }
        }
    }
    lp_arrays_free(&L);
    return st;
}

/* The largest t in [0, cap] for which a static field exists under gravity plus an acceleration
 * t * load of every body (load absolute, at the centres of mass): the equilibrium LP with a
 * column for t (in units of |load|), a row t <= cap, and its cost on t alone. *t = -1 when no
 * field exists at t = 0, when a part is driven into another, when the LP has more than
 * CN_LIMIT_LP_MAX_COLS columns (GLPK's simplex alone would take long) or fails. Nothing is
 * verified: the margins use it only to choose where their verdicts look. */
cnStatus cn_ck_load_limit_lp(Work *w, const double load[3], double cap, double *t, cnDiag *diag) {
    *t = -1;
    for (int c = 0; c < w->K; c++)
        if (w->nominal[c] == NOM_CLOSE) return CN_OK;
    const cnMech *m = &w->m;
    int nd = m->nd, dim = w->a->dim;
    double lmag = cn_norm3(load);
    if (!(lmag > 0) || !isfinite(lmag)) return CN_OK;
    LpArrays L;
    memset(&L, 0, sizeof L);
    cnStatus st = lp_arrays_alloc(w, false, &L, diag);
    if (st || L.ncols > CN_LIMIT_LP_MAX_COLS) {
        lp_arrays_free(&L);
        return st;
    }
    /* room for the column of t: one more column pointer, and an entry a linear row and one more */
    int *cp = cn_realloc(L.colptr, sizeof(int) * (size_t)(L.ncols + 2));
    if (cp) L.colptr = cp;
    size_t cap_nz = (size_t)L.ncols * (2 * nd + 1) + 1 + (size_t)L.neq + 1;
    int *ri = cp ? cn_realloc(L.rowi, sizeof(int) * cap_nz) : NULL;
    if (ri) L.rowi = ri;
    double *va = ri ? cn_realloc(L.vals, sizeof(double) * cap_nz) : NULL;
    if (va) L.vals = va;
    double *co = va ? cn_realloc(L.cost, sizeof(double) * (size_t)(L.ncols + 2)) : NULL;
    if (co) L.cost = co;
    double *x = co ? cn_realloc(L.x, sizeof(double) * (size_t)(L.ncols + 2)) : NULL;
    if (x) L.x = x;
    if (!x) {
        lp_arrays_free(&L);
        return cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the LP");
    }
    lp_columns(w, false, &L);
    lp_scaled_matrix(w, &L);
    int n = L.ncols, k = L.colptr[n];
    for (int j = 0; j < n; j++) L.cost[j] = 0;
    for (int b = 0; b < m->nb; b++)
        for (int d = 0; d < dim; d++) {
            double v = m->mass[b] * load[d] / L.rowscale[b * nd + d];
            if (v != 0) L.rowi[k] = b * nd + d, L.vals[k] = v, k++;
        }
    L.rowi[k] = L.neq + L.ninq, L.vals[k] = -1, k++; /* -t >= -cap */
    L.rhs[L.neq + L.ninq] = -cap;
    L.cost[n] = -1;
    L.colptr[n + 1] = k;
    /* a short budget: a simplex that cycles leaves the margin to its verdicts alone */
    cnLpProblem lp = {n + 1, L.neq, L.ninq + 1, L.colptr, L.rowi, L.vals, L.rhs, L.cost,
                      false, CN_LP_PRIMAL_AUTO, true, false};
    bool feas = false;
    if (cn_lp_solve(&lp, &feas, L.x, diag) == CN_OK && feas && isfinite(L.x[n]))
        *t = fmin(fmax(L.x[n], 0), cap);
    lp_arrays_free(&L);
    return CN_OK;
}

/* The model's equilibrium LP undecided: a numerical failure, said with the LP's size. */
cnStatus cn_ck_lp_failure(const Work *w, const LpAnswer *ans, cnDiag *diag) {
    char why[160];
    if (ans->glpk_error) /* GLPK's own message says why */
        return cn_diag_set(diag, CN_ERR_NUMERIC, "",
                           "the LP solver (GLPK) stopped on an internal error (out of memory, or "
                           "numbers it cannot scale) on the equilibrium LP (%d rows, %d columns); "
                           "no verdict",
                           ans->rows, ans->cols);
    return cn_diag_set(diag, CN_ERR_NUMERIC, "",
                       "the equilibrium LP (%d rows, %d columns) is too ill-conditioned to decide: "
                       "neither a static force field (closest residual %.2g of the weights) nor a "
                       "certificate that none exists verifies%s; no verdict",
                       ans->rows, ans->cols, ans->residual, cn_ck_mass_span(w, why, sizeof why));
}

/* The motion of the LP's certificate u, sized as the acceleration along it when contacts do no
 * work: a = (fext.u / u^T M u) u. */
void cn_ck_cert_motion(const Work *w, double *acc) {
    const cnMech *m = &w->m;
    int nv = m->nb * m->nd;
    double fu = 0;
    for (int i = 0; i < nv; i++) fu += m->fext[i] * w->cert[i];
    double e = cn_mech_kinetic(m, w->cert, NULL);
    double t = e > 0 ? fu / e : 0;
    for (int i = 0; i < nv; i++) acc[i] = t * w->cert[i];
}
