// libFuzzer harness for what rome_sweep parses (examples/sweep/sweep_io.h): its --grid and --seeds ranges, --set, the
// run records and summaries it reads back on resume, and the CSV cells it writes.
//
// Input: a first byte choosing the parser (its value mod 8: the digits '0' to '7' in the seeds), then the text given
// to it: 0 grid, 1 grid of an integer flag, 2 seeds, 3 run record, 4 summary, 5 CSV cell, 6 and 7 --set.
// Fine: a value that keeps the parser's promise (below), or std::invalid_argument whose message is one line.
// A finding: any other exception, a multi-line message, a crash, a sanitizer report, a hang (-timeout), or:
//   grid: a value count outside 1..kMaxGridPoints, a value entry (a tuple's, comma-separated) that is not a finite
//   number or (integer flags) not whole, values of different tuple lengths;
//   seeds: more than kMaxRuns seeds, or seeds that are not consecutive whole numbers;
//   set: an empty name, or text that is not UTF-8;
//   run record: a record that RunRecordText and ParseRunRecord do not give back, or an exit code out of range;
//   summary: a value that is not an object with string "status" and "status_kind";
//   CSV cell: a cell that does not read back (RFC 4180) as the text, or the text after a "'"; a special character
//   outside quotes; a read-back cell that a spreadsheet would run as a formula.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>
#include <string_view>

#include "examples/sweep/sweep_io.h"
#include "framework/text.h"

namespace {

using namespace rome::sweep;

[[noreturn]] void Finding(const char* what, const std::string& input) {
  std::fprintf(stderr, "sweep_input_fuzzer: %s (input '%s')\n", what, rome::Excerpt(input, 200).c_str());
  std::abort();
}

double Number(const std::string& text) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  return (text.empty() || *end != '\0') ? std::nan("") : v;
}

void Grid(const std::string& text, bool integer) {
  const Parameter p = ParseGrid(text, integer);
  if (p.values.empty() || p.values.size() > static_cast<size_t>(kMaxGridPoints))
    Finding("grid value count out of range", text);
  // Each value is a tuple a,b,... (one entry for a flag of one number) of the same length in every value.
  size_t entries = 0;
  for (const std::string& v : p.values) {
    size_t count = 0;
    for (size_t at = 0;; ++count) {
      const size_t comma = v.find(',', at);
      const std::string entry = v.substr(at, comma == std::string::npos ? std::string::npos : comma - at);
      const double x = Number(entry);
      if (!std::isfinite(x)) Finding("grid value entry is not a finite number", text);
      if (integer && (x != std::floor(x) || entry.find_first_not_of("-0123456789") != std::string::npos))
        Finding("integer grid value entry is not whole", text);
      if (comma == std::string::npos) break;
      at = comma + 1;
    }
    if (entries != 0 && count + 1 != entries) Finding("grid values have different tuple lengths", text);
    entries = count + 1;
  }
}

void Seeds(const std::string& text) {
  const Parameter p = ParseSeeds(text);
  if (p.values.empty() || p.values.size() > static_cast<size_t>(kMaxRuns)) Finding("seed count out of range", text);
  for (size_t i = 1; i < p.values.size(); ++i)
    if (std::stol(p.values[i]) != std::stol(p.values[i - 1]) + 1) Finding("seeds are not consecutive", text);
}

void Record(const std::string& text) {
  const auto record = ParseRunRecord(text);
  if (!record) return;
  if (record->exit_code < kMinExitCode || record->exit_code > kMaxExitCode) Finding("exit code out of range", text);
  const auto again = ParseRunRecord(RunRecordText(*record));
  if (!again || !(*again == *record)) Finding("run record does not round-trip", text);
}

void Summary(const std::string& text) {
  const auto summary = ParseSummary(text);
  if (!summary) return;
  if (!summary->is_object() || !summary->at("status").is_string() || !summary->at("status_kind").is_string())
    Finding("summary without its fields", text);
}

// The text of a CSV cell as a spreadsheet reads it (RFC 4180).
std::string ReadCell(const std::string& cell) {
  if (cell.empty() || cell[0] != '"') return cell;
  std::string text;
  for (size_t i = 1; i + 1 < cell.size(); ++i) {
    text += cell[i];
    if (cell[i] == '"') ++i;
  }
  return text;
}

void Cell(const std::string& text) {
  const std::string cell = CsvCell(text);
  const bool quoted = !cell.empty() && cell[0] == '"';
  if (quoted && (cell.size() < 2 || cell.back() != '"')) Finding("quoted cell not closed", text);
  if (!quoted && cell.find_first_of(",\"\r\n") != std::string::npos) Finding("special character outside quotes", text);
  const std::string back = ReadCell(cell);
  if (back != text && back != "'" + text) Finding("cell does not read back as its text", text);
  if (!back.empty() && std::string_view("=+-@\t\r").find(back[0]) != std::string_view::npos &&
      !std::isfinite(Number(back)))
    Finding("cell would run as a formula", text);
}

void Set(const std::string& text) {
  const auto [name, value] = ParseSet(text);
  if (name.empty() || !rome::IsValidUtf8(name + value))
    Finding("--set accepted an empty name or text that is not UTF-8", text);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    switch (data[0] % 8) {
      case 0: Grid(text, false); break;
      case 1: Grid(text, true); break;
      case 2: Seeds(text); break;
      case 3: Record(text); break;
      case 4: Summary(text); break;
      case 5: Cell(text); break;
      default: Set(text); break;
    }
  } catch (const std::invalid_argument& e) {
    if (std::strpbrk(e.what(), "\n\r") != nullptr) Finding("multi-line error message", e.what());
  }
  return 0;
}
