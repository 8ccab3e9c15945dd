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
        cn_mech_product(&w->m, &w->rows[c], 1, &w->rows[c], 1, W / g, &mcc, 1);
        d[c] = mcc > 0 && isfinite(mcc) ? 1.0 / sqrt(mcc) : 1.0;
    }
    if (friction)
        for (int f = 0; f < Kf; f++) {
            double dc = d[w->contact_of_fric[f]];
            for (int k = 0; k < D; k++) d[K + f * D + k] = dc;
            d[K + Kf * D + f] = 1.0 / dc;
        }
}

cnStatus cn_ck_build_lcp(const Work *w, int n, bool friction, cnLcp *lcp, double *dscale) {
    if (cn_lcp_alloc(lcp, n) != CN_OK) return CN_ERR_MEMORY;
    int K = w->K, Kf = w->Kf, D = w->D, nrows = friction ? K + Kf * D : K;
    double g = w->m.g, W = w->m.wref;
    lcp_scale(w, n, friction, dscale);
    cn_mech_gram(&w->m, w->rows, nrows, w->rows, nrows, W / g, dscale, lcp->M, n);
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
