// The CLF-QP's joint-limit brake (joint_limit_brake.h) on the 2 kg slider (q̈ = u / m, closed form) with its upper
// limit moved to 0.5 m: a task that drives the block past the limit gets the torque whose constant-acceleration
// prediction over the horizon ends exactly the margin inside the limit, the brake row is active with a multiplier of
// the right sign (the KKT conditions of the solved QP, checked from its data), and without the brake the same task
// takes the full 20 N toward the stop. Far from the limit the brake changes nothing.
#include "systems/controllers/joint_limit_brake.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "systems/controllers/clf_qp_controller.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kMass = 2.0, kUpper = 0.5, kForceLimit = 20.0;

std::string ReadFile(const std::string& path) {
  std::ifstream in(rome::test::SourcePath(path));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The slider of the CLF-QP tests with its upper limit at kUpper.
std::shared_ptr<const MultibodyModel> LimitedSlider() {
  std::string urdf = ReadFile("tests/systems/controllers/data/slider.urdf");
  const std::string from = "upper=\"10\"";
  const size_t at = urdf.find(from);
  EXPECT_NE(at, std::string::npos);
  urdf.replace(at, from.size(), "upper=\"0.5\"");
  return std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromText(urdf, ReadFile("tests/systems/controllers/data/slider.rome.json")));
}

struct Answer {
  double u = 0;
  QpStatus status = QpStatus::kInvalidInput;
  double stationarity = 0;  // ||H x + g + Aᵀ y_ineq + y_bounds||_inf / max(1, ||g||_inf, ||H x||_inf) of the final QP
  double brake_multiplier = 0;
  double brake_slack = 0;  // u_row − a_rowᵀ x of the brake row
};

Answer Solve(bool brake, double q, double v, double y_desired) {
  const auto model = LimitedSlider();
  ClfQpParams params;
  params.joint_limit_brake.enabled = brake;
  ClfQpController controller("clf", model, {0},
                             {ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("x", *model, "slide"))},
                             params);
  auto context = controller.CreateDefaultLeafContext();
  context->FixInputPort(0, Eigen::Vector2d(q, v));
  context->FixAbstractInputPort(1, std::any(0));
  context->FixInputPort(2, Eigen::Vector3d(y_desired, 0.0, 0.0));
  Eigen::VectorXd next = context->discrete_state();
  EXPECT_TRUE(controller.periodic_events().at(0).update(*context, &next).ok());
  context->get_mutable_discrete_state() = next;
  Answer a;
  a.u = controller.EvalOutput(*context, "u")[0];
  a.status = controller.diagnostics(*context).qp_status.value_or(QpStatus::kInvalidInput);
  const DenseQpSolver& qp = controller.last_qp(*context);
  const Eigen::VectorXd Hx = qp.H * qp.x();
  a.stationarity = (Hx + qp.g + qp.A.transpose() * qp.y_ineq() + qp.y_bounds()).cwiseAbs().maxCoeff() /
                   std::max({1.0, qp.g.cwiseAbs().maxCoeff(), Hx.cwiseAbs().maxCoeff()});
  if (brake) {
    EXPECT_EQ(qp.num_inequalities(), 2);  // the CLF row, then the brake row of the one limited joint
    a.brake_multiplier = qp.y_ineq()[1];
    a.brake_slack = qp.u[1] - qp.A.row(1).dot(qp.x());
  }
  return a;
}

TEST(JointLimitBrake, ATaskPastTheLimitIsBrakedToTheMarginAtTheHorizon) {
  const JointLimitBrakeParams p;  // margin 0.02 m, horizon 0.05 s
  // Coasting, the block would be at 0.49 m at the horizon: the full 20 N forward takes it past the 0.5 m limit, and
  // 16 N backward keeps it at the margin (within the 20 N limit).
  const double q = 0.4, v = 1.8, T = p.horizon_s;
  // Closed form: q + v T + ½ (u / m) T² = q_max − margin  ⇒  u = 2 m (q_max − margin − q − v T) / T² = −16 N.
  const double u_brake = 2.0 * kMass * (kUpper - p.margin_rad - q - v * T) / (T * T);
  ASSERT_LT(std::abs(u_brake), kForceLimit);
  const Answer free = Solve(false, q, v, 2.0);
  ASSERT_EQ(free.status, QpStatus::kOptimal);
  EXPECT_NEAR(free.u, kForceLimit, 1e-9);  // without the brake the task pushes with all it has (the CLF row asks
  // ÿ ≥ 25 m/s² here, beyond the 20 N limit)
  EXPECT_GT(q + v * T + 0.5 * free.u / kMass * T * T, kUpper);
  const Answer braked = Solve(true, q, v, 2.0);
  ASSERT_EQ(braked.status, QpStatus::kOptimal);
  EXPECT_NEAR(braked.u, u_brake, 1e-7);
  EXPECT_NEAR(q + v * T + 0.5 * braked.u / kMass * T * T, kUpper - p.margin_rad, 1e-9);
  // KKT: stationarity holds, the brake row is at its upper side with a positive multiplier (solver convention).
  EXPECT_LT(braked.stationarity, 1e-9);
  EXPECT_NEAR(braked.brake_slack, 0.0, 1e-9);
  EXPECT_GT(braked.brake_multiplier, 1e-6);
}

TEST(JointLimitBrake, FarFromTheLimitTheBrakeChangesNothing) {
  const Answer free = Solve(false, -0.5, -0.2, 0.0), braked = Solve(true, -0.5, -0.2, 0.0);
  ASSERT_EQ(braked.status, QpStatus::kOptimal);
  EXPECT_NEAR(braked.u, free.u, 1e-9);
  EXPECT_EQ(braked.brake_multiplier, 0.0);
  EXPECT_GT(braked.brake_slack, 1.0);
  EXPECT_LT(braked.stationarity, 1e-9);
}

TEST(JointLimitBrake, BoundsFollowTheConstantAccelerationPrediction) {
  const auto model = LimitedSlider();
  JointLimitBrakeParams p;
  p.enabled = true;
  const JointLimitBrake brake(*model, p, "test");
  ASSERT_EQ(brake.num_rows(), 1);
  double lo = 0, hi = 0;
  brake.Bounds(0.1, -0.3, 0, &lo, &hi);
  // At the bounds, q + v T + ½ q̈ T² lands on q_lower + margin and q_upper − margin.
  const double T = p.horizon_s;
  EXPECT_NEAR(0.1 - 0.3 * T + 0.5 * hi * T * T, kUpper - p.margin_rad, 1e-12);
  EXPECT_NEAR(0.1 - 0.3 * T + 0.5 * lo * T * T, -10.0 + p.margin_rad, 1e-12);
}

TEST(JointLimitBrake, BadParametersAreNamed) {
  const auto model = LimitedSlider();
  JointLimitBrakeParams p;
  p.enabled = true;
  p.horizon_s = 0.0;
  try {
    JointLimitBrake brake(*model, p, "system 'clf'");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("system 'clf': params.joint_limit_brake.horizon_s = 0"), std::string::npos)
        << e.what();
  }
  p.horizon_s = 0.05;
  p.margin_rad = 6.0;  // the slider's range is [-10, 0.5] m
  try {
    JointLimitBrake brake(*model, p, "system 'clf'");
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint 'slide'"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace rome
