#include "diagrams/walking/pre_impact_sampler.h"

#include <cmath>

#include <gtest/gtest.h>

namespace rome {
namespace {

// A ballistic COM, z(t) = z0 + v0 t − g t²/2, sampled every 0.7 ms: at a touchdown 0.6 ms after the last sample the
// extrapolated ż is within g·dt·dt_gap-order of the closed form ż(t) = v0 − g t, and z within g t_gap²; the last
// sample alone would be off by g · 0.6 ms = 5.9e-3 m/s.
TEST(PreImpactSampler, ExtrapolatesToTheTouchdownInstant) {
  const double g = 9.81, z0 = 0.9, v0 = 0.3, dt = 7e-4;
  auto state = [&](double t) {
    PreImpactSampler::State s = PreImpactSampler::State::Zero();
    s(2) = z0 + v0 * t - 0.5 * g * t * t;
    s(5) = v0 - g * t;
    return s;
  };
  PreImpactSampler sampler;
  double t = 0.0;
  for (int k = 0; k <= 100; ++k, t = k * dt) sampler.Record(t, state(t));
  const double t_last = 100 * dt, t_touchdown = t_last + 6e-4;
  const PreImpactSampler::State at = sampler.At(t_touchdown), exact = state(t_touchdown);
  EXPECT_NEAR(at(5), exact(5), 1e-12);  // ż is linear in t: exact
  EXPECT_NEAR(at(2), exact(2), 0.5 * g * 6e-4 * (6e-4 + dt) + 1e-12);
  EXPECT_GT(std::abs(state(t_last)(5) - exact(5)), 5e-3);
  // A repeated instant replaces the last sample instead of dividing by zero.
  sampler.Record(t_last, state(t_last));
  EXPECT_TRUE(sampler.At(t_touchdown).allFinite());
}

}  // namespace
}  // namespace rome
