#include "diagrams/hopping/hopping_diagram.h"

#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "framework/simulator_presets.h"
#include "systems/multibody/model_scaling.h"

namespace rome {

HybridContactPlantParams HoppingDiagramParams::DefaultPlantParams() {
  HybridContactPlantParams p;
  p.min_base_height_m = 0.5;    // [m] pelvis below this is a fall (standing pelvis ~1.0 m, crouched ~0.85 m)
  p.min_time_in_mode_s = 0.02;  // spec [R] A3: minimum 20 ms between events
  // [N] ours: lift-off at 8 N (2.4 % of m g); at the spec's 3.3 N the take-off slips first
  // (docs/design-notes.md#hopping-liftoff-force).
  p.planned_liftoff_force_N = 8.0;
  return p;
}

BulletWorldPlantParams HoppingDiagramParams::DefaultBulletPlantParams() {
  BulletWorldPlantParams p;
  p.step_s = DefaultControllerParams().update_period_s;
  // Ours: 5 substeps of 0.1 ms, so the springs' torques damp the settle (docs/design-notes.md#hopping-bullet-substeps).
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
  // ρ_u = 1e-4 (spec [R] A4.5); the block's 1e-6 leaves the landing QP ill-conditioned
  // (docs/design-notes.md#hopping-torque-penalty).
  p.u_regularization = 1e-4;
  // The cost targets ÿ_d − Kp e − Kd ė on every CLF output (ours; the paper's targets ÿ_d): with ÿ_d alone the flight
  // knees drift and the landing slips (docs/design-notes.md#hopping-cost-target).
  p.cost_pd_feedback = true;
  // Relaxation weight p = 1e4 on ½ p δ² (ours; the block's and the walking spec's 1e5, the hopping spec says "large"):
  // with 1e5 the landing torques jump between ticks (docs/design-notes.md#hopping-relaxation-weight).
  p.relaxation_weight = 1e4;
  // The uniform torque penalty stays: the per-actuator one changed nothing
  // (docs/design-notes.md#hopping-relaxation-weight).
  return p;
}

HoppingReferenceParams HoppingDiagramParams::DefaultReferenceParams() {
  HoppingReferenceParams p;
  // Flight hip targets follow the pelvis pitch (−1, ours): the legs take the lift-off angular momentum off the pelvis
  // (docs/design-notes.md#hopping-flight-hips).
  p.flight_hip_pitch_follow = -1.0;
  // Jump momentum gain 10 and landing deflection feedback 0.7 (both ours): what first made the robot land
  // (docs/design-notes.md#hopping-first-landing).
  p.jump_momentum_gain = 10.0;
  p.landing_deflection_feedback = 0.7;
  // GRF feedback in Jump, k_F = 6, k_I = 40 1/s (ours): closes the air-time gap
  // (docs/design-notes.md#hopping-air-time).
  p.jump_force_feedback = 6.0;
  p.jump_force_integral_per_s = 40.0;
  // Landing quintics (COM x, pelvis pitch back to 0) over 0.5 s (ours; spec [R] C10: 0.3 s, with which the third of
  // three hops slips; docs/design-notes.md#hopping-landing-blend).
  p.landing_blend_s = 0.5;
  return p;
}

HoppingOutputParams HoppingDiagramParams::DefaultOutputParams() {
  HoppingOutputParams p;
  p.jump_tracks_momentum = false;
  // Flight motors at 30 rad/s, critically damped (ours; the TaskGains' 10 rad/s leave the joints off their targets
  // at touchdown; docs/design-notes.md#hopping-flight-motors).
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
  perturbations.Validate();
  if (landing_u_regularization_scale != 1.0 &&
      (controller.u_regularization_weights.size() != 0 || !controller.u_regularization_modes.empty())) {
    std::ostringstream msg;
    msg << "HoppingDiagramParams: landing_u_regularization_scale = " << landing_u_regularization_scale
        << " sets the controller's u_regularization_weights and u_regularization_modes; leave those empty or set the "
           "scale to 1";
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
  return TasksOf(MakeHoppingOutputs(
      model, [](double, double* L, double* dL) { *L = 0.0, *dL = 0.0; }, params));
}

HoppingDiagram BuildHoppingDiagram(std::shared_ptr<const MultibodyModel> model,
                                   const HoppingReference::LegLengthFunction& leg_length,
                                   HoppingReference::JumpPlanner jump_planner,
                                   HoppingReference::LandingPlanner landing_planner, const HoppingDiagramParams& params,
                                   PlantKind plant, const HoppingControllerFactory& controller_factory) {
  params.Validate();
  if (!controller_factory) throw std::invalid_argument("BuildHoppingDiagram: the controller factory is empty");
  if (!model) throw std::invalid_argument("BuildHoppingDiagram: the model is null");
  // `model` is the reference's and the pose solver's: the Euler base (plant_base picks the plant's and the
  // controller's).
  model->RequireNqEqualsNv("BuildHoppingDiagram");
  HoppingDiagram d;
  d.model = model;
  d.leg_length = leg_length;
  d.params = params;
  d.layout = MakeHoppingOutputLayout(params.outputs);
  d.plant_kind = plant;
  DiagramBuilder b;
  // Perturbations of the simulated world: the plant may be pushed and built from a scaled model; the reference, its
  // planners and the controller keep `model`.
  const PerturbationParams& perturb = params.perturbations;
  HybridContactPlantParams plant_params = params.plant;
  BulletWorldPlantParams bullet_params = params.bullet_plant;
  plant_params.external_force_input = bullet_params.external_force_input = perturb.push.has_value();
  std::shared_ptr<const MultibodyModel> base_model = model;
  if (params.plant_base == PlantBase::kQuaternion) {
    if (plant != PlantKind::kHybrid)
      throw std::invalid_argument(
          std::string("BuildHoppingDiagram: plant_base = quaternion needs the hybrid plant, not ") + ToString(plant));
    if (perturb.push.has_value())
      throw std::invalid_argument(
          "BuildHoppingDiagram: plant_base = quaternion does not take perturbations.push (its generalized force is in "
          "the Euler model's coordinates)");
    base_model = LoadQuaternionTwin(*model);
  }
  const std::shared_ptr<const MultibodyModel> plant_model =
      perturb.model_mismatch() ? std::make_shared<const MultibodyModel>(
                                     ScaleMassAndFriction(*base_model, perturb.mass_scale, perturb.friction_scale))
                               : base_model;
  d.plant_model = plant_model;
  d.plant = b.AddSystem(MakeContactPlant(plant, "plant", plant_model,
                                         ContactModeGraph::JumpFlightLanding("left_foot", "right_foot"),
                                         Terrain::Flat(), plant_params, bullet_params));
  // The Euler state the reference and the logger read: the plant's, or its map on the quaternion base. The controller
  // runs on the plant's base and reads the plant's state.
  std::string state_source = "plant";
  if (params.plant_base == PlantBase::kQuaternion) {
    d.euler_state =
        b.AddSystem(std::make_unique<QuaternionToEulerState>("euler_state", model, plant_model, params.euler_state));
    b.Connect("plant", "state", "euler_state", "quaternion_state");
    state_source = "euler_state";
  }
  d.reference = b.AddSystem(std::make_unique<HoppingReference>("reference", model, leg_length, std::move(jump_planner),
                                                               std::move(landing_planner), d.layout, params.reference));
  HoppingControllerSpec spec;
  spec.model = base_model;
  spec.mode_contacts = ActiveContactsPerMode(*d.plant);
  spec.outputs = MakeHoppingOutputs(*base_model, leg_length, params.outputs);
  spec.tasks = TasksOf(spec.outputs);
  spec.layout = d.layout;
  spec.controller = params.controller;
  spec.controller.contact_stabilization = params.plant.dynamics;
  if (params.landing_u_regularization_scale != 1.0) {
    spec.controller.u_regularization_weights =
        Eigen::VectorXd::Constant(model->nu(), params.landing_u_regularization_scale);
    spec.controller.u_regularization_modes = {HoppingDomain::kLanding};
  }
  d.tasks = spec.tasks;
  std::unique_ptr<System> controller = controller_factory(spec);
  if (!controller) throw std::invalid_argument("BuildHoppingDiagram: the controller factory returned no system");
  d.controller = controller.get();
  b.AddSystem(std::move(controller), spec.name);
  b.Connect(state_source, "state", "reference", "state");
  b.Connect("plant", "mode", "reference", "mode");
  b.Connect("plant", "contact_forces", "reference", "contact_forces");
  b.Connect("reference", "desired", spec.name, "desired");
  b.Connect("reference", "domain", spec.name, "mode");
  // plant.state → controller.state and controller.u → plant.u, through the perturbation blocks that are on.
  d.perturbation_blocks = AddPerturbationBlocks(b, perturb, base_model, "plant", spec.name);
  b.ExportOutput(spec.name, "u", "u");
  if (d.controller->HasOutputPort("qp_failures")) b.ExportOutput(spec.name, "qp_failures", "qp_failures");
  std::vector<std::pair<std::string, std::string>> logged = {{"plant", "state"},      {"plant", "mode"},
                                                             {"plant", "com"},        {"plant", "contact_forces"},
                                                             {"reference", "domain"}, {"reference", "desired"}};
  if (d.euler_state) logged.push_back({"euler_state", "state"});
  for (const char* port : {"u", "V", "delta", "contact_forces", "qp_status", "solve_time_s"})
    if (d.controller->HasOutputPort(port)) logged.push_back({spec.name, port});
  d.logger = AddVectorLogger(b, "logger", logged, params.log_period_s);
  d.diagram = b.Build("hopping");
  return d;
}

const Eigen::VectorXd& HoppingEulerState(const HoppingDiagram& d, const Context& context) {
  if (d.euler_state) return d.euler_state->EvalOutput(d.diagram->GetSubsystemContext(*d.euler_state, context), "state");
  return d.plant->EvalOutput(d.diagram->GetSubsystemContext(*d.plant, context), "state");
}

void SetHoppingInitialState(const HoppingDiagram& d, Context& context, const Eigen::VectorXd& q) {
  LeafContext& pc = d.diagram->GetMutableSubsystemContext(*d.plant, context);
  const Eigen::VectorXd q_plant = d.euler_state ? EulerConfigurationToQuaternion(q) : q;
  d.plant->SetState(pc, q_plant, Eigen::VectorXd::Zero(q.size()), "jump");
  LeafContext& rc = d.diagram->GetMutableSubsystemContext(*d.reference, context);
  d.reference->Initialize(rc, q);
  if (const DelayLine* delay = d.perturbation_blocks.sensor_latency)
    delay->SetHistory(
        d.diagram->GetMutableSubsystemContext(*delay, context),
        (Eigen::VectorXd(q_plant.size() + q.size()) << q_plant, Eigen::VectorXd::Zero(q.size())).finished());
}

SimulatorConfig HoppingSimulatorConfig() {
  // ARKODE's explicit Bogacki-Shampine 3(2), rtol 1e-5, atol 1e-7, each 0.5 ms interval started with the error test's
  // step (ours; spec [R] A5: CVODE BDF at 1e-6 / 1e-8): the flow is not stiff at these steps and BDF paid a Jacobian
  // at every restart of the zero-order hold (docs/design-notes.md#hopping-integrator).
  return ExplicitRestartingSimulatorConfig(1e-5, 1e-7);
}

}  // namespace rome
