#include "tests/common/source_path.h"

#include <cstdlib>
#include <stdexcept>

#include "framework/files.h"

namespace rome::test {

std::string SourcePath(std::string_view relative) {
  if (!relative.empty() && relative.front() == '/') {
    throw std::invalid_argument("SourcePath: relative path '" + std::string(relative) + "' starts with '/'");
  }
  static const std::string root = ROME_SOURCE_DIR;
  std::string path;
  path.reserve(root.size() + 1 + relative.size());
  path.append(root);
  path.push_back('/');
  path.append(relative);
  return path;
}

const std::string& ScratchDir() {
  static const TempFolder folder("rome-test");
  return folder.path();
}

std::string TestPlanCacheDir(std::string_view name) {
  std::string path;
  const char* xdg = std::getenv("XDG_CACHE_HOME");
  const char* home = std::getenv("HOME");
  if (xdg != nullptr && *xdg == '/') {
    path.append(xdg);
    path.append("/rome/test_plans/");
  } else if (home != nullptr && *home == '/') {
    path.append(home);
    path.append("/.cache/rome/test_plans/");
  } else {
    path.append(ROME_BINARY_DIR);
    path.append("/test_cache/");
  }
  path.append(name);
  return path;
}

}  // namespace rome::test
