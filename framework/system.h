#pragma once
// System: the structure of a block (ports, state sizes, modes, guards, periodic events), const while it runs.
// LeafSystem: a block whose constructor declares everything it has; behaviour goes into a few hooks.
//
// Semantics (documented once, here):
// - Inputs are pulled: EvalInput() asks the connected upstream output, which is computed on demand and cached
//   until the context's version changes. Diagram::Build() rejects algebraic loops, so the pull terminates.
// - An output declared with Feedthrough::None() must not read any input (checked: EvalInput on it throws
//   while that output is being computed would be too costly, so it is the author's contract).
// - Guards (hybrid events) belong to one mode or to all modes. A guard's witness w(x) is a vector; each
//   component is handed to CVODE's rootfinder with the guard's direction. kRising fires when a component
//   goes from negative to positive, kFalling from positive to negative. The reset map may change the
//   continuous state, the discrete state and the mode.
// - Periodic discrete updates happen exactly at t = offset + k * period (integer k). All updates due at one
//   time are computed from the same pre-update state, then applied together.

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "framework/context.h"

namespace rome {

/// Returned by resets, discrete updates, publishes and monitors. Any system can end the run with a reason.
struct EventStatus {
  enum class Kind { kSucceeded, kReachedTermination, kFailed };
  Kind kind = Kind::kSucceeded;
  std::string message;
  static EventStatus Succeeded() { return {}; }
  static EventStatus ReachedTermination(std::string why) { return {Kind::kReachedTermination, std::move(why)}; }
  static EventStatus Failed(std::string why) { return {Kind::kFailed, std::move(why)}; }
  bool ok() const { return kind == Kind::kSucceeded; }
};

enum class CrossingDirection { kRising, kFalling, kEither };

/// Which inputs an output reads. Direct feedthrough drives the algebraic-loop check and the evaluation order.
class Feedthrough {
 public:
  static Feedthrough None() { return Feedthrough(false, {}); }
  static Feedthrough All() { return Feedthrough(true, {}); }
  static Feedthrough From(std::vector<int> inputs) { return Feedthrough(false, std::move(inputs)); }
  bool DependsOn(int input) const;

 private:
  Feedthrough(bool all, std::vector<int> inputs) : all_(all), inputs_(std::move(inputs)) {}
  bool all_;
  std::vector<int> inputs_;
};

struct PortInfo {
  std::string name;
  int size = 0;
};

class System {
 public:
  virtual ~System() = default;
  System(const System&) = delete;
  System& operator=(const System&) = delete;

  const std::string& name() const { return name_; }
  int num_input_ports() const { return static_cast<int>(input_ports_.size()); }
  int num_output_ports() const { return static_cast<int>(output_ports_.size()); }
  const PortInfo& input_port(int index) const;
  const PortInfo& output_port(int index) const;
  /// Index of the named port, or an error naming this system and the port.
  int GetInputPortIndex(const std::string& port_name) const;
  int GetOutputPortIndex(const std::string& port_name) const;
  bool HasInputPort(const std::string& port_name) const;
  bool HasOutputPort(const std::string& port_name) const;

  virtual bool is_diagram() const = 0;
  virtual std::unique_ptr<Context> CreateDefaultContext() const = 0;
  /// Value of output port `index` at `context` (cached until the context changes).
  virtual const Eigen::VectorXd& EvalOutput(const Context& context, int index) const = 0;
  const Eigen::VectorXd& EvalOutput(const Context& context, const std::string& port) const {
    return EvalOutput(context, GetOutputPortIndex(port));
  }
  /// Fixes an input port of this system to a value in `context`.
  virtual void FixInputPort(Context& context, int index, const Eigen::VectorXd& value) const = 0;

 protected:
  explicit System(std::string name);
  void set_name(std::string name) { name_ = std::move(name); }
  std::vector<PortInfo> input_ports_;
  std::vector<PortInfo> output_ports_;

 private:
  friend class DiagramBuilder;
  std::string name_;
};

class LeafSystem : public System {
 public:
  static constexpr int kAllModes = -1;

  using OutputCalc = std::function<void(const LeafContext&, Eigen::VectorXd*)>;
  using WitnessCalc = std::function<void(const LeafContext&, Eigen::Ref<Eigen::VectorXd>)>;
  using ScalarWitnessCalc = std::function<double(const LeafContext&)>;
  /// `component` is the witness component that fired; `next` starts as a copy of the current state.
  using ResetMap = std::function<EventStatus(const LeafContext&, int component, State* next)>;
  using DiscreteUpdate = std::function<EventStatus(const LeafContext&, Eigen::VectorXd* discrete_next)>;
  using Publish = std::function<EventStatus(const LeafContext&)>;

  struct OutputPortDecl {
    OutputCalc calc;
    Feedthrough feedthrough = Feedthrough::All();
  };
  struct Guard {
    std::string name;
    int mode = kAllModes;
    int size = 1;
    WitnessCalc witness;
    CrossingDirection direction = CrossingDirection::kEither;
    ResetMap reset;
  };
  struct PeriodicEvent {
    double period = 0;
    double offset = 0;
    DiscreteUpdate update;  // exactly one of update / publish is set
    Publish publish;
  };

  bool is_diagram() const override { return false; }
  std::unique_ptr<Context> CreateDefaultContext() const override;
  std::unique_ptr<LeafContext> CreateDefaultLeafContext() const;
  const Eigen::VectorXd& EvalOutput(const Context& context, int index) const override;
  using System::EvalOutput;
  void FixInputPort(Context& context, int index, const Eigen::VectorXd& value) const override;

  /// Value of input port `index`; an error naming this system and port if it is not connected.
  const Eigen::VectorXd& EvalInput(const LeafContext& context, int index) const;

  /// xdot = f_mode(t, x, u). Checks sizes and finiteness of nothing (the simulator checks the state).
  void CalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const;

  int num_continuous_states() const { return num_continuous_states_; }
  int num_discrete_states() const { return static_cast<int>(default_discrete_state_.size()); }
  int num_modes() const { return static_cast<int>(mode_names_.size()); }
  const std::string& mode_name(int mode) const;
  int GetModeIndex(const std::string& mode_name) const;
  int num_numeric_parameters() const { return static_cast<int>(parameter_names_.size()); }
  const std::string& numeric_parameter_name(int index) const { return parameter_names_.at(index); }
  int GetNumericParameterIndex(const std::string& name) const;
  const std::vector<Guard>& guards() const { return guards_; }
  const std::vector<PeriodicEvent>& periodic_events() const { return periodic_events_; }
  const std::vector<Publish>& event_publishes() const { return event_publishes_; }
  const Feedthrough& output_feedthrough(int index) const { return output_decls_.at(index).feedthrough; }
  /// True if output `output` reads input `input` directly.
  bool HasDirectFeedthrough(int input, int output) const { return output_feedthrough(output).DependsOn(input); }
  /// Whether the guard is active in `mode`.
  static bool GuardActiveIn(const Guard& g, int mode) { return g.mode == kAllModes || g.mode == mode; }

  /// Default values written into new contexts.
  const Eigen::VectorXd& default_continuous_state() const { return default_continuous_state_; }
  const Eigen::VectorXd& default_discrete_state() const { return default_discrete_state_; }
  int default_mode() const { return default_mode_; }

 protected:
  explicit LeafSystem(std::string name) : System(std::move(name)) {}

  // ---- Declarations: call these in the constructor only. ----
  int DeclareInputPort(std::string name, int size);
  int DeclareOutputPort(std::string name, int size, OutputCalc calc, Feedthrough feedthrough = Feedthrough::All());
  /// Declares `size` continuous states with default values zero.
  void DeclareContinuousState(int size);
  void DeclareContinuousState(const Eigen::VectorXd& default_value);
  void DeclareDiscreteState(const Eigen::VectorXd& default_value);
  int DeclareNumericParameter(std::string name, const Eigen::VectorXd& default_value);
  /// Declares the modes by name; the first (or `default_mode`) is active in a new context.
  void DeclareModes(std::vector<std::string> names, int default_mode = 0);
  void DeclarePeriodicDiscreteUpdate(double period, double offset, DiscreteUpdate update);
  void DeclarePeriodicPublish(double period, double offset, Publish publish);
  /// Called at initialisation, after every guard event and after every periodic sample time.
  void DeclareEventPublish(Publish publish);
  /// Vector guard: fires when any component crosses zero in `direction`.
  int DeclareGuard(std::string name, int mode, int size, WitnessCalc witness, CrossingDirection direction, ResetMap reset);
  /// Scalar guard.
  int DeclareGuard(std::string name, int mode, ScalarWitnessCalc witness, CrossingDirection direction, ResetMap reset);

  // ---- Hooks. ----
  virtual void DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const;
  /// Per-run scratch stored in the context (e.g. a QP workspace). Default: none.
  virtual std::any AllocateScratch() const { return {}; }

  /// Error helper: "system 'name': what".
  [[noreturn]] void ThrowError(const std::string& what) const;

 private:
  std::vector<OutputPortDecl> output_decls_;
  int num_continuous_states_ = 0;
  Eigen::VectorXd default_continuous_state_;
  Eigen::VectorXd default_discrete_state_;
  std::vector<std::string> parameter_names_;
  std::vector<Eigen::VectorXd> default_parameters_;
  std::vector<std::string> mode_names_{"default"};
  int default_mode_ = 0;
  std::vector<Guard> guards_;
  std::vector<PeriodicEvent> periodic_events_;
  std::vector<Publish> event_publishes_;
};

}  // namespace rome
