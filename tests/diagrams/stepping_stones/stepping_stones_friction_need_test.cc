// CalcPeriodicPlanFrictionNeed against closed forms on flat steps:
// the LIP orbit of energy E (E = ṗx² − λ² px², λ² = g / z0) is px(t) = (√E/λ) sinh(λ t + asinh(λ px⁺/√E)), the
// momentum map gives u_des = z0 (√(E + λ²((1−ε) l)²) − √(E + λ²(ε l)²)) / l, and the smallest Σ u_k² that brings ṗz
// from 0 to u_des and pz back to its start over N equal intervals is linear in the interval midpoints t_k (the
// minimum-norm solution lies in the span of the two constraint rows), u_k = α + β t_k, whose coefficients follow from
// the midpoint moments Σ dt = T, Σ dt t_k = T²/2, Σ dt t_k² = T³/3 − T dt²/12. The force on the robot in single stance
// is m (p̈ + g e_z), so |F_t|/F_n = λ² |px| / (g + u_k).
#include "diagrams/stepping_stones/stepping_stones_friction_need.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace rome {
namespace {

constexpr double kG = 9.81, kZ0 = 0.8, kL = 0.8;  // AMBER's walking height, the 0.8 m steps

struct ClosedForm {
  double T, u_des, ratio_at_last_sample;
};

// The closed form above for flat steps of length kL, sampled like CalcPeriodicPlanFrictionNeed (n samples, N = 20).
ClosedForm Flat(double energy, double eps, int n = 400, int N = 20) {
  const double lam = std::sqrt(kG / kZ0), se = std::sqrt(energy);
  const double x_plus = (eps - 1.0) * kL, x_minus = eps * kL;
  ClosedForm c;
  c.T = (std::asinh(lam * x_minus / se) - std::asinh(lam * x_plus / se)) / lam;
  c.u_des =
      kZ0 * (std::sqrt(energy + lam * lam * x_plus * x_plus) - std::sqrt(energy + lam * lam * x_minus * x_minus)) / kL;
  const double T = c.T, dt = T / N, s2 = T * T * T / 3.0 - T * dt * dt / 12.0;
  // α T + β T²/2 = u_des;  α T²/2 + β (T³/2 − s2) = 0  (Σ dt (T − t_k) u_k = p_N − p_0 − T ṗ_0 = 0)
  const double det = T * (T * T * T / 2.0 - s2) - T * T / 2.0 * T * T / 2.0;
  const double alpha = c.u_des * (T * T * T / 2.0 - s2) / det, beta = -c.u_des * (T * T / 2.0) / det;
  const double t = T * (n - 0.5) / n, u_last = alpha + beta * (T - dt / 2.0);
  const double x = se / lam * std::sinh(lam * t + std::asinh(lam * x_plus / se));
  c.ratio_at_last_sample = lam * lam * std::abs(x) / (kG + u_last);
  return c;
}

PlanFrictionNeed Need(double energy, double eps) {
  MomentumRegulationPlannerParams p;
  p.target_orbital_energy = energy;
  p.impact_fraction = eps;
  return CalcPeriodicPlanFrictionNeed(kL, 0.0, kZ0, p, {});
}

TEST(PlanFrictionNeed, HalfStepImpactNeedsNoVerticalMotionAndTheLegsSlope) {
  // ε = 0.5 on flat steps: the orbit is symmetric, u_des = 0, the COM stays level (F_n = m g), and the largest
  // |F_t|/F_n = λ² |px| / g = px / z0 is at the step's ends, l / (2 z0) = 0.5.
  for (const double energy : {0.3, 1.0, 2.0}) {
    const PlanFrictionNeed n = Need(energy, 0.5);
    const ClosedForm c = Flat(energy, 0.5);
    EXPECT_NEAR(n.u_des_mps, 0.0, 1e-12) << energy;
    EXPECT_NEAR(n.min_normal_force_fraction, 1.0, 1e-9) << energy;
    EXPECT_NEAR(n.step_duration_s, c.T, 1e-6) << energy;
    EXPECT_NEAR(n.mean_speed_mps, kL / c.T, 1e-5) << energy;
    EXPECT_NEAR(n.max_ratio, c.ratio_at_last_sample, 1e-6) << energy;
    // The last sample is half a sample period (T / 800) inside the step's end, where px moves at most at the end speed.
    const double end_speed = std::sqrt(energy + kG / kZ0 * kL * kL / 4);
    EXPECT_LE(n.max_ratio, kL / (2 * kZ0)) << energy;
    EXPECT_GE(n.max_ratio, (kL / 2 - end_speed * c.T / 800) / kZ0) << energy;
  }
}

TEST(PlanFrictionNeed, PaperImpactFractionMatchesTheClosedForm) {
  // ε = 0.6 (paper): u_des < 0, the vertical plan pushes up, then accelerates down hardest at the impact, where px is
  // largest: the need peaks in the last sample. The −g bound is not active for these E*.
  for (const double energy : {0.3, 0.5, 0.8, 1.0, 1.5}) {
    const PlanFrictionNeed n = Need(energy, 0.6);
    const ClosedForm c = Flat(energy, 0.6);
    EXPECT_NEAR(n.step_duration_s, c.T, 1e-6) << energy;
    EXPECT_NEAR(n.u_des_mps, c.u_des, 1e-9) << energy;
    EXPECT_NEAR(n.max_ratio, c.ratio_at_last_sample, 1e-6) << energy;
    EXPECT_NEAR(n.time_of_max_s, c.T * (399.5 / 400), 1e-6) << energy;
  }
}

TEST(PlanFrictionNeed, NeedGrowsWithEnergyAtThePapersImpactFractionAndCrossesMu) {
  // The measurement of docs/stepping-stones.md: at ε = 0.6 on flat 0.8 m steps the plan asks AMBER's μ = 0.8 from
  // E* ≈ 0.62 on (the closed form's crossing, by bisection); at ε = 0.5 it asks l / (2 z0) = 0.5 at any E*.
  double lo = 0.1, hi = 2.0;
  for (int i = 0; i < 60; ++i) (Flat(0.5 * (lo + hi), 0.6).ratio_at_last_sample <= 0.8 ? lo : hi) = 0.5 * (lo + hi);
  EXPECT_LE(Need(lo * 0.999, 0.6).max_ratio, 0.8);
  EXPECT_GT(Need(lo * 1.001, 0.6).max_ratio, 0.8);
  EXPECT_NEAR(lo, 0.62, 0.01);
  EXPECT_LT(Need(2.0, 0.5).max_ratio, 0.5);
}

TEST(PlanFrictionNeed, BadInputIsRefused) {
  EXPECT_THROW(CalcPeriodicPlanFrictionNeed(0.0, 0.0, kZ0, {}, {}), std::invalid_argument);
  EXPECT_THROW(CalcPeriodicPlanFrictionNeed(kL, 0.0, kZ0, {}, {}, 0), std::invalid_argument);
}

}  // namespace
}  // namespace rome
