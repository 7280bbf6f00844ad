// Benchmark: `lidarscout serve` under N concurrent clients on loopback (issue 56). Starts the
// program on a dataset (default: the 2,025-tile virtual replica, `synth replicate --virtual`) and,
// once it prints its URL, N clients at once, each doing what the page does: info, palette, auto
// camera, tiles; then the cells and their chunk points in batches of 64 cells with 4 requests in
// flight until the server has loaded every chunk point and the client has them all (its first
// overview), then the heightmap patches of the 64 cells nearest the data's centre in batches of
// 16 (its first terrain), then levels 0-2 of the full-resolution points of the 4 central tiles (its
// full resolution). Reports per client the seconds to the first overview and terrain
// and to full resolution (median, max), requests that failed, the bytes on the wire (gzip) per chunk point, and for the
// server its resident size (sampled every 20 ms, and its high-water mark) against --memory and the
// CPU seconds it spent per client.
// Usage: bench_serve [--clients N] [--memory SIZE] [DATASET]
#include <fmt/format.h>

#include <atomic>
#include <cstring>
#include <map>
#include <cmath>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "bench_main.hpp"
#include "bench_timing.hpp"
#include "serve/gzip.hpp"
#include "serve/serve_fixture.hpp"

namespace {

using lidarscout::bench::Clock;
using lidarscout::bench::seconds_since;

const char* kUsage = "[--clients N] [--memory SIZE] [DATASET (default /work/bench-data/replica-2025)]";

struct ClientResult {
    double overview_s = -1, terrain_s = -1, full_res_s = -1;
    std::uint64_t points = 0, wire_point_bytes = 0, failures = 0, level_bytes = 0;
};

struct Cell {
    std::int32_t ix, iy;
    std::uint32_t n;
};

template <typename T>
T read_at(const std::string& s, std::size_t offset) {
    T v;
    std::memcpy(&v, s.data() + offset, sizeof v);
    return v;
}

std::vector<Cell> parse_cell_list(const std::string& body) {
    std::vector<Cell> out(body.size() >= 4 ? read_at<std::uint32_t>(body, 0) : 0);
    for (std::size_t i = 0; i < out.size(); ++i) {
        out[i] = {read_at<std::int32_t>(body, 4 + 12 * i), read_at<std::int32_t>(body, 8 + 12 * i),
                  read_at<std::uint32_t>(body, 12 + 12 * i)};
    }
    return out;
}

std::string cell_list(const std::vector<Cell>& cells, std::size_t from, std::size_t count) {
    std::string s;
    for (std::size_t i = from; i < std::min(cells.size(), from + count); ++i) {
        s += (s.empty() ? "" : ";") + std::to_string(cells[i].ix) + "," + std::to_string(cells[i].iy);
    }
    return s;
}

class Client {
public:
    explicit Client(int port) : port_(port) {}

    ClientResult run() {
        const auto t0 = Clock::now();
        for (const char* path :
             {"/", "/app.js", "/api/info", "/api/palette", "/api/d/0/camera?w=1280&h=720&fov=60", "/api/d/0/tiles"}) {
            get(path);
        }
        std::vector<Cell> cells;
        for (bool finished = false; !finished;) {
            const auto info = nlohmann::json::parse(get("/api/info"));
            finished = info["datasets"][0]["loading"]["finished"].get<bool>();
            cells = parse_cell_list(get("/api/d/0/cells"));
            fetch_points(cells);
            if (!finished) std::this_thread::sleep_for(std::chrono::milliseconds(250));
        }
        result_.overview_s = seconds_since(t0);
        fetch_terrain(cells);
        result_.terrain_s = seconds_since(t0);
        fetch_levels(nlohmann::json::parse(get("/api/d/0/tiles")));
        result_.full_res_s = seconds_since(t0);
        return result_;
    }

private:
    std::string get(const std::string& path, bool points = false) {
        httplib::Client c("127.0.0.1", port_);
        c.set_decompress(false);
        c.set_read_timeout(120, 0);  // a level waits for its tile's decoding (two at a time)
        const auto res = c.Get(path, {{"Accept-Encoding", "gzip"}});
        std::lock_guard lock(mutex_);
        if (!res || res->status != 200) {
            ++result_.failures;
            return {};
        }
        if (points) result_.wire_point_bytes += res->body.size();
        return res->get_header_value("Content-Encoding") == "gzip" ? lidarscout::serve::gunzip(res->body) : res->body;
    }

    // The cells whose points it does not have yet (or fewer than listed), 64 a request, 4 at once.
    void fetch_points(const std::vector<Cell>& cells) {
        std::vector<Cell> wanted;
        for (const auto& c : cells) {
            auto& have = have_[(static_cast<std::int64_t>(c.ix) << 32) ^ static_cast<std::uint32_t>(c.iy)];
            if (have < c.n) wanted.push_back(c), result_.points += c.n - have, have = c.n;
        }
        in_parallel(wanted, 64, "/api/d/0/points?cells=", true);
    }

    void fetch_terrain(std::vector<Cell> cells) {
        double cx = 0, cy = 0;
        for (const auto& c : cells) cx += c.ix, cy += c.iy;
        cx /= std::max<std::size_t>(1, cells.size()), cy /= std::max<std::size_t>(1, cells.size());
        std::sort(cells.begin(), cells.end(), [&](const Cell& a, const Cell& b) {
            return std::hypot(a.ix - cx, a.iy - cy) < std::hypot(b.ix - cx, b.iy - cy);
        });
        cells.resize(std::min<std::size_t>(cells.size(), 64));
        in_parallel(cells, 16, "/api/d/0/heightmaps?cells=", false);
    }

    // Levels 0-2 of the 4 tiles nearest the data's centre (the page's full resolution near the camera),
    // the RGB mode's attributes, 4 requests at once.
    void fetch_levels(const nlohmann::json& tiles) {
        const auto& boxes = tiles["boxes_dm"];
        const std::size_t n = tiles["names"].size();
        double cx = 0, cy = 0;
        for (std::size_t i = 0; i < n; ++i) cx += boxes[6 * i].get<double>() + boxes[6 * i + 3].get<double>(),
                                          cy += boxes[6 * i + 1].get<double>() + boxes[6 * i + 4].get<double>();
        cx /= 2.0 * std::max<std::size_t>(1, n), cy /= 2.0 * std::max<std::size_t>(1, n);
        std::vector<std::pair<double, std::size_t>> order;
        for (std::size_t i = 0; i < n; ++i) {
            const double x = 0.5 * (boxes[6 * i].get<double>() + boxes[6 * i + 3].get<double>());
            const double y = 0.5 * (boxes[6 * i + 1].get<double>() + boxes[6 * i + 4].get<double>());
            order.emplace_back(std::hypot(x - cx, y - cy), i);
        }
        std::sort(order.begin(), order.end());
        std::vector<std::string> paths;
        for (int level = 0; level < 3; ++level) {
            for (std::size_t k = 0; k < std::min<std::size_t>(4, n); ++k) {
                paths.push_back(fmt::format("/api/d/0/tile/{}/level/{}?attrs=rgb565,class", order[k].second, level));
            }
        }
        std::atomic<std::size_t> next{0};
        std::atomic<std::uint64_t> bytes{0};
        std::vector<std::thread> threads;
        for (int t = 0; t < 4; ++t) {
            threads.emplace_back([&] {
                for (std::size_t i; (i = next.fetch_add(1)) < paths.size();) bytes += get(paths[i]).size();
            });
        }
        for (auto& t : threads) t.join();
        result_.level_bytes = bytes;
    }

    void in_parallel(const std::vector<Cell>& cells, std::size_t batch, const std::string& path, bool points) {
        std::atomic<std::size_t> next{0};
        std::vector<std::thread> threads;
        for (int t = 0; t < 4; ++t) {
            threads.emplace_back([&] {
                for (std::size_t i; (i = next.fetch_add(batch)) < cells.size();) {
                    get(path + cell_list(cells, i, batch), points);
                }
            });
        }
        for (auto& t : threads) t.join();
    }

    int port_;
    std::mutex mutex_;
    ClientResult result_;
    std::map<std::int64_t, std::uint32_t> have_;
};

// VmRSS or VmHWM of a process, bytes.
std::uint64_t status_bytes(pid_t pid, const std::string& field) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/status");
    for (std::string line; std::getline(in, line);) {
        if (line.rfind(field + ":", 0) == 0) return std::stoull(line.substr(field.size() + 1)) * 1024;
    }
    return 0;
}

double cpu_seconds(pid_t pid) {
    std::ifstream in("/proc/" + std::to_string(pid) + "/stat");
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::istringstream fields(text.substr(text.rfind(')') + 2));
    std::string f;
    std::uint64_t utime = 0, stime = 0;
    for (int i = 3; i <= 15 && fields >> f; ++i) {
        if (i == 14) utime = std::stoull(f);
        if (i == 15) stime = std::stoull(f);
    }
    return static_cast<double>(utime + stime) / static_cast<double>(sysconf(_SC_CLK_TCK));
}

int run(int argc, char** argv) {
    int clients = 20;
    std::string memory = "1G", dataset = "/work/bench-data/replica-2025";
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        if (a == "--clients" && i + 1 < argc) clients = std::stoi(argv[++i]);
        else if (a == "--memory" && i + 1 < argc) memory = argv[++i];
        else dataset = a;
    }
    const auto start = Clock::now();
    lidarscout::test::ServeChild server("'" + dataset + "' --memory " + memory);
    const std::string url = server.url();
    if (url.rfind("http://127.0.0.1:", 0) != 0) throw lidarscout::Error("the server did not start: '" + url + "'");
    const double listening_s = seconds_since(start);
    const int port = std::stoi(url.substr(17));
    const double cpu0 = cpu_seconds(server.pid);
    std::atomic<bool> done{false};
    std::uint64_t max_rss = 0;
    std::thread sampler([&] {
        while (!done) {
            max_rss = std::max(max_rss, status_bytes(server.pid, "VmRSS"));
            std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    });
    std::vector<ClientResult> results(clients);
    std::vector<std::thread> threads;
    for (int c = 0; c < clients; ++c) threads.emplace_back([&, c] { results[c] = Client(port).run(); });
    for (auto& t : threads) t.join();
    done = true;
    sampler.join();
    const double cpu = cpu_seconds(server.pid) - cpu0;
    std::vector<double> overview, terrain, full_res;
    std::uint64_t failures = 0, points = 0, bytes = 0;
    for (const auto& r : results) {
        overview.push_back(r.overview_s), terrain.push_back(r.terrain_s), full_res.push_back(r.full_res_s);
        failures += r.failures, points += r.points, bytes += r.wire_point_bytes;
    }
    fmt::print("bench_serve: {} ({} clients, --memory {}); listening after {:.2f} s\n", dataset, clients, memory,
               listening_s);
    fmt::print("first overview per client: median {:.2f} s, max {:.2f} s; first terrain (64 patches): median {:.2f} "
               "s, max {:.2f} s\n",
               lidarscout::bench::median(overview), *std::max_element(overview.begin(), overview.end()),
               lidarscout::bench::median(terrain), *std::max_element(terrain.begin(), terrain.end()));
    fmt::print("full resolution (levels 0-2 of the 4 central tiles): median {:.2f} s, max {:.2f} s\n",
               lidarscout::bench::median(full_res), *std::max_element(full_res.begin(), full_res.end()));
    fmt::print("chunk points per client {}, {:.2f} bytes each on the wire (gzip); failed requests {}\n",
               points / std::max(1, clients), static_cast<double>(bytes) / std::max<std::uint64_t>(1, points),
               failures);
    fmt::print("server: resident at most {:.0f} MiB sampled, high-water mark {:.0f} MiB; CPU {:.2f} s, {:.3f} s per "
               "client\n", max_rss / 1048576.0, status_bytes(server.pid, "VmHWM") / 1048576.0, cpu, cpu / clients);
    return failures ? 3 : 0;
}

}  // namespace

int main(int argc, char** argv) { return lidarscout::bench::bench_main("bench_serve", kUsage, argc, argv, run); }
