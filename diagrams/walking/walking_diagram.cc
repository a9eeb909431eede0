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
  p.contact.friction_margin = 0.5;  // ours: room for the force drift over a held sample as a foot unloads
  // Ours (spec [R]: 0.02 m). Measured on gait A: the swing leg's yaw momentum and the horizontal force of the
  // momentum compensation ask the stance sole for |M_z| up to ~0.08 F_z (41 N m at F_z = 514 N just after lift-off);
  // with 0.02, 0.04 or 0.05 m the pelvis yaws and the run fails within 3 steps, 0.057 m fails at step 9, 0.07-0.1 m
  // walk. A rigid 0.25 x 0.10 m sole under uniform pressure transmits at most mu * 0.068 m = 0.054 m F_z (mu = 0.8):
  // the hybrid plant's rigid flat foot has no torsional slip, so this exceeds what a real sole could hold.
  p.contact.yaw_moment_coefficient_m = 0.1;
  p.contact.cop_margin_m = 0.01;  // ours: the plant's CoP drifts by ~1 mm over a held sample when the QP holds it on the edge, more near lift-off (5 mm: 1 mm outside at F_z = 21 N in an -O1 build)
  p.resolve_at_events = true;
  // Ours (default 1e-6): the torque penalty is relative to the largest output curvature, the swing foot's rotation
  // (a 1.3 kg foot); DenseQpSolver needs pivots above 1e-8 of H's largest diagonal, so 1e-8 is the least it accepts
  // (below: kNonConvex, held torques). Measured on the stand-to-walk run: 1e-8-1e-7 walk, 1e-6 pulls the stance knee
  // torque down so far that the COM sinks 6 cm in the first step and the run fails.
  p.u_regularization = 3e-8;
  // Ours (spec §5.5 [C22]: the cost's target is μ = 0, the minimum-norm input). With that cost the CLF row is the only
  // feedback, so it binds at every update and the torque is the pointwise min-norm CLF controller: where the active
  // CoP/yaw/friction rows leave the row's L_G V almost no direction to act in, δ reaches 1.8 (median 4e-5) and
  // torques swing by up to 190 N m from one tick to the next. Measured on (0.23 m, 0.38 s, 0.12 s, 0.26 m) from
  // standing, NLP seed 1: a touchdown 7.3 cm off its foothold. With the cost's target at the PD law
  // ÿ_d − Kp e − Kd ė (TaskGains: 100 /s², 20 /s, critically damped at 1/ε = 10 rad/s) the feedback is in the cost
  // and the row only bounds V̇: there δ stays ≤ 0.019 and that gait walks (COM RMS x 2.7 mm), gait A's COM RMS x goes
  // from 5.2 to 3.2 mm, and every gait of the README's sweeps that has a plan walks.
  p.cost_pd_feedback = true;
  p.force_band_loading_floor_N = -1.0;  // set by the builder: 2 x the plant's planned lift-off force (2 % of m g, ours)
  return p;
}

namespace {
// "WHO: FIELD = VALUE UNIT is outside RANGE" when !ok.
void Require(bool ok, const std::string& who, const char* field, double value, const char* unit, const std::string& range) {
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
  Require(In(swing.touchdown_velocity_mps, 0.05, 0.5), who, "swing.touchdown_velocity_mps", swing.touchdown_velocity_mps, "m/s", Interval(0.05, 0.5, "m/s"));
  Require(swing.apex_height_m > 0 && swing.apex_height_m <= 0.3, who, "swing.apex_height_m", swing.apex_height_m, "m", Interval(0, 0.3, "m", '('));
  Require(swing_foot_weight > 0 && std::isfinite(swing_foot_weight), who, "swing_foot_weight", swing_foot_weight, "", "(0, inf)");
  Require(swing_foot_orientation_weight > 0 && std::isfinite(swing_foot_orientation_weight), who, "swing_foot_orientation_weight",
          swing_foot_orientation_weight, "", "(0, inf)");
}

void WalkingGait::Validate(const std::string& who) const {
  const double v[4] = {step_length_m, ssp_duration_s, dsp_duration_s, step_width_m};
  const char* names[4] = {"step_length_m", "ssp_duration_s", "dsp_duration_s", "step_width_m"};
  const char* units[4] = {"m", "s", "s", "m"};
  for (int i = 0; i < 4; ++i) Require(In(v[i], kMin[i], kMax[i]), who, names[i], v[i], units[i], Interval(kMin[i], kMax[i], units[i]));
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
    Require(In(start[i], kSideGaitMin[i], kSideGaitMax[i]), who, start_names[i], start[i], units[i], Interval(kSideGaitMin[i], kSideGaitMax[i], units[i]));
    Require(In(lead[i], kSideGaitMin[i], kSideGaitMax[i]), who, lead_names[i], lead[i], units[i], Interval(kSideGaitMin[i], kSideGaitMax[i], units[i]));
  }
  Require(sagittal_cop_margin_m >= 0 && sagittal_cop_margin_m < 0.07, who, "sagittal_cop_margin_m", sagittal_cop_margin_m, "m", Interval(0, 0.07, "m", '[', ')'));
  Require(transition_min_ssp_duration_s == 0 || In(transition_min_ssp_duration_s, 0.3, 1.0), who, "transition_min_ssp_duration_s",
          transition_min_ssp_duration_s, "s", "0 or [0.3, 1] s");
  Require(In(height_min_m, 0.7, 1.0), who, "height_min_m", height_min_m, "m", Interval(0.7, 1.0, "m"));
  Require(In(height_max_m, 0.7, 1.0) && height_max_m > height_min_m, who, "height_max_m", height_max_m, "m",
          "(height_min_m, 1] m = " + Interval(height_min_m, 1.0, "m", '('));
  Require(standing_height_m >= height_min_m && standing_height_m <= height_max_m, who, "standing_height_m", standing_height_m, "m",
          "[height_min_m, height_max_m] = " + Interval(height_min_m, height_max_m, "m"));
  Require(gait_change_max_force_fraction == 0 || (gait_change_max_force_fraction > 1 && gait_change_max_force_fraction <= 3), who,
          "gait_change_max_force_fraction", gait_change_max_force_fraction, "m g", "0 (no bound) or (1, 3] m g");
  Require(periodic_max_force_fraction == 0 || (periodic_max_force_fraction > 1 && periodic_max_force_fraction <= 3), who,
          "periodic_max_force_fraction", periodic_max_force_fraction, "m g", "0 (never) or (1, 3] m g");
  Require(chain_steps >= 1 && chain_steps <= 20, who, "chain_steps", chain_steps, "", "[1, 20]");
  Require(reload_floor_fraction >= 0 && reload_floor_fraction < 0.5, who, "reload_floor_fraction", reload_floor_fraction, "m g", "[0, 0.5)");
  gait_graph.Validate();
  Require(min_dsp_stance_force_fraction >= 0 && min_dsp_stance_force_fraction < 1, who, "min_dsp_stance_force_fraction",
          min_dsp_stance_force_fraction, "", Interval(0, 1, "", '[', ')'));
  const double lateral = lateral_cop_margin_m, sag = sagittal_cop_margin_m, standing = standing_sagittal_cop_margin_m;
  if (!(sole.heel_m - sag > 0 && sole.toe_m - sag > 0))
    throw std::invalid_argument(who + ": sagittal_cop_margin_m = " + std::to_string(sag) + " m leaves no sole (heel " + std::to_string(sole.heel_m) +
                                " m, toe " + std::to_string(sole.toe_m) + " m)");
  if (!(lateral >= 0) || !(sole.left_m - lateral > 0 && sole.right_m - lateral > 0))
    throw std::invalid_argument(who + ": lateral_cop_margin_m = " + std::to_string(lateral) + " must be >= 0 and leave a sole");
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

std::function<void(const WalkingPlan&)> WalkingPoseCheck(std::shared_ptr<const MultibodyModel> model, const WalkingDiagramParams& params) {
  if (model == nullptr) throw std::invalid_argument("WalkingPoseCheck: the model is null");
  if (!params.compensate_centroidal_momentum) return {};
  const SwingFootTrajectoryParams swing = RobotSwing(*model, params);
  const CentroidalMomentumCompensationParams compensation = params.compensation;
  return [model, swing, compensation](const WalkingPlan& plan) {
    WalkingPlan copy = plan;
    CompensateCentroidalMomentum(*model, copy, swing, compensation);
  };
}

WalkingPlanTorqueReport CheckWalkingPlanTorques(const MultibodyModel& model, const WalkingPlan& plan, const WalkingDiagramParams& params,
                                                double end_time_s) {
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
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_roll", m, "base_roll", pelvis_gains)),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_pitch", m, "base_pitch", pelvis_gains)),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_yaw", m, "base_yaw", pelvis_gains)),
      // Eq. (17): swing foot position and orientation, in the other foot's stance only.
      ClfOutput::RelativeDegreeTwo(std::make_shared<PointPositionTask>("left_ankle", m, "left_foot", Eigen::Vector3d::Zero(), xyz, foot_gains,
                                                                       std::vector<int>{right_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<BodyOrientationTask>("left_foot_orientation", m, "left_foot", foot_orientation_gains, std::vector<int>{right_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<PointPositionTask>("right_ankle", m, "right_foot", Eigen::Vector3d::Zero(), xyz, foot_gains,
                                                                       std::vector<int>{left_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<BodyOrientationTask>("right_foot_orientation", m, "right_foot", foot_orientation_gains, std::vector<int>{left_stance})),
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

WalkingDiagram BuildWalkingDiagram(std::shared_ptr<const MultibodyModel> model, const WalkingPlan& plan, const WalkingDiagramParams& params,
                                   PlantKind plant, const WalkingControllerFactory& controller) {
  params.Validate();
  if (model == nullptr) throw std::invalid_argument("BuildWalkingDiagram: the model is null");
  const MultibodyModel& m = *model;
  for (const char* foot : {"left_foot", "right_foot"}) {
    const ContactInfo& c = m.contacts()[m.ContactIndex(foot)];
    if (c.type != ContactType::kFlat)
      throw std::invalid_argument(std::string("BuildWalkingDiagram: robot '") + m.name() + "': contact '" + foot + "' is not a flat foot");
  }
  const SwingFootTrajectoryParams swing = RobotSwing(m, params);

  DiagramBuilder b;
  WalkingDiagram d;
  d.model = model;
  d.plan = plan;
  if (params.compensate_centroidal_momentum) d.compensation = CompensateCentroidalMomentum(m, d.plan, swing, params.compensation);
  HybridContactPlantParams plant_params = params.plant;
  if (plant_params.planned_liftoff_force_N <= 0.0) plant_params.planned_liftoff_force_N = 0.01 * m.total_mass() * 9.81;  // spec §7.5 [R]
  // The Bullet plant releases the trailing foot at the same force (a planned lift-off; see bullet_world_plant.h).
  BulletWorldPlantParams bullet_params = params.bullet_plant;
  if (bullet_params.planned_liftoff_force_N < 0) bullet_params.planned_liftoff_force_N = plant_params.planned_liftoff_force_N;
  if (bullet_params.min_time_in_mode_s <= 0) bullet_params.min_time_in_mode_s = plant_params.min_time_in_mode_s;
  const ContactModeGraph modes = ContactModeGraph::WithDoubleSupport("left_foot", "right_foot");
  if (modes.ModeIndex("left_foot_stance", "plant") != kWalkingLeftStance || modes.ModeIndex("double_support", "plant") != kWalkingDoubleSupport ||
      modes.ModeIndex("right_foot_stance", "plant") != kWalkingRightStance)
    throw std::logic_error("BuildWalkingDiagram: the plant's mode numbers differ from WalkingPlantMode");
  d.plant = b.AddSystem(MakeContactPlant(plant, "plant", model, modes, Terrain::Flat(),
                                         plant_params, bullet_params));
  WalkingControllerSpec spec;
  spec.model = model;
  spec.mode_contacts = ActiveContactsPerMode(*d.plant);
  spec.tasks = WalkingControllerTasks(m, params);
  spec.layout = WalkingDesiredLayout(spec.tasks);
  spec.params = params.controller;
  spec.params.contact_stabilization = plant_params.dynamics;
  if (spec.params.force_band_loading_floor_N < 0.0) spec.params.force_band_loading_floor_N = 2.0 * plant_params.planned_liftoff_force_N;  // above the plant's release force
  d.reference = b.AddSystem(std::make_unique<WalkingTrajectorySource>("walking_reference", d.plan));
  d.outputs = b.AddSystem(std::make_unique<WalkingOutputReference>("outputs", d.plan, swing));
  std::unique_ptr<System> block = controller ? controller(spec) : MakeWalkingClfQpController(spec);
  if (block == nullptr) throw std::invalid_argument("BuildWalkingDiagram: the controller factory returned no system");
  for (const char* port : {"state", "mode", "desired"})
    if (!block->HasInputPort(port))
      throw std::invalid_argument("BuildWalkingDiagram: controller '" + block->name() + "' has no input port '" + port + "' (the seam needs state, mode, desired)");
  if (!block->HasOutputPort("u")) throw std::invalid_argument("BuildWalkingDiagram: controller '" + block->name() + "' has no output port 'u'");
  const bool force_reference = block->HasInputPort("normal_force_reference");
  d.controller = b.AddSystem(std::move(block), spec.name);
  b.Connect("walking_reference", "com", "outputs", "com");
  b.Connect("outputs", "desired", spec.name, "desired");
  if (force_reference) b.Connect("walking_reference", "normal_force_reference", spec.name, "normal_force_reference");
  b.Connect("plant", "state", spec.name, "state");
  b.Connect("plant", "mode", spec.name, "mode");
  b.Connect(spec.name, "u", "plant", "u");
  d.diagram = b.Build("walking");
  for (int i = 0; i < d.diagram->num_leaves() && d.clf_qp == nullptr; ++i) d.clf_qp = dynamic_cast<const ClfQpController*>(&d.diagram->leaf(i));
  return d;
}

SimulatorConfig WalkingSimulatorConfig() {
  return ExplicitRestartingSimulatorConfig(1e-5, 1e-7);
}

SoleGeometry SoleOf(const MultibodyModel& model, const std::string& contact) {
  const ContactInfo& c = model.contacts()[model.ContactIndex(contact)];
  if (c.type != ContactType::kFlat || c.points.empty())
    throw std::invalid_argument("SoleOf: robot '" + model.name() + "': contact '" + contact + "' is not a flat foot");
  SoleGeometry s;
  s.heel_m = s.toe_m = s.left_m = s.right_m = -std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& p : c.points) {
    s.toe_m = std::max(s.toe_m, p.x());
    s.heel_m = std::max(s.heel_m, -p.x());
    s.left_m = std::max(s.left_m, p.y());
    s.right_m = std::max(s.right_m, -p.y());
  }
  if (!(s.heel_m > 0 && s.toe_m > 0 && s.left_m > 0 && s.right_m > 0))
    throw std::invalid_argument("SoleOf: robot '" + model.name() + "': contact '" + contact + "': the ankle is not over the sole");
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;
double SecondsSince(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

AslipPeriodicGaitParams GaitParams(const WalkingGait& g, const StandToWalkParams& sp) {
  AslipPeriodicGaitParams gp;
  gp.step_length = g.step_length_m;
  gp.ssp_duration = g.ssp_duration_s;
  gp.dsp_duration = g.dsp_duration_s;
  gp.height_min = sp.height_min_m;
  gp.height_max = sp.height_max_m;
  return gp;
}

struct SolvedGait {
  AslipPeriodicGaitPlanner planner;
  AslipPeriodicGait gait;
  double solve_s = 0;
};

SolvedGait SolveGait(const WalkingGait& g, std::uint32_t seed, const PlanCache* cache, const StandToWalkParams& sp, const std::string& who,
                     const std::string& which) {
  if (!(sp.periodic_max_force_fraction == 0 || (sp.periodic_max_force_fraction > 1 && std::isfinite(sp.periodic_max_force_fraction))))
    throw std::invalid_argument(who + ": periodic_max_force_fraction must be 0 (no bound) or > 1, got " +
                                std::to_string(sp.periodic_max_force_fraction));
  SolvedGait r{AslipPeriodicGaitPlanner(GaitParams(g, sp)), {}, 0.0};
  const auto t0 = Clock::now();
  r.gait = r.planner.Solve(seed, cache);
  r.solve_s = SecondsSince(t0);
  if (!r.gait.success()) throw std::runtime_error(who + ": the periodic aSLIP NLP of " + which + " failed: " + r.gait.collocation.nlp.message);
  if (sp.periodic_max_force_fraction > 0) {  // re-plan a gait that asks more than the bound (see the parameter)
    const AslipPeriodicGaitParams& gp = r.planner.params();
    double peak = 0;
    for (int ph = 0; ph < 2; ++ph) {
      const Eigen::MatrixXd G = r.gait.GroundReactions(gp.aslip, gp.step_length, ph);
      peak = std::max({peak, G.row(1).maxCoeff(), G.row(3).maxCoeff()});
    }
    if (peak > sp.periodic_max_force_fraction * gp.aslip.mass * gp.aslip.gravity) {
      AslipPeriodicGaitParams bounded = gp;
      bounded.max_vertical_force_fraction = sp.periodic_max_force_fraction;
      SolvedGait b{AslipPeriodicGaitPlanner(bounded), {}, 0.0};
      b.gait = b.planner.Solve(seed, cache);
      b.solve_s = r.solve_s + SecondsSince(t0);
      if (!b.gait.success())
        throw std::runtime_error(who + ": the periodic aSLIP NLP of " + which + " asks " + std::to_string(peak / (gp.aslip.mass * gp.aslip.gravity)) +
                                 " m g per leg, and with periodic_max_force_fraction = " + std::to_string(sp.periodic_max_force_fraction) +
                                 " it failed: " + b.gait.collocation.nlp.message);
      return b;
    }
  }
  return r;
}

// The footed-aSLIP transition NLP onto `target` (Eq. (9)-(10) on the robot's sole, less the ROM margins).
AslipTransitionParams TransitionParams(const AslipPeriodicGaitParams& target_params, const WalkingGait& target, const StandToWalkParams& sp) {
  AslipTransitionParams tp;
  tp.bounds = target_params;
  tp.bounds.aslip.heel_length = sp.sole.heel_m - sp.sagittal_cop_margin_m;
  tp.bounds.aslip.toe_length = sp.sole.toe_m - sp.sagittal_cop_margin_m;
  tp.min_ssp_duration = std::max({tp.min_ssp_duration, target.ssp_duration_s, sp.transition_min_ssp_duration_s});
  tp.max_ssp_duration = std::max(tp.max_ssp_duration, tp.min_ssp_duration);
  if (sp.point_foot_transition_ssp) tp.max_ssp_ankle_torque = 0.0;
  tp.min_dsp_stance_force_fraction = sp.min_dsp_stance_force_fraction;
  tp.lateral = sp.lateral_in_transition_nlp;
  tp.foot_width_left_of_ankle = sp.sole.left_m - sp.lateral_cop_margin_m;
  tp.foot_width_right_of_ankle = sp.sole.right_m - sp.lateral_cop_margin_m;
  return tp;
}

// Solves the transition NLP for `data` (legs and pivots in the frame whose origin is world x = x_offset), then the
// footed H-LIP QP on its nodes (Eq. (11)-(15)), and appends both to `plan`; the lifting foot lands at world landing_x.
// landing_y: the lifting foot's world y at touchdown (NaN: where it lifted).
void AppendSolvedTransition(WalkingPlan& plan, const AslipTransitionPlanner& planner, const AslipTransitionData& data, double x_offset,
                            double step_width, double landing_x, const StandToWalkParams& sp, const PlanCache* cache, const std::string& who,
                            WalkingNlpReport* report, WalkingTransitionNodes* nodes,
                            double landing_y = std::numeric_limits<double>::quiet_NaN(), double reload_floor_N = 0.0) {
  const auto t0 = Clock::now();
  const AslipTransition transition = planner.Solve(data, cache);
  if (report != nullptr) *report = {SecondsSince(t0), transition.collocation.nlp.iterations, transition.max_constraint_violation};
  if (!transition.success()) throw std::runtime_error(who + ": the transition footed-aSLIP NLP failed: " + transition.collocation.nlp.message);
  const AslipParams& aslip = planner.params().bounds.aslip;
  if (const double t = transition.LiftingLegReloadTime(aslip, data, reload_floor_N); reload_floor_N > 0 && !std::isnan(t))
    throw std::runtime_error(who + ": the transition's plan unloads the lifting foot and loads it again " + std::to_string(t) + " s into its double support");
  FootedHlipTransitionData lat = LateralDataOnTransitionNodes(transition, aslip, data, planner.params().bounds.nodes_per_domain, step_width);
  lat.stance_left = data.lifting_leg == 1;
  lat.left_foot_y = data.left_foot_y;
  lat.right_foot_y = data.right_foot_y;
  lat.initial_state = data.initial_lateral_state;
  lat.final_state = data.final_lateral_state;
  FootedHlipTransitionParams lp;
  lp.mass = aslip.mass;
  lp.foot_width_left_of_ankle = sp.sole.left_m - sp.lateral_cop_margin_m;  // Eq. (14) on the robot's sole
  lp.foot_width_right_of_ankle = sp.sole.right_m - sp.lateral_cop_margin_m;
  lp.normal_force_pivots = sp.lateral_normal_force_pivots;
  const FootedHlipTransitionPlan lateral = FootedHlipTransitionPlanner(lp).Solve(lat);
  if (!lateral.success()) throw std::runtime_error(who + ": the footed H-LIP transition QP failed: " + lateral.message);
  if (nodes != nullptr) {
    const int n = static_cast<int>(lat.node_times.size()), N = planner.params().bounds.nodes_per_domain;
    WalkingTransitionNodes& r = *nodes;
    r = WalkingTransitionNodes{};
    r.t = lat.node_times.array() + plan.end_time();
    r.x.resize(n), r.z.resize(n), r.y = lateral.states.row(0).transpose(), r.ydot = lateral.states.row(1).transpose();
    r.normal_force.resize(2, n), r.pitch_torque.resize(2, n), r.roll_torque.resize(2, n);
    r.roll_torque.row(0) = lateral.left_torque.transpose(), r.roll_torque.row(1) = lateral.right_torque.transpose();
    for (int ph = 0; ph < 2; ++ph) {
      const CollocationPhaseSolution& s = transition.collocation.phases[ph];
      const Eigen::MatrixXd G = transition.GroundReactions(aslip, data, ph);
      for (int k = ph; k < N; ++k) {
        const int j = ph * (N - 1) + k;
        r.x(j) = x_offset + s.states(0, k), r.z(j) = s.states(1, k);
        r.normal_force(0, j) = G(1, k), r.normal_force(1, j) = G(3, k);
        r.pitch_torque(0, j) = s.inputs(2, k), r.pitch_torque(1, j) = s.inputs(3, k);
      }
    }
    for (int j = 0; j < n; ++j) r.single_support.push_back(j >= N);
    r.heel_m = aslip.heel_length, r.toe_m = aslip.toe_length;
    r.left_m = lp.foot_width_left_of_ankle, r.right_m = lp.foot_width_right_of_ankle;
  }
  plan.AppendTransition(planner, transition, data, x_offset, lat, lateral, aslip.mass, landing_x, landing_y);
}

// Swaps the two legs' rest lengths and rates of an aSLIP state [x, z, ẋ, ż, L_0, L_1, L̇_0, L̇_1].
Eigen::Matrix<double, 8, 1> SwapLegs(Eigen::Matrix<double, 8, 1> s) {
  std::swap(s[4], s[5]);
  std::swap(s[6], s[7]);
  return s;
}

bool SameTiming(const WalkingGait& a, const WalkingGait& b) {
  return std::abs(a.step_length_m - b.step_length_m) <= 1e-9 && std::abs(a.ssp_duration_s - b.ssp_duration_s) <= 1e-9 &&
         std::abs(a.dsp_duration_s - b.dsp_duration_s) <= 1e-9;
}

// `sp` with the standing transition's sagittal CoP margin in place of sagittal_cop_margin_m (when it is set).
StandToWalkParams WithStandingMargin(const StandToWalkParams& sp) {
  StandToWalkParams p = sp;
  if (sp.standing_sagittal_cop_margin_m >= 0) p.sagittal_cop_margin_m = sp.standing_sagittal_cop_margin_m;
  return p;
}

// Stand → the solved gait `a` (timing of `g`; the right foot lifts first) and `steps` periodic steps of it; with
// end_in_single_support the last step stops at its touchdown (its DSP left to a following transition).
WalkingPlan StandingInto(const SolvedGait& a, const WalkingGait& g, int steps, const PlanCache* cache, WalkingPlanReport* report,
                         const StandToWalkParams& sp, const std::string& who, bool end_in_single_support, const char* into = "gait") {
  const AslipPeriodicGaitParams& gp = a.planner.params();
  const StandToWalkParams standing = WithStandingMargin(sp);
  const AslipTransitionPlanner transition_planner(TransitionParams(gp, g, standing));
  AslipTransitionData data;
  data.left_foot_x = 0.0;
  data.right_foot_x = -sp.stance_stagger_m;
  data.initial_state = AslipTransitionPlanner::StandingState(gp.aslip, sp.standing_height_m, data.left_foot_x, data.right_foot_x);
  data.final_state = a.gait.collocation.phases[0].states.col(gp.nodes_per_domain - 1);
  const HybridLinearInvertedPendulum hlip({.z0 = a.gait.mean_height, .ssp_duration = g.ssp_duration_s, .dsp_duration = g.dsp_duration_s});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(g.step_width_m);  // end of a left stance, about the left foot
  data.left_foot_y = g.step_width_m / 2;
  data.right_foot_y = -g.step_width_m / 2;
  data.initial_lateral_state = Eigen::Vector2d(0.0, 0.0);
  data.final_lateral_state = Eigen::Vector2d(data.left_foot_y + pre(0), pre(1));
  data.lifting_leg = 1;
  WalkingPlan plan;
  WalkingNlpReport transition_report;
  AppendSolvedTransition(plan, transition_planner, data, 0.0, g.step_width_m, gp.step_length, standing, cache, who + " (standing -> " + into + ")", &transition_report,
                         report != nullptr ? &report->transition_nodes : nullptr);
  // The transition lands the right foot one step ahead: the first periodic step contributes its DSP only, so `steps`
  // single supports of the gait follow.
  plan.AppendPeriodicSteps(a.planner, a.gait, steps + 1, WalkingDomain::kLeftStance, 0.0, g.step_width_m, /*begin_with_double_support=*/true,
                           end_in_single_support);
  if (report != nullptr) report->transition = transition_report;
  return plan;
}

// `plan` ends at a touchdown of the solved gait `ga` (timing `a`): the transition footed-aSLIP NLP from its post-impact
// state to `gb`'s pre-impact state (the foot behind lifts) with its footed H-LIP QP, then `steps_b` steps of b.
void AppendGaitChange(WalkingPlan& plan, const SolvedGait& ga, const WalkingGait& a, const SolvedGait& gb, const WalkingGait& b, int steps_b,
                      bool end_in_single_support, const PlanCache* cache, const StandToWalkParams& sp, const std::string& who,
                      WalkingNlpReport* transition_report, WalkingTransitionNodes* nodes) {
  const AslipPeriodicGaitParams& pa = ga.planner.params();
  const AslipPeriodicGaitParams& pb = gb.planner.params();
  // The plan ends at a touchdown of gait A: the foot that just landed is the transition's stance foot, the one behind
  // lifts. The transition's frame has its origin at the landed foot.
  const WalkingPlanSegment& last = plan.segments().back();
  const bool old_stance_left = last.domain == WalkingDomain::kLeftStance;
  const Eigen::Vector2d landed = old_stance_left ? last.right_foothold : last.left_foothold;
  const Eigen::Vector2d behind = old_stance_left ? last.left_foothold : last.right_foothold;
  const double x_offset = landed.x();
  AslipTransitionData data;
  (old_stance_left ? data.left_foot_x : data.right_foot_x) = behind.x() - x_offset;
  (old_stance_left ? data.right_foot_x : data.left_foot_x) = 0.0;
  data.left_foot_y = old_stance_left ? behind.y() : landed.y();
  data.right_foot_y = old_stance_left ? landed.y() : behind.y();
  data.lifting_leg = old_stance_left ? 0 : 1;
  // Gait A's post-impact state (start of its DSP; plan leg 0 = the old stance) in the new frame, world legs.
  Eigen::Matrix<double, 8, 1> start = ga.gait.collocation.phases[1].states.col(0);
  start[0] -= pa.step_length;
  data.initial_state = old_stance_left ? start : SwapLegs(start);
  // Gait B's pre-impact state (end of its SSP; plan leg 0 = the stance, here the landed foot), world legs.
  const Eigen::Matrix<double, 8, 1> end = gb.gait.collocation.phases[0].states.col(pb.nodes_per_domain - 1);
  data.final_state = old_stance_left ? SwapLegs(end) : end;
  const WalkingReference at_touchdown = plan.Sample(plan.end_time());
  data.initial_lateral_state = Eigen::Vector2d(at_touchdown.com_position.y(), at_touchdown.com_velocity.y());
  const HybridLinearInvertedPendulum hlip({.z0 = gb.gait.mean_height, .ssp_duration = b.ssp_duration_s, .dsp_duration = b.dsp_duration_s});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(b.step_width_m);  // end of a left stance, about the left foot
  data.final_lateral_state = old_stance_left ? Eigen::Vector2d(landed.y() - pre(0), -pre(1)) : Eigen::Vector2d(landed.y() + pre(0), pre(1));
  // Initial guess: gait A's DSP and gait B's SSP in the new frame, world legs.
  data.dsp_state_guess = ga.gait.collocation.phases[1].states.topRows(8);
  data.dsp_state_guess.row(0).array() -= pa.step_length;
  data.ssp_state_guess = gb.gait.collocation.phases[0].states.topRows(8);
  for (Eigen::Index k = 0; k < data.dsp_state_guess.cols(); ++k)
    if (!old_stance_left) data.dsp_state_guess.col(k) = SwapLegs(data.dsp_state_guess.col(k));
  for (Eigen::Index k = 0; k < data.ssp_state_guess.cols(); ++k)
    if (old_stance_left) data.ssp_state_guess.col(k) = SwapLegs(data.ssp_state_guess.col(k));
  data.dsp_duration_guess = a.dsp_duration_s;
  data.ssp_duration_guess = b.ssp_duration_s;
  // The A → B transition's SSP may use the stance ankle (Eq. (10)): measured, with a point-foot SSP (as the standing
  // transition's) Ipopt ends at a point of local infeasibility (violation 9e-3) for gaits A and B.
  StandToWalkParams spb = sp;
  spb.point_foot_transition_ssp = false;
  AslipTransitionParams tp = TransitionParams(pb, b, spb);
  // The DSP starts at A's touchdown, where the landed (stance) leg carries nothing (s = 0): no load floor on it.
  tp.min_dsp_stance_force_fraction = 0.0;
  tp.max_vertical_force_fraction = sp.gait_change_max_force_fraction;
  // The transition's DSP may be as short as the gaits' own (the spec's [R] 0.1 s lower bound is above T_DSP = 0.08 s):
  // measured, (0.20 m, 0.35 s, 0.08 s, 0.20 m) -> 0.25 m steps is locally infeasible with 0.1 s and walks with 0.08 s.
  tp.min_dsp_duration = std::min({tp.min_dsp_duration, a.dsp_duration_s, b.dsp_duration_s});
  const AslipTransitionPlanner transition_planner(tp);
  if (transition_planner.params().lateral) {  // lateral rows [y, ẏ]: straight from the initial to the final lateral state
    const Eigen::Vector2d y0 = data.initial_lateral_state, y1 = data.final_lateral_state, mid = 0.5 * (y0 + y1);
    for (Eigen::MatrixXd* g : {&data.dsp_state_guess, &data.ssp_state_guess}) {
      const Eigen::Vector2d from = g == &data.dsp_state_guess ? y0 : mid, to = g == &data.dsp_state_guess ? mid : y1;
      g->conservativeResize(10, Eigen::NoChange);
      for (Eigen::Index k = 0; k < g->cols(); ++k) g->col(k).tail<2>() = from + (to - from) * (double(k) / double(g->cols() - 1));
    }
  }
  // The lateral footed H-LIP transition to B's step width: the landed foot stays, the lifting foot lands W_B to its
  // side (the final lateral state above is B's P2 pre-impact state about the landed foot), and B walks about the
  // walking line between them (it moves by (W_A - W_B) / 2 when W changes).
  const double landing_y = old_stance_left ? landed.y() + b.step_width_m : landed.y() - b.step_width_m;
  AppendSolvedTransition(plan, transition_planner, data, x_offset, b.step_width_m, x_offset + pb.step_length, sp, cache, who, transition_report, nodes,
                         landing_y, sp.reload_floor_fraction * pb.aslip.mass * pb.aslip.gravity);
  // As after the standing transition: B's first step is the transition's single support (on the foot A landed last,
  // at x_offset), so it contributes its DSP only.
  plan.AppendPeriodicSteps(gb.planner, gb.gait, steps_b + 1, old_stance_left ? WalkingDomain::kRightStance : WalkingDomain::kLeftStance, x_offset,
                           b.step_width_m, /*begin_with_double_support=*/true, end_in_single_support, 0.5 * (landed.y() + landing_y));
}

// Stand → gait `g` (the right foot lifts first) and `steps` periodic steps of g; with end_in_single_support the last
// step stops at its touchdown (its DSP left to a following transition). With StandToWalkParams::start_gait_steps, the
// standing transition goes into the start gait, which walks those steps and changes into g.
WalkingPlan ChainGaitChange(WalkingPlan plan, const SolvedGait& ga, const WalkingGait& a, const SolvedGait& gb, const WalkingGait& b, int steps_b,
                            bool end_in_single_support, std::uint32_t seed, const PlanCache* cache, const StandToWalkParams& sp,
                            const std::string& who, const std::string& direct_error, WalkingNlpReport* last_transition,
                            WalkingTransitionNodes* nodes, WalkingPlanReport* report, std::vector<WalkingGait>* walked);

// With `chain`, a start gait → g change with no direct plan goes through the gait graph (report->start_chain).
WalkingPlan StandToWalk(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache, WalkingPlanReport* report,
                        const StandToWalkParams& sp, const std::string& who, bool end_in_single_support, SolvedGait* gait_out,
                        bool chain = false) {
  sp.Validate(who);
  if (steps < 1) throw std::invalid_argument(who + ": steps must be >= 1, got " + std::to_string(steps));
  SolvedGait a = SolveGait(g, seed, cache, sp, who, "the gait");
  const WalkingGait start{sp.start_gait_step_length_m, sp.start_gait_ssp_duration_s, sp.start_gait_dsp_duration_s, g.step_width_m};
  WalkingPlan plan;
  if (sp.start_gait_steps > 0 && !SameTiming(g, start)) {
    const SolvedGait s = SolveGait(start, seed, cache, sp, who, "the start gait");
    plan = StandingInto(s, start, sp.start_gait_steps, cache, report, sp, who, /*end_in_single_support=*/true, "start gait");
    WalkingNlpReport change;
    const StandToWalkParams from_start = WithStandingMargin(sp);  // the start gait's change keeps the standing margin
    WalkingTransitionNodes* nodes = report != nullptr ? &report->start_change_nodes : nullptr;
    if (report != nullptr) report->start_chain = {start, g};
    try {
      WalkingPlan direct = plan;
      AppendGaitChange(direct, s, start, a, g, steps, end_in_single_support, cache, from_start, who + " (start gait -> gait)", &change, nodes);
      plan = std::move(direct);
    } catch (const std::runtime_error& direct) {
      if (!chain) throw;
      std::vector<WalkingGait> walked{start};
      plan = ChainGaitChange(std::move(plan), s, start, a, g, steps, end_in_single_support, seed, cache, from_start, who, direct.what(), &change, nodes,
                             report, &walked);
      if (report != nullptr) report->start_chain = walked;
    }
    if (report != nullptr) {
      report->start_gait_used = true;
      report->start_gait = start;
      report->periodic_start = {s.solve_s, s.gait.collocation.nlp.iterations, s.gait.max_constraint_violation};
      report->transition_start = change;
    }
  } else {
    plan = StandingInto(a, g, steps, cache, report, sp, who, end_in_single_support);
    if (report != nullptr) report->start_gait_used = false, report->periodic_start = {}, report->transition_start = {};
  }
  if (report != nullptr) report->periodic = {a.solve_s, a.gait.collocation.nlp.iterations, a.gait.max_constraint_violation};
  if (gait_out != nullptr) *gait_out = std::move(a);
  return plan;
}

GaitVector AsVector(const WalkingGait& g) { return {g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m}; }
std::string GaitText(const WalkingGait& g) {
  char b[96];
  std::snprintf(b, sizeof b, "(%g m, %g s, %g s, %g m)", g.step_length_m, g.ssp_duration_s, g.dsp_duration_s, g.step_width_m);
  return b;
}

// `plan` ends at a touchdown of the solved gait `ga`, whose direct change into `gb` has no plan (`direct_error`): the
// lazy gait-graph search (GaitGraph) appends changes through intermediate gaits, chain_steps steps each, then the
// change into b and steps_b steps of it. A transition or an intermediate gait that has no plan removes that edge.
// Appends the gaits after a to *walked and adds the search's time and counts to the report.
WalkingPlan ChainGaitChange(WalkingPlan plan, const SolvedGait& ga, const WalkingGait& a, const SolvedGait& gb, const WalkingGait& b, int steps_b,
                            bool end_in_single_support, std::uint32_t seed, const PlanCache* cache, const StandToWalkParams& sp,
                            const std::string& who, const std::string& direct_error, WalkingNlpReport* last_transition,
                            WalkingTransitionNodes* nodes, WalkingPlanReport* report, std::vector<WalkingGait>* walked) {
  const auto t0 = Clock::now();
  GaitGraph graph(sp.gait_graph, AsVector(a), AsVector(b));
  graph.MarkInfeasible(graph.start(), graph.goal());
  const GaitVector goal = graph.node(graph.goal());
  std::vector<WalkingPlan> plans{std::move(plan)};  // plans[k]: after the chain's first k transitions
  std::vector<std::shared_ptr<const SolvedGait>> solved{std::make_shared<const SolvedGait>(ga)};
  std::vector<WalkingGait> gaits{a};
  std::map<GaitVector, std::shared_ptr<const SolvedGait>> periodic;  // intermediate gaits solved so far (null: no plan)
  const GaitChain chain = graph.ShortestFeasibleChain([&](int depth, const GaitVector&, const GaitVector& to) {
    plans.resize(depth + 1), solved.resize(depth + 1), gaits.resize(depth + 1);
    const bool last = to == goal;
    const WalkingGait g = last ? b : WalkingGait{to[0], to[1], to[2], to[3]};
    try {
      if (!last && !periodic.count(to)) {
        periodic[to] = nullptr;  // stays null when the gait has no periodic plan (SolveGait throws)
        periodic[to] = std::make_shared<const SolvedGait>(SolveGait(g, seed, cache, sp, who, "the chain gait " + GaitText(g)));
      }
      const std::shared_ptr<const SolvedGait> s = last ? std::make_shared<const SolvedGait>(gb) : periodic[to];
      if (s == nullptr) return false;
      WalkingPlan next = plans[depth];
      AppendGaitChange(next, *solved[depth], gaits[depth], *s, g, last ? steps_b : sp.chain_steps, last ? end_in_single_support : true, cache, sp,
                       who + " (chain " + GaitText(gaits[depth]) + " -> " + GaitText(g) + ")", last_transition, last ? nodes : nullptr);
      plans.push_back(std::move(next)), solved.push_back(s), gaits.push_back(g);
      return true;
    } catch (const std::runtime_error&) {
      return false;
    }
  });
  if (report != nullptr) {
    report->chain_planning_s += SecondsSince(t0);
    report->chain_transitions_tried += chain.transitions_tried;
    report->chain_transitions_failed += chain.transitions_failed;
  }
  if (!chain.found) throw std::runtime_error(direct_error + "; through the gait graph: " + chain.message);
  if (walked != nullptr) walked->insert(walked->end(), gaits.begin() + 1, gaits.end());
  return std::move(plans.back());
}

// Standing → gaits[0] (as StandToWalk, `steps` steps), then each change into the next gait (directly, or with `chain`
// through the gait graph when the direct transition has no plan), `steps` steps of each and steps_last of the last.
// The report's *_b entries are the last gait's and its change's.
WalkingPlan SequencePlan(const std::vector<WalkingGait>& gaits, int steps, std::uint32_t seed, const PlanCache* cache, WalkingPlanReport* report,
                         const StandToWalkParams& sp, int steps_last, bool chain, const std::string& who) {
  if (steps_last < 0) steps_last = steps;
  SolvedGait prev{AslipPeriodicGaitPlanner(GaitParams(gaits.front(), sp)), {}, 0.0};
  if (report != nullptr) report->chain_planning_s = 0, report->chain_transitions_tried = report->chain_transitions_failed = 0;
  WalkingPlan plan = StandToWalk(gaits.front(), steps, seed, cache, report, sp, who, /*end_in_single_support=*/true, &prev, chain);
  if (report != nullptr) report->chain = {gaits.front()};
  for (size_t i = 1; i < gaits.size(); ++i) {
    const bool last = i + 1 == gaits.size();
    const WalkingGait &a = gaits[i - 1], &b = gaits[i];
    SolvedGait gb = SolveGait(b, seed, cache, sp, who, gaits.size() == 2 ? "gait B" : "gait " + std::to_string(i + 1));
    const std::string change = gaits.size() == 2 ? " (gait A -> gait B)" : " (gait " + std::to_string(i) + " -> gait " + std::to_string(i + 1) + ")";
    const int steps_b = last ? steps_last : steps;
    WalkingNlpReport transition_report;
    WalkingTransitionNodes* nodes = last && report != nullptr ? &report->transition_b_nodes : nullptr;
    try {
      WalkingPlan direct = plan;
      AppendGaitChange(direct, prev, a, gb, b, steps_b, /*end_in_single_support=*/!last, cache, sp, who + change, &transition_report, nodes);
      plan = std::move(direct);
      if (report != nullptr) report->chain.push_back(b);
    } catch (const std::runtime_error& direct) {
      if (!chain) throw;
      plan = ChainGaitChange(std::move(plan), prev, a, gb, b, steps_b, !last, seed, cache, sp, who, direct.what(), &transition_report, nodes, report,
                             report != nullptr ? &report->chain : nullptr);
    }
    if (report != nullptr && last) {
      report->periodic_b = {gb.solve_s, gb.gait.collocation.nlp.iterations, gb.gait.max_constraint_violation};
      report->transition_b = transition_report;
    }
    prev = std::move(gb);
  }
  return plan;
}

// BuildGaitChangePlan without the gait range check (the lead-in gait may lie outside it); with `chain`, a change with
// no direct plan goes through the gait graph (ChainGaitChange).
WalkingPlan GaitChangePlan(const WalkingGait& a, const WalkingGait& b, int steps, std::uint32_t seed, const PlanCache* cache,
                           WalkingPlanReport* report, const StandToWalkParams& sp, int steps_b, bool chain = false) {
  return SequencePlan({a, b}, steps, seed, cache, report, sp, steps_b, chain, "BuildGaitChangePlan");
}

}  // namespace

WalkingPlan BuildStandToWalkPlan(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache, WalkingPlanReport* report,
                                 const StandToWalkParams& sp) {
  g.Validate("BuildStandToWalkPlan: gait");
  sp.Validate("BuildStandToWalkPlan");
  if (steps < 1) throw std::invalid_argument("BuildStandToWalkPlan: steps must be >= 1, got " + std::to_string(steps));
  WalkingGait lead = g;
  lead.step_length_m = sp.lead_in_step_length_m;
  lead.ssp_duration_s = sp.lead_in_ssp_duration_s;
  lead.dsp_duration_s = sp.lead_in_dsp_duration_s;
  const bool is_lead = SameTiming(g, lead);
  const bool faster = g.ssp_duration_s < lead.ssp_duration_s - 1e-9 || g.dsp_duration_s < lead.dsp_duration_s - 1e-9;
  const auto with_lead_in = [&](const std::string& reason) {
    WalkingPlanReport r;
    WalkingPlan plan = GaitChangePlan(lead, g, sp.lead_in_steps, seed, cache, &r, sp, steps);
    r.lead_in = true;
    r.lead_in_gait = lead;
    r.lead_in_reason = reason;
    if (report != nullptr) *report = r;
    return plan;
  };
  const auto with_unit = [](double x, const char* unit) {
    char b[40];
    std::snprintf(b, sizeof b, "%g %s", x, unit);
    return std::string(b);
  };
  const auto seconds = [&](double s) { return with_unit(s, "s"); };
  if (faster && sp.lead_in_steps > 0) {
    const std::string reason = "the gait (T_SSP " + seconds(g.ssp_duration_s) + ", T_DSP " + seconds(g.dsp_duration_s) +
                               ") is faster than the lead-in (T_SSP " + seconds(lead.ssp_duration_s) + ", T_DSP " +
                               seconds(lead.dsp_duration_s) + "): " +
                               (sp.start_gait_steps > 0 ? "the change from the start gait would ask more of the legs"
                                                        : "its first swing from the step stance would lag");
    try {
      return with_lead_in(reason);
    } catch (const std::runtime_error& e) {  // "gait A" / "gait B" in e are the lead-in and the gait
      const std::string through = "BuildStandToWalkPlan: " + reason + "; through a lead-in of " + std::to_string(sp.lead_in_steps) + " steps of (" +
                                  with_unit(lead.step_length_m, "m") + ", " + seconds(lead.ssp_duration_s) + ", " + seconds(lead.dsp_duration_s) +
                                  "): " + e.what();
      if (sp.start_gait_steps == 0) throw std::runtime_error(through);
      // From the start gait (a short, slow first swing) the direct change may still plan.
      try {
        WalkingPlan plan = StandToWalk(g, steps, seed, cache, report, sp, "BuildStandToWalkPlan", false, nullptr);
        if (sp.plan_check) sp.plan_check(plan);
        if (report != nullptr) report->lead_in = false, report->lead_in_reason = "tried and had no plan, so planned directly from the start gait: " + through;
        return plan;
      } catch (const std::runtime_error& direct) {
        throw std::runtime_error(through + "; directly from the start gait: " + direct.what());
      }
    }
  }
  try {
    WalkingPlan plan = StandToWalk(g, steps, seed, cache, report, sp, "BuildStandToWalkPlan", false, nullptr);
    if (sp.plan_check) sp.plan_check(plan);
    return plan;
  } catch (const std::runtime_error& direct) {
    if (sp.lead_in_steps == 0 || is_lead) throw;
    try {
      return with_lead_in(direct.what());
    } catch (const std::runtime_error& e) {
      throw std::runtime_error(std::string(direct.what()) + "; with a lead-in of " + std::to_string(sp.lead_in_steps) + " steps of (" +
                               with_unit(lead.step_length_m, "m") + ", " + seconds(lead.ssp_duration_s) + ", " +
                               seconds(lead.dsp_duration_s) + "): " + e.what());
    }
  }
}

WalkingPlan BuildGaitChangePlan(const WalkingGait& a, const WalkingGait& b, int steps, std::uint32_t seed, const PlanCache* cache,
                                WalkingPlanReport* report, const StandToWalkParams& sp, int steps_b) {
  a.Validate("BuildGaitChangePlan: gait A");
  b.Validate("BuildGaitChangePlan: gait B");
  sp.Validate("BuildGaitChangePlan");
  return GaitChangePlan(a, b, steps, seed, cache, report, sp, steps_b, sp.chain_gait_changes);
}

WalkingPlan BuildGaitSequencePlan(const std::vector<WalkingGait>& gaits, int steps, std::uint32_t seed, const PlanCache* cache,
                                  WalkingPlanReport* report, const StandToWalkParams& sp, int steps_last) {
  const std::string who = "BuildGaitSequencePlan";
  if (gaits.size() < 2 || gaits.size() > 20)
    throw std::invalid_argument(who + ": the sequence has " + std::to_string(gaits.size()) + " gaits, expected 2 to 20");
  for (size_t i = 0; i < gaits.size(); ++i) gaits[i].Validate(who + ": gait " + std::to_string(i + 1));
  sp.Validate(who);
  if (steps < 1) throw std::invalid_argument(who + ": steps must be >= 1, got " + std::to_string(steps));
  return SequencePlan(gaits, steps, seed, cache, report, sp, steps_last, sp.chain_gait_changes, who);
}

WalkingPlan BuildPeriodicWalkingPlan(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache, const StandToWalkParams& sp) {
  g.Validate("BuildPeriodicWalkingPlan: gait");
  sp.Validate("BuildPeriodicWalkingPlan");
  if (steps < 1) throw std::invalid_argument("BuildPeriodicWalkingPlan: steps must be >= 1, got " + std::to_string(steps));
  const SolvedGait a = SolveGait(g, seed, cache, sp, "BuildPeriodicWalkingPlan", "the gait");
  WalkingPlan plan;
  plan.AppendPeriodicSteps(a.planner, a.gait, steps + 1, WalkingDomain::kLeftStance, 0.0, g.step_width_m, /*begin_with_double_support=*/true);
  return plan;
}

Eigen::VectorXd WalkingInitialVelocity(const MultibodyModel& model, const Eigen::VectorXd& q, const WalkingPlan& plan, double t) {
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
  const int yaw = model.VelocityIndex("base_yaw"), pitch = model.VelocityIndex("base_pitch"), roll = model.VelocityIndex("base_roll");
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
