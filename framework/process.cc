#include "framework/process.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

extern char** environ;

namespace rome {

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

// Reads both pipes until they close; false if standard output went past `max_bytes`.
bool Drain(int out_fd, int err_fd, size_t max_bytes, std::string* out, std::string* err) {
  pollfd fds[2] = {{out_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  char buffer[1 << 15];
  int open_fds = 2;
  while (open_fds > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      return true;
    }
    for (int k = 0; k < 2; ++k) {
      if (fds[k].fd < 0 || fds[k].revents == 0) continue;
      const ssize_t n = ::read(fds[k].fd, buffer, sizeof(buffer));
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        fds[k].fd = -1;
        --open_fds;
        continue;
      }
      std::string& sink = k == 0 ? *out : *err;
      if (k == 1 && sink.size() > 4096) continue;  // only the first lines of standard error are kept
      sink.append(buffer, static_cast<size_t>(n));
      if (k == 0 && sink.size() > max_bytes) return false;
    }
  }
  return true;
}

}  // namespace

ProcessResult RunProgram(std::vector<std::string> argv, size_t max_output_bytes) {
  ProcessResult result;
  if (argv.empty()) {
    result.error = "no program given";
    return result;
  }
  int out_pipe[2], err_pipe[2];
  if (::pipe2(out_pipe, O_CLOEXEC) != 0) {
    result.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    return result;
  }
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) {
    result.error = std::string("cannot create a pipe: ") + std::strerror(errno);
    ::close(out_pipe[0]);
    ::close(out_pipe[1]);
    return result;
  }
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 0, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_adddup2(&actions, out_pipe[1], 1);
  posix_spawn_file_actions_adddup2(&actions, err_pipe[1], 2);
  std::vector<char*> args = ArgvOf(argv);
  pid_t pid = -1;
  const int rc = ::posix_spawnp(&pid, argv[0].c_str(), &actions, nullptr, args.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  if (rc != 0) {
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    result.error = "cannot run " + argv[0] + ": " + std::strerror(rc);
    return result;
  }
  result.started = true;
  std::string err;
  const bool within = Drain(out_pipe[0], err_pipe[0], max_output_bytes, &result.out, &err);
  if (!within) ::kill(pid, SIGKILL);
  ::close(out_pipe[0]);
  ::close(err_pipe[0]);
  const ExitStatus status = WaitForChild(pid);
  result.exit_code = (within && status.signal == 0) ? status.code : -1;
  result.error = err.substr(0, err.find('\n'));
  if (!within) result.error = argv[0] + " wrote more than " + std::to_string(max_output_bytes) + " bytes";
  return result;
}

}  // namespace rome
