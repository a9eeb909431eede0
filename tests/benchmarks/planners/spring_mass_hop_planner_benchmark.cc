// Solve times of the hopping paper's spring-mass NLPs (Ipopt, Hermite–Simpson collocation, AutoDiff derivatives):
// the jump NLP, Eq. (14)-(15), from the standing state, and the landing NLP, Eq. (16) + rest conditions, cold from
// the predicted touchdown and warm-started from a perturbed "measured" post-impact state. Both leg-stiffness
// variants (arg 0: published, 1: identified on robots/cassie). Target (issue 12): <= 200 ms each; the paper: ~2 s.
#include <benchmark/benchmark.h>

#include <string>

#include "systems/planners/spring_mass_hop_planner.h"
#include "systems/rom/cassie_leg_stiffness.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kStandingLegLength = 0.85;  // [m] ≈ L(q_knee = −1.2 rad)

SpringMassParams Rom(bool identified) {
  SpringMassParams p;
  if (identified) {
    static const MultibodyModel model =
        MultibodyModel::Load(rome::test::SourcePath("robots/cassie/cassie.urdf"), "", {.euler_floating_base = true});
    static const SpringMassParams identified = CassieSpringMassParams(model, LegStiffnessVariant::kIdentified);
    p = identified;
  }
  return p;
}

void Report(benchmark::State& state, const SpringMassPlan& plan) {
  state.counters["iterations"] = plan.iterations;
  state.counters["violation"] = plan.max_violation;
  state.counters["duration_s"] = plan.duration;
  if (!plan.success()) state.SkipWithError(plan.message.c_str());
}

void BM_SpringMassJumpNlp(benchmark::State& state) {
  const bool identified = state.range(0) != 0;
  const SpringMassParams rom = Rom(identified);
  const SpringMassJumpPlanner planner(rom, {});  // default apex rise: 0.423 s ROM air time
  const Eigen::Vector4d z0 = SpringMassModel(rom).StaticState(kStandingLegLength);
  SpringMassPlan plan;
  for (auto _ : state) {
    plan = planner.Solve(z0);
    benchmark::DoNotOptimize(plan.cost);
  }
  Report(state, plan);
  state.SetLabel(identified ? "identified K(L)" : "published K(L)");
}
BENCHMARK(BM_SpringMassJumpNlp)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// args: variant, warm (0: cold Solve from the predicted touchdown, 1: Resolve from the measured state)
void BM_SpringMassLandingNlp(benchmark::State& state) {
  const bool identified = state.range(0) != 0, warm = state.range(1) != 0;
  const SpringMassParams rom = Rom(identified);
  const SpringMassModel model(rom);
  const Eigen::Vector4d z_stand = model.StaticState(kStandingLegLength);
  const SpringMassPlan jump = SpringMassJumpPlanner(rom, {}).Solve(z_stand);
  const Eigen::Vector4d predicted = PredictFlight(model, jump.FinalState()).touchdown_state;
  Eigen::Vector4d measured = predicted;
  measured(1) *= 0.9;
  measured(0) -= 0.01;
  SpringMassLandingParams lp;
  lp.rest_height = z_stand(0);
  SpringMassPlan plan;
  for (auto _ : state) {
    state.PauseTiming();
    SpringMassLandingPlanner planner(rom, lp);
    if (warm) plan = planner.Solve(predicted);  // at lift-off
    state.ResumeTiming();
    plan = warm ? planner.Resolve(measured) : planner.Solve(predicted);
    benchmark::DoNotOptimize(plan.cost);
  }
  Report(state, plan);
  state.SetLabel(std::string(identified ? "identified K(L)" : "published K(L)") +
                 (warm ? ", warm re-solve at touchdown" : ", cold at lift-off"));
}
BENCHMARK(BM_SpringMassLandingNlp)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
}  // namespace rome

BENCHMARK_MAIN();
