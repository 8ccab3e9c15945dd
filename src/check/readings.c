/* The readings of corner contacts' normals (a corner on a corner has a cone of normals): each
 * reading checked, and their verdicts merged into one; cn_check, the public entry. */
#include "check_work.h"
#include "section.h"

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
    stat->corners.disagree = true;
    stat->corners.reading_moves = mov->corners.reading;
    stat->proof = CN_PROOF_NONE;
    stat->undecided = CN_UNDECIDED_NO;
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
    if (r->friction && !(r->proof == CN_PROOF_FRICTIONLESS && r->corners.proof_idle) &&
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
/* Does every reading stand at once? When a frictionless force field balances gravity without
 * the corner contacts, it is a static solution of each reading and bounds every motion from rest
 * of each (the contacts it uses are in all of them; see strong.c). r: the first reading's check. */
static bool all_by_field(const Found *f, const cnAssembly *a, const cnCheckOptions *opt,
                         const cnCheckResult *r, Reading first, bool unload) {
    cnCheckOptions o = *opt;
    if (r->verdict == CN_VERDICT_STABLE && corners_idle(r, &o)) {
        /* the first reading's own field already leaves them idle: no second check (a whole
         * check each, on stacks whose diagonal neighbours touch edge on edge at thousands of
         * points) */
        return true;
    }
    if (r->verdict == CN_VERDICT_STABLE) {
        cnCheckResult dr;
        int kd;
        cnDiag quiet;
        if (cn_ck_check_reading(f, a, &o, &dr, &quiet, first, true, unload, &kd) == CN_OK) {
            /* with --accept-prestress (weak stability: a static solution is enough) any static
             * solution without the corner contacts is one of every reading, its corners idle */
            bool all = !dr.infeasible && dr.verdict == CN_VERDICT_STABLE &&
                       (!dr.friction || dr.proof == CN_PROOF_FRICTIONLESS ||
                        (o.accept_prestress && dr.proof == CN_PROOF_ACCEPTED));
            cn_check_result_free(&dr);
            if (all) return true;
        }
    }
    return false;
}

/* The verdict over the readings tried (i of total): one that stands and one that moves (merged:
 * not guaranteed), else an undecided one, else r's, undecided when not every reading was tried;
 * moved into r. */
static void conclude_readings(const cnAssembly *a, cnCheckResult *r, cnCheckResult *stat, cnCheckResult *mov,
                              cnCheckResult *undec, long i, double total, int k) {
    cnCheckResult *out = r;
    if (stat && mov && stat == mov) out = stat;
    else if (stat && mov) merge_readings(a, stat, mov), out = stat;
    else if (undec) out = undec;
    else if (!mov && i < total) { /* standing in every reading tried, not in all */
        r->verdict = CN_VERDICT_UNDECIDED;
        r->stable = false;
        r->proof = CN_PROOF_UNDECIDED;
        r->undecided = CN_UNDECIDED_CORNERS;
        r->corners.undecided = true;
    } else if (!mov && r->corners.wide) { /* standing in every reading kept, not in all */
        r->verdict = CN_VERDICT_UNDECIDED;
        r->stable = false;
        r->proof = CN_PROOF_UNDECIDED;
        r->undecided = CN_UNDECIDED_CORNERS_WIDE;
        r->corners.undecided = true;
    }
    if (out != r) {
        cn_check_result_free(r);
        *r = *out;
        memset(out, 0, sizeof *out);
    }
    r->corners.count = k, r->corners.readings = i;
}

static cnStatus check_readings(const Found *f, const cnAssembly *a, const cnCheckOptions *opt,
                               bool unload, cnCheckResult *r, cnDiag *diag) {
    cnCheckOptions o = *opt;
    int k = 0;
    const Reading first = {o.one_reading ? o.reading : 0, -1, 0};
    cnStatus st = cn_ck_check_reading(f, a, &o, r, diag, first, false, unload, &k);
    if (!st && o.one_reading) {
        r->corners.count = k, r->corners.readings = k ? 1 : 0;
        return CN_OK;
    }
    if (st || k == 0 || r->infeasible || r->verdict == CN_VERDICT_NOT_GUARANTEED) {
        r->corners.count = k, r->corners.readings = k ? 1 : 0;
        return st;
    }
    /* the readings are tried in the order of their index i (cn_ck_meet_contacts): all ends as
     * found, all reversed, then each pattern and its reverse in turn, which covers every reading by
     * i < total (the reverse of pattern j is pattern total - 1 - j) */
    double total = r->corners.readings_all;
    if (r->verdict == CN_VERDICT_STABLE && all_by_field(f, a, &o, r, first, unload)) {
        r->corners.count = k, r->corners.readings = (long)fmin(total, 9.2e18);
        r->corners.by_field = true;
        return CN_OK;
    }
    /* a corner on a corner: each reading of the cone ends is a possible contact; the assembly
     * stands only if every reading does (the first reading is r; stat and mov are the first
     * readings found standing and moving) */
    long nread = (long)fmin(total, (double)CN_CORNER_READINGS);
    /* Too many readings to decide them all: the verdict cannot be stable whatever they say (a
     * first reading that moves makes it unstable or not guaranteed, an undecided one leaves it
     * undecided unless another moves, a standing one leaves it undecided unless another moves).
     * Only the first reading and, when it stands, its complement are tried: each reading is a
     * whole check, and vaults with hundreds of edges resting on edges would run dozens of them.
     * With at most log2(CN_CORNER_READINGS) corners every reading is decided. */
    if (total > CN_CORNER_READINGS) nread = r->verdict == CN_VERDICT_STABLE ? 2 : 1;
    Reading *plan = cn_malloc(sizeof(Reading) * (size_t)(nread + CN_CORNER_FLIPS));
    if (!plan) {
        cn_check_result_free(r);
        return cn_diag_oom(diag);
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
        st = cn_ck_check_reading(f, a, &o, x, diag, plan[i - 1], false, unload, &k2);
        if (st) break;
        bool keep = false;
        if (x->infeasible) { /* a collision in one reading: the step fails */
            cn_check_result_free(r);
            *r = *x;
            memset(x, 0, sizeof *x);
            r->corners.count = k, r->corners.readings = i + 1;
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
    if (!st) conclude_readings(a, r, stat, mov, undec, i, total, k);
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
    memset(r, 0, sizeof *r);
    r->ref_part = -1;
    /* the contacts, once: every reading and both passes below take a copy */
    Found f;
    cnStatus st = cn_ck_find_contacts(a, &o, &f, diag);
    if (st) return st;
    /* a static 3-D check: its section, if a prism, is checked where the search would start */
    cnSectionCache section = {0};
    if (a->dim == 3 && !o.motion) f.section = &section;
    /* Proposition 2: a held part presses nothing. Without its contacts with free parts the rest
     * must stand by itself; when it does not (a free part leans or rests on the held one, or is
     * left undecided), the contacts are taken as any other. */
    bool done = false;
    if (held_and_free(a, &o)) {
        st = check_readings(&f, a, &o, true, r, diag);
        done = st || r->held_unloaded == 0 || r->infeasible || r->verdict == CN_VERDICT_STABLE;
        if (!done) cn_check_result_free(r);
    }
    if (!done) {
        st = check_readings(&f, a, &o, false, r, diag);
        if (!st) r->held_unloaded = 0;
    }
    cn_ck_found_free(&f);
    /* the section (checked where a search started: every undecided verdict's) is reported with
       an undecided verdict, one it settled, or one its lifted motion decided */
    bool lifted = r->verdict == CN_VERDICT_NOT_GUARANTEED && r->section.lifted; /* the verdict's reading's */
    if (!st && (r->verdict == CN_VERDICT_UNDECIDED || r->proof == CN_PROOF_SECTION || lifted)) {
        r->section = section.rep;
        r->section.lifted = lifted;
    } else if (!st)
        memset(&r->section, 0, sizeof r->section);
    cn_free(section.motion);
    return st;
}
