// CommandLine's scenario file (--scenario-file) and the effective scenario (cli.h).
#include <algorithm>
#include <charconv>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "examples/common/cli.h"
#include "framework/files.h"
#include "framework/text.h"
#include "systems/multibody/robot_file_text.h"

namespace rome::examples {

CommandLine& CommandLine::ScenarioFile(std::vector<std::string> outputs) {
  Option("scenario-file", "",
         "FILE.json: any of the other options (not the outputs) as {\"name\": value}; options given here win");
  outputs_ = std::move(outputs);
  has_scenario_file_ = true;
  return *this;
}

bool CommandLine::IsScenarioParameter(const std::string& name) const {
  return decls_.count(name) > 0 && name != "scenario-file" &&
         std::find(outputs_.begin(), outputs_.end(), name) == outputs_.end();
}

namespace {

// The shortest text that reads back as the same double.
std::string ExactNumber(double v) {
  char buf[64];
  const auto end = std::to_chars(buf, buf + sizeof(buf), v).ptr;
  return std::string(buf, end);
}

// The numbers of a comma-separated list of at least two finite numbers ("0.3,0.1"), else nothing.
std::optional<std::vector<double>> NumberList(const std::string& v) {
  if (v.find(',') == std::string::npos) return std::nullopt;
  std::vector<double> numbers;
  size_t start = 0;
  while (start <= v.size()) {
    const size_t end = std::min(v.find(',', start), v.size());
    double x = 0;
    const auto [ptr, ec] = std::from_chars(v.data() + start, v.data() + end, x);
    if (ec != std::errc() || ptr != v.data() + end || !std::isfinite(x) || end == start) return std::nullopt;
    numbers.push_back(x);
    start = end + 1;
  }
  return numbers;
}

}  // namespace

void CommandLine::LoadScenarioFile(const std::string& path) {
  const std::string where = program_ + ": --scenario-file " + Excerpt(path, 200);
  scenario_file_ = Excerpt(path, 200);
  std::string text;
  try {
    text = ReadRegularFile(path, "--scenario-file", 1 << 20);
  } catch (const std::exception& e) { throw std::invalid_argument(program_ + ": " + e.what()); }
  nlohmann::json j;
  try {
    j = ParseJsonStrict(text, where);  // no key twice (the last would silently win), nesting capped
  } catch (const std::exception& e) { throw std::invalid_argument(e.what()); }
  if (!j.is_object()) throw std::invalid_argument(where + ": expected a JSON object {\"option\": value, ...}");
  for (const auto& [key, value] : j.items()) {
    if (!IsScenarioParameter(key))
      throw std::invalid_argument(
          where + ": unknown key '" + Excerpt(key, 60) + "'" +
          (decls_.count(key) ? " (an output or the file itself, not a scenario parameter)" : " (see --help)"));
    const bool flag = decls_.at(key).is_flag;
    std::string v;
    if (flag && value.is_boolean())
      v = value.get<bool>() ? "1" : "";
    else if (!flag && value.is_string())
      v = value.get<std::string>();
    else if (!flag && value.is_number_integer())
      v = value.dump();
    else if (!flag && value.is_number_float())
      v = ExactNumber(value.get<double>());
    else if (!flag && value.is_array() && !value.empty() &&
             std::all_of(value.begin(), value.end(), [](const nlohmann::json& x) { return x.is_number(); })) {
      for (const auto& x : value)
        v += (v.empty() ? "" : ",") + (x.is_number_integer() ? x.dump() : ExactNumber(x.get<double>()));
    } else {
      throw std::invalid_argument(where + ": key '" + key + "' needs " +
                                  (flag ? "true or false" : "a string, a number or an array of numbers") + ", got " +
                                  Excerpt(value.dump(), 80));
    }
    if (values_.count(key)) continue;  // the command line wins
    if (flag && v.empty()) continue;   // false: the flag stays off
    values_[key] = v;
    from_file_[key] = Excerpt(value.dump(), 80);
  }
}

std::string CommandLine::ScenarioJson() const {
  nlohmann::json j = nlohmann::json::object();
  for (const std::string& name : order_) {
    if (!IsScenarioParameter(name)) continue;
    if (decls_.at(name).is_flag) {
      j[name] = GetFlag(name);
      continue;
    }
    // A number (or list of numbers) only where it reads back as the same text ("007", "-0", "0.30" stay strings): the
    // scenario file must give the program exactly what it was given.
    const std::string v = Get(name);
    if (const std::optional<std::vector<double>> list = NumberList(v)) {
      std::string again;
      for (double x : *list) again += (again.empty() ? "" : ",") + ExactNumber(x);
      if (again == v) {
        j[name] = *list;
        continue;
      }
    }
    const char* const last = v.data() + v.size();
    long long integer = 0;
    double number = 0;
    if (const auto [end, ec] = std::from_chars(v.data(), last, integer);
        !v.empty() && ec == std::errc() && end == last && std::to_string(integer) == v)
      j[name] = integer;
    else if (const auto [end2, ec2] = std::from_chars(v.data(), last, number);
             !v.empty() && ec2 == std::errc() && end2 == last && std::isfinite(number) && ExactNumber(number) == v)
      j[name] = number;
    else
      j[name] = v;
  }
  return j.dump(2);
}

}  // namespace rome::examples
