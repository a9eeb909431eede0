// SteppingStonesOutputAdapter: Y_d relative to the stance foot → world-frame rows of the controller's task layout.
// Expected values are written out by hand from the layout in the header.
#include "diagrams/stepping_stones/stepping_stones_output_adapter.h"

#include <gtest/gtest.h>

namespace rome {
namespace {

Eigen::VectorXd Desired(int mode) {
  SteppingStonesOutputAdapter adapter;
  auto c = adapter.CreateDefaultLeafContext();
  adapter.FixInputPort(
      *c, 0, Eigen::Vector4d(0.1, 0.8, 0.25, 0.05));  // φ, p_com^z, p_sw^x, p_sw^z relative to the stance foot
  adapter.FixInputPort(*c, 1, Eigen::Vector4d(0.2, -0.1, 1.5, 0.3));   // rates
  adapter.FixInputPort(*c, 2, Eigen::Vector4d(-1.0, 2.0, 3.0, -4.0));  // accelerations
  adapter.FixInputPort(*c, 3, Eigen::Vector2d(2.0, 0.4));              // stance foot in the world
  adapter.FixTypedInputPort(*c, 4, mode);
  return adapter.EvalOutput(*c, "desired");
}

TEST(SteppingStonesOutputAdapter, LeftStanceMovesTheRightFootRowsToTheWorld) {
  Eigen::VectorXd expected(18);
  expected << 0.1, 1.2, 0, 0, 2.25, 0.45,  // positions shifted by the stance foot (2.0, 0.4); right foot swings
      0.2, -0.1, 0, 0, 1.5, 0.3,           // rates unchanged
      -1.0, 2.0, 0, 0, 3.0, -4.0;
  EXPECT_LT((Desired(0) - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(SteppingStonesOutputAdapter, RightStanceMovesTheLeftFootRows) {
  Eigen::VectorXd expected(18);
  expected << 0.1, 1.2, 2.25, 0.45, 0, 0, 0.2, -0.1, 1.5, 0.3, 0, 0, -1.0, 2.0, 3.0, -4.0, 0, 0;
  EXPECT_LT((Desired(1) - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(SteppingStonesOutputAdapter, InFlightNoFootSwings) {
  Eigen::VectorXd expected(18);
  expected << 0.1, 1.2, 0, 0, 0, 0, 0.2, -0.1, 0, 0, 0, 0, -1.0, 2.0, 0, 0, 0, 0;
  EXPECT_LT((Desired(2) - expected).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(SteppingStonesOutputAdapter, PortsAreNamed) {
  SteppingStonesOutputAdapter adapter;
  const PortInfo& out = adapter.output_port(adapter.GetOutputPortIndex("desired"));
  ASSERT_EQ(out.element_names.size(), 18u);
  EXPECT_EQ(out.element_names[1], "com_z");
  EXPECT_EQ(out.element_names[10], "d_right_foot_x");
  EXPECT_FALSE(adapter.input_port(adapter.GetInputPortIndex("mode")).is_vector());
}

TEST(SteppingStonesOutputAdapter, LineFeetAddTheSwingFootPitchRows) {
  SteppingStonesOutputAdapterParams p;
  p.foot_pitch = true;
  p.left_foot_flat_pitch_rad = -0.3;
  p.right_foot_flat_pitch_rad = 0.7;
  SteppingStonesOutputAdapter adapter("output_adapter", p);
  EXPECT_EQ(adapter.num_task_rows(), 8);
  auto c = adapter.CreateDefaultLeafContext();
  adapter.FixInputPort(*c, 0, Eigen::Vector4d(0.1, 0.8, 0.25, 0.05));
  adapter.FixInputPort(*c, 1, Eigen::Vector4d(0.2, -0.1, 1.5, 0.3));
  adapter.FixInputPort(*c, 2, Eigen::Vector4d(-1.0, 2.0, 3.0, -4.0));
  adapter.FixInputPort(*c, 3, Eigen::Vector2d(2.0, 0.4));
  adapter.FixTypedInputPort(*c, 4, 0);  // left stance: the right foot swings and is held at its flat pitch
  Eigen::VectorXd expected(24);
  expected << 0.1, 1.2, 0, 0, 2.25, 0.45, 0, 0.7, 0.2, -0.1, 0, 0, 1.5, 0.3, 0, 0, -1.0, 2.0, 0, 0, 3.0, -4.0, 0, 0;
  EXPECT_LT((adapter.EvalOutput(*c, "desired") - expected).cwiseAbs().maxCoeff(), 1e-15);
  adapter.FixTypedInputPort(*c, 4, 1);
  expected << 0.1, 1.2, 2.25, 0.45, 0, 0, -0.3, 0, 0.2, -0.1, 1.5, 0.3, 0, 0, 0, 0, -1.0, 2.0, 3.0, -4.0, 0, 0, 0, 0;
  EXPECT_LT((adapter.EvalOutput(*c, "desired") - expected).cwiseAbs().maxCoeff(), 1e-15);
  const PortInfo& out = adapter.output_port(adapter.GetOutputPortIndex("desired"));
  ASSERT_EQ(out.element_names.size(), 24u);
  EXPECT_EQ(out.element_names[7], "right_foot_pitch");
  EXPECT_EQ(out.element_names[14], "d_left_foot_pitch");
}

}  // namespace
}  // namespace rome
