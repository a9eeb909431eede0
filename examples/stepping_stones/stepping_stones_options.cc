#include "examples/stepping_stones/stepping_stones_options.h"

#include "diagrams/stepping_stones/stepping_stones_feasibility.h"
#include "diagrams/stepping_stones/stepping_stones_torque_need.h"
#include "examples/common/perturbation_options.h"
#include "framework/text.h"

#include <iostream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace rome::examples {

namespace {

Terrain MakeTerrain(const CommandLine& cli, int steps, double default_stone_length) {
  const std::string kind = cli.Get("terrain");
  const double stone_length =
      cli.Get("stone-length") == "default" ? default_stone_length : cli.GetDouble("stone-length");
  const int n = steps + 2;
  if (kind == "flat" || kind == "stairs-up" || kind == "stairs-down") {
    const double l = cli.GetDouble("step-length");
    double h = 0.0;
    if (kind != "flat")
      h = cli.Get("step-height") == "default" ? (kind == "stairs-up" ? 0.2 : -0.1) : cli.GetDouble("step-height");
    if (!(l > 0))
      throw std::invalid_argument("stepping_stones: --step-length must be positive, got " + cli.Get("step-length"));
    return PeriodicSteppingStones(l, h, n, stone_length);
  }
  if (kind == "random") {
    // Ranges (ours: bounded terrain), each error naming the option; what the robot can step is checked later
    // (CheckSteppingStonesFeasible).
    const double min_gap = cli.GetDouble("min-gap"), max_gap = cli.GetDouble("max-gap"),
                 max_rise = cli.GetDouble("max-rise");
    if (!(min_gap > stone_length && min_gap <= 100.0))
      throw std::invalid_argument("stepping_stones: --min-gap must be in (" + FormatNumber(stone_length) +
                                  ", 100] m (above the stone length), got " + cli.Get("min-gap"));
    if (!(max_gap >= min_gap && max_gap <= 100.0))
      throw std::invalid_argument("stepping_stones: --max-gap must be in [--min-gap " + cli.Get("min-gap") +
                                  ", 100] m, got " + cli.Get("max-gap"));
    if (!(max_rise >= 0.0 && max_rise <= 100.0))
      throw std::invalid_argument("stepping_stones: --max-rise must be in [0, 100] m, got " + cli.Get("max-rise"));
    RandomSteppingStonesParams p;
    p.num_stones = n;
    p.min_gap_m = cli.GetDouble("min-gap");
    p.max_gap_m = cli.GetDouble("max-gap");
    p.max_rise_m = cli.GetDouble("max-rise");
    p.stone_length_m = stone_length;
    if (cli.GetInt("seed") < 0)
      throw std::invalid_argument("stepping_stones: --seed must be a whole number in [0, 2147483647], got " +
                                  cli.Get("seed"));
    p.seed = static_cast<unsigned>(cli.GetInt("seed"));
    return RandomSteppingStones(p);
  }
  if (kind.empty())
    throw std::invalid_argument(
        "stepping_stones: --terrain must be flat, stairs-up, stairs-down, random or a CSV file, got ''");
  return Terrain::FromCsv(kind, stone_length);
}

// --plan-check report: what the periodic plan asks of the actuators and of friction (stepping_stones_torque_need.h)
// on flat and stairs terrains with point feet, printed before the run. A measurement only: no threshold on it separates
// the gaits that walk from those that fail (docs/design-notes.md), so nothing is refused on it.
void ReportPlanTorqueNeed(const CommandLine& cli, const MultibodyModel& model, const Terrain& terrain,
                          const SteppingStonesDiagramParams& params) {
  const std::string mode = cli.Get("plan-check"), kind = cli.Get("terrain");
  if (mode != "off" && mode != "report")
    throw std::invalid_argument("stepping_stones: --plan-check must be 'off' or 'report', got '" + Excerpt(mode, 40) +
                                "'");
  if (mode == "off") return;
  if (kind != "flat" && kind != "stairs-up" && kind != "stairs-down")
    throw std::invalid_argument(
        "stepping_stones: --plan-check report needs --terrain flat, stairs-up or stairs-down "
        "(a periodic course), got '" +
        Excerpt(kind, 40) + "'");
  for (const ContactInfo& c : model.contacts())
    if (c.type != ContactType::kPoint)
      throw std::invalid_argument("stepping_stones: --plan-check report needs point feet; robot '" + model.name() +
                                  "' has a " + ToString(c.type) + " contact '" + c.name + "'");
  const auto& stones = terrain.stones();
  const double l = stones[1].x_center_m - stones[0].x_center_m, h = stones[1].top_height_m - stones[0].top_height_m;
  PlanTorqueNeed need;
  try {
    need = CalcPeriodicPlanTorqueNeed(model, l, h, stones[0].length_m, params);
  } catch (const std::invalid_argument& e) {  // the plan itself has no posture or solution: reported, not refused
    std::cout << "plan check: " << e.what() << "\n";
    return;
  }
  std::cout << "plan check: the plan needs " << need.torque_Nm << " N m at the "
            << (need.on_stance_leg ? "stance " : "swing ") << model.actuators()[need.actuator].joint << " (limit "
            << need.limit_Nm << " N m) at " << need.time_of_max_s << " s of " << need.step_duration_s
            << " s; |tau|/limit at most " << need.max_stance_torque_ratio << " (stance leg), "
            << need.max_swing_torque_ratio << " (swing leg); torque beyond the limits "
            << need.stance_excess_impulse_Nms << " N m s (stance), " << need.swing_excess_impulse_Nms
            << " N m s (swing); a stance joint over its limit " << need.stance_over_limit_fraction
            << " of the step; |F_x|/F_z at most " << need.max_friction_ratio << ", F_z at least "
            << need.min_normal_force_N << " N; planned speed " << need.mean_speed_mps << " m/s\n";
}

}  // namespace

void DeclareSteppingStonesOptions(CommandLine& cli) {
  cli.Option("terrain", "random", "flat | stairs-up | stairs-down | random | FILE.csv (x,z[,length] per line)")
      .Option("step-length", "0.4", "[m] distance between stones for flat and stairs")
      .Option("step-height", "default", "[m] height change per stone for stairs (default: +0.2 up, -0.1 down)")
      .Option("stone-length", "default",
              "[m] length of each stone's top (default: 0.1 for point feet, the sole + 4 cm for line feet)")
      .Option("min-gap", "0.2", "[m] random terrain: smallest distance between stones")
      .Option("max-gap", "0.7", "[m] random terrain: largest distance between stones")
      .Option("max-rise", "0.25", "[m] random terrain: largest height change from one stone to the next")
      .Option("seed", "1", "random seed of the random terrain and of the perturbations (noise, stone-height errors)")
      .Option("steps", "30", "number of steps to walk")
      .Option(
          "energy", "default",
          "E* [m^2/s^2], desired orbital energy (default: the robot's, AMBER 0.4 (ours), planar Cassie 0.5 (the "
          "paper's)). Measured on flat 0.8 m steps: AMBER walks at 1.0 / 1.5 / 2.0 / 2.5 (1.27 / 1.44 / 1.59 / 1.73 "
          "m/s), planar Cassie at 1.5 (1.60 m/s); AMBER walks 1.52 m/s on stairs down (0.8, -0.2) m at 0.5 and 1.66 "
          "m/s on flat 0.65 m steps at 2.5 (docs/stepping-stones.md)")
      .Option("plan-check", "off",
              "off | report: before a periodic run (flat, stairs-up, stairs-down; point feet) print the joint "
              "torques and the contact force the plan's inverse dynamics needs (a measurement; nothing is refused)")
      .Option("epsilon", "0.6", "epsilon [-], desired pre-impact COM position as a fraction of the step (paper: 0.6)")
      .Option("swing-clearance", "0.1", "[m] z_sw^max above the highest of the start, stance and next stones")
      .Option("swing-apex", "clear",
              "paper (Bezier control points at z_sw^max, Eq. (24)) | exact (the curve peaks at z_sw^max) | clear "
              "(exact, and at least "
              "5 cm above the stance stone wherever the foot passes over it; for line feet also 5 cm above the next "
              "stone where the foot crosses its rear edge)")
      .Option("initial-com-x", "-0.1", "[m] COM position relative to the stance foot at the start (on the E* orbit)")
      .Option("robot", "robots/amber/amber.rome.json",
              "planar robot sidecar (AMBER: point feet; planar Cassie: line feet; a relative path is looked up in "
              "ROME's data folders, ./PATH reads the current folder)")
      .Option("torso-gains", "default",
              "weight,kp,kd of the torso-pitch output (default: the robot's, SteppingStonesDiagramParams::ForRobot)")
      .Option("com-gains", "default", "weight,kp,kd of the COM-height output")
      .Option("swing-gains", "default", "weight,kp,kd of the swing-foot position output")
      .Option("foot-pitch-gains", "default", "weight,kp,kd of the swing-foot pitch output (line feet only)")
      .Option("walking-height", "default", "[m] supervisor.walking_com_height_m (default: the robot's)")
      .Option("max-com-foot-distance", "default",
              "[m] supervisor.max_com_foot_distance_m: long steps lower the pre-impact COM so it stays this close to "
              "both feet (e.g. 100: no cap; default: the robot's, AMBER 0.904)")
      .Option("log", "stepping_stones.csv", "CSV log")
      .Option("summary", "stepping_stones.json", "JSON summary")
      .Option("log-period", "0.005", "[s] sample period of the CSV log")
      .Option("friction-margin", "0.95",
              "[-] the controller's friction pyramid uses this fraction of mu (1 = the paper's cone)")
      .Option("min-normal-force", "2", "[N] the controller's smallest stance normal force (0 = the paper's F_z >= 0)")
      .Option("clf-relaxation-weight", "default", "CLF-QP: weight p of the CLF relaxation (default: the diagram's)")
      .Option("clf-rate", "default", "[Hz] CLF-QP update rate (default: the diagram's)")
      .Option("clf-cone-offset", "default",
              "[N] CLF-QP: apex of the friction pyramid, |F_t| <= mu' (F_z - offset) (default: the diagram's)")
      .Option("plant", "hybrid",
              "hybrid (event-accurate rigid contact, HybridContactPlant) | bullet (Bullet's physics world at 1 kHz, "
              "BulletWorldPlant)")
      .Option("controller", "tsc-qp",
              "tsc-qp (task-space QP, Eq. (29)-(31)) | clf-qp (CLF-QP, the same outputs and GRF rows)")
      .Option("clf-cost-only", "default",
              "CLF-QP: comma-separated outputs kept out of the CLF and tracked in the cost with their PD gains (e.g. "
              "torso_pitch), or none (default: the diagram's)")
      .Option("clf-hold-drift", "default",
              "on | off: CLF-QP: also keep the wrench rows at the force predicted at the end of the held sample "
              "(default: the diagram's)")
      .Option("clf-cost-pd", "default",
              "on | off: CLF-QP: the cost tracks each output's PD target (task gains) instead of its feedforward "
              "(default: the diagram's)")
      .Option("mpc-hold", "default",
              "[s] vertical-COM MPC: below this predicted time to impact the plan is held, not re-solved (default: the "
              "diagram's)")
      .Option(
          "mpc-max-accel", "default",
          "[m/s^2] vertical-COM MPC: largest upward COM acceleration the plan may ask for, > -9.81 (none: no bound; "
          "default: the diagram's)")
      .Option("min-u-des", "default",
              "[m/s] lower bound of the planner's pre-impact vertical COM velocity u_des, <= 0 (none: the paper's "
              "unbounded Eq. (26); default: the robot's, AMBER -1.5, planar Cassie -1 (both ours))")
      .Option("mpc-position-weight", "default",
              "[-] vertical-COM MPC: weight of the terminal height error when the terminal state is out of reach, > 0 "
              "(default: the diagram's)")
      .Option("clf-com-weight", "default",
              "[-] CLF-QP: cost weight of the COM-height output, in (0, 1000] (default: the diagram's: 20 for line "
              "feet, else the --com-gains weight, 1)")
      .Option("clf-epsilon", "default",
              "epsilon [-] of the CLF-QP's RES-CLF (--controller clf-qp; default: the diagram's)")
      .Option("unilateral-contact", "on",
              "on | off: the plant's stance feet lift off at F_n = 0 and a slip fails the run (off: welded feet, as "
              "before)")
      .Option("resolve-at-events", "on",
              "on | off: the controller and the MPC re-solve at touchdown and lift-off (off: 1 kHz hold only)")
      .Flag("report-qp-failures",
            "print the task-space QP's failure messages (which constraints conflict) as they occur")
      .Option("plots", "", "directory for PNG plots (empty: none)")
      .Option("animation", "", "FILE.html: a self-contained 3D animation of the run (three.js inlined; empty: none)")
      .ScenarioFile({"log", "summary", "plots", "animation"});
  DeclarePerturbationOptions(cli);
}

const std::vector<std::pair<std::string, std::string>> kSteppingStonesParameterOptions = [] {
  std::vector<std::pair<std::string, std::string>> t = {{"target_orbital_energy", "energy"},
                                                        {"impact_fraction", "epsilon"},
                                                        {"log_period_s", "log-period"},
                                                        {"initial_com_x_m", "initial-com-x"},
                                                        {"supervisor.max_steps", "steps"},
                                                        {"outputs.swing_foot.clearance", "swing-clearance"},
                                                        {"mpc.hold_plan_below_horizon_s", "mpc-hold"},
                                                        {"max_acceleration", "mpc-max-accel"},
                                                        {"terminal_position_weight", "mpc-position-weight"},
                                                        {"min_pre_impact_vertical_velocity_mps", "min-u-des"},
                                                        {"clf_com_height_weight", "clf-com-weight"},
                                                        {"clf_controller.update_period_s", "clf-rate"},
                                                        {"controller.friction_margin", "friction-margin"},
                                                        {"controller.min_normal_force_N", "min-normal-force"},
                                                        {"supervisor.walking_com_height_m", "walking-height"},
                                                        {"supervisor.max_com_foot_distance_m", "max-com-foot-distance"},
                                                        {"mass_scale", "mass-scale"},
                                                        {"friction_scale", "friction-scale"},
                                                        {"stone_height_sigma_m", "stone-height-error"},
                                                        {"position_noise_sigma", "sensor-noise"},
                                                        {"velocity_noise_sigma", "sensor-noise"},
                                                        {"torque_noise_sigma_Nm", "torque-noise"}};
  for (const auto& [gains, option] :
       std::vector<std::pair<std::string, std::string>>{{"torso_gains", "torso-gains"},
                                                        {"com_height_gains", "com-gains"},
                                                        {"swing_foot_gains", "swing-gains"},
                                                        {"swing_foot_pitch_gains", "foot-pitch-gains"}})
    for (const char* element : {".weight", ".kp", ".kd"}) t.emplace_back(gains + element, option);
  return t;
}();

SteppingStonesScenario SteppingStonesScenarioFromCommandLine(const CommandLine& cli) {
  const int steps = cli.GetInt("steps");
  // A flag the chosen controller or plant ignores is an error naming both.
  for (const char* clf : {"clf-relaxation-weight", "clf-rate", "clf-cone-offset", "clf-cost-only", "clf-hold-drift",
                          "clf-cost-pd", "clf-com-weight", "clf-epsilon"})
    cli.RequireModeFor(clf, "controller", {"clf-qp"});
  cli.RequireModeFor("unilateral-contact", "plant", {"hybrid"});
  // Ranges of the diagram's parameters are the library's (SteppingStonesDiagramParams::Validate, below); the terrain's
  // (ours) are checked here, each error naming the option and the value.
  auto in_range = [&](const std::string& name, double lo, double hi, bool lo_open) {
    const double v = cli.GetDouble(name);
    if ((lo_open ? !(v > lo) : !(v >= lo)) || !(v <= hi))
      throw std::invalid_argument("stepping_stones: --" + name + " must be in " + (lo_open ? "(" : "[") +
                                  FormatNumber(lo) + ", " + FormatNumber(hi) + "], got " + cli.Get(name));
    return v;
  };
  if (cli.Get("stone-length") != "default") in_range("stone-length", 0.0, 1.0, true);
  if (cli.Get("terrain") == "flat" || cli.Get("terrain") == "stairs-up" || cli.Get("terrain") == "stairs-down")
    in_range("step-length", 0.0, 5.0, true);
  // Output files are checked before the simulation, so a long run is not lost to a typo.
  cli.CheckOutputs({"log", "summary", "animation"}, {"plots"});
  SteppingStonesDiagramParams params = SteppingStonesDiagramParams::ForRobot(cli.Get("robot"));
  auto gains = [&](const std::string& flag, TaskGains* g) {
    if (cli.Get(flag) == "default") return;
    const std::vector<double> v = cli.GetNumbers(flag, 3, "weight,kp,kd");
    *g = {v[0], v[1], v[2]};
  };
  gains("torso-gains", &params.torso_gains);
  gains("com-gains", &params.com_height_gains);
  gains("swing-gains", &params.swing_foot_gains);
  gains("foot-pitch-gains", &params.swing_foot_pitch_gains);
  if (cli.Get("walking-height") != "default") params.supervisor.walking_com_height_m = cli.GetDouble("walking-height");
  if (cli.Get("max-com-foot-distance") != "default")
    params.supervisor.max_com_foot_distance_m = cli.GetDouble("max-com-foot-distance");
  if (cli.Get("energy") != "default") params.target_orbital_energy = cli.GetDouble("energy");
  // A bound option: "default" keeps the diagram's value, "none" sets `none`, anything else is a number.
  auto bound = [&](const std::string& flag, double none, double* value) {
    if (cli.Get(flag) == "none")
      *value = none;
    else if (cli.Get(flag) != "default")
      *value = cli.GetDouble(flag);
  };
  bound("min-u-des", -std::numeric_limits<double>::infinity(), &params.planner.min_pre_impact_vertical_velocity_mps);
  params.impact_fraction = cli.GetDouble("epsilon");
  params.supervisor.max_steps = steps;
  params.log_period_s = cli.GetDouble("log-period");
  params.initial_com_x_m = cli.GetDouble("initial-com-x");
  params.outputs.swing_foot.clearance = cli.GetDouble("swing-clearance");
  params.controller.friction_margin = cli.GetDouble("friction-margin");
  params.controller.min_normal_force_N = cli.GetDouble("min-normal-force");
  if (cli.Get("resolve-at-events") != "on" && cli.Get("resolve-at-events") != "off")
    throw std::invalid_argument("stepping_stones: --resolve-at-events must be 'on' or 'off', got '" +
                                cli.Get("resolve-at-events") + "'");
  if (cli.Get("unilateral-contact") != "on" && cli.Get("unilateral-contact") != "off")
    throw std::invalid_argument("stepping_stones: --unilateral-contact must be 'on' or 'off', got '" +
                                cli.Get("unilateral-contact") + "'");
  params.plant.unilateral_contact = cli.Get("unilateral-contact") == "on";
  params.controller.resolve_at_events = params.mpc.resolve_at_events = params.clf_controller.resolve_at_events =
      cli.Get("resolve-at-events") == "on";
  params.clf_controller.contact.friction_margin = params.controller.friction_margin;
  params.clf_controller.contact.min_normal_force_N = params.controller.min_normal_force_N;
  if (cli.Get("mpc-hold") != "default") params.mpc.hold_plan_below_horizon_s = cli.GetDouble("mpc-hold");
  bound("mpc-max-accel", std::numeric_limits<double>::infinity(), &params.mpc.mpc.max_acceleration);
  if (cli.Get("mpc-position-weight") != "default")
    params.mpc.mpc.terminal_position_weight = cli.GetDouble("mpc-position-weight");
  if (cli.Get("clf-com-weight") != "default") params.clf_com_height_weight = cli.GetDouble("clf-com-weight");
  if (cli.Get("clf-epsilon") != "default") params.clf_controller.epsilon = cli.GetDouble("clf-epsilon");
  if (cli.Get("clf-relaxation-weight") != "default")
    params.clf_controller.relaxation_weight = cli.GetDouble("clf-relaxation-weight");
  if (cli.Get("clf-rate") != "default") params.clf_controller.update_period_s = 1.0 / cli.GetDouble("clf-rate");
  if (cli.Get("clf-cone-offset") != "default")
    params.clf_controller.contact.friction_cone_offset_N = cli.GetDouble("clf-cone-offset");
  if (cli.Get("clf-cost-only") == "none") {
    params.clf_controller.cost_only_outputs.clear();
  } else if (cli.Get("clf-cost-only") != "default") {
    params.clf_controller.cost_only_outputs.clear();
    std::stringstream names(cli.Get("clf-cost-only"));
    for (std::string name; std::getline(names, name, ',');) params.clf_controller.cost_only_outputs.push_back(name);
  }
  if (cli.Get("clf-hold-drift") != "default") {
    if (cli.Get("clf-hold-drift") != "on" && cli.Get("clf-hold-drift") != "off")
      throw std::invalid_argument("stepping_stones: --clf-hold-drift must be 'on', 'off' or 'default', got '" +
                                  cli.Get("clf-hold-drift") + "'");
    params.clf_controller.predict_hold_drift = cli.Get("clf-hold-drift") == "on";
  }
  if (cli.Get("clf-cost-pd") != "default") {
    if (cli.Get("clf-cost-pd") != "on" && cli.Get("clf-cost-pd") != "off")
      throw std::invalid_argument("stepping_stones: --clf-cost-pd must be 'on', 'off' or 'default', got '" +
                                  cli.Get("clf-cost-pd") + "'");
    params.clf_controller.cost_pd_feedback = cli.Get("clf-cost-pd") == "on";
  }
  params.Validate();  // the library's ranges, before the controller and the terrain (--steps sizes it) are made
  SteppingStonesControllerFactory controller;
  if (cli.Get("controller") == "clf-qp")
    controller = ClfQpControllerFactory(params);
  else if (cli.Get("controller") != "tsc-qp")
    throw std::invalid_argument("stepping_stones: --controller must be 'tsc-qp' or 'clf-qp', got '" +
                                cli.Get("controller") + "'");
  if (cli.Get("swing-apex") == "clear")
    params.outputs.swing_foot.apex_shape = SwingApexShape::kClearStanceStone;
  else if (cli.Get("swing-apex") == "exact")
    params.outputs.swing_foot.apex_shape = SwingApexShape::kExactPeak;
  else if (cli.Get("swing-apex") == "paper")
    params.outputs.swing_foot.apex_shape = SwingApexShape::kControlPoints;
  else
    throw std::invalid_argument("stepping_stones: --swing-apex must be 'paper', 'exact' or 'clear', got '" +
                                cli.Get("swing-apex") + "'");
  const double log_rows = (3.0 * steps + 2.0) / params.log_period_s;
  if (!cli.Get("log").empty() && log_rows > 5e6)
    throw std::invalid_argument("stepping_stones: --log-period " + cli.Get("log-period") + " s over up to " +
                                std::to_string(3 * steps + 2) + " s would log " +
                                std::to_string(static_cast<long>(log_rows)) +
                                " rows (limit 5e6); raise --log-period or lower --steps");
  // What the diagram cannot walk is bad input, refused here before the simulation (stepping_stones_feasibility.h).
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(params.robot_sidecar, {.euler_floating_base = true});
  try {
    CheckSteppingStonesRobot(model);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("stepping_stones: --robot " + Excerpt(cli.Get("robot"), 200) + ": " + e.what());
  }
  if (cli.GetInt("seed") < 0)
    throw std::invalid_argument("stepping_stones: --seed must be a whole number in [0, 2147483647], got " +
                                cli.Get("seed"));
  params.perturbations = PerturbationsFromCommandLine(
      cli, model, static_cast<std::uint64_t>(cli.GetInt("seed")),
      cli.Get("controller") == "clf-qp" ? params.clf_controller.update_period_s : params.controller.update_period_s);
  if (params.perturbations.push) cli.RequireModeFor("push-force", "plant", {"hybrid"});
  if (params.perturbations.push) cli.RequireModeFor("push-impulse", "plant", {"hybrid"});
  const Terrain terrain = MakeTerrain(cli, steps, SteppingStoneLengthFor(model));
  try {
    CheckSteppingStonesFeasible(model, terrain, params);
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    if (what.rfind("terrain: ", 0) != 0) throw;  // a parameter's limit: the caller names its option
    throw std::invalid_argument(
        "stepping_stones: --terrain " + Excerpt(cli.Get("terrain"), 200) +
        (cli.Get("stone-length") == "default" ? "" : " --stone-length " + Excerpt(cli.Get("stone-length"), 40)) + ": " +
        what.substr(9));
  }
  ReportPlanTorqueNeed(cli, model, terrain, params);
  return {params, terrain, controller, ParsePlantKind(cli.Get("plant"), "stepping_stones: --plant"), steps};
}

}  // namespace rome::examples
