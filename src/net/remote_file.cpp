// Remote files: the process-wide registry, the edge requests that open a file, and reads.
#include "net/remote_file.hpp"

#include <future>
#include <map>
#include <mutex>
#include <optional>

#include "core/error.hpp"
#include "net/range_cache.hpp"
#include "net/s3_request.hpp"
#include "net/url.hpp"

namespace lidarscout::net {

namespace {

using Opening = std::shared_future<std::shared_ptr<const RemoteFile>>;  // null: the open failed

struct Registry {
    std::mutex mutex;
    std::map<std::string, std::shared_ptr<const RemoteFile>> files;  // by URL, as given and as shown
    std::map<std::string, Opening> opening;                          // prefetches in flight, by URL
};

Registry& registry() {
    static Registry r;
    return r;
}

// What open() finds for `url`, under one lock: its file, or the opening in flight (a prefetch's
// or another thread's open), or neither, and then `mine` is registered as its opening, for the
// others to wait on (two looks under two locks let a prefetch end between them: two requests more).
struct Found {
    std::shared_ptr<const RemoteFile> file;
    std::optional<Opening> pending;
};
Found find_or_claim(const std::string& url, const Opening& mine) {
    auto& r = registry();
    std::lock_guard lock(r.mutex);
    if (const auto it = r.files.find(url); it != r.files.end()) return {it->second, std::nullopt};
    if (const auto it = r.opening.find(url); it != r.opening.end()) return {nullptr, it->second};
    r.opening.emplace(url, mine);
    return {};
}

// Ends an opening registered for `url`: those waiting on it get `file` (null: it failed).
void end_opening(const std::string& url, std::promise<std::shared_ptr<const RemoteFile>>& opened,
                 std::shared_ptr<const RemoteFile> file) {
    {
        auto& r = registry();
        std::lock_guard lock(r.mutex);
        r.opening.erase(url);
    }
    opened.set_value(std::move(file));
}

std::shared_ptr<const RemoteFile> register_file(const std::string& url, std::shared_ptr<RemoteFile> file) {
    auto& r = registry();
    std::lock_guard lock(r.mutex);
    const auto& kept = r.files.emplace(url, std::move(file)).first->second;  // the first one stays
    r.files.emplace(kept->display_url(), kept);  // so that a shown URL opens the same file
    return kept;
}

RangeRequest head_request(const std::string& url) { return remote_request(url, {{0, RemoteFile::kEdge}}, {}); }

// The tail range of a file opened by its head, or nothing when the head held it all.
std::optional<ByteRange> tail_range(const RemoteFile& f) {
    if (f.size() <= 2 * RemoteFile::kEdge) return std::nullopt;
    return ByteRange{f.size() - RemoteFile::kEdge, RemoteFile::kEdge};
}

// Submits `request`, answered from the on-disk cache when it holds it (then at once, on this
// thread); successful answers are stored there.
void fetch_cached(RangeRequest request, HttpClient::Callback done) {
    auto& cache = RangeCache::shared();
    if (auto parts = cache.find(request)) {
        RangeReply reply;
        reply.parts = std::move(*parts);
        reply.validator = request.validator;
        return done(std::move(reply));
    }
    auto shared = std::make_shared<RangeRequest>(request);
    HttpClient::shared().submit(std::move(request), [shared, done = std::move(done)](RangeReply&& reply) {
        RangeCache::shared().store(*shared, reply);
        done(std::move(reply));
    });
}

[[noreturn]] void throw_reply_error(const std::string& url, std::uint64_t offset, const std::string& error) {
    throw Error(redact_url(url), offset, error + s3_error_context(url));
}

}  // namespace

// Where the redirects of a file's requests led: its next requests go there directly, and back
// to the file's own URL when that answers 403 (a signed URL that expired).
struct RemoteFile::Redirect {
    std::mutex mutex;
    std::string target;  // "" = none

    std::string get() {
        std::lock_guard lock(mutex);
        return target;
    }
    void keep(const RangeReply& reply) {
        std::lock_guard lock(mutex);
        if (!reply.final_url.empty()) target = reply.final_url;
    }
    void forget(const std::string& expired) {
        std::lock_guard lock(mutex);
        if (target == expired) target.clear();
    }
};

namespace {

// Fetches `request` at the file's redirected URL when it has one; a 403 there asks the file's
// own URL again, once.
void fetch_following(RangeRequest request, std::shared_ptr<RemoteFile::Redirect> redirect,
                     HttpClient::Callback done) {
    const std::string redirected = redirect->get();
    auto original = std::make_shared<RangeRequest>(request);
    if (!redirected.empty()) request.target = redirected;
    fetch_cached(std::move(request), [=, done = std::move(done)](RangeReply&& reply) mutable {
        const bool expired = !reply.error.empty() && reply.status == 403 && !redirected.empty();
        if (!expired) {
            redirect->keep(reply);
            return done(std::move(reply));
        }
        redirect->forget(redirected);
        fetch_cached(std::move(*original), [redirect, done = std::move(done)](RangeReply&& again) {
            redirect->keep(again);
            done(std::move(again));
        });
    });
}

}  // namespace

RemoteFile::RemoteFile(std::string url, RangeReply&& head)
    : url_(std::move(url)), display_url_(redact_url(url_)), validator_(std::move(head.validator)),
      redirect_(std::make_shared<Redirect>()) {
    if (!head.total) throw Error(display_url_, std::nullopt, "the server does not give the file's size");
    size_ = *head.total;
    head_ = std::move(head.parts.at(0));
    redirect_->keep(head);
}

RangeReply RemoteFile::fetch_now(std::vector<ByteRange> ranges) const {
    std::promise<RangeReply> promise;
    auto future = promise.get_future();
    fetch_async(std::move(ranges), [&promise](RangeReply&& reply) { promise.set_value(std::move(reply)); });
    return future.get();
}

void RemoteFile::set_tail(RangeReply&& reply) { tail_ = std::move(reply.parts.at(0)); }

namespace {

// Fetches the edges of `url` and registers its file; throws Error.
std::shared_ptr<const RemoteFile> open_now(const std::string& url) {
    RangeReply head = HttpClient::shared().fetch(head_request(url));
    if (!head.error.empty()) throw_reply_error(url, 0, head.error);
    auto file = std::make_shared<RemoteFile>(url, std::move(head));
    if (auto tail = tail_range(*file)) {
        RangeReply reply = file->fetch_now({*tail});
        if (!reply.error.empty()) throw_reply_error(url, tail->offset, reply.error);
        file->set_tail(std::move(reply));
    }
    return register_file(url, std::move(file));
}

}  // namespace

std::shared_ptr<const RemoteFile> RemoteFile::open(const std::string& url) {
    if (const std::string problem = url_problem(url); !problem.empty()) {
        throw Error(redact_url(url), std::nullopt, problem);
    }
    std::promise<std::shared_ptr<const RemoteFile>> opened;
    const Found found = find_or_claim(url, opened.get_future().share());
    if (found.file) return found.file;
    if (found.pending) {
        if (auto f = found.pending->get()) return f;
        return open_now(url);  // the other opening failed: again here, to report why
    }
    try {
        auto file = open_now(url);
        end_opening(url, opened, file);
        return file;
    } catch (...) {
        end_opening(url, opened, nullptr);
        throw;
    }
}

namespace {

// Starts opening `url` (head, then tail) on the client's thread; `opened` gets the file, or
// null when a request failed.
void open_async(const std::string& url, std::shared_ptr<std::promise<std::shared_ptr<const RemoteFile>>> opened) {
    const auto finish = [url, opened](std::shared_ptr<RemoteFile> file) {
        std::shared_ptr<const RemoteFile> kept = file ? register_file(url, std::move(file)) : nullptr;
        {
            auto& r = registry();
            std::lock_guard lock(r.mutex);
            r.opening.erase(url);
        }
        opened->set_value(std::move(kept));
    };
    HttpClient::shared().submit(head_request(url), [url, finish](RangeReply&& head) {
        if (!head.error.empty() || !head.total) return finish(nullptr);
        auto file = std::make_shared<RemoteFile>(url, std::move(head));
        auto tail = tail_range(*file);
        if (!tail) return finish(std::move(file));
        file->fetch_async({*tail}, [finish, file](RangeReply&& reply) {
            if (!reply.error.empty()) return finish(nullptr);
            file->set_tail(std::move(reply));
            finish(file);
        });
    });
}

}  // namespace

void RemoteFile::prefetch(std::span<const std::string> urls) {
    for (const auto& url : urls) {
        if (!is_url(url) || !url_problem(url).empty()) continue;
        auto opened = std::make_shared<std::promise<std::shared_ptr<const RemoteFile>>>();
        {
            auto& r = registry();
            std::lock_guard lock(r.mutex);
            if (r.files.contains(url) || r.opening.contains(url)) continue;
            r.opening.emplace(url, opened->get_future().share());
        }
        try {
            open_async(url, std::move(opened));
        } catch (const Error&) {  // (an s3 URL without a key, a bad S3 setting): open() reports it
            auto& r = registry();
            std::lock_guard lock(r.mutex);
            r.opening.erase(url);
        }
    }
}

void RemoteFile::forget_all() {
    auto& r = registry();
    std::lock_guard lock(r.mutex);
    r.files.clear();
    r.opening.clear();  // (those in flight still register their file when they end)
}

void RemoteFile::read(std::uint64_t offset, std::span<std::uint8_t> out) const {
    if (out.empty()) return;
    RangeReply reply = fetch_now({{offset, out.size()}});
    if (!reply.error.empty()) throw_reply_error(url_, offset, reply.error);
    const auto& part = reply.parts.at(0);
    if (part.size() != out.size()) {
        throw Error(display_url_, offset, "the server's file ends before the " + std::to_string(out.size()) +
                                              " bytes asked for");
    }
    std::copy(part.begin(), part.end(), out.begin());
}

void RemoteFile::fetch_async(std::vector<ByteRange> ranges, HttpClient::Callback done) const {
    RangeRequest request = remote_request(url_, std::move(ranges), validator_);
    request.total = size_;  // (without a validator, the only sign that the file was replaced)
    fetch_following(std::move(request), redirect_, std::move(done));
}

}  // namespace lidarscout::net
