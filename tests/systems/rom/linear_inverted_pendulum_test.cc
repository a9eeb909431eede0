// LinearInvertedPendulum: closed-form flow Eq. (13), time-to-impact Eq. (14)-(15), orbital energy Eq. (16),
// slope-adjusted height Eq. (27).
#include "systems/rom/linear_inverted_pendulum.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <Eigen/LU>

namespace rome {
namespace {

TEST(LinearInvertedPendulum, LambdaMatchesClosedForm) {
  // Reference values λ = sqrt(g/z0), g = 9.81, to 4 decimals: z0 = 0.75 m gives 3.6166 1/s; z0 = 0.34 m gives 5.3715.
  EXPECT_NEAR(LinearInvertedPendulum({.z0 = 0.75}).lambda(), 3.6166, 5e-5);
  EXPECT_NEAR(LinearInvertedPendulum({.z0 = 0.34}).lambda(), 5.3715, 5e-5);
  const LinearInvertedPendulum lip({.z0 = 0.8, .gravity = 9.81});
  EXPECT_DOUBLE_EQ(lip.lambda() * lip.lambda() * 0.8, 9.81);
}

TEST(LinearInvertedPendulum, TransitionMatrixIsTheFlowOfEq12) {
  const LinearInvertedPendulum lip({.z0 = 0.9});
  Eigen::Matrix2d F;  // Eq. (12) system matrix
  F << 0, 1 / 0.9, 9.81, 0;
  for (double t : {0.0, 0.05, 0.3, 0.7, -0.4}) {
    const Eigen::Matrix2d A = lip.TransitionMatrix(t);
    // Flow property A(t)A(s) = A(t+s), A(0) = I, unit determinant (area preserving, det = cosh² − sinh²).
    EXPECT_NEAR((A * lip.TransitionMatrix(0.2) - lip.TransitionMatrix(t + 0.2)).norm(), 0.0, 1e-12);
    EXPECT_NEAR(A.determinant(), 1.0, 1e-12);
    // dA/dt = F A (central differences).
    const double h = 1e-5;
    const Eigen::Matrix2d dA = (lip.TransitionMatrix(t + h) - lip.TransitionMatrix(t - h)) / (2 * h);
    EXPECT_NEAR((dA - F * A).norm(), 0.0, 1e-7 * (1 + A.norm()));
  }
  EXPECT_NEAR((lip.TransitionMatrix(0.0) - Eigen::Matrix2d::Identity()).norm(), 0.0, 0.0);
}

TEST(LinearInvertedPendulum, OrbitalEnergyIsConservedAlongTheFlow) {
  const LinearInvertedPendulum lip({.z0 = 0.8});
  for (const Eigen::Vector2d& x0 :
       {Eigen::Vector2d(-0.15, 0.5), Eigen::Vector2d(0.2, -0.1), Eigen::Vector2d(-0.3, 0.1)}) {
    const double E0 = lip.OrbitalEnergy(x0);
    for (double t = 0; t <= 1.0; t += 0.05) {
      const Eigen::Vector2d x = lip.Flow(x0, t);
      EXPECT_NEAR(lip.OrbitalEnergy(x), E0, 1e-11 * (1 + x.squaredNorm())) << "t = " << t;
    }
  }
  // Inverse of Eq. (16).
  const double L = *lip.MomentumOnOrbit(0.4, -0.15);
  EXPECT_NEAR(lip.OrbitalEnergy(Eigen::Vector2d(-0.15, L)), 0.4, 1e-14);
  EXPECT_FALSE(lip.MomentumOnOrbit(-0.5, 0.05).has_value());
}

TEST(LinearInvertedPendulum, TimeToImpactMatchesEq14AndTheFlow) {
  const LinearInvertedPendulum lip({.z0 = 0.8});
  const double lz = lip.lambda() * lip.z0();
  // Forward walking: x0 < 0 < x_des, E > 0. Eq. (14) literally.
  const Eigen::Vector2d x0(-0.16, 0.55);
  const double x_des = 0.24;
  const double eq14 =
      std::log((x_des + std::sqrt(x_des * x_des - x0[0] * x0[0] + x0[1] * x0[1] / (lz * lz))) / (x0[0] + x0[1] / lz)) /
      lip.lambda();
  const TimeToImpact t = lip.TimeToReach(x_des, x0);
  ASSERT_TRUE(t.ok()) << ToString(t.status);
  EXPECT_NEAR(t.time_s, eq14, 1e-14);
  EXPECT_NEAR(lip.Flow(x0, t.time_s)[0], x_des, 1e-13);
  ASSERT_TRUE(t.time().has_value());

  // Random states: whenever a time is returned, the flow reaches the target there, and never before.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> pos(-0.4, 0.4), mom(-0.8, 0.8);
  int reached = 0, insufficient = 0, backwards = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const Eigen::Vector2d s(pos(rng), mom(rng));
    const double target = pos(rng);
    const TimeToImpact r = lip.TimeToReach(target, s);
    const double discriminant = target * target + lip.OrbitalEnergy(s) / (lip.lambda() * lip.lambda());
    if (r.ok()) {
      ++reached;
      EXPECT_NEAR(lip.Flow(s, r.time_s)[0], target, 1e-10 * (1 + std::exp(lip.lambda() * r.time_s)));
      // x(t) − target keeps one sign on [0, T): no earlier crossing.
      const double sign0 = s[0] - target;
      for (int k = 1; k < 50; ++k) {
        const double tk = r.time_s * k / 50.0;
        EXPECT_GT((lip.Flow(s, tk)[0] - target) * sign0, -1e-12) << "earlier crossing at " << tk;
      }
    } else if (r.status == TimeToImpact::Status::kInsufficientEnergy) {
      ++insufficient;
      EXPECT_TRUE(discriminant < 0 || (lip.OrbitalEnergy(s) <= 1e-12 && s[0] * target <= 0));
      // The orbit never gets to the target: its turning point |x| = sqrt(−E)/λ is short of it.
      for (double tk = 0; tk < 3; tk += 0.01) EXPECT_GT((lip.Flow(s, tk)[0] - target) * (s[0] - target), 0);
    } else {
      ++backwards;
      EXPECT_GE(discriminant, 0);
      EXPECT_FALSE(lip.OrbitalEnergy(s) < -1e-12 && s[0] * target <= 0);
      for (double tk = 0.01; tk < 3; tk += 0.01) EXPECT_GT((lip.Flow(s, tk)[0] - target) * (s[0] - target), 0);
    }
  }
  // All three outcomes occur in the sample.
  EXPECT_GT(reached, 100);
  EXPECT_GT(insufficient, 100);
  EXPECT_GT(backwards, 100);
}

TEST(LinearInvertedPendulum, TimeToImpactNoSolutionCases) {
  const LinearInvertedPendulum lip({.z0 = 0.8});
  // Too little energy: starts behind the foot, slowly forward; turns back before reaching x = 0.
  const Eigen::Vector2d slow(-0.2, 0.2);
  ASSERT_LT(lip.OrbitalEnergy(slow), 0);
  const TimeToImpact r = lip.TimeToReach(0.1, slow);
  EXPECT_EQ(r.status, TimeToImpact::Status::kInsufficientEnergy);
  EXPECT_FALSE(r.time().has_value());
  // Ahead of the target and moving away from it.
  EXPECT_EQ(lip.TimeToReach(0.1, Eigen::Vector2d(0.2, 1.0)).status, TimeToImpact::Status::kNotReachedForward);
  // Falling back with too little energy: a target ahead of the foot is never reached (though Eq. (14) has a root
  // on the other branch of the hyperbola, at negative time).
  EXPECT_EQ(lip.TimeToReach(0.3, Eigen::Vector2d(-0.3, 0.1)).status, TimeToImpact::Status::kInsufficientEnergy);
  // Already there.
  EXPECT_EQ(lip.TimeToReach(0.1, Eigen::Vector2d(0.1, 0.3)).time_s, 0.0);
  // On the stable manifold (L = −λ z0 x): approaches the foot, reaches any point between x0 and 0.
  const Eigen::Vector2d capture(-0.2, 0.2 * lip.lambda() * lip.z0());
  const TimeToImpact c = lip.TimeToReach(-0.05, capture);
  ASSERT_TRUE(c.ok());
  EXPECT_NEAR(c.time_s, std::log(4.0) / lip.lambda(), 1e-12);
  EXPECT_EQ(lip.TimeToReach(0.05, capture).status, TimeToImpact::Status::kInsufficientEnergy);  // E = 0: never crosses
}

TEST(LinearInvertedPendulum, SlopeAdjustedHeight) {
  // COM on the line z = (h/l) x + z0: the slope-adjusted height is z0 everywhere, and L = z ẋ − x ż = z0 ẋ.
  const double l = 0.5, h = 0.2, z0 = 0.85;
  for (double x : {-0.2, 0.0, 0.3}) {
    const double z = LinearInvertedPendulum::ComHeightOnSlope(x, z0, l, h);
    EXPECT_NEAR(LinearInvertedPendulum::SlopeAdjustedHeight(x, z, l, h), z0, 1e-15);
    const double xdot = 0.7, zdot = h / l * xdot;
    EXPECT_NEAR(z * xdot - x * zdot, z0 * xdot, 1e-15);
  }
  EXPECT_THROW(LinearInvertedPendulum::SlopeAdjustedHeight(0.1, 0.8, 0.0, 0.1), std::invalid_argument);
}

TEST(LinearInvertedPendulum, RejectsBadParameters) {
  try {
    LinearInvertedPendulum lip({.z0 = -0.1});
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("z0"), std::string::npos) << e.what();
  }
  EXPECT_THROW(LinearInvertedPendulum({.z0 = 0.8, .gravity = 0.0}), std::invalid_argument);
}

}  // namespace
}  // namespace rome
