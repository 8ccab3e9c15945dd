/* cairn: simulating a disassembly plan along its motion paths (paper sec. III-B, Algorithm 1). */
#ifndef CAIRN_SIMULATE_H
#define CAIRN_SIMULATE_H

#include "cairn/export.h"

#include <stdbool.h>

#include "cairn/margin.h"
#include "cairn/stability.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Outcome of one step. */
typedef enum cnStepStatus {
    CN_STEP_STABLE = 0,     /**< every sample stable, and the state after the step too */
    CN_STEP_UNSTABLE = 1,   /**< some part other than the moved ones starts to move */
    CN_STEP_INFEASIBLE = 2, /**< the moved parts would penetrate a part that does not move */
    CN_STEP_SKIPPED = 3,    /**< not simulated: an earlier step failed (Proposition 1) */
    CN_STEP_UNDECIDED = 4   /**< with friction, a sample (or the state after the step) is
                                 undecided: a static solution exists, but the search for a motion
                                 from rest ran out of budget (cnCheckResult.undecided).
                                 Not stable: the run stops there, as at an instability */
} cnStepStatus;

/** One contact at one sample, for histories and plots. */
typedef struct cnSimContact {
    int id;               /**< the contact's id at that sample */
    int body1, body2;     /**< part indices (body1 = CN_WORLD for a fixel) */
    int vertex;           /**< the vertex number at the point, or 0 */
    double point[3];
    double normal[3];
    double force;         /**< absolute */
    double motion;        /**< normal separation acceleration (friction: velocity change / dt) */
    bool separates, slides;
} cnSimContact;

/** One sample of a step. */
typedef struct cnSimSample {
    int step;
    double time;          /**< from the start of the plan */
    double step_time;     /**< from the start of the step */
    double distance;      /**< along the path */
    double disp[3];       /**< displacement of the moved parts (a path with turns: of their
                             centre of mass) */
    double angle;         /**< how far they have turned, radians (2-D: counter-clockwise
                             positive; 3-D: the rotation's angle, >= 0) */
    cnPose pose;          /**< their pose */
    bool stable;
    bool held;            /**< the gripper carries the moved parts' weight at this sample */
    int first, count;     /**< its contacts in cnSimResult.contacts */
    double margin[3];     /**< with cnSimOptions.margin: the critical friction, tilt (radians) and
                             lateral factor (g) at this sample (cnMargin.value); NAN where not
                             found (not asked, not a sample the margins were taken at, or a
                             step that was not stable) */
} cnSimSample;

/** Contact events sampled per segment of a step (move or turn), at most (cnStepResult.nevents);
 *  more are counted in events_dropped and the report warns. */
#define CN_SIM_MAX_EVENTS 4096

/** An interval of a pushed step in which the gripper carried a part's weight. */
typedef struct cnCarryInterval {
    double t0, t1;        /**< from, to (absolute time, t0 <= t1; t1 is where it could rest
                             again, or the step's end or onset) */
    int part;             /**< the gripped part */
    bool released;        /**< it ended because the part could rest by itself again (else the
                             step ended, or failed, while it was carried) */
} cnCarryInterval;

/** The weakest sample of a stable step for one margin (cnSimOptions.margin): the largest
 *  critical friction, the smallest tilt or lateral factor over the samples whose margin was
 *  found. */
typedef struct cnStepMargin {
    bool computed;        /**< found at `samples` samples (a stable step, this margin asked) */
    int samples;
    int sample;           /**< the weakest one, an index into cnSimResult.samples */
    double time, step_time, distance; /**< where it is on the path */
    cnMargin at;          /**< its margin (value, direction, the collapse mechanism there) */
} cnStepMargin;

/** Samples of one step whose margins are found, at most (cnSimOptions.margin_samples 0): evenly
 *  spread over the step's samples, the first and the last among them. */
#define CN_SIM_MARGIN_SAMPLES 24
/** A path's margins are found to this relative tolerance when cnSimOptions.margin's rel_tol is 0:
 *  coarser than a check's (CN_MARGIN_DEFAULT_REL_TOL), as each of up to CN_SIM_MARGIN_SAMPLES
 *  samples is a margin of its own. */
#define CN_SIM_MARGIN_REL_TOL 1e-4

typedef struct cnStepResult {
    cnStepStatus status;
    double t0, t1;        /**< plan time at the step's start and end */
    double length;        /**< path length */
    double weight;        /**< weight of the moved parts (forces are normalized by it) */
    bool has_onset;       /**< instability or infeasibility located */
    double onset_time, onset_step_time, onset_distance, onset_disp[3];
    double onset_angle;   /**< the moved parts' turn at the onset, radians (as cnSimSample.angle) */
    cnPose onset_pose;    /**< their pose at the onset */
    bool onset_after;     /**< the instability appears when the moved parts are taken away at the
                             end of the path (their detachment), not during the motion */
    cnCheckResult onset;  /**< the check at the onset (moving parts, contacts) when unstable;
                             when undecided, the undecided check (its static forces) */
    int blocking_part;    /**< infeasible: the part that blocks, else -1 */
    int blocked_part;     /**< infeasible: the moved part that would penetrate it */
    double depth;         /**< infeasible: penetration at the onset */
    bool took_weight;     /**< push: the gripper carried the pushed part's weight somewhere on
                             the path (ncarry > 0) */
    double took_weight_time; /**< when it first did (carry[0].t0) */
    int took_weight_part;
    int ncarry;           /**< push: intervals in which the gripper carried the pushed part, because
                             it could not rest by itself (with every other part held still); its
                             weight is back on its supports outside them (paper, sec. IV) */
    cnCarryInterval *carry; /**< ncarry intervals, in time order (owned) */
    int nevents;          /**< contact events of its segments (where a contact can begin or end:
                             along a move, cn_contact_events; along a turn,
                             cn_contact_events_turn), each sampled at it and just after it */
    int events_dropped;   /**< events beyond the per-segment cap, not sampled */
    int first_sample, nsamples;
    cnStepMargin margin[3]; /**< with cnSimOptions.margin, a stable step: its weakest sample's
                               friction, tilt and lateral margin (the kinds asked) */
    double sampled_to;    /**< undecided: the sampling stopped after CN_SIM_MAX_UNDECIDED undecided
                             samples, here along the path (of `length`); the rest was not checked.
                             Else the path's length */
} cnStepResult;

/** Undecided samples of one step after which its sampling stops (the step is undecided either
 *  way; the samples after the first undecided one are only looked at for one proved unstable,
 *  which decides the step). Bounds a long path whose every sample is undecided. */
#define CN_SIM_MAX_UNDECIDED 64

typedef struct cnSimResult {
    bool stable;          /**< every step stable */
    bool undecided;       /**< no verdict: the step that stopped the run is CN_STEP_UNDECIDED
                             (no step failed before it) */
    bool assemble;        /**< the plan was run as an assembly (reversed) */
    int nsteps;
    cnStepResult *steps;  /**< in the order simulated (assembly: reversed plan order) */
    int *plan_index;      /**< the plan step each simulated step is */
    int nsamples;
    cnSimSample *samples;
    int ncontacts, capcontacts;
    cnSimContact *contacts;
    /* the contact LCPs along the paths (samples and bisection) */
    long lcp_solves;      /**< solved */
    long lcp_warm;        /**< of them, solved on the previous sample's basis without pivoting */
    long lcp_pivots;      /**< pivots in all */
    double lcp_seconds;   /**< wall time in the solves (not reported by default: it varies) */
    double lcp_warm_seconds; /**< of it, in the warm-started solves */
} cnSimResult;

typedef struct cnSimOptions {
    cnCheckOptions check;
    bool assemble;        /**< run the plan as an assembly: steps reversed, paths reversed */
    double bisect_tol;    /**< onset located to this fraction of the path length (1e-6) */
    int max_samples;      /**< samples of a step at most (0: CN_MAX_SAMPLES); beyond, the path is
                             sampled more coarsely (bisection still locates an onset) */
    bool cold;            /**< solve every sample's LCP from scratch: no warm start from the
                             previous sample's basis (for comparisons; the verdicts are the same) */
    bool stop_at_undecided; /**< end a step at its first undecided sample (the planner: it needs
                                 only "not stable"); by default the path is sampled on, so that a
                                 later sample proved unstable or infeasible decides the step, and
                                 the step is undecided only when none is */
    /** Called now and then while a plan is simulated (at most every progress_every seconds,
     *  default 0.25, from the calling thread) with the step being simulated (0-based), the
     *  number of steps, the samples taken so far and the seconds spent, for a progress display;
     *  NULL (the default): never. It must not call into the library. */
    void (*progress)(void *ctx, int step, int nsteps, long samples, double seconds);
    void *progress_ctx;
    double progress_every;
    /** NULL (the default): no margins. Else, for each stable step, the margins these options ask
     *  for (kinds, axis, direction, pair, rel_tol; their check options are replaced by `check`
     *  above) at up to margin_samples of its samples, each decided by this simulation's own
     *  rules (the gripper's roles, a held part pressing nothing, a pushed part's weight); the
     *  state after the step is not among them (it is the next step's state before). */
    const cnMarginOptions *margin;
    int margin_samples;   /**< 0: CN_SIM_MARGIN_SAMPLES */
} cnSimOptions;

CN_API cnSimOptions cn_sim_options_default(void);

/** Simulate the assembly's plan. The state before a step must be stable for the step to be
 *  simulated; the moved parts are taken away after it. Returns CN_ERR_INPUT when there is no
 *  plan, CN_ERR_NUMERIC when a check cannot be decided. */
CN_API cnStatus cn_simulate(const cnAssembly *a, const cnSimOptions *opt, cnSimResult *out, cnDiag *diag);

CN_API void cn_sim_result_free(cnSimResult *r);

/** Simulate one step from a given state (the parts flagged in `absent` are gone; the plan's
 *  gripper bodies other than st->gripper should be flagged too), including the check of the state
 *  after it (its parts taken away). The state before is assumed stable. `out->onset` must be
 *  freed with cn_check_result_free (cn_step_result_free does it). Margins are not found here
 *  (opt->margin is ignored): cn_simulate finds them. */
CN_API cnStatus cn_simulate_step(const cnAssembly *a, const unsigned char *absent, const cnPlanStep *st,
                          const cnSimOptions *opt, cnStepResult *out, cnDiag *diag);

CN_API void cn_step_result_free(cnStepResult *r);

#ifdef __cplusplus
}
#endif
#endif
