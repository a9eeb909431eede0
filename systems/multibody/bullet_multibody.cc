#include "systems/multibody/bullet_multibody.h"

namespace rome {

btQuaternion ToBtQuat(const Eigen::Matrix3d& R) {
  Eigen::Quaterniond q(R);
  q.normalize();
  return btQuaternion(q.x(), q.y(), q.z(), q.w());
}

Eigen::Vector3d BodyPointInBulletLink(const MultibodyBody& body, const Eigen::Vector3d& p_body) {
  return body.R_link_principal.transpose() * (p_body - body.com);
}

std::unique_ptr<btMultiBody> BuildBulletMultiBody(const std::vector<MultibodyBody>& bodies, int extra_links) {
  const int nb = static_cast<int>(bodies.size());
  // Fixed, massless Bullet base at the world origin; every body is a Bullet link.
  auto mb =
      std::make_unique<btMultiBody>(nb + extra_links, 0.0, btVector3(0, 0, 0), /*fixedBase=*/true, /*canSleep=*/false);
  mb->setBasePos(btVector3(0, 0, 0));
  mb->setWorldToBaseRot(btQuaternion(0, 0, 0, 1));
  for (int i = 0; i < nb; ++i) {
    const MultibodyBody& b = bodies[i];
    Eigen::Matrix3d V_parent = Eigen::Matrix3d::Identity();
    Eigen::Vector3d c_parent = Eigen::Vector3d::Zero();
    if (b.parent >= 0) {
      V_parent = bodies[b.parent].R_link_principal;
      c_parent = bodies[b.parent].com;
    }
    const Eigen::Matrix3d& V = b.R_link_principal;
    const Eigen::Matrix3d R_pp_cp = V_parent.transpose() * b.X_parent_joint.linear() * V;
    // Bullet: rotParentToThis rotates parent-frame vectors into this frame (at q = 0).
    const btQuaternion rot_parent_to_this = ToBtQuat(R_pp_cp.transpose());
    const btVector3 parent_com_to_pivot = ToBt(V_parent.transpose() * (b.X_parent_joint.translation() - c_parent));
    const btVector3 pivot_to_com = ToBt(V.transpose() * b.com);
    const btVector3 inertia = ToBt(b.principal_moments);
    switch (b.joint_type) {
      case MultibodyJointType::kRevolute:
        mb->setupRevolute(i, b.mass, inertia, b.parent, rot_parent_to_this, ToBt(V.transpose() * b.axis),
                          parent_com_to_pivot, pivot_to_com, true);
        break;
      case MultibodyJointType::kPrismatic:
        mb->setupPrismatic(i, b.mass, inertia, b.parent, rot_parent_to_this, ToBt(V.transpose() * b.axis),
                           parent_com_to_pivot, pivot_to_com, true);
        break;
      case MultibodyJointType::kFixed:
        mb->setupFixed(i, b.mass, inertia, b.parent, rot_parent_to_this, parent_com_to_pivot, pivot_to_com, true);
        break;
    }
  }
  mb->setLinearDamping(0.0);
  mb->setAngularDamping(0.0);
  mb->setMaxCoordinateVelocity(1e300);
  mb->setUseGyroTerm(true);
  mb->setCanSleep(false);
  return mb;
}

}  // namespace rome
