#pragma once
// PreImpactSampler: the pre-impact COM state of a walking run, for the acceptance's step-to-step convergence check.
//
// A monitor samples the COM state relative to the stance foot, [x, y, z, ẋ, ẏ, ż] (m, m/s; y mirrored in right
// stance), after every integrator step in single support (Record). The integrator ends a step exactly at the
// touchdown, so the last sample lies up to one step (here ≤ 1 ms, the control period) before it; at 1 m/s² of
// vertical acceleration that is 1e-3 m/s of jitter in ż, and the check compares consecutive steps. At(t_touchdown)
// extrapolates linearly through the last two samples to the touchdown time (error O(dt²)).
#include <Eigen/Core>

namespace rome {

class PreImpactSampler {
 public:
  using State = Eigen::Matrix<double, 6, 1>;
  void Record(double t, const State& state) {
    if (count_ > 0 && t <= t_last_) {  // a repeated instant (a sample at an event) replaces the last one
      last_ = state;
      return;
    }
    t_prev_ = t_last_, prev_ = last_;
    t_last_ = t, last_ = state;
    ++count_;
  }
  /// The state extrapolated to time t ≥ the last sample (the last sample itself with fewer than two samples).
  State At(double t) const {
    if (count_ < 2 || !(t_last_ > t_prev_)) return last_;
    return last_ + (last_ - prev_) * ((t - t_last_) / (t_last_ - t_prev_));
  }

 private:
  double t_prev_ = 0.0, t_last_ = 0.0;
  State prev_ = State::Zero(), last_ = State::Zero();
  long count_ = 0;
};

}  // namespace rome
