#include "examples/walking/walking_options.h"

#include <algorithm>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <vector>

#include "examples/common/perturbation_options.h"
#include "framework/text.h"

namespace rome::examples {

const std::vector<std::pair<std::string, std::string>> kWalkingParameterOptions = {
    {"controller.force_band_halfwidth", "force-band"},
    {"force_band_lead_periods", "force-band-lead"},
    {"stance_stagger_m", "stance-stagger"},
    {"standing_height_m", "com-heights"},
    {"height_min_m", "com-heights"},
    {"height_max_m", "com-heights"},
    {"start_gait_step_length_m", "start-gait"},
    {"start_gait_ssp_duration_s", "start-gait"},
    {"start_gait_dsp_duration_s", "start-gait"},
    {"start_gait_steps", "start-gait-steps"},
    {"lead_in_step_length_m", "lead-in"},
    {"lead_in_ssp_duration_s", "lead-in"},
    {"lead_in_dsp_duration_s", "lead-in"},
    {"lead_in_steps", "lead-in-steps"},
    {"transition_min_ssp_duration_s", "transition-ssp"},
    {"gait_change_max_force_fraction", "gait-change-max-force"},
    {"periodic_max_force_fraction", "periodic-max-force"},
    {"sagittal_cop_margin_m", "rom-cop-margin"},
    {"swing.touchdown_velocity_mps", "touchdown-speed"},
    {"pitch_max_rad", "swing-pitch"},
    {"foothold_tolerance_m", "foothold-tolerance"}};

void DeclareWalkingOptions(CommandLine& cli) {
  cli.Option("scenario", "stand-to-walk",
             "stand-to-walk (standing side by side -> transition -> --start-gait-steps of the --start-gait -> gait A; "
             "a gait faster than the --lead-in gait (shorter T_SSP or T_DSP), or with no plan from the start gait, "
             "walks --lead-in-steps of the lead-in first) | gait-change (standing -> gait A as stand-to-walk, but "
             "never through the lead-in -> transition -> gait B) | periodic (started on gait A's orbit, no transition; "
             "the start and lead-in flags do not apply) | gait-sequence (standing -> the first of --gaits as "
             "gait-change's gait A -> a change into each next gait) | walk-to-stand (stand-to-walk's start, --steps of "
             "gait "
             "A, a change into short slow steps at the --start-gait timing, then a stop that ends standing with the "
             "feet side by side, at rest). A change with no direct transition plan goes "
             "through intermediate gaits of a gait graph over the range")
      .Option("gait-a", "0.30,0.40,0.10,0.25", "gait A: step length L [m], T_SSP [s], T_DSP [s], step width W [m]")
      .Option("gait-b", "0.40,0.40,0.10,0.25", "gait B (gait-change scenario)")
      .Option("gaits", "",
              "gait-sequence scenario: 2 to 20 gaits L,T_SSP,T_DSP,W separated by ';' (e.g. "
              "\"0.3,0.4,0.1,0.25;0.4,0.4,0.1,0.25\"), --steps each")
      .Option("steps", "10", "periodic single supports per gait after each transition (1 to 1000)")
      .Option("force-band", "0.1", "c of the force band, Eq. (25)")
      .Option("force-band-lead", "1",
              "the force band's reference is the plan's this many control periods ahead, where the held torque's "
              "force is next sampled (ours; 0: the paper's F_ref(t); 0 to 2)")
      .Option("force-band-at", "hold-end",
              "hold-end | solve: the force band bounds the force predicted at the end of the held control period "
              "(ours, default) or at the QP's solve instant (the paper)")
      .Option("hold-drift", "on",
              "on | off: the CLF-QP also keeps each stance wrench's rows (friction, CoP, the corners' yaw) at the "
              "wrench predicted at the end of the held control period (ClfQpParams::predict_hold_drift; ours, on: "
              "an unloading foot's torsion then falls with its normal force)")
      .Option("hold-drift-settle", "0.003",
              "[s] --hold-drift's rows take no drift until this long into a contact mode (ClfQpParams::"
              "hold_drift_settle_s; ours: Bullet's touchdown impacts last 2-3 steps; 0 to 0.1)")
      .Option("stance-stagger", "0",
              "standing stance: 0 = feet side by side (spec [R]; through the start gait), or a step stance with the "
              "right foot this far behind the left [m] (StandToWalkParams::StepStance; 0.40 the earlier default)")
      .Option("start-gait", "0.20,0.50,0.15",
              "the start gait L,T_SSP,T_DSP [m, s, s] (at gait A's W): from standing side by side, the standing "
              "transition goes into it (ours; same ranges as --lead-in)")
      .Option("start-gait-steps", "auto",
              "periodic steps of the start gait before the change into gait A or the lead-in (0 to 20; auto: 6 side by "
              "side, 0 from a step stance)")
      .Option("lead-in", "0.30,0.40,0.10",
              "the lead-in gait L,T_SSP,T_DSP [m, s, s] (at gait A's W): stand-to-walk walks it before gait A when "
              "gait A is faster or has no plan otherwise (ours; L 0.1-0.45 m, T_SSP 0.35-0.6 s, T_DSP 0.08-0.3 s)")
      .Option("lead-in-steps", "6",
              "periodic steps of the lead-in gait before the change to gait A (0: no lead-in; up to 20)")
      .Option("transition-ssp", "0",
              "lower bound of the standing transition's single-support time [s] (0: the T_SSP of the gait it goes "
              "into: the start gait's side by side, gait A's from a step stance)")
      .Option("com-heights", "auto",
              "H,MIN,MAX: the ROM's COM height standing, and the NLPs' height range [m] (ours; spec [R] 0.9 in "
              "0.85-0.95); a standing height above the range is left and reached in double support; auto: "
              "0.91,0.84,0.90 side by side (the standing ankles inside their URDF limits), 0.86,0.84,0.90 from a step "
              "stance (whose legs do not reach 0.91 m)")
      .Option("gait-change-max-force", "1.6",
              "the gait-change transition NLPs (A -> B, a lead-in -> A, the start gait -> the next gait) keep each "
              "leg's vertical force <= this many m g (ours; 0: no bound, else in (1, 3])")
      .Option("periodic-max-force", "1.5",
              "a periodic aSLIP plan whose leg force exceeds this many m g is planned again with that bound (ours; 0: "
              "never, else in (1, 3])")
      .Option("rom-cop-margin", "0.05",
              "the footed aSLIP keeps its CoP this far inside the robot's heel and toe [m] (side by side, the standing "
              "transition and the start gait's change keep 0.02 m: StandToWalkParams::standing_sagittal_cop_margin_m)")
      .Option("touchdown-speed", "0.1",
              "the swing sole's downward speed at the planned touchdown [m/s] (spec [R] 0.1; range 0.05 to 0.5, ours)")
      .Option("swing-pitch", "0.25",
              "the swing foot's toe-down pitch at the apex [rad], in proportion to the ankle's height above standing "
              "(ours; 0: the flat swing foot of spec [R]; 0 to 0.44, the toe's clearance): keeps the swing ankle "
              "further from its dorsiflexion limit")
      .Option("clf-cost-target", "pd",
              "pd | min-norm: the CLF-QP cost tracks each output's PD law (ours, default) or its feedforward ÿ_d (spec "
              "§5.5 [C22]: minimum-norm μ = 0)")
      .Option("sole-torsion", "corner-cone",
              "coefficient | corner-cone: the CLF-QP bounds each sole's yaw moment by |tau_z| <= 0.1 m f_z wherever "
              "the CoP is (more than a rigid sole holds near an edge: on the Bullet plant the feet slide) or each "
              "sole's wrench by the contact wrench cone of its four corners (ours, default: a rigid sole, less torsion "
              "where the CoP nears an edge or the foot carries a tangential force)")
      .Option("sole-torsion-margin", "0.002",
              "corner-cone: the yaw rows' half-sizes are the whole sole's less this margin [m] (ours; < 0: the CoP "
              "rows' sole, 1 cm inside its edges)")
      .Option("plant-sole-torsion", "on",
              "on | off: the hybrid plant's four-corner soles also slip torsionally outside their corners' wrench cone "
              "(HybridContactPlantParams::sole_torsion; on, the default, as a rigid sole; off: only the friction "
              "cone)")
      .Option("contact-projection", "on",
              "on | off: with --latency, the controller reads the delayed state with its velocity projected onto the "
              "plant's current contacts (ContactVelocityProjection; ours, on: the new stance foot otherwise bounces "
              "at each touchdown)")
      .Option("sole-torsion-friction", "0.75",
              "corner-cone: the friction coefficient of the corners' pyramids in the yaw rows (inscribed in the "
              "cone; ours, 0.75: a relative margin below the exoskeleton sole's 0.8 for the force's drift over a held "
              "sample); < 0: the sole's own (the robot file's)")
      .Option("foothold-tolerance", "0.05",
              "a touchdown counts as a step only this close to its planned foothold [m] (ours)")
      .Option("plant", "hybrid",
              "hybrid (event-accurate rigid contact, HybridContactPlant) | bullet (Bullet's physics world at 1 kHz, "
              "BulletWorldPlant)")
      .Option("base", "euler",
              "the plant's floating base: euler (ZYX Euler angles) | quaternion (the quaternion free-flyer twin of the "
              "robot's files, also the controller's, which reads the plant's state; the plan and the logs keep the "
              "Euler state through a QuaternionToEulerState block; hybrid plant, spatial robots only)")
      .Option("joint-limits", "on",
              "on | off: the Bullet plant enforces the URDF's joint limits (the hybrid plant: --joint-stops)")
      .Option("joint-stops", "off",
              "on | off: the hybrid plant ends the run when a joint reaches its URDF limit, and the CLF-QP brakes each "
              "joint before its limit (ours; off by default: the walking plans bend the ankles beyond the URDF's)")
      .Option("feasibility", "torque",
              "before simulating, the plan's inverse dynamics (CheckWalkingPlanFeasibility) is checked against the "
              "torque limits, a rigid sole's four-corner wrench cone and the joint limits: torque = refuse (exit 1) a "
              "plan over a torque limit, report the rest | strict = refuse any of them | off")
      .Option("check-only", "off", "on: plan and check the plan's feasibility, then exit without simulating")
      .Option("seed", "1", "seed of the NLP initial guesses")
      .Option("robot", "robots/exoskeleton/exoskeleton.rome.json",
              "robot sidecar (a relative path is looked up in ROME's data folders; ./PATH reads the current folder)")
      .Option("cache", "walking_plans",
              "directory of cached ROM plans, created if missing (empty: none, every NLP is solved)")
      .Option("log", "", "CSV log file (empty: none)")
      .Option(
          "summary", "",
          "JSON summary file (empty: none); its \"scenario\" holds every option's effective value (a --scenario-file)")
      .Option("plots", "",
              "directory for PNG plots (empty: none): the paper's Fig. 2 S2/L2, 3 S2/L2 and 5a/b/d from this run, and "
              "gait tiles")
      .Option("animation", "", "FILE.html: a self-contained 3D animation of the run (three.js inlined; empty: none)")
      .Option("perturbation-seed", "1",
              "seed of the perturbations' random draws (--sensor-noise, --torque-noise; apart from --seed, so that the "
              "cached plans stay)")
      .ScenarioFile({"log", "summary", "plots", "animation", "cache"});
  DeclarePerturbationOptions(cli);
}

namespace {

// `n` comma-separated numbers of option `flag` (form checked here, ranges by Validate).
std::vector<double> Numbers(const CommandLine& cli, const std::string& flag, int n, const std::string& form) {
  return cli.GetNumbers(flag, n, form);
}

WalkingGait Gait(const CommandLine& cli, const std::string& flag) {
  const std::vector<double> v = Numbers(cli, flag, 4, "L,T_SSP,T_DSP,W");
  return WalkingGait{v[0], v[1], v[2], v[3]};
}

// --gaits "L,T_SSP,T_DSP,W;...": the form only (the ranges are WalkingGait::Validate's).
std::vector<WalkingGait> GaitList(const std::string& text) {
  std::vector<WalkingGait> gaits;
  size_t begin = 0;
  for (int index = 1;; ++index) {
    const size_t end = std::min(text.find(';', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    double v[4];
    int used = -1;
    if (std::sscanf(item.c_str(), " %lf , %lf , %lf , %lf %n", &v[0], &v[1], &v[2], &v[3], &used) != 4 ||
        used != static_cast<int>(item.size()))
      throw std::invalid_argument("walking: --gaits: gait " + std::to_string(index) + " '" + Excerpt(item, 80) +
                                  "' is not L,T_SSP,T_DSP,W (4 numbers; gaits separated by ';')");
    gaits.push_back(WalkingGait{v[0], v[1], v[2], v[3]});
    if (end == text.size()) break;
    begin = end + 1;
  }
  if (gaits.size() < 2 || gaits.size() > 20)
    throw std::invalid_argument("walking: --gaits has " + std::to_string(gaits.size()) +
                                " gaits, expected 2 to 20 separated by ';'");
  return gaits;
}

std::string OneOf(const CommandLine& cli, const std::string& flag, std::initializer_list<const char*> words) {
  const std::string value = cli.Get(flag);
  std::string list;
  for (const char* w : words) {
    if (value == w) return value;
    list += (list.empty() ? "'" : ", '") + std::string(w) + "'";
  }
  throw std::invalid_argument("walking: --" + flag + " must be one of " + list + ", got '" + Excerpt(value, 200) + "'");
}

}  // namespace

WalkingOptions ParseWalkingOptions(const CommandLine& cli) {
  WalkingOptions o;
  o.plant = ParsePlantKind(cli.Get("plant"), "walking: --plant");
  o.diagram.plant_base = ParsePlantBase(cli.Get("base"), "walking: --base");
  o.scenario = OneOf(cli, "scenario", {"stand-to-walk", "gait-change", "periodic", "gait-sequence", "walk-to-stand"});
  o.feasibility = OneOf(cli, "feasibility", {"torque", "strict", "off"});
  o.check_only = OneOf(cli, "check-only", {"on", "off"}) == "on";
  // A flag the chosen scenario or plant ignores is an error (the periodic scenario starts on gait A's orbit).
  for (const char* standing : {"stance-stagger", "start-gait", "start-gait-steps", "lead-in", "lead-in-steps",
                               "transition-ssp", "gait-change-max-force"})
    cli.RequireModeFor(standing, "scenario", {"stand-to-walk", "gait-change", "gait-sequence", "walk-to-stand"});
  cli.RequireModeFor("gait-b", "scenario", {"gait-change"});
  cli.RequireModeFor("gaits", "scenario", {"gait-sequence"});
  cli.RequireModeFor("joint-limits", "plant", {"bullet"});
  cli.RequireModeFor("joint-stops", "plant", {"hybrid"});
  o.gait_a = Gait(cli, "gait-a");
  o.gait_b = Gait(cli, "gait-b");
  if (o.scenario == "gait-sequence") o.gaits = GaitList(cli.Get("gaits"));
  o.steps = cli.GetInt("steps");
  if (cli.GetInt("seed") < 0)
    throw std::invalid_argument("walking: --seed must be a whole number in [0, 2147483647], got " + cli.Get("seed"));
  o.seed = static_cast<std::uint32_t>(cli.GetInt("seed"));
  if (cli.GetInt("perturbation-seed") < 0)
    throw std::invalid_argument("walking: --perturbation-seed must be a whole number in [0, 2147483647], got " +
                                cli.Get("perturbation-seed"));
  o.perturbation_seed = static_cast<std::uint32_t>(cli.GetInt("perturbation-seed"));
  // Side by side (stagger 0, the default) goes through the start gait; a step stance does not (StepStance).
  const double stagger = cli.GetDouble("stance-stagger");
  StandToWalkParams& s = o.stand;
  s = stagger == 0 ? StandToWalkParams{} : StandToWalkParams::StepStance(stagger);
  s.stance_stagger_m = stagger;
  if (cli.Get("start-gait-steps") != "auto") s.start_gait_steps = cli.GetInt("start-gait-steps");
  const std::vector<double> start = Numbers(cli, "start-gait", 3, "L,T_SSP,T_DSP");
  s.start_gait_step_length_m = start[0], s.start_gait_ssp_duration_s = start[1], s.start_gait_dsp_duration_s = start[2];
  const std::vector<double> lead = Numbers(cli, "lead-in", 3, "L,T_SSP,T_DSP");
  s.lead_in_step_length_m = lead[0], s.lead_in_ssp_duration_s = lead[1], s.lead_in_dsp_duration_s = lead[2];
  s.lead_in_steps = cli.GetInt("lead-in-steps");
  s.sagittal_cop_margin_m = cli.GetDouble("rom-cop-margin");
  s.transition_min_ssp_duration_s = cli.GetDouble("transition-ssp");
  s.gait_change_max_force_fraction = cli.GetDouble("gait-change-max-force");
  s.periodic_max_force_fraction = cli.GetDouble("periodic-max-force");
  if (cli.Get("com-heights") != "auto") {
    const std::vector<double> heights = Numbers(cli, "com-heights", 3, "H,MIN,MAX");
    s.standing_height_m = heights[0], s.height_min_m = heights[1], s.height_max_m = heights[2];
  }
  WalkingDiagramParams& p = o.diagram;
  p.controller.force_band_halfwidth = cli.GetDouble("force-band");
  p.force_band_lead_periods = cli.GetDouble("force-band-lead");
  p.controller.force_band_at_hold_end = OneOf(cli, "force-band-at", {"hold-end", "solve"}) == "hold-end";
  p.controller.predict_hold_drift = OneOf(cli, "hold-drift", {"on", "off"}) == "on";
  p.controller.hold_drift_settle_s = cli.GetDouble("hold-drift-settle");
  if (!(p.controller.hold_drift_settle_s >= 0.0 && p.controller.hold_drift_settle_s <= 0.1))
    throw std::invalid_argument("walking: --hold-drift-settle must be in [0, 0.1] s, got " +
                                cli.Get("hold-drift-settle"));
  p.swing.touchdown_velocity_mps = cli.GetDouble("touchdown-speed");
  p.swing.pitch_max_rad = cli.GetDouble("swing-pitch");
  if (!(p.swing.pitch_max_rad >= 0.0 && p.swing.pitch_max_rad <= 0.44))
    throw std::invalid_argument("walking: --swing-pitch must be in [0, 0.44] rad, got " + cli.Get("swing-pitch"));
  p.controller.cost_pd_feedback = OneOf(cli, "clf-cost-target", {"pd", "min-norm"}) == "pd";
  p.controller.contact.corner_wrench_cone = OneOf(cli, "sole-torsion", {"coefficient", "corner-cone"}) == "corner-cone";
  p.controller.contact.corner_cone_friction_coefficient = cli.GetDouble("sole-torsion-friction");
  p.controller.contact.corner_cone_yaw_margin_m = cli.GetDouble("sole-torsion-margin");
  p.plant.sole_torsion = OneOf(cli, "plant-sole-torsion", {"on", "off"}) == "on";
  p.project_velocity_on_contacts = OneOf(cli, "contact-projection", {"on", "off"}) == "on";
  if (!(p.controller.contact.corner_cone_yaw_margin_m <= 0.05))
    throw std::invalid_argument(
        "walking: --sole-torsion-margin must be < 0 (the CoP rows' sole) or in [0, 0.05] m, got " +
        cli.Get("sole-torsion-margin"));
  if (!(p.controller.contact.corner_cone_friction_coefficient <= 2.0))
    throw std::invalid_argument("walking: --sole-torsion-friction must be < 0 (the sole's own) or in [0, 2], got " +
                                cli.Get("sole-torsion-friction"));
  p.bullet_plant.enable_joint_limits = OneOf(cli, "joint-limits", {"on", "off"}) == "on";
  p.plant.joint_stops = p.controller.joint_limit_brake.enabled = OneOf(cli, "joint-stops", {"on", "off"}) == "on";
  o.run.foothold_tolerance_m = cli.GetDouble("foothold-tolerance");
  // The periodic scenario starts inside the first double support, where both feet carry load (at its first instant
  // the landed foot's planned force is 0), on the plan's orbit.
  if (o.scenario == "periodic") o.run.start_time_s = 0.5 * o.gait_a.dsp_duration_s, o.run.start_at_rest = false;
  return o;
}

void ValidateWalkingOptions(const WalkingOptions& o) {
  o.gait_a.Validate("walking: --gait-a");
  o.gait_b.Validate("walking: --gait-b");
  for (size_t i = 0; i < o.gaits.size(); ++i) o.gaits[i].Validate("walking: --gaits: gait " + std::to_string(i + 1));
  if (o.steps < 1 || o.steps > 1000)
    throw std::invalid_argument("walking: --steps = " + std::to_string(o.steps) + " is outside [1, 1000]");
  o.stand.Validate("walking: StandToWalkParams");
  o.diagram.Validate();
  o.run.Validate();
}

}  // namespace rome::examples
