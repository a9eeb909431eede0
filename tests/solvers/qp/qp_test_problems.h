#pragma once
// Seeded QP problem families shared by the DenseQpSolver tests and tests/benchmarks/qp/qp_benchmark.cpp.
//
// Every family is feasible by construction: a strictly feasible point x_feas is drawn first, the equality
// right-hand sides are A_eq x_feas and every inequality side keeps a positive margin at x_feas. The linear term
// pulls the unconstrained minimum x_des well outside the feasible set, so several constraints are active.
// Variables are normalized (forces by body weight m g, torques by their limits), so the data is O(1).
//
//   A: CLF-QP (Eq. (26) of the aSLIP/H-LIP walking paper): x = [tau (6); F_left (3); F_right (3)], 12 variables,
//      2 equalities (holonomic / vertical dynamics rows), 21 inequality rows (1 CLF row dV/dt <= -gamma V, 2 x 10
//      ground-reaction-force rows: 8-face friction pyramid, normal-force window), 12 two-sided bounds.
//   B: task-space QP with contact forces as variables: x = [qdd (10); F (4 contacts x 3)], 22 variables,
//      12 equalities (6 floating-base dynamics rows, 6 contact-acceleration rows), 30 inequality rows
//      (4 x (4 pyramid faces + 1 normal window) + 10 joint-torque rows), no bounds.
//   C: MPC for a double integrator (H-LIP-like transition) over N steps, x = [u_k, p_{k+1}, v_{k+1}]_k, 3N
//      variables, 2N dynamics equalities (banded), N input-rate rows, bounds on u, p, v. Tridiagonal-block H.
//   D: condensed MPC of a double integrator (CondensedMpcSequence): N input variables, dense H, 2N two-sided
//      state rows, input bounds; H and A are fixed and only g and the row bounds move with the initial state,
//      which follows the closed loop of the MPC itself (the qpOASES "hot start" use case).
//
// Each family is a smooth function of time t (seconds) so that consecutive samples 1 ms apart form the slowly
// changing sequence of a 1 kHz control loop.

#include <Eigen/Dense>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "solvers/qp/dense_qp_solver.h"

namespace rome::qp_test {

struct QpProblem {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  Eigen::MatrixXd A_eq;
  Eigen::VectorXd b_eq;
  Eigen::MatrixXd A;
  Eigen::VectorXd l, u, lb, ub;
  int n() const { return static_cast<int>(H.rows()); }
  int n_eq() const { return static_cast<int>(A_eq.rows()); }
  int n_ineq() const { return static_cast<int>(A.rows()); }
};

inline constexpr double kInf = std::numeric_limits<double>::infinity();

// Copies the problem into the solver's preallocated data (no allocation when the sizes match).
inline void LoadInto(const QpProblem& p, DenseQpSolver* solver) {
  if (solver->num_variables() != p.n() || solver->num_equalities() != p.n_eq() ||
      solver->num_inequalities() != p.n_ineq()) {
    solver->Resize(p.n(), p.n_eq(), p.n_ineq());
  }
  solver->H = p.H;
  solver->g = p.g;
  solver->A_eq = p.A_eq;
  solver->b_eq = p.b_eq;
  solver->A = p.A;
  solver->l = p.l;
  solver->u = p.u;
  solver->lb = p.lb;
  solver->ub = p.ub;
}

inline Eigen::MatrixXd RandomMatrix(std::mt19937& rng, int rows, int cols, double scale = 1.0) {
  std::normal_distribution<double> normal(0.0, scale);
  Eigen::MatrixXd m(rows, cols);
  for (int j = 0; j < cols; ++j)
    for (int i = 0; i < rows; ++i) m(i, j) = normal(rng);
  return m;
}

inline double Uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}

// Generic random convex QP of assorted structure. Condition number of H <= ~1e3.
inline QpProblem RandomQp(std::mt19937& rng, int n, int n_eq, int n_ineq, bool with_bounds) {
  QpProblem p;
  const Eigen::MatrixXd M = RandomMatrix(rng, n, n);
  p.H = M.transpose() * M / n + Uniform(rng, 0.01, 1.0) * Eigen::MatrixXd::Identity(n, n);
  const Eigen::VectorXd x_feas = RandomMatrix(rng, n, 1);
  const Eigen::VectorXd x_des = x_feas + 3.0 * RandomMatrix(rng, n, 1);
  p.g = -p.H * x_des;
  p.A_eq = RandomMatrix(rng, n_eq, n);
  p.b_eq = p.A_eq * x_feas;
  p.A = RandomMatrix(rng, n_ineq, n);
  const Eigen::VectorXd ax = p.A * x_feas;
  p.l.resize(n_ineq);
  p.u.resize(n_ineq);
  for (int i = 0; i < n_ineq; ++i) {
    const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
    p.l[i] = (kind == 1) ? -kInf : ax[i] - Uniform(rng, 0.01, 1.0);
    p.u[i] = (kind == 2) ? kInf : ax[i] + Uniform(rng, 0.01, 1.0);
  }
  p.lb = Eigen::VectorXd::Constant(n, -kInf);
  p.ub = Eigen::VectorXd::Constant(n, kInf);
  if (with_bounds) {
    for (int j = 0; j < n; ++j) {
      const int kind = std::uniform_int_distribution<int>(0, 3)(rng);
      if (kind != 1) p.lb[j] = x_feas[j] - Uniform(rng, 0.05, 1.5);
      if (kind != 2) p.ub[j] = x_feas[j] + Uniform(rng, 0.05, 1.5);
    }
  }
  return p;
}

// ---------------------------------------------------------------------------------------------------------
// Family A: CLF-QP with ground reaction forces of two 3D contacts.
class ClfQpFamily {
 public:
  static constexpr int kN = 12, kNeq = 2, kNineq = 21;

  explicit ClfQpFamily(unsigned seed) : rng_(seed) {
    // Strictly feasible torques/forces: |tau| <= 0.5, forces in the interior of the friction cones.
    x_feas_.resize(kN);
    for (int j = 0; j < 6; ++j) x_feas_[j] = Uniform(rng_, -0.5, 0.5);
    for (int c = 0; c < 2; ++c) {
      const double fz = Uniform(rng_, 0.35, 0.65);
      const double angle = Uniform(rng_, 0.0, 2.0 * M_PI);
      const double ft = Uniform(rng_, 0.0, 0.5) * kMu * fz;
      x_feas_.segment<3>(6 + 3 * c) << ft * std::cos(angle), ft * std::sin(angle), fz;
    }
    task_jacobian_ = RandomMatrix(rng_, 8, kN, 1.0 / std::sqrt(kN));
    task_jacobian_rate_ = RandomMatrix(rng_, 8, kN, 0.05 / std::sqrt(kN));
    A_eq0_ = RandomMatrix(rng_, kNeq, kN, 0.5);
    A_eq0_(0, 8) = 1.0;  // vertical force balance row: fz_left + fz_right + coupling to torques
    A_eq0_(0, 11) = 1.0;
    A_eq_rate_ = RandomMatrix(rng_, kNeq, kN, 0.05);
    clf_row0_ = RandomMatrix(rng_, 1, kN, 1.0);  // L_g V
    clf_row_rate_ = RandomMatrix(rng_, 1, kN, 0.1);
    coupling_row_ = RandomMatrix(rng_, 2, kN, 0.3);
    // Desired (unconstrained) torques/forces well outside the feasible set: activates limits and cone faces.
    x_des0_ = x_feas_ + RandomMatrix(rng_, kN, 1, 0.9);
    x_des_amplitude_ = RandomMatrix(rng_, kN, 1, 0.4);
    phase_ = RandomMatrix(rng_, kN, 1, 3.0);
  }

  QpProblem Sample(double t) const {
    QpProblem p;
    const double s = std::sin(2.0 * M_PI * 0.7 * t);
    const Eigen::MatrixXd Jt = task_jacobian_ + s * task_jacobian_rate_;
    p.H = Jt.transpose() * Jt;
    p.H.diagonal().array() += 0.1;  // torque / force regularization weights
    Eigen::VectorXd x_des(kN);
    for (int j = 0; j < kN; ++j) x_des[j] = x_des0_[j] + x_des_amplitude_[j] * std::sin(2.0 * M_PI * t + phase_[j]);
    p.g = -p.H * x_des;
    p.A_eq = A_eq0_ + s * A_eq_rate_;
    p.b_eq = p.A_eq * x_feas_;
    p.A.setZero(kNineq, kN);
    p.l.setConstant(kNineq, -kInf);
    p.u.setConstant(kNineq, kInf);
    // Row 0, CLF condition L_g V x <= -gamma V - L_f V (Eq. (23)); margin 0.05 at x_feas.
    p.A.row(0) = clf_row0_ + s * clf_row_rate_;
    p.u[0] = p.A.row(0).dot(x_feas_) + 0.05 + 0.02 * std::cos(2.0 * M_PI * t);
    for (int c = 0; c < 2; ++c) {
      const int f = 6 + 3 * c;
      const int r0 = 1 + 10 * c;
      // 8-face friction pyramid inscribed in the cone: cos(th) fx + sin(th) fy - mu cos(pi/8) fz <= 0.
      for (int k = 0; k < 8; ++k) {
        const double th = 2.0 * M_PI * k / 8.0;
        p.A(r0 + k, f) = std::cos(th);
        p.A(r0 + k, f + 1) = std::sin(th);
        p.A(r0 + k, f + 2) = -kMu * std::cos(M_PI / 8.0);
        p.u[r0 + k] = 0.0;
      }
      // Normal-force window (unilateral contact with a minimum normal force).
      p.A(r0 + 8, f + 2) = 1.0;
      p.l[r0 + 8] = 0.05;
      p.u[r0 + 8] = 1.5;
      // Torque / force coupling row (e.g. ankle torque vs. center of pressure), two-sided.
      p.A.row(r0 + 9) = coupling_row_.row(c);
      const double center = p.A.row(r0 + 9).dot(x_feas_);
      p.l[r0 + 9] = center - 0.3;
      p.u[r0 + 9] = center + 0.3;
    }
    // Bounds: normalized torque limits and force ranges.
    p.lb.resize(kN);
    p.ub.resize(kN);
    for (int j = 0; j < 6; ++j) {
      p.lb[j] = -1.0;
      p.ub[j] = 1.0;
    }
    for (int c = 0; c < 2; ++c) {
      p.lb.segment<3>(6 + 3 * c) << -2.0, -2.0, 0.0;
      p.ub.segment<3>(6 + 3 * c) << 2.0, 2.0, 2.0;
    }
    return p;
  }

 private:
  static constexpr double kMu = 0.7;
  mutable std::mt19937 rng_;
  Eigen::VectorXd x_feas_, x_des0_, x_des_amplitude_, phase_;
  Eigen::MatrixXd task_jacobian_, task_jacobian_rate_, A_eq0_, A_eq_rate_, clf_row0_, clf_row_rate_, coupling_row_;
};

// ---------------------------------------------------------------------------------------------------------
// Family B: task-space QP with 4 contact forces as variables.
class TaskSpaceQpFamily {
 public:
  static constexpr int kNq = 10, kNc = 4, kN = kNq + 3 * kNc, kNeq = 12, kNineq = 30;

  explicit TaskSpaceQpFamily(unsigned seed) : rng_(seed) {
    x_feas_.resize(kN);
    x_feas_.head(kNq) = RandomMatrix(rng_, kNq, 1, 0.5);
    for (int c = 0; c < kNc; ++c) {
      const double fz = Uniform(rng_, 0.15, 0.35);
      x_feas_.segment<3>(kNq + 3 * c) << Uniform(rng_, -0.3, 0.3) * kMu * fz, Uniform(rng_, -0.3, 0.3) * kMu * fz, fz;
    }
    // Floating-base rows [M_b, -J_b^T] and contact-acceleration rows [J_c, 0].
    A_eq0_.setZero(kNeq, kN);
    A_eq0_.topLeftCorner(6, kNq) = RandomMatrix(rng_, 6, kNq, 0.5);
    A_eq0_.topRightCorner(6, 3 * kNc) = RandomMatrix(rng_, 6, 3 * kNc, 0.5);
    A_eq0_.bottomLeftCorner(6, kNq) = RandomMatrix(rng_, 6, kNq, 0.5);
    A_eq_rate_.setZero(kNeq, kN);
    A_eq_rate_.leftCols(kNq) = RandomMatrix(rng_, kNeq, kNq, 0.02);
    task_jacobian_ = RandomMatrix(rng_, 8, kNq, 0.6);
    task_rate_ = RandomMatrix(rng_, 8, kNq, 0.03);
    torque_rows_ = RandomMatrix(rng_, 10, kN, 0.4);
    a_des0_ = RandomMatrix(rng_, 8, 1, 1.5);
    a_des_amplitude_ = RandomMatrix(rng_, 8, 1, 0.5);
    f_des_ = RandomMatrix(rng_, 3 * kNc, 1, 0.4);
  }

  QpProblem Sample(double t) const {
    QpProblem p;
    const double s = std::sin(2.0 * M_PI * 0.5 * t);
    const Eigen::MatrixXd Jt = task_jacobian_ + s * task_rate_;
    p.H.setZero(kN, kN);
    p.H.topLeftCorner(kNq, kNq) = Jt.transpose() * Jt;
    p.H.diagonal().head(kNq).array() += 0.05;
    p.H.diagonal().tail(3 * kNc).array() += 0.5;  // force tracking weight
    Eigen::VectorXd a_des(8);
    for (int k = 0; k < 8; ++k) a_des[k] = a_des0_[k] + a_des_amplitude_[k] * std::sin(2.0 * M_PI * t + k);
    p.g.setZero(kN);
    p.g.head(kNq) = -Jt.transpose() * a_des;
    p.g.tail(3 * kNc) = -0.5 * f_des_;
    p.A_eq = A_eq0_ + s * A_eq_rate_;
    p.b_eq = p.A_eq * x_feas_;
    p.A.setZero(kNineq, kN);
    p.l.setConstant(kNineq, -kInf);
    p.u.setConstant(kNineq, kInf);
    for (int c = 0; c < kNc; ++c) {
      const int f = kNq + 3 * c;
      const int r0 = 5 * c;
      const double faces[4][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
      for (int k = 0; k < 4; ++k) {
        p.A(r0 + k, f) = faces[k][0];
        p.A(r0 + k, f + 1) = faces[k][1];
        p.A(r0 + k, f + 2) = -kMu / std::sqrt(2.0);
        p.u[r0 + k] = 0.0;
      }
      p.A(r0 + 4, f + 2) = 1.0;
      p.l[r0 + 4] = 0.0;
      p.u[r0 + 4] = 1.0;
    }
    // Joint-torque limits tau = S (M qdd + h - J^T F) written on x, two-sided.
    for (int k = 0; k < 10; ++k) {
      p.A.row(20 + k) = torque_rows_.row(k);
      const double center = p.A.row(20 + k).dot(x_feas_);
      p.l[20 + k] = center - 0.4 - 0.05 * std::cos(2.0 * M_PI * t + k);
      p.u[20 + k] = center + 0.4;
    }
    p.lb.setConstant(kN, -kInf);
    p.ub.setConstant(kN, kInf);
    return p;
  }

 private:
  static constexpr double kMu = 0.6;
  mutable std::mt19937 rng_;
  Eigen::VectorXd x_feas_, a_des0_, a_des_amplitude_, f_des_;
  Eigen::MatrixXd A_eq0_, A_eq_rate_, task_jacobian_, task_rate_, torque_rows_;
};

// ---------------------------------------------------------------------------------------------------------
// Family C: double-integrator MPC (COM position p, velocity v, acceleration input u) over N steps.
class MpcQpFamily {
 public:
  explicit MpcQpFamily(int horizon) : N_(horizon) {}
  int n() const { return 3 * N_; }

  QpProblem Sample(double t) const {
    const int N = N_;
    const int n = 3 * N;
    const double dt = 0.05;
    const double w = 2.0 * M_PI * 0.4;
    // Current state (a smooth trajectory inside the limits) and the reference, beyond the position limit.
    const double p0 = 0.15 * std::sin(w * t);
    const double v0 = 0.15 * w * std::cos(w * t);
    const double u_prev = -0.15 * w * w * std::sin(w * t);
    const double p_ref = 1.0 + 0.1 * std::sin(3.0 * t);
    const double q_p = 10.0, q_v = 1.0, r_u = 0.1, r_du = 1.0;
    QpProblem p;
    p.H.setZero(n, n);
    p.g.setZero(n);
    auto iu = [](int k) { return 3 * k; };
    for (int k = 0; k < N; ++k) {
      p.H(iu(k), iu(k)) += r_u;
      p.H(iu(k) + 1, iu(k) + 1) += q_p;
      p.g[iu(k) + 1] -= q_p * p_ref;
      p.H(iu(k) + 2, iu(k) + 2) += q_v;
      // Input-rate penalty r_du (u_k - u_{k-1})^2: banded coupling.
      p.H(iu(k), iu(k)) += r_du;
      if (k > 0) {
        p.H(iu(k - 1), iu(k - 1)) += r_du;
        p.H(iu(k), iu(k - 1)) -= r_du;
        p.H(iu(k - 1), iu(k)) -= r_du;
      } else {
        p.g[iu(0)] -= r_du * u_prev;
      }
    }
    // Dynamics p_{k+1} = p_k + dt v_k + dt^2/2 u_k, v_{k+1} = v_k + dt u_k.
    p.A_eq.setZero(2 * N, n);
    p.b_eq.setZero(2 * N);
    for (int k = 0; k < N; ++k) {
      p.A_eq(2 * k, iu(k) + 1) = 1.0;
      p.A_eq(2 * k, iu(k)) = -0.5 * dt * dt;
      p.A_eq(2 * k + 1, iu(k) + 2) = 1.0;
      p.A_eq(2 * k + 1, iu(k)) = -dt;
      if (k > 0) {
        p.A_eq(2 * k, iu(k - 1) + 1) = -1.0;
        p.A_eq(2 * k, iu(k - 1) + 2) = -dt;
        p.A_eq(2 * k + 1, iu(k - 1) + 2) = -1.0;
      } else {
        p.b_eq[0] = p0 + dt * v0;
        p.b_eq[1] = v0;
      }
    }
    // Input-rate limits |u_k - u_{k-1}| <= du_max.
    const double du_max = 0.6;
    p.A.setZero(N, n);
    p.l.setConstant(N, -du_max);
    p.u.setConstant(N, du_max);
    for (int k = 0; k < N; ++k) {
      p.A(k, iu(k)) = 1.0;
      if (k > 0) {
        p.A(k, iu(k - 1)) = -1.0;
      } else {
        p.l[0] += u_prev;
        p.u[0] += u_prev;
      }
    }
    p.lb.resize(n);
    p.ub.resize(n);
    for (int k = 0; k < N; ++k) {
      p.lb.segment<3>(iu(k)) << -2.0, -0.8, -0.5;
      p.ub.segment<3>(iu(k)) << 2.0, 0.8, 0.5;
    }
    return p;
  }

 private:
  int N_;
};

// ---------------------------------------------------------------------------------------------------------
// Family D: condensed MPC of a double integrator (position p, velocity v, acceleration input a), N steps of
// dt = 0.05 s. The states are eliminated, z_k = Phi_k z_0 + Gamma_k a (z_k = [p_k, v_k], k = 1..N):
//   minimize  sum_k q_p (p_k - p_ref)^2 + q_v v_k^2 + r a_k^2      (written 1/2 a^T H a + g^T a, H dense)
//   s.t.      -p_max <= p_k <= p_max, -v_max <= v_k <= v_max    (2N two-sided rows of the fixed matrix A)
//             -a_max <= a_k <= a_max                              (bounds)
// Only g and the row bounds l, u depend on the initial state z_0 and the reference p_ref. The sequence is a
// closed loop: every tick (10 ms) the plant applies the first input of the (cold) MPC solution, plus a smooth
// disturbance; p_ref is a square wave of +-1.2 m (beyond p_max = 1 m, so the position rows become active) with
// period 2 s. Problems are generated once and stored (Problem(k)).
class CondensedMpcSequence {
 public:
  CondensedMpcSequence(int horizon, int length) : N_(horizon) {
    const int N = horizon;
    // Prediction matrices.
    Phi_.setZero(2 * N, 2);
    Gamma_.setZero(2 * N, N);
    for (int k = 0; k < N; ++k) {
      const double t = (k + 1) * kDt;
      Phi_.row(2 * k) << 1.0, t;
      Phi_.row(2 * k + 1) << 0.0, 1.0;
      for (int j = 0; j <= k; ++j) {
        const double steps = k - j;  // a_j acts from interval j to k
        Gamma_(2 * k, j) = kDt * kDt * (steps + 0.5);
        Gamma_(2 * k + 1, j) = kDt;
      }
    }
    Eigen::VectorXd q(2 * N);
    for (int k = 0; k < N; ++k) q.segment<2>(2 * k) << kQp, kQv;
    H_ = Gamma_.transpose() * q.asDiagonal() * Gamma_;
    H_.diagonal().array() += kR;
    H_ = 0.5 * (H_ + H_.transpose()).eval();
    H_ *= 2.0;  // 1/2 a^T H a convention
    qv_ = 2.0 * q;
    // Closed loop.
    DenseQpSolver solver(N, 0, 2 * N);
    solver.settings().warm_start = false;
    Eigen::Vector2d z(0.0, 0.0);
    problems_.reserve(length);
    for (int tick = 0; tick < length; ++tick) {
      const double t = kTick * tick;
      const double p_ref = std::fmod(t, 2.0) < 1.0 ? 1.2 : -1.2;
      problems_.push_back(Build(z, p_ref));
      LoadInto(problems_.back(), &solver);
      const double a = solver.Solve() == QpStatus::kOptimal ? solver.x()[0] : 0.0;
      const double w = a + 0.3 * std::sin(2.3 * t) + 0.2 * std::sin(7.1 * t);  // disturbance (m/s^2)
      z = Eigen::Vector2d(z[0] + kTick * z[1] + 0.5 * kTick * kTick * w, z[1] + kTick * w);
    }
  }

  int size() const { return static_cast<int>(problems_.size()); }
  const QpProblem& Problem(int k) const { return problems_[k]; }

 private:
  static constexpr double kDt = 0.05, kTick = 0.01, kQp = 10.0, kQv = 1.0, kR = 0.1;
  static constexpr double kPMax = 1.0, kVMax = 0.8, kAMax = 2.0;

  QpProblem Build(const Eigen::Vector2d& z0, double p_ref) const {
    const int N = N_;
    QpProblem p;
    p.H = H_;
    const Eigen::VectorXd free = Phi_ * z0;  // states with a = 0
    Eigen::VectorXd err = free;
    for (int k = 0; k < N; ++k) err[2 * k] -= p_ref;
    p.g = Gamma_.transpose() * qv_.cwiseProduct(err);
    p.A_eq.setZero(0, N);
    p.b_eq.setZero(0);
    p.A = Gamma_;
    p.l.resize(2 * N);
    p.u.resize(2 * N);
    for (int k = 0; k < N; ++k) {
      p.l[2 * k] = -kPMax - free[2 * k];
      p.u[2 * k] = kPMax - free[2 * k];
      p.l[2 * k + 1] = -kVMax - free[2 * k + 1];
      p.u[2 * k + 1] = kVMax - free[2 * k + 1];
    }
    p.lb.setConstant(N, -kAMax);
    p.ub.setConstant(N, kAMax);
    return p;
  }

  int N_;
  Eigen::MatrixXd Phi_, Gamma_, H_;
  Eigen::VectorXd qv_;
  std::vector<QpProblem> problems_;
};

}  // namespace rome::qp_test
