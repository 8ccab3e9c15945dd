/* Is there a motion from rest? The second half of the friction verdict (strong stability, Pang
 * and Trinkle 2000): a static force field may exist (the LP) while the Stewart-Trinkle LCP also
 * admits a motion, e.g. a block held only by a squeeze that nothing applies. Private to the
 * library. */
#ifndef CAIRN_STRONG_H
#define CAIRN_STRONG_H

#include "mech.h"

/* The contact LCP of one instant, as the search reads it (see still.c for how it is made):
 * K normal rows then Kf*D friction rows, each a cnJRow of the mechanics m. */
typedef struct cnMotionProblem {
    const cnMech *m;
    int K, Kf, D;
    const cnJRow *rows;         /* K + Kf*D. With D >= 3 a friction contact's D rows must be
                                   unit directions in angular order about its normal (either
                                   way), consecutive ones (and the last and the first) less
                                   than pi apart: the search's sliding modes rest on it
                                   (search_joint.c, cn_bb_mode). With D = 2, +t then -t. */
    const int *contact_of_fric; /* Kf: the contact of each friction contact */
    const double *mu;           /* Kf */
    const double *nominal;      /* Kf*D: nominal relative velocity / dt along each friction row
                                   (nonzero where a gripped part slides on another); NULL: none */
    double motion_tol;          /* a body moves when its motion exceeds this fraction of g */
    long max_nodes;             /* branch-and-bound budget (0: cn_motion_energy_budget, or
                                   cn_motion_drag_budget with nominal sliding) */
    bool pointwise;             /* branch on each contact by itself, no joint patterns (for
                                   cross-checks) */
    double max_seconds;         /* wall time at most (0: none); past it, UNDECIDED */
    void (*progress)(void *ctx, long lps, double seconds); /* NULL, or called at most every
                                   CN_PROGRESS_SECONDS */
    void *progress_ctx;
    bool no_learning;           /* prune by LP bounds alone, never by learned sets (for
                                   cross-checks) */
    const double *field;        /* NULL, or a static field (K + Kf*D forces, absolute): where a
                                   motion of one body held among the rest is extended to the
                                   whole, the rest's field beyond its neighbours (search_local.c) */
    int floors;                 /* the normal-force floors of 2-D joints in the energy cuts
                                   (search_lp.c): 0 in a second pass when a budget of
                                   CN_BB_FLOOR_MIN_BUDGET or more ran out, 1 from the start,
                                   -1 never (for cross-checks) */
} cnMotionProblem;

/* Does nominal sliding drag a body? Only along a friction row that touches one: between two
 * parts that are not bodies of the problem (a held part on the table) its forces act on nothing,
 * and the energy argument holds. nominal: Kf*D entries, or NULL. */
static inline bool cn_motion_drags(const cnJRow *rows, int K, int Kf, int D, const double *nominal) {
    for (int i = 0; nominal && i < Kf * D; i++)
        if (nominal[i] != 0 && (rows[K + i].body[0] >= 0 || rows[K + i].body[1] >= 0)) return true;
    return false;
}

/* Complementarity pairs of a group of bodies beyond which its search is not started (its LPs
 * would take seconds each): undecided unless the frictionless certificate holds. The pairs are
 * the search's own, its friction groups merged (cn_motion_search_pairs): the two points of a 2-D
 * joint carry one set of friction rows, so a 2-D joint counts 5 pairs, not 8. */
#define CN_MOTION_MAX_PAIRS 400
/* Past this many pairs point by point, the friction groups are not sought for the count (a
 * quadratic pass); the count is then the points'. */
#define CN_SEARCH_PAIRS_GROUPED_UPTO (4 * CN_MOTION_MAX_PAIRS)

/* The complementarity pairs of p's search: K + G (D + 1) for its G friction groups (search_lp.c),
 * or the points' count, K + Kf (D + 1), past CN_SEARCH_PAIRS_GROUPED_UPTO (or out of memory). */
int cn_motion_search_pairs(const cnMotionProblem *p);

/* Once a group of bodies is undecided the whole cannot be proved still, and a later group can
 * only make it not guaranteed by a motion: its default budget is at most this (LPs). */
#define CN_MOTION_AFTER_UNDECIDED 500

/* Default budgets of the search (LPs): with the energy bound; and in all (shared by the motion
 * components) when a gripped part slides on another (no energy bound), CN_MOTION_DRAG_WORK
 * divided by the square of the complementarity pairs, within the two limits. The square: a search's LPs
 * grow with the pairs, and so does each LP; a small drag (a box pushed along a table) gets the
 * most, the large drags of a planner the least. */
#define CN_MOTION_MAX_NODES 2000
/* With the energy bound, a small problem gets more: CN_MOTION_WORK divided by the square of its
 * complementarity pairs, between CN_MOTION_MAX_NODES and CN_MOTION_MAX_NODES_SMALL (two boxes on
 * a table, a wedge between two supports: 80 pairs, 7,812 LPs; 159 pairs and up, 2,000), so that
 * what a few thousand LPs decide is decided at the default, while a large search that will not
 * end stops about as soon as before. */
#define CN_MOTION_WORK 50000000
#define CN_MOTION_MAX_NODES_SMALL 20000
#define CN_MOTION_DRAG_WORK 8000000
#define CN_MOTION_MIN_NODES_DRAG 500
#define CN_MOTION_MAX_NODES_DRAG 5000

static inline long cn_motion_energy_budget(int pairs) {
    long b = pairs > 0 ? CN_MOTION_WORK / ((long)pairs * pairs) : CN_MOTION_MAX_NODES_SMALL;
    return b < CN_MOTION_MAX_NODES ? CN_MOTION_MAX_NODES : b > CN_MOTION_MAX_NODES_SMALL ? CN_MOTION_MAX_NODES_SMALL : b;
}

static inline long cn_motion_drag_budget(int pairs) {
    long b = pairs > 0 ? CN_MOTION_DRAG_WORK / ((long)pairs * pairs) : CN_MOTION_MAX_NODES_DRAG;
    return b < CN_MOTION_MIN_NODES_DRAG ? CN_MOTION_MIN_NODES_DRAG
         : b > CN_MOTION_MAX_NODES_DRAG ? CN_MOTION_MAX_NODES_DRAG : b;
}

typedef enum cnMotionAnswer {
    CN_MOTION_NONE = 0,      /* proved: no solution from rest moves */
    CN_MOTION_FOUND = 1,     /* a verified solution that moves (force, acc filled) */
    CN_MOTION_UNDECIDED = 2  /* the budget ran out, or the LP solver failed, before either */
} cnMotionAnswer;

typedef struct cnMotionStats {
    long nodes;        /* branch-and-bound nodes (LPs solved) */
    long local_lps;    /* LPs of the searches of single bodies held among the rest
                          (cn_local_motion), after an undecided search */
    long budget;       /* the LPs it was given */
    long default_budget; /* ... and the default for this problem (max_nodes 0) */
    int depth;         /* deepest node */
    int joints;        /* joints whose points were branched on together (search_joint.c) */
    long learned;      /* nodes pruned by a learned set, without an LP (search_learn.c) */
    bool certificate;  /* decided by the frictionless certificate alone */
    int floors;        /* friction groups given a positive normal-force floor (search_lp.c) */
    double bound;      /* proved: every motion has |a|_M below this (absolute); else 0 */
    cnUndecided why;   /* UNDECIDED: what stopped the search */
    double open_power; /* UNDECIDED by the budget: gravity's power in every motion not ruled out
                          is at most this (absolute), so |a|_M^2 is too (a^T M a <= fext.a);
                          inf when the root was never solved */
    unsigned char *open_bodies; /* in: NULL, or nb flags that receive, when UNDECIDED by the
                                   budget, the bodies that move in the LP solutions of the open
                                   nodes' parents (indicative, not a proof that others stay) */
    unsigned char *open_contacts; /* in: NULL, or K flags that receive, when UNDECIDED, the
                                   contacts whose complementarity (normal or friction) those LP
                                   solutions leave unresolved (every contact when no node was
                                   solved) */
} cnMotionStats;

/* Bound every motion from rest by a frictionless force field f (K normal forces, >= 0, absolute):
 * with r = fext + J_n^T f, any solution of the LCP from rest has |a|_M <= |r|_{M^-1} (Gauss:
 * a^T M a <= fext.a = r.a - f.J_n a <= r.a). Returns that bound; *proved is set when it keeps
 * every body below motion_tol. Valid only without nominally sliding friction contacts. */
double cn_motion_frictionless_bound(const cnMotionProblem *p, const double *force, bool *proved);

/* A solution (cn_motion_verify) counts as a motion only when its largest motion (in g) is this
 * many times its largest violation (scaled): at the default motion threshold (1e-6) every
 * solution within the verification's tolerance (1e-7) qualifies; under a finer one (a margin's
 * verdicts, 1e-9) a large LCP's rounding (a residual of 1e-8 on a wall of 400 bricks) would
 * otherwise pass for a motion of the whole wall. */
#define CN_VERIFY_MOTION_OVER 10.0

/* Check a solution of the LCP found elsewhere (e.g. by Lemke) with the search's per-contact
 * tolerances: force (K + Kf*D) and lambda (Kf, sliding speeds / dt) absolute; acc receives the
 * motion. 1: a solution that moves, 0: one that does not, -1: not a solution at this accuracy
 * (or a motion that its violations could account for). */
int cn_motion_verify(const cnMotionProblem *p, const double *force, const double *lambda,
                     double *acc);

/* Decide whether a solution of the Stewart-Trinkle LCP moves, group by group of the bodies that
 * contacts join (search_split.c): branch and bound over its complementarity pairs, an LP
 * (GLPK) at each node. Without nominal sliding the LP maximises the
 * power of gravity, which every motion makes positive (a^T M a <= fext.a); with it, each
 * component of every body's motion in turn. FOUND fills force (K + Kf*D, absolute) and acc
 * (nb*nd, the motion that starts), both verified against the LCP's conditions here. */
cnStatus cn_motion_search(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                          double *acc, cnMotionStats *stats, cnDiag *diag);

/* Motions of one body held among the rest (search_local.c), for a problem whose own search
 * left it undecided or was not started: each body's search alone (at most CN_LOCAL_LPS LPs),
 * its motion extended to the whole by a static field of the rest (an LP about it, p->field
 * beyond) and verified (cn_motion_verify). FOUND fills force and acc as cn_motion_search does;
 * NONE proves nothing. At most max_lps LPs in all (*lps: how many) and max_seconds. */
cnStatus cn_local_motion(const cnMotionProblem *p, long max_lps, double max_seconds,
                         cnMotionAnswer *answer, double *force, double *acc, long *lps, cnDiag *diag);
#define CN_LOCAL_LPS 100
/* ... and in all at most the group's default budget divided by this (a wall's end brick, or two
 * blocks, are found within a few hundred LPs; a 3-D vault whose parts all hold takes them all) */
#define CN_LOCAL_SHARE 4
/* The bodies an LP may rebalance when the moving ones (flags) change their forces: each moving
 * body's chain down to a fixed part (by contacts, towards the nearest) and every body in contact
 * with those, the moving ones included: in (nb flags). 0, or -1 out of memory. */
int cn_local_chain_ring(const cnMotionProblem *p, const unsigned char *moving, unsigned char *in);

/* A body's degree of freedom d in the LPs' units: g per unit, a rotation times the body's radius
 * (1 without one). */
static inline double cn_motion_dof_unit(const cnMech *m, int b, int d) {
    return (d < m->dim ? 1.0 : (m->radius[b] > 0 ? m->radius[b] : 1.0)) / m->g;
}

/* Masses spanning more than this factor are named when a verdict fails numerically, and keep
 * the sparse QP out (its iterations mix the scales, where the lighter parts' balance is lost to
 * rounding). */
#define CN_MASS_SPAN_RESOLVED 1e8

/* The frictionless motion by the sparse QP (motion_qp.c): K normal rows of m; force (K,
 * absolute) and acc (the bodies' accelerations) receive a verified solution of the frictionless
 * LCP when *solved: its natural residual, scaled as the dense LCP's verification scales it
 * (cn_lcp_residual on the LCP of build_lcp), at most tol (0: CN_LCP_DEFAULT_TOL); *residual is
 * that residual. Not attempted (*solved false, no error) when a body is pushed (its inverse mass
 * is singular) or the masses span more than CN_MASS_SPAN_RESOLVED. motion (nb * nd, or NULL)
 * receives the QP's own accelerations, unverified: they hold its closed contacts closed more
 * exactly than acc, which carries the forces' rounding. *polish_moves (when not NULL): how many
 * times the QP's polish moved a contact after its guess of the held ones (cnQpIpmInfo.moves),
 * or -1 when no polish ran to its end (the interior point converged, or the polish failed).
 * Errors: out of memory only. */
bool cn_motion_qp_usable(const cnMech *m);
cnStatus cn_motion_qp(const cnMech *m, const cnJRow *rows, int K, double tol, double *force, double *acc,
                      double *motion, bool *solved, double *residual, int *polish_moves, cnDiag *diag);

#endif
