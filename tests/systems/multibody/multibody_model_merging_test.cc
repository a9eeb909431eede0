// MultibodyModel URDF semantics (issue 18): fixed joints merge links into one rigid body, every
// link stays a named frame, massless frames, inertia checks and repair, singular-M rejection,
// 0-DOF robots. Expected values come from closed forms (solid boxes, parallel-axis theorem) or
// from an equivalent model, never from the loader itself.
#include <cmath>
#include <fstream>
#include <random>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_model.h"
#include "tests/systems/multibody/test_models.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

using test::DataPath;

bool HasWarning(const MultibodyModel& model, const std::string& fragment) {
  for (const auto& w : model.warnings())
    if (w.find(fragment) != std::string::npos) return true;
  return false;
}

std::string LoadError(const std::string& urdf, const LoadOptions& options = {}) {
  try {
    MultibodyModel::Load(urdf, "", options);
  } catch (const std::runtime_error& e) { return e.what(); }
  return "";
}

// URDF <origin rpy>: R = Rz(yaw) Ry(pitch) Rx(roll).
Eigen::Matrix3d Rpy(double r, double p, double y) {
  return (Eigen::AngleAxisd(y, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(p, Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(r, Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Eigen::Matrix3d BoxInertia(double m, double a, double b, double c) {
  return (m / 12.0 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b)).asDiagonal();
}

TEST(MultibodyModelMergingTest, MasslessWorldRoot) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("massless_world_root.urdf"));
  EXPECT_EQ(model.nv(), 1);
  EXPECT_EQ(model.num_bodies(), 2);  // world+base, arm
  EXPECT_EQ(model.frames().size(), 3u);
  EXPECT_EQ(model.BodyIndex("base"), model.BodyIndex("world"));
  EXPECT_NEAR(model.total_mass(), 4.2, 1e-12);
  const MultibodyFrame& base = model.Frame("base");
  EXPECT_LT((base.X_body_frame.translation() - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-15);
  // The base's COM, 0.1 above the base frame, is 0.6 above the world link.
  EXPECT_LT((model.body(base.body).com - Eigen::Vector3d(0, 0, 0.6)).norm(), 1e-15);
  EXPECT_TRUE(HasWarning(model, "link 'world': no <inertial>: massless frame"));
  EXPECT_TRUE(HasWarning(model, "link 'base': merged into body 'world'"));
  // M of the single joint: arm about its pivot, I_yy + m d^2.
  MultibodyWorkspace ws(model);
  const Eigen::MatrixXd M = CalcMassMatrix(model, ws, Eigen::VectorXd::Zero(1));
  EXPECT_NEAR(M(0, 0), 0.03 + 1.2 * 0.25 * 0.25, 1e-14);
}

TEST(MultibodyModelMergingTest, SensorFramesOnFixedJoints) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("sensor_frames.urdf"));
  EXPECT_EQ(model.nv(), 1);
  EXPECT_EQ(model.num_bodies(), 2);
  EXPECT_EQ(model.frames().size(), 5u);
  EXPECT_NEAR(model.total_mass(), 3.0, 1e-15);
  EXPECT_TRUE(HasWarning(model, "link 'imu': no <inertial>: massless frame"));
  EXPECT_TRUE(HasWarning(model, "link 'camera': mass 0: massless frame"));
  EXPECT_TRUE(HasWarning(model, "link 'flange': mass 0: massless frame (its nonzero <inertia> is ignored)"));
  // The arm (rod with a -1e-20 moment) is accepted; merged massless frames leave it unchanged.
  const MultibodyBody& arm = model.body(model.BodyIndex("arm"));
  EXPECT_EQ(arm.mass, 1.0);
  EXPECT_LT((arm.com - Eigen::Vector3d(0, 0, -0.3)).norm(), 1e-15);
  EXPECT_GE(arm.principal_moments.minCoeff(), 0.0);
  EXPECT_EQ(model.BodyIndex("flange"), model.BodyIndex("arm"));
  // Frame poses: world pose of the frame = body pose * fixed offset, checked against the chain.
  MultibodyWorkspace ws(model);
  const double q0 = 0.7;
  const Eigen::VectorXd q = Eigen::VectorXd::Constant(1, q0);
  const Eigen::Isometry3d X_w_arm = CalcLinkPose(model, ws, q, model.BodyIndex("arm"));
  const MultibodyFrame& flange = model.Frame("flange");
  const Eigen::Isometry3d X_w_flange = X_w_arm * flange.X_body_frame;
  Eigen::Isometry3d expected = Eigen::Isometry3d::Identity();
  expected.linear() = Eigen::AngleAxisd(q0, Eigen::Vector3d::UnitY()).toRotationMatrix();
  Eigen::Isometry3d X_arm_camera = Eigen::Isometry3d::Identity();
  X_arm_camera.linear() = Rpy(0, 0.4, 0);
  X_arm_camera.translation() = Eigen::Vector3d(0.02, 0, -0.2);
  Eigen::Isometry3d X_camera_flange = Eigen::Isometry3d::Identity();
  X_camera_flange.translation() = Eigen::Vector3d(0, 0, -0.1);
  expected = expected * X_arm_camera * X_camera_flange;
  EXPECT_LT((X_w_flange.matrix() - expected.matrix()).norm(), 1e-14);
  // The IMU is on the (welded) base.
  EXPECT_EQ(model.Frame("imu").body, model.BodyIndex("base"));
  EXPECT_LT((model.Frame("imu").X_body_frame.translation() - Eigen::Vector3d(0.05, 0, 0.1)).norm(), 1e-15);
}

TEST(MultibodyModelMergingTest, ZeroMassFootContactFrame) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("contact_frame_walker.urdf"));
  EXPECT_EQ(model.nv(), 4);
  const int shin = model.BodyIndex("shin");
  EXPECT_EQ(model.BodyIndex("foot_contact"), shin);
  EXPECT_EQ(model.contacts()[0].link, "foot_contact");
  EXPECT_EQ(model.contacts()[0].body, shin);
  // Contact point (0, 0, -0.02) in foot_contact = (0.01, 0, -0.5) + Ry(0.3) (0, 0, -0.02) in the shin.
  MultibodyWorkspace ws(model);
  std::mt19937 rng(5);
  Eigen::VectorXd q, v;
  test::RandomState(model, rng, q, v);
  const Eigen::Vector3d p_shin = Eigen::Vector3d(0.01, 0, -0.5) + Rpy(0, 0.3, 0) * Eigen::Vector3d(0, 0, -0.02);
  const Eigen::Vector3d expected = CalcLinkPose(model, ws, q, shin) * p_shin;
  EXPECT_LT((CalcContactPointPosition(model, ws, q, 0, 0) - expected).norm(), 1e-14);
  // Loop-closure point on the merged frame, likewise.
  const auto& loop = model.loop_closures()[0];
  EXPECT_EQ(loop.body_b, shin);
  const Eigen::Vector3d pb = Eigen::Vector3d(0.01, 0, -0.5) + Rpy(0, 0.3, 0) * Eigen::Vector3d(0.03, 0, 0);
  EXPECT_LT((loop.point_b - pb).norm(), 1e-15);
  // A task on the merged link uses the same point.
  const MultibodyFrame& f = model.Frame("foot_contact");
  EXPECT_LT((CalcLinkPose(model, ws, q, f.body) * f.X_body_frame * Eigen::Vector3d(0, 0, -0.02) - expected).norm(),
            1e-14);
}

TEST(MultibodyModelMergingTest, MovingJointCarryingOnlyMasslessLinksIsRejected) {
  const std::string what = LoadError(DataPath("massless_moving_link.urdf"));
  EXPECT_NE(what.find("massless_moving_link.urdf"), std::string::npos) << what;
  EXPECT_NE(what.find("joint 'wrist' moves no mass"), std::string::npos) << what;
  EXPECT_NE(what.find("singular"), std::string::npos) << what;
  EXPECT_EQ(what.find("kinematics only"), std::string::npos) << what;
  // A URDF without any <inertial> (a kinematics-only arm description) is told so.
  const std::string path = rome::test::ScratchDir() + "/rome_kinematics_only.urdf";
  std::ofstream(path) << R"(<robot name="k"><link name="a"/><link name="b"/>
    <joint name="j" type="revolute"><parent link="a"/><child link="b"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint></robot>)";
  const std::string kin = LoadError(path);
  EXPECT_NE(kin.find("joint 'j' moves no mass"), std::string::npos) << kin;
  EXPECT_NE(kin.find("no link in this URDF has an <inertial>: it describes kinematics only"), std::string::npos) << kin;
}

TEST(MultibodyModelMergingTest, NonPhysicalInertiaRejectedOrRepaired) {
  const std::string what = LoadError(DataPath("nonphysical_inertia.urdf"));
  EXPECT_NE(what.find("link 'paddle'"), std::string::npos) << what;
  EXPECT_NE(what.find("triangle inequality"), std::string::npos) << what;
  EXPECT_NE(what.find("principal moments 1 1 3"), std::string::npos) << what;
  const MultibodyModel model = MultibodyModel::Load(DataPath("nonphysical_inertia.urdf"), "", {.repair_inertia = true});
  EXPECT_TRUE(HasWarning(model, "link 'paddle': <inertia> violates the triangle inequality"));
  // Nearest point of {I1 + I2 >= I3} to (1, 1, 3): move along the face normal (1, 1, -1) by 1/3.
  const Eigen::Matrix3d expected = Eigen::Vector3d(4.0 / 3.0, 4.0 / 3.0, 8.0 / 3.0).asDiagonal();
  EXPECT_LT((model.body(model.BodyIndex("paddle")).inertia - expected).norm(), 1e-12);
}

// Public robot descriptions put dummy inertias (every entry 1e-6) on frame links welded into
// real bodies; each rigid body the dynamics sees is physical, so the robot loads with a warning.
TEST(MultibodyModelMergingTest, DummyInertiaWeldedIntoAPhysicalBodyIsAccepted) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("welded_dummy_inertia.urdf"));
  EXPECT_EQ(model.nv(), 1);
  EXPECT_TRUE(HasWarning(model, "link 'footprint': <inertia> violates the triangle inequality"));
  EXPECT_TRUE(HasWarning(model, "accepted, because rigid body 'footprint' (its links merged"));
  EXPECT_TRUE(HasWarning(model, "link 'tip': <inertia> violates the triangle inequality"));
  EXPECT_TRUE(HasWarning(model, "accepted, because rigid body 'arm' (its links merged"));
  // The dummy parts are kept, not dropped: closed form of the merged arm body (arm + tip), by the
  // parallel-axis theorem about the combined COM.
  const double m_arm = 1.0, m_tip = 1e-6;
  const Eigen::Vector3d c_arm(0, 0, -0.2), c_tip(0, 0, -0.4);
  const double m = m_arm + m_tip;
  const Eigen::Vector3d c = (m_arm * c_arm + m_tip * c_tip) / m;
  auto shift = [](double mass, const Eigen::Vector3d& d) {
    return Eigen::Matrix3d(mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  const Eigen::Matrix3d I = Eigen::Vector3d(0.01, 0.01, 0.001).asDiagonal().toDenseMatrix() +
                            Eigen::Matrix3d::Constant(1e-6) + shift(m_arm, c_arm - c) + shift(m_tip, c_tip - c);
  const MultibodyBody& arm = model.body(model.BodyIndex("tip"));
  EXPECT_EQ(arm.name, "arm");
  EXPECT_NEAR(arm.mass, m, 1e-15);
  EXPECT_LT((arm.com - c).norm(), 1e-15);
  EXPECT_LT((arm.inertia - I).norm(), 1e-15);
  // Every body is physical: principal moments >= 0 and I1 + I2 >= I3.
  for (const MultibodyBody& b : model.bodies()) {
    const Eigen::Vector3d l = b.principal_moments;
    EXPECT_GE(l.minCoeff(), 0.0) << b.name;
    EXPECT_GE(l.sum() - 2.0 * l.maxCoeff(), -1e-12 * l.maxCoeff()) << b.name;
  }
}

TEST(MultibodyModelMergingTest, NonPhysicalInertiaWeldedIntoANonPhysicalBodyIsRejected) {
  const std::string what = LoadError(DataPath("welded_nonphysical_inertia.urdf"));
  EXPECT_NE(what.find("welded_nonphysical_inertia.urdf: link 'plate': <inertia> violates the triangle inequality"),
            std::string::npos)
      << what;
  EXPECT_NE(what.find("principal moments 1 1 3"), std::string::npos) << what;
  EXPECT_NE(what.find("and so does rigid body 'chassis' (its links merged over fixed joints)"), std::string::npos)
      << what;
  const MultibodyModel model =
      MultibodyModel::Load(DataPath("welded_nonphysical_inertia.urdf"), "", {.repair_inertia = true});
  EXPECT_TRUE(HasWarning(model, "link 'plate': <inertia> violates the triangle inequality"));
  // chassis (0.001 I) + plate repaired to (4/3, 4/3, 8/3), both at the body origin.
  const Eigen::Matrix3d expected =
      Eigen::Vector3d(0.001 + 4.0 / 3.0, 0.001 + 4.0 / 3.0, 0.001 + 8.0 / 3.0).asDiagonal();
  EXPECT_LT((model.body(model.BodyIndex("plate")).inertia - expected).norm(), 1e-12);
}

TEST(MultibodyModelMergingTest, NearlySingularInertiaOfTheIssue) {
  // Principal moments -3.5e-8 against 9e-8: a real violation, not rounding.
  const std::string dir = rome::test::ScratchDir();
  const std::string path = dir + "/rome_negative_moment.urdf";
  std::ofstream(path) << R"(<robot name="r"><link name="a"><inertial><mass value="1"/>
    <inertia ixx="9e-8" ixy="0" ixz="0" iyy="9e-8" iyz="0" izz="-3.5e-8"/></inertial></link></robot>)";
  const std::string what = LoadError(path);
  EXPECT_NE(what.find("link 'a': <inertia> is not positive semi-definite"), std::string::npos) << what;
  EXPECT_NE(what.find("-3.5e-08"), std::string::npos) << what;
  const MultibodyModel model = MultibodyModel::Load(path, "", {.repair_inertia = true});
  EXPECT_GE(model.body(0).principal_moments.minCoeff(), 0.0);
}

TEST(MultibodyModelMergingTest, RoundingNoiseInertiaIsAPointMass) {
  // Principal moments of -5e-20 on a 0.5 kg bob: rounding (a radius of gyration of 3e-10 m), within
  // the absolute floor mass * (1 um)^2. The bob is then a point mass: M = m d^2 about the hinge.
  const MultibodyModel model = MultibodyModel::Load(DataPath("point_mass_rounding_inertia.urdf"));
  ASSERT_EQ(model.nv(), 1);
  EXPECT_GE(model.body(model.BodyIndex("bob")).principal_moments.minCoeff(), 0.0);
  MultibodyWorkspace ws(model);
  for (const double q : {0.0, 0.7, -2.1})
    EXPECT_NEAR(CalcMassMatrix(model, ws, Eigen::VectorXd::Constant(1, q))(0, 0), 0.5 * 0.4 * 0.4, 1e-15);
  // The floor does not hide a real violation at the same mass: moments -1e-9 against 1e-9.
  const std::string path = rome::test::ScratchDir() + "/rome_dust_inertia.urdf";
  std::ofstream(path) << R"(<robot name="r"><link name="a"><inertial><mass value="0.5"/>
    <inertia ixx="1e-9" ixy="0" ixz="0" iyy="1e-9" iyz="0" izz="-1e-9"/></inertial></link></robot>)";
  const std::string what = LoadError(path);
  EXPECT_NE(what.find("link 'a': <inertia> is not positive semi-definite"), std::string::npos) << what;
}

TEST(MultibodyModelMergingTest, TwoWeldedBoxesMatchTheClosedForm) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("two_boxes_welded.urdf"));
  EXPECT_EQ(model.nv(), 2);
  const MultibodyBody& body = model.body(model.BodyIndex("box_a"));
  EXPECT_EQ(model.BodyIndex("box_b"), model.BodyIndex("box_a"));
  const double ma = 3.0, mb = 1.5;
  const Eigen::Vector3d ca(0.1, 0, 0);
  const Eigen::Matrix3d R = Rpy(0.3, -0.2, 0.5);
  const Eigen::Vector3d cb = Eigen::Vector3d(0.3, 0.1, -0.2) + R * Eigen::Vector3d(0.05, 0, -0.1);
  const double m = ma + mb;
  const Eigen::Vector3d c = (ma * ca + mb * cb) / m;
  auto shift = [](double mass, const Eigen::Vector3d& d) {  // parallel-axis term
    return Eigen::Matrix3d(mass * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose()));
  };
  const Eigen::Matrix3d I = BoxInertia(ma, 0.4, 0.2, 0.1) + shift(ma, ca - c) +
                            R * BoxInertia(mb, 0.1, 0.3, 0.2) * R.transpose() + shift(mb, cb - c);
  EXPECT_NEAR(body.mass, m, 1e-12);
  EXPECT_LT((body.com - c).norm(), 1e-12);
  EXPECT_LT((body.inertia - I).norm(), 1e-12);
  EXPECT_LT(
      (body.R_link_principal * body.principal_moments.asDiagonal() * body.R_link_principal.transpose() - I).norm(),
      1e-12);
}

TEST(MultibodyModelMergingTest, MergedMassMatrixEqualsHingedModelHeldAtZero) {
  // two_boxes_hinged.urdf is the same robot with "weld" a revolute joint; holding it at 0 and
  // deleting its row and column must give the merged model's M (and the same bias forces).
  const MultibodyModel welded = MultibodyModel::Load(DataPath("two_boxes_welded.urdf"));
  const MultibodyModel hinged = MultibodyModel::Load(DataPath("two_boxes_hinged.urdf"));
  ASSERT_EQ(welded.nv(), 2);
  ASSERT_EQ(hinged.nv(), 3);
  MultibodyWorkspace ws_w(welded), ws_h(hinged);
  const int hw = hinged.VelocityIndex("weld");
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-2.0, 2.0);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd qw(2), vw(2), qh = Eigen::VectorXd::Zero(3), vh = Eigen::VectorXd::Zero(3);
    for (const char* j : {"hinge", "tip_joint"}) {
      qw[welded.VelocityIndex(j)] = qh[hinged.VelocityIndex(j)] = u(rng);
      vw[welded.VelocityIndex(j)] = vh[hinged.VelocityIndex(j)] = u(rng);
    }
    const Eigen::MatrixXd Mw = CalcMassMatrix(welded, ws_w, qw);
    const Eigen::MatrixXd Mh = CalcMassMatrix(hinged, ws_h, qh);
    const Eigen::VectorXd hw_bias = CalcBiasForces(welded, ws_w, qw, vw);
    const Eigen::VectorXd hh_bias = CalcBiasForces(hinged, ws_h, qh, vh);
    for (const char* a : {"hinge", "tip_joint"}) {
      EXPECT_NEAR(hw_bias[welded.VelocityIndex(a)], hh_bias[hinged.VelocityIndex(a)], 1e-12);
      for (const char* b : {"hinge", "tip_joint"})
        EXPECT_NEAR(Mw(welded.VelocityIndex(a), welded.VelocityIndex(b)),
                    Mh(hinged.VelocityIndex(a), hinged.VelocityIndex(b)), 1e-12)
            << a << " " << b;
    }
    EXPECT_GT(Mh(hw, hw), 0.0);
    // The tip link's pose agrees too (its body's parent chain runs through the merged frame).
    EXPECT_LT((CalcLinkPose(welded, ws_w, qw, welded.BodyIndex("tip")).matrix() -
               CalcLinkPose(hinged, ws_h, qh, hinged.BodyIndex("tip")).matrix())
                  .norm(),
              1e-13);
  }
}

TEST(MultibodyModelMergingTest, RobotsAndTestModelsMatchTheirFixedJointsTurnedRevolute) {
  // For every model with fixed joints, M (fixed base, no sidecar) equals the model whose fixed
  // joints are revolute joints held at 0, with their rows and columns removed.
  int checked = 0;
  for (const std::string& path : test::AllModelUrdfs()) {
    std::ifstream in(path);
    std::string urdf((std::istreambuf_iterator<char>(in)), {});
    if (urdf.find("type=\"fixed\"") == std::string::npos) continue;
    const std::string dir = rome::test::ScratchDir();
    const std::string welded_path = dir + "/rome_welded.urdf", hinged_path = dir + "/rome_hinged.urdf";
    std::ofstream(welded_path) << urdf;
    std::string hinged = urdf;
    for (size_t i = 0; (i = hinged.find("type=\"fixed\">", i)) != std::string::npos;)
      hinged.replace(i, 13, "type=\"continuous\"><axis xyz=\"0 0 1\"/>");
    std::ofstream(hinged_path) << hinged;
    const MultibodyModel w = MultibodyModel::Load(welded_path), h = MultibodyModel::Load(hinged_path);
    MultibodyWorkspace ws_w(w), ws_h(h);
    std::mt19937 rng(2);
    Eigen::VectorXd qw, vw;
    test::RandomState(w, rng, qw, vw);
    Eigen::VectorXd qh = Eigen::VectorXd::Zero(h.nv());
    for (int k = 0; k < w.nv(); ++k) qh[h.VelocityIndex(w.JointName(k))] = qw[k];
    const Eigen::MatrixXd Mw = CalcMassMatrix(w, ws_w, qw), Mh = CalcMassMatrix(h, ws_h, qh);
    double err = 0.0;
    for (int a = 0; a < w.nv(); ++a)
      for (int b = 0; b < w.nv(); ++b)
        err = std::max(err, std::abs(Mw(a, b) - Mh(h.VelocityIndex(w.JointName(a)), h.VelocityIndex(w.JointName(b)))));
    EXPECT_LT(err, 1e-12 * std::max(1.0, Mw.norm())) << path;
    EXPECT_NEAR(w.total_mass(), h.total_mass(), 1e-12) << path;
    ++checked;
  }
  EXPECT_GE(checked, 2);  // biped3d (test model) and cassie_planar
}

TEST(MultibodyModelMergingTest, MasslessIntermediateLinkOfAUniversalJoint) {
  // hip_roll (no <inertial>) only connects two joint axes; M stays regular and Bullet's ABA
  // agrees with the CRBA mass matrix.
  const std::string path = rome::test::ScratchDir() + "/rome_universal.urdf";
  std::ofstream(path) << R"(<robot name="u">
    <link name="base"><inertial><mass value="3"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
    <joint name="roll" type="continuous"><parent link="base"/><child link="hip_roll"/><axis xyz="1 0 0"/></joint>
    <link name="hip_roll"/>
    <joint name="pitch" type="continuous"><parent link="hip_roll"/><child link="leg"/><axis xyz="0 1 0"/></joint>
    <link name="leg"><inertial><origin xyz="0.02 0 -0.3"/><mass value="2"/>
      <inertia ixx="0.06" ixy="0" ixz="0" iyy="0.06" iyz="0" izz="0.004"/></inertial></link></robot>)";
  const MultibodyModel model = MultibodyModel::Load(path);
  ASSERT_EQ(model.nv(), 2);
  MultibodyWorkspace ws(model);
  const Eigen::Vector2d q(0.3, -0.5), v(0.7, -1.1);
  const Eigen::VectorXd u(0);
  Eigen::VectorXd qdd(2);
  CalcForwardDynamics(model, ws, q, v, u, Eigen::VectorXd(), qdd);
  const Eigen::MatrixXd M = CalcMassMatrix(model, ws, q);
  const Eigen::VectorXd h = CalcBiasForces(model, ws, q, v);
  EXPECT_LT((M * qdd + h).norm(), 1e-10);
  EXPECT_GT(M.determinant(), 0.0);
}

TEST(MultibodyModelMergingTest, MasslessFloatingRobotIsRejected) {
  const std::string urdf = rome::test::ScratchDir() + "/rome_ghost.urdf";
  const std::string sidecar = rome::test::ScratchDir() + "/rome_ghost.rome.json";
  std::ofstream(urdf) << R"(<robot name="ghost"><link name="a"/></robot>)";
  std::ofstream(sidecar) << R"({"floating_base": "planar"})";
  try {
    MultibodyModel::Load(urdf, sidecar);
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("joint 'base_x' moves no mass (the whole robot is massless)"),
              std::string::npos)
        << e.what();
  }
}

TEST(MultibodyModelMergingTest, ZeroDofRobot) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("zero_dof.urdf"));
  EXPECT_EQ(model.nv(), 0);
  EXPECT_EQ(model.num_bodies(), 1);
  EXPECT_EQ(model.frames().size(), 3u);
  EXPECT_NEAR(model.total_mass(), 4.5, 1e-15);
  MultibodyWorkspace ws(model);
  const Eigen::VectorXd q(0);
  EXPECT_EQ(CalcMassMatrix(model, ws, q).size(), 0);
  // COM: (4 * 0.05 + 0.5 * 0.3) / 4.5 above the base.
  EXPECT_NEAR(CalcComPosition(model, ws, q).z(), (4.0 * 0.05 + 0.5 * 0.3) / 4.5, 1e-15);
}

}  // namespace
}  // namespace rome
