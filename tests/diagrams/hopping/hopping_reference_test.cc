// HoppingReference's GRF feedback in Jump (HoppingReferenceParams::jump_force_feedback, jump_force_integral_per_s,
// jump_force_correction_max_m), on the block alone with fixed inputs (standing Cassie, plant mode "jump", a fixed
// measured ground force) and a hand-made jump plan of constant force F_plan and stiffness n K. Expected values in
// closed form: e = (F_plan − F) / (n K), w = 1 (the plan's force does not fall), and after m periodic updates in Jump
// the leg-length target is L_plan + k_F e + m T k_I e (the integral and the sum each clamped to ±c_max); with F =
// F_plan it is L_plan. A plan without force while the feedback is on fails the jump with a message naming the block.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>

#include "framework/simulator.h"
#include "diagrams/hopping/hopping_reference.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kFPlan = 500.0, kStiffness = 2.0e4, kLPlan = 0.85, kSettle = 0.01, kT = 5e-4;

struct ReferenceRun {
  double L_d = NAN, Ldot_d = NAN;
  SimulatorStatus status;
};

// Standing Cassie, the reference told the plant is in "jump" with total normal force `F` [N] (half per foot), `until`
// [s] simulated; the jump starts at kSettle.
ReferenceRun RunReference(double F, double k_F, double k_I, double c_max, double until, bool plan_has_force = true) {
  auto model = std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
      rome::test::SourcePath("robots/cassie/cassie.rome.json"), {.euler_floating_base = true}));
  auto leg_length = [](double q, double* L, double* dL) { *L = 0.9 - 0.2 * q, *dL = -0.2; };  // any smooth L(q_knee)
  auto jump = [plan_has_force](const RomState&, LegLengthPlan* plan, std::string*) {
    plan->t = Eigen::Vector3d(0.0, 0.1, 0.2);
    plan->L = Eigen::Vector3d::Constant(kLPlan);
    plan->Ldot = Eigen::Vector3d::Zero();
    if (plan_has_force) {
      plan->force = Eigen::Vector3d::Constant(kFPlan);
      plan->stiffness = Eigen::Vector3d::Constant(kStiffness);
    }
    return true;
  };
  HoppingReferenceParams params;
  params.update_period_s = kT;
  params.settle_time_s = kSettle;
  params.jump_momentum_gain = 0.0;
  params.jump_force_feedback = k_F;
  params.jump_force_integral_per_s = k_I;
  params.jump_force_correction_max_m = c_max;
  const HoppingOutputLayout layout;
  HoppingReference reference("reference", model, leg_length, jump, nullptr, layout, params);
  auto context = reference.CreateDefaultLeafContext();
  const Eigen::VectorXd q = model->q_nominal();
  reference.Initialize(*context, q);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * model->nv());
  x.head(model->nv()) = q;
  reference.FixInputPort(*context, reference.GetInputPortIndex("state"), x);
  reference.FixTypedInputPort(*context, reference.GetInputPortIndex("mode"), 0);
  Eigen::VectorXd forces = Eigen::VectorXd::Zero(3 * model->num_contacts());
  for (const char* foot : {"left_foot", "right_foot"}) forces[3 * model->ContactIndex(foot) + 2] = 0.5 * F;
  reference.FixInputPort(*context, reference.GetInputPortIndex("contact_forces"), forces);
  Simulator sim(reference, std::move(context));
  ReferenceRun r;
  r.status = sim.AdvanceTo(until);
  const LeafContext& c = dynamic_cast<const LeafContext&>(sim.get_context());
  const Eigen::VectorXd& y = reference.EvalOutput(c, "desired");
  r.L_d = y[layout.leg_left];
  r.Ldot_d = y[layout.size + layout.leg_left];
  EXPECT_EQ(y[layout.leg_right], r.L_d);
  return r;
}

TEST(HoppingReference, JumpGrfFeedbackLengthensTheLegByTheMissingDeflection) {
  // 40 periodic updates in Jump: t = kSettle + T, ..., kSettle + 40 T (the update at kSettle starts the Jump).
  const int m = 40;
  const double until = kSettle + m * kT + 0.5 * kT;
  const double F = 300.0, e = (kFPlan - F) / kStiffness;  // 1 cm of missing deflection
  const double k_F = 2.0, k_I = 20.0;
  const ReferenceRun r = RunReference(F, k_F, k_I, 0.1, until);
  ASSERT_TRUE(r.status.ok()) << r.status.ToString();
  EXPECT_NEAR(r.L_d, kLPlan + k_F * e + m * kT * k_I * e, 1e-12);
  EXPECT_NEAR(r.Ldot_d, 0.0, 1e-12);  // the target's rate stays the plan's

  // The measured force equals the plan's: no correction.
  const ReferenceRun same = RunReference(kFPlan, k_F, k_I, 0.1, until);
  ASSERT_TRUE(same.status.ok()) << same.status.ToString();
  EXPECT_NEAR(same.L_d, kLPlan, 1e-12);

  // Off: the paper's target.
  const ReferenceRun off = RunReference(F, 0.0, 0.0, 0.1, until);
  EXPECT_NEAR(off.L_d, kLPlan, 1e-12);

  // Clamped: a 0.25 m deficit (no ground force) is limited to c_max = 0.03 m.
  const ReferenceRun clamped = RunReference(0.0, 10.0, 0.0, 0.03, until);
  EXPECT_NEAR(clamped.L_d, kLPlan + 0.03, 1e-12);
  // The integral alone is clamped too: m T k_I e = 40 · 5e-4 · 100 · 0.025 = 0.05 m > c_max = 0.02 m.
  const ReferenceRun integral = RunReference(0.0, 0.0, 100.0, 0.02, until);
  EXPECT_NEAR(integral.L_d, kLPlan + 0.02, 1e-12);
  // Below the clamp the integral grows as m T k_I e: 40 · 5e-4 · 10 · 0.025 = 5 mm.
  const ReferenceRun small = RunReference(0.0, 0.0, 10.0, 0.02, until);
  EXPECT_NEAR(small.L_d, kLPlan + m * kT * 10.0 * (kFPlan / kStiffness), 1e-12);
}

TEST(HoppingReference, JumpPlanWithoutForceFailsWhileTheFeedbackIsOn) {
  const ReferenceRun r = RunReference(300.0, 2.0, 0.0, 0.1, kSettle + 0.005, /*plan_has_force=*/false);
  ASSERT_FALSE(r.status.ok());
  EXPECT_NE(r.status.ToString().find("reference"), std::string::npos) << r.status.ToString();
  EXPECT_NE(r.status.ToString().find("jump_force_feedback"), std::string::npos) << r.status.ToString();
}

}  // namespace
}  // namespace rome
