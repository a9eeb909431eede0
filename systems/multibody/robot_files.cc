#include "systems/multibody/robot_files.h"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "framework/install_location.h"
#include "framework/text.h"

namespace rome {

namespace {

// Whether the user named the file relative to the current folder on purpose: "./x", "../x", "." or "..".
bool NamesCurrentFolder(const std::filesystem::path& path) {
  const auto first = path.begin();
  return first != path.end() && (*first == "." || *first == "..");
}

}  // namespace

std::vector<std::string> RobotDataFolders() {
  std::vector<std::string> folders;
  if (const char* env = std::getenv("ROME_DATA_DIR"); env != nullptr && *env != '\0') folders.emplace_back(env);
  if (std::string installed = InstalledDataFolder(); !installed.empty()) folders.push_back(std::move(installed));
  return folders;
}

std::string FindRobotFile(const std::string& path) {
  namespace fs = std::filesystem;
  if (path.empty()) throw std::runtime_error("robot file: the path is empty");
  const fs::path given(path);
  if (given.is_absolute() || NamesCurrentFolder(given)) return path;
  std::error_code ec;
  std::string tried;
  for (const std::string& folder : RobotDataFolders()) {
    const fs::path candidate = fs::path(folder) / given;
    if (fs::is_regular_file(candidate, ec))
      return fs::absolute(candidate, ec).string();  // absolute: a second lookup finds it as given
    tried += (tried.empty() ? "'" : ", '") + Excerpt(candidate.string(), 200) + "'";
  }
  const std::string shown = Excerpt(path, 200);
  throw std::runtime_error(
      "robot file " + shown + ": file does not exist in the data folders (looked at " +
      (tried.empty() ? std::string("none: no data folder is set") : tried) + "); write ./" + shown +
      " to read it from the current folder, or set ROME_DATA_DIR to the folder that holds robots/");
}

}  // namespace rome
