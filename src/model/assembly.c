/* The loaded assembly: lookups and freeing. */
#include <math.h>
#include <string.h>

#include "pieces.h"

void cn_assembly_free(cnAssembly *a) {
    if (!a) return;
    for (int i = 0; i < a->nparts; i++) {
        cnPart *p = &a->parts[i];
        for (int k = 0; k < p->npieces; k++) cn_piece_free(&p->pieces[k]);
        cn_free(p->pieces);
        cn_free(p->outline);
        cn_free(p->mesh_file);
        cn_free(p->name);
    }
    cn_free(a->parts);
    for (int k = 0; k < a->nsteps; k++) {
        cn_free(a->plan[k].move);
        cn_free(a->plan[k].grip);
        cn_free(a->plan[k].seg);
    }
    cn_free(a->plan);
    for (int k = 0; k < a->ncand; k++) {
        cn_free(a->cand[k].name);
        cn_free(a->cand[k].seg);
    }
    cn_free(a->cand);
    cn_free(a->fixels);
    cn_free(a->pairs);
    cn_free(a->name);
    cn_free(a->source);
    cn_free(a);
}

int cn_assembly_find_part(const cnAssembly *a, const char *name) {
    for (int i = 0; i < a->nparts; i++)
        if (a->parts[i].name && !strcmp(a->parts[i].name, name)) return i;
    return -1;
}

double cn_assembly_mu(const cnAssembly *a, int i, int j) {
    if (i < 0 || j < 0) return 0.0; /* fixels are frictionless */
    int lo = i < j ? i : j, hi = i < j ? j : i;
    for (int k = 0; k < a->npairs; k++)
        if (a->pairs[k].a == lo && a->pairs[k].b == hi) return a->pairs[k].mu;
    return a->friction;
}

double cn_part_weight(const cnAssembly *a, int i) {
    return a->parts[i].mass * cn_norm3(a->gravity);
}

bool cn_assembly_part_present(const cnAssembly *a, const unsigned char *absent, int i) {
    return absent ? !absent[i] : a->parts[i].gripper_step < 0;
}

int cn_part_present(const cnAssembly *a, const cnContactQuery *q, int i) {
    return cn_assembly_part_present(a, q ? q->absent : NULL, i);
}

int cn_plan_moves(const cnAssembly *a, int step, int part) {
    if (step < 0 || step >= a->nsteps) return 0;
    for (int i = 0; i < a->plan[step].nmove; i++)
        if (a->plan[step].move[i] == part) return 1;
    return 0;
}

void cn_fixel_probe(const cnAssembly *a, const cnFixel *f, double *at, double *in, double *out, double *tol) {
    const cnPart *pt = &a->parts[f->part];
    double psize = hypot(hypot(pt->hi[0] - pt->lo[0], pt->hi[1] - pt->lo[1]), pt->hi[2] - pt->lo[2]);
    double eps = 1e-3 * psize, pin[3], pout[3];
    *tol = fmax(a->contact_tol, 1e-9 * psize);
    for (int k = 0; k < 3; k++) pin[k] = f->point[k] + eps * f->normal[k], pout[k] = f->point[k] - eps * f->normal[k];
    *at = *in = *out = INFINITY;
    for (int i = 0; i < pt->npieces; i++) {
        *at = fmin(*at, cn_piece_plane_distance(&pt->pieces[i], a->dim, f->point));
        *in = fmin(*in, cn_piece_plane_distance(&pt->pieces[i], a->dim, pin));
        *out = fmin(*out, cn_piece_plane_distance(&pt->pieces[i], a->dim, pout));
    }
}
