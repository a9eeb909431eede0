#include "systems/planners/spring_mass_hop_planner.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "solvers/collocation/direct_collocation.h"

namespace rome {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Bounds shared by both NLPs (Cassie's kinematic capability, spec A2 [R]).
struct LegBounds {
  int num_intervals;
  double min_duration, max_duration, min_leg_length, max_leg_length, max_leg_speed, max_leg_acceleration;
};

void CheckBounds(const std::string& who, const LegBounds& b) {
  auto fail = [&](const std::string& what, double value) {
    std::ostringstream msg;
    msg << who << ": " << what << " = " << value << " is invalid";
    throw std::invalid_argument(msg.str());
  };
  if (b.num_intervals < 2 || b.num_intervals > 1000) fail("num_intervals (2..1000)", b.num_intervals);
  if (!(b.min_duration > 0.0)) fail("min_duration (must be > 0 s)", b.min_duration);
  if (!(b.max_duration >= b.min_duration) || !std::isfinite(b.max_duration)) {
    fail("max_duration (must be finite and >= min_duration)", b.max_duration);
  }
  if (!(b.min_leg_length > 0.0)) fail("min_leg_length (must be > 0 m)", b.min_leg_length);
  if (!(b.max_leg_length > b.min_leg_length)) fail("max_leg_length (must be > min_leg_length)", b.max_leg_length);
  if (!(b.max_leg_speed > 0.0)) fail("max_leg_speed (must be > 0 m/s)", b.max_leg_speed);
  if (!(b.max_leg_acceleration > 0.0)) fail("max_leg_acceleration (must be > 0 m/s^2)", b.max_leg_acceleration);
}

CollocationPhase MakePhase(const std::string& name, const SpringMassParams& rom, const LegBounds& b) {
  CollocationPhase phase;
  phase.name = name;
  phase.num_states = 4;
  phase.num_inputs = 1;
  phase.num_nodes = b.num_intervals + 1;
  // Hermite–Simpson (4th order) rather than the paper's trapezoid: with the identified (stiff, lightly damped) legs
  // the trapezoid needs ~200 intervals before an RK4 re-integration of the plan agrees to 1e-3 (measured).
  phase.method = CollocationMethod::kHermiteSimpson;
  phase.dynamics = [rom](const NodeVector& z, const NodeVector& u, NodeVector& zdot) {
    SpringMassDerivative<NodeScalar>(rom, z, u(0), zdot);  // Sec. III-B
  };
  phase.min_duration = b.min_duration;
  phase.max_duration = b.max_duration;
  phase.state_lower = Eigen::Vector4d(-kInf, -kInf, b.min_leg_length, -b.max_leg_speed);
  phase.state_upper = Eigen::Vector4d(kInf, kInf, b.max_leg_length, b.max_leg_speed);
  phase.input_lower = Eigen::VectorXd::Constant(1, -b.max_leg_acceleration);
  phase.input_upper = Eigen::VectorXd::Constant(1, b.max_leg_acceleration);
  return phase;
}

StateInputFunction LegForceFunction(const SpringMassParams& rom) {
  return [rom](const NodeVector& z, const NodeVector&, NodeVector& y) {
    y.resize(1);
    y(0) = SpringMassLegForce<NodeScalar>(rom, z(0), z(1), z(2), z(3));
  };
}

void CheckState(const std::string& who, const Eigen::Vector4d& z0, const LegBounds& b) {
  if (!z0.allFinite() || z0(2) < b.min_leg_length - 1e-12 || z0(2) > b.max_leg_length + 1e-12 ||
      std::abs(z0(3)) > b.max_leg_speed + 1e-12) {
    std::ostringstream msg;
    msg << who << ": initial state [x, xdot, L, Ldot] = [" << z0.transpose() << "] is outside the leg bounds L in ["
        << b.min_leg_length << ", " << b.max_leg_length << "] m, |Ldot| <= " << b.max_leg_speed << " m/s";
    throw std::invalid_argument(msg.str());
  }
}

// Largest violation of the NLP's variable bounds and constraint bounds at its solution (unscaled units).
double MaxViolation(const NlpProblem& nlp, const NlpResult& r) {
  double v = 0.0;
  if (r.x.size() == nlp.num_variables()) {
    v = std::max(v, (nlp.variable_lower_bounds() - r.x).cwiseMax(0.0).maxCoeff());
    v = std::max(v, (r.x - nlp.variable_upper_bounds()).cwiseMax(0.0).maxCoeff());
  }
  if (r.constraints.size() == nlp.num_constraints() && nlp.num_constraints() > 0) {
    v = std::max(v, (nlp.constraint_lower_bounds() - r.constraints).cwiseMax(0.0).maxCoeff());
    v = std::max(v, (r.constraints - nlp.constraint_upper_bounds()).cwiseMax(0.0).maxCoeff());
  }
  return v;
}

SpringMassPlan SolveCollocation(const DirectCollocation& dc, const SpringMassParams& rom,
                                const IpoptSolverOptions& options, const SpringMassPlan* warm, bool warm_multipliers) {
  std::unique_ptr<NlpProblem> nlp = dc.BuildNlp();
  IpoptSolverOptions opts = options;
  opts.use_limited_memory_hessian = true;  // DirectCollocation has no exact Hessian
  const bool use_warm = warm != nullptr && warm->decision_variables.size() == nlp->num_variables();
  const Eigen::VectorXd x0 = use_warm ? warm->decision_variables : dc.InitialGuessVector();
  const NlpMultipliers* mult =
      use_warm && warm_multipliers && warm->multipliers.constraints.size() == nlp->num_constraints()
          ? &warm->multipliers
          : nullptr;
  NlpResult r = IpoptSolver(opts).Solve(*nlp, x0, mult);
  SpringMassPlan plan;
  plan.status = r.status;
  plan.message = r.message;
  plan.iterations = r.iterations;
  plan.solve_time_s = r.wall_time;
  plan.cost = r.cost;
  // Ipopt returns g at its last iterate, before it moves x back inside the original bounds; re-evaluate at x.
  if (r.x.size() == nlp->num_variables() && nlp->num_constraints() > 0) {
    r.constraints.resize(nlp->num_constraints());
    nlp->EvalConstraints(r.x, r.constraints);
  }
  plan.max_violation = MaxViolation(*nlp, r);

  const CollocationResult unpacked = dc.Unpack(r.x);
  const CollocationPhaseSolution& s = unpacked.phases.front();
  plan.duration = s.duration;
  plan.times = s.times;
  plan.states = s.states;
  plan.inputs = s.inputs.row(0).transpose();
  plan.leg_force.resize(s.states.cols());
  for (int k = 0; k < s.states.cols(); ++k) {
    plan.leg_force(k) = SpringMassLegForce<double>(rom, s.states(0, k), s.states(1, k), s.states(2, k), s.states(3, k));
  }
  plan.state_trajectory = s.state_trajectory;
  plan.input_trajectory = s.input_trajectory;
  plan.decision_variables = std::move(r.x);
  plan.multipliers = std::move(r.multipliers);
  return plan;
}

Eigen::MatrixXd Interpolate(const Eigen::Vector4d& a, const Eigen::Vector4d& b, int nodes) {
  Eigen::MatrixXd m(4, nodes);
  for (int k = 0; k < nodes; ++k) {
    const double t = static_cast<double>(k) / (nodes - 1);
    m.col(k) = (1.0 - t) * a + t * b;
  }
  return m;
}

}  // namespace

IpoptSolverOptions SpringMassPlannerSolverOptions() {
  IpoptSolverOptions options;
  options.bound_relax_factor = 0.0;
  return options;
}

// ---------------------------------------------------------------------------------------------------------------
Eigen::Vector4d SpringMassPlan::State(double t) const { return state_trajectory.Value(t); }

double SpringMassPlan::LegLength(double t) const { return state_trajectory.Value(std::clamp(t, 0.0, duration))(2); }

double SpringMassPlan::LegLengthRate(double t) const {
  if (t < 0.0 || t > duration) return 0.0;
  return state_trajectory.Value(t)(3);
}

double SpringMassPlan::LegLengthAcceleration(double t) const {
  if (t < 0.0 || t > duration) return 0.0;
  return input_trajectory.Value(t)(0);
}

double SpringMassPlan::LegForce(const SpringMassParams& rom, double t) const {
  const Eigen::Vector4d z = State(t);
  return SpringMassLegForce<double>(rom, z(0), z(1), z(2), z(3));
}

// ---------------------------------------------------------------------------------------------------------------
SpringMassJumpPlanner::SpringMassJumpPlanner(SpringMassParams rom, SpringMassJumpParams params)
    : rom_(rom), params_(std::move(params)) {
  params_.Validate();
}

void SpringMassJumpParams::Validate() const {
  CheckBounds("SpringMassJumpParams", {num_intervals, min_duration, max_duration, min_leg_length, max_leg_length,
                                       max_leg_speed, max_leg_acceleration});
  if (!(apex_rise > 0.0) || !std::isfinite(apex_rise)) {
    std::ostringstream msg;
    msg << "SpringMassJumpParams: apex_rise = " << apex_rise << " m must be positive and finite";
    throw std::invalid_argument(msg.str());
  }
}

SpringMassPlan SpringMassJumpPlanner::Solve(const Eigen::Vector4d& z0) const {
  const SpringMassJumpParams& P = params_;
  const LegBounds b{P.num_intervals,  P.min_duration,  P.max_duration,        P.min_leg_length,
                    P.max_leg_length, P.max_leg_speed, P.max_leg_acceleration};
  CheckState("SpringMassJumpPlanner::Solve", z0, b);
  const SpringMassParams& rom = rom_.params();
  CollocationPhase phase = MakePhase("jump", rom, b);
  phase.running_cost = [](const NodeVector&, const NodeVector& u) { return NodeScalar(u(0) * u(0)); };  // Eq. (15)
  DirectCollocation dc("spring_mass_jump", {phase});
  const int N = P.num_intervals + 1;
  dc.SetNodeStateBounds(0, 0, z0, z0);  // the standing state (L̈_0 free)
  // Eq. (14) with x_des = x_N + H: ẋ_N = sqrt(2 g H).
  const double v_liftoff = std::sqrt(2.0 * rom.gravity * P.apex_rise);
  dc.SetNodeStateBounds(0, -1, Eigen::Vector4d(-kInf, v_liftoff, -kInf, -kInf),
                        Eigen::Vector4d(kInf, v_liftoff, kInf, kInf));
  dc.AddPathConstraint(0, 1, LegForceFunction(rom), Eigen::VectorXd::Zero(1), Eigen::VectorXd::Constant(1, kInf),
                       "leg force >= 0");
  dc.AddNodeConstraint(0, -1, 1, LegForceFunction(rom), Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1),
                       "lift-off: leg force = 0");
  // Initial guess: extend from the standing state to a lift-off at full extension with the lift-off speed.
  const Eigen::Vector4d z_end(P.max_leg_length, v_liftoff, P.max_leg_length, 0.0);
  double T_guess = P.initial_guess_duration;
  if (T_guess <= 0.0) {
    // Automatic: 2.75 half-periods of the loaded spring, π / sqrt(n_legs K(L_0) / m) (fits both K variants).
    const double K0 = std::max(rom_.Stiffness(z0(2)), 1.0);
    T_guess = std::clamp(2.75 * M_PI / std::sqrt(rom.n_legs * K0 / rom.mass), P.min_duration, P.max_duration);
  }
  dc.SetInitialGuess(0, Interpolate(z0, z_end, N), Eigen::MatrixXd::Zero(1, N), T_guess);
  return SolveCollocation(dc, rom, P.solver, nullptr, false);
}

// ---------------------------------------------------------------------------------------------------------------
SpringMassLandingPlanner::SpringMassLandingPlanner(SpringMassParams rom, SpringMassLandingParams params)
    : rom_(rom), params_(std::move(params)) {
  const SpringMassLandingParams& P = params_;
  P.Validate();
  if (!(P.rest_height > 0.0)) {
    std::ostringstream msg;
    msg << "SpringMassLandingParams: rest_height (must be > 0 m) = " << P.rest_height << " is invalid";
    throw std::invalid_argument(msg.str());
  }
  const double L_rest = RestLegLength();
  if (L_rest < P.min_leg_length || L_rest > P.max_leg_length || L_rest - P.rest_height > P.max_spring_compression) {
    std::ostringstream msg;
    msg << "SpringMassLandingParams: rest_height = " << P.rest_height << " m needs leg length " << L_rest
        << " m and compression " << L_rest - P.rest_height << " m at rest, outside the leg bounds [" << P.min_leg_length
        << ", " << P.max_leg_length << "] m or max_spring_compression " << P.max_spring_compression << " m";
    throw std::invalid_argument(msg.str());
  }
}

void SpringMassLandingParams::Validate() const {
  CheckBounds("SpringMassLandingParams", {num_intervals, min_duration, max_duration, min_leg_length, max_leg_length,
                                          max_leg_speed, max_leg_acceleration});
  auto fail = [](const std::string& what, double value) {
    std::ostringstream msg;
    msg << "SpringMassLandingParams: " << what << " = " << value << " is invalid";
    throw std::invalid_argument(msg.str());
  };
  if (!(min_force_fraction >= 0.0 && min_force_fraction < 1.0))
    fail("min_force_fraction (must be in [0, 1))", min_force_fraction);
  if (!(max_spring_compression > 0.0)) fail("max_spring_compression (must be > 0 m)", max_spring_compression);
  if (!(spring_rate_weight >= 0.0)) fail("spring_rate_weight (must be >= 0)", spring_rate_weight);
}

double SpringMassLandingPlanner::RestLegLength() const {
  // n_legs K(L) (L − x_rest) = m g, Newton from the stiffness at x_rest.
  const SpringMassParams& p = rom_.params();
  const double x = params_.rest_height, W = p.mass * p.gravity;
  double L = x + W / (p.n_legs * std::max(rom_.Stiffness(x), 1.0));
  for (int it = 0; it < 50; ++it) {
    const double K = rom_.Stiffness(L), dK = p.leg.stiffness.Derivative(L);
    const double r = p.n_legs * K * (L - x) - W;
    const double dr = p.n_legs * (dK * (L - x) + K);
    if (std::abs(r) < 1e-10 * W) break;
    L -= r / dr;
  }
  return L;
}

SpringMassPlan SpringMassLandingPlanner::Solve(const Eigen::Vector4d& z0) { return SolveFrom(z0, nullptr); }

SpringMassPlan SpringMassLandingPlanner::Resolve(const Eigen::Vector4d& z0) {
  return SolveFrom(z0, last_ ? &*last_ : nullptr);
}

SpringMassPlan SpringMassLandingPlanner::SolveFrom(const Eigen::Vector4d& z0, const SpringMassPlan* warm) {
  const SpringMassLandingParams& P = params_;
  const LegBounds b{P.num_intervals,  P.min_duration,  P.max_duration,        P.min_leg_length,
                    P.max_leg_length, P.max_leg_speed, P.max_leg_acceleration};
  CheckState("SpringMassLandingPlanner::Solve", z0, b);
  const SpringMassParams& rom = rom_.params();
  const double W = rom.mass * rom.gravity;
  CollocationPhase phase = MakePhase("landing", rom, b);
  const double alpha = P.spring_rate_weight;
  phase.running_cost = [alpha](const NodeVector& z, const NodeVector& u) {  // Eq. (16): L̈² + α ṡ²
    const NodeScalar sdot = z(3) - z(1);
    return NodeScalar(u(0) * u(0) + alpha * sdot * sdot);
  };
  DirectCollocation dc("spring_mass_landing", {phase});
  const int N = P.num_intervals + 1;
  dc.SetNodeStateBounds(0, 0, z0, z0);  // post-impact state (L̈_0 free)
  // Terminal rest: x_N = x_des, ẋ_N = 0 (ṡ_N = L̇_N − ẋ_N = 0 with L̇_N = 0), L̇_N = 0.
  dc.SetNodeStateBounds(0, -1, Eigen::Vector4d(P.rest_height, 0.0, -kInf, 0.0),
                        Eigen::Vector4d(P.rest_height, 0.0, kInf, 0.0));
  dc.AddNodeConstraint(0, -1, 1, LegForceFunction(rom), Eigen::VectorXd::Constant(1, W),
                       Eigen::VectorXd::Constant(1, W), "rest: leg force = m g");
  dc.AddNodeConstraint(
      0, -1, 1,
      [](const NodeVector&, const NodeVector& u, NodeVector& y) {
        y.resize(1);
        y(0) = u(0);
      },
      Eigen::VectorXd::Zero(1), Eigen::VectorXd::Zero(1), "rest: Lddot = 0");
  // The robot must not leave the ground: F ≥ F_min after the (fixed) impact node.
  for (int k = 1; k < N; ++k) {
    dc.AddNodeConstraint(0, k, 1, LegForceFunction(rom), Eigen::VectorXd::Constant(1, P.min_force_fraction * W),
                         Eigen::VectorXd::Constant(1, kInf), "leg force >= F_min");
  }
  dc.AddPathConstraint(
      0, 1,
      [](const NodeVector& z, const NodeVector&, NodeVector& y) {
        y.resize(1);
        y(0) = z(2) - z(0);
      },
      Eigen::VectorXd::Constant(1, -kInf), Eigen::VectorXd::Constant(1, P.max_spring_compression), "s <= s_max");
  const Eigen::Vector4d z_rest(P.rest_height, 0.0, RestLegLength(), 0.0);
  dc.SetInitialGuess(0, Interpolate(z0, z_rest, N), Eigen::MatrixXd::Zero(1, N), P.initial_guess_duration);
  SpringMassPlan plan = SolveCollocation(dc, rom, P.solver, warm, P.warm_start_multipliers);
  if (plan.success()) last_ = plan;
  return plan;
}

// ---------------------------------------------------------------------------------------------------------------
SpringMassFlight PredictFlight(const SpringMassModel& rom, const Eigen::Vector4d& z) {
  const double g = rom.params().gravity, v = z(1), x0 = z(0), L = z(2);
  const double disc = v * v + 2.0 * g * (x0 - L);
  if (!(v > 0.0) || !(disc >= 0.0)) {
    std::ostringstream msg;
    msg << "PredictFlight: lift-off state [x, xdot, L, Ldot] = [" << z.transpose()
        << "] does not leave the ground upwards (xdot must be > 0 and the mass must clear L)";
    throw std::domain_error(msg.str());
  }
  SpringMassFlight f;
  const double root = std::sqrt(disc);
  f.air_time = (v + root) / g;  // x0 + v t − g t²/2 = L on the way down
  f.apex_height = x0 + v * v / (2.0 * g);
  f.touchdown_state = Eigen::Vector4d(L, -root, L, 0.0);
  return f;
}

double ApexRiseForAirTime(const SpringMassParams& rom, SpringMassJumpParams params, const Eigen::Vector4d& z0,
                          double air_time, SpringMassPlan* plan_out) {
  if (!(air_time > 0.0)) throw std::invalid_argument("ApexRiseForAirTime: air_time must be > 0 s");
  const SpringMassModel model(rom);
  auto residual = [&](double H, SpringMassPlan* plan) {
    params.apex_rise = H;
    SpringMassPlan p = SpringMassJumpPlanner(rom, params).Solve(z0);
    if (!p.success()) {
      std::ostringstream msg;
      msg << "ApexRiseForAirTime: jump NLP failed at H = " << H << " m: " << p.message;
      throw std::runtime_error(msg.str());
    }
    const double r = PredictFlight(model, p.FinalState()).air_time - air_time;
    if (plan) *plan = std::move(p);
    return r;
  };
  // Ballistic guess: flight from and back to the same height, H = g t² / 8.
  double H0 = rom.gravity * air_time * air_time / 8.0, H1 = 1.02 * H0;
  double r0 = residual(H0, nullptr), r1 = residual(H1, nullptr);
  for (int it = 0; it < 20; ++it) {
    if (std::abs(r1) < 1e-6) {
      if (plan_out) residual(H1, plan_out);
      return H1;
    }
    const double H2 = H1 - r1 * (H1 - H0) / (r1 - r0);
    H0 = H1;
    r0 = r1;
    H1 = H2;
    r1 = residual(H1, nullptr);
  }
  std::ostringstream msg;
  msg << "ApexRiseForAirTime: no convergence to air time " << air_time << " s (last H = " << H1 << " m, error " << r1
      << " s)";
  throw std::runtime_error(msg.str());
}

}  // namespace rome
