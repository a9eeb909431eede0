"""Task-space tasks from Python (TaskSpaceTask.calc): BodyOrientationTask, BodyEulerAngleTask and JointFunctionTask.

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


def quaternion_from_zyx(yaw, pitch, roll):
    """(w, x, y, z) of Rz(yaw) Ry(pitch) Rx(roll), the closed form."""
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    return np.array([cr * cp * cy + sr * sp * sy, sr * cp * cy - cr * sp * sy,
                     cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy])


@pytest.mark.parametrize("seed", [1, 2])
def test_body_euler_angle_task_is_the_base_coordinate_and_differentiates_along_the_motion(cassie, seed):
    q, v = random_state(cassie, seed)
    for angle, joint in [(rome.EulerAngle.roll, "base_roll"), (rome.EulerAngle.pitch, "base_pitch"),
                         (rome.EulerAngle.yaw, "base_yaw")]:
        i = cassie.velocity_index(joint)
        y, J, Jdot_v = rome.BodyEulerAngleTask("a", cassie, "pelvis", angle).calc(cassie, q, v)
        assert y[0] == pytest.approx(q[i], abs=1e-12)
        assert J[0] == pytest.approx(np.eye(cassie.nv)[i], abs=1e-12)
        assert Jdot_v[0] == pytest.approx(0.0, abs=1e-10)
        # a link below the pelvis: J v and J-dot q-dot against central differences along q + t v (q-dot = v here)
        task = rome.BodyEulerAngleTask("a", cassie, "left_foot", angle)
        y, J, Jdot_v = task.calc(cassie, q, v)
        y_of = lambda t: task.calc(cassie, q + t * v, v)[0][0]  # noqa: E731
        assert J[0] @ v == pytest.approx((y_of(1e-6) - y_of(-1e-6)) / 2e-6, abs=1e-7)
        assert Jdot_v[0] == pytest.approx((y_of(1e-4) - 2 * y[0] + y_of(-1e-4)) / 1e-8, abs=1e-4)


def test_base_angle_task_on_the_quaternion_base_reads_the_quaternion():
    quat = rome.MultibodyModel.load(CASSIE)  # the quaternion free-flyer (default)
    assert quat.nq == quat.nv + 1
    q = np.array(quat.q_nominal, dtype=float)
    yaw, pitch, roll = 0.4, -0.7, 0.3
    q[3:7] = quaternion_from_zyx(yaw, pitch, roll)
    v = np.zeros(quat.nv)
    for angle, expected in [(rome.EulerAngle.roll, roll), (rome.EulerAngle.pitch, pitch), (rome.EulerAngle.yaw, yaw)]:
        y, J, _ = rome.make_base_angle_task("a", quat, angle).calc(quat, q, v)
        assert y[0] == pytest.approx(expected, abs=1e-12)
        assert np.all(J[0][6:] == 0.0)  # the base's angles move with the base twist only
    with pytest.raises(ValueError, match="twist entry"):
        rome.JointPositionTask("yaw", quat, "base_wz")
    q[3:7] = quaternion_from_zyx(0.0, math.pi / 2, 0.0)
    with pytest.raises(RuntimeError, match="pitch"):
        rome.BodyEulerAngleTask("p", quat, "pelvis", rome.EulerAngle.pitch).calc(quat, q, v)
