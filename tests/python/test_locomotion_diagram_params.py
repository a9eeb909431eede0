"""The walking and hopping diagrams' parameters as Python objects, passed to run_walking and run_hopping.

Physics checks that the parameters reach the blocks:
- walking (hybrid plant, started on gait A's orbit): with the force band's reference read one control period ahead
  (WalkingDiagramParams.force_band_lead_periods = 1, the default) the plant's normal forces sit strictly inside the
  Eq. (25) band at >= 98 % of the ticks; with the paper's F_ref(t) (0) the torque held over each 1 ms tick leaves the
  plant's force one tick behind the band and the strict figure drops below 96 %
  (docs/design-notes.md#walking-strict-band);
- hopping on the Bullet plant: the flight is ballistic, so the COM's rise between lift-off and touchdown at equal
  heights is g T^2 / 8 for the air time T;
- hopping: HoppingReferenceParams.settle_time_s 0.5 s shorter moves the whole hop, and so the run's end, 0.5 s earlier.
"""
import pytest

import rome

G = 9.81


def test_walking_diagram_params_have_keyword_constructors_nested_fields_and_a_repr():
    swing = rome.SwingFootTrajectoryParams(apex_height_m=0.1)
    params = rome.WalkingDiagramParams(force_band_lead_periods=0.5, swing=swing)
    params.controller.epsilon = 0.2
    params.compensation.iterations = 3
    text = repr(params)
    for field in ["force_band_lead_periods=0.5", "apex_height_m=0.1", "epsilon=0.2", "iterations=3",
                  "plant=HybridContactPlantParams(", "bullet_plant=BulletWorldPlantParams("]:
        assert field in text, field
    with pytest.raises(TypeError, match="no field 'lead'"):
        rome.WalkingDiagramParams(lead=1.0)


def test_walking_force_band_lead_reaches_the_controller():
    strict = {}
    for lead in [0.0, 1.0]:
        result = rome.run_walking(scenario="periodic", steps=4,
                                  diagram=rome.WalkingDiagramParams(force_band_lead_periods=lead))
        assert result["success"] and result["steps_completed"] == 4
        assert result["contact_violations"] == 0
        strict[lead] = result["force_in_band_fraction_strict"]
    assert strict[1.0] >= 0.98
    assert strict[0.0] < 0.96


def test_walking_and_hopping_refuse_bad_diagram_params_and_plants():
    with pytest.raises(ValueError, match="force_band_lead_periods = 5"):
        rome.run_walking(diagram=rome.WalkingDiagramParams(force_band_lead_periods=5.0))
    with pytest.raises(ValueError, match="run_walking: plant 'foo'"):
        rome.run_walking(plant="foo")
    with pytest.raises(ValueError, match="run_hopping: plant 'ode'"):
        rome.run_hopping(plant="ode")


def test_hopping_on_bullet_flies_ballistically():
    result = rome.run_hopping(plant="bullet")
    assert result["success"] and result["plant"] == "bullet"
    assert result["contact_violations"] == 0
    T = result["air_time_s"]
    assert result["com_rise_m"] == pytest.approx(G * T * T / 8.0, rel=0.03)


def test_hopping_settle_time_moves_the_hop():
    ends = {}
    for settle in [1.5, 1.0]:
        diagram = rome.HoppingDiagramParams()
        diagram.reference.settle_time_s = settle
        assert f"settle_time_s={settle}" in repr(diagram)
        result = rome.run_hopping(diagram=diagram)
        assert result["success"]
        ends[settle] = result["simulated_s"]
    # The run ends a fixed 2.5 s after the touchdown; the air time differs by a few ms between the two hops.
    assert ends[1.5] - ends[1.0] == pytest.approx(0.5, abs=0.02)
