// PreImpactPostureOptimizer (Eq. (21)): the solution meets the stone, joint-limit and COM-height constraints (checked
// with independent multibody calls), is a strict local minimum (reduced gradient zero and no feasible perturbation
// lowers the cost), and an unreachable stone is reported as infeasible with the documented fallback.
#include "systems/posture/pre_impact_posture_optimizer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

#include "systems/multibody/multibody_kinematics.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

std::shared_ptr<const MultibodyModel> LoadRobot(const std::string& robot) {
  return std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/" + robot + "/" + robot + ".rome.json"), {.euler_floating_base = true}));
}

Eigen::Vector3d FootPosition(const MultibodyModel& model, const Eigen::VectorXd& q, const std::string& contact) {
  MultibodyWorkspace ws(model);
  const ContactInfo& c = model.contacts()[model.ContactIndex(contact)];
  return CalcPointPosition(model, ws, q, c.body, c.frame_origin);
}

void ExpectFeasible(const MultibodyModel& model, const PreImpactPostureParams& params, const PreImpactPostureRequest& r,
                    const PreImpactPosture& p) {
  ASSERT_TRUE(p.success) << p.message;
  ASSERT_EQ(p.q.size(), model.nv());
  const Eigen::Vector3d st = FootPosition(model, p.q, r.stance_contact), sw = FootPosition(model, p.q, r.swing_contact);
  EXPECT_NEAR(st.x(), r.stance_foot_position.x(), 1e-9);
  EXPECT_NEAR(st.z(), r.stance_foot_position.y(), 1e-9);
  EXPECT_NEAR(sw.x() - st.x(), r.step_length_m, 1e-6);
  EXPECT_NEAR(sw.z() - st.z(), r.step_height_m, 1e-6);
  MultibodyWorkspace ws(model);
  const Eigen::Vector3d com = CalcComPosition(model, ws, p.q);
  EXPECT_GE(com.z() - std::min(st.z(), sw.z()), params.min_com_height_m - 1e-6);  // above the lower foot
  EXPECT_NEAR(p.com_height_m, com.z() - st.z(), 1e-9);
  EXPECT_NEAR(p.com_x_m, com.x() - st.x(), 1e-9);
  EXPECT_EQ(p.torso_pitch_rad, p.q[2]);
  for (int i = 3; i < model.nv(); ++i) {
    EXPECT_GE(p.q[i], model.position_lower_limits()[i] - 1e-6) << model.JointName(i);
    EXPECT_LE(p.q[i], model.position_upper_limits()[i] + 1e-6) << model.JointName(i);
  }
}

// Strict local minimum on the constraint manifold: the reduced gradient Zᵀ∇f vanishes, and moving along the
// manifold (a null-space step followed by a Newton projection back onto the active constraints) raises the cost.
void ExpectLocalMinimum(const MultibodyModel& model, const PreImpactPostureParams& params,
                        const PreImpactPostureRequest& r, const PreImpactPosture& p) {
  PreImpactPostureProblem problem(model, params, r);
  const Eigen::VectorXd x = problem.FromConfiguration(p.q);
  const int n = problem.num_variables(), m = problem.num_constraints();
  Eigen::VectorXd g(m), grad(n), values(problem.constraint_jacobian_sparsity().nnz());
  problem.EvalConstraints(x, g);
  problem.EvalConstraintJacobian(x, values);
  problem.EvalCostGradient(x, grad);
  const double f0 = problem.EvalCost(x);
  // Active rows: equalities, plus the COM-height row if it is at its bound.
  std::vector<int> active;
  for (int i = 0; i < m; ++i)
    if (problem.constraint_lower_bounds()[i] == problem.constraint_upper_bounds()[i] ||
        std::abs(g[i] - problem.constraint_lower_bounds()[i]) < 1e-7)
      active.push_back(i);
  Eigen::MatrixXd A(active.size(), n);
  for (size_t k = 0; k < active.size(); ++k)
    for (int j = 0; j < n; ++j) A(k, j) = values[active[k] * n + j];
  for (int j = 0; j < n; ++j)
    ASSERT_TRUE(x[j] > problem.variable_lower_bounds()[j] + 1e-6 && x[j] < problem.variable_upper_bounds()[j] - 1e-6)
        << "joint limit active; test assumes interior";
  Eigen::FullPivLU<Eigen::MatrixXd> lu(A);
  const Eigen::MatrixXd Z = lu.kernel();
  const double reduced_gradient = (Z.transpose() * grad).cwiseAbs().maxCoeff();
  std::mt19937 rng(11);
  std::normal_distribution<double> N(0.0, 1.0);
  double worst_decrease = 0.0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::VectorXd d = Z * Eigen::VectorXd::NullaryExpr(Z.cols(), [&] { return N(rng); });
    d *= 1e-3 / d.norm();
    Eigen::VectorXd y = x + d;
    for (int it = 0; it < 20; ++it) {  // project back: A(y) Δ = −c(y), minimum norm
      problem.EvalConstraints(y, g);
      problem.EvalConstraintJacobian(y, values);
      Eigen::VectorXd c(active.size());
      for (size_t k = 0; k < active.size(); ++k) {
        c[k] = g[active[k]] - problem.constraint_lower_bounds()[active[k]];
        for (int j = 0; j < n; ++j) A(k, j) = values[active[k] * n + j];
      }
      if (c.norm() < 1e-13) break;
      y -= A.completeOrthogonalDecomposition().solve(c);
    }
    worst_decrease = std::max(worst_decrease, f0 - problem.EvalCost(y));
  }
  std::printf(
      "  local minimum: %zu active constraints, %d free directions, |Zᵀ∇f| = %.2e, worst cost decrease under 1 mrad "
      "moves %.2e (f* = %.3e)\n",
      active.size(), static_cast<int>(Z.cols()), reduced_gradient, worst_decrease, f0);
  EXPECT_LT(reduced_gradient, 1e-6);
  EXPECT_LE(worst_decrease, 1e-12);
}

TEST(PreImpactPostureOptimizer, AmberPosturesMeetTheStoneAndAreLocalMinima) {
  auto model = LoadRobot("amber");
  PreImpactPostureParams params;
  PreImpactPostureOptimizer optimizer(model, params);
  struct Step {
    double l, h;
  };
  for (const Step s : {Step{0.3, 0.0}, Step{0.45, 0.1}, Step{0.5, -0.15}, Step{0.2, 0.2}, Step{0.1, -0.2}}) {
    PreImpactPostureRequest r;
    r.step_length_m = s.l;
    r.step_height_m = s.h;
    r.stance_foot_position = Eigen::Vector2d(1.5, 0.25);
    const PreImpactPosture p = optimizer.Solve(r);
    std::printf(
        "step l = %.2f h = %+.2f: %s\n  φ_f = %+.5f rad, p_com,f^z = %.4f m, p_com^x = %.4f m (εl = %.4f), solve %.2f "
        "ms, %d iterations\n",
        s.l, s.h, p.message.c_str(), p.torso_pitch_rad, p.com_height_m, p.com_x_m, params.com_x_fraction * s.l,
        p.solve_time_s * 1e3, p.iterations);
    ExpectFeasible(*model, params, r, p);
    EXPECT_EQ(p.status, NlpStatus::kSolved);
    EXPECT_EQ(p.fallback, PreImpactPosture::Fallback::kNone);
    // Eq. (21)'s terms are (nearly) zero: the only bias is the tiny posture term.
    EXPECT_NEAR(p.com_x_m, params.com_x_fraction * s.l, 1e-3);
    EXPECT_NEAR(p.torso_pitch_rad, 0.0, 1e-3);
    ExpectLocalMinimum(*model, params, r, p);
  }
}

TEST(PreImpactPostureOptimizer, MinimumComHeightBindsAndIsMet) {
  auto model = LoadRobot("amber");
  PreImpactPostureParams params;
  PreImpactPostureRequest r;
  r.step_length_m = 0.5;
  PreImpactPostureOptimizer free_optimizer(model, params);
  const PreImpactPosture free = free_optimizer.Solve(r);
  ASSERT_TRUE(free.success) << free.message;
  // The highest COM this step allows (approximately): pull the COM up hard.
  PreImpactPostureParams high_params = params;
  high_params.com_height_weight = 100.0;
  PreImpactPostureRequest high_request = r;
  high_request.com_height_m = 1.5;
  const PreImpactPosture high = PreImpactPostureOptimizer(model, high_params).Solve(high_request);
  ASSERT_TRUE(high.success) << high.message;
  ASSERT_GT(high.com_height_m, free.com_height_m + 0.005);
  // Ask for a COM halfway between the free optimum and that: the bound becomes active.
  const double bound_above_stance = 0.5 * (free.com_height_m + high.com_height_m);
  params.min_com_height_m = bound_above_stance - std::min(r.step_height_m, 0.0);  // the bound is above the lower foot
  PreImpactPostureOptimizer optimizer(model, params);
  const PreImpactPosture p = optimizer.Solve(r);
  std::printf("  free COM height %.4f m, with p_com^{z,min} = %.4f m: %.4f m (%s)\n", free.com_height_m,
              params.min_com_height_m, p.com_height_m, p.message.c_str());
  ExpectFeasible(*model, params, r, p);
  EXPECT_NEAR(p.com_height_m, bound_above_stance, 1e-6);
  EXPECT_GE(p.cost, free.cost - 1e-12);  // a tighter feasible set cannot lower the optimum
  ExpectLocalMinimum(*model, params, r, p);
}

TEST(PreImpactPostureOptimizer, LongStepDownKeepsTheMinimumHeightAboveTheLandingFoot) {
  // 0.5 m forward and 0.25 m down (the largest random-stone drop of the paper): with the default 0.7 m bound measured
  // from the stance foot, the COM would have to be 0.95 m above the landing foot, beyond AMBER's 0.87 m legs.
  auto model = LoadRobot("amber");
  PreImpactPostureParams params;
  PreImpactPostureRequest r;
  r.step_length_m = 0.5;
  r.step_height_m = -0.25;
  const PreImpactPosture p = PreImpactPostureOptimizer(model, params).Solve(r);
  std::printf("  l = 0.5 m, h = -0.25 m: COM %.4f m above the stance foot, %.4f m above the landing foot (%s)\n",
              p.com_height_m, p.com_height_m - r.step_height_m, p.message.c_str());
  ExpectFeasible(*model, params, r, p);
  EXPECT_GE(p.com_height_m - r.step_height_m, params.min_com_height_m - 1e-6);
  EXPECT_LT(p.com_height_m - r.step_height_m, 0.87 + 0.05);  // geometry: legs of 0.87 m, COM about 4 cm above the hip
}

TEST(PreImpactPostureOptimizer, StoneOutOfReachIsReportedAsInfeasibleWithTheFallback) {
  auto model = LoadRobot("amber");
  PreImpactPostureOptimizer optimizer(model);
  PreImpactPostureRequest r;
  r.step_length_m = 2.0;  // the legs are 0.87 m long: no posture reaches 2 m
  const PreImpactPosture p = optimizer.Solve(r);
  std::printf("  %s (%.2f ms)\n", p.message.c_str(), p.solve_time_s * 1e3);
  EXPECT_FALSE(p.success);
  EXPECT_EQ(p.status, NlpStatus::kInfeasible);
  EXPECT_NE(p.message.find("infeasible"), std::string::npos);
  EXPECT_NE(p.message.find("l = 2 m"), std::string::npos);
  EXPECT_EQ(p.fallback, PreImpactPosture::Fallback::kNominalPose);
  EXPECT_EQ((p.q.tail(5) - model->q_nominal().tail(5)).norm(), 0.0);
  // After a successful step, the fallback is that solution.
  r.step_length_m = 0.3;
  const PreImpactPosture good = optimizer.Solve(r);
  ASSERT_TRUE(good.success) << good.message;
  r.step_length_m = 2.0;
  const PreImpactPosture again = optimizer.Solve(r);
  EXPECT_FALSE(again.success);
  EXPECT_EQ(again.fallback, PreImpactPosture::Fallback::kPreviousSolution);
  EXPECT_NEAR((again.q - good.q).norm(), 0.0, 1e-12);
  EXPECT_NE(again.message.find("previous solution"), std::string::npos);
}

TEST(PreImpactPostureOptimizer, MalformedRequestsAreNamed) {
  auto model = LoadRobot("amber");
  PreImpactPostureOptimizer optimizer(model);
  PreImpactPostureRequest r;
  r.swing_contact = "right_toe";
  try {
    optimizer.Solve(r);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'right_toe'"), std::string::npos) << e.what();
  }
  r.swing_contact = "left_foot";
  EXPECT_THROW(optimizer.Solve(r), std::invalid_argument);
  r = {};
  r.step_length_m = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(optimizer.Solve(r), std::invalid_argument);
  EXPECT_THROW(PreImpactPostureOptimizer(LoadRobot("exoskeleton")), std::invalid_argument);
}

}  // namespace
}  // namespace rome
