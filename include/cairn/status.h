/* cairn: status codes and diagnostics.
 *
 * The library never prints, aborts or exits on bad input. Every fallible call returns a cnStatus
 * and, when it fails, fills a cnDiag with where the problem is (a JSON path such as
 * "parts[3].polygon", or "line:column" for JSON syntax) and a message that says what to do. */
#ifndef CAIRN_STATUS_H
#define CAIRN_STATUS_H

#include "cairn/export.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Outcome of a library call. Verdicts (stable / unstable) are results, not statuses. */
typedef enum cnStatus {
    CN_OK = 0,        /**< success */
    CN_ERR_INPUT = 2, /**< bad input or usage: the file, its JSON, its geometry */
    CN_ERR_NUMERIC = 3, /**< numerical failure: a solver did not converge or a result failed
                           verification; never reported as a verdict */
    CN_ERR_MEMORY = 4, /**< out of memory */
    CN_ERR_IO = 5      /**< a file could not be read */
} cnStatus;

/** A diagnostic: filled by a failing call. `where` may be empty when no place applies. */
typedef struct cnDiag {
    cnStatus code;
    char where[256];
    char message[1024];
    char file[256];   /**< the file the problem is in, when not the one the caller named (a plan
                         file given apart from its assembly); else empty */
} cnDiag;

/** Reset a diagnostic to "no error". `d` may be NULL. */
CN_API void cn_diag_clear(cnDiag *d);

/** Fill a diagnostic (printf-style message) and return `code`, so callers can write
 *  `return cn_diag_set(d, CN_ERR_INPUT, "parts[2]", "...")`. `d` may be NULL. */
CN_API cnStatus cn_diag_set(cnDiag *d, cnStatus code, const char *where, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/** Short English name of a status ("ok", "bad input", "numerical failure", ...). */
CN_API const char *cn_status_name(cnStatus s);

#ifdef __cplusplus
}
#endif
#endif
