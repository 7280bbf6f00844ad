// Refusing what is not a regular file before reading it: stat's mode, and an open that cannot block.
#include "core/regular_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.hpp"

namespace lidarscout {

namespace {

[[noreturn]] void refuse(const std::string& path, mode_t mode) {
    throw Error(path, std::nullopt, "is " + non_regular_kind(mode) + ", not a regular file: not read");
}

}  // namespace

std::string non_regular_kind(mode_t mode) {
    if (S_ISREG(mode)) return {};
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISDIR(mode)) return "a folder";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a file";  // (no other kind exists on Linux)
}

void require_regular_file(const std::string& path) {
    struct stat st {};
    if (::stat(path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) refuse(path, st.st_mode);
}

int open_regular_file(const std::string& path, int flags) {
    const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK | flags);
    if (fd < 0) return fd;
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        const int error = errno;
        ::close(fd);
        throw Error(path, std::nullopt, std::string("cannot stat: ") + std::strerror(error));
    }
    if (!S_ISREG(st.st_mode)) {
        ::close(fd);
        refuse(path, st.st_mode);
    }
    const int status = ::fcntl(fd, F_GETFL);
    if (status < 0 || ::fcntl(fd, F_SETFL, status & ~O_NONBLOCK) != 0) {  // reads (io_uring's too) may wait again
        const int error = errno;
        ::close(fd);
        throw Error(path, std::nullopt, std::string("cannot set the file's flags: ") + std::strerror(error));
    }
    return fd;
}

}  // namespace lidarscout
