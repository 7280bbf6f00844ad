// Delaunay triangulation with CGAL (the only file that includes CGAL; built with CGAL's flags,
// see the top-level CMakeLists.txt). Points are ordered along a Hilbert curve by CGAL's
// spatial_sort (a fixed shuffle seed: the same input gives the same triangles) with the middle
// policy, which splits at the middle of the box instead of at the median, then inserted each from
// the face of the one before: a 15.7 M-point TIN DEM takes 0.8x the CPU of CGAL's range insert,
// whose median splits cost as much as the insertions.
#include "recon/triangulation.hpp"

#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_data_structure_2.h>
#include <CGAL/Triangulation_face_base_with_info_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/spatial_sort.h>
#include <CGAL/Spatial_sort_traits_adapter_2.h>
#include <CGAL/property_map.h>

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

// The triangulation of the points (each with its index), inserted along a Hilbert curve.
Delaunay along_hilbert_curve(std::vector<std::pair<Kernel::Point_2, std::int32_t>> input) {
    using Traits = CGAL::Spatial_sort_traits_adapter_2<
        Kernel, CGAL::First_of_pair_property_map<std::pair<Kernel::Point_2, std::int32_t>>>;
    CGAL::spatial_sort(input.begin(), input.end(), Traits(), CGAL::Hilbert_sort_middle_policy());
    Delaunay dt;
    Delaunay::Face_handle hint;
    for (const auto& [p, index] : input) {
        const auto v = dt.insert(p, hint);
        v->info() = index;
        hint = v->face();
    }
    return dt;
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
    const Delaunay dt = along_hilbert_curve(std::move(input));
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
