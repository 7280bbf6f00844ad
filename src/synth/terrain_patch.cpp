// TerrainPatch: the caches (lattice, river rows, road columns, tree and building cells) and
// the column of a point: ground surface and its colour, then a roof or a tree crown on top.
#include "synth/terrain_patch.hpp"

#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "core/random.hpp"
#include "synth/noise.hpp"

namespace lidarscout::synth {
namespace {

enum Stream : std::uint64_t { kTint = 501 };
constexpr double kGardenWidth = 10.0;  // lawn around buildings, metres

// Light from the north-west, 50 degrees above the horizon (a unit vector).
constexpr double kSunX = -0.45, kSunY = 0.45, kSunZ = 0.7714;

double lerp(double a, double b, double t) { return a + (b - a) * t; }

// Brightness of a surface with unit normal (nx, ny, nz) under the sun (1 for flat ground).
double shade(double nx, double ny, double nz) {
    return std::clamp(0.62 + 0.5 * (nx * kSunX + ny * kSunY + nz * kSunZ), 0.3, 1.25);
}

double shade_of_gradient(double gx, double gy) {
    const double n = std::sqrt(gx * gx + gy * gy + 1);
    return shade(-gx / n, -gy / n, 1 / n);
}

double shade_of_normal(double nx, double ny) { return shade(nx, ny, std::sqrt(std::max(0.0, 1 - nx * nx - ny * ny))); }

bool is_crop(Material m) {
    return m == Material::Wheat || m == Material::Soil || m == Material::YoungCrop || m == Material::Maize ||
           m == Material::Rapeseed;
}

// Lane markings of the main road (edge lines and a dashed centre line) and the valley road
// (dashed centre line).
bool is_marking(const RoadHit& road) {
    const bool dash = road.along / 12.0 - std::floor(road.along / 12.0) < 0.4;
    if (road.kind == RoadKind::Main) {
        return (road.offset < 0.08 && dash) || std::fabs(road.offset - (road.half_width - 0.35)) < 0.08;
    }
    return road.kind == RoadKind::Valley && road.offset < 0.07 && dash;
}

std::int64_t cell_index(double v, double origin, double size) {
    return static_cast<std::int64_t>(std::floor((v - origin) / size));
}

}  // namespace

TerrainPatch::TerrainPatch(const TerrainModel& model, double x0, double y0, double x1, double y1) : model_(model) {
    villages_ = model.layout().villages_near(x0, y0, x1, y1, 3 * kBuildingCell);
    fill_lattice(x0, y0, x1, y1);
    fill_trees(x0, y0, x1, y1);
    fill_buildings(x0, y0, x1, y1);
}

void TerrainPatch::fill_lattice(double x0, double y0, double x1, double y1) {
    const auto& relief = model_.relief();
    lx0_ = static_cast<std::int64_t>(std::floor(x0)) - 1;
    ly0_ = static_cast<std::int64_t>(std::floor(y0)) - 1;
    lw_ = static_cast<std::int64_t>(std::ceil(x1)) + 2 - lx0_;
    lh_ = static_cast<std::int64_t>(std::ceil(y1)) + 2 - ly0_;
    river_rows_.resize(static_cast<std::size_t>(lh_));
    road_columns_.resize(static_cast<std::size_t>(lw_));
    heights_.resize(static_cast<std::size_t>(lw_ * lh_));
    for (std::int64_t i = 0; i < lw_; ++i) road_columns_[i] = model_.layout().main_road(static_cast<double>(lx0_ + i));
    for (std::int64_t j = 0; j < lh_; ++j) {
        const double y = static_cast<double>(ly0_ + j);
        river_rows_[j] = relief.river(y);
        for (std::int64_t i = 0; i < lw_; ++i) {
            heights_[j * lw_ + i] = relief.ground(static_cast<double>(lx0_ + i), y, river_rows_[j]);
        }
    }
}

void TerrainPatch::fill_trees(double x0, double y0, double x1, double y1) {
    const Area& area = model_.area();  // a margin of one cell: crowns reach across
    trees_.fill(cell_index(x0, area.x0, kTreeCell) - 1, cell_index(y0, area.y0, kTreeCell) - 1,
                cell_index(x1, area.x0, kTreeCell) + 1, cell_index(y1, area.y0, kTreeCell) + 1,
                [&](std::int64_t i, std::int64_t j) { return tree_in_cell(model_, i, j, villages_); });
}

void TerrainPatch::fill_buildings(double x0, double y0, double x1, double y1) {
    const Area& area = model_.area();  // a margin of one cell for gardens
    buildings_.fill(cell_index(x0, area.x0, kBuildingCell) - 1, cell_index(y0, area.y0, kBuildingCell) - 1,
                    cell_index(x1, area.x0, kBuildingCell) + 1, cell_index(y1, area.y0, kBuildingCell) + 1,
                    [&](std::int64_t i, std::int64_t j) { return building_in_cell(model_, i, j, villages_); });
}

TerrainPatch::Cell TerrainPatch::lattice_cell(double x, double y) const {
    const double fx = std::floor(x), fy = std::floor(y);
    const std::int64_t i = static_cast<std::int64_t>(fx) - lx0_, j = static_cast<std::int64_t>(fy) - ly0_;
    if (i < 0 || j < 0 || i + 1 >= lw_ || j + 1 >= lh_) throw Error("internal: terrain sampled outside its patch");
    const double* row = &heights_[static_cast<std::size_t>(j * lw_ + i)];
    return {row[0], row[1], row[lw_], row[lw_ + 1], x - fx, y - fy};
}

double TerrainPatch::ground(double x, double y) const {
    const Cell c = lattice_cell(x, y);
    return lerp(lerp(c.z00, c.z10, c.fx), lerp(c.z01, c.z11, c.fx), c.fy);
}

RiverRow TerrainPatch::river_at(double y) const {
    const double fy = std::floor(y);
    const std::int64_t j = static_cast<std::int64_t>(fy) - ly0_;
    const RiverRow& a = river_rows_[static_cast<std::size_t>(j)];
    const RiverRow& b = river_rows_[static_cast<std::size_t>(j + 1)];
    const double t = y - fy;
    return {lerp(a.centre, b.centre, t), lerp(a.half_width, b.half_width, t), lerp(a.water_level, b.water_level, t),
            lerp(a.cos_slope, b.cos_slope, t)};
}

MainRoadColumn TerrainPatch::main_road_at(double x) const {
    const double fx = std::floor(x);
    const std::int64_t i = static_cast<std::int64_t>(fx) - lx0_;
    const MainRoadColumn& a = road_columns_[static_cast<std::size_t>(i)];
    const MainRoadColumn& b = road_columns_[static_cast<std::size_t>(i + 1)];
    const double t = x - fx;
    return {lerp(a.centre, b.centre, t), lerp(a.cos_slope, b.cos_slope, t)};
}

const TreeCell& TerrainPatch::tree_cell(std::int64_t i, std::int64_t j) const {
    return trees_.at(i, j);
}

const std::optional<Building>& TerrainPatch::building_cell(std::int64_t i, std::int64_t j) const {
    return buildings_.at(i, j);
}

Rgb TerrainPatch::ground_colour(const Column& c, double x, double y, double gx, double gy,
                                const FieldSample* field) const {
    Rgb colour = base_colour(c.ground_material);
    const double u = x - model_.area().x0, v = y - model_.area().y0;
    double factor = 1.0 + 0.08 * gradient_noise(hash_of(model_.seed(), kTint), u / 23.0, v / 23.0);
    if (c.ground_material == Material::Water) return scaled(colour, factor);
    if (field) {
        factor *= 0.88 + 0.24 * unit_of(field->id);
        if (is_crop(c.ground_material)) {
            const double t = field->row / 2.6 - std::floor(field->row / 2.6);
            factor *= 0.9 + 0.16 * std::fabs(2 * t - 1);
        }
    }
    return scaled(colour, factor * shade_of_gradient(gx, gy));
}

bool TerrainPatch::near_building(double x, double y, double margin) const {
    const Area& area = model_.area();
    const std::int64_t ci = cell_index(x, area.x0, kBuildingCell), cj = cell_index(y, area.y0, kBuildingCell);
    for (std::int64_t j = cj - 1; j <= cj + 1; ++j) {
        for (std::int64_t i = ci - 1; i <= ci + 1; ++i) {
            const auto& b = building_cell(i, j);
            if (b && b->covers(x, y, margin)) return true;
        }
    }
    return false;
}

double TerrainPatch::forest(double x, double y) const {
    // Bilinear between the centres of the four nearest tree cells.
    const double u = (x - model_.area().x0) / kTreeCell - 0.5, v = (y - model_.area().y0) / kTreeCell - 0.5;
    const double fu = std::floor(u), fv = std::floor(v);
    const auto i = static_cast<std::int64_t>(fu), j = static_cast<std::int64_t>(fv);
    const double tu = u - fu, tv = v - fv;
    return lerp(lerp(tree_cell(i, j).forest, tree_cell(i + 1, j).forest, tu),
                lerp(tree_cell(i, j + 1).forest, tree_cell(i + 1, j + 1).forest, tu), tv);
}

bool TerrainPatch::in_village(double x, double y) const {
    for (const Village* v : villages_) {
        const double dx = x - v->x, dy = y - v->y;
        if (!v->farm && dx * dx + dy * dy < 0.8 * 0.8 * v->radius * v->radius) return true;
    }
    return false;
}

void TerrainPatch::ground_surface(Column& c, double x, double y) const {
    const RiverRow river = river_at(y);
    const Cell cell = lattice_cell(x, y);
    double z = lerp(lerp(cell.z00, cell.z10, cell.fx), lerp(cell.z01, cell.z11, cell.fx), cell.fy);
    double gx = lerp(cell.z10 - cell.z00, cell.z11 - cell.z01, cell.fy);
    double gy = lerp(cell.z01 - cell.z00, cell.z11 - cell.z10, cell.fx);
    const double d = river.distance(x);
    const RoadHit road = model_.layout().road(x, y, river, main_road_at(x), villages_);
    c.ground_class = cls::kGround;
    std::optional<FieldSample> field;  // for fields: their tint and plough rows
    if (road.on_road()) {
        c.ground_class = cls::kRoadSurface;
        c.ground_material = is_marking(road) ? Material::Marking : Material::Asphalt;
        if (road.kind == RoadKind::Main && d < river.half_width + 40) {  // the bridge and its ramps
            const double deck = river.water_level + 5.0 - 0.15 * std::max(0.0, d - river.half_width - 14.0);
            if (deck > z) {
                z = deck;
                gx = gy = 0;
                if (d < river.half_width + 1.0) c.ground_class = cls::kBridgeDeck;
            }
        }
    } else if (d < river.half_width) {
        z = river.water_level;
        gx = gy = 0;
        c.ground_class = cls::kWater;
        c.ground_material = Material::Water;
    } else if (d < river.half_width + 6) {
        c.ground_material = Material::Bank;
    } else if (near_building(x, y, kGardenWidth)) {
        c.ground_material = Material::Lawn;
    } else if (forest(x, y) > 0) {
        c.ground_material = Material::ForestFloor;
    } else if (in_village(x, y)) {
        c.ground_material = Material::Meadow;
    } else {
        field = model_.land().field(x, y);
        c.ground_material = field->edge_distance < 1.2 ? Material::Meadow : field->crop;
    }
    c.ground_z = z;
    c.colour = ground_colour(c, x, y, gx, gy, field ? &*field : nullptr);
}

void TerrainPatch::objects(Column& c, double x, double y) const {
    const Area& area = model_.area();
    const auto& b = building_cell(cell_index(x, area.x0, kBuildingCell), cell_index(y, area.y0, kBuildingCell));
    if (b && b->covers(x, y)) {
        double nx = 0, ny = 0;
        c.top = Top::Roof;
        c.top_z = b->roof_z(x, y, nx, ny);
        c.top_material = b->roof;
        c.colour = scaled(base_colour(b->roof), b->tint * shade_of_normal(nx, ny));
        return;
    }
    const std::int64_t ci = cell_index(x, area.x0, kTreeCell), cj = cell_index(y, area.y0, kTreeCell);
    const Tree* best = nullptr;
    double best_z = -1e18, best_r2 = 0, best_nx = 0, best_ny = 0;
    for (std::int64_t j = cj - 1; j <= cj + 1; ++j) {
        for (std::int64_t i = ci - 1; i <= ci + 1; ++i) {
            const auto& t = tree_cell(i, j).tree;
            if (!t) continue;
            double r2 = 0, nx = 0, ny = 0;
            const double z = t->crown_z(x, y, r2, nx, ny);
            if (r2 < 1.0 && z > best_z) {
                best = &*t;
                best_z = z;
                best_r2 = r2;
                best_nx = nx;
                best_ny = ny;
            }
        }
    }
    if (!best || best_z < c.ground_z + 0.5) return;
    c.top = Top::Canopy;
    c.top_z = best_z;
    c.crown_bottom = std::max(c.ground_z, best->base_z + best->height - best->crown_depth);
    c.crown_r2 = best_r2;
    c.top_material = best->conifer ? Material::Needles : Material::Leaves;
    c.colour = scaled(best->colour, shade_of_normal(best_nx, best_ny) * (0.82 + 0.25 * (1 - best_r2)));
}

Column TerrainPatch::column(double x, double y) const {
    Column c;
    ground_surface(c, x, y);
    objects(c, x, y);
    return c;
}

}  // namespace lidarscout::synth
