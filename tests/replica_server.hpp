// A test fixture: the replica object server (tests/replica_server.py, Python 3's standard library)
// serving a virtual replica's tiles (a replicate.json manifest) on 127.0.0.1 at an ephemeral port:
// /tiles/NAME over HTTP (multi-range), s3://BUCKET/NAME (one range per GET, ListObjectsV2),
// /catalog.vpc (every tile's STAC item, generated on the fly), /search (a paged STAC API) and
// /_stats (requests and bytes per kind), with an optional round trip and bandwidth (and a search's last
// page held until release()). The server
// writes its port to a file once it listens; it is stopped when the fixture is destroyed (and
// killed with the process if that dies), as nginx_server.hpp and s3_server.hpp do. Used by
// tests/replica_server_test.cpp and bench_http --replica.
#pragma once

#include <curl/curl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cctype>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "child_process.hpp"
#include "test_paths.hpp"

namespace lidarscout::test {

class ReplicaServer {
public:
    struct Options {
        std::string program = LIDARSCOUT_CLI;  // the lidarscout CLI: its `catalog` gives the sources' items
        double rtt_ms = 0;                     // each response's delay (a new connection's first: twice)
        std::uint64_t bandwidth = 0;           // bytes/s per connection; 0: unlimited
        std::string bucket = "replica";        // the S3 bucket's name
        std::string overview;                  // an overview sidecar to serve (and name in the VPC); "" none
        bool hold_last_page = false;           // a search's last page (of several) answered after release()
        int port = 0;                          // 0: an ephemeral one (another: a server restarted on its port)
    };

    // A server of the replica `manifest`, started at once; throws when it does not start (its
    // one-line reason, from its log, in the message).
    explicit ReplicaServer(const std::filesystem::path& manifest) : ReplicaServer(manifest, Options()) {}
    ReplicaServer(const std::filesystem::path& manifest, const Options& options) : bucket_(options.bucket) {
        dir_ = std::filesystem::temp_directory_path() /
               ("lidarscout_replica_" + std::to_string(::getpid()) + "_" + std::to_string(++count()));
        std::filesystem::create_directories(dir_);
        start(manifest, options);
    }
    ReplicaServer(const ReplicaServer&) = delete;
    ReplicaServer& operator=(const ReplicaServer&) = delete;
    ~ReplicaServer() { stop_server(pid_, dir_); }

    int port() const { return port_; }
    std::string endpoint() const { return "http://127.0.0.1:" + std::to_string(port_); }
    std::string url(const std::string& path) const { return endpoint() + "/" + path; }
    std::string tile_url(const std::string& name) const { return url("tiles/" + name); }
    std::string catalog_url() const { return url("catalog.vpc"); }
    std::string s3_url(const std::string& key = "") const { return "s3://" + bucket_ + "/" + key; }
    const std::string& bucket() const { return bucket_; }

    // The environment (shell assignments, ending in a space) that points a program's s3:// URLs at
    // this server (any key is accepted).
    std::string s3_environment() const {
        return "AWS_SHARED_CREDENTIALS_FILE=/dev/null AWS_CONFIG_FILE=/dev/null AWS_ENDPOINT_URL=" + endpoint() +
               " AWS_ACCESS_KEY_ID=replica AWS_SECRET_ACCESS_KEY=replica ";
    }

    struct Reply {
        long status = 0;
        std::string content_type, content_range, etag, last_modified, body;
        std::uint64_t content_length = 0;
    };

    // One request for `path` (GET, or HEAD with `head`), with the given header lines ("Range: ...").
    Reply fetch(const std::string& path, const std::vector<std::string>& headers = {}, bool head = false) const {
        Reply r;
        CURL* easy = curl_easy_init();
        const std::string target = url(path);
        curl_slist* list = nullptr;
        for (const auto& h : headers) list = curl_slist_append(list, h.c_str());
        curl_easy_setopt(easy, CURLOPT_URL, target.c_str());
        curl_easy_setopt(easy, CURLOPT_HTTPHEADER, list);
        curl_easy_setopt(easy, CURLOPT_NOBODY, head ? 1L : 0L);
        const auto body = +[](char* p, std::size_t s, std::size_t n, void* out) {
            static_cast<std::string*>(out)->append(p, s * n);
            return s * n;
        };
        const auto header = +[](char* p, std::size_t s, std::size_t n, void* out) {
            const std::string line(p, s * n);
            auto& reply = *static_cast<Reply*>(out);
            const auto colon = line.find(':');
            if (colon != std::string::npos) {
                std::string name = line.substr(0, colon), v = line.substr(colon + 1);
                for (auto& c : name) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
                v.erase(0, v.find_first_not_of(' '));
                v.erase(v.find_last_not_of("\r\n ") + 1);
                if (name == "content-type") reply.content_type = v;
                if (name == "content-range") reply.content_range = v;
                if (name == "etag") reply.etag = v;
                if (name == "last-modified") reply.last_modified = v;
                if (name == "content-length") reply.content_length = std::stoull(v);
            }
            return s * n;
        };
        curl_easy_setopt(easy, CURLOPT_WRITEFUNCTION, body);
        curl_easy_setopt(easy, CURLOPT_WRITEDATA, &r.body);
        curl_easy_setopt(easy, CURLOPT_HEADERFUNCTION, header);
        curl_easy_setopt(easy, CURLOPT_HEADERDATA, &r);
        const CURLcode code = curl_easy_perform(easy);
        curl_easy_getinfo(easy, CURLINFO_RESPONSE_CODE, &r.status);
        curl_slist_free_all(list);
        curl_easy_cleanup(easy);
        if (code != CURLE_OK) throw std::runtime_error("replica server: " + target + ": " + curl_easy_strerror(code));
        return r;
    }

    // Lets the server answer the search pages it holds (Options::hold_last_page), and those asked later.
    void release() const { fetch("_release"); }

    // The server's counters (GET /_stats): requests and bytes per kind, tiles touched, ...; with
    // `reset`, counting starts again after this answer.
    nlohmann::json stats(bool reset = false) const {
        return nlohmann::json::parse(fetch(reset ? "_stats?reset=1" : "_stats").body);
    }

private:
    static int& count() {
        static int n = 0;
        return n;
    }

    void start(const std::filesystem::path& manifest, const Options& o) {
        const std::string script = std::string(LIDARSCOUT_SOURCE_DIR) + "/tests/replica_server.py";
        const std::string port_file = (dir_ / "port").string(), log = (dir_ / "server.log").string();
        const std::string m = std::filesystem::absolute(manifest).string(), rtt = std::to_string(o.rtt_ms);
        const std::string bandwidth = std::to_string(o.bandwidth);
        std::vector<const char*> args = {"python3", script.c_str(), m.c_str(), "--port-file", port_file.c_str(),
                                         "--program", o.program.c_str(), "--bucket", o.bucket.c_str(),
                                         "--rtt-ms", rtt.c_str(), "--bandwidth", bandwidth.c_str()};
        if (!o.overview.empty()) args.insert(args.end(), {"--overview", o.overview.c_str()});
        if (o.hold_last_page) args.push_back("--hold-last-page");
        const std::string port = std::to_string(o.port);
        args.insert(args.end(), {"--port", port.c_str()});
        args.push_back(nullptr);  // (made before the fork: the child only calls exec)
        pid_ = ::fork();
        if (pid_ == 0) {
            ::prctl(PR_SET_PDEATHSIG, SIGTERM);
            std::freopen(log.c_str(), "w", stderr);
            ::execv("/usr/bin/python3", const_cast<char* const*>(args.data()));
            ::_exit(127);
        }
        // (152,100 tiles take some seconds: the manifest, the sources' items, every item's length)
        for (int i = 0; i < 12000 && port_ == 0; ++i) {
            if (::waitpid(pid_, nullptr, WNOHANG) == pid_) {
                pid_ = -1;
                break;
            }
            std::ifstream in(port_file);
            in >> port_;
            if (port_ == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        if (port_ == 0) {
            std::ifstream in(log);
            const std::string why((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
            stop_server(pid_, dir_);
            pid_ = -1;
            throw std::runtime_error("the replica server (tests/replica_server.py) did not start: " + why);
        }
    }

    std::filesystem::path dir_;
    std::string bucket_;
    pid_t pid_ = -1;
    int port_ = 0;
};

}  // namespace lidarscout::test
