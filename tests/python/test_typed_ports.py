"""Typed ports (ports that carry one C++ value: a contact mode, a controller's diagnostics) read and set from Python.

The physics check: a task-space QP controller run standalone, with its typed 'mode' input fixed from Python, answers
with torques, accelerations and contact forces that satisfy the robot's equations of motion M qdd + h = B u + J^T F
(numpy on the bound model), and the forces are those of the contacts of the mode that was fixed (zero on the others).
"""
import numpy as np
import pytest

import rome
from test_contact_blocks import AMBER, hybrid_plant, run_standing, standing_pose


@pytest.fixture(scope="module")
def model():
    return rome.MultibodyModel.load(AMBER)


def controller_for(plant, tasks):
    return rome.TaskSpaceQpController("ctrl", plant, tasks)


@pytest.mark.parametrize("mode_name", ["double_support", "left_foot_stance"])
def test_a_controller_with_its_typed_mode_fixed_from_python_obeys_the_equations_of_motion(model, mode_name):
    plant = hybrid_plant(model)
    mode = plant.graph.mode_index(mode_name)
    tasks = [rome.ComPositionTask("com", [rome.Axis.x, rome.Axis.z]), rome.JointPositionTask("pitch", model, "base_pitch")]
    ctrl = controller_for(plant, tasks)
    assert ctrl.input_port_type("mode") == "int" and ctrl.input_port_type("state") == "a vector of size 14"
    q = standing_pose(model)
    simulator = rome.Simulator(ctrl)  # the controller alone: its outputs hold the discrete state of its updates
    context = simulator.context
    ctrl.fix_input_port(context, "state", np.concatenate([q, np.zeros(model.nv)]))
    ctrl.fix_input_port(context, "mode", mode)
    com = model.com_position(q)
    ctrl.fix_input_port(context, "desired", [com[0] + 0.01, com[2] - 0.01, 0.0] + [0.0] * 6)
    assert simulator.advance_to(5e-4).ok()  # the update at t = 0 has run
    u, qdd, F = (np.asarray(ctrl.eval_output(context, p)) for p in ("u", "qdd", "contact_forces"))
    rhs = np.asarray(model.B) @ u
    for i, c in enumerate(model.contact_names):
        rhs += np.asarray(model.contact_jacobian(q, c)).T @ F[3 * i:3 * i + 3]
    lhs = np.asarray(model.mass_matrix(q)) @ qdd + np.asarray(model.bias_forces(q, np.zeros(model.nv)))
    assert lhs == pytest.approx(rhs, abs=1e-6 * model.total_mass * 9.81)
    active = plant.active_contacts(mode)
    for i, c in enumerate(model.contact_names):
        if c not in active:
            assert F[3 * i:3 * i + 3] == pytest.approx([0.0, 0.0, 0.0], abs=1e-9)
        else:
            assert F[3 * i + 2] > 0.0
    diagnostics = ctrl.eval_output(context, "diagnostics")
    assert isinstance(diagnostics, dict) and "qp_failures" in diagnostics


def test_typed_outputs_of_a_running_diagram(model):
    _, _, _, diagnostics = run_standing(model, lambda plant, tasks: rome.ClfQpController("ctrl", plant, tasks),
                                        seconds=0.05)
    assert diagnostics["solved"] >= 50  # 1 kHz over 0.05 s

    plant = hybrid_plant(model)
    builder = rome.DiagramBuilder()
    builder.add_system(plant)
    builder.fix_input("plant", "u", [0.0] * model.nu)
    diagram = builder.build()
    context = diagram.create_default_context()
    plant.set_state(diagram.get_subsystem_context(plant, context), standing_pose(model), np.zeros(model.nv),
                    "left_foot_stance")
    mode = diagram.eval_subsystem_output(plant, "mode", context)
    assert isinstance(mode, int) and plant.mode_names[mode] == "left_foot_stance"


def test_typed_ports_refuse_values_of_another_type(model):
    plant = hybrid_plant(model)
    ctrl = controller_for(plant, [rome.ComPositionTask("com", [rome.Axis.z])])
    context = ctrl.create_default_context()
    with pytest.raises(ValueError, match="input port 'mode' of system 'ctrl': expected an int"):
        ctrl.fix_input_port(context, "mode", "left_stance")
    ctrl.fix_input_port(context, "mode", np.int64(1))  # a numpy integer is an int
    with pytest.raises(ValueError, match="1-D sequence"):
        ctrl.fix_input_port(context, "state", "abc")
    builder = rome.DiagramBuilder()
    builder.add_system(controller_for(hybrid_plant(model), [rome.ComPositionTask("com", [rome.Axis.z])]))
    with pytest.raises(ValueError, match="expected an int"):
        builder.fix_input("ctrl", "mode", 0.5)
