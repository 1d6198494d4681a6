"""`pip install .` from the repository root into a fresh virtual environment
of Debian's python3 (numpy from python3-numpy through --system-site-packages),
then `import stac` from outside the source tree. Long (label `long`): pip
builds the library again, minutes on two cores the first time (its build
folder, build/pip/, is kept: a second run rebuilds only what changed)."""
import os
import pathlib
import subprocess

from conftest import DATA, SOURCE


def test_pip_install_then_import(tmp_path):
    venv = tmp_path / "venv"
    subprocess.run(["/usr/bin/python3", "-m", "venv", "--system-site-packages", str(venv)],
                   check=True)
    python = str(venv / "bin" / "python")
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    r = subprocess.run([python, "-m", "pip", "install", "--no-input", str(SOURCE)], cwd=tmp_path,
                       env=env, capture_output=True, text=True)
    assert r.returncode == 0, r.stdout[-3000:] + r.stderr[-3000:]
    script = (
        "import numpy, stac\n"
        f"robot = stac.RobotModel.from_urdf({str(DATA / 'gimbal2.urdf')!r})\n"
        f"seed = stac.read_sensors({str(DATA / 'gimbal2_seed.yaml')!r}, robot)\n"
        f"log = stac.read_log({str(DATA / 'gimbal2_example.csv')!r})\n"
        "r = stac.calibrate(robot, seed, log, max_iterations=5)\n"
        "print(stac.__file__)\nprint(numpy.__file__)\nprint(r.joint_angles.shape)\n")
    r = subprocess.run([python, "-c", script], cwd=tmp_path, env=env, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
    module, numpy_file, shape = r.stdout.splitlines()
    assert pathlib.Path(module).is_relative_to(venv), module
    assert numpy_file.startswith("/usr/lib/python3/dist-packages/"), numpy_file
    assert shape == "(300, 2)"
