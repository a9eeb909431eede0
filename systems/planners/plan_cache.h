#pragma once
// PlanCache: offline ROM plans (NLP decision vectors) stored on disk, keyed by everything that defines them, so that
// a second run with the same parameters starts at once (walking issue: "plans are cached to a file keyed by their
// parameters").
//
// A key is a canonical text of the problem's parameters (numbers printed with 17 significant digits, so equal keys
// mean bit-equal parameters). The file is <directory>/<name>-<FNV-1a 64-bit hash of the key, hex>.plan and holds
//   rome-plan-cache 2          (the format)
//   <the full key>             (a hash collision or a stale file is a miss)
//   count <N>
//   fnv1a64 <16 hex digits>    (checksum of the payload: the text of the lines below)
//   N lines, one number each   (shortest round-trip text, so a loaded plan is bit-equal to the stored one)
// A cache folder may be shared (CI runners, lab machines) and so may hold anything: Load reads only a regular file
// (never through a symlink) of at most kMaxFileBytes, and any entry that is not exactly the format above (a wrong
// header or key, a count the file cannot hold, a checksum mismatch, a value that is not a finite number, a missing or
// extra line) is a miss, which the planners re-solve and overwrite. Store writes through AtomicFileWriter
// (framework/files.h): a new file of an unpredictable name beside the entry, renamed over it, so a planted symlink is
// replaced, never followed, and readers never see a half-written plan.
#include <cstdint>
#include <optional>
#include <sstream>
#include <string>

#include <Eigen/Core>

namespace rome {

/// Builds a canonical key: Add("name", value) appends "name=value;" with 17 significant digits.
class PlanCacheKey {
 public:
  explicit PlanCacheKey(std::string problem) : problem_(std::move(problem)) { text_ << problem_ << ';'; }
  PlanCacheKey& Add(const char* name, double value);
  PlanCacheKey& Add(const char* name, const Eigen::MatrixXd& value);
  const std::string& problem() const { return problem_; }
  std::string text() const { return text_.str(); }

 private:
  std::string problem_;
  std::ostringstream text_;
};

class PlanCache {
 public:
  /// The largest entry Load reads (about 600,000 values; the walking plans hold a few thousand). A larger entry is a
  /// miss.
  static constexpr std::uintmax_t kMaxFileBytes = 16u << 20;

  /// The directory is created by EnsureDirectory() or the first Store(). Throws std::invalid_argument for an empty
  /// path.
  explicit PlanCache(std::string directory);
  const std::string& directory() const { return directory_; }
  /// Creates the directory if it is missing and checks that a file can be created in it. Empty if so; otherwise the
  /// one-line reason, naming the folder (a file at the path, a parent that is a file, no permission). For programs to
  /// call before any NLP runs, so that a bad --cache is bad input rather than a failure after the solves.
  std::string EnsureDirectory() const;
  /// The file a key maps to.
  std::string FileFor(const PlanCacheKey& key) const;
  /// The stored vector, or nothing (a miss) if there is no entry or it is not a valid entry of this key (see the top
  /// of this file). Never throws for what the file holds.
  std::optional<Eigen::VectorXd> Load(const PlanCacheKey& key) const;
  /// Stores the vector (atomically, see the top of this file), so processes sharing the directory may store the same
  /// key at once; the last rename wins. Returns "" or, if it cannot be written (a full disk, a folder planted at the
  /// entry's name), the one-line reason naming the file: the cache is only a shortcut, so a caller warns and goes on.
  std::string Store(const PlanCacheKey& key, const Eigen::VectorXd& value) const;

  /// The text of an entry as Store writes it (a vector holding NaN or an infinity gives an entry Load misses).
  static std::string EntryText(const PlanCacheKey& key, const Eigen::VectorXd& value);
  /// The vector of an entry's text if it is a valid entry for `key_text`, else nothing.
  static std::optional<Eigen::VectorXd> ParseEntry(const std::string& text, const std::string& key_text);

 private:
  std::string directory_;
};

/// Prints "warning: <error> (the plan is used, not cached)" on stderr when Store's `error` is not empty.
void WarnIfNotCached(const std::string& error);

}  // namespace rome
