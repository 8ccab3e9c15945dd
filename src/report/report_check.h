/* report: what the check's JSON writer (report_check_json.c), its text writer
 * (report_check_text.c) and the contacts report (report.c) share. Private. */
#ifndef CAIRN_REPORT_CHECK_H
#define CAIRN_REPORT_CHECK_H

#include <jansson.h>
#include <stdbool.h>
#include <stdio.h>

#include "json_out.h"
#include "cairn/report.h"

/* check --json and check's text (cn_report_check chooses). */
cnStatus cn_report_check_json(FILE *f, const cnAssembly *a, const cnCheckResult *r);
void cn_report_check_text(FILE *f, const cnAssembly *a, const cnCheckResult *r);

/* The contacts streamed into a JSON document: a check's (r, with forces) or found ones (cs). */
typedef struct {
    const cnAssembly *a;
    const cnCheckResult *r;  /* a check's contacts and forces, or */
    const cnContactSet *cs;  /* the contacts alone */
} cnReportContacts;
void cn_report_check_contacts(cnJsonStream *s, void *ctx);

/* A vector of dim components as a JSON array, rounding cleaned at scale. */
json_t *cn_report_vec(const double *v, int dim, double scale);
/* The same as text, "(x, y[, z])". */
void cn_report_fmt_vec(char *buf, size_t n, const double *v, int dim, double scale);
/* The name of side `which` (1 or 2) of contact c: its part's, with the piece of a split part. */
void cn_report_body_name(const cnAssembly *a, const cnContact *c, int which, char *buf, size_t n);
/* The deepest overlap accepted as contact: its index in the contacts, or -1 when no two parts
 * overlap; *rel: its depth over the smaller part's size. */
int cn_report_deepest_overlap(const cnAssembly *a, const cnContactSet *cs, double *rel);
/* The parts read from mesh files, as text lines and as JSON. */
void cn_report_mesh_text(FILE *f, const cnAssembly *a);
json_t *cn_report_mesh_json(const cnAssembly *a);
/* How a stable friction verdict was proved, as JSON names it (NULL: not proved). */
const char *cn_report_proof_name(cnProof p);
/* The paper's own test agrees with the static solution: the LCP's solution by Lemke's method does
 * not move (its forces are the ones reported). */
bool cn_report_lemke_static(const cnCheckResult *r);
/* The name of a contact's part (a fixel's "world"). */
const char *cn_report_contact_part(const cnAssembly *a, int part);
/* For each contact, whether it is the first unsettled one between its two parts (either way
 * round): a flag per contact (cn_free it), NULL when out of memory. */
unsigned char *cn_report_unsettled_joints(const cnCheckResult *r);

#endif
