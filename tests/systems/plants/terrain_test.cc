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
