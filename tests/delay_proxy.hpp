// A TCP proxy on loopback that adds a round-trip latency: every byte is delivered `one_way`
// later than it arrived, in each direction (tc netem needs a kernel module that is not always
// there). Used by bench_http and by the tests of the viewer's progressive opening.
#pragma once

#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <map>
#include <string>
#include <thread>

namespace lidarscout::test {

namespace delay_proxy_detail {

inline int loopback_listener(int& port) {
    const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
    ::listen(s, 1024);
    ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
    port = ntohs(a.sin_port);
    return s;
}

inline int connect_loopback(int port) {
    const int s = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        ::close(s);
        return -1;
    }
    return s;
}

}  // namespace delay_proxy_detail

// One thread, epoll; chunks leave in arrival order, so one FIFO suffices.
class DelayProxy {
public:
    DelayProxy(int upstream_port, std::chrono::microseconds one_way) : upstream_(upstream_port), delay_(one_way) {
        listener_ = delay_proxy_detail::loopback_listener(port_);
        epoll_ = ::epoll_create1(EPOLL_CLOEXEC);
        watch(listener_);
        thread_ = std::thread([this] { run(); });
    }
    ~DelayProxy() {
        stop_ = true;
        thread_.join();
        for (const auto& [fd, peer] : peers_) ::close(fd);
        ::close(listener_);
        ::close(epoll_);
    }
    int port() const { return port_; }

private:
    struct Chunk {
        std::chrono::steady_clock::time_point due;
        int to;
        std::string bytes;  // empty: the sender closed; shut the peer's writing side
    };

    void watch(int fd) {
        epoll_event e{};
        e.events = EPOLLIN;
        e.data.fd = fd;
        ::epoll_ctl(epoll_, EPOLL_CTL_ADD, fd, &e);
    }

    void accept_one() {
        const int client = ::accept4(listener_, nullptr, nullptr, SOCK_CLOEXEC);
        if (client < 0) return;
        const int server = delay_proxy_detail::connect_loopback(upstream_);
        if (server < 0) return (void)::close(client);
        for (const int fd : {client, server}) {
            int one = 1;
            ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
            watch(fd);
        }
        peers_[client] = server;
        peers_[server] = client;
    }

    void read_from(int fd) {
        char buffer[1 << 16];
        const ssize_t n = ::recv(fd, buffer, sizeof buffer, MSG_DONTWAIT);
        if (n < 0) return;
        const int to = peers_.at(fd);
        const auto bytes = static_cast<std::size_t>(std::max<ssize_t>(n, 0));
        queue_.push_back({std::chrono::steady_clock::now() + delay_, to, std::string(buffer, bytes)});
        if (n == 0) ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
    }

    void send_due() {
        const auto now = std::chrono::steady_clock::now();
        while (!queue_.empty() && queue_.front().due <= now) {
            const Chunk& c = queue_.front();
            if (c.bytes.empty()) {
                ::shutdown(c.to, SHUT_WR);
            } else {
                for (std::size_t done = 0; done < c.bytes.size();) {
                    const ssize_t n = ::send(c.to, c.bytes.data() + done, c.bytes.size() - done, MSG_NOSIGNAL);
                    if (n <= 0) break;
                    done += static_cast<std::size_t>(n);
                }
            }
            queue_.pop_front();
        }
    }

    int timeout_ms() const {
        if (queue_.empty()) return 50;
        using std::chrono::steady_clock, std::chrono::microseconds;
        const auto wait = std::chrono::duration_cast<microseconds>(queue_.front().due - steady_clock::now());
        return static_cast<int>(std::clamp<long long>((wait.count() + 999) / 1000, 0, 50));
    }

    void run() {
        epoll_event events[64];
        while (!stop_) {
            const int n = ::epoll_wait(epoll_, events, 64, timeout_ms());
            for (int i = 0; i < n; ++i) {
                if (events[i].data.fd == listener_) {
                    accept_one();
                } else {
                    read_from(events[i].data.fd);
                }
            }
            send_due();
        }
    }

    int upstream_, port_ = 0, listener_ = -1, epoll_ = -1;
    std::chrono::microseconds delay_;
    std::map<int, int> peers_;
    std::deque<Chunk> queue_;
    std::atomic<bool> stop_{false};
    std::thread thread_;
};

}  // namespace lidarscout::test
