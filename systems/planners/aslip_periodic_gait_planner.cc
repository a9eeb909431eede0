#include "systems/planners/aslip_periodic_gait_planner.h"

#include <algorithm>
#include <limits>
#include <memory>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

namespace rome {
namespace {

constexpr int kNx = 8, kNu = 2;

void Require(bool ok, const std::string& what, double value) {
  if (ok) return;
  std::ostringstream msg;
  msg << "AslipPeriodicGaitPlanner: parameter " << what << ", got " << value;
  throw std::invalid_argument(msg.str());
}

// Path rows of one leg on the ground: F/(m g) ≥ 0, (μ G_z ∓ G_x)/(m g) ≥ 0, s ∈ [s_min, s_max].
void LegRows(const ActuatedSpringLoadedInvertedPendulumParams& p, double mu, const NodeVector& x, int leg,
             double foot_x, NodeVector& y, int row) {
  const ActuatedSpringLoadedInvertedPendulumLeg<NodeScalar> g =
      AslipLegState<NodeScalar>(p, x, leg, foot_x, NodeScalar(0.0));
  const double weight = p.mass * p.gravity;
  y(row) = g.force / weight;
  y(row + 1) = (mu * g.grf_z - g.grf_x) / weight;
  y(row + 2) = (mu * g.grf_z + g.grf_x) / weight;
  y(row + 3) = g.spring;
}

}  // namespace

AslipPeriodicGaitPlanner::AslipPeriodicGaitPlanner(AslipPeriodicGaitParams params) : params_(params) {
  const auto& q = params_;
  Require(q.step_length > 0 && std::isfinite(q.step_length), "step_length must be > 0 m", q.step_length);
  Require(q.ssp_duration > 0 && std::isfinite(q.ssp_duration), "ssp_duration must be > 0 s", q.ssp_duration);
  Require(q.dsp_duration > 0 && std::isfinite(q.dsp_duration), "dsp_duration must be > 0 s", q.dsp_duration);
  Require(q.nodes_per_domain >= 3, "nodes_per_domain must be >= 3", q.nodes_per_domain);
  Require(q.friction_coefficient > 0, "friction_coefficient must be > 0", q.friction_coefficient);
  Require(q.spring_min < q.spring_max, "spring_min must be < spring_max", q.spring_min);
  Require(q.leg_length_min > 0.2807 && q.leg_length_min < q.leg_length_max,
          "leg_length_min must be in (0.2807, leg_length_max) m (K, D > 0 only there)", q.leg_length_min);
  Require(q.height_min > 0 && q.height_min < q.height_max, "height_min must be in (0, height_max) m", q.height_min);
  Require(q.max_leg_length_acceleration > 0, "max_leg_length_acceleration must be > 0 m/s²",
          q.max_leg_length_acceleration);
  Require(q.max_vertical_force_fraction == 0 || q.max_vertical_force_fraction > 1,
          "max_vertical_force_fraction must be 0 (no bound) or > 1", q.max_vertical_force_fraction);
}

ActuatedSpringLoadedInvertedPendulumContact AslipPeriodicGaitPlanner::PhaseContact(int phase) const {
  ActuatedSpringLoadedInvertedPendulumContact c;
  c.left = true;         // leg 0 stands in both domains
  c.right = phase == 1;  // leg 1 only in DSP
  c.left_foot_x = 0.0;
  c.right_foot_x = params_.step_length;
  return c;
}

DirectCollocation AslipPeriodicGaitPlanner::BuildProblem() const {
  const auto& q = params_;
  const ActuatedSpringLoadedInvertedPendulumParams p = q.aslip;
  const double v = q.max_speed;
  Eigen::VectorXd xl(kNx), xu(kNx);
  xl << -2.0 * q.step_length - 1.0, q.height_min, -v, -v, q.leg_length_min, q.leg_length_min, -v, -v;
  xu << 2.0 * q.step_length + 1.0, q.height_max, v, v, q.leg_length_max, q.leg_length_max, v, v;
  const Eigen::VectorXd ul = Eigen::VectorXd::Constant(kNu, -q.max_leg_length_acceleration);
  const Eigen::VectorXd uu = Eigen::VectorXd::Constant(kNu, q.max_leg_length_acceleration);
  std::vector<CollocationPhase> phases(2);
  const char* names[2] = {"ssp", "dsp"};
  const double durations[2] = {q.ssp_duration, q.dsp_duration};
  for (int ph = 0; ph < 2; ++ph) {
    CollocationPhase& c = phases[ph];
    c.name = names[ph];
    c.num_states = kNx;
    c.num_inputs = kNu;
    c.num_nodes = q.nodes_per_domain;
    c.min_duration = c.max_duration = durations[ph];
    const ActuatedSpringLoadedInvertedPendulumContact contact = PhaseContact(ph);
    c.dynamics = [p, contact](const NodeVector& x, const NodeVector& u, NodeVector& y) {
      y = AslipDynamics<NodeScalar>(p, contact, x, u);
    };
    c.state_lower = xl;
    c.state_upper = xu;
    c.input_lower = ul;
    c.input_upper = uu;
    c.running_cost = [](const NodeVector&, const NodeVector& u) {
      return NodeScalar(u(0) * u(0) + u(1) * u(1));
    };  // Eq. (4)
  }
  DirectCollocation problem("aslip_periodic_gait", std::move(phases));
  problem.SetExactHessian(q.exact_hessian);
  const double mu = q.friction_coefficient, l = q.step_length;
  // Eq. (5) path rows: SSP leg 0; DSP both legs.
  Eigen::VectorXd lo1(4), hi1(4);
  const double inf = std::numeric_limits<double>::infinity();
  lo1 << 0, 0, 0, q.spring_min;
  hi1 << inf, inf, inf, q.spring_max;
  problem.AddPathConstraint(
      0, 4,
      [p, mu](const NodeVector& x, const NodeVector&, NodeVector& y) {
        y.resize(4);
        LegRows(p, mu, x, 0, 0.0, y, 0);
      },
      lo1, hi1, "stance_leg_force_friction_spring");
  Eigen::VectorXd lo2(8), hi2(8);
  lo2 << lo1, lo1;
  hi2 << hi1, hi1;
  problem.AddPathConstraint(
      1, 8,
      [p, mu, l](const NodeVector& x, const NodeVector&, NodeVector& y) {
        y.resize(8);
        LegRows(p, mu, x, 0, 0.0, y, 0);
        LegRows(p, mu, x, 1, l, y, 4);
      },
      lo2, hi2, "both_legs_force_friction_spring");
  if (q.max_vertical_force_fraction > 0) {  // G_z/(m g) ≤ the bound: SSP leg 0; DSP both legs
    for (int ph = 0; ph < 2; ++ph) {
      const int legs = ph == 0 ? 1 : 2;
      problem.AddPathConstraint(
          ph, legs,
          [p, l, legs](const NodeVector& x, const NodeVector&, NodeVector& y) {
            y.resize(legs);
            for (int leg = 0; leg < legs; ++leg)
              y(leg) = AslipLegState<NodeScalar>(p, x, leg, leg == 0 ? 0.0 : l, NodeScalar(0.0)).grf_z /
                       (p.mass * p.gravity);
          },
          Eigen::VectorXd::Constant(legs, -inf), Eigen::VectorXd::Constant(legs, q.max_vertical_force_fraction),
          ph == 0 ? "ssp_leg_max_force" : "dsp_leg_max_force");
    }
  }
  // Touchdown at the last SSP node: s_1 = 0 (and ṡ_1 = 0 for a smooth force rise).
  const int td_rows = q.smooth_touchdown ? 2 : 1;
  problem.AddNodeConstraint(
      0, -1, td_rows,
      [p, l, td_rows](const NodeVector& x, const NodeVector&, NodeVector& y) {
        const ActuatedSpringLoadedInvertedPendulumLeg<NodeScalar> g =
            AslipLegState<NodeScalar>(p, x, 1, l, NodeScalar(0.0));
        y.resize(td_rows);
        y(0) = g.spring;
        if (td_rows == 2) y(1) = g.spring_rate;
      },
      Eigen::VectorXd::Zero(td_rows), Eigen::VectorXd::Zero(td_rows), "touchdown");
  // Lift-off guard at the last DSP node: F_0 = 0.
  problem.AddNodeConstraint(
      1, -1, 1,
      [p](const NodeVector& x, const NodeVector&, NodeVector& y) {
        y.resize(1);
        y(0) = AslipLegState<NodeScalar>(p, x, 0, 0.0, NodeScalar(0.0)).force / (p.mass * p.gravity);
      },
      Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), "liftoff");
  // Periodicity: about the new stance foot (x − l), legs swapped.
  problem.SetPeriodicTransition([l](const NodeVector& x, NodeVector& y) {
    y.resize(kNx);
    y << x(0) - l, x(1), x(2), x(3), x(5), x(4), x(7), x(6);
  });
  return problem;
}

void AslipPeriodicGaitPlanner::SetRandomInitialGuess(DirectCollocation* problem, std::uint32_t seed) const {
  const auto& q = params_;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> noise(-1.0, 1.0);
  const int N = q.nodes_per_domain;
  const double T = q.ssp_duration + q.dsp_duration;
  const double speed = q.step_length / T;
  const double z_mid = 0.5 * (q.height_min + q.height_max);
  const double L_mid = std::clamp(z_mid + 0.05, q.leg_length_min, q.leg_length_max);
  const double x_start = -0.5 * speed * q.ssp_duration;
  for (int ph = 0; ph < 2; ++ph) {
    const double t0 = ph == 0 ? 0.0 : q.ssp_duration;
    const double duration = ph == 0 ? q.ssp_duration : q.dsp_duration;
    Eigen::MatrixXd X(kNx, N), U(kNu, N);
    for (int k = 0; k < N; ++k) {
      const double t = t0 + duration * k / (N - 1);
      X(0, k) = x_start + speed * t + 0.02 * noise(rng);
      X(1, k) = z_mid + 0.02 * noise(rng);
      X(2, k) = speed + 0.1 * noise(rng);
      X(3, k) = 0.1 * noise(rng);
      X(4, k) = L_mid + 0.02 * noise(rng);
      X(5, k) = L_mid + 0.02 * noise(rng);
      X(6, k) = 0.1 * noise(rng);
      X(7, k) = 0.1 * noise(rng);
      U(0, k) = 1.0 * noise(rng);
      U(1, k) = 1.0 * noise(rng);
    }
    problem->SetInitialGuess(ph, X, U, duration);
  }
}

AslipPeriodicGait AslipPeriodicGaitPlanner::Solve(std::uint32_t seed, const PlanCache* cache) const {
  DirectCollocation problem = BuildProblem();
  SetRandomInitialGuess(&problem, seed);
  const PlanCacheKey key = CacheKey(seed);
  if (cache != nullptr) {
    if (std::optional<CollocationResult> hit = LoadCachedCollocation(problem, *cache, key)) {
      AslipPeriodicGait gait = Summarize(std::move(*hit), problem);
      return gait;
    }
  }
  AslipPeriodicGait gait = Solve(problem);
  if (cache != nullptr && gait.success()) WarnIfNotCached(cache->Store(key, gait.collocation.nlp.x));
  return gait;
}

PlanCacheKey AslipPeriodicGaitPlanner::CacheKey(std::uint32_t seed) const {
  PlanCacheKey key("aslip_periodic_gait");
  AddToCacheKey(params_, &key);
  key.Add("seed", seed);
  return key;
}

void AddToCacheKey(const AslipPeriodicGaitParams& q, PlanCacheKey* key) {
  const ActuatedSpringLoadedInvertedPendulumParams& a = q.aslip;
  key->Add("mass", a.mass).Add("gravity", a.gravity).Add("c", a.spring_scale).Add("k4", a.k4).Add("k2", a.k2);
  key->Add("k1", a.k1).Add("k0", a.k0).Add("d4", a.d4).Add("d2", a.d2).Add("d1", a.d1).Add("d0", a.d0);
  key->Add("L_h", a.heel_length).Add("L_t", a.toe_length);
  key->Add("l", q.step_length).Add("T_SSP", q.ssp_duration).Add("T_DSP", q.dsp_duration).Add("N", q.nodes_per_domain);
  key->Add("mu", q.friction_coefficient).Add("s_min", q.spring_min).Add("s_max", q.spring_max);
  key->Add("L_min", q.leg_length_min).Add("L_max", q.leg_length_max).Add("z_min", q.height_min);
  key->Add("z_max", q.height_max).Add("Ldd_max", q.max_leg_length_acceleration).Add("v_max", q.max_speed);
  key->Add("smooth", q.smooth_touchdown).Add("tol", q.tolerance).Add("constr_tol", q.constraint_tolerance);
  key->Add("max_iter", q.max_iterations).Add("history", q.limited_memory_history).Add("hessian", q.exact_hessian);
  key->Add(q.mu_strategy == "adaptive" ? "mu_adaptive" : "mu_monotone", 1.0);
  key->Add(q.bound_mult_init_method == "mu-based" ? "bound_mult_mu_based" : "bound_mult_constant", 1.0);
  key->Add("mu_init", q.mu_init);
  key->Add("mumps_pivot_order", q.mumps_pivot_order);
  if (q.max_vertical_force_fraction > 0) key->Add("max_vertical_force", q.max_vertical_force_fraction);
}

std::optional<CollocationResult> LoadCachedCollocation(const DirectCollocation& problem, const PlanCache& cache,
                                                       const PlanCacheKey& key) {
  std::optional<Eigen::VectorXd> z = cache.Load(key);
  std::unique_ptr<NlpProblem> nlp = problem.BuildNlp();
  if (!z || z->size() != nlp->num_variables()) return std::nullopt;
  if (!(MaxConstraintViolation(*nlp, *z) <= 1e-6)) return std::nullopt;
  CollocationResult result = problem.Unpack(*z);
  result.nlp.status = NlpStatus::kSolved;
  result.nlp.iterations = 0;
  result.nlp.x = *z;
  result.nlp.cost = nlp->EvalCost(*z);
  result.nlp.constraints.resize(nlp->num_constraints());
  nlp->EvalConstraints(*z, result.nlp.constraints);
  result.nlp.message = "NLP '" + nlp->name() + "': loaded from " + cache.FileFor(key);
  return result;
}

AslipPeriodicGait AslipPeriodicGaitPlanner::Summarize(CollocationResult result,
                                                      const DirectCollocation& problem) const {
  AslipPeriodicGait gait;
  gait.collocation = std::move(result);
  std::unique_ptr<NlpProblem> nlp = problem.BuildNlp();
  gait.max_constraint_violation = MaxConstraintViolation(*nlp, gait.collocation.nlp.x);
  gait.mean_height = MeanPlanHeight(gait.collocation);
  return gait;
}

AslipPeriodicGait AslipPeriodicGaitPlanner::Solve(const DirectCollocation& problem) const {
  IpoptSolverOptions options;
  options.tolerance = params_.tolerance;
  options.constraint_violation_tolerance = params_.constraint_tolerance;
  options.max_iterations = params_.max_iterations;
  options.limited_memory_history = params_.limited_memory_history;
  options.mu_strategy = params_.mu_strategy;
  options.mu_init = params_.mu_init;
  options.bound_mult_init_method = params_.bound_mult_init_method;
  options.mumps_pivot_order = params_.mumps_pivot_order;
  return Summarize(problem.Solve(options), problem);
}

Eigen::MatrixXd AslipPeriodicGait::GroundReactions(const ActuatedSpringLoadedInvertedPendulumParams& params,
                                                   double step_length, int phase) const {
  const CollocationPhaseSolution& s = collocation.phases.at(phase);
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(4, s.states.cols());
  for (Eigen::Index k = 0; k < s.states.cols(); ++k) {
    const Eigen::VectorXd x = s.states.col(k);
    for (int leg = 0; leg < 2; ++leg) {
      if (leg == 1 && phase == 0) continue;  // leg 1 swings in SSP
      const ActuatedSpringLoadedInvertedPendulumLeg<double> g =
          AslipLegState<double>(params, x, leg, leg == 0 ? 0.0 : step_length, 0.0);
      G(2 * leg, k) = g.grf_x;
      G(2 * leg + 1, k) = g.grf_z;
    }
  }
  return G;
}

double MeanPlanHeight(const CollocationResult& plan) {
  double integral = 0.0, total = 0.0;
  for (const auto& s : plan.phases) {
    const int n = static_cast<int>(s.times.size());
    const double h = s.duration / (n - 1);
    for (int k = 0; k + 1 < n; ++k) integral += 0.5 * h * (s.states(1, k) + s.states(1, k + 1));
    total += s.duration;
  }
  return integral / total;
}

double MaxConstraintViolation(NlpProblem& nlp, const Eigen::VectorXd& z) {
  Eigen::VectorXd g(nlp.num_constraints());
  nlp.EvalConstraints(z, g);
  double worst = 0.0;
  for (int i = 0; i < g.size(); ++i) {
    worst = std::max({worst, nlp.constraint_lower_bounds()(i) - g(i), g(i) - nlp.constraint_upper_bounds()(i)});
  }
  for (int i = 0; i < z.size(); ++i) {
    worst = std::max({worst, nlp.variable_lower_bounds()(i) - z(i), z(i) - nlp.variable_upper_bounds()(i)});
  }
  return worst;
}

}  // namespace rome
