// The stepping-stones diagram with perturbations: the plant is built from the scaled model while the controller keeps
// the nominal one, the latency block feeds the controller, and a forward push speeds the COM up against the nominal
// run (the blocks themselves are checked in tests/systems/perturbations/).
#include <gtest/gtest.h>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "tests/common/error_of.h"

namespace rome {
namespace {

// COM x-velocity of the plant at time t, from its com output.
double ComVelocityX(const SteppingStonesDiagram& d, const SteppingStonesDiagramParams& params, double t) {
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  sim.Initialize();
  EXPECT_TRUE(sim.AdvanceTo(t).ok());
  return d.plant->EvalOutput(d.diagram->GetSubsystemContext(*d.plant, sim.get_context()), "com")[3];
}

TEST(SteppingStonesPerturbations, PlantGetsTheScaledModelAndAPushSpeedsTheComUp) {
  const Terrain terrain = PeriodicSteppingStones(0.4, 0.0, 8);
  SteppingStonesDiagramParams nominal;
  nominal.supervisor.max_steps = 4;
  SteppingStonesDiagramParams perturbed = nominal;
  PerturbationParams& p = perturbed.perturbations;
  p.mass_scale = 1.05;
  p.friction_scale = 1.2;
  p.latency_samples = 1;
  ExternalPushParams push;
  push.body = "torso";
  push.start_time_s = 0.05;
  push.duration_s = 0.05;
  push.force_N = Eigen::Vector3d(100.0, 0.0, 0.0);  // 5 N s forward
  p.push = push;
  const SteppingStonesDiagram dn = BuildSteppingStonesDiagram(terrain, nominal);
  const SteppingStonesDiagram dp = BuildSteppingStonesDiagram(terrain, perturbed);
  EXPECT_NEAR(dp.plant->model().total_mass(), 1.05 * dp.model->total_mass(), 1e-12 * dp.model->total_mass());
  EXPECT_DOUBLE_EQ(dp.plant->model().contacts()[0].friction_coefficient,
                   1.2 * dp.model->contacts()[0].friction_coefficient);
  EXPECT_EQ(dp.model->total_mass(), dn.model->total_mass());  // the controller keeps the nominal model
  ASSERT_NE(dp.perturbation_blocks.push, nullptr);
  ASSERT_NE(dp.perturbation_blocks.sensor_latency, nullptr);
  EXPECT_EQ(dp.perturbation_blocks.sensor_noise, nullptr);
  EXPECT_EQ(dp.perturbation_blocks.torque_noise, nullptr);
  EXPECT_TRUE(dp.plant->HasInputPort("tau_external"));
  EXPECT_FALSE(dn.plant->HasInputPort("tau_external"));
  // Right after the push (t = 0.1 s): 5 N s on about 22.6 kg is 0.22 m/s; the stance foot and the controller take
  // some of it, but the COM must be faster than in the nominal run.
  const double faster = ComVelocityX(dp, perturbed, 0.1) - ComVelocityX(dn, nominal, 0.1);
  EXPECT_GT(faster, 0.05) << faster;
}

TEST(SteppingStonesPerturbations, APushNeedsTheHybridPlant) {
  SteppingStonesDiagramParams params;
  params.perturbations.push = ExternalPushParams{};
  params.perturbations.push->force_N = Eigen::Vector3d(1.0, 0.0, 0.0);
  const std::string e = test::ErrorOf(
      [&] { BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 4), params, nullptr, PlantKind::kBullet); });
  EXPECT_NE(e.find("perturbations.push needs the hybrid plant"), std::string::npos) << e;
}

}  // namespace
}  // namespace rome
