// A test fixture: Debian's nginx serving ../shared/data (read in place, nothing copied) on
// 127.0.0.1 at an ephemeral port, with a generated config, temp prefix and logs in a temp
// folder, and a second temp folder served at /lists/ for tile lists the tests write (and at /typed/json/ and
// /typed/laszip/, every file there with the Content-Type application/geo+json or application/vnd.laszip;
// elsewhere application/octet-stream, nginx's default). One
// server per test process, stopped when the process exits (and killed with it if it dies).
// It also serves the same root over HTTPS and HTTP/2, with a certificate signed by a test CA
// (both made by the openssl command), which a verifying client refuses unless given that CA.
// (bench_http serves its replica with one of its own.) Two redirects: /moved.laz (301, over
// HTTP) and /downgrade.laz (302 from HTTPS to HTTP) lead to the Woodford tile.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <thread>

#include "child_process.hpp"
#include "test_data.hpp"

namespace lidarscout::test {

class NginxServer {
public:
    static constexpr const char* kRedirected = "surveys/ky-woodford-county/5205000_3900000.laz";

    // The process's server, started on first use.
    static NginxServer& instance() {
        static NginxServer server;
        return server;
    }

    // The URL of a path relative to ../shared/data ("surveys/x/y.laz") or of "lists/name".
    std::string url(const std::string& relative) const {
        return "http://127.0.0.1:" + std::to_string(port_) + "/" + relative;
    }
    const std::filesystem::path& lists_dir() const { return lists_; }
    std::filesystem::path access_log() const { return dir_ / "access.log"; }
    int port() const { return port_; }
    int tls_port() const { return tls_port_; }
    // The CA that signed the HTTPS listener's certificate (PEM).
    std::filesystem::path ca_file() const { return dir_ / "ca.pem"; }
    // The URL of `relative` on the HTTPS listener (HTTP/2; its certificate is signed by ca_file()).
    std::string https_url(const std::string& relative) const {
        return "https://127.0.0.1:" + std::to_string(tls_port_) + "/" + relative;
    }

    // A server for `root` (a folder), started at once; throws when nginx does not start.
    explicit NginxServer(std::filesystem::path root) : root_(std::filesystem::canonical(root)) {
        dir_ = std::filesystem::temp_directory_path() / ("lidarscout_nginx_" + std::to_string(::getpid()));
        lists_ = dir_ / "lists";
        std::filesystem::create_directories(lists_);
        make_certificate();
        for (int attempt = 0; attempt < 5 && pid_ <= 0; ++attempt) start(free_port());
        if (pid_ <= 0) throw std::runtime_error("nginx did not start; see " + (dir_ / "error.log").string());
    }
    NginxServer(const NginxServer&) = delete;
    NginxServer& operator=(const NginxServer&) = delete;

    ~NginxServer() { stop_server(pid_, dir_); }

private:
    NginxServer() : NginxServer(data_dir()) {}

    static int free_port() {
        const int s = ::socket(AF_INET, SOCK_STREAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t len = sizeof a;
        ::bind(s, reinterpret_cast<sockaddr*>(&a), sizeof a);
        ::getsockname(s, reinterpret_cast<sockaddr*>(&a), &len);
        ::close(s);
        return ntohs(a.sin_port);
    }

    // A test CA and a server certificate it signs for 127.0.0.1 (nobody trusts that CA unless
    // told: ca_file()).
    void make_certificate() const {
        const std::string d = dir_.string();
        const std::string ec = " -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes ";
        const std::string cmd =
            "(cd " + d + " && openssl req -x509" + ec + "-days 2 -subj /CN=lidarscout-test-ca -keyout ca-key.pem "
            "-out ca.pem && openssl req" + ec + "-subj /CN=127.0.0.1 -keyout key.pem -out server.csr && "
            "printf 'subjectAltName=IP:127.0.0.1\\n' > san.ext && openssl x509 -req -in server.csr -CA ca.pem "
            "-CAkey ca-key.pem -CAcreateserial -days 2 -extfile san.ext -out cert.pem) >/dev/null 2>&1";
        if (std::system(cmd.c_str()) != 0) throw std::runtime_error("openssl could not make a test certificate");
    }

    void write_config(int port) const {
        const std::string d = dir_.string();
        std::ofstream c(dir_ / "nginx.conf");
        c << "worker_processes 1;\npid " << d << "/nginx.pid;\nerror_log " << d << "/error.log;\n"
          << "events { worker_connections 1024; }\nhttp {\n  access_log " << d << "/access.log;\n"
          << "  client_body_temp_path " << d << "/body;\n  proxy_temp_path " << d << "/proxy;\n"
          << "  fastcgi_temp_path " << d << "/fastcgi;\n  uwsgi_temp_path " << d << "/uwsgi;\n"
          << "  scgi_temp_path " << d << "/scgi;\n  default_type application/octet-stream;\n"
          << "  keepalive_requests 100000;\n"
          << "  server {\n    listen 127.0.0.1:" << port << ";\n    root " << root_.string()
          << ";\n    location /lists/ { alias " << lists_.string() << "/; }\n"
          << "    location /typed/json/ { alias " << lists_.string() << "/; default_type application/geo+json; }\n"
          << "    location /typed/laszip/ { alias " << lists_.string() << "/; default_type application/vnd.laszip; }\n"
          << "    location = /moved.laz { return 301 /" << kRedirected << "; }\n  }\n"
          << "  server {\n    listen 127.0.0.1:" << tls_port_ << " ssl http2;\n"
          << "    location = /downgrade.laz { return 302 http://127.0.0.1:" << port << "/" << kRedirected << "; }\n"
          << "    ssl_certificate " << d << "/cert.pem;\n"
          << "    ssl_certificate_key " << d << "/key.pem;\n    root " << root_.string()
          << ";\n    location /lists/ { alias " << lists_.string() << "/; }\n  }\n}\n";
    }

    void start(int port) {
        tls_port_ = free_port();
        write_config(port);
        const std::string conf = (dir_ / "nginx.conf").string(), prefix = dir_.string() + "/";
        const std::string err = (dir_ / "error.log").string();
        // as root the workers would switch to "nobody"; the tests' user reads the data
        const std::string globals = ::geteuid() == 0 ? "daemon off; user root;" : "daemon off;";
        const pid_t pid = ::fork();
        if (pid == 0) {
            ::prctl(PR_SET_PDEATHSIG, SIGTERM);
            ::execlp("nginx", "nginx", "-p", prefix.c_str(), "-c", conf.c_str(), "-e", err.c_str(), "-g",
                     globals.c_str(), static_cast<char*>(nullptr));
            ::_exit(127);
        }
        if (wait_until_listening(pid, port)) {
            pid_ = pid;
            port_ = port;
        }
    }

    static bool wait_until_listening(pid_t pid, int port) {
        for (int i = 0; i < 500; ++i) {
            if (::waitpid(pid, nullptr, WNOHANG) == pid) return false;  // exited (port taken?)
            const int s = ::socket(AF_INET, SOCK_STREAM, 0);
            sockaddr_in a{};
            a.sin_family = AF_INET;
            a.sin_port = htons(static_cast<std::uint16_t>(port));
            a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
            const bool up = ::connect(s, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
            ::close(s);
            if (up) return true;
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        ::kill(pid, SIGKILL);
        ::waitpid(pid, nullptr, 0);
        return false;
    }

    std::filesystem::path root_, dir_, lists_;
    pid_t pid_ = -1;
    int port_ = 0, tls_port_ = 0;
};

}  // namespace lidarscout::test
