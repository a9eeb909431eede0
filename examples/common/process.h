#pragma once
// Child processes without a shell: a program path and its arguments as a list, so that no character of a path or a
// value (quotes, backquotes, $(...), newlines) is ever interpreted.

#include <sys/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace rome::examples {

/// How a child process ended: its exit code (0-255), or the signal that killed it.
struct ExitStatus {
  int code = 0;    ///< the exit code if it exited, else 0
  int signal = 0;  ///< the signal that ended it, else 0
};

/// Waits for the child `pid` (through EINTR). A failed wait reports code 127.
ExitStatus WaitForChild(pid_t pid);

/// The output of a finished program.
struct ProcessOutput {
  ExitStatus status;
  std::string output;  ///< its stdout and stderr, interleaved, cut at max_bytes (the rest is read and dropped)
};

/// Runs the program at argv[0] (a path, not looked up in PATH) with the arguments argv[1...], stdin from /dev/null,
/// and collects its output. Throws std::runtime_error naming the program if it cannot be started.
ProcessOutput RunAndCapture(const std::vector<std::string>& argv, size_t max_bytes);

/// argv as a null-terminated array for exec/posix_spawn, pointing into `args` (which must outlive it).
std::vector<char*> ArgvOf(std::vector<std::string>& args);

}  // namespace rome::examples
