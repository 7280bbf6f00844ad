#!/usr/bin/env bash
# build_training_set.sh (kept in the data tree as /work/traindata/rebuild.sh)
#
# Rebuilds the lidarscout training set of issue 17, item 4, from LOCAL copies of public
# git repositories (bare mirrors as the fetch tool leaves them: MIRROR/<owner>+<name>/repo).
# It downloads nothing. For every source it:
#   1. finds the mirror and checks that the pinned commit is there;
#   2. runs reserved.py OWNER/NAME and reserved.py OWNER/NAME:PATH (exit 1 = reserved
#      unseen test data: the source is skipped and the build reports it);
#   3. converts the Potree 1.x cloud or EPT dataset at that commit into square LAS 1.2
#      tiles with potree2las.py (EPT through the embedded ept2las.py, which reuses
#      potree2las.py's tiling and writing);
#   4. drops tiles with fewer than --min-points points (slivers at grid edges);
#   5. checks every tile with potree2las.py verify and runs reserved.py --scan on them;
#   6. optionally compresses the tiles to LAZ with 50,000-point chunks (--lidarscout).
# Finally it runs reserved.py --scan on the whole output and writes build_summary.json.
#
# Needs: bash, git, python3 with numpy (Debian python3-numpy), and for Potree clouds with
# LAZ nodes a LAZ decoder: --laszip PROG (called as PROG -i in.laz -o out.las), or
# --lidarscout PATH (its `convert` is used, e.g. build/lidarscout). Without one, LAZ-node sources
# are skipped with a message.
#
# Usage: build_training_set.sh [MIRROR] [--mirror DIR] [--shared DIR] [--out DIR]
#            [--laszip PROG] [--lidarscout PATH] [--workers N] [--min-points N]
#            [--only NAME[,NAME...]] [--list]
#   MIRROR / --mirror  root of the local mirrors (default /work/.mirror)
#   --shared           the shared folder with tools/potree2las.py and tools/reserved.py
#                      (default ../shared, relative to the current directory)
#   --out              output folder, one sub-folder per source (default ../traindata)
set -euo pipefail

MIRROR=/work/.mirror
SHARED=../shared
OUT=../traindata
LASZIP=""
LIDARSCOUT=""
WORKERS=1
MIN_POINTS=50000
ONLY=""
LIST=0
DATE=2026-11-24          # creation date written into the LAS headers (reproducible bytes)
PY=${PYTHON:-python3}

while [[ $# -gt 0 ]]; do
  case "$1" in
    --mirror) MIRROR=$2; shift 2 ;;
    --shared) SHARED=$2; shift 2 ;;
    --out) OUT=$2; shift 2 ;;
    --laszip) LASZIP=$2; shift 2 ;;
    --lidarscout) LIDARSCOUT=$2; shift 2 ;;
    --workers) WORKERS=$2; shift 2 ;;
    --min-points) MIN_POINTS=$2; shift 2 ;;
    --only) ONLY=$2; shift 2 ;;
    --list) LIST=1; shift ;;
    -h|--help) sed -n '2,36p' "$0"; exit 0 ;;
    -*) echo "unknown option $1" >&2; exit 2 ;;
    *) MIRROR=$1; shift ;;
  esac
done

# name|owner/repo|commit|path in repo|kind|grid|epsg|units|LAZ nodes?|GeoTIFF citation
SOURCES=(
"als-terrain-annotator|jandopsnx/pointCloudAnnotator|3dc4dc8594861204568164c17c2bbcc5aa700202|pointclouds/terrain|potree|1000|32767|m|no|unknown projected CRS (source gives none; UTM-like), x, y, z in metres"
"autzen-oregon-ept|PDAL/data|ce0024257c573526389c4db9ab26e82739b8aaa9|entwine/data/binary|ept|3000|2994|ft|no|NAD83(HARN) / Oregon Lambert (ft), international feet"
"ky-georgetown|Hmsi229/Georgetown_Development|e592c9e376a43150cf0181eb7d08ec13b375ce7e|potree/pointclouds/index|potree|5000|3089|ftUS|no|NAD83 / Kentucky Single Zone (ftUS)"
"ky-lockegee|AlexGIS-projects/lockagee|d5aed7ae6aed3941e2d97118a72033b6a70a6fd1|3D/pointclouds/index|potree|5000|3089|ftUS|no|NAD83 / Kentucky Single Zone (ftUS)"
"ky-robinson-forest|MasonMefford/Final_Project|6134f1997917a0f45011a058196c935c167e61dc|potree/pointclouds/index|potree|5000|3089|ftUS|no|NAD83 / Kentucky Single Zone (ftUS)"
"ky-n066e379|ionajo/rrg|2d50e49e682ab546928381786e8468bacba8cba1|3d/pointclouds/index|potree|5000|3089|ftUS|no|NAD83 / Kentucky Single Zone (ftUS)"
"galapagos-lidar|faustoaguanor/GalapagosLAS|29998cb5fc412802dc347d800c186c2d5811f379|pointclouds/index|potree|1000|32715|m|yes|WGS 84 / UTM zone 15S"
)

if [[ $LIST == 1 ]]; then printf '%s\n' "${SOURCES[@]}"; exit 0; fi

TOOLS=$SHARED/tools
P2L=$TOOLS/potree2las.py
RES=$TOOLS/reserved.py
[[ -f $P2L && -f $RES ]] || { echo "potree2las.py / reserved.py not found under $TOOLS (use --shared)" >&2; exit 2; }
"$PY" -c 'import numpy' 2>/dev/null || { echo "$PY has no numpy (Debian: python3-numpy; or set PYTHON=/usr/bin/python3)" >&2; exit 2; }
mkdir -p "$OUT"
OUT=$(cd "$OUT" && pwd)
TOOLS=$(cd "$TOOLS" && pwd)
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT

# ---------------------------------------------------------------- embedded helpers
cat > "$WORK/ept2las.py" <<'PYEOF'
#!/usr/bin/env python3
"""ept2las: convert an Entwine Point Tile (EPT) dataset into square LAS 1.2 tiles.

Reads ept.json, the JSON hierarchy (ept-hierarchy/*.json) and every node in
ept-data/ (dataType "binary" is decoded here with numpy; dataType "laszip" needs
an external decoder called as PROG -i in.laz -o out.las, exactly like
potree2las.py --laszip), from a folder or from a bare git repository at a commit.

Everything after reading (deduplication, tiling on a square grid, point order,
LAS 1.2 writing, GeoKeys, the JSON report with occupied 10 m cells per tile) is
done by potree2las.py, which this script imports: pass its folder with
--tools DIR (default: the folder of this script, then ../shared/tools).

Usage: ept2las.py [ept] convert (--src DIR | --git-dir G --rev C --path P) --out DIR
       --grid G --epsg E --units {m,ftUS,ft} [other potree2las convert options]
       ept2las.py potree convert|info|verify ...   (potree2las.py itself, with a git
       reader that accepts the repository root and skips blobs absent from the copy)
"""
import argparse
import json
import os
import sys

import numpy as np


def _import_potree2las(argv):
    tools = None
    for i, a in enumerate(argv):
        if a == "--tools" and i + 1 < len(argv):
            tools = argv[i + 1]
        elif a.startswith("--tools="):
            tools = a.split("=", 1)[1]
    here = os.path.dirname(os.path.abspath(__file__))
    for d in ([tools] if tools else []) + [here, os.path.join(here, "..", "shared", "tools")]:
        if d and os.path.exists(os.path.join(d, "potree2las.py")):
            sys.path.insert(0, d)
            import potree2las
            return potree2las
    sys.exit("ept2las: potree2las.py not found (pass --tools DIR)")


P = _import_potree2las(sys.argv)

NUM = {("signed", 1): "<i1", ("signed", 2): "<i2", ("signed", 4): "<i4", ("signed", 8): "<i8",
       ("unsigned", 1): "u1", ("unsigned", 2): "<u2", ("unsigned", 4): "<u4",
       ("unsigned", 8): "<u8", ("float", 4): "<f4", ("float", 8): "<f8"}


def load_hierarchy(src):
    """{node key: point count} from ept-hierarchy/0-0-0-0.json and its sub-files (-1)."""
    out = {}
    todo = ["0-0-0-0"]
    while todo:
        k = todo.pop()
        h = json.loads(src.read("ept-hierarchy/%s.json" % k).decode())
        for key, v in h.items():
            if v == -1:
                todo.append(key)
            else:
                out[key] = int(v)
    return out


def binary_node_columns(ept, data):
    schema = ept["schema"]
    dt = np.dtype([(d["name"], NUM[(d["type"], d["size"])]) for d in schema])
    if len(data) % dt.itemsize:
        raise IOError("binary node size %d is not a multiple of %d" % (len(data), dt.itemsize))
    a = np.frombuffer(data, dtype=dt)
    n = len(a)
    out = {"n": n}
    for d in schema:
        if d["name"] in ("X", "Y", "Z"):
            out[d["name"].lower()] = (a[d["name"]].astype(np.float64) * d.get("scale", 1.0)
                                      + d.get("offset", 0.0))
    names = a.dtype.names

    def col(name, dtype):
        return a[name].astype(dtype) if name in names else None

    for ept_name, c, t in (("Intensity", "intensity", np.uint16),
                           ("Classification", "cls", np.uint8),
                           ("ReturnNumber", "ret", np.uint8),
                           ("NumberOfReturns", "nret", np.uint8),
                           ("UserData", "ud", np.uint8),
                           ("PointSourceId", "psid", np.uint16),
                           ("GpsTime", "gps", np.float64),
                           ("Red", "R", np.uint16), ("Green", "G", np.uint16),
                           ("Blue", "B", np.uint16)):
        v = col(ept_name, t)
        if v is not None:
            out[c] = v
    if "ScanAngleRank" in names:
        out["sar"] = np.clip(np.rint(a["ScanAngleRank"].astype(np.float64)), -128, 127).astype(np.int8)
    flags = np.zeros(n, np.uint8)
    if "ScanDirectionFlag" in names:
        flags |= (a["ScanDirectionFlag"].astype(np.uint8) & 1) << 6
    if "EdgeOfFlightLine" in names:
        flags |= (a["EdgeOfFlightLine"].astype(np.uint8) & 1) << 7
    out["flags"] = flags
    return out


def read_ept(src, laszip=None, workers=1, log=print):
    ept = json.loads(src.read("ept.json").decode())
    dtype = ept.get("dataType")
    ext = {"binary": ".bin", "laszip": ".laz"}.get(dtype)
    if ext is None:
        raise SystemExit("ept2las: dataType %r not supported" % dtype)
    files = [rel for rel, _ in src.list() if rel.startswith("ept-data/") and rel.endswith(ext)]
    hier = load_hierarchy(src)
    log("EPT %s: dataType %s, %d node files, %d nodes in hierarchy, ept.json points %s"
        % (ept.get("version"), dtype, len(files), len(hier), ept.get("points")))
    parts = []
    per_node = {}
    if dtype == "binary":
        for rel, data in src.read_many(files):
            d = binary_node_columns(ept, data)
            per_node[os.path.basename(rel)[:-len(ext)]] = d["n"]
            parts.append(d)
    else:
        jobs = ((rel, data, laszip) for rel, data in src.read_many(files))
        if workers > 1:
            import multiprocessing as mp
            with mp.Pool(workers) as pool:
                it = pool.imap(P._laz_worker, jobs, chunksize=1)
                for i, (rel, d) in enumerate(it):
                    per_node[os.path.basename(rel)[:-len(ext)]] = d["n"]
                    parts.append(d)
                    if (i + 1) % 100 == 0:
                        log("  decoded %d/%d LAZ nodes" % (i + 1, len(files)))
        else:
            for i, job in enumerate(jobs):
                rel, d = P._laz_worker(job)
                per_node[os.path.basename(rel)[:-len(ext)]] = d["n"]
                parts.append(d)
                if (i + 1) % 100 == 0:
                    log("  decoded %d/%d LAZ nodes" % (i + 1, len(files)))
    total = sum(p["n"] for p in parts)
    cols, present = {}, {}
    for c in P.COLS:
        present[c] = any(c in p for p in parts)
        if not present[c]:
            continue
        dt = next(p[c].dtype for p in parts if c in p)
        cols[c] = np.concatenate([p[c] if c in p else np.zeros(p["n"], dtype=dt) for p in parts])
    flags = [p.get("flags") for p in parts]
    if any(f is not None for f in flags):
        cols["flags"] = np.concatenate([f if f is not None else np.zeros(p["n"], np.uint8)
                                        for f, p in zip(flags, parts)])
    # 8-bit colour stored in 16-bit fields: scale to the full 16-bit range
    rgb8 = False
    if present.get("R"):
        mx = max(int(cols[c].max()) if len(cols[c]) else 0 for c in ("R", "G", "B"))
        if 0 < mx <= 255:
            for c in ("R", "G", "B"):
                cols[c] = (cols[c].astype(np.uint32) * 257).astype(np.uint16)
            rgb8 = True
    # potree2las.cmd_convert reads these presence keys
    present.update({"R": present.get("R", False), "gps": present.get("gps", False),
                    "intensity": present.get("intensity", False),
                    "cls": present.get("cls", False),
                    "ret": present.get("ret", False), "nret": present.get("nret", False),
                    "psid": present.get("psid", False)})
    missing = sorted(set(hier) - set(per_node))
    extra = sorted(set(per_node) - set(hier))
    mismatch = sorted(k for k in per_node if k in hier and hier[k] != per_node[k])
    check = {"node_files": len(per_node), "hierarchy_nodes": len(hier),
             "hierarchy_points": int(sum(hier.values())), "decoded_points": int(total),
             "cloudjs_points": ept.get("points"),
             "nodes_missing": missing[:20], "n_nodes_missing": len(missing),
             "nodes_not_in_hierarchy": extra[:20],
             "hrc_count_differs_informational": mismatch[:20],
             "n_hrc_count_differs_informational": len(mismatch)}
    if missing or mismatch:
        log("WARNING: %d hierarchy nodes missing, %d with other counts" % (len(missing), len(mismatch)))
    cj = {"version": "EPT " + str(ept.get("version")), "points": ept.get("points")}
    return cj, [], "EPT-" + dtype, None, cols, present, rgb8, check


class GitSourceRobust(P.GitSource):
    """potree2las.GitSource that also accepts the repository root (empty --path) and skips
    blobs the local copy lacks (ls-tree prints no size for them; snapshots drop files of
    4 MiB or more), e.g. a source LAZ kept next to a Potree cloud."""

    def __init__(self, gitdir, rev, path):
        import subprocess
        self.gitdir = gitdir
        self.path = path.strip("/")
        self.rev = subprocess.check_output(
            ["git", "--git-dir", gitdir, "rev-parse", rev + "^{commit}"]).decode().strip()
        self.desc = "%s@%s:%s" % (gitdir, self.rev, self.path)
        cmd = ["git", "--git-dir", gitdir, "ls-tree", "-r", "-l", self.rev]
        if self.path:
            cmd += ["--", self.path + "/"]
        out = subprocess.check_output(cmd)
        self.entries = {}
        self.skipped = []
        for line in out.decode().splitlines():
            meta, name = line.split("\t", 1)
            mode, typ, sha, size = meta.split()
            if typ != "blob":
                continue
            rel = name[len(self.path) + 1:] if self.path else name
            if not size.isdigit():
                self.skipped.append(rel)
                continue
            self.entries[rel] = (sha, int(size))
        if self.skipped:
            print("note: %d blobs absent from the local copy, skipped: %s"
                  % (len(self.skipped), ", ".join(self.skipped[:5])), file=sys.stderr)


def main(argv):
    argv = list(argv)
    # drop our own --tools option before handing the rest to potree2las
    clean = []
    skip = False
    for i, a in enumerate(argv):
        if skip:
            skip = False
            continue
        if a == "--tools":
            skip = True
            continue
        if a.startswith("--tools="):
            continue
        clean.append(a)
    P.GitSource = GitSourceRobust
    if clean and clean[0] == "potree":
        # plain potree2las.py, with the robust git reader
        return P.main(clean[1:])
    if clean and clean[0] == "ept":
        clean = clean[1:]
    if not clean or clean[0] != "convert":
        sys.exit(__doc__)
    if "--names" not in clean:
        clean += ["--names", "coords"]
    P.read_potree = read_ept
    return P.main(clean)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
PYEOF

# ---------------------------------------------------------------- LAZ decoder
DECODER=""
if [[ -n $LASZIP ]]; then
  DECODER=$LASZIP
elif [[ -n $LIDARSCOUT ]]; then  # our own codec: `lidarscout convert in.laz out.las`
  printf '#!/bin/sh\n# PROG -i in.laz -o out.las\nexec "%s" convert "$2" "$4"\n' "$LIDARSCOUT" > "$WORK/lazdec"
  chmod +x "$WORK/lazdec"; DECODER=$WORK/lazdec
fi

gitdir_of() {   # owner/name -> bare git dir under $MIRROR
  local d=$MIRROR/${1/\//+}
  if [[ -d $d/repo/.git ]]; then echo "$d/repo/.git"
  elif [[ -d $d/repo ]]; then echo "$d/repo"
  elif [[ -d $d/.git ]]; then echo "$d/.git"
  elif [[ -d $d ]]; then echo "$d"
  else return 1; fi
}

reserved() {    # 0 = free, 1 = reserved (anything else is an error)
  local rc=0
  "$PY" "$RES" "$@" >/dev/null 2>&1 || rc=$?
  if [[ $rc -gt 1 ]]; then echo "reserved.py $* failed (exit $rc)" >&2; exit 3; fi
  return $rc
}

STATUS=$WORK/status.tsv
: > "$STATUS"
note() { printf '%s\t%s\t%s\n' "$1" "$2" "$3" >> "$STATUS"; echo "[$1] $2: $3"; }

for line in "${SOURCES[@]}"; do
  IFS='|' read -r NAME REPO COMMIT SPATH KIND GRID EPSG UNITS LAZ CITATION <<< "$line"
  if [[ -n $ONLY && ",$ONLY," != *",$NAME,"* ]]; then continue; fi
  echo "=== $NAME  ($REPO@$COMMIT:$SPATH)"
  if ! G=$(gitdir_of "$REPO"); then note "$NAME" skipped "no mirror of $REPO under $MIRROR"; continue; fi
  if ! git --git-dir="$G" cat-file -e "$COMMIT^{commit}" 2>/dev/null; then
    note "$NAME" skipped "commit $COMMIT not in $G"; continue; fi
  if ! reserved "$REPO"; then note "$NAME" RESERVED "$REPO is reserved unseen test data"; continue; fi
  if ! reserved "$REPO:$SPATH"; then note "$NAME" RESERVED "$REPO:$SPATH is reserved unseen test data"; continue; fi
  EXTRA=()
  if [[ $LAZ == yes ]]; then
    if [[ -z $DECODER ]]; then note "$NAME" skipped "LAZ nodes and no decoder (--laszip/--lidarscout)"; continue; fi
    EXTRA=(--laszip "$DECODER" --workers "$WORKERS")
  fi
  DEST=$OUT/$NAME
  TMP=$OUT/.$NAME.part
  rm -rf "$TMP"
  MODE=$KIND; [[ $KIND == potree ]] && MODE="potree"
  nice -n 10 "$PY" "$WORK/ept2las.py" --tools "$TOOLS" $MODE convert \
      --git-dir "$G" --rev "$COMMIT" --path "$SPATH" --out "$TMP" \
      --grid "$GRID" --epsg "$EPSG" --units "$UNITS" --citation "$CITATION" \
      --names coords --date "$DATE" --report potree2las_report.json "${EXTRA[@]}" \
      > "$WORK/$NAME.log" 2>&1 || { tail -20 "$WORK/$NAME.log" >&2; note "$NAME" FAILED "conversion failed"; rm -rf "$TMP"; continue; }
  cp "$WORK/$NAME.log" "$TMP/convert.log"
  # drop sliver tiles, record what was dropped
  "$PY" - "$TMP" "$MIN_POINTS" "$REPO" "$COMMIT" "$SPATH" <<'PYEOF'
import json, os, sys
d, mn = sys.argv[1], int(sys.argv[2])
p = os.path.join(d, "potree2las_report.json")
r = json.load(open(p))
keep, drop = [], []
for t in r["tiles"]:
    (keep if t["points"] >= mn else drop).append(t)
for t in drop:
    os.remove(os.path.join(d, t["file"]))
r["tiles"] = keep
r["dropped_tiles"] = [{"file": t["file"], "points": t["points"], "occupied_km2": t["occupied_km2"]} for t in drop]
r["min_points_per_tile"] = mn
r["source_pin"] = {"repo": sys.argv[3], "commit": sys.argv[4], "path": sys.argv[5]}
json.dump(r, open(p, "w"), indent=1)
print("kept %d tiles (%d points, %.3f km2 occupied); dropped %d tiles with %d points"
      % (len(keep), sum(t["points"] for t in keep), sum(t["occupied_km2"] for t in keep),
         len(drop), sum(t["points"] for t in drop)))
PYEOF
  "$PY" "$P2L" verify "$TMP"/*.las > "$TMP/verify.log" 2>&1 || { cat "$TMP/verify.log" >&2; note "$NAME" FAILED "verify failed"; rm -rf "$TMP"; continue; }
  if ! reserved --scan "$TMP"; then note "$NAME" RESERVED "a converted tile name is reserved; source removed"; rm -rf "$TMP"; continue; fi
  if [[ -n $LIDARSCOUT ]]; then
    for f in "$TMP"/*.las; do
      "$LIDARSCOUT" convert "$f" "${f%.las}.laz" > /dev/null && rm -f "$f"
    done
    if ! reserved --scan "$TMP"; then note "$NAME" RESERVED "a tile name is reserved; source removed"; rm -rf "$TMP"; continue; fi
  fi
  rm -rf "$DEST"; mv "$TMP" "$DEST"
  note "$NAME" ok "$(ls "$DEST" | grep -cE '\.la[sz]$') tiles"
done

# ---------------------------------------------------------------- whole output
rc=0; "$PY" "$RES" --scan "$OUT" || rc=$?
if [[ $rc -ne 0 ]]; then echo "reserved.py --scan $OUT: exit $rc -- do not use this tree" >&2; exit 4; fi
"$PY" - "$OUT" "$STATUS" <<'PYEOF'
import json, os, sys
out, status = sys.argv[1], sys.argv[2]
rows = [l.rstrip("\n").split("\t") for l in open(status) if l.strip()]
summ = {"sources": [], "status": [{"name": a, "status": b, "detail": c} for a, b, c in rows]}
for name in sorted(os.listdir(out)):
    p = os.path.join(out, name, "potree2las_report.json")
    if not os.path.isfile(p):
        continue
    r = json.load(open(p))
    t = r["tiles"]
    summ["sources"].append({
        "name": name, "pin": r.get("source_pin"), "tiles": len(t),
        "points": sum(x["points"] for x in t),
        "occupied_km2_10m_cells": round(sum(x["occupied_km2"] for x in t), 4),
        "tiles_ge_200k_points": sum(1 for x in t if x["points"] >= 200000),
        "epsg": r["epsg"], "units": r["units"], "rgb": r["has"]["rgb"], "gps_time": r["has"]["gps"],
        "order": r["order"], "dropped_tiles": len(r.get("dropped_tiles", []))})
summ["total_points"] = sum(s["points"] for s in summ["sources"])
summ["total_occupied_km2"] = round(sum(s["occupied_km2_10m_cells"] for s in summ["sources"]), 3)
json.dump(summ, open(os.path.join(out, "build_summary.json"), "w"), indent=1)
for s in summ["sources"]:
    print("%-24s %4d tiles %11d points %8.3f km2" % (s["name"], s["tiles"], s["points"], s["occupied_km2_10m_cells"]))
print("%-24s %4s       %11d points %8.3f km2" % ("TOTAL", "", summ["total_points"], summ["total_occupied_km2"]))
PYEOF
