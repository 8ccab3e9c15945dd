/* Sliding modes of the search for a motion from rest: a friction group's modes, and the
 * patterns of modes a joint's points can take together, branched on member by member. */
#include <math.h>
#include <string.h>

#include "search.h"

/* A joint's sliding patterns kept at most, and the small LPs spent finding them (past either,
 * its points are branched on one by one, as single contacts). */
#define CN_BB_JOINT_MAX_PATTERNS 1024
#define CN_BB_JOINT_MAX_LPS 20000
/* Simplex pivots per LP of a joint's enumeration, at most. */
#define CN_BB_JOINT_PIVOTS 2000
/* A joint's pattern exists when the LP's margin on its strict inequalities exceeds this (the
 * conditions are cones, so a pattern that exists reaches the cap of 1; this only absorbs
 * rounding). */
#define CN_BB_JOINT_STRICT 1e-9

/* With two friction directions (2-D) a group's friction pairs have three modes, which between
 * them hold every solution (up to its sliding speed lambda, which no motion depends on: where
 * the group carries no normal force, lambda = |a_t| is as good as any larger one):
 *   0 stick     lambda = 0 (both rows w = +-a_t >= 0, so a_t = 0)
 *   1 slide +   zeta = 0, p_+ = 0, w_- = 0 (friction mu sum p_n along -, a_t = lambda >= 0)
 *   2 slide -   zeta = 0, p_- = 0, w_+ = 0
 * With D >= 3 directions evenly spaced about the normal (3-D), D + 1 modes:
 *   0     stick   lambda = 0 (w_d = d.a_t >= 0 in every direction, so a_t = 0)
 *   1 + j slide   zeta = 0, w_j = 0, p_d = 0 for every d other than j and j + 1 (mod D)
 * Every solution with lambda > 0 and a_t != 0 has lambda = max_d (-d.a_t) (were it larger, every
 * w_d > 0, no friction, zeta = mu p_n = 0 and lambda can be lowered to that max), attained by one
 * direction or two adjacent ones, and friction only there: mode 1 + j for the first of them.
 * With a_t = 0 and lambda > 0 the contact carries nothing and lambda = 0 is as good: mode 0.
 * (With nominal sliding v, w_d = d.(a_t + v) + lambda and the same holds of a_t + v; the modes
 * are used only without it, see below.)
 * One branch per mode instead of one per pair: the pairs' patterns, most of them empty, are
 * never visited one by one (about half the LPs on a 3-D block on an incline). In 3-D, only in
 * the energy search: in the component search (nominal sliding) the LPs after fixing D + 1
 * pairs at once take longer than the branches they save. bb_mode_pairs lists the pairs a mode
 * fixes (choice 1: z = 0, 2: w = 0); cn_bb_mode fixes them (fixed/nfixed receive them). */
static int bb_mode_pairs(const Bb *s, int g, int mode, int *pairs, int *choice) {
    int K = s->p->K, D = s->p->D, lam = s->nrows + g, base = K + g * D, k = 0;
    if (mode == 0) {
        pairs[k] = lam, choice[k++] = 1;
    } else if (D == 2) {
        int plus = base, minus = base + 1;
        pairs[k] = lam, choice[k++] = 2;
        pairs[k] = mode == 1 ? plus : minus, choice[k++] = 1;
        pairs[k] = mode == 1 ? minus : plus, choice[k++] = 2;
    } else {
        int j = mode - 1, j1 = (j + 1) % D;
        pairs[k] = lam, choice[k++] = 2;
        pairs[k] = base + j, choice[k++] = 2;
        for (int d = 0; d < D; d++)
            if (d != j && d != j1) pairs[k] = base + d, choice[k++] = 1;
    }
    return k;
}

void cn_bb_mode(Bb *s, int g, int mode, int *fixed, int *nfixed) {
    int pairs[CN_BB_MAX_D + 2], choice[CN_BB_MAX_D + 2];
    int k = bb_mode_pairs(s, g, mode, pairs, choice);
    for (int j = 0; j < k; j++) {
        cn_bb_pair_set(s, pairs[j], choice[j]);
        fixed[(*nfixed)++] = pairs[j];
    }
}

/* The distance of the node's LP solution from a friction group's mode: the sum of what the mode
 * sets to zero (z of the pairs it fixes at z = 0, w of those at w = 0). */
double cn_bb_mode_far(const Bb *s, int g, int mode) {
    int pairs[CN_BB_MAX_D + 2], choice[CN_BB_MAX_D + 2];
    int k = bb_mode_pairs(s, g, mode, pairs, choice);
    double far = 0;
    for (int j = 0; j < k; j++) far += choice[j] == 1 ? s->x[pairs[j]] : s->wv[pairs[j]];
    return far;
}

/* The group whose friction modes to branch on for pair i: -1 when i is a normal pair, one of
 * the group's pairs is already fixed, or the pyramid has more than two directions outside the
 * energy search. */
int cn_bb_mode_group(const Bb *s, int i) {
    int K = s->p->K, D = s->p->D;
    if (i < K || D < 2 || D > CN_BB_MAX_D || (D > 2 && !s->energy)) return -1;
    int g = i < s->nrows ? (i - K) / D : i - s->nrows;
    if (s->fix[s->nrows + g]) return -1;
    for (int d = 0; d < D; d++)
        if (s->fix[K + g * D + d]) return -1;
    return g;
}

/* Are none of group g's pairs (its friction rows and sliding speed) fixed? */
bool cn_bb_group_free(const Bb *s, int g) {
    int K = s->p->K, D = s->p->D;
    if (s->fix[s->nrows + g]) return false;
    for (int d = 0; d < D; d++)
        if (s->fix[K + g * D + d]) return false;
    return true;
}

/* Joint patterns. A friction group's sliding modes (bb_mode_pairs: 0 stick, 1 + j sliding with
 * d_j a direction of largest -d.u, friction on d_j and d_{j+1}) depend only on its slip u, and
 * the slips of a joint's points are those of one relative motion of its two bodies: a face that
 * slides without turning slides the same way at every point, one that turns about its normal
 * slides each point about the same pole. A pattern (one mode per member) is kept when some
 * motion of the two bodies gives it: stick, u = 0; mode 1 + j, d_j.u <= d.u for every direction
 * d, strictly for d_{j-1} (a slip whose largest -d.u is at d_{j-1} and d_j is mode j's); and,
 * unless every member sticks, the sliding members' slips summing to a positive amount (the
 * conditions are cones). Every solution of the LCP has one of the patterns, each member's mode
 * being the one bb_mode_pairs assigns it, so branching on a joint's patterns leaves no solution
 * out, with far fewer children than the members' modes combined (a rectangle's 4 points at 8
 * directions: about 200 of 9^4 = 6,561). */
typedef struct {
    Bb *s;
    glp_prob *P;
    int J, k, D, nb2, body[2];
    const int *mem;           /* the joint's groups */
    int idx[CN_BB_JOINT_MAX];  /* k: the members enumerated (indices into mem) */
    unsigned char *pat;       /* k: the pattern being built */
    unsigned char *out;       /* cap patterns of k modes: those found */
    int cap, npat;
    long lps;
    bool over;                /* more than cap patterns, or CN_BB_JOINT_MAX_LPS */
} JointEnum;

/* Member i's slip along direction d as a row over the two bodies' velocities (out[1..nv],
 * dense; a rotational dof in units of g / radius, as the search's LP, so that every coefficient
 * is of order 1). */
static void je_row(const JointEnum *e, int i, int d, double *out) {
    const cnMotionProblem *p = e->s->p;
    const cnMech *m = p->m;
    const cnJRow *r = &p->rows[p->K + e->s->grep[e->mem[e->idx[i]]] * p->D + d];
    for (int c = 0; c <= e->nb2 * m->nd; c++) out[c] = 0;
    for (int x = 0; x < 2; x++) {
        int b = r->body[x];
        if (b < 0) continue;
        int slot = b == e->body[0] ? 0 : 1;
        double rad = m->radius[b] > 0 ? m->radius[b] : 1.0;
        for (int q = 0; q < m->nd; q++) out[slot * m->nd + q + 1] += r->c[x][q] / (q < m->dim ? 1.0 : rad);
    }
}

/* Adds the row sum_c coef[c] y_c (+ t when strict; bounds type, lo, hi) to the enumeration's
 * LP. */
static void je_add(JointEnum *e, const double *coef, bool strict, int type, double lo, double hi) {
    int nv = e->nb2 * e->s->p->m->nd, nz = 0, ind[14];
    double val[14];
    for (int c = 1; c <= nv; c++)
        if (coef[c] != 0) ind[++nz] = c, val[nz] = coef[c];
    if (strict) ind[++nz] = nv + 1, val[nz] = 1.0;
    int r = glp_add_rows(e->P, 1);
    glp_set_mat_row(e->P, r, nz, ind, val);
    glp_set_row_bnds(e->P, r, type, lo, hi);
}

/* Is the set the rows added so far describe nonempty? Column nv + 1 (t) is the margin of the
 * strict inequalities; the set is nonempty when the LP's largest t is positive (past rounding).
 * 1 yes, 0 no, -1 the solver failed. */
static int je_feasible(JointEnum *e) {
    if (++e->lps > CN_BB_JOINT_MAX_LPS) {
        e->over = true;
        return 0;
    }
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    parm.presolve = GLP_OFF;
    /* a few dozen rows and columns: past this the simplex cycles (a degenerate vertex of badly
       scaled rows), the joint's patterns are given up and its points branched on one by one */
    parm.it_lim = CN_BB_JOINT_PIVOTS;
    for (int attempt = 0; attempt < 2; attempt++) {
        if (attempt == 1) glp_adv_basis(e->P, 0);
        if (glp_simplex(e->P, &parm) != 0) continue;
        int st = glp_get_status(e->P);
        if (st == GLP_OPT) return glp_get_obj_val(e->P) > CN_BB_JOINT_STRICT;
        if (st == GLP_NOFEAS) return 0;
    }
    return -1;
}

/* Depth-first over the members: member i's mode, its rows added, pruned when infeasible;
 * complete patterns are recorded. Returns -1 when the solver failed. */
static int je_dfs(JointEnum *e, int i, int nsliding) {
    int D = e->D, nv = e->nb2 * e->s->p->m->nd;
    double rj[13], rd[13], coef[13];
    for (int mode = 0; mode <= D && !e->over; mode++) {
        int first = glp_get_num_rows(e->P) + 1;
        if (mode == 0) {
            for (int d = 0; d < D; d++) je_row(e, i, d, rd), je_add(e, rd, false, GLP_FX, 0.0, 0.0);
        } else {
            je_row(e, i, mode - 1, rj);
            for (int d = 0; d < D; d++) {
                if (d == mode - 1) continue;
                je_row(e, i, d, rd);
                for (int c = 1; c <= nv; c++) coef[c] = rj[c] - rd[c];
                /* d_j.u <= d.u, and < for the direction before j: a slip whose friction may lie
                   on d_{j-1} and d_j is mode j's (bb_mode_pairs) */
                je_add(e, coef, d == (mode - 2 + D) % D, GLP_UP, 0.0, 0.0);
            }
        }
        /* row 1: minus the sliding members' slips along their own direction, >= 1 once one
           slides */
        e->pat[i] = (unsigned char)mode;
        int ns = nsliding + (mode > 0);
        for (int c = 0; c <= nv; c++) coef[c] = 0;
        for (int q = 0; q <= i; q++) {
            if (e->pat[q] == 0) continue;
            je_row(e, q, e->pat[q] - 1, rd);
            for (int c = 1; c <= nv; c++) coef[c] -= rd[c];
        }
        int nz = 0, ind[13];
        double val[13];
        for (int c = 1; c <= nv; c++)
            if (coef[c] != 0) ind[++nz] = c, val[nz] = coef[c];
        glp_set_mat_row(e->P, 1, nz, ind, val);
        if (ns > 0) glp_set_row_bnds(e->P, 1, GLP_LO, 1.0, 0.0);
        else glp_set_row_bnds(e->P, 1, GLP_FR, 0.0, 0.0);
        int f = je_feasible(e), rc = 0;
        if (f < 0) rc = -1;
        else if (f == 1 && i + 1 < e->k) rc = je_dfs(e, i + 1, ns);
        else if (f == 1 && e->npat >= e->cap) e->over = true;
        else if (f == 1) memcpy(e->out + (size_t)e->npat++ * (size_t)e->k, e->pat, (size_t)e->k);
        int nrow = glp_get_num_rows(e->P), del[65], nd = 0;
        for (int r = first; r <= nrow && nd < 64; r++) del[++nd] = r;
        if (nd > 0) glp_del_rows(e->P, nd, del);
        if (rc < 0) return -1;
    }
    return 0;
}

/* The joints (s->joint, jfirst, jmem, NJ): friction groups between the same two bodies whose
 * normal rows have the same direction, 2 to CN_BB_JOINT_MAX of them. Their patterns are found later
 * (cn_bb_joint_patterns). Only in 3-D, in the energy search. Returns -1 when out of memory. */
int cn_bb_joints(Bb *s) {
    const cnMotionProblem *p = s->p;
    const cnMech *m = p->m;
    int G = s->G;
    s->joint = cn_malloc(sizeof(int) * (size_t)(G + 1));
    s->jfirst = cn_malloc(sizeof(int) * (size_t)(G + 2));
    s->jmem = cn_malloc(sizeof(int) * (size_t)(G + 1));
    if (!s->joint || !s->jfirst || !s->jmem) return -1;
    int *root = s->jmem; /* scratch first: the first group of each group's joint */
    for (int g = 0; g < G; g++) {
        const cnJRow *rg = &p->rows[p->contact_of_fric[s->grep[g]]];
        root[g] = g;
        if ((rg->body[0] < 0 && rg->body[1] < 0) || s->gfirst[g + 1] - s->gfirst[g] != 1) continue;
        for (int h = 0; h < g && root[g] == g; h++) {
            if (root[h] != h) continue;
            const cnJRow *rh = &p->rows[p->contact_of_fric[s->grep[h]]];
            bool same = rg->body[0] == rh->body[0] && rg->body[1] == rh->body[1] &&
                        s->gfirst[h + 1] - s->gfirst[h] == 1;
            for (int x = 0; x < 2 && same; x++)
                for (int k = 0; k < m->dim && same; k++)
                    if (fabs(rg->c[x][k] - rh->c[x][k]) > CN_BB_SAME_ROW) same = false;
            if (same) root[g] = h;
        }
    }
    int NJ = 0;
    for (int g = 0; g < G; g++) s->joint[g] = -1;
    for (int g = 0; g < G; g++) {
        if (root[g] != g) continue;
        int k = 0;
        for (int h = g; h < G; h++) k += root[h] == g;
        if (k < 2 || k > CN_BB_JOINT_MAX) continue;
        for (int h = g; h < G; h++)
            if (root[h] == g) s->joint[h] = NJ;
        NJ++;
    }
    int at = 0;
    for (int J = 0; J < NJ; J++) {
        s->jfirst[J] = at;
        for (int g = 0; g < G; g++)
            if (s->joint[g] == J) s->jmem[at++] = g;
    }
    s->jfirst[NJ] = at;
    s->NJ = NJ;
    size_t slots = (size_t)NJ << CN_BB_JOINT_MAX;
    s->jnpat = cn_malloc(sizeof(int) * (slots + 1));
    s->jpat = cn_calloc(slots + 1, sizeof(unsigned char *));
    if (!s->jnpat || !s->jpat) return -1;
    for (size_t i = 0; i < slots; i++) s->jnpat[i] = -1;
    return 0;
}

/* The patterns of joint J's members in mask, found on first use: how many (0 when there are
 * too many, or the LP solver failed, or memory ran out: those points are then branched on one
 * by one). */
int cn_bb_joint_patterns(Bb *s, int J, unsigned mask) {
    size_t slot = ((size_t)J << CN_BB_JOINT_MAX) + mask;
    if (s->jnpat[slot] >= 0) return s->jnpat[slot];
    const cnMotionProblem *p = s->p;
    int cap = CN_BB_JOINT_MAX_PATTERNS, n = s->jfirst[J + 1] - s->jfirst[J];
    const int *mem = s->jmem + s->jfirst[J];
    const cnJRow *r0 = &p->rows[p->contact_of_fric[s->grep[mem[0]]]];
    unsigned char pat[CN_BB_JOINT_MAX];
    s->jnpat[slot] = 0;
    JointEnum e = {s, NULL, J, 0, p->D, 0, {-1, -1}, mem, {0}, pat, NULL, cap, 0, 0, false};
    for (int q = 0; q < n; q++)
        if (mask >> q & 1) e.idx[e.k++] = q;
    if (e.k == 0) return 0;
    unsigned char *out = cn_bb_tmp(s, TMP_JOUT, (size_t)cap * (size_t)e.k);
    if (!out) return 0;
    e.out = out;
    e.P = glp_create_prob();
    for (int x = 0; x < 2; x++)
        if (r0->body[x] >= 0) e.body[e.nb2++] = r0->body[x];
    int nv = e.nb2 * p->m->nd;
    glp_add_cols(e.P, nv + 1);
    for (int c = 1; c <= nv; c++) glp_set_col_bnds(e.P, c, GLP_FR, 0.0, 0.0);
    glp_set_col_bnds(e.P, nv + 1, GLP_UP, 0.0, 1.0); /* t <= 1 */
    glp_set_obj_coef(e.P, nv + 1, 1.0);
    glp_set_obj_dir(e.P, GLP_MAX);
    glp_add_rows(e.P, 1);
    glp_set_row_bnds(e.P, 1, GLP_FR, 0.0, 0.0);
    int rc = je_dfs(&e, 0, 0);
    glp_delete_prob(e.P);
    if (rc < 0 || e.over || e.npat == 0) {
        cn_bb_tmp_free(s, TMP_JOUT);
        return 0;
    }
    s->tmp[TMP_JOUT] = NULL; /* the joint's now */
    unsigned char *kept = cn_realloc(out, (size_t)e.npat * (size_t)e.k);
    s->jpat[slot] = kept ? kept : out;
    s->jnpat[slot] = e.npat;
    return e.npat;
}

/* Children of a node that branches on joint J's member `level` (in the mask's order): one per
 * mode that member has in the patterns agreeing with pattern rep on the members before it (rep
 * -1: every pattern), each child carrying such a pattern; the mode nearest the LP's solution is
 * pushed last (explored first). False when out of memory. */
bool cn_bb_prefix_children(Bb *s, int *top, const BbEntry *e, int J, unsigned mask, int rep,
                           int level, double obj) {
    int nm = s->jfirst[J + 1] - s->jfirst[J], k = 0, member = -1;
    for (int q = 0; q < nm; q++)
        if (mask >> q & 1 && k++ == level) member = s->jmem[s->jfirst[J] + q];
    size_t slot = ((size_t)J << CN_BB_JOINT_MAX) + mask;
    const unsigned char *pats = s->jpat[slot];
    int np = s->jnpat[slot], nmode = s->p->D + 1;
    int rep_of[CN_BB_MAX_D + 1], order[CN_BB_MAX_D + 1], n = 0;
    double far[CN_BB_MAX_D + 1] = {0};
    for (int m = 0; m < nmode; m++) rep_of[m] = -1;
    for (int q = 0; q < np; q++) {
        const unsigned char *pat = pats + (size_t)q * (size_t)k;
        if (rep >= 0 && memcmp(pat, pats + (size_t)rep * (size_t)k, (size_t)level) != 0) continue;
        if (rep_of[pat[level]] < 0) rep_of[pat[level]] = q;
    }
    for (int m = 0; m < nmode; m++)
        if (rep_of[m] >= 0) order[n] = m, far[m] = cn_bb_mode_far(s, member, m), n++;
    if (!cn_bb_stack_room(s, *top, n)) return false;
    BbEntry *stack = s->tmp[TMP_STACK];
    cn_bb_sort_by_far(order, n, far);
    for (int c = 0; c < n; c++)
        stack[(*top)++] = (BbEntry){e->depth + 1, J, (int)mask, -3, rep_of[order[c]], obj, level};
    return true;
}
