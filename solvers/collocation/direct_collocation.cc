#include "solvers/collocation/direct_collocation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "solvers/collocation/collocation_nlp.h"

namespace rome {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

}  // namespace

using namespace collocation_internal;

DirectCollocation::DirectCollocation(std::string name, std::vector<CollocationPhase> phases)
    : name_(std::move(name)), phases_(std::move(phases)) {
  std::ostringstream msg;
  if (phases_.empty()) { throw std::invalid_argument("DirectCollocation '" + name_ + "': needs at least one phase"); }
  for (size_t p = 0; p < phases_.size(); ++p) {
    CollocationPhase& ph = phases_[p];
    if (ph.name.empty()) ph.name = "phase" + std::to_string(p);
    const std::string who = "DirectCollocation '" + name_ + "', phase '" + ph.name + "': ";
    auto fail = [&](const std::string& what) { throw std::invalid_argument(who + what); };
    if (ph.num_states < 1) fail("num_states must be ≥ 1, got " + std::to_string(ph.num_states));
    if (ph.num_inputs < 0) fail("num_inputs must be ≥ 0, got " + std::to_string(ph.num_inputs));
    if (ph.num_nodes < 2) fail("num_nodes must be ≥ 2, got " + std::to_string(ph.num_nodes));
    if (ph.num_states + ph.num_inputs > kMaxNodeVariables) {
      fail("num_states + num_inputs must be ≤ " + std::to_string(kMaxNodeVariables) + " (kMaxNodeVariables), got " +
           std::to_string(ph.num_states + ph.num_inputs));
    }
    if (!ph.dynamics) fail("dynamics function is empty");
    if (!(ph.min_duration > 0.0) || !(ph.max_duration >= ph.min_duration) || !std::isfinite(ph.max_duration)) {
      std::ostringstream m;
      m << "durations must satisfy 0 < min_duration ≤ max_duration < ∞, got [" << ph.min_duration << ", "
        << ph.max_duration << "] s";
      fail(m.str());
    }
    auto check_bounds = [&](Eigen::VectorXd& lo, Eigen::VectorXd& hi, int n, const char* what) {
      if (lo.size() == 0) lo = Eigen::VectorXd::Constant(n, -kInf);
      if (hi.size() == 0) hi = Eigen::VectorXd::Constant(n, kInf);
      if (lo.size() != n || hi.size() != n) {
        std::ostringstream m;
        m << what << " bounds must have size " << n << " (or be empty), got " << lo.size() << " and " << hi.size();
        fail(m.str());
      }
      for (int i = 0; i < n; ++i) {
        if (!(lo(i) <= hi(i))) {
          std::ostringstream m;
          m << what << " bound " << i << ": lower " << lo(i) << " > upper " << hi(i);
          fail(m.str());
        }
      }
    };
    check_bounds(ph.state_lower, ph.state_upper, ph.num_states, "state");
    check_bounds(ph.input_lower, ph.input_upper, ph.num_inputs, "input");
  }
  transitions_.resize(phases_.size() - 1);
  guesses_.resize(phases_.size());
}

DirectCollocation::~DirectCollocation() = default;

const CollocationPhase& DirectCollocation::phase(int p) const {
  if (p < 0 || p >= num_phases()) {
    throw std::out_of_range("DirectCollocation '" + name_ + "': no phase " + std::to_string(p));
  }
  return phases_[p];
}

int DirectCollocation::NodeIndex(int p, int node, const char* who) const {
  const int N = phase(p).num_nodes;
  const int k = node < 0 ? N + node : node;
  if (k < 0 || k >= N) {
    std::ostringstream msg;
    msg << "DirectCollocation '" << name_ << "'::" << who << ": phase '" << phases_[p].name << "' has " << N
        << " nodes, node " << node << " is out of range";
    throw std::out_of_range(msg.str());
  }
  return k;
}

namespace {

void CheckConstraintBounds(const std::string& who, int size, const Eigen::VectorXd& lower,
                           const Eigen::VectorXd& upper) {
  std::ostringstream msg;
  if (size < 1 || lower.size() != size || upper.size() != size) {
    msg << who << ": size " << size << " with bounds of size " << lower.size() << "/" << upper.size();
    throw std::invalid_argument(msg.str());
  }
  for (int i = 0; i < size; ++i) {
    if (!(lower(i) <= upper(i))) {
      msg << who << ": bound " << i << " has lower " << lower(i) << " > upper " << upper(i);
      throw std::invalid_argument(msg.str());
    }
  }
}

}  // namespace

void DirectCollocation::AddPathConstraint(int p, int size, StateInputFunction g, const Eigen::VectorXd& lower,
                                          const Eigen::VectorXd& upper, std::string name) {
  phase(p);
  const std::string who = "DirectCollocation '" + name_ + "': path constraint '" + name + "'";
  CheckConstraintBounds(who, size, lower, upper);
  if (!g) throw std::invalid_argument(who + ": function is empty");
  path_constraints_.push_back({p, kEveryNode, size, std::move(g), lower, upper, std::move(name)});
}

void DirectCollocation::AddNodeConstraint(int p, int node, int size, StateInputFunction c, const Eigen::VectorXd& lower,
                                          const Eigen::VectorXd& upper, std::string name) {
  const int k = NodeIndex(p, node, "AddNodeConstraint");
  const std::string who = "DirectCollocation '" + name_ + "': node constraint '" + name + "'";
  CheckConstraintBounds(who, size, lower, upper);
  if (!c) throw std::invalid_argument(who + ": function is empty");
  node_constraints_.push_back({p, k, size, std::move(c), lower, upper, std::move(name)});
}

void DirectCollocation::SetNodeStateBounds(int p, int node, const Eigen::VectorXd& lower,
                                           const Eigen::VectorXd& upper) {
  const int k = NodeIndex(p, node, "SetNodeStateBounds");
  CheckConstraintBounds("DirectCollocation '" + name_ + "'::SetNodeStateBounds, phase '" + phases_[p].name + "'",
                        phases_[p].num_states, lower, upper);
  node_bounds_.push_back({p, k, lower, upper});
}

void DirectCollocation::SetTransition(int p, StateFunction reset) {
  if (p < 0 || p + 1 >= num_phases()) {
    std::ostringstream msg;
    msg << "DirectCollocation '" << name_ << "'::SetTransition: phase " << p << " has no successor (" << num_phases()
        << " phases)";
    throw std::out_of_range(msg.str());
  }
  transitions_[p] = std::move(reset);
}

void DirectCollocation::SetPeriodicTransition(StateFunction reset) {
  if (!reset) {
    throw std::invalid_argument("DirectCollocation '" + name_ + "'::SetPeriodicTransition: function is empty");
  }
  periodic_transition_ = std::move(reset);
}

void DirectCollocation::SetExactHessian(bool exact) { exact_hessian_ = exact; }

void DirectCollocation::SetTerminalCost(ScalarStateInputFunction cost) { terminal_cost_ = std::move(cost); }

void DirectCollocation::SetInitialGuess(int p, const Eigen::MatrixXd& states, const Eigen::MatrixXd& inputs,
                                        double duration) {
  const CollocationPhase& ph = phase(p);
  if (states.rows() != ph.num_states || states.cols() != ph.num_nodes || inputs.rows() != ph.num_inputs ||
      inputs.cols() != ph.num_nodes || !(duration > 0.0)) {
    std::ostringstream msg;
    msg << "DirectCollocation '" << name_ << "'::SetInitialGuess, phase '" << ph.name << "': expected states "
        << ph.num_states << "x" << ph.num_nodes << ", inputs " << ph.num_inputs << "x" << ph.num_nodes
        << ", duration > 0; got " << states.rows() << "x" << states.cols() << ", " << inputs.rows() << "x"
        << inputs.cols() << ", " << duration;
    throw std::invalid_argument(msg.str());
  }
  guesses_[p] = {states, inputs, duration, true};
}

std::unique_ptr<NlpProblem> DirectCollocation::BuildNlp() const {
  for (size_t p = 0; p + 1 < phases_.size(); ++p) {
    if (!transitions_[p] && phases_[p].num_states != phases_[p + 1].num_states) {
      std::ostringstream msg;
      msg << "DirectCollocation '" << name_ << "': phases '" << phases_[p].name << "' (" << phases_[p].num_states
          << " states) and '" << phases_[p + 1].name << "' (" << phases_[p + 1].num_states
          << " states) need a transition map (SetTransition)";
      throw std::invalid_argument(msg.str());
    }
  }
  int num_variables = 0;
  const std::vector<PhaseLayout> layout = MakeLayout(phases_, &num_variables);
  int num_constraints = 0;
  for (const auto& L : layout) num_constraints += (L.N - 1) * L.nx;
  for (size_t p = 1; p < layout.size(); ++p) num_constraints += layout[p].nx;
  if (periodic_transition_) num_constraints += layout.front().nx;
  std::vector<NodeConstraint> constraints = path_constraints_;
  constraints.insert(constraints.end(), node_constraints_.begin(), node_constraints_.end());
  Eigen::VectorXd g_lower(0), g_upper(0);
  std::vector<double> lo, hi;
  for (const auto& c : constraints) {
    const int count = c.node == kEveryNode ? layout[c.phase].N : 1;
    for (int k = 0; k < count; ++k) {
      lo.insert(lo.end(), c.lower.data(), c.lower.data() + c.size);
      hi.insert(hi.end(), c.upper.data(), c.upper.data() + c.size);
    }
  }
  const int num_dynamic = num_constraints;
  num_constraints += static_cast<int>(lo.size());

  std::unique_ptr<NlpProblem> nlp =
      MakeCollocationNlp(name_, phases_, layout, num_variables, num_constraints, constraints, transitions_,
                         periodic_transition_, terminal_cost_, InitialGuessVector(), exact_hessian_);
  Eigen::VectorXd gl = Eigen::VectorXd::Zero(num_constraints);
  Eigen::VectorXd gu = Eigen::VectorXd::Zero(num_constraints);
  for (size_t i = 0; i < lo.size(); ++i) {
    gl(num_dynamic + i) = lo[i];
    gu(num_dynamic + i) = hi[i];
  }
  nlp->SetConstraintBounds(gl, gu);

  Eigen::VectorXd xl(num_variables), xu(num_variables);
  for (size_t p = 0; p < phases_.size(); ++p) {
    const CollocationPhase& ph = phases_[p];
    const PhaseLayout& L = layout[p];
    for (int k = 0; k < L.N; ++k) {
      xl.segment(L.x(k), L.nx) = ph.state_lower;
      xu.segment(L.x(k), L.nx) = ph.state_upper;
      xl.segment(L.u(k), L.nu) = ph.input_lower;
      xu.segment(L.u(k), L.nu) = ph.input_upper;
    }
    if (L.T_index >= 0) {
      xl(L.T_index) = ph.min_duration;
      xu(L.T_index) = ph.max_duration;
    }
  }
  for (const auto& b : node_bounds_) {
    const PhaseLayout& L = layout[b.phase];
    for (int i = 0; i < L.nx; ++i) {
      const int v = L.x(b.node) + i;
      xl(v) = std::max(xl(v), b.lower(i));
      xu(v) = std::min(xu(v), b.upper(i));
      if (xl(v) > xu(v)) {
        std::ostringstream msg;
        msg << "DirectCollocation '" << name_ << "': state " << i << " at node " << b.node << " of phase '"
            << phases_[b.phase].name << "' has empty bounds [" << xl(v) << ", " << xu(v) << "]";
        throw std::invalid_argument(msg.str());
      }
    }
  }
  nlp->SetVariableBounds(xl, xu);
  return nlp;
}

Eigen::VectorXd DirectCollocation::InitialGuessVector() const {
  int num_variables = 0;
  const std::vector<PhaseLayout> layout = MakeLayout(phases_, &num_variables);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(num_variables);
  for (size_t p = 0; p < phases_.size(); ++p) {
    const CollocationPhase& ph = phases_[p];
    const PhaseLayout& L = layout[p];
    const Guess& guess = guesses_[p];
    for (int k = 0; k < L.N; ++k) {
      if (guess.set) {
        z.segment(L.x(k), L.nx) = guess.states.col(k);
        z.segment(L.u(k), L.nu) = guess.inputs.col(k);
      } else {
        z.segment(L.x(k), L.nx) = Eigen::VectorXd::Zero(L.nx).cwiseMax(ph.state_lower).cwiseMin(ph.state_upper);
        z.segment(L.u(k), L.nu) = Eigen::VectorXd::Zero(L.nu).cwiseMax(ph.input_lower).cwiseMin(ph.input_upper);
      }
    }
    if (L.T_index >= 0) {
      z(L.T_index) = guess.set ? std::clamp(guess.duration, ph.min_duration, ph.max_duration)
                               : 0.5 * (ph.min_duration + ph.max_duration);
    }
  }
  // Node bounds (boundary conditions) are applied to the default guess as well.
  for (const auto& b : node_bounds_) {
    const PhaseLayout& L = layout[b.phase];
    z.segment(L.x(b.node), L.nx) = z.segment(L.x(b.node), L.nx).cwiseMax(b.lower).cwiseMin(b.upper);
  }
  return z;
}

CollocationResult DirectCollocation::Unpack(const Eigen::VectorXd& z) const {
  int num_variables = 0;
  const std::vector<PhaseLayout> layout = MakeLayout(phases_, &num_variables);
  if (z.size() != num_variables) {
    std::ostringstream msg;
    msg << "DirectCollocation '" << name_ << "'::Unpack: decision vector has size " << z.size() << ", expected "
        << num_variables;
    throw std::invalid_argument(msg.str());
  }
  CollocationResult result;
  double t0 = 0.0;
  Eigen::VectorXd value;
  Eigen::MatrixXd J;
  for (size_t p = 0; p < phases_.size(); ++p) {
    const CollocationPhase& ph = phases_[p];
    const PhaseLayout& L = layout[p];
    CollocationPhaseSolution s;
    s.name = ph.name;
    s.start_time = t0;
    s.duration = L.T_index >= 0 ? z(L.T_index) : L.fixed_T;
    const double h = s.duration / (L.N - 1);
    s.times = Eigen::VectorXd::LinSpaced(L.N, t0, t0 + s.duration);
    s.states.resize(L.nx, L.N);
    s.inputs.resize(L.nu, L.N);
    s.state_derivatives.resize(L.nx, L.N);
    for (int k = 0; k < L.N; ++k) {
      s.states.col(k) = z.segment(L.x(k), L.nx);
      s.inputs.col(k) = z.segment(L.u(k), L.nu);
      EvalWithJacobian(ph.dynamics, L.nx, s.states.col(k), s.inputs.col(k), "dynamics of phase '" + ph.name + "'",
                       &value, &J);
      s.state_derivatives.col(k) = value;
    }
    for (int k = 0; k + 1 < L.N; ++k) {
      Eigen::VectorXd slope = 0.5 * (s.state_derivatives.col(k) + s.state_derivatives.col(k + 1));
      if (ph.method == CollocationMethod::kHermiteSimpson) {
        const Eigen::VectorXd x_c = 0.5 * (s.states.col(k) + s.states.col(k + 1)) +
                                    (h / 8.0) * (s.state_derivatives.col(k) - s.state_derivatives.col(k + 1));
        const Eigen::VectorXd u_c = 0.5 * (s.inputs.col(k) + s.inputs.col(k + 1));
        EvalWithJacobian(ph.dynamics, L.nx, x_c, u_c, "dynamics of phase '" + ph.name + "'", &value, &J);
        slope = (s.state_derivatives.col(k) + 4.0 * value + s.state_derivatives.col(k + 1)) / 6.0;
      }
      const Eigen::VectorXd defect = s.states.col(k + 1) - s.states.col(k) - h * slope;
      result.max_defect = std::max(result.max_defect, defect.cwiseAbs().maxCoeff());
    }
    s.state_trajectory = PiecewisePolynomial::CubicHermite(s.times, s.states, s.state_derivatives);
    if (L.nu > 0) s.input_trajectory = PiecewisePolynomial::FirstOrderHold(s.times, s.inputs);
    t0 += s.duration;
    result.phases.push_back(std::move(s));
  }
  return result;
}

CollocationResult DirectCollocation::Solve(const IpoptSolverOptions& options) const {
  std::unique_ptr<NlpProblem> nlp = BuildNlp();
  IpoptSolverOptions opts = options;
  opts.use_limited_memory_hessian = !exact_hessian_;
  NlpResult nlp_result = IpoptSolver(opts).Solve(*nlp, InitialGuessVector());
  CollocationResult result = Unpack(nlp_result.x);
  result.nlp = std::move(nlp_result);
  return result;
}

namespace {

PiecewisePolynomial Concatenate(const std::vector<CollocationPhaseSolution>& phases, bool states) {
  PiecewisePolynomial joined;
  for (const auto& s : phases) {
    const PiecewisePolynomial& piece = states ? s.state_trajectory : s.input_trajectory;
    if (!joined.empty() && piece.rows() != joined.rows()) {
      std::ostringstream msg;
      msg << "CollocationResult: cannot concatenate " << (states ? "state" : "input") << " trajectories, phase '"
          << s.name << "' has " << piece.rows() << " rows, earlier "
          << "phases " << joined.rows();
      throw std::invalid_argument(msg.str());
    }
    joined.Append(piece);
  }
  return joined;
}

}  // namespace

PiecewisePolynomial CollocationResult::ConcatenatedStateTrajectory() const { return Concatenate(phases, true); }

PiecewisePolynomial CollocationResult::ConcatenatedInputTrajectory() const { return Concatenate(phases, false); }

}  // namespace rome
