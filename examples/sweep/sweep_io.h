#pragma once
// What rome_sweep parses and writes, apart from running programs, as pure functions (tested by
// tests/examples/sweep_io_test.cc, fuzzed by tests/fuzz/sweep_input_fuzzer.cc): its grids and seeds, the checks
// that keep each flag given once, the cap on the run count, each run's record (run_N.exit, trusted on resume only if
// it is exactly what RunRecordText writes), the runs' JSON summaries, and the cells of sweep.csv.
// Every error is a std::invalid_argument of one line, "rome_sweep: ...", naming the flag and the value.

#include <optional>
#include <map>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/text.h"

namespace rome::sweep {

using rome::CsvCell;  // framework/text.h: sweep.csv cells

/// The most runs of one sweep (run files are numbered with six digits).
inline constexpr long kMaxRuns = 1000000;
/// The most values of one --grid.
inline constexpr int kMaxGridPoints = 100000;
/// The deepest nesting of a run's summary that is read (the examples write 3 levels).
inline constexpr int kMaxSummaryDepth = 32;

/// One swept flag: its values as passed to the example, and the argument that gave it (for messages).
struct Parameter {
  std::string name;
  std::vector<std::string> values;
  std::string origin;  ///< e.g. "--grid energy=0.1:0.7:4"
  bool seeds = false;  ///< from --seeds: the runs of each value pool into one point of the plots
};

/// --grid NAME=LO:HI:N: N values from LO to HI (N = 1: LO alone), with finite LO and HI and N in 1..kMaxGridPoints.
/// LO and HI may be tuples of the same length, for a flag that takes several numbers (--grid
/// sensor-noise=0,0:1e-4,1e-3:3 sends 0,0 then 5e-05,0.0005 then 0.0001,0.001): each entry runs from its LO to its
/// HI, and the plots' axis is the first entry. For an `integer` flag every value must be a whole number in int's
/// range (--grid steps=1:2:3 is refused, it would send 1.5).
Parameter ParseGrid(const std::string& spec, bool integer);

/// --seeds A:B, or --seeds NAME=A:B for a seed flag with another name (walking's perturbation-seed): the flag = A,
/// A+1, ..., B with 0 <= A <= B <= 2147483647 and at most kMaxRuns seeds. The result has `seeds` set.
Parameter ParseSeeds(const std::string& spec);

/// The number of runs, the product of the swept values' counts; refused, naming the cap, beyond kMaxRuns (computed
/// without overflow, whatever the grids).
long CountRuns(const std::vector<Parameter>& swept);

/// --set NAME=VALUE as (NAME, VALUE); refused if there is no NAME or the text is not valid UTF-8.
std::pair<std::string, std::string> ParseSet(const std::string& arg);

/// Refuses a flag swept twice, a --set of a swept flag, a flag set twice, and the flags rome_sweep gives every run
/// itself (--summary, --log) or that end a run (--help). `fixed` holds the --set NAME=VALUE pairs.
void CheckFlagsGivenOnce(const std::vector<Parameter>& swept,
                         const std::vector<std::pair<std::string, std::string>>& fixed);

/// The flag names a program's --help text shows ("--name").
std::set<std::string> FlagsInHelp(const std::string& help);
/// The unit of each flag whose help line starts with one in brackets ("  --push-impulse VALUE\n      [N s] ..."):
/// {"push-impulse", "N s"}. For plot axes.
std::map<std::string, std::string> FlagUnitsInHelp(const std::string& help);

/// What rome_sweep records of a finished run in run_N.exit (written last, atomically): how the run ended, and the
/// flags it ran with, its parameters' fingerprint, so that a resume with other parameters is refused.
struct RunRecord {
  int exit_code = 0;               ///< 0-255 as the program exited, or -N when signal N (1-64) killed it
  std::vector<std::string> flags;  ///< the swept and fixed flags, without the output paths
  bool KilledBySignal() const { return exit_code < 0; }
  bool operator==(const RunRecord&) const = default;
};
inline constexpr int kMinExitCode = -64, kMaxExitCode = 255;

/// The record's text: the exit code on the first line, the flags as a JSON array of strings on the second.
std::string RunRecordText(const RunRecord& record);

/// The record of a text that is exactly what RunRecordText writes (an exit code in range, flags that are strings),
/// else nothing: such a run is not trusted and runs again.
std::optional<RunRecord> ParseRunRecord(const std::string& text);

/// A run's summary: a JSON object, nested at most kMaxSummaryDepth deep, with the string fields "status" and
/// "status_kind" (which stepping_stones and bouncing_ball write); anything else is nothing.
std::optional<nlohmann::json> ParseSummary(const std::string& text);

}  // namespace rome::sweep
