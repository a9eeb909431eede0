"""The contact plant and the QP controllers as blocks of a diagram built in Python (AMBER standing in double support).

Each run is checked against physics computed here in numpy from the robot model, not against the blocks' own numbers:
Newton-Euler for the whole robot (the ground carries m g at rest), the equations of motion M qdd + h = B u + J^T F for
the task-space QP's answer, unilateral forces inside the friction cone, and the plant's forces equal to those the
controllers planned (both use the same contact model and the held torque).
"""
import numpy as np
import pytest

import rome

AMBER = "robots/amber/amber.rome.json"
G = 9.81  # [m/s^2] the model's gravity (robots.md)


@pytest.fixture(scope="module")
def model():
    return rome.MultibodyModel.load(AMBER)


def standing_pose(model, left_hip=-0.5, knee=0.4):
    """Both feet on the ground (z = 0), the left one ahead, the COM over their midpoint, torso upright."""
    q = np.array(model.q_nominal, dtype=float)

    def height_gap(right_hip):
        q[3:7] = [left_hip, knee, right_hip, knee]
        return model.contact_position(q, "left_foot")[2] - model.contact_position(q, "right_foot")[2]

    lo, hi = -0.2, 0.8  # the right hip angle that levels the feet lies between (sign change of height_gap)
    assert height_gap(lo) * height_gap(hi) < 0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if height_gap(lo) * height_gap(mid) > 0 else (lo, mid)
    height_gap(lo)
    q[1] -= model.contact_position(q, "left_foot")[2]
    feet_x = [model.contact_position(q, c)[0] for c in model.contact_names]
    q[0] -= model.com_position(q)[0] - 0.5 * sum(feet_x)
    return q


def hybrid_plant(model):
    return rome.HybridContactPlant("plant", model, rome.ContactModeGraph.with_double_support("left_foot", "right_foot"))


def run_standing(model, controller_for, seconds=2.0, com_offset=(0.01, -0.01), plant_for=hybrid_plant, extend=None):
    """Plant + controller + constant desired outputs [COM x, COM z, base pitch] offset from the start by com_offset [m]
    (and whatever extend(builder) adds); returns (log data, the start COM, the desired outputs, the controller's
    diagnostics)."""
    q0 = standing_pose(model)
    com0 = model.com_position(q0)
    plant = plant_for(model)
    tasks = [rome.ComPositionTask("com", [rome.Axis.x, rome.Axis.z]), rome.JointPositionTask("pitch", model, "base_pitch")]
    controller = controller_for(plant, tasks)
    builder = rome.DiagramBuilder()
    builder.add_system(plant)
    builder.add_system(controller)
    y_d = [com0[0] + com_offset[0], com0[2] + com_offset[1], 0.0]
    builder.add_system(rome.ConstantVectorSource("desired", y_d + [0.0] * 6))
    builder.connect("plant", "state", "ctrl", "state")
    builder.connect("plant", "mode", "ctrl", "mode")
    builder.connect("desired", "y", "ctrl", "desired")
    builder.connect("ctrl", "u", "plant", "u")
    ports = [("plant", "state"), ("plant", "contact_forces"), ("plant", "com"), ("ctrl", "u"), ("ctrl", "contact_forces")]
    if isinstance(controller, rome.TaskSpaceQpController):
        ports.append(("ctrl", "qdd"))
    else:
        ports.append(("ctrl", "V"))
    if extend is not None:
        extend(builder)
    logger = rome.add_vector_logger(builder, "log", ports, 0.01)
    diagram = builder.build()
    simulator = rome.Simulator(diagram)
    plant.set_state(diagram.get_subsystem_context(plant, simulator.context), q0, np.zeros(model.nv), "double_support")
    status = simulator.advance_to(seconds)
    assert status.ok(), status
    data = logger.data(diagram.get_subsystem_context(logger, simulator.context))
    return data, com0, y_d, controller.diagnostics(diagram.get_subsystem_context(controller, simulator.context))


def forces(data, prefix, model, k):
    """The 3 nc ground forces at log sample k: the plant's, or those the controller planned."""
    if prefix == "plant":
        return np.array([data[f"plant.contact_forces.{c}_f{a}"][k] for c in model.contact_names for a in "xyz"])
    return np.array([data[f"ctrl.contact_forces[{i}]"][k] for i in range(3 * len(model.contact_names))])


def check_ground_forces(model, data, mu):
    """Unilateral, inside |F_x| <= mu F_z, equal to the controller's planned forces, and, by Newton, the robot's mass
    times its COM acceleration (central differences of the plant's COM velocity) plus its weight."""
    worst_ratio = 0.0
    m, dt = model.total_mass, data["time"][1] - data["time"][0]
    for k in range(1, len(data["time"]) - 1):
        plant_f, planned_f = forces(data, "plant", model, k), forces(data, "ctrl", model, k)
        assert np.abs(plant_f - planned_f).max() < 1e-6 * m * G
        for i in range(len(model.contact_names)):
            fx, fz = plant_f[3 * i], plant_f[3 * i + 2]
            assert fz > 0.0
            worst_ratio = max(worst_ratio, abs(fx) / fz)
        a_x = (data["plant.com.vx"][k + 1] - data["plant.com.vx"][k - 1]) / (2 * dt)
        a_z = (data["plant.com.vz"][k + 1] - data["plant.com.vz"][k - 1]) / (2 * dt)
        assert plant_f[0] + plant_f[3] == pytest.approx(m * a_x, abs=2e-3 * m * G)
        assert plant_f[2] + plant_f[5] == pytest.approx(m * (G + a_z), abs=2e-3 * m * G)
    assert worst_ratio <= mu * (1 + 1e-6)
    return worst_ratio


def test_task_space_qp_block_on_the_hybrid_plant(model):
    mu = 0.1  # the QP's pyramid, far inside the model's 0.8: the splayed legs' least-torque forces need more
    params = rome.TaskSpaceQpParams(friction_coefficient=mu)
    data, com0, y_d, diagnostics = run_standing(
        model, lambda plant, tasks: rome.TaskSpaceQpController("ctrl", plant, tasks, params))
    assert diagnostics["qp_failures"] == 0 and diagnostics["solved"] == 2000
    worst = check_ground_forces(model, data, mu)
    assert worst > 0.99 * mu  # the cone binds: the plant's forces sit on the QP's pyramid, not inside by luck
    # The QP's answer obeys the equations of motion at the state it was computed at: M qdd + h = B u + tau_s + J^T F.
    names = model.joint_names
    for k in range(1, len(data["time"]), 10):
        q = np.array([data[f"plant.state.q_{n}"][k] for n in names])
        v = np.array([data[f"plant.state.v_{n}"][k] for n in names])
        qdd = np.array([data[f"ctrl.qdd[{i}]"][k] for i in range(model.nv)])
        u = np.array([data[f"ctrl.u[{i}]"][k] for i in range(model.nu)])
        f = forces(data, "ctrl", model, k)
        lhs = model.mass_matrix(q) @ qdd + model.bias_forces(q, v)
        rhs = model.B @ u + model.spring_torques(q, v) + sum(
            model.contact_jacobian(q, c).T @ f[3 * i:3 * i + 3] for i, c in enumerate(model.contact_names))
        assert np.abs(lhs - rhs).max() < 1e-9 * np.abs(lhs).max()
    # The PD output dynamics (kp 100, kd 20: a double pole at 10 rad/s) bring the COM to the 1 cm offsets in 2 s.
    assert data["plant.com.x"][-1] == pytest.approx(y_d[0], abs=1e-4)
    assert data["plant.com.z"][-1] == pytest.approx(y_d[1], abs=1e-4)


def test_clf_qp_block_on_the_hybrid_plant(model):
    data, com0, y_d, diagnostics = run_standing(
        model, lambda plant, tasks: rome.ClfQpController("ctrl", plant, tasks, rome.ClfQpParams()), seconds=4.0)
    assert diagnostics["qp_failures"] == 0 and diagnostics["solved"] == 4000
    check_ground_forces(model, data, model.contact_friction_coefficients[0])
    # The RES-CLF drives V to zero: V falls by orders of magnitude from the first update to the end.
    V = data["ctrl.V[0]"]
    assert V[-1] < 1e-4 * V[1]
    assert data["plant.com.x"][-1] == pytest.approx(y_d[0], abs=1e-4)
    assert data["plant.com.z"][-1] == pytest.approx(y_d[1], abs=1e-4)


def test_clf_qp_contact_rows_from_python_bind_on_the_plant(model):
    # The CLF-QP's contact wrench parameters set from Python reach its QP: with a friction pyramid of mu = 0.1, far
    # inside the model's 0.8, the plant's forces sit on that pyramid (as with the task-space QP above).
    mu = 0.1
    params = rome.ClfQpParams(contact=rome.ContactWrenchParams(friction_coefficient=mu))
    data, com0, y_d, diagnostics = run_standing(
        model, lambda plant, tasks: rome.ClfQpController("ctrl", plant, tasks, params), seconds=4.0)
    assert diagnostics["qp_failures"] == 0
    assert check_ground_forces(model, data, mu) > 0.99 * mu


def test_contact_blocks_refuse_bad_arguments(model):
    graph = rome.ContactModeGraph.with_double_support("left_foot", "right_foot")
    graph.initial_mode = "no_such_mode"
    with pytest.raises(ValueError, match="no_such_mode"):
        rome.HybridContactPlant("plant", model, graph)
    plant = rome.HybridContactPlant("plant", model, rome.ContactModeGraph.with_double_support("left_foot", "right_foot"))
    with pytest.raises(ValueError, match="no_such_joint"):
        rome.JointPositionTask("j", model, "no_such_joint")
    context = plant.create_default_context()
    with pytest.raises(ValueError, match="plant"):
        plant.set_state(context, np.zeros(3), np.zeros(model.nv), "double_support")


def test_task_space_qp_block_on_the_bullet_plant(model):
    # Bullet's world (rigid contacts, Coulomb friction at the model's mu = 0.8, 1 ms steps) under the same controller:
    # its ground forces are its solver's impulses over a step, so only Newton at rest and the cone are checked.
    def bullet_plant(m):
        graph = rome.ContactModeGraph.with_double_support("left_foot", "right_foot")
        return rome.BulletWorldPlant("plant", m, graph, rome.Terrain.flat(), rome.BulletWorldPlantParams())

    data, com0, y_d, diagnostics = run_standing(
        model, lambda plant, tasks: rome.TaskSpaceQpController("ctrl", plant, tasks), seconds=2.0, plant_for=bullet_plant)
    assert diagnostics["qp_failures"] == 0
    mu = model.contact_friction_coefficients[0]
    for c in model.contact_names:
        fx, fz = data[f"plant.contact_forces.{c}_fx"][1:], data[f"plant.contact_forces.{c}_fz"][1:]
        assert (fz > 0.0).all()
        assert (np.abs(fx) <= mu * fz * (1 + 1e-6)).all()
    end = forces(data, "plant", model, -1)
    assert end[2] + end[5] == pytest.approx(model.total_mass * G, rel=1e-3)  # the COM at rest: the weight
    assert data["plant.com.x"][-1] == pytest.approx(y_d[0], abs=1e-3)
    assert data["plant.com.z"][-1] == pytest.approx(y_d[1], abs=1e-3)
