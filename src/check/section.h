/* The 2-D section of a 3-D prism assembly and its check (section.c). Private to src/check/. */
#ifndef CAIRN_SECTION_H
#define CAIRN_SECTION_H
#include "cairn/contact.h"
#include "cairn/model.h"
#include "cairn/stability.h"

/* The coordinate axis (0, 1, 2) along which every part present is an extrusion perpendicular to
 * gravity, the free parts over one depth and the fixed ones over at least it; -1 when there is
 * none (2-D, fixels, parts posed by the query, or not prisms). */
int cn_section_axis(const cnAssembly *a, const cnContactQuery *q);

/* After an undecided static 3-D check r: check the section across cn_section_axis as a 2-D
 * assembly and record it in r->section; with o->assume_planar a stable section makes r stable
 * (CN_PROOF_SECTION). Does nothing otherwise. Fails only when out of memory. */
cnStatus cn_section_check(const cnAssembly *a, const cnCheckOptions *o, cnCheckResult *r, cnDiag *diag);

#endif
