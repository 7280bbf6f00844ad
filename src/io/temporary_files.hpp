// The temporary files a process is writing (outputs before their rename, scratch rasters), kept
// in a fixed table so that an interrupted run (Ctrl-C, SIGTERM, SIGHUP) removes them instead of
// leaving hidden, half-written files beside the user's outputs. The signal handler only reads
// the table and calls unlink(), which is safe in a handler; then the signal's default action
// ends the process as it would have. A SignalHold defers those signals over a few steps that must
// all happen or none (the renames of an output set: output_group.hpp).
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

// While alive, SIGINT, SIGTERM and SIGHUP (with the handler above installed) neither end the process
// nor remove temporary files: one that arrives, in any thread, is raised again when the hold ends,
// and then does both. If a signal is already ending the process, the constructor waits for the end.
// One hold at a time per process (a second waits for the first); keep it to a few system calls.
class SignalHold {
public:
    SignalHold();
    ~SignalHold();
    SignalHold(const SignalHold&) = delete;
    SignalHold& operator=(const SignalHold&) = delete;
};

}  // namespace lidarscout::io
