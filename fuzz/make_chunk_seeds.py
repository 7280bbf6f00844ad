#!/usr/bin/env python3
"""Seeds for fuzz_chunk: the first chunk of a few corpus LAZ files (up to 64 KiB), each
prefixed with the fuzz target's layout byte and point count. Usage: make_chunk_seeds.py OUT_DIR"""
import json
import os
import sys

FORMATS = os.path.join(os.path.dirname(__file__), "..", "..", "shared", "data", "formats")
# file -> index of its item list in fuzz_chunk.cpp's layouts()
FILES = {
    "PDAL__PDAL/test__data__laz__autzen_trim.laz": 3,
    "hobuinc__laz-perf/cpp__test__raw-sets__point10.las.laz": 0,
    "hobuinc__laz-perf/cpp__test__raw-sets__extrabytes.laz": 4,
    "IGNF__ign-pdal-tools/test__data__decimated_laz__test_semis_2021_0382_6565_LA93_IGN69_cropped.laz": 8,
    "visgl__loaders.gl/modules__las__test__data__pdrf8-1.4.laz": 9,
    "visgl__loaders.gl/modules__las__test__data__pdrf10-1.5.laz": 11,
}


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    for name, layout in FILES.items():
        with open(os.path.join(FORMATS, "expected", name.replace("/", "__") + ".json")) as f:
            chunk = json.load(f)["chunks"][0]
        with open(os.path.join(FORMATS, name), "rb") as f:
            f.seek(chunk["byte_offset"])
            data = f.read(min(chunk["byte_size"], 65536))
        n = min(chunk["point_count"], 4096) - 1
        with open(os.path.join(out_dir, os.path.basename(name)), "wb") as f:
            f.write(bytes([layout, n & 255, n >> 8]) + data)


if __name__ == "__main__":
    main(sys.argv[1])
