// MultibodyModel: a URDF "floating" (or "planar") joint out of a massless world root link is the
// robot's floating base (issue 18). The expected values come from the same robot written without the
// world link and given its floating base by the sidecar (a path of the loader that does not look at
// floating joints), from the closed form of M's translational block (total mass times identity),
// and from the joint's <origin> (the nominal base pose).
#include <cmath>
#include <cstdio>
#include <random>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {
namespace {

// A small legged robot (our own numbers): a torso with a full inertia, an IMU frame welded to it,
// a leg on an oblique revolute hip, a prismatic shin and an arm on a continuous shoulder.
const char* kRobotLinks = R"(
  <link name="torso">
    <inertial><origin xyz="0.02 -0.01 0.05" rpy="0.1 0.2 0.3"/><mass value="5.0"/>
      <inertia ixx="0.11" ixy="0.004" ixz="-0.003" iyy="0.09" iyz="0.002" izz="0.07"/></inertial>
  </link>
  <joint name="imu_joint" type="fixed">
    <parent link="torso"/><child link="imu"/><origin xyz="0.05 0 0.1" rpy="0 0 0.4"/>
  </joint>
  <link name="imu">
    <inertial><mass value="0.05"/><inertia ixx="1e-5" ixy="0" ixz="0" iyy="1e-5" iyz="0" izz="1e-5"/></inertial>
  </link>
  <joint name="hip" type="revolute">
    <parent link="torso"/><child link="thigh"/><origin xyz="0 0.1 -0.15" rpy="0 0 0"/>
    <axis xyz="0.2 1 0.1"/><limit lower="-2" upper="2" effort="50" velocity="10"/>
  </joint>
  <link name="thigh">
    <inertial><origin xyz="0 0 -0.2"/><mass value="1.2"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.02" iyz="0" izz="0.003"/></inertial>
  </link>
  <joint name="knee" type="prismatic">
    <parent link="thigh"/><child link="shin"/><origin xyz="0 0 -0.4"/>
    <axis xyz="0 0 1"/><limit lower="-0.1" upper="0.1" effort="200" velocity="1"/>
  </joint>
  <link name="shin">
    <inertial><origin xyz="0 0 -0.2"/><mass value="0.8"/>
      <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.001"/></inertial>
  </link>
  <joint name="shoulder" type="continuous">
    <parent link="torso"/><child link="arm"/><origin xyz="0 -0.2 0.2" rpy="0.5 0 0"/><axis xyz="1 0 0"/>
  </joint>
  <link name="arm">
    <inertial><origin xyz="0 0 -0.15"/><mass value="0.7"/>
      <inertia ixx="0.006" ixy="0" ixz="0" iyy="0.006" iyz="0" izz="0.0008"/></inertial>
  </link>
)";

std::string Robot(const std::string& head) { return "<robot name=\"walker\">" + head + kRobotLinks + "</robot>"; }

// The same robot with every joint in the x-z plane (hip and shoulder about y), as a planar base requires.
std::string PlanarRobot(const std::string& head) {
  std::string urdf = Robot(head);
  for (const auto& [from, to] :
       {std::pair<std::string, std::string>{R"(<axis xyz="0.2 1 0.1"/>)", R"(<axis xyz="0 1 0"/>)"},
        {R"(rpy="0.5 0 0"/><axis xyz="1 0 0"/>)", R"(rpy="0 0 0"/><axis xyz="0 1 0"/>)"}})
    urdf.replace(urdf.find(from), from.size(), to);
  return urdf;
}

std::string WorldJoint(const std::string& type, const std::string& origin, const std::string& extra = "") {
  return "<link name=\"world\"/><joint name=\"root_joint\" type=\"" + type +
         "\"><parent link=\"world\"/><child link=\"torso\"/>" + origin + extra + "</joint>";
}

std::string LoadError(const std::string& urdf, const std::string& sidecar = "") {
  try {
    MultibodyModel::LoadFromText(urdf, sidecar, "walker.urdf", "walker.rome.json");
  } catch (const std::runtime_error& e) { return e.what(); }
  return "";
}

// M of the two models at the same q (same coordinate order: base, then the URDF joints).
void ExpectSameMassMatrix(const MultibodyModel& a, const MultibodyModel& b, double total_mass, int translations) {
  ASSERT_EQ(a.nv(), b.nv());
  ASSERT_EQ(a.joint_names(), b.joint_names());
  MultibodyWorkspace wa(a), wb(b);
  for (int seed = 1; seed <= 10; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.2, 1.2);
    Eigen::VectorXd q(a.nv());
    for (int i = 0; i < a.nv(); ++i) q[i] = u(rng);
    const Eigen::MatrixXd Ma = CalcMassMatrix(a, wa, q);
    const Eigen::MatrixXd Mb = CalcMassMatrix(b, wb, q);
    EXPECT_LT((Ma - Mb).cwiseAbs().maxCoeff(), 1e-12) << "seed " << seed;
    // Closed form: base translations along world axes see the total mass, uncoupled.
    EXPECT_LT((Ma.topLeftCorner(translations, translations) -
               total_mass * Eigen::MatrixXd::Identity(translations, translations))
                  .cwiseAbs()
                  .maxCoeff(),
              1e-12)
        << "seed " << seed;
  }
}

TEST(MultibodyModelFloatingJointTest, FloatingJointFromWorldIsTheSpatialBase) {
  // Euler coordinates here, so that both models take the same random q.
  const MultibodyModel with_world = MultibodyModel::LoadFromText(
      Robot(WorldJoint("floating", "")), "", "walker_world.urdf", "", {.euler_floating_base = true});
  const MultibodyModel without_world = MultibodyModel::LoadFromText(
      Robot(""), R"({"floating_base": "spatial"})", "walker.urdf", "walker.rome.json", {.euler_floating_base = true});
  EXPECT_EQ(with_world.floating_base(), FloatingBaseType::kSpatial);
  // By default the floating joint is the quaternion free-flyer: one more position coordinate than velocities.
  const MultibodyModel by_default =
      MultibodyModel::LoadFromText(Robot(WorldJoint("floating", "")), "", "walker_world.urdf");
  EXPECT_STREQ(by_default.base_kind(), "quaternion");
  EXPECT_EQ(by_default.nv(), 6 + 3);
  EXPECT_EQ(by_default.nq(), 7 + 3);
  EXPECT_EQ(with_world.nv(), 6 + 3);
  EXPECT_FALSE(with_world.HasFrame("world"));
  EXPECT_TRUE(with_world.HasFrame("imu"));
  EXPECT_EQ(with_world.num_bodies(), without_world.num_bodies());
  EXPECT_NEAR(with_world.total_mass(), 5.0 + 0.05 + 1.2 + 0.8 + 0.7, 1e-12);
  bool warned = false;
  for (const auto& w : with_world.warnings())
    warned |= w.find("link 'world': massless root of floating joint 'root_joint'") != std::string::npos;
  EXPECT_TRUE(warned);
  ExpectSameMassMatrix(with_world, without_world, 7.75, 3);
}

TEST(MultibodyModelFloatingJointTest, FloatingJointOriginIsTheNominalBasePose) {
  const MultibodyModel model =
      MultibodyModel::LoadFromText(Robot(WorldJoint("floating", R"(<origin xyz="0.1 -0.2 0.9" rpy="0.3 -0.2 0.5"/>)")),
                                   "", "walker_world.urdf", "", {.euler_floating_base = true});
  const Eigen::VectorXd& q = model.q_nominal();
  ASSERT_EQ(q.size(), 9);
  // URDF rpy (roll, pitch, yaw) = (0.3, -0.2, 0.5); ROME's base is [x, y, z, yaw, pitch, roll].
  Eigen::VectorXd expected(6);
  expected << 0.1, -0.2, 0.9, 0.5, -0.2, 0.3;
  EXPECT_LT((q.head(6) - expected).cwiseAbs().maxCoeff(), 1e-14);
  // At the nominal pose the torso sits where the URDF's <origin> puts it.
  MultibodyWorkspace ws(model);
  const Eigen::Isometry3d X = CalcLinkPose(model, ws, q, model.BodyIndex("torso"));
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.2, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  EXPECT_LT((X.translation() - Eigen::Vector3d(0.1, -0.2, 0.9)).norm(), 1e-14);
  EXPECT_LT((X.linear() - R).norm(), 1e-14);
  // The default quaternion base puts the torso at the same pose: q = [p; quaternion of R].
  const MultibodyModel quat = MultibodyModel::LoadFromText(
      Robot(WorldJoint("floating", R"(<origin xyz="0.1 -0.2 0.9" rpy="0.3 -0.2 0.5"/>)")), "", "walker_world.urdf");
  ASSERT_EQ(quat.q_nominal().size(), 10);
  const Eigen::Quaterniond quat_R(R);
  EXPECT_LT((quat.q_nominal().head(3) - Eigen::Vector3d(0.1, -0.2, 0.9)).norm(), 1e-14);
  EXPECT_LT(std::abs(std::abs(quat.q_nominal().segment<4>(3).dot(
                         Eigen::Vector4d(quat_R.w(), quat_R.x(), quat_R.y(), quat_R.z()))) -
                     1.0),
            1e-14);
  MultibodyWorkspace ws_quat(quat);
  const Eigen::Isometry3d X_quat = CalcLinkPose(quat, ws_quat, quat.q_nominal(), quat.BodyIndex("torso"));
  EXPECT_LT((X_quat.matrix() - X.matrix()).cwiseAbs().maxCoeff(), 1e-14);
  // A sidecar nominal base overrides it.
  const MultibodyModel overridden =
      MultibodyModel::LoadFromText(Robot(WorldJoint("floating", R"(<origin xyz="0.1 -0.2 0.9" rpy="0.3 -0.2 0.5"/>)")),
                                   R"({"nominal_pose": {"base": [0, 0, 1, 0, 0, 0]}})", "walker_world.urdf",
                                   "walker_world.rome.json", {.euler_floating_base = true});
  EXPECT_EQ(overridden.q_nominal()[2], 1.0);
  EXPECT_EQ(overridden.q_nominal()[3], 0.0);
}

TEST(MultibodyModelFloatingJointTest, PlanarJointFromWorldIsThePlanarBase) {
  const MultibodyModel with_world = MultibodyModel::LoadFromText(
      PlanarRobot(WorldJoint("planar", R"(<origin xyz="0.3 0 1.1" rpy="0 0.2 0"/>)", R"(<axis xyz="0 1 0"/>)")), "",
      "walker_world.urdf");
  const MultibodyModel without_world = MultibodyModel::LoadFromText(PlanarRobot(""), R"({"floating_base": "planar"})",
                                                                    "walker.urdf", "walker.rome.json");
  EXPECT_EQ(with_world.floating_base(), FloatingBaseType::kPlanar);
  EXPECT_LT((with_world.q_nominal().head(3) - Eigen::Vector3d(0.3, 1.1, 0.2)).cwiseAbs().maxCoeff(), 1e-14);
  ExpectSameMassMatrix(with_world, without_world, 7.75, 2);
}

// A planar base with a joint that leaves the x-z plane (the oblique hip) is refused, naming the joint and its axis.
TEST(MultibodyModelFloatingJointTest, APlanarRobotsJointsMustStayInThePlane) {
  const std::string e = LoadError(Robot(""), R"({"floating_base": "planar"})");
  EXPECT_NE(e.find("joint 'hip' turns about world axis"), std::string::npos) << e;
  const Eigen::Vector3d oblique = Eigen::Vector3d(0.2, 1, 0.1).normalized();  // the hip's <axis>, unit length
  char expected[64];
  std::snprintf(expected, sizeof(expected), "%.6g %.6g %.6g", oblique.x(), oblique.y(), oblique.z());
  EXPECT_NE(e.find(expected), std::string::npos) << e;
  EXPECT_NO_THROW(MultibodyModel::LoadFromText(PlanarRobot(""), R"({"floating_base": "planar"})", "walker.urdf",
                                               "walker.rome.json"));
}

TEST(MultibodyModelFloatingJointTest, UnsupportedPlacementsAreRejectedNamingTheJoint) {
  // A floating joint out of a root link that has mass.
  std::string e = LoadError(R"(<robot name="w"><link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      <joint name="loose" type="floating"><parent link="a"/><child link="b"/></joint>
      <link name="b"><inertial><mass value="1"/><inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link>
      </robot>)");
  EXPECT_NE(e.find("URDF walker.urdf: floating joint 'loose': its parent, root link 'a', has mass 1 kg"),
            std::string::npos)
      << e;
  // A second floating joint inside a robot with a world root: that joint is named.
  std::string urdf = Robot(WorldJoint("floating", ""));
  urdf.replace(urdf.find("type=\"continuous\""), 17, "type=\"floating\"");
  e = LoadError(urdf);
  EXPECT_NE(e.find("floating joint 'shoulder' between links 'torso' and 'arm' is not supported"), std::string::npos)
      << e;
  // A planar joint whose plane is not the world x-z plane.
  e = LoadError(Robot(WorldJoint("planar", "", R"(<axis xyz="1 0 0"/>)")));
  EXPECT_NE(e.find("planar joint 'root_joint': <axis> 1 0 0 is not supported"), std::string::npos) << e;
  // A world root with a second joint.
  e = LoadError(Robot(
      WorldJoint("floating", "") +
      R"(<joint name="cam" type="fixed"><parent link="world"/><child link="camera"/></joint><link name="camera"/>)"));
  EXPECT_NE(e.find("floating joint 'root_joint': root link 'world' has 2 joints"), std::string::npos) << e;
  // A sidecar that says otherwise.
  e = LoadError(Robot(WorldJoint("floating", "")), R"({"floating_base": "fixed"})");
  EXPECT_NE(e.find("sidecar walker.rome.json: floating_base: 'fixed' contradicts URDF walker.urdf"), std::string::npos)
      << e;
  // One line each.
  EXPECT_EQ(e.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace rome
