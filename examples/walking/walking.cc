// walking: the 12-joint exoskeleton walks (walking paper: aSLIP + H-LIP planning composed into a 3D COM reference,
// CLF-QP with force matching). --scenario stand-to-walk (standing -> transition -> gait A), gait-change (standing -> A
// -> transition -> B; with no direct transition plan, through intermediate gaits of a gait graph), gait-sequence
// (--gaits "A;B;C": as gait-change, one change after another) or periodic (started on gait A's orbit). The ROM plans
// are built offline (NLPs cached in
// --cache), the COM reference is corrected for the legs' angular momentum (CompensateCentroidalMomentum), then the
// diagram of diagrams/walking runs (RunWalking judges it). Writes a CSV log (--log), a JSON summary (--summary, with
// the effective scenario under "scenario": pass it back as --scenario-file to run it again), PNG plots (--plots DIR:
// the paper's Fig. 2 S2/L2 and 3 S2/L2 from this run's plans, COM position and velocity desired vs actual, per-foot
// normal force in its band, gait tiles) and an HTML animation (--animation). Exit 0 success, 3 failed run (fell,
// slipped, a planner failed), 1 bad input.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <vector>

#include "diagrams/walking/walking_diagram.h"
#include "diagrams/walking/walking_robot_check.h"
#include "diagrams/walking/walking_run.h"
#include "diagrams/walking/walking_stop_plan.h"
#include "examples/common/cli.h"
#include "examples/common/perturbation_options.h"
#include "examples/walking/walking_options.h"
#include "examples/walking/walking_outputs.h"
#include "examples/walking/walking_report.h"
#include "framework/interrupt.h"
#include "framework/text.h"

using namespace rome;

namespace {

// The plan's feasibility check before simulating (--feasibility): -1 to go on, else the program's exit code.
int CheckFeasibility(const MultibodyModel& model, const WalkingDiagram& d, const examples::WalkingOptions& o,
                     double t_stop) {
  if (o.feasibility == "off") return -1;
  WalkingFeasibilityParams fp;
  fp.enforce_sole_wrench = fp.enforce_joint_limits = o.feasibility == "strict";
  WalkingFeasibilityReport f;
  try {
    f = CheckWalkingPlanFeasibility(model, d.plan, o.diagram, t_stop, fp);
  } catch (const std::exception& e) {
    std::cerr << "walking: feasibility check: " << e.what() << "\n";
    return 3;
  }
  std::printf("feasibility check (%s): %d plan samples every %.0f ms (%d in single support), %s (%.2f s)\n",
              o.feasibility.c_str(), f.samples, fp.sample_period_s * 1e3, f.single_support_samples,
              f.problem.empty() ? "within what it enforces" : "refused", f.solve_s);
  for (const std::string* p : {&f.sole_problem, &f.joint_limit_problem})
    if (!p->empty() && o.feasibility != "strict") std::printf("feasibility warning: %s\n", p->c_str());
  if (!f.problem.empty()) {
    std::cerr << "walking: " << f.problem << "\n";
    return 1;
  }
  return -1;
}

// Before any transition is planned (every scenario but periodic): each gait on its own orbit (the plan and check of
// --scenario periodic with --steps 3) against what --feasibility enforces. A gait the robot cannot walk even there is
// refused at once (one line, exit 1), not after the transition and gait-graph searches. -1 to go on, else the exit
// code.
int CheckOrbits(const std::shared_ptr<const MultibodyModel>& model, const examples::WalkingOptions& o,
                const PlanCache* cache) {
  if (o.feasibility == "off" || o.scenario == "periodic") return -1;
  std::vector<WalkingGait> gaits = o.scenario == "gait-sequence" ? o.gaits : std::vector<WalkingGait>{o.gait_a};
  if (o.scenario == "gait-change") gaits.push_back(o.gait_b);
  WalkingFeasibilityParams fp;
  fp.enforce_sole_wrench = fp.enforce_joint_limits = o.feasibility == "strict";
  for (const WalkingGait& g : gaits) {
    const WalkingPlan plan = BuildPeriodicWalkingPlan(g, 3 + o.run.trailing_steps, o.seed, cache, o.stand);
    const WalkingDiagram d = BuildWalkingDiagram(model, plan, o.diagram);
    const WalkingFeasibilityReport f =
        CheckWalkingPlanFeasibility(*model, d.plan, o.diagram, WalkingRunEndTime(d.plan, o.run), fp);
    if (!f.problem.empty()) {
      std::cerr << "walking: " << f.problem << " on the gait's own orbit\n";
      return 1;
    }
  }
  return -1;
}

}  // namespace

int main(int argc, char** argv) {
  examples::CommandLine cli(
      "walking",
      "The exoskeleton walks from standing: aSLIP + H-LIP plan, CLF-QP with force matching (walking paper).\n"
      "Measured range (periodic plans on a grid of L 0.2-0.45 m, T_SSP 0.35-0.5 s, T_DSP 0.08-0.15 s, W 0.2-0.3 m): "
      "within the torque limits but for T_SSP 0.35 s with L >= 0.375 m (knee 302-325 of 300 N m, refused);\n"
      "no gait of the grid fits a rigid sole and the URDF joint limits (--feasibility strict: the ankles' "
      "dorsiflexion in late stance and early swing, the sole's CoP and torsion), see docs/walking.md.");
  examples::DeclareWalkingOptions(cli);
  examples::WalkingOptions o;
  std::optional<PlanCache> cache;
  std::shared_ptr<const MultibodyModel> model;
  try {
    if (!cli.Parse(argc, argv)) return 0;
    InstallInterruptHandlers();  // SIGINT/SIGTERM: the run stops, its outputs are written, exit 128 + signal
    o = examples::ParseWalkingOptions(cli);
    cli.CheckOutputs({"log", "summary", "animation"}, {"plots"});
    // Before any NLP runs: a cache that cannot be written is bad input, not a failed run after the solves.
    if (!cli.Get("cache").empty()) {
      cache.emplace(cli.Get("cache"));
      if (const std::string problem = cache->EnsureDirectory(); !problem.empty())
        throw std::invalid_argument("walking: --cache: " + problem);
    }
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }
  try {
    // The plan's and the controller's model, on the Euler base (--base quaternion: BuildWalkingDiagram loads the
    // plant's quaternion twin from the same files).
    model = std::make_shared<const MultibodyModel>(
        MultibodyModel::LoadFromSidecar(cli.Get("robot"), {.euler_floating_base = true}));
    CheckWalkingRobot(*model);  // a robot the diagram cannot use is bad input, before any plan
  } catch (const std::exception& e) {
    std::cerr << "walking: --robot " << Excerpt(cli.Get("robot"), 200) << ": " << examples::OneLine(e.what()) << "\n";
    return 1;
  }
  WalkingPlanReport nlp;
  WalkingPlan plan;
  try {
    o.stand.sole = SoleOf(*model, "left_foot");
    o.diagram.perturbations = examples::FlatGroundPerturbationsFromCommandLine(
        cli, "walking", *model, o.perturbation_seed, o.diagram.controller.update_period_s);
    examples::ValidateWalkingOptions(o);  // the library's ranges, before any NLP
    o.stand.plan_check =
        WalkingPoseCheck(model, o.diagram);  // a direct plan the legs cannot follow goes through the lead-in
    // A gait-change transition beyond the torque limits is planned again (a tighter force bound, the gait graph).
    if (o.feasibility != "off") o.stand.change_check = WalkingChangeFeasibilityCheck(model, o.diagram);
    std::cout << "planning: periodic aSLIP, standing transition, footed H-LIP ...\n";
    if (const int code = CheckOrbits(model, o, cache ? &*cache : nullptr); code >= 0) return code;
    // The plan runs trailing_steps steps past the simulated ones, so that the last simulated steps are not the plan's
    // (and the momentum correction's) end.
    const PlanCache* plan_cache = cache ? &*cache : nullptr;
    const int planned = o.steps + o.run.trailing_steps;
    if (o.scenario == "periodic")
      plan = BuildPeriodicWalkingPlan(o.gait_a, planned, o.seed, plan_cache, o.stand);
    else if (o.scenario == "gait-change")
      plan = BuildGaitChangePlan(o.gait_a, o.gait_b, o.steps, o.seed, plan_cache, &nlp, o.stand, planned);
    else if (o.scenario == "walk-to-stand")
      plan = BuildWalkToStandPlan(o.gait_a, o.steps, o.seed, plan_cache, &nlp, o.stand);
    else if (o.scenario == "gait-sequence")
      plan = BuildGaitSequencePlan(o.gaits, o.steps, o.seed, plan_cache, &nlp, o.stand, planned);
    else
      plan = BuildStandToWalkPlan(o.gait_a, planned, o.seed, plan_cache, &nlp, o.stand);
    examples::PrintPlanReport(nlp, o.stand);
  } catch (const std::invalid_argument& e) {
    std::cerr << cli.NameTheOption(e.what(), examples::kWalkingParameterOptions) << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 3;
  }
  double compensation_s = 0.0;
  WalkingDiagram d;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    d = BuildWalkingDiagram(model, plan, o.diagram, o.plant);
    compensation_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } catch (const std::exception& e) {
    std::cerr << "walking: " << e.what() << "\n";
    return 3;
  }
  std::printf(
      "angular-momentum compensation: largest CoP shift in single support %.3f m -> %.3f m, COM correction up to %.3f "
      "m (%.2f s)\n",
      d.compensation.max_cop_shift_uncorrected_m, d.compensation.max_cop_shift_corrected_m,
      d.compensation.max_correction_m, compensation_s);
  // walk-to-stand: the run ends with the plan, standing (no trailing steps).
  if (o.scenario == "walk-to-stand") o.run.end_time_s = d.plan.end_time(), o.run.judge_standing_end = true;
  const double t_stop = WalkingRunEndTime(d.plan, o.run);
  if (const int code = CheckFeasibility(*model, d, o, t_stop); code >= 0) return code;
  if (!nlp.refused_plan_kept.empty()) {  // refused by the change check, within the limits on the whole plan by a hair
    std::cerr << "walking: " << nlp.refused_plan_kept << "\n";
    return 1;
  }
  if (o.check_only) return 0;
  const nlohmann::json plan_torques = examples::PlanTorqueReport(d, o.diagram, t_stop);
  examples::WalkingRecorder recorder(d, !cli.Get("log").empty(), !cli.Get("plots").empty(),
                                     !cli.Get("animation").empty());
  std::cout << "simulating " << t_stop << " s on the " << ToString(o.plant) << " plant ...\n";
  WalkingRunResult run;
  try {
    run = RunWalking(d, o.run, recorder.Observer());
  } catch (const std::exception& e) {
    std::cerr << "walking: " << e.what() << "\n";
    return 3;
  }
  nlohmann::json scenario = nlohmann::json::parse(cli.ScenarioJson());
  if (o.scenario != "periodic")
    scenario["start-gait-steps"] = o.stand.start_gait_steps;  // "auto" resolved (periodic: no start gait)
  nlohmann::json s =
      examples::WalkingSummary(run, d, nlp, o.scenario, o.stand, compensation_s, plan_torques, o.plant, scenario);
  if (run.standing_end_judged)
    std::printf("end: COM %.4f m from the midpoint between the ankles, %.4f m/s, ankles %.4f m apart in x: %s\n",
                run.standing_end.com_to_feet_midpoint_m, run.standing_end.com_speed_mps, run.standing_end.feet_gap_x_m,
                run.at_rest ? "standing at rest" : "NOT at rest");
  if (!cli.Get("summary").empty() &&
      !examples::WriteOutputFile("walking", cli.Get("summary"), s.dump(2) + "\n", "summary"))
    return 1;
  if (!cli.Get("log").empty() && !examples::WriteOutputFile("walking", cli.Get("log"), recorder.log(), "log")) return 1;
  if (!cli.Get("plots").empty()) recorder.WritePlots(cli.Get("plots"), plan, nlp, o.scenario, t_stop);
  if (const visualization::AnimationRecorder* animation = recorder.animation()) {
    std::string error;
    if (!animation->WriteHtml(cli.Get("animation"), "ROME walking, " + o.scenario, {}, &error))
      std::cerr << "walking: " << error << "\n";
    else
      std::cout << "animation: " << cli.Get("animation") << " (" << animation->num_frames() << " frames)\n";
  }
  examples::PrintRunResult(run, o.plant);
  if (run.interrupted) {
    std::cout << "result: interrupted (" << run.status.ToString() << "); outputs written up to there\n";
    return 128 + InterruptSignal();
  }
  return run.success ? 0 : 3;
}
