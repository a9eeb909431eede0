#include "diagrams/hopping/hopping_diagram.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "framework/simulator_presets.h"

namespace rome {

HybridContactPlantParams HoppingDiagramParams::DefaultPlantParams() {
  HybridContactPlantParams p;
  p.min_base_height_m = 0.5;  // [m] pelvis below this is a fall (standing pelvis ~1.0 m, crouched ~0.85 m)
  p.min_time_in_mode_s = 0.02;  // spec [R] A3: minimum 20 ms between events
  // [N] ours: lift-off at 8 N (2.4 % of m g). The spec's 1 % of m g (3.3 N, [R] A3) is measured too low: at take-off the
  // plant's |F_t|/F_n reached the friction coefficient at F_n = 3.7 N (a slip) before the normal force fell to 3.3 N.
  p.planned_liftoff_force_N = 8.0;
  return p;
}

BulletWorldPlantParams HoppingDiagramParams::DefaultBulletPlantParams() {
  BulletWorldPlantParams p;
  p.step_s = DefaultControllerParams().update_period_s;
  // Ours, measured: 5 substeps of 0.1 ms. With the springs' torques recomputed only every 0.5 ms the settle's bounce is
  // not damped (COM z range 9.4 mm over 1.0-1.45 s against 3.9 mm with 5 substeps, 3.6 mm with 10 and ~2 mm on the
  // hybrid plant), and the jump planned from that state unloads the feet 0.19 s before the ROM's take-off.
  p.substeps = 5;
  p.min_base_height_m = DefaultPlantParams().min_base_height_m;
  // Take-off is a planned lift-off at the hybrid plant's 8 N (see bullet_world_plant.h), touchdowns 20 ms after it.
  p.planned_liftoff_force_N = DefaultPlantParams().planned_liftoff_force_N;
  p.min_time_in_mode_s = DefaultPlantParams().min_time_in_mode_s;
  return p;
}

ClfQpParams HoppingDiagramParams::DefaultControllerParams() {
  ClfQpParams p;
  p.formulation = ClfQpFormulation::kAugmentedInput;
  p.update_period_s = 5e-4;
  p.epsilon = 0.1;
  // ρ_u = 1e-4 (spec [R] A4.5). With the block's default 1e-6 the landing QP's Hessian reached a condition number of
  // 1e9 right after the impact (smallest eigenvalue 2.3e-8 against 20: the 4 torque directions the 6 outputs leave
  // free see only ρ_u); DenseQpSolver then took its proximal path and stopped at its iteration limit on every landing
  // tick, so the flight torques were held and a foot slipped. 1e-4 gives 2.3e-6 and an optimal QP at every tick.
  p.u_regularization = 1e-4;
  // The cost targets ÿ* = ÿ_d − Kp e − Kd ė (TaskGains: 100 1/s², 20 1/s) on every CLF output (ours, the block's
  // cost_pd_feedback; the paper's cost targets ÿ_d). Measured on the default hop: with ÿ_d alone the cost asks for zero
  // output acceleration, so an output moves only as far as the CLF row forces it (V decays at γ/ε ≈ 3.7 1/s). In Flight
  // the knees kept their lift-off speed (3.8 rad/s) and drifted 0.28 rad from their held targets, so at touchdown the
  // legs were 5 cm longer (L = 0.97 m) than the landing NLP's bound (0.92 m): the landing plan started 5 cm short, the
  // controller shortened the legs at once, the feet unloaded to 40 N and slipped 78 ms after touchdown. With the PD
  // target the knees hold their targets in Flight (touchdown at L = 0.93 m), the landing GRF follows the ROM (NRMSE
  // 35 % -> 4 %) and the foot clearance is 0.154 m (was 0.120 m).
  p.cost_pd_feedback = true;
  // Relaxation weight p = 1e4 on ½ p δ² (ours; the block's and the walking spec's [R] 1e5; the hopping spec only says
  // "large"). Measured in the landing with 1e5: on the ticks where the CLF row cannot be met (δ > 0, the feet carrying
  // ~100 N each in the rebound), the QP bought a little less δ with torques that jumped by up to 190 N m from one
  // 0.5 ms tick to the next (27 jumps above 80 N m in three hops); the third hop was still rolling on the springs 2 s
  // after touchdown (0.055 rad/s) and the fourth of five hops slipped. With 1e4: no such jump, 3 and 5 hops land and are
  // at rest 2 s after touchdown; the six tuning apex rises (0.12-0.28 m) all land either way, and so do 3e3 and 3e4 for
  // three hops; 1e3 is not at rest 2 s after the fifth hop.
  p.relaxation_weight = 1e4;
  // The block's per-actuator torque penalty (u_regularization_kind kInverseJointInertia in Flight) was measured on the
  // default hop with the 30 rad/s flight motors: pitch change 4.929° either way, so the uniform penalty stays.
  return p;
}

HoppingReferenceParams HoppingDiagramParams::DefaultReferenceParams() {
  HoppingReferenceParams p;
  // Flight hip targets q_hip_lo + r (θ − θ_lo) (flight_hip_pitch_follow = −1, ours): the hips turn the legs with the
  // pelvis pitch, so the legs take the lift-off angular momentum off the pelvis. Measured on the default hop (with the
  // 30 rad/s flight motors): pelvis pitch change in flight 8.8° -> 4.9°, feet at touchdown 14.2 -> 15.5 cm ahead of
  // the COM. +1 (legs keep their world pitch) puts the feet 3.3 cm ahead but turns the pelvis by 45°: with the flight
  // angular momentum the jump leaves, the two cannot both be met.
  p.flight_hip_pitch_follow = -1.0;
  // Jump momentum gain 10 and landing deflection feedback 0.7 (both ours). With the block's gain 2 the jump left
  // H_pitch = −0.84 N m s at lift-off, the pelvis and legs turned in flight and the feet touched down 15.5 cm ahead of
  // the COM: the robot tipped back and a foot slipped 0.1 s after touchdown (every apex rise 0.15-0.25 m). Gain 10:
  // |H_pitch| = 0.15 N m s (spec: < 0.3), feet 2.2 cm ahead. That alone still slipped 0.2 s after touchdown: the
  // landing plan's legs are tracked open loop, the real springs rebound more than the ROM's, and the feet unloaded to
  // 40-60 N total while the plan asked for ≥ 229 N (landing F_min raised to 0.7 m g). With the leg-length target
  // corrected by 0.7 of the mass-height error (landing_deflection_feedback) the spring deflection follows the plan.
  // Measured with both: the robot lands and comes to rest at apex rises 0.15, 0.20, 0.2205 (default), 0.25 and 0.28 m,
  // 3 hops in a row, and on the Bullet plant; feedback 0.3 or gain 5-7 slip again, 0.5 fails at 0.25 m.
  p.jump_momentum_gain = 10.0;
  p.landing_deflection_feedback = 0.7;
  // GRF feedback in Jump, k_F = 6, k_I = 40 1/s (ours). Without it the robot's COM rose only 66-70 % of the ROM's
  // apex rise at every H from 0.10 to 0.25 m (default hop: air time 0.350 s, clearance 0.148 m): the leg lengths
  // followed the plan to ~1 mm, but the plant's GRF peaked at 1130 N where the plan asked 1430 N, the jump's impulse
  // was 5 % short (154.0 against 161.6 N s) and, the lift-off speed being the small difference m v = ∫F dt − m g T, the
  // COM left at 1.74 m/s against the ROM's 2.08 m/s. Chosen on apex rises 0.12/0.15/0.18/0.20/0.23/0.28 m (the tests
  // check 0.10, 0.2205 and 0.25), with landing_u_regularization_scale = 10 (air time [s], all six land):
  //   k_F 4, k_I 40: 0.287 0.323 0.355 0.376 0.405 0.378;  k_F 6, k_I 40: 0.294 0.331 0.365 0.385 0.392 0.372
  //   k_F 4, k_I 60: 0.23 m slips in the landing;  without the fade w: 0.28 m slips at lift-off
  //   P alone (k_F 1 / 3 / 8): default air 0.362 / 0.380 / 0.384 s, k_F 5 slips in the landing
  // Also tried: the leg-length target corrected by the mass-height error as in Landing (g = 0.3-1 in Jump): the GRF
  // followed the ROM force law better (NRMSE 9 %) but the air time fell to 0.32-0.33 s.
  p.jump_force_feedback = 6.0;
  p.jump_force_integral_per_s = 40.0;
  // Landing quintics (COM x, pelvis pitch back to 0) over 0.5 s (ours; spec [R] C10: 0.3 s). With the higher jumps of
  // the GRF feedback, 0.1-0.2 s after touchdown the feet rebound to ~100 N each while the 0.3 s quintic still asks for
  // pitch acceleration; a foot slipped in the second or third of 3 hops. Measured (--hops 5, default apex; tuning apex
  // rises as above): 0.3 s: hop 3 slips; 0.4 s: 5 hops land, Bullet 3 hops falls; 0.5 s: 5 hops land, Bullet 3 hops
  // land, 6/6 tuning apex rises; 0.6 s: hop 4 slips. (Measured with the relaxation weight 1e5 and before the landing NLP
  // was also solved at lift-off; with that warm start and 1e5 the fourth of 5 hops slipped; with 1e4, see
  // DefaultControllerParams, 5 hops land and come to rest.)
  p.landing_blend_s = 0.5;
  return p;
}

HoppingOutputParams HoppingDiagramParams::DefaultOutputParams() {
  HoppingOutputParams p;
  p.jump_tracks_momentum = false;
  // Flight motors at 30 rad/s, critically damped (ours; was the TaskGains 10 rad/s). Measured on the default hop: at
  // 10 rad/s the hips and knees, which leave the ground moving, were still 0.13-0.14 rad off their held targets 0.12 s
  // into the 0.38 s flight; at 30 rad/s they are within 0.01 rad after 0.15 s, and the foot clearance is 0.17 m
  // (was 0.154 m).
  p.motor_kp = 900.0;
  p.motor_kd = 60.0;
  return p;
}

namespace {

// Throws "HoppingDiagramParams: <field> = <value>: must be in [lo, hi]<unit>" unless lo <= value <= hi.
void CheckRange(const char* field, double value, double lo, double hi, const char* unit = "") {
  if (value >= lo && value <= hi) return;  // false for NaN
  std::ostringstream msg;
  msg << "HoppingDiagramParams: " << field << " = " << value << ": must be in [" << lo << ", " << hi << "]" << unit;
  throw std::invalid_argument(msg.str());
}

}  // namespace

void HoppingDiagramParams::Validate() const {
  CheckRange("reference.hops", reference.hops, 1, 1000);
  CheckRange("reference.jump_momentum_gain", reference.jump_momentum_gain, 0.0, 100.0);
  CheckRange("reference.flight_hip_pitch_follow", reference.flight_hip_pitch_follow, -10.0, 10.0);
  CheckRange("reference.landing_deflection_feedback", reference.landing_deflection_feedback, 0.0, 2.0);
  CheckRange("reference.jump_force_feedback", reference.jump_force_feedback, 0.0, 10.0);
  CheckRange("reference.jump_force_integral_per_s", reference.jump_force_integral_per_s, 0.0, 1000.0, " 1/s");
  CheckRange("reference.landing_blend_s", reference.landing_blend_s, 1e-3, 10.0, " s");
  CheckRange("landing_u_regularization_scale", landing_u_regularization_scale, 1e-3, 1e3);
  CheckRange("bullet_plant.substeps", bullet_plant.substeps, 1, 100);
  CheckRange("log_period_s", log_period_s, 1e-5, 10.0, " s");
  if (landing_u_regularization_scale != 1.0 && (controller.u_regularization_weights.size() != 0 || !controller.u_regularization_modes.empty())) {
    std::ostringstream msg;
    msg << "HoppingDiagramParams: landing_u_regularization_scale = " << landing_u_regularization_scale
        << " sets the controller's u_regularization_weights and u_regularization_modes; leave those empty or set the scale to 1";
    throw std::invalid_argument(msg.str());
  }
}

std::unique_ptr<System> MakeDefaultHoppingController(const HoppingControllerSpec& spec) {
  return std::make_unique<ClfQpController>(spec.name, spec.model, spec.mode_contacts, spec.outputs, spec.controller);
}

namespace {

std::vector<HoppingTask> TasksOf(const std::vector<ClfOutput>& outputs) {
  std::vector<HoppingTask> tasks;
  int row = 0;
  for (const ClfOutput& o : outputs) {
    HoppingTask t{o.name(), row, o.size(), {}};
    for (int domain : {HoppingDomain::kJump, HoppingDomain::kFlight, HoppingDomain::kLanding})
      if (o.IsActiveIn(domain)) t.domains.push_back(domain);
    row += o.size();
    tasks.push_back(std::move(t));
  }
  return tasks;
}

}  // namespace

std::vector<HoppingTask> HoppingTasks(const MultibodyModel& model, const HoppingOutputParams& params) {
  // Only the names, sizes and domains are read: any leg-length function will do.
  return TasksOf(MakeHoppingOutputs(model, [](double, double* L, double* dL) { *L = 0.0, *dL = 0.0; }, params));
}

HoppingDiagram BuildHoppingDiagram(std::shared_ptr<const MultibodyModel> model, const HoppingReference::LegLengthFunction& leg_length,
                                   HoppingReference::JumpPlanner jump_planner, HoppingReference::LandingPlanner landing_planner,
                                   const HoppingDiagramParams& params, PlantKind plant, const HoppingControllerFactory& controller_factory) {
  params.Validate();
  if (!controller_factory) throw std::invalid_argument("BuildHoppingDiagram: the controller factory is empty");
  HoppingDiagram d;
  d.model = model;
  d.leg_length = leg_length;
  d.params = params;
  d.layout = MakeHoppingOutputLayout(params.outputs);
  d.plant_kind = plant;
  DiagramBuilder b;
  d.plant = b.AddSystem(MakeContactPlant(plant, "plant", model, ContactModeGraph::JumpFlightLanding("left_foot", "right_foot"), Terrain::Flat(),
                                         params.plant, params.bullet_plant));
  d.reference = b.AddSystem(std::make_unique<HoppingReference>("reference", model, leg_length, std::move(jump_planner), std::move(landing_planner),
                                                               d.layout, params.reference));
  HoppingControllerSpec spec;
  spec.model = model;
  spec.mode_contacts = ActiveContactsPerMode(*d.plant);
  spec.outputs = MakeHoppingOutputs(*model, leg_length, params.outputs);
  spec.tasks = TasksOf(spec.outputs);
  spec.layout = d.layout;
  spec.controller = params.controller;
  spec.controller.contact_stabilization = params.plant.dynamics;
  if (params.landing_u_regularization_scale != 1.0) {
    spec.controller.u_regularization_weights = Eigen::VectorXd::Constant(model->nu(), params.landing_u_regularization_scale);
    spec.controller.u_regularization_modes = {HoppingDomain::kLanding};
  }
  d.tasks = spec.tasks;
  std::unique_ptr<System> controller = controller_factory(spec);
  if (!controller) throw std::invalid_argument("BuildHoppingDiagram: the controller factory returned no system");
  d.controller = controller.get();
  b.AddSystem(std::move(controller), spec.name);
  b.Connect("plant", "state", "reference", "state");
  b.Connect("plant", "mode", "reference", "mode");
  b.Connect("plant", "contact_forces", "reference", "contact_forces");
  b.Connect("reference", "desired", spec.name, "desired");
  b.Connect("reference", "domain", spec.name, "mode");
  b.Connect("plant", "state", spec.name, "state");
  b.Connect(spec.name, "u", "plant", "u");
  b.ExportOutput(spec.name, "u", "u");
  if (d.controller->HasOutputPort("qp_failures")) b.ExportOutput(spec.name, "qp_failures", "qp_failures");
  std::vector<std::pair<std::string, std::string>> logged = {
      {"plant", "state"}, {"plant", "mode"}, {"plant", "com"}, {"plant", "contact_forces"}, {"reference", "domain"}, {"reference", "desired"}};
  for (const char* port : {"u", "V", "delta", "contact_forces", "qp_status", "solve_time_s"})
    if (d.controller->HasOutputPort(port)) logged.push_back({spec.name, port});
  d.logger = AddVectorLogger(b, "logger", logged, params.log_period_s);
  d.diagram = b.Build("hopping");
  return d;
}

void SetHoppingInitialState(const HoppingDiagram& d, Context& context, const Eigen::VectorXd& q) {
  LeafContext& pc = d.diagram->GetMutableSubsystemContext(*d.plant, context);
  d.plant->SetState(pc, q, Eigen::VectorXd::Zero(q.size()), "jump");
  LeafContext& rc = d.diagram->GetMutableSubsystemContext(*d.reference, context);
  d.reference->Initialize(rc, q);
}

SimulatorConfig HoppingSimulatorConfig() {
  // ARKODE's explicit Bogacki-Shampine 3(2), rtol 1e-5, atol 1e-7, each 0.5 ms control interval started with the step
  // size the error test asks for at the end of the previous one (ours, measured; was CVODE BDF at rtol 1e-6 / atol 1e-8,
  // spec [R] A5). The springs do not make this flow stiff at these step sizes: the plant linearised in double stance at
  // the nominal pose has its fastest eigenvalues at -87 ± 282j 1/s (heel and shin springs), so h|λ| ≈ 0.15 at 0.5 ms.
  // The controller's zero-order hold changes u every 0.5 ms, so every integrator restarts 2000 times a second, and BDF
  // paid for each restart with a new 44 x 44 finite-difference Jacobian (44 derivative evaluations: 200 244 of its
  // 292 278 on the hop of that time), an LU factorisation and ~12 short order-1/2 steps. Measured then (2.27 s
  // simulated), user CPU time: BDF 7.0 s, Dormand-Prince 5(4) 2.0 s, Bogacki-Shampine 3(2) carrying the step 1.5 s.
  // Measured on the default hop now (4.69 s simulated, same machine), derivative evaluations / steps / rejected steps:
  //   rtol 1e-6, atol 1e-8, restart with ARKODE's reported step   90 583 / 24 865 / 2199
  //     (that step is the one clipped to the sample time: every interval took two steps, ~0.45 + 0.05 ms)
  //   rtol 1e-6, atol 1e-8, restart with the error test's step    61 702 / 17 162 /  275
  //   rtol 1e-5, atol 1e-7, restart with the error test's step    41 173 / 10 481 /  113
  // Against Dormand-Prince at rtol 1e-10 / atol 1e-12: air time, foot clearance and COM rise agree to 2e-5 (rtol 1e-6)
  // and 8e-6 (rtol 1e-5) s / m; the lift-off time to 1e-4 and 3e-4 s (the normal force falls to 0 slowly, so the
  // crossing moves with any small change); the largest joint-position difference on the 1 ms log is 3e-4 for both
  // (the closed loop's QP amplifies any difference: it is the same for the tighter tolerance).
  return ExplicitRestartingSimulatorConfig(1e-5, 1e-7);
}

}  // namespace rome
