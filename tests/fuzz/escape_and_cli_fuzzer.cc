// libFuzzer harness for the output escapers of framework/text.h and the examples' command-line parser.
//
// Input: bytes. The whole input is escaped four ways; then it is split at NUL bytes into an argument list for
// CommandLine (examples/common/cli.h), whose values are read as numbers and number lists; and the whole input is
// read as a list of 1 to 4 numbers by ParseNumberList (the walking gait flags and the gain flags).
// Fine: escaped text that keeps its promise; std::invalid_argument (the parser's documented error).
// A finding: JsonStringForScript output that nlohmann::json does not parse back to the input (valid UTF-8 input), or
// that holds '<', '>', '&' or a raw U+2028/U+2029; HtmlText output with '<', '>', '"' or '\''; GnuplotString output
// with a line break, or a quote that is not joined in by sprintf; CsvCell output that does not read back as one cell;
// any other exception, a crash or a sanitizer report.
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "examples/common/cli.h"
#include "framework/text.h"

namespace {

[[noreturn]] void Finding(const char* what, const std::string& detail) {
  std::fprintf(stderr, "escape_and_cli_fuzzer: %s: %s\n", what, rome::Excerpt(detail, 200).c_str());
  std::abort();
}

void CheckEscapers(const std::string& s) {
  const std::string json = rome::JsonStringForScript(s);
  if (json.find_first_of("<>&") != std::string::npos || json.find("\xe2\x80\xa8") != std::string::npos ||
      json.find("\xe2\x80\xa9") != std::string::npos)
    Finding("JSON for a script holds markup or a JavaScript line break", json);
  try {
    const std::string back = nlohmann::json::parse(json).get<std::string>();
    if (rome::IsValidUtf8(s) && back != s) Finding("JSON does not parse back to its input", json);
  } catch (const nlohmann::json::exception&) { Finding("JSON does not parse", json); }
  if (rome::HtmlText(s).find_first_of("<>\"'") != std::string::npos) Finding("HTML text holds markup", s);
  // Without its joined-in quotes, the gnuplot expression is quoted pieces "'...'" joined by '.', nothing else.
  std::string gp = rome::GnuplotString(s);
  for (size_t at; (at = gp.find("'.sprintf('%c',39).'")) != std::string::npos;) gp.replace(at, 20, "");
  if (gp.size() < 2 || gp.front() != '\'' || gp.back() != '\'' || gp.find_first_of("\r\n") != std::string::npos ||
      gp.find('\'', 1) != gp.size() - 1)
    Finding("gnuplot string is not one quoted piece", gp);
  const std::string csv = rome::CsvCell(s);
  bool quoted = !csv.empty() && csv.front() == '"';
  if (!quoted && csv.find_first_of(",\"\r\n") != std::string::npos) Finding("CSV cell unquoted with a separator", csv);
  double number = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), number);
  const bool is_number = !s.empty() && ec == std::errc() && end == s.data() + s.size() && std::isfinite(number);
  if (!csv.empty() && std::string("=+-@").find(csv.front()) != std::string::npos && !(is_number && csv == s))
    Finding("CSV cell starts a formula", csv);  // only a finite number, kept as it is, may start with '-' or '+
}

void CheckCommandLine(const std::string& input) {
  std::vector<std::string> args = {"prog"};
  size_t start = 0;
  for (size_t end; (end = input.find('\0', start)) != std::string::npos && args.size() < 64; start = end + 1)
    args.push_back(input.substr(start, end - start));
  if (start < input.size() && args.size() < 64) args.push_back(input.substr(start));
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  rome::examples::CommandLine cli("prog", "fuzz");
  cli.Option("x", "1", "a number")
      .Option("n", "2", "an integer")
      .Option("list", "1,2,3", "three numbers")
      .Flag("f", "a flag");
  try {
    if (!cli.Parse(static_cast<int>(argv.size()), argv.data())) return;
    (void)cli.GetDouble("x");
    (void)cli.GetInt("n");
    const std::vector<double> v = cli.GetNumbers("list", 3, "a,b,c");
    if (v.size() != 3) Finding("GetNumbers returned another count", cli.Get("list"));
  } catch (const std::invalid_argument&) {
    // the documented error; the programs print it through OneLine
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  CheckEscapers(input);
  CheckCommandLine(input);
  for (int n = 1; n <= 4; ++n)
    if (const auto v = rome::examples::ParseNumberList(input, n)) {
      if (static_cast<int>(v->size()) != n) Finding("ParseNumberList returned another count", input);
      for (double x : *v)
        if (!std::isfinite(x)) Finding("ParseNumberList accepted a number that is not finite", input);
    }
  return 0;
}
