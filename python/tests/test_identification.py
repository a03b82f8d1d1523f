"""Identification from arrays: a simulated data set recovers the truth as the Rust tests do
(noise-free torques with exact derivatives give the true base parameters to 1e-8), the
identified robot written as YAML and URDF loads back, payloads, and bad data."""

import numpy as np
import pytest

import dyngen
from conftest import REPO

ARM7 = REPO / "robots" / "arm7.yaml"
PAYLOAD = dict(mass=1.5, com=[0.01, -0.02, 0.05], inertia_com=np.diag([2e-3, 3e-3, 1e-3]))


@pytest.fixture(scope="module")
def arm7():
    return dyngen.Robot.load(ARM7)


@pytest.fixture(scope="module")
def excitation(arm7):
    return dyngen.excite(arm7, harmonics=3, iterations=10, starts=2, samples=40, seed=3)


@pytest.fixture(scope="module")
def measured(arm7, excitation):
    """The arm carrying a payload its description lacks, along the excitation (10 s, 50 Hz)."""
    truth = arm7.with_body_at(arm7.end_effector, **PAYLOAD)
    t = np.arange(500) / 50.0
    q, qd, qdd = excitation.sample(t)
    return truth, t, q, qd, qdd, truth.inverse_dynamics(q, qd, qdd)


def test_the_excitation_is_better_conditioned_than_random_and_periodic(arm7, excitation):
    assert excitation.condition_number < excitation.random_condition_number
    q0, qd0, _ = excitation.sample([0.0])
    q1, qd1, _ = excitation.sample([excitation.period])
    np.testing.assert_allclose(q1, q0, atol=1e-9)
    np.testing.assert_allclose(qd1, qd0, atol=1e-9)
    offsets, a, b = excitation.coefficients
    assert len(offsets) == arm7.dof and np.shape(a) == (arm7.dof, 3) == np.shape(b)


def test_noise_free_identification_recovers_the_true_base_parameters(arm7, measured):
    truth, t, q, qd, qdd, tau = measured
    result = dyngen.identify(arm7, t, q, tau, qd=qd, qdd=qdd)
    # Base parameters depend on the kinematics only: the truth's are the description's.
    expected = np.array(truth.base_parameters())
    assert result.base_parameter_names == arm7.base_parameter_names
    scale = np.abs(expected).max()
    error = np.abs(result.base_parameters - expected) / np.maximum(np.abs(expected), 1e-3 * scale)
    assert error.max() <= 1e-8, f"{result.base_parameter_names[error.argmax()]}: {error.max():.2e}"
    assert not result.differentiated and result.samples_used == len(t)
    assert result.written == "consistent" and result.consistent_compatible
    assert result.joint_noise.shape == (arm7.dof,)
    assert result.base_covariance.shape == (len(expected),) * 2
    # The identified robot's torques are the truth's.
    np.testing.assert_allclose(result.robot.inverse_dynamics(q, qd, qdd), tau, rtol=1e-6, atol=1e-6 * np.abs(tau).max())


def test_positions_only_are_differentiated_and_the_description_loads_back(arm7, measured, tmp_path):
    truth, t, q, qd, qdd, tau = measured
    rng = np.random.default_rng(1)
    noisy = tau + 0.01 * np.abs(tau).max(axis=0) * rng.standard_normal(tau.shape)
    result = dyngen.identify(arm7, t, q, noisy, cutoff=5.0)
    assert result.differentiated and result.samples_used < len(t)
    flagged, untrusted = result.trust(0.1)
    assert untrusted is None and len(flagged) < len(result.base_parameter_names)
    files, warnings = result.write(tmp_path / "identified.yaml")
    loaded = dyngen.Robot.load(files[0])
    np.testing.assert_allclose(loaded.parameters, result.parameters, rtol=1e-12, atol=1e-15)
    urdf_files, _ = result.write(tmp_path / "identified.urdf")
    through_urdf = dyngen.Robot.load(urdf_files[-1])
    np.testing.assert_allclose(
        through_urdf.mass_matrix(q[::50]), loaded.mass_matrix(q[::50]), rtol=1e-12, atol=1e-12
    )
    with pytest.raises(ValueError, match="expected a .yaml, .yml or .urdf"):
        result.write(tmp_path / "identified.txt")


def test_a_payload_from_torques_is_the_body_added(arm7, measured):
    truth, t, q, qd, qdd, tau = measured
    payload = dyngen.identify_payload(arm7, t, q, tau=tau, qd=qd, qdd=qdd)
    assert payload.frame == arm7.end_effector
    assert payload.mass == pytest.approx(PAYLOAD["mass"], rel=1e-6)
    np.testing.assert_allclose(payload.com, PAYLOAD["com"], atol=1e-6)
    # The consistent payload is a least-squares body: its inertias hold to the noise-free
    # data's conditioning, 1e-5 of the largest parameter.
    expected = np.array(truth.parameters)
    np.testing.assert_allclose(payload.robot.parameters, expected, rtol=0, atol=1e-5 * np.abs(expected).max())


def test_bad_data_is_refused_naming_argument_and_sample(arm7, measured):
    truth, t, q, qd, qdd, tau = measured
    back = t.copy()
    back[7] = back[6]
    with pytest.raises(ValueError, match="argument 't': time .* at sample 7 does not increase"):
        dyngen.identify(arm7, back, q, tau)
    with pytest.raises(ValueError, match="argument 'tau' has 499 samples, but 't' has 500"):
        dyngen.identify(arm7, t, q, tau[1:])
    far = q.copy()
    far[3, 1] = 10.0
    with pytest.raises(ValueError, match="argument 'q': sample 3, joint 'joint2': position 10 is outside"):
        dyngen.identify(arm7, t, far, tau)
    holed = qd.copy()
    holed[4, 2] = np.nan
    with pytest.raises(ValueError, match="argument 'qd': sample 4, column 2 is NaN"):
        dyngen.identify(arm7, t, q, tau, qd=holed, qdd=qdd)
    with pytest.raises(ValueError, match="observation: expected"):
        dyngen.identify(arm7, t, q, tau, observation="torques")
    still = np.repeat(q[:1], len(t), axis=0)
    with pytest.raises(dyngen.IdentificationError, match="cannot be determined"):
        dyngen.identify(arm7, t, still, tau, qd=np.zeros_like(q), qdd=np.zeros_like(q))


def test_a_floating_base_is_not_identified():
    solo = dyngen.Robot.load(REPO / "robots" / "solo12.yaml")
    with pytest.raises(dyngen.IdentificationError, match="floating-base robot is not supported"):
        dyngen.identify(solo, [0.0], np.zeros((1, 12)), np.zeros((1, 12)))
