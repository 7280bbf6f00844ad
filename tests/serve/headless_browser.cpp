// HeadlessBrowser: chromium's DevTools protocol over --remote-debugging-pipe (headless_browser.hpp).
#include "serve/headless_browser.hpp"

#include <fcntl.h>
#include <openssl/evp.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <fstream>
#include <stdexcept>
#include <thread>

namespace lidarscout::test {
namespace {

using Clock = std::chrono::steady_clock;

Clock::time_point after(double seconds) {
    return Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
}

// Moves `fd` to exactly `target` in the child (the pipes' own numbers may be 3 or 4 already).
void place(int fd, int target) {
    if (fd != target) ::dup2(fd, target);
}

bool write_all(int fd, const std::string& s) {
    std::size_t done = 0;
    while (done < s.size()) {
        const ssize_t n = ::write(fd, s.data() + done, s.size() - done);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) return false;
        done += static_cast<std::size_t>(n);
    }
    return true;
}

std::string base64_decode(const std::string& text) {
    std::string out(text.size() / 4 * 3 + 3, '\0');
    const int n = EVP_DecodeBlock(reinterpret_cast<unsigned char*>(out.data()),
                                  reinterpret_cast<const unsigned char*>(text.data()), static_cast<int>(text.size()));
    if (n < 0) return {};
    std::size_t size = static_cast<std::size_t>(n);
    for (std::size_t i = text.size(); i > 0 && text[i - 1] == '='; --i) --size;  // (the block keeps the padding)
    out.resize(size);
    return out;
}

}  // namespace

HeadlessBrowser::HeadlessBrowser(const std::filesystem::path& profile, int width, int height) {
    ::signal(SIGPIPE, SIG_IGN);  // (a write to a chromium that has gone fails instead of ending the tests)
    int ours[2], theirs[2];  // ours: we write, chromium reads (its fd 3); theirs: chromium writes (its fd 4)
    if (::pipe2(ours, O_CLOEXEC) != 0) return;
    if (::pipe2(theirs, O_CLOEXEC) != 0) return;
    pid_ = ::fork();
    if (pid_ == 0) {
        ::setpgid(0, 0);  // (its helpers with it, so that the destructor ends them all)
        const int in = ::dup(ours[0]), out = ::dup(theirs[1]);
        place(in, 3);
        place(out, 4);
        const int null = ::open("/dev/null", O_RDWR);
        ::dup2(null, 1);
        ::dup2(null, 2);
        const std::string dir = "--user-data-dir=" + profile.string();
        const std::string size = "--window-size=" + std::to_string(width) + "," + std::to_string(height);
        ::execl("/usr/bin/chromium", "chromium", "--headless", "--no-sandbox", "--use-angle=swiftshader",
                "--enable-unsafe-swiftshader", "--hide-scrollbars", "--remote-debugging-pipe", dir.c_str(),
                size.c_str(), "about:blank", static_cast<char*>(nullptr));
        ::_exit(127);
    }
    ::close(ours[0]);
    ::close(theirs[1]);
    to_ = ours[1];
    from_ = theirs[0];
    if (pid_ < 0) return;
    try {
        const auto target = call("Target.createTarget", {{"url", "about:blank"}}, true).at("targetId");
        session_ = call("Target.attachToTarget", {{"targetId", target}, {"flatten", true}}, true)
                       .at("sessionId")
                       .get<std::string>();
        call("Emulation.setDeviceMetricsOverride",
             {{"width", width}, {"height", height}, {"deviceScaleFactor", 1}, {"mobile", false}});
    } catch (const std::exception&) {
        session_.clear();
    }
}

HeadlessBrowser::~HeadlessBrowser() {
    if (pid_ > 0) {
        try {
            call("Browser.close", nlohmann::json::object(), true, 5);
        } catch (const std::exception&) {
        }
        const auto until = Clock::now() + std::chrono::seconds(5);
        while (::waitpid(pid_, nullptr, WNOHANG) == 0 && Clock::now() < until) {
            std::this_thread::sleep_for(std::chrono::milliseconds(50));
        }
        ::kill(-pid_, SIGKILL);  // (whatever is left of its process group)
        ::waitpid(pid_, nullptr, WNOHANG);
    }
    if (to_ >= 0) ::close(to_);
    if (from_ >= 0) ::close(from_);
}

nlohmann::json HeadlessBrowser::read_message(double seconds) {
    const auto until = after(seconds);
    for (;;) {
        const auto end = pending_.find('\0');
        if (end != std::string::npos) {
            auto message = nlohmann::json::parse(pending_.substr(0, end), nullptr, false);
            pending_.erase(0, end + 1);
            return message;
        }
        const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(until - Clock::now()).count();
        if (left <= 0) throw std::runtime_error("chromium did not answer in time");
        pollfd p{from_, POLLIN, 0};
        const int ready = ::poll(&p, 1, static_cast<int>(left));
        if (ready < 0 && errno == EINTR) continue;
        if (ready <= 0) continue;
        char buf[65536];
        const ssize_t n = ::read(from_, buf, sizeof buf);
        if (n < 0 && errno == EINTR) continue;
        if (n <= 0) throw std::runtime_error("chromium closed its pipe");
        pending_.append(buf, static_cast<std::size_t>(n));
    }
}

nlohmann::json HeadlessBrowser::call(const std::string& method, const nlohmann::json& params, bool browser_level,
                                     double seconds) {
    const int id = next_id_++;
    nlohmann::json message = {{"id", id}, {"method", method}, {"params", params}};
    if (!browser_level) message["sessionId"] = session_;
    if (!write_all(to_, message.dump() + std::string(1, '\0'))) throw std::runtime_error("chromium's pipe is closed");
    for (;;) {  // (events of the page's session come between; they are not asked for and are dropped)
        const auto answer = read_message(seconds);
        if (!answer.is_object() || answer.value("id", -1) != id) continue;
        if (answer.contains("error")) throw std::runtime_error(method + ": " + answer["error"].dump());
        return answer.value("result", nlohmann::json::object());
    }
}

bool HeadlessBrowser::open(const std::string& url) {
    try {
        call("Page.navigate", {{"url", "about:blank"}});  // (a new document even when only the #fragment differs)
        return !call("Page.navigate", {{"url", url}}).contains("errorText");
    } catch (const std::exception&) {
        return false;
    }
}

nlohmann::json HeadlessBrowser::evaluate(const std::string& expression) {
    try {
        const auto r = call("Runtime.evaluate",
                            {{"expression", expression}, {"returnByValue", true}, {"awaitPromise", true}});
        if (r.contains("exceptionDetails")) return nullptr;
        return r.at("result").value("value", nlohmann::json());
    } catch (const std::exception&) {
        return nullptr;
    }
}

bool HeadlessBrowser::wait_until(const std::string& expression, double seconds) {
    const auto until = after(seconds);
    while (Clock::now() < until) {
        if (evaluate("Boolean(" + expression + ")") == true) return true;
        std::this_thread::sleep_for(std::chrono::milliseconds(250));
    }
    return false;
}

bool HeadlessBrowser::screenshot(const std::filesystem::path& path) {
    try {
        const auto png = base64_decode(call("Page.captureScreenshot", {{"format", "png"}}).at("data"));
        std::ofstream out(path, std::ios::binary);
        out.write(png.data(), static_cast<std::streamsize>(png.size()));
        return !png.empty() && static_cast<bool>(out);
    } catch (const std::exception&) {
        return false;
    }
}

std::string HeadlessBrowser::html() {
    const auto v = evaluate("document.documentElement.outerHTML");
    return v.is_string() ? v.get<std::string>() : std::string();
}

}  // namespace lidarscout::test
