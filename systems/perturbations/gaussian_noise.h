#pragma once
// AdditiveGaussianNoise: y = u + σ ⊙ n_k, a white Gaussian noise held over each sample period (sensor noise on the
// state a controller sees, torque noise between a controller and its plant).
//
// inputs:  u (size)   any signal
// outputs: y (size)   u + σ ⊙ n_k on [k T, (k+1) T) (direct feedthrough of u), n_k ~ N(0, I) independent over k and
//                     over elements
// discrete state (size + 1): [σ ⊙ n_k; k]. The update at t = k T draws n_k; the default state holds n_0.
// n_k,i is a pure function of (seed, k, i) (StandardNormalDraw: a SplitMix64 hash and the Box-Muller transform), so
// a run is reproducible from its seed, two blocks with different seeds draw independent noise, and drawing allocates
// nothing and keeps no generator state outside the context.

#include <cstdint>
#include <string>

#include <Eigen/Core>

#include "framework/system.h"

namespace rome {

/// A standard normal number that depends only on (seed, counter, element): Box-Muller on two uniforms from SplitMix64
/// hashes of the three. Different arguments give (statistically) independent draws.
double StandardNormalDraw(std::uint64_t seed, std::uint64_t counter, std::uint64_t element);

struct AdditiveGaussianNoiseParams {
  double period_s = 1e-3;  ///< [s] T: a new draw every period (ours: the controllers' 1 kHz)
  std::uint64_t seed = 0;  ///< noise stream; equal seeds give equal noise
  /// Throws std::invalid_argument naming the field and value: period_s in [1e-6, 10] s.
  void Validate() const;
};

class AdditiveGaussianNoise final : public LeafSystem {
 public:
  /// `sigma`: standard deviation per element, in u's units (>= 0, finite; 0 passes that element through). Throws
  /// naming the system, the element and the value otherwise, and as params.Validate().
  AdditiveGaussianNoise(std::string name, const Eigen::VectorXd& sigma, AdditiveGaussianNoiseParams params);
  const Eigen::VectorXd& sigma() const { return sigma_; }
  const AdditiveGaussianNoiseParams& params() const { return params_; }

 private:
  Eigen::VectorXd sigma_;
  AdditiveGaussianNoiseParams params_;
};

}  // namespace rome
