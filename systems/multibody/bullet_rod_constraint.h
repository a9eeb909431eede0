#pragma once
// Internal: a rod (distance) constraint between two points of Bullet multibodies, for loop closures such as Cassie's
// achilles rods: |p_a − p_b| = L, one bilateral row. Bullet's btMultiBodyPoint2Point holds a point (three rows, the two
// points coincide); a rod leaves the two points free to turn about each other, so its one row is the rod direction:
//   c = |d| − L,  d = p_a − p_b,  u = d / |d|,  ċ = u · (ṗ_a − ṗ_b) = (u^T J_a − u^T J_b) v
// (the same row as the hybrid plant's loop closure, contact_dynamics.cc). Bullet's sequential-impulse solver drives ċ
// to −erp c / h (btContactSolverInfo::m_erp, the joint ERP; h the substep), so the length is held at velocity level
// with a Baumgarte-like position correction; its length error is in docs/design-notes.md#bullet-rod-constraint-error.
// The points are given in the Bullet link frames (BodyPointInBulletLink). A link of −1 is the multibody's base.
#include <BulletDynamics/Featherstone/btMultiBodyConstraint.h>

namespace rome {

class BulletRodConstraint final : public btMultiBodyConstraint {
 public:
  BulletRodConstraint(btMultiBody* body_a, int link_a, const btVector3& point_a, btMultiBody* body_b, int link_b,
                      const btVector3& point_b, double length_m);

  void finalizeMultiDof() override;
  int getIslandIdA() const override;
  int getIslandIdB() const override;
  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override;
  void debugDraw(btIDebugDraw*) override {}

  /// |p_a − p_b| − L at the bodies' current (cached) link transforms [m].
  double LengthError() const;

 private:
  btVector3 point_a_, point_b_;
  double length_m_;
};

}  // namespace rome
