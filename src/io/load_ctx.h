/* Loading an assembly from JSON: the reading state and the readers shared by load_json.c (the
 * document, its parts, fixels and pairs), load_read.c (messages, keys, numbers, points, paths,
 * part lists), load_shape.c (shapes, meshes, poses) and load_plan.c (the plan, candidates,
 * grippers). Private to src/io/. */
#ifndef CAIRN_LOAD_CTX_H
#define CAIRN_LOAD_CTX_H

#include <jansson.h>
#include <stdbool.h>

#include "cairn/model.h"

typedef struct {
    cnDiag *diag;
    int dim;
    double rel_tol;        /* the assembly's relative tolerance (meshes are welded within it) */
    const char *mesh_dir;  /* mesh paths are relative to this directory */
    bool mesh_anywhere;    /* and may lead outside it */
    json_t *names;         /* while the parts load: each name so far, with its part's index */
} Ctx;

/* Room for a JSON path in a message. */
#define PATH_MAX_LEN 256

/* load_read.c */
cnStatus cn_ld_fail(Ctx *c, const char *path, const char *fmt, ...)
                    __attribute__((format(printf, 3, 4)));
cnStatus cn_ld_printable(Ctx *c, const char *text, const char *path);
cnStatus cn_ld_no_such_part(Ctx *c, const char *path, const char *name, const cnAssembly *a);
const char *cn_ld_type_name(const json_t *v);
cnStatus cn_ld_check_keys(Ctx *c, const json_t *obj, const char *path,
                          const char *const *allowed);
cnStatus cn_ld_get_number(Ctx *c, const json_t *v, const char *path, double *out);
cnStatus cn_ld_get_positive(Ctx *c, const json_t *v, const char *path, double *out);
cnStatus cn_ld_get_point(Ctx *c, const json_t *v, const char *path, int dim, double out[3]);
cnStatus cn_ld_get_place(Ctx *c, const json_t *v, const char *path, int dim, double out[3]);
cnStatus cn_ld_get_path(Ctx *c, const json_t *v, const char *path, int dim, cnSegment **segs,
                        int *n);
cnStatus cn_ld_check_turns(Ctx *c, const cnAssembly *a, const char *path, const int *parts,
                           int n, const cnSegment *seg, int nseg);
cnStatus cn_ld_get_points(Ctx *c, const json_t *v, const char *path, int dim, int min,
                          const char *what, double (**pts)[3], int *n);
cnStatus cn_ld_get_part_list(Ctx *c, const json_t *v, const char *path, const cnAssembly *a,
                             const int *removed_by, int step, const int *allowed, int nallowed,
                             int **out, int *n);
cnStatus cn_ld_get_support(Ctx *c, const json_t *e, const char *p, int *out);

/* load_shape.c */
cnStatus cn_ld_load_shape(Ctx *c, const json_t *v, const char *path, cnPart *part);
cnStatus cn_ld_get_pose(Ctx *c, const json_t *v, const char *path, cnPose *out, bool *posed);

/* load_plan.c */
cnStatus cn_ld_load_plan(Ctx *c, const json_t *root, cnAssembly *a);
cnStatus cn_ld_load_candidates(Ctx *c, const json_t *root, cnAssembly *a);
cnStatus cn_ld_check_grippers(Ctx *c, cnAssembly *a);

#endif
