// framework/files.h at the trust boundary: what ReadRegularFile refuses (and that it refuses at once), that
// AtomicFileWriter never writes through a planted symlink and keeps the old file when a write fails or is abandoned,
// and that ResolveInsideFolder keeps a package's paths inside it.
#include "framework/files.h"

#include <gtest/gtest.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <future>
#include <sstream>

#include "tests/common/text_files.h"

namespace rome {
namespace {

namespace fs = std::filesystem;

// The message of the std::runtime_error that `f` throws ("" if none).
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const std::runtime_error& e) { return e.what(); }
  return "";
}

// Files in `folder` besides `keep`: a temporary file left behind would show here.
std::vector<std::string> OtherFiles(const std::string& folder, const std::vector<std::string>& keep) {
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (std::find(keep.begin(), keep.end(), name) == keep.end()) out.push_back(name);
  }
  return out;
}

TEST(ReadRegularFile, ReadsAFileWhole) {
  TempFolder dir;
  std::string text(200000, 'a');
  text[12345] = '\0';  // binary content survives
  test::WriteText(dir.File("f"), text);
  EXPECT_EQ(ReadRegularFile(dir.File("f"), "test file", 1u << 20), text);
  EXPECT_EQ(ReadRegularFile(dir.File("f"), "test file", text.size()), text);  // exactly at the cap
  EXPECT_NE(
      ErrorOf([&] { ReadRegularFile(dir.File("f"), "test file", text.size() - 1); }).find("limit is 199999 bytes"),
      std::string::npos);
}

TEST(ReadRegularFile, RefusesWhatIsNotARegularFile) {
  TempFolder dir;
  EXPECT_EQ(ErrorOf([] { ReadRegularFile("/dev/zero", "terrain", 1u << 20); }),
            "terrain /dev/zero: is a device, not a regular file");
  EXPECT_EQ(ErrorOf([&] { ReadRegularFile(dir.path(), "URDF", 1u << 20); }),
            "URDF " + dir.path() + ": is a directory, not a regular file");
  EXPECT_EQ(ErrorOf([&] { ReadRegularFile(dir.File("none"), "URDF", 1u << 20); }),
            "URDF " + dir.File("none") + ": file does not exist");
  ASSERT_EQ(::mkfifo(dir.File("fifo").c_str(), 0600), 0);
  // A FIFO with no writer would block a plain open() forever: the read runs on its own thread with a deadline.
  auto fifo = std::async(std::launch::async,
                         [&] { return ErrorOf([&] { ReadRegularFile(dir.File("fifo"), "sidecar", 1u << 20); }); });
  if (fifo.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
    const int writer = ::open(dir.File("fifo").c_str(), O_WRONLY | O_NONBLOCK);  // releases the blocked reader
    if (writer >= 0) ::close(writer);
    FAIL() << "reading a FIFO blocked";
  }
  EXPECT_EQ(fifo.get(), "sidecar " + dir.File("fifo") + ": is a FIFO, not a regular file");
}

TEST(AtomicFileWriter, ReplacesAPlantedSymlinkInsteadOfFollowingIt) {
  TempFolder out, elsewhere;
  test::WriteText(elsewhere.File("victim"), "precious");
  ASSERT_EQ(::symlink(elsewhere.File("victim").c_str(), out.File("summary.json").c_str()), 0);
  WriteFileAtomically(out.File("summary.json"), "{}\n", "summary");
  EXPECT_EQ(test::ReadText(elsewhere.File("victim")), "precious");
  EXPECT_FALSE(fs::is_symlink(out.File("summary.json")));
  EXPECT_EQ(test::ReadText(out.File("summary.json")), "{}\n");
  EXPECT_TRUE(OtherFiles(out.path(), {"summary.json"}).empty());
}

TEST(AtomicFileWriter, AnAbandonedWriteKeepsTheOldFile) {
  TempFolder out;
  test::WriteText(out.File("log.csv"), "old\n");
  {
    AtomicFileWriter writer(out.File("log.csv"), "log");
    writer.Append("t,x\n0,1\n");
  }  // destroyed without Commit, as by an exception during the run
  EXPECT_EQ(test::ReadText(out.File("log.csv")), "old\n");
  EXPECT_TRUE(OtherFiles(out.path(), {"log.csv"}).empty());
}

// A write that fails part way (the file size limit stands in for a full disk): Commit reports it naming the file,
// the old content stays, and no temporary file is left. In a child process, so the limit touches nothing else.
TEST(AtomicFileWriter, AFailedWriteIsReportedAndKeepsTheOldFile) {
  TempFolder out;
  test::WriteText(out.File("log.csv"), "old\n");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    ::setrlimit(RLIMIT_FSIZE, &limit);
    const std::string error =
        ErrorOf([&] { WriteFileAtomically(out.File("log.csv"), std::string(1 << 20, 'x'), "log"); });
    const bool named = error.rfind("log " + out.File("log.csv") + ": writing failed", 0) == 0;
    std::_Exit(named ? 0 : 1);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the failed write was not reported with the file's name";
  EXPECT_EQ(test::ReadText(out.File("log.csv")), "old\n");
  EXPECT_TRUE(OtherFiles(out.path(), {"log.csv"}).empty());
}

TEST(AtomicFileWriter, RefusesDevicesFoldersAndMissingFolders) {
  TempFolder out;
  EXPECT_EQ(CheckOutputPath("/dev/full", "summary"),
            "summary /dev/full: is a device, not a regular file; give a file name");
  EXPECT_EQ(CheckOutputPath(out.path(), "log"), "log " + out.path() + ": is a directory, not a file");
  EXPECT_EQ(CheckOutputPath(out.File("no/x.csv"), "log"),
            "log " + out.File("no/x.csv") + ": the folder " + out.File("no") + " does not exist");
  EXPECT_EQ(CheckOutputPath(out.File("x.csv"), "log"), "");
  EXPECT_THROW(AtomicFileWriter("/dev/full", "summary"), std::runtime_error);
  struct stat st {};
  ASSERT_EQ(::stat("/dev/full", &st), 0);
  EXPECT_TRUE(S_ISCHR(st.st_mode)) << "/dev/full was replaced";
}

TEST(ResolveInsideFolder, KeepsPathsInsideTheirPackage) {
  TempFolder pkg, outside;
  fs::create_directories(pkg.File("meshes"));
  test::WriteText(pkg.File("meshes/a.urdf"), "x");
  test::WriteText(outside.File("secret"), "x");
  EXPECT_EQ(ResolveInsideFolder(pkg.path(), "meshes/a.urdf", "urdf"),
            fs::canonical(pkg.File("meshes/a.urdf")).string());
  EXPECT_EQ(ResolveInsideFolder(pkg.path(), "meshes/../meshes/a.urdf", "urdf"),
            fs::canonical(pkg.File("meshes/a.urdf")).string());
  EXPECT_NE(ErrorOf([&] { ResolveInsideFolder(pkg.path(), "/etc/passwd", "urdf"); }).find("is an absolute path"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              ResolveInsideFolder(pkg.path(), "../" + fs::path(outside.path()).filename().string() + "/secret", "urdf");
            }).find("leaves its package folder"),
            std::string::npos);
  ASSERT_EQ(::symlink(outside.File("secret").c_str(), pkg.File("link").c_str()), 0);
  EXPECT_NE(ErrorOf([&] { ResolveInsideFolder(pkg.path(), "link", "urdf"); }).find("leaves its package folder"),
            std::string::npos);
  // A missing folder before "..": resolved by text alone, "nope/../link" would be "link" inside the package, and
  // reading it would follow the link out. The system does not resolve it at all (nope does not exist): refused.
  EXPECT_NE(ErrorOf([&] { ResolveInsideFolder(pkg.path(), "nope/../link", "urdf"); }).find("file does not exist"),
            std::string::npos);
  ASSERT_EQ(::symlink("/", pkg.File("up").c_str()), 0);
  EXPECT_NE(ErrorOf([&] { ResolveInsideFolder(pkg.path(), "x/../up/etc/passwd", "urdf"); }).find("file does not exist"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              ResolveInsideFolder(pkg.path(), "meshes/../up/etc/passwd", "urdf");
            }).find("leaves its package folder"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { ResolveInsideFolder(pkg.path(), "meshes/none.urdf", "urdf"); }).find("file does not exist"),
            std::string::npos);
  // A sibling folder whose name starts with the package's is outside too (a prefix is not a parent).
  fs::create_directories(pkg.path() + "-evil");
  test::WriteText(pkg.path() + "-evil/x", "x");
  EXPECT_NE(ErrorOf([&] {
              ResolveInsideFolder(pkg.path(), "../" + fs::path(pkg.path()).filename().string() + "-evil/x", "urdf");
            }).find("leaves its package folder"),
            std::string::npos);
  fs::remove_all(pkg.path() + "-evil");
}

TEST(TempFolder, IsPrivateAndRemovedWithItsContent) {
  std::string path;
  {
    TempFolder dir("rome-files-test");
    path = dir.path();
    struct stat st {};
    ASSERT_EQ(::stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0700u);
    fs::create_directories(dir.File("a/b"));
    test::WriteText(dir.File("a/b/c"), "x");
  }
  EXPECT_FALSE(fs::exists(path));
}

}  // namespace
}  // namespace rome
