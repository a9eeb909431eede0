// walking_plan_benchmark: the walking paper's ROM NLPs as the walking diagram poses them (examples/walking's default
// plans, StandToWalkParams defaults with the exoskeleton's sole, NLP seed 1, no plan cache), so the figures are the
// ones a user waits for:
//   arg 0: BuildStandToWalkPlan, gait A: the periodic aSLIP NLP (Eq. (4)-(5)) and, from standing side by side, the
//          start gait's periodic NLP, the standing transition NLP into it (Eq. (9)-(10), with the lateral rows and the
//          real sole) and its change into gait A, each with its footed H-LIP QP;
//   arg 1: BuildGaitChangePlan A -> B: also gait B's periodic NLP and the A -> B transition (force bound 1.6 m g).
// Counters: each NLP's median Ipopt wall time [ms] and its iterations, over the benchmark's iterations (3).
//   ./walking_plan_benchmark
#include <algorithm>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "diagrams/walking/walking_diagram.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0.0 : v[v.size() / 2];
}

void WalkingPlanNlps(benchmark::State& state) {
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/exoskeleton/exoskeleton.rome.json"), {.euler_floating_base = true});
  StandToWalkParams stand;
  stand.sole = SoleOf(model, "left_foot");
  const WalkingGait a{}, b{.step_length_m = 0.40};
  const bool change = state.range(0) == 1;
  std::vector<double> periodic, transition, periodic_b, transition_b, periodic_start, transition_start;
  WalkingPlanReport report;
  for (auto _ : state) {
    report = WalkingPlanReport{};
    const WalkingPlan plan = change ? BuildGaitChangePlan(a, b, 10, 1, nullptr, &report, stand, 12)
                                    : BuildStandToWalkPlan(a, 12, 1, nullptr, &report, stand);
    benchmark::DoNotOptimize(plan.end_time());
    periodic.push_back(1e3 * report.periodic.solve_s);
    transition.push_back(1e3 * report.transition.solve_s);
    periodic_b.push_back(1e3 * report.periodic_b.solve_s);
    transition_b.push_back(1e3 * report.transition_b.solve_s);
    periodic_start.push_back(1e3 * report.periodic_start.solve_s);
    transition_start.push_back(1e3 * report.transition_start.solve_s);
  }
  state.counters["periodic_a_ms"] = Median(periodic);
  state.counters["periodic_a_iter"] = report.periodic.iterations;
  state.counters["transition_ms"] = Median(transition);
  state.counters["transition_iter"] = report.transition.iterations;
  if (report.start_gait_used) {
    state.counters["periodic_start_ms"] = Median(periodic_start);
    state.counters["transition_start_to_a_ms"] = Median(transition_start);
    state.counters["transition_start_to_a_iter"] = report.transition_start.iterations;
  }
  if (change) {
    state.counters["periodic_b_ms"] = Median(periodic_b);
    state.counters["transition_a_b_ms"] = Median(transition_b);
    state.counters["transition_a_b_iter"] = report.transition_b.iterations;
  }
  state.SetLabel(change ? "gait change A -> B" : "stand to walk, gait A");
}
BENCHMARK(WalkingPlanNlps)->Arg(0)->Arg(1)->Iterations(3)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
