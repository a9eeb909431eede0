#include "systems/multibody/free_flyer_kernels.h"

namespace rome {

namespace {

Eigen::Matrix3d Skew(const Eigen::Vector3d& x) {
  Eigen::Matrix3d S;
  S << 0.0, -x.z(), x.y(), x.z(), 0.0, -x.x(), -x.y(), x.x(), 0.0;
  return S;
}

}  // namespace

void CalcFreeFlyerMassMatrix(const MultibodyModel& model, MultibodyWorkspace& ws) {
  const Eigen::Matrix3d& R = ws.R_world_link(kFreeFlyerRootBody);
  const Eigen::VectorXd& armature = model.reflected_inertia();
  Eigen::MatrixXd& M = ws.M;
  const int nb = model.num_bodies();
  for (int i = kFreeFlyerRootBody + 1; i < nb; ++i) {
    const int k = model.body(i).v_index;
    if (k < 0) continue;
    const Vector6d F = ws.composite_inertia(i) * ws.S(i);
    M(k, k) = ws.S(i).dot(F) + armature[k];
    // support_body lists the bodies with a dof from i to the root: the joints, then the base's six.
    int m = ws.support_begin[i] + 1;
    for (int j = ws.support_body[m]; j > kFreeFlyerRootBody; j = ws.support_body[++m]) {
      const int kj = model.body(j).v_index;
      const double Mkj = ws.S(j).dot(F);
      M(kj, k) = Mkj;
      M(k, kj) = Mkj;
    }
    // Base column S_base^T F = [R^T f; R^T n].
    const Eigen::Vector3d f_B = R.transpose() * F.tail<3>(), n_B = R.transpose() * F.head<3>();
    M.block<3, 1>(0, k) = f_B;
    M.block<3, 1>(3, k) = n_B;
    M.block<1, 3>(k, 0) = f_B.transpose();
    M.block<1, 3>(k, 3) = n_B.transpose();
  }
  const SpatialInertia& Ic = ws.composite_inertia(kFreeFlyerRootBody);
  const Eigen::Vector3d h_B = R.transpose() * Ic.h;
  const Eigen::Matrix3d H = Skew(h_B);
  M.topLeftCorner<3, 3>() = Ic.m * Eigen::Matrix3d::Identity();
  M.block<3, 3>(0, 3) = -H;
  M.block<3, 3>(3, 0) = H;
  const Eigen::Matrix3d I_B = R.transpose() * Ic.I * R;
  M.block<3, 3>(3, 3) = 0.5 * (I_B + I_B.transpose());  // exactly symmetric, as M is
  M.diagonal().head<6>() += armature.head<6>();
}

void CalcFreeFlyerRnea(const MultibodyModel& model, MultibodyWorkspace& ws, const double* qdd, double* tau) {
  const Eigen::Matrix3d& R = ws.R_world_link(kFreeFlyerRootBody);
  // Gravity enters as the fictitious base acceleration a_0 = [0; -g].
  Vector6d a0 = Vector6d::Zero();
  a0.tail<3>() = -model.gravity();
  const int nb = model.num_bodies();
  Vector6d& a_root = ws.a_[kFreeFlyerRootBody];  // S_base qdd_base
  a_root.setZero();
  if (qdd) {
    a_root.head<3>().noalias() = R * Eigen::Map<const Eigen::Vector3d>(qdd + 3);
    a_root.tail<3>().noalias() = R * Eigen::Map<const Eigen::Vector3d>(qdd);
  }
  for (int b = kFreeFlyerRootBody; b < nb; ++b) {
    Vector6d& a = ws.a_[b];
    if (b > kFreeFlyerRootBody) {
      a = ws.a_[model.body(b).parent];
      const int k = model.body(b).v_index;
      if (qdd && k >= 0) a += ws.S(b) * qdd[k];
    }
    const SpatialInertia& I = ws.inertia(b);
    if (I.m == 0.0) {
      ws.f_[b].setZero();
      continue;
    }
    const Vector6d& V = ws.V(b);
    const Vector6d IV = I * V;
    Vector6d f = I * (a + ws.A_bias(b) + a0);
    f.head<3>() += V.head<3>().cross(IV.head<3>()) + V.tail<3>().cross(IV.tail<3>());
    f.tail<3>() += V.head<3>().cross(IV.tail<3>());
    ws.f_[b] = f;
  }
  const Eigen::VectorXd& armature = model.reflected_inertia();
  for (int b = nb - 1; b > kFreeFlyerRootBody; --b) {
    const int k = model.body(b).v_index;
    if (k >= 0) tau[k] = ws.S(b).dot(ws.f_[b]) + (qdd ? armature[k] * qdd[k] : 0.0);
    ws.f_[model.body(b).parent] += ws.f_[b];
  }
  const Vector6d& f = ws.f_[kFreeFlyerRootBody];
  Eigen::Map<Eigen::Vector3d>(tau).noalias() = R.transpose() * f.tail<3>();
  Eigen::Map<Eigen::Vector3d>(tau + 3).noalias() = R.transpose() * f.head<3>();
  if (qdd)
    for (int k = 0; k < 6; ++k) tau[k] += armature[k] * qdd[k];
}

Eigen::Matrix<double, 3, 6> FreeFlyerPointJacobianColumns(const MultibodyWorkspace& ws, const Eigen::Vector3d& r) {
  const Eigen::Matrix3d& R = ws.R_world_link(kFreeFlyerRootBody);
  Eigen::Matrix<double, 3, 6> J;
  J.leftCols<3>() = R;
  // Column j of the angular part: (R e_j) x r.
  for (int j = 0; j < 3; ++j) J.col(3 + j) = R.col(j).cross(r);
  return J;
}

}  // namespace rome
