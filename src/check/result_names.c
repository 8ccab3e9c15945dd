/* The names and sentences of a check result's enums, as the reports write them. */
#include "cairn/stability.h"

const char *cn_undecided_text(cnUndecided why) {
    switch (why) {
    case CN_UNDECIDED_NO: return "";
    case CN_UNDECIDED_BUDGET: return "the branch-and-bound budget of nodes ran out";
    case CN_UNDECIDED_TIME: return "the search's time budget ran out";
    case CN_UNDECIDED_TOO_LARGE:
        return "the LCP of a group of bodies that contacts join is too large for the whole search: "
               "more than 400 complementarity pairs; searches of its bodies held among the rest, one "
               "or two at a time, found no motion of the whole";
    case CN_UNDECIDED_THRESHOLD:
        return "solutions moving at the motion threshold could not be told from still ones";
    case CN_UNDECIDED_SOLVER: return "the LP solver (GLPK) failed on a node";
    case CN_UNDECIDED_MEMORY: return "out of memory";
    case CN_UNDECIDED_CORNERS:
        return "too many corner-on-corner contacts to decide every reading of their normals";
    case CN_UNDECIDED_CORNERS_WIDE:
        return "a corner contact's cone of normals has more ends than cairn keeps";
    }
    return "undecided";
}

const char *cn_forces_from_name(cnForcesFrom from) {
    switch (from) {
    case CN_FORCES_NONE: return "none";
    case CN_FORCES_PIVOT: return "pivot";
    case CN_FORCES_LEMKE: return "lemke";
    case CN_FORCES_LP: return "lp";
    case CN_FORCES_SPARSE_QP: return "interior point";
    }
    return "none";
}

const char *cn_lp_method_name(cnLpMethod method) {
    switch (method) {
    case CN_LP_METHOD_NONE: return NULL;
    case CN_LP_METHOD_LOAD_DESCENT: return "load descent";
    case CN_LP_METHOD_INTERIOR_POINT: return "interior point";
    case CN_LP_METHOD_QP_MOTION: return "QP motion";
    case CN_LP_METHOD_WHOLE: return "whole assembly";
    case CN_LP_METHOD_GLPK_INTERIOR: return "GLPK interior point";
    case CN_LP_METHOD_GLPK_SIMPLEX: return "GLPK simplex";
    case CN_LP_METHOD_GLPK_ELASTIC: return "GLPK simplex, elastic";
    }
    return NULL;
}

const char *cn_unsolved_text(cnUnsolved why) {
    switch (why) {
    case CN_UNSOLVED_NO: return "";
    case CN_UNSOLVED_RAY: return "secondary ray";
    case CN_UNSOLVED_INFEASIBLE: return "infeasible";
    case CN_UNSOLVED_PIVOTS: return "pivot limit";
    case CN_UNSOLVED_NUMERIC: return "numerical failure";
    case CN_UNSOLVED_TOO_LARGE: return "too large for a dense LCP";
    case CN_UNSOLVED_TOO_LARGE_QP: return "too large for a dense LCP, and the sparse QP's answer did not verify";
    case CN_UNSOLVED_NOT_SOLVED: return "not solved";
    }
    return "not solved";
}
