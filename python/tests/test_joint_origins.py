"""Joint-origin corrections (SPEC §3) reach Python as they reach the YAML:
in parameters, std and the summary, and through write_sensors unchanged."""
import numpy as np

import stac
from conftest import SOURCE

SENSORS = """mocap:
  sigma: 0.002
  markers:
    - {name: m_upper, link: upper_arm_link, position: [0.05, 0.02, 0.1]}
    - {name: m_fore, link: forearm_link, position: [0.04, -0.03, 0.2]}
    - {name: m_tool_a, link: wrist_3_link, position: [0.03, 0.04, 0.02]}
    - {name: m_tool_b, link: wrist_3_link, position: [-0.04, 0.02, 0.05]}
joint_sensors:
  - {name: p_pan, joint: shoulder_pan_joint, gain: 1.1, bias: 0.1, sigma: 0.01}
  - {name: p_lift, joint: shoulder_lift_joint, gain: 0.9, bias: -0.2, sigma: 0.01}
  - {name: p_elbow, joint: elbow_joint, gain: 1.0, bias: 0.05, sigma: 0.01}
  - {name: p_w1, joint: wrist_1_joint, gain: -1.2, bias: 0.3, sigma: 0.01}
  - {name: p_w2, joint: wrist_2_joint, gain: 1.0, bias: 0.0, sigma: 0.01}
  - {name: p_w3, joint: wrist_3_joint, gain: 0.8, bias: -0.1, sigma: 0.01}
joint_origins:
  prior_std: {xyz: 0.004, rpy: 0.02}
  joints:
    - joint: elbow_joint
      xyz: [0.001, -0.002, 0.003]
      rpy: [0.01, 0.02, -0.03]
    - joint: wrist_1_joint
      xyz: [-0.002, 0.001, 0.0]
      rpy: [0.0, -0.01, 0.02]
      fixed: [rpy]
"""


def test_origins_in_parameters_std_summary_and_written_file(tmp_path):
    robot = stac.RobotModel.from_urdf(str(SOURCE / "test" / "fixtures" / "ur5.urdf"))
    truth = stac.parse_sensors(SENSORS, robot, "truth.yaml")
    origins = truth.parameters["joint_origins"]
    assert set(origins) == {"elbow_joint", "wrist_1_joint"}
    np.testing.assert_allclose(origins["elbow_joint"]["xyz"], [0.001, -0.002, 0.003])
    np.testing.assert_allclose(origins["wrist_1_joint"]["rpy"], [0.0, -0.01, 0.02])

    log = stac.simulate(robot, truth, 600, seed=2)["log"]
    r = stac.calibrate(robot, truth, log, threads=2)
    assert set(r.parameters["joint_origins"]) == set(origins)
    sd = r.std["joint_origins"]
    assert sd["elbow_joint"]["xyz"].shape == (3,) and (sd["elbow_joint"]["xyz"] > 0).all()
    assert (sd["wrist_1_joint"]["rpy"] == 0).all(), "a held part has std 0"
    listed = {d["joint"]: d for d in r.summary["joint_origins"]}
    assert "elbow_joint" in listed
    assert set(listed["elbow_joint"]) == {"joint", "determined", "on_prior"}
    # The held rpy of wrist_1 stays what the file says.
    np.testing.assert_array_equal(r.parameters["joint_origins"]["wrist_1_joint"]["rpy"],
                                  origins["wrist_1_joint"]["rpy"])

    out = tmp_path / "calib.yaml"
    stac.write_sensors(str(out), r)
    back = stac.read_sensors(str(out), robot).parameters["joint_origins"]
    for joint, c in r.parameters["joint_origins"].items():
        np.testing.assert_allclose(back[joint]["xyz"], c["xyz"], rtol=1e-12, atol=1e-15)
        np.testing.assert_allclose(back[joint]["rpy"], c["rpy"], rtol=1e-12, atol=1e-15)
