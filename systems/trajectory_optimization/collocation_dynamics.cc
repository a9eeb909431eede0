#include "systems/trajectory_optimization/collocation_dynamics.h"

#include <algorithm>
#include <memory>
#include <stdexcept>

namespace rome {

namespace {

[[noreturn]] void Fail(const LeafSystem& system, const std::string& what) {
  throw std::invalid_argument("CollocationDynamicsFromSystem: system '" + system.name() + "': " + what);
}

Eigen::VectorXd Values(const NodeVector& v) {
  Eigen::VectorXd out(v.size());
  for (Eigen::Index i = 0; i < v.size(); ++i) out[i] = v[i].value();
  return out;
}

// Rows: the derivative vectors of v (size nd; an empty one is a constant, a zero row).
Eigen::MatrixXd Seeds(const NodeVector& v, Eigen::Index nd) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(v.size(), nd);
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (v[i].derivatives().size() == nd) out.row(i) = v[i].derivatives().transpose();
  return out;
}

Eigen::Index NumDerivatives(const NodeVector& x, const NodeVector& u) {
  Eigen::Index nd = 0;
  for (Eigen::Index i = 0; i < x.size(); ++i) nd = std::max(nd, x[i].derivatives().size());
  for (Eigen::Index i = 0; i < u.size(); ++i) nd = std::max(nd, u[i].derivatives().size());
  return nd;
}

}  // namespace

StateInputFunction CollocationDynamicsFromSystem(const LeafSystem& system, const LeafContext& context,
                                                 const std::string& input_port, const LinearizeParams& params) {
  if (&context.system() != &system) Fail(system, "was given the context of system '" + context.system().name() + "'");
  const int n = system.num_continuous_states();
  if (n == 0) Fail(system, "has no continuous state; collocation needs xdot = f(x, u)");
  int input = -1;
  if (!input_port.empty()) {
    input = system.GetInputPortIndex(input_port);  // names the ports the system has
    if (!system.input_port(input).is_vector())
      Fail(system,
           "input port '" + input_port + "' carries " + system.input_port(input).TypeString() + ", not a vector");
  }
  const int m = input >= 0 ? system.input_port(input).size : 0;
  std::shared_ptr<LeafContext> own;
  try {
    own.reset(static_cast<LeafContext*>(context.Clone().release()));
  } catch (const std::logic_error& e) {
    Fail(system, std::string("needs a context of its own, not one wired into a diagram (") + e.what() + ")");
  }
  if (input >= 0) system.FixInputPort(*own, input, Eigen::VectorXd::Zero(m));

  return [&system, own, input, input_port, params, n, m](const NodeVector& x, const NodeVector& u, NodeVector& y) {
    if (x.size() != n)
      Fail(system,
           "x has size " + std::to_string(x.size()) + ", the system has " + std::to_string(n) + " continuous states");
    if (u.size() != m)
      Fail(system, "u has size " + std::to_string(u.size()) + ", input port '" + input_port + "' has size " +
                       std::to_string(m));
    own->get_mutable_continuous_state() = Values(x);
    if (input >= 0) system.FixInputPort(*own, input, Values(u));
    const Eigen::Index nd = NumDerivatives(x, u);
    y.resize(n);
    if (nd == 0) {
      Eigen::VectorXd xdot;
      system.CalcTimeDerivatives(*own, &xdot);
      if (xdot.size() != n)
        Fail(system,
             "DoCalcTimeDerivatives produced size " + std::to_string(xdot.size()) + ", expected " + std::to_string(n));
      for (int i = 0; i < n; ++i) y[i] = NodeScalar(xdot[i]);
      return;
    }
    const LinearSystemMatrices lin = Linearize(system, *own, input_port, "", params);
    // Chain rule: dẋ/dseeds = A dx/dseeds + B du/dseeds.
    Eigen::MatrixXd dy = lin.A * Seeds(x, nd);
    if (m > 0) dy += lin.B * Seeds(u, nd);
    for (int i = 0; i < n; ++i) {
      y[i].value() = lin.xdot0[i];
      y[i].derivatives() = dy.row(i).transpose();
    }
  };
}

}  // namespace rome
