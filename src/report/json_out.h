/* report: what every report shares (the JSON writer, the words for a step's status). Private. */
#ifndef CAIRN_JSON_OUT_H
#define CAIRN_JSON_OUT_H

#include <stdio.h>
#include "core.h"
#include "cairn/simulate.h"

/* ---- reports (report.c) ---- */
/* Write a JSON document (jansson json_t *, taken: it is released) with 2-space indentation and
 * `precision` significant digits, then a newline. */
cnStatus cn_json_write(FILE *f, void *json, int precision);

/* ---- reports of simulations and plans (report_sim.c) ---- */

#endif
