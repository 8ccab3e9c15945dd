/* Diagnostics: status names and filling cnDiag. */
#include <stdarg.h>
#include <stdio.h>
#include <string.h>

#include "core.h"

void cn_diag_clear(cnDiag *d) {
    if (!d) return;
    d->code = CN_OK;
    d->where[0] = '\0';
    d->message[0] = '\0';
    d->file[0] = '\0';
}

cnStatus cn_diag_set(cnDiag *d, cnStatus code, const char *where, const char *fmt, ...) {
    if (!d) return code;
    d->code = code;
    snprintf(d->where, sizeof d->where, "%s", where ? where : "");
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(d->message, sizeof d->message, fmt, ap);
    va_end(ap);
    return code;
}

const char *cn_status_name(cnStatus s) {
    switch (s) {
    case CN_OK: return "ok";
    case CN_ERR_INPUT: return "bad input";
    case CN_ERR_NUMERIC: return "numerical failure";
    case CN_ERR_MEMORY: return "out of memory";
    case CN_ERR_IO: return "cannot read file";
    }
    return "unknown status";
}

cnStatus cn_diag_oom(cnDiag *d) { return cn_diag_set(d, CN_ERR_MEMORY, "", "out of memory"); }
