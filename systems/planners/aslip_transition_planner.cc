#include "systems/planners/aslip_transition_planner.h"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace rome {
namespace {

constexpr int kNx = 8, kNu = 4;

// Rows of one leg on the ground: F/(m g) ≥ 0, (μ G_z ∓ G_x)/(m g) ≥ 0, s ∈ [s_min, s_max], Eq. (10)
// (L_t G_z − u)/(m g L_t) ≥ 0 and (u + L_h G_z)/(m g L_h) ≥ 0.
void LegRows(const AslipParams& p, double mu, const VectorXad& x, const VectorXad& u, int leg, double foot_x,
             VectorXad& y, int row) {
  const AslipLeg<AutoDiffXd> g = AslipLegState<AutoDiffXd>(p, x, leg, foot_x, u(2 + leg));
  const double weight = p.mass * p.gravity;
  y(row) = g.force / weight;
  y(row + 1) = (mu * g.grf_z - g.grf_x) / weight;
  y(row + 2) = (mu * g.grf_z + g.grf_x) / weight;
  y(row + 3) = g.spring;
  y(row + 4) = (p.toe_length * g.grf_z - u(2 + leg)) / (weight * p.toe_length);
  y(row + 5) = (u(2 + leg) + p.heel_length * g.grf_z) / (weight * p.heel_length);
}

}  // namespace

AslipTransitionPlanner::AslipTransitionPlanner(AslipTransitionParams params) : params_(std::move(params)) {
  AslipPeriodicGaitPlanner check(params_.bounds);  // validates the shared parameters
  auto require = [](bool ok, const char* what, double v) {
    if (ok) return;
    std::ostringstream msg;
    msg << "AslipTransitionPlanner: parameter " << what << ", got " << v;
    throw std::invalid_argument(msg.str());
  };
  require(params_.min_dsp_duration > 0 && params_.min_dsp_duration <= params_.max_dsp_duration,
          "min_dsp_duration must be in (0, max_dsp_duration] s", params_.min_dsp_duration);
  require(params_.min_ssp_duration > 0 && params_.min_ssp_duration <= params_.max_ssp_duration,
          "min_ssp_duration must be in (0, max_ssp_duration] s", params_.min_ssp_duration);
  require(params_.max_ankle_torque > 0, "max_ankle_torque must be > 0 N m", params_.max_ankle_torque);
  require(params_.torque_cost_scale > 0, "torque_cost_scale must be > 0 N m", params_.torque_cost_scale);
}

AslipContact AslipTransitionPlanner::PhaseContact(const AslipTransitionData& data, int phase) {
  AslipContact c;
  c.left_foot_x = data.left_foot_x;
  c.right_foot_x = data.right_foot_x;
  c.left = phase == 0 || data.lifting_leg != 0;
  c.right = phase == 0 || data.lifting_leg != 1;
  return c;
}

Eigen::Matrix<double, 8, 1> AslipTransitionPlanner::StandingState(const AslipParams& params, double z) {
  const double L = AslipRestLengthForForce(params, z, 0.5 * params.mass * params.gravity);
  Eigen::Matrix<double, 8, 1> x;
  x << 0, z, 0, 0, L, L, 0, 0;
  return x;
}

DirectCollocation AslipTransitionPlanner::BuildProblem(const AslipTransitionData& data) const {
  if (data.lifting_leg != 0 && data.lifting_leg != 1) {
    throw std::invalid_argument("AslipTransitionPlanner: lifting_leg must be 0 (left) or 1 (right), got " +
                                std::to_string(data.lifting_leg));
  }
  if (!data.initial_state.allFinite() || !data.final_state.allFinite()) {
    throw std::invalid_argument("AslipTransitionPlanner: initial_state and final_state must be finite");
  }
  const AslipPeriodicGaitParams& q = params_.bounds;
  const AslipParams p = q.aslip;
  const double v = q.max_speed, umax = params_.max_ankle_torque, us = params_.torque_cost_scale;
  Eigen::VectorXd xl(kNx), xu(kNx);
  const double xmin = std::min(data.initial_state(0), data.final_state(0)) - 1.0;
  const double xmax = std::max(data.initial_state(0), data.final_state(0)) + 1.0;
  xl << xmin, q.height_min, -v, -v, q.leg_length_min, q.leg_length_min, -v, -v;
  xu << xmax, q.height_max, v, v, q.leg_length_max, q.leg_length_max, v, v;
  std::vector<CollocationPhase> phases(2);
  for (int ph = 0; ph < 2; ++ph) {
    CollocationPhase& c = phases[ph];
    c.name = ph == 0 ? "dsp" : "ssp";
    c.num_states = kNx;
    c.num_inputs = kNu;
    c.num_nodes = q.nodes_per_domain;
    c.min_duration = ph == 0 ? params_.min_dsp_duration : params_.min_ssp_duration;
    c.max_duration = ph == 0 ? params_.max_dsp_duration : params_.max_ssp_duration;
    const AslipContact contact = PhaseContact(data, ph);
    c.dynamics = [p, contact](const VectorXad& x, const VectorXad& u, VectorXad& y) {
      y = AslipDynamics<AutoDiffXd>(p, contact, x, u);
    };
    c.state_lower = xl;
    c.state_upper = xu;
    c.input_lower.resize(kNu);
    c.input_upper.resize(kNu);
    c.input_lower << -q.max_leg_length_acceleration, -q.max_leg_length_acceleration, -umax, -umax;
    c.input_upper << q.max_leg_length_acceleration, q.max_leg_length_acceleration, umax, umax;
    if (ph == 1) {  // no torque at a foot in the air
      c.input_lower(2 + data.lifting_leg) = 0.0;
      c.input_upper(2 + data.lifting_leg) = 0.0;
    }
    c.running_cost = [us](const VectorXad&, const VectorXad& u) {  // Eq. (9)
      return AutoDiffXd(u(0) * u(0) + u(1) * u(1) + (u(2) / us) * (u(2) / us) + (u(3) / us) * (u(3) / us));
    };
  }
  DirectCollocation problem("aslip_transition", std::move(phases));
  problem.SetExactHessian(q.exact_hessian);
  const double mu = q.friction_coefficient, inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd lo1(6), hi1(6);
  lo1 << 0, 0, 0, q.spring_min, 0, 0;
  hi1 << inf, inf, inf, q.spring_max, inf, inf;
  const AslipContact dsp = PhaseContact(data, 0);
  Eigen::VectorXd lo2(12), hi2(12);
  lo2 << lo1, lo1;
  hi2 << hi1, hi1;
  problem.AddPathConstraint(
      0, 12,
      [p, mu, dsp](const VectorXad& x, const VectorXad& u, VectorXad& y) {
        y.resize(12);
        LegRows(p, mu, x, u, 0, dsp.left_foot_x, y, 0);
        LegRows(p, mu, x, u, 1, dsp.right_foot_x, y, 6);
      },
      lo2, hi2, "legs_force_friction_spring_zmp");
  const int stance = 1 - data.lifting_leg;
  const double stance_x = dsp.foot_x(stance);
  problem.AddPathConstraint(
      1, 6,
      [p, mu, stance, stance_x](const VectorXad& x, const VectorXad& u, VectorXad& y) {
        y.resize(6);
        LegRows(p, mu, x, u, stance, stance_x, y, 0);
      },
      lo1, hi1, "stance_leg_force_friction_spring_zmp");
  const int lift = data.lifting_leg;
  const double lift_x = dsp.foot_x(lift);
  problem.AddNodeConstraint(
      0, -1, 1,
      [p, lift, lift_x](const VectorXad& x, const VectorXad& u, VectorXad& y) {
        y.resize(1);
        y(0) = AslipLegState<AutoDiffXd>(p, x, lift, lift_x, u(2 + lift)).grf_z / (p.mass * p.gravity);
      },
      Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), "liftoff");
  if (params_.zero_final_ankle_torque) {
    problem.AddNodeConstraint(
        1, -1, 1,
        [stance](const VectorXad&, const VectorXad& u, VectorXad& y) {
          y.resize(1);
          y(0) = u(2 + stance) / 100.0;
        },
        Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), "final_ankle_torque");
  }
  problem.SetNodeStateBounds(0, 0, data.initial_state, data.initial_state);
  problem.SetNodeStateBounds(1, -1, data.final_state, data.final_state);
  // Initial guess: straight line in state space, mid-range durations.
  const int N = q.nodes_per_domain;
  const bool guessed = data.dsp_state_guess.size() > 0 || data.ssp_state_guess.size() > 0;
  if (guessed) {
    if (data.dsp_state_guess.rows() != kNx || data.dsp_state_guess.cols() != N || data.ssp_state_guess.rows() != kNx ||
        data.ssp_state_guess.cols() != N || !(data.dsp_duration_guess > 0) || !(data.ssp_duration_guess > 0)) {
      std::ostringstream msg;
      msg << "AslipTransitionPlanner: the state guesses must be 8 x " << N << " each with durations > 0, got "
          << data.dsp_state_guess.rows() << "x" << data.dsp_state_guess.cols() << " and "
          << data.ssp_state_guess.rows() << "x" << data.ssp_state_guess.cols() << ", " << data.dsp_duration_guess
          << " and " << data.ssp_duration_guess << " s";
      throw std::invalid_argument(msg.str());
    }
    problem.SetInitialGuess(0, data.dsp_state_guess, Eigen::MatrixXd::Zero(kNu, N), data.dsp_duration_guess);
    problem.SetInitialGuess(1, data.ssp_state_guess, Eigen::MatrixXd::Zero(kNu, N), data.ssp_duration_guess);
    return problem;
  }
  const double Td = 0.5 * (params_.min_dsp_duration + params_.max_dsp_duration);
  const double Ts = 0.5 * (params_.min_ssp_duration + params_.max_ssp_duration);
  for (int ph = 0; ph < 2; ++ph) {
    Eigen::MatrixXd X(kNx, N);
    for (int k = 0; k < N; ++k) {
      const double t = (ph == 0 ? Td * k / (N - 1) : Td + Ts * k / (N - 1)) / (Td + Ts);
      X.col(k) = (1 - t) * data.initial_state + t * data.final_state;
      X(2, k) = (data.final_state(0) - data.initial_state(0)) / (Td + Ts);
    }
    problem.SetInitialGuess(ph, X, Eigen::MatrixXd::Zero(kNu, N), ph == 0 ? Td : Ts);
  }
  return problem;
}

PlanCacheKey AslipTransitionPlanner::CacheKey(const AslipTransitionData& data) const {
  PlanCacheKey key("aslip_transition");
  AddToCacheKey(params_.bounds, &key);
  key.Add("T_DSP_min", params_.min_dsp_duration).Add("T_DSP_max", params_.max_dsp_duration);
  key.Add("T_SSP_min", params_.min_ssp_duration).Add("T_SSP_max", params_.max_ssp_duration);
  key.Add("u_max", params_.max_ankle_torque).Add("u_scale", params_.torque_cost_scale);
  key.Add("zero_final_u", params_.zero_final_ankle_torque);
  key.Add("x0", Eigen::MatrixXd(data.initial_state)).Add("xf", Eigen::MatrixXd(data.final_state));
  key.Add("foot_L", data.left_foot_x).Add("foot_R", data.right_foot_x).Add("lift", data.lifting_leg);
  key.Add("guess_dsp", data.dsp_state_guess).Add("guess_ssp", data.ssp_state_guess);
  key.Add("guess_T_DSP", data.dsp_duration_guess).Add("guess_T_SSP", data.ssp_duration_guess);
  return key;
}

AslipTransition AslipTransitionPlanner::Solve(const AslipTransitionData& data, const PlanCache* cache) const {
  const DirectCollocation problem = BuildProblem(data);
  const AslipPeriodicGaitParams& q = params_.bounds;
  IpoptSolverOptions options;
  options.tolerance = q.tolerance;
  options.constraint_violation_tolerance = q.constraint_tolerance;
  options.max_iterations = q.max_iterations;
  options.limited_memory_history = q.limited_memory_history;
  options.mu_strategy = q.mu_strategy;
  AslipTransition out;
  const PlanCacheKey key = CacheKey(data);
  std::optional<CollocationResult> hit;
  if (cache != nullptr) hit = LoadCachedCollocation(problem, *cache, key);
  out.collocation = hit ? std::move(*hit) : problem.Solve(options);
  if (cache != nullptr && !hit && out.success()) cache->Store(key, out.collocation.nlp.x);
  std::unique_ptr<NlpProblem> nlp = problem.BuildNlp();
  out.max_constraint_violation = MaxConstraintViolation(*nlp, out.collocation.nlp.x);
  double integral = 0.0, total = 0.0;
  for (const auto& s : out.collocation.phases) {
    const int n = static_cast<int>(s.times.size());
    const double h = s.duration / (n - 1);
    for (int k = 0; k + 1 < n; ++k) integral += 0.5 * h * (s.states(1, k) + s.states(1, k + 1));
    total += s.duration;
  }
  out.mean_height = integral / total;
  return out;
}

Eigen::MatrixXd AslipTransition::GroundReactions(const AslipParams& params, const AslipTransitionData& data,
                                                 int phase) const {
  const CollocationPhaseSolution& s = collocation.phases.at(phase);
  const AslipContact c = AslipTransitionPlanner::PhaseContact(data, phase);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(4, s.states.cols());
  for (Eigen::Index k = 0; k < s.states.cols(); ++k) {
    const Eigen::VectorXd x = s.states.col(k);
    for (int leg = 0; leg < 2; ++leg) {
      if (!c.in_contact(leg)) continue;
      const AslipLeg<double> g = AslipLegState<double>(params, x, leg, c.foot_x(leg), s.inputs(2 + leg, k));
      G(2 * leg, k) = g.grf_x;
      G(2 * leg + 1, k) = g.grf_z;
    }
  }
  return G;
}

}  // namespace rome
