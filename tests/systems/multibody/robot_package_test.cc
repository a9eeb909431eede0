// A robot package reads only regular files inside its own folder tree (issue 45): the sidecar's "urdf" entry and the
// sidecar found beside a URDF must stay inside the package unless LoadOptions::allow_files_outside_package; devices
// and FIFOs are refused at once; FindRobotFile never takes a relative robot path from the current folder unless the
// user writes ./ or ../. Every scratch file lives in a private TempFolder.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <future>
#include <initializer_list>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "framework/files.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/robot_files.h"
#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

namespace fs = std::filesystem;
using test::DataPath;

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

void WriteText(const std::string& path, const std::string& text) {
  fs::create_directories(fs::path(path).parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  const size_t i = s.find(from);
  EXPECT_NE(i, std::string::npos) << from;
  if (i != std::string::npos) s.replace(i, from.size(), to);
  return s;
}

// The refusal must be one printable line holding every fragment.
void ExpectRefusal(const std::string& outcome, std::initializer_list<std::string> fragments) {
  ASSERT_EQ(outcome.rfind("error: ", 0), 0u) << outcome;
  for (const std::string& f : fragments)
    EXPECT_NE(outcome.find(f), std::string::npos) << "'" << f << "' not in: " << outcome;
  for (char c : outcome) EXPECT_GE(static_cast<unsigned char>(c), 0x20u) << outcome;
  EXPECT_LT(outcome.size(), 1000u) << outcome;
}

// Layout in a private folder:
//   ROOT/outside.urdf, ROOT/outside.rome.json   a valid robot outside the package
//   ROOT/pkg/robot/walker2d.urdf                the package's URDF
//   ROOT/pkg/robot/robot.rome.json              the sidecar under test (its "urdf" entry varies)
class RobotPackage : public ::testing::Test {
 protected:
  void SetUp() override {
    urdf_ = ReadText(DataPath("walker2d.urdf"));
    sidecar_ = ReadText(DataPath("walker2d.rome.json"));
    ASSERT_FALSE(urdf_.empty());
    WriteText(root_.File("outside.urdf"), urdf_);
    WriteText(root_.File("outside.rome.json"),
              Replace(sidecar_, R"("urdf": "walker2d.urdf")", R"("urdf": "outside.urdf")"));
    WriteText(Package("walker2d.urdf"), urdf_);
  }

  std::string Package(const std::string& name) const { return root_.File("pkg/robot/" + name); }
  // Writes the package's sidecar with the given "urdf" entry (JSON string content) and returns its path.
  std::string Sidecar(const std::string& entry) const {
    const std::string path = Package("robot.rome.json");
    WriteText(path, Replace(sidecar_, R"("urdf": "walker2d.urdf")", "\"urdf\": \"" + entry + "\""));
    return path;
  }
  std::string Fifo(const std::string& path) {
    fs::create_directories(fs::path(path).parent_path());
    EXPECT_EQ(::mkfifo(path.c_str(), 0600), 0) << path;
    fifos_.push_back(path);
    return path;
  }

  // Runs `load` on another thread: "loaded", or "error: " and the message. A load that has not returned within 10 s
  // fails the test (a FIFO opened without O_NONBLOCK blocks forever); the FIFOs are then opened for writing and
  // closed, which releases it with an empty file.
  std::string Within10s(const std::function<MultibodyModel()>& load) const {
    auto outcome = std::async(std::launch::async, [load]() -> std::string {
      try {
        load();
        return "loaded";
      } catch (const std::exception& e) { return std::string("error: ") + e.what(); }
    });
    if (outcome.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
      ADD_FAILURE() << "the load did not return within 10 s";
      for (const std::string& fifo : fifos_)
        if (const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK); fd >= 0) ::close(fd);
    }
    return outcome.get();
  }
  std::string FromSidecar(const std::string& sidecar, bool allow_outside = false) const {
    LoadOptions options;
    options.allow_files_outside_package = allow_outside;
    return Within10s([sidecar, options] { return MultibodyModel::LoadFromSidecar(sidecar, options); });
  }

  TempFolder root_{"rome_robot_package_test"};
  std::string urdf_, sidecar_;
  std::vector<std::string> fifos_;
};

TEST_F(RobotPackage, RelativeEntriesInsideThePackageLoad) {
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(Sidecar("walker2d.urdf"));
  EXPECT_EQ(model.nv(), MultibodyModel::Load(DataPath("walker2d.urdf")).nv());
  EXPECT_TRUE(model.is_planar());
  EXPECT_TRUE(fs::equivalent(model.urdf_path(), Package("walker2d.urdf")));
  // A subfolder, and a "../" that climbs but stays inside the package.
  WriteText(Package("urdf/w.urdf"), urdf_);
  EXPECT_EQ(FromSidecar(Sidecar("urdf/w.urdf")), "loaded");
  EXPECT_EQ(FromSidecar(Sidecar("./urdf/../walker2d.urdf")), "loaded");
}

TEST_F(RobotPackage, AbsoluteEntriesAreRefused) {
  const std::string sidecar = Package("robot.rome.json");
  for (const std::string& entry : {std::string("/dev/zero"), std::string("/etc/passwd"), root_.File("outside.urdf")})
    ExpectRefusal(FromSidecar(Sidecar(entry)),
                  {sidecar, "\"urdf\"", entry, "is an absolute path", "allow_files_outside_package"});
}

TEST_F(RobotPackage, EntriesThatClimbOutAreRefused) {
  const std::string sidecar = Package("robot.rome.json");
  ExpectRefusal(FromSidecar(Sidecar("../../outside.urdf")),
                {sidecar, "\"urdf\" ../../outside.urdf", "leaves its package folder"});
  ExpectRefusal(FromSidecar(Sidecar("../../../../../../../../../../etc/hostname")),
                {sidecar, "\"urdf\"", "leaves its package folder"});
}

TEST_F(RobotPackage, SymlinksPointingOutAreRefused) {
  fs::create_symlink(root_.File("outside.urdf"), Package("link.urdf"));
  fs::create_directory_symlink(root_.path(), Package("up"));
  const std::string sidecar = Package("robot.rome.json");
  ExpectRefusal(FromSidecar(Sidecar("link.urdf")), {sidecar, "\"urdf\" link.urdf", "leaves its package folder"});
  ExpectRefusal(FromSidecar(Sidecar("up/outside.urdf")),
                {sidecar, "\"urdf\" up/outside.urdf", "leaves its package folder"});
  // A link that stays inside is fine.
  fs::create_symlink("walker2d.urdf", Package("inside_link.urdf"));
  EXPECT_EQ(FromSidecar(Sidecar("inside_link.urdf")), "loaded");
}

TEST_F(RobotPackage, FifosAreRefusedAtOnce) {
  Fifo(Package("fifo.urdf"));
  const std::string sidecar = Sidecar("fifo.urdf");
  ExpectRefusal(FromSidecar(sidecar), {sidecar, "\"urdf\"", "fifo.urdf", "is a FIFO, not a regular file"});
  ExpectRefusal(FromSidecar(sidecar, /*allow_outside=*/true), {"fifo.urdf", "is a FIFO"});
  // The sidecar itself, and a URDF named directly.
  const std::string fifo_sidecar = Fifo(Package("fifo.rome.json"));
  ExpectRefusal(FromSidecar(fifo_sidecar), {"sidecar", fifo_sidecar, "is a FIFO"});
  const std::string fifo_urdf = Fifo(Package("direct.urdf"));
  ExpectRefusal(Within10s([fifo_urdf] { return MultibodyModel::Load(fifo_urdf); }), {"URDF", fifo_urdf, "is a FIFO"});
}

TEST_F(RobotPackage, DevicesAreRefusedEvenWhenOutsideFilesAreAllowed) {
  // Before: "/dev/zero" was read whole, grew past 1 GB and ended in std::bad_alloc.
  const std::string sidecar = Sidecar("/dev/zero");
  ExpectRefusal(FromSidecar(sidecar, /*allow_outside=*/true),
                {sidecar, "\"urdf\" /dev/zero", "is a device, not a regular file"});
  ExpectRefusal(FromSidecar(Sidecar("../../../../../../../../../../dev/null"), true), {"dev/null", "is a device"});
  ExpectRefusal(FromSidecar(Sidecar("."), true), {"is a directory"});
}

TEST_F(RobotPackage, AllowFilesOutsidePackageLoadsThem) {
  fs::create_symlink(root_.File("outside.urdf"), Package("link.urdf"));
  for (const std::string& entry :
       {std::string("../../outside.urdf"), root_.File("outside.urdf"), std::string("link.urdf")}) {
    EXPECT_EQ(FromSidecar(Sidecar(entry), /*allow_outside=*/true), "loaded") << entry;
    EXPECT_NE(FromSidecar(Sidecar(entry)), "loaded") << entry;
  }
  LoadOptions allow;
  allow.allow_files_outside_package = true;
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(Sidecar("../../outside.urdf"), allow);
  EXPECT_TRUE(fs::equivalent(model.urdf_path(), root_.File("outside.urdf")));
}

TEST_F(RobotPackage, TheSidecarBesideAUrdfStaysInside) {
  // pkg/robot/w.urdf with w.rome.json a link to the sidecar outside (planar base): refused, or followed when allowed.
  WriteText(Package("w.urdf"), urdf_);
  fs::create_symlink(root_.File("outside.rome.json"), Package("w.rome.json"));
  const std::string urdf = Package("w.urdf");
  ExpectRefusal(Within10s([urdf] { return MultibodyModel::Load(urdf); }),
                {urdf, "its sidecar w.rome.json", "leaves its package folder"});
  LoadOptions allow;
  allow.allow_files_outside_package = true;
  EXPECT_TRUE(MultibodyModel::Load(urdf, "", allow).is_planar());
  // A FIFO beside the URDF is refused at once.
  fs::remove(Package("w.rome.json"));
  Fifo(Package("w.rome.json"));
  ExpectRefusal(Within10s([urdf] { return MultibodyModel::Load(urdf); }), {"sidecar", "w.rome.json", "is a FIFO"});
}

// ---- FindRobotFile: the current folder only when the user asks for it ----

// A private folder as the current folder, holding a planted robots/amber/ whose sidecar names the robot "planted".
class RobotFileLookup : public ::testing::Test {
 protected:
  void SetUp() override {
    WriteText(root_.File("robots/amber/amber.urdf"), ReadText(test::SourcePath("robots/amber/amber.urdf")));
    const std::string real = ReadText(test::SourcePath("robots/amber/amber.rome.json"));
    WriteText(root_.File("robots/amber/amber.rome.json"),
              Replace(real, R"("robot": "amber")", R"("robot": "planted")"));
    WriteText(root_.File("robots/only_here/only_here.rome.json"), real);
    WriteText(root_.File("robots/only_here/amber.urdf"), ReadText(test::SourcePath("robots/amber/amber.urdf")));
    fs::create_directories(root_.File("sub"));
    previous_ = fs::current_path();
    fs::current_path(root_.path());
  }
  void TearDown() override { fs::current_path(previous_); }

  TempFolder root_{"rome_robot_file_lookup_test"};
  fs::path previous_;
};

TEST_F(RobotFileLookup, PlainRelativePathsComeFromTheDataFolders) {
  const std::string found = FindRobotFile("robots/amber/amber.rome.json");
  EXPECT_FALSE(fs::equivalent(found, root_.File("robots/amber/amber.rome.json"))) << found;
  bool in_a_data_folder = false;
  for (const std::string& folder : RobotDataFolders()) in_a_data_folder |= found.rfind(folder, 0) == 0;
  EXPECT_TRUE(in_a_data_folder) << found;
  EXPECT_EQ(MultibodyModel::LoadFromSidecar("robots/amber/amber.rome.json").name(), "amber");
  EXPECT_EQ(MultibodyModel::Load("robots/amber/amber.urdf").name(), "amber");
}

TEST_F(RobotFileLookup, DotSlashReadsTheCurrentFolder) {
  EXPECT_TRUE(
      fs::equivalent(FindRobotFile("./robots/amber/amber.rome.json"), root_.File("robots/amber/amber.rome.json")));
  EXPECT_EQ(MultibodyModel::LoadFromSidecar("./robots/amber/amber.rome.json").name(), "planted");
  fs::current_path(root_.File("sub"));
  EXPECT_EQ(MultibodyModel::LoadFromSidecar("../robots/amber/amber.rome.json").name(), "planted");
  const std::string absolute = root_.File("robots/amber/amber.rome.json");
  EXPECT_EQ(FindRobotFile(absolute), absolute);
}

TEST_F(RobotFileLookup, AFileOnlyInTheCurrentFolderIsNotFoundAndTheErrorSaysHow) {
  try {
    FindRobotFile("robots/only_here/only_here.rome.json");
    ADD_FAILURE() << "a file of the current folder was found without ./";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("robot file robots/only_here/only_here.rome.json: file does not exist in the data folders"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("write ./robots/only_here/only_here.rome.json to read it from the current folder"),
              std::string::npos)
        << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  EXPECT_EQ(MultibodyModel::LoadFromSidecar("./robots/only_here/only_here.rome.json").name(), "amber");
}

}  // namespace
}  // namespace rome
