"""lidarscout.open and the dataset's description against `scan` and `info` of the same tiles; errors as
lidarscout.Error (file, offset, cause), never a crash or a print."""

import pathlib

import pytest

import lidarscout
from conftest import JMO335, WOODFORD, run_cli


def test_open_describes_the_tiles_as_scan_and_info_do(jmo335):
    scan = run_cli("scan", JMO335, "--json")
    assert len(jmo335.tiles) == scan["tiles"] == 9
    assert jmo335.point_count == scan["points"] == 15_677_894
    info = {pathlib.Path(t["path"]).name: t for t in run_cli("info", JMO335, "--json")}
    for tile in jmo335.tiles:
        name = pathlib.Path(tile["path"]).name
        assert tile["count"] == info[name]["point_count"]
        assert tile["point_format"] == info[name]["point_format"]
        assert tile["crs"]["epsg"] == 3089
    assert sum(t["count"] for t in jmo335.tiles) == jmo335.point_count


def test_bounds_are_in_the_crs_units(jmo335):
    min_x, min_y, min_z, max_x, max_y, max_z = jmo335.bounds
    # the README's bbox, in US survey feet (EPSG:3089)
    assert min_x == pytest.approx(5673834.80, abs=0.01) and max_x == pytest.approx(5681834.79, abs=0.01)
    assert min_y == pytest.approx(3768732.54, abs=0.01) and max_y == pytest.approx(3776732.53, abs=0.01)
    assert min_z == pytest.approx(877.26, abs=0.01) and max_z == pytest.approx(1450.10, abs=0.01)


def test_crs_has_wkt_and_epsg(woodford):
    crs = woodford.crs
    assert crs["epsg"] == 3089
    assert "Kentucky" in crs["wkt"] and crs["wkt"].startswith(("PROJCRS", "COMPOUNDCRS"))
    assert crs["geographic"] is False


def test_a_list_of_paths_opens_those_tiles():
    files = sorted(str(p) for p in JMO335.glob("*.laz"))[:2]
    ds = lidarscout.open(files)
    assert [t["path"] for t in ds.tiles] == files


def test_no_readable_tile_is_an_error_naming_why(tmp_path):
    bad = tmp_path / "bad.laz"
    bad.write_bytes(b"LASF" + b"\x00" * 50)
    with pytest.raises(lidarscout.Error) as raised:
        lidarscout.open(str(bad))
    assert isinstance(raised.value, RuntimeError)
    assert "bad.laz" in str(raised.value) and raised.value.cause


def test_a_bad_tile_beside_good_ones_is_skipped_and_named(tmp_path):
    bad = tmp_path / "bad.laz"
    bad.write_bytes(b"LASF" + b"\x00" * 50)
    ds = lidarscout.open([str(WOODFORD / "5205000_3900000.laz"), str(bad)])
    assert len(ds.tiles) == 1
    assert [s["path"] for s in ds.skipped] == [str(bad)] and ds.skipped[0]["error"]


def test_a_bad_crs_is_an_error(woodford):
    with pytest.raises(lidarscout.Error):
        lidarscout.open(str(WOODFORD), crs="EPSG:999999")


def test_a_bad_origin_list_is_an_error():
    with pytest.raises(lidarscout.Error) as raised:
        lidarscout.open(str(WOODFORD), allow_origins="not a url")
    assert raised.value.file is None and raised.value.offset is None and "not a url" in raised.value.cause


def test_region_errors_are_lidarscout_errors(woodford):
    with pytest.raises(lidarscout.Error, match="no tile touches"):
        woodford.read(bounds=(0, 0, 10, 10))
    with pytest.raises(lidarscout.Error, match="xmin <= xmax"):
        woodford.read(bounds=(10, 0, 0, 10))
    with pytest.raises(lidarscout.Error, match="four numbers"):
        woodford.read(bounds=(0, 0, 10))
    with pytest.raises(lidarscout.Error):
        woodford.read(classes="not a class")
    with pytest.raises(lidarscout.Error):
        woodford.read(polygon="POLYGON ((0 0, 1")
    with pytest.raises(lidarscout.Error):
        woodford.dem(texel=-1)
