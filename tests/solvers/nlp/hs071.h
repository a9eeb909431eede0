#pragma once
// Hock–Schittkowski problem 71 with analytic first and second derivatives (test fixture).
//   min x0 x3 (x0 + x1 + x2) + x2
//   s.t. x0 x1 x2 x3 ≥ 25,  x0² + x1² + x2² + x3² = 40,  1 ≤ x ≤ 5.
// Known solution x* = (1, 4.74299963, 3.82114998, 1.37940829), f* = 17.0140173.
#include <limits>

#include "solvers/nlp/nlp_problem.h"

namespace rome::test {

class Hs071 final : public NlpProblem {
 public:
  Hs071() : NlpProblem("hs071", 4, 2) {
    SetVariableBounds(Eigen::Vector4d::Constant(1.0), Eigen::Vector4d::Constant(5.0));
    SetConstraintBounds(Eigen::Vector2d(25.0, 40.0), Eigen::Vector2d(std::numeric_limits<double>::infinity(), 40.0));
    SparsityPattern J;
    for (int i = 0; i < 2; ++i) {
      for (int j = 0; j < 4; ++j) J.Add(i, j);
    }
    SetConstraintJacobianSparsity(J);
    SparsityPattern H;
    for (int i = 0; i < 4; ++i) {
      for (int j = 0; j <= i; ++j) H.Add(i, j);
    }
    SetLagrangianHessianSparsity(H);
  }

  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) override {
    return x(0) * x(3) * (x(0) + x(1) + x(2)) + x(2);
  }
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    g(0) = x(3) * (2.0 * x(0) + x(1) + x(2));
    g(1) = x(0) * x(3);
    g(2) = x(0) * x(3) + 1.0;
    g(3) = x(0) * (x(0) + x(1) + x(2));
  }
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override {
    g(0) = x(0) * x(1) * x(2) * x(3);
    g(1) = x.squaredNorm();
  }
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> v) override {
    v(0) = x(1) * x(2) * x(3);
    v(1) = x(0) * x(2) * x(3);
    v(2) = x(0) * x(1) * x(3);
    v(3) = x(0) * x(1) * x(2);
    for (int j = 0; j < 4; ++j) v(4 + j) = 2.0 * x(j);
  }
  void EvalLagrangianHessian(const Eigen::Ref<const Eigen::VectorXd>& x, double s,
                             const Eigen::Ref<const Eigen::VectorXd>& l, Eigen::Ref<Eigen::VectorXd> v) override {
    // Order: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2) (3,0) (3,1) (3,2) (3,3).
    v(0) = s * 2.0 * x(3) + l(1) * 2.0;
    v(1) = s * x(3) + l(0) * x(2) * x(3);
    v(2) = l(1) * 2.0;
    v(3) = s * x(3) + l(0) * x(1) * x(3);
    v(4) = l(0) * x(0) * x(3);
    v(5) = l(1) * 2.0;
    v(6) = s * (2.0 * x(0) + x(1) + x(2)) + l(0) * x(1) * x(2);
    v(7) = s * x(0) + l(0) * x(0) * x(2);
    v(8) = s * x(0) + l(0) * x(0) * x(1);
    v(9) = l(1) * 2.0;
  }
};

inline Eigen::Vector4d Hs071Solution() { return Eigen::Vector4d(1.0, 4.74299963, 3.82114998, 1.37940829); }
constexpr double kHs071OptimalCost = 17.0140173;

}  // namespace rome::test
