// Finding the tiles of a dataset: paths given by the user, folders searched recursively for
// .las/.laz files (case-insensitive), in a stable sorted order, tile lists (text files
// naming one tile or folder per line), EPT datasets (ept.json / entwine.json: the LAZ nodes),
// STAC catalogs and QGIS virtual point clouds (.vpc / .json: dataset/stac_catalog.hpp) and
// http(s) and s3 URLs of any of these but folders; s3 prefixes ("s3://bucket/prefix/", listed:
// dataset/s3_prefix.hpp) as folders, and so an s3 URL "s3://bucket/prefix" that names no object but
// a prefix (said in a note).
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/diagnostic.hpp"

namespace lidarscout::dataset {

struct CatalogItem;

// A path that gives no tile: the path as the user (or a list) named it, and one line naming it
// and the cause.
struct SkippedFile {
    std::string path;
    std::string error;
};

struct FoundFiles {
    std::vector<std::string> files;   // LAS/LAZ files, folders expanded, sorted per argument
    std::vector<SkippedFile> errors;  // one per path that does not exist / cannot be listed / holds no tile
    // What was read anyway: a catalog item's field that could not be used (stac_catalog.hpp), an s3 URL
    // opened as the prefix it names.
    Diagnostics warnings;
    // What a STAC catalog says of the files it named, to place them before their headers are read: (the file's
    // index in `files`, its item), in the order of `files`.
    std::vector<std::pair<std::size_t, std::shared_ptr<const CatalogItem>>> items;
};

bool has_point_cloud_extension(const std::string& path);

// True when `path` is a tile list rather than a point cloud: a text file (no NUL byte in its
// first 4 KiB) that does not start with the LAS signature "LASF" and has no .las/.laz
// extension.
bool is_tile_list(const std::string& path);

// Expands every path: a folder is searched recursively for .las/.laz files; a tile list is
// read line by line (blank lines and lines starting with '#' skipped; relative entries are
// relative to the list's folder or URL; entries may be files, folders, URLs or EPT metadata,
// not further lists); an EPT metadata file gives its nodes; a STAC catalog its items' data
// assets; any other file or URL is kept as given (whatever its extension; reading it reports
// what is wrong).
FoundFiles find_point_cloud_files(const std::vector<std::string>& paths);

// A tile to read: a file, or a virtual replica's source with its x/y shift (in its own units)
// and its name in the replica's grid (for display).
struct TileSource {
    std::string path;
    std::optional<std::array<double, 2>> shift;
    std::string name;  // "" for a plain file
    std::shared_ptr<const CatalogItem> item;  // what a STAC catalog says of it (null when none named it)
};

struct FoundSources {
    std::vector<TileSource> sources;
    std::vector<SkippedFile> errors;
    Diagnostics warnings;  // FoundFiles::warnings, and sources left out because they name a tile named before
};

// Called as a catalog's documents are read (each page of a STAC API search), on the thread of
// find_tile_sources before it returns: the tiles of the document just read (with their items), and whether
// more of that catalog remains to be read; its last document is told with no tiles (`more` false). What
// find_tile_sources returns holds them again (duplicates dropped there, not here): a caller may open the first
// pages while the later ones arrive.
using SourcesArriving = std::function<void(std::span<const TileSource> sources, bool more)>;

// find_point_cloud_files, with virtual replica manifests (dataset/virtual_replica.hpp) among the
// paths opened as their shifted tiles: what every command that reads tiles opens, so that a
// folder, a tile list and a manifest mean the same to all of them. Each tile once, however many
// items, entries and paths name it (dataset/source_identity.hpp), said in one warning.
FoundSources find_tile_sources(const std::vector<std::string>& paths, const SourcesArriving& arriving = {});

// Every local file and folder that reading `paths` touches, for the output check
// (io/output_check.hpp), without searching folders or reading a tile: the paths themselves, the
// entries of tile lists, the source tiles of virtual replica manifests, a local EPT dataset's
// folder. URLs and paths that cannot be read are left out (reading them reports the cause).
std::vector<std::string> local_inputs(const std::vector<std::string>& paths);

}  // namespace lidarscout::dataset
