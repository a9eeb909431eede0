// Latency of rome::DenseQpSolver on three problem families shaped like ROME's controllers
// (tests/solvers/qp/qp_test_problems.h):
//   A: CLF-QP, 12 variables, 2 equalities, 21 inequality rows, 12 two-sided bounds;
//   B: task-space QP with contact forces, 22 variables, 12 equalities, 30 inequality rows;
//   C: double-integrator MPC over N steps, 3N variables (N = 20, 40), banded.
//   D: condensed double-integrator MPC, N variables (N = 20, 40), dense H, 2N two-sided state rows, input bounds;
//      H and A fixed, g and the row bounds follow the MPC's own closed loop (10 ms ticks, 10 s, then it repeats).
// "Cold": every solve starts from the unconstrained minimum. "Warm": consecutive problems of a 1 kHz control
// loop (t advances 1 ms per solve), each started from the previous active set (QpSettings::hot_start off).
// "Hot" (C and D, whose matrices are fixed): the kept factorization of the previous working set, with the caller
// declaring the matrices unchanged (Solve(QpDataChange::kVectorsOnly), answer verified); "HotDetect": the same
// with the default Solve(), which compares the matrices with its copies. Cold, warm and hot run on the same
// sequence. Reference (issue 16, not measurable here): qpOASES's hot start on condensed MPC, N = 40, median 12 us;
// p99 317 us on the project's MPC instances.
// Each solve is timed individually (std::chrono::steady_clock); counters report the median and 99th percentile
// latency in microseconds, the mean number of iterations and the largest KKT residual of all solutions
// (must be < 1e-9). Problem data is copied into the solver before the clock starts (as the controller writes it
// in place) and is not timed.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <vector>

#include "solvers/qp/dense_qp_solver.h"
#include "tests/solvers/qp/qp_test_problems.h"

namespace rome {
namespace {

using qp_test::QpProblem;

constexpr int kPoolSize = 1000;  // 1 s of a 1 kHz control loop

template <typename Family>
std::vector<QpProblem> MakePool(const Family& family) {
  std::vector<QpProblem> pool;
  pool.reserve(kPoolSize);
  for (int k = 0; k < kPoolSize; ++k) pool.push_back(family.Sample(1e-3 * k));
  return pool;
}

double Percentile(std::vector<double>& v, double fraction) {
  const size_t k = std::min(v.size() - 1, static_cast<size_t>(fraction * static_cast<double>(v.size())));
  std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(k), v.end());
  return v[k];
}

// kDefault: default settings (warm and hot start on) and Solve(); A and B never hot start (H changes every tick).
enum class Start { kCold, kWarm, kDefault, kHot, kHotDetect };

void RunPool(benchmark::State& state, const std::vector<QpProblem>& pool, Start start) {
  const QpProblem& first = pool.front();
  const bool warm = start != Start::kCold;
  QpSettings settings;
  settings.hot_start = start == Start::kDefault || start == Start::kHot || start == Start::kHotDetect;
  DenseQpSolver solver(first.n(), first.n_eq(), first.n_ineq(), settings);
  const QpDataChange change = start == Start::kHot ? QpDataChange::kVectorsOnly : QpDataChange::kUnknown;
  qp_test::LoadInto(first, &solver);
  solver.Solve();  // size the workspace and fill the warm start
  std::vector<double> times_us;
  times_us.reserve(1 << 20);
  double kkt_max = 0.0;
  double iterations = 0.0;
  double hot = 0.0;
  int failures = 0;
  size_t k = 1;
  for (auto _ : state) {
    const QpProblem& p = pool[k % pool.size()];
    ++k;
    qp_test::LoadInto(p, &solver);
    if (!warm) solver.ResetWarmStart();
    const auto t0 = std::chrono::steady_clock::now();
    const QpStatus status = solver.Solve(change);
    const auto t1 = std::chrono::steady_clock::now();
    const double seconds = std::chrono::duration<double>(t1 - t0).count();
    state.SetIterationTime(seconds);
    if (times_us.size() < times_us.capacity()) times_us.push_back(1e6 * seconds);
    if (status != QpStatus::kOptimal) ++failures;
    kkt_max = std::max(kkt_max, ComputeQpKktResiduals(solver).Max());
    iterations += solver.iterations();
    hot += solver.hot_started();
  }
  state.counters["median_us"] = Percentile(times_us, 0.5);
  state.counters["p99_us"] = Percentile(times_us, 0.99);
  state.counters["kkt_max"] = kkt_max;
  state.counters["mean_iterations"] = iterations / static_cast<double>(std::max<size_t>(k - 1, 1));
  state.counters["failures"] = failures;
  if (settings.hot_start) state.counters["hot_fraction"] = hot / static_cast<double>(std::max<size_t>(k - 1, 1));
  state.counters["n"] = first.n();
}

const std::vector<QpProblem>& FamilyAPool() {
  static const std::vector<QpProblem> pool = MakePool(qp_test::ClfQpFamily(2024));
  return pool;
}
const std::vector<QpProblem>& FamilyBPool() {
  static const std::vector<QpProblem> pool = MakePool(qp_test::TaskSpaceQpFamily(2024));
  return pool;
}
const std::vector<QpProblem>& FamilyCPool(int horizon) {
  static const std::vector<QpProblem> pool20 = MakePool(qp_test::MpcQpFamily(20));
  static const std::vector<QpProblem> pool40 = MakePool(qp_test::MpcQpFamily(40));
  return horizon == 20 ? pool20 : pool40;
}

const std::vector<QpProblem>& FamilyDPool(int horizon) {
  auto make = [](int n) {
    const qp_test::CondensedMpcSequence sequence(n, kPoolSize);
    std::vector<QpProblem> pool;
    for (int k = 0; k < sequence.size(); ++k) pool.push_back(sequence.Problem(k));
    return pool;
  };
  static const std::vector<QpProblem> pool20 = make(20);
  static const std::vector<QpProblem> pool40 = make(40);
  return horizon == 20 ? pool20 : pool40;
}

void BM_QP_FamilyA_Cold(benchmark::State& state) { RunPool(state, FamilyAPool(), Start::kCold); }
void BM_QP_FamilyA_Warm(benchmark::State& state) { RunPool(state, FamilyAPool(), Start::kDefault); }
void BM_QP_FamilyB_Cold(benchmark::State& state) { RunPool(state, FamilyBPool(), Start::kCold); }
void BM_QP_FamilyB_Warm(benchmark::State& state) { RunPool(state, FamilyBPool(), Start::kDefault); }
void BM_QP_FamilyC_Cold(benchmark::State& state) {
  RunPool(state, FamilyCPool(static_cast<int>(state.range(0))), Start::kCold);
}
void BM_QP_FamilyC_Warm(benchmark::State& state) {
  RunPool(state, FamilyCPool(static_cast<int>(state.range(0))), Start::kWarm);
}

void BM_QP_FamilyC_Hot(benchmark::State& state) {
  RunPool(state, FamilyCPool(static_cast<int>(state.range(0))), Start::kHot);
}
void BM_QP_FamilyD_Hot(benchmark::State& state) {
  RunPool(state, FamilyDPool(static_cast<int>(state.range(0))), Start::kHot);
}
void BM_QP_FamilyD_HotDetect(benchmark::State& state) {
  RunPool(state, FamilyDPool(static_cast<int>(state.range(0))), Start::kHotDetect);
}
void BM_QP_FamilyD_Cold(benchmark::State& state) {
  RunPool(state, FamilyDPool(static_cast<int>(state.range(0))), Start::kCold);
}
void BM_QP_FamilyD_Warm(benchmark::State& state) {
  RunPool(state, FamilyDPool(static_cast<int>(state.range(0))), Start::kWarm);
}

BENCHMARK(BM_QP_FamilyA_Cold)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyA_Warm)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyB_Cold)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyB_Warm)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyC_Cold)->Arg(20)->Arg(40)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyC_Warm)->Arg(20)->Arg(40)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyD_Cold)->Arg(20)->Arg(40)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyD_Warm)->Arg(20)->Arg(40)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyC_Hot)->Arg(20)->Arg(40)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyD_Hot)->Arg(20)->Arg(40)->UseManualTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_QP_FamilyD_HotDetect)->Arg(20)->Arg(40)->UseManualTime()->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
