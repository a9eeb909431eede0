// HybridContactPlant: touchdown times against free fall, the impact reset, falls, and static stances.
#include "systems/plants/hybrid_contact_plant.h"

#include <limits>

#include <gtest/gtest.h>

#include <cmath>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/controllers/joint_pd_controller.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> Load(const std::string& robot) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/" + robot + "/" + robot + ".rome.json"), {.euler_floating_base = true}));
}

SimulatorConfig Tight() {
  SimulatorConfig c;
  c.relative_tolerance = 1e-10;
  c.absolute_tolerance = 1e-10;
  return c;
}

// AMBER dropped from 0.3 m above the ground with both legs at the nominal pose, passive.
TEST(HybridContactPlant, TouchdownTimeMatchesFreeFallAndImpactStopsTheFeet) {
  auto model = Load("amber");
  HybridContactPlant plant("amber", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat());
  auto context = plant.CreateDefaultLeafContext();
  Eigen::VectorXd q = model->q_nominal();
  const double drop = 0.3;
  q[1] += drop;
  plant.SetState(*context, q, Eigen::VectorXd::Zero(model->nv()), "flight");
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  const LeafContext* ctx = context.get();
  MultibodyWorkspace ws(*model);
  // The feet start drop + z0 above the ground (z0: the nominal pose's foot height, ~0).
  const double z0 = CalcContactHeight(*model, ws, model->q_nominal(), 0);
  ASSERT_NEAR(z0, 0.0, 1e-5);
  Simulator sim(plant, std::move(context), Tight());
  const double t_expected = std::sqrt(2 * (drop + z0) / 9.81);
  // Just before touchdown: still in flight, free fall.
  ASSERT_TRUE(sim.AdvanceTo(t_expected - 1e-4).ok());
  EXPECT_EQ(ctx->mode(), plant.GetModeIndex("flight"));
  const Eigen::VectorXd v_before = ctx->continuous_state().tail(model->nv());
  const double ke_before_est = CalcKineticEnergy(*model, ws, ctx->continuous_state().head(model->nv()), v_before);
  ASSERT_TRUE(sim.AdvanceTo(t_expected + 1e-4).ok());
  ASSERT_GE(sim.statistics().events.size(), 1u);
  const EventRecord& ev = sim.statistics().events[0];
  EXPECT_NEAR(ev.time, t_expected, 1e-8);
  EXPECT_EQ(ev.mode_after, plant.GetModeIndex("stance"));
  // Right after the impact both feet are at rest (plastic impact with both feet).
  const Eigen::VectorXd qq = ctx->continuous_state().head(model->nv()), vv = ctx->continuous_state().tail(model->nv());
  for (int c = 0; c < 2; ++c)
    EXPECT_LT(CalcContactPointVelocity(*model, ws, qq, vv, c, 0).norm(), 1e-3) << "contact " << c;
  // Kinetic energy does not increase across the impact (it was ~ m g drop before).
  EXPECT_LT(CalcKineticEnergy(*model, ws, qq, vv), ke_before_est);
  EXPECT_NEAR(ke_before_est, model->total_mass() * 9.81 * drop, 0.02 * model->total_mass() * 9.81 * drop);
}

TEST(HybridContactPlant, PassiveRobotCollapsesAndTheRunEndsAsAFall) {
  auto model = Load("amber");
  HybridContactPlantParams params;
  params.min_base_height_m = 0.8;
  HybridContactPlant plant("amber", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat(),
                           params);
  auto context = plant.CreateDefaultLeafContext();
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  Simulator sim(plant, std::move(context));
  const SimulatorStatus status = sim.AdvanceTo(5.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kFailed) << status.ToString();
  EXPECT_NE(status.message.find("robot fell"), std::string::npos) << status.message;
  EXPECT_EQ(status.system, "amber");
}

TEST(HybridContactPlant, TouchdownBetweenStonesIsAFall) {
  auto model = Load("amber");
  // Stones far from where the feet come down (x ~ 0).
  HybridContactPlant plant("amber", model, ContactModeGraph::Hopping("left_foot", "right_foot"),
                           Terrain::Stones({{-1.0, 0.0, 0.2}, {1.0, 0.0, 0.2}}));
  auto context = plant.CreateDefaultLeafContext();
  Eigen::VectorXd q = model->q_nominal();
  q[1] += 0.1;
  plant.SetState(*context, q, Eigen::VectorXd::Zero(model->nv()), "flight");
  context->FixInputPort(0, Eigen::VectorXd::Zero(model->nu()));
  MultibodyWorkspace ws(*model);
  const double z0 = CalcContactHeight(*model, ws, model->q_nominal(), 0);
  Simulator sim(plant, std::move(context), Tight());
  const SimulatorStatus status = sim.AdvanceTo(2.0);
  EXPECT_EQ(status.reason, SimulatorStatus::Reason::kFailed);
  EXPECT_NE(status.message.find("not on any stone"), std::string::npos) << status.message;
  EXPECT_NEAR(status.time, std::sqrt(2 * (0.1 + z0) / 9.81), 1e-8);
}

TEST(HybridContactPlant, UnknownContactInModeGraphIsNamed) {
  auto model = Load("amber");
  try {
    HybridContactPlant plant("amber", model, ContactModeGraph::Hopping("left_toe", "right_foot"), Terrain::Flat());
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'left_toe'"), std::string::npos) << e.what();
  }
}

TEST(HybridContactPlant, NegativeOrNanPlannedLiftoffForceIsNamed) {
  auto model = Load("amber");
  for (double bad : {-1.0, std::numeric_limits<double>::quiet_NaN()}) {
    HybridContactPlantParams params;
    params.planned_liftoff_force_N = bad;
    try {
      HybridContactPlant plant("amber", model, ContactModeGraph::AlternatingSingleSupport("left_foot", "right_foot"),
                               Terrain::Flat(), params);
      FAIL() << bad;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find("planned_liftoff_force_N"), std::string::npos) << e.what();
    }
  }
}

// Gravity compensation as the feedforward of a joint PD around the nominal pose (constant torques alone
// leave the upright stance an unstable equilibrium: integration error grows at ~sqrt(g/l)).
TEST(HybridContactPlant, FlatFootedStanceUnderGravityCompensationStaysStill) {
  auto model = Load("exoskeleton");
  ContactModeGraph graph;
  graph.modes = {{"double_support", {"left_foot", "right_foot"}}};
  graph.initial_mode = "double_support";
  DiagramBuilder builder;
  auto* plant = builder.AddSystem(std::make_unique<HybridContactPlant>("exo", model, graph, Terrain::Flat()));
  const int nu = model->nu();
  JointPdGains gains{Eigen::VectorXd::Constant(nu, 500.0), Eigen::VectorXd::Constant(nu, 50.0),
                     model->B().transpose() * model->q_nominal(),
                     CalcStanceGravityCompensation(*model, plant->active_contacts(0), model->q_nominal())};
  builder.AddSystem(std::make_unique<JointPdController>("pd", model->B(), gains));
  builder.Connect("exo", "state", "pd", "state");
  builder.Connect("pd", "u", "exo", "u");
  auto diagram = builder.Build("exo_standing");
  Simulator sim(*diagram, Tight());
  const LeafContext& ctx = diagram->GetSubsystemContext(*plant, sim.get_context());
  double worst = 0;
  sim.set_monitor([&](const Context&) {
    worst = std::max(worst, ctx.continuous_state().tail(model->nv()).cwiseAbs().maxCoeff());
    return EventStatus::Succeeded();
  });
  ASSERT_TRUE(sim.AdvanceTo(2.0).ok());
  EXPECT_LT(worst, 1e-6);
  // The feet carry the weight: total normal force = m g.
  const Eigen::VectorXd& f = plant->EvalOutput(ctx, "contact_forces");
  EXPECT_NEAR(f[2] + f[5], model->total_mass() * 9.81, 1e-6 * model->total_mass() * 9.81);
  EXPECT_EQ(plant->EvalOutput(ctx, "contact_violation").sum(), 0.0);
}

double RodLength(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q, int loop) {
  const auto& l = model.loop_closures()[loop];
  return (CalcPointPosition(model, ws, q, l.body_a, l.point_a) - CalcPointPosition(model, ws, q, l.body_b, l.point_b))
      .norm();
}

TEST(HybridContactPlant, CassieStandingUnderPdKeepsAchillesRodLength) {
  auto model = Load("cassie");
  ASSERT_EQ(model->num_loop_closures(), 2);
  ContactModeGraph graph;
  graph.modes = {{"double_support", {"left_foot", "right_foot"}}};
  graph.initial_mode = "double_support";
  DiagramBuilder builder;
  auto* plant = builder.AddSystem(std::make_unique<HybridContactPlant>("cassie", model, graph, Terrain::Flat()));
  // Stiff PD on hips and knees, stiffer on the toes (the ankle holds the inverted-pendulum mode of the whole
  // robot: it needs kp above about m g h / 2 per foot). No feedforward: at the nominal pose the springs are
  // undeflected, so Cassie settles into its loaded equilibrium.
  const int nu = model->nu();
  ASSERT_EQ(model->actuators()[4].joint, "left_toe");
  ASSERT_EQ(model->actuators()[9].joint, "right_toe");
  Eigen::VectorXd kp(nu);
  kp << 1000, 1000, 1000, 1000, 1500, 1000, 1000, 1000, 1000, 1500;
  JointPdGains gains{kp, 0.03 * kp, model->B().transpose() * model->q_nominal(), Eigen::VectorXd::Zero(nu)};
  builder.AddSystem(std::make_unique<JointPdController>("pd", model->B(), gains));
  builder.Connect("cassie", "state", "pd", "state");
  builder.Connect("pd", "u", "cassie", "u");
  auto diagram = builder.Build("cassie_standing");
  SimulatorConfig config;
  config.relative_tolerance = 1e-9;
  config.absolute_tolerance = 1e-10;
  Simulator sim(*diagram, config);
  const LeafContext& ctx = diagram->GetSubsystemContext(*plant, sim.get_context());
  MultibodyWorkspace ws(*model);
  double worst = 0;
  sim.set_monitor([&](const Context&) {
    const Eigen::VectorXd q = ctx.continuous_state().head(model->nv());
    for (int l = 0; l < 2; ++l) worst = std::max(worst, std::abs(RodLength(*model, ws, q, l) - 0.5012));
    return EventStatus::Succeeded();
  });
  const SimulatorStatus status = sim.AdvanceTo(5.0);
  ASSERT_TRUE(status.ok()) << status.ToString();
  EXPECT_LT(worst, 1e-6);
  // Still standing: base height within 5 cm of nominal.
  EXPECT_NEAR(ctx.continuous_state()[2], model->q_nominal()[2], 0.05);
}

}  // namespace
}  // namespace rome
