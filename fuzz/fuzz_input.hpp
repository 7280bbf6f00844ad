// The fuzzers' input as a file: the bytes written to one memfd, opened by its /proc path.
#pragma once

#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <optional>
#include <string>

#include "io/file.hpp"

namespace lidarscout::fuzz {

// The bytes as an open file, or nothing when the memfd cannot be written.
inline std::optional<io::File> input_file(const std::uint8_t* data, std::size_t size) {
    static const int fd = memfd_create("lidarscout-fuzz", 0);
    if (fd < 0 || ftruncate(fd, 0) != 0) return std::nullopt;
    for (std::size_t done = 0; done < size;) {
        const ssize_t n = pwrite(fd, data + done, size - done, static_cast<off_t>(done));
        if (n <= 0) return std::nullopt;
        done += static_cast<std::size_t>(n);
    }
    return io::File::open("/proc/self/fd/" + std::to_string(fd));
}

}  // namespace lidarscout::fuzz
