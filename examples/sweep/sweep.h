#pragma once
// rome_sweep's parts (rome_sweep.cc: command line and MPI; sweep_runs.cc: starting, recording and resuming runs;
// sweep_results.cc: the CSV, the JSON and the plots). What they share: the examples it can sweep and the sweep itself.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "examples/sweep/sweep_io.h"

namespace rome::sweep {

struct Example {
  std::string program;
  std::set<std::string> integer_flags;  // flags that take whole numbers: their grids must give whole numbers
};
inline const std::map<std::string, Example> kExamples = {
    {"stepping-stones", {"stepping_stones", {"seed", "steps"}}},
    {"bouncing-ball", {"bouncing_ball", {}}},
    {"walking", {"walking", {"seed", "perturbation-seed", "steps", "lead-in-steps", "start-gait-steps"}}},
    {"hopping", {"hopping", {"seed", "hops", "bullet-substeps"}}}};
// "a | b | c" or "a, b, c": the example names, for help and errors.
inline std::string ExampleNames(const char* separator) {
  std::string names;
  for (const auto& [name, example] : kExamples) names += (names.empty() ? "" : separator) + name;
  return names;
}
// Summary fields left out of the CSV: they measure the machine, not the run.
inline const std::set<std::string> kTimingFields = {"wall_time_s", "realtime_factor", "controller_update_us"};
// Size caps of what is read back (the examples' summaries are a few kB).
inline constexpr std::uintmax_t kMaxRecordBytes = 1u << 20, kMaxSummaryBytes = 4u << 20;
inline constexpr size_t kMaxHelpBytes = 1u << 20;

struct Sweep {
  std::string example, binary, out;
  std::string metric;  // --metric: a numeric summary field plotted over the first grid parameter (empty: none)
  std::vector<Parameter> swept;                            // grid axes and seeds, in command-line order
  std::vector<std::pair<std::string, std::string>> fixed;  // --set name=value
  long total = 0;                                          // runs
  std::map<std::string, std::string> units;                // flag -> unit, from the example's --help (plot axes)
};

/// Creates DIR/runs and checks that files can be created in it, before any run starts (sweep_runs.cc).
void PrepareOutFolder(const Sweep& s);
/// Refuses to resume into a folder whose runs were made with other flags (sweep_runs.cc).
void CheckResume(const Sweep& s);
/// This rank's share of the runs (i = rank, rank + size, ...), skipping those done before; returns how many it ran.
long RunShare(const Sweep& s, int rank, int size);
/// Run i's values of the swept parameters (the first parameter varies slowest).
std::vector<std::string> RunValues(const Sweep& s, long index);
/// DIR/runs/run_NNNNNN.<ext>.
std::string RunPath(const Sweep& s, long i, const char* ext);
/// Run i's record, if it is a valid one.
std::optional<RunRecord> ReadRecord(const Sweep& s, long i);
/// Run i's summary: whether something is at its name, and its content if that is a valid summary.
struct SummaryFile {
  bool present = false;
  std::optional<nlohmann::json> summary;
};
SummaryFile ReadSummary(const Sweep& s, long i);
/// Writes sweep.csv, sweep.json and the plot; throws std::runtime_error naming a file that cannot be written
/// (sweep_results.cc).
void Gather(const Sweep& s);

}  // namespace rome::sweep
