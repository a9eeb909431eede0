#pragma once
// Desired output trajectories of the stepping-stones paper, Eq. (19)-(24), pure math (no framework). General: the
// phase, Bézier and swing-foot curves know no robot; the diagram's own block is SteppingStonesOutputsSystem.
//
//   Eq. (19)  Y_d = [φ_torso^d, p_com^{z,d}, p_sw^{x,d}, p_sw^{z,d}] (the order of Y_a); p_com^{z,d} comes from the
//             vertical-COM MPC (VerticalComMpc / VerticalComMpcSystem), the rest from polynomials in a phase τ.
//   Eq. (20)  state-based phase τ = (p^x − p^x_0) / (p^{x,d}_f − p^x_0), p^{x,d}_f = ε l_des  (PhaseType::kStateBased)
//   Sec. VI-D time-based phase τ_t = (t − t_0) / T_s, T_s from Eq. (27) at the start of the step (kTimeBased)
//   Eq. (22)  torso pitch cubic φ(τ) = [1 τ τ² τ³] c with φ(0) = φ_0, φ(1) = φ_f, φ'(0) = φ'(1) = 0,
//             i.e. φ = φ_0 + (φ_f − φ_0)(3τ² − 2τ³)
//   Eq. (23)  p_sw^x = (1 − b_h(τ)) p_sw0^x + b_h(τ) l_des,  b_h Bézier with γ = [0, 0, 0, 1, 1, 1]
//   Eq. (24)  p_sw^z = b_v(τ),  γ = [p_sw0^z, z_max, z_max, z_max, h_des, h_des + z_neg]
//   (the paper calls them degree M−1 polynomials with coefficients γ_0..γ_M; six coefficients: degree 5.)
// Every trajectory gives its value and its first and second derivatives with respect to τ and, by the chain
// rule ẏ = y' τ̇, ÿ = y'' τ̇² + y' τ̈, with respect to time.
// Units: angles rad, positions m (relative to the stance foot), time s.

#include <Eigen/Core>

namespace rome {

/// Value and first two derivatives of a scalar trajectory (w.r.t. τ or t, as stated where it is returned).
struct ScalarDerivatives {
  double value = 0, first = 0, second = 0;
};

/// Phase τ with its time derivatives.
struct Phase {
  double tau = 0;       ///< [-]
  double tau_dot = 0;   ///< [1/s]
  double tau_ddot = 0;  ///< [1/s²]
};

/// Chain rule: d/dt of y(τ(t)) from dy/dτ, d²y/dτ² and the phase.
ScalarDerivatives ToTimeDerivatives(const ScalarDerivatives& y_tau, const Phase& phase);

enum class PhaseType {
  kStateBased,  ///< Eq. (20): COM forward position between the step start and ε l_des (the paper's default)
  kTimeBased,   ///< Sec. VI-D: τ_t = (t − t_0)/T_s
};

struct PhaseVariableParams {
  PhaseType type = PhaseType::kStateBased;
  /// Hold τ in [0, 1] (derivatives zero outside). Ours: an early or late impact then freezes the polynomials at
  /// their end points (the swing foot keeps descending to h_des + z_neg) instead of extrapolating them.
  bool saturate = true;
};

class PhaseVariable {
 public:
  explicit PhaseVariable(PhaseVariableParams params = {}) : params_(params) {}
  const PhaseVariableParams& params() const { return params_; }

  /// Eq. (20). p_com_x0 = COM position at the start of the step, p_com_xf = ε l_des (must differ from p_com_x0).
  /// pddot_com_x is the COM forward acceleration (e.g. λ² p^x on the LIP, Eq. (11)). Throws std::invalid_argument
  /// if p_com_xf == p_com_x0.
  Phase StateBased(double p_com_x, double pdot_com_x, double pddot_com_x, double p_com_x0, double p_com_xf) const;
  /// Sec. VI-D: τ_t = (t − t0)/T_s. Throws std::invalid_argument if T_s <= 0.
  Phase TimeBased(double t, double step_start_time, double step_duration) const;

 private:
  Phase Saturate(Phase phase) const;
  PhaseVariableParams params_;
};

/// Eq. (22): cubic torso pitch with zero slope (in τ) at both ends.
class TorsoPitchCubic {
 public:
  TorsoPitchCubic(double phi_0, double phi_f);
  /// Coefficients c of Eq. (22), φ = [1 τ τ² τ³] c.
  const Eigen::Vector4d& coefficients() const { return c_; }
  /// φ, dφ/dτ, d²φ/dτ².
  ScalarDerivatives Evaluate(double tau) const;

 private:
  Eigen::Vector4d c_;
};

/// A scalar Bézier polynomial of degree M = (number of control points − 1), at most kMaxControlPoints points.
class BezierCurve {
 public:
  static constexpr int kMaxControlPoints = 12;
  BezierCurve() = default;
  /// Throws std::invalid_argument if there are fewer than 2 or more than kMaxControlPoints control points.
  explicit BezierCurve(const Eigen::Ref<const Eigen::VectorXd>& control_points);
  int degree() const { return num_points_ - 1; }
  double control_point(int k) const { return gamma_[k]; }
  void set_control_point(int k, double value) { gamma_[k] = value; }
  /// b(τ), b'(τ), b''(τ) (Bernstein form; derivatives from the forward differences of the control points).
  ScalarDerivatives Evaluate(double tau) const;

 private:
  double gamma_[kMaxControlPoints] = {};
  int num_points_ = 0;
};

enum class SwingApexShape {
  kControlPoints,  ///< Paper, Eq. (24): γ_1 = γ_2 = γ_3 = z_max (the curve peaks somewhat below z_max).
  kExactPeak,      ///< Ours: γ_1..γ_3 chosen so that the maximum of b_v over τ in [0, 1] is exactly z_max.
  /// Ours: kExactPeak, raised where needed so that the foot is at least stance_stone_clearance above the stance
  /// stone wherever it passes over it (|p_sw^x| <= stance_stone_half_length). The paper's curve peaks near τ = 0.5
  /// whatever the step: after a long step followed by a short one, the foot passes over the stance stone late,
  /// already on its way down, and grazes it. γ_1 = γ_2 = γ_3 = c as in the paper, c = max(c of kExactPeak, c that
  /// meets the stance clearance at both edges and, with clear_next_stone_rear_edge, at the next stone's rear edge).
  kClearStanceStone,
};
/// When the swing foot reaches the foothold height h_des along the phase (ours).
enum class SwingTouchdownTiming {
  /// Paper, Eq. (24) as written: b_v(τ). b_v passes h_des at some τ_td < 1 (because of z_sw^neg), so the foot
  /// lands while the COM is still short of ε l_des (about 0.92 of the way for a 0.1 m clearance and a 1 cm
  /// strike depth), not where Eq. (17), (25)-(27) assume the impact happens.
  kPaperPhase,
  /// b_v(τ_td τ): the same curve, re-timed so that it reaches h_des exactly at τ = 1, i.e. when the COM is at
  /// p_comf^{x,d} = ε l_des, the pre-impact position of the impact map (17) and of Eq. (25)-(27). Past τ = 1 (a
  /// late impact) the foot keeps descending at its touchdown speed dz/dτ = τ_td b_v'(τ_td) (the phase is not
  /// saturated for this output), so it always strikes. Eq. (23) (x) is unchanged and reaches l_des at τ = 1.
  kAtPhaseEnd,
};
enum class SwingApexReference {
  kStanceFoot,      ///< Paper: z_max is a height relative to the stance foot.
  kHigherFoothold,  ///< Ours: z_max = max(p_sw0^z, h_des) + clearance (stairs-friendly).
  /// Ours: z_max = max(p_sw0^z, 0, h_des) + clearance: also clears the stance foot's stone, which the swing foot
  /// passes over (on random stones both neighbours can lie below it).
  kHighestStone,
};

struct SwingFootBezierParams {
  double clearance = 0.1;       ///< [m] z_sw^max (the paper gives no number; ours)
  double strike_depth = -0.01;  ///< [m] z_sw^neg < 0: the foot aims this far below the next foothold (ours)
  SwingApexShape apex_shape = SwingApexShape::kControlPoints;
  SwingApexReference apex_reference = SwingApexReference::kStanceFoot;
  SwingTouchdownTiming touchdown_timing = SwingTouchdownTiming::kPaperPhase;
  /// [m] half the length of the stance stone's top, for SwingApexShape::kClearStanceStone (ours; the paper's stones
  /// are 0.1 m long in our terrains).
  double stance_stone_half_length = 0.05;
  /// [m] for SwingApexShape::kClearStanceStone: the least height above the stance stone at its edges, and above the
  /// next stone's top at its rear edge with clear_next_stone_rear_edge (ours).
  double stance_stone_clearance = 0.05;
  /// For SwingApexShape::kClearStanceStone (ours, off by default): the foot is also stance_stone_clearance above the
  /// next stone's top where it crosses that stone's rear edge, x = l_des − stance_stone_half_length (the same
  /// half-length, which includes the sole's; a terrain of mixed stone lengths places the edge by its longest stone).
  /// A line foot's toe reaches half a sole ahead of the foot; on a short step up the next stone's rear face can be
  /// closer than that, and the toe otherwise runs into it. An edge behind the swing foot's start is not checked.
  bool clear_next_stone_rear_edge = false;
  /// [-] τ_a in (0, 1]: Eq. (23) runs on τ / τ_a, so the foot is above the foothold (x = l_des, at rest in x) from
  /// τ = τ_a on and the last part of the swing is a vertical descent. 1 = the paper. Ours: a foot that lags in x on a
  /// short, fast step then still lands on the stone centre instead of its near edge.
  double horizontal_arrival_phase = 1.0;
  /// Ours, off by default (the paper's table under Eq. (24)): the vertical curve's second control point equals its
  /// first, [p_sw0^z, p_sw0^z, c, c, h_des, h_des + z_neg] instead of [p_sw0^z, c, c, c, ...], so the swing foot's
  /// desired vertical velocity at lift-off is 0 like the foot's own (the horizontal curve already starts at rest). For
  /// controllers that correct a velocity error fast (a CLF-QP with a small ε), which otherwise kick the swing leg at
  /// the torque limits at every lift-off. The apex (kExactPeak, kClearStanceStone) is still met by raising c.
  bool lift_off_at_rest = false;
};

/// Eq. (23)-(24): swing foot x and z relative to the stance foot as functions of τ.
class SwingFootBezier {
 public:
  /// Throws std::invalid_argument if strike_depth >= 0, or (kExactPeak) the apex lies below an end point.
  SwingFootBezier(SwingFootBezierParams params, double p_sw0_x, double p_sw0_z, double step_length, double step_height);
  const SwingFootBezierParams& params() const { return params_; }
  const BezierCurve& horizontal() const { return b_h_; }
  const BezierCurve& vertical() const { return b_v_; }
  /// The apex height z_max used for the control points or the exact peak (m).
  double apex_height() const { return apex_; }
  /// Eq. (23): p_sw^x and its τ-derivatives.
  ScalarDerivatives X(double tau) const;
  /// Eq. (24): p_sw^z and its τ-derivatives (for kAtPhaseEnd: b_v(τ_td τ), and linear beyond τ = 1).
  ScalarDerivatives Z(double tau) const;
  /// τ at which p_sw^z comes down through h_des: τ_td of b_v for kPaperPhase (0 if b_v never rises above h_des),
  /// 1 for kAtPhaseEnd.
  double touchdown_phase() const;
  /// max over τ in [0, 1] of p_sw^z, and where (found by sampling and Newton on dp/dτ = 0).
  double MaxHeight(double* tau_at_max = nullptr) const;
  /// τ at which p_sw^x passes x (e.g. an edge of the stance stone), or NaN if the swing does not pass it.
  double CrossingPhase(double x) const;

 private:
  void SetExactPeak();
  double TouchdownParameter() const;  // root of b_v = h_des on the descent (0 if none)
  SwingFootBezierParams params_;
  double p_sw0_x_, step_length_, step_height_;
  BezierCurve b_h_, b_v_;
  double apex_;
  double tau_touchdown_ = 1.0;  // root of b_v(τ) = h_des on the descent
};

/// Per-step constants of the outputs: α_0 (post-impact) and α_f (pre-impact posture, Eq. (21)), the step, and
/// the phase bounds.
struct StepOutputParameters {
  double phi_0 = 0;              ///< [rad] torso pitch at the start of the step
  double phi_f = 0;              ///< [rad] desired pre-impact torso pitch (Eq. (21))
  double p_com_x0 = 0;           ///< [m] COM forward position at the start of the step
  double p_sw0_x = 0;            ///< [m] swing foot at the start of the step
  double p_sw0_z = 0;            ///< [m]
  double step_length = 0.4;      ///< [m] l_des
  double step_height = 0;        ///< [m] h_des
  double impact_fraction = 0.6;  ///< [-] ε, p_comf^{x,d} = ε l_des
  double step_start_time = 0;    ///< [s] t_0 (time-based phase)
  double step_duration = 0.4;    ///< [s] T_s from Eq. (27) at the start of the step (time-based phase)
};

/// Y_d, Ẏ_d, Ÿ_d of Eq. (19) in the order [φ_torso, p_com^z, p_sw^x, p_sw^z].
struct DesiredOutputs {
  Eigen::Vector4d y = Eigen::Vector4d::Zero();
  Eigen::Vector4d ydot = Eigen::Vector4d::Zero();
  Eigen::Vector4d yddot = Eigen::Vector4d::Zero();
  Phase phase;
};

/// Eq. (19): all desired outputs of one step.
class SteppingStonesOutputTrajectories {
 public:
  SteppingStonesOutputTrajectories(PhaseVariableParams phase_params, SwingFootBezierParams swing_params,
                                   const StepOutputParameters& step);
  const StepOutputParameters& step() const { return step_; }
  const SwingFootBezier& swing_foot() const { return swing_; }
  const TorsoPitchCubic& torso() const { return torso_; }
  /// The phase from the COM forward state (state-based) or the time (time-based).
  Phase CalcPhase(double t, double p_com_x, double pdot_com_x, double pddot_com_x) const;
  /// Y_d and its time derivatives; com_height_desired = [p^{z,d}, ṗ^{z,d}, p̈^{z,d}] from the MPC.
  DesiredOutputs Evaluate(double t, double p_com_x, double pdot_com_x, double pddot_com_x,
                          const Eigen::Vector3d& com_height_desired) const;

 private:
  PhaseVariable phase_;
  PhaseVariable raw_phase_;  // unsaturated, for the swing foot past τ = 1 (SwingTouchdownTiming::kAtPhaseEnd)
  StepOutputParameters step_;
  TorsoPitchCubic torso_;
  SwingFootBezier swing_;
};

}  // namespace rome
