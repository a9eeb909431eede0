#pragma once
// The walking tests' independent torque check of a plan (walking_change_check_test, walking_start_chain_test): the
// joint torques of the plan's kinematic replay by the mass-matrix form of the equations of motion,
// M(q) q̈ + C(q, q̇) q̇ + g(q) − τ_spring = B u + J_sᵀ w (CalcMassMatrix, CalcBiasForces: the composite-rigid-body
// algorithm, where the library's check uses recursive Newton-Euler inverse dynamics), with the stance sole's wrench w,
// on the plan the diagram tracks (BuildWalkingDiagram's, with its COM correction).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "diagrams/walking/walking_diagram.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome::test {

struct TorquePeak {
  double limit_fraction = 0;  ///< largest |u_j| / limit_j
  std::string joint;
  double time_s = 0;
};

// The largest |u_j| / limit_j over the single supports of `plan` in [from_s, to_s] (transition SSPs only when
// transitions_only), on a 2 ms replay, by M q̈ + h = B u + J_sᵀ w.
inline TorquePeak PeakTorque(const MultibodyModel& model, const WalkingPlan& plan, double from_s, double to_s,
                             bool transitions_only) {
  const double h = 2e-3;
  SwingFootTrajectoryParams swing = WalkingDiagramParams{}.swing;  // as the diagram: the robot's ankle height
  swing.ankle_height_m = -model.contacts()[model.ContactIndex("left_foot")].points.front().z();
  const Eigen::MatrixXd q = ReplayWalkingPlan(model, plan, swing, h);
  const int nv = model.nv(), nu = model.nu();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(nv, nu + 6), J(6, nv);
  for (int j = 0; j < nu; ++j) A(model.actuators()[j].v_index, j) = 1.0;
  MultibodyWorkspace ws(model);
  TorquePeak peak;
  for (Eigen::Index k = 1; k + 1 < q.cols(); ++k) {
    const double t = static_cast<double>(k) * h;
    if (t < from_s || t > to_s) continue;
    const size_t seg = plan.SegmentIndexAt(t);
    const WalkingPlanSegment& s = plan.segments()[seg];
    if (s.domain == WalkingDomain::kDoubleSupport) continue;
    if (transitions_only && s.lateral_nodes.cols() == 0) continue;
    if (plan.SegmentIndexAt(t - h) != seg || plan.SegmentIndexAt(t + h) != seg) continue;  // no difference across
    const Eigen::VectorXd v = (q.col(k + 1) - q.col(k - 1)) / (2 * h);
    const Eigen::VectorXd qdd = (q.col(k + 1) - 2 * q.col(k) + q.col(k - 1)) / (h * h);
    const Eigen::VectorXd tau = CalcMassMatrix(model, ws, q.col(k)) * qdd + CalcBiasForces(model, ws, q.col(k), v) -
                                CalcSpringTorques(model, ws, q.col(k), v);
    const int foot = model.BodyIndex(s.domain == WalkingDomain::kLeftStance ? "left_foot" : "right_foot");
    CalcFrameJacobian(model, ws, q.col(k), foot, Eigen::Vector3d(0, 0, -swing.ankle_height_m), J);
    A.rightCols(6) = J.transpose();
    const Eigen::VectorXd x = A.fullPivLu().solve(tau);
    EXPECT_LT((A * x - tau).norm(), 1e-6 * (1.0 + tau.norm())) << "t = " << t;
    for (int j = 0; j < nu; ++j) {
      const double f = std::abs(x[j]) / model.actuators()[j].torque_limit_Nm;
      if (f > peak.limit_fraction) peak = {f, model.actuators()[j].joint, t};
    }
  }
  return peak;
}

}  // namespace rome::test
