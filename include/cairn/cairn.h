/* cairn: stability of assemblies under part removal, by linear complementarity.
 * Umbrella header: include this one. */
#ifndef CAIRN_H
#define CAIRN_H

#include "cairn/export.h"

#define CAIRN_VERSION "0.1.0"

#include "cairn/builder.h"
#include "cairn/contact.h"
#include "cairn/figure.h"
#include "cairn/lcp.h"
#include "cairn/margin.h"
#include "cairn/model.h"
#include "cairn/plan.h"
#include "cairn/report.h"
#include "cairn/run.h"
#include "cairn/simulate.h"
#include "cairn/stability.h"
#include "cairn/status.h"

#ifdef __cplusplus
extern "C" {
#endif
/** The version of the library linked at run time (CAIRN_VERSION is the headers'). */
CN_API const char *cn_version(void);
#ifdef __cplusplus
}
#endif

#endif
