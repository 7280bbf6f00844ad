"""`cmake --install` puts the module where Debian's python3 finds it under the prefix it is given: with
--prefix /usr in /usr/lib/python3/dist-packages (where the .deb puts it), with the default /usr/local in
/usr/local/lib/python3.X/dist-packages, elsewhere in P/lib/python3.X/site-packages. Installed into a DESTDIR,
the module imports from there (not from the build tree) and opens a survey."""

import os
import pathlib
import subprocess
import sys
import sysconfig

import pytest

from conftest import WOODFORD

BUILD = pathlib.Path(os.environ.get("LIDARSCOUT_BUILD_DIR", pathlib.Path(__file__).resolve().parents[2] / "build"))
VERSION = f"python{sys.version_info.major}.{sys.version_info.minor}"

PREFIXES = {
    "/usr": "/usr/lib/python3/dist-packages",
    "/usr/local": f"/usr/local/lib/{VERSION}/dist-packages",
    "/opt/lidarscout": f"/opt/lidarscout/lib/{VERSION}/site-packages",
}


def test_debian_python_looks_where_usr_and_usr_local_install():
    assert sysconfig.get_path("platlib", "deb_system") == PREFIXES["/usr"]
    assert sysconfig.get_path("platlib", "posix_local") == PREFIXES["/usr/local"]
    assert PREFIXES["/usr"] in sys.path and PREFIXES["/usr/local"] in sys.path


@pytest.mark.parametrize("prefix", sorted(PREFIXES))
def test_install_puts_the_module_where_python_finds_it(tmp_path, prefix):
    root = tmp_path / "root"
    env = dict(os.environ, DESTDIR=str(root))
    subprocess.run(["cmake", "--install", str(BUILD), "--prefix", prefix], env=env, check=True, capture_output=True)
    site = root / PREFIXES[prefix].lstrip("/")
    assert sorted(p.name for p in (site / "lidarscout").iterdir() if p.suffix == ".py") == ["__init__.py", "_error.py"]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env["PYTHONPATH"] = str(site)
    code = "import sys, lidarscout; print(lidarscout.__file__); print(lidarscout.open(sys.argv[1]).point_count)"
    done = subprocess.run([sys.executable, "-c", code, str(WOODFORD)], env=env, cwd=tmp_path, check=True,
                          capture_output=True, text=True)
    where, count = done.stdout.split()
    assert pathlib.Path(where).is_relative_to(site)
    assert int(count) > 0
