#include "framework/linearize.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "framework/diagram.h"

namespace rome {

namespace {

[[noreturn]] void Fail(const System& system, const std::string& what) {
  throw std::invalid_argument("Linearize: system '" + system.name() + "': " + what);
}

// The continuous state of a leaf system or a diagram as one vector (leaves in diagram order), read and written
// element by element in place, and its time derivative.
class StackedState {
 public:
  StackedState(const System& system, Context& context) : system_(system) {
    if (system.is_diagram() != context.is_diagram_context())
      Fail(system, std::string("was given a ") + (context.is_diagram_context() ? "diagram" : "leaf") + " context");
    if (system.is_diagram()) {
      const auto& diagram = static_cast<const Diagram&>(system);
      for (int i = 0; i < diagram.num_leaves(); ++i)
        Add(diagram.leaf(i), diagram.GetMutableSubsystemContext(diagram.leaf(i), context), diagram.leaf_path(i));
    } else {
      auto& leaf_context = static_cast<LeafContext&>(context);
      if (&leaf_context.system() != &system)
        Fail(system, "was given the context of system '" + leaf_context.system().name() + "'");
      Add(static_cast<const LeafSystem&>(system), leaf_context, system.name());
    }
  }

  int size() const { return static_cast<int>(element_.size()); }
  double& operator[](int i) {
    const Element& e = element_[i];
    return parts_[e.part].context->get_mutable_continuous_state()[e.offset];
  }
  Eigen::VectorXd Get() const {
    Eigen::VectorXd x(size());
    for (int i = 0; i < size(); ++i) x[i] = parts_[element_[i].part].context->continuous_state()[element_[i].offset];
    return x;
  }
  // f(t, x, u) stacked; sizes checked as the Simulator checks them.
  void CalcDerivatives(Eigen::VectorXd* xdot) {
    xdot->resize(size());
    int offset = 0;
    for (Part& p : parts_) {
      const int n = p.system->num_continuous_states();
      if (n == 0) continue;
      p.system->CalcTimeDerivatives(*p.context, &p.xdot);
      if (p.xdot.size() != n)
        Fail(system_, "DoCalcTimeDerivatives of '" + p.path + "' produced size " + std::to_string(p.xdot.size()) +
                          ", expected " + std::to_string(n));
      xdot->segment(offset, n) = p.xdot;
      offset += n;
    }
  }

 private:
  struct Part {
    const LeafSystem* system;
    LeafContext* context;
    std::string path;
    Eigen::VectorXd xdot;
  };
  struct Element {
    int part;
    int offset;
  };
  void Add(const LeafSystem& leaf, LeafContext& context, const std::string& path) {
    parts_.push_back({&leaf, &context, path, Eigen::VectorXd()});
    for (int k = 0; k < leaf.num_continuous_states(); ++k) element_.push_back({static_cast<int>(parts_.size()) - 1, k});
  }
  const System& system_;
  std::vector<Part> parts_;
  std::vector<Element> element_;
};

int VectorPortIndex(const System& system, const std::string& name, bool input) {
  if (name.empty()) return -1;
  const int index = input ? system.GetInputPortIndex(name) : system.GetOutputPortIndex(name);  // names the ports it has
  const PortInfo& port = input ? system.input_port(index) : system.output_port(index);
  if (!port.is_vector())
    Fail(system, std::string(input ? "input" : "output") + " port '" + name + "' carries " + port.TypeString() +
                     ", not a vector");
  return index;
}

Eigen::VectorXd FixedInput(const System& system, const Context& context, int index) {
  try {
    if (system.is_diagram()) return static_cast<const Diagram&>(system).EvalInput(context, index);
    return static_cast<const LeafSystem&>(system).EvalInput(static_cast<const LeafContext&>(context), index);
  } catch (const std::runtime_error&) {
    Fail(system, "input port '" + system.input_port(index).name +
                     "' has no fixed value; fix it to the operating-point input u0 first");
  }
}

// `where()` describes the point; it is formatted only for the error.
template <class Where>
void CheckFinite(const System& system, const Eigen::VectorXd& v, const char* what, const Where& where) {
  for (int i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i]))
      Fail(system, std::string(what) + "[" + std::to_string(i) + "] is " +
                       (std::isnan(v[i]) ? "NaN"
                        : v[i] > 0       ? "+Inf"
                                         : "-Inf") +
                       " at " + where());
}

std::string OperatingPoint() { return "the operating point"; }

// Puts x0 and u0 back (the same bits) when Linearize returns or throws.
struct Restore {
  StackedState& state;
  const System& system;
  Context& context;
  const Eigen::VectorXd x0;  // copies: the result's x0 and u0 may be moved out before this runs
  const Eigen::VectorXd u0;
  int input;
  bool input_changed = false;  // set once a perturbed u was fixed (a connected input refuses the first one)
  ~Restore() {
    for (int i = 0; i < state.size(); ++i) state[i] = x0[i];
    try {
      if (input_changed) system.FixInputPort(context, input, u0);  // the port took a value of this size before
    } catch (...) {                                                // never throw from a destructor
    }
  }
};

}  // namespace

LinearSystemMatrices Linearize(const System& system, Context& context, const std::string& input_port,
                               const std::string& output_port, const LinearizeParams& params) {
  if (!(params.step_scale > 0) || !std::isfinite(params.step_scale))
    Fail(system, "LinearizeParams::step_scale must be positive and finite, got " + std::to_string(params.step_scale));
  const int input = VectorPortIndex(system, input_port, true);
  const int output = VectorPortIndex(system, output_port, false);
  StackedState state(system, context);
  if (state.size() == 0) Fail(system, "has no continuous state; Linearize needs xdot = f(t, x, u) to form A and B");

  LinearSystemMatrices lin;
  lin.time = context.time();
  lin.x0 = state.Get();
  if (input >= 0) lin.u0 = FixedInput(system, context, input);
  const int n = state.size(), m = static_cast<int>(lin.u0.size());
  const int p = output >= 0 ? system.output_port(output).size : 0;
  CheckFinite(system, lin.x0, "state x", OperatingPoint);
  CheckFinite(system, lin.u0, "input u", OperatingPoint);
  state.CalcDerivatives(&lin.xdot0);
  CheckFinite(system, lin.xdot0, "time derivative xdot", OperatingPoint);
  if (output >= 0) {
    lin.y0 = system.EvalOutput(context, output);
    CheckFinite(system, lin.y0, "output y", OperatingPoint);
  }
  lin.A.resize(n, n);
  lin.B.resize(n, m);
  lin.C.resize(p, n);
  lin.D.resize(p, m);

  Restore restore{state, system, context, lin.x0, lin.u0, input};
  Eigen::VectorXd f_plus, f_minus, g_plus(p), g_minus(p), u = lin.u0;
  // Evaluates f and g with element j of z (x if j < n, else u) at z_j + delta.
  auto evaluate = [&](int j, double delta, Eigen::VectorXd* f, Eigen::VectorXd* g) {
    const bool is_state = j < n;
    const auto where = [&] {
      return std::string(is_state ? "x[" : "u[") + std::to_string(is_state ? j : j - n) + "] " +
             (delta > 0 ? "+ " : "- ") + std::to_string(std::abs(delta));
    };
    if (is_state) {
      state[j] = lin.x0[j] + delta;
    } else {
      u[j - n] = lin.u0[j - n] + delta;
      system.FixInputPort(context, input, u);
      restore.input_changed = true;
    }
    state.CalcDerivatives(f);
    CheckFinite(system, *f, "time derivative xdot", where);
    if (output >= 0) {
      *g = system.EvalOutput(context, output);
      CheckFinite(system, *g, "output y", where);
    }
    if (is_state) {
      state[j] = lin.x0[j];
    } else {
      u[j - n] = lin.u0[j - n];
      system.FixInputPort(context, input, u);
    }
  };
  for (int j = 0; j < n + m; ++j) {
    const double z = j < n ? lin.x0[j] : lin.u0[j - n];
    const double h = params.step_scale * std::max(1.0, std::abs(z));
    evaluate(j, h, &f_plus, &g_plus);
    evaluate(j, -h, &f_minus, &g_minus);
    // The step actually taken (z + h may round): divide by the difference of the representable points.
    const double two_h = (z + h) - (z - h);
    if (j < n) {
      lin.A.col(j) = (f_plus - f_minus) / two_h;
      if (p > 0) lin.C.col(j) = (g_plus - g_minus) / two_h;
    } else {
      lin.B.col(j - n) = (f_plus - f_minus) / two_h;
      if (p > 0) lin.D.col(j - n) = (g_plus - g_minus) / two_h;
    }
  }
  return lin;
}

}  // namespace rome
