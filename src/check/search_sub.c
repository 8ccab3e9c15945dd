/* Part of a motion problem as a problem of its own: some of its bodies, every contact that
 * touches one of them (the other side, when it is not one of them, held still as a fixed part),
 * their friction and their rows of the static field, renumbered. A group of bodies that
 * contacts join (search_split.c) has no contact with the rest; a single body held among the
 * rest (search_local.c) has. */
#include <string.h>

#include "search.h"

void cn_sub_free(cnSub *g) {
    cn_free(g->m.com), cn_free(g->m.minv), cn_free(g->m.mass), cn_free(g->m.inertia);
    cn_free(g->m.fext), cn_free(g->m.a0), cn_free(g->m.radius), cn_free(g->m.pushed);
    cn_free(g->m.part_of_body);
    cn_free(g->rows), cn_free(g->cof), cn_free(g->mu), cn_free(g->nominal), cn_free(g->field);
    cn_free(g->body), cn_free(g->row);
    memset(g, 0, sizeof *g);
}

/* Does a row touch one of the bodies kept (sub >= 0)? */
static bool kept(const cnJRow *row, const int *sub) {
    return (row->body[0] >= 0 && sub[row->body[0]] >= 0) ||
           (row->body[1] >= 0 && sub[row->body[1]] >= 0);
}

int cn_sub_make(const cnMotionProblem *p, const int *sub, const int *bodies, int nbodies,
                const int *contacts, int ncontacts, const int *fof, cnSub *g) {
    const cnMech *M = p->m;
    int nd = M->nd, K = p->K, Kf = p->Kf, D = p->D, nb = 0, k = 0, kf = 0;
    memset(g, 0, sizeof *g);
    if (bodies)
        nb = nbodies;
    else
        for (int b = 0; b < M->nb; b++)
            nb += sub[b] >= 0;
    int *own = NULL; /* the contacts kept, when not given */
    if (!contacts) {
        own = cn_malloc(sizeof(int) * (size_t)(K + 1));
        if (!own) return -1;
        for (int c = 0; c < K; c++)
            if (kept(&p->rows[c], sub)) own[ncontacts++] = c;
        contacts = own;
    }
    int *ffor = NULL; /* the friction contact of each contact, when not given */
    if (!fof) {
        ffor = cn_malloc(sizeof(int) * (size_t)(K + 1));
        if (!ffor) {
            cn_free(own);
            return -1;
        }
        for (int c = 0; c < K; c++)
            ffor[c] = -1;
        for (int f = 0; f < Kf; f++)
            ffor[p->contact_of_fric[f]] = f;
        fof = ffor;
    }
    k = ncontacts;
    for (int i = 0; i < ncontacts; i++)
        kf += fof[contacts[i]] >= 0;
    cnMech *m = &g->m;
    *m = *M;
    m->nb = nb;
    m->body_of_part = NULL; /* not read by the search */
    m->com = cn_malloc(sizeof(double[3]) * (size_t)(nb + 1));
    m->minv = cn_malloc(sizeof(double) * (size_t)(nb * nd * nd + 1));
    m->mass = cn_malloc(sizeof(double) * (size_t)(nb + 1));
    m->inertia = cn_malloc(sizeof(double) * (size_t)(nb + 1) * 9);
    m->fext = cn_malloc(sizeof(double) * (size_t)(nb * nd + 1));
    m->a0 = cn_malloc(sizeof(double) * (size_t)(nb * nd + 1));
    m->radius = cn_malloc(sizeof(double) * (size_t)(nb + 1));
    m->pushed = cn_malloc((size_t)nb + 1);
    m->part_of_body = cn_malloc(sizeof(int) * (size_t)(nb + 1));
    g->body = cn_malloc(sizeof(int) * (size_t)(nb + 1));
    size_t nrows = (size_t)k + (size_t)kf * (size_t)D;
    g->rows = cn_malloc(sizeof(cnJRow) * (nrows + 1));
    g->row = cn_malloc(sizeof(int) * (nrows + 1));
    g->cof = cn_malloc(sizeof(int) * (size_t)(kf + 1));
    g->mu = cn_malloc(sizeof(double) * (size_t)(kf + 1));
    g->nominal = cn_calloc((size_t)kf * (size_t)D + 1, sizeof(double));
    g->field = p->field ? cn_malloc(sizeof(double) * (nrows + 1)) : NULL;
    if (!m->com || !m->minv || !m->mass || !m->inertia || !m->fext || !m->a0 || !m->radius ||
        !m->pushed || !m->part_of_body || !g->body || !g->rows || !g->row || !g->cof || !g->mu ||
        !g->nominal || (p->field && !g->field)) {
        cn_free(own), cn_free(ffor);
        return -1;
    }
    for (int i = 0; i < (bodies ? nbodies : M->nb); i++) {
        int b = bodies ? bodies[i] : i, s = sub[b];
        if (s < 0) continue;
        g->body[s] = b;
        memcpy(m->com[s], M->com[b], sizeof(double[3]));
        memcpy(m->minv + (size_t)s * nd * nd, M->minv + (size_t)b * nd * nd,
               sizeof(double) * (size_t)(nd * nd));
        memcpy(m->inertia + (size_t)s * 9, M->inertia + (size_t)b * 9, sizeof(double) * 9);
        memcpy(m->fext + (size_t)s * nd, M->fext + (size_t)b * nd, sizeof(double) * (size_t)nd);
        memcpy(m->a0 + (size_t)s * nd, M->a0 + (size_t)b * nd, sizeof(double) * (size_t)nd);
        m->mass[s] = M->mass[b], m->radius[s] = M->radius[b], m->pushed[s] = M->pushed[b];
        m->part_of_body[s] = M->part_of_body[b];
    }
    bool drags = false;
    for (int i = 0, ff = 0; i < ncontacts; i++) {
        int c = contacts[i], f = fof[c];
        g->row[i] = c;
        g->rows[i] = p->rows[c];
        if (f < 0) continue;
        g->cof[ff] = i;
        g->mu[ff] = p->mu[f];
        for (int d = 0; d < D; d++) {
            int src = K + f * D + d, dst = k + ff * D + d;
            g->row[dst] = src;
            g->rows[dst] = p->rows[src];
            double v = p->nominal ? p->nominal[f * D + d] : 0;
            g->nominal[ff * D + d] = v;
            drags |= v != 0;
        }
        ff++;
    }
    cn_free(own), cn_free(ffor);
    for (size_t i = 0; i < nrows; i++) {
        for (int x = 0; x < 2; x++) /* the other side, when not kept, held still */
            if (g->rows[i].body[x] >= 0) g->rows[i].body[x] = sub[g->rows[i].body[x]];
        if (g->field) g->field[i] = p->field[g->row[i]];
    }
    g->p = *p;
    g->p.m = m;
    g->p.K = k, g->p.Kf = kf;
    g->p.rows = g->rows;
    g->p.contact_of_fric = g->cof;
    g->p.mu = g->mu;
    g->p.nominal = drags ? g->nominal : NULL;
    g->p.field = g->field;
    return 0;
}
