"""Cassie loaded with the quaternion free-flyer base from Python.

nq == nv + 1; M(q) is symmetric positive definite; and M equals the Euler model's mass matrix at the same physical
state: with the ZYX-Euler base q_e = [p, yaw, pitch, roll, joints] and the free-flyer's twist in base axes,
v_quat = A v_euler with A = blockdiag(R^T, R^T E, I), E the map from Euler rates to the world angular velocity
(written here), so equal kinetic energies give M_euler = A^T M_quat A. At rest h is gravity alone, a generalized force,
which maps the same way: h_euler = A^T h_quat.
"""
import math

import numpy as np
import pytest

import rome

CASSIE = "robots/cassie/cassie.rome.json"


def rot_z(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def rot_x(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def quaternion_of(R):
    """(w, x, y, z) of a rotation matrix with w > 0 (Shepperd's method, the w-largest branch suffices here)."""
    w = 0.5 * math.sqrt(1.0 + np.trace(R))
    return np.array([w, (R[2, 1] - R[1, 2]) / (4 * w), (R[0, 2] - R[2, 0]) / (4 * w), (R[1, 0] - R[0, 1]) / (4 * w)])


def euler_to_quaternion_state(q_e, nv):
    yaw, pitch, roll = q_e[3:6]
    R = rot_z(yaw) @ rot_y(pitch) @ rot_x(roll)
    # World angular velocity = yawdot e_z + pitchdot Rz e_y + rolldot Rz Ry e_x.
    E = np.column_stack([[0.0, 0.0, 1.0], rot_z(yaw)[:, 1], (rot_z(yaw) @ rot_y(pitch))[:, 0]])
    A = np.eye(nv)
    A[0:3, 0:3] = R.T
    A[3:6, 3:6] = R.T @ E
    q_q = np.concatenate([q_e[0:3], quaternion_of(R), q_e[6:]])
    return q_q, A


@pytest.fixture(scope="module")
def models():
    return rome.MultibodyModel.load(CASSIE, euler_floating_base=True), rome.MultibodyModel.load(CASSIE)


def test_quaternion_is_the_default_and_euler_is_asked_for():
    assert rome.MultibodyModel.load(CASSIE, quaternion_floating_base=True).nq == 23
    assert rome.MultibodyModel.load("robots/exoskeleton/exoskeleton.rome.json").base_kind == "quaternion"
    assert rome.MultibodyModel.load("robots/amber/amber.rome.json", euler_floating_base=True).base_kind == "planar"
    with pytest.raises(Exception, match="both set"):
        rome.MultibodyModel.load(CASSIE, quaternion_floating_base=True, euler_floating_base=True)


def test_quaternion_cassie_has_one_more_position_than_velocity(models):
    euler, quat = models
    assert quat.base_kind == "quaternion" and euler.base_kind == "spatial_euler"
    assert quat.nq == quat.nv + 1
    assert quat.nv == euler.nv and euler.nq == euler.nv
    assert len(quat.q_nominal) == quat.nq


def test_mass_matrix_is_spd_and_equals_the_euler_models_through_the_twist_map(models):
    euler, quat = models
    rng = np.random.default_rng(1)
    for _ in range(5):
        q_e = np.array(euler.q_nominal) + rng.uniform(-0.4, 0.4, euler.nq)
        q_q, A = euler_to_quaternion_state(q_e, euler.nv)
        M_q = np.array(quat.mass_matrix(q_q))
        assert np.max(np.abs(M_q - M_q.T)) == 0.0
        assert np.min(np.linalg.eigvalsh(M_q)) > 0.0
        M_e = np.array(euler.mass_matrix(q_e))
        scale = np.max(np.abs(M_e))
        assert np.max(np.abs(A.T @ M_q @ A - M_e)) < 1e-10 * scale
        # At rest h is gravity alone, a generalized force: it maps by A^T as M does.
        zero = np.zeros(euler.nv)
        h_q = np.array(quat.bias_forces(q_q, zero))
        h_e = np.array(euler.bias_forces(q_e, zero))
        assert np.max(np.abs(A.T @ h_q - h_e)) < 1e-10 * (1.0 + np.max(np.abs(h_e)))


def test_a_planar_robot_is_refused_with_the_quaternion_option():
    with pytest.raises(Exception, match="quaternion"):
        rome.MultibodyModel.load("robots/amber/amber.rome.json", quaternion_floating_base=True)
