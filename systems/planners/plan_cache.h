#pragma once
// PlanCache: offline ROM plans (NLP decision vectors) stored on disk, keyed by everything that defines them, so that
// a second run with the same parameters starts at once (walking issue: "plans are cached to a file keyed by their
// parameters").
//
// A key is a canonical text of the problem's parameters (numbers printed with 17 significant digits, so equal keys
// mean bit-equal parameters). The file is <directory>/<name>-<FNV-1a 64-bit hash of the key, hex>.plan and holds the
// full key on its first line (a hash collision or a stale file is detected and treated as a miss), then the vector.
// Writes go to a temporary file that is renamed into place, so a reader never sees a half-written plan.
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
  /// The directory is created on the first Store(). Throws std::invalid_argument for an empty path.
  explicit PlanCache(std::string directory);
  const std::string& directory() const { return directory_; }
  /// The file a key maps to.
  std::string FileFor(const PlanCacheKey& key) const;
  /// The stored vector, or nothing if there is no file, its key differs, or it cannot be parsed.
  std::optional<Eigen::VectorXd> Load(const PlanCacheKey& key) const;
  /// Stores the vector: written to a temporary file of this process's own, then renamed over the plan's file, so
  /// processes sharing the directory may store the same key at once. Throws std::runtime_error naming the file if it
  /// cannot be written.
  void Store(const PlanCacheKey& key, const Eigen::VectorXd& value) const;

 private:
  std::string directory_;
};

}  // namespace rome
