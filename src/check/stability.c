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
#include <float.h>

#include "check_work.h"

/* Nominal relative velocities below this fraction of (|v| + |w| L + g dt) count as zero (a
 * contact neither slides nor opens by the nominal motion): v the moved parts' velocity at the
 * contact, w their turning rate, L the assembly's size. Nominal motions are exact, so this only
 * absorbs rounding, which near a turn's axis is that of the positions (|w| L) whatever the
 * velocity there. */
#define CN_NOMINAL_TOL 1e-9
/* LCPs larger than this are not solved when the LP (run first) finds a static solution: with
 * friction, and frictionless. Frictionless the LP is a sparse simplex and the dense LCP costs
 * O(n^2) per pivot, so the LP goes first from a smaller size; below about 100 the dense solvers
 * keep their warm starts along paths. */
#define CN_LCP_LP_FIRST 600
#define CN_LCP_LP_FIRST_FRICTIONLESS 100
/* Memory for the dense LCP and Lemke's basis inverse (16 n^2 bytes) at most: beyond, cairn says
 * so rather than exhaust the machine. */
#define CN_DENSE_LCP_MAX_BYTES ((double)(1u << 30))
/* With the LP's certificate in hand, the dense LCP's pivots times n^2 at most (a few seconds):
 * its motion would only be a better one than the certificate's. */
#define CN_CERT_LCP_WORK 2e10
/* Frictionless LCPs of this many contacts or more go to the sparse QP first (motion_qp.c), the
 * dense pivoting after it when its answer does not verify: Lemke's O(n^2) pivots fall behind
 * the sparse QP from about this size; below it both are fast and the dense pivoting keeps its
 * warm starts along paths. */
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
    cn_lcp_free(&r->solver.lcp);
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

/* The work's arrays freed (the result's are the caller's). */
void cn_ck_work_free(Work *w) {
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
static void mechanism_result(Work *w, cnCheckResult *r, cnUnsolved why, double *force,
                             double (*fric)[3], double *acc, double motion_tol) {
    memset(force, 0, sizeof(double) * (size_t)(w->K + w->Kf * w->D));
    memset(fric, 0, sizeof(double[3]) * (size_t)w->K);
    cn_ck_cert_motion(w, acc);
    r->verdict = CN_VERDICT_UNSTABLE;
    r->stable = false;
    r->unsolved = why != CN_UNSOLVED_NO ? why : CN_UNSOLVED_NOT_SOLVED;
    r->solver.forces_from = CN_FORCES_NONE;
    cn_ck_fill_result(w, r, force, (const double(*)[3])fric, acc, motion_tol);
}

/* ---- cn_check, stage by stage ---- */

static cnStatus out_of_memory(Work *w) { return cn_diag_oom(w->diag); }

cnStatus cn_ck_find_contacts(const cnAssembly *a, const cnCheckOptions *o, Found *f, cnDiag *diag) {
    memset(f, 0, sizeof *f);
    cnStatus st = cn_contacts_find(a, o->query, &f->cs, &f->ov, diag);
    if (st) {
        cn_ck_found_free(f); /* the contacts found before it failed */
        return st;
    }
    /* corners that the faces of their pair imply at their point: no reading of them changes
     * anything, and each would double the readings (compas_cra's bridge section: 6 of 10) */
    f->implied = cn_calloc((size_t)f->cs.count + 1, 1);
    if (!f->implied) {
        cn_ck_found_free(f);
        return cn_diag_oom(diag);
    }
    for (int c = 0; c < f->cs.count; c++) f->implied[c] = cn_contact_corner_implied(a, &f->cs, c);
    return CN_OK;
}

void cn_ck_found_free(Found *f) {
    cn_contacts_free(&f->cs);
    cn_free(f->implied);
    f->implied = NULL;
}

/* The reading's contacts (a copy of those found, each corner contact turned to the reading's
 * end), and the mechanics over them. *finished: an overlap decided it. */
cnStatus cn_ck_meet_contacts(Work *w, bool *finished) {
    const cnAssembly *a = w->a;
    const Found *f = w->found;
    cnCheckResult *r = w->r;
    *finished = false;
    const cnOverlap ov = f->ov;
    r->contacts.items = cn_malloc(sizeof(cnContact) * (size_t)(f->cs.count + 1));
    if (!r->contacts.items) return out_of_memory(w);
    r->contacts.capacity = f->cs.count + 1;
    r->contacts.count = f->cs.count;
    if (f->cs.count > 0) memcpy(r->contacts.items, f->cs.items, sizeof(cnContact) * (size_t)f->cs.count);
    const unsigned char *implied = f->implied;
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
    r->corners.implied = 0;
    for (int c = 0; c < r->contacts.count; c++) {
        cnContact *ct = &r->contacts.items[c];
        if (implied[c]) {
            r->corners.implied++;
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
    r->corners.reading_moves = -1;
    r->corners.reading = w->ncorners == 0 || !shown_ok ? -1
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
    cnStatus st = cn_mech_build(a, w->o->query, w->o->motion, &w->m, w->diag);
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
void cn_ck_classify_nominal(Work *w) {
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
cnStatus cn_ck_build_rows(Work *w) {
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
    w->n = r->solver.lcp_size = r->friction ? K + Kf * D + Kf : K;
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
 * CN_ROUTE_NO_SPARSE_QP in the options' route skips it: the tests and benchmarks compare the LP
 * certificate's motion with it. */
static bool sparse_qp_allowed(const Work *w) {
    return !w->r->friction && cn_motion_qp_usable(&w->m) && !(w->o->route & CN_ROUTE_NO_SPARSE_QP);
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
    r->solver.forces_from = CN_FORCES_SPARSE_QP;
    return CN_OK;
}

static bool lp_still(Work *w);

/* The answer of the model's equilibrium LP (not the search's frictionless LP) as the check's:
 * feasible, its certificate, the deferral, the residual and the method reported. */
static void model_lp_answer(Work *w, const LpAnswer *ans) {
    w->lp_feasible = ans->outcome == LP_FIELD;
    w->has_cert = ans->outcome == LP_CERTIFICATE;
    w->cert_deferred = ans->outcome == LP_DEFERRED;
    if (ans->outcome == LP_FIELD || ans->outcome == LP_CERTIFICATE) {
        w->lp_residual = ans->residual;
        w->lp_method = ans->method;
    }
}

/* A moving part of the LCP's motion whose every acceleration component lies within
 * CN_ROUNDING_RESOLVE times its rounding floor (DBL_EPSILON times its weight plus the contact
 * forces through it, as accelerations): a part far lighter than the loads it passes on (a stem
 * under a block 1e12 times heavier), whose motion is the forces' last bits. -1 when none. */
#define CN_ROUNDING_RESOLVE 1e4
static int unresolved_mover(const Work *w) {
    int nb = w->m.nb, nd = w->m.nd;
    double *floor = cn_calloc((size_t)nb * (size_t)nd + 1, sizeof(double));
    if (!floor) return -1; /* cannot tell: the LCP's motion stands */
    for (int i = 0; i < nb * nd; i++) floor[i] = fabs(w->m.a0[i]);
    for (int r = 0; r < w->K; r++) /* one pass over the rows: the forces through each part */
        for (int x = 0; x < 2; x++) {
            int b = w->rows[r].body[x];
            if (b < 0) continue;
            for (int k = 0; k < nd; k++) floor[(size_t)b * nd + k] += fabs(w->rows[r].u[x][k] * w->force[r]);
        }
    int found = -1;
    for (int b = 0; b < nb && found < 0; b++) {
        if (!cn_mech_moves(&w->m, b, w->acc, w->o->motion_tol)) continue;
        bool resolved = false;
        for (int k = 0; k < nd && !resolved; k++)
            resolved = fabs(w->acc[(size_t)b * nd + k]) > CN_ROUNDING_RESOLVE * DBL_EPSILON * floor[(size_t)b * nd + k];
        if (!resolved) found = b;
    }
    cn_free(floor);
    return found;
}

/* With friction, large, and no nominal sliding: the frictionless equilibrium LP before the
 * friction one. Its force field, if any, is a static solution with friction too (friction zero)
 * and, through cn_motion_frictionless_bound, usually the proof that nothing moves, which
 * cn_ck_prove_still would seek with the same LP anyway. The friction LP (D + 1 columns a contact
 * instead of one, with cone rows) then runs only when no frictionless field exists. */
static cnStatus frictionless_first(Work *w) {
    cnMotionProblem mp;
    if (!cn_ck_motion_problem(w, w->o, w->nominal_rows, &mp)) return CN_OK;
    bool proved = false;
    /* no field: the friction LP decides, so the frictionless one's certificate (a second
     * interior point) and GLPK's slow fallbacks (the slowest steps on large vaults) are not wanted */
    const LpAsk ask = {.nofric = true, .field_only = true};
    LpAnswer ans;
    cnStatus st = cn_ck_static_lp(w, &ask, &ans, w->lpforce, w->lpfric, w->diag);
    if (st) return st;
    if (ans.outcome == LP_UNDECIDED) return CN_OK; /* proves nothing: the friction LP decides */
    w->nf_done = true;
    if (ans.outcome != LP_FIELD) return CN_OK;
    model_lp_answer(w, &ans);
    cn_motion_frictionless_bound(&mp, w->lpforce, &proved);
    w->nf_proved = proved;
    w->lp_done = w->lp_feasible = w->lp_trusted = true;
    return CN_OK;
}

/* The route of a problem of n LCP unknowns: the solver steps in the order they may run (each
 * runs when its guard in cn_ck_solve_models holds). Large problems take the equilibrium LP
 * first: a verified solution is a certificate of stability and an LCP solution itself (see
 * decide_*), so dense Lemke is skipped; the LCP is still solved whenever the assembly is
 * unstable, for the motion that starts (and, frictionless, as the cross-check of the verdict).
 * With friction the frictionless LP comes before the friction one (frictionless_first).
 * Frictionless and large, only the LP's load descent runs first: when it finds no field, the
 * sparse QP comes before the LP's interior point, whose work a moving QP answer (the LP's
 * certificate then) saves. Returns the number of steps. */
int cn_ck_route(int n, bool friction, CheckStep steps[CN_ROUTE_STEPS]) {
    int k = 0;
    bool lp_first = n > (friction ? CN_LCP_LP_FIRST : CN_LCP_LP_FIRST_FRICTIONLESS);
    bool sparse_first = !friction && n >= CN_QP_FIRST;
    bool dense = dense_bytes(n) <= CN_DENSE_LCP_MAX_BYTES;
    if (lp_first && friction) steps[k++] = STEP_FIELD_FIRST;
    if (lp_first) steps[k++] = sparse_first ? STEP_LP_DEFERRING : STEP_LP;
    if (n > 0) {
        if (sparse_first) steps[k++] = STEP_SPARSE_QP, steps[k++] = STEP_LP_RESUMED;
        if (dense) steps[k++] = STEP_DENSE_LCP;
        if (!sparse_first && !friction) steps[k++] = STEP_SPARSE_QP;
        if (!dense) steps[k++] = STEP_TOO_LARGE;
    }
    steps[k++] = STEP_LP_CHECK;
    return k;
}

/* The model's equilibrium LP as asked; undecided, a numerical failure. */
static cnStatus model_lp(Work *w, const LpAsk *ask) {
    LpAnswer ans;
    cnStatus st = cn_ck_static_lp(w, ask, &ans, w->lpforce, w->lpfric, w->diag);
    if (st) return st;
    if (ans.outcome == LP_UNDECIDED) return cn_ck_lp_failure(w, &ans, w->diag);
    model_lp_answer(w, &ans);
    return CN_OK;
}

/* Why a contact LCP that ended with status ls gave no motion. */
static cnUnsolved unsolved_of(cnLcpStatus ls) {
    switch (ls) {
    case CN_LCP_RAY: return CN_UNSOLVED_RAY;
    case CN_LCP_INFEASIBLE: return CN_UNSOLVED_INFEASIBLE;
    case CN_LCP_MAX_PIVOTS: return CN_UNSOLVED_PIVOTS;
    case CN_LCP_NUMERIC: return CN_UNSOLVED_NUMERIC;
    case CN_LCP_SOLVED: break;
    }
    return CN_UNSOLVED_NO;
}

/* The dense LCP, warm-started (Lemke or principal pivoting). */
static cnStatus dense_lcp(Work *w) {
    cnCheckResult *r = w->r;
    const cnCheckOptions *o = w->o;
    int n = w->n;
    if (cn_ck_build_lcp(w, n, r->friction, &w->lcp, w->dscale) != CN_OK) return out_of_memory(w);
    /* with the LP's certificate in hand the verdict is made: a long Lemke path that fails is
       not retried (its motion is only a better one than the certificate's) */
    cnLcpOptions lo = o->lcp;
    lo.short_retries = w->lp_done && w->has_cert;
    /* ... nor run long: past CN_CERT_LCP_WORK (pivots times n^2) the certificate's motion is
       reported (a 12 x 20 wall turned past its friction angle: 26,137 pivots, 80 s, to a
       secondary ray) */
    if (lo.short_retries && lo.max_pivots <= 0) {
        double cap = CN_CERT_LCP_WORK / ((double)n * n);
        if (cap < 50.0 * n + 1000) lo.max_pivots = (int)fmax(cap, 1.0);
    }
    w->ls = cn_ck_warm_solve(o->warm, &r->contacts, w->fric_of, w->Kf, w->D, &w->lcp, o->solver,
                             !r->friction, &lo, w->z, w->wv, &w->info, &r->solver.forces_from);
    for (int i = 0; i < n; i++) w->z[i] *= w->dscale[i], w->wv[i] /= w->dscale[i];
    w->lcp_why = unsolved_of(w->ls);
    return CN_OK;
}

/* No LCP solved and none fits in memory: the LP's certificate gives the motion, else no verdict. */
static cnStatus too_large(Work *w) {
    if (w->lp_done && w->has_cert) {
        w->lcp_why = w->qp_failed ? CN_UNSOLVED_TOO_LARGE_QP : CN_UNSOLVED_TOO_LARGE;
        return CN_OK;
    }
    return cn_diag_set(w->diag, CN_ERR_NUMERIC, "",
                       "%s; the contact LCP that would say how it moves has %d unknowns "
                       "and needs %.1f GiB as a dense problem, more than the %.0f GiB "
                       "limit%s, so no motion is computed; no verdict",
                       w->lp_done ? "the equilibrium LP finds no static solution" : "the assembly is large",
                       w->n, dense_bytes(w->n) / (1 << 30), CN_DENSE_LCP_MAX_BYTES / (1 << 30),
                       w->qp_failed ? ", and the sparse QP's answer did not verify" : "");
}

/* The LCP's answer read: its forces, friction vectors and motion, whether it moves, and whether
 * a frictionless motion is only squeezed or rounding. */
static void read_lcp(Work *w) {
    cnCheckResult *r = w->r;
    r->solver.pivots = w->info.pivots;
    r->solver.residual = w->info.residual;
    w->lcp_ok = w->ls == CN_LCP_SOLVED;
    if (w->lcp_ok) {
        for (int i = 0; i < w->nrows; i++) w->force[i] = w->z[i] * w->m.wref;
        if (r->friction) friction_vectors(w, w->force, w->fric);
        cn_mech_response(&w->m, w->rows, r->friction ? w->nrows : w->K, w->force, w->acc);
        w->lcp_static = true;
        for (int b = 0; b < w->m.nb; b++)
            if (cn_mech_moves(&w->m, b, w->acc, w->o->motion_tol)) w->lcp_static = false;
    }
    /* frictionless, a motion carried by forces above CN_SQUEEZE_WEIGHTS is decided by the LP */
    w->squeezed = false;
    if (w->lcp_ok && !r->friction && !w->lcp_static)
        for (int i = 0; i < w->K; i++)
            if (w->z[i] > CN_SQUEEZE_WEIGHTS) w->squeezed = true;
    /* frictionless, a motion of a part far lighter than the loads through it may be rounding:
       the LP, an exact second formulation, says whether a static solution exists */
    w->rounding_body = w->lcp_ok && !r->friction && !w->lcp_static ? unresolved_mover(w) : -1;
}

/* The models of a check solved along its route (cn_ck_route): the contact LCP (paper eq. 3 or
 * 5), the equilibrium LP where it is needed, and the sparse QP for large frictionless ones. */
cnStatus cn_ck_solve_models(Work *w) {
    cnCheckResult *r = w->r;
    const cnCheckOptions *o = w->o;
    cnStatus st = CN_OK;
    w->rounding_body = -1;
    memset(&w->info, 0, sizeof w->info);
    w->ls = CN_LCP_NUMERIC;
    if (w->n == 0) w->ls = CN_LCP_SOLVED, r->solver.forces_from = CN_FORCES_NONE;
    CheckStep route[CN_ROUTE_STEPS];
    int nsteps = cn_ck_route(w->n, r->friction, route);
    bool need_lp = false;
    for (int i = 0; i < nsteps && !st; i++) {
        /* the LCP's steps run until one solves it, unless the LP's field already decides */
        bool open = !w->lp_trusted && w->ls != CN_LCP_SOLVED;
        switch (route[i]) {
        case STEP_FIELD_FIRST:
            st = frictionless_first(w);
            break;
        case STEP_LP:
        case STEP_LP_DEFERRING:
            if (w->lp_done) break;
            /* when the sparse QP follows, the LP's interior point waits for it (after the
               descent): a moving answer of the QP is the LP's certificate too (need_lp), and a
               static one is cross-checked by the LP as the dense LCP's is */
            st = model_lp(w, &(LpAsk){.defer_cert = route[i] == STEP_LP_DEFERRING && sparse_qp_allowed(w)});
            if (st) break;
            w->lp_done = !w->cert_deferred;
            /* frictionless, its static solution decides only when its forces keep every part
               still (lp_still): else the LCP decides, with the LP as its cross-check */
            w->lp_trusted = w->lp_feasible && (r->friction || lp_still(w));
            break;
        case STEP_SPARSE_QP:
            if (open) st = sparse_frictionless(w);
            break;
        case STEP_LP_RESUMED:
            /* the QP gave no verified answer: the LP in full now, before the dense LCP, so that
               its static field decides alone (as when it ran first) and its certificate cuts
               Lemke's retries short */
            if (!open || !w->cert_deferred) break;
            if ((st = model_lp(w, &(LpAsk){.resumed = true}))) break;
            w->lp_done = true;
            w->lp_trusted = w->lp_feasible && lp_still(w);
            break;
        case STEP_DENSE_LCP:
            if (open) st = dense_lcp(w);
            break;
        case STEP_TOO_LARGE:
            if (open) st = too_large(w);
            break;
        case STEP_LP_CHECK:
            read_lcp(w);
            /* With friction a static LCP solution already decides (stable), and the LP is
               needed only when the LCP's solution moves (another solution may be static).
               Frictionless, the LP is the cross-check of the LCP's verdict, and decides a
               motion that only a squeeze carries or that may be rounding. */
            need_lp = !w->lp_done &&
                      (!w->lcp_ok || (r->friction ? !w->lcp_static
                                                  : o->lp_crosscheck || w->squeezed || w->rounding_body >= 0));
            /* still deferred here, the QP's answer verified (else the LP ran in full before the
               dense LCP): its motion, when it moves, is tried as the certificate first */
            if (need_lp)
                st = model_lp(w, &(LpAsk){.cert_try = w->cert_deferred && !w->lcp_static ? w->qp_motion : NULL,
                                          .resumed = w->cert_deferred});
            break;
        }
    }
    if (st) return st;
    r->solver.lp_stable = (w->lp_done || need_lp) ? w->lp_feasible : w->lcp_static; /* skipped: implied */
    r->solver.lp_method = (w->lp_done || need_lp) ? w->lp_method : CN_LP_METHOD_NONE;
    return CN_OK;
}

/* Stable on the LP's solution: it keeps every part on its nominal motion; with v = v0 and
 * lambda at the sliding contacts' kinetic level it solves the same LCP, and cn_ck_static_lp()
 * verified the conditions (p >= 0, equilibrium, cones). */
static void stable_by_lp(Work *w) {
    cnCheckResult *r = w->r;
    r->solver.residual = w->lp_residual;
    r->solver.forces_from = CN_FORCES_LP;
    memset(w->acc, 0, sizeof(double) * (size_t)w->m.nb * w->m.nd); /* no deviation anywhere */
    r->stable = true;
    r->verdict = CN_VERDICT_STABLE;
    cn_ck_fill_result(w, r, w->lpforce, (const double(*)[3])w->lpfric, w->acc, w->o->motion_tol);
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
    } else if (w->lp_feasible && !w->lcp_static && w->rounding_body >= 0) {
        /* a static field within the LP's tolerance, and a motion that is rounding */
        char why[160];
        int b = w->rounding_body;
        return cn_diag_set(w->diag, CN_ERR_NUMERIC, "",
                           "the LCP's motion of '%s' is within rounding of the forces through it, "
                           "and the equilibrium LP finds a static solution%s; no verdict",
                           w->a->parts[w->m.part_of_body[b]].name, cn_ck_mass_span(w, why, sizeof why));
    } else if (o->lp_crosscheck && lp_static != w->lcp_static) {
        char why[160];
        return cn_diag_set(w->diag, CN_ERR_NUMERIC, "",
                           "the LCP says %s but the equilibrium LP says %s: %s; no verdict",
                           w->lcp_static ? "stable" : "unstable", lp_static ? "stable" : "unstable",
                           cn_ck_mass_span(w, why, sizeof why)[0] ? why + 2
                                                           : "the assembly is within numerical tolerance of a tipping threshold");
    } else {
        r->stable = w->lcp_static;
        r->verdict = w->lcp_static ? CN_VERDICT_STABLE : CN_VERDICT_UNSTABLE;
        cn_ck_fill_result(w, r, w->force, (const double(*)[3])w->fric, w->acc, o->motion_tol);
    }
    return CN_OK;
}

/* With friction and no static solution: unstable, with the LCP's motion or, without it, the
 * LP's certificate (a mechanism); the search for a moving LCP solution is not run here (it
 * rarely finds one where Lemke ends on a secondary ray). */
static cnStatus decide_friction_unstable(Work *w) {
    cnCheckResult *r = w->r;
    if (w->lcp_ok) {
        r->verdict = CN_VERDICT_UNSTABLE;
        cn_ck_fill_result(w, r, w->force, (const double(*)[3])w->fric, w->acc, w->o->motion_tol);
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
    if (!w->lcp_static) r->solver.residual = w->lp_residual, r->solver.forces_from = CN_FORCES_LP;
    if (o->accept_prestress) {
        r->verdict = CN_VERDICT_STABLE;
        r->proof = CN_PROOF_ACCEPTED;
        memset(w->acc, 0, nacc);
    } else {
        cnMotionProblem mp;
        bool energy = cn_ck_motion_problem(w, o, w->nominal_rows, &mp);
        mp.field = sforce; /* the rest's field where one body's motion is extended */
        if (w->lcp_ok && !w->lcp_static && !(o->route & CN_ROUTE_NO_LEMKE_MOTION) &&
            cn_ck_lemke_motion_holds(w, &mp, w->force, w->z, w->acc)) {
            r->verdict = CN_VERDICT_NOT_GUARANTEED; /* the LCP's own solution moves */
        } else {
            cnMotionAnswer ans;
            cnStatus st = cn_ck_prove_still(w, &mp, energy, r, w->mforce, w->acc, &ans, w->diag);
            if (st) return st;
            if (ans == CN_MOTION_FOUND) r->verdict = CN_VERDICT_NOT_GUARANTEED;
            else memset(w->acc, 0, nacc);
            if (ans == CN_MOTION_UNDECIDED) r->verdict = CN_VERDICT_UNDECIDED;
        }
    }
    r->stable = r->verdict == CN_VERDICT_STABLE;
    cn_ck_fill_result(w, r, sforce, sfric, w->acc, o->motion_tol);
    return CN_OK;
}

static cnStatus check_stages(Work *w) {
    bool finished;
    cnStatus st = cn_ck_meet_contacts(w, &finished);
    if (st || finished) return st;
    cn_ck_classify_nominal(w);
    if (w->r->infeasible) return CN_OK; /* a collision: nothing to solve */
    if ((st = cn_ck_build_rows(w)) || (st = cn_ck_solve_models(w))) return st;
    if (!w->r->friction) return decide_frictionless(w);
    if (!w->lcp_static && !w->lp_feasible) return decide_friction_unstable(w);
    return decide_friction_static(w);
}

void cn_ck_work_init(Work *w, const Found *found, const cnAssembly *a, const cnCheckOptions *o,
                     cnCheckResult *r, cnDiag *diag, Reading reading, bool drop, bool unload) {
    memset(r, 0, sizeof *r);
    r->ref_part = -1;
    memset(w, 0, sizeof *w);
    w->a = a;
    w->found = found;
    w->o = o;
    w->r = r;
    w->diag = diag;
    w->reading = reading;
    w->drop_corners = drop;
    w->held_unloaded = unload;
    w->cs = &r->contacts;
    w->dt = (o->motion && o->motion->dt > 0) ? o->motion->dt : 1.0;
}

/* One reading of the corner contacts' normals (reading, as cn_ck_meet_contacts reads it; drop:
 * without them), as cn_check documents for the whole check (its LCP kept on failure too, though
 * cn_check frees a later reading's); *ncorners: how many corner contacts the assembly has (their
 * readings in r->corners.readings_all and _log2, r->corners.wide). */
cnStatus cn_ck_check_reading(const Found *found, const cnAssembly *a, const cnCheckOptions *opt,
                             cnCheckResult *r, cnDiag *diag, Reading reading, bool drop, bool unload,
                             int *ncorners) {
    cnCheckOptions o = *opt;
    Work w;
    cn_ck_work_init(&w, found, a, &o, r, diag, reading, drop, unload);
    cnStatus st = check_stages(&w);
    if (!st && o.keep_lcp && w.n > 0 && dense_bytes(w.n) <= CN_DENSE_LCP_MAX_BYTES &&
        w.lcp.n != w.n) {
        cn_lcp_free(&w.lcp);
        if (cn_ck_build_lcp(&w, w.n, r->friction, &w.lcp, w.dscale) != CN_OK)
            st = out_of_memory(&w);
    }
    /* keep the LCP when asked, on failure too: that is when it is most wanted */
    cnLcp kept = {0};
    if (o.keep_lcp && (st ? w.lcp.n > 0 : dense_bytes(w.n) <= CN_DENSE_LCP_MAX_BYTES)) {
        kept = w.lcp;
        memset(&w.lcp, 0, sizeof w.lcp);
    }
    if (st) cn_check_result_free(r);
    r->solver.lcp = kept;
    *ncorners = w.ncorners;
    r->corners.readings_all = w.readings;
    r->corners.readings_log2 = w.readings_log2;
    r->corners.wide = w.corners_wide;
    cn_ck_work_free(&w);
    return st;
}
