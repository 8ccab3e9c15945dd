/* The branch and bound of the search for a motion from rest (strong.c), its node LP
 * (search_lp.c) and its joint patterns (search_joint.c): the state they share. Private to
 * src/check/. */
#ifndef CAIRN_SEARCH_H
#define CAIRN_SEARCH_H

#include <glpk.h>
#include <time.h>

#include "strong.h"

/* Two friction rows are the same row when their coefficients differ by less than this (linear
 * parts, unit; rotational parts relative to the body's radius): contacts along one line of a
 * 2-D joint. */
#define CN_BB_SAME_ROW 1e-9
/* Friction directions up to which a contact's sliding modes are branched on together. */
#define CN_BB_MAX_D 64
/* Complementarity is met when min(z, w) of a pair, in scaled units, is below this. */
#define CN_BB_COMPL_TOL 1e-9
/* Points of a joint at most (more: its points are branched on one by one) */
#define CN_BB_JOINT_MAX 8

/* Energy cuts (cn_bb_cut): one round at a node whose power bound (scaled) is below
 * CN_BB_CUT_BELOW, near a prune, where they decide it (on the large bounds of a search's first
 * levels they cost more pivots than they save); kept for the rest of the search (valid for every
 * solution), at most CN_BB_CUT_MAX: rows only grow, so a saved basis stays valid with the cuts
 * added since it as basic rows. */
#define CN_BB_CUT_BELOW 1e-2
#define CN_BB_CUT_MAX 30
/* Normal-force floors (cn_bb_normal_floors): the least budget of a search that is run again with
 * them when it ends undecided (strong.c; smaller budgets are a planner's quick probes), and the
 * share of that budget the second pass gets (1 / CN_BB_FLOOR_SHARE; 2-D arches of 56 to 79
 * voussoirs take 340 to 430 LPs of it); passes over the root LP's motion; rounds of energy cuts
 * for each group's least normal force; cuts made so, at most; the margin taken off each least
 * force (in the LP's force scale, absolute and relative) for the simplex's tolerances (1e-7). */
#define CN_BB_FLOOR_MIN_BUDGET 1000
#define CN_BB_FLOOR_SHARE 2
#define CN_BB_FLOOR_PASSES 40
#define CN_BB_FLOOR_ROUNDS 4
#define CN_BB_FLOOR_CUTS 100
#define CN_BB_FLOOR_MARGIN 1e-5

/* Scratch arrays alive across GLPK calls, kept in the search's state so that they are freed
 * even when GLPK's error hook jumps out of the search (cn_lp_guarded_call). */
enum { TMP_IA, TMP_JA, TMP_AR, TMP_IND, TMP_VAL, TMP_STACK, TMP_FIXED, TMP_MARK, TMP_BASIS,
       TMP_BASIS_ROWS, TMP_JOUT, TMP_MOVING, TMP_LOOSE, TMP_SLOTS };

typedef struct {
    const cnMotionProblem *p;
    glp_prob *P;
    void *tmp[TMP_SLOTS];
    int nv, nrows, n;     /* motion unknowns, force rows, complementarity pairs */
    double *sv;           /* nv: a = sv x */
    double *wcol;         /* nrows: force scale of each row's column */
    double *rowlo;        /* n: lower bound of each pair's row (w_i >= rowlo_i) */
    unsigned char *fix;   /* n: 0 free, 1 z = 0, 2 w = 0 */
    double *x;            /* scratch: column values */
    double *wv;           /* scratch: row slacks of the pairs */
    double *force, *acc;  /* out: the solution found */
    long nodes, budget;
    double seconds;       /* wall-time budget */
    struct timespec t0;
    double *lambda;       /* scratch: Kf sliding speeds */
    /* Friction groups: friction contacts whose friction rows are the same rows and whose mu is
     * the same (the points of a 2-D joint along its line). Only the sum of their friction acts,
     * and that sum can be anything with |sum| <= mu sum p_n, so the search carries one set of
     * friction rows and one sliding speed per group (exact: a solution of either LCP gives one
     * of the other, the friction shared in proportion to the normal forces). */
    int G;                /* groups */
    int *grep;            /* G: a member (friction contact) whose rows stand for the group */
    int *gfirst;          /* G + 1: offsets into gmem */
    int *gmem;            /* Kf: friction contacts, by group */
    double *a, *ma;       /* scratch: nv */
    /* Joints: friction groups between the same two bodies with the same normal (the points of a
     * face or edge contact). Their tangential slips are those of one relative motion, so only
     * some combinations of the points' sliding modes can occur together: those are listed once
     * (cn_bb_joint_patterns) and branched on member by member within them
     * (cn_bb_prefix_children): a member's children are its modes in the patterns that agree
     * with the members fixed before it, so a mode no pattern of the prefix allows is never
     * tried, and an infeasible prefix cuts every pattern that extends it with one LP. */
    int *joint;           /* G: the joint of each group, -1 when it has no joint of its own */
    int NJ;
    int *jfirst, *jmem;   /* NJ + 1 offsets into jmem; the groups of each joint */
    int *jnpat;           /* NJ x 2^CN_BB_JOINT_MAX: patterns of each joint's subset of members
                             (a mask), found when first branched on (-1 not yet; 0 none kept:
                             its points are branched on one by one) */
    unsigned char **jpat; /* the same: the patterns, jnpat x (members in the mask) modes */
    int stack_cap;        /* entries of the search's stack */
    unsigned char *moving; /* (depth + 1) x nb: the bodies the LP's motion moves at the node
                              branched on at each depth of the current path */
    double open_bound;    /* undecided by the budget: the largest bound (scaled power) of the
                             nodes left open */
    unsigned char *open_bodies; /* ... and the bodies their parents' motions move (nb) */
    unsigned char *loose;  /* (depth + 1) x K: the contacts with a pair (theirs or their
                              friction's) unresolved in the LP of the node branched on at each
                              depth of the current path */
    unsigned char *open_contacts; /* undecided: those of the open nodes' parents (K) */
    int cuts;
    double *nfloor;       /* G: a lower bound on each group's total normal force in every
                             solution (absolute units), 0 where none is known (search_lp.c) */
    int floored;          /* ... how many are positive */
    int depth;
    bool energy;          /* the search maximises gravity's power (no nominal sliding) */
    int gray;             /* complementary points near the threshold that did not resolve */
    int exact;            /* nodes solved again in exact arithmetic */
    double progress_at;   /* seconds into the search of the next progress call */
    bool exact_ok;        /* the LP's numbers are within CN_BB_EXACT_RANGE for glp_exact */
    /* Learned prunes (search_learn.c): sets of fixes that prune every node holding them all */
    int *ng;              /* the fixes, 2 i + choice - 1, of every learned set in turn */
    int *ng_end;          /* ng_count: the end of each set in ng */
    int ng_count, ng_len, ng_cap, ng_endcap;
    long ng_hits;         /* nodes pruned by a learned set, without an LP */
    unsigned char *fix0;  /* n: the fixes made before the search (in every node) */
    cnUndecided why;
} Bb;

/* A node to explore: at depth, one pair fixed (pair >= 0, choice 1: z = 0, 2: w = 0), or one
 * friction group's sliding mode (group >= 0). */
typedef struct {
    int depth, pair, choice, group, mode; /* group -3: joint `pair`'s member `level` (in the
                                             order of mask `choice`) takes its mode in the
                                             joint's pattern `mode` */
    double bound;                         /* the parent's bound (scaled power; root: inf) */
    int level;
} BbEntry;

/* search_sub.c: part of a motion problem as one of its own */
typedef struct {
    cnMech m;
    cnMotionProblem p;
    cnJRow *rows;
    int *cof;
    double *mu, *nominal, *field;
    int *body; /* m.nb: each body's index in the whole problem */
    int *row;  /* p.K + p.Kf * p.D: each row's index in the whole problem */
} cnSub;
/* The bodies b with sub[b] >= 0 (numbered by it) and the contacts that touch one (the other
 * side, when not kept, held still). bodies (nbodies), contacts (ncontacts, ascending): those
 * kept, or NULL to find them; fof: the friction contact of each contact (-1 none), or NULL to
 * find it. 0, or -1 out of memory (free it either way). */
int cn_sub_make(const cnMotionProblem *p, const int *sub, const int *bodies, int nbodies,
                const int *contacts, int ncontacts, const int *fof, cnSub *g);
void cn_sub_free(cnSub *g);

/* search_line.c: the inner points of 2-D joints. cn_line_inner: for each contact strictly
 * inside a line of three or more points of one joint (search_line.c), the two outermost in
 * end0[c], end1[c] (else -1); K entries each. Returns how many, or -1 out of memory. */
int cn_line_inner(const cnMotionProblem *p, int *end0, int *end1);
/* The static field of g (a part of p without the inner points) with each inner point's forces
 * moved to its line's ends, shared as the point lies between them (the same wrench). */
void cn_line_field(const cnMotionProblem *p, const int *end0, const int *end1, const cnSub *g);

/* search_lp.c: the node LP */
/* Friction contacts f1 and f2 have the same friction rows (between the same bodies, within
 * CN_BB_SAME_ROW), coefficient and nominal sliding: the points of one 2-D joint. */
bool cn_bb_same_friction(const cnMotionProblem *p, int f1, int f2);
/* p's friction groups (cn_bb_same_friction, each against the first member of the groups so far):
 * of[f] each friction contact's group, rep[g] each group's first member (Kf each). Returns how
 * many. */
int cn_bb_friction_groups(const cnMotionProblem *p, int *of, int *rep);
double cn_bb_row_weight(const cnMech *m, const cnJRow *row);
void *cn_bb_tmp(Bb *s, int slot, size_t bytes);
void cn_bb_tmp_free(Bb *s, int slot);
const cnJRow *cn_bb_row(const Bb *s, int r);
int cn_bb_group(Bb *s);
void cn_bb_pair_set(Bb *s, int i, int choice);
int cn_bb_build(Bb *s, bool energy);
void cn_bb_basis_get(const Bb *s, unsigned char *b);
void cn_bb_basis_put(Bb *s, const unsigned char *b, int nr_saved);
bool cn_bb_cut(Bb *s);
long cn_bb_normal_floors(Bb *s);
int cn_bb_lp(Bb *s);
int cn_bb_lp_meth(Bb *s, int meth);
int cn_bb_node_lp(Bb *s);
int cn_bb_exact(Bb *s);

/* search_joint.c: sliding modes and joint patterns */
void cn_bb_mode(Bb *s, int g, int mode, int *fixed, int *nfixed);
double cn_bb_mode_far(const Bb *s, int g, int mode);
int cn_bb_mode_group(const Bb *s, int i);
bool cn_bb_group_free(const Bb *s, int g);
int cn_bb_joints(Bb *s);
int cn_bb_joint_patterns(Bb *s, int J, unsigned mask);
bool cn_bb_prefix_children(Bb *s, int *top, const BbEntry *e, int J, unsigned mask, int rep,
                           int level, double obj);

/* search_learn.c: prunes learned from the LP's duals */
void cn_bb_learn(Bb *s);
void cn_bb_learn_infeasible(Bb *s);
bool cn_bb_known(const Bb *s);
void cn_bb_learn_reset(Bb *s);

/* strong.c: the search over one group of bodies (cn_motion_search, search_split.c, calls it
 * for each group that contacts join), and its stack */
cnStatus cn_bb_search_group(const cnMotionProblem *p, cnMotionAnswer *answer, double *force,
                            double *acc, cnMotionStats *stats, cnDiag *diag);
bool cn_bb_stack_room(Bb *s, int top, int more);
void cn_bb_sort_by_far(int *order, int n, const double *far);

#endif
