"""The progress callback: once per iteration, and a clean stop from it (an
exception it raises, or Ctrl-C) in every method; the GIL released while the
library works."""
import os
import signal
import threading
import time
import warnings

import pytest

import stac


class Stop(Exception):
    pass


def test_called_once_per_iteration(gimbal2):
    robot, seed, log = gimbal2
    reports = []
    r = stac.calibrate(robot, seed, log, progress=reports.append)
    stages = [p["stage"] for p in reports]
    assert stages[0] == "init" and reports[0]["iteration"] == 0
    stac_reports = [p for p in reports if p["stage"] == "stac"]
    assert [p["iteration"] for p in stac_reports] == list(range(1, r.summary["iterations"] + 1))
    assert len(reports) == 1 + r.summary["iterations"]
    elapsed = [p["elapsed"] for p in reports]
    assert elapsed == sorted(elapsed)
    assert set(reports[-1]["rms"]) == {"marker", "tendon"}
    assert all(isinstance(p["cost"], float) for p in reports)


def test_progress_does_not_change_the_result(gimbal2):
    robot, seed, log = gimbal2
    quiet = stac.calibrate(robot, seed, log, threads=1)
    loud = stac.calibrate(robot, seed, log, threads=1, progress=lambda p: None)
    strip = lambda y: "\n".join(l for l in y.splitlines() if "wall_time" not in l)
    assert strip(quiet.to_yaml()) == strip(loud.to_yaml())


METHODS = [("stac", "gimbal2"), ("joint", "gimbal2"), ("ekf", "gimbal2"), ("classical", "hand24")]


def second_call_does(action):
    """A progress callback that runs `action` at its second call, and its calls."""
    calls = []

    def progress(p):
        calls.append(p)
        if len(calls) == 2:
            action(p)

    return progress, calls


def stop(p):
    raise Stop(f"stopped at {p['stage']} {p['iteration']}")


@pytest.mark.parametrize("method, robot_name", METHODS)
def test_an_exception_from_the_callback_stops_every_method(method, robot_name, request):
    robot, seed, log = request.getfixturevalue(robot_name)
    progress, calls = second_call_does(stop)
    with pytest.raises(Stop, match="stopped at"):
        stac.calibrate(robot, seed, log, method=method, progress=progress)
    assert len(calls) == 2, "no call after the one that raised"
    # The library is left clean: the same run again completes.
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", stac.SuspectCalibrationWarning)
        again = stac.calibrate(robot, seed, log, method=method, max_iterations=3)
    assert again.summary["method"] == method


@pytest.mark.parametrize("method, robot_name", METHODS)
def test_ctrl_c_stops_every_method(method, robot_name, request):
    robot, seed, log = request.getfixturevalue(robot_name)
    # As Ctrl-C does: SIGINT to the process, while the callback runs.
    progress, calls = second_call_does(lambda p: os.kill(os.getpid(), signal.SIGINT))
    with pytest.raises(KeyboardInterrupt):
        stac.calibrate(robot, seed, log, method=method, progress=progress)
    assert len(calls) == 2


def test_ctrl_c_without_a_callback(hand24):
    robot, seed, log = hand24
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            # Long enough that the signal comes during the solve.
            stac.calibrate(robot, seed, log, method="stac", tolerance=0.0, max_iterations=10000,
                           threads=1)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 60


def test_the_gil_is_released_during_the_solve(hand24):
    robot, seed, log = hand24
    done = threading.Event()
    box = {}

    def work():
        box["result"] = stac.calibrate(robot, seed, log, threads=1, max_iterations=20)
        done.set()

    worker = threading.Thread(target=work)
    ticks = 0
    start = time.monotonic()
    worker.start()
    while not done.is_set():
        ticks += 1
        time.sleep(0.005)
    worker.join()
    seconds = time.monotonic() - start
    # Without a progress callback the library takes the GIL only for a
    # moment per iteration (to look for Ctrl-C): holding it for the whole
    # solve would leave this thread a tick or two.
    assert ticks > max(10, 5 * seconds), (ticks, seconds)
    assert box["result"].joint_angles.shape == (log.frames, robot.dof)
