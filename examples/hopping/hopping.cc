// hopping: Cassie hops on the spring-mass ROM's plans (hopping paper: jump NLP Eq. (14)-(15), landing NLP Eq. (16),
// Jump/Flight/Landing CLF-QP with the augmented input Eq. (45)-(51)). 3D Cassie with live springs and achilles rods.
// A driver: parse → params → build (BuildHoppingDiagram) → run (RunHopping: the hops, the metrics and the success rule,
// diagrams/hopping/hopping_run.h) → write.
//
// Writes a CSV log (--log), a JSON summary (--summary, with the effective "scenario": --scenario-file with it
// reproduces the run), PNG plots (--plots DIR, hopping_plots.h) and an HTML animation (--animation).
// Perturbations (--push-*, --mass-scale, --sensor-noise, --latency, --torque-noise; docs/robustness.md) change the
// simulated world, not the ROM's plans or the controller's model.
// Exit 0: hopped (the COM rose at least H/2) and came to rest; 3: the run failed (fell, slipped, a planner gave up:
// Ipopt's status in the message); 1: bad input (the library's Validate() names the parameter and the value).
#include <iostream>
#include <memory>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "diagrams/hopping/hopping_run.h"
#include "examples/common/cli.h"
#include "examples/common/perturbation_options.h"
#include "examples/hopping/hopping_plots.h"
#include "framework/interrupt.h"
#include "systems/visualization/animation.h"

using namespace rome;

namespace {

void DeclareOptions(examples::CommandLine& cli) {
  const HoppingReferenceParams ref = HoppingDiagramParams::DefaultReferenceParams();
  using examples::FormatNumber;
  cli.Option(
         "apex-rise", FormatNumber(SpringMassJumpParams{}.apex_rise),
         "H [m]: COM rise above the take-off height (default: the ROM's air time is 0.423 s with the identified K(L))")
      .Option("leg-stiffness", "identified",
              "K(L), D(L) of the ROM: published (walking paper) or identified (Eq. (4)-(13) on our model)")
      .Option("hops", "1",
              "number of hops (1 to 1000); the landing of one hop is the crouch of the next (a bounce off the ground "
              "after a landing counts as a hop)")
      .Option("plant", "hybrid",
              "hybrid (event-accurate rigid contact, HybridContactPlant) | bullet (Bullet's physics world at 2 kHz, "
              "BulletWorldPlant)")
      .Option("base", "euler",
              "the plant's floating base: euler (ZYX Euler angles) | quaternion (the quaternion free-flyer twin of the "
              "same files, also the controller's, which reads the plant's state; the reference and the logs keep the "
              "Euler state through a QuaternionToEulerState block; hybrid plant only)")
      .Option(
          "bullet-substeps", std::to_string(HoppingDiagramParams::DefaultBulletPlantParams().substeps),
          "Bullet plant: Bullet steps per 0.5 ms plant step (1 to 100); the springs' torques are recomputed at each")
      .Option("jump-momentum-gain", FormatNumber(ref.jump_momentum_gain),
              "k [-] of the Jump pitch reference, theta_dot_d = theta_dot - k H_pitch / I_p (0: hold the pitch; "
              "HoppingReferenceParams)")
      .Option("flight-hip-follow", FormatNumber(ref.flight_hip_pitch_follow),
              "k [-]: in Flight the hip-pitch targets turn with the pelvis pitch, q_hip_d = q_hip_lo - k r (theta - "
              "theta_lo) (HoppingReferenceParams)")
      .Option("landing-deflection-feedback", FormatNumber(ref.landing_deflection_feedback),
              "g [-]: Landing leg-length target L_plan + g (x - x_plan), so the spring deflection follows the plan's "
              "(0: off; HoppingReferenceParams)")
      .Option("jump-force-feedback", FormatNumber(ref.jump_force_feedback),
              "k_F [-]: Jump leg-length target L_plan + k_F (F_plan - F) / (n K(L)), F the plant's normal GRF (0: off; "
              "HoppingReferenceParams)")
      .Option("jump-force-integral", FormatNumber(ref.jump_force_integral_per_s),
              "k_I [1/s]: Jump leg-length target also + integral of k_I (F_plan - F) / (n K(L)) dt (0: off; "
              "HoppingReferenceParams)")
      .Option("landing-torque-regularization", FormatNumber(HoppingDiagramParams{}.landing_u_regularization_scale),
              "[-] the CLF-QP's torque penalty rho_u is multiplied by this in Landing (1: off; HoppingDiagramParams)")
      .Option("landing-min-force", FormatNumber(SpringMassLandingParams{}.min_force_fraction),
              "F_min / (m g) [-]: the landing plan's smallest leg force (spec [R] 0.25)")
      .Option("landing-blend", FormatNumber(ref.landing_blend_s),
              "[s] Landing: duration of the COM-x and pitch quintics to the support centre and 0 (spec [R] 0.3 s)")
      .Option("duration", "0",
              "[s] simulated time; 0: until 2.5 s after the last hop's touchdown (rest is judged 2 s after it: a "
              "shorter run is not 'settled')")
      .Option("log", "", "CSV log path (empty: none)")
      .Option("summary", "", "JSON summary path (empty: none)")
      .Option("plots", "", "directory for PNG plots (empty: none)")
      .Option("animation", "", "FILE.html: a self-contained 3D animation of the run (three.js inlined; empty: none)")
      .Option("seed", "1", "seed of the perturbations' random draws (--sensor-noise, --torque-noise)")
      .ScenarioFile({"log", "summary", "plots", "animation"});
  examples::DeclarePerturbationOptions(cli);
}

// The parameters of a run, from the parsed options (ranges are checked by the library's Validate()).
struct Scenario {
  HoppingDiagramParams diagram;
  SpringMassJumpParams jump;
  SpringMassLandingParams landing;
  LegStiffnessVariant leg_stiffness = LegStiffnessVariant::kIdentified;
  PlantKind plant = PlantKind::kHybrid;
  HoppingRunParams run;
};

Scenario ScenarioFromOptions(const examples::CommandLine& cli) {
  Scenario s;
  s.plant = ParsePlantKind(cli.Get("plant"), "--plant");
  cli.RequireModeFor("bullet-substeps", "plant", {"bullet"});  // a flag the chosen plant ignores is an error
  s.diagram.plant_base = ParsePlantBase(cli.Get("base"), "--base");
  try {
    s.leg_stiffness = ParseLegStiffnessVariant(cli.Get("leg-stiffness"));
  } catch (const std::exception&) {
    throw std::invalid_argument("--leg-stiffness " + cli.Get("leg-stiffness") +
                                ": unknown variant (published or identified)");
  }
  s.jump.apex_rise = cli.GetDouble("apex-rise");
  s.landing.min_force_fraction = cli.GetDouble("landing-min-force");
  HoppingReferenceParams& ref = s.diagram.reference;
  ref.hops = cli.GetInt("hops");
  ref.jump_momentum_gain = cli.GetDouble("jump-momentum-gain");
  ref.flight_hip_pitch_follow = cli.GetDouble("flight-hip-follow");
  ref.landing_blend_s = cli.GetDouble("landing-blend");
  ref.landing_deflection_feedback = cli.GetDouble("landing-deflection-feedback");
  ref.jump_force_feedback = cli.GetDouble("jump-force-feedback");
  ref.jump_force_integral_per_s = cli.GetDouble("jump-force-integral");
  s.diagram.landing_u_regularization_scale = cli.GetDouble("landing-torque-regularization");
  s.diagram.bullet_plant.substeps = cli.GetInt("bullet-substeps");
  s.run.duration_s = cli.GetDouble("duration");
  s.run.record_plot_samples = !cli.Get("plots").empty();
  s.run.progress = &std::cerr;
  return s;
}

}  // namespace

// The library parameter each option sets, as Validate()'s messages name it (for errors in the options' terms).
const std::vector<std::pair<std::string, std::string>> kParameterOptions = {
    {"reference.hops", "hops"},
    {"apex_rise", "apex-rise"},
    {"reference.jump_momentum_gain", "jump-momentum-gain"},
    {"reference.flight_hip_pitch_follow", "flight-hip-follow"},
    {"reference.landing_deflection_feedback", "landing-deflection-feedback"},
    {"min_force_fraction", "landing-min-force"},
    {"reference.landing_blend_s", "landing-blend"},
    {"reference.jump_force_feedback", "jump-force-feedback"},
    {"reference.jump_force_integral_per_s", "jump-force-integral"},
    {"landing_u_regularization_scale", "landing-torque-regularization"},
    {"bullet_plant.substeps", "bullet-substeps"},
    {"duration_s", "duration"}};

int main(int argc, char** argv) {
  examples::CommandLine cli("hopping", "Cassie hops on the spring-mass ROM's jump and landing plans (hopping paper).");
  DeclareOptions(cli);
  Scenario s;
  std::shared_ptr<const MultibodyModel> model;
  std::unique_ptr<SpringMassHopPlanners> planners;
  HoppingDiagram d;
  try {
    if (!cli.Parse(argc, argv)) return 0;
    InstallInterruptHandlers();  // SIGINT/SIGTERM: the run stops, its outputs are written, exit 128 + signal
    s = ScenarioFromOptions(cli);
    s.run.Validate();
    cli.CheckOutputs({"log", "summary", "animation"}, {"plots"});
    // The controller's model, on the Euler base (--base quaternion: BuildHoppingDiagram loads the plant's quaternion
    // twin).
    model = std::make_shared<const MultibodyModel>(
        MultibodyModel::LoadFromSidecar("robots/cassie/cassie.rome.json", {.euler_floating_base = true}));
    if (cli.GetInt("seed") < 0)
      throw std::invalid_argument("hopping: --seed must be a whole number in [0, 2147483647], got " + cli.Get("seed"));
    s.diagram.perturbations = examples::FlatGroundPerturbationsFromCommandLine(
        cli, "hopping", *model, static_cast<std::uint64_t>(cli.GetInt("seed")), s.diagram.controller.update_period_s);
    planners = std::make_unique<SpringMassHopPlanners>(*model, s.leg_stiffness, s.jump, s.landing);
    d = BuildHoppingDiagram(model, planners->leg_length, planners->jump, planners->landing, s.diagram, s.plant);
  } catch (const std::exception& e) {
    std::cerr << cli.NameTheOption(examples::OneLine(e.what()), kParameterOptions) << "\n";
    return 1;
  }

  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());
  std::unique_ptr<visualization::AnimationRecorder> animation;
  if (!cli.Get("animation").empty()) {
    animation = std::make_unique<visualization::AnimationRecorder>(*model);
    s.run.observer = [&](const Context& c, const HoppingRunState&) {
      const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, c);
      animation->Record(pc.time(), HoppingEulerState(d, c).head(model->nv()),
                        d.plant->mode_name(d.plant->EvalTypedOutput<int>(pc, "mode")),
                        d.plant->EvalOutput(pc, "contact_forces"));
    };
  }
  std::cout << "hopping: simulating " << HoppingRunDuration(d, s.run) << " s on the " << ToString(s.plant) << " plant ("
            << ToString(s.diagram.plant_base) << " base) ...\n"
            << std::flush;
  HoppingRunResult r;
  try {
    r = RunHopping(d, sim, s.run, planners.get());
  } catch (const std::exception& e) {
    std::cerr << "hopping: " << e.what() << "\n";
    return 3;
  }

  const std::string summary = HoppingSummaryJson(d, r, planners.get(), cli.ScenarioJson());
  if (!cli.Get("summary").empty() && !examples::WriteOutputFile("hopping", cli.Get("summary"), summary, "summary"))
    return 1;
  if (!cli.Get("log").empty() &&
      !examples::WriteOutputFile("hopping", cli.Get("log"),
                                 d.logger->CsvText(d.diagram->GetSubsystemContext(*d.logger, sim.get_context())),
                                 "log"))
    return 1;
  if (animation) {
    std::string error;
    if (!animation->WriteHtml(cli.Get("animation"), "ROME hopping, Cassie", {}, &error))
      std::cerr << "hopping: " << error << "\n";
    else
      std::cout << "animation: " << cli.Get("animation") << " (" << animation->num_frames() << " frames)\n";
  }
  if (!cli.Get("plots").empty()) examples::WriteHoppingPlots(*model, r, cli.Get("plots"));
  std::cout << "hopping (" << ToString(s.plant) << " plant): " << r.status.ToString() << "\n"
            << "  air time " << r.air_time_s << " s (paper 0.423), foot clearance " << r.foot_clearance_m
            << " m (paper ~0.18), COM rise " << r.com_rise_m << " m, lift-off vs ROM " << r.takeoff_time_error_s
            << " s\n"
            << "  GRF NRMSE jump " << r.grf_nrmse_jump << ", landing " << r.grf_nrmse_landing
            << "; pitch change in flight " << r.max_pelvis_pitch_change_flight_rad * 180 / M_PI << " deg; hops landed "
            << r.touchdowns << "; hopped " << (r.hopped ? "yes" : "no") << "; settled " << (r.settled ? "yes" : "no")
            << "; QP median " << r.qp_solve_us_median << " us; real-time factor " << r.realtime_factor
            << "\n  plant contact violations " << r.contact.violations << " (" << r.contact.samples << " samples)"
            << (r.contact.violations ? ", first: " + r.contact.first_violation : "") << ", max |F_t|/F_n "
            << r.contact.max_friction_ratio << "\n";
  if (r.status.kind() == SimulatorStatus::Kind::kInterrupted) {
    std::cout << "result: interrupted (" << r.status.ToString() << "); outputs written up to there\n";
    return 128 + InterruptSignal();
  }
  return r.success ? 0 : 3;
}
