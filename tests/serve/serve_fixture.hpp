// A `lidarscout serve` server in the test process: a survey opened, the server bound on a free
// loopback port and run on a thread, and an httplib client for it; or the program itself as a
// child whose first stdout line (its URL) is read back.
#pragma once

#include <httplib.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "dataset/dataset.hpp"
#include "serve/server.hpp"
#include "test_data.hpp"

namespace lidarscout::test {

struct RunningServer {
    std::unique_ptr<serve::Server> server;
    std::thread thread;
    int port = 0;
    serve::Survey* survey = nullptr;

    explicit RunningServer(const std::vector<std::string>& paths, serve::ServerOptions options = {}) {
        if (options.web_dir.empty()) options.web_dir = std::string(LIDARSCOUT_SOURCE_DIR) + "/web";
        if (options.memory_budget == 0) options.memory_budget = 64ull << 20;
        auto cache = std::make_unique<serve::ResponseCache>(options.memory_budget);
        std::vector<std::unique_ptr<serve::Survey>> surveys;
        surveys.push_back(std::make_unique<serve::Survey>(dataset::open_dataset(paths), *cache));
        survey = surveys.back().get();
        server = std::make_unique<serve::Server>(std::move(surveys), options, std::move(cache));
        port = server->bind();
        thread = std::thread([this] { server->run(); });
    }
    ~RunningServer() {
        server->stop();
        thread.join();
    }
    httplib::Client client() const {
        httplib::Client c("127.0.0.1", port);
        c.set_decompress(false);  // the tests look at the bytes sent
        return c;
    }
};

// The program as a child: `lidarscout serve ARGS` with stdout piped; url() reads its first line.
struct ServeChild {
    pid_t pid = -1;
    FILE* out = nullptr;

    explicit ServeChild(const std::string& args) {
        int fds[2];
        if (::pipe(fds) != 0) return;
        pid = ::fork();
        if (pid == 0) {
            ::dup2(fds[1], 1);
            ::close(fds[0]);
            const std::string line = "exec '" + std::string(LIDARSCOUT_CLI) + "' serve " + args + " 2>/dev/null";
            ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
            ::_exit(127);
        }
        ::close(fds[1]);
        out = ::fdopen(fds[0], "r");
    }
    ~ServeChild() {
        if (pid > 0) {
            ::kill(pid, SIGTERM);
            ::waitpid(pid, nullptr, 0);
        }
        if (out) std::fclose(out);
    }
    // The first line of stdout (empty when the program ended without one).
    std::string url() {
        char line[4096] = {};
        if (!out || !std::fgets(line, sizeof line, out)) return {};
        std::string s(line);
        while (!s.empty() && (s.back() == '\n' || s.back() == '\r')) s.pop_back();
        return s;
    }
};

}  // namespace lidarscout::test
