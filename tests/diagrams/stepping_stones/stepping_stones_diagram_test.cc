// Closed-loop stepping-stones walking (Algorithm 1 of the stepping-stones paper) on AMBER: the example's diagram
// run event by event, 12 steps on flat ground with l = 0.4 m: no fall, convergence to a periodic orbit (post-impact
// L_y of the last steps within 1 %), L+ within 3 % of the planner's L_des, touchdowns within 2 cm of the stone
// centres. The 30-step sweep over the paper's periodic footholds is stepping_stones_walking_sweep_test (slow).
#include "diagrams/stepping_stones/stepping_stones_diagram.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>

#include "tests/diagrams/stepping_stones/stepping_stones_walk.h"

namespace rome {
namespace {

TEST(SteppingStonesDiagram, FlatGroundConvergesToAPeriodicOrbit) {
  const int steps = 12;
  test::ExpectPeriodicWalk(test::Walk(PeriodicSteppingStones(0.4, 0.0, steps + 2), steps), steps, "flat l = 0.4 m");
}

// Outputs are pure: evaluating every output of every block twice, at a mid-step state, changes no state and gives
// the same values.
TEST(SteppingStonesDiagram, EvaluatingOutputsChangesNothing) {
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 4;
  const Terrain terrain = PeriodicSteppingStones(0.4, 0.0, 8);
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(terrain, params);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  ASSERT_TRUE(sim.AdvanceTo(1.2345).ok());
  ASSERT_GE(sim.statistics().guard_events, 1);  // past the first touchdown
  auto& dc = static_cast<DiagramContext&>(sim.get_mutable_context());
  std::vector<State> before;
  for (int i = 0; i < dc.num_leaves(); ++i) before.push_back(dc.leaf(i).state());
  const size_t steps_before = d.supervisor->steps(d.diagram->GetSubsystemContext(*d.supervisor, dc)).size();
  std::vector<Eigen::VectorXd> first;
  for (int pass = 0; pass < 2; ++pass) {
    int k = 0;
    for (int i = 0; i < d.diagram->num_leaves(); ++i) {
      const LeafSystem& sys = d.diagram->leaf(i);
      for (int p = 0; p < sys.num_output_ports(); ++p) {
        dc.InvalidateCache();
        if (!sys.output_port(p).is_vector()) {
          sys.EvalAbstractOutput(dc.leaf(i), p);
          continue;
        }
        const Eigen::VectorXd value = sys.EvalOutput(dc.leaf(i), p);
        if (pass == 0)
          first.push_back(value);
        else
          EXPECT_EQ(value, first[k]) << d.diagram->leaf_path(i) << "." << sys.output_port(p).name;
        ++k;
      }
    }
  }
  for (int i = 0; i < dc.num_leaves(); ++i) {
    EXPECT_EQ(dc.leaf(i).state().continuous, before[i].continuous) << d.diagram->leaf_path(i);
    EXPECT_EQ(dc.leaf(i).state().discrete, before[i].discrete) << d.diagram->leaf_path(i);
    EXPECT_EQ(dc.leaf(i).state().mode, before[i].mode) << d.diagram->leaf_path(i);
  }
  EXPECT_EQ(d.supervisor->steps(d.diagram->GetSubsystemContext(*d.supervisor, dc)).size(), steps_before);
}

// The controller is a parameter of the builder: a factory with other gains walks; a block without the seam's ports
// is refused with its name.
class NoStatusController final : public LeafSystem {
 public:
  explicit NoStatusController(int nv, int nu) : LeafSystem("bare") {
    DeclareInputPort("state", 2 * nv);
    DeclareTypedInputPort<int>("mode");
    DeclareInputPort("desired", 18);
    DeclareOutputPort(
        "u", nu, [nu](const LeafContext&, Eigen::VectorXd* y) { y->setZero(nu); }, Feedthrough::None());
    DeclareOutputPort(
        "qp_failures", 1, [](const LeafContext&, Eigen::VectorXd* y) { y->setZero(1); }, Feedthrough::None());
  }
};

TEST(SteppingStonesDiagram, ControllerIsAParameterOfTheBuilder) {
  const int steps = 6;
  SteppingStonesDiagramParams params;
  params.swing_foot_gains = {5.0, 300.0, 35.0};  // a differently tuned task-space QP, through the same seam
  SteppingStonesDiagramParams tuned = params;
  const test::WalkResult r =
      test::Walk(PeriodicSteppingStones(0.4, 0.0, steps + 2), steps, params, TaskSpaceQpControllerFactory(tuned));
  ASSERT_EQ(r.status.kind(), SimulatorStatus::Kind::kSuccess) << r.status.ToString();
  EXPECT_EQ(static_cast<int>(r.steps.size()), steps);
  test::ExpectPhysicalContact(r, "tuned TSC");
  try {
    BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 8), params,
                               [](const SteppingStonesControllerSpec& spec) {
                                 return std::make_unique<NoStatusController>(spec.model->nv(), spec.model->nu());
                               });
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "BuildSteppingStonesDiagram: controller 'bare' has no output port 'qp_status' (a vector of size 1); a "
              "stepping-stones controller needs "
              "inputs state, mode, desired and outputs u, qp_failures, qp_status");
  }
}

// Every touchdown is followed, at the same instant, by the supervisor's, the MPC's and the controller's event updates:
// the plant never runs a touchdown's new contact mode on the torque of the previous mode. Checked through the
// controller's planned contact forces (a port of both controllers): right after each touchdown they load the new
// stance foot and leave the old one at zero.
TEST(SteppingStonesDiagram, ControllerResolvesAtEveryTouchdown) {
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 3;
  for (const auto& factory : {TaskSpaceQpControllerFactory(params), ClfQpControllerFactory(params)}) {
    SteppingStonesDiagram d = BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 6), params, factory);
    Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
    SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
    const int left = d.model->ContactIndex("left_foot"), right = d.model->ContactIndex("right_foot");
    int checked = 0;
    long events_seen = 0;
    sim.set_monitor([&](const Context& c) {
      if (sim.statistics().guard_events == events_seen) return EventStatus::Succeeded();
      events_seen = sim.statistics().guard_events;
      const EventRecord& e = sim.statistics().events.back();
      if (std::abs(c.time() - e.time) > 1e-12 || e.guard.rfind("touchdown_", 0) != 0) return EventStatus::Succeeded();
      const int mode = d.plant->EvalTypedOutput<int>(d.diagram->GetSubsystemContext(*d.plant, c), "mode");
      const Eigen::VectorXd& planned = d.EvalControllerOutput(c, "contact_forces");
      const int stance = mode == 0 ? left : right, old = mode == 0 ? right : left;
      EXPECT_GT(planned[3 * stance + 2], 1.0) << "t = " << c.time() << ": the new stance foot carries the robot";
      EXPECT_EQ(planned.segment<3>(3 * old).norm(), 0.0)
          << "t = " << c.time() << ": the old stance foot carries nothing";
      ++checked;
      return EventStatus::Succeeded();
    });
    const SimulatorStatus status = sim.AdvanceTo(10.0);
    EXPECT_EQ(status.kind(), SimulatorStatus::Kind::kSuccess) << status.ToString();
    EXPECT_GE(checked, 2);
  }
}

// The plant swap (sim-to-sim): one builder argument puts the same diagram on Bullet's physics world. The supervisor
// learns of every touchdown through the Bullet plant's touchdown_<foot> guards (mode changes), exactly as on the hybrid
// plant: each committed step coincides with a touchdown event, and both plants walk the same 4 steps onto the planned
// stones, their footholds within 1 cm of each other (bound ours: Bullet's 1 ms step and its non-instantaneous impact).
TEST(SteppingStonesDiagram, BulletPlantIsOneBuilderArgumentAndTheSupervisorSeesItsTouchdowns) {
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 4;
  const Terrain terrain = PeriodicSteppingStones(0.4, 0.0, 7);
  std::vector<double> footholds[2];
  for (const PlantKind kind : {PlantKind::kHybrid, PlantKind::kBullet}) {
    SteppingStonesDiagram d = BuildSteppingStonesDiagram(terrain, params, nullptr, kind);
    EXPECT_NE(dynamic_cast<const BulletWorldPlant*>(d.plant) != nullptr, kind == PlantKind::kHybrid);
    Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
    SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
    const SimulatorStatus status = sim.AdvanceTo(10.0);
    ASSERT_EQ(status.kind(), SimulatorStatus::Kind::kSuccess) << ToString(kind) << ": " << status.ToString();
    const auto& steps = d.supervisor->steps(d.diagram->GetSubsystemContext(*d.supervisor, sim.get_context()));
    ASSERT_EQ(steps.size(), 4u);
    std::vector<double> touchdowns;
    for (const EventRecord& e : sim.statistics().events)
      if (e.system == "plant" && e.guard.rfind("touchdown_", 0) == 0) touchdowns.push_back(e.time);
    ASSERT_GE(touchdowns.size(), steps.size()) << ToString(kind);
    for (const StepRecord& r : steps) {
      const double end = r.start_time_s + r.duration_s;
      double nearest = 1e9;
      for (double t : touchdowns) nearest = std::min(nearest, std::abs(t - end));
      EXPECT_LT(nearest, 1e-9) << ToString(kind) << ": a step was committed away from a touchdown";
      EXPECT_LT(r.foothold_error_m, 0.02) << ToString(kind);
      footholds[kind == PlantKind::kBullet].push_back(r.foothold_error_m);
    }
  }
  for (size_t i = 0; i < footholds[0].size(); ++i) EXPECT_NEAR(footholds[0][i], footholds[1][i], 0.01) << "step " << i;
}

// The controller swap users make: one builder call per controller on the same terrain; both walk it with physical
// contact forces (the plant's) and land every step within 2 cm of its stone.
TEST(SteppingStonesDiagram, TaskSpaceQpAndClfQpWalkTheSameTerrain) {
  const int steps = 12;
  const Terrain terrain = PeriodicSteppingStones(0.5, 0.0, steps + 2);
  SteppingStonesDiagramParams params;
  for (const auto& [name, factory] :
       {std::pair<std::string, SteppingStonesControllerFactory>{"tsc-qp", TaskSpaceQpControllerFactory(params)},
        std::pair<std::string, SteppingStonesControllerFactory>{"clf-qp", ClfQpControllerFactory(params)}}) {
    const test::WalkResult r = test::Walk(terrain, steps, params, factory);
    ASSERT_EQ(r.status.kind(), SimulatorStatus::Kind::kSuccess) << name << ": " << r.status.ToString();
    ASSERT_EQ(static_cast<int>(r.steps.size()), steps) << name;
    test::ExpectPhysicalContact(r, name);
    for (const StepRecord& s : r.steps) {
      EXPECT_EQ(s.stone, s.planned_stone) << name;
      EXPECT_LT(s.foothold_error_m, 0.02) << name;
    }
    EXPECT_EQ(r.qp_failures, 0) << name;
    EXPECT_EQ(r.touchdowns, steps) << name;
  }
}

// The seam takes a sub-diagram: the default controller wrapped in controller → Saturation (SaturatedControllerFactory).
// The QP is told limits of kQpLimitNm (below AMBER's 100 N m), the Saturation clamps at kLimitNm, a little lower, so it
// acts whenever the QP uses the last 5 N m of its range. It walks the flat stones the unconstrained controller walks
// (whose torques reach beyond both limits), with physical contact forces, and the torque the plant receives stays
// inside the Saturation's bounds at every logged sample and every integrator step.
TEST(SteppingStonesDiagram, SaturatedSubDiagramControllerWalks) {
  constexpr double kLimitNm = 60.0, kQpLimitNm = 65.0;
  const int steps = 6;
  const Terrain terrain = PeriodicSteppingStones(0.4, 0.0, steps + 2);
  SteppingStonesDiagramParams params;
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(params.robot_sidecar, {.euler_floating_base = true});
  const int nu = model.nu();
  ASSERT_GT(model.torque_limits().minCoeff(), kLimitNm);  // below the default limits
  const Eigen::VectorXd lower = Eigen::VectorXd::Constant(nu, -kLimitNm),
                        upper = Eigen::VectorXd::Constant(nu, kLimitNm);
  const test::WalkResult free = test::Walk(terrain, steps, params);
  SteppingStonesDiagramParams limited = params;
  limited.controller.torque_limits = Eigen::VectorXd::Constant(nu, kQpLimitNm);
  const test::WalkResult saturated = test::Walk(
      terrain, steps, params, SaturatedControllerFactory(TaskSpaceQpControllerFactory(limited), lower, upper));
  for (const auto* r : {&free, &saturated}) {
    const std::string what = r == &free ? "unsaturated" : "saturated";
    ASSERT_EQ(r->status.kind(), SimulatorStatus::Kind::kSuccess) << what << ": " << r->status.ToString();
    ASSERT_EQ(static_cast<int>(r->steps.size()), steps) << what;
    test::ExpectPhysicalContact(*r, what);
    for (const StepRecord& s : r->steps) {
      EXPECT_EQ(s.stone, s.planned_stone) << what;
      EXPECT_LT(s.foothold_error_m, 0.02) << what;
    }
    ASSERT_EQ(r->u_max.size(), nu) << what;
  }
  EXPECT_GT(saturated.u_samples, 1000);
  for (int i = 0; i < nu; ++i) {
    EXPECT_GE(saturated.u_min[i], -kLimitNm) << "actuator " << model.actuators()[i].joint;
    EXPECT_LE(saturated.u_max[i], kLimitNm) << "actuator " << model.actuators()[i].joint;
  }
  EXPECT_GT(std::max(free.u_max.maxCoeff(), -free.u_min.minCoeff()), kQpLimitNm)
      << "the unconstrained run never needs more than the limits";
  EXPECT_GT(saturated.inner_u_abs_max, kLimitNm) << "the saturation never acted";
  EXPECT_EQ(free.inner_u_abs_max, 0.0);  // a leaf controller: no inner block
  // The same walk: the saturation changes the gait little (speed within 10 %).
  EXPECT_NEAR(saturated.mean_speed_mps, free.mean_speed_mps, 0.1 * free.mean_speed_mps);
  // A nu mismatch is refused with the sizes.
  try {
    BuildSteppingStonesDiagram(
        terrain, params,
        SaturatedControllerFactory(TaskSpaceQpControllerFactory(params), lower.head(2), upper.head(2)));
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("need nu = 4 elements"), std::string::npos) << e.what();
  }
}

// The spec tells a controller of your own the layout of `desired`; checked against the output adapter's own port
// (its size and element names) for point feet (AMBER, 18 elements) and line feet (planar Cassie, 24).
TEST(SteppingStonesDiagram, ControllerSpecGivesTheLayoutOfDesired) {
  struct Case {
    std::string sidecar;
    int rows;
    std::vector<std::string> tasks;
  };
  const std::vector<std::string> amber_tasks{"torso_pitch", "com_height", "left_swing_foot", "right_swing_foot"};
  std::vector<std::string> cassie_tasks = amber_tasks;
  cassie_tasks.push_back("left_swing_foot_pitch");
  cassie_tasks.push_back("right_swing_foot_pitch");
  for (const Case& c : {Case{"robots/amber/amber.rome.json", 6, amber_tasks},
                        Case{"robots/cassie_planar/cassie_planar.rome.json", 8, cassie_tasks}}) {
    const SteppingStonesDiagramParams params = SteppingStonesDiagramParams::ForRobot(c.sidecar);
    SteppingStonesControllerSpec seen;
    const auto spy = [&](const SteppingStonesControllerSpec& spec) {
      seen = spec;
      return TaskSpaceQpControllerFactory(params)(spec);
    };
    const MultibodyModel model = MultibodyModel::LoadFromSidecar(c.sidecar, {.euler_floating_base = true});
    const SteppingStonesDiagram d =
        BuildSteppingStonesDiagram(PeriodicSteppingStones(0.5, 0.0, 4, SteppingStoneLengthFor(model)), params, spy);
    EXPECT_EQ(seen.num_task_rows, c.rows) << c.sidecar;
    const PortInfo& desired = d.output_adapter->output_port(d.output_adapter->GetOutputPortIndex("desired"));
    ASSERT_EQ(desired.size, 3 * seen.num_task_rows) << c.sidecar;
    ASSERT_EQ(seen.tasks.size(), c.tasks.size()) << c.sidecar;
    int next_row = 0;
    for (size_t k = 0; k < seen.tasks.size(); ++k) {
      const SteppingStonesTaskRows& t = seen.tasks[k];
      EXPECT_EQ(t.task, c.tasks[k]) << c.sidecar;
      EXPECT_EQ(t.first_row, next_row) << c.sidecar << " " << t.task;
      for (size_t j = 0; j < t.row_names.size(); ++j) {
        const int row = t.first_row + static_cast<int>(j);
        EXPECT_EQ(desired.element_names[row], t.row_names[j]) << c.sidecar;
        EXPECT_EQ(desired.element_names[seen.num_task_rows + row], "d_" + t.row_names[j]) << c.sidecar;
        EXPECT_EQ(desired.element_names[2 * seen.num_task_rows + row], "dd_" + t.row_names[j]) << c.sidecar;
      }
      next_row += static_cast<int>(t.row_names.size());
      // A swing-foot task is tracked in the other foot's stance only.
      if (t.task.rfind("left_swing", 0) == 0) {
        EXPECT_EQ(t.active_modes, std::vector<int>{seen.right_stance_mode}) << t.task;
      }
      if (t.task.rfind("right_swing", 0) == 0) {
        EXPECT_EQ(t.active_modes, std::vector<int>{seen.left_stance_mode}) << t.task;
      }
    }
    EXPECT_EQ(next_row, seen.num_task_rows) << c.sidecar;
    EXPECT_EQ(seen.tasks[2].row_names, (std::vector<std::string>{"left_foot_x", "left_foot_z"})) << c.sidecar;
  }
}

// Simulating without SetSteppingStonesInitialState is reported at the first evaluation with one line that names the
// call to make.
TEST(SteppingStonesDiagram, ForgottenInitialStateNamesTheCall) {
  SteppingStonesDiagramParams params;
  const SteppingStonesDiagram d = BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 6), params);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  try {
    sim.AdvanceTo(0.01);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("call SetSteppingStonesInitialState(diagram, params, context) before simulating"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("system 'supervisor'"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  // With the call, the same diagram runs.
  Simulator ok(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, ok.get_mutable_context());
  EXPECT_TRUE(ok.AdvanceTo(0.01).ok());
}

// The library checks the parameters' ranges before it builds anything, naming the field and the value; the program's
// options go through the same check (tests/bad_inputs/catalogue.tsv: --energy, --epsilon, --torso-gains ...).
TEST(SteppingStonesDiagram, OutOfRangeParametersFailAtOnceNamingTheFieldAndTheValue) {
  const Terrain flat = PeriodicSteppingStones(0.4, 0.0, 6);
  auto error_of = [&](const std::function<void(SteppingStonesDiagramParams&)>& change) {
    SteppingStonesDiagramParams params;
    change(params);
    try {
      BuildSteppingStonesDiagram(flat, params);
    } catch (const std::invalid_argument& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  EXPECT_EQ(error_of([](auto& p) { p.target_orbital_energy = 0.0; }),
            "SteppingStonesDiagramParams: target_orbital_energy = 0 m^2/s^2 is outside (0, 10] m^2/s^2");
  EXPECT_NE(error_of([](auto& p) { p.impact_fraction = 1.0; }).find("impact_fraction = 1 is outside (0,"),
            std::string::npos);
  EXPECT_NE(
      error_of([](auto& p) { p.torso_gains.kp = 1e308; }).find("torso_gains.kp = 1e+308 1/s^2 is outside [0, 1e+06]"),
      std::string::npos);
  EXPECT_NE(error_of([](auto& p) {
              p.controller.min_normal_force_N = 1e308;
            }).find("controller.min_normal_force_N = 1e+308 N"),
            std::string::npos);
  EXPECT_NE(error_of([](auto& p) { p.initial_com_x_m = 5.0; }).find("initial_com_x_m = 5 m is outside [-0.5, 0.5] m"),
            std::string::npos);
  EXPECT_NE(error_of([](auto& p) { p.log_period_s = std::nan(""); }).find("log_period_s = nan"), std::string::npos);
  EXPECT_EQ(error_of([](auto&) {}), "no error");
}

TEST(SteppingStonesDiagram, TerrainHelpersRejectBadInput) {
  EXPECT_THROW(PeriodicSteppingStones(0.05, 0.0, 10), std::invalid_argument);  // stones would overlap
  EXPECT_THROW(PeriodicSteppingStones(0.4, 0.0, 1), std::invalid_argument);
  RandomSteppingStonesParams p;
  p.min_gap_m = 0.8;  // above max_gap_m
  EXPECT_THROW(RandomSteppingStones(p), std::invalid_argument);
  // The random stones respect the paper's ranges.
  const Terrain t = RandomSteppingStones(RandomSteppingStonesParams{});
  for (size_t k = 1; k < t.stones().size(); ++k) {
    const double gap = t.stones()[k].x_center_m - t.stones()[k - 1].x_center_m;
    const double rise = t.stones()[k].top_height_m - t.stones()[k - 1].top_height_m;
    EXPECT_GE(gap, 0.2);
    EXPECT_LE(gap, 0.7);
    EXPECT_LE(std::abs(rise), 0.25);
  }
}

}  // namespace
}  // namespace rome
