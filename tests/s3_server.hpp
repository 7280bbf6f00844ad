// A test fixture: an S3 server (@20minutes/s3rver under node, tests/s3_server.js) on 127.0.0.1
// at an ephemeral port, storing what the tests put in a temp folder (removed at exit), with the
// buckets "tiles", "many" and "paid". It checks AWS Signature V4: requests signed with a wrong
// secret get SignatureDoesNotMatch; anonymous requests are served. One server per test process,
// stopped when the process exits (and killed with it if it dies), as nginx_server.hpp does.
// put() stores an object (a signed PUT, by libcurl's own AWS Signature V4). bench_http makes
// a server of its own whose store it fills before the start (link_object: the server's files
// as links to a dataset's, nothing copied).
#pragma once

#include "test_paths.hpp"
#include <curl/curl.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "child_process.hpp"
#include "net/s3_config.hpp"

namespace lidarscout::test {

class S3Server {
public:
    static constexpr const char* kKey = "S3RVER";  // its access key and secret
    static constexpr const char* kSecret = "S3RVER";

    static S3Server& instance() {
        static S3Server server({"tiles", "many", "paid"});
        return server;
    }

    // A server with `buckets`, its store (data_dir()) filled by `fill` before it starts.
    explicit S3Server(const std::vector<std::string>& buckets,
                      const std::function<void(const std::filesystem::path&)>& fill = {}) {
        dir_ = std::filesystem::temp_directory_path() /
               ("lidarscout_s3_" + std::to_string(::getpid()) + "_" + std::to_string(++count()));
        std::filesystem::create_directories(dir_ / "data");
        if (fill) fill(dir_ / "data");
        start(buckets);
    }

    // In the store at `data`: bucket/key as a link to `file`, with a fixed ETag (the server
    // would read the whole file for its MD5 otherwise). The server must not be running yet.
    static void link_object(const std::filesystem::path& data, const std::string& bucket, const std::string& key,
                            const std::filesystem::path& file) {
        const std::filesystem::path object = data / bucket / (key + "._S3rver_object");
        std::filesystem::create_directories(object.parent_path());
        std::filesystem::create_symlink(std::filesystem::absolute(file), object);
        std::ofstream(object.string() + ".md5") << "0123456789abcdef0123456789abcdef";
    }

    int port() const { return port_; }
    std::string endpoint() const { return "http://127.0.0.1:" + std::to_string(port_); }
    std::filesystem::path data_dir() const { return dir_ / "data"; }

    // A configuration for this server: path-style requests to its endpoint, signed with `secret`
    // (none: anonymous).
    net::S3Config config(const std::string& secret = kSecret) const {
        net::S3Config c;
        c.endpoint = endpoint();
        if (!secret.empty()) {
            c.access_key = kKey;
            c.secret_key = secret;
        }
        return c;
    }

    // Stores `bytes` at bucket/key; throws when the server refuses it.
    void put(const std::string& bucket, const std::string& key, const std::string& bytes) {
        CURL* easy = curl_easy_init();
        const std::string url = endpoint() + "/" + bucket + "/" + key;
        curl_slist* headers = curl_slist_append(nullptr, "x-amz-content-sha256: UNSIGNED-PAYLOAD");
        curl_easy_setopt(easy, CURLOPT_URL, url.c_str());
        curl_easy_setopt(easy, CURLOPT_CUSTOMREQUEST, "PUT");
        curl_easy_setopt(easy, CURLOPT_POSTFIELDS, bytes.data());
        curl_easy_setopt(easy, CURLOPT_POSTFIELDSIZE_LARGE, static_cast<curl_off_t>(bytes.size()));
        curl_easy_setopt(easy, CURLOPT_HTTPHEADER, headers);
        curl_easy_setopt(easy, CURLOPT_AWS_SIGV4, "aws:amz:us-east-1:s3");
        curl_easy_setopt(easy, CURLOPT_USERNAME, kKey);
        curl_easy_setopt(easy, CURLOPT_PASSWORD, kSecret);
        const auto discard = +[](char*, std::size_t s, std::size_t n, void*) { return s * n; };
        curl_easy_setopt(easy, CURLOPT_WRITEFUNCTION, discard);
        const CURLcode code = curl_easy_perform(easy);
        long status = 0;
        curl_easy_getinfo(easy, CURLINFO_RESPONSE_CODE, &status);
        curl_slist_free_all(headers);
        curl_easy_cleanup(easy);
        if (code != CURLE_OK || status != 200) {
            throw std::runtime_error("S3 PUT " + url + " failed: status " + std::to_string(status));
        }
    }
    void put_file(const std::string& bucket, const std::string& key, const std::filesystem::path& file) {
        std::ifstream in(file, std::ios::binary);
        put(bucket, key, std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()));
    }

    S3Server(const S3Server&) = delete;
    S3Server& operator=(const S3Server&) = delete;
    ~S3Server() { stop_server(pid_, dir_); }

private:
    static int& count() {
        static int n = 0;
        return n;
    }

    void start(const std::vector<std::string>& buckets) {
        const std::string script = std::string(LIDARSCOUT_SOURCE_DIR) + "/tests/s3_server.js";
        const std::string data = (dir_ / "data").string(), port_file = (dir_ / "port").string();
        const std::string log = (dir_ / "server.log").string();
        pid_ = ::fork();
        if (pid_ == 0) {
            ::prctl(PR_SET_PDEATHSIG, SIGTERM);
            std::freopen(log.c_str(), "w", stderr);
            // (the server's continuation tokens are DES-encrypted: OpenSSL 3 keeps DES in its legacy provider)
            std::vector<const char*> argv = {"node", "--openssl-legacy-provider", script.c_str(), data.c_str(),
                                             port_file.c_str()};
            for (const auto& b : buckets) argv.push_back(b.c_str());
            argv.push_back(nullptr);
            ::execvp("node", const_cast<char* const*>(argv.data()));
            ::_exit(127);
        }
        for (int i = 0; i < 1000 && port_ == 0; ++i) {
            if (::waitpid(pid_, nullptr, WNOHANG) == pid_) break;
            std::ifstream in(port_file);
            in >> port_;
            if (port_ == 0) std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        if (port_ == 0) {
            throw std::runtime_error("the S3 server (node tests/s3_server.js, @20minutes/s3rver from scripts/setup.sh)"
                                     " did not start; see " + log);
        }
    }

    std::filesystem::path dir_;
    pid_t pid_ = -1;
    int port_ = 0;
};

}  // namespace lidarscout::test
