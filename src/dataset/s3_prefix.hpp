// An s3 prefix as a dataset: "s3://bucket/prefix/" (or "s3://bucket" for the whole bucket)
// names the LAS/LAZ objects whose keys start with the prefix, listed with ListObjectsV2
// (net/s3_request.hpp, every page, within its limits), in key order; keys are normalised and
// kept inside the bucket and prefix.
#pragma once

#include <string>
#include <vector>

namespace lidarscout::dataset {

// True for an s3 URL that names a prefix: its key is empty or ends with '/'.
bool is_s3_prefix(const std::string& url);

// The s3 URLs of the .las/.laz objects under `prefix`; throws Error naming the bucket and
// prefix when the listing fails (with the S3 error code) or finds no such object.
std::vector<std::string> s3_prefix_tiles(const std::string& prefix);

// Whether any object's key starts with the key of `prefix` (one ListObjectsV2 request asking for one
// key); false when the listing fails.
bool s3_prefix_has_objects(const std::string& prefix);

}  // namespace lidarscout::dataset
