// Read-only random-access file: positioned reads (pread) that are safe to issue from
// many threads at once. We never open a user's input for writing.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace lidarscout::io {

class File {
public:
    // Opens `path` read-only; throws lidarscout::Error if it cannot.
    static File open(const std::string& path);

    File() = default;
    File(File&& other) noexcept;
    File& operator=(File&& other) noexcept;
    File(const File&) = delete;
    File& operator=(const File&) = delete;
    ~File();

    const std::string& path() const noexcept { return path_; }
    std::uint64_t size() const noexcept { return size_; }
    int fd() const noexcept { return fd_; }

    // Reads up to out.size() bytes at `offset`; returns how many were read (short at EOF).
    std::size_t read_at(std::uint64_t offset, std::span<std::uint8_t> out) const;
    // Reads exactly out.size() bytes at `offset` or throws an Error naming what was missing.
    void read_exact(std::uint64_t offset, std::span<std::uint8_t> out,
                    const char* what = "data") const;
    std::vector<std::uint8_t> read_vector(std::uint64_t offset, std::size_t n,
                                          const char* what = "data") const;

private:
    std::string path_;
    int fd_ = -1;
    std::uint64_t size_ = 0;
};

}  // namespace lidarscout::io
