// hopping_benchmark: the closed-loop real-time factor of the default hop (examples/hopping: 3D Cassie, springs,
// achilles rods, HybridContactPlant, CLF-QP at 2 kHz, jump and landing NLPs), simulated from rest to t = 2.2 s (1.5 s
// settle, jump, 0.35 s flight, the first 60 ms of the landing), with three integrators:
//   scheme 0: CVODE BDF, rtol 1e-6, atol 1e-8 (the diagram's integrator before; a new finite-difference Jacobian at
//             each of the 4 400 restarts the 2 kHz zero-order hold forces)
//   scheme 1: ARKODE Dormand-Prince 5(4), same tolerances
//   scheme 2: HoppingSimulatorConfig(): Bogacki-Shampine 3(2), rtol 1e-5, atol 1e-7, restart_with_last_step
// Counters: realtime_factor (simulated s per wall s), steps, rhs_evals (with the Jacobians'), jacobian_rhs_evals,
// restarts, root_evals, air_time_s (all three agree to ~1e-4 s). One iteration each (a run takes 0.5-8 s):
//   ./hopping_benchmark
#include <chrono>
#include <memory>
#include <string>

#include <benchmark/benchmark.h>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "systems/rom/cassie_leg_stiffness.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kDuration = 2.2;  // [s] simulated

void HoppingClosedLoop(benchmark::State& state) {
  auto model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
  const SpringMassParams rom = CassieSpringMassParams(*model, LegStiffnessVariant::kIdentified);
  const LegLengthTable leg_length(*model);
  SimulatorConfig config = HoppingSimulatorConfig();
  if (state.range(0) < 2) {
    config = SimulatorConfig{};
    config.relative_tolerance = 1e-6;
    config.absolute_tolerance = 1e-8;
    config.scheme = state.range(0) == 0 ? IntegrationScheme::kBdf : IntegrationScheme::kExplicitRungeKutta;
  }
  SimulatorStatistics stats;
  double sim_s = 0, wall_s = 0, air_time = 0;
  for (auto _ : state) {
    state.PauseTiming();
    auto records = std::make_shared<std::vector<PlannerRecord>>();
    auto rest_height = std::make_shared<double>(0.0);
    HoppingDiagram d = BuildHoppingDiagram(model, leg_length,
                                           MakeSpringMassJumpPlanner(rom, SpringMassJumpParams{}, records, rest_height),
                                           MakeSpringMassLandingPlanner(rom, {}, records, rest_height));
    Simulator sim(*d.diagram, config);
    SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
    state.ResumeTiming();
    const auto t0 = std::chrono::steady_clock::now();
    const SimulatorStatus status = sim.AdvanceTo(kDuration);
    wall_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!status.ok()) state.SkipWithError(status.ToString().c_str());
    sim_s += sim.get_context().time();
    stats = sim.statistics();
    double liftoff = -1, touchdown = -1;
    for (const EventRecord& e : stats.events) {
      if (e.guard.rfind("liftoff_", 0) == 0 && liftoff < 0) liftoff = e.time;
      if (e.guard.rfind("touchdown_", 0) == 0 && touchdown < 0) touchdown = e.time;
    }
    air_time = touchdown - liftoff;
  }
  state.counters["realtime_factor"] = sim_s / wall_s;
  state.counters["steps"] = static_cast<double>(stats.steps);
  state.counters["rhs_evals"] = static_cast<double>(stats.rhs_evals);
  state.counters["jacobian_rhs_evals"] = static_cast<double>(stats.jacobian_rhs_evals);
  state.counters["restarts"] = static_cast<double>(stats.restarts);
  state.counters["root_evals"] = static_cast<double>(stats.root_evals);
  state.counters["air_time_s"] = air_time;
}
BENCHMARK(HoppingClosedLoop)
    ->ArgName("scheme")
    ->DenseRange(0, 2)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
