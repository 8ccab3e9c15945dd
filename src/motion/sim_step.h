/* Simulating a plan along its paths (simulate.c): the work state of one step and the steps'
 * shared pieces, the path (sim_path.c), a sample's check (sim_sample.c), the onset located by
 * bisection (sim_onset.c) and the margins along a step (sim_margin.c). Private to src/motion/. */
#ifndef CAIRN_SIM_STEP_H
#define CAIRN_SIM_STEP_H

#include <time.h>

#include "pieces.h"
#include "cairn/simulate.h"

/* Bisection stops when the interval is below this fraction of the path length. */
#define SIM_BISECT_TOL 1e-6

/* The work state of one step. */
typedef struct {
    const cnAssembly *a;
    const cnSimOptions *o;
    const cnPlanStep *st;
    int nseg;
    cnSegment *seg;       /* traversal segments (assembly: reversed and inverted) */
    double *seglen;       /* their lengths: the distance the moved parts' farthest point travels */
    cnPose start;         /* pose of the moved parts at distance 0 */
    double length;
    double com[3];        /* the moved parts' centre of mass as loaded (reported displacements) */
    unsigned char *absent;
    cnPose *pose;         /* per part */
    unsigned char *role;
    cnTwist *vel;         /* per part velocity (contact tie-breaking) */
    bool held;            /* push switched to hold */
    bool after_known;     /* the caller proved the state after the step stable with the same
                             check options (the planner, by Proposition 1's check of that
                             state): that check is not repeated (cn_sm_simulate_step) */
    long later_budget;    /* after an undecided sample: the search budget of the later ones (0: the
                             options'), which are only looked at for a motion that is found */
    cnWarmStart *warm;    /* the previous sample's LCP basis, and the solve counters */
    struct timespec t0;   /* when the simulation started (progress) */
    double progress_at;   /* seconds into it of the last progress call */
    int nsteps;           /* steps of the plan (progress) */
    double *rec_s;        /* the step's recorded samples: distance, and leaving a junction */
    unsigned char *rec_leave;
    int nrec, caprec;
} Step;

/* Where the path is at one distance. */
typedef struct {
    cnPose pose;          /* of the moved parts */
    cnTwist unit;         /* their velocity at unit path speed (zero at the very start of a
                             zero-length path) */
    double dir[3];        /* a move: its unit direction; a turn: zero */
    bool turn;            /* the segment being travelled is a turn */
    bool paused;          /* at a segment's end (see path_at) */
} PathPoint;

/* A sample's check options and what they point to (cn_sm_pose_check). */
typedef struct {
    cnCheckOptions check;
    cnContactQuery query;
    cnMotion motion;
} cnSamplePose;

typedef enum { EV_STABLE = 0, EV_UNSTABLE = 1, EV_INFEASIBLE = 2, EV_UNDECIDED = 3 } EvStatus;

/* sim_path.c: the path of a step and its samples */
void cn_sm_path_at(const Step *S, double s, bool leave, PathPoint *pp);
bool cn_sm_always_held(const cnAssembly *a, const PathPoint *pp);
void cn_sm_reported_disp(const Step *S, const cnPose *ps, double disp[3]);
int cn_sm_step_alloc(Step *S, int maxseg);
void cn_sm_step_free(Step *S);
void cn_sm_step_setup(Step *S, const cnPlanStep *st, bool assemble);
void cn_sm_set_onset_pose(const Step *S, double s, cnStepResult *out);
cnStatus cn_sm_event_samples(Step *S, double **sv, unsigned char **lv, int *nsamp, cnStepResult *out);

/* sim_sample.c: a sample's check, and its record */
cnStepStatus cn_sm_step_status(EvStatus ev);
void cn_sm_pose_check(Step *S, double s, bool leave, const cnCheckOptions *base, cnSamplePose *sp);
cnStatus cn_sm_eval(Step *S, double s, bool leave, bool moving, cnCheckResult *r, EvStatus *ev,
                    cnDiag *diag);
cnStatus cn_sm_eval_static(Step *S, cnCheckResult *r, EvStatus *ev, cnDiag *diag);
cnStatus cn_sm_record(cnSimResult *R, int step, double t0, double s, Step *S, const cnCheckResult *r,
                      EvStatus ev, bool held);
cnStatus cn_sm_remember(Step *S, double s, bool leave);

/* sim_onset.c: where a step starts to fail, or the gripper to carry */
cnStatus cn_sm_bisect(Step *S, double s_lo, double s_hi, cnCheckResult *r, EvStatus *ev, double *s_on,
                      cnDiag *diag);
cnStatus cn_sm_bisect_carry(Step *S, double s_lo, double s_hi, bool was_held, double *at, cnDiag *diag);
cnStatus cn_sm_push_carry(cnStepResult *out, double t0, double t1, bool released, const cnPlanStep *st);

/* sim_margin.c: the margins along a stable step */
cnStatus cn_sm_step_margins(Step *S, cnSimResult *R, cnStepResult *out, cnDiag *diag);
void cn_sm_drop_margins(cnSimResult *R, cnStepResult *out);

#endif
