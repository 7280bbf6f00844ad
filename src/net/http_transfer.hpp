// One HTTP attempt at some of a request's ranges: the libcurl easy handle with its options
// (TLS verification, same-scheme redirects, time-outs, the deadline, AWS Signature V4 by
// libcurl), the header and body
// callbacks that stop a wrong response early (status 200 to a Range request, a body larger
// than asked, a redirect to another scheme or origin), and the validation of the finished
// response (206, Content-Range, length, validator).
#pragma once

#include <curl/curl.h>

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "net/http_client.hpp"

namespace lidarscout::net {

// A request and what has been received for it so far (shared by its transfers).
struct HttpJob {
    RangeRequest request;
    HttpClient::Callback done;
    RangeReply reply;          // reply.validator: pinned by the caller or by the first response
    std::size_t pending = 0;   // transfers not finished
};

enum class TransferOutcome {
    Done,          // the ranges are in the job's reply
    Retry,         // a transient failure: try again after a backoff
    Fail,          // a definite failure: message()
    NoMultiRange,  // the server does not answer multi-range requests: ask for each range alone
};

class HttpTransfer {
public:
    HttpTransfer(std::shared_ptr<HttpJob> job, std::vector<std::size_t> ranges);
    ~HttpTransfer();
    HttpTransfer(const HttpTransfer&) = delete;
    HttpTransfer& operator=(const HttpTransfer&) = delete;

    // A fresh easy handle for the next attempt (owned by this transfer).
    CURL* start_attempt(const HttpSettings& settings);
    // Judges the attempt that ended with `code`; on Done the data are in the job's reply.
    TransferOutcome finish_attempt(CURLcode code);

    HttpJob& job() { return *job_; }
    const std::shared_ptr<HttpJob>& job_ptr() const { return job_; }
    const std::vector<std::size_t>& ranges() const { return ranges_; }
    const std::string& message() const { return message_; }
    unsigned attempts() const { return attempts_; }
    std::uint64_t body_bytes() const { return attempt_body_; }
    std::uint64_t header_bytes() const { return attempt_headers_; }
    // Of the attempt just finished: whether it was answered over HTTP/2; connections it opened.
    bool used_http2() const;
    std::uint64_t new_connections() const;
    // Whether the attempt just finished was answered as multipart/byteranges.
    bool answered_multipart() const;

    std::chrono::steady_clock::time_point not_before{};  // when a retry may start

private:
    static std::size_t on_header(char* data, std::size_t size, std::size_t n, void* self);
    static std::size_t on_body(char* data, std::size_t size, std::size_t n, void* self);
    static int on_progress(void* self, curl_off_t, curl_off_t, curl_off_t, curl_off_t);
    void header_line(std::string_view line);
    bool accept_body_start();
    bool accept_multipart_start();
    bool accept_whole_file();
    bool multi() const { return ranges_.size() > 1 || job_->request.suffix > 0; }  // asks several ranges
    bool is_suffix(const ContentRange& got) const;
    std::size_t keep_error_body(const char* data, std::size_t bytes);
    std::string status_message() const;
    void set_signing();
    void keep_final_url();
    TransferOutcome take_whole();
    bool check_single_range_start();
    TransferOutcome judge_attempt(CURLcode code);
    TransferOutcome judge_transport(CURLcode code);
    TransferOutcome judge_status();
    TransferOutcome take_single();
    TransferOutcome take_multipart();
    TransferOutcome take_whole_file();
    bool take_part(const BodyPart& part, const std::map<std::uint64_t, std::size_t>& by_offset,
                   std::vector<bool>& seen);
    bool validator_matches();
    bool total_matches(const ContentRange& got);
    TransferOutcome fail(std::string message);
    bool check_redirect();           // at the end of a 3xx response's headers
    bool single_body_complete() const;
    bool past_deadline() const;
    std::string deadline_message() const;
    std::uint64_t asked_bytes() const;
    ByteRange asked_now() const;  // the single range this attempt asks for (resumed part left out)
    std::uint64_t body_limit() const;

    std::shared_ptr<HttpJob> job_;
    std::vector<std::size_t> ranges_;
    CURL* easy_ = nullptr;
    curl_slist* headers_ = nullptr;
    unsigned attempts_ = 0;
    std::vector<std::uint8_t> body_;  // single range: all bytes so far (kept across attempts)
    std::string error_body_;          // of an error status (bounded)
    std::uint64_t attempt_start_ = 0; // body_.size() when this attempt started
    std::uint64_t attempt_body_ = 0, attempt_headers_ = 0;

    // the response of this attempt (the last one when redirected)
    long status_ = 0;
    std::string content_range_, content_type_, etag_, last_modified_, location_;
    bool clock_started_ = false;  // the deadline's: at the first attempt's first progress
    std::chrono::steady_clock::time_point started_{}, deadline_{};
    std::chrono::milliseconds grace_{0};
    std::uint64_t min_rate_ = 0;
    bool body_started_ = false;
    TransferOutcome abort_ = TransferOutcome::Done;  // set when a callback stopped the transfer
    std::string message_;
    char curl_error_[CURL_ERROR_SIZE] = {};
};

}  // namespace lidarscout::net
