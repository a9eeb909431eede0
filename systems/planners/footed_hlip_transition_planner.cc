#include "systems/planners/footed_hlip_transition_planner.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "systems/rom/hybrid_linear_inverted_pendulum.h"

namespace rome {
namespace {

[[noreturn]] void Fail(const std::string& what) { throw std::invalid_argument("FootedHlipTransitionPlanner: " + what); }

}  // namespace

FootedHlipTransitionPlanner::FootedHlipTransitionPlanner(FootedHlipTransitionParams params) : params_(params) {
  auto positive = [](double v, const char* name) {
    if (!(v > 0) || !std::isfinite(v)) {
      std::ostringstream msg;
      msg << "parameter " << name << " must be > 0, got " << v;
      Fail(msg.str());
    }
  };
  positive(params_.mass, "mass");
  positive(params_.gravity, "gravity");
  positive(params_.foot_width_left_of_ankle, "foot_width_left_of_ankle");
  positive(params_.foot_width_right_of_ankle, "foot_width_right_of_ankle");
  positive(params_.max_ankle_roll_torque, "max_ankle_roll_torque");
}

FootedHlipTransitionPlan FootedHlipTransitionPlanner::Solve(const FootedHlipTransitionData& d) const {
  const int N = static_cast<int>(d.node_times.size());
  std::ostringstream msg;
  if (N < 2) Fail("node_times needs at least 2 nodes, got " + std::to_string(N));
  if (static_cast<int>(d.single_support.size()) != N - 1 || d.left_normal_force.size() != N ||
      d.right_normal_force.size() != N) {
    msg << "with " << N << " nodes, single_support needs " << N - 1 << " entries and each normal force " << N
        << ", got " << d.single_support.size() << ", " << d.left_normal_force.size() << ", "
        << d.right_normal_force.size();
    Fail(msg.str());
  }
  for (int k = 0; k + 1 < N; ++k) {
    if (!(d.node_times(k + 1) > d.node_times(k))) {
      msg << "node_times must increase strictly, got t[" << k << "] = " << d.node_times(k) << " and t[" << k + 1
          << "] = " << d.node_times(k + 1);
      Fail(msg.str());
    }
  }
  for (int k = 0; k < N; ++k) {
    if (!(d.left_normal_force(k) >= 0) || !(d.right_normal_force(k) >= 0)) {
      msg << "normal forces must be >= 0 N and finite, got F_L[" << k << "] = " << d.left_normal_force(k) << ", F_R["
          << k << "] = " << d.right_normal_force(k);
      Fail(msg.str());
    }
  }
  if (!(d.z0 > 0) || !d.initial_state.allFinite() || !d.final_state.allFinite()) {
    msg << "z0 must be > 0 m and the boundary states finite, got z0 = " << d.z0;
    Fail(msg.str());
  }
  const bool heights = params_.normal_force_pivots && d.node_heights.size() > 0;
  if (d.node_heights.size() > 0 &&
      (d.node_heights.size() != N || !(d.node_heights.minCoeff() > 0) || !d.node_heights.allFinite())) {
    msg << "node_heights must hold " << N << " heights > 0 m (or none), got " << d.node_heights.size()
        << (d.node_heights.size() > 0 ? " with the smallest " + std::to_string(d.node_heights.minCoeff()) + " m"
                                      : std::string());
    Fail(msg.str());
  }
  const double m = params_.mass, lambda = std::sqrt(params_.gravity / d.z0);
  const int n = 4 * N, n_eq = 2 * (N - 1) + 4, n_ineq = 2 * N;
  auto uL = [](int k) { return k; };
  auto uR = [N](int k) { return N + k; };
  auto Y = [N](int k) { return 2 * N + 2 * k; };
  DenseQpSolver qp(n, n_eq, n_ineq);
  // Eq. (15) cost Σ (u_L² + u_R²) = ½ zᵀ H z with H = 2 I on the torques.
  for (int k = 0; k < 2 * N; ++k) qp.H(k, k) = 2.0;
  // Dynamics: Y^{k+1} = A (Y^k − [c; 0]) + [c; 0] + B u^k on every interval.
  const double y_stance = d.stance_left ? d.left_foot_y : d.right_foot_y;
  Eigen::VectorXd stiffness(N - 1), pivot(N - 1), height(N - 1);
  for (int k = 0; k + 1 < N; ++k) {
    const double T = d.node_times(k + 1) - d.node_times(k);
    const bool ssp = d.single_support[k];
    double a = ssp ? lambda * lambda : 0.0, c = ssp ? y_stance : 0.0;
    const double z = heights ? 0.5 * (d.node_heights(k) + d.node_heights(k + 1)) : d.z0;
    if (params_.normal_force_pivots) {
      const double FL = 0.5 * (d.left_normal_force(k) + d.left_normal_force(k + 1));
      const double FR = 0.5 * (d.right_normal_force(k) + d.right_normal_force(k + 1));
      a = (FL + FR) / (m * z);
      c = FL + FR > 0 ? (FL * d.left_foot_y + FR * d.right_foot_y) / (FL + FR) : 0.0;
    }
    stiffness(k) = a;
    pivot(k) = c;
    height(k) = z;
    const FootedLinearInvertedPendulumStep s =
        FootedLinearInvertedPendulumDiscretization(a > 0 ? std::sqrt(a) : lambda, T, m, z, a > 0);
    const int row = 2 * k;
    qp.A_eq.block<2, 2>(row, Y(k + 1)) = Eigen::Matrix2d::Identity();
    qp.A_eq.block<2, 2>(row, Y(k)) = -s.A;
    qp.b_eq.segment<2>(row) = (Eigen::Matrix2d::Identity() - s.A) * Eigen::Vector2d(c, 0.0);
    if (ssp && !params_.normal_force_pivots) {
      qp.A_eq.block<2, 1>(row, d.stance_left ? uL(k) : uR(k)) = -s.B;
    } else {
      qp.A_eq.block<2, 1>(row, uL(k)) = -s.B;
      qp.A_eq.block<2, 1>(row, uR(k)) = -s.B;
    }
  }
  const int b = 2 * (N - 1);
  qp.A_eq.block<2, 2>(b, Y(0)) = Eigen::Matrix2d::Identity();
  qp.b_eq.segment<2>(b) = d.initial_state;
  qp.A_eq.block<2, 2>(b + 2, Y(N - 1)) = Eigen::Matrix2d::Identity();
  qp.b_eq.segment<2>(b + 2) = d.final_state;
  // Eq. (14): −W1 F ≤ u ≤ W2 F per foot and node; |u| ≤ u_max.
  for (int k = 0; k < N; ++k) {
    qp.A(2 * k, uL(k)) = 1.0;
    qp.l(2 * k) = -params_.foot_width_left_of_ankle * d.left_normal_force(k);
    qp.u(2 * k) = params_.foot_width_right_of_ankle * d.left_normal_force(k);
    qp.A(2 * k + 1, uR(k)) = 1.0;
    qp.l(2 * k + 1) = -params_.foot_width_left_of_ankle * d.right_normal_force(k);
    qp.u(2 * k + 1) = params_.foot_width_right_of_ankle * d.right_normal_force(k);
  }
  qp.lb.head(2 * N).setConstant(-params_.max_ankle_roll_torque);
  qp.ub.head(2 * N).setConstant(params_.max_ankle_roll_torque);

  FootedHlipTransitionPlan plan;
  plan.status = qp.Solve();
  plan.iterations = qp.iterations();
  std::ostringstream out;
  out << "footed H-LIP transition QP (" << N << " nodes): " << to_string(plan.status);
  if (!plan.success()) out << " (" << qp.status_message() << ")";
  plan.message = out.str();
  const Eigen::VectorXd& z = qp.x();
  plan.left_torque = z.head(N);
  plan.right_torque = z.segment(N, N);
  plan.states = Eigen::Map<const Eigen::MatrixXd>(z.data() + 2 * N, 2, N);
  plan.interval_stiffness = stiffness;
  plan.interval_pivot = pivot;
  plan.interval_height = height;
  plan.cost = plan.left_torque.squaredNorm() + plan.right_torque.squaredNorm();
  return plan;
}

}  // namespace rome
