// The HTTP side of run_batch_reads: a source wrapper that passes local requests on to the
// back end and sends remote ones as range requests. Requests for one remote file that the
// source hands out consecutively are held together and sent as one multi-range request when
// a request for another file arrives (or the source is done), so a tile's chunk points cost
// one request (over S3, one a span of nearby ones, and none for those its first and last bytes
// hold: net/remote_file.hpp). At most `max_in_flight` HTTP requests are out at once; beyond that next()
// waits, so a source that reorders its work (the viewer's focus) still decides what goes next.
#pragma once

#include <condition_variable>
#include <mutex>
#include <vector>

#include "io/batch_reader.hpp"

namespace lidarscout::io {

class RemoteRouter final : public ReadSource {
public:
    RemoteRouter(ReadSource& inner, unsigned max_in_flight, std::size_t max_group);
    ~RemoteRouter() override;  // waits for the HTTP requests in flight

    // Local requests only; returns 0 once the inner source is done and every remote read completed.
    std::size_t next(std::span<ReadRequest> out) override;
    void complete(const ReadRequest& request, std::span<const std::uint8_t> data, const ErrorRecord* error) override;

private:
    // Adds `r` to the open group; a group it closes goes to `full`.
    void hold(const ReadRequest& r, std::vector<std::vector<ReadRequest>>& full);
    void send(std::vector<ReadRequest> requests, std::unique_lock<std::mutex>& lock);
    void deliver(const std::vector<ReadRequest>& group, std::vector<std::vector<std::uint8_t>>& parts,
                 const std::string& error);

    ReadSource& inner_;
    const unsigned max_in_flight_;
    const std::size_t max_group_;
    std::mutex mutex_;
    std::condition_variable idle_;
    std::vector<ReadRequest> group_;  // consecutive requests for one remote file, not sent yet
    unsigned in_flight_ = 0;
    bool exhausted_ = false;
};

}  // namespace lidarscout::io
