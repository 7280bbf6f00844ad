// The HTTP side of `lidarscout serve`: routes, access checks, bounds and the response headers.
#include "serve/server.hpp"

#include <httplib.h>
#include <nlohmann/json.hpp>

#include <charconv>

#include <fmt/format.h>

#include "core/error.hpp"
#include "render/colour_modes.hpp"
#include "serve/client_link.hpp"
#include "serve/encoding.hpp"
#include "serve/gzip.hpp"

namespace lidarscout::serve {
namespace {

// Content types httplib leaves alone (it compresses text/* and plain "application/json" itself):
// these bodies are gzip'd already, once, in the cache.
const std::string kJson = "application/json; charset=utf-8";
const std::string kBinary = "application/octet-stream";
const std::string kImmutable = "public, max-age=86400";  // content named by what it holds
const std::string kRevalidate = "no-cache";             // may change while loading: ask with the ETag
constexpr std::size_t kMaxPayload = 1024;               // GET only: no body worth more
constexpr int kBacklog = 1024;                          // connections waiting to be accepted

bool accepts_gzip(const httplib::Request& req) {
    return req.get_header_value("Accept-Encoding").find("gzip") != std::string::npos;
}

std::int32_t parse_int32(std::string_view text, const std::string& whole) {
    std::int32_t v = 0;
    const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
    if (text.empty() || ec != std::errc() || end != text.data() + text.size()) {
        throw Error("'" + whole.substr(0, 60) + "': '" + std::string(text.substr(0, 20)) + "' is not an int32");
    }
    return v;
}

CellKey parse_cell(std::string_view pair, const std::string& whole) {
    const std::size_t comma = pair.find(',');
    if (comma == std::string_view::npos) throw Error("cells '" + whole.substr(0, 60) + "': a cell is IX,IY");
    return {parse_int32(pair.substr(0, comma), whole), parse_int32(pair.substr(comma + 1), whole)};
}

EncodedPtr palette_body() {
    nlohmann::json ramp = nlohmann::json::array(), classes = nlohmann::json::array();
    for (int i = 0; i < 256; ++i) {
        ramp.push_back(render::elevation_ramp(static_cast<float>(i) / 255.0f) & 0xffffffu);
        classes.push_back(render::classification_colour(static_cast<std::uint8_t>(i)) & 0xffffffu);
    }
    return encode(nlohmann::json{{"elevation", ramp}, {"classes", classes}}.dump(), 0);
}

void refuse(httplib::Response& res, int status, const std::string& why) {
    res.status = status;
    res.set_content(why + "\n", "text/plain; charset=utf-8");
}

int parse_dimension(const httplib::Request& req, const char* name, int fallback, int lo, int hi) {
    if (!req.has_param(name)) return fallback;
    const int v = parse_int32(req.get_param_value(name), req.get_param_value(name));
    if (v < lo || v > hi) throw Error(std::string(name) + " out of range");
    return v;
}

// ?attrs=rgb,class,intensity (all of them when absent).
std::uint32_t attributes_of(const httplib::Request& req) {
    return req.has_param("attrs") ? parse_attributes(req.get_param_value("attrs")) : kAllAttributes;
}

// Whether the client of `req` has gone (its socket looked up on the first call).
ClientGone client_gone(const httplib::Request& req) {
    auto link = std::make_shared<ClientLink>(
        ConnectionEnds{req.local_addr, req.local_port, req.remote_addr, req.remote_port});
    return [link] { return link->gone(); };
}

}  // namespace

std::vector<CellKey> parse_cells(const std::string& text) {
    std::vector<CellKey> cells;
    std::string_view rest(text);
    while (!rest.empty()) {
        if (cells.size() == kMaxCellsPerRequest) {
            throw Error("more than " + std::to_string(kMaxCellsPerRequest) + " cells in one request");
        }
        const std::size_t semi = rest.find(';');
        cells.push_back(parse_cell(rest.substr(0, semi), text));
        rest = semi == std::string_view::npos ? std::string_view() : rest.substr(semi + 1);
    }
    if (cells.empty()) throw Error("no cells asked for");
    return cells;
}

Server::Server(std::vector<std::unique_ptr<Survey>> surveys, ServerOptions options,
               std::unique_ptr<ResponseCache> cache)
    : surveys_(std::move(surveys)), options_(std::move(options)), cache_(std::move(cache)) {
    check_access_rule(options_.listen, options_.token);
    assets_ = read_web_assets(options_.web_dir);
    palette_ = palette_body();
    http_ = std::make_unique<httplib::Server>();
    const unsigned threads = options_.threads;
    http_->new_task_queue = [threads] { return new httplib::ThreadPool(threads); };
    http_->set_keep_alive_timeout(2);
    http_->set_keep_alive_max_count(1000);
    http_->set_payload_max_length(kMaxPayload);
    routes();
}

Server::~Server() { stop(); }

int Server::bind() {
    const std::string& host = options_.listen.host;
    port_ = options_.listen.port == 0 ? http_->bind_to_any_port(host) : options_.listen.port;
    const bool ok = options_.listen.port == 0 ? port_ > 0 : http_->bind_to_port(host, port_);
    if (!ok) throw Error("serve: cannot listen on " + host + ":" + std::to_string(options_.listen.port));
    widen_backlog(port_, kBacklog);  // (httplib's is 5)
    return port_;
}

std::string Server::url() const {
    const std::string& h = options_.listen.host;
    const std::string host = h.find(':') != std::string::npos ? "[" + h + "]" : h;
    const std::string query = options_.token.empty() ? "" : "?token=" + options_.token;
    return "http://" + host + ":" + std::to_string(port_) + "/" + query;
}

void Server::run() { http_->listen_after_bind(); }

void Server::stop() {
    if (http_) http_->stop();
}

bool Server::authorised(const httplib::Request& req) const {
    if (options_.token.empty()) return true;
    const std::string bearer = req.get_header_value("Authorization");
    if (bearer.rfind("Bearer ", 0) == 0 && same_token(std::string_view(bearer).substr(7), options_.token)) return true;
    return req.has_param("token") && same_token(req.get_param_value("token"), options_.token);
}

// The raw request path (before httplib decodes it): no "..", backslash, percent-encoding or NUL.
bool Server::safe_path(const httplib::Request& req) const {
    const std::string path = req.target.substr(0, req.target.find('?'));
    return !path.empty() && path.front() == '/' && path.find("..") == std::string::npos &&
           path.find_first_of(std::string("%\\\0", 3)) == std::string::npos && path.size() <= 256;
}

void Server::send(const httplib::Request& req, httplib::Response& res, const Encoded& body, const std::string& type,
                  const std::string& cache_control) const {
    res.set_header("ETag", body.etag);
    res.set_header("Cache-Control", cache_control);
    res.set_header("Vary", "Accept-Encoding");
    if (req.get_header_value("If-None-Match") == body.etag) {
        res.status = 304;
        return;
    }
    if (accepts_gzip(req)) {
        res.set_header("Content-Encoding", "gzip");
        res.set_content(body.gzipped, type);
    } else {
        res.set_content(gunzip(body.gzipped), type);
    }
}

void Server::send_fresh(const httplib::Request& req, httplib::Response& res, const std::string& body,
                        const std::string& type) const {
    send(req, res, *encode(body, 0), type, kRevalidate);
}

Survey* Server::survey_of(const httplib::Request& req, httplib::Response& res) const {
    const std::string index = req.matches[1];
    std::size_t i = 0;
    const auto [end, ec] = std::from_chars(index.data(), index.data() + index.size(), i);
    if (ec != std::errc() || end != index.data() + index.size() || i >= surveys_.size()) {
        refuse(res, 404, "no such dataset");
        return nullptr;
    }
    return surveys_[i].get();
}

// A route whose handler runs only while its client has fewer than max_in_flight_per_client
// requests under way (429 otherwise).
void Server::get(const std::string& pattern, Handler handler) {
    http_->Get(pattern, [this, handler = std::move(handler)](const httplib::Request& req, httplib::Response& res) {
        {
            std::lock_guard lock(in_flight_mutex_);
            if (in_flight_[req.remote_addr] >= options_.max_in_flight_per_client) {
                res.set_header("Retry-After", "1");
                return refuse(res, 429, "too many requests at once");
            }
            ++in_flight_[req.remote_addr];
            ++requests_;
        }
        struct Done {
            Server* s;
            const std::string& addr;
            ~Done() {
                std::lock_guard lock(s->in_flight_mutex_);
                if (--s->in_flight_[addr] <= 0) s->in_flight_.erase(addr);
            }
        } done{this, req.remote_addr};
        handler(req, res);
    });
}

void Server::routes() {
    http_->set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
        if (!options_.cors_origin.empty()) res.set_header("Access-Control-Allow-Origin", options_.cors_origin);
        if (!safe_path(req)) return refuse(res, 400, "refused: a path with '..', '%', '\\' or too long"),
                                    httplib::Server::HandlerResponse::Handled;
        if (req.method != "GET" && req.method != "HEAD") {
            return refuse(res, 405, "only GET"), httplib::Server::HandlerResponse::Handled;
        }
        // The page's files hold no data (and its scripts' imports cannot carry the token): the API needs it.
        if (req.path.rfind("/api/", 0) == 0 && !authorised(req)) {
            return refuse(res, 403, "a token is needed"), httplib::Server::HandlerResponse::Handled;
        }
        return httplib::Server::HandlerResponse::Unhandled;
    });
    http_->set_exception_handler([](const httplib::Request&, httplib::Response& res, std::exception_ptr ep) {
        try {
            std::rethrow_exception(ep);
        } catch (const Error& e) {
            refuse(res, 400, e.what());
        } catch (const std::exception& e) {
            refuse(res, 500, e.what());
        }
    });
    get(R"(/([a-z0-9_\-]{1,64}\.(?:html|js|css))?)", [this](const httplib::Request& req, httplib::Response& res) {
        const std::string name = req.matches[1].length() ? std::string(req.matches[1]) : "index.html";
        const auto it = assets_.find(name);
        if (it == assets_.end()) return refuse(res, 404, "no such page file");
        res.set_header("Cache-Control", kRevalidate);
        res.set_header("ETag", it->second.body->etag);
        if (req.get_header_value("If-None-Match") == it->second.body->etag) {
            res.status = 304;
            return;
        }
        res.set_content(gunzip(it->second.body->gzipped), it->second.content_type);  // httplib compresses text
    });
    api_routes();
}

std::string Server::stats_json() const {
    int in_flight = 0;
    std::uint64_t requests = 0;
    {
        std::lock_guard lock(in_flight_mutex_);
        for (const auto& [addr, n] : in_flight_) in_flight += n;
        requests = requests_;
    }
    std::string body = fmt::format("{{\"requests\":{},\"in_flight\":{},"
                                   "\"cache\":{{\"bytes\":{},\"hits\":{},\"misses\":{}}},\"datasets\":[",
                                   requests, in_flight, cache_->bytes(), cache_->hits(), cache_->misses());
    for (std::size_t i = 0; i < surveys_.size(); ++i) body += (i ? "," : "") + surveys_[i]->stats_json();
    return body + "]}";
}

void Server::api_routes() {
    get("/api/info", [this](const httplib::Request& req, httplib::Response& res) {
        std::string body = "{\"datasets\":[";
        for (std::size_t i = 0; i < surveys_.size(); ++i) {
            if (i) body += ',';
            body += surveys_[i]->info_json(i);
        }
        body += "]}";
        send_fresh(req, res, body, kJson);
    });
    get("/api/stats", [this](const httplib::Request& req, httplib::Response& res) {
        send_fresh(req, res, stats_json(), kJson);
    });
    get("/api/palette", [this](const httplib::Request& req, httplib::Response& res) {
        send(req, res, *palette_, kJson, kImmutable);
    });
    get(R"(/api/d/(\d{1,4})/tiles)", [this](const httplib::Request& req, httplib::Response& res) {
        if (Survey* s = survey_of(req, res)) send(req, res, *s->tiles(), kJson, kRevalidate);
    });
    get(R"(/api/d/(\d{1,4})/cells)", [this](const httplib::Request& req, httplib::Response& res) {
        if (Survey* s = survey_of(req, res)) send_fresh(req, res, s->cells_body(), kBinary);
    });
    get(R"(/api/d/(\d{1,4})/points)", [this](const httplib::Request& req, httplib::Response& res) {
        Survey* s = survey_of(req, res);
        if (!s) return;
        const auto cells = parse_cells(req.get_param_value("cells"));
        send(req, res, *s->cell_points(cells, attributes_of(req)), kBinary, s->loaded() ? kImmutable : kRevalidate);
    });
    get(R"(/api/d/(\d{1,4})/heightmaps)", [this](const httplib::Request& req, httplib::Response& res) {
        Survey* s = survey_of(req, res);
        if (!s) return;
        const auto cells = parse_cells(req.get_param_value("cells"));
        const std::string method = req.has_param("method") ? req.get_param_value("method") : "linear";
        if (method != "linear" && method != "cnn") throw Error("unknown method '" + method.substr(0, 20) + "'");
        const int step = parse_dimension(req, "step", 1, 1, 16);
        const bool detail = req.has_param("detail") && req.get_param_value("detail") == "1";
        const auto body = s->heightmaps(cells, method == "cnn", step, detail, client_gone(req));
        if (!body) {
            res.set_header("Retry-After", "1");
            return refuse(res, 503, "the chunk points are still loading");
        }
        send(req, res, **body, kBinary, kImmutable);
    });
    get(R"(/api/d/(\d{1,4})/tile/(\d{1,9})/level/(\d))", [this](const httplib::Request& req, httplib::Response& res) {
        Survey* s = survey_of(req, res);
        if (!s) return;
        const auto level =
            s->level(std::stoul(req.matches[2]), std::stoi(req.matches[3]), attributes_of(req), client_gone(req));
        send(req, res, *level, kBinary, kImmutable);
    });
    get(R"(/api/d/(\d{1,4})/camera)", [this](const httplib::Request& req, httplib::Response& res) {
        Survey* s = survey_of(req, res);
        if (!s) return;
        const int w = parse_dimension(req, "w", 1280, 1, 16384), h = parse_dimension(req, "h", 720, 1, 16384);
        const int fov = parse_dimension(req, "fov", 60, 1, 179);
        std::optional<std::size_t> tile;
        if (req.has_param("tile")) tile = static_cast<std::size_t>(parse_dimension(req, "tile", 0, 0, INT32_MAX));
        send_fresh(req, res, s->auto_camera_json(w, h, fov, tile), kJson);
    });
}

}  // namespace lidarscout::serve
