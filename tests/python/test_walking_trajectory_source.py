"""WalkingTrajectorySource (a WalkingPlan as a block) and its typed 'domain' port, from Python.

Checked against physics written here: the COM velocity and acceleration outputs are the time derivatives of the
position output (central differences), the aSLIP's vertical ground forces carry the point mass (F_L + F_R = m (g +
z-double-dot), Newton on the ROM), the lateral motion in single support is the H-LIP's y'' = lambda^2 (y - y_stance)
(walking paper Eq. (6)), and the swing foot of a single support (the typed domain) carries no force.
"""
import numpy as np
import pytest

import rome

G = 9.81


@pytest.fixture(scope="module")
def source():
    planner = rome.AslipPeriodicGaitPlanner(rome.AslipPeriodicGaitParams())
    plan = rome.WalkingPlan.periodic(planner, steps=3, seed=1, step_width=0.25)
    return rome.WalkingTrajectorySource("reference", plan), planner.params.aslip.mass


def outputs(system, context, t):
    context.time = t
    return {p: system.eval_output(context, p) for p in system.output_port_names()}


def test_the_source_plays_a_physically_consistent_walking_plan(source):
    system, mass = source
    plan = system.plan
    assert system.output_port_type("domain") == "rome::WalkingDomain"
    context = system.create_default_context()
    h = 1e-5
    seen = set()
    for k in range(plan.num_segments):
        seg = plan.segment(k)
        for s in np.linspace(0.1, 0.9, 5):  # inside the segment: the derivatives are smooth there
            t = seg["start_time"] + s * seg["duration"]
            now, before, after = outputs(system, context, t), outputs(system, context, t - h), outputs(system, context, t + h)
            com = now["com"]
            velocity_fd = (after["com"][0:3] - before["com"][0:3]) / (2 * h)
            acceleration_fd = (after["com"][3:6] - before["com"][3:6]) / (2 * h)
            # Lateral: the H-LIP's closed form, exact up to the differences' rounding.
            assert com[4] == pytest.approx(velocity_fd[1], abs=1e-8)
            assert com[7] == pytest.approx(acceleration_fd[1], abs=1e-7)
            # Sagittal: the aSLIP's x, z and their velocities are separate cubic Hermite interpolants of the
            # collocation nodes and the accelerations a first-order hold of the nodal values, so they agree to the
            # collocation's accuracy (measured: 5e-6 m/s and 4e-5 m/s^2 at most on this plan).
            assert com[[3, 5]] == pytest.approx(velocity_fd[[0, 2]], abs=2e-5)
            assert com[[6, 8]] == pytest.approx(acceleration_fd[[0, 2]], abs=2e-4)
            F = now["normal_force_reference"]
            assert F.sum() == pytest.approx(mass * (G + com[8]), rel=1e-9)
            domain = now["domain"]
            assert domain == seg["domain"]
            seen.add(domain)
            if domain == rome.WalkingDomain.left_stance:
                assert F[1] == pytest.approx(0.0, abs=1e-6)
            if domain == rome.WalkingDomain.right_stance:
                assert F[0] == pytest.approx(0.0, abs=1e-6)
            if domain != rome.WalkingDomain.double_support:
                assert com[7] == pytest.approx(seg["lambda_"] ** 2 * (com[1] - seg["lateral_pivot_y"]), abs=1e-6)
            reference = plan.sample(t)  # the plan read directly agrees with the block
            assert list(reference["com_position"]) == pytest.approx(list(com[0:3]), abs=1e-12)
    assert seen == {rome.WalkingDomain.left_stance, rome.WalkingDomain.right_stance, rome.WalkingDomain.double_support}


def test_the_domain_reaches_a_python_leaf_and_the_logger_in_a_diagram(source):
    system, _ = source
    planner = rome.AslipPeriodicGaitPlanner(rome.AslipPeriodicGaitParams())
    plan = rome.WalkingPlan.periodic(planner, steps=2, seed=1)
    builder = rome.DiagramBuilder()
    builder.add_system(rome.WalkingTrajectorySource("reference", plan))
    log = rome.add_vector_logger(builder, "log", [("reference", "com")], 0.01)
    diagram = builder.build()
    simulator = rome.Simulator(diagram)
    assert simulator.advance_to(plan.end_time).ok()
    ref = diagram.get_leaf("reference")
    assert diagram.eval_subsystem_output(ref, "domain", simulator.context) == plan.sample(plan.end_time)["domain"]
    data = log.data(diagram.get_subsystem_context(log, simulator.context))
    k = len(data["time"]) // 2
    assert data["reference.com.z"][k] == pytest.approx(plan.sample(data["time"][k])["com_position"][2], abs=1e-12)


def test_bad_walking_plan_arguments_raise():
    planner = rome.AslipPeriodicGaitPlanner(rome.AslipPeriodicGaitParams())
    with pytest.raises(ValueError, match="steps = 0"):
        rome.WalkingPlan.periodic(planner, steps=0)
    with pytest.raises(ValueError, match="step_width = -0.1"):
        rome.WalkingPlan.periodic(planner, steps=1, step_width=-0.1)
    with pytest.raises(ValueError, match="first_stance"):
        rome.WalkingPlan.periodic(planner, steps=1, first_stance=rome.WalkingDomain.double_support)
