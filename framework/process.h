#pragma once
// Child processes without a shell: a program and its arguments as a list, so that no character of a path or a value
// (quotes, backquotes, $(...), newlines) is ever interpreted.

#include <sys/types.h>

#include <cstddef>
#include <string>
#include <vector>

namespace rome {

/// How a child process ended: its exit code (0-255), or the signal that killed it.
struct ExitStatus {
  int code = 0;    ///< the exit code if it exited, else 0
  int signal = 0;  ///< the signal that ended it, else 0
};

/// Waits for the child `pid` (through EINTR). A failed wait reports code 127.
ExitStatus WaitForChild(pid_t pid);

/// argv as a null-terminated array for exec/posix_spawn, pointing into `args` (which must outlive it).
std::vector<char*> ArgvOf(std::vector<std::string>& args);

struct ProcessResult {
  bool started = false;  ///< false: the program could not be started (not installed); `error` says why
  int exit_code = -1;    ///< the program's exit code; -1 if it died from a signal or was not started
  std::string out;       ///< what it wrote on standard output
  std::string error;     ///< why it could not be started, or the first line it wrote on standard error
};

/// Runs argv[0] (looked up on PATH when it has no '/') with the arguments argv[1..], standard input from /dev/null,
/// and waits for it. Standard output is captured whole up to `max_output_bytes` (beyond it the program is killed and
/// exit_code is -1).
ProcessResult RunProgram(std::vector<std::string> argv, size_t max_output_bytes = 256u << 20);

}  // namespace rome
