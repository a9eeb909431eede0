// DelayLine: a consumer that samples at the same period (a controller) sees the input exactly N periods late.
#include "systems/perturbations/delay_line.h"

#include <gtest/gtest.h>

#include <cmath>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "tests/common/error_of.h"

namespace rome {
namespace {

Eigen::Vector2d Signal(double t) { return Eigen::Vector2d(3.0 * t + 1.0, std::sin(7.0 * t)); }

TEST(DelayLine, ASamplerAtTheSamePeriodSeesTheInputExactlyNPeriodsLate) {
  const double T = 1e-3;
  for (int N : {1, 3, 7}) {
    DiagramBuilder b;
    b.AddSystem(std::make_unique<TrajectorySource>("signal", 2,
                                                   [](double t, Eigen::Ref<Eigen::VectorXd> out) { out = Signal(t); }));
    const auto* delay =
        b.AddSystem(std::make_unique<DelayLine>("latency", Eigen::Vector2d(-5.0, -5.0), DelayLineParams{T, N}));
    // The consumer: samples the delay line's output at k T, as a 1 kHz controller does.
    const auto* sampler = b.AddSystem(std::make_unique<ZeroOrderHold>("sampler", T, 2));
    b.Connect("signal", "y", "latency", "u");
    b.Connect("latency", "y", "sampler", "u");
    auto diagram = b.Build("delay");
    Simulator sim(*diagram);
    sim.Initialize();
    for (int k = 0; k < N + 25; ++k) {
      ASSERT_TRUE(sim.AdvanceTo((k + 0.5) * T).ok());
      const Eigen::VectorXd& seen = diagram->GetSubsystemContext(*sampler, sim.get_context()).discrete_state();
      // Sampled at k T: u((k - N) T), or the initial history before N samples have come in.
      const Eigen::Vector2d expected = k >= N ? Signal((k - N) * T) : Eigen::Vector2d(-5.0, -5.0);
      EXPECT_NEAR((seen - expected).norm(), 0.0, 1e-12) << "N = " << N << ", k = " << k;
    }
    // SetHistory: the whole history becomes one value.
    LeafContext& c = diagram->GetMutableSubsystemContext(*delay, sim.get_mutable_context());
    delay->SetHistory(c, Eigen::Vector2d(4.0, 2.0));
    EXPECT_EQ(delay->EvalOutput(c, 0), Eigen::VectorXd(Eigen::Vector2d(4.0, 2.0)));
  }
}

TEST(DelayLine, BadParametersNameTheField) {
  EXPECT_NE(test::ErrorOf([] {
              DelayLine("d", Eigen::Vector2d::Zero(), DelayLineParams{1e-3, 0});
            }).find("delay_samples = 0"),
            std::string::npos);
  EXPECT_NE(test::ErrorOf([] {
              DelayLine("d", Eigen::Vector2d::Zero(), DelayLineParams{0.0, 2});
            }).find("period_s"),
            std::string::npos);
  DelayLine d("d", Eigen::Vector2d::Zero(), DelayLineParams{1e-3, 2});
  auto c = d.CreateDefaultLeafContext();
  EXPECT_NE(test::ErrorOf([&] { d.SetHistory(*c, Eigen::Vector3d::Zero()); }).find("3 elements"), std::string::npos);
}

}  // namespace
}  // namespace rome
