#pragma once
// PiecewisePolynomial: a vector-valued piecewise polynomial of time, as returned by direct
// collocation (states: cubic Hermite through the node values and the dynamics f(x, u) at the
// nodes; inputs: first-order hold).
//
// Segment k covers [breaks[k], breaks[k+1]] and is stored as coefficients C_k (rows × (degree+1))
// in local time τ = t − breaks[k]:  p(t) = Σ_j C_k(:, j) τ^j.
// Evaluation is right-continuous at interior breaks (a hybrid jump at a break shows the
// post-jump value there); t outside [start_time, end_time] is clamped into the interval.
#include <functional>
#include <vector>

#include <Eigen/Dense>

namespace rome {

class PiecewisePolynomial {
 public:
  PiecewisePolynomial() = default;

  // Cubic Hermite interpolant: values and derivatives are rows × num_breaks.
  // Throws std::invalid_argument on size mismatch or non-increasing breaks.
  static PiecewisePolynomial CubicHermite(const Eigen::VectorXd& breaks, const Eigen::MatrixXd& values,
                                          const Eigen::MatrixXd& derivatives);
  // Linear interpolation (first-order hold) between the columns of `values`.
  static PiecewisePolynomial FirstOrderHold(const Eigen::VectorXd& breaks, const Eigen::MatrixXd& values);
  // Piecewise constant: segment k holds values(:, k) (last column used only at end_time).
  static PiecewisePolynomial ZeroOrderHold(const Eigen::VectorXd& breaks, const Eigen::MatrixXd& values);

  bool empty() const { return coefficients_.empty(); }
  int rows() const { return rows_; }
  int num_segments() const { return static_cast<int>(coefficients_.size()); }
  const std::vector<double>& breaks() const { return breaks_; }
  double start_time() const;
  double end_time() const;

  Eigen::VectorXd Value(double t) const;
  // d^order p / dt^order (order ≥ 0).
  Eigen::VectorXd Derivative(double t, int order = 1) const;
  // Allocation-free variants for control loops: `out` must have size rows().
  void ValueInto(double t, Eigen::Ref<Eigen::VectorXd> out) const;
  void DerivativeInto(double t, int order, Eigen::Ref<Eigen::VectorXd> out) const;

  // Adds `offset` to every break.
  void ShiftTime(double offset);
  // Appends `next` after shifting it by `time_offset`; the shifted start must equal end_time()
  // (relative tolerance 1e-9) and rows must match. Appending to an empty polynomial copies.
  void Append(const PiecewisePolynomial& next, double time_offset = 0.0);

  // A self-contained copy as t ↦ Value(t) (for trajectory-source blocks).
  std::function<Eigen::VectorXd(double)> AsFunction() const;

 private:
  PiecewisePolynomial(std::vector<double> breaks, std::vector<Eigen::MatrixXd> coefficients);
  int SegmentIndex(double t) const;

  int rows_ = 0;
  std::vector<double> breaks_;
  std::vector<Eigen::MatrixXd> coefficients_;
};

}  // namespace rome
