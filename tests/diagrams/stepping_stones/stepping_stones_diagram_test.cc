// Closed-loop stepping-stones walking (Algorithm 1 of the stepping-stones paper) on AMBER: the example's diagram
// run event by event, 12 steps on flat ground with l = 0.4 m: no fall, convergence to a periodic orbit (post-impact
// L_y of the last steps within 1 %), L+ within 3 % of the planner's L_des, touchdowns within 2 cm of the stone
// centres. The 30-step sweep over the paper's periodic footholds is stepping_stones_walking_sweep_test (slow).
#include "diagrams/stepping_stones/stepping_stones_diagram.h"

#include <gtest/gtest.h>

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
    DeclareOutputPort("u", nu, [nu](const LeafContext&, Eigen::VectorXd* y) { y->setZero(nu); }, Feedthrough::None());
    DeclareOutputPort("qp_failures", 1, [](const LeafContext&, Eigen::VectorXd* y) { y->setZero(1); }, Feedthrough::None());
  }
};

TEST(SteppingStonesDiagram, ControllerIsAParameterOfTheBuilder) {
  const int steps = 6;
  SteppingStonesDiagramParams params;
  params.swing_foot_gains = {5.0, 300.0, 35.0};  // a differently tuned task-space QP, through the same seam
  SteppingStonesDiagramParams tuned = params;
  const test::WalkResult r = test::Walk(PeriodicSteppingStones(0.4, 0.0, steps + 2), steps, params, TaskSpaceQpControllerFactory(tuned));
  ASSERT_EQ(r.status.kind(), SimulatorStatus::Kind::kSuccess) << r.status.ToString();
  EXPECT_EQ(static_cast<int>(r.steps.size()), steps);
  test::ExpectPhysicalContact(r, "tuned TSC");
  try {
    BuildSteppingStonesDiagram(PeriodicSteppingStones(0.4, 0.0, 8), params,
                               [](const SteppingStonesControllerSpec& spec) { return std::make_unique<NoStatusController>(spec.model->nv(), spec.model->nu()); });
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "BuildSteppingStonesDiagram: controller 'bare' has no output port 'qp_status' (a vector of size 1); a stepping-stones controller needs "
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
      const Eigen::VectorXd& planned = d.controller->EvalOutput(d.diagram->GetSubsystemContext(*d.controller, c), "contact_forces");
      const int stance = mode == 0 ? left : right, old = mode == 0 ? right : left;
      EXPECT_GT(planned[3 * stance + 2], 1.0) << "t = " << c.time() << ": the new stance foot carries the robot";
      EXPECT_EQ(planned.segment<3>(3 * old).norm(), 0.0) << "t = " << c.time() << ": the old stance foot carries nothing";
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
  for (const auto& [name, factory] : {std::pair<std::string, SteppingStonesControllerFactory>{"tsc-qp", TaskSpaceQpControllerFactory(params)},
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
