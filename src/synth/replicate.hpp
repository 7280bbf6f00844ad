// `synth replicate`: a large dataset for benchmarks, made by copying real tiles onto a grid.
// Each output is a byte copy of a source tile in which only the header's x/y offsets and x/y
// bounds (and a COPC file's octree centre) are moved: LAS/LAZ point records are integers
// relative to the header's scale and offset, so the copy is a valid tile whose points are the
// source's, shifted. The result is a tool for benchmarks, not a data product: the same points
// repeat across the grid and neighbouring tiles do not join.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/diagnostic.hpp"
#include "dataset/tile.hpp"
#include "dataset/virtual_replica.hpp"

namespace lidarscout {
class ThreadPool;
}
namespace lidarscout::io {
class File;
}

namespace lidarscout::synth {

struct GridSize {
    std::uint32_t nx = 0, ny = 0;
};

// Parses "NXxNY" (e.g. "45x45", also "45X45"); throws lidarscout::Error on anything else.
GridSize parse_grid(const std::string& text);

struct ReplicaSource {
    std::string path;
    dataset::Tile tile;           // its metadata (header, VLRs, COPC info, ...)
    std::string unit;             // horizontal unit name ("metre", "us_survey_foot", ...)
    double to_metres = 1.0;       // metres per x/y unit (1 when the file does not say)
    double footprint_metres = 0;  // the larger side of its x/y bounds
    std::array<double, 2> quantum{1.0, 1.0};  // x/y shifts are multiples of this (1 unit, or the scale)
};

struct ReplicaTile {
    std::string path;              // the output file
    std::uint32_t gx = 0, gy = 0;  // grid cell
    std::size_t source = 0;        // index into ReplicatePlan::sources
    std::array<double, 2> shift{}; // added to x/y offsets and bounds, in the source's units
};

struct ReplicatePlan {
    std::string out_dir;
    GridSize grid;
    std::vector<ReplicaSource> sources;
    std::vector<ReplicaTile> tiles;            // row by row: index = gx + gy * nx
    double cell_metres = 0;                    // side of a grid cell
    std::array<double, 2> anchor_metres{};     // first source's min x/y corner, in metres
    Diagnostics warnings;                      // skipped sources, unknown units (one line each)
    std::uint64_t total_bytes = 0;
    std::uint64_t total_points = 0;
};

// Finds and reads the sources (files or folders), checks the output folder and lays out the
// grid; writes nothing. A source that cannot be read is skipped with a warning. Throws
// lidarscout::Error when a SRC path does not exist, when no source is usable, when the grid is
// empty, or when `out_dir` contains a source (outputs must never land on an input).
ReplicatePlan plan_replicas(const std::vector<std::string>& sources, const std::string& out_dir, GridSize grid);

// Writes one replica: a copy of `source` (described by `tile`) at `target`, written under a
// temporary name and renamed when complete, with x/y offsets and bounds moved by `shift`.
void write_replica(const io::File& source, const dataset::Tile& tile, const std::string& target,
                   std::array<double, 2> shift);

// Creates the output folder, writes every tile of `plan` in parallel on `pool`, then the
// manifest `replicate.json`. `on_bytes` (may be empty) is called with each tile's size as it is
// written, from the pool's threads.
void write_replicas(const ReplicatePlan& plan, ThreadPool& pool,
                    const std::function<void(std::uint64_t bytes)>& on_bytes = {});

// Writes only the manifest, marked "virtual": the tiles stay their sources, opened with their
// shifts by dataset::open_dataset (dataset/virtual_replica.hpp); nothing is copied.
void write_virtual_replica(const ReplicatePlan& plan);

// The manifest's file name inside the output folder.
inline constexpr const char* kManifestName = dataset::kReplicaManifestName;

}  // namespace lidarscout::synth
