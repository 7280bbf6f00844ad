// Debian's chromium, headless, driven over the DevTools protocol on a pipe (--remote-debugging-pipe:
// JSON messages ending in a NUL byte, ours on fd 3, chromium's on fd 4), so that a test waits in real
// time for what the page says it has done. (--virtual-time-budget with --dump-dom or --screenshot let
// the page's clock run ahead while one of its fetches was still answered beside a busy suite: the
// budget ran out with the page stalled before its first chunk points, in 2 of 6 tries beside a
// DEM test in a loop.) WebGL2 on SwiftShader, at a fixed viewport of 1280 x 720 CSS pixels.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

namespace lidarscout::test {

class HeadlessBrowser {
public:
    // Starts chromium with its profile under `profile`; ok() is false when it could not start.
    HeadlessBrowser(const std::filesystem::path& profile, int width = 1280, int height = 720);
    ~HeadlessBrowser();
    HeadlessBrowser(const HeadlessBrowser&) = delete;
    HeadlessBrowser& operator=(const HeadlessBrowser&) = delete;

    bool ok() const { return pid_ > 0 && !session_.empty(); }
    // Opens `url` in the page (a fresh navigation).
    bool open(const std::string& url);
    // The value of a JavaScript expression in the page (awaited when it is a promise); null when it threw.
    nlohmann::json evaluate(const std::string& expression);
    // Whether `expression` became true within `seconds`, asked every 250 ms.
    bool wait_until(const std::string& expression, double seconds);
    // The viewport as a PNG file at `path`.
    bool screenshot(const std::filesystem::path& path);
    // The document's HTML.
    std::string html();

private:
    // Sends one command (to the page's session unless `browser_level`) and returns its result; throws
    // std::runtime_error on an error answer, a closed pipe or no answer within `seconds`.
    nlohmann::json call(const std::string& method, const nlohmann::json& params, bool browser_level = false,
                        double seconds = 60);
    nlohmann::json read_message(double seconds);

    pid_t pid_ = -1;
    int to_ = -1, from_ = -1;
    int next_id_ = 1;
    std::string session_, pending_;
};

}  // namespace lidarscout::test
