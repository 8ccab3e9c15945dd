/* The stability verdict of an assembly at rest.
 *
 * Frictionless (paper sec. III-A, eq. 1; Baraff 1994): a = A F + b with A = J M^-1 J^T,
 * b = J M^-1 f_ext, 0 <= F _|_ a >= 0. The body accelerations M^-1 (f_ext + J^T F) are the same
 * for every solution (they solve a strictly convex QP by Gauss' principle), so the LCP decides:
 * stable iff they vanish. An LP (equilibrium with F >= 0) must agree; it is run as a cross-check.
 *
 * Friction (eq. 5, Stewart & Trinkle 1996): the impulse-velocity LCP over one step dt = 1 from
 * rest, with a D-direction friction pyramid. It can have several solutions, static and moving,
 * so the existence of a static one is decided exactly by an LP over the same constraints
 * (equilibrium, p_n >= 0, p_f >= 0, mu p_n - sum p_f >= 0); the LCP gives the motion that starts
 * when there is none. Every LCP solution (and an LP solution, as an LCP solution) is verified. */
#include <math.h>
#include <string.h>

#include "mech.h"

/* Equilibrium residual accepted for an LP solution, relative to the reference weight. */
#define CN_LP_EQ_TOL 1e-7

cnCheckOptions cn_check_options_default(void) {
    cnCheckOptions o;
    memset(&o, 0, sizeof o);
    o.solver = CN_SOLVER_AUTO;
    o.lp_crosscheck = true;
    o.motion_tol = CN_DEFAULT_MOTION_TOL;
    o.lcp = cn_lcp_options_default();
    o.query = NULL;
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
 * along the downhill direction (gravity projected on the tangent plane) when there is one, so
 * that an incline is resolved exactly by the pyramid. */
static void friction_dirs(const cnAssembly *a, const double n[3], int D, double (*dirs)[3]) {
    if (a->dim == 2) {
        double t[3] = {-n[1], n[0], 0};
        cn_copy3(dirs[0], t);
        for (int k = 0; k < 3; k++) dirs[1][k] = -t[k];
        return;
    }
    double t1[3], t2[3], g[3];
    double gn = cn_dot3(a->gravity, n);
    for (int k = 0; k < 3; k++) g[k] = a->gravity[k] - gn * n[k];
    if (cn_norm3(g) > 1e-6 * cn_norm3(a->gravity)) {
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

typedef struct {
    const cnAssembly *a;
    cnMech m;
    int K;          /* contacts */
    int Kf;         /* contacts with friction */
    int D;          /* friction directions */
    int *fric_of;   /* contact -> friction index or -1 */
    int *contact_of_fric;
    double *mu;     /* per friction contact */
    double lp_residual; /* verified residual of the LP's static solution (relative to W) */
    cnJRow *rows;   /* K normal rows, then Kf*D friction rows */
} Work;

static void work_free(Work *w) {
    cn_mech_free(&w->m);
    cn_free(w->fric_of);
    cn_free(w->contact_of_fric);
    cn_free(w->mu);
    cn_free(w->rows);
}

/* LP: does a static solution exist? x (size K + Kf*D) receives the forces (absolute). */
static cnStatus static_lp(Work *w, bool *feasible, double *x, cnDiag *diag) {
    const cnMech *m = &w->m;
    int nd = m->nd, nb = m->nb, K = w->K, Kf = w->Kf, D = w->D;
    int nv = K + Kf * D, neq = nb * nd, nin = Kf;
    int cap = nv * 2 * nd + Kf * (D + 1) + 1;
    int *colptr = cn_malloc(sizeof(int) * (size_t)(nv + 1));
    int *rowi = cn_malloc(sizeof(int) * (size_t)cap);
    double *vals = cn_malloc(sizeof(double) * (size_t)cap);
    double *rhs = cn_malloc(sizeof(double) * (size_t)(neq + nin + 1));
    double *cost = cn_malloc(sizeof(double) * (size_t)(nv + 1));
    cnStatus st = CN_ERR_MEMORY;
    if (!colptr || !rowi || !vals || !rhs || !cost) {
        cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory building the LP");
        goto done;
    }
    /* Scaling: variables in units of wref; force rows / wref; torque rows / (wref L). */
    double L = w->a->length_scale, W = m->wref;
    int dimlin = w->a->dim;
    int k = 0;
    for (int j = 0; j < nv; j++) {
        colptr[j] = k;
        const cnJRow *r = &w->rows[j];
        for (int side = 0; side < 2; side++) {
            int b = r->body[side];
            if (b < 0) continue;
            for (int d = 0; d < nd; d++) {
                double v = r->c[side][d] / (d < dimlin ? 1.0 : L);
                if (v == 0) continue;
                rowi[k] = b * nd + d;
                vals[k] = v;
                k++;
            }
        }
        if (j < K) {
            int f = w->fric_of[j];
            if (f >= 0) rowi[k] = neq + f, vals[k] = w->mu[f], k++;
            cost[j] = 1.0;
        } else {
            int f = (j - K) / D;
            rowi[k] = neq + f, vals[k] = -1.0, k++;
            cost[j] = 0.0;
        }
    }
    colptr[nv] = k;
    for (int b = 0; b < nb; b++)
        for (int d = 0; d < nd; d++)
            rhs[b * nd + d] = -m->fext[(size_t)b * nd + d] / (W * (d < dimlin ? 1.0 : L));
    for (int f = 0; f < nin; f++) rhs[neq + f] = 0;
    cnLpProblem lp = {nv, neq, nin, colptr, rowi, vals, rhs, cost};
    st = cn_lp_solve(&lp, feasible, x, diag);
    if (st == CN_OK && *feasible) {
        /* Verify the equilibrium ourselves and clip round-off negatives. */
        for (int j = 0; j < nv; j++) x[j] = fmax(x[j], 0.0) * W;
        double worst = 0;
        double *res = cn_calloc((size_t)neq + 1, sizeof(double));
        if (!res) {
            st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
            goto done;
        }
        for (int i = 0; i < neq; i++) res[i] = m->fext[i];
        for (int j = 0; j < nv; j++)
            for (int x2 = 0; x2 < 2; x2++) {
                int b = w->rows[j].body[x2];
                if (b < 0) continue;
                for (int d = 0; d < nd; d++) res[b * nd + d] += w->rows[j].c[x2][d] * x[j];
            }
        for (int i = 0; i < neq; i++)
            worst = fmax(worst, fabs(res[i]) / (W * ((i % nd) < dimlin ? 1.0 : L)));
        for (int f = 0; f < Kf; f++) {
            double s = w->mu[f] * x[w->contact_of_fric[f]];
            for (int d = 0; d < D; d++) s -= x[K + f * D + d];
            worst = fmax(worst, -s / W);
        }
        cn_free(res);
        w->lp_residual = worst;
        if (!(worst <= CN_LP_EQ_TOL)) *feasible = false; /* not a certificate: treat as none */
    }
done:
    cn_free(colptr);
    cn_free(rowi);
    cn_free(vals);
    cn_free(rhs);
    cn_free(cost);
    return st;
}

/* Above this size the automatic choice skips principal pivoting, whose every step refactorises
 * the clamped block (O(|C|^3)), and goes to Lemke (O(n^2) per pivot). */
#define CN_PIVOT_MAX_AUTO 200
/* LCPs larger than this are not solved when the LP finds a static solution. */
#define CN_LCP_LP_FIRST 600

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

/* Is the body at rest? acc: its generalized acceleration (or velocity after dt = 1). */
static bool body_moves(const Work *w, int b, const double *acc, double tol) {
    const cnMech *m = &w->m;
    int nd = m->nd, dim = w->a->dim;
    const double *v = acc + (size_t)b * nd;
    double lin = 0, ang = 0;
    for (int k = 0; k < dim; k++) lin += v[k] * v[k];
    for (int k = dim; k < nd; k++) ang += v[k] * v[k];
    double scale = m->g;
    return sqrt(lin) > tol * scale || sqrt(ang) * m->radius[b] > tol * scale;
}

static void fill_result(Work *w, cnCheckResult *r, const double *force, const double *acc,
                        double tol) {
    const cnMech *m = &w->m;
    const cnAssembly *a = w->a;
    int nd = m->nd, K = w->K, D = w->D;
    double scale = m->g;
    r->nmoving = 0;
    for (int b = 0; b < m->nb; b++) {
        int p = m->part_of_body[b];
        bool mv = body_moves(w, b, acc, tol);
        r->part[p].moves = mv;
        if (!mv) continue;
        r->moving[r->nmoving++] = p;
        for (int k = 0; k < a->dim; k++) r->part[p].lin[k] = acc[(size_t)b * nd + k];
        if (a->dim == 2) r->part[p].ang[2] = acc[(size_t)b * nd + 2];
        else
            for (int k = 0; k < 3; k++) r->part[p].ang[k] = acc[(size_t)b * nd + 3 + k];
    }
    /* parts are listed in part order */
    for (int i = 1; i < r->nmoving; i++)
        for (int j = i; j > 0 && r->moving[j - 1] > r->moving[j]; j--) {
            int t = r->moving[j];
            r->moving[j] = r->moving[j - 1];
            r->moving[j - 1] = t;
        }
    for (int c = 0; c < K; c++) {
        cnContactResult *cr = &r->contact[c];
        const cnContact *ct = &r->contacts.items[c];
        cr->normal_force = force[c];
        int f = w->fric_of[c];
        if (f >= 0) {
            double dirs[64][3];
            friction_dirs(a, ct->normal, D, dirs);
            for (int d = 0; d < D; d++)
                for (int k = 0; k < 3; k++) cr->friction[k] += force[K + f * D + d] * dirs[d][k];
        }
        double sep = cn_mech_relative(m, &w->rows[c], acc);
        cr->separation = sep;
        /* tangential relative motion: relative motion of the contact point minus its normal
         * part, along two tangents */
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
}

/* The scaled contact LCP (dense): unknowns in units of W (forces, or impulses over dt = 1),
 * rows in units of g (accelerations, or velocities after dt = 1). Friction adds the
 * Stewart-Trinkle blocks E, -E^T and mu (eq. 5). */
static cnStatus build_lcp(const Work *w, int n, cnLcp *lcp) {
    if (cn_lcp_alloc(lcp, n) != CN_OK) return CN_ERR_MEMORY;
    int K = w->K, Kf = w->Kf, D = w->D, nrows = K + Kf * D;
    double g = w->m.g, W = w->m.wref;
    cn_mech_product(&w->m, w->rows, nrows, w->rows, nrows, W / g, lcp->M, n);
    for (int i = 0; i < nrows; i++) lcp->q[i] = cn_mech_relative(&w->m, &w->rows[i], w->m.a0) / g;
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
    return CN_OK;
}

cnStatus cn_check(const cnAssembly *a, const cnCheckOptions *opt, cnCheckResult *r,
                  cnDiag *diag) {
    cnCheckOptions o = opt ? *opt : cn_check_options_default();
    if (o.motion_tol <= 0) o.motion_tol = CN_DEFAULT_MOTION_TOL;
    memset(r, 0, sizeof *r);
    r->ref_part = -1;
    Work w;
    memset(&w, 0, sizeof w);
    w.a = a;
    cnLcp lcp = {0};
    double *z = NULL, *wv = NULL, *force = NULL, *acc = NULL, *lpx = NULL;
    cnStatus st;

    cnOverlap ov;
    st = cn_contacts_find(a, o.query, &r->contacts, &ov, diag);
    if (st) goto fail;
    if (ov.found) {
        st = cn_diag_set(diag, CN_ERR_INPUT, "", "parts '%s' and '%s' overlap by %.6g (tolerance %.3g)",
                         a->parts[ov.part1].name, a->parts[ov.part2].name, ov.depth,
                         a->contact_tol);
        goto fail;
    }
    st = cn_mech_build(a, o.query, &w.m, diag);
    if (st) goto fail;
    r->ref_weight = w.m.wref;
    r->ref_part = w.m.ref_part;
    int K = w.K = r->contacts.count;
    int nd = w.m.nd, nb = w.m.nb;
    w.D = a->friction_dirs;
    w.fric_of = cn_malloc(sizeof(int) * (size_t)(K + 1));
    w.contact_of_fric = cn_malloc(sizeof(int) * (size_t)(K + 1));
    w.mu = cn_malloc(sizeof(double) * (size_t)(K + 1));
    r->contact = cn_calloc((size_t)K + 1, sizeof(cnContactResult));
    r->part = cn_calloc((size_t)a->nparts, sizeof(cnPartMotion));
    r->moving = cn_calloc((size_t)a->nparts, sizeof(int));
    acc = cn_calloc((size_t)nb * nd + 1, sizeof(double));
    if (!w.fric_of || !w.contact_of_fric || !w.mu || !r->contact || !r->part || !r->moving || !acc)
        goto oom;
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &r->contacts.items[c];
        double mu = cn_assembly_mu(a, ct->body1, ct->body2);
        w.fric_of[c] = -1;
        if (mu > 0) {
            w.fric_of[c] = w.Kf;
            w.contact_of_fric[w.Kf] = c;
            w.mu[w.Kf] = mu;
            w.Kf++;
        }
    }
    int Kf = w.Kf, D = w.D;
    int nrows = K + Kf * D;
    w.rows = cn_calloc((size_t)nrows + 1, sizeof(cnJRow));
    force = cn_calloc((size_t)nrows + 1, sizeof(double));
    lpx = cn_calloc((size_t)nrows + 1, sizeof(double));
    if (!w.rows || !force || !lpx) goto oom;
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &r->contacts.items[c];
        cn_mech_row(&w.m, ct->body1, ct->body2, ct->point, ct->normal, &w.rows[c]);
        int f = w.fric_of[c];
        if (f < 0) continue;
        double dirs[64][3];
        friction_dirs(a, ct->normal, D, dirs);
        for (int d = 0; d < D; d++)
            cn_mech_row(&w.m, ct->body1, ct->body2, ct->point, dirs[d], &w.rows[K + f * D + d]);
    }
    r->friction = Kf > 0;
    double W = w.m.wref;

    /* The LCP, scaled: unknowns in units of W (forces, or impulses over dt = 1), rows in units
     * of g (accelerations, or velocities after dt = 1). */
    int n = r->friction ? K + Kf * D + Kf : K;
    r->lcp_size = n;
    z = cn_calloc((size_t)n + 1, sizeof(double));
    wv = cn_calloc((size_t)n + 1, sizeof(double));
    if (!z || !wv) goto oom;
    if (r->friction && o.solver == CN_SOLVER_PIVOT) {
        st = cn_diag_set(diag, CN_ERR_INPUT, "",
                         "the pivot solver handles frictionless assemblies only; use --solver "
                         "lemke or auto");
        goto fail;
    }
    /* For large LCPs the LP runs first: a verified static solution is a certificate of
     * stability and an LCP solution itself (see below), so dense Lemke is skipped; the LCP is
     * still solved whenever the assembly is unstable, for the motion that starts (and,
     * frictionless, as the cross-check of the verdict). */
    bool lp_done = false, lp_feasible = false;
    if (n > CN_LCP_LP_FIRST) {
        st = static_lp(&w, &lp_feasible, lpx, diag);
        if (st) goto fail;
        lp_done = true;
    }
    cnLcpInfo info;
    memset(&info, 0, sizeof info);
    cnLcpStatus ls = CN_LCP_NUMERIC;
    if (n == 0) ls = CN_LCP_SOLVED, r->solver = "none";
    else if (!(lp_done && lp_feasible)) {
        if (build_lcp(&w, n, &lcp) != CN_OK) goto oom;
        ls = solve_lcp(&lcp, o.solver, !r->friction, &o.lcp, z, wv, &info, &r->solver);
    }
    r->pivots = info.pivots;
    r->residual = info.residual;
    bool lcp_ok = ls == CN_LCP_SOLVED;
    bool lcp_static = false;
    if (lcp_ok) {
        for (int i = 0; i < nrows; i++) force[i] = z[i] * W;
        cn_mech_response(&w.m, w.rows, nrows, force, acc);
        lcp_static = true;
        for (int b = 0; b < nb; b++)
            if (body_moves(&w, b, acc, o.motion_tol)) lcp_static = false;
    }

    bool need_lp = !lp_done && (r->friction || o.lp_crosscheck || !lcp_ok);
    if (need_lp) {
        st = static_lp(&w, &lp_feasible, lpx, diag);
        if (st) goto fail;
    }
    r->lp_stable = lp_feasible;

    if (!r->friction) {
        if (lp_done && lp_feasible) {
            /* stable by the LP's verified static solution (large problem, LCP not solved) */
            r->residual = w.lp_residual;
            r->solver = "lp";
            cn_mech_response(&w.m, w.rows, nrows, lpx, acc);
            r->stable = true;
            fill_result(&w, r, lpx, acc, o.motion_tol);
        } else if (!lcp_ok && lp_feasible) {
            /* No verified LCP solution, but a static one exists. It solves the same LCP: with
             * nothing accelerating w = J a = 0, and static_lp() verified F >= 0 and the
             * equilibrium residual, which is then the LCP residual. */
            r->residual = w.lp_residual;
            r->solver = "lp";
            cn_mech_response(&w.m, w.rows, nrows, lpx, acc);
            r->stable = true;
            fill_result(&w, r, lpx, acc, o.motion_tol);
        } else if (!lcp_ok) {
            st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                             "the frictionless contact LCP (%d contacts) was not solved: %s after "
                             "%d pivots, and no static solution exists; no verdict",
                             n, cn_lcp_status_name(ls), info.pivots);
            goto fail;
        } else {
            if (o.lp_crosscheck && lp_feasible != lcp_static) {
                st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                                 "the LCP says %s but the equilibrium LP says %s: the assembly is "
                                 "within numerical tolerance of a tipping threshold; no verdict",
                                 lcp_static ? "stable" : "unstable",
                                 lp_feasible ? "stable" : "unstable");
                goto fail;
            }
            r->stable = lcp_static;
            fill_result(&w, r, force, acc, o.motion_tol);
        }
    } else {
        if (lcp_static) {
            r->stable = true;
            fill_result(&w, r, force, acc, o.motion_tol);
        } else if (lp_feasible) {
            /* A static solution exists: with v = 0 and lambda = 0 it solves the same LCP (w_n and
             * rho vanish, zeta = mu p_n - sum p_f >= 0), and static_lp() verified exactly
             * those conditions: p >= 0, the equilibrium and the friction cones. */
            r->residual = w.lp_residual;
            r->solver = "lp";
            cn_mech_response(&w.m, w.rows, nrows, lpx, acc);
            r->stable = true;
            fill_result(&w, r, lpx, acc, o.motion_tol);
        } else if (lcp_ok) {
            r->stable = false;
            fill_result(&w, r, force, acc, o.motion_tol);
        } else {
            st = cn_diag_set(diag, CN_ERR_NUMERIC, "",
                             "no static solution exists (LP), but the friction LCP (n = %d) was "
                             "not solved (%s), so the motion is unknown; no verdict",
                             n, cn_lcp_status_name(ls));
            goto fail;
        }
    }
    if (o.keep_lcp) {
        if (lcp.n != n && (cn_lcp_free(&lcp), build_lcp(&w, n, &lcp)) != CN_OK) goto oom;
        r->lcp = lcp;
        memset(&lcp, 0, sizeof lcp);
    }
    st = CN_OK;
    goto done;
oom:
    st = cn_diag_set(diag, CN_ERR_MEMORY, "", "out of memory");
fail: {
    /* keep the LCP on failure when asked: that is when it is most wanted */
    cnLcp kept = {0};
    if (o.keep_lcp && lcp.n > 0) {
        kept = lcp;
        memset(&lcp, 0, sizeof lcp);
    }
    cn_check_result_free(r);
    r->lcp = kept;
}
done:
    work_free(&w);
    cn_lcp_free(&lcp);
    cn_free(z);
    cn_free(wv);
    cn_free(force);
    cn_free(acc);
    cn_free(lpx);
    return st;
}
