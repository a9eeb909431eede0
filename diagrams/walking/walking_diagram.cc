#include "diagrams/walking/walking_diagram.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

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
  p.contact.yaw_moment_coefficient_m = 0.02;
  p.contact.cop_margin_m = 0.01;  // ours: the plant's CoP drifts by ~1 mm over a held sample when the QP holds it on the edge, more near lift-off (5 mm: 1 mm outside at F_z = 21 N in an -O1 build)
  p.resolve_at_events = true;
  return p;
}

WalkingDiagram BuildWalkingDiagram(std::shared_ptr<const MultibodyModel> model, const WalkingPlan& plan, const WalkingDiagramParams& params,
                                   PlantKind plant) {
  const MultibodyModel& m = *model;
  for (const char* foot : {"left_foot", "right_foot"}) {
    const ContactInfo& c = m.contacts()[m.ContactIndex(foot)];
    if (c.type != ContactType::kFlat)
      throw std::invalid_argument(std::string("BuildWalkingDiagram: robot '") + m.name() + "': contact '" + foot + "' is not a flat foot");
  }
  SwingFootTrajectoryParams swing = params.swing;
  swing.ankle_height_m = -m.contacts()[m.ContactIndex("left_foot")].points.front().z();

  DiagramBuilder b;
  WalkingDiagram d;
  HybridContactPlantParams plant_params = params.plant;
  if (plant_params.planned_liftoff_force_N <= 0.0) plant_params.planned_liftoff_force_N = 0.01 * m.total_mass() * 9.81;  // spec §7.5 [R]
  // The Bullet plant releases the trailing foot at the same force (a planned lift-off; see bullet_world_plant.h).
  BulletWorldPlantParams bullet_params = params.bullet_plant;
  if (bullet_params.planned_liftoff_force_N < 0) bullet_params.planned_liftoff_force_N = plant_params.planned_liftoff_force_N;
  if (bullet_params.min_time_in_mode_s <= 0) bullet_params.min_time_in_mode_s = plant_params.min_time_in_mode_s;
  d.plant = b.AddSystem(MakeContactPlant(plant, "plant", model, ContactModeGraph::WithDoubleSupport("left_foot", "right_foot"), Terrain::Flat(),
                                         plant_params, bullet_params));
  const int left_stance = 0, right_stance = 2;
  TaskGains foot_gains;
  foot_gains.weight = params.swing_foot_weight;
  const std::vector<Axis> xyz{Axis::kX, Axis::kY, Axis::kZ};
  std::vector<ClfOutput> outputs = {
      // Eq. (16): COM position and pelvis orientation, every mode.
      ClfOutput::RelativeDegreeTwo(std::make_shared<ComPositionTask>("com", xyz)),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_roll", m, "base_roll")),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_pitch", m, "base_pitch")),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_yaw", m, "base_yaw")),
      // Eq. (17): swing foot position and orientation, in the other foot's stance only.
      ClfOutput::RelativeDegreeTwo(std::make_shared<PointPositionTask>("left_ankle", m, "left_foot", Eigen::Vector3d::Zero(), xyz, foot_gains,
                                                                       std::vector<int>{right_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<BodyOrientationTask>("left_foot_orientation", m, "left_foot", foot_gains, std::vector<int>{right_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<PointPositionTask>("right_ankle", m, "right_foot", Eigen::Vector3d::Zero(), xyz, foot_gains,
                                                                       std::vector<int>{left_stance})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<BodyOrientationTask>("right_foot_orientation", m, "right_foot", foot_gains, std::vector<int>{left_stance})),
  };
  ClfQpParams cp = params.controller;
  cp.contact_stabilization = plant_params.dynamics;
  d.reference = b.AddSystem(std::make_unique<WalkingTrajectorySource>("walking_reference", plan));
  d.outputs = b.AddSystem(std::make_unique<WalkingOutputReference>("outputs", plan, swing));
  d.controller = b.AddSystem(std::make_unique<ClfQpController>("controller", model, ActiveContactsPerMode(*d.plant), std::move(outputs), cp));
  b.Connect("walking_reference", "com", "outputs", "com");
  b.Connect("outputs", "desired", "controller", "desired");
  b.Connect("walking_reference", "normal_force_reference", "controller", "normal_force_reference");
  b.Connect("plant", "state", "controller", "state");
  b.Connect("plant", "mode", "controller", "mode");
  b.Connect("controller", "u", "plant", "u");
  d.diagram = b.Build("walking");
  return d;
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

WalkingPlan BuildStandToWalkPlan(const WalkingGait& g, int steps, std::uint32_t seed, const PlanCache* cache, WalkingPlanReport* report,
                                 const StandToWalkParams& sp) {
  using Clock = std::chrono::steady_clock;
  const SoleGeometry& sole = sp.sole;
  const double margin = sp.lateral_cop_margin_m, sag = sp.sagittal_cop_margin_m;
  if (!(sag >= 0) || !(sole.heel_m - sag > 0 && sole.toe_m - sag > 0))
    throw std::invalid_argument("BuildStandToWalkPlan: sagittal_cop_margin_m = " + std::to_string(sag) + " must be >= 0 and leave a sole");
  if (!(margin >= 0) || !(sole.left_m - margin > 0 && sole.right_m - margin > 0))
    throw std::invalid_argument("BuildStandToWalkPlan: lateral_cop_margin_m = " + std::to_string(margin) + " must be >= 0 and leave a sole");
  if (!(sp.stance_stagger_m >= 0) || !std::isfinite(sp.stance_stagger_m))
    throw std::invalid_argument("BuildStandToWalkPlan: stance_stagger_m must be >= 0 m, got " + std::to_string(sp.stance_stagger_m));
  AslipPeriodicGaitParams gp;
  gp.step_length = g.step_length_m;
  gp.ssp_duration = g.ssp_duration_s;
  gp.dsp_duration = g.dsp_duration_s;
  gp.height_min = sp.height_min_m;
  gp.height_max = sp.height_max_m;
  const AslipPeriodicGaitPlanner periodic(gp);
  auto t0 = Clock::now();
  const AslipPeriodicGait gait = periodic.Solve(seed, cache);
  const double periodic_s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!gait.success()) throw std::runtime_error("BuildStandToWalkPlan: the periodic aSLIP NLP failed: " + gait.collocation.nlp.message);
  AslipTransitionParams tp;
  tp.bounds = gp;
  tp.bounds.aslip.heel_length = sole.heel_m - sag;  // Eq. (10) on the robot's sole
  tp.bounds.aslip.toe_length = sole.toe_m - sag;
  tp.min_ssp_duration = std::max({tp.min_ssp_duration, g.ssp_duration_s, sp.transition_min_ssp_duration_s});
  tp.max_ssp_duration = std::max(tp.max_ssp_duration, tp.min_ssp_duration);
  if (sp.point_foot_transition_ssp) tp.max_ssp_ankle_torque = 0.0;
  tp.min_dsp_stance_force_fraction = sp.min_dsp_stance_force_fraction;
  tp.lateral = sp.lateral_in_transition_nlp;
  tp.foot_width_left_of_ankle = sole.left_m - margin;
  tp.foot_width_right_of_ankle = sole.right_m - margin;
  const AslipTransitionPlanner transition_planner(tp);
  AslipTransitionData data;
  data.left_foot_x = 0.0;
  data.right_foot_x = -sp.stance_stagger_m;
  data.initial_state = AslipTransitionPlanner::StandingState(gp.aslip, sp.standing_height_m, data.left_foot_x, data.right_foot_x);
  data.final_state = gait.collocation.phases[0].states.col(gp.nodes_per_domain - 1);
  const HybridLinearInvertedPendulum hlip({.z0 = gait.mean_height, .ssp_duration = g.ssp_duration_s, .dsp_duration = g.dsp_duration_s});
  const Eigen::Vector2d pre = hlip.P2PreImpactState(g.step_width_m);  // end of a left stance, about the left foot
  data.left_foot_y = g.step_width_m / 2;
  data.right_foot_y = -g.step_width_m / 2;
  data.initial_lateral_state = Eigen::Vector2d(0.0, 0.0);
  data.final_lateral_state = Eigen::Vector2d(data.left_foot_y + pre(0), pre(1));
  data.lifting_leg = 1;
  t0 = Clock::now();
  const AslipTransition transition = transition_planner.Solve(data, cache);
  const double transition_s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!transition.success()) throw std::runtime_error("BuildStandToWalkPlan: the transition footed-aSLIP NLP failed: " + transition.collocation.nlp.message);
  // Footed H-LIP QP on the transition's nodes (the DSP's last node is the SSP's first), with its per-foot forces.
  const double W = g.step_width_m, m = gp.aslip.mass;
  FootedHlipTransitionData lat = LateralDataOnTransitionNodes(transition, tp.bounds.aslip, data, gp.nodes_per_domain, W);
  lat.final_state = data.final_lateral_state;
  FootedHlipTransitionParams lp;
  lp.mass = m;
  lp.foot_width_left_of_ankle = sole.left_m - margin;  // Eq. (14) on the robot's sole
  lp.foot_width_right_of_ankle = sole.right_m - margin;
  lp.normal_force_pivots = sp.lateral_normal_force_pivots;
  const FootedHlipTransitionPlan lateral = FootedHlipTransitionPlanner(lp).Solve(lat);
  if (!lateral.success()) throw std::runtime_error("BuildStandToWalkPlan: the footed H-LIP transition QP failed: " + lateral.message);
  WalkingPlan plan;
  plan.AppendTransition(transition_planner, transition, data, 0.0, lat, lateral, m, gp.step_length);
  plan.AppendPeriodicSteps(periodic, gait, steps, WalkingDomain::kLeftStance, 0.0, W, /*begin_with_double_support=*/true);
  if (report != nullptr) {
    report->periodic_solve_s = periodic_s;
    report->transition_solve_s = transition_s;
    report->periodic_iterations = gait.collocation.nlp.iterations;
    report->transition_iterations = transition.collocation.nlp.iterations;
    report->periodic_violation = gait.max_constraint_violation;
    report->transition_violation = transition.max_constraint_violation;
  }
  return plan;
}

Eigen::VectorXd WalkingStandingPose(const MultibodyModel& model, const WalkingPlan& plan) {
  const WalkingReference r = plan.Sample(0.0);
  const int nv = model.nv();
  const double ankle = -model.contacts()[model.ContactIndex("left_foot")].points.front().z();
  const int feet[2] = {model.BodyIndex("left_foot"), model.BodyIndex("right_foot")};
  const Eigen::Vector3d target[2] = {Eigen::Vector3d(r.left_foothold.x(), r.left_foothold.y(), ankle),
                                     Eigen::Vector3d(r.right_foothold.x(), r.right_foothold.y(), ankle)};
  // Free coordinates: base x, y, z and the 12 joints (the base angles stay 0).
  std::vector<int> free;
  for (const char* n : {"base_x", "base_y", "base_z"}) free.push_back(model.VelocityIndex(n));
  const int yaw = model.VelocityIndex("base_yaw"), pitch = model.VelocityIndex("base_pitch"), roll = model.VelocityIndex("base_roll");
  for (int i = 0; i < nv; ++i)
    if (i != yaw && i != pitch && i != roll && std::find(free.begin(), free.end(), i) == free.end()) free.push_back(i);
  const int n = static_cast<int>(free.size());
  MultibodyWorkspace ws(model);
  Eigen::VectorXd q = model.q_nominal();
  Eigen::VectorXd res(n);
  Eigen::MatrixXd J(n, nv), Jc(3, nv), Jf(6, nv);
  for (int it = 0; it < 50; ++it) {
    res.head<3>() = CalcComPosition(model, ws, q) - r.com_position;
    CalcComJacobian(model, ws, q, Jc);
    J.topRows(3) = Jc;
    for (int f = 0; f < 2; ++f) {
      const Eigen::Isometry3d X = CalcLinkPose(model, ws, q, feet[f]);
      const Eigen::AngleAxisd aa(X.linear());
      res.segment<3>(3 + 6 * f) = X.translation() - target[f];
      res.segment<3>(6 + 6 * f) = aa.angle() * aa.axis();
      CalcFrameJacobian(model, ws, q, feet[f], Eigen::Vector3d::Zero(), Jf);
      J.middleRows(3 + 6 * f, 3) = Jf.bottomRows(3);
      J.middleRows(6 + 6 * f, 3) = Jf.topRows(3);
    }
    if (res.norm() < 1e-10) return q;
    Eigen::MatrixXd Jr(n, n);
    for (int k = 0; k < n; ++k) Jr.col(k) = J.col(free[k]);
    const Eigen::VectorXd dq = Jr.fullPivLu().solve(-res);
    for (int k = 0; k < n; ++k) q[free[k]] += dq[k];
  }
  throw std::runtime_error("WalkingStandingPose: robot '" + model.name() + "': no standing pose for the plan's start (residual " +
                           std::to_string(res.norm()) + ")");
}

}  // namespace rome
