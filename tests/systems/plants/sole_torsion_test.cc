// HybridContactPlant's torsional slip of a four-corner sole (HybridContactPlantParams::sole_torsion): a free block
// standing on a flat 0.20 x 0.10 m sole (corners only, mu = 0.8), pressed by its weight m g and twisted by a yaw torque
// that ramps up, k t; a constant roll torque moves its centre of pressure |e| across the sole. The run must fail as a
// torsional slip when the twist reaches what four corners hold, computed here independently of the plant's rows:
//   with corner forces in pyramids |f_x|, |f_y| <= mu' f_z (mu' = mu/sqrt(2), inscribed in the Coulomb cone), no net
//   tangential force and the CoP at (0, e): the x-forces of the two corner pairs at y = +Y and y = -Y are equal and
//   opposite, each at most mu' times the lighter pair's load (m g (1 - |e|/Y) / 2), and give at most
//   2 Y mu' m g (1 - |e|/Y) / 2 of torsion; the y-forces of the front and back pairs (equal loads m g / 2) give at
//   most X mu' m g; both bounds are reached together (every corner at its pyramid's vertex), so
//   tau_max = mu' (X + Y - |e|) m g.
// Without the check (sole_torsion = false) the welded sole holds any twist: the same ramp runs to the end.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/plants/hybrid_contact_plant.h"

namespace rome {
namespace {

constexpr double kMass = 10.0, kMu = 0.8, kHalfX = 0.10, kHalfY = 0.05, kGravity = 9.81;
constexpr double kRamp = 10.0;  // [N m/s] the twist's rate

std::shared_ptr<const MultibodyModel> Block() {
  const std::string urdf = R"(<?xml version="1.0"?>
<robot name="twisted_block">
  <link name="block">
    <inertial><origin xyz="0 0 0"/><mass value="10.0"/>
      <inertia ixx="0.05" ixy="0" ixz="0" iyy="0.08" iyz="0" izz="0.1"/></inertial>
  </link>
</robot>)";
  const std::string sidecar = R"({
  "robot": "twisted_block", "urdf": "twisted_block.urdf", "floating_base": "spatial_euler",
  "contacts": [{"name": "sole", "link": "block", "type": "flat", "friction_coefficient": 0.8,
                "points": [[0.1, 0.05, -0.05], [-0.1, 0.05, -0.05], [-0.1, -0.05, -0.05], [0.1, -0.05, -0.05]]}],
  "nominal_pose": {"base": [0.0, 0.0, 0.05, 0.0, 0.0, 0.0]}
})";
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromText(urdf, sidecar, "twisted_block.urdf", "twisted_block.rome.json"));
}

// Twists the standing block by twist0 + ramp t about z with a constant roll torque `roll` (N m) until t_final.
SimulatorStatus Twist(double roll, bool sole_torsion, double t_final, double twist0 = 0.0, double ramp = kRamp) {
  const auto model = Block();
  HybridContactPlantParams pp;
  pp.external_force_input = true;
  pp.sole_torsion = sole_torsion;
  ContactModeGraph graph;
  graph.modes = {{"stand", {"sole"}}};
  graph.initial_mode = "stand";
  DiagramBuilder b;
  const auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>("plant", model, graph, Terrain::Flat(), pp));
  // Spatial base coordinates [x, y, z, yaw, pitch, roll]: at zero angles the yaw and roll entries are the world z and
  // x torques.
  const int nv = model->nv();
  b.AddSystem(std::make_unique<TrajectorySource>("twist", nv, [=](double t, Eigen::Ref<Eigen::VectorXd> y) {
    y.setZero();
    y[3] = twist0 + ramp * t;
    y[nv - 1] = roll;
  }));
  b.AddSystem(std::make_unique<ConstantVectorSource>("no_torque", Eigen::VectorXd::Zero(model->nu())));
  b.Connect("twist", "y", "plant", "tau_external");
  b.Connect("no_torque", "y", "plant", "u");
  auto diagram = b.Build("twisted_block");
  SimulatorConfig config;
  config.relative_tolerance = 1e-10;
  config.absolute_tolerance = 1e-10;
  Simulator sim(*diagram, config);
  plant->SetState(diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context()), model->q_nominal(),
                  Eigen::VectorXd::Zero(nv), "stand");
  sim.Initialize();
  return sim.AdvanceTo(t_final);
}

double ClosedFormSlipTime(double cop_offset) {
  return kMu / std::sqrt(2.0) * (kHalfX + kHalfY - std::abs(cop_offset)) * kMass * kGravity / kRamp;
}

TEST(SoleTorsion, ATwistedSoleSlipsWhenTheTwistReachesWhatFourCornersHold) {
  for (const double e : {0.0, 0.03, -0.02}) {  // CoP offsets across the sole [m]
    const double roll = e * kMass * kGravity;  // the ground's roll torque -roll puts the CoP at |e|
    const double t_star = ClosedFormSlipTime(e);
    const SimulatorStatus status = Twist(roll, true, 2.0 * t_star);
    ASSERT_EQ(status.reason, SimulatorStatus::Reason::kFailed) << "e = " << e << ": " << status.ToString();
    EXPECT_NEAR(status.time, t_star, 1e-6 * t_star) << "e = " << e << ": " << status.ToString();
    EXPECT_NE(status.message.find("'sole' slipped torsionally"), std::string::npos) << status.message;
  }
}

TEST(SoleTorsion, WithoutTheCheckTheWeldedSoleHoldsAnyTwist) {
  const double t_star = ClosedFormSlipTime(0.0);
  const SimulatorStatus status = Twist(0.0, false, 2.0 * t_star);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kReachedBoundaryTime) << status.ToString();
}

TEST(SoleTorsion, AConstantTwistBeyondTheBoundSlipsAtOnceAndOneWithinHolds) {
  // No ramp: the plant's event publish judges the wrench right after initialisation (no witness can cross).
  const double e = 0.02, bound = kRamp * ClosedFormSlipTime(e);
  const SimulatorStatus beyond = Twist(e * kMass * kGravity, true, 0.1, 1.01 * bound, 0.0);
  ASSERT_EQ(beyond.reason, SimulatorStatus::Reason::kFailed) << beyond.ToString();
  EXPECT_LT(beyond.time, 1e-6);
  EXPECT_NE(beyond.message.find("slipped torsionally"), std::string::npos) << beyond.message;
  const SimulatorStatus within = Twist(e * kMass * kGravity, true, 0.1, 0.99 * bound, 0.0);
  EXPECT_EQ(within.reason, SimulatorStatus::Reason::kReachedBoundaryTime) << within.ToString();
}

}  // namespace
}  // namespace rome
