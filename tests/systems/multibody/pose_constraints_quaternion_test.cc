// SolvePose on the quaternion free-flyer base (issue 43): its Newton steps move q by MultibodyModel::Integrate, so the
// base quaternion stays a unit quaternion, and its Jacobian columns are the velocities (the base twist first).
// Independent checks: a solution is evaluated on the ZYX-Euler model of the same files, its base angles read from the
// quaternion in closed form; the rotation is compared with Eigen's AngleAxis; the constraint Jacobian is compared with
// central differences taken on the manifold (q moved by Integrate along each velocity direction).
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/pose_constraints.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

MultibodyModel LoadExoskeleton(bool quaternion) {
  LoadOptions options;
  if (quaternion)
    options.quaternion_floating_base = true;
  else
    options.euler_floating_base = true;
  return MultibodyModel::LoadFromSidecar(rome::test::SourcePath("robots/exoskeleton/exoskeleton.rome.json"), options);
}

Eigen::Vector3d ContactOrigin(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q,
                              const std::string& contact) {
  const ContactInfo& info = model.contacts()[model.ContactIndex(contact)];
  return CalcPointPosition(model, ws, q, info.body, info.frame_origin);
}

// The pelvis origin's height above the left foot's contact frame with the legs straight (the nominal pose).
double StraightLegHeight(const MultibodyModel& model) {
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd& q = model.q_nominal();
  return CalcLinkPose(model, ws, q, model.BodyIndex("pelvis")).translation().z() -
         ContactOrigin(model, ws, q, "left_foot").z();
}

Eigen::Quaterniond BaseQuaternion(const Eigen::VectorXd& q) { return {q[3], q[4], q[5], q[6]}; }

// The Euler model's q for a quaternion model's q: ZYX angles of R = Rz(yaw) Ry(pitch) Rx(roll) in closed form (away
// from pitch ±90°), the joints shifted down by one entry.
Eigen::VectorXd EulerOf(const Eigen::VectorXd& q_quat) {
  const Eigen::Matrix3d R = BaseQuaternion(q_quat).normalized().toRotationMatrix();
  Eigen::VectorXd q(q_quat.size() - 1);
  q.head<3>() = q_quat.head<3>();
  q[3] = std::atan2(R(1, 0), R(0, 0));
  q[4] = std::asin(-R(2, 0));
  q[5] = std::atan2(R(2, 1), R(2, 2));
  q.tail(q.size() - 6) = q_quat.tail(q_quat.size() - 7);
  return q;
}

// The pelvis' pose by points on it: its origin at `origin`, its y axis along world y (the tip (0, 0.3, 0) keeps the
// origin's x and z) and its pitch about y at `pitch` (the point (0.3, 0, 0.3) at height 0.3 (cos pitch − sin pitch)
// above the origin). Each of these coordinates changes at first order with one rotation axis for every pitch in
// [0, 90°], so the request is regular all the way from level to the Euler base's singular 90°.
std::vector<PoseConstraint> PelvisPose(const MultibodyModel& model, const Eigen::Vector3d& origin, double pitch) {
  std::vector<PoseConstraint> pose;
  for (int a = 0; a < 3; ++a)
    pose.push_back(PoseConstraint::Point(model, "pelvis", Eigen::Vector3d::Zero(), a, origin[a]));
  const Eigen::Vector3d y_tip(0, 0.3, 0), diagonal(0.3, 0, 0.3);
  pose.push_back(PoseConstraint::Point(model, "pelvis", y_tip, 0, origin.x()));
  pose.push_back(PoseConstraint::Point(model, "pelvis", y_tip, 2, origin.z()));
  pose.push_back(
      PoseConstraint::Point(model, "pelvis", diagonal, 2, origin.z() + 0.3 * (std::cos(pitch) - std::sin(pitch))));
  return pose;
}

TEST(PoseConstraintsQuaternionTest, StancePoseMeetsItsConstraintsOnTheEulerModelAndKeepsAUnitQuaternion) {
  const MultibodyModel quat = LoadExoskeleton(true), euler = LoadExoskeleton(false);
  ASSERT_EQ(quat.nq(), quat.nv() + 1);
  MultibodyWorkspace ws(quat);
  const Eigen::Vector3d left(0.1, 0.12, 0.0), right(-0.1, -0.12, 0.0);
  const Eigen::Vector3d pelvis(0.0, 0.01, 0.92 * StraightLegHeight(quat));  // knees bent
  std::vector<PoseConstraint> pose = PelvisPose(quat, pelvis, 0.0);
  for (int a = 0; a < 3; ++a) {
    pose.push_back(PoseConstraint::ContactPoint(quat, "left_foot", a, left[a]));
    pose.push_back(PoseConstraint::ContactPoint(quat, "right_foot", a, right[a]));
  }
  const Eigen::VectorXd q = SolvePose(quat, ws, quat.q_nominal(), pose);
  EXPECT_NEAR(BaseQuaternion(q).norm(), 1.0, 1e-12);
  const Eigen::VectorXd qe = EulerOf(q);
  MultibodyWorkspace wse(euler);
  EXPECT_LT((ContactOrigin(euler, wse, qe, "left_foot") - left).norm(), 1e-9);
  EXPECT_LT((ContactOrigin(euler, wse, qe, "right_foot") - right).norm(), 1e-9);
  EXPECT_LT((CalcLinkPose(euler, wse, qe, euler.BodyIndex("pelvis")).translation() - pelvis).norm(), 1e-9);
  EXPECT_LT(qe.segment<3>(3).norm(), 1e-9);  // the pelvis level and facing x
}

// A pitch of 90° is the Euler base's singularity (yaw and roll share an axis); the quaternion base has none there. From
// the upright nominal pose, the Newton iteration turns the pelvis onto its front and reaches the tolerance.
TEST(PoseConstraintsQuaternionTest, PelvisTurnedToNinetyDegreesOfPitchConvergesToTheRotationAboutY) {
  const MultibodyModel quat = LoadExoskeleton(true);
  MultibodyWorkspace ws(quat);
  const Eigen::Vector3d origin(0.2, -0.1, 0.5);
  const Eigen::VectorXd q = SolvePose(quat, ws, quat.q_nominal(), PelvisPose(quat, origin, M_PI / 2),
                                      {.max_iterations = 30, .tolerance = 1e-12});
  EXPECT_NEAR(BaseQuaternion(q).norm(), 1.0, 1e-12);
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  EXPECT_LT((BaseQuaternion(q).normalized().toRotationMatrix() - expected).norm(), 1e-10);
  EXPECT_LT((q.head<3>() - origin).norm(), 1e-10);
  EXPECT_LT((q.tail(quat.nq() - 7) - quat.q_nominal().tail(quat.nq() - 7)).norm(), 1e-12);  // joints not asked
}

// The Jacobian rows (points, COM, the base position's coordinates, a joint coordinate) against central differences on
// the manifold, at a pose with every base angle non-zero.
TEST(PoseConstraintsQuaternionTest, JacobianMatchesDifferencesTakenOnTheManifold) {
  const MultibodyModel quat = LoadExoskeleton(true);
  MultibodyWorkspace ws(quat);
  Eigen::VectorXd q = quat.q_nominal();
  const Eigen::Quaterniond R = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(-0.7, Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX());
  q.head<3>() << 0.1, -0.2, 0.9;
  q.segment<4>(3) << R.w(), R.x(), R.y(), R.z();
  for (int i = 7; i < quat.nq(); ++i) q[i] = 0.05 * (i - 10);
  const int knee = quat.PositionIndexOfVelocity(quat.VelocityIndex("left_knee"));
  const std::vector<PoseConstraint> pose = {
      PoseConstraint::ContactPoint(quat, "left_foot", 0, 0.0),
      PoseConstraint::ContactPoint(quat, "right_foot", 2, 0.0),
      PoseConstraint::Com(1, 0.0),
      PoseConstraint::Point(quat, "pelvis", Eigen::Vector3d(0.1, 0.2, 0.3), 2, 0.0),
      PoseConstraint::Coordinate(0, 0.0),
      PoseConstraint::Coordinate(1, 0.0),
      PoseConstraint::Coordinate(2, 0.0),
      PoseConstraint::Coordinate(knee, 0.0)};
  const Eigen::Index m = static_cast<Eigen::Index>(pose.size());
  Eigen::VectorXd c(m), cp(m), cm(m);
  Eigen::MatrixXd C(m, quat.nv()), unused(m, quat.nv());
  CalcPoseConstraints(quat, ws, q, pose, c, C);
  const double h = 1e-6;
  Eigen::VectorXd qp(quat.nq()), qm(quat.nq());
  for (int j = 0; j < quat.nv(); ++j) {
    const Eigen::VectorXd e = Eigen::VectorXd::Unit(quat.nv(), j);
    quat.Integrate(q, e, h, qp);
    quat.Integrate(q, e, -h, qm);
    CalcPoseConstraints(quat, ws, qp, pose, cp, unused);
    CalcPoseConstraints(quat, ws, qm, pose, cm, unused);
    EXPECT_LT(((cp - cm) / (2 * h) - C.col(j)).cwiseAbs().maxCoeff(), 1e-8) << "velocity column " << j;
  }
}

TEST(PoseConstraintsQuaternionTest, RespectingTheJointLimitsKeepsEveryJointInsideAndReachesTheFoot) {
  const MultibodyModel quat = LoadExoskeleton(true);
  MultibodyWorkspace ws(quat);
  const Eigen::Vector3d left_nominal = ContactOrigin(quat, ws, quat.q_nominal(), "left_foot");
  std::vector<PoseConstraint> pose =
      PelvisPose(quat, Eigen::Vector3d(0.0, 0.0, left_nominal.z() + 0.95 * StraightLegHeight(quat)), 0.0);
  const Eigen::Vector3d foot = left_nominal + Eigen::Vector3d(0.15, 0.0, 0.12);  // the left foot forward and lifted
  for (int a = 0; a < 3; ++a) pose.push_back(PoseConstraint::ContactPoint(quat, "left_foot", a, foot[a]));
  const Eigen::VectorXd q = SolvePose(quat, ws, quat.q_nominal(), pose, {.respect_joint_limits = true});
  EXPECT_NEAR(BaseQuaternion(q).norm(), 1.0, 1e-12);
  for (int i = 7; i < quat.nq(); ++i) {
    EXPECT_GE(q[i], quat.position_lower_limits()[i]) << quat.JointName(i - 1);
    EXPECT_LE(q[i], quat.position_upper_limits()[i]) << quat.JointName(i - 1);
  }
  MultibodyWorkspace fresh(quat);
  EXPECT_LT((ContactOrigin(quat, fresh, q, "left_foot") - foot).norm(), 1e-10);
}

TEST(PoseConstraintsQuaternionTest, AnEntryOfTheBaseQuaternionIsRefusedNamingIt) {
  const MultibodyModel quat = LoadExoskeleton(true);
  MultibodyWorkspace ws(quat);
  try {
    SolvePose(quat, ws, quat.q_nominal(), {PoseConstraint::Coordinate(4, 0.1)});
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("q[4] (base quaternion)"), std::string::npos) << what;
    EXPECT_NE(what.find("constrain the base's orientation by points"), std::string::npos) << what;
  }
}

}  // namespace
}  // namespace rome
