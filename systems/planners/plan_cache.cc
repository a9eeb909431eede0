#include "systems/planners/plan_cache.h"

#include <sys/stat.h>

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <iomanip>
#include <stdexcept>
#include <string_view>
#include <system_error>

#include "framework/files.h"
#include "framework/text.h"

namespace rome {
namespace {

constexpr std::string_view kFormatLine = "rome-plan-cache 2";
constexpr std::string_view kCountPrefix = "count ";
constexpr std::string_view kChecksumPrefix = "fnv1a64 ";

std::uint64_t Fnv1a(std::string_view text) {
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 1099511628211ull;
  }
  return h;
}

std::string Hex16(std::uint64_t v) {
  char hex[17];
  std::snprintf(hex, sizeof(hex), "%016llx", static_cast<unsigned long long>(v));
  return hex;
}

// The '\n'-terminated line of `text` starting at *at, advancing *at past it; false if no full line is left.
bool NextLine(std::string_view text, size_t* at, std::string_view* line) {
  const size_t end = text.find('\n', *at);
  if (end == std::string_view::npos) return false;
  *line = text.substr(*at, end - *at);
  *at = end + 1;
  return true;
}

// `line` is `prefix` followed by an unsigned number in `base` and nothing else.
bool ParseField(std::string_view line, std::string_view prefix, int base, std::uint64_t* value) {
  if (line.substr(0, prefix.size()) != prefix || line.size() == prefix.size()) return false;
  const char* end = line.data() + line.size();
  const auto [ptr, ec] = std::from_chars(line.data() + prefix.size(), end, *value, base);
  return ec == std::errc() && ptr == end;
}

// One finite number filling the whole line.
bool ParseValue(std::string_view line, double* value) {
  const char* end = line.data() + line.size();
  const auto [ptr, ec] = std::from_chars(line.data(), end, *value);
  return ec == std::errc() && ptr == end && std::isfinite(*value);
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

std::string PlanCache::EnsureDirectory() const {
  const std::string name = "plan cache folder '" + Excerpt(directory_, 200) + "'";
  struct stat st {};
  if (::stat(directory_.c_str(), &st) == 0 && !S_ISDIR(st.st_mode))
    return name + ": is " + (S_ISREG(st.st_mode) ? "a file" : "not a regular folder") + ", not a folder";
  std::error_code ec;
  std::filesystem::create_directories(directory_, ec);
  if (ec) return name + ": cannot be created (" + ec.message() + ")";
  try {
    // A real probe (a temporary file, removed again): access() says yes to root on a read-only file system.
    const AtomicFileWriter probe(directory_ + "/.write_probe", "plan cache folder");
  } catch (const std::exception& e) { return name + ": is not writable (" + Excerpt(e.what(), 300) + ")"; }
  return {};
}

std::string PlanCache::FileFor(const PlanCacheKey& key) const {
  return directory_ + "/" + key.problem() + "-" + Hex16(Fnv1a(key.text())) + ".plan";
}

std::string PlanCache::EntryText(const PlanCacheKey& key, const Eigen::VectorXd& value) {
  std::string payload;
  char number[64];
  for (Eigen::Index i = 0; i < value.size(); ++i) {
    const auto [end, ec] = std::to_chars(number, number + sizeof(number), value(i));  // shortest round trip
    payload.append(number, ec == std::errc() ? end : number);
    payload += '\n';
  }
  std::string text(kFormatLine);
  text += '\n' + key.text() + '\n';
  text += std::string(kCountPrefix) + std::to_string(value.size()) + '\n';
  text += std::string(kChecksumPrefix) + Hex16(Fnv1a(payload)) + '\n';
  return text + payload;
}

std::optional<Eigen::VectorXd> PlanCache::ParseEntry(const std::string& text, const std::string& key_text) {
  size_t at = 0;
  std::string_view line;
  std::uint64_t count = 0, checksum = 0;
  if (!NextLine(text, &at, &line) || line != kFormatLine) return std::nullopt;
  if (!NextLine(text, &at, &line) || line != key_text) return std::nullopt;
  if (!NextLine(text, &at, &line) || !ParseField(line, kCountPrefix, 10, &count)) return std::nullopt;
  if (!NextLine(text, &at, &line) || line.size() != kChecksumPrefix.size() + 16 ||
      !ParseField(line, kChecksumPrefix, 16, &checksum))
    return std::nullopt;
  const std::string_view payload = std::string_view(text).substr(at);
  // Each value takes two bytes at least (a digit and its newline): a count the file cannot hold is refused before
  // anything is allocated.
  if (count > payload.size() / 2 || Fnv1a(payload) != checksum) return std::nullopt;
  Eigen::VectorXd value(static_cast<Eigen::Index>(count));
  for (Eigen::Index i = 0; i < value.size(); ++i) {
    if (!NextLine(text, &at, &line) || !ParseValue(line, &value(i))) return std::nullopt;
  }
  if (at != text.size()) return std::nullopt;  // more lines than the count
  return value;
}

std::optional<Eigen::VectorXd> PlanCache::Load(const PlanCacheKey& key) const {
  const std::string file = FileFor(key);
  // The entry itself must be a regular file: a symlink (which may point anywhere), a FIFO or a device is a miss.
  struct stat st {};
  if (::lstat(file.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return std::nullopt;
  try {
    return ParseEntry(ReadRegularFile(file, "plan cache entry", kMaxFileBytes), key.text());
  } catch (const std::exception&) {  // replaced meanwhile by something unreadable, or over the size cap
    return std::nullopt;
  }
}

std::string PlanCache::Store(const PlanCacheKey& key, const Eigen::VectorXd& value) const {
  std::error_code ignored;  // a folder that cannot be created shows as the writer's error, naming the file
  std::filesystem::create_directories(directory_, ignored);
  // The entry's name is the cache's own: a FIFO, a device node or an empty folder standing there
  // is removed by name, never opened; a symlink is replaced by the rename itself.
  const std::string file = FileFor(key);
  const std::filesystem::file_status st = std::filesystem::symlink_status(file, ignored);
  if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st) && !std::filesystem::is_symlink(st))
    std::filesystem::remove(file, ignored);  // a folder with content stays, and the write below names it
  try {
    WriteFileAtomically(file, EntryText(key, value), "plan cache entry");
  } catch (const std::exception& e) { return e.what(); }
  return {};
}

void WarnIfNotCached(const std::string& error) {
  if (!error.empty()) std::cerr << "warning: " << error << " (the plan is used, not cached)\n";
}

}  // namespace rome
