#include "systems/controllers/clf_outputs.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rome {

RelativeDegreeOneOutput::RelativeDegreeOneOutput(std::string name, int size, double weight,
                                                 std::vector<int> active_modes)
    : name_(std::move(name)), size_(size), weight_(weight), active_modes_(std::move(active_modes)) {
  if (size_ <= 0)
    throw std::invalid_argument("output '" + name_ + "': size must be positive, got " + std::to_string(size_));
  if (!(weight_ > 0) || !std::isfinite(weight_))
    throw std::invalid_argument("output '" + name_ + "': weight must be positive, got " + std::to_string(weight_));
}

bool RelativeDegreeOneOutput::IsActiveIn(int mode) const {
  return active_modes_.empty() || std::find(active_modes_.begin(), active_modes_.end(), mode) != active_modes_.end();
}

CentroidalPitchMomentumOutput::CentroidalPitchMomentumOutput(std::string name, double weight,
                                                             std::vector<int> active_modes)
    : RelativeDegreeOneOutput(std::move(name), 1, weight, std::move(active_modes)) {}

void CentroidalPitchMomentumOutput::Calc(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                         const VectorRef& v, Eigen::Ref<Eigen::VectorXd> y1,
                                         Eigen::Ref<Eigen::MatrixXd> A, Eigen::Ref<Eigen::VectorXd> Adot_v) const {
  // A_G rows: [angular about the COM (x, y, z); linear]; the pitch row is the angular y row (Eq. (39)).
  CalcCentroidalMomentumMatrix(model, ws, q, ws.J_point);
  A = ws.J_point.row(1);
  y1[0] = ws.J_point.row(1).dot(v);
  Adot_v[0] = CalcCentroidalMomentumBias(model, ws, q, v)[1];
}

}  // namespace rome
