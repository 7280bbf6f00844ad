// ReadTarget: the descriptor or remote file that batch read requests name.
#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <utility>

#include "core/error.hpp"
#include "core/regular_file.hpp"
#include "io/batch_reader.hpp"
#include "net/remote_file.hpp"
#include "net/url.hpp"

namespace lidarscout::io {

namespace {

// (regular files only: core/regular_file.hpp)
int open_descriptor(const std::string& path, bool direct) {
    if (direct) {
        const int fd = open_regular_file(path, O_DIRECT);
        if (fd >= 0 || errno != EINVAL) return fd;  // EINVAL: the file system has no O_DIRECT
    }
    return open_regular_file(path);
}

}  // namespace

ReadTarget ReadTarget::open(const std::string& path, bool direct) {
    ReadTarget t;
    if (net::is_url(path)) {
        t.remote_ = net::RemoteFile::open(path);
        t.path_ = std::make_shared<const std::string>(t.remote_->display_url());
        return t;
    }
    t.path_ = std::make_shared<const std::string>(path);
    t.fd_ = open_descriptor(path, direct);
    if (t.fd_ < 0) throw Error(path, std::nullopt, std::string("cannot open: ") + std::strerror(errno));
    return t;
}

ReadTarget::ReadTarget(ReadTarget&& other) noexcept { *this = std::move(other); }

ReadTarget& ReadTarget::operator=(ReadTarget&& other) noexcept {
    if (this != &other) {
        if (fd_ >= 0) ::close(fd_);
        fd_ = std::exchange(other.fd_, -1);
        remote_ = std::move(other.remote_);
        path_ = std::move(other.path_);
    }
    return *this;
}

ReadTarget::~ReadTarget() {
    if (fd_ >= 0) ::close(fd_);
}

ReadRequest ReadTarget::request(std::uint64_t offset, std::uint32_t length, std::uint64_t tag) const {
    return {fd_, offset, length, tag, remote_.get(), path_.get()};
}

ErrorRecord read_error(const ReadRequest& request, std::string cause) {
    return {request.path ? *request.path : std::string(), request.offset, std::move(cause)};
}

}  // namespace lidarscout::io
