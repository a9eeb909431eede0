#pragma once
// Shared by the closed-loop stepping-stones tests: runs the example's diagram with the library's run
// (RunSteppingStones, as the example does) and checks the paper's claims for
// periodic footholds (no fall, periodic orbit: post-impact L_y of the last steps within 1 %, Sec. VI-B; L+ near
// the planner's L_des, Eq. (17)-(18); touchdowns within 2 cm of the stone centres; speed in 0.4-1.6 m/s), and the
// plant's own contact forces over every integrator step (a simulator monitor): F_n ≥ 0 and |F_t| ≤ μ F_n + 1e-6.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "diagrams/stepping_stones/stepping_stones_run.h"
#include "systems/plants/contact_force_statistics.h"

namespace rome::test {

struct WalkResult {
  SimulatorStatus status;
  std::vector<StepRecord> steps;
  double mean_speed_mps = 0;
  double qp_failures = 0;  ///< the controller's (not the MPC's)
  ContactForceStatistics
      contact;          ///< the plant's contact forces, after every integrator step and event (RunSteppingStones)
  long touchdowns = 0;  ///< the plant's touchdown events
  /// [N m] per actuator, the smallest and largest torque the plant received (the controller's u port, which feeds the
  /// plant's u), over every logged sample and every integrator step.
  Eigen::VectorXd u_min, u_max;
  long u_samples = 0;  ///< logged samples and integrator steps that went into u_min, u_max
  /// [N m] A controller sub-diagram (SaturatedControllerFactory) only: the largest |u| of its inner block
  /// "controller/controller" over every integrator step, before the saturation; 0 otherwise.
  double inner_u_abs_max = 0;
};

/// Folds the torque u into r's u_min, u_max.
inline void RecordTorque(const Eigen::VectorXd& u, WalkResult* r) {
  if (r->u_samples++ == 0) {
    r->u_min = u;
    r->u_max = u;
  }
  r->u_min = r->u_min.cwiseMin(u);
  r->u_max = r->u_max.cwiseMax(u);
}

inline WalkResult Walk(const Terrain& terrain, int steps, SteppingStonesDiagramParams params = {},
                       const SteppingStonesControllerFactory& controller = nullptr) {
  params.supervisor.max_steps = steps;
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(terrain, params, controller);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  sim.Initialize();
  WalkResult r;
  const LeafSystem* inner = nullptr;
  for (int i = 0; i < d.diagram->num_leaves(); ++i)
    if (d.diagram->leaf_path(i) == "controller/controller") inner = &d.diagram->leaf(i);
  sim.add_monitor(
      [&](const Context& c) {
        RecordTorque(d.EvalControllerOutput(c, "u"), &r);
        if (inner != nullptr)
          r.inner_u_abs_max =
              std::max(r.inner_u_abs_max, d.diagram->EvalSubsystemOutput(*inner, "u", c).cwiseAbs().maxCoeff());
        return EventStatus::Succeeded();
      },
      "torques");
  // The library's run (what the example runs): contact statistics, step records, speed, success rule.
  SteppingStonesRunOptions options;
  options.max_time_s = options.chunk_s = 3.0 * steps;
  const SteppingStonesResult run = RunSteppingStones(d, sim, options);
  r.status = run.status;
  r.contact = run.contact;
  r.steps = run.steps;
  r.mean_speed_mps = run.mean_forward_speed_mps();
  for (const EventRecord& e : run.integrator.events) r.touchdowns += e.guard.rfind("touchdown_", 0) == 0 ? 1 : 0;
  r.qp_failures = d.EvalControllerOutput(sim.get_context(), "qp_failures")[0];
  // The logged torques (the logger's "controller.u" columns, at every logged sample).
  const std::vector<std::string> columns = d.logger->ColumnNames();
  int first_u = -1;
  for (size_t i = 1; i < columns.size() && first_u < 0; ++i)
    if (columns[i].rfind("controller.u.", 0) == 0 || columns[i].rfind("controller.u[", 0) == 0)
      first_u = static_cast<int>(i) - 1;
  EXPECT_GE(first_u, 0) << "no logged controller.u column";
  const LogData& log = d.logger->log(d.diagram->GetSubsystemContext(*d.logger, sim.get_context()));
  EXPECT_FALSE(log.samples.empty());
  if (first_u >= 0)
    for (const Eigen::VectorXd& sample : log.samples) RecordTorque(sample.segment(first_u, d.model->nu()), &r);
  return r;
}

/// Speed of the converged gait: Σ l / Σ T over the last `n` steps [m/s].
/// The stepping_stones example's random course for its default 30 steps (--terrain random --seed seed), whose first
/// steps a test may walk; stone_length_m as the example's for the robot (the default: point feet).
inline Terrain ExampleRandomCourse(unsigned seed, double stone_length_m = RandomSteppingStonesParams{}.stone_length_m) {
  RandomSteppingStonesParams course;
  course.num_stones = 30 + 2;
  course.seed = seed;
  course.stone_length_m = stone_length_m;
  return RandomSteppingStones(course);
}

inline double LastStepsSpeed(const WalkResult& r, int n) {
  double length = 0, duration = 0;
  for (int k = static_cast<int>(r.steps.size()) - n; k < static_cast<int>(r.steps.size()); ++k) {
    length += r.steps[k].step_length_m;
    duration += r.steps[k].duration_s;
  }
  return length / duration;
}

/// The plant's own contact forces stayed unilateral and inside the friction cone over every integrator step.
inline void ExpectPhysicalContact(const WalkResult& r, const std::string& what) {
  EXPECT_GT(r.contact.samples, 0) << what;
  EXPECT_EQ(r.contact.violations, 0) << what << ": first " << r.contact.first_violation;
  EXPECT_GE(r.contact.min_normal_force_N, 0.0) << what;
  EXPECT_LE(r.contact.max_cone_excess_N, 1e-6) << what << ": largest |F_t|/F_n " << r.contact.max_friction_ratio;
}

/// `momentum_tolerance`: relative distance of the last L+ from L_des (3 %: the task-space QP's tracking; the CLF-QP's
/// looser output tracking leaves the planner's target less exactly met).
inline void ExpectPeriodicWalk(const WalkResult& r, int steps, const std::string& what,
                               double momentum_tolerance = 0.03) {
  ASSERT_EQ(r.status.kind(), SimulatorStatus::Kind::kSuccess) << what << ": " << r.status.ToString();
  ExpectPhysicalContact(r, what);
  EXPECT_NE(r.status.message.find("completed"), std::string::npos) << what << ": " << r.status.message;
  ASSERT_EQ(static_cast<int>(r.steps.size()), steps) << what;
  for (size_t k = 0; k < r.steps.size(); ++k) {
    EXPECT_EQ(r.steps[k].stone, r.steps[k].planned_stone) << what << ", step " << k;
    EXPECT_LT(r.steps[k].foothold_error_m, 0.02) << what << ", step " << k;
  }
  // Periodic orbit: the post-impact momentum of the last steps repeats to within 1 % ...
  const int n = static_cast<int>(r.steps.size());
  for (int k = n - 3; k < n; ++k) {
    const double change = std::abs(r.steps[k].post_impact_momentum - r.steps[k - 1].post_impact_momentum) /
                          r.steps[k - 1].post_impact_momentum;
    EXPECT_LT(change, 0.01) << what << ", step " << k << ": L+ " << r.steps[k - 1].post_impact_momentum << " -> "
                            << r.steps[k].post_impact_momentum;
  }
  // ... and sits on the planner's target: Eq. (17)-(18) drive L+ to L_des.
  const StepRecord& last = r.steps.back();
  EXPECT_NEAR(last.post_impact_momentum, last.L_des, momentum_tolerance * last.L_des) << what;
  EXPECT_GT(r.mean_speed_mps, 0.4) << what;
  EXPECT_LT(r.mean_speed_mps, 1.6) << what;
  EXPECT_EQ(r.qp_failures, 0) << what;
}

}  // namespace rome::test
