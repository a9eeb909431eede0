#include "framework/primitives.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace rome {

namespace {
// Port name "<prefix><index>". (Built with append: GCC 12 warns falsely about operator+ here, -Wrestrict.)
std::string Indexed(const char* prefix, size_t i) {
  std::string s(prefix);
  s.append(std::to_string(i));
  return s;
}
}  // namespace

ConstantVectorSource::ConstantVectorSource(std::string name, const Eigen::VectorXd& value)
    : LeafSystem(std::move(name)) {
  DeclareOutputPort(
      "y", static_cast<int>(value.size()), [value](const LeafContext&, Eigen::VectorXd* y) { *y = value; },
      Feedthrough::None());
}

Gain::Gain(std::string name, double k, int size) : LeafSystem(std::move(name)) {
  DeclareInputPort("u", size);
  DeclareOutputPort("y", size, [this, k](const LeafContext& c, Eigen::VectorXd* y) { *y = k * EvalInput(c, 0); });
}

Gain::Gain(std::string name, const Eigen::MatrixXd& K) : LeafSystem(std::move(name)) {
  DeclareInputPort("u", static_cast<int>(K.cols()));
  DeclareOutputPort("y", static_cast<int>(K.rows()),
                    [this, K](const LeafContext& c, Eigen::VectorXd* y) { y->noalias() = K * EvalInput(c, 0); });
}

namespace {

std::string FormatDouble(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

}  // namespace

Saturation::Saturation(std::string name, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper)
    : LeafSystem(std::move(name)), lower_(lower), upper_(upper) {
  if (lower.size() != upper.size())
    ThrowError("lower bounds have " + std::to_string(lower.size()) + " elements but upper bounds " +
               std::to_string(upper.size()));
  if (lower.size() == 0) ThrowError("a saturation needs at least one element");
  for (Eigen::Index i = 0; i < lower.size(); ++i) {
    if (std::isnan(lower[i]) || std::isnan(upper[i]) || lower[i] > upper[i])
      ThrowError("element " + std::to_string(i) + ": bounds [" + FormatDouble(lower[i]) + ", " +
                 FormatDouble(upper[i]) + "] are not an interval (need lower <= upper, neither NaN)");
  }
  DeclareInputPort("u", static_cast<int>(lower.size()));
  DeclareOutputPort("y", static_cast<int>(lower.size()), [this](const LeafContext& c, Eigen::VectorXd* y) {
    const Eigen::VectorXd& u = EvalInput(c, 0);
    for (Eigen::Index i = 0; i < u.size(); ++i)
      (*y)[i] = std::isnan(u[i]) ? u[i] : std::min(std::max(u[i], lower_[i]), upper_[i]);
  });
}

Saturation::Saturation(std::string name, double limit, int size)
    : Saturation(std::move(name), Eigen::VectorXd::Constant(std::max(size, 0), -limit),
                 Eigen::VectorXd::Constant(std::max(size, 0), limit)) {}

Adder::Adder(std::string name, int num_inputs, int size) : LeafSystem(std::move(name)) {
  if (num_inputs < 1) ThrowError("an adder needs at least one input, got " + std::to_string(num_inputs));
  for (int i = 0; i < num_inputs; ++i) DeclareInputPort(Indexed("u", i), size);
  DeclareOutputPort("sum", size, [this, num_inputs](const LeafContext& c, Eigen::VectorXd* y) {
    *y = EvalInput(c, 0);
    for (int i = 1; i < num_inputs; ++i) *y += EvalInput(c, i);
  });
}

Multiplexer::Multiplexer(std::string name, std::vector<int> input_sizes) : LeafSystem(std::move(name)) {
  for (size_t i = 0; i < input_sizes.size(); ++i) DeclareInputPort(Indexed("u", i), input_sizes[i]);
  const int total = std::accumulate(input_sizes.begin(), input_sizes.end(), 0);
  DeclareOutputPort("y", total, [this, input_sizes](const LeafContext& c, Eigen::VectorXd* y) {
    int at = 0;
    for (size_t i = 0; i < input_sizes.size(); ++i) {
      y->segment(at, input_sizes[i]) = EvalInput(c, static_cast<int>(i));
      at += input_sizes[i];
    }
  });
}

Demultiplexer::Demultiplexer(std::string name, std::vector<int> output_sizes) : LeafSystem(std::move(name)) {
  const int total = std::accumulate(output_sizes.begin(), output_sizes.end(), 0);
  DeclareInputPort("u", total);
  int at = 0;
  for (size_t i = 0; i < output_sizes.size(); ++i) {
    const int n = output_sizes[i];
    DeclareOutputPort(Indexed("y", i), n,
                      [this, at, n](const LeafContext& c, Eigen::VectorXd* y) { *y = EvalInput(c, 0).segment(at, n); });
    at += n;
  }
}

ZeroOrderHold::ZeroOrderHold(std::string name, double period_s, int size, double offset_s)
    : ZeroOrderHold(std::move(name), period_s, Eigen::VectorXd::Zero(size), offset_s) {}

ZeroOrderHold::ZeroOrderHold(std::string name, double period_s, const Eigen::VectorXd& initial_value, double offset_s)
    : LeafSystem(std::move(name)) {
  const int size = static_cast<int>(initial_value.size());
  DeclareInputPort("u", size);
  DeclareDiscreteState(initial_value);
  DeclarePeriodicDiscreteUpdate(period_s, offset_s, [this](const LeafContext& c, Eigen::VectorXd* xd) {
    *xd = EvalInput(c, 0);
    return EventStatus::Succeeded();
  });
  DeclareOutputPort(
      "y", size, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state(); }, Feedthrough::None());
}

TrajectorySource::TrajectorySource(std::string name, int size, Function value, Function derivative)
    : LeafSystem(std::move(name)) {
  if (!value) ThrowError("trajectory source needs a value function");
  DeclareOutputPort(
      "y", size, [value](const LeafContext& c, Eigen::VectorXd* y) { value(c.time(), *y); }, Feedthrough::None());
  if (derivative)
    DeclareOutputPort(
        "ydot", size, [derivative](const LeafContext& c, Eigen::VectorXd* y) { derivative(c.time(), *y); },
        Feedthrough::None());
}

std::unique_ptr<TrajectorySource> TrajectorySource::FromFunction(std::string name, int size,
                                                                 std::function<Eigen::VectorXd(double)> value,
                                                                 std::function<Eigen::VectorXd(double)> derivative) {
  Function v = [value](double t, Eigen::Ref<Eigen::VectorXd> out) { out = value(t); };
  Function d = nullptr;
  if (derivative) d = [derivative](double t, Eigen::Ref<Eigen::VectorXd> out) { out = derivative(t); };
  return std::make_unique<TrajectorySource>(std::move(name), size, std::move(v), std::move(d));
}

}  // namespace rome
