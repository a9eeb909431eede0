#include "examples/sweep/sweep_io.h"

#include <cctype>
#include <charconv>
#include <climits>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include "framework/text.h"

namespace rome::sweep {
namespace {

using nlohmann::json;

std::invalid_argument Error(const std::string& message) { return std::invalid_argument("rome_sweep: " + message); }

std::string Format(double v) {
  std::ostringstream os;
  os.precision(10);
  os << v;
  return os.str();
}

std::vector<std::string_view> Split(std::string_view text, char separator) {
  std::vector<std::string_view> parts;
  for (size_t at = 0;;) {
    const size_t end = text.find(separator, at);
    parts.push_back(text.substr(at, end == std::string_view::npos ? std::string_view::npos : end - at));
    if (end == std::string_view::npos) return parts;
    at = end + 1;
  }
}

// The whole of `s` as a finite number (an optional leading '+' allowed, as a user types it).
bool ParseDouble(std::string_view s, double* v) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-' && s[1] != '+') s.remove_prefix(1);
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), *v);
  return !s.empty() && ec == std::errc() && ptr == s.data() + s.size() && std::isfinite(*v);
}

// The whole of `s` as a whole number of type T.
template <typename T>
bool ParseWhole(std::string_view s, T* v) {
  const auto [ptr, ec] = std::from_chars(s.data(), s.data() + s.size(), *v);
  return !s.empty() && ec == std::errc() && ptr == s.data() + s.size();
}

// Throws, from a parse callback, when a value nests deeper than kMaxSummaryDepth.
struct TooDeep {};

json ParseWithDepthCap(std::string_view text) {
  return json::parse(text, [](int depth, json::parse_event_t, json&) {
    if (depth > kMaxSummaryDepth) throw TooDeep{};
    return true;
  });
}

}  // namespace

Parameter ParseGrid(const std::string& spec, bool integer) {
  const size_t eq = spec.find('=');
  if (eq == std::string::npos || eq == 0) throw Error("--grid '" + Excerpt(spec) + "' must be NAME=LO:HI:N");
  Parameter p{spec.substr(0, eq), {}, "--grid " + Excerpt(spec)};
  const std::string range = spec.substr(eq + 1);
  const std::vector<std::string_view> parts = Split(range, ':');
  auto malformed = [&] {
    return Error("--grid " + Excerpt(p.name) + ": malformed range '" + Excerpt(range) +
                 "' (expected LO:HI:N with finite LO, HI and N in 1.." + std::to_string(kMaxGridPoints) +
                 "; LO and HI may be tuples a,b,... of the same length)");
  };
  int n = 0;
  if (parts.size() != 3 || !ParseWhole(parts[2], &n) || n < 1 || n > kMaxGridPoints) throw malformed();
  const std::vector<std::string_view> lo_text = Split(parts[0], ','), hi_text = Split(parts[1], ',');
  if (lo_text.size() != hi_text.size() || lo_text.size() > 16) throw malformed();
  std::vector<double> lo(lo_text.size()), hi(hi_text.size());
  for (size_t e = 0; e < lo.size(); ++e)
    if (!ParseDouble(lo_text[e], &lo[e]) || !ParseDouble(hi_text[e], &hi[e])) throw malformed();
  for (int k = 0; k < n; ++k) {
    std::string value;
    for (size_t e = 0; e < lo.size(); ++e) {
      const double v = n == 1 ? lo[e] : lo[e] + (hi[e] - lo[e]) * k / (n - 1);
      if (!std::isfinite(v)) throw Error(p.origin + ": the values overflow (LO and HI are too far apart)");
      if (integer && (v != std::floor(v) || v < INT_MIN || v > INT_MAX))
        throw Error(p.origin + ": --" + Excerpt(p.name) + " takes whole numbers, and this grid gives " + Format(v) +
                    " (choose LO, HI and N so that every value is a whole number of int's range)");
      if (e > 0) value += ',';
      value += integer ? std::to_string(static_cast<long long>(v)) : Format(v);
    }
    p.values.push_back(value);
  }
  return p;
}

Parameter ParseSeeds(const std::string& spec) {
  const size_t eq = spec.find('=');
  const std::string name = eq == std::string::npos ? "seed" : spec.substr(0, eq);
  const std::string range = eq == std::string::npos ? spec : spec.substr(eq + 1);
  const std::vector<std::string_view> parts = Split(range, ':');
  long a = 0, b = 0;
  if (name.empty() || parts.size() != 2 || !ParseWhole(parts[0], &a) || !ParseWhole(parts[1], &b) || a < 0 || b < a ||
      b > INT_MAX)
    throw Error("--seeds: malformed range '" + Excerpt(spec) +
                "' (expected A:B or NAME=A:B with whole numbers 0 <= A <= B <= " + std::to_string(INT_MAX) + ")");
  if (b - a + 1 > kMaxRuns)
    throw Error("--seeds " + Excerpt(spec) + ": " + std::to_string(b - a + 1) + " seeds; a sweep has at most " +
                std::to_string(kMaxRuns) + " runs");
  Parameter p{name, {}, "--seeds " + Excerpt(spec), true};
  for (long s = a; s <= b; ++s) p.values.push_back(std::to_string(s));
  return p;
}

long CountRuns(const std::vector<Parameter>& swept) {
  long total = 1;
  double product = 1;
  bool over = false;
  std::string factors;
  for (const Parameter& p : swept) {
    const long n = static_cast<long>(p.values.size());
    factors += (factors.empty() ? "" : " x ") + std::to_string(n);
    product *= static_cast<double>(n);
    if (n > 0 && total > kMaxRuns / n) over = true;  // total * n > kMaxRuns, without computing it
    if (!over) total *= n;
  }
  if (over)
    throw Error("the grids and seeds give " + factors + " = " + Format(product) + " runs; a sweep has at most " +
                std::to_string(kMaxRuns) + " (split it into several sweeps)");
  return total;
}

std::pair<std::string, std::string> ParseSet(const std::string& arg) {
  const size_t eq = arg.find('=');
  if (eq == std::string::npos || eq == 0) throw Error("--set '" + Excerpt(arg) + "' must be NAME=VALUE");
  // Each run's flags are recorded as JSON, which holds UTF-8 text only.
  if (!IsValidUtf8(arg)) throw Error("--set '" + Excerpt(arg) + "': not valid UTF-8");
  return {arg.substr(0, eq), arg.substr(eq + 1)};
}

void CheckFlagsGivenOnce(const std::vector<Parameter>& swept,
                         const std::vector<std::pair<std::string, std::string>>& fixed) {
  static const std::map<std::string, std::string> kReserved = {
      {"summary", "rome_sweep gives every run its own --summary (DIR/runs/run_N.json)"},
      {"log", "rome_sweep runs every example with --log '' (its output goes to DIR/runs/run_N.log)"},
      {"help", "--help prints the help and runs nothing"},
      {"scenario-file",
       "a run's parameters are fingerprinted from its command line, not from a file that may change before a resume "
       "(give them with --set)"},
      {"plots", "every run would write its plots into the same folder"},
      {"animation", "every run would write the same file"}};
  std::map<std::string, std::string> given;  // flag -> the argument that gave it first
  for (const Parameter& p : swept) {
    if (auto r = kReserved.find(p.name); r != kReserved.end())
      throw Error(p.origin + ": --" + p.name + " cannot be swept: " + r->second);
    if (auto [it, fresh] = given.emplace(p.name, p.origin); !fresh)
      throw Error(p.origin + ": --" + Excerpt(p.name) + " is already swept by " + it->second + " (one grid per flag)");
  }
  for (const auto& [name, value] : fixed) {
    const std::string origin = "--set " + Excerpt(name + "=" + value);
    if (auto r = kReserved.find(name); r != kReserved.end())
      throw Error(origin + ": --" + name + " cannot be set: " + r->second);
    if (auto [it, fresh] = given.emplace(name, origin); !fresh) {
      if (it->second.rfind("--set", 0) == 0)
        throw Error(origin + ": --" + Excerpt(name) + " is already set by " + it->second);
      throw Error(origin + ": --" + Excerpt(name) + " is swept by " + it->second +
                  " (a fixed value would replace the swept one in every run)");
    }
  }
}

std::set<std::string> FlagsInHelp(const std::string& help) {
  std::set<std::string> flags;
  for (size_t at = help.find("--"); at != std::string::npos; at = help.find("--", at + 2)) {
    size_t end = at + 2;
    while (end < help.size() && (std::isalnum(static_cast<unsigned char>(help[end])) || help[end] == '-')) ++end;
    if (end > at + 2) flags.insert(help.substr(at + 2, end - at - 2));
  }
  return flags;
}

std::map<std::string, std::string> FlagUnitsInHelp(const std::string& help) {
  std::map<std::string, std::string> units;
  std::istringstream lines(help);
  std::string flag;
  for (std::string line; std::getline(lines, line);) {
    const size_t first = line.find_first_not_of(' ');
    if (first == std::string::npos) continue;
    if (line.compare(first, 2, "--") == 0) {
      flag = line.substr(first + 2, line.find(' ', first) == std::string::npos ? std::string::npos
                                                                               : line.find(' ', first) - first - 2);
    } else if (!flag.empty() && line[first] == '[' && line.find(']', first) != std::string::npos) {
      units[flag] = line.substr(first + 1, line.find(']', first) - first - 1);
      flag.clear();
    } else {
      flag.clear();
    }
  }
  return units;
}

std::string RunRecordText(const RunRecord& record) {
  // ParseSet admits only valid UTF-8, so `replace` never changes a flag; it keeps dump() from throwing.
  return std::to_string(record.exit_code) + "\n" +
         json(record.flags).dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

std::optional<RunRecord> ParseRunRecord(const std::string& text) {
  const std::string_view body(text);
  const size_t first = body.find('\n');
  if (first == std::string_view::npos || body.back() != '\n') return std::nullopt;
  const std::string_view second = body.substr(first + 1, body.size() - first - 2);  // without its final newline
  if (first + 1 == body.size() || second.find('\n') != std::string_view::npos) return std::nullopt;
  RunRecord record;
  if (!ParseWhole(body.substr(0, first), &record.exit_code) || record.exit_code < kMinExitCode ||
      record.exit_code > kMaxExitCode)
    return std::nullopt;
  try {
    const json flags = ParseWithDepthCap(second);
    if (!flags.is_array()) return std::nullopt;
    for (const json& f : flags) {
      if (!f.is_string()) return std::nullopt;
      record.flags.push_back(f.get<std::string>());
    }
  } catch (...) {  // not JSON, invalid UTF-8, or nested too deep
    return std::nullopt;
  }
  return record;
}

std::optional<nlohmann::json> ParseSummary(const std::string& text) {
  json summary;
  try {
    summary = ParseWithDepthCap(text);
  } catch (...) { return std::nullopt; }
  if (!summary.is_object()) return std::nullopt;
  for (const char* field : {"status", "status_kind"}) {
    const auto it = summary.find(field);
    if (it == summary.end() || !it->is_string()) return std::nullopt;
  }
  return summary;
}

}  // namespace rome::sweep
