// DiagramBuilder: every Build() error with its message, evaluation order, and nested == flat.
#include "framework/diagram.h"

#include <gtest/gtest.h>

#include "framework/primitives.h"
#include "framework/simulator.h"

namespace rome {
namespace {

// ẋ = −x + u, y = x (no feedthrough).
class Lag final : public LeafSystem {
 public:
  explicit Lag(std::string name, double x0 = 1.0) : LeafSystem(std::move(name)) {
    DeclareInputPort("u", 1);
    DeclareContinuousState(Eigen::VectorXd::Constant(1, x0));
    DeclareOutputPort(
        "y", 1, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  }
  void DoCalcTimeDerivatives(const LeafContext& c, Eigen::VectorXd* xdot) const override {
    (*xdot)[0] = -c.continuous_state()[0] + EvalInput(c, 0)[0];
  }
};

void ExpectBuildError(DiagramBuilder& b, const std::vector<std::string>& fragments) {
  try {
    b.Build("d");
    FAIL() << "Build() should have thrown";
  } catch (const std::invalid_argument& e) {
    for (const auto& f : fragments)
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos) << "missing '" << f << "' in: " << e.what();
  }
}

TEST(DiagramBuilder, RejectsUnconnectedInput) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<Gain>("gain", 2.0, 3));
  ExpectBuildError(b, {"input port 'u' of system 'gain' is not connected"});
}

TEST(DiagramBuilder, FixedInputCountsAsConnected) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<Gain>("gain", 2.0, 2));
  b.FixInput("gain", "u", Eigen::Vector2d(1, 2));
  b.ExportOutput("gain", "y");
  auto d = b.Build();
  auto ctx = d->CreateDefaultContext();
  EXPECT_EQ(d->EvalOutput(*ctx, "y"), Eigen::VectorXd(Eigen::Vector2d(2, 4)));
}

TEST(DiagramBuilder, RejectsSizeMismatch) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<ConstantVectorSource>("source", Eigen::Vector3d::Zero()));
  b.AddSystem(std::make_unique<Gain>("gain", 2.0, 2));
  b.Connect("source", "y", "gain", "u");
  ExpectBuildError(b, {"size mismatch", "output port 'y' of system 'source' has size 3",
                       "input port 'u' of system 'gain' has size 2"});
}

TEST(DiagramBuilder, RejectsSecondConnection) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<ConstantVectorSource>("a", Eigen::VectorXd::Zero(1)));
  b.AddSystem(std::make_unique<ConstantVectorSource>("b", Eigen::VectorXd::Zero(1)));
  b.AddSystem(std::make_unique<Gain>("gain", 2.0, 1));
  b.Connect("a", "y", "gain", "u");
  b.Connect("b", "y", "gain", "u");
  ExpectBuildError(b, {"input port 'u' of system 'gain' has a second source", "output port 'y' of system 'b'"});
}

TEST(DiagramBuilder, RejectsAlgebraicLoop) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<Gain>("g1", 2.0, 1));
  b.AddSystem(std::make_unique<Gain>("g2", 3.0, 1));
  b.Connect("g1", "y", "g2", "u");
  b.Connect("g2", "y", "g1", "u");
  ExpectBuildError(b, {"algebraic loop", "output 'y' of 'g1'", "output 'y' of 'g2'"});
}

TEST(DiagramBuilder, LoopThroughStateIsNotAlgebraic) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<Lag>("lag"));
  b.AddSystem(std::make_unique<Gain>("k", -2.0, 1));
  b.Connect("lag", "y", "k", "u");
  b.Connect("k", "y", "lag", "u");
  EXPECT_NO_THROW(b.Build());
}

TEST(DiagramBuilder, RejectsUnknownNamesAndDuplicates) {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<Gain>("gain", 2.0, 1));
  EXPECT_THROW(b.AddSystem(std::make_unique<Gain>("gain", 2.0, 1)), std::invalid_argument);
  try {
    b.Connect("gain", "nope", "gain", "u");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("system 'gain' has no output port 'nope'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(b.Connect("missing", "y", "gain", "u"), std::invalid_argument);
}

TEST(DiagramBuilder, EvaluationOrderRespectsFeedthrough) {
  DiagramBuilder b;
  // Added in reverse order on purpose.
  b.AddSystem(std::make_unique<Gain>("last", 5.0, 1));
  b.AddSystem(std::make_unique<Gain>("middle", 3.0, 1));
  b.AddSystem(std::make_unique<ConstantVectorSource>("first", Eigen::VectorXd::Constant(1, 2.0)));
  b.Connect("first", "y", "middle", "u");
  b.Connect("middle", "y", "last", "u");
  b.ExportOutput("last", "y");
  auto d = b.Build();
  const auto& order = d->output_evaluation_order();
  auto pos = [&](const std::string& n) {
    for (size_t i = 0; i < order.size(); ++i)
      if (d->leaf_path(order[i].leaf) == n) return static_cast<int>(i);
    return -1;
  };
  EXPECT_LT(pos("first"), pos("middle"));
  EXPECT_LT(pos("middle"), pos("last"));
  auto ctx = d->CreateDefaultContext();
  EXPECT_DOUBLE_EQ(d->EvalOutput(*ctx, "y")[0], 30.0);
}

// The same closed loop (lag + gain feedback + reference), flat and as nested diagrams.
std::unique_ptr<Diagram> MakeController() {
  DiagramBuilder b;
  b.AddSystem(std::make_unique<Gain>("k", -2.0, 1));
  b.AddSystem(std::make_unique<Adder>("sum", 2, 1));
  b.Connect("k", "y", "sum", "u0");
  b.ExportInput("k", "u", "measurement");
  b.ExportInput("sum", "u1", "reference");
  b.ExportOutput("sum", "sum", "command");
  return b.Build("controller");
}

TEST(DiagramBuilder, NestedDiagramMatchesFlat) {
  // Flat.
  DiagramBuilder fb;
  fb.AddSystem(std::make_unique<Lag>("lag"));
  fb.AddSystem(std::make_unique<Gain>("k", -2.0, 1));
  fb.AddSystem(std::make_unique<Adder>("sum", 2, 1));
  fb.AddSystem(std::make_unique<ConstantVectorSource>("ref", Eigen::VectorXd::Constant(1, 0.5)));
  fb.Connect("lag", "y", "k", "u");
  fb.Connect("k", "y", "sum", "u0");
  fb.Connect("ref", "y", "sum", "u1");
  fb.Connect("sum", "sum", "lag", "u");
  fb.ExportOutput("lag", "y");
  auto flat = fb.Build("flat");
  // Nested twice: (plant + (controller)) inside an outer diagram with the reference outside.
  DiagramBuilder ib;
  ib.AddSystem(std::make_unique<Lag>("lag"));
  ib.AddSystem(MakeController());
  ib.Connect("lag", "y", "controller", "measurement");
  ib.Connect("controller", "command", "lag", "u");
  ib.ExportInput("controller", "reference");
  ib.ExportOutput("lag", "y");
  auto inner = ib.Build("loop");
  DiagramBuilder ob;
  ob.AddSystem(std::make_unique<ConstantVectorSource>("ref", Eigen::VectorXd::Constant(1, 0.5)));
  ob.AddSystem(std::move(inner));
  ob.Connect("ref", "y", "loop", "reference");
  ob.ExportOutput("loop", "y");
  auto nested = ob.Build("outer");
  EXPECT_EQ(nested->num_leaves(), 4);
  EXPECT_NO_THROW(nested->GetLeafIndex("loop/controller/k"));

  Simulator a(*flat), b(*nested);
  for (int k = 1; k <= 20; ++k) {
    ASSERT_TRUE(a.AdvanceTo(0.1 * k).ok());
    ASSERT_TRUE(b.AdvanceTo(0.1 * k).ok());
    EXPECT_EQ(flat->EvalOutput(a.get_context(), "y")[0], nested->EvalOutput(b.get_context(), "y")[0]);
  }
  // Closed form: ẋ = −3x + 0.5 → x(t) = 1/6 + (1 − 1/6) e^{−3t}.
  EXPECT_NEAR(flat->EvalOutput(a.get_context(), "y")[0], 1.0 / 6 + (5.0 / 6) * std::exp(-6.0), 1e-7);
  EXPECT_EQ(a.statistics().steps, b.statistics().steps);
}

// A nested diagram's exported output read from the parent's context, at depth 1 and 2: y = clamp(2 u, -1, 1) by hand.
TEST(DiagramBuilder, EvalSubsystemOutputReadsNestedDiagrams) {
  auto make_inner = [] {
    DiagramBuilder b;
    b.AddSystem(std::make_unique<Gain>("gain", 2.0, 2));
    b.AddSystem(std::make_unique<Saturation>("saturation", 1.0, 2));
    b.Connect("gain", "y", "saturation", "u");
    b.ExportInput("gain", "u");
    b.ExportOutput("saturation", "y", "clamped");
    return b.Build("inner");
  };
  DiagramBuilder mid_builder;
  const Diagram* inner = mid_builder.AddSystem(make_inner(), "inner");
  mid_builder.ExportInput("inner", "u");
  mid_builder.ExportOutput("inner", "clamped");
  DiagramBuilder b;
  const auto* source = b.AddSystem(std::make_unique<ConstantVectorSource>("source", Eigen::Vector2d(0.3, 0.8)));
  const Diagram* mid = b.AddSystem(mid_builder.Build("mid"), "mid");
  b.Connect("source", "y", "mid", "u");
  const auto top = b.Build("top");
  const auto context = top->CreateDefaultContext();
  EXPECT_EQ(top->EvalSubsystemOutput(*mid, "clamped", *context), Eigen::Vector2d(0.6, 1.0));
  EXPECT_EQ(top->EvalSubsystemOutput(*inner, "clamped", *context), Eigen::Vector2d(0.6, 1.0));
  EXPECT_EQ(top->EvalSubsystemOutput(*source, "y", *context), Eigen::Vector2d(0.3, 0.8));
  EXPECT_EQ(top->leaf_path(top->GetLeafIndex(top->leaf(2))), "mid/inner/saturation");
  try {
    top->EvalSubsystemOutput(*mid, "nope", *context);
    FAIL() << "no error";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()), "system 'mid' has no output port 'nope' (it has 'clamped')");
  }
  Gain stranger("stranger", 1.0, 2);
  EXPECT_THROW(top->EvalSubsystemOutput(stranger, "y", *context), std::invalid_argument);
}

TEST(DiagramBuilder, NestedUnconnectedInputIsNamed) {
  DiagramBuilder b;
  b.AddSystem(MakeController());
  b.FixInput("controller", "reference", Eigen::VectorXd::Zero(1));
  ExpectBuildError(b, {"input port 'measurement' of system 'controller' is not connected"});
}

TEST(DiagramBuilder, ExportedInputMustBeFixedBeforeUse) {
  auto d = MakeController();
  auto ctx = d->CreateDefaultContext();
  try {
    d->EvalOutput(*ctx, "command");
    FAIL();
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("is not connected"), std::string::npos) << e.what();
  }
  d->FixInputPort(*ctx, d->GetInputPortIndex("measurement"), Eigen::VectorXd::Constant(1, 1.0));
  d->FixInputPort(*ctx, d->GetInputPortIndex("reference"), Eigen::VectorXd::Constant(1, 0.25));
  EXPECT_DOUBLE_EQ(d->EvalOutput(*ctx, "command")[0], -1.75);
  EXPECT_THROW(d->FixInputPort(*ctx, 0, Eigen::VectorXd::Zero(3)), std::invalid_argument);
}

}  // namespace
}  // namespace rome
