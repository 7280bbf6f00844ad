// A test fixture: a small HTTP/1.1 server on 127.0.0.1 (ephemeral port, one thread per
// connection) serving one byte buffer with correct single-range answers, and faults injected
// on demand: the connection dropped mid-body, 503 before success, Range ignored, a wrong
// Content-Range, a truncated body, a slow response, a body longer than asked, a changed
// ETag, a redirect to another scheme; and hostile answers: a body trickled a few bytes at a
// time, a Content-Length larger than the Content-Range, stray bytes after a body on a kept-alive
// connection, a redirect to any URL, 404 for every request after the first few. Multi-range
// requests are answered with the whole buffer and status 200, as object stores do. S3's faults:
// 503 SlowDown with its XML body, 403 (an expired signed URL). No answer has an Accept-Ranges
// header. The head of every request is kept (requests_seen) for the tests of what is sent. A
// test may answer every request itself (`respond`: a hostile S3 server's listings and errors).
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace lidarscout::test {

enum class Fault {
    None,
    DropMidBody,        // half the body, then the connection is closed
    ServiceUnavailable, // 503
    IgnoreRange,        // 200 and the whole buffer
    WrongContentRange,  // 206 with a Content-Range one byte off
    TruncatedBody,      // Content-Length of the range, all but its last byte, connection closed
    Slow,               // nothing for `slow_ms`, then the answer
    LongerBody,         // 206 with the right Content-Range and 100 bytes more
    NewEtag,            // another ETag (the file changed)
    RedirectToHttps,    // 302 to https://
    Trickle,            // the right headers, then the body `trickle_bytes` every `trickle_ms`
    LyingLength,        // 206, the right Content-Range and body, Content-Length 1000 more; then closed
    StrayBytes,         // the right answer, then 16 bytes more (sent when the next request has come)
    Redirect,           // `redirect_status` (302) to `redirect_to`
    SlowDown,           // 503 with S3's XML error body, code SlowDown
    Forbidden,          // 403 with S3's XML error body, code AccessDenied
};

class FaultServer {
public:
    explicit FaultServer(std::vector<std::uint8_t> data) : data_(std::move(data)) {
        listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
        int one = 1;
        ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t len = sizeof a;
        ::bind(listener_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        ::listen(listener_, 64);
        ::getsockname(listener_, reinterpret_cast<sockaddr*>(&a), &len);
        port_ = ntohs(a.sin_port);
        acceptor_ = std::thread([this] { accept_loop(); });
    }
    ~FaultServer() {
        stop_ = true;
        ::shutdown(listener_, SHUT_RDWR);
        ::close(listener_);
        acceptor_.join();
        std::lock_guard lock(mutex_);
        for (const int fd : connections_) ::shutdown(fd, SHUT_RDWR);
        for (auto& t : workers_) t.join();
    }

    std::string url() const { return "http://127.0.0.1:" + std::to_string(port_) + "/file.bin"; }
    // The next `count` requests get `fault` (then the server answers correctly).
    void inject(Fault fault, int count = 1) {
        std::lock_guard lock(mutex_);
        fault_ = fault;
        fault_count_ = count;
    }
    int slow_ms = 2500;
    int trickle_ms = 20;
    std::size_t trickle_bytes = 2;
    std::string redirect_to;
    int redirect_status = 302;
    bool multi_range_206 = false;  // a multi-range request gets 206 with the whole file (as s3rver answers)
    int answer_first = 1 << 30;  // requests answered; 404 for the ones after
    // When set, answers every request (its request line and headers in, the whole response out;
    // a shared answer is sent without a copy). Set before the first request.
    std::function<std::shared_ptr<const std::string>(const std::string& head)> respond;
    std::vector<std::string> ranges_seen() {
        std::lock_guard lock(mutex_);
        return ranges_;
    }
    int requests() const { return requests_.load(); }
    // The request line and headers of every request so far.
    std::vector<std::string> requests_seen() {
        std::lock_guard lock(mutex_);
        return heads_;
    }

private:
    void accept_loop() {
        while (!stop_) {
            const int fd = ::accept(listener_, nullptr, nullptr);
            if (fd < 0) return;
            std::lock_guard lock(mutex_);
            connections_.push_back(fd);
            workers_.emplace_back([this, fd] { serve(fd); });
        }
    }

    void serve(int fd) {
        std::string buffer;
        char chunk[4096];
        for (;;) {
            const auto end = buffer.find("\r\n\r\n");
            if (end == std::string::npos) {
                const ssize_t n = ::recv(fd, chunk, sizeof chunk, 0);
                if (n <= 0) break;
                buffer.append(chunk, static_cast<std::size_t>(n));
                continue;
            }
            const std::string request = buffer.substr(0, end);
            buffer.erase(0, end + 4);
            if (!answer(fd, request)) break;
        }
        ::close(fd);
    }

    Fault take_fault() {
        std::lock_guard lock(mutex_);
        if (fault_count_ <= 0) return Fault::None;
        --fault_count_;
        return fault_;
    }

    static std::string header_value(const std::string& request, const std::string& name) {
        const auto at = request.find("\r\n" + name + ": ");
        if (at == std::string::npos) return {};
        const auto start = at + name.size() + 4;
        return request.substr(start, request.find("\r\n", start) - start);
    }

    static void send_all(int fd, const std::string& s) {
        for (std::size_t done = 0; done < s.size();) {
            const ssize_t n = ::send(fd, s.data() + done, s.size() - done, MSG_NOSIGNAL);
            if (n <= 0) return;
            done += static_cast<std::size_t>(n);
        }
    }

    // Answers one request; false when the connection is to be closed.
    bool answer(int fd, const std::string& request) {
        ++requests_;
        const std::string range = header_value(request, "Range");
        {
            std::lock_guard lock(mutex_);
            ranges_.push_back(range);
            heads_.push_back(request);
        }
        if (stray_next_.exchange(false)) send_all(fd, "STRAY BYTES HERE");  // as if they ended the last body
        if (respond) return send_all(fd, *respond(request)), true;
        const Fault fault = take_fault();
        if (fault == Fault::Slow) std::this_thread::sleep_for(std::chrono::milliseconds(slow_ms));
        const std::string etag = fault == Fault::NewEtag ? "\"v2\"" : "\"v1\"";
        const std::string body(data_.begin(), data_.end());
        if (fault == Fault::ServiceUnavailable) {
            send_all(fd, "HTTP/1.1 503 Service Unavailable\r\nContent-Length: 0\r\n\r\n");
            return true;
        }
        if (requests_ > answer_first) {
            send_all(fd, "HTTP/1.1 404 Not Found\r\nContent-Length: 0\r\n\r\n");
            return true;
        }
        if (fault == Fault::Redirect) {
            send_all(fd, "HTTP/1.1 " + std::to_string(redirect_status) + " Redirect\r\nLocation: " + redirect_to +
                             "\r\nContent-Length: 0\r\n\r\n");
            return true;
        }
        if (fault == Fault::SlowDown || fault == Fault::Forbidden) {
            const bool slow = fault == Fault::SlowDown;
            const std::string xml = std::string("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<Error><Code>") +
                                    (slow ? "SlowDown" : "AccessDenied") + "</Code><Message>" +
                                    (slow ? "Please reduce your request rate." : "Request has expired") +
                                    "</Message></Error>";
            send_all(fd, std::string(slow ? "HTTP/1.1 503 Slow Down" : "HTTP/1.1 403 Forbidden") +
                             "\r\nContent-Type: application/xml\r\nContent-Length: " + std::to_string(xml.size()) +
                             "\r\n\r\n" + xml);
            return true;
        }
        if (fault == Fault::RedirectToHttps) {
            send_all(fd, "HTTP/1.1 302 Found\r\nLocation: https://127.0.0.1:" + std::to_string(port_) +
                             "/file.bin\r\nContent-Length: 0\r\n\r\n");
            return true;
        }
        const bool single = range.rfind("bytes=", 0) == 0 && range.find(',') == std::string::npos;
        if (!single && multi_range_206) {
            send_all(fd, "HTTP/1.1 206 Partial Content\r\nETag: " + etag + "\r\nContent-Range: bytes 0-" +
                             std::to_string(body.size() - 1) + "/" + std::to_string(body.size()) +
                             "\r\nContent-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body);
            return true;
        }
        if (fault == Fault::IgnoreRange || !single) {
            send_all(fd, "HTTP/1.1 200 OK\r\nETag: " + etag + "\r\nContent-Length: " + std::to_string(body.size()) +
                             "\r\n\r\n" + body);
            return true;
        }
        const auto dash = range.find('-');
        const std::uint64_t first = std::stoull(range.substr(6, dash - 6));
        std::uint64_t last = std::stoull(range.substr(dash + 1));
        if (first >= body.size()) {
            send_all(fd, "HTTP/1.1 416 Range Not Satisfiable\r\nContent-Length: 0\r\n\r\n");
            return true;
        }
        last = std::min<std::uint64_t>(last, body.size() - 1);
        std::string part = body.substr(first, last - first + 1);
        const std::uint64_t shown_first = fault == Fault::WrongContentRange ? first + 1 : first;
        const std::uint64_t shown_last = fault == Fault::WrongContentRange ? last + 1 : last;
        if (fault == Fault::LongerBody) part += std::string(100, 'x');
        const std::size_t length = part.size() + (fault == Fault::LyingLength ? 1000 : 0);
        std::string head = "HTTP/1.1 206 Partial Content\r\nETag: " + etag + "\r\nContent-Range: bytes " +
                           std::to_string(shown_first) + "-" + std::to_string(shown_last) + "/" +
                           std::to_string(body.size()) + "\r\nContent-Length: " + std::to_string(length) +
                           "\r\n\r\n";
        if (fault == Fault::Trickle) return trickle(fd, head, part);
        if (fault == Fault::LyingLength) return send_all(fd, head + part), false;
        if (fault == Fault::StrayBytes) stray_next_ = true;
        if (fault == Fault::DropMidBody || fault == Fault::TruncatedBody) {
            send_all(fd, head + part.substr(0, fault == Fault::DropMidBody ? part.size() / 2 : part.size() - 1));
            return false;
        }
        send_all(fd, head + part);
        return true;
    }

    // Sends the head at once and the body a few bytes at a time; false (closes) when done or refused.
    bool trickle(int fd, const std::string& head, const std::string& body) {
        send_all(fd, head);
        for (std::size_t at = 0; at < body.size() && !stop_; at += trickle_bytes) {
            const std::string piece = body.substr(at, trickle_bytes);
            if (::send(fd, piece.data(), piece.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(piece.size())) break;
            ++trickled_;
            std::this_thread::sleep_for(std::chrono::milliseconds(trickle_ms));
        }
        return false;
    }

public:
    int trickled_sends() const { return trickled_.load(); }

private:
    std::atomic<int> trickled_{0};
    std::atomic<bool> stray_next_{false};
    std::vector<std::uint8_t> data_;
    int listener_ = -1;
    int port_ = 0;
    std::atomic<bool> stop_{false};
    std::atomic<int> requests_{0};
    std::thread acceptor_;
    std::mutex mutex_;
    std::vector<int> connections_;
    std::vector<std::thread> workers_;
    Fault fault_ = Fault::None;
    int fault_count_ = 0;
    std::vector<std::string> ranges_;
    std::vector<std::string> heads_;
};

}  // namespace lidarscout::test
