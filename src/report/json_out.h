/* report: the JSON writer every report shares. Private. */
#ifndef CAIRN_JSON_OUT_H
#define CAIRN_JSON_OUT_H

#include <stdio.h>
#include "core.h"

/* ---- reports (report.c) ---- */
/* Write a JSON document (jansson json_t *, taken: it is released) with 2-space indentation and
 * `precision` significant digits, then a newline. */
cnStatus cn_json_write(FILE *f, void *json, int precision);

#endif
