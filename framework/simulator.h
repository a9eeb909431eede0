#pragma once
// Simulator: integrates the stacked continuous state of a diagram (or one leaf system) with SUNDIALS CVODE,
// finds every guard crossing with CVODE's rootfinder, and runs periodic discrete updates exactly at their
// sample times using CVODE stop times.
//
// Order of operations (documented contract):
//  1. Initialize(): event publishes run once at the initial time.
//  2. Each pass of AdvanceTo(t_final):
//     a. Periodic events due at the current time run: all discrete updates due now are computed from the same
//        pre-update state, then applied together (systems in diagram order, updates in declaration order);
//        then the periodic publishes due now; then event publishes. Events due exactly at t_final are left for
//        the next AdvanceTo (so a 1 kHz counter updates 1000 times in [0, 1 s)).
//     b. CVODE integrates one step towards min(next sample time, t_final) with that time as stop time.
//        The monitors (if any) run after each accepted step, in the order they were added; the first that returns
//        anything but EventStatus::Succeeded() ends the run.
//     c. If guards fired, their resets run in diagram order (systems as added to the builder), then in guard
//        declaration order within a system. Each reset sees the state left by the earlier ones; a guard
//        whose mode is no longer active after an earlier reset is skipped. Then the event updates whose trigger
//        matches one of the guards that fired run once each, in diagram order (then declaration order), each
//        seeing the state left by the resets and by the earlier event updates (so a controller added after its
//        planner re-solves with the planner's new plan at the same instant). Then event publishes run and the
//        integrator is re-initialised at the event time. With SimulatorConfig::max_guard_events = N > 0, the instant
//        at which the N-th guard event fires ends the run (kReachedEventLimit) after its resets, event updates and
//        event publishes, before the monitors.
//  3. Zeno policy: events closer than EventPolicy::min_event_separation_s to the previous event count as the
//     same instant; more than EventPolicy::max_events_per_instant of them end the run with kZeno (or throw,
//     if EventPolicy::throw_on_violation).
// Any system ends the run by returning EventStatus::ReachedTermination(reason) (goal reached: a success) or
// EventStatus::Failed(reason) (a fall, a slip, a solver that gave up) from a reset, update, publish, or the monitor.
// A NaN or Inf in the continuous state ends the run with kFailed, naming the system. SimulatorStatus::kind() tells
// success, failure and limit (the run reached its time limit t_final, or its event limit, without a verdict) apart;
// a limit is no verdict: a diagram that defines success at its planned end (e.g. the stepping-stones supervisor after
// max_steps) ends the run itself with ReachedTermination.
// The simulator checks, when it is constructed, that every system and guard named by an event update's trigger
// exists, and throws a one-line error naming the system, the event update and the unknown name otherwise.

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "framework/context.h"
#include "framework/diagram.h"
#include "framework/system.h"

namespace rome {

/// kBdf and kAdams solve each implicit step by Newton iteration on a dense finite-difference Jacobian (robust for
/// stiff plants). kAdamsFunctional uses Adams-Moulton with fixed-point (functional) iteration: no Jacobian at all,
/// the cheapest multistep choice for non-stiff plants whose integration is restarted often (e.g. by a 1 kHz
/// zero-order hold). kExplicitRungeKutta is ARKODE's ERKStep with an embedded pair (SimulatorConfig::
/// explicit_rk_method: Dormand-Prince 5(4), 7 stages, or Bogacki-Shampine 3(2), 4 stages): a one-step method,
/// so restarting at every sample costs nothing (a multistep method restarts at order 1 with small steps); for
/// non-stiff plants sampled at kHz rates it needs the fewest derivative evaluations. max_order does not apply to it.
/// Every scheme locates guard events by root finding on its own dense output.
enum class IntegrationScheme { kBdf, kAdams, kAdamsFunctional, kExplicitRungeKutta };
/// The embedded pair of IntegrationScheme::kExplicitRungeKutta. Bogacki-Shampine needs 4 derivative evaluations per
/// step against 7, but its steps are shorter at tight tolerances; at kHz sampling with moderate tolerances both take
/// one step per sample.
enum class ExplicitRungeKuttaMethod { kDormandPrince54, kBogackiShampine32 };

struct EventPolicy {
  /// [s] An event closer than this to the previous event counts as "at the same instant". Legged-robot events
  /// (touchdown, lift-off) are milliseconds apart unless they are chained (impact then lift-off at once).
  double min_event_separation_s = 1e-4;
  /// Events allowed at one instant (chained resets) before the run stops as Zeno.
  int max_events_per_instant = 5;
  bool throw_on_violation = false;  ///< Throw std::runtime_error instead of returning kZeno.
};

struct SimulatorConfig {
  IntegrationScheme scheme = IntegrationScheme::kBdf;
  double relative_tolerance = 1e-8;   ///< [-]
  double absolute_tolerance = 1e-10;  ///< [state units]
  double max_step_s = 0.0;            ///< [s] 0 = no limit.
  double initial_step_s = 0.0;        ///< [s] 0 = CVODE's estimate.
  int max_order = 0;                  ///< 0 = CVODE's default (5 for BDF, 12 for Adams).
  ExplicitRungeKuttaMethod explicit_rk_method =
      ExplicitRungeKuttaMethod::kDormandPrince54;  ///< kExplicitRungeKutta only.
  /// kExplicitRungeKutta only: after a discrete update (not after a guard's reset), start with the step size the
  /// error control asks for at the end of the previous interval instead of ARKODE's initial-step estimate. When that
  /// interval ended with a step clipped to the sample time, the size comes from the clipped step's own error estimate
  /// (ARKODE would report the clipped size). Measured on the 2 kHz hopping loop (diagrams/hopping): 32 % fewer
  /// derivative evaluations with Bogacki-Shampine than carrying ARKODE's reported step. Off by default.
  bool restart_with_last_step = false;
  long max_steps_per_advance = 1000000000L;  ///< Safety net on CVODE internal steps within one AdvanceTo.
  /// [-] End the run right after the N-th guard event (counted over the simulator's life, SimulatorStatistics::
  /// guard_events), at the end of that event instant (its resets, event updates and event publishes done), with
  /// SimulatorStatus::Reason::kReachedEventLimit (kind "limit"). 0 = no limit; negative values are refused.
  long max_guard_events = 0;
  EventPolicy event_policy;
};

struct SimulatorStatistics {
  long steps = 0;
  long rhs_evals = 0;  ///< Every derivative evaluation, including those of finite-difference Jacobians.
  long root_evals = 0;
  long jacobian_evals = 0;        ///< Iteration-matrix Jacobians (kBdf, kAdams; 0 for the other schemes).
  long jacobian_rhs_evals = 0;    ///< Derivative evaluations spent on finite-difference Jacobians (in rhs_evals).
  long nonlinear_iterations = 0;  ///< Newton (or fixed-point) iterations of the implicit schemes.
  long error_test_failures = 0;   ///< Rejected steps (local error too large).
  long convergence_failures = 0;  ///< Nonlinear-solver convergence failures.
  long restarts = 0;              ///< Integrator re-initialisations after a discrete update or an event reset.
  /// [s] Explicit Runge-Kutta only: the largest first step ARKODE took in an interval that began with a state reset
  /// (a guard's reset map), where restart_with_last_step must not carry the step; 0 if there was none.
  double max_initial_step_after_reset_s = 0.0;
  long guard_events = 0;
  long discrete_samples = 0;  ///< Sample times at which periodic events ran.
  std::vector<EventRecord> events;
};

struct SimulatorStatus {
  /// kReachedBoundaryTime: the run reached the time limit t_final given to AdvanceTo (message "reached the time limit
  /// t = ... s"; the run can be continued). kReachedEventLimit: SimulatorConfig::max_guard_events guard events
  /// happened (message "reached the event limit of N guard events"; the run has ended).
  enum class Reason { kReachedBoundaryTime, kReachedTermination, kZeno, kFailed, kInterrupted, kReachedEventLimit };
  /// kSuccess: a system ended the run because its goal was reached (ReachedTermination). kFailure: a system failed
  /// (EventStatus::Failed: fell, slipped, solver gave up), a non-finite state, Zeno, or an integrator error. kLimit:
  /// the run stopped at its time limit t_final or its event limit, without either verdict. kInterrupted: SIGINT or
  /// SIGTERM arrived (framework/interrupt.h) and the run stopped at its next step.
  enum class Kind { kSuccess, kFailure, kLimit, kInterrupted };
  Reason reason = Reason::kReachedBoundaryTime;
  double time = 0;
  std::string system;   ///< The system that ended the run, if any.
  std::string message;  ///< Human-readable reason.
  /// True if the run reached its time limit t_final (and may be continued); false if it ended (any other reason).
  bool ok() const { return reason == Reason::kReachedBoundaryTime; }
  Kind kind() const;
  /// "success", "failure", "limit" or "interrupted".
  std::string kind_name() const;
  std::string ToString() const;
};

class Simulator {
 public:
  using Monitor = std::function<EventStatus(const Context&)>;

  /// The simulator keeps references to `system`; it owns a default context unless one is given.
  explicit Simulator(const System& system, SimulatorConfig config = {});
  Simulator(const System& system, std::unique_ptr<Context> context, SimulatorConfig config = {});
  ~Simulator();
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  Context& get_mutable_context() { return *context_; }
  const Context& get_context() const { return *context_; }
  const SimulatorConfig& config() const { return config_; }
  /// Changing the configuration after Initialize() re-creates the integrator at the current state.
  void set_config(const SimulatorConfig& config);
  /// Replaces every monitor by `monitor` (an empty function removes them all).
  void set_monitor(Monitor monitor);
  /// Appends a monitor: it runs after every accepted step, after those added before it. A monitor that returns
  /// anything but EventStatus::Succeeded() ends the run; the status names `name` as the system that ended it.
  void add_monitor(Monitor monitor, std::string name = "monitor");
  /// Removes every monitor named `name`; returns how many there were. A run function that added its own monitor
  /// removes it this way before it returns (also when the run throws), leaving the caller's monitors in place.
  int remove_monitor(const std::string& name);
  int num_monitors() const { return static_cast<int>(monitors_.size()); }

  /// Reads the state from the context and prepares the integrator. Called by AdvanceTo if needed; call it
  /// again after changing the state in the context by hand.
  SimulatorStatus Initialize();
  /// Advances to `t_final`, handling every event on the way. May be called repeatedly.
  SimulatorStatus AdvanceTo(double t_final);

  const SimulatorStatistics& statistics() const { return stats_; }
  /// The system (usually a Diagram) this simulator advances.
  const System& system() const { return system_; }
  /// Total continuous states integrated.
  int num_continuous_states() const { return nx_; }

  struct Impl;  // CVODE memory and preallocated buffers (opaque)

 private:
  std::unique_ptr<Impl> impl_;
  const System& system_;
  std::unique_ptr<Context> context_;
  SimulatorConfig config_;
  struct NamedMonitor {
    Monitor monitor;
    std::string name;
  };
  std::vector<NamedMonitor> monitors_;
  SimulatorStatistics stats_;
  int nx_ = 0;
  bool initialized_ = false;
  bool terminated_ = false;
  SimulatorStatus terminal_status_;
  friend struct SimulatorCallbacks;

  // AdvanceTo's parts. Each that can end the run returns the run's status then (nullopt: go on).
  /// Ends the run (a boundary time only pauses it) and copies the integrator's counters into the statistics.
  SimulatorStatus Finish(SimulatorStatus::Reason reason, const std::string& system, const std::string& message);
  SimulatorStatus FromEvent(const EventStatus& status, const std::string& system);
  /// Restarts the integrator at the contexts' state; carry_step: the continuous state did not jump (a discrete update
  /// only changed the inputs).
  void Reinitialize(bool carry_step);
  /// The periodic updates and publishes due at `next_sample`, then the per-step publishes.
  std::optional<SimulatorStatus> RunPeriodicEvents(double next_sample);
  /// One integrator step towards `t_stop`: its return flag and time, the state written into the contexts.
  std::optional<SimulatorStatus> Step(double t_stop, int* flag, double* t_ret);
  /// After a root return: the resets of the guards that fired (Zeno policy), the event updates, the publishes.
  std::optional<SimulatorStatus> HandleGuards(double t_ret);
  std::optional<SimulatorStatus> RunEventUpdates();
};

}  // namespace rome
