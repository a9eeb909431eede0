// bouncing_ball: the hybrid simulator's hello world. A ball dropped from --height bounces with
// --restitution; every impact is found by CVODE's rootfinder and compared with the closed form.
//
// Writes a CSV log (--log), a JSON summary (--summary, with the effective "scenario": give it back as --scenario-file
// to run it again) and a PNG of height over time (--plots DIR).

#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "systems/visualization/animation.h"
#include "examples/common/cli.h"
#include "systems/visualization/plot.h"
#include "framework/simulator.h"
#include "framework/vector_logger.h"
#include "systems/classic/bouncing_ball.h"
#include "framework/interrupt.h"

using namespace rome;

namespace {

void DeclareOptions(examples::CommandLine& cli) {
  cli.Option("restitution", "0.8", "coefficient of restitution e in [0, 1]")
      .Option("height", "1.0", "initial height [m]")
      .Option("gravity", "9.81", "gravitational acceleration [m/s^2]")
      .Option("duration", "3.0", "simulated time [s]")
      .Option("rest-velocity", "0", "impact speed below which the ball comes to rest [m/s]; 0 = never (Zeno)")
      .Option("log", "bouncing_ball.csv", "CSV log file (time, height, velocity every 1 ms)")
      .Option("summary", "bouncing_ball.json", "JSON summary file")
      .Option("plots", "", "directory for PNG plots (empty: no plots)")
      .Option("animation", "", "FILE.html: a self-contained 3D animation of the run (three.js inlined; empty: none)")
      .ScenarioFile({"log", "summary", "plots", "animation"});
}

// Height over time with the simulated and the closed-form impact times, as DIR/bouncing_ball_height.png.
void WriteHeightPlot(const LogData& data, const std::vector<double>& impacts, const std::vector<double>& analytic,
                     const std::string& restitution, const std::string& plots) {
  std::filesystem::create_directories(plots);
  visualization::Series h{"height", {}, {}, "lines"},
      imp{"impacts (simulated)", impacts, std::vector<double>(impacts.size(), 0.0), "points pt 7"};
  visualization::Series ana{"impacts (closed form)", analytic, std::vector<double>(analytic.size(), 0.0),
                            "points pt 6 ps 2"};
  for (size_t k = 0; k < data.times.size(); ++k) {
    h.x.push_back(data.times[k]);
    h.y.push_back(data.samples[k][0]);
  }
  std::string err;
  if (!visualization::WritePlot({"Bouncing ball, e = " + restitution, "time [s]", "height [m]", {h, imp, ana}},
                                plots + "/bouncing_ball_height.png", &err))
    std::cerr << "warning: " << err << "\n";
}

}  // namespace

int main(int argc, char** argv) {
  examples::CommandLine cli("bouncing_ball",
                            "Drops a ball and finds every impact exactly with CVODE's rootfinder; compares the impact "
                            "times with the closed form.");
  DeclareOptions(cli);
  try {
    if (!cli.Parse(argc, argv)) return 0;
    InstallInterruptHandlers();  // SIGINT/SIGTERM: the run stops, its outputs are written, exit 128 + signal
    BouncingBallParams params;
    params.restitution = cli.GetDouble("restitution");
    params.initial_height = cli.GetDouble("height");
    params.gravity = cli.GetDouble("gravity");
    params.rest_velocity_cutoff = cli.GetDouble("rest-velocity");
    const double duration = cli.GetDouble("duration");
    // Bounded work (ours): the 1 kHz log holds at most 5e6 rows.
    if (!(duration > 0 && duration <= 5000))
      throw std::invalid_argument("bouncing_ball: --duration must be in (0, 5000] s, got " + cli.Get("duration"));
    // Output files are checked before the simulation, so a run is not lost to a typo.
    cli.CheckOutputs({"log", "summary", "animation"}, {"plots"});

    DiagramBuilder builder;
    auto* ball = builder.AddSystem(std::make_unique<BouncingBall>("ball", params));
    auto* logger = AddVectorLogger(builder, "logger", {{"ball", "state"}}, 1e-3);
    auto diagram = builder.Build("bouncing_ball");
    SimulatorConfig config;
    config.relative_tolerance = 1e-12;
    config.absolute_tolerance = 1e-12;
    Simulator sim(*diagram, config);

    std::cout << "bouncing_ball: e = " << params.restitution << ", h0 = " << params.initial_height
              << " m, g = " << params.gravity << " m/s^2, simulating " << duration << " s\n";
    const auto start = std::chrono::steady_clock::now();
    SimulatorStatus status;
    std::string animation_error;
    std::unique_ptr<visualization::AnimationRecorder> animation;
    if (!cli.Get("animation").empty()) {
      animation = std::make_unique<visualization::AnimationRecorder>(0.05);
      const LeafContext& ball_context = diagram->GetSubsystemContext(*ball, sim.get_context());
      sim.set_monitor([&, ball_context_ptr = &ball_context](const Context& c) {
        // The ball's centre is one radius above its contact point (the state's height).
        animation->RecordPoint(c.time(), Eigen::Vector3d(0, 0, ball_context_ptr->continuous_state()[0] + 0.05),
                               "flight");
        return EventStatus::Succeeded();
      });
    }
    const int chunks = 10;
    for (int k = 1; k <= chunks; ++k) {
      status = sim.AdvanceTo(duration * k / chunks);
      std::cout << "  t = " << sim.get_context().time() << " s, impacts so far: " << sim.statistics().guard_events
                << "\n";
      if (!status.ok()) break;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();

    std::vector<double> impacts;
    for (const auto& e : sim.statistics().events) impacts.push_back(e.time);
    const auto analytic = ball->AnalyticImpactTimes(static_cast<int>(impacts.size()));
    double max_err = 0;
    for (size_t i = 0; i < impacts.size() && i < analytic.size(); ++i)
      max_err = std::max(max_err, std::abs(impacts[i] - analytic[i]));

    const auto& log_ctx = diagram->GetSubsystemContext(*logger, sim.get_context());
    const std::string log_path = cli.Get("log");
    if (!log_path.empty()) logger->WriteCsv(log_ctx, log_path);

    nlohmann::json summary = {{"restitution", params.restitution},
                              {"height_m", params.initial_height},
                              {"gravity_mps2", params.gravity},
                              {"duration_s", duration},
                              {"status", status.ToString()},
                              {"status_kind", status.kind_name()},
                              {"ended_early", !status.ok()},
                              {"impact_times", impacts},
                              {"analytic_impact_times", analytic},
                              {"max_impact_time_error_s", max_err},
                              {"steps", sim.statistics().steps},
                              {"rhs_evals", sim.statistics().rhs_evals},
                              {"wall_time_s", wall},
                              {"scenario", nlohmann::json::parse(cli.ScenarioJson())}};
    const std::string summary_path = cli.Get("summary");
    if (!summary_path.empty() &&
        !examples::WriteOutputFile("bouncing_ball", summary_path, summary.dump(2) + "\n", "summary"))
      return 1;
    if (animation && !animation->WriteHtml(cli.Get("animation"), "ROME bouncing ball, e = " + cli.Get("restitution"),
                                           {}, &animation_error))
      std::cerr << "warning: " << animation_error << "\n";
    if (!cli.Get("plots").empty())
      WriteHeightPlot(logger->log(log_ctx), impacts, analytic, cli.Get("restitution"), cli.Get("plots"));
    std::cout << "\n"
              << status.ToString() << "\n"
              << impacts.size() << " impacts; largest impact-time error against the closed form: " << max_err << " s\n"
              << sim.statistics().steps << " integrator steps, " << sim.statistics().rhs_evals
              << " right-hand-side evaluations, " << wall * 1e3 << " ms wall time\n";
    if (status.kind() == SimulatorStatus::Kind::kInterrupted) {
      std::cout << "result: interrupted (" << status.ToString() << "); outputs written up to there\n";
      return 128 + InterruptSignal();
    }
    // The run is meant to reach its duration: a limit is success here; a failure (Zeno, non-finite state) is not.
    if (status.kind() == SimulatorStatus::Kind::kFailure) {
      std::cout << "result: failed run (" << status.ToString() << ")\n";
      return 3;
    }
    std::cout << "result: success (reached " << duration << " s)\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "error: " << examples::OneLine(e.what()) << "\n";
    return 1;
  }
}
