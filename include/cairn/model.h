/* cairn: the loaded assembly (immutable after loading).
 *
 * Units are the file's own; cairn never assumes metres or kilograms. Every tolerance is scaled by
 * the assembly's length scale (the diagonal of its bounding box) and its weights. */
#ifndef CAIRN_MODEL_H
#define CAIRN_MODEL_H

#include "cairn/export.h"

#include <stdbool.h>

#include "cairn/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Default relative contact tolerance: two surfaces closer than this fraction of the assembly's
 *  length scale touch; overlap deeper than it is an input error. */
#define CN_DEFAULT_RELATIVE_TOLERANCE 1e-6
/** Most samples one plan step may take (path length / (speed dt)): beyond, the file is refused,
 *  so that no run is endless. The planner's candidate paths use the same dt. */
#define CN_MAX_SAMPLES 100000

/** Most segments one path may have (a plan step's or a candidate's): a longer path is refused at
 *  load with its JSON path. */
#define CN_MAX_PATH_SEGMENTS 10000
/** Default number of friction-pyramid directions in 3-D (2-D always uses 2). */
#define CN_DEFAULT_FRICTION_DIRECTIONS 8
/** Most friction-pyramid directions a 3-D assembly may have (a file asking more is refused). */
#define CN_MAX_FRICTION_DIRECTIONS 64

/** A planar face of a convex 3-D piece. */
typedef struct cnFace {
    int nverts;       /**< number of vertices on the face loop */
    int *verts;       /**< indices into the piece's vertices, counter-clockwise seen from outside */
    double normal[3]; /**< outward unit normal */
    double offset;    /**< normal . x = offset on the face */
} cnFace;

/** The kind of a convex piece: which narrow phase meets it (see src/collide/contact.c's table). */
typedef enum cnShape {
    CN_SHAPE_POLYGON = 0,    /**< a convex polygon in the plane z = 0 (2-D assemblies) */
    CN_SHAPE_POLYHEDRON = 1, /**< a convex polyhedron with faces and edges (3-D assemblies) */
    CN_SHAPE_COUNT
} cnShape;

/** A convex piece of a part. In 2-D the vertices are a counter-clockwise polygon with z = 0. */
typedef struct cnPiece {
    cnShape shape;
    int nverts;
    double (*verts)[3];
    int nfaces;         /**< 3-D only */
    cnFace *faces;      /**< 3-D only */
    int nedges;         /**< 3-D only: unique edges */
    int (*edges)[2];    /**< 3-D only: vertex index pairs */
    double lo[3], hi[3]; /**< axis-aligned bounding box */
    int *vnum;          /**< a piece split from a part's outline (a non-convex "polygon"): the
                            outline index of each vertex (its number is vertex_base + vnum + 1);
                            NULL: the piece's vertices are numbered in turn */
} cnPiece;

/** Where a part is: a point x of the part as loaded goes to R x + t, with R the rotation of the
 *  unit quaternion q = (w, x, y, z) (in 2-D a rotation about z). The identity leaves the part
 *  where the file put it; a translation has q = (1, 0, 0, 0). */
typedef struct cnPose {
    double q[4];
    double t[3];
} cnPose;

/** The identity pose. */
CN_API cnPose cn_pose_identity(void);
/** A translation by t. */
CN_API cnPose cn_pose_translation(const double t[3]);
/** A rotation by `angle` radians about the line through `about` along `axis` (right-hand rule;
 *  axis need not be unit, must be nonzero; in 2-D pass (0, 0, 1): counter-clockwise). */
CN_API cnPose cn_pose_rotation(const double axis[3], double angle, const double about[3]);
/** First `first`, then `then`: x -> then(first(x)). */
CN_API cnPose cn_pose_then(const cnPose *first, const cnPose *then);
/** The image of point x (out may alias x). */
CN_API void cn_pose_apply(const cnPose *p, const double x[3], double out[3]);
/** The image of direction v: rotated, not translated (out may alias v). */
CN_API void cn_pose_rotate(const cnPose *p, const double v[3], double out[3]);
/** The rotation matrix of p. */
CN_API void cn_pose_matrix(const cnPose *p, double R[3][3]);
/** Is p a pure translation (its rotation exactly the identity)? */
CN_API bool cn_pose_is_translation(const cnPose *p);
/** The rotation angle of p in radians, in [0, pi] (2-D: signed, counter-clockwise positive). */
CN_API double cn_pose_angle(const cnPose *p, int dim);

/** A rigid velocity: the point at `about` moves with `v`, and the part turns with angular
 *  velocity `w` (radians per unit time about the axis along w; in 2-D only w[2] is used). The
 *  velocity of a point x is v + w x (x - about). */
typedef struct cnTwist {
    double v[3];
    double w[3];
    double about[3];
} cnTwist;

/** The velocity of point x under twist t. */
CN_API void cn_twist_at(const cnTwist *t, const double x[3], double out[3]);

/** A rigid part: the union of its convex pieces. */
typedef struct cnPart {
    char *name;
    bool fixed;          /**< a support (table, wall): never moves, has no mass */
    int npieces;
    cnPiece *pieces;
    int gripper_step;    /**< >= 0: the gripper body of plan step gripper_step (absent unless a
                            motion query includes it); -1 for the assembly's own parts */
    double size;         /**< area (2-D) or volume (3-D) */
    double density;      /**< mass per unit size */
    double mass;
    double com[3];       /**< centre of mass */
    double inertia[3][3]; /**< inertia tensor about the centre of mass, world axes. In 2-D only
                             inertia[2][2] (the polar moment) is used. */
    double lo[3], hi[3]; /**< bounding box over pieces */
    int vertex_base;     /**< vertices are numbered vertex_base + 1 .. over the pieces in order
                            (the numbers the figures show); a part split from a non-convex
                            outline numbers its outline's vertices instead */
    int nnumbers;        /**< vertex numbers the part uses (its pieces' vertices, or its outline's) */
    int noutline;        /**< a non-convex "polygon" split into pieces: its outline (counter-
                            clockwise), else 0 */
    double (*outline)[3];
    char *mesh_file;     /**< the part came from this mesh file (as the assembly names it), or NULL */
    int mesh_split;      /**< convex pieces the exact decomposition made of its non-convex meshes
                            (0: every mesh of the file was convex, one piece each) */
} cnPart;

/** How the gripper carries the part it moves (paper sec. III-A). */
typedef enum cnSupport {
    CN_SUPPORT_HOLD = 0, /**< the gripper carries the part's weight */
    CN_SUPPORT_PUSH = 1  /**< the gripper drives the part along its path only */
} cnSupport;

/** The kind of a path segment. */
typedef enum cnSegmentKind {
    CN_SEGMENT_MOVE = 0, /**< a translation by `move` */
    CN_SEGMENT_TURN = 1  /**< a rotation by `angle` about the line through `about` along `axis` */
} cnSegmentKind;

/** One segment of a motion path. Segments chain: each moves the parts from where the previous
 *  one left them, and a turn's `about` is a point in world coordinates at the segment's start. */
typedef struct cnSegment {
    cnSegmentKind kind;
    double move[3];  /**< MOVE: the displacement */
    double angle;    /**< TURN: radians, right-hand rule about axis (2-D: counter-clockwise) */
    double axis[3];  /**< TURN: unit axis ((0, 0, 1) in 2-D) */
    double about[3]; /**< TURN: a point on the axis */
} cnSegment;

/** Does a path of nseg segments turn (have a CN_SEGMENT_TURN)? */
CN_API bool cn_path_turns(const cnSegment *seg, int nseg);

/** The pose a segment applies after the fraction f (0 .. 1) of it, in world coordinates. */
CN_API cnPose cn_segment_pose(const cnSegment *s, double f);

/** One step of a disassembly plan: `move` leaves along `path`. */
typedef struct cnPlanStep {
    int nmove;
    int *move;          /**< part indices */
    int ngrip;
    int *grip;          /**< the parts the gripper holds (a subset of move) */
    int nseg;
    cnSegment *seg;     /**< path segments, in order */
    bool path_given;    /**< false: straight up against gravity until clear (made at load) */
    cnSupport support;
    int gripper;        /**< index of the gripper body among the parts, or -1 */
    const unsigned char *still; /**< per part: held in place by the other hand while the step
                                   runs (two-handed disassembly of a subassembly); NULL: none */
} cnPlanStep;

/** A named candidate path for a part (the paper's exits), for the planner. */
typedef struct cnCandidate {
    int part;
    char *name;
    int nseg;
    cnSegment *seg;
    int support;        /**< cnSupport, or -1 for the file's candidate_support */
} cnCandidate;

/** A frictionless point fixture: pushes on `part` at `point` along `normal` (unit). */
typedef struct cnFixel {
    int part;
    double point[3];
    double normal[3];
} cnFixel;

/** A friction coefficient that overrides the default for one pair of parts. */
typedef struct cnFrictionPair {
    int a, b;
    double mu;
} cnFrictionPair;

/** An assembly, as loaded. Immutable: work state lives elsewhere. */
typedef struct cnAssembly {
    char *name;           /**< optional title (may be NULL) */
    char *source;         /**< file the assembly came from (may be NULL) */
    int dim;              /**< 2 or 3 */
    double gravity[3];    /**< acceleration of gravity (z = 0 in 2-D) */
    double density;       /**< default density */
    double friction;      /**< default friction coefficient (0 = frictionless) */
    int friction_dirs;    /**< friction pyramid directions (2 in 2-D) */
    double rel_tol;       /**< relative contact tolerance */
    int nparts;           /**< including the plan's gripper bodies, which come last */
    int nreal;            /**< the assembly's own parts: parts[0 .. nreal-1] */
    cnPart *parts;
    int nfixels;
    cnFixel *fixels;
    int npairs;
    cnFrictionPair *pairs;
    int nsteps;
    cnPlanStep *plan;     /**< the disassembly plan (may be empty) */
    int ncand;
    cnCandidate *cand;    /**< named candidate paths, grouped by part in file order */
    cnSupport cand_support; /**< default support of candidates (hold) */
    double sim_dt;        /**< sampling interval of a motion (default 1) */
    double sim_speed;     /**< speed along a path (default 1) */
    double lo[3], hi[3];  /**< bounding box of all parts */
    double length_scale;  /**< diagonal of the bounding box */
    double contact_tol;   /**< absolute contact tolerance = rel_tol * length_scale */
} cnAssembly;

/** Load an assembly from a JSON file ("-": standard input). On failure returns CN_ERR_INPUT / CN_ERR_IO and fills
 *  `diag` (where = "line:column" or a JSON path). `*out` is set only on success; free it with
 *  cn_assembly_free(). */
CN_API cnStatus cn_assembly_load_file(const char *path, cnAssembly **out, cnDiag *diag);

/** Load an assembly file with the plan taken from another file: a JSON object with "plan" and
 *  optionally "simulation", "fixels" and "name" (appended to the assembly's name), which replace
 *  the assembly file's own. Problems in the plan file set diag->file to plan_path. plan_path NULL:
 *  cn_assembly_load_file. */
CN_API cnStatus cn_assembly_load_with_plan(const char *path, const char *plan_path, cnAssembly **out,
                                    cnDiag *diag);

/** cn_assembly_load_with_plan with the plan file's text given instead of its path ("<plan>" in
 *  diagnostics); plan_text NULL: cn_assembly_load_file. */
CN_API cnStatus cn_assembly_load_with_plan_text(const char *path, const char *plan_text, cnAssembly **out,
                                         cnDiag *diag);

/** What the caller overrides when loading (the CLI's --friction, --density, --tolerance,
 *  --supports). Make with cn_load_options_default(). */
typedef struct cnLoadOptions {
    double friction;      /**< the default friction coefficient, instead of the file's (NAN: the file's) */
    double density;       /**< the default density (NAN: the file's) */
    double tolerance;     /**< the relative contact tolerance (NAN: the file's) */
    const char *supports; /**< a COMPAS assembly: the node keys of its supports, comma-separated
                               (NULL: the nodes' is_support); refused for a cairn file */
    const char *mesh_dir; /**< the directory "mesh" paths are relative to (NULL: the assembly
                               file's own; the current directory for text and standard input) */
    bool mesh_anywhere;   /**< mesh paths may lead outside that directory (else refused) */
} cnLoadOptions;

CN_API cnLoadOptions cn_load_options_default(void);

/** Load an assembly file, cairn's or a COMPAS assembly (compas_assembly's Assembly or
 *  compas_cra's CRA_Assembly: a part per graph node, named by its key, the convex hull of its
 *  block; a block that is not convex is refused), with the plan from plan_path or plan_text (both
 *  NULL: the file's own) and the caller's overrides (o may be NULL). */
CN_API cnStatus cn_assembly_load_with(const char *path, const char *plan_path, const char *plan_text,
                               const cnLoadOptions *o, cnAssembly **out, cnDiag *diag);

/** Load from JSON text; `source` names it in diagnostics (may be NULL). */
CN_API cnStatus cn_assembly_load_string(const char *text, const char *source, cnAssembly **out,
                                 cnDiag *diag);
/** cn_assembly_load_string with the caller's overrides (o may be NULL). */
CN_API cnStatus cn_assembly_load_string_with(const char *text, const char *source, const cnLoadOptions *o,
                                      cnAssembly **out, cnDiag *diag);

/** Free an assembly (NULL is allowed). */
CN_API void cn_assembly_free(cnAssembly *a);

/** Index of the part named `name`, or -1. */
CN_API int cn_assembly_find_part(const cnAssembly *a, const char *name);

/** Friction coefficient between parts i and j (j = -1: the world, i.e. a fixel: always 0). */
CN_API double cn_assembly_mu(const cnAssembly *a, int i, int j);

/** The presence rule, the one every stage uses: is part i in the scene? With an `absent` mask
 *  (per part, 1 = removed), as it says; without (NULL), every part but the plan's gripper bodies. */
CN_API bool cn_assembly_part_present(const cnAssembly *a, const unsigned char *absent, int i);
/** The length of a path for sampling: a move's length, a turn's angle times the largest distance
 *  from its axis of a vertex of the parts `parts` (n of them) where the turn starts: the distance
 *  the farthest point travels. lengths (nseg entries, may be NULL) receives each segment's;
 *  returns the total. */
CN_API double cn_path_length(const cnAssembly *a, const int *parts, int n, const cnSegment *seg, int nseg,
                      double *lengths);

/** Weight (mass times |g|) of part i. */
CN_API double cn_part_weight(const cnAssembly *a, int i);

#ifdef __cplusplus
}
#endif
#endif
