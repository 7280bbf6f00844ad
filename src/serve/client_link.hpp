// Whether the client of a request is still there. cpp-httplib 0.11 tells a handler nothing of a
// closed connection (its DataSink::is_writable only selects for writing, which a closed peer's
// socket still passes), so the server finds the request's socket itself, by its two ends (the
// Request's local and remote address and port), and looks at it without blocking: a socket whose
// peer has closed reads end-of-file (or hangs up). A handler polls this between the steps of
// expensive work, and a request whose client left is not worked on further. And the listening
// socket's backlog, which httplib 0.11 sets to 5 (twenty clients opening their connections at once
// overflowed it: a dropped connection is tried again by its client a second later).
#pragma once

#include <string>

namespace lidarscout::serve {

// The connection's two ends, as httplib's Request has them.
struct ConnectionEnds {
    std::string local_addr;
    int local_port = -1;
    std::string remote_addr;
    int remote_port = -1;
};

inline constexpr int kCannotLook = -3;  // find_connection: the descriptors cannot be listed (no /proc)

// The descriptor of this process's connected socket with these ends, -1 when there is none, or
// kCannotLook.
int find_connection(const ConnectionEnds& ends);

// False once the peer of connected socket `fd` has closed or reset it (a read would give
// end-of-file or an error); true while it is open (also with unread bytes: a pipelined request).
bool peer_connected(int fd);

// Sets the backlog of this process's listening socket on `port` (listen() again, which Linux allows
// on a listening socket); false when there is none.
bool widen_backlog(int port, int backlog);

// One request's client: its socket looked up on first use, then polled.
class ClientLink {
public:
    explicit ClientLink(ConnectionEnds ends) : ends_(std::move(ends)) {}
    // True once the client has gone (also when its socket is not found: it was closed already);
    // never where the sockets cannot be looked at.
    bool gone();

private:
    static constexpr int kNotLooked = -2;
    ConnectionEnds ends_;
    int fd_ = kNotLooked;
};

}  // namespace lidarscout::serve
