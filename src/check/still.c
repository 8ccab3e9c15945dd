/* Whether a static solution is the only one: the frictionless field's bound, the frictionless LCP,
 * and the search for a motion from rest (strong.c), wired to a check's work state. */
#include "check_work.h"
#include "section.h"


/* The contact LCP as the motion search reads it; nominal (Kf*D entries) receives the nominal
 * sliding along each friction row. Returns true when nothing slides nominally (the energy
 * argument holds). */
bool cn_ck_motion_problem(const Work *w, const cnCheckOptions *o, double *nominal,
                           cnMotionProblem *p) {
    int Kf = w->Kf, D = w->D;
    for (int f = 0; f < Kf; f++) {
        const cnContact *ct = &w->cs->items[w->contact_of_fric[f]];
        for (int d = 0; d < D; d++)
            nominal[f * D + d] = cn_mech_nominal(&w->m, ct->body1, ct->body2, ct->point, w->dirs[f * D + d]) / w->dt;
    }
    bool energy = !cn_motion_drags(w->rows, w->K, Kf, D, nominal);
    *p = (cnMotionProblem){&w->m, w->K, Kf, D, w->rows, w->contact_of_fric, w->mu,
                           energy ? NULL : nominal, o->motion_tol, o->max_nodes, false,
                           o->max_seconds, o->progress, o->progress_ctx, false, NULL, 0};
    return energy;
}

/* Lemke's solution z moves: is it a solution that moves by the search's per-contact tolerances
 * too (so that rounding in a problem of very unequal parts is not taken for a motion)? acc
 * receives its motion. */
bool cn_ck_lemke_motion_holds(const Work *w, const cnMotionProblem *p, const double *force,
                               const double *z, double *acc) {
    int K = w->K, Kf = w->Kf, D = w->D;
    double *lambda = cn_calloc((size_t)Kf + 1, sizeof(double));
    if (!lambda) return false;
    for (int f = 0; f < Kf; f++) lambda[f] = z[K + Kf * D + f] * w->m.g;
    bool holds = cn_motion_verify(p, force, lambda, acc) == 1;
    cn_free(lambda);
    return holds;
}


/* Does a field of normal forces (absolute units, one per contact) leave every corner contact
 * idle? */
static bool field_leaves_corners(const Work *w, const double *force) {
    double cap = CN_CORNER_IDLE * w->m.wref;
    for (int i = 0; i < w->K; i++)
        if (w->r->contacts.items[i].corner && !(fabs(force[i]) <= cap)) return false;
    return true;
}

/* The frictionless certificate of cn_ck_prove_still from the frictionless contact LCP instead of
 * the equilibrium LP, for up to CN_PIVOT_MAX_AUTO contacts (principal pivoting, microseconds where
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
    if (!d || cn_ck_build_lcp(w, K, false, &lcp, d) != CN_OK) {
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
    for (int c = 0; c < w->K && r->contact; c++)
        r->contact[c].unsettled = !stats->open_contacts || stats->open_contacts[c];
    bool bounded = stats->open_bodies && isfinite(stats->open_power);
    r->open_speed = bounded ? 0 : INFINITY;
    for (int b = 0; b < m->nb; b++) {
        bool open = !bounded || stats->open_bodies[b];
        int part = m->part_of_body[b];
        if (open && part >= 0 && r->part) r->part[part].unsettled = true;
        if (bounded && m->mass[b] > 0) r->open_speed = fmax(r->open_speed, sqrt(stats->open_power / m->mass[b]));
    }
}

/* The section's motion (w->found->section->motion, per part) as the bodies' target, lifted to p:
 * *ans FOUND (force, acc) when it verifies, else unchanged. */
static cnStatus lift(Work *w, const cnMotionProblem *p, double *force, double *acc, cnMotionAnswer *ans) {
    const cnSectionCache *sc = w->found->section;
    const cnMech *m = p->m;
    double *target = cn_calloc((size_t)(m->nb * m->nd) + 1, sizeof(double));
    if (!target) return cn_diag_oom(w->diag);
    for (int b = 0; b < m->nb; b++)
        for (int d = 0; d < m->nd; d++) target[b * m->nd + d] = sc->motion[(size_t)m->part_of_body[b] * 6 + d];
    int ok = cn_section_lift(p, target, force, acc);
    cn_free(target);
    if (ok < 0) return cn_diag_oom(w->diag);
    if (ok) *ans = CN_MOTION_FOUND;
    return CN_OK;
}

/* A static solution exists: is there also a motion from rest? First the frictionless certificate
 * (cn_motion_frictionless_bound: a frictionless force field that balances gravity proves that
 * nothing can move, whatever the friction; only without nominal sliding), then the exact search
 * (cn_motion_search). A prism's section comes before the search (w->found->section): its motion,
 * when it has one, lifted and verified is FOUND (r->section.lifted); when it is stable and
 * assume_planar, a search left undecided is NONE (CN_PROOF_SECTION). *ans: NONE (r->proof: how), FOUND (force, acc: the motion) or UNDECIDED
 * (r->proof = CN_PROOF_UNDECIDED, r->undecided: why). */
cnStatus cn_ck_prove_still(Work *w, const cnMotionProblem *p, bool energy, cnCheckResult *r,
                            double *force, double *acc, cnMotionAnswer *ans, cnDiag *diag) {
    int K = w->K;
    cnStatus st = CN_OK;
    *ans = CN_MOTION_UNDECIDED;
    bool idle = false;
    if (energy && frictionless_lcp_proves(w, p, &idle)) {
        *ans = CN_MOTION_NONE;
        r->proof = CN_PROOF_FRICTIONLESS;
        r->corners.proof_idle = idle;
        return CN_OK;
    }
    if (energy && w->nf_done) {
        if (w->nf_proved) {
            *ans = CN_MOTION_NONE;
            r->proof = CN_PROOF_FRICTIONLESS;
            r->corners.proof_idle = field_leaves_corners(w, w->lpforce);
        }
    } else if (energy) {
        double(*nffric)[3] = cn_calloc((size_t)K + 1, sizeof(double[3]));
        if (!nffric) return cn_diag_oom(diag);
        bool proved = false;
        const LpAsk ask = {.nofric = true, .field_only = true};
        LpAnswer lp;
        st = cn_ck_static_lp(w, &ask, &lp, force, nffric, diag);
        /* only a shortcut to a proof: an LP that cannot be decided proves nothing */
        bool feas = !st && lp.outcome == LP_FIELD;
        cn_free(nffric);
        if (!st && feas) cn_motion_frictionless_bound(p, force, &proved);
        if (!st && proved) {
            *ans = CN_MOTION_NONE;
            r->proof = CN_PROOF_FRICTIONLESS;
            r->corners.proof_idle = field_leaves_corners(w, force);
        }
    }
    cnSectionCache *sc = w->found->section;
    if (!st && *ans == CN_MOTION_UNDECIDED && sc) { /* set for static checks only */
        /* a prism: its section first. Not guaranteed, its motion lifted and verified is one of
           the prism's */
        if (!sc->tried && (st = cn_section_run(w->a, w->o, sc, diag))) return st;
        if (sc->rep.verdict == CN_VERDICT_NOT_GUARANTEED && sc->motion && (st = lift(w, p, force, acc, ans)))
            return st;
        if (*ans == CN_MOTION_FOUND) {
            r->section.lifted = true; /* this reading's verdict (cn_check reports the section) */
            return CN_OK;
        }
    }
    if (!st && *ans == CN_MOTION_UNDECIDED) {
        cnMotionStats stats;
        memset(&stats, 0, sizeof stats);
        stats.open_bodies = cn_calloc((size_t)w->m.nb + 1, 1);
        stats.open_contacts = cn_calloc((size_t)K + 1, 1);
        if (!stats.open_bodies || !stats.open_contacts) {
            cn_free(stats.open_bodies), cn_free(stats.open_contacts);
            return cn_diag_oom(diag);
        }
        /* along a path: the same problem as an earlier sample's is decided as it was */
        cnWarmStart *ws = w->o->warm && !w->o->warm->record_only ? w->o->warm : NULL;
        if (!(ws && cn_proof_memo_find(ws->proofs, p, ans, &stats))) {
            st = cn_motion_search(p, ans, force, acc, &stats, diag);
            if (!st && ws) (void)cn_proof_memo_keep(&ws->proofs, p, *ans, &stats); /* out of
                                                   memory: not kept, and the memo stays valid */
        }
        r->solver.search_nodes = stats.nodes;
        if (!st && *ans == CN_MOTION_NONE) r->proof = CN_PROOF_SEARCH;
        if (!st && *ans == CN_MOTION_UNDECIDED && sc && sc->rep.checked && sc->rep.verdict == CN_VERDICT_STABLE &&
            w->o->assume_planar) {
            /* assumed planar: the motions the search left open leave the section's plane, where
               the section proves none */
            *ans = CN_MOTION_NONE;
            r->proof = CN_PROOF_SECTION;
        }
        if (!st && *ans == CN_MOTION_UNDECIDED) {
            r->undecided = stats.why ? stats.why : CN_UNDECIDED_BUDGET;
            r->proof = CN_PROOF_UNDECIDED;
            open_motions(w, &stats, r);
        }
        cn_free(stats.open_bodies);
        cn_free(stats.open_contacts);
    }
    return st;
}
