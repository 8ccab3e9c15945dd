/* Margins whose verdicts come from elsewhere than cn_check: a sample of a motion path decided by
 * simulate's own rules (the gripper's roles, Proposition 2, a pushed part's weight). Private to
 * the library. */
#ifndef CAIRN_MARGIN_HOOK_H
#define CAIRN_MARGIN_HOOK_H

#include "cairn/margin.h"

/* One verdict on v, the assembly with its gravity or friction changed (a shallow copy of the
 * assembly given to cn_margin_with, sharing its parts), under options o. Fills r (the margin
 * frees it); r->verdict is what counts. */
typedef cnStatus (*cnMarginVerdictFn)(void *ctx, const cnAssembly *v, const cnCheckOptions *o,
                                      cnCheckResult *r, cnDiag *diag);

/* The check options under which the static limits (the equilibrium LP alone) of a verdict of fn
 * are taken: o posed as fn poses it (a path's sample: its poses, roles and motion), in storage of
 * the hook's own that stays valid until its next call. The limits only guide where the verdicts
 * look; a margin is always bracketed by two verdicts. */
typedef const cnCheckOptions *(*cnMarginPoseFn)(void *ctx, const cnCheckOptions *o);

/* A margin kind (CN_MARGIN_FRICTION, _TILT, _LATERAL) as an index of the three: 0, 1, 2. */
static inline int cn_margin_kind_index(int kind) {
    return kind == CN_MARGIN_FRICTION ? 0 : kind == CN_MARGIN_TILT ? 1 : 2;
}

/* Is margin value x weaker than y, for kind index k? A larger critical friction, a smaller tilt
 * or lateral factor. */
static inline bool cn_margin_weaker(int k, double x, double y) { return k == 0 ? x > y : x < y; }

/* cn_margin with every verdict, the one as loaded included, from fn (NULL: cn_check), and the
 * static limits under the check options pose makes (NULL: none are taken unless fn is NULL). */
cnStatus cn_margin_with(const cnAssembly *a, const cnMarginOptions *opt, cnMarginVerdictFn fn,
                        cnMarginPoseFn pose, void *ctx, cnMarginResult *out, cnDiag *diag);

#endif
