#include "systems/plants/terrain.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>

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
  const std::string path = ::testing::TempDir() + "/stones.csv";
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
  const std::string path = std::string(::testing::TempDir()) + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string ErrorOf(const std::string& path) {
  try {
    Terrain::FromCsv(path, 0.1);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(TerrainCsv, BomCarriageReturnsAndHeaders) {
  EXPECT_EQ(Terrain::FromCsv(WriteTemp("bom.csv", "\xEF\xBB\xBF" "0,0\n0.4,0.1\n"), 0.1).stones().size(), 2u);  // the BOM line is a stone
  EXPECT_EQ(Terrain::FromCsv(WriteTemp("cr.csv", "0,0\r0.4,0.1\r0.8,0\r"), 0.1).stones().size(), 3u);
  EXPECT_EQ(Terrain::FromCsv(WriteTemp("crlf.csv", "x,z\r\n0,0\r\n0.4,0.1\r\n"), 0.1).stones().size(), 2u);
  EXPECT_EQ(Terrain::FromCsv(WriteTemp("header.csv", "# stones\nx,z,length\n0,0\n0.4,0.1,0.2\n"), 0.1).stones()[1].length_m, 0.2);
}

TEST(TerrainCsv, EveryErrorNamesTheLineAndTheField) {
  EXPECT_EQ(ErrorOf(WriteTemp("typo.csv", "O,0\n0.4,0\n")), "terrain file '" + ::testing::TempDir() + "/typo.csv' line 1: expected 'x,z[,length]' numbers, got 'O,0'");
  EXPECT_NE(ErrorOf(WriteTemp("nan.csv", "0,0\n0.4,nan\n")).find("line 2: z must be finite"), std::string::npos);
  EXPECT_NE(ErrorOf(WriteTemp("inf.csv", "0,0,inf\n")).find("line 1: length must be finite and positive"), std::string::npos);
  EXPECT_NE(ErrorOf(WriteTemp("overlap.csv", "0,0\n# gap\n0.4,0.1\n0.45,0.1\n")).find("the stones of lines 3 and 4 overlap"), std::string::npos);
  EXPECT_NE(ErrorOf(::testing::TempDir()).find("is a directory"), std::string::npos);
  EXPECT_NE(ErrorOf(WriteTemp("empty.csv", "# nothing\n")).find("has no stones"), std::string::npos);
  const std::string binary = ErrorOf(WriteTemp("binary.csv", std::string("0,0\n\x01\x02,\xff") + std::string(10000, 'x') + "\n"));
  EXPECT_NE(binary.find("\\x01\\x02"), std::string::npos) << binary;
  EXPECT_LT(binary.size(), 250u);
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
      if (std::abs(x - t.stones()[i].x_center_m) < best) best = std::abs(x - t.stones()[i].x_center_m), scan = static_cast<int>(i);
    EXPECT_EQ(t.NearestStone(x), scan) << x;
    const bool on = std::abs(x - t.stones()[scan].x_center_m) <= 0.05;
    EXPECT_EQ(t.StoneAt(x), on ? scan : -1) << x;
  }
}

}  // namespace
}  // namespace rome
