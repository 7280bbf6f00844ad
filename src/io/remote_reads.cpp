// RemoteRouter: grouping remote read requests into multi-range HTTP requests.
#include "io/remote_reads.hpp"

#include <utility>

#include "net/remote_file.hpp"

namespace lidarscout::io {

RemoteRouter::RemoteRouter(ReadSource& inner, unsigned max_in_flight, std::size_t max_group)
    : inner_(inner), max_in_flight_(std::max(1u, max_in_flight)), max_group_(std::max<std::size_t>(1, max_group)) {}

RemoteRouter::~RemoteRouter() {
    std::unique_lock lock(mutex_);
    idle_.wait(lock, [&] { return in_flight_ == 0; });
}

std::size_t RemoteRouter::next(std::span<ReadRequest> out) {
    std::unique_lock lock(mutex_);
    while (!exhausted_) {
        const std::size_t n = inner_.next(out);
        if (n == 0) {
            exhausted_ = true;
            send(std::exchange(group_, {}), lock);
            break;
        }
        // The whole batch is grouped before anything is sent: sending lets other threads in,
        // and the requests they take come after this batch's
        std::vector<std::vector<ReadRequest>> full;
        std::size_t local = 0;
        for (std::size_t i = 0; i < n; ++i) {
            if (out[i].remote) {
                hold(out[i], full);
            } else {
                out[local++] = out[i];
            }
        }
        for (auto& group : full) send(std::move(group), lock);
        if (local > 0) return local;
    }
    send(std::exchange(group_, {}), lock);  // (empty unless a batch was grouped after the end)
    idle_.wait(lock, [&] { return in_flight_ == 0; });
    return 0;
}

void RemoteRouter::hold(const ReadRequest& r, std::vector<std::vector<ReadRequest>>& full) {
    if (!group_.empty() && (group_.front().remote != r.remote || group_.size() >= max_group_)) {
        full.push_back(std::exchange(group_, {}));
    }
    group_.push_back(r);
}

void RemoteRouter::send(std::vector<ReadRequest> requests, std::unique_lock<std::mutex>& lock) {
    if (requests.empty()) return;
    auto group = std::make_shared<std::vector<ReadRequest>>(std::move(requests));
    idle_.wait(lock, [&] { return in_flight_ < max_in_flight_; });
    std::vector<net::ByteRange> ranges;
    ranges.reserve(group->size());
    for (const auto& r : *group) ranges.push_back({r.offset, r.length});
    ++in_flight_;
    lock.unlock();  // a reply from the on-disk cache arrives at once, on this thread
    group->front().remote->fetch_async(std::move(ranges), [this, group](net::RangeReply&& reply) {
        deliver(*group, reply.parts, reply.error);
        std::lock_guard done(mutex_);
        --in_flight_;
        idle_.notify_all();
    });
    lock.lock();
}

void RemoteRouter::deliver(const std::vector<ReadRequest>& group, std::vector<std::vector<std::uint8_t>>& parts,
                           const std::string& error) {
    for (std::size_t i = 0; i < group.size(); ++i) {
        if (!error.empty()) {
            const auto failure = read_error(group[i], error);
            inner_.complete(group[i], {}, &failure);
        } else if (parts[i].size() != group[i].length) {
            const auto failure = read_error(group[i], kShortRead);
            inner_.complete(group[i], {}, &failure);
        } else {
            inner_.complete(group[i], parts[i], nullptr);
        }
    }
}

void RemoteRouter::complete(const ReadRequest& request, std::span<const std::uint8_t> data, const ErrorRecord* error) {
    inner_.complete(request, data, error);
}

}  // namespace lidarscout::io
