#pragma once
// Whole-file text helpers for tests (binary-safe): scratch inputs written and outputs read back.

#include <fstream>
#include <sstream>
#include <string>

namespace rome::test {

/// The content of `path` ("" if it cannot be read).
inline std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// Writes `text` to `path`, replacing it.
inline void WriteText(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

}  // namespace rome::test
