// LeafSystem: declarations, caching, fixed inputs and the errors that name the system and port.
#include "framework/system.h"

#include <gtest/gtest.h>

namespace rome {
namespace {

class Counted final : public LeafSystem {
 public:
  Counted() : LeafSystem("counted") {
    DeclareInputPort("u", 2);
    DeclareContinuousState(Eigen::Vector3d(1, 2, 3));
    DeclareDiscreteState(Eigen::VectorXd::Constant(1, 7));
    k_ = DeclareNumericParameter("k", Eigen::VectorXd::Constant(1, 4.0));
    DeclareModes({"a", "b"}, 1);
    DeclareOutputPort("y", 2, [this](const LeafContext& c, Eigen::VectorXd* y) {
      ++calls;
      *y = c.numeric_parameter(k_)[0] * EvalInput(c, 0);
    });
    DeclareOutputPort(
        "bad", 3, [](const LeafContext&, Eigen::VectorXd* y) { y->resize(1); }, Feedthrough::None());
  }
  mutable int calls = 0;
  int k_;
};

TEST(LeafSystem, DeclaresEverythingInConstructor) {
  Counted s;
  EXPECT_EQ(s.num_input_ports(), 1);
  EXPECT_EQ(s.num_output_ports(), 2);
  EXPECT_EQ(s.num_continuous_states(), 3);
  EXPECT_EQ(s.num_discrete_states(), 1);
  EXPECT_EQ(s.num_modes(), 2);
  EXPECT_EQ(s.GetModeIndex("b"), 1);
  EXPECT_TRUE(s.HasDirectFeedthrough(0, 0));
  EXPECT_FALSE(s.HasDirectFeedthrough(0, 1));
  auto c = s.CreateDefaultLeafContext();
  EXPECT_EQ(c->mode(), 1);
  EXPECT_EQ(c->continuous_state(), Eigen::VectorXd(Eigen::Vector3d(1, 2, 3)));
  EXPECT_THROW(c->set_mode(2), std::out_of_range);
}

TEST(LeafSystem, OutputsAreCachedUntilTheContextChanges) {
  Counted s;
  auto c = s.CreateDefaultLeafContext();
  c->FixInputPort(0, Eigen::Vector2d(1, -1));
  EXPECT_EQ(s.EvalOutput(*c, 0), Eigen::VectorXd(Eigen::Vector2d(4, -4)));
  s.EvalOutput(*c, 0);
  EXPECT_EQ(s.calls, 1);
  c->get_mutable_numeric_parameter(s.k_)[0] = 2.0;
  EXPECT_EQ(s.EvalOutput(*c, 0), Eigen::VectorXd(Eigen::Vector2d(2, -2)));
  EXPECT_EQ(s.calls, 2);
  c->SetTime(1.0);
  s.EvalOutput(*c, 0);
  EXPECT_EQ(s.calls, 3);
}

TEST(LeafSystem, ErrorsNameSystemAndPort) {
  Counted s;
  auto c = s.CreateDefaultLeafContext();
  try {
    s.EvalOutput(*c, 0);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "input port 'u' of system 'counted' is not connected");
  }
  try {
    c->FixInputPort(0, Eigen::Vector3d::Zero());
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(
        std::string(e.what()).find("input port 'u' of system 'counted' has size 2 but the fixed value has size 3"),
        std::string::npos);
  }
  try {
    s.EvalOutput(*c, 1);
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("output port 'bad' has size 3 but its calculation produced size 1"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(s.GetInputPortIndex("v"), std::invalid_argument);
}

}  // namespace
}  // namespace rome
