#include "diagrams/stepping_stones/stepping_stones_diagram.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>

#include "framework/primitives.h"
#include "systems/controllers/task_space_tasks.h"
#include "systems/multibody/model_scaling.h"
#include "systems/multibody/pose_constraints.h"

namespace rome {

namespace {

// Checks that `controller` has the seam's ports (see stepping_stones_diagram.h), naming the missing or wrong one.
void CheckControllerPorts(const System& controller, int nv, int nu, int task_rows) {
  auto check = [&](bool input, const std::string& port, const PortInfo& expected) {
    const bool has = input ? controller.HasInputPort(port) : controller.HasOutputPort(port);
    const std::string what = std::string(input ? "input" : "output") + " port '" + port + "'";
    if (!has)
      throw std::invalid_argument("BuildSteppingStonesDiagram: controller '" + controller.name() + "' has no " + what +
                                  " (" + expected.TypeString() +
                                  "); a stepping-stones controller needs inputs state, mode, desired and outputs u, "
                                  "qp_failures, qp_status");
    const PortInfo& info = input ? controller.input_port(controller.GetInputPortIndex(port))
                                 : controller.output_port(controller.GetOutputPortIndex(port));
    if (!info.SameTypeAs(expected))
      throw std::invalid_argument("BuildSteppingStonesDiagram: controller '" + controller.name() + "': " + what +
                                  " carries " + info.TypeString() + ", expected " + expected.TypeString());
  };
  check(true, "state", {"state", 2 * nv, {}, nullptr});
  check(true, "mode", {"mode", 0, {}, &typeid(int)});
  check(true, "desired", {"desired", 3 * task_rows, {}, nullptr});
  check(false, "u", {"u", nu, {}, nullptr});
  check(false, "qp_failures", {"qp_failures", 1, {}, nullptr});
  check(false, "qp_status", {"qp_status", 1, {}, nullptr});
}

// {contact, joint} pairs whose actuator gets zero torque while the contact is active: the actuated inboard joint of a
// line/flat foot's link (planar Cassie's toe), so that the stance ankle is passive like AMBER's point foot.
std::vector<std::pair<std::string, std::string>> PassiveStanceAnkles(const SteppingStonesDiagramParams& params,
                                                                     const MultibodyModel& model) {
  std::vector<std::pair<std::string, std::string>> out;
  if (!params.passive_stance_ankle) return out;
  for (const char* foot : {"left_foot", "right_foot"}) {
    const ContactInfo& c = model.contacts()[model.ContactIndex(foot)];
    if (c.type == ContactType::kPoint) continue;
    const std::string& joint = model.body(c.body).joint_name;
    for (const ActuatorInfo& a : model.actuators())
      if (a.joint == joint) out.emplace_back(c.name, joint);
  }
  return out;
}

double FlatFootPitch(const MultibodyModel& model, const std::string& contact) {
  MultibodyWorkspace ws(model);
  ws.SetPositions(model, model.q_nominal());
  const Eigen::Matrix3d& R = ws.R_world_link(model.contacts()[model.ContactIndex(contact)].body);
  return std::atan2(R(0, 2), R(0, 0));
}

}  // namespace

std::vector<std::shared_ptr<const TaskSpaceTask>> SteppingStonesTasks(const SteppingStonesDiagramParams& params,
                                                                      const SteppingStonesControllerSpec& spec) {
  const MultibodyModel& model = *spec.model;
  std::vector<std::shared_ptr<const TaskSpaceTask>> tasks = {
      std::make_shared<BodyPitchTask>(
          "torso_pitch", model, model.body(model.BodyOfVelocity(model.num_base_dofs() - 1)).name, params.torso_gains),
      std::make_shared<ComPositionTask>("com_height", std::vector<Axis>{Axis::kZ}, params.com_height_gains),
      PointPositionTask::ForContact("left_swing_foot", model, "left_foot", {Axis::kX, Axis::kZ},
                                    params.swing_foot_gains, {spec.right_stance_mode}),
      PointPositionTask::ForContact("right_swing_foot", model, "right_foot", {Axis::kX, Axis::kZ},
                                    params.swing_foot_gains, {spec.left_stance_mode}),
  };
  // Line/flat feet: the fifth output, the swing foot's pitch (its sole lands parallel to the stone).
  if (HasFootPitchOutput(model)) {
    tasks.push_back(std::make_shared<BodyPitchTask>(
        "left_swing_foot_pitch", model, model.contacts()[model.ContactIndex("left_foot")].link,
        params.swing_foot_pitch_gains, std::vector<int>{spec.right_stance_mode}));
    tasks.push_back(std::make_shared<BodyPitchTask>(
        "right_swing_foot_pitch", model, model.contacts()[model.ContactIndex("right_foot")].link,
        params.swing_foot_pitch_gains, std::vector<int>{spec.left_stance_mode}));
  }
  return tasks;
}

double SoleLength(const MultibodyModel& model) {
  double sole = 0.0;
  for (const ContactInfo& c : model.contacts()) {
    if (c.type == ContactType::kPoint) continue;
    MultibodyWorkspace ws(model);
    double x_min = 1e9, x_max = -1e9;
    for (const Eigen::Vector3d& p : c.points) {
      const double x = CalcPointPosition(model, ws, model.q_nominal(), c.body, p).x();
      x_min = std::min(x_min, x), x_max = std::max(x_max, x);
    }
    sole = std::max(sole, x_max - x_min);
  }
  return sole;
}

double SteppingStoneLengthFor(const MultibodyModel& model) {
  const double sole = SoleLength(model);
  return sole > 0.0 ? sole + 0.04 : 0.1;
}

SteppingStonesDiagramParams SteppingStonesDiagramParams::ForRobot(const std::string& sidecar) {
  SteppingStonesDiagramParams p;
  p.robot_sidecar = sidecar;
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(sidecar, {.euler_floating_base = true});
  if (!HasFootPitchOutput(model)) return p;
  // Line/flat feet (planar Cassie). The paper's E* = 0.5, and u_des >= −1 m/s (ours; AMBER −1.5 m/s): unbounded, short
  // steps down ask for a steep fall that the CLF-QP does not recover from
  // (docs/design-notes.md#stepping-stones-cassie-udes-bound).
  p.target_orbital_energy = 0.5;
  p.planner.min_pre_impact_vertical_velocity_mps = -1.0;
  // z0 (hopping spec C.12): the nominal standing pose's COM height above its soles.
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd& q = model.q_nominal();
  const double sole_z = CalcPointPosition(model, ws, q, model.contacts()[0].body, model.contacts()[0].frame_origin).z();
  p.supervisor.walking_com_height_m = CalcComPosition(model, ws, q).z() - sole_z;
  // No long-step cap: planar Cassie walks flat 0.8 m steps at its nominal height (1.60 m/s at E* = 1.5).
  p.supervisor.max_com_foot_distance_m = std::numeric_limits<double>::infinity();
  // Swing foot Kp 900 1/s², Kd 60 1/s (critically damped, 30 rad/s; AMBER: 400, 40): with AMBER's gains the rear foot
  // lags its lift on a steep step up. Cassie's legs are light, so the torques stay small
  // (docs/design-notes.md#stepping-stones-cassie-swing, as the choices below).
  p.swing_foot_gains = TaskGains{5.0, 900.0, 60.0};
  // The swing foot's desired vertical velocity starts at 0 (lift_off_at_rest): with the paper's curve the foot, at
  // rest on its stone, starts with a velocity error of about 0.7 m/s that the CLF-QP below corrects at the torque
  // limits in the first samples of every step.
  p.outputs.swing_foot.lift_off_at_rest = true;
  // CLF-QP: ε = 0.02 (output bandwidth about 1/ε = 50 rad/s, as fast as the swing foot's 30 rad/s PD above needs),
  // γ = 1 (V decays at γ/ε = 50 1/s instead of the CARE bound λ_min(Q)/λ_max(P)/ε ≈ 18 1/s), and the friction
  // pyramid's apex 5 N up (a stance foot that unloads keeps |F_t|/F_n well inside μ over a held sample).
  p.clf_controller.epsilon = 0.02;
  p.clf_controller.gamma = 1.0;
  p.clf_controller.contact.friction_cone_offset_N = 5.0;
  // The torso pitch is tracked in the cost only (cost_only_outputs, with its PD gains), and the cost of the other
  // outputs is their feedforward ÿ_d (cost_pd_feedback off): as a CLF output the torso took the stance force, at the
  // friction pyramid's edge (slips).
  p.clf_controller.cost_pd_feedback = false;
  p.clf_controller.cost_only_outputs = {"torso_pitch"};
  // The COM height's cost weight 20 in the CLF-QP (ours; the task-space QP keeps 1): with 1 the gait ran faster than
  // the planner's momentum and the COM rose out of the swing leg's reach
  // (docs/design-notes.md#stepping-stones-cassie-com-weight).
  p.clf_com_height_weight = 20.0;
  // Vertical-COM MPC: upward COM acceleration at most 12 m/s² (the stance leg gives about 6 crouched after a step up);
  // with the default's terminal velocity first (ρ_p = 1e3), an unreachable rise otherwise ends in an impact rising at
  // 1 m/s, a COM out of the next swing leg's reach and a whip of that leg
  // (docs/design-notes.md#stepping-stones-cassie-whip).
  p.mpc.mpc.max_acceleration = 12.0;
  // The swing curve also clears the next stone's rear edge: the toe reaches half a sole ahead of the foot's midpoint,
  // and on a short step up the next stone's rear face can be closer than that; without the check the toe runs into it
  // (docs/design-notes.md#stepping-stones-cassie-first-step).
  p.outputs.swing_foot.clear_next_stone_rear_edge = true;
  return p;
}

bool HasFootPitchOutput(const MultibodyModel& model) {
  return model.contacts()[model.ContactIndex("left_foot")].type != ContactType::kPoint ||
         model.contacts()[model.ContactIndex("right_foot")].type != ContactType::kPoint;
}

SteppingStonesControllerFactory ClfQpControllerFactory(const SteppingStonesDiagramParams& params) {
  SteppingStonesDiagramParams clf_params = params;
  if (!std::isnan(params.clf_com_height_weight)) {
    if (!(params.clf_com_height_weight > 0) || !std::isfinite(params.clf_com_height_weight))
      throw std::invalid_argument(
          "ClfQpControllerFactory: params.clf_com_height_weight must be positive (or NaN), got " +
          std::to_string(params.clf_com_height_weight));
    clf_params.com_height_gains.weight = params.clf_com_height_weight;
  }
  return [params = std::move(clf_params)](const SteppingStonesControllerSpec& spec) -> std::unique_ptr<System> {
    std::vector<ClfOutput> outputs;
    for (auto& task : SteppingStonesTasks(params, spec))
      outputs.push_back(ClfOutput::RelativeDegreeTwo(std::move(task)));
    ClfQpParams cp = params.clf_controller;
    cp.contact_stabilization = spec.contact_stabilization;
    for (const auto& pair : PassiveStanceAnkles(params, *spec.model)) cp.zero_torque_in_contact.push_back(pair);
    return std::make_unique<ClfQpController>(spec.name, spec.model, spec.mode_contacts, std::move(outputs), cp);
  };
}

SteppingStonesControllerFactory SaturatedControllerFactory(SteppingStonesControllerFactory controller,
                                                           Eigen::VectorXd lower, Eigen::VectorXd upper) {
  if (!controller) throw std::invalid_argument("SaturatedControllerFactory: the controller factory is empty");
  return [controller = std::move(controller), lower = std::move(lower),
          upper = std::move(upper)](const SteppingStonesControllerSpec& spec) -> std::unique_ptr<System> {
    const int nu = spec.model->nu();
    if (lower.size() != nu || upper.size() != nu)
      throw std::invalid_argument("SaturatedControllerFactory: lower and upper need nu = " + std::to_string(nu) +
                                  " elements (robot '" + spec.model->name() + "'), got " +
                                  std::to_string(lower.size()) + " and " + std::to_string(upper.size()));
    SteppingStonesControllerSpec inner = spec;
    inner.name = "controller";
    std::unique_ptr<System> block = controller(inner);
    if (!block)
      throw std::invalid_argument("SaturatedControllerFactory: the wrapped controller factory returned no block");
    DiagramBuilder b;
    b.AddSystem(std::move(block), "controller");
    b.AddSystem(std::make_unique<Saturation>("saturation", lower, upper));
    b.Connect("controller", "u", "saturation", "u");
    for (const char* port : {"state", "mode", "desired"}) b.ExportInput("controller", port);
    b.ExportOutput("saturation", "y", "u");
    for (const char* port : {"qp_failures", "qp_status"}) b.ExportOutput("controller", port);
    return b.Build(spec.name);
  };
}

SteppingStonesControllerFactory TaskSpaceQpControllerFactory(const SteppingStonesDiagramParams& params) {
  return [params](const SteppingStonesControllerSpec& spec) -> std::unique_ptr<System> {
    TaskSpaceQpParams cp = params.controller;
    cp.contact_stabilization = spec.contact_stabilization;
    for (const auto& pair : PassiveStanceAnkles(params, *spec.model)) cp.zero_torque_in_contact.push_back(pair);
    return std::make_unique<TaskSpaceQpController>(spec.name, spec.model, spec.mode_contacts,
                                                   SteppingStonesTasks(params, spec), cp);
  };
}

namespace {

// "SteppingStonesDiagramParams: <field> = <value> [unit] is outside <range>" unless lo <= value <= hi (lo excluded when
// lo_open); NaN is always outside.
void RequireIn(const char* field, double value, double lo, double hi, bool lo_open, const char* unit) {
  if ((lo_open ? value > lo : value >= lo) && value <= hi) return;
  std::ostringstream out;
  out << "SteppingStonesDiagramParams: " << field << " = " << value << (*unit ? " " : "") << unit << " is outside "
      << (lo_open ? "(" : "[") << lo << ", " << hi << "]" << (*unit ? " " : "") << unit;
  throw std::invalid_argument(out.str());
}

void RequireGains(const char* name, const TaskGains& g) {
  const std::string n(name);
  RequireIn((n + ".weight").c_str(), g.weight, 0.0, 1e6, false, "");
  RequireIn((n + ".kp").c_str(), g.kp, 0.0, 1e6, false, "1/s^2");
  RequireIn((n + ".kd").c_str(), g.kd, 0.0, 1e5, false, "1/s");
}

}  // namespace

void SteppingStonesDiagramParams::Validate() const {
  // E* > 0: the LIP crosses the stance foot and walks forwards (E* <= 0 turns back before reaching the stone).
  RequireIn("target_orbital_energy", target_orbital_energy, 0.0, 10.0, true, "m^2/s^2");
  RequireIn("impact_fraction", impact_fraction, 0.0, 1.0 - 1e-9, true, "");
  RequireIn("log_period_s", log_period_s, 1e-4, 10.0, false, "s");
  RequireIn("initial_com_x_m", initial_com_x_m, -0.5, 0.5, false, "m");
  RequireIn("supervisor.max_steps", supervisor.max_steps, 1, 10000, false, "");
  RequireIn("outputs.swing_foot.clearance", outputs.swing_foot.clearance, 0.0, 1.0, true, "m");
  RequireIn("mpc.hold_plan_below_horizon_s", mpc.hold_plan_below_horizon_s, 0.0, 10.0, false, "s");
  if (!std::isnan(clf_com_height_weight))
    RequireIn("clf_com_height_weight", clf_com_height_weight, 0.0, 1000.0, true, "");
  RequireIn("clf_controller.update_period_s", clf_controller.update_period_s, 1e-5, 1.0, false, "s");
  RequireIn("controller.friction_margin", controller.friction_margin, 0.0, 1.0, true, "");
  RequireIn("controller.min_normal_force_N", controller.min_normal_force_N, 0.0, 1e4, false, "N");
  RequireIn("controller.friction_cone_offset_N", controller.friction_cone_offset_N, 0.0, 1e4, false, "N");
  RequireGains("torso_gains", torso_gains);
  RequireGains("com_height_gains", com_height_gains);
  RequireGains("swing_foot_gains", swing_foot_gains);
  RequireGains("swing_foot_pitch_gains", swing_foot_pitch_gains);
}

SteppingStonesDiagram BuildSteppingStonesDiagram(const Terrain& terrain, const SteppingStonesDiagramParams& params,
                                                 const SteppingStonesControllerFactory& controller, PlantKind plant) {
  params.Validate();
  SteppingStonesDiagram d;
  d.model = std::make_shared<const MultibodyModel>(
      MultibodyModel::LoadFromSidecar(params.robot_sidecar, {.euler_floating_base = true}));
  const auto& model = *d.model;
  DiagramBuilder b;
  auto graph = ContactModeGraph::AlternatingSingleSupport("left_foot", "right_foot", true);
  // The plant's fall guard compares the absolute base height with min_base_height_m; here that parameter is read as
  // a height above the lowest stone, so that walking down stairs is not taken for a fall (the supervisor watches
  // the COM height above the stance foot).
  HybridContactPlantParams plant_params = params.plant;
  double lowest_stone = 0.0;
  for (const SteppingStone& s : terrain.stones()) lowest_stone = std::min(lowest_stone, s.top_height_m);
  plant_params.min_base_height_m += lowest_stone;
  BulletWorldPlantParams bullet_params = params.bullet_plant;
  bullet_params.min_base_height_m += lowest_stone;
  // Perturbations of the simulated world (the supervisor and the controller keep the nominal model and terrain).
  const PerturbationParams& perturb = params.perturbations;
  perturb.Validate();
  if (perturb.push && plant != PlantKind::kHybrid)
    throw std::invalid_argument("BuildSteppingStonesDiagram: perturbations.push needs the hybrid plant (the " +
                                std::string(ToString(plant)) + " plant has no tau_external input)");
  plant_params.external_force_input = perturb.push.has_value();
  const std::shared_ptr<const MultibodyModel> plant_model =
      perturb.model_mismatch() ? std::make_shared<const MultibodyModel>(
                                     ScaleMassAndFriction(model, perturb.mass_scale, perturb.friction_scale))
                               : d.model;
  const Terrain plant_terrain =
      WithStoneHeightErrors(terrain, perturb.stone_height_sigma_m, PerturbationStreamSeed(perturb.seed, 3));
  d.plant =
      b.AddSystem(MakeContactPlant(plant, "plant", plant_model, graph, plant_terrain, plant_params, bullet_params));

  SteppingStonesSupervisorParams sp = params.supervisor;
  sp.impact_fraction = params.impact_fraction;
  sp.posture.com_x_fraction = params.impact_fraction;
  d.supervisor = b.AddSystem(std::make_unique<SteppingStonesSupervisor>("supervisor", d.model, terrain, sp));

  MomentumRegulationPlannerParams pp = params.planner;
  pp.target_orbital_energy = params.target_orbital_energy;
  pp.impact_fraction = params.impact_fraction;
  d.planner = b.AddSystem(std::make_unique<MomentumRegulationPlannerSystem>("planner", pp));
  d.mpc = b.AddSystem(std::make_unique<VerticalComMpcSystem>("vertical_com_mpc", params.mpc));
  SteppingStonesOutputsSystemParams op = params.outputs;
  if (std::isnan(op.swing_foot.stance_stone_half_length)) {
    op.swing_foot.stance_stone_half_length = 0.0;
    for (const SteppingStone& stone : terrain.stones())
      op.swing_foot.stance_stone_half_length = std::max(op.swing_foot.stance_stone_half_length, 0.5 * stone.length_m);
    // A line/flat sole reaches half its length beyond its midpoint (the swing output): its heel and toe must clear
    // the stance stone too (0 for point feet).
    op.swing_foot.stance_stone_half_length += 0.5 * SoleLength(model);
  }
  d.outputs = b.AddSystem(std::make_unique<SteppingStonesOutputsSystem>("outputs", op));
  SteppingStonesOutputAdapterParams adapter_params;
  if (HasFootPitchOutput(model)) {
    adapter_params.foot_pitch = true;
    adapter_params.left_foot_flat_pitch_rad = FlatFootPitch(model, "left_foot");
    adapter_params.right_foot_flat_pitch_rad = FlatFootPitch(model, "right_foot");
  }
  d.output_adapter = b.AddSystem(std::make_unique<SteppingStonesOutputAdapter>("output_adapter", adapter_params));

  SteppingStonesControllerSpec spec;
  spec.model = d.model;
  spec.mode_contacts = ActiveContactsPerMode(*d.plant);
  spec.contact_stabilization = plant_params.dynamics;
  spec.left_stance_mode = d.plant->GetModeIndex("left_foot_stance");
  spec.right_stance_mode = d.plant->GetModeIndex("right_foot_stance");
  spec.num_task_rows = d.output_adapter->num_task_rows();
  {
    const std::vector<std::string> row_names = d.output_adapter->task_row_names();
    int row = 0;
    for (const auto& task : SteppingStonesTasks(params, spec)) {
      spec.tasks.push_back(
          {task->name(), row, {row_names.begin() + row, row_names.begin() + row + task->size()}, task->active_modes()});
      row += task->size();
    }
    if (row != spec.num_task_rows)
      throw std::logic_error("BuildSteppingStonesDiagram: the tasks span " + std::to_string(row) +
                             " rows, the output adapter " + std::to_string(spec.num_task_rows));
  }
  std::unique_ptr<System> block = controller ? controller(spec) : TaskSpaceQpControllerFactory(params)(spec);
  if (!block) throw std::invalid_argument("BuildSteppingStonesDiagram: the controller factory returned no block");
  CheckControllerPorts(*block, model.nv(), model.nu(), spec.num_task_rows);
  d.controller = b.AddSystem(std::move(block), "controller");

  b.Connect("plant", "state", "supervisor", "state");
  b.Connect("plant", "mode", "supervisor", "mode");
  b.Connect("planner", "u_des", "supervisor", "u_des");
  b.Connect("planner", "L_des", "supervisor", "L_des");
  b.Connect("supervisor", "com_state", "planner", "com_state");
  b.Connect("supervisor", "angular_momentum", "planner", "angular_momentum");
  b.Connect("supervisor", "step", "planner", "step");
  b.Connect("supervisor", "pre_impact_com_height", "planner", "pre_impact_com_height");
  b.Connect("supervisor", "com_vertical_state", "vertical_com_mpc", "com_vertical_state");
  b.Connect("planner", "vertical_com_target", "vertical_com_mpc", "target");
  b.Connect("supervisor", "com_state", "outputs", "com_state");
  b.Connect("supervisor", "step_parameters", "outputs", "step_parameters");
  b.Connect("vertical_com_mpc", "com_height_desired", "outputs", "com_height_desired");
  b.Connect("outputs", "y_desired", "output_adapter", "y_desired");
  b.Connect("outputs", "ydot_desired", "output_adapter", "ydot_desired");
  b.Connect("outputs", "yddot_desired", "output_adapter", "yddot_desired");
  b.Connect("supervisor", "stance_foot", "output_adapter", "stance_foot");
  b.Connect("plant", "mode", "output_adapter", "mode");
  b.Connect("plant", "mode", "controller", "mode");
  b.Connect("output_adapter", "desired", "controller", "desired");
  // plant.state → controller.state and controller.u → plant.u, through the perturbation blocks that are on.
  d.perturbation_blocks = AddPerturbationBlocks(b, perturb, d.model, "plant", "controller");
  d.logger = AddVectorLogger(b, "logger",
                             {{"plant", "state"},
                              {"plant", "mode"},
                              {"plant", "com"},
                              {"supervisor", "com_state"},
                              {"supervisor", "angular_momentum"},
                              {"supervisor", "stance_foot"},
                              {"planner", "u_des"},
                              {"planner", "L_des"},
                              {"planner", "time_to_impact"},
                              {"supervisor", "pre_impact_com_height"},
                              {"vertical_com_mpc", "com_height_desired"},
                              {"plant", "contact_forces"},
                              {"controller", "u"},
                              {"controller", "qp_status"},
                              {"vertical_com_mpc", "qp_status"},
                              {"outputs", "y_desired"},
                              {"outputs", "phase"}},
                             params.log_period_s);
  d.diagram = b.Build("stepping_stones");
  return d;
}

Terrain PeriodicSteppingStones(double step_length_m, double step_height_m, int num_stones, double stone_length_m) {
  if (!(step_length_m > stone_length_m))
    throw std::invalid_argument("PeriodicSteppingStones: step length " + std::to_string(step_length_m) +
                                " m must exceed the stone length " + std::to_string(stone_length_m) + " m");
  if (num_stones < 2)
    throw std::invalid_argument("PeriodicSteppingStones: needs at least 2 stones, got " + std::to_string(num_stones));
  std::vector<SteppingStone> stones;
  for (int k = 0; k < num_stones; ++k) stones.push_back({k * step_length_m, k * step_height_m, stone_length_m});
  return Terrain::Stones(stones);
}

Terrain RandomSteppingStones(const RandomSteppingStonesParams& p) {
  if (!(p.min_gap_m > p.stone_length_m && p.max_gap_m >= p.min_gap_m && p.max_rise_m >= 0))
    throw std::invalid_argument(
        "RandomSteppingStones: needs stone_length_m < min_gap_m <= max_gap_m and max_rise_m >= 0, got " +
        std::to_string(p.stone_length_m) + ", " + std::to_string(p.min_gap_m) + ", " + std::to_string(p.max_gap_m) +
        ", " + std::to_string(p.max_rise_m));
  if (p.num_stones < 2)
    throw std::invalid_argument("RandomSteppingStones: needs at least 2 stones, got " + std::to_string(p.num_stones));
  std::mt19937 rng(p.seed);
  std::uniform_real_distribution<double> gap(p.min_gap_m, p.max_gap_m);
  std::uniform_real_distribution<double> rise(-p.max_rise_m, p.max_rise_m);
  std::vector<SteppingStone> stones;
  double x = 0, z = 0;
  stones.push_back({0, 0, p.stone_length_m});
  for (int k = 1; k < p.num_stones; ++k) {
    x += gap(rng);
    z += rise(rng);
    stones.push_back({x, z, p.stone_length_m});
  }
  return Terrain::Stones(stones);
}

SimulatorConfig SteppingStonesSimulatorConfig() {
  SimulatorConfig config;
  config.scheme = IntegrationScheme::kExplicitRungeKutta;
  config.explicit_rk_method = ExplicitRungeKuttaMethod::kBogackiShampine32;
  config.relative_tolerance = 1e-6;
  config.absolute_tolerance = 1e-8;
  config.initial_step_s = 1e-3;
  return config;
}

Eigen::VectorXd SteppingStonesInitialState(const MultibodyModel& model, const Terrain& terrain,
                                           const SteppingStonesDiagramParams& params) {
  const int nv = model.nv();
  if (terrain.stones().empty()) throw std::runtime_error("SteppingStonesInitialState: the terrain has no stones");
  if (!model.is_planar())
    throw std::invalid_argument("SteppingStonesInitialState: robot '" + model.name() + "' is not planar");
  const auto& stones = terrain.stones();
  MultibodyWorkspace ws(model);
  // The pose is solved with the first stone at the origin and then moved onto it (exact for the planar base's x and z):
  // a stone far from the origin (|z| up to 1e6 m) would otherwise leave Newton's 1e-12 tolerance below the
  // coordinates' resolution.
  const Eigen::Vector2d stone_world(stones[0].x_center_m, stones[0].top_height_m), stone = Eigen::Vector2d::Zero();
  const double com_height = params.supervisor.walking_com_height_m;
  const int pitch = model.num_base_dofs() - 1;
  // Configuration: SolvePose (Newton with minimum-norm steps) from the nominal pose.
  Eigen::VectorXd q0 = model.q_nominal();
  // Each foot on the stone centre: a point foot by its point; a line/flat foot by its frame origin's x and every
  // contact point's z (the sole flat on the stone). Then the COM, the torso pitch and the loop closures.
  std::vector<PoseConstraint> pose;
  for (const char* foot : {"left_foot", "right_foot"}) {
    const ContactInfo& info = model.contacts()[model.ContactIndex(foot)];
    pose.push_back(PoseConstraint::ContactPoint(model, foot, 0, stone.x()));
    if (info.type == ContactType::kPoint) {
      pose.push_back(PoseConstraint::ContactPoint(model, foot, 2, stone.y()));
    } else {
      for (const Eigen::Vector3d& p : info.points)
        pose.push_back(PoseConstraint::Point(model, info.link, p, 2, stone.y()));
    }
  }
  const int com_x_row = static_cast<int>(pose.size());
  pose.push_back(PoseConstraint::Com(0, stone.x() + params.initial_com_x_m));
  pose.push_back(PoseConstraint::Com(2, stone.y() + com_height));
  pose.push_back(PoseConstraint::Coordinate(pitch, 0.0));
  for (const PoseConstraint& c : PoseConstraint::LoopClosures(model)) pose.push_back(c);
  Eigen::VectorXd q;
  try {
    q = SolvePose(model, ws, q0, pose, {.max_iterations = 100, .tolerance = 1e-12});
  } catch (const std::runtime_error& e) {
    std::ostringstream height;
    height << com_height;  // 6 significant digits (std::to_string writes 1e308 with 309)
    throw std::runtime_error("SteppingStonesInitialState: robot '" + model.name() +
                             "' cannot stand on the first stone with its COM " + height.str() +
                             " m above the feet (supervisor.walking_com_height_m): " + e.what());
  }
  const int m = static_cast<int>(pose.size());
  Eigen::MatrixXd C(m, nv);
  Eigen::VectorXd c(m);
  CalcPoseConstraints(model, ws, q, pose, c, C);  // C = d(constraints)/dq at the solution
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(m);
  const double lambda_squared = params.planner.gravity / com_height;
  rhs[com_x_row] = std::sqrt(
      std::max(params.target_orbital_energy + lambda_squared * params.initial_com_x_m * params.initial_com_x_m, 0.0));
  const Eigen::VectorXd v = C.completeOrthogonalDecomposition().solve(rhs);
  if (!((C * v - rhs).norm() < 1e-9))
    throw std::runtime_error("SteppingStonesInitialState: no joint velocity moves the COM of robot '" + model.name() +
                             "' with both feet at rest");
  Eigen::VectorXd x(2 * nv);
  x << q, v;
  x[0] += stone_world.x();  // planar base: q = [x, z, pitch, joints]
  x[1] += stone_world.y();
  return x;
}

void SetSteppingStonesInitialState(const SteppingStonesDiagram& d, const SteppingStonesDiagramParams& params,
                                   Context& context) {
  const int nv = d.model->nv();
  const Eigen::VectorXd x = SteppingStonesInitialState(*d.model, d.plant->terrain(), params);
  d.plant->SetState(d.diagram->GetMutableSubsystemContext(*d.plant, context), x.head(nv), x.tail(nv),
                    "left_foot_stance");
  d.supervisor->Initialize(d.diagram->GetMutableSubsystemContext(*d.supervisor, context), x, 0);
  // A sensor with latency has been reading the initial state.
  if (const DelayLine* delay = d.perturbation_blocks.sensor_latency)
    delay->SetHistory(d.diagram->GetMutableSubsystemContext(*delay, context), x);
}

}  // namespace rome
