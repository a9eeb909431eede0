// TaskSpaceQpController in closed loop with the HybridContactPlant (Simulator, 1 kHz zero-order-held QP): AMBER
// holds a double-support posture and a single-support posture with the swing foot in the air for 2 s; the output
// errors converge below 1 mm, the robot does not fall, the ground forces stay unilateral and inside the friction
// cone, and no QP fails. Separate binary (label slow): about 1 s in Release, minutes under Debug sanitizers.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/plants/hybrid_contact_plant.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

using test::AmberDoubleSupportPose;
using test::AmberSingleSupportPose;
using test::LoadRobot;
using test::TaskValues;

using Tasks = std::vector<std::shared_ptr<const TaskSpaceTask>>;

Eigen::VectorXd Stack(const Eigen::VectorXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& c) {
  Eigen::VectorXd d(a.size() + b.size() + c.size());
  d << a, b, c;
  return d;
}

struct ClosedLoopResult {
  Eigen::VectorXd final_error;
  double worst_friction_ratio = 0;
  double min_normal_force = 1e9;
  double qp_failures = 0;
  double worst_pyramid_excess = -1e9;  // [N] max of |F_x| − μ' F_z over the stance contacts (μ' of the controller)
  SimulatorStatus status;
};

ClosedLoopResult RunClosedLoop(std::shared_ptr<const MultibodyModel> model, const ContactModeGraph& graph,
                               const Eigen::VectorXd& q0, const Tasks& tasks, const Eigen::VectorXd& y_desired,
                               double duration_s, const TaskSpaceQpParams& params = {}) {
  DiagramBuilder builder;
  HybridContactPlantParams plant_params;
  auto* plant =
      builder.AddSystem(std::make_unique<HybridContactPlant>("amber", model, graph, Terrain::Flat(), plant_params));
  auto* controller = builder.AddSystem(
      std::make_unique<TaskSpaceQpController>("tsc", model, ActiveContactsPerMode(*plant), tasks, params));
  const int ny = controller->num_task_outputs();
  builder.AddSystem(std::make_unique<ConstantVectorSource>(
      "desired", Stack(y_desired, Eigen::VectorXd::Zero(ny), Eigen::VectorXd::Zero(ny))));
  builder.Connect("amber", "state", "tsc", "state");
  builder.Connect("amber", "mode", "tsc", "mode");
  builder.Connect("desired", "y", "tsc", "desired");
  builder.Connect("tsc", "u", "amber", "u");
  auto diagram = builder.Build("amber_tsc");
  SimulatorConfig config;
  config.relative_tolerance = 1e-8;
  config.absolute_tolerance = 1e-9;
  Simulator sim(*diagram, config);
  LeafContext& pc = diagram->GetMutableSubsystemContext(*plant, sim.get_mutable_context());
  plant->SetState(pc, q0, Eigen::VectorXd::Zero(model->nv()), graph.initial_mode);
  const LeafContext& cc = diagram->GetSubsystemContext(*controller, sim.get_context());
  ClosedLoopResult r;
  sim.set_monitor([&](const Context&) {
    const Eigen::VectorXd& f = plant->EvalOutput(pc, "contact_forces");
    for (int c = 0; c < model->num_contacts(); ++c) {
      if (!(plant->active_contacts(pc.mode()) & ContactBit(c))) continue;
      r.min_normal_force = std::min(r.min_normal_force, f[3 * c + 2]);
      r.worst_friction_ratio = std::max(r.worst_friction_ratio, std::abs(f[3 * c]) / f[3 * c + 2]);
      const double mu =
          params.friction_coefficient >= 0 ? params.friction_coefficient : model->contacts()[c].friction_coefficient;
      r.worst_pyramid_excess =
          std::max(r.worst_pyramid_excess, std::abs(f[3 * c]) - params.friction_margin * mu * f[3 * c + 2]);
    }
    return EventStatus::Succeeded();
  });
  r.status = sim.AdvanceTo(duration_s);
  const Eigen::VectorXd x = pc.continuous_state();
  r.final_error = TaskValues(*model, tasks, x.head(model->nv()), x.tail(model->nv())) - y_desired;
  r.qp_failures = controller->EvalOutput(cc, "qp_failures")[0];
  std::printf(
      "  closed loop %.1f s: %s, final |error| %.2e, min F_z %.1f N, max |F_x|/F_z %.3f, %ld steps, %ld samples\n",
      duration_s, r.status.ToString().c_str(), r.final_error.cwiseAbs().maxCoeff(), r.min_normal_force,
      r.worst_friction_ratio, sim.statistics().steps, sim.statistics().discrete_samples);
  return r;
}

TEST(TaskSpaceQpController, AmberHoldsADoubleSupportPostureInClosedLoop) {
  auto model = LoadRobot("amber");
  ContactModeGraph graph;
  graph.modes = {{"double_support", {"left_foot", "right_foot"}}};
  graph.initial_mode = "double_support";
  const Tasks tasks = {std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}),
                       std::make_shared<BodyPitchTask>("torso_pitch", *model, "torso")};
  const Eigen::VectorXd q0 = AmberDoubleSupportPose(*model);
  // Start 2 cm above the desired COM height, 1 cm behind, torso 0.1 rad off.
  const Eigen::VectorXd y_desired =
      TaskValues(*model, tasks, q0, Eigen::VectorXd::Zero(7)) + Eigen::Vector3d(0.01, -0.02, 0.1);
  const ClosedLoopResult r = RunClosedLoop(model, graph, q0, tasks, y_desired, 2.0);
  ASSERT_TRUE(r.status.ok()) << r.status.ToString();
  EXPECT_LT(r.final_error.cwiseAbs().maxCoeff(), 1e-3);
  EXPECT_GT(r.min_normal_force, 0.0);
  EXPECT_LE(r.worst_friction_ratio, 0.8 + 1e-6);
  EXPECT_EQ(r.qp_failures, 0.0);
}

TEST(TaskSpaceQpController, AmberHoldsASingleSupportPostureWithTheSwingFootInTheAir) {
  auto model = LoadRobot("amber");
  ContactModeGraph graph;
  graph.modes = {{"left_stance", {"left_foot"}}};
  graph.initial_mode = "left_stance";
  // On one point foot the angular momentum about the foot changes only through gravity, L̇ = m g (x_com − x_foot).
  // Holding COM x above the foot (a task here, instead of the torso pitch of the walking outputs) keeps L = 0, so
  // the torso pitch (the zero dynamics) settles wherever the other motions leave it instead of drifting.
  const Tasks tasks = {std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}),
                       PointPositionTask::ForContact("swing_foot", *model, "right_foot", {Axis::kX, Axis::kZ})};
  const Eigen::VectorXd q0 = AmberSingleSupportPose(*model, 0.12, 0.08);
  const Eigen::VectorXd y0 = TaskValues(*model, tasks, q0, Eigen::VectorXd::Zero(7));
  Eigen::VectorXd y_desired = y0;
  y_desired[1] -= 0.01;  // COM 1 cm lower
  y_desired[2] += 0.03;  // swing foot 3 cm further forward
  y_desired[3] += 0.02;  // and 2 cm higher
  const ClosedLoopResult r = RunClosedLoop(model, graph, q0, tasks, y_desired, 2.0);
  ASSERT_TRUE(r.status.ok()) << r.status.ToString();
  EXPECT_LT(r.final_error.cwiseAbs().maxCoeff(), 1e-3) << r.final_error.transpose();
  EXPECT_GT(r.min_normal_force, 0.0);
  EXPECT_LE(r.worst_friction_ratio, 0.8 + 1e-6);
  EXPECT_EQ(r.qp_failures, 0.0);
}

// A single stance, the COM sent 2 cm forward, with a low friction pyramid in the controller (μ' = 0.1; the plant keeps
// the model's μ, so nothing slips) and a swing foot sent 5 cm forward and up: the stance force sits on the pyramid's
// edge while the legs move fast, so over each 1 ms zero-order-held sample the plant's force (judged at every integrator
// step, independently of the QP) drifts past the edge the QP planned on. With predict_hold_drift the QP also holds the
// edge for the force extrapolated to the end of the sample; the excess left is the extrapolation's second-order error.
TEST(TaskSpaceQpController, PredictedHoldDriftKeepsThePlantsStanceForceInsideThePyramidOverEachHeldSample) {
  auto model = LoadRobot("amber");
  ContactModeGraph graph;
  graph.modes = {{"left_stance", {"left_foot"}}};
  graph.initial_mode = "left_stance";
  const Tasks tasks = {std::make_shared<ComPositionTask>("com", std::vector<Axis>{Axis::kX, Axis::kZ}),
                       PointPositionTask::ForContact("swing_foot", *model, "right_foot", {Axis::kX, Axis::kZ})};
  const Eigen::VectorXd q0 = AmberSingleSupportPose(*model, 0.12, 0.08);
  Eigen::VectorXd y_desired = TaskValues(*model, tasks, q0, Eigen::VectorXd::Zero(7));
  y_desired[0] += 0.02;  // COM 2 cm forward: the stance force leans on the pyramid's edge
  y_desired[2] += 0.05;
  y_desired[3] += 0.05;
  TaskSpaceQpParams params;
  params.friction_coefficient = 0.1;
  params.friction_margin = 1.0;
  const ClosedLoopResult off = RunClosedLoop(model, graph, q0, tasks, y_desired, 0.3, params);
  params.predict_hold_drift = true;
  const ClosedLoopResult on = RunClosedLoop(model, graph, q0, tasks, y_desired, 0.3, params);
  std::printf("  |F_x| - mu' F_z at worst: %.4f N without, %.4f N with the predicted drift\n", off.worst_pyramid_excess,
              on.worst_pyramid_excess);
  ASSERT_TRUE(off.status.ok()) << off.status.ToString();
  ASSERT_TRUE(on.status.ok()) << on.status.ToString();
  EXPECT_GT(off.worst_pyramid_excess, 0.05);  // the scenario drifts out of the planned pyramid without the prediction
  EXPECT_LT(on.worst_pyramid_excess, 0.1 * off.worst_pyramid_excess);
  EXPECT_GT(on.min_normal_force, 0.0);
  EXPECT_EQ(on.qp_failures, 0.0);
}

}  // namespace
}  // namespace rome
