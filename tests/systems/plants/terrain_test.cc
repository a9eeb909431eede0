#include "systems/plants/terrain.h"
#include "tests/common/source_path.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <future>
#include <utility>
#include <vector>

#include "framework/files.h"

namespace rome {
namespace {

TEST(Terrain, StonesLookup) {
  Terrain t = Terrain::Stones({{1.0, 0.2, 0.2}, {0.0, 0.0, 0.2}});
  EXPECT_EQ(t.stones()[0].x_center_m, 0.0);  // sorted
  EXPECT_EQ(t.StoneAt(0.05), 0);
  EXPECT_EQ(t.StoneAt(0.5), -1);
  EXPECT_EQ(t.StoneAt(0.11, 0.02), 0);
  EXPECT_DOUBLE_EQ(t.SurfaceHeight(0.95), 0.2);
  EXPECT_DOUBLE_EQ(t.SurfaceHeight(0.7), 0.0);  // in the gap: the lower neighbour
  EXPECT_DOUBLE_EQ(t.SurfaceHeight(0.3), 0.0);
  EXPECT_DOUBLE_EQ(t.SurfaceHeight(-1.0), 0.0);  // before the first stone
  EXPECT_DOUBLE_EQ(t.SurfaceHeight(2.0), 0.2);   // after the last stone
  EXPECT_THROW(Terrain::Stones({{0, 0, 0.2}, {0.1, 0, 0.2}}), std::invalid_argument);
  EXPECT_THROW(Terrain::Stones({{0, 0, -0.2}}), std::invalid_argument);
}

TEST(Terrain, CsvErrorsNameFileAndLine) {
  const std::string path = rome::test::ScratchDir() + "/stones.csv";
  {
    std::ofstream f(path);
    f << "x,z,length\n0,0,0.3\n0.5,0.1\n1.0,abc\n";
  }
  try {
    Terrain::FromCsv(path, 0.2);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("line 4"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  {
    std::ofstream f(path);
    f << "x,z,length\n0,0,0.3\n0.5,0.1\n";
  }
  Terrain t = Terrain::FromCsv(path, 0.2);
  ASSERT_EQ(t.stones().size(), 2u);
  EXPECT_DOUBLE_EQ(t.stones()[1].length_m, 0.2);
  std::remove(path.c_str());
  EXPECT_THROW(Terrain::FromCsv("/no/such/file.csv", 0.2), std::runtime_error);
}

}  // namespace
}  // namespace rome

namespace rome {
namespace {

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = rome::test::ScratchDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string ErrorOf(const std::string& path) {
  try {
    Terrain::FromCsv(path, 0.1);
  } catch (const std::exception& e) { return e.what(); }
  return "";
}

TEST(TerrainCsv, BomCarriageReturnsAndHeaders) {
  EXPECT_EQ(Terrain::FromCsv(WriteTemp("bom.csv",
                                       "\xEF\xBB\xBF"
                                       "0,0\n0.4,0.1\n"),
                             0.1)
                .stones()
                .size(),
            2u);  // the BOM line is a stone
  EXPECT_EQ(Terrain::FromCsv(WriteTemp("cr.csv", "0,0\r0.4,0.1\r0.8,0\r"), 0.1).stones().size(), 3u);
  EXPECT_EQ(Terrain::FromCsv(WriteTemp("crlf.csv", "x,z\r\n0,0\r\n0.4,0.1\r\n"), 0.1).stones().size(), 2u);
  EXPECT_EQ(
      Terrain::FromCsv(WriteTemp("header.csv", "# stones\nx,z,length\n0,0\n0.4,0.1,0.2\n"), 0.1).stones()[1].length_m,
      0.2);
}

TEST(TerrainCsv, EveryErrorNamesTheLineAndTheField) {
  EXPECT_EQ(
      ErrorOf(WriteTemp("typo.csv", "O,0\n0.4,0\n")),
      "terrain file '" + rome::test::ScratchDir() + "/typo.csv' line 1: expected 'x,z[,length]' numbers, got 'O,0'");
  EXPECT_NE(ErrorOf(WriteTemp("nan.csv", "0,0\n0.4,nan\n")).find("line 2: z must be finite"), std::string::npos);
  EXPECT_NE(ErrorOf(WriteTemp("inf.csv", "0,0,inf\n")).find("line 1: length must be finite and at least 1e-06 m"),
            std::string::npos);
  EXPECT_NE(
      ErrorOf(WriteTemp("overlap.csv", "0,0\n# gap\n0.4,0.1\n0.45,0.1\n")).find("the stones of lines 3 and 4 overlap"),
      std::string::npos);
  EXPECT_NE(ErrorOf(rome::test::ScratchDir()).find("is a directory"), std::string::npos);
  EXPECT_NE(ErrorOf(WriteTemp("empty.csv", "# nothing\n")).find("has no stones"), std::string::npos);
  const std::string binary =
      ErrorOf(WriteTemp("binary.csv", std::string("0,0\n\x01\x02,\xff") + std::string(10000, 'x') + "\n"));
  EXPECT_NE(binary.find("\\x01\\x02"), std::string::npos) << binary;
  EXPECT_LT(binary.size(), 250u);
  // The file's path is untrusted text too: a newline and a control byte in it are escaped, a 10,000-character path cut.
  const std::string odd_path = ErrorOf(rome::test::ScratchDir() +
                                       "/no\nsuch\x07"
                                       "file.csv");
  EXPECT_EQ(odd_path.find('\n'), std::string::npos) << odd_path;
  EXPECT_NE(odd_path.find("no\\x0Asuch\\x07file.csv: file does not exist"), std::string::npos) << odd_path;
  const std::string long_path = ErrorOf(std::string(10000, 'p') + ".csv");
  EXPECT_LT(long_path.size(), 300u) << long_path.substr(0, 300);
  EXPECT_NE(long_path.find("(10004 bytes)"), std::string::npos) << long_path.substr(0, 300);
}

// A million stones: lookups are binary searches (checked here against a linear scan on sampled points).
TEST(TerrainLookup, MillionStonesMatchALinearScan) {
  std::vector<SteppingStone> stones;
  for (int k = 0; k < 1000000; ++k) stones.push_back({0.3 * k, 0.01 * (k % 7), 0.1});
  const Terrain t = Terrain::Stones(stones);
  for (double x : {-1.0, 0.0, 0.04, 0.06, 0.15, 0.16, 1234.56, 299999.7, 299999.76, 400000.0}) {
    int scan = -1;
    double best = 1e300;
    for (size_t i = 0; i < t.stones().size(); ++i)
      if (std::abs(x - t.stones()[i].x_center_m) < best)
        best = std::abs(x - t.stones()[i].x_center_m), scan = static_cast<int>(i);
    EXPECT_EQ(t.NearestStone(x), scan) << x;
    const bool on = std::abs(x - t.stones()[scan].x_center_m) <= 0.05;
    EXPECT_EQ(t.StoneAt(x), on ? scan : -1) << x;
  }
}

// FromCsvText (the fuzz harness's entry) parses the text exactly as FromCsv parses the file, and names the text as
// given.
TEST(TerrainCsv, TextParsesAsTheFile) {
  const std::string text = "x,z,length\r\n1.2,0.1,0.3\r\n0,0\r\n0.6,-0.05\r\n";
  const Terrain from_file = Terrain::FromCsv(WriteTemp("text.csv", text), 0.2);
  const Terrain from_text = Terrain::FromCsvText(text, 0.2);
  ASSERT_EQ(from_text.stones().size(), 3u);
  for (size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(from_text.stones()[i].x_center_m, from_file.stones()[i].x_center_m);
    EXPECT_EQ(from_text.stones()[i].top_height_m, from_file.stones()[i].top_height_m);
    EXPECT_EQ(from_text.stones()[i].length_m, from_file.stones()[i].length_m);
  }
  EXPECT_EQ(from_text.stones()[2].length_m, 0.3);  // sorted by x: the 1.2 m stone is last and keeps its length
  try {
    Terrain::FromCsvText("0,0\n0.4,zz\n", 0.1, "my stones");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("terrain file 'my stones' line 2"), std::string::npos) << e.what();
  }
}

// Found by tests/fuzz/terrain_csv_fuzzer: "1e200,0\n1e200,0\n" was accepted as two stones. At x = 1e200 a 0.1 m
// stone's edges x +- 0.05 round to x, so the overlap test (with its absolute 1e-12 m allowance) passed, and
// StoneAt(x) could not tell the two stones apart. The class: a stone whose length is not resolved at its coordinate.
// Now coordinates are capped at kMaxTerrainCoordinate_m and lengths are at least kMinStoneLength_m, and the overlap
// allowance for rounding is relative to the coordinates but never more than a quarter of the shorter stone.
TEST(Terrain, StonesMustBeResolvedAtTheirCoordinates) {
  auto error_of = [](const std::string& text) {
    try {
      Terrain::FromCsvText(text, 0.1, "fuzz.csv");
    } catch (const std::runtime_error& e) { return std::string(e.what()); }
    return std::string("accepted");
  };
  EXPECT_EQ(error_of("1e200,0\n1e200,0\n"),
            "terrain file 'fuzz.csv' line 1: x must be finite and within +-1e+06 m, got '1e200,0'");
  EXPECT_NE(error_of("0,1e7\n").find("line 1: z must be finite and within +-1e+06 m"), std::string::npos);
  EXPECT_NE(error_of("0,0,1e-7\n").find("line 1: length must be finite and at least 1e-06 m"), std::string::npos);
  EXPECT_THROW(Terrain::Stones({{1e7, 0.0, 0.1}}), std::invalid_argument);
  EXPECT_THROW(Terrain::Stones({{0.0, 0.0, 1e-9}}), std::invalid_argument);
  // At the limits, two stones on one x overlap, and so do two stones overlapping by a tenth of their length.
  EXPECT_NE(
      error_of("1e6,0,1e-6\n1e6,0.1,1e-6\n").find("the stones of lines 1 and 2 overlap (x = 1e+06 m and 1e+06 m)"),
      std::string::npos)
      << error_of("1e6,0,1e-6\n1e6,0.1,1e-6\n");
  EXPECT_THROW(Terrain::Stones({{-1e6, 0.0, 1e-6}, {-1e6 + 0.9e-6, 0.0, 1e-6}}), std::invalid_argument);
  // Touching stones (0.1 + 0.2 is not exactly 0.3 in binary: the edges meet only up to rounding) are accepted, and
  // StoneAt finds each at its centre, near the origin and at the coordinate limit.
  const Terrain touching = Terrain::Stones({{0.1, 0.0, 0.2}, {0.3, 0.0, 0.2}, {1e6 - 0.2, 0.0, 0.2}, {1e6, 0.0, 0.2}});
  for (int i = 0; i < 4; ++i) EXPECT_EQ(touching.StoneAt(touching.stones()[i].x_center_m), i);
}

// A terrain is read only from a regular file of at most kMaxTerrainFileBytes (issue 45): before, "--terrain
// /dev/zero" was read without bound and a FIFO blocked forever. Each is refused at once (a load still running after
// 10 s fails the test; the FIFO is then opened for writing to release it).
TEST(TerrainCsv, OnlyRegularFilesUnderTheCapAreRead) {
  const TempFolder folder("rome_terrain_test");
  const std::string fifo = folder.File("stones.csv");
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  const std::string big = folder.File("big.csv");
  {  // a sparse file one byte over the cap: its size is refused before any reading
    std::ofstream(big, std::ios::binary) << "0,0\n";
    std::filesystem::resize_file(big, kMaxTerrainFileBytes + 1);
  }
  for (const auto& [path, reason] : std::vector<std::pair<std::string, std::string>>{
           {"/dev/zero", "is a device, not a regular file"},
           {fifo, "is a FIFO, not a regular file"},
           {big, "; the limit is " + std::to_string(kMaxTerrainFileBytes) + " bytes"}}) {
    auto error = std::async(std::launch::async, [path = path] { return ErrorOf(path); });
    if (error.wait_for(std::chrono::seconds(10)) != std::future_status::ready) {
      ADD_FAILURE() << path << " was not refused within 10 s";
      if (const int fd = ::open(fifo.c_str(), O_WRONLY | O_NONBLOCK); fd >= 0) ::close(fd);
    }
    const std::string what = error.get();
    EXPECT_EQ(what.rfind("terrain file " + path + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(reason), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rome
