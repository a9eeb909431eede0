#include "systems/planners/walking_trajectory_source.h"

namespace rome {

WalkingTrajectorySource::WalkingTrajectorySource(std::string name, WalkingPlan plan)
    : LeafSystem(std::move(name)), plan_(std::move(plan)) {
  if (plan_.segments().empty()) ThrowError("the walking plan is empty");
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
      [this](const LeafContext& c, Eigen::VectorXd* y) { *y = plan_.Sample(c.time()).normal_force; },
      Feedthrough::None());
  DeclareTypedOutputPort<WalkingDomain>(
      "domain", [this](const LeafContext& c, WalkingDomain* d) { *d = plan_.Sample(c.time()).domain; },
      Feedthrough::None());
}

}  // namespace rome
