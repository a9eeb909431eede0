#include "examples/common/process.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "framework/text.h"

extern char** environ;

namespace rome::examples {

ExitStatus WaitForChild(pid_t pid) {
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return {127, 0};
  }
  if (WIFEXITED(status)) return {WEXITSTATUS(status), 0};
  return {0, WIFSIGNALED(status) ? WTERMSIG(status) : 0};
}

std::vector<char*> ArgvOf(std::vector<std::string>& args) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  return argv;
}

namespace {

// Reads `fd` to its end, keeping the first max_bytes.
std::string ReadAll(int fd, size_t max_bytes) {
  std::string text;
  char buffer[4096];
  for (;;) {
    const ssize_t n = ::read(fd, buffer, sizeof(buffer));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    text.append(buffer, std::min(static_cast<size_t>(n), max_bytes - std::min(max_bytes, text.size())));
  }
  return text;
}

}  // namespace

ProcessOutput RunAndCapture(const std::vector<std::string>& argv_in, size_t max_bytes) {
  if (argv_in.empty()) throw std::invalid_argument("RunAndCapture: no program given");
  std::vector<std::string> args = argv_in;
  std::vector<char*> argv = ArgvOf(args);
  int pipe_fds[2];
  if (::pipe2(pipe_fds, O_CLOEXEC) != 0) throw std::runtime_error(std::string("cannot create a pipe (") + std::strerror(errno) + ")");
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 1);  // dup2 clears O_CLOEXEC on 1 and 2 only
  posix_spawn_file_actions_adddup2(&actions, pipe_fds[1], 2);
  pid_t pid = 0;
  const int rc = ::posix_spawn(&pid, args[0].c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(pipe_fds[1]);
  if (rc != 0) {
    ::close(pipe_fds[0]);
    throw std::runtime_error("cannot run '" + Excerpt(args[0], 200) + "' (" + std::strerror(rc) + ")");
  }
  ProcessOutput out;
  out.output = ReadAll(pipe_fds[0], max_bytes);
  ::close(pipe_fds[0]);
  out.status = WaitForChild(pid);
  return out;
}

}  // namespace rome::examples
