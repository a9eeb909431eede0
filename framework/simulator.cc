#include "framework/simulator.h"

#include "framework/interrupt.h"

#include <arkode/arkode_erkstep.h>
#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <sstream>

namespace rome {

SimulatorStatus::Kind SimulatorStatus::kind() const {
  switch (reason) {
    case Reason::kReachedTermination: return Kind::kSuccess;
    case Reason::kFailed:
    case Reason::kZeno: return Kind::kFailure;
    case Reason::kInterrupted: return Kind::kInterrupted;
    case Reason::kReachedBoundaryTime:
    case Reason::kReachedEventLimit: break;
  }
  return Kind::kLimit;
}

std::string SimulatorStatus::kind_name() const {
  switch (kind()) {
    case Kind::kSuccess: return "success";
    case Kind::kFailure: return "failure";
    case Kind::kInterrupted: return "interrupted";
    case Kind::kLimit: break;
  }
  return "limit";
}

std::string SimulatorStatus::ToString() const {
  std::ostringstream os;
  if (reason == Reason::kReachedBoundaryTime) {
    os << "reached the time limit t = " << time << " s";
    return os.str();
  }
  switch (reason) {
    case Reason::kReachedBoundaryTime: break;
    case Reason::kReachedEventLimit: os << "reached the event limit"; break;
    case Reason::kReachedTermination: os << "terminated"; break;
    case Reason::kZeno: os << "Zeno behaviour"; break;
    case Reason::kFailed: os << "failed"; break;
    case Reason::kInterrupted: os << "interrupted"; break;
  }
  os << " at t = " << time << " s";
  if (!system.empty()) os << " (system '" << system << "')";
  if (!message.empty()) os << ": " << message;
  return os.str();
}

struct Simulator::Impl {
  std::vector<const LeafSystem*> systems;
  std::vector<LeafContext*> contexts;
  std::vector<std::string> paths;
  std::vector<int> xc_offset;
  struct GuardRef {
    int leaf, guard, root_offset;
  };
  std::vector<GuardRef> guards;
  int nroots = 0;
  std::vector<int> rootdir, rootsfound;
  struct Periodic {
    int leaf, event;
    double period, offset;
    long k;
    double next_time() const { return offset + static_cast<double>(k) * period; }
  };
  std::vector<Periodic> periodic;
  struct EventUpdateRef {
    int leaf, update;
    std::vector<int> guards;  // indices into `guards` that trigger it; empty with any = true
    bool any = false;
  };
  std::vector<EventUpdateRef> event_updates;
  std::vector<char> guard_fired;  // per entry of `guards`, at the current event instant
  std::vector<EventRecord> fired_records;
  std::vector<Eigen::VectorXd> xdot, xd_next;
  std::vector<char> xd_touched;
  std::vector<State> state_buf;
  int nx_integrated = 0;  // >= 1 (a dummy state when the diagram has none)

  SUNContext sunctx = nullptr;
  N_Vector y = nullptr;
  N_Vector ele = nullptr, ewt = nullptr;  // ERK: the last step's local error estimate and error weights
  double stop_step_h = 0.0;  // ERK: the step size the error test suggests after a step clipped to a stop time (0: none)
  void* mem = nullptr;
  SUNMatrix A = nullptr;
  SUNLinearSolver LS = nullptr;
  SUNNonlinearSolver NLS = nullptr;
  SimulatorStatistics acc;  // integrator counters of the earlier integrator lives (only the counter fields are used)
  long root_calls = 0;      // root-function (guard) evaluations over every life
  bool life_after_reset = false;  // the current integrator life began with a state reset (reinit without carry)
  std::exception_ptr error;
  std::string cvode_message;
  std::string failure;  // non-finite derivative report from the RHS
  double last_event_time = -std::numeric_limits<double>::infinity();
  int events_at_instant = 0;

  bool erk = false;  // IntegrationScheme::kExplicitRungeKutta: ARKODE's ERKStep instead of CVODE

  ~Impl() { FreeCvode(); }
  void FreeCvode() {
    if (mem) {
      if (erk)
        ERKStepFree(&mem);
      else
        CVodeFree(&mem);
    }
    if (NLS) SUNNonlinSolFree(NLS);
    if (LS) SUNLinSolFree(LS);
    if (A) SUNMatDestroy(A);
    if (y) N_VDestroy(y);
    if (ele) N_VDestroy(ele);
    if (ewt) N_VDestroy(ewt);
    if (sunctx) SUNContext_Free(&sunctx);
    mem = nullptr;
    LS = nullptr;
    NLS = nullptr;
    A = nullptr;
    y = nullptr;
    ele = ewt = nullptr;
    stop_step_h = 0.0;  // a re-created integrator starts with its own estimate
    sunctx = nullptr;
  }

  void StateToContexts(double t, const double* ydata) {
    for (size_t i = 0; i < systems.size(); ++i) {
      const int n = systems[i]->num_continuous_states();
      if (n > 0) contexts[i]->state_.continuous = Eigen::Map<const Eigen::VectorXd>(ydata + xc_offset[i], n);
    }
    if (!contexts.empty()) contexts[0]->SetTime(t);  // shared clock; bumps the shared cache version
  }
  void ContextsToState(double* ydata) const {
    for (size_t i = 0; i < systems.size(); ++i) {
      const int n = systems[i]->num_continuous_states();
      if (n > 0) Eigen::Map<Eigen::VectorXd>(ydata + xc_offset[i], n) = contexts[i]->state_.continuous;
    }
    if (nx_integrated == 1 && xc_offset.empty()) ydata[0] = 0.0;
  }
  // Integrator counters since the last (re)initialisation, added to `out`'s counter fields.
  void AddCounters(SimulatorStatistics* out) const {
    if (!mem) return;
    long steps = 0, rhs = 0, jac = 0, jac_rhs = 0, nli = 0, etf = 0, ncf = 0;
    // Root-function evaluations are counted by the callback (root_calls): ARKODE's own counter is uninitialised after
    // ERKStepRootInit until the first step, and a reinitialisation without a step would count it twice.
    if (erk) {
      ERKStepGetNumSteps(mem, &steps);
      if (life_after_reset && steps > 0) {
        double h0 = 0.0;
        ERKStepGetActualInitStep(mem, &h0);
        out->max_initial_step_after_reset_s = std::max(out->max_initial_step_after_reset_s, h0);
      }
      ERKStepGetNumRhsEvals(mem, &rhs);
      ERKStepGetNumErrTestFails(mem, &etf);
    } else {
      CVodeGetNumSteps(mem, &steps);
      CVodeGetNumRhsEvals(mem, &rhs);
      CVodeGetNumErrTestFails(mem, &etf);
      CVodeGetNumNonlinSolvIters(mem, &nli);
      CVodeGetNumNonlinSolvConvFails(mem, &ncf);
      if (LS) {
        CVodeGetNumJacEvals(mem, &jac);
        CVodeGetNumLinRhsEvals(mem, &jac_rhs);
      }
    }
    out->steps += steps;
    out->rhs_evals += rhs + jac_rhs;
    out->jacobian_evals += jac;
    out->jacobian_rhs_evals += jac_rhs;
    out->nonlinear_iterations += nli;
    out->error_test_failures += etf;
    out->convergence_failures += ncf;
  }
  void AccumulateCounters() { AddCounters(&acc); }
};

struct SimulatorCallbacks {
  static int Rhs(sunrealtype t, N_Vector y, N_Vector ydot, void* user_data) {
    auto* impl = static_cast<Simulator::Impl*>(user_data);
    try {
      double* yd = N_VGetArrayPointer(ydot);
      impl->StateToContexts(t, N_VGetArrayPointer(y));
      bool any = false;
      for (size_t i = 0; i < impl->systems.size(); ++i) {
        const int n = impl->systems[i]->num_continuous_states();
        if (n == 0) continue;
        any = true;
        impl->systems[i]->CalcTimeDerivatives(*impl->contexts[i], &impl->xdot[i]);
        const Eigen::VectorXd& d = impl->xdot[i];
        if (d.size() != n)
          throw std::runtime_error("system '" + impl->paths[i] + "': DoCalcTimeDerivatives produced size " +
                                   std::to_string(d.size()) + ", expected " + std::to_string(n));
        if (!d.allFinite()) {
          std::ostringstream os;
          os << "system '" << impl->paths[i] << "' produced a non-finite time derivative at t = " << t << " (mode '"
             << impl->systems[i]->mode_name(impl->contexts[i]->mode()) << "')";
          impl->failure = os.str();
          return -1;
        }
        Eigen::Map<Eigen::VectorXd>(yd + impl->xc_offset[i], n) = d;
      }
      if (!any) yd[0] = 0.0;
      return 0;
    } catch (...) {
      impl->error = std::current_exception();
      return -1;
    }
  }
  static int Roots(sunrealtype t, N_Vector y, sunrealtype* gout, void* user_data) {
    auto* impl = static_cast<Simulator::Impl*>(user_data);
    ++impl->root_calls;
    try {
      impl->StateToContexts(t, N_VGetArrayPointer(y));
      for (const auto& g : impl->guards) {
        const LeafSystem::Guard& guard = impl->systems[g.leaf]->guards()[g.guard];
        Eigen::Map<Eigen::VectorXd> out(gout + g.root_offset, guard.size);
        if (LeafSystem::GuardActiveIn(guard, impl->contexts[g.leaf]->mode())) {
          guard.witness(*impl->contexts[g.leaf], out);
        } else {
          out.setOnes();  // inactive guards never cross
        }
      }
      return 0;
    } catch (...) {
      impl->error = std::current_exception();
      return -1;
    }
  }
  static void ErrHandler(int, const char* module, const char* function, char* msg, void* user_data) {
    auto* impl = static_cast<Simulator::Impl*>(user_data);
    impl->cvode_message = std::string(module) + "::" + function + ": " + msg;
  }
};

Simulator::Simulator(const System& system, SimulatorConfig config)
    : Simulator(system, system.CreateDefaultContext(), config) {}

Simulator::Simulator(const System& system, std::unique_ptr<Context> context, SimulatorConfig config)
    : impl_(std::make_unique<Impl>()), system_(system), context_(std::move(context)), config_(config) {
  if (!context_) throw std::invalid_argument("Simulator: null context for system '" + system.name() + "'");
  Impl& m = *impl_;
  if (system.is_diagram()) {
    const auto& d = static_cast<const Diagram&>(system);
    auto& dc = static_cast<DiagramContext&>(*context_);
    for (int i = 0; i < d.num_leaves(); ++i) {
      m.systems.push_back(&d.leaf(i));
      m.contexts.push_back(&d.GetMutableSubsystemContext(d.leaf(i), dc));
      m.paths.push_back(d.leaf_path(i));
    }
  } else {
    if (context_->is_diagram_context())
      throw std::invalid_argument("Simulator: leaf system '" + system.name() + "' given a diagram context");
    m.systems.push_back(static_cast<const LeafSystem*>(&system));
    m.contexts.push_back(static_cast<LeafContext*>(context_.get()));
    m.paths.push_back(system.name());
  }
  int offset = 0;
  for (size_t i = 0; i < m.systems.size(); ++i) {
    const LeafSystem& s = *m.systems[i];
    m.xc_offset.push_back(offset);
    offset += s.num_continuous_states();
    m.xdot.emplace_back(Eigen::VectorXd::Zero(s.num_continuous_states()));
    m.xd_next.emplace_back(Eigen::VectorXd::Zero(s.num_discrete_states()));
    m.state_buf.push_back(m.contexts[i]->state());
    for (int g = 0; g < static_cast<int>(s.guards().size()); ++g) {
      const auto& guard = s.guards()[g];
      m.guards.push_back({static_cast<int>(i), g, m.nroots});
      for (int c = 0; c < guard.size; ++c)
        m.rootdir.push_back(guard.direction == CrossingDirection::kRising    ? 1
                            : guard.direction == CrossingDirection::kFalling ? -1
                                                                             : 0);
      m.nroots += guard.size;
    }
    for (int e = 0; e < static_cast<int>(s.periodic_events().size()); ++e) {
      const auto& pe = s.periodic_events()[e];
      m.periodic.push_back({static_cast<int>(i), e, pe.period, pe.offset, 0});
    }
  }
  // Event updates: resolve the systems and guards their triggers name.
  auto basename = [](const std::string& path) { return path.substr(path.rfind('/') + 1); };
  for (size_t i = 0; i < m.systems.size(); ++i) {
    const auto& ups = m.systems[i]->event_updates();
    for (int u = 0; u < static_cast<int>(ups.size()); ++u) {
      Impl::EventUpdateRef ref{static_cast<int>(i), u, {}, ups[u].trigger.any()};
      for (const auto& name : ups[u].trigger.guards) {
        int leaf = -1;
        for (size_t k = 0; k < m.systems.size() && leaf < 0; ++k)
          if (m.paths[k] == name.system) leaf = static_cast<int>(k);
        for (size_t k = 0; k < m.systems.size() && leaf < 0; ++k)
          if (basename(m.paths[k]) == name.system) leaf = static_cast<int>(k);
        const std::string who = "system '" + m.paths[i] + "': event update '" + ups[u].name + "'";
        if (leaf < 0)
          throw std::invalid_argument(who + " names system '" + name.system + "', which is not in '" + system.name() +
                                      "'");
        const bool prefix = name.guard.back() == '*';
        const std::string stem = prefix ? name.guard.substr(0, name.guard.size() - 1) : name.guard;
        bool found = false;
        std::string known;
        for (size_t k = 0; k < m.guards.size(); ++k) {
          if (m.guards[k].leaf != leaf) continue;
          const std::string& gname = m.systems[leaf]->guards()[m.guards[k].guard].name;
          known += (known.empty() ? "'" : ", '") + gname + "'";
          if (prefix ? gname.compare(0, stem.size(), stem) == 0 : gname == stem) {
            ref.guards.push_back(static_cast<int>(k));
            found = true;
          }
        }
        if (!found)
          throw std::invalid_argument(who + " names guard '" + name.guard + "' of system '" + m.paths[leaf] +
                                      "', which has no such guard (it has " + (known.empty() ? "none" : known) + ")");
      }
      m.event_updates.push_back(std::move(ref));
    }
  }
  m.guard_fired.assign(m.guards.size(), 0);
  m.xd_touched.assign(m.systems.size(), 0);
  m.rootsfound.assign(m.nroots, 0);
  nx_ = offset;
  m.nx_integrated = std::max(offset, 1);
  if (offset == 0) m.xc_offset.clear();  // marks the dummy state
  if (offset == 0) m.xc_offset.assign(m.systems.size(), 0);
}

Simulator::~Simulator() = default;

void Simulator::set_config(const SimulatorConfig& config) {
  config_ = config;
  if (initialized_) Initialize();
}

void Simulator::set_monitor(Monitor monitor) {
  monitors_.clear();
  if (monitor) add_monitor(std::move(monitor));
}

int Simulator::remove_monitor(const std::string& name) {
  const auto removed = std::erase_if(monitors_, [&](const NamedMonitor& m) { return m.name == name; });
  return static_cast<int>(removed);
}

void Simulator::add_monitor(Monitor monitor, std::string name) {
  if (!monitor) throw std::invalid_argument("Simulator::add_monitor: monitor '" + name + "' is an empty function");
  monitors_.push_back({std::move(monitor), std::move(name)});
}

namespace {
EventStatus RunEventPublishes(Simulator::Impl& m);
}

SimulatorStatus Simulator::Initialize() {
  Impl& m = *impl_;
  if (m.mem) m.AccumulateCounters();
  m.FreeCvode();
  const double t0 = context_->time();
  if (SUNContext_Create(nullptr, &m.sunctx) != 0) throw std::runtime_error("Simulator: SUNContext_Create failed");
  m.y = N_VNew_Serial(m.nx_integrated, m.sunctx);
  N_VConst(0.0, m.y);
  if (nx_ > 0) m.ContextsToState(N_VGetArrayPointer(m.y));
  if (!(config_.relative_tolerance > 0) || !(config_.absolute_tolerance > 0))
    throw std::invalid_argument("SimulatorConfig: tolerances must be positive (relative_tolerance = " +
                                std::to_string(config_.relative_tolerance) +
                                ", absolute_tolerance = " + std::to_string(config_.absolute_tolerance) + ")");
  if (config_.max_guard_events < 0)
    throw std::invalid_argument("SimulatorConfig: max_guard_events must be 0 (no limit) or positive, got " +
                                std::to_string(config_.max_guard_events));
  m.erk = config_.scheme == IntegrationScheme::kExplicitRungeKutta;
  if (m.erk) {
    // Dormand-Prince 5(4) or Bogacki-Shampine 3(2), error-controlled; one-step, so a restart at every sample costs
    // nothing extra.
    m.mem = ERKStepCreate(&SimulatorCallbacks::Rhs, t0, m.y, m.sunctx);
    if (!m.mem) throw std::runtime_error("Simulator: ERKStepCreate failed");
    if (config_.restart_with_last_step) {
      m.ele = N_VClone(m.y);
      m.ewt = N_VClone(m.y);
      if (!m.ele || !m.ewt) throw std::runtime_error("Simulator: N_VClone failed");
    }
    ERKStepSetErrHandlerFn(m.mem, &SimulatorCallbacks::ErrHandler, &m);
    ERKStepSetTableNum(m.mem, config_.explicit_rk_method == ExplicitRungeKuttaMethod::kBogackiShampine32
                                  ? ARKODE_BOGACKI_SHAMPINE_4_2_3
                                  : ARKODE_DORMAND_PRINCE_7_4_5);
    ERKStepSStolerances(m.mem, config_.relative_tolerance, config_.absolute_tolerance);
    ERKStepSetUserData(m.mem, &m);
    if (config_.max_step_s > 0) ERKStepSetMaxStep(m.mem, config_.max_step_s);
    if (config_.initial_step_s > 0) ERKStepSetInitStep(m.mem, config_.initial_step_s);
    ERKStepSetMaxNumSteps(m.mem, 100000);
    if (m.nroots > 0) {
      ERKStepRootInit(m.mem, m.nroots, &SimulatorCallbacks::Roots);
      ERKStepSetRootDirection(m.mem, m.rootdir.data());
      ERKStepSetNoInactiveRootWarn(m.mem);
    }
  } else {
    m.mem = CVodeCreate(config_.scheme == IntegrationScheme::kBdf ? CV_BDF : CV_ADAMS, m.sunctx);
    if (!m.mem) throw std::runtime_error("Simulator: CVodeCreate failed");
    CVodeSetErrHandlerFn(m.mem, &SimulatorCallbacks::ErrHandler, &m);
    if (CVodeInit(m.mem, &SimulatorCallbacks::Rhs, t0, m.y) != CV_SUCCESS)
      throw std::runtime_error("Simulator: CVodeInit failed: " + m.cvode_message);
    CVodeSStolerances(m.mem, config_.relative_tolerance, config_.absolute_tolerance);
    CVodeSetUserData(m.mem, &m);
    if (config_.scheme == IntegrationScheme::kAdamsFunctional) {
      // Fixed-point iteration with no Anderson acceleration: no Jacobian, no linear solver.
      m.NLS = SUNNonlinSol_FixedPoint(m.y, 0, m.sunctx);
      if (!m.NLS || CVodeSetNonlinearSolver(m.mem, m.NLS) != CV_SUCCESS)
        throw std::runtime_error("Simulator: could not attach CVODE's fixed-point solver: " + m.cvode_message);
    } else {
      m.A = SUNDenseMatrix(m.nx_integrated, m.nx_integrated, m.sunctx);
      m.LS = SUNLinSol_Dense(m.y, m.A, m.sunctx);
      CVodeSetLinearSolver(m.mem, m.LS, m.A);
    }
    if (config_.max_step_s > 0) CVodeSetMaxStep(m.mem, config_.max_step_s);
    if (config_.initial_step_s > 0) CVodeSetInitStep(m.mem, config_.initial_step_s);
    if (config_.max_order > 0) CVodeSetMaxOrd(m.mem, config_.max_order);
    CVodeSetMaxNumSteps(m.mem, 100000);
    if (m.nroots > 0) {
      CVodeRootInit(m.mem, m.nroots, &SimulatorCallbacks::Roots);
      CVodeSetRootDirection(m.mem, m.rootdir.data());
      CVodeSetNoInactiveRootWarn(m.mem);
    }
  }
  // First sample index of every periodic event at or after t0.
  for (auto& p : m.periodic) {
    p.k = 0;
    if (t0 > p.offset) p.k = static_cast<long>(std::ceil((t0 - p.offset) / p.period - 1e-9));
  }
  initialized_ = true;
  terminated_ = false;
  SimulatorStatus status;
  status.time = t0;
  EventStatus es = RunEventPublishes(m);
  if (!es.ok()) {
    status.reason = es.kind == EventStatus::Kind::kFailed ? SimulatorStatus::Reason::kFailed
                                                          : SimulatorStatus::Reason::kReachedTermination;
    status.message = es.message;
    terminated_ = true;
    terminal_status_ = status;
  }
  return status;
}

namespace {

EventStatus RunEventPublishes(Simulator::Impl& m) {
  for (size_t i = 0; i < m.systems.size(); ++i)
    for (const auto& pub : m.systems[i]->event_publishes()) {
      EventStatus s = pub(*m.contexts[i]);
      if (!s.ok()) return s;
    }
  return EventStatus::Succeeded();
}

bool SameTime(double a, double b) { return std::isfinite(a) && std::abs(a - b) <= 1e-12 * std::max(1.0, std::abs(a)); }

}  // namespace

SimulatorStatus Simulator::AdvanceTo(double t_final) {
  if (!initialized_) {
    SimulatorStatus s = Initialize();
    if (!s.ok()) return s;
  }
  if (terminated_) return terminal_status_;
  Impl& m = *impl_;
  if (!std::isfinite(t_final))
    throw std::invalid_argument("Simulator::AdvanceTo: t_final must be finite, got " + std::to_string(t_final));
  long steps_this_advance = 0;
  while (true) {
    double t = context_->time();
    if (t >= t_final || SameTime(t, t_final)) break;
    if (const int signal = InterruptSignal(); signal != 0)
      return Finish(SimulatorStatus::Reason::kInterrupted, "", "signal " + std::to_string(signal));
    // (a) Periodic events due now.
    double next_sample = std::numeric_limits<double>::infinity();
    for (const auto& p : m.periodic) next_sample = std::min(next_sample, p.next_time());
    if (next_sample <= t || SameTime(next_sample, t)) {
      if (std::optional<SimulatorStatus> end = RunPeriodicEvents(next_sample)) return *end;
      continue;
    }
    // (b) One integrator step towards the next stop.
    int flag = 0;
    double t_ret = t;
    if (std::optional<SimulatorStatus> end = Step(std::min(next_sample, t_final), &flag, &t_ret)) return *end;
    if (++steps_this_advance > config_.max_steps_per_advance)
      return Finish(SimulatorStatus::Reason::kFailed, "",
                    "more than max_steps_per_advance = " + std::to_string(config_.max_steps_per_advance) + " steps");
    // Non-finite state check, naming the system.
    if (!Eigen::Map<const Eigen::VectorXd>(N_VGetArrayPointer(m.y), m.nx_integrated).allFinite()) {
      for (size_t i = 0; i < m.systems.size(); ++i)
        if (!m.contexts[i]->continuous_state().allFinite())
          return Finish(SimulatorStatus::Reason::kFailed, m.paths[i], "NaN or Inf in the continuous state");
    }
    // (c) Guards.
    if (flag == CV_ROOT_RETURN) {
      if (std::optional<SimulatorStatus> end = HandleGuards(t_ret)) return *end;
    }
    for (const NamedMonitor& monitor : monitors_) {
      EventStatus es = monitor.monitor(*context_);
      if (!es.ok()) return FromEvent(es, monitor.name);
    }
  }
  return Finish(SimulatorStatus::Reason::kReachedBoundaryTime, "", "");
}

SimulatorStatus Simulator::Finish(SimulatorStatus::Reason reason, const std::string& sys, const std::string& msg) {
  Impl& m = *impl_;
  SimulatorStatus status;
  status.reason = reason;
  status.system = sys;
  status.message = msg;
  status.time = context_->time();
  if (reason == SimulatorStatus::Reason::kReachedBoundaryTime)
    status.message = status.ToString();  // "reached the time limit t = ..."
  if (reason != SimulatorStatus::Reason::kReachedBoundaryTime) {
    terminated_ = true;
    terminal_status_ = status;
  }
  stats_.steps = m.acc.steps;
  stats_.rhs_evals = m.acc.rhs_evals;
  stats_.root_evals = m.root_calls;
  stats_.jacobian_evals = m.acc.jacobian_evals;
  stats_.jacobian_rhs_evals = m.acc.jacobian_rhs_evals;
  stats_.nonlinear_iterations = m.acc.nonlinear_iterations;
  stats_.error_test_failures = m.acc.error_test_failures;
  stats_.convergence_failures = m.acc.convergence_failures;
  stats_.restarts = m.acc.restarts;
  stats_.max_initial_step_after_reset_s = m.acc.max_initial_step_after_reset_s;
  m.AddCounters(&stats_);
  if (reason == SimulatorStatus::Reason::kZeno && config_.event_policy.throw_on_violation)
    throw std::runtime_error(status.ToString());
  return status;
}

SimulatorStatus Simulator::FromEvent(const EventStatus& es, const std::string& sys) {
  return Finish(es.kind == EventStatus::Kind::kFailed ? SimulatorStatus::Reason::kFailed
                                                      : SimulatorStatus::Reason::kReachedTermination,
                sys, es.message);
}

void Simulator::Reinitialize(bool carry_step) {
  Impl& m = *impl_;
  m.AccumulateCounters();
  ++m.acc.restarts;
  m.ContextsToState(N_VGetArrayPointer(m.y));
  if (!m.erk) {
    CVodeReInit(m.mem, context_->time(), m.y);
    return;
  }
  // A one-step method needs no history: after a discrete update, start the new interval with the step size the error
  // control asked for at the end of the last one instead of ARKODE's conservative initial-step estimate (which costs
  // derivative evaluations and usually a few short steps). A step that is too long is rejected by the same error test.
  // Not after a guard's reset: the state jumped, and the root finder's check of a guard that is 0 at the restart looks
  // a fraction of the first step ahead.
  double h_next = 0.0;
  if (carry_step && config_.restart_with_last_step) {
    ERKStepGetCurrentStep(m.mem, &h_next);
    h_next = std::max(h_next, m.stop_step_h);
  }
  m.life_after_reset = !carry_step;
  ERKStepReInit(m.mem, &SimulatorCallbacks::Rhs, context_->time(), m.y);
  // Always set it: ARKODE keeps the last value across ERKStepReInit (0 restores its own estimate).
  ERKStepSetInitStep(m.mem, h_next > 0.0 ? h_next : config_.initial_step_s);
}

std::optional<SimulatorStatus> Simulator::RunPeriodicEvents(double next_sample) {
  Impl& m = *impl_;
  bool any_update = false;
  for (auto& p : m.periodic) {
    if (!SameTime(p.next_time(), next_sample)) continue;
    const auto& ev = m.systems[p.leaf]->periodic_events()[p.event];
    if (ev.update) {
      if (!m.xd_touched[p.leaf]) {
        m.xd_next[p.leaf] = m.contexts[p.leaf]->discrete_state();
        m.xd_touched[p.leaf] = 1;
      }
      EventStatus es = ev.update(*m.contexts[p.leaf], &m.xd_next[p.leaf]);
      if (m.xd_next[p.leaf].size() != m.systems[p.leaf]->num_discrete_states())
        throw std::runtime_error("system '" + m.paths[p.leaf] +
                                 "': a discrete update changed the size of the discrete state to " +
                                 std::to_string(m.xd_next[p.leaf].size()));
      if (!es.ok()) return FromEvent(es, m.paths[p.leaf]);
      any_update = true;
    }
  }
  for (size_t i = 0; i < m.systems.size(); ++i)
    if (m.xd_touched[i]) {
      m.contexts[i]->get_mutable_discrete_state() = m.xd_next[i];
      m.xd_touched[i] = 0;
    }
  for (auto& p : m.periodic) {
    if (!SameTime(p.next_time(), next_sample)) continue;
    const auto& ev = m.systems[p.leaf]->periodic_events()[p.event];
    if (ev.publish) {
      EventStatus es = ev.publish(*m.contexts[p.leaf]);
      if (!es.ok()) return FromEvent(es, m.paths[p.leaf]);
    }
    ++p.k;
  }
  ++stats_.discrete_samples;
  EventStatus es = RunEventPublishes(m);
  if (!es.ok()) return FromEvent(es, "");
  if (any_update) Reinitialize(true);
  return std::nullopt;
}

std::optional<SimulatorStatus> Simulator::Step(double t_stop, int* flag_out, double* t_ret) {
  Impl& m = *impl_;
  m.cvode_message.clear();
  // CVODE and ARKODE share the return codes used here (success 0, tstop 1, root 2, errors < 0).
  static_assert(CV_TSTOP_RETURN == ARK_TSTOP_RETURN && CV_ROOT_RETURN == ARK_ROOT_RETURN);
  int& flag = *flag_out;
  if (m.erk) {
    ERKStepSetStopTime(m.mem, t_stop);
    flag = ERKStepEvolve(m.mem, t_stop, m.y, t_ret, ARK_ONE_STEP);
  } else {
    CVodeSetStopTime(m.mem, t_stop);
    flag = CVode(m.mem, t_stop, m.y, t_ret, CV_ONE_STEP);
  }
  if (m.error) {
    std::exception_ptr e = m.error;
    m.error = nullptr;
    terminated_ = true;
    std::rethrow_exception(e);
  }
  if (flag < 0) {
    if (!m.failure.empty()) return Finish(SimulatorStatus::Reason::kFailed, "", m.failure);
    return Finish(SimulatorStatus::Reason::kFailed, "",
                  std::string(m.erk ? "ARKODE" : "CVODE") + " error " + std::to_string(flag) + ": " + m.cvode_message);
  }
  if (flag == CV_TSTOP_RETURN) *t_ret = t_stop;  // exact sample times
  m.stop_step_h = 0.0;
  if (m.erk && flag == CV_TSTOP_RETURN && config_.restart_with_last_step) {
    // ARKODE clips the step that lands on the stop time and then reports that clipped size as its next step, so
    // carrying it over would start every control interval with a short step (measured on the hop: 2 steps in
    // every 0.5 ms interval, 0.45 + 0.05 ms, where one 0.5 ms step passes the error test). The size the error
    // test asks for instead, from this step's local error estimate (elementary controller, order p + 1 of the
    // embedded error, safety 0.9, growth at most 20 as ARKODE's own bound).
    double h_last = 0.0;
    ERKStepGetLastStep(m.mem, &h_last);
    ERKStepGetEstLocalErrors(m.mem, m.ele);
    ERKStepGetErrWeights(m.mem, m.ewt);
    const double dsm = N_VWrmsNorm(m.ele, m.ewt);
    const double p1 = config_.explicit_rk_method == ExplicitRungeKuttaMethod::kBogackiShampine32 ? 3.0 : 5.0;
    const double growth = dsm > 0.0 ? std::clamp(0.9 * std::pow(dsm, -1.0 / p1), 1.0, 20.0) : 20.0;
    m.stop_step_h = h_last * growth;
  }
  m.StateToContexts(*t_ret, N_VGetArrayPointer(m.y));
  return std::nullopt;
}

std::optional<SimulatorStatus> Simulator::HandleGuards(double t_ret) {
  Impl& m = *impl_;
  if (m.erk)
    ERKStepGetRootInfo(m.mem, m.rootsfound.data());
  else
    CVodeGetRootInfo(m.mem, m.rootsfound.data());
  std::fill(m.guard_fired.begin(), m.guard_fired.end(), 0);
  m.fired_records.clear();
  for (size_t gi = 0; gi < m.guards.size(); ++gi) {
    const auto& g = m.guards[gi];
    const LeafSystem& sys = *m.systems[g.leaf];
    const LeafSystem::Guard& guard = sys.guards()[g.guard];
    LeafContext& ctx = *m.contexts[g.leaf];
    if (!LeafSystem::GuardActiveIn(guard, ctx.mode())) continue;
    int component = -1;
    for (int c = 0; c < guard.size; ++c)
      if (m.rootsfound[g.root_offset + c] != 0) {
        component = c;
        break;
      }
    if (component < 0) continue;
    // Zeno policy.
    if (t_ret - m.last_event_time < config_.event_policy.min_event_separation_s) {
      if (++m.events_at_instant > config_.event_policy.max_events_per_instant) {
        std::ostringstream os;
        os << "guard '" << guard.name << "' fired " << m.events_at_instant << " times with less than "
           << config_.event_policy.min_event_separation_s
           << " s between events (EventPolicy::max_events_per_instant = " << config_.event_policy.max_events_per_instant
           << ")";
        return Finish(SimulatorStatus::Reason::kZeno, m.paths[g.leaf], os.str());
      }
    } else {
      m.events_at_instant = 1;
    }
    m.last_event_time = t_ret;
    State& next = m.state_buf[g.leaf];
    next = ctx.state();
    const int mode_before = ctx.mode();
    EventStatus es = guard.reset ? guard.reset(ctx, component, &next) : EventStatus::Succeeded();
    if (next.continuous.size() != sys.num_continuous_states() || next.discrete.size() != sys.num_discrete_states() ||
        next.mode < 0 || next.mode >= sys.num_modes())
      throw std::runtime_error("system '" + m.paths[g.leaf] + "': the reset of guard '" + guard.name +
                               "' produced a state of the wrong size or an unknown mode " + std::to_string(next.mode));
    ctx.get_mutable_state() = next;
    ++stats_.guard_events;
    stats_.events.push_back({t_ret, m.paths[g.leaf], guard.name, component, mode_before, next.mode});
    m.guard_fired[gi] = 1;
    m.fired_records.push_back(stats_.events.back());
    if (!es.ok()) return FromEvent(es, m.paths[g.leaf]);
  }
  if (std::optional<SimulatorStatus> end = RunEventUpdates()) return end;
  EventStatus es = RunEventPublishes(m);
  if (!es.ok()) return FromEvent(es, "");
  if (config_.max_guard_events > 0 && stats_.guard_events >= config_.max_guard_events)
    return Finish(SimulatorStatus::Reason::kReachedEventLimit, "",
                  "reached the event limit of " + std::to_string(config_.max_guard_events) +
                      " guard events (SimulatorConfig::max_guard_events)");
  Reinitialize(false);
  return std::nullopt;
}

std::optional<SimulatorStatus> Simulator::RunEventUpdates() {
  Impl& m = *impl_;
  // Event updates, in diagram order, each seeing the state left by the resets and earlier updates.
  if (m.fired_records.empty()) return std::nullopt;
  for (const auto& ref : m.event_updates) {
    const EventRecord* trigger = nullptr;
    if (ref.any) {
      trigger = &m.fired_records.front();
    } else {
      for (int gi : ref.guards)
        if (m.guard_fired[gi]) {
          const auto& g = m.guards[gi];
          const std::string& gname = m.systems[g.leaf]->guards()[g.guard].name;
          for (const auto& rec : m.fired_records)
            if (rec.guard == gname && rec.system == m.paths[g.leaf]) trigger = &rec;
          break;
        }
    }
    if (trigger == nullptr) continue;
    const LeafSystem& sys = *m.systems[ref.leaf];
    LeafContext& ctx = *m.contexts[ref.leaf];
    State& next = m.state_buf[ref.leaf];
    next = ctx.state();
    EventStatus es = sys.event_updates()[ref.update].update(ctx, *trigger, &next);
    if (next.discrete.size() != sys.num_discrete_states() || next.mode < 0 || next.mode >= sys.num_modes())
      throw std::runtime_error(
          "system '" + m.paths[ref.leaf] + "': event update '" + sys.event_updates()[ref.update].name +
          "' produced a discrete state of the wrong size or an unknown mode " + std::to_string(next.mode));
    State& cur = ctx.get_mutable_state();
    cur.discrete = next.discrete;
    cur.mode = next.mode;
    if (!es.ok()) return FromEvent(es, m.paths[ref.leaf]);
  }
  return std::nullopt;
}

}  // namespace rome
