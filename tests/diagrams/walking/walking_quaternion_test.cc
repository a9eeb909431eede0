// A short walk (gait A on its orbit, 4 planned steps, the exoskeleton) with the plant on the quaternion free-flyer base
// (WalkingDiagramParams::plant_base, issue 43): the controller runs on the quaternion twin and reads the plant's state;
// the plan and the run read the Euler state through the QuaternionToEulerState block. Checks, from the plant's own
// outputs:
//   * every planned step is walked, with no plant contact violation (normal forces >= 0, inside the friction cone,
//     after every integrator step: ContactForceStatistics) and |F_t|/F_n below the feet's mu;
//   * the quaternion's norm stays within the documented 1e-10 of 1 (docs/design-notes.md#quaternion-norm);
//   * the COM trajectory at every control tick stays within 1 um of the same walk on the Euler plant (the tolerance:
//     the two plants integrate different coordinates at rtol 1e-5, atol 1e-7, and the 1 kHz QP and the event-timed
//     modes carry the integrator's error along; measured 4.9e-11 m, docs/design-notes.md, "Diagrams on the quaternion
//     plant").
// Label slow.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_run.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

struct Walk {
  WalkingRunResult result;
  std::vector<double> t;
  std::vector<Eigen::Vector3d> com;
  double worst_norm = 0;
  bool controller_quaternion = false;  // the CLF-QP's model has the quaternion base
};

Walk RunShortWalk(PlantBase base) {
  LoadOptions euler;
  euler.euler_floating_base = true;
  auto model = std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/exoskeleton/exoskeleton.rome.json"), euler));
  const PlanCache cache(rome::test::TestPlanCacheDir("rome_walking_quaternion_test_plans"));
  StandToWalkParams stand;
  stand.sole = SoleOf(*model, "left_foot");
  const WalkingGait gait;
  WalkingDiagramParams params;
  params.plant_base = base;
  const WalkingDiagram d = BuildWalkingDiagram(model, BuildPeriodicWalkingPlan(gait, 4, 1, &cache, stand), params);
  WalkingRunParams run;
  run.start_time_s = 0.5 * gait.dsp_duration_s;
  run.start_at_rest = false;
  Walk w;
  w.controller_quaternion = d.clf_qp != nullptr && d.clf_qp->model().has_quaternion_base();
  w.result = RunWalking(d, run, [&](const Context& c, const WalkingRunSample& s) {
    if (base == PlantBase::kQuaternion) {
      const Eigen::VectorXd& x = d.plant->EvalOutput(d.diagram->GetSubsystemContext(*d.plant, c), "state");
      w.worst_norm = std::max(w.worst_norm, std::abs(x.segment<4>(3).norm() - 1.0));
    }
    if (!s.tick) return;
    w.t.push_back(s.t);
    w.com.push_back(s.com);
  });
  return w;
}

TEST(WalkingQuaternion, ShortWalkOnTheQuaternionPlantIsPhysicalAndFollowsTheEulerPlantsCom) {
  const Walk q = RunShortWalk(PlantBase::kQuaternion);
  const Walk e = RunShortWalk(PlantBase::kEuler);
  double worst = 0;
  size_t compared = 0;
  for (size_t i = 0, j = 0; i < q.t.size(); ++i) {  // the ticks both runs sampled
    while (j < e.t.size() && e.t[j] < q.t[i] - 1e-12) ++j;
    if (j == e.t.size()) break;
    if (std::abs(e.t[j] - q.t[i]) > 1e-12) continue;
    worst = std::max(worst, (q.com[i] - e.com[j]).norm());
    ++compared;
  }
  std::printf(
      "quaternion plant: %s, %d of %d steps, max |F_t|/F_n %.4f, violations %ld, norm %.3g; Euler plant: %s, %d "
      "steps; COM difference over %zu ticks <= %.3g m\n",
      q.result.status.ToString().c_str(), q.result.steps_completed, q.result.steps_planned,
      q.result.contact.max_friction_ratio, q.result.contact.violations, q.worst_norm,
      e.result.status.ToString().c_str(), e.result.steps_completed, compared, worst);
  ASSERT_TRUE(q.result.success) << q.result.status.ToString();
  ASSERT_TRUE(e.result.success) << e.result.status.ToString();
  EXPECT_TRUE(q.controller_quaternion);
  EXPECT_FALSE(e.controller_quaternion);
  EXPECT_EQ(q.result.steps_completed, q.result.steps_planned);
  EXPECT_EQ(q.result.contact.violations, 0);
  EXPECT_LT(q.result.contact.max_friction_ratio, 0.8);  // the exoskeleton's feet: mu = 0.8 (its robot file)
  EXPECT_LT(q.worst_norm, 1e-10);
  EXPECT_GT(compared, 1000u);
  EXPECT_LT(worst, 1e-6);
}

}  // namespace
}  // namespace rome
