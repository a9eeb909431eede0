"""The sole-model parameters set from Python reach the C++ blocks and act as documented (walking issue 39, item 5).

A free 10 kg block standing on a flat 0.20 x 0.10 m sole (corners only, mu = 0.8), as in
tests/systems/plants/sole_torsion_test.cc:
  * HybridContactPlantParams.sole_torsion: a constant yaw torque just above what four corners hold slips at once, one
    just below holds, and without the check the welded sole holds the larger one. What four corners hold is computed
    here from the corner forces: pyramids |f_x|, |f_y| <= mu' f_z (mu' = mu / sqrt(2)), no net tangential force, the
    CoP at (0, e): tau_max = mu' (X + Y - |e|) m g.
  * BulletWorldPlantParams.planned_liftoff_min_contact_s: with a planned lift-off force far above the block's weight
    the planned lift-off releases the sole at the first world step, unless the contact must have touched for
    planned_liftoff_min_contact_s first: then no earlier than that.
And ContactWrenchParams.corner_cone_yaw_margin_m on the walking diagram (the exoskeleton's 0.25 x 0.10 m sole, the
CLF-QP's corner cone with the walking default's mu 0.75, inscribed: 0.530): gait A's plan asks a stance yaw moment of
up to 0.082 m F_z (plan_inverse_dynamics, docs/design-notes.md#walking-sole-torsion). With the yaw rows on the whole
sole less 2 mm, 0.530 (0.123 + 0.048) = 0.091 m F_z at the centre, gait A walks; less 45 mm, 0.530 (0.080 + 0.005) =
0.045 m F_z, below the plan's need, the controller cannot give the swing leg's reaction and the run fails.
"""
import math

import numpy as np
import pytest

import rome

MASS, MU, HALF_X, HALF_Y, G = 10.0, 0.8, 0.10, 0.05, 9.81

URDF = """<?xml version="1.0"?>
<robot name="twisted_block">
  <link name="block">
    <inertial><origin xyz="0 0 0"/><mass value="10.0"/>
      <inertia ixx="0.05" ixy="0" ixz="0" iyy="0.08" iyz="0" izz="0.1"/></inertial>
  </link>
</robot>
"""
SIDECAR = """{
  "robot": "twisted_block", "urdf": "twisted_block.urdf", "floating_base": "spatial",
  "contacts": [{"name": "sole", "link": "block", "type": "flat", "friction_coefficient": 0.8,
                "points": [[0.1, 0.05, -0.05], [-0.1, 0.05, -0.05], [-0.1, -0.05, -0.05], [0.1, -0.05, -0.05]]}],
  "nominal_pose": {"base": [0.0, 0.0, 0.05, 0.0, 0.0, 0.0]}
}
"""


@pytest.fixture(scope="module")
def block(tmp_path_factory):
    folder = tmp_path_factory.mktemp("block")
    (folder / "twisted_block.urdf").write_text(URDF)
    (folder / "twisted_block.rome.json").write_text(SIDECAR)
    return rome.MultibodyModel.load(str(folder / "twisted_block.rome.json"), euler_floating_base=True)


def four_corner_torsion_limit(cop_offset_m):
    """[N m] the yaw torque four corners with inscribed pyramids hold under m g with the CoP at (0, e)."""
    return MU / math.sqrt(2.0) * (HALF_X + HALF_Y - abs(cop_offset_m)) * MASS * G


def twist_on_hybrid_plant(block, sole_torsion, yaw_torque, roll_torque, t_final=0.1):
    params = rome.HybridContactPlantParams(external_force_input=True, sole_torsion=sole_torsion)
    assert f"sole_torsion={sole_torsion}" in repr(params)
    graph = rome.ContactModeGraph()
    graph.modes = [rome.ContactMode("stand", ["sole"])]
    graph.initial_mode = "stand"
    plant = rome.HybridContactPlant("plant", block, graph, rome.Terrain.flat(), params)
    builder = rome.DiagramBuilder()
    builder.add_system(plant)
    # Spatial base coordinates [x, y, z, yaw, pitch, roll]: at zero angles the yaw and roll entries are the world z
    # and x torques.
    builder.add_system(rome.ConstantVectorSource("twist", [0.0, 0.0, 0.0, yaw_torque, 0.0, roll_torque]))
    builder.add_system(rome.ConstantVectorSource("no_torque", np.zeros(block.nu)))
    builder.connect("twist", "y", "plant", "tau_external")
    builder.connect("no_torque", "y", "plant", "u")
    diagram = builder.build()
    simulator = rome.Simulator(diagram, rome.SimulatorConfig(relative_tolerance=1e-10, absolute_tolerance=1e-10))
    plant.set_state(diagram.get_subsystem_context(plant, simulator.context), block.q_nominal, np.zeros(block.nv),
                    "stand")
    simulator.initialize()
    return simulator.advance_to(t_final)


def test_sole_torsion_makes_a_twisted_sole_slip_at_what_its_four_corners_hold(block):
    e = 0.02  # [m] the CoP's offset across the sole, set by a roll torque e m g
    limit = four_corner_torsion_limit(e)
    beyond = twist_on_hybrid_plant(block, True, 1.01 * limit, e * MASS * G)
    assert not beyond.ok() and beyond.time < 1e-6, beyond
    assert "slipped torsionally" in beyond.message, beyond
    within = twist_on_hybrid_plant(block, True, 0.99 * limit, e * MASS * G)
    assert within.ok() and within.time == pytest.approx(0.1), within
    welded = twist_on_hybrid_plant(block, False, 1.01 * limit, e * MASS * G)  # the default: only the linear cone
    assert welded.ok() and welded.time == pytest.approx(0.1), welded


def bullet_contact_before_release_s(block, min_contact_s, drop_m=0.005, t_final=0.2):
    """[s] how long the block's sole touches before the Bullet plant releases it as a planned lift-off: the block is
    dropped drop_m onto its sole (a landing, not a contact standing at the start, which counts as settled) with a
    planned lift-off force (1e4 N) far above its weight; None if no touchdown and release happen before t_final."""
    params = rome.BulletWorldPlantParams(min_base_height_m=0.0, planned_liftoff_force_N=1e4, planned_liftoff_min_contact_s=min_contact_s)
    assert f"planned_liftoff_min_contact_s={min_contact_s}" in repr(params)
    graph = rome.ContactModeGraph()
    graph.modes = [rome.ContactMode("stand", ["sole"]), rome.ContactMode("air", [])]
    graph.transitions = [rome.ContactTransition("stand", "air", rome.ContactTransitionKind.liftoff, "sole"),
                         rome.ContactTransition("air", "stand", rome.ContactTransitionKind.touchdown, "sole")]
    graph.initial_mode = "air"
    plant = rome.BulletWorldPlant("plant", block, graph, rome.Terrain.flat(), params)
    builder = rome.DiagramBuilder()
    builder.add_system(plant)
    builder.add_system(rome.ConstantVectorSource("no_torque", np.zeros(block.nu)))
    builder.connect("no_torque", "y", "plant", "u")
    diagram = builder.build()
    simulator = rome.Simulator(diagram)
    q0 = np.array(block.q_nominal)
    q0[2] += drop_m  # q = [x, y, z, yaw, pitch, roll]
    plant.set_state(diagram.get_subsystem_context(plant, simulator.context), q0, np.zeros(block.nv), "air")
    simulator.initialize()
    stand = 0  # graph.modes' order
    dt = params.step_s
    touched = None
    for k in range(1, int(round(t_final / dt)) + 1):
        status = simulator.advance_to(k * dt)
        assert status.ok(), status
        mode = diagram.get_subsystem_context(plant, simulator.context).mode
        if touched is None and mode == stand:
            touched = k * dt
        elif touched is not None and mode != stand:
            return k * dt - touched
    return None


def test_planned_liftoff_min_contact_s_keeps_a_landed_contact_until_it_has_touched_that_long(block):
    step = rome.BulletWorldPlantParams().step_s
    at_once = bullet_contact_before_release_s(block, 0.0)
    assert at_once is not None and at_once <= 2 * step, at_once
    held = bullet_contact_before_release_s(block, 0.05)
    assert held is not None and 0.05 <= held <= 0.05 + 2 * step, held


def gait_a_on_its_orbit(yaw_margin_m):
    diagram = rome.WalkingDiagramParams()
    diagram.controller.contact.corner_wrench_cone = True
    diagram.controller.contact.corner_cone_yaw_margin_m = yaw_margin_m
    assert f"corner_cone_yaw_margin_m={yaw_margin_m}" in repr(diagram.controller.contact)
    return rome.run_walking(steps=4, scenario="periodic", diagram=diagram)


def test_corner_cone_yaw_margin_m_bounds_the_torsion_the_controller_can_ask():
    mu = rome.WalkingDiagramParams().controller.contact.corner_cone_friction_coefficient
    assert mu == 0.75, mu  # the walking default; the bounds below are written for it
    sole_x, sole_y, mu_corner = 0.125, 0.05, mu / math.sqrt(2.0)  # the exoskeleton's sole (half-sizes) and mu'
    need = 0.082  # [m F_z] gait A's largest stance yaw moment (plan_inverse_dynamics)
    wide, narrow = 0.002, 0.045
    assert mu_corner * (sole_x + sole_y - 2 * wide) > need > mu_corner * (sole_x + sole_y - 2 * narrow)
    walks = gait_a_on_its_orbit(wide)
    assert walks["success"], walks["status"]
    assert max(walks["com_rms_error_m"]) < 0.01
    starved = gait_a_on_its_orbit(narrow)  # measured with the walking example: falls at 1.70 s, COM RMS x 0.44 m
    assert not starved["success"], starved["status"]
