// walking --scenario-file: a run is reproduced from its summary alone. A run with non-default options writes its
// effective scenario under "scenario"; that object, given back as --scenario-file with no other parameter, gives the
// same summary (every figure but wall times), options on the command line win over the file, and an unknown key is
// an error that names it.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/process.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

namespace fs = std::filesystem;

fs::path WorkDir() { return fs::path(test::ScratchDir()); }

nlohmann::json ReadJson(const fs::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

void WriteJson(const fs::path& path, const nlohmann::json& j) { std::ofstream(path) << j.dump(2); }

// The summary without wall-clock measures (solve times, real-time factor, QP solve times).
nlohmann::json WithoutTimes(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::json out = nlohmann::json::object();
    for (const auto& [key, value] : j.items())
      if (key != "solve_s" && key != "realtime_factor" && key.rfind("qp_solve_us", 0) != 0)
        out[key] = WithoutTimes(value);
    return out;
  }
  if (j.is_array()) {
    nlohmann::json out = nlohmann::json::array();
    for (const auto& value : j) out.push_back(WithoutTimes(value));
    return out;
  }
  return j;
}

ProcessResult Walking(std::vector<std::string> args) {
  args.insert(args.begin(), ROME_WALKING_BIN);
  return RunProgram(args);
}

TEST(WalkingScenarioFile, ASummarysScenarioReproducesItsRun) {
  const fs::path dir = WorkDir();
  const ProcessResult first = Walking({"--scenario", "periodic", "--steps", "3", "--gait-a", "0.32,0.4,0.1,0.24",
                                       "--touchdown-speed", "0.12", "--force-band", "0.12", "--foothold-tolerance",
                                       "0.06", "--cache", "", "--summary", (dir / "a.json").string()});
  ASSERT_TRUE(first.started) << first.error;
  ASSERT_EQ(first.exit_code, 0) << first.error << "\n" << first.out;
  const nlohmann::json a = ReadJson(dir / "a.json");
  const nlohmann::json& scenario = a.at("scenario");
  // The scenario holds what was asked, and the defaults of the rest.
  EXPECT_EQ(scenario.at("scenario"), "periodic");
  EXPECT_EQ(scenario.at("steps"), 3);
  EXPECT_EQ(scenario.at("gait-a"),
            nlohmann::json({0.32, 0.40, 0.10, 0.24}));      // numbers that read back as given: an array
  EXPECT_EQ(scenario.at("gait-b"), "0.40,0.40,0.10,0.25");  // the default as written ("0.40"): kept as text
  EXPECT_EQ(scenario.at("force-band"), 0.12);
  EXPECT_EQ(scenario.at("seed"), 1);
  EXPECT_EQ(scenario.at("clf-cost-target"), "pd");
  EXPECT_FALSE(scenario.contains("summary"));
  WriteJson(dir / "scenario.json", scenario);

  const ProcessResult second = Walking(
      {"--scenario-file", (dir / "scenario.json").string(), "--cache", "", "--summary", (dir / "b.json").string()});
  ASSERT_EQ(second.exit_code, 0) << second.error << "\n" << second.out;
  const nlohmann::json b = ReadJson(dir / "b.json");
  EXPECT_GT(a.at("steps_completed").get<int>(), 2);
  EXPECT_EQ(WithoutTimes(a), WithoutTimes(b)) << "first:\n"
                                              << WithoutTimes(a).dump(1) << "\nsecond:\n"
                                              << WithoutTimes(b).dump(1);

  // The command line wins over the file.
  const ProcessResult third = Walking({"--scenario-file", (dir / "scenario.json").string(), "--steps", "2", "--cache",
                                       "", "--summary", (dir / "c.json").string()});
  ASSERT_EQ(third.exit_code, 0) << third.error;
  const nlohmann::json c = ReadJson(dir / "c.json");
  EXPECT_EQ(c.at("scenario").at("steps"), 2);
  EXPECT_EQ(c.at("scenario").at("force-band"), 0.12);
  EXPECT_EQ(c.at("steps_planned").get<int>(), a.at("steps_planned").get<int>() - 1);
}

TEST(WalkingScenarioFile, AnUnknownKeyOrAnOutputIsAnErrorNamingTheKey) {
  const fs::path dir = WorkDir();
  WriteJson(dir / "unknown.json", {{"steps", 3}, {"gait_a", {0.3, 0.4, 0.1, 0.25}}});
  const ProcessResult unknown = Walking({"--scenario-file", (dir / "unknown.json").string(), "--cache", ""});
  EXPECT_EQ(unknown.exit_code, 1);
  EXPECT_NE(unknown.error.find("unknown key 'gait_a'"), std::string::npos) << unknown.error;
  WriteJson(dir / "output.json", {{"summary", "x.json"}});
  const ProcessResult output = Walking({"--scenario-file", (dir / "output.json").string(), "--cache", ""});
  EXPECT_EQ(output.exit_code, 1);
  EXPECT_NE(output.error.find("'summary'"), std::string::npos) << output.error;
  WriteJson(dir / "range.json", {{"gait-a", {0.6, 0.4, 0.1, 0.25}}});
  const ProcessResult range = Walking({"--scenario-file", (dir / "range.json").string(), "--cache", ""});
  EXPECT_EQ(range.exit_code, 1);
  EXPECT_NE(range.error.find("step_length_m = 0.6 m is outside [0.2, 0.45] m"), std::string::npos) << range.error;
}

}  // namespace
}  // namespace rome
