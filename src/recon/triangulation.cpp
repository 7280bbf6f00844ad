// Delaunay triangulation with CGAL (the only file that includes CGAL; built with CGAL's flags,
// see the top-level CMakeLists.txt). Points are inserted as a range, which CGAL orders along a
// space-filling curve with a fixed shuffle seed: the same input gives the same triangles.
#include "recon/triangulation.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <utility>

#include "core/error.hpp"

namespace lidarscout::recon {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using VertexBase = CGAL::Triangulation_vertex_base_with_info_2<std::int32_t, Kernel>;
using FaceBase = CGAL::Triangulation_face_base_with_info_2<std::int32_t, Kernel>;
using Tds = CGAL::Triangulation_data_structure_2<VertexBase, FaceBase>;
using Delaunay = CGAL::Delaunay_triangulation_2<Kernel, Tds>;

// The chunk points, then (with `pad_corners`) the window corners that no chunk point occupies.
std::vector<GridXY> with_padding(std::span<const GridXY> points, std::int64_t extent, bool pad_corners) {
    const double e = static_cast<double>(extent);
    std::vector<GridXY> out(points.begin(), points.end());
    for (const GridXY& p : points) {
        if (!(p.x >= 0.0 && p.x <= e && p.y >= 0.0 && p.y <= e)) {
            throw Error::in_stage("recon", "triangulation point outside the window");
        }
    }
    if (!pad_corners) return out;
    for (const GridXY corner : {GridXY{0, 0}, GridXY{e, 0}, GridXY{e, e}, GridXY{0, e}}) {
        bool taken = false;
        for (const GridXY& p : points) taken = taken || p == corner;
        if (!taken) out.push_back(corner);
    }
    return out;
}

}  // namespace

Triangulation triangulate(std::span<const GridXY> points, std::int64_t extent, bool pad_corners) {
    Triangulation out;
    out.vertices = with_padding(points, extent, pad_corners);
    out.real_count = points.size();

    std::vector<std::pair<Kernel::Point_2, std::int32_t>> input;
    input.reserve(out.vertices.size());
    for (std::size_t i = 0; i < out.vertices.size(); ++i) {
        input.emplace_back(Kernel::Point_2(out.vertices[i].x, out.vertices[i].y), static_cast<std::int32_t>(i));
    }
    Delaunay dt;
    dt.insert(input.begin(), input.end());
    if (dt.number_of_vertices() != out.vertices.size()) {
        throw Error::in_stage("recon", "triangulation input has repeated positions");
    }

    std::int32_t next = 0;
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) f->info() = next++;
    out.triangles.reserve(next);
    out.neighbours.reserve(next);
    for (auto f = dt.finite_faces_begin(); f != dt.finite_faces_end(); ++f) {
        std::array<std::int32_t, 3> tri{}, nb{};
        for (int k = 0; k < 3; ++k) {
            tri[k] = f->vertex(k)->info();
            const auto n = f->neighbor(k);
            nb[k] = dt.is_infinite(n) ? -1 : n->info();
        }
        out.triangles.push_back(tri);
        out.neighbours.push_back(nb);
    }
    return out;
}

Triangulation triangulate(const PatchPoints& patch) {
    return triangulate(grid_positions(patch), patch.spec.grid_extent());
}

}  // namespace lidarscout::recon
