/* report: what the plan's JSON writer (report_plan_json.c) and its text writer and entry points
 * (report_plan.c) share. Private. */
#ifndef CAIRN_REPORT_PLAN_H
#define CAIRN_REPORT_PLAN_H

#include <jansson.h>
#include <stdbool.h>

#include "json_out.h"
#include "cairn/report.h"

/* plan --json's document. */
json_t *cn_report_plan_json(const cnAssembly *a, const cnPlanResult *r);
/* plan --margin's ranking (under "margins"): n of the nlisted sequences, ranked by `rank`. */
json_t *cn_report_plan_margins_json(const cnAssembly *a, const cnPlanMargin *m, int n, int nlisted, int rank);
/* A fixel suggestion, and the best plan as a plan file's "plan" array. */
json_t *cn_report_fixels_json(const cnAssembly *a, const cnFixelSuggestion *fs);
json_t *cn_report_best_plan_json(const cnAssembly *a, const cnPlanSequence *best);
/* A group taken out with every part gripped (a rigid whole). */
bool cn_report_grip_whole(const cnPlanMove *m);
/* The margins' JSON keys, in cnMarginKind's order. */
extern const char *const CN_REPORT_MARGIN_KEYS[3];

#endif
