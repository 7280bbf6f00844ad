// A file that appears under its final name only when complete: data goes to a temporary
// file beside the target, which commit() renames over the target. Without commit() (an
// error, an interrupted run: see temporary_files.hpp for Ctrl-C) the temporary file is removed
// and the target never sees a half-written file. A file of a set that must appear together is
// handed to an OutputGroup instead (commit(group)), which renames the set at the end.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

namespace lidarscout::io {

class File;
class OutputGroup;
class TemporaryFileGuard;

class AtomicOutputFile {
public:
    // Refuses (lidarscout::Error) when `target` names the same file as `protect` or as an input
    // registered with io::protect_inputs (output_check.hpp).
    AtomicOutputFile(std::string target, const std::string& protect = {});
    ~AtomicOutputFile();
    AtomicOutputFile(const AtomicOutputFile&) = delete;
    AtomicOutputFile& operator=(const AtomicOutputFile&) = delete;

    void write(std::span<const std::uint8_t> bytes);      // appends
    void write_at(std::uint64_t offset, std::span<const std::uint8_t> bytes);  // patches
    // Appends `length` bytes of `source` from `offset`, copied by the kernel (copy_file_range;
    // read/write where the kernel cannot, e.g. across file systems). Throws an Error if
    // `source` ends before the range does.
    void copy_from(const File& source, std::uint64_t offset, std::uint64_t length);
    std::uint64_t size() const noexcept { return size_; }
    const std::string& target() const noexcept { return target_; }
    // The temporary file's name, for writers that write by name (GDAL): what they write there
    // is what commit() renames. It ends in the target's extension (".x.gpkg.tmp-PID.gpkg").
    const std::string& temp_path() const noexcept { return temp_; }

    // Flushes, syncs and renames the temporary file to the target.
    void commit();
    // Flushes and syncs it and hands it to `group`, whose commit() renames it with the others.
    void commit(OutputGroup& group);

private:
    void sync_and_close();

    std::string target_;
    std::string temp_;
    std::unique_ptr<TemporaryFileGuard> guard_;  // removes temp_ if a signal ends the process
    int fd_ = -1;
    std::uint64_t size_ = 0;
    bool committed_ = false;
};

}  // namespace lidarscout::io
