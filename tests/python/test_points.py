"""ds.overview(), ds.read() and ds.iter_read() against the CLI on the shared surveys: the overview is
`scan`'s chunk points (and `info --chunks`' values), a region's points are the points `clip` writes."""

import pathlib

import numpy as np
import pytest

import lidarscout
from conftest import JMO335, WOODFORD, run_cli

WOODFORD_TILE = WOODFORD / "5205000_3900000.laz"
# A box over the corner of four ky-jmo335 tiles (N117E380, N117E381, N118E380, N118E381), in US feet.
JMO335_BOX = (5679000.0, 3774000.0, 5681000.0, 3776000.0)


def sorted_xyz(points):
    order = np.lexsort((points["z"], points["y"], points["x"]))
    return np.stack([points["x"][order], points["y"][order], points["z"][order]], axis=1)


def clipped(tmp_path, survey, *options):
    """The points `clip` writes for OPTIONS, read back whole, and its --json report."""
    out = tmp_path / "clip.laz"
    report = run_cli("clip", survey, "-o", out, "--json", *options)
    return lidarscout.open(str(out)).read(), report


def test_overview_is_scans_chunk_points(jmo335):
    points = jmo335.overview()
    assert len(points) == run_cli("scan", JMO335, "--json")["chunk_points"]
    assert jmo335.last_skipped == []
    assert set(np.unique(points["tile"])) == set(range(len(jmo335.tiles)))
    assert points.dtype.names == ("x", "y", "z", "intensity", "return_number", "number_of_returns",
                                  "classification", "red", "green", "blue", "tile")


def test_overview_of_a_catalog_with_a_sidecar_reads_no_tile(tmp_path):
    # A virtual replica's catalog names tiles that are not on disk: only its overview sidecar holds their
    # chunk points, and overview() takes them from it, as scan does.
    run_cli("synth", "replicate", WOODFORD, "--grid", "3x2", "--virtual", "-o", tmp_path / "rep")
    vpc = tmp_path / "rep.vpc"
    run_cli("catalog", tmp_path / "rep" / "replicate.json", "-o", vpc, "--overview")
    ds = lidarscout.open(str(vpc))
    assert not any(pathlib.Path(t["path"]).exists() for t in ds.tiles)
    points = ds.overview()
    assert ds.last_skipped == []
    assert len(points) == run_cli("scan", vpc, "--json")["chunk_points"] > 0
    assert set(np.unique(points["tile"])) == set(range(len(ds.tiles)))


def test_overview_values_are_infos_chunk_points(woodford):
    points = woodford.overview()
    expected = run_cli("info", WOODFORD_TILE, "--json", "--chunks")[0]["chunk_points"]
    assert len(points) == len(expected)
    for k in (0, 1, len(expected) // 2, len(expected) - 1):
        p, e = points[k], expected[k]
        assert (p["x"], p["y"], p["z"]) == (e["x"], e["y"], e["z"])
        assert (p["intensity"], p["classification"], p["return_number"]) == (
            e["intensity"], e["classification"], e["return_number"])
        assert p["gps_time"] == e["gps_time"] and [p["red"], p["green"], p["blue"]] == e["rgb"]


def test_read_of_a_box_is_clips_points(tmp_path, jmo335):
    bounds = ",".join(map(str, JMO335_BOX))
    expected, report = clipped(tmp_path, JMO335, "--bounds", bounds)
    points = jmo335.read(bounds=JMO335_BOX)
    assert len(points) == report["points_written"] == len(expected)
    assert len(points) > 100_000
    np.testing.assert_allclose(sorted_xyz(points), sorted_xyz(expected), rtol=0, atol=1e-6)
    assert set(np.unique(points["tile"])) == {1, 2, 4, 5}


def test_read_of_a_polygon_with_filters_is_clips_points(tmp_path, woodford):
    polygon = "POLYGON ((5208500 3903200, 5209800 3903500, 5209200 3904800, 5208500 3903200))"
    expected, report = clipped(tmp_path, WOODFORD, "--polygon", polygon, "--classes", "2,6",
                               "--returns", "last", "--intensity", "0-2000")
    points = woodford.read(polygon=polygon, classes=[2, 6], returns=["last"], intensity=(0, 2000))
    assert len(points) == report["points_written"] == len(expected) > 1000
    np.testing.assert_array_equal(sorted_xyz(points), sorted_xyz(expected))
    assert set(np.unique(points["classification"])) <= {2, 6}
    assert np.all(points["return_number"] == points["number_of_returns"])


def test_read_with_one_thread_equals_read_with_two(woodford):
    one = woodford.read(bounds=(5208500, 3903200, 5209500, 3904500), threads=1)
    two = woodford.read(bounds=(5208500, 3903200, 5209500, 3904500), threads=2)
    assert len(one) > 0
    np.testing.assert_array_equal(one, two)


def test_read_of_everything_is_every_point(woodford):
    points = woodford.read()
    assert len(points) == woodford.point_count
    assert points.flags["OWNDATA"] is False and points.base is not None  # the table itself, not a copy


def test_iter_read_is_read_in_bounded_batches(woodford):
    whole = woodford.read(classes=[2])
    batches = list(woodford.iter_read(classes=[2], batch=50_000))
    assert all(len(b) == 50_000 for b in batches[:-1]) and 0 < len(batches[-1]) <= 50_000
    np.testing.assert_array_equal(np.concatenate(batches), whole)


def test_iter_read_can_stop_early(woodford):
    stream = woodford.iter_read(batch=10_000)
    first = next(stream)
    stream.close()
    assert len(first) == 10_000
    with pytest.raises(StopIteration):
        next(stream)
