/* Why a check gave no verdict, in the library's words. */
#include "cairn/stability.h"

const char *cn_undecided_text(cnUndecided why) {
    switch (why) {
    case CN_UNDECIDED_NO: return "";
    case CN_UNDECIDED_BUDGET: return "the branch-and-bound budget of nodes ran out";
    case CN_UNDECIDED_TIME: return "the search's time budget ran out";
    case CN_UNDECIDED_TOO_LARGE:
        return "the LCP of a group of bodies that contacts join is too large for the search: more "
               "than 400 complementarity pairs";
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
