#include "solvers/riccati/rapidly_exponentially_stabilizing_clf.h"

#include <random>
#include <stdexcept>

#include <gtest/gtest.h>

#include "solvers/riccati/continuous_algebraic_riccati_equation.h"

namespace rome {
namespace {

TEST(RapidlyExponentiallyStabilizingClf, OutputDynamicsOfEq26) {
  Eigen::MatrixXd F, G;
  MakeOutputDynamics(1, 2, &F, &G);
  // η = [y1, y2(2), ẏ2(2)]; μ = [μ1, μ2(2)]. η̇ = [μ1, ẏ2, μ2].
  Eigen::VectorXd eta(5), mu(3);
  eta << 1.0, 2.0, 3.0, 4.0, 5.0;
  mu << -1.0, -2.0, -3.0;
  Eigen::VectorXd expected(5);
  expected << -1.0, 4.0, 5.0, -2.0, -3.0;
  EXPECT_LT((F * eta + G * mu - expected).norm(), 1e-15);
}

TEST(RapidlyExponentiallyStabilizingClf, DecreaseConditionOfEq30Holds) {
  // Hopping-paper layout: o1 = 1 (e.g. pitch rate), o2 = 3. Check Eq. (30)–(33): with
  // μ = −(1/ε) Gᵀ P I_ε η, V̇_ε = L_F V_ε + L_G V_ε μ ≤ −(γ/ε) V_ε for random η and several ε.
  const int o1 = 1, o2 = 3, n = o1 + 2 * o2;
  Eigen::MatrixXd F, G;
  MakeOutputDynamics(o1, o2, &F, &G);
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Identity(n, n);
  std::mt19937 rng(11);
  std::normal_distribution<double> normal;
  for (double eps : {1.0, 0.2, 0.05}) {
    RapidlyExponentiallyStabilizingClfParameters params;
    params.num_relative_degree_one_outputs = o1;
    params.num_relative_degree_two_outputs = o2;
    params.epsilon = eps;
    const auto clf = ComputeRapidlyExponentiallyStabilizingClf(F, G, Q, params);
    EXPECT_LT(ContinuousAlgebraicRiccatiRelativeResidual(F, G, Q, Eigen::MatrixXd::Identity(4, 4), clf.P), 1e-10);
    EXPECT_LT((clf.P_epsilon - clf.I_epsilon * clf.P * clf.I_epsilon).norm(), 1e-12);
    EXPECT_DOUBLE_EQ(clf.I_epsilon(o1, o1), 1.0 / eps);
    EXPECT_DOUBLE_EQ(clf.I_epsilon(o1 + o2, o1 + o2), 1.0);
    EXPECT_GT(clf.gamma, 0.0);
    double tightest = 0.0;  // max over samples of V̇ / (−(γ/ε) V), must stay ≥ 1
    double worst_ratio = 1e300;
    for (int trial = 0; trial < 200; ++trial) {
      Eigen::VectorXd eta(n);
      for (int i = 0; i < n; ++i) eta(i) = normal(rng);
      const double V = eta.dot(clf.P_epsilon * eta);                                          // Eq. (29)
      const double LfV = eta.dot((F.transpose() * clf.P_epsilon + clf.P_epsilon * F) * eta);  // (32)
      const Eigen::RowVectorXd LgV = 2.0 * eta.transpose() * clf.P_epsilon * G;               // Eq. (33)
      const Eigen::VectorXd mu = -(1.0 / eps) * G.transpose() * clf.P * clf.I_epsilon * eta;
      const double Vdot = LfV + LgV.dot(mu);  // Eq. (31)
      const double ratio = Vdot / (-(clf.gamma / eps) * V);
      worst_ratio = std::min(worst_ratio, ratio);
      tightest = std::max(tightest, ratio);
    }
    EXPECT_GE(worst_ratio, 1.0 - 1e-12) << "ε = " << eps;
    std::printf("ε = %.2f: γ = %.4f, rate γ/ε = %.3f 1/s, min V̇/(−γV/ε) = %.3f\n", eps, clf.gamma, clf.convergence_rate,
                worst_ratio);
  }
}

TEST(RapidlyExponentiallyStabilizingClf, LyapunovVariantNeedsHurwitzF) {
  Eigen::MatrixXd F, G;
  MakeOutputDynamics(1, 1, &F, &G);
  RapidlyExponentiallyStabilizingClfParameters params;
  params.num_relative_degree_one_outputs = 1;
  params.num_relative_degree_two_outputs = 1;
  params.equation = ClfEquation::kLyapunov;
  // F of Eq. (26) is nilpotent: the CTLE has no positive-definite solution.
  EXPECT_THROW(ComputeRapidlyExponentiallyStabilizingClf(F, G, Eigen::Matrix3d::Identity(), params),
               std::invalid_argument);
  // Closed-loop matrix of Eq. (28) with ε = 1 is Hurwitz: CTLE works.
  Eigen::Matrix3d F_cl;
  F_cl << -1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, -1.0, -2.0;
  const auto clf = ComputeRapidlyExponentiallyStabilizingClf(F_cl, G, Eigen::Matrix3d::Identity(), params);
  EXPECT_LT((F_cl.transpose() * clf.P + clf.P * F_cl + Eigen::Matrix3d::Identity()).norm(), 1e-12);
}

TEST(RapidlyExponentiallyStabilizingClf, RejectsBadParameters) {
  Eigen::MatrixXd F, G;
  MakeOutputDynamics(1, 1, &F, &G);
  RapidlyExponentiallyStabilizingClfParameters params;
  params.num_relative_degree_one_outputs = 1;
  params.num_relative_degree_two_outputs = 1;
  params.epsilon = 0.0;
  EXPECT_THROW(ComputeRapidlyExponentiallyStabilizingClf(F, G, Eigen::Matrix3d::Identity(), params),
               std::invalid_argument);
  params.epsilon = 0.1;
  params.num_relative_degree_two_outputs = 2;  // sizes no longer match F
  EXPECT_THROW(ComputeRapidlyExponentiallyStabilizingClf(F, G, Eigen::Matrix3d::Identity(), params),
               std::invalid_argument);
}

}  // namespace
}  // namespace rome
