#include "systems/perturbations/gaussian_noise.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace rome {

namespace {

// SplitMix64's output function (Steele, Lea and Flood 2014): a bijective 64-bit mix with full avalanche.
std::uint64_t Mix(std::uint64_t z) {
  z += 0x9e3779b97f4a7c15ULL;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

// Uniform in (0, 1): the top 53 bits, offset by half a unit so that 0 never occurs (log(0) in Box-Muller).
double Uniform(std::uint64_t bits) { return (static_cast<double>(bits >> 11) + 0.5) * 0x1.0p-53; }

}  // namespace

double StandardNormalDraw(std::uint64_t seed, std::uint64_t counter, std::uint64_t element) {
  const std::uint64_t key = Mix(Mix(Mix(seed) ^ counter) ^ element);
  const double u1 = Uniform(Mix(key)), u2 = Uniform(Mix(key ^ 0x5851f42d4c957f2dULL));
  return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * std::numbers::pi * u2);
}

void AdditiveGaussianNoiseParams::Validate() const {
  if (!(period_s >= 1e-6 && period_s <= 10.0))
    throw std::invalid_argument("AdditiveGaussianNoiseParams: period_s = " + std::to_string(period_s) +
                                " s is outside [1e-6, 10] s");
}

AdditiveGaussianNoise::AdditiveGaussianNoise(std::string name, const Eigen::VectorXd& sigma,
                                             AdditiveGaussianNoiseParams params)
    : LeafSystem(std::move(name)), sigma_(sigma), params_(params) {
  try {
    params_.Validate();
  } catch (const std::invalid_argument& e) { ThrowError(e.what()); }
  const int n = static_cast<int>(sigma_.size());
  if (n == 0) ThrowError("sigma has no elements");
  for (int i = 0; i < n; ++i)
    if (!(sigma_[i] >= 0.0) || !std::isfinite(sigma_[i]))
      ThrowError("sigma[" + std::to_string(i) + "] = " + std::to_string(sigma_[i]) + " must be >= 0 and finite");
  const std::uint64_t seed = params_.seed;
  Eigen::VectorXd x0(n + 1);
  for (int i = 0; i < n; ++i) x0[i] = sigma_[i] * StandardNormalDraw(seed, 0, i);
  x0[n] = 0.0;
  DeclareDiscreteState(x0);
  DeclareInputPort("u", n);
  DeclarePeriodicDiscreteUpdate(params_.period_s, 0.0, [this, n, seed](const LeafContext& c, Eigen::VectorXd* xd) {
    const double k = c.discrete_state()[n] + 1.0;
    const auto counter = static_cast<std::uint64_t>(k);
    for (int i = 0; i < n; ++i) (*xd)[i] = sigma_[i] * StandardNormalDraw(seed, counter, i);
    (*xd)[n] = k;
    return EventStatus::Succeeded();
  });
  DeclareOutputPort("y", n, [this, n](const LeafContext& c, Eigen::VectorXd* y) {
    *y = c.discrete_state().head(n);
    *y += EvalInput(c, 0);
  });
}

}  // namespace rome
