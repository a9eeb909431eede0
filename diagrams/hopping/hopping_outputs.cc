#include "diagrams/hopping/hopping_outputs.h"

namespace rome {

std::vector<ClfOutput> MakeHoppingOutputs(const MultibodyModel& model, const JointFunctionTask::Function& leg_length, const HoppingOutputParams& p) {
  const int jump = HoppingDomain::kJump, flight = HoppingDomain::kFlight, landing = HoppingDomain::kLanding;
  auto gains = [](double weight) {
    TaskGains g;
    g.weight = weight;
    return g;
  };
  std::vector<ClfOutput> outputs = {
      ClfOutput::RelativeDegreeOne(std::make_shared<CentroidalPitchMomentumOutput>("centroidal_pitch_momentum", p.momentum_weight, std::vector<int>{jump})),
      ClfOutput::RelativeDegreeTwo(
          std::make_shared<JointFunctionTask>("leg_length_left", model, "left_knee", leg_length, gains(p.leg_length_weight), std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(
          std::make_shared<JointFunctionTask>("leg_length_right", model, "right_knee", leg_length, gains(p.leg_length_weight), std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<ComPositionTask>("com_xy", std::vector<Axis>{Axis::kX, Axis::kY}, gains(p.com_weight), std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_yaw", model, "base_yaw", gains(p.pelvis_weight), std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("pelvis_pitch", model, "base_pitch", gains(p.pelvis_weight), std::vector<int>{landing}))};
  for (const ActuatorInfo& a : model.actuators())
    outputs.push_back(ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>("motor_" + a.joint, model, a.joint, gains(p.motor_weight), std::vector<int>{flight})));
  return outputs;
}

}  // namespace rome
