#include "diagrams/walking/walking_diagram.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

#include "framework/simulator_presets.h"
#include "systems/multibody/model_scaling.h"
#include "systems/controllers/contact_velocity_projection.h"
#include "systems/controllers/task_space_qp_controller.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome {

ClfQpParams WalkingDiagramParams::DefaultWalkingControllerParams() {
  ClfQpParams p;
  p.update_period_s = 1e-3;
  p.epsilon = 0.1;
  p.relaxation_weight = 1e5;
  p.force_band = true;
  p.force_band_halfwidth = 0.1;
  p.contact.friction_coefficient = 0.6;
  p.contact.min_normal_force_N = 0.0;
  p.force_band_carry_inactive = true;  // a late touchdown: the stance foot keeps the planned total (ours)
  p.force_band_at_hold_end = true;     // the band on the force at the end of the held sample (ours)
  // Ours: the wrench rows also hold at the end of the held sample, so that an unloading foot's torsion falls with its
  // normal force (docs/design-notes.md#walking-hold-drift).
  p.predict_hold_drift = true;
  p.hold_drift_settle_s = 0.003;    // ours: Bullet's touchdown impacts last 2-3 steps
  p.force_band_margin_N = 0.5;      // ours: the plant misses an edge the QP holds by < 0.05 N (design notes)
  p.contact.friction_margin = 0.5;  // ours: room for the force drift over a held sample as a foot unloads
  // Ours (spec [R]: |τ_z| ≤ 0.02 m f_z): a rigid sole's four-corner wrench cone, so that the QP asks no more torsion
  // than the plant's four corners (sole_torsion) or Bullet's hold. Its yaw rows on the whole sole less 2 mm, and the
  // corners' μ 0.75 against the sole's 0.8: a relative margin for the wrench's drift over a held sample as a foot
  // unloads (docs/design-notes.md#walking-strict-sole-default). yaw_moment_coefficient_m is unused with it.
  p.contact.corner_wrench_cone = true;
  p.contact.corner_cone_yaw_margin_m = 0.002;
  p.contact.yaw_moment_coefficient_m = 0.1;
  p.contact.corner_cone_friction_coefficient = 0.75;
  p.contact.cop_margin_m = 0.01;  // ours: the plant's CoP drifts by ~1 mm over a held sample when the QP holds it on
                                  // the edge, more near lift-off (5 mm: 1 mm outside at F_z = 21 N in an -O1 build)
  p.resolve_at_events = true;
  // Ours: the stance feet are predicted as held, J q̈ + J̇ q̇ = 0, not with the plant's Baumgarte velocity feedback
  // −2α J q̇: the plant keeps J q̇ near 0 itself, and α = 10 1/s on a measured J q̇ turns sensor noise into predicted
  // contact force (a rigid sole then slips torsionally at 5e-5 rad of noise; docs/design-notes.md
  // #walking-controller-contact-model). The exoskeleton has no loop closure for β.
  p.contact_stabilization.baumgarte_alpha_per_s = 0.0;
  // Ours (default 1e-6): the torque penalty is relative to the largest output curvature, the swing foot's rotation
  // (a 1.3 kg foot); DenseQpSolver needs pivots above 1e-8 of H's largest diagonal, so 1e-8 is the least it accepts
  // (below: kNonConvex, held torques); 1e-6 starves the stance knee (docs/design-notes.md#walking-controller-defaults).
  p.u_regularization = 3e-8;
  // Ours (spec §5.5 [C22]: the cost's target is μ = 0, the minimum-norm input, which leaves the CLF row as the only
  // feedback). The cost's target is the PD law ÿ_d − Kp e − Kd ė, so the row only bounds V̇
  // (docs/design-notes.md#walking-controller-defaults).
  p.cost_pd_feedback = true;
  p.force_band_loading_floor_N = -1.0;  // set by the builder: 2 x the plant's planned lift-off force (2 % of m g, ours)
  return p;
}

HybridContactPlantParams WalkingDiagramParams::DefaultWalkingPlantParams() {
  HybridContactPlantParams p;
  p.sole_torsion = true;  // the sole as strict as a rigid sole's four corners, as on Bullet (ours)
  return p;
}

namespace {
// "WHO: FIELD = VALUE UNIT is outside RANGE" when !ok.
void Require(bool ok, const std::string& who, const char* field, double value, const char* unit,
             const std::string& range) {
  if (ok) return;
  std::ostringstream os;
  os << who << ": " << field << " = " << value << (*unit ? " " : "") << unit << " is outside " << range;
  throw std::invalid_argument(os.str());
}
std::string Interval(double lo, double hi, const char* unit, char open = '[', char close = ']') {
  std::ostringstream os;
  os << open << lo << ", " << hi << close << (*unit ? " " : "") << unit;
  return os.str();
}
bool In(double x, double lo, double hi) { return x >= lo - 1e-12 && x <= hi + 1e-12; }
}  // namespace

void WalkingDiagramParams::Validate() const {
  const std::string who = "WalkingDiagramParams";
  const double c = controller.force_band_halfwidth;
  Require(c > 0 && c < 1, who, "controller.force_band_halfwidth", c, "", Interval(0, 1, "", '(', ')'));
  Require(In(swing.touchdown_velocity_mps, 0.05, 0.5), who, "swing.touchdown_velocity_mps",
          swing.touchdown_velocity_mps, "m/s", Interval(0.05, 0.5, "m/s"));
  Require(swing.apex_height_m > 0 && swing.apex_height_m <= 0.3, who, "swing.apex_height_m", swing.apex_height_m, "m",
          Interval(0, 0.3, "m", '('));
  Require(swing_foot_weight > 0 && std::isfinite(swing_foot_weight), who, "swing_foot_weight", swing_foot_weight, "",
          "(0, inf)");
  Require(swing_foot_orientation_weight > 0 && std::isfinite(swing_foot_orientation_weight), who,
          "swing_foot_orientation_weight", swing_foot_orientation_weight, "", "(0, inf)");
  Require(In(force_band_lead_periods, 0.0, 2.0), who, "force_band_lead_periods", force_band_lead_periods,
          "update periods", Interval(0, 2, "update periods"));
  perturbations.Validate();
}

void WalkingGait::Validate(const std::string& who) const {
  const double v[4] = {step_length_m, ssp_duration_s, dsp_duration_s, step_width_m};
  const char* names[4] = {"step_length_m", "ssp_duration_s", "dsp_duration_s", "step_width_m"};
  const char* units[4] = {"m", "s", "s", "m"};
  for (int i = 0; i < 4; ++i)
    Require(In(v[i], kMin[i], kMax[i]), who, names[i], v[i], units[i], Interval(kMin[i], kMax[i], units[i]));
}

void StandToWalkParams::Validate(const std::string& who) const {
  Require(In(stance_stagger_m, 0, 0.5), who, "stance_stagger_m", stance_stagger_m, "m", Interval(0, 0.5, "m"));
  Require(start_gait_steps >= 0 && start_gait_steps <= 20, who, "start_gait_steps", start_gait_steps, "", "[0, 20]");
  Require(lead_in_steps >= 0 && lead_in_steps <= 20, who, "lead_in_steps", lead_in_steps, "", "[0, 20]");
  const char* units[3] = {"m", "s", "s"};
  const double start[3] = {start_gait_step_length_m, start_gait_ssp_duration_s, start_gait_dsp_duration_s};
  const char* start_names[3] = {"start_gait_step_length_m", "start_gait_ssp_duration_s", "start_gait_dsp_duration_s"};
  const double lead[3] = {lead_in_step_length_m, lead_in_ssp_duration_s, lead_in_dsp_duration_s};
  const char* lead_names[3] = {"lead_in_step_length_m", "lead_in_ssp_duration_s", "lead_in_dsp_duration_s"};
  for (int i = 0; i < 3; ++i) {
    Require(In(start[i], kSideGaitMin[i], kSideGaitMax[i]), who, start_names[i], start[i], units[i],
            Interval(kSideGaitMin[i], kSideGaitMax[i], units[i]));
    Require(In(lead[i], kSideGaitMin[i], kSideGaitMax[i]), who, lead_names[i], lead[i], units[i],
            Interval(kSideGaitMin[i], kSideGaitMax[i], units[i]));
  }
  Require(sagittal_cop_margin_m >= 0 && sagittal_cop_margin_m < 0.07, who, "sagittal_cop_margin_m",
          sagittal_cop_margin_m, "m", Interval(0, 0.07, "m", '[', ')'));
  Require(transition_min_ssp_duration_s == 0 || In(transition_min_ssp_duration_s, 0.3, 1.0), who,
          "transition_min_ssp_duration_s", transition_min_ssp_duration_s, "s", "0 or [0.3, 1] s");
  Require(In(height_min_m, 0.7, 1.0), who, "height_min_m", height_min_m, "m", Interval(0.7, 1.0, "m"));
  Require(In(height_max_m, 0.7, 1.0) && height_max_m > height_min_m, who, "height_max_m", height_max_m, "m",
          "(height_min_m, 1] m = " + Interval(height_min_m, 1.0, "m", '('));
  Require(standing_height_m >= height_min_m && standing_height_m <= 1.0, who, "standing_height_m", standing_height_m,
          "m", "[height_min_m, 1] m = " + Interval(height_min_m, 1.0, "m"));
  Require(gait_change_max_force_fraction == 0 ||
              (gait_change_max_force_fraction > 1 && gait_change_max_force_fraction <= 3),
          who, "gait_change_max_force_fraction", gait_change_max_force_fraction, "m g", "0 (no bound) or (1, 3] m g");
  Require(gait_change_retry_max_force_fraction == 0 ||
              (gait_change_retry_max_force_fraction > 1 && gait_change_retry_max_force_fraction <= 3),
          who, "gait_change_retry_max_force_fraction", gait_change_retry_max_force_fraction, "m g",
          "0 (no retry) or (1, 3] m g");
  Require(periodic_max_force_fraction == 0 || (periodic_max_force_fraction > 1 && periodic_max_force_fraction <= 3),
          who, "periodic_max_force_fraction", periodic_max_force_fraction, "m g", "0 (never) or (1, 3] m g");
  Require(chain_steps >= 1 && chain_steps <= 20, who, "chain_steps", chain_steps, "", "[1, 20]");
  Require(reload_floor_fraction >= 0 && reload_floor_fraction < 0.5, who, "reload_floor_fraction",
          reload_floor_fraction, "m g", "[0, 0.5)");
  gait_graph.Validate();
  Require(min_dsp_stance_force_fraction >= 0 && min_dsp_stance_force_fraction < 1, who, "min_dsp_stance_force_fraction",
          min_dsp_stance_force_fraction, "", Interval(0, 1, "", '[', ')'));
  const double lateral = lateral_cop_margin_m, sag = sagittal_cop_margin_m, standing = standing_sagittal_cop_margin_m;
  if (!(sole.heel_m - sag > 0 && sole.toe_m - sag > 0))
    throw std::invalid_argument(who + ": sagittal_cop_margin_m = " + std::to_string(sag) + " m leaves no sole (heel " +
                                std::to_string(sole.heel_m) + " m, toe " + std::to_string(sole.toe_m) + " m)");
  if (!(lateral >= 0) || !(sole.left_m - lateral > 0 && sole.right_m - lateral > 0))
    throw std::invalid_argument(who + ": lateral_cop_margin_m = " + std::to_string(lateral) +
                                " must be >= 0 and leave a sole");
  if (!(standing < 0 || (sole.heel_m - standing > 0 && sole.toe_m - standing > 0)))
    throw std::invalid_argument(who + ": standing_sagittal_cop_margin_m = " + std::to_string(standing) +
                                " must be negative (use sagittal_cop_margin_m) or >= 0 and leave a sole");
}

namespace {
// The swing-foot parameters the diagram tracks: ankle_height_m from the robot's sole.
SwingFootTrajectoryParams RobotSwing(const MultibodyModel& m, const WalkingDiagramParams& params) {
  SwingFootTrajectoryParams swing = params.swing;
  swing.ankle_height_m = -m.contacts()[m.ContactIndex("left_foot")].points.front().z();
  return swing;
}
}  // namespace

std::function<void(const WalkingPlan&)> WalkingPoseCheck(std::shared_ptr<const MultibodyModel> model,
                                                         const WalkingDiagramParams& params) {
  if (model == nullptr) throw std::invalid_argument("WalkingPoseCheck: the model is null");
  if (!params.compensate_centroidal_momentum) return {};
  const SwingFootTrajectoryParams swing = RobotSwing(*model, params);
  const CentroidalMomentumCompensationParams compensation = params.compensation;
  return [model, swing, compensation](const WalkingPlan& plan) {
    WalkingPlan copy = plan;
    CompensateCentroidalMomentum(*model, copy, swing, compensation);
  };
}

WalkingPlanTorqueReport CheckWalkingPlanTorques(const MultibodyModel& model, const WalkingPlan& plan,
                                                const WalkingDiagramParams& params, double end_time_s) {
  return CalcWalkingPlanTorques(model, plan, RobotSwing(model, params), {.end_time_s = end_time_s});
}

std::vector<ClfOutput> WalkingControllerTasks(const MultibodyModel& m, const WalkingDiagramParams& params) {
  const int left_stance = kWalkingLeftStance, right_stance = kWalkingRightStance;
  TaskGains foot_gains;
  foot_gains.weight = params.swing_foot_weight;
  TaskGains foot_orientation_gains = foot_gains;
  foot_orientation_gains.weight = params.swing_foot_orientation_weight;
  const std::vector<Axis> xyz{Axis::kX, Axis::kY, Axis::kZ};
  TaskGains com_gains, pelvis_gains;  // weight 1 (the cost of Eq. (26) weighs every output alike)
  return {
      // Eq. (16): COM position and pelvis orientation, every mode.
      ClfOutput::RelativeDegreeTwo(std::make_shared<ComPositionTask>("com", xyz, com_gains)),
      ClfOutput::RelativeDegreeTwo(MakeBaseAngleTask("pelvis_roll", m, EulerAngle::kRoll, pelvis_gains)),
      ClfOutput::RelativeDegreeTwo(MakeBaseAngleTask("pelvis_pitch", m, EulerAngle::kPitch, pelvis_gains)),
      ClfOutput::RelativeDegreeTwo(MakeBaseAngleTask("pelvis_yaw", m, EulerAngle::kYaw, pelvis_gains)),
      // Eq. (17): swing foot position and orientation, in the other foot's stance only.
      ClfOutput::RelativeDegreeTwo(std::make_shared<PointPositionTask>(
          "left_ankle", m, "left_foot", Eigen::Vector3d::Zero(), xyz, foot_gains, std::vector<int>{right_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<BodyOrientationTask>(
          "left_foot_orientation", m, "left_foot", foot_orientation_gains, std::vector<int>{right_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<PointPositionTask>(
          "right_ankle", m, "right_foot", Eigen::Vector3d::Zero(), xyz, foot_gains, std::vector<int>{left_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<BodyOrientationTask>(
          "right_foot_orientation", m, "right_foot", foot_orientation_gains, std::vector<int>{left_stance})),
  };
}

std::vector<WalkingTaskRows> WalkingDesiredLayout(const std::vector<ClfOutput>& tasks) {
  std::vector<WalkingTaskRows> rows;
  int row = 0;
  for (const ClfOutput& t : tasks) {
    rows.push_back({t.name(), row, t.size()});
    row += t.size();
  }
  return rows;
}

std::unique_ptr<System> MakeWalkingClfQpController(const WalkingControllerSpec& spec) {
  return std::make_unique<ClfQpController>(spec.name, spec.model, spec.mode_contacts, spec.tasks, spec.params);
}

WalkingDiagram BuildWalkingDiagram(std::shared_ptr<const MultibodyModel> model, const WalkingPlan& plan,
                                   const WalkingDiagramParams& params, PlantKind plant,
                                   const WalkingControllerFactory& controller) {
  params.Validate();
  if (model == nullptr) throw std::invalid_argument("BuildWalkingDiagram: the model is null");
  const MultibodyModel& m = *model;
  // `model` is the plan's and the pose solver's: the Euler base (plant_base picks the plant's and the controller's).
  m.RequireNqEqualsNv("BuildWalkingDiagram");
  for (const char* foot : {"left_foot", "right_foot"}) {
    const ContactInfo& c = m.contacts()[m.ContactIndex(foot)];
    if (c.type != ContactType::kFlat)
      throw std::invalid_argument(std::string("BuildWalkingDiagram: robot '") + m.name() + "': contact '" + foot +
                                  "' is not a flat foot");
  }
  const SwingFootTrajectoryParams swing = RobotSwing(m, params);

  DiagramBuilder b;
  WalkingDiagram d;
  d.model = model;
  d.plan = plan;
  if (params.compensate_centroidal_momentum)
    d.compensation = CompensateCentroidalMomentum(m, d.plan, swing, params.compensation);
  HybridContactPlantParams plant_params = params.plant;
  if (plant_params.planned_liftoff_force_N <= 0.0)
    plant_params.planned_liftoff_force_N = 0.01 * m.total_mass() * 9.81;  // spec §7.5 [R]
  // The Bullet plant releases the trailing foot at the same force (a planned lift-off; see bullet_world_plant.h).
  BulletWorldPlantParams bullet_params = params.bullet_plant;
  if (bullet_params.planned_liftoff_force_N < 0)
    bullet_params.planned_liftoff_force_N = plant_params.planned_liftoff_force_N;
  if (bullet_params.min_time_in_mode_s <= 0) bullet_params.min_time_in_mode_s = plant_params.min_time_in_mode_s;
  // A foot that lands early is not released by that force before the controller loads it (no touchdown bounce).
  if (bullet_params.planned_liftoff_min_contact_s <= 0)
    bullet_params.planned_liftoff_min_contact_s = plant_params.min_time_in_mode_s;
  const ContactModeGraph modes = ContactModeGraph::WithDoubleSupport("left_foot", "right_foot");
  if (modes.ModeIndex("left_foot_stance", "plant") != kWalkingLeftStance ||
      modes.ModeIndex("double_support", "plant") != kWalkingDoubleSupport ||
      modes.ModeIndex("right_foot_stance", "plant") != kWalkingRightStance)
    throw std::logic_error("BuildWalkingDiagram: the plant's mode numbers differ from WalkingPlantMode");
  // Perturbations of the simulated world: the plant may be pushed and built from a scaled model; the plan and the
  // controller keep `model`.
  const PerturbationParams& perturb = params.perturbations;
  plant_params.external_force_input = bullet_params.external_force_input = perturb.push.has_value();
  std::shared_ptr<const MultibodyModel> base_model = model;
  if (params.plant_base == PlantBase::kQuaternion) {
    if (plant != PlantKind::kHybrid)
      throw std::invalid_argument(
          std::string("BuildWalkingDiagram: plant_base = quaternion needs the hybrid plant, not ") + ToString(plant));
    if (perturb.push.has_value())
      throw std::invalid_argument(
          "BuildWalkingDiagram: plant_base = quaternion does not take perturbations.push (its generalized force is in "
          "the Euler model's coordinates)");
    base_model = LoadQuaternionTwin(m);
  }
  auto scaled = [&](const std::shared_ptr<const MultibodyModel>& x) {
    return perturb.model_mismatch() ? std::make_shared<const MultibodyModel>(
                                          ScaleMassAndFriction(*x, perturb.mass_scale, perturb.friction_scale))
                                    : x;
  };
  const std::shared_ptr<const MultibodyModel> plant_model = scaled(base_model);
  d.plant_euler_model = base_model == model ? plant_model : scaled(model);
  d.plant =
      b.AddSystem(MakeContactPlant(plant, "plant", plant_model, modes, Terrain::Flat(), plant_params, bullet_params));
  if (params.plant_base == PlantBase::kQuaternion) {  // the Euler state for the run's monitors and logs
    d.euler_state =
        b.AddSystem(std::make_unique<QuaternionToEulerState>("euler_state", model, plant_model, params.euler_state));
    b.Connect("plant", "state", "euler_state", "quaternion_state");
  }
  WalkingControllerSpec spec;
  spec.model = base_model;  // the controller runs on the plant's base and reads the plant's state
  spec.mode_contacts = ActiveContactsPerMode(*d.plant);
  spec.tasks = WalkingControllerTasks(*base_model, params);
  spec.layout = WalkingDesiredLayout(spec.tasks);
  spec.params = params.controller;
  if (spec.params.contact.corner_wrench_cone && spec.params.contact.corner_cone_friction_coefficient < 0.0)
    spec.params.contact.corner_cone_friction_coefficient =
        std::min(m.contacts()[m.ContactIndex("left_foot")].friction_coefficient,
                 m.contacts()[m.ContactIndex("right_foot")].friction_coefficient);
  if (spec.params.force_band_loading_floor_N < 0.0)
    spec.params.force_band_loading_floor_N =
        2.0 * plant_params.planned_liftoff_force_N;  // above the plant's release force
  d.reference = b.AddSystem(std::make_unique<WalkingTrajectorySource>(
      "walking_reference", d.plan, params.force_band_lead_periods * spec.params.update_period_s));
  d.outputs = b.AddSystem(std::make_unique<WalkingOutputReference>("outputs", d.plan, swing));
  std::unique_ptr<System> block = controller ? controller(spec) : MakeWalkingClfQpController(spec);
  if (block == nullptr) throw std::invalid_argument("BuildWalkingDiagram: the controller factory returned no system");
  for (const char* port : {"state", "mode", "desired"})
    if (!block->HasInputPort(port))
      throw std::invalid_argument("BuildWalkingDiagram: controller '" + block->name() + "' has no input port '" + port +
                                  "' (the seam needs state, mode, desired)");
  if (!block->HasOutputPort("u"))
    throw std::invalid_argument("BuildWalkingDiagram: controller '" + block->name() + "' has no output port 'u'");
  const bool force_reference = block->HasInputPort("normal_force_reference");
  d.controller = b.AddSystem(std::move(block), spec.name);
  b.Connect("walking_reference", "com", "outputs", "com");
  b.Connect("outputs", "desired", spec.name, "desired");
  if (force_reference) b.Connect("walking_reference", "normal_force_reference", spec.name, "normal_force_reference");
  b.Connect("plant", "mode", spec.name, "mode");
  // plant.state → controller.state and controller.u → plant.u, through the perturbation blocks that are on.
  std::string state_sink;  // the sensor path's end: the controller, or the projection in front of it
  if (params.project_velocity_on_contacts && perturb.latency_samples > 0) {
    b.AddSystem(std::make_unique<ContactVelocityProjection>("contact_projection", base_model, spec.mode_contacts,
                                                            plant_params.dynamics));
    b.Connect("plant", "mode", "contact_projection", "mode");
    b.Connect("contact_projection", "state", spec.name, "state");
    state_sink = "contact_projection";
  }
  d.perturbation_blocks = AddPerturbationBlocks(b, perturb, base_model, "plant", spec.name, "", state_sink);
  d.diagram = b.Build("walking");
  for (int i = 0; i < d.diagram->num_leaves() && d.clf_qp == nullptr; ++i)
    d.clf_qp = dynamic_cast<const ClfQpController*>(&d.diagram->leaf(i));
  return d;
}

const Eigen::VectorXd& WalkingPlantEulerState(const WalkingDiagram& d, const Context& context) {
  if (d.euler_state) return d.euler_state->EvalOutput(d.diagram->GetSubsystemContext(*d.euler_state, context), "state");
  return d.plant->EvalOutput(d.diagram->GetSubsystemContext(*d.plant, context), "state");
}

void SetWalkingPlantState(const WalkingDiagram& d, Context& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                          const std::string& mode) {
  LeafContext& pc = d.diagram->GetMutableSubsystemContext(*d.plant, context);
  if (!d.euler_state) return d.plant->SetState(pc, q, v, mode);
  const int nv = static_cast<int>(v.size());
  Eigen::VectorXd x_q(2 * nv + 1);
  EulerStateToQuaternion((Eigen::VectorXd(2 * nv) << q, v).finished(), x_q);
  d.plant->SetState(pc, x_q.head(nv + 1), x_q.tail(nv), mode);
}

SimulatorConfig WalkingSimulatorConfig() { return ExplicitRestartingSimulatorConfig(1e-5, 1e-7); }

Eigen::VectorXd WalkingInitialVelocity(const MultibodyModel& model, const Eigen::VectorXd& q, const WalkingPlan& plan,
                                       double t) {
  const WalkingReference r = plan.Sample(t);
  const int nv = model.nv();
  MultibodyWorkspace ws(model);
  Eigen::MatrixXd J(15, nv), Jc(3, nv), Jf(6, nv);
  CalcComJacobian(model, ws, q, Jc);
  J.topRows(3) = Jc;
  const int feet[2] = {model.BodyIndex("left_foot"), model.BodyIndex("right_foot")};
  for (int f = 0; f < 2; ++f) {
    CalcFrameJacobian(model, ws, q, feet[f], Eigen::Vector3d::Zero(), Jf);
    J.middleRows(3 + 6 * f, 6) = Jf;
  }
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(15);
  rhs.head<3>() = r.com_velocity;
  std::vector<int> free;
  const int yaw = model.VelocityIndex("base_yaw"), pitch = model.VelocityIndex("base_pitch"),
            roll = model.VelocityIndex("base_roll");
  for (int i = 0; i < nv; ++i)
    if (i != yaw && i != pitch && i != roll) free.push_back(i);
  Eigen::MatrixXd Jr(15, free.size());
  for (size_t k = 0; k < free.size(); ++k) Jr.col(k) = J.col(free[k]);
  const Eigen::VectorXd x = Jr.fullPivLu().solve(rhs);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(nv);
  for (size_t k = 0; k < free.size(); ++k) v[free[k]] = x[k];
  return v;
}

Eigen::VectorXd WalkingStandingPose(const MultibodyModel& model, const WalkingPlan& plan, double t) {
  const WalkingReference r = plan.Sample(t);
  const double ankle = -model.contacts()[model.ContactIndex("left_foot")].points.front().z();
  return SolveWalkingPose(model, r.com_position, Eigen::Vector3d(r.left_foothold.x(), r.left_foothold.y(), ankle),
                          Eigen::Vector3d(r.right_foothold.x(), r.right_foothold.y(), ankle), model.q_nominal());
}

}  // namespace rome
