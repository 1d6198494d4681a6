# Type stubs for the `stac` package (the extension stac._stac).
from os import PathLike
from typing import Any, Callable, Dict, List, Optional, Sequence, TypedDict, Union, overload

import numpy as np
import numpy.typing as npt

_Path = Union[str, "PathLike[str]"]
_Array = npt.NDArray[np.float64]

class InputError(ValueError):
    """Bad input: str(e) starts with 'file:line:column:' as stac_calib prints it."""
    file: str
    line: int    # 1-based; 0 when not applicable
    column: int  # 1-based; 0 when not applicable

class SuspectCalibrationWarning(UserWarning):
    """The calibration failed its own checks: result.verdict says why."""

class RobotModel:
    """A robot's kinematics from a URDF, never changed once loaded."""
    @staticmethod
    def from_urdf(path: _Path) -> RobotModel: ...
    @staticmethod
    def from_urdf_string(urdf: str, source: str = "<string>") -> RobotModel: ...
    @property
    def name(self) -> str: ...
    @property
    def source(self) -> str: ...
    @property
    def dof(self) -> int: ...
    @property
    def joint_names(self) -> List[str]:
        """The joints of q, in q order (the columns of joint_angles)."""
    @property
    def link_names(self) -> List[str]: ...
    @property
    def lower_limits(self) -> _Array: ...
    @property
    def upper_limits(self) -> _Array: ...
    @property
    def urdf(self) -> str: ...

class _GainBias(TypedDict):
    gain: float
    bias: float

class _Origin(TypedDict):
    xyz: _Array
    rpy: _Array

class Parameters(TypedDict):
    """θ: 'mocap' has 'translation', 'rpy', 'quaternion' ([w, x, y, z]) when there are markers;
    'joint_origins' the corrections of the joints the sensors file names (SPEC §3)."""
    mocap: Dict[str, _Array]
    markers: Dict[str, _Array]
    joint_sensors: Dict[str, _GainBias]
    tendon_sensors: Dict[str, _GainBias]
    joint_origins: Dict[str, _Origin]

class Sensors:
    """Sensors and their parameters θ: a seed, or a calibration read back."""
    @property
    def source(self) -> str: ...
    @property
    def markers(self) -> List[str]: ...
    @property
    def joint_sensors(self) -> List[str]: ...
    @property
    def tendon_sensors(self) -> List[str]: ...
    @property
    def parameters(self) -> Parameters: ...
    @property
    def sigma(self) -> Dict[str, float]: ...
    def to_yaml(self) -> str: ...

class Log:
    """A synchronized log: frames x columns, NaN = missing."""
    def __init__(self, data: Any, columns: Optional[Sequence[str]] = None,
                 source: str = "<table>") -> None:
        """From a 2-D array and its column names (a time column among them), or a pandas
        DataFrame. One copy into the log. Errors name `source`, line (header = 1) and column."""
    @property
    def source(self) -> str: ...
    @property
    def columns(self) -> List[str]: ...
    @property
    def time_name(self) -> str: ...
    @property
    def frames(self) -> int: ...
    @property
    def values(self) -> _Array:
        """frames x columns, a read-only view of the log's data (no copy)."""
    @property
    def time(self) -> Optional[_Array]:
        """The time column, a read-only view, or None."""
    def __len__(self) -> int: ...

class _Residual(TypedDict):
    rms: float
    mae: float
    count: int

class _Unidentifiable(TypedDict):
    parameters: List[str]
    reason: str
    kind: str  # null_direction, weak, modulo_turn, still_joint or mirror

class Summary(TypedDict):
    method: str
    q_phase: str
    iterations: int
    converged: bool
    initial_cost: float
    final_cost: float
    frames: int
    wall_time: float
    sigma: Dict[str, float]        # per group: 'marker', 'joint', 'tendon'
    rms_before: Dict[str, float]
    rms_after: Dict[str, float]
    unidentifiable: List[_Unidentifiable]
    downweighted: List[Dict[str, Any]]
    joint_origins: List[Dict[str, Any]]  # per corrected joint: 'joint', 'determined', 'on_prior'
    spikes_set_aside: Dict[str, int]  # per group, before the fit (robust loss only)
    verdict: List[str]

class Progress(TypedDict):
    iteration: int
    stage: str   # 'init', 'seed', 'stac', 'joint', 'ekf', 'classical'
    cost: float
    rms: Dict[str, float]
    elapsed: float

class CalibrationResult:
    @property
    def parameters(self) -> Parameters: ...
    @property
    def std(self) -> Dict[str, Any]:
        """Like parameters ('mocap': 'translation', 'rotation'); inf: undetermined, 0: fixed."""
    @property
    def sigma(self) -> Dict[str, float]: ...
    @property
    def residuals(self) -> Dict[str, Dict[str, _Residual]]: ...
    @property
    def joint_angles(self) -> _Array:
        """frames x dof, a read-only view of the result's own matrix (no copy)."""
    @property
    def summary(self) -> Summary: ...
    @property
    def verdict(self) -> List[str]:
        """Why the result failed its own checks; [] when it passed."""
    @property
    def ok(self) -> bool: ...
    @property
    def unidentifiable(self) -> List[_Unidentifiable]: ...
    @property
    def sensors(self) -> Sensors: ...
    @property
    def report(self) -> str: ...
    def to_yaml(self) -> str: ...

def read_sensors(path: _Path, robot: RobotModel) -> Sensors: ...
def parse_sensors(text: str, robot: RobotModel, source: str = "<string>") -> Sensors: ...
def infer_sensors(log: Log, robot: RobotModel) -> Sensors: ...
@overload
def write_sensors(path: _Path, sensors: Sensors) -> None: ...
@overload
def write_sensors(path: _Path, result: CalibrationResult) -> None:
    """Exactly what stac_calib --output writes."""
def read_log(path: _Path) -> Log: ...
def parse_log(text: str, source: str = "<string>") -> Log: ...
def write_log(path: _Path, log: Log) -> None: ...

def calibrate(
    robot: RobotModel,
    sensors: Sensors,
    log: Log,
    *,
    method: str = "stac",          # 'stac' | 'joint' | 'ekf' | 'classical'
    q_phase: str = "lm-iter",      # 'lm-iter' | 'lm-batch' | 'bfgs'
    max_iterations: int = 200,
    tolerance: float = 1e-7,
    threads: int = 0,              # 0: all cores
    loss: str = "none",            # 'none' | 'huber' | 'cauchy'
    loss_scale: float = 3.0,
    adapt_variance: bool = True,
    mocap_units: str = "m",        # 'm' | 'mm'
    progress: Optional[Callable[[Progress], Any]] = None,
    ekf_initial_q: Optional[npt.ArrayLike] = None,
    ekf_q_speed: Optional[float] = None,
    ekf_iterations: Optional[int] = None,
    ekf_theta_std: Optional[float] = None,
) -> CalibrationResult:
    """Calibrates as stac_calib does; the GIL is released while it runs.

    progress(dict) is called once per iteration; an exception it raises, or
    Ctrl-C, stops the run and propagates."""

class _Simulation(TypedDict):
    log: Log
    joint_angles: _Array
    outliers: List[Dict[str, Any]]

def simulate(robot: RobotModel, truth: Sensors, frames: int, *, seed: int = 1,
             rate: float = 100.0, noise_scale: float = 1.0, dropout: float = 0.0,
             outliers: float = 0.0) -> _Simulation: ...

def evaluate(robot: RobotModel, sensors: Sensors, log: Log, *, use: Sequence[str],
             predict: Optional[Sequence[str]] = None, truth: Optional[Sensors] = None,
             threads: int = 0, mocap_units: str = "m") -> Dict[str, Any]:
    """stac_eval's --json numbers as a dict, plus 'report' and 'joint_angles'."""
