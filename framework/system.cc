#include "framework/system.h"

#include <cxxabi.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

namespace rome {

namespace {
std::string SizeString(const Eigen::VectorXd& v) { return std::to_string(v.size()); }
}  // namespace

std::string DemangledTypeName(const std::type_info& type) {
  int status = 0;
  char* name = abi::__cxa_demangle(type.name(), nullptr, nullptr, &status);
  std::string out = (status == 0 && name != nullptr) ? name : type.name();
  std::free(name);
  return out;
}

std::string PortInfo::TypeString() const {
  return is_vector() ? "a vector of size " + std::to_string(size) : DemangledTypeName(*value_type);
}

bool PortInfo::SameTypeAs(const PortInfo& other) const {
  if (is_vector() != other.is_vector()) return false;
  return is_vector() ? size == other.size : *value_type == *other.value_type;
}

bool Feedthrough::DependsOn(int input) const {
  return all_ || std::find(inputs_.begin(), inputs_.end(), input) != inputs_.end();
}

System::System(std::string name) : name_(std::move(name)) {
  if (name_.empty()) throw std::invalid_argument("System: a system needs a non-empty name");
}

const PortInfo& System::input_port(int index) const {
  if (index < 0 || index >= num_input_ports())
    throw std::out_of_range("system '" + name_ + "' has no input port " + std::to_string(index));
  return input_ports_[index];
}

const PortInfo& System::output_port(int index) const {
  if (index < 0 || index >= num_output_ports())
    throw std::out_of_range("system '" + name_ + "' has no output port " + std::to_string(index));
  return output_ports_[index];
}

static std::string PortList(const std::vector<PortInfo>& ports) {
  std::string s;
  for (const auto& p : ports) s += (s.empty() ? "'" : ", '") + p.name + "'";
  return s.empty() ? "none" : s;
}

int System::GetInputPortIndex(const std::string& port_name) const {
  for (int i = 0; i < num_input_ports(); ++i)
    if (input_ports_[i].name == port_name) return i;
  throw std::invalid_argument("system '" + name_ + "' has no input port '" + port_name + "' (it has " +
                              PortList(input_ports_) + ")");
}

int System::GetOutputPortIndex(const std::string& port_name) const {
  for (int i = 0; i < num_output_ports(); ++i)
    if (output_ports_[i].name == port_name) return i;
  throw std::invalid_argument("system '" + name_ + "' has no output port '" + port_name + "' (it has " +
                              PortList(output_ports_) + ")");
}

void System::CheckPortType(const PortInfo& port, const std::type_info& type, const char* direction) const {
  if (!port.is_vector() && *port.value_type == type) return;
  throw std::invalid_argument("system '" + name_ + "': " + direction + " port '" + port.name + "' carries " +
                              port.TypeString() + ", not " + DemangledTypeName(type));
}

bool System::HasInputPort(const std::string& port_name) const {
  return std::any_of(input_ports_.begin(), input_ports_.end(), [&](const PortInfo& p) { return p.name == port_name; });
}
bool System::HasOutputPort(const std::string& port_name) const {
  return std::any_of(output_ports_.begin(), output_ports_.end(),
                     [&](const PortInfo& p) { return p.name == port_name; });
}

// ---------------------------------------------------------------------------------------------------------
// LeafContext

void LeafContext::set_mode(int mode) {
  if (mode < 0 || mode >= system_->num_modes())
    throw std::out_of_range("system '" + system_->name() + "': mode " + std::to_string(mode) +
                            " does not exist (it has " + std::to_string(system_->num_modes()) + " modes)");
  InvalidateCache();
  state_.mode = mode;
}

void LeafContext::FixInputPort(int index, const Eigen::VectorXd& value) {
  const PortInfo& port = system_->input_port(index);
  if (!port.is_vector())
    throw std::invalid_argument("input port '" + port.name + "' of system '" + system_->name() + "' carries " +
                                port.TypeString() +
                                "; fix it with a value of that type (FixTypedInputPort), not a vector");
  if (value.size() != port.size)
    throw std::invalid_argument("input port '" + port.name + "' of system '" + system_->name() + "' has size " +
                                std::to_string(port.size) + " but the fixed value has size " + SizeString(value));
  if (inputs_[index].kind == InputSource::Kind::kUpstream)
    throw std::logic_error("input port '" + port.name + "' of system '" + system_->name() +
                           "' is connected; it cannot also be fixed");
  fixed_inputs_[index] = value;
  inputs_[index].kind = InputSource::Kind::kFixed;
  inputs_[index].fixed_value = &fixed_inputs_[index];
  InvalidateCache();
}

void LeafContext::FixAbstractInputPort(int index, std::any value) {
  const PortInfo& port = system_->input_port(index);
  const std::type_info& given = value.type();
  if (port.is_vector() || *port.value_type != given)
    throw std::invalid_argument("input port '" + port.name + "' of system '" + system_->name() + "' carries " +
                                port.TypeString() + " but the fixed value is " + DemangledTypeName(given));
  if (inputs_[index].kind == InputSource::Kind::kUpstream)
    throw std::logic_error("input port '" + port.name + "' of system '" + system_->name() +
                           "' is connected; it cannot also be fixed");
  fixed_abstract_inputs_[index] = std::move(value);
  inputs_[index].kind = InputSource::Kind::kFixed;
  inputs_[index].fixed_abstract = &fixed_abstract_inputs_[index];
  InvalidateCache();
}

std::unique_ptr<LeafContext> LeafContext::CloneLeaf() const {
  std::unique_ptr<LeafContext> c(new LeafContext(*this));
  c->time_ = std::make_shared<double>(*time_);
  c->version_ = std::make_shared<std::uint64_t>(*version_);
  for (size_t i = 0; i < c->inputs_.size(); ++i) {
    InputSource& src = c->inputs_[i];
    if (src.fixed_value != nullptr) src.fixed_value = &c->fixed_inputs_[i];
    if (src.fixed_abstract != nullptr) src.fixed_abstract = &c->fixed_abstract_inputs_[i];
  }
  return c;
}

std::unique_ptr<Context> LeafContext::Clone() const {
  for (const InputSource& src : inputs_)
    if (src.kind == InputSource::Kind::kUpstream)
      throw std::logic_error("LeafContext::Clone: system '" + system_->name() +
                             "' is part of a diagram; clone the diagram's context");
  return CloneLeaf();
}

// ---------------------------------------------------------------------------------------------------------
// LeafSystem

void LeafSystem::ThrowError(const std::string& what) const {
  throw std::runtime_error("system '" + name() + "': " + what);
}

int LeafSystem::DeclareInputPort(std::string port_name, int size) {
  if (size < 0) ThrowError("input port '" + port_name + "' has negative size " + std::to_string(size));
  if (HasInputPort(port_name)) ThrowError("input port '" + port_name + "' is declared twice");
  input_ports_.push_back({std::move(port_name), size, {}, nullptr});
  return num_input_ports() - 1;
}

int LeafSystem::DeclareInputPort(std::string port_name, std::vector<std::string> element_names) {
  const int index = DeclareInputPort(std::move(port_name), static_cast<int>(element_names.size()));
  input_ports_[index].element_names = std::move(element_names);
  return index;
}

int LeafSystem::DeclareAbstractInputPort(std::string port_name, const std::type_info& type) {
  if (HasInputPort(port_name)) ThrowError("input port '" + port_name + "' is declared twice");
  input_ports_.push_back({std::move(port_name), 0, {}, &type});
  return num_input_ports() - 1;
}

int LeafSystem::DeclareOutputPort(std::string port_name, std::vector<std::string> element_names, OutputCalc calc,
                                  Feedthrough feedthrough) {
  const int index = DeclareOutputPort(std::move(port_name), static_cast<int>(element_names.size()), std::move(calc),
                                      std::move(feedthrough));
  output_ports_[index].element_names = std::move(element_names);
  return index;
}

int LeafSystem::DeclareAbstractOutputPort(std::string port_name, const std::type_info& type, std::any default_value,
                                          AbstractOutputCalc calc, Feedthrough feedthrough) {
  if (HasOutputPort(port_name)) ThrowError("output port '" + port_name + "' is declared twice");
  if (!calc) ThrowError("output port '" + port_name + "' has no calculation function");
  if (default_value.type() != type)
    ThrowError("output port '" + port_name + "' carries " + DemangledTypeName(type) + " but its default value is " +
               DemangledTypeName(default_value.type()));
  output_ports_.push_back({std::move(port_name), 0, {}, &type});
  output_decls_.push_back({nullptr, std::move(calc), std::move(default_value), std::move(feedthrough)});
  return num_output_ports() - 1;
}

int LeafSystem::DeclareOutputPort(std::string port_name, int size, OutputCalc calc, Feedthrough feedthrough) {
  if (size < 0) ThrowError("output port '" + port_name + "' has negative size " + std::to_string(size));
  if (HasOutputPort(port_name)) ThrowError("output port '" + port_name + "' is declared twice");
  if (!calc) ThrowError("output port '" + port_name + "' has no calculation function");
  output_ports_.push_back({std::move(port_name), size, {}, nullptr});
  output_decls_.push_back({std::move(calc), nullptr, {}, std::move(feedthrough)});
  return num_output_ports() - 1;
}

void LeafSystem::DeclareContinuousState(int size) { DeclareContinuousState(Eigen::VectorXd::Zero(size)); }

void LeafSystem::DeclareContinuousState(const Eigen::VectorXd& default_value) {
  num_continuous_states_ = static_cast<int>(default_value.size());
  default_continuous_state_ = default_value;
}

void LeafSystem::DeclareDiscreteState(const Eigen::VectorXd& default_value) { default_discrete_state_ = default_value; }

int LeafSystem::DeclareNumericParameter(std::string param_name, const Eigen::VectorXd& default_value) {
  parameter_names_.push_back(std::move(param_name));
  default_parameters_.push_back(default_value);
  return num_numeric_parameters() - 1;
}

int LeafSystem::GetNumericParameterIndex(const std::string& param_name) const {
  for (int i = 0; i < num_numeric_parameters(); ++i)
    if (parameter_names_[i] == param_name) return i;
  ThrowError("no numeric parameter named '" + param_name + "'");
}

void LeafSystem::DeclareModes(std::vector<std::string> names, int default_mode) {
  if (names.empty()) ThrowError("DeclareModes needs at least one mode");
  if (default_mode < 0 || default_mode >= static_cast<int>(names.size()))
    ThrowError("default mode " + std::to_string(default_mode) + " is out of range");
  mode_names_ = std::move(names);
  default_mode_ = default_mode;
}

const std::string& LeafSystem::mode_name(int mode) const {
  if (mode < 0 || mode >= num_modes()) ThrowError("mode " + std::to_string(mode) + " does not exist");
  return mode_names_[mode];
}

int LeafSystem::GetModeIndex(const std::string& mode) const {
  for (int i = 0; i < num_modes(); ++i)
    if (mode_names_[i] == mode) return i;
  ThrowError("no mode named '" + mode + "'");
}

void LeafSystem::DeclarePeriodicDiscreteUpdate(double period, double offset, DiscreteUpdate update) {
  if (!(period > 0) || !std::isfinite(period))
    ThrowError("periodic update period must be positive and finite, got " + std::to_string(period));
  if (!(offset >= 0)) ThrowError("periodic update offset must be non-negative, got " + std::to_string(offset));
  periodic_events_.push_back({period, offset, std::move(update), nullptr});
}

void LeafSystem::DeclarePeriodicPublish(double period, double offset, Publish publish) {
  if (!(period > 0) || !std::isfinite(period))
    ThrowError("periodic publish period must be positive and finite, got " + std::to_string(period));
  if (!(offset >= 0)) ThrowError("periodic publish offset must be non-negative, got " + std::to_string(offset));
  periodic_events_.push_back({period, offset, nullptr, std::move(publish)});
}

void LeafSystem::DeclareEventPublish(Publish publish) { event_publishes_.push_back(std::move(publish)); }

void LeafSystem::DeclareEventUpdate(std::string update_name, EventTrigger trigger, EventUpdate update) {
  if (!update) ThrowError("event update '" + update_name + "' has no update function");
  for (const auto& g : trigger.guards)
    if (g.system.empty() || g.guard.empty())
      ThrowError("event update '" + update_name + "' names an empty system or guard ('" + g.system + "', '" + g.guard +
                 "')");
  event_updates_.push_back({std::move(update_name), std::move(trigger), std::move(update)});
}

int LeafSystem::DeclareGuard(std::string guard_name, int mode, int size, WitnessCalc witness,
                             CrossingDirection direction, ResetMap reset) {
  if (size <= 0) ThrowError("guard '" + guard_name + "' needs a positive witness size, got " + std::to_string(size));
  if (mode != kAllModes && (mode < 0 || mode >= num_modes()))
    ThrowError("guard '" + guard_name + "' names mode " + std::to_string(mode) +
               ", which is not declared (declare modes first)");
  if (!witness) ThrowError("guard '" + guard_name + "' has no witness function");
  guards_.push_back({std::move(guard_name), mode, size, std::move(witness), direction, std::move(reset)});
  return static_cast<int>(guards_.size()) - 1;
}

int LeafSystem::DeclareGuard(std::string guard_name, int mode, ScalarWitnessCalc witness, CrossingDirection direction,
                             ResetMap reset) {
  if (!witness) ThrowError("guard '" + guard_name + "' has no witness function");
  return DeclareGuard(
      std::move(guard_name), mode, 1,
      [w = std::move(witness)](const LeafContext& c, Eigen::Ref<Eigen::VectorXd> out) { out[0] = w(c); }, direction,
      std::move(reset));
}

std::unique_ptr<LeafContext> LeafSystem::CreateDefaultLeafContext() const {
  std::unique_ptr<LeafContext> c(new LeafContext());
  c->system_ = this;
  c->state_.continuous = default_continuous_state_;
  c->state_.discrete = default_discrete_state_;
  c->state_.mode = default_mode_;
  c->parameters_ = default_parameters_;
  c->inputs_.resize(num_input_ports());
  c->fixed_inputs_.resize(num_input_ports());
  c->fixed_abstract_inputs_.resize(num_input_ports());
  c->outputs_.resize(num_output_ports());
  for (int i = 0; i < num_output_ports(); ++i) {
    if (output_ports_[i].is_vector())
      c->outputs_[i].value = Eigen::VectorXd::Zero(output_ports_[i].size);
    else
      c->outputs_[i].abstract = output_decls_[i].default_value;
  }
  c->scratch_ = AllocateScratch();
  return c;
}

std::unique_ptr<Context> LeafSystem::CreateDefaultContext() const { return CreateDefaultLeafContext(); }

static const LeafContext& AsLeafContext(const Context& context, const LeafSystem& sys) {
  if (context.is_diagram_context())
    throw std::invalid_argument("system '" + sys.name() +
                                "' was given a diagram context; use Diagram::GetSubsystemContext()");
  const auto& leaf = static_cast<const LeafContext&>(context);
  if (&leaf.system() != &sys)
    throw std::invalid_argument("system '" + sys.name() + "' was given the context of system '" + leaf.system().name() +
                                "'");
  return leaf;
}

const Eigen::VectorXd& LeafSystem::EvalOutput(const Context& context, int index) const {
  const LeafContext& c = AsLeafContext(context, *this);
  const PortInfo& port = output_port(index);  // range check with a named error
  if (!port.is_vector())
    ThrowError("output port '" + port.name + "' carries " + port.TypeString() +
               "; read it with EvalTypedOutput<T>, not as a vector");
  auto& cache = c.outputs_[index];
  if (cache.version != c.version()) {
    output_decls_[index].calc(c, &cache.value);
    if (cache.value.size() != output_ports_[index].size)
      ThrowError("output port '" + output_ports_[index].name + "' has size " +
                 std::to_string(output_ports_[index].size) + " but its calculation produced size " +
                 SizeString(cache.value));
    cache.version = c.version();
  }
  return cache.value;
}

const std::any& LeafSystem::EvalAbstractOutput(const Context& context, int index) const {
  const LeafContext& c = AsLeafContext(context, *this);
  const PortInfo& port = output_port(index);
  if (port.is_vector()) ThrowError("output port '" + port.name + "' is a vector port; read it with EvalOutput");
  auto& cache = c.outputs_[index];
  if (cache.version != c.version()) {
    output_decls_[index].abstract_calc(c, &cache.abstract);
    cache.version = c.version();
  }
  return cache.abstract;
}

void LeafSystem::FixInputPort(Context& context, int index, const Eigen::VectorXd& value) const {
  const_cast<LeafContext&>(AsLeafContext(context, *this)).FixInputPort(index, value);
}

void LeafSystem::FixAbstractInputPort(Context& context, int index, std::any value) const {
  const_cast<LeafContext&>(AsLeafContext(context, *this)).FixAbstractInputPort(index, std::move(value));
}

const std::any& LeafSystem::EvalAbstractInput(const LeafContext& context, int index) const {
  const PortInfo& port = input_port(index);
  if (port.is_vector()) ThrowError("input port '" + port.name + "' is a vector port; read it with EvalInput");
  const InputSource& src = context.inputs_[index];
  switch (src.kind) {
    case InputSource::Kind::kFixed: return *src.fixed_abstract;
    case InputSource::Kind::kUpstream:
      return src.upstream_system->EvalAbstractOutput(*src.upstream_context, src.upstream_port);
    case InputSource::Kind::kUnconnected: break;
  }
  throw std::runtime_error("input port '" + port.name + "' of system '" + name() + "' is not connected");
}

const Eigen::VectorXd& LeafSystem::EvalInput(const LeafContext& context, int index) const {
  const InputSource& src = context.inputs_[index];
  if (src.kind != InputSource::Kind::kUnconnected && !input_ports_[index].is_vector())
    ThrowError("input port '" + input_ports_[index].name + "' carries " + input_ports_[index].TypeString() +
               "; read it with EvalTypedInput<T>, not as a vector");
  switch (src.kind) {
    case InputSource::Kind::kFixed: return *src.fixed_value;
    case InputSource::Kind::kUpstream: return src.upstream_system->EvalOutput(*src.upstream_context, src.upstream_port);
    case InputSource::Kind::kUnconnected: break;
  }
  throw std::runtime_error("input port '" + input_port(index).name + "' of system '" + name() + "' is not connected");
}

void LeafSystem::CalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const {
  if (num_continuous_states_ == 0) {
    xdot->resize(0);
    return;
  }
  xdot->resize(num_continuous_states_);  // no allocation when it already has the size (the simulator's buffers)
  DoCalcTimeDerivatives(context, xdot);
}

void LeafSystem::DoCalcTimeDerivatives(const LeafContext&, Eigen::VectorXd*) const {
  ThrowError("declares " + std::to_string(num_continuous_states_) +
             " continuous states but does not override DoCalcTimeDerivatives");
}

}  // namespace rome
