// rome_sweep: a parameter grid or a Monte Carlo over seeds of any ROME example, spread over MPI ranks.
//
//   mpirun -np 2 build/bin/rome_sweep stepping-stones --grid energy=0.1:0.7:4 --grid step-length=0.2:0.8:4
//       --set terrain=flat --set steps=15 --out DIR
//   mpirun -np 2 build/bin/rome_sweep stepping-stones --seeds 1:1000 --out DIR
//
// Every run is the example program itself (a separate process: Ipopt 3.11 with MUMPS is not thread-safe), started
// with an argument list (no shell) and the swept values as its flags, writing DIR/runs/run_NNNNNN.json (its summary),
// .log (its output) and .exit (its record, written last: how it ended and the flags it ran with; sweep_io.h). Run i
// goes to rank i mod size. A sweep restarted with the same --out resumes: it skips the runs whose record is valid and
// whose summary, if any, is a valid summary; a run killed by a signal, or with a damaged record or summary, runs
// again; a record made with other flags refuses the whole resume. Rank 0 prints runs done / total with an ETA, then
// gathers every run, in run order, into DIR/sweep.csv (one row per run: the swept values, the exit code and the
// summary's deterministic fields — wall times and real-time factors are left out, so the file is identical whatever
// the number of ranks) and DIR/sweep.json (success rate, failures by reason, mean and percentiles of the numeric
// fields), and draws DIR/sweep_speed.png (mean forward speed over the first grid parameter, one line per value of
// the second: Fig. 6 of the stepping-stones paper for an energy × step-length grid) or DIR/sweep_success.png (success
// rate over seeds). Files in DIR are written atomically (framework/files.h); none is written through a symlink.
// Exit codes: 0 the sweep completed (whatever its runs' outcomes: see sweep.json), 1 bad input or results that could
// not be written (one line naming it).

#include <fcntl.h>
#include <mpi.h>
#include <spawn.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "systems/visualization/plot.h"
#include "framework/process.h"
#include "examples/sweep/sweep_io.h"
#include "framework/files.h"
#include "framework/text.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using rome::Excerpt;
using rome::sweep::Parameter;
using rome::sweep::RunRecord;

struct Example {
  std::string program;
  std::set<std::string> integer_flags;  // flags that take whole numbers: their grids must give whole numbers
};
const std::map<std::string, Example> kExamples = {
    {"stepping-stones", {"stepping_stones", {"seed", "steps"}}},
    {"bouncing-ball", {"bouncing_ball", {}}},
    {"walking", {"walking", {"seed", "steps", "lead-in-steps", "start-gait-steps"}}},
    {"hopping", {"hopping", {"hops", "bullet-substeps"}}}};
// "a | b | c" or "a, b, c": the example names, for help and errors.
std::string ExampleNames(const char* separator) {
  std::string names;
  for (const auto& [name, example] : kExamples) names += (names.empty() ? "" : separator) + name;
  return names;
}
// Summary fields left out of the CSV: they measure the machine, not the run.
const std::set<std::string> kTimingFields = {"wall_time_s", "realtime_factor", "controller_update_us"};
// Size caps of what is read back (the examples' summaries are a few kB).
constexpr std::uintmax_t kMaxRecordBytes = 1u << 20, kMaxSummaryBytes = 4u << 20;
constexpr size_t kMaxHelpBytes = 1u << 20;

struct Sweep {
  std::string example, binary, out;
  std::vector<Parameter> swept;                            // grid axes and seeds, in command-line order
  std::vector<std::pair<std::string, std::string>> fixed;  // --set name=value
  long total = 0;                                          // runs
};

void PrintHelp() {
  std::cout << "usage: rome_sweep EXAMPLE [--grid NAME=LO:HI:N]... [--seeds A:B] [--set NAME=VALUE]... --out DIR\n"
               "  EXAMPLE        " << ExampleNames(" | ") << " (the program next to rome_sweep)\n"
               "  --grid         N values from LO to HI (N = 1: LO) of the example's flag --NAME; several grids multiply\n"
               "                 (whole numbers only for the flags that take them: seed, steps, hops, ...)\n"
               "  --seeds A:B    --seed A, A+1, ..., B (a Monte Carlo; multiplies with the grids)\n"
               "  --set          a fixed flag --NAME VALUE for every run (not a swept flag)\n"
               "  --out DIR      results: runs/, sweep.csv, sweep.json, PNG plots; a rerun with the same DIR and the same\n"
               "                 parameters resumes (other parameters are refused)\n"
               "At most " << rome::sweep::kMaxRuns << " runs. Run it under mpirun (mpirun -np 2 ...); each rank runs every size-th run.\n"
               "Exit codes: 0 the sweep completed (its success rate is in sweep.json), 1 bad input or unwritable results.\n";
}

// The flags the example accepts, read from its --help (run without a shell: the build folder may hold any character).
std::set<std::string> ExampleFlags(const std::string& binary) {
  const rome::ProcessResult help = rome::RunProgram({binary, "--help"}, kMaxHelpBytes);
  if (!help.started || help.exit_code != 0)
    throw std::runtime_error("rome_sweep: '" + Excerpt(binary, 200) + " --help' failed (" +
                             (help.started ? "exit code " + std::to_string(help.exit_code) : help.error) + ")");
  return rome::sweep::FlagsInHelp(help.out);
}

void CheckExampleHasFlags(const Sweep& s, const std::set<std::string>& flags) {
  auto check = [&](const std::string& name) {
    if (flags.count(name)) return;
    std::string known;
    for (const auto& f : flags)
      if (f != "help") known += (known.empty() ? "" : ", ") + f;
    throw std::invalid_argument("rome_sweep: example '" + s.example + "' has no parameter '" + Excerpt(name) + "' (it has " + known + ")");
  };
  for (const auto& p : s.swept) check(p.name);
  for (const auto& [name, v] : s.fixed) check(name);
}

Sweep Parse(int argc, char** argv) {
  Sweep s;
  if (argc < 2) throw std::invalid_argument("rome_sweep: name an example (" + ExampleNames(" | ") + "); see --help");
  s.example = argv[1];
  auto it = kExamples.find(s.example);
  if (it == kExamples.end()) throw std::invalid_argument("rome_sweep: unknown example '" + Excerpt(s.example) + "' (known: " + ExampleNames(", ") + ")");
  const Example& example = it->second;
  // The example beside this program's own file (/proc/self/exe), never a name looked up in the current folder or PATH.
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  s.binary = ((ec ? fs::absolute(argv[0], ec) : self).parent_path() / example.program).string();
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("rome_sweep: " + Excerpt(a) + " needs a value");
      return argv[++i];
    };
    if (a == "--grid") {
      const std::string spec = value();
      s.swept.push_back(rome::sweep::ParseGrid(spec, example.integer_flags.count(spec.substr(0, spec.find('='))) > 0));
    } else if (a == "--seeds") {
      s.swept.push_back(rome::sweep::ParseSeeds(value()));
    } else if (a == "--set") {
      s.fixed.push_back(rome::sweep::ParseSet(value()));
    } else if (a == "--out") {
      s.out = value();
    } else {
      throw std::invalid_argument("rome_sweep: unknown argument '" + Excerpt(a) + "' (see --help)");
    }
  }
  if (s.out.empty()) throw std::invalid_argument("rome_sweep: --out DIR is required");
  if (s.swept.empty()) throw std::invalid_argument("rome_sweep: nothing to sweep: give --grid or --seeds");
  rome::sweep::CheckFlagsGivenOnce(s.swept, s.fixed);
  s.total = rome::sweep::CountRuns(s.swept);
  if (!fs::exists(s.binary)) throw std::invalid_argument("rome_sweep: the example program '" + Excerpt(s.binary, 200) + "' does not exist (build it first)");
  CheckExampleHasFlags(s, ExampleFlags(s.binary));
  return s;
}

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
    throw std::invalid_argument("rome_sweep: the output folder '" + Excerpt(s.out, 200) + "' has a 'runs' that is not a folder (a symlink or a file)");
  std::string reason = ec ? ec.message() : "";
  if (!ec) {
    try {
      const rome::AtomicFileWriter probe(runs + "/.write_probe", "output folder");
    } catch (const std::exception& e) {
      reason = e.what();
    }
  }
  if (!reason.empty()) throw std::invalid_argument("rome_sweep: cannot write to the output folder '" + Excerpt(s.out, 200) + "' (" + Excerpt(reason, 300) + ")");
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

// Run i's summary: whether something is at its name, and its content if that is a valid summary.
struct SummaryFile {
  bool present = false;
  std::optional<json> summary;
};

SummaryFile ReadSummary(const Sweep& s, long i) {
  const std::string path = RunPath(s, i, "json");
  struct stat st {};
  if (::lstat(path.c_str(), &st) != 0) return {};
  if (!S_ISREG(st.st_mode)) return {true, std::nullopt};
  try {
    return {true, rome::sweep::ParseSummary(rome::ReadRegularFile(path, "run summary", kMaxSummaryBytes))};
  } catch (const std::exception&) {
    return {true, std::nullopt};
  }
}

// Whether run i can be skipped on resume: a valid record of these flags that no signal ended, and a valid summary if
// there is one (a successful run must have one). Anything else runs again.
bool RunIsDone(const Sweep& s, long i, const std::vector<std::string>& flags) {
  const std::optional<RunRecord> record = ReadRecord(s, i);
  // A run stopped by a signal, whether it died of it or caught it (exit 128 + SIGINT/SIGTERM, summary "interrupted"),
  // runs again.
  if (!record || record->KilledBySignal() || record->exit_code == 128 + SIGINT || record->exit_code == 128 + SIGTERM || record->flags != flags)
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
      throw std::invalid_argument("rome_sweep: --out '" + Excerpt(s.out, 200) + "' holds run " + std::to_string(i) + " made with other parameters ('" +
                                  Excerpt(Join(record->flags), 200) + "', this sweep's: '" + Excerpt(Join(flags), 200) +
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
  for (const char* ext : {"exit", "json"}) ::unlink(RunPath(s, i, ext).c_str());  // an earlier attempt's, never followed
  const std::string log = RunPath(s, i, "log");
  const int log_fd = CreateRunLog(log);
  if (log_fd < 0) {
    std::cerr << "rome_sweep: run " << i << ": cannot create its log '" << Excerpt(log, 200) << "' (" << std::strerror(errno)
              << "); the run is left for a resume\n";
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

std::string FailureReason(const std::optional<json>& summary, const std::optional<RunRecord>& record) {
  if (!record) return "no run record";
  if (record->KilledBySignal()) return "killed by signal " + std::to_string(-record->exit_code);
  if (!summary) return "no summary (exit code " + std::to_string(record->exit_code) + ")";
  const std::string status = summary->at("status").get<std::string>(), kind = summary->at("status_kind").get<std::string>();
  const auto violations = summary->find("contact_violations");
  if (violations != summary->end() && violations->is_number() && violations->get<double>() > 0) return "contact violation";
  if (status.find("slipped") != std::string::npos) return "slip";
  if (status.find("missed its stone") != std::string::npos) return "missed stone";
  if (status.find("fell") != std::string::npos) return "fell";
  if (status.find("lifted off") != std::string::npos) return "lift-off with no mode";
  if (kind == "limit") return "time limit";
  return kind;
}

double Percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5))];
}

std::string Format(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

// Every run's record and summary, flattened to the summary's deterministic scalar fields (one level of objects:
// "tracking_rms.torso_pitch_rad").
struct Results {
  std::vector<std::optional<RunRecord>> records;
  std::vector<std::map<std::string, std::string>> cells;  // run -> field -> its text
  std::vector<std::map<std::string, double>> numbers;     // run -> numeric field -> its value
  std::vector<std::string> columns;                       // fields in order of first appearance
  std::map<std::string, std::vector<double>> numeric;     // numeric field -> every run's value
  std::map<std::string, long> failures;
  long succeeded = 0;
};

void AddField(Results& r, long i, const std::string& key, const json& v) {
  std::string text;
  if (v.is_number()) {
    text = Format(v.get<double>());
    r.numeric[key].push_back(v.get<double>());
    r.numbers[i][key] = v.get<double>();
  } else if (v.is_boolean()) {
    text = v.get<bool>() ? "1" : "0";
  } else if (v.is_string()) {
    text = v.get<std::string>();
  } else {
    return;
  }
  if (std::find(r.columns.begin(), r.columns.end(), key) == r.columns.end()) r.columns.push_back(key);
  r.cells[i][key] = text;
}

Results ReadResults(const Sweep& s) {
  Results r;
  r.records.resize(s.total);
  r.cells.resize(s.total);
  r.numbers.resize(s.total);
  for (long i = 0; i < s.total; ++i) {
    r.records[i] = ReadRecord(s, i);
    const std::optional<json> summary = ReadSummary(s, i).summary;
    if (r.records[i] && r.records[i]->exit_code == 0)
      ++r.succeeded;
    else
      ++r.failures[FailureReason(summary, r.records[i])];
    if (!summary) continue;
    for (const auto& [key, v] : summary->items()) {
      if (kTimingFields.count(key)) continue;
      if (v.is_object()) {
        for (const auto& [k2, v2] : v.items()) AddField(r, i, key + "." + k2, v2);
      } else {
        AddField(r, i, key, v);
      }
    }
  }
  return r;
}

std::string CsvText(const Sweep& s, const Results& r) {
  using rome::sweep::CsvCell;
  std::ostringstream csv;
  csv << "run";
  for (const auto& p : s.swept) csv << "," << CsvCell(p.name);
  csv << ",exit_code";
  for (const auto& c : r.columns) csv << "," << CsvCell(c);
  csv << "\n";
  for (long i = 0; i < s.total; ++i) {
    csv << i;
    for (const auto& v : RunValues(s, i)) csv << "," << CsvCell(v);
    csv << "," << (r.records[i] ? std::to_string(r.records[i]->exit_code) : "");
    for (const auto& c : r.columns) {
      auto it = r.cells[i].find(c);
      csv << "," << (it == r.cells[i].end() ? "" : CsvCell(it->second));
    }
    csv << "\n";
  }
  return csv.str();
}

json Aggregate(const Sweep& s, const Results& r) {
  json agg = {{"example", s.example},
              {"runs", s.total},
              {"succeeded", r.succeeded},
              {"success_rate", s.total ? static_cast<double>(r.succeeded) / static_cast<double>(s.total) : 0.0},
              {"failures_by_reason", r.failures}};
  json stats = json::object();
  for (const auto& [key, v] : r.numeric) {
    double mean = 0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    stats[key] = {{"mean", mean}, {"p5", Percentile(v, 0.05)}, {"p50", Percentile(v, 0.5)}, {"p95", Percentile(v, 0.95)}, {"min", Percentile(v, 0)},
                  {"max", Percentile(v, 1)}};
  }
  agg["fields"] = stats;
  return agg;
}

// A plot that fails is a warning (WritePlot passes no path to gnuplot and writes the PNG atomically).
void WritePlotInto(const rome::visualization::PlotSpec& spec, const std::string& destination) {
  std::string err;
  if (!rome::visualization::WritePlot(spec, destination, &err)) std::cerr << "warning: " << err << "\n";
}

void WritePlots(const Sweep& s, const Results& r) {
  if (s.swept[0].name != "seed" && r.numeric.count("mean_forward_speed_mps")) {
    std::vector<rome::visualization::Series> series;
    const Parameter& x = s.swept[0];
    const size_t lines = s.swept.size() > 1 ? s.swept[1].values.size() : 1;
    for (size_t l = 0; l < lines; ++l) {
      rome::visualization::Series ser{s.swept.size() > 1 ? s.swept[1].name + " = " + s.swept[1].values[l] : "runs", {}, {}, "linespoints"};
      for (long i = 0; i < s.total; ++i) {
        const auto v = RunValues(s, i);
        if (s.swept.size() > 1 && v[1] != s.swept[1].values[l]) continue;
        auto it = r.numbers[i].find("mean_forward_speed_mps");
        if (it == r.numbers[i].end() || !r.records[i] || r.records[i]->exit_code != 0) continue;
        ser.x.push_back(std::strtod(v[0].c_str(), nullptr));
        ser.y.push_back(it->second);
      }
      series.push_back(ser);
    }
    WritePlotInto({"Mean forward speed (successful runs)", x.name, "speed [m/s]", series}, (fs::path(s.out) / "sweep_speed.png").string());
  } else {
    rome::visualization::Series ser{"success rate so far", {}, {}, "lines"};
    long ok = 0;
    for (long i = 0; i < s.total; ++i) {
      ok += r.records[i] && r.records[i]->exit_code == 0 ? 1 : 0;
      ser.x.push_back(static_cast<double>(i + 1));
      ser.y.push_back(static_cast<double>(ok) / static_cast<double>(i + 1));
    }
    WritePlotInto({"Success rate over runs", "runs", "success rate", {ser}}, (fs::path(s.out) / "sweep_success.png").string());
  }
}

// Writes sweep.csv, sweep.json and the plot; throws std::runtime_error naming a file that cannot be written.
void Gather(const Sweep& s) {
  const Results r = ReadResults(s);
  rome::WriteFileAtomically((fs::path(s.out) / "sweep.csv").string(), CsvText(s, r), "sweep CSV");
  const json agg = Aggregate(s, r);
  rome::WriteFileAtomically((fs::path(s.out) / "sweep.json").string(), agg.dump(2, ' ', false, json::error_handler_t::replace) + "\n", "sweep JSON");
  WritePlots(s, r);
  std::cout << "rome_sweep: " << r.succeeded << " of " << s.total << " runs succeeded (" << 100.0 * agg["success_rate"].get<double>() << " %)";
  for (const auto& [reason, n] : r.failures) std::cout << "; " << Excerpt(reason) << ": " << n;
  std::cout << "\nrome_sweep: " << Excerpt((fs::path(s.out) / "sweep.csv").string(), 200) << ", sweep.json and the plots written\n";
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
      std::cout << "  " << done << " / " << s.total << " runs done, ETA " << (rate > 0 ? static_cast<long>((s.total - done) / rate) : 0) << " s\n"
                << std::flush;
    }
  }
  return ran;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  if (argc >= 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    if (rank == 0) PrintHelp();
    MPI_Finalize();
    return 0;
  }
  // Rank 0 checks the input, the output folder and a resume's parameters before any run starts; every rank agrees.
  Sweep s;
  int ok = 1;
  try {
    s = Parse(argc, argv);
    if (rank == 0) {
      PrepareOutFolder(s);
      CheckResume(s);
    }
  } catch (const std::exception& e) {
    if (rank == 0) std::cerr << "error: " << e.what() << "\n";
    ok = 0;
  }
  MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  if (!ok) {
    MPI_Finalize();
    return 1;
  }
  const auto start = std::chrono::steady_clock::now();
  if (rank == 0) std::cout << "rome_sweep: " << s.total << " runs of " << s.example << " on " << size << " rank(s), results in " << Excerpt(s.out, 200) << "\n";
  long ran = 0, ran_total = 0;
  try {
    ran = RunShare(s, rank, size);
  } catch (const std::exception& e) {  // a run that cannot start is recorded; this is only what cannot be foreseen
    std::cerr << "rome_sweep: rank " << rank << ": " << e.what() << "\n";
  }
  MPI_Reduce(&ran, &ran_total, 1, MPI_LONG, MPI_SUM, 0, MPI_COMM_WORLD);
  int result = 0;
  if (rank == 0) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "rome_sweep: " << ran_total << " runs in " << elapsed << " s wall on " << size << " rank(s)\n";
    try {
      Gather(s);
    } catch (const std::exception& e) {
      std::cerr << "error: rome_sweep: " << e.what() << "\n";
      result = 1;
    }
  }
  MPI_Bcast(&result, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return result;
}
