"""A floating base (Solo-12) against Pinocchio's values: the configuration with its unit
quaternion, the velocity with the base twist."""

import numpy as np
import pytest

import dyngen
from conftest import REPO, assert_close, fixture, stacked


@pytest.fixture(scope="module")
def solo():
    return dyngen.Robot.load(REPO / "robots" / "solo12.yaml")


def test_solo12_matches_pinocchio(solo):
    reference = fixture("floating/solo12")
    assert solo.joint_names == reference["joint_names"]
    assert (solo.nq, solo.nv, solo.floating_base) == (19, 18, True)
    states = reference["states"]
    q, v, a, vr, ar = (stacked(states, k) for k in ["q", "v", "a", "vr", "ar"])
    results = {
        "D": solo.mass_matrix(q),
        "C": solo.coriolis_matrix(q, v),
        "g": solo.gravity(q),
        "tau": solo.inverse_dynamics(q, v, a),
        "tau_ref": solo.slotine_li(q, v, vr, ar),
        "Y": solo.regressor(q, v, v, a),
        "Minv": solo.mass_matrix_inverse(q),
        "com": solo.center_of_mass(q),
        "Jcom": solo.center_of_mass_jacobian(q),
        "Ag": solo.centroidal_momentum_matrix(q),
        "dAg_v": solo.centroidal_bias(q, v),
    }
    dq, dv = solo.inverse_dynamics_derivatives(q, v, a)
    results.update(dtau_dq=dq, dtau_dv=dv)
    tau = stacked(states, "tau")
    results["aba"] = solo.forward_dynamics(q, v, tau)
    for key, value in results.items():
        for k, s in enumerate(states):
            assert_close(f"solo12 state {k}: {key}", value[k], s[key])
    assert_close("θ", solo.parameters, reference["pi"])


def test_a_non_unit_quaternion_is_refused_naming_the_state(solo):
    q = stacked(fixture("floating/solo12")["states"], "q")[:3].copy()
    q[2, 3:7] *= 1.1
    with pytest.raises(ValueError, match=r"state 2: the base quaternion .* has norm"):
        solo.mass_matrix(q)
    with pytest.raises(ValueError, match="has norm"):
        solo.gravity(q[2])


def test_integrate_and_difference_are_inverse(solo):
    q0 = np.array(stacked(fixture("floating/solo12")["states"], "q")[0])
    nu = np.linspace(-0.5, 0.5, solo.nv)
    q1 = solo.integrate(q0, nu, 0.1)
    assert_close("difference(q0, q0 ⊕ ν dt)", solo.difference(q0, q1), 0.1 * nu, 1e-12)


def test_fixed_and_floating_only_methods_say_what_they_need(solo, robots):
    with pytest.raises(ValueError, match="needs a floating base"):
        robots["ur5"].center_of_mass(np.zeros(6))
    with pytest.raises(ValueError, match="fixed base only"):
        solo.energy_regressor(np.zeros(19), np.zeros(18))
