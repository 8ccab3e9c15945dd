/* cairn: how far an assembly at rest is from falling. Three margins, each bracketed by two
 * verdicts of cn_check: the least friction at which it stands, the largest angle by which
 * gravity can be turned, and the largest horizontal acceleration (in g) it resists. */
#ifndef CAIRN_MARGIN_H
#define CAIRN_MARGIN_H

#include "cairn/export.h"

#include <stdbool.h>

#include "cairn/model.h"
#include "cairn/stability.h"
#include "cairn/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Which margins to find (bits of cnMarginOptions.kinds). */
typedef enum cnMarginKind {
    CN_MARGIN_FRICTION = 1, /**< the least friction coefficient at which the assembly stands */
    CN_MARGIN_TILT = 2,     /**< the largest turn of gravity about a horizontal axis */
    CN_MARGIN_LATERAL = 4   /**< the largest horizontal acceleration, in g */
} cnMarginKind;
#define CN_MARGIN_ALL 7

/** Bisection ends when the bracket is narrower than this fraction of the value (or, for a value
 *  of 0, than this in absolute terms: radians, g or friction coefficient). */
#define CN_MARGIN_DEFAULT_REL_TOL 1e-7
/** Motion threshold of the verdicts a margin runs (see CN_DEFAULT_MOTION_TOL): finer than a
 *  check's, so that the bracket is not blurred by motions below a check's threshold. */
#define CN_MARGIN_MOTION_TOL 1e-9
/** Margins below this (radians, g, friction coefficient) are reported as 0: a hundred times the
 *  verdicts' motion threshold, their resolution. */
#define CN_MARGIN_ZERO 1e-7
/** In 3-D without a given axis or direction, the azimuths tried first (then refined about the
 *  weakest down to CN_MARGIN_AZIMUTH_STEP radians at a coarse tolerance, then again, at the
 *  asked one, down to a finer step). */
#define CN_MARGIN_AZIMUTHS 16
#define CN_MARGIN_AZIMUTH_STEP 1e-3
/** The ranges searched: friction coefficients up to this, tilts up to 90 degrees, lateral
 *  accelerations up to this many g. */
#define CN_MARGIN_MAX_FRICTION 1e3
#define CN_MARGIN_MAX_LATERAL 1e3

typedef struct cnMarginOptions {
    unsigned kinds;      /**< cnMarginKind bits (0: all three) */
    int pair[2];         /**< friction: only this pair of parts' coefficient varies (they must
                            touch; {-1, -1}: every coefficient, scaled together with the default,
                            or with the largest pair coefficient when the default is 0) */
    double axis[3];      /**< tilt about this axis (perpendicular to gravity; zero: the weakest,
                            both senses in 2-D) */
    double direction[3]; /**< lateral acceleration along this direction (perpendicular to gravity;
                            zero: the weakest) */
    double rel_tol;      /**< see CN_MARGIN_DEFAULT_REL_TOL (0: that) */
    double max_seconds;  /**< wall time after which every bracket is left as it stands (0: none);
                            the margins are then proved but wider (cnMargin.stopped) */
    cnCheckOptions check; /**< options of every verdict (motion_tol 0: CN_MARGIN_MOTION_TOL; the
                             verdict as loaded takes CN_DEFAULT_MOTION_TOL then, as cn_check) */
} cnMarginOptions;

CN_API cnMarginOptions cn_margin_options_default(void);

/** How a margin's search ended. */
typedef enum cnMarginEnd {
    CN_MARGIN_FOUND = 0, /**< stable at `value`, not stable at `past`, within rel_tol of it */
    CN_MARGIN_NONE = 1,  /**< not stable anywhere searched: friction, not even at
                            CN_MARGIN_MAX_FRICTION (value +inf); tilt and lateral, not as given
                            (value 0) */
    CN_MARGIN_WHOLE = 2  /**< stable over the whole range: friction, even frictionless (value 0);
                            tilt, up to 90 degrees; lateral, up to CN_MARGIN_MAX_LATERAL g */
} cnMarginEnd;

typedef struct cnMargin {
    bool computed;
    cnMarginEnd end;
    double value;        /**< friction: the least coefficient proved stable; tilt: the largest
                            angle proved stable (radians); lateral: the largest acceleration proved
                            stable (in g) */
    double past;         /**< the value nearest it on the other side, where the verdict was not
                            stable (friction "none": the largest tried; NAN otherwise when end is
                            not FOUND) */
    cnVerdict past_verdict; /**< that verdict: unstable or not guaranteed proves the bracket;
                               undecided leaves that side unproved */
    bool past_failed;    /**< the verdict at `past` failed numerically (counted as not stable:
                            that side is unproved) */
    bool stopped;        /**< max_seconds ran out first: the bracket is wider than rel_tol, and
                            without a given direction the weakest is that of those tried */
    double dir[3];       /**< tilt: the axis (right hand: gravity turned about it by `value`);
                            lateral: the direction of the acceleration's force on the parts */
    double base;         /**< friction: the coefficient that varies, as loaded (the pair's; or
                            the default, and when that is 0 the largest pair coefficient) */
    double gravity[3];   /**< the gravity of the verdict at mechanism_at */
    int verdicts;        /**< checks run */
    double mechanism_at; /**< where `collapse` was taken: a little past `past` (a thousandth of
                            it farther), where the motion is well above the verdicts' threshold;
                            `past` itself when that verdict was stable there too */
    cnCheckResult collapse; /**< the verdict at mechanism_at (its moving parts and opening and
                               sliding contacts are the mechanism); zeroed when there is none */
} cnMargin;

typedef struct cnMarginResult {
    cnVerdict verdict;   /**< the assembly's verdict as loaded */
    cnMargin friction, tilt, lateral;
} cnMarginResult;

/** Find the margins asked for. Each is a bisection between a stable and a not-stable verdict of
 *  cn_check on the assembly with one thing changed (its friction coefficients, the direction of
 *  gravity, a horizontal acceleration added to gravity); it assumes the verdict changes once
 *  along the range, and reports the bracket it found. An undecided verdict counts as not
 *  stable (the margin is then a proved lower bound of stability, and past_verdict says so).
 *  Returns CN_ERR_INPUT for bad options (diag names them) or parts that overlap, CN_ERR_NUMERIC
 *  when a verdict failed numerically. cn_margin_result_free is always safe afterwards. */
CN_API cnStatus cn_margin(const cnAssembly *a, const cnMarginOptions *opt, cnMarginResult *out,
                   cnDiag *diag);

CN_API void cn_margin_result_free(cnMarginResult *r);

#ifdef __cplusplus
}
#endif
#endif
