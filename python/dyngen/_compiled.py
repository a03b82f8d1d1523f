"""A robot's compiled library behind the methods of dyngen.Robot."""


class CompiledRobot:
    """A robot's generated code, compiled as its C library and loaded (dyngen.compile): the
    dynamics methods of dyngen.Robot, with the same arguments and result shapes, evaluated by
    the generated functions (a batch without the GIL, in one call into the library).

    A method of a group the robot was compiled without raises ValueError naming it.
    `evaluate(name, *arrays, frame=None)` calls any function of the library's table by name
    (`functions` lists them), e.g. "kinematics" or "regressor_products".
    """

    def __init__(self, library, robot):
        self._library = library
        #: The dyngen.Robot the code was generated from (its generic dynamics, names, limits).
        self.robot = robot

    def __repr__(self):
        library = self._library
        return (
            f"<dyngen.CompiledRobot '{library.name}': {library.dof} DOF, "
            f"{len(library.functions)} functions, {library.path}>"
        )

    name = property(lambda self: self._library.name, doc="The robot's name.")
    dof = property(lambda self: self._library.dof, doc="Number of joint coordinates.")
    nq = property(lambda self: self._library.nq, doc="Length of the configuration q.")
    nv = property(lambda self: self._library.nv, doc="Length of velocities and forces.")
    floating_base = property(lambda self: self._library.floating_base, doc="Whether the base flies free.")
    joint_names = property(lambda self: self._library.joint_names, doc="The coordinates' joints.")
    frame_names = property(lambda self: self._library.frame_names, doc="The named frames, end-effector first.")
    parameter_names = property(lambda self: self._library.parameter_names, doc="Names of θ's entries.")
    base_parameter_names = property(lambda self: self._library.base_parameter_names, doc="Names of θ_b's entries.")
    parameters = property(lambda self: self._library.parameters, doc="The description's θ.")
    functions = property(lambda self: self._library.functions, doc="The library's function table, by name.")
    path = property(lambda self: self._library.path, doc="The shared library loaded.")

    def base_parameters(self, theta=None):
        """θ_b of `theta` (default: the description's θ)."""
        return self._library.base_parameters(theta)

    def evaluate(self, name, *arrays, frame=None):
        """Function `name` of the library's table on `arrays` (one state or a batch each)."""
        index = None if frame is None else self._frame(frame)
        return self._library.evaluate(name, list(arrays), index)

    def _frame(self, frame):
        try:
            return self._library.frame_names.index(frame)
        except ValueError:
            raise ValueError(
                f"unknown frame '{frame}': the robot's frames are {', '.join(self._library.frame_names)}"
            ) from None

    def _reference(self, name, reference):
        if reference not in ("local", "world", "local_world_aligned"):
            raise ValueError(
                f"unknown reference frame '{reference}': expected \"local\", \"world\" or \"local_world_aligned\""
            )
        return f"{name}_{reference}"

    def end_effector_pose(self, q):
        """End-effector pose: (rotation (3, 3), translation (3,))."""
        return self.evaluate("forward_kinematics", q)

    def jacobian(self, q):
        """J(q) of the end-effector, 6 × nv, LOCAL_WORLD_ALIGNED."""
        return self.evaluate("jacobian", q)

    def jacobian_dot(self, q, qd):
        """J̇(q, q̇) of the end-effector."""
        return self.evaluate("jacobian_dot", q, qd)

    def frame_pose(self, frame, q):
        """The pose of frame `frame`: (rotation (3, 3), translation (3,))."""
        return self.evaluate("frame_pose", q, frame=frame)

    def frame_jacobian(self, frame, q, reference="local_world_aligned"):
        """J of frame `frame` (6 × nv) in `reference`."""
        return self.evaluate(self._reference("frame_jacobian", reference), q, frame=frame)

    def frame_jacobian_time_variation(self, frame, q, qd, reference="local_world_aligned"):
        """J̇ of frame `frame` in `reference`."""
        return self.evaluate(self._reference("frame_jacobian_time_variation", reference), q, qd, frame=frame)

    def frame_velocity(self, frame, q, qd, reference="local_world_aligned"):
        """J q̇ of frame `frame` in `reference` (6,)."""
        return self.evaluate(self._reference("frame_velocity", reference), q, qd, frame=frame)

    def frame_classical_acceleration(self, frame, q, qd, qdd, reference="local_world_aligned"):
        """The classical acceleration of frame `frame` in `reference` (6,)."""
        return self.evaluate(self._reference("frame_classical_acceleration", reference), q, qd, qdd, frame=frame)

    def mass_matrix(self, q):
        """D(q), nv × nv."""
        return self.evaluate("mass_matrix", q)

    def coriolis_matrix(self, q, qd):
        """C(q, q̇), nv × nv."""
        return self.evaluate("coriolis_matrix", q, qd)

    def gravity(self, q):
        """g(q), (nv,)."""
        return self.evaluate("gravity", q)

    def inverse_dynamics(self, q, qd, qdd):
        """τ = D q̈ + C q̇ + g, (nv,)."""
        return self.evaluate("inverse_dynamics", q, qd, qdd)

    def slotine_li(self, q, qd, v, a):
        """D a + C(q, q̇) v + g, (nv,)."""
        return self.evaluate("slotine_li", q, qd, v, a)

    def regressor(self, q, qd, v, a):
        """Y(q, q̇, v, a), nv × P."""
        return self.evaluate("regressor", q, qd, v, a)

    def torque_regressor(self, q, qd, qdd):
        """Y(q, q̇, q̇, q̈), nv × P."""
        return self.evaluate("torque_regressor", q, qd, qdd)

    def base_regressor(self, q, qd, v, a):
        """Y_b(q, q̇, v, a), nv × B."""
        return self.evaluate("base_regressor", q, qd, v, a)

    def base_torque_regressor(self, q, qd, qdd):
        """Y_b(q, q̇, q̇, q̈), nv × B."""
        return self.evaluate("base_torque_regressor", q, qd, qdd)

    def forward_dynamics(self, q, qd, tau):
        """q̈ = D⁻¹ (τ − C q̇ − g), (nv,)."""
        return self.evaluate("forward_dynamics", q, qd, tau)

    def mass_matrix_inverse(self, q):
        """D(q)⁻¹, nv × nv."""
        return self.evaluate("mass_matrix_inverse", q)

    def inverse_dynamics_derivatives(self, q, qd, qdd):
        """(∂τ/∂q, ∂τ/∂q̇), nv × nv each."""
        return self.evaluate("inverse_dynamics_derivatives", q, qd, qdd)

    def forward_dynamics_derivatives(self, q, qd, tau):
        """(∂q̈/∂q, ∂q̈/∂q̇), nv × nv each."""
        return self.evaluate("forward_dynamics_derivatives", q, qd, tau)

    def center_of_mass(self, q):
        """Centre of mass in the world (3,) (floating base)."""
        return self.evaluate("center_of_mass", q)

    def centroidal_momentum_matrix(self, q):
        """A_g(q), 6 × nv (floating base)."""
        return self.evaluate("centroidal_momentum_matrix", q)

    def centroidal_bias(self, q, qd):
        """Ȧ_g ν, (6,) (floating base)."""
        return self.evaluate("centroidal_bias", q, qd)
