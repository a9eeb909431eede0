#include "solvers/collocation/piecewise_polynomial.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace rome {
namespace {

// p(t) = [t³ − 2t + 1; 0.5 t² + 3], p'(t) = [3t² − 2; t].
Eigen::Vector2d Cubic(double t) { return {t * t * t - 2.0 * t + 1.0, 0.5 * t * t + 3.0}; }
Eigen::Vector2d CubicDot(double t) { return {3.0 * t * t - 2.0, t}; }

TEST(PiecewisePolynomial, CubicHermiteReproducesCubicsExactly) {
  const Eigen::VectorXd breaks = (Eigen::VectorXd(4) << -1.0, 0.2, 0.5, 2.0).finished();
  Eigen::MatrixXd values(2, 4), derivatives(2, 4);
  for (int k = 0; k < 4; ++k) {
    values.col(k) = Cubic(breaks(k));
    derivatives.col(k) = CubicDot(breaks(k));
  }
  const auto pp = PiecewisePolynomial::CubicHermite(breaks, values, derivatives);
  EXPECT_EQ(pp.num_segments(), 3);
  EXPECT_DOUBLE_EQ(pp.start_time(), -1.0);
  EXPECT_DOUBLE_EQ(pp.end_time(), 2.0);
  for (double t = -1.0; t <= 2.0; t += 0.0137) {
    EXPECT_LT((pp.Value(t) - Cubic(t)).norm(), 1e-12) << t;
    EXPECT_LT((pp.Derivative(t) - CubicDot(t)).norm(), 1e-11) << t;
    EXPECT_NEAR(pp.Derivative(t, 2)(0), 6.0 * t, 1e-10);
    EXPECT_NEAR(pp.Derivative(t, 3)(0), 6.0, 1e-9);
    EXPECT_NEAR(pp.Derivative(t, 4)(0), 0.0, 1e-12);
  }
  // Clamped outside the interval.
  EXPECT_LT((pp.Value(5.0) - Cubic(2.0)).norm(), 1e-12);
  const auto f = pp.AsFunction();
  EXPECT_LT((f(0.3) - Cubic(0.3)).norm(), 1e-12);
}

TEST(PiecewisePolynomial, HermiteInterpolationErrorIsFourthOrder) {
  // sin on [0, π] : max error of the Hermite interpolant shrinks ~16× per halving of h.
  double previous = 0.0;
  for (int n : {5, 10, 20}) {
    const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n + 1, 0.0, M_PI);
    const Eigen::MatrixXd v = t.array().sin().matrix().transpose();
    const Eigen::MatrixXd d = t.array().cos().matrix().transpose();
    const auto pp = PiecewisePolynomial::CubicHermite(t, v, d);
    double err = 0.0;
    for (double s = 0.0; s <= M_PI; s += 1e-3) err = std::max(err, std::abs(pp.Value(s)(0) - std::sin(s)));
    if (previous > 0.0) { EXPECT_NEAR(previous / err, 16.0, 1.5) << "n = " << n; }
    previous = err;
  }
}

TEST(PiecewisePolynomial, FirstOrderHoldAndZeroOrderHold) {
  const Eigen::Vector3d breaks(0.0, 1.0, 3.0);
  Eigen::MatrixXd values(1, 3);
  values << 2.0, 4.0, 0.0;
  const auto foh = PiecewisePolynomial::FirstOrderHold(breaks, values);
  EXPECT_DOUBLE_EQ(foh.Value(0.5)(0), 3.0);
  EXPECT_DOUBLE_EQ(foh.Value(2.0)(0), 2.0);
  EXPECT_DOUBLE_EQ(foh.Derivative(2.0)(0), -2.0);
  EXPECT_DOUBLE_EQ(foh.Derivative(0.5)(0), 2.0);
  const auto zoh = PiecewisePolynomial::ZeroOrderHold(breaks, values);
  EXPECT_DOUBLE_EQ(zoh.Value(0.99)(0), 2.0);
  EXPECT_DOUBLE_EQ(zoh.Value(1.0)(0), 4.0);  // right-continuous
  EXPECT_DOUBLE_EQ(zoh.Value(3.0)(0), 4.0);
}

TEST(PiecewisePolynomial, AppendWithOffsetIsRightContinuousAtTheJump) {
  Eigen::MatrixXd a(1, 2), b(1, 2);
  a << 0.0, 1.0;
  b << -1.0, 5.0;  // jump from 1 to −1 (a reset)
  auto joined = PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(0.0, 1.0), a);
  joined.Append(PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(0.0, 2.0), b), 1.0);
  EXPECT_EQ(joined.num_segments(), 2);
  EXPECT_DOUBLE_EQ(joined.end_time(), 3.0);
  EXPECT_DOUBLE_EQ(joined.Value(1.0 - 1e-12)(0), 1.0 - 1e-12);
  EXPECT_DOUBLE_EQ(joined.Value(1.0)(0), -1.0);
  EXPECT_DOUBLE_EQ(joined.Value(2.0)(0), 2.0);
  // Gaps and row mismatches are rejected.
  EXPECT_THROW(joined.Append(PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(0.0, 1.0), a)), std::invalid_argument);
  EXPECT_THROW(
      joined.Append(PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(3.0, 4.0), Eigen::MatrixXd::Zero(2, 2))),
      std::invalid_argument);
  joined.ShiftTime(-1.0);
  EXPECT_DOUBLE_EQ(joined.start_time(), -1.0);
  EXPECT_DOUBLE_EQ(joined.Value(0.0)(0), -1.0);
}

TEST(PiecewisePolynomial, RejectsBadInput) {
  EXPECT_THROW(PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(1.0, 1.0), Eigen::MatrixXd::Zero(1, 2)),
               std::invalid_argument);
  EXPECT_THROW(PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(0.0, 1.0), Eigen::MatrixXd::Zero(1, 3)),
               std::invalid_argument);
  EXPECT_THROW(PiecewisePolynomial().Value(0.0), std::logic_error);
  const auto pp = PiecewisePolynomial::FirstOrderHold(Eigen::Vector2d(0.0, 1.0), Eigen::MatrixXd::Zero(2, 2));
  Eigen::VectorXd wrong(3);
  EXPECT_THROW(pp.ValueInto(0.5, wrong), std::invalid_argument);
}

}  // namespace
}  // namespace rome
