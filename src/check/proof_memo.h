/* Searches for a motion from rest already decided along a path: consecutive samples of a step
 * often pose the same contact problem (a box pushed along a table meets the table the same way
 * at every sample), so a proof found once is taken again instead of searched again. Private to
 * the library. */
#ifndef CAIRN_PROOF_MEMO_H
#define CAIRN_PROOF_MEMO_H

#include "strong.h"

typedef struct cnProofMemo cnProofMemo;

/* The answer of an earlier search on the same problem (every integer equal, every number within
 * CN_MEMO_SAME of its array's scale): NONE (proved: no motion, whatever the budget) or
 * UNDECIDED (when the earlier search had at least this problem's budget; the same search stops
 * the same way). True when found; stats receives what the earlier search reported (its
 * open_bodies copied into stats->open_bodies when that is given). FOUND is never kept: its
 * motion is reported from a search of its own. */
bool cn_proof_memo_find(const cnProofMemo *memo, const cnMotionProblem *p, cnMotionAnswer *answer,
                        cnMotionStats *stats);

/* Keep a search's answer (NONE or UNDECIDED; others are ignored). Returns false when out of
 * memory (nothing kept; the memo stays valid). */
bool cn_proof_memo_keep(cnProofMemo **memo, const cnMotionProblem *p, cnMotionAnswer answer,
                        const cnMotionStats *stats);

void cn_proof_memo_free(cnProofMemo *memo);

#endif
