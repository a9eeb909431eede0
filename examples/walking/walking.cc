// walking: the 12-joint exoskeleton walks (walking paper: aSLIP + H-LIP planning composed into a 3D COM reference,
// CLF-QP with force matching). --scenario stand-to-walk (standing -> transition -> gait A), gait-change (standing -> A
// -> transition -> B) or periodic (started on gait A's orbit). The ROM plans are built offline (NLPs cached in
// --cache), the COM reference is corrected for the legs' angular momentum (CompensateCentroidalMomentum), then the
// diagram of diagrams/walking runs. Writes a CSV log (--log), a JSON summary (--summary) and PNG plots (--plots DIR:
// COM desired vs actual, per-foot normal force in its band). Exit 0 success, 3 failed run (fell, slipped, a planner
// failed), 1 bad input.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "diagrams/walking/walking_diagram.h"
#include "examples/common/cli.h"
#include "examples/common/plot.h"
#include "framework/simulator.h"
#include "systems/plants/contact_force_statistics.h"
#include "systems/multibody/multibody_kinematics.h"

using namespace rome;

namespace {

WalkingGait ParseGait(const std::string& flag, const std::string& text) {
  std::vector<double> v;
  std::stringstream ss(text);
  std::string item;
  while (std::getline(ss, item, ',')) {
    try {
      size_t used = 0;
      v.push_back(std::stod(item, &used));
      if (used != item.size()) throw std::invalid_argument(item);
    } catch (const std::exception&) {
      throw std::invalid_argument("walking: --" + flag + " expects L,T_SSP,T_DSP,W (numbers), got '" + text + "'");
    }
  }
  if (v.size() != 4) throw std::invalid_argument("walking: --" + flag + " expects 4 numbers L,T_SSP,T_DSP,W, got '" + text + "'");
  // The range the ROM planners are built and tested for (the walking issue's gait range).
  const char* names[4] = {"step length L", "T_SSP", "T_DSP", "step width W"};
  const double lo[4] = {0.2, 0.35, 0.08, 0.2}, hi[4] = {0.45, 0.5, 0.15, 0.3};
  const char* units[4] = {"m", "s", "s", "m"};
  for (int i = 0; i < 4; ++i)
    if (!(v[i] >= lo[i] - 1e-12 && v[i] <= hi[i] + 1e-12)) {
      std::ostringstream os;
      os << "walking: --" << flag << ": " << names[i] << " = " << v[i] << " " << units[i] << " is outside [" << lo[i] << ", " << hi[i] << "] " << units[i];
      throw std::invalid_argument(os.str());
    }
  return WalkingGait{v[0], v[1], v[2], v[3]};
}

double Percentile(std::vector<double> x, double p) {
  if (x.empty()) return 0.0;
  std::sort(x.begin(), x.end());
  return x[std::min(x.size() - 1, static_cast<size_t>(p * (x.size() - 1) + 0.5))];
}

}  // namespace

int main(int argc, char** argv) {
  examples::CommandLine cli("walking", "The exoskeleton walks from standing: aSLIP + H-LIP plan, CLF-QP with force matching (walking paper).");
  cli.Option("scenario", "stand-to-walk", "stand-to-walk (standing -> transition -> gait A) | gait-change (standing -> gait A -> transition -> gait B) | periodic (started on gait A's orbit, no transition)")
      .Option("gait-a", "0.30,0.40,0.10,0.25", "gait A: step length L [m], T_SSP [s], T_DSP [s], step width W [m]")
      .Option("gait-b", "0.40,0.40,0.10,0.25", "gait B (gait-change scenario)")
      .Option("steps", "10", "periodic single supports per gait after each transition (1 to 1000)")
      .Option("force-band", "0.1", "c of the force band, Eq. (25)")
      .Option("stance-stagger", "0.40", "standing step stance: the right foot starts this far behind the left [m] (0: side by side)")
      .Option("transition-ssp", "0", "lower bound of the standing transition's single-support time [s] (0: gait A's T_SSP)")
      .Option("com-heights", "0.86,0.84,0.90", "the ROM's COM height standing, and the NLPs' height range min,max [m] (ours; spec [R] 0.9 in 0.85-0.95)")
      .Option("rom-cop-margin", "0.05", "the footed aSLIP keeps its CoP this far inside the robot's heel and toe [m]")
      .Option("foothold-tolerance", "0.05", "a touchdown counts as a step only this close to its planned foothold [m] (ours)")
      .Option("plant", "hybrid", "hybrid (event-accurate rigid contact, HybridContactPlant) | bullet (Bullet's physics world at 1 kHz, BulletWorldPlant)")
      .Option("joint-limits", "on", "on | off: the Bullet plant enforces the URDF's joint limits (the hybrid plant and the CLF-QP have none)")
      .Option("seed", "1", "seed of the NLP initial guesses")
      .Option("robot", "robots/exoskeleton/exoskeleton.rome.json", "robot sidecar (run from the repository root)")
      .Option("cache", "walking_plans", "directory of cached ROM plans")
      .Option("log", "", "CSV log file (empty: none)")
      .Option("summary", "", "JSON summary file (empty: none)")
      .Option("plots", "", "directory for PNG plots (empty: none)");
  constexpr int kTrailingSteps = 2;
  double heights[3] = {0.86, 0.84, 0.90};
  WalkingGait gait_a, gait_b;
  std::string scenario;
  int steps = 0;
  double band = 0.1, stagger = 0.4, rom_margin = 0.05, transition_ssp = 0.0, foothold_tolerance = 0.05;
  PlantKind plant_kind = PlantKind::kHybrid;
  try {
    if (!cli.Parse(argc, argv)) return 0;
    plant_kind = ParsePlantKind(cli.Get("plant"), "walking: --plant");
    if (cli.Get("joint-limits") != "on" && cli.Get("joint-limits") != "off")
      throw std::invalid_argument("walking: --joint-limits must be 'on' or 'off', got '" + cli.Get("joint-limits") + "'");
    scenario = cli.Get("scenario");
    if (scenario != "stand-to-walk" && scenario != "gait-change" && scenario != "periodic")
      throw std::invalid_argument("walking: --scenario must be stand-to-walk, gait-change or periodic, got '" + scenario + "'");
    gait_a = ParseGait("gait-a", cli.Get("gait-a"));
    gait_b = ParseGait("gait-b", cli.Get("gait-b"));
    if (scenario == "gait-change" && gait_a.step_width_m != gait_b.step_width_m)
      throw std::invalid_argument("walking: --gait-b: step width W = " + std::to_string(gait_b.step_width_m) + " m must equal gait A's " +
                                  std::to_string(gait_a.step_width_m) + " m (a change of W is not built)");
    steps = cli.GetInt("steps");
    if (steps < 1 || steps > 1000) throw std::invalid_argument("walking: --steps must be in [1, 1000], got " + cli.Get("steps"));
    stagger = cli.GetDouble("stance-stagger");
    if (!(stagger >= 0 && stagger <= 0.5)) throw std::invalid_argument("walking: --stance-stagger must be in [0, 0.5] m, got " + cli.Get("stance-stagger"));
    rom_margin = cli.GetDouble("rom-cop-margin");
    if (!(rom_margin >= 0 && rom_margin < 0.07)) throw std::invalid_argument("walking: --rom-cop-margin must be in [0, 0.07) m, got " + cli.Get("rom-cop-margin"));
    transition_ssp = cli.GetDouble("transition-ssp");
    if (!(transition_ssp == 0 || (transition_ssp >= 0.3 && transition_ssp <= 1.0)))
      throw std::invalid_argument("walking: --transition-ssp must be 0 or in [0.3, 1.0] s, got " + cli.Get("transition-ssp"));
    band = cli.GetDouble("force-band");
    if (!(band > 0 && band < 1)) throw std::invalid_argument("walking: --force-band: c = " + cli.Get("force-band") + " is outside (0, 1)");
    {
      std::stringstream ss(cli.Get("com-heights"));
      std::string item;
      int n = 0;
      while (std::getline(ss, item, ',')) {
        size_t used = 0;
        double value = std::nan("");
        try {
          value = std::stod(item, &used);
        } catch (const std::exception&) {
        }
        if (n < 3) heights[n] = used == item.size() ? value : std::nan("");
        ++n;
      }
      if (n != 3 || !(heights[1] >= 0.7 && heights[2] <= 1.0 && heights[1] < heights[2] && heights[0] >= heights[1] && heights[0] <= heights[2]))
        throw std::invalid_argument("walking: --com-heights expects H,MIN,MAX with 0.7 <= MIN <= H <= MAX <= 1.0 m and MIN < MAX, got '" +
                                    cli.Get("com-heights") + "'");
    }
    foothold_tolerance = cli.GetDouble("foothold-tolerance");
    if (!(foothold_tolerance > 0 && foothold_tolerance <= 0.5))
      throw std::invalid_argument("walking: --foothold-tolerance must be in (0, 0.5] m, got " + cli.Get("foothold-tolerance"));
    cli.CheckOutputs({"log", "summary"}, {"plots"});
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 1;
  }

  std::shared_ptr<const MultibodyModel> model;
  try {
    model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(cli.Get("robot")));
  } catch (const std::exception& e) {
    std::cerr << "walking: --robot: " << e.what() << "\n";
    return 1;
  }
  const PlanCache cache(cli.Get("cache"));
  WalkingPlanReport nlp;
  WalkingPlan plan;
  try {
    std::cout << "planning: periodic aSLIP, standing transition, footed H-LIP ...\n";
    StandToWalkParams stand;
    stand.sole = SoleOf(*model, "left_foot");
    stand.stance_stagger_m = stagger;
    stand.sagittal_cop_margin_m = rom_margin;
    stand.transition_min_ssp_duration_s = transition_ssp;
    stand.standing_height_m = heights[0];
    stand.height_min_m = heights[1];
    stand.height_max_m = heights[2];
    const auto seed = static_cast<std::uint32_t>(cli.GetInt("seed"));
    // The plan runs kTrailingSteps steps past the simulated ones, so that the last simulated steps are not the plan's
    // (and the momentum correction's) end.
    if (scenario == "periodic") plan = BuildPeriodicWalkingPlan(gait_a, steps + kTrailingSteps, seed, &cache, stand);
    else if (scenario == "gait-change") plan = BuildGaitChangePlan(gait_a, gait_b, steps, seed, &cache, &nlp, stand, steps + kTrailingSteps);
    else plan = BuildStandToWalkPlan(gait_a, steps + kTrailingSteps, seed, &cache, &nlp, stand);
  } catch (const std::exception& e) {
    std::cerr << e.what() << "\n";
    return 3;
  }
  double compensation_s = 0.0;
  WalkingDiagramParams params;
  params.controller.force_band_halfwidth = band;
  params.bullet_plant.enable_joint_limits = cli.Get("joint-limits") == "on";
  WalkingDiagram d;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    d = BuildWalkingDiagram(model, plan, params, plant_kind);
    compensation_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } catch (const std::exception& e) {
    std::cerr << "walking: " << e.what() << "\n";
    return 3;
  }
  std::printf("angular-momentum compensation: largest CoP shift in single support %.3f m -> %.3f m, COM correction up to %.3f m (%.2f s)\n",
              d.compensation.max_cop_shift_uncorrected_m, d.compensation.max_cop_shift_corrected_m, d.compensation.max_correction_m, compensation_s);
  plan = d.plan;
  Simulator sim(*d.diagram, WalkingSimulatorConfig());
  LeafContext& pc = d.diagram->GetMutableSubsystemContext(*d.plant, sim.get_mutable_context());
  // The periodic scenario starts inside the first double support, where both feet carry load (at its first instant
  // the landed foot's planned force is 0).
  const double t_init = scenario == "periodic" ? 0.5 * gait_a.dsp_duration_s : 0.0;
  sim.get_mutable_context().SetTime(t_init);
  const Eigen::VectorXd q_init = WalkingStandingPose(*model, plan, t_init);
  d.plant->SetState(pc, q_init, scenario == "periodic" ? WalkingInitialVelocity(*model, q_init, plan, t_init) : Eigen::VectorXd::Zero(model->nv()), "double_support");

  const double mg = model->total_mass() * 9.81;
  MultibodyWorkspace ws(*model);
  const int right_foot = model->BodyIndex("right_foot");
  std::ofstream log;
  if (!cli.Get("log").empty()) {
    log.open(cli.Get("log"));
    log << "t,mode,com_x,com_y,com_z,com_des_x,com_des_y,com_des_z,fz_left,fz_right,fz_ref_left,fz_ref_right,right_ankle_x,right_ankle_y,right_ankle_z,right_ankle_des_x,right_ankle_des_y,right_ankle_des_z,right_ankle_des_ax,V,delta,qp_status,left_ankle_x,left_ankle_y,left_ankle_z,left_ankle_des_x,left_ankle_des_y,left_ankle_des_z,pelvis_roll,pelvis_pitch,pelvis_yaw,qp_fz_left,qp_fz_right,fallback_band,fallback_cop,fallback_hold,right_sole_height";
    for (const ActuatorInfo& a : model->actuators()) log << ",u_" << a.joint << ",q_" << a.joint;
    log << '\n';
  }
  long tick = -1, band_ticks = 0, band_in = 0, n_err = 0;
  int touchdowns = 0, off_target_touchdowns = 0, last_mode = 1;
  double last_touchdown = -1.0, liftoff_max = 0.0, pelvis_max = 0.0, touchdown_error_max = 0.0;
  const int left_foot = model->BodyIndex("left_foot");
  Eigen::Vector2d last_fz = Eigen::Vector2d::Zero();
  Eigen::Vector3d sum_sq = Eigen::Vector3d::Zero(), err_max = Eigen::Vector3d::Zero();
  std::vector<double> solve_us, t_s, cx, cxd, cy, cyd, cz, czd, fl, fr, fl_ref, fr_ref;
  const double after_first_step = plan.segments().size() > 2 ? plan.segments()[2].start_time : 0.0;
  std::vector<std::pair<double, Eigen::Matrix<double, 6, 1>>> pre_impact;  // (touchdown time, COM state just before)
  Eigen::Matrix<double, 6, 1> last_com_state = Eigen::Matrix<double, 6, 1>::Zero();
  ContactForceStatistics contact;  // the plant's own forces after every integrator step and event
  sim.set_monitor([&](const Context& c) {
    const double t = c.time();
    const LeafContext& ctx = d.diagram->GetSubsystemContext(*d.plant, c);
    contact.Record(*d.plant, ctx);
    const int mode = d.plant->EvalTypedOutput<int>(ctx, "mode");
    const Eigen::VectorXd& f = d.plant->EvalOutput(ctx, "contact_forces");
    // A touchdown: into double support, or straight from one stance into the other. Mode 0 is left stance (the right
    // foot swings), 2 right stance. It is a step only on its planned foothold (the plan's (x, y) of that ankle).
    if ((mode == 1 && last_mode != 1) || (mode != 1 && last_mode != 1 && mode != last_mode)) {
      const bool right_landed = last_mode == 0;
      pre_impact.push_back({t, last_com_state});
      const Eigen::VectorXd& q = d.plant->EvalOutput(ctx, "q");
      const Eigen::Vector2d ankle = CalcLinkPose(*model, ws, q, right_landed ? right_foot : left_foot).translation().head<2>();
      const WalkingReference r = plan.Sample(t);
      const double error = (ankle - (right_landed ? r.right_foothold : r.left_foothold)).norm();
      touchdown_error_max = std::max(touchdown_error_max, error);
      if (error <= foothold_tolerance) ++touchdowns;
      else ++off_target_touchdowns;
      last_touchdown = t;
    }
    if (mode != 1 && last_mode == 1) liftoff_max = std::max(liftoff_max, mode == 0 ? last_fz[1] : last_fz[0]);
    last_mode = mode;
    last_fz << f[2], f[5];
    {
      // The COM state relative to the stance foot, mirrored in y for a right stance (the lateral P2 orbit alternates).
      const Eigen::VectorXd& qq = d.plant->EvalOutput(ctx, "q");
      const Eigen::VectorXd& vv = d.plant->EvalOutput(ctx, "v");
      const Eigen::Vector3d p = CalcComPosition(*model, ws, qq), v = CalcComVelocity(*model, ws, qq, vv);
      const int stance = mode == 0 ? left_foot : right_foot;
      const Eigen::Vector3d foot = CalcLinkPose(*model, ws, qq, stance).translation();
      const double mirror = mode == 0 ? 1.0 : -1.0;
      last_com_state << p.x() - foot.x(), mirror * (p.y() - foot.y()), p.z(), v.x(), mirror * v.y(), v.z();
    }
    const long k = static_cast<long>(std::floor(t * 1000.0 + 1e-9));
    if (k == tick) return EventStatus::Succeeded();
    tick = k;  // once per control tick
    const Eigen::VectorXd& q = d.plant->EvalOutput(ctx, "q");
    const Eigen::Vector3d com = CalcComPosition(*model, ws, q);
    const WalkingReference r = plan.Sample(t);
    const LeafContext& cc = d.diagram->GetSubsystemContext(*d.controller, c);
    solve_us.push_back(1e6 * d.controller->EvalOutput(cc, "solve_time_s")[0]);
    for (const char* a : {"base_roll", "base_pitch", "base_yaw"}) pelvis_max = std::max(pelvis_max, std::abs(q[model->VelocityIndex(a)]));
    if (t > after_first_step) {
      const Eigen::Vector3d e = (com - r.com_position).cwiseAbs();
      sum_sq += e.cwiseProduct(e);
      err_max = err_max.cwiseMax(e);
      ++n_err;
    }
    if (last_touchdown < 0 || t > last_touchdown + 0.02) {
      for (int foot = 0; foot < 2; ++foot) {
        const double fz = f[3 * foot + 2], ref = r.normal_force[foot];
        band_in += (fz >= (1 - band) * ref - 0.02 * mg && fz <= (1 + band) * ref + 0.02 * mg) ? 1 : 0;
        ++band_ticks;
      }
    }
    if (log.is_open())
      log << t << ',' << mode << ',' << com.x() << ',' << com.y() << ',' << com.z() << ',' << r.com_position.x() << ',' << r.com_position.y() << ','
          << r.com_position.z() << ',' << f[2] << ',' << f[5] << ',' << r.normal_force[0] << ',' << r.normal_force[1];
    if (log.is_open()) {
      const Eigen::Vector3d ankle = CalcLinkPose(*model, ws, q, right_foot).translation();
      Eigen::Vector3d p, v, a;
      d.outputs->SwingFoot(1, t, p, v, a);
      log << ',' << ankle.x() << ',' << ankle.y() << ',' << ankle.z() << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << a.x() << ',' << d.controller->EvalOutput(cc, "V")[0] << ',' << d.controller->EvalOutput(cc, "delta")[0] << ',' << d.controller->EvalOutput(cc, "qp_status")[0];
      const Eigen::Vector3d la = CalcLinkPose(*model, ws, q, left_foot).translation();
      d.outputs->SwingFoot(0, t, p, v, a);
      log << ',' << la.x() << ',' << la.y() << ',' << la.z() << ',' << p.x() << ',' << p.y() << ',' << p.z() << ',' << q[model->VelocityIndex("base_roll")] << ',' << q[model->VelocityIndex("base_pitch")] << ',' << q[model->VelocityIndex("base_yaw")];
      const Eigen::VectorXd& qf = d.controller->EvalOutput(cc, "contact_forces");
      const Eigen::VectorXd& fbk = d.controller->EvalOutput(cc, "fallbacks");
      log << ',' << qf[2] << ',' << qf[5] << ',' << fbk[0] << ',' << fbk[1] << ',' << fbk[2] << ',' << CalcContactHeight(*model, ws, q, model->ContactIndex("right_foot"));
      const Eigen::VectorXd& u = d.controller->EvalOutput(cc, "u");
      for (int j = 0; j < model->nu(); ++j) log << ',' << u[j] << ',' << q[model->actuators()[j].v_index];
      log << '\n';
    }
    t_s.push_back(t), cx.push_back(com.x()), cxd.push_back(r.com_position.x()), cy.push_back(com.y()), cyd.push_back(r.com_position.y());
    cz.push_back(com.z()), czd.push_back(r.com_position.z()), fl.push_back(f[2]), fr.push_back(f[5]);
    fl_ref.push_back(r.normal_force[0]), fr_ref.push_back(r.normal_force[1]);
    if (k % 500 == 0) std::cout << "  t = " << t << " s, steps " << touchdowns << "\n";
    return EventStatus::Succeeded();
  });
  const WalkingGait& last_gait = scenario == "gait-change" ? gait_b : gait_a;
  const double t_stop = plan.end_time() - kTrailingSteps * (last_gait.ssp_duration_s + last_gait.dsp_duration_s);
  std::cout << "simulating " << t_stop << " s on the " << ToString(plant_kind) << " plant ...\n";
  const auto wall0 = std::chrono::steady_clock::now();
  const SimulatorStatus status = sim.AdvanceTo(t_stop);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  const double t_end = sim.get_context().time();
  const LeafContext& cc = d.diagram->GetSubsystemContext(*d.controller, sim.get_context());
  const bool fell = status.kind() != SimulatorStatus::Kind::kLimit;
  // Every single support of the plan ends in a touchdown on its foothold.
  int planned_touchdowns = 0;
  std::vector<double> transition_ends;  // end of each transition's single support (footed H-LIP segments)
  for (const WalkingPlanSegment& seg : plan.segments()) {
    if (seg.domain == WalkingDomain::kDoubleSupport || seg.start_time + seg.duration > t_stop + 1e-9) continue;
    ++planned_touchdowns;
    if (seg.lateral_nodes.cols() > 0) transition_ends.push_back(seg.start_time + seg.duration);
  }
  // Convergence after each transition: the step-to-step change (2-norm) of the pre-impact COM state, from the 5th
  // periodic touchdown after it to the next transition.
  std::vector<double> change_from_step5;
  for (size_t j = 0; j < transition_ends.size(); ++j) {
    const double begin = transition_ends[j] - 0.05, end = j + 1 < transition_ends.size() ? transition_ends[j + 1] - 0.05 : 1e9;
    std::vector<Eigen::Matrix<double, 6, 1>> states;
    for (const auto& [time, state] : pre_impact)
      if (time > begin && time < end) states.push_back(state);
    double worst = -1.0;  // states[0] is the transition's own touchdown; states[k] the k-th periodic one
    for (size_t k = 5; k < states.size(); ++k) worst = std::max(worst, (states[k] - states[k - 1]).norm());
    change_from_step5.push_back(worst);
  }
  const bool success = !fell && touchdowns >= planned_touchdowns && off_target_touchdowns == 0 && contact.violations == 0;
  Eigen::Vector3d rms = Eigen::Vector3d::Zero();
  if (n_err > 0) rms = (sum_sq / static_cast<double>(n_err)).cwiseSqrt();
  const Eigen::VectorXd& fb = d.controller->EvalOutput(cc, "fallbacks");
  nlohmann::json s;
  s["success"] = success;
  s["status_kind"] = fell ? "failed" : "limit";
  s["status"] = status.ToString();
  s["fell"] = fell;
  s["steps_completed"] = touchdowns;
  s["steps_planned"] = planned_touchdowns;
  s["pre_impact_state_change_from_step5"] = change_from_step5;  // per transition; -1: fewer than 6 touchdowns after it
  // Each touchdown's pre-impact COM state about the stance ankle, y mirrored in right stance: [t, x, y, z, ẋ, ẏ, ż].
  s["pre_impact_states"] = nlohmann::json::array();
  for (const auto& [time, state] : pre_impact) {
    nlohmann::json row = {time};
    for (int i = 0; i < 6; ++i) row.push_back(state[i]);
    s["pre_impact_states"].push_back(row);
  }
  s["touchdowns_off_target"] = off_target_touchdowns;
  s["largest_touchdown_error_m"] = touchdown_error_max;
  s["com_rms_error_m"] = {rms.x(), rms.y(), rms.z()};
  s["com_max_error_m"] = {err_max.x(), err_max.y(), err_max.z()};
  s["pelvis_max_orientation_error_rad"] = pelvis_max;
  s["force_in_band_fraction"] = band_ticks ? static_cast<double>(band_in) / band_ticks : 0.0;
  s["liftoff_normal_force_max_N"] = liftoff_max;
  s["contact_violations"] = contact.violations;
  s["first_contact_violation"] = contact.first_violation;
  s["min_stance_normal_force_N"] = contact.samples > 0 ? contact.min_normal_force_N : 0.0;
  s["max_friction_ratio"] = contact.max_friction_ratio;
  s["qp_infeasible_ticks"] = d.controller->EvalOutput(cc, "qp_failures")[0];
  s["qp_fallbacks"] = fb.sum();
  s["qp_solve_us_median"] = Percentile(solve_us, 0.5);
  s["qp_solve_us_p99"] = Percentile(solve_us, 0.99);
  auto nlp_json = [](const WalkingNlpReport& r) { return nlohmann::json{{"solve_s", r.solve_s}, {"iterations", r.iterations}, {"constraint_violation", r.violation}}; };
  s["nlp"] = {{"periodic_aslip_a", nlp_json(nlp.periodic)}, {"transition_aslip", nlp_json(nlp.transition)}};
  if (scenario == "gait-change") s["nlp"]["periodic_aslip_b"] = nlp_json(nlp.periodic_b), s["nlp"]["transition_aslip_a_to_b"] = nlp_json(nlp.transition_b);
  s["scenario"] = scenario;
  s["angular_momentum_compensation"] = {{"max_cop_shift_uncorrected_m", d.compensation.max_cop_shift_uncorrected_m},
                                        {"max_cop_shift_corrected_m", d.compensation.max_cop_shift_corrected_m},
                                        {"max_com_correction_m", d.compensation.max_correction_m},
                                        {"solve_s", compensation_s}};
  s["realtime_factor"] = wall > 0 ? t_end / wall : 0.0;
  s["simulated_s"] = t_end;
  s["plant"] = ToString(plant_kind);
  if (!cli.Get("summary").empty()) std::ofstream(cli.Get("summary")) << s.dump(2) << "\n";
  if (!cli.Get("plots").empty()) {
    std::string err;
    const std::string dir = cli.Get("plots");
    examples::PlotSpec com{"COM desired vs actual (Fig. 5a)", "t [s]", "m", {{"x", t_s, cx}, {"x desired", t_s, cxd}, {"y", t_s, cy}, {"y desired", t_s, cyd},
                                                                          {"z", t_s, cz}, {"z desired", t_s, czd}}};
    if (!examples::WritePlot(com, dir + "/com.png", &err)) std::cerr << "plot: " << err << "\n";
    examples::PlotSpec force{"plant normal forces and the aSLIP reference (Fig. 5d)", "t [s]", "N",
                             {{"left", t_s, fl}, {"left reference", t_s, fl_ref}, {"right", t_s, fr}, {"right reference", t_s, fr_ref}}};
    if (!examples::WritePlot(force, dir + "/normal_forces.png", &err)) std::cerr << "plot: " << err << "\n";
  }
  std::cout << (success ? "walked" : "FAILED") << ": " << status.ToString() << "\n  " << touchdowns << " steps (" << off_target_touchdowns << " touchdowns off their footholds, largest error "
            << touchdown_error_max << " m), COM RMS error (after the first step) "
            << rms.transpose() << " m, force in band " << s["force_in_band_fraction"] << ", real-time factor " << s["realtime_factor"] << "\n  plant "
            << ToString(plant_kind) << ": contact violations " << contact.violations << " (" << contact.samples << " samples)"
            << (contact.violations ? ", first: " + contact.first_violation : "") << ", max |F_t|/F_n " << contact.max_friction_ratio << "\n";
  return success ? 0 : 3;
}
