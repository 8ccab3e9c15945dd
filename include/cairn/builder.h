/* cairn: build an assembly in code instead of writing its JSON text.
 *
 * A builder collects the same things the assembly file holds (parts and their shapes, gravity,
 * friction, a plan) and cn_builder_finish() loads them through the same checks as a file: a
 * problem is reported with the JSON path the equivalent file would have ("parts[2].polygon":
 * the third part added), so the builder and the file format cannot drift apart.
 *
 *     cnBuilder *b = cn_builder_new(2);
 *     cn_builder_add_polygon(b, "table", 4, (double[]){-5, -1, 5, -1, 5, 0, -5, 0}, true);
 *     cn_builder_add_polygon(b, "A", 4, (double[]){0, 0, 2, 0, 2, 1, 0, 1}, false);
 *     cnAssembly *a;
 *     cnDiag d;
 *     if (cn_builder_finish(b, &a, &d) != CN_OK) ...   // d.where, d.message
 *     cn_builder_free(b);
 *
 * Calls after a failed one do nothing and return the first failure's status; cn_builder_finish
 * reports it. */
#ifndef CAIRN_BUILDER_H
#define CAIRN_BUILDER_H

#include "cairn/export.h"

#include <stdbool.h>

#include "cairn/model.h"
#include "cairn/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** An assembly under construction (opaque). */
typedef struct cnBuilder cnBuilder;

/** A new, empty builder for a 2-D or 3-D assembly (gravity 9.81 down the last axis, density 1,
 *  frictionless, as a file that says nothing else). NULL when out of memory; a dim other than 2
 *  or 3 is reported by cn_builder_finish. */
CN_API cnBuilder *cn_builder_new(int dim);
/** Free a builder (NULL is allowed). The assemblies it made stay valid. */
CN_API void cn_builder_free(cnBuilder *b);

/** The assembly's title. */
CN_API cnStatus cn_builder_set_name(cnBuilder *b, const char *name);
/** The acceleration of gravity (dim components). */
CN_API cnStatus cn_builder_set_gravity(cnBuilder *b, const double *g);
/** The default Coulomb friction coefficient (0: frictionless). */
CN_API cnStatus cn_builder_set_friction(cnBuilder *b, double mu);
/** The default density. */
CN_API cnStatus cn_builder_set_density(cnBuilder *b, double density);
/** The number of friction-pyramid directions (3-D). */
CN_API cnStatus cn_builder_set_friction_directions(cnBuilder *b, int n);
/** The relative contact tolerance (the file's "tolerance"). */
CN_API cnStatus cn_builder_set_tolerance(cnBuilder *b, double rel_tol);
/** A friction coefficient for the pair of parts named a and b. */
CN_API cnStatus cn_builder_set_pair_friction(cnBuilder *b, const char *a, const char *bname, double mu);

/** Add a 2-D part: a convex polygon of n vertices, xy = x0, y0, x1, y1, ... (either
 *  orientation). `fixed`: a support. */
CN_API cnStatus cn_builder_add_polygon(cnBuilder *b, const char *name, int n, const double *xy, bool fixed);
/** Add a 3-D part: an axis-aligned box. */
CN_API cnStatus cn_builder_add_box(cnBuilder *b, const char *name, const double lo[3], const double hi[3],
                            bool fixed);
/** Add a 3-D part: the convex hull of n points, xyz = x0, y0, z0, x1, ... */
CN_API cnStatus cn_builder_add_hull(cnBuilder *b, const char *name, int n, const double *xyz, bool fixed);
/** Add one more convex piece (a polygon in 2-D, a hull in 3-D, n points as above) to the part
 *  added last: a non-convex part as a union of convex pieces (a box part cannot take pieces). */
CN_API cnStatus cn_builder_add_piece(cnBuilder *b, int n, const double *pts);
/** The density of the part added last (instead of the default). */
CN_API cnStatus cn_builder_set_part_density(cnBuilder *b, double density);
/** The mass of the part added last (instead of density times size). */
CN_API cnStatus cn_builder_set_part_mass(cnBuilder *b, double mass);

/** The pose of the part added last: its shape turned by pose->q about the origin of the
 *  coordinates it was given in, then moved by pose->t (the file's "rotation" and "position"; in
 *  2-D the rotation must be about z). */
CN_API cnStatus cn_builder_set_part_pose(cnBuilder *b, const cnPose *pose);

/** Add a frictionless point fixture on the part named `part` at `point`, pushing along
 *  `normal` (dim components each). */
CN_API cnStatus cn_builder_add_fixel(cnBuilder *b, const char *part, const double *point, const double *normal);

/** Add a plan step: the nmove parts named in `move` leave along nseg segments (nseg 0: straight
 *  up against gravity until clear), carried (CN_SUPPORT_HOLD) or pushed (CN_SUPPORT_PUSH) by
 *  the gripper, which holds the first part named. A segment is a translation (CN_SEGMENT_MOVE,
 *  its `move`) or a turn (CN_SEGMENT_TURN: `angle` in radians about `axis` through `about`). */
CN_API cnStatus cn_builder_add_step(cnBuilder *b, int nmove, const char *const *move, int nseg,
                             const cnSegment *seg, cnSupport support);
/** The sampling of a plan's motion: interval dt (0: the default) and speed (0: 1). */
CN_API cnStatus cn_builder_set_simulation(cnBuilder *b, double dt, double speed);

/** Load what the builder holds as an assembly, with every check of the file format. On failure
 *  the diagnostic's `where` is the JSON path in the equivalent file. The builder stays usable
 *  (add more and finish again). */
CN_API cnStatus cn_builder_finish(const cnBuilder *b, cnAssembly **out, cnDiag *diag);

/** The equivalent assembly file as JSON text (newly allocated; free with cn_string_free), e.g.
 *  to save what was built. NULL when out of memory. */
CN_API char *cn_builder_json(const cnBuilder *b);

/** Free a string returned by the library. */
CN_API void cn_string_free(char *s);

#ifdef __cplusplus
}
#endif
#endif
