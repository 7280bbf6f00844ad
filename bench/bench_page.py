"""The web page's own timings in real time (issue 56's targets: first terrain within 1 s of page load, full
resolution near the camera within 5 s): `lidarscout serve PATH` is started, the page opened at CAMERA in
headless chromium (SwiftShader WebGL2) driven over the DevTools protocol on a pipe (tests/serve/chromium_page.py:
real time, no virtual time), and after --seconds the page's
#timings (ms since navigation, performance.now) are read back; medians of --runs, each run a fresh server
and a fresh browser profile (nothing cached).

    /usr/bin/python3 bench/bench_page.py [PATH] [--camera auto] [--runs 3] [--seconds 10] [--cli build/lidarscout]

With --then up|mode|leave [--after S], the page moves on S seconds after navigation (40 steps up, the
classification colour mode, or away to about:blank) and the server's /api/stats (tiles decoded,
heightmaps built, requests given up because their client had gone) is printed before and 6 s after,
with the page's count of the levels it aborted: what a client's moving on or leaving costs the server.
"""

import argparse
import json
import urllib.request
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

REPO = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "tests" / "serve"))
from chromium_page import DevTools  # noqa: E402  (the browser tests' driver)
SURVEY = REPO.parent / "shared" / "data" / "surveys" / "ky-jmo335-eastern-kentucky"
KEYS = ("info", "first_terrain", "overview", "terrain", "first_full_res", "first_detail", "levels_dropped")


def serve(cli, path):
    """`lidarscout serve PATH` on a free loopback port; the process and the page's URL (its first line)."""
    server = subprocess.Popen([cli, "serve", str(path)], stdout=subprocess.PIPE, stderr=subprocess.DEVNULL,
                              text=True)
    url = server.stdout.readline().strip()
    if not url:
        server.kill()
        raise RuntimeError(f"{cli} serve {path} printed no URL")
    return server, url


MOVES = {"up": "for (let i = 0; i < 40; ++i) window.dispatchEvent(new KeyboardEvent('keydown', {key: 'e'}))",
         "mode": "(() => { const c = document.getElementById('colour'); c.value = '3';"
                 " c.dispatchEvent(new Event('change')); })()"}


def server_stats(url):
    with urllib.request.urlopen(url + "api/stats") as res:
        return json.loads(res.read())["datasets"][0]


def move_on(browser, session, url, then, after):
    """The page moves on (or leaves) `after` seconds in: the server's counts before and 6 s after."""
    time.sleep(after)
    before = server_stats(url)
    if then == "leave":
        browser.call("Page.navigate", {"url": "about:blank"}, session)
    else:
        browser.call("Runtime.evaluate", {"expression": MOVES[then]}, session)
    time.sleep(6)
    print(f"{then} after {after:g} s: server before {json.dumps(before)}, 6 s later {json.dumps(server_stats(url))}")


def page_timings(cli, path, camera, seconds, then=None, after=0.0):
    server, url = serve(cli, path)
    try:
        with tempfile.TemporaryDirectory(prefix="bench_page_", ignore_cleanup_errors=True) as profile:
            browser = DevTools(profile)
            try:
                target = browser.call("Target.createTarget", {"url": "about:blank"})["targetId"]
                session = browser.call("Target.attachToTarget", {"targetId": target, "flatten": True})["sessionId"]
                browser.call("Page.navigate", {"url": f"{url}#camera={camera}"}, session)
                if then:
                    move_on(browser, session, url, then, after)
                    if then == "leave":
                        return {}
                else:
                    time.sleep(seconds)
                value = browser.call("Runtime.evaluate", {"expression": "document.getElementById('timings')"
                                                                        ".textContent"}, session)
                return json.loads(value["result"].get("value") or "{}")
            finally:
                browser.close()
    finally:
        server.terminate()
        server.wait()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("path", nargs="?", default=str(SURVEY))
    parser.add_argument("--camera", default="auto", help="the page's #camera (render's syntax)")
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--seconds", type=float, default=10.0, help="how long each page runs before it is read")
    parser.add_argument("--cli", default=str(REPO / "build" / "lidarscout"))
    parser.add_argument("--then", choices=["up", "mode", "leave"], help="the page moves on (or leaves) --after S")
    parser.add_argument("--after", type=float, default=1.5)
    o = parser.parse_args()
    runs = [page_timings(o.cli, o.path, o.camera, o.seconds, o.then, o.after) for _ in range(o.runs)]
    if o.then == "leave":
        return
    for r in runs:
        print(json.dumps(r))
    print(f"{o.path} at #camera={o.camera}, median of {o.runs} runs, ms since navigation (real time):")
    for key in KEYS:
        values = [r[key] for r in runs if key in r]
        missing = len(runs) - len(values)
        shown = f"{statistics.median(values):.0f}" if not missing else f"missing in {missing} runs"
        print(f"  {key:15s} {shown}")
    print(f"  errors          {sum(r.get('errors', 0) for r in runs)}")


if __name__ == "__main__":
    main()
