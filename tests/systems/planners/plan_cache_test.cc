// PlanCache: keyed round trip to every bit; processes that store the same key into one directory at once (parallel
// runs planning the same gait: two walking runs whose gaits differ only in the step width share the sagittal plan);
// and a shared cache folder holding anything (issue 45): planted symlinks are replaced, never followed, and every
// entry that is not valid (a huge count, a checksum mismatch, NaN, truncation, a FIFO, a symlink) is a miss that
// returns at once and that Store overwrites.
#include "systems/planners/plan_cache.h"

#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "framework/files.h"
#include "tests/common/text_files.h"

namespace rome {
namespace {

PlanCacheKey Key(double step_length) {
  PlanCacheKey key("test_plan");
  key.Add("step_length", step_length);
  return key;
}

Eigen::VectorXd Value() {
  Eigen::VectorXd value(4);
  value << M_PI, -1e-300, 1.0 / 3.0, 6.02214076e23;
  return value;
}

bool IsRegularFile(const std::string& path) {
  struct stat st {};
  return ::lstat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

enum class Outcome { kMiss, kHit, kThrew, kTimedOut, kCrashed };

// Load in a child process, so that a hang (a FIFO opened for reading) or a crash is seen and ends.
Outcome LoadInChild(const PlanCache& cache, const PlanCacheKey& key, double seconds = 10.0) {
  const pid_t pid = fork();
  if (pid == 0) {
    int code = 2;
    try {
      code = cache.Load(key).has_value() ? 1 : 0;
    } catch (...) {}
    _exit(code);
  }
  if (pid < 0) return Outcome::kCrashed;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return Outcome::kTimedOut;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  if (!WIFEXITED(status)) return Outcome::kCrashed;
  const int code = WEXITSTATUS(status);
  return code == 0 ? Outcome::kMiss : code == 1 ? Outcome::kHit : Outcome::kThrew;
}

const char* Name(Outcome o) {
  switch (o) {
    case Outcome::kMiss: return "a miss";
    case Outcome::kHit: return "a hit";
    case Outcome::kThrew: return "an exception";
    case Outcome::kTimedOut: return "no return within 10 s";
    case Outcome::kCrashed: return "a crash";
  }
  return "?";
}

// `text` with its line number `line` (0-based) replaced by `replacement`.
std::string ReplaceLine(const std::string& text, int line, const std::string& replacement) {
  size_t begin = 0;
  for (int i = 0; i < line; ++i) begin = text.find('\n', begin) + 1;
  const size_t end = text.find('\n', begin);
  return text.substr(0, begin) + replacement + text.substr(end);
}

TEST(PlanCache, RoundTripsEveryBitAndMissesOtherKeys) {
  const TempFolder tmp("plan_cache_test");
  const PlanCache cache(tmp.File("plans"));
  Eigen::VectorXd value(6);
  value << M_PI, -1e-300, 1.0 / 3.0, 6.02214076e23, -0.0, std::numeric_limits<double>::denorm_min();
  cache.Store(Key(0.3), value);
  const auto loaded = cache.Load(Key(0.3));
  ASSERT_TRUE(loaded.has_value());
  ASSERT_EQ(loaded->size(), value.size());
  for (Eigen::Index i = 0; i < value.size(); ++i)
    EXPECT_EQ(std::memcmp(&(*loaded)(i), &value(i), sizeof(double)), 0) << "value " << i;
  EXPECT_FALSE(cache.Load(Key(0.31)).has_value());
  // Nothing but the plan's file is left in the directory, and it is a regular file.
  int files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(cache.directory())) {
    ++files;
    EXPECT_EQ(entry.path().string(), cache.FileFor(Key(0.3)));
  }
  EXPECT_EQ(files, 1);
  EXPECT_TRUE(IsRegularFile(cache.FileFor(Key(0.3))));
}

TEST(PlanCache, AnEmptyVectorRoundTrips) {
  const TempFolder tmp("plan_cache_test");
  const PlanCache cache(tmp.path());
  cache.Store(Key(0.3), Eigen::VectorXd());
  const auto loaded = cache.Load(Key(0.3));
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(loaded->size(), 0);
}

TEST(PlanCache, ProcessesStoringTheSameKeyAtOnceAllSucceed) {
  const TempFolder tmp("plan_cache_test");
  const std::string dir = tmp.File("plans");
  constexpr int kProcesses = 4, kStores = 300;
  Eigen::VectorXd value = Eigen::VectorXd::LinSpaced(2000, 0.0, 1.0);
  pid_t children[kProcesses];
  for (int i = 0; i < kProcesses; ++i) {
    children[i] = fork();
    ASSERT_GE(children[i], 0) << "fork failed";
    if (children[i] == 0) {
      int failures = 0;
      try {
        const PlanCache cache(dir);
        for (int k = 0; k < kStores; ++k) cache.Store(Key(0.3), value);
      } catch (const std::exception&) { failures = 1; }
      _exit(failures);
    }
  }
  int failed = 0;
  for (pid_t child : children) {
    int status = 0;
    ASSERT_EQ(waitpid(child, &status, 0), child);
    failed += !(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  }
  EXPECT_EQ(failed, 0) << "a process's Store threw (another process wrote or renamed its temporary file)";
  const PlanCache cache(dir);
  const auto loaded = cache.Load(Key(0.3));
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ((*loaded - value).cwiseAbs().maxCoeff(), 0.0);
  int files = 0;
  for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(dir)) ++files;
  EXPECT_EQ(files, 1);  // no temporary file left behind
}

// Symlinks planted in a shared cache folder, pointing at a victim file outside it: at the entry's own name, and at
// every temporary name an earlier version of Store used (<entry>.<pid>-<n>.tmp, a fixed function of public values).
TEST(PlanCache, StoreReplacesPlantedSymlinksAndNeverWritesThroughThem) {
  const TempFolder tmp("plan_cache_test");
  const std::string victim = tmp.File("victim.txt");
  test::WriteText(victim, "precious\n");
  const PlanCache cache(tmp.File("shared_plans"));
  ASSERT_EQ(cache.EnsureDirectory(), "");
  const std::string entry = cache.FileFor(Key(0.3));
  ASSERT_EQ(::symlink(victim.c_str(), entry.c_str()), 0);
  for (int n = 0; n < 64; ++n) {
    const std::string temp = entry + "." + std::to_string(::getpid()) + "-" + std::to_string(n) + ".tmp";
    ASSERT_EQ(::symlink(victim.c_str(), temp.c_str()), 0);
  }
  // A symlinked entry is a miss (even one pointing at a valid entry: see NonRegularEntriesAreMisses).
  EXPECT_EQ(LoadInChild(cache, Key(0.3)), Outcome::kMiss);
  cache.Store(Key(0.3), Value());
  EXPECT_EQ(test::ReadText(victim), "precious\n") << "Store wrote through a planted symlink";
  EXPECT_TRUE(IsRegularFile(entry)) << "the entry is not a regular file after Store";
  const auto loaded = cache.Load(Key(0.3));
  ASSERT_TRUE(loaded.has_value());
  EXPECT_EQ(*loaded, Value());
}

TEST(PlanCache, CorruptEntriesAreMissesThatReturnAtOnceAndStoreReplaces) {
  const TempFolder tmp("plan_cache_test");
  const PlanCache cache(tmp.File("plans"));
  ASSERT_EQ(cache.EnsureDirectory(), "");
  const std::string valid = PlanCache::EntryText(Key(0.3), Value());
  Eigen::VectorXd with_nan = Value(), with_inf = Value();
  with_nan(2) = std::nan("");
  with_inf(1) = -std::numeric_limits<double>::infinity();
  std::string flipped = valid;
  const size_t digit = flipped.rfind("3333");  // a digit of 1/3 in the payload
  ASSERT_NE(digit, std::string::npos);
  flipped[digit] = '4';
  std::ostringstream old_format;  // the format before checksums: key, count, values
  old_format.precision(17);
  old_format << Key(0.3).text() << "\n4\n" << M_PI << "\n-1e-300\n" << 1.0 / 3.0 << "\n6.02214076e23\n";
  const std::vector<std::pair<std::string, std::string>> corrupt = {
      {"a count line of 999999999999", ReplaceLine(valid, 2, "count 999999999999")},
      {"a count of 2^64 - 1", ReplaceLine(valid, 2, "count 18446744073709551615")},
      {"a count past 2^64", ReplaceLine(valid, 2, "count 99999999999999999999999")},
      {"a negative count", ReplaceLine(valid, 2, "count -4")},
      {"a count one more than the values", ReplaceLine(valid, 2, "count 5")},
      {"a count one less than the values", ReplaceLine(valid, 2, "count 3")},
      {"a flipped digit (checksum)", flipped},
      {"a checksum that is not hex", ReplaceLine(valid, 3, "fnv1a64 0123456789abcdeg")},
      {"a NaN value (with its checksum)", PlanCache::EntryText(Key(0.3), with_nan)},
      {"an infinite value (with its checksum)", PlanCache::EntryText(Key(0.3), with_inf)},
      {"truncated in the values", valid.substr(0, valid.size() - 5)},
      {"truncated in the header", valid.substr(0, 30)},
      {"the last newline missing", valid.substr(0, valid.size() - 1)},
      {"an empty file", ""},
      {"another key's entry", PlanCache::EntryText(Key(0.31), Value())},
      {"another format version", ReplaceLine(valid, 0, "rome-plan-cache 1")},
      {"the format without a checksum", old_format.str()},
      {"binary noise", std::string("\x00\xff\n\x01", 4) + "count 4\n"},
  };
  for (const auto& [what, text] : corrupt) {
    // The parser itself neither throws nor allocates for a count the text cannot hold (8 TB for 999999999999).
    EXPECT_FALSE(PlanCache::ParseEntry(text, Key(0.3).text()).has_value()) << what;
    test::WriteText(cache.FileFor(Key(0.3)), text);
    EXPECT_EQ(LoadInChild(cache, Key(0.3)), Outcome::kMiss) << what << ": " << Name(LoadInChild(cache, Key(0.3)));
    cache.Store(Key(0.3), Value());  // the planner re-solves a miss and overwrites the entry
    const auto loaded = cache.Load(Key(0.3));
    ASSERT_TRUE(loaded.has_value()) << what << ": the overwritten entry does not load";
    EXPECT_EQ(*loaded, Value()) << what;
  }
  EXPECT_EQ(LoadInChild(cache, Key(0.3)), Outcome::kHit);  // the child process sees what the parent does
}

TEST(PlanCache, AnEntryLargerThanTheCapIsAMiss) {
  const TempFolder tmp("plan_cache_test");
  const PlanCache cache(tmp.path());
  // 1.2 million values of 17 or more characters each: valid, but over the 16 MiB cap.
  const Eigen::VectorXd big = Eigen::VectorXd::LinSpaced(1200000, 0.1, 0.9);
  cache.Store(Key(0.3), big);
  ASSERT_GT(std::filesystem::file_size(cache.FileFor(Key(0.3))), PlanCache::kMaxFileBytes);
  EXPECT_FALSE(cache.Load(Key(0.3)).has_value());
}

TEST(PlanCache, NonRegularEntriesAreMissesAndStoreReplacesThem) {
  const TempFolder tmp("plan_cache_test");
  const PlanCache cache(tmp.File("plans"));
  ASSERT_EQ(cache.EnsureDirectory(), "");
  const std::string entry = cache.FileFor(Key(0.3));
  // A FIFO nobody writes to: reading it would wait forever.
  ASSERT_EQ(::mkfifo(entry.c_str(), 0644), 0);
  EXPECT_EQ(LoadInChild(cache, Key(0.3)), Outcome::kMiss) << "a FIFO at the entry's name";
  cache.Store(Key(0.3), Value());
  EXPECT_TRUE(IsRegularFile(entry));
  EXPECT_TRUE(cache.Load(Key(0.3)).has_value());
  // A symlink to a valid entry elsewhere: the link may point anywhere, so it is never read.
  const std::string elsewhere = tmp.File("elsewhere.plan");
  test::WriteText(elsewhere, PlanCache::EntryText(Key(0.3), Value()));
  std::filesystem::remove(entry);
  ASSERT_EQ(::symlink(elsewhere.c_str(), entry.c_str()), 0);
  EXPECT_EQ(LoadInChild(cache, Key(0.3)), Outcome::kMiss) << "a symlink at the entry's name";
  // A symlink to a device.
  std::filesystem::remove(entry);
  ASSERT_EQ(::symlink("/dev/zero", entry.c_str()), 0);
  EXPECT_EQ(LoadInChild(cache, Key(0.3)), Outcome::kMiss) << "a symlink to /dev/zero";
  // A directory.
  std::filesystem::remove(entry);
  std::filesystem::create_directory(entry);
  EXPECT_EQ(LoadInChild(cache, Key(0.3)), Outcome::kMiss) << "a directory at the entry's name";
}

TEST(PlanCache, EnsureDirectoryCreatesAFolderAndNamesAPathThatCannotBeOne) {
  const TempFolder tmp("plan_cache_test");
  const PlanCache nested(tmp.File("a/b/plans"));
  EXPECT_EQ(nested.EnsureDirectory(), "");
  EXPECT_TRUE(std::filesystem::is_directory(nested.directory()));
  EXPECT_TRUE(std::filesystem::is_empty(nested.directory())) << "the write probe was left behind";
  test::WriteText(tmp.File("a_file"), "not a folder\n");
  const std::string file_error = PlanCache(tmp.File("a_file")).EnsureDirectory();
  EXPECT_NE(file_error.find("plan cache folder '" + tmp.File("a_file") + "': is a file, not a folder"),
            std::string::npos)
      << file_error;
  const std::string under_file = PlanCache(tmp.File("a_file/plans")).EnsureDirectory();
  EXPECT_NE(under_file.find(tmp.File("a_file/plans") + "': cannot be created"), std::string::npos) << under_file;
  const std::string proc = PlanCache("/proc/rome_plan_cache_test").EnsureDirectory();
  EXPECT_NE(proc.find("'/proc/rome_plan_cache_test'"), std::string::npos) << proc;
  for (const std::string& message : {file_error, under_file, proc})
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  EXPECT_THROW(PlanCache(""), std::invalid_argument);
}

}  // namespace
}  // namespace rome

namespace rome {
namespace {

// The cache is a shortcut: a Store that cannot write (here a folder with content planted at the entry's name) returns
// its reason naming the file, and throws nothing, so the run that solved the plan goes on.
TEST(PlanCache, AStoreThatCannotWriteReturnsItsReasonInsteadOfThrowing) {
  const TempFolder tmp("plan_cache_test");
  const PlanCache cache(tmp.File("plans"));
  ASSERT_EQ(cache.EnsureDirectory(), "");
  const std::string entry = cache.FileFor(Key(0.3));
  std::filesystem::create_directories(entry + "/content");
  std::string error;
  EXPECT_NO_THROW(error = cache.Store(Key(0.3), Value()));
  EXPECT_NE(error.find("plan cache entry " + entry), std::string::npos) << error;
  EXPECT_EQ(error.find('\n'), std::string::npos);
  std::filesystem::remove_all(entry);
  EXPECT_EQ(cache.Store(Key(0.3), Value()), "");
  EXPECT_TRUE(cache.Load(Key(0.3)).has_value());
}

}  // namespace
}  // namespace rome
