// Solve times of the stepping-stones planning blocks (µs per call): the vertical-COM MPC, Eq. (28), for several
// horizons, cold and warm, with the contact constraint inactive and active; the momentum planner; the outputs; the
// pre-impact posture NLP, Eq. (21), with Ipopt (once per step in the closed loop).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <string>

#include "systems/planners/momentum_regulation_planner.h"
#include "systems/planners/output_trajectories.h"
#include "systems/planners/vertical_com_mpc.h"
#include "systems/posture/pre_impact_posture_optimizer.h"
#include "tests/common/source_path.h"

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
  const double p0 = active ? 0.80 : 0.82, v0 = active ? 0.5 : -0.05, pf = active ? 0.735 : 0.80,
               vf = active ? -1.5 : 0.25;
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
BENCHMARK(BM_VerticalComMpcSolve)->ArgsProduct({{10, 20, 40}, {0, 1}, {0, 1}})->Unit(benchmark::kMicrosecond);

void BM_MomentumRegulationPlan(benchmark::State& state) {
  const MomentumRegulationPlanner planner;
  MomentumRegulationInput in{.p_com_x = -0.05,
                             .p_com_z = 0.82,
                             .pdot_com_x = 1.0,
                             .L_y = 0.8,
                             .step_length = 0.5,
                             .step_height = 0.1,
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

// One random-stone-like sequence of steps, solved one after the other (warm start from the previous solution for the
// same stance, as in the closed loop).
void BM_PreImpactPostureSolve(benchmark::State& state) {
  auto model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/amber/amber.rome.json"), {.euler_floating_base = true}));
  PreImpactPostureOptimizer optimizer(model);
  const double steps[][2] = {{0.4, 0.0}, {0.35, -0.1}, {0.5, 0.15}, {0.3, -0.2}, {0.6, 0.05}, {0.25, 0.2}};
  int k = 0;
  long iterations = 0, solves = 0;
  for (auto _ : state) {
    PreImpactPostureRequest r;
    r.stance_contact = k % 2 == 0 ? "left_foot" : "right_foot";
    r.swing_contact = k % 2 == 0 ? "right_foot" : "left_foot";
    r.step_length_m = steps[k % 6][0];
    r.step_height_m = steps[k % 6][1];
    r.com_height_m = 0.8 + std::min(r.step_height_m, 0.0);
    const PreImpactPosture p = optimizer.Solve(r);
    if (!p.success) state.SkipWithError(p.message.c_str());
    iterations += p.iterations;
    ++solves;
    ++k;
  }
  state.counters["ipopt_iterations"] = static_cast<double>(iterations) / static_cast<double>(solves);
  state.SetLabel("AMBER, Eq. (21), warm-started");
}
BENCHMARK(BM_PreImpactPostureSolve)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
