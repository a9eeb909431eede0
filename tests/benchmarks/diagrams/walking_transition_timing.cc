// walking_transition_timing: the transition NLP's solve times (Eq. (9)-(10), as the walking diagram poses it) over
// the gait pairs the walking tests change between and 20 random pairs (Python random.Random(39): for each pair, gait A
// then gait B, each coordinate uniform in the range in the order L, T_SSP, T_DSP, W, rounded to 0.01), planned
// as BuildGaitChangePlan does (exoskeleton sole, NLP seed 1, 2 steps per gait). Every transition NLP a plan solves is
// timed (StandToWalkParams::on_transition_nlp: standing, the start gait's change, the change and every chain link,
// failed ones too). Without --cache no plan cache is used (every NLP solved); with --cache DIR the plans use it (a
// second run shows what a cache, failures included, saves). Prints one line per pair and the distribution (median,
// 90th percentile, max) of all transition NLPs and of the changes' chain planning.
// With --check the plans refuse transitions beyond the torque limits as the walking example does
// (StandToWalkParams::change_check). Wall and CPU times (the solving thread's) are both printed.
//   ./walking_transition_timing [--cache DIR] [--pairs N] [--check]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_robot_check.h"
#include "tests/common/source_path.h"

namespace {

using rome::WalkingGait;

double ThreadCpuSeconds() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(q * static_cast<double>(v.size())))];
}

struct Pair {
  WalkingGait a, b;
};

// The walking tests' changes (walking_diagram_test, walking_gait_change_plan_test, issue 39's pairs) and the random
// pairs of the top of this file.
const std::vector<Pair>& Pairs() {
  static const std::vector<Pair> pairs = {
      {{0.30, 0.40, 0.10, 0.25}, {0.40, 0.40, 0.10, 0.25}},
      {{0.30, 0.40, 0.10, 0.25}, {0.30, 0.40, 0.10, 0.20}},
      {{0.30, 0.40, 0.10, 0.25}, {0.40, 0.40, 0.10, 0.28}},
      {{0.30, 0.40, 0.10, 0.25}, {0.36, 0.42, 0.11, 0.27}},
      {{0.36, 0.42, 0.11, 0.27}, {0.33, 0.38, 0.09, 0.23}},
      {{0.33, 0.38, 0.09, 0.23}, {0.25, 0.45, 0.12, 0.22}},
      {{0.25, 0.38, 0.09, 0.27}, {0.42, 0.42, 0.11, 0.24}},
      {{0.22, 0.48, 0.14, 0.21}, {0.38, 0.40, 0.10, 0.28}},
      {{0.25, 0.38, 0.09, 0.27}, {0.42, 0.42, 0.11, 0.27}},
      {{0.22, 0.48, 0.14, 0.21}, {0.38, 0.40, 0.10, 0.21}},
      // random.Random(39)
      {{0.25, 0.41, 0.09, 0.24}, {0.34, 0.45, 0.10, 0.24}},
      {{0.24, 0.47, 0.10, 0.29}, {0.22, 0.35, 0.11, 0.24}},
      {{0.39, 0.48, 0.12, 0.23}, {0.38, 0.42, 0.10, 0.23}},
      {{0.20, 0.46, 0.08, 0.22}, {0.35, 0.44, 0.12, 0.26}},
      {{0.40, 0.49, 0.15, 0.24}, {0.29, 0.37, 0.11, 0.22}},
      {{0.43, 0.46, 0.10, 0.27}, {0.37, 0.36, 0.14, 0.27}},
      {{0.32, 0.49, 0.09, 0.20}, {0.38, 0.45, 0.08, 0.26}},
      {{0.35, 0.41, 0.09, 0.28}, {0.42, 0.43, 0.10, 0.25}},
      {{0.36, 0.43, 0.14, 0.22}, {0.42, 0.46, 0.09, 0.21}},
      {{0.39, 0.40, 0.14, 0.29}, {0.27, 0.46, 0.10, 0.25}},
      {{0.25, 0.47, 0.09, 0.29}, {0.29, 0.39, 0.08, 0.22}},
      {{0.22, 0.38, 0.15, 0.27}, {0.23, 0.37, 0.11, 0.29}},
      {{0.31, 0.40, 0.13, 0.21}, {0.25, 0.43, 0.14, 0.25}},
      {{0.27, 0.43, 0.14, 0.22}, {0.24, 0.42, 0.10, 0.21}},
      {{0.25, 0.48, 0.09, 0.23}, {0.44, 0.41, 0.15, 0.28}},
      {{0.32, 0.42, 0.08, 0.24}, {0.33, 0.50, 0.09, 0.28}},
      {{0.44, 0.48, 0.12, 0.27}, {0.29, 0.35, 0.11, 0.27}},
      {{0.22, 0.42, 0.08, 0.21}, {0.41, 0.36, 0.12, 0.23}},
      {{0.27, 0.49, 0.11, 0.26}, {0.42, 0.45, 0.09, 0.23}},
      {{0.41, 0.40, 0.09, 0.23}, {0.27, 0.42, 0.09, 0.28}},
  };
  return pairs;
}

}  // namespace

int main(int argc, char** argv) {
  std::string cache_dir;
  size_t max_pairs = Pairs().size();
  bool check = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--cache") == 0 && i + 1 < argc) {
      cache_dir = argv[++i];
    } else if (std::strcmp(argv[i], "--check") == 0) {
      check = true;
    } else if (std::strcmp(argv[i], "--pairs") == 0 && i + 1 < argc) {
      max_pairs = static_cast<size_t>(std::atoi(argv[++i]));
    } else {
      std::fprintf(stderr,
                   "walking_transition_timing: unknown argument '%s' (expected --cache DIR, --pairs N, --check)\n",
                   argv[i]);
      return 1;
    }
  }
  const auto shared_model = std::make_shared<const rome::MultibodyModel>(rome::MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/exoskeleton/exoskeleton.rome.json"), {.euler_floating_base = true}));
  const rome::MultibodyModel& model = *shared_model;
  std::unique_ptr<rome::PlanCache> cache;
  if (!cache_dir.empty()) cache = std::make_unique<rome::PlanCache>(cache_dir);
  std::vector<double> all_ms, all_cpu_ms, chain_s, plan_s, plan_cpu_s;
  int failed_nlps = 0;
  for (size_t i = 0; i < std::min(max_pairs, Pairs().size()); ++i) {
    const Pair& p = Pairs()[i];
    rome::StandToWalkParams stand;
    stand.sole = rome::SoleOf(model, "left_foot");
    if (check) stand.change_check = rome::WalkingChangeFeasibilityCheck(shared_model, rome::WalkingDiagramParams{});
    std::vector<double> ms;
    std::string each;  // every NLP: time [ms] / iterations
    int failed = 0;
    stand.on_transition_nlp = [&](const rome::WalkingNlpReport& r) {
      ms.push_back(1e3 * r.solve_s);
      all_cpu_ms.push_back(1e3 * r.cpu_s);
      failed += r.violation > 1e-6 ? 1 : 0;
      // Appended piece by piece: GCC 12 warns falsely (-Wstringop-overflow) on " " + string with the PCH.
      each += ' ';
      each += std::to_string(static_cast<int>(1e3 * r.solve_s));
      each += '/';
      each += std::to_string(r.iterations);
    };
    rome::WalkingPlanReport report;
    const auto t0 = std::chrono::steady_clock::now();
    const double cpu0 = ThreadCpuSeconds();
    std::string outcome = "planned";
    try {
      rome::BuildGaitChangePlan(p.a, p.b, 2, 1, cache.get(), &report, stand, 2);
    } catch (const std::exception& e) { outcome = std::string("no plan: ") + std::string(e.what()).substr(0, 120); }
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const double cpu = ThreadCpuSeconds() - cpu0;
    std::printf(
        "(%g %g %g %g) -> (%g %g %g %g): %zu transition NLPs, median %.0f ms, max %.0f ms; chain %.2f s (%d "
        "tried, %d failed, %zu refused by the check); plan %.2f s (CPU %.2f s); %s\n",
        p.a.step_length_m, p.a.ssp_duration_s, p.a.dsp_duration_s, p.a.step_width_m, p.b.step_length_m,
        p.b.ssp_duration_s, p.b.dsp_duration_s, p.b.step_width_m, ms.size(), Quantile(ms, 0.5), Quantile(ms, 1.0),
        report.chain_planning_s, report.chain_transitions_tried, report.chain_transitions_failed,
        report.refused_changes.size(), total, cpu, outcome.c_str());
    std::printf("  NLPs (ms/iterations):%s\n", each.c_str());
    std::fflush(stdout);
    all_ms.insert(all_ms.end(), ms.begin(), ms.end());
    chain_s.push_back(report.chain_planning_s);
    plan_s.push_back(total);
    plan_cpu_s.push_back(cpu);
    failed_nlps += failed;
  }
  std::printf(
      "all %zu transition NLPs (%d with a constraint violation > 1e-6): median %.0f ms, 90th percentile %.0f ms, max "
      "%.0f ms\nchain planning per pair: median %.2f s, max %.2f s; whole plan per pair: median %.2f s, max %.2f s\n",
      all_ms.size(), failed_nlps, Quantile(all_ms, 0.5), Quantile(all_ms, 0.9), Quantile(all_ms, 1.0),
      Quantile(chain_s, 0.5), Quantile(chain_s, 1.0), Quantile(plan_s, 0.5), Quantile(plan_s, 1.0));
  std::printf(
      "CPU time (this thread): transition NLPs median %.0f ms, 90th percentile %.0f ms, max %.0f ms; whole plan per "
      "pair median %.2f s, max %.2f s\n",
      Quantile(all_cpu_ms, 0.5), Quantile(all_cpu_ms, 0.9), Quantile(all_cpu_ms, 1.0), Quantile(plan_cpu_s, 0.5),
      Quantile(plan_cpu_s, 1.0));
  return 0;
}
