#include "systems/planners/walking_trajectory_source.h"

namespace rome {

WalkingTrajectorySource::WalkingTrajectorySource(std::string name, WalkingPlan plan, double normal_force_lead_s)
    : LeafSystem(std::move(name)), plan_(std::move(plan)), normal_force_lead_s_(normal_force_lead_s) {
  if (plan_.segments().empty()) ThrowError("the walking plan is empty");
  if (!(normal_force_lead_s >= 0.0 && normal_force_lead_s <= 0.1))
    ThrowError("normal_force_lead_s = " + std::to_string(normal_force_lead_s) + " s is outside [0, 0.1] s");
  DeclareOutputPort(
      "com", {"x", "y", "z", "xdot", "ydot", "zdot", "xddot", "yddot", "zddot"},
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const WalkingReference r = plan_.Sample(c.time());
        *y << r.com_position, r.com_velocity, r.com_acceleration;
      },
      Feedthrough::None());
  DeclareOutputPort(
      "footholds", {"left_x", "left_y", "right_x", "right_y"},
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        const WalkingReference r = plan_.Sample(c.time());
        *y << r.left_foothold, r.right_foothold;
      },
      Feedthrough::None());
  DeclareOutputPort(
      "normal_force_reference", {"left", "right"},
      [this](const LeafContext& c, Eigen::VectorXd* y) {
        *y = plan_.Sample(c.time() + normal_force_lead_s_).normal_force;
      },
      Feedthrough::None());
  DeclareTypedOutputPort<WalkingDomain>(
      "domain", [this](const LeafContext& c, WalkingDomain* d) { *d = plan_.Sample(c.time()).domain; },
      Feedthrough::None());
}

}  // namespace rome
