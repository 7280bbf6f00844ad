// The one check every output of every command goes through before any work starts, so that a
// command never writes into its user's inputs:
// - an output that is the same file as an input (same device and inode: through symbolic and
//   hard links, `./` and absolute spellings) is refused, naming both;
// - an output inside an input folder with a name the folder search takes for a tile (.las,
//   .laz) is refused: it would become one of the inputs;
// - an output whose extension does not match what is written is refused, naming the expected
//   extension (a raster never lands among the tiles of a folder);
// - an output whose folder does not exist, is a file or is not writable is refused;
// - two outputs of one command that name the same file are refused.
// The inputs are also registered for the whole process (protect_inputs): AtomicOutputFile
// refuses to replace any of them, so a writer added later without declaring its output still
// cannot overwrite an input.
#pragma once

#include <string>
#include <vector>

namespace lidarscout::io {

// What an output holds, which decides the extensions it may have.
enum class OutputKind {
    GeoTiff,       // .tif, .tiff
    Png,           // .png
    Hillshade,     // .tif, .tiff (georeferenced) or .png (with a world file)
    GeoPackage,    // .gpkg
    Json,          // .json
    Catalog,       // .vpc (a QGIS virtual point cloud)
    PointCloud,    // .las, .laz
    Profile,       // .csv, .las, .laz, .png (a profile's points or image)
    TrainingData,  // lidarscout's own layout: any extension but those of the formats above
    Folder,        // a folder, created when missing (its parent must be writable)
};

// An output named on the command line: the path and the option that named it ("-o", "--rgb").
struct OutputTarget {
    std::string path;
    std::string option;
    OutputKind kind = OutputKind::GeoTiff;
};

// "one of .tif, .tiff" / ".png": the extensions a kind wants, for messages.
std::string expected_extensions(OutputKind kind);

// Refuses (lidarscout::Error naming the output, the option and, where one is involved, the input)
// any output above that breaks a rule; `inputs` are every local file and folder the command reads
// (URLs and paths that do not exist are skipped: reading them reports what is wrong). Nothing is
// created. (The CLI then registers the inputs with protect_inputs().)
void check_outputs(const std::vector<OutputTarget>& outputs, const std::vector<std::string>& inputs);

// Registers files and folders for the whole process: no AtomicOutputFile may replace such a file.
void protect_inputs(const std::vector<std::string>& inputs);
// Forgets them (tests, which reuse one process for many temporary inputs).
void forget_protected_inputs();

// Throws lidarscout::Error when `target` is a file protect_inputs() registered (same device and
// inode). Called by AtomicOutputFile before it creates anything.
void refuse_protected_input(const std::string& target);

}  // namespace lidarscout::io
