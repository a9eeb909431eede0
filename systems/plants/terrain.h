#pragma once
// Terrain for the hybrid contact plant: flat ground, or a row of stepping stones along world x.
// Stones are infinitely wide in y (the planar robots never leave the sagittal plane; for 3D robots they
// are bands across the walking direction).

#include <cstdint>
#include <string>
#include <vector>

namespace rome {

/// Limits on a stone (ours): within them a stone's edges x +- length/2 are resolved in double precision (at 1e6 m one
/// unit in the last place is 1.2e-10 m), so stones that overlap are told apart from stones that touch.
inline constexpr double kMaxTerrainCoordinate_m = 1e6;  ///< [m] |x| and |z| of a stone at most this.
inline constexpr double kMinStoneLength_m = 1e-6;       ///< [m] a stone is at least this long.
/// A terrain CSV is read whole: at most this many bytes (ours; about 4 million stones), checked while reading.
inline constexpr std::uintmax_t kMaxTerrainFileBytes = std::uintmax_t{64} << 20;  // 64 MiB

struct SteppingStone {
  double x_center_m = 0.0;    ///< [m] centre of the stone's top along x.
  double top_height_m = 0.0;  ///< [m] height of the stone's top.
  double length_m = 0.1;      ///< [m] extent of the stone's top along x.
};

class Terrain {
 public:
  static Terrain Flat(double height_m = 0.0);
  /// Stones sorted by x (they are sorted here); an error naming the stone for a coordinate beyond
  /// kMaxTerrainCoordinate_m, a length below kMinStoneLength_m (or not finite), or an overlap.
  static Terrain Stones(std::vector<SteppingStone> stones);
  /// Reads a CSV with one stone a line: x,z[,length]; a header line is allowed; `default_length_m`
  /// when the length column is missing. Errors name the file and the line. Only a regular file of at most
  /// kMaxTerrainFileBytes is read (a device, FIFO or directory is refused at once).
  static Terrain FromCsv(const std::string& path, double default_length_m);
  /// The same from the CSV's text in memory; `name` stands for the file in error messages.
  static Terrain FromCsvText(std::string text, double default_length_m, const std::string& name = "<terrain text>");

  bool is_flat() const { return stones_.empty(); }
  const std::vector<SteppingStone>& stones() const { return stones_; }
  /// Height used by touchdown witnesses at x: the ground, or the top of the stone under x, or, in a gap
  /// between two stones, the lower of their tops (so a foot that misses every stone still produces a
  /// touchdown once it is inside the gap, which the plant then reports as a fall). Stone sides are not
  /// modelled: a toe that stubs a higher stone's side is not detected until it drops into a gap.
  double SurfaceHeight(double x) const;
  /// Index of the stone whose top contains x (with `tolerance_m` margin), or -1.
  int StoneAt(double x, double tolerance_m = 0.0) const;
  /// Index of the stone whose centre is nearest to x (-1 on flat ground).
  int NearestStone(double x) const;

 private:
  double flat_height_ = 0.0;
  std::vector<SteppingStone> stones_;
};

}  // namespace rome
