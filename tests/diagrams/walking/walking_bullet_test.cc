// Issue 39 §5 on the Bullet plant (joint limits off; the default four-corner sole cone, μ 0.75 and a 2 mm yaw margin,
// `walking --plant bullet --joint-limits off`): gait B on its
// orbit (started mid double support), gait A → B from standing and gait B from standing through the gait graph, 10
// steps of each gait. Judged from the PLANT at every simulator sample, with the thresholds:
//  * no foot slides more than 1 cm: each sole corner that rests on the ground (within 1 mm of it) is followed from
//    where it came to rest, in the plant's configuration, until it rises; its largest horizontal travel is the slide
//    (independent of the plant's own slip check, which must report nothing as well);
//  * the plant's ground forces (Bullet's impulses over each step) are unilateral and inside the friction cone of the
//    robot file's μ (a relative 1e-6 for the round-off of Bullet's per-point clamp, as ContactForceStatistics);
//  * the COM from the plant tracks the plan's with RMS ≤ 2 cm per axis after the first step (computed here from the
//    plant's COM and the plan at each control tick);
//  * every planned step lands on its foothold, once, and the run reaches its end.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_robot_check.h"
#include "diagrams/walking/walking_run.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/bullet_world_plant.h"
#include "tests/common/sanitizer_scale.h"
#include "tests/common/source_path.h"
#include "tests/systems/controllers/amber_test_setup.h"

namespace rome {
namespace {

constexpr double kMaxSlideM = 0.01;    // issue 39: no slide over 1 cm
constexpr double kMaxComRmsM = 0.02;   // issue 39: COM RMS <= 2 cm (Bullet)
constexpr double kRestHeightM = 1e-3;  // a sole corner rests on the ground within this height (Bullet's 1 mm spheres)
const WalkingGait kGaitA{0.30, 0.40, 0.10, 0.25};
const WalkingGait kGaitB{0.40, 0.40, 0.10, 0.25};

WalkingDiagramParams BulletParams() {
  WalkingDiagramParams params;
  params.bullet_plant.enable_joint_limits = false;  // the plans bend the ankles beyond the URDF's (the sole: defaults)
  return params;
}

StandToWalkParams Stand(const std::shared_ptr<const MultibodyModel>& model, const WalkingDiagramParams& params) {
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  stand.plan_check = WalkingPoseCheck(model, params);  // as the walking example with its default --feasibility
  stand.change_check = WalkingChangeFeasibilityCheck(model, params);
  return stand;
}

struct PlantChecks {
  double largest_slide_m = 0, largest_friction_ratio = 0, smallest_normal_N = 0;
  long friction_bad = 0, unilateral_bad = 0, ticks = 0;
  std::array<double, 3> com_rms_m{};
  std::string worst_slide;
};

// Runs `plan` on the Bullet plant and measures the checks above from the plant.
PlantChecks RunOnBullet(const std::shared_ptr<const MultibodyModel>& model, const WalkingPlan& plan,
                        const WalkingDiagramParams& params, WalkingRunParams run, WalkingRunResult& r) {
  const WalkingDiagram d = BuildWalkingDiagram(model, plan, params, PlantKind::kBullet);
  EXPECT_NE(dynamic_cast<const BulletWorldPlant*>(d.plant), nullptr);
  const int nc = model->num_contacts();
  std::vector<std::vector<Eigen::Vector3d>> rest(nc);  // each corner's resting point (NaN: not resting)
  for (int c = 0; c < nc; ++c)
    rest[c].assign(model->contacts()[c].points.size(), Eigen::Vector3d::Constant(std::nan("")));
  const double after_first_step = d.plan.segments().size() > 2 ? d.plan.segments()[2].start_time : 0.0;
  MultibodyWorkspace ws(*model);
  PlantChecks k;
  std::array<double, 3> sum_sq{};
  r = RunWalking(d, run, [&](const Context&, const WalkingRunSample& s) {
    const Eigen::VectorXd& f = *s.contact_forces;
    for (int c = 0; c < nc; ++c) {
      const ContactInfo& info = model->contacts()[c];
      const Eigen::Vector3d force = f.segment<3>(3 * c);
      k.smallest_normal_N = std::min(k.smallest_normal_N, force.z());
      if (force.z() < 0.0) ++k.unilateral_bad;
      const double tangential = force.head<2>().norm();
      if (force.z() > 0.0) k.largest_friction_ratio = std::max(k.largest_friction_ratio, tangential / force.z());
      if (tangential > info.friction_coefficient * force.z() * (1 + 1e-6) + 1e-6) ++k.friction_bad;
      for (size_t i = 0; i < info.points.size(); ++i) {
        const Eigen::Vector3d p = CalcPointPosition(*model, ws, *s.q, info.body, info.points[i]);
        Eigen::Vector3d& at = rest[c][i];
        if (p.z() > kRestHeightM) {
          at.setConstant(std::nan(""));
          continue;
        }
        if (std::isnan(at.x())) at = p;
        const double slide = (p - at).head<2>().norm();
        if (slide > k.largest_slide_m) {
          k.largest_slide_m = slide;
          char line[160];
          std::snprintf(line, sizeof line, "'%s' corner %zu at t = %.3f s", info.name.c_str(), i, s.t);
          k.worst_slide = line;
        }
      }
    }
    if (s.tick && s.t >= after_first_step) {
      ++k.ticks;
      for (int a = 0; a < 3; ++a) sum_sq[a] += std::pow(s.com[a] - s.reference.com_position[a], 2);
    }
  });
  for (int a = 0; a < 3; ++a) k.com_rms_m[a] = k.ticks > 0 ? std::sqrt(sum_sq[a] / k.ticks) : 0.0;
  std::printf(
      "  %s: t = %.3f of %.3f s, %d of %d steps (%d off target); largest slide %.4f m (%s); min F_z %.3g N, largest "
      "|F_t|/F_z %.4f (%ld outside the cone); COM RMS %.4f %.4f %.4f m; plant's slip check: %ld\n",
      r.status.ToString().c_str(), r.simulated_s, r.end_time_s, r.steps_completed, r.steps_planned,
      r.touchdowns_off_target, k.largest_slide_m, k.worst_slide.c_str(), k.smallest_normal_N, k.largest_friction_ratio,
      k.friction_bad, k.com_rms_m[0], k.com_rms_m[1], k.com_rms_m[2], r.contact.violations);
  return k;
}

void ExpectWalks(const PlantChecks& k, const WalkingRunResult& r, int min_steps) {
  EXPECT_EQ(r.status.kind(), SimulatorStatus::Kind::kLimit) << r.status.ToString();
  EXPECT_GE(r.steps_planned, min_steps);
  EXPECT_EQ(r.steps_completed, r.steps_planned);  // each step lands once (a bounce is an extra touchdown)
  EXPECT_EQ(r.touchdowns_off_target, 0);
  EXPECT_LE(k.largest_slide_m, kMaxSlideM) << k.worst_slide;
  EXPECT_EQ(r.contact.violations, 0) << r.contact.first_violation;
  EXPECT_EQ(k.unilateral_bad, 0);
  EXPECT_EQ(k.friction_bad, 0);
  EXPECT_GT(k.ticks, 1000);
  for (int a = 0; a < 3; ++a) EXPECT_LE(k.com_rms_m[a], kMaxComRmsM) << "axis " << a;
}

// Started mid double support on gait B's orbit (the walking example's --scenario periodic). Before the plant's start
// counted the standing feet as touching since the start, the trailing foot could not be released at its planned
// lift-off (50 ms later, BulletWorldPlantParams::planned_liftoff_min_contact_s) and slid 1 cm at 0.35 s.
TEST(WalkingBullet, GaitBOnItsOrbitWalksTenStepsWithoutASlide) {
  if (test::kSanitizerBuild) GTEST_SKIP() << "a full walking run on Bullet: the Release suite runs it";
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const WalkingDiagramParams params = BulletParams();
  WalkingRunParams run;
  const WalkingPlan plan = BuildPeriodicWalkingPlan(kGaitB, 10 + run.trailing_steps, 1, &cache, Stand(model, params));
  run.start_time_s = 0.5 * kGaitB.dsp_duration_s, run.start_at_rest = false;
  WalkingRunResult r;
  const PlantChecks k = RunOnBullet(model, plan, params, run, r);
  ExpectWalks(k, r, 10);
}

TEST(WalkingBullet, GaitAToGaitBFromStandingWalksTenStepsOfEachWithoutASlide) {
  if (test::kSanitizerBuild) GTEST_SKIP() << "a full walking run on Bullet: the Release suite runs it";
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const WalkingDiagramParams params = BulletParams();
  WalkingRunParams run;
  const WalkingPlan plan =
      BuildGaitChangePlan(kGaitA, kGaitB, 10, 1, &cache, nullptr, Stand(model, params), 10 + run.trailing_steps);
  WalkingRunResult r;
  const PlantChecks k = RunOnBullet(model, plan, params, run, r);
  ExpectWalks(k, r, 20);
}

TEST(WalkingBullet, GaitBFromStandingThroughTheGaitGraphWalksTenStepsWithoutASlide) {
  if (test::kSanitizerBuild) GTEST_SKIP() << "a full walking run on Bullet: the Release suite runs it";
  auto model = test::LoadRobot("exoskeleton");
  const PlanCache cache(test::TestPlanCacheDir("rome_walking_diagram_test_plans"));
  const WalkingDiagramParams params = BulletParams();
  WalkingRunParams run;
  WalkingPlanReport report;
  const WalkingPlan plan =
      BuildStandToWalkPlan(kGaitB, 10 + run.trailing_steps, 1, &cache, &report, Stand(model, params));
  ASSERT_GT(report.start_chain.size(), 2u);  // through the gait graph
  WalkingRunResult r;
  const PlantChecks k = RunOnBullet(model, plan, params, run, r);
  ExpectWalks(k, r, 10);
}

}  // namespace
}  // namespace rome
