"""Task-space tasks from Python (TaskSpaceTask.calc): BodyOrientationTask and JointFunctionTask.

Checked against math written here: y against the closed form (the rotation vector of the link's rotation matrix, built
from the world positions of points on the link by the bound forward kinematics; f(q_i) of the Python function), J
against central differences of y (or, for the orientation, the world angular velocity from central differences of R),
and J-dot q-dot against central differences of J v along the motion q(t) = q + t v (Cassie's base coordinates are
Euler angles, so q-dot = v).
"""
import math

import numpy as np
import pytest

import rome

CASSIE = "robots/cassie/cassie.rome.json"
AMBER = "robots/amber/amber.rome.json"


@pytest.fixture(scope="module")
def cassie():
    return rome.MultibodyModel.load(CASSIE, euler_floating_base=True)


def rotation(model, q, link):
    """R_world_link from the world positions of the link frame's origin and unit points (forward kinematics)."""
    o = model.point_position(q, link)
    return np.column_stack([model.point_position(q, link, e) - o for e in np.eye(3)])


def log_so3(R):
    angle = math.acos(max(-1.0, min(1.0, (np.trace(R) - 1) / 2)))
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    return w * (0.5 if angle < 1e-12 else angle / (2 * math.sin(angle)))


def random_state(model, seed):
    rng = np.random.default_rng(seed)
    q = np.array(model.q_nominal, dtype=float) + rng.uniform(-0.3, 0.3, model.nq)
    return q, rng.uniform(-1.0, 1.0, model.nv)


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("link", ["pelvis", "left_foot"])
def test_body_orientation_task_is_the_rotation_vector_with_the_angular_velocity_jacobian(cassie, seed, link):
    task = rome.BodyOrientationTask("orientation", cassie, link)
    q, v = random_state(cassie, seed)
    y, J, Jdot_v = task.calc(cassie, q, v)
    R = rotation(cassie, q, link)
    assert np.allclose(R.T @ R, np.eye(3), atol=1e-12)
    assert y == pytest.approx(log_so3(R), abs=1e-10)
    eps = 1e-6
    Rdot = (rotation(cassie, q + eps * v, link) - rotation(cassie, q - eps * v, link)) / (2 * eps)
    W = Rdot @ R.T  # skew(omega), world frame
    omega = np.array([W[2, 1], W[0, 2], W[1, 0]])
    assert J @ v == pytest.approx(omega, abs=1e-7)
    Jv = lambda qq: task.calc(cassie, qq, v)[1] @ v  # noqa: E731
    assert Jdot_v == pytest.approx((Jv(q + eps * v) - Jv(q - eps * v)) / (2 * eps), abs=1e-6)


def test_joint_function_task_is_f_of_one_coordinate(cassie):
    f = lambda x: (0.5 * math.cos(x) + 0.1 * x**2, -0.5 * math.sin(x) + 0.2 * x)  # noqa: E731
    f2 = lambda x: -0.5 * math.cos(x) + 0.2  # noqa: E731  f'' in closed form
    task = rome.JointFunctionTask("leg", cassie, "left_knee", f)
    i = cassie.velocity_index("left_knee")
    q, v = random_state(cassie, 4)
    y, J, Jdot_v = task.calc(cassie, q, v)
    assert y[0] == pytest.approx(f(q[i])[0], abs=1e-14)
    expected_J = np.zeros(cassie.nv)
    expected_J[i] = f(q[i])[1]
    assert J[0] == pytest.approx(expected_J, abs=1e-14)
    # f'' by the task's central difference of f' (step 1e-5): error ~ step^2 f'''' / 6
    assert Jdot_v[0] == pytest.approx(f2(q[i]) * v[i] ** 2, abs=1e-8)
    # and by central differences of y along q + t v, as for any task
    eps = 1e-5
    y_of = lambda t: task.calc(cassie, q + t * v, v)[0][0]  # noqa: E731
    assert (y_of(eps) - 2 * y[0] + y_of(-eps)) / eps**2 == pytest.approx(Jdot_v[0], abs=1e-4)


def test_tasks_report_bad_arguments_and_failing_functions(cassie):
    with pytest.raises(ValueError, match="nose"):
        rome.BodyOrientationTask("o", cassie, "nose")
    with pytest.raises(ValueError, match="elbow"):
        rome.JointFunctionTask("f", cassie, "elbow", lambda x: (x, 1.0))
    task = rome.JointFunctionTask("f", cassie, "left_knee", lambda x: "not a pair")
    with pytest.raises(RuntimeError, match="must return"):
        task.calc(cassie, cassie.q_nominal, np.zeros(cassie.nv))

    def failing(x):
        raise ArithmeticError("f undefined here")

    with pytest.raises(ArithmeticError, match="undefined"):
        rome.JointFunctionTask("g", cassie, "left_knee", failing).calc(cassie, cassie.q_nominal, np.zeros(cassie.nv))
    with pytest.raises(ValueError, match="nq = 22"):
        task.calc(cassie, [0.0] * 3, [0.0] * 3)
