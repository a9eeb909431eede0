#pragma once
// PreImpactPostureOptimizer: the desired pre-impact posture of the stepping-stones paper, Eq. (21), solved as a
// small NLP with Ipopt (rome::IpoptSolver, exact first derivatives from the multibody Jacobians; the Lagrangian
// Hessian by central differences of those exact gradients).
//
// Given the next stone relative to the stance foot, (l, h) = (step_length_m, step_height_m), find q*:
//   q* = argmin  w_x (p_com^x(q) − p_com,f^{x,d})² + w_φ φ_torso(q)²                        (Eq. (21))
//               + w_z (p_com^z(q) − p_com,f^{z,d})²      [ours, optional: w_z = 0 by default]
//               + w_r ||q_joints − q_nominal,joints||²     [ours: a small posture term, see below]
//   s.t.        q_lower ≤ q_joints ≤ q_upper                                               (joint limits)
//               p_sw(q) − p_st(q) = (l, h)                                                 (stone)
//               p_com^z(q) − p_st^z(q) ≥ p_com^{z,min} + min(h, 0)                        (COM position)
//               (ours: the minimum height is measured from the lower of the two feet; the paper's bound on
//               p_com^z relative to the stance foot alone makes every long step down a 0.25 m drop infeasible)
//               loop closures |p_a − p_b| = d (planar Cassie's achilles rods) and, for line/flat feet,
//               the swing and stance foot pitch equal to their flat (nominal-pose) pitch    [ours: physical validity]
// with p_com,f^{x,d} = ε l (the paper's desired pre-impact COM position) unless the request gives it. All positions
// are relative to the stance foot, so the decision variables are q without the base translation
// x = [pitch, joints] (planar models), and q* is returned with the stance foot at request.stance_foot_position.
// φ_torso is the base pitch q[2] (the torso for AMBER, the pelvis for planar Cassie).
// The posture term: with 2 cost terms, 2 stone equalities and nv − 2 = 5 variables (AMBER), Eq. (21) alone has a
// one-parameter family of minimisers; w_r (1e-4, so it moves the paper's terms by much less than a millimetre)
// picks the member nearest the nominal posture and makes the optimum isolated (a strict local minimum).
//
// Output for Algorithm 1, line 9: the final torso pitch φ_f^d and the final COM height p_com,f^{z,d} (relative to the
// stance foot) of q*, for the output trajectories of Eq. (19), (22).
//
// Failure policy (documented contract): Solve() never throws for an unreachable stone; it returns
// success = false with the Ipopt status and a message naming the request, and fills the posture from a fallback:
// the last successful solution for the same stance contact (fallback = kPreviousSolution) if there is one, else the
// nominal pose (kNominalPose). The caller decides whether to use it; message says which one was used.
// Solve() is called once per step (at touchdown); it allocates (Ipopt does) and is not for the 1 kHz loop.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "solvers/nlp/ipopt_solver.h"
#include "solvers/nlp/nlp_problem.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

struct PreImpactPostureParams {
  double com_x_fraction = 0.6;  ///< ε [-]: p_com,f^{x,d} = ε l (paper: ε ∈ [0, 1]; 0.6 in its random-stone runs).
  double min_com_height_m = 0.7;    ///< p_com^{z,min} [m] above the lower of the two feet (paper gives no value;
                                    ///< AMBER's nominal COM is 0.90 m above its feet).
  double com_x_weight = 1.0;        ///< w_x [1/m²] (Eq. (21): 1).
  double torso_pitch_weight = 1.0;  ///< w_φ [1/rad²] (Eq. (21): 1).
  double com_height_weight = 0.0;   ///< w_z [1/m²] on a requested COM height (0: not in Eq. (21)).
  double posture_weight = 1e-4;     ///< w_r [1/rad²] on the joints' distance to the nominal posture (ours).
  /// [rad] step of the central differences of the analytic gradients that give Ipopt its Lagrangian Hessian
  /// (first derivatives are exact; the Hessian is accurate to about step² ≈ 1e-10 relative).
  double hessian_difference_step = 1e-5;
  IpoptSolverOptions ipopt = DefaultIpoptOptions();  ///< tolerances of the solve
  static IpoptSolverOptions DefaultIpoptOptions() {
    IpoptSolverOptions o;
    o.tolerance = 1e-10;
    o.constraint_violation_tolerance = 1e-10;
    o.max_iterations = 500;
    return o;
  }
};

struct PreImpactPostureRequest {
  std::string stance_contact = "left_foot";                        ///< contact on the current stone
  std::string swing_contact = "right_foot";                        ///< contact that lands on the next stone
  double step_length_m = 0.3;                                      ///< l [m]: next stone minus stance foot, along x
  double step_height_m = 0.0;                                      ///< h [m]: next stone minus stance foot, along z
  double com_x_m = std::numeric_limits<double>::quiet_NaN();       ///< p_com,f^{x,d} [m]; NaN = ε l
  double com_height_m = std::numeric_limits<double>::quiet_NaN();  ///< target for w_z [m]; NaN = no target
  Eigen::Vector2d stance_foot_position = Eigen::Vector2d::Zero();  ///< world (x, z) [m] of the stance foot for q*
};

struct PreImpactPosture {
  enum class Fallback { kNone, kPreviousSolution, kNominalPose };
  bool success = false;
  NlpStatus status = NlpStatus::kError;
  Fallback fallback = Fallback::kNone;
  std::string message;           ///< names the request, the outcome and the fallback used
  Eigen::VectorXd q;             ///< pre-impact configuration (nq), stance foot at request.stance_foot_position
  double torso_pitch_rad = 0.0;  ///< φ_f^d of q
  double com_x_m = 0.0;          ///< p_com^x of q relative to the stance foot [m]
  double com_height_m = 0.0;     ///< p_com,f^{z,d}: p_com^z of q relative to the stance foot [m]
  Eigen::Vector2d swing_foot = Eigen::Vector2d::Zero();  ///< p_sw − p_st of q [m]
  double cost = 0.0;
  int iterations = 0;
  double solve_time_s = 0.0;  ///< wall time of the Ipopt solve [s]
};

/// The NLP of Eq. (21) for one request (public so that tests can evaluate cost and constraints).
/// Variables: q without the base translation ([pitch, joints] for a planar model).
/// Constraints, in order: swing foot x, z relative to the stance foot; COM height relative to the stance foot;
/// every loop closure (|p_a − p_b| − d); for a line/flat swing then stance contact, its link pitch minus the nominal.
class PreImpactPostureProblem final : public NlpProblem {
 public:
  PreImpactPostureProblem(const MultibodyModel& model, const PreImpactPostureParams& params,
                          const PreImpactPostureRequest& request);

  /// Full configuration from the variables, with the stance foot at request.stance_foot_position.
  Eigen::VectorXd ToConfiguration(const Eigen::Ref<const Eigen::VectorXd>& x);
  /// Variables of a configuration.
  Eigen::VectorXd FromConfiguration(const Eigen::VectorXd& q) const;
  double com_x_target() const { return com_x_target_; }

  double EvalCost(const Eigen::Ref<const Eigen::VectorXd>& x) override;
  void EvalCostGradient(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> gradient) override;
  void EvalConstraints(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> g) override;
  void EvalConstraintJacobian(const Eigen::Ref<const Eigen::VectorXd>& x, Eigen::Ref<Eigen::VectorXd> values) override;
  /// Central differences of the analytic Lagrangian gradient (see params.hessian_difference_step).
  void EvalLagrangianHessian(const Eigen::Ref<const Eigen::VectorXd>& x, double cost_factor,
                             const Eigen::Ref<const Eigen::VectorXd>& lambda,
                             Eigen::Ref<Eigen::VectorXd> values) override;

 private:
  void Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x);

  const MultibodyModel& model_;
  PreImpactPostureParams params_;
  PreImpactPostureRequest request_;
  int stance_ = -1, swing_ = -1;
  std::vector<int> flat_contacts_;  // contacts whose pitch is constrained
  std::vector<double> flat_pitch_;  // their nominal-pose pitch
  double com_x_target_ = 0.0;
  MultibodyWorkspace ws_;
  Eigen::VectorXd q_nominal_, cached_x_, q_, g_, cost_gradient_;
  Eigen::MatrixXd G_;  // constraint Jacobian (dense, rows x variables)
  Eigen::MatrixXd J3_, J6_;
  double cost_ = 0.0;
  bool cached_ = false;
};

class PreImpactPostureOptimizer {
 public:
  explicit PreImpactPostureOptimizer(std::shared_ptr<const MultibodyModel> model, PreImpactPostureParams params = {});

  const MultibodyModel& model() const { return *model_; }
  const PreImpactPostureParams& params() const { return params_; }

  /// Solves Eq. (21) for the request; see the failure policy in the header comment. Throws std::invalid_argument
  /// only for a malformed request (unknown contact names, stance == swing, non-finite numbers, non-planar model).
  PreImpactPosture Solve(const PreImpactPostureRequest& request);

  /// Forgets the previous solutions (warm starts and fallbacks).
  void Reset();

 private:
  PreImpactPosture Describe(PreImpactPostureProblem& problem, const PreImpactPostureRequest& request,
                            const Eigen::VectorXd& x) const;

  std::shared_ptr<const MultibodyModel> model_;
  PreImpactPostureParams params_;
  IpoptSolver solver_;
  // Last successful solution per stance contact (variables), for warm starts and the fallback.
  std::vector<Eigen::VectorXd> previous_;
  std::vector<NlpMultipliers> previous_multipliers_;  // and its multipliers (Ipopt warm start)
};

}  // namespace rome
