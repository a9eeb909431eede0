#include "systems/plants/terrain.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rome {

Terrain Terrain::Flat(double height_m) {
  Terrain t;
  t.flat_height_ = height_m;
  return t;
}

Terrain Terrain::Stones(std::vector<SteppingStone> stones) {
  if (stones.empty()) throw std::invalid_argument("Terrain::Stones: no stones given");
  std::sort(stones.begin(), stones.end(), [](const SteppingStone& a, const SteppingStone& b) { return a.x_center_m < b.x_center_m; });
  for (size_t i = 0; i < stones.size(); ++i) {
    const auto& s = stones[i];
    if (!(s.length_m > 0) || !std::isfinite(s.x_center_m) || !std::isfinite(s.top_height_m))
      throw std::invalid_argument("Terrain::Stones: stone " + std::to_string(i) + " at x = " + std::to_string(s.x_center_m) +
                                  " m has length " + std::to_string(s.length_m) + " m (must be positive and finite)");
    if (i > 0 && stones[i - 1].x_center_m + stones[i - 1].length_m / 2 > s.x_center_m - s.length_m / 2 + 1e-12)
      throw std::invalid_argument("Terrain::Stones: stones " + std::to_string(i - 1) + " and " + std::to_string(i) + " overlap (x = " +
                                  std::to_string(stones[i - 1].x_center_m) + " m and " + std::to_string(s.x_center_m) + " m)");
  }
  Terrain t;
  t.stones_ = std::move(stones);
  return t;
}

Terrain Terrain::FromCsv(const std::string& path, double default_length_m) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("terrain file '" + path + "' cannot be opened");
  std::vector<SteppingStone> stones;
  std::string line;
  int line_no = 0;
  while (std::getline(in, line)) {
    ++line_no;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> cols;
    std::stringstream ss(line);
    std::string col;
    while (std::getline(ss, col, ',')) cols.push_back(col);
    auto parse = [&](const std::string& s, double* out) {
      try {
        size_t used = 0;
        *out = std::stod(s, &used);
        while (used < s.size() && std::isspace(static_cast<unsigned char>(s[used]))) ++used;
        return used == s.size();
      } catch (const std::exception&) {
        return false;
      }
    };
    SteppingStone st;
    st.length_m = default_length_m;
    if (cols.size() < 2 || cols.size() > 3 || !parse(cols[0], &st.x_center_m) || !parse(cols[1], &st.top_height_m) ||
        (cols.size() == 3 && !parse(cols[2], &st.length_m))) {
      if (line_no == 1 && stones.empty()) continue;  // header
      throw std::runtime_error("terrain file '" + path + "' line " + std::to_string(line_no) + ": expected 'x,z[,length]' numbers, got '" + line + "'");
    }
    stones.push_back(st);
  }
  if (stones.empty()) throw std::runtime_error("terrain file '" + path + "' has no stones");
  try {
    return Stones(std::move(stones));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error("terrain file '" + path + "': " + e.what());
  }
}

int Terrain::StoneAt(double x, double tolerance_m) const {
  for (size_t i = 0; i < stones_.size(); ++i)
    if (std::abs(x - stones_[i].x_center_m) <= stones_[i].length_m / 2 + tolerance_m) return static_cast<int>(i);
  return -1;
}

int Terrain::NearestStone(double x) const {
  int best = -1;
  double dist = 0;
  for (size_t i = 0; i < stones_.size(); ++i) {
    const double d = std::abs(x - stones_[i].x_center_m);
    if (best < 0 || d < dist) {
      best = static_cast<int>(i);
      dist = d;
    }
  }
  return best;
}

double Terrain::SurfaceHeight(double x) const {
  if (stones_.empty()) return flat_height_;
  const int on = StoneAt(x);
  if (on >= 0) return stones_[on].top_height_m;
  // In a gap: the lower of the two neighbouring tops (a foot over the gap only "touches down" once it is
  // below both, i.e. inside the gap); before the first or after the last stone: that stone's top.
  if (x < stones_.front().x_center_m) return stones_.front().top_height_m;
  if (x > stones_.back().x_center_m) return stones_.back().top_height_m;
  for (size_t i = 0; i + 1 < stones_.size(); ++i)
    if (x < stones_[i + 1].x_center_m) return std::min(stones_[i].top_height_m, stones_[i + 1].top_height_m);
  return stones_.back().top_height_m;
}

}  // namespace rome
