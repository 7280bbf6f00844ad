// The temporary files a process is writing (outputs before their rename, scratch rasters), kept
// in a fixed table so that an interrupted run (Ctrl-C, SIGTERM, SIGHUP) removes them instead of
// leaving hidden, half-written files beside the user's outputs. The signal handler only reads
// the table and calls unlink(), which is safe in a handler; then the signal's default action
// ends the process as it would have.
#pragma once

#include <string>

namespace lidarscout::io {

// Installs the handler for SIGINT, SIGTERM and SIGHUP (the program calls this once, at start).
void remove_temporary_files_on_signal();

// While alive, `path` is removed if the process is ended by one of those signals. The string
// must outlive the guard. With a full table (64 files at once) the file is simply not guarded.
class TemporaryFileGuard {
public:
    explicit TemporaryFileGuard(const std::string& path);
    ~TemporaryFileGuard();
    TemporaryFileGuard(const TemporaryFileGuard&) = delete;
    TemporaryFileGuard& operator=(const TemporaryFileGuard&) = delete;

private:
    int slot_ = -1;
};

}  // namespace lidarscout::io
