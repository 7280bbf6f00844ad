// Trees: where they grow (forest mask, river banks, field edges, gardens, open land), their
// species and size, and the crown surfaces (a cone for conifers, a half-ellipsoid otherwise).
#include "synth/vegetation.hpp"

#include <algorithm>
#include <cmath>

#include "core/random.hpp"
#include "synth/buildings.hpp"

namespace lidarscout::synth {
namespace {

enum Stream : std::uint64_t { kTree = 401 };

enum class Habitat { None, Forest, River, Hedge, Garden, Open };

void size_tree(Tree& t, Rng& rng, Habitat habitat) {
    switch (habitat) {
        case Habitat::Forest:
            t.height = t.conifer ? rng.uniform(16, 30) : rng.uniform(14, 26);
            break;
        case Habitat::River: t.height = rng.uniform(7, 18); break;
        case Habitat::Hedge: t.height = rng.chance(0.6) ? rng.uniform(2, 5) : rng.uniform(6, 13); break;
        case Habitat::Garden: t.height = rng.uniform(4, 12); break;
        default: t.height = rng.uniform(9, 20); break;
    }
    if (t.conifer) {
        t.crown_radius = t.height * rng.uniform(0.13, 0.17);
        t.crown_depth = t.height * rng.uniform(0.6, 0.8);
    } else {
        t.crown_radius = std::max(1.0, t.height * rng.uniform(0.18, 0.26));
        t.crown_depth = t.height * rng.uniform(0.45, 0.65);
    }
    t.crown_radius = std::min(t.crown_radius, kTreeCell - 0.5);
}

void colour_tree(Tree& t, Rng& rng) {
    const Rgb base = base_colour(t.conifer ? Material::Needles : Material::Leaves);
    const double bright = rng.uniform(0.8, 1.2);
    t.colour = {base.r * bright * rng.uniform(0.9, 1.12), base.g * bright * rng.uniform(0.94, 1.06),
                base.b * bright * rng.uniform(0.9, 1.1)};
}

// Whether a building stands within `reach` metres of (x, y).
bool near_building(const TerrainModel& model, double x, double y, double reach,
                   const std::vector<const Village*>& villages) {
    if (villages.empty()) return false;  // buildings outside villages stand by the roads, cleared anyway
    const Area& area = model.area();
    const auto i0 = static_cast<std::int64_t>(std::floor((x - reach - area.x0) / kBuildingCell));
    const auto i1 = static_cast<std::int64_t>(std::floor((x + reach - area.x0) / kBuildingCell));
    const auto j0 = static_cast<std::int64_t>(std::floor((y - reach - area.y0) / kBuildingCell));
    const auto j1 = static_cast<std::int64_t>(std::floor((y + reach - area.y0) / kBuildingCell));
    for (auto j = j0; j <= j1; ++j) {
        for (auto i = i0; i <= i1; ++i) {
            const auto b = building_in_cell(model, i, j, villages);
            if (b && b->covers(x, y, reach)) return true;
        }
    }
    return false;
}

// The forest value at (x, y): the land cover's mask, kept out of the river's banks and the
// villages' clearings.
double forest_at(const TerrainModel& model, double x, double y, const std::vector<const Village*>& villages) {
    const RiverRow river = model.relief().river(y);
    const double v = model.land().forest(x, y, model.relief().ground(x, y, river) - river.water_level);
    if (v <= 0) return v;
    if (river.distance(x) < river.half_width + 25 || in_clearing(model, x, y, villages)) return -0.05;
    return v;
}

}  // namespace

double Tree::crown_z(double px, double py, double& r2, double& nx, double& ny) const {
    const double dx = px - x, dy = py - y;
    r2 = (dx * dx + dy * dy) / (crown_radius * crown_radius);
    if (r2 >= 1.0) return -1.0;
    const double top = base_z + height;
    if (conifer) {
        const double r = std::sqrt(r2);
        const double slope = crown_depth / crown_radius;
        const double n = std::sqrt(1 + slope * slope);
        const double inv = r > 1e-9 ? 1.0 / (r * crown_radius) : 0.0;
        nx = slope * dx * inv / n;
        ny = slope * dy * inv / n;
        return top - crown_depth * r;
    }
    // Half-ellipsoid with vertical semi-axis c = crown_depth / 2 on top of the crown's middle.
    const double c = 0.5 * crown_depth;
    const double h = std::sqrt(1 - r2);
    const double gx = dx / (crown_radius * crown_radius), gy = dy / (crown_radius * crown_radius);
    const double gz = h / c;  // gradient of the ellipsoid's implicit function, up to a factor
    const double n = std::sqrt(gx * gx + gy * gy + gz * gz);
    nx = gx / n;
    ny = gy / n;
    return top - c + c * h;
}

TreeCell tree_in_cell(const TerrainModel& model, std::int64_t i, std::int64_t j,
                      const std::vector<const Village*>& villages) {
    const Area& area = model.area();
    Rng rng(hash_of(model.seed(), kTree, i, j));
    Tree t;
    t.x = area.x0 + (i + rng.uniform(0.1, 0.9)) * kTreeCell;
    t.y = area.y0 + (j + rng.uniform(0.1, 0.9)) * kTreeCell;
    const auto& relief = model.relief();
    const RiverRow river = relief.river(t.y);
    const double d = river.distance(t.x);
    t.base_z = relief.ground(t.x, t.y, river);

    TreeCell cell;
    cell.forest = forest_at(model, area.x0 + (i + 0.5) * kTreeCell, area.y0 + (j + 0.5) * kTreeCell, villages);
    bool in_village = false;
    settlement_weight(t.x, t.y, villages, in_village);
    Habitat habitat = Habitat::None;
    if (d < river.half_width + 2) habitat = Habitat::None;
    else if (cell.forest > 0) habitat = rng.chance(0.85) ? Habitat::Forest : Habitat::None;
    else if (d < river.half_width + 28) habitat = rng.chance(0.5) ? Habitat::River : Habitat::None;
    else if (in_village) habitat = rng.chance(0.1) ? Habitat::Garden : Habitat::None;
    else if (model.land().field(t.x, t.y).edge_distance < 3.5)
        habitat = rng.chance(0.4) ? Habitat::Hedge : Habitat::None;
    else habitat = rng.chance(0.012) ? Habitat::Open : Habitat::None;
    if (habitat == Habitat::None) return cell;

    t.conifer = habitat == Habitat::Forest && model.land().conifer(t.x, t.y) > 0;
    size_tree(t, rng, habitat);
    colour_tree(t, rng);
    const auto& layout = model.layout();
    if (layout.road(t.x, t.y, river, layout.main_road(t.x), villages).clearance() < 1.0) return cell;
    if (near_building(model, t.x, t.y, t.crown_radius + 1.0, villages)) return cell;
    cell.tree = t;
    return cell;
}

}  // namespace lidarscout::synth
