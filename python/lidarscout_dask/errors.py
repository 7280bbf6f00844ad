"""How the driver fails, as the `lidarscout` program does (src/cli/failure_output.hpp): one line on stderr
("lidarscout_dask: MESSAGE"), exit status 1 (2 for an internal error), and with --json one JSON object on
stdout: {"error": {"kind": "input" | "usage" | "internal", "message", "file", "offset", "cause"}}. A
lidarscout.Error of the module is passed on as it said it (plan.py); an unknown option is named with the
closest valid one, found as the program finds it (src/cli/usage_error.cpp)."""
import json
import sys

PROGRAM = "lidarscout_dask"


class Failure(Exception):
    """A failed run: what `report` prints."""

    def __init__(self, message, kind="input", file=None, cause=None):
        super().__init__(message)
        self.message, self.kind, self.file, self.cause = " ".join(message.split()), kind, file, cause


def wants_json(argv):
    return "--json" in argv


def report(failure, json_wanted):
    """The line on stderr and, with `json_wanted`, the object on stdout."""
    prefix = "internal error: " if failure.kind == "internal" else ""
    sys.stderr.write(f"{PROGRAM}: {prefix}{failure.message}\n")
    sys.stderr.flush()
    if json_wanted:
        error = {"kind": failure.kind, "message": failure.message, "file": failure.file, "offset": None,
                 "cause": " ".join((failure.cause or failure.message).split())}
        print(json.dumps({"error": error}, indent=2), flush=True)


def edit_distance(a, b):
    """Insertions, deletions, substitutions and swaps of two neighbours ("--pices" is one from "--pieces")."""
    d = [[i + j if i * j == 0 else 0 for j in range(len(b) + 1)] for i in range(len(a) + 1)]
    for i in range(1, len(a) + 1):
        for j in range(1, len(b) + 1):
            d[i][j] = min(d[i - 1][j] + 1, d[i][j - 1] + 1, d[i - 1][j - 1] + (a[i - 1] != b[j - 1]))
            if i > 1 and j > 1 and a[i - 1] == b[j - 2] and a[i - 2] == b[j - 1]:
                d[i][j] = min(d[i][j], d[i - 2][j - 2] + 1)
    return d[len(a)][len(b)]


def closest_name(word, candidates):
    """The candidate within a third of the word's edits (one for short words), or the only one it starts;
    None when none is close."""
    bare = word.lstrip("-")
    allowed = max(1, len(bare) // 3)
    best, best_distance = None, allowed + 1
    for c in candidates:
        d = edit_distance(bare, c.lstrip("-"))
        if d < best_distance:
            best, best_distance = c, d
    starting = [c for c in candidates if len(bare) >= 3 and c.lstrip("-").startswith(bare)]
    return best if best is not None or len(starting) != 1 else starting[0]
