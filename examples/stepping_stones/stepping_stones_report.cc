#include "examples/stepping_stones/stepping_stones_report.h"

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

#include "framework/files.h"
#include "framework/interrupt.h"
#include "systems/plants/contact_plant.h"
#include "systems/visualization/plot.h"
#include "systems/visualization/stick_figure.h"

namespace rome::examples {

nlohmann::json SteppingStonesSummary(const SteppingStonesResult& r, const SteppingStonesScenario& scenario,
                                     const CommandLine& cli) {
  nlohmann::json step_list = nlohmann::json::array();
  for (const StepRecord& s : r.steps)
    step_list.push_back({{"l", s.step_length_m},
                         {"h", s.step_height_m},
                         {"duration_s", s.duration_s},
                         {"pre_impact_com_vz_mps", s.pre_impact_com_vz_mps},
                         {"u_des_mps", s.u_des_mps},
                         {"post_impact_momentum", s.post_impact_momentum},
                         {"L_des", s.L_des},
                         {"foothold_error_m", s.foothold_error_m},
                         {"stone", s.stone},
                         {"planned_stone", s.planned_stone},
                         {"posture_ok", s.posture_ok}});
  nlohmann::json clf_activity = nullptr;
  if (r.has_clf_activity)
    clf_activity = {{"active_updates", r.clf_active_updates},
                    {"solved_updates", r.clf_solved_updates},
                    {"active_fraction", r.clf_solved_updates > 0 ? r.clf_active_updates / r.clf_solved_updates : 0.0}};
  nlohmann::json stone_list = nlohmann::json::array();
  for (const auto& st : scenario.terrain.stones()) stone_list.push_back({st.x_center_m, st.top_height_m, st.length_m});
  return {{"success", r.success},
          {"status_kind", r.status.kind_name()},
          {"controller", r.controller_kind},
          {"plant", ToString(scenario.plant)},
          {"steps_completed", r.steps.size()},
          {"fell", r.fell},
          {"fall_reason", r.fell ? r.status.message : ""},
          {"status", r.status.ToString()},
          {"min_stance_normal_force_N", r.contact.samples > 0 ? r.contact.min_normal_force_N : 0.0},
          {"max_friction_ratio", r.contact.max_friction_ratio},
          {"contact_violations", r.contact.violations},
          {"first_contact_violation", r.contact.first_violation},
          {"tracking_rms",
           {{"torso_pitch_rad", r.tracking_torso_pitch_rms_rad},
            {"com_height_m", r.tracking_com_height_rms_m},
            {"swing_foot_m", r.tracking_swing_foot_rms_m}}},
          {"u_squared_integral_per_step_N2m2s", r.u_squared_integral_per_step()},
          {"controller_update_us",
           {{"median", 1e6 * r.ControllerUpdateTime(0.5)},
            {"p99", 1e6 * r.ControllerUpdateTime(0.99)},
            {"updates", r.controller_update_times_s.size()}}},
          {"sim_time_s", r.sim_time_s},
          {"wall_time_s", r.wall_time_s},
          {"realtime_factor", r.wall_time_s > 0 ? r.sim_time_s / r.wall_time_s : 0.0},
          {"mean_forward_speed_mps", r.mean_forward_speed_mps()},
          {"max_foothold_error_m", r.max_foothold_error_m},
          {"qp_failures", r.qp_failures},
          {"clf_row_activity", clf_activity},
          {"nlp_failures", r.nlp_failures},
          {"energy", scenario.params.target_orbital_energy},
          {"epsilon", scenario.params.impact_fraction},
          {"terrain", cli.Get("terrain")},
          {"seed", cli.GetInt("seed")},
          {"steps", step_list},
          {"integrator",
           {{"steps", r.integrator.steps},
            {"rhs_evaluations", r.integrator.rhs_evals},
            {"root_evaluations", r.integrator.root_evals},
            {"guard_events", r.integrator.guard_events},
            {"discrete_samples", r.integrator.discrete_samples}}},
          {"stones", stone_list},
          {"scenario", nlohmann::json::parse(cli.ScenarioJson())}};
}

namespace {

bool IsStance(double mode) {
  return mode == ContactModeGraph::SingleSupportMode::kLeftStance ||
         mode == ContactModeGraph::SingleSupportMode::kRightStance;
}

// Fig. 5 of the paper from the log: outputs.png (torso pitch and COM height above the stance foot, desired against
// actual; the COM's vertical velocity against the planner's u_des(t), pre-impact instants marked) and
// pre_impact_vz.png / pre_impact_vz.csv (per step: the plant's ż at the last logged sample before the stance switch
// against the planner's u_des at that sample). The pre-impact sample lies at most one log period before the impact;
// a run that ends at its last touchdown logs no switch for that step.
void WriteFig5Plots(const SteppingStonesDiagram& d, const LogData& log, const std::string& dir) {
  const int mode = d.logger->ColumnIndex("plant.mode"), com_z = d.logger->ColumnIndex("plant.com.z"),
            com_vz = d.logger->ColumnIndex("plant.com.vz");
  const int u_des = d.logger->ColumnIndex("planner.u_des[0]"), rel_z = d.logger->ColumnIndex("supervisor.com_state.z");
  const int z_d = d.logger->ColumnIndex("outputs.y_desired.com_z"),
            phi_d = d.logger->ColumnIndex("outputs.y_desired.torso_pitch");
  // The supervisor's torso pitch is the planar base pitch, q[2] (SteppingStonesSupervisor).
  const int phi = d.logger->ColumnIndex("plant.state.q_" + d.model->JointName(2));
  using visualization::Series;
  Series phi_act{"actual", {}, {}}, phi_des{"desired", {}, {}, "lines dt 2 lw 2"}, z_act{"actual", {}, {}},
      z_des{"desired", {}, {}, "lines dt 2 lw 2"};
  Series vz{"plant", {}, {}}, ud{"u_des(t), planner", {}, {}, "lines dt 2 lw 2"};
  Series pre{"COM vz before impact (plant)", {}, {}, "linespoints pt 7"},
      pre_u{"u_des (planner)", {}, {}, "linespoints pt 4 dt 2"};
  Series pre_t{"pre-impact", {}, {}, "points pt 7 ps 1.5"};
  std::ostringstream csv;
  csv << "step,time_s,com_vz_mps,u_des_mps,com_vz_finite_difference_mps\n";
  const size_t n = log.times.size();
  int step = 0;
  for (size_t k = 0; k < n; ++k) {
    const Eigen::VectorXd& s = log.samples[k];
    const double t = log.times[k];
    phi_act.x.push_back(t), phi_act.y.push_back(1e3 * s[phi]), phi_des.x.push_back(t),
        phi_des.y.push_back(1e3 * s[phi_d]);
    z_act.x.push_back(t), z_act.y.push_back(s[rel_z]), z_des.x.push_back(t), z_des.y.push_back(s[z_d]);
    vz.x.push_back(t), vz.y.push_back(s[com_vz]), ud.x.push_back(t), ud.y.push_back(s[u_des]);
    // A touchdown: one stance mode here, the other at the next sample.
    if (k == 0 || k + 1 >= n || !IsStance(s[mode]) || !IsStance(log.samples[k + 1][mode]) ||
        log.samples[k + 1][mode] == s[mode])
      continue;
    // Backward difference of the logged COM height: a check of the plant's ż that does not use its velocity.
    const double fd = (s[com_z] - log.samples[k - 1][com_z]) / (t - log.times[k - 1]);
    ++step;
    pre.x.push_back(step), pre.y.push_back(s[com_vz]), pre_u.x.push_back(step), pre_u.y.push_back(s[u_des]);
    pre_t.x.push_back(t), pre_t.y.push_back(s[com_vz]);
    csv << step << "," << FormatNumber(t) << "," << FormatNumber(s[com_vz]) << "," << FormatNumber(s[u_des]) << ","
        << FormatNumber(fd) << "\n";
  }
  try {
    WriteFileAtomically(dir + "/pre_impact_vz.csv", csv.str(), "pre-impact CSV");
  } catch (const std::exception& e) { std::cerr << "warning: " << e.what() << "\n"; }
  std::string err;
  std::vector<visualization::PlotSpec> panels{
      {"Fig. 5: torso pitch", "time [s]", "pitch [mrad]", {phi_act, phi_des}},
      {"Fig. 5: COM height above the stance foot", "time [s]", "z [m]", {z_act, z_des}},
      {"Fig. 5: COM vertical velocity and the planner's u_des",
       "time [s]",
       "vertical velocity [m/s]",
       {vz, ud, pre_t}}};
  for (auto& p : panels) p.height_px = 330;
  if (!visualization::WritePanels(panels, dir + "/outputs.png", &err)) std::cerr << "warning: " << err << "\n";
  visualization::PlotSpec per_step{
      "Fig. 5: pre-impact COM vertical velocity per step", "step", "vertical velocity [m/s]", {pre, pre_u}};
  per_step.width_px = 1100;
  if (!visualization::WritePlot(per_step, dir + "/pre_impact_vz.png", &err)) std::cerr << "warning: " << err << "\n";
}

}  // namespace

void WriteSteppingStonesPlots(const SteppingStonesDiagram& d, const Context& context,
                              const SteppingStonesScenario& scenario, const std::string& energy_label,
                              const std::string& dir) {
  std::filesystem::create_directories(dir);
  const LogData& log = d.logger->log(d.diagram->GetSubsystemContext(*d.logger, context));
  const int com_z = d.logger->ColumnIndex("plant.com.z");
  const int nv = d.model->nv();
  const int rel_x = d.logger->ColumnIndex("supervisor.com_state.x"),
            rel_z = d.logger->ColumnIndex("supervisor.com_state.z");
  const int L_col = d.logger->ColumnIndex("supervisor.angular_momentum.L");
  const int q0 = d.logger->ColumnIndex("plant.state.q_" + d.model->JointName(0));
  std::string err;
  // COM height over time.
  visualization::Series zc{"COM height (world)", {}, {}, "lines"};
  for (size_t k = 0; k < log.times.size(); ++k) {
    zc.x.push_back(log.times[k]);
    zc.y.push_back(log.samples[k][com_z]);
  }
  if (!visualization::WritePlot({"COM height", "time [s]", "z [m]", {zc}}, dir + "/com_height.png", &err))
    std::cerr << "warning: " << err << "\n";
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
    orbit.y.push_back(z0 * std::sqrt(scenario.params.target_orbital_energy + lambda2 * x * x));
  }
  if (!visualization::WritePlot(
          {"Phase portrait, E* = " + energy_label, "p_com^x relative to stance foot [m]", "L_y [m^2/s]", {ph, orbit}},
          dir + "/phase_portrait.png", &err))
    std::cerr << "warning: " << err << "\n";
  // Gait tiles: stick figures every 0.1 s over the stones.
  MultibodyWorkspace ws(*d.model);
  visualization::Series sticks{"robot", {}, {}, "lines lc rgb '#3060c0'"},
      stones{"stones", {}, {}, "lines lw 6 lc rgb '#808080'"};
  for (const auto& s : scenario.terrain.stones()) {
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
  WriteFig5Plots(d, log, dir);
}

int PrintSteppingStonesReport(const SteppingStonesResult& r, const SteppingStonesScenario& scenario) {
  const double speedup = r.wall_time_s > 0 ? r.sim_time_s / r.wall_time_s : 0;
  std::cout << "\n"
            << r.status.ToString() << "\n"
            << r.steps.size() << " of " << scenario.steps << " steps" << (r.fell ? " (fell)" : "") << ", "
            << r.sim_time_s << " s simulated in " << r.wall_time_s << " s wall (" << speedup
            << "x real time), controller " << r.controller_kind << ", plant " << ToString(scenario.plant) << "\n"
            << "mean forward speed " << r.mean_forward_speed_mps() << " m/s, largest foothold error "
            << r.max_foothold_error_m * 100 << " cm, QP failures " << r.qp_failures
            << (r.has_clf_activity
                    ? ", CLF row active in " +
                          FormatNumber(100.0 *
                                       (r.clf_solved_updates > 0 ? r.clf_active_updates / r.clf_solved_updates : 0.0)) +
                          " % of updates"
                    : std::string())
            << ", NLP failures " << r.nlp_failures << "\n"
            << "plant contact forces: min stance F_n " << (r.contact.samples > 0 ? r.contact.min_normal_force_N : 0.0)
            << " N, max |F_t|/F_n " << r.contact.max_friction_ratio << ", violations " << r.contact.violations << " of "
            << r.contact.samples << " samples\n";
  if (r.status.kind() == SimulatorStatus::Kind::kInterrupted) {
    std::cout << "result: interrupted (" << r.status.ToString() << "); outputs written up to there\n";
    return 128 + InterruptSignal();
  }
  if (r.success) {
    std::cout << "result: success (" << r.status.message << ")\n";
    return 0;
  }
  std::cout << "result: failed run ("
            << (r.contact.violations > 0 ? "contact violation: " + r.contact.first_violation
                                         : r.status.kind_name() + ": " + r.status.ToString())
            << ")\n";
  return 3;
}

}  // namespace rome::examples
