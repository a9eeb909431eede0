#include "systems/rom/hybrid_linear_inverted_pendulum.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

namespace rome {
namespace {

void Require(bool ok, const char* who, const char* what, double value) {
  if (ok) return;
  std::ostringstream msg;
  msg << who << ": parameter " << what << ", got " << value;
  throw std::invalid_argument(msg.str());
}

}  // namespace

HybridLinearInvertedPendulum::HybridLinearInvertedPendulum(HybridLinearInvertedPendulumParams params)
    : params_(params) {
  const char* who = "HybridLinearInvertedPendulum";
  Require(params_.z0 > 0 && std::isfinite(params_.z0), who, "z0 must be > 0 m", params_.z0);
  Require(params_.ssp_duration > 0 && std::isfinite(params_.ssp_duration), who, "ssp_duration must be > 0 s",
          params_.ssp_duration);
  Require(params_.dsp_duration >= 0 && std::isfinite(params_.dsp_duration), who, "dsp_duration must be >= 0 s",
          params_.dsp_duration);
  Require(params_.gravity > 0 && std::isfinite(params_.gravity), who, "gravity must be > 0 m/s²", params_.gravity);
  lambda_ = std::sqrt(params_.gravity / params_.z0);
}

double HybridLinearInvertedPendulum::sigma1() const {
  return lambda_ / std::tanh(0.5 * lambda_ * params_.ssp_duration);
}

double HybridLinearInvertedPendulum::sigma2() const {
  return lambda_ * std::tanh(0.5 * lambda_ * params_.ssp_duration);
}

Eigen::Matrix2d HybridLinearInvertedPendulum::SingleSupportTransition(double t) const {
  const double ch = std::cosh(lambda_ * t), sh = std::sinh(lambda_ * t);
  Eigen::Matrix2d E;
  E << ch, sh / lambda_, lambda_ * sh, ch;
  return E;
}

Eigen::Matrix2d HybridLinearInvertedPendulum::StepToStepA() const {
  Eigen::Matrix2d dsp;
  dsp << 1, params_.dsp_duration, 0, 1;
  return SingleSupportTransition(params_.ssp_duration) * dsp;
}

Eigen::Vector2d HybridLinearInvertedPendulum::StepToStepB() const {
  const double T = params_.ssp_duration;
  return -Eigen::Vector2d(std::cosh(lambda_ * T), lambda_ * std::sinh(lambda_ * T));
}

Eigen::RowVector2d HybridLinearInvertedPendulum::DeadbeatGain() const {
  return {1.0, params_.dsp_duration + 1.0 / (std::tanh(lambda_ * params_.ssp_duration) * lambda_)};
}

Eigen::Vector2d HybridLinearInvertedPendulum::P1PreImpactState(double step) const {
  const double p = step / (2.0 + params_.dsp_duration * sigma1());
  return {p, sigma1() * p};
}

Eigen::Vector2d HybridLinearInvertedPendulum::P2PreImpactState(double step_width) const {
  Require(step_width > 0 && std::isfinite(step_width), "HybridLinearInvertedPendulum::P2PreImpactState",
          "step_width must be > 0 m", step_width);
  const double p = -step_width / (2.0 + params_.dsp_duration * sigma2());
  return {p, sigma2() * p};
}

double HybridLinearInvertedPendulum::P2Step(const Eigen::Vector2d& pre_impact) const {
  return 2.0 * pre_impact(0) + params_.dsp_duration * pre_impact(1);
}

FootedLinearInvertedPendulumStep FootedLinearInvertedPendulumDiscretization(double lambda, double T, double mass,
                                                                            double z0, bool single_support) {
  const char* who = "FootedLinearInvertedPendulumDiscretization";
  Require(T >= 0 && std::isfinite(T), who, "T must be >= 0 s", T);
  Require(mass > 0 && std::isfinite(mass), who, "mass must be > 0 kg", mass);
  Require(z0 > 0 && std::isfinite(z0), who, "z0 must be > 0 m", z0);
  Require(lambda > 0 && std::isfinite(lambda), who, "lambda must be > 0 1/s", lambda);
  FootedLinearInvertedPendulumStep step;
  const double mz = mass * z0;
  if (single_support) {
    const double ch = std::cosh(lambda * T), sh = std::sinh(lambda * T);
    step.A << ch, sh / lambda, lambda * sh, ch;
    step.B << (ch - 1.0) / (lambda * lambda * mz), sh / (lambda * mz);
  } else {
    step.A << 1, T, 0, 1;
    step.B << T * T / (2.0 * mz), T / mz;
  }
  return step;
}

}  // namespace rome
