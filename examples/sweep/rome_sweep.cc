// rome_sweep: a parameter grid or a Monte Carlo over seeds of any ROME example, spread over MPI ranks.
//
//   mpirun -np 2 build/bin/rome_sweep stepping-stones --grid energy=0.1:0.7:4 --grid step-length=0.2:0.8:4
//       --set terrain=flat --set steps=15 --out DIR
//   mpirun -np 2 build/bin/rome_sweep stepping-stones --seeds 1:1000 --out DIR
//
// Every run is the example program itself (a separate process: Ipopt 3.11 with MUMPS is not thread-safe) with the
// swept values as its flags, writing DIR/runs/run_NNNNNN.json (its summary), .log (its output) and .exit (its exit
// code, written last). Run i goes to rank i mod size. A sweep restarted with the same --out skips the runs that have
// an .exit file (resume). Rank 0 prints runs done / total with an ETA, then gathers every run, in run order, into
// DIR/sweep.csv (one row per run: the swept values, the exit code and the summary's deterministic fields — wall
// times and real-time factors are left out, so the file is identical whatever the number of ranks) and
// DIR/sweep.json (success rate, failures by reason, mean and percentiles of the numeric fields), and draws
// DIR/sweep_speed.png (mean forward speed over the first grid parameter, one line per value of the second: Fig. 6
// of the stepping-stones paper for an energy × step-length grid) or DIR/sweep_success.png (success rate over seeds).
// Exit codes: 0 every run succeeded, 3 some run failed, 1 bad input (one line naming it).

#include <fcntl.h>
#include <mpi.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "examples/common/plot.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct Parameter {
  std::string name;
  std::vector<std::string> values;
};

struct Sweep {
  std::string example, binary, out;
  std::vector<Parameter> swept;                           // grid axes and seeds, in command-line order
  std::vector<std::pair<std::string, std::string>> fixed;  // --set name=value
};

const std::map<std::string, std::string> kExamples = {{"stepping-stones", "stepping_stones"}, {"bouncing-ball", "bouncing_ball"}};
// Summary fields left out of the CSV: they measure the machine, not the run.
const std::set<std::string> kTimingFields = {"wall_time_s", "realtime_factor", "controller_update_us"};

void PrintHelp() {
  std::cout << "usage: rome_sweep EXAMPLE [--grid NAME=LO:HI:N]... [--seeds A:B] [--set NAME=VALUE]... --out DIR\n"
               "  EXAMPLE        stepping-stones | bouncing-ball (the program next to rome_sweep)\n"
               "  --grid         N values from LO to HI (N = 1: LO) of the example's flag --NAME; several grids multiply\n"
               "  --seeds A:B    --seed A, A+1, ..., B (a Monte Carlo; multiplies with the grids)\n"
               "  --set          a fixed flag --NAME VALUE for every run\n"
               "  --out DIR      results: runs/, sweep.csv, sweep.json, PNG plots; a rerun with the same DIR resumes\n"
               "Run it under mpirun (mpirun -np 2 ...); each rank runs every size-th run.\n";
}

std::string Format(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

Parameter ParseGrid(const std::string& spec) {
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) throw std::invalid_argument("rome_sweep: --grid '" + spec + "' must be NAME=LO:HI:N");
  Parameter p{spec.substr(0, eq), {}};
  const std::string range = spec.substr(eq + 1);
  double lo = 0, hi = 0;
  int n = 0;
  char c1 = 0, c2 = 0;
  std::istringstream is(range);
  std::string rest;
  if (!(is >> lo >> c1 >> hi >> c2 >> n) || c1 != ':' || c2 != ':' || (is >> rest) || !std::isfinite(lo) || !std::isfinite(hi) || n < 1 || n > 100000)
    throw std::invalid_argument("rome_sweep: --grid " + p.name + ": malformed range '" + range + "' (expected LO:HI:N with N in 1..100000)");
  for (int k = 0; k < n; ++k) p.values.push_back(Format(n == 1 ? lo : lo + (hi - lo) * k / (n - 1)));
  return p;
}

Parameter ParseSeeds(const std::string& range) {
  long a = 0, b = 0;
  char c = 0;
  std::istringstream is(range);
  std::string rest;
  if (!(is >> a >> c >> b) || c != ':' || (is >> rest) || a < 0 || b < a || b - a > 1000000)
    throw std::invalid_argument("rome_sweep: --seeds: malformed range '" + range + "' (expected A:B with 0 <= A <= B)");
  Parameter p{"seed", {}};
  for (long s = a; s <= b; ++s) p.values.push_back(std::to_string(s));
  return p;
}

// The flags the example accepts, read from its --help ("--name ...").
std::set<std::string> ExampleFlags(const std::string& binary) {
  std::string cmd = "'" + binary + "' --help 2>&1";
  FILE* pipe = popen(cmd.c_str(), "r");
  if (!pipe) throw std::runtime_error("rome_sweep: cannot run '" + binary + " --help'");
  std::string text;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof(buf), pipe)) text.append(buf, n);
  pclose(pipe);
  std::set<std::string> flags;
  for (size_t at = text.find("--"); at != std::string::npos; at = text.find("--", at + 2)) {
    size_t end = at + 2;
    while (end < text.size() && (std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '-')) ++end;
    if (end > at + 2) flags.insert(text.substr(at + 2, end - at - 2));
  }
  return flags;
}

Sweep Parse(int argc, char** argv) {
  Sweep s;
  if (argc < 2) throw std::invalid_argument("rome_sweep: name an example (stepping-stones | bouncing-ball); see --help");
  s.example = argv[1];
  auto it = kExamples.find(s.example);
  if (it == kExamples.end()) throw std::invalid_argument("rome_sweep: unknown example '" + s.example + "' (known: stepping-stones, bouncing-ball)");
  s.binary = (fs::path(argv[0]).parent_path() / it->second).string();
  if (fs::path(argv[0]).parent_path().empty()) s.binary = it->second;
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument("rome_sweep: " + a + " needs a value");
      return argv[++i];
    };
    if (a == "--grid") {
      s.swept.push_back(ParseGrid(value()));
    } else if (a == "--seeds") {
      s.swept.push_back(ParseSeeds(value()));
    } else if (a == "--set") {
      const std::string v = value();
      const size_t eq = v.find('=');
      if (eq == std::string::npos || eq == 0) throw std::invalid_argument("rome_sweep: --set '" + v + "' must be NAME=VALUE");
      s.fixed.emplace_back(v.substr(0, eq), v.substr(eq + 1));
    } else if (a == "--out") {
      s.out = value();
    } else {
      throw std::invalid_argument("rome_sweep: unknown argument '" + a + "' (see --help)");
    }
  }
  if (s.out.empty()) throw std::invalid_argument("rome_sweep: --out DIR is required");
  if (s.swept.empty()) throw std::invalid_argument("rome_sweep: nothing to sweep: give --grid or --seeds");
  if (!fs::exists(s.binary)) throw std::invalid_argument("rome_sweep: the example program '" + s.binary + "' does not exist (build it first)");
  const std::set<std::string> flags = ExampleFlags(s.binary);
  auto check = [&](const std::string& name) {
    if (!flags.count(name)) {
      std::string known;
      for (const auto& f : flags)
        if (f != "help") known += (known.empty() ? "" : ", ") + f;
      throw std::invalid_argument("rome_sweep: example '" + s.example + "' has no parameter '" + name + "' (it has " + known + ")");
    }
  };
  for (const auto& p : s.swept) check(p.name);
  for (const auto& [name, v] : s.fixed) check(name);
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

std::string RunPath(const Sweep& s, long i, const char* ext) {
  char name[64];
  std::snprintf(name, sizeof(name), "run_%06ld.%s", i, ext);
  return (fs::path(s.out) / "runs" / name).string();
}

int RunOne(const Sweep& s, long i) {
  std::vector<std::string> args = {s.binary};
  const auto values = RunValues(s, i);
  for (size_t k = 0; k < values.size(); ++k) args.insert(args.end(), {"--" + s.swept[k].name, values[k]});
  for (const auto& [name, v] : s.fixed) args.insert(args.end(), {"--" + name, v});
  args.insert(args.end(), {"--summary", RunPath(s, i, "json"), "--log", ""});
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  const std::string log = RunPath(s, i, "log");
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, s.binary.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  int code = 127;
  if (rc == 0) {
    int status = 0;
    waitpid(pid, &status, 0);
    code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
  }
  std::ofstream(RunPath(s, i, "exit")) << code << "\n";
  return code;
}

long CountDone(const Sweep& s) {
  long n = 0;
  for (const auto& e : fs::directory_iterator(fs::path(s.out) / "runs"))
    if (e.path().extension() == ".exit") ++n;
  return n;
}

std::string FailureReason(const json& summary, int code) {
  if (summary.is_null()) return "no summary (exit code " + std::to_string(code) + ")";
  const std::string status = summary.value("status", "");
  if (summary.value("contact_violations", 0) > 0) return "contact violation";
  if (status.find("slipped") != std::string::npos) return "slip";
  if (status.find("missed its stone") != std::string::npos) return "missed stone";
  if (status.find("fell") != std::string::npos) return "fell";
  if (status.find("lifted off") != std::string::npos) return "lift-off with no mode";
  if (summary.value("status_kind", "") == "limit") return "time limit";
  return summary.value("status_kind", "failure");
}

double Percentile(std::vector<double> v, double p) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5))];
}

int Gather(const Sweep& s, long total) {
  // Flatten each summary's deterministic scalar fields (one level of objects: "tracking_rms.torso_pitch_rad").
  std::vector<std::map<std::string, std::string>> rows(total);
  std::vector<std::string> columns;
  std::map<std::string, std::vector<double>> numeric;
  std::map<std::string, long> failures;
  std::vector<int> codes(total);
  long succeeded = 0;
  auto add = [&](long i, const std::string& key, const json& v) {
    std::string text;
    if (v.is_number()) {
      text = Format(v.get<double>());
      numeric[key].push_back(v.get<double>());
    } else if (v.is_boolean()) {
      text = v.get<bool>() ? "1" : "0";
    } else if (v.is_string()) {
      text = v.get<std::string>();
      for (char& c : text)
        if (c == ',' || c == '\n') c = ';';
    } else {
      return;
    }
    if (std::find(columns.begin(), columns.end(), key) == columns.end()) columns.push_back(key);
    rows[i][key] = text;
  };
  for (long i = 0; i < total; ++i) {
    int code = 127;
    std::ifstream(RunPath(s, i, "exit")) >> code;
    codes[i] = code;
    json summary;
    std::ifstream in(RunPath(s, i, "json"));
    if (in) {
      try {
        in >> summary;
      } catch (const std::exception&) {
        summary = nullptr;
      }
    }
    if (code == 0)
      ++succeeded;
    else
      ++failures[FailureReason(summary, code)];
    if (!summary.is_object()) continue;
    for (const auto& [key, v] : summary.items()) {
      if (kTimingFields.count(key)) continue;
      if (v.is_object()) {
        for (const auto& [k2, v2] : v.items()) add(i, key + "." + k2, v2);
      } else {
        add(i, key, v);
      }
    }
  }
  std::ofstream csv(fs::path(s.out) / "sweep.csv");
  csv << "run";
  for (const auto& p : s.swept) csv << "," << p.name;
  csv << ",exit_code";
  for (const auto& c : columns) csv << "," << c;
  csv << "\n";
  for (long i = 0; i < total; ++i) {
    csv << i;
    for (const auto& v : RunValues(s, i)) csv << "," << v;
    csv << "," << codes[i];
    for (const auto& c : columns) {
      auto it = rows[i].find(c);
      csv << "," << (it == rows[i].end() ? "" : it->second);
    }
    csv << "\n";
  }
  json agg = {{"example", s.example}, {"runs", total}, {"succeeded", succeeded},
              {"success_rate", total ? static_cast<double>(succeeded) / static_cast<double>(total) : 0.0}, {"failures_by_reason", failures}};
  json stats = json::object();
  for (const auto& [key, v] : numeric) {
    double mean = 0;
    for (double x : v) mean += x / static_cast<double>(v.size());
    stats[key] = {{"mean", mean}, {"p5", Percentile(v, 0.05)}, {"p50", Percentile(v, 0.5)}, {"p95", Percentile(v, 0.95)}, {"min", Percentile(v, 0)},
                  {"max", Percentile(v, 1)}};
  }
  agg["fields"] = stats;
  std::ofstream(fs::path(s.out) / "sweep.json") << agg.dump(2) << "\n";
  // Plots.
  std::string err;
  if (s.swept[0].name != "seed" && numeric.count("mean_forward_speed_mps")) {
    std::vector<rome::examples::Series> series;
    const Parameter& x = s.swept[0];
    const size_t lines = s.swept.size() > 1 ? s.swept[1].values.size() : 1;
    for (size_t l = 0; l < lines; ++l) {
      rome::examples::Series ser{s.swept.size() > 1 ? s.swept[1].name + " = " + s.swept[1].values[l] : "runs", {}, {}, "linespoints"};
      for (long i = 0; i < total; ++i) {
        const auto v = RunValues(s, i);
        if (s.swept.size() > 1 && v[1] != s.swept[1].values[l]) continue;
        auto it = rows[i].find("mean_forward_speed_mps");
        if (it == rows[i].end() || codes[i] != 0) continue;
        ser.x.push_back(std::stod(v[0]));
        ser.y.push_back(std::stod(it->second));
      }
      series.push_back(ser);
    }
    if (!rome::examples::WritePlot({"Mean forward speed (successful runs)", x.name, "speed [m/s]", series}, (fs::path(s.out) / "sweep_speed.png").string(), &err))
      std::cerr << "warning: " << err << "\n";
  } else {
    rome::examples::Series ser{"success rate so far", {}, {}, "lines"};
    long ok = 0;
    for (long i = 0; i < total; ++i) {
      ok += codes[i] == 0 ? 1 : 0;
      ser.x.push_back(static_cast<double>(i + 1));
      ser.y.push_back(static_cast<double>(ok) / static_cast<double>(i + 1));
    }
    if (!rome::examples::WritePlot({"Success rate over runs", "runs", "success rate", {ser}}, (fs::path(s.out) / "sweep_success.png").string(), &err))
      std::cerr << "warning: " << err << "\n";
  }
  std::cout << "rome_sweep: " << succeeded << " of " << total << " runs succeeded (" << 100.0 * agg["success_rate"].get<double>() << " %)";
  for (const auto& [reason, n] : failures) std::cout << "; " << reason << ": " << n;
  std::cout << "\nrome_sweep: " << (fs::path(s.out) / "sweep.csv").string() << ", sweep.json and the plots written\n";
  return succeeded == total ? 0 : 3;
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int result = 0;
  Sweep s;
  long total = 0;
  // Rank 0 checks the input and the output folder before any run starts; every rank then agrees.
  int ok = 1;
  if (argc >= 2 && (std::string(argv[1]) == "--help" || std::string(argv[1]) == "-h")) {
    if (rank == 0) PrintHelp();
    MPI_Finalize();
    return 0;
  }
  try {
    s = Parse(argc, argv);
    total = 1;
    for (const auto& p : s.swept) total *= static_cast<long>(p.values.size());
    if (rank == 0) {
      std::error_code ec;
      fs::create_directories(fs::path(s.out) / "runs", ec);
      const fs::path probe = fs::path(s.out) / "runs" / ".write_test";
      std::ofstream t(probe);
      if (ec || !t) throw std::invalid_argument("rome_sweep: cannot write to the output folder '" + s.out + "'");
      t.close();
      fs::remove(probe);
    }
  } catch (const std::exception& e) {
    if (rank == 0) std::cerr << "error: " << e.what() << "\n";
    ok = 0;
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (!ok) {
    MPI_Finalize();
    return 1;
  }
  const auto start = std::chrono::steady_clock::now();
  if (rank == 0) std::cout << "rome_sweep: " << total << " runs of " << s.example << " on " << size << " rank(s), results in " << s.out << "\n";
  long mine_done = 0;
  const long already = rank == 0 ? CountDone(s) : 0;
  for (long i = rank; i < total; i += size) {
    if (fs::exists(RunPath(s, i, "exit"))) continue;  // resume
    RunOne(s, i);
    ++mine_done;
    if (rank == 0) {
      const long done = CountDone(s);
      const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double rate = static_cast<double>(done - already) / std::max(elapsed, 1e-9);
      std::cout << "  " << done << " / " << total << " runs done, ETA " << (rate > 0 ? static_cast<long>((total - done) / rate) : 0) << " s\n" << std::flush;
    }
  }
  MPI_Barrier(MPI_COMM_WORLD);
  if (rank == 0) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "rome_sweep: " << total - already << " runs in " << elapsed << " s wall on " << size << " rank(s)\n";
    result = Gather(s, total);
  }
  MPI_Bcast(&result, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return result;
}
