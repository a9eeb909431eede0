#include "diagrams/stepping_stones/stepping_stones_outputs_system.h"

#include <cmath>
#include <stdexcept>

namespace rome {

SteppingStonesOutputsSystem::SteppingStonesOutputsSystem(std::string name, SteppingStonesOutputsSystemParams params)
    : LeafSystem(std::move(name)), params_(params) {
  if (!(params_.gravity > 0))
    ThrowError("parameter gravity must be positive (m/s²), got " + std::to_string(params_.gravity));
  com_port_ = DeclareInputPort("com_state", {"x", "z", "vx", "vz"});
  step_port_ = DeclareTypedInputPort<StepOutputParameters>("step_parameters");
  height_port_ = DeclareInputPort("com_height_desired", {"z", "vz", "az"});
  const std::vector<std::string> names{"torso_pitch", "com_z", "swing_x", "swing_z"};
  DeclareOutputPort("y_desired", names, [this](const LeafContext& c, Eigen::VectorXd* y) { *y = CalcOutputs(c).y; });
  DeclareOutputPort("ydot_desired", names,
                    [this](const LeafContext& c, Eigen::VectorXd* y) { *y = CalcOutputs(c).ydot; });
  DeclareOutputPort("yddot_desired", names,
                    [this](const LeafContext& c, Eigen::VectorXd* y) { *y = CalcOutputs(c).yddot; });
  DeclareOutputPort("phase", {"tau", "tau_dot", "tau_ddot"}, [this](const LeafContext& c, Eigen::VectorXd* y) {
    const Phase p = CalcOutputs(c).phase;
    *y << p.tau, p.tau_dot, p.tau_ddot;
  });
}

Eigen::Matrix<double, SteppingStonesOutputsSystem::kNumStepParameters, 1>
SteppingStonesOutputsSystem::PackStepParameters(const StepOutputParameters& s) {
  Eigen::Matrix<double, kNumStepParameters, 1> v;
  v << s.phi_0, s.phi_f, s.p_com_x0, s.p_sw0_x, s.p_sw0_z, s.step_length, s.step_height, s.impact_fraction,
      s.step_start_time, s.step_duration;
  return v;
}

StepOutputParameters SteppingStonesOutputsSystem::UnpackStepParameters(const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (v.size() != kNumStepParameters)
    throw std::invalid_argument("SteppingStonesOutputsSystem: step parameters need " +
                                std::to_string(kNumStepParameters) + " entries, got " + std::to_string(v.size()));
  StepOutputParameters s;
  s.phi_0 = v[0];
  s.phi_f = v[1];
  s.p_com_x0 = v[2];
  s.p_sw0_x = v[3];
  s.p_sw0_z = v[4];
  s.step_length = v[5];
  s.step_height = v[6];
  s.impact_fraction = v[7];
  s.step_start_time = v[8];
  s.step_duration = v[9];
  return s;
}

DesiredOutputs SteppingStonesOutputsSystem::CalcOutputs(const LeafContext& context) const {
  const Eigen::VectorXd& com = EvalInput(context, com_port_);
  const Eigen::Matrix<double, kNumStepParameters, 1> packed =
      PackStepParameters(EvalTypedInput<StepOutputParameters>(context, step_port_));
  const Eigen::VectorXd& height = EvalInput(context, height_port_);
  Cache& cache = context.scratch<Cache>();
  try {
    if (!cache.trajectories || packed != cache.key) {
      cache.trajectories.emplace(params_.phase, params_.swing_foot, UnpackStepParameters(packed));
      cache.key = packed;
    }
    const StepOutputParameters& step = cache.trajectories->step();
    if (!(step.step_length > 0))
      throw std::invalid_argument("step length l_des must be positive, got " + std::to_string(step.step_length) + " m");
    const double z0_hat = com[1] - step.step_height / step.step_length * com[0];
    if (!(z0_hat > 0))
      throw std::invalid_argument("COM height above the virtual slope must be positive, got " + std::to_string(z0_hat) +
                                  " m");
    const double pddot_x = params_.gravity / z0_hat * com[0];  // LIP, Eq. (11)
    return cache.trajectories->Evaluate(context.time(), com[0], com[2], pddot_x,
                                        Eigen::Vector3d(height[0], height[1], height[2]));
  } catch (const std::invalid_argument& e) {
    cache.trajectories.reset();
    ThrowError(std::string("input 'step_parameters' or 'com_state' rejected: ") + e.what());
  }
}

}  // namespace rome
