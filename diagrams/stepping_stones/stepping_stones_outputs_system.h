#pragma once
// SteppingStonesOutputsSystem: the desired outputs Y_d of the stepping-stones paper, Eq. (19)-(24), as a framework
// block (wraps SteppingStonesOutputTrajectories; see output_trajectories.h for the equations).
//
// inputs:  com_state (4)          = [p^x, p^z (m), ṗ^x, ṗ^z (m/s)] COM relative to the stance foot
//          step_parameters (typed StepOutputParameters, output_trajectories.h): φ_0 (rad), φ_f (rad), p_com0^x (m),
//                                   p_sw0^x (m), p_sw0^z (m), l_des (m), h_des (m), ε (-), t_0 (s), T_s (s) — constant
//                                   during a step, updated at impact (Algorithm 1, lines 8-10) by whoever owns the step
//                                   sequence. PackStepParameters() stores them in a vector (e.g. a discrete state).
//          com_height_desired (3) = [p^{z,d}, ṗ^{z,d}, p̈^{z,d}] from VerticalComMpcSystem
// outputs: y_desired (4), ydot_desired (4), yddot_desired (4) = Y_d, Ẏ_d, Ÿ_d in the order
//                                   [φ_torso (rad), p_com^z (m), p_sw^x (m), p_sw^z (m)] and their time derivatives
//          phase (3)              = [τ, τ̇ (1/s), τ̈ (1/s²)]
// The state-based phase needs p̈^x for τ̈: we use the LIP's p̈^x = g p^x / ẑ0, ẑ0 = p^z − (h/l) p^x (Eq. (11), (27)).
// The trajectories are rebuilt only when step_parameters change (cached in the context scratch).

#include <optional>
#include <string>

#include "framework/system.h"
#include "systems/planners/output_trajectories.h"

namespace rome {

struct SteppingStonesOutputsSystemParams {
  PhaseVariableParams phase{};
  SwingFootBezierParams swing_foot{};
  double gravity = 9.81;  ///< [m/s²] for the LIP estimate of p̈^x
};

class SteppingStonesOutputsSystem final : public LeafSystem {
 public:
  static constexpr int kNumStepParameters = 10;
  explicit SteppingStonesOutputsSystem(std::string name = "outputs", SteppingStonesOutputsSystemParams params = {});
  const SteppingStonesOutputsSystemParams& params() const { return params_; }

  static Eigen::Matrix<double, kNumStepParameters, 1> PackStepParameters(const StepOutputParameters& step);
  static StepOutputParameters UnpackStepParameters(const Eigen::Ref<const Eigen::VectorXd>& packed);
  /// Y_d and its derivatives for the inputs in `context`.
  DesiredOutputs CalcOutputs(const LeafContext& context) const;

 protected:
  struct Cache {
    Eigen::Matrix<double, kNumStepParameters, 1> key = Eigen::Matrix<double, kNumStepParameters, 1>::Constant(NAN);
    std::optional<SteppingStonesOutputTrajectories> trajectories;
  };
  std::any AllocateScratch() const override { return Cache{}; }

 private:
  SteppingStonesOutputsSystemParams params_;
  int com_port_, step_port_, height_port_;
};

}  // namespace rome
