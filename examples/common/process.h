#pragma once
// Running another program without a shell: an argument list goes to posix_spawnp as it is, so no byte of a path or
// a label can be read as shell syntax.

#include <string>
#include <vector>

namespace rome::examples {

struct ProcessResult {
  bool started = false;     ///< false: the program could not be started (not installed); `error` says why
  int exit_code = -1;       ///< the program's exit code; -1 if it died from a signal or was not started
  std::string out;          ///< what it wrote on standard output
  std::string error;        ///< why it could not be started, or the first line it wrote on standard error
};

/// Runs argv[0] (looked up on PATH) with the arguments argv[1..], standard input from /dev/null, and waits for it.
/// Standard output is captured whole up to `max_output_bytes` (beyond it the program is killed and exit_code is -1).
ProcessResult RunProgram(const std::vector<std::string>& argv, size_t max_output_bytes = 256u << 20);

}  // namespace rome::examples
