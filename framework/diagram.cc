#include "framework/diagram.h"

#include <algorithm>
#include <functional>
#include <sstream>

namespace rome {

// ---------------------------------------------------------------------------------------------------------
// Diagram

std::unique_ptr<DiagramContext> Diagram::CreateDefaultDiagramContext() const {
  std::unique_ptr<DiagramContext> dc(new DiagramContext());
  dc->fixed_inputs_.resize(exported_inputs_.size());
  dc->input_fixed_.assign(exported_inputs_.size(), false);
  for (const Leaf& leaf : leaves_) {
    std::unique_ptr<LeafContext> lc = leaf.system->CreateDefaultLeafContext();
    lc->time_ = dc->time_;  // one clock and one cache version for the whole diagram
    lc->version_ = dc->version_;
    dc->leaves_.push_back(std::move(lc));
  }
  for (int i = 0; i < num_leaves(); ++i) {
    LeafContext& lc = *dc->leaves_[i];
    for (size_t p = 0; p < wiring_[i].size(); ++p) {
      const LeafInputWiring& w = wiring_[i][p];
      InputSource& src = lc.inputs_[p];
      switch (w.kind) {
        case LeafInputWiring::Kind::kUpstream:
          src.kind = InputSource::Kind::kUpstream;
          src.upstream_system = leaves_[w.upstream.leaf].system;
          src.upstream_context = dc->leaves_[w.upstream.leaf].get();
          src.upstream_port = w.upstream.port;
          break;
        case LeafInputWiring::Kind::kFixed:
          src.kind = InputSource::Kind::kFixed;
          if (w.fixed_abstract.has_value()) {
            lc.fixed_abstract_inputs_[p] = w.fixed_abstract;
            src.fixed_abstract = &lc.fixed_abstract_inputs_[p];
          } else {
            lc.fixed_inputs_[p] = w.fixed_value;
            src.fixed_value = &lc.fixed_inputs_[p];
          }
          break;
        case LeafInputWiring::Kind::kExported:
          src.kind = InputSource::Kind::kUnconnected;  // until the diagram input is fixed
          break;
      }
    }
  }
  return dc;
}

std::unique_ptr<Context> Diagram::CreateDefaultContext() const { return CreateDefaultDiagramContext(); }

std::unique_ptr<Context> DiagramContext::Clone() const {
  std::unique_ptr<DiagramContext> dc(new DiagramContext());
  *dc->time_ = *time_;
  *dc->version_ = *version_;
  dc->fixed_inputs_ = fixed_inputs_;
  dc->input_fixed_ = input_fixed_;
  for (const auto& leaf : leaves_) {
    std::unique_ptr<LeafContext> lc = leaf->CloneLeaf();
    lc->time_ = dc->time_;
    lc->version_ = dc->version_;
    dc->leaves_.push_back(std::move(lc));
  }
  // Re-wire upstream sources and the diagram's fixed inputs to the copies.
  for (size_t i = 0; i < leaves_.size(); ++i)
    for (size_t p = 0; p < leaves_[i]->inputs_.size(); ++p) {
      const InputSource& old_src = leaves_[i]->inputs_[p];
      InputSource& src = dc->leaves_[i]->inputs_[p];
      if (old_src.kind == InputSource::Kind::kUpstream) {
        for (size_t k = 0; k < leaves_.size(); ++k)
          if (leaves_[k].get() == old_src.upstream_context) src.upstream_context = dc->leaves_[k].get();
      }
      for (size_t k = 0; k < fixed_inputs_.size(); ++k)
        if (old_src.fixed_value == &fixed_inputs_[k]) src.fixed_value = &dc->fixed_inputs_[k];
    }
  return dc;
}

const DiagramContext& Diagram::AsDiagramContext(const Context& context) const {
  if (!context.is_diagram_context()) throw std::invalid_argument("diagram '" + name() + "' was given a leaf context");
  const auto& dc = static_cast<const DiagramContext&>(context);
  if (dc.num_leaves() != num_leaves() || (num_leaves() > 0 && &dc.leaf(0).system() != leaves_[0].system))
    throw std::invalid_argument("diagram '" + name() + "' was given the context of another diagram");
  return dc;
}

const Eigen::VectorXd& Diagram::EvalOutput(const Context& context, int index) const {
  const DiagramContext& dc = AsDiagramContext(context);
  output_port(index);
  const OutputRef& ref = exported_outputs_[index];
  return leaves_[ref.leaf].system->EvalOutput(dc.leaf(ref.leaf), ref.port);
}

const std::any& Diagram::EvalAbstractOutput(const Context& context, int index) const {
  const DiagramContext& dc = AsDiagramContext(context);
  output_port(index);
  const OutputRef& ref = exported_outputs_[index];
  return leaves_[ref.leaf].system->EvalAbstractOutput(dc.leaf(ref.leaf), ref.port);
}

void Diagram::FixInputPort(Context& context, int index, const Eigen::VectorXd& value) const {
  auto& dc = const_cast<DiagramContext&>(AsDiagramContext(context));
  const PortInfo& port = input_port(index);
  if (!port.is_vector())
    throw std::invalid_argument("input port '" + port.name + "' of diagram '" + name() + "' carries " +
                                port.TypeString() + "; it cannot be fixed to a vector");
  if (value.size() != port.size)
    throw std::invalid_argument("input port '" + port.name + "' of diagram '" + name() + "' has size " +
                                std::to_string(port.size) + " but the fixed value has size " +
                                std::to_string(value.size()));
  dc.fixed_inputs_[index] = value;
  dc.input_fixed_[index] = true;
  for (const InputRef& in : exported_inputs_[index]) {
    InputSource& src = dc.leaf(in.leaf).inputs_[in.port];
    src.kind = InputSource::Kind::kFixed;
    src.fixed_value = &dc.fixed_inputs_[index];
  }
  dc.InvalidateCache();
}

const Eigen::VectorXd& Diagram::EvalInput(const Context& context, int index) const {
  const DiagramContext& dc = AsDiagramContext(context);
  const PortInfo& port = input_port(index);
  if (!port.is_vector())
    throw std::invalid_argument("input port '" + port.name + "' of diagram '" + name() + "' carries " +
                                port.TypeString() + ", not a vector");
  if (!dc.input_fixed_[index])
    throw std::runtime_error("input port '" + port.name + "' of diagram '" + name() + "' has no fixed value");
  return dc.fixed_inputs_[index];
}

int Diagram::GetLeafIndex(const LeafSystem& system) const {
  for (int i = 0; i < num_leaves(); ++i)
    if (leaves_[i].system == &system) return i;
  throw std::invalid_argument("system '" + system.name() + "' is not part of diagram '" + name() + "'");
}

int Diagram::GetLeafIndex(const std::string& path) const {
  for (int i = 0; i < num_leaves(); ++i)
    if (leaves_[i].path == path) return i;
  throw std::invalid_argument("diagram '" + name() + "' has no system named '" + path + "'");
}

LeafContext& Diagram::GetMutableSubsystemContext(const LeafSystem& system, Context& context) const {
  auto& dc = const_cast<DiagramContext&>(AsDiagramContext(context));
  return dc.leaf(GetLeafIndex(system));
}

const Eigen::VectorXd& Diagram::EvalSubsystemOutput(const System& subsystem, const std::string& port,
                                                    const Context& context) const {
  const DiagramContext& dc = AsDiagramContext(context);
  const int index = subsystem.GetOutputPortIndex(port);
  if (!subsystem.is_diagram()) {
    const auto& leaf = static_cast<const LeafSystem&>(subsystem);
    return leaf.EvalOutput(dc.leaf(GetLeafIndex(leaf)), index);
  }
  // A nested diagram's exported outputs point at its own (already flattened) leaves, which are leaves of this diagram.
  const auto& child = static_cast<const Diagram&>(subsystem);
  const OutputRef& ref = child.exported_outputs_[index];
  const LeafSystem& leaf = child.leaf(ref.leaf);
  return leaf.EvalOutput(dc.leaf(GetLeafIndex(leaf)), ref.port);
}

const LeafContext& Diagram::GetSubsystemContext(const LeafSystem& system, const Context& context) const {
  return AsDiagramContext(context).leaf(GetLeafIndex(system));
}

void Diagram::EvalAllOutputs(const Context& context) const {
  const DiagramContext& dc = AsDiagramContext(context);
  for (const OutputRef& o : evaluation_order_) leaves_[o.leaf].system->EvalOutput(dc.leaf(o.leaf), o.port);
}

// ---------------------------------------------------------------------------------------------------------
// DiagramBuilder

void DiagramBuilder::AddSystemImpl(std::unique_ptr<System> system, const std::string& name) {
  if (!system) throw std::invalid_argument("DiagramBuilder::AddSystem: null system");
  std::string n = name.empty() ? system->name() : name;
  if (n.find('/') != std::string::npos)
    throw std::invalid_argument("DiagramBuilder: system name '" + n + "' must not contain '/'");
  if (HasSystem(n))
    throw std::invalid_argument("DiagramBuilder: a system named '" + n + "' was already added; names must be unique");
  for (const auto& s : systems_)
    if (s.get() == system.get()) throw std::invalid_argument("DiagramBuilder: system '" + n + "' was added twice");
  system->set_name(n);
  names_.push_back(n);
  systems_.push_back(std::move(system));
}

bool DiagramBuilder::HasSystem(const std::string& name) const {
  return std::find(names_.begin(), names_.end(), name) != names_.end();
}

int DiagramBuilder::SystemIndex(const std::string& name) const {
  for (size_t i = 0; i < names_.size(); ++i)
    if (names_[i] == name) return static_cast<int>(i);
  throw std::invalid_argument("DiagramBuilder: no system named '" + name + "'");
}

int DiagramBuilder::SystemIndex(const System& system) const {
  for (size_t i = 0; i < systems_.size(); ++i)
    if (systems_[i].get() == &system) return static_cast<int>(i);
  throw std::invalid_argument("DiagramBuilder: system '" + system.name() + "' was not added to this builder");
}

System& DiagramBuilder::GetMutableSystem(const std::string& name) const { return *systems_[SystemIndex(name)]; }

void DiagramBuilder::Connect(const std::string& from_system, const std::string& output_port,
                             const std::string& to_system, const std::string& input_port) {
  const int from = SystemIndex(from_system), to = SystemIndex(to_system);
  const int out = systems_[from]->GetOutputPortIndex(output_port);
  const int in = systems_[to]->GetInputPortIndex(input_port);
  connections_.push_back({{from, out}, {to, in}});
}

void DiagramBuilder::Connect(const System& from_system, const std::string& output_port, const System& to_system,
                             const std::string& input_port) {
  Connect(names_[SystemIndex(from_system)], output_port, names_[SystemIndex(to_system)], input_port);
}

void DiagramBuilder::Connect(const System& from, const System& to) {
  if (from.num_output_ports() != 1)
    throw std::invalid_argument("DiagramBuilder::Connect: system '" + from.name() + "' has " +
                                std::to_string(from.num_output_ports()) + " output ports; name the port");
  if (to.num_input_ports() != 1)
    throw std::invalid_argument("DiagramBuilder::Connect: system '" + to.name() + "' has " +
                                std::to_string(to.num_input_ports()) + " input ports; name the port");
  Connect(from, from.output_port(0).name, to, to.input_port(0).name);
}

void DiagramBuilder::FixInput(const std::string& system, const std::string& input_port, const Eigen::VectorXd& value) {
  const int s = SystemIndex(system);
  fixed_.push_back({{s, systems_[s]->GetInputPortIndex(input_port)}, value});
}

void DiagramBuilder::FixAbstractInput(const std::string& system, const std::string& input_port, std::any value) {
  const int s = SystemIndex(system);
  fixed_abstract_.push_back({{s, systems_[s]->GetInputPortIndex(input_port)}, std::move(value)});
}

void DiagramBuilder::ExportInput(const std::string& system, const std::string& input_port, const std::string& name) {
  const int s = SystemIndex(system);
  const PortRef ref{s, systems_[s]->GetInputPortIndex(input_port)};
  const std::string n = name.empty() ? input_port : name;
  for (auto& [ename, refs] : exported_inputs_)
    if (ename == n) {
      refs.push_back(ref);
      return;
    }
  exported_inputs_.push_back({n, {ref}});
}

void DiagramBuilder::ExportOutput(const std::string& system, const std::string& output_port, const std::string& name) {
  const int s = SystemIndex(system);
  const std::string n = name.empty() ? output_port : name;
  for (const auto& e : exported_outputs_)
    if (e.first == n) throw std::invalid_argument("DiagramBuilder: output '" + n + "' is exported twice");
  exported_outputs_.push_back({n, {s, systems_[s]->GetOutputPortIndex(output_port)}});
}

std::unique_ptr<Diagram> DiagramBuilder::Build(const std::string& name) {
  std::unique_ptr<Diagram> d(new Diagram(name));
  std::vector<int> offset;
  std::vector<PendingInput> pending;
  ExpandLeaves(*d, &offset, &pending);
  WireInputs(*d, name, offset, pending);
  for (const auto& [ename, ref] : exported_outputs_) {
    PortInfo exported = systems_[ref.system]->output_port(ref.port);
    exported.name = ename;
    d->output_ports_.push_back(exported);
    d->exported_outputs_.push_back(LeafOutput(offset, ref));
  }
  SortEvaluationOrder(*d, name);
  d->owned_ = std::move(systems_);
  systems_.clear();
  names_.clear();
  connections_.clear();
  fixed_.clear();
  fixed_abstract_.clear();
  exported_inputs_.clear();
  exported_outputs_.clear();
  return d;
}

std::string DiagramBuilder::PortName(int s, int p, bool input) const {
  const System& sys = *systems_[s];
  return std::string(input ? "input" : "output") + " port '" + (input ? sys.input_port(p) : sys.output_port(p)).name +
         "' of system '" + names_[s] + "'";
}

Diagram::OutputRef DiagramBuilder::LeafOutput(const std::vector<int>& offset, PortRef o) const {
  if (!systems_[o.system]->is_diagram()) return {offset[o.system], o.port};
  const auto* child = static_cast<const Diagram*>(systems_[o.system].get());
  Diagram::OutputRef r = child->exported_outputs_[o.port];
  r.leaf += offset[o.system];
  return r;
}

void DiagramBuilder::ExpandLeaves(Diagram& diagram, std::vector<int>* offset,
                                  std::vector<PendingInput>* pending) const {
  using Wiring = Diagram::LeafInputWiring;
  Diagram* d = &diagram;
  const int nsys = static_cast<int>(systems_.size());
  offset->assign(nsys, 0);
  for (int s = 0; s < nsys; ++s) {
    (*offset)[s] = d->num_leaves();
    if (!systems_[s]->is_diagram()) {
      const auto* leaf = static_cast<const LeafSystem*>(systems_[s].get());
      d->leaves_.push_back({leaf, names_[s]});
      d->wiring_.emplace_back(leaf->num_input_ports(), Wiring{Wiring::Kind::kExported, {-1, -1}, {}, {}, -1});
      for (int p = 0; p < leaf->num_input_ports(); ++p) pending->push_back({(*offset)[s], p, s, p});
    } else {
      const auto* child = static_cast<const Diagram*>(systems_[s].get());
      for (int i = 0; i < child->num_leaves(); ++i) {
        d->leaves_.push_back({child->leaves_[i].system, names_[s] + "/" + child->leaves_[i].path});
        std::vector<Wiring> w = child->wiring_[i];
        for (size_t p = 0; p < w.size(); ++p) {
          if (w[p].kind == Wiring::Kind::kUpstream) w[p].upstream.leaf += (*offset)[s];
          if (w[p].kind == Wiring::Kind::kExported)
            pending->push_back({(*offset)[s] + i, static_cast<int>(p), s, w[p].exported_index});
        }
        d->wiring_.push_back(std::move(w));
      }
    }
  }
}

void DiagramBuilder::WireInputs(Diagram& diagram, const std::string& name, const std::vector<int>& offset,
                                const std::vector<PendingInput>& pending) const {
  using Wiring = Diagram::LeafInputWiring;
  Diagram* d = &diagram;
  const int nsys = static_cast<int>(systems_.size());
  auto port_name = [&](int s, int p, bool input) { return PortName(s, p, input); };
  auto leaf_output = [&](PortRef o) { return LeafOutput(offset, o); };
  // 2. One source per block input: a connection, a fixed value, or an export.
  std::map<std::pair<int, int>, int> source_count;
  std::map<std::pair<int, int>, Wiring> source;
  auto add_source = [&](PortRef in, Wiring w, const std::string& what) {
    auto key = std::make_pair(in.system, in.port);
    if (source_count[key]++ > 0)
      throw std::invalid_argument("DiagramBuilder::Build('" + name + "'): " + port_name(in.system, in.port, true) +
                                  " has a second source (" + what + "); an input takes exactly one connection");
    source[key] = std::move(w);
  };
  for (const Connection& c : connections_) {
    const PortInfo& out_port = systems_[c.from.system]->output_port(c.from.port);
    const PortInfo& in_port = systems_[c.to.system]->input_port(c.to.port);
    if (!out_port.is_vector() || !in_port.is_vector()) {
      if (!out_port.SameTypeAs(in_port))
        throw std::invalid_argument("DiagramBuilder::Build('" + name +
                                    "'): type mismatch: " + port_name(c.from.system, c.from.port, false) + " carries " +
                                    out_port.TypeString() + " but " + port_name(c.to.system, c.to.port, true) +
                                    " takes " + in_port.TypeString());
    }
    const int out_size = out_port.size;
    const int in_size = in_port.size;
    if (out_size != in_size)
      throw std::invalid_argument("DiagramBuilder::Build('" + name +
                                  "'): size mismatch: " + port_name(c.from.system, c.from.port, false) + " has size " +
                                  std::to_string(out_size) + " but " + port_name(c.to.system, c.to.port, true) +
                                  " has size " + std::to_string(in_size));
    add_source(c.to, Wiring{Wiring::Kind::kUpstream, leaf_output(c.from), {}, {}, -1},
               "connection from " + port_name(c.from.system, c.from.port, false));
  }
  for (const auto& [in, value] : fixed_) {
    const PortInfo& in_port = systems_[in.system]->input_port(in.port);
    if (!in_port.is_vector())
      throw std::invalid_argument("DiagramBuilder::Build('" + name +
                                  "'): type mismatch: " + port_name(in.system, in.port, true) + " takes " +
                                  in_port.TypeString() + " but its fixed value is a vector (use FixTypedInput)");
    const int in_size = in_port.size;
    if (value.size() != in_size)
      throw std::invalid_argument(
          "DiagramBuilder::Build('" + name + "'): size mismatch: " + port_name(in.system, in.port, true) +
          " has size " + std::to_string(in_size) + " but its fixed value has size " + std::to_string(value.size()));
    add_source(in, Wiring{Wiring::Kind::kFixed, {-1, -1}, value, {}, -1}, "a fixed value");
  }
  for (const auto& [in, value] : fixed_abstract_) {
    const PortInfo& in_port = systems_[in.system]->input_port(in.port);
    if (in_port.is_vector() || *in_port.value_type != value.type())
      throw std::invalid_argument("DiagramBuilder::Build('" + name +
                                  "'): type mismatch: " + port_name(in.system, in.port, true) + " takes " +
                                  in_port.TypeString() + " but its fixed value is " + DemangledTypeName(value.type()));
    add_source(in, Wiring{Wiring::Kind::kFixed, {-1, -1}, {}, value, -1}, "a fixed value");
  }
  for (size_t k = 0; k < exported_inputs_.size(); ++k) {
    const auto& [ename, refs] = exported_inputs_[k];
    const PortInfo& first = systems_[refs[0].system]->input_port(refs[0].port);
    const int size = first.size;
    for (const PortRef& in : refs) {
      const int in_size = systems_[in.system]->input_port(in.port).size;
      if (!systems_[in.system]->input_port(in.port).SameTypeAs(first))
        throw std::invalid_argument("DiagramBuilder::Build('" + name + "'): type mismatch: exported input '" + ename +
                                    "' fans out to " + port_name(in.system, in.port, true) + ", which takes " +
                                    systems_[in.system]->input_port(in.port).TypeString() +
                                    ", and to a port that takes " + first.TypeString());
      if (in_size != size)
        throw std::invalid_argument("DiagramBuilder::Build('" + name + "'): size mismatch: exported input '" + ename +
                                    "' fans out to " + port_name(in.system, in.port, true) + " of size " +
                                    std::to_string(in_size) + " and to a port of size " + std::to_string(size));
      add_source(in, Wiring{Wiring::Kind::kExported, {-1, -1}, {}, {}, static_cast<int>(k)},
                 "the diagram input '" + ename + "'");
    }
    PortInfo exported = first;
    exported.name = ename;
    d->input_ports_.push_back(exported);
    d->exported_inputs_.emplace_back();
  }
  for (const PendingInput& p : pending) {
    auto key = std::make_pair(p.block, p.block_input);
    auto it = source.find(key);
    if (it == source.end())
      throw std::invalid_argument("DiagramBuilder::Build('" + name + "'): " + port_name(p.block, p.block_input, true) +
                                  " is not connected (connect it, fix it with FixInput, or export it)");
    d->wiring_[p.leaf][p.port] = it->second;
    if (it->second.kind == Wiring::Kind::kExported)
      d->exported_inputs_[it->second.exported_index].push_back({p.leaf, p.port});
  }
  // Block inputs of nested diagrams whose exported input reaches no leaf still need a source check.
  for (int s = 0; s < nsys; ++s)
    for (int p = 0; p < systems_[s]->num_input_ports(); ++p)
      if (!source.count({s, p}))
        throw std::invalid_argument("DiagramBuilder::Build('" + name + "'): " + port_name(s, p, true) +
                                    " is not connected (connect it, fix it with FixInput, or export it)");
}

// Algebraic loops and evaluation order over leaf output ports (depth-first topological sort).
void DiagramBuilder::SortEvaluationOrder(Diagram& diagram, const std::string& name) {
  using Wiring = Diagram::LeafInputWiring;
  Diagram* d = &diagram;
  const int nleaves = d->num_leaves();
  std::vector<std::vector<int>> state(nleaves);  // 0 unvisited, 1 on stack, 2 done
  for (int i = 0; i < nleaves; ++i) state[i].assign(d->leaves_[i].system->num_output_ports(), 0);
  std::vector<Diagram::OutputRef> stack;
  auto describe = [&](Diagram::OutputRef o) {
    return "output '" + d->leaves_[o.leaf].system->output_port(o.port).name + "' of '" + d->leaves_[o.leaf].path + "'";
  };
  std::function<void(Diagram::OutputRef)> visit = [&](Diagram::OutputRef o) {
    int& st = state[o.leaf][o.port];
    if (st == 2) return;
    if (st == 1) {
      std::string loop;
      auto it = std::find_if(stack.begin(), stack.end(),
                             [&](const Diagram::OutputRef& r) { return r.leaf == o.leaf && r.port == o.port; });
      for (; it != stack.end(); ++it) loop += describe(*it) + " -> ";
      loop += describe(o);
      throw std::invalid_argument("DiagramBuilder::Build('" + name +
                                  "'): algebraic loop among direct-feedthrough ports: " + loop);
    }
    st = 1;
    stack.push_back(o);
    const LeafSystem& sys = *d->leaves_[o.leaf].system;
    for (int in = 0; in < sys.num_input_ports(); ++in) {
      const Wiring& w = d->wiring_[o.leaf][in];
      if (w.kind == Wiring::Kind::kUpstream && sys.HasDirectFeedthrough(in, o.port)) visit(w.upstream);
    }
    stack.pop_back();
    st = 2;
    d->evaluation_order_.push_back(o);
  };
  for (int i = 0; i < nleaves; ++i)
    for (int p = 0; p < d->leaves_[i].system->num_output_ports(); ++p) visit({i, p});
}

}  // namespace rome
