#include "systems/multibody/multibody_workspace.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyLink.h>

#include "systems/multibody/bullet_multibody.h"
#include "systems/multibody/bullet_scratch.h"
#include "systems/multibody/free_flyer.h"

namespace rome {

MultibodyWorkspace::MultibodyWorkspace(const MultibodyModel& model) { Build(model); }
MultibodyWorkspace::~MultibodyWorkspace() = default;
MultibodyWorkspace::MultibodyWorkspace(MultibodyWorkspace&&) noexcept = default;
MultibodyWorkspace& MultibodyWorkspace::operator=(MultibodyWorkspace&&) noexcept = default;

MultibodyWorkspace::MultibodyWorkspace(const MultibodyWorkspace& other)
    : valid(),
      M(other.M),
      dof_parent(other.dof_parent),
      support_begin(other.support_begin),
      support_body(other.support_body),
      ancestor_begin(other.ancestor_begin),
      ancestor_index(other.ancestor_index),
      L_packed(other.L_packed),
      D(other.D),
      use_tree_factor(other.use_tree_factor),
      M_llt(other.M_llt),
      h(other.h),
      tau_spring(other.tau_spring),
      tmp_nv(other.tmp_nv),
      tmp2_nv(other.tmp2_nv),
      tau_total(other.tau_total),
      f_(other.f_),
      a_(other.a_),
      bullet_in(other.bullet_in),
      bullet_out(other.bullet_out),
      armature_dofs(other.armature_dofs),
      Minv_P(other.Minv_P),
      armature_system(other.armature_system),
      armature_llt(other.armature_llt),
      armature_y(other.armature_y),
      J(other.J),
      Jdot_qdot(other.Jdot_qdot),
      phi(other.phi),
      Minv_JT(other.Minv_JT),
      JLinv(other.JLinv),
      solve_rows(other.solve_rows),
      Lambda(other.Lambda),
      Lambda_L(other.Lambda_L),
      rhs(other.rhs),
      lambda_sol(other.lambda_sol),
      residual(other.residual),
      J_point(other.J_point),
      bodies_(other.bodies_),
      q_(other.q_),
      v_(other.v_),
      has_q_(false),
      has_v_(false),
      quaternion_base_(other.quaternion_base_),
      free_flyer_one_joint_(other.free_flyer_one_joint_),
      robot_name_(other.robot_name_),
      position_index_(other.position_index_),
      axis_index_(other.axis_index_),
      axis_sign_(other.axis_sign_),
      joint_rotation_identity_(other.joint_rotation_identity_),
      O_(other.O_),
      R_wl_(other.R_wl_),
      p_wl_(other.p_wl_),
      c_w_(other.c_w_),
      S_(other.S_),
      V_(other.V_),
      A_bias_(other.A_bias_),
      I_(other.I_),
      Ic_(other.Ic_) {}

MultibodyWorkspace& MultibodyWorkspace::operator=(const MultibodyWorkspace& other) {
  if (this != &other) {
    MultibodyWorkspace copy(other);
    *this = std::move(copy);
  }
  return *this;
}

void MultibodyWorkspace::Build(const MultibodyModel& model) {
  bodies_ = model.shared_bodies();
  const int nv = model.nv();
  const int nb = model.num_bodies();
  const int rows = model.max_constraint_rows();
  q_.setZero(model.nq());
  v_.setZero(nv);
  quaternion_base_ = model.has_quaternion_base();
  robot_name_ = model.name();
  position_index_.assign(nb, -1);
  for (int i = 0; i < nb; ++i) position_index_[i] = model.PositionIndexOfVelocity((*bodies_)[i].v_index);
  R_wl_.assign(nb, Eigen::Matrix3d::Identity());
  p_wl_.assign(nb, Eigen::Vector3d::Zero());
  c_w_.assign(nb, Eigen::Vector3d::Zero());
  S_.assign(nb, Vector6d::Zero());
  V_.assign(nb, Vector6d::Zero());
  A_bias_.assign(nb, Vector6d::Zero());
  f_.assign(nb, Vector6d::Zero());
  a_.assign(nb, Vector6d::Zero());
  I_.assign(nb, SpatialInertia());
  Ic_.assign(nb, SpatialInertia());
  M.setZero(nv, nv);
  M_llt.compute(Eigen::MatrixXd::Identity(nv, nv));  // sizes the factor storage once
  dof_parent.assign(nv, -1);
  use_tree_factor = true;
  {
    const std::vector<MultibodyBody>& bodies = *bodies_;
    for (int i = 0; i < nb; ++i) {
      const int k = bodies[i].v_index;
      if (k < 0) continue;
      int j = bodies[i].parent;
      while (j >= 0 && bodies[j].v_index < 0) j = bodies[j].parent;
      dof_parent[k] = j >= 0 ? bodies[j].v_index : -1;
      if (dof_parent[k] >= k) use_tree_factor = false;
    }
  }
  axis_index_.assign(nb, -1);
  axis_sign_.assign(nb, 1.0);
  joint_rotation_identity_.assign(nb, 0);
  for (int i = 0; i < nb; ++i) {
    const MultibodyBody& b = (*bodies_)[i];
    for (int j = 0; j < 3; ++j)
      if (std::abs(b.axis[j]) == 1.0 && b.axis[(j + 1) % 3] == 0.0 && b.axis[(j + 2) % 3] == 0.0) {
        axis_index_[i] = j;
        axis_sign_[i] = b.axis[j];
      }
    joint_rotation_identity_[i] = b.X_parent_joint.linear() == Eigen::Matrix3d::Identity();
  }
  support_begin.assign(1, 0);
  support_body.clear();
  for (int i = 0; i < nb; ++i) {
    for (int b = i; b >= 0; b = (*bodies_)[b].parent)
      if ((*bodies_)[b].v_index >= 0) support_body.push_back(b);
    support_begin.push_back(static_cast<int>(support_body.size()));
  }
  ancestor_begin.assign(1, 0);
  ancestor_index.clear();
  for (int k = 0; k < nv; ++k) {
    if (use_tree_factor)
      for (int j = dof_parent[k]; j >= 0; j = dof_parent[j]) ancestor_index.push_back(j);
    ancestor_begin.push_back(static_cast<int>(ancestor_index.size()));
  }
  L_packed.setZero(static_cast<Eigen::Index>(ancestor_index.size()));
  D.setOnes(nv);
  h.setZero(nv);
  tau_spring.setZero(nv);
  tmp_nv.setZero(nv);
  tmp2_nv.setZero(nv);
  tau_total.setZero(nv);
  bullet_in.setZero(6 + nv);
  bullet_out.setZero(6 + nv);
  armature_dofs.clear();
  for (int k = 0; k < nv; ++k)
    if (model.reflected_inertia()[k] > 0.0) armature_dofs.push_back(k);
  const int na = static_cast<int>(armature_dofs.size());
  Minv_P.setZero(nv, na);
  armature_system.setZero(na, na);
  armature_llt.compute(Eigen::MatrixXd::Identity(na, na));
  armature_y.setZero(na);
  J.setZero(rows, nv);
  Jdot_qdot.setZero(rows);
  phi.setZero(rows);
  Minv_JT.setZero(nv, rows);
  JLinv.setZero(rows, nv);
  solve_rows.setZero(std::max({nv, model.nu(), rows}), nv);
  Lambda.setZero(rows, rows);
  Lambda_L.setZero(rows, rows);
  rhs.setZero(rows);
  lambda_sol.setZero(rows);
  residual.setZero(rows);
  J_point.setZero(6, nv);
}

btMultiBody& MultibodyWorkspace::bullet() {
  if (!bullet_) BuildBullet();
  return *bullet_;
}

MultibodyWorkspace::BulletScratch& MultibodyWorkspace::bullet_scratch() {
  if (!bullet_) BuildBullet();
  return *scratch_;
}

void MultibodyWorkspace::BuildBullet() {
  if (quaternion_base_)
    throw std::logic_error("robot '" + robot_name_ +
                           "': Bullet (its articulated-body algorithm, M^-1 operator and poses) does not support the "
                           "quaternion floating base; the CRBA, RNEA and SolveMassMatrix do");
  scratch_ = std::make_unique<BulletScratch>();
  bullet_ = BuildBulletMultiBody(*bodies_);
  bullet_->finalizeMultiDof();
  // Size Bullet's scratch arrays once (later calls resize to the same sizes: no allocation).
  bullet_->forwardKinematics(scratch_->world_to_local, scratch_->local_origin);
  bullet_->computeAccelerationsArticulatedBodyAlgorithmMultiDof(0.0, scratch_->scratch_r, scratch_->scratch_v,
                                                                scratch_->scratch_m, false, false, false);
  // Own buffers: a lazy build must not overwrite bullet_in, which a caller may have filled already.
  Eigen::VectorXd in = Eigen::VectorXd::Zero(bullet_in.size()), out(bullet_out.size());
  bullet_->calcAccelerationDeltasMultiDof(in.data(), out.data(), scratch_->scratch_r2, scratch_->scratch_v2);
  // Nothing was pushed into the new tree yet; the kinematics and M of the current state stay valid.
  valid.bullet_q = valid.bullet_v = valid.bullet_minv = valid.armature = false;
}

void MultibodyWorkspace::SetPositions(const MultibodyModel& model, const Eigen::Ref<const Eigen::VectorXd>& q) {
  if (q.size() != model.nq())
    throw std::invalid_argument("robot '" + model.name() + "': q has size " + std::to_string(q.size()) +
                                ", expected nq = " + std::to_string(model.nq()));
  // Bitwise compare (memcmp beats an element-wise == loop). -0.0 against 0.0 only costs a recomputation; the same NaN
  // bits count as unchanged (== recomputed them), which is harmless: the results would be the same NaNs.
  if (has_q_ && (q_.size() == 0 || std::memcmp(q.data(), q_.data(), sizeof(double) * q_.size()) == 0))
    return;  // no dof: null data
  q_ = q;
  has_q_ = true;
  has_v_ = false;  // velocity kinematics depend on q
  valid = Flags();

  const std::vector<MultibodyBody>& bodies = *bodies_;
  const int nb = static_cast<int>(bodies.size());
  int first_body = 0;
  if (quaternion_base_) first_body = SetFreeFlyerPose(model);
  // Forward kinematics with fixed-size Eigen math (the URDF joint chain), root to leaves:
  //   R_wl = R_wp R_pj R_axis(q),  p_wl = p_wp + R_wp (t_pj + R_pj axis q) (prismatic).
  // Bullet's joint positions are only pushed (lazily, EnsureBulletPositions) when a Bullet
  // algorithm (ABA, M^-1) is called; the test suite checks these poses against Bullet's
  // forwardKinematics to 1e-12.
  for (int i = first_body; i < nb; ++i) {
    const MultibodyBody& b = bodies[i];
    const int p = b.parent;
    const auto R_pj = b.X_parent_joint.linear();
    const auto t_pj = b.X_parent_joint.translation();
    Eigen::Matrix3d R_wj;  // joint frame at q = 0 in world
    Eigen::Vector3d p_wj;
    if (p >= 0) {
      if (joint_rotation_identity_[i])
        R_wj = R_wl_[p];
      else
        R_wj.noalias() = R_wl_[p].lazyProduct(R_pj);
      p_wj.noalias() = R_wl_[p] * t_pj;
      p_wj += p_wl_[p];
    } else {
      R_wj = R_pj;
      p_wj = t_pj;
    }
    const double qi = position_index_[i] >= 0 ? q_[position_index_[i]] : 0.0;
    switch (b.joint_type) {
      case MultibodyJointType::kRevolute: {
        if (axis_index_[i] >= 0) {
          // About ±e_a: columns a+1, a+2 (cyclic) turn by the angle ±q in their plane; column a stays.
          const int a = axis_index_[i], a1 = (a + 1) % 3, a2 = (a + 2) % 3;
          const double s = std::sin(axis_sign_[i] * qi), c = std::cos(qi);
          R_wl_[i].col(a) = R_wj.col(a);
          R_wl_[i].col(a1) = c * R_wj.col(a1) + s * R_wj.col(a2);
          R_wl_[i].col(a2) = c * R_wj.col(a2) - s * R_wj.col(a1);
          p_wl_[i] = p_wj;
          break;
        }
        // Rodrigues: R_axis(q) = cos q I + sin q [a]x + (1 - cos q) a a^T, so with w = R_wj a
        // column j of R_wj R_axis is cos q r_j + sin q (w x r_j) + (1 - cos q) a_j w.
        const double s = std::sin(qi), c = std::cos(qi), c1 = 1.0 - c;
        const Eigen::Vector3d& a = b.axis;
        const Eigen::Vector3d w = R_wj * a;
        for (int j = 0; j < 3; ++j) {
          const Eigen::Vector3d r = R_wj.col(j);
          R_wl_[i].col(j) = c * r + s * w.cross(r) + (c1 * a[j]) * w;
        }
        p_wl_[i] = p_wj;
        break;
      }
      case MultibodyJointType::kPrismatic:
        R_wl_[i] = R_wj;
        p_wl_[i].noalias() = p_wj + (qi * R_wj) * b.axis;
        break;
      case MultibodyJointType::kFixed:
        R_wl_[i] = R_wj;
        p_wl_[i] = p_wj;
        break;
    }
    c_w_[i].noalias() = R_wl_[i] * b.com;
    c_w_[i] += p_wl_[i];
  }
  // Reference point O for all spatial quantities: the root link origin (keeps lever arms small).
  O_ = p_wl_[model.num_base_dofs() > 0 ? model.num_base_dofs() - 1 : 0];
  for (int i = 0; i < nb; ++i) {
    const MultibodyBody& b = bodies[i];
    // Motion subspace in world axes at O.
    const Eigen::Vector3d axis = axis_index_[i] >= 0 ? Eigen::Vector3d(axis_sign_[i] * R_wl_[i].col(axis_index_[i]))
                                                     : Eigen::Vector3d(R_wl_[i] * b.axis);
    switch (b.joint_type) {
      case MultibodyJointType::kRevolute:
        S_[i].head<3>() = axis;
        S_[i].tail<3>() = (p_wl_[i] - O_).cross(axis);
        break;
      case MultibodyJointType::kPrismatic:
        S_[i].head<3>().setZero();
        S_[i].tail<3>() = axis;
        break;
      case MultibodyJointType::kFixed: S_[i].setZero(); break;
    }
    // Spatial inertia at O: I_O = R I_c R^T + m (|c|^2 1 - c c^T), h = m c.
    SpatialInertia& I = I_[i];
    if (b.mass == 0.0 && b.inertia.isZero(0.0)) {  // massless (virtual) body
      I = SpatialInertia();
      continue;
    }
    const Eigen::Vector3d c = c_w_[i] - O_;
    I.m = b.mass;
    I.h = b.mass * c;
    const Eigen::Matrix3d RI = R_wl_[i].lazyProduct(b.inertia);
    I.I.noalias() = RI.lazyProduct(R_wl_[i].transpose());
    I.I.noalias() -= (b.mass * c).lazyProduct(c.transpose());
    I.I.diagonal().array() += b.mass * c.squaredNorm();
  }
  // Composite inertias (leaves to root); all at the same point, so they simply add.
  for (int i = 0; i < nb; ++i) Ic_[i] = I_[i];
  for (int i = nb - 1; i >= 0; --i)
    if (bodies[i].parent >= 0) Ic_[bodies[i].parent] += Ic_[i];
}

int MultibodyWorkspace::SetFreeFlyerPose(const MultibodyModel& model) {
  const Vector7d base = q_.head<7>();
  Eigen::Quaterniond quat;
  if (!FreeFlyerRotation(base, &quat)) {
    has_q_ = false;
    throw std::invalid_argument("robot '" + model.name() +
                                "': q's base quaternion (w x y z) = " + std::to_string(base[3]) + " " +
                                std::to_string(base[4]) + " " + std::to_string(base[5]) + " " +
                                std::to_string(base[6]) + " is not a finite nonzero quaternion");
  }
  const Eigen::Matrix3d R = quat.toRotationMatrix();
  for (int i = 0; i < 6; ++i) {
    R_wl_[i] = R;
    p_wl_[i] = base.head<3>();
    c_w_[i] = p_wl_[i] + R * (*bodies_)[i].com;
  }
  return 6;
}

void MultibodyWorkspace::SetFreeFlyerAsOneJoint(bool one_joint) {
  free_flyer_one_joint_ = one_joint;
  has_q_ = has_v_ = false;
  valid = Flags();
}

void MultibodyWorkspace::EnsureBulletPositions() {
  if (!bullet_) BuildBullet();
  if (valid.bullet_q) return;
  const std::vector<MultibodyBody>& bodies = *bodies_;
  const int nb = static_cast<int>(bodies.size());
  for (int i = 0; i < nb; ++i)
    if (bodies[i].v_index >= 0) bullet_->setJointPos(i, q_[bodies[i].v_index]);
  valid.bullet_q = true;
}

void MultibodyWorkspace::CalcBulletLinkPoses(std::vector<Eigen::Isometry3d>& X_world_link) {
  if (!has_q_) throw std::logic_error("CalcBulletLinkPoses called before SetPositions");
  EnsureBulletPositions();
  bullet_->forwardKinematics(scratch_->world_to_local, scratch_->local_origin);
  const std::vector<MultibodyBody>& bodies = *bodies_;
  const int nb = static_cast<int>(bodies.size());
  X_world_link.assign(nb, Eigen::Isometry3d::Identity());
  // Bullet link frames are the principal frames at the COM: R_wl = R_wb V^T, p_wl = c_w - R_wl c.
  for (int i = 0; i < nb; ++i) {
    const btTransform& X = bullet_->getLink(i).m_cachedWorldTransform;
    const btMatrix3x3& Rb = X.getBasis();
    Eigen::Matrix3d R_wb;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) R_wb(r, c) = Rb[r][c];
    const btVector3& o = X.getOrigin();
    X_world_link[i].linear() = R_wb * bodies[i].R_link_principal.transpose();
    X_world_link[i].translation() = Eigen::Vector3d(o.x(), o.y(), o.z()) - X_world_link[i].linear() * bodies[i].com;
  }
}

void MultibodyWorkspace::SetVelocities(const MultibodyModel& model, const Eigen::Ref<const Eigen::VectorXd>& v) {
  if (!has_q_) throw std::logic_error("robot '" + model.name() + "': SetVelocities called before SetPositions");
  if (v.size() != model.nv())
    throw std::invalid_argument("robot '" + model.name() + "': v has size " + std::to_string(v.size()) +
                                ", expected nv = " + std::to_string(model.nv()));
  if (has_v_ && (v_.size() == 0 || std::memcmp(v.data(), v_.data(), sizeof(double) * v_.size()) == 0)) return;
  v_ = v;
  has_v_ = true;
  valid.h = false;
  valid.bullet_v = false;
  const std::vector<MultibodyBody>& bodies = *bodies_;
  const int nb = static_cast<int>(bodies.size());
  int first_body = 0;
  if (free_flyer_as_one_joint()) {
    // The base joint's velocity S_base v_base = [R w_B; R v_B]; its bias is zero (S_base is fixed in the base).
    Vector6d V_base;
    V_base.head<3>().noalias() = R_wl_[0] * v_.segment<3>(3);
    V_base.tail<3>().noalias() = R_wl_[0] * v_.head<3>();
    for (int i = 0; i < 6; ++i) {
      V_[i] = V_base;
      A_bias_[i].setZero();
    }
    first_body = 6;
  }
  for (int i = first_body; i < nb; ++i) {
    const int p = bodies[i].parent;
    const int k = bodies[i].v_index;
    if (p >= 0) {
      V_[i] = V_[p];
      A_bias_[i] = A_bias_[p];
    } else {
      V_[i].setZero();
      A_bias_[i].setZero();
    }
    if (k >= 0) {
      const Vector6d vj = S_[i] * v_[k];
      V_[i] += vj;
      if (quaternion_base_ && i < 6) continue;  // d/dt (S v_base) = V x V = 0: S is fixed in the base
      // Featherstone: c_i = v_i x (S_i qd_i) (spatial motion cross product).
      const Eigen::Vector3d w = V_[i].head<3>();
      const Eigen::Vector3d vo = V_[i].tail<3>();
      A_bias_[i].head<3>() += w.cross(vj.head<3>());
      A_bias_[i].tail<3>() += w.cross(vj.tail<3>()) + vo.cross(vj.head<3>());
    }
  }
}

}  // namespace rome
