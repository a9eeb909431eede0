#pragma once
// MomentumRegulationPlanner: the step-level planner of the stepping-stones paper (Sec. IV-2), pure math.
// Conventions as in systems/rom/linear_inverted_pendulum.h: planar x forward, z up, positions relative to
// the stance foot, L_y the mass-normalised angular momentum about the stance foot [m²/s] (L_y > 0 walking
// forward), next foothold at (l_des, h_des) relative to the stance foot.
//
// Equations (paper numbering):
//   Eq. (17)  impact map: p^{x+} = p^{x−} − l,  L⁺ = L⁻ + l u − h ṗ^{x−}   (u = ṗ^{z−}, pre-impact vertical velocity)
//   Eq. (18)  u_des = (L_des − L⁻ + h ṗ^{x−}) / l
//   L_des (unnumbered, after Eq. (24)): post-impact orbital energy E⁺ = (L_des/z0⁺)² − λ⁺² (p^{x+})² = E* with
//             p^{x+} = (ε − 1) l,  z0⁺ = p^{z−} − h − (h/l) p^{x+} (slope-adjusted height after impact),
//             λ⁺ = sqrt(g / z0⁺)  =>  L_des = z0⁺ sqrt(E* + λ⁺² (p^{x+})²).
//             p^{z−} is the desired pre-impact COM height p_comf^{z,d} or the current p^z (paper allows both;
//             PreImpactHeightSource selects).
//   Eq. (25)  L̂⁻ = sqrt(ẑ0 g ((ε l)² − (p^x)²) + L_y²)   (LIP energy conservation to x = ε l)
//   Eq. (26)  u_des(t) = (L_des − L̂⁻ + h ṗ^x) / l        (current ṗ^x stands in for ṗ^{x−}, as in the paper)
//   Eq. (27)  T̂_s = T_I(ε l, ẑ0, p^x, L_y),  ẑ0 = p^z − (h/l) p^x
// We use the slope-adjusted ẑ0 of Eq. (27) in Eq. (25) as well, so both predictions use one LIP.

#include <cstdint>
#include <limits>
#include <string>

#include "systems/rom/linear_inverted_pendulum.h"

namespace rome {

enum class PreImpactHeightSource {
  kDesiredPreImpactHeight,  ///< p^{z−} = p_comf^{z,d} (constant within a step; from the pre-impact posture Eq. (21))
  kCurrentHeight,           ///< p^{z−} = current p_com^z
};

struct MomentumRegulationPlannerParams {
  /// [m²/s²] E*: desired post-impact orbital energy, Eq. (16). Paper: 0.5 (random stones), 0.3 (Fig. 6(a)).
  double target_orbital_energy = 0.5;
  /// [-] ε: desired pre-impact COM position p_comf^{x,d} = ε l_des. Paper: 0.6.
  double impact_fraction = 0.6;
  double gravity = 9.81;  ///< [m/s²]
  PreImpactHeightSource pre_impact_height_source = PreImpactHeightSource::kDesiredPreImpactHeight;
  /// [s] T̂_s is clamped to [min, max] (ours; the paper gives none). When Eq. (14) has no root t >= 0 because
  /// the COM already passed ε l, T̂_s = min; when the orbit lacks energy to reach ε l, T̂_s = max.
  double min_time_to_impact_s = 0.02;
  double max_time_to_impact_s = 2.0;
  /// [m/s] u_des is at least this (ours; the paper: no bound, −∞). Eq. (26) sheds momentum at an impact only through
  /// l u, so a short step after a fast one asks for a steep fall (u_des down to −2.8 m/s on AMBER's random courses);
  /// bounded, the excess momentum is shed over the next steps instead (kPreImpactVelocityClamped).
  double min_pre_impact_vertical_velocity_mps = -std::numeric_limits<double>::infinity();
};

/// Current robot (or ROM) state relative to the stance foot, and the next step.
struct MomentumRegulationInput {
  double p_com_x = 0;                ///< [m]
  double p_com_z = 0;                ///< [m]
  double pdot_com_x = 0;             ///< [m/s]
  double L_y = 0;                    ///< [m²/s] about the stance foot
  double step_length = 0;            ///< [m] l_des > 0
  double step_height = 0;            ///< [m] h_des
  double pre_impact_com_height = 0;  ///< [m] p_comf^{z,d}, relative to the current stance foot
};

struct MomentumRegulationPlan {
  /// Bits of `status`.
  enum StatusBit : std::uint32_t {
    kOk = 0,
    kPreImpactMomentumClamped = 1u << 0,        ///< Eq. (25) radicand < 0 (cannot reach ε l): L̂⁻ set to 0.
    kTimeToImpactInsufficientEnergy = 1u << 1,  ///< Eq. (14) has no real root: T̂ = max.
    kTimeToImpactPassed = 1u << 2,              ///< ε l reached only backwards in time: T̂ = min.
    kTimeToImpactClamped = 1u << 3,             ///< T̂ was outside [min, max].
    kPreImpactVelocityClamped = 1u << 4,        ///< Eq. (26) asked for less than min_pre_impact_vertical_velocity_mps.
  };
  double L_des = 0;                  ///< [m²/s] desired post-impact momentum
  double L_pre_impact = 0;           ///< [m²/s] L̂⁻, Eq. (25)
  double u_des = 0;                  ///< [m/s] desired pre-impact vertical COM velocity, Eq. (26)
  double time_to_impact = 0;         ///< [s] T̂_s, Eq. (27), after clamping
  double time_to_impact_raw = 0;     ///< [s] T_I before clamping (0 if no root)
  double slope_adjusted_height = 0;  ///< [m] ẑ0 = p^z − (h/l) p^x
  double post_impact_height = 0;     ///< [m] z0⁺
  double pre_impact_position = 0;    ///< [m] ε l
  std::uint32_t status = kOk;
  bool ok() const { return status == kOk; }
};

class MomentumRegulationPlanner {
 public:
  /// Throws std::invalid_argument naming the parameter if a parameter is out of range.
  explicit MomentumRegulationPlanner(MomentumRegulationPlannerParams params = {});
  const MomentumRegulationPlannerParams& params() const { return params_; }

  /// The full plan. Throws std::invalid_argument (naming the value) if l_des <= 0, ẑ0 <= 0 or z0⁺ <= 0, or
  /// an input is not finite. Allocation-free on success.
  MomentumRegulationPlan Plan(const MomentumRegulationInput& in) const;

  /// L_des for a step (l, h) and pre-impact COM height p^{z−} (see the header comment).
  double DesiredPostImpactMomentum(double step_length, double step_height, double pre_impact_com_height) const;
  /// Eq. (25). Returns the radicand's square root, or 0 with *clamped = true when the radicand is negative.
  static double PredictPreImpactMomentum(double p_com_x, double L_y, double z0_hat, double pre_impact_position,
                                         double gravity, bool* clamped);
  /// Eq. (18)/(26).
  static double DesiredPreImpactVerticalVelocity(double step_length, double step_height, double L_des,
                                                 double L_pre_impact, double pdot_com_x_pre_impact);
  /// Eq. (17): post-impact (p^x, L) from the pre-impact values.
  static Eigen::Vector2d ImpactMap(double p_com_x_pre, double L_pre, double pdot_com_x_pre, double pdot_com_z_pre,
                                   double step_length, double step_height);

 private:
  MomentumRegulationPlannerParams params_;
};

}  // namespace rome
