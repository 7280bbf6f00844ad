// The client's thread: a libcurl multi handle that runs every transfer, retries with
// backoff, and splits multi-range requests for hosts that do not answer them.
#include "net/http_client.hpp"

#include <algorithm>
#include <condition_variable>
#include <deque>
#include <future>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "net/http_transfer.hpp"

namespace lidarscout::net {

namespace {

using Clock = std::chrono::steady_clock;

// "scheme://host:port" of a URL (the unit that answers multi-range requests or not).
std::string origin_of(const std::string& url) {
    const auto start = url.find("://");
    if (start == std::string::npos) return url;
    const auto end = url.find_first_of("/?#", start + 3);
    return url.substr(0, end);
}

// Splits the job's ranges into groups whose Range header stays under `max_header` characters.
// (A request with a suffix is one group: it is never split.)
std::vector<std::vector<std::size_t>> range_groups(const RangeRequest& r, std::size_t max_header, bool multi) {
    std::vector<std::vector<std::size_t>> groups;
    if (r.suffix) {
        groups.emplace_back(r.ranges.size());
        for (std::size_t i = 0; i < r.ranges.size(); ++i) groups.back()[i] = i;
        return groups;
    }
    std::size_t length = 0;
    for (std::size_t i = 0; i < r.ranges.size(); ++i) {
        const auto& range = r.ranges[i];
        const std::size_t item = std::to_string(range.offset).size() + std::to_string(range.last()).size() + 2;
        if (groups.empty() || !multi || length + item > max_header) {
            groups.emplace_back();
            length = 0;
        }
        groups.back().push_back(i);
        length += item;
    }
    return groups;
}

}  // namespace

struct HttpClient::Impl {
    using MultiRange = HttpClient::MultiRange;
    explicit Impl(HttpSettings s) : settings(s) {
        static std::once_flag global;
        std::call_once(global, [] { curl_global_init(CURL_GLOBAL_DEFAULT); });
        multi = curl_multi_init();
        curl_multi_setopt(multi, CURLMOPT_PIPELINING, CURLPIPE_MULTIPLEX);
        curl_multi_setopt(multi, CURLMOPT_MAX_HOST_CONNECTIONS, static_cast<long>(s.connections_per_host));
        curl_multi_setopt(multi, CURLMOPT_MAXCONNECTS, static_cast<long>(s.connections_per_host * 2));
        thread = std::thread([this] { run(); });
    }
    ~Impl() {
        {
            std::lock_guard lock(mutex);
            stop = true;
        }
        curl_multi_wakeup(multi);
        thread.join();
        for (auto& [easy, t] : running) curl_multi_remove_handle(multi, easy);
        running.clear();
        curl_multi_cleanup(multi);
    }

    void submit(RangeRequest request, Callback done) {
        auto job = std::make_shared<HttpJob>();
        job->reply.parts.resize(request.ranges.size() + (request.suffix ? 1 : 0));
        job->reply.validator = request.validator;
        job->request = std::move(request);
        job->done = std::move(done);
        {
            std::lock_guard lock(mutex);
            incoming.push_back(std::move(job));
        }
        curl_multi_wakeup(multi);
    }

    // --- on the client's thread ---------------------------------------------------

    void run() {
        for (;;) {
            std::deque<std::shared_ptr<HttpJob>> jobs;
            {
                std::lock_guard lock(mutex);
                if (stop) return;
                jobs.swap(incoming);
            }
            for (const auto& job : jobs) start_job(job);
            start_due_retries();
            int still = 0;
            curl_multi_perform(multi, &still);
            reap();
            curl_multi_poll(multi, nullptr, 0, poll_timeout_ms(), nullptr);
        }
    }

    void start_job(const std::shared_ptr<HttpJob>& job) {
        if (job->request.ranges.empty() && !job->request.suffix) return finish_job(*job);
        const bool multi_ok = !job->request.one_range && answers_multi_range(job->request.asked());
        const HttpSettings s = current_settings();
        for (auto& group : range_groups(job->request, s.max_range_header, multi_ok)) {
            ++job->pending;
            launch(std::make_unique<HttpTransfer>(job, std::move(group)), s);
        }
    }

    // Starts `t`, or queues it behind its origin's transfers when that origin already has
    // connections_per_host of them in the multi handle: libcurl keeps the handles it cannot connect
    // yet in a list it walks on every removal, so tens of thousands added at once cost time
    // quadratic in their number (a 22,500-tile catalog: 88% of the client's CPU).
    void launch(std::unique_ptr<HttpTransfer> t, const HttpSettings& s) {
        const std::string origin = origin_of(t->job().request.asked());
        if (active[origin] >= std::max(1u, s.connections_per_host)) {
            queued[origin].push_back(std::move(t));
            return;
        }
        ++active[origin];
        CURL* easy = t->start_attempt(s);
        curl_multi_add_handle(multi, easy);
        running.emplace(easy, std::move(t));
        std::lock_guard lock(stats_mutex);
        ++stats.requests;
        stats.peak_transfers = std::max<std::uint64_t>(stats.peak_transfers, running.size());
    }

    void reap() {
        int left = 0;
        while (CURLMsg* msg = curl_multi_info_read(multi, &left)) {
            if (msg->msg != CURLMSG_DONE) continue;
            CURL* easy = msg->easy_handle;
            const CURLcode code = msg->data.result;
            curl_multi_remove_handle(multi, easy);
            auto node = running.extract(easy);
            const std::string origin = origin_of(node.mapped()->job().request.asked());
            finished(std::move(node.mapped()), code);
            --active[origin];
            start_queued(origin);
        }
    }

    // The next transfers queued behind `origin`'s, as far as its limit allows.
    void start_queued(const std::string& origin) {
        auto it = queued.find(origin);
        if (it == queued.end()) return;
        const HttpSettings s = current_settings();
        while (!it->second.empty() && active[origin] < std::max(1u, s.connections_per_host)) {
            auto t = std::move(it->second.front());
            it->second.pop_front();
            launch(std::move(t), s);
        }
        if (it->second.empty()) queued.erase(it);
    }

    void finished(std::unique_ptr<HttpTransfer> t, CURLcode code) {
        const TransferOutcome outcome = t->finish_attempt(code);
        {
            std::lock_guard lock(stats_mutex);
            stats.body_bytes += t->body_bytes();
            stats.header_bytes += t->header_bytes();
            stats.http2_responses += t->used_http2() ? 1 : 0;
            stats.connections += t->new_connections();
        }
        const HttpSettings s = current_settings();
        if (outcome == TransferOutcome::Done && t->answered_multipart()) learned(t->job().request.asked(), true);
        switch (outcome) {
            case TransferOutcome::Done: return transfer_done(*t);
            case TransferOutcome::Retry:
                if (t->attempts() <= s.retries) return schedule_retry(std::move(t), s);
                return transfer_failed(*t, t->message() + " (after " + std::to_string(t->attempts()) + " attempts)");
            case TransferOutcome::NoMultiRange:
                if (!t->job().request.suffix) return split(std::move(t), s);
                learned(t->job().request.asked(), false);
                return transfer_failed(*t, t->message());
            case TransferOutcome::Fail: return transfer_failed(*t, t->message());
        }
    }

    void schedule_retry(std::unique_ptr<HttpTransfer> t, const HttpSettings& s) {
        {
            std::lock_guard lock(stats_mutex);
            ++stats.retries;
        }
        const auto delay = s.backoff * (1u << std::min(t->attempts() - 1, 6u));
        t->not_before = Clock::now() + delay;
        waiting.push_back(std::move(t));
    }

    void start_due_retries() {
        const auto now = Clock::now();
        const HttpSettings s = current_settings();
        for (auto it = waiting.begin(); it != waiting.end();) {
            if ((*it)->not_before > now) {
                ++it;
                continue;
            }
            auto t = std::move(*it);
            it = waiting.erase(it);
            launch(std::move(t), s);
        }
    }

    int poll_timeout_ms() const {
        if (waiting.empty()) return 1000;
        auto soonest = waiting.front()->not_before;
        for (const auto& t : waiting) soonest = std::min(soonest, t->not_before);
        const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(soonest - Clock::now()).count();
        return static_cast<int>(std::clamp<long long>(ms, 0, 1000));
    }

    // The server answered a multi-range request with something else: ask range by range,
    // now and for later requests to the same origin.
    void split(std::unique_ptr<HttpTransfer> t, const HttpSettings& s) {
        HttpJob& job = t->job();
        learned(job.request.asked(), false);
        for (const auto i : t->ranges()) {
            ++job.pending;
            launch(std::make_unique<HttpTransfer>(t->job_ptr(), std::vector<std::size_t>{i}), s);
        }
        --job.pending;
    }

    void transfer_failed(HttpTransfer& t, const std::string& message) {
        if (t.job().reply.error.empty()) t.job().reply.error = message;
        transfer_done(t);
    }

    void transfer_done(HttpTransfer& t) {
        HttpJob& job = t.job();
        if (--job.pending == 0) finish_job(job);
    }

    void finish_job(HttpJob& job) {
        if (!job.reply.error.empty()) job.reply.parts.clear();
        auto done = std::move(job.done);
        done(std::move(job.reply));
    }

    // What an answer from `url`'s origin showed: that it answers several ranges at once, or not (which
    // stays, whatever other answers show).
    void learned(const std::string& url, bool multi_range) {
        std::lock_guard lock(mutex);
        (multi_range ? multi_range_origins : single_range_origins).insert(origin_of(url));
    }

    bool answers_multi_range(const std::string& url) const {
        std::lock_guard lock(mutex);
        return !single_range_origins.contains(origin_of(url));
    }

    MultiRange multi_range(const std::string& url) const {
        const std::string origin = origin_of(url);
        std::lock_guard lock(mutex);
        if (single_range_origins.contains(origin)) return MultiRange::no;
        return multi_range_origins.contains(origin) ? MultiRange::yes : MultiRange::unknown;
    }

    HttpSettings current_settings() const {
        std::lock_guard lock(mutex);
        return settings;
    }

    mutable std::mutex mutex;
    HttpSettings settings;
    bool stop = false;
    std::deque<std::shared_ptr<HttpJob>> incoming;
    CURLM* multi = nullptr;
    std::map<CURL*, std::unique_ptr<HttpTransfer>> running;
    std::vector<std::unique_ptr<HttpTransfer>> waiting;  // retries not yet due
    std::map<std::string, unsigned> active;  // transfers in the multi handle, by origin
    std::map<std::string, std::deque<std::unique_ptr<HttpTransfer>>> queued;  // waiting for their origin
    std::set<std::string> single_range_origins;  // (guarded by mutex: read by answers_multi_range)
    std::set<std::string> multi_range_origins;   // those that answered a multipart response (guarded by mutex)
    mutable std::mutex stats_mutex;
    HttpStats stats;
    std::thread thread;
};

HttpClient::HttpClient(HttpSettings settings) : impl_(std::make_unique<Impl>(settings)) {}
HttpClient::~HttpClient() = default;

HttpClient& HttpClient::shared() {
    static HttpClient client;
    return client;
}

void HttpClient::submit(RangeRequest request, Callback done) { impl_->submit(std::move(request), std::move(done)); }

RangeReply HttpClient::fetch(RangeRequest request) {
    std::promise<RangeReply> promise;
    auto future = promise.get_future();
    submit(std::move(request), [&promise](RangeReply&& reply) { promise.set_value(std::move(reply)); });
    return future.get();
}

void HttpClient::set_settings(const HttpSettings& settings) {
    std::lock_guard lock(impl_->mutex);
    impl_->settings = settings;
}

HttpSettings HttpClient::settings() const { return impl_->current_settings(); }

bool HttpClient::answers_multi_range(const std::string& url) const { return impl_->answers_multi_range(url); }

HttpClient::MultiRange HttpClient::multi_range(const std::string& url) const { return impl_->multi_range(url); }

void HttpClient::count_open(bool in_one) {
    std::lock_guard lock(impl_->stats_mutex);
    ++(in_one ? impl_->stats.opens_in_one : impl_->stats.open_fallbacks);
}

HttpStats HttpClient::stats() const {
    std::lock_guard lock(impl_->stats_mutex);
    return impl_->stats;
}

}  // namespace lidarscout::net
