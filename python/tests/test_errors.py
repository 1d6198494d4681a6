"""Every error path: a Python exception whose message is the one stac_calib
(stac_eval) prints after 'error: ' for the same input, file:line included."""
import numpy as np
import pytest

import stac
from conftest import DATA, cli_error

URDF, SEED, LOG = DATA / "gimbal2.urdf", DATA / "gimbal2_seed.yaml", DATA / "gimbal2_example.csv"


def calib_error(tmp_path, urdf=URDF, log=LOG, sensors=SEED, *options):
    return cli_error("stac_calib", "--urdf", urdf, "--log", log, "--sensors", sensors,
                     "--output", tmp_path / "out.yaml", "--quiet", *options)


def python_error(fn, *args, **kwargs):
    with pytest.raises(stac.InputError) as e:
        fn(*args, **kwargs)
    assert isinstance(e.value, ValueError)
    return e.value


def test_missing_urdf(tmp_path):
    missing = tmp_path / "missing.urdf"
    e = python_error(stac.RobotModel.from_urdf, str(missing))
    assert str(e) == calib_error(tmp_path, urdf=missing)
    assert e.file == str(missing) and e.line == 0


def test_bad_urdf_text():
    e = python_error(stac.RobotModel.from_urdf_string, "<robot name='x'><link name='a'/>",
                     source="mine.urdf")
    assert str(e).startswith("mine.urdf") and e.file == "mine.urdf"


def test_sensors_file_error_names_key_and_line(tmp_path, gimbal2):
    robot, _, _ = gimbal2
    bad = tmp_path / "bad.yaml"
    bad.write_text(SEED.read_text() + "bogus_key: 1\n")
    e = python_error(stac.read_sensors, str(bad), robot)
    assert str(e) == calib_error(tmp_path, sensors=bad)
    assert e.file == str(bad) and e.line > 0


def test_csv_error_names_line_and_column(tmp_path):
    bad = tmp_path / "bad.csv"
    lines = LOG.read_text().splitlines()
    cells = lines[5].split(",")
    cells[2] = "inf"
    lines[5] = ",".join(cells)
    bad.write_text("\n".join(lines) + "\n")
    e = python_error(stac.read_log, str(bad))
    assert str(e) == calib_error(tmp_path, log=bad)
    assert (e.line, e.column) == (6, 3)


def test_table_errors_as_the_csv_would_have_them(gimbal2):
    _, _, csv = gimbal2
    header = ["time"] + csv.columns
    table = np.column_stack([csv.time, csv.values])
    table[4, 2] = np.inf
    e = python_error(stac.Log, table, header, source="t")
    assert str(e).startswith("t:6:3: column '%s': 'inf' is not finite" % header[2])
    table[4, 2] = 0.0
    table[7, 0] = np.nan
    e = python_error(stac.Log, table, header, source="t")
    assert str(e) == "t:9:1: column 'time': the time is missing"
    e = python_error(stac.Log, table[:, :3], ["a", "b", "a"], source="t")
    assert str(e) == "t:1:3: column 'a' appears twice in the header"
    e = python_error(stac.Log, table[:, :3], ["a", "time", "t"], source="t")
    assert "two time columns" in str(e)
    with pytest.raises(ValueError, match="3 columns of values but 2 column names"):
        stac.Log(table[:, :3], ["a", "b"])
    with pytest.raises(ValueError, match="2-D"):
        stac.Log(np.zeros(3), ["a"])
    with pytest.raises(TypeError, match="column names"):
        stac.Log(np.zeros((3, 1)))


def test_log_that_does_not_fit_the_sensors(tmp_path, gimbal2):
    robot, seed, _ = gimbal2
    extra = tmp_path / "extra.csv"
    lines = LOG.read_text().splitlines()
    extra.write_text("\n".join([lines[0] + ",stray"] + [l + ",1.0" for l in lines[1:]]) + "\n")
    e = python_error(stac.calibrate, robot, seed, stac.read_log(str(extra)))
    assert str(e) == calib_error(tmp_path, log=extra)


def test_mapped_column_the_log_lacks_names_its_key_and_line(tmp_path, gimbal2):
    robot, _, log = gimbal2
    seed = tmp_path / "mapped.yaml"
    text = SEED.read_text()
    assert "  - name: neck_cyl_1\n" in text
    seed.write_text(text.replace("  - name: neck_cyl_1\n",
                                 "  - name: neck_cyl_1\n    column: no_such_column\n"))
    e = python_error(stac.calibrate, robot, stac.read_sensors(str(seed), robot), log)
    assert str(e) == calib_error(tmp_path, sensors=seed)
    assert "column" in str(e) and e.file == str(seed) and e.line > 0, str(e)


def test_sensor_without_readings(tmp_path, gimbal2):
    robot, seed, log = gimbal2
    blank = tmp_path / "blank.csv"
    lines = LOG.read_text().splitlines()
    col = lines[0].split(",").index(log.columns[0])
    rows = [lines[0]]
    for l in lines[1:]:
        cells = l.split(",")
        cells[col] = ""
        rows.append(",".join(cells))
    blank.write_text("\n".join(rows) + "\n")
    e = python_error(stac.calibrate, robot, seed, stac.read_log(str(blank)))
    assert str(e) == calib_error(tmp_path, log=blank)


def test_header_only_log(tmp_path, gimbal2):
    robot, seed, _ = gimbal2
    empty = tmp_path / "empty.csv"
    empty.write_text(LOG.read_text().splitlines()[0] + "\n")
    e = python_error(stac.calibrate, robot, seed, stac.read_log(str(empty)))
    assert str(e) == calib_error(tmp_path, log=empty)


def test_method_that_cannot_use_the_sensors_names_the_sensors_file(tmp_path, gimbal2):
    robot, seed, log = gimbal2
    e = python_error(stac.calibrate, robot, seed, log, method="classical")
    assert str(e) == calib_error(tmp_path, URDF, LOG, SEED, "--method", "classical")
    assert e.file == str(SEED)


@pytest.mark.parametrize("option, message", [
    ({"method": "bogus"}, "method='bogus': must be one of stac|joint|ekf|classical"),
    ({"q_phase": "x"}, "q_phase='x': must be one of lm-iter|lm-batch|bfgs"),
    ({"loss": "l1"}, "loss='l1': must be one of none|huber|cauchy"),
    ({"mocap_units": "cm"}, "mocap_units='cm': must be one of m|mm"),
    ({"loss_scale": -1.0}, "loss scale must be positive and finite"),
    ({"threads": -1}, "threads must be >= 0"),
    ({"max_iterations": 0}, "max_iterations must be at least 1"),
    ({"tolerance": float("nan")}, "tolerance must be a finite number >= 0"),
    ({"ekf_q_speed": 3.0}, "ekf_q_speed needs method='ekf'"),
    ({"method": "ekf", "ekf_iterations": 0}, "iterations"),
])
def test_bad_options(gimbal2, option, message):
    robot, seed, log = gimbal2
    with pytest.raises(ValueError) as e:
        stac.calibrate(robot, seed, log, **option)
    assert not isinstance(e.value, stac.InputError)
    assert message in str(e.value)


def test_progress_must_be_callable(gimbal2):
    robot, seed, log = gimbal2
    with pytest.raises(TypeError, match="progress"):
        stac.calibrate(robot, seed, log, progress=3)


def test_unwritable_output(tmp_path, gimbal2):
    robot, seed, _ = gimbal2
    target = tmp_path / "no_such_folder" / "seed.yaml"
    e = python_error(stac.write_sensors, str(target), seed)
    assert str(e).startswith(f"{target}: cannot write: ")
    assert not target.parent.exists()


def test_evaluate_groups(gimbal2):
    robot, seed, log = gimbal2
    with pytest.raises(ValueError, match="use joint: the sensors file '.*' has no joint sensors"):
        stac.evaluate(robot, seed, log, use=["joint"])
    with pytest.raises(ValueError, match="must be marker, joint or tendon"):
        stac.evaluate(robot, seed, log, use=["pots"])
    with pytest.raises(ValueError, match="use: names 'tendon' twice"):
        stac.evaluate(robot, seed, log, use=["tendon", "tendon"])


def test_truth_that_does_not_match(tmp_path, gimbal2):
    robot, seed, log = gimbal2
    hand = stac.RobotModel.from_urdf(str(DATA / "hand24.urdf"))
    other = stac.read_sensors(str(DATA / "hand24_truth.yaml"), hand)
    with pytest.raises(stac.InputError):
        stac.evaluate(robot, seed, log, use=["tendon"], truth=other)


def test_other_errors_are_runtime_or_type_errors(gimbal2):
    robot, seed, log = gimbal2
    with pytest.raises(TypeError):
        stac.calibrate(robot, log, seed)
