"""C++ exceptions reach Python as Python exceptions carrying the C++ message: one bad input per layer."""
import numpy as np
import pytest

import rome


def test_framework_unknown_port_names_system_and_port():
    builder = rome.DiagramBuilder()
    builder.add_system(rome.ConstantVectorSource("source", [1.0]))
    builder.add_system(rome.Gain("gain", 2.0, 1))
    with pytest.raises(ValueError, match="no_such_port") as error:
        builder.connect("source", "no_such_port", "gain", "u")
    assert "source" in str(error.value)


def test_framework_unconnected_input_is_refused_by_build():
    builder = rome.DiagramBuilder()
    builder.add_system(rome.Gain("gain", 2.0, 1))
    with pytest.raises(Exception, match="'u'.*'gain'|'gain'.*'u'"):
        builder.build()


def test_framework_wrong_state_size():
    lip = rome.LinearInvertedPendulumSystem("lip")
    context = lip.create_default_context()
    with pytest.raises(ValueError, match="system 'lip'.*expected 2 elements, got 3"):
        context.continuous_state = [1.0, 2.0, 3.0]


def test_solver_care_with_wrong_sizes():
    with pytest.raises(ValueError) as error:
        rome.solve_care(np.eye(2), np.ones((3, 1)), np.eye(2), np.eye(1))
    assert str(error.value)  # the C++ message, one line
    assert "\n" not in str(error.value)


def test_solver_lqr_not_stabilizable():
    A = np.diag([1.0, -1.0])
    B = np.array([[0.0], [1.0]])  # the unstable mode x0 is not actuated
    with pytest.raises(ValueError, match="^LinearQuadraticRegulator: "):
        rome.lqr(A, B, np.eye(2), np.eye(1))


def test_solver_qp_bad_data_names_the_field():
    with pytest.raises(ValueError, match="solve_qp: .*H"):
        rome.solve_qp(np.array([[1.0, np.nan], [np.nan, 1.0]]), np.zeros(2))


def test_diagram_params_validate_names_the_field():
    params = rome.SteppingStonesDiagramParams(target_orbital_energy=-1.0)
    with pytest.raises(ValueError, match="target_orbital_energy"):
        params.validate()
    with pytest.raises(TypeError, match="no field 'energy'"):
        rome.SteppingStonesDiagramParams(energy=0.5)


def test_python_leaf_exception_propagates_unchanged():
    class Broken(rome.LeafSystem):
        def __init__(self):
            super().__init__("broken")
            self.declare_continuous_state(1)

        def do_calc_time_derivatives(self, context):
            raise ZeroDivisionError("broken on purpose")

    builder = rome.DiagramBuilder()
    builder.add_system(Broken())
    sim = rome.Simulator(builder.build())
    with pytest.raises(ZeroDivisionError, match="broken on purpose"):
        sim.advance_to(0.1)


def test_python_leaf_wrong_derivative_size_names_the_system():
    class WrongSize(rome.LeafSystem):
        def __init__(self):
            super().__init__("wrong_size")
            self.declare_continuous_state(2)

        def do_calc_time_derivatives(self, context):
            return [0.0]

    system = WrongSize()
    with pytest.raises(ValueError, match="system 'wrong_size': do_calc_time_derivatives returned 1 elements, expected 2"):
        system.calc_time_derivatives(system.create_default_context())


def test_run_refuses_a_course_beyond_the_legs_reach():
    # AMBER's legs reach thigh + shin = 0.4064 + 0.4667 m each (robots.md): stones 50 m apart are bad input, refused
    # before the simulation as the stepping_stones program refuses them, not a failed run.
    terrain = rome.periodic_stepping_stones(50.0, 0.0, 4, 0.1)
    with pytest.raises(ValueError, match="terrain"):
        rome.run_stepping_stones(terrain, rome.SteppingStonesDiagramParams())


def test_run_walking_refuses_a_robot_the_diagram_cannot_use():
    # AMBER is planar: the walking diagram needs a spatial base and flat feet.
    with pytest.raises(ValueError, match="walking diagram: robot .*spatial"):
        rome.run_walking("robots/amber/amber.rome.json", rome.WalkingGait(), steps=2)


def test_run_walking_refuses_a_gait_over_the_knee_limit_before_simulating():
    # (0.45 m, 0.35 s, 0.08 s, 0.20 m): its plan asks the knee for more than the URDF's 300 N m (the walking program's
    # exit 1); the error names the gait, the knee, its need and the limit.
    gait = rome.WalkingGait()
    gait.step_length_m, gait.ssp_duration_s, gait.dsp_duration_s, gait.step_width_m = 0.45, 0.35, 0.08, 0.20
    with pytest.raises(ValueError, match=r"gait 0\.45,0\.35,0\.08,0\.20: the (left|right) knee needs 3[0-9][0-9] N m "
                                         r"\(limit 300 N m\)"):
        rome.run_walking(gait=gait, steps=2, scenario="periodic")
