// Primitive blocks: each against its defining equation.
#include "framework/primitives.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "framework/diagram.h"
#include "framework/simulator.h"

namespace rome {
namespace {

// Saturation: y_i = min(max(u_i, lower_i), upper_i), elementwise, inside a diagram; NaN is not clamped.
TEST(Primitives, SaturationClampsEachElementToItsInterval) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  DiagramBuilder b;
  Eigen::VectorXd u(5);
  u << -7.0, 0.25, 9.0, -1e300, nan;
  b.AddSystem(std::make_unique<ConstantVectorSource>("u", u));
  Eigen::VectorXd lo(5), hi(5);
  lo << -2.0, -2.0, -2.0, -inf, -1.0;
  hi << 3.0, 3.0, 3.0, 4.0, 1.0;
  b.AddSystem(std::make_unique<Saturation>("sat", lo, hi));
  b.Connect("u", "y", "sat", "u");
  b.ExportOutput("sat", "y");
  auto d = b.Build();
  auto c = d->CreateDefaultContext();
  const Eigen::VectorXd y = d->EvalOutput(*c, "y");
  EXPECT_EQ(y[0], -2.0);
  EXPECT_EQ(y[1], 0.25);
  EXPECT_EQ(y[2], 3.0);
  EXPECT_EQ(y[3], -1e300);
  EXPECT_TRUE(std::isnan(y[4]));
}

TEST(Primitives, SaturationRefusesBoundsThatAreNoInterval) {
  try {
    Saturation("tau_limit", Eigen::Vector2d(-1, 2), Eigen::Vector2d(1, 1));
    FAIL() << "an empty interval was accepted";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("tau_limit"), std::string::npos) << what;
    EXPECT_NE(what.find("element 1"), std::string::npos) << what;
  }
  EXPECT_THROW(Saturation("s", Eigen::Vector2d(-1, std::nan("")), Eigen::Vector2d(1, 1)), std::exception);
  EXPECT_THROW(Saturation("s", Eigen::VectorXd::Zero(2), Eigen::VectorXd::Zero(3)), std::exception);
  EXPECT_THROW(Saturation("s", -1.0, 2), std::exception);  // a negative symmetric limit is an empty interval
  const Saturation sym("s", 5.0, 3);
  EXPECT_EQ(sym.lower(), Eigen::VectorXd::Constant(3, -5.0));
  EXPECT_EQ(sym.upper(), Eigen::VectorXd::Constant(3, 5.0));
}

TEST(Primitives, GainAdderMuxDemux) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<ConstantVectorSource>("a", Eigen::Vector2d(1, 2)));
  b.AddSystem(std::make_unique<ConstantVectorSource>("b", Eigen::VectorXd::Constant(1, 3)));
  b.AddSystem(std::make_unique<Multiplexer>("mux", std::vector<int>{2, 1}));
  Eigen::Matrix3d K;
  K << 1, 0, 0, 0, 2, 0, 1, 1, 1;
  b.AddSystem(std::make_unique<Gain>("K", Eigen::MatrixXd(K)));
  b.AddSystem(std::make_unique<Demultiplexer>("demux", std::vector<int>{1, 2}));
  b.AddSystem(std::make_unique<Adder>("add", 2, 3));
  b.Connect("a", "y", "mux", "u0");
  b.Connect("b", "y", "mux", "u1");
  b.Connect("mux", "y", "K", "u");
  b.Connect("K", "y", "demux", "u");
  b.Connect("K", "y", "add", "u0");
  b.Connect("mux", "y", "add", "u1");
  b.ExportOutput("demux", "y0");
  b.ExportOutput("demux", "y1");
  b.ExportOutput("add", "sum");
  auto d = b.Build();
  auto c = d->CreateDefaultContext();
  // K [1 2 3] = [1 4 6].
  EXPECT_EQ(d->EvalOutput(*c, "y0"), Eigen::VectorXd::Constant(1, 1.0));
  EXPECT_EQ(d->EvalOutput(*c, "y1"), Eigen::VectorXd(Eigen::Vector2d(4, 6)));
  EXPECT_EQ(d->EvalOutput(*c, "sum"), Eigen::VectorXd(Eigen::Vector3d(2, 6, 9)));
}

TEST(Primitives, ZeroOrderHoldHoldsBetweenSamples) {
  DiagramBuilder b;
  auto sine = TrajectorySource::FromFunction(
      "sine", 1, [](double t) { return Eigen::VectorXd::Constant(1, std::sin(t)); },
      [](double t) { return Eigen::VectorXd::Constant(1, std::cos(t)); });
  b.AddSystem(std::move(sine));
  b.AddSystem(std::make_unique<ZeroOrderHold>("zoh", 0.1, 1));
  b.Connect("sine", "y", "zoh", "u");
  b.ExportOutput("zoh", "y");
  b.ExportOutput("sine", "ydot");
  auto d = b.Build();
  Simulator sim(*d);
  for (int k = 0; k < 10; ++k) {
    ASSERT_TRUE(sim.AdvanceTo(0.1 * k + 0.05).ok());
    EXPECT_DOUBLE_EQ(d->EvalOutput(sim.get_context(), "y")[0], std::sin(0.1 * k)) << k;
    EXPECT_DOUBLE_EQ(d->EvalOutput(sim.get_context(), "ydot")[0], std::cos(0.1 * k + 0.05));
  }
}

}  // namespace
}  // namespace rome
