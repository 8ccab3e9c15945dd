/* The warm start carried from one check to the next along a motion path (cnWarmStart, opaque in
 * the public API): bases of the last contact LCPs, decided searches, and solve counters. */
#ifndef CAIRN_WARM_START_H
#define CAIRN_WARM_START_H

#include <stdbool.h>

#include "cairn/stability.h"

/* Bases remembered: bisection alternates between the two sides of an onset, whose contacts, or
 * bases, differ. */
#define CN_WARM_SLOTS 4

/* A new LCP with the same contacts (the same rows in the same order) tries the remembered bases
 * of those contacts first; one whose contacts changed tries the latest basis carried over row by
 * row (a new contact's rows start nonbasic). Zero-initialised; cn_warm_start_release frees what
 * it holds. */
struct cnWarmStart {
    bool record_only;       /* count solves but never warm-start (for comparisons) */
    struct {
        unsigned long long key; /* the contact structure the basis belongs to */
        int n, cap;
        unsigned char *basic;   /* n flags (see cn_lcp_basis_of) */
        unsigned long long *row; /* n row identities (contact and kind of row) */
        long stamp;             /* when last used (0: empty) */
    } slot[CN_WARM_SLOTS];
    unsigned long long *row_work; /* scratch: the current LCP's row identities */
    unsigned char *basic_work;    /* scratch: a carried-over basis, then the solution's */
    unsigned char *used_work;     /* scratch: remembered rows already matched */
    int work_cap;
    cnWarmStats stats;      /* the solves' counters */
    struct cnProofMemo *proofs; /* searches for a motion from rest already decided */
};

/* Free what a warm start holds (not the struct itself: internal callers keep it on the stack). */
void cn_warm_start_release(cnWarmStart *w);

#endif
