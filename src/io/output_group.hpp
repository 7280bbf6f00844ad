// A set of outputs that appear together or not at all (a `dem` run's rasters, hillshade and
// contours): each is written under a temporary name beside its target (AtomicOutputFile::commit
// hands it to the group instead of renaming it), and commit() renames them all at the end, with
// Ctrl-C held off until the last rename is done. Until then no target is touched, so a run that
// fails or is interrupted leaves the files that were there before, and none of the new ones:
// dropping the group without commit() removes every temporary file it holds, and a signal that
// ends the process removes them too (temporary_files.hpp).
#pragma once

#include <memory>
#include <string>
#include <vector>

namespace lidarscout::io {

class TemporaryFileGuard;

class OutputGroup {
public:
    OutputGroup();
    ~OutputGroup();  // without commit(): removes the temporary files
    OutputGroup(const OutputGroup&) = delete;
    OutputGroup& operator=(const OutputGroup&) = delete;

    // From now on `temp` (complete, or written by name later, e.g. by GDAL) belongs to the group:
    // commit() renames it to `target`, and it is removed if the group is dropped or a signal ends
    // the process. Throws lidarscout::Error (naming `target`) when the group already holds it.
    void add(std::string temp, std::string target);

    // Where `target`'s content is until commit(): its temporary name; `target` itself when the
    // group does not hold it. For a writer that reads an output of the set (a hillshade its DEM).
    const std::string& path_of(const std::string& target) const;

    // Renames every file to its target, in the order added; SIGINT, SIGTERM and SIGHUP wait
    // until the last one is done. Throws lidarscout::Error naming the first that cannot be
    // renamed (those before it are in place: a rename fails on a full or read-only disk).
    void commit();

private:
    struct Entry;
    std::vector<std::unique_ptr<Entry>> entries_;  // the guards keep pointers to their names
    bool committed_ = false;
};

}  // namespace lidarscout::io
