/* The path of a step: where its parts are at a distance along it, its traversal (reversed for an
 * assembly), and the samples its contact events add. */
#include <math.h>
#include <string.h>

#include "collide.h"
#include "sim_step.h"

/* A path segment within this angle (sine) of gravity counts as vertical: always held. */
#define SIM_VERTICAL_SIN 1e-9

/* The path at distance s: the pose, the velocity of the segment being travelled (at a junction:
 * the one that ends there, the part arriving, or with `leave` the one that starts there), and
 * whether the part pauses there: at a segment's end (within twice the contact tolerance) the
 * motion along it stops before the next begins, so a part placed at the end of a segment
 * arrives at its contacts instead of being driven into them. */
void cn_sm_path_at(const Step *S, double s, bool leave, PathPoint *pp) {
    memset(pp, 0, sizeof *pp);
    pp->pose = S->start;
    double left = s, near = 2 * S->a->contact_tol;
    for (int i = 0; i < S->nseg; i++) {
        const cnSegment *sg = &S->seg[i];
        double L = S->seglen[i];
        /* leaving a junction: the next segment, from its start */
        bool here = leave ? left < L - near || i == S->nseg - 1 : left <= L || i == S->nseg - 1;
        double f = here ? fmin(left, L) : L;
        if (sg->kind == CN_SEGMENT_MOVE) {
            if (here) {
                cn_copy3(pp->dir, sg->move);
                cn_scale3(pp->dir, 1.0 / L);
                cn_copy3(pp->unit.v, pp->dir);
                for (int k = 0; k < 3; k++) pp->pose.t[k] += pp->dir[k] * f;
            } else {
                cn_add3(pp->pose.t, sg->move, pp->pose.t);
            }
        } else {
            cnPose turn = cn_segment_pose(sg, f / L);
            pp->pose = cn_pose_then(&pp->pose, &turn);
            if (here) {
                pp->turn = true;
                for (int k = 0; k < 3; k++) pp->unit.w[k] = sg->axis[k] * sg->angle / L;
                cn_copy3(pp->unit.about, sg->about);
            }
        }
        if (here) {
            pp->paused = L - f <= near;
            return;
        }
        left -= L;
    }
}

/* Corollary 1: along or against gravity the gripper always carries the weight. A turn is
 * always held: a gripper that only drives a part cannot turn it about a given axis. */
bool cn_sm_always_held(const cnAssembly *a, const PathPoint *pp) {
    if (pp->turn) return true;
    double gd[3];
    cn_cross3(pp->dir, a->gravity, gd);
    return cn_norm3(gd) <= SIM_VERTICAL_SIN * cn_norm3(a->gravity);
}

/* The displacement reported for a pose of the moved parts: the translation itself for a move
 * (exact), else how far their centre of mass went. */
void cn_sm_reported_disp(const Step *S, const cnPose *ps, double disp[3]) {
    if (cn_pose_is_translation(ps)) {
        cn_copy3(disp, ps->t);
        return;
    }
    double x[3];
    cn_pose_apply(ps, S->com, x);
    cn_sub3(x, S->com, disp);
}

int cn_sm_step_alloc(Step *S, int maxseg) {
    int n = S->a->nparts;
    S->absent = cn_calloc((size_t)n + 1, 1);
    S->pose = cn_calloc((size_t)n + 1, sizeof(cnPose));
    S->role = cn_calloc((size_t)n + 1, 1);
    S->vel = cn_calloc((size_t)n + 1, sizeof(cnTwist));
    S->seg = cn_calloc((size_t)maxseg + 1, sizeof(cnSegment));
    S->seglen = cn_calloc((size_t)maxseg + 1, sizeof(double));
    return S->absent && S->pose && S->role && S->vel && S->seg && S->seglen ? 0 : -1;
}

void cn_sm_step_free(Step *S) {
    cn_free(S->absent);
    cn_free(S->pose);
    cn_free(S->role);
    cn_free(S->vel);
    cn_free(S->seg);
    cn_free(S->seglen);
    cn_free(S->rec_s);
    cn_free(S->rec_leave);
}

/* The traversal of step st: its segments as given, or for an assembly reversed and inverted
 * from where disassembly leaves the parts; their lengths; the moved parts' centre of mass. */
void cn_sm_step_setup(Step *S, const cnPlanStep *st, bool assemble) {
    const cnAssembly *a = S->a;
    S->st = st;
    S->held = false;
    S->nseg = st->nseg;
    S->start = cn_pose_identity();
    double *len = S->seglen;
    S->length = cn_path_length(a, st->move, st->nmove, st->seg, st->nseg, len);
    if (!assemble) {
        memcpy(S->seg, st->seg, sizeof(cnSegment) * (size_t)st->nseg);
    } else {
        /* inserted from where disassembly leaves it, along the path reversed */
        for (int i = 0; i < st->nseg; i++) {
            cnSegment sg = st->seg[i];
            if (sg.kind == CN_SEGMENT_MOVE) {
                cn_add3(S->start.t, sg.move, S->start.t);
            } else {
                cnPose turn = cn_segment_pose(&sg, 1.0);
                S->start = cn_pose_then(&S->start, &turn);
            }
        }
        for (int i = 0, j = st->nseg - 1; i < j; i++, j--) {
            double t = len[i];
            len[i] = len[j], len[j] = t;
        }
        for (int i = 0; i < st->nseg; i++) {
            cnSegment sg = st->seg[st->nseg - 1 - i];
            for (int d = 0; d < 3; d++) sg.move[d] = -sg.move[d];
            sg.angle = -sg.angle;
            S->seg[i] = sg;
        }
    }
    double m = 0;
    S->com[0] = S->com[1] = S->com[2] = 0;
    for (int i = 0; i < st->nmove; i++) {
        const cnPart *p = &a->parts[st->move[i]];
        for (int k = 0; k < 3; k++) S->com[k] += p->mass * p->com[k];
        m += p->mass;
    }
    if (m > 0) cn_scale3(S->com, 1.0 / m);
}

void cn_sm_set_onset_pose(const Step *S, double s, cnStepResult *out) {
    PathPoint pp;
    cn_sm_path_at(S, s, false, &pp);
    out->onset_pose = pp.pose;
    out->onset_angle = cn_pose_angle(&pp.pose, S->a->dim);
    cn_sm_reported_disp(S, &pp.pose, out->onset_disp);
}

/* Merge the contact events of every segment of the step (moves: cn_contact_events, turns:
 * cn_contact_events_turn) into the samples sv/lv (sorted): each event at it and just after it
 * (the touching point moved twice the contact tolerance, past the band in which a pair counts as
 * touching), which samples every stretch between two events with the contacts
 * it has (not just before: a vertex that grazes a corner would be caught closing on the face
 * it passes, within the band). *sv and *lv are reallocated; out counts the events. */
cnStatus cn_sm_event_samples(Step *S, double **sv, unsigned char **lv, int *nsamp,
                              cnStepResult *out) {
    const cnAssembly *a = S->a;
    const cnPlanStep *st = S->st;
    int n = a->nparts;
    unsigned char *mov = cn_calloc((size_t)n + 1, 1), *still = cn_calloc((size_t)n + 1, 1);
    double *ev = cn_malloc(sizeof(double) * CN_SIM_MAX_EVENTS);
    double *extra = NULL;
    int nx = 0, capx = 0;
    cnStatus rc = CN_OK;
    if (!mov || !still || !ev) rc = CN_ERR_MEMORY;
    for (int i = 0; !rc && i < st->nmove; i++) mov[st->move[i]] = 1;
    for (int i = 0; !rc && i < n; i++)
        still[i] = !S->absent[i] && !mov[i] && a->parts[i].gripper_step < 0;
    double *rad = cn_malloc(sizeof(double) * CN_SIM_MAX_EVENTS);
    if (!rad) rc = CN_ERR_MEMORY;
    double acc = 0, delta = 2 * a->contact_tol;
    for (int i = 0; !rc && i < S->nseg; i++) {
        const cnSegment *sg = &S->seg[i];
        double L = S->seglen[i];
        if (L > 0 && (sg->kind == CN_SEGMENT_MOVE || sg->kind == CN_SEGMENT_TURN)) {
            PathPoint pp;
            cn_sm_path_at(S, acc, false, &pp);
            int dropped = 0, ne;
            /* a turn's events are angles: at distance f into it the turn is angle f / L (path_at),
               and a point at distance r from the axis has gone r / (L / |angle|) as far as the
               farthest one, so the sample just after an event moves its touching point 2 tol */
            double per_angle = 1;
            if (sg->kind == CN_SEGMENT_MOVE) {
                double u[3];
                cn_copy3(u, sg->move);
                cn_scale3(u, 1.0 / cn_norm3(u));
                ne = cn_contact_events(a, mov, still, &pp.pose, u, L, ev, CN_SIM_MAX_EVENTS, &dropped);
            } else {
                per_angle = L / fabs(sg->angle);
                ne = cn_contact_events_turn(a, mov, still, &pp.pose, sg->axis, sg->about, sg->angle,
                                            ev, rad, CN_SIM_MAX_EVENTS, &dropped);
            }
            if (ne < 0) {
                rc = CN_ERR_MEMORY;
                break;
            }
            out->nevents += ne;
            out->events_dropped += dropped;
            if (nx + 2 * ne > capx) {
                capx = 2 * (nx + 2 * ne) + 16;
                double *x = cn_realloc(extra, sizeof(double) * (size_t)capx);
                if (!x) {
                    rc = CN_ERR_MEMORY;
                    break;
                }
                extra = x;
            }
            for (int e = 0; e < ne; e++) {
                double at = ev[e] * per_angle, after = delta;
                if (sg->kind == CN_SEGMENT_TURN) /* a point on the axis: past it at the end */
                    after = rad[e] > 0 ? delta * per_angle / rad[e] : L;
                extra[nx++] = acc + fmin(at, L);
                extra[nx++] = acc + fmin(at + after, L);
            }
        }
        acc += L;
    }
    if (!rc && nx > 0) {
        /* sort the extra samples, then merge (the existing ones first at equal distances) */
        for (int i = 1; i < nx; i++) /* insertion sort: nearly sorted by construction */
            for (int j = i; j > 0 && extra[j] < extra[j - 1]; j--) {
                double t = extra[j];
                extra[j] = extra[j - 1], extra[j - 1] = t;
            }
        int m = *nsamp;
        double *ns = cn_malloc(sizeof(double) * (size_t)(m + nx));
        unsigned char *nl = cn_calloc((size_t)(m + nx), 1);
        if (!ns || !nl) {
            cn_free(ns);
            cn_free(nl);
            rc = CN_ERR_MEMORY;
        } else {
            double same = 1e-12 * fmax(S->length, 1e-300);
            int i = 0, j = 0, k = 0;
            while (i < m || j < nx) {
                if (j >= nx || (i < m && (*sv)[i] <= extra[j] + same)) {
                    ns[k] = (*sv)[i], nl[k] = (*lv)[i], k++;
                    /* an extra sample at the same distance as this one adds nothing */
                    while (j < nx && fabs(extra[j] - (*sv)[i]) <= same) j++;
                    i++;
                } else {
                    if (k == 0 || extra[j] - ns[k - 1] > same) ns[k] = extra[j], nl[k] = 0, k++;
                    j++;
                }
            }
            cn_free(*sv);
            cn_free(*lv);
            *sv = ns, *lv = nl, *nsamp = k;
        }
    }
    cn_free(mov);
    cn_free(still);
    cn_free(ev);
    cn_free(rad);
    cn_free(extra);
    return rc;
}
