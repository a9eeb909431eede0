#pragma once
// Test sizes under the sanitizers. Under AddressSanitizer + UndefinedBehaviorSanitizer (-O1, ./rome test-sanitize) the
// closed loops run 15-20 times slower than in Release. The sanitizer suite looks for memory errors and undefined
// behaviour, which the first random courses exercise along the same code paths as all ten, so the long statistical
// loops run fewer seeds there; every physics check of each run is the same. 13 of the walking diagram's gait-range
// variants (other gaits along the code paths of the defaults' runs, or paths a unit test checks there) and a few
// planning-only cases skip there. The Release suite
// (./rome test) runs the full counts and every variant.

namespace rome::test {

#if defined(__SANITIZE_ADDRESS__)
inline constexpr bool kSanitizerBuild = true;
#else
inline constexpr bool kSanitizerBuild = false;
#endif

/// `release` in the Release suite, `sanitizer` under the sanitizers.
constexpr int SanitizerScaled(int release, int sanitizer) { return kSanitizerBuild ? sanitizer : release; }

/// Random stepping-stone courses of the sweep tests: seeds 1-10, seeds 1-3 under the sanitizers.
constexpr unsigned kRandomCourseSeeds = static_cast<unsigned>(SanitizerScaled(10, 3));

}  // namespace rome::test
