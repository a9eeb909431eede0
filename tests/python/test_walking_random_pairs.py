"""examples/python/walking_random_pairs.py: its draw reproduces the pairs docs/walking.md names for seed 39, and it
sorts a run as the walking issue's acceptance does (the thresholds are the issue's, not the script's)."""
import importlib.util
import pathlib

_PATH = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python" / "walking_random_pairs.py"
_SPEC = importlib.util.spec_from_file_location("walking_random_pairs", _PATH)
pairs = importlib.util.module_from_spec(_SPEC)
_SPEC.loader.exec_module(pairs)


def test_seed_39_draws_the_pairs_docs_walking_names():
    drawn = pairs.random_pairs(39, 20)
    assert drawn[0] == ((0.25, 0.41, 0.09, 0.24), (0.34, 0.45, 0.10, 0.24))
    # Pairs named in docs/walking.md's table of the 20 random pairs (in either direction).
    named = [((0.43, 0.46, 0.10, 0.27), (0.37, 0.36, 0.14, 0.27)),
             ((0.44, 0.41, 0.15, 0.28), (0.25, 0.48, 0.09, 0.23)),
             ((0.29, 0.35, 0.11, 0.27), (0.44, 0.48, 0.12, 0.27))]
    unordered = [set(p) for p in drawn]
    for pair in named:
        assert set(pair) in unordered, pair
    assert any((0.41, 0.36, 0.12, 0.23) in p for p in drawn)
    for a, b in drawn:
        for gait in (a, b):
            assert all(lo <= v <= hi for v, lo, hi in zip(gait, pairs.RANGE_MIN, pairs.RANGE_MAX)), gait


def _summary(**changes):
    summary = {"success": True, "com_rms_error_m": [0.008, 0.002, 0.001], "force_in_band_fraction_strict": 0.99,
               "qp_infeasible_ticks": 0, "contact_violations": 0}
    summary.update(changes)
    return summary


def test_a_run_is_sorted_by_the_issues_thresholds():
    assert pairs.judge(0, _summary(), "") == ("walked", "")
    assert pairs.judge(0, _summary(com_rms_error_m=[0.0101, 0.0, 0.0]), "")[0] == "failed"  # COM RMS <= 1 cm
    assert pairs.judge(0, _summary(force_in_band_fraction_strict=0.949), "")[0] == "failed"  # >= 95 % in band
    assert pairs.judge(0, _summary(qp_infeasible_ticks=1), "")[0] == "failed"
    assert pairs.judge(0, _summary(contact_violations=1), "")[0] == "failed"
    reason = "walking: gait 0.41,0.36,0.12,0.23: the left knee needs 312 N m (limit 300 N m)"
    assert pairs.judge(1, None, "planning: periodic aSLIP ...\n", reason + "\n") == ("refused", reason)
    # Exit 1 before planning, or after simulating, is bad input (an option, an output file), not a refusal.
    bad = "walking: option '--steps' is given twice (first '2'); give it once"
    assert pairs.judge(1, None, "", bad + "\n") == ("error", bad)
    assert pairs.judge(1, None, "planning: ...\nsimulating 5 s ...\n", "walking: cannot write\n")[0] == "error"
    assert pairs.judge(0, _summary(com_rms_error_m=[None, 0.0, 0.0]), "")[0] == "failed"  # a NaN written as null
    failed = "t = 6 s\nFAILED: failed at t = 6.021 s (system 'plant'): slipped\n  7 steps\n"
    assert pairs.judge(3, _summary(success=False), failed) == ("failed", failed.splitlines()[1])
