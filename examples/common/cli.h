#pragma once
// Tiny command-line parser shared by ROME's example programs: --name value options, --flags, and --help.
// Unknown options and malformed values are errors that name the option and the value.

#include <initializer_list>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace rome::examples {

/// An error message as the examples print it: one line (newlines, CRs and tabs become spaces, other control bytes
/// \xNN), cut at 2000 characters.
std::string OneLine(const std::string& message);

/// A number as a user would type it (shortest round-trip form, e.g. "1e-04" → "0.0001").
std::string FormatNumber(double v);

/// Writes an output atomically (framework/files.h: a temporary file beside it, renamed when complete, so a failure
/// or an interrupted run keeps the old file). False after printing "PROGRAM: <what> PATH: <reason>" on stderr.
bool WriteOutputFile(const std::string& program, const std::string& path, const std::string& content,
                     const std::string& what);

/// Exactly `n` finite numbers separated by commas: no empty item, no junk, no trailing comma; nullopt otherwise.
std::optional<std::vector<double>> ParseNumberList(const std::string& text, int n);

class CommandLine {
 public:
  CommandLine(std::string program, std::string summary) : program_(std::move(program)), summary_(std::move(summary)) {}

  /// Declares an option with a default value (printed by --help).
  CommandLine& Option(const std::string& name, const std::string& default_value, const std::string& help);
  /// Declares a boolean flag (present = true).
  CommandLine& Flag(const std::string& name, const std::string& help);

  /// Declares --scenario-file FILE.json: a JSON object whose keys are this program's option names (without "--") and
  /// whose values are strings, numbers, arrays of numbers (an option of comma-separated numbers) or, for flags,
  /// booleans. Parse() reads it after argv: options given on the command line win. Every option except `outputs` (and
  /// scenario-file itself) is a scenario parameter; any other key is an error naming the key. ScenarioJson() writes the
  /// effective parameters back in the same form.
  CommandLine& ScenarioFile(std::vector<std::string> outputs);
  /// Parses argv (and the scenario file, if declared and given). Returns false if --help was given (the help text is
  /// printed). Throws std::invalid_argument naming the option for unknown options or missing values, and naming the
  /// file and the key for a scenario file that cannot be read or holds an unknown key or a value of another type.
  bool Parse(int argc, char** argv);
  /// Every scenario parameter's effective value as a JSON object's text (numbers as numbers, comma-separated numbers
  /// as arrays, flags as booleans, other values as strings), so that --scenario-file with it reproduces the run's
  /// parameters.
  std::string ScenarioJson() const;

  std::string Get(const std::string& name) const;
  /// A library Validate() error told in the command line's terms: the first of `parameters` ({the parameter's name as
  /// the library's message writes it, the option that sets it}) that `message` names gives
  /// "PROGRAM: --OPTION VALUE: MESSAGE" (the program's own prefix is not repeated); a message naming none comes back as
  /// it is (with the program's prefix).
  std::string NameTheOption(const std::string& message,
                            const std::vector<std::pair<std::string, std::string>>& parameters) const;
  double GetDouble(const std::string& name) const;
  int GetInt(const std::string& name) const;
  /// Exactly `n` finite numbers separated by commas (`form` names them, e.g. "weight,kp,kd"): no empty item, no
  /// trailing junk or comma. std::invalid_argument "PROGRAM: --NAME expects N numbers FORM, got 'VALUE'" otherwise.
  std::vector<double> GetNumbers(const std::string& name, int n, const std::string& form) const;
  bool GetFlag(const std::string& name) const;
  /// Whether option `name` holds other than its default (given on the command line or in a scenario file; numbers and
  /// lists of numbers compared by value, so a summary's scenario, which writes every default, sets nothing).
  bool IsSet(const std::string& name) const;
  /// A flag the chosen mode ignores is an error, never dropped: throws std::invalid_argument
  /// "PROGRAM: --OPTION applies to --MODE A|B only (got --MODE C)" when `option` is set and `mode` is not one of
  /// `modes`.
  void RequireModeFor(const std::string& option, const std::string& mode, const std::vector<std::string>& modes) const;
  std::string Help() const;
  /// Checks, before a long run, that the output options can be written: each of `files` (when not empty) is not a
  /// folder and its folder exists and is writable (nothing is created or opened), no two of them name the same file,
  /// and each of `folders` (when not empty) exists or can be created. Throws std::invalid_argument
  /// "PROGRAM: --NAME: ..." naming the first that fails.
  void CheckOutputs(std::initializer_list<const char*> files, std::initializer_list<const char*> folders) const;

 private:
  struct Decl {
    std::string default_value, help;
    bool is_flag = false;
  };
  std::string program_, summary_;
  std::vector<std::string> order_;
  std::map<std::string, Decl> decls_;
  std::map<std::string, std::string> values_;
  bool has_scenario_file_ = false;
  std::vector<std::string> outputs_;              // options that are not scenario parameters
  std::string scenario_file_;                     // the --scenario-file read, for errors
  std::map<std::string, std::string> from_file_;  // option -> its value as the scenario file wrote it (JSON)
  /// "PROGRAM: option '--NAME' needs EXPECTED, got 'VALUE'", or, for a value from the scenario file,
  /// "PROGRAM: --scenario-file FILE: key 'NAME' needs EXPECTED, got JSON".
  std::string ValueError(const std::string& name, const std::string& expected) const;
  bool IsScenarioParameter(const std::string& name) const;
  void LoadScenarioFile(const std::string& path);
};

}  // namespace rome::examples
