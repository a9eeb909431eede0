// Solve times of the walking paper's ROM planners (offline, once per gait or transition): the periodic point-foot
// aSLIP NLP, Eq. (4)-(5), from the random initial guesses of seeds 1-10 (Ipopt, L-BFGS; the paper reports 1-2 s in
// MATLAB, our target is ≤ 100 ms median), and the footed H-LIP transition QP, Eq. (11)-(15).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <string>

#include "systems/planners/aslip_periodic_gait_planner.h"
#include "systems/planners/footed_hlip_transition_planner.h"
#include "systems/rom/hybrid_linear_inverted_pendulum.h"

namespace rome {
namespace {

// arg: step length in cm (30 = gait A, 40 = gait B). Iteration i solves from the random guess of seed 1 + (i % 10);
// the counters give the median and worst solve (Ipopt wall time) over the iterations.
void BM_AslipPeriodicGaitNlp(benchmark::State& state) {
  AslipPeriodicGaitParams params;
  params.step_length = state.range(0) / 100.0;
  const AslipPeriodicGaitPlanner planner(params);
  std::uint32_t i = 0;
  int failures = 0, iterations = 0;
  std::vector<double> times_ms;
  for (auto _ : state) {
    const AslipPeriodicGait gait = planner.Solve(1 + (i++ % 10));
    failures += gait.success() ? 0 : 1;
    iterations += gait.collocation.nlp.iterations;
    times_ms.push_back(1e3 * gait.collocation.nlp.wall_time);
  }
  std::sort(times_ms.begin(), times_ms.end());
  state.counters["median_ms"] = times_ms[times_ms.size() / 2];
  state.counters["max_ms"] = times_ms.back();
  state.counters["ipopt_iterations"] = static_cast<double>(iterations) / times_ms.size();
  state.counters["failures"] = failures;
  state.SetLabel("N = 21 per domain, seeds 1-10");
}
BENCHMARK(BM_AslipPeriodicGaitNlp)->Arg(30)->Arg(40)->Unit(benchmark::kMillisecond)->Iterations(20);

void BM_FootedHlipTransitionQp(benchmark::State& state) {
  const int dsp_intervals = static_cast<int>(state.range(0)), ssp_intervals = 20;
  const double mg = 76 * 9.81;
  FootedHlipTransitionData d;
  const int N = dsp_intervals + ssp_intervals + 1;
  d.node_times.resize(N);
  d.left_normal_force.resize(N);
  d.right_normal_force.resize(N);
  for (int k = 0; k < N; ++k) {
    const bool dsp = k <= dsp_intervals;
    const double s = dsp ? static_cast<double>(k) / dsp_intervals : static_cast<double>(k - dsp_intervals) / ssp_intervals;
    d.node_times(k) = dsp ? 0.6 * s : 0.6 + 0.4 * s;
    d.left_normal_force(k) = dsp ? 0.5 * mg * (1 + s) : mg;
    d.right_normal_force(k) = dsp ? 0.5 * mg * (1 - s) : 0.0;
  }
  for (int k = 0; k + 1 < N; ++k) d.single_support.push_back(k >= dsp_intervals);
  const HybridLinearInvertedPendulum h;
  const Eigen::Vector2d pre = h.P2PreImpactState(0.25);
  d.final_state = Eigen::Vector2d(d.left_foot_y + pre(0), pre(1));
  const FootedHlipTransitionPlanner planner;
  int failures = 0;
  for (auto _ : state) failures += planner.Solve(d).success() ? 0 : 1;
  state.counters["failures"] = failures;
  state.SetLabel(std::to_string(N) + " nodes (" + std::to_string(4 * N) + " variables)");
}
BENCHMARK(BM_FootedHlipTransitionQp)->Arg(30)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
