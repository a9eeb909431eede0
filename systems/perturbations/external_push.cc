#include "systems/perturbations/external_push.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

struct ExternalPush::Scratch {
  explicit Scratch(const MultibodyModel& model) : ws(model), J(Eigen::MatrixXd::Zero(3, model.nv())) {}
  MultibodyWorkspace ws;
  Eigen::MatrixXd J;
};

void ExternalPushParams::Validate() const {
  auto fail = [](const std::string& field, const std::string& value, const std::string& range) {
    throw std::invalid_argument("ExternalPushParams: " + field + " = " + value + " is outside " + range);
  };
  auto num = [](double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  };
  if (!(start_time_s >= 0.0 && start_time_s <= 1e6)) fail("start_time_s", num(start_time_s), "[0, 1e6] s");
  if (!(duration_s > 0.0 && duration_s <= 1e6)) fail("duration_s", num(duration_s), "(0, 1e6] s");
  if (!force_N.allFinite() || !(force_N.norm() <= 1e6))
    fail("force_N", num(force_N.x()) + "," + num(force_N.y()) + "," + num(force_N.z()), "|F| <= 1e6 N");
  if (!point_in_body_m.allFinite() || !(point_in_body_m.norm() <= 100.0))
    fail("point_in_body_m", num(point_in_body_m.norm()), "|p| <= 100 m");
}

ExternalPush::ExternalPush(std::string name, std::shared_ptr<const MultibodyModel> model, ExternalPushParams params)
    : LeafSystem(std::move(name)), model_(std::move(model)), params_(std::move(params)) {
  try {
    params_.Validate();
  } catch (const std::invalid_argument& e) { ThrowError(e.what()); }
  if (!model_->HasFrame(params_.body))
    ThrowError("robot '" + model_->name() + "' has no link '" + params_.body + "' to push");
  const MultibodyFrame& frame = model_->Frame(params_.body);
  body_ = frame.body;
  point_in_body_ = frame.X_body_frame * params_.point_in_body_m;
  const int nv = model_->nv();
  DeclareInputPort("state", 2 * nv);
  DeclareDiscreteState(Eigen::VectorXd::Zero(1));
  DeclarePeriodicDiscreteUpdate(params_.duration_s, params_.start_time_s,
                                [](const LeafContext& c, Eigen::VectorXd* xd) {
                                  (*xd)[0] = std::min(c.discrete_state()[0] + 1.0, 2.0);
                                  return EventStatus::Succeeded();
                                });
  DeclareOutputPort("tau_external", model_->joint_names(), [this, nv](const LeafContext& c, Eigen::VectorXd* tau) {
    if (c.discrete_state()[0] != 1.0) {
      tau->setZero();
      return;
    }
    Scratch& s = c.scratch<Scratch>();
    const auto q = EvalInput(c, 0).head(nv);
    CalcPointJacobian(*model_, s.ws, q, body_, point_in_body_, s.J);
    tau->noalias() = s.J.transpose() * params_.force_N;
  });
}

std::any ExternalPush::AllocateScratch() const { return Scratch(*model_); }

}  // namespace rome
