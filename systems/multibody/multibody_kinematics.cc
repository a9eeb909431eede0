#include "systems/multibody/multibody_kinematics.h"

#include "systems/multibody/free_flyer_kernels.h"

#include <stdexcept>
#include <string>

namespace rome {

namespace {

void CheckBody(const MultibodyModel& model, int body) {
  if (body < 0 || body >= model.num_bodies())
    throw std::invalid_argument("robot '" + model.name() + "': body index " + std::to_string(body) +
                                " out of range [0, " + std::to_string(model.num_bodies()) + ")");
}

void CheckJacobianSize(const MultibodyModel& model, const Eigen::Ref<Eigen::MatrixXd>& J, int rows, const char* what) {
  if (J.rows() != rows || J.cols() != model.nv())
    throw std::invalid_argument(std::string(what) + " of robot '" + model.name() + "': output is " +
                                std::to_string(J.rows()) + "x" + std::to_string(J.cols()) + ", expected " +
                                std::to_string(rows) + "x" + std::to_string(model.nv()));
}

}  // namespace

Eigen::Isometry3d CalcLinkPose(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body) {
  CheckBody(model, body);
  ws.SetPositions(model, q);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = ws.R_world_link(body);
  X.translation() = ws.p_world_link(body);
  return X;
}

Eigen::Vector3d CalcPointPosition(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body,
                                  const Eigen::Vector3d& p_link) {
  CheckBody(model, body);
  ws.SetPositions(model, q);
  return ws.p_world_link(body) + ws.R_world_link(body) * p_link;
}

Vector6d CalcFrameVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                           int body, const Eigen::Vector3d& p_link) {
  CheckBody(model, body);
  ws.SetState(model, q, v);
  const Eigen::Vector3d r = ws.p_world_link(body) + ws.R_world_link(body) * p_link - ws.reference_point();
  const Vector6d& V = ws.V(body);
  Vector6d out;
  out.head<3>() = V.head<3>();
  out.tail<3>() = V.tail<3>() + V.head<3>().cross(r);
  return out;
}

Eigen::Vector3d CalcPointVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                  const VectorRef& v, int body, const Eigen::Vector3d& p_link) {
  return CalcFrameVelocity(model, ws, q, v, body, p_link).tail<3>();
}

void CalcFrameJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body,
                       const Eigen::Vector3d& p_link, Eigen::Ref<Eigen::MatrixXd> J) {
  CheckBody(model, body);
  CheckJacobianSize(model, J, 6, "CalcFrameJacobian");
  ws.SetPositions(model, q);
  J.setZero();
  const Eigen::Vector3d r = ws.p_world_link(body) + ws.R_world_link(body) * p_link - ws.reference_point();
  const bool one_joint = ws.free_flyer_as_one_joint();
  for (int b = body; b >= 0; b = model.body(b).parent) {
    if (one_joint && b <= kFreeFlyerRootBody) {  // the base joint's six columns: angular [0, R], linear
      J.block<3, 3>(0, 3) = ws.R_world_link(kFreeFlyerRootBody);
      J.bottomLeftCorner<3, 6>() = FreeFlyerPointJacobianColumns(ws, r);
      break;
    }
    const int k = model.body(b).v_index;
    if (k < 0) continue;
    const Vector6d& S = ws.S(b);
    J.col(k).head<3>() = S.head<3>();
    J.col(k).tail<3>() = S.tail<3>() + S.head<3>().cross(r);
  }
}

void CalcPointJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, int body,
                       const Eigen::Vector3d& p_link, Eigen::Ref<Eigen::MatrixXd> J) {
  CheckBody(model, body);
  CheckJacobianSize(model, J, 3, "CalcPointJacobian");
  ws.SetPositions(model, q);
  J.setZero();
  const Eigen::Vector3d r = ws.p_world_link(body) + ws.R_world_link(body) * p_link - ws.reference_point();
  const bool one_joint = ws.free_flyer_as_one_joint();
  for (int m = ws.support_begin[body]; m < ws.support_begin[body + 1]; ++m) {
    const int b = ws.support_body[m];
    if (one_joint && b <= kFreeFlyerRootBody) {  // the base joint's six columns
      J.leftCols<6>() = FreeFlyerPointJacobianColumns(ws, r);
      break;
    }
    const Vector6d& S = ws.S(b);
    J.col(model.body(b).v_index) = S.tail<3>() + S.head<3>().cross(r);
  }
}

Vector6d CalcFrameJdotQdot(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v,
                           int body, const Eigen::Vector3d& p_link) {
  CheckBody(model, body);
  ws.SetState(model, q, v);
  const Eigen::Vector3d r = ws.p_world_link(body) + ws.R_world_link(body) * p_link - ws.reference_point();
  const Vector6d& V = ws.V(body);
  const Vector6d& A = ws.A_bias(body);
  // Classical acceleration of a body point from the spatial acceleration at O:
  // a_p = a_O + omegadot x r + omega x v_p.
  const Eigen::Vector3d v_p = V.tail<3>() + V.head<3>().cross(r);
  Vector6d out;
  out.head<3>() = A.head<3>();
  out.tail<3>() = A.tail<3>() + A.head<3>().cross(r) + V.head<3>().cross(v_p);
  return out;
}

Eigen::Vector3d CalcPointJdotQdot(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                  const VectorRef& v, int body, const Eigen::Vector3d& p_link) {
  return CalcFrameJdotQdot(model, ws, q, v, body, p_link).tail<3>();
}

Eigen::Vector3d CalcComPosition(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q) {
  ws.SetPositions(model, q);
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int b = 0; b < model.num_bodies(); ++b) c += model.body(b).mass * ws.com_world(b);
  return c / model.total_mass();
}

namespace {

// Total spatial momentum about O: sum_b I_b V_b.
Vector6d SpatialMomentumAtO(const MultibodyModel& model, MultibodyWorkspace& ws) {
  Vector6d hO = Vector6d::Zero();
  for (int b = 0; b < model.num_bodies(); ++b) hO += ws.inertia(b) * ws.V(b);
  return hO;
}

// Rate of the spatial momentum about the fixed point O with qdd = 0 and no gravity:
// sum_b I_b A_bias_b + V_b x* (I_b V_b).
Vector6d SpatialMomentumBiasAtO(const MultibodyModel& model, MultibodyWorkspace& ws) {
  Vector6d out = Vector6d::Zero();
  for (int b = 0; b < model.num_bodies(); ++b) {
    const SpatialInertia& I = ws.inertia(b);
    if (I.m == 0.0) continue;
    const Vector6d& V = ws.V(b);
    const Vector6d IV = I * V;
    out += I * ws.A_bias(b);
    out.head<3>() += V.head<3>().cross(IV.head<3>()) + V.tail<3>().cross(IV.tail<3>());
    out.tail<3>() += V.head<3>().cross(IV.tail<3>());
  }
  return out;
}

// Shift a spatial force/momentum from O to the COM: [n_G; f] = [n_O - (c - O) x f; f].
Vector6d ShiftToCom(const Vector6d& hO, const Eigen::Vector3d& c_minus_O) {
  Vector6d out;
  out.head<3>() = hO.head<3>() - c_minus_O.cross(hO.tail<3>());
  out.tail<3>() = hO.tail<3>();
  return out;
}

}  // namespace

Eigen::Vector3d CalcComVelocity(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                const VectorRef& v) {
  ws.SetState(model, q, v);
  return SpatialMomentumAtO(model, ws).tail<3>() / model.total_mass();
}

void CalcCentroidalMomentumMatrix(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                  Eigen::Ref<Eigen::MatrixXd> A_G) {
  CheckJacobianSize(model, A_G, 6, "CalcCentroidalMomentumMatrix");
  ws.SetPositions(model, q);
  const Eigen::Vector3d c = CalcComPosition(model, ws, q) - ws.reference_point();
  // Column k: momentum of the subtree of joint k moving with unit rate, Ic_k S_k (at O),
  // shifted to the COM.
  for (int b = 0; b < model.num_bodies(); ++b) {
    const int k = model.body(b).v_index;
    if (k < 0) continue;
    A_G.col(k) = ShiftToCom(ws.composite_inertia(b) * ws.S(b), c);
  }
}

void CalcComJacobian(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                     Eigen::Ref<Eigen::MatrixXd> J_com) {
  CheckJacobianSize(model, J_com, 3, "CalcComJacobian");
  ws.SetPositions(model, q);
  for (int b = 0; b < model.num_bodies(); ++b) {
    const int k = model.body(b).v_index;
    if (k < 0) continue;
    J_com.col(k) = (ws.composite_inertia(b) * ws.S(b)).tail<3>() / model.total_mass();
  }
}

Vector6d CalcCentroidalMomentum(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                const VectorRef& v) {
  ws.SetState(model, q, v);
  const Eigen::Vector3d c = CalcComPosition(model, ws, q) - ws.reference_point();
  return ShiftToCom(SpatialMomentumAtO(model, ws), c);
}

Vector6d CalcCentroidalMomentumBias(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                    const VectorRef& v) {
  ws.SetState(model, q, v);
  const Eigen::Vector3d c = CalcComPosition(model, ws, q) - ws.reference_point();
  // d/dt k_G = d/dt k_O - cdot x l - (c - O) x ldot, and cdot x l = 0 (l = m cdot).
  return ShiftToCom(SpatialMomentumBiasAtO(model, ws), c);
}

Eigen::Vector3d CalcComJdotQdot(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q,
                                const VectorRef& v) {
  ws.SetState(model, q, v);
  return SpatialMomentumBiasAtO(model, ws).tail<3>() / model.total_mass();
}

double CalcKineticEnergy(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q, const VectorRef& v) {
  ws.SetState(model, q, v);
  double T = 0.0;
  for (int b = 0; b < model.num_bodies(); ++b) T += 0.5 * ws.V(b).dot(ws.inertia(b) * ws.V(b));
  T += 0.5 * (model.reflected_inertia().array() * v.array().square()).sum();
  return T;
}

double CalcPotentialEnergy(const MultibodyModel& model, MultibodyWorkspace& ws, const VectorRef& q) {
  ws.SetPositions(model, q);
  double U = 0.0;
  for (int b = 0; b < model.num_bodies(); ++b) U -= model.body(b).mass * model.gravity().dot(ws.com_world(b));
  const int n = model.has_quaternion_base() ? model.nv() - 6 : model.nv();  // joint coordinates: q's last n
  U += 0.5 *
       (model.spring_stiffness().tail(n).array() * (q.tail(n) - model.spring_rest().tail(n)).array().square()).sum();
  return U;
}

}  // namespace rome
