// SolvePose: stance poses of the robots satisfy every requested constraint, checked with the kinematics
// functions directly (not through CalcPoseConstraints); the Jacobian matches finite differences; a
// single-support pose with the COM above the stance foot is in static equilibrium on that foot alone; bad
// requests get a clear error.
#include "systems/multibody/pose_constraints.h"

#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

MultibodyModel LoadRobot(const std::string& name) {
  return MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/" + name + "/" + name + ".rome.json"),
                                         {.euler_floating_base = true});
}

Eigen::Vector3d ContactOrigin(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q,
                              const std::string& contact) {
  const ContactInfo& info = model.contacts()[model.ContactIndex(contact)];
  return CalcPointPosition(model, ws, q, info.body, info.frame_origin);
}

// Expects `what` to throw E with a message that contains every string of `parts`.
template <class E, class F>
void ExpectThrowWith(F what, const std::vector<std::string>& parts) {
  try {
    what();
    ADD_FAILURE() << "no exception";
  } catch (const E& e) {
    for (const auto& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << "'" << p << "' not in: " << e.what();
  }
}

std::vector<PoseConstraint> AmberSingleSupport(const MultibodyModel& model, double swing_x, double swing_z) {
  return {PoseConstraint::ContactPoint(model, "left_foot", 0, 0.0),
          PoseConstraint::ContactPoint(model, "left_foot", 2, 0.0),
          PoseConstraint::Com(0, 0.0),
          PoseConstraint::Coordinate(2, 0.0),
          PoseConstraint::ContactPoint(model, "right_foot", 0, swing_x),
          PoseConstraint::ContactPoint(model, "right_foot", 2, swing_z)};
}

TEST(PoseConstraintsTest, AmberSingleSupportSatisfiesEveryConstraint) {
  const MultibodyModel model = LoadRobot("amber");
  MultibodyWorkspace ws(model);
  for (const auto& [sx, sz] : std::vector<std::pair<double, double>>{{0.12, 0.08}, {-0.2, 0.05}, {0.3, 0.0}}) {
    const Eigen::VectorXd q = SolvePose(model, ws, model.q_nominal(), AmberSingleSupport(model, sx, sz));
    MultibodyWorkspace fresh(model);  // independent evaluation, no cached state
    const Eigen::Vector3d pl = ContactOrigin(model, fresh, q, "left_foot"),
                          pr = ContactOrigin(model, fresh, q, "right_foot");
    const Eigen::Vector3d com = CalcComPosition(model, fresh, q);
    EXPECT_NEAR(pl.x(), 0.0, 1e-10);
    EXPECT_NEAR(pl.z(), 0.0, 1e-10);
    EXPECT_NEAR(com.x(), 0.0, 1e-10);
    EXPECT_NEAR(q[2], 0.0, 1e-10);
    EXPECT_NEAR(pr.x(), sx, 1e-10);
    EXPECT_NEAR(pr.z(), sz, 1e-10);
    // The shin end is the foot: (0, 0, -0.4667) in the shin frame, from the sidecar.
    const Eigen::Vector3d shin_end =
        CalcPointPosition(model, fresh, q, model.BodyIndex("left_shin"), Eigen::Vector3d(0, 0, -0.4667));
    EXPECT_NEAR((shin_end - pl).norm(), 0.0, 1e-12);
  }
}

// Physics: with the COM straight above the stance foot, gravity has no moment about that foot, so the robot held
// still (v = 0, q̈ = 0) needs only a vertical force of m g at the stance foot: the generalized gravity force is
// balanced by J_foot^T (0, m g) plus joint torques, with zero torque on the unactuated base.
TEST(PoseConstraintsTest, AmberComAboveStanceFootIsStaticallyBalanced) {
  const MultibodyModel model = LoadRobot("amber");
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd q = SolvePose(model, ws, model.q_nominal(), AmberSingleSupport(model, 0.12, 0.08));
  const int nv = model.nv();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nv);
  Eigen::VectorXd g = CalcBiasForces(model, ws, q, zero);  // h(q, 0) = generalized gravity force
  const ContactInfo& L = model.contacts()[model.ContactIndex("left_foot")];
  Eigen::MatrixXd J3(3, nv);
  CalcPointJacobian(model, ws, q, L.body, L.frame_origin, J3);
  const double mg = model.total_mass() * 9.81;
  // Base rows (x, z, pitch): g_base = J_base^T f with f = (0, 0, m g) at the foot.
  const Eigen::Vector3d base_residual = g.head<3>() - J3.leftCols<3>().transpose() * Eigen::Vector3d(0, 0, mg);
  EXPECT_LT(base_residual.norm(), 1e-9 * mg) << base_residual.transpose();
  // Control: a pose with the COM 5 cm ahead of the foot is not balanced by a vertical force (pitch row m g 0.05).
  std::vector<PoseConstraint> off = AmberSingleSupport(model, 0.12, 0.08);
  off[2].target = 0.05;
  const Eigen::VectorXd q_off = SolvePose(model, ws, model.q_nominal(), off);
  g = CalcBiasForces(model, ws, q_off, zero);
  CalcPointJacobian(model, ws, q_off, L.body, L.frame_origin, J3);
  const Eigen::Vector3d off_residual = g.head<3>() - J3.leftCols<3>().transpose() * Eigen::Vector3d(0, 0, mg);
  EXPECT_NEAR(std::abs(off_residual[2]), mg * 0.05, 1e-9 * mg);
}

TEST(PoseConstraintsTest, AmberDoubleSupportOnARaisedStone) {
  const MultibodyModel model = LoadRobot("amber");
  MultibodyWorkspace ws(model);
  const double x0 = 1.3, z0 = 0.2, com_height = 0.82;
  Eigen::VectorXd q0 = model.q_nominal();
  q0[0] += x0;
  q0[1] += z0;
  const std::vector<PoseConstraint> pose = {PoseConstraint::ContactPoint(model, "left_foot", 0, x0),
                                            PoseConstraint::ContactPoint(model, "left_foot", 2, z0),
                                            PoseConstraint::ContactPoint(model, "right_foot", 0, x0),
                                            PoseConstraint::ContactPoint(model, "right_foot", 2, z0),
                                            PoseConstraint::Com(0, x0 - 0.02),
                                            PoseConstraint::Com(2, z0 + com_height),
                                            PoseConstraint::Coordinate(2, 0.0)};
  const Eigen::VectorXd q = SolvePose(model, ws, q0, pose);
  MultibodyWorkspace fresh(model);
  const Eigen::Vector3d pl = ContactOrigin(model, fresh, q, "left_foot"),
                        pr = ContactOrigin(model, fresh, q, "right_foot");
  const Eigen::Vector3d com = CalcComPosition(model, fresh, q);
  EXPECT_NEAR(pl.x(), x0, 1e-10);
  EXPECT_NEAR(pl.z(), z0, 1e-10);
  EXPECT_NEAR(pr.x(), x0, 1e-10);
  EXPECT_NEAR(pr.z(), z0, 1e-10);
  EXPECT_NEAR(com.x(), x0 - 0.02, 1e-10);
  EXPECT_NEAR(com.z(), z0 + com_height, 1e-10);
  EXPECT_NEAR(q[2], 0.0, 1e-10);
  // Here the nearby solution is a knee-flexed stance inside the joint limits (SolvePose does not enforce limits).
  for (const char* j : {"left_hip", "left_knee", "right_hip", "right_knee"}) {
    const int i = model.VelocityIndex(j);
    EXPECT_GE(q[i], model.position_lower_limits()[i]) << j;
    EXPECT_LE(q[i], model.position_upper_limits()[i]) << j;
  }
}

// A 3D model with y constraints and a line-foot planar model.
TEST(PoseConstraintsTest, ExoskeletonAndPlanarCassieStancePoses) {
  {
    const MultibodyModel model = LoadRobot("exoskeleton");
    MultibodyWorkspace ws(model);
    std::vector<PoseConstraint> pose;
    const Eigen::Vector3d left(0.1, 0.12, 0.0), right(-0.1, -0.12, 0.0), com_xy(0.0, 0.01, 0.0);
    for (int a = 0; a < 3; ++a) {
      pose.push_back(PoseConstraint::ContactPoint(model, "left_foot", a, left[a]));
      pose.push_back(PoseConstraint::ContactPoint(model, "right_foot", a, right[a]));
    }
    pose.push_back(PoseConstraint::Com(0, com_xy.x()));
    pose.push_back(PoseConstraint::Com(1, com_xy.y()));
    for (int b = 3; b < 6; ++b) pose.push_back(PoseConstraint::Coordinate(b, 0.0));  // base yaw, pitch, roll
    const Eigen::VectorXd q = SolvePose(model, ws, model.q_nominal(), pose);
    MultibodyWorkspace fresh(model);
    EXPECT_LT((ContactOrigin(model, fresh, q, "left_foot") - left).norm(), 1e-10);
    EXPECT_LT((ContactOrigin(model, fresh, q, "right_foot") - right).norm(), 1e-10);
    EXPECT_LT((CalcComPosition(model, fresh, q).head<2>() - com_xy.head<2>()).norm(), 1e-10);
    EXPECT_LT(q.segment<3>(3).norm(), 1e-10);
  }
  {
    const MultibodyModel model = LoadRobot("cassie_planar");
    MultibodyWorkspace ws(model);
    const std::vector<PoseConstraint> pose = {PoseConstraint::ContactPoint(model, "left_foot", 0, 0.1),
                                              PoseConstraint::ContactPoint(model, "left_foot", 2, 0.0),
                                              PoseConstraint::ContactPoint(model, "right_foot", 0, -0.1),
                                              PoseConstraint::ContactPoint(model, "right_foot", 2, 0.0),
                                              PoseConstraint::Com(0, 0.0),
                                              PoseConstraint::Coordinate(2, 0.0)};
    const Eigen::VectorXd q = SolvePose(model, ws, model.q_nominal(), pose);
    MultibodyWorkspace fresh(model);
    const Eigen::Vector3d pl = ContactOrigin(model, fresh, q, "left_foot"),
                          pr = ContactOrigin(model, fresh, q, "right_foot");
    EXPECT_NEAR(pl.x(), 0.1, 1e-10);
    EXPECT_NEAR(pl.z(), 0.0, 1e-10);
    EXPECT_NEAR(pr.x(), -0.1, 1e-10);
    EXPECT_NEAR(pr.z(), 0.0, 1e-10);
    EXPECT_NEAR(CalcComPosition(model, fresh, q).x(), 0.0, 1e-10);
    EXPECT_NEAR(q[2], 0.0, 1e-10);
  }
}

TEST(PoseConstraintsTest, PlanarCassieFlatSolesAndClosedRods) {
  const MultibodyModel model = LoadRobot("cassie_planar");
  MultibodyWorkspace ws(model);
  std::vector<PoseConstraint> pose;
  for (const char* foot : {"left_foot", "right_foot"}) {
    const ContactInfo& info = model.contacts()[model.ContactIndex(foot)];
    pose.push_back(PoseConstraint::ContactPoint(model, foot, 0, 0.05));
    for (const Eigen::Vector3d& p : info.points)
      pose.push_back(PoseConstraint::Point(model, info.link, p, 2, 0.1));  // sole flat at z = 0.1
  }
  pose.push_back(PoseConstraint::Com(0, 0.0));
  pose.push_back(PoseConstraint::Com(2, 0.9));
  pose.push_back(PoseConstraint::Coordinate(2, 0.0));
  const std::vector<PoseConstraint> rods = PoseConstraint::LoopClosures(model);
  ASSERT_EQ(rods.size(), 2u);
  EXPECT_EQ(DescribePoseConstraint(model, rods[0]), "loop closure left_achilles");
  pose.insert(pose.end(), rods.begin(), rods.end());
  const Eigen::VectorXd q = SolvePose(model, ws, model.q_nominal(), pose);
  MultibodyWorkspace fresh(model);
  for (const LoopClosureInfo& lc : model.loop_closures())
    EXPECT_NEAR((CalcPointPosition(model, fresh, q, lc.body_a, lc.point_a) -
                 CalcPointPosition(model, fresh, q, lc.body_b, lc.point_b))
                    .norm(),
                lc.distance_m, 1e-10)
        << lc.name;
  for (int c = 0; c < 2; ++c)
    for (const Eigen::Vector3d& p : model.contacts()[c].points)
      EXPECT_NEAR(CalcPointPosition(model, fresh, q, model.contacts()[c].body, p).z(), 0.1, 1e-10);
  // The loop-closure rows' Jacobian matches finite differences.
  Eigen::VectorXd qq = q;
  for (int i = 0; i < model.nv(); ++i) qq[i] += 0.03 * std::cos(2.0 + i);
  Eigen::VectorXd c(2), cp(2), cm(2);
  Eigen::MatrixXd C(2, model.nv()), scratch(2, model.nv());
  CalcPoseConstraints(model, ws, qq, rods, c, C);
  for (int i = 0; i < model.nv(); ++i) {
    Eigen::VectorXd qp = qq, qm = qq;
    qp[i] += 1e-6;
    qm[i] -= 1e-6;
    CalcPoseConstraints(model, ws, qp, rods, cp, scratch);
    CalcPoseConstraints(model, ws, qm, rods, cm, scratch);
    EXPECT_LT((C.col(i) - (cp - cm) / 2e-6).norm(), 1e-7) << "column " << i;
  }
  EXPECT_THROW(ValidatePoseConstraints(model, {PoseConstraint::LoopClosure(2)}), std::invalid_argument);
}

TEST(PoseConstraintsTest, JacobianMatchesFiniteDifferences) {
  const MultibodyModel model = LoadRobot("exoskeleton");
  MultibodyWorkspace ws(model);
  std::vector<PoseConstraint> pose = {
      PoseConstraint::ContactPoint(model, "left_foot", 1, 0.0), PoseConstraint::Com(2, 0.9),
      PoseConstraint::Point(model, "right_shank", Eigen::Vector3d(0.01, 0.02, -0.2), 0, 0.0),
      PoseConstraint::Coordinate(8, 0.3), PoseConstraint::Com(0, 0.1)};
  const int m = static_cast<int>(pose.size()), nv = model.nv();
  Eigen::VectorXd q = model.q_nominal();
  for (int i = 0; i < nv; ++i) q[i] += 0.05 * std::sin(1.0 + i);
  Eigen::VectorXd c(m), cp(m), cm(m);
  Eigen::MatrixXd C(m, nv), scratch(m, nv);
  CalcPoseConstraints(model, ws, q, pose, c, C);
  const double eps = 1e-6;
  for (int i = 0; i < nv; ++i) {
    Eigen::VectorXd qp = q, qm = q;
    qp[i] += eps;
    qm[i] -= eps;
    CalcPoseConstraints(model, ws, qp, pose, cp, scratch);
    CalcPoseConstraints(model, ws, qm, pose, cm, scratch);
    EXPECT_LT((C.col(i) - (cp - cm) / (2 * eps)).norm(), 1e-7) << "column " << i;
  }
  EXPECT_NEAR(c[3], q[8] - 0.3, 1e-15);
  EXPECT_NEAR(c[1], CalcComPosition(model, ws, q).z() - 0.9, 1e-15);
}

// A redundant request (only the tip's x on the double pendulum) whose plain minimum-norm Newton bends the elbow past
// its 2.5 rad limit: with respect_joint_limits the elbow stays within [-2.5, 2.5] and the shoulder carries the rest;
// the tip is checked with the kinematics directly.
TEST(PoseConstraintsTest, RespectJointLimitsKeepsTheElbowInsideItsLimitAndStillReachesTheTarget) {
  const MultibodyModel model = MultibodyModel::Load(
      rome::test::SourcePath("tests/systems/multibody/data/double_pendulum.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  const int lower = model.BodyIndex("lower");
  const Eigen::Vector3d tip(0, 0, -0.5);
  const Eigen::VectorXd q0 = Eigen::Vector2d(0.0, 2.3);
  const auto tip_x = [&](const Eigen::VectorXd& q) { return CalcPointPosition(model, ws, q, lower, tip).x(); };
  // Move the target the way that opens the elbow (finite-difference sign of d x / d q_elbow).
  const double h = 1e-6, dx_delbow = (tip_x(q0 + Eigen::Vector2d(0, h)) - tip_x(q0 - Eigen::Vector2d(0, h))) / (2 * h);
  const double target = tip_x(q0) + (dx_delbow > 0 ? 0.3 : -0.3);
  const std::vector<PoseConstraint> pose = {PoseConstraint::Point(model, "lower", tip, 0, target)};
  const Eigen::VectorXd q_free = SolvePose(model, ws, q0, pose);
  ASSERT_GT(q_free[1], 2.5) << "the unbounded solve must leave the limit for this test to mean anything";
  PoseSolverOptions bounded;
  bounded.respect_joint_limits = true;
  const Eigen::VectorXd q = SolvePose(model, ws, q0, pose, bounded);
  EXPECT_LE(q[1], 2.5);
  EXPECT_GE(q[1], -2.5);
  EXPECT_NEAR(tip_x(q), target, 1e-10);
  // A target beyond the reach inside the limits is an error that says so.
  const std::vector<PoseConstraint> far = {PoseConstraint::Point(model, "lower", tip, 0, 1.3)};
  ExpectThrowWith<std::runtime_error>([&] { SolvePose(model, ws, q0, far, bounded); }, {"within the joint limits"});
}

TEST(PoseConstraintsTest, BadRequestsGetClearErrors) {
  const MultibodyModel model = LoadRobot("amber");
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd q0 = model.q_nominal();
  ExpectThrowWith<std::invalid_argument>([&] { SolvePose(model, ws, q0, {}); }, {"amber", "no constraints"});
  ExpectThrowWith<std::invalid_argument>(
      [&] { SolvePose(model, ws, Eigen::VectorXd::Zero(3), {PoseConstraint::Com(0, 0)}); },
      {"q0 has size 3", "nq = 7"});
  ExpectThrowWith<std::invalid_argument>([&] { SolvePose(model, ws, q0, {PoseConstraint::Com(1, 0.0)}); },
                                         {"COM y", "planar"});
  ExpectThrowWith<std::invalid_argument>(
      [&] { SolvePose(model, ws, q0, {PoseConstraint::ContactPoint(model, "left_foot", 3, 0.0)}); },
      {"left_foot", "axis 3"});
  ExpectThrowWith<std::invalid_argument>([&] { SolvePose(model, ws, q0, {PoseConstraint::Coordinate(7, 0.0)}); },
                                         {"coordinate 7", "nq = 7"});
  ExpectThrowWith<std::invalid_argument>([&] { SolvePose(model, ws, q0, {PoseConstraint::Com(2, std::nan(""))}); },
                                         {"COM z", "non-finite"});
  ExpectThrowWith<std::invalid_argument>([&] { PoseConstraint::ContactPoint(model, "nose", 0, 0.0); }, {"nose"});
  ExpectThrowWith<std::invalid_argument>(
      [&] { SolvePose(model, ws, q0, {PoseConstraint::Com(0, 0)}, {.max_iterations = 10, .tolerance = 0}); },
      {"tolerance > 0"});
  // Out of reach: the right foot 2 m from the left foot with legs 0.87 m long. Names the robot and a foot.
  ExpectThrowWith<std::runtime_error>([&] { SolvePose(model, ws, q0, AmberSingleSupport(model, 2.0, 0.0)); },
                                      {"amber", "did not converge", "of contact"});
  // The COM 2 m above the ground with both feet on it: the legs are 0.87 m long.
  ExpectThrowWith<std::runtime_error>(
      [&] {
        SolvePose(model, ws, q0,
                  {PoseConstraint::ContactPoint(model, "left_foot", 2, 0.0),
                   PoseConstraint::ContactPoint(model, "right_foot", 2, 0.0), PoseConstraint::Com(2, 2.0),
                   PoseConstraint::Coordinate(2, 0.0)});
      },
      {"did not converge"});
}

}  // namespace
}  // namespace rome
