"""The QP controllers' and the plants' parameters set from Python reach the C++ blocks and act as documented.

Physics checks on AMBER standing (as in test_contact_blocks.py): with the left knee declared passive while the left
foot is in contact (zero_torque_in_contact of ClfQpParams and of TaskSpaceQpParams), the robot still stands on the
plant's ground forces, which obey Newton and the friction cone, and that knee's torque stays zero; the hybrid plant
with its joint stops and stiffer stabilisation set from Python holds AMBER standing on physical forces; on
BulletWorldPlant with its external-force input declared (BulletWorldPlantParams.external_force_input), a constant
horizontal push on the base is carried at rest by the feet's friction (Newton: the ground's horizontal force is minus
the push, its vertical force the weight).
"""
import math

import numpy as np
import pytest

import rome
from test_contact_blocks import AMBER, G, check_ground_forces, forces, run_standing


@pytest.fixture(scope="module")
def model():
    return rome.MultibodyModel.load(AMBER)


def test_clf_qp_params_have_keyword_constructors_and_a_repr_of_every_field():
    params = rome.ClfQpParams(
        u_regularization_kind=rome.TorqueRegularization.inverse_joint_inertia, u_regularization_weights=[1, 2, 1, 2],
        u_regularization_modes=[1], force_band_loading_fall_tolerance_N=0.02, cost_only_outputs=["pitch"],
        predict_hold_drift=True, hold_drift_settle_s=0.004, cost_pd_feedback=True, clf_active_tolerance=1e-6,
        contact_stabilization=rome.ConstrainedDynamicsParameters(baumgarte_alpha_per_s=20.0),
        resolve_at=rome.EventTrigger([("plant", "touchdown_*")]), qp=rome.QpSettings(max_iterations=50),
        zero_torque_in_contact=[("left_foot", "left_knee")])
    text = repr(params)
    for field in ["u_regularization_kind=<TorqueRegularization.inverse_joint_inertia", "cost_only_outputs=['pitch']",
                  "resolve_at=EventTrigger([('plant', 'touchdown_*')])", "max_iterations=50",
                  "baumgarte_alpha_per_s=20.0", "zero_torque_in_contact=[('left_foot', 'left_knee')]",
                  "clf_active_tolerance=1e-06", "predict_hold_drift=True", "hold_drift_settle_s=0.004"]:
        assert field in text, field
    assert list(params.u_regularization_weights) == [1, 2, 1, 2]
    with pytest.raises(TypeError, match="no field 'cost_only'"):
        rome.ClfQpParams(cost_only=["pitch"])


def clf_qp_with_passive_left_knee(plant, tasks):
    params = rome.ClfQpParams(zero_torque_in_contact=[("left_foot", "left_knee")])
    return rome.ClfQpController("ctrl", plant, tasks, params)


def task_space_qp_with_passive_left_knee(plant, tasks):
    stabilization = rome.ConstrainedDynamicsParameters(baumgarte_alpha_per_s=10.0)
    params = rome.TaskSpaceQpParams(zero_torque_in_contact=[("left_foot", "left_knee")], predict_hold_drift=True,
                                    qp=rome.QpSettings(max_iterations=200), contact_stabilization=stabilization)
    assert "zero_torque_in_contact=[('left_foot', 'left_knee')]" in repr(params)
    return rome.TaskSpaceQpController("ctrl", plant, tasks, params)


@pytest.mark.parametrize("controller", [clf_qp_with_passive_left_knee, task_space_qp_with_passive_left_knee])
def test_a_passive_knee_in_contact_gets_no_torque_and_the_robot_still_stands(model, controller):
    data, com0, y_d, diagnostics = run_standing(model, controller, seconds=2.0)
    assert diagnostics["qp_failures"] == 0
    knee = model.actuated_joints.index("left_knee")
    assert np.abs(data[f"ctrl.u[{knee}]"]).max() < 1e-9
    assert max(np.abs(data[f"ctrl.u[{i}]"]).max() for i in range(model.nu) if i != knee) > 10.0  # the others work
    check_ground_forces(model, data, model.contact_friction_coefficients[0])
    assert data["plant.com.x"][-1] == pytest.approx(y_d[0], abs=1e-3)
    assert data["plant.com.z"][-1] == pytest.approx(y_d[1], abs=1e-3)


@pytest.mark.parametrize("push_N", [10.0, -15.0])
def test_bullet_external_force_input_is_carried_by_the_ground(model, push_N):
    # BulletWorldPlantParams.external_force_input declares tau_external (nv); a constant horizontal push on the base,
    # unknown to the controller, is balanced at rest by the feet's friction: sum F_x = -push, sum F_z = m g.
    params = rome.BulletWorldPlantParams(external_force_input=True, slip_distance_m=math.inf, max_impulse_Ns=1e5,
                                         warm_start_factor=0.9, solver_residual_threshold=1e-12)
    assert "external_force_input=True" in repr(params) and "slip_distance_m=inf" in repr(params)

    def bullet_plant(m):
        graph = rome.ContactModeGraph.with_double_support("left_foot", "right_foot")
        return rome.BulletWorldPlant("plant", m, graph, rome.Terrain.flat(), params)

    def push(builder):
        builder.add_system(rome.ConstantVectorSource("push", [push_N] + [0.0] * (model.nv - 1)))
        builder.connect("push", "y", "plant", "tau_external")

    data, _, _, diagnostics = run_standing(model, lambda plant, tasks: rome.TaskSpaceQpController("ctrl", plant, tasks),
                                           seconds=2.0, plant_for=bullet_plant, extend=push)
    assert diagnostics["qp_failures"] == 0
    end = forces(data, "plant", model, -1)
    mg = model.total_mass * G
    assert end[0] + end[3] == pytest.approx(-push_N, abs=2e-3 * mg)
    assert end[2] + end[5] == pytest.approx(mg, rel=1e-3)


def test_hybrid_plant_params_from_python_reach_the_plant(model):
    # The hybrid plant with its joint stops armed and stiffer contact stabilisation, all set from Python: AMBER
    # standing stays inside its joint limits (a stop would end the run) on ground forces that obey Newton and the
    # friction cone.
    params = rome.HybridContactPlantParams(
        joint_stops=True, joint_stop_tolerance=1e-9, immediate_event_delay_s=1e-9, event_tolerance_N=1e-6,
        dynamics=rome.ConstrainedDynamicsParameters(baumgarte_alpha_per_s=20.0, baumgarte_beta_per_s=20.0))
    for field in ["joint_stops=True", "joint_stop_tolerance=1e-09", "baumgarte_alpha_per_s=20.0"]:
        assert field in repr(params), field
    with pytest.raises(TypeError, match="no field 'joint_stop'"):
        rome.HybridContactPlantParams(joint_stop=True)

    def stiff_hybrid_plant(m):
        graph = rome.ContactModeGraph.with_double_support("left_foot", "right_foot")
        return rome.HybridContactPlant("plant", m, graph, rome.Terrain.flat(), params)

    data, _, y_d, diagnostics = run_standing(
        model, lambda plant, tasks: rome.TaskSpaceQpController("ctrl", plant, tasks), plant_for=stiff_hybrid_plant)
    assert diagnostics["qp_failures"] == 0
    check_ground_forces(model, data, model.contact_friction_coefficients[0])
    assert data["plant.com.x"][-1] == pytest.approx(y_d[0], abs=1e-3)
