// Running a command as a child process and measuring it: its exit status, its stderr, the
// largest resident size of it and its own children (wait4's rusage, for that child only, unlike
// getrusage(RUSAGE_CHILDREN)), and the most threads it ran at once (its /proc task list, polled
// while it runs). For the checks that hostile options stay within a memory and thread bound.
// And the end of a server a fixture started (nginx, the S3 server): stop it, remove its folder.
#pragma once

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <thread>

namespace lidarscout::test {

struct ChildRun {
    int status = -1;             // exit status; -1 when killed by a signal
    std::string err;             // what it wrote to stderr
    long max_rss_kb = 0;         // largest resident size, KiB
    std::size_t max_threads = 0; // most threads seen at once
};

// Runs `command` (a shell command line; its last program is exec'd, so the threads counted are
// its own) with stdout discarded and stderr kept in `err_file`.
inline ChildRun run_measured(const std::string& command, const std::filesystem::path& err_file) {
    ChildRun run;
    const pid_t pid = ::fork();
    if (pid == 0) {
        const std::string line = "exec " + command + " >/dev/null 2>'" + err_file.string() + "'";
        ::execl("/bin/sh", "sh", "-c", line.c_str(), static_cast<char*>(nullptr));
        ::_exit(127);
    }
    const std::filesystem::path tasks = "/proc/" + std::to_string(pid) + "/task";
    int status = 0;
    rusage usage{};
    for (;;) {
        std::error_code ec;
        std::size_t n = 0;
        const std::filesystem::directory_iterator end;
        for (auto it = std::filesystem::directory_iterator(tasks, ec); !ec && it != end; it.increment(ec)) {
            ++n;
        }
        run.max_threads = std::max(run.max_threads, n);
        const pid_t done = ::wait4(pid, &status, WNOHANG, &usage);
        if (done == pid) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    run.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    run.max_rss_kb = usage.ru_maxrss;
    std::ifstream in(err_file);
    run.err.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return run;
}

// Stops the server child `pid` (SIGTERM, then reaped) if it runs, and removes its folder.
inline void stop_server(pid_t pid, const std::filesystem::path& dir) {
    if (pid > 0) {
        ::kill(pid, SIGTERM);
        ::waitpid(pid, nullptr, 0);
    }
    std::error_code ec;
    std::filesystem::remove_all(dir, ec);
}

}  // namespace lidarscout::test
