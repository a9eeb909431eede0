// rome_sweep: every run's record and summary gathered into sweep.csv, sweep.json and the plots (sweep.h).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "examples/sweep/sweep.h"
#include "framework/files.h"
#include "framework/text.h"
#include "systems/visualization/plot.h"

namespace rome::sweep {

namespace fs = std::filesystem;
using nlohmann::json;
using rome::Excerpt;

namespace {

std::string FailureReason(const std::optional<json>& summary, const std::optional<RunRecord>& record) {
  if (!record) return "no run record";
  if (record->KilledBySignal()) return "killed by signal " + std::to_string(-record->exit_code);
  if (!summary) return "no summary (exit code " + std::to_string(record->exit_code) + ")";
  const std::string status = summary->at("status").get<std::string>(),
                    kind = summary->at("status_kind").get<std::string>();
  const auto violations = summary->find("contact_violations");
  if (violations != summary->end() && violations->is_number() && violations->get<double>() > 0)
    return "contact violation";
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

// Every run's record and summary, flattened to the summary's deterministic scalar fields and lists of numbers (one
// level of objects: "tracking_rms.torso_pitch_rad").
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
  } else if (v.is_array() && !v.empty() &&
             std::all_of(v.begin(), v.end(), [](const json& x) { return x.is_number(); })) {
    // Any list of numbers (a tuple flag such as scenario.sensor-noise, a per-axis error): comma-joined, as a tuple
    // flag takes it (10 significant digits, as every number here).
    for (const json& x : v) text += (text.empty() ? "" : ",") + Format(x.get<double>());
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
    stats[key] = {{"mean", mean},
                  {"p5", Percentile(v, 0.05)},
                  {"p50", Percentile(v, 0.5)},
                  {"p95", Percentile(v, 0.95)},
                  {"min", Percentile(v, 0)},
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

// The axis label of a swept flag: a name with its symbol and unit for the flags listed here, else "name [unit]" when
// the example's help gives the flag's unit, else the flag's name.
std::string AxisLabel(const Sweep& s, const std::string& flag) {
  static const std::map<std::string, std::string> kUnits = {{"step-length", "step length l [m]"},
                                                            {"step-height", "step height h [m]"},
                                                            {"energy", "orbital energy E* [m^2/s^2]"},
                                                            {"epsilon", "epsilon [-]"},
                                                            {"min-gap", "min gap [m]"},
                                                            {"max-gap", "max gap [m]"},
                                                            {"max-rise", "max rise [m]"},
                                                            {"swing-clearance", "swing clearance [m]"},
                                                            {"initial-com-x", "initial COM x [m]"},
                                                            {"force-band", "force band c [-]"},
                                                            {"touchdown-speed", "touchdown speed [m/s]"},
                                                            {"duration", "duration [s]"},
                                                            {"height", "initial height [m]"},
                                                            {"hops", "hops [-]"},
                                                            {"steps", "steps [-]"}};
  if (const auto it = kUnits.find(flag); it != kUnits.end()) return it->second;
  const auto it = s.units.find(flag);
  return it == s.units.end() ? flag : flag + " [" + it->second + "]";
}

// The mean of `value(i)` over the runs i with each value of the first grid parameter (seeds and other grids pooled;
// runs where `value` gives NaN are left out), one line per value of the second parameter unless that is the seed.
template <typename Value>
std::vector<rome::visualization::Series> MeanOverParameter(const Sweep& s, const std::string& single_line,
                                                           const Value& value) {
  const Parameter& x = s.swept[0];
  const bool lines_by_second = s.swept.size() > 1 && !s.swept[1].seeds;
  const size_t lines = lines_by_second ? s.swept[1].values.size() : 1;
  std::vector<rome::visualization::Series> series;
  for (size_t l = 0; l < lines; ++l) {
    rome::visualization::Series ser{
        lines_by_second ? s.swept[1].name + " = " + s.swept[1].values[l] : single_line, {}, {}, "linespoints"};
    for (const std::string& xv : x.values) {
      long runs = 0;
      double sum = 0;
      for (long i = 0; i < s.total; ++i) {
        const auto v = RunValues(s, i);
        if (v[0] != xv || (lines_by_second && v[1] != s.swept[1].values[l])) continue;
        const double y = value(i);
        if (std::isnan(y)) continue;
        ++runs;
        sum += y;
      }
      if (runs == 0) continue;
      ser.x.push_back(std::strtod(xv.c_str(), nullptr));
      ser.y.push_back(sum / static_cast<double>(runs));
    }
    series.push_back(ser);
  }
  return series;
}

// Success rate over the first grid parameter.
void WriteSuccessOverParameter(const Sweep& s, const Results& r) {
  const auto series = MeanOverParameter(
      s, "success rate", [&](long i) { return r.records[i] && r.records[i]->exit_code == 0 ? 1.0 : 0.0; });
  WritePlotInto({"Success rate over " + s.swept[0].name, AxisLabel(s, s.swept[0].name), "success rate [-]", series},
                (fs::path(s.out) / "sweep_success_vs_parameter.png").string());
}

// The mean of the summary field s.metric (every run that reports it, failed or not) over the first grid parameter.
void WriteMetricOverParameter(const Sweep& s, const Results& r) {
  if (!r.numeric.count(s.metric)) {
    std::cerr << "warning: rome_sweep: --metric " << Excerpt(s.metric) << ": no run's summary has this numeric field; "
              << "sweep_metric_vs_parameter.png not drawn\n";
    return;
  }
  const auto series = MeanOverParameter(s, "mean over runs", [&](long i) {
    const auto it = r.numbers[i].find(s.metric);
    return it == r.numbers[i].end() ? std::nan("") : it->second;
  });
  WritePlotInto({"Mean " + s.metric + " over " + s.swept[0].name + " (every run reporting it)",
                 AxisLabel(s, s.swept[0].name), s.metric, series},
                (fs::path(s.out) / "sweep_metric_vs_parameter.png").string());
}

void WritePlots(const Sweep& s, const Results& r) {
  if (!s.swept[0].seeds) WriteSuccessOverParameter(s, r);
  if (!s.swept[0].seeds && !s.metric.empty()) WriteMetricOverParameter(s, r);
  if (!s.swept[0].seeds && r.numeric.count("mean_forward_speed_mps")) {
    std::vector<rome::visualization::Series> series;
    const Parameter& x = s.swept[0];
    const size_t lines = s.swept.size() > 1 ? s.swept[1].values.size() : 1;
    for (size_t l = 0; l < lines; ++l) {
      rome::visualization::Series ser{
          s.swept.size() > 1 ? s.swept[1].name + " = " + s.swept[1].values[l] : "runs", {}, {}, "linespoints"};
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
    WritePlotInto({"Mean forward speed (successful runs)", AxisLabel(s, x.name), "mean forward speed [m/s]", series},
                  (fs::path(s.out) / "sweep_speed.png").string());
  } else {
    rome::visualization::Series ser{"success rate so far", {}, {}, "lines"};
    long ok = 0;
    for (long i = 0; i < s.total; ++i) {
      ok += r.records[i] && r.records[i]->exit_code == 0 ? 1 : 0;
      ser.x.push_back(static_cast<double>(i + 1));
      ser.y.push_back(static_cast<double>(ok) / static_cast<double>(i + 1));
    }
    WritePlotInto({"Success rate over runs", "runs completed [-]", "success rate [-]", {ser}},
                  (fs::path(s.out) / "sweep_success.png").string());
  }
}

}  // namespace

void Gather(const Sweep& s) {
  const Results r = ReadResults(s);
  rome::WriteFileAtomically((fs::path(s.out) / "sweep.csv").string(), CsvText(s, r), "sweep CSV");
  const json agg = Aggregate(s, r);
  rome::WriteFileAtomically((fs::path(s.out) / "sweep.json").string(),
                            agg.dump(2, ' ', false, json::error_handler_t::replace) + "\n", "sweep JSON");
  WritePlots(s, r);
  std::cout << "rome_sweep: " << r.succeeded << " of " << s.total << " runs succeeded ("
            << 100.0 * agg["success_rate"].get<double>() << " %)";
  for (const auto& [reason, n] : r.failures) std::cout << "; " << Excerpt(reason) << ": " << n;
  std::cout << "\nrome_sweep: " << Excerpt((fs::path(s.out) / "sweep.csv").string(), 200)
            << ", sweep.json and the plots written\n";
}

}  // namespace rome::sweep
