// libFuzzer harness for a robot package's file handling: the input is written as the sidecar of a package folder and
// loaded through MultibodyModel::LoadFromSidecar, so its "urdf" entry (absolute paths, "../", links, odd bytes) is
// resolved and read as a shared package's would be.
//
// The package, in a private folder made once per process:
//   ROOT/outside.urdf                    a valid URDF outside the package
//   ROOT/pkg/robot.urdf                  the package's valid URDF
//   ROOT/pkg/robot.rome.json             the fuzz input
//   ROOT/pkg/sub/                        an empty folder
//   ROOT/pkg/up -> ROOT                  a folder link pointing out
//   ROOT/pkg/link.urdf -> ROOT/outside.urdf, ROOT/pkg/self.urdf -> robot.urdf
//   ROOT/pkg/fifo.urdf                   a FIFO (no writer: opening it for reading without O_NONBLOCK would block)
// Fine: a model whose URDF lies inside ROOT/pkg, or std::runtime_error (the loader's documented error) whose message
// is one line. A finding: a model read from outside the package, any other exception, a multi-line message, a crash,
// a sanitizer report, or a hang (libFuzzer -timeout).
#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include "framework/files.h"
#include "systems/multibody/multibody_model.h"

namespace {

namespace fs = std::filesystem;

[[noreturn]] void Finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "robot_package_fuzzer: %s: %s\n", what, detail.c_str());
  std::abort();
}

const char* const kUrdf = R"(<?xml version="1.0"?>
<robot name="pendulum">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="arm"><inertial><mass value="1"/><origin xyz="0 0 -0.5"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <joint name="hinge" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="10" velocity="5"/></joint>
</robot>
)";

void Write(const std::string& path, const char* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(data, static_cast<std::streamsize>(size));
  if (!out) Finding("cannot write the package file", path);
}

// The package folder (see above), made on first use; removed with ROOT when the process exits.
struct Package {
  rome::TempFolder root{"rome_robot_package_fuzzer"};
  std::string folder = root.File("pkg");
  std::string canonical_folder;
  std::string sidecar = folder + "/robot.rome.json";

  Package() {
    fs::create_directories(folder + "/sub");
    Write(root.File("outside.urdf"), kUrdf, std::strlen(kUrdf));
    Write(folder + "/robot.urdf", kUrdf, std::strlen(kUrdf));
    fs::create_directory_symlink(root.path(), folder + "/up");
    fs::create_symlink(root.File("outside.urdf"), folder + "/link.urdf");
    fs::create_symlink("robot.urdf", folder + "/self.urdf");
    if (::mkfifo((folder + "/fifo.urdf").c_str(), 0600) != 0) Finding("cannot make the FIFO", folder);
    canonical_folder = fs::canonical(folder).string();
  }
};

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const Package package;
  Write(package.sidecar, reinterpret_cast<const char*>(data), size);
  try {
    const rome::MultibodyModel model = rome::MultibodyModel::LoadFromSidecar(package.sidecar);
    std::error_code ec;
    const std::string urdf = fs::canonical(model.urdf_path(), ec).string();
    if (ec || urdf.compare(0, package.canonical_folder.size() + 1, package.canonical_folder + "/") != 0)
      Finding("a URDF outside the package was read", model.urdf_path());
  } catch (const std::runtime_error& e) {
    if (std::strchr(e.what(), '\n') != nullptr) Finding("multi-line error message", e.what());
  } catch (const std::exception& e) { Finding("an exception other than std::runtime_error", e.what()); }
  return 0;
}
