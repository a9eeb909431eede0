// Which K(L) our Cassie plant matches: Cassie stands on the hybrid plant (robots/cassie, both feet in line contact,
// achilles rods closed, shin and heel springs live) with its 10 motors held by a stiff joint PD at the nominal pose,
// released with the springs undeflected; after 10 s it is at rest (|v| < 1e-3). Then the leg compression s = L(q_knee)
// − L_r(q) (virtual minus real leg length, Eq. (13)) and the COM drop are compared with the spring-mass ROM's static
// deflection m g / (n_legs K(L)) for the `published` and the `identified` K(L). The expected values come from the ROM;
// the measured ones from the plant's constrained dynamics (an independent computation).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "framework/diagram.h"
#include "framework/simulator.h"
#include "systems/controllers/joint_pd_controller.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "systems/rom/cassie_leg_stiffness.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

TEST(SpringMassStandingDeflection, PlantMatchesIdentifiedStiffness) {
  auto model = std::make_shared<const MultibodyModel>(
      MultibodyModel::Load(rome::test::SourcePath("robots/cassie/cassie.urdf"), "", {.euler_floating_base = true}));
  const int nu = model->nu(), nv = model->nv();
  JointPdGains gains;
  gains.kp.resize(nu);
  gains.kd.resize(nu);
  for (int i = 0; i < nu; ++i) {
    const bool toe = model->actuators()[i].joint.find("toe") != std::string::npos;
    gains.kp(i) = toe ? 1500.0 : 3000.0;  // [N m/rad] "held" motors (ours)
    gains.kd(i) = toe ? 30.0 : 40.0;      // [N m s/rad] (the toes damp the pelvis rocking about the ankles)
  }
  gains.q_des = model->B().transpose() * model->q_nominal();
  gains.u_ff = Eigen::VectorXd::Zero(nu);
  DiagramBuilder b;
  auto* plant = b.AddSystem(std::make_unique<HybridContactPlant>(
      "plant", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat()));
  b.AddSystem(std::make_unique<JointPdController>("pd", model->B(), gains));
  b.Connect("pd", "u", "plant", "u");
  b.Connect("plant", "state", "pd", "state");
  auto diagram = b.Build("standing");
  SimulatorConfig config;
  config.relative_tolerance = 1e-8;
  config.absolute_tolerance = 1e-10;
  Simulator sim(*diagram, config);
  LeafContext& ctx = diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context());
  plant->SetState(ctx, model->q_nominal(), Eigen::VectorXd::Zero(nv), "stance");
  const double com0 = plant->EvalOutput(ctx, "com")(2);
  const auto status = sim.AdvanceTo(10.0);
  ASSERT_TRUE(status.ok()) << status.message;
  ASSERT_EQ(ctx.mode(), plant->GetModeIndex("stance")) << "a foot left the ground";
  const Eigen::VectorXd q = plant->EvalOutput(ctx, "q"), v = plant->EvalOutput(ctx, "v");
  Eigen::Index worst_v = 0;
  v.cwiseAbs().maxCoeff(&worst_v);
  EXPECT_LT(v.cwiseAbs().maxCoeff(), 1e-3)
      << "not settled: v of " << model->JointName(static_cast<int>(worst_v)) << " = " << v(worst_v);
  const double com_drop = com0 - plant->EvalOutput(ctx, "com")(2);
  const CassieVirtualLeg left(*model, "left"), right(*model, "right");
  const double L_left = left.Length(q(left.knee_index())), L_right = right.Length(q(right.knee_index()));
  const double s_left = L_left - left.RealLength(q), s_right = L_right - right.RealLength(q);
  const double L = 0.5 * (L_left + L_right), s = 0.5 * (s_left + s_right);
  EXPECT_NEAR(s_left, s_right, 1e-4);  // symmetric stance

  const double W = model->total_mass() * 9.81;
  const double K_pub = PublishedLegStiffness().stiffness.Evaluate(L);
  const double K_id = IdentifyCassieLegStiffness(left).leg.stiffness.Evaluate(L);
  const double s_pub = W / (2.0 * K_pub), s_id = W / (2.0 * K_id);
  std::printf(
      "standing on the plant: m = %.2f kg, L = %.4f m, measured s = L - L_r = %.2f mm (left %.2f, right %.2f),"
      " COM drop %.2f mm, pelvis pitch %.4f rad\n",
      model->total_mass(), L, 1e3 * s, 1e3 * s_left, 1e3 * s_right, 1e3 * com_drop, q(4));
  std::printf("  ROM m g/(2 K(L)): published K = %.0f N/m -> %.2f mm; identified K = %.0f N/m -> %.2f mm\n", K_pub,
              1e3 * s_pub, K_id, 1e3 * s_id);
  // The plant's legs are the identified springs (same chain, same spring constants), not the published quartic.
  EXPECT_LT(std::abs(s - s_id), std::abs(s - s_pub));
  EXPECT_NEAR(s / s_id, 1.0, 0.25);
}

}  // namespace
}  // namespace rome
