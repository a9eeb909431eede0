#include "tests/common/source_path.h"

#include <stdexcept>

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

}  // namespace rome::test
