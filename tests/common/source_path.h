#pragma once
// SourcePath: files of the repository (robots/..., tests/.../data/...) by absolute path, for tests and benchmarks.
//
// The repository root is known only to source_path.cc (compile definition ROME_SOURCE_DIR). Callers never paste the
// root into a string expression: with the root as a literal of a length the compiler can see, GCC 12 -O3 with the
// precompiled headers reports false -Warray-bounds in std::string's operator+ for some clone paths (a 16-character
// root, CI's, did; this machine's 10-character one did not), so a -Werror build depended on where it was cloned.

#include <string>
#include <string_view>

namespace rome::test {

/// The repository root joined with `relative` ("robots/amber/amber.urdf"); `relative` must not start with '/'.
std::string SourcePath(std::string_view relative);

/// This test process's private scratch folder (mkdtemp, mode 0700; removed when the process exits). Tests write
/// their files here, never at fixed names in the shared temporary folder, where a planted symlink could redirect them.
const std::string& ScratchDir();

/// A plan cache folder `name` for tests: $XDG_CACHE_HOME/rome/test_plans/name (default ~/.cache/...), or
/// <build>/test_cache/name without a home folder. Kept between runs and builds (the Release and sanitizer suites share
/// the solved NLPs), and private to the user, unlike a fixed folder in the shared /tmp.
std::string TestPlanCacheDir(std::string_view name);

}  // namespace rome::test
