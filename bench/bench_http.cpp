// Benchmark: the overview of a remote dataset (issue 18). nginx serves a local dataset folder
// on loopback; a delaying proxy in front of it adds a round-trip latency (each direction
// delayed by half of it; tc netem needs a kernel module that is not always there). For each
// latency: seconds for all headers and chunk tables, seconds and rate for all chunk points,
// HTTP requests (per tile), and bytes moved (response bodies and headers) against the bytes
// of the dataset. Every run starts cold: no open remote file, no range cache.
// Every figure is the median of --runs runs (default 3).
// Usage: bench_http [--runs N] [--rtt-ms 0,20,50] FOLDER
#include <fcntl.h>
#include <fmt/format.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/epoll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <deque>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "bench_timing.hpp"
#include "core/error.hpp"
#include "dataset/chunk_point_loader.hpp"
#include "dataset/dataset.hpp"
#include "dataset/file_search.hpp"
#include "dataset/patch_grid.hpp"
#include "net/http_client.hpp"
#include "net/range_cache.hpp"
#include "net/remote_file.hpp"
#include "nginx_server.hpp"

using namespace lidarscout;

namespace {

using bench::Clock;
using bench::median;
using bench::seconds_since;

int loopback_listener(int& port) {
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

int connect_loopback(int port) {
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

// A TCP proxy on loopback that delivers every byte `one_way` later than it arrived, in each
// direction (one thread, epoll; chunks leave in arrival order, so one FIFO suffices).
class DelayProxy {
public:
    DelayProxy(int upstream_port, std::chrono::microseconds one_way) : upstream_(upstream_port), delay_(one_way) {
        listener_ = loopback_listener(port_);
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
        Clock::time_point due;
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
        const int server = connect_loopback(upstream_);
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
        queue_.push_back({Clock::now() + delay_, to, std::string(buffer, bytes)});
        if (n == 0) ::epoll_ctl(epoll_, EPOLL_CTL_DEL, fd, nullptr);
    }

    void send_due() {
        const auto now = Clock::now();
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
        const auto wait = std::chrono::duration_cast<std::chrono::microseconds>(queue_.front().due - Clock::now());
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

struct Run {
    double headers = 0, chunk_points = 0, rate = 0;
    std::uint64_t requests = 0, header_requests = 0, retries = 0, bytes = 0, tiles = 0, points = 0;
};

Run run_once(const std::string& list_url) {
    net::RemoteFile::forget_all();
    const auto before = net::HttpClient::shared().stats();
    Run r;
    auto t0 = Clock::now();
    const auto ds = dataset::open_dataset({list_url});
    r.headers = seconds_since(t0);
    r.header_requests = net::HttpClient::shared().stats().requests - before.requests;
    r.tiles = ds.tiles.size();
    if (!ds.skipped.empty()) throw Error(ds.skipped.front().path + ": " + ds.skipped.front().error);
    const auto [ox, oy] = dataset::patch_grid_origin(ds);
    dataset::PatchGrid grid(ox, oy);
    dataset::ChunkPointLoader loader(ds, grid);
    t0 = Clock::now();
    loader.start();
    loader.wait();
    r.chunk_points = seconds_since(t0);
    r.points = loader.loaded();
    if (loader.failed() > 0) throw Error("chunk points failed: " + loader.errors().front().message());
    r.rate = static_cast<double>(r.points) / r.chunk_points;
    const auto after = net::HttpClient::shared().stats();
    r.requests = after.requests - before.requests;
    r.retries = after.retries - before.retries;
    r.bytes = (after.body_bytes - before.body_bytes) + (after.header_bytes - before.header_bytes);
    return r;
}

// Writes the server's lists/tiles.txt naming every tile of `folder` (relative URLs); returns
// its path on the server and adds the tiles' bytes to `dataset_bytes`.
std::string write_tile_list(const test::NginxServer& server, const std::filesystem::path& folder,
                            std::uint64_t& dataset_bytes) {
    std::ofstream list(server.lists_dir() / "tiles.txt");
    for (const auto& f : dataset::find_point_cloud_files({folder.string()}).files) {
        list << "../" << std::filesystem::relative(f, folder).string() << "\n";
        dataset_bytes += std::filesystem::file_size(f);
    }
    return "lists/tiles.txt";
}

}  // namespace

int main(int argc, char** argv) {
    int runs = 3;
    std::vector<int> rtts = {0, 20, 50};
    std::string folder;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--runs" && i + 1 < argc) {
            runs = std::max(1, std::atoi(argv[++i]));
        } else if (a == "--rtt-ms" && i + 1 < argc) {
            rtts.clear();
            std::string list = argv[++i];
            for (std::size_t at = 0; at <= list.size();) {
                const auto comma = std::min(list.find(',', at), list.size());
                rtts.push_back(std::atoi(list.substr(at, comma - at).c_str()));
                at = comma + 1;
            }
        } else {
            folder = a;
        }
    }
    if (folder.empty()) {
        fmt::print(stderr, "usage: bench_http [--runs N] [--rtt-ms 0,20,50] FOLDER\n");
        return 2;
    }
    try {
        net::RangeCache::configure({{}, 0});  // every run from the network
        test::NginxServer server(folder);
        std::uint64_t dataset_bytes = 0;
        const std::string list = write_tile_list(server, folder, dataset_bytes);
        for (const int rtt : rtts) {
            DelayProxy proxy(server.port(), std::chrono::microseconds(rtt * 500));
            const std::string url = "http://127.0.0.1:" + std::to_string(proxy.port()) + "/" + list;
            std::vector<double> headers, points, rate, requests, header_requests, retries, bytes;
            Run last;
            for (int k = 0; k < runs; ++k) {
                last = run_once(url);
                headers.push_back(last.headers);
                points.push_back(last.chunk_points);
                rate.push_back(last.rate);
                requests.push_back(static_cast<double>(last.requests));
                header_requests.push_back(static_cast<double>(last.header_requests));
                retries.push_back(static_cast<double>(last.retries));
                bytes.push_back(static_cast<double>(last.bytes));
            }
            fmt::print("rtt {:>3} ms: {} tiles, {} chunk points; headers+chunk tables {:.3f} s; chunk points {:.3f} s "
                       "({:.0f}/s); {:.0f} requests ({:.2f}/tile; {:.0f} before the chunk points, {:.0f} retries); "
                       "{:.1f} MB moved of {:.1f} GB ({:.4f}%)\n",
                       rtt, last.tiles, last.points, median(headers), median(points), median(rate), median(requests),
                       median(requests) / static_cast<double>(std::max<std::uint64_t>(1, last.tiles)),
                       median(header_requests), median(retries),
                       median(bytes) / 1e6, static_cast<double>(dataset_bytes) / 1e9,
                       100.0 * median(bytes) / static_cast<double>(dataset_bytes));
        }
    } catch (const std::exception& e) {
        fmt::print(stderr, "bench_http: {}\n", e.what());
        return 1;
    }
    return 0;
}
