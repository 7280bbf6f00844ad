// Out-of-line parts of io::ByteReader (error reporting, fixed-size strings).
#include "io/byte_reader.hpp"

namespace lidarscout::io {

void ByteReader::fail(const char* what, std::size_t needed) const {
    throw Error(file_, file_offset(),
                std::string("truncated ") + what + ": needs " + std::to_string(needed) + " bytes, only " +
                    std::to_string(remaining()) + " left");
}

std::string ByteReader::fixed_string(std::size_t n, const char* what) {
    auto s = take(n, what);
    std::size_t len = 0;
    while (len < n && s[len] != 0) ++len;
    return std::string(reinterpret_cast<const char*>(s.data()), len);
}

}  // namespace lidarscout::io
