#include "diagrams/hopping/hopping_outputs.h"

namespace rome {

HoppingOutputLayout MakeHoppingOutputLayout(const HoppingOutputParams& p) {
  HoppingOutputLayout l;
  const int o = p.jump_tracks_momentum ? 1 : 0;
  l.momentum = p.jump_tracks_momentum ? 0 : -1;
  l.leg_left = o, l.leg_right = o + 1, l.com_x = o + 2, l.com_y = o + 3, l.yaw = o + 4, l.pitch = o + 5,
  l.motors = o + 6, l.size = o + 16;
  return l;
}

std::vector<ClfOutput> MakeHoppingOutputs(const MultibodyModel& model, const JointFunctionTask::Function& leg_length,
                                          const HoppingOutputParams& p) {
  const int jump = HoppingDomain::kJump, flight = HoppingDomain::kFlight, landing = HoppingDomain::kLanding;
  auto gains = [](double weight) {
    TaskGains g;
    g.weight = weight;
    return g;
  };
  TaskGains motor_gains = gains(p.motor_weight);
  motor_gains.kp = p.motor_kp, motor_gains.kd = p.motor_kd;
  std::vector<ClfOutput> outputs;
  if (p.jump_tracks_momentum)
    outputs.push_back(ClfOutput::RelativeDegreeOne(std::make_shared<CentroidalPitchMomentumOutput>(
        "centroidal_pitch_momentum", p.momentum_weight, std::vector<int>{jump})));
  const std::vector<ClfOutput> rest = {
      ClfOutput::RelativeDegreeTwo(std::make_shared<JointFunctionTask>("leg_length_left", model, "left_knee",
                                                                       leg_length, gains(p.leg_length_weight),
                                                                       std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(
          std::make_shared<JointFunctionTask>("leg_length_right", model, "right_knee", leg_length,
                                              gains(p.leg_length_weight), std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(std::make_shared<ComPositionTask>(
          "com_xy", std::vector<Axis>{Axis::kX, Axis::kY}, gains(p.com_weight), std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(MakeBaseAngleTask("pelvis_yaw", model, EulerAngle::kYaw, gains(p.pelvis_weight),
                                                     std::vector<int>{jump, landing})),
      ClfOutput::RelativeDegreeTwo(
          MakeBaseAngleTask("pelvis_pitch", model, EulerAngle::kPitch, gains(p.pelvis_weight),
                            p.jump_tracks_momentum ? std::vector<int>{landing} : std::vector<int>{jump, landing}))};
  outputs.insert(outputs.end(), rest.begin(), rest.end());
  for (const ActuatorInfo& a : model.actuators())
    outputs.push_back(ClfOutput::RelativeDegreeTwo(std::make_shared<JointPositionTask>(
        "motor_" + a.joint, model, a.joint, motor_gains, std::vector<int>{flight})));
  return outputs;
}

}  // namespace rome
