"""The stepping-stones paper's pre-impact posture NLP and its planner blocks, from Python.

Checked against sources other than the code under test: the posture by forward kinematics of the bound robot model
(the swing foot on the stone, the COM height bound, the joint limits, the paper's cost terms at their zero), the
momentum-regulation block by the LIP's cosh/sinh solution and the orbital energy (Eq. (13), (16), (17)), and the
vertical-COM MPC block by the minimum-norm input of the exact zero-order-hold double integrator (numpy least squares)
and the double integrator's own flow.
"""
import math

import numpy as np
import pytest

import rome

AMBER = "robots/amber/amber.rome.json"
G = 9.81


@pytest.fixture(scope="module")
def model():
    return rome.MultibodyModel.load(AMBER)


def xz(p):
    return np.array([p[0], p[2]])


@pytest.mark.parametrize("l,h", [(0.40, 0.0), (0.50, 0.10), (0.35, -0.15)])
def test_pre_impact_posture_puts_the_swing_foot_on_the_stone(model, l, h):
    params = rome.PreImpactPostureParams()
    optimizer = rome.PreImpactPostureOptimizer(model, params)
    stance = np.array([0.2, 0.05])
    r = optimizer.solve(rome.PreImpactPostureRequest(step_length_m=l, step_height_m=h, stance_foot_position=stance))
    assert r["success"], r["message"]
    q = np.asarray(r["q"])
    st, sw = xz(model.contact_position(q, "left_foot")), xz(model.contact_position(q, "right_foot"))
    com = model.com_position(q)
    # The constraints of Eq. (21), by forward kinematics: stance foot where asked, swing foot on the stone, COM at
    # least min_com_height_m above the lower foot, joints inside their URDF limits.
    assert st == pytest.approx(stance, abs=1e-8)
    assert sw - st == pytest.approx([l, h], abs=1e-7)
    assert com[2] - min(st[1], sw[1]) >= params.min_com_height_m - 1e-7
    lo, hi = np.asarray(model.position_lower_limits), np.asarray(model.position_upper_limits)
    assert np.all(q[3:] >= lo[3:] - 1e-8) and np.all(q[3:] <= hi[3:] + 1e-8)
    # The paper's two cost terms can both reach zero on this stone: COM at eps l ahead of the stance foot and the torso
    # upright (the small posture term w_r = 1e-4 moves them by far less than a millimetre / milliradian).
    assert com[0] - st[0] == pytest.approx(params.com_x_fraction * l, abs=1e-3)
    assert q[2] == pytest.approx(0.0, abs=1e-3)
    # What the optimizer reports is the forward kinematics of its q.
    assert r["com_x_m"] == pytest.approx(com[0] - st[0], abs=1e-9)
    assert r["com_height_m"] == pytest.approx(com[2] - st[1], abs=1e-9)
    assert r["torso_pitch_rad"] == pytest.approx(q[2], abs=1e-12)
    assert list(r["swing_foot"]) == pytest.approx(list(sw - st), abs=1e-9)


def test_pre_impact_posture_out_of_reach_falls_back_and_bad_requests_raise(model):
    optimizer = rome.PreImpactPostureOptimizer(model)
    good = optimizer.solve(rome.PreImpactPostureRequest(step_length_m=0.4))
    assert good["success"]
    far = optimizer.solve(rome.PreImpactPostureRequest(step_length_m=3.0))  # legs of about 0.9 m cannot span 3 m
    assert not far["success"]
    assert far["fallback"] == "previous_solution"
    assert np.allclose(far["q"], good["q"], atol=1e-12)
    feet = xz(model.contact_position(far["q"], "right_foot")) - xz(model.contact_position(far["q"], "left_foot"))
    assert feet[0] == pytest.approx(0.4, abs=1e-7)  # the fallback is the earlier stone's posture, not a 3 m split
    with pytest.raises(ValueError, match="nose"):
        optimizer.solve(rome.PreImpactPostureRequest(swing_contact="nose"))
    with pytest.raises(ValueError, match="non-finite"):
        optimizer.solve(rome.PreImpactPostureRequest(step_length_m=float("nan")))
    with pytest.raises(TypeError, match="no field 'step'"):
        rome.PreImpactPostureRequest(step=0.4)
    assert "com_x_fraction=0.6" in repr(rome.PreImpactPostureParams())


def planner_diagram(x, z0, L, l, h, p_z, pdot_z, E_star=0.5, N=20):
    """Sources -> MomentumRegulationPlannerSystem -> VerticalComMpcSystem (its target from the planner)."""
    builder = rome.DiagramBuilder()
    planner = builder.add_system(
        rome.MomentumRegulationPlannerSystem("planner", rome.MomentumRegulationPlannerParams(target_orbital_energy=E_star)))
    mpc = builder.add_system(
        rome.VerticalComMpcSystem("mpc", rome.VerticalComMpcSystemParams(mpc=rome.VerticalComMpcParams(horizon_steps=N))))
    for name, value in [("com", [x, z0, L / z0, 0.0]), ("L", [L]), ("step", [l, h]), ("height", [z0]),
                        ("vertical", [p_z, pdot_z])]:
        builder.add_system(rome.ConstantVectorSource(name, value))
    builder.connect("com", "y", "planner", "com_state")
    builder.connect("L", "y", "planner", "angular_momentum")
    builder.connect("step", "y", "planner", "step")
    builder.connect("height", "y", "planner", "pre_impact_com_height")
    builder.connect("planner", "vertical_com_target", "mpc", "target")
    builder.connect("vertical", "y", "mpc", "com_vertical_state")
    return builder.build(), planner, mpc


def test_momentum_regulation_block_follows_the_lip_and_feeds_the_mpc_block():
    x, z0, L, l, E_star, eps = -0.1, 0.8, 0.6, 0.4, 0.5, 0.6
    p0, v0, N = 0.82, 0.05, 20
    diagram, planner, mpc = planner_diagram(x, z0, L, l, 0.0, p0, v0, E_star, N)
    simulator = rome.Simulator(diagram)
    t_read = 2e-4  # after the MPC's first periodic solve (t = 0), before its second (1 ms)
    assert simulator.advance_to(t_read).ok()
    ctx = simulator.context
    out = {p: diagram.eval_subsystem_output(planner, p, ctx) for p in planner.output_port_names()}
    # Eq. (13): the LIP from (x, L) reaches eps l at T with momentum L_T (cosh/sinh, written here).
    lam = math.sqrt(G / z0)
    T = out["time_to_impact"][0]
    b = L / (z0 * lam)
    assert x * math.cosh(lam * T) + b * math.sinh(lam * T) == pytest.approx(eps * l, rel=1e-9)
    L_T = z0 * lam * (x * math.sinh(lam * T) + b * math.cosh(lam * T))
    assert out["predicted_pre_impact_momentum"][0] == pytest.approx(L_T, rel=1e-9)
    # Eq. (17) + (16): with u_des the post-impact state lies on the orbit of energy E*.
    u_des = out["u_des"][0]
    L_plus, x_plus = L_T + l * u_des, (eps - 1) * l
    assert (L_plus / z0) ** 2 - lam**2 * x_plus**2 == pytest.approx(E_star, rel=1e-9)
    assert list(out["vertical_com_target"]) == pytest.approx([z0, u_des, T], rel=1e-12)
    assert out["status"][0] == 0
    # The block's plan is the planner's, computed by another path (the pure planner on the same numbers).
    assert planner.calc_plan(diagram.get_subsystem_context(planner, ctx))["u_des"] == pytest.approx(u_des, rel=1e-12)
    # MPC block: minimum-norm input to (z0, u_des) in T from the measured (p0, v0) (the bound u >= -g inactive).
    dt = T / N
    rows = np.array([[dt**2 / 2 + (N - 1 - k) * dt**2 for k in range(N)], [dt] * N])
    u = np.linalg.lstsq(rows, np.array([z0 - p0 - v0 * T, u_des - v0]), rcond=None)[0]
    assert np.all(u > -G)
    assert np.allclose(diagram.eval_subsystem_output(mpc, "planned_inputs", ctx), u, atol=1e-8)
    # Its output at t_read is the double integrator's flow from the measured state under u_0.
    desired = diagram.eval_subsystem_output(mpc, "com_height_desired", ctx)
    assert list(desired) == pytest.approx([p0 + v0 * t_read + 0.5 * u[0] * t_read**2, v0 + u[0] * t_read, u[0]],
                                          abs=1e-10)
    assert diagram.eval_subsystem_output(mpc, "qp_status", ctx)[0] == 0


def test_planner_blocks_refuse_bad_parameters():
    with pytest.raises(ValueError, match="target_orbital_energy|impact_fraction"):
        rome.MomentumRegulationPlannerSystem("p", rome.MomentumRegulationPlannerParams(impact_fraction=1.5))
    with pytest.raises(ValueError, match="control_period"):
        rome.VerticalComMpcSystem("m", rome.VerticalComMpcSystemParams(control_period_s=-1.0))
    assert "control_period_s=0.001" in repr(rome.VerticalComMpcSystemParams())
