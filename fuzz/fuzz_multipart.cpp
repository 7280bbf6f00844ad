// libFuzzer target: the multipart/byteranges parser (net/byte_ranges) that splits a server's
// answer to a multi-range request. The first input byte gives the boundary's length (taken
// from the next bytes); the rest is the body. A lidarscout::Error is the expected outcome for
// a malformed body; a crash, a read outside the body or a part outside the body is a bug.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "core/error.hpp"
#include "net/byte_ranges.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size < 1) return 0;
    const std::size_t boundary_length = std::min<std::size_t>(data[0] % 71, size - 1);
    const std::string boundary(reinterpret_cast<const char*>(data + 1), boundary_length);
    const std::span<const std::uint8_t> body(data + 1 + boundary_length, size - 1 - boundary_length);
    try {
        for (const auto& part : lidarscout::net::parse_multipart_byteranges(body, boundary)) {
            const bool inside = part.data.data() >= body.data() &&
                                part.data.data() + part.data.size() <= body.data() + body.size();
            if (!inside || part.data.size() != part.content_range.range.length) std::abort();
        }
    } catch (const lidarscout::Error&) {
    }
    return 0;
}
