// stepping_stones_benchmark: real-time factor of the whole stepping-stones closed loop (event-accurate plant, MPC and
// task-space QP at 1 kHz, posture NLP at every impact) on AMBER, 30 random stones (seed 7, the demo's course).
// Prints the median and range of `runs` runs for the current loop (unilateral contact with lift-off and slip guards;
// the controller and the MPC re-solve at every touchdown) next to the previous loop (welded stance contacts, 1 kHz
// zero-order hold only), both measured in this run, interleaved so that a slow spell of the machine hits both alike.
//   usage: stepping_stones_benchmark [runs (default 5)]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "diagrams/stepping_stones/stepping_stones_diagram.h"

using namespace rome;

namespace {

struct Run {
  double sim_time_s = 0, wall_s = 0;
  int steps = 0;
  std::string status;
};

Run Once(bool resolve_at_events) {
  RandomSteppingStonesParams stones;
  stones.num_stones = 32;
  stones.seed = 7;
  const Terrain terrain = RandomSteppingStones(stones);
  SteppingStonesDiagramParams params;
  params.supervisor.max_steps = 30;
  params.controller.resolve_at_events = params.mpc.resolve_at_events = resolve_at_events;
  // The previous loop: welded stance contacts (no lift-off or slip guards) and the 1 kHz hold only.
  params.plant.unilateral_contact = resolve_at_events;
  SteppingStonesDiagram d = BuildSteppingStonesDiagram(terrain, params);
  Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
  SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
  sim.Initialize();
  const auto start = std::chrono::steady_clock::now();
  const SimulatorStatus status = sim.AdvanceTo(92.0);
  Run r;
  r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.sim_time_s = sim.get_context().time();
  r.steps =
      static_cast<int>(d.supervisor->steps(d.diagram->GetSubsystemContext(*d.supervisor, sim.get_context())).size());
  r.status = status.kind_name();
  return r;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

}  // namespace

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  mallopt(M_TRIM_THRESHOLD, 256 << 20);  // as the example: keep Ipopt's freed heap (see examples/stepping_stones)
  mallopt(M_TOP_PAD, 64 << 20);
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
#endif
  const int runs = argc > 1 ? std::atoi(argv[1]) : 5;
  if (runs < 1 || runs > 100) {
    std::fprintf(stderr, "stepping_stones_benchmark: runs must be in 1..100, got '%s'\n", argv[1]);
    return 1;
  }
  std::vector<double> current, previous;
  Run last_current, last_previous;
  for (int k = 0; k < runs; ++k) {
    last_current = Once(true);
    current.push_back(last_current.sim_time_s / last_current.wall_s);
    last_previous = Once(false);
    previous.push_back(last_previous.sim_time_s / last_previous.wall_s);
  }
  std::printf("stepping-stones closed loop, AMBER, 30 random stones (seed 7), %d runs each, interleaved:\n", runs);
  std::printf("  %-52s %6.1fx real time (median; %.1f-%.1fx), %d steps, %.2f s simulated, %s\n",
              "current (unilateral contact, re-solve at touchdowns):", Median(current),
              *std::min_element(current.begin(), current.end()), *std::max_element(current.begin(), current.end()),
              last_current.steps, last_current.sim_time_s, last_current.status.c_str());
  std::printf("  %-52s %6.1fx real time (median; %.1f-%.1fx), %d steps, %.2f s simulated, %s\n",
              "previous (welded contacts, 1 kHz hold only):", Median(previous),
              *std::min_element(previous.begin(), previous.end()), *std::max_element(previous.begin(), previous.end()),
              last_previous.steps, last_previous.sim_time_s, last_previous.status.c_str());
  return 0;
}
