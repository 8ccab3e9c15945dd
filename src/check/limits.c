/* Static limits for the margins: the equilibrium LP of a check's first reading, with a column
 * for a load factor (cn_check_load_limit) or alone (cn_check_has_field). */
#include "check_work.h"
#include "check_limit.h"

/* The first reading of a check's work, up to its rows, for an LP of its own (lp). */
static cnStatus first_reading_lp(const cnAssembly *a, const cnCheckOptions *opt,
                                 cnStatus (*lp)(Work *w, void *ctx), void *ctx, cnDiag *diag) {
    cnCheckOptions o = opt ? *opt : cn_check_options_default();
    Found f;
    cnStatus st = cn_ck_find_contacts(a, &o, &f, diag);
    if (st) return st;
    cnCheckResult r;
    Work w;
    cn_ck_work_init(&w, &f, a, &o, &r, diag, (Reading){0, -1, 0}, false, false);
    bool finished = false;
    st = cn_ck_meet_contacts(&w, &finished);
    if (!st && !finished) {
        cn_ck_classify_nominal(&w);
        if (!r.infeasible && !(st = cn_ck_build_rows(&w))) st = lp(&w, ctx);
    }
    cn_ck_work_free(&w);
    cn_check_result_free(&r);
    cn_ck_found_free(&f);
    return st;
}

typedef struct {
    const double *load;
    double cap, *t;
} LimitAsk;

static cnStatus limit_lp(Work *w, void *ctx) {
    LimitAsk *q = ctx;
    return cn_ck_load_limit_lp(w, q->load, q->cap, q->t, w->diag);
}

cnStatus cn_check_load_limit(const cnAssembly *a, const cnCheckOptions *opt, const double load[3],
                             double cap, double *t, cnDiag *diag) {
    *t = -1;
    LimitAsk q = {load, cap, t};
    return first_reading_lp(a, opt, limit_lp, &q, diag);
}

static cnStatus field_lp(Work *w, void *ctx) {
    int *has = ctx;
    if (w->K + (double)w->Kf * w->D > CN_LIMIT_LP_MAX_COLS) return CN_OK; /* not known: too large */
    LpAnswer ans;
    cnStatus st = cn_ck_static_lp(w, &(LpAsk){0}, &ans, w->lpforce, w->lpfric, w->diag);
    *has = st ? -1 : ans.outcome == LP_FIELD ? 1 : ans.outcome == LP_CERTIFICATE ? 0 : -1;
    return st == CN_ERR_MEMORY ? st : CN_OK;
}

cnStatus cn_check_has_field(const cnAssembly *a, const cnCheckOptions *opt, int *has, cnDiag *diag) {
    *has = -1;
    return first_reading_lp(a, opt, field_lp, has, diag);
}
