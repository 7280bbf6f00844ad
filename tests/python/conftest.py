"""Fixtures of the Python module's tests (pytest): the CLI they compare with, the shared surveys, and a
runner of the CLI that returns its --json output. CTest runs each test_*.py here with PYTHONPATH set
to build/python and LIDARSCOUT_CLI, LIDARSCOUT_DATA_DIR to this build's program and data."""

import json
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
DATA = pathlib.Path(os.environ.get("LIDARSCOUT_DATA_DIR", REPO.parent / "shared" / "data"))
CLI = os.environ.get("LIDARSCOUT_CLI", str(REPO / "build" / "lidarscout"))
WOODFORD = DATA / "surveys" / "ky-woodford-county"
JMO335 = DATA / "surveys" / "ky-jmo335-eastern-kentucky"


def run_cli(*args, expect=0):
    """Runs `lidarscout ARGS` and returns its stdout parsed as JSON (or as text when it is not JSON)."""
    done = subprocess.run([CLI, *map(str, args)], capture_output=True, text=True, check=False)
    assert done.returncode == expect, done.stderr
    try:
        return json.loads(done.stdout)
    except json.JSONDecodeError:
        return done.stdout


@pytest.fixture(scope="session")
def woodford():
    import lidarscout
    return lidarscout.open(str(WOODFORD))


@pytest.fixture(scope="session")
def jmo335():
    import lidarscout
    return lidarscout.open(str(JMO335))
