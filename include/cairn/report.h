/* cairn: human-readable and JSON reports. The library writes only to streams it is given. */
#ifndef CAIRN_REPORT_H
#define CAIRN_REPORT_H

#include <stdio.h>

#include "cairn/contact.h"
#include "cairn/lcp.h"
#include "cairn/stability.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Write the contact list as text or JSON (JSON ends with a newline). */
cnStatus cn_report_contacts(FILE *f, const cnAssembly *a, const cnContactSet *c, int json);

/** Write a check result as text or JSON. */
cnStatus cn_report_check(FILE *f, const cnAssembly *a, const cnCheckResult *r, int json);

/** Write an LCP solve as text or JSON. `z` and `w` may be NULL when there is no solution. */
cnStatus cn_report_lcp(FILE *f, const cnLcp *p, cnLcpStatus st, const char *solver,
                       const double *z, const double *w, const cnLcpInfo *info, int json,
                       const char *note);

#ifdef __cplusplus
}
#endif
#endif
