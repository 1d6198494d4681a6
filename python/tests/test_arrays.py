"""numpy in and out: shapes, dtypes, and where the data is shared or copied.

Views (no copy): Log.values, Log.time, CalibrationResult.joint_angles (over
the object's own storage, read-only, keeping the object alive); simulate's
and evaluate's joint_angles (the library's matrix moved under the array).
One copy: a Log made from an array or DataFrame (the log owns its values),
and small vectors built on each access (parameters, std, limits)."""
import gc

import numpy as np
import pytest

import stac
from conftest import DATA, SOURCE


def test_log_values_are_a_read_only_view(gimbal2):
    _, _, log = gimbal2
    v = log.values
    assert v.dtype == np.float64 and v.shape == (300, len(log.columns))
    assert v.flags.c_contiguous and not v.flags.writeable and not v.flags.owndata
    assert np.shares_memory(v, log.values), "each access views the same storage"
    with pytest.raises(ValueError):
        v[0, 0] = 1.0
    assert log.time.shape == (300,) and np.shares_memory(log.time, log.time)
    assert log.time_name == "time" and "time" not in log.columns


def test_a_view_keeps_its_log_alive(data):
    v = stac.read_log(str(data / "gimbal2_example.csv")).values
    gc.collect()
    expected = np.array(stac.read_log(str(data / "gimbal2_example.csv")).values)
    np.testing.assert_array_equal(v, expected)


def test_log_from_array_copies_once_and_matches_the_csv(gimbal2, data):
    _, _, csv = gimbal2
    table = np.column_stack([csv.time, csv.values])
    header = ["time"] + csv.columns
    log = stac.Log(table, header, source="table")
    assert log.columns == csv.columns and log.time_name == "time"
    np.testing.assert_array_equal(log.values, csv.values)
    assert not np.shares_memory(log.values, table), "the log owns its values"
    table[0, 1] = 123.0
    assert log.values[0, 0] != 123.0
    # Any numeric dtype and layout converts (another copy first).
    f32 = stac.Log(np.asfortranarray(table.astype(np.float32)), header)
    np.testing.assert_allclose(f32.values[1:], csv.values[1:], rtol=1e-6)


class FakeDataFrame:
    """What Log takes from a pandas DataFrame: .columns and .to_numpy()."""
    def __init__(self, values, columns):
        self._values, self.columns = values, columns

    def to_numpy(self, dtype=None):
        return self._values.astype(dtype) if dtype else self._values


def test_log_from_a_dataframe(gimbal2):
    _, _, csv = gimbal2
    df = FakeDataFrame(np.column_stack([csv.time, csv.values]), ["time"] + csv.columns)
    log = stac.Log(df)
    assert log.columns == csv.columns and log.source == "<table>"
    np.testing.assert_array_equal(log.values, csv.values)


def test_log_from_pandas(gimbal2):
    pd = pytest.importorskip("pandas")
    _, _, csv = gimbal2
    df = pd.DataFrame(csv.values, columns=csv.columns)
    df.insert(0, "time", csv.time)
    np.testing.assert_array_equal(stac.Log(df).values, csv.values)


def test_calibration_outputs(gimbal2):
    robot, seed, log = gimbal2
    r = stac.calibrate(robot, seed, log, threads=1)
    q = r.joint_angles
    assert q.shape == (log.frames, robot.dof) and q.dtype == np.float64
    assert q.flags.c_contiguous and not q.flags.writeable
    assert np.shares_memory(q, r.joint_angles), "a view of the result's matrix"
    del r
    gc.collect()
    assert np.isfinite(q).all(), "the view keeps the result alive"

    r = stac.calibrate(robot, seed, log, threads=1)
    p = r.parameters
    assert p["mocap"]["translation"].shape == (3,) and p["mocap"]["quaternion"].shape == (4,)
    assert all(v.shape == (3,) and v.dtype == np.float64 for v in p["markers"].values())
    assert set(p["tendon_sensors"]) == set(seed.tendon_sensors)
    assert all(isinstance(gb["gain"], float) for gb in p["tendon_sensors"].values())
    s = r.std
    fixed = [m for m, v in s["markers"].items() if not v.any()]
    assert fixed, "the seed's fixed markers have std 0"
    res = r.residuals
    assert set(res["markers"]) == set(seed.markers)
    assert all(v["count"] > 0 and v["rms"] >= v["mae"] > 0 for v in res["markers"].values())
    summary = r.summary
    assert summary["frames"] == log.frames and summary["method"] == "stac"
    assert set(summary["sigma"]) == {"marker", "tendon"}
    assert r.verdict == [] and r.ok and r.unidentifiable == []
    assert isinstance(r.report, str) and "stac" in r.report


def test_result_is_close_to_the_truth(gimbal2, data):
    robot, seed, log = gimbal2
    truth = stac.read_sensors(str(data / "gimbal2_truth.yaml"), robot).parameters
    r = stac.calibrate(robot, seed, log)
    for name, gb in r.parameters["tendon_sensors"].items():
        sd = r.std["tendon_sensors"][name]
        assert abs(gb["gain"] - truth["tendon_sensors"][name]["gain"]) < 5 * sd["gain"] + 1e-3
        assert abs(gb["bias"] - truth["tendon_sensors"][name]["bias"]) < 5 * sd["bias"] + 1e-3


def test_robot_arrays(gimbal2):
    robot, _, _ = gimbal2
    assert robot.dof == 2 and len(robot.joint_names) == 2
    lo, hi = robot.lower_limits, robot.upper_limits
    assert lo.shape == hi.shape == (2,) and (lo < hi).all()


def test_ekf_initial_q_takes_an_array(gimbal2):
    robot, seed, log = gimbal2
    # From the paper's seeding the EKF fails its checks (README): a warning.
    with pytest.warns(stac.SuspectCalibrationWarning, match="failed its own checks"):
        r = stac.calibrate(robot, seed, log, method="ekf", ekf_initial_q=np.zeros(robot.dof),
                           threads=1)
    assert r.verdict and not r.ok
    assert r.joint_angles.shape == (log.frames, robot.dof)
    with pytest.raises(ValueError, match="ekf_initial_q: expected 2 joint angles"):
        stac.calibrate(robot, seed, log, method="ekf", ekf_initial_q=[0.0])


def test_paths_may_be_pathlib(tmp_path, data):
    robot = stac.RobotModel.from_urdf(data / "gimbal2.urdf")
    seed = stac.read_sensors(data / "gimbal2_seed.yaml", robot)
    log = stac.read_log(data / "gimbal2_example.csv")
    stac.write_sensors(tmp_path / "seed.yaml", seed)
    stac.write_log(tmp_path / "log.csv", log)
    assert (tmp_path / "seed.yaml").read_text() == seed.to_yaml()
    assert (tmp_path / "log.csv").read_bytes() == (data / "gimbal2_example.csv").read_bytes()


def test_unidentifiable_directions_carry_their_kind():
    """The real TIAGo recording, a marker per point-1 columns and every gain
    and bias free: three exact gauges, each listed with kind null_direction."""
    tiago = SOURCE.resolve().parent / "shared" / "realdata" / "tiago"
    if not tiago.is_dir():
        pytest.skip("no ../shared/realdata/tiago")
    raw = np.genfromtxt(tiago / "qualisys_2021-11-30_static_postures.csv", delimiter=",",
                        names=True)
    joints = ["torso_lift_joint"] + ["arm_%d_joint" % i for i in range(1, 8)]
    columns = ["p1@wrist_ft_tool_link." + a for a in "xyz"] + joints
    log = stac.Log(np.column_stack([raw[c] for c in ["x1", "y1", "z1"] + joints]), columns)
    robot = stac.RobotModel.from_urdf(tiago / "tiago_48_schunk.urdf")
    r = stac.calibrate(robot, stac.infer_sensors(log, robot), log, threads=1)
    assert r.ok, r.verdict
    assert len(r.unidentifiable) == 3
    assert {u["kind"] for u in r.unidentifiable} == {"null_direction"}
    biases = {p for u in r.unidentifiable for p in u["parameters"] if p.endswith(".bias")}
    assert biases == {"joint_sensors.%s.bias" % j
                      for j in ("torso_lift_joint", "arm_1_joint", "arm_7_joint")}
