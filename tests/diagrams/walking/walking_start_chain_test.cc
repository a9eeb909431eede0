// Gait B (0.40 m, 0.40 s, 0.10 s, 0.25 m) from standing side by side (issue 39 §1): the start gait's direct change
// into B has no plan, so the start goes through the gait graph (StandToWalkParams::chain_gait_changes, the
// walking example's change check on). Judged independently of the planner and the controller:
//  * every single support of the plan the diagram tracks, the chain's transitions included, fits every actuator's
//    torque limit by the mass-matrix inverse dynamics (plan_torque_peak.h, not the library's Newton-Euler check);
//  * from the PLANT at every integrator step: each active foot's wrench of the plant's constrained dynamics is
//    unilateral, in the friction cone of the model's μ with its CoP on the sole (PlantContactCounts), and inside each
//    single support (no impact) the robot's linear momentum changes by the plant's ground forces less m g
//    (m Δv_com = ∫ Σ F dt − m g Δt ẑ);
//  * the walk reaches gait B's orbit: the last steps' lengths, measured between the landed feet's ankles in the plant's
//    configuration at touchdown, are B's 0.40 m.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_robot_check.h"
#include "diagrams/walking/walking_run.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/contact_force_statistics.h"
#include "tests/common/sanitizer_scale.h"
#include "tests/common/source_path.h"
#include "tests/diagrams/walking/plant_contact_counts.h"
#include "tests/diagrams/walking/plan_torque_peak.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

constexpr double kGravity = 9.81;  // [m/s^2] the plant's gravity (MultibodyModel default)

struct Sample {
  double t;
  int mode;
  Eigen::Vector3d v_com, force;  // [m/s], [N] Σ of the plant's ground forces
};

TEST(WalkingStartChain, GaitBFromStandingGoesThroughTheGaitGraphWithinTheLimitsAndReachesItsOrbit) {
  if (test::kSanitizerBuild) GTEST_SKIP() << "a full walking run with a chain search: the Release suite runs it";
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const WalkingGait b{0.40, 0.40, 0.10, 0.25};
  const WalkingDiagramParams params;
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  stand.plan_check = WalkingPoseCheck(model, params);
  stand.change_check = WalkingChangeFeasibilityCheck(model, params);
  WalkingPlanReport report;
  const WalkingPlan rom_plan = BuildStandToWalkPlan(b, 6, 1, &cache, &report, stand);
  std::printf("  start chain (%zu gaits, %d transitions tried, %d failed, %.1f s):", report.start_chain.size(),
              report.chain_transitions_tried, report.chain_transitions_failed, report.chain_planning_s);
  for (const WalkingGait& g : report.start_chain)
    std::printf(" (%g, %g, %g, %g)", g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m);
  std::printf("\n");
  ASSERT_TRUE(report.start_gait_used);
  ASSERT_FALSE(report.lead_in);
  ASSERT_GT(report.start_chain.size(), 2u);  // not the direct change: through intermediate gaits
  EXPECT_NEAR(report.start_chain.front().step_length_m, stand.start_gait_step_length_m, 1e-12);
  EXPECT_NEAR(report.start_chain.back().step_length_m, b.step_length_m, 1e-12);
  EXPECT_NEAR(report.start_chain.back().ssp_duration_s, b.ssp_duration_s, 1e-12);
  EXPECT_GT(report.chain_transitions_tried, 0);

  WalkingDiagram d = BuildWalkingDiagram(model, rom_plan, params);
  const WalkingRunParams run;
  const double end = WalkingRunEndTime(d.plan, run);
  const test::TorquePeak peak = test::PeakTorque(*model, d.plan, 0.0, end, false);
  std::printf("  plan: the %s needs %.3f of its limit at t = %.3f s\n", peak.joint.c_str(), peak.limit_fraction,
              peak.time_s);
  EXPECT_LE(peak.limit_fraction, 1.0);

  MultibodyWorkspace ws(*model);
  test::PlantContactCounts counts;
  Eigen::VectorXd qdd(model->nv()), F(model->max_constraint_rows());
  ContactForceCheckParameters cop_check;
  cop_check.cop_margin_m = -5e-4;  // rounding-level CoP motion past the sole's edge between samples (as walk_to_stand)
  std::vector<Sample> samples;
  std::vector<double> landed_x;  // the landed foot's ankle x at each touchdown (SSP → DSP), from the plant's q
  int mode_seen = kWalkingDoubleSupport;
  const int left = model->contacts()[model->ContactIndex("left_foot")].body;
  const int right = model->contacts()[model->ContactIndex("right_foot")].body;
  const WalkingRunResult r = RunWalking(d, run, [&](const Context&, const WalkingRunSample& s) {
    counts.Record(*model, ws, *s.q, *s.v, *s.u, d.plant->active_contacts(s.mode), params.plant.dynamics, cop_check, qdd,
                  F);
    const Eigen::VectorXd& f = *s.contact_forces;
    samples.push_back({s.t, s.mode, CalcComVelocity(*model, ws, *s.q, *s.v), f.segment<3>(0) + f.segment<3>(3)});
    if (s.mode == kWalkingDoubleSupport && mode_seen != kWalkingDoubleSupport)
      landed_x.push_back(
          CalcLinkPose(*model, ws, *s.q, mode_seen == kWalkingLeftStance ? right : left).translation().x());
    mode_seen = s.mode;
  });
  std::printf("  %s: %d of %d steps, COM RMS (%.4f %.4f %.4f) m, band %.3f (strictly %.3f), qp infeasible %.0f\n",
              r.status.ToString().c_str(), r.steps_completed, r.steps_planned, r.com_rms_error_m.x(),
              r.com_rms_error_m.y(), r.com_rms_error_m.z(), r.force_in_band_fraction, r.force_in_band_fraction_strict,
              r.qp_infeasible_ticks);
  EXPECT_TRUE(r.success) << r.status.ToString();
  EXPECT_EQ(counts.unilateral_bad, 0);
  EXPECT_EQ(counts.friction_bad, 0);
  EXPECT_EQ(counts.cop_bad, 0);
  EXPECT_EQ(r.contact.violations, 0) << r.contact.first_violation;
  EXPECT_EQ(r.qp_infeasible_ticks, 0.0);

  // Momentum balance over each single support, 5 ms inside its ends (no impact; the lift-off is force-continuous).
  const double m = model->total_mass();
  int windows = 0;
  double worst_h = 0, worst_v = 0;
  for (size_t i = 0; i < samples.size();) {
    size_t j = i;
    while (j < samples.size() && samples[j].mode == samples[i].mode) ++j;  // [i, j): one mode
    if (samples[i].mode != kWalkingDoubleSupport && j < samples.size()) {
      const double t0 = samples[i].t + 5e-3, t1 = samples[j - 1].t - 5e-3;
      size_t a = i;
      while (samples[a].t < t0) ++a;
      size_t e = a;
      Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
      for (; e + 1 < j && samples[e + 1].t <= t1; ++e)
        impulse += 0.5 * (samples[e + 1].t - samples[e].t) * (samples[e].force + samples[e + 1].force);
      const Eigen::Vector3d residual =
          m * (samples[e].v_com - samples[a].v_com) -
          (impulse - m * kGravity * (samples[e].t - samples[a].t) * Eigen::Vector3d::UnitZ());
      worst_h = std::max(worst_h, residual.head<2>().cwiseAbs().maxCoeff());
      worst_v = std::max(worst_v, std::abs(residual.z()));
      ++windows;
    }
    i = j;
  }
  // The trapezoid rule over the monitor's samples leaves about 0.2 N s per 0.3 s window (walking_perturbation_test).
  std::printf("  momentum balance over %d single supports: largest residual %.3f N s (x, y), %.3f N s (z)\n", windows,
              worst_h, worst_v);
  EXPECT_GE(windows, 20);
  EXPECT_LT(worst_h, 0.3);
  EXPECT_LT(worst_v, 0.5);

  // Gait B's orbit: the last three steps, between consecutive landed feet.
  ASSERT_GE(landed_x.size(), 4u);
  std::printf("  last step lengths from the plant:");
  for (size_t k = landed_x.size() - 3; k < landed_x.size(); ++k) {
    const double step = landed_x[k] - landed_x[k - 1];
    std::printf(" %.4f", step);
    EXPECT_NEAR(step, b.step_length_m, 0.01) << "touchdown " << k;
  }
  std::printf(" m\n");
}

}  // namespace
}  // namespace rome
