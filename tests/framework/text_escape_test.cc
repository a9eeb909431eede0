// The four escapers of framework/text.h: each output parses back to its input with a parser that is not the
// escaper's (nlohmann::json for JSON, a decoder of the five entities for HTML, an RFC 4180 reader for CSV), and none
// lets a hostile string end the context it is written into.
#include "framework/text.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace rome {
namespace {

const std::vector<std::string>& Hostile() {
  static const std::vector<std::string> strings = {
      "",
      "torso",
      "torso</script><img src=x onerror=\"document.title='PWNED'\">",
      "</SCRIPT ><!--<script>",
      "a\"b\\c'd`touch pwned`$(touch pwned)@macro",
      std::string("nul\0byte", 8),
      "line\nbreak\r\ttab\x01\x1f\x7f",
      "\xe2\x80\xa8 and \xe2\x80\xa9 end JavaScript lines",
      "caf\xc3\xa9 \xf0\x9f\xa4\x96",
      "=cmd|' /C calc'!A0",
      "+1,2",
      "-x",
      "@SUM(A1)",
  };
  return strings;
}

TEST(JsonStringForScript, ParsesBackAndCannotEndTheScript) {
  for (const std::string& s : Hostile()) {
    const std::string out = JsonStringForScript(s);
    EXPECT_EQ(nlohmann::json::parse(out).get<std::string>(), s) << out;
    EXPECT_EQ(out.find('<'), std::string::npos) << out;
    EXPECT_EQ(out.find('>'), std::string::npos) << out;
    EXPECT_EQ(out.find('&'), std::string::npos) << out;
    EXPECT_EQ(out.find("\xe2\x80\xa8"), std::string::npos) << out;
    EXPECT_EQ(out.find("\xe2\x80\xa9"), std::string::npos) << out;
    for (char c : out) EXPECT_GE(static_cast<unsigned char>(c), 0x20) << out;
  }
  // Invalid UTF-8 becomes U+FFFD, so the result is always valid JSON.
  EXPECT_EQ(nlohmann::json::parse(JsonStringForScript("a\xff"
                                                      "b"))
                .get<std::string>(),
            "a\xef\xbf\xbd"
            "b");
}

std::string DecodeEntities(const std::string& s) {
  static const std::vector<std::pair<std::string, char>> entities = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&#39;", '\''}};
  std::string out;
  for (size_t i = 0; i < s.size();) {
    bool matched = false;
    for (const auto& [entity, c] : entities)
      if (s.compare(i, entity.size(), entity) == 0) {
        out += c;
        i += entity.size();
        matched = true;
        break;
      }
    if (!matched) out += s[i++];
  }
  return out;
}

TEST(HtmlText, DecodesBackAndHasNoMarkup) {
  for (const std::string& s : Hostile()) {
    const std::string out = HtmlText(s);
    EXPECT_EQ(out.find_first_of("<>\"'"), std::string::npos) << out;
    bool has_control = false;
    for (char c : s) has_control |= (static_cast<unsigned char>(c) < 0x20 && c != '\t' && c != '\n') || c == 0x7f;
    if (!has_control) { EXPECT_EQ(DecodeEntities(out), s); }
  }
  EXPECT_EQ(HtmlText("a&lt;"), "a&amp;lt;");  // an entity in the input is shown as typed, not decoded
}

// RFC 4180 cells of one line.
std::vector<std::string> ReadCsvLine(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"')
        cells.back() += '"', ++i;
      else if (c == '"')
        quoted = false;
      else
        cells.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  return cells;
}

TEST(CsvCell, ReadsBackAsOneCellAndIsNeverAFormula) {
  for (const std::string& s : Hostile()) {
    const std::string out = CsvCell(s);
    const std::vector<std::string> cells = ReadCsvLine(out + "," + CsvCell("next"));
    ASSERT_EQ(cells.size(), 2u) << out;
    EXPECT_EQ(cells[1], "next");
    const bool formula = !s.empty() && std::string("=+-@\t\r").find(s[0]) != std::string::npos;  // none is a number
    EXPECT_EQ(cells[0], formula ? "'" + s : s) << out;
  }
  EXPECT_EQ(CsvCell("plain_name"), "plain_name");
  EXPECT_EQ(CsvCell("-0.5"), "-0.5");     // a number stays a number
  EXPECT_EQ(CsvCell("+1e-3"), "'+1e-3");  // from_chars reads no leading '+': kept as text, neutralised
  EXPECT_EQ(CsvCell("-inf"), "'-inf");
}

// Whether `expr` is single-quoted pieces with no quote or line break inside, and sprintf('%c',39), joined by '.'.
bool IsQuotedPiecesExpression(const std::string& expr) {
  static const std::string kQuote = "sprintf('%c',39)";
  size_t i = 0;
  for (;;) {
    if (expr.compare(i, kQuote.size(), kQuote) == 0) {
      i += kQuote.size();
    } else {
      if (i >= expr.size() || expr[i] != '\'') return false;
      const size_t end = expr.find('\'', i + 1);
      if (end == std::string::npos || expr.find_first_of("\r\n", i) < end) return false;
      i = end + 1;
    }
    if (i == expr.size()) return true;
    if (expr[i++] != '.') return false;
  }
}

TEST(GnuplotString, IsQuotedPiecesWithoutLineBreaks) {
  EXPECT_EQ(GnuplotString("it's `x`"), "'it'.sprintf('%c',39).'s `x`'");
  EXPECT_EQ(GnuplotString("a\nb"), "'a b'");
  for (const std::string& s : Hostile()) EXPECT_TRUE(IsQuotedPiecesExpression(GnuplotString(s))) << GnuplotString(s);
  EXPECT_FALSE(IsQuotedPiecesExpression("'a''b'"));  // the checker itself rejects a doubled quote
}

}  // namespace
}  // namespace rome
