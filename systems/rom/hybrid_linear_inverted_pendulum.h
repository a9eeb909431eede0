#pragma once
// HybridLinearInvertedPendulum (H-LIP): the lateral reduced-order model of the walking paper (Sec. III-B, Eq. (6)-(8))
// with the step-to-step results of its ref [14] (Xiong & Ames, IROS 2019) collected in spec §2.2, and the footed
// H-LIP of Sec. IV-B with its exact zero-order-hold discretisation (spec §3.3 [R], replacing Eq. (11)-(13)).
// Pure math: no framework dependency (the block is HybridLinearInvertedPendulumSystem).
//
// Conventions: y [m] is the mass position relative to the stance foot (+y = left), ẏ [m/s]; z0 fixed, λ = sqrt(g/z0).
//   SSP: ÿ = λ² y.  DSP: ÿ = 0.  Switching is time based (T_SSP, T_DSP).
//   Eq. (6) SSP→DSP: identity.  Eq. (7) DSP→SSP: y⁺ = y⁻ − w, ẏ⁺ = ẏ⁻, w = signed offset old stance → new stance foot.
//   Pre-impact state x = (p, v) at the end of SSP. Step to step: x_{k+1} = A x_k + B w_k with
//     A = e^{A_s T_SSP} [[1, T_DSP], [0, 1]],  B = −[cosh(λ T_SSP); λ sinh(λ T_SSP)].
//   Eq. (8): σ2 = λ tanh(λ T_SSP / 2) (P2 orbits, v = σ2 p); σ1 = λ coth(λ T_SSP / 2) (P1 orbits, ref [14]).
//   Deadbeat stepping (ref [14], library only; the paper plans footholds open loop): w = w* + K (x − x*),
//     K = [1, T_DSP + coth(λ T_SSP)/λ], so that (A + B K)² = 0.
// Footed H-LIP (Sec. IV-B): SSP ÿ = λ² y + u/(m z0), DSP ÿ = (u_L + u_R)/(m z0), u the ankle roll torque.
#include <Eigen/Core>

namespace rome {

struct HybridLinearInvertedPendulumParams {
  double z0 = 0.9;            ///< [m] mass height (the mean aSLIP height, spec §2.2)
  double ssp_duration = 0.4;  ///< [s] T_SSP (gait A, spec §3.1 [R])
  double dsp_duration = 0.1;  ///< [s] T_DSP (gait A, spec §3.1 [R]); may be 0
  double gravity = 9.81;      ///< [m/s²]
};

class HybridLinearInvertedPendulum {
 public:
  /// Throws std::invalid_argument naming the parameter unless z0 > 0, T_SSP > 0, T_DSP >= 0, g > 0 (all finite).
  explicit HybridLinearInvertedPendulum(HybridLinearInvertedPendulumParams params = {});
  const HybridLinearInvertedPendulumParams& params() const { return params_; }

  double lambda() const { return lambda_; }  ///< [1/s] sqrt(g / z0)
  double sigma1() const;                     ///< [1/s] λ coth(λ T_SSP / 2), slope of P1 orbits
  double sigma2() const;                     ///< [1/s] λ tanh(λ T_SSP / 2), Eq. (8), slope of P2 orbits

  /// e^{A_s t} of the SSP flow ÿ = λ² y.
  Eigen::Matrix2d SingleSupportTransition(double t) const;
  /// Step-to-step matrices (pre-impact to pre-impact).
  Eigen::Matrix2d StepToStepA() const;
  Eigen::Vector2d StepToStepB() const;
  /// Deadbeat gain K of w = w* + K (x − x*).
  Eigen::RowVector2d DeadbeatGain() const;

  /// P1 orbit with constant step w: pre-impact (p, v) with v = σ1 p and w = 2p + T_DSP v.
  Eigen::Vector2d P1PreImpactState(double step) const;
  /// Symmetric P2 orbit (mean step 0) with foot separation step_width > 0: the pre-impact state at the end of a
  /// left stance, p = −W/(2 + T_DSP σ2), v = σ2 p (a right stance ends at −(p, v)).
  Eigen::Vector2d P2PreImpactState(double step_width) const;
  /// The step w = 2p + T_DSP v that a pre-impact state on a P2 line with mean step 0 takes.
  double P2Step(const Eigen::Vector2d& pre_impact) const;

 private:
  HybridLinearInvertedPendulumParams params_;
  double lambda_;
};

/// One-step discretisation Y⁺ = A Y + B u of the footed H-LIP over a zero-order-hold interval T [s].
struct FootedLinearInvertedPendulumStep {
  Eigen::Matrix2d A;
  Eigen::Vector2d B;
};

/// Exact ZOH of the footed H-LIP (spec §3.3 [R], the corrected Eq. (11)-(13)).
///   SSP: A = e^{A_s T}, B = [(cosh λT − 1)/(λ² m z0); sinh λT/(λ m z0)] for ÿ = λ² y + u/(m z0).
///   DSP: A = [[1, T], [0, 1]], B = [T²/(2 m z0); T/(m z0)] for ÿ = u/(m z0) (the paper's P).
/// Throws std::invalid_argument unless T >= 0, mass > 0, z0 > 0, λ > 0.
FootedLinearInvertedPendulumStep FootedLinearInvertedPendulumDiscretization(double lambda, double T, double mass,
                                                                            double z0, bool single_support);

}  // namespace rome
