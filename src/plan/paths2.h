/* plan: 2-D translational escape paths. Private. */
#ifndef CAIRN_PATHS2_H
#define CAIRN_PATHS2_H

#include "pieces.h"

/* ---- 2-D translational paths (paths2.c) ---- */
/* Up to max_paths piecewise-linear paths (at most 8 segments each) leaving through distinct
 * openings, shortest first; straight-out paths are left to the straight-line candidates. */
cnStatus cn_paths2(const cnAssembly *a, const unsigned char *absent, const unsigned char *moving,
                   int max_paths, double (*segs)[8][3], int *nseg, int *npaths, cnDiag *diag);

#endif
