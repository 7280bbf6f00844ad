// The two back ends of run_batch_reads. Both share one notion of a read slot: a buffer
// (4 KiB-aligned), the request, and the byte range actually read (widened to sectors for
// direct I/O); deliver() turns the kernel's answer into the source's bytes or an error.
#include "io/batch_reader.hpp"

#include <liburing.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "core/error.hpp"
#include "core/thread_pool.hpp"
#include "io/remote_reads.hpp"

namespace lidarscout::io {

const char* backend_name(ReadBackend backend) {
    switch (backend) {
        case ReadBackend::Auto: return "auto";
        case ReadBackend::IoUring: return "io_uring";
        case ReadBackend::Pread: return "pread";
    }
    return "?";
}

namespace {

constexpr std::uint64_t kSector = 4096;

struct FreeDeleter {
    void operator()(std::uint8_t* p) const noexcept { std::free(p); }
};

class Slot {
public:
    // Sets up the read for `r`: the range to read and a buffer large enough for it.
    void prepare(const ReadRequest& r, bool direct) {
        request = r;
        start = direct ? r.offset / kSector * kSector : r.offset;
        const std::uint64_t end = r.offset + r.length;
        bytes = static_cast<std::uint32_t>(direct ? (end + kSector - 1) / kSector * kSector - start : r.length);
        if (bytes > capacity_) grow(bytes);
    }
    std::uint8_t* buffer() { return buffer_.get(); }

    // `result`: bytes read, or -errno. Passes the requested bytes (or an error) to the source.
    void deliver(ReadSource& source, long result) const {
        const std::uint64_t skip = request.offset - start;
        if (result < 0) {
            const auto error =
                read_error(request, std::string("read failed: ") + std::strerror(static_cast<int>(-result)));
            source.complete(request, {}, &error);
        } else if (static_cast<std::uint64_t>(result) < skip + request.length) {
            const auto error = read_error(request, kShortRead);
            source.complete(request, {}, &error);
        } else {
            source.complete(request, std::span<const std::uint8_t>(buffer_.get() + skip, request.length), nullptr);
        }
    }

    ReadRequest request;
    std::uint64_t start = 0;
    std::uint32_t bytes = 0;

private:
    void grow(std::uint32_t need) {
        const std::size_t size = (need + kSector - 1) / kSector * kSector;
        void* p = std::aligned_alloc(kSector, size);
        if (!p) throw std::bad_alloc();
        buffer_.reset(static_cast<std::uint8_t*>(p));
        capacity_ = static_cast<std::uint32_t>(size);
    }

    std::unique_ptr<std::uint8_t, FreeDeleter> buffer_;
    std::uint32_t capacity_ = 0;
};

unsigned hardware_threads() { return std::max(1u, std::thread::hardware_concurrency()); }

// Runs `body` on `n` threads (the caller being one of them), waits for all, and rethrows
// the first exception any of them threw.
template <typename Body>
void run_on_threads(unsigned n, Body body) {
    std::mutex mutex;
    std::exception_ptr first;
    auto guarded = [&] {
        try {
            body();
        } catch (...) {
            std::lock_guard lock(mutex);
            if (!first) first = std::current_exception();
        }
    };
    std::vector<std::thread> threads;
    try {
        for (unsigned i = 1; i < capped_threads(n); ++i) threads.emplace_back(guarded);
    } catch (const std::system_error& e) {  // the system refused a thread: those started finish the reads
        const std::string cause = std::string("cannot start a reader thread: ") + e.what();
        std::lock_guard lock(mutex);
        first = std::make_exception_ptr(Error::in_stage("io", cause));
    }
    guarded();
    for (auto& t : threads) t.join();
    if (first) std::rethrow_exception(first);
}

// --- pread back end ------------------------------------------------------------------

void pread_worker(ReadSource& source, bool direct) {
    Slot slot;
    ReadRequest batch[4];
    for (;;) {
        const std::size_t n = source.next(batch);
        if (n == 0) return;
        for (std::size_t i = 0; i < n; ++i) {
            slot.prepare(batch[i], direct);
            std::uint64_t got = 0;
            long result = 0;
            while (got < slot.bytes) {
                const ssize_t r = ::pread(slot.request.fd, slot.buffer() + got, slot.bytes - got,
                                          static_cast<off_t>(slot.start + got));
                if (r < 0 && errno == EINTR) continue;
                if (r <= 0) {
                    result = r < 0 ? -errno : static_cast<long>(got);
                    break;
                }
                got += static_cast<std::uint64_t>(r);
                result = static_cast<long>(got);
            }
            slot.deliver(source, result);
        }
    }
}

// --- io_uring back end -----------------------------------------------------------------

class Ring {
public:
    explicit Ring(unsigned depth) {
        const int rc = io_uring_queue_init(depth, &ring_, 0);
        if (rc < 0) throw Error(std::string("io_uring unavailable: ") + std::strerror(-rc));
    }
    ~Ring() { io_uring_queue_exit(&ring_); }
    Ring(const Ring&) = delete;
    Ring& operator=(const Ring&) = delete;
    io_uring* get() { return &ring_; }

private:
    io_uring ring_{};
};

class UringWorker {
public:
    UringWorker(ReadSource& source, unsigned depth, bool direct)
        : source_(source), ring_(depth), slots_(depth), direct_(direct), requests_(depth) {
        for (unsigned i = 0; i < depth; ++i) free_.push_back(i);
    }

    void run() {
        bool exhausted = false;
        for (;;) {
            if (!exhausted) exhausted = !fill();
            if (in_flight_ == 0) {
                if (exhausted) return;
                continue;
            }
            const int rc = io_uring_submit_and_wait(ring_.get(), 1);
            if (rc < 0 && rc != -EINTR) throw Error(std::string("io_uring submit failed: ") + std::strerror(-rc));
            reap();
        }
    }

private:
    // Queues as many new reads as there are free slots; false when the source is done.
    bool fill() {
        if (free_.empty()) return true;
        const std::size_t n = source_.next(std::span(requests_.data(), free_.size()));
        for (std::size_t i = 0; i < n; ++i) {
            io_uring_sqe* sqe = io_uring_get_sqe(ring_.get());
            if (!sqe) break;  // cannot happen: the ring has one entry per slot
            const unsigned s = free_.back();
            free_.pop_back();
            Slot& slot = slots_[s];
            slot.prepare(requests_[i], direct_);
            io_uring_prep_read(sqe, slot.request.fd, slot.buffer(), slot.bytes, slot.start);
            io_uring_sqe_set_data64(sqe, s);
            ++in_flight_;
        }
        return n > 0;
    }

    void reap() {
        io_uring_cqe* cqe = nullptr;
        while (io_uring_peek_cqe(ring_.get(), &cqe) == 0) {
            const auto s = static_cast<unsigned>(io_uring_cqe_get_data64(cqe));
            const long result = cqe->res;
            io_uring_cqe_seen(ring_.get(), cqe);
            slots_[s].deliver(source_, result);
            free_.push_back(s);
            --in_flight_;
        }
    }

    ReadSource& source_;
    Ring ring_;
    std::vector<Slot> slots_;
    bool direct_;
    std::vector<ReadRequest> requests_;
    std::vector<unsigned> free_;
    unsigned in_flight_ = 0;
};

}  // namespace

bool io_uring_available() {
    static const bool available = [] {
        io_uring ring{};
        if (io_uring_queue_init(2, &ring, 0) < 0) return false;
        io_uring_queue_exit(&ring);
        return true;
    }();
    return available;
}

ReadBackend run_batch_reads(ReadSource& user_source, const BatchReadOptions& options) {
    RemoteRouter source(user_source, options.http_in_flight, options.http_max_ranges);
    ReadBackend backend = options.backend;
    if (backend == ReadBackend::Auto) backend = io_uring_available() ? ReadBackend::IoUring : ReadBackend::Pread;
    if (backend == ReadBackend::IoUring && !io_uring_available()) {
        throw Error("io_uring is not available on this system (use the pread back end)");
    }
    const unsigned depth = std::max(1u, options.queue_depth);
    if (backend == ReadBackend::IoUring) {
        const unsigned rings = options.threads ? options.threads : hardware_threads();
        run_on_threads(rings, [&] { UringWorker(source, depth, options.direct).run(); });
    } else {
        const unsigned threads = options.threads ? options.threads : depth;
        run_on_threads(threads, [&] { pread_worker(source, options.direct); });
    }
    return backend;
}

}  // namespace lidarscout::io
