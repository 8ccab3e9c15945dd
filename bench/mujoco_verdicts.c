/* Stability verdicts against a physics engine that simulates and watches (MuJoCo, the way
 * simulation-based planners decide): each assembly is checked by cairn (cn_check, the exact
 * LCP/LP verdict) and simulated by MuJoCo for SECONDS of simulated time from rest; MuJoCo's
 * verdict is "unstable" when some free part's centre moves more than MOVE_FRACTION of its size
 * or it turns by more than TURN_DEGREES. Prints one Markdown row per assembly: both verdicts,
 * whether they agree, cairn's time per verdict (median of repeated checks, model loaded), MuJoCo's
 * simulation time (model compiled; the compile time apart) and the ratio.
 *
 * Translation: every part is a MuJoCo body; a fixed part's pieces are world geoms. Pieces that
 * are boxes (rectangles in 2-D, extruded by a slab of the part's size) become box geoms, whose
 * collider gives a full contact patch; any other piece becomes a mesh geom (its convex hull), on
 * which MuJoCo 2.2 puts one contact point per pair, which cannot hold a face resting on a face:
 * such rows are marked "mesh" and left out of the agreement count. 2-D parts move in their plane
 * (two slides and a hinge). Masses are cairn's. Frictionless assemblies use condim 1 (normal
 * force only), with friction condim 3 and the assembly's coefficient (per-pair coefficients
 * through <contact><pair>).
 *   usage: mujoco_verdicts [--seconds T] [--keep DIR] [~]FILE.json ...      (make bench)
 *          mujoco_verdicts --scale [--seconds T] FILE.json
 * --scale (the scale table of make bench) simulates one file without checking it and prints
 * "verdict|simulation seconds|compile seconds" (or "error|message|"): cairn's time on the same
 * file is taken by the table itself, from the command line.
 * A file named with a leading ~ is within a few percent of a tipping threshold: reported, but
 * not counted in the agreement.
 * --keep writes each MuJoCo model to DIR/NAME.xml. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include <mujoco/mujoco.h>

#include "bench.h"
#include "cairn/cairn.h"

#define MOVE_FRACTION 0.02
#define TURN_DEGREES 2.0
#define TIMESTEP 0.001
/* MuJoCo 2.2's box-box collider puts spurious contacts at corners where two boxes have coplanar
 * side faces (a plank on a narrower block, both extruded to the same slab, gets one at its free
 * end and is thrown). So no two parts share a side plane: part i's boxes are shrunk by
 * BOX_SHRINK (1 + i mod 5) of their size (and start a hair apart, then settle), and in 2-D its
 * slab is 1 - SLAB_STEP (i mod 4) of the full one. A turned box (its axes not the coordinate
 * axes) keeps its size: the collider loses the edge of a turned box resting inside another box's
 * face once the turned box is the narrower (a domino leaning on a block, shrunk, falls). */
#define BOX_SHRINK 1e-3
#define SLAB_STEP 0.1


/* Is the piece a box? Fills its centre, half sizes and frame (rows: axes). */
static bool piece_box(const cnPiece *p, int dim, double slab, double shrink, double c[3],
                      double h[3], double R[3][3]) {
    double ax[3][3];
    if (dim == 2) {
        if (p->nverts != 4) return false;
        double e[2][3];
        for (int k = 0; k < 2; k++)
            for (int d = 0; d < 3; d++) e[k][d] = p->verts[k + 1][d] - p->verts[k][d];
        double l0 = hypot(e[0][0], e[0][1]), l1 = hypot(e[1][0], e[1][1]);
        if (l0 <= 0 || l1 <= 0 || fabs(e[0][0] * e[1][0] + e[0][1] * e[1][1]) > 1e-9 * l0 * l1)
            return false;
        double ax0[3] = {e[0][0] / l0, e[0][1] / l0, 0}, ax1[3] = {-ax0[1], ax0[0], 0};
        memcpy(ax[0], ax0, sizeof ax0);
        memcpy(ax[1], ax1, sizeof ax1);
        ax[2][0] = ax[2][1] = 0, ax[2][2] = 1;
    } else {
        if (p->nverts != 8 || p->nfaces != 6) return false;
        memcpy(ax[0], p->faces[0].normal, sizeof ax[0]);
        int k = 1;
        while (k < 6 && fabs(ax[0][0] * p->faces[k].normal[0] + ax[0][1] * p->faces[k].normal[1] +
                             ax[0][2] * p->faces[k].normal[2]) > 1e-9)
            k++;
        if (k == 6) return false;
        memcpy(ax[1], p->faces[k].normal, sizeof ax[1]);
        ax[2][0] = ax[0][1] * ax[1][2] - ax[0][2] * ax[1][1];
        ax[2][1] = ax[0][2] * ax[1][0] - ax[0][0] * ax[1][2];
        ax[2][2] = ax[0][0] * ax[1][1] - ax[0][1] * ax[1][0];
    }
    for (int a = 0; a < 3; a++) /* a turned box is not shrunk */
        if (fabs(ax[a][0]) + fabs(ax[a][1]) + fabs(ax[a][2]) - 1 > 1e-12) shrink = 0;
    for (int a = 0; a < 3; a++) {
        if (dim == 2 && a == 2) {
            c[2] = 0, h[2] = slab / 2;
            continue;
        }
        double lo = INFINITY, hi = -INFINITY;
        for (int i = 0; i < p->nverts; i++) {
            double s = ax[a][0] * p->verts[i][0] + ax[a][1] * p->verts[i][1] + ax[a][2] * p->verts[i][2];
            lo = fmin(lo, s), hi = fmax(hi, s);
        }
        /* every vertex on one of the two faces */
        for (int i = 0; i < p->nverts; i++) {
            double s = ax[a][0] * p->verts[i][0] + ax[a][1] * p->verts[i][1] + ax[a][2] * p->verts[i][2];
            if (fmin(s - lo, hi - s) > 1e-9 * (hi - lo)) return false;
        }
        h[a] = (hi - lo) / 2 * (1 - shrink);
        c[a] = (hi + lo) / 2; /* along axis a */
    }
    double cw[3] = {0, 0, 0};
    for (int a = 0; a < 3; a++)
        for (int d = 0; d < 3; d++) cw[d] += c[a] * ax[a][d];
    memcpy(c, cw, sizeof cw);
    memcpy(R, ax, sizeof ax);
    return true;
}

/* Rotation matrix (rows: the frame's axes in world coordinates) to MuJoCo's quaternion. */
static void mat_quat(double R[3][3], double q[4]) {
    /* the frame's axes are the columns of the body-to-world rotation */
    double m[3][3];
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) m[i][j] = R[j][i];
    double tr = m[0][0] + m[1][1] + m[2][2];
    if (tr > 0) {
        double s = sqrt(tr + 1) * 2;
        q[0] = s / 4, q[1] = (m[2][1] - m[1][2]) / s, q[2] = (m[0][2] - m[2][0]) / s,
        q[3] = (m[1][0] - m[0][1]) / s;
    } else if (m[0][0] > m[1][1] && m[0][0] > m[2][2]) {
        double s = sqrt(1 + m[0][0] - m[1][1] - m[2][2]) * 2;
        q[0] = (m[2][1] - m[1][2]) / s, q[1] = s / 4, q[2] = (m[0][1] + m[1][0]) / s,
        q[3] = (m[0][2] + m[2][0]) / s;
    } else if (m[1][1] > m[2][2]) {
        double s = sqrt(1 + m[1][1] - m[0][0] - m[2][2]) * 2;
        q[0] = (m[0][2] - m[2][0]) / s, q[1] = (m[0][1] + m[1][0]) / s, q[2] = s / 4,
        q[3] = (m[1][2] + m[2][1]) / s;
    } else {
        double s = sqrt(1 + m[2][2] - m[0][0] - m[1][1]) * 2;
        q[0] = (m[1][0] - m[0][1]) / s, q[1] = (m[0][2] + m[2][0]) / s,
        q[2] = (m[1][2] + m[2][1]) / s, q[3] = s / 4;
    }
}

static double part_diag(const cnPart *p, int dim) {
    double s = 0;
    for (int k = 0; k < dim; k++) s += (p->hi[k] - p->lo[k]) * (p->hi[k] - p->lo[k]);
    return sqrt(s);
}

/* Write the MJCF model; returns whether every piece is a box. */
static bool write_mjcf(FILE *f, const cnAssembly *a) {
    double full = a->length_scale / 4; /* 2-D: the extrusion */
    bool boxes = true;
    bool fric = a->friction > 0 || a->npairs > 0;
    int ngeom = 0;
    for (int i = 0; i < a->nreal; i++) ngeom += a->parts[i].npieces;
    fprintf(f, "<mujoco>\n<option timestep=\"%g\" gravity=\"%.17g %.17g %.17g\" jacobian=\"%s\"/>\n",
            TIMESTEP, a->gravity[0], a->gravity[1], a->gravity[2], ngeom > 60 ? "sparse" : "dense");
    fprintf(f, "<size nconmax=\"%d\" njmax=\"%d\"/>\n", 12 * ngeom + 100,
            (fric ? 48 : 12) * ngeom + 400);
    fprintf(f, "<default><geom condim=\"%d\" friction=\"%.17g 0.005 0.0001\"/></default>\n",
            fric ? 3 : 1, fric ? a->friction : 0.0);
    fprintf(f, "<asset>\n");
    for (int i = 0; i < a->nreal; i++)
        for (int k = 0; k < a->parts[i].npieces; k++) {
            const cnPiece *p = &a->parts[i].pieces[k];
            double c[3], h[3], R[3][3], slab = full * (1 - SLAB_STEP * (i % 4));
            if (piece_box(p, a->dim, slab, BOX_SHRINK * (1 + i % 5), c, h, R)) continue;
            boxes = false;
            fprintf(f, "<mesh name=\"m%d_%d\" vertex=\"", i, k);
            for (int v = 0; v < p->nverts; v++)
                for (int z = 0; z < (a->dim == 2 ? 2 : 1); z++)
                    fprintf(f, "%.17g %.17g %.17g ", p->verts[v][0], p->verts[v][1],
                            a->dim == 2 ? (z ? slab / 2 : -slab / 2) : p->verts[v][2]);
            fprintf(f, "\"/>\n");
        }
    fprintf(f, "</asset>\n<worldbody>\n");
    for (int i = 0; i < a->nreal; i++) {
        const cnPart *P = &a->parts[i];
        if (!P->fixed) {
            fprintf(f, "<body name=\"b%d\">\n", i);
            if (a->dim == 3) fprintf(f, "<freejoint/>\n");
            else
                fprintf(f, "<joint type=\"slide\" axis=\"1 0 0\" pos=\"%.17g %.17g 0\"/><joint "
                           "type=\"slide\" axis=\"0 1 0\"/><joint type=\"hinge\" axis=\"0 0 1\" "
                           "pos=\"%.17g %.17g 0\"/>\n",
                        P->com[0], P->com[1], P->com[0], P->com[1]);
        }
        /* cairn's mass over MuJoCo's volume of the part */
        double slab = full * (1 - SLAB_STEP * (i % 4)), shrink = BOX_SHRINK * (1 + i % 5);
        double vol = P->size * (a->dim == 2 ? slab : 1);
        double rho = P->fixed ? 1 : P->mass / vol;
        for (int k = 0; k < P->npieces; k++) {
            const cnPiece *p = &P->pieces[k];
            double c[3], h[3], R[3][3], q[4];
            if (piece_box(p, a->dim, slab, shrink, c, h, R)) {
                mat_quat(R, q);
                fprintf(f, "<geom name=\"g%d_%d\" type=\"box\" pos=\"%.17g %.17g %.17g\" "
                           "quat=\"%.17g %.17g %.17g %.17g\" size=\"%.17g %.17g %.17g\" "
                           "density=\"%.17g\"/>\n",
                        i, k, c[0], c[1], c[2], q[0], q[1], q[2], q[3], h[0], h[1], h[2], rho);
            } else {
                fprintf(f, "<geom name=\"g%d_%d\" type=\"mesh\" mesh=\"m%d_%d\" density=\"%.17g\"/>\n",
                        i, k, i, k, rho);
            }
        }
        if (!P->fixed) fprintf(f, "</body>\n");
    }
    fprintf(f, "</worldbody>\n");
    if (a->npairs > 0) {
        fprintf(f, "<contact>\n");
        for (int k = 0; k < a->npairs; k++) {
            const cnFrictionPair *fp = &a->pairs[k];
            for (int g1 = 0; g1 < a->parts[fp->a].npieces; g1++)
                for (int g2 = 0; g2 < a->parts[fp->b].npieces; g2++)
                    fprintf(f, "<pair geom1=\"g%d_%d\" geom2=\"g%d_%d\" condim=\"%d\" "
                               "friction=\"%.17g %.17g 0.005 0.0001 0.0001\"/>\n",
                            fp->a, g1, fp->b, g2, fp->mu > 0 ? 3 : 1, fp->mu, fp->mu);
        }
        fprintf(f, "</contact>\n");
    }
    fprintf(f, "</mujoco>\n");
    return boxes;
}

typedef struct {
    bool ok, stable, boxes;
    double compile_s, sim_s, move, turn_deg;
    char err[300];
} MjResult;

static const char *keep_dir;

static void mujoco_verdict(const cnAssembly *a, const char *name, double seconds, MjResult *out) {
    memset(out, 0, sizeof *out);
    char path[] = "/tmp/cairn_mjcf_XXXXXX";
    int fd = mkstemp(path);
    if (fd < 0) {
        snprintf(out->err, sizeof out->err, "cannot make a temporary file");
        return;
    }
    FILE *f = fdopen(fd, "w");
    out->boxes = write_mjcf(f, a);
    fclose(f);
    double t0 = bench_now();
    mjModel *m = mj_loadXML(path, NULL, out->err, sizeof out->err);
    if (keep_dir) { /* keep the model for a look */
        char dst[4096];
        snprintf(dst, sizeof dst, "%s/%s.xml", keep_dir, name);
        rename(path, dst);
    }
    unlink(path);
    if (!m) return;
    mjData *d = mj_makeData(m);
    mj_forward(m, d);
    out->compile_s = bench_now() - t0;
    int nb = m->nbody;
    double *x0 = malloc(sizeof(double) * 3 * (size_t)m->ngeom);
    memcpy(x0, d->geom_xpos, sizeof(double) * 3 * (size_t)m->ngeom);
    double *q0 = malloc(sizeof(double) * 4 * (size_t)nb);
    memcpy(q0, d->xquat, sizeof(double) * 4 * (size_t)nb);
    int steps = (int)ceil(seconds / m->opt.timestep);
    t0 = bench_now();
    for (int s = 0; s < steps; s++) mj_step(m, d);
    out->sim_s = bench_now() - t0;
    /* the largest move of a free part's geom (relative to the part's size) and turn */
    out->stable = true;
    for (int g = 0; g < m->ngeom; g++) {
        int b = m->geom_bodyid[g];
        if (b == 0) continue;
        int part = atoi(mj_id2name(m, mjOBJ_BODY, b) + 1);
        double dx = 0;
        for (int k = 0; k < 3; k++) dx += pow(d->geom_xpos[3 * g + k] - x0[3 * g + k], 2);
        double rel = sqrt(dx) / part_diag(&a->parts[part], a->dim);
        double dot = 0;
        for (int k = 0; k < 4; k++) dot += d->xquat[4 * b + k] * q0[4 * b + k];
        double turn = 2 * acos(fmin(1, fabs(dot))) * 180 / M_PI;
        out->move = fmax(out->move, rel);
        out->turn_deg = fmax(out->turn_deg, turn);
    }
    out->stable = out->move <= MOVE_FRACTION && out->turn_deg <= TURN_DEGREES;
    out->ok = true;
    free(x0);
    free(q0);
    mj_deleteData(d);
    mj_deleteModel(m);
}

/* --scale: MuJoCo alone on one file, one line for bench/run.sh's scale table. */
static int scale_main(const char *file, double seconds) {
    cnAssembly *a = NULL;
    cnDiag dg;
    cn_diag_clear(&dg);
    if (cn_assembly_load_file(file, &a, &dg) != CN_OK) {
        printf("error|%s|\n", dg.message);
        return 1;
    }
    MjResult mj;
    mujoco_verdict(a, "scale", seconds, &mj);
    if (mj.ok)
        printf("%s%s|%.3f|%.3f\n", mj.stable ? "stable" : "unstable", mj.boxes ? "" : " (mesh)",
               mj.sim_s, mj.compile_s);
    else
        printf("error|%s|\n", mj.err);
    cn_assembly_free(a);
    return mj.ok ? 0 : 1;
}

int main(int argc, char **argv) {
    double seconds = 2.0;
    if (argc >= 3 && !strcmp(argv[1], "--scale")) {
        int i = 2;
        if (i + 2 < argc && !strcmp(argv[i], "--seconds")) seconds = atof(argv[i + 1]), i += 2;
        return scale_main(argv[i], seconds);
    }
    int agree = 0, counted = 0, bad = 0;
    double ratio_min = INFINITY;
    printf("| assembly | parts | cairn | MuJoCo (move, turn) | agree | cairn ms | MuJoCo ms "
           "(compile) | MuJoCo / cairn |\n|---|---|---|---|---|---|---|---|\n");
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--seconds") && i + 1 < argc) {
            seconds = atof(argv[++i]);
            continue;
        }
        if (!strcmp(argv[i], "--keep") && i + 1 < argc) {
            keep_dir = argv[++i];
            continue;
        }
        /* "~FILE": within a few percent of a tipping threshold (reported, not counted) */
        bool near = argv[i][0] == '~';
        const char *file = argv[i] + near;
        cnAssembly *a = NULL;
        cnDiag dg;
        cn_diag_clear(&dg);
        if (cn_assembly_load_file(file, &a, &dg) != CN_OK) {
            fprintf(stderr, "mujoco_verdicts: %s: %s\n", argv[i], dg.message);
            bad = 1;
            continue;
        }
        const char *name = strrchr(file, '/');
        name = name ? name + 1 : file;
        if (a->nfixels > 0) {
            printf("| %s | %d | (fixels: not translated) | | | | | |\n", name, a->nreal);
            cn_assembly_free(a);
            continue;
        }
        /* cairn: median of repeated checks */
        enum { REPS = 21 };
        double t[REPS];
        bool stable = false, undecided = false, ok = true;
        for (int k = 0; k < REPS && ok; k++) {
            cnCheckOptions o = cn_check_options_default();
            cnCheckResult r;
            double t0 = bench_now();
            ok = cn_check(a, &o, &r, &dg) == CN_OK;
            t[k] = bench_now() - t0;
            stable = r.stable;
            undecided = r.verdict == CN_VERDICT_UNDECIDED;
            cn_check_result_free(&r);
        }
        MjResult mj;
        mujoco_verdict(a, name, seconds, &mj);
        if (!ok || !mj.ok) {
            printf("| %s | %d | %s | %s | | | | |\n", name, a->nreal, ok ? "" : dg.message,
                   mj.ok ? "" : mj.err);
            cn_assembly_free(a);
            continue;
        }
        qsort(t, REPS, sizeof t[0], bench_cmp_double);
        double tc = t[REPS / 2];
        bool same = stable == mj.stable;
        if (mj.boxes && !near && !undecided) counted++, agree += same;
        ratio_min = fmin(ratio_min, mj.sim_s / tc);
        /* %.3g: a ratio below 1 (cairn slower) must not print as 0 */
        printf("| %s%s | %d | %s | %s (%.3g, %.2g°)%s | %s | %.3g | %.4g (%.3g) | %.3g |\n", name,
               near ? " (near a threshold)" : "", a->nreal,
               undecided ? "undecided" : stable ? "stable" : "unstable",
               mj.stable ? "stable" : "unstable", mj.move, mj.turn_deg, mj.boxes ? "" : " (mesh)",
               undecided ? "-" : same ? "yes" : "**no**",
               1e3 * tc, 1e3 * mj.sim_s, 1e3 * mj.compile_s, mj.sim_s / tc);
        cn_assembly_free(a);
    }
    printf("\nMuJoCo %s, %.3g s simulated at dt = %g; unstable = a part moves more than %g of its "
           "size or turns more than %g°. Verdicts agree on %d of the %d assemblies made of boxes and not "
           "near a threshold; MuJoCo's simulation takes at least %.3g times cairn's check.\n",
           mj_versionString(), seconds, TIMESTEP, MOVE_FRACTION, TURN_DEGREES, agree, counted,
           ratio_min);
    return bad;
}
