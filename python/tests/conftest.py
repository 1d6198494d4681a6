"""Shared fixtures: the bundled data, the built apps, logs they simulate.

ctest sets STAC_APPS_DIR, STAC_DATA_DIR and PYTHONPATH (python/CMakeLists.txt);
run by hand: PYTHONPATH=build/python STAC_APPS_DIR=build/apps python3 -m pytest python/tests
"""
import os
import pathlib
import re
import subprocess

import pytest

import stac

SOURCE = pathlib.Path(os.environ.get("STAC_SOURCE_DIR", pathlib.Path(__file__).parents[2]))
DATA = pathlib.Path(os.environ.get("STAC_DATA_DIR", SOURCE / "data"))
APPS = pathlib.Path(os.environ.get("STAC_APPS_DIR", SOURCE / "build" / "apps"))


def app(name):
    path = APPS / name
    if not path.exists():
        pytest.skip(f"{path} not built")
    return str(path)


def run_app(name, *args):
    """Runs a stac_* command; returns (exit code, stdout, stderr)."""
    r = subprocess.run([app(name), *map(str, args)], capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


def cli_error(name, *args):
    """The message a command prints after '<name>: error: ' (it must fail with exit 2)."""
    code, _, err = run_app(name, *args)
    assert code == 2, err
    m = re.search(rf"^{name}: error: (.*)$", err, re.M)
    assert m, err
    return m.group(1)


def without_wall_time(text):
    """The calibration YAML with its measured wall_time line blanked."""
    return re.sub(r"(?m)^(  wall_time: ).*$", r"\1-", text)


@pytest.fixture(scope="session")
def data():
    return DATA


@pytest.fixture(scope="session")
def gimbal2():
    robot = stac.RobotModel.from_urdf(str(DATA / "gimbal2.urdf"))
    return robot, stac.read_sensors(str(DATA / "gimbal2_seed.yaml"), robot), stac.read_log(
        str(DATA / "gimbal2_example.csv"))


@pytest.fixture(scope="session")
def hand24_log(tmp_path_factory):
    """300 frames of hand24 from its truth, made by stac_simulate."""
    path = tmp_path_factory.mktemp("hand24") / "hand24.csv"
    code, _, err = run_app("stac_simulate", "--urdf", DATA / "hand24.urdf", "--sensors",
                           DATA / "hand24_truth.yaml", "--frames", 300, "--log", path,
                           "--seed", 3)
    assert code == 0, err
    return path


@pytest.fixture(scope="session")
def hand24(hand24_log):
    robot = stac.RobotModel.from_urdf(str(DATA / "hand24.urdf"))
    return robot, stac.read_sensors(str(DATA / "hand24_seed.yaml"), robot), stac.read_log(
        str(hand24_log))
