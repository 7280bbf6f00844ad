"""ds.dem() against `dem`'s raster (read with GDAL's Python): the same texels and geotransform."""

import numpy as np
import pytest
from osgeo import gdal

import lidarscout
from conftest import WOODFORD, run_cli


def cli_raster(tmp_path, *options):
    out = tmp_path / "dem.tif"
    report = run_cli("dem", WOODFORD, "-o", out, "--json", *options)
    path = report["products"]["dtm"] if "products" in report else report["output"]
    raster = gdal.Open(str(path))
    return raster.GetRasterBand(1).ReadAsArray(), raster.GetGeoTransform()


@pytest.mark.parametrize("texel", [2.0, 5.0])
def test_dtm_is_dems_raster(tmp_path, woodford, texel):
    expected, geotransform = cli_raster(tmp_path, "--product", "dtm", "--texel", texel)
    raster, transform = woodford.dem(texel=texel, product="dtm")
    assert raster.dtype == np.float32 and raster.shape == expected.shape
    assert transform == pytest.approx(geotransform)
    np.testing.assert_array_equal(raster, expected)


def test_mean_dem_of_a_box_is_dems_raster(tmp_path, woodford):
    box = (5208500, 3903200, 5209500, 3904500)
    expected, geotransform = cli_raster(tmp_path, "--method", "mean", "--texel", "3", "--classes", "2",
                                        "--bounds", ",".join(map(str, box)))
    raster, transform = woodford.dem(texel=3, method="mean", classes=[2], bounds=box)
    assert transform == pytest.approx(geotransform)
    np.testing.assert_array_equal(raster, expected)


def test_a_method_and_a_product_together_are_refused(woodford):
    with pytest.raises(lidarscout.Error, match="not both"):
        woodford.dem(product="dsm", method="mean")


def test_plan_is_dems_plan(tmp_path, woodford):
    options = ("--texel", "1", "--product", "dtm,density")
    expected = run_cli("dem", WOODFORD, "-o", tmp_path / "x.tif", "--json", "--plan", "4", *options)
    plan = woodford.dem_plan(4, texel=1, product=["dtm", "density"])
    for piece in plan["pieces"]:
        piece["blocks"], piece["window"] = list(piece["blocks"]), list(piece["window"])
    assert plan == {key: value for key, value in expected.items()}


@pytest.mark.parametrize("index", [1, 3])
def test_a_block_is_dems_block(tmp_path, woodford, index):
    report = run_cli("dem", WOODFORD, "-o", tmp_path / "cli.tif", "--json", "--texel", "1", "--product",
                     "dtm,chm", "--block", f"{index}/4", "--max-edge", "30")
    made = woodford.dem_block(index, 4, tmp_path / "module.tif", texel=1, product="dtm,chm", max_edge=30, threads=2)
    assert made["block"] == {**report["block"], "blocks": tuple(report["block"]["blocks"]),
                             "window": tuple(report["block"]["window"])}
    assert made["points_used"] == report["points_used"]
    assert sorted(made["outputs"]) == ["chm", "dtm"]
    for name, path in made["outputs"].items():
        a, b = gdal.Open(str(path)), gdal.Open(report["products"][name])
        assert a.GetGeoTransform() == b.GetGeoTransform()
        np.testing.assert_array_equal(a.GetRasterBand(1).ReadAsArray(), b.GetRasterBand(1).ReadAsArray())
    assert sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("module")) == \
        ["module_chm.tif", "module_dtm.tif"]  # nothing left under a temporary name


def test_a_bad_piece_is_an_error(tmp_path, woodford):
    with pytest.raises(lidarscout.Error, match="--block"):
        woodford.dem_block(5, 4, tmp_path / "x.tif", texel=1)
    with pytest.raises(lidarscout.Error, match="over the budget"):
        woodford.dem_block(1, 4, tmp_path / "x.tif", texel=1, memory=1 << 20)
    with pytest.raises(lidarscout.Error, match="unknown option 'texle'"):
        woodford.dem_plan(4, texle=2)
    with pytest.raises(lidarscout.Error, match="radius: must be more than 0"):
        woodford.dem_plan(4, method="idw", radius=0)
    assert not list(tmp_path.iterdir())
