// AtomicOutputFile: temporary file + rename (POSIX); kernel copies with copy_file_range (Linux).
#include "io/output_file.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <vector>

#include "core/error.hpp"
#include "io/file.hpp"
#include "io/output_check.hpp"
#include "io/output_group.hpp"
#include "io/temporary_files.hpp"

namespace lidarscout::io {
namespace fs = std::filesystem;

AtomicOutputFile::AtomicOutputFile(std::string target, const std::string& protect) : target_(std::move(target)) {
    std::error_code ec;
    if (!protect.empty() && fs::exists(target_, ec) && fs::equivalent(target_, protect, ec)) {
        throw Error(target_, std::nullopt, "refusing to overwrite the input file");
    }
    refuse_protected_input(target_);
    const auto dir = fs::path(target_).parent_path();
    const auto name = fs::path(target_).filename().string();
    // ".out.gpkg.tmp-PID.gpkg": hidden, and ending in the target's extension, which writers that write by
    // name check (GDAL's GeoPackage driver warns on any other).
    const std::string ext = fs::path(target_).extension().string();
    temp_ = ((dir.empty() ? fs::path(".") : dir) / ("." + name + ".tmp-" + std::to_string(::getpid()) + ext)).string();
    guard_ = std::make_unique<TemporaryFileGuard>(temp_);
    fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
    if (fd_ < 0) {
        throw Error(target_, std::nullopt,
                    std::string("cannot create a temporary file beside it: ") + std::strerror(errno));
    }
}

AtomicOutputFile::~AtomicOutputFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!committed_) ::unlink(temp_.c_str());
}

void AtomicOutputFile::write_at(std::uint64_t offset, std::span<const std::uint8_t> bytes) {
    std::size_t done = 0;
    while (done < bytes.size()) {
        ssize_t n = ::pwrite(fd_, bytes.data() + done, bytes.size() - done, static_cast<off_t>(offset + done));
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw Error(target_, offset + done, std::string("write failed: ") + std::strerror(errno));
        done += static_cast<std::size_t>(n);
    }
    size_ = std::max<std::uint64_t>(size_, offset + bytes.size());
}

void AtomicOutputFile::write(std::span<const std::uint8_t> bytes) { write_at(size_, bytes); }

namespace {

// Errors after which copy_file_range cannot work for this pair of files (but read/write can).
bool kernel_copy_unsupported(int err) {
    return err == EXDEV || err == ENOSYS || err == EOPNOTSUPP || err == EINVAL || err == EBADF;
}

[[noreturn]] void fail_short_source(const File& source, std::uint64_t at) {
    throw Error(source.path(), at, "the file ends before the range to copy does");
}

}  // namespace

void AtomicOutputFile::copy_from(const File& source, std::uint64_t offset, std::uint64_t length) {
    loff_t in = static_cast<loff_t>(offset), out = static_cast<loff_t>(size_);
    std::uint64_t left = length;
    while (left > 0) {
        const auto step = static_cast<std::size_t>(std::min<std::uint64_t>(left, 1u << 30));
        const ssize_t n = ::copy_file_range(source.fd(), &in, fd_, &out, step, 0);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0 && kernel_copy_unsupported(errno)) break;
        if (n < 0) {
            throw Error(target_, static_cast<std::uint64_t>(out), std::string("copy failed: ") + std::strerror(errno));
        }
        if (n == 0) fail_short_source(source, static_cast<std::uint64_t>(in));
        left -= static_cast<std::uint64_t>(n);
    }
    size_ = std::max<std::uint64_t>(size_, static_cast<std::uint64_t>(out));
    std::vector<std::uint8_t> buffer(left > 0 ? std::min<std::uint64_t>(left, 1u << 20) : 0);
    while (left > 0) {  // the fallback: plain reads and writes
        const auto n = source.read_at(static_cast<std::uint64_t>(in),
                                      std::span(buffer.data(), std::min<std::uint64_t>(left, buffer.size())));
        if (n == 0) fail_short_source(source, static_cast<std::uint64_t>(in));
        write_at(static_cast<std::uint64_t>(out), std::span<const std::uint8_t>(buffer.data(), n));
        in += static_cast<loff_t>(n);
        out += static_cast<loff_t>(n);
        left -= n;
    }
}

void AtomicOutputFile::sync_and_close() {
    if (::fsync(fd_) != 0) throw Error(target_, std::nullopt, std::string("fsync failed: ") + std::strerror(errno));
    ::close(fd_);
    fd_ = -1;
}

void AtomicOutputFile::commit(OutputGroup& group) {
    sync_and_close();
    group.add(temp_, target_);
    committed_ = true;  // the group removes it now, unless it renames it
}

void AtomicOutputFile::commit() {
    sync_and_close();
    if (std::rename(temp_.c_str(), target_.c_str()) != 0) {
        throw Error(target_, std::nullopt, std::string("cannot rename the temporary file: ") + std::strerror(errno));
    }
    committed_ = true;
}

}  // namespace lidarscout::io
