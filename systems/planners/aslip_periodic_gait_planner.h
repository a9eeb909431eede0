#pragma once
// AslipPeriodicGaitPlanner: the periodic point-foot aSLIP walking gait of the walking paper, Eq. (4)-(5), by
// trapezoidal direct collocation (solvers/collocation) on Ipopt. Offline: solved once before a run.
//
// One step = two domains, SSP then DSP, each with N evenly spaced nodes and a fixed duration (spec §3.1).
// Leg labels inside a plan: leg 0 ("stance") stands at the origin during SSP and trails in DSP; leg 1 ("swing") lands
// at (l, 0) at the end of SSP and leads in DSP. State [x, z, ẋ, ż, L_0, L_1, L̇_0, L̇_1], input [L̈_0, L̈_1].
//   Cost, Eq. (4):  Σ (dt/2)(L̈_0² + L̈_1²) with trapezoid weights per domain.
//   Constraints, Eq. (5) with the spec's [R] numbers:
//     bounds    z ∈ [0.85, 0.95] m, L ∈ [0.70, 1.00] m, |L̈| ≤ 50 m/s² at every node;
//     path      F_i ≥ 0, |G_ix| ≤ μ G_iz, s_i ∈ [−0.01, 0.12] m for each leg on the ground;
//     touchdown s_1 = 0 at the last SSP node (leg 1's rest length reaches its foothold at (l, 0)), and with
//               smooth_touchdown also ṡ_1 = 0, i.e. F_1 = 0 right after touchdown (no force jump, Fig. 2 S2);
//     lift-off  F_0 = 0 at the last DSP node (the guard of the trailing leg);
//     periodic  the last DSP state re-expressed about the new stance foot (x − l) with the legs swapped equals the
//               first SSP state, so the gait repeats with speed l/(T_SSP + T_DSP).
#include <cstdint>
#include <optional>
#include <string>

#include <Eigen/Core>

#include "solvers/collocation/direct_collocation.h"
#include "systems/planners/plan_cache.h"
#include "systems/rom/actuated_spring_loaded_inverted_pendulum.h"

namespace rome {

struct AslipPeriodicGaitParams {
  ActuatedSpringLoadedInvertedPendulumParams aslip{};
  double step_length = 0.30;                ///< [m] l (gait A, spec §3.1 [R])
  double ssp_duration = 0.40;               ///< [s] T_SSP (gait A)
  double dsp_duration = 0.10;               ///< [s] T_DSP (gait A)
  int nodes_per_domain = 21;                ///< [-] N (spec [R])
  double friction_coefficient = 0.6;        ///< [-] μ (spec [R])
  double spring_min = -0.01;                ///< [m] s lower bound (spec [R])
  double spring_max = 0.12;                 ///< [m] s upper bound (spec [R])
  double leg_length_min = 0.70;             ///< [m] L lower bound (spec [R])
  double leg_length_max = 1.00;             ///< [m] L upper bound (spec [R])
  double height_min = 0.85;                 ///< [m] z lower bound (spec [R])
  double height_max = 0.95;                 ///< [m] z upper bound (spec [R])
  double max_leg_length_acceleration = 50;  ///< [m/s²] |L̈| bound (spec [R])
  double max_speed = 5.0;                   ///< [m/s] |ẋ|, |ż|, |L̇| bound (ours: keeps Ipopt's iterates sane)
  /// [-] every leg's vertical GRF G_z ≤ this fraction of m g, in both domains (ours; 0: no bound, else > 1). The
  /// NLP's cost does not see the robot's knees: a caller that knows them can bound the force they must carry.
  double max_vertical_force_fraction = 0.0;
  bool smooth_touchdown = true;        ///< F_1 = 0 just after touchdown (spec §2.1 [R], optional there)
  double tolerance = 1e-6;             ///< [-] Ipopt tol (ours)
  double constraint_tolerance = 1e-8;  ///< [unit of the row] Ipopt constr_viol_tol (ours; acceptance is 1e-6)
  int max_iterations = 1000;           ///< Ipopt max_iter (ours)
  int limited_memory_history = 6;      ///< Ipopt limited_memory_max_history when !exact_hessian (ours)
  bool exact_hessian = true;           ///< collocation Hessian (true) or Ipopt's L-BFGS (false) (ours)
  std::string mu_strategy =
      "adaptive";  ///< Ipopt mu_strategy (ours: fewer iterations; docs/design-notes.md#walking-ipopt-options)
  /// Ipopt bound_mult_init_method and mu_init (ours). Bound multipliers start at mu_init / slack instead of 1, with a
  /// small initial barrier: about 4x fewer iterations, same optimum (docs/design-notes.md#walking-ipopt-options).
  std::string bound_mult_init_method = "mu-based";
  double mu_init = 0.01;  ///< [-] Ipopt mu_init (ours; see bound_mult_init_method)
  /// MUMPS ordering (Ipopt mumps_pivot_order; ours): 6, QAMD, handles the free durations' dense columns (faster than
  /// MUMPS's automatic choice; docs/design-notes.md#walking-ipopt-options).
  int mumps_pivot_order = 6;
};

/// A solved (or failed) periodic gait.
struct AslipPeriodicGait {
  CollocationResult collocation;          ///< phases 0 = "ssp", 1 = "dsp"
  double max_constraint_violation = 0.0;  ///< ‖violation‖_∞ of every row and bound of the NLP at the answer
  double mean_height = 0.0;  ///< [m] time average of z over the step (trapezoid rule), the H-LIP z0 (spec §2.2)
  bool success() const { return collocation.success(); }
  /// Ground reaction [G_0x, G_0z, G_1x, G_1z] (N) at every node of phase p (4 × N); zero for a leg in the air.
  Eigen::MatrixXd GroundReactions(const ActuatedSpringLoadedInvertedPendulumParams& params, double step_length,
                                  int phase) const;
};

class AslipPeriodicGaitPlanner {
 public:
  /// Throws std::invalid_argument naming the parameter for a non-positive step length or duration, N < 3, or
  /// empty bounds.
  explicit AslipPeriodicGaitPlanner(AslipPeriodicGaitParams params = {});
  const AslipPeriodicGaitParams& params() const { return params_; }

  /// The collocation problem Eq. (4)-(5) without an initial guess.
  DirectCollocation BuildProblem() const;
  /// Random initial guess (spec [R]): x at the gait speed, z, L and L̇ around a standing posture with uniform noise,
  /// noisy inputs; deterministic in `seed`.
  void SetRandomInitialGuess(DirectCollocation* problem, std::uint32_t seed) const;
  /// Builds, guesses with `seed`, solves. With a cache: a stored plan for the same parameters and seed is loaded
  /// instead (0 iterations; its constraints are re-checked, and a plan violating them by > 1e-6 is re-solved), and a
  /// new successful plan is stored.
  AslipPeriodicGait Solve(std::uint32_t seed, const PlanCache* cache = nullptr) const;
  /// Solves a problem that already has its initial guess.
  AslipPeriodicGait Solve(const DirectCollocation& problem) const;
  /// Every parameter and the seed.
  PlanCacheKey CacheKey(std::uint32_t seed) const;
  /// The contact of phase p (0 = SSP, 1 = DSP) in plan coordinates.
  ActuatedSpringLoadedInvertedPendulumContact PhaseContact(int phase) const;

 private:
  AslipPeriodicGait Summarize(CollocationResult result, const DirectCollocation& problem) const;
  AslipPeriodicGaitParams params_;
};

/// ‖violation‖_∞ of g_lo ≤ g(z) ≤ g_hi and z_lo ≤ z ≤ z_hi.
double MaxConstraintViolation(NlpProblem& nlp, const Eigen::VectorXd& z);

/// [m] Time average of the COM height (state row 1) over all phases of a plan, by the trapezoid rule on each
/// phase's uniform grid: the H-LIP z0 of the periodic gait and of the transition (spec §2.2, §2.3).
double MeanPlanHeight(const CollocationResult& plan);

/// The model and bounds of the shared aSLIP NLP parameters, appended to a cache key.
void AddToCacheKey(const AslipPeriodicGaitParams& params, PlanCacheKey* key);

/// A collocation result for a stored decision vector z of `problem`, if it meets every row and bound to 1e-6
/// (status kSolved, 0 iterations, message naming the file).
std::optional<CollocationResult> LoadCachedCollocation(const DirectCollocation& problem, const PlanCache& cache,
                                                       const PlanCacheKey& key);

}  // namespace rome
