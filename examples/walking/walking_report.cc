#include "examples/walking/walking_report.h"

#include <chrono>
#include <cstdio>
#include <iostream>
#include <stdexcept>

namespace rome::examples {

void PrintPlanReport(const WalkingPlanReport& nlp, const StandToWalkParams& stand) {
  const double stagger = stand.stance_stagger_m;
  if (nlp.start_gait_used)
    std::cout << (stagger == 0 ? std::string("standing side by side: ")
                               : "standing in a " + std::to_string(stagger) + " m step stance: ")
              << stand.start_gait_steps << " steps of the start gait (" << nlp.start_gait.step_length_m << " m, "
              << nlp.start_gait.ssp_duration_s << " s, " << nlp.start_gait.dsp_duration_s
              << " s), then a gait change\n";
  if (nlp.lead_in)
    std::cout << "starting with " << stand.lead_in_steps << " lead-in steps of (" << nlp.lead_in_gait.step_length_m
              << " m, " << nlp.lead_in_gait.ssp_duration_s << " s, " << nlp.lead_in_gait.dsp_duration_s
              << " s) and changing gait: " << nlp.lead_in_reason << "\n";
  else if (!nlp.lead_in_reason.empty())
    std::cout << "the lead-in " << nlp.lead_in_reason << "\n";
  if (nlp.start_chain.size() > 2) {
    std::cout << "no direct start gait -> gait A transition: through the gait graph:";
    for (const WalkingGait& g : nlp.start_chain)
      std::cout << " (" << g.step_length_m << ", " << g.ssp_duration_s << ", " << g.dsp_duration_s << ", "
                << g.step_width_m << ")";
    std::cout << "\n";
  }
  for (const WalkingChangeRefusal& r : nlp.refused_changes)
    std::cout << "refused before simulating (force bound " << r.max_force_fraction << " m g): " << r.problem << "\n";
  if (nlp.chain.size() > 2) {
    std::cout << "no direct A -> B transition: through the gait graph (" << nlp.chain_transitions_tried
              << " transitions tried, " << nlp.chain_transitions_failed << " without a plan, " << nlp.chain_planning_s
              << " s):";
    for (const WalkingGait& g : nlp.chain)
      std::cout << " (" << g.step_length_m << ", " << g.ssp_duration_s << ", " << g.dsp_duration_s << ", "
                << g.step_width_m << ")";
    std::cout << "\n";
  }
}

nlohmann::json PlanTorqueReport(const WalkingDiagram& d, const WalkingDiagramParams& params, double t_stop) {
  const MultibodyModel& model = *d.model;
  try {
    const auto t0 = std::chrono::steady_clock::now();
    const WalkingPlanTorqueReport r = CheckWalkingPlanTorques(model, d.plan, params, t_stop);
    const double solve_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (r.worst_actuator < 0) throw std::runtime_error("the plan has no single-support sample");
    const ActuatorInfo& worst = model.actuators()[r.worst_actuator];
    std::printf(
        "plan inverse dynamics (%d single-support samples): largest torque for its limit %s %.0f of %.0f N m at t = "
        "%.3f s, "
        "peak stance F_z %.2f m g (%.2f s)\n",
        r.samples, worst.joint.c_str(), r.peak_torque_Nm[r.worst_actuator], worst.torque_limit_Nm,
        r.peak_time_s[r.worst_actuator], r.peak_normal_force_N / (model.total_mass() * 9.81), solve_s);
    std::printf(
        "plan inverse dynamics: the stance sole needs |F_t|/F_n up to %.2f (t = %.3f s), its CoP up to %.3f m (x) / "
        "%.3f m (y) "
        "from the ankle, |M_z|/F_n up to %.3f m\n",
        r.peak_friction_ratio, r.peak_friction_ratio_time_s, r.peak_cop_offset_m.x(), r.peak_cop_offset_m.y(),
        r.peak_yaw_moment_ratio_m);
    if (r.worst_limit_fraction > 1.0)
      std::printf(
          "warning: the plan asks %s for %.0f N m, above its %.0f N m limit; the CLF-QP keeps torques within the "
          "limits, so it cannot follow the plan exactly there\n",
          worst.joint.c_str(), r.peak_torque_Nm[r.worst_actuator], worst.torque_limit_Nm);
    nlohmann::json peaks = nlohmann::json::object();
    for (int j = 0; j < model.nu(); ++j) peaks[model.actuators()[j].joint] = r.peak_torque_Nm[j];
    return {{"peak_torque_Nm", peaks},
            {"worst_joint", worst.joint},
            {"worst_limit_fraction", r.worst_limit_fraction},
            {"worst_time_s", r.peak_time_s[r.worst_actuator]},
            {"peak_normal_force_N", r.peak_normal_force_N},
            {"peak_friction_ratio", r.peak_friction_ratio},
            {"peak_friction_ratio_time_s", r.peak_friction_ratio_time_s},
            {"peak_cop_offset_m", {r.peak_cop_offset_m.x(), r.peak_cop_offset_m.y()}},
            {"peak_yaw_moment_ratio_m", r.peak_yaw_moment_ratio_m},
            {"samples", r.samples},
            {"solve_s", solve_s}};
  } catch (const std::exception& e) {
    std::printf("warning: plan inverse dynamics not available: %s\n", e.what());
    return nullptr;
  }
}

nlohmann::json WalkingSummary(const WalkingRunResult& run, const WalkingDiagram& d, const WalkingPlanReport& nlp,
                              const std::string& scenario_name, const StandToWalkParams& stand, double compensation_s,
                              const nlohmann::json& plan_torques, PlantKind plant, const nlohmann::json& scenario) {
  nlohmann::json s = nlohmann::json::parse(run.ToJson());
  // walk-to-stand plans as gait-change with the stop gait as gait B.
  const bool changes =
      scenario_name == "gait-change" || scenario_name == "gait-sequence" || scenario_name == "walk-to-stand";
  auto nlp_json = [](const WalkingNlpReport& r) {
    return nlohmann::json{{"solve_s", r.solve_s}, {"iterations", r.iterations}, {"constraint_violation", r.violation}};
  };
  s["nlp"] = {{"periodic_aslip_a", nlp_json(nlp.periodic)}, {"transition_aslip", nlp_json(nlp.transition)}};
  if (changes)
    s["nlp"]["periodic_aslip_b"] = nlp_json(nlp.periodic_b),
    s["nlp"]["transition_aslip_a_to_b"] = nlp_json(nlp.transition_b);
  // gait-change / gait-sequence / walk-to-stand: the gaits walked from gait A on (A and B alone: the direct
  // transition), with any chain's intermediate gaits, and the chain searches' time. stand-to-walk: gait A alone, or
  // the lead-in and gait A (with any chain between them); its start gait's change (and chain) is start_gait_chain.
  s["gait_chain"] = nullptr;
  if (changes || scenario_name == "stand-to-walk") {
    const auto list = [](const std::vector<WalkingGait>& chain) {
      nlohmann::json gaits = nlohmann::json::array();
      for (const WalkingGait& g : chain)
        gaits.push_back({g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m});
      return gaits;
    };
    // start_gait_chain: the start gait's change into gait A (2 gaits: direct; empty: no start gait).
    s["gait_chain"] = {{"gaits", list(nlp.chain)},
                       {"start_gait_chain", list(nlp.start_gait_used ? nlp.start_chain : std::vector<WalkingGait>{})},
                       {"planning_s", nlp.chain_planning_s},
                       {"transitions_tried", nlp.chain_transitions_tried},
                       {"transitions_failed", nlp.chain_transitions_failed}};
    // Transitions planned and refused by the feasibility check before simulating (StandToWalkParams::change_check):
    // then planned again with a tighter force bound or chained.
    nlohmann::json refused = nlohmann::json::array();
    for (const WalkingChangeRefusal& r : nlp.refused_changes)
      refused.push_back({{"from", list({r.from})[0]},
                         {"to", list({r.to})[0]},
                         {"max_force_fraction", r.max_force_fraction},
                         {"problem", r.problem}});
    s["gait_chain"]["refused_transitions"] = refused;
  }
  // stand-to-walk with a lead-in: periodic_aslip_a / transition_aslip are the lead-in gait's, then its change to gait
  // A.
  s["lead_in"] = nullptr;
  // A lead-in that was tried, had no plan, and left the plan to the direct change from the start gait: its error.
  s["lead_in_tried"] =
      !nlp.lead_in && !nlp.lead_in_reason.empty() ? nlohmann::json(nlp.lead_in_reason) : nlohmann::json(nullptr);
  if (nlp.lead_in) {
    const WalkingGait& g = nlp.lead_in_gait;
    s["lead_in"] = {{"gait", {g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m}},
                    {"reason", nlp.lead_in_reason}};
    s["nlp"]["periodic_aslip_gait_a"] = nlp_json(nlp.periodic_b),
    s["nlp"]["transition_aslip_lead_in_to_a"] = nlp_json(nlp.transition_b);
  }
  // Standing side by side: the standing transition (transition_aslip) goes into the start gait, which changes into the
  // next gait (the lead-in, or gait A).
  s["start_gait"] = nullptr;
  if (nlp.start_gait_used) {
    const WalkingGait& g = nlp.start_gait;
    s["start_gait"] = {{"gait", {g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m}},
                       {"steps", stand.start_gait_steps}};
    s["nlp"]["periodic_aslip_start_gait"] = nlp_json(nlp.periodic_start),
    s["nlp"]["transition_aslip_start_to_next"] = nlp_json(nlp.transition_start);
  }
  s["stance_stagger_m"] = stand.stance_stagger_m;
  s["scenario"] = scenario;
  s["angular_momentum_compensation"] = {{"max_cop_shift_uncorrected_m", d.compensation.max_cop_shift_uncorrected_m},
                                        {"max_cop_shift_corrected_m", d.compensation.max_cop_shift_corrected_m},
                                        {"max_com_correction_m", d.compensation.max_correction_m},
                                        {"solve_s", compensation_s}};
  s["plan_inverse_dynamics"] = plan_torques;
  s["plant"] = ToString(plant);
  s["plant_base"] = ToString(d.euler_state ? PlantBase::kQuaternion : PlantBase::kEuler);
  return s;
}

void PrintRunResult(const WalkingRunResult& r, PlantKind plant) {
  std::cout << (r.success ? "walked" : "FAILED") << ": " << r.status.ToString() << "\n  " << r.steps_completed
            << " steps (" << r.touchdowns_off_target << " touchdowns off their footholds, largest error "
            << r.largest_touchdown_error_m << " m), COM RMS error (after the first step) "
            << r.com_rms_error_m.transpose() << " m, force in band " << nlohmann::json(r.force_in_band_fraction)
            << " (strictly " << nlohmann::json(r.force_in_band_fraction_strict) << "), real-time factor "
            << nlohmann::json(r.realtime_factor()) << "\n  plant " << ToString(plant) << ": contact violations "
            << r.contact.violations << " (" << r.contact.samples << " samples)"
            << (r.contact.violations ? ", first: " + r.contact.first_violation : "") << ", max |F_t|/F_n "
            << r.contact.max_friction_ratio << "\n  joint limits: smallest margin " << r.joint_limit_min_margin << " ("
            << r.joint_limit_min_margin_at << "), samples beyond a limit " << r.joint_limits.violations
            << (r.joint_limits.violations ? ", first: " + r.joint_limits.first_violation : "") << "\n";
}

}  // namespace rome::examples
