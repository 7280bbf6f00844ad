// `lidarscout serve`'s HTTP server (cpp-httplib, Debian libcpp-httplib-dev): the page's files
// from memory and the binary API over the served surveys, every path naming a survey by index.
//
//   GET /                          the page (index.html), /NAME.js|.css its other files
//   GET /api/info                  JSON: the surveys, their frames, bounds and loading progress
//   GET /api/palette               JSON: render's elevation ramp and class colours
//   GET /api/d/N/tiles             JSON: tile names and boxes (decimetres from the grid origin)
//   GET /api/d/N/cells             the cells holding chunk points so far (binary)
//   GET /api/d/N/points?cells=..   chunk points of up to 256 cells "ix,iy;ix,iy" (encoding.hpp)
//                                  (these two with &attrs=rgb,class,intensity: the attributes sent, all by default)
//   GET /api/d/N/heightmaps?cells= heightmap patches, &method=linear (default) or cnn (the network, with
//                                  --model), &step=1|2|4|8|16 (texels that many times as large), &detail=1
//                                  (the decoded tiles' points laid over them); 503 until the chunk points are in
//   GET /api/d/N/tile/I/level/L    level of detail L (0-3) of tile I's full-resolution points
//   GET /api/d/N/camera?w=&h=&fov=[&tile=I]  render's auto camera for that image (of tile I)
//   GET /api/stats                 JSON: requests handled and in flight (this one included), the cache, and
//                                  per dataset the tiles decoded, heightmaps built and requests given up
//                                  because their client had gone
//
// Bodies are gzip'd once (a client that does not accept gzip gets them inflated), with a strong
// ETag (304 on If-None-Match) and Cache-Control. With a token every API request must carry it
// (?token= or Authorization: Bearer; the page's own files hold no data and need none). Paths
// with "..", a backslash or percent-encoding are refused before routing; requests in flight per
// client address and the cells per request are bounded; no CORS header unless an origin is given.
// A heightmap or level request whose client has gone (closed its connection: the page aborts what
// it no longer needs) stops before its next step (client_link.hpp), and one still waiting for a
// decoding slot leaves the queue: work queued for a gone client is never done.
#pragma once

#include <atomic>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "serve/listen_address.hpp"
#include "serve/response_cache.hpp"
#include "serve/survey.hpp"
#include "serve/web_assets.hpp"

namespace httplib {
class Server;
struct Request;
struct Response;
}  // namespace httplib

namespace lidarscout::serve {

struct ServerOptions {
    ListenAddress listen;
    std::string token;
    std::string cors_origin;            // empty: no CORS headers
    std::uint64_t memory_budget = 0;    // the response cache's share (bytes)
    std::string web_dir;                // the page's folder
    unsigned threads = 64;              // connections served at once
    int max_in_flight_per_client = 128;  // requests at once from one address (loopback: every local client)
};

class Server {
public:
    // Checks the access rule and reads the page; opens nothing on the network yet.
    Server(std::vector<std::unique_ptr<Survey>> surveys, ServerOptions options, std::unique_ptr<ResponseCache> cache);
    ~Server();
    Server(const Server&) = delete;
    Server& operator=(const Server&) = delete;

    // Binds and listens; returns the port (the chosen one for port 0). Throws lidarscout::Error.
    int bind();
    // The page's URL, with ?token= when one is set.
    std::string url() const;
    // Serves until stop() (from another thread or a signal handler's thread).
    void run();
    void stop();

    ResponseCache& cache() { return *cache_; }
    // /api/stats's body.
    std::string stats_json() const;

private:
    bool authorised(const httplib::Request& req) const;
    bool safe_path(const httplib::Request& req) const;
    using Handler = std::function<void(const httplib::Request&, httplib::Response&)>;
    void get(const std::string& pattern, Handler handler);
    void routes();
    void api_routes();
    Survey* survey_of(const httplib::Request& req, httplib::Response& res) const;
    void send(const httplib::Request& req, httplib::Response& res, const Encoded& body, const std::string& type,
              const std::string& cache_control) const;
    void send_fresh(const httplib::Request& req, httplib::Response& res, const std::string& body,
                    const std::string& type) const;

    std::vector<std::unique_ptr<Survey>> surveys_;
    ServerOptions options_;
    std::unique_ptr<ResponseCache> cache_;
    std::map<std::string, WebAsset> assets_;
    EncodedPtr palette_;
    std::unique_ptr<httplib::Server> http_;
    int port_ = 0;
    mutable std::mutex in_flight_mutex_;
    std::map<std::string, int> in_flight_;  // requests under way per client address
    std::uint64_t requests_ = 0;            // API and page requests handled (under in_flight_mutex_)
};

// Parses "ix,iy;ix,iy;..." (at most kMaxCellsPerRequest cells, each number an int32); throws
// lidarscout::Error naming what is wrong.
std::vector<CellKey> parse_cells(const std::string& text);

}  // namespace lidarscout::serve
