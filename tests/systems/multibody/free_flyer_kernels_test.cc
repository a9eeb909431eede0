// The quaternion base as one 6-DOF joint (free_flyer_kernels.h). References: the generic path over the six 1-DOF
// virtual joints (an independent implementation, MultibodyWorkspace::SetFreeFlyerAsOneJoint(false)); the whole
// robot's spatial inertia summed body by body from the URDF's mass properties and the link poses; the Newton-Euler
// equations of the robot locked into one rigid body.
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/free_flyer.h"
#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

std::vector<std::string> RobotUrdfs() {
  std::vector<std::string> out = {test::DataPath("biped3d.urdf")};
  for (const std::string name : {"cassie", "exoskeleton"}) {
    const std::string p = test::SourcePath("robots/" + name + "/" + name + ".urdf");
    if (std::filesystem::exists(p)) out.push_back(p);
  }
  return out;
}

MultibodyModel LoadQuaternion(const std::string& urdf) {
  LoadOptions options;
  options.quaternion_floating_base = true;
  return MultibodyModel::Load(urdf, "", options);
}

Eigen::Matrix3d Skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d S;
  S << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return S;
}

// The whole robot as one rigid body, in base axes about the base origin: mass, first moment m c_B and rotational
// inertia I_B = sum R I_c R^T + m (|c|^2 1 - c c^T), each body's pose from CalcLinkPose.
struct CompositeBody {
  double m = 0.0;
  Eigen::Vector3d h = Eigen::Vector3d::Zero();
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
};
CompositeBody SumBodies(const MultibodyModel& model, MultibodyWorkspace& ws, const Eigen::VectorXd& q) {
  const Eigen::Isometry3d X_wb = CalcLinkPose(model, ws, q, model.BodyIndex(model.body(5).name));
  CompositeBody out;
  for (int b = 0; b < model.num_bodies(); ++b) {
    const MultibodyBody& body = model.body(b);
    const Eigen::Isometry3d X = X_wb.inverse() * CalcLinkPose(model, ws, q, b);
    const Eigen::Vector3d c = X * body.com;
    out.m += body.mass;
    out.h += body.mass * c;
    out.I += X.linear() * body.inertia * X.linear().transpose() +
             body.mass * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
  }
  return out;
}

TEST(FreeFlyerKernelsTest, CrbaBaseBlockIsTheWholeRobotsSpatialInertiaInBaseAxes) {
  for (const std::string& urdf : RobotUrdfs()) {
    const MultibodyModel model = LoadQuaternion(urdf);
    MultibodyWorkspace ws(model);
    std::mt19937 rng(1);
    Eigen::VectorXd q, v;
    for (int trial = 0; trial < 10; ++trial) {
      test::RandomState(model, rng, q, v);
      const CompositeBody body = SumBodies(model, ws, q);
      Eigen::Matrix<double, 6, 6> expected;
      expected << body.m * Eigen::Matrix3d::Identity(), -Skew(body.h), Skew(body.h), body.I;
      expected.diagonal() += model.reflected_inertia().head<6>();
      const Eigen::MatrixXd M = CalcMassMatrix(model, ws, q);
      EXPECT_LT((M.topLeftCorner<6, 6>() - expected).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + body.I.norm())) << urdf;
      EXPECT_NEAR(body.m, model.total_mass(), 1e-12 * body.m) << urdf;
    }
  }
}

TEST(FreeFlyerKernelsTest, RneaOfTheLockedRobotIsTheNewtonEulerWrenchOfOneRigidBody) {
  for (const std::string& urdf : RobotUrdfs()) {
    const MultibodyModel model = LoadQuaternion(urdf);
    MultibodyWorkspace ws(model);
    std::mt19937 rng(2);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd q, v, a = Eigen::VectorXd::Zero(model.nv()), tau(model.nv());
    for (int trial = 0; trial < 10; ++trial) {
      test::RandomState(model, rng, q, v);
      v.tail(model.nv() - 6).setZero();  // joints locked: the robot is one rigid body
      for (int i = 0; i < 6; ++i) a[i] = 2.0 * u(rng);
      CalcRnea(model, ws, q, v, a, tau);
      // Body axes, about the base origin: the twist [v; w] and its rate [vd; wd] (v̇ of the body-frame twist). The COM
      // c moves with a_c = vd + w x v + wd x c + w x (w x c); the force is m (a_c - g_B), and the moment about the COM
      // is I_G wd + w x I_G w, I_G = I_B - m (|c|^2 1 - c c^T).
      const CompositeBody body = SumBodies(model, ws, q);
      const Eigen::Vector3d c = body.h / body.m;
      const Eigen::Matrix3d I_G = body.I - body.m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
      const Eigen::Matrix3d R = CalcLinkPose(model, ws, q, 5).linear();
      const Eigen::Vector3d g_B = R.transpose() * model.gravity();
      const Eigen::Vector3d vl = v.head<3>(), w = v.segment<3>(3), vd = a.head<3>(), wd = a.segment<3>(3);
      const Eigen::Vector3d a_c = vd + w.cross(vl) + wd.cross(c) + w.cross(w.cross(c));
      const Eigen::Vector3d f = body.m * (a_c - g_B);
      const Eigen::Vector3d n = I_G * wd + w.cross(I_G * w) + c.cross(f);
      const double scale = body.m * 10.0 * (1.0 + c.norm());
      EXPECT_LT((tau.head<3>() - f).cwiseAbs().maxCoeff(), 1e-12 * scale) << urdf;
      EXPECT_LT((tau.segment<3>(3) - n).cwiseAbs().maxCoeff(), 1e-12 * scale) << urdf;
    }
  }
}

// Every kernel with the base as one joint against the generic path over the six virtual joints, at random states.
TEST(FreeFlyerKernelsTest, OneJointKernelsAgreeWithTheSixJointPath) {
  for (const std::string& urdf : RobotUrdfs()) {
    const MultibodyModel model = LoadQuaternion(urdf);
    const int nv = model.nv();
    MultibodyWorkspace one(model), six(model);
    ASSERT_TRUE(one.free_flyer_as_one_joint());
    six.SetFreeFlyerAsOneJoint(false);
    ASSERT_FALSE(six.free_flyer_as_one_joint());
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd q, v, a(nv), t1(nv), t6(nv), qdd1(nv), qdd6(nv);
    const Eigen::VectorXd act = Eigen::VectorXd::Ones(model.nu());
    Eigen::VectorXd F1(std::max(1, model.max_constraint_rows())), F6 = F1;
    Eigen::MatrixXd J1(6, nv), J6(6, nv), P1(3, nv), P6(3, nv);
    ContactSet all = 0;
    for (int c = 0; c < model.num_contacts(); ++c) all |= ContactBit(c);
    for (int trial = 0; trial < 10; ++trial) {
      test::RandomState(model, rng, q, v);
      for (int i = 0; i < nv; ++i) a[i] = u(rng);
      const Eigen::MatrixXd M1 = CalcMassMatrix(model, one, q), M6 = CalcMassMatrix(model, six, q);
      const double scale = 1.0 + M6.cwiseAbs().maxCoeff();
      EXPECT_LT((M1 - M6).cwiseAbs().maxCoeff(), 1e-12 * scale) << urdf;
      EXPECT_LT((CalcBiasForces(model, one, q, v) - CalcBiasForces(model, six, q, v)).cwiseAbs().maxCoeff(),
                1e-11 * scale)
          << urdf;
      CalcRnea(model, one, q, v, a, t1);
      CalcRnea(model, six, q, v, a, t6);
      EXPECT_LT((t1 - t6).cwiseAbs().maxCoeff(), 1e-11 * scale) << urdf;
      CalcInverseDynamics(model, one, q, v, a, t1);
      CalcInverseDynamics(model, six, q, v, a, t6);
      EXPECT_LT((t1 - t6).cwiseAbs().maxCoeff(), 1e-11 * scale) << urdf;
      const Eigen::Vector3d p(0.1 * u(rng), 0.1 * u(rng), 0.1 * u(rng));
      // Bodies 0..4 are the massless virtual bodies: one joint moves them with the base, six joints only partly.
      for (int body = 5; body < model.num_bodies(); ++body) {
        CalcFrameJacobian(model, one, q, body, p, J1);
        CalcFrameJacobian(model, six, q, body, p, J6);
        EXPECT_LT((J1 - J6).cwiseAbs().maxCoeff(), 1e-13) << urdf << " body " << body;
        CalcPointJacobian(model, one, q, body, p, P1);
        CalcPointJacobian(model, six, q, body, p, P6);
        EXPECT_LT((P1 - P6).cwiseAbs().maxCoeff(), 1e-13) << urdf << " body " << body;
        EXPECT_LT((CalcFrameJdotQdot(model, one, q, v, body, p) - CalcFrameJdotQdot(model, six, q, v, body, p))
                      .cwiseAbs()
                      .maxCoeff(),
                  1e-12)
            << urdf << " body " << body;
      }
      const int rows = CalcConstrainedForwardDynamics(model, one, q, v, act, all, {}, qdd1, F1);
      CalcConstrainedForwardDynamics(model, six, q, v, act, all, {}, qdd6, F6);
      EXPECT_LT((one.J.topRows(rows) - six.J.topRows(rows)).cwiseAbs().maxCoeff(), 1e-13) << urdf;
      EXPECT_LT((qdd1 - qdd6).cwiseAbs().maxCoeff(), 1e-8 * (1.0 + qdd6.cwiseAbs().maxCoeff())) << urdf;
    }
  }
}

}  // namespace
}  // namespace rome
