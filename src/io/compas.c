/* COMPAS assembly files (compas_assembly's Assembly, compas_cra's CRA_Assembly) read as cairn
 * assemblies: each graph node's block (a COMPAS mesh, its surface checked as a "mesh" part's)
 * becomes a part named by its node key: the convex hull of its vertices when it is convex within
 * the tolerance, else the exact convex decomposition of its surface; supports from the nodes'
 * is_support, or from the caller's list of keys. The result is a cairn JSON document, loaded and
 * checked as any file. */
#include <jansson.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "core.h"
#include "io.h"

bool cn_compas_is(const json_t *root) {
    const char *dt = json_string_value(json_object_get(root, "dtype"));
    return dt && (!strcmp(dt, "compas_assembly.datastructures/Assembly") ||
                  !strcmp(dt, "compas_cra.datastructures/CRA_Assembly"));
}

/* The next key of a comma-separated list: its start is list, its length *len; the rest of the
 * list, or NULL after the last. Keys are compared whole, however long. */
static const char *next_key(const char *list, size_t *len) {
    const char *e = strchr(list, ',');
    *len = e ? (size_t)(e - list) : strlen(list);
    return e ? e + 1 : NULL;
}

/* Is key one of the comma-separated keys in list? */
static bool listed(const char *list, const char *key) {
    size_t n = strlen(key), m;
    for (const char *p = list, *q; p && *p; p = q)
        if (q = next_key(p, &m), m == n && !memcmp(p, key, n)) return true;
    return false;
}

static json_t *attr(const json_t *node, const json_t *defaults, const char *key) {
    json_t *v = json_object_get(node, key);
    return v ? v : json_object_get(defaults, key);
}

/* A block's closed surface (checked by cn_mesh_check) split exactly into convex pieces:
 * [[[x, y, z], ...], ...], or NULL with the diagnostic set (a surface that intersects itself,
 * named by its faces). */
static json_t *decompose(cnMesh *m, const char *where, double tol, cnDiag *diag) {
    json_t *out = NULL;
    cnMeshPieces mp = {0, NULL, NULL};
    int f1, f2, r = cn_mesh_split(m, tol, &mp, &f1, &f2);
    if (r) {
        if (r < 0) cn_diag_set(diag, CN_ERR_MEMORY, where, "out of memory");
        else if (r == 3 && f1 >= 0 && f2 >= 0)
            cn_diag_set(diag, CN_ERR_INPUT, where, "the block is not convex, and its surface "
                        "intersects itself (faces %d and %d cross, counted from 1 in the order of its "
                        "\"face\" dict); fix the block", m->face_id[f1], m->face_id[f2]);
        else
            cn_diag_set(diag, CN_ERR_INPUT, where, "the block is not convex (raise --tolerance if "
                        "its faces are only warped), and its surface %s", cn_mesh_split_why(r));
        goto done;
    }
    out = json_array();
    for (int i = 0; out && i < mp.n; i++) {
        json_t *piece = json_array();
        for (int v = 0; piece && v < mp.lens[i]; v++)
            json_array_append_new(piece, json_pack("[f,f,f]", mp.pts[i][v][0], mp.pts[i][v][1], mp.pts[i][v][2]));
        json_array_append_new(out, piece);
    }
done:
    cn_mesh_pieces_free(&mp);
    return out;
}

/* One block's shape: {"hull": its vertices} (in the order of the mesh's dict) when it is convex
 * (every vertex on the inner side of every face's plane, by its Newell normal through its
 * centroid, within tol of the block's size), else {"hulls": its exact convex pieces}. NULL with
 * the diagnostic set. */
static json_t *block_shape(const json_t *mesh, const char *where, double rel_tol, cnDiag *diag) {
    const json_t *verts = json_object_get(mesh, "vertex"), *faces = json_object_get(mesh, "face");
    const json_t *vdef = json_object_get(mesh, "default_vertex_attributes");
    if (!json_is_object(verts) || !json_is_object(faces) || json_object_size(verts) < 4) {
        cn_diag_set(diag, CN_ERR_INPUT, where, "expected a COMPAS mesh with a \"vertex\" dict (at least 4) and a \"face\" dict");
        return NULL;
    }
    size_t n = json_object_size(verts);
    double(*x)[3] = cn_calloc(n, sizeof(double[3]));
    const char **keys = cn_calloc(n, sizeof(char *));
    json_t *pts = json_array();
    if (!x || !keys || !pts) {
        cn_free(x), cn_free(keys), json_decref(pts);
        cn_diag_set(diag, CN_ERR_MEMORY, where, "out of memory");
        return NULL;
    }
    size_t i = 0;
    const char *key;
    json_t *v;
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    json_object_foreach((json_t *)verts, key, v) {
        keys[i] = key;
        for (int k = 0; k < 3; k++) {
            const char *axis = k == 0 ? "x" : k == 1 ? "y" : "z";
            json_t *c = json_object_get(v, axis);
            if (!c) c = json_object_get(vdef, axis);
            if (!json_is_number(c) || !isfinite(json_number_value(c))) {
                cn_diag_set(diag, CN_ERR_INPUT, where, "vertex '%s' has no finite %s", key, axis);
                cn_free(x), cn_free(keys), json_decref(pts);
                return NULL;
            }
            if (fabs(json_number_value(c)) > CN_MAX_COORD) {
                cn_diag_set(diag, CN_ERR_INPUT, where, "vertex '%s': %s = %g is beyond the coordinates cairn computes "
                            "with (magnitude up to %g); scale the file", key, axis, json_number_value(c), CN_MAX_COORD);
                cn_free(x), cn_free(keys), json_decref(pts);
                return NULL;
            }
            x[i][k] = json_number_value(c);
            lo[k] = fmin(lo[k], x[i][k]), hi[k] = fmax(hi[k], x[i][k]);
        }
        json_array_append_new(pts, json_pack("[f,f,f]", x[i][0], x[i][1], x[i][2]));
        i++;
    }
    double size = sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) + (hi[2] - lo[2]) * (hi[2] - lo[2]));
    double tol = fmax(rel_tol, 1e-6) * size;
    /* the faces as index loops, checked */
    size_t nf = json_object_size(faces), ni = 0;
    json_t *f;
    json_object_foreach((json_t *)faces, key, f) ni += json_array_size(f);
    int *start = cn_malloc(sizeof(int) * (nf + 1)), *idx = cn_malloc(sizeof(int) * (ni + 1));
    if (!start || !idx) {
        cn_free(x), cn_free(keys), cn_free(start), cn_free(idx), json_decref(pts);
        cn_diag_set(diag, CN_ERR_MEMORY, where, "out of memory");
        return NULL;
    }
    size_t fi = 0, k = 0;
    json_object_foreach((json_t *)faces, key, f) {
        size_t m = json_array_size(f);
        bool ok = json_is_array(f) && m >= 3;
        start[fi] = (int)k;
        for (size_t a = 0; ok && a < m; a++) {
            json_t *e = json_array_get(f, a);
            char kb[32];
            if (json_is_integer(e)) snprintf(kb, sizeof kb, "%lld", (long long)json_integer_value(e));
            else ok = false;
            int found = -1;
            for (size_t b = 0; ok && b < n && found < 0; b++)
                if (!strcmp(keys[b], kb)) found = (int)b;
            if (found < 0) ok = false;
            else idx[k++] = found;
        }
        if (!ok) {
            cn_diag_set(diag, CN_ERR_INPUT, where, "face '%s' is not a loop of 3 or more of the mesh's vertex keys", key);
            cn_free(x), cn_free(keys), cn_free(start), cn_free(idx), json_decref(pts);
            return NULL;
        }
        fi++;
    }
    start[fi] = (int)k;
    /* the surface closed, consistently oriented, enclosing a volume (turned to point out), as
     * a mesh part's; a convex block's surface too: its hull would hide a missing face */
    cnMesh m = {.nverts = (int)n, .nfaces = (int)nf, .verts = cn_malloc(sizeof(double[3]) * (n + 1)),
                .start = start, .idx = idx, .face_id = cn_malloc(sizeof(int) * (nf + 1))};
    if (!m.verts || !m.face_id) {
        cn_mesh_free(&m), cn_free(x), cn_free(keys), json_decref(pts);
        cn_diag_set(diag, CN_ERR_MEMORY, where, "out of memory");
        return NULL;
    }
    memcpy(m.verts, x, sizeof(double[3]) * n);
    for (size_t g = 0; g < nf; g++) m.face_id[g] = (int)g + 1;
    if (cn_mesh_check(&m, tol, diag) != CN_OK) {
        char msg[sizeof diag->message];
        snprintf(msg, sizeof msg, "%s", diag->message);
        cn_diag_set(diag, diag->code, where, "the block %s (faces counted from 1 in the order of its "
                    "\"face\" dict)", msg);
        cn_mesh_free(&m), cn_free(x), cn_free(keys), json_decref(pts);
        return NULL;
    }
    bool convex = true;
    for (int g = 0; g < m.nfaces && convex; g++) {
        int nv = m.start[g + 1] - m.start[g];
        double nrm[3] = {0, 0, 0}, c[3] = {0, 0, 0};
        for (int a = 0; a < nv; a++) { /* Newell */
            const double *p = m.verts[m.idx[m.start[g] + a]], *q = m.verts[m.idx[m.start[g] + (a + 1) % nv]];
            nrm[0] += (p[1] - q[1]) * (p[2] + q[2]);
            nrm[1] += (p[2] - q[2]) * (p[0] + q[0]);
            nrm[2] += (p[0] - q[0]) * (p[1] + q[1]);
            for (int d = 0; d < 3; d++) c[d] += p[d] / (double)nv;
        }
        double L = cn_norm3(nrm);
        for (size_t b = 0; b < n && convex; b++) {
            double d[3];
            cn_sub3(x[b], c, d);
            if (cn_dot3(d, nrm) / L > tol) convex = false;
        }
    }
    cn_free(x), cn_free(keys);
    if (!convex) { /* its exact convex pieces: "hulls" */
        json_decref(pts);
        pts = decompose(&m, where, tol, diag);
        cn_mesh_free(&m);
        return pts ? json_pack("{s:o}", "hulls", pts) : NULL;
    }
    cn_mesh_free(&m);
    return json_pack("{s:o}", "hull", pts);
}

json_t *cn_compas_to_cairn(const json_t *root, const char *supports, double rel_tol, cnDiag *diag) {
    const json_t *graph = json_object_get(json_object_get(json_object_get(root, "data"), "graph"), "data");
    const json_t *nodes = json_object_get(graph, "node"), *defaults = json_object_get(graph, "default_node_attributes");
    if (!json_is_object(nodes)) {
        cn_diag_set(diag, CN_ERR_INPUT, "data.graph.data.node", "a COMPAS assembly needs its graph's nodes (a dict)");
        return NULL;
    }
    json_t *doc = json_object(), *parts = json_array();
    const char *name = json_string_value(json_object_get(json_object_get(json_object_get(root, "data"), "attributes"), "name"));
    json_object_set_new(doc, "name", json_string(name ? name : "COMPAS assembly"));
    json_object_set_new(doc, "dimension", json_integer(3));
    json_object_set_new(doc, "parts", parts);
    const char *key;
    json_t *node;
    int nsup = 0;
    json_object_foreach((json_t *)nodes, key, node) {
        int at, code = cn_control_char(key, &at); /* keys name the parts */
        if (code >= 0) {
            cn_diag_set(diag, CN_ERR_INPUT, "data.graph.data.node",
                        "a node key contains a control character (code %d at byte %d); keys name the parts: "
                        "use printable characters", code, at);
            json_decref(doc);
            return NULL;
        }
        char where[256];
        snprintf(where, sizeof where, "data.graph.data.node.%s.block", key);
        const json_t *block = attr(node, defaults, "block");
        const json_t *mesh = json_object_get(block, "data");
        json_t *shape = mesh ? block_shape(mesh, where, rel_tol, diag) : NULL;
        if (!shape) {
            if (!mesh) cn_diag_set(diag, CN_ERR_INPUT, where, "the node has no block (a COMPAS mesh)");
            json_decref(doc);
            return NULL;
        }
        const json_t *is_sup = attr(node, defaults, "is_support");
        if (!supports && is_sup && !json_is_boolean(is_sup) && !json_is_null(is_sup)) {
            char w[256];
            snprintf(w, sizeof w, "data.graph.data.node.%s.is_support", key);
            cn_diag_set(diag, CN_ERR_INPUT, w, "expected true or false (whether the block is a support)");
            json_decref(shape);
            json_decref(doc);
            return NULL;
        }
        bool sup = supports ? listed(supports, key) : json_is_true(is_sup);
        nsup += sup;
        json_object_set_new(shape, "name", json_string(key));
        json_object_set_new(shape, "fixed", json_boolean(sup));
        json_array_append_new(parts, shape);
    }
    /* every key of --supports must be a node */
    for (const char *p = supports, *q; p && *p; p = q) {
        size_t m;
        q = next_key(p, &m);
        if (!json_object_getn(nodes, p, m)) {
            cn_diag_set(diag, CN_ERR_INPUT, "--supports", "no node '%.*s' in the COMPAS assembly; its keys are those of data.graph.data.node", (int)m, p);
            json_decref(doc);
            return NULL;
        }
    }
    if (nsup == 0) {
        cn_diag_set(diag, CN_ERR_INPUT, "--supports",
                    "no block of this COMPAS assembly is a support (no node has is_support); name the supports' node "
                    "keys with --supports KEY,... (e.g. --supports 0)");
        json_decref(doc);
        return NULL;
    }
    return doc;
}
