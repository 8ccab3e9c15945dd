/* Fixels suggested for a failing transition of a plan. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "plan_state.h"
#include "solve.h"

/* Try fixels on the parts that start to move in a failing transition: at their vertices, pushing
 * against faces the motion opens; keep the fewest (one, else two) that make the step stable,
 * verified by simulating it again. */

/* A candidate fixel, scored by how directly the motion opens its face. */
typedef struct {
    cnFixel f;
    double score;
} FC;

/* The candidate fixels of a failing step's onset r (its moving parts' vertices on the faces their
 * motion opens), best first, at most 10: *fcp (nf of them; NULL when out of memory). */
static FC *fixel_candidates(const cnAssembly *a, const cnCheckResult *onset, int *nfp) {
    int dim = a->dim;
    int cap = 64, nf = 0;
    FC *fc = cn_malloc(sizeof(FC) * (size_t)cap);
    for (int i = 0; fc && i < onset->nmoving; i++) {
        int p = onset->moving[i];
        const cnPart *pt = &a->parts[p];
        const cnPartMotion *m = &onset->part[p];
        for (int sI = 0; sI < pt->npieces; sI++) {
            const cnPiece *pc = &pt->pieces[sI];
            for (int v = 0; v < pc->nverts; v++) {
                double rr[3], vel[3];
                cn_sub3(pc->verts[v], pt->com, rr);
                if (dim == 2) {
                    vel[0] = m->lin[0] - m->ang[2] * rr[1];
                    vel[1] = m->lin[1] + m->ang[2] * rr[0];
                    vel[2] = 0;
                } else {
                    cn_cross3(m->ang, rr, vel);
                    cn_add3(vel, m->lin, vel);
                }
                /* faces through v: 2-D the two edges at v; 3-D the faces listing v */
                double normals[16][3];
                int nn = 0;
                if (dim == 2) {
                    for (int e = 0; e < 2; e++) {
                        const double *A = pc->verts[e ? v : (v + pc->nverts - 1) % pc->nverts];
                        const double *B = pc->verts[e ? (v + 1) % pc->nverts : v];
                        double ex = B[0] - A[0], ey = B[1] - A[1], L = hypot(ex, ey);
                        normals[nn][0] = ey / L, normals[nn][1] = -ex / L, normals[nn][2] = 0, nn++;
                    }
                } else {
                    for (int f = 0; f < pc->nfaces && nn < 16; f++)
                        for (int k = 0; k < pc->faces[f].nverts; k++)
                            if (pc->faces[f].verts[k] == v) cn_copy3(normals[nn++], pc->faces[f].normal);
                }
                for (int k = 0; k < nn; k++) {
                    double sc = cn_dot3(vel, normals[k]);
                    if (sc <= 0) continue;
                    /* at a corner sharper than a right angle the face's inward normal runs out
                       past the next face: a fixel there pushes nothing (the loader refuses it) */
                    cnFixel f = {.part = p};
                    cn_copy3(f.point, pc->verts[v]);
                    for (int q = 0; q < 3; q++) f.normal[q] = -normals[k][q];
                    double at, in, out, tol;
                    cn_fixel_probe(a, &f, &at, &in, &out, &tol);
                    if (!(in <= tol && out > tol)) continue;
                    if (nf == cap) {
                        cap *= 2;
                        FC *n2 = cn_realloc(fc, sizeof(FC) * (size_t)cap);
                        if (!n2) break;
                        fc = n2;
                    }
                    fc[nf].f.part = p;
                    cn_copy3(fc[nf].f.point, pc->verts[v]);
                    for (int q = 0; q < 3; q++) fc[nf].f.normal[q] = -normals[k][q];
                    fc[nf].score = sc;
                    nf++;
                }
            }
        }
    }
    for (int i = 1; i < nf; i++) /* best first */
        for (int j = i; j > 0 && fc[j - 1].score < fc[j].score; j--) {
            FC x = fc[j];
            fc[j] = fc[j - 1];
            fc[j - 1] = x;
        }
    if (nf > 10) nf = 10;
    *nfp = nf;
    return fc;
}

/* Try the candidates alone, then in pairs, until one makes step st stable: the first that does
 * goes into out. */
static cnStatus try_fixels(Out *O, Mask present, const Trans *t, const cnPlanStep *st, const FC *fc, int nf,
                           FixList *out) {
    Planner *P = O->P;
    const cnAssembly *a = P->a;
    cnStepResult r;
    cnStatus s;
    cnAssembly copy = *a;
    cnFixel *fx = cn_malloc(sizeof(cnFixel) * (size_t)(a->nfixels + 2));
    if (!fx) return cn_diag_oom(P->diag);
    if (a->nfixels > 0) memcpy(fx, a->fixels, sizeof(cnFixel) * (size_t)a->nfixels);
    copy.fixels = fx;
    bool found = false;
    for (int size = 1; size <= 2 && !found; size++)
        for (int i = 0; i < nf && !found; i++)
            for (int j = size == 1 ? i : i + 1; j < (size == 1 ? i + 1 : nf) && !found; j++) {
                fx[a->nfixels] = fc[i].f;
                if (size == 2) fx[a->nfixels + 1] = fc[j].f;
                copy.nfixels = a->nfixels + size;
                cn_pl_set_absent(P, present);
                s = cn_simulate_step(&copy, P->absent, st, &P->o->sim, &r, P->diag);
                P->nsims++;
                if (s) {
                    cn_free(fx);
                    return s;
                }
                if (r.status == CN_STEP_STABLE) {
                    found = true;
                    cnFixelSuggestion *na = cn_pl_grow(O, out->items, out->n, &out->cap, sizeof *na);
                    if (na) {
                        out->items = na;
                        cnFixelSuggestion *fs = &na[out->n++];
                        fs->step = cn_pl_move_of(O, t);
                        fs->nfixels = size;
                        for (int q = 0; q < size; q++) fs->fixels[q] = fx[a->nfixels + q];
                    }
                }
                cn_step_result_free(&r);
            }
    cn_free(fx);
    return CN_OK;
}

cnStatus cn_pl_suggest_fixels(Out *O, Mask present, const Trans *t, FixList *out) {
    Planner *P = O->P;
    const cnAssembly *a = P->a;
    if (t->status != CN_STEP_UNSTABLE) return CN_OK; /* only a step that fails has an onset */
    /* the motion at the onset: simulate once more to get it */
    int mv[PLAN_MAX_PARTS], nm = 0;
    for (int b = 0; b < P->nfree; b++)
        if (t->move >> b & 1) mv[nm++] = P->part_of[b];
    cnPlanStep st;
    memset(&st, 0, sizeof st);
    st.nmove = st.ngrip = nm;
    st.move = st.grip = mv;
    st.nseg = t->cand.nseg;
    st.seg = (cnSegment *)cn_cand_seg(&t->cand); /* read only */
    st.path_given = true;
    st.support = t->cand.support;
    st.gripper = -1;
    cn_pl_set_absent(P, present);
    cnStepResult r;
    cnStatus s = cn_simulate_step(a, P->absent, &st, &P->o->sim, &r, P->diag);
    P->nsims++;
    if (s) return s;
    if (r.status != CN_STEP_UNSTABLE || !r.onset.part) {
        cn_step_result_free(&r);
        return CN_OK;
    }
    int nf = 0;
    FC *fc = fixel_candidates(a, &r.onset, &nf);
    cn_step_result_free(&r);
    if (!fc) return cn_diag_oom(P->diag);
    s = try_fixels(O, present, t, &st, fc, nf, out);
    cn_free(fc);
    return s;
}
