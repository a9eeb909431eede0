// Linearize: A, B, C, D against Jacobians derived by hand, series composition of a diagram, restored context, errors.
#include "framework/linearize.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "tests/common/error_of.h"

namespace rome {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Damped pendulum with a torque: x = (θ, ω), u = τ,  θ̇ = ω,  ω̇ = −(g/l) sin θ − b ω + τ/(m l²).
// Output y = (l sin θ, −l cos θ, τ ω) (tip position and the power of the torque, to have a feedthrough D).
class Pendulum final : public LeafSystem {
 public:
  static constexpr double g = 9.81, l = 0.7, m = 1.3, b = 0.4;
  Pendulum() : LeafSystem("pendulum") {
    DeclareContinuousState(2);
    DeclareInputPort("tau", 1);
    DeclareOutputPort("y", 3, [this](const LeafContext& c, Eigen::VectorXd* y) {
      const Eigen::VectorXd& x = c.continuous_state();
      const double tau = EvalInput(c, 0)[0];
      *y = Eigen::Vector3d(l * std::sin(x[0]), -l * std::cos(x[0]), tau * x[1]);
    });
  }

 private:
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    const Eigen::VectorXd& x = c.continuous_state();
    *xdot = Eigen::Vector2d(x[1], -(g / l) * std::sin(x[0]) - b * x[1] + EvalInput(c, 0)[0] / (m * l * l));
  }
};

// ẋ = A x + B u, y = C x + D u.
class LinearBlock final : public LeafSystem {
 public:
  LinearBlock(std::string name, Eigen::MatrixXd A, Eigen::MatrixXd B, Eigen::MatrixXd C, Eigen::MatrixXd D)
      : LeafSystem(std::move(name)), A_(std::move(A)), B_(std::move(B)), C_(std::move(C)), D_(std::move(D)) {
    DeclareContinuousState(static_cast<int>(A_.rows()));
    DeclareInputPort("u", static_cast<int>(B_.cols()));
    DeclareOutputPort("y", static_cast<int>(C_.rows()), [this](const LeafContext& c, Eigen::VectorXd* y) {
      *y = C_ * c.continuous_state() + D_ * EvalInput(c, 0);
    });
  }

 private:
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    *xdot = A_ * c.continuous_state() + B_ * EvalInput(c, 0);
  }
  Eigen::MatrixXd A_, B_, C_, D_;
};

// ẋ = sqrt(x): finite at x = 0, NaN once x is perturbed below zero.
class SquareRootFlow final : public LeafSystem {
 public:
  SquareRootFlow() : LeafSystem("sqrt_flow") { DeclareContinuousState(Eigen::VectorXd::Constant(1, 0.0)); }

 private:
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    *xdot = c.continuous_state().cwiseSqrt();
  }
};

// Error bound of the header for one entry: h²/6 · M3 (truncation, M3 bounds |∂³F|) + ε |F| / h (round-off), with
// h the largest step used and a factor 4 for the few roundings inside F.
double CentralDifferenceBound(double h, double third_derivative_bound, double value_bound) {
  return h * h / 6.0 * third_derivative_bound + 4.0 * kEps * value_bound / h;
}

TEST(Linearize, PendulumMatchesHandDerivedJacobians) {
  Pendulum p;
  auto context = p.CreateDefaultLeafContext();
  const double theta = 2.5, omega = 3.0, tau = 1.5;  // |z| > 1: the step scales with the element
  context->get_mutable_continuous_state() << theta, omega;
  p.FixInputPort(*context, 0, Eigen::VectorXd::Constant(1, tau));
  context->SetTime(0.25);

  const LinearizeParams params;
  EXPECT_NEAR(params.step_scale, std::cbrt(kEps), 1e-20);
  const LinearSystemMatrices lin = Linearize(p, *context, "tau", "y", params);

  Eigen::Matrix2d A;
  A << 0, 1, -(Pendulum::g / Pendulum::l) * std::cos(theta), -Pendulum::b;
  const Eigen::Vector2d B(0, 1 / (Pendulum::m * Pendulum::l * Pendulum::l));
  Eigen::Matrix<double, 3, 2> C;
  C << Pendulum::l * std::cos(theta), 0, Pendulum::l * std::sin(theta), 0, 0, tau;
  const Eigen::Vector3d D(0, 0, omega);

  // Third derivatives: g/l (sin in ω̇) and l (sin, cos in y); everything else is at most quadratic. |F| ≤ 20.
  const double h = params.step_scale * std::max({1.0, theta, omega, tau});
  const double tol = CentralDifferenceBound(h, Pendulum::g / Pendulum::l, 20.0);
  EXPECT_LT(tol, 1e-8);
  EXPECT_LT((lin.A - A).cwiseAbs().maxCoeff(), tol) << lin.A;
  EXPECT_LT((lin.B - B).cwiseAbs().maxCoeff(), tol) << lin.B;
  EXPECT_LT((lin.C - C).cwiseAbs().maxCoeff(), tol) << lin.C;
  EXPECT_LT((lin.D - D).cwiseAbs().maxCoeff(), tol) << lin.D;
  std::printf("pendulum: bound %.1e; max error A %.1e, B %.1e, C %.1e, D %.1e\n", tol,
              (lin.A - A).cwiseAbs().maxCoeff(), (lin.B - B).cwiseAbs().maxCoeff(), (lin.C - C).cwiseAbs().maxCoeff(),
              (lin.D - D).cwiseAbs().maxCoeff());
  EXPECT_EQ(lin.time, 0.25);
  EXPECT_NEAR(lin.xdot0[1],
              -(Pendulum::g / Pendulum::l) * std::sin(theta) - Pendulum::b * omega +
                  tau / (Pendulum::m * Pendulum::l * Pendulum::l),
              1e-14);
}

// ẍ = −ω² x written element by element into xdot, as the simulator's contract allows (xdot arrives sized): Linearize
// must hand it a sized vector too. A = [0 1; −ω² 0] exactly (central differences are exact on a linear system).
class Oscillator final : public LeafSystem {
 public:
  Oscillator() : LeafSystem("oscillator") { DeclareContinuousState(Eigen::Vector2d(1.0, 0.0)); }
  static constexpr double kOmega = 2.0;

 private:
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = c.continuous_state()[1];
    (*xdot)[1] = -kOmega * kOmega * c.continuous_state()[0];
  }
};

TEST(Linearize, ASystemWritingXdotByElementGetsASizedVector) {
  const Oscillator oscillator;
  auto context = oscillator.CreateDefaultContext();
  const LinearSystemMatrices lin = Linearize(oscillator, *context, "", "");
  Eigen::Matrix2d expected;
  expected << 0.0, 1.0, -Oscillator::kOmega * Oscillator::kOmega, 0.0;
  EXPECT_LT((lin.A - expected).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(Linearize, LeavesTheContextAsItWas) {
  Pendulum p;
  auto context = p.CreateDefaultLeafContext();
  const Eigen::Vector2d x0(0.1 + 1e-9, -0.3);  // values whose perturbations do not round-trip exactly
  context->get_mutable_continuous_state() = x0;
  const Eigen::VectorXd u0 = Eigen::VectorXd::Constant(1, 1.0 / 3.0);
  p.FixInputPort(*context, 0, u0);
  const Eigen::VectorXd y_before = p.EvalOutput(*context, "y");
  Linearize(p, *context, "tau", "y");
  EXPECT_EQ(context->continuous_state(), x0);  // bit for bit
  EXPECT_EQ(p.EvalInput(*context, 0), u0);
  EXPECT_EQ(p.EvalOutput(*context, "y"), y_before);
}

// Series composition: u → block 1 → block 2 → y. With x = (x1, x2):
//   A = [A1 0; B2 C1 A2],  B = [B1; B2 D1],  C = [D2 C1  C2],  D = D2 D1.
TEST(Linearize, DiagramInSeriesGivesTheComposedMatrices) {
  Eigen::MatrixXd A1(2, 2), B1(2, 1), C1(2, 2), D1(2, 1), A2(1, 1), B2(1, 2), C2(2, 1), D2(2, 2);
  A1 << -1, 2, 0.5, -3;
  B1 << 1, -2;
  C1 << 1, 0.5, -1, 2;
  D1 << 0.3, -0.7;
  A2 << -4;
  B2 << 2, -1;
  C2 << 1.5, -0.5;
  D2 << 1, 2, -3, 0.25;
  DiagramBuilder builder;
  builder.AddSystem(std::make_unique<LinearBlock>("first", A1, B1, C1, D1));
  builder.AddSystem(std::make_unique<LinearBlock>("second", A2, B2, C2, D2));
  builder.Connect("first", "y", "second", "u");
  builder.ExportInput("first", "u");
  builder.ExportOutput("second", "y");
  auto diagram = builder.Build("series");
  auto context = diagram->CreateDefaultContext();
  diagram->FixInputPort(*context, 0, Eigen::VectorXd::Constant(1, 0.8));
  diagram->GetMutableSubsystemContext(diagram->GetLeafByPath("first"), *context).get_mutable_continuous_state() << 2.0,
      -1.0;
  diagram->GetMutableSubsystemContext(diagram->GetLeafByPath("second"), *context).get_mutable_continuous_state() << 0.5;

  const LinearSystemMatrices lin = Linearize(*diagram, *context, "u", "y");
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(3, 3), B(3, 1), C(2, 3);
  A.topLeftCorner(2, 2) = A1;
  A.bottomLeftCorner(1, 2) = B2 * C1;
  A.bottomRightCorner(1, 1) = A2;
  B << B1, B2 * D1;
  C << D2 * C1, C2;
  const Eigen::MatrixXd D = D2 * D1;
  // Linear in (x, u): no truncation error, round-off only (|F| ≤ 20, h = step_scale · 2).
  const double tol = CentralDifferenceBound(LinearizeParams{}.step_scale * 2.0, 0.0, 20.0);
  EXPECT_LT((lin.A - A).cwiseAbs().maxCoeff(), tol) << lin.A;
  EXPECT_LT((lin.B - B).cwiseAbs().maxCoeff(), tol) << lin.B;
  EXPECT_LT((lin.C - C).cwiseAbs().maxCoeff(), tol) << lin.C;
  EXPECT_LT((lin.D - D).cwiseAbs().maxCoeff(), tol) << lin.D;
  EXPECT_EQ(diagram->EvalInput(*context, 0)[0], 0.8);  // input restored
}

// Pendulum → Gain K: the diagram's C and D are K times the pendulum's.
TEST(Linearize, DiagramWithGainScalesOutputJacobians) {
  Eigen::MatrixXd K(2, 3);
  K << 1, -2, 0.5, 0, 3, -1;
  DiagramBuilder builder;
  const Pendulum* pendulum = builder.AddSystem(std::make_unique<Pendulum>());
  builder.AddSystem(std::make_unique<Gain>("gain", K));
  builder.Connect("pendulum", "y", "gain", "u");
  builder.ExportInput("pendulum", "tau");
  builder.ExportOutput("gain", "y");
  auto diagram = builder.Build("pendulum_with_gain");
  auto context = diagram->CreateDefaultContext();
  diagram->FixInputPort(*context, 0, Eigen::VectorXd::Constant(1, -0.5));
  diagram->GetMutableSubsystemContext(*pendulum, *context).get_mutable_continuous_state() << 0.4, 1.2;
  const LinearSystemMatrices whole = Linearize(*diagram, *context, "tau", "y");

  Pendulum alone;
  auto leaf_context = alone.CreateDefaultLeafContext();
  leaf_context->get_mutable_continuous_state() << 0.4, 1.2;
  alone.FixInputPort(*leaf_context, 0, Eigen::VectorXd::Constant(1, -0.5));
  const LinearSystemMatrices part = Linearize(alone, *leaf_context, "tau", "y");
  EXPECT_LT((whole.A - part.A).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((whole.B - part.B).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT((whole.C - K * part.C).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((whole.D - K * part.D).cwiseAbs().maxCoeff(), 1e-9);
}

using test::ErrorOf;

TEST(Linearize, ErrorsNameTheSystemAndWhatIsWrong) {
  Pendulum p;
  auto context = p.CreateDefaultLeafContext();
  EXPECT_EQ(ErrorOf([&] { Linearize(p, *context, "tau", "y"); }),
            "Linearize: system 'pendulum': input port 'tau' has no fixed value; fix it to the operating-point input u0 "
            "first");
  p.FixInputPort(*context, 0, Eigen::VectorXd::Zero(1));
  EXPECT_EQ(ErrorOf([&] { Linearize(p, *context, "torque", "y"); }),
            "system 'pendulum' has no input port 'torque' (it has 'tau')");
  EXPECT_EQ(ErrorOf([&] { Linearize(p, *context, "tau", "tip"); }),
            "system 'pendulum' has no output port 'tip' (it has 'y')");
  EXPECT_NE(ErrorOf([&] { Linearize(p, *context, "tau", "y", LinearizeParams{0.0}); }).find("step_scale"),
            std::string::npos);

  Gain gain("gain", 2.0, 1);
  auto gain_context = gain.CreateDefaultLeafContext();
  gain.FixInputPort(*gain_context, 0, Eigen::VectorXd::Zero(1));
  EXPECT_EQ(ErrorOf([&] { Linearize(gain, *gain_context, "u", "y"); }),
            "Linearize: system 'gain': has no continuous state; Linearize needs xdot = f(t, x, u) to form A and B");

  // A leaf inside a diagram whose input is connected: its input cannot be perturbed on its own.
  DiagramBuilder builder;
  builder.AddSystem(std::make_unique<ConstantVectorSource>("torque", Eigen::VectorXd::Constant(1, 0.5)));
  const Pendulum* inner = builder.AddSystem(std::make_unique<Pendulum>());
  builder.Connect("torque", "y", "pendulum", "tau");
  auto diagram = builder.Build();
  auto diagram_context = diagram->CreateDefaultContext();
  LeafContext& inner_context = diagram->GetMutableSubsystemContext(*inner, *diagram_context);
  EXPECT_EQ(ErrorOf([&] { Linearize(*inner, inner_context, "tau", "y"); }),
            "input port 'tau' of system 'pendulum' is connected; it cannot also be fixed");
  EXPECT_EQ(inner->EvalInput(inner_context, 0)[0], 0.5);  // still connected

  SquareRootFlow flow;
  auto flow_context = flow.CreateDefaultLeafContext();
  const std::string at_perturbed = ErrorOf([&] { Linearize(flow, *flow_context, "", ""); });
  EXPECT_NE(at_perturbed.find("time derivative xdot[0] is NaN at x[0] - "), std::string::npos) << at_perturbed;
  EXPECT_EQ(flow_context->continuous_state()[0], 0.0);  // restored after the error
  flow_context->get_mutable_continuous_state()[0] = -1.0;
  EXPECT_NE(ErrorOf([&] { Linearize(flow, *flow_context, "", ""); }).find("xdot[0] is NaN at the operating point"),
            std::string::npos);
}

}  // namespace
}  // namespace rome
