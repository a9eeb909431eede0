// rome_sweep: a parameter grid or a Monte Carlo over seeds of any ROME example, spread over MPI ranks.
//
//   mpirun -np 2 build/bin/rome_sweep stepping-stones --grid energy=0.1:0.7:4 --grid step-length=0.2:0.8:4
//       --set terrain=flat --set steps=15 --out DIR
//   mpirun -np 2 build/bin/rome_sweep stepping-stones --seeds 1:1000 --out DIR
//   mpirun -np 2 build/bin/rome_sweep walking --grid sensor-noise=0,0:1e-4,1e-3:5
//       --seeds perturbation-seed=1000:1009 --out DIR
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
// rate over seeds), and with a grid DIR/sweep_success_vs_parameter.png (success rate over the first grid parameter)
// and, with --metric NAME, DIR/sweep_metric_vs_parameter.png (the summary field NAME's mean over it). Files in DIR are
// written atomically (framework/files.h); none is written through a symlink. Exit codes: 0 the sweep completed
// (whatever its runs' outcomes: see sweep.json), 1 bad input or results that could not be written (one line naming it).

#include <mpi.h>

#include <chrono>
#include <iostream>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "examples/sweep/sweep.h"
#include "framework/process.h"
#include "framework/text.h"

namespace {

namespace fs = std::filesystem;
using rome::Excerpt;
using namespace rome::sweep;

void PrintHelp() {
  std::cout
      << "usage: rome_sweep EXAMPLE [--grid NAME=LO:HI:N]... [--seeds [NAME=]A:B] [--set NAME=VALUE]... [--metric "
         "NAME] --out "
         "DIR\n"
         "  EXAMPLE        "
      << ExampleNames(" | ")
      << " (the program next to rome_sweep)\n"
         "  --grid         N values from LO to HI (N = 1: LO) of the example's flag --NAME; several grids multiply\n"
         "                 (whole numbers only for the flags that take them: seed, steps, hops, ...); for a flag\n"
         "                 of several numbers LO and HI are tuples a,b,... (each entry interpolated; plots use the "
         "first)\n"
         "  --seeds A:B    --seed A, A+1, ..., B (a Monte Carlo; multiplies with the grids; the plots pool them);\n"
         "                 NAME=A:B for another seed flag (walking: perturbation-seed)\n"
         "  --set          a fixed flag --NAME VALUE for every run (not a swept flag)\n"
         "  --metric NAME  also plot the mean of the summary's numeric field NAME over the first grid parameter\n"
         "                 (sweep_metric_vs_parameter.png; every run that reports it, failed or not)\n"
         "  --out DIR      results: runs/, sweep.csv, sweep.json, PNG plots; a rerun with the same DIR and the same\n"
         "                 parameters resumes (other parameters are refused)\n"
         "At most "
      << rome::sweep::kMaxRuns
      << " runs. Run it under mpirun (mpirun -np 2 ...); each rank runs every size-th run.\n"
         "Exit codes: 0 the sweep completed (its success rate is in sweep.json), 1 bad input or unwritable results.\n";
}

// The example's --help text (run without a shell: the build folder may hold any character).
std::string ExampleHelp(const std::string& binary) {
  const rome::ProcessResult help = rome::RunProgram({binary, "--help"}, kMaxHelpBytes);
  if (!help.started || help.exit_code != 0)
    throw std::runtime_error("rome_sweep: '" + Excerpt(binary, 200) + " --help' failed (" +
                             (help.started ? "exit code " + std::to_string(help.exit_code) : help.error) + ")");
  return help.out;
}

void CheckExampleHasFlags(const Sweep& s, const std::set<std::string>& flags) {
  auto check = [&](const std::string& name) {
    if (flags.count(name)) return;
    std::string known;
    for (const auto& f : flags)
      if (f != "help") known += (known.empty() ? "" : ", ") + f;
    throw std::invalid_argument("rome_sweep: example '" + s.example + "' has no parameter '" + Excerpt(name) +
                                "' (it has " + known + ")");
  };
  for (const auto& p : s.swept) check(p.name);
  for (const auto& [name, v] : s.fixed) check(name);
}

Sweep Parse(int argc, char** argv) {
  Sweep s;
  if (argc < 2) throw std::invalid_argument("rome_sweep: name an example (" + ExampleNames(" | ") + "); see --help");
  s.example = argv[1];
  auto it = kExamples.find(s.example);
  if (it == kExamples.end())
    throw std::invalid_argument("rome_sweep: unknown example '" + Excerpt(s.example) +
                                "' (known: " + ExampleNames(", ") + ")");
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
    } else if (a == "--metric") {
      s.metric = value();
      if (s.metric.empty() || s.metric.size() > 200)
        throw std::invalid_argument("rome_sweep: --metric '" + Excerpt(s.metric) +
                                    "': name a numeric field of the example's summary (1 to 200 characters)");
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
  if (!fs::exists(s.binary))
    throw std::invalid_argument("rome_sweep: the example program '" + Excerpt(s.binary, 200) +
                                "' does not exist (build it first)");
  const std::string help = ExampleHelp(s.binary);
  CheckExampleHasFlags(s, rome::sweep::FlagsInHelp(help));
  s.units = rome::sweep::FlagUnitsInHelp(help);
  return s;
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
  if (rank == 0)
    std::cout << "rome_sweep: " << s.total << " runs of " << s.example << " on " << size << " rank(s), results in "
              << Excerpt(s.out, 200) << "\n";
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
