// PlanCache: keyed round trip to 17 digits, and processes that store the same key into one directory at once (parallel
// runs planning the same gait: two walking runs whose gaits differ only in the step width share the sagittal plan).
#include "systems/planners/plan_cache.h"

#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace rome {
namespace {

PlanCacheKey Key(double step_length) {
  PlanCacheKey key("test_plan");
  key.Add("step_length", step_length);
  return key;
}

TEST(PlanCache, RoundTripsEveryDigitAndMissesOtherKeys) {
  const std::string dir = ::testing::TempDir() + "/plan_cache_round_trip_test";
  std::filesystem::remove_all(dir);
  const PlanCache cache(dir);
  Eigen::VectorXd value(4);
  value << M_PI, -1e-300, 1.0 / 3.0, 6.02214076e23;
  cache.Store(Key(0.3), value);
  const auto loaded = cache.Load(Key(0.3));
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ((*loaded - value).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_FALSE(cache.Load(Key(0.31)).has_value());
  // Nothing but the plan's file is left in the directory.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    ++files;
    EXPECT_EQ(entry.path().string(), cache.FileFor(Key(0.3)));
  }
  EXPECT_EQ(files, 1);
  std::filesystem::remove_all(dir);
}

TEST(PlanCache, ProcessesStoringTheSameKeyAtOnceAllSucceed) {
  const std::string dir = ::testing::TempDir() + "/plan_cache_concurrent_test";
  std::filesystem::remove_all(dir);
  constexpr int kProcesses = 4, kStores = 300;
  Eigen::VectorXd value = Eigen::VectorXd::LinSpaced(2000, 0.0, 1.0);
  pid_t children[kProcesses];
  for (int i = 0; i < kProcesses; ++i) {
    children[i] = fork();
    ASSERT_GE(children[i], 0) << "fork failed";
    if (children[i] == 0) {
      int failures = 0;
      try {
        const PlanCache cache(dir);
        for (int k = 0; k < kStores; ++k) cache.Store(Key(0.3), value);
      } catch (const std::exception&) {
        failures = 1;
      }
      _exit(failures);
    }
  }
  int failed = 0;
  for (pid_t child : children) {
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    failed += !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  EXPECT_EQ(failed, 0) << "a process's Store threw (another process wrote or renamed its temporary file)";
  const PlanCache cache(dir);
  const auto loaded = cache.Load(Key(0.3));
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ((*loaded - value).cwiseAbs().maxCoeff(), 0.0);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);  // no temporary file left behind
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace rome
