#include "systems/planners/plan_cache.h"

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <stdexcept>

#include <unistd.h>

namespace rome {
namespace {

std::uint64_t Fnv1a(const std::string& text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

}  // namespace

PlanCacheKey& PlanCacheKey::Add(const char* name, double value) {
  text_ << name << '=' << std::setprecision(17) << value << ';';
  return *this;
}

PlanCacheKey& PlanCacheKey::Add(const char* name, const Eigen::MatrixXd& value) {
  text_ << name << '[' << value.rows() << 'x' << value.cols() << "]=";
  for (Eigen::Index i = 0; i < value.size(); ++i) text_ << std::setprecision(17) << value.data()[i] << ',';
  text_ << ';';
  return *this;
}

PlanCache::PlanCache(std::string directory) : directory_(std::move(directory)) {
  if (directory_.empty()) throw std::invalid_argument("PlanCache: the cache directory must not be empty");
}

std::string PlanCache::FileFor(const PlanCacheKey& key) const {
  char hash[17];
  std::snprintf(hash, sizeof(hash), "%016llx", static_cast<unsigned long long>(Fnv1a(key.text())));
  return directory_ + "/" + key.problem() + "-" + hash + ".plan";
}

std::optional<Eigen::VectorXd> PlanCache::Load(const PlanCacheKey& key) const {
  std::ifstream in(FileFor(key));
  if (!in) return std::nullopt;
  std::string stored_key;
  if (!std::getline(in, stored_key) || stored_key != key.text()) return std::nullopt;
  long n = 0;
  if (!(in >> n) || n < 0) return std::nullopt;
  Eigen::VectorXd value(n);
  for (long i = 0; i < n; ++i) {
    if (!(in >> value(i))) return std::nullopt;
  }
  return value;
}

void PlanCache::Store(const PlanCacheKey& key, const Eigen::VectorXd& value) const {
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  // Each writer has its own temporary file (process id and a per-process count), so runs sharing a cache directory
  // (parallel runs planning the same gait) never write into or rename away one another's file; the rename is atomic
  // and the last one wins, with the same plan.
  static std::atomic<unsigned long> writes{0};
  const std::string file = FileFor(key);
  const std::string tmp = file + "." + std::to_string(static_cast<long>(::getpid())) + "-" + std::to_string(writes++) + ".tmp";
  {
    std::ofstream out(tmp);
    out << key.text() << '\n' << value.size() << '\n' << std::setprecision(17);
    for (Eigen::Index i = 0; i < value.size(); ++i) out << value(i) << '\n';
    if (!out) {
      std::error_code ignored;
      std::filesystem::remove(tmp, ignored);
      throw std::runtime_error("PlanCache: cannot write plan file " + tmp);
    }
  }
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw std::runtime_error("PlanCache: cannot rename " + tmp + " to " + file + ": " + ec.message());
  }
}

}  // namespace rome
