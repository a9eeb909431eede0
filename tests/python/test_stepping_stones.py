"""The stepping-stones run from Python against the same run from C++ (the stepping_stones example program): the same
steps and figures, to the digits the C++ program prints (its JSON summary holds every double in full)."""
import json
import os
import subprocess

import pytest

import rome

STEPS = 4
EXE = os.environ.get("ROME_STEPPING_STONES_EXE", "")


def python_run():
    params = rome.SteppingStonesDiagramParams.for_robot("robots/amber/amber.rome.json")
    params.supervisor.max_steps = STEPS
    terrain = rome.periodic_stepping_stones(0.4, 0.0, STEPS + 2, 0.1)  # the example's --terrain flat
    return rome.run_stepping_stones(terrain, params)


def test_params_are_python_objects():
    params = rome.SteppingStonesDiagramParams(target_orbital_energy=0.3, impact_fraction=0.55)
    params.supervisor.max_steps = 7
    assert params.supervisor.max_steps == 7
    text = repr(params)
    assert text.startswith("SteppingStonesDiagramParams(") and "target_orbital_energy=0.3" in text and "max_steps=7" in text


def test_the_planner_bound_is_a_field_that_reaches_the_run():
    assert rome.SteppingStonesDiagramParams.for_robot("robots/amber/amber.rome.json").planner.min_pre_impact_vertical_velocity_mps == -1.5
    assert rome.SteppingStonesDiagramParams.for_robot(
        "robots/cassie_planar/cassie_planar.rome.json").planner.min_pre_impact_vertical_velocity_mps == -1.0
    # AMBER down stairs (0.4, -0.1) m asks for u_des below -0.3 m/s; bounded at -0.3, every step's u_des is at the bound.
    terrain = rome.periodic_stepping_stones(0.4, -0.1, STEPS + 2, 0.1)
    params = rome.SteppingStonesDiagramParams.for_robot("robots/amber/amber.rome.json")
    params.supervisor.max_steps = STEPS
    free = rome.run_stepping_stones(terrain, params)
    params.planner.min_pre_impact_vertical_velocity_mps = -0.3
    bounded = rome.run_stepping_stones(terrain, params)
    assert free["success"] and bounded["success"]
    assert min(step["u_des_mps"] for step in free["steps"]) < -0.3 - 0.1
    assert all(step["u_des_mps"] >= -0.3 - 1e-12 for step in bounded["steps"])
    assert any(abs(step["u_des_mps"] + 0.3) < 1e-9 for step in bounded["steps"])


@pytest.mark.skipif(not EXE, reason="the stepping_stones example is not built (ROME_BUILD_EXAMPLES=OFF)")
def test_python_run_matches_the_cpp_program(tmp_path):
    summary = tmp_path / "summary.json"
    subprocess.run([EXE, "--terrain", "flat", "--steps", str(STEPS), "--summary", str(summary), "--log", str(tmp_path / "log.csv")],
                   check=True, stdout=subprocess.DEVNULL)
    cpp = json.loads(summary.read_text())
    py = python_run()
    assert cpp["success"] and py["success"]
    assert py["steps_completed"] == cpp["steps_completed"] == STEPS
    for key in ("status_kind", "controller", "sim_time_s", "mean_forward_speed_mps", "max_foothold_error_m", "qp_failures",
                "nlp_failures", "max_friction_ratio", "contact_violations"):
        assert py[key] == cpp[key], key
    assert py["tracking_rms"] == cpp["tracking_rms"]
    for key in ("steps", "rhs_evaluations", "root_evaluations", "guard_events", "discrete_samples"):
        assert py["integrator"][key] == cpp["integrator"][key], key
    for py_step, cpp_step in zip(py["steps"], cpp["steps"]):
        assert py_step["step_length_m"] == cpp_step["l"] and py_step["step_height_m"] == cpp_step["h"]
        for key in ("duration_s", "pre_impact_com_vz_mps", "u_des_mps", "post_impact_momentum", "foothold_error_m", "stone", "planned_stone",
                    "posture_ok"):
            assert py_step[key] == cpp_step[key], key
