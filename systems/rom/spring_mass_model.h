#pragma once
// Spring-mass reduced-order model of vertical hopping, Sec. III of the hopping paper (Xiong & Ames, "Bipedal
// Hopping: Reduced-order Model Embedding via Optimization-based Control", IROS 2018). Pure math, no framework
// dependency; the dynamics are templated on the scalar so solvers/nlp's AutoDiff differentiates them.
//
// API summary (stable; used by the hopping planners and controllers):
//   LegPolynomial                 c0 + c1 L + c2 L² + c4 L⁴ (no cubic term, footnote 1), Evaluate<T>(L)
//   LegStiffnessVariant           kPublished | kIdentified; ParseLegStiffnessVariant("published"|"identified")
//   PublishedLegStiffness()       K(L), D(L) of the walking paper's Appendix 3 with c = 1
//   SpringMassParams              mass, gravity, n_legs, stiffness K(L), damping D(L)
//   SpringMassDerivative<T>(p, z, v)   ż for z = [x, ẋ, L, L̇], v = L̈        (Sec. III-B)
//   SpringMassLegForce<T>(p, x, ẋ, L, L̇)  total leg force n_legs (K(L) s + D(L) ṡ) [N] = ROM ground reaction
//   SpringMassModel               validated params + StaticDeflection(L), StaticState(L), Energy(z)
//
// State z = [x (m), ẋ (m/s), L (m), L̇ (m/s)]: x = height of the point mass above the ground = real leg length L_r,
// L = the actuated (virtual) leg length = the spring's rest length, s = L − x the spring compression (> 0 loaded).
// Input v = L̈ (m/s²).
//   ẍ = F/m − g,  F = n_legs (K(L) s + D(L) ṡ),  s = L − x,  ṡ = L̇ − ẋ           (Sec. III-B, spec A1.1)
// The legs act in parallel (spec C1 [R]): each of the n_legs legs carries K(L) s + D(L) ṡ. The dynamics are the
// stance dynamics; they do not clip F at zero (the planners constrain F ≥ 0; SpringMassSystem clips in flight).

#include <stdexcept>
#include <string>

#include <Eigen/Core>

namespace rome {

/// c0 + c1 L + c2 L² + c4 L⁴, the regression form of footnote 1 of the hopping paper (no cubic term).
struct LegPolynomial {
  double c0 = 0.0;
  double c1 = 0.0;
  double c2 = 0.0;
  double c4 = 0.0;
  template <class T>
  T Evaluate(const T& L) const {
    const T L2 = L * L;
    return c0 + c1 * L + c2 * L2 + c4 * L2 * L2;
  }
  template <class T>
  T Derivative(const T& L) const {
    return c1 + 2.0 * c2 * L + 4.0 * c4 * L * L * L;
  }
};

enum class LegStiffnessVariant {
  kPublished,   ///< walking paper, Appendix 3, c = 1 (the quartic the hopping paper's method gave on hardware)
  kIdentified,  ///< Eq. (4)-(13) of the hopping paper on our Cassie model (systems/rom/cassie_leg_stiffness.h)
};
/// "published" or "identified"; std::invalid_argument naming the flag value otherwise.
LegStiffnessVariant ParseLegStiffnessVariant(const std::string& name);
std::string ToString(LegStiffnessVariant variant);

/// K(L) [N/m] and D(L) [N s/m] of one leg.
struct LegStiffness {
  LegPolynomial stiffness;  ///< K(L) [N/m], L in m
  LegPolynomial damping;    ///< D(L) [N s/m]
};

/// Walking paper (Appendix 3) with c = 1: K = 23309 L⁴ − 55230 L² + 48657 L − 9451, D = 348 L⁴ − 824 L² + 726 L − 141.
LegStiffness PublishedLegStiffness();

struct SpringMassParams {
  double mass = 33.3;     ///< [kg] robot mass (robots.md Cassie with rods; use the model's total mass on a robot)
  double gravity = 9.81;  ///< [m/s²]
  int n_legs = 2;         ///< legs in parallel under the mass (spec C1 [R]: both of Cassie's legs)
  LegStiffness leg = PublishedLegStiffness();
};

/// Total leg force F = n_legs (K(L) s + D(L) ṡ) [N], s = L − x, ṡ = L̇ − ẋ (the ROM's vertical ground reaction in
/// stance). Scalar form: no allocation for T = double.
template <class T>
T SpringMassLegForce(const SpringMassParams& p, const T& x, const T& xdot, const T& L, const T& Ldot) {
  const T s = L - x;
  const T sdot = Ldot - xdot;
  return static_cast<double>(p.n_legs) * (p.leg.stiffness.Evaluate(L) * s + p.leg.damping.Evaluate(L) * sdot);
}

/// F for z = [x, ẋ, L, L̇] (any Eigen vector of size 4).
template <class T, class Vector>
T SpringMassLegForce(const SpringMassParams& p, const Vector& z) {
  return SpringMassLegForce<T>(p, T(z(0)), T(z(1)), T(z(2)), T(z(3)));
}

/// ż = [ẋ, F/m − g, L̇, v] for z = [x, ẋ, L, L̇], v = L̈ (Sec. III-B). `zdot` is resized to 4.
template <class T>
void SpringMassDerivative(const SpringMassParams& p, const Eigen::Matrix<T, Eigen::Dynamic, 1>& z, const T& v,
                          Eigen::Matrix<T, Eigen::Dynamic, 1>& zdot) {
  const T F = SpringMassLegForce<T>(p, z(0), z(1), z(2), z(3));
  zdot.resize(4);
  zdot(0) = z(1);
  zdot(1) = F / p.mass - p.gravity;
  zdot(2) = z(3);
  zdot(3) = v;
}

/// Energies of the spring-mass model [J]: kinetic ½ m ẋ², potential m g x, spring n_legs ∫₀ˢ K(L) σ dσ = ½ n_legs K(L)
/// s².
struct SpringMassEnergy {
  double kinetic = 0.0;
  double potential = 0.0;
  double spring = 0.0;
  double total() const { return kinetic + potential + spring; }
};

class SpringMassModel {
 public:
  /// Throws std::invalid_argument naming the parameter if mass, gravity or n_legs is not positive (or not finite).
  explicit SpringMassModel(SpringMassParams params = {});
  const SpringMassParams& params() const { return params_; }

  double Stiffness(double L) const { return params_.leg.stiffness.Evaluate(L); }  ///< K(L) of one leg [N/m]
  double Damping(double L) const { return params_.leg.damping.Evaluate(L); }      ///< D(L) of one leg [N s/m]
  /// Static compression s = m g / (n_legs K(L)) [m] at rest on the ground with leg length L.
  /// Throws std::domain_error if K(L) ≤ 0 (the quartic is negative for L < ~0.28 m).
  double StaticDeflection(double L) const;
  /// Rest state [L − s, 0, L, 0] with s = StaticDeflection(L).
  Eigen::Vector4d StaticState(double L) const;
  /// Leg force F = n_legs (K s + D ṡ) [N] (not clipped).
  double LegForce(const Eigen::Vector4d& z) const;
  /// ż for z and v = L̈ (stance dynamics, not clipped).
  Eigen::Vector4d Derivative(const Eigen::Vector4d& z, double v) const;
  SpringMassEnergy Energy(const Eigen::Vector4d& z) const;

 private:
  SpringMassParams params_;
};

}  // namespace rome
