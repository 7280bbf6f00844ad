#!/usr/bin/python3
"""A replica object server for tests and benchmarks (issue 54): serves the tiles of a virtual replica
(`lidarscout synth replicate --virtual`, its replicate.json manifest) as objects, without copying them.

A tile's bytes are its source tile's bytes with the header's x/y offsets and bounds (and a COPC info VLR's
centre) moved by the tile's shift, as dataset::shift_tile moves them (LAS 1.0-1.4 header layout); the rest
is read from the source file. It answers:

  HTTP   GET/HEAD /tiles/NAME: Range with one range (206, Content-Range), several ranges (206,
         multipart/byteranges as nginx writes it), none or a malformed one (200, the whole tile), an
         unsatisfiable one (416, Content-Range: bytes */SIZE); several that add up to more than the tile
         (200, the whole tile, as nginx does); ETag, Last-Modified, Content-Length,
         Accept-Ranges. /catalog.vpc and /search pages answer ranges the same way.
  S3     GET/HEAD /BUCKET/KEY (keys are the tile names), path-style, any signature or none accepted: one
         range per GET. Amazon S3 does not support several ranges in one GET (its GetObject
         documentation); it ignores such a Range header and sends the whole object with 200, and so does
         this server. An unsatisfiable single range is 416 InvalidRange. GET /BUCKET?list-type=2 is
         ListObjectsV2 (prefix, continuation-token, start-after, max-keys up to 1000 a page, keys in byte
         order, the XML S3 writes; a delimiter is echoed but groups nothing: the keys hold no '/').
  VPC    GET/HEAD /catalog.vpc: one QGIS virtual point cloud (STAC ItemCollection) of every tile, laid
         out as `lidarscout catalog` writes it (an item a line); each item is the item `PROGRAM catalog` writes
         for the tile's source, with its id, asset href ("./tiles/NAME"), proj:bbox (and proj:geometry,
         where an item has one) moved. The WGS 84 bbox and geometry are the source's moved by the shift in degrees at the
         source's latitude (an approximation: no PROJ here; readers place tiles by proj:bbox).
         Generated on the fly (each item's length is known, so any range is made from the items it
         covers): never held whole in memory.
  STAC   GET /search?limit=N&token=T: a STAC API ItemCollection page (limit 10 by default, at most 10000),
         its items as in the VPC with absolute hrefs, a "next" link (token-based) while items remain,
         numberMatched and numberReturned. GET / is a landing page linking it. With --hold-last-page, the
         last page of a search of several pages is answered only once GET /_release was asked (never
         delayed nor counted): a test sees what a reader does with the first pages before the last arrives.
  Overview  GET/HEAD /catalog.overview.laz: with --overview FILE, that file (an overview sidecar written by
         `PROGRAM catalog MANIFEST -o OUT.vpc --overview`), ranges answered as a tile's; /catalog.vpc then
         names it in a top-level link of rel "lidarscout:overview" (item ids are the tiles' names' stems in
         both, which is how the sidecar's tiles are found).
  Stats  GET /_stats: requests and body bytes per kind (tile, tile_head, s3_object, s3_head, s3_list,
         catalog, search, landing, error), tiles touched, connections, ranges, multi-range requests, the
         requests held (--hold-last-page) now, the requests in flight (read, not yet answered) at most and
         on average from the first request to the last answer, as JSON; /_stats?reset=1 answers, then starts counting
         again. Never delayed nor counted.

Options: --rtt-ms MS delays each response by MS (a connection's first by 2 x MS: its TCP handshake);
--bandwidth B sends each connection's bodies at B bytes/s (0: unlimited); --overview FILE serves an
overview sidecar (above); --hold-last-page holds a search's last page until /_release (above).

One asyncio event loop (no thread per connection; http.server's thread-per-connection and header parsing
cost far more per request on the 2 cores the benchmarks share). Started by tests/replica_server.hpp, which
waits for --port-file (written once the server listens). Python 3 standard library only.
"""

import argparse
import array
import asyncio
import base64
import copy
import email.utils
import hashlib
import json
import math
import os
import re
import struct
import subprocess
import sys
import tempfile
import time
import urllib.parse
from xml.sax.saxutils import escape as xml_escape

# LAS header fields (LAS 1.0-1.4 share this layout)
HEADER_MIN_SIZE = 227
OFFSET_XY = 155  # x, y offsets (f64)
BOUNDS_XY = 179  # max x, min x, max y, min y (f64)
VLR_HEADER = 54
COPC_USER = b"copc"
COPC_INFO_RECORD = 1

MAX_SEARCH_LIMIT = 10000
S3_PAGE = 1000
BOUNDARY = "00000000000000000001"  # nginx's first boundary
PIECE = 256 * 1024  # bytes read and sent at a time


class Refusal(Exception):
    """A source or manifest the server cannot serve: one line, exit status 2."""


def fail(message):
    raise Refusal(message)


# --- tiles ------------------------------------------------------------------------------------------


class Source:
    """A source tile: its file (kept open), size, mtime and the header fields a shift moves."""

    def __init__(self, path, copc_expected):
        self.path = path
        try:
            self.fd = os.open(path, os.O_RDONLY)
            st = os.fstat(self.fd)
        except OSError as e:
            fail(f"{path}: cannot be read ({e.strerror})")
        self.size, self.mtime = st.st_size, st.st_mtime
        head = os.pread(self.fd, 375, 0)
        if len(head) < HEADER_MIN_SIZE or head[:4] != b"LASF":
            fail(f"{path}: not a LAS/LAZ file (no LASF signature or a header under {HEADER_MIN_SIZE} bytes)")
        major, minor = head[24], head[25]
        header_size, = struct.unpack_from("<H", head, 94)
        if major != 1 or minor > 4 or header_size < HEADER_MIN_SIZE or header_size > self.size:
            fail(f"{path}: LAS {major}.{minor} with a {header_size}-byte header; only LAS 1.0-1.4 headers are shifted")
        self.offset = struct.unpack_from("<2d", head, OFFSET_XY)
        self.bounds = struct.unpack_from("<4d", head, BOUNDS_XY)  # max x, min x, max y, min y
        self.copc_centre_at, self.copc_centre = self._find_copc_centre(head, header_size)
        # Where the bytes a shift writes end: a read past it (a chunk point, a chunk table) is the source's as it is.
        self.patched_end = max(OFFSET_XY + 16, BOUNDS_XY + 32,
                               self.copc_centre_at + 16 if self.copc_centre_at is not None else 0)
        if copc_expected and self.copc_centre_at is None:
            fail(f"{path}: the manifest says COPC but its header holds no COPC info VLR")

    def _find_copc_centre(self, head, header_size):
        """The file offset and value of the COPC info VLR's x/y centre; (None, None) when it has none."""
        count, = struct.unpack_from("<I", head, 100)
        at = header_size
        for _ in range(min(count, 10000)):
            vlr = os.pread(self.fd, VLR_HEADER + 16, at)
            if len(vlr) < VLR_HEADER:
                return None, None
            user = vlr[2:18].rstrip(b"\0")
            record, length = struct.unpack_from("<HH", vlr, 18)
            if user == COPC_USER and record == COPC_INFO_RECORD:
                if length < 16 or len(vlr) < VLR_HEADER + 16:
                    fail(f"{self.path}: a COPC info VLR of {length} bytes")
                return at + VLR_HEADER, struct.unpack_from("<2d", vlr, VLR_HEADER)
            at += VLR_HEADER + length
        return None, None

    def patches(self, dx, dy):
        """The (file offset, bytes) a shift by dx, dy writes over the source's bytes."""
        ox, oy = self.offset
        maxx, minx, maxy, miny = self.bounds
        out = [(OFFSET_XY, struct.pack("<2d", ox + dx, oy + dy)),
               (BOUNDS_XY, struct.pack("<4d", maxx + dx, minx + dx, maxy + dy, miny + dy))]
        if self.copc_centre_at is not None:
            cx, cy = self.copc_centre
            out.append((self.copc_centre_at, struct.pack("<2d", cx + dx, cy + dy)))
        return out


class Replica:
    """The manifest's tiles: names, sources and shifts, held compactly (152,100 tiles in a few MB)."""

    def __init__(self, manifest_path):
        self.path = os.path.abspath(manifest_path)
        try:
            with open(self.path, "rb") as f:
                m = json.load(f)
        except (OSError, ValueError) as e:
            fail(f"{manifest_path}: not a readable replicate.json manifest ({e})")
        if not isinstance(m, dict) or m.get("virtual") is not True:
            fail(f"{manifest_path}: not a virtual replica manifest (no \"virtual\": true)")
        try:
            self.sources = [Source(s["path"], bool(s.get("copc", False))) for s in m["sources"]]
            self.to_metres = [float(s.get("to_metres", 1.0)) for s in m["sources"]]
            self.names, self.source = [], array.array("I")
            self.dx, self.dy = array.array("d"), array.array("d")
            for t in m["tiles"]:
                s = int(t["source"])
                if not 0 <= s < len(self.sources):
                    fail(f"{manifest_path}: tile {t['file']} names source {s} of {len(self.sources)}")
                self.names.append(str(t["file"]))
                self.source.append(s)
                self.dx.append(float(t["shift"][0]))
                self.dy.append(float(t["shift"][1]))
        except (KeyError, TypeError, IndexError, ValueError) as e:
            fail(f"{manifest_path}: a malformed manifest ({type(e).__name__}: {e})")
        del m
        self.index = {name: i for i, name in enumerate(self.names)}
        if len(self.index) != len(self.names):
            fail(f"{manifest_path}: tile names repeat")
        self.keys = sorted(self.names, key=lambda k: k.encode())  # S3 lists keys in UTF-8 byte order
        self.mtime = os.stat(self.path).st_mtime

    def size(self, i):
        return self.sources[self.source[i]].size

    def mtime_of(self, i):
        return self.sources[self.source[i]].mtime

    def etag(self, i):
        s = self.sources[self.source[i]]
        text = f"{s.path}|{s.size}|{s.mtime}|{self.dx[i]!r}|{self.dy[i]!r}"
        return '"' + hashlib.md5(text.encode()).hexdigest() + '"'

    def read(self, i, offset, length):
        """Bytes [offset, offset + length) of tile i: the source's, with the shifted fields over them."""
        s = self.sources[self.source[i]]
        data = os.pread(s.fd, length, offset)
        if offset >= s.patched_end:
            return data
        end = offset + len(data)
        patched = None
        for at, value in s.patches(self.dx[i], self.dy[i]):
            lo, hi = max(at, offset), min(at + len(value), end)
            if lo < hi:
                if patched is None:
                    patched = bytearray(data)
                patched[lo - offset:hi - offset] = value[lo - at:hi - at]
        return bytes(patched) if patched is not None else data


# --- catalog items ------------------------------------------------------------------------------------

PLACEHOLDER = re.compile(r'"@@(\w+)@@"')
CATALOG_HEAD = '{"type":"FeatureCollection","features":[\n'
ITEM_SEPARATOR = ",\n"


def source_items(program, replica):
    """The item `PROGRAM catalog` writes for each source tile, by source index."""
    paths = [s.path for s in replica.sources]
    with tempfile.TemporaryDirectory(prefix="replica_server_") as d:
        out = os.path.join(d, "sources.vpc")
        try:
            run = subprocess.run([program, "catalog", *paths, "-o", out], capture_output=True, text=True)
        except OSError as e:
            fail(f"{program}: cannot run it for the sources' catalog items ({e.strerror}); see --program")
        if run.returncode != 0:
            fail(f"{program} catalog of the sources failed: {run.stderr.strip()[-500:]}")
        with open(out) as f:
            features = json.load(f)["features"]
        by_path = {}
        for item in features:
            href = item["assets"]["data"]["href"]
            by_path[os.path.realpath(os.path.join(d, href))] = item
    items = []
    for p in paths:
        item = by_path.get(os.path.realpath(p))
        if item is None:
            fail(f"{program} catalog wrote no item for {p}")
        items.append(item)
    return items


def mark_ring(geometry, x_names, y_names, box):
    """Replaces a box polygon's coordinates by placeholders: x by x_names (min, max), y by y_names."""
    for ring in geometry["coordinates"]:
        for point in ring:
            point[0] = f"@@{x_names[0] if point[0] == box[0] else x_names[1]}@@"
            point[1] = f"@@{y_names[0] if point[1] == box[1] else y_names[1]}@@"


class ItemTemplate:
    """A source's item as text with holes for what a shift changes: literal pieces and field names."""

    def __init__(self, item, to_metres):
        t = copy.deepcopy(item)
        props = t["properties"]
        pb, bb = props["proj:bbox"], t["bbox"]
        self.proj = (pb[0], pb[1], pb[3], pb[4])      # min x, min y, max x, max y (the source's units)
        self.lonlat = (bb[0], bb[1], bb[3], bb[4])    # west, south, east, north
        self.geographic = self.lonlat != self.proj    # (a tile without a CRS keeps its own box)
        self.to_metres = to_metres
        t["id"], t["assets"]["data"]["href"] = "@@ID@@", "@@HREF@@"
        pb[0], pb[1], pb[3], pb[4] = "@@X0@@", "@@Y0@@", "@@X1@@", "@@Y1@@"
        bb[0], bb[1], bb[3], bb[4] = "@@W@@", "@@S@@", "@@E@@", "@@N@@"
        if "proj:geometry" in props:  # (written by earlier versions)
            mark_ring(props["proj:geometry"], ("X0", "X1"), ("Y0", "Y1"), (self.proj[0], self.proj[1]))
        mark_ring(t["geometry"], ("W", "E"), ("S", "N"), (self.lonlat[0], self.lonlat[1]))
        # one line, as `lidarscout catalog` writes an item
        text = json.dumps(t, separators=(",", ":"))  # (ASCII: offsets are bytes)
        pieces = PLACEHOLDER.split(text)
        self.literals, self.fields = pieces[0::2], pieces[1::2]

    def values(self, name, dx, dy):
        """The fields of the tile `name` shifted by dx, dy (the source's units), as JSON text."""
        x0, y0, x1, y1 = self.proj
        v = {"X0": x0 + dx, "Y0": y0 + dy, "X1": x1 + dx, "Y1": y1 + dy}
        w, s, e, n = self.lonlat
        if self.geographic:  # metres to degrees at the source's latitude (an approximation, see the top)
            lat = math.radians((s + n) / 2)
            dlon = dx * self.to_metres / (111320.0 * max(1e-6, math.cos(lat)))
            dlat = dy * self.to_metres / 110574.0
        else:
            dlon, dlat = dx, dy
        v.update({"W": w + dlon, "S": s + dlat, "E": e + dlon, "N": n + dlat})
        out = {k: repr(x) for k, x in v.items()}
        out["ID"] = json.dumps(item_id(name))
        return out

    def text(self, values, href):
        values["HREF"] = json.dumps(href)
        parts = [self.literals[0]]
        for field, literal in zip(self.fields, self.literals[1:]):
            parts.append(values[field])
            parts.append(literal)
        return "".join(parts)


def item_id(name):
    """The item id `lidarscout catalog` gives a tile: its file name without .copc.laz, .laz or .las."""
    for ext in (".copc.laz", ".laz", ".las"):
        if len(name) > len(ext) and name.endswith(ext):
            return name[:-len(ext)]
    return name


class Items:
    """Every tile's item text, made on demand; each one's length (with an href prefix of "") known."""

    def __init__(self, replica, templates):
        self.replica, self.templates = replica, templates
        self.quoted = [urllib.parse.quote(n) for n in replica.names]
        self.cum = array.array("Q", [0])  # cum[i]: the length of items [0, i) with an empty href prefix
        total = 0
        for i in range(len(replica.names)):
            total += len(self.text(i, ""))
            self.cum.append(total)

    def text(self, i, prefix):
        r = self.replica
        t = self.templates[r.source[i]]
        return t.text(t.values(r.names[i], r.dx[i], r.dy[i]), prefix + self.quoted[i])


class ItemDocument:
    """An ItemCollection of items [first, first + count): head, the items (each href prefixed), tail.
    Its size is known without making it; read() makes only the items a range covers."""

    def __init__(self, items, first, count, prefix, tail, head=CATALOG_HEAD):
        self.items, self.first, self.count = items, first, count
        self.prefix, self.head, self.tail = prefix, head, tail
        self.step = len(prefix) + len(ITEM_SEPARATOR)  # what each item adds beyond its core length
        self.rendered = None  # the whole document's bytes, once render() made them
        cum = items.cum
        self.size = (len(self.head) + cum[first + count] - cum[first] + count * len(prefix) +
                     max(0, count - 1) * len(ITEM_SEPARATOR) + len(self.tail))

    def _start(self, k):
        """The offset of item k (0 <= k <= count) in the document."""
        cum = self.items.cum
        return len(self.head) + cum[self.first + k] - cum[self.first] + k * self.step

    def _item_at(self, offset):
        """The last item starting at or before `offset` (0 when none)."""
        lo, hi = 0, self.count - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if self._start(mid) <= offset:
                lo = mid
            else:
                hi = mid - 1
        return max(0, lo)

    def render(self):
        """Makes the whole document once, so that reads are served as a static file's (a server that made
        each item for each request would bound a client's catalog read by its own speed)."""
        self.rendered = b"".join(self.read(0, self.size))
        return self

    def read(self, offset, length):
        """Yields the bytes [offset, offset + length), in pieces."""
        if self.rendered is not None:
            view = memoryview(self.rendered)
            for at in range(offset, offset + length, 1 << 20):
                yield view[at:min(offset + length, at + (1 << 20))]
            return
        end = offset + length
        if offset < len(self.head):
            yield self.head[offset:min(end, len(self.head))].encode()
        k = self._item_at(offset) if self.count else 0
        while k < self.count and self._start(k) < end:
            at = self._start(k)
            text = self.items.text(self.first + k, self.prefix)
            if k + 1 < self.count:
                text += ITEM_SEPARATOR
            lo, hi = max(offset, at), min(end, at + len(text))
            if lo < hi:
                yield text[lo - at:hi - at].encode()
            k += 1
        tail_at = self.size - len(self.tail)
        lo, hi = max(offset, tail_at), min(end, self.size)
        if lo < hi:
            yield self.tail[lo - tail_at:hi - tail_at].encode()


def json_tail(fields):
    """The end of an ItemCollection whose "features" precede `fields`, laid out as `lidarscout catalog` does."""
    if not fields:
        return "\n]}\n"
    return "\n]," + json.dumps(fields, separators=(",", ":"))[1:] + "\n"


# --- HTTP ---------------------------------------------------------------------------------------------


class Stats:
    KINDS = ("tile", "tile_head", "s3_object", "s3_head", "s3_list", "catalog", "search", "landing", "overview",
             "error")

    def __init__(self):
        self.reset()

    def reset(self):
        self.kinds = {k: {"requests": 0, "bytes": 0} for k in self.KINDS}
        self.touched = set()
        self.connections = self.ranges = self.multi_range = 0
        self.held = 0  # requests waiting for /_release now (not reset: they are still waiting)
        # requests read and not yet answered: now, at most, and their sum over time (the mean in flight, from
        # the first request to the last answer)
        self.in_flight = getattr(self, "in_flight", 0)
        self.in_flight_peak, self.in_flight_seconds, self.flight_first, self.flight_last = self.in_flight, 0.0, None, None

    def flight(self, delta):
        now = time.monotonic()
        if self.flight_last is not None:
            self.in_flight_seconds += self.in_flight * (now - self.flight_last)
        self.flight_first = now if self.flight_first is None else self.flight_first
        self.flight_last = now
        self.in_flight += delta
        self.in_flight_peak = max(self.in_flight_peak, self.in_flight)

    def as_json(self, tiles):
        return {"requests": sum(k["requests"] for k in self.kinds.values()),
                "bytes": sum(k["bytes"] for k in self.kinds.values()),
                "kinds": self.kinds, "tiles": tiles, "tiles_touched": len(self.touched),
                "connections": self.connections, "ranges": self.ranges, "multi_range_requests": self.multi_range,
                "held": self.held, "in_flight_peak": self.in_flight_peak, "in_flight_mean": self.in_flight_mean()}

    def in_flight_mean(self):
        span = (self.flight_last or 0) - (self.flight_first or 0)
        return round(self.in_flight_seconds / span, 1) if span > 0 else 0.0


class Response:
    """A status, headers and a body: bytes, or a size and a function yielding its pieces."""

    def __init__(self, status, headers=None, body=b"", size=None, pieces=None, kind="error"):
        self.status, self.headers, self.kind = status, dict(headers or {}), kind
        self.body, self.pieces = body, pieces
        self.size = len(body) if size is None else size
        self.held = False  # answered only after /_release (--hold-last-page)


REASONS = {200: "OK", 206: "Partial Content", 400: "Bad Request", 404: "Not Found", 405: "Method Not Allowed",
           416: "Range Not Satisfiable", 500: "Internal Server Error"}


def parse_ranges(value, size):
    """RFC 9110 byte ranges: None when the header is malformed (ignored), else the satisfiable ranges
    as (first, last) pairs, in the order asked ([] when none is: 416)."""
    value = value.strip()
    if value[:6].lower() != "bytes=":
        return None
    out, specs = [], [s.strip() for s in value[6:].split(",")]
    if not any(specs):
        return None
    for spec in specs:
        if not spec:
            continue
        first, dash, last = (p.strip() for p in spec.partition("-"))
        if not dash or (first and not first.isdigit()) or (last and not last.isdigit()) or not (first or last):
            return None
        if not first:  # the last N bytes
            n = int(last)
            if n > 0 and size > 0:
                out.append((max(0, size - n), size - 1))
            continue
        a, b = int(first), (int(last) if last else None)
        if b is not None and b < a:
            return None
        if a < size:
            out.append((a, size - 1 if b is None else min(b, size - 1)))
    return out


def range_count(value):
    return len([s for s in value.split(",") if s.strip()])


class Resource:
    """What a range request reads: a size, validators and read(offset, length) yielding pieces."""

    def __init__(self, size, etag, mtime, read, content_type):
        self.size, self.etag, self.mtime, self.read, self.content_type = size, etag, mtime, read, content_type

    def headers(self):
        return {"ETag": self.etag, "Last-Modified": email.utils.formatdate(self.mtime, usegmt=True),
                "Accept-Ranges": "bytes", "Content-Type": self.content_type}


def pieces_of(resource, ranges):
    """A multipart/byteranges body of `ranges` (nginx's layout) as (size, piece function)."""
    parts = []
    for a, b in ranges:
        parts.append((f"\r\n--{BOUNDARY}\r\nContent-Type: {resource.content_type}\r\n"
                      f"Content-Range: bytes {a}-{b}/{resource.size}\r\n\r\n").encode())
        parts.append((a, b - a + 1))
    closing = f"\r\n--{BOUNDARY}--\r\n".encode()
    size = sum(len(p) if isinstance(p, bytes) else p[1] for p in parts) + len(closing)

    def pieces():
        for p in parts:
            if isinstance(p, bytes):
                yield p
            else:
                yield from resource.read(*p)
        yield closing
    return size, pieces


def ranged(resource, range_header, head, kind, stats, multi=True):
    """The answer to GET/HEAD of `resource`: 200, 206 (one range or multipart) or 416. With multi False
    (S3), a Range header of several ranges is ignored: 200 and the whole object."""
    headers = resource.headers()
    ranges = None
    if range_header and not head and (multi or range_count(range_header) == 1):
        ranges = parse_ranges(range_header, resource.size)
    if ranges and sum(b - a + 1 for a, b in ranges) > resource.size:
        ranges = None  # (nginx's rule: ranges that add up to more than the file are answered with all of it)
    if ranges is None:
        return Response(200, headers, size=resource.size, kind=kind,
                        pieces=None if head else (lambda: resource.read(0, resource.size)))
    if not ranges:
        headers = {"Content-Range": f"bytes */{resource.size}"}
        if not multi:
            return s3_error(416, "InvalidRange", "The requested range is not satisfiable", headers)
        return Response(416, headers, b"range not satisfiable\n", kind="error")
    stats.ranges += len(ranges)
    if len(ranges) == 1:
        a, b = ranges[0]
        headers["Content-Range"] = f"bytes {a}-{b}/{resource.size}"
        return Response(206, headers, size=b - a + 1, kind=kind, pieces=lambda: resource.read(a, b - a + 1))
    stats.multi_range += 1
    size, pieces = pieces_of(resource, ranges)
    headers["Content-Type"] = f"multipart/byteranges; boundary={BOUNDARY}"
    return Response(206, headers, size=size, kind=kind, pieces=pieces)


def s3_error(status, code, message, headers=None):
    body = (f'<?xml version="1.0" encoding="UTF-8"?>\n<Error><Code>{code}</Code><Message>{xml_escape(message)}'
            f"</Message><RequestId>replica</RequestId></Error>").encode()
    h = {"Content-Type": "application/xml"}
    h.update(headers or {})
    return Response(status, h, body, kind="error")


def json_response(value, kind):
    return Response(200, {"Content-Type": "application/json"}, (json.dumps(value, indent=1) + "\n").encode(),
                    kind=kind)


def overview_resource(path):
    """An overview sidecar file as a Resource (read from the file as asked)."""
    try:
        fd = os.open(path, os.O_RDONLY)
        st = os.fstat(fd)
    except OSError as e:
        fail(f"{path}: cannot be read ({e.strerror})")
    etag = '"' + hashlib.md5(f"{path}|{st.st_size}|{st.st_mtime}".encode()).hexdigest() + '"'

    def read(offset, length):
        end = offset + length
        while offset < end:
            data = os.pread(fd, min(PIECE, end - offset), offset)
            if not data:
                return
            yield data
            offset += len(data)
    return Resource(st.st_size, etag, st.st_mtime, read, "application/vnd.laszip")


class Server:
    def __init__(self, replica, items, options):
        self.replica, self.items, self.options = replica, items, options
        self.stats = Stats()
        self.rtt = options.rtt_ms / 1000.0
        self.overview = None
        self.release = None  # an asyncio.Event, set by /_release (made in the server's loop)
        head = CATALOG_HEAD
        if options.overview:  # (its link before the items, as `lidarscout catalog` writes it)
            self.overview = overview_resource(options.overview)
            links = [{"rel": "lidarscout:overview", "href": "./catalog.overview.laz", "type": "application/vnd.laszip"}]
            head = '{"type":"FeatureCollection","links":' + json.dumps(links, separators=(",", ":")) + ',"features":[\n'
        self.catalog = ItemDocument(items, 0, len(replica.names), "./tiles/", json_tail({}), head).render()

    # -- routes

    def route(self, method, target, headers):
        """The response to a request, and whether it is delayed by the round trip."""
        url = urllib.parse.urlsplit(target)
        path = urllib.parse.unquote(url.path)
        query = urllib.parse.parse_qs(url.query, keep_blank_values=True)
        if path == "/_stats":
            answer = json_response(self.stats.as_json(len(self.replica.names)), "stats")
            if query.get("reset", ["0"])[0] not in ("", "0"):
                self.stats.reset()
            return answer, False
        if path == "/_release":
            self.released().set()
            return json_response({"released": True}, "release"), False
        if method not in ("GET", "HEAD"):
            return Response(405, {"Allow": "GET, HEAD"}, b"method not allowed\n"), True
        head, rng = method == "HEAD", headers.get("range", "")
        if path.startswith("/tiles/"):
            return self.tile(path[len("/tiles/"):], rng, head, "tile_head" if head else "tile"), True
        if path == "/catalog.overview.laz" and self.overview:
            return ranged(self.overview, rng, head, "overview", self.stats), True
        if path == "/catalog.vpc":
            return ranged(self.catalog_resource(self.catalog), rng, head, "catalog", self.stats), True
        if path == "/search":
            return self.search(query, headers, rng, head), True
        if path == "/":
            return self.landing(headers), True
        bucket, _, key = path[1:].partition("/")
        if bucket != self.options.bucket:
            return s3_error(404, "NoSuchBucket", f"The specified bucket does not exist: {bucket}"), True
        if not key:
            if head:
                return Response(200, {"Content-Type": "application/xml"}, kind="s3_head"), True
            return self.list_objects(query), True
        return self.tile(key, rng, head, "s3_head" if head else "s3_object", s3=True), True

    def tile(self, name, rng, head, kind, s3=False):
        r = self.replica
        i = r.index.get(name)
        if i is None:
            if s3:
                return s3_error(404, "NoSuchKey", "The specified key does not exist.")
            return Response(404, {"Content-Type": "text/plain"}, b"no such tile\n")
        self.stats.touched.add(i)
        resource = Resource(r.size(i), r.etag(i), r.mtime_of(i), lambda o, n: self.tile_pieces(i, o, n),
                            "application/octet-stream")
        return ranged(resource, rng, head, kind, self.stats, multi=not s3)

    def tile_pieces(self, i, offset, length):
        end = offset + length
        while offset < end:
            n = min(PIECE, end - offset)
            data = self.replica.read(i, offset, n)
            if not data:
                return
            yield data
            offset += len(data)

    def catalog_resource(self, doc, tag=""):
        text = f"{self.replica.path}|{self.replica.mtime}|{doc.first}|{doc.count}|{doc.prefix}|{tag}"
        etag = '"' + hashlib.md5(text.encode()).hexdigest() + '"'
        return Resource(doc.size, etag, self.replica.mtime, doc.read, "application/geo+json")

    def base_url(self, headers):
        """The server's URL as the client named it (a Host that JSON would escape is not taken)."""
        host = headers.get("host", "")
        if not re.fullmatch(r"[A-Za-z0-9.:\[\]-]{1,255}", host):
            host = f"127.0.0.1:{self.options.port}"
        return "http://" + host

    def landing(self, headers):
        base = self.base_url(headers)
        return json_response({
            "type": "Catalog", "id": "replica", "stac_version": "1.0.0",
            "description": "a virtual replica's tiles (tests/replica_server.py)",
            "conformsTo": ["https://api.stacspec.org/v1.0.0/core", "https://api.stacspec.org/v1.0.0/item-search"],
            "links": [{"rel": "self", "href": base + "/", "type": "application/json"},
                      {"rel": "root", "href": base + "/", "type": "application/json"},
                      {"rel": "search", "href": base + "/search", "type": "application/geo+json", "method": "GET"}]},
            "landing")

    def search(self, query, headers, rng, head):
        total = len(self.replica.names)
        try:
            limit = int(query.get("limit", ["10"])[0])
            token = query.get("token", ["0"])[0] or "0"
            first = int(token[5:]) if token.startswith("next:") else int(token)
        except ValueError:
            return Response(400, {"Content-Type": "text/plain"}, b"limit and token must be numbers\n")
        if limit < 1 or not 0 <= first <= total:
            return Response(400, {"Content-Type": "text/plain"}, b"limit or token out of range\n")
        limit = min(limit, MAX_SEARCH_LIMIT)
        count = min(limit, total - first)
        base = self.base_url(headers)
        page = f"{base}/search?limit={limit}"
        links = [{"rel": "self", "href": page + (f"&token=next:{first}" if first else ""),
                  "type": "application/geo+json"},
                 {"rel": "root", "href": base + "/", "type": "application/json"}]
        if first + count < total:
            links.append({"rel": "next", "href": f"{page}&token=next:{first + count}", "type": "application/geo+json",
                          "method": "GET"})
        tail = json_tail({"links": links, "numberMatched": total, "numberReturned": count})
        doc = ItemDocument(self.items, first, count, base + "/tiles/", tail)
        response = ranged(self.catalog_resource(doc, tail), rng, head, "search", self.stats)
        response.held = self.options.hold_last_page and first > 0 and first + count >= total
        return response

    def released(self):
        if self.release is None:
            self.release = asyncio.Event()
        return self.release

    def list_objects(self, query):
        keys = self.replica.keys
        arg = lambda name, default="": query.get(name, [default])[0]
        prefix, token, after = arg("prefix"), arg("continuation-token"), arg("start-after")
        try:
            max_keys = max(0, min(S3_PAGE, int(arg("max-keys", str(S3_PAGE)))))
        except ValueError:
            return s3_error(400, "InvalidArgument", "max-keys is not a number")
        start = bisect_left(keys, prefix)
        if token:
            try:
                last = base64.urlsafe_b64decode(token.encode()).decode()
            except ValueError:
                return s3_error(400, "InvalidArgument", "The continuation token provided is incorrect")
            start = max(start, bisect_right(keys, last))
        elif after:
            start = max(start, bisect_right(keys, after))
        page = []
        i = start
        while i < len(keys) and len(page) < max_keys and keys[i].startswith(prefix):
            page.append(keys[i])
            i += 1
        truncated = i < len(keys) and keys[i].startswith(prefix) and max_keys > 0
        out = ['<?xml version="1.0" encoding="UTF-8"?>\n'
               '<ListBucketResult xmlns="http://s3.amazonaws.com/doc/2006-03-01/">',
               f"<Name>{xml_escape(self.options.bucket)}</Name><Prefix>{xml_escape(prefix)}</Prefix>",
               f"<KeyCount>{len(page)}</KeyCount><MaxKeys>{max_keys}</MaxKeys>"]
        if arg("delimiter"):
            out.append(f"<Delimiter>{xml_escape(arg('delimiter'))}</Delimiter>")
        out.append(f"<IsTruncated>{'true' if truncated else 'false'}</IsTruncated>")
        if token:
            out.append(f"<ContinuationToken>{xml_escape(token)}</ContinuationToken>")
        if after:
            out.append(f"<StartAfter>{xml_escape(after)}</StartAfter>")
        if truncated:
            next_token = base64.urlsafe_b64encode(page[-1].encode()).decode()
            out.append(f"<NextContinuationToken>{next_token}</NextContinuationToken>")
        r = self.replica
        for key in page:
            i = r.index[key]
            modified = time.strftime("%Y-%m-%dT%H:%M:%S.000Z", time.gmtime(r.mtime_of(i)))
            out.append(f"<Contents><Key>{xml_escape(key)}</Key><LastModified>{modified}</LastModified>"
                       f"<ETag>{xml_escape(r.etag(i), {chr(34): '&quot;'})}</ETag><Size>{r.size(i)}</Size>"
                       "<StorageClass>STANDARD</StorageClass></Contents>")
        out.append("</ListBucketResult>")
        return Response(200, {"Content-Type": "application/xml"}, "".join(out).encode(), kind="s3_list")

    # -- connections

    async def connection(self, reader, writer):
        self.stats.connections += 1
        first = True
        try:
            while True:
                try:
                    head = await reader.readuntil(b"\r\n\r\n")
                except (asyncio.IncompleteReadError, asyncio.LimitOverrunError, ConnectionError):
                    return
                request = parse_head(head)
                if request is None:
                    await self.send(writer, Response(400, {"Connection": "close"}, b"bad request\n"), False)
                    return
                method, target, version, headers = request
                length = headers.get("content-length", "0")
                if length.isdigit() and int(length) > 0:
                    await reader.readexactly(int(length))  # (a body is read and dropped)
                try:
                    response, delayed = self.route(method, target, headers)
                except Exception as e:  # a bug here is an answer, not a dead connection
                    response, delayed = Response(500, {"Content-Type": "text/plain"}, f"{e!r}\n".encode()), False
                if delayed:  # (the stats' own requests not counted in flight)
                    self.stats.flight(1)
                if delayed and self.rtt > 0:
                    await asyncio.sleep(self.rtt * (2 if first else 1))
                first = False
                if response.held and not self.released().is_set():
                    self.stats.held += 1
                    await self.released().wait()
                    self.stats.held -= 1
                close = headers.get("connection", "").lower() == "close" or version == "HTTP/1.0"
                if close:
                    response.headers["Connection"] = "close"
                try:
                    await self.send(writer, response, method == "HEAD")
                finally:
                    if delayed:
                        self.stats.flight(-1)
                if close:
                    return
        except (ConnectionError, asyncio.IncompleteReadError):
            return
        finally:
            writer.close()

    async def send(self, writer, response, head):
        h = [f"HTTP/1.1 {response.status} {REASONS.get(response.status, 'Status')}",
             f"Date: {email.utils.formatdate(usegmt=True)}", "Server: replica_server",
             f"Content-Length: {response.size}", "x-amz-request-id: replica"]
        h += [f"{k}: {v}" for k, v in response.headers.items()]
        header = ("\r\n".join(h) + "\r\n\r\n").encode()
        counted = self.stats.kinds.get(response.kind)
        if counted is not None:
            counted["requests"] += 1
        if head:
            writer.write(header)
            await writer.drain()
            return
        pieces = response.pieces() if response.pieces else [response.body]
        bandwidth, start, sent = self.options.bandwidth, time.monotonic(), 0
        if not bandwidth:  # (a reply of at most PIECE bytes in one write: a multipart one's parts had been 16 sends)
            body = b"".join(pieces) if response.size <= PIECE else None
            if body is not None:
                writer.write(header + body)
                await writer.drain()
                if counted is not None:
                    counted["bytes"] += len(body)
                return
        writer.write(header)
        step = max(1024, min(PIECE, bandwidth // 20)) if bandwidth else PIECE  # (~20 writes a second)
        for piece in pieces:
            for at in range(0, len(piece), step):
                chunk = piece[at:at + step]
                if bandwidth:
                    ahead = start + sent / bandwidth - time.monotonic()
                    if ahead > 0:
                        await asyncio.sleep(ahead)
                writer.write(chunk)
                await writer.drain()
                sent += len(chunk)
                if counted is not None:
                    counted["bytes"] += len(chunk)
        await writer.drain()


def bisect_left(keys, key):
    lo, hi, k = 0, len(keys), key.encode()
    while lo < hi:
        mid = (lo + hi) // 2
        if keys[mid].encode() < k:
            lo = mid + 1
        else:
            hi = mid
    return lo


def bisect_right(keys, key):
    lo, hi, k = 0, len(keys), key.encode()
    while lo < hi:
        mid = (lo + hi) // 2
        if k < keys[mid].encode():
            hi = mid
        else:
            lo = mid + 1
    return lo


def parse_head(head):
    """(method, target, version, headers with lower-case names) of a request head; None when malformed."""
    try:
        lines = head.decode("latin-1").split("\r\n")
        method, target, version = lines[0].split(" ")
    except ValueError:
        return None
    if not version.startswith("HTTP/1.") or not target.startswith("/"):
        return None
    headers = {}
    for line in lines[1:]:
        if not line:
            continue
        name, colon, value = line.partition(":")
        if not colon:
            return None
        headers[name.strip().lower()] = value.strip()
    return method, target, version, headers


def parse_size(text):
    """A byte count with an optional K, M or G (powers of 1024)."""
    m = re.fullmatch(r"\s*(\d+)\s*([kKmMgG]?)\s*", text)
    if not m:
        raise argparse.ArgumentTypeError(f"{text!r}: expected bytes per second, e.g. 0, 500000, 8M")
    return int(m.group(1)) << {"": 0, "k": 10, "m": 20, "g": 30}[m.group(2).lower()]


async def serve(server, options):
    listener = await asyncio.start_server(server.connection, options.host, options.port, backlog=4096,
                                          limit=64 * 1024)
    port = listener.sockets[0].getsockname()[1]
    options.port = port
    if options.port_file:
        tmp = options.port_file + ".tmp"
        with open(tmp, "w") as f:
            f.write(f"{port}\n")
        os.replace(tmp, options.port_file)
    if not options.quiet:
        print(f"replica_server: {len(server.replica.names)} tiles from {len(server.replica.sources)} sources on "
              f"http://{options.host}:{port}/ (catalog.vpc {server.catalog.size} bytes; S3 bucket "
              f"{options.bucket}; rtt {options.rtt_ms} ms, bandwidth {options.bandwidth or 'unlimited'})",
              file=sys.stderr, flush=True)
    async with listener:
        await listener.serve_forever()


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("manifest", help="a virtual replica's replicate.json")
    p.add_argument("--host", default="127.0.0.1")
    p.add_argument("--port", type=int, default=0, help="0: an ephemeral port (see --port-file)")
    p.add_argument("--port-file", help="where the port is written once the server listens")
    p.add_argument("--program", default="lidarscout", help="the lidarscout CLI (its catalog gives the items)")
    p.add_argument("--bucket", default="replica", help="the S3 bucket's name (default replica)")
    p.add_argument("--rtt-ms", type=float, default=0.0, help="each response's delay, ms (a new connection's: 2x)")
    p.add_argument("--bandwidth", type=parse_size, default=0, help="bytes/s per connection (0: unlimited)")
    p.add_argument("--overview", help="an overview sidecar to serve at /catalog.overview.laz (named in the VPC)")
    p.add_argument("--hold-last-page", action="store_true",
                   help="answer a search's last page (of several) only once GET /_release was asked")
    p.add_argument("--quiet", action="store_true")
    options = p.parse_args()
    if options.bucket in ("tiles", "catalog.vpc", "search", "_stats", "_release") or "/" in options.bucket:
        p.error(f"--bucket {options.bucket}: that name is one of the server's own paths")
    try:
        started = time.monotonic()
        replica = Replica(options.manifest)
        templates = [ItemTemplate(item, replica.to_metres[k])
                     for k, item in enumerate(source_items(options.program, replica))]
        items = Items(replica, templates)
        server = Server(replica, items, options)
        if not options.quiet:
            print(f"replica_server: ready in {time.monotonic() - started:.1f} s", file=sys.stderr, flush=True)
    except Refusal as e:
        print(f"replica_server: {e}", file=sys.stderr)
        return 2
    try:
        asyncio.run(serve(server, options))
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
