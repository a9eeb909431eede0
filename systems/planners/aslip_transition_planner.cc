#include "systems/planners/aslip_transition_planner.h"

#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <utility>
#include <vector>
#include <sstream>
#include <stdexcept>

namespace rome {
namespace {

// A failure the same problem, guess and options give again (Ipopt is deterministic): not a time limit or an error.
bool RepeatableFailure(int status) {
  const NlpStatus s = static_cast<NlpStatus>(status);
  return s == NlpStatus::kInfeasible || s == NlpStatus::kMaxIterations || s == NlpStatus::kDivergingIterates ||
         s == NlpStatus::kRestorationFailed || s == NlpStatus::kSearchDirectionTooSmall;
}

constexpr int kNx8 = 8, kNu4 = 4;

// Rows of one leg on the ground: F/(m g) ≥ 0, (μ G_z ∓ G_x)/(m g) ≥ 0, s ∈ [s_min, s_max], Eq. (10)
// (L_t G_z − u)/(m g L_t) ≥ 0 and (u + L_h G_z)/(m g L_h) ≥ 0.
void LegRows(const ActuatedSpringLoadedInvertedPendulumParams& p, double mu, const NodeVector& x, const NodeVector& u,
             int leg, double foot_x, NodeVector& y, int row) {
  const ActuatedSpringLoadedInvertedPendulumLeg<NodeScalar> g =
      AslipLegState<NodeScalar>(p, x, leg, foot_x, u(2 + leg));
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
  require(params_.min_dsp_stance_force_fraction >= 0 && params_.min_dsp_stance_force_fraction < 1,
          "min_dsp_stance_force_fraction must be in [0, 1)", params_.min_dsp_stance_force_fraction);
  require(params_.max_vertical_force_fraction == 0 || params_.max_vertical_force_fraction > 1,
          "max_vertical_force_fraction must be 0 (no bound) or > 1", params_.max_vertical_force_fraction);
  require(params_.max_ankle_torque > 0, "max_ankle_torque must be > 0 N m", params_.max_ankle_torque);
  require(params_.torque_cost_scale > 0, "torque_cost_scale must be > 0 N m", params_.torque_cost_scale);
}

ActuatedSpringLoadedInvertedPendulumContact AslipTransitionPlanner::PhaseContact(const AslipTransitionData& data,
                                                                                 int phase) {
  ActuatedSpringLoadedInvertedPendulumContact c;
  c.left_foot_x = data.left_foot_x;
  c.right_foot_x = data.right_foot_x;
  c.left = phase == 0 || data.lifting_leg != 0;
  c.right = phase == 0 || data.lifting_leg != 1;
  return c;
}

Eigen::Matrix<double, 8, 1> AslipTransitionPlanner::StandingState(
    const ActuatedSpringLoadedInvertedPendulumParams& params, double z) {
  return StandingState(params, z, 0.0, 0.0);
}

Eigen::Matrix<double, 8, 1> AslipTransitionPlanner::StandingState(
    const ActuatedSpringLoadedInvertedPendulumParams& params, double z, double left_foot_x, double right_foot_x) {
  const double half = 0.5 * std::abs(left_foot_x - right_foot_x), r = std::hypot(half, z);
  // Leg force F along the leg with vertical component F z / r = m g / 2.
  const double L = AslipRestLengthForForce(params, r, 0.5 * params.mass * params.gravity * r / z);
  Eigen::Matrix<double, 8, 1> x;
  x << 0.5 * (left_foot_x + right_foot_x), z, 0, 0, L, L, 0, 0;
  return x;
}

namespace {

// The DSP and SSP phases of Eq. (9): state bounds (with the lateral rows [y, ẏ] when params.lateral), the footed
// aSLIP dynamics (and the lateral footed H-LIP rows on the aSLIP's forces), input bounds and the torque cost.
std::vector<CollocationPhase> TransitionPhases(const AslipTransitionParams& params, const AslipTransitionData& data) {
  const AslipPeriodicGaitParams& q = params.bounds;
  const ActuatedSpringLoadedInvertedPendulumParams p = q.aslip;
  const double v = q.max_speed, umax = params.max_ankle_torque, us = params.torque_cost_scale;
  const bool lat = params.lateral;
  const int kNx = lat ? 10 : kNx8, kNu = lat ? 6 : kNu4;
  Eigen::VectorXd xl(kNx), xu(kNx);
  const double xmin = std::min(data.initial_state(0), data.final_state(0)) - 1.0;
  const double xmax = std::max(data.initial_state(0), data.final_state(0)) + 1.0;
  xl.head(8) << xmin, q.height_min, -v, -v, q.leg_length_min, q.leg_length_min, -v, -v;
  xu.head(8) << xmax, q.height_max, v, v, q.leg_length_max, q.leg_length_max, v, v;
  if (lat) {
    xl.tail(2) << std::min(data.left_foot_y, data.right_foot_y) - 1.0, -v;
    xu.tail(2) << std::max(data.left_foot_y, data.right_foot_y) + 1.0, v;
  }
  const double foot_y[2] = {data.left_foot_y, data.right_foot_y};
  std::vector<CollocationPhase> phases(2);
  for (int ph = 0; ph < 2; ++ph) {
    CollocationPhase& c = phases[ph];
    c.name = ph == 0 ? "dsp" : "ssp";
    c.num_states = kNx;
    c.num_inputs = kNu;
    c.num_nodes = q.nodes_per_domain;
    c.min_duration = ph == 0 ? params.min_dsp_duration : params.min_ssp_duration;
    c.max_duration = ph == 0 ? params.max_dsp_duration : params.max_ssp_duration;
    const ActuatedSpringLoadedInvertedPendulumContact contact = AslipTransitionPlanner::PhaseContact(data, ph);
    c.dynamics = [p, contact, lat, foot_y](const NodeVector& x, const NodeVector& u, NodeVector& y) {
      if (!lat) {
        y = AslipDynamics<NodeScalar>(p, contact, x, u);
        return;
      }
      y.resize(10);
      y.head(8) = AslipDynamics<NodeScalar>(p, contact, NodeVector(x.head(8)), NodeVector(u.head(4)));
      NodeScalar fy = 0.0 * x(8);
      for (int leg = 0; leg < 2; ++leg) {
        if (!contact.in_contact(leg)) continue;
        const ActuatedSpringLoadedInvertedPendulumLeg<NodeScalar> g =
            AslipLegState<NodeScalar>(p, x, leg, contact.foot_x(leg), u(2 + leg));
        fy += g.grf_z * (x(8) - foot_y[leg]) + u(4 + leg);
      }
      y(8) = x(9);
      y(9) = fy / (p.mass * x(1));
    };
    c.state_lower = xl;
    c.state_upper = xu;
    c.input_lower.resize(kNu);
    c.input_upper.resize(kNu);
    c.input_lower.head(4) << -q.max_leg_length_acceleration, -q.max_leg_length_acceleration, -umax, -umax;
    c.input_upper.head(4) << q.max_leg_length_acceleration, q.max_leg_length_acceleration, umax, umax;
    if (lat) {
      c.input_lower.tail(2).setConstant(-params.max_ankle_roll_torque);
      c.input_upper.tail(2).setConstant(params.max_ankle_roll_torque);
    }
    if (ph == 1) {  // no torque at a foot in the air
      c.input_lower(2 + data.lifting_leg) = 0.0;
      c.input_upper(2 + data.lifting_leg) = 0.0;
      if (lat) c.input_lower(4 + data.lifting_leg) = c.input_upper(4 + data.lifting_leg) = 0.0;
      if (params.max_ssp_ankle_torque >= 0) {
        const double ssp_max = std::min(umax, params.max_ssp_ankle_torque);
        c.input_lower(3 - data.lifting_leg) = -ssp_max;
        c.input_upper(3 - data.lifting_leg) = ssp_max;
      }
    }
    c.running_cost = [us, lat](const NodeVector&, const NodeVector& u) {  // Eq. (9)
      NodeScalar cost = u(0) * u(0) + u(1) * u(1) + (u(2) / us) * (u(2) / us) + (u(3) / us) * (u(3) / us);
      if (lat) cost += (u(4) / us) * (u(4) / us) + (u(5) / us) * (u(5) / us);  // Eq. (15)'s torques, same scale
      return cost;
    };
  }
  return phases;
}

// Per-leg path rows of Eq. (10) (force, friction, spring, sagittal ZMP), the DSP stance load floor, the vertical force
// bound and, with the lateral rows, Eq. (14)'s lateral ZMP.
void AddContactConstraints(DirectCollocation& problem, const AslipTransitionParams& params,
                           const AslipTransitionData& data) {
  const AslipPeriodicGaitParams& q = params.bounds;
  const ActuatedSpringLoadedInvertedPendulumParams p = q.aslip;
  const double mu = q.friction_coefficient, inf = std::numeric_limits<double>::infinity();
  Eigen::VectorXd lo1(6), hi1(6);
  lo1 << 0, 0, 0, q.spring_min, 0, 0;
  hi1 << inf, inf, inf, q.spring_max, inf, inf;
  const ActuatedSpringLoadedInvertedPendulumContact dsp = AslipTransitionPlanner::PhaseContact(data, 0);
  Eigen::VectorXd lo2(12), hi2(12);
  lo2 << lo1, lo1;
  hi2 << hi1, hi1;
  problem.AddPathConstraint(
      0, 12,
      [p, mu, dsp](const NodeVector& x, const NodeVector& u, NodeVector& y) {
        y.resize(12);
        LegRows(p, mu, x, u, 0, dsp.left_foot_x, y, 0);
        LegRows(p, mu, x, u, 1, dsp.right_foot_x, y, 6);
      },
      lo2, hi2, "legs_force_friction_spring_zmp");
  const int stance = 1 - data.lifting_leg;
  const double stance_x = dsp.foot_x(stance);
  if (params.min_dsp_stance_force_fraction > 0) {
    problem.AddPathConstraint(
        0, 1,
        [p, stance, stance_x](const NodeVector& x, const NodeVector& u, NodeVector& y) {
          y.resize(1);
          y(0) = AslipLegState<NodeScalar>(p, x, stance, stance_x, u(2 + stance)).grf_z / (p.mass * p.gravity);
        },
        Eigen::VectorXd::Constant(1, params.min_dsp_stance_force_fraction), Eigen::VectorXd::Constant(1, inf),
        "dsp_stance_leg_min_force");
  }
  if (params.max_vertical_force_fraction > 0) {
    for (int ph = 0; ph < 2; ++ph) {
      const ActuatedSpringLoadedInvertedPendulumContact contact = AslipTransitionPlanner::PhaseContact(data, ph);
      problem.AddPathConstraint(
          ph, 2,
          [p, contact](const NodeVector& x, const NodeVector& u, NodeVector& y) {
            y.resize(2);
            for (int leg = 0; leg < 2; ++leg)
              y(leg) = contact.in_contact(leg)
                           ? AslipLegState<NodeScalar>(p, x, leg, contact.foot_x(leg), u(2 + leg)).grf_z /
                                 (p.mass * p.gravity)
                           : NodeScalar(0.0 * x(0));
          },
          Eigen::VectorXd::Constant(2, -inf), Eigen::VectorXd::Constant(2, params.max_vertical_force_fraction),
          ph == 0 ? "dsp_leg_max_force" : "ssp_leg_max_force");
    }
  }
  problem.AddPathConstraint(
      1, 6,
      [p, mu, stance, stance_x](const NodeVector& x, const NodeVector& u, NodeVector& y) {
        y.resize(6);
        LegRows(p, mu, x, u, stance, stance_x, y, 0);
      },
      lo1, hi1, "stance_leg_force_friction_spring_zmp");
  if (params.lateral) {  // Eq. (14): −W1 G_z ≤ u_x ≤ W2 G_z per leg on the ground, rows scaled by m g
    const double W1 = params.foot_width_left_of_ankle, W2 = params.foot_width_right_of_ankle;
    for (int ph = 0; ph < 2; ++ph) {
      const ActuatedSpringLoadedInvertedPendulumContact contact = AslipTransitionPlanner::PhaseContact(data, ph);
      problem.AddPathConstraint(
          ph, 4,
          [p, contact, W1, W2](const NodeVector& x, const NodeVector& u, NodeVector& y) {
            y.resize(4);
            for (int leg = 0; leg < 2; ++leg) {
              const NodeScalar gz = contact.in_contact(leg)
                                        ? AslipLegState<NodeScalar>(p, x, leg, contact.foot_x(leg), u(2 + leg)).grf_z
                                        : NodeScalar(0.0 * x(0));
              y(2 * leg) = (u(4 + leg) + W1 * gz) / (p.mass * p.gravity * W1);
              y(2 * leg + 1) = (W2 * gz - u(4 + leg)) / (p.mass * p.gravity * W2);
            }
          },
          Eigen::VectorXd::Zero(4), Eigen::VectorXd::Constant(4, inf), ph == 0 ? "lateral_zmp_dsp" : "lateral_zmp_ssp");
    }
  }
}

// The boundary states [aSLIP state; y, ẏ with the lateral rows]: initial and final.
std::pair<Eigen::VectorXd, Eigen::VectorXd> BoundaryStates(const AslipTransitionParams& params,
                                                           const AslipTransitionData& data) {
  const int nx = params.lateral ? 10 : kNx8;
  Eigen::VectorXd x0(nx), xf(nx);
  x0.head(8) = data.initial_state;
  xf.head(8) = data.final_state;
  if (params.lateral) {
    x0.tail(2) = data.initial_lateral_state;
    xf.tail(2) = data.final_lateral_state;
  }
  return {x0, xf};
}

// The lift-off (the lifting leg unloaded at the DSP's end), the optional zero final ankle torque, and the boundary
// states (initial and final, lateral rows included).
void AddEventConstraints(DirectCollocation& problem, const AslipTransitionParams& params,
                         const AslipTransitionData& data) {
  const ActuatedSpringLoadedInvertedPendulumParams p = params.bounds.aslip;
  const ActuatedSpringLoadedInvertedPendulumContact dsp = AslipTransitionPlanner::PhaseContact(data, 0);
  const int stance = 1 - data.lifting_leg;
  const int lift = data.lifting_leg;
  const double lift_x = dsp.foot_x(lift);
  problem.AddNodeConstraint(
      0, -1, 1,
      [p, lift, lift_x](const NodeVector& x, const NodeVector& u, NodeVector& y) {
        y.resize(1);
        y(0) = AslipLegState<NodeScalar>(p, x, lift, lift_x, u(2 + lift)).grf_z / (p.mass * p.gravity);
      },
      Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), "liftoff");
  if (params.zero_final_ankle_torque) {
    problem.AddNodeConstraint(
        1, -1, 1,
        [stance](const NodeVector&, const NodeVector& u, NodeVector& y) {
          y.resize(1);
          y(0) = u(2 + stance) / 100.0;
        },
        Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), "final_ankle_torque");
  }
  const auto [x0, xf] = BoundaryStates(params, data);
  problem.SetNodeStateBounds(0, 0, x0, x0);
  problem.SetNodeStateBounds(1, -1, xf, xf);
}

// Initial guess: data's guesses if given (checked), else a straight line in state space at mid-range durations.
void SetTransitionGuess(DirectCollocation& problem, const AslipTransitionParams& params,
                        const AslipTransitionData& data) {
  const AslipPeriodicGaitParams& q = params.bounds;
  const bool lat = params.lateral;
  const int kNx = lat ? 10 : kNx8, kNu = lat ? 6 : kNu4;
  const auto [x0, xf] = BoundaryStates(params, data);
  const int N = q.nodes_per_domain;
  const bool guessed = data.dsp_state_guess.size() > 0 || data.ssp_state_guess.size() > 0;
  if (guessed) {
    if (data.dsp_state_guess.rows() != kNx || data.dsp_state_guess.cols() != N || data.ssp_state_guess.rows() != kNx ||
        data.ssp_state_guess.cols() != N || !(data.dsp_duration_guess > 0) || !(data.ssp_duration_guess > 0)) {
      std::ostringstream msg;
      msg << "AslipTransitionPlanner: the state guesses must be " << kNx << " x " << N
          << " each with durations > 0, got " << data.dsp_state_guess.rows() << "x" << data.dsp_state_guess.cols()
          << " and " << data.ssp_state_guess.rows() << "x" << data.ssp_state_guess.cols() << ", "
          << data.dsp_duration_guess << " and " << data.ssp_duration_guess << " s";
      throw std::invalid_argument(msg.str());
    }
    problem.SetInitialGuess(0, data.dsp_state_guess, Eigen::MatrixXd::Zero(kNu, N), data.dsp_duration_guess);
    problem.SetInitialGuess(1, data.ssp_state_guess, Eigen::MatrixXd::Zero(kNu, N), data.ssp_duration_guess);
    return;
  }
  const double Td = 0.5 * (params.min_dsp_duration + params.max_dsp_duration);
  const double Ts = 0.5 * (params.min_ssp_duration + params.max_ssp_duration);
  for (int ph = 0; ph < 2; ++ph) {
    Eigen::MatrixXd X(kNx, N);
    for (int k = 0; k < N; ++k) {
      const double t = (ph == 0 ? Td * k / (N - 1) : Td + Ts * k / (N - 1)) / (Td + Ts);
      X.col(k) = (1 - t) * x0 + t * xf;
      X(2, k) = (data.final_state(0) - data.initial_state(0)) / (Td + Ts);
    }
    problem.SetInitialGuess(ph, X, Eigen::MatrixXd::Zero(kNu, N), ph == 0 ? Td : Ts);
  }
}

}  // namespace

DirectCollocation AslipTransitionPlanner::BuildProblem(const AslipTransitionData& data) const {
  if (data.lifting_leg != 0 && data.lifting_leg != 1) {
    throw std::invalid_argument("AslipTransitionPlanner: lifting_leg must be 0 (left) or 1 (right), got " +
                                std::to_string(data.lifting_leg));
  }
  if (!data.initial_state.allFinite() || !data.final_state.allFinite()) {
    throw std::invalid_argument("AslipTransitionPlanner: initial_state and final_state must be finite");
  }
  DirectCollocation problem("aslip_transition", TransitionPhases(params_, data));
  problem.SetExactHessian(params_.bounds.exact_hessian);
  AddContactConstraints(problem, params_, data);
  AddEventConstraints(problem, params_, data);
  SetTransitionGuess(problem, params_, data);
  return problem;
}

PlanCacheKey AslipTransitionPlanner::CacheKey(const AslipTransitionData& data) const {
  PlanCacheKey key("aslip_transition");
  AddToCacheKey(params_.bounds, &key);
  key.Add("T_DSP_min", params_.min_dsp_duration).Add("T_DSP_max", params_.max_dsp_duration);
  key.Add("T_SSP_min", params_.min_ssp_duration).Add("T_SSP_max", params_.max_ssp_duration);
  key.Add("u_max", params_.max_ankle_torque).Add("u_scale", params_.torque_cost_scale);
  key.Add("zero_final_u", params_.zero_final_ankle_torque).Add("u_max_ssp", params_.max_ssp_ankle_torque);
  key.Add("min_dsp_stance_force", params_.min_dsp_stance_force_fraction);
  if (params_.max_vertical_force_fraction > 0) key.Add("max_vertical_force", params_.max_vertical_force_fraction);
  key.Add("x0", Eigen::MatrixXd(data.initial_state)).Add("xf", Eigen::MatrixXd(data.final_state));
  key.Add("foot_L", data.left_foot_x).Add("foot_R", data.right_foot_x).Add("lift", data.lifting_leg);
  if (params_.lateral) {
    key.Add("lateral", true).Add("W1", params_.foot_width_left_of_ankle).Add("W2", params_.foot_width_right_of_ankle);
    key.Add("u_x_max", params_.max_ankle_roll_torque)
        .Add("foot_L_y", data.left_foot_y)
        .Add("foot_R_y", data.right_foot_y);
    key.Add("y0", Eigen::MatrixXd(data.initial_lateral_state)).Add("yf", Eigen::MatrixXd(data.final_lateral_state));
  }
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
  options.mu_init = q.mu_init;
  options.bound_mult_init_method = q.bound_mult_init_method;
  options.mumps_pivot_order = q.mumps_pivot_order;
  AslipTransition out;
  const PlanCacheKey key = CacheKey(data);
  // A failure is cached too (under the key plus "failed"), so that a chain search does not solve a known failure
  // again: [status, iterations, largest constraint violation]. Only failures that the same data and options repeat.
  PlanCacheKey failed_key = CacheKey(data);
  failed_key.Add("failed", 1.0);
  if (cache != nullptr) {
    const std::optional<Eigen::VectorXd> f = cache->Load(failed_key);
    if (f && f->size() == 3 && RepeatableFailure(static_cast<int>((*f)(0)))) {
      const NlpStatus status = static_cast<NlpStatus>(static_cast<int>((*f)(0)));
      out.collocation.nlp.status = status;
      out.collocation.nlp.iterations = static_cast<int>((*f)(1));
      out.max_constraint_violation = (*f)(2);
      out.collocation.nlp.message = std::string("transition NLP: ") + ToString(status) + " after " +
                                    std::to_string(out.collocation.nlp.iterations) +
                                    " iterations when solved before (plan cache " + cache->FileFor(failed_key) +
                                    "), not solved again";
      return out;
    }
  }
  std::optional<CollocationResult> hit;
  if (cache != nullptr) hit = LoadCachedCollocation(problem, *cache, key);
  out.collocation = hit ? std::move(*hit) : problem.Solve(options);
  if (cache != nullptr && !hit && out.success()) WarnIfNotCached(cache->Store(key, out.collocation.nlp.x));
  std::unique_ptr<NlpProblem> nlp = problem.BuildNlp();
  out.max_constraint_violation = MaxConstraintViolation(*nlp, out.collocation.nlp.x);
  out.mean_height = MeanPlanHeight(out.collocation);
  if (cache != nullptr && !hit && RepeatableFailure(static_cast<int>(out.collocation.nlp.status))) {
    Eigen::VectorXd f(3);
    f << static_cast<double>(out.collocation.nlp.status), out.collocation.nlp.iterations, out.max_constraint_violation;
    WarnIfNotCached(cache->Store(failed_key, f));
  }
  return out;
}

double AslipTransition::LiftingLegReloadTime(const ActuatedSpringLoadedInvertedPendulumParams& params,
                                             const AslipTransitionData& data, double floor_N) const {
  const Eigen::MatrixXd G = GroundReactions(params, data, 0);
  const CollocationPhaseSolution& dsp = collocation.phases.at(0);
  bool unloaded = false;
  for (Eigen::Index k = 0; k < G.cols(); ++k) {
    const double f = G(2 * data.lifting_leg + 1, k);
    if (unloaded && f > floor_N) return dsp.times(k) - dsp.start_time;
    unloaded = unloaded || f < floor_N;
  }
  return std::numeric_limits<double>::quiet_NaN();
}

Eigen::MatrixXd AslipTransition::GroundReactions(const ActuatedSpringLoadedInvertedPendulumParams& params,
                                                 const AslipTransitionData& data, int phase) const {
  const CollocationPhaseSolution& s = collocation.phases.at(phase);
  const ActuatedSpringLoadedInvertedPendulumContact c = AslipTransitionPlanner::PhaseContact(data, phase);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(4, s.states.cols());
  for (Eigen::Index k = 0; k < s.states.cols(); ++k) {
    const Eigen::VectorXd x = s.states.col(k);
    for (int leg = 0; leg < 2; ++leg) {
      if (!c.in_contact(leg)) continue;
      const ActuatedSpringLoadedInvertedPendulumLeg<double> g =
          AslipLegState<double>(params, x, leg, c.foot_x(leg), s.inputs(2 + leg, k));
      G(2 * leg, k) = g.grf_x;
      G(2 * leg + 1, k) = g.grf_z;
    }
  }
  return G;
}

}  // namespace rome
