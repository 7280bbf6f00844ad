// Remote files: the process-wide registry, the edge requests that open a file, and reads.
#include "net/remote_file.hpp"

#include <algorithm>
#include <functional>
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

// A LAS file's head, from its header: its VLRs and the first point record (a LAZ file's first chunk
// point, after the chunk table's 8-byte offset) end this many bytes in; 0 when `head` is not a LAS
// header. Read whole at open (up to kMaxHead), not VLR by VLR.
constexpr std::uint64_t kMaxHead = 64 * 1024;

std::uint64_t las_head_end(std::span<const std::uint8_t> head) {
    constexpr std::size_t kPointDataOffset = 96, kRecordLength = 105;
    if (head.size() < kRecordLength + 2 || !std::equal(head.begin(), head.begin() + 4, "LASF")) return 0;
    const auto u32 = [&](std::size_t at) {
        return std::uint64_t{head[at]} | std::uint64_t{head[at + 1]} << 8 | std::uint64_t{head[at + 2]} << 16 |
               std::uint64_t{head[at + 3]} << 24;
    };
    const std::uint64_t record = head[kRecordLength] | std::uint64_t{head[kRecordLength + 1]} << 8;
    return u32(kPointDataOffset) + 8 + record;
}

// What the second request of an open asks, after the head (the first kEdge bytes): the tail (a LAZ
// file's chunk table) and the rest of a LAS file's head when the first bytes did not hold it (a WKT
// VLR of a few KiB), in one request where the server answers several ranges at once (and one range,
// merged, where they are near); a small file's whole rest instead, when it costs no more than a
// request does (HttpSettings::merge_gap_one_range): its chunk points are then read from memory.
struct OpenPlan {
    std::optional<ByteRange> more_head, tail;
    std::vector<ByteRange> ranges() const {
        std::vector<ByteRange> out;
        if (more_head) out.push_back(*more_head);
        if (tail) out.push_back(*tail);
        return out;
    }
};

// (After an open in one request, the tail is held: only a head longer than its guess is asked.)
OpenPlan open_plan(const RemoteFile& f) {
    OpenPlan plan;
    const std::uint64_t size = f.size(), have = f.head().size();
    const bool tail_held = !f.tail().empty();
    if (size <= have) return plan;
    if (!tail_held && size - have <= RemoteFile::kEdge + HttpClient::shared().settings().merge_gap_one_range) {
        plan.more_head = ByteRange{have, size - have};
        return plan;
    }
    const std::uint64_t tail_start = size - (tail_held ? f.tail().size() : RemoteFile::kEdge);
    const std::uint64_t head_end = std::min({las_head_end(f.head()), kMaxHead, tail_start});
    if (head_end > have) plan.more_head = ByteRange{have, head_end - have};
    if (!tail_held) plan.tail = ByteRange{tail_start, RemoteFile::kEdge};
    return plan;
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
      content_type_(std::move(head.content_type)), redirect_(std::make_shared<Redirect>()) {
    if (!head.total) throw Error(display_url_, std::nullopt, "the server does not give the file's size");
    size_ = *head.total;
    head_ = std::move(head.parts.at(0));
    redirect_->keep(head);
}

RangeReply RemoteFile::fetch_now(std::vector<ByteRange> ranges, std::vector<std::uint8_t> buffer) const {
    std::promise<RangeReply> promise;
    auto future = promise.get_future();
    fetch_async(
        std::move(ranges), [&promise](RangeReply&& reply) { promise.set_value(std::move(reply)); }, std::move(buffer));
    return future.get();
}

void RemoteFile::set_rest(bool more_head, bool tail, RangeReply&& reply) {
    std::size_t part = 0;
    if (more_head) {
        const auto& more = reply.parts.at(part++);
        head_.insert(head_.end(), more.begin(), more.end());
    }
    if (tail) tail_ = std::move(reply.parts.at(part));
}

void RemoteFile::set_tail(std::vector<std::uint8_t> tail) { tail_ = std::move(tail); }

void RemoteFile::trim_head(std::uint64_t bytes) {
    if (bytes >= head_.size()) return;
    head_.resize(bytes);
    head_.shrink_to_fit();
}

namespace {

// Fetches the edges of `url` (the head, then the rest) and registers its file; throws Error.
std::shared_ptr<const RemoteFile> open_in_two_now(const std::string& url) {
    RangeReply head = HttpClient::shared().fetch(head_request(url));
    if (!head.error.empty()) throw_reply_error(url, 0, head.error);
    auto file = std::make_shared<RemoteFile>(url, std::move(head));
    if (const OpenPlan plan = open_plan(*file); plan.more_head || plan.tail) {
        const auto ranges = plan.ranges();
        RangeReply reply = file->fetch_now(ranges);
        if (!reply.error.empty()) throw_reply_error(url, ranges.front().offset, reply.error);
        file->set_rest(plan.more_head.has_value(), plan.tail.has_value(), std::move(reply));
    }
    return register_file(url, std::move(file));
}

// The end of an open started on the client's thread: the file, or null when a request failed.
using Finish = std::function<void(std::shared_ptr<RemoteFile>)>;

// Fetches what `file`'s open plan still asks (the rest of its head, its tail), then finishes.
void fetch_rest(std::shared_ptr<RemoteFile> file, Finish finish) {
    const OpenPlan plan = open_plan(*file);
    if (!plan.more_head && !plan.tail) return finish(std::move(file));
    file->fetch_async(plan.ranges(), [finish = std::move(finish), file, plan](RangeReply&& reply) {
        if (!reply.error.empty()) return finish(nullptr);
        file->set_rest(plan.more_head.has_value(), plan.tail.has_value(), std::move(reply));
        finish(file);
    });
}

// Opens `url` as a host that answers one range per request is opened: the head, then the rest.
void open_in_two(const std::string& url, Finish finish) {
    HttpClient::shared().submit(head_request(url), [url, finish = std::move(finish)](RangeReply&& head) {
        if (!head.error.empty() || !head.total) return finish(nullptr);
        fetch_rest(std::make_shared<RemoteFile>(url, std::move(head)), finish);
    });
}

// The first request of an open where the host answers several ranges at once: the first bytes and the
// last kEdge together ("bytes=0-8191,-2048"): at first kOpenHead, then a head the host's files showed
// (head_guess). The heads of the LAZ tiles at hand end (with the chunk table's 8-byte offset and the first
// point record) 0.4-2.6 KiB in, a WKT VLR makes some a few KiB; the chunk tables at their ends take 13-293
// bytes. A longer head is asked for afterwards (open_plan).
constexpr std::uint64_t kOpenHead = 8 * 1024;

// The file of an answer to the first request of an open in one request: the whole file, or its head
// (cut to what a LAS head needs, as an open in two requests keeps) and its tail; null when it failed.
std::shared_ptr<RemoteFile> opened_in_one(const std::string& url, RangeReply&& reply) {
    if (!reply.error.empty() || !reply.total) return nullptr;
    const bool whole = reply.whole_file;
    auto tail = whole ? std::vector<std::uint8_t>() : std::move(reply.parts.at(1));
    auto file = std::make_shared<RemoteFile>(url, std::move(reply));
    if (whole) return file;
    file->set_tail(std::move(tail));
    file->trim_head(std::max(RemoteFile::kEdge, las_head_end(file->head())));
    return file;
}

// What opens in one request know of each host (by origin): the opens waiting for its first answer,
// started when it comes, and the head its opens ask for.
struct Hosts {
    std::mutex mutex;
    std::map<std::string, std::vector<std::function<void()>>> waiting;
    std::map<std::string, std::uint64_t> head;
};

Hosts& hosts() {
    static Hosts h;
    return h;
}

void release_probe(const std::string& origin) {
    std::vector<std::function<void()>> waiting;
    {
        std::lock_guard lock(hosts().mutex);
        auto node = hosts().waiting.extract(origin);
        if (node) waiting = std::move(node.mapped());
    }
    for (auto& start : waiting) start();
}

// The head an open in one request asks of `origin`: kOpenHead until one of its LAS files opened so, then
// the longest LAS head seen there (learn_head) with 1 KiB to spare, in KiB (kEdge to kMaxHead): a
// catalog's tiles, made alike, then cost the bytes they need.
std::uint64_t head_guess(const std::string& origin) {
    std::lock_guard lock(hosts().mutex);
    const auto it = hosts().head.find(origin);
    return it == hosts().head.end() ? kOpenHead : it->second;
}

void learn_head(const std::string& origin, std::span<const std::uint8_t> head) {
    const std::uint64_t end = las_head_end(head);
    if (end == 0) return;
    const std::uint64_t guess = std::clamp((end + 2047) / 1024 * 1024, RemoteFile::kEdge, kMaxHead);
    std::lock_guard lock(hosts().mutex);
    auto [it, added] = hosts().head.try_emplace(origin, guess);
    it->second = std::max(it->second, guess);
}

// Opens `url` in one request, then what its plan still asks (a head longer than guessed); in two
// requests when the server's answer could not be used (not multipart, the whole of a large file), and
// not at all when it was an error (a 404: open() asks again to report it). `probe`: its answer releases
// the opens waiting for its host's first answer (after the head it shows is learnt).
void open_in_one(const std::string& url, RangeRequest request, Finish finish, bool probe) {
    const std::string origin = url_origin(request.asked());
    HttpClient::shared().submit(std::move(request), [url, origin, finish = std::move(finish),
                                                     probe](RangeReply&& reply) {
        const bool answered = reply.status == 200 || reply.status == 206;
        auto file = opened_in_one(url, std::move(reply));
        if (file) learn_head(origin, file->head());
        if (probe) release_probe(origin);
        const bool more = !file || open_plan(*file).more_head;
        if (file || answered) HttpClient::shared().count_open(!more);
        if (!file) return answered ? open_in_two(url, finish) : finish(nullptr);
        fetch_rest(std::move(file), finish);
    });
}

// The first request of an open of `url` in one request (its head and tail), and what its host is known
// to do with several ranges (S3's GetObject: answers one).
std::pair<RangeRequest, HttpClient::MultiRange> first_request(const std::string& url) {
    RangeRequest first = remote_request(url, {{0, kOpenHead}}, {});
    first.ranges.front().length = head_guess(url_origin(first.asked()));
    first.suffix = RemoteFile::kEdge;
    const auto known = first.one_range ? HttpClient::MultiRange::no : HttpClient::shared().multi_range(first.asked());
    return {std::move(first), known};
}

// Opens `url` on the client's thread: in one request where its host is known to answer several ranges
// at once, in two where it is not. When nothing tells of the host yet (`may_probe`: a prefetch of several
// files, whose other opens it may spare a request each), the first open asks in one request and the others
// wait for its answer (then ask in two requests if it told nothing either: a small file answered whole, an
// error). A host that answers one range costs that first open one request more.
void open_with(const std::string& url, Finish finish, bool may_probe) {
    auto [first, known] = first_request(url);
    using MultiRange = HttpClient::MultiRange;
    if (known == MultiRange::yes) return open_in_one(url, std::move(first), std::move(finish), false);
    if (known == MultiRange::no || !may_probe) return open_in_two(url, std::move(finish));
    const std::string origin = url_origin(first.asked());
    {
        std::lock_guard lock(hosts().mutex);
        auto [it, probing] = hosts().waiting.try_emplace(origin);
        if (!probing) {
            it->second.push_back([url, finish] {
                try {
                    open_with(url, finish, false);
                } catch (const Error&) {  // (not thrown for a URL asked before; open() reports it)
                    finish(nullptr);
                }
            });
            return;
        }
    }
    open_in_one(url, std::move(first), std::move(finish), true);
}

// Opens `url` and registers its file; throws Error. In one request where its host is known to answer
// several ranges at once (else, and when that fails, in two: a failure is reported from those).
std::shared_ptr<const RemoteFile> open_now(const std::string& url) {
    auto [first, known] = first_request(url);
    if (known != HttpClient::MultiRange::yes) return open_in_two_now(url);
    std::promise<std::shared_ptr<RemoteFile>> opened;
    auto future = opened.get_future();
    open_in_one(url, std::move(first), [&opened](std::shared_ptr<RemoteFile> file) { opened.set_value(file); }, false);
    if (auto file = future.get()) return register_file(url, std::move(file));
    return open_in_two_now(url);
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
        return open_in_two_now(url);  // the other opening failed: again here, to report why
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

std::future<RemoteFile::FromStart> RemoteFile::open_from_start(const std::string& url, std::uint64_t bytes) {
    if (const std::string problem = url_problem(url); !problem.empty()) {
        throw Error(redact_url(url), std::nullopt, problem);
    }
    auto opened = std::make_shared<std::promise<std::shared_ptr<const RemoteFile>>>();
    const Found found = find_or_claim(url, opened->get_future().share());
    if (found.file || found.pending) {  // (open() waits for the one in flight, or reports its failure again)
        return std::async(std::launch::deferred, [url] { return FromStart{open(url), {}}; });
    }
    auto result = std::make_shared<std::promise<FromStart>>();
    auto future = result->get_future();
    RangeRequest request;
    try {
        request = remote_request(url, {{0, std::max(bytes, kEdge)}}, {});
    } catch (...) {  // (an s3 URL whose signing cannot be made: the claim ends, or open() would wait for ever)
        end_opening(url, *opened, nullptr);
        throw;
    }
    fetch_cached(std::move(request), [url, opened, result](RangeReply&& reply) {
        try {
            if (!reply.error.empty()) throw_reply_error(url, 0, reply.error);
            std::vector<std::uint8_t> first = std::move(reply.parts.at(0));
            const auto edge = static_cast<std::ptrdiff_t>(std::min<std::uint64_t>(first.size(), kEdge));
            reply.parts.at(0).assign(first.begin(), first.begin() + edge);
            auto file = register_file(url, std::make_shared<RemoteFile>(url, std::move(reply)));
            end_opening(url, *opened, file);
            result->set_value({std::move(file), std::move(first)});
        } catch (...) {
            end_opening(url, *opened, nullptr);
            result->set_exception(std::current_exception());
        }
    });
    return future;
}

namespace {

// Starts opening `url` on the client's thread; `opened` gets the file, or null when a request failed.
// `may_probe`: as open_with's.
void open_async(const std::string& url, std::shared_ptr<std::promise<std::shared_ptr<const RemoteFile>>> opened,
                bool may_probe) {
    open_with(url, [url, opened](std::shared_ptr<RemoteFile> file) {
        std::shared_ptr<const RemoteFile> kept = file ? register_file(url, std::move(file)) : nullptr;
        {
            auto& r = registry();
            std::lock_guard lock(r.mutex);
            r.opening.erase(url);
        }
        opened->set_value(std::move(kept));
    }, may_probe);
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
            open_async(url, std::move(opened), urls.size() > 1);
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
    const std::vector<std::uint8_t> part = read_bytes(offset, out.size());
    std::copy(part.begin(), part.end(), out.begin());
}

std::vector<std::vector<std::uint8_t>> RemoteFile::read_ranges(std::vector<ByteRange> ranges,
                                                               std::vector<std::uint8_t> buffer) const {
    if (ranges.empty()) return {};
    const std::vector<ByteRange> asked = ranges;
    RangeReply reply = fetch_now(std::move(ranges), std::move(buffer));
    if (!reply.error.empty()) throw_reply_error(url_, asked.front().offset, reply.error);
    if (reply.parts.size() != asked.size()) {
        throw Error(display_url_, asked.front().offset, "the server answered " + std::to_string(reply.parts.size()) +
                                                            " parts for " + std::to_string(asked.size()) + " ranges");
    }
    for (std::size_t k = 0; k < asked.size(); ++k) {
        if (reply.parts[k].size() != asked[k].length) {
            throw Error(display_url_, asked[k].offset, "the server's file ends before the " +
                                                           std::to_string(asked[k].length) + " bytes asked for");
        }
    }
    return std::move(reply.parts);
}

std::vector<std::uint8_t> RemoteFile::read_bytes(std::uint64_t offset, std::uint64_t size,
                                                 std::vector<std::uint8_t> buffer) const {
    if (size == 0) return {};
    return std::move(read_ranges({{offset, size}}, std::move(buffer)).at(0));
}

namespace {

// The gap up to which the ranges of `request` are merged: a request per range where its server
// answers one range per request, a part's framing where it answers several at once.
std::uint64_t merge_gap(const RangeRequest& request) {
    const HttpClient& client = HttpClient::shared();
    const HttpSettings s = client.settings();
    const bool one_range = request.one_range || !client.answers_multi_range(request.asked());
    return one_range ? s.merge_gap_one_range : s.merge_gap_multi_range;
}

// Whether every span of `merged` is exactly one range asked, in the order asked.
bool nothing_merged(const MergedRanges& merged) {
    if (merged.spans.size() != merged.slices.size()) return false;
    for (std::size_t i = 0; i < merged.slices.size(); ++i) {
        if (merged.slices[i].span != i || merged.slices[i].skip != 0) return false;
    }
    return true;
}

// Puts the parts of the ranges asked (cut from the parts of the merged spans, `got`) at their places
// (`where`) among the parts already known, and hands all of them back in `got`.
void place_parts(const MergedRanges& merged, const std::vector<ByteRange>& asked, const std::vector<std::size_t>& where,
                 std::vector<std::vector<std::uint8_t>>& got, std::vector<std::vector<std::uint8_t>>& known) {
    auto parts = nothing_merged(merged) ? std::move(got) : cut_parts(merged, asked, got);
    for (std::size_t k = 0; k < where.size(); ++k) known[where[k]] = std::move(parts[k]);
    got = std::move(known);
}

}  // namespace

std::optional<std::vector<std::uint8_t>> RemoteFile::held(const ByteRange& r) const {
    if (r.offset <= head_.size() && r.length <= head_.size() - r.offset) {
        const auto first = head_.begin() + static_cast<std::ptrdiff_t>(r.offset);
        return std::vector<std::uint8_t>(first, first + static_cast<std::ptrdiff_t>(r.length));
    }
    const std::uint64_t tail_start = size_ - tail_.size();
    if (!tail_.empty() && r.offset >= tail_start && r.offset <= size_ && r.length <= size_ - r.offset) {
        const auto first = tail_.begin() + static_cast<std::ptrdiff_t>(r.offset - tail_start);
        return std::vector<std::uint8_t>(first, first + static_cast<std::ptrdiff_t>(r.length));
    }
    return std::nullopt;
}

void RemoteFile::fetch_async(std::vector<ByteRange> ranges, HttpClient::Callback done,
                             std::vector<std::uint8_t> buffer) const {
    auto reply = std::make_shared<RangeReply>();  // the parts the head and tail hold, the others to come
    reply->parts.resize(ranges.size());
    reply->total = size_;
    reply->validator = validator_;
    std::vector<ByteRange> asked;
    std::vector<std::size_t> where;  // the index in `ranges` of each range asked
    for (std::size_t i = 0; i < ranges.size(); ++i) {
        if (auto bytes = held(ranges[i])) {
            reply->parts[i] = std::move(*bytes);
        } else {
            asked.push_back(ranges[i]);
            where.push_back(i);
        }
    }
    if (asked.empty()) return done(std::move(*reply));
    RangeRequest request = remote_request(url_, asked, validator_);
    request.total = size_;  // (without a validator, the only sign that the file was replaced)
    auto merged = std::make_shared<const MergedRanges>(merge_ranges(asked, merge_gap(request)));
    request.ranges = merged->spans;
    if (request.ranges.size() == 1 && asked.size() == 1) {
        buffer.clear();  // (its capacity is what is reused)
        request.buffer = std::move(buffer);
    }
    fetch_following(std::move(request), redirect_,
                    [reply, merged, asked = std::move(asked), where = std::move(where),
                     done = std::move(done)](RangeReply&& got) {
                        if (got.error.empty()) place_parts(*merged, asked, where, got.parts, reply->parts);
                        done(std::move(got));
                    });
}

}  // namespace lidarscout::net
