// gzip and gunzip through zlib's deflate/inflate with the gzip wrapper (window bits 16 + 15).
#include "serve/gzip.hpp"

#include <zlib.h>

#include "core/error.hpp"

namespace lidarscout::serve {
namespace {

constexpr int kGzipWindow = 16 + MAX_WBITS;

}  // namespace

std::string gzip(std::string_view data) {
    z_stream z{};
    if (deflateInit2(&z, 6, Z_DEFLATED, kGzipWindow, 8, Z_DEFAULT_STRATEGY) != Z_OK) {
        throw Error::in_stage("serve", "zlib could not start a gzip stream");
    }
    std::string out(deflateBound(&z, static_cast<uLong>(data.size())), '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    z.avail_in = static_cast<uInt>(data.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = static_cast<uInt>(out.size());
    const int rc = deflate(&z, Z_FINISH);
    out.resize(z.total_out);
    deflateEnd(&z);
    if (rc != Z_STREAM_END) throw Error::in_stage("serve", "zlib could not compress a response");
    return out;
}

std::string gunzip(std::string_view stream) {
    z_stream z{};
    if (inflateInit2(&z, kGzipWindow) != Z_OK) throw Error::in_stage("serve", "zlib could not start inflating");
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(stream.data()));
    z.avail_in = static_cast<uInt>(stream.size());
    std::string out;
    char buffer[1 << 15];
    int rc = Z_OK;
    while (rc == Z_OK) {
        z.next_out = reinterpret_cast<Bytef*>(buffer);
        z.avail_out = sizeof buffer;
        rc = inflate(&z, Z_NO_FLUSH);
        out.append(buffer, sizeof buffer - z.avail_out);
    }
    inflateEnd(&z);
    if (rc != Z_STREAM_END) throw Error::in_stage("serve", "not a complete gzip stream");
    return out;
}

}  // namespace lidarscout::serve
