#pragma once
// Primitive blocks used by every diagram.
//
// ConstantVectorSource   outputs: y (n)                      y = value
// Gain                   inputs: u (n)         outputs: y (m)  y = K u            (direct feedthrough)
// Adder                  inputs: u0..u{k-1} (n) outputs: sum (n)                  (direct feedthrough)
// Multiplexer            inputs: u0..u{k-1} (n_i) outputs: y (sum n_i) stacked   (direct feedthrough)
// Demultiplexer          inputs: u (sum n_i)  outputs: y0..y{k-1} (n_i)           (direct feedthrough)
// ZeroOrderHold          inputs: u (n)         outputs: y (n)  y = u(t_k) held over [t_k, t_k + period)
// TrajectorySource       outputs: y (n) [, ydot (n)]          y = trajectory(t)
// Saturation             inputs: u (n)         outputs: y (n)  y_i = min(max(u_i, lower_i), upper_i) (direct
// feedthrough)

#include <functional>
#include <string>
#include <vector>

#include "framework/system.h"

namespace rome {

class ConstantVectorSource final : public LeafSystem {
 public:
  ConstantVectorSource(std::string name, const Eigen::VectorXd& value);
};

class Gain final : public LeafSystem {
 public:
  /// y = k u with a scalar gain.
  Gain(std::string name, double k, int size);
  /// y = K u with a matrix gain.
  Gain(std::string name, const Eigen::MatrixXd& K);
};

class Adder final : public LeafSystem {
 public:
  Adder(std::string name, int num_inputs, int size);
};

class Multiplexer final : public LeafSystem {
 public:
  Multiplexer(std::string name, std::vector<int> input_sizes);
};

class Demultiplexer final : public LeafSystem {
 public:
  Demultiplexer(std::string name, std::vector<int> output_sizes);
};

/// Clamps each element of u to [lower_i, upper_i] (e.g. a controller's torques to the actuators' limits). A bound may
/// be ±infinity; a NaN input stays NaN (it is never clamped into a plausible value). The constructor throws, naming the
/// system and the element, when a lower bound exceeds its upper bound, a bound is NaN, or the sizes differ.
class Saturation final : public LeafSystem {
 public:
  Saturation(std::string name, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper);
  /// The same symmetric limit on every element: y_i = min(max(u_i, -limit), limit).
  Saturation(std::string name, double limit, int size);
  const Eigen::VectorXd& lower() const { return lower_; }
  const Eigen::VectorXd& upper() const { return upper_; }

 private:
  Eigen::VectorXd lower_, upper_;
};

class ZeroOrderHold final : public LeafSystem {
 public:
  /// Samples u at t = offset + k * period and holds it. `initial_value` is output before the first sample.
  ZeroOrderHold(std::string name, double period_s, int size, double offset_s = 0.0);
  ZeroOrderHold(std::string name, double period_s, const Eigen::VectorXd& initial_value, double offset_s = 0.0);
};

/// Plays back y(t) (and optionally ẏ(t)) from functions of time that write into a preallocated vector, so
/// evaluation allocates nothing. Wrap any trajectory (e.g. a collocation PiecewisePolynomial) this way.
class TrajectorySource final : public LeafSystem {
 public:
  using Function = std::function<void(double t, Eigen::Ref<Eigen::VectorXd> out)>;
  TrajectorySource(std::string name, int size, Function value, Function derivative = nullptr);
  /// Convenience for functions returning a vector (allocates per call).
  static std::unique_ptr<TrajectorySource> FromFunction(std::string name, int size,
                                                        std::function<Eigen::VectorXd(double)> value,
                                                        std::function<Eigen::VectorXd(double)> derivative = nullptr);
};

}  // namespace rome
