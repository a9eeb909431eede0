// stepping_stones: AMBER walks over stepping stones with momentum regulation (stepping-stones paper, Algorithm 1).
// Event-accurate hybrid plant (or Bullet's physics world: --plant bullet), LIP momentum planner, vertical-COM MPC,
// pre-impact posture NLP, task-space QP (or CLF-QP: --controller clf-qp).
//
// Writes a CSV log (--log), a JSON summary (--summary) and PNG plots (--plots DIR): gait tiles over the stones,
// COM height over time, and the phase portrait (p_com^x, L_y) against the LIP orbit of E*.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <nlohmann/json.hpp>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "systems/visualization/animation.h"
#include "examples/common/cli.h"
#include "systems/visualization/plot.h"
#include "systems/visualization/stick_figure.h"
#include "framework/simulator.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/plants/contact_force_statistics.h"
#include "framework/interrupt.h"

using namespace rome;

namespace {

Terrain MakeTerrain(const examples::CommandLine& cli, int steps, double default_stone_length) {
  const std::string kind = cli.Get("terrain");
  const double stone_length = cli.Get("stone-length") == "default" ? default_stone_length : cli.GetDouble("stone-length");
  const int n = steps + 2;
  if (kind == "flat" || kind == "stairs-up" || kind == "stairs-down") {
    const double l = cli.GetDouble("step-length");
    double h = 0.0;
    if (kind != "flat") h = cli.Get("step-height") == "default" ? (kind == "stairs-up" ? 0.2 : -0.1) : cli.GetDouble("step-height");
    if (!(l > 0)) throw std::invalid_argument("stepping_stones: --step-length must be positive, got " + cli.Get("step-length"));
    return PeriodicSteppingStones(l, h, n, stone_length);
  }
  if (kind == "random") {
    RandomSteppingStonesParams p;
    p.num_stones = n;
    p.min_gap_m = cli.GetDouble("min-gap");
    p.max_gap_m = cli.GetDouble("max-gap");
    p.max_rise_m = cli.GetDouble("max-rise");
    p.stone_length_m = stone_length;
    p.seed = static_cast<unsigned>(cli.GetInt("seed"));
    return RandomSteppingStones(p);
  }
  if (kind.empty()) throw std::invalid_argument("stepping_stones: --terrain must be flat, stairs-up, stairs-down, random or a CSV file, got ''");
  return Terrain::FromCsv(kind, stone_length);
}

/// RMS tracking errors of the stepping-stones outputs (Eq. (19)) against the output adapter's world-frame desired
/// values: torso pitch [rad], COM height [m], swing-foot position (x, z) [m] (the foot that swings in the mode).
class TrackingStatistics {
 public:
  explicit TrackingStatistics(const MultibodyModel& model)
      : model_(model), ws_(model), left_(model.ContactIndex("left_foot")), right_(model.ContactIndex("right_foot")) {}
  void Record(const Eigen::VectorXd& x, int mode, const Eigen::VectorXd& desired) {
    const int nv = model_.nv();
    const Eigen::VectorXd q = x.head(nv);
    const double pitch = q[model_.num_base_dofs() - 1];
    const double com_z = CalcComPosition(model_, ws_, q).z();
    sum_[0] += std::pow(pitch - desired[0], 2);
    sum_[1] += std::pow(com_z - desired[1], 2);
    ++n_;
    if (mode == 0 || mode == 1) {  // the swing foot's rows: right foot in left stance (4, 5), left foot in right stance (2, 3)
      const int contact = mode == 0 ? right_ : left_, row = mode == 0 ? 4 : 2;
      const ContactInfo& info = model_.contacts()[contact];
      const Eigen::Vector3d p = CalcPointPosition(model_, ws_, q, info.body, info.frame_origin);
      sum_[2] += std::pow(p.x() - desired[row], 2) + std::pow(p.z() - desired[row + 1], 2);
      ++n_swing_;
    }
  }
  double rms(int k) const { return std::sqrt(sum_[k] / std::max<long>(k == 2 ? n_swing_ : n_, 1)); }

 private:
  const MultibodyModel& model_;
  MultibodyWorkspace ws_;
  int left_, right_;
  double sum_[3] = {0, 0, 0};
  long n_ = 0, n_swing_ = 0;
};

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * static_cast<double>(v.size() - 1) + 0.5))];
}

/// The controller block's C++ class without its namespace, e.g. "TaskSpaceQpController".
std::string ControllerKind(const System& controller) {
  const std::string type = DemangledTypeName(typeid(controller));
  return type.substr(type.rfind(':') + 1);
}

}  // namespace

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
                            "A planar biped (AMBER, planar Cassie) walks over stepping stones: LIP momentum regulation, vertical-COM MPC, pre-impact posture NLP and a task-space QP "
                            "(stepping-stones paper, Algorithm 1), simulated event by event.");
  cli.Option("terrain", "random", "flat | stairs-up | stairs-down | random | FILE.csv (x,z[,length] per line)")
      .Option("step-length", "0.4", "[m] distance between stones for flat and stairs")
      .Option("step-height", "default", "[m] height change per stone for stairs (default: +0.2 up, -0.1 down)")
      .Option("stone-length", "default", "[m] length of each stone's top (default: 0.1 for point feet, the sole + 4 cm for line feet)")
      .Option("min-gap", "0.2", "[m] random terrain: smallest distance between stones")
      .Option("max-gap", "0.7", "[m] random terrain: largest distance between stones")
      .Option("max-rise", "0.25", "[m] random terrain: largest height change from one stone to the next")
      .Option("seed", "1", "random seed of the random terrain")
      .Option("steps", "30", "number of steps to walk")
      .Option("energy", "0.5", "E* [m^2/s^2], desired orbital energy (paper: 0.5)")
      .Option("epsilon", "0.6", "epsilon [-], desired pre-impact COM position as a fraction of the step (paper: 0.6)")
      .Option("swing-clearance", "0.1", "[m] z_sw^max above the highest of the start, stance and next stones")
      .Option("swing-apex", "clear",
              "paper (Bezier control points at z_sw^max, Eq. (24)) | exact (the curve peaks at z_sw^max) | clear (exact, and at least "
              "5 cm above the stance stone wherever the foot passes over it)")
      .Option("initial-com-x", "-0.1", "[m] COM position relative to the stance foot at the start (on the E* orbit)")
      .Option("robot", "robots/amber/amber.rome.json", "planar robot sidecar (AMBER: point feet; planar Cassie: line feet; a relative path is looked up in ROME's data folders, ./PATH reads the current folder)")
      .Option("torso-gains", "default", "weight,kp,kd of the torso-pitch output (default: the robot's, SteppingStonesDiagramParams::ForRobot)")
      .Option("com-gains", "default", "weight,kp,kd of the COM-height output")
      .Option("swing-gains", "default", "weight,kp,kd of the swing-foot position output")
      .Option("foot-pitch-gains", "default", "weight,kp,kd of the swing-foot pitch output (line feet only)")
      .Option("walking-height", "default", "[m] supervisor.walking_com_height_m (default: the robot's)")
      .Option("log", "stepping_stones.csv", "CSV log")
      .Option("summary", "stepping_stones.json", "JSON summary")
      .Option("log-period", "0.005", "[s] sample period of the CSV log")
      .Option("friction-margin", "0.95", "[-] the controller's friction pyramid uses this fraction of mu (1 = the paper's cone)")
      .Option("min-normal-force", "2", "[N] the controller's smallest stance normal force (0 = the paper's F_z >= 0)")
      .Option("clf-relaxation-weight", "default", "CLF-QP: weight p of the CLF relaxation (default: the diagram's)")
      .Option("clf-rate", "default", "[Hz] CLF-QP update rate (default: the diagram's)")
      .Option("clf-cone-offset", "default", "[N] CLF-QP: apex of the friction pyramid, |F_t| <= mu' (F_z - offset) (default: the diagram's)")
      .Option("plant", "hybrid", "hybrid (event-accurate rigid contact, HybridContactPlant) | bullet (Bullet's physics world at 1 kHz, BulletWorldPlant)")
      .Option("controller", "tsc-qp", "tsc-qp (task-space QP, Eq. (29)-(31)) | clf-qp (CLF-QP, the same outputs and GRF rows)")
      .Option("clf-cost-only", "default", "CLF-QP: comma-separated outputs kept out of the CLF and tracked in the cost with their PD gains (e.g. torso_pitch), or none (default: the diagram's)")
      .Option("clf-hold-drift", "default", "on | off: CLF-QP: also keep the wrench rows at the force predicted at the end of the held sample (default: the diagram's)")
      .Option("clf-cost-pd", "default", "on | off: CLF-QP: the cost tracks each output's PD target (task gains) instead of its feedforward (default: the diagram's)")
      .Option("mpc-hold", "default", "[s] vertical-COM MPC: below this predicted time to impact the plan is held, not re-solved (default: the diagram's)")
      .Option("clf-com-weight", "default", "[-] CLF-QP: cost weight of the COM-height output, in (0, 1000] (default: the diagram's: 20 for line feet, else the --com-gains weight, 1)")
      .Option("clf-epsilon", "default", "epsilon [-] of the CLF-QP's RES-CLF (--controller clf-qp; default: the diagram's)")
      .Option("unilateral-contact", "on", "on | off: the plant's stance feet lift off at F_n = 0 and a slip fails the run (off: welded feet, as before)")
      .Option("resolve-at-events", "on", "on | off: the controller and the MPC re-solve at touchdown and lift-off (off: 1 kHz hold only)")
      .Flag("report-qp-failures", "print the task-space QP's failure messages (which constraints conflict) as they occur")
      .Option("plots", "", "directory for PNG plots (empty: none)")
      .Option("animation", "", "FILE.html: a self-contained 3D animation of the run (three.js inlined; empty: none)");
  try {
    if (!cli.Parse(argc, argv)) return 0;
    InstallInterruptHandlers();  // SIGINT/SIGTERM: the run stops, its outputs are written, exit 128 + signal
    const int steps = cli.GetInt("steps");
    // Ranges (ours): bounded work and physically meaningful gaits; each error names the option and the value.
    auto in_range = [&](const std::string& name, double lo, double hi, bool lo_open) {
      const double v = cli.GetDouble(name);
      if ((lo_open ? !(v > lo) : !(v >= lo)) || !(v <= hi))
        throw std::invalid_argument("stepping_stones: --" + name + " must be in " + (lo_open ? "(" : "[") + examples::FormatNumber(lo) + ", " +
                                    examples::FormatNumber(hi) + "], got " + cli.Get(name));
      return v;
    };
    if (steps < 1 || steps > 10000) throw std::invalid_argument("stepping_stones: --steps must be in [1, 10000], got " + cli.Get("steps"));
    in_range("energy", 0.0, 10.0, true);  // E* > 0: the robot walks forwards (E* <= 0 turns back before the stone)
    in_range("epsilon", 0.0, 1.0, true);
    const double log_period = in_range("log-period", 1e-4, 10.0, false);
    const double log_rows = (3.0 * steps + 2.0) / log_period;
    if (!cli.Get("log").empty() && log_rows > 5e6)
      throw std::invalid_argument("stepping_stones: --log-period " + cli.Get("log-period") + " s over up to " + std::to_string(3 * steps + 2) + " s would log " +
                                  std::to_string(static_cast<long>(log_rows)) + " rows (limit 5e6); raise --log-period or lower --steps");
    if (cli.Get("stone-length") != "default") in_range("stone-length", 0.0, 1.0, true);
    in_range("swing-clearance", 0.0, 1.0, true);
    if (cli.Get("terrain") == "flat" || cli.Get("terrain") == "stairs-up" || cli.Get("terrain") == "stairs-down") in_range("step-length", 0.0, 5.0, true);
    // Output files are checked before the simulation, so a long run is not lost to a typo.
    cli.CheckOutputs({"log", "summary", "animation"}, {"plots"});
    SteppingStonesDiagramParams params = SteppingStonesDiagramParams::ForRobot(cli.Get("robot"));
    const Terrain terrain = MakeTerrain(cli, steps, SteppingStoneLengthFor(MultibodyModel::LoadFromSidecar(params.robot_sidecar)));
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
    params.target_orbital_energy = cli.GetDouble("energy");
    params.impact_fraction = cli.GetDouble("epsilon");
    params.supervisor.max_steps = steps;
    params.log_period_s = cli.GetDouble("log-period");
    params.initial_com_x_m = cli.GetDouble("initial-com-x");
    params.outputs.swing_foot.clearance = cli.GetDouble("swing-clearance");
    params.controller.friction_margin = cli.GetDouble("friction-margin");
    params.controller.min_normal_force_N = cli.GetDouble("min-normal-force");
    if (cli.Get("resolve-at-events") != "on" && cli.Get("resolve-at-events") != "off")
      throw std::invalid_argument("stepping_stones: --resolve-at-events must be 'on' or 'off', got '" + cli.Get("resolve-at-events") + "'");
    if (cli.Get("unilateral-contact") != "on" && cli.Get("unilateral-contact") != "off")
      throw std::invalid_argument("stepping_stones: --unilateral-contact must be 'on' or 'off', got '" + cli.Get("unilateral-contact") + "'");
    params.plant.unilateral_contact = cli.Get("unilateral-contact") == "on";
    params.controller.resolve_at_events = params.mpc.resolve_at_events = params.clf_controller.resolve_at_events = cli.Get("resolve-at-events") == "on";
    params.clf_controller.contact.friction_margin = params.controller.friction_margin;
    params.clf_controller.contact.min_normal_force_N = params.controller.min_normal_force_N;
    if (cli.Get("mpc-hold") != "default") {
      const double hold = cli.GetDouble("mpc-hold");
      if (!(hold >= 0 && hold <= 10)) throw std::invalid_argument("stepping_stones: --mpc-hold must be in [0, 10] s, got " + cli.Get("mpc-hold"));
      params.mpc.hold_plan_below_horizon_s = hold;
    }
    if (cli.Get("clf-com-weight") != "default") {
      const double w = cli.GetDouble("clf-com-weight");
      if (!(w > 0 && w <= 1000)) throw std::invalid_argument("stepping_stones: --clf-com-weight must be in (0, 1000], got " + cli.Get("clf-com-weight"));
      if (cli.Get("controller") != "clf-qp")
        throw std::invalid_argument("stepping_stones: --clf-com-weight applies to --controller clf-qp only (got --controller " + cli.Get("controller") + ")");
      params.clf_com_height_weight = w;
    }
    if (cli.Get("clf-epsilon") != "default") params.clf_controller.epsilon = cli.GetDouble("clf-epsilon");
    if (cli.Get("clf-relaxation-weight") != "default") params.clf_controller.relaxation_weight = cli.GetDouble("clf-relaxation-weight");
    if (cli.Get("clf-rate") != "default") {
      const double rate = cli.GetDouble("clf-rate");
      if (!(rate > 0 && rate <= 1e5)) throw std::invalid_argument("stepping_stones: --clf-rate must be in (0, 1e5] Hz, got " + cli.Get("clf-rate"));
      params.clf_controller.update_period_s = 1.0 / rate;
    }
    if (cli.Get("clf-cone-offset") != "default") params.clf_controller.contact.friction_cone_offset_N = cli.GetDouble("clf-cone-offset");
    if (cli.Get("clf-cost-only") == "none") {
      params.clf_controller.cost_only_outputs.clear();
    } else if (cli.Get("clf-cost-only") != "default") {
      params.clf_controller.cost_only_outputs.clear();
      std::stringstream names(cli.Get("clf-cost-only"));
      for (std::string name; std::getline(names, name, ',');) params.clf_controller.cost_only_outputs.push_back(name);
    }
    if (cli.Get("clf-hold-drift") != "default") {
      if (cli.Get("clf-hold-drift") != "on" && cli.Get("clf-hold-drift") != "off")
        throw std::invalid_argument("stepping_stones: --clf-hold-drift must be 'on', 'off' or 'default', got '" + cli.Get("clf-hold-drift") + "'");
      params.clf_controller.predict_hold_drift = cli.Get("clf-hold-drift") == "on";
    }
    if (cli.Get("clf-cost-pd") != "default") {
      if (cli.Get("clf-cost-pd") != "on" && cli.Get("clf-cost-pd") != "off")
        throw std::invalid_argument("stepping_stones: --clf-cost-pd must be 'on', 'off' or 'default', got '" + cli.Get("clf-cost-pd") + "'");
      params.clf_controller.cost_pd_feedback = cli.Get("clf-cost-pd") == "on";
    }
    SteppingStonesControllerFactory controller;
    if (cli.Get("controller") == "clf-qp")
      controller = ClfQpControllerFactory(params);
    else if (cli.Get("controller") != "tsc-qp")
      throw std::invalid_argument("stepping_stones: --controller must be 'tsc-qp' or 'clf-qp', got '" + cli.Get("controller") + "'");
    if (cli.Get("swing-apex") == "clear")
      params.outputs.swing_foot.apex_shape = SwingApexShape::kClearStanceStone;
    else if (cli.Get("swing-apex") == "exact")
      params.outputs.swing_foot.apex_shape = SwingApexShape::kExactPeak;
    else if (cli.Get("swing-apex") == "paper")
      params.outputs.swing_foot.apex_shape = SwingApexShape::kControlPoints;
    else
      throw std::invalid_argument("stepping_stones: --swing-apex must be 'paper', 'exact' or 'clear', got '" + cli.Get("swing-apex") + "'");
    std::string animation_error;
    const PlantKind plant_kind = ParsePlantKind(cli.Get("plant"), "stepping_stones: --plant");
    SteppingStonesDiagram d = BuildSteppingStonesDiagram(terrain, params, controller, plant_kind);
    std::unique_ptr<visualization::AnimationRecorder> animation;
    if (!cli.Get("animation").empty()) animation = std::make_unique<visualization::AnimationRecorder>(*d.model);
    Simulator sim(*d.diagram, SteppingStonesSimulatorConfig());
    SetSteppingStonesInitialState(d, params, sim.get_mutable_context());
    sim.Initialize();

    std::cout << "stepping_stones: " << ToString(plant_kind) << " plant, " << terrain.stones().size() << " stones (" << cli.Get("terrain") << "), E* = " << params.target_orbital_energy
              << ", epsilon = " << params.impact_fraction << ", " << steps << " steps\n";
    const auto start = std::chrono::steady_clock::now();
    SimulatorStatus status;
    const LeafContext& sup_ctx = d.diagram->GetSubsystemContext(*d.supervisor, sim.get_context());
    size_t reported = 0;
    const double max_time = 3.0 * steps + 2.0;
    // The plant's own contact forces after every integrator step and event (not the controller's plan).
    ContactForceStatistics contact;
    const bool report_qp = cli.GetFlag("report-qp-failures");
    double last_qp_status = 0;
    // Controller comparison figures, read through the seam's ports and the plant: output tracking error against the
    // output adapter's desired values (torso pitch, COM height, swing foot x and z), ∫u² dt, and the update's wall time.
    TrackingStatistics tracking(*d.model);
    std::vector<double> solve_times;
    solve_times.reserve(static_cast<size_t>(max_time * 1000.0) + 1000);
    double u2_integral = 0, last_time = 0, last_solve_time = -1;
    Eigen::VectorXd last_u = Eigen::VectorXd::Zero(d.model->nu());
    const bool has_solve_time = d.controller->HasOutputPort("solve_time_s");
    sim.set_monitor([&](const Context& c) {
      const LeafContext& plant_context = d.diagram->GetSubsystemContext(*d.plant, c);
      contact.Record(*d.plant, plant_context);
      if (animation) {
        const int mode = d.plant->EvalTypedOutput<int>(plant_context, "mode");
        animation->Record(c.time(), d.plant->EvalOutput(plant_context, "q"), d.plant->mode_name(mode),
                          d.plant->EvalOutput(plant_context, "contact_forces"));
      }
      u2_integral += last_u.squaredNorm() * (c.time() - last_time);  // u is held between updates
      last_time = c.time();
      last_u = d.EvalControllerOutput(c, "u");
      tracking.Record(d.plant->EvalOutput(plant_context, "state"), d.plant->EvalTypedOutput<int>(plant_context, "mode"),
                      d.output_adapter->EvalOutput(d.diagram->GetSubsystemContext(*d.output_adapter, c), "desired"));
      if (has_solve_time) {
        const double st = d.EvalControllerOutput(c, "solve_time_s")[0];
        if (st != last_solve_time && st > 0) solve_times.push_back(st);
        last_solve_time = st;
      }
      if (report_qp) {  // each change of the controller's QP status (0 = solved), through its qp_status port
        const double qp_status = d.EvalControllerOutput(c, "qp_status")[0];
        if (qp_status != last_qp_status) std::cerr << "t = " << c.time() << " s: controller qp_status " << qp_status << "\n";
        last_qp_status = qp_status;
      }
      return EventStatus::Succeeded();
    });
    for (double t = 0.5; t <= max_time + 1e-9; t += 0.5) {
      try {
        status = sim.AdvanceTo(t);
      } catch (const std::exception& e) {
        // A block rejected its inputs mid-run (e.g. a step the planner cannot reach): a failed run, reported and
        // summarised like a fall, not a crash of the program.
        status.reason = SimulatorStatus::Reason::kFailed;
        status.time = sim.get_context().time();
        status.message = e.what();
      }
      const auto& recs = d.supervisor->steps(sup_ctx);
      if (recs.size() != reported) {
        std::cout << "  t = " << sim.get_context().time() << " s: " << recs.size() << " steps, last l = " << recs.back().step_length_m
                  << " m, foothold error " << recs.back().foothold_error_m * 100 << " cm\n";
        reported = recs.size();
      }
      if (!status.ok()) break;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const auto& recs = d.supervisor->steps(sup_ctx);
    const double sim_time = sim.get_context().time();
    const bool failed = status.kind() == SimulatorStatus::Kind::kFailure;
    const bool fell = failed && status.message.find("fell") != std::string::npos;
    const bool success = status.kind() == SimulatorStatus::Kind::kSuccess && contact.violations == 0;
    const LeafContext& plant_ctx = d.diagram->GetSubsystemContext(*d.plant, sim.get_context());
    const double x_end = d.plant->EvalOutput(plant_ctx, "com")[0];
    const LeafContext& log_ctx = d.diagram->GetSubsystemContext(*d.logger, sim.get_context());
    const auto& log = d.logger->log(log_ctx);
    const int com_x = d.logger->ColumnIndex("plant.com.x"), com_z = d.logger->ColumnIndex("plant.com.z");
    const double x_start = log.samples.empty() ? x_end : log.samples.front()[com_x];
    double max_foothold = 0;
    nlohmann::json step_list = nlohmann::json::array();
    for (const auto& r : recs) {
      max_foothold = std::max(max_foothold, r.foothold_error_m);
      step_list.push_back({{"l", r.step_length_m},
                           {"h", r.step_height_m},
                           {"duration_s", r.duration_s},
                           {"pre_impact_com_vz_mps", r.pre_impact_com_vz_mps},
                           {"u_des_mps", r.u_des_mps},
                           {"post_impact_momentum", r.post_impact_momentum},
                           {"L_des", r.L_des},
                           {"foothold_error_m", r.foothold_error_m},
                           {"stone", r.stone},
                           {"planned_stone", r.planned_stone},
                           {"posture_ok", r.posture_ok}});
    }
    const LeafContext& mpc_ctx = d.diagram->GetSubsystemContext(*d.mpc, sim.get_context());
    // CLF-QP only: how often the CLF inequality binds at the solution (clf_activity = [active, solved updates]).
    nlohmann::json clf_activity = nullptr;
    if (d.controller->HasOutputPort("clf_activity")) {
      const Eigen::VectorXd a = d.EvalControllerOutput(sim.get_context(), "clf_activity");
      clf_activity = {{"active_updates", a[0]}, {"solved_updates", a[1]}, {"active_fraction", a[1] > 0 ? a[0] / a[1] : 0.0}};
    }
    const int qp_failures = static_cast<int>(d.EvalControllerOutput(sim.get_context(), "qp_failures")[0]) +
                            static_cast<int>(d.mpc->EvalOutput(mpc_ctx, "qp_failures")[0]);
    nlohmann::json summary = {{"success", success},
                              {"status_kind", status.kind_name()},
                              {"controller", ControllerKind(*d.controller)},
                              {"plant", ToString(plant_kind)},
                              {"steps_completed", recs.size()},
                              {"fell", fell},
                              {"fall_reason", fell ? status.message : ""},
                              {"status", status.ToString()},
                              {"min_stance_normal_force_N", contact.samples > 0 ? contact.min_normal_force_N : 0.0},
                              {"max_friction_ratio", contact.max_friction_ratio},
                              {"contact_violations", contact.violations},
                              {"first_contact_violation", contact.first_violation},
                              {"tracking_rms", {{"torso_pitch_rad", tracking.rms(0)}, {"com_height_m", tracking.rms(1)}, {"swing_foot_m", tracking.rms(2)}}},
                              {"u_squared_integral_per_step_N2m2s", recs.empty() ? 0.0 : u2_integral / static_cast<double>(recs.size())},
                              {"controller_update_us", {{"median", 1e6 * Percentile(solve_times, 0.5)}, {"p99", 1e6 * Percentile(solve_times, 0.99)},
                                                        {"updates", solve_times.size()}}},
                              {"sim_time_s", sim_time},
                              {"wall_time_s", wall},
                              {"realtime_factor", wall > 0 ? sim_time / wall : 0.0},
                              {"mean_forward_speed_mps", sim_time > 0 ? (x_end - x_start) / sim_time : 0.0},
                              {"max_foothold_error_m", max_foothold},
                              {"qp_failures", qp_failures},
                              {"clf_row_activity", clf_activity},
                              {"nlp_failures", d.supervisor->posture_failures(sup_ctx)},
                              {"energy", params.target_orbital_energy},
                              {"epsilon", params.impact_fraction},
                              {"terrain", cli.Get("terrain")},
                              {"seed", cli.GetInt("seed")},
                              {"steps", step_list}};
    const SimulatorStatistics& stats = sim.statistics();
    summary["integrator"] = {{"steps", stats.steps},
                             {"rhs_evaluations", stats.rhs_evals},
                             {"root_evaluations", stats.root_evals},
                             {"guard_events", stats.guard_events},
                             {"discrete_samples", stats.discrete_samples}};
    nlohmann::json stone_list = nlohmann::json::array();
    for (const auto& st : terrain.stones()) stone_list.push_back({st.x_center_m, st.top_height_m, st.length_m});
    summary["stones"] = stone_list;
    if (!cli.Get("summary").empty() && !examples::WriteOutputFile("stepping_stones", cli.Get("summary"), summary.dump(2) + "\n", "summary"))
      return 1;
    if (!cli.Get("log").empty()) d.logger->WriteCsv(log_ctx, cli.Get("log"));
    if (animation) {
      std::vector<visualization::AnimationStone> stones;
      for (const auto& st : terrain.stones()) stones.push_back({st.x_center_m, st.top_height_m, st.length_m});
      if (!animation->WriteHtml(cli.Get("animation"), "ROME stepping stones, " + ControllerKind(*d.controller), stones, &animation_error))
        std::cerr << "warning: " << animation_error << "\n";
      else
        std::cout << "animation: " << cli.Get("animation") << " (" << animation->num_frames() << " frames)\n";
    }
    if (!cli.Get("plots").empty()) {
      const std::string dir = cli.Get("plots");
      std::filesystem::create_directories(dir);
      const int nv = d.model->nv();
      const int rel_x = d.logger->ColumnIndex("supervisor.com_state.x"), rel_z = d.logger->ColumnIndex("supervisor.com_state.z");
      const int L_col = d.logger->ColumnIndex("supervisor.angular_momentum.L");
      const int q0 = d.logger->ColumnIndex("plant.state.q_" + d.model->JointName(0));
      std::string err;
      // COM height over time.
      visualization::Series zc{"COM height (world)", {}, {}, "lines"};
      for (size_t k = 0; k < log.times.size(); ++k) {
        zc.x.push_back(log.times[k]);
        zc.y.push_back(log.samples[k][com_z]);
      }
      if (!visualization::WritePlot({"COM height", "time [s]", "z [m]", {zc}}, dir + "/com_height.png", &err)) std::cerr << "warning: " << err << "\n";
      // Phase portrait against the LIP orbit of E*: L = z0 sqrt(E* + λ² x²).
      visualization::Series ph{"robot (p_com^x, L_y)", {}, {}, "lines"}, orbit{"LIP orbit of E*", {}, {}, "lines dt 2"};
      double zsum = 0;
      for (size_t k = 0; k < log.times.size(); ++k) {
        ph.x.push_back(log.samples[k][rel_x]);
        ph.y.push_back(log.samples[k][L_col]);
        zsum += log.samples[k][rel_z];
      }
      const double z0 = log.times.empty() ? 0.9 : zsum / log.times.size();
      const double lambda2 = 9.81 / z0;
      for (int i = -50; i <= 50; ++i) {
        const double x = 0.5 * i / 50.0;
        orbit.x.push_back(x);
        orbit.y.push_back(z0 * std::sqrt(params.target_orbital_energy + lambda2 * x * x));
      }
      if (!visualization::WritePlot({"Phase portrait, E* = " + cli.Get("energy"), "p_com^x relative to stance foot [m]", "L_y [m^2/s]", {ph, orbit}},
                               dir + "/phase_portrait.png", &err))
        std::cerr << "warning: " << err << "\n";
      // Gait tiles: stick figures every 0.1 s over the stones.
      MultibodyWorkspace ws(*d.model);
      visualization::Series sticks{"robot", {}, {}, "lines lc rgb '#3060c0'"}, stones{"stones", {}, {}, "lines lw 6 lc rgb '#808080'"};
      for (const auto& s : terrain.stones()) {
        stones.x.insert(stones.x.end(), {s.x_center_m - s.length_m / 2, s.x_center_m + s.length_m / 2, NAN});
        stones.y.insert(stones.y.end(), {s.top_height_m, s.top_height_m, NAN});
      }
      // The robot as its description draws it (every link to its parent, the soles): no link names assumed.
      double next_t = 0;
      for (size_t k = 0; k < log.times.size(); ++k) {
        if (log.times[k] < next_t) continue;
        next_t = log.times[k] + 0.1;
        visualization::AppendStickFigure(*d.model, ws, log.samples[k].segment(q0, nv), 0, 0.0, &sticks, &sticks);
      }
      visualization::PlotSpec tiles{"Gait tiles (every 0.1 s)", "x [m]", "z [m]", {stones, sticks}};
      tiles.equal_axes = true;
      tiles.width_px = 1600;
      tiles.height_px = 500;
      if (!visualization::WritePlot(tiles, dir + "/gait_tiles.png", &err)) std::cerr << "warning: " << err << "\n";
    }
    std::cout << "\n"
              << status.ToString() << "\n"
              << recs.size() << " of " << steps << " steps" << (fell ? " (fell)" : "") << ", " << sim_time << " s simulated in " << wall
              << " s wall (" << (wall > 0 ? sim_time / wall : 0) << "x real time), controller " << ControllerKind(*d.controller) << ", plant "
              << ToString(plant_kind) << "\n"
              << "mean forward speed " << summary["mean_forward_speed_mps"].get<double>() << " m/s, largest foothold error " << max_foothold * 100
              << " cm, QP failures " << qp_failures
              << (clf_activity.is_null() ? std::string() : ", CLF row active in " + examples::FormatNumber(100.0 * clf_activity["active_fraction"].get<double>()) + " % of updates")
              << ", NLP failures " << d.supervisor->posture_failures(sup_ctx) << "\n"
              << "plant contact forces: min stance F_n " << summary["min_stance_normal_force_N"].get<double>() << " N, max |F_t|/F_n "
              << contact.max_friction_ratio << ", violations " << contact.violations << " of " << contact.samples << " samples\n";
    if (status.kind() == SimulatorStatus::Kind::kInterrupted) {
      std::cout << "result: interrupted (" << status.ToString() << "); outputs written up to there\n";
      return 128 + InterruptSignal();
    }
    if (success) {
      std::cout << "result: success (" << status.message << ")\n";
      return 0;
    }
    std::cout << "result: failed run (" << (contact.violations > 0 ? "contact violation: " + contact.first_violation : status.kind_name() + ": " + status.ToString())
              << ")\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "error: " << examples::OneLine(e.what()) << "\n";
    return 1;
  }
}
