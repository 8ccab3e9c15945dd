/* The node LP of the search for a motion from rest: the relaxation of the contact LCP with some
 * of its complementarity pairs fixed, built once and re-bounded at each node, energy cuts, its
 * basis saved and restored, and its solves in double and in rational arithmetic. */
#include <math.h>
#include <string.h>

#include "search.h"

/* Motions are boxed to this many g in the component search (nominal sliding): no solution of a
 * contact problem under gravity and a gripper's drag comes near it. */
#define CN_BB_BOX 1e4
/* Pivots an exact solve may take (past them the double bound stands): it starts from the double
 * simplex's optimal basis, which is nearly always optimal exactly too, within a few pivots. */
#define CN_BB_EXACT_ITERS 10
/* The exact solve is declined when a coefficient or bound of the LP is outside this range of
 * magnitudes (a friction coefficient of 5e-324, densities 1e150 apart): GLPK's exact simplex
 * turns its fractions into doubles to choose pivots and stops on an internal error when one
 * underflows to 0, and then cannot free its GMP numbers. The node keeps its double bound. */
#define CN_BB_EXACT_RANGE 1e100

/* The force scale of a row: the weight of the heaviest body it touches (the reference weight
 * when it touches none). */
double cn_bb_row_weight(const cnMech *m, const cnJRow *row) {
    double wr = 0;
    for (int x = 0; x < 2; x++)
        if (row->body[x] >= 0) wr = fmax(wr, m->mass[row->body[x]] * m->g);
    return wr > 0 ? wr : m->wref;
}

void *cn_bb_tmp(Bb *s, int slot, size_t bytes) { return s->tmp[slot] = cn_malloc(bytes); }

/* A number of the LP: exact arithmetic is declined when one is outside the range it handles. */
static void exact_range(Bb *s, double v) {
    double a = fabs(v);
    if (a != 0 && !(a >= 1 / CN_BB_EXACT_RANGE && a <= CN_BB_EXACT_RANGE)) s->exact_ok = false;
}
void cn_bb_tmp_free(Bb *s, int slot) {
    cn_free(s->tmp[slot]);
    s->tmp[slot] = NULL;
}

/* The force row of the search's column r: a normal row, or the representative's friction row. */
const cnJRow *cn_bb_row(const Bb *s, int r) {
    const cnMotionProblem *p = s->p;
    if (r < p->K) return &p->rows[r];
    int g = (r - p->K) / p->D, d = (r - p->K) % p->D;
    return &p->rows[p->K + s->grep[g] * p->D + d];
}

/* Are friction contacts f1 and f2 the same rows with the same mu and nominal sliding? */
bool cn_bb_same_friction(const cnMotionProblem *p, int f1, int f2) {
    const cnMech *m = p->m;
    int D = p->D, nd = m->nd, dim = m->dim;
    if (p->mu[f1] != p->mu[f2]) return false;
    for (int d = 0; d < D; d++) {
        const cnJRow *a = &p->rows[p->K + f1 * D + d], *b = &p->rows[p->K + f2 * D + d];
        for (int x = 0; x < 2; x++) {
            if (a->body[x] != b->body[x]) return false;
            if (a->body[x] < 0) continue;
            double rad = m->radius[a->body[x]] > 0 ? m->radius[a->body[x]] : 1.0;
            for (int k = 0; k < nd; k++)
                if (fabs(a->c[x][k] - b->c[x][k]) > CN_BB_SAME_ROW * (k < dim ? 1.0 : rad)) return false;
        }
        if (p->nominal) {
            double u = p->nominal[f1 * D + d], v = p->nominal[f2 * D + d];
            if (fabs(u - v) > CN_BB_SAME_ROW * fmax(fabs(u), fabs(v))) return false;
        }
    }
    return true;
}

int cn_bb_friction_groups(const cnMotionProblem *p, int *of, int *rep) {
    int G = 0;
    for (int f = 0; f < p->Kf; f++) {
        int g = 0;
        while (g < G && !cn_bb_same_friction(p, rep[g], f)) g++;
        if (g == G) rep[G++] = f;
        of[f] = g;
    }
    return G;
}

int cn_motion_search_pairs(const cnMotionProblem *p) {
    int K = p->K, Kf = p->Kf, D = p->D, raw = K + Kf * D + Kf;
    if (raw > CN_SEARCH_PAIRS_GROUPED_UPTO) return raw;
    int *of = cn_malloc(sizeof(int) * (size_t)(2 * Kf + 1));
    if (!of) return raw;
    int G = cn_bb_friction_groups(p, of, of + Kf);
    cn_free(of);
    return K + G * D + G;
}

/* Group the friction contacts (s->G, grep, gfirst, gmem); -1 out of memory. */
int cn_bb_group(Bb *s) {
    const cnMotionProblem *p = s->p;
    int Kf = p->Kf;
    int *of = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    s->grep = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    s->gfirst = cn_malloc(sizeof(int) * (size_t)(Kf + 2));
    s->gmem = cn_malloc(sizeof(int) * (size_t)(Kf + 1));
    if (!of || !s->grep || !s->gfirst || !s->gmem) {
        cn_free(of);
        return -1;
    }
    int G = cn_bb_friction_groups(p, of, s->grep);
    int k = 0;
    for (int g = 0; g < G; g++) {
        s->gfirst[g] = k;
        for (int f = 0; f < Kf; f++)
            if (of[f] == g) s->gmem[k++] = f;
    }
    s->gfirst[G] = k;
    s->G = G;
    cn_free(of);
    return 0;
}

void cn_bb_pair_set(Bb *s, int i, int choice) {
    int col = s->nv + i + 1, row = s->nv + i + 1;
    /* each side that the choice fixes or the previous one fixed is set: a pair switched from one
       choice to the other is never left with z = 0 and w = 0 both (which would hide the solutions
       of either side), and a side nobody fixed is not touched */
    int was = s->fix[i];
    s->fix[i] = (unsigned char)choice;
    if (choice == 1 || was == 1) glp_set_col_bnds(s->P, col, choice == 1 ? GLP_FX : GLP_LO, 0.0, 0.0);
    if (choice == 2) glp_set_row_bnds(s->P, row, GLP_FX, s->rowlo[i], s->rowlo[i]);
    else if (was == 2) glp_set_row_bnds(s->P, row, GLP_LO, s->rowlo[i], 0.0);
}

/* The LP of the relaxation: dynamics (equalities), the pairs' rows (>= lower bounds), and in
 * the energy search the power row 0 <= fext.a <= fext.a0 (valid: every solution has
 * 0 <= |a|_M^2 <= fext.a, and Cauchy-Schwarz gives fext.a <= |fext|_{M^-1}^2). */
int cn_bb_build(Bb *s, bool energy) {
    const cnMotionProblem *p = s->p;
    const cnMech *m = p->m;
    int nd = m->nd, nb = m->nb, K = p->K, Kf = p->Kf, D = p->D, dim = m->dim;
    int nv = s->nv, nrows = s->nrows, n = s->n;
    double W = m->wref, g = m->g;
    glp_prob *P = s->P = glp_create_prob();
    glp_set_obj_dir(P, GLP_MAX);
    int nrow_all = nv + n + (energy ? 1 : 0), ncol = nv + n;
    glp_add_rows(P, nrow_all);
    glp_add_cols(P, ncol);
    for (int b = 0; b < nb; b++)
        for (int k = 0; k < nd; k++) {
            double rad = m->radius[b] > 0 ? m->radius[b] : 1.0;
            s->sv[b * nd + k] = k < dim ? g : g / rad;
        }
    for (int r = 0; r < nrows; r++) s->wcol[r] = cn_bb_row_weight(m, cn_bb_row(s, r));
    /* nonzeros: dynamics 2 nd per force column + nv identity; pair rows 2 nd + 1 each; zeta
     * rows D + 1; power row nv */
    size_t cap = (size_t)nv * 2 + (size_t)nrows * (4 * nd + 1) + (size_t)Kf * (D + 2) + 8;
    int *ia = cn_bb_tmp(s, TMP_IA, sizeof(int) * (cap + 1));
    int *ja = cn_bb_tmp(s, TMP_JA, sizeof(int) * (cap + 1));
    double *ar = cn_bb_tmp(s, TMP_AR, sizeof(double) * (cap + 1));
    if (!ia || !ja || !ar) {
        cn_bb_tmp_free(s, TMP_IA), cn_bb_tmp_free(s, TMP_JA), cn_bb_tmp_free(s, TMP_AR);
        return -1;
    }
    int k = 0;
#define PUT(row, col, val) (ia[++k] = (row), ja[k] = (col), ar[k] = (val))
    s->exact_ok = true;
    for (int i = 0; i < nv; i++) {
        exact_range(s, m->a0[i] / s->sv[i]);
        glp_set_row_bnds(P, i + 1, GLP_FX, m->a0[i] / s->sv[i], 0.0);
        glp_set_col_bnds(P, i + 1, energy ? GLP_FR : GLP_DB, -CN_BB_BOX, CN_BB_BOX);
        PUT(i + 1, i + 1, 1.0);
    }
    for (int r = 0; r < nrows; r++) {
        int col = nv + r + 1, row = nv + r + 1;
        glp_set_col_bnds(P, col, GLP_LO, 0.0, 0.0);
        const cnJRow *jr = cn_bb_row(s, r);
        for (int x = 0; x < 2; x++) {
            int b = jr->body[x];
            if (b < 0) continue;
            for (int d = 0; d < nd; d++) {
                /* dynamics: x - sum (u W_r / sv) p = a0 / sv */
                double u = jr->u[x][d] * s->wcol[r] / s->sv[b * nd + d];
                if (u != 0) PUT(b * nd + d + 1, col, -u);
                /* the pair's row: relative motion along the row, in g */
                double c = jr->c[x][d] * s->sv[b * nd + d] / g;
                if (c != 0) PUT(row, b * nd + d + 1, c);
            }
        }
        double lo = 0;
        if (r >= K) {
            int gr = (r - K) / D;
            PUT(row, nv + nrows + gr + 1, 1.0); /* lambda */
            lo = p->nominal ? -p->nominal[s->grep[gr] * D + (r - K) % D] / g : 0.0;
        }
        s->rowlo[r] = lo;
        exact_range(s, lo);
        glp_set_row_bnds(P, row, GLP_LO, lo, 0.0);
    }
    for (int gr = 0; gr < s->G; gr++) {
        int col = nv + nrows + gr + 1, row = nv + nrows + gr + 1;
        glp_set_col_bnds(P, col, GLP_LO, 0.0, 0.0);
        s->rowlo[nrows + gr] = 0;
        glp_set_row_bnds(P, row, GLP_LO, 0.0, 0.0);
        /* mu sum p_n - sum p_k: every member's normal row has the representative's force scale
           (the same two bodies) */
        for (int j = s->gfirst[gr]; j < s->gfirst[gr + 1]; j++) {
            int f = s->gmem[j];
            PUT(row, nv + p->contact_of_fric[f] + 1, p->mu[f]);
        }
        for (int d = 0; d < D; d++) PUT(row, nv + K + gr * D + d + 1, -1.0);
    }
    if (energy) {
        int row = nv + n + 1;
        double e0 = 0;
        for (int b = 0; b < nb; b++) {
            double mass = m->mass[b];
            for (int d = 0; d < dim; d++) {
                double fa = mass * m->a0[b * nd + d]; /* gravity as the body feels it */
                e0 += fa * m->a0[b * nd + d];
                double coef = fa * s->sv[b * nd + d] / (W * g);
                if (coef != 0) PUT(row, b * nd + d + 1, coef);
                glp_set_obj_coef(P, b * nd + d + 1, coef);
            }
        }
        exact_range(s, e0 / (W * g));
        glp_set_row_bnds(P, row, GLP_DB, -CN_TOL_NOISE, e0 / (W * g) * (1 + 1e-9) + CN_TOL_NOISE);
    }
#undef PUT
    for (int i = 1; i <= k; i++) exact_range(s, ar[i]);
    glp_load_matrix(P, k, ia, ja, ar);
    cn_bb_tmp_free(s, TMP_IA), cn_bb_tmp_free(s, TMP_JA), cn_bb_tmp_free(s, TMP_AR);
    return 0;
}

/* Every solution of the LCP from rest has z.w = a^T M a - fext.a + sum lambda mu p_n = 0, so
 * a^T M a <= fext.a - sum_G mu N_G lambda_G: the contacts do no net work on the motion, and each
 * friction group dissipates mu N_G lambda_G, at least mu l_G lambda_G where l_G is a lower bound
 * of its total normal force N_G (s->nfloor). The LP relaxation does not know it (a friction force
 * may push along the sliding it opposes, if another brakes); this adds the tangent plane of the
 * convex constraint at the current LP solution when that violates it (outer approximation,
 * Kelley): 2 (M a*).a - fext.a + sum mu l_G lambda_G <= a*^T M a*. Returns true when a cut was
 * added. Valid without nominal sliding only. */
bool cn_bb_cut(Bb *s) {
    const cnMotionProblem *p = s->p;
    const cnMech *m = p->m;
    int nv = s->nv, nd = m->nd, dim = m->dim, G = s->G;
    double W = m->wref, g = m->g;
    double fa = 0, diss = 0;
    for (int i = 0; i < nv; i++) s->a[i] = glp_get_col_prim(s->P, i + 1) * s->sv[i];
    double e = cn_mech_kinetic(s->p->m, s->a, s->ma);
    for (int b = 0; b < m->nb; b++)
        for (int k = 0; k < dim; k++) fa += m->mass[b] * m->a0[b * nd + k] * s->a[b * nd + k];
    for (int gr = 0; s->nfloor && gr < G; gr++)
        if (s->nfloor[gr] > 0)
            diss += p->mu[s->grep[gr]] * s->nfloor[gr] * g *
                    fmax(glp_get_col_prim(s->P, nv + s->nrows + gr + 1), 0);
    if (!(e + diss > fa + 1e-9 * (fabs(fa) + e + diss) + CN_TOL_NOISE * W * g)) return false;
    int row = glp_add_rows(s->P, 1);
    int *ind = cn_bb_tmp(s, TMP_IND, sizeof(int) * (size_t)(nv + G + 1));
    double *val = cn_bb_tmp(s, TMP_VAL, sizeof(double) * (size_t)(nv + G + 1));
    if (!ind || !val) {
        cn_bb_tmp_free(s, TMP_IND), cn_bb_tmp_free(s, TMP_VAL);
        glp_del_rows(s->P, 1, (const int[]){0, row});
        return false;
    }
    int k = 0;
    for (int i = 0; i < nv; i++) {
        int b = i / nd, d = i % nd;
        double f = d < dim ? m->mass[b] * m->a0[i] : 0;
        double c = (2 * s->ma[i] - f) * s->sv[i] / (W * g);
        if (c != 0) ind[++k] = i + 1, val[k] = c, exact_range(s, c);
    }
    for (int gr = 0; s->nfloor && gr < G; gr++) {
        double c = p->mu[s->grep[gr]] * s->nfloor[gr] / W; /* lambda's column is in g */
        if (c > 0) ind[++k] = nv + s->nrows + gr + 1, val[k] = c, exact_range(s, c);
    }
    exact_range(s, e / (W * g));
    glp_set_mat_row(s->P, row, k, ind, val);
    glp_set_row_bnds(s->P, row, GLP_UP, 0.0, e / (W * g));
    cn_bb_tmp_free(s, TMP_IND), cn_bb_tmp_free(s, TMP_VAL);
    s->cuts++;
    return true;
}

/* The least total normal force of group gr that the relaxation allows (the LP with its energy
 * cuts, which every solution satisfies), with rounds of energy cuts at its minimizers; the
 * objective is left zero. Returns the force in the LP's scale, or -1 when an LP failed. */
static double group_least(Bb *s, int gr, long *lps, int *added) {
    const cnMotionProblem *p = s->p;
    int nv = s->nv, j0 = s->gfirst[gr], j1 = s->gfirst[gr + 1];
    for (int i = 0; i < nv; i++) glp_set_obj_coef(s->P, i + 1, 0.0);
    for (int j = j0; j < j1; j++) glp_set_obj_coef(s->P, nv + p->contact_of_fric[s->gmem[j]] + 1, -1.0);
    double least = 0;
    for (int round = 0; round < CN_BB_FLOOR_ROUNDS; round++) {
        int lp = cn_bb_lp_meth(s, round == 0 ? GLP_PRIMAL : GLP_DUALP);
        (*lps)++;
        if (lp < 0) return -1;
        if (lp == 0) break; /* no solution at all: nothing to bound */
        least = -glp_get_obj_val(s->P);
        if (!(*added < CN_BB_FLOOR_CUTS && cn_bb_cut(s))) break;
        s->cuts--, (*added)++;
    }
    for (int j = j0; j < j1; j++) glp_set_obj_coef(s->P, nv + p->contact_of_fric[s->gmem[j]] + 1, 0.0);
    return fmax(least, 0);
}

/* Lower bounds of the groups' total normal forces (s->nfloor), each the least the relaxation
 * allows less a margin for the simplex's tolerances; they make the energy cuts count the
 * dissipation of sliding joints. Found for the groups that slide in the root LP's motion, pass
 * after pass, the root's bound cut down with them between passes. Only groups of two points or
 * more (the points of a 2-D joint, which slide together): a single point can lose its load by
 * rocking, and a 3-D joint's points slide at different speeds when it twists. Returns the LPs
 * solved (s->floored: how many floors are positive), or -1 when one failed. */
long cn_bb_normal_floors(Bb *s) {
    const cnMotionProblem *p = s->p;
    int nv = s->nv, G = s->G;
    long lps = 0;
    bool any = false;
    for (int gr = 0; gr < G; gr++) any |= s->gfirst[gr + 1] - s->gfirst[gr] >= 2;
    if (!any || p->m->dim != 2) return 0;
    s->nfloor = cn_calloc((size_t)G + 1, sizeof(double));
    double *obj = cn_malloc(sizeof(double) * (size_t)(nv + 1));
    unsigned char *done = cn_calloc((size_t)G + 1, 1);
    if (!s->nfloor || !obj || !done) {
        cn_free(obj), cn_free(done);
        cn_free(s->nfloor);
        s->nfloor = NULL;
        return 0; /* no floors: the cuts stay as they were */
    }
    for (int i = 0; i < nv; i++) obj[i] = glp_get_obj_coef(s->P, i + 1);
    int added = 0; /* cuts made here, not counted against the search's own (s->cuts) */
    bool failed = false;
    for (int pass = 0; pass < CN_BB_FLOOR_PASSES && !failed; pass++) {
        int lp = cn_bb_lp(s);
        lps++;
        if (lp <= 0) {
            failed = lp < 0;
            break;
        }
        int found = 0;
        for (int gr = 0; gr < G && !failed; gr++) {
            int j0 = s->gfirst[gr];
            if (done[gr] || s->gfirst[gr + 1] - j0 < 2) continue;
            if (!(glp_get_col_prim(s->P, nv + s->nrows + gr + 1) > CN_BB_COMPL_TOL)) continue;
            done[gr] = 1, found++;
            double least = group_least(s, gr, &lps, &added);
            if (least < 0) failed = true;
            /* in the members' force scale (one for the group: the same two bodies) */
            else s->nfloor[gr] = fmax(least - CN_BB_FLOOR_MARGIN * (1 + least), 0) *
                                 s->wcol[p->contact_of_fric[s->gmem[j0]]];
        }
        for (int i = 0; i < nv; i++) glp_set_obj_coef(s->P, i + 1, obj[i]);
        if (failed) break;
        if (found > 0 && added > 0) { /* the floors' cuts served the floors: dense rows that
                                           slow every LP after them */
            int nr = glp_get_num_rows(s->P);
            int *del = cn_malloc(sizeof(int) * (size_t)(added + 1));
            if (del) {
                for (int k = 1; k <= added; k++) del[k] = nr - added + k;
                glp_del_rows(s->P, added, del);
                cn_free(del);
                glp_adv_basis(s->P, 0);
                added = 0;
            }
        }
        if (found == 0) { /* no new sliding group: cut the bound down instead */
            if (added >= CN_BB_FLOOR_CUTS || !cn_bb_cut(s)) break;
            s->cuts--, added++;
        }
    }
    cn_free(obj), cn_free(done);
    if (failed) {
        memset(s->nfloor, 0, sizeof(double) * (size_t)G);
        return -1;
    }
    for (int gr = 0; gr < G; gr++) s->floored += s->nfloor[gr] > 0;
    return lps;
}

/* The LP's basis, the status of each row and column (rows + cols bytes), into b and back: a
 * node's children start from their parent's basis, one fix away, wherever the search went in
 * between. nr_saved: the rows when it was saved; the cuts added since are basic rows (their
 * slack in the basis). GLPK factorizes the basis put back at the next solve (cn_bb_lp falls back
 * to an advanced basis when that fails). */
void cn_bb_basis_get(const Bb *s, unsigned char *b) {
    int nr = glp_get_num_rows(s->P), nc = glp_get_num_cols(s->P);
    for (int i = 1; i <= nr; i++) b[i - 1] = (unsigned char)glp_get_row_stat(s->P, i);
    for (int j = 1; j <= nc; j++) b[nr + j - 1] = (unsigned char)glp_get_col_stat(s->P, j);
}

void cn_bb_basis_put(Bb *s, const unsigned char *b, int nr_saved) {
    int nr = glp_get_num_rows(s->P), nc = glp_get_num_cols(s->P);
    for (int i = 1; i <= nr; i++) glp_set_row_stat(s->P, i, i <= nr_saved ? b[i - 1] : GLP_BS);
    for (int j = 1; j <= nc; j++) glp_set_col_stat(s->P, j, b[nr_saved + j - 1]);
}

/* Solve the current node's LP: 1 optimal, 0 infeasible, -1 the solver failed. */
int cn_bb_lp(Bb *s) { return cn_bb_lp_meth(s, GLP_DUALP); }

/* The same with the simplex method given: GLP_PRIMAL after a change of objective, whose basis
 * stays primal feasible. */
int cn_bb_lp_meth(Bb *s, int meth) {
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.meth = meth;
    parm.presolve = GLP_OFF;
    parm.it_lim = 20000 + 50 * (glp_get_num_rows(s->P) + glp_get_num_cols(s->P));
    for (int attempt = 0; attempt < 2; attempt++) {
        if (attempt == 1) glp_adv_basis(s->P, 0);
        int rc = glp_simplex(s->P, &parm);
        if (rc != 0) continue;
        int st = glp_get_status(s->P);
        if (st == GLP_OPT) return 1;
        if (st == GLP_NOFEAS) return 0;
    }
    return -1;
}

/* The node's LP as the search solves it: in the energy search, one round of energy cuts when
 * its bound is near a prune (below CN_BB_CUT_BELOW) while fewer than CN_BB_CUT_MAX are kept,
 * then solved again. Returns as cn_bb_lp. */
int cn_bb_node_lp(Bb *s) {
    int lp = cn_bb_lp(s);
    if (s->energy && lp == 1 && s->cuts < CN_BB_CUT_MAX &&
        glp_get_obj_val(s->P) < CN_BB_CUT_BELOW && cn_bb_cut(s))
        lp = cn_bb_lp(s);
    return lp;
}

/* The current node's LP again in exact rational arithmetic, from the basis the double simplex
 * left: 1 optimal (its solution now the LP's), 0 infeasible, -1 not solved (an iteration limit
 * or a failure; the LP is then solved again in double so that its solution is the node's), -2
 * that double solve failed too. */
int cn_bb_exact(Bb *s) {
    if (!s->exact_ok) return -1; /* the double solve just made stands */
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.it_lim = CN_BB_EXACT_ITERS;
    if (glp_exact(s->P, &parm) == 0) {
        int st = glp_get_status(s->P);
        if (st == GLP_OPT) return 1;
        if (st == GLP_NOFEAS) return 0;
    }
    int lp = cn_bb_lp(s);
    return lp == 1 ? -1 : lp == 0 ? 0 : -2;
}
