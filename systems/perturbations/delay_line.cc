#include "systems/perturbations/delay_line.h"

#include <stdexcept>
#include <string>

namespace rome {

void DelayLineParams::Validate() const {
  if (!(period_s >= 1e-6 && period_s <= 10.0))
    throw std::invalid_argument("DelayLineParams: period_s = " + std::to_string(period_s) +
                                " s is outside [1e-6, 10] s");
  if (!(delay_samples >= 1 && delay_samples <= 10000))
    throw std::invalid_argument("DelayLineParams: delay_samples = " + std::to_string(delay_samples) +
                                " is outside [1, 10000]");
}

DelayLine::DelayLine(std::string name, const Eigen::VectorXd& initial_value, DelayLineParams params)
    : LeafSystem(std::move(name)), params_(params), size_(static_cast<int>(initial_value.size())) {
  try {
    params_.Validate();
  } catch (const std::invalid_argument& e) { ThrowError(e.what()); }
  if (size_ == 0) ThrowError("the delayed signal has no elements");
  const int n = size_, N = params_.delay_samples;
  // [sample 0; ...; sample N-1; index of the oldest sample]
  Eigen::VectorXd x0(N * n + 1);
  for (int k = 0; k < N; ++k) x0.segment(k * n, n) = initial_value;
  x0[N * n] = 0.0;
  DeclareDiscreteState(x0);
  DeclareInputPort("u", n);
  DeclarePeriodicDiscreteUpdate(params_.period_s, 0.0, [this, n, N](const LeafContext& c, Eigen::VectorXd* xd) {
    // The oldest sample leaves (it was output until now); the new one takes its slot, the next slot becomes oldest.
    const int oldest = static_cast<int>(c.discrete_state()[N * n]);
    xd->segment(oldest * n, n) = EvalInput(c, 0);
    (*xd)[N * n] = (oldest + 1) % N;
    return EventStatus::Succeeded();
  });
  DeclareOutputPort(
      "y", n,
      [n, N](const LeafContext& c, Eigen::VectorXd* y) {
        const int oldest = static_cast<int>(c.discrete_state()[N * n]);
        *y = c.discrete_state().segment(oldest * n, n);
      },
      Feedthrough::None());
}

void DelayLine::SetHistory(LeafContext& context, const Eigen::VectorXd& value) const {
  if (value.size() != size_)
    ThrowError("SetHistory: the value has " + std::to_string(value.size()) + " elements, the signal " +
               std::to_string(size_));
  Eigen::VectorXd& xd = context.get_mutable_discrete_state();
  for (int k = 0; k < params_.delay_samples; ++k) xd.segment(k * size_, size_) = value;
  xd[params_.delay_samples * size_] = 0.0;
}

}  // namespace rome
