/* The contact LCP of a check (frictionless, paper eq. 1, or Stewart-Trinkle, eq. 5) built from the
 * work state, and a solution of it written into the check's result. */
#include "check_work.h"

/* Contacts of a moving body whose motion is at least this fraction of the largest are reported as
 * opening or sliding (see cn_ck_fill_result). */
#define CN_ONSET_FRACTION 1e-2

void cn_ck_fill_result(Work *w, cnCheckResult *r, const double *force, const double (*fric)[3],
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
static void lcp_scale(const Work *w, int n, bool friction, double *d) {
    int K = w->K, Kf = w->Kf, D = w->D;
    double g = w->m.g, W = w->m.wref;
    for (int i = 0; i < n; i++) d[i] = 1.0;
    for (int c = 0; c < K; c++) {
        double mcc;
        cn_mech_gram(&w->m, &w->rows[c], 1, &w->rows[c], 1, W / g, NULL, &mcc, 1);
        d[c] = mcc > 0 && isfinite(mcc) ? 1.0 / sqrt(mcc) : 1.0;
    }
    if (friction)
        for (int f = 0; f < Kf; f++) {
            double dc = d[w->contact_of_fric[f]];
            for (int k = 0; k < D; k++) d[K + f * D + k] = dc;
            d[K + Kf * D + f] = 1.0 / dc;
        }
}

/* The friction LCP's J M^-1 J^T through each contact's basis rows (its point, the dim axes): a
 * row is linear in its direction, so the dim x dim products of two contacts' basis rows give
 * every entry between their normal and friction rows (d_a^T G d_b), each pair once and
 * mirrored, times scale d[a] d[b]. Contacts that share no body leave their entries zero.
 * -1 out of memory. */
static int gram_by_contact(const Work *w, int n, double scale, const double *ds, double *M) {
    int K = w->K, Kf = w->Kf, D = w->D, dim = w->m.dim, R = 1 + D;
    cnJRow *B = cn_malloc(sizeof(cnJRow) * (size_t)K * dim);
    int *ri = cn_malloc(sizeof(int) * (size_t)K * R), *nr = cn_malloc(sizeof(int) * (size_t)K);
    double *sd = cn_malloc(sizeof(double) * 3 * (size_t)K * R);
    if (!B || !ri || !nr || !sd) {
        cn_free(B), cn_free(ri), cn_free(nr), cn_free(sd);
        return -1;
    }
    /* each contact's rows: their index in M and their direction times the row's scale */
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &w->cs->items[c];
        nr[c] = 1, ri[c * R] = c;
        for (int k = 0; k < 3; k++) sd[3 * c * R + k] = ct->normal[k] * ds[c];
        for (int i = 0; i < dim; i++) {
            double e[3] = {0, 0, 0};
            e[i] = 1;
            cn_mech_row(&w->m, ct->body1, ct->body2, ct->point, e, &B[c * dim + i]);
        }
    }
    for (int f = 0; f < Kf; f++) {
        int c = w->contact_of_fric[f];
        for (int k = 0; k < D; k++, nr[c]++) {
            int r = K + f * D + k;
            ri[c * R + nr[c]] = r;
            for (int x = 0; x < 3; x++) sd[3 * (c * R + nr[c]) + x] = w->dirs[f * D + k][x] * ds[r];
        }
    }
    double h[CN_MAX_FRICTION_DIRECTIONS + 1][3];
    for (int a = 0; a < K; a++) {
        const int *ba = B[a * dim].body;
        const double *sa = sd + 3 * (size_t)a * R;
        for (int b = a; b < K; b++) {
            const int *bb = B[b * dim].body;
            bool share = false;
            for (int x = 0; x < 2; x++)
                for (int y = 0; y < 2; y++) share |= ba[x] >= 0 && ba[x] == bb[y];
            if (!share) continue;
            double g[9] = {0}; /* 3 x 3 whatever dim (2-D: the third row and column zero) */
            cn_mech_gram(&w->m, &B[a * dim], dim, &B[b * dim], dim, scale, NULL, g, 3);
            const double *sb = sd + 3 * (size_t)b * R;
            for (int j = 0; j < nr[b]; j++)
                for (int i = 0; i < 3; i++) h[j][i] = g[3 * i] * sb[3 * j] + g[3 * i + 1] * sb[3 * j + 1] + g[3 * i + 2] * sb[3 * j + 2];
            for (int i = 0; i < nr[a]; i++) {
                double *Mi = M + (size_t)ri[a * R + i] * n;
                for (int j = a == b ? i : 0; j < nr[b]; j++) {
                    double t = sa[3 * i] * h[j][0] + sa[3 * i + 1] * h[j][1] + sa[3 * i + 2] * h[j][2];
                    Mi[ri[b * R + j]] = t;
                    M[(size_t)ri[b * R + j] * n + ri[a * R + i]] = t;
                }
            }
        }
    }
    cn_free(B), cn_free(ri), cn_free(nr), cn_free(sd);
    return 0;
}

cnStatus cn_ck_build_lcp(const Work *w, int n, bool friction, cnLcp *lcp, double *dscale) {
    if (cn_lcp_alloc(lcp, n) != CN_OK) return CN_ERR_MEMORY;
    int K = w->K, Kf = w->Kf, D = w->D, nrows = friction ? K + Kf * D : K;
    double g = w->m.g, W = w->m.wref;
    lcp_scale(w, n, friction, dscale);
    if (!friction || w->D > CN_MAX_FRICTION_DIRECTIONS)
        cn_mech_gram(&w->m, w->rows, nrows, w->rows, nrows, W / g, dscale, lcp->M, n);
    else if (gram_by_contact(w, n, W / g, dscale, lcp->M) != 0) {
        cn_lcp_free(lcp);
        return CN_ERR_MEMORY;
    }
    for (int i = 0; i < nrows; i++) {
        lcp->q[i] = cn_mech_relative(&w->m, &w->rows[i], w->m.a0) / g;
        if (friction) {
            const cnContact *ct = &w->cs->items[i < K ? i : w->contact_of_fric[(i - K) / D]];
            double d[3];
            if (i < K) cn_copy3(d, ct->normal);
            else cn_copy3(d, w->dirs[i - K]);
            lcp->q[i] += cn_mech_nominal(&w->m, ct->body1, ct->body2, ct->point, d) / (g * w->dt);
        }
        lcp->q[i] *= dscale[i];
    }
    if (!friction) return CN_OK;
    /* E, -E^T and mu keep their entries: d of a lambda row is 1 / d of its contact's rows */
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
