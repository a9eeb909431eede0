// SteppingStonesSupervisor: impact bookkeeping of Algorithm 1 (lines 8-10) in its event update. Stance foot, stone
// index and step parameters after an impact, the step record, termination after max_steps, the fall check, pure
// outputs, and L_y about the stance foot against the rigid-translation closed form L = r_z v_x − r_x v_z.
#include "diagrams/stepping_stones/stepping_stones_supervisor.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "diagrams/stepping_stones/stepping_stones_diagram.h"
#include "systems/multibody/contact_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "diagrams/stepping_stones/stepping_stones_outputs_system.h"
#include "tests/common/source_path.h"

namespace rome {
namespace {

constexpr double kStep = 0.4;

class SupervisorTest : public ::testing::Test {
 protected:
  SupervisorTest()
      : model_(std::make_shared<const MultibodyModel>(MultibodyModel::LoadFromSidecar(
            rome::test::SourcePath("robots/amber/amber.rome.json"), {.euler_floating_base = true}))),
        terrain_(PeriodicSteppingStones(kStep, 0.0, 6)),
        ws_(*model_) {
    params_.max_steps = 3;
    supervisor_ = std::make_unique<SteppingStonesSupervisor>("supervisor", model_, terrain_, params_);
    context_ = supervisor_->CreateDefaultLeafContext();
    left_ = model_->ContactIndex("left_foot");
    right_ = model_->ContactIndex("right_foot");
  }

  Eigen::Vector3d Foot(const Eigen::VectorXd& x, int contact) {
    return CalcContactPointPosition(*model_, ws_, x.head(model_->nv()), contact, 0);
  }
  Eigen::VectorXd Output(const std::string& port) { return supervisor_->EvalOutput(*context_, port); }
  void SetInputs(const Eigen::VectorXd& x, int mode) {
    supervisor_->FixInputPort(*context_, 0, x);
    supervisor_->FixTypedInputPort(*context_, 1, mode);
    supervisor_->FixInputPort(*context_, 2, Eigen::VectorXd::Constant(1, -0.3));
    supervisor_->FixInputPort(*context_, 3, Eigen::VectorXd::Constant(1, 0.7));
  }
  EventStatus RunUpdate() {
    Eigen::VectorXd next = context_->discrete_state();
    const EventStatus status = supervisor_->periodic_events().at(0).update(*context_, &next);
    context_->get_mutable_discrete_state() = next;
    return status;
  }
  // The event update the simulator runs right after a guard's reset (here: a touchdown).
  EventStatus RunEventUpdate() {
    State next = context_->state();
    const EventStatus status = supervisor_->event_updates().at(0).update(
        *context_, EventRecord{context_->time(), "plant", "touchdown", 0, 0, 0}, &next);
    context_->get_mutable_state() = next;
    return status;
  }
  // A configuration with the `stance` foot at `stance_xz` and the other foot on the stone (l, h) ahead (Eq. (21)).
  Eigen::VectorXd PreImpactState(const std::string& stance, const std::string& swing, const Eigen::Vector2d& stance_xz,
                                 double l) {
    PreImpactPostureOptimizer optimizer(model_);
    PreImpactPostureRequest request;
    request.stance_contact = stance;
    request.swing_contact = swing;
    request.step_length_m = l;
    request.step_height_m = 0.0;
    request.stance_foot_position = stance_xz;
    const PreImpactPosture posture = optimizer.Solve(request);
    EXPECT_TRUE(posture.success) << posture.message;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(2 * model_->nv());
    x.head(model_->nv()) = posture.q;
    x[model_->nv()] = 0.6;  // some forward base velocity
    return x;
  }

  std::shared_ptr<const MultibodyModel> model_;
  Terrain terrain_;
  MultibodyWorkspace ws_;
  SteppingStonesSupervisorParams params_;
  std::unique_ptr<SteppingStonesSupervisor> supervisor_;
  std::unique_ptr<LeafContext> context_;
  int left_ = -1, right_ = -1;
};

TEST_F(SupervisorTest, InitialStepAndRigidTranslationMomentum) {
  SteppingStonesDiagramParams dp;
  Eigen::VectorXd x = SteppingStonesInitialState(*model_, terrain_, dp);
  const int nv = model_->nv();
  // The initial state stands on the first stone's centre with both feet at rest.
  EXPECT_NEAR(Foot(x, left_).x(), 0.0, 1e-10);
  EXPECT_NEAR(Foot(x, right_).z(), 0.0, 1e-10);
  EXPECT_NEAR(CalcPointVelocity(*model_, ws_, x.head(nv), x.tail(nv), model_->contacts()[left_].body,
                                model_->contacts()[left_].frame_origin)
                  .norm(),
              0.0, 1e-10);
  // ... with the COM at initial_com_x_m on the E* orbit of the LIP at the walking height (Eq. (16)).
  const double x0 = dp.initial_com_x_m, lambda_squared = 9.81 / dp.supervisor.walking_com_height_m;
  EXPECT_NEAR(CalcComPosition(*model_, ws_, x.head(nv)).x(), x0, 1e-10);
  EXPECT_NEAR(CalcComPosition(*model_, ws_, x.head(nv)).z(), dp.supervisor.walking_com_height_m, 1e-10);
  const double xdot = CalcComVelocity(*model_, ws_, x.head(nv), x.tail(nv)).x();
  EXPECT_NEAR(xdot * xdot - lambda_squared * x0 * x0, dp.target_orbital_energy, 1e-9);
  EXPECT_NEAR(CalcComVelocity(*model_, ws_, x.head(nv), x.tail(nv)).z(), 0.0, 1e-10);
  EXPECT_NEAR(x[nv + 2], 0.0, 1e-12);  // torso not rotating

  // Pure translation of the whole robot (no joint or pitch rates): the centroidal angular momentum is zero and
  // L about the stance foot is the point-mass value r_z v_x − r_x v_z.
  x.tail(nv).setZero();
  x[nv] = 0.7;
  x[nv + 1] = -0.2;
  x[0] += 0.03;  // shift the robot (the feet stay on the 0.1 m stone)
  SetInputs(x, 0);
  supervisor_->Initialize(*context_, x, 0);
  const Eigen::Vector2d st = supervisor_->stance_foot(*context_);
  EXPECT_NEAR(st.x(), Foot(x, left_).x(), 1e-12);
  EXPECT_EQ(supervisor_->stone(*context_), 0);
  EXPECT_EQ(supervisor_->stance_mode(*context_), 0);
  const Eigen::Vector3d com = CalcComPosition(*model_, ws_, x.head(nv));
  const double rx = com.x() - st.x(), rz = com.z() - st.y();
  const Eigen::VectorXd com_state = Output("com_state");
  EXPECT_NEAR(com_state[0], rx, 1e-12);
  EXPECT_NEAR(com_state[1], rz, 1e-12);
  EXPECT_NEAR(com_state[2], 0.7, 1e-12);
  EXPECT_NEAR(com_state[3], -0.2, 1e-12);
  EXPECT_NEAR(Output("angular_momentum")[0], rz * 0.7 - rx * (-0.2), 1e-12);
  // The first step aims at stone 1 from the stance foot.
  EXPECT_NEAR(Output("step")[0], kStep - st.x(), 1e-12);
  EXPECT_NEAR(Output("step")[1], -st.y(), 1e-12);
  const StepOutputParameters p = supervisor_->EvalTypedOutput<StepOutputParameters>(*context_, "step_parameters");
  EXPECT_NEAR(p.p_com_x0, rx, 1e-12);
  EXPECT_NEAR(p.p_sw0_x, Foot(x, right_).x() - st.x(), 1e-12);
  EXPECT_NEAR(p.step_length, kStep - st.x(), 1e-12);
  // The pre-impact COM height aims at the walking height: a soft target (weight 0.1 against the NLP's small posture
  // term), so it lands within a couple of centimetres, well below the straight-leg height of about 0.9 m.
  EXPECT_NEAR(Output("pre_impact_com_height")[0], params_.walking_com_height_m, 0.02);
}

TEST_F(SupervisorTest, ImpactBookkeeping) {
  SteppingStonesDiagramParams dp;
  const Eigen::VectorXd x0 = SteppingStonesInitialState(*model_, terrain_, dp);
  SetInputs(x0, 0);
  supervisor_->Initialize(*context_, x0, 0);
  EXPECT_TRUE(RunUpdate().ok());  // no impact: nothing committed
  EXPECT_EQ(supervisor_->num_steps(*context_), 0);

  // Touchdown of the right foot on stone 1: the plant is in right stance (mode 1).
  const Eigen::VectorXd x1 = PreImpactState("left_foot", "right_foot", Eigen::Vector2d(0.0, 0.0), kStep);
  context_->SetTime(0.3);
  SetInputs(x1, 1);
  const Eigen::Vector3d foot = Foot(x1, right_);
  // Until the event update runs, the outputs describe the committed (old) step: they are pure functions of it.
  EXPECT_EQ(Output("stone")[0], 0.0);
  EXPECT_TRUE(RunUpdate().ok());  // a periodic update commits nothing about the impact
  EXPECT_EQ(supervisor_->stance_mode(*context_), 0);
  // The event update commits the new step.
  EXPECT_TRUE(RunEventUpdate().ok());
  EXPECT_EQ(supervisor_->stance_mode(*context_), 1);
  EXPECT_EQ(supervisor_->stone(*context_), 1);
  EXPECT_EQ(supervisor_->num_steps(*context_), 1);
  EXPECT_NEAR(Output("stance_foot")[0], foot.x(), 1e-12);
  EXPECT_EQ(Output("stone")[0], 1.0);
  EXPECT_NEAR(Output("step")[0], 2 * kStep - foot.x(), 1e-12);
  const StepOutputParameters p = supervisor_->EvalTypedOutput<StepOutputParameters>(*context_, "step_parameters");
  EXPECT_NEAR(p.p_sw0_x, Foot(x1, left_).x() - foot.x(), 1e-12);  // the old stance foot is the new swing foot
  EXPECT_NEAR(p.p_com_x0, CalcComPosition(*model_, ws_, x1.head(model_->nv())).x() - foot.x(), 1e-12);
  EXPECT_NEAR(p.phi_0, x1[2], 1e-15);
  EXPECT_DOUBLE_EQ(p.step_start_time, 0.3);
  const double L_after = Output("angular_momentum")[0];
  // A second event at the same stance (e.g. a touchdown from flight onto the same foot) is no new step.
  EXPECT_TRUE(RunEventUpdate().ok());
  EXPECT_EQ(supervisor_->num_steps(*context_), 1);
  // Evaluating any output twice changes nothing (outputs are pure).
  const Eigen::VectorXd xd_before = context_->discrete_state();
  for (int k = 0; k < 2; ++k)
    for (int i = 0; i < supervisor_->num_output_ports(); ++i) {
      context_->InvalidateCache();
      if (supervisor_->output_port(i).is_vector())
        supervisor_->EvalOutput(*context_, i);
      else
        supervisor_->EvalAbstractOutput(*context_, i);
    }
  EXPECT_EQ(context_->discrete_state(), xd_before);
  EXPECT_EQ(supervisor_->steps(*context_).size(), 1u);
  ASSERT_EQ(supervisor_->steps(*context_).size(), 1u);
  const StepRecord& r = supervisor_->steps(*context_)[0];
  EXPECT_EQ(r.stone, 1);
  EXPECT_EQ(r.planned_stone, 1);
  EXPECT_NEAR(r.foothold_error_m, std::abs(foot.x() - kStep), 1e-12);
  EXPECT_LT(r.foothold_error_m, 1e-6);  // the posture NLP put the foot on the stone centre
  EXPECT_NEAR(r.step_length_m, kStep, 1e-12);
  EXPECT_NEAR(r.post_impact_momentum, L_after, 1e-12);
  EXPECT_NEAR(r.duration_s, 0.3, 1e-15);
  EXPECT_TRUE(r.posture_ok);
  EXPECT_EQ(supervisor_->posture_failures(*context_), 0);

  // Second impact: left foot onto stone 2 (mode 0), third: right foot onto stone 3 ends the run (max_steps = 3).
  const Eigen::VectorXd x2 =
      PreImpactState("right_foot", "left_foot", Eigen::Vector2d(foot.x(), foot.z()), 2 * kStep - foot.x());
  SetInputs(x2, 0);
  EXPECT_TRUE(RunEventUpdate().ok());
  EXPECT_EQ(supervisor_->stone(*context_), 2);
  EXPECT_EQ(supervisor_->stance_mode(*context_), 0);
  const Eigen::Vector3d foot2 = Foot(x2, left_);
  const Eigen::VectorXd x3 =
      PreImpactState("left_foot", "right_foot", Eigen::Vector2d(foot2.x(), foot2.z()), 3 * kStep - foot2.x());
  SetInputs(x3, 1);
  const EventStatus end = RunEventUpdate();
  EXPECT_EQ(end.kind, EventStatus::Kind::kReachedTermination);
  EXPECT_NE(end.message.find("completed 3 steps"), std::string::npos) << end.message;
  EXPECT_EQ(supervisor_->steps(*context_).size(), 3u);
  EXPECT_EQ(supervisor_->steps(*context_).back().stone, 3);
}

TEST_F(SupervisorTest, FallAndBadInput) {
  SteppingStonesDiagramParams dp;
  Eigen::VectorXd x = SteppingStonesInitialState(*model_, terrain_, dp);
  SetInputs(x, 0);
  supervisor_->Initialize(*context_, x, 0);
  // The COM sinks below min_com_height_m above the stance foot: "robot fell".
  x[1] -= dp.supervisor.walking_com_height_m - params_.min_com_height_m + 0.01;
  SetInputs(x, 0);
  const EventStatus fell = RunUpdate();
  EXPECT_EQ(fell.kind, EventStatus::Kind::kFailed);
  EXPECT_NE(fell.message.find("robot fell"), std::string::npos) << fell.message;
  // A stance foot off every stone is rejected with a message naming it.
  Eigen::VectorXd off = SteppingStonesInitialState(*model_, terrain_, dp);
  off[0] += 0.2;
  try {
    supervisor_->Initialize(*context_, off, 0);
    FAIL() << "expected an exception";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("not on any stone"), std::string::npos) << e.what();
  }
  EXPECT_THROW(SteppingStonesSupervisor("s", model_, Terrain::Flat(), params_), std::exception);
}

// The long-step cap on the pre-impact COM height: the posture NLP, given the supervisor's request, puts the COM within
// max_com_foot_distance_m of both feet (measured by forward kinematics of its solution, the height being a soft target:
// 1 cm), where the uncapped walking height would put it sqrt(0.80² + 0.48²) = 0.933 m from the rear foot on a flat
// 0.8 m step. Steps up to the paper's random-course 0.7 m keep the walking height; stepping down still subtracts h.
TEST_F(SupervisorTest, LongStepComHeightStaysWithinReach) {
  SteppingStonesSupervisorParams p;  // AMBER's defaults, ε = 0.6
  const double reach = p.max_com_foot_distance_m;
  EXPECT_DOUBLE_EQ(PreImpactComHeightRequest(p, 0.4, 0.0), p.walking_com_height_m);
  EXPECT_DOUBLE_EQ(PreImpactComHeightRequest(p, 0.7, 0.0), p.walking_com_height_m);
  EXPECT_DOUBLE_EQ(PreImpactComHeightRequest(p, 0.4, -0.1), p.walking_com_height_m - 0.1);
  EXPECT_GT(std::hypot(p.walking_com_height_m, 0.6 * 0.8), reach + 0.02);  // the cap binds on 0.8 m

  PreImpactPostureParams posture_params = p.posture;
  posture_params.com_x_fraction = p.impact_fraction;
  PreImpactPostureOptimizer optimizer(model_, posture_params);
  for (const double h : {0.0, -0.1}) {
    PreImpactPostureRequest request;
    request.stance_contact = "left_foot";
    request.swing_contact = "right_foot";
    request.step_length_m = 0.8;
    request.step_height_m = h;
    request.com_height_m = PreImpactComHeightRequest(p, 0.8, h);
    const PreImpactPosture posture = optimizer.Solve(request);
    ASSERT_TRUE(posture.success) << posture.message;
    const Eigen::Vector3d com = CalcComPosition(*model_, ws_, posture.q);
    const Eigen::Vector3d stance = CalcContactPointPosition(*model_, ws_, posture.q, left_, 0);
    const Eigen::Vector3d swing = CalcContactPointPosition(*model_, ws_, posture.q, right_, 0);
    EXPECT_NEAR(swing.x() - stance.x(), 0.8, 1e-6);
    // Level ground: both feet; stepping down: the stance foot (the landing foot is h lower, the COM height above it).
    EXPECT_LT((com - stance).norm(), reach + 0.01) << "h = " << h;
    if (h == 0.0) { EXPECT_LT((com - swing).norm(), reach + 0.01); }
  }

  // A cap too small for the step is bad input, named; so is a non-positive cap.
  p.max_com_foot_distance_m = 0.3;
  try {
    PreImpactComHeightRequest(p, 0.8, 0.0);
    FAIL() << "expected an exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_com_foot_distance_m = 0.3"), std::string::npos) << e.what();
  }
  p.max_com_foot_distance_m = 0.0;
  EXPECT_THROW(SteppingStonesSupervisor("s", model_, terrain_, p), std::exception);
}

}  // namespace
}  // namespace rome
