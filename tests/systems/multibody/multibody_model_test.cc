// MultibodyModel loading: structure of the loaded tree, sidecar contents, and one test per
// malformed-input case (each error must name the file, the element and the problem).
#include "systems/multibody/multibody_model.h"
#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_workspace.h"

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

#include <gtest/gtest.h>

#include "tests/systems/multibody/test_models.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

using test::DataPath;

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

class ModelFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::path(rome::test::ScratchDir()) /
           ("rome_mb_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(dir_);
    urdf_ = ReadText(DataPath("walker2d.urdf"));
    sidecar_ = ReadText(DataPath("walker2d.rome.json"));
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }
  // Writes walker2d.urdf / walker2d.rome.json (possibly edited) and returns the URDF path.
  std::string Write(const std::string& urdf, const std::string& sidecar) {
    std::ofstream(dir_ / "walker2d.urdf") << urdf;
    std::ofstream(dir_ / "walker2d.rome.json") << sidecar;
    return (dir_ / "walker2d.urdf").string();
  }
  static std::string Replace(std::string s, const std::string& from, const std::string& to) {
    const size_t i = s.find(from);
    EXPECT_NE(i, std::string::npos) << from;
    if (i != std::string::npos) s.replace(i, from.size(), to);
    return s;
  }
  // Expects a std::runtime_error whose message contains every fragment.
  static void ExpectError(const std::string& urdf_path, std::initializer_list<std::string> fragments) {
    try {
      MultibodyModel::Load(urdf_path);
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      const std::string what = e.what();
      for (const auto& f : fragments) EXPECT_NE(what.find(f), std::string::npos) << "'" << f << "' not in: " << what;
    }
  }
  std::filesystem::path dir_;
  std::string urdf_, sidecar_;
};

TEST(MultibodyModelTest, LoadsPlanarWalker) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("walker2d.urdf"));
  EXPECT_EQ(model.name(), "walker2d");
  EXPECT_EQ(model.floating_base(), FloatingBaseType::kPlanar);
  EXPECT_EQ(model.nq(), 5);
  EXPECT_EQ(model.nv(), 5);
  EXPECT_EQ(model.nu(), 2);
  EXPECT_EQ(model.JointName(0), "base_x");
  EXPECT_EQ(model.JointName(1), "base_z");
  EXPECT_EQ(model.JointName(2), "base_pitch");
  EXPECT_NEAR(model.total_mass(), 12.0, 1e-12);
  const int lh = model.VelocityIndex("left_hip");
  EXPECT_EQ(model.B()(lh, 0), 1.0);
  EXPECT_EQ(model.B().sum(), 2.0);
  EXPECT_NEAR(model.reflected_inertia()[lh], 0.05, 1e-15);
  EXPECT_NEAR(model.torque_limits()[0], 80.0, 1e-15);
  EXPECT_NEAR(model.q_nominal()[1], 0.98, 1e-15);
  EXPECT_NEAR(model.q_nominal()[lh], 0.2, 1e-15);
  EXPECT_EQ(model.num_contacts(), 2);
  EXPECT_EQ(model.contacts()[0].num_rows, 2);
  EXPECT_EQ(model.max_constraint_rows(), 4);
  EXPECT_NEAR(model.position_lower_limits()[lh], -1.5, 1e-15);
  EXPECT_THROW(model.VelocityIndex("nope"), std::invalid_argument);
  EXPECT_THROW(model.BodyIndex("nope"), std::invalid_argument);
}

TEST(MultibodyModelTest, PrincipalFrameReproducesInertia) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("biped3d.urdf"));
  EXPECT_EQ(model.nv(), 18);
  EXPECT_EQ(model.contacts()[0].num_rows, 6);
  EXPECT_EQ(model.contacts()[1].num_rows, 5);
  EXPECT_EQ(model.contacts()[2].num_rows, 3);
  for (const auto& b : model.bodies()) {
    const Eigen::Matrix3d I = b.R_link_principal * b.principal_moments.asDiagonal() * b.R_link_principal.transpose();
    EXPECT_LT((I - b.inertia).norm(), 1e-14) << b.name;
    EXPECT_NEAR(b.R_link_principal.determinant(), 1.0, 1e-12);
  }
  // A fixed-joint link is merged into its parent's body and stays addressable as a frame.
  EXPECT_EQ(model.BodyIndex("left_toe_cap"), model.BodyIndex("left_foot"));
  EXPECT_EQ(model.Frame("left_toe_cap").body, model.BodyIndex("left_foot"));
  EXPECT_LT((model.Frame("left_toe_cap").X_body_frame.translation() - Eigen::Vector3d(0.1, 0, -0.05)).norm(), 1e-15);
  EXPECT_EQ(model.contacts()[2].body, model.BodyIndex("left_foot"));
  EXPECT_LT((model.contacts()[2].points[0] - Eigen::Vector3d(0.12, 0, -0.05)).norm(), 1e-15);
}

TEST(MultibodyModelTest, NoSidecarMeansFixedBase) {
  const MultibodyModel model = MultibodyModel::Load(DataPath("double_pendulum.urdf"));
  EXPECT_EQ(model.floating_base(), FloatingBaseType::kFixed);
  EXPECT_EQ(model.nv(), 2);
  EXPECT_EQ(model.nu(), 0);
}

TEST(MultibodyModelTest, LoadFromSidecarResolvesUrdf) {
  const MultibodyModel model = MultibodyModel::LoadFromSidecar(DataPath("walker2d.rome.json"));
  EXPECT_EQ(model.nv(), 5);
}

TEST_F(ModelFiles, MissingUrdfFile) {
  ExpectError((dir_ / "nothere.urdf").string(), {"nothere.urdf", "does not exist"});
}

TEST_F(ModelFiles, MissingSidecarFileGivenExplicitly) {
  const std::string path = Write(urdf_, sidecar_);
  try {
    MultibodyModel::Load(path, (dir_ / "missing.rome.json").string());
    ADD_FAILURE();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("missing.rome.json: file does not exist"), std::string::npos) << e.what();
  }
}

TEST_F(ModelFiles, MalformedXml) {
  ExpectError(Write(Replace(urdf_, "</robot>", "</robo>"), sidecar_), {"walker2d.urdf", "malformed"});
}

TEST_F(ModelFiles, MissingInertia) {
  // left_leg without <inertial> is a massless frame: the only thing left_hip moves, so M is
  // singular and the joint is named ...
  const std::string bad = ReadText(DataPath("bad_missing_inertia.urdf"));
  ExpectError(Write(bad, Replace(sidecar_, R"("reflected_inertia_kgm2": 0.05)", R"("reflected_inertia_kgm2": 0.0)")),
              {"walker2d.urdf", "joint 'left_hip' moves no mass", "link 'left_leg'"});
  // ... unless the sidecar gives that joint a reflected (rotor) inertia.
  const MultibodyModel model = MultibodyModel::Load(Write(bad, sidecar_));
  EXPECT_NEAR(model.body(model.BodyIndex("left_leg")).mass, 0.0, 0.0);
}

TEST_F(ModelFiles, NonPositiveDefiniteInertia) {
  ExpectError(
      Write(Replace(urdf_, R"(ixx="0.4" ixy="0" ixz="0" iyy="0.4")", R"(ixx="0.4" ixy="0.9" ixz="0" iyy="0.4")"),
            sidecar_),
      {"walker2d.urdf", "link 'left_leg'", "not positive semi-definite"});
}

TEST_F(ModelFiles, NonPositiveMass) {
  ExpectError(Write(Replace(urdf_, R"(<mass value="2.0"/>)", R"(<mass value="-2.0"/>)"), sidecar_),
              {"link 'hip'", "mass"});
}

TEST_F(ModelFiles, MalformedJson) {
  ExpectError(Write(urdf_, Replace(sidecar_, "\"robot\": \"walker2d\",", "\"robot\": \"walker2d\"")),
              {"walker2d.rome.json", "malformed JSON"});
}

TEST_F(ModelFiles, SidecarNamesUnknownJoint) {
  ExpectError(Write(urdf_, Replace(sidecar_, R"({"joint": "right_hip")", R"({"joint": "right_knee")")),
              {"walker2d.rome.json", "actuators[1]", "joint 'right_knee' does not exist"});
}

TEST_F(ModelFiles, SidecarNamesUnknownLink) {
  ExpectError(Write(urdf_, Replace(sidecar_, R"("link": "right_leg")", R"("link": "right_shin")")),
              {"walker2d.rome.json", "contacts[1] ('right_foot')", "link 'right_shin' does not exist"});
}

TEST_F(ModelFiles, BadContactType) {
  ExpectError(
      Write(urdf_, Replace(sidecar_, R"("type": "point", "points": [[0.0, 0.0, -1.0]], "friction_coefficient": 0.8},)",
                           R"("type": "sphere", "points": [[0.0, 0.0, -1.0]], "friction_coefficient": 0.8},)")),
      {"walker2d.rome.json", "contacts[0] ('left_foot')", "unknown contact type 'sphere'"});
}

TEST_F(ModelFiles, LoopClosureNamesUnknownLink) {
  const std::string loops =
      R"("loop_closures": [{"name": "rod", "link_a": "hip", "point_a": [0,0,0], "link_b": "tail", "point_b": [0,0,0], "distance_m": 0.5}],
  "nominal_pose")";
  ExpectError(Write(urdf_, Replace(sidecar_, "\"nominal_pose\"", loops)),
              {"walker2d.rome.json", "loop_closures[0] ('rod') link_b", "link 'tail' does not exist"});
}

TEST_F(ModelFiles, BadFloatingBaseAndNominalPose) {
  ExpectError(Write(urdf_, Replace(sidecar_, R"("planar")", R"("hovering")")),
              {"floating_base", "unknown type 'hovering'"});
  ExpectError(Write(urdf_, Replace(sidecar_, R"("base": [0.0, 0.98, 0.0])", R"("base": [0.0, 0.98])")),
              {"nominal_pose.base", "expected 3 numbers"});
}

TEST_F(ModelFiles, WrongValueType) {
  ExpectError(Write(urdf_, Replace(sidecar_, R"("torque_limit_Nm": 80.0}
  ],)",
                                   R"("torque_limit_Nm": "lots"}
  ],)")),
              {"actuators[1]", "'torque_limit_Nm' must be a number"});
}

// LoadFromText (the fuzz harness's entry) reads the same robot as Load from the files: the same coordinates, the same
// mass, and the same mass matrix at the nominal pose, computed from the file-loaded model's workspace.
TEST(LoadFromText, SameRobotAsFromTheFiles) {
  for (const std::string robot : {"amber", "cassie"}) {
    const std::string urdf = rome::test::SourcePath("robots/" + robot + "/" + robot + ".urdf");
    const std::string sidecar = rome::test::SourcePath("robots/" + robot + "/" + robot + ".rome.json");
    const MultibodyModel from_files = MultibodyModel::Load(urdf, sidecar);
    const MultibodyModel from_text = MultibodyModel::LoadFromText(ReadText(urdf), ReadText(sidecar));
    ASSERT_EQ(from_text.nv(), from_files.nv()) << robot;
    EXPECT_EQ(from_text.joint_names(), from_files.joint_names()) << robot;
    EXPECT_EQ(from_text.num_contacts(), from_files.num_contacts()) << robot;
    EXPECT_EQ(from_text.nu(), from_files.nu()) << robot;
    EXPECT_DOUBLE_EQ(from_text.total_mass(), from_files.total_mass()) << robot;
    EXPECT_EQ(from_text.q_nominal(), from_files.q_nominal()) << robot;
    MultibodyWorkspace ws_text(from_text), ws_files(from_files);
    const Eigen::MatrixXd M_text = CalcMassMatrix(from_text, ws_text, from_text.q_nominal());
    const Eigen::MatrixXd M_files = CalcMassMatrix(from_files, ws_files, from_files.q_nominal());
    EXPECT_TRUE(M_text.isApprox(M_files, 1e-14)) << robot;
  }
  // No sidecar text: a fixed-base model with no actuators, and no file is looked for next to the "URDF".
  const std::string amber_urdf = ReadText(rome::test::SourcePath("robots/amber/amber.urdf"));
  const MultibodyModel fixed = MultibodyModel::LoadFromText(amber_urdf, "");
  EXPECT_EQ(fixed.floating_base(), FloatingBaseType::kFixed);
  EXPECT_EQ(fixed.nu(), 0);
}

TEST(LoadFromText, ErrorsNameTheGivenNamesAndTheSizeCapHolds) {
  auto error_of = [](const std::string& urdf, const std::string& sidecar) {
    try {
      MultibodyModel::LoadFromText(urdf, sidecar, "given.urdf", "given.rome.json");
    } catch (const std::runtime_error& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  const std::string amber_urdf = ReadText(rome::test::SourcePath("robots/amber/amber.urdf"));
  EXPECT_NE(error_of("<robot", "").find("URDF given.urdf: malformed"), std::string::npos) << error_of("<robot", "");
  EXPECT_NE(error_of(amber_urdf, "{").find("sidecar given.rome.json: malformed JSON"), std::string::npos);
  const std::string big(kMaxUrdfBytes + 1, ' ');
  EXPECT_NE(error_of(big, "").find("URDF given.urdf: text is " + std::to_string(kMaxUrdfBytes + 1) + " bytes"),
            std::string::npos);
  EXPECT_NE(error_of(amber_urdf, big).find("sidecar given.rome.json: text is"), std::string::npos);
}

// The fuzzer's finding: a truncated 4-byte UTF-8 sequence followed by a NUL inside an attribute made TinyXML (under
// urdfdom) read past the buffer. Every URDF that is not UTF-8 text is refused before the XML parser sees it, naming
// the line and the byte; a valid multi-byte name still loads.
TEST(LoadFromText, UrdfThatIsNotUtf8TextIsRefusedBeforeParsing) {
  auto error_of = [](const std::string& urdf) {
    try {
      MultibodyModel::LoadFromText(urdf, "", "given.urdf", "");
    } catch (const std::runtime_error& e) { return std::string(e.what()); }
    return std::string("no error");
  };
  const std::string head =
      "<robot name=\"r\">\n<link name=\"base\"/>\n<joint name=\"j\" type=\"revolute\"><limit lower=\"ca";
  const std::string truncated = head + std::string("\xF3\0u", 3);
  EXPECT_NE(error_of(truncated).find("URDF given.urdf: line 3: byte 0xF3 at offset"), std::string::npos)
      << error_of(truncated);
  const std::string nul = head + std::string("\0\"/></joint></robot>", 14);
  EXPECT_NE(error_of(nul).find("is a NUL byte"), std::string::npos) << error_of(nul);
  const std::string latin1 = "<robot name=\"r\xE9\"><link name=\"base\"/></robot>";
  EXPECT_NE(error_of(latin1).find("line 1: byte 0xE9"), std::string::npos) << error_of(latin1);
  EXPECT_EQ(error_of("<robot name=\"r\xC3\xA9\"><link name=\"base\"/></robot>"), "no error");
}

}  // namespace
}  // namespace rome
