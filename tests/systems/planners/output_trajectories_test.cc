// Output trajectories, Eq. (19)-(24): Bézier end-point and derivative conditions, exact apex, torso cubic
// against Eq. (22) solved numerically, derivatives against finite differences, chain rule through τ̇.
#include "systems/planners/output_trajectories.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>

#include <Eigen/Dense>

namespace rome {
namespace {

// Central finite differences of f at x.
ScalarDerivatives FiniteDifferences(const std::function<double(double)>& f, double x, double h = 1e-4) {
  return {f(x), (f(x + h) - f(x - h)) / (2 * h), (f(x + h) - 2 * f(x) + f(x - h)) / (h * h)};
}

TEST(OutputTrajectories, BezierDerivativesMatchFiniteDifferences) {
  const BezierCurve b((Eigen::VectorXd(6) << 0.02, 0.3, -0.1, 0.25, 0.1, 0.05).finished());
  for (double tau = 0.05; tau < 1.0; tau += 0.1) {
    const ScalarDerivatives exact = b.Evaluate(tau);
    const ScalarDerivatives fd = FiniteDifferences([&](double s) { return b.Evaluate(s).value; }, tau);
    EXPECT_NEAR(exact.first, fd.first, 1e-6);  // central differences: O(h²) = 1e-8 × |b'''|
    EXPECT_NEAR(exact.second, fd.second, 1e-5);
  }
  // Bernstein form against the explicit sum Σ γ_k C(5,k) τ^k (1−τ)^{5−k}.
  const double gamma[6] = {0.02, 0.3, -0.1, 0.25, 0.1, 0.05}, binomial[6] = {1, 5, 10, 10, 5, 1};
  for (double tau : {0.0, 0.3, 0.77, 1.0}) {
    double sum = 0;
    for (int k = 0; k < 6; ++k) sum += gamma[k] * binomial[k] * std::pow(tau, k) * std::pow(1 - tau, 5 - k);
    EXPECT_NEAR(b.Evaluate(tau).value, sum, 1e-15);
  }
  EXPECT_THROW(BezierCurve(Eigen::VectorXd::Zero(1)), std::invalid_argument);
}

TEST(OutputTrajectories, SwingFootEndPointsAndDerivatives) {
  const double p_sw0_x = -0.35, p_sw0_z = 0.0, l = 0.45, h = 0.15;
  SwingFootBezierParams params;
  params.clearance = 0.2;
  params.strike_depth = -0.02;
  const SwingFootBezier swing(params, p_sw0_x, p_sw0_z, l, h);
  // Eq. (23): x from p_sw0^x to l_des with zero velocity and acceleration in τ at both ends (γ = [0,0,0,1,1,1]).
  EXPECT_DOUBLE_EQ(swing.X(0).value, p_sw0_x);
  EXPECT_DOUBLE_EQ(swing.X(1).value, l);
  for (double tau : {0.0, 1.0}) {
    EXPECT_NEAR(swing.X(tau).first, 0.0, 1e-14);
    EXPECT_NEAR(swing.X(tau).second, 0.0, 1e-13);
  }
  // Eq. (24): z from p_sw0^z to h + z_neg (below the foothold: the foot strikes), descending at impact with
  // dz/dτ = 5 z_neg; lifting off with dz/dτ = 5 (z_max − p_sw0^z).
  EXPECT_DOUBLE_EQ(swing.Z(0).value, p_sw0_z);
  EXPECT_DOUBLE_EQ(swing.Z(1).value, h - 0.02);
  EXPECT_LT(swing.Z(1).value, h);
  EXPECT_NEAR(swing.Z(1).first, 5 * -0.02, 1e-14);
  EXPECT_NEAR(swing.Z(0).first, 5 * (0.2 - p_sw0_z), 1e-14);
  // Second derivatives at the ends: 20 (γ_2 − 2γ_1 + γ_0) and 20 (γ_5 − 2γ_4 + γ_3).
  EXPECT_NEAR(swing.Z(0).second, 20 * (0.2 - 2 * 0.2 + p_sw0_z), 1e-13);
  EXPECT_NEAR(swing.Z(1).second, 20 * ((h - 0.02) - 2 * h + 0.2), 1e-13);
  // Derivatives against finite differences in the interior.
  for (double tau = 0.05; tau < 1.0; tau += 0.15) {
    const ScalarDerivatives fx = FiniteDifferences([&](double s) { return swing.X(s).value; }, tau);
    const ScalarDerivatives fz = FiniteDifferences([&](double s) { return swing.Z(s).value; }, tau);
    EXPECT_NEAR(swing.X(tau).first, fx.first, 1e-6);
    EXPECT_NEAR(swing.X(tau).second, fx.second, 1e-5);
    EXPECT_NEAR(swing.Z(tau).first, fz.first, 1e-6);
    EXPECT_NEAR(swing.Z(tau).second, fz.second, 1e-5);
  }
  // The paper's control-point apex stays below z_max (convex hull property) and above the end points.
  const double peak = swing.MaxHeight();
  EXPECT_LT(peak, 0.2);
  EXPECT_GT(peak, h);
  SwingFootBezierParams bad = params;
  bad.strike_depth = 0.0;
  EXPECT_THROW(SwingFootBezier(bad, p_sw0_x, p_sw0_z, l, h), std::invalid_argument);
}

TEST(OutputTrajectories, ExactApexReachesTheClearance) {
  for (const auto& [p0, h] : {std::pair{0.0, 0.0}, std::pair{0.0, 0.2}, std::pair{0.1, -0.15}}) {
    SwingFootBezierParams params;
    params.clearance = 0.08;
    params.apex_shape = SwingApexShape::kExactPeak;
    params.apex_reference = SwingApexReference::kHigherFoothold;
    const SwingFootBezier swing(params, -0.3, p0, 0.4, h);
    const double apex = std::max(p0, h) + 0.08;
    EXPECT_DOUBLE_EQ(swing.apex_height(), apex);
    double tau_max = 0;
    const double peak = swing.MaxHeight(&tau_max);
    EXPECT_NEAR(peak, apex, 1e-12) << "p0 = " << p0 << ", h = " << h;
    // It is a true interior maximum: zero slope, negative curvature, and no sample above it.
    EXPECT_NEAR(swing.Z(tau_max).first, 0.0, 1e-9);
    EXPECT_LT(swing.Z(tau_max).second, 0.0);
    for (int k = 0; k <= 1000; ++k) EXPECT_LE(swing.Z(k / 1000.0).value, apex + 1e-12);
    // End points are unchanged by the apex fit.
    EXPECT_DOUBLE_EQ(swing.Z(0).value, p0);
    EXPECT_DOUBLE_EQ(swing.Z(1).value, h + params.strike_depth);
  }
  SwingFootBezierParams too_low;
  too_low.clearance = 0.05;
  too_low.apex_shape = SwingApexShape::kExactPeak;  // relative to the stance foot, below a 0.2 m foothold
  EXPECT_THROW(SwingFootBezier(too_low, -0.3, 0.0, 0.4, 0.2), std::invalid_argument);
}

TEST(OutputTrajectories, LiftOffAtRestStartsWithZeroVerticalVelocityAndKeepsTheApex) {
  for (const auto shape : {SwingApexShape::kExactPeak, SwingApexShape::kClearStanceStone}) {
    SwingFootBezierParams params;
    params.clearance = 0.1;
    params.apex_shape = shape;
    params.apex_reference = SwingApexReference::kHighestStone;
    params.touchdown_timing = SwingTouchdownTiming::kAtPhaseEnd;
    params.stance_stone_half_length = 0.16;
    const SwingFootBezier paper(params, -0.3, -0.1, 0.35, 0.15);
    params.lift_off_at_rest = true;
    const SwingFootBezier rest(params, -0.3, -0.1, 0.35, 0.15);
    EXPECT_GT(paper.Z(0).first, 0.1);          // the paper's curve starts rising at once
    EXPECT_NEAR(rest.Z(0).first, 0.0, 1e-12);  // ours starts at rest
    EXPECT_DOUBLE_EQ(rest.Z(0).value, -0.1);
    EXPECT_NEAR(rest.Z(1).value, 0.15, 1e-9);  // kAtPhaseEnd: the foothold height at τ = 1
    EXPECT_GE(rest.MaxHeight(), 0.25 - 1e-9);  // the apex is still reached
    if (shape == SwingApexShape::kExactPeak) { EXPECT_NEAR(rest.MaxHeight(), 0.25, 1e-9); }
    // kClearStanceStone: at least stance_stone_clearance above the stance stone wherever the foot passes over it.
    for (int k = 0; k <= 1000; ++k) {
      const double tau = k / 1000.0, x = rest.X(tau).value;
      if (std::abs(x) <= 0.16 && shape == SwingApexShape::kClearStanceStone) {
        EXPECT_GE(rest.Z(tau).value, params.stance_stone_clearance - 1e-9) << "tau " << tau;
      }
    }
  }
}

TEST(OutputTrajectories, TouchdownAtPhaseEndRetimesTheSwingCurve) {
  // kAtPhaseEnd: the same Eq. (24) curve b_v(τ_td τ), reaching h_des exactly at τ = 1 (COM at ε l_des), descending,
  // and continuing straight down past τ = 1. Eq. (23) still reaches l_des at τ = 1.
  for (const auto& [p0, h] : {std::pair{0.0, 0.0}, std::pair{0.0, 0.2}, std::pair{0.1, -0.15}}) {
    SwingFootBezierParams paper;
    paper.apex_reference = SwingApexReference::kHigherFoothold;
    SwingFootBezierParams retimed = paper;
    retimed.touchdown_timing = SwingTouchdownTiming::kAtPhaseEnd;
    const SwingFootBezier a(paper, -0.3, p0, 0.4, h), b(retimed, -0.3, p0, 0.4, h);
    const double tau_td = a.touchdown_phase();
    EXPECT_GT(tau_td, 0.5);
    EXPECT_LT(tau_td, 1.0);
    EXPECT_NEAR(a.Z(tau_td).value, h, 1e-12);  // the paper's curve lands early, at τ_td
    EXPECT_LT(a.Z(tau_td).first, 0.0);
    EXPECT_DOUBLE_EQ(b.touchdown_phase(), 1.0);
    EXPECT_NEAR(b.Z(1.0).value, h, 1e-12);
    EXPECT_NEAR(b.Z(1.0).first, tau_td * a.Z(tau_td).first, 1e-12);
    EXPECT_DOUBLE_EQ(b.Z(0.0).value, p0);
    EXPECT_DOUBLE_EQ(b.X(1.0).value, 0.4);
    for (double tau = 0.05; tau < 1.0; tau += 0.15) {
      EXPECT_NEAR(b.Z(tau).value, a.Z(tau_td * tau).value, 1e-15);
      const ScalarDerivatives fd = FiniteDifferences([&](double s) { return b.Z(s).value; }, tau);
      EXPECT_NEAR(b.Z(tau).first, fd.first, 1e-6);
      EXPECT_NEAR(b.Z(tau).second, fd.second, 1e-5);
      if (tau > 0.5) {
        EXPECT_GT(b.Z(tau).value, h);  // on the way down: above the foothold until τ = 1
      }
    }
    // Past τ = 1 (late impact): a straight line with the touchdown slope, x held at l_des.
    const ScalarDerivatives late = b.Z(1.2);
    EXPECT_NEAR(late.value, h + 0.2 * b.Z(1.0).first, 1e-12);
    EXPECT_NEAR(late.first, b.Z(1.0).first, 1e-15);
    EXPECT_EQ(late.second, 0.0);
    EXPECT_DOUBLE_EQ(b.X(1.2).value, 0.4);
  }
  // The full outputs use the unsaturated phase for the swing height past τ = 1 only.
  StepOutputParameters step;
  step.p_com_x0 = -0.16;
  step.p_sw0_x = -0.4;
  SwingFootBezierParams swing;
  swing.touchdown_timing = SwingTouchdownTiming::kAtPhaseEnd;
  const SteppingStonesOutputTrajectories outputs({.type = PhaseType::kStateBased, .saturate = true}, swing, step);
  const DesiredOutputs late = outputs.Evaluate(0.0, 0.28, 0.8, 0.0, Eigen::Vector3d(0.8, 0, 0));  // τ = 1.1
  EXPECT_DOUBLE_EQ(late.phase.tau, 1.0);
  EXPECT_NEAR(late.y[3], outputs.swing_foot().Z(1.1).value, 1e-12);
  EXPECT_LT(late.y[3], step.step_height);
  EXPECT_NEAR(late.ydot[3], outputs.swing_foot().Z(1.1).first * 0.8 / 0.4, 1e-12);  // τ̇ = ṗx / (ε l − p_com0)
}

TEST(OutputTrajectories, HorizontalArrivalPhaseReachesTheFootholdEarlyAndSmoothly) {
  // Eq. (23) on τ / τ_a: x = l_des with zero velocity and acceleration from τ_a on; before, the paper's curve at τ /
  // τ_a (value equal, derivatives scaled by 1/τ_a and 1/τ_a²), checked against central differences.
  SwingFootBezierParams paper, early;
  early.horizontal_arrival_phase = 0.8;
  const SwingFootBezier a(paper, -0.3, 0.0, 0.4, -0.1), b(early, -0.3, 0.0, 0.4, -0.1);
  for (double tau : {0.8, 0.9, 1.0}) {
    EXPECT_DOUBLE_EQ(b.X(tau).value, 0.4);
    EXPECT_EQ(b.X(tau).first, 0.0);
    EXPECT_EQ(b.X(tau).second, 0.0);
  }
  for (double tau : {0.1, 0.3, 0.5, 0.7, 0.79}) {
    EXPECT_NEAR(b.X(tau).value, a.X(tau / 0.8).value, 1e-15);
    const double h = 1e-6;
    EXPECT_NEAR(b.X(tau).first, (b.X(tau + h).value - b.X(tau - h).value) / (2 * h), 1e-6);
    EXPECT_NEAR(b.X(tau).second, (b.X(tau + h).first - b.X(tau - h).first) / (2 * h), 1e-5);
  }
  EXPECT_NEAR(b.X(0.8 - 1e-9).value, 0.4, 1e-8);  // continuous at τ_a, with zero slope
  EXPECT_NEAR(b.X(0.8 - 1e-6).first, 0.0, 1e-5);
  EXPECT_EQ(b.Z(0.5).value, a.Z(0.5).value);  // the vertical curve is unchanged
  early.horizontal_arrival_phase = 0.0;
  EXPECT_THROW(SwingFootBezier(early, -0.3, 0.0, 0.4, -0.1), std::invalid_argument);
}

TEST(OutputTrajectories, ClearStanceStoneRaisesTheCurveWhereTheFootPassesOverTheStanceStone) {
  // After a long step up and before a short step down (start 0.52 m behind and 0.15 m below the stance foot, next stone
  // 0.21 m ahead and 0.23 m below), the paper-shaped curve peaks early and passes over the stance stone on its way
  // down; kClearStanceStone keeps the paper's family (γ_1 = γ_2 = γ_3) but raises it so that the foot is at least
  // stance_stone_clearance (5 cm) above the stance stone (|x| <= 0.05 m). On a symmetric step it changes nothing.
  SwingFootBezierParams exact, clear;
  exact.touchdown_timing = clear.touchdown_timing = SwingTouchdownTiming::kAtPhaseEnd;
  exact.apex_reference = clear.apex_reference = SwingApexReference::kHighestStone;
  exact.apex_shape = SwingApexShape::kExactPeak;
  clear.apex_shape = SwingApexShape::kClearStanceStone;
  const SwingFootBezier e(exact, -0.52, -0.15, 0.21, -0.23), c(clear, -0.52, -0.15, 0.21, -0.23);
  auto height_over_stone = [](const SwingFootBezier& b) {
    double lowest = INFINITY;
    for (int k = 0; k <= 10000; ++k) {
      const double tau = k / 10000.0;
      if (std::abs(b.X(tau).value) <= 0.05) lowest = std::min(lowest, b.Z(tau).value);
    }
    return lowest;
  };
  std::printf("  lowest height over the stance stone: exact peak %.4f m, clear stance stone %.4f m (required %.2f m)\n",
              height_over_stone(e), height_over_stone(c), clear.stance_stone_clearance);
  EXPECT_LT(height_over_stone(e), 0.01);  // the failure this shape fixes: the foot grazes the stance stone
  EXPECT_NEAR(height_over_stone(c), clear.stance_stone_clearance, 1e-3);  // raised just enough (sampled at 1e-4 in τ)
  EXPECT_GE(height_over_stone(c), clear.stance_stone_clearance - 1e-6);
  EXPECT_EQ(c.vertical().control_point(1), c.vertical().control_point(2));
  EXPECT_EQ(c.vertical().control_point(2), c.vertical().control_point(3));
  EXPECT_NEAR(c.Z(1.0).value, -0.23, 1e-9);  // still lands at h_des at τ = 1
  EXPECT_NEAR(c.X(1.0).value, 0.21, 1e-12);
  // Symmetric step: the crossing is mid-swing, near the 0.1 m peak; the curve is the exact-peak one.
  const SwingFootBezier es(exact, -0.4, 0.0, 0.4, 0.0), cs(clear, -0.4, 0.0, 0.4, 0.0);
  EXPECT_GE(height_over_stone(cs), clear.stance_stone_clearance);
  EXPECT_EQ(cs.vertical().control_point(1), es.vertical().control_point(1));
}

TEST(OutputTrajectories, ClearNextStoneRearEdgeKeepsTheToeAboveAHigherNextStone) {
  // Planar Cassie's first step up (issue 42): the swing foot starts beside the stance foot, the next stone is 0.20 m
  // ahead and 0.22 m up, and the edge half-length is the stone's 0.09 m plus the sole's 0.07 m. The next stone's rear
  // edge, widened by that half-length, is at x = 0.20 − 0.16 = 0.04 m: from there on the toe is over the stone. With
  // the check, the foot crosses x = 0.04 m stance_stone_clearance above the stone's top and stays above the top until
  // it lands; without it, it crosses below the top (the toe runs into the face).
  SwingFootBezierParams params;
  params.apex_shape = SwingApexShape::kClearStanceStone;
  params.apex_reference = SwingApexReference::kHighestStone;
  params.touchdown_timing = SwingTouchdownTiming::kAtPhaseEnd;
  params.lift_off_at_rest = true;
  params.stance_stone_half_length = 0.16;
  const double l = 0.20, h = 0.22, edge = l - params.stance_stone_half_length;
  const SwingFootBezier unchecked(params, 0.0, 0.0, l, h);
  params.clear_next_stone_rear_edge = true;
  const SwingFootBezier checked(params, 0.0, 0.0, l, h);
  // Sampled independently of CrossingPhase: the height where x first reaches the edge.
  auto height_at_edge = [&](const SwingFootBezier& b) -> double {
    for (int k = 0; k <= 100000; ++k)
      if (b.X(k / 100000.0).value >= edge) return b.Z(k / 100000.0).value;
    return NAN;
  };
  std::printf("  height where the foot crosses x = %.2f m: unchecked %.4f m, checked %.4f m (stone top %.2f m)\n", edge,
              height_at_edge(unchecked), height_at_edge(checked), h);
  EXPECT_LT(height_at_edge(unchecked), h);
  EXPECT_NEAR(height_at_edge(checked), h + params.stance_stone_clearance, 1e-3);
  EXPECT_GE(height_at_edge(checked), h + params.stance_stone_clearance - 1e-6);
  for (int k = 0; k < 100000; ++k) {
    const double tau = k / 100000.0;
    if (checked.X(tau).value >= edge) {
      EXPECT_GE(checked.Z(tau).value, h - 1e-9) << "tau " << tau;  // over the stone, above its top
    }
  }
  EXPECT_NEAR(checked.Z(1.0).value, h, 1e-9);  // still lands at h_des at τ = 1
  EXPECT_NEAR(checked.X(1.0).value, l, 1e-12);
  // A long step then a short step down (ClearStanceStoneRaisesTheCurve... above): the stance stone's check binds (c
  // above the exact peak's), and the next stone's edge, 0.23 m lower, adds nothing.
  SwingFootBezierParams exact = params, down_params = params;
  exact.apex_shape = SwingApexShape::kExactPeak;
  exact.stance_stone_half_length = down_params.stance_stone_half_length = 0.05;
  exact.lift_off_at_rest = down_params.lift_off_at_rest = false;
  down_params.clear_next_stone_rear_edge = false;
  SwingFootBezierParams down_checked_params = down_params;
  down_checked_params.clear_next_stone_rear_edge = true;
  const SwingFootBezier down_exact(exact, -0.52, -0.15, 0.21, -0.23), down(down_params, -0.52, -0.15, 0.21, -0.23),
      down_checked(down_checked_params, -0.52, -0.15, 0.21, -0.23);
  EXPECT_GT(down.vertical().control_point(2), down_exact.vertical().control_point(2) + 1e-3);
  EXPECT_EQ(down_checked.vertical().control_point(2), down.vertical().control_point(2));
}

TEST(OutputTrajectories, HighestStoneApexClearsTheStanceStone) {
  // Both neighbouring stones below the stance stone: z_max is measured from the stance stone (z = 0).
  SwingFootBezierParams params;
  params.clearance = 0.1;
  params.apex_reference = SwingApexReference::kHighestStone;
  EXPECT_DOUBLE_EQ(SwingFootBezier(params, -0.3, -0.2, 0.4, -0.15).apex_height(), 0.1);
  EXPECT_DOUBLE_EQ(SwingFootBezier(params, -0.3, -0.2, 0.4, 0.15).apex_height(), 0.25);
  EXPECT_DOUBLE_EQ(SwingFootBezier(params, -0.3, 0.05, 0.4, -0.15).apex_height(), 0.15);
  params.apex_reference = SwingApexReference::kHigherFoothold;
  EXPECT_DOUBLE_EQ(SwingFootBezier(params, -0.3, -0.2, 0.4, -0.15).apex_height(), -0.05);
}

TEST(OutputTrajectories, TorsoCubicSolvesEq22) {
  const double phi0 = 0.12, phif = -0.05;
  Eigen::Matrix4d M;
  M << 1, 0, 0, 0, 0, 1, 0, 0, 1, 1, 1, 1, 0, 1, 2, 3;
  const Eigen::Vector4d c = M.partialPivLu().solve(Eigen::Vector4d(phi0, 0, phif, 0));
  const TorsoPitchCubic torso(phi0, phif);
  EXPECT_NEAR((torso.coefficients() - c).norm(), 0.0, 1e-15);
  EXPECT_DOUBLE_EQ(torso.Evaluate(0).value, phi0);
  EXPECT_NEAR(torso.Evaluate(1).value, phif, 1e-15);
  EXPECT_EQ(torso.Evaluate(0).first, 0.0);
  EXPECT_NEAR(torso.Evaluate(1).first, 0.0, 1e-15);
  for (double tau = 0.1; tau < 1; tau += 0.2) {
    const ScalarDerivatives fd = FiniteDifferences([&](double s) { return torso.Evaluate(s).value; }, tau);
    EXPECT_NEAR(torso.Evaluate(tau).first, fd.first, 1e-8);  // h² |φ'''| / 6 = 3.4e-9
    EXPECT_NEAR(torso.Evaluate(tau).second, fd.second, 1e-6);
  }
}

TEST(OutputTrajectories, PhaseVariables) {
  const PhaseVariable state_based({.type = PhaseType::kStateBased, .saturate = true});
  // Eq. (20): τ = (p − p0)/(ε l − p0).
  const Phase p = state_based.StateBased(0.05, 0.8, 2.0, -0.16, 0.24);
  EXPECT_NEAR(p.tau, 0.21 / 0.4, 1e-15);
  EXPECT_NEAR(p.tau_dot, 0.8 / 0.4, 1e-15);
  EXPECT_NEAR(p.tau_ddot, 2.0 / 0.4, 1e-15);
  // Saturation past the pre-impact position.
  const Phase late = state_based.StateBased(0.3, 0.8, 2.0, -0.16, 0.24);
  EXPECT_EQ(late.tau, 1.0);
  EXPECT_EQ(late.tau_dot, 0.0);
  EXPECT_GT(PhaseVariable({.saturate = false}).StateBased(0.3, 0.8, 2.0, -0.16, 0.24).tau, 1.0);
  // Sec. VI-D: τ_t = (t − t0)/T_s.
  const Phase t = state_based.TimeBased(1.3, 1.1, 0.4);
  EXPECT_NEAR(t.tau, 0.5, 1e-15);
  EXPECT_NEAR(t.tau_dot, 2.5, 1e-15);
  EXPECT_EQ(t.tau_ddot, 0.0);
  EXPECT_THROW(state_based.TimeBased(1.0, 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(state_based.StateBased(0.0, 0.0, 0.0, 0.2, 0.2), std::invalid_argument);
}

TEST(OutputTrajectories, TimeDerivativesFollowTheChainRuleAlongALipStep) {
  // Along a LIP step (x(t) = flow of Eq. (12)), Y_d(t) differentiated numerically in time must equal Ẏ_d, Ÿ_d.
  const double z0 = 0.8, g = 9.81, lambda = std::sqrt(g / z0);
  const double x0 = -0.16, xdot0 = 0.9;
  auto x_of_t = [&](double t) { return x0 * std::cosh(lambda * t) + xdot0 / lambda * std::sinh(lambda * t); };
  auto xdot_of_t = [&](double t) { return x0 * lambda * std::sinh(lambda * t) + xdot0 * std::cosh(lambda * t); };
  StepOutputParameters step;
  step.phi_0 = 0.1;
  step.phi_f = -0.02;
  step.p_com_x0 = x0;
  step.p_sw0_x = -0.32;
  step.p_sw0_z = 0.0;
  step.step_length = 0.4;
  step.step_height = 0.1;
  step.impact_fraction = 0.6;
  step.step_start_time = 0.0;
  step.step_duration = 0.35;
  SwingFootBezierParams swing;
  swing.clearance = 0.18;
  for (PhaseType type : {PhaseType::kStateBased, PhaseType::kTimeBased}) {
    const SteppingStonesOutputTrajectories outputs({.type = type, .saturate = true}, swing, step);
    const Eigen::Vector3d com_height(0.8, 0.0, 0.0);  // the MPC part is passed through
    auto y_of_t = [&](double t, int i) {
      const double x = x_of_t(t);
      return outputs.Evaluate(t, x, xdot_of_t(t), lambda * lambda * x, com_height).y[i];
    };
    for (double t = 0.03; t < 0.3; t += 0.05) {
      const double x = x_of_t(t);
      const DesiredOutputs d = outputs.Evaluate(t, x, xdot_of_t(t), lambda * lambda * x, com_height);
      ASSERT_GT(d.phase.tau, 0.0);
      ASSERT_LT(d.phase.tau, 1.0);
      for (int i : {0, 2, 3}) {
        const ScalarDerivatives fd = FiniteDifferences([&](double s) { return y_of_t(s, i); }, t, 1e-4);
        EXPECT_NEAR(d.ydot[i], fd.first, 1e-6 * (1 + std::abs(fd.first))) << "output " << i << " t = " << t;
        EXPECT_NEAR(d.yddot[i], fd.second, 1e-4 * (1 + std::abs(fd.second))) << "output " << i << " t = " << t;
      }
      EXPECT_EQ(d.y[1], 0.8);
    }
  }
}

}  // namespace
}  // namespace rome
