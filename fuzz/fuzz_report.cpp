// libFuzzer target: the `info --json` report of arbitrary bytes (mutated headers and VLRs):
// the tile is read as `info` reads it and its report serialised; a string that is not valid
// UTF-8 makes the JSON writer throw, which is a crash here. A lidarscout::Error is the
// expected outcome for malformed input.
#include <cstdint>

#include "cli/tile_json.hpp"
#include "core/error.hpp"
#include "dataset/tile.hpp"
#include "fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        auto file = lidarscout::fuzz::input_file(data, size);
        if (!file) return 0;
        const auto tile = lidarscout::dataset::read_tile(*file);
        (void)lidarscout::cli::tile_to_json(tile).dump();
    } catch (const lidarscout::Error&) {
    }
    return 0;
}
