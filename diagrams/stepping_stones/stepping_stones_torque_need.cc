#include "diagrams/stepping_stones/stepping_stones_torque_need.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include <cstdio>
#include "systems/multibody/multibody_dynamics.h"
#include "systems/planners/momentum_regulation_planner.h"
#include "systems/planners/output_trajectories.h"
#include "systems/planners/vertical_com_mpc.h"
#include "systems/posture/pre_impact_posture_optimizer.h"
#include "systems/rom/linear_inverted_pendulum.h"

namespace rome {

namespace {

constexpr int kPitch = 2;  // planar floating base [x, z, pitch]

// A number with `digits` significant digits (%g).
std::string FormatNumber(double v, int digits = 4) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

std::string Step(double l, double h) { return "(" + FormatNumber(l) + ", " + FormatNumber(h) + ") m"; }

// The planned COM and outputs of one step, from the post-impact state of the periodic gait.
struct StepPlan {
  Eigen::VectorXd q_start;  // post-impact posture, the new stance foot at the origin
  double x0 = 0, xdot0 = 0, lambda = 0, z0 = 0, zdot0 = 0, duration = 0, speed = 0;
  Eigen::VectorXd mpc_inputs;
  double mpc_dt = 0;
  std::unique_ptr<SteppingStonesOutputTrajectories> outputs;
};

StepPlan PlanPeriodicStep(const MultibodyModel& model, double l, double h, double stone_length,
                          const SteppingStonesDiagramParams& params) {
  PreImpactPostureParams posture_params = params.supervisor.posture;
  posture_params.com_x_fraction = params.impact_fraction;
  PreImpactPostureOptimizer optimizer(std::make_shared<const MultibodyModel>(model), posture_params);
  PreImpactPostureRequest request;  // the supervisor's request (stepping_stones_supervisor.cc, PlanStep)
  request.stance_contact = "left_foot";
  request.swing_contact = "right_foot";
  request.step_length_m = l;
  request.step_height_m = h;
  SteppingStonesSupervisorParams supervisor = params.supervisor;
  supervisor.impact_fraction = params.impact_fraction;
  request.com_height_m = PreImpactComHeightRequest(supervisor, l, h);
  const PreImpactPosture posture = optimizer.Solve(request);
  if (!posture.success)
    throw std::invalid_argument("the pre-impact posture NLP finds no posture for the step " + Step(l, h) + ": " +
                                posture.message);
  StepPlan plan;
  // Periodic: the next step starts from q_f with the right foot, now at (l, h), as the stance foot at the origin.
  plan.q_start = posture.q;
  plan.q_start[0] -= posture.swing_foot.x();
  plan.q_start[1] -= posture.swing_foot.y();
  const double zf = posture.com_height_m;
  MomentumRegulationPlannerParams pp = params.planner;
  pp.target_orbital_energy = params.target_orbital_energy;
  pp.impact_fraction = params.impact_fraction;
  const MomentumRegulationPlanner planner(pp);
  MomentumRegulationInput in;
  in.step_length = l;
  in.step_height = h;
  in.pre_impact_com_height = zf;
  in.p_com_x = posture.com_x_m - posture.swing_foot.x();
  in.p_com_z = zf - posture.swing_foot.y();
  in.L_y = planner.DesiredPostImpactMomentum(l, h, zf);
  const double z0_hat = LinearInvertedPendulum::SlopeAdjustedHeight(in.p_com_x, in.p_com_z, l, h);
  in.pdot_com_x = in.L_y / z0_hat;
  const MomentumRegulationPlan mr = planner.Plan(in);
  if (!std::isfinite(mr.time_to_impact) || !std::isfinite(mr.u_des) || !(z0_hat > 0.0))
    throw std::invalid_argument("no finite momentum-regulation plan for the step " + Step(l, h));
  plan.x0 = in.p_com_x;
  plan.xdot0 = in.pdot_com_x;
  plan.lambda = std::sqrt(pp.gravity / z0_hat);
  plan.z0 = in.p_com_z;
  plan.zdot0 = (h / l) * in.pdot_com_x;
  plan.duration = mr.time_to_impact;
  plan.speed = l / mr.time_to_impact;
  VerticalComMpc mpc(params.mpc.mpc);
  if (mpc.Solve(plan.z0, plan.zdot0, zf, mr.u_des, plan.duration) != QpStatus::kOptimal)
    throw std::invalid_argument("the vertical-COM QP fails for the step " + Step(l, h));
  plan.mpc_inputs = mpc.inputs();
  plan.mpc_dt = mpc.dt();
  StepOutputParameters step;
  step.phi_0 = step.phi_f = posture.torso_pitch_rad;
  step.p_com_x0 = plan.x0;
  step.p_sw0_x = -posture.swing_foot.x();
  step.p_sw0_z = -posture.swing_foot.y();
  step.step_length = l;
  step.step_height = h;
  step.impact_fraction = params.impact_fraction;
  step.step_duration = plan.duration;
  SwingFootBezierParams swing = params.outputs.swing_foot;
  if (std::isnan(swing.stance_stone_half_length)) swing.stance_stone_half_length = 0.5 * stone_length;
  plan.outputs = std::make_unique<SteppingStonesOutputTrajectories>(params.outputs.phase, swing, step);
  return plan;
}

// The task rows [stance x, z; COM x, z; torso pitch; swing x, z] of posture q: positions, Jacobian, J̇ v.
struct Tasks {
  Eigen::Matrix<double, 7, 1> y, jdot_v;
  Eigen::MatrixXd J;
};

class PlanKinematics {
 public:
  explicit PlanKinematics(const MultibodyModel& model) : model_(model), ws_(model), J3_(3, model.nv()) {
    for (int side = 0; side < 2; ++side) {
      const ContactInfo& c = model.contacts()[model.ContactIndex(side == 0 ? "right_foot" : "left_foot")];
      if (c.type != ContactType::kPoint)
        throw std::invalid_argument("robot '" + model.name() + "': contact '" + c.name +
                                    "' is not a point foot; the plan's inverse dynamics needs point feet");
      body_[side] = c.body;
      point_[side] = c.frame_origin;
    }
  }
  MultibodyWorkspace& ws() { return ws_; }
  int stance_body() const { return body_[0]; }
  const Eigen::Vector3d& stance_point() const { return point_[0]; }

  void Eval(const Eigen::VectorXd& q, const Eigen::VectorXd* v, Tasks* t) {
    const int nv = model_.nv();
    t->J.resize(7, nv);
    const Eigen::Vector3d com = CalcComPosition(model_, ws_, q);
    t->y << 0, 0, com.x(), com.z(), q[kPitch], 0, 0;
    CalcComJacobian(model_, ws_, q, J3_);
    t->J.row(2) = J3_.row(0);
    t->J.row(3) = J3_.row(2);
    t->J.row(4).setZero();
    t->J(4, kPitch) = 1.0;
    t->jdot_v.setZero();
    if (v) {
      const Eigen::Vector3d a = CalcComJdotQdot(model_, ws_, q, *v);
      t->jdot_v[2] = a.x();
      t->jdot_v[3] = a.z();
    }
    for (int side = 0; side < 2; ++side) {
      const int row = side == 0 ? 0 : 5;
      const Eigen::Vector3d p = CalcPointPosition(model_, ws_, q, body_[side], point_[side]);
      t->y[row] = p.x();
      t->y[row + 1] = p.z();
      CalcPointJacobian(model_, ws_, q, body_[side], point_[side], J3_);
      t->J.row(row) = J3_.row(0);
      t->J.row(row + 1) = J3_.row(2);
      if (v) {
        const Eigen::Vector3d a = CalcPointJdotQdot(model_, ws_, q, *v, body_[side], point_[side]);
        t->jdot_v[row] = a.x();
        t->jdot_v[row + 1] = a.z();
      }
    }
  }

 private:
  const MultibodyModel& model_;
  MultibodyWorkspace ws_;
  Eigen::MatrixXd J3_;
  int body_[2] = {-1, -1};
  Eigen::Vector3d point_[2];
};

// One sample: the posture, velocity, accelerations, torques and force that follow the plan at time t.
PlanInverseDynamicsSample SolveSample(const MultibodyModel& model, PlanKinematics& kin, const StepPlan& plan, double t,
                                      Eigen::VectorXd& q_guess, const PlanTorqueNeedParams& np) {
  const double ch = std::cosh(plan.lambda * t), sh = std::sinh(plan.lambda * t);
  const double x = plan.x0 * ch + plan.xdot0 / plan.lambda * sh;
  const double xdot = plan.x0 * plan.lambda * sh + plan.xdot0 * ch;
  const double xddot = plan.lambda * plan.lambda * x;
  const Eigen::Vector3d z = VerticalComMpc::EvaluatePlan(plan.z0, plan.zdot0, plan.mpc_inputs, plan.mpc_dt, t);
  const DesiredOutputs out = plan.outputs->Evaluate(t, x, xdot, xddot, z);
  Eigen::Matrix<double, 7, 1> target, rate, accel;  // rows as in Tasks
  target << 0, 0, x, out.y[1], out.y[0], out.y[2], out.y[3];
  rate << 0, 0, xdot, out.ydot[1], out.ydot[0], out.ydot[2], out.ydot[3];
  accel << 0, 0, 0, out.yddot[1], out.yddot[0], out.yddot[2], out.yddot[3];
  Tasks tasks;
  PlanInverseDynamicsSample s;
  s.time_s = t;
  s.q = q_guess;
  for (int it = 0;; ++it) {
    kin.Eval(s.q, nullptr, &tasks);
    const Eigen::Matrix<double, 7, 1> r = tasks.y - target;
    if (r.cwiseAbs().maxCoeff() < np.ik_tolerance_m) break;
    if (it >= np.max_ik_iterations)
      throw std::invalid_argument("no posture follows the plan at t = " + FormatNumber(t) + " s (residual " +
                                  FormatNumber(r.cwiseAbs().maxCoeff()) + " m after " +
                                  std::to_string(np.max_ik_iterations) + " Newton steps)");
    s.q -= tasks.J.completeOrthogonalDecomposition().solve(r);
  }
  q_guess = s.q;
  s.v = tasks.J.completeOrthogonalDecomposition().solve(rate);
  kin.Eval(s.q, &s.v, &tasks);
  const int nv = model.nv(), nu = model.nu();
  // Unknowns [q̈; τ; λ]: M q̈ − B τ − J_stᵀ λ = −h; J_st q̈ = −J̇_st v; the output rows J_y q̈ = Ÿ_d − J̇_y v.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(nv + 6, nv + nu + 2);
  Eigen::VectorXd b(nv + 6);
  A.topLeftCorner(nv, nv) = CalcMassMatrix(model, kin.ws(), s.q);
  b.head(nv) = -CalcBiasForces(model, kin.ws(), s.q, s.v);
  for (int i = 0; i < nu; ++i) A(model.actuators()[i].v_index, nv + i) = -1.0;
  A.block(0, nv + nu, nv, 2) = -tasks.J.topRows(2).transpose();
  A.block(nv, 0, 2, nv) = tasks.J.topRows(2);
  b.segment(nv, 2) = -tasks.jdot_v.head(2);
  A.block(nv + 2, 0, 4, nv) = tasks.J.bottomRows(4);
  b.tail(4) = accel.tail(4) - tasks.jdot_v.tail(4);
  const Eigen::VectorXd sol = A.completeOrthogonalDecomposition().solve(b);
  s.vdot = sol.head(nv);
  s.tau = sol.segment(nv, nu);
  s.force = sol.tail(2);
  return s;
}

}  // namespace

PlanTorqueNeed CalcPeriodicPlanTorqueNeed(const MultibodyModel& model, double l, double h, double stone_length_m,
                                          const SteppingStonesDiagramParams& params, const PlanTorqueNeedParams& np,
                                          std::vector<PlanInverseDynamicsSample>* samples_out) {
  if (!(l > 0.0) || !std::isfinite(l) || !std::isfinite(h))
    throw std::invalid_argument("CalcPeriodicPlanTorqueNeed: the step " + Step(l, h) + " needs a finite length > 0");
  if (np.samples < 1 || np.max_ik_iterations < 1 || !(np.ik_tolerance_m > 0.0))
    throw std::invalid_argument("CalcPeriodicPlanTorqueNeed: samples (" + std::to_string(np.samples) +
                                ") and max_ik_iterations (" + std::to_string(np.max_ik_iterations) +
                                ") must be >= 1 and ik_tolerance_m (" + FormatNumber(np.ik_tolerance_m) + " m) > 0");
  if (!model.is_planar() || model.nu() < 1)
    throw std::invalid_argument("CalcPeriodicPlanTorqueNeed: robot '" + model.name() +
                                "' must be planar with actuators");
  const StepPlan plan = PlanPeriodicStep(model, l, h, stone_length_m, params);
  PlanKinematics kin(model);
  Eigen::MatrixXd J_stance(3, model.nv());
  PlanTorqueNeed need;
  need.step_duration_s = plan.duration;
  need.mean_speed_mps = plan.speed;
  need.min_normal_force_N = std::numeric_limits<double>::infinity();
  Eigen::VectorXd q_guess = plan.q_start;
  const double dt = plan.duration / np.samples;
  if (samples_out) samples_out->clear();
  for (int i = 0; i < np.samples; ++i) {
    const double t = plan.duration * (i + 0.5) / np.samples;
    PlanInverseDynamicsSample s = SolveSample(model, kin, plan, t, q_guess, np);
    const double fz = s.force.y();
    need.min_normal_force_N = std::min(need.min_normal_force_N, fz);
    need.max_friction_ratio = std::max(need.max_friction_ratio,
                                       fz > 0.0 ? std::abs(s.force.x()) / fz : std::numeric_limits<double>::infinity());
    CalcPointJacobian(model, kin.ws(), s.q, kin.stance_body(), kin.stance_point(), J_stance);
    bool stance_over = false;
    for (int k = 0; k < model.nu(); ++k) {
      const ActuatorInfo& a = model.actuators()[k];
      const double ratio = std::abs(s.tau[k]) / a.torque_limit_Nm;
      const bool stance_leg = J_stance.col(a.v_index).norm() > 1e-9;
      double& leg_max = stance_leg ? need.max_stance_torque_ratio : need.max_swing_torque_ratio;
      leg_max = std::max(leg_max, ratio);
      const double excess = std::max(std::abs(s.tau[k]) - a.torque_limit_Nm, 0.0) * dt;
      (stance_leg ? need.stance_excess_impulse_Nms : need.swing_excess_impulse_Nms) += excess;
      stance_over = stance_over || (stance_leg && ratio > 1.0);
      if (ratio <= need.max_torque_ratio) continue;
      need.max_torque_ratio = ratio;
      need.actuator = k;
      need.on_stance_leg = stance_leg;
      need.torque_Nm = std::abs(s.tau[k]);
      need.limit_Nm = a.torque_limit_Nm;
      need.time_of_max_s = t;
    }
    if (stance_over) need.stance_over_limit_fraction += 1.0 / np.samples;
    if (samples_out) samples_out->push_back(std::move(s));
  }
  return need;
}

}  // namespace rome
