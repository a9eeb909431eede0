#include "examples/common/cli.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "framework/files.h"
#include "framework/text.h"

namespace rome::examples {

std::string OneLine(const std::string& message) {
  std::string out;
  char buf[8];
  for (char ch : message) {
    const unsigned char c = static_cast<unsigned char>(ch);
    if (c == '\n' || c == '\r' || c == '\t')
      out += ' ';
    else if (c < 0x20 || c == 0x7F) {
      std::snprintf(buf, sizeof(buf), "\\x%02X", c);
      out += buf;
    } else
      out += ch;
    if (out.size() >= 2000) {
      out += "...";
      break;
    }
  }
  return out;
}

std::string FormatNumber(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

CommandLine& CommandLine::Option(const std::string& name, const std::string& default_value, const std::string& help) {
  order_.push_back(name);
  decls_[name] = {default_value, help, false};
  return *this;
}

CommandLine& CommandLine::Flag(const std::string& name, const std::string& help) {
  order_.push_back(name);
  decls_[name] = {"", help, true};
  return *this;
}

bool CommandLine::Parse(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    std::string arg = argv[i];
    if (arg == "--help" || arg == "-h") {
      std::cout << Help();
      return false;
    }
    if (arg.rfind("--", 0) != 0)
      throw std::invalid_argument(program_ + ": unexpected argument '" + arg + "' (options start with --; see --help)");
    std::string name = arg.substr(2), value;
    const auto eq = name.find('=');
    if (eq != std::string::npos) {
      value = name.substr(eq + 1);
      name = name.substr(0, eq);
    }
    auto it = decls_.find(name);
    if (it == decls_.end()) throw std::invalid_argument(program_ + ": unknown option '--" + name + "' (see --help)");
    // An option given twice is refused (the first would be dropped without a word).
    if (const auto seen = values_.find(name); seen != values_.end())
      throw std::invalid_argument(program_ + ": option '--" + name + "' is given twice (first '" +
                                  Excerpt(seen->second, 80) + "'); give it once");
    if (it->second.is_flag) {
      // --FLAG or --FLAG=true|1 turns it on; --FLAG=false|0 turns it off (and overrides a scenario file that sets it).
      if (eq == std::string::npos || value == "1" || value == "true")
        values_[name] = "1";
      else if (value == "0" || value == "false")
        values_[name] = "";
      else
        throw std::invalid_argument(program_ + ": '--" + name + "' is a flag: give it alone, or as --" + name +
                                    "=true|false (got '" + Excerpt(arg.substr(2), 80) + "')");
      continue;
    }
    if (eq == std::string::npos) {
      if (i + 1 >= argc) throw std::invalid_argument(program_ + ": option '--" + name + "' needs a value");
      value = argv[++i];
    }
    values_[name] = value;
  }
  if (has_scenario_file_ && !Get("scenario-file").empty()) LoadScenarioFile(Get("scenario-file"));
  return true;
}

bool CommandLine::IsSet(const std::string& name) const {
  const auto d = decls_.find(name);
  if (d == decls_.end()) throw std::logic_error(program_ + ": option '--" + name + "' was never declared");
  const std::string value = Get(name), default_value = d->second.default_value;
  if (value == default_value) return false;
  if (d->second.is_flag) return !value.empty();
  // Numbers and lists of numbers by value ("0.30,0.40" is "0.3,0.4").
  auto numbers = [](const std::string& text) {
    std::vector<double> out;
    std::stringstream in(text);
    for (std::string item; std::getline(in, item, ',');) {
      size_t used = 0;
      try {
        out.push_back(std::stod(item, &used));
      } catch (const std::exception&) { return std::vector<double>{}; }
      if (used != item.size()) return std::vector<double>{};
    }
    return out;
  };
  const std::vector<double> a = numbers(value), b = numbers(default_value);
  return a.empty() || a != b;
}

void CommandLine::RequireModeFor(const std::string& option, const std::string& mode,
                                 const std::vector<std::string>& modes) const {
  if (!IsSet(option) || std::find(modes.begin(), modes.end(), Get(mode)) != modes.end()) return;
  std::string allowed;
  for (const std::string& m : modes) allowed += (allowed.empty() ? "" : "|") + m;
  throw std::invalid_argument(program_ + ": --" + option + " applies to --" + mode + " " + allowed + " only (got --" +
                              mode + " " + Excerpt(Get(mode), 80) + "); leave --" + option + " out");
}

std::string CommandLine::NameTheOption(const std::string& message,
                                       const std::vector<std::pair<std::string, std::string>>& parameters) const {
  const std::string prefix = program_ + ": ";
  const std::string text = message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message;
  if (text.rfind("--", 0) == 0) return prefix + text;  // already names its option
  auto is_name_char = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '.'; };
  for (const auto& [parameter, option] : parameters) {
    if (!decls_.count(option)) continue;  // a table naming an undeclared option must not throw from an error handler
    for (size_t at = text.find(parameter); at != std::string::npos; at = text.find(parameter, at + 1)) {
      const size_t end = at + parameter.size();
      if ((at > 0 && is_name_char(text[at - 1])) || (end < text.size() && is_name_char(text[end])))
        continue;  // part of a longer name
      return prefix + "--" + option + " " + Excerpt(Get(option), 200) + ": " + text;
    }
  }
  return prefix + text;
}

std::string CommandLine::Get(const std::string& name) const {
  auto v = values_.find(name);
  if (v != values_.end()) return v->second;
  auto d = decls_.find(name);
  if (d == decls_.end()) throw std::logic_error(program_ + ": option '--" + name + "' was never declared");
  return d->second.default_value;
}

std::string CommandLine::ValueError(const std::string& name, const std::string& expected) const {
  if (const auto it = from_file_.find(name); it != from_file_.end())
    return program_ + ": --scenario-file " + scenario_file_ + ": key '" + name + "' needs " + expected + ", got " +
           it->second;
  return program_ + ": option '--" + name + "' needs " + expected + ", got '" + Get(name) + "'";
}

// A scalar option from the scenario file is a JSON number or string, never an array (an array of one number would
// otherwise pass as that number).
double CommandLine::GetDouble(const std::string& name) const {
  const std::string s = Get(name);
  try {
    if (const auto it = from_file_.find(name); it != from_file_.end() && it->second.rfind('[', 0) == 0)
      throw std::invalid_argument("");
    size_t used = 0;
    const double v = std::stod(s, &used);
    if (used != s.size() || !std::isfinite(v)) throw std::invalid_argument("");
    return v;
  } catch (const std::exception&) { throw std::invalid_argument(ValueError(name, "a finite number")); }
}

int CommandLine::GetInt(const std::string& name) const {
  const std::string s = Get(name);
  try {
    if (const auto it = from_file_.find(name); it != from_file_.end() && it->second.rfind('[', 0) == 0)
      throw std::invalid_argument("");
    size_t used = 0;
    const int v = std::stoi(s, &used);
    if (used != s.size()) throw std::invalid_argument("");
    return v;
  } catch (const std::exception&) { throw std::invalid_argument(ValueError(name, "an integer")); }
}

std::optional<std::vector<double>> ParseNumberList(const std::string& text, int n) {
  std::vector<double> v;
  for (size_t start = 0;;) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    size_t used = 0;
    try {
      v.push_back(std::stod(item, &used));
    } catch (const std::exception&) { return std::nullopt; }
    if (used != item.size() || !std::isfinite(v.back()) || static_cast<int>(v.size()) > n) return std::nullopt;
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (static_cast<int>(v.size()) != n) return std::nullopt;
  return v;
}

std::vector<double> CommandLine::GetNumbers(const std::string& name, int n, const std::string& form) const {
  const std::string s = Get(name);
  std::optional<std::vector<double>> v = ParseNumberList(s, n);
  if (!v && from_file_.count(name))
    throw std::invalid_argument(ValueError(name, std::to_string(n) + " numbers " + form));
  if (!v)
    throw std::invalid_argument(program_ + ": --" + name + " expects " + std::to_string(n) + " numbers " + form +
                                ", got '" + Excerpt(s, 200) + "'");
  return *v;
}

bool CommandLine::GetFlag(const std::string& name) const {
  const auto it = values_.find(name);
  return it != values_.end() && it->second == "1";
}

std::string CommandLine::Help() const {
  std::ostringstream os;
  os << "Usage: " << program_ << " [options]\n\n" << summary_ << "\n\nOptions:\n";
  for (const auto& name : order_) {
    const Decl& d = decls_.at(name);
    os << "  --" << name << (d.is_flag ? "" : " VALUE");
    os << "\n      " << d.help;
    if (!d.is_flag && !d.default_value.empty()) os << " (default: " << d.default_value << ")";
    os << "\n";
  }
  os << "  --help\n      Print this help and exit.\n";
  return os.str();
}

void CommandLine::CheckOutputs(std::initializer_list<const char*> files,
                               std::initializer_list<const char*> folders) const {
  namespace fs = std::filesystem;
  std::map<std::string, std::string> seen;  // absolute, normalised path -> the option that names it
  for (const char* name : files) {
    const std::string path = Get(name);
    if (path.empty()) continue;
    if (const std::string problem = CheckOutputPath(path, "cannot write"); !problem.empty())
      throw std::invalid_argument(program_ + ": --" + name + ": " + problem);
    std::error_code ec;
    // The folder resolved, the name as given: a link at the name is replaced by the write, not followed.
    const fs::path absolute = fs::absolute(path, ec);
    const std::string key = (fs::weakly_canonical(absolute.parent_path(), ec) / absolute.filename()).string();
    if (const auto [it, inserted] = seen.emplace(key, name); !inserted)
      throw std::invalid_argument(program_ + ": --" + name + " and --" + it->second + " name the same file '" +
                                  Excerpt(path, 200) + "'; give each output its own file");
  }
  // An output never overwrites an input: an option's value that names an existing regular file (a terrain, a scenario
  // file, a robot) is compared with every output, the output's folder and name resolved as above.
  for (const std::string& name : order_) {
    const std::string path = Get(name);
    std::error_code ec;
    if (path.empty() || decls_.at(name).is_flag || !fs::is_regular_file(path, ec)) continue;
    const fs::path absolute = fs::absolute(path, ec);
    for (const std::string& key : {(fs::weakly_canonical(absolute.parent_path(), ec) / absolute.filename()).string(),
                                   fs::weakly_canonical(absolute, ec).string()})
      if (const auto it = seen.find(key); it != seen.end() && it->second != name)
        throw std::invalid_argument(program_ + ": --" + it->second + " names the file '" + Excerpt(path, 200) +
                                    "' that --" + name +
                                    " reads; writing it would destroy the input: give the output its own file");
  }
  for (const char* name : folders) {
    const std::string path = Get(name);
    if (path.empty()) continue;
    std::error_code ec;
    fs::create_directories(path, ec);
    if (ec || !fs::is_directory(path, ec))
      throw std::invalid_argument(program_ + ": --" + name + ": cannot create the folder '" + Excerpt(path, 200) + "'");
  }
}

bool WriteOutputFile(const std::string& program, const std::string& path, const std::string& content,
                     const std::string& what) {
  try {
    WriteFileAtomically(path, content, what);
    return true;
  } catch (const std::exception& e) {
    std::cerr << program << ": " << OneLine(e.what()) << "\n";
    return false;
  }
}

}  // namespace rome::examples
