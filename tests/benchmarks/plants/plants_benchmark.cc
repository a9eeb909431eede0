// plants_benchmark: one 1 ms step of AMBER's Bullet world (BulletWorldPlant) with both feet on the ground (µs per step;
// target <= 30 µs), and the same for 10 substeps. Each iteration runs the plant's periodic update from the same
// standing state (both feet touching, at rest, torques holding the nominal pose roughly), so it pays collision
// detection, two contact manifolds, four armature gears and the joint limits every time. The solver's warm start
// (warm_start_factor, default 0.98) then starts from the impulses of the same problem one step earlier: the best case.
// advance = 1 steps on from each result instead (a moving state), which is nearer to a closed loop; the counter
// mean_iterations is the solver's mean over the timed steps. The plant's defaults are substeps 1, iterations 100,
// residual 10, warm 98.
//   ./plants_benchmark --benchmark_filter='residual:10/warm:98' --benchmark_repetitions=5
#include <cmath>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/plants/bullet_world_plant.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

// advance = 1: each step starts from the previous one's state (a 0.2 s transient from rest under the constant torques,
// restarted every kRunSteps steps), so the solver's warm start sees a moving state, not the same problem again.
constexpr long kRunSteps = 200;

void BulletWorldStep(benchmark::State& state) {
  auto model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/amber/amber.rome.json"), {.euler_floating_base = true}));
  BulletWorldPlantParams params;
  params.substeps = static_cast<int>(state.range(0));
  params.solver_iterations = static_cast<int>(state.range(1));
  params.solver_residual_threshold = state.range(2) > 0 ? std::pow(10.0, -static_cast<double>(state.range(2))) : 0.0;
  params.warm_start_factor = static_cast<double>(state.range(3)) / 100.0;
  const bool advance = state.range(4) != 0;
  BulletWorldPlant plant("amber", model, ContactModeGraph::Hopping("left_foot", "right_foot"), Terrain::Flat(), params);
  auto context = plant.CreateDefaultLeafContext();
  plant.SetState(*context, model->q_nominal(), Eigen::VectorXd::Zero(model->nv()), "stance");
  context->FixInputPort(0, Eigen::VectorXd::Constant(model->nu(), 5.0));
  Eigen::VectorXd next = context->discrete_state();
  const auto& update = plant.periodic_events().at(0).update;
  for (int i = 0; i < 10; ++i) update(*context, &next);  // contacts established, solver warm
  const int fz_left = plant.forces_offset() + 2, fz_right = plant.forces_offset() + 5;
  long steps = 0, iterations = 0;
  for (auto _ : state) {
    if (advance && steps % kRunSteps == 0) {
      state.PauseTiming();
      plant.SetState(*context, model->q_nominal(), Eigen::VectorXd::Zero(model->nv()), "stance");
      state.ResumeTiming();
    }
    next = context->discrete_state();
    update(*context, &next);
    benchmark::DoNotOptimize(next.data());
    if (advance) context->get_mutable_discrete_state() = next;
    ++steps;
    iterations += plant.SolverIterationsUsed(*context);
  }
  state.counters["mean_iterations"] = static_cast<double>(iterations) / static_cast<double>(steps);
  state.counters["Fz_left_N"] = next[fz_left];
  state.counters["Fz_right_N"] = next[fz_right];
  state.counters["iterations_used"] = plant.SolverIterationsUsed(*context);
  state.counters["residual"] = plant.SolverResidual(*context);
  state.counters["gear_error_rad_s"] = plant.GearVelocityError(*context);
}
// residual: the solver's stopping threshold 10^-residual (m/s)² (0: none, always `iterations`); warm: the solver's
// warm-start factor in percent (0: cold start); advance: see kRunSteps.
BENCHMARK(BulletWorldStep)
    ->Args({1, 100, 0, 0, 0})
    ->Args({1, 30, 0, 0, 0})
    ->Args({1, 10, 0, 0, 0})
    ->Args({10, 100, 0, 0, 0})
    ->Args({1, 100, 14, 0, 0})
    ->Args({1, 100, 12, 0, 0})
    ->Args({1, 100, 10, 0, 0})
    ->Args({1, 100, 8, 0, 0})
    ->Args({1, 100, 10, 0, 1})
    ->Args({1, 100, 10, 85, 0})
    ->Args({1, 100, 10, 85, 1})
    ->Args({1, 100, 10, 90, 0})
    ->Args({1, 100, 10, 90, 1})
    ->Args({1, 100, 10, 95, 0})
    ->Args({1, 100, 10, 95, 1})
    ->Args({1, 100, 10, 98, 0})
    ->Args({1, 100, 10, 98, 1})
    ->Args({1, 100, 10, 99, 0})
    ->Args({1, 100, 10, 99, 1})
    ->Args({1, 100, 10, 100, 0})
    ->Args({1, 100, 10, 100, 1})
    ->ArgNames({"substeps", "iterations", "residual", "warm", "advance"})
    ->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
