// libFuzzer harness for the plan cache's reader: PlanCache::Load on a file a shared cache folder may hold.
//
// Input: a first byte choosing the mode, then the bytes it uses.
//   even: the bytes are written as the entry of a fixed key, in a private folder (TempFolder), and loaded.
//         Fine: a miss, or finite values, no more than the file's size allows (two bytes a value), which the writer
//         gives back unchanged (ParseEntry(EntryText(v)) == v).
//   odd:  the bytes, eight at a time, are doubles: EntryText then ParseEntry must give them back bit for bit when all
//         are finite, and a miss when one is NaN or infinite.
// A finding: an exception out of Load, a crash, a sanitizer report, a hang (-timeout), an allocation beyond
// -rss_limit_mb (a count line the file cannot hold), or a broken promise above.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>

#include "framework/files.h"
#include "systems/planners/plan_cache.h"

namespace {

[[noreturn]] void Finding(const char* what) {
  std::fprintf(stderr, "plan_cache_fuzzer: %s\n", what);
  std::abort();
}

rome::PlanCacheKey Key() {
  rome::PlanCacheKey key("fuzz_plan");
  key.Add("x", 1.0);
  return key;
}

bool BitEqual(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         (a.size() == 0 || std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0);
}

void LoadFile(const std::string& bytes) {
  static const rome::TempFolder folder("rome_plan_cache_fuzzer");
  static const rome::PlanCache cache(folder.path());
  std::ofstream(cache.FileFor(Key()), std::ios::binary | std::ios::trunc) << bytes;
  std::optional<Eigen::VectorXd> loaded;
  try {
    loaded = cache.Load(Key());
  } catch (...) { Finding("Load threw"); }
  if (!loaded) return;
  if (static_cast<size_t>(loaded->size()) > bytes.size() / 2) Finding("more values than the file can hold");
  if (!loaded->allFinite()) Finding("a value that is not finite was loaded");
  const auto again = rome::PlanCache::ParseEntry(rome::PlanCache::EntryText(Key(), *loaded), Key().text());
  if (!again || !BitEqual(*again, *loaded)) Finding("a loaded plan does not survive EntryText and ParseEntry");
}

void RoundTrip(const uint8_t* data, size_t size) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(size / sizeof(double)));
  if (v.size() > 0) std::memcpy(v.data(), data, sizeof(double) * static_cast<size_t>(v.size()));
  const auto back = rome::PlanCache::ParseEntry(rome::PlanCache::EntryText(Key(), v), Key().text());
  if (v.allFinite() ? !back || !BitEqual(*back, v) : back.has_value())
    Finding("EntryText and ParseEntry do not round-trip");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  if (data[0] % 2 == 0)
    LoadFile(std::string(reinterpret_cast<const char*>(data) + 1, size - 1));
  else
    RoundTrip(data + 1, size - 1);
  return 0;
}
