// One HTTP attempt: libcurl easy handle set-up, response callbacks and validation.
#include "net/http_transfer.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <new>
#include <optional>

#include "core/error.hpp"
#include "core/text.hpp"
#include "net/origin_policy.hpp"
#include "net/server_text.hpp"
#include "net/url.hpp"
#include "net/xml_text.hpp"

namespace lidarscout::net {

namespace {

std::string_view trim(std::string_view s) {
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
    while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
    return s;
}

// Multipart framing allowed per part on top of its data (delimiter, Content-Type, Content-Range).
constexpr std::uint64_t kPartFraming = 512;
// The bytes of an error response's body read for its cause.
constexpr std::size_t kErrorBody = 16 * 1024;

// Whether `got` answers `asked`: the same start, and the same end or one cut at the file's end.
bool answers(const ContentRange& got, const ByteRange& asked) {
    if (got.range.offset != asked.offset) return false;
    if (got.range.length == asked.length) return true;
    return got.range.length < asked.length && got.total && got.range.last() + 1 == *got.total;
}

std::string describe(const ByteRange& r) { return std::to_string(r.offset) + "-" + std::to_string(r.last()); }

bool retryable(CURLcode code) {
    switch (code) {
        case CURLE_OPERATION_TIMEDOUT:
        case CURLE_COULDNT_CONNECT:
        case CURLE_PARTIAL_FILE:
        case CURLE_RECV_ERROR:
        case CURLE_SEND_ERROR:
        case CURLE_GOT_NOTHING:
        case CURLE_HTTP2:
        case CURLE_HTTP2_STREAM:
            return true;
        default:
            return false;
    }
}

}  // namespace

HttpTransfer::HttpTransfer(std::shared_ptr<HttpJob> job, std::vector<std::size_t> ranges)
    : job_(std::move(job)), ranges_(std::move(ranges)) {
    RangeRequest& request = job_->request;  // (a request of one range: its buffer is the body's memory)
    if (request.ranges.size() == 1 && ranges_.size() == 1 && !request.suffix && !request.whole) {
        body_ = std::move(request.buffer);
        body_.clear();
    }
}

HttpTransfer::~HttpTransfer() {
    if (easy_) curl_easy_cleanup(easy_);
    if (headers_) curl_slist_free_all(headers_);
}

ByteRange HttpTransfer::asked_now() const {
    const ByteRange whole = job_->request.ranges[ranges_.front()];
    return {whole.offset + attempt_start_, whole.length - attempt_start_};
}

std::uint64_t HttpTransfer::asked_bytes() const {
    std::uint64_t sum = job_->request.suffix;
    for (const auto i : ranges_) sum += job_->request.ranges[i].length;
    return sum;
}

std::uint64_t HttpTransfer::body_limit() const {
    if (!multi()) return asked_now().length;  // (a whole GET: the most bytes accepted)
    if (status_ == 200) return asked_bytes();  // (a suffix request's whole file)
    const std::uint64_t parts = ranges_.size() + (job_->request.suffix ? 1 : 0);
    return asked_bytes() + (parts + 1) * kPartFraming;
}

CURL* HttpTransfer::start_attempt(const HttpSettings& s) {
    if (easy_) curl_easy_cleanup(easy_);
    if (headers_) curl_slist_free_all(headers_);
    headers_ = nullptr;
    ++attempts_;
    status_ = 0;
    content_range_.clear(), content_type_.clear(), etag_.clear(), last_modified_.clear();
    body_started_ = false;
    abort_ = TransferOutcome::Done;
    if (multi() || job_->request.whole) body_.clear();
    attempt_start_ = body_.size();
    error_body_.clear();
    attempt_body_ = attempt_headers_ = 0;
    curl_error_[0] = '\0';
    location_.clear();
    if (attempts_ == 1) {
        min_rate_ = s.min_rate;
        grace_ = s.deadline_grace;
    }

    std::vector<ByteRange> asked;
    if (!multi()) {
        asked.push_back(asked_now());
    } else {
        for (const auto i : ranges_) asked.push_back(job_->request.ranges[i]);
    }
    std::string range = "Range: " + range_header(asked);
    if (job_->request.suffix) range += (asked.empty() ? "-" : ",-") + std::to_string(job_->request.suffix);
    if (!job_->request.whole) headers_ = curl_slist_append(headers_, range.c_str());
    headers_ = curl_slist_append(headers_, "Accept-Encoding: identity");
    for (const auto& line : job_->request.signing.headers) headers_ = curl_slist_append(headers_, line.c_str());

    easy_ = curl_easy_init();
    const std::string scheme = url_scheme(job_->request.asked());
    curl_easy_setopt(easy_, CURLOPT_URL, job_->request.asked().c_str());
    if (job_->request.path_as_is) curl_easy_setopt(easy_, CURLOPT_PATH_AS_IS, 1L);
    set_signing();
    curl_easy_setopt(easy_, CURLOPT_HTTPHEADER, headers_);
    curl_easy_setopt(easy_, CURLOPT_PROTOCOLS_STR, "http,https");
    curl_easy_setopt(easy_, CURLOPT_FOLLOWLOCATION, 1L);
    curl_easy_setopt(easy_, CURLOPT_MAXREDIRS, 5L);
    curl_easy_setopt(easy_, CURLOPT_REDIR_PROTOCOLS_STR, scheme.c_str());  // never to another scheme
    curl_easy_setopt(easy_, CURLOPT_SSL_VERIFYPEER, 1L);
    curl_easy_setopt(easy_, CURLOPT_SSL_VERIFYHOST, 2L);
    if (!s.ca_file.empty()) curl_easy_setopt(easy_, CURLOPT_CAINFO, s.ca_file.c_str());
    curl_easy_setopt(easy_, CURLOPT_NOSIGNAL, 1L);
    curl_easy_setopt(easy_, CURLOPT_PIPEWAIT, 1L);
    curl_easy_setopt(easy_, CURLOPT_TCP_NODELAY, 1L);
    curl_easy_setopt(easy_, CURLOPT_CONNECTTIMEOUT, s.connect_timeout_s);
    curl_easy_setopt(easy_, CURLOPT_LOW_SPEED_LIMIT, 1L);
    curl_easy_setopt(easy_, CURLOPT_LOW_SPEED_TIME, s.stall_timeout_s);
    curl_easy_setopt(easy_, CURLOPT_NOPROGRESS, 0L);  // the progress callback keeps the deadline
    curl_easy_setopt(easy_, CURLOPT_XFERINFOFUNCTION, &HttpTransfer::on_progress);
    curl_easy_setopt(easy_, CURLOPT_XFERINFODATA, this);
    curl_easy_setopt(easy_, CURLOPT_USERAGENT, "lidarscout");
    curl_easy_setopt(easy_, CURLOPT_ERRORBUFFER, curl_error_);
    curl_easy_setopt(easy_, CURLOPT_HEADERFUNCTION, &HttpTransfer::on_header);
    curl_easy_setopt(easy_, CURLOPT_HEADERDATA, this);
    curl_easy_setopt(easy_, CURLOPT_WRITEFUNCTION, &HttpTransfer::on_body);
    curl_easy_setopt(easy_, CURLOPT_WRITEDATA, this);
    curl_easy_setopt(easy_, CURLOPT_PRIVATE, this);
    return easy_;
}

// AWS Signature V4, computed by libcurl for each request (and each redirect to the same host).
void HttpTransfer::set_signing() {
    const RequestSigning& s = job_->request.signing;
    if (s.aws_sigv4.empty()) return;
    curl_easy_setopt(easy_, CURLOPT_AWS_SIGV4, s.aws_sigv4.c_str());
    curl_easy_setopt(easy_, CURLOPT_USERNAME, s.access_key.c_str());
    curl_easy_setopt(easy_, CURLOPT_PASSWORD, s.secret.c_str());
}

bool HttpTransfer::used_http2() const {
    long version = 0;
    return easy_ && curl_easy_getinfo(easy_, CURLINFO_HTTP_VERSION, &version) == CURLE_OK &&
           version == CURL_HTTP_VERSION_2_0;
}

std::uint64_t HttpTransfer::new_connections() const {
    long count = 0;
    if (!easy_ || curl_easy_getinfo(easy_, CURLINFO_NUM_CONNECTS, &count) != CURLE_OK) return 0;
    return static_cast<std::uint64_t>(std::max(0L, count));
}

// The deadline's clock starts with the first attempt's progress (not while the request waits
// for a connection of libcurl's pool), and a request past it is stopped.
int HttpTransfer::on_progress(void* self, curl_off_t, curl_off_t, curl_off_t, curl_off_t) {
    auto* t = static_cast<HttpTransfer*>(self);
    if (!t->min_rate_) return 0;
    const auto now = std::chrono::steady_clock::now();
    if (!t->clock_started_) {
        t->clock_started_ = true;
        t->started_ = now;
        const double seconds = static_cast<double>(t->asked_bytes()) / static_cast<double>(t->min_rate_);
        t->deadline_ = now + t->grace_ +
                       std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::duration<double>(seconds));
    }
    if (now < t->deadline_) return 0;
    t->abort_ = TransferOutcome::Fail;
    t->message_ = t->deadline_message();
    return 1;  // stops the transfer
}

std::size_t HttpTransfer::on_header(char* data, std::size_t size, std::size_t n, void* self) {
    auto* t = static_cast<HttpTransfer*>(self);
    t->attempt_headers_ += size * n;
    t->header_line(std::string_view(data, size * n));
    const bool end_of_headers = trim(std::string_view(data, size * n)).empty();
    if (end_of_headers && t->status_ >= 300 && t->status_ < 400 && !t->check_redirect()) return 0;  // stops it
    return size * n;
}

void HttpTransfer::header_line(std::string_view line) {
    line = trim(line);
    if (line.rfind("HTTP/", 0) == 0) {  // a new response (after a redirect or 100 Continue)
        status_ = 0;
        content_range_.clear(), content_type_.clear(), etag_.clear(), last_modified_.clear(), location_.clear();
        const auto space = line.find(' ');
        if (space != std::string_view::npos) status_ = std::atol(std::string(line.substr(space + 1, 3)).c_str());
        return;
    }
    const auto colon = line.find(':');
    if (colon == std::string_view::npos) return;
    const std::string name = ascii_lower(trim(line.substr(0, colon)));
    const std::string value(trim(line.substr(colon + 1)));
    if (name == "content-range") content_range_ = value;
    else if (name == "content-type") content_type_ = value;
    else if (name == "etag") etag_ = value;
    else if (name == "last-modified") last_modified_ = value;
    else if (name == "location") location_ = value;
}

// A redirect is followed (by libcurl) only to the scheme and origin of the URL asked for,
// or to an origin the user allowed; never from https to http.
bool HttpTransfer::check_redirect() {
    if (location_.empty()) return true;  // nothing to follow
    const char* current = nullptr;
    curl_easy_getinfo(easy_, CURLINFO_EFFECTIVE_URL, &current);
    const std::string& asked = job_->request.asked();
    const std::string target = resolve_url(current ? current : asked, location_);
    if (url_scheme(target) != url_scheme(asked)) {
        message_ = "a redirect to another scheme is refused (to " + server_text(redact_url(target)) + ")";
    } else if (const std::string refusal = derived_url_refusal(asked, target); !refusal.empty()) {
        message_ = "a redirect to " + server_text(redact_url(target)) + " is refused: " + server_text(refusal);
    } else {
        return true;
    }
    abort_ = TransferOutcome::Fail;
    return false;
}

std::size_t HttpTransfer::on_body(char* data, std::size_t size, std::size_t n, void* self) {
    auto* t = static_cast<HttpTransfer*>(self);
    const std::size_t bytes = size * n;
    if (!t->body_started_) {
        t->body_started_ = true;
        if (!t->accept_body_start()) return 0;  // stops the transfer: nothing more is downloaded
        // A range's bytes in one allocation (a block of 8 MB grown by doubling is copied and its pages touched
        // twice over), and a whole GET's where the server says its length (up to the most accepted: a
        // country's catalog, 245 MB, had been copied eight times while it came).
        if (!t->multi() && !t->job_->request.whole && t->status_ < 300) {
            t->body_.reserve(t->attempt_start_ + t->asked_now().length);
        } else if (!t->multi() && t->status_ == 200) {
            curl_off_t length = -1;
            if (curl_easy_getinfo(t->easy_, CURLINFO_CONTENT_LENGTH_DOWNLOAD_T, &length) == CURLE_OK && length > 0) {
                try {  // (a length the memory cannot hold: the body grows as it comes, and the transfer says why)
                    t->body_.reserve(t->attempt_start_ + std::min<std::uint64_t>(length, t->body_limit()));
                } catch (const std::exception&) {
                }
            }
        }
    }
    t->attempt_body_ += bytes;
    if (t->status_ >= 300) return t->keep_error_body(data, bytes);
    if (t->body_.size() - t->attempt_start_ + bytes > t->body_limit()) {
        t->abort_ = TransferOutcome::Fail;
        t->message_ = t->job_->request.whole
                          ? "the response is larger than the " + std::to_string(t->body_limit()) + " bytes accepted"
                          : std::string("the server sent more bytes than were asked for");
        return 0;
    }
    try {  // (an exception must not cross libcurl's C frames)
        t->body_.insert(t->body_.end(), data, data + bytes);
    } catch (const std::bad_alloc&) {
        t->abort_ = TransferOutcome::Fail;
        t->message_ = "out of memory for the response (" + std::to_string(t->body_.size()) + " bytes held)";
        return 0;
    }
    return bytes;
}

// An error response's body, kept (bounded) for the cause it names.
std::size_t HttpTransfer::keep_error_body(const char* data, std::size_t bytes) {
    if (error_body_.size() + bytes > kErrorBody) {
        abort_ = (status_ == 429 || status_ >= 500) ? TransferOutcome::Retry : TransferOutcome::Fail;
        message_ = status_message();
        return 0;
    }
    error_body_.append(data, bytes);
    return bytes;
}

// "HTTP status 403", with the error code and message of an XML error body (S3's), each cut and
// redacted (net/server_text.hpp).
std::string HttpTransfer::status_message() const {
    std::string message = "HTTP status " + std::to_string(status_);
    const std::string code = xml_text(error_body_, "Code");
    if (code.empty()) return message;
    const std::string text = xml_text(error_body_, "Message");
    message += ", error " + server_text(code) + (text.empty() ? "" : " (" + server_text(text) + ")");
    // (S3 names the bucket's region or endpoint when the request went to the wrong one)
    for (const char* tag : {"Region", "Endpoint"}) {
        const std::string value = xml_text(error_body_, tag);
        if (!value.empty()) message += std::string(", ") + tag + " " + server_text(value);
    }
    return message;
}

bool HttpTransfer::accept_body_start() {
    if (status_ >= 300) return true;  // its body names the cause (a redirect here had no Location)
    if (job_->request.whole) {
        if (status_ == 200) return true;
        abort_ = TransferOutcome::Fail;
        message_ = "HTTP status " + std::to_string(status_);
        return false;
    }
    if (status_ == 206 && multi()) return accept_multipart_start();
    if (status_ == 206) return check_single_range_start();
    if (status_ == 200 && job_->request.suffix) return accept_whole_file();
    if (status_ == 200) {
        abort_ = multi() ? TransferOutcome::NoMultiRange : TransferOutcome::Fail;
        message_ = "the server ignores Range requests (status 200); a full download is not done";
    } else {
        abort_ = TransferOutcome::Fail;
        message_ = "HTTP status " + std::to_string(status_);
    }
    return false;
}

// A 206 to a multi-range request that is not multipart/byteranges (one range spanning them all,
// or the whole file as a 206) is not downloaded: the ranges are asked one by one instead.
// A suffix request's answer in one range (a server that joins ranges that overlap) fails it, but tells
// nothing of the server's other answers.
bool HttpTransfer::accept_multipart_start() {
    if (!multipart_boundary(content_type_).empty()) return true;
    abort_ = job_->request.suffix ? TransferOutcome::Fail : TransferOutcome::NoMultiRange;
    message_ = "the server answers multi-range requests with one range";
    return false;
}

// A 200 to a suffix request is the whole file: taken when it is no larger than what was asked (the
// ranges add up to more than the file), else not downloaded (a server that does not answer several
// ranges).
bool HttpTransfer::accept_whole_file() {
    curl_off_t length = -1;
    curl_easy_getinfo(easy_, CURLINFO_CONTENT_LENGTH_DOWNLOAD_T, &length);
    if (length >= 0 && static_cast<std::uint64_t>(length) <= asked_bytes()) return validator_matches();
    abort_ = TransferOutcome::NoMultiRange;
    message_ = "the server answers multi-range requests with the whole file (status 200)";
    return false;
}

bool HttpTransfer::answered_multipart() const { return status_ == 206 && !multipart_boundary(content_type_).empty(); }

// A single range's Content-Range is checked before any byte is kept, so that a resumed
// body never mixes bytes from elsewhere.
bool HttpTransfer::check_single_range_start() {
    const auto got = parse_content_range(content_range_);
    if (!got || !answers(*got, asked_now())) {
        abort_ = TransferOutcome::Fail;
        message_ = "the server answered bytes \"" + server_text(content_range_) + "\" to a request for " +
                   describe(asked_now());
        return false;
    }
    if (!validator_matches() || !total_matches(*got)) {
        abort_ = TransferOutcome::Fail;
        return false;
    }
    job_->reply.total = got->total;
    return true;
}

bool HttpTransfer::validator_matches() {
    const std::string& got = etag_.empty() ? last_modified_ : etag_;
    std::string& pinned = job_->reply.validator;
    if (pinned.empty()) {
        pinned = got;
        return true;
    }
    if (got == pinned) return true;
    message_ = "the file changed on the server during this session (validator " + server_text(pinned) + ", now " +
               (got.empty() ? std::string("none") : server_text(got)) + ")";
    return false;
}

// The file's size must stay what it was when it was opened (a server without ETag and
// Last-Modified may switch files unnoticed otherwise). A total of "*" tells nothing.
bool HttpTransfer::total_matches(const ContentRange& got) {
    const auto& pinned = job_->request.total;
    if (!pinned || !got.total || *got.total == *pinned) return true;
    message_ = "the file changed on the server during this session (its size was " + std::to_string(*pinned) +
               " bytes, now " + std::to_string(*got.total) + ")";
    return false;
}

TransferOutcome HttpTransfer::fail(std::string message) {
    message_ = std::move(message);
    return TransferOutcome::Fail;
}

bool HttpTransfer::single_body_complete() const {
    if (multi() || !body_started_) return false;
    const auto got = parse_content_range(content_range_);
    return got && body_.size() - attempt_start_ >= got->range.length;
}

bool HttpTransfer::past_deadline() const {
    return min_rate_ && clock_started_ && std::chrono::steady_clock::now() >= deadline_;
}

std::string HttpTransfer::deadline_message() const {
    const double took = std::chrono::duration<double>(std::chrono::steady_clock::now() - started_).count();
    const double allowed = std::chrono::duration<double>(deadline_ - started_).count();
    const std::uint64_t got = !multi() ? body_.size() : attempt_body_;
    char text[160];
    std::snprintf(text, sizeof text, " bytes in %.1f s, past its deadline of %.1f s (%.1f s, then %llu bytes/s; "
                  "--min-rate)", took, allowed, std::chrono::duration<double>(grace_).count(),
                  static_cast<unsigned long long>(min_rate_));
    return "the server sent " + std::to_string(got) + " of " + std::to_string(asked_bytes()) + text;
}

TransferOutcome HttpTransfer::judge_transport(CURLcode code) {
    message_ = server_text(curl_error_[0] ? std::string_view(curl_error_) : curl_easy_strerror(code));
    if (code == CURLE_UNSUPPORTED_PROTOCOL && message_.find("HTTP/0.9") != std::string::npos) {
        // (libcurl then closes the connection: a retry starts on a fresh one)
        message_ = "the server's answer does not start as an HTTP response (stray bytes after an earlier "
                   "response on the same connection?)";
        return TransferOutcome::Retry;
    }
    if (single_body_complete()) {  // every byte of the Content-Range arrived, yet the transfer did not end
        return fail("the response ended badly (" + message_ + ") after all the bytes of its Content-Range " +
                    server_text(content_range_) + ": its Content-Length does not match its Content-Range");
    }
    if (!retryable(code)) return TransferOutcome::Fail;
    // a cut single-range body resumes from what arrived; a cut multipart body starts again
    if (multi()) body_.clear();
    return TransferOutcome::Retry;
}

TransferOutcome HttpTransfer::judge_status() {
    if (status_ == 429 || status_ >= 500) {
        message_ = status_message();
        return TransferOutcome::Retry;
    }
    if (status_ >= 300 && status_ != 416) return fail(status_message());
    if (job_->request.whole) return status_ == 200 ? take_whole() : fail(status_message());
    if (status_ == 200 && job_->request.suffix) return take_whole_file();
    if (status_ == 200) return multi() ? TransferOutcome::NoMultiRange :
        fail("the server ignores Range requests (status 200); a full download is not done");
    if (status_ == 416) return fail("HTTP status 416: the range lies beyond the end of the file");
    if (status_ != 206) return fail(status_message());
    if (!body_started_ && !multi() && !check_single_range_start()) return TransferOutcome::Fail;
    return !multi() ? take_single() : take_multipart();
}

TransferOutcome HttpTransfer::finish_attempt(CURLcode code) {
    const TransferOutcome outcome = judge_attempt(code);
    job_->reply.status = status_;
    if (outcome == TransferOutcome::Done) {
        keep_final_url();
        if (multipart_boundary(content_type_).empty()) job_->reply.content_type = content_type_;
    }
    if (outcome == TransferOutcome::Retry && past_deadline()) return fail(deadline_message());
    return outcome;
}

TransferOutcome HttpTransfer::judge_attempt(CURLcode code) {
    if (abort_ != TransferOutcome::Done) {
        if (abort_ == TransferOutcome::Retry && multi()) body_.clear();
        if (abort_ == TransferOutcome::Retry && !multi()) body_.resize(attempt_start_);
        return abort_;
    }
    if (code != CURLE_OK) return judge_transport(code);
    try {
        return judge_status();
    } catch (const Error& e) {  // a malformed multipart body
        return fail(e.what());
    }
}

// Where the redirects of a successful attempt led (kept by the caller for its next requests).
void HttpTransfer::keep_final_url() {
    const char* effective = nullptr;
    curl_easy_getinfo(easy_, CURLINFO_EFFECTIVE_URL, &effective);
    if (effective && job_->request.asked() != effective) job_->reply.final_url = effective;
}

TransferOutcome HttpTransfer::take_whole() {
    job_->reply.parts[ranges_.front()] = std::move(body_);
    body_.clear();
    return TransferOutcome::Done;
}

TransferOutcome HttpTransfer::take_single() {
    const ByteRange whole = job_->request.ranges[ranges_.front()];
    const auto got = parse_content_range(content_range_);
    const bool whole_answered = got->range.length == asked_now().length;
    const std::uint64_t expected = whole_answered ? whole.length : attempt_start_ + got->range.length;
    if (body_.size() != expected) {
        return fail("the body holds " + std::to_string(body_.size() - attempt_start_) +
                    " bytes, Content-Range promised " + std::to_string(got->range.length));
    }
    job_->reply.parts[ranges_.front()] = std::move(body_);
    body_.clear();
    return TransferOutcome::Done;
}

TransferOutcome HttpTransfer::take_multipart() {
    if (!validator_matches()) return TransferOutcome::Fail;
    const std::string boundary = multipart_boundary(content_type_);
    if (boundary.empty()) return TransferOutcome::NoMultiRange;  // e.g. only the first range answered
    std::map<std::uint64_t, std::size_t> by_offset;
    for (const auto i : ranges_) by_offset.emplace(job_->request.ranges[i].offset, i);
    std::vector<bool> seen(job_->reply.parts.size(), false);
    for (const auto& part : parse_multipart_byteranges(body_, boundary)) {
        if (!take_part(part, by_offset, seen)) return TransferOutcome::Fail;
    }
    for (const auto i : ranges_) {
        if (!seen[i]) return fail("the multipart response lacks bytes " + describe(job_->request.ranges[i]));
    }
    if (job_->request.suffix && !seen.back()) {
        return fail("the multipart response lacks the last " + std::to_string(job_->request.suffix) + " bytes");
    }
    body_.clear();
    return TransferOutcome::Done;
}

// Whether `got` answers a suffix request's last bytes: the file's end, as many bytes as asked or the
// whole file.
bool HttpTransfer::is_suffix(const ContentRange& got) const {
    const std::uint64_t suffix = job_->request.suffix;
    return suffix && got.total && got.range.last() + 1 == *got.total &&
           got.range.length == std::min(suffix, *got.total);
}

// Puts a multipart answer's part in the reply, at the range it answers (`seen` marks those answered;
// the last is the suffix's); false (with the message set) for a part not asked for.
bool HttpTransfer::take_part(const BodyPart& part, const std::map<std::uint64_t, std::size_t>& by_offset,
                             std::vector<bool>& seen) {
    std::optional<std::size_t> index;
    const auto it = by_offset.find(part.content_range.range.offset);
    if (it != by_offset.end() && !seen[it->second] && answers(part.content_range, job_->request.ranges[it->second])) {
        index = it->second;
    } else if (is_suffix(part.content_range) && !seen.back()) {
        index = seen.size() - 1;
    }
    if (!index) {
        message_ = "a part of the multipart response has Content-Range bytes " + describe(part.content_range.range) +
                   ", which was not asked for";
        return false;
    }
    if (!total_matches(part.content_range)) return false;
    seen[*index] = true;
    job_->reply.parts[*index].assign(part.data.begin(), part.data.end());
    if (part.content_range.total) job_->reply.total = part.content_range.total;
    return true;
}

// A suffix request's 200: the whole file, no larger than what was asked (accept_whole_file).
TransferOutcome HttpTransfer::take_whole_file() {
    if (body_.size() > asked_bytes()) return fail("the server sent more bytes than were asked for");
    if (!body_started_ && !validator_matches()) return TransferOutcome::Fail;
    job_->reply.total = body_.size();
    job_->reply.whole_file = true;
    job_->reply.parts.assign(1, std::move(body_));
    body_.clear();
    return TransferOutcome::Done;
}

}  // namespace lidarscout::net
