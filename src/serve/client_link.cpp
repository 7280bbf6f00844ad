// Finding a request's socket by its ends and seeing whether its peer is still there; the listening
// socket's backlog.
#include "serve/client_link.hpp"

#include <dirent.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>

#include <cstdlib>

namespace lidarscout::serve {
namespace {

// The numeric address and port of one end of socket `fd` (false when it is not a connected socket).
bool end_of(int fd, bool peer, std::string& addr, int& port) {
    sockaddr_storage sa{};
    socklen_t len = sizeof sa;
    const int rc = peer ? ::getpeername(fd, reinterpret_cast<sockaddr*>(&sa), &len)
                        : ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &len);
    if (rc != 0 || (sa.ss_family != AF_INET && sa.ss_family != AF_INET6)) return false;
    char host[NI_MAXHOST], service[NI_MAXSERV];
    if (::getnameinfo(reinterpret_cast<sockaddr*>(&sa), len, host, sizeof host, service, sizeof service,
                      NI_NUMERICHOST | NI_NUMERICSERV) != 0) {
        return false;
    }
    addr = host, port = std::atoi(service);
    return true;
}

bool has_ends(int fd, const ConnectionEnds& ends) {
    std::string addr;
    int port = -1;
    if (!end_of(fd, false, addr, port) || port != ends.local_port) return false;
    if (!end_of(fd, true, addr, port)) return false;
    return port == ends.remote_port && addr == ends.remote_addr;
}

// The first of this process's descriptors for which `matches` holds, -1 when none does, or
// kCannotLook when the process's descriptors cannot be listed (no /proc).
template <typename Match>
int find_socket(const Match& matches) {
    DIR* dir = ::opendir("/proc/self/fd");
    if (!dir) return kCannotLook;
    int found = -1;
    while (const dirent* e = ::readdir(dir)) {
        char* end = nullptr;
        const long fd = std::strtol(e->d_name, &end, 10);
        if (end == e->d_name || *end != '\0' || fd == ::dirfd(dir)) continue;
        if (matches(static_cast<int>(fd))) {
            found = static_cast<int>(fd);
            break;
        }
    }
    ::closedir(dir);
    return found;
}

}  // namespace

int find_connection(const ConnectionEnds& ends) {
    return find_socket([&](int fd) { return has_ends(fd, ends); });
}

bool widen_backlog(int port, int backlog) {
    const int fd = find_socket([&](int s) {
        int listening = 0;
        socklen_t len = sizeof listening;
        std::string addr;
        int local = -1;
        return ::getsockopt(s, SOL_SOCKET, SO_ACCEPTCONN, &listening, &len) == 0 && listening &&
               end_of(s, false, addr, local) && local == port;
    });
    return fd >= 0 && ::listen(fd, backlog) == 0;
}

bool peer_connected(int fd) {
    pollfd p{fd, POLLIN | POLLRDHUP, 0};
    if (::poll(&p, 1, 0) < 0) return false;
    if (p.revents & (POLLRDHUP | POLLHUP | POLLERR | POLLNVAL)) return false;
    if (!(p.revents & POLLIN)) return true;
    char byte;
    return ::recv(fd, &byte, 1, MSG_PEEK | MSG_DONTWAIT) > 0;  // 0: end of file; < 0: reset
}

bool ClientLink::gone() {
    if (fd_ == kNotLooked) fd_ = find_connection(ends_);
    if (fd_ == kCannotLook) return false;  // (not knowing, the work is done)
    return fd_ < 0 || !peer_connected(fd_);
}

}  // namespace lidarscout::serve
