/* io: reading assembly files. Private. */
#ifndef CAIRN_IO_H
#define CAIRN_IO_H

#include <jansson.h>
#include <stdbool.h>
#include <stddef.h>

#include "cairn/status.h"
#include "mesh3.h"

/* A part is at most this many times smaller than its distance from the origin: double
 * coordinates keep about 16 digits, of which it would keep fewer than 8 (the contact tolerance is
 * 1e-6 of a part). */
#define CN_MAX_FAR_RATIO 1e8
/* A part's size (its box's diagonal) is within these: its volume and inertia (the fifth power of
 * its size in 3-D) neither overflow nor underflow, whatever unit the file uses. */
#define CN_MIN_PART_SIZE 1e-50
#define CN_MAX_PART_SIZE 1e50
/* Coordinates of a place (a shape's point, a box corner, a fixel's point, a position, a COMPAS
 * block's vertex) are at most this in magnitude: the largest part, as far out as it may be. */
#define CN_MAX_COORD (CN_MAX_PART_SIZE * CN_MAX_FAR_RATIO)

/* The first control character of text (C0, DEL, or C1 written in UTF-8): its code, with its
 * byte offset in *at; -1 when there is none. Names go into one-line messages and tables. */
int cn_control_char(const char *text, int *at);

/* Is the JSON document a COMPAS assembly (compas_assembly's Assembly, compas_cra's
 * CRA_Assembly)? */
bool cn_compas_is(const json_t *root);
/* The COMPAS assembly as a cairn document (new reference): a part per graph node, the hull of
 * its block's vertices, named by the node key; supports: the comma-separated node keys in
 * `supports`, or (NULL) the nodes' is_support. Blocks not convex within rel_tol of their size
 * are refused. NULL with diag set on failure. */
json_t *cn_compas_to_cairn(const json_t *root, const char *supports, double rel_tol, cnDiag *diag);

/* The meshes of a mesh file (Assimp), each scaled by `scale`, one per placement in the file's
 * node tree: *nout of them in *out (free each with cn_mesh_free, then the array with cn_free).
 * CN_ERR_INPUT (no `where`; the file named `shown`) when the file is not OBJ, STL, PLY or OFF,
 * cannot be read, holds no faces, a face names a vertex it does not have, or a coordinate is
 * not finite. */
cnStatus cn_mesh_read(const char *file, const char *shown, double scale, cnMesh **out, int *nout,
                      cnDiag *diag);

/* A PLY file (len bytes of buf, named `shown`) checked before Assimp reads it: its header line by
 * line, the counts it declares against the file's size, each list's count against the rest of
 * its line (text) or of the file (binary). CN_ERR_INPUT naming the line or byte, else CN_OK. */
cnStatus cn_ply_check(const char *buf, size_t len, const char *shown, cnDiag *diag);
/* An OFF file checked the same way: its header, its counts against the file's size, each face
 * (a count of 3 to 9 vertices, indices that name vertices of the file). */
cnStatus cn_off_check(const char *buf, size_t len, const char *shown, cnDiag *diag);

#endif
