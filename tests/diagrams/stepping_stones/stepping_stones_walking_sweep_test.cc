// Closed-loop stepping-stones walking on the paper's periodic footholds (Sec. VI-B, Fig. 4): 30 steps on flat ground
// for every l = 0.2..0.8 m (0.1 m apart), upstairs (l, h) = (0.5, 0.2) m and downstairs (0.4, −0.1) m. Each walk
// must converge to a periodic orbit (post-impact L_y of the last steps within 1 %) with touchdowns within 2 cm of
// the stone centres; ten random-stone courses; the speed trends of Fig. 6. On every course the plant's own contact
// forces stay unilateral and inside the friction cone over every integrator step. Label slow (about 30 s).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "tests/common/sanitizer_scale.h"
#include "tests/diagrams/stepping_stones/stepping_stones_walk.h"

namespace rome {
namespace {

constexpr int kSteps = 30;

class FlatGround : public ::testing::TestWithParam<double> {};

TEST_P(FlatGround, ConvergesToAPeriodicOrbit) {
  const double l = GetParam();
  test::ExpectPeriodicWalk(test::Walk(PeriodicSteppingStones(l, 0.0, kSteps + 2), kSteps), kSteps,
                           "flat l = " + std::to_string(l) + " m");
}
INSTANTIATE_TEST_SUITE_P(StepLengths, FlatGround, ::testing::Values(0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8));

TEST(Stairs, UpstairsConvergesToAPeriodicOrbit) {
  test::ExpectPeriodicWalk(test::Walk(PeriodicSteppingStones(0.5, 0.2, kSteps + 2), kSteps), kSteps,
                           "upstairs (0.5, 0.2)");
}

TEST(Stairs, DownstairsConvergesToAPeriodicOrbit) {
  test::ExpectPeriodicWalk(test::Walk(PeriodicSteppingStones(0.4, -0.1, kSteps + 2), kSteps), kSteps,
                           "downstairs (0.4, -0.1)");
}

// Random stones (Sec. VI-C: 0.2-0.7 m apart, ±0.25 m, E* = 0.5, ε = 0.6): seeds 1-10, 30 steps each without a fall,
// every touchdown on the planned stone and within 2 cm of its centre.
TEST(RandomStones, TenCoursesOfThirtyStepsWithoutAFall) {
  int misplaced = 0;
  for (unsigned seed = 1; seed <= test::kRandomCourseSeeds; ++seed) {
    RandomSteppingStonesParams p;
    p.num_stones = kSteps + 2;
    p.seed = seed;
    const test::WalkResult r = test::Walk(RandomSteppingStones(p), kSteps);
    EXPECT_EQ(r.status.kind(), SimulatorStatus::Kind::kSuccess) << "seed " << seed << ": " << r.status.ToString();
    test::ExpectPhysicalContact(r, "seed " + std::to_string(seed));
    EXPECT_EQ(static_cast<int>(r.steps.size()), kSteps) << "seed " << seed << ": " << r.status.message;
    EXPECT_NE(r.status.message.find("completed"), std::string::npos) << "seed " << seed << ": " << r.status.message;
    double worst = 0;
    for (size_t k = 0; k < r.steps.size(); ++k) {
      const StepRecord& s = r.steps[k];
      if (s.stone != s.planned_stone || !(s.foothold_error_m < 0.02)) {
        ++misplaced;
        std::printf(
            "  seed %u step %zu (l = %.3f m, h = %.3f m): landed on stone %d (planned %d), %.2f cm from its centre\n",
            seed, k + 1, s.step_length_m, s.step_height_m, s.stone, s.planned_stone, 100 * s.foothold_error_m);
      }
      worst = std::max(worst, s.foothold_error_m);
    }
    std::printf(
        "  seed %u: %zu steps, mean speed %.3f m/s, largest foothold error %.2f cm, %g QP failures, plant F_n >= %.2f "
        "N, |F_t|/F_n <= %.3f\n",
        seed, r.steps.size(), r.mean_speed_mps, 100 * worst, r.qp_failures, r.contact.min_normal_force_N,
        r.contact.max_friction_ratio);
  }
  EXPECT_EQ(misplaced, 0) << "touchdowns off the planned stone or more than 2 cm from its centre, over "
                          << 30 * test::kRandomCourseSeeds << " (seeds 1-" << test::kRandomCourseSeeds << ")";
}

// The CLF-QP (ClfQpControllerFactory) on the same courses: periodic footholds walk to a periodic orbit; the random
// courses of seeds 1-10 must all be walked with physical contact and every touchdown within 2 cm (measured: at most
// 0.74 cm). Before DefaultClfParams' PD cost, seed 1 ended with a slip at 0.78 s (the stance foot unloaded to ~1.5 N
// under a bang-bang torque). Parameters chosen on seeds 1000-1099 only (92 of 100 walked before, 99 after).
// L+ within 5 % of L_des (measured: up to 3.8 % upstairs) against the task-space QP's 3 %.
constexpr double kClfMomentumTolerance = 0.05;
class ClfFlatGround : public ::testing::TestWithParam<double> {};
TEST_P(ClfFlatGround, ConvergesToAPeriodicOrbit) {
  const double l = GetParam();
  SteppingStonesDiagramParams params;
  test::ExpectPeriodicWalk(
      test::Walk(PeriodicSteppingStones(l, 0.0, kSteps + 2), kSteps, params, ClfQpControllerFactory(params)), kSteps,
      "CLF-QP, flat l = " + std::to_string(l) + " m", kClfMomentumTolerance);
}
INSTANTIATE_TEST_SUITE_P(StepLengths, ClfFlatGround, ::testing::Values(0.2, 0.4, 0.6, 0.8));

TEST(ClfStairs, UpAndDownConvergeToPeriodicOrbits) {
  SteppingStonesDiagramParams params;
  test::ExpectPeriodicWalk(
      test::Walk(PeriodicSteppingStones(0.5, 0.2, kSteps + 2), kSteps, params, ClfQpControllerFactory(params)), kSteps,
      "CLF-QP upstairs (0.5, 0.2)", kClfMomentumTolerance);
  test::ExpectPeriodicWalk(
      test::Walk(PeriodicSteppingStones(0.4, -0.1, kSteps + 2), kSteps, params, ClfQpControllerFactory(params)), kSteps,
      "CLF-QP downstairs (0.4, -0.1)", kClfMomentumTolerance);
}

TEST(ClfRandomStones, AllTenCoursesWithPhysicalContact) {
  int walked = 0;
  SteppingStonesDiagramParams params;
  for (unsigned seed = 1; seed <= test::kRandomCourseSeeds; ++seed) {
    RandomSteppingStonesParams p;
    p.num_stones = kSteps + 2;
    p.seed = seed;
    const test::WalkResult r = test::Walk(RandomSteppingStones(p), kSteps, params, ClfQpControllerFactory(params));
    bool ok = r.status.kind() == SimulatorStatus::Kind::kSuccess && static_cast<int>(r.steps.size()) == kSteps &&
              r.contact.violations == 0;
    double worst = 0;
    for (const StepRecord& s : r.steps) {
      ok = ok && s.stone == s.planned_stone && s.foothold_error_m < 0.02;
      worst = std::max(worst, s.foothold_error_m);
    }
    walked += ok ? 1 : 0;
    std::printf("  CLF-QP seed %u: %zu steps, largest foothold error %.2f cm, %s\n", seed, r.steps.size(), 100 * worst,
                ok ? "walked" : r.status.ToString().c_str());
  }
  EXPECT_EQ(walked, static_cast<int>(test::kRandomCourseSeeds));
}

// Fig. 6 of the paper: the converged forward speed rises with the orbital energy E* (l = 0.4 m, Fig. 6(b)) and with
// the step length l (E* = 0.3, Fig. 6(a)); ε = 0.6 throughout. Speed of the converged gait: the last 5 of 15 steps.
TEST(Fig6Trends, SpeedRisesWithOrbitalEnergyAndWithStepLength) {
  constexpr int kTrendSteps = 15;
  auto speed = [&](double l, double energy) {
    SteppingStonesDiagramParams params;
    params.target_orbital_energy = energy;
    const test::WalkResult r = test::Walk(PeriodicSteppingStones(l, 0.0, kTrendSteps + 2), kTrendSteps, params);
    EXPECT_EQ(static_cast<int>(r.steps.size()), kTrendSteps)
        << "l = " << l << " m, E* = " << energy << ": " << r.status.message;
    if (static_cast<int>(r.steps.size()) < kTrendSteps) return 0.0;
    const double v = test::LastStepsSpeed(r, 5);
    std::printf("  l = %.1f m, E* = %.1f m^2/s^2: converged speed %.3f m/s\n", l, energy, v);
    return v;
  };
  double previous = 0;
  for (double energy : {0.1, 0.3, 0.5, 0.7}) {
    const double v = speed(0.4, energy);
    EXPECT_GT(v, previous + 0.02) << "E* = " << energy;
    previous = v;
  }
  previous = 0;
  for (double l : {0.2, 0.4, 0.6, 0.8}) {
    const double v = speed(l, 0.3);
    EXPECT_GT(v, previous + 0.02) << "l = " << l;
    previous = v;
  }
}

}  // namespace
}  // namespace rome
