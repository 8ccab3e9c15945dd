/* The work state of one check (cn_check) and what the check stage's files share of it. Private
 * to the check stage. */
#ifndef CAIRN_CHECK_WORK_H
#define CAIRN_CHECK_WORK_H

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <math.h>
#include <string.h>

#include "mech.h"
#include "solve.h"
#include "proof_memo.h"
#include "strong.h"
#include "warm_start.h"

/* The static limits for the margins (check_limit.h) are left unknown past this many LP columns:
 * GLPK's simplex alone would take long. */
#define CN_LIMIT_LP_MAX_COLS 20000
/* Corner contacts carrying at most this fraction of the reference weight (normal force and
 * friction) are idle in a static field: leaving them out changes its equilibrium by less than
 * a millionth of what the LP's verification accepts (CN_LP_EQ_TOL). */
#define CN_CORNER_IDLE 1e-13
/* Equilibrium residual accepted for an LP solution, relative to the reference weight. */
#define CN_LP_EQ_TOL 1e-7
/* Above this size the automatic choice skips principal pivoting, whose every step refactorises
 * the clamped block (O(|C|^3)), and goes to Lemke (O(n^2) per pivot). */
#define CN_PIVOT_MAX_AUTO 200

/* How the nominal motion meets a contact. */
enum { NOM_STICK = 0, NOM_SLIDE = 1, NOM_OPEN = 2, NOM_CLOSE = 3 };

/* A reading of the corner contacts' normals: by index (cn_ck_meet_contacts), or with one corner
 * (the one-th, from 0) taking end `end` and every other its first end (one >= 0). */
typedef struct {
    unsigned long long index;
    int one, end;
} Reading;

/* The contacts of the assembly, found once per check (cn_check) and copied into each reading:
 * the set as cn_contacts_find numbered it, its deepest overlap, and which of its corner contacts
 * the faces of their pair imply (cn_contact_corner_implied); section, set by cn_check. */
typedef struct {
    cnContactSet cs;
    cnOverlap ov;
    unsigned char *implied;
    struct cnSectionCache *section; /* a static 3-D check's 2-D section, checked by the first
                                       reading that searches for a motion (NULL: none) */
} Found;

/* The solver steps of a check's route (cn_ck_route), in the order they may run. */
typedef enum {
    STEP_FIELD_FIRST,  /* with friction, large: a frictionless field sought first */
    STEP_LP,           /* large: the equilibrium LP first */
    STEP_LP_DEFERRING, /* ... frictionless and large: its interior point left until after the QP */
    STEP_SPARSE_QP,    /* frictionless: the sparse QP (first when large, else after the LCP) */
    STEP_LP_RESUMED,   /* the deferred LP in full, when the QP gave no verified answer */
    STEP_DENSE_LCP,    /* the dense LCP, when it fits in CN_DENSE_LCP_MAX_BYTES */
    STEP_TOO_LARGE,    /* no LCP fits: the LP's certificate gives the motion, or no verdict */
    STEP_LP_CHECK,     /* the LCP's answer read, and the LP where that answer needs it */
} CheckStep;
#define CN_ROUTE_STEPS 8

/* What the equilibrium LP (cn_ck_static_lp) is asked for. */
typedef struct {
    bool nofric;            /* frictionless: normal forces only */
    bool field_only;        /* a field or nothing (the frictionless LP before the friction one): no
                               certificate and no GLPK fallbacks when the interior point finds none */
    bool defer_cert;        /* may stop after the load descent, its interior point left until
                               after the sparse QP */
    bool resumed;           /* after a deferral: the load descent is known to fail */
    const double *cert_try; /* nb * nd, or NULL: a motion tried as the certificate first */
} LpAsk;

/* How the equilibrium LP ended (out of memory is a status; a numerical failure is LP_UNDECIDED,
 * which the model's callers turn into CN_ERR_NUMERIC with cn_ck_lp_failure). */
typedef enum {
    LP_FIELD,       /* a verified static field, in force and fric */
    LP_CERTIFICATE, /* none: a verified Farkas certificate, in Work.cert */
    LP_DEFERRED,    /* asked to defer: the load descent found no field, nothing else ran */
    LP_ABSENT,      /* field_only: the interior point found no field; the friction LP decides */
    LP_NONE,        /* not run: a part is driven into another, nothing static to find */
    LP_UNDECIDED,   /* neither a field nor a certificate verifies (cn_ck_lp_failure says so) */
} LpOutcome;

typedef struct {
    LpOutcome outcome;
    double residual;    /* the best equilibrium residual found (relative to W) */
    cnLpMethod method;  /* field or certificate: the last method tried */
    int rows, cols;     /* the LP's size */
    bool glpk_error;    /* undecided: GLPK stopped on an internal error */
} LpAnswer;

typedef struct {
    const cnAssembly *a;
    const Found *found;
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
    double lp_residual; /* verified residual of the model's LP answer (relative to W) */
    cnLpMethod lp_method; /* how the model's LP answer was found */
    double *cert;       /* nb * nd: when the LP has no solution, its verified Farkas certificate:
                           a virtual motion (velocity per dof) with f_ext . cert > 0 */
    bool has_cert;      /* cert holds the certificate of the model's equilibrium LP */
    bool cert_deferred; /* the model's LP waits for the sparse QP: its descent found no field */
    double *qp_motion; /* nb * nd: the sparse QP's own accelerations, when a certificate waits */
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
    cnUnsolved lcp_why;          /* why the LCP was not solved */
    bool qp_failed;              /* the sparse QP was tried and its answer did not verify */
    bool lp_done, lp_feasible;   /* the LP ran; it found a static solution */
    bool lp_trusted;             /* ran first, and its static solution decides (no LCP) */
    bool nf_done, nf_proved;     /* with friction: the frictionless field was sought first
                                    (frictionless_first); it proves that nothing moves */
    bool lcp_ok, lcp_static;     /* the LCP was solved; its solution is static */
    bool squeezed;   /* frictionless LCP motion carried by forces above CN_SQUEEZE_WEIGHTS */
    int rounding_body; /* frictionless: a part whose LCP motion is within rounding (-1 none) */
    Reading reading; /* the reading of the corner contacts' normals (cn_ck_meet_contacts) */
    bool drop_corners;           /* leave the corner contacts out altogether */
    bool held_unloaded;          /* leave out the contacts of held parts with free parts */
    int ncorners;                /* contacts that are a corner on a corner */
    double readings, readings_log2; /* their readings: the product of their cones' ends */
    bool corners_wide;           /* a corner contact's cone had more ends than were kept */
} Work;

cnStatus cn_ck_build_lcp(const Work *w, int n, bool friction, cnLcp *lcp, double *dscale);
cnStatus cn_ck_build_rows(Work *w);
void cn_ck_classify_nominal(Work *w);
/* A reading's work on the contacts found, before its stages: the options o (the caller's copy,
 * alive as long as w), result r (zeroed here), the reading and its corner handling. */
void cn_ck_work_init(Work *w, const Found *found, const cnAssembly *a, const cnCheckOptions *o,
                     cnCheckResult *r, cnDiag *diag, Reading reading, bool drop, bool unload);
void cn_ck_work_free(Work *w);
void cn_ck_cert_motion(const Work *w, double *acc);
cnStatus cn_ck_check_reading(const Found *found, const cnAssembly *a, const cnCheckOptions *opt,
                             cnCheckResult *r, cnDiag *diag, Reading reading, bool drop, bool unload,
                             int *ncorners);
cnStatus cn_ck_find_contacts(const cnAssembly *a, const cnCheckOptions *o, Found *f, cnDiag *diag);
void cn_ck_found_free(Found *f);
void cn_ck_fill_result(Work *w, cnCheckResult *r, const double *force, const double (*fric)[3],
                       const double *acc, double tol);
bool cn_ck_lemke_motion_holds(const Work *w, const cnMotionProblem *p, const double *force,
                              const double *z, double *acc);
const char *cn_ck_mass_span(const Work *w, char *buf, size_t cap);
cnStatus cn_ck_meet_contacts(Work *w, bool *finished);
bool cn_ck_motion_problem(const Work *w, const cnCheckOptions *o, double *nominal,
                          cnMotionProblem *p);
cnStatus cn_ck_prove_still(Work *w, const cnMotionProblem *p, bool energy, cnCheckResult *r,
                           double *force, double *acc, cnMotionAnswer *ans, cnDiag *diag);
int cn_ck_route(int n, bool friction, CheckStep steps[CN_ROUTE_STEPS]);
cnStatus cn_ck_solve_models(Work *w);
cnStatus cn_ck_static_lp(Work *w, const LpAsk *ask, LpAnswer *ans, double *force,
                         double (*fric)[3], cnDiag *diag);
cnStatus cn_ck_lp_failure(const Work *w, const LpAnswer *ans, cnDiag *diag);
cnStatus cn_ck_load_limit_lp(Work *w, const double load[3], double cap, double *t, cnDiag *diag);
cnLcpStatus cn_ck_warm_solve(cnWarmStart *ws, const cnContactSet *cs, const int *fric_of, int Kf,
                             int D, const cnLcp *p, cnSolverChoice choice, bool symmetric_psd,
                             const cnLcpOptions *o, double *z, double *wv, cnLcpInfo *info,
                             cnForcesFrom *used);

#endif
