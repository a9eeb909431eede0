// Solve times of the walking paper's ROM planners (offline, once per gait or transition): the periodic point-foot
// aSLIP NLP, Eq. (4)-(5), from the random initial guesses of seeds 1-10 (Ipopt, L-BFGS; the paper reports 1-2 s in
// MATLAB, our target is ≤ 100 ms median), the transitional footed-aSLIP NLP, Eq. (9)-(10) (target ≤ 300 ms), and the
// footed H-LIP transition QP, Eq. (11)-(15).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>
#include <string>

#include "systems/planners/aslip_periodic_gait_planner.h"
#include "systems/planners/aslip_transition_planner.h"
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

// arg 0: standing → gait A (straight-line guess); arg 1: gait A → gait B (guess: A's DSP, B's SSP).
void BM_AslipTransitionNlp(benchmark::State& state) {
  AslipPeriodicGaitParams gait_a, gait_b;
  gait_b.step_length = 0.40;
  const AslipPeriodicGait a = AslipPeriodicGaitPlanner(gait_a).Solve(1);
  const AslipPeriodicGait b = AslipPeriodicGaitPlanner(gait_b).Solve(1);
  AslipTransitionParams params;
  params.bounds = gait_a;
  const AslipTransitionPlanner planner(params);
  AslipTransitionData d;
  const int N = gait_a.nodes_per_domain;
  if (state.range(0) == 0) {
    d.initial_state = AslipTransitionPlanner::StandingState(gait_a.aslip, 0.9);
    d.final_state = a.collocation.phases[0].states.col(N - 1);
    d.lifting_leg = 1;
  } else {
    d.initial_state = a.collocation.phases[1].states.col(0);
    d.right_foot_x = gait_a.step_length;
    d.lifting_leg = 0;
    const Eigen::VectorXd pre = b.collocation.phases[0].states.col(N - 1);
    d.final_state << pre(0) + gait_a.step_length, pre(1), pre(2), pre(3), pre(5), pre(4), pre(7), pre(6);
    d.dsp_state_guess = a.collocation.phases[1].states;
    d.dsp_duration_guess = gait_a.dsp_duration;
    d.ssp_state_guess = b.collocation.phases[0].states;
    d.ssp_state_guess.row(0).array() += gait_a.step_length;
    d.ssp_state_guess.row(4).swap(d.ssp_state_guess.row(5));
    d.ssp_state_guess.row(6).swap(d.ssp_state_guess.row(7));
    d.ssp_duration_guess = gait_b.ssp_duration;
  }
  int failures = 0, iterations = 0;
  std::vector<double> times_ms;
  for (auto _ : state) {
    const AslipTransition t = planner.Solve(d);
    failures += t.success() ? 0 : 1;
    iterations = t.collocation.nlp.iterations;
    times_ms.push_back(1e3 * t.collocation.nlp.wall_time);
  }
  std::sort(times_ms.begin(), times_ms.end());
  state.counters["median_ms"] = times_ms[times_ms.size() / 2];
  state.counters["ipopt_iterations"] = iterations;
  state.counters["failures"] = failures;
  state.SetLabel(state.range(0) == 0 ? "standing -> gait A" : "gait A -> gait B");
}
BENCHMARK(BM_AslipTransitionNlp)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->Iterations(5);

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
    const double s =
        dsp ? static_cast<double>(k) / dsp_intervals : static_cast<double>(k - dsp_intervals) / ssp_intervals;
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
