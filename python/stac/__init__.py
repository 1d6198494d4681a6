"""STAC — Simultaneous Tracking And Calibration of a robot's kinematic sensors.

The C++ library itself, with numpy in and out: the same file formats,
checks, error messages and results as the stac_calib, stac_simulate and
stac_eval commands (SPEC.md).

    import stac
    robot = stac.RobotModel.from_urdf("data/gimbal2.urdf")
    seed = stac.read_sensors("data/gimbal2_seed.yaml", robot)
    log = stac.read_log("data/gimbal2_example.csv")
    result = stac.calibrate(robot, seed, log)
    stac.write_sensors("calibration.yaml", result)   # = stac_calib --output
    result.joint_angles                              # frames x dof, numpy
"""

from ._stac import (
    CalibrationResult,
    InputError,
    Log,
    RobotModel,
    Sensors,
    SuspectCalibrationWarning,
    calibrate,
    evaluate,
    infer_sensors,
    parse_log,
    parse_sensors,
    read_log,
    read_sensors,
    simulate,
    write_log,
    write_sensors,
)

__all__ = [
    "CalibrationResult",
    "InputError",
    "Log",
    "RobotModel",
    "Sensors",
    "SuspectCalibrationWarning",
    "calibrate",
    "evaluate",
    "infer_sensors",
    "parse_log",
    "parse_sensors",
    "read_log",
    "read_sensors",
    "simulate",
    "write_log",
    "write_sensors",
]
