#include "systems/plants/quaternion_to_euler_state.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Geometry>

#include "systems/multibody/free_flyer.h"
#include "systems/plants/contact_plant.h"

namespace rome {

const char* ToString(PlantBase base) { return base == PlantBase::kQuaternion ? "quaternion" : "euler"; }

PlantBase ParsePlantBase(const std::string& text, const std::string& what) {
  if (text == "euler") return PlantBase::kEuler;
  if (text == "quaternion") return PlantBase::kQuaternion;
  throw std::invalid_argument(what + " " + text + ": unknown base (euler or quaternion)");
}

void EulerStateParams::Validate() const {
  if (singularity_margin_rad > 0.0 && singularity_margin_rad < 0.5 * M_PI) return;  // false for NaN
  std::ostringstream msg;
  msg << "EulerStateParams: singularity_margin_rad = " << singularity_margin_rad << ": must be in (0, pi/2) rad";
  throw std::invalid_argument(msg.str());
}

namespace {

int NvOfQuaternionState(Eigen::Index size) {
  if (size < 13 || size % 2 == 0) {
    std::ostringstream msg;
    msg << "a quaternion-base state has 2 nv + 1 entries with nv >= 6, got " << size;
    throw std::invalid_argument(msg.str());
  }
  return static_cast<int>((size - 1) / 2);
}

}  // namespace

void QuaternionStateToEuler(const Eigen::Ref<const Eigen::VectorXd>& x_q, const EulerStateParams& params,
                            Eigen::Ref<Eigen::VectorXd> x_e) {
  const int nv = NvOfQuaternionState(x_q.size()), nq = nv + 1, nj = nv - 6;
  if (x_e.size() != 2 * nv) throw std::invalid_argument("QuaternionStateToEuler: the output has the wrong size");
  Eigen::Quaterniond quat;
  if (!FreeFlyerRotation(x_q.head<7>(), &quat))
    throw std::invalid_argument("QuaternionStateToEuler: the base quaternion is zero or not finite");
  const Eigen::Matrix3d R = quat.toRotationMatrix();
  // R = Rz(yaw) Ry(pitch) Rx(roll): R(2,0) = -sin(pitch), R(2,1) = cos(pitch) sin(roll), R(2,2) = cos(pitch) cos(roll),
  // R(1,0) = cos(pitch) sin(yaw), R(0,0) = cos(pitch) cos(yaw). atan2 keeps full precision near +-pi/2 (asin does not).
  const double pitch = std::atan2(-R(2, 0), std::hypot(R(0, 0), R(1, 0)));
  if (!(std::abs(pitch) <= 0.5 * M_PI - params.singularity_margin_rad)) {
    std::ostringstream msg;
    msg << "QuaternionStateToEuler: pitch = " << pitch
        << " rad is within singularity_margin_rad = " << params.singularity_margin_rad
        << " rad of +-pi/2, where the ZYX-Euler base is singular";
    throw std::invalid_argument(msg.str());
  }
  const double yaw = std::atan2(R(1, 0), R(0, 0)), roll = std::atan2(R(2, 1), R(2, 2));
  const Eigen::Vector3d v_B = x_q.segment<3>(nq), w = x_q.segment<3>(nq + 3);
  const double sr = std::sin(roll), cr = std::cos(roll);
  const double dyaw = (sr * w.y() + cr * w.z()) / std::cos(pitch);
  x_e.head<3>() = x_q.head<3>();
  x_e.segment<3>(3) << yaw, pitch, roll;
  x_e.segment(6, nj) = x_q.segment(7, nj);
  x_e.segment<3>(nv) = R * v_B;
  x_e.segment<3>(nv + 3) << dyaw, cr * w.y() - sr * w.z(), w.x() + std::sin(pitch) * dyaw;
  x_e.tail(nj) = x_q.tail(nj);
}

void EulerStateToQuaternion(const Eigen::Ref<const Eigen::VectorXd>& x_e, Eigen::Ref<Eigen::VectorXd> x_q) {
  if (x_e.size() < 12 || x_e.size() % 2 != 0 || x_q.size() != x_e.size() + 1)
    throw std::invalid_argument("EulerStateToQuaternion: sizes must be 2 nv (nv >= 6) and 2 nv + 1");
  const int nv = static_cast<int>(x_e.size() / 2), nq = nv + 1, nj = nv - 6;
  const Vector7d base = FreeFlyerFromEuler(x_e.head<6>());
  const double pitch = x_e[4], roll = x_e[5];
  const Eigen::Vector3d rates = x_e.segment<3>(nv + 3);  // d(yaw, pitch, roll)/dt
  Eigen::Quaterniond quat;
  FreeFlyerRotation(base, &quat);
  x_q.head<7>() = base;
  x_q.segment(7, nj) = x_e.segment(6, nj);
  x_q.segment<3>(nq) = quat.conjugate() * Eigen::Vector3d(x_e.segment<3>(nv));
  // w_B = Rx(roll)^T Ry(pitch)^T (dyaw e_z) + Rx(roll)^T (dpitch e_y) + droll e_x.
  const double sp = std::sin(pitch), cp = std::cos(pitch), sr = std::sin(roll), cr = std::cos(roll);
  x_q.segment<3>(nq + 3) << rates[2] - sp * rates[0], cr * rates[1] + sr * cp * rates[0],
      -sr * rates[1] + cr * cp * rates[0];
  x_q.tail(nj) = x_e.tail(nj);
}

Eigen::VectorXd EulerConfigurationToQuaternion(const Eigen::VectorXd& q_e) {
  if (q_e.size() < 6) throw std::invalid_argument("EulerConfigurationToQuaternion: q has fewer than 6 entries");
  Eigen::VectorXd q(q_e.size() + 1);
  q << FreeFlyerFromEuler(q_e.head<6>()), q_e.tail(q_e.size() - 6);
  return q;
}

void CheckEulerQuaternionTwins(const MultibodyModel& euler, const MultibodyModel& quaternion, const std::string& user) {
  auto fail = [&](const std::string& what) { throw std::invalid_argument(user + ": " + what); };
  if (euler.floating_base() != FloatingBaseType::kSpatial || euler.has_quaternion_base())
    fail("robot '" + euler.name() + "' (the Euler model) has base '" + euler.base_kind() + "', not 'spatial_euler'");
  if (!quaternion.has_quaternion_base())
    fail("robot '" + quaternion.name() + "' (the plant's model) has base '" + quaternion.base_kind() +
         "', not 'quaternion'");
  if (euler.nv() != quaternion.nv())
    fail("the Euler model has nv = " + std::to_string(euler.nv()) +
         ", the quaternion model nv = " + std::to_string(quaternion.nv()));
  for (int i = 6; i < euler.nv(); ++i)
    if (euler.JointName(i) != quaternion.JointName(i))
      fail("velocity " + std::to_string(i) + " is joint '" + euler.JointName(i) + "' on the Euler model, '" +
           quaternion.JointName(i) + "' on the quaternion model");
}

std::shared_ptr<const MultibodyModel> LoadQuaternionTwin(const MultibodyModel& euler) {
  if (euler.floating_base() != FloatingBaseType::kSpatial || euler.has_quaternion_base())
    throw std::invalid_argument("LoadQuaternionTwin: robot '" + euler.name() + "' has base '" + euler.base_kind() +
                                "', not a spatial Euler base");
  if (euler.urdf_path().empty())
    throw std::invalid_argument("LoadQuaternionTwin: robot '" + euler.name() +
                                "' was not loaded from a file (no URDF path to load its quaternion twin from)");
  LoadOptions options;
  options.quaternion_floating_base = true;
  auto twin =
      std::make_shared<const MultibodyModel>(MultibodyModel::Load(euler.urdf_path(), euler.sidecar_path(), options));
  CheckEulerQuaternionTwins(euler, *twin, "LoadQuaternionTwin");
  return twin;
}

QuaternionToEulerState::QuaternionToEulerState(std::string name, std::shared_ptr<const MultibodyModel> euler,
                                               std::shared_ptr<const MultibodyModel> quaternion,
                                               EulerStateParams params)
    : LeafSystem(std::move(name)), params_(params) {
  if (!euler || !quaternion) ThrowError("a model is null");
  try {
    params_.Validate();
    CheckEulerQuaternionTwins(*euler, *quaternion, "QuaternionToEulerState");
  } catch (const std::invalid_argument& e) { ThrowError(e.what()); }
  const int nv = euler->nv();
  DeclareInputPort("quaternion_state", 2 * nv + 1);
  DeclareOutputPort("state", StateElementNames(*euler), [this](const LeafContext& c, Eigen::VectorXd* y) {
    try {
      QuaternionStateToEuler(EvalInput(c, 0), params_, *y);
    } catch (const std::invalid_argument& e) {
      ThrowError(std::string(e.what()) + " at t = " + std::to_string(c.time()));
    }
  });
}

}  // namespace rome
