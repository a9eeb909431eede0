// hopping: Cassie hops on the spring-mass ROM's plans (hopping paper: jump NLP Eq. (14)-(15), landing NLP Eq. (16),
// Jump/Flight/Landing CLF-QP with the augmented input Eq. (45)-(51)). 3D Cassie with live springs and achilles rods.
//
// Writes a CSV log (--log), a JSON summary (--summary) and PNG plots (--plots DIR), the paper's Fig. 6 from our run:
// robot vs ROM normal GRF, COM height, shin spring torque against the GRF, centroidal pitch momentum, pelvis pitch,
// desired vs actual outputs in Jump and Landing (leg length, COM x, pelvis pitch), energies robot vs ROM, hop tiles.
// Exit 0: hopped (the COM rose at least H/2) and came to rest; 3: the run failed (fell, slipped, a planner gave up:
// Ipopt's status in the message); 1: bad input.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>

#include <nlohmann/json.hpp>

#include "diagrams/hopping/hopping_diagram.h"
#include "diagrams/hopping/hopping_plans.h"
#include "examples/common/cli.h"
#include "systems/visualization/animation.h"
#include "systems/visualization/plot.h"
#include "systems/visualization/stick_figure.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/robot_files.h"
#include "systems/plants/contact_force_statistics.h"
#include "systems/rom/cassie_leg_stiffness.h"
#include "framework/interrupt.h"

using namespace rome;

namespace {

double Percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<size_t>(p * (v.size() - 1) + 0.5))];
}

double Nrmse(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.empty()) return NAN;
  double se = 0, peak = 0;
  for (size_t i = 0; i < a.size(); ++i) se += (a[i] - b[i]) * (a[i] - b[i]), peak = std::max(peak, std::abs(b[i]));
  return std::sqrt(se / a.size()) / std::max(peak, 1e-9);
}

double Correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  if (n < 2) return NAN;
  double ma = 0, mb = 0;
  for (size_t i = 0; i < a.size(); ++i) ma += a[i] / n, mb += b[i] / n;
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < a.size(); ++i) sab += (a[i] - ma) * (b[i] - mb), saa += (a[i] - ma) * (a[i] - ma), sbb += (b[i] - mb) * (b[i] - mb);
  return sab / std::sqrt(saa * sbb);
}

}  // namespace

int main(int argc, char** argv) {
  examples::CommandLine cli("hopping", "Cassie hops on the spring-mass ROM's jump and landing plans (hopping paper).");
  cli.Option("apex-rise", examples::FormatNumber(SpringMassJumpParams{}.apex_rise),
             "H [m]: COM rise above the take-off height (default: the ROM's air time is 0.423 s with the identified K(L))")
      .Option("leg-stiffness", "identified", "K(L), D(L) of the ROM: published (walking paper) or identified (Eq. (4)-(13) on our model)")
      .Option("hops", "1", "number of hops (1 to 1000); the landing of one hop is the crouch of the next (a bounce off the ground after a landing counts as a hop)")
      .Option("plant", "hybrid", "hybrid (event-accurate rigid contact, HybridContactPlant) | bullet (Bullet's physics world at 2 kHz, BulletWorldPlant)")
      .Option("bullet-substeps", std::to_string(HoppingDiagramParams::DefaultBulletPlantParams().substeps),
              "Bullet plant: Bullet steps per 0.5 ms plant step (1 to 100); the springs' torques are recomputed at each")
      .Option("jump-momentum-gain", examples::FormatNumber(HoppingDiagramParams::DefaultReferenceParams().jump_momentum_gain),
              "k [-] of the Jump pitch reference, theta_dot_d = theta_dot - k H_pitch / I_p (0: hold the pitch; HoppingReferenceParams)")
      .Option("flight-hip-follow", examples::FormatNumber(HoppingDiagramParams::DefaultReferenceParams().flight_hip_pitch_follow),
              "k [-]: in Flight the hip-pitch targets turn with the pelvis pitch, q_hip_d = q_hip_lo - k r (theta - theta_lo) (HoppingReferenceParams)")
      .Option("landing-deflection-feedback", examples::FormatNumber(HoppingDiagramParams::DefaultReferenceParams().landing_deflection_feedback),
              "g [-]: Landing leg-length target L_plan + g (x - x_plan), so the spring deflection follows the plan's (0: off; HoppingReferenceParams)")
      .Option("jump-force-feedback", examples::FormatNumber(HoppingDiagramParams::DefaultReferenceParams().jump_force_feedback),
              "k_F [-]: Jump leg-length target L_plan + k_F (F_plan - F) / (n K(L)), F the plant's normal GRF (0: off; HoppingReferenceParams)")
      .Option("jump-force-integral", examples::FormatNumber(HoppingDiagramParams::DefaultReferenceParams().jump_force_integral_per_s),
              "k_I [1/s]: Jump leg-length target also + integral of k_I (F_plan - F) / (n K(L)) dt (0: off; HoppingReferenceParams)")
      .Option("landing-torque-regularization", examples::FormatNumber(HoppingDiagramParams{}.landing_u_regularization_scale),
              "[-] the CLF-QP's torque penalty rho_u is multiplied by this in Landing (1: off; HoppingDiagramParams)")
      .Option("landing-min-force", examples::FormatNumber(SpringMassLandingParams{}.min_force_fraction),
              "F_min / (m g) [-]: the landing plan's smallest leg force (spec [R] 0.25)")
      .Option("landing-blend", examples::FormatNumber(HoppingDiagramParams::DefaultReferenceParams().landing_blend_s),
              "[s] Landing: duration of the COM-x and pitch quintics to the support centre and 0 (spec [R] 0.3 s)")
      .Option("duration", "0", "[s] simulated time; 0: until 2.5 s after the last hop's touchdown (rest is judged 2 s after it: a shorter run is not 'settled')")
      .Option("log", "", "CSV log path (empty: none)")
      .Option("summary", "", "JSON summary path (empty: none)")
      .Option("plots", "", "directory for PNG plots (empty: none)")
      .Option("animation", "", "FILE.html: a self-contained 3D animation of the run (three.js inlined; empty: none)");
  double apex_rise = 0;
  int hops = 0;
  LegStiffnessVariant variant = LegStiffnessVariant::kIdentified;
  PlantKind plant_kind = PlantKind::kHybrid;
  int substeps = HoppingDiagramParams::DefaultBulletPlantParams().substeps;
  double jump_momentum_gain = 0, flight_hip_follow = 0, landing_blend = 0, deflection_feedback = 0, force_feedback = 0, force_integral = 0, landing_reg = 1;
  SpringMassLandingParams landing_params;
  std::shared_ptr<const MultibodyModel> model;
  try {
    if (!cli.Parse(argc, argv)) return 0;
    InstallInterruptHandlers();  // SIGINT/SIGTERM: the run stops, its outputs are written, exit 128 + signal
    plant_kind = ParsePlantKind(cli.Get("plant"), "--plant");
    substeps = cli.GetInt("bullet-substeps");
    if (substeps < 1 || substeps > 100) throw std::invalid_argument("--bullet-substeps " + cli.Get("bullet-substeps") + ": must be in [1, 100]");
    apex_rise = cli.GetDouble("apex-rise");
    hops = cli.GetInt("hops");
    if (!(apex_rise > 0.0 && apex_rise <= 0.35))
      throw std::invalid_argument("--apex-rise " + cli.Get("apex-rise") + ": outside what the legs can reach (0 < H <= 0.35 m)");
    jump_momentum_gain = cli.GetDouble("jump-momentum-gain");
    if (!(jump_momentum_gain >= 0.0 && jump_momentum_gain <= 100.0))
      throw std::invalid_argument("--jump-momentum-gain " + cli.Get("jump-momentum-gain") + ": must be in [0, 100]");
    flight_hip_follow = cli.GetDouble("flight-hip-follow");
    if (!(flight_hip_follow >= -10.0 && flight_hip_follow <= 10.0))
      throw std::invalid_argument("--flight-hip-follow " + cli.Get("flight-hip-follow") + ": must be in [-10, 10]");
    deflection_feedback = cli.GetDouble("landing-deflection-feedback");
    if (!(deflection_feedback >= 0.0 && deflection_feedback <= 2.0))
      throw std::invalid_argument("--landing-deflection-feedback " + cli.Get("landing-deflection-feedback") + ": must be in [0, 2]");
    force_feedback = cli.GetDouble("jump-force-feedback");
    if (!(force_feedback >= 0.0 && force_feedback <= 10.0))
      throw std::invalid_argument("--jump-force-feedback " + cli.Get("jump-force-feedback") + ": must be in [0, 10]");
    landing_reg = cli.GetDouble("landing-torque-regularization");
    if (!(landing_reg >= 1e-3 && landing_reg <= 1e3))
      throw std::invalid_argument("--landing-torque-regularization " + cli.Get("landing-torque-regularization") + ": must be in [0.001, 1000]");
    force_integral = cli.GetDouble("jump-force-integral");
    if (!(force_integral >= 0.0 && force_integral <= 1000.0))
      throw std::invalid_argument("--jump-force-integral " + cli.Get("jump-force-integral") + ": must be in [0, 1000] 1/s");
    landing_params.min_force_fraction = cli.GetDouble("landing-min-force");
    if (!(landing_params.min_force_fraction >= 0.0 && landing_params.min_force_fraction < 1.0))
      throw std::invalid_argument("--landing-min-force " + cli.Get("landing-min-force") + ": must be in [0, 1)");
    landing_blend = cli.GetDouble("landing-blend");
    if (!(landing_blend >= 1e-3 && landing_blend <= 10.0))
      throw std::invalid_argument("--landing-blend " + cli.Get("landing-blend") + ": must be in [0.001, 10] s");
    if (hops < 1 || hops > 1000) throw std::invalid_argument("--hops " + cli.Get("hops") + ": must be in [1, 1000]");
    const double duration_s = cli.GetDouble("duration");  // here, inside the try: nan, inf or junk is bad input
    if (!(duration_s >= 0.0 && duration_s <= 3600.0))
      throw std::invalid_argument("--duration " + cli.Get("duration") + ": must be in [0, 3600] s (0: until the robot rests)");
    try {
      variant = ParseLegStiffnessVariant(cli.Get("leg-stiffness"));
    } catch (const std::exception&) {
      throw std::invalid_argument("--leg-stiffness " + cli.Get("leg-stiffness") + ": unknown variant (published or identified)");
    }
    cli.CheckOutputs({"log", "summary", "animation"}, {"plots"});
    model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar("robots/cassie/cassie.rome.json"));
  } catch (const std::exception& e) {
    const std::string what = e.what();
    std::cerr << (what.rfind("hopping: ", 0) == 0 ? "" : "hopping: ") << examples::OneLine(what) << "\n";
    return 1;
  }

  const SpringMassParams rom = CassieSpringMassParams(*model, variant);
  SpringMassJumpParams jump_params;
  jump_params.apex_rise = apex_rise;
  auto records = std::make_shared<std::vector<PlannerRecord>>();
  auto rest_height = std::make_shared<double>(0.0);
  const LegLengthTable leg_length(*model);
  HoppingDiagramParams params;
  params.reference.hops = hops;
  params.reference.jump_momentum_gain = jump_momentum_gain;
  params.reference.flight_hip_pitch_follow = flight_hip_follow;
  params.reference.landing_blend_s = landing_blend;
  params.reference.landing_deflection_feedback = deflection_feedback;
  params.reference.jump_force_feedback = force_feedback;
  params.reference.jump_force_integral_per_s = force_integral;
  params.landing_u_regularization_scale = landing_reg;
  params.bullet_plant.substeps = substeps;
  HoppingDiagram d = BuildHoppingDiagram(model, leg_length, MakeSpringMassJumpPlanner(rom, jump_params, records, rest_height),
                                         MakeSpringMassLandingPlanner(rom, landing_params, records, rest_height), params, plant_kind);
  Simulator sim(*d.diagram, HoppingSimulatorConfig());
  SetHoppingInitialState(d, sim.get_mutable_context(), model->q_nominal());

  const int nv = model->nv();
  MultibodyWorkspace ws(*model);
  const int pitch_index = model->VelocityIndex("base_pitch");
  const int shin[2] = {model->VelocityIndex("left_shin_spring"), model->VelocityIndex("right_shin_spring")};
  struct Sample {
    double t, grf, rom_grf, shin_torque, com_z, pitch, pitch_momentum, since_touchdown;  // since_touchdown: of the current hop [s], or -1
    int domain;
    // For the plots: desired vs actual outputs (mean leg length L(q_knee) [m], COM x [m], pelvis pitch [rad]; desired NaN
    // in Flight), energies [J] relative to the current hop's jump start (robot: kinetic 1/2 v^T M v, potential m g Δz_com,
    // springs 1/2 k (q - q_rest)^2; ROM: 1/2 m xdot^2, m g Δx, 1/2 n K(L) s^2; NaN without a plan) and q for the tiles.
    double leg_length, leg_length_d, com_x, com_x_d, pitch_d;
    double kinetic, potential, spring_energy, rom_kinetic, rom_potential, rom_spring;
    Eigen::VectorXd q;
  };
  const HoppingOutputLayout layout = MakeHoppingOutputLayout(params.outputs);
  const int knee[2] = {model->VelocityIndex("left_knee"), model->VelocityIndex("right_knee")};
  double com_z_ref = NAN, rom_x_ref = NAN;  // at the current hop's jump start
  // GRF samples on a fixed 1 ms grid (the first integrator step at or after each tick): averages over integrator steps
  // would weight each stretch by how finely that integrator happened to step.
  std::vector<Sample> samples;
  double next_sample_t = 0.0;
  // liftoff, touchdown, jump_start: the first hop's (its metrics); *_now: the current hop's (the ROM force of its plans).
  double jump_start_now = -1, touchdown_now = -1;
  double liftoff = -1, touchdown = -1, jump_start = -1, clearance = 0, com_liftoff = 0, com_max = 0, pitch_liftoff = 0, pitch_change = 0;
  // At touchdown: mean sole point x minus COM x [m] (+: feet ahead); after it: lowest pelvis height [m].
  double touchdown_foot_com_x = NAN, liftoff_foot_com_x = NAN, pelvis_min_after_touchdown = NAN;
  double liftoff_pitch_momentum = NAN;  // H_pitch about the COM at lift-off [N m s] (spec: |H| < 0.3)
  auto foot_com_x = [&](const Eigen::VectorXd& q) {
    double x_sum = 0;
    int points = 0;
    for (int k = 0; k < model->num_contacts(); ++k)
      for (size_t i = 0; i < model->contacts()[k].points.size(); ++i, ++points) x_sum += CalcContactPointPosition(*model, ws, q, k, static_cast<int>(i)).x();
    return x_sum / points - CalcComPosition(*model, ws, q).x();
  };
  const int base_z = model->VelocityIndex("base_z");
  int last_domain = HoppingDomain::kLanding, landings = 0;
  const bool stop_after_last = cli.GetDouble("duration") <= 0;  // --duration 0: end 2.5 s after the last touchdown
  double rest_speed = NAN;  // max |q̇| 2 s after the last hop's touchdown
  const bool want_plots = !cli.Get("plots").empty();
  double last_progress = 0;
  ContactForceStatistics contact;  // the plant's own forces after every integrator step and event
  std::unique_ptr<visualization::AnimationRecorder> animation;
  if (!cli.Get("animation").empty()) animation = std::make_unique<visualization::AnimationRecorder>(*model);
  sim.set_monitor([&](const Context& c) {
    const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, c);
    const LeafContext& rc = d.diagram->GetSubsystemContext(*d.reference, c);
    contact.Record(*d.plant, pc);
    if (animation)
      animation->Record(pc.time(), d.plant->EvalOutput(pc, "q"), d.plant->mode_name(d.plant->EvalTypedOutput<int>(pc, "mode")),
                        d.plant->EvalOutput(pc, "contact_forces"));
    const Eigen::VectorXd& x = d.plant->EvalOutput(pc, "state");
    const Eigen::VectorXd q = x.head(nv);
    const int domain = d.reference->EvalTypedOutput<int>(rc, "domain");
    const double t = pc.time();
    const Eigen::VectorXd& f = d.plant->EvalOutput(pc, "contact_forces");
    // The COM height only where it is used (a domain change, Flight, a 1 ms sample): the monitor runs after every
    // integrator step, and a new q costs the forward kinematics.
    const bool sample_due = t >= next_sample_t;
    const double com_z = domain != last_domain || domain == HoppingDomain::kFlight || sample_due ? CalcComPosition(*model, ws, q).z() : NAN;
    if (domain == HoppingDomain::kJump && last_domain != HoppingDomain::kJump) {
      jump_start_now = t;
      if (jump_start < 0) jump_start = t;
      com_z_ref = com_z;
      if (!records->empty()) rom_x_ref = records->back().plan.states(0, 0);
    }
    if (domain == HoppingDomain::kLanding && last_domain == HoppingDomain::kFlight) touchdown_now = t, ++landings;
    if (domain == HoppingDomain::kFlight && last_domain != HoppingDomain::kFlight && liftoff < 0) {
      liftoff = t, com_liftoff = com_max = com_z, pitch_liftoff = q[pitch_index];
      liftoff_foot_com_x = foot_com_x(q);
      liftoff_pitch_momentum = CalcCentroidalMomentum(*model, ws, q, x.tail(nv))[1];
    }
    if (domain == HoppingDomain::kLanding && last_domain == HoppingDomain::kFlight && touchdown < 0) {
      touchdown = t;
      touchdown_foot_com_x = foot_com_x(q);
    }
    if (touchdown > 0) pelvis_min_after_touchdown = std::isfinite(pelvis_min_after_touchdown) ? std::min(pelvis_min_after_touchdown, q[base_z]) : q[base_z];
    if (domain == HoppingDomain::kFlight && touchdown < 0) {
      double lowest = 1e9;
      for (int k = 0; k < model->num_contacts(); ++k) lowest = std::min(lowest, CalcContactHeight(*model, ws, q, k));
      clearance = std::max(clearance, lowest);
      com_max = std::max(com_max, com_z);
      pitch_change = std::max(pitch_change, std::abs(q[pitch_index] - pitch_liftoff));
    }
    // ROM force of the active plan (Jump: the jump plan from its start; Landing after a hop: the landing plan).
    double rom_grf = NAN;
    if (domain == HoppingDomain::kJump && !records->empty() && records->back().plan.success())
      rom_grf = records->back().plan.LegForce(rom, t - jump_start_now);
    if (domain == HoppingDomain::kLanding && touchdown_now > 0 && !records->empty() && records->back().kind == PlannerRecord::Kind::kLanding &&
        records->back().plan.success())  // a failed touchdown solve: the reference's quintic fallback, no ROM force
      rom_grf = records->back().plan.LegForce(rom, t - touchdown_now);
    const double shin_torque = -model->spring_stiffness()[shin[0]] * x[shin[0]] - model->spring_stiffness()[shin[1]] * x[shin[1]];
    if (sample_due) {
      Sample smp{};
      smp.t = t, smp.grf = f[2] + f[5], smp.rom_grf = rom_grf, smp.shin_torque = shin_torque, smp.com_z = com_z, smp.pitch = q[pitch_index];
      smp.pitch_momentum = CalcCentroidalMomentum(*model, ws, q, x.tail(nv))[1];
      smp.since_touchdown = touchdown_now > 0 ? t - touchdown_now : -1.0;
      smp.domain = domain;
      if (want_plots) {  // the plot-only quantities (the mass matrix costs ~3 % of the run)
        double L_leg[2], dL;
        for (int leg = 0; leg < 2; ++leg) leg_length(q[knee[leg]], &L_leg[leg], &dL);
        smp.leg_length = 0.5 * (L_leg[0] + L_leg[1]);
        smp.com_x = CalcComPosition(*model, ws, q).x();
        const Eigen::VectorXd& yd = d.reference->EvalOutput(rc, "desired");
        const bool tracked = domain != HoppingDomain::kFlight;
        smp.leg_length_d = tracked ? 0.5 * (yd[layout.leg_left] + yd[layout.leg_right]) : NAN;
        smp.com_x_d = tracked ? yd[layout.com_x] : NAN;
        smp.pitch_d = tracked ? yd[layout.pitch] : NAN;
        const Eigen::VectorXd v = x.tail(nv);
        smp.kinetic = 0.5 * v.dot(CalcMassMatrix(*model, ws, q) * v);
        smp.potential = model->total_mass() * rom.gravity * (com_z - com_z_ref);
        smp.spring_energy = 0.5 * (model->spring_stiffness().array() * (q - model->spring_rest()).array().square()).sum();
        smp.rom_kinetic = smp.rom_potential = smp.rom_spring = NAN;
        const double rom_t = domain == HoppingDomain::kJump ? t - jump_start_now : t - touchdown_now;
        if (std::isfinite(rom_grf)) {
          const Eigen::Vector4d z = records->back().plan.State(rom_t);
          smp.rom_kinetic = 0.5 * rom.mass * z[1] * z[1];
          smp.rom_potential = rom.mass * rom.gravity * (z[0] - rom_x_ref);
          smp.rom_spring = 0.5 * rom.n_legs * rom.leg.stiffness.Evaluate(z[2]) * (z[2] - z[0]) * (z[2] - z[0]);
        }
        smp.q = q;
      }
      samples.push_back(std::move(smp));
      next_sample_t = std::floor(t / 1e-3 + 1.0) * 1e-3;
    }
    last_domain = domain;
    if (landings >= hops && t >= touchdown_now + 2.0 && std::isnan(rest_speed)) rest_speed = x.tail(nv).cwiseAbs().maxCoeff();
    if (stop_after_last && landings >= hops && t >= touchdown_now + 2.5)
      return EventStatus::ReachedTermination("all " + std::to_string(hops) + " hop(s) landed; 2.5 s after the last touchdown");
    if (t - last_progress >= 0.5) {
      last_progress = t;
      std::cerr << "  t = " << t << " s, domain " << domain << "\n";
    }
    return EventStatus::Succeeded();
  });

  const double duration =
      cli.GetDouble("duration") > 0 ? cli.GetDouble("duration") : params.reference.settle_time_s + hops * 1.0 + (hops - 1) * params.reference.max_rest_time_s + 2.5;
  std::cout << "hopping: simulating " << duration << " s on the " << ToString(plant_kind) << " plant ...\n" << std::flush;
  const auto wall0 = std::chrono::steady_clock::now();
  SimulatorStatus status;
  try {
    status = sim.AdvanceTo(duration);
  } catch (const std::exception& e) {
    std::cerr << "hopping: " << e.what() << "\n";
    return 3;
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  // Metrics.
  std::vector<double> jr, jm, lr, lm, st, sg;
  for (const Sample& s : samples) {
    if (s.domain == HoppingDomain::kJump && std::isfinite(s.rom_grf)) jr.push_back(s.grf), jm.push_back(s.rom_grf);
    if (s.domain == HoppingDomain::kLanding && s.since_touchdown > 0.02 && std::isfinite(s.rom_grf)) lr.push_back(s.grf), lm.push_back(s.rom_grf);
    if (s.domain != HoppingDomain::kFlight && jump_start > 0 && s.t >= jump_start) st.push_back(s.shin_torque), sg.push_back(s.grf);
  }
  const LeafContext& pc = d.diagram->GetSubsystemContext(*d.plant, sim.get_context());
  const LeafContext& cc = d.diagram->GetSubsystemContext(*d.controller, sim.get_context());
  const Eigen::VectorXd v_end = d.plant->EvalOutput(pc, "v");
  // At rest (hopping issue): every |q̇| < 0.05 2 s after the last touchdown, and still at the end.
  const bool settled = std::isfinite(rest_speed) && rest_speed < 0.05 && v_end.cwiseAbs().maxCoeff() < 0.05;
  const LogData& log = d.logger->log(d.diagram->GetSubsystemContext(*d.logger, sim.get_context()));
  std::vector<double> solve_us;
  const int solve_col = d.logger->ColumnIndex("controller.solve_time_s[0]");
  for (const Eigen::VectorXd& row : log.samples) solve_us.push_back(1e6 * row[solve_col]);
  double takeoff_error = NAN;
  if (liftoff > 0 && !records->empty()) takeoff_error = (liftoff - jump_start) - records->front().plan.duration;
  // A hop: the COM rises at least half the planned apex rise H in flight (ours). Without it a foot's normal force that
  // dips to the lift-off threshold in the crouch counts as a hop (measured on the Bullet plant with 1 substep: 20 ms
  // "flight", 0.26 mm foot clearance, COM rise 0).
  const bool hopped = liftoff > 0 && touchdown > 0 && com_max - com_liftoff >= 0.5 * apex_rise;
  const bool ran = status.ok() || status.reason == SimulatorStatus::Reason::kReachedTermination;
  const bool ok = ran && hopped && settled && contact.violations == 0;

  nlohmann::json summary;
  summary["success"] = ok;
  summary["status_kind"] = ran ? (ok ? "success" : "limit") : status.kind_name();
  summary["status"] = status.ToString();
  summary["air_time_s"] = liftoff > 0 && touchdown > 0 ? touchdown - liftoff : NAN;
  summary["foot_clearance_m"] = clearance;
  summary["com_rise_m"] = liftoff > 0 ? com_max - com_liftoff : NAN;
  summary["takeoff_time_error_s"] = takeoff_error;
  {
    const Eigen::VectorXd& ps = d.reference->EvalOutput(d.diagram->GetSubsystemContext(*d.reference, sim.get_context()), "plan_status");
    summary["jump_plans"] = ps[0];
    summary["landing_plans"] = ps[1];  // at each planned lift-off (predicted touchdown) and at each touchdown
    summary["planner_failures"] = ps[2];
  }
  summary["rest_speed_2s_after_last_touchdown"] = rest_speed;  // max |q̇| [rad/s, m/s]; settled needs < 0.05
  summary["grf_nrmse_jump"] = Nrmse(jr, jm);
  summary["grf_nrmse_landing"] = Nrmse(lr, lm);
  summary["spring_torque_grf_correlation"] = Correlation(st, sg);
  summary["settled"] = settled;
  summary["hopped"] = hopped;
  summary["max_pelvis_pitch_change_flight_rad"] = pitch_change;
  summary["liftoff_foot_com_offset_x_m"] = liftoff_foot_com_x;
  summary["liftoff_pitch_momentum_Nms"] = liftoff_pitch_momentum;
  summary["touchdown_foot_com_offset_x_m"] = touchdown_foot_com_x;
  summary["min_pelvis_height_after_touchdown_m"] = pelvis_min_after_touchdown;
  summary["qp_infeasible_ticks"] = d.controller->EvalOutput(cc, "qp_failures")[0];
  summary["qp_solve_us_median"] = Percentile(solve_us, 0.5);
  summary["qp_solve_us_p99"] = Percentile(solve_us, 0.99);
  summary["realtime_factor"] = pc.time() / wall;
  summary["leg_stiffness"] = cli.Get("leg-stiffness");
  summary["jump_momentum_gain"] = jump_momentum_gain;
  summary["flight_hip_follow"] = flight_hip_follow;
  summary["landing_min_force_fraction"] = landing_params.min_force_fraction;
  summary["landing_blend_s"] = landing_blend;
  summary["landing_deflection_feedback"] = deflection_feedback;
  summary["jump_force_feedback"] = force_feedback;
  summary["jump_force_integral_per_s"] = force_integral;
  summary["landing_torque_regularization"] = landing_reg;
  summary["plant"] = ToString(plant_kind);
  summary["bullet_substeps"] = substeps;
  summary["contact_violations"] = contact.violations;
  summary["first_contact_violation"] = contact.first_violation;
  summary["max_friction_ratio"] = contact.max_friction_ratio;
  summary["simulated_s"] = pc.time();
  summary["apex_rise_m"] = apex_rise;
  nlohmann::json nlp = nlohmann::json::array();
  for (const PlannerRecord& r : *records)
    nlp.push_back({{"problem", r.kind == PlannerRecord::Kind::kJump ? "jump" : r.kind == PlannerRecord::Kind::kLanding ? "landing" : "landing_predicted_at_liftoff"},
                   {"time_s", r.plan.solve_time_s},
                   {"iterations", r.plan.iterations},
                   {"violation", r.plan.max_violation},
                   {"duration_s", r.plan.duration},
                   {"status", r.plan.message}});
  summary["nlp"] = nlp;
  const SimulatorStatistics& stats = sim.statistics();
  summary["integrator"] = {{"steps", stats.steps},
                           {"rhs_evaluations", stats.rhs_evals},
                           {"jacobian_evaluations", stats.jacobian_evals},
                           {"jacobian_rhs_evaluations", stats.jacobian_rhs_evals},
                           {"nonlinear_iterations", stats.nonlinear_iterations},
                           {"error_test_failures", stats.error_test_failures},
                           {"convergence_failures", stats.convergence_failures},
                           {"restarts", stats.restarts},
                           {"root_evaluations", stats.root_evals},
                           {"guard_events", stats.guard_events},
                           {"discrete_samples", stats.discrete_samples},
                           {"wall_s", wall}};
  if (!cli.Get("summary").empty() && !examples::WriteOutputFile("hopping", cli.Get("summary"), summary.dump(2) + "\n", "summary")) return 1;
  if (!cli.Get("log").empty() && !examples::WriteOutputFile("hopping", cli.Get("log"), d.logger->CsvText(d.diagram->GetSubsystemContext(*d.logger, sim.get_context())), "log")) return 1;
  if (animation) {
    std::string error;
    if (!animation->WriteHtml(cli.Get("animation"), "ROME hopping, Cassie", {}, &error)) std::cerr << "hopping: " << error << "\n";
    else std::cout << "animation: " << cli.Get("animation") << " (" << animation->num_frames() << " frames)\n";
  }
  if (!cli.Get("plots").empty()) {
    visualization::PlotSpec grf{"Normal GRF: robot vs spring-mass ROM", "t [s]", "F [N]", {}};
    visualization::PlotSpec com{"COM height", "t [s]", "z [m]", {}};
    visualization::PlotSpec spring{"Shin spring torque (both legs) and robot normal GRF / 10", "t [s]", "torque [N m], force [10 N]", {}};
    visualization::PlotSpec momentum{"Centroidal pitch momentum H_pitch", "t [s]", "H [N m s]", {}};
    visualization::PlotSpec pitch{"Pelvis pitch", "t [s]", "pitch [rad]", {}};
    visualization::Series robot{"robot", {}, {}}, romf{"ROM", {}, {}}, comz{"COM z", {}, {}}, shin{"shin springs", {}, {}}, grf10{"GRF / 10", {}, {}},
        H{"H_pitch", {}, {}}, theta{"pelvis pitch", {}, {}};
    for (const Sample& s : samples) {
      robot.x.push_back(s.t), robot.y.push_back(s.grf), comz.x.push_back(s.t), comz.y.push_back(s.com_z);
      shin.x.push_back(s.t), shin.y.push_back(s.shin_torque), grf10.x.push_back(s.t), grf10.y.push_back(0.1 * s.grf);
      H.x.push_back(s.t), H.y.push_back(s.pitch_momentum), theta.x.push_back(s.t), theta.y.push_back(s.pitch);
      if (std::isfinite(s.rom_grf)) romf.x.push_back(s.t), romf.y.push_back(s.rom_grf);
    }
    // Fig. 6 of the paper from our run, over the first hop (jump start − 0.1 s to touchdown + 1 s): desired vs actual
    // outputs in Jump and Landing, energies robot vs ROM, and hop tiles.
    const double t_from = jump_start > 0 ? jump_start - 0.1 : 0.0, t_to = touchdown > 0 ? touchdown + 1.0 : 1e9;
    auto dashed = [](const std::string& title) { return visualization::Series{title, {}, {}, "lines dt 2 lw 2"}; };
    visualization::Series L_act{"L actual (mean of legs)", {}, {}}, L_des = dashed("L desired"), cx_act{"COM x actual", {}, {}}, cx_des = dashed("COM x desired"),
                     th_act{"pitch actual", {}, {}}, th_des = dashed("pitch desired");
    visualization::Series ke{"robot kinetic", {}, {}}, pe{"robot potential", {}, {}}, se{"robot springs", {}, {}}, rke = dashed("ROM kinetic"),
        rpe = dashed("ROM potential"), rse = dashed("ROM spring");
    auto push = [](visualization::Series& series, double t, double y) { series.x.push_back(t), series.y.push_back(y); };
    for (const Sample& s : samples) {
      if (s.t < t_from || s.t > t_to) continue;
      push(L_act, s.t, s.leg_length), push(L_des, s.t, s.leg_length_d), push(cx_act, s.t, s.com_x), push(cx_des, s.t, s.com_x_d);
      push(th_act, s.t, s.pitch), push(th_des, s.t, s.pitch_d);
      push(ke, s.t, s.kinetic), push(pe, s.t, s.potential), push(se, s.t, s.spring_energy);
      push(rke, s.t, s.rom_kinetic), push(rpe, s.t, s.rom_potential), push(rse, s.t, s.rom_spring);
    }
    visualization::PlotSpec out_L{"Output: virtual leg length L(q_knee), Jump and Landing (gap: Flight)", "t [s]", "L [m]", {L_act, L_des}};
    visualization::PlotSpec out_x{"Output: COM x, Jump and Landing", "t [s]", "x [m]", {cx_act, cx_des}};
    visualization::PlotSpec out_th{"Output: pelvis pitch, Jump and Landing", "t [s]", "pitch [rad]", {th_act, th_des}};
    visualization::PlotSpec energy{"Energy relative to the jump start: robot vs spring-mass ROM", "t [s]", "E [J]", {ke, pe, se, rke, rpe, rse}};
    // Hop tiles: the sagittal (x-z) projection of every link-to-parent segment and of each sole line, one frame every
    // 0.07 s from 0.1 s before the jump to 0.3 s after touchdown, side by side.
    visualization::Series sticks{"robot", {}, {}, "lines lw 2 lc rgb '#3060c0'"}, ground{"ground", {}, {}, "lines lw 3 lc rgb '#808080'"};
    int tile = 0;
    double next_tile = t_from;
    constexpr double kTileDx = 0.5;  // [m]
    for (const Sample& s : samples) {
      if (s.t < next_tile || s.t > std::min(t_to - 0.7, t_from + 1.5)) continue;
      next_tile = s.t + 0.07;
      visualization::AppendStickFigure(*model, ws, s.q, 0, kTileDx * tile++, &sticks, &sticks);
    }
    ground.x = {-0.4, kTileDx * tile}, ground.y = {0.0, 0.0};
    visualization::PlotSpec tiles{"Hop tiles, sagittal projection (every 0.07 s from 0.1 s before the jump to 0.3 s after touchdown; 0.5 m apart)",
                             "x [m] (+ 0.5 m per tile)", "z [m]", {ground, sticks}};
    tiles.equal_axes = true;
    tiles.width_px = 1800;
    tiles.height_px = 600;
    grf.series = {robot, romf};
    com.series = {comz};
    spring.series = {shin, grf10};
    momentum.series = {H};
    pitch.series = {theta};
    std::string error;
    for (auto& [spec, file] : {std::pair{grf, "grf.png"}, std::pair{com, "com_height.png"}, std::pair{spring, "spring_torque.png"},
                               std::pair{momentum, "pitch_momentum.png"}, std::pair{pitch, "pelvis_pitch.png"}, std::pair{out_L, "output_leg_length.png"},
                               std::pair{out_x, "output_com_x.png"}, std::pair{out_th, "output_pitch.png"}, std::pair{energy, "energy.png"},
                               std::pair{tiles, "hop_tiles.png"}})
      if (!visualization::WritePlot(spec, cli.Get("plots") + "/" + file, &error)) std::cerr << "hopping: plot " << file << ": " << error << "\n";
  }
  std::cout << "hopping (" << ToString(plant_kind) << " plant): " << status.ToString() << "\n"
            << "  air time " << summary["air_time_s"] << " s (paper 0.423), foot clearance " << clearance << " m (paper ~0.18), COM rise "
            << summary["com_rise_m"] << " m, lift-off vs ROM " << takeoff_error << " s\n"
            << "  GRF NRMSE jump " << summary["grf_nrmse_jump"] << ", landing " << summary["grf_nrmse_landing"] << "; pitch change in flight "
            << pitch_change * 180 / M_PI << " deg; hopped " << (hopped ? "yes" : "no") << "; settled " << (settled ? "yes" : "no") << "; QP median " << summary["qp_solve_us_median"]
            << " us; real-time factor " << summary["realtime_factor"] << "\n  plant contact violations " << contact.violations << " ("
            << contact.samples << " samples)" << (contact.violations ? ", first: " + contact.first_violation : "") << ", max |F_t|/F_n "
            << contact.max_friction_ratio << "\n";
  if (status.kind() == SimulatorStatus::Kind::kInterrupted) {
    std::cout << "result: interrupted (" << status.ToString() << "); outputs written up to there\n";
    return 128 + InterruptSignal();
  }
  return ok ? 0 : 3;
}
