// Solve times of the stepping-stones planning blocks (µs per call): the vertical-COM MPC, Eq. (28), for several
// horizons, cold and warm, with the contact constraint inactive and active; the momentum planner; the outputs.
#include <benchmark/benchmark.h>

#include "systems/planners/momentum_regulation_planner.h"
#include "systems/planners/output_trajectories.h"
#include "systems/planners/vertical_com_mpc.h"

namespace rome {
namespace {

// args: N, active (0/1), warm (0/1)
void BM_VerticalComMpcSolve(benchmark::State& state) {
  VerticalComMpcParams params;
  params.horizon_steps = static_cast<int>(state.range(0));
  const bool active = state.range(1) != 0, warm = state.range(2) != 0;
  params.qp.warm_start = warm;
  VerticalComMpc mpc(params);
  // Inactive: smooth plan. Active: ends in a free-fall arc (see vertical_com_mpc_test.cc).
  const double p0 = active ? 0.80 : 0.82, v0 = active ? 0.5 : -0.05, pf = active ? 0.735 : 0.80, vf = active ? -1.5 : 0.25;
  const double T = active ? 0.3 : 0.35;
  int k = 0;
  for (auto _ : state) {
    // Successive control ticks: the horizon shrinks by 1 ms.
    const QpStatus status = mpc.Solve(p0, v0, pf, vf, T - 1e-6 * (k++ % 100));
    benchmark::DoNotOptimize(status);
  }
  state.counters["qp_iterations"] = mpc.qp().iterations();
  state.SetLabel(std::string(active ? "contact active" : "contact inactive") + (warm ? ", warm" : ", cold"));
}
BENCHMARK(BM_VerticalComMpcSolve)
    ->ArgsProduct({{10, 20, 40}, {0, 1}, {0, 1}})
    ->Unit(benchmark::kMicrosecond);

void BM_MomentumRegulationPlan(benchmark::State& state) {
  const MomentumRegulationPlanner planner;
  MomentumRegulationInput in{.p_com_x = -0.05, .p_com_z = 0.82, .pdot_com_x = 1.0, .L_y = 0.8, .step_length = 0.5, .step_height = 0.1,
                             .pre_impact_com_height = 0.86};
  for (auto _ : state) benchmark::DoNotOptimize(planner.Plan(in));
  state.SetLabel("Eq. (25)-(27)");
}
BENCHMARK(BM_MomentumRegulationPlan)->Unit(benchmark::kMicrosecond);

void BM_OutputTrajectoriesEvaluate(benchmark::State& state) {
  StepOutputParameters step;
  step.p_com_x0 = -0.16;
  step.p_sw0_x = -0.32;
  const SteppingStonesOutputTrajectories outputs({}, {}, step);
  double x = -0.1;
  for (auto _ : state) {
    benchmark::DoNotOptimize(outputs.Evaluate(0.1, x, 0.9, 1.0, Eigen::Vector3d(0.8, 0, 0)));
    x = x > 0.2 ? -0.1 : x + 1e-3;
  }
}
BENCHMARK(BM_OutputTrajectoriesEvaluate)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
