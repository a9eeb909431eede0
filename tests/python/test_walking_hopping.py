"""The walking and hopping runs from Python against the same runs from C++ (the walking and hopping programs): every
metric of the program's JSON summary that the Python result also has is the same, apart from wall-clock timings."""
import json
import os
import re
import subprocess

import pytest

import rome

WALKING_EXE = os.environ.get("ROME_WALKING_EXE", "")
HOPPING_EXE = os.environ.get("ROME_HOPPING_EXE", "")
TIMING = re.compile(r"wall|realtime|_us|solve_time|seconds_per|^time_s$")


def assert_same_metrics(py, cpp, path=""):
    """Every key of `py` that `cpp` has too holds the same value (timings excepted); returns how many were compared."""
    compared = 0
    for key, value in py.items():
        if key not in cpp or TIMING.search(key):
            continue
        if isinstance(value, dict) and isinstance(cpp[key], dict):
            compared += assert_same_metrics(value, cpp[key], path + key + ".")
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            assert len(value) == len(cpp[key]), path + key
            for i, (v, c) in enumerate(zip(value, cpp[key])):
                compared += assert_same_metrics(v, c, f"{path}{key}[{i}].")
        else:
            assert value == cpp[key], path + key
            compared += 1
    return compared


def test_run_params_are_python_objects():
    gait = rome.WalkingGait(step_length_m=0.35)
    assert "step_length_m=0.35" in repr(gait)
    with pytest.raises(ValueError, match="step_length_m"):
        rome.WalkingGait(step_length_m=0.9).validate()
    with pytest.raises(ValueError, match="rest_max_speed"):
        rome.run_hopping(run=rome.HoppingRunParams(rest_max_speed=-1.0))


@pytest.mark.skipif(not WALKING_EXE, reason="the walking example is not built (ROME_BUILD_EXAMPLES=OFF)")
def test_periodic_walking_matches_the_cpp_program(tmp_path):
    summary = tmp_path / "summary.json"
    subprocess.run([WALKING_EXE, "--scenario", "periodic", "--steps", "2", "--summary", str(summary)], check=True, stdout=subprocess.DEVNULL,
                   cwd=tmp_path)
    cpp = json.loads(summary.read_text())
    py = rome.run_walking(scenario="periodic", steps=2)
    assert py["success"] and cpp["success"] and py["steps_completed"] == 2
    assert assert_same_metrics(py, cpp) >= 10


@pytest.mark.skipif(not HOPPING_EXE, reason="the hopping example is not built (ROME_BUILD_EXAMPLES=OFF)")
def test_one_hop_matches_the_cpp_program(tmp_path):
    summary = tmp_path / "summary.json"
    subprocess.run([HOPPING_EXE, "--hops", "1", "--summary", str(summary)], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   cwd=tmp_path)
    cpp = json.loads(summary.read_text())
    py = rome.run_hopping(hops=1)
    assert py["success"] and cpp["success"] and py["hopped"]
    assert assert_same_metrics(py, cpp) >= 20
