/* The 2-D section of a 3-D prism assembly and its check (section.c). Private to src/check/. */
#ifndef CAIRN_SECTION_H
#define CAIRN_SECTION_H
#include "cairn/contact.h"
#include "cairn/model.h"
#include "cairn/stability.h"
#include "strong.h"

/* A check's section, found once (by the first reading that searches for a motion from rest). */
typedef struct cnSectionCache {
    bool tried;
    cnSectionReport rep;
    double *motion; /* when the section is not guaranteed: each part's motion in it (nreal x 6,
                       linear then angular, 3-D coordinates; zero for parts not moving), or NULL */
} cnSectionCache;

/* The coordinate axis (0, 1, 2) along which every part present is an extrusion perpendicular to
 * gravity, the free parts over one depth and the fixed ones over at least it; -1 when there is
 * none (2-D, fixels, parts posed by the query, or not prisms). */
int cn_section_axis(const cnAssembly *a, const cnContactQuery *q);

/* Check the section across cn_section_axis as a 2-D assembly with o's options into c (c->rep.checked:
 * it was; false when the assembly is not a prism or has parts in motion). Fails only when out of
 * memory; a section that cannot be decided is reported undecided. */
cnStatus cn_section_run(const cnAssembly *a, const cnCheckOptions *o, cnSectionCache *c, cnDiag *diag);

/* The section's motion lifted to p (target: nb x nd, the bodies' motion): 1 a verified motion from
 * rest of p (force: K + Kf*D, absolute; acc: the motion), 0 not one, -1 out of memory. */
int cn_section_lift(const cnMotionProblem *p, const double *target, double *force, double *acc);

#endif
