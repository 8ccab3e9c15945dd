/* Planning (plan.c): the search's state shared by the search (plan.c), its two-handed splits
 * (plan_split.c), the result it harvests (plan_harvest.c) and its fixel suggestions
 * (plan_fixels.c). Private to src/plan/. */
#ifndef CAIRN_PLAN_STATE_H
#define CAIRN_PLAN_STATE_H

#include <time.h>

#include "cands.h"
#include "plan_large.h"
#include "cairn/plan.h"

/* Free parts at most (a state is a bit mask of them). */
#define PLAN_MAX_PARTS 62
/* Exhaustive search up to this many free parts; beyond, depth-first to the first stable plan. */
#define PLAN_MAX_EXHAUSTIVE 16

typedef unsigned long long Mask;

/* State.held of a subassembly held as a rigid whole (every part gripped). */
#define HELD_WHOLE (-2)

/* A simulated transition: `move` leaves state S along `cand`. */
typedef struct {
    Mask move;
    cnCand cand;
    cnStepStatus status;
    double time;          /* onset (when not stable) */
    Mask moving;          /* parts that start to move (unstable) */
    int blocking;         /* infeasible: the part in the way */
    int grip;             /* the bit of the gripped part; -1: every moved part is gripped */
    int from;             /* the state it leaves (subassembly transitions), else -1 */
    bool prop1;           /* unstable without simulation: the state it leads to is (Prop. 1) */
} Trans;

typedef struct {
    Mask mask;
    int held;             /* bit of the part a gripper holds still (no supports); -1: on the
                             supports, where the assembly stood; HELD_WHOLE: every part held */
    int stable;           /* -1 unknown */
    int solved;           /* -1 unknown: ways computed */
    double ways;          /* stable single-part sequences from here */
    int first, ntrans;    /* single-part transitions */
    double sub_plans;     /* -1 unknown: stable two-handed plans from here (0: none) */
    int sub_choice;       /* the first split that works (index into trans), -1 */
    double orders;        /* stable orders of the parts from here (paths aside), -1 unknown */
    Mask falls;           /* not stable: the parts that start to move */
    bool undecided;       /* not stable because its friction verdict is undecided */
    bool unexplored;      /* left unexpanded when the search budget ran out */
} State;

typedef struct {
    const cnAssembly *a;
    const cnPlanOptions *o;
    int nfree;
    int part_of[PLAN_MAX_PARTS]; /* bit -> part index */
    State *st;
    int nst, capst;
    int *hash;             /* open addressing: state index + 1, 0 empty */
    size_t hmask;
    Trans *tr;
    int ntr, captr;
    int nsims;
    bool truncated;        /* not exhaustive */
    bool splits_capped;    /* ... because a state's groups were taken from 20 of its parts */
    bool budget;           /* the state or time budget was reached */
    bool out_of_time;      /* ... and it was the time budget */
    struct timespec t0;    /* when the search started */
    double progress_at;    /* seconds into the search of the last progress call */
    cnDiag *diag;
    unsigned char *absent;
    unsigned char *moving;
    unsigned char *still;  /* per part: held still by the other hand */
    unsigned char *role;   /* per part: roles for the check of a held state */
    Mask touch[PLAN_MAX_PARTS]; /* per free part (bit): the free parts it touches (bits) */
    cnCandGen gen;         /* candidate paths, and the blocking graph's cones they come from */
} Planner;

typedef struct {
    Planner *P;
    cnArena *mem;
    cnPlanMove *memo; /* per transition: its move, built once (path == NULL: not yet); the
                         result's lists share its name, segments and part lists */
    bool nomem;  /* an allocation failed: the result is incomplete and is not returned */
} Out;

typedef struct {
    cnFixelSuggestion *items;
    int n, cap;
} FixList;

/* plan.c: the search */
int cn_pl_init(Planner *P, const cnAssembly *a, const cnPlanOptions *o, cnDiag *diag);
cnStatus cn_pl_find_touching(Planner *P);
void cn_pl_free(Planner *P);
bool cn_pl_out_of_budget(Planner *P);
bool cn_pl_first_only(const Planner *P);
int cn_pl_state_at(Planner *P, Mask m, int held);
int cn_pl_state_of(Planner *P, Mask m);
void cn_pl_set_absent_held(Planner *P, Mask present, int held);
void cn_pl_set_absent(Planner *P, Mask present);
cnStatus cn_pl_state_stable(Planner *P, int si, bool *stable);
cnStatus cn_pl_candidates(Planner *P, Mask present, int held, Mask move, cnCand **out, int *n);
Trans cn_pl_trans_init(Mask move, const cnCand *cand, int grip, int from);
cnStatus cn_pl_transition(Planner *P, Mask present, int held, Mask move, int grip,
                          const cnCand *cand, bool after_known, Trans *t);
int cn_pl_push_trans(Planner *P, const Trans *t);
cnStatus cn_pl_expand(Planner *P, int si);

/* plan_split.c: two-handed splits */
int cn_pl_popcount(Mask m);
cnStatus cn_pl_split_states(Planner *P, int si, const Trans *t, int *rest, int *out);
cnStatus cn_pl_solve_sub(Planner *P, int si);

/* plan_harvest.c: the result */
cnPlanMove cn_pl_move_of(Out *O, const Trans *t);
void *cn_pl_grow(Out *O, void *arr, int n, int *cap, size_t size);
cnStatus cn_pl_harvest(Out *O, int root, Trans **stack, cnPlanResult *out);

/* plan_fixels.c: fixels */
cnStatus cn_pl_suggest_fixels(Out *O, Mask present, const Trans *t, FixList *out);

#endif
