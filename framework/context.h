#pragma once
// Context: the values of one simulation run (time, state, parameters, fixed inputs, output cache, scratch).
// A System is const while it runs; everything that changes lives here (Drake's System/Context split).
//
// Cache validity uses one version counter shared by all leaf contexts of a diagram: every mutable access to
// time, state, parameters or fixed inputs bumps it, and an output is recomputed only when its cached version
// is older. Hold mutable references only briefly: take them again after any other call into the framework.

#include <any>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <typeinfo>
#include <vector>

#include <Eigen/Core>

namespace rome {

class LeafSystem;

/// The full state of one leaf system: continuous state xc, discrete state xd and the active mode.
/// The sizes of xc and xd are fixed across modes.
struct State {
  Eigen::VectorXd continuous;
  Eigen::VectorXd discrete;
  int mode = 0;
};

class Context {
 public:
  virtual ~Context() = default;
  double time() const { return *time_; }
  /// Sets the time of this context (and of every leaf context of a diagram).
  void SetTime(double t) {
    *time_ = t;
    ++*version_;
  }
  /// Version of the values in this context; bumps on every mutable access.
  std::uint64_t version() const { return *version_; }
  void InvalidateCache() { ++*version_; }
  virtual bool is_diagram_context() const = 0;
  /// A deep copy: time, state, parameters, fixed inputs and per-run scratch (workspaces, warm starts, logs) are
  /// copied; the copy has its own clock and cache and is wired to its own leaf contexts. Simulating the copy (a
  /// branch: Monte Carlo, look-ahead) leaves this context untouched. Scratch is copied with its type's copy
  /// constructor, so a block whose scratch shares a heavy object through a pointer must deep-copy it there.
  virtual std::unique_ptr<Context> Clone() const = 0;

 protected:
  Context() = default;
  // Shared between a diagram context and all its leaf contexts.
  std::shared_ptr<double> time_ = std::make_shared<double>(0.0);
  std::shared_ptr<std::uint64_t> version_ = std::make_shared<std::uint64_t>(1);
  friend class Diagram;
  friend class DiagramContext;
};

/// Where an input port of a leaf gets its value from.
struct InputSource {
  enum class Kind { kUnconnected, kFixed, kUpstream };
  Kind kind = Kind::kUnconnected;
  const LeafSystem* upstream_system = nullptr;  // kUpstream
  const class LeafContext* upstream_context = nullptr;
  int upstream_port = -1;
  const Eigen::VectorXd* fixed_value = nullptr;  // kFixed vector port: points into fixed storage
  const std::any* fixed_abstract = nullptr;      // kFixed typed port: points into fixed storage
};

class LeafContext final : public Context {
 public:
  bool is_diagram_context() const override { return false; }
  std::unique_ptr<Context> Clone() const override;
  const LeafSystem& system() const { return *system_; }

  const State& state() const { return state_; }
  State& get_mutable_state() {
    InvalidateCache();
    return state_;
  }
  const Eigen::VectorXd& continuous_state() const { return state_.continuous; }
  Eigen::VectorXd& get_mutable_continuous_state() {
    InvalidateCache();
    return state_.continuous;
  }
  const Eigen::VectorXd& discrete_state() const { return state_.discrete; }
  Eigen::VectorXd& get_mutable_discrete_state() {
    InvalidateCache();
    return state_.discrete;
  }
  int mode() const { return state_.mode; }
  /// Sets the active mode; the index is checked against the modes the system declared.
  void set_mode(int mode);

  const Eigen::VectorXd& numeric_parameter(int index) const { return parameters_.at(index); }
  Eigen::VectorXd& get_mutable_numeric_parameter(int index) {
    InvalidateCache();
    return parameters_.at(index);
  }

  /// Gives input port `index` a fixed value (size checked). Replaces nothing that a diagram connected:
  /// fixing a connected input is an error.
  void FixInputPort(int index, const Eigen::VectorXd& value);
  /// Same for a typed input port; the value's type is checked against the port's.
  void FixAbstractInputPort(int index, std::any value);

  /// Per-run scratch (workspaces, logs, warm starts) created by LeafSystem::AllocateScratch().
  /// Mutable through a const context: it never changes a value that another system can observe.
  template <class T>
  T& scratch() const {
    T* p = std::any_cast<T>(&scratch_);
    if (p == nullptr)
      throw std::logic_error("LeafContext::scratch: wrong scratch type requested (" + std::string(typeid(T).name()) +
                             ")");
    return *p;
  }

 private:
  friend class LeafSystem;
  friend class Diagram;
  friend class DiagramContext;
  friend class Simulator;
  LeafContext() = default;
  LeafContext(const LeafContext&) = default;
  /// Copy with fixed inputs re-pointed at this copy's storage (upstream sources are re-wired by the diagram).
  std::unique_ptr<LeafContext> CloneLeaf() const;

  struct OutputCache {
    Eigen::VectorXd value;  // vector ports
    std::any abstract;      // typed ports
    std::uint64_t version = 0;
  };

  const LeafSystem* system_ = nullptr;
  State state_;
  std::vector<Eigen::VectorXd> parameters_;
  std::vector<InputSource> inputs_;
  std::vector<Eigen::VectorXd> fixed_inputs_;
  std::vector<std::any> fixed_abstract_inputs_;
  mutable std::vector<OutputCache> outputs_;
  mutable std::any scratch_;
};

}  // namespace rome
