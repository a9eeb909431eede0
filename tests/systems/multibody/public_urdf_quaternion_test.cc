// Public floating-base URDFs load with the quaternion base by default (issue 43), and it is the same robot as the
// Euler base: Atlas v3 (its no-head file) and DRC-Hubo from Debian's dart-doc package (DART's example data, read from
// /usr/share/doc/dart/data; never copied into this repository). Each file is loaded twice as its own floating base:
// once with a URDF "floating" joint out of a "world" link added in front of its root link, once with a sidecar's
// "spatial"; both must be the quaternion free-flyer, and "spatial_euler" the Euler base. Checked on each:
//   * the total mass equals the sum of the file's <mass> values (read here with a regular expression);
//   * at random states (seeds 1-3) mapped between the bases by the map written below (not the loader's), the COM of
//     both models agrees, and so do the kinetic energy 1/2 v^T M v and the COM velocity, which also equals the
//     central difference of the Euler model's COM along q + t qdot.
// Fails, naming the file and the package, when dart-doc is not installed: ./rome setup installs it (a dpkg
// path-exclude of /usr/share/doc would drop the files too).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"

namespace rome {
namespace {

const char* const kDartData = "/usr/share/doc/dart/data/";
// atlas_v3.urdf itself is refused: its neck joint moves a massless head (one line naming neck_ry).
const char* const kFiles[] = {"sdf/atlas/atlas_v3_no_head.urdf", "urdf/drchubo/drchubo.urdf"};

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The <mass value="..."> values outside XML comments (atlas_v3_no_head.urdf keeps the head's link in a comment). Plain
// string scanning: std::regex trips GCC 12's -Wmaybe-uninitialized in the sanitizer build.
double SumOfMasses(const std::string& urdf_with_comments) {
  std::string urdf;
  for (size_t at = 0; at < urdf_with_comments.size();) {
    const size_t open = urdf_with_comments.find("<!--", at);
    urdf += urdf_with_comments.substr(at, open == std::string::npos ? std::string::npos : open - at);
    if (open == std::string::npos) break;
    const size_t close = urdf_with_comments.find("-->", open + 4);
    if (close == std::string::npos) break;
    at = close + 3;
  }
  double sum = 0.0;
  for (size_t at = urdf.find("<mass"); at != std::string::npos; at = urdf.find("<mass", at + 5)) {
    const size_t end = urdf.find('>', at);
    const size_t value = urdf.find("value", at);
    if (value == std::string::npos || value > end) continue;
    const size_t quote = urdf.find_first_of("\"'", value);
    sum += std::stod(urdf.substr(quote + 1, urdf.find(urdf[quote], quote + 1) - quote - 1));
  }
  return sum;
}

// The URDF with <link name="world"/> and a floating joint from it to `root` right after the <robot ...> tag.
std::string WithFloatingJoint(const std::string& urdf, const std::string& root) {
  const size_t robot = urdf.find("<robot");
  const size_t open_end = urdf.find('>', robot);
  return urdf.substr(0, open_end + 1) + "<link name=\"world\"/><joint name=\"world_to_root\" type=\"floating\">" +
         "<parent link=\"world\"/><child link=\"" + root + "\"/></joint>" + urdf.substr(open_end + 1);
}

struct PublicRobot {
  std::string file, urdf;
};

class PublicUrdfQuaternionTest : public ::testing::TestWithParam<const char*> {
 protected:
  void SetUp() override {
    robot_.file = std::string(kDartData) + GetParam();
    if (!std::filesystem::is_regular_file(robot_.file))
      GTEST_FAIL() << "public URDF " << robot_.file << " is absent: install Debian's dart-doc (./rome setup does)";
    robot_.urdf = ReadText(robot_.file);
  }
  PublicRobot robot_;
};

// ZYX Euler base (q = [p, yaw, pitch, roll], qdot) -> free-flyer (q = [p, quaternion w x y z], v = [R^T pdot, w_B]).
void EulerToFreeFlyer(const Eigen::VectorXd& qe, const Eigen::VectorXd& ve, Eigen::VectorXd& qq, Eigen::VectorXd& vq) {
  const int nj = static_cast<int>(qe.size()) - 6;
  const double yaw = qe[3], pitch = qe[4], roll = qe[5];
  const Eigen::Matrix3d Rz = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d Ry = Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Matrix3d Rx = Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()).toRotationMatrix();
  const Eigen::Matrix3d R = Rz * Ry * Rx;
  const Eigen::Quaterniond quat(R);
  qq.resize(qe.size() + 1);
  qq << qe.head<3>(), quat.w(), quat.x(), quat.y(), quat.z(), qe.tail(nj);
  // World angular velocity of R = Rz Ry Rx: yawdot e_z + pitchdot Rz e_y + rolldot Rz Ry e_x.
  const Eigen::Vector3d w_world = ve[3] * Eigen::Vector3d::UnitZ() + ve[4] * (Rz * Eigen::Vector3d::UnitY()) +
                                  ve[5] * (Rz * Ry * Eigen::Vector3d::UnitX());
  vq.resize(ve.size());
  vq << R.transpose() * ve.head<3>(), R.transpose() * w_world, ve.tail(nj);
}

TEST_P(PublicUrdfQuaternionTest, LoadsAsTheQuaternionBaseAndIsTheEulerRobot) {
  const std::string name = std::filesystem::path(robot_.file).filename().string();
  // The root link: the first body of the fixed-base reading (no sidecar, no floating joint).
  const MultibodyModel fixed = MultibodyModel::LoadFromText(robot_.urdf, "", name);
  ASSERT_EQ(fixed.floating_base(), FloatingBaseType::kFixed);
  const std::string root = fixed.body(0).name;
  const MultibodyModel from_joint = MultibodyModel::LoadFromText(WithFloatingJoint(robot_.urdf, root), "", name);
  const MultibodyModel from_sidecar =
      MultibodyModel::LoadFromText(robot_.urdf, R"({"floating_base": "spatial"})", name, "public.rome.json");
  const MultibodyModel euler =
      MultibodyModel::LoadFromText(robot_.urdf, R"({"floating_base": "spatial_euler"})", name, "public.rome.json");
  for (const MultibodyModel* quat : {&from_joint, &from_sidecar}) {
    EXPECT_STREQ(quat->base_kind(), "quaternion") << name;
    EXPECT_EQ(quat->nv(), fixed.nv() + 6) << name;
    EXPECT_EQ(quat->nq(), quat->nv() + 1) << name;
  }
  EXPECT_STREQ(euler.base_kind(), "spatial_euler");
  ASSERT_EQ(euler.nq(), fixed.nv() + 6);
  const double urdf_mass = SumOfMasses(robot_.urdf);
  EXPECT_GT(urdf_mass, 40.0) << name;  // 146.6 kg and 44.0 kg of humanoid
  for (const MultibodyModel* m : {&from_joint, &from_sidecar, &euler})
    EXPECT_NEAR(m->total_mass(), urdf_mass, 1e-9 * urdf_mass) << name;

  MultibodyWorkspace ws_e(euler), ws_j(from_joint), ws_s(from_sidecar);
  for (int seed = 1; seed <= 3; ++seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::VectorXd qe = euler.q_nominal(), ve(euler.nv());
    for (int i = 0; i < euler.nv(); ++i) {
      qe[i] += (i < 6 ? 1.2 : 0.4) * u(rng);  // base angles up to 1.2 rad, joints +-0.4 rad
      ve[i] = u(rng);
    }
    Eigen::VectorXd qq, vq;
    EulerToFreeFlyer(qe, ve, qq, vq);
    const Eigen::Vector3d com_e = CalcComPosition(euler, ws_e, qe);
    const double ke_e = 0.5 * ve.dot(CalcMassMatrix(euler, ws_e, qe) * ve);
    const Eigen::Vector3d vcom_e = CalcComVelocity(euler, ws_e, qe, ve);
    // Independent of both velocity kernels: the central difference of the COM along q + t qdot (Euler: v = qdot).
    const double h = 1e-6;
    const Eigen::VectorXd qp = qe + h * ve, qm = qe - h * ve;
    const Eigen::Vector3d vcom_fd = (CalcComPosition(euler, ws_e, qp) - CalcComPosition(euler, ws_e, qm)) / (2 * h);
    EXPECT_LT((vcom_e - vcom_fd).norm(), 1e-7) << name << " seed " << seed;
    for (auto [quat, ws] : {std::pair<const MultibodyModel*, MultibodyWorkspace*>{&from_joint, &ws_j},
                            std::pair<const MultibodyModel*, MultibodyWorkspace*>{&from_sidecar, &ws_s}}) {
      EXPECT_LT((CalcComPosition(*quat, *ws, qq) - com_e).norm(), 1e-12) << name << " seed " << seed;
      const double ke_q = 0.5 * vq.dot(CalcMassMatrix(*quat, *ws, qq) * vq);
      EXPECT_GT(ke_e, 0.0);
      EXPECT_NEAR(ke_q, ke_e, 1e-10 * ke_e) << name << " seed " << seed;
      EXPECT_LT((CalcComVelocity(*quat, *ws, qq, vq) - vcom_fd).norm(), 1e-7) << name << " seed " << seed;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(DartDoc, PublicUrdfQuaternionTest, ::testing::ValuesIn(kFiles));

}  // namespace
}  // namespace rome
