#include "systems/multibody/bullet_rod_constraint.h"

#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

namespace rome {

namespace {
// Island of a link's collider (a multibody constraint is solved in its links' islands; every link of our trees has a
// collider, see BulletWorldPlant::World::Build).
int IslandOf(const btMultiBody* body, int link) {
  const btMultiBodyLinkCollider* collider = link < 0 ? body->getBaseCollider() : body->getLink(link).m_collider;
  return collider ? collider->getIslandTag() : -1;
}
}  // namespace

BulletRodConstraint::BulletRodConstraint(btMultiBody* body_a, int link_a, const btVector3& point_a, btMultiBody* body_b,
                                         int link_b, const btVector3& point_b, double length_m)
    : btMultiBodyConstraint(body_a, body_b, link_a, link_b, /*numRows=*/1, /*isUnilateral=*/false,
                            MAX_MULTIBODY_CONSTRAINT_TYPE),
      point_a_(point_a),
      point_b_(point_b),
      length_m_(length_m) {}

void BulletRodConstraint::finalizeMultiDof() {
  allocateJacobiansMultiDof();
  m_numDofsFinalized = m_jacSizeBoth;
}

int BulletRodConstraint::getIslandIdA() const { return IslandOf(m_bodyA, m_linkA); }
int BulletRodConstraint::getIslandIdB() const { return IslandOf(m_bodyB, m_linkB); }

double BulletRodConstraint::LengthError() const {
  return (m_bodyA->localPosToWorld(m_linkA, point_a_) - m_bodyB->localPosToWorld(m_linkB, point_b_)).length() -
         length_m_;
}

void BulletRodConstraint::createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                                               const btContactSolverInfo& info) {
  if (m_numDofsFinalized != m_jacSizeBoth) finalizeMultiDof();
  const btVector3 pa = m_bodyA->localPosToWorld(m_linkA, point_a_);
  const btVector3 pb = m_bodyB->localPosToWorld(m_linkB, point_b_);
  const btVector3 d = pa - pb;
  const btScalar length = d.length();
  if (!(length > SIMD_EPSILON)) return;  // coincident ends: no direction (the model loader rejects a zero-length rod)
  const btVector3 u = d / length;
  btMultiBodySolverConstraint& row = rows.expandNonInitializing();
  row.m_orgConstraint = this;
  row.m_orgDofIndex = 0;
  row.m_relpos1CrossNormal.setValue(0, 0, 0);
  row.m_contactNormal1.setValue(0, 0, 0);
  row.m_relpos2CrossNormal.setValue(0, 0, 0);
  row.m_contactNormal2.setValue(0, 0, 0);
  row.m_angularComponentA.setValue(0, 0, 0);
  row.m_angularComponentB.setValue(0, 0, 0);
  row.m_solverBodyIdA = data.m_fixedBodyId;
  row.m_solverBodyIdB = data.m_fixedBodyId;
  // Bullet builds the row u^T J_a(p_a) − u^T J_b(p_b) from the normal and the two world points; the position error is
  // c = |d| − L (ċ is the row times v).
  fillMultiBodyConstraint(row, data, nullptr, nullptr, btVector3(0, 0, 0), u, pa, pb, length - length_m_, info,
                          -m_maxAppliedImpulse, m_maxAppliedImpulse);
}

}  // namespace rome
