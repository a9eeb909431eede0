#include "systems/plants/joint_limit_statistics.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rome {

void JointLimitStatistics::Record(const MultibodyModel& model, double t, const Eigen::Ref<const Eigen::VectorXd>& q) {
  const int nv = model.nv();
  if (q.size() != nv)
    throw std::invalid_argument("JointLimitStatistics: q has size " + std::to_string(q.size()) + "; robot '" +
                                model.name() + "' has nv = " + std::to_string(nv));
  if (min_lower_margin.size() != nv) {
    min_lower_margin.setConstant(nv, std::numeric_limits<double>::infinity());
    min_upper_margin.setConstant(nv, std::numeric_limits<double>::infinity());
  }
  const Eigen::VectorXd& lo = model.position_lower_limits();
  const Eigen::VectorXd& hi = model.position_upper_limits();
  ++samples;
  bool violated = false;
  for (int i = 0; i < nv; ++i) {
    const double lower = std::isfinite(lo[i]) ? q[i] - lo[i] : std::numeric_limits<double>::infinity();
    const double upper = std::isfinite(hi[i]) ? hi[i] - q[i] : std::numeric_limits<double>::infinity();
    min_lower_margin[i] = std::min(min_lower_margin[i], lower);
    min_upper_margin[i] = std::min(min_upper_margin[i], upper);
    if (lower >= -tolerance_rad && upper >= -tolerance_rad) continue;
    if (!violated && violations == 0) {
      std::ostringstream os;
      const bool below = lower < -tolerance_rad;
      os << "t = " << t << " s: joint '" << model.JointName(i) << "' q = " << q[i] << ", beyond its "
         << (below ? "lower" : "upper") << " limit " << (below ? lo[i] : hi[i]);
      first_violation = os.str();
    }
    violated = true;
  }
  if (violated) ++violations;
}

double JointLimitStatistics::SmallestMargin(const MultibodyModel& model, std::string* where) const {
  double smallest = std::numeric_limits<double>::infinity();
  for (Eigen::Index i = 0; i < min_lower_margin.size(); ++i)
    for (const bool lower : {true, false}) {
      const double m = lower ? min_lower_margin[i] : min_upper_margin[i];
      if (m < smallest) {
        smallest = m;
        if (where) *where = model.JointName(static_cast<int>(i)) + (lower ? " lower" : " upper");
      }
    }
  return smallest;
}

std::string JointLimitStatistics::MarginsText(const MultibodyModel& model) const {
  std::ostringstream os;
  for (Eigen::Index i = 0; i < min_lower_margin.size(); ++i)
    if (std::isfinite(min_lower_margin[i]) || std::isfinite(min_upper_margin[i]))
      os << model.JointName(static_cast<int>(i)) << ": lower margin " << min_lower_margin[i] << ", upper margin "
         << min_upper_margin[i] << "\n";
  return os.str();
}

}  // namespace rome
