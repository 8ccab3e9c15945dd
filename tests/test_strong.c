/* The search for a motion from rest (strong stability) against brute force: small random 2-D
 * contact problems whose Stewart-Trinkle LCP is enumerated, an LP over the solutions of each
 * pattern, so that "a solution moves" is known without the search's energy bound, cuts or
 * friction groups. Two enumerations: every complementarity pattern (each pair z = 0 or w = 0:
 * independent of any case split, run on the problems of at most 3 contacts) and every contact
 * mode (open, stick, slide either way: the same four-way split the search's modes rest on, its
 * argument in brute_modes; all problems). Contacts are drawn on the faces of one or two blocks,
 * often two at the corners of one face (a flat joint, whose friction the search carries as one
 * group), under gravity from a random direction; in a third of the problems the frame slides
 * under the blocks (nominal sliding: the search without its energy bound). */
#include <glpk.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <valgrind/valgrind.h>

#include "helpers.h"
#include "mech.h"
#include "proof_memo.h"
#include "strong.h"

#define MAXC 6
#define D2 2

typedef struct {
    const cnMotionProblem *p;
    glp_prob *P;
    int nv, nrows, n;
    double tol; /* motion threshold, absolute */
    int moves;  /* 1: a solution moves by more than 10 tol; set by leaves */
    int gray;   /* a leaf's largest motion between 0.1 and 10 tol */
    long lps;
} Brute;

static int quiet(void *info, const char *s) {
    (void)info, (void)s;
    return 1;
}

/* The LP of every solution of the LCP (no complementarity): a, the forces, the sliding speeds. */
static glp_prob *brute_lp(const cnMotionProblem *p, int nv, int nrows) {
    const cnMech *m = p->m;
    int nd = m->nd, K = p->K, D = p->D, Kf = p->Kf;
    glp_prob *P = glp_create_prob();
    glp_add_rows(P, nv + nrows + Kf);
    glp_add_cols(P, nv + nrows + Kf);
    for (int i = 0; i < nv; i++) {
        glp_set_col_bnds(P, i + 1, GLP_FR, 0, 0);
        glp_set_row_bnds(P, i + 1, GLP_FX, m->a0[i], m->a0[i]);
        int ind[64], k = 0;
        double val[64];
        ind[++k] = i + 1, val[k] = 1.0;
        for (int r = 0; r < nrows; r++)
            for (int x = 0; x < 2; x++)
                if (p->rows[r].body[x] == i / nd && p->rows[r].u[x][i % nd] != 0)
                    ind[++k] = nv + r + 1, val[k] = -p->rows[r].u[x][i % nd];
        glp_set_mat_row(P, i + 1, k, ind, val);
    }
    for (int r = 0; r < nrows; r++) {
        glp_set_col_bnds(P, nv + r + 1, GLP_LO, 0, 0);
        double lo = r >= K && p->nominal ? -p->nominal[r - K] : 0.0; /* w >= 0 with the sliding */
        glp_set_row_bnds(P, nv + r + 1, GLP_LO, lo, lo);
        int ind[32], k = 0;
        double val[32];
        for (int x = 0; x < 2; x++)
            for (int d = 0; d < nd; d++)
                if (p->rows[r].body[x] >= 0 && p->rows[r].c[x][d] != 0)
                    ind[++k] = p->rows[r].body[x] * nd + d + 1, val[k] = p->rows[r].c[x][d];
        if (r >= K) ind[++k] = nv + nrows + (r - K) / D + 1, val[k] = 1.0;
        glp_set_mat_row(P, nv + r + 1, k, ind, val);
    }
    for (int f = 0; f < Kf; f++) {
        int row = nv + nrows + f + 1;
        glp_set_col_bnds(P, row, GLP_LO, 0, 0);
        glp_set_row_bnds(P, row, GLP_LO, 0, 0);
        int ind[16], k = 0;
        double val[16];
        ind[++k] = nv + p->contact_of_fric[f] + 1, val[k] = p->mu[f];
        for (int d = 0; d < D; d++) ind[++k] = nv + K + f * D + d + 1, val[k] = -1.0;
        glp_set_mat_row(P, row, k, ind, val);
    }
    return P;
}

static int brute_solve(Brute *b) {
    glp_smcp parm;
    glp_init_smcp(&parm);
    parm.msg_lev = GLP_MSG_OFF;
    b->lps++;
    if (glp_simplex(b->P, &parm) != 0) return -1;
    return glp_get_status(b->P);
}

/* Fix a pair's column (z = 0) or row (w at its lower bound) or free it again. */
static void set_fx(glp_prob *P, int col, bool row, bool fix) {
    if (row) {
        double lo = glp_get_row_lb(P, col);
        glp_set_row_bnds(P, col, fix ? GLP_FX : GLP_LO, lo, lo);
    } else {
        glp_set_col_bnds(P, col, fix ? GLP_FX : GLP_LO, 0, 0);
    }
}

/* Is the node's LP (pairs fixed so far) feasible? */
static bool brute_feasible(Brute *b) {
    glp_set_obj_dir(b->P, GLP_MAX);
    for (int j = 0; j < b->nv; j++) glp_set_obj_coef(b->P, j + 1, 0.0);
    return brute_solve(b) != GLP_NOFEAS;
}

/* Every pair fixed: a face of the solution set; its extreme motions, component by component. */
static void brute_leaf(Brute *b) {
    const cnMech *m = b->p->m;
    for (int j = 0; j < b->nv && !b->moves; j++) {
        int body = j / m->nd, k = j % m->nd;
        double scale = k < m->dim ? 1.0 : m->radius[body];
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            glp_set_obj_coef(b->P, j + 1, sgn);
            int st = brute_solve(b);
            double v = st == GLP_UNBND ? INFINITY : st == GLP_OPT ? glp_get_obj_val(b->P) : 0;
            if (v * scale > 10 * b->tol) b->moves = 1;
            else if (v * scale > 0.1 * b->tol / 2) b->gray = 1;
        }
        glp_set_obj_coef(b->P, j + 1, 0.0);
    }
}

/* Pairs 0..i-1 fixed: pair i both ways (its column, then its row), pruning empty patterns. */
static void brute_pairs(Brute *b, int i) {
    if (b->moves || !brute_feasible(b)) return;
    if (i == b->n) {
        brute_leaf(b);
        return;
    }
    int col = b->nv + i + 1;
    for (int side = 0; side < 2; side++) {
        set_fx(b->P, col, side == 1, true);
        brute_pairs(b, i + 1);
        set_fx(b->P, col, side == 1, false);
    }
}

/* Each contact's pairs in one of four modes, whose union is exactly the contact's complementary
 * points (by cases, with a_t the tangential sliding including any nominal sliding: p_n = 0
 * forces the friction to zero, and the sliding speed's pair holds whatever it is; p_n > 0
 * closes the contact, and then either lambda = 0, so that both friction rows w = +-a_t >= 0
 * make a_t = 0, or lambda > 0, the friction is at mu p_n and exactly one of w = +-a_t + lambda
 * is zero, the other direction's force with it):
 *   open     p_n = 0
 *   stick    w_n = 0, lambda = 0
 *   slide +t w_n = 0, zeta = 0, p_{+t} = 0, w_{-t} = 0
 *   slide -t w_n = 0, zeta = 0, p_{-t} = 0, w_{+t} = 0
 * Contacts 0..c-1 set: set contact c each way, pruning patterns with no solution. */
static void brute_modes(Brute *b, int c) {
    if (b->moves || !brute_feasible(b)) return;
    const cnMotionProblem *p = b->p;
    if (c == p->K) {
        brute_leaf(b);
        return;
    }
    int nv = b->nv, n_col = nv + c + 1, lam = nv + b->nrows + c + 1;
    int tp = nv + p->K + c * p->D + 1, tm = tp + 1;
    for (int mode = 0; mode < 4 && !b->moves; mode++) {
        bool on = true;
        for (int pass = 0; pass < 2; pass++, on = false) {
            switch (mode) {
            case 0: set_fx(b->P, n_col, false, on); break;
            case 1: set_fx(b->P, n_col, true, on), set_fx(b->P, lam, false, on); break;
            default:
                set_fx(b->P, n_col, true, on), set_fx(b->P, lam, true, on);
                set_fx(b->P, mode == 2 ? tp : tm, false, on);
                set_fx(b->P, mode == 2 ? tm : tp, true, on);
            }
            if (on) brute_modes(b, c + 1);
        }
    }
}

/* The brute force's state for problem p, its LP built. */
static Brute brute_new(const cnMotionProblem *p) {
    Brute b;
    memset(&b, 0, sizeof b);
    b.p = p;
    b.nv = p->m->nb * p->m->nd;
    b.nrows = p->K + p->Kf * p->D;
    b.n = b.nrows + p->Kf;
    b.tol = CN_DEFAULT_MOTION_TOL * p->m->g;
    b.P = brute_lp(p, b.nv, b.nrows);
    return b;
}

static double urand(unsigned *seed) {
    *seed = *seed * 1103515245u + 12345u;
    return (double)((*seed >> 8) & 0xffffff) / (double)0x1000000;
}

/* A contact on a face of a box (x0..x1, y0..y1): face 0 bottom, 1 right, 2 top, 3 left; at
 * parameter s along it; normal into the box. */
static void face_point(const double box[4], int face, double s, double p[3], double n[3]) {
    double x0 = box[0], y0 = box[1], x1 = box[2], y1 = box[3];
    p[2] = n[2] = 0;
    switch (face) {
    case 0: p[0] = x0 + s * (x1 - x0), p[1] = y0, n[0] = 0, n[1] = 1; break;
    case 1: p[0] = x1, p[1] = y0 + s * (y1 - y0), n[0] = -1, n[1] = 0; break;
    case 2: p[0] = x0 + s * (x1 - x0), p[1] = y1, n[0] = 0, n[1] = -1; break;
    default: p[0] = x0, p[1] = y0 + s * (y1 - y0), n[0] = 1, n[1] = 0; break;
    }
}

static void test_search_vs_brute_force(void) {
    glp_term_hook(quiet, NULL);
    const double boxA[4] = {0, 0, 2, 1}, boxB[4] = {0.5, 1, 1.5, 1.6};
    int trials = 0, agree = 0, gray = 0, found = 0, grouped = 0, undecided = 0, nsliding = 0, npairs = 0;
    int napart = 0;
    long brute_lps = 0, search_lps = 0;
    unsigned seed = 12345;
    int ntr = RUNNING_ON_VALGRIND ? 99 : 300; /* under memcheck a third: memory, not coverage */
    for (int t = 0; t < ntr; t++) {
        bool two = t % 3 == 2, apart = two && t / 3 % 2 == 1;
        double ang = (urand(&seed) - 0.5) * 1.4; /* gravity within 40 degrees of -y */
        char json[1024];
        scene_two_boxes_2d(json, sizeof json, ang, two);
        cnAssembly *a = load_ok(json);
        if (!a) return;
        cnMech m;
        cnDiag d;
        if (cn_mech_build(a, NULL, NULL, &m, &d) != CN_OK) {
            CHECK_MSG(0, "mech: %s", d.message);
            cn_assembly_free(a);
            return;
        }
        int F = cn_assembly_find_part(a, "F"), A = cn_assembly_find_part(a, "A");
        int B = two ? cn_assembly_find_part(a, "B") : -1;
        /* contacts: (part1, part2, point, normal from part1 into part2) */
        int K = 0, p1[MAXC], p2[MAXC];
        double pt[MAXC][3], nr[MAXC][3];
        double mu0 = 0.05 + 1.2 * urand(&seed);
        double mu[MAXC];
        int nfa = two ? 2 : 3 + (int)(urand(&seed) * 2); /* contacts of the frame on A */
        for (int c = 0; c < nfa && K < MAXC; c++) {
            int face = urand(&seed) < 0.5 ? 0 : (int)(urand(&seed) * 4);
            bool joint = urand(&seed) < 0.5 && K + 1 < MAXC && c + 1 < nfa;
            double s = joint ? 0 : urand(&seed);
            p1[K] = F, p2[K] = A;
            face_point(boxA, face, s, pt[K], nr[K]);
            K++;
            if (joint) { /* the face's other corner: a flat joint */
                p1[K] = F, p2[K] = A;
                face_point(boxA, face, 1, pt[K], nr[K]);
                K++, c++;
            }
        }
        if (two) {
            /* B on A's top (a flat joint, or one point), and maybe the frame at B's side; in
               half of them B rests on the frame instead, apart from A: two groups of bodies
               that no contact joins (searched one by one, search_split.c) */
            p1[K] = apart ? F : A, p2[K] = B;
            face_point(boxB, 0, urand(&seed) < 0.5 ? 0 : urand(&seed), pt[K], nr[K]);
            K++;
            p1[K] = apart ? F : A, p2[K] = B;
            face_point(boxB, 0, 1, pt[K], nr[K]);
            K++;
            if (urand(&seed) < 0.5) {
                p1[K] = F, p2[K] = B;
                face_point(boxB, urand(&seed) < 0.5 ? 1 : 3, urand(&seed), pt[K], nr[K]);
                K++;
            }
        }
        for (int c = 0; c < K; c++) mu[c] = urand(&seed) < 0.15 ? 0.05 + 1.2 * urand(&seed) : mu0;
        cnJRow rows[MAXC * (1 + D2)];
        int cof[MAXC];
        for (int c = 0; c < K; c++) {
            cn_mech_row(&m, p1[c], p2[c], pt[c], nr[c], &rows[c]);
            double tg[3] = {-nr[c][1], nr[c][0], 0}, tm[3] = {nr[c][1], -nr[c][0], 0};
            cn_mech_row(&m, p1[c], p2[c], pt[c], tg, &rows[K + c * D2]);
            cn_mech_row(&m, p1[c], p2[c], pt[c], tm, &rows[K + c * D2 + 1]);
            cof[c] = c;
        }
        /* in a third of the problems the frame slides under the blocks (at up to g, mostly
           sideways): nominal sliding along its contacts' friction rows */
        double nom[MAXC * D2];
        bool sliding = t % 3 == 1 || (apart && t / 6 % 2 == 0);
        double vf[2] = {(urand(&seed) - 0.5) * 9.81, (urand(&seed) - 0.5) * 2};
        for (int c = 0; c < K; c++) {
            double v = p1[c] == F ? -(vf[0] * -nr[c][1] + vf[1] * nr[c][0]) : 0;
            nom[c * D2] = v, nom[c * D2 + 1] = -v;
        }
        nsliding += sliding;
        cnMotionProblem prob = {&m, K, K, D2, rows, cof, mu, sliding ? nom : NULL,
                                CN_DEFAULT_MOTION_TOL, 1000000, false, 0, NULL, NULL, false, NULL, 0};
        Brute b = brute_new(&prob);
        brute_modes(&b, 0);
        if (K <= 3) { /* the independent enumeration, pair by pair, must say the same */
            Brute c = b;
            c.moves = c.gray = 0;
            brute_pairs(&c, 0);
            CHECK_MSG(c.moves == b.moves, "trial %d: pairs say %s, modes %s", t,
                      c.moves ? "moves" : "still", b.moves ? "moves" : "still");
            b.lps = c.lps;
            npairs++;
        }
        glp_delete_prob(b.P);
        brute_lps += b.lps;
        double force[MAXC * (1 + D2)], acc[12];
        cnMotionAnswer ans;
        cnMotionStats stats = {0};
        cnStatus st = cn_motion_search(&prob, &ans, force, acc, &stats, &d);
        search_lps += stats.nodes;
        for (int c = 0; c + 1 < K; c++)
            if (p1[c] == p1[c + 1] && p2[c] == p2[c + 1] && nr[c][0] == nr[c + 1][0] &&
                nr[c][1] == nr[c + 1][1] && mu[c] == mu[c + 1] &&
                (nr[c][0] != 0 ? pt[c][0] == pt[c + 1][0] : pt[c][1] == pt[c + 1][1]))
                grouped++;
        trials++;
        if (b.gray && !b.moves) {
            gray++;
        } else if (st != CN_OK || ans == CN_MOTION_UNDECIDED) {
            undecided++;
            CHECK_MSG(0, "trial %d: status %d, undecided (%s) after %ld LPs", t, (int)st,
                      cn_undecided_text(stats.why), stats.nodes);
        } else {
            bool moves = ans == CN_MOTION_FOUND;
            CHECK_MSG(moves == (b.moves == 1), "trial %d (%d contacts%s): search says %s, brute force %s",
                      t, K, two ? ", two blocks" : "", moves ? "moves" : "still",
                      b.moves ? "moves" : "still");
            if (moves == (b.moves == 1)) agree++, napart += apart;
            found += moves;
        }
        cn_mech_free(&m);
        cn_assembly_free(a);
    }
    printf("strong: search and brute force agree in %d of %d random contact problems (%d move, "
           "%d with the frame sliding, %d also enumerated pair by pair, %d at the threshold "
           "skipped, %d undecided, %d flat joints, %d of two blocks apart); %ld LPs against %ld\n",
           agree, trials, found, nsliding, npairs, gray, undecided, grouped, napart, search_lps,
           brute_lps);
    CHECK(found > 20 * ntr / 300 && agree - found > 20 * ntr / 300 && npairs > 50 * ntr / 300 &&
          napart > 30 * ntr / 300);
}

/* A fixed frame F far off and the boxes `parts` (JSON part objects after F's) under gravity
 * 9.81 turned ang from -z towards azimuth az, with its mechanics built in *m; NULL on failure
 * (reported). */
static cnAssembly *boxes_under_gravity(double ang, double az, const char *parts, cnMech *m) {
    char json[1024];
    snprintf(json, sizeof json,
             "{\"dimension\":3,\"gravity\":[%.17g,%.17g,%.17g],\"parts\":["
             "{\"name\":\"F\",\"fixed\":true,\"box\":{\"min\":[-9,-9,-9],\"max\":[-8,-8,-8]}},%s]}",
             9.81 * sin(ang) * cos(az), 9.81 * sin(ang) * sin(az), -9.81 * cos(ang), parts);
    cnAssembly *a = load_ok(json);
    if (!a) return NULL;
    cnDiag d;
    if (cn_mech_build(a, NULL, NULL, m, &d) != CN_OK) {
        CHECK_MSG(0, "mech: %s", d.message);
        cn_assembly_free(a);
        return NULL;
    }
    return a;
}

/* The same in 3-D, where the search branches on a contact's sliding modes as a whole (stick, or
 * friction along one pyramid edge or the face between two adjacent ones: D + 1 children). Brute
 * force enumerates every complementarity pattern, pair by pair, so it assumes no such split:
 * one box on a fixed frame, 1 to 3 contact points on its faces (mostly its bottom; in half the
 * problems three under it, around its centre of mass, under gravity within 23 degrees), 3 or 4
 * friction directions turned at random about each normal, gravity within 40 degrees of -z, the
 * frame sliding under the box in a third of the problems. */
static void test_search_vs_brute_force_3d(void) {
    glp_term_hook(quiet, NULL);
    int trials = 0, agree = 0, gray = 0, found = 0, nsliding = 0;
    long brute_lps = 0, search_lps = 0;
    unsigned seed = 777;
    /* 11 s of brute force (1.8 million LPs): under valgrind's memcheck a twelfth of it */
    int ntrials = RUNNING_ON_VALGRIND ? 12 : 150;
    for (int t = 0; t < ntrials; t++) {
        /* half the problems: a tripod of points under the box, around its centre of mass */
        bool tripod = t % 4 < 2;
        double ang = (urand(&seed) - 0.5) * (tripod ? 0.8 : 1.4), az = urand(&seed) * 2 * CN_PI;
        cnMech m;
        cnDiag d;
        cnAssembly *a = boxes_under_gravity(ang, az, "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[2,1,1]}}", &m);
        if (!a) return;
        int F = cn_assembly_find_part(a, "F"), A = cn_assembly_find_part(a, "A");
        int D = t % 2 && !(tripod && t % 8 >= 2) ? 4 : 3; /* 4 in a quarter of the tripods */
        int K = tripod ? 3 : 1 + (int)(urand(&seed) * (D == 3 ? 3 : 2));
        double mu0 = 0.05 + 1.2 * urand(&seed), mu[MAXC];
        cnJRow rows[MAXC * 5];
        int cof[MAXC];
        double nom[MAXC * 4];
        bool sliding = t % 3 == 1;
        double vf[3] = {(urand(&seed) - 0.5) * 9.81, (urand(&seed) - 0.5) * 9.81, (urand(&seed) - 0.5)};
        for (int c = 0; c < K; c++) {
            /* a point on a face of the box: axis k at its low (n = +e_k into the box) or high side */
            int k = urand(&seed) < 0.6 ? 2 : (int)(urand(&seed) * 3);
            bool low = k == 2 ? urand(&seed) < 0.85 : urand(&seed) < 0.5;
            double ext[3] = {2, 1, 1}, pt[3], nr[3] = {0, 0, 0};
            for (int x = 0; x < 3; x++) pt[x] = urand(&seed) < 0.3 ? (urand(&seed) < 0.5 ? 0 : ext[x])
                                                                  : urand(&seed) * ext[x];
            pt[k] = low ? 0 : ext[k];
            nr[k] = low ? 1 : -1;
            if (tripod) {
                static const double tri[3][3] = {{0, 0, 0}, {2, 0, 0}, {1, 1, 0}};
                k = 2;
                cn_copy3(pt, tri[c]);
                nr[0] = nr[1] = 0, nr[2] = 1;
            }
            cn_mech_row(&m, F, A, pt, nr, &rows[c]);
            double t1[3] = {0, 0, 0}, t2[3];
            t1[(k + 1) % 3] = 1;
            cn_cross3(nr, t1, t2);
            double off = urand(&seed) * 2 * CN_PI;
            for (int j = 0; j < D; j++) {
                double th = off + 2 * CN_PI * j / D, dir[3];
                for (int x = 0; x < 3; x++) dir[x] = cos(th) * t1[x] + sin(th) * t2[x];
                cn_mech_row(&m, F, A, pt, dir, &rows[K + c * D + j]);
                nom[c * D + j] = -cn_dot3(vf, dir);
            }
            cof[c] = c;
            mu[c] = urand(&seed) < 0.15 ? 0.05 + 1.2 * urand(&seed) : mu0;
        }
        nsliding += sliding;
        cnMotionProblem prob = {&m, K, K, D, rows, cof, mu, sliding ? nom : NULL,
                                CN_DEFAULT_MOTION_TOL, 1000000, false, 0, NULL, NULL, false, NULL, 0};
        Brute b = brute_new(&prob);
        brute_pairs(&b, 0);
        glp_delete_prob(b.P);
        brute_lps += b.lps;
        double force[MAXC * 5], acc[12];
        cnMotionAnswer ans;
        cnMotionStats stats = {0};
        cnStatus st = cn_motion_search(&prob, &ans, force, acc, &stats, &d);
        search_lps += stats.nodes;
        trials++;
        if (b.gray && !b.moves) {
            gray++;
        } else {
            CHECK_MSG(st == CN_OK && ans != CN_MOTION_UNDECIDED, "3-D trial %d: status %d, undecided (%s)",
                      t, (int)st, cn_undecided_text(stats.why));
            bool moves = ans == CN_MOTION_FOUND;
            CHECK_MSG(moves == (b.moves == 1), "3-D trial %d (%d contacts, D %d%s): search says %s, brute force %s",
                      t, K, D, sliding ? ", frame sliding" : "", moves ? "moves" : "still",
                      b.moves ? "moves" : "still");
            if (st == CN_OK && moves == (b.moves == 1)) agree++;
            found += moves;
        }
        cn_mech_free(&m);
        cn_assembly_free(a);
    }
    printf("strong 3-D: search and brute force agree in %d of %d random contact problems (%d move, "
           "%d with the frame sliding, %d at the threshold skipped); %ld LPs against %ld\n",
           agree, trials, found, nsliding, gray, search_lps, brute_lps);
    CHECK(found > ntrials / 8 && agree - found > ntrials / 8);
}

/* 3-D modes, contact by contact: open (p_n = 0), stuck (w_n = 0, lambda = 0), or sliding with
 * direction j a largest -d.u (w_n = 0, zeta = 0, w_j = 0, no friction but on j and j + 1), the
 * latter split on j + 1's pair (its force zero, or j + 1 a largest too): each pattern exactly a
 * set of solutions, so that no joint, energy bound or cut is assumed. Contacts 0..c-1 set; the
 * patterns with no solution pruned. */
static void brute_modes_3d(Brute *b, int c) {
    if (b->moves || !brute_feasible(b)) return;
    const cnMotionProblem *p = b->p;
    if (c == p->K) {
        brute_leaf(b);
        return;
    }
    int nv = b->nv, D = p->D, n_col = nv + c + 1, lam = nv + b->nrows + c + 1;
    int f0 = nv + p->K + c * D + 1;
    for (int mode = 0; mode < 2 + 2 * D && !b->moves; mode++) {
        bool on = true;
        for (int pass = 0; pass < 2; pass++, on = false) {
            if (mode == 0) {
                set_fx(b->P, n_col, false, on);
            } else if (mode == 1) {
                set_fx(b->P, n_col, true, on), set_fx(b->P, lam, false, on);
            } else {
                int j = (mode - 2) / 2, j1 = (j + 1) % D;
                set_fx(b->P, n_col, true, on), set_fx(b->P, lam, true, on);
                set_fx(b->P, f0 + j, true, on);
                set_fx(b->P, f0 + j1, (mode - 2) % 2 == 1, on);
                for (int d = 0; d < D; d++)
                    if (d != j && d != j1) set_fx(b->P, f0 + d, false, on);
            }
            if (on) brute_modes_3d(b, c + 1);
        }
    }
}

/* Joints (strong.c, joint patterns): the points of one face between two free bodies are
 * branched on together, one child per pattern of sliding modes their relative motion can give.
 * Against contact-by-contact modes: box B (1 x 0.6 x 0.5) on box A (2 x 1 x 1) on a fixed frame,
 * 2 or 3 points under A and 2 or 3 between A and B (two corners of an edge of the face and the
 * middle of the opposite edge, each anywhere on the face in one draw of 12), 3 or 4 friction directions turned
 * at random per point, gravity within 14 degrees of -z, mu from 0.05 to 1.25, often different
 * under A and B. */
static void test_joints_vs_brute_force_3d(void) {
    glp_term_hook(quiet, NULL);
    int trials = 0, agree = 0, gray = 0, found = 0, jointed = 0, bounded = 0, learned = 0;
    long plain_lps = 0;
    long brute_lps = 0, search_lps = 0;
    unsigned seed = 4242;
    int ntrials = RUNNING_ON_VALGRIND ? 3 : 30;
    for (int t = 0; t < ntrials; t++) {
        double ang = (urand(&seed) - 0.5) * 0.5, az = urand(&seed) * 2 * CN_PI;
        cnMech m;
        cnDiag d;
        cnAssembly *a = boxes_under_gravity(ang, az, "{\"name\":\"A\",\"box\":{\"min\":[0,0,0],\"max\":[2,1,1]}},"
                                            "{\"name\":\"B\",\"box\":{\"min\":[0.5,0.2,1],\"max\":[1.5,0.8,1.5]}}", &m);
        if (!a) return;
        int F = cn_assembly_find_part(a, "F"), A = cn_assembly_find_part(a, "A"),
            B = cn_assembly_find_part(a, "B");
        int D = t % 2 ? 4 : 3;
        int na = 3 - (urand(&seed) < 0.1), nbp = 3 - (urand(&seed) < 0.2);
        int K = na + nbp;
        double mua = 0.05 + 1.2 * urand(&seed), mub = urand(&seed) < 0.5 ? mua : 0.05 + 1.2 * urand(&seed);
        /* the points of a face: at its corners in turn (a third of the draws), else anywhere */
        int corner0 = (int)(urand(&seed) * 4);
        double mu[MAXC];
        cnJRow rows[MAXC * 5];
        int cof[MAXC];
        for (int c = 0; c < K; c++) {
            bool under = c < na;
            double lo[2] = {under ? 0 : 0.5, under ? 0 : 0.2}, hi[2] = {under ? 2 : 1.5, under ? 1 : 0.8};
            double pt[3], nr[3] = {0, 0, 1};
            /* two corners of an edge and the middle of the opposite edge (a tripod around the
               centre), or anywhere on the face */
            int i = under ? c : c - na, q = (corner0 + i) % 4;
            static const double cx[4] = {0, 1, 1, 0}, cy[4] = {0, 0, 1, 1};
            double u = cx[q], v = cy[q];
            if (i == 2) u = (cx[q] + cx[(q + 1) % 4]) / 2, v = (cy[q] + cy[(q + 1) % 4]) / 2;
            if (urand(&seed) < 0.08) u = urand(&seed), v = urand(&seed);
            pt[0] = lo[0] + u * (hi[0] - lo[0]), pt[1] = lo[1] + v * (hi[1] - lo[1]);
            pt[2] = under ? 0 : 1;
            cn_mech_row(&m, under ? F : A, under ? A : B, pt, nr, &rows[c]);
            double t1[3] = {1, 0, 0}, t2[3] = {0, 1, 0};
            double off = urand(&seed) * 2 * CN_PI;
            for (int j = 0; j < D; j++) {
                double th = off + 2 * CN_PI * j / D, dir[3];
                for (int x = 0; x < 3; x++) dir[x] = cos(th) * t1[x] + sin(th) * t2[x];
                cn_mech_row(&m, under ? F : A, under ? A : B, pt, dir, &rows[K + c * D + j]);
            }
            cof[c] = c;
            mu[c] = under ? mua : mub;
        }
        cnMotionProblem prob = {&m,   K,    K,     D, rows, cof, mu, NULL, CN_DEFAULT_MOTION_TOL,
                                1000000, false, 0, NULL, NULL, false, NULL, 0};
        Brute b = brute_new(&prob);
        brute_modes_3d(&b, 0);
        glp_delete_prob(b.P);
        brute_lps += b.lps;
        double force[MAXC * 5], acc[12];
        cnMotionAnswer ans;
        cnMotionStats stats = {0};
        cnStatus st = cn_motion_search(&prob, &ans, force, acc, &stats, &d);
        search_lps += stats.nodes;
        jointed += stats.joints > 0;
        trials++;
        {   /* the learned prunes are a second route to the same answer: without them, the
               same verdict */
            cnMotionAnswer plain;
            cnMotionStats ps = {0};
            double f0[MAXC * 5], a0[12];
            memset(&ps, 0, sizeof ps);
            prob.no_learning = true;
            cnStatus st0 = cn_motion_search(&prob, &plain, f0, a0, &ps, &d);
            prob.no_learning = false;
            CHECK_MSG(st0 == st && (plain == CN_MOTION_FOUND) == (ans == CN_MOTION_FOUND),
                      "joint trial %d: with learned prunes %d, without %d", t, (int)ans, (int)plain);
            learned += stats.learned > 0;
            plain_lps += ps.nodes;
        }
        if (b.gray && !b.moves) {
            gray++;
        } else {
            CHECK_MSG(st == CN_OK && ans != CN_MOTION_UNDECIDED, "joint trial %d: status %d, undecided (%s)",
                      t, (int)st, cn_undecided_text(stats.why));
            bool moves = ans == CN_MOTION_FOUND;
            CHECK_MSG(moves == (b.moves == 1), "joint trial %d (%d + %d points, D %d): search says %s, brute force %s",
                      t, na, nbp, D, moves ? "moves" : "still", b.moves ? "moves" : "still");
            if (moves != (b.moves == 1)) {
                prob.pointwise = true;
                cnMotionAnswer a2;
                cn_motion_search(&prob, &a2, force, acc, &stats, &d);
                fprintf(stderr, "  pointwise: %d; mua %g mub %g\n", (int)a2, mua, mub);
                for (int c = 0; c < K; c++) fprintf(stderr, "  row %d bodies %d %d\n", c, rows[c].body[0], rows[c].body[1]);
            }
            if (st == CN_OK && moves == (b.moves == 1)) agree++;
            found += moves;
            if (moves) {
                /* stopped early, the search bounds what it left open: the motion it finds with
                   its whole budget must be within that bound on gravity's power */
                double ma[12], kin = cn_mech_kinetic(&m, acc, ma);
                unsigned char open[2] = {0, 0};
                cnMotionStats early = {0};
                memset(&early, 0, sizeof early);
                early.open_bodies = open;
                prob.max_nodes = 3;
                double f2[MAXC * 5], a2[12];
                cnMotionAnswer ans2;
                if (cn_motion_search(&prob, &ans2, f2, a2, &early, &d) == CN_OK && ans2 == CN_MOTION_UNDECIDED &&
                    isfinite(early.open_power)) {
                    bounded++;
                    CHECK_MSG(kin <= early.open_power * (1 + 1e-6) + 1e-12, "joint trial %d: a motion of power "
                              "%g beyond the bound %g left open", t, kin, early.open_power);
                }
                prob.max_nodes = 1000000;
            }
        }
        cn_mech_free(&m);
        cn_assembly_free(a);
    }
    printf("strong joints: search and contact-by-contact modes agree in %d of %d two-box problems (%d "
           "move, %d with joints branched on, %d at the threshold skipped); %ld LPs against %ld; "
           "stopped after 3 LPs, %d bounded the motion found later; learned prunes in %d, %ld LPs "
           "without them\n",
           agree, trials, found, jointed, gray, search_lps, brute_lps, bounded, learned, plain_lps);
    if (!RUNNING_ON_VALGRIND) /* under memcheck three problems only: memory, not coverage */
        CHECK(found > ntrials / 8 && agree - found > ntrials / 8 && jointed > ntrials / 2 && bounded > 0);
}

/* The sparse QP's guess of its held contacts (qp_ipm.c, the last step's indicators): on the 3-D
 * vault of 6 x 10 voussoirs (the CLI case's file), whose faces' four points share their forces in
 * many ways, the polish runs and its guess needs no correction, and the motion verifies. Guessed
 * by the force above the slack alone, 541 contacts were held and 50 then pulled: a round of
 * corrections, one more factorisation; so this fails if the indicators stop being read. */
static void test_qp_guess(void) {
    char path[512];
    snprintf(path, sizeof path, "%s/tests/cases/vault6x10_frictionless_sparse.json", CAIRN_SOURCE_DIR);
    cnAssembly *a = NULL;
    cnDiag d;
    if (cn_assembly_load_file(path, &a, &d) != CN_OK) {
        CHECK_MSG(0, "vault: %s", d.message);
        return;
    }
    cnContactSet set = {0};
    cnMech m;
    bool have_m = false;
    cnJRow *rows = NULL;
    double *force = NULL, *acc = NULL;
    if (cn_contacts_find(a, NULL, &set, NULL, &d) != CN_OK || cn_mech_build(a, NULL, NULL, &m, &d) != CN_OK) {
        CHECK_MSG(0, "vault: %s", d.message);
        goto done;
    }
    have_m = true;
    int K = set.count;
    rows = calloc((size_t)K, sizeof *rows);
    force = calloc((size_t)K, sizeof *force);
    acc = calloc((size_t)(m.nb * m.nd), sizeof *acc);
    if (!rows || !force || !acc) goto done;
    for (int c = 0; c < K; c++) {
        const cnContact *ct = &set.items[c];
        cn_mech_row(&m, ct->body1, ct->body2, ct->point, ct->normal, &rows[c]);
    }
    bool solved = false;
    double residual = INFINITY;
    int moves = -2;
    CHECK(cn_motion_qp(&m, rows, K, 0, force, acc, NULL, &solved, &residual, &moves, &d) == CN_OK);
    CHECK_MSG(solved && residual <= 1e-9, "vault 6 x 10: the QP's answer does not verify (residual %g)", residual);
    /* 0: the polish ran (the interior point stalls on these faces) and moved nothing */
    CHECK_MSG(K > 500 && moves == 0,
              "vault 6 x 10 (%d contacts): the polish moved %d contacts of its guess (-1: no polish)", K, moves);
    int moving = 0;
    for (int b = 0; b < m.nb; b++) moving += cn_mech_moves(&m, b, acc, 1e-6);
    CHECK_MSG(moving > 0, "vault 6 x 10: nothing moves");
done:
    free(rows), free(force), free(acc);
    if (have_m) cn_mech_free(&m);
    cn_contacts_free(&set);
    cn_assembly_free(a);
}


/* The memo of decided searches (proof_memo.c) on a made-up problem (it reads numbers, not
 * mechanics): a proof is taken again for the same problem, moved by rounding (1e-14 of an
 * array's scale) but not by 1e-9; an undecided answer only for a budget no larger than the one
 * spent; a motion found is never kept; past 8 problems the oldest is forgotten. */
static void test_proof_memo(void) {
    enum { NB = 1, ND = 6, K = 2, KF = 2, DD = 4, NR = K + KF * DD };
    double minv[NB * ND * ND] = {0}, mass[NB] = {2}, inertia[9 * NB] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
    double fext[NB * ND] = {0, 0, -19.62}, a0[NB * ND] = {0, 0, -9.81}, radius[NB] = {0.9};
    for (int i = 0; i < ND; i++) minv[i * ND + i] = 0.5;
    cnMech m;
    memset(&m, 0, sizeof m);
    m.dim = 3, m.nd = ND, m.nb = NB, m.minv = minv, m.mass = mass, m.inertia = inertia;
    m.fext = fext, m.a0 = a0, m.radius = radius, m.g = 9.81, m.wref = 19.62;
    cnJRow rows[NR];
    memset(rows, 0, sizeof rows);
    for (int r = 0; r < NR; r++) {
        rows[r].body[0] = -1, rows[r].body[1] = 0;
        for (int d = 0; d < ND; d++) rows[r].c[1][d] = sin(1.0 + r * 7 + d), rows[r].u[1][d] = 0.5 * rows[r].c[1][d];
    }
    int cof[KF] = {0, 1};
    double mu[KF] = {0.5, 0.5};
    cnMotionProblem p = {&m, K, KF, DD, rows, cof, mu, NULL, 1e-6, 0, false, 0, NULL, NULL, false, NULL, 0};
    cnMotionStats st, got;
    memset(&st, 0, sizeof st);
    st.nodes = 321;
    cnProofMemo *memo = NULL;
    cnMotionAnswer ans = CN_MOTION_FOUND;
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_NONE, &st));
    memset(&got, 0, sizeof got);
    CHECK(cn_proof_memo_find(memo, &p, &ans, &got) && ans == CN_MOTION_NONE && got.nodes == 321);
    /* rounding of a moment arm: the same problem; a real change: another */
    cnJRow keep = rows[5];
    rows[5].c[1][4] += 1e-14;
    CHECK(cn_proof_memo_find(memo, &p, &ans, &got) && ans == CN_MOTION_NONE);
    rows[5].c[1][4] = keep.c[1][4] + 1e-9;
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    rows[5] = keep;
    rows[3].body[0] = 0; /* another body: never the same */
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    rows[3].body[0] = -1;
    CHECK(cn_proof_memo_find(memo, &p, &ans, &got));
    mu[1] = 0.5 + 1e-6;
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    mu[1] = 0.5;
    p.motion_tol = 1e-6 * (1 + 1e-15); /* compared exactly */
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    p.motion_tol = 1e-6;
    /* undecided at a budget of 500: the same below it, searched again above it */
    double g2[NB * ND] = {0, 0.1, -9.81};
    m.a0 = g2;
    st.budget = 500, st.default_budget = 2000;
    st.why = CN_UNDECIDED_MEMORY; /* not the budget: not kept */
    CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_UNDECIDED, &st));
    p.max_nodes = 400;
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    p.max_nodes = 0;
    st.why = CN_UNDECIDED_BUDGET;
    CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_UNDECIDED, &st));
    p.max_nodes = 400;
    CHECK(cn_proof_memo_find(memo, &p, &ans, &got) && ans == CN_MOTION_UNDECIDED);
    p.max_nodes = 600;
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    p.max_nodes = 0; /* the default, 2,000 for this problem */
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    st.budget = 2000;
    CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_UNDECIDED, &st));
    CHECK(cn_proof_memo_find(memo, &p, &ans, &got) && ans == CN_MOTION_UNDECIDED);
    /* then proved: the proof replaces the undecided answer */
    CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_NONE, &st));
    CHECK(cn_proof_memo_find(memo, &p, &ans, &got) && ans == CN_MOTION_NONE);
    /* a large coefficient elsewhere does not hide a change of a small one (each number has
       the scale of its own block) */
    mu[0] = 1e7;
    CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_NONE, &st));
    mu[1] = 0.5 * (1 + 1e-9);
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    mu[1] = 0.5, mu[0] = 0.5;
    p.max_nodes = 600;
    /* a motion found is not kept */
    double g3[NB * ND] = {0, 0.2, -9.81};
    m.a0 = g3;
    CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_FOUND, &st));
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    st.budget = 0;
    /* eight more problems: the first one is forgotten, the last eight kept */
    double gk[8][NB * ND];
    for (int k = 0; k < 8; k++) {
        memcpy(gk[k], a0, sizeof a0);
        gk[k][0] = 0.01 * (k + 1);
        m.a0 = gk[k];
        CHECK(cn_proof_memo_keep(&memo, &p, CN_MOTION_NONE, &st));
    }
    m.a0 = a0;
    p.max_nodes = 0;
    CHECK(!cn_proof_memo_find(memo, &p, &ans, &got));
    for (int k = 0; k < 8; k++) {
        m.a0 = gk[k];
        CHECK_MSG(cn_proof_memo_find(memo, &p, &ans, &got) && ans == CN_MOTION_NONE, "entry %d", k);
    }
    cn_proof_memo_free(memo);
}

/* A motion within the rounding of its solution is no motion (cn_motion_verify): a flush-ended
 * running-bond wall of 410 bricks under 1e-8 g sideways, checked at a margin's motion threshold
 * (1e-9). Lemke's solution of its LCP (9,360 rows) has violations near 1e-8 and moves every
 * brick by about 6e-8 g; that passed for a motion (not guaranteed) though no brick can slide
 * under such a load (friction 0.6) nor tip (half a brick wide for each brick high at least). */
static void test_rounding_is_no_motion(void) {
    if (RUNNING_ON_VALGRIND) return; /* the LCP's size is the point: seconds under memcheck */
    int rows = 20, cols = 20;
    size_t cap = 512 + (size_t)rows * (size_t)(cols + 1) * 128, len = 0;
    char *s = malloc(cap);
    len += (size_t)snprintf(s + len, cap - len,
                            "{\"dimension\": 2, \"friction\": 0.6, \"gravity\": [9.81e-8, -9.81], \"parts\": ["
                            "{\"name\": \"ground\", \"fixed\": true, \"polygon\": [[-2,-1],[%d,-1],[%d,0],[-2,0]]}",
                            2 * cols + 3, 2 * cols + 3);
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols + r % 2; c++) {
            int x0 = r % 2 ? (c == 0 ? 0 : 2 * c - 1) : 2 * c, x1 = r % 2 ? (c == cols ? 2 * cols : 2 * c + 1) : 2 * c + 2;
            len += (size_t)snprintf(s + len, cap - len,
                                    ", {\"name\": \"r%dc%d\", \"polygon\": [[%d,%d],[%d,%d],[%d,%d],[%d,%d]]}", r, c,
                                    x0, r, x1, r, x1, r + 1, x0, r + 1);
        }
    snprintf(s + len, cap - len, "]}");
    cnAssembly *a = load_ok(s);
    free(s);
    if (!a) return;
    cnCheckOptions o = cn_check_options_default();
    o.motion_tol = 1e-9;
    cnCheckResult r;
    cnDiag d;
    memset(&r, 0, sizeof r);
    CHECK_MSG(cn_check(a, &o, &r, &d) == CN_OK, "%s", d.message);
    CHECK_MSG(r.verdict == CN_VERDICT_STABLE || r.verdict == CN_VERDICT_UNDECIDED,
              "a wall under 1e-8 g sideways: verdict %d, %d parts moving", r.verdict, r.nmoving);
    printf("strong: rounding is no motion: a 410-brick wall under 1e-8 g at threshold 1e-9: verdict %d\n",
           r.verdict);
    cn_check_result_free(&r);
    cn_assembly_free(a);
}

void test_strong(void) {
    test_rounding_is_no_motion();
    test_proof_memo();
    test_search_vs_brute_force();
    test_search_vs_brute_force_3d();
    test_joints_vs_brute_force_3d();
    test_qp_guess();
}
