// libFuzzer harness for the terrain CSV parser: Terrain::FromCsvText.
//
// Input: the CSV's bytes. The default stone length is fixed at 0.1 m (stepping_stones' default for point feet).
// Fine: a terrain, or std::runtime_error (the parser's documented error) whose message is one line.
// A finding: any other exception, a multi-line message, a crash, a sanitizer report, a hang (libFuzzer -timeout),
// or an accepted terrain that breaks the parser's promise: stones sorted by x, finite, positive lengths, and no
// overlap: StoneAt, NearestStone and SurfaceHeight at each stone's centre find that stone.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <string>

#include "systems/plants/terrain.h"

namespace {

[[noreturn]] void Finding(const char* what, size_t stone) {
  std::fprintf(stderr, "terrain_csv_fuzzer: %s (stone %zu)\n", what, stone);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const rome::Terrain terrain =
        rome::Terrain::FromCsvText(std::string(reinterpret_cast<const char*>(data), size), 0.1, "fuzz.csv");
    const auto& stones = terrain.stones();
    if (stones.empty()) Finding("accepted terrain has no stones", 0);
    for (size_t i = 0; i < stones.size(); ++i) {
      const rome::SteppingStone& s = stones[i];
      if (!std::isfinite(s.x_center_m) || !std::isfinite(s.top_height_m) || !std::isfinite(s.length_m) ||
          !(s.length_m > 0))
        Finding("accepted stone is not finite or has no length", i);
      if (i > 0 && !(stones[i - 1].x_center_m < s.x_center_m))
        Finding("accepted stones share a centre or are not sorted", i);
      // The stone's centre is on it, and the surface there is its top.
      if (terrain.StoneAt(s.x_center_m) != static_cast<int>(i)) Finding("StoneAt(centre) is not the stone", i);
      if (terrain.SurfaceHeight(s.x_center_m) != s.top_height_m)
        Finding("SurfaceHeight(centre) is not the stone's top", i);
      if (terrain.NearestStone(s.x_center_m) != static_cast<int>(i))
        Finding("NearestStone(centre) is not the stone", i);
    }
  } catch (const std::runtime_error& e) {
    if (std::strchr(e.what(), '\n') != nullptr) {
      std::fprintf(stderr, "terrain_csv_fuzzer: multi-line error message: %s\n", e.what());
      std::abort();
    }
  }
  return 0;
}
