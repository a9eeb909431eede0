#include "systems/plants/hybrid_contact_plant.h"

#include <cmath>
#include <sstream>

#include "systems/multibody/multibody_dynamics.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

// ---------------------------------------------------------------------------------------------------------
// Mode graphs

ContactModeGraph ContactModeGraph::AlternatingSingleSupport(const std::string& left, const std::string& right, bool start_on_left) {
  ContactModeGraph g;
  const std::string ls = left + "_stance", rs = right + "_stance";
  g.modes = {{ls, {left}}, {rs, {right}}};
  g.transitions = {{ls, rs, Kind::kTouchdown, right}, {rs, ls, Kind::kTouchdown, left}};
  g.initial_mode = start_on_left ? ls : rs;
  return g;
}

ContactModeGraph ContactModeGraph::WithDoubleSupport(const std::string& left, const std::string& right, const std::string& initial_mode) {
  ContactModeGraph g;
  const std::string ls = left + "_stance", rs = right + "_stance", ds = "double_support";
  g.modes = {{ls, {left}}, {ds, {left, right}}, {rs, {right}}};
  g.transitions = {{ls, ds, Kind::kTouchdown, right}, {rs, ds, Kind::kTouchdown, left}, {ds, rs, Kind::kLiftoff, left}, {ds, ls, Kind::kLiftoff, right}};
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

// ---------------------------------------------------------------------------------------------------------
// Plant

struct HybridContactPlant::Scratch {
  explicit Scratch(const MultibodyModel& model)
      : ws(model),
        u(Eigen::VectorXd::Zero(model.nu())),
        qdd(Eigen::VectorXd::Zero(model.nv())),
        F(Eigen::VectorXd::Zero(std::max(model.max_constraint_rows(), 1))),
        impulse(Eigen::VectorXd::Zero(std::max(model.max_constraint_rows(), 1))),
        v_plus(Eigen::VectorXd::Zero(model.nv())) {}
  MultibodyWorkspace ws;
  Eigen::VectorXd u, qdd, F, impulse, v_plus;
  ContactSet active = 0;
  std::uint64_t version = 0;
};

namespace {
int FindMode(const ContactModeGraph& g, const std::string& name, const std::string& plant) {
  for (size_t i = 0; i < g.modes.size(); ++i)
    if (g.modes[i].name == name) return static_cast<int>(i);
  throw std::invalid_argument("system '" + plant + "': the contact-mode graph has no mode named '" + name + "'");
}
}  // namespace

int HybridContactPlant::base_height_index() const {
  switch (model_->floating_base()) {
    case FloatingBaseType::kPlanar: return 1;
    case FloatingBaseType::kSpatial: return 2;
    case FloatingBaseType::kFixed: return -1;
  }
  return -1;
}

HybridContactPlant::HybridContactPlant(std::string name, std::shared_ptr<const MultibodyModel> model, ContactModeGraph graph, Terrain terrain,
                                       HybridContactPlantParams params)
    : LeafSystem(std::move(name)), model_(std::move(model)), graph_(std::move(graph)), terrain_(std::move(terrain)), params_(params) {
  if (!model_) ThrowError("null MultibodyModel");
  if (graph_.modes.empty()) ThrowError("the contact-mode graph has no modes");
  const int nv = model_->nv(), nu = model_->nu(), nc = model_->num_contacts();
  std::vector<std::string> names;
  for (const auto& m : graph_.modes) {
    ContactSet set = 0;
    for (const auto& c : m.contacts) {
      int idx = -1;
      try {
        idx = model_->ContactIndex(c);
      } catch (const std::exception&) {
        ThrowError("mode '" + m.name + "' names contact '" + c + "', which robot '" + model_->name() + "' does not have");
      }
      set |= ContactBit(idx);
    }
    mode_contacts_.push_back(set);
    names.push_back(m.name);
  }
  const int initial = FindMode(graph_, graph_.initial_mode.empty() ? graph_.modes[0].name : graph_.initial_mode, this->name());
  DeclareModes(names, initial);

  Eigen::VectorXd x0(2 * nv);
  x0 << model_->q_nominal(), Eigen::VectorXd::Zero(nv);
  DeclareContinuousState(x0);
  DeclareDiscreteState(Eigen::VectorXd::Zero(1));  // time the current mode began
  DeclareInputPort("u", nu);

  DeclareOutputPort("q", nv, [nv](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state().head(nv); }, Feedthrough::None());
  DeclareOutputPort("v", nv, [nv](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state().tail(nv); }, Feedthrough::None());
  std::vector<std::string> state_names, force_names;
  for (const std::string& j : model_->joint_names()) state_names.push_back("q_" + j);
  for (const std::string& j : model_->joint_names()) state_names.push_back("v_" + j);
  for (const ContactInfo& contact : model_->contacts())
    for (const char* axis : {"fx", "fy", "fz"}) force_names.push_back(contact.name + "_" + axis);
  DeclareOutputPort("state", state_names, [](const LeafContext& c, Eigen::VectorXd* y) { *y = c.continuous_state(); }, Feedthrough::None());
  DeclareTypedOutputPort<int>("mode", [](const LeafContext& c, int* y) { *y = c.mode(); }, Feedthrough::None());
  DeclareOutputPort("contact_forces", force_names, [this, nc, nv](const LeafContext& c, Eigen::VectorXd* y) {
    const Scratch& s = EvalDynamics(c);
    y->setZero();
    for (int i = 0; i < nc; ++i)
      if (s.active & ContactBit(i)) {
        auto& ws = const_cast<Scratch&>(s).ws;
        y->segment<3>(3 * i) = ExtractContactWrench(*model_, ws, c.continuous_state().head(nv), s.active, s.F, i).force;
      }
  });
  DeclareOutputPort("contact_violation", nc, [this, nc, nv](const LeafContext& c, Eigen::VectorXd* y) {
    const Scratch& s = EvalDynamics(c);
    y->setZero();
    auto& ws = const_cast<Scratch&>(s).ws;
    const auto q = c.continuous_state().head(nv);
    for (int i = 0; i < nc; ++i)
      if (s.active & ContactBit(i)) {
        const ContactWrench w = ExtractContactWrench(*model_, ws, q, s.active, s.F, i);
        const ContactForceCheck check = CheckContactForce(*model_, ws, q, i, w);
        (*y)[i] = (check.unilateral_ok ? 0 : 1) + (check.friction_ok ? 0 : 2);
      }
  });
  DeclareOutputPort("com", {"x", "y", "z", "vx", "vy", "vz"}, [this, nv](const LeafContext& c, Eigen::VectorXd* y) {
    auto& ws = c.scratch<Scratch>().ws;
    const auto q = c.continuous_state().head(nv);
    const auto v = c.continuous_state().tail(nv);
    y->head<3>() = CalcComPosition(*model_, ws, q);
    y->tail<3>() = CalcComVelocity(*model_, ws, q, v);
  }, Feedthrough::None());

  // Guards from the mode graph.
  for (const auto& t : graph_.transitions) {
    const int from = FindMode(graph_, t.from, this->name());
    const int to = FindMode(graph_, t.to, this->name());
    int contact = -1;
    try {
      contact = model_->ContactIndex(t.contact);
    } catch (const std::exception&) {
      ThrowError("transition '" + t.from + "' -> '" + t.to + "' names contact '" + t.contact + "', which robot '" + model_->name() + "' does not have");
    }
    const std::string contact_name = t.contact;
    if (t.kind == ContactModeGraph::Kind::kTouchdown) {
      if (mode_contacts_[from] & ContactBit(contact))
        ThrowError("touchdown of '" + t.contact + "' from mode '" + t.from + "', where that contact is already active");
      DeclareGuard(
          "touchdown_" + contact_name, from, [this, contact](const LeafContext& c) { return TouchdownWitness(c, contact); }, CrossingDirection::kFalling,
          [this, contact, contact_name, to, nv](const LeafContext& c, int, State* next) {
            auto& s = c.scratch<Scratch>();
            const auto q = c.continuous_state().head(nv);
            if (!terrain_.is_flat()) {
              const Eigen::Vector3d p = CalcContactPointPosition(*model_, s.ws, q, contact, 0);
              if (terrain_.StoneAt(p.x(), params_.stone_tolerance_m) < 0) {
                std::ostringstream os;
                const int near = terrain_.NearestStone(p.x());
                os << "robot fell: '" << contact_name << "' touched down at x = " << p.x() << " m, not on any stone (nearest stone " << near
                   << " spans " << terrain_.stones()[near].x_center_m - terrain_.stones()[near].length_m / 2 << " .. "
                   << terrain_.stones()[near].x_center_m + terrain_.stones()[near].length_m / 2 << " m)";
                return EventStatus::ReachedTermination(os.str());
              }
            }
            CalcImpactMap(*model_, s.ws, q, c.continuous_state().tail(nv), mode_contacts_[to], params_.dynamics, s.v_plus, s.impulse);
            next->continuous.tail(nv) = s.v_plus;
            next->discrete[0] = c.time();
            next->mode = to;
            return EventStatus::Succeeded();
          });
    } else {
      if (!(mode_contacts_[from] & ContactBit(contact)))
        ThrowError("lift-off of '" + t.contact + "' from mode '" + t.from + "', where that contact is not active");
      DeclareGuard(
          "liftoff_" + contact_name, from,
          [this, contact, nv](const LeafContext& c) {
            const Scratch& s = EvalDynamics(c);
            auto& ws = const_cast<Scratch&>(s).ws;
            return ExtractContactWrench(*model_, ws, c.continuous_state().head(nv), s.active, s.F, contact).force.z();
          },
          CrossingDirection::kFalling,
          [to](const LeafContext& c, int, State* next) {
            next->discrete[0] = c.time();
            next->mode = to;
            return EventStatus::Succeeded();
          });
    }
  }
  if (base_height_index() >= 0) {
    DeclareGuard(
        "fall", kAllModes, [this](const LeafContext& c) { return c.continuous_state()[base_height_index()] - params_.min_base_height_m; },
        CrossingDirection::kFalling, [this](const LeafContext& c, int, State*) {
          std::ostringstream os;
          os << "robot fell: base height " << c.continuous_state()[base_height_index()] << " m is below min_base_height_m = " << params_.min_base_height_m
             << " m";
          return EventStatus::ReachedTermination(os.str());
        });
  }
}

std::any HybridContactPlant::AllocateScratch() const { return Scratch(*model_); }

void HybridContactPlant::SetState(LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v, const std::string& mode) const {
  const int nv = model_->nv();
  if (q.size() != nv || v.size() != nv)
    ThrowError("SetState: q has size " + std::to_string(q.size()) + " and v size " + std::to_string(v.size()) + "; robot '" + model_->name() +
               "' has nv = " + std::to_string(nv));
  State& s = context.get_mutable_state();
  s.continuous << q, v;
  s.mode = FindMode(graph_, mode, name());
  s.discrete[0] = context.time();
}

const HybridContactPlant::Scratch& HybridContactPlant::EvalDynamics(const LeafContext& context) const {
  Scratch& s = context.scratch<Scratch>();
  if (s.version == context.version()) return s;
  const int nv = model_->nv();
  const auto q = context.continuous_state().head(nv);
  const auto v = context.continuous_state().tail(nv);
  const Eigen::VectorXd& u = EvalInput(context, 0);
  if (params_.saturate_torques)
    s.u = u.cwiseMax(-model_->torque_limits()).cwiseMin(model_->torque_limits());
  else
    s.u = u;
  s.active = mode_contacts_[context.mode()];
  CalcConstrainedForwardDynamics(*model_, s.ws, q, v, s.u, s.active, params_.dynamics, s.qdd, s.F);
  s.version = context.version();
  return s;
}

void HybridContactPlant::DoCalcTimeDerivatives(const LeafContext& context, Eigen::VectorXd* xdot) const {
  const int nv = model_->nv();
  const Scratch& s = EvalDynamics(context);
  xdot->head(nv) = context.continuous_state().tail(nv);
  xdot->tail(nv) = s.qdd;
}

double HybridContactPlant::TouchdownWitness(const LeafContext& context, int contact) const {
  if (context.time() - context.discrete_state()[0] < params_.min_time_in_mode_s) return 1.0;  // not armed yet
  auto& ws = context.scratch<Scratch>().ws;
  const auto q = context.continuous_state().head(model_->nv());
  double lowest = std::numeric_limits<double>::infinity();
  const int np = static_cast<int>(model_->contacts()[contact].points.size());
  for (int p = 0; p < np; ++p) {
    const Eigen::Vector3d pos = CalcContactPointPosition(*model_, ws, q, contact, p);
    lowest = std::min(lowest, pos.z() - terrain_.SurfaceHeight(pos.x()));
  }
  return lowest;
}

}  // namespace rome
