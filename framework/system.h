#pragma once
// System: the structure of a block (ports, state sizes, modes, guards, periodic and event updates), const while
// it runs. LeafSystem: a block whose constructor declares everything it has; behaviour goes into a few hooks.
//
// Semantics (documented once, here):
// - Inputs are pulled: EvalInput() asks the connected upstream output, which is computed on demand and cached
//   until the context's version changes. Diagram::Build() rejects algebraic loops, so the pull terminates.
// - Output calculations have no side effects: they may fill per-context scratch (caches, workspaces) but never
//   change anything another block or a later evaluation can observe. Work that changes the state goes into
//   periodic updates, guard resets and event updates.
// - An output declared with Feedthrough::None() must not read any input (checked: EvalInput on it throws
//   while that output is being computed would be too costly, so it is the author's contract).
// - Ports are either vector ports (Eigen::VectorXd of a fixed size, with optional element names, e.g. "x", "z")
//   or typed ports that carry one C++ value (an int mode, a struct of step parameters, a plan), as Drake's
//   abstract-valued ports. Build() checks that both ends of a connection carry the same type (and size).
// - Guards (hybrid events) belong to one mode or to all modes. A guard's witness w(x) is a vector; each
//   component is handed to the integrator's rootfinder with the guard's direction. kRising fires when a component
//   goes from negative to positive, kFalling from positive to negative. The reset map may change the
//   continuous state, the discrete state and the mode.
// - Periodic discrete updates happen exactly at t = offset + k * period (integer k). All updates due at one
//   time are computed from the same pre-update state, then applied together.
// - Event updates (Drake's witness-triggered unrestricted updates) run at guard events of the diagram, right after
//   the resets of that instant: at every guard event, or only at named guards of named systems (EventTrigger).
//   They may change the discrete state and the mode of their own system. They run in diagram order, each seeing
//   the state left by the earlier ones, so a controller added after its planner re-solves with the planner's new
//   state at the same instant (see simulator.h for the full order).

#include <any>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <typeinfo>
#include <vector>

#include <Eigen/Core>

#include "framework/context.h"

namespace rome {

/// Returned by resets, discrete updates, publishes and monitors. Any system can end the run with a reason:
/// ReachedTermination when the run reached its goal (a success), Failed when it failed (a fall, a slip, a solver that
/// gave up, bad data).
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

/// Readable name of a C++ type (demangled), used in port type messages.
std::string DemangledTypeName(const std::type_info& type);

struct PortInfo {
  std::string name;
  int size = 0;                                ///< vector ports: number of elements; typed ports: 0
  std::vector<std::string> element_names;      ///< vector ports: one name per element, or empty
  const std::type_info* value_type = nullptr;  ///< typed ports: the C++ type carried; nullptr for vector ports
  bool is_vector() const { return value_type == nullptr; }
  /// "a vector of size 4" or the demangled type name, e.g. "int".
  std::string TypeString() const;
  /// True if a value of `other` may flow into this port (same type, and same size for vectors).
  bool SameTypeAs(const PortInfo& other) const;
};

/// One guard event, as the simulator records it and hands it to event updates.
struct EventRecord {
  double time = 0;
  std::string system;  ///< Path of the system whose guard fired.
  std::string guard;
  int component = 0;
  int mode_before = 0;
  int mode_after = 0;
};

/// Which guard events run an event update. Empty: every guard event of the diagram.
struct EventTrigger {
  struct GuardName {
    std::string system;  ///< a leaf's path ("walker/plant") or its own name ("plant")
    std::string guard;   ///< a guard name; a trailing '*' matches every guard with that prefix ("touchdown_*")
  };
  std::vector<GuardName> guards;
  static EventTrigger AnyGuard() { return {}; }
  static EventTrigger Guards(std::vector<GuardName> names) { return {std::move(names)}; }
  bool any() const { return guards.empty(); }
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
  /// Value of vector output port `index` at `context` (cached until the context changes). A typed port is an
  /// error naming the system, the port and its type.
  virtual const Eigen::VectorXd& EvalOutput(const Context& context, int index) const = 0;
  const Eigen::VectorXd& EvalOutput(const Context& context, const std::string& port) const {
    return EvalOutput(context, GetOutputPortIndex(port));
  }
  /// Value of typed output port `index` (an error naming the port and both types if it carries another type).
  template <class T>
  const T& EvalTypedOutput(const Context& context, int index) const {
    CheckPortType(output_port(index), typeid(T), "output");
    return *std::any_cast<T>(&EvalAbstractOutput(context, index));
  }
  template <class T>
  const T& EvalTypedOutput(const Context& context, const std::string& port) const {
    return EvalTypedOutput<T>(context, GetOutputPortIndex(port));
  }
  /// The typed output's value as std::any (typed ports only).
  virtual const std::any& EvalAbstractOutput(const Context& context, int index) const = 0;
  /// Fixes an input port of this system to a value in `context`.
  virtual void FixInputPort(Context& context, int index, const Eigen::VectorXd& value) const = 0;

 protected:
  explicit System(std::string name);
  void set_name(std::string name) { name_ = std::move(name); }
  /// Throws, naming this system, the port and both types, unless `port` carries `type`.
  void CheckPortType(const PortInfo& port, const std::type_info& type, const char* direction) const;
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
  using AbstractOutputCalc = std::function<void(const LeafContext&, std::any*)>;
  using WitnessCalc = std::function<void(const LeafContext&, Eigen::Ref<Eigen::VectorXd>)>;
  using ScalarWitnessCalc = std::function<double(const LeafContext&)>;
  /// `component` is the witness component that fired; `next` starts as a copy of the current state.
  using ResetMap = std::function<EventStatus(const LeafContext&, int component, State* next)>;
  using DiscreteUpdate = std::function<EventStatus(const LeafContext&, Eigen::VectorXd* discrete_next)>;
  using Publish = std::function<EventStatus(const LeafContext&)>;
  /// `event` is the (first) guard event of this instant that matched the trigger; `next` starts as a copy of the
  /// current state. Changes to next->continuous are ignored (only resets change the continuous state).
  using EventUpdate = std::function<EventStatus(const LeafContext&, const EventRecord& event, State* next)>;

  struct OutputPortDecl {
    OutputCalc calc;                   // vector ports
    AbstractOutputCalc abstract_calc;  // typed ports
    std::any default_value;            // typed ports: the value a new context starts with
    Feedthrough feedthrough = Feedthrough::All();
  };
  struct EventUpdateDecl {
    std::string name;
    EventTrigger trigger;
    EventUpdate update;
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
  const std::any& EvalAbstractOutput(const Context& context, int index) const override;
  void FixInputPort(Context& context, int index, const Eigen::VectorXd& value) const override;
  /// Fixes typed input port `index` (an error naming the port and both types if `value` is of another type).
  template <class T>
  void FixTypedInputPort(Context& context, int index, T value) const {
    FixAbstractInputPort(context, index, std::any(std::move(value)));
  }
  void FixAbstractInputPort(Context& context, int index, std::any value) const;

  /// Value of vector input port `index`; an error naming this system and port if it is not connected or typed.
  const Eigen::VectorXd& EvalInput(const LeafContext& context, int index) const;
  /// Value of typed input port `index`; an error naming this system, the port and both types on a type mismatch.
  template <class T>
  const T& EvalTypedInput(const LeafContext& context, int index) const {
    CheckPortType(input_port(index), typeid(T), "input");
    return *std::any_cast<T>(&EvalAbstractInput(context, index));
  }
  const std::any& EvalAbstractInput(const LeafContext& context, int index) const;

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
  const std::vector<EventUpdateDecl>& event_updates() const { return event_updates_; }
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
  /// Vector input with element names (its size is the number of names).
  int DeclareInputPort(std::string name, std::vector<std::string> element_names);
  int DeclareOutputPort(std::string name, int size, OutputCalc calc, Feedthrough feedthrough = Feedthrough::All());
  /// Vector output with element names (its size is the number of names), e.g. {"x", "z", "vx", "vz"}.
  int DeclareOutputPort(std::string name, std::vector<std::string> element_names, OutputCalc calc,
                        Feedthrough feedthrough = Feedthrough::All());
  /// Typed input port carrying a T.
  template <class T>
  int DeclareTypedInputPort(std::string name) {
    return DeclareAbstractInputPort(std::move(name), typeid(T));
  }
  /// Typed output port carrying a T; `calc` fills the cached value in place (no allocation once T has its size).
  template <class T>
  int DeclareTypedOutputPort(std::string name, std::function<void(const LeafContext&, T*)> calc,
                             Feedthrough feedthrough = Feedthrough::All(), T default_value = T{}) {
    if (!calc) ThrowError("output port '" + name + "' has no calculation function");
    return DeclareAbstractOutputPort(
        std::move(name), typeid(T), std::any(std::move(default_value)),
        [calc = std::move(calc)](const LeafContext& c, std::any* value) { calc(c, std::any_cast<T>(value)); },
        std::move(feedthrough));
  }
  int DeclareAbstractInputPort(std::string name, const std::type_info& type);
  int DeclareAbstractOutputPort(std::string name, const std::type_info& type, std::any default_value,
                                AbstractOutputCalc calc, Feedthrough feedthrough = Feedthrough::All());
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
  /// An update of this system's discrete state and mode that runs at the guard events `trigger` selects, right after
  /// the resets of that instant (see the top of this file). `name` appears in errors. The simulator checks, when it
  /// is built, that every named system and guard exists.
  void DeclareEventUpdate(std::string name, EventTrigger trigger, EventUpdate update);
  /// Vector guard: fires when any component crosses zero in `direction`.
  int DeclareGuard(std::string name, int mode, int size, WitnessCalc witness, CrossingDirection direction,
                   ResetMap reset);
  /// Scalar guard.
  int DeclareGuard(std::string name, int mode, ScalarWitnessCalc witness, CrossingDirection direction, ResetMap reset);

  // ---- Hooks. ----
  /// ẋ of the continuous state; `xdot` arrives with num_continuous_states() elements (CalcTimeDerivatives sizes it).
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
  std::vector<EventUpdateDecl> event_updates_;
};

}  // namespace rome
