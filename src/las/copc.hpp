// COPC (Cloud Optimized Point Cloud, https://copc.io): a LAZ 1.4 file whose variable-size
// chunks are the nodes of an octree. The info VLR (user "copc", record 1, the first VLR)
// locates the root page of the hierarchy (EVLR "copc" 1000); its pages list each node's key,
// the byte range of its LAZ chunk and its point count, or point to child pages.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "las/vlr.hpp"

namespace lidarscout::io {
class File;
}

namespace lidarscout::las {

struct CopcInfo {
    double center[3] = {0, 0, 0};  // octree centre, in CRS units (already scaled)
    double halfsize = 0;           // centre to a face of the root cube
    double spacing = 0;            // point spacing at the root; halves at each level
    std::uint64_t root_hier_offset = 0;  // absolute file offset of the root hierarchy page
    std::uint64_t root_hier_size = 0;    // its size in bytes
    double gpstime_min = 0, gpstime_max = 0;
};

struct CopcNode {
    std::int32_t level = 0, x = 0, y = 0, z = 0;  // octree key (EPT naming)
    std::uint64_t offset = 0;       // absolute file offset of the node's LAZ chunk
    std::int32_t byte_size = 0;     // compressed size of the chunk
    std::int32_t point_count = 0;   // > 0
};

struct CopcHierarchy {
    std::vector<CopcNode> nodes;  // nodes with points, in page order (root page first, then BFS)
    std::size_t pages = 0;        // hierarchy pages read
    std::uint64_t total_points = 0;
};

// The COPC info when the first VLR is the COPC info VLR; nullopt otherwise (also when a
// "copc" 1 record exists elsewhere: the spec requires it first, and such a file is read as
// plain LAZ). Throws lidarscout::Error (file, offset) if its payload is not 160 bytes.
std::optional<CopcInfo> find_copc_info(const std::vector<Vlr>& vlrs, const std::string& file);

// Reads every hierarchy page from the root page on and returns the data nodes. Throws
// lidarscout::Error naming the file and offset when a page lies outside the file, has a size
// that is not a positive multiple of 32, is visited twice (a cycle), when the pages hold more
// entries than the file size allows (one per 32 bytes), or when an entry is invalid: a bad
// key, a point count below -1, a data range outside the file.
CopcHierarchy read_copc_hierarchy(const io::File& file, const CopcInfo& info);

}  // namespace lidarscout::las
