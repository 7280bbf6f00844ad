// Sampling the landscape point by point over a rectangle (one tile plus a margin): the
// ground on a 1 m lattice (bilinear in between), the river and main road interpolated
// between whole metres, and the buildings and trees of the cells that touch the rectangle,
// all computed once. A point's answer depends only on the model and the point, never on the
// rectangle that sampled it, so tiles agree where they meet.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "synth/buildings.hpp"
#include "synth/materials.hpp"
#include "synth/terrain_model.hpp"
#include "synth/vegetation.hpp"

namespace lidarscout::synth {

// ASPRS classes used by the generator.
namespace cls {
inline constexpr std::uint8_t kGround = 2, kLowVegetation = 3, kMediumVegetation = 4, kHighVegetation = 5,
                              kBuilding = 6, kWater = 9, kRoadSurface = 11, kBridgeDeck = 17;
}

enum class Top : std::uint8_t { None, Roof, Canopy };

// What a vertical line through (x, y) meets, from the top down.
struct Column {
    double ground_z = 0;  // the lowest surface: terrain, water, road or bridge deck
    std::uint8_t ground_class = cls::kGround;
    Material ground_material = Material::Meadow;
    Top top = Top::None;  // an object above the ground
    double top_z = 0;     // roof or crown surface
    double crown_bottom = 0;
    double crown_r2 = 0;  // (distance from the trunk / crown radius)^2
    Material top_material = Material::Meadow;
    Rgb colour;           // of the topmost surface, as an orthophoto shows it
};

// The values of a lattice of cells over a rectangle of cells [i0, i1] x [j0, j1], computed
// once per patch (trees, buildings) and looked up by cell index.
template <typename T>
struct CellCache {
    std::int64_t i0 = 0, j0 = 0, width = 0;
    std::vector<T> values;

    template <typename Fn>  // Fn: (i, j) -> T
    void fill(std::int64_t first_i, std::int64_t first_j, std::int64_t last_i, std::int64_t last_j, Fn value_of) {
        i0 = first_i;
        j0 = first_j;
        width = last_i - first_i + 1;
        values.clear();
        values.reserve(static_cast<std::size_t>(width * (last_j - first_j + 1)));
        for (std::int64_t j = first_j; j <= last_j; ++j) {
            for (std::int64_t i = first_i; i <= last_i; ++i) values.push_back(value_of(i, j));
        }
    }
    const T& at(std::int64_t i, std::int64_t j) const {
        return values[static_cast<std::size_t>((j - j0) * width + (i - i0))];
    }
};

class TerrainPatch {
public:
    // Covers [x0, x1] x [y0, y1]; columns outside it are an error.
    TerrainPatch(const TerrainModel& model, double x0, double y0, double x1, double y1);

    Column column(double x, double y) const;
    // The terrain height (the 1 m lattice, bilinear), without water, roads or objects.
    double ground(double x, double y) const;

private:
    void fill_lattice(double x0, double y0, double x1, double y1);
    void fill_trees(double x0, double y0, double x1, double y1);
    void fill_buildings(double x0, double y0, double x1, double y1);

    struct Cell {
        double z00, z10, z01, z11, fx, fy;
    };
    Cell lattice_cell(double x, double y) const;
    RiverRow river_at(double y) const;
    MainRoadColumn main_road_at(double x) const;
    const TreeCell& tree_cell(std::int64_t i, std::int64_t j) const;
    const std::optional<Building>& building_cell(std::int64_t i, std::int64_t j) const;
    bool near_building(double x, double y, double margin) const;
    bool in_village(double x, double y) const;
    double forest(double x, double y) const;  // the forest mask, smooth between tree cells
    void ground_surface(Column& c, double x, double y) const;
    void objects(Column& c, double x, double y) const;
    Rgb ground_colour(const Column& c, double x, double y, double gx, double gy, const FieldSample* field) const;

    const TerrainModel& model_;
    std::vector<const Village*> villages_;
    std::int64_t lx0_, ly0_, lw_, lh_;  // lattice origin (whole metres) and size
    std::vector<double> heights_;
    std::vector<RiverRow> river_rows_;
    std::vector<MainRoadColumn> road_columns_;
    CellCache<TreeCell> trees_;
    CellCache<std::optional<Building>> buildings_;
};

}  // namespace lidarscout::synth
