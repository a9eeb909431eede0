#pragma once
// JointLimitStatistics: checks a plant's generalized positions against the model's URDF joint position limits
// (MultibodyModel::position_lower_limits / position_upper_limits; joints without a limit are skipped), sample by
// sample. Record() it from a simulator monitor to check every integrator step and event:
//   sim.add_monitor([&](const Context& c) { limits.Record(plant.model(), c.time(), q_of(c)); return ...; });
// A sample violates the limits when some joint lies more than tolerance_rad beyond its lower or upper limit (units of
// q: rad for revolute joints, m for prismatic ones). It also keeps, per joint, the smallest margin to each limit
// (q − q_lower, q_upper − q; negative beyond the limit) over the samples.

#include <limits>
#include <string>

#include <Eigen/Core>

#include "systems/multibody/multibody_model.h"

namespace rome {

struct JointLimitStatistics {
  /// [rad or m] allowed excess (ours): a joint stop's event lands on the limit within the rootfinder's tolerance.
  double tolerance_rad = 1e-9;
  Eigen::VectorXd min_lower_margin;  ///< per coordinate, smallest q − q_lower (+inf: no limit, or no sample yet)
  Eigen::VectorXd min_upper_margin;  ///< per coordinate, smallest q_upper − q
  long samples = 0;
  long violations = 0;          ///< samples with some joint more than tolerance_rad beyond a limit
  std::string first_violation;  ///< "t = … s: joint 'left_ankle_pitch' q = … rad, beyond its lower limit … rad"

  /// Records one sample: q (model.nv()) at time t [s]. The first call sizes the margins (the only allocation).
  /// Throws std::invalid_argument naming the robot if q has the wrong size.
  void Record(const MultibodyModel& model, double t, const Eigen::Ref<const Eigen::VectorXd>& q);
  /// The smallest margin over every limited joint and both limits [rad or m] (+inf without samples or limits), and
  /// (if `where` is given) "left_ankle_pitch lower" naming its joint and limit.
  double SmallestMargin(const MultibodyModel& model, std::string* where = nullptr) const;
  /// Per limited joint "name: lower margin, upper margin" (rad), one line each, for reports.
  std::string MarginsText(const MultibodyModel& model) const;
};

}  // namespace rome
