"""Types of dyngen's Rust module. Every dynamics method takes one state (1-D arrays) or a batch
(2-D arrays, one state per row, batch first) and returns float64 arrays; a batch's results
have the batch size first. `n` below is `nv` (= `dof` on a fixed base)."""

from os import PathLike
from typing import Dict, List, Literal, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
from numpy.typing import ArrayLike, NDArray

__version__: str

Array = NDArray[np.float64]
Pose = Tuple[Array, Array]
Reference = Literal["local", "world", "local_world_aligned"]
Path = Union[str, PathLike]

class DyngenError(Exception):
    """The base of every error dyngen raises besides ValueError for bad arguments."""

class DescriptionError(DyngenError):
    """A description that cannot be loaded; the message is `file:line:column: item: problem`."""

    file: str
    line: Optional[int]
    column: Optional[int]
    item: Optional[str]
    problem: str

class IdentificationError(DyngenError):
    """Identification failed; `file`, `line`, `column` where the data came from a file."""

    file: Optional[str]
    line: Optional[int]
    column: Optional[str]

class CompileError(DyngenError):
    """Generating or building a compiled robot failed, or no cargo toolchain was found."""

class Robot:
    """A loaded description with its generic f64 dynamics."""

    @staticmethod
    def load(
        path: Path,
        *,
        end_effector: Optional[str] = None,
        frames: Union[None, Literal["all"], Sequence[str]] = None,
        locked_joints: Optional[Mapping[str, float]] = None,
        gravity: Optional[Sequence[float]] = None,
        snap_angles: Optional[float] = None,
        inertia: Optional[Literal["as_written", "repair", "strict"]] = None,
        floating_base: bool = False,
    ) -> Robot: ...
    name: str
    dof: int
    nq: int
    nv: int
    floating_base: bool
    joint_names: List[str]
    joint_limits: List[Optional[Tuple[float, float]]]
    frame_names: List[str]
    end_effector: str
    gravity_vector: List[float]
    parameters: List[float]
    parameter_names: List[str]
    base_parameter_names: List[str]
    base_parameter_columns: List[int]
    warnings: List[str]
    notes: List[str]
    path: Optional[str]
    def base_parameters(self, theta: Optional[Sequence[float]] = None) -> List[float]: ...
    def with_parameters(self, theta: Sequence[float]) -> Robot: ...
    def with_body_at(
        self, frame: str, mass: float, com: Sequence[float], inertia_com: ArrayLike
    ) -> Robot: ...
    # Kinematics and frames: rotation (3, 3) and translation (3,); J and J̇ (6, n); 6-vectors.
    def end_effector_pose(self, q: ArrayLike) -> Pose: ...
    def jacobian(self, q: ArrayLike) -> Array: ...
    def jacobian_dot(self, q: ArrayLike, qd: ArrayLike) -> Array: ...
    def frame_pose(self, frame: str, q: ArrayLike) -> Pose: ...
    def frame_jacobian(self, frame: str, q: ArrayLike, reference: Reference = ...) -> Array: ...
    def frame_jacobian_time_variation(
        self, frame: str, q: ArrayLike, qd: ArrayLike, reference: Reference = ...
    ) -> Array: ...
    def frame_velocity(self, frame: str, q: ArrayLike, qd: ArrayLike, reference: Reference = ...) -> Array: ...
    def frame_classical_acceleration(
        self, frame: str, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike, reference: Reference = ...
    ) -> Array: ...
    # Dynamics: D, C, D⁻¹ (n, n); g, τ, q̈ (n,); regressors (n, P) and (n, B).
    def mass_matrix(self, q: ArrayLike) -> Array: ...
    def coriolis_matrix(self, q: ArrayLike, qd: ArrayLike) -> Array: ...
    def gravity(self, q: ArrayLike) -> Array: ...
    def inverse_dynamics(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> Array: ...
    def slotine_li(self, q: ArrayLike, qd: ArrayLike, v: ArrayLike, a: ArrayLike) -> Array: ...
    def regressor(self, q: ArrayLike, qd: ArrayLike, v: ArrayLike, a: ArrayLike) -> Array: ...
    def torque_regressor(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> Array: ...
    def base_regressor(self, q: ArrayLike, qd: ArrayLike, v: ArrayLike, a: ArrayLike) -> Array: ...
    def base_torque_regressor(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> Array: ...
    def forward_dynamics(self, q: ArrayLike, qd: ArrayLike, tau: ArrayLike) -> Array: ...
    def mass_matrix_inverse(self, q: ArrayLike) -> Array: ...
    def inverse_dynamics_derivatives(self, q: ArrayLike, qd: ArrayLike, qdd: ArrayLike) -> Tuple[Array, Array]: ...
    def forward_dynamics_derivatives(self, q: ArrayLike, qd: ArrayLike, tau: ArrayLike) -> Tuple[Array, Array]: ...
    def energy_regressor(self, q: ArrayLike, qd: ArrayLike) -> Array: ...
    # Floating base only.
    def center_of_mass(self, q: ArrayLike) -> Array: ...
    def center_of_mass_jacobian(self, q: ArrayLike) -> Array: ...
    def centroidal_momentum_matrix(self, q: ArrayLike) -> Array: ...
    def centroidal_bias(self, q: ArrayLike, qd: ArrayLike) -> Array: ...
    def integrate(self, q: ArrayLike, qd: ArrayLike, dt: float) -> Array: ...
    def difference(self, q0: ArrayLike, q1: ArrayLike) -> Array: ...

Written = Tuple[List[str], List[str]]

class Identification:
    base_parameter_names: List[str]
    base_parameters: Array
    base_std_dev: Array
    base_relative_std_dev: Array
    base_covariance: Array
    joint_noise: Array
    condition_number: float
    parameter_names: List[str]
    parameters: Array
    consistent_base_parameters: Array
    consistent_std_dev: Array
    consistent_misfit: float
    consistent_compatible: bool
    written: Literal["consistent", "least_squares", "description"]
    samples_used: int
    differentiated: bool
    delay: Optional[float]
    warnings: List[str]
    notes: List[str]
    robot: Robot
    def trust(self, max_relative_std: float = 0.1) -> Tuple[List[str], Optional[str]]: ...
    def yaml(self, source: str = ...) -> str: ...
    def write(self, path: Path, source: str = ...) -> Written: ...

class Excitation:
    period: float
    condition_number: float
    random_condition_number: float
    workspace_margin: Optional[float]
    coefficients: Tuple[List[float], List[List[float]], List[List[float]]]
    def sample(self, t: ArrayLike) -> Tuple[Array, Array, Array]: ...

class Payload:
    frame: str
    mass: float
    com: List[float]
    inertia_com: List[List[float]]
    parameters: List[float]
    least_squares: Tuple[List[str], List[float], List[float]]
    made_consistent: bool
    sensor_offset: Optional[List[float]]
    samples_used: int
    warnings: List[str]
    notes: List[str]
    robot: Robot
    def yaml(self, source: str = ...) -> str: ...
    def write(self, path: Path, source: str = ...) -> Written: ...

class Library:
    """A robot's C library, loaded (what dyngen.compile returns wraps it)."""

    def __init__(self, path: Path, prefix: str) -> None: ...
    name: str
    floating_base: bool
    dof: int
    nq: int
    nv: int
    joint_names: List[str]
    frame_names: List[str]
    parameter_names: List[str]
    base_parameter_names: List[str]
    parameters: List[float]
    functions: List[str]
    path: str
    def inputs(self, name: str) -> List[str]: ...
    def evaluate(
        self, name: str, inputs: Sequence[ArrayLike], frame: Optional[int] = None
    ) -> Union[Array, Tuple[Array, ...]]: ...
    def base_parameters(self, theta: Optional[Sequence[float]] = None) -> List[float]: ...

def identify(
    robot: Robot,
    t: ArrayLike,
    q: ArrayLike,
    tau: ArrayLike,
    *,
    qd: Optional[ArrayLike] = None,
    qdd: Optional[ArrayLike] = None,
    cutoff: Optional[float] = None,
    observation: Literal["torque", "energy", "momentum"] = "torque",
    window: Optional[float] = None,
    max_delay: Optional[int] = None,
) -> Identification: ...
def excite(
    robot: Robot,
    *,
    base_frequency: Optional[float] = None,
    harmonics: Optional[int] = None,
    iterations: Optional[int] = None,
    starts: Optional[int] = None,
    samples: Optional[int] = None,
    seed: Optional[int] = None,
    acceleration_per_velocity: float = 3.0,
    boxes: Sequence[Tuple[Optional[str], Sequence[float], Sequence[float]]] = ...,
    above: Sequence[Tuple[Optional[str], Sequence[float], float]] = ...,
) -> Excitation: ...
def identify_payload(
    robot: Robot,
    t: ArrayLike,
    q: ArrayLike,
    *,
    tau: Optional[ArrayLike] = None,
    wrench: Optional[ArrayLike] = None,
    sensor_frame: Optional[str] = None,
    qd: Optional[ArrayLike] = None,
    qdd: Optional[ArrayLike] = None,
    frame: Optional[str] = None,
    data: Optional[Literal["torques", "wrench", "both"]] = None,
    refit_joint_terms: bool = False,
    cutoff: Optional[float] = None,
) -> Payload: ...
def runtime_checkout() -> Optional[str]: ...
def compile_source(robot: Robot, functions: object = None) -> Tuple[Optional[str], Optional[str], List[str], str]: ...
def write_c_library(
    robot: Robot,
    dir: Path,
    prefix: str,
    functions: object = None,
    description: Optional[Path] = None,
    runtime: Optional[Path] = None,
) -> List[str]: ...
