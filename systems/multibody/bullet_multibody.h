#pragma once
// Internal: the Bullet btMultiBody of a MultibodyModel's kinematic tree, shared by MultibodyWorkspace (ABA, M⁻¹) and
// BulletWorldPlant (a btMultiBodyDynamicsWorld). Body i of the model is Bullet link i; the Bullet base is fixed and
// massless at the world origin (the floating base is the model's chain of virtual joints). Bullet link frames are the
// principal inertia frames at each COM (MultibodyBody::R_link_principal).
#include <memory>
#include <vector>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "systems/multibody/multibody_model.h"

namespace rome {

inline btVector3 ToBt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
inline Eigen::Vector3d FromBt(const btVector3& v) { return Eigen::Vector3d(v.x(), v.y(), v.z()); }
btQuaternion ToBtQuat(const Eigen::Matrix3d& R);

/// A fixed-base btMultiBody with one link per body (links 0 .. bodies.size() - 1) followed by `extra_links` links the
/// caller sets up before calling btMultiBody::finalizeMultiDof(). Damping off, coordinate velocity clamp off,
/// gyroscopic terms on, never sleeping.
std::unique_ptr<btMultiBody> BuildBulletMultiBody(const std::vector<MultibodyBody>& bodies, int extra_links = 0);

/// Position of a point given in a body's frame (MultibodyBody: the link frame), in that body's Bullet link frame.
Eigen::Vector3d BodyPointInBulletLink(const MultibodyBody& body, const Eigen::Vector3d& p_body);

}  // namespace rome
