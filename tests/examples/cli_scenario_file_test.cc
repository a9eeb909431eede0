// CommandLine::ScenarioFile (--scenario-file) and ScenarioJson (examples/common/cli.h): the scenario a program writes
// reads back to the same option values, bit for bit for numbers; the command line wins over the file; unknown keys,
// refused keys and values of another type are errors naming the key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "examples/common/cli.h"
#include "tests/common/source_path.h"
#include "tests/common/text_files.h"

namespace rome::examples {
namespace {

CommandLine Declared() {
  CommandLine cli("demo", "test program");
  cli.Option("gain", "0.1", "a number")
      .Option("gains", "1,2,3", "numbers")
      .Option("count", "6", "an integer")
      .Option("mode", "auto", "a word");
  cli.Option("out", "", "an output").Flag("fast", "a flag").ScenarioFile({"out"});
  return cli;
}

void Parse(CommandLine& cli, std::vector<std::string> args) {
  args.insert(args.begin(), "demo");
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  ASSERT_TRUE(cli.Parse(static_cast<int>(argv.size()), argv.data()));
}

TEST(CliScenarioFile, TheWrittenScenarioReadsBackToTheSameValues) {
  CommandLine first = Declared();
  // 0.1 + 0.2 and 1e-7 need all 17 digits / an exponent to round-trip.
  Parse(first,
        {"--gain", "0.30000000000000004", "--gains", "1e-07,-2.5,3", "--count", "12", "--mode", "min-norm", "--fast"});
  const nlohmann::json scenario = nlohmann::json::parse(first.ScenarioJson());
  EXPECT_FALSE(scenario.contains("out"));
  EXPECT_EQ(scenario.at("count"), 12);
  EXPECT_TRUE(scenario.at("count").is_number_integer());
  EXPECT_EQ(scenario.at("gains"), nlohmann::json({1e-7, -2.5, 3.0}));
  EXPECT_EQ(scenario.at("mode"), "min-norm");
  EXPECT_EQ(scenario.at("fast"), true);
  const std::string path = test::ScratchDir() + "/scenario.json";
  test::WriteText(path, scenario.dump());
  CommandLine second = Declared();
  Parse(second, {"--scenario-file", path});
  EXPECT_EQ(second.GetDouble("gain"), 0.1 + 0.2);
  EXPECT_EQ(second.GetNumbers("gains", 3, "a,b,c"), (std::vector<double>{1e-7, -2.5, 3.0}));
  EXPECT_EQ(second.GetInt("count"), 12);
  EXPECT_EQ(second.Get("mode"), "min-norm");
  EXPECT_TRUE(second.GetFlag("fast"));
  EXPECT_EQ(nlohmann::json::parse(second.ScenarioJson()), scenario);
}

TEST(CliScenarioFile, TheCommandLineWinsAndBadKeysAreNamed) {
  const std::string path = test::ScratchDir() + "/partial.json";
  test::WriteText(path, R"({"count": 3, "gain": 0.5})");
  CommandLine cli = Declared();
  Parse(cli, {"--count", "4", "--scenario-file", path});
  EXPECT_EQ(cli.GetInt("count"), 4);
  EXPECT_EQ(cli.GetDouble("gain"), 0.5);
  EXPECT_EQ(cli.Get("mode"), "auto");  // neither: the default
  const auto error = [&](const std::string& text) {
    test::WriteText(path, text);
    CommandLine c = Declared();
    std::vector<std::string> args = {"demo", "--scenario-file", path};
    std::vector<char*> argv;
    for (std::string& a : args) argv.push_back(a.data());
    try {
      c.Parse(static_cast<int>(argv.size()), argv.data());
    } catch (const std::invalid_argument& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  EXPECT_NE(error(R"({"gian": 1})").find("unknown key 'gian'"), std::string::npos);
  EXPECT_NE(
      error(R"({"out": "x.csv"})").find("unknown key 'out' (an output or the file itself, not a scenario parameter)"),
      std::string::npos);
  EXPECT_NE(error(R"({"gains": [1, "2"]})").find("key 'gains'"), std::string::npos);
  EXPECT_NE(error(R"({"fast": 1})").find("key 'fast' needs true or false"), std::string::npos);
  EXPECT_NE(error(R"([1, 2])").find("expected a JSON object"), std::string::npos);
  EXPECT_NE(error("{").find("malformed JSON"), std::string::npos);
  EXPECT_NE(error(R"({"gain": 0.1, "gain": 0.7})").find("top level: key 'gain' appears twice"), std::string::npos);
}

// A flag set in the scenario file is turned off from the command line with --FLAG=false; a value that would not read
// back as the same text as a number ("007", "0.30") stays a string in the written scenario.
TEST(CliScenarioFile, TheCommandLineTurnsAFileFlagOffAndTextStaysText) {
  const std::string path = test::ScratchDir() + "/flag.json";
  test::WriteText(path, R"({"fast": true})");
  CommandLine on = Declared();
  Parse(on, {"--scenario-file", path});
  EXPECT_TRUE(on.GetFlag("fast"));
  CommandLine off = Declared();
  Parse(off, {"--scenario-file", path, "--fast=false"});
  EXPECT_FALSE(off.GetFlag("fast"));
  CommandLine text = Declared();
  Parse(text, {"--mode", "007", "--gains", "0.30,2,3"});
  const nlohmann::json scenario = nlohmann::json::parse(text.ScenarioJson());
  EXPECT_EQ(scenario.at("mode"), "007");
  EXPECT_EQ(scenario.at("gains"), "0.30,2,3");
}

}  // namespace
}  // namespace rome::examples
