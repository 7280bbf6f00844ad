// libFuzzer target: header + VLR/EVLR + CRS + laszip VLR + chunk table + COPC hierarchy +
// chunk point parsing of arbitrary bytes. Any crash, hang or sanitizer report is a bug; a
// lidarscout::Error is the expected outcome for malformed input.
#include <cstdint>

#include "core/error.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/tile.hpp"
#include "fuzz_input.hpp"
#include "las/copc.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        auto file = lidarscout::fuzz::input_file(data, size);
        if (!file) return 0;
        auto tile = lidarscout::dataset::read_tile(*file);
        (void)lidarscout::dataset::read_chunk_points(*file, tile);
        if (tile.copc) (void)lidarscout::las::read_copc_hierarchy(*file, *tile.copc);
    } catch (const lidarscout::Error&) {
    }
    return 0;
}
