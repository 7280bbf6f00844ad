// libFuzzer target: header + VLR/EVLR + CRS + laszip VLR + chunk table + COPC hierarchy +
// chunk point parsing of arbitrary bytes. Any crash, hang or sanitizer report is a bug; a
// lidarscout::Error is the expected outcome for malformed input.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <string>

#include "core/error.hpp"
#include "dataset/chunk_points.hpp"
#include "dataset/tile.hpp"
#include "io/file.hpp"
#include "las/copc.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    static const int fd = memfd_create("lidarscout-fuzz", 0);
    if (fd < 0) return 0;
    if (ftruncate(fd, 0) != 0) return 0;
    for (std::size_t done = 0; done < size;) {
        ssize_t n = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
        if (n <= 0) return 0;
        done += static_cast<std::size_t>(n);
    }
    try {
        auto file = lidarscout::io::File::open("/proc/self/fd/" + std::to_string(fd));
        auto tile = lidarscout::dataset::read_tile(file);
        (void)lidarscout::dataset::read_chunk_points(file, tile);
        if (tile.copc) (void)lidarscout::las::read_copc_hierarchy(file, *tile.copc);
    } catch (const lidarscout::Error&) {
    }
    return 0;
}
