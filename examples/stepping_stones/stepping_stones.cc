// stepping_stones: AMBER walks over stepping stones with momentum regulation (stepping-stones paper, Algorithm 1).
// Event-accurate hybrid plant (or Bullet's physics world: --plant bullet), LIP momentum planner, vertical-COM MPC,
// pre-impact posture NLP, task-space QP (or CLF-QP: --controller clf-qp).
//
// Writes a CSV log (--log), a JSON summary (--summary) and PNG plots (--plots DIR): gait tiles over the stones,
// COM height over time, and the phase portrait (p_com^x, L_y) against the LIP orbit of E*.

#include <iostream>
#include <memory>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "diagrams/stepping_stones/stepping_stones_run.h"
#include "examples/stepping_stones/stepping_stones_options.h"
#include "examples/stepping_stones/stepping_stones_report.h"
#include "framework/interrupt.h"
#include "systems/visualization/animation.h"

using namespace rome;

int main(int argc, char** argv) {
#if defined(__GLIBC__)
  // Real-time practice: keep freed heap memory instead of returning it to the OS after every posture NLP (Ipopt and
  // MUMPS allocate and free their workspaces at each solve; giving the pages back and faulting them in again costs
  // about 10 % of the closed loop). The 1 kHz loop itself allocates nothing.
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
  mallopt(M_TOP_PAD, 64 << 20);
  mallopt(M_MMAP_THRESHOLD, 256 << 20);
#endif
  examples::CommandLine cli("stepping_stones",
                            "A planar biped (AMBER, planar Cassie) walks over stepping stones: LIP momentum "
                            "regulation, vertical-COM MPC, pre-impact posture NLP and a task-space QP "
                            "(stepping-stones paper, Algorithm 1), simulated event by event.");
  examples::DeclareSteppingStonesOptions(cli);
  try {
    if (!cli.Parse(argc, argv)) return 0;
    InstallInterruptHandlers();  // SIGINT/SIGTERM: the run stops, its outputs are written, exit 128 + signal
    const examples::SteppingStonesScenario scenario = examples::SteppingStonesScenarioFromCommandLine(cli);
    const SteppingStonesDiagramParams& params = scenario.params;
    SteppingStonesDiagram d = BuildSteppingStonesDiagram(scenario.terrain, params, scenario.controller, scenario.plant);
    std::unique_ptr<visualization::AnimationRecorder> animation;
    if (!cli.Get("animation").empty()) animation = std::make_unique<visualization::AnimationRecorder>(*d.model);
    Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
    SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
    sim.Initialize();
    std::cout << "stepping_stones: " << ToString(scenario.plant) << " plant, " << scenario.terrain.stones().size()
              << " stones (" << cli.Get("terrain") << "), E* = " << params.target_orbital_energy
              << ", epsilon = " << params.impact_fraction << ", " << scenario.steps << " steps\n";
    if (animation)
      sim.add_monitor(
          [&](const Context& c) {
            const LeafContext& plant_context = d.diagram->GetSubsystemContext(*d.plant, c);
            const int mode = d.plant->EvalTypedOutput<int>(plant_context, "mode");
            animation->Record(c.time(), d.plant->EvalOutput(plant_context, "q"), d.plant->mode_name(mode),
                              d.plant->EvalOutput(plant_context, "contact_forces"));
            return EventStatus::Succeeded();
          },
          "animation");
    double last_qp_status = 0;
    if (cli.GetFlag("report-qp-failures"))  // each change of the controller's QP status (0 = solved), through its
                                            // qp_status port
      sim.add_monitor(
          [&](const Context& c) {
            const double qp_status = d.EvalControllerOutput(c, "qp_status")[0];
            if (qp_status != last_qp_status)
              std::cerr << "t = " << c.time() << " s: controller qp_status " << qp_status << "\n";
            last_qp_status = qp_status;
            return EventStatus::Succeeded();
          },
          "qp_report");
    SteppingStonesRunOptions run;
    size_t reported = 0;
    run.progress = [&](const Simulator& s, const std::vector<StepRecord>& recs) {
      if (recs.size() == reported) return;
      std::cout << "  t = " << s.get_context().time() << " s: " << recs.size()
                << " steps, last l = " << recs.back().step_length_m << " m, foothold error "
                << recs.back().foothold_error_m * 100 << " cm\n";
      reported = recs.size();
    };
    const SteppingStonesResult result = RunSteppingStones(d, sim, run);
    const nlohmann::json summary = examples::SteppingStonesSummary(result, scenario, cli);
    if (!cli.Get("summary").empty() &&
        !examples::WriteOutputFile("stepping_stones", cli.Get("summary"), summary.dump(2) + "\n", "summary"))
      return 1;
    if (!cli.Get("log").empty())
      d.logger->WriteCsv(d.diagram->GetSubsystemContext(*d.logger, sim.get_context()), cli.Get("log"));
    if (animation) {
      std::vector<visualization::AnimationStone> stones;
      for (const auto& st : scenario.terrain.stones()) stones.push_back({st.x_center_m, st.top_height_m, st.length_m});
      std::string animation_error;
      if (!animation->WriteHtml(cli.Get("animation"), "ROME stepping stones, " + result.controller_kind, stones,
                                &animation_error))
        std::cerr << "warning: " << animation_error << "\n";
      else
        std::cout << "animation: " << cli.Get("animation") << " (" << animation->num_frames() << " frames)\n";
    }
    if (!cli.Get("plots").empty())
      examples::WriteSteppingStonesPlots(d, sim.get_context(), scenario,
                                         examples::FormatNumber(scenario.params.target_orbital_energy),
                                         cli.Get("plots"));
    return examples::PrintSteppingStonesReport(result, scenario);
  } catch (const std::exception& e) {
    std::cerr << "error: " << cli.NameTheOption(examples::OneLine(e.what()), examples::kSteppingStonesParameterOptions)
              << "\n";
    return 1;
  }
}
