/* cairn: the stability verdict of an assembly at rest (the paper's section III-A). */
#ifndef CAIRN_STABILITY_H
#define CAIRN_STABILITY_H

#include "cairn/export.h"

#include <stdbool.h>

#include "cairn/contact.h"
#include "cairn/lcp.h"
#include "cairn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum cnSolverChoice {
    CN_SOLVER_AUTO = 0, /**< frictionless: principal pivoting, Lemke if it fails; friction: Lemke */
    CN_SOLVER_LEMKE = 1,
    CN_SOLVER_PIVOT = 2
} cnSolverChoice;

/** Relative threshold below which a body's acceleration (frictionless) or velocity after one
 *  unit step (friction) counts as zero: a fraction of |g| (and |g| / length for rotations). */
#define CN_DEFAULT_MOTION_TOL 1e-6

/** What a part does during a motion step (paper sec. III-B and IV). */
typedef enum cnRole {
    CN_ROLE_FREE = 0,  /**< stays put unless the mechanics move it (fixed parts stay fixed) */
    CN_ROLE_HELD = 1,  /**< gripped, weight carried: a kinematic body moving at `velocity` */
    CN_ROLE_PUSHED = 2, /**< gripped, driven only along `velocity`: free in every other direction */
    CN_ROLE_CARRIED = 3, /**< moved but not gripped: must keep moving at `velocity` by contact */
    CN_ROLE_STILL = 4    /**< held in place, at rest (used to ask whether a pushed part would fall
                            or tip by itself) */
} cnRole;

/** The state of motion of a step at one instant: the held, pushed and carried parts move
 *  rigidly together (a translation, a turn, or both). */
typedef struct cnMotion {
    const unsigned char *role; /**< per part (cnRole); NULL: every part free */
    cnTwist twist;             /**< velocity of held, pushed and carried parts (may be zero:
                                  a pause between two path segments) */
    double speed;              /**< rate of the path parameter: distance travelled per unit time
                                  by the moved parts' farthest point (0: not moving). Locates
                                  where along the path two surfaces meet. */
    double direction[3];       /**< direction along which pushed parts are driven (unit); zero:
                                  that of twist.v. Pushing is a translation. */
    double dt;                 /**< time step of the friction (impulse-velocity) LCP; 0: 1 */
} cnMotion;

/** Work state carried from one check to the next along a motion path (cnCheckOptions.warm): the
 *  bases of the last contact LCPs, searches already decided, and counters of the solves. Opaque:
 *  made by cn_warm_start_new, freed by cn_warm_start_free. */
typedef struct cnWarmStart cnWarmStart;

/** Counters of the contact LCP solves made with one warm start. */
typedef struct cnWarmStats {
    long solves;            /**< contact LCPs solved */
    long warm_solves;       /**< of them, solved on a remembered basis without pivoting */
    long pivots;            /**< pivots of all the solves */
    double seconds;         /**< wall time in the LCP solves */
    double warm_seconds;    /**< of it, in the solves that were warm-started */
} cnWarmStats;

/** A new warm start (NULL when out of memory); record_only: count the solves but never start one
 *  from a remembered basis (for comparisons). */
CN_API cnWarmStart *cn_warm_start_new(bool record_only);
/** The counters of the solves made with `w` so far. */
CN_API cnWarmStats cn_warm_start_stats(const cnWarmStart *w);
/** Free a warm start and all it holds (NULL: nothing). */
CN_API void cn_warm_start_free(cnWarmStart *w);

/** The verdict of a check (paper sec. III-A; with friction, Pang and Trinkle's strong and weak
 *  stability). */
typedef enum cnVerdict {
    CN_VERDICT_STABLE = 0,   /**< nothing moves: frictionless, the accelerations vanish; with
                                friction, a static solution exists and no solution of the
                                Stewart-Trinkle LCP from rest moves */
    CN_VERDICT_UNSTABLE = 1, /**< no static solution: parts move */
    CN_VERDICT_NOT_GUARANTEED = 2, /**< a static solution exists, but so does a motion from
                                rest; with friction, the assembly stands only if a prestress or a
                                favourable sharing of the load holds it (weakly stable); with or
                                without, where parts touch corner to corner, one reading of the
                                contact normals stands and another moves (corners.disagree) */
    CN_VERDICT_UNDECIDED = 3 /**< with friction: a static solution exists, but the search for a
                                motion from rest ran out of budget before finding one or proving
                                that none exists (undecided says why): no verdict.
                                stable is false and no part is reported moving, so the weak
                                reading (simulation and planning still take it) sees it stable */
} cnVerdict;

/** Why a check gave no verdict (cnCheckResult.undecided): CN_UNDECIDED_NO when it gave one. */
typedef enum cnUndecided {
    CN_UNDECIDED_NO = 0,
    CN_UNDECIDED_BUDGET = 1,    /**< the search for a motion from rest ran out of its LPs
                                     (cnCheckOptions.max_nodes) */
    CN_UNDECIDED_TIME = 2,      /**< ... of its time (cnCheckOptions.max_seconds) */
    CN_UNDECIDED_TOO_LARGE = 3, /**< a group of bodies that contacts join has more complementarity
                                     pairs than the search takes (400): it was not run */
    CN_UNDECIDED_THRESHOLD = 4, /**< solutions moving at the motion threshold could not be told
                                     from still ones */
    CN_UNDECIDED_SOLVER = 5,    /**< the LP solver failed on a node of the search */
    CN_UNDECIDED_MEMORY = 6,    /**< the search ran out of memory */
    CN_UNDECIDED_CORNERS = 7,   /**< every reading of the corner contacts' normals tried stands,
                                     but there are more than CN_CORNER_READINGS */
    CN_UNDECIDED_CORNERS_WIDE = 8 /**< every reading kept stands, but a corner contact's cone had
                                     more ends than CN_CORNER_ENDS */
} cnUndecided;

/** The library's sentence for why a check gave no verdict (a static string; "" for
 *  CN_UNDECIDED_NO), e.g. "the branch-and-bound budget of nodes ran out". */
CN_API const char *cn_undecided_text(cnUndecided why);

/** Where the forces a check reports come from (cnCheckResult.solver.forces_from). */
typedef enum cnForcesFrom {
    CN_FORCES_NONE = 0,     /**< none: no contacts, or nothing solved (the motion is then a
                                 certificate's, see cnCheckResult.unsolved) */
    CN_FORCES_PIVOT = 1,    /**< the contact LCP, by principal pivoting */
    CN_FORCES_LEMKE = 2,    /**< the contact LCP, by Lemke's method (the paper's) */
    CN_FORCES_LP = 3,       /**< the equilibrium LP's static field */
    CN_FORCES_SPARSE_QP = 4 /**< the sparse QP of a large frictionless check (interior point) */
} cnForcesFrom;

/** Its name as the reports write it: "none", "pivot", "lemke", "lp", "interior point". */
CN_API const char *cn_forces_from_name(cnForcesFrom from);

/** How the equilibrium LP's answer was found (cnCheckResult.solver.lp_method). */
typedef enum cnLpMethod {
    CN_LP_METHOD_NONE = 0,           /**< the LP was not solved */
    CN_LP_METHOD_LOAD_DESCENT = 1,   /**< body by body from the top down (cairn's own; LPs of
                                          2,000 columns or more without friction cones) */
    CN_LP_METHOD_INTERIOR_POINT = 2, /**< cairn's interior point on CHOLMOD (LPs of 2,000 columns
                                          or more) */
    CN_LP_METHOD_QP_MOTION = 3,      /**< no static solution, and the sparse QP's verified motion
                                          is the certificate of it */
    CN_LP_METHOD_GLPK_INTERIOR = 4,  /**< GLPK's interior point */
    CN_LP_METHOD_GLPK_SIMPLEX = 5,   /**< GLPK's simplex */
    CN_LP_METHOD_GLPK_ELASTIC = 6,   /**< GLPK's simplex on the elastic LP */
    CN_LP_METHOD_WHOLE = 7           /**< no static solution, shown on the whole assembly taken as
                                          one rigid body on its supports: its motion is the
                                          certificate (LPs of 2,000 columns or more) */
} cnLpMethod;

/** Its name as the reports write it ("load descent", "interior point", "QP motion", "GLPK
 *  interior point", "GLPK simplex", "GLPK simplex, elastic", "whole assembly"); NULL for
 *  CN_LP_METHOD_NONE. */
CN_API const char *cn_lp_method_name(cnLpMethod method);

/** Why the motion reported is the LP certificate's and not the contact LCP's
 *  (cnCheckResult.unsolved): CN_UNSOLVED_NO when it is the LCP's, or there is none. */
typedef enum cnUnsolved {
    CN_UNSOLVED_NO = 0,
    CN_UNSOLVED_RAY = 1,          /**< Lemke's method ended on a secondary ray */
    CN_UNSOLVED_INFEASIBLE = 2,   /**< the LCP was found infeasible */
    CN_UNSOLVED_PIVOTS = 3,       /**< its pivot budget ran out */
    CN_UNSOLVED_NUMERIC = 4,      /**< a singular pivot, or a result that did not verify */
    CN_UNSOLVED_TOO_LARGE = 5,    /**< too large for a dense LCP */
    CN_UNSOLVED_TOO_LARGE_QP = 6, /**< too large for a dense LCP, and the sparse QP's answer did
                                       not verify */
    CN_UNSOLVED_NOT_SOLVED = 7    /**< not solved for another reason */
} cnUnsolved;

/** Its sentence as the reports write it, e.g. "secondary ray" ("" for CN_UNSOLVED_NO). */
CN_API const char *cn_unsolved_text(cnUnsolved why);

/** How a friction verdict "stable" was proved, or that it was not (cnCheckResult.proof). */
typedef enum cnProof {
    CN_PROOF_NONE = 0,        /**< not needed (frictionless, unstable) or not asked */
    CN_PROOF_FRICTIONLESS = 1, /**< a frictionless force field balances gravity: every motion
                                   from rest would raise the potential energy */
    CN_PROOF_SEARCH = 2,      /**< branch and bound over the LCP's complementarity pairs found no
                                   solution that moves */
    CN_PROOF_ACCEPTED = 3,    /**< not proved: accept_prestress takes a static solution as enough */
    CN_PROOF_UNDECIDED = 4,   /**< not proved: the search for a motion from rest found none but
                                   ran out of budget (undecided says why; the verdict is
                                   CN_VERDICT_UNDECIDED) */
    CN_PROOF_SECTION = 5      /**< not proved in 3-D: assume_planar, and the 2-D section of a
                                   prism assembly is proved stable (cnCheckResult.section);
                                   motions out of the section's plane were not ruled out */
} cnProof;

typedef struct cnCheckOptions {
    cnSolverChoice solver;
    bool lp_crosscheck;  /**< frictionless: also decide by LP and fail (numeric) on disagreement */
    double motion_tol;   /**< see CN_DEFAULT_MOTION_TOL */
    cnLcpOptions lcp;
    const cnContactQuery *query; /**< pose of the parts (NULL: as loaded) */
    bool keep_lcp;       /**< keep the (scaled) contact LCP in the result, e.g. to write it out */
    const cnMotion *motion; /**< parts in motion (NULL: all at rest, the static check) */
    bool overlap_is_result; /**< an overlap is reported in the result (infeasible = true) instead
                               of failing with CN_ERR_INPUT: parts in motion may collide */
    cnWarmStart *warm;   /**< in/out: warm start from the previous check, updated (NULL: cold) */
    bool accept_prestress; /**< with friction: a static solution is enough for "stable" (weak
                              stability, the paper's reading), even when a motion from rest
                              exists too; for parts known to be wedged in */
    long max_nodes;      /**< budget of the search for a motion from rest, in LPs (0: the
                            default, 2000; when a gripped part slides on another, 8e6 over the
                            square of the complementarity pairs, within 500..5000), so that
                            verdicts do not depend on the machine's speed */
    bool one_reading;    /**< decide only reading `reading` of the corner contacts' normals
                            (cnCheckResult.corners.reading names the one a result shows), e.g. to
                            see again the motion of the reading that moved */
    unsigned long long reading; /**< with one_reading: 0 .. corners.readings_all - 1 */
    double max_seconds;  /**< wall time each search for a motion from rest may take, at most
                            (0: no limit); past it that search is undecided, a verdict that
                            then depends on the machine's speed (off by default) */
    /** Called now and then during a search for a motion from rest (at most every
     *  CN_PROGRESS_SECONDS) with the LPs solved and the seconds spent; NULL: never. It must not
     *  call cairn or GLPK (it runs inside the search's LP solver guard), and it may be called
     *  from a planner's worker thread. */
    void (*progress)(void *ctx, long lps, double seconds);
    void *progress_ctx;
    unsigned route;      /**< CN_ROUTE_* bits: methods left out, for cross-checks and benchmarks
                            (0: every method; the verdict is the same, the way to it differs) */
    bool assume_planar;  /**< 3-D, with friction: a prism (cnCheckResult.section) whose 2-D
                            section is stable, and whose search for a motion from rest is
                            undecided, is stable (CN_PROOF_SECTION): the motions the search left
                            open, out of the section's plane, are assumed away. A decided verdict
                            is unchanged. Static checks only */
} cnCheckOptions;

/** Methods a check can be told to leave out (cnCheckOptions.route). */
#define CN_ROUTE_NO_SPARSE_QP 1u    /**< the frictionless motion by the sparse QP */
#define CN_ROUTE_NO_LOAD_DESCENT 2u /**< the equilibrium LP by load descent */
#define CN_ROUTE_LP_GLPK_ONLY 4u    /**< large LPs by GLPK only, not cairn's interior point */
#define CN_ROUTE_NO_LEMKE_MOTION 8u /**< with friction, the motion of the LCP's solution by Lemke's
                                         method is not taken as the motion from rest: the search
                                         (or a prism's section) has to find one */
#define CN_ROUTE_NO_WHOLE 16u       /**< large LPs: the whole assembly on its supports is not
                                         tried first (cn_lp_method WHOLE) */

/** Seconds between two progress calls of a check, at least. */
#define CN_PROGRESS_SECONDS 0.25

CN_API cnCheckOptions cn_check_options_default(void);

/** Per-contact results, indexed like the contact set. */
typedef struct cnContactResult {
    double normal_force;   /**< >= 0, absolute units (force; with friction: impulse over 1 s) */
    double friction[3];    /**< friction force vector on body2 (zero when frictionless) */
    double separation;     /**< normal separation acceleration (frictionless) or velocity */
    double slip;           /**< tangential relative acceleration / velocity magnitude */
    bool separates;        /**< the contact opens */
    bool slides;           /**< the contact slides */
    bool unsettled;        /**< undecided: its complementarity (normal or friction) is left
                                unresolved by the LP relaxation of a node the search left open
                                (indicative, as cnPartMotion.unsettled) */
} cnContactResult;

/** Per-part motion that starts, relative to the part's nominal motion (zero for parts that keep
 *  it, and for fixed and held parts). */
typedef struct cnPartMotion {
    bool moves;
    bool unsettled; /**< undecided: the part moves in the LP relaxation of a node the search left
                       open (indicative: a motion left open may move other parts too) */
    double lin[3]; /**< linear acceleration of the centre of mass (friction: change of velocity
                      over one step dt) */
    double ang[3]; /**< angular acceleration (2-D: ang[2]) */
} cnPartMotion;

/** The most readings of the corner contacts' normals one check decides; with more corner
 *  contacts than that covers, a check that stands in every reading tried is undecided. */
#define CN_CORNER_READINGS 64

/** With more readings than CN_CORNER_READINGS and a first reading that stands, the most
 *  readings tried that each turn one loaded corner contact to another end of its cone (most
 *  loaded first): one that moves makes the check not guaranteed instead of undecided. */
#define CN_CORNER_FLIPS 16

/** How a check's verdict and forces were found (JSON "solver"). */
typedef struct cnSolverReport {
    cnForcesFrom forces_from; /**< where the forces come from */
    bool lp_stable;         /**< the equilibrium LP's verdict (the decision itself when friction is
                                 on) */
    cnLpMethod lp_method;   /**< how the LP's answer was found (CN_LP_METHOD_NONE: the LP was not
                                 solved) */
    int lcp_size;           /**< complementarity pairs of the contact LCP (0: not built) */
    int pivots;             /**< pivots of the contact LCP's solve (0: not solved by pivoting) */
    double residual;        /**< the residual of the solve the forces come from (LCP or LP) */
    long search_nodes;      /**< LPs of the search for a motion from rest (0: not searched) */
    cnLcp lcp;              /**< the scaled contact LCP when keep_lcp was set (else n = 0) */
} cnSolverReport;

/** Contacts that touch corner to corner, and the readings of their normals that a check decided
 * (each corner contact taking one end of its cone of normals). */
typedef struct cnCornerReport {
    int count;              /**< contacts that are a corner on a corner (cnContact.corner) */
    int implied;            /**< corners on corners left out because the contacts of their pair at
                                 their point imply them (cn_contact_corner_implied); not in
                                 `count` nor in the contacts */
    long long reading;      /**< the reading whose verdict, forces and motion are shown (its index
                                 for cnCheckOptions.reading; -1: no corner contacts; with
                                 `disagree` the reading that stands, its forces) */
    long long reading_moves; /**< with `disagree`: the reading that moves (the motion shown is
                                  its), else -1 */
    long readings;          /**< readings decided (up to CN_CORNER_READINGS). The verdict is the
                                 worst: stable only if every reading stands, not guaranteed when
                                 one stands and another moves (the motion is the moving one's) */
    double readings_all;    /**< how many readings there are: the product of the corner contacts'
                                 cone ends (2^count when each has two; +inf past a double's
                                 range) */
    double readings_log2;   /**< its base-2 logarithm (finite at any count) */
    bool wide;              /**< a corner contact's cone had more ends than CN_CORNER_ENDS: a check
                                 that stands in every reading kept is undecided */
    bool disagree;          /**< not guaranteed because one reading stands and another moves */
    bool by_field;          /**< stable in every reading at once: a frictionless force field
                                 balances gravity without the corner contacts */
    bool undecided;         /**< undecided because more readings exist than CN_CORNER_READINGS (or
                                 than were kept: `wide`) and every one tried stands */
    bool proof_idle;        /**< with friction, stable by a frictionless force field that puts no
                                 force on a corner contact (so it proves every reading) */
} cnCornerReport;

/** The 2-D section of a 3-D prism assembly, checked when the 3-D friction verdict is
 *  undecided: every part present is an extrusion along coordinate axis `axis`, perpendicular to
 *  gravity, the free parts over one depth and the fixed ones over at least it. */
typedef struct cnSectionReport {
    bool checked;           /**< the section was checked (false: not a prism, or not undecided) */
    int axis;               /**< 0, 1, 2: x, y, z */
    cnVerdict verdict;      /**< the section's verdict */
    cnProof proof;          /**< how the section's stability was proved */
    long search_nodes;      /**< LPs its search took */
    bool lifted;            /**< the section is not guaranteed, and its motion extruded is a
                                 verified motion from rest of the 3-D assembly (the verdict's) */
} cnSectionReport;

typedef struct cnCheckResult {
    bool stable;            /**< verdict == CN_VERDICT_STABLE */
    cnVerdict verdict;
    cnProof proof;          /**< with friction and stable: how no motion from rest was proved */
    cnUndecided undecided;  /**< CN_VERDICT_UNDECIDED: why (CN_UNDECIDED_NO otherwise; its
                                 sentence: cn_undecided_text) */
    double open_speed;      /**< undecided by the search's budget: in every motion from rest it
                               left open, no part starts faster than this (a change of velocity
                               over one step, as `part[].lin`; from the open nodes' bound on
                               gravity's power). Infinite when nothing was bounded (a gripped
                               part sliding on another, or leaves at the threshold), 0 when
                               decided */
    cnUnsolved unsolved;    /**< unstable, but the contact LCP was not solved (why): the motion
                                 in `part` is then the collapse mechanism of the LP's Farkas
                                 certificate (a virtual motion on which gravity does work and no
                                 contact force resists, sized as the acceleration along it), and
                                 the forces are zero; CN_UNSOLVED_NO when the motion is the LCP's */
    bool friction;          /**< the friction model (Stewart-Trinkle) was used */
    cnContactSet contacts;
    cnContactResult *contact; /**< contacts.count entries */
    cnPartMotion *part;     /**< nparts entries */
    int nmoving;
    int *moving;            /**< indices of parts that start to move, in part order */
    double ref_weight;      /**< forces are also reported divided by this */
    int ref_part;           /**< the part whose weight is ref_weight (the heaviest free part), -1 */
    cnSolverReport solver;  /**< how the verdict and forces were found */
    cnCornerReport corners; /**< corner contacts and the readings of their normals */
    int held_unloaded;      /**< contacts between a held part and a free part that carry no
                               force (Proposition 2: the gripper carries the held part's weight,
                               so it presses nothing); 0 when the free parts needed them (the
                               check was decided with them, as for any other contact) */
    bool infeasible;        /**< overlap_is_result and two parts overlap: nothing was solved */
    cnOverlap overlap;      /**< the deepest overlap when infeasible */
    cnSectionReport section; /**< a 3-D prism's 2-D section, when it was checked and the verdict
                                  is undecided, stable by CN_PROOF_SECTION, or not guaranteed by
                                  its lifted motion */
} cnCheckResult;

/** Decide whether the assembly stays put (every free part at rest, every pushed or carried part
 *  keeping its nominal velocity). A held part presses nothing (paper, Proposition 2): the check
 *  is first made without its contacts with free parts (those its motion does not drive it into);
 *  only when that is not stable, because a free part needs the held part's support, are they
 *  taken as any other contact (held_unloaded says which reading decided). Frictionless: Baraff's acceleration LCP (eq. 1); the
 *  accelerations are unique and decide. With friction: the Stewart-Trinkle LCP (eq. 5) for forces
 *  and motion, an LP for the existence of a static solution, and a search for a motion from rest
 *  when one exists (see cnVerdict): a not-guaranteed verdict reports the static solution's forces
 *  (the squeeze it needs) in `contact` and the motion it also admits in `part` and the contacts'
 *  separates/slides. When the search for a motion from rest runs out of budget the verdict is
 *  CN_VERDICT_UNDECIDED (proof CN_PROOF_UNDECIDED), with the static solution's forces. "No static solution" is believed only when the
 *  LP's Farkas certificate verifies, and when the LCP then fails (or is too large) the motion
 *  reported is that certificate's (see `unsolved`). Returns CN_ERR_INPUT when parts overlap,
 *  CN_ERR_NUMERIC when neither a verified solution nor a verified certificate was found. On failure only out->lcp may be set
 *  (with keep_lcp); cn_check_result_free(out) is always safe. */
CN_API cnStatus cn_check(const cnAssembly *a, const cnCheckOptions *opt, cnCheckResult *out,
                  cnDiag *diag);

CN_API void cn_check_result_free(cnCheckResult *r);

#ifdef __cplusplus
}
#endif
#endif
