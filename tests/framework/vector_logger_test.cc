// VectorLogger: periodic and per-event sampling, and a CSV whose header names every column.
#include "framework/vector_logger.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <sstream>

#include "framework/simulator.h"
#include "systems/classic/bouncing_ball.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

TEST(VectorLogger, PeriodicSamplesMatchClosedForm) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<BouncingBall>("ball", BouncingBallParams{.restitution = 0.8}));
  auto* logger = AddVectorLogger(b, "log", {{"ball", "state"}}, 0.01);
  auto d = b.Build();
  Simulator sim(*d);
  ASSERT_TRUE(sim.AdvanceTo(0.4).ok());  // before the first impact (0.4515 s)
  const auto& data = logger->log(d->GetSubsystemContext(*logger, sim.get_context()));
  ASSERT_EQ(data.times.size(), 40u);  // t = 0, 0.01, ..., 0.39
  for (size_t k = 0; k < data.times.size(); ++k) {
    const double t = data.times[k];
    EXPECT_NEAR(t, 0.01 * k, 1e-15);
    EXPECT_NEAR(data.samples[k][0], 1.0 - 0.5 * 9.81 * t * t, 1e-7);
  }
  const std::string path = rome::test::ScratchDir() + "/ball.csv";
  logger->WriteCsv(d->GetSubsystemContext(*logger, sim.get_context()), path);
  std::ifstream in(path);
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  EXPECT_EQ(header, "time,ball.state[0],ball.state[1]");
  EXPECT_EQ(first, "0,1,0");
  std::remove(path.c_str());
  EXPECT_THROW(logger->WriteCsv(d->GetSubsystemContext(*logger, sim.get_context()), "/nonexistent/dir/x.csv"),
               std::runtime_error);
}

TEST(VectorLogger, EventModeRecordsEveryImpact) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<BouncingBall>("ball", BouncingBallParams{.restitution = 0.8}));
  auto* logger = AddVectorLogger(b, "log", {{"ball", "state"}}, 0.0);
  auto d = b.Build();
  Simulator sim(*d);
  ASSERT_TRUE(sim.AdvanceTo(2.0).ok());
  const auto& data = logger->log(d->GetSubsystemContext(*logger, sim.get_context()));
  const auto& events = sim.statistics().events;
  ASSERT_EQ(data.times.size(), events.size() + 1);  // initial sample + one per event
  for (size_t k = 0; k < events.size(); ++k) {
    EXPECT_EQ(data.times[k + 1], events[k].time);
    EXPECT_GT(data.samples[k + 1][1], 0.0);  // post-impact velocity is upward
  }
}

}  // namespace
}  // namespace rome
