// Kinematics against finite differences of Bullet's forward kinematics: point and frame
// Jacobians, Jdot*v, COM Jacobian and its bias, centroidal momentum matrix A_G and Adot_G v.
#include "systems/multibody/multibody_kinematics.h"

#include <random>

#include <gtest/gtest.h>

#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

Eigen::Vector3d RotationLog(const Eigen::Matrix3d& R) {
  Eigen::AngleAxisd aa(R);
  return aa.angle() * aa.axis();
}

class KinematicsTest : public ::testing::TestWithParam<std::string> {};

TEST_P(KinematicsTest, JacobiansMatchFiniteDifferences) {
  const MultibodyModel model = MultibodyModel::Load(GetParam(), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  std::mt19937 rng(7);
  const int n = model.nv();
  const double eps = 1e-6;
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd q, v;
    test::RandomState(model, rng, q, v);
    const Eigen::VectorXd qp = q + eps * v, qm = q - eps * v;
    for (int b = 0; b < model.num_bodies(); ++b) {
      const Eigen::Vector3d p_link(0.03, -0.02, -0.1);
      // Point and frame velocity vs the finite-difference of pose along v.
      const Eigen::Vector3d pp = CalcPointPosition(model, ws, qp, b, p_link);
      const Eigen::Vector3d pm = CalcPointPosition(model, ws, qm, b, p_link);
      const Eigen::Matrix3d Rp = CalcLinkPose(model, ws, qp, b).linear();
      const Eigen::Matrix3d Rm = CalcLinkPose(model, ws, qm, b).linear();
      const Eigen::Vector3d v_fd = (pp - pm) / (2 * eps);
      const Eigen::Vector3d w_fd = RotationLog(Rp * Rm.transpose()) / (2 * eps);
      Eigen::MatrixXd Jf(6, n), J3(3, n);
      CalcFrameJacobian(model, ws, q, b, p_link, Jf);
      CalcPointJacobian(model, ws, q, b, p_link, J3);
      const Vector6d V = CalcFrameVelocity(model, ws, q, v, b, p_link);
      EXPECT_LT((Jf.bottomRows(3) * v - v_fd).norm(), 1e-7);
      EXPECT_LT((Jf.topRows(3) * v - w_fd).norm(), 1e-7);
      EXPECT_LT((J3 - Jf.bottomRows(3)).norm(), 1e-14);
      EXPECT_LT((V - Jf * v).norm(), 1e-12);
      // Jdot v = d/dt(J(q)) v: finite difference of J along v, plus check with the point
      // acceleration d/dt (J v) at constant v.
      Eigen::MatrixXd Jfp(6, n), Jfm(6, n);
      CalcFrameJacobian(model, ws, qp, b, p_link, Jfp);
      CalcFrameJacobian(model, ws, qm, b, p_link, Jfm);
      const Vector6d Jdv_fd = (Jfp - Jfm) / (2 * eps) * v;
      const Vector6d Jdv = CalcFrameJdotQdot(model, ws, q, v, b, p_link);
      EXPECT_LT((Jdv - Jdv_fd).norm(), 1e-6 * std::max(1.0, Jdv.norm())) << "body " << b;
    }
    // COM: position, Jacobian, bias.
    const Eigen::Vector3d c_fd = (CalcComPosition(model, ws, qp) - CalcComPosition(model, ws, qm)) / (2 * eps);
    Eigen::MatrixXd Jc(3, n), Jcp(3, n), Jcm(3, n);
    CalcComJacobian(model, ws, q, Jc);
    EXPECT_LT((Jc * v - c_fd).norm(), 1e-7);
    EXPECT_LT((CalcComVelocity(model, ws, q, v) - Jc * v).norm(), 1e-12);
    CalcComJacobian(model, ws, qp, Jcp);
    CalcComJacobian(model, ws, qm, Jcm);
    EXPECT_LT((CalcComJdotQdot(model, ws, q, v) - (Jcp - Jcm) / (2 * eps) * v).norm(), 1e-6);
    // Centroidal momentum: linear part = m J_com; angular part from link momenta about the
    // COM (finite-difference link velocities); Adot_G v from finite differences of A_G.
    Eigen::MatrixXd AG(6, n), AGp(6, n), AGm(6, n);
    CalcCentroidalMomentumMatrix(model, ws, q, AG);
    EXPECT_LT((AG.bottomRows(3) - model.total_mass() * Jc).norm(), 1e-10);
    const Eigen::Vector3d com = CalcComPosition(model, ws, q);
    Eigen::Vector3d k_ref = Eigen::Vector3d::Zero();
    for (int b = 0; b < model.num_bodies(); ++b) {
      const MultibodyBody& body = model.body(b);
      if (body.mass == 0.0) continue;
      ws.SetPositions(model, qp);
      const Eigen::Vector3d cp = ws.com_world(b);
      const Eigen::Matrix3d Rp2 = ws.R_world_link(b);
      ws.SetPositions(model, qm);
      const Eigen::Vector3d cm = ws.com_world(b);
      const Eigen::Matrix3d Rm2 = ws.R_world_link(b);
      ws.SetPositions(model, q);
      const Eigen::Matrix3d R = ws.R_world_link(b);
      const Eigen::Vector3d w = RotationLog(Rp2 * Rm2.transpose()) / (2 * eps);
      k_ref += (ws.com_world(b) - com).cross(body.mass * (cp - cm) / (2 * eps)) + R * body.inertia * R.transpose() * w;
    }
    EXPECT_LT((AG.topRows(3) * v - k_ref).norm(), 1e-6 * std::max(1.0, k_ref.norm()));
    EXPECT_LT((CalcCentroidalMomentum(model, ws, q, v) - AG * v).norm(), 1e-10);
    CalcCentroidalMomentumMatrix(model, ws, qp, AGp);
    CalcCentroidalMomentumMatrix(model, ws, qm, AGm);
    const Vector6d bias_fd = (AGp - AGm) / (2 * eps) * v;
    EXPECT_LT((CalcCentroidalMomentumBias(model, ws, q, v) - bias_fd).norm(), 1e-6 * std::max(1.0, bias_fd.norm()));
  }
}

INSTANTIATE_TEST_SUITE_P(AllModels, KinematicsTest, ::testing::ValuesIn(test::AllModelUrdfs()),
                         [](const ::testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param.substr(info.param.find_last_of('/') + 1);
                           return name.substr(0, name.find('.'));
                         });

TEST(MultibodyKinematicsTest, SpatialBaseCoordinatesAreZyxEuler) {
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("biped3d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.nq());
  q.head<6>() << 0.1, -0.2, 0.9, 0.3, -0.4, 0.5;
  const Eigen::Isometry3d X = CalcLinkPose(model, ws, q, model.BodyIndex("pelvis"));
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  EXPECT_LT((X.linear() - R).norm(), 1e-14);
  EXPECT_LT((X.translation() - Eigen::Vector3d(0.1, -0.2, 0.9)).norm(), 1e-14);
  // Child joint origin: left hip yaw at (0, 0.1, -0.05) in the pelvis frame.
  const Eigen::Isometry3d Xh = CalcLinkPose(model, ws, q, model.BodyIndex("left_hip_yaw_link"));
  EXPECT_LT((Xh.translation() - (X * Eigen::Vector3d(0, 0.1, -0.05))).norm(), 1e-14);
}

TEST(MultibodyKinematicsTest, RejectsBadSizesAndIndices) {
  const MultibodyModel model = MultibodyModel::Load(test::DataPath("walker2d.urdf"), "", {.euler_floating_base = true});
  MultibodyWorkspace ws(model);
  Eigen::VectorXd q = model.q_nominal();
  Eigen::MatrixXd J(3, model.nv() + 1);
  EXPECT_THROW(CalcPointJacobian(model, ws, q, 0, Eigen::Vector3d::Zero(), J), std::invalid_argument);
  EXPECT_THROW(CalcPointPosition(model, ws, q, 99, Eigen::Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(CalcComPosition(model, ws, Eigen::VectorXd::Zero(2)), std::invalid_argument);
}

}  // namespace
}  // namespace rome
