"""A page in Debian's chromium, headless (SwiftShader WebGL2), driven over the DevTools protocol on a pipe
(--remote-debugging-pipe), so that the caller waits in real time for what the page says it has done: the
browser tests (tests/serve/browser_test.cpp) and bench/bench_page.py. (--virtual-time-budget with --dump-dom or
--screenshot let the page's clock run out while one of its fetches was still answered beside a busy suite.)

    /usr/bin/python3 tests/serve/chromium_page.py URL --profile DIR [--until EXPR] [--seconds S]
                     [--screenshot PNG] [--html OUT]

opens URL at 1280 x 720 CSS pixels, waits (asking every 250 ms, at most S seconds, default 300) until the
JavaScript expression EXPR is true (default: the page's #timings hold "idle", lidarscout serve's page having
everything its view wants), lets it draw two more frames, then writes the viewport as a PNG and the document's
HTML. Exit status 0 when EXPR became true, 1 when it did not (the files are written either way), 2 when
chromium could not be driven.
"""

import argparse
import base64
import json
import os
import pathlib
import subprocess
import sys
import time

PAGE_IDLE = "'idle' in JSON.parse(document.getElementById('timings').textContent || '{}')"


class DevTools:
    """Chromium's DevTools protocol over --remote-debugging-pipe: JSON messages ended by a NUL byte, read
    by chromium on its fd 3 and written on its fd 4."""

    def __init__(self, profile):
        to_chromium, self._write = os.pipe()
        self._read, from_chromium = os.pipe()

        def fds_3_and_4():
            a, b = os.dup(to_chromium), os.dup(from_chromium)  # (above 4: neither dup2 overwrites the other)
            os.dup2(a, 3)
            os.dup2(b, 4)

        self.process = subprocess.Popen(
            ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--use-angle=swiftshader",
             "--enable-unsafe-swiftshader", "--hide-scrollbars", "--window-size=1280,720",
             f"--user-data-dir={profile}", "--remote-debugging-pipe", "about:blank"],
            preexec_fn=fds_3_and_4, close_fds=False, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        os.close(to_chromium)
        os.close(from_chromium)
        self._buffer, self._id = b"", 0

    def call(self, method, params=None, session=None):
        self._id += 1
        message = {"id": self._id, "method": method, "params": params or {}}
        if session:
            message["sessionId"] = session
        os.write(self._write, json.dumps(message).encode() + b"\0")
        while True:
            while b"\0" in self._buffer:
                text, self._buffer = self._buffer.split(b"\0", 1)
                answer = json.loads(text)
                if answer.get("id") == self._id:
                    if "error" in answer:
                        raise RuntimeError(f"{method}: {answer['error']}")
                    return answer["result"]
            data = os.read(self._read, 1 << 20)
            if not data:
                raise RuntimeError("chromium ended")
            self._buffer += data

    def close(self):
        try:
            self.call("Browser.close")  # (its helper processes end with it, before the profile is removed)
            self.process.wait(timeout=10)
        except (RuntimeError, OSError, subprocess.TimeoutExpired):
            self.process.kill()
            self.process.wait()


def open_page(browser, url, width=1280, height=720):
    """A new page at `url` (width x height CSS pixels); its DevTools session."""
    target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
    session = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
    browser.call("Emulation.setDeviceMetricsOverride",
                 {"width": width, "height": height, "deviceScaleFactor": 1, "mobile": False}, session)
    browser.call("Page.navigate", {"url": url}, session)
    return session


def evaluate(browser, session, expression):
    """The value of `expression` in the page (awaited when a promise); None when it threw."""
    r = browser.call("Runtime.evaluate", {"expression": expression, "returnByValue": True, "awaitPromise": True},
                     session)
    return None if "exceptionDetails" in r else r["result"].get("value")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("url")
    parser.add_argument("--profile", required=True, help="chromium's profile folder (made fresh)")
    parser.add_argument("--until", default=PAGE_IDLE)
    parser.add_argument("--seconds", type=float, default=300.0)
    parser.add_argument("--screenshot")
    parser.add_argument("--html")
    args = parser.parse_args()
    try:
        browser = DevTools(args.profile)
    except OSError as e:
        print(f"chromium_page: {e}", file=sys.stderr)
        return 2
    try:
        session = open_page(browser, args.url)
        deadline, reached = time.monotonic() + args.seconds, False
        while not reached and time.monotonic() < deadline:
            reached = evaluate(browser, session, f"Boolean({args.until})") is True
            if not reached:
                time.sleep(0.25)
        evaluate(browser, session, "new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)))")
        if args.screenshot:
            shot = browser.call("Page.captureScreenshot", {"format": "png"}, session)["data"]
            pathlib.Path(args.screenshot).write_bytes(base64.b64decode(shot))
        if args.html:
            pathlib.Path(args.html).write_text(evaluate(browser, session, "document.documentElement.outerHTML") or "")
        if not reached:
            print(f"chromium_page: {args.until} not true within {args.seconds:g} s", file=sys.stderr)
        return 0 if reached else 1
    except RuntimeError as e:
        print(f"chromium_page: {e}", file=sys.stderr)
        return 2
    finally:
        browser.close()


if __name__ == "__main__":
    sys.exit(main())
