#include "systems/plants/contact_plant.h"

#include <stdexcept>

namespace rome {

ContactModeGraph ContactModeGraph::AlternatingSingleSupport(const std::string& left, const std::string& right,
                                                            bool start_on_left) {
  ContactModeGraph g;
  const std::string ls = left + "_stance", rs = right + "_stance", fl = "flight";
  g.modes = {{ls, {left}}, {rs, {right}}, {fl, {}}};  // indices 0, 1, 2: other code relies on them
  g.transitions = {{ls, rs, Kind::kTouchdown, right}, {rs, ls, Kind::kTouchdown, left},
                   {ls, fl, Kind::kLiftoff, left},    {rs, fl, Kind::kLiftoff, right},
                   {fl, ls, Kind::kTouchdown, left},  {fl, rs, Kind::kTouchdown, right}};
  g.initial_mode = start_on_left ? ls : rs;
  return g;
}

ContactModeGraph ContactModeGraph::WithDoubleSupport(const std::string& left, const std::string& right,
                                                     const std::string& initial_mode) {
  ContactModeGraph g;
  const std::string ls = left + "_stance", rs = right + "_stance", ds = "double_support";
  g.modes = {{ls, {left}}, {ds, {left, right}}, {rs, {right}}};
  g.transitions = {{ls, ds, Kind::kTouchdown, right},
                   {rs, ds, Kind::kTouchdown, left},
                   {ds, rs, Kind::kLiftoff, left},
                   {ds, ls, Kind::kLiftoff, right}};
  g.initial_mode = initial_mode;
  return g;
}

ContactModeGraph ContactModeGraph::Hopping(const std::string& left, const std::string& right) {
  ContactModeGraph g;
  g.modes = {{"stance", {left, right}}, {"flight", {}}};
  g.transitions = {{"stance", "flight", Kind::kLiftoff, left},
                   {"stance", "flight", Kind::kLiftoff, right},
                   {"flight", "stance", Kind::kTouchdown, left},
                   {"flight", "stance", Kind::kTouchdown, right}};
  g.initial_mode = "stance";
  return g;
}

ContactModeGraph ContactModeGraph::JumpFlightLanding(const std::string& left, const std::string& right) {
  ContactModeGraph g;
  g.modes = {{"jump", {left, right}}, {"flight", {}}, {"landing", {left, right}}};  // indices 0, 1, 2
  g.transitions = {{"jump", "flight", Kind::kLiftoff, left},      {"jump", "flight", Kind::kLiftoff, right},
                   {"flight", "landing", Kind::kTouchdown, left}, {"flight", "landing", Kind::kTouchdown, right},
                   {"landing", "flight", Kind::kLiftoff, left},   {"landing", "flight", Kind::kLiftoff, right}};
  g.initial_mode = "jump";
  return g;
}

int ContactModeGraph::ModeIndex(const std::string& name, const std::string& system) const {
  for (size_t i = 0; i < modes.size(); ++i)
    if (modes[i].name == name) return static_cast<int>(i);
  throw std::invalid_argument("system '" + system + "': the contact-mode graph has no mode named '" + name + "'");
}

ContactPlant::ContactPlant(std::string name, std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph,
                           Terrain terrain)
    : LeafSystem(std::move(name)), model_(std::move(model)), graph_(std::move(graph)), terrain_(std::move(terrain)) {
  if (!model_) ThrowError("null MultibodyModel");
  if (graph_.modes.empty()) ThrowError("the contact-mode graph has no modes");
  std::vector<std::string> names;
  for (const auto& m : graph_.modes) {
    ContactSet set = 0;
    for (const auto& c : m.contacts) {
      int idx = -1;
      try {
        idx = model_->ContactIndex(c);
      } catch (const std::exception&) {
        ThrowError("mode '" + m.name + "' names contact '" + c + "', which robot '" + model_->name() +
                   "' does not have");
      }
      set |= ContactBit(idx);
    }
    mode_contacts_.push_back(set);
    names.push_back(m.name);
  }
  const int initial =
      graph_.ModeIndex(graph_.initial_mode.empty() ? graph_.modes[0].name : graph_.initial_mode, this->name());
  DeclareModes(names, initial);

  // Transitions: modes and contact resolved; a touchdown needs the contact inactive, a lift-off active.
  graph_liftoff_.assign(graph_.modes.size(), std::vector<int>(model_->num_contacts(), -1));
  for (const auto& t : graph_.transitions) {
    ResolvedTransition r;
    r.from = graph_.ModeIndex(t.from, this->name());
    r.to = graph_.ModeIndex(t.to, this->name());
    r.kind = t.kind;
    try {
      r.contact = model_->ContactIndex(t.contact);
    } catch (const std::exception&) {
      ThrowError("transition '" + t.from + "' -> '" + t.to + "' names contact '" + t.contact + "', which robot '" +
                 model_->name() + "' does not have");
    }
    const bool active = mode_contacts_[r.from] & ContactBit(r.contact);
    if (t.kind == ContactModeGraph::Kind::kTouchdown && active)
      ThrowError("touchdown of '" + t.contact + "' from mode '" + t.from + "', where that contact is already active");
    if (t.kind == ContactModeGraph::Kind::kLiftoff) {
      if (!active)
        ThrowError("lift-off of '" + t.contact + "' from mode '" + t.from + "', where that contact is not active");
      if (graph_liftoff_[r.from][r.contact] < 0) graph_liftoff_[r.from][r.contact] = r.to;
    }
    transitions_.push_back(r);
  }
}

int ContactPlant::LiftoffMode(int m, int c) const {
  if (graph_liftoff_[m][c] >= 0) return graph_liftoff_[m][c];
  for (size_t k = 0; k < mode_contacts_.size(); ++k)
    if (mode_contacts_[k] == (mode_contacts_[m] & ~ContactBit(c))) return static_cast<int>(k);
  return -1;
}

int ContactPlant::base_height_index() const {
  switch (model_->floating_base()) {
    case FloatingBaseType::kPlanar: return 1;
    case FloatingBaseType::kSpatial: return 2;
    case FloatingBaseType::kFixed: return -1;
  }
  return -1;
}

std::vector<std::string> StateElementNames(const MultibodyModel& model) {
  std::vector<std::string> names;
  if (model.has_quaternion_base())
    for (const char* e : {"x", "y", "z", "qw", "qx", "qy", "qz"}) names.push_back(std::string("q_base_") + e);
  for (int i = model.has_quaternion_base() ? 6 : 0; i < model.nv(); ++i) names.push_back("q_" + model.JointName(i));
  for (const std::string& j : model.joint_names()) names.push_back("v_" + j);
  return names;
}

std::vector<ContactSet> ActiveContactsPerMode(const ContactPlant& plant) {
  std::vector<ContactSet> sets;
  for (int m = 0; m < plant.num_modes(); ++m) sets.push_back(plant.active_contacts(m));
  return sets;
}

}  // namespace rome
