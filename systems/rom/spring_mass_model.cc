#include "systems/rom/spring_mass_model.h"

#include <cmath>
#include <sstream>

namespace rome {

LegStiffnessVariant ParseLegStiffnessVariant(const std::string& name) {
  if (name == "published") return LegStiffnessVariant::kPublished;
  if (name == "identified") return LegStiffnessVariant::kIdentified;
  throw std::invalid_argument("leg stiffness variant '" + name + "' is unknown (expected 'published' or 'identified')");
}

std::string ToString(LegStiffnessVariant variant) {
  return variant == LegStiffnessVariant::kPublished ? "published" : "identified";
}

LegStiffness PublishedLegStiffness() {
  // Walking paper, Appendix 3, with the mass ratio c = 1 (Cassie): coefficients of L⁰, L¹, L², L⁴.
  LegStiffness leg;
  leg.stiffness = {-9451.0, 48657.0, -55230.0, 23309.0};
  leg.damping = {-141.0, 726.0, -824.0, 348.0};
  return leg;
}

SpringMassModel::SpringMassModel(SpringMassParams params) : params_(params) {
  auto check = [](double value, const char* name) {
    if (!(std::isfinite(value) && value > 0.0)) {
      std::ostringstream msg;
      msg << "SpringMassParams: " << name << " = " << value << " must be positive and finite";
      throw std::invalid_argument(msg.str());
    }
  };
  check(params_.mass, "mass");
  check(params_.gravity, "gravity");
  if (params_.n_legs < 1) {
    throw std::invalid_argument("SpringMassParams: n_legs = " + std::to_string(params_.n_legs) + " must be >= 1");
  }
}

double SpringMassModel::StaticDeflection(double L) const {
  const double K = Stiffness(L);
  if (!(K > 0.0)) {
    std::ostringstream msg;
    msg << "SpringMassModel::StaticDeflection: K(L = " << L << " m) = " << K << " N/m is not positive";
    throw std::domain_error(msg.str());
  }
  return params_.mass * params_.gravity / (params_.n_legs * K);
}

Eigen::Vector4d SpringMassModel::StaticState(double L) const {
  return Eigen::Vector4d(L - StaticDeflection(L), 0.0, L, 0.0);
}

double SpringMassModel::LegForce(const Eigen::Vector4d& z) const {
  return SpringMassLegForce<double>(params_, z(0), z(1), z(2), z(3));
}

Eigen::Vector4d SpringMassModel::Derivative(const Eigen::Vector4d& z, double v) const {
  const double F = LegForce(z);
  return Eigen::Vector4d(z(1), F / params_.mass - params_.gravity, z(3), v);
}

SpringMassEnergy SpringMassModel::Energy(const Eigen::Vector4d& z) const {
  SpringMassEnergy e;
  e.kinetic = 0.5 * params_.mass * z(1) * z(1);
  e.potential = params_.mass * params_.gravity * z(0);
  const double s = z(2) - z(0);
  e.spring = 0.5 * params_.n_legs * Stiffness(z(2)) * s * s;
  return e;
}

}  // namespace rome
