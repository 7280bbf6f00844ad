// libFuzzer target: decoding of corrupt LAZ chunks. The first input byte picks an item list
// (every point-wise and layered combination of the corpus), the next two the point count;
// the rest is the chunk. A lidarscout::Error is the expected outcome for bad data; a crash,
// hang, sanitizer report or a huge allocation is a bug.
#include <cstdint>
#include <vector>

#include "core/error.hpp"
#include "las/laszip_vlr.hpp"
#include "laz/chunk_decoder.hpp"

namespace {

using lidarscout::las::LazItem;
using lidarscout::las::LaszipVlr;

LaszipVlr make(std::uint16_t compressor, std::vector<LazItem> items) {
    LaszipVlr v;
    v.compressor = compressor;
    v.chunk_size = 50000;
    v.items = std::move(items);
    return v;
}

const std::vector<LaszipVlr>& layouts() {
    static const std::vector<LaszipVlr> all = {
        make(2, {{6, 20, 2}}),
        make(2, {{6, 20, 2}, {7, 8, 2}}),
        make(2, {{6, 20, 2}, {8, 6, 2}}),
        make(2, {{6, 20, 2}, {7, 8, 2}, {8, 6, 2}}),
        make(2, {{6, 20, 2}, {7, 8, 2}, {8, 6, 2}, {0, 3, 2}}),
        make(1, {{6, 20, 1}, {7, 8, 1}, {8, 6, 1}}),
        make(2, {{6, 20, 2}, {7, 8, 2}, {9, 29, 1}}),
        make(3, {{10, 30, 3}}),
        make(3, {{10, 30, 3}, {11, 6, 3}}),
        make(3, {{10, 30, 3}, {12, 8, 3}}),
        make(3, {{10, 30, 3}, {12, 8, 3}, {14, 5, 3}}),
        make(3, {{10, 30, 4}, {12, 8, 4}, {13, 29, 4}, {14, 4, 4}}),
    };
    return all;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 3) return 0;
    const auto& laz = layouts()[data[0] % layouts().size()];
    const std::uint64_t points = 1 + ((data[1] | (data[2] << 8)) % 4096);
    std::vector<std::uint8_t> out(points * laz.record_length());
    try {
        lidarscout::laz::decode_chunk(laz, {{data + 3, size - 3}, points, out});
    } catch (const lidarscout::Error&) {
    }
    return 0;
}
