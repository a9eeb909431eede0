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
  return {"`touch " + marker + "1`", "$(touch " + marker + "2)", "'; system('touch " + marker + "3'); '", "\"`touch " + marker + "4`\"",
          "line\n!touch " + marker + "5\nprint 1", "@x"};
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
  PlotSpec spec{hostile[0], hostile[1], hostile[2], {{hostile[3], {0, 1, 2}, {0, 1, 4}, "lines"}, {hostile[4], {0, 1}, {1, 0}, "points"}}};
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
    EXPECT_EQ(std::string(e.what()), "prog: --summary and --log name the same file './out.csv'; give each output its own file");
  }
  EXPECT_TRUE(FilesHere().empty());  // the check creates nothing
}

TEST(WriteOutputFile, AFailedWriteIsReportedAndReturnsFalse) {
  testing::internal::CaptureStderr();
  EXPECT_FALSE(WriteOutputFile("prog", "/dev/full", "{}", "summary"));
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "prog: summary /dev/full: is a device, not a regular file; give a file name\n");
}

}  // namespace
}  // namespace rome::visualization
