// AdditiveGaussianNoise: reproducible from its seed, and the noise has the requested mean, standard deviation,
// Gaussian kurtosis and no correlation from one sample to the next (bounds many standard errors wide, but narrower
// than a wrong sigma: a sigma off by 3 % or more fails).
#include "systems/perturbations/gaussian_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "tests/common/error_of.h"

namespace rome {
namespace {

// The noise y - u of `samples` periods, per element (the block's own periodic update, applied as the simulator does).
std::vector<std::vector<double>> Draw(const AdditiveGaussianNoise& block, int samples) {
  auto c = block.CreateDefaultLeafContext();
  const int n = static_cast<int>(block.sigma().size());
  const Eigen::VectorXd u = Eigen::VectorXd::LinSpaced(n, 1.0, 2.0);
  c->FixInputPort(0, u);
  std::vector<std::vector<double>> out(n);
  Eigen::VectorXd next;
  for (int k = 0; k < samples; ++k) {
    const Eigen::VectorXd y = block.EvalOutput(*c, 0);
    for (int i = 0; i < n; ++i) out[i].push_back(y[i] - u[i]);
    next = c->discrete_state();
    EXPECT_TRUE(block.periodic_events()[0].update(*c, &next).ok());
    c->get_mutable_discrete_state() = next;
    c->SetTime((k + 1) * block.params().period_s);
  }
  return out;
}

TEST(AdditiveGaussianNoise, HasTheRequestedStandardDeviationAndIsWhite) {
  const Eigen::Vector3d sigma(0.5, 2.0, 0.0);
  AdditiveGaussianNoise block("noise", sigma, {1e-3, 1234});
  const int N = 40000;
  const auto draws = Draw(block, N);
  for (int i = 0; i < 2; ++i) {
    double mean = 0, m2 = 0, m4 = 0, lag1 = 0;
    for (double x : draws[i]) mean += x;
    mean /= N;
    for (int k = 0; k < N; ++k) {
      const double d = draws[i][k] - mean;
      m2 += d * d, m4 += d * d * d * d;
      if (k > 0) lag1 += d * (draws[i][k - 1] - mean);
    }
    m2 /= N, m4 /= N, lag1 /= N;
    const double sd = std::sqrt(m2);
    // Standard errors for N = 40000 Gaussian draws: mean sigma/200, sd 0.35 % of sigma, kurtosis 0.024, lag-1
    // correlation 0.005.
    EXPECT_LT(std::abs(mean), 5 * sigma[i] / std::sqrt(N)) << "element " << i;
    EXPECT_LT(std::abs(sd / sigma[i] - 1.0), 0.02) << "element " << i << ": sd " << sd << " vs sigma " << sigma[i];
    EXPECT_NEAR(m4 / (m2 * m2), 3.0, 0.15) << "element " << i;
    EXPECT_LT(std::abs(lag1 / m2), 0.025) << "element " << i;
  }
  for (double x : draws[2]) EXPECT_EQ(x, 0.0);  // sigma 0 passes the input through
  // The two noisy elements are uncorrelated.
  double cross = 0;
  for (int k = 0; k < N; ++k) cross += draws[0][k] * draws[1][k];
  EXPECT_LT(std::abs(cross / N / (sigma[0] * sigma[1])), 0.025);
}

TEST(AdditiveGaussianNoise, IsReproducibleFromItsSeed) {
  const Eigen::Vector2d sigma(1.0, 1.0);
  const auto a = Draw(AdditiveGaussianNoise("a", sigma, {1e-3, 7}), 200);
  const auto b = Draw(AdditiveGaussianNoise("b", sigma, {1e-3, 7}), 200);
  const auto c = Draw(AdditiveGaussianNoise("c", sigma, {1e-3, 8}), 200);
  EXPECT_EQ(a, b);
  int equal = 0;
  for (int k = 0; k < 200; ++k) equal += a[0][k] == c[0][k];
  EXPECT_EQ(equal, 0);
}

TEST(AdditiveGaussianNoise, BadSigmaNamesTheElement) {
  EXPECT_NE(test::ErrorOf([] { AdditiveGaussianNoise("n", Eigen::Vector2d(1.0, -1.0), {}); }).find("sigma[1]"),
            std::string::npos);
  EXPECT_NE(test::ErrorOf([] {
              AdditiveGaussianNoise("n", Eigen::Vector2d(1.0, 1.0), {0.0, 1});
            }).find("period_s"),
            std::string::npos);
}

}  // namespace
}  // namespace rome
