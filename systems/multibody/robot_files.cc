#include "systems/multibody/robot_files.h"

#include <cstdlib>
#include <filesystem>
#include <stdexcept>

namespace rome {

std::vector<std::string> RobotDataFolders() {
  std::vector<std::string> folders;
  if (const char* env = std::getenv("ROME_DATA_DIR"); env != nullptr && *env != '\0') folders.emplace_back(env);
#ifdef ROME_INSTALL_DATA_DIR
  folders.emplace_back(ROME_INSTALL_DATA_DIR);
#endif
#ifdef ROME_SOURCE_DATA_DIR
  folders.emplace_back(ROME_SOURCE_DATA_DIR);
#endif
  return folders;
}

std::string FindRobotFile(const std::string& path) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (path.empty()) throw std::runtime_error("robot file: the path is empty");
  if (fs::exists(path, ec)) return path;  // the loader names what is wrong with it (a directory, too large, ...)
  std::string tried = "'" + path + "'";
  if (fs::path(path).is_relative())
    for (const std::string& folder : RobotDataFolders()) {
      const fs::path candidate = fs::path(folder) / path;
      if (fs::is_regular_file(candidate, ec)) return candidate.string();
      tried += ", '" + candidate.string() + "'";
    }
  throw std::runtime_error("robot file " + path + ": file does not exist (looked at " + tried + "; set ROME_DATA_DIR to the folder that holds robots/)");
}

}  // namespace rome
