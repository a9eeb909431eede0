#include "systems/plants/terrain.h"
#include "framework/files.h"
#include "framework/text.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <iterator>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rome {

Terrain Terrain::Flat(double height_m) {
  Terrain t;
  t.flat_height_ = height_m;
  return t;
}

namespace {
// A coordinate as an error shows it: six significant digits ("1e+300 m", not 300 digits).
std::string Meters(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

// Whether stone b (b.x >= a.x) overlaps stone a. Touching stones (a's right edge on b's left edge up to rounding) do
// not: the rounding allowance is 16 units in the last place of the coordinates, and never more than a quarter of the
// shorter stone, so two stones centred on one x always overlap, however short they are.
bool Overlap(const SteppingStone& a, const SteppingStone& b) {
  const double ulp =
      std::numeric_limits<double>::epsilon() * std::max({1.0, std::abs(a.x_center_m), std::abs(b.x_center_m)});
  const double rounding = std::min(16.0 * ulp, 0.25 * std::min(a.length_m, b.length_m));
  return a.x_center_m + a.length_m / 2 > b.x_center_m - b.length_m / 2 + rounding;
}
}  // namespace

Terrain Terrain::Stones(std::vector<SteppingStone> stones) {
  if (stones.empty()) throw std::invalid_argument("Terrain::Stones: no stones given");
  std::sort(stones.begin(), stones.end(),
            [](const SteppingStone& a, const SteppingStone& b) { return a.x_center_m < b.x_center_m; });
  for (size_t i = 0; i < stones.size(); ++i) {
    const auto& s = stones[i];
    if (!(std::abs(s.x_center_m) <= kMaxTerrainCoordinate_m))
      throw std::invalid_argument("Terrain::Stones: stone " + std::to_string(i) + " has x = " + Meters(s.x_center_m) +
                                  " m (must be finite, within +-" + Meters(kMaxTerrainCoordinate_m) + " m)");
    if (!(std::abs(s.top_height_m) <= kMaxTerrainCoordinate_m))
      throw std::invalid_argument("Terrain::Stones: stone " + std::to_string(i) + " at x = " + Meters(s.x_center_m) +
                                  " m has height z = " + Meters(s.top_height_m) + " m (must be finite, within +-" +
                                  Meters(kMaxTerrainCoordinate_m) + " m)");
    if (!(s.length_m >= kMinStoneLength_m) || !std::isfinite(s.length_m))
      throw std::invalid_argument("Terrain::Stones: stone " + std::to_string(i) + " at x = " + Meters(s.x_center_m) +
                                  " m has length " + Meters(s.length_m) + " m (must be finite and at least " +
                                  Meters(kMinStoneLength_m) + " m)");
    if (i > 0 && Overlap(stones[i - 1], s))
      throw std::invalid_argument("Terrain::Stones: stones " + std::to_string(i - 1) + " and " + std::to_string(i) +
                                  " overlap (x = " + Meters(stones[i - 1].x_center_m) + " m and " +
                                  Meters(s.x_center_m) + " m)");
  }
  Terrain t;
  t.stones_ = std::move(stones);
  return t;
}

namespace {
// A line as it may be shown in an error: at most 80 characters, control and non-ASCII bytes escaped.
}  // namespace

Terrain Terrain::FromCsv(const std::string& path, double default_length_m) {
  return FromCsvText(ReadRegularFile(path, "terrain file", kMaxTerrainFileBytes), default_length_m, path);
}

Terrain Terrain::FromCsvText(std::string text, double default_length_m, const std::string& path) {
  if (text.size() >= 3 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // UTF-8 byte-order mark
  for (char& c : text)
    if (c == '\r') c = '\n';  // CR-only and CRLF files: every CR ends a line (CRLF gives an empty line, skipped)
  std::vector<SteppingStone> stones;
  std::vector<int> stone_lines;
  std::stringstream lines(text);
  std::string line;
  int line_no = 0;
  bool header_seen = false;
  while (std::getline(lines, line)) {
    ++line_no;
    const size_t first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line[first] == '#') continue;
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
      } catch (const std::exception&) { return false; }
    };
    SteppingStone st;
    st.length_m = default_length_m;
    const bool numbers = cols.size() >= 2 && cols.size() <= 3 && parse(cols[0], &st.x_center_m) &&
                         parse(cols[1], &st.top_height_m) && (cols.size() == 2 || parse(cols[2], &st.length_m));
    if (!numbers) {
      // A header is the first non-comment line, and only if it has no digit in it (a mistyped stone is an error).
      const bool header = !header_seen && stones.empty() && line.find_first_of("0123456789") == std::string::npos;
      if (header) {
        header_seen = true;
        continue;
      }
      throw std::runtime_error("terrain file '" + Excerpt(path, 200) + "' line " + std::to_string(line_no) +
                               ": expected 'x,z[,length]' numbers, got '" + Excerpt(line) + "'");
    }
    header_seen = true;
    const bool bad_length = !(std::isfinite(st.length_m) && st.length_m >= kMinStoneLength_m);
    const char* bad = !(std::abs(st.x_center_m) <= kMaxTerrainCoordinate_m)     ? "x"
                      : !(std::abs(st.top_height_m) <= kMaxTerrainCoordinate_m) ? "z"
                      : bad_length                                              ? "length"
                                                                                : nullptr;
    if (bad != nullptr)
      throw std::runtime_error(
          "terrain file '" + Excerpt(path, 200) + "' line " + std::to_string(line_no) + ": " + bad + " must be finite" +
          (bad_length && !std::strcmp(bad, "length") ? " and at least " + Meters(kMinStoneLength_m) + " m"
                                                     : " and within +-" + Meters(kMaxTerrainCoordinate_m) + " m") +
          ", got '" + Excerpt(line) + "'");
    stones.push_back(st);
    stone_lines.push_back(line_no);
  }
  if (stones.empty())
    throw std::runtime_error("terrain file '" + Excerpt(path, 200) + "' has no stones (expected lines 'x,z[,length]')");
  // Overlaps, reported with the file's line numbers.
  std::vector<size_t> order(stones.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t a, size_t b) { return stones[a].x_center_m < stones[b].x_center_m; });
  for (size_t k = 1; k < order.size(); ++k) {
    const SteppingStone &a = stones[order[k - 1]], &b = stones[order[k]];
    if (Overlap(a, b))
      throw std::runtime_error("terrain file '" + Excerpt(path, 200) + "': the stones of lines " +
                               std::to_string(stone_lines[order[k - 1]]) + " and " +
                               std::to_string(stone_lines[order[k]]) + " overlap (x = " + Meters(a.x_center_m) +
                               " m and " + Meters(b.x_center_m) + " m)");
  }
  try {
    return Stones(std::move(stones));
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error("terrain file '" + Excerpt(path, 200) + "': " + e.what());
  }
}

// Stones are sorted by x and do not overlap: binary searches (O(log n) per query).
int Terrain::StoneAt(double x, double tolerance_m) const {
  if (stones_.empty()) return -1;
  auto it = std::lower_bound(stones_.begin(), stones_.end(), x,
                             [](const SteppingStone& s, double v) { return s.x_center_m < v; });
  for (auto cand : {it, it == stones_.begin() ? it : std::prev(it)}) {
    if (cand == stones_.end()) continue;
    if (std::abs(x - cand->x_center_m) <= cand->length_m / 2 + tolerance_m)
      return static_cast<int>(cand - stones_.begin());
  }
  return -1;
}

int Terrain::NearestStone(double x) const {
  if (stones_.empty()) return -1;
  auto it = std::lower_bound(stones_.begin(), stones_.end(), x,
                             [](const SteppingStone& s, double v) { return s.x_center_m < v; });
  if (it == stones_.end()) return static_cast<int>(stones_.size()) - 1;
  if (it == stones_.begin()) return 0;
  const auto before = std::prev(it);
  return static_cast<int>((std::abs(x - before->x_center_m) <= std::abs(x - it->x_center_m) ? before : it) -
                          stones_.begin());
}

double Terrain::SurfaceHeight(double x) const {
  if (stones_.empty()) return flat_height_;
  const int on = StoneAt(x);
  if (on >= 0) return stones_[on].top_height_m;
  // In a gap: the lower of the two neighbouring tops (a foot over the gap only "touches down" once it is
  // below both, i.e. inside the gap); before the first or after the last stone: that stone's top.
  if (x < stones_.front().x_center_m) return stones_.front().top_height_m;
  if (x > stones_.back().x_center_m) return stones_.back().top_height_m;
  auto next = std::upper_bound(stones_.begin(), stones_.end(), x,
                               [](double v, const SteppingStone& s) { return v < s.x_center_m; });
  return std::min(std::prev(next)->top_height_m, next->top_height_m);
}

}  // namespace rome
