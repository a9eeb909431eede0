// Plots and outputs of the example programs at the trust boundary: gnuplot gets every text through GnuplotString and
// runs without a shell, so backquotes, $(...), quotes and newlines in a title or a path run nothing (checked by the
// files such commands would create); a PNG is written atomically, never through a planted symlink.
#include "systems/visualization/plot.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "examples/common/cli.h"
#include "framework/process.h"
#include "framework/files.h"
#include "framework/text.h"
#include "tests/common/text_files.h"

namespace rome::visualization {
namespace {

namespace fs = std::filesystem;
using examples::CommandLine;
using examples::WriteOutputFile;

// Each string, if a shell or gnuplot ran it, would create the file named by its marker in the current folder.
std::vector<std::string> Hostile(const std::string& marker) {
  return {"`touch " + marker + "1`",
          "$(touch " + marker + "2)",
          "'; system('touch " + marker + "3'); '",
          "\"`touch " + marker + "4`\"",
          "line\n!touch " + marker + "5\nprint 1",
          "@x"};
}

// Runs `body` in a fresh current folder and checks that it created nothing there but the files it names.
class InScratchFolder : public ::testing::Test {
 protected:
  void SetUp() override {
    old_ = fs::current_path();
    fs::current_path(scratch_.path());
  }
  void TearDown() override { fs::current_path(old_); }
  std::vector<std::string> FilesHere() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(scratch_.path())) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
  TempFolder scratch_;
  fs::path old_;
};

TEST_F(InScratchFolder, GnuplotPrintsEveryHostileStringVerbatim) {
  for (const std::string& s : Hostile("pwned")) {
    WriteFileAtomically("print.gp", "set print '-'\nprint " + GnuplotString(s) + "\n", "script");
    const ProcessResult run = RunProgram({"gnuplot", "print.gp"});
    ASSERT_TRUE(run.started) << run.error;
    EXPECT_EQ(run.exit_code, 0) << run.error;
    std::string expected = s;
    std::replace(expected.begin(), expected.end(), '\n', ' ');
    EXPECT_EQ(run.out, expected + "\n");
  }
  EXPECT_EQ(FilesHere(), std::vector<std::string>{"print.gp"});
}

TEST_F(InScratchFolder, HostileTitlesAndPathsRunNothing) {
  const std::vector<std::string> hostile = Hostile("pwned");
  std::string folder = "out `touch pwned6` $(touch pwned7) ' \" \n x";
  fs::create_directories(folder);
  PlotSpec spec{hostile[0],
                hostile[1],
                hostile[2],
                {{hostile[3], {0, 1, 2}, {0, 1, 4}, "lines"}, {hostile[4], {0, 1}, {1, 0}, "points"}}};
  std::string error;
  const std::string png = folder + "/p`touch pwned8`$(touch pwned9).png";
  ASSERT_TRUE(WritePlot(spec, png, &error)) << error;
  EXPECT_EQ(rome::test::ReadText(png).substr(0, 8), "\x89PNG\r\n\x1a\n");
  EXPECT_EQ(FilesHere(), std::vector<std::string>{folder});
  std::vector<std::string> in_folder;
  for (const auto& e : fs::directory_iterator(folder)) in_folder.push_back(e.path().filename().string());
  EXPECT_EQ(in_folder, std::vector<std::string>{"p`touch pwned8`$(touch pwned9).png"});
}

TEST_F(InScratchFolder, APlantedSymlinkAtThePlotIsReplacedNotFollowed) {
  TempFolder elsewhere;
  std::ofstream(elsewhere.File("victim")) << "precious";
  ASSERT_EQ(::symlink(elsewhere.File("victim").c_str(), "com.png"), 0);
  std::string error;
  ASSERT_TRUE(WritePlot({"t", "x", "y", {{"s", {0, 1}, {0, 1}, "lines"}}}, "com.png", &error)) << error;
  EXPECT_EQ(rome::test::ReadText(elsewhere.File("victim")), "precious");
  EXPECT_FALSE(fs::is_symlink("com.png"));
  EXPECT_EQ(rome::test::ReadText("com.png").substr(0, 4), "\x89PNG");
}

TEST_F(InScratchFolder, TwoOutputsCannotNameOneFile) {
  CommandLine cli("prog", "test");
  cli.Option("log", "", "").Option("summary", "", "");
  const char* argv[] = {"prog", "--log", "out.csv", "--summary", "./out.csv"};
  ASSERT_TRUE(cli.Parse(5, const_cast<char**>(argv)));
  try {
    cli.CheckOutputs({"log", "summary"}, {});
    FAIL() << "the same file was accepted twice";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "prog: --summary and --log name the same file './out.csv'; give each output its own file");
  }
  EXPECT_TRUE(FilesHere().empty());  // the check creates nothing
}

// --scenario-file (CommandLine::ScenarioFile): values of each JSON type reach the options exactly (0.1 + 0.2 is
// 0.30000000000000004, not 0.3), the command line wins, ScenarioJson writes every parameter but the outputs, and a
// second parse of that text gives the same values; unknown keys and outputs are refused, naming the key.
TEST_F(InScratchFolder, ScenarioFileRoundTripsEveryParameterExactly) {
  auto declare = [](CommandLine& cli) {
    cli.Option("gain", "1", "")
        .Option("steps", "3", "")
        .Option("terrain", "flat", "")
        .Option("speed", "0.5", "")
        .Flag("fast", "")
        .Option("log", "", "");
    cli.ScenarioFile({"log"});
  };
  test::WriteText("s.json",
                  R"({"gain": 0.30000000000000004, "steps": 7, "terrain": "stairs", "speed": 2.5, "fast": true})");
  CommandLine cli("prog", "test");
  declare(cli);
  const char* argv[] = {"prog", "--scenario-file", "s.json", "--speed", "1.25", "--log", "x.csv"};
  ASSERT_TRUE(cli.Parse(7, const_cast<char**>(argv)));
  EXPECT_EQ(cli.GetDouble("gain"), 0.1 + 0.2);
  EXPECT_EQ(cli.GetInt("steps"), 7);
  EXPECT_EQ(cli.Get("terrain"), "stairs");
  EXPECT_EQ(cli.GetDouble("speed"), 1.25);  // the command line wins
  EXPECT_TRUE(cli.GetFlag("fast"));
  const std::string scenario = cli.ScenarioJson();
  EXPECT_EQ(scenario.find("log"), std::string::npos) << scenario;
  test::WriteText("again.json", scenario);
  CommandLine again("prog", "test");
  declare(again);
  const char* argv2[] = {"prog", "--scenario-file", "again.json"};
  ASSERT_TRUE(again.Parse(3, const_cast<char**>(argv2)));
  EXPECT_EQ(again.GetDouble("gain"), 0.1 + 0.2);
  EXPECT_EQ(again.GetInt("steps"), 7);
  EXPECT_EQ(again.Get("terrain"), "stairs");
  EXPECT_EQ(again.GetDouble("speed"), 1.25);
  EXPECT_TRUE(again.GetFlag("fast"));
  for (const auto& [text, message] : std::vector<std::pair<std::string, std::string>>{
           {R"({"gian": 1})", "prog: --scenario-file bad.json: unknown key 'gian' (see --help)"},
           {R"({"log": "y.csv"})",
            "prog: --scenario-file bad.json: unknown key 'log' (an output or the file itself, not a scenario "
            "parameter)"},
           {R"({"fast": 1})", "prog: --scenario-file bad.json: key 'fast' needs true or false, got 1"}}) {
    test::WriteText("bad.json", text);
    CommandLine bad("prog", "test");
    declare(bad);
    const char* argv3[] = {"prog", "--scenario-file", "bad.json"};
    try {
      bad.Parse(3, const_cast<char**>(argv3));
      ADD_FAILURE() << "accepted " << text;
    } catch (const std::invalid_argument& e) { EXPECT_EQ(std::string(e.what()), message); }
  }
}

TEST(WriteOutputFile, AFailedWriteIsReportedAndReturnsFalse) {
  testing::internal::CaptureStderr();
  EXPECT_FALSE(WriteOutputFile("prog", "/dev/full", "{}", "summary"));
  EXPECT_EQ(testing::internal::GetCapturedStderr(),
            "prog: summary /dev/full: is a device, not a regular file; give a file name\n");
}

}  // namespace
}  // namespace rome::visualization
