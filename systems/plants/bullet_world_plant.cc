#include "systems/plants/bullet_world_plant.h"

#include <btBulletDynamicsCommon.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyGearConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <cmath>
#include <limits>
#include <sstream>

#include "systems/multibody/bullet_multibody.h"
#include "systems/multibody/bullet_rod_constraint.h"
#include "systems/multibody/multibody_kinematics.h"
#include "systems/multibody/multibody_workspace.h"

namespace rome {

namespace {
// Collision groups: the terrain collides with the robot's feet only; feet never collide with each other.
constexpr int kTerrainGroup = 1, kRobotGroup = 2;

std::string Num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}
// Bullet's multibody solver with a stopping test that works for planar models. Bullet's own residual (the largest
// squared velocity change of a row) is NaN when a row is singular — a planar model's out-of-plane friction row has a
// zero Jacobian, so Bullet disables it with m_jacDiagABInv = 0 and its residual is 0 · (1/0) — and a NaN never passes
// m_leastSquaresResidualThreshold. This solver returns instead the largest squared change of any multibody velocity
// coordinate over the iteration [(m/s)² or (rad/s)²] (Bullet's m_data.m_deltaVelocities, which every row's impulse
// updates), so the threshold means "the velocities moved less than sqrt(threshold) in the last sweep".
//
// Warm start (warm_start_factor > 0): after Bullet's setup, each multibody constraint row (the armature gears, joint
// limits, rods) starts from warm_start_factor times its impulse of the previous substep, each normal contact row from
// its manifold point's, and each friction row from the projection of the point's previous friction impulse (a world
// vector) on the row's new direction (Bullet recomputes the directions every substep), clamped to μ times the normal
// start. The start impulse is applied as Bullet applies any row impulse: to the solver's velocity changes and to the
// multibody's deferred velocity change (m_deltaV). Bullet's own SOLVER_USE_ARTICULATED_WARMSTARTING stays off: it
// starts no friction row and scales the normal impulse by a ratio of right-hand sides; measured on AMBER standing, it
// used all 100 iterations where the cold start used 63.
class ConvergingMultiBodySolver final : public btMultiBodyConstraintSolver {
 public:
  double warm_start_factor = 0.0;

 protected:
  btScalar solveGroupCacheFriendlySetup(btCollisionObject** bodies, int num_bodies, btPersistentManifold** manifolds,
                                        int num_manifolds, btTypedConstraint** constraints, int num_constraints,
                                        const btContactSolverInfo& info, btIDebugDraw* draw) override {
    // Each manifold point's friction impulse of the previous substep as a world vector (its directions change).
    friction_points_.resize(0);
    friction_impulses_.resize(0);
    if (warm_start_factor > 0)
      for (int m = 0; m < num_manifolds; ++m)
        for (int j = 0; j < manifolds[m]->getNumContacts(); ++j) {
          const btManifoldPoint& cp = manifolds[m]->getContactPoint(j);
          friction_points_.push_back(&cp);
          friction_impulses_.push_back(cp.m_lateralFrictionDir1 * cp.m_appliedImpulseLateral1 +
                                       cp.m_lateralFrictionDir2 * cp.m_appliedImpulseLateral2);
        }
    const btScalar result = btMultiBodyConstraintSolver::solveGroupCacheFriendlySetup(
        bodies, num_bodies, manifolds, num_manifolds, constraints, num_constraints, info, draw);
    if (warm_start_factor > 0) {
      for (int i = 0; i < m_multiBodyNonContactConstraints.size(); ++i) {
        btMultiBodySolverConstraint& c = m_multiBodyNonContactConstraints[i];
        if (c.m_orgConstraint != nullptr)
          WarmStart(c, warm_start_factor * c.m_orgConstraint->getAppliedImpulse(c.m_orgDofIndex), c.m_lowerLimit,
                    c.m_upperLimit);
      }
      const int num_directions = (info.m_solverMode & SOLVER_USE_2_FRICTION_DIRECTIONS) ? 2 : 1;
      for (int i = 0; i < m_multiBodyNormalContactConstraints.size(); ++i) {
        btMultiBodySolverConstraint& c = m_multiBodyNormalContactConstraints[i];
        const auto* cp = static_cast<const btManifoldPoint*>(c.m_originalContactPoint);
        if (cp == nullptr) continue;
        WarmStart(c, warm_start_factor * cp->m_appliedImpulse, c.m_lowerLimit, c.m_upperLimit);
        const btScalar normal = c.m_appliedImpulse;
        const int k = friction_points_.findLinearSearch(cp);
        if (normal <= 0 || k == friction_points_.size() ||
            c.m_frictionIndex + num_directions > m_multiBodyFrictionContactConstraints.size())
          continue;
        const btVector3 directions[2] = {cp->m_lateralFrictionDir1, cp->m_lateralFrictionDir2};
        for (int d = 0; d < num_directions; ++d) {
          btMultiBodySolverConstraint& f = m_multiBodyFrictionContactConstraints[c.m_frictionIndex + d];
          const btScalar limit = f.m_friction * normal;
          WarmStart(f, warm_start_factor * friction_impulses_[k].dot(directions[d]), -limit, limit);
        }
      }
    }
    return result;
  }
  btScalar solveSingleIteration(int iteration, btCollisionObject** bodies, int num_bodies,
                                btPersistentManifold** manifolds, int num_manifolds, btTypedConstraint** constraints,
                                int num_constraints, const btContactSolverInfo& info, btIDebugDraw* draw) override {
    btMultiBodyConstraintSolver::solveSingleIteration(iteration, bodies, num_bodies, manifolds, num_manifolds,
                                                      constraints, num_constraints, info, draw);
    const btAlignedObjectArray<btScalar>& dv = m_data.m_deltaVelocities;
    if (previous_.size() != dv.size()) previous_.resize(dv.size(), 0.0);  // grows to the high-water mark only
    btScalar change = 0;
    for (int i = 0; i < dv.size(); ++i) {
      const btScalar d = dv[i] - previous_[i];
      change = btMax(change, d * d);
      previous_[i] = dv[i];
    }
    return iteration == 0 ? BT_LARGE_FLOAT : change;  // the first sweep has no predecessor to compare with
  }

 private:
  btAlignedObjectArray<btScalar> previous_;
  btAlignedObjectArray<const btManifoldPoint*> friction_points_;  // grow to the high-water mark only
  btAlignedObjectArray<btVector3> friction_impulses_;

  // Starts row c at warm_start_factor * previous (clamped to its limits). Only rows between multibodies and static
  // objects (the terrain): a dynamic rigid body's solver body would need the impulse too, and there is none.
  void WarmStart(btMultiBodySolverConstraint& c, btScalar start, btScalar lower, btScalar upper) {
    if ((c.m_multiBodyA == nullptr && !IsStatic(c.m_solverBodyIdA)) ||
        (c.m_multiBodyB == nullptr && !IsStatic(c.m_solverBodyIdB)))
      return;
    const btScalar impulse = btMin(upper, btMax(lower, start));
    if (impulse == 0) return;
    c.m_appliedImpulse = impulse;
    if (c.m_multiBodyA)
      Apply(c.m_multiBodyA, &m_data.m_deltaVelocitiesUnitImpulse[c.m_jacAindex], impulse, c.m_deltaVelAindex);
    if (c.m_multiBodyB)
      Apply(c.m_multiBodyB, &m_data.m_deltaVelocitiesUnitImpulse[c.m_jacBindex], impulse, c.m_deltaVelBindex);
  }
  // As Bullet's rows do: the solver's velocity change and the multibody's deferred one (m_deltaV, which the world adds
  // to the velocities after the solve).
  void Apply(btMultiBody* body, const btScalar* unit_response, btScalar impulse, int velocity_index) {
    body->applyDeltaVeeMultiDof2(unit_response, impulse);
    applyDeltaVee(const_cast<btScalar*>(unit_response), impulse, velocity_index, body->getNumDofs() + 6);
  }
  bool IsStatic(int solver_body) const {
    return solver_body < 0 || m_tmpSolverBodyPool[solver_body].m_originalBody == nullptr;
  }
};

}  // namespace

/// One run's Bullet world (scratch). Built from the plant; a copy builds a fresh world (see the header).
struct BulletWorldPlant::World {
  explicit World(const BulletWorldPlant& plant) : plant(&plant), ws(plant.model()) { Build(); }
  World(const World& other) : World(*other.plant) {}
  World& operator=(const World&) = delete;
  ~World() {
    if (!world) return;
    for (auto& c : constraints) world->removeMultiBodyConstraint(c.get());
    for (auto& c : colliders) world->removeCollisionObject(c.get());
    for (auto& t : terrain) world->removeCollisionObject(t.get());
    world->removeMultiBody(mb.get());
    for (auto& r : rotors) world->removeMultiBody(r.get());
  }

  void Build();
  // Build's parts, in order: the robot, its armature rotors, joint limits and loop closures; the colliders of its
  // links (contact spheres); the terrain.
  void AddRobotConstraints();
  void AddLinkColliders();
  void AddTerrain();

  const BulletWorldPlant* plant;
  MultibodyWorkspace ws;  // COM output and contact heights (our kinematics)
  std::unique_ptr<btDefaultCollisionConfiguration> config;
  std::unique_ptr<btCollisionDispatcher> dispatcher;
  std::unique_ptr<btDbvtBroadphase> broadphase;
  std::unique_ptr<ConvergingMultiBodySolver> solver;
  std::unique_ptr<btMultiBodyDynamicsWorld> world;
  std::unique_ptr<btMultiBody> mb;
  std::vector<std::unique_ptr<btMultiBody>> rotors;  // one per geared armature
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> terrain;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> constraints;
  // Per Bullet link: the contact points on it (sphere centres in the Bullet link frame) and their contact indices.
  std::vector<std::vector<std::pair<btVector3, int>>> link_points;
  std::vector<std::vector<Eigen::Vector3d>> link_body_points;  // the same points in the model's body frame
  btAlignedObjectArray<btQuaternion> world_to_local;
  btAlignedObjectArray<btVector3> local_origin;
  Eigen::VectorXd q, v, tau, u;
  Eigen::Matrix3Xd impulse;          // per contact, summed over the step [N s]
  Eigen::Matrix3Xd angular_impulse;  // per contact, its moment about the world origin, summed over the step [N m s]
  Eigen::VectorXd slide_speed;       // per contact, the fastest loaded point's sliding speed in the last substep [m/s]
};

void BulletWorldPlant::World::Build() {
  const MultibodyModel& model = plant->model();
  const BulletWorldPlantParams& p = plant->params_;
  const int nv = model.nv();
  config = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher = std::make_unique<btCollisionDispatcher>(config.get());
  broadphase = std::make_unique<btDbvtBroadphase>();
  solver = std::make_unique<ConvergingMultiBodySolver>();
  world = std::make_unique<btMultiBodyDynamicsWorld>(dispatcher.get(), broadphase.get(), solver.get(), config.get());
  world->setGravity(ToBt(model.gravity()));
  btContactSolverInfo& info = world->getSolverInfo();
  info.m_numIterations = p.solver_iterations;
  info.m_leastSquaresResidualThreshold = p.solver_residual_threshold;
  info.m_erp = p.joint_erp;
  info.m_erp2 = p.contact_erp;
  info.m_globalCfm = p.cfm;
  info.m_restitution = p.restitution;
  info.m_splitImpulse = 0;
  solver->warm_start_factor = p.warm_start_factor;

  AddRobotConstraints();
  AddLinkColliders();
  AddTerrain();
  q.setZero(nv);
  v.setZero(nv);
  tau.setZero(nv);
  u.setZero(model.nu());
  impulse.setZero(3, model.num_contacts());
  angular_impulse.setZero(3, model.num_contacts());
  slide_speed.setZero(model.num_contacts());
  mb->forwardKinematics(world_to_local, local_origin);
  mb->updateCollisionObjectWorldTransforms(world_to_local, local_origin);
}

void BulletWorldPlant::World::AddRobotConstraints() {
  const MultibodyModel& model = plant->model();
  const BulletWorldPlantParams& p = plant->params_;
  const int nb = model.num_bodies();
  // The robot: the model's tree; then one rotor per actuated joint with reflected inertia, each its own one-link
  // btMultiBody on a fixed base (a wheel about a fixed axis), geared to the joint.
  const int nr = plant->num_rotors();
  mb = BuildBulletMultiBody(model.bodies());
  mb->finalizeMultiDof();
  mb->setMaxAppliedImpulse(p.max_impulse_Ns);
  world->addMultiBody(mb.get());
  for (int r = 0; r < nr; ++r) {
    const double I = model.reflected_inertia()[plant->rotor_dofs_[r]];
    auto rotor = std::make_unique<btMultiBody>(1, 0.0, btVector3(0, 0, 0), /*fixedBase=*/true, /*canSleep=*/false);
    rotor->setupRevolute(0, 0.0, btVector3(I, I, I), -1, btQuaternion(0, 0, 0, 1), btVector3(0, 0, 1),
                         btVector3(0, 0, 0), btVector3(0, 0, 0), true);
    rotor->finalizeMultiDof();
    rotor->setLinearDamping(0.0);
    rotor->setAngularDamping(0.0);
    rotor->setMaxCoordinateVelocity(1e300);
    rotor->setCanSleep(false);
    rotor->setMaxAppliedImpulse(p.max_impulse_Ns);
    world->addMultiBody(rotor.get());
    const int link = model.BodyOfVelocity(plant->rotor_dofs_[r]);
    // Row: q̇_joint + ratio q̇_rotor = 0 with ratio −1, i.e. the rotor turns with the joint. No position error term: the
    // rotor angle enters nothing.
    auto gear = std::make_unique<btMultiBodyGearConstraint>(mb.get(), link, rotor.get(), 0, btVector3(0, 0, 0),
                                                            btVector3(0, 0, 0), btMatrix3x3::getIdentity(),
                                                            btMatrix3x3::getIdentity());
    gear->setGearRatio(-1.0);
    gear->setErp(0.0);
    gear->setMaxAppliedImpulse(p.max_impulse_Ns);
    world->addMultiBodyConstraint(gear.get());
    constraints.push_back(std::move(gear));
    rotors.push_back(std::move(rotor));
  }
  if (p.enable_joint_limits)
    for (int i = 0; i < nb; ++i) {
      const MultibodyBody& b = model.body(i);
      if (b.is_virtual || b.v_index < 0) continue;
      const double lo = model.position_lower_limits()[b.v_index], hi = model.position_upper_limits()[b.v_index];
      if (!std::isfinite(lo) || !std::isfinite(hi)) continue;
      auto limit = std::make_unique<btMultiBodyJointLimitConstraint>(mb.get(), i, lo, hi);
      limit->setMaxAppliedImpulse(p.max_impulse_Ns);
      world->addMultiBodyConstraint(limit.get());
      constraints.push_back(std::move(limit));
    }

  // Loop closures: one rod (distance) row each, between the two points on their Bullet links.
  for (const LoopClosureInfo& loop : model.loop_closures()) {
    auto rod = std::make_unique<BulletRodConstraint>(
        mb.get(), loop.body_a, ToBt(BodyPointInBulletLink(model.body(loop.body_a), loop.point_a)), mb.get(),
        loop.body_b, ToBt(BodyPointInBulletLink(model.body(loop.body_b), loop.point_b)), loop.distance_m);
    rod->setMaxAppliedImpulse(p.max_impulse_Ns);
    world->addMultiBodyConstraint(rod.get());
    constraints.push_back(std::move(rod));
  }
}

void BulletWorldPlant::World::AddLinkColliders() {
  const MultibodyModel& model = plant->model();
  const BulletWorldPlantParams& p = plant->params_;
  const int nb = model.num_bodies();
  // Feet: a compound of spheres, one per contact point, on the contact's body.
  link_points.assign(nb, {});
  link_body_points.assign(nb, {});
  std::vector<double> link_mu(nb, 1.0);
  for (int c = 0; c < model.num_contacts(); ++c) {
    const ContactInfo& contact = model.contacts()[c];
    for (const Eigen::Vector3d& point : contact.points) {
      link_points[contact.body].emplace_back(ToBt(BodyPointInBulletLink(model.body(contact.body), point)), c);
      link_body_points[contact.body].push_back(point);
    }
    link_mu[contact.body] = contact.friction_coefficient;
  }
  for (int i = 0; i < nb; ++i) {
    if (link_points[i].empty()) {
      // Bullet solves a multibody constraint (the armature gears, joint limits) only within the simulation island of
      // its links' colliders: a link without one has its gear silently ignored (measured: the hips' gears applied no
      // impulse until their thighs had colliders). An empty compound that collides with nothing gives it one.
      auto empty = std::make_unique<btCompoundShape>(false, 0);
      auto collider = std::make_unique<btMultiBodyLinkCollider>(mb.get(), i);
      collider->setCollisionShape(empty.get());
      shapes.push_back(std::move(empty));
      world->addCollisionObject(collider.get(), kRobotGroup, 0);
      mb->getLink(i).m_collider = collider.get();
      colliders.push_back(std::move(collider));
      continue;
    }
    auto compound = std::make_unique<btCompoundShape>(false, static_cast<int>(link_points[i].size()));
    for (const auto& [centre, c] : link_points[i]) {
      (void)c;
      auto sphere = std::make_unique<btSphereShape>(p.point_radius_m);
      btTransform X;
      X.setIdentity();
      X.setOrigin(centre);
      compound->addChildShape(X, sphere.get());
      shapes.push_back(std::move(sphere));
    }
    auto collider = std::make_unique<btMultiBodyLinkCollider>(mb.get(), i);
    collider->setCollisionShape(compound.get());
    collider->setFriction(link_mu[i]);
    collider->setRestitution(p.restitution);
    if (p.contact_stiffness_N_per_m > 0)
      collider->setContactStiffnessAndDamping(p.contact_stiffness_N_per_m, p.contact_damping_Ns_per_m);
    shapes.push_back(std::move(compound));
    world->addCollisionObject(collider.get(), kRobotGroup, kTerrainGroup);
    mb->getLink(i).m_collider = collider.get();
    colliders.push_back(std::move(collider));
  }
}

void BulletWorldPlant::World::AddTerrain() {
  const BulletWorldPlantParams& p = plant->params_;
  // Terrain, lowered by the sphere radius (a contact point touches when it reaches the terrain).
  auto add_static = [&](std::unique_ptr<btCollisionShape> shape, const btVector3& origin) {
    auto object = std::make_unique<btCollisionObject>();
    btTransform X;
    X.setIdentity();
    X.setOrigin(origin);
    object->setWorldTransform(X);
    object->setCollisionShape(shape.get());
    object->setFriction(1.0);
    object->setRestitution(p.restitution);
    if (p.contact_stiffness_N_per_m > 0)
      object->setContactStiffnessAndDamping(p.contact_stiffness_N_per_m, p.contact_damping_Ns_per_m);
    world->addCollisionObject(object.get(), kTerrainGroup, kRobotGroup);
    shapes.push_back(std::move(shape));
    terrain.push_back(std::move(object));
  };
  const Terrain& ground = plant->terrain();
  const double r = p.point_radius_m;
  if (ground.is_flat()) {
    add_static(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), ground.SurfaceHeight(0.0) - r),
               btVector3(0, 0, 0));
  } else {
    double lowest = std::numeric_limits<double>::infinity();
    for (const SteppingStone& s : ground.stones()) lowest = std::min(lowest, s.top_height_m);
    const double bottom = lowest - p.stone_depth_m - r;
    for (const SteppingStone& s : ground.stones()) {
      const double top = s.top_height_m - r, half_height = 0.5 * (top - bottom);
      auto box = std::make_unique<btBoxShape>(btVector3(0.5 * s.length_m, 5.0, half_height));
      box->setMargin(0.0);
      add_static(std::move(box), btVector3(s.x_center_m, 0.0, bottom + half_height));
    }
    add_static(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), bottom), btVector3(0, 0, 0));
  }
}

BulletWorldPlant::BulletWorldPlant(std::string name, std::shared_ptr<const MultibodyModel> model,
                                   ContactModeGraph graph, Terrain terrain, BulletWorldPlantParams params)
    : ContactPlant(std::move(name), std::move(model), std::move(graph), std::move(terrain)), params_(params) {
  // Bullet's multibody steps the Euler chain and the state is [q; v] with dq/dt = v: nq == nv.
  model_->RequireNqEqualsNv("system '" + this->name() + "'");
  const int nv = model_->nv(), nu = model_->nu(), nc = model_->num_contacts();
  if (!(params_.step_s > 0) || !std::isfinite(params_.step_s))
    ThrowError("parameter step_s must be positive, got " + Num(params_.step_s) + " s");
  if (params_.substeps < 1)
    ThrowError("parameter substeps must be at least 1, got " + std::to_string(params_.substeps));
  if (!(params_.update_offset_s >= 0 && params_.update_offset_s < params_.step_s))
    ThrowError("parameter update_offset_s must be in [0, step_s), got " + Num(params_.update_offset_s) + " s");
  if (!(params_.point_radius_m > 0))
    ThrowError("parameter point_radius_m must be positive, got " + Num(params_.point_radius_m) + " m");
  if (!(params_.solver_residual_threshold >= 0))
    ThrowError("parameter solver_residual_threshold must be >= 0, got " + Num(params_.solver_residual_threshold) +
               " (m/s)^2");
  if (!(params_.min_time_in_mode_s >= 0) || !std::isfinite(params_.min_time_in_mode_s))
    ThrowError("parameter min_time_in_mode_s must be >= 0, got " + Num(params_.min_time_in_mode_s) + " s");
  if (!(params_.planned_liftoff_min_contact_s >= 0) || !std::isfinite(params_.planned_liftoff_min_contact_s))
    ThrowError("parameter planned_liftoff_min_contact_s must be >= 0 and finite, got " +
               Num(params_.planned_liftoff_min_contact_s) + " s");
  if (std::isnan(params_.planned_liftoff_force_N))
    ThrowError("parameter planned_liftoff_force_N is NaN (negative: off)");
  if (!(params_.slip_speed_mps >= 0) || !std::isfinite(params_.slip_speed_mps))
    ThrowError("parameter slip_speed_mps must be finite and >= 0, got " + Num(params_.slip_speed_mps) + " m/s");
  if (!(params_.slip_distance_m > 0))
    ThrowError("parameter slip_distance_m must be positive (infinity: off), got " + Num(params_.slip_distance_m) +
               " m");
  if (!(params_.slip_min_point_force_N >= 0) || !std::isfinite(params_.slip_min_point_force_N))
    ThrowError("parameter slip_min_point_force_N must be finite and >= 0, got " + Num(params_.slip_min_point_force_N) +
               " N");
  if (params_.solver_iterations < 1)
    ThrowError("parameter solver_iterations must be at least 1, got " + std::to_string(params_.solver_iterations));
  if (!(params_.mode_change_delay_s > 0 && params_.mode_change_delay_s < params_.step_s - params_.update_offset_s))
    ThrowError("parameter mode_change_delay_s must be in (0, step_s - update_offset_s), got " +
               Num(params_.mode_change_delay_s) + " s");
  for (const ContactInfo& c : model_->contacts())
    if (c.points.empty())
      ThrowError("contact '" + c.name + "' of robot '" + model_->name() +
                 "' has no points, so it has no collision geometry");
  for (const SteppingStone& s : terrain_.stones())
    if (!(s.length_m > 0))
      ThrowError("a stepping stone at x = " + Num(s.x_center_m) + " m has length " + Num(s.length_m) +
                 " m; it must be positive");
  for (int k = 0; k < nv; ++k)
    if (model_->reflected_inertia()[k] > 0) rotor_dofs_.push_back(k);

  td_time_offset_ = touching_offset() + nc;
  lo_time_offset_ = td_time_offset_ + nc;
  mode_start_offset_ = lo_time_offset_ + nc;
  slide_offset_ = mode_start_offset_ + 1;
  Eigen::VectorXd xd = Eigen::VectorXd::Zero(slide_offset_ + nc);
  xd.head(nv) = model_->q_nominal();
  DeclareDiscreteState(xd);
  DeclareInputPort("u", nu);
  if (params_.external_force_input) DeclareInputPort("tau_external", model_->joint_names());
  DeclarePeriodicDiscreteUpdate(params_.step_s, params_.update_offset_s,
                                [this](const LeafContext& c, Eigen::VectorXd* next) { return Step(c, next); });

  DeclareOutputPort(
      "q", nv, [nv](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().head(nv); },
      Feedthrough::None());
  DeclareOutputPort(
      "v", nv, [nv](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment(nv, nv); },
      Feedthrough::None());
  std::vector<std::string> state_names, force_names;
  for (const std::string& j : model_->joint_names()) state_names.push_back("q_" + j);
  for (const std::string& j : model_->joint_names()) state_names.push_back("v_" + j);
  for (const ContactInfo& contact : model_->contacts())
    for (const char* axis : {"fx", "fy", "fz"}) force_names.push_back(contact.name + "_" + axis);
  DeclareOutputPort(
      "state", state_names, [nv](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().head(2 * nv); },
      Feedthrough::None());
  DeclareTypedOutputPort<int>(
      "mode", [](const LeafContext& c, int* y) { *y = c.mode(); }, Feedthrough::None());
  const int f0 = forces_offset();
  DeclareOutputPort(
      "contact_forces", force_names,
      [f0, nc](const LeafContext& c, Eigen::VectorXd* y) { *y = c.discrete_state().segment(f0, 3 * nc); },
      Feedthrough::None());
  DeclareOutputPort(
      "contact_violation", nc,
      [this, f0, nc](const LeafContext& c, Eigen::VectorXd* y) {
        for (int i = 0; i < nc; ++i) {
          const Eigen::Vector3d f = c.discrete_state().segment<3>(f0 + 3 * i);
          const double mu = model_->contacts()[i].friction_coefficient;
          const bool sliding = f.head<2>().norm() > mu * f.z() * (1 + 1e-6) + 1e-6 || SlipDistance(c, i) > 0.0;
          (*y)[i] = (f.z() < -1e-9 ? 1 : 0) + (sliding ? 2 : 0);
        }
      },
      Feedthrough::None());
  DeclareOutputPort(
      "com", {"x", "y", "z", "vx", "vy", "vz"},
      [this, nv](const LeafContext& c, Eigen::VectorXd* y) {
        auto& ws = c.scratch<World>().ws;
        const auto q = c.discrete_state().head(nv);
        const auto v = c.discrete_state().segment(nv, nv);
        y->head<3>() = CalcComPosition(*model_, ws, q);
        y->tail<3>() = CalcComVelocity(*model_, ws, q, v);
      },
      Feedthrough::None());

  DeclareModeChangeGuards();
}

// Mode changes, announced by guards (see the header). Touchdowns from the graph.
void BulletWorldPlant::DeclareModeChangeGuards() {
  const int nc = model_->num_contacts();
  const int num_modes = static_cast<int>(graph_.modes.size());
  for (const ResolvedTransition& t : transitions_) {
    if (t.kind != ContactModeGraph::Kind::kTouchdown) continue;
    const int from = t.from, to = t.to, c = t.contact;
    const std::string contact_name = model_->contacts()[c].name;
    DeclareGuard(
        "touchdown_" + contact_name, from,
        [this, c](const LeafContext& ctx) {
          const Eigen::VectorXd& xd = ctx.discrete_state();
          const double td = xd[td_time_offset_ + c];
          const bool armed = xd[touching_offset() + c] > 0.5 && td > xd[mode_start_offset_];
          // Announced no earlier than min_time_in_mode_s after the contact last stopped touching.
          return armed ? std::max(td, xd[lo_time_offset_ + c] + params_.min_time_in_mode_s) +
                             params_.mode_change_delay_s - ctx.time()
                       : 1.0;
        },
        CrossingDirection::kFalling,
        [this, c, contact_name, to](const LeafContext& ctx, int, State* next) {
          if (!terrain_.is_flat()) {
            auto& ws = ctx.scratch<World>().ws;
            const Eigen::Vector3d p = CalcPointPosition(*model_, ws, ctx.discrete_state().head(model_->nv()),
                                                        model_->contacts()[c].body, model_->contacts()[c].frame_origin);
            if (terrain_.StoneAt(p.x(), params_.stone_tolerance_m) < 0) {
              const int near = terrain_.NearestStone(p.x());
              std::ostringstream os;
              os << "robot fell: '" << contact_name << "' touched down at x = " << p.x() << " m, z = " << p.z()
                 << " m, not on any stone (nearest stone " << near << " spans "
                 << terrain_.stones()[near].x_center_m - terrain_.stones()[near].length_m / 2 << " .. "
                 << terrain_.stones()[near].x_center_m + terrain_.stones()[near].length_m / 2 << " m)";
              return EventStatus::Failed(os.str());
            }
          }
          EnterMode(ctx.time(), to, next);
          return EventStatus::Succeeded();
        });
  }
  for (int m = 0; m < num_modes; ++m)
    for (int c = 0; c < nc; ++c) {
      if (!(mode_contacts_[m] & ContactBit(c))) continue;
      const int to = LiftoffMode(m, c);
      const std::string contact_name = model_->contacts()[c].name;
      DeclareGuard(
          "liftoff_" + contact_name, m,
          [this, c](const LeafContext& ctx) {
            const Eigen::VectorXd& xd = ctx.discrete_state();
            if (xd[touching_offset() + c] > 0.5) return 1.0;
            return std::max(xd[lo_time_offset_ + c], xd[mode_start_offset_]) + params_.mode_change_delay_s - ctx.time();
          },
          CrossingDirection::kFalling,
          [this, m, to, contact_name](const LeafContext& ctx, int, State* next) {
            if (to < 0)
              return EventStatus::Failed("'" + contact_name + "' lifted off at t = " + Num(ctx.time()) +
                                         " s in mode '" + graph_.modes[m].name +
                                         "', but the contact-mode graph has no mode to lift off into");
            EnterMode(ctx.time(), to, next);
            return EventStatus::Succeeded();
          });
    }
}

BulletWorldPlant::~BulletWorldPlant() = default;

std::any BulletWorldPlant::AllocateScratch() const { return World(*this); }

void BulletWorldPlant::EnterMode(double t, int to, State* next) const {
  next->discrete[mode_start_offset_] = t;
  next->mode = to;
}

double BulletWorldPlant::ContactHeight(const LeafContext& context, const Eigen::Ref<const Eigen::VectorXd>& q,
                                       int contact) const {
  auto& ws = context.scratch<World>().ws;
  const ContactInfo& info = model_->contacts()[contact];
  double lowest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& point : info.points) {
    const Eigen::Vector3d p = CalcPointPosition(*model_, ws, q, info.body, point);
    lowest = std::min(lowest, p.z() - terrain_.SurfaceHeight(p.x()));
  }
  return lowest;
}

void BulletWorldPlant::SetState(LeafContext& context, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                const std::string& mode) const {
  const int nv = model_->nv(), nc = model_->num_contacts();
  if (q.size() != nv || v.size() != nv)
    ThrowError("SetState: q has size " + std::to_string(q.size()) + " and v size " + std::to_string(v.size()) +
               "; robot '" + model_->name() + "' has nv = " + std::to_string(nv));
  const double t = context.time();
  std::vector<double> touching(nc);
  for (int c = 0; c < nc; ++c) touching[c] = ContactHeight(context, q, c) <= params_.liftoff_height_m ? 1.0 : 0.0;
  State& s = context.get_mutable_state();
  s.discrete.setZero();
  s.discrete.head(nv) = q;
  s.discrete.segment(nv, nv) = v;
  for (int c = 0; c < nc; ++c) {
    s.discrete[touching_offset() + c] = touching[c];
    // A contact touching at the start stands there: it has touched for planned_liftoff_min_contact_s already, so a
    // planned lift-off may release it at once (with the start's time, a run started on a gait's orbit less than that
    // before the trailing foot's planned lift-off kept the foot until the controller loaded it again: measured on
    // gait (0.40, 0.40, 0.10, 0.25) started mid double support, docs/design-notes.md#walking-bullet-orbit-start).
    s.discrete[td_time_offset_ + c] = t - params_.planned_liftoff_min_contact_s;
    s.discrete[lo_time_offset_ + c] = t;
  }
  s.discrete[mode_start_offset_] = t;
  s.mode = graph_.ModeIndex(mode, name());
}

ContactWrench BulletWorldPlant::LastStepContactWrench(const LeafContext& context, int contact) const {
  if (contact < 0 || contact >= model_->num_contacts())
    ThrowError("LastStepContactWrench: contact " + std::to_string(contact) + " is out of range; robot '" +
               model_->name() + "' has " + std::to_string(model_->num_contacts()));
  const World& w = context.scratch<World>();
  ContactWrench wrench;
  wrench.force = w.impulse.col(contact) / params_.step_s;
  wrench.torque = w.angular_impulse.col(contact) / params_.step_s;
  return wrench;
}

double BulletWorldPlant::SlipDistance(const LeafContext& context, int contact) const {
  if (contact < 0 || contact >= model_->num_contacts())
    ThrowError("SlipDistance: contact " + std::to_string(contact) + " is out of range; robot '" + model_->name() +
               "' has " + std::to_string(model_->num_contacts()));
  const double slid = context.discrete_state()[slide_offset_ + contact];
  return slid > params_.slip_distance_m ? slid : 0.0;
}

int BulletWorldPlant::SolverIterationsUsed(const LeafContext& context) const {
  return context.scratch<World>().solver->m_analyticsData.m_numIterationsUsed;
}

double BulletWorldPlant::SolverResidual(const LeafContext& context) const {
  return context.scratch<World>().solver->m_analyticsData.m_remainingLeastSquaresResidual;
}

double BulletWorldPlant::GearVelocityError(const LeafContext& context) const {
  World& w = context.scratch<World>();
  double err = 0;
  for (int r = 0; r < num_rotors(); ++r)
    err = std::max(err,
                   std::abs(w.mb->getJointVel(model_->BodyOfVelocity(rotor_dofs_[r])) - w.rotors[r]->getJointVel(0)));
  return err;
}

EventStatus BulletWorldPlant::Step(const LeafContext& context, Eigen::VectorXd* next) const {
  World& w = context.scratch<World>();
  const MultibodyModel& model = *model_;
  const int nv = model.nv(), nb = model.num_bodies(), nc = model.num_contacts();
  const Eigen::VectorXd& xd = context.discrete_state();
  w.q = xd.head(nv);
  w.v = xd.segment(nv, nv);
  // Push the state (the world's own state equals it unless the context was changed by hand).
  for (int i = 0; i < nb; ++i) {
    const int k = model.body(i).v_index;
    if (k < 0) continue;
    w.mb->setJointPos(i, w.q[k]);
    w.mb->setJointVel(i, w.v[k]);
  }
  for (int r = 0; r < num_rotors(); ++r) w.rotors[r]->setJointVel(0, w.v[rotor_dofs_[r]]);
  w.mb->forwardKinematics(w.world_to_local, w.local_origin);
  w.mb->updateCollisionObjectWorldTransforms(w.world_to_local, w.local_origin);

  const Eigen::VectorXd& u_in = EvalInput(context, 0);
  if (params_.saturate_torques)
    w.u = u_in.cwiseMax(-model.torque_limits()).cwiseMin(model.torque_limits());
  else
    w.u = u_in;
  const Eigen::VectorXd* tau_external = params_.external_force_input ? &EvalInput(context, 1) : nullptr;
  const double h = params_.step_s / params_.substeps;
  w.impulse.setZero();
  w.angular_impulse.setZero();
  w.slide_speed.setZero();
  for (int sub = 0; sub < params_.substeps; ++sub) {
    // Joint torques of this substep: B sat(u) + τ_spring at the substep's start.
    w.tau.noalias() = model.B() * w.u;
    w.tau.array() -= model.spring_stiffness().array() * (w.q - model.spring_rest()).array() +
                     model.spring_damping().array() * w.v.array();
    if (tau_external != nullptr) w.tau += *tau_external;
    for (int i = 0; i < nb; ++i) {
      const int k = model.body(i).v_index;
      if (k >= 0 && w.tau[k] != 0.0) w.mb->addJointTorque(i, w.tau[k]);
    }
    w.world->stepSimulation(h, 0, h);
    for (int i = 0; i < nb; ++i) {
      const int k = model.body(i).v_index;
      if (k < 0) continue;
      w.q[k] = w.mb->getJointPos(i);
      w.v[k] = w.mb->getJointVel(i);
    }
    // Ground impulses of this substep, per contact (the manifold point's nearest contact point on the foot).
    const int num_manifolds = w.dispatcher->getNumManifolds();
    for (int m = 0; m < num_manifolds; ++m) {
      const btPersistentManifold* manifold = w.dispatcher->getManifoldByIndexInternal(m);
      const btMultiBodyLinkCollider* foot = btMultiBodyLinkCollider::upcast(manifold->getBody0());
      double sign = 1.0;  // force on body 0 = impulse along the normal on body 1, pointing to body 0
      if (foot == nullptr) {
        foot = btMultiBodyLinkCollider::upcast(manifold->getBody1());
        sign = -1.0;
      }
      if (foot == nullptr || foot->m_multiBody != w.mb.get() || foot->m_link < 0) continue;
      const auto& points = w.link_points[foot->m_link];
      for (int j = 0; j < manifold->getNumContacts(); ++j) {
        const btManifoldPoint& pt = manifold->getContactPoint(j);
        const btVector3& local = sign > 0 ? pt.m_localPointA : pt.m_localPointB;
        int contact = points.front().second;
        size_t nearest = 0;
        double best = std::numeric_limits<double>::infinity();
        for (size_t k = 0; k < points.size(); ++k) {
          const double d = (local - points[k].first).length2();
          if (d < best) best = d, contact = points[k].second, nearest = k;
        }
        // Sliding: the loaded sole point's velocity along the surface after the last substep (flat surfaces: x, y).
        // slip_distance_m = 1 cm lies between the longest slide of the passing runs and the exoskeleton's sliding foot
        // (docs/design-notes.md#stepping-stones-bullet).
        if (sub == params_.substeps - 1 && pt.m_appliedImpulse > params_.slip_min_point_force_N * h) {
          const Eigen::Vector3d pv = CalcPointVelocity(model, w.ws, w.q, w.v, model.contacts()[contact].body,
                                                       w.link_body_points[foot->m_link][nearest]);
          w.slide_speed[contact] = std::max(w.slide_speed[contact], pv.head<2>().norm());
        }
        const btVector3 J = pt.m_normalWorldOnB * pt.m_appliedImpulse +
                            pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                            pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
        w.impulse.col(contact) += sign * FromBt(J);
        const btVector3& at = sign > 0 ? pt.m_positionWorldOnA : pt.m_positionWorldOnB;
        w.angular_impulse.col(contact) += sign * FromBt(at.cross(J));
      }
    }
  }

  Eigen::VectorXd& x = *next;
  x.head(nv) = w.q;
  x.segment(nv, nv) = w.v;
  const double t = context.time();
  for (int c = 0; c < nc; ++c) {
    const Eigen::Vector3d f = w.impulse.col(c) / params_.step_s;
    x.segment<3>(forces_offset() + 3 * c) = f;
    // The distance slid since the contact last held (sliding speed at most slip_speed_mps) or started touching.
    const bool slides = w.slide_speed[c] > params_.slip_speed_mps && x[touching_offset() + c] > 0.5;
    x[slide_offset_ + c] = slides ? xd[slide_offset_ + c] + w.slide_speed[c] * params_.step_s : 0.0;
    const bool was = xd[touching_offset() + c] > 0.5;
    if (!was && f.z() > params_.touchdown_force_N) {
      x[touching_offset() + c] = 1.0;
      x[td_time_offset_ + c] = t;
    } else if (was &&
               ((f.z() <= params_.touchdown_force_N && ContactHeight(context, w.q, c) > params_.liftoff_height_m) ||
                (params_.planned_liftoff_force_N >= 0 && IsGraphLiftoff(context.mode(), c) &&
                 f.z() <= params_.planned_liftoff_force_N &&
                 t - xd[td_time_offset_ + c] >= params_.planned_liftoff_min_contact_s))) {
      x[touching_offset() + c] = 0.0;
      x[lo_time_offset_ + c] = t;
    }
  }
  if (!w.q.allFinite() || !w.v.allFinite())
    return EventStatus::Failed("the Bullet world's state is not finite at t = " + Num(t) + " s");
  const int zi = base_height_index();
  if (zi >= 0 && w.q[zi] < params_.min_base_height_m)
    return EventStatus::Failed("robot fell: base height " + Num(w.q[zi]) +
                               " m is below min_base_height_m = " + Num(params_.min_base_height_m) + " m");
  return EventStatus::Succeeded();
}

}  // namespace rome
