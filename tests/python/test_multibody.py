"""Multibody robot models from Python: loading, model facts and dynamics on numpy arrays.

Expected values come from elsewhere than the function under test: the URDF's own <inertial> and <limit> entries
(read here with xml.etree), Bullet's articulated-body forward dynamics against the CRBA/RNEA inverse dynamics, and the
gravity term against finite differences of the potential m g z_com(q).
"""
import xml.etree.ElementTree as ET

import numpy as np
import pytest

import rome

ROBOTS = ["robots/amber/amber.rome.json", "robots/cassie/cassie.rome.json"]


def urdf_of(sidecar):
    return sidecar.replace(".rome.json", ".urdf")


def random_state(model, seed):
    rng = np.random.default_rng(seed)
    q = model.q_nominal + 0.1 * rng.standard_normal(model.nq)
    v = rng.standard_normal(model.nv)
    return rng, q, v


@pytest.mark.parametrize("path", ROBOTS)
def test_model_facts_match_the_urdf(path):
    model = rome.MultibodyModel.load(path, euler_floating_base=True)
    root = ET.parse(urdf_of(path)).getroot()
    urdf_mass = sum(float(m.get("value")) for m in root.iter("mass"))
    assert model.total_mass == pytest.approx(urdf_mass, rel=1e-12)
    assert sum(model.body_masses) == pytest.approx(urdf_mass, rel=1e-12)
    assert model.nq == model.nv == len(model.joint_names)
    assert model.B.shape == (model.nv, model.nu) and len(model.actuated_joints) == model.nu
    # Every limited URDF joint's <limit lower upper> is the model's position limit of that coordinate.
    checked = 0
    for joint in root.iter("joint"):
        limit = joint.find("limit")
        if joint.get("type") not in ("revolute", "prismatic") or limit is None:
            continue
        lower, upper = float(limit.get("lower", 0)), float(limit.get("upper", 0))
        if lower == upper or joint.get("name") not in model.joint_names:
            continue
        i = model.velocity_index(joint.get("name"))
        assert model.position_lower_limits[i] == pytest.approx(lower)
        assert model.position_upper_limits[i] == pytest.approx(upper)
        checked += 1
    assert checked > 0
    assert repr(model).startswith("MultibodyModel('")


@pytest.mark.parametrize("path", ROBOTS)
def test_inverse_dynamics_is_m_qdd_plus_h_and_inverts_bullets_forward_dynamics(path):
    model = rome.MultibodyModel.load(path, euler_floating_base=True)
    for seed in range(1, 4):
        rng, q, v = random_state(model, seed)
        M = model.mass_matrix(q)
        assert np.allclose(M, M.T, atol=1e-12)
        assert np.linalg.eigvalsh(M).min() > 0
        qdd = rng.standard_normal(model.nv)
        tau = model.inverse_dynamics(q, v, qdd)
        expected = M @ qdd + model.bias_forces(q, v) - model.spring_torques(q, v)
        assert np.allclose(tau, expected, rtol=1e-10, atol=1e-9)
        # Bullet's ABA (an independent algorithm) with the actuators' torques u: ID(FD(u)) = B u.
        u = rng.standard_normal(model.nu)
        qdd_fd = model.forward_dynamics(q, v, u)
        scale = max(1.0, np.abs(model.B @ u).max())
        assert np.allclose(model.inverse_dynamics(q, v, qdd_fd), model.B @ u, atol=1e-7 * scale)


@pytest.mark.parametrize("path", ROBOTS)
def test_gravity_term_is_the_gradient_of_the_potential(path):
    model = rome.MultibodyModel.load(path, euler_floating_base=True)
    _, q, _ = random_state(model, 4)
    g = -model.gravity[2]
    step = 1e-6
    potential_gradient = np.zeros(model.nv)
    for i in range(model.nv):
        dq = np.zeros(model.nv)
        dq[i] = step
        up, down = model.com_position(q + dq)[2], model.com_position(q - dq)[2]
        potential_gradient[i] = model.total_mass * g * (up - down) / (2 * step)
    h0 = model.bias_forces(q, np.zeros(model.nv))
    assert np.allclose(h0, potential_gradient, atol=1e-6 * model.total_mass * g)


def test_kinetic_energy_equals_the_centroidal_and_point_quantities():
    """½ vᵀ M v ≥ ½ m |v_com|² (König), with the COM velocity = J_com v from finite differences of the COM."""
    model = rome.MultibodyModel.load(ROBOTS[0], euler_floating_base=True)
    _, q, v = random_state(model, 5)
    step = 1e-7
    com_rate = (model.com_position(q + step * v) - model.com_position(q - step * v)) / (2 * step)
    assert np.allclose(model.com_velocity(q, v), com_rate, atol=1e-6)
    linear_momentum = model.centroidal_momentum(q, v)[3:]
    assert np.allclose(linear_momentum, model.total_mass * com_rate, atol=1e-5)
    kinetic = 0.5 * v @ model.mass_matrix(q) @ v
    assert kinetic >= 0.5 * model.total_mass * com_rate @ com_rate


def test_bad_input_names_the_model_and_the_size():
    model = rome.MultibodyModel.load(ROBOTS[0], euler_floating_base=True)
    with pytest.raises(ValueError, match=r"MultibodyModel 'amber.*': q has 3 entries, expected"):
        model.mass_matrix(np.zeros(3))
    with pytest.raises(ValueError, match=r"v\[0\] = nan is not finite"):
        model.bias_forces(model.q_nominal, np.full(model.nv, np.nan))
    with pytest.raises(ValueError, match="u has"):
        model.forward_dynamics(model.q_nominal, np.zeros(model.nv), np.zeros(model.nu + 1))
    with pytest.raises(ValueError, match="no_such_robot"):
        rome.MultibodyModel.load("robots/no_such_robot/no_such_robot.rome.json")
