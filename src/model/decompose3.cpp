/* Exact convex decomposition of a closed polyhedral mesh (CGAL's Nef polyhedra), behind a C
 * interface (mesh3.h). The only C++ in cairn: CGAL is a header library of templates. */
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Nef_polyhedron_3.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Polyhedron_3.h>
#include <CGAL/convex_decomposition_3.h>

#include <cstdlib>
#include <exception>
#include <functional>
#include <new>
#include <utility>
#include <vector>

extern "C" {
#include "mesh3.h"
}

typedef CGAL::Exact_predicates_exact_constructions_kernel K;
typedef CGAL::Polyhedron_3<K> Poly;
typedef CGAL::Nef_polyhedron_3<K> Nef;
namespace PMP = CGAL::Polygon_mesh_processing;

extern "C" int cn_mesh_decompose(const cnMesh *m, cnMeshPieces *out, int *face1, int *face2) {
    out->n = 0;
    out->lens = NULL;
    out->pts = NULL;
    *face1 = *face2 = -1;
    try {
        /* the vertices the faces use (welding leaves the others unused), renumbered */
        std::vector<K::Point_3> pts;
        std::vector<long> to(static_cast<std::size_t>(m->nverts), -1);
        std::vector<std::vector<std::size_t>> faces;
        for (int f = 0; f < m->nfaces; f++) {
            std::vector<std::size_t> face;
            for (int k = m->start[f]; k < m->start[f + 1]; k++) {
                std::size_t v = (std::size_t)m->idx[k];
                if (to[v] < 0) {
                    to[v] = (long)pts.size();
                    pts.emplace_back(m->verts[v][0], m->verts[v][1], m->verts[v][2]);
                }
                face.push_back((std::size_t)to[v]);
            }
            faces.push_back(face);
        }
        if (!PMP::is_polygon_soup_a_polygon_mesh(faces)) return 5;
        Poly poly;
        PMP::polygon_soup_to_polygon_mesh(pts, faces, poly);
        if (!poly.is_valid() || !poly.is_closed()) return 2;
        PMP::triangulate_faces(poly);
        /* faces of the triangulated mesh: which input face each came from is not kept, so a
         * self-intersection is named by its triangles' first vertices' input faces below */
        std::vector<std::pair<Poly::Facet_const_handle, Poly::Facet_const_handle>> hits;
        PMP::self_intersections(poly, std::back_inserter(hits));
        if (!hits.empty()) {
            /* the input faces that hold both triangles' vertices */
            auto face_of = [&](Poly::Facet_const_handle fh) {
                std::vector<std::size_t> vs;
                auto h = fh->facet_begin();
                do {
                    const K::Point_3 &p = h->vertex()->point();
                    for (std::size_t i = 0; i < pts.size(); i++)
                        if (pts[i] == p) { vs.push_back(i); break; }
                } while (++h != fh->facet_begin());
                for (int f = 0; f < m->nfaces; f++) {
                    int found = 0;
                    for (std::size_t v : vs)
                        for (int k = m->start[f]; k < m->start[f + 1]; k++)
                            if ((std::size_t)to[(std::size_t)m->idx[k]] == v) { found++; break; }
                    if (found == (int)vs.size()) return f;
                }
                return -1;
            };
            *face1 = face_of(hits[0].first);
            *face2 = face_of(hits[0].second);
            return 3;
        }
        /* the decomposition's time grows with the cube of the concave edges (docs/bench.md,
           section 10): refused past CN_MESH_SPLIT_MAX_REFLEX */
        long reflex = 0;
        for (auto h = poly.halfedges_begin(); h != poly.halfedges_end(); ++h) {
            if (h->is_border() || h->opposite()->is_border() || std::less<const void *>()(&*h->opposite(), &*h)) continue;
            const K::Point_3 &a = h->opposite()->vertex()->point(), &b = h->vertex()->point();
            const K::Point_3 &c = h->next()->vertex()->point(), &d = h->opposite()->next()->vertex()->point();
            if (CGAL::orientation(a, b, c, d) == CGAL::POSITIVE) reflex++;
        }
        if (reflex > CN_MESH_SPLIT_MAX_REFLEX) return 9;
        const K::FT whole = PMP::volume(poly); /* exact, as triangulated */
        Nef nef(poly);
        CGAL::convex_decomposition_3(nef);
        std::vector<std::vector<double>> pieces;
        K::FT sum = 0;
        for (auto ci = ++nef.volumes_begin(); ci != nef.volumes_end(); ++ci) {
            if (!ci->mark()) continue;
            Poly piece;
            nef.convert_inner_shell_to_polyhedron(ci->shells_begin(), piece);
            Poly tri = piece;
            PMP::triangulate_faces(tri);
            sum += PMP::volume(tri); /* the piece's outer shell only: a cavity is left out */
            std::vector<double> xyz;
            for (auto v = piece.vertices_begin(); v != piece.vertices_end(); ++v) {
                xyz.push_back(CGAL::to_double(v->point().x()));
                xyz.push_back(CGAL::to_double(v->point().y()));
                xyz.push_back(CGAL::to_double(v->point().z()));
            }
            pieces.push_back(xyz);
        }
        /* the pieces fill the solid exactly, unless a volume has more than one shell (a cavity)
         * or the surface nests shells: then they would not add up */
        if (CGAL::abs(CGAL::to_double(sum - whole)) > 1e-9 * CGAL::abs(CGAL::to_double(whole))) return 7;
        int n = (int)pieces.size();
        out->lens = (int *)calloc((size_t)n + 1, sizeof(int));
        out->pts = (double (**)[3])calloc((size_t)n + 1, sizeof(double (*)[3]));
        if (!out->lens || !out->pts) {
            cn_mesh_pieces_free(out);
            return -1;
        }
        out->n = n;
        for (int i = 0; i < n; i++) {
            int len = (int)(pieces[(size_t)i].size() / 3);
            out->pts[i] = (double (*)[3])malloc(sizeof(double[3]) * (size_t)(len + 1));
            if (!out->pts[i]) {
                cn_mesh_pieces_free(out);
                return -1;
            }
            out->lens[i] = len;
            for (int k = 0; k < len; k++)
                for (int d = 0; d < 3; d++) out->pts[i][k][d] = pieces[(size_t)i][(size_t)(3 * k + d)];
        }
        return 0;
    } catch (const std::bad_alloc &) {
        cn_mesh_pieces_free(out);
        return -1;
    } catch (const std::exception &) {
        cn_mesh_pieces_free(out);
        return 4;
    } catch (...) {
        cn_mesh_pieces_free(out);
        return 4;
    }
}
