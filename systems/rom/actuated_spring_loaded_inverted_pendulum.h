#pragma once
// ActuatedSpringLoadedInvertedPendulum (aSLIP): the sagittal reduced-order model of the walking paper (Xiong & Ames,
// "Motion Decoupling and Composition via Reduced Order Model Optimization for Dynamic Humanoid Walking with CLF-QP
// based Active Force Control", Sec. III-A, IV-A and Appendix), point-foot and footed. Pure math, templated on the
// scalar so that solvers/collocation can differentiate it with AutoDiff. The framework block is
// ActuatedSpringLoadedInvertedPendulumSystem.
//
// Model: a point mass m on two massless prismatic legs with flat ground at z = 0. Leg i (0 = left, 1 = right) has a
// virtual rest length L_i, driven by the input L̈_i, and a series nonlinear spring/damper between L_i and the actual
// leg length r_i = |p − f_i| (f_i = (x_i, 0) its foot pivot; spec: the ankle projection):
//   F_i = K(L_i) s_i + D(L_i) ṡ_i,  s_i = L_i − r_i,  ṡ_i = L̇_i − ṙ_i,  ṙ_i = e_i · ṗ      (Appendix 3, ref [22])
//   K(L) = c (23309 L⁴ − 55230 L² + 48657 L − 9451) [N/m], D(L) = c (348 L⁴ − 824 L² + 726 L − 141) [N s/m].
// Cartesian form of the Appendix-1 dynamics (spec §2.1 [R]; verified against the polar form in the tests):
//   m p̈ = Σ_{i in contact} G_i − m g ẑ,   G_i = F_i e_i + (u_i / r_i) n_i,
//   e_i = (p − f_i)/r_i, n_i = (−e_iz, e_ix) (e_i rotated +90°), u_i the ankle pitch torque (footed model only).
// With this n_i the moment of G_i about the pivot is u_i, so the COP is x_cop,i − x_i = u_i / G_iz (Eq. (10)).
// State (SSP and DSP alike): [x, z, ẋ, ż, L_L, L_R, L̇_L, L̇_R]; input [L̈_L, L̈_R] (point foot) or
// [L̈_L, L̈_R, u_L, u_R] (footed). A leg off the ground exerts nothing; its L and L̇ still flow (they fix the
// touchdown spring state). Touchdown (Appendix 2) leaves the mass velocity unchanged: in Cartesian form it is the
// identity; AslipPolarImpactMap gives the Appendix's polar re-expression (with the spec's r1 fix).
#include <cmath>

#include <Eigen/Core>

namespace rome {

/// Parameters of the aSLIP. Defaults: the 76 kg exoskeleton of robots.md (spec §1.1, §2.1).
struct ActuatedSpringLoadedInvertedPendulumParams {
  double mass = 76.0;     ///< [kg] m = 2.28 × 33.3 kg (Cassie), so that c stays consistent (robots.md, spec §1.1).
  double gravity = 9.81;  ///< [m/s²]
  double spring_scale = 2.28;  ///< [-] c, the exo-to-Cassie mass ratio multiplying K(L) and D(L) (paper, Appendix 3).
  /// [N/m/c] K(L)/c = k4 L⁴ + k2 L² + k1 L + k0 (ref [22]; there is no L³ term).
  double k4 = 23309, k2 = -55230, k1 = 48657, k0 = -9451;
  /// [N s/m/c] D(L)/c = d4 L⁴ + d2 L² + d1 L + d0 (ref [22]).
  double d4 = 348, d2 = -824, d1 = 726, d0 = -141;
  double heel_length = 0.07;  ///< [m] L_h, ankle pitch axis to heel (robots.md; footed model, Eq. (10)).
  double toe_length = 0.18;   ///< [m] L_t, ankle pitch axis to toe (robots.md; footed model, Eq. (10)).
};

/// Which legs are on the ground and where their pivots are (ground height 0).
struct ActuatedSpringLoadedInvertedPendulumContact {
  bool left = true, right = true;  ///< DSP: both; SSP: one.
  double left_foot_x = 0.0;        ///< [m] pivot of the left leg
  double right_foot_x = 0.0;       ///< [m] pivot of the right leg
  bool in_contact(int leg) const { return leg == 0 ? left : right; }
  double foot_x(int leg) const { return leg == 0 ? left_foot_x : right_foot_x; }
};

/// K(L) [N/m] (Appendix 3, times c).
template <class T>
T AslipStiffness(const ActuatedSpringLoadedInvertedPendulumParams& p, const T& L) {
  const T L2 = L * L;
  return p.spring_scale * (p.k4 * L2 * L2 + p.k2 * L2 + p.k1 * L + p.k0);
}

/// D(L) [N s/m] (Appendix 3, times c).
template <class T>
T AslipDamping(const ActuatedSpringLoadedInvertedPendulumParams& p, const T& L) {
  const T L2 = L * L;
  return p.spring_scale * (p.d4 * L2 * L2 + p.d2 * L2 + p.d1 * L + p.d0);
}

/// Kinematics and forces of one leg at a state.
template <class T>
struct ActuatedSpringLoadedInvertedPendulumLeg {
  T r;             ///< [m] actual leg length |p − f|
  T r_dot;         ///< [m/s] ṙ = e · ṗ
  T ex, ez;        ///< unit vector from the pivot to the mass
  T spring;        ///< [m] s = L − r
  T spring_rate;   ///< [m/s] ṡ = L̇ − ṙ
  T force;         ///< [N] F = K(L) s + D(L) ṡ along the leg (0 is not imposed: the NLP constrains F ≥ 0)
  T grf_x, grf_z;  ///< [N] G = F e + (u/r) n, the ground reaction on the mass
};

/// Leg `leg` (0 = left, 1 = right) with pivot x = foot_x and ankle torque `torque` [N m].
template <class T, class Vec>
ActuatedSpringLoadedInvertedPendulumLeg<T> AslipLegState(const ActuatedSpringLoadedInvertedPendulumParams& p,
                                                         const Vec& state, int leg, double foot_x, const T& torque) {
  using std::sqrt;
  ActuatedSpringLoadedInvertedPendulumLeg<T> out;
  const T dx = state(0) - foot_x;
  const T dz = state(1);
  out.r = sqrt(dx * dx + dz * dz);
  out.ex = dx / out.r;
  out.ez = dz / out.r;
  out.r_dot = out.ex * state(2) + out.ez * state(3);
  const T L = state(4 + leg);
  out.spring = L - out.r;
  out.spring_rate = state(6 + leg) - out.r_dot;
  out.force = AslipStiffness(p, L) * out.spring + AslipDamping(p, L) * out.spring_rate;
  // n = (−e_z, e_x).
  out.grf_x = out.force * out.ex - torque / out.r * out.ez;
  out.grf_z = out.force * out.ez + torque / out.r * out.ex;
  return out;
}

/// ẋ = f(x, u) of the aSLIP in the domain given by `contact`. `input` has 2 (point foot) or 4 (footed) entries.
template <class T>
Eigen::Matrix<T, 8, 1> AslipDynamics(const ActuatedSpringLoadedInvertedPendulumParams& p,
                                     const ActuatedSpringLoadedInvertedPendulumContact& contact,
                                     const Eigen::Matrix<T, Eigen::Dynamic, 1>& state,
                                     const Eigen::Matrix<T, Eigen::Dynamic, 1>& input) {
  Eigen::Matrix<T, 8, 1> xdot;
  T ax = T(0.0) * state(0), az = T(-p.gravity) + T(0.0) * state(0);
  for (int leg = 0; leg < 2; ++leg) {
    if (!contact.in_contact(leg)) continue;
    const T torque = input.size() >= 4 ? input(2 + leg) : T(0.0);
    const ActuatedSpringLoadedInvertedPendulumLeg<T> g = AslipLegState<T>(p, state, leg, contact.foot_x(leg), torque);
    ax += g.grf_x / p.mass;
    az += g.grf_z / p.mass;
  }
  xdot(0) = state(2);
  xdot(1) = state(3);
  xdot(2) = ax;
  xdot(3) = az;
  xdot(4) = state(6);
  xdot(5) = state(7);
  xdot(6) = input(0);
  xdot(7) = input(1);
  return xdot;
}

/// Rest length L with K(L)(L − r) = F for a leg of actual length r carrying the static leg force F ≥ 0 (spec §3.2:
/// "L is recovered by force balance ... needs Newton's method, since K depends on L"). Newton from L = r + F/K(r);
/// throws std::invalid_argument if it does not converge to 1e-12 m in 50 steps or leaves L > 0.2807 m (K > 0).
double AslipRestLengthForForce(const ActuatedSpringLoadedInvertedPendulumParams& params, double r, double F);

/// Appendix 2, the SSP→DSP touchdown in polar coordinates (leg 1 = stance, leg 2 = landing):
///   ṙ2⁺ = ṙ1 cos Δq − q̇1 r1 sin Δq,  q̇2⁺ = (q̇1 r1 cos Δq + ṙ1 sin Δq) / r2   (spec [P-fix]: q̇1 r1, not q̇1 ṙ1),
/// with Δq = q1 − q2 and the leg angle convention e = (−sin q, cos q). Returns (ṙ2⁺, q̇2⁺).
inline Eigen::Vector2d AslipPolarImpactMap(double r1, double q1, double r1_dot, double q1_dot, double r2, double q2) {
  const double dq = q1 - q2;
  return {r1_dot * std::cos(dq) - q1_dot * r1 * std::sin(dq),
          (q1_dot * r1 * std::cos(dq) + r1_dot * std::sin(dq)) / r2};
}

}  // namespace rome
