// rome_sweep's parsing and writing (examples/sweep/sweep_io.h), as pure functions: grids (integer flags get whole
// numbers), seeds, the run-count cap, flags given once, the run record read back on resume, the summaries, and the
// CSV cells of sweep.csv (RFC 4180 quoting and formula neutralisation). Issues 40 (item 6) and 45.
#include "examples/sweep/sweep_io.h"

#include <gtest/gtest.h>

#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace rome::sweep {
namespace {

// The message of the std::invalid_argument that `f` throws ("" if it throws none).
template <typename F>
std::string ErrorOf(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) { return e.what(); }
  return "";
}

// Reads one CSV cell back as a spreadsheet would (RFC 4180): a quoted cell loses its quotes and its doubled quotes.
std::string ReadCell(const std::string& cell) {
  if (cell.empty() || cell[0] != '"') return cell;
  std::string text;
  for (size_t i = 1; i + 1 < cell.size(); ++i) {
    text += cell[i];
    if (cell[i] == '"') ++i;  // the second of a doubled quote
  }
  return text;
}

TEST(SweepCsvCell, QuotesSeparatorsQuotesAndLineBreaks) {
  EXPECT_EQ(CsvCell("plain text"), "plain text");
  EXPECT_EQ(CsvCell("a,b"), "\"a,b\"");
  EXPECT_EQ(CsvCell("x\"y"), "\"x\"\"y\"");
  EXPECT_EQ(CsvCell("line\nbreak"), "\"line\nbreak\"");
  EXPECT_EQ(CsvCell("carriage\rreturn"), "\"carriage\rreturn\"");
  EXPECT_EQ(CsvCell(""), "");
}

TEST(SweepCsvCell, NeutralisesFormulasButKeepsNumbers) {
  EXPECT_EQ(CsvCell("=cmd|' /C calc'!A0"), "'=cmd|' /C calc'!A0");
  EXPECT_EQ(CsvCell("=cmd"), "'=cmd");
  EXPECT_EQ(CsvCell("+cmd"), "'+cmd");
  EXPECT_EQ(CsvCell("-cmd"), "'-cmd");
  EXPECT_EQ(CsvCell("@SUM(A1)"), "'@SUM(A1)");
  EXPECT_EQ(CsvCell("\r"), "\"'\r\"");  // neutralised, then quoted
  EXPECT_EQ(CsvCell("\tx"), "'\tx");
  EXPECT_EQ(CsvCell("=1+2,3"), "\"'=1+2,3\"");
  EXPECT_EQ(CsvCell("=\"a\""), "\"'=\"\"a\"\"\"");
  EXPECT_EQ(CsvCell("-inf"), "'-inf");  // not a finite number: a spreadsheet would evaluate it
  for (const std::string number : {"-1.5", "-0.001", "1e-05", "-2e+10", "0", "42"}) EXPECT_EQ(CsvCell(number), number);
}

TEST(SweepCsvCell, ReadsBackAsTheTextWithAtMostALeadingQuoteMark) {
  for (const std::string text : {"a,b", "x\"y", "\r", "\"\"", "=cmd", ",\n\r\"", "-", "@", "plain"}) {
    const std::string cell = CsvCell(text);
    std::string back = ReadCell(cell);
    if (back != text && !back.empty() && back[0] == '\'') back.erase(0, 1);
    EXPECT_EQ(back, text) << "cell " << cell;
    // No separator, line break or lone quote outside the quotes.
    if (cell.empty() || cell[0] != '"') { EXPECT_EQ(cell.find_first_of(",\"\r\n"), std::string::npos) << cell; }
  }
}

TEST(SweepGrid, SpreadsValuesAndGivesIntegerFlagsWholeNumbers) {
  EXPECT_EQ(ParseGrid("energy=0.1:0.7:4", false).values, (std::vector<std::string>{"0.1", "0.3", "0.5", "0.7"}));
  EXPECT_EQ(ParseGrid("energy=0.3:0.9:1", false).values, (std::vector<std::string>{"0.3"}));
  EXPECT_EQ(ParseGrid("steps=1:5:5", true).values, (std::vector<std::string>{"1", "2", "3", "4", "5"}));
  EXPECT_EQ(ParseGrid("steps=-2:2:3", true).values, (std::vector<std::string>{"-2", "0", "2"}));
  EXPECT_EQ(ParseGrid("steps=0:3000000:4", true).values,
            (std::vector<std::string>{"0", "1000000", "2000000", "3000000"}));
  EXPECT_EQ(ParseGrid("energy=+0.5:1:2", false).values, (std::vector<std::string>{"0.5", "1"}));
  const std::string half = ErrorOf([] { ParseGrid("steps=1:2:3", true); });
  EXPECT_NE(half.find("--grid steps=1:2:3: --steps takes whole numbers, and this grid gives 1.5"), std::string::npos)
      << half;
  EXPECT_NE(ErrorOf([] { ParseGrid("steps=1:3000000000:2", true); }).find("3000000000"), std::string::npos);
}

TEST(SweepGrid, InterpolatesTuplesEntryByEntry) {
  // A flag of several numbers (--sensor-noise sigma_q,sigma_v): each entry runs from its LO to its HI.
  EXPECT_EQ(ParseGrid("sensor-noise=0,0:1e-4,1e-3:3", false).values,
            (std::vector<std::string>{"0,0", "5e-05,0.0005", "0.0001,0.001"}));
  EXPECT_EQ(ParseGrid("push-force=0,10,-20:40,10,20:2", false).values,
            (std::vector<std::string>{"0,10,-20", "40,10,20"}));
  EXPECT_EQ(ParseGrid("gait=1,2:3,4:1", true).values, (std::vector<std::string>{"1,2"}));
  for (const char* bad :
       {"sensor-noise=0,0:1e-4:3", "sensor-noise=0,:1,1:2", "sensor-noise=,0:1,1:2", "sensor-noise=0,nan:1,1:2",
        "a=0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0,0:1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1,1:2"}) {
    const std::string e = ErrorOf([&] { ParseGrid(bad, false); });
    EXPECT_NE(e.find("malformed range"), std::string::npos) << bad << ": " << e;
    EXPECT_NE(e.find("tuples"), std::string::npos) << e;
  }
  const std::string half = ErrorOf([] { ParseGrid("gait=1,1:2,2:3", true); });
  EXPECT_NE(half.find("takes whole numbers, and this grid gives 1.5"), std::string::npos) << half;
}

TEST(SweepGrid, RefusesMalformedRangesWithOneLine) {
  EXPECT_NE(ErrorOf([] { ParseGrid("energy=0.1:0.7", false); }).find("malformed range '0.1:0.7'"), std::string::npos);
  for (const char* bad :
       {"energy=nan:1:2", "energy=0:inf:2", "energy=0:1:0", "energy=0:1:100001", "energy=0:1:2junk", "energy=0:1:2:3",
        "energy=0: 1:2", "energy=0:1:-2", "energy=0x1:2:2", "energy=::", "energy="}) {
    const std::string e = ErrorOf([&] { ParseGrid(bad, false); });
    EXPECT_NE(e.find("malformed range"), std::string::npos) << bad << ": " << e;
  }
  EXPECT_NE(ErrorOf([] { ParseGrid("=0:1:2", false); }).find("must be NAME=LO:HI:N"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseGrid("energy", false); }).find("must be NAME=LO:HI:N"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseGrid("energy=1e308:-1e308:3", false); }).find("overflow"), std::string::npos);
  const std::string control = ErrorOf([] { ParseGrid("ener\ngy=\x01:1:2", false); });
  EXPECT_EQ(control.find_first_of("\n\x01"), std::string::npos) << control;
}

TEST(SweepSeeds, AreWholeNumbersInRangeAndNameTheRunCap) {
  EXPECT_EQ(ParseSeeds("1:3").values, (std::vector<std::string>{"1", "2", "3"}));
  EXPECT_EQ(ParseSeeds("7:7").values, (std::vector<std::string>{"7"}));
  EXPECT_EQ(ParseSeeds("1:3").name, "seed");
  EXPECT_TRUE(ParseSeeds("1:3").seeds);
  EXPECT_FALSE(ParseGrid("seed=1:3:3", true).seeds);
  const Parameter named = ParseSeeds("perturbation-seed=1000:1002");
  EXPECT_EQ(named.name, "perturbation-seed");
  EXPECT_EQ(named.values, (std::vector<std::string>{"1000", "1001", "1002"}));
  EXPECT_TRUE(named.seeds);
  for (const char* bad : {"=1:3", "perturbation-seed=", "perturbation-seed=1", "a=b=1:2"})
    EXPECT_NE(ErrorOf([&] { ParseSeeds(bad); }).find("malformed range"), std::string::npos) << bad;
  EXPECT_NE(ErrorOf([] { ParseSeeds("5:1"); }).find("malformed range '5:1'"), std::string::npos);
  for (const char* bad : {"-1:3", "1:99999999999", "1.5:3", "1:3junk", "1", "1:2:3", ""})
    EXPECT_NE(ErrorOf([&] { ParseSeeds(bad); }).find("malformed range"), std::string::npos) << bad;
  const std::string many = ErrorOf([] { ParseSeeds("0:2000000"); });
  EXPECT_NE(many.find("2000001 seeds; a sweep has at most 1000000 runs"), std::string::npos) << many;
}

TEST(SweepRunCount, IsCappedWithoutOverflow) {
  const Parameter big{"energy", std::vector<std::string>(100000, "1"), "--grid energy=0:1:100000"};
  const std::string e = ErrorOf([&] { CountRuns({big, big, big, big}); });
  EXPECT_NE(e.find("100000 x 100000 x 100000 x 100000 = 1e+20 runs; a sweep has at most 1000000"), std::string::npos)
      << e;
  const Parameter thousand{"a", std::vector<std::string>(1000, "1"), ""},
      more{"b", std::vector<std::string>(1001, "1"), ""};
  EXPECT_EQ(CountRuns({thousand, thousand}), 1000000);
  EXPECT_NE(ErrorOf([&] { CountRuns({thousand, more}); }).find("1000 x 1001 = 1001000 runs"), std::string::npos);
  EXPECT_EQ(CountRuns({Parameter{"seed", {"1", "2", "3"}, ""}}), 3);
}

TEST(SweepFlags, EachFlagIsGivenOnceAndOutputsAreRomeSweeps) {
  const Parameter seeds = ParseSeeds("1:3"), energy = ParseGrid("energy=0.1:0.7:4", false),
                  energy2 = ParseGrid("energy=0:1:3", false);
  EXPECT_EQ(ErrorOf([&] { CheckFlagsGivenOnce({seeds, energy}, {{"steps", "4"}}); }), "");
  EXPECT_NE(ErrorOf([&] {
              CheckFlagsGivenOnce({energy, energy2}, {});
            }).find("--grid energy=0:1:3: --energy is already swept by --grid energy=0.1:0.7:4"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              CheckFlagsGivenOnce({seeds}, {{"seed", "7"}});
            }).find("--set seed=7: --seed is swept by --seeds 1:3"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              CheckFlagsGivenOnce({seeds}, {{"steps", "4"}, {"steps", "5"}});
            }).find("--set steps=5: --steps is already set by --set steps=4"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] {
              CheckFlagsGivenOnce({seeds}, {{"summary", "x.json"}});
            }).find("--summary cannot be set"),
            std::string::npos);
  EXPECT_NE(ErrorOf([&] { CheckFlagsGivenOnce({ParseGrid("log=0:1:2", false)}, {}); }).find("--log cannot be swept"),
            std::string::npos);
  EXPECT_EQ(ParseSet("terrain=flat"), (std::pair<std::string, std::string>{"terrain", "flat"}));
  EXPECT_EQ(ParseSet("terrain="), (std::pair<std::string, std::string>{"terrain", ""}));
  EXPECT_NE(ErrorOf([] { ParseSet("=flat"); }).find("must be NAME=VALUE"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSet("terrain=\xff"); }).find("not valid UTF-8"), std::string::npos);
}

TEST(SweepFlags, AreReadFromTheHelp) {
  const std::set<std::string> flags =
      FlagsInHelp("Usage: x [options]\n  --steps VALUE\n      n (default: 3)\n  --step-length VALUE\n  --help\n");
  EXPECT_EQ(flags, (std::set<std::string>{"steps", "step-length", "help"}));
}

TEST(SweepFlags, UnitsAreTheBracketsThatOpenAFlagsHelp) {
  const auto units = FlagUnitsInHelp(
      "Usage: x [options]\n  --push-impulse VALUE\n      [N s] forward impulse (default: 0)\n  --steps VALUE\n      "
      "number of steps [1, 100] (default: 3)\n  --mass-scale VALUE\n      [-] ratio (default: 1)\n  --flag\n");
  EXPECT_EQ(units, (std::map<std::string, std::string>{{"push-impulse", "N s"}, {"mass-scale", "-"}}));
}

TEST(SweepRunRecord, RoundTrips) {
  for (const RunRecord& r :
       {RunRecord{0, {"--seed", "1", "--steps", "4"}}, RunRecord{-9, {}}, RunRecord{255, {"--terrain", "a\nb\"c,\\"}},
        RunRecord{3, {"--set", "\xc3\xa9t\xc3\xa9"}}}) {
    const auto back = ParseRunRecord(RunRecordText(r));
    ASSERT_TRUE(back.has_value()) << RunRecordText(r);
    EXPECT_EQ(*back, r);
  }
  EXPECT_TRUE(ParseRunRecord("-9\n[]\n")->KilledBySignal());
  EXPECT_FALSE(ParseRunRecord("3\n[]\n")->KilledBySignal());
}

TEST(SweepRunRecord, AnythingElseIsNotTrusted) {
  std::string deep = "0\n";
  for (int i = 0; i < 100000; ++i) deep += '[';
  deep += "\n";
  for (const std::string& bad : std::vector<std::string>{"",
                                                         "0",
                                                         "0\n",
                                                         "\n[]\n",
                                                         "abc\n[]\n",
                                                         "256\n[]\n",
                                                         "-65\n[]\n",
                                                         "0\n[]",
                                                         "0\n[]\n\n",
                                                         "0\n[1]\n",
                                                         "0\n{}\n",
                                                         "0 \n[]\n",
                                                         " 0\n[]\n",
                                                         "1e2\n[]\n",
                                                         "0\n[\"a\"]\nextra\n",
                                                         "0\n[\"a\"\n",
                                                         "0\r\n[]\r\n",
                                                         "99999999999\n[]\n",
                                                         std::string("0\n[\"\xff\"]\n"),
                                                         deep})
    EXPECT_FALSE(ParseRunRecord(bad).has_value()) << "'" << bad.substr(0, 40) << "'";
}

TEST(SweepSummary, IsAnObjectWithItsStatusFields) {
  const auto ok = ParseSummary(
      R"({"status": "walked 4 steps", "status_kind": "success", "steps": 4, "tracking_rms": {"torso": 0.1}})");
  ASSERT_TRUE(ok.has_value());
  EXPECT_EQ((*ok)["steps"], 4);
  std::string deep;
  for (int i = 0; i < 100000; ++i) deep += "{\"a\":";
  for (const std::string& bad : std::vector<std::string>{
           "", "not json", "[]", "42", R"({"status": "x"})", R"({"status": 1, "status_kind": "success"})",
           R"({"status": "x", "status_kind": null})", R"({"status": "x", "status_kind": "success")",
           std::string("{\"status\": \"\xff\", \"status_kind\": \"success\"}"),
           R"({"status": "x", "status_kind": "y", "n": 1e999})", deep})
    EXPECT_FALSE(ParseSummary(bad).has_value()) << bad.substr(0, 60);
}

}  // namespace
}  // namespace rome::sweep
