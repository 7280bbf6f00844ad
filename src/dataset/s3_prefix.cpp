// The tiles of an s3 prefix: its listing, filtered to point cloud files as it is read.
#include "dataset/s3_prefix.hpp"

#include "core/error.hpp"
#include "dataset/file_search.hpp"
#include "net/s3_request.hpp"

namespace lidarscout::dataset {

bool is_s3_prefix(const std::string& url) {
    const auto where = net::parse_s3_url(url);
    return where && (where->key.empty() || where->key.back() == '/');
}

std::vector<std::string> s3_prefix_tiles(const std::string& prefix) {
    const auto where = net::parse_s3_url(prefix);
    if (!where) throw Error(prefix, std::nullopt, "not an s3 URL (s3://bucket/prefix/)");
    std::vector<std::string> tiles;  // (only the tiles are held while the listing goes on)
    const std::uint64_t listed = net::for_each_s3_object(prefix, [&](net::S3Object&& o) {
        std::string url = "s3://" + where->bucket + "/" + o.key;
        if (!has_point_cloud_extension(url)) return false;
        tiles.push_back(std::move(url));
        return true;
    });
    if (tiles.empty()) {
        throw Error(prefix, std::nullopt, "no .las/.laz object under this prefix (" + std::to_string(listed) +
                                              " objects listed in bucket \"" + where->bucket + "\", prefix \"" +
                                              where->key + "\")");
    }
    return tiles;
}

bool s3_prefix_has_objects(const std::string& prefix) {
    net::S3ListLimits one;
    one.page_size = 1;
    one.max_pages = 1;
    bool any = false;
    try {
        net::for_each_s3_object(prefix, [&any](net::S3Object&&) { return any = true, false; }, one);
    } catch (const Error&) {
        // more than one page (there are objects: `any` is set), or the listing failed (none known)
    }
    return any;
}

}  // namespace lidarscout::dataset
