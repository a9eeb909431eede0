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


def test_spring_mass_system_refuses_a_non_finite_initial_state():
    # Before: a NaN initial state was accepted and the run failed later, at the first derivative.
    params = rome.SpringMassSystemParams(initial_state=[0.78, np.nan, 0.8, 0.0])
    with pytest.raises(ValueError, match=r"^system 'hopper': params\.initial_state\[1\] \(xdot \[m/s\]\) = nan must be "
                                         r"finite$"):
        rome.SpringMassSystem("hopper", params)
    params = rome.SpringMassSystemParams(initial_state=[0.78, 0.0, -0.1, 0.0])  # a leg of negative length
    with pytest.raises(ValueError, match=r"initial_state\[2\] \(L \[m\]\) = -0\.1 must be finite and > 0"):
        rome.SpringMassSystem("hopper", params)


def test_vertical_com_mpc_refuses_a_negative_horizon_and_non_finite_data():
    mpc = rome.VerticalComMpc(rome.VerticalComMpcParams(horizon_steps=10, min_horizon_s=0.02))
    # Before: a negative horizon was silently raised to min_horizon_s and solved.
    with pytest.raises(ValueError, match=r"^VerticalComMpc\.solve: horizon_s = -0\.2 s must be >= 0 .*"
                                         r"min_horizon_s = 0\.02 s"):
        mpc.solve(0.9, 0.0, 0.92, 0.0, -0.2)
    with pytest.raises(ValueError, match=r"^VerticalComMpc\.solve: v_final = nan is not finite$"):
        mpc.solve(0.9, 0.0, 0.92, np.nan, 0.3)
    # A horizon in [0, min_horizon_s) is still raised to min_horizon_s, as documented: the plan then reaches its
    # target in 0.02 s. Rising 1 mm from rest to rest in T = 0.02 s needs the double integrator's minimum-effort
    # profile, whose end state is checked by integrating its inputs here.
    plan = mpc.solve(0.9, 0.0, 0.901, 0.0, 0.005)
    assert plan["status"] == "optimal"
    dt = plan["dt"]
    assert dt * 10 == pytest.approx(0.02)
    p, v = 0.9, 0.0
    for u in plan["inputs"]:
        p, v = p + dt * v + 0.5 * dt * dt * u, v + dt * u
    assert p == pytest.approx(0.901, abs=1e-9) and v == pytest.approx(0.0, abs=1e-9)


@pytest.mark.parametrize("make, pattern", [
    # a block's bad parameters (C++ LeafSystem::ThrowError, a std::runtime_error): ValueError, not RuntimeError
    (lambda: rome.Gain("gain", 2.0, -2), r"^system 'gain': input port 'u' has negative size -2$"),
    (lambda: rome.JointPdController("pd", np.eye(1), rome.JointPdGains(kp=[1.0], kd=[1.0, 2.0], q_des=[0.0],
                                                                        u_ff=[0.0])),
     r"^system 'pd': gain 'kd' has size 2, expected nu = 1"),
    # a planner's bad parameters (std::invalid_argument)
    (lambda: rome.VerticalComMpc(rome.VerticalComMpcParams(horizon_steps=0)),
     r"^VerticalComMpc: parameter horizon_steps \(N\) must be >= 1, got 0$"),
    # a robot file that does not exist (C++ FileError, a std::runtime_error)
    (lambda: rome.MultibodyModel.load("robots/no_such_robot/no_such_robot.rome.json"),
     r"no_such_robot\.rome\.json: file does not exist"),
])
def test_bad_arguments_are_value_errors_whatever_the_cpp_exception(make, pattern):
    with pytest.raises(ValueError, match=pattern):
        make()


def test_a_python_leaf_declaring_a_port_twice_is_a_value_error():
    class Twice(rome.LeafSystem):
        def __init__(self):
            super().__init__("twice")
            self.declare_input_port("u", 1)
            self.declare_input_port("u", 2)

    with pytest.raises(ValueError, match=r"^system 'twice': input port 'u' is declared twice$"):
        Twice()


def test_a_failure_while_computing_stays_a_runtime_error():
    # Not an argument of the call that fails: evaluating an output whose input was never connected or fixed.
    gain = rome.Gain("gain", 2.0, 1)
    with pytest.raises(RuntimeError, match=r"input port 'u' of system 'gain' is not connected"):
        gain.eval_output(gain.create_default_context(), "y")
