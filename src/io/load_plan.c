/* The plan and the candidate moves of an assembly file, and its grippers. */
#include <errno.h>
#include <jansson.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "collide.h"
#include "io.h"
#include "load_ctx.h"
#include "pieces.h"

/* Straight up, against gravity, until the moved parts are clear of every remaining part whose
 * shadow along gravity meets theirs, plus 1% of their own height. */
static void default_lift(cnAssembly *a, cnPlanStep *st, const int *removed_by, int step) {
    double u[3], t1[3], t2[3];
    cn_copy3(u, a->gravity);
    cn_scale3(u, -1.0 / cn_norm3(u));
    if (a->dim == 2) t1[0] = u[1], t1[1] = -u[0], t1[2] = 0, t2[0] = t2[1] = t2[2] = 0;
    else cn_tangent_basis(u, t1, t2);
    double mlo[3] = {INFINITY, INFINITY, INFINITY}, mhi[3] = {-INFINITY, -INFINITY, -INFINITY};
    const double *axes[3] = {u, t1, t2};
    for (int i = 0; i < st->nmove; i++) {
        const cnPart *p = &a->parts[st->move[i]];
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nverts; v++)
                for (int k = 0; k < 3; k++) {
                    double d = cn_dot3(axes[k], p->pieces[s].verts[v]);
                    mlo[k] = fmin(mlo[k], d), mhi[k] = fmax(mhi[k], d);
                }
    }
    double need = 0, tol = a->contact_tol;
    for (int r = 0; r < a->nreal; r++) {
        if (removed_by[r] >= 0 && removed_by[r] <= step) continue;
        const cnPart *p = &a->parts[r];
        double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
        for (int s = 0; s < p->npieces; s++)
            for (int v = 0; v < p->pieces[s].nverts; v++)
                for (int k = 0; k < 3; k++) {
                    double d = cn_dot3(axes[k], p->pieces[s].verts[v]);
                    lo[k] = fmin(lo[k], d), hi[k] = fmax(hi[k], d);
                }
        int shadow = 1; /* touching side by side counts: clear means clear of it too */
        for (int k = 1; k < a->dim; k++)
            if (lo[k] > mhi[k] + tol || mlo[k] > hi[k] + tol) shadow = 0;
        if (shadow) need = fmax(need, hi[0] - mlo[0]);
    }
    double lift = need + 0.01 * (mhi[0] - mlo[0]);
    st->nseg = 1;
    st->seg = cn_calloc(1, sizeof(cnSegment));
    if (st->seg) for (int k = 0; k < 3; k++) st->seg[0].move[k] = lift * u[k];
}

/* The default distance between samples of a motion: half the size (largest extent) of the
 * smallest free part, so that sampling is the same whatever the unit of length. A part that
 * moves this far can neither pass over nor leave a support of any free part unseen between
 * two samples, and bisection then locates an onset to the solver's tolerance. */
static double default_sample_length(const cnAssembly *a) {
    double h = INFINITY;
    for (int i = 0; i < a->nreal; i++) {
        const cnPart *p = &a->parts[i];
        if (p->fixed) continue;
        double ext = 0;
        for (int k = 0; k < a->dim; k++) ext = fmax(ext, p->hi[k] - p->lo[k]);
        h = fmin(h, 0.5 * ext);
    }
    return isfinite(h) && h > 0 ? h : a->length_scale;
}

/* The simulation's dt and speed (*dt_given: dt was in the file, else the default sample
 * length at that speed). */
static cnStatus load_simulation(Ctx *c, const json_t *root, cnAssembly *a, bool *dt_given) {
    json_t *sim = json_object_get(root, "simulation");
    *dt_given = false;
    a->sim_dt = 1.0;
    a->sim_speed = 1.0;
    if (sim) {
        if (!json_is_object(sim))
            return cn_ld_fail(c, "simulation", "expected {\"dt\": number, \"speed\": number}, found %s", cn_ld_type_name(sim));
        static const char *const keys[] = {"dt", "speed", NULL};
        cnStatus s = cn_ld_check_keys(c, sim, "simulation", keys);
        if (s) return s;
        json_t *e = json_object_get(sim, "dt");
        if (e && (s = cn_ld_get_positive(c, e, "simulation.dt", &a->sim_dt))) return s;
        *dt_given = e != NULL;
        e = json_object_get(sim, "speed");
        if (e && (s = cn_ld_get_positive(c, e, "simulation.speed", &a->sim_speed))) return s;
    }
    if (!*dt_given) a->sim_dt = default_sample_length(a) / a->sim_speed;
    return CN_OK;
}

/* Step st's path (e, at `path`.path): its segments, none of zero length or too long for the
 * parts' digits, its turns checked. */
static cnStatus load_step_path(Ctx *c, const json_t *e, const char *path, cnAssembly *a, cnPlanStep *st) {
    char p[PATH_MAX_LEN];
    snprintf(p, sizeof p, "%s.path", path);
    if (!json_is_array(e) || json_array_size(e) == 0)
        return cn_ld_fail(c, p, "expected a non-empty array of displacements, e.g. [[-12, 0], [0, 6]]");
    cnSegment *pts;
    int np;
    cnStatus s = cn_ld_get_path(c, e, p, a->dim, &pts, &np);
    if (s) return s;
    st->seg = pts;
    st->nseg = np;
    st->path_given = true;
    for (int i = 0; i < np && !s; i++) {
        const double *mv = pts[i].move; /* hypot: 1e200 is not inf */
        double len = pts[i].kind == CN_SEGMENT_MOVE ? hypot(hypot(mv[0], mv[1]), mv[2]) : 1;
        snprintf(p, sizeof p, "%s.path[%d]", path, i);
        if (!(len > CN_TOL_LENGTH_ZERO * a->length_scale))
            s = cn_ld_fail(c, p, "a displacement of zero length; remove it");
        /* where the parts would end, double coordinates keep too few digits for contacts
           of their size (as for a part far from the origin) */
        else if (!(len <= CN_MAX_FAR_RATIO * a->length_scale))
            s = cn_ld_fail(c, p, "a displacement of %.3g, more than %g times the parts' size (%.3g): "
                           "shorten it", len, CN_MAX_FAR_RATIO, a->length_scale);
    }
    if (s) return s;
    snprintf(p, sizeof p, "%s.path", path);
    return cn_ld_check_turns(c, a, p, st->move, st->nmove, st->seg, st->nseg);
}

/* Plan step k (its move, grip, support and path), its parts marked in removed_by. */
static cnStatus load_step(Ctx *c, const json_t *plan, int k, cnAssembly *a, int *removed_by) {
    cnPlanStep *st = &a->plan[k];
    char path[PATH_MAX_LEN], p[PATH_MAX_LEN];
    cnStatus s;
    const json_t *v = json_array_get(plan, (size_t)k);
    snprintf(path, sizeof path, "plan[%d]", k);
    if (!json_is_object(v))
        return cn_ld_fail(c, path, "expected a step {\"move\": ..., \"path\": ...}, found %s", cn_ld_type_name(v));
    static const char *const keys[] = {"move", "grip", "path", "support", "gripper", NULL};
    if ((s = cn_ld_check_keys(c, v, path, keys))) return s;
    json_t *e = json_object_get(v, "move");
    snprintf(p, sizeof p, "%s.move", path);
    if (!e) return cn_ld_fail(c, p, "missing; name the part or parts that leave");
    if ((s = cn_ld_get_part_list(c, e, p, a, removed_by, k, NULL, 0, &st->move, &st->nmove))) return s;
    e = json_object_get(v, "grip");
    snprintf(p, sizeof p, "%s.grip", path);
    if (e) {
        if ((s = cn_ld_get_part_list(c, e, p, a, removed_by, k, st->move, st->nmove, &st->grip, &st->ngrip))) return s;
    } else {
        st->grip = cn_malloc(sizeof(int) * (size_t)st->nmove);
        if (!st->grip) return cn_diag_set(c->diag, CN_ERR_MEMORY, p, "out of memory");
        memcpy(st->grip, st->move, sizeof(int) * (size_t)st->nmove);
        st->ngrip = st->nmove;
    }
    for (int i = 0; i < st->nmove; i++) removed_by[st->move[i]] = k;
    e = json_object_get(v, "support");
    snprintf(p, sizeof p, "%s.support", path);
    if (e) {
        int sup;
        if ((s = cn_ld_get_support(c, e, p, &sup))) return s;
        st->support = (cnSupport)sup;
    }
    e = json_object_get(v, "path");
    return e ? load_step_path(c, e, path, a, st) : CN_OK;
}

/* A bound on the samples of a step, so that a tiny dt cannot make a run that never ends. */
static cnStatus check_samples(Ctx *c, const cnAssembly *a) {
    cnStatus s = CN_OK;
    for (int k = 0; !s && k < a->nsteps; k++) {
        const cnPlanStep *st = &a->plan[k];
        double L = cn_path_length(a, st->move, st->nmove, st->seg, st->nseg, NULL);
        double n = L / (a->sim_speed * a->sim_dt);
        if (n > CN_MAX_SAMPLES)
            s = cn_ld_fail(c, "simulation.dt",
                           "plan[%d] would take %.3g samples (path length %.6g, speed %g, dt %g); at "
                           "most %d are allowed: raise dt or speed",
                           k, n, L, a->sim_speed, a->sim_dt, CN_MAX_SAMPLES);
    }
    return s;
}

/* The gripper bodies of the steps that have one: extra parts, after the assembly's own. */
static cnStatus load_grippers(Ctx *c, const json_t *plan, cnAssembly *a) {
    char p[PATH_MAX_LEN];
    cnStatus s;
    int ngrippers = 0;
    for (int k = 0; k < a->nsteps; k++) ngrippers += json_object_get(json_array_get(plan, (size_t)k), "gripper") != NULL;
    if (ngrippers == 0) return CN_OK;
    cnPart *np = cn_realloc(a->parts, sizeof(cnPart) * (size_t)(a->nparts + ngrippers));
    if (!np) return cn_diag_set(c->diag, CN_ERR_MEMORY, "plan", "out of memory");
    a->parts = np;
    for (int k = 0; k < a->nsteps; k++) {
        const json_t *g = json_object_get(json_array_get(plan, (size_t)k), "gripper");
        if (!g) continue;
        snprintf(p, sizeof p, "plan[%d].gripper", k);
        if (!json_is_object(g)) return cn_ld_fail(c, p, "expected a shape object, e.g. {\"polygon\": [...]}, found %s", cn_ld_type_name(g));
        static const char *const keys2[] = {"polygon", "polygons", NULL};
        static const char *const keys3[] = {"box", "hull", "hulls", NULL};
        if ((s = cn_ld_check_keys(c, g, p, c->dim == 2 ? keys2 : keys3))) return s;
        int gi = a->nparts++;
        cnPart *part = &a->parts[gi];
        memset(part, 0, sizeof *part);
        char name[32];
        snprintf(name, sizeof name, "gripper%d", k + 1);
        if (cn_assembly_find_part(a, name) >= 0 && cn_assembly_find_part(a, name) != gi)
            return cn_ld_fail(c, p, "a part is already named '%s', the name of this step's gripper; rename the part", name);
        part->name = cn_strdup(name);
        part->fixed = true;
        part->gripper_step = k;
        if ((s = cn_ld_load_shape(c, g, p, part))) return s;
        cn_mass_part(part, c->dim, 1.0, 0);
        a->plan[k].gripper = gi;
    }
    return CN_OK;
}

cnStatus cn_ld_load_plan(Ctx *c, const json_t *root, cnAssembly *a) {
    bool dt_given;
    cnStatus s = load_simulation(c, root, a, &dt_given);
    if (s) return s;
    json_t *plan = json_object_get(root, "plan");
    if (!plan) return CN_OK;
    if (!json_is_array(plan)) return cn_ld_fail(c, "plan", "expected an array of steps, found %s", cn_ld_type_name(plan));
    int ns = (int)json_array_size(plan);
    a->plan = cn_calloc((size_t)ns + 1, sizeof(cnPlanStep));
    int *removed_by = cn_malloc(sizeof(int) * (size_t)(a->nreal + 1));
    if (!a->plan || !removed_by) {
        cn_free(removed_by);
        return cn_diag_set(c->diag, CN_ERR_MEMORY, "plan", "out of memory");
    }
    for (int i = 0; i < a->nreal; i++) removed_by[i] = -1;
    for (int k = 0; k < ns && !s; k++) {
        a->plan[k].gripper = -1;
        a->nsteps = k + 1;
        s = load_step(c, plan, k, a, removed_by);
    }
    if (!s)
        for (int k = 0; k < a->nsteps; k++)
            if (!a->plan[k].path_given) default_lift(a, &a->plan[k], removed_by, k);
    if (!s && dt_given) s = check_samples(c, a);
    cn_free(removed_by);
    if (s) return s;
    return load_grippers(c, plan, a);
}

/* "candidates": {"C": {"I": [[0, 6]], "II": {"path": [[-8, 0], [0, 6]], "support": "push"}}} */
cnStatus cn_ld_load_candidates(Ctx *c, const json_t *root, cnAssembly *a) {
    a->cand_support = CN_SUPPORT_HOLD;
    json_t *cs = json_object_get(root, "candidate_support");
    cnStatus s;
    if (cs) {
        int v;
        if ((s = cn_ld_get_support(c, cs, "candidate_support", &v))) return s;
        a->cand_support = (cnSupport)v;
    }
    json_t *cands = json_object_get(root, "candidates");
    if (!cands) return CN_OK;
    if (!json_is_object(cands))
        return cn_ld_fail(c, "candidates", "expected {\"part\": {\"name\": path, ...}, ...}, found %s", cn_ld_type_name(cands));
    int total = 0;
    const char *pname;
    json_t *pv;
    json_object_foreach(cands, pname, pv) total += json_is_object(pv) ? (int)json_object_size(pv) : 0;
    a->cand = cn_calloc((size_t)total + 1, sizeof(cnCandidate));
    if (!a->cand) return cn_diag_set(c->diag, CN_ERR_MEMORY, "candidates", "out of memory");
    char p[PATH_MAX_LEN];
    json_object_foreach(cands, pname, pv) {
        snprintf(p, sizeof p, "candidates.%s", pname);
        int k = cn_assembly_find_part(a, pname);
        if (k < 0 || k >= a->nreal) return cn_ld_no_such_part(c, p, pname, a);
        if (a->parts[k].fixed) return cn_ld_fail(c, p, "part '%s' is fixed; fixed parts never move", pname);
        if (!json_is_object(pv))
            return cn_ld_fail(c, p, "expected named paths, e.g. {\"I\": [[0, 6]]}, found %s", cn_ld_type_name(pv));
        const char *cname;
        json_t *cv;
        json_object_foreach(pv, cname, cv) {
            char q[PATH_MAX_LEN];
            snprintf(q, sizeof q, "candidates.%s.%s", pname, cname);
            cnStatus ps = cn_ld_printable(c, cname, q);
            if (ps) return ps;
            cnCandidate *cd = &a->cand[a->ncand];
            cd->part = k;
            cd->support = -1;
            cd->name = cn_strdup(cname);
            if (!cd->name) return cn_diag_set(c->diag, CN_ERR_MEMORY, q, "out of memory");
            a->ncand++;
            const json_t *path = cv;
            if (json_is_object(cv)) {
                static const char *const keys[] = {"path", "support", NULL};
                if ((s = cn_ld_check_keys(c, cv, q, keys))) return s;
                path = json_object_get(cv, "path");
                json_t *sup = json_object_get(cv, "support");
                char q2[PATH_MAX_LEN];
                snprintf(q2, sizeof q2, "%s.support", q);
                if (sup && (s = cn_ld_get_support(c, sup, q2, &cd->support))) return s;
                snprintf(q2, sizeof q2, "%s.path", q);
                if (!path) return cn_ld_fail(c, q2, "missing; give the path's displacements");
                if (!json_is_array(path) || json_array_size(path) == 0)
                    return cn_ld_fail(c, q2, "expected a non-empty array of displacements");
                if ((s = cn_ld_get_path(c, path, q2, a->dim, &cd->seg, &cd->nseg))) return s;
                if ((s = cn_ld_check_turns(c, a, q2, &cd->part, 1, cd->seg, cd->nseg))) return s;
            } else {
                if (!json_is_array(cv) || json_array_size(cv) == 0)
                    return cn_ld_fail(c, q, "expected a path: a non-empty array of displacements, e.g. [[0, 6]]");
                if ((s = cn_ld_get_path(c, cv, q, a->dim, &cd->seg, &cd->nseg))) return s;
                if ((s = cn_ld_check_turns(c, a, q, &cd->part, 1, cd->seg, cd->nseg))) return s;
            }
            for (int i = 0; i < cd->nseg; i++)
                if (cd->seg[i].kind == CN_SEGMENT_MOVE &&
                    !(cn_norm3(cd->seg[i].move) > CN_TOL_LENGTH_ZERO * a->length_scale))
                    return cn_ld_fail(c, q, "displacement %d has zero length; remove it", i);
            double L = cn_path_length(a, &cd->part, 1, cd->seg, cd->nseg, NULL);
            if (L / (a->sim_speed * a->sim_dt) > CN_MAX_SAMPLES)
                return cn_ld_fail(c, q, "the path would take %.3g samples (length %.6g, speed %g, dt %g); "
                                  "at most %d are allowed: raise simulation.dt or speed",
                            L / (a->sim_speed * a->sim_dt), L, a->sim_speed, a->sim_dt, CN_MAX_SAMPLES);
        }
    }
    return CN_OK;
}

/* A gripper must touch the parts it supports and not overlap them. */
cnStatus cn_ld_check_grippers(Ctx *c, cnAssembly *a) {
    unsigned char *absent = cn_malloc((size_t)a->nparts);
    if (!absent) return cn_diag_set(c->diag, CN_ERR_MEMORY, "plan", "out of memory");
    cnStatus s = CN_OK;
    for (int k = 0; k < a->nsteps && !s; k++) {
        const cnPlanStep *st = &a->plan[k];
        if (st->gripper < 0) continue;
        memset(absent, 1, (size_t)a->nparts);
        absent[st->gripper] = 0;
        for (int i = 0; i < st->nmove; i++) absent[st->move[i]] = 0;
        cnContactQuery q = {NULL, absent, NULL};
        cnContactSet cs = {0};
        cnOverlap ov;
        s = cn_contacts_find(a, &q, &cs, &ov, c->diag);
        int touches = 0;
        for (int i = 0; i < cs.count; i++)
            touches |= cs.items[i].body1 == st->gripper || cs.items[i].body2 == st->gripper;
        cn_contacts_free(&cs);
        char p[PATH_MAX_LEN];
        snprintf(p, sizeof p, "plan[%d].gripper", k);
        if (!s && ov.found)
            s = cn_ld_fail(c, p, "the gripper overlaps part '%s' by %.6g; it must touch the moved parts, not overlap them",
                           a->parts[ov.part1 == st->gripper ? ov.part2 : ov.part1].name, ov.depth);
        else if (!s && !touches)
            s = cn_ld_fail(c, p, "the gripper does not touch the parts this step moves; place it against them");
    }
    cn_free(absent);
    return s;
}
