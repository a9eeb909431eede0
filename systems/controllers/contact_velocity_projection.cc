#include "systems/controllers/contact_velocity_projection.h"

#include <algorithm>
#include <stdexcept>

#include "systems/controllers/controller_setup.h"
#include "systems/multibody/multibody_workspace.h"
#include "systems/plants/contact_plant.h"

namespace rome {

struct ContactVelocityProjection::Scratch {
  Scratch(const MultibodyModel& model, int rows) : ws(model), impulse(Eigen::VectorXd::Zero(std::max(rows, 1))) {}
  MultibodyWorkspace ws;
  Eigen::VectorXd impulse;
};

ContactVelocityProjection::ContactVelocityProjection(std::string name, std::shared_ptr<const MultibodyModel> model,
                                                     std::vector<ContactSet> mode_contacts,
                                                     ConstrainedDynamicsParameters dynamics)
    : LeafSystem(std::move(name)),
      model_(std::move(model)),
      mode_contacts_(std::move(mode_contacts)),
      dynamics_(dynamics) {
  if (!model_) ThrowError("null MultibodyModel");
  if (mode_contacts_.empty()) ThrowError("no contact modes given (mode_contacts is empty)");
  for (const ContactSet active : mode_contacts_) {
    try {
      max_rows_ = std::max(max_rows_, CountConstraintRows(*model_, active));
    } catch (const std::exception& e) { ThrowError(e.what()); }
  }
  const int nq = model_->nq(), nv = model_->nv();
  DeclareInputPort("state", nq + nv);
  mode_port_ = DeclareTypedInputPort<int>("mode");
  DeclareOutputPort("state", StateElementNames(*model_), [this, nq, nv](const LeafContext& c, Eigen::VectorXd* y) {
    const Eigen::VectorXd& x = EvalInput(c, 0);
    if (!x.allFinite()) ThrowError("input port 'state' is not finite at t = " + std::to_string(c.time()));
    const int mode =
        CheckedModeIndex(EvalTypedInput<int>(c, mode_port_), static_cast<int>(mode_contacts_.size()), this->name());
    Scratch& s = c.scratch<Scratch>();
    y->head(nq) = x.head(nq);
    CalcImpactMap(*model_, s.ws, x.head(nq), x.tail(nv), mode_contacts_[mode], dynamics_, y->tail(nv), s.impulse);
  });
}

std::any ContactVelocityProjection::AllocateScratch() const { return Scratch(*model_, max_rows_); }

}  // namespace rome
