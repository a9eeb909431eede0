#pragma once
// Tiny command-line parser shared by ROME's example programs: --name value options, --flags, and --help.
// Unknown options and malformed values are errors that name the option and the value.

#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace rome::examples {

/// An error message as the examples print it: one line (newlines, CRs and tabs become spaces, other control bytes
/// \xNN), cut at 2000 characters.
std::string OneLine(const std::string& message);

/// A number as a user would type it (shortest round-trip form, e.g. "1e-04" → "0.0001").
std::string FormatNumber(double v);

/// Writes an output atomically (framework/files.h: a temporary file beside it, renamed when complete, so a failure
/// or an interrupted run keeps the old file). False after printing "PROGRAM: <what> PATH: <reason>" on stderr.
bool WriteOutputFile(const std::string& program, const std::string& path, const std::string& content, const std::string& what);

/// Exactly `n` finite numbers separated by commas: no empty item, no junk, no trailing comma; nullopt otherwise.
std::optional<std::vector<double>> ParseNumberList(const std::string& text, int n);

class CommandLine {
 public:
  CommandLine(std::string program, std::string summary) : program_(std::move(program)), summary_(std::move(summary)) {}

  /// Declares an option with a default value (printed by --help).
  CommandLine& Option(const std::string& name, const std::string& default_value, const std::string& help);
  /// Declares a boolean flag (present = true).
  CommandLine& Flag(const std::string& name, const std::string& help);

  /// Parses argv. Returns false if --help was given (the help text is printed). Throws std::invalid_argument
  /// naming the option for unknown options or missing values.
  bool Parse(int argc, char** argv);

  std::string Get(const std::string& name) const;
  double GetDouble(const std::string& name) const;
  int GetInt(const std::string& name) const;
  /// Exactly `n` finite numbers separated by commas (`form` names them, e.g. "weight,kp,kd"): no empty item, no
  /// trailing junk or comma. std::invalid_argument "PROGRAM: --NAME expects N numbers FORM, got 'VALUE'" otherwise.
  std::vector<double> GetNumbers(const std::string& name, int n, const std::string& form) const;
  bool GetFlag(const std::string& name) const;
  std::string Help() const;
  /// Checks, before a long run, that the output options can be written: each of `files` (when not empty) is not a
  /// folder and its folder exists and is writable (nothing is created or opened), no two of them name the same file,
  /// and each of `folders` (when not empty) exists or can be created. Throws std::invalid_argument
  /// "PROGRAM: --NAME: ..." naming the first that fails.
  void CheckOutputs(std::initializer_list<const char*> files, std::initializer_list<const char*> folders) const;

  /// Reads a scenario file: a JSON object whose keys are option names (without "--") and whose values are strings,
  /// numbers, arrays of numbers (an option of comma-separated numbers) or booleans (flags). Each sets its option unless
  /// the command line gave it (the command line wins). Throws std::invalid_argument "PROGRAM: --scenario-file PATH: ..."
  /// naming an unknown key, a key of `not_allowed` (e.g. the output files), a value of another type, or a file that
  /// cannot be read or parsed.
  void ReadScenarioFile(const std::string& path, std::initializer_list<const char*> not_allowed);
  /// Every option's effective value (command line, then scenario file, then default) but those in `exclude`, as a JSON
  /// object text that ReadScenarioFile reads back to the same values: an integer or a finite number as a number, a
  /// list of numbers as an array, a flag as a boolean, anything else as a string.
  std::string ScenarioJson(std::initializer_list<const char*> exclude) const;

 private:
  struct Decl {
    std::string default_value, help;
    bool is_flag = false;
  };
  std::string program_, summary_;
  std::vector<std::string> order_;
  std::map<std::string, Decl> decls_;
  std::map<std::string, std::string> values_;       // given on the command line
  std::map<std::string, std::string> file_values_;  // given in the scenario file
};

}  // namespace rome::examples
