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
