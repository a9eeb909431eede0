#pragma once
// Diagram and DiagramBuilder: wire systems by port name; diagrams nest.
//
// A built Diagram is flat inside: nested diagrams are expanded into their leaf systems, with full path
// names ("walker/controller"), so evaluation never walks through layers. The nested Diagram objects stay
// owned by their parent so their exported port names keep working.
//
// Build() rejects, naming the systems and ports: an unconnected input (unless fixed or exported), a type or size
// mismatch, a second connection into one input, and an algebraic loop among direct-feedthrough ports.

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "framework/context.h"
#include "framework/system.h"

namespace rome {

class DiagramContext final : public Context {
 public:
  bool is_diagram_context() const override { return true; }
  std::unique_ptr<Context> Clone() const override;
  int num_leaves() const { return static_cast<int>(leaves_.size()); }
  LeafContext& leaf(int i) { return *leaves_[i]; }
  const LeafContext& leaf(int i) const { return *leaves_[i]; }

 private:
  friend class Diagram;
  DiagramContext() = default;
  std::vector<std::unique_ptr<LeafContext>> leaves_;
  std::vector<Eigen::VectorXd> fixed_inputs_;  // per exported input
  std::vector<bool> input_fixed_;
};

class Diagram final : public System {
 public:
  bool is_diagram() const override { return true; }
  std::unique_ptr<Context> CreateDefaultContext() const override;
  std::unique_ptr<DiagramContext> CreateDefaultDiagramContext() const;
  const Eigen::VectorXd& EvalOutput(const Context& context, int index) const override;
  using System::EvalOutput;
  const std::any& EvalAbstractOutput(const Context& context, int index) const override;
  void FixInputPort(Context& context, int index, const Eigen::VectorXd& value) const override;
  /// Value fixed on vector input `index` of this diagram in `context`; an error naming the diagram and the port if
  /// the port is typed or has no fixed value.
  const Eigen::VectorXd& EvalInput(const Context& context, int index) const;

  int num_leaves() const { return static_cast<int>(leaves_.size()); }
  const LeafSystem& leaf(int i) const { return *leaves_[i].system; }
  /// Full path name of leaf i, e.g. "walker/controller".
  const std::string& leaf_path(int i) const { return leaves_[i].path; }
  /// Index of a leaf by its system or its path; an error naming the system if it is not in this diagram.
  int GetLeafIndex(const LeafSystem& system) const;
  int GetLeafIndex(const std::string& path) const;
  const LeafSystem& GetLeafByPath(const std::string& path) const { return leaf(GetLeafIndex(path)); }

  LeafContext& GetMutableSubsystemContext(const LeafSystem& system, Context& context) const;
  const LeafContext& GetSubsystemContext(const LeafSystem& system, const Context& context) const;
  /// Output `port` of `subsystem`, a leaf of this diagram or a diagram nested in it (at any depth), evaluated in this
  /// diagram's `context`: a nested diagram's exported output is read from the leaf that produces it. Throws, naming
  /// the system and the port, if `subsystem` is not part of this diagram or has no such (vector) output.
  const Eigen::VectorXd& EvalSubsystemOutput(const System& subsystem, const std::string& port,
                                             const Context& context) const;

  /// Leaf output ports in an order where every direct-feedthrough dependency comes first.
  struct OutputRef {
    int leaf;
    int port;
  };
  const std::vector<OutputRef>& output_evaluation_order() const { return evaluation_order_; }
  /// Evaluates every leaf output in dependency order (useful for logging and checks).
  void EvalAllOutputs(const Context& context) const;

 private:
  friend class DiagramBuilder;
  explicit Diagram(std::string name) : System(std::move(name)) {}
  const DiagramContext& AsDiagramContext(const Context& context) const;

  struct Leaf {
    const LeafSystem* system;
    std::string path;
  };
  struct InputRef {
    int leaf;
    int port;
  };
  // Where each leaf input gets its value.
  struct LeafInputWiring {
    enum class Kind { kUpstream, kFixed, kExported } kind;
    OutputRef upstream{-1, -1};
    Eigen::VectorXd fixed_value;
    std::any fixed_abstract;  // typed ports
    int exported_index = -1;
  };
  std::vector<std::unique_ptr<System>> owned_;
  std::vector<Leaf> leaves_;
  std::vector<std::vector<LeafInputWiring>> wiring_;    // [leaf][input port]
  std::vector<std::vector<InputRef>> exported_inputs_;  // [diagram input] -> leaf inputs
  std::vector<OutputRef> exported_outputs_;             // [diagram output] -> leaf output
  std::vector<OutputRef> evaluation_order_;
};

class DiagramBuilder {
 public:
  DiagramBuilder() = default;

  /// Adds a system under a unique name (the system's own name if `name` is empty). Returns a raw pointer
  /// that stays valid as long as the built diagram lives.
  template <class S>
  S* AddSystem(std::unique_ptr<S> system, const std::string& name = "") {
    S* raw = system.get();
    AddSystemImpl(std::unique_ptr<System>(std::move(system)), name);
    return raw;
  }
  template <class S, class... Args>
  S* AddNamedSystem(const std::string& name, Args&&... args) {
    return AddSystem(std::make_unique<S>(std::forward<Args>(args)...), name);
  }

  void Connect(const std::string& from_system, const std::string& output_port, const std::string& to_system,
               const std::string& input_port);
  void Connect(const System& from_system, const std::string& output_port, const System& to_system,
               const std::string& input_port);
  /// Connects the only output of `from` to the only input of `to`.
  void Connect(const System& from, const System& to);
  /// Gives an input a fixed value inside the diagram.
  void FixInput(const std::string& system, const std::string& input_port, const Eigen::VectorXd& value);
  /// Gives a typed input a fixed value (its type is checked by Build()).
  template <class T>
  void FixTypedInput(const std::string& system, const std::string& input_port, T value) {
    FixAbstractInput(system, input_port, std::any(std::move(value)));
  }
  void FixAbstractInput(const std::string& system, const std::string& input_port, std::any value);
  /// Makes an input of a subsystem an input of the diagram, under `name` (default: the port's name).
  /// Several subsystem inputs may share one exported name (same size): they are fanned out.
  void ExportInput(const std::string& system, const std::string& input_port, const std::string& name = "");
  void ExportOutput(const std::string& system, const std::string& output_port, const std::string& name = "");

  bool HasSystem(const std::string& name) const;
  System& GetMutableSystem(const std::string& name) const;

  /// Builds the diagram; the builder is empty afterwards.
  std::unique_ptr<Diagram> Build(const std::string& name = "diagram");

 private:
  void AddSystemImpl(std::unique_ptr<System> system, const std::string& name);
  int SystemIndex(const std::string& name) const;
  int SystemIndex(const System& system) const;

  struct PortRef {
    int system;
    int port;
  };
  struct Connection {
    PortRef from, to;
  };
  // A leaf input whose source is block `block`'s input `block_input` (a nested diagram's exported input).
  struct PendingInput {
    int leaf, port, block, block_input;
  };
  // Build's stages: the blocks expanded into leaves; one source per block input (checked) wired into the leaves; the
  // leaf outputs in evaluation order (algebraic loops rejected).
  void ExpandLeaves(Diagram& d, std::vector<int>* offset, std::vector<PendingInput>* pending) const;
  void WireInputs(Diagram& d, const std::string& name, const std::vector<int>& offset,
                  const std::vector<PendingInput>& pending) const;
  static void SortEvaluationOrder(Diagram& d, const std::string& name);
  std::string PortName(int system, int port, bool input) const;
  /// The leaf output behind output `o` of a block (offset: each block's first leaf).
  Diagram::OutputRef LeafOutput(const std::vector<int>& offset, PortRef o) const;
  std::vector<std::unique_ptr<System>> systems_;
  std::vector<std::string> names_;
  std::vector<Connection> connections_;
  std::vector<std::pair<PortRef, Eigen::VectorXd>> fixed_;
  std::vector<std::pair<PortRef, std::any>> fixed_abstract_;
  std::vector<std::pair<std::string, std::vector<PortRef>>> exported_inputs_;
  std::vector<std::pair<std::string, PortRef>> exported_outputs_;
};

}  // namespace rome
