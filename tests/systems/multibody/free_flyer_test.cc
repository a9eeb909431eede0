// Tests of the quaternion free-flyer base (free_flyer.h): Integrate and Difference invert each other and Integrate is
// the flow of a constant body twist (against Eigen's angle-axis and a quadrature of dp/dt = R(t) v), the loader's
// opt-in, and its one-line refusals. References: closed forms and quadrature written here, not the code under test.
#include "systems/multibody/free_flyer.h"

#include <cmath>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/pose_constraints.h"
#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

using test::DataPath;

MultibodyModel LoadBiped(bool quaternion) {
  LoadOptions options;
  options.quaternion_floating_base = quaternion;
  options.euler_floating_base = !quaternion;
  return MultibodyModel::Load(DataPath("biped3d.urdf"), "", options);
}

Eigen::Quaterniond RandomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
}

// A random configuration: random base rotation (any orientation, pitch up to +-90 deg included), joints +-0.5 rad.
Eigen::VectorXd RandomConfiguration(const MultibodyModel& model, std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd q = model.q_nominal();
  for (int i = 0; i < 3; ++i) q[i] += u(rng);
  const Eigen::Quaterniond R = RandomRotation(rng);
  q.segment<4>(3) << R.w(), R.x(), R.y(), R.z();
  for (int i = 7; i < model.nq(); ++i) q[i] += 0.5 * u(rng);
  return q;
}

Eigen::Quaterniond BaseRotation(const Eigen::VectorXd& q) { return Eigen::Quaterniond(q[3], q[4], q[5], q[6]); }

TEST(FreeFlyerTest, IntegrateAndDifferenceInvertEachOther) {
  const MultibodyModel model = LoadBiped(true);
  ASSERT_EQ(model.nq(), model.nv() + 1);
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd q1(model.nq()), v(model.nv()), v_back(model.nv()), q_back(model.nq());
  // Rotation angles from 1e-9 rad (series branch) through the series threshold to 3 rad (< pi: Log is unique).
  for (const double angle : {1e-9, 1e-5, 0.9e-2, 1.1e-2, 0.3, 1.5, 3.0}) {
    for (int trial = 0; trial < 20; ++trial) {
      const Eigen::VectorXd q0 = RandomConfiguration(model, rng);
      for (int i = 0; i < model.nv(); ++i) v[i] = 2.0 * u(rng);
      v.segment<3>(3) = angle * v.segment<3>(3).normalized();
      model.Integrate(q0, v, 1.0, q1);
      EXPECT_NEAR(BaseRotation(q1).norm(), 1.0, 1e-15);
      model.Difference(q0, q1, v_back);
      EXPECT_LT((v_back - v).cwiseAbs().maxCoeff(), 1e-12) << "angle " << angle;
      // And the other way: q1 reached from q0 by its difference (a quaternion and its negative are one rotation).
      const Eigen::VectorXd q2 = RandomConfiguration(model, rng);
      model.Difference(q0, q2, v_back);
      model.Integrate(q0, v_back, 1.0, q_back);
      const double sign = BaseRotation(q_back).dot(BaseRotation(q2)) < 0.0 ? -1.0 : 1.0;
      EXPECT_LT((q_back.head<3>() - q2.head<3>()).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((sign * q_back.segment<4>(3) - q2.segment<4>(3)).cwiseAbs().maxCoeff(), 1e-12);
      EXPECT_LT((q_back.tail(model.nv() - 6) - q2.tail(model.nv() - 6)).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(FreeFlyerTest, IntegrateIsTheFlowOfAConstantBodyTwist) {
  // R(1) = R0 AngleAxis(|w|, w/|w|) and p(1) = p0 + int_0^1 R0 Exp(t w) v dt (composite Simpson, 2000 intervals).
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 20; ++trial) {
    Vector7d q0;
    const Eigen::Quaterniond R0 = RandomRotation(rng);
    q0 << u(rng), u(rng), u(rng), R0.w(), R0.x(), R0.y(), R0.z();
    FreeFlyerTwist xi;
    for (int i = 0; i < 6; ++i) xi[i] = 2.0 * u(rng);
    const Eigen::Vector3d v = xi.head<3>(), w = xi.tail<3>();
    const Vector7d q1 = FreeFlyerIntegrate(q0, xi);
    auto R_at = [&](double t) {
      return Eigen::Matrix3d(R0.toRotationMatrix() *
                             Eigen::AngleAxisd(t * w.norm(), w.normalized()).toRotationMatrix());
    };
    const Eigen::Matrix3d R1 = Eigen::Quaterniond(q1[3], q1[4], q1[5], q1[6]).toRotationMatrix();
    EXPECT_LT((R1 - R_at(1.0)).cwiseAbs().maxCoeff(), 1e-14);
    const int n = 2000;
    Eigen::Vector3d integral = R_at(0.0) * v + R_at(1.0) * v;
    for (int k = 1; k < n; ++k) integral += (k % 2 ? 4.0 : 2.0) * (R_at(double(k) / n) * v);
    integral /= 3.0 * n;
    EXPECT_LT((q1.head<3>() - q0.head<3>() - integral).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(FreeFlyerTest, MapVelocityToQDotMatchesTheDerivativeOfIntegrate) {
  const MultibodyModel model = LoadBiped(true);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::VectorXd v(model.nv()), qdot(model.nq()), qp(model.nq()), qm(model.nq());
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = RandomConfiguration(model, rng);
    for (int i = 0; i < model.nv(); ++i) v[i] = u(rng);
    model.MapVelocityToQDot(q, v, qdot);
    const double eps = 1e-5;
    model.Integrate(q, v, eps, qp);
    model.Integrate(q, v, -eps, qm);
    EXPECT_LT(((qp - qm) / (2 * eps) - qdot).cwiseAbs().maxCoeff(), 1e-9);
  }
}

TEST(FreeFlyerTest, LoaderOptionsGiveBothBasesAndConvertTheNominalPose) {
  const MultibodyModel euler = LoadBiped(false), quat = LoadBiped(true);
  EXPECT_FALSE(euler.has_quaternion_base());
  EXPECT_EQ(euler.nq(), euler.nv());
  EXPECT_STREQ(euler.base_kind(), "spatial_euler");
  EXPECT_STREQ(quat.base_kind(), "quaternion");
  ASSERT_EQ(quat.nv(), euler.nv());
  EXPECT_EQ(quat.nq(), euler.nq() + 1);
  EXPECT_EQ(quat.VelocityIndex("base_wz"), 5);
  EXPECT_EQ(quat.VelocityIndex("left_knee"), euler.VelocityIndex("left_knee"));
  EXPECT_EQ(quat.PositionIndexOfVelocity(quat.VelocityIndex("left_knee")), euler.VelocityIndex("left_knee") + 1);
  EXPECT_THROW(quat.VelocityIndex("base_yaw"), std::invalid_argument);
  // The Euler nominal base pose [x y z yaw pitch roll] as a quaternion: R = Rz Ry Rx.
  const Eigen::VectorXd& qe = euler.q_nominal();
  const Eigen::Quaterniond R(Eigen::AngleAxisd(qe[3], Eigen::Vector3d::UnitZ()) *
                             Eigen::AngleAxisd(qe[4], Eigen::Vector3d::UnitY()) *
                             Eigen::AngleAxisd(qe[5], Eigen::Vector3d::UnitX()));
  const Eigen::VectorXd& qq = quat.q_nominal();
  EXPECT_LT((qq.head<3>() - qe.head<3>()).norm(), 1e-15);
  EXPECT_NEAR(std::abs(BaseRotation(qq).dot(R)), 1.0, 1e-15);
  EXPECT_EQ(qq.tail(quat.nv() - 6), qe.tail(euler.nv() - 6));
  // The same link poses at the nominal pose (the virtual bodies differ: the Euler chain's sit along the chain).
  MultibodyWorkspace we(euler), wq(quat);
  for (int b = 0; b < euler.num_bodies(); ++b) {
    if (euler.body(b).is_virtual) continue;
    EXPECT_LT((CalcLinkPose(euler, we, qe, b).matrix() - CalcLinkPose(quat, wq, qq, b).matrix()).cwiseAbs().maxCoeff(),
              1e-14);
  }
}

TEST(FreeFlyerTest, SidecarRequestsTheQuaternionBase) {
  const std::string urdf = R"(<robot name="box"><link name="box"><inertial><mass value="2"/>
      <inertia ixx="0.1" iyy="0.2" izz="0.3" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)";
  const MultibodyModel model =
      MultibodyModel::LoadFromText(urdf, R"({"floating_base": "quaternion"})", "box.urdf", "box.rome.json");
  EXPECT_TRUE(model.has_quaternion_base());
  EXPECT_EQ(model.nq(), 7);
  EXPECT_EQ(model.nv(), 6);
  try {
    MultibodyModel::LoadFromText(urdf, R"({"floating_base": "quarternion"})", "box.urdf", "box.rome.json");
    ADD_FAILURE() << "a misspelt base kind loaded";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("box.rome.json"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("expected fixed, planar, spatial, quaternion or spatial_euler"),
              std::string::npos)
        << e.what();
  }
}

// The quaternion base is the default for a spatial base, from a URDF floating joint or a sidecar's "spatial"; the
// Euler base is asked for by the sidecar's "spatial_euler" or LoadOptions::euler_floating_base, and LoadOptions
// override the sidecar.
TEST(FreeFlyerTest, QuaternionIsTheDefaultSpatialBaseAndEulerIsAskedFor) {
  const std::string box = R"(<robot name="box"><link name="box"><inertial><mass value="2"/>
      <inertia ixx="0.1" iyy="0.2" izz="0.3" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)";
  const std::string world = R"(<robot name="box"><link name="world"/>
      <joint name="float" type="floating"><parent link="world"/><child link="box"/></joint>
      <link name="box"><inertial><mass value="2"/>
      <inertia ixx="0.1" iyy="0.2" izz="0.3" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>)";
  auto kind = [](const std::string& urdf, const std::string& sidecar, const LoadOptions& options) {
    const MultibodyModel m = MultibodyModel::LoadFromText(urdf, sidecar, "box.urdf", "box.rome.json", options);
    EXPECT_EQ(m.nq(), m.nv() + (m.has_quaternion_base() ? 1 : 0));
    return std::string(m.base_kind());
  };
  const LoadOptions none{}, euler{.euler_floating_base = true}, quaternion{.quaternion_floating_base = true};
  EXPECT_EQ(kind(world, "", none), "quaternion");
  EXPECT_EQ(kind(box, R"({"floating_base": "spatial"})", none), "quaternion");
  EXPECT_EQ(kind(box, R"({"floating_base": "quaternion"})", none), "quaternion");
  EXPECT_EQ(kind(box, R"({"floating_base": "spatial_euler"})", none), "spatial_euler");
  EXPECT_EQ(kind(world, R"({"floating_base": "spatial_euler"})", none), "spatial_euler");
  EXPECT_EQ(kind(world, "", euler), "spatial_euler");
  EXPECT_EQ(kind(box, R"({"floating_base": "quaternion"})", euler), "spatial_euler");
  EXPECT_EQ(kind(box, R"({"floating_base": "spatial_euler"})", quaternion), "quaternion");
  EXPECT_EQ(kind(box, R"({"floating_base": "planar"})", euler), "planar");  // no effect on a planar base
  EXPECT_EQ(kind(box, "", euler), "fixed");
  EXPECT_EQ(LoadBiped(false).nq(), 18);
  EXPECT_EQ(MultibodyModel::Load(DataPath("biped3d.urdf")).nq(), 19);  // its sidecar says "spatial"
  try {
    kind(box, R"({"floating_base": "spatial"})", {.euler_floating_base = true, .quaternion_floating_base = true});
    ADD_FAILURE() << "both base options were accepted";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("box.urdf: LoadOptions::quaternion_floating_base and LoadOptions::euler_floating_base are "
                        "both set"),
              std::string::npos)
        << what;
  }
}

TEST(FreeFlyerTest, RefusalsNameTheRobotAndTheValue) {
  LoadOptions options;
  options.quaternion_floating_base = true;
  try {
    MultibodyModel::Load(DataPath("walker2d.urdf"), "", options);
    ADD_FAILURE() << "a planar robot loaded with a quaternion base";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("walker2d.urdf"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("planar"), std::string::npos) << e.what();
  }
  const MultibodyModel model = LoadBiped(true);
  MultibodyWorkspace ws(model);
  Eigen::VectorXd q = model.q_nominal(), q_out(model.nq()), v = Eigen::VectorXd::Zero(model.nv());
  q.segment<4>(3).setZero();
  EXPECT_THROW(ws.SetPositions(model, q), std::invalid_argument);
  EXPECT_THROW(model.Integrate(q, v, 0.1, q_out), std::invalid_argument);
  q[3] = std::nan("");
  EXPECT_THROW(model.Integrate(q, v, 0.1, q_out), std::invalid_argument);
  EXPECT_THROW(ws.bullet(), std::logic_error);
  try {
    model.RequireNqEqualsNv("system 'plant'");
    ADD_FAILURE() << "a quaternion model passed RequireNqEqualsNv";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("system 'plant': robot 'biped3d' has a quaternion floating base"), std::string::npos) << what;
    EXPECT_NE(what.find("biped3d.rome.json' with LoadOptions::euler_floating_base"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos);
  }
  EXPECT_NO_THROW(LoadBiped(false).RequireNqEqualsNv("system 'plant'"));
  // The pose solver runs it (pose_constraints_quaternion_test) but refuses a constraint on one quaternion entry.
  EXPECT_THROW(SolvePose(model, ws, model.q_nominal(), {PoseConstraint::Coordinate(3, 0.9)}), std::invalid_argument);
}

}  // namespace
}  // namespace rome
