/* cairn: contacts found from the geometry. */
#ifndef CAIRN_CONTACT_H
#define CAIRN_CONTACT_H

#include "cairn/export.h"

#include "cairn/model.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Index used for "the world" (a fixel) in cnContact.body1. */
#define CN_WORLD (-1)

/** Which features touch (the dimension of the touching region). */
typedef enum cnContactKind {
    CN_CONTACT_VERTEX = 0, /**< a single point: vertex-edge (2-D), vertex-face or edge-edge (3-D) */
    CN_CONTACT_EDGE = 1,   /**< a segment: edge-edge (2-D), edge-face (3-D) */
    CN_CONTACT_FACE = 2,   /**< a polygon: face-face (3-D) */
    CN_CONTACT_FIXEL = 3   /**< a fixel */
} cnContactKind;

/** The most ends of a corner contact's cone of normals that are kept (a 3-D vertex on a
 *  vertex: the extreme rays where the two vertices' normal cones meet, 3 for a box's corner on
 *  a box's corner). */
#define CN_CORNER_ENDS 8

/** One contact point. The normal points from body1 into body2: a compressive contact force f >= 0
 *  pushes body2 along +normal and body1 along -normal. */
typedef struct cnContact {
    int id;           /**< 1-based, stable for a given input */
    int body1, body2; /**< part indices; body1 is CN_WORLD for a fixel */
    int piece1, piece2;
    int fixel;        /**< fixel index, or -1 */
    cnContactKind kind;
    double point[3];
    double normal[3]; /**< unit */
    double gap;       /**< signed distance between the surfaces (negative = overlap) */
    int vertex;       /**< the number of a vertex (of body2, else body1) at the point, or 0 */
    bool corner;      /**< a corner on a corner: the contact has no normal of its own; any
                         direction in the cone spanned by `normal`, `alt_normal` and
                         `more_normals` separates the parts, which may move apart along any
                         motion that one of the cone's ends does not close. In 2-D and for a
                         3-D edge on a parallel edge the cone has two ends; a 3-D vertex on a
                         vertex or on an edge up to CN_CORNER_ENDS. cn_check decides every
                         reading (each such contact taking one end as its normal) and reports
                         the worst */
    double alt_normal[3]; /**< with corner: the second end of the cone of normals (unit) */
    int corner_ends;      /**< with corner: the ends of its cone (2 .. CN_CORNER_ENDS), else 0 */
    bool corner_wide;     /**< with corner: the cone had more ends than CN_CORNER_ENDS, and only
                             the first CN_CORNER_ENDS were kept: the check cannot call it stable */
    double more_normals[CN_CORNER_ENDS - 2][3]; /**< with corner: ends 3 .. corner_ends */
} cnContact;

/** End e (0 .. corner_ends - 1) of a corner contact's cone of normals: `normal`, `alt_normal`,
 *  then `more_normals`. */
static inline double *cn_contact_end(cnContact *c, int e) {
    return e == 0 ? c->normal : e == 1 ? c->alt_normal : c->more_normals[e - 2];
}

/** A growable list of contacts. Zero-initialise it; free with cn_contacts_free(). */
typedef struct cnContactSet {
    int count, capacity;
    cnContact *items;
} cnContactSet;

/** Work options for contact detection. Make with cn_contact_query_default(). */
typedef struct cnContactQuery {
    const cnPose *pose;          /**< per-part placement (NULL: parts where loaded) */
    const unsigned char *absent; /**< per-part flag: 1 = removed from the scene (NULL: all here) */
    const cnTwist *twist;        /**< per-part velocity (NULL: at rest). Only breaks ties: where
                                    two separating axes touch equally (a corner on a corner), the
                                    one the relative motion does not close is the normal */
} cnContactQuery;

/** The deepest overlap found, if any (depth > contact tolerance). */
typedef struct cnOverlap {
    int found;
    int part1, part2;
    double depth; /**< penetration; in a check of moving parts, a negative value is the distance
                     the motion still has to go before two touching surfaces collide */
    double tol;   /**< the contact tolerance of the pair (deeper is an overlap) */
} cnOverlap;

CN_API cnContactQuery cn_contact_query_default(void);

/** Find every contact among the parts of `a` (posed by `query`, NULL = as loaded) and the
 *  fixels. Contacts are appended to `out` (cleared first), numbered 1.. in a deterministic order
 *  (by part pair, then along the contact). Overlaps deeper than the tolerance are not contacts:
 *  the deepest is reported in `overlap` (may be NULL). Returns CN_OK or CN_ERR_MEMORY. */
CN_API cnStatus cn_contacts_find(const cnAssembly *a, const cnContactQuery *query, cnContactSet *out,
                          cnOverlap *overlap, cnDiag *diag);

CN_API void cn_contacts_free(cnContactSet *s);

/** The part nearest to part i where the parts are loaded (-1: no other part), and in *gap a
 *  lower bound of their distance (the widest gap along a face normal of two of their pieces,
 *  exact where the nearest features are parallel faces; 0 or less when no face normal separates
 *  them). For messages about a part that touches nothing. */
CN_API int cn_part_nearest(const cnAssembly *a, int i, double *gap);

/** Is contact c of `set` (as cn_contacts_find numbered it) a 2-D corner on a corner that the
 *  other contacts of its pair already imply? It is when contacts of the same two parts lie at
 *  its point (within the pair's contact tolerance, and within 1e-6 of the smaller part's size
 *  whatever the tolerance: float32 rounding) and both ends of its cone are nonnegative
 *  combinations of their normals: a part's corner seated in a notch of the other, touching
 *  both faces there. Every constraint a reading puts on the motion is then one the faces put;
 *  and whenever the corner would carry force both faces are closed, so the point sticks and the
 *  faces carry the force (its friction cone lies in the sum of theirs). No reading of it adds
 *  or removes a solution: the check leaves it out. False in 3-D, where faces closed at a
 *  point do not make it stick. */
CN_API bool cn_contact_corner_implied(const cnAssembly *a, const cnContactSet *set, int c);

#ifdef __cplusplus
}
#endif
#endif
