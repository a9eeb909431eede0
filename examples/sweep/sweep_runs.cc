// rome_sweep: starting each run, its record, and resuming (sweep.h).
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "examples/sweep/sweep.h"
#include "framework/files.h"
#include "framework/process.h"
#include "framework/text.h"

extern char** environ;

namespace rome::sweep {

namespace fs = std::filesystem;
using nlohmann::json;
using rome::Excerpt;

// Run i's values of the swept parameters (the first parameter varies slowest).
std::vector<std::string> RunValues(const Sweep& s, long index) {
  std::vector<std::string> v(s.swept.size());
  for (int k = static_cast<int>(s.swept.size()) - 1; k >= 0; --k) {
    const long n = static_cast<long>(s.swept[k].values.size());
    v[k] = s.swept[k].values[index % n];
    index /= n;
  }
  return v;
}

// Run i's flags, swept and fixed, without the output paths: what its record holds.
std::vector<std::string> RunFlags(const Sweep& s, long i) {
  std::vector<std::string> flags;
  const auto values = RunValues(s, i);
  for (size_t k = 0; k < values.size(); ++k) flags.insert(flags.end(), {"--" + s.swept[k].name, values[k]});
  for (const auto& [name, v] : s.fixed) flags.insert(flags.end(), {"--" + name, v});
  return flags;
}

std::string RunsFolder(const Sweep& s) { return (fs::path(s.out) / "runs").string(); }

std::string RunPath(const Sweep& s, long i, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof(name), "run_%06ld.%s", i, ext);
  return (fs::path(s.out) / "runs" / name).string();
}

std::string Join(const std::vector<std::string>& flags) {
  std::string text;
  for (const auto& f : flags) text += (text.empty() ? "" : " ") + f;
  return text;
}

// Creates DIR/runs and checks that files can be created in it, before any run starts.
void PrepareOutFolder(const Sweep& s) {
  const std::string runs = RunsFolder(s);
  std::error_code ec;
  fs::create_directories(runs, ec);
  struct stat st {};
  // A symlink at DIR/runs (planted in a shared folder) would send every run's files wherever it points.
  if (!ec && (::lstat(runs.c_str(), &st) != 0 || !S_ISDIR(st.st_mode)))
    throw std::invalid_argument("rome_sweep: the output folder '" + Excerpt(s.out, 200) +
                                "' has a 'runs' that is not a folder (a symlink or a file)");
  std::string reason = ec ? ec.message() : "";
  if (!ec) {
    try {
      const rome::AtomicFileWriter probe(runs + "/.write_probe", "output folder");
    } catch (const std::exception& e) { reason = e.what(); }
  }
  if (!reason.empty())
    throw std::invalid_argument("rome_sweep: cannot write to the output folder '" + Excerpt(s.out, 200) + "' (" +
                                Excerpt(reason, 300) + ")");
}

// Run i's record, if there is a valid one.
std::optional<RunRecord> ReadRecord(const Sweep& s, long i) {
  const std::string path = RunPath(s, i, "exit");
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return std::nullopt;
  try {
    return rome::sweep::ParseRunRecord(rome::ReadRegularFile(path, "run record", kMaxRecordBytes));
  } catch (const std::exception&) {  // not a regular file, or over the cap
    return std::nullopt;
  }
}

SummaryFile ReadSummary(const Sweep& s, long i) {
  const std::string path = RunPath(s, i, "json");
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {};
  if (!S_ISREG(st.st_mode)) return {true, std::nullopt};
  try {
    return {true, rome::sweep::ParseSummary(rome::ReadRegularFile(path, "run summary", kMaxSummaryBytes))};
  } catch (const std::exception&) { return {true, std::nullopt}; }
}

// Whether run i can be skipped on resume: a valid record of these flags that no signal ended, and a valid summary if
// there is one (a successful run must have one). Anything else runs again.
bool RunIsDone(const Sweep& s, long i, const std::vector<std::string>& flags) {
  const std::optional<RunRecord> record = ReadRecord(s, i);
  // A run stopped by a signal, whether it died of it or caught it (exit 128 + SIGINT/SIGTERM, summary "interrupted"),
  // runs again.
  if (!record || record->KilledBySignal() || record->exit_code == 128 + SIGINT || record->exit_code == 128 + SIGTERM ||
      record->flags != flags)
    return false;
  const SummaryFile summary = ReadSummary(s, i);
  return summary.present ? summary.summary.has_value() : record->exit_code != 0;
}

// Refuses to resume into a folder whose runs were made with other flags: mixing them would be a silent wrong answer.
void CheckResume(const Sweep& s) {
  for (long i = 0; i < s.total; ++i) {
    const std::optional<RunRecord> record = ReadRecord(s, i);
    if (!record) continue;
    const std::vector<std::string> flags = RunFlags(s, i);
    if (record->flags != flags)
      throw std::invalid_argument("rome_sweep: --out '" + Excerpt(s.out, 200) + "' holds run " + std::to_string(i) +
                                  " made with other parameters ('" + Excerpt(Join(record->flags), 200) +
                                  "', this sweep's: '" + Excerpt(Join(flags), 200) +
                                  "'); resume with the same parameters or choose another --out");
  }
}

// Opens run i's log for a new run: whatever is at the name (an old log, a planted symlink) is removed, and the new
// file is created with O_EXCL|O_NOFOLLOW, so nothing outside DIR/runs is ever written. -1 (errno set) if it cannot.
int CreateRunLog(const std::string& path) {
  ::unlink(path.c_str());
  return ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
}

// Runs the example with run i's flags; its output goes to run i's log; its record is written last.
void RunOne(const Sweep& s, long i) {
  const std::vector<std::string> flags = RunFlags(s, i);
  for (const char* ext : {"exit", "json"})
    ::unlink(RunPath(s, i, ext).c_str());  // an earlier attempt's, never followed
  const std::string log = RunPath(s, i, "log");
  const int log_fd = CreateRunLog(log);
  if (log_fd < 0) {
    std::cerr << "rome_sweep: run " << i << ": cannot create its log '" << Excerpt(log, 200) << "' ("
              << std::strerror(errno) << "); the run is left for a resume\n";
    return;
  }
  std::vector<std::string> args = {s.binary};
  args.insert(args.end(), flags.begin(), flags.end());
  args.insert(args.end(), {"--summary", RunPath(s, i, "json"), "--log", ""});
  std::vector<char*> argv = rome::ArgvOf(args);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_adddup2(&actions, log_fd, 1);
  posix_spawn_file_actions_adddup2(&actions, log_fd, 2);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, s.binary.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  RunRecord record{127, flags};  // 127: could not be started, as a shell reports it
  if (rc != 0) {
    const std::string why = "rome_sweep: cannot start '" + Excerpt(s.binary, 200) + "' (" + std::strerror(rc) + ")\n";
    [[maybe_unused]] const ssize_t written = ::write(log_fd, why.data(), why.size());
  }
  ::close(log_fd);
  if (rc == 0) {
    const rome::ExitStatus status = rome::WaitForChild(pid);
    record.exit_code = status.signal != 0 ? -std::min(status.signal, -rome::sweep::kMinExitCode) : status.code;
  }
  try {
    rome::WriteFileAtomically(RunPath(s, i, "exit"), rome::sweep::RunRecordText(record), "run record");
  } catch (const std::exception& e) {
    std::cerr << "rome_sweep: run " << i << ": " << e.what() << "; the run is left for a resume\n";
  }
}

long CountDone(const Sweep& s) {
  long n = 0;
  std::error_code ec;
  for (fs::directory_iterator it(RunsFolder(s), ec), end; !ec && it != end; it.increment(ec))
    if (it->path().extension() == ".exit") ++n;
  return n;
}

// This rank's share of the runs (i = rank, rank + size, ...), skipping those done before; returns how many it ran.
long RunShare(const Sweep& s, int rank, int size) {
  const auto start = std::chrono::steady_clock::now();
  const long already = rank == 0 ? CountDone(s) : 0;
  long ran = 0;
  for (long i = rank; i < s.total; i += size) {
    if (RunIsDone(s, i, RunFlags(s, i))) continue;  // resume
    RunOne(s, i);
    ++ran;
    if (rank == 0) {
      const long done = CountDone(s);
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double rate = static_cast<double>(done - already) / std::max(elapsed, 1e-9);
      std::cout << "  " << done << " / " << s.total << " runs done, ETA "
                << (rate > 0 ? static_cast<long>((s.total - done) / rate) : 0) << " s\n"
                << std::flush;
    }
  }
  return ran;
}

}  // namespace rome::sweep
