// MultibodyModel on hostile input (issue 15, loader classes): one test per class. Each bad file
// must give a std::runtime_error naming the file, the element and the value, on one short
// printable line; nothing may crash, hang or be silently accepted.
#include <chrono>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_model.h"
#include "tests/common/source_path.h"
#include "tests/systems/multibody/test_models.h"

namespace rome {
namespace {

using test::DataPath;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class BadInput : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(rome::test::ScratchDir()) /
           ("rome_bad_input_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
    urdf_ = ReadText(DataPath("walker2d.urdf"));
    sidecar_ = ReadText(DataPath("walker2d.rome.json"));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  std::string Write(const std::string& urdf, const std::string& sidecar) {
    std::ofstream(dir_ / "walker2d.urdf", std::ios::binary) << urdf;
    std::ofstream(dir_ / "walker2d.rome.json", std::ios::binary) << sidecar;
    return (dir_ / "walker2d.urdf").string();
  }
  std::string WriteUrdfOnly(const std::string& name, const std::string& urdf) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << urdf;
    return path;
  }
  static std::string Replace(std::string s, const std::string& from, const std::string& to) {
    const size_t i = s.find(from);
    EXPECT_NE(i, std::string::npos) << from;
    if (i != std::string::npos) s.replace(i, from.size(), to);
    return s;
  }
  // The error must contain every fragment, be one line, short and printable.
  static std::string ExpectError(const std::string& urdf_path, std::initializer_list<std::string> fragments) {
    try {
      MultibodyModel::Load(urdf_path);
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      for (const auto& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
      EXPECT_LT(what.size(), 1000u);
      for (char c : what) EXPECT_GE(static_cast<unsigned char>(c), 0x20u) << what;
      return what;
    }
    return "";
  }
  // A chain of n links joined by joints of the given type.
  static std::string Chain(int n, const std::string& type) {
    std::string s = "<robot name=\"chain\">\n";
    for (int i = 0; i <= n; ++i) {
      s += "<link name=\"l" + std::to_string(i) +
           "\"><inertial><mass value=\"1\"/><origin xyz=\"0 0 -0.05\"/>"
           "<inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" iyz=\"0\" izz=\"0.01\"/></inertial></link>\n";
      if (i > 0)
        s += "<joint name=\"j" + std::to_string(i) + "\" type=\"" + type + "\"><parent link=\"l" +
             std::to_string(i - 1) + "\"/><child link=\"l" + std::to_string(i) +
             "\"/><origin xyz=\"0 0 -0.1\"/><axis xyz=\"0 1 0\"/></joint>\n";
    }
    return s + "</robot>\n";
  }
  std::filesystem::path dir_;
  std::string urdf_, sidecar_;
};

// ---- crashes ----

TEST_F(BadInput, ZeroDofModelsLoadAndComputeDynamics) {
  const std::string one_link = WriteUrdfOnly("one.urdf", R"(<robot name="one"><link name="a"><inertial><mass value="1"/>
      <inertia ixx="1" ixy="0" ixz="0" iyy="1" iyz="0" izz="1"/></inertial></link></robot>)");
  for (const std::string& path : {one_link, DataPath("zero_dof.urdf")}) {
    const MultibodyModel model = MultibodyModel::Load(path);
    EXPECT_EQ(model.nv(), 0);
    MultibodyWorkspace ws(model);
    const Eigen::VectorXd q(0), v(0);
    EXPECT_EQ(CalcMassMatrix(model, ws, q).rows(), 0);
    EXPECT_EQ(CalcBiasForces(model, ws, q, v).size(), 0);
  }
}

TEST_F(BadInput, TenThousandLinkChainDoesNotOverflowTheStack) {
  // All fixed: one merged body (0 DOF) built by the iterative walk.
  const MultibodyModel welded = MultibodyModel::Load(WriteUrdfOnly("welded.urdf", Chain(10000, "fixed")));
  EXPECT_EQ(welded.nv(), 0);
  EXPECT_EQ(welded.num_bodies(), 1);
  EXPECT_EQ(welded.frames().size(), 10001u);
  EXPECT_NEAR(welded.total_mass(), 10001.0, 1e-9);
  // Moving joints: beyond the model-size cap, a clear error.
  ExpectError(WriteUrdfOnly("moving.urdf", Chain(10000, "continuous")),
              {"moving.urdf", "more than 1000 degrees of freedom", "joint 'j1001'"});
}

TEST_F(BadInput, DeeplyNestedXmlIsRejectedBeforeParsing) {
  std::string deep = "<robot name=\"deep\">";
  for (int i = 0; i < 200000; ++i) deep += "<a>";
  for (int i = 0; i < 200000; ++i) deep += "</a>";
  deep += "</robot>";
  ExpectError(WriteUrdfOnly("deep.urdf", deep), {"deep.urdf", "line 1", "nested more than 64 deep"});
  // Oversized file.
  std::string big = "<robot name=\"big\"><link name=\"a\"/><!--" + std::string(17u << 20, 'x') + "--></robot>";
  ExpectError(WriteUrdfOnly("big.urdf", big), {"big.urdf", "bytes; the limit is 16777216 bytes"});
  // A directory is not a file.
  ExpectError(dir_.string(), {"is a directory"});
}

// ---- unbounded work ----

TEST_F(BadInput, ModelSizeIsCapped) {
  // 1000 moving joints is the documented cap and loads (the loader must not be quadratic).
  const auto t0 = std::chrono::steady_clock::now();
  const MultibodyModel model = MultibodyModel::Load(WriteUrdfOnly("ok.urdf", Chain(kMaxDofs, "continuous")));
  EXPECT_EQ(model.nv(), kMaxDofs);
  (void)t0;
  ExpectError(WriteUrdfOnly("too_big.urdf", Chain(kMaxDofs + 1, "continuous")), {"more than 1000 degrees of freedom"});
}

// ---- silent wrong answers ----

TEST_F(BadInput, InertiaTriangleInequalityAndNaN) {
  // izz > ixx + iyy: positive definite, but no rigid body has it.
  ExpectError(Write(Replace(urdf_, R"(ixx="0.4" ixy="0" ixz="0" iyy="0.4" iyz="0" izz="0.01")",
                            R"(ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.3")"),
                    sidecar_),
              {"walker2d.urdf", "link 'left_leg'", "triangle inequality", "principal moments 0.1 0.1 0.3"});
  // urdfdom cannot parse "nan" (it would leave zeros): the error names the NaN and its line.
  ExpectError(Write(Replace(urdf_, R"(ixx="0.4" ixy="0" ixz="0" iyy="0.4")", R"(ixx="nan" ixy="0" ixz="0" iyy="0.4")"),
                    sidecar_),
              {"walker2d.urdf", "ixx is not a valid double", "line 16: NaN in <inertia ixx=\"nan\""});
  ExpectError(Write(Replace(urdf_, R"(<mass value="2.0"/>)", R"(<mass value="NaN"/>)"), sidecar_),
              {"walker2d.urdf", "line 6: NaN in <mass value=\"NaN\"/>"});
}

TEST_F(BadInput, JointLimits) {
  ExpectError(Write(Replace(urdf_, R"(lower="-1.5" upper="1.5")", R"(lower="1.5" upper="-1.5")"), sidecar_),
              {"walker2d.urdf", "joint 'left_hip'", "lower 1.5 must not exceed upper -1.5"});
  // lower == upper: documented as "no position limit", with a warning.
  const MultibodyModel model =
      MultibodyModel::Load(Write(Replace(urdf_, R"(lower="-1.5" upper="1.5")", R"(lower="0" upper="0")"), sidecar_));
  const int k = model.VelocityIndex("left_hip");
  EXPECT_EQ(model.position_lower_limits()[k], -std::numeric_limits<double>::infinity());
  bool warned = false;
  for (const auto& w : model.warnings())
    warned |= w.find("joint 'left_hip': <limit> lower == upper (0)") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST_F(BadInput, TorqueLimits) {
  // No torque_limit_Nm in the sidecar: the URDF effort (80) is used ...
  const std::string no_sidecar_limit = Replace(sidecar_, R"(, "torque_limit_Nm": 80.0},
    {"joint": "right_hip")",
                                               R"(},
    {"joint": "right_hip")");
  const MultibodyModel model = MultibodyModel::Load(Write(urdf_, no_sidecar_limit));
  EXPECT_EQ(model.torque_limits()[0], 80.0);
  // ... a missing or negative effort is an error, never +inf.
  ExpectError(Write(Replace(urdf_, R"(effort="80")", R"(effort="-5")"), no_sidecar_limit),
              {"walker2d.rome.json", "actuators[0] (joint 'left_hip')", "no torque limit", "-5"});
  ExpectError(Write(Replace(urdf_, R"(effort="80")", R"(effort="0")"), no_sidecar_limit),
              {"actuators[0] (joint 'left_hip')", "no torque limit"});
  ExpectError(Write(urdf_, Replace(sidecar_, R"("torque_limit_Nm": 80.0},
    {"joint": "right_hip")",
                                   R"("torque_limit_Nm": -3},
    {"joint": "right_hip")")),
              {"actuators[0] (joint 'left_hip')", "torque_limit_Nm must be positive, got -3"});
}

TEST_F(BadInput, UnknownSidecarKeysSuggestTheNearestKey) {
  ExpectError(Write(urdf_, Replace(sidecar_, R"("contacts")", R"("contactz")")),
              {"walker2d.rome.json", "top level", "unknown key 'contactz'", "did you mean 'contacts'"});
  ExpectError(Write(urdf_, Replace(sidecar_, R"("torque_limit_Nm": 80.0},
    {"joint": "right_hip")",
                                   R"("torque_limit_nm": 80.0},
    {"joint": "right_hip")")),
              {"actuators[0]", "unknown key 'torque_limit_nm'", "did you mean 'torque_limit_Nm'"});
  ExpectError(Write(urdf_, Replace(sidecar_, R"("friction_coefficient": 0.8},)", R"("friction": 0.8},)")),
              {"contacts[0] ('left_foot')", "unknown key 'friction'"});
  ExpectError(Write(urdf_, Replace(sidecar_, R"("joints": {)", R"("joint": {)")),
              {"nominal_pose", "unknown key 'joint'", "did you mean 'joints'"});
}

TEST_F(BadInput, DuplicateSpringIsRejected) {
  const std::string springs =
      R"("springs": [{"joint": "left_hip", "stiffness_Nm_per_rad": 100}, {"joint": "left_hip", "stiffness_Nm_per_rad": 200}],
  "contacts")";
  ExpectError(Write(urdf_, Replace(sidecar_, "\"contacts\"", springs)),
              {"walker2d.rome.json", "springs[1] (joint 'left_hip')", "second spring"});
}

TEST_F(BadInput, AbsurdMagnitudesAreRejected) {
  ExpectError(Write(urdf_, Replace(sidecar_, "[[0.0, 0.0, -1.0]], \"friction_coefficient\": 0.8},",
                                   "[[0.0, 0.0, -1e308]], \"friction_coefficient\": 0.8},")),
              {"walker2d.rome.json", "contacts[0] ('left_foot') points", "-1e+308", "exceed 1000 m"});
  ExpectError(Write(urdf_, Replace(sidecar_, "[[0.0, 0.0, -1.0]], \"friction_coefficient\": 0.8},",
                                   "[[0.0, 0.0, -1e400]], \"friction_coefficient\": 0.8},")),
              {"walker2d.rome.json", "number overflow parsing '-1e400'"});
  // COM at 1e308 in the URDF.
  ExpectError(Write(Replace(urdf_, R"(<origin xyz="0 0 0.05"/><mass value="2.0"/>)",
                            R"(<origin xyz="0 0 1e308"/><mass value="2.0"/>)"),
                    sidecar_),
              {"walker2d.urdf", "link 'hip'", "<inertial> <origin xyz> 0 0 1e+308 m exceeds 1000 m"});
  // A joint origin, too.
  ExpectError(Write(Replace(urdf_, R"(<origin xyz="0 0.1 0"/>)", R"(<origin xyz="1e9 0.1 0"/>)"), sidecar_),
              {"walker2d.urdf", "joint 'left_hip'", "<origin> 1e+09 0.1 0 m", "exceeds 1000 m"});
}

// ---- misleading errors ----

TEST_F(BadInput, NonUtf8NamesGiveAClearError) {
  std::string urdf = urdf_;
  for (size_t i = 0; (i = urdf.find("\"left_leg\"", i)) != std::string::npos;)
    urdf.replace(i, 10, "\"left_\xff\xfeleg\"");
  ExpectError(Write(urdf, Replace(sidecar_, R"("link": "left_leg")", R"("link": "right_leg")")),
              {"walker2d.urdf", "line 10: byte 0xFF at offset", "is not valid UTF-8"});
  // Invalid UTF-8 in the sidecar: the JSON parser's error, escaped.
  ExpectError(Write(urdf_, Replace(sidecar_, R"("robot": "walker2d")", "\"robot\": \"walker\xff\"")),
              {"walker2d.rome.json", "malformed JSON"});
}

TEST_F(BadInput, HugeOrBinaryValuesAreTruncatedAndEscaped) {
  const std::string huge(10u << 20, 'q');
  const std::string what =
      ExpectError(Write(urdf_, Replace(sidecar_, R"({"joint": "right_hip")", "{\"joint\": \"" + huge + "\"")),
                  {"walker2d.rome.json", "actuators[1]", "does not exist", "(10485760 bytes)"});
  EXPECT_LT(what.size(), 700u);
  ExpectError(Write(urdf_, Replace(sidecar_, R"({"joint": "right_hip")", R"({"joint": "ri\u0001\u001bght")")),
              {"actuators[1]", "joint 'ri\\x01\\x1Bght'"});
}

}  // namespace
}  // namespace rome
