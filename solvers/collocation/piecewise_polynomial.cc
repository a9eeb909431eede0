#include "solvers/collocation/piecewise_polynomial.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rome {
namespace {

void CheckBreaks(const char* who, const Eigen::VectorXd& breaks, Eigen::Index columns) {
  std::ostringstream msg;
  if (breaks.size() < 2) {
    msg << "PiecewisePolynomial::" << who << ": need at least 2 breaks, got " << breaks.size();
    throw std::invalid_argument(msg.str());
  }
  if (columns != breaks.size()) {
    msg << "PiecewisePolynomial::" << who << ": " << breaks.size() << " breaks but " << columns << " sample columns";
    throw std::invalid_argument(msg.str());
  }
  for (Eigen::Index k = 0; k + 1 < breaks.size(); ++k) {
    if (!(breaks(k + 1) > breaks(k))) {
      msg << "PiecewisePolynomial::" << who << ": breaks must be strictly increasing, breaks[" << k
          << "] = " << breaks(k) << ", breaks[" << k + 1 << "] = " << breaks(k + 1);
      throw std::invalid_argument(msg.str());
    }
  }
}

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

}  // namespace

PiecewisePolynomial::PiecewisePolynomial(std::vector<double> breaks, std::vector<Eigen::MatrixXd> coefficients)
    : rows_(coefficients.empty() ? 0 : static_cast<int>(coefficients.front().rows())),
      breaks_(std::move(breaks)),
      coefficients_(std::move(coefficients)) {}

PiecewisePolynomial PiecewisePolynomial::CubicHermite(const Eigen::VectorXd& breaks, const Eigen::MatrixXd& values,
                                                      const Eigen::MatrixXd& derivatives) {
  CheckBreaks("CubicHermite", breaks, values.cols());
  if (derivatives.rows() != values.rows() || derivatives.cols() != values.cols()) {
    std::ostringstream msg;
    msg << "PiecewisePolynomial::CubicHermite: derivatives are " << derivatives.rows() << "x" << derivatives.cols()
        << ", values " << values.rows() << "x" << values.cols();
    throw std::invalid_argument(msg.str());
  }
  std::vector<Eigen::MatrixXd> coefficients;
  for (Eigen::Index k = 0; k + 1 < breaks.size(); ++k) {
    const double h = breaks(k + 1) - breaks(k);
    const Eigen::VectorXd x0 = values.col(k), x1 = values.col(k + 1);
    const Eigen::VectorXd d0 = derivatives.col(k), d1 = derivatives.col(k + 1);
    Eigen::MatrixXd C(values.rows(), 4);
    C.col(0) = x0;
    C.col(1) = d0;
    C.col(2) = (3.0 * (x1 - x0) / h - 2.0 * d0 - d1) / h;
    C.col(3) = (2.0 * (x0 - x1) / h + d0 + d1) / (h * h);
    coefficients.push_back(std::move(C));
  }
  return PiecewisePolynomial(ToStd(breaks), std::move(coefficients));
}

PiecewisePolynomial PiecewisePolynomial::FirstOrderHold(const Eigen::VectorXd& breaks, const Eigen::MatrixXd& values) {
  CheckBreaks("FirstOrderHold", breaks, values.cols());
  std::vector<Eigen::MatrixXd> coefficients;
  for (Eigen::Index k = 0; k + 1 < breaks.size(); ++k) {
    Eigen::MatrixXd C(values.rows(), 2);
    C.col(0) = values.col(k);
    C.col(1) = (values.col(k + 1) - values.col(k)) / (breaks(k + 1) - breaks(k));
    coefficients.push_back(std::move(C));
  }
  return PiecewisePolynomial(ToStd(breaks), std::move(coefficients));
}

PiecewisePolynomial PiecewisePolynomial::ZeroOrderHold(const Eigen::VectorXd& breaks, const Eigen::MatrixXd& values) {
  CheckBreaks("ZeroOrderHold", breaks, values.cols());
  std::vector<Eigen::MatrixXd> coefficients;
  for (Eigen::Index k = 0; k + 1 < breaks.size(); ++k) coefficients.push_back(values.col(k));
  return PiecewisePolynomial(ToStd(breaks), std::move(coefficients));
}

double PiecewisePolynomial::start_time() const {
  if (empty()) throw std::logic_error("PiecewisePolynomial::start_time: polynomial is empty");
  return breaks_.front();
}

double PiecewisePolynomial::end_time() const {
  if (empty()) throw std::logic_error("PiecewisePolynomial::end_time: polynomial is empty");
  return breaks_.back();
}

int PiecewisePolynomial::SegmentIndex(double t) const {
  // First break strictly greater than t, minus one: right-continuous at interior breaks.
  const auto it = std::upper_bound(breaks_.begin(), breaks_.end(), t);
  const int index = static_cast<int>(it - breaks_.begin()) - 1;
  return std::clamp(index, 0, num_segments() - 1);
}

void PiecewisePolynomial::ValueInto(double t, Eigen::Ref<Eigen::VectorXd> out) const { DerivativeInto(t, 0, out); }

void PiecewisePolynomial::DerivativeInto(double t, int order, Eigen::Ref<Eigen::VectorXd> out) const {
  if (empty()) throw std::logic_error("PiecewisePolynomial: evaluating an empty polynomial");
  if (order < 0 || out.size() != rows_) {
    std::ostringstream msg;
    msg << "PiecewisePolynomial::DerivativeInto: order " << order << " (must be ≥ 0), output size " << out.size()
        << " (must be " << rows_ << ")";
    throw std::invalid_argument(msg.str());
  }
  t = std::clamp(t, breaks_.front(), breaks_.back());
  const int k = SegmentIndex(t);
  const Eigen::MatrixXd& C = coefficients_[k];
  const double tau = t - breaks_[k];
  out.setZero();
  // Horner on the order-th derivative: Σ_{j≥order} j!/(j−order)! C_j τ^(j−order).
  for (Eigen::Index j = C.cols() - 1; j >= order; --j) {
    double factor = 1.0;
    for (int i = 0; i < order; ++i) factor *= static_cast<double>(j - i);
    out = out * tau + factor * C.col(j);
  }
}

Eigen::VectorXd PiecewisePolynomial::Value(double t) const {
  Eigen::VectorXd out(rows_);
  ValueInto(t, out);
  return out;
}

Eigen::VectorXd PiecewisePolynomial::Derivative(double t, int order) const {
  Eigen::VectorXd out(rows_);
  DerivativeInto(t, order, out);
  return out;
}

void PiecewisePolynomial::ShiftTime(double offset) {
  for (double& b : breaks_) b += offset;
}

void PiecewisePolynomial::Append(const PiecewisePolynomial& next, double time_offset) {
  if (next.empty()) return;
  if (empty()) {
    *this = next;
    ShiftTime(time_offset);
    return;
  }
  const double next_start = next.breaks_.front() + time_offset;
  const double scale = std::max({1.0, std::abs(end_time()), std::abs(next_start)});
  std::ostringstream msg;
  if (next.rows_ != rows_) {
    msg << "PiecewisePolynomial::Append: rows differ (" << rows_ << " vs " << next.rows_ << ")";
    throw std::invalid_argument(msg.str());
  }
  if (std::abs(next_start - end_time()) > 1e-9 * scale) {
    msg << "PiecewisePolynomial::Append: next starts at " << next_start << " but this ends at " << end_time();
    throw std::invalid_argument(msg.str());
  }
  for (size_t k = 1; k < next.breaks_.size(); ++k) breaks_.push_back(next.breaks_[k] + time_offset);
  coefficients_.insert(coefficients_.end(), next.coefficients_.begin(), next.coefficients_.end());
}

std::function<Eigen::VectorXd(double)> PiecewisePolynomial::AsFunction() const {
  return [copy = *this](double t) { return copy.Value(t); };
}

}  // namespace rome
