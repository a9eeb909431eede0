#pragma once
// Spring-mass jump and landing trajectory optimisation, Sec. III-C of the hopping paper (Xiong & Ames, IROS 2018):
// direct collocation (even node spacing, free duration; Hermite–Simpson defects instead of the paper's trapezoid, so
// the plan re-integrates to 1e-3 with 40 intervals) on the spring-mass ROM (spring_mass_model.h),
// solved with Ipopt (solvers/collocation DirectCollocation, solvers/nlp IpoptSolver, AutoDiff derivatives).
//
// API summary (stable; used by the hopping diagram and example):
//   SpringMassJumpPlanner jump(rom, SpringMassJumpParams{.apex_rise = H});
//   SpringMassPlan plan = jump.Solve(rom_model.StaticState(L0));      // Eq. (14)-(15), from the standing state
//   SpringMassFlight flight = PredictFlight(rom_model, plan.FinalState());   // ballistic, leg held at L(T)
//   SpringMassLandingPlanner landing(rom, SpringMassLandingParams{.rest_height = plan.states(0, 0)});
//   SpringMassPlan land = landing.Solve(flight.touchdown_state);      // Eq. (16) + terminal rest conditions
//   land = landing.Resolve(measured_post_impact_state);               // warm start from the last landing solution
//   plan.LegLength(t), plan.LegLengthRate(t), plan.LegLengthAcceleration(t), plan.LegForce(t)  (t since the start)
//   ApexRiseForAirTime(rom, jump_params, z0, air_time)                // the H whose ROM air time is air_time
//
// Jump NLP (stance only, from rest until the ground force reaches zero):
//   z_k = [x, ẋ, L, L̇]_k, v_k = L̈_k, k = 0..N, and T ∈ [min_duration, max_duration]
//   defects (Hermite–Simpson, L̈ first-order hold), z_0 = the given standing state (v_0 free),
//   L ∈ [min_leg_length, max_leg_length], |L̇| ≤ max_leg_speed, |L̈| ≤ max_leg_acceleration  (Cassie's kinematics)
//   F_k ≥ 0 at every node, F_N = 0 (lift-off), F = n_legs (K(L) s + D(L) ṡ)
//   Eq. (14): x_N + ẋ_N²/(2g) = x_des with x_des = x_N + H (H = apex_rise, the COM rise above the take-off
//             height), imposed as ẋ_N = sqrt(2 g H) (the same set for ẋ_N > 0, and linear)
//   Eq. (15): min ∫₀ᵀ L̈² dt (trapezoid quadrature)
// Landing NLP (from the post-impact state until rest):
//   z_0 = the given post-impact state (v_0 free), T ∈ [min_duration, max_duration], same L/L̇/L̈ bounds,
//   F_k ≥ min_force_fraction m g for k ≥ 1 (node 0 is the impact state, fixed; the robot must not leave the ground),
//   s_k = L_k − x_k ≤ max_spring_compression,
//   terminal (spec A2 [R], the paper's printed list without its redundancies): x_N = rest_height, L̇_N = 0,
//   ṡ_N = 0 (so ẋ_N = 0), F_N = m g, L̈_N = 0
//   Eq. (16): min ∫₀ᵀ (L̈² + α ṡ²) dt
// After T a plan holds its last L with zero rates (spec A2 [R]).
// Solve() builds and solves a fresh NLP; it allocates (offline planner, or an event update of the diagram).
// Ipopt is serialised process-wide (IpoptMutex); do not call from parallel threads expecting parallel solves.

#include <optional>
#include <string>

#include <Eigen/Core>

#include "solvers/collocation/piecewise_polynomial.h"
#include "solvers/nlp/ipopt_solver.h"
#include "systems/rom/spring_mass_model.h"

namespace rome {

/// Ipopt options of both planners: defaults, with bound_relax_factor = 0 so the returned point satisfies the bounds
/// exactly (a relaxed L ≤ L_max moves F by 2 K × 1e-8 m ≈ 1e-4 N otherwise).
IpoptSolverOptions SpringMassPlannerSolverOptions();

/// One solved (or failed) jump or landing NLP.
struct SpringMassPlan {
  NlpStatus status = NlpStatus::kError;
  std::string message;  ///< Ipopt's outcome, naming the problem
  int iterations = 0;
  double solve_time_s = 0.0;   ///< wall time of the Ipopt solve [s]
  double max_violation = 0.0;  ///< max violation of every constraint and bound at the solution (unscaled)
  double cost = 0.0;
  double duration = 0.0;                 ///< T [s]
  Eigen::VectorXd times;                 ///< node times [s], N + 1
  Eigen::MatrixXd states;                ///< 4 × (N + 1): x, ẋ, L, L̇
  Eigen::VectorXd inputs;                ///< L̈ at the nodes [m/s²]
  Eigen::VectorXd leg_force;             ///< F at the nodes [N]
  PiecewisePolynomial state_trajectory;  ///< cubic Hermite through (z_k, ż_k)
  PiecewisePolynomial input_trajectory;  ///< first-order hold of L̈
  Eigen::VectorXd decision_variables;    ///< for warm starts
  NlpMultipliers multipliers;

  bool success() const { return status == NlpStatus::kSolved || status == NlpStatus::kSolvedToAcceptableLevel; }
  Eigen::Vector4d InitialState() const { return states.col(0); }
  Eigen::Vector4d FinalState() const { return states.col(states.cols() - 1); }
  /// z(t) on the collocation interpolant for t ∈ [0, T]; t outside [0, T] is clamped (no flight prediction:
  /// use PredictFlight after a jump).
  Eigen::Vector4d State(double t) const;
  /// L^des(t), L̇^des(t), L̈^des(t): the plan for t ∈ [0, T], L(T) held with zero rates afterwards (and L(0) before 0).
  double LegLength(double t) const;
  double LegLengthRate(double t) const;
  double LegLengthAcceleration(double t) const;
  /// F(t) = n_legs (K s + D ṡ) along the interpolated state [N] (0 ≤ t ≤ T, clamped).
  double LegForce(const SpringMassParams& rom, double t) const;
};

struct SpringMassJumpParams {
  double apex_rise = 0.2205;            ///< H [m]: COM rise above take-off. Default: the ROM air time is the paper's
                                        ///< 0.423 s with the identified K(L) from standing at L = 0.85 m
                                        ///< (ApexRiseForAirTime; 0.2286 m with the published K(L))
  int num_intervals = 30;               ///< N (spec A2 [R]: 40 trapezoid intervals; 30 Hermite–Simpson intervals
                                        ///< re-integrate to ~1e-4, measured)
  double min_duration = 0.15;           ///< [s] (spec A2 [R])
  double max_duration = 1.0;            ///< [s]
  double min_leg_length = 0.60;         ///< [m] (spec A2 [R])
  double max_leg_length = 0.92;         ///< [m] (spec A2 [R]: Caltech knee limit −54.4°)
  double max_leg_speed = 2.5;           ///< [m/s] (knee 8.5 rad/s × dL/dq ≈ 0.3 m/rad)
  double max_leg_acceleration = 100;    ///< [m/s²] (spec A2 [R])
  double initial_guess_duration = 0.0;  ///< [s] (ours); ≤ 0: automatic, 2.75 π / sqrt(n_legs K(L_0) / m) (the
                                        ///< stance times of both K variants are ~2.5-3 loaded half-periods)
  IpoptSolverOptions solver = SpringMassPlannerSolverOptions();
  /// Throws std::invalid_argument "SpringMassJumpParams: <field> ... = <value> ..." for the first invalid field
  /// (num_intervals 2..1000, durations > 0 and ordered, leg bounds > 0 and ordered, apex_rise > 0 and finite).
  void Validate() const;
};

struct SpringMassLandingParams {
  double rest_height = 0.83;             ///< x_des [m]: mass height at rest (spec A2 [R]: x_0 of the jump; set it)
  int num_intervals = 30;                ///< N (as the jump)
  double min_duration = 0.3;             ///< [s] (spec A2 [R])
  double max_duration = 1.5;             ///< [s]
  double min_leg_length = 0.60;          ///< [m]
  double max_leg_length = 0.92;          ///< [m]
  double max_leg_speed = 2.5;            ///< [m/s]
  double max_leg_acceleration = 100;     ///< [m/s²]
  double min_force_fraction = 0.25;      ///< F_min / (m g) (spec A2 [R])
  double max_spring_compression = 0.10;  ///< s_max [m] (spec A2 [R])
  double spring_rate_weight = 100.0;     ///< α of Eq. (16) [1/s²] (spec A2 [R])
  double initial_guess_duration = 0.6;   ///< [s] (ours)
  bool warm_start_multipliers = true;    ///< Resolve() also passes the last multipliers to Ipopt
  IpoptSolverOptions solver = SpringMassPlannerSolverOptions();
  /// Throws std::invalid_argument "SpringMassLandingParams: <field> ... = <value> ..." for the first invalid field
  /// (the jump's bounds, min_force_fraction in [0, 1), max_spring_compression > 0, spring_rate_weight >= 0). The
  /// rest height is checked against the leg bounds when the planner is built.
  void Validate() const;
};

class SpringMassJumpPlanner {
 public:
  /// Throws std::invalid_argument naming the parameter for bad params (non-positive H, bounds out of order, …).
  SpringMassJumpPlanner(SpringMassParams rom, SpringMassJumpParams params = {});
  const SpringMassJumpParams& params() const { return params_; }
  const SpringMassModel& rom() const { return rom_; }
  /// Solves from the standing state z0 (std::invalid_argument naming the value if z0 violates the L bounds).
  SpringMassPlan Solve(const Eigen::Vector4d& z0) const;

 private:
  SpringMassModel rom_;
  SpringMassJumpParams params_;
};

class SpringMassLandingPlanner {
 public:
  SpringMassLandingPlanner(SpringMassParams rom, SpringMassLandingParams params = {});
  const SpringMassLandingParams& params() const { return params_; }
  const SpringMassModel& rom() const { return rom_; }
  /// Cold start from the post-impact state z0 (interpolated initial guess). Remembers the solution.
  SpringMassPlan Solve(const Eigen::Vector4d& z0);
  /// Warm start from the last successful solution (primal point, and multipliers if warm_start_multipliers);
  /// a cold Solve() if there is none.
  SpringMassPlan Resolve(const Eigen::Vector4d& z0);
  /// Leg length at rest: n_legs K(L) (L − rest_height) = m g (Newton) [m].
  double RestLegLength() const;

 private:
  SpringMassPlan SolveFrom(const Eigen::Vector4d& z0, const SpringMassPlan* warm);
  SpringMassModel rom_;
  SpringMassLandingParams params_;
  std::optional<SpringMassPlan> last_;
};

/// Ballistic flight after lift-off with the leg held at L(T) (the ROM's flight phase).
struct SpringMassFlight {
  double air_time = 0.0;                                      ///< [s] from lift-off until x = L(T) on the way down
  double apex_height = 0.0;                                   ///< x at the apex [m]
  Eigen::Vector4d touchdown_state = Eigen::Vector4d::Zero();  ///< [L(T), ẋ_td, L(T), 0]
};
/// std::domain_error if the mass never returns to the leg length (it cannot: gravity) or lift-off is not upward.
SpringMassFlight PredictFlight(const SpringMassModel& rom, const Eigen::Vector4d& liftoff_state);

/// The apex rise H for which the jump NLP's ROM air time equals `air_time` [s] (secant iterations on H, each a
/// jump NLP solve; tolerance 1e-6 s). std::runtime_error if a solve fails or it does not converge.
double ApexRiseForAirTime(const SpringMassParams& rom, SpringMassJumpParams params, const Eigen::Vector4d& z0,
                          double air_time, SpringMassPlan* plan = nullptr);

}  // namespace rome
