#pragma once
// DelayLine: a sampled transport delay of a whole number of periods (sensor latency).
//
// inputs:  u (size)   any signal (units passed through)
// outputs: y (size)   u sampled delay_samples periods earlier: on [k T, (k+1) T), y = u((k − N) T) for k >= N, and
//                     `initial_value` before that (T = period_s, N = delay_samples >= 1). A periodic consumer that
//                     samples y at k T (a controller at the same period and offset: updates due at one time all
//                     read the pre-update state) therefore sees u((k − N) T): a latency of exactly N T.
// discrete state (N size + 1): a ring buffer of the last N samples and the index of the oldest; preallocated, so the
//   update allocates nothing.

#include <string>

#include <Eigen/Core>

#include "framework/system.h"

namespace rome {

struct DelayLineParams {
  double period_s = 1e-3;  ///< [s] T, sample period (ours: the controllers' 1 kHz)
  int delay_samples = 1;   ///< N >= 1 periods of delay (latency N T)
  /// Throws std::invalid_argument naming the field and value: period_s in [1e-6, 10] s, delay_samples in [1, 10000].
  void Validate() const;
};

class DelayLine final : public LeafSystem {
 public:
  /// Throws naming the system as params.Validate() does, or if initial_value is empty.
  DelayLine(std::string name, const Eigen::VectorXd& initial_value, DelayLineParams params);
  const DelayLineParams& params() const { return params_; }
  /// Fills the whole history with `value` (size checked): y = value until N new samples have come in (a sensor that
  /// has been reading a constant). `context` is this block's.
  void SetHistory(LeafContext& context, const Eigen::VectorXd& value) const;

 private:
  DelayLineParams params_;
  int size_ = 0;
};

}  // namespace rome
