// The C++ half of python/benchmarks/cpp_diagram_speed.py: builds the same diagram of C++ blocks the Python script
// builds (a stepping LIP walking a periodic orbit, a spring-mass model settling on its leg, a 1 kHz zero-order hold
// of the spring-mass state and a 100 Hz logger) and prints the wall and process CPU times of Simulator::AdvanceTo over
// `seconds` simulated seconds (the smallest of `repeats` runs, and every run's wall and user CPU time), and the final
// state (so that the two halves can be compared).
//
// usage: cpp_diagram_speed [seconds=50] [repeats=7]      exit 0, or 1 on bad arguments
#include <algorithm>
#include <chrono>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <memory>
#include <string>

#include <sys/resource.h>

#include "framework/diagram.h"
#include "framework/primitives.h"
#include "framework/simulator.h"
#include "framework/vector_logger.h"
#include "systems/rom/spring_mass_system.h"
#include "systems/rom/stepping_linear_inverted_pendulum.h"

namespace {

/// User CPU time of this process so far [s] (getrusage; the Python half reads the same counter).
double UserCpuSeconds() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec) + 1e-6 * static_cast<double>(usage.ru_utime.tv_usec);
}

struct BenchmarkDiagram {
  std::unique_ptr<rome::Diagram> diagram;
  const rome::System* lip = nullptr;
  const rome::System* spring_mass = nullptr;
};

BenchmarkDiagram BuildBenchmarkDiagram() {
  BenchmarkDiagram d;
  rome::DiagramBuilder builder;
  rome::SteppingLinearInvertedPendulumParams lip;
  lip.impact_fraction = 0.5;  // x- = l/2, x+ = -l/2: with u = h = 0 a periodic orbit
  d.lip = builder.AddSystem(std::make_unique<rome::SteppingLinearInvertedPendulum>("stepping_lip", lip));
  builder.AddSystem(std::make_unique<rome::ConstantVectorSource>("step", Eigen::Vector2d(0.4, 0.0)));
  builder.AddSystem(std::make_unique<rome::ConstantVectorSource>("impact_velocity", Eigen::VectorXd::Zero(1)));
  d.spring_mass = builder.AddSystem(std::make_unique<rome::SpringMassSystem>("spring_mass"));
  builder.AddSystem(std::make_unique<rome::ConstantVectorSource>("leg_acceleration", Eigen::VectorXd::Zero(1)));
  builder.AddSystem(std::make_unique<rome::ZeroOrderHold>("zoh", 1e-3, 4));
  builder.Connect("step", "y", "stepping_lip", "step");
  builder.Connect("impact_velocity", "y", "stepping_lip", "impact_vertical_velocity");
  builder.Connect("leg_acceleration", "y", "spring_mass", "leg_length_acceleration");
  builder.Connect("spring_mass", "state", "zoh", "u");
  rome::AddVectorLogger(builder, "logger", {{"stepping_lip", "state"}, {"zoh", "y"}}, 0.01);
  d.diagram = builder.Build("benchmark");
  return d;
}

}  // namespace

int main(int argc, char** argv) {
  const double seconds = argc > 1 ? std::atof(argv[1]) : 50.0;
  const int repeats = argc > 2 ? std::atoi(argv[2]) : 7;
  if (!(seconds > 0 && seconds <= 1e4) || repeats < 1 || repeats > 100) {
    std::fprintf(stderr, "cpp_diagram_speed: seconds must be in (0, 1e4] and repeats in [1, 100]\n");
    return 1;
  }
  double best = std::numeric_limits<double>::infinity(), best_cpu = best;
  std::string wall_runs, user_runs;  // every run's wall and user CPU time [s], for medians
  Eigen::VectorXd lip_state, spring_mass_state;
  for (int r = 0; r < repeats; ++r) {
    const BenchmarkDiagram d = BuildBenchmarkDiagram();
    rome::Simulator simulator(*d.diagram);
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    const double user_start = UserCpuSeconds();
    const rome::SimulatorStatus status = simulator.AdvanceTo(seconds);
    user_runs += ' ';
    user_runs += std::to_string(UserCpuSeconds() - user_start);
    best_cpu = std::min(best_cpu, static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC);
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    best = std::min(best, wall);
    wall_runs += ' ';
    wall_runs += std::to_string(wall);
    if (!status.ok()) {
      std::fprintf(stderr, "cpp_diagram_speed: %s\n", status.ToString().c_str());
      return 3;
    }
    lip_state = d.diagram->EvalSubsystemOutput(*d.lip, "state", simulator.get_context());
    spring_mass_state = d.diagram->EvalSubsystemOutput(*d.spring_mass, "state", simulator.get_context());
  }
  std::printf("wall_s %.6f\n", best);
  std::printf("cpu_s %.6f\n", best_cpu);
  std::printf("wall_runs_s%s\n", wall_runs.c_str());
  std::printf("user_runs_s%s\n", user_runs.c_str());
  std::printf("stepping_lip %.12g %.12g\n", lip_state[0], lip_state[1]);
  std::printf("spring_mass %.12g %.12g %.12g %.12g\n", spring_mass_state[0], spring_mass_state[1], spring_mass_state[2],
              spring_mass_state[3]);
  return 0;
}
